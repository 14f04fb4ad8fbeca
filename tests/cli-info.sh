#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope info on every sample, EuRoC, raw int16, stdin; text, JSON
# and CSV output; atomic -o; --plot.
. "$(dirname "$0")/lib.sh"

for f in gyro-static.csv accel-thermal.csv vibration.csv euroc-imu.csv; do
	run "info $f" 0 info "$SAMPLES/$f"
	has "info $f: rate line" "$T/out" '^  rate: +[0-9]'
done

run "gyro json" 0 info --format json "$SAMPLES/gyro-static.csv"
cp "$T/out" "$T/gyro.json"
json_check "gyro: contract fields" "$T/gyro.json" \
  '.command == "info" and (.channels | length) == 3 and .channels[0].name == "gx" and .channels[0].unit == "deg/s" and .channels[0].quantity == "angular rate" and .channels[0].rate_hz == 10 and .channels[0].samples == 36000 and .channels[0].duration_s == 3600 and .rate_source == "header"'
json_check "gyro: statistics in deg/s" "$T/gyro.json" \
  '(.channels[0].mean - 0.12 | fabs) < 0.02 and .channels[0].sd > 0.005 and .channels[0].sd < 0.05 and .channels[0].min < .channels[0].mean and .channels[0].max > .channels[0].mean'

run "accel json" 0 info --format json "$SAMPLES/accel-thermal.csv"
cp "$T/out" "$T/acc.json"
json_check "accel: temperature range" "$T/acc.json" \
  '.temperature.min < -9 and .temperature.max > 49 and .temperature.unit == "degC"'
json_check "accel: rate from time column, no gaps" "$T/acc.json" \
  '.rate_source == "time column" and .rate_hz == 1 and (.gaps | length) == 0 and .channels[2].unit == "g" and (.channels[2].mean - 1 | fabs) < 0.01'

run "euroc json" 0 info --format json "$SAMPLES/euroc-imu.csv"
cp "$T/out" "$T/euroc.json"
json_check "euroc: 200 Hz from ns stamps, SI units" "$T/euroc.json" \
  '.rate_hz == 200 and (.channels | length) == 6 and .channels[0].unit == "rad s^-1" and .channels[3].quantity == "acceleration" and .timing.jitter_rms_s < 1e-12'

run "raw int16" 0 info --format json --raw i16:6:le --scale 0.01 -u deg/s -r 100 "$SAMPLES/imu-raw.bin"
cp "$T/out" "$T/raw.json"
json_check "raw: 6 channels, 6000 samples, scaled" "$T/raw.json" \
  '(.channels | length) == 6 and .channels[0].samples == 6000 and (.channels[0].mean - 0.1 | fabs) < 0.01 and (.channels[2].mean - 0.3 | fabs) < 0.01 and .channels[0].unit == "deg/s"'
run "raw column selection" 0 info --format json --raw i16:6:le --scale 0.5 -u mg -r 100 -c 6 "$SAMPLES/imu-raw.bin"
json_check "raw: az = 1000 mg" "$T/out" '(.channels | length) == 1 and .channels[0].name == "ch6" and (.channels[0].mean - 1000 | fabs) < 1'

run_in "stdin" 0 "$SAMPLES/vibration.csv" info --format json -
cp "$T/out" "$T/stdin.json"
json_check "stdin: same as the file" "$T/stdin.json" \
  '.rate_hz == 5000 and .channels[0].samples == 10000 and .file == "-"'
run "vibration csv" 0 info --format csv "$SAMPLES/vibration.csv"
has "csv header" "$T/out" '^file,channel,unit,quantity,rate_hz,samples'
has "csv row" "$T/out" 'vibration.csv,ax,m/s\^2,acceleration,5000,10000,'

run "columns by name" 0 info -c gz,gx "$SAMPLES/gyro-static.csv"
has "selected gz" "$T/out" '^  gz '
lacks "not gy" "$T/out" '^  gy '

# -o writes atomically; a failing run leaves nothing behind
run "-o file" 0 info -o "$T/info.txt" "$SAMPLES/gyro-static.csv"
has "-o content" "$T/info.txt" 'rows: +36000'
run "-o into a missing directory" 1 info -o "$T/no/such/dir/x.txt" "$SAMPLES/gyro-static.csv"
one_line_error "-o into a missing directory"
run "failed load leaves no output" 1 info -o "$T/never.txt" "$DATA/ragged.csv"
if [ ! -e "$T/never.txt" ] && [ -z "$(ls "$T" | grep tmp)" ]; then ok "no partial output"; else not_ok "partial output left"; fi

# time-stamp gaps
run "gaps" 0 info --format json "$DATA/gaps.csv"
json_check "gaps listed" "$T/out" '.timing.gaps == 2 and .timing.missing == 3 and .gaps[0].row == 5 and .gaps[0].missing == 2'
run "gaps text" 0 info "$DATA/gaps.csv"
has "gap text" "$T/out" 'gaps: +2 \(about 3 samples missing\)'

# --rate against a time column that disagrees: warning, not error
run "rate mismatch warns" 0 info -r 50 "$SAMPLES/accel-thermal.csv"
has "warning text" "$T/err" 'warning: .*--rate 50 Hz but the time column implies 1 Hz: using --rate 50 Hz'

if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "--plot" 0 info --plot "$T/info.png" "$SAMPLES/accel-thermal.csv"
	if head -c 8 "$T/info.png" | od -An -c | grep -q 'P   N   G'; then ok "PNG written"; else not_ok "PNG written"; fi
else
	run "--plot without OpenCV" 2 info --plot "$T/info.png" "$SAMPLES/accel-thermal.csv"
	has "--plot message" "$T/err" 'built without OpenCV'
fi
done_testing
