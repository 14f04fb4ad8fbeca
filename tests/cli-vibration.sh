#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope vibration: the contract's JSON on the bundled samples
# (unbalance at 1770 rpm; an outer-race defect at 1797 rpm), units, a
# MATLAB v5 file, bad options and inputs, --plot.
. "$(dirname "$0")/lib.sh"

run "unbalance sample, text" 0 vibration --rpm 1770 --iso-class II "$SAMPLES/vibration.csv"
has "velocity and zone" "$T/out" 'velocity 10-1000 Hz: 15\.[0-9]+ mm/s rms, zone D \(class II\)'
has "unbalance finding with evidence" "$T/out" 'unbalance: 1x = 15\.[0-9] mm/s rms at 29\.50 Hz'
lacks "no misalignment" "$T/out" 'misalignment'
has "edition named" "$T/out" 'ISO 10816-1:1995'

run "unbalance sample, json" 0 vibration --format json --rpm 1770 --iso-class II -c ax "$SAMPLES/vibration.csv"
cp "$T/out" "$T/u.json"
json_check "contract: severity, kurtosis, diagnosis" "$T/u.json" \
  '.command == "vibration" and (.channels[0].severity.velocity_rms_mm_s | . > 15 and . < 16) and .channels[0].severity.zone == "D" and (.channels[0].kurtosis | type) == "number" and .channels[0].diagnosis[0].finding == "unbalance" and (.channels[0].diagnosis[0].evidence | test("1x = ")) and .diagnosis[0].channel == "ax"'
json_check "orders: 1x 4 m/s^2 at 29.5 Hz, 2x 0.8, 3x 0.3" "$T/u.json" \
  '.channels[0].orders as $o | ($o | length) == 3 and ($o[0].frequency_hz - 29.5 | fabs) < 0.02 and ($o[0].amplitude / 4 - 1 | fabs) < 0.01 and ($o[1].amplitude / 0.8 - 1 | fabs) < 0.03 and ($o[2].amplitude / 0.3 - 1 | fabs) < 0.05'
json_check "psd fields as psd's" "$T/u.json" \
  '.channels[0].psd_unit == "(m/s^2)^2/Hz" and (.channels[0].psd | length) == (.channels[0].frequency_hz | length) and .channels[0].envelope_peaks == []'

# the same signal in g: amplitudes in g, velocity unchanged
awk -F, 'NR == 1 || /^#/ {print; next} NR == 2 {print "t [s],ax [g]"; next} {printf "%s,%.9g\n", $1, $2 / 9.80665}' "$SAMPLES/vibration.csv" >"$T/g.csv"
run "in g" 0 vibration --format json --rpm 1770 "$T/g.csv"
json_check "in g: amplitude 4/9.80665 g, same velocity, no zone without a class" "$T/out" \
  '(.channels[0].orders[0].amplitude * 9.80665 / 4 - 1 | fabs) < 0.01 and (.channels[0].severity.velocity_rms_mm_s | . > 15 and . < 16) and .channels[0].severity.zone == null and .channels[0].severity.zones.II == "D" and .channels[0].unit == "g"'

run "bearing sample" 0 vibration --format json --rpm 1797 --bearing 9,7.94,39.04 "$SAMPLES/bearing-outer.csv"
cp "$T/out" "$T/b.json"
json_check "outer-race defect found, nothing else" "$T/b.json" \
  '(.channels[0].diagnosis | map(.finding)) == ["outer-race defect"] and (.channels[0].diagnosis[0].evidence | test("BPFO 107\\.36 Hz"))'
json_check "bearing frequencies (CWRU multiples of 29.95 Hz)" "$T/b.json" \
  '.channels[0].bearing as $b | ($b.bpfo_hz / 29.95 / 3.5848 - 1 | fabs) < 2e-4 and ($b.bpfi_hz / 29.95 / 5.4152 - 1 | fabs) < 2e-4'
json_check "envelope peaks matched" "$T/b.json" \
  '.channels[0].envelope_peaks[0].match == "BPFO" and (.channels[0].envelope_peaks | map(select(.match == "2xBPFO")) | length) == 1 and (.channels[0].envelope.band_hz[0] < 3000 and .channels[0].envelope.band_hz[1] > 3000)'
run "bearing sample, text" 0 vibration --rpm 1797 --bearing 9,7.94,39.04 "$SAMPLES/bearing-outer.csv"
has "text finding" "$T/out" '^      outer-race defect: 107\.[0-9]+ Hz \(BPFO'
run "bearing, given envelope band" 0 vibration --format json --rpm 1797 --bearing 9,7.94,39.04 --envelope-band 2500:3500 "$SAMPLES/bearing-outer.csv"
json_check "given band used" "$T/out" '.channels[0].envelope.band_hz == [2500, 3500] and .channels[0].diagnosis[0].finding == "outer-race defect"'
run "csv" 0 vibration --format csv --rpm 1797 --bearing 9,7.94,39.04 "$SAMPLES/bearing-outer.csv"
has "csv row" "$T/out" 'bearing-outer.csv,acc,m/s\^2,12000,24000,.*,outer-race defect$'

