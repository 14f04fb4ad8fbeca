#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Inputs beyond CSV through the real binary: ROS 1 bags, MCAP, rosbag2
# folders and .db3 files written by tests/gen-ros from the format
# specifications; info on each (topics, receive times), --topic, and the
# mistakes users make (the npy/bag/gz that used to be "binary data", the
# rostopic -p CSV, nanosecond stamps read as seconds, an unknown topic),
# each a right answer or a one-line error naming the format and the fix
# (the noise files, --topic, scenes and the 1 h equivalence: cli-ros-noise.sh).
. "$(dirname "$0")/lib.sh"

GEN="$top_builddir/tests/gen-ros"
"$GEN" "$T/r" 200 30 || { not_ok "gen-ros"; done_testing; exit 0; }
have_db3=0
[ -f "$T/r/rosbag2/rosbag2_0.db3" ] && have_db3=1

for f in imu-none.bag imu-bz2.bag imu-lz4.bag imu-zstd.mcap imu-lz4.mcap \
	 imu-ros1.mcap rosbag2-mcap rosbag2 rosbag2/rosbag2_0.db3 rosbag2-zstd; do
	case $f in rosbag2|rosbag2/*|rosbag2-zstd)
		if [ $have_db3 = 0 ] && [ $f = rosbag2-zstd ]; then
			skip "$f" "built without SQLite"
			continue
		fi
		if [ $have_db3 = 0 ]; then
			# recognised by its leading bytes, refused with the fix
			mkdir -p "$T/r/rosbag2"
			{ printf 'SQLite format 3\000'; head -c 4080 /dev/zero; } \
				>"$T/r/rosbag2/rosbag2_0.db3"
			printf 'rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n  relative_file_paths:\n    - rosbag2_0.db3\n' \
				>"$T/r/rosbag2/metadata.yaml"
			run "$f without SQLite" 2 info "$T/r/$f"
			has "$f: names the fix" "$T/err" 'without SQLite.*--with-sqlite3'
			one_line_error "$f"
			continue
		fi;;
	esac
	run "info $f" 0 info "$T/r/$f"
	has "$f: format line" "$T/out" '^  format: +(ROS 1 bag v2.0|MCAP|rosbag2)'
	has "$f: topics with counts" "$T/out" '/imu/data +sensor_msgs/(msg/)?Imu +6000 messages +\(read\)'
	has "$f: other types listed" "$T/out" '/chatter +std_msgs/(msg/)?String +31 messages +\(not an IMU type\)'
	has "$f: 200 Hz from the header stamps" "$T/out" '^  rate: +200 Hz \(time column\)'
	has "$f: receive times compared" "$T/out" 'latency after the header stamps median 0.0015 s'
	has "$f: gx in rad/s" "$T/out" '^  gx +rad/s +angular rate'
	has "$f: temperature topic as the temperature column" "$T/out" "temperature: 25 .. 25.3 degC"
done

run "info json of a bag" 0 info --format json "$T/r/imu-bz2.bag"
json_check "bag json: format, topics, receive times" "$T/out" \
  '.format == "ROS 1 bag v2.0 (bz2 chunks)" and (.topics | length) == 3 and ([.topics[] | select(.selected)] | length) == 2 and .receive_times.agree == true and (.receive_times.latency_median_s - 0.0015 | fabs) < 1e-9 and (.channels | map(.name)) == ["gx","gy","gz","ax","ay","az"]'

# the big benchmark's bag at 1 s (gen-ros bag-camera, streamed): the IMU
# among 30 camera frames in chunks of 768 KiB, every message counted
for m in none lz4; do
	"$GEN" "$T/c" 200 1 "bag-camera$([ $m = lz4 ] && echo -lz4)" || not_ok "gen-ros bag-camera $m"
	run "info json of a camera bag ($m)" 0 info --format json "$T/c/camera-imu-$m.bag"
	json_check "camera bag ($m): 200 IMU rows among 30 frames" "$T/out" \
	  '.rows == 200 and ([.topics[] | [.name, .messages]]) == [["/imu/data", 200], ["/camera/image_raw", 30]] and .receive_times.agree == true'
	rm -f "$T/c/camera-imu-$m.bag"
done

run "two IMU topics" 1 info "$T/r/two-imu.mcap"
has "two IMU topics: lists them and names --topic" "$T/err" 'MCAP|two-imu.mcap: 2 IMU topics: choose one with --topic NAME .*/imu1/data'
one_line_error "two IMU topics"
run "--topic picks one" 0 info --format json --topic /imu1/data "$T/r/two-imu.mcap"
json_check "--topic: the named topic is read" "$T/out" \
  '([.topics[] | select(.selected) | .name]) == ["/imu1/data"] and .channels[0].samples == 6000'
