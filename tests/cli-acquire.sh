#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope acquire through the simulator (no hardware): captures that
# other commands read, counts and durations, the summary in text and
# JSON, clean stops on SIGINT and SIGTERM, usage errors, missing devices,
# and the not-built path of --drdy.  Recordings are never lost: FILE.partial
# is read after kill -9, a full disk (a tmpfs where a mount is permitted)
# and a file size limit keep the samples, an existing file is refused
# without --overwrite, and the unpaced simulator never drops a sample.  The device paths are tested against
# emulated devices by tests/acq-fake.
. "$(dirname "$0")/lib.sh"

slow=0
[ -n "$SSCOPE_RUN" ] && slow=1
N=2000
[ "$slow" = 1 ] && N=400

run "acquire --help" 0 acquire --help
has "help names --drdy" "$T/out" '--drdy CHIP:LINE'
has "help names the simulator" "$T/out" 'sim\[:OPTS\]'
has "help gives the exit status" "$T/out" 'Exit status'

# a capture from the simulator, paced 20 times faster than real time
run "sim capture" 0 acquire --source sim:speed=20 --count "$N" -o "$T/a.csv"
has "summary: samples" "$T/out" "^samples: +$N\$"
has "summary: drops" "$T/out" '^drops: +0 '
has "summary: checksum errors" "$T/out" '^checksum errors: 0'
has "summary: stopped by count" "$T/out" '^stopped by: +count'
has "capture header" "$T/a.csv" '^time \[s\],gx \[deg/s\],gy \[deg/s\],gz \[deg/s\],ax \[m/s\^2\],ay \[m/s\^2\],az \[m/s\^2\],temp \[degC\]$'
has "capture says where it came from" "$T/a.csv" '^# sensorscope acquire: simulator'
has "capture end comment" "$T/a.csv" "^# end: $N samples, 0 missing"
run "info reads the capture" 0 info --format json "$T/a.csv"
json_check "info: $N rows at 1 kHz, 6 channels, no gap" "$T/out" \
	".channels | length == 6 and .[0].samples == $N and (.[0].rate_hz - 1000 | fabs) < 1e-6"
json_check "info: gyro in deg/s, accelerometer near 1 g on z" "$T/out" \
	'.channels[0].unit == "deg/s" and (.channels[5].mean - 9.80665 | fabs) < 0.01'

run "json summary" 0 acquire --source sim:rate=500,speed=max --duration 0.5 --format json -o "$T/b.csv"
json_check "json: 250 samples over 0.5 s at 500 Hz" "$T/out" \
	'.command == "acquire" and .samples == 250 and .stop == "duration" and .nominal_rate_hz == 500'
json_check "json: drops, checksum errors, interval" "$T/out" \
	'.drops.total == 0 and .checksum_errors == 0 and .interval.n == 249 and .interval.jitter_s == 0 and .committed'

run "binary capture" 0 acquire --source sim:speed=max,channels=3 --count 100 --capture-format f32 -o "$T/c.ssb"
has "binary header" "$T/c.ssb" '^#sensorscope-binary 1 f32 le$'
run "info reads the binary capture" 0 info --format json "$T/c.ssb"
json_check "binary: 100 rows of 3 channels" "$T/out" '.channels | length == 3 and .[0].samples == 100'

run "capture to stdout" 0 acquire --source sim:speed=max --count 10 -o -
has "stdout holds the capture" "$T/out" '^time \[s\],gx'
lacks "stdout holds no summary" "$T/out" '^samples:'
has "the summary goes to stderr" "$T/err" '^samples: +10$'

run "live view" 0 acquire --source sim:speed=10 --count 1500 --live -o "$T/d.csv"
has "live view shows ADEV" "$T/err" 'ADEV'
has "live view shows the channels" "$T/err" 'gx \[deg/s\]'

# --realtime: SCHED_FIFO and mlockall, or a warning that says why not
run "--realtime" 0 acquire --source sim:speed=10 --count 500 --realtime --format json -o "$T/rt.csv"
if command -v jq >/dev/null 2>&1; then
	if [ "$(jq .realtime "$T/out")" = true ]; then
		lacks "--realtime granted: no warning" "$T/err" 'SCHED_FIFO'
	else
		has "--realtime refused: a warning says so" "$T/err" '^sensorscope: acquire: warning: SCHED_FIFO priority 50 not permitted'
	fi
	json_check "--realtime: all 500 samples" "$T/out" '.samples == 500 and .drops.total == 0'
else
	skip "--realtime" "jq not installed"
fi

