#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: big ROS recordings read by streaming in bounded memory.  A
# 200 Hz IMU topic among the frames of a 30 Hz camera, about
# BENCH_ROS_BIG_GB gigabytes (default 10) each, generated streaming by
# tests/gen-ros:
#   1. an MCAP with zstd chunks of 4 MiB (mcap-camera-zst), with the
#      chunks' zstd frames alone beside it (one zstd stream): zstd -d -T0
#      on that stream is timed against the reader on the MCAP;
#   2. a ROS 1 bag v2.0 with uncompressed chunks of 768 KiB (bag-camera).
# Each is read with the whole command `sensorscope info --format json` on
# the default threads and on one (/usr/bin/time: wall, CPU, peak RSS) and
# deleted.  Every timed run reads its file from the page cache.  Needs about 2 * BENCH_ROS_BIG_GB of free disk in BENCH_ROS_DIR
# (default a temporary folder).  Targets: the MCAP at least 300 MB/s or
# within 1.5x of zstd -d, the bag at least 1 GB/s, peak RSS at most 1 GB.
set -u
: "${top_builddir:=.}"
S="$top_builddir/src/sensorscope"
GEN="$top_builddir/tests/gen-ros"
GB=${BENCH_ROS_BIG_GB:-10}
D=$(mktemp -d "${BENCH_ROS_DIR:-${TMPDIR:-/tmp}}/sscope-bench-ros-big.XXXXXX")
trap 'rm -rf "$D"' EXIT
if [ ! -x /usr/bin/time ]; then
	echo "bench-ros-big: /usr/bin/time (Debian package time) is needed for the peak memory: skipped"
	exit 0
fi

# generate MODE DURATION FILE: sets mb, the file's size in MB
generate() {
	t0=$(date +%s.%N)
	"$GEN" "$D" 200 "$2" "$1" || exit 1
	t1=$(date +%s.%N)
	mb=$(echo "$(du -b "$3" | cut -f1) / 1000000" | bc -l)
	printf '%s: generated %.0f MB (%d s of recording) in %.1f s; load average %s\n' \
		"$1" "$mb" "$2" "$(echo "$t1 - $t0" | bc)" "$(cut -d' ' -f1-3 /proc/loadavg)"
	sync # no write-back of the generated files during the timed runs
}

# warm FILE: read once, so that every timed run reads it from the page
# cache (the first read of a file just written can be bound by the disk)
warm() {
	cat "$1" >/dev/null
}

# timed LABEL MB COMMAND...: one run under /usr/bin/time; sets w (wall)
timed() {
	l=$1
	m=$2
	shift 2
	/usr/bin/time -f "%e %U %S %M" -o "$D/time" "$@" >"$D/out.json" || exit 1
	read -r w us sy kb <"$D/time"
	printf '%s: %.2f s wall, %.2f s CPU, %.0f MB/s, peak RSS %.0f MB\n' \
		"$l" "$w" "$(echo "$us + $sy" | bc)" "$(echo "$m / $w" | bc -l)" \
		"$(echo "$kb / 1024" | bc -l)"
}

# reads FILE LABEL: info on the default threads and on one, twice each;
# sets wd (the best wall on the default threads) and rows
reads() {
	for th in default 1; do
		for i in 1 2; do
			if [ "$th" = default ]; then
				timed "$2 info, $th threads, run $i" "$mb" "$S" info --format json "$1"
				[ "$i" = 1 ] || [ "$(echo "$w < $wd" | bc)" = 1 ] && wd=$w
			else
				timed "$2 info, $th thread, run $i" "$mb" env OMP_NUM_THREADS=1 \
					"$S" info --format json "$1"
			fi
		done
	done
	rows=$(sed -n 's/.*"rows": *\([0-9]*\).*/\1/p' "$D/out.json" | head -n 1)
}

# 1. MCAP, zstd chunks: 4.64 MB of file per second of recording
dur=$(echo "$GB * 1000000000 / 4640000" | bc)
F="$D/camera-imu-zstd.mcap"
Z="$D/camera-imu-zstd.zst"
generate mcap-camera-zst "$dur" "$F"
if command -v zstd >/dev/null; then
	zmb=$(echo "$(du -b "$Z" | cut -f1) / 1000000" | bc -l)
	warm "$Z"
	for i in 1 2; do
		timed "$(zstd -V | sed 's/.*\(v[0-9.]*\).*/zstd \1/') -d -T0 -c on the chunks' frames ($(printf %.0f "$zmb") MB), run $i" \
			"$zmb" zstd -q -d -T0 -c "$Z"
		[ "$i" = 1 ] || [ "$(echo "$w < $zw" | bc)" = 1 ] && zw=$w
	done
else
	echo "zstd: not installed, no comparison"
	zw=
fi
rm -f "$Z"
warm "$F"
reads "$F" MCAP
echo "MCAP: IMU rows read: $rows (expected about $((dur * 200)): the messages up to the last frame)"
[ -n "$zw" ] && printf 'MCAP: best info on the default threads %.2f s against zstd -d %.2f s: %.2fx its time\n' \
	"$wd" "$zw" "$(echo "$wd / $zw" | bc -l)"
rm -f "$F"

# 2. ROS 1 bag, uncompressed chunks: 9.29 MB of file per second
dur=$(echo "$GB * 1000000000 / 9290000" | bc)
F="$D/camera-imu-none.bag"
generate bag-camera "$dur" "$F"
warm "$F"
reads "$F" "ROS 1 bag"
echo "ROS 1 bag: IMU rows read: $rows (expected $((dur * 200)))"
rm -f "$F"
[ "$rows" = $((dur * 200)) ] || exit 1