run "unknown topic" 1 info --topic /nope "$T/r/imu-lz4.bag"
has "unknown topic: lists the readable ones" "$T/err" "no topic '/nope' \\(readable topics: .*/imu/data"
one_line_error "unknown topic"
run "--topic on a CSV" 1 info --topic /imu "$T/r/imu.csv"
one_line_error "--topic on a CSV"

# a bag cut short
head -c 300000 "$T/r/imu-lz4.bag" >"$T/cut.bag"
run "truncated bag" 1 info "$T/cut.bag"
has "truncated bag: names the format and the fix" "$T/err" 'ROS bag: .* at byte [0-9]+ \(truncated or corrupt; `rosbag reindex`'
one_line_error "truncated bag"
head -c 300000 "$T/r/imu-zstd.mcap" >"$T/cut.mcap"
run "truncated MCAP" 1 info "$T/cut.mcap"
has "truncated MCAP: names the format and the fix" "$T/err" 'MCAP: .*`mcap recover`'
one_line_error "truncated MCAP"
printf '#ROSBAG V1.2\n0000000000' >"$T/old.bag"
run "bag v1.2" 1 info "$T/old.bag"
has "bag v1.2: names the version and the fix" "$T/err" "only ROS bag format 2.0 is read \\(migrate older bags with \`rosbag fix\`\\)"

# the same data through stdin (recognised by the leading bytes)
run_in "MCAP on stdin" 0 "$T/r/imu-lz4.mcap" info --format json -
json_check "MCAP on stdin: 6000 rows" "$T/out" '.channels[0].samples == 6000 and .format == "MCAP (lz4 chunks)"'
gzip -c "$T/r/imu.csv" >"$T/imu.csv.gz"
run_in "gzip CSV on stdin" 0 "$T/imu.csv.gz" info --format json -
json_check "gzip on stdin: format, rows" "$T/out" '.format == "gzip-compressed text" and .channels[0].samples == 6000 and .rate_hz == 200'
head -c 100000 "$T/imu.csv.gz" >"$T/cut.csv.gz"
run "truncated gzip" 1 info "$T/cut.csv.gz"
has "truncated gzip: says so" "$T/err" 'gzip data truncated'
one_line_error "truncated gzip"

# the codecs' and SQLite's libraries are opened when a file needs them:
# one that cannot be loaded (here a broken file found first through
# LD_LIBRARY_PATH) is a one-line error naming it, and the files that do
# not need it still read
mkdir -p "$T/badlib"
for l in libzstd.so.1 liblz4.so.1 libbz2.so.1.0 libsqlite3.so.0; do
	echo 'not a library' >"$T/badlib/$l"
done
badlib_run() {
	old_llp=${LD_LIBRARY_PATH-}
	LD_LIBRARY_PATH="$T/badlib${old_llp:+:$old_llp}"
	export LD_LIBRARY_PATH
	run "$@"
	if [ -n "$old_llp" ]; then LD_LIBRARY_PATH=$old_llp; else unset LD_LIBRARY_PATH; fi
}
for f in imu-zstd.mcap:libzstd.so.1 imu-lz4.bag:liblz4.so.1 \
	 imu-bz2.bag:libbz2.so.1.0; do
	badlib_run "${f%%:*} without ${f#*:}" 1 info "$T/r/${f%%:*}"
	has "${f%%:*} without ${f#*:}: names the library" "$T/err" "cannot load ${f#*:} \\("
	one_line_error "${f%%:*} without ${f#*:}"