# clean stops: everything read is in a valid file
for sig in INT TERM HUP; do
	$SSCOPE_RUN "$SSCOPE" acquire --source sim:rate=2000 --format json \
		-o "$T/s$sig.csv" >"$T/out" 2>"$T/err" &
	pid=$!
	# wait for the capture to start, then stop it
	i=0
	while [ ! -s "$T/s$sig.csv.partial" ] && [ $i -lt 600 ]; do
		sleep 0.1
		i=$((i + 1))
	done
	sleep 1
	kill -"$sig" "$pid"
	wait "$pid"
	got=$?
	if [ "$got" -eq 0 ]; then ok "SIG$sig: exit 0"; else not_ok "SIG$sig: exit $got"; diag "$T/err"; fi
	json_check "SIG$sig: stopped by the signal" "$T/out" '.stop == "signal" and .samples > 0'
	if command -v jq >/dev/null 2>&1; then
		n=$(jq .samples "$T/out")
		rows=$(grep -cv '^[#t]' "$T/s$sig.csv")
		if [ "$n" = "$rows" ]; then ok "SIG$sig: $rows rows = reported samples"; else not_ok "SIG$sig: $rows rows, $n reported"; fi
	else
		skip "SIG$sig: rows = reported samples" "jq not installed"
	fi
	run "SIG$sig: the file is a valid capture" 0 info "$T/s$sig.csv"
	if ls "$T" | grep -q '\.tmp\.\|\.partial'; then not_ok "SIG$sig: temporary left"; else ok "SIG$sig: no temporary left"; fi
done

# kill -9 (or an out-of-memory kill, or a power cut): the samples are in
# FILE.partial, which every command reads up to its last complete row
for fmt in csv f32; do
	k=$T/k-$fmt
	$SSCOPE_RUN "$SSCOPE" acquire --source sim:rate=1000,channels=3 \
		--capture-format $fmt -o "$k" >"$T/out" 2>"$T/err" &
	pid=$!
	# until at least 1000 rows are in the file (as long as it takes)
	i=0 n=0
	while [ $i -lt 1200 ]; do
		if [ -s "$k.partial" ]; then
			ss info --format json "$k.partial" >"$T/kinfo" 2>/dev/null &&
				n=$(sed -n 's/.*"rows":\([0-9]*\).*/\1/p' "$T/kinfo")
			[ "${n:-0}" -ge 1000 ] && break
		fi
		sleep 0.1
		i=$((i + 1))
	done
	kill -KILL "$pid"
	wait "$pid" 2>/dev/null
	if [ ! -e "$k" ] && [ -e "$k.partial" ]; then
		ok "kill -9 ($fmt): the recording is FILE.partial"
	else
		not_ok "kill -9 ($fmt): no FILE.partial"
	fi
	run "kill -9 ($fmt): info reads FILE.partial" 0 info --format json "$k.partial"
	json_check "kill -9 ($fmt): every sample seen before the kill, at 1 kHz, no gap" "$T/out" \
		".rows >= ${n:-1000} and (.rate_hz - 1000 | fabs) < 0.01 and (.gaps | length) == 0"
	if [ $fmt = csv ]; then
		rows=$(grep -cv '^[#t]' "$k.partial")
		lacks "kill -9 (csv): no end line" "$k.partial" '^# end:'
		# the row being written when the process died
		printf '9.99,0.012,-0.0' >>"$k.partial"
	else
		# rows of 5 float32 after the two header lines
		rows=$((($(wc -c <"$k.partial") - $(head -2 "$k.partial" | wc -c)) / 20))
		printf 'abc' >>"$k.partial"
	fi
	run "kill -9 ($fmt): an unfinished last row is left out" 0 info --format json "$k.partial"
	json_check "kill -9 ($fmt): the $rows whole rows read" "$T/out" ".rows == $rows"
	run "kill -9 ($fmt): allan reads it too" 0 allan --format json -c gx "$k.partial"
	run "kill -9 ($fmt): the interrupted recording is never overwritten" 1 \
		acquire --source sim:speed=max --count 10 --overwrite --capture-format $fmt -o "$k"
	one_line_error "kill -9 ($fmt): refused"
	has "kill -9 ($fmt): the refusal says why" "$T/err" 'partial exists'
done

# an existing file is never replaced by accident
echo "precious" >"$T/old.csv"
run "existing file refused" 1 acquire --source sim:speed=max --count 10 -o "$T/old.csv"
one_line_error "existing file refused"
has "existing file: says what to do" "$T/err" 'exists; give another name, or --overwrite'
if [ "$(cat "$T/old.csv")" = precious ] && [ ! -e "$T/old.csv.partial" ]; then
	ok "existing file: untouched, nothing left"
else
	not_ok "existing file: changed"
fi
run "--overwrite replaces it at the end" 0 acquire --source sim:speed=max --count 10 --overwrite -o "$T/old.csv"
has "--overwrite: the new recording" "$T/old.csv" '^# end: 10 samples'