# MATLAB v5 file, as public bearing data sets are distributed
if [ -f "$DATA/bearing.mat" ]; then
	run "MATLAB .mat" 0 vibration --format json -r 12000 -u m/s^2 -c acc --rpm 1797 --bearing 9,7.94,39.04 "$DATA/bearing.mat"
	json_check ".mat: the same analysis" "$T/out" '(.channels[0].diagnosis | map(.finding)) == ["outer-race defect"]'
fi

# errors
run "--bearing without --rpm" 2 vibration --bearing 9,7.94,39.04 "$SAMPLES/bearing-outer.csv"
one_line_error "--bearing without --rpm"
for bad in "--bearing 9,39,7" "--bearing 9,7.94" "--bearing 0,1,2" "--bearing 9,1,2,95" "--iso-class V" "--rpm -5" "--tolerance 0.5" "--envelope-band 5:1" "--nperseg 4" "--peaks 50"; do
	# shellcheck disable=SC2086
	run "usage: $bad" 2 vibration --rpm 1797 $bad "$SAMPLES/bearing-outer.csv"
	one_line_error "usage: $bad"
done
run "not an acceleration" 1 vibration "$SAMPLES/gyro-static.csv"
one_line_error "not an acceleration"
has "message" "$T/err" 'channel gx is in deg/s: not an acceleration'
run "envelope band above Nyquist" 2 vibration --rpm 1797 --bearing 9,7.94,39.04 --envelope-band 5000:7000 "$SAMPLES/bearing-outer.csv"
one_line_error "envelope band above Nyquist"
printf '# rate: 1000 Hz\na [m/s^2]\n' >"$T/nan.csv"
awk 'BEGIN { for (i = 0; i < 1000; i++) print (i == 500 ? "nan" : sin(i)) }' >>"$T/nan.csv"
run "NaN gaps" 1 vibration --allow-nan "$T/nan.csv"
one_line_error "NaN gaps"
printf '# rate: 1000 Hz\na [m/s^2]\n1\n2\n3\n' >"$T/short.csv"
run "too short" 1 vibration "$T/short.csv"
one_line_error "too short"

if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "--plot" 0 vibration --plot "$T/v.png" --rpm 1797 --bearing 9,7.94,39.04 "$SAMPLES/bearing-outer.csv"
	if head -c 8 "$T/v.png" | od -An -c | grep -q 'P   N   G'; then ok "PNG written"; else not_ok "PNG written"; fi
else
	run "--plot without OpenCV" 2 vibration --plot "$T/v.png" --rpm 1797 "$SAMPLES/vibration.csv"
fi
# what the record or the options make plain is said: a gap in the stamps,
# a shaft above the Nyquist frequency, a segment longer than the record
awk 'BEGIN { print "t [s],ax [m/s^2]"; for (i = 0; i < 4096; i++)
	printf "%.6f,%.6f\n", i / 2000 + (i > 2000 ? 5 : 0), 0.5 * sin(2 * 3.14159265 * 29.5 * i / 2000) }' \
	>"$T/vgap.csv"
run "vibration, a 5 s gap" 0 vibration "$T/vgap.csv"
has "the gap: said" "$T/err" "1 gap in the time stamps: the spectrum assumes uniform sampling"
awk 'BEGIN { print "# rate: 2000 Hz"; print "ax [m/s^2]"; for (i = 0; i < 4096; i++)
	printf "%.6f\n", 0.5 * sin(2 * 3.14159265 * 29.5 * i / 2000) }' >"$T/vsine.csv"
run "vibration --rpm 1e6" 0 vibration --rpm 1e6 "$T/vsine.csv"
has "a shaft above Nyquist: said" "$T/err" "--rpm 1e\+06 puts the shaft at 16667 Hz, above the Nyquist frequency 1000 Hz"
run "vibration --nperseg 100000" 0 vibration --nperseg 100000 "$T/vsine.csv"
has "a segment longer than the record: one of the record" "$T/err" "--nperseg 100000 is longer than the record \(4096 samples\): one segment of 4096"
# a rate whose Nyquist frequency lies below the velocity band: refused
run "vibration on a 1 Hz record" 1 vibration "$SAMPLES/accel-thermal.csv"
has "1 Hz: why, and the rate it needs" "$T/err" 'a rate of 1 Hz shows nothing of the velocity band \(10 to 1000 Hz\).*needs a rate above 20 Hz'
lacks "1 Hz: no nan printed" "$T/out" 'nan'

done_testing
