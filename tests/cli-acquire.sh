#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope acquire through the simulator (no hardware): captures that
# other commands read, counts and durations, the summary in text and
# JSON, clean stops on SIGINT and SIGTERM, usage errors, missing devices,
# and the not-built path of --drdy.  The device paths are tested against
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
	while [ ! -s "$T/s$sig.csv" ] && ! ls "$T" | grep -q "s$sig.csv.tmp" && [ $i -lt 200 ]; do
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
	if ls "$T" | grep -q '\.tmp\.'; then not_ok "SIG$sig: temporary left"; else ok "SIG$sig: no temporary left"; fi
done

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
has "no such SPI device: named" "$T/err" '/dev/spidev-none.9: No such file'
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