# the unpaced simulator waits for the writer: the manual's example, and a
# tiny ring, lose nothing
run "unpaced, the manual's example" 0 acquire --source sim:speed=max --count 100000 \
	--capture-format f64 --format json -o "$T/max.ssb"
json_check "unpaced: 100000 samples, no drop" "$T/out" \
	'.samples == 100000 and .drops.total == 0 and .missing == 0'
lacks "unpaced: no overrun warning" "$T/err" 'fell behind'
run "unpaced, 16-sample ring" 0 acquire --source sim:speed=max --count 20000 \
	--ring 16 --format json -o "$T/max16.csv"
json_check "16-sample ring: 20000 samples, no drop" "$T/out" \
	'.samples == 20000 and .drops.total == 0'

# a file size limit (RLIMIT_FSIZE; acquire ignores SIGXFSZ, so writes fail
# with EFBIG, a full disk's path): the file ends at its last complete row,
# kept
(
	ulimit -f 64 # 32 or 64 KiB (blocks of 512 or 1024 bytes)
	exec $SSCOPE_RUN "$SSCOPE" acquire --source sim:speed=max --count 100000 \
		--format json -o "$T/limit.csv" >"$T/out" 2>"$T/err"
)
got=$?
if [ $got -eq 1 ]; then ok "file size limit: exit 1"; else not_ok "file size limit: exit $got"; fi
one_line_error "file size limit"
has "file size limit: says it and where the samples are" "$T/err" \
	'^sensorscope: acquire: stopped: file size limit: .*limit.csv: file too large; the [0-9]+ samples recorded before it are in .*limit.csv'
json_check "file size limit: summary" "$T/out" \
	'.stop == "file size limit" and .committed and .samples > 100 and .unsaved > 0'
if [ -e "$T/limit.csv" ] && [ ! -e "$T/limit.csv.partial" ]; then
	ok "file size limit: kept as FILE"
else
	not_ok "file size limit: FILE missing"
fi
if [ "$(tail -c 1 "$T/limit.csv" | od -An -c | tr -d ' ')" = '\n' ]; then
	ok "file size limit: the file ends with a whole line"
else
	not_ok "file size limit: a cut line at the end"
fi
if command -v jq >/dev/null 2>&1; then
	n=$(jq .samples "$T/out")
	rows=$(grep -cv '^[#t]' "$T/limit.csv")
	if [ "$n" = "$rows" ]; then
		ok "file size limit: $rows rows = reported samples"
	else
		not_ok "file size limit: $rows rows, $n reported"
	fi
	run "file size limit: info reads it" 0 info --format json "$T/limit.csv"
	json_check "file size limit: info finds the samples" "$T/out" ".rows == $n"
else
	skip "file size limit: rows" "jq not installed"
fi

# a really full disk: a 64 KiB tmpfs mounted in a private mount namespace
# (as root, or in an unprivileged user namespace); skipped where neither
# is permitted (a container without CAP_SYS_ADMIN)
cat >"$T/full.sh" <<'END'
mount -t tmpfs -o size=64k none "$1" 2>/dev/null || exit 77
cd "$1" || exit 77
$SSCOPE_RUN "$SSCOPE" acquire --source sim:speed=max --count 100000 \
	-o rec.csv >"$2/out" 2>"$2/err"
echo $? >"$2/rc"
ls -a >"$2/ls"
grep -cv '^[#t]' rec.csv >"$2/rows"
tail -c 1 rec.csv | od -An -c | tr -d ' ' >"$2/last"
$SSCOPE_RUN "$SSCOPE" info --format json rec.csv >"$2/info" 2>&1
exit 0
END
mkdir "$T/mnt" "$T/fullres"
export SSCOPE SSCOPE_RUN
how=
for u in "unshare -m" "unshare -rm"; do
	if $u sh "$T/full.sh" "$T/mnt" "$T/fullres" 2>/dev/null; then
		how=$u
		break
	fi