done
if [ $have_db3 = 1 ]; then
	badlib_run "a .db3 without libsqlite3" 1 info "$T/r/rosbag2"
	has "a .db3 without libsqlite3: names the library" "$T/err" 'cannot load libsqlite3.so.0 \('
fi
badlib_run "an uncompressed bag needs none of them" 0 info "$T/r/imu-none.bag"

# npy: its header is not read as samples; shapes are checked
if [ -x /usr/bin/python3 ] && /usr/bin/python3 -c 'import numpy' 2>/dev/null; then
	/usr/bin/python3 - "$T" <<'EOF'
import sys, numpy as np
d = sys.argv[1]
x = np.arange(3000, dtype='<f4').reshape(1000, 3) * 0.25
np.save(d + '/x.npy', x)
np.save(d + '/xf.npy', np.asfortranarray(x.astype('>f8')))
np.save(d + '/cube.npy', np.zeros((2, 3, 4)))
EOF
	for f in x.npy xf.npy; do
		run "npy $f" 0 info --format json -r 100 -u deg/s "$T/$f"
		json_check "npy $f: 3 channels of 1000, exact values" "$T/out" \
		  '(.format | startswith("NumPy .npy")) and (.channels | length) == 3 and .channels[1].samples == 1000 and .channels[1].min == 0.25 and .channels[2].max == 749.75 and .channels[0].unit == "deg/s"'
	done
	run "npy of three dimensions" 1 info "$T/cube.npy"
	has "npy 3-D: says what a capture is" "$T/err" 'more than two dimensions'
	one_line_error "npy 3-D"
	head -c 2000 "$T/x.npy" >"$T/cut.npy"
	run "truncated npy" 1 info "$T/cut.npy"
	has "truncated npy: shape named" "$T/err" 'npy data are [0-9]+ bytes where the shape \(1000, 3\) and dtype need 12000 \(truncated\?\)'
	one_line_error "truncated npy"
else
	skip "npy files" "no numpy"
fi

# rostopic echo -p CSV: frame_id strings skipped, %time in ns
{
	echo '%time,field.header.seq,field.header.stamp,field.header.frame_id,field.angular_velocity.x,field.angular_velocity.y,field.angular_velocity.z,field.linear_acceleration.x,field.linear_acceleration.y,field.linear_acceleration.z,field.angular_velocity_covariance0'
	i=0
	while [ $i -lt 400 ]; do
		echo "$((1700000000001500000 + 5000000 * i)),$i,$((1700000000000000000 + 5000000 * i)),imu_link,0.0$((i % 7)),0.01,0.02,0.1,0.2,9.8,-1"
		i=$((i + 1))
	done
} >"$T/rostopic.csv"
run "rostopic -p CSV" 0 info --format json "$T/rostopic.csv"
json_check "rostopic: gx..az, 200 Hz from the ns header stamps" "$T/out" \
  '(.channels | map(.name)) == ["gx","gy","gz","ax","ay","az"] and .rate_hz == 200 and .channels[0].unit == "rad/s" and .channels[5].unit == "m/s^2"'
run "rostopic -p CSV with -c" 0 info --format json -c gx "$T/rostopic.csv"
json_check "rostopic -c: still 200 Hz" "$T/out" '.rate_hz == 200'

# nanoseconds read as seconds: a warning that names the unit
awk -F, 'NR == 1 { print "time,gx"; next } { print $1 "," $2 }' "$T/r/imu.csv" >"$T/ns.csv"
run "ns stamps without a unit" 0 info "$T/ns.csv"
has "ns as s: warning names ns and the true rate" "$T/err" "warning: .*rate 2e-07 Hz from the time column 'time' \\(read as s\\) is implausible: if its stamps are in ns the rate is 200 Hz"

done_testing