done
if [ -n "$how" ] && [ -s "$T/fullres/rc" ]; then
	if [ "$(cat "$T/fullres/rc")" = 1 ]; then ok "disk full ($how): exit 1"; else not_ok "disk full: exit $(cat "$T/fullres/rc")"; fi
	cp "$T/fullres/err" "$T/err"
	one_line_error "disk full"
	has "disk full: says so" "$T/err" \
		'^sensorscope: acquire: stopped: disk full: rec.csv: no space left on device; the [0-9]+ samples recorded before it are in rec.csv'
	has "disk full: the summary says it" "$T/fullres/out" '^stopped by: +disk full'
	n=$(sed -n 's/^samples: *//p' "$T/fullres/out")
	if [ "$n" = "$(cat "$T/fullres/rows")" ] && [ "$n" -gt 100 ]; then
		ok "disk full: the $n rows kept = reported samples"
	else
		not_ok "disk full: $(cat "$T/fullres/rows") rows, $n reported"
	fi
	if grep -qx 'rec.csv' "$T/fullres/ls" && ! grep -q partial "$T/fullres/ls"; then
		ok "disk full: kept as FILE"
	else
		not_ok "disk full: not kept"
	fi
	if [ "$(cat "$T/fullres/last")" = '\n' ]; then ok "disk full: ends with a whole line"; else not_ok "disk full: a cut line at the end"; fi
	json_check "disk full: info reads it" "$T/fullres/info" ".rows == $n"
else
	skip "disk full on a 64 KiB tmpfs" "no mount namespace here (needs root or user namespaces)"
fi

# usage errors: exit 2, one line
run "no source" 2 acquire -o "$T/x.csv"
one_line_error "no source"
run "no output" 2 acquire --source sim --count 10
one_line_error "no output"
has "no output: says what to give" "$T/err" 'give -o FILE'
run "sim and spi together" 2 acquire --source sim --spi /dev/spidev0.0 --device adis16470 -o "$T/x.csv"
one_line_error "sim and spi together"
run "unknown source" 2 acquire --source frob -o "$T/x.csv"
one_line_error "unknown source"
run "bad sim option" 2 acquire --source sim:rate=fast -o "$T/x.csv"
one_line_error "bad sim option"
run "bad --count" 2 acquire --source sim --count 0 -o "$T/x.csv"
run "bad --duration" 2 acquire --source sim --duration 3kg -o "$T/x.csv"
one_line_error "bad --duration"
run "bad --capture-format" 2 acquire --source sim --capture-format xml -o "$T/x.csv"
run "--format csv is for captures" 2 acquire --source sim --format csv -o "$T/x.csv"
run "unknown device" 2 acquire --spi /dev/spidev0.0 --device adis99999 -o "$T/x.csv"
one_line_error "unknown device"
has "unknown device: lists the known ones" "$T/err" 'adis16470'
run "bad converter frame" 2 acquire --spi /dev/spidev0.0 --rate 100 --device spiadc:tx=zz,ch=a@0 -o "$T/x.csv"
one_line_error "bad converter frame"
run "converter frame without a rate or a data-ready line" 2 acquire --spi /dev/spidev0.0 --device spiadc:tx=0000,bits=12,range=0:5,ch=a@4 -o "$T/x.csv"
one_line_error "converter frame without a rate"

# runtime errors: exit 1, one line, no file
run "no such SPI device" 1 acquire --spi /dev/spidev-none.9 --device adis16470 --count 5 -o "$T/x.csv"
one_line_error "no such SPI device"
has "no such SPI device: named" "$T/err" '/dev/spidev-none.9: no such file'
run "output directory missing" 1 acquire --source sim:speed=max --count 5 -o "$T/nodir/x.csv"
one_line_error "output directory missing"
if [ -e "$T/x.csv" ]; then not_ok "no file after errors"; else ok "no file after errors"; fi

# --drdy needs libgpiod
if ss --version | grep -q 'acquisition: no'; then
	run "--drdy not built" 2 acquire --spi /dev/spidev0.0 --drdy gpiochip0:25 --device adis16470 -o "$T/x.csv"
	one_line_error "--drdy not built"
	has "--drdy not built: says why" "$T/err" 'built without'
else
	skip "--drdy not built" "this sensorscope has libgpiod"
	run "--drdy malformed" 2 acquire --spi /dev/spidev-none.9 --drdy gpiochip0 --device adis16470 -o "$T/x.csv"
	one_line_error "--drdy malformed"
fi
# a recorded capture runs through allan and psd unchanged: the simulator's
# ARW 0.34 deg/sqrt(h) comes back (6000 samples: sd of N about 1 %, bound 5 %)
run "record for allan" 0 acquire --source sim:rate=100,speed=50,seed=4 --duration 60 -o "$T/rec.csv"
run "allan of the recording" 0 allan --taus octave --format json -c gx,gy,gz "$T/rec.csv"
json_check "ARW recovered" "$T/out" '[.channels[] | .noise.N.value] | all(((. - 0.34) / 0.34 | fabs) < 0.05)'
run "psd of the recording" 0 psd --format json -c gx "$T/rec.csv"
# white noise: RMS = N sqrt(fs) = 0.34/60 deg/sqrt(s) * 10 /sqrt(s)
json_check "white level recovered" "$T/out" '((.channels[0].rms - 0.34 / 60 * 10) / (0.34 / 60 * 10) | fabs) < 0.05'
done_testing
