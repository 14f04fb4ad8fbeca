#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope datasheet: the conversions of the shipped datasheets against
# values worked by hand, verdicts on simulated captures at 0.8x, 1.0x and
# 1.25x a datasheet's noise density, and bad input (one line, exit 1 for a
# file, 2 for usage).
. "$(dirname "$0")/lib.sh"
DS="$SAMPLES/datasheets"

run "datasheet --help" 0 datasheet --help
has "help names --check" "$T/out" '--check CAPTURE'
run "no operand" 2 datasheet
one_line_error "no operand"
run "two operands" 2 datasheet "$DS/bmi088.ini" "$DS/stim300.ini"
run "bad --ci" 2 datasheet --ci 1.5 "$DS/bmi088.ini"
run "csv refused" 2 datasheet --format csv "$DS/bmi088.ini"

# every shipped datasheet converts
for f in "$DS"/*.ini; do
	run "convert $(basename "$f")" 0 datasheet "$f"
done

# STIM300 by hand: N = 0.15 deg/sqrt(h) = 0.15 / 60 = 0.0025 deg/s/sqrt(Hz)
# = 0.15 * pi/180 / 60 = 4.3633e-5 rad/sqrt(s); B = Allan minimum / 0.6642825
# = 0.5 / 0.6642825 = 0.7526918 deg/h; the 300 ppm accelerometer scale factor
# is 3e-4
run "stim300 json" 0 datasheet --format json "$DS/stim300.ini"
json_check "N in SI" "$T/out" '((.sections[0].terms.N.si) - 0.15 * 3.141592653589793 / 180 / 60 | fabs) < 1e-15'
json_check "N as a density" "$T/out" '((.sections[0].as_lines[] | select(.key == "noise_density") | .value) - 0.0025 | fabs) < 1e-12'
json_check "B = min / 0.6643" "$T/out" '((.sections[0].as_lines[] | select(.key == "bias_instability") | .value) - 0.7526918 | fabs) < 1e-6'
json_check "terms say where they come from" "$T/out" '.sections[0].terms.N.from == "random_walk" and .sections[0].terms.B.from == "in_run_bias_stability" and .sections[0].terms.K == null'
json_check "ppm to a ratio" "$T/out" '(.sections[1].lines[] | select(.key == "scale_factor_error") | .si) == 0.0003'
json_check "GJB from terms is a lower bound" "$T/out" '(.sections[0].as_lines[] | select(.key == "bias_stability_10s") | .lower_bound) == true'
# MPU-6000: 0.05 deg/s rms over 100 Hz -> 0.05 / sqrt(100) = 0.005 deg/s/sqrt(Hz)
run "mpu-6000 json" 0 datasheet --format json "$DS/mpu-6000.ini"
json_check "rms over a bandwidth to a density" "$T/out" '((.sections[0].lines[] | select(.key == "rms_noise") | .term_si) - 0.005 * 3.141592653589793 / 180 | fabs) < 1e-15'
# ADIS16448 accelerometer: 0.23 mg/sqrt(Hz) = 0.23e-3 * 9.80665 = 2.2555e-3 m/s^2/sqrt(Hz)
run "adis16448 json" 0 datasheet --format json -o "$T/a.json" "$DS/adis16448.ini"
json_check "mg/sqrt(Hz) to SI" "$T/a.json" '((.sections[1].lines[] | select(.key == "noise_density") | .si) - 2.2555295e-3 | fabs) < 1e-12'

# verdicts: BMI088 gyro 0.014 deg/s/sqrt(Hz); 10 min at 100 Hz resolves N
# to about 0.3 % (1 sigma), the 99 % guard band to about 1 %
for k in 0.8:within 1.0:inconclusive 1.25:out; do
	f=${k%%:*} expect=${k#*:}
	nd=$(awk "BEGIN { printf \"%.6g\", $f * 0.014 }")
	printf '[sensor]\nnoise_density = %s deg/s/sqrt(Hz)\n' "$nd" >"$T/s.ini"
	run "simulate ${f}x" 0 simulate --sensor "$T/s.ini" --rate 100 --duration 600 --seed 7 -o "$T/c.csv"
	run "check ${f}x" 0 datasheet --check "$T/c.csv" --format json "$DS/bmi088.ini"
	json_check "${f}x: $expect" "$T/out" ".channels[0].section == \"gyro\" and (.channels[0].checks[0].verdict | startswith(\"$expect\"))"
done
json_check "interval in the written unit" "$T/out" '.channels[0].checks[0].unit == "deg/s/sqrt(Hz)" and .channels[0].checks[0].lo < .channels[0].checks[0].value and .channels[0].checks[0].value < .channels[0].checks[0].hi'
run "check text" 0 datasheet --check "$T/c.csv" "$DS/bmi088.ini"
has "text verdict" "$T/out" 'noise density.*out of spec'
# --spec SPEC CAPTURE (the scene stage's form) is the same command
cp "$T/out" "$T/check.txt"
run "--spec form" 0 datasheet --spec "$DS/bmi088.ini" "$T/c.csv"
if cmp -s "$T/out" "$T/check.txt"; then ok "--spec form: the same text as --check"; else not_ok "--spec form: the same text as --check"; fi
run "--spec without a capture" 2 datasheet --spec "$DS/bmi088.ini"
one_line_error "--spec without a capture"
run "--spec and --check" 2 datasheet --spec "$DS/bmi088.ini" --check "$T/c.csv" "$T/c.csv"
one_line_error "--spec and --check"
run "--spec: a missing datasheet" 1 datasheet --spec "$T/nope.ini" "$T/c.csv"
one_line_error "--spec: a missing datasheet"
# a line the capture cannot establish: inconclusive with its reason, no 0
run "check stim300" 0 datasheet --check "$T/c.csv" --format json "$DS/stim300.ini"
json_check "scale factor not measured" "$T/out" '(.channels[0].checks[] | select(.key == "scale_factor_error") | .verdict == "inconclusive" and .value == null and (.why | length) > 0)'
json_check "no zero anywhere" "$T/out" '[.channels[].checks[] | .value, .lo, .hi] | all(. != 0)'
# accelerometer channel against [accel]
printf '[sensor]\nnoise_density = 120 ug/sqrt(Hz)\n' >"$T/a.ini"
run "simulate accel" 0 simulate --sensor "$T/a.ini" --rate 100 --duration 120 --seed 3 -o "$T/acc.csv"
run "check accel" 0 datasheet --check "$T/acc.csv" --format json "$DS/bmi088.ini"
json_check "accel section used" "$T/out" '.channels[0].section == "accel" and .channels[0].checks[0].verdict == "within spec"'
# GJB 10 s against a datasheet line: 600 s of white noise at 0.014 * 1.25
printf '[gyro]\nbias_stability_10s = 1 deg/h\n' >"$T/gjb.ini"
run "gjb line" 0 datasheet --check "$T/c.csv" --format json "$T/gjb.ini"
json_check "GJB measured: 60 means, N/sqrt(10) = 0.0175 / 3.162 deg/s = 19.9 deg/h" "$T/out" '(.channels[0].checks[0].value - 19.92 | fabs) < 3 and .channels[0].checks[0].verdict == "out of spec"'

# the bias lines, limits on a magnitude: the offset is the record's mean
# (as info's), the ramp the block means' slope; the temperature
# sensitivity needs the temperatures (not measured here, with the reason)
printf '[gyro]\nbias_offset = 0.01 deg/s\nrate_ramp = 1 deg/h/h\nbias_tempco = 0.01 deg/s/degC\n' >"$T/bias.ini"
run "bias lines" 0 datasheet --check "$T/c.csv" --format json "$T/bias.ini"
cp "$T/out" "$T/bias.json"
run "info of the capture" 0 info --format json "$T/c.csv"
json_check "offset = the record's mean" "$T/bias.json" \
	"(.channels[0].checks[0] | .key == \"bias_offset\" and .value < .hi and .lo < .value) and ((.channels[0].checks[0].value - $(jq '.channels[0].mean' "$T/out" 2>/dev/null || echo 0)) | fabs) < 1e-6"
json_check "tempco: not measured, with the reason, no 0" "$T/bias.json" \
	'.channels[0].checks[2] | .value == null and .verdict == "inconclusive" and (.why | test("temperature"))'
json_check "ramp: measured, a verdict" "$T/bias.json" '.channels[0].checks[1] | .value != null and .lo < .hi'

# bad input: one line each, exit 1 for a file that cannot be used
run "missing file" 1 datasheet "$T/none.ini"
one_line_error "missing file"
printf '[gyro]\nnoise_density = 0.01 furlongs\n' >"$T/bad.ini"
run "unknown unit" 1 datasheet "$T/bad.ini"
one_line_error "unknown unit"
has "unknown unit named" "$T/err" "line 2: noise_density = 0.01 furlongs: unknown unit 'furlongs'"
printf '[gyro]\nnoise_density 0.01 deg/s/sqrt(Hz)\n' >"$T/bad.ini"
run "malformed line" 1 datasheet "$T/bad.ini"
one_line_error "malformed line"
has "malformed line named" "$T/err" 'line 2'
printf '[gyro]\nnoise_density = 0.01\n' >"$T/bad.ini"
run "no unit" 1 datasheet "$T/bad.ini"
one_line_error "no unit"
printf '[gyro]\nnoise_density = 0.01 deg/h\n' >"$T/bad.ini"
run "wrong dimension" 1 datasheet "$T/bad.ini"
has "wrong dimension named" "$T/err" 'is not a unit of noise_density'
printf '[gyro]\nnoise_densty = 0.01 deg/s/sqrt(Hz)\n' >"$T/bad.ini"
run "unknown key" 1 datasheet "$T/bad.ini"
one_line_error "unknown key"
printf '[gyro]\nrms_noise = 0.05 deg/s\n' >"$T/bad.ini"
run "rms without bandwidth" 1 datasheet "$T/bad.ini"
one_line_error "rms without bandwidth"
printf '[magnetometer]\nnoise = 1 nT\n' >"$T/bad.ini"
run "unknown section" 1 datasheet "$T/bad.ini"
one_line_error "unknown section"
printf '[gyro]\nnoise_density = -0.01 deg/s/sqrt(Hz)\n' >"$T/bad.ini"
run "negative value" 1 datasheet "$T/bad.ini"
one_line_error "negative value"
printf '[gyro]\nnoise_density = 1e400 deg/s/sqrt(Hz)\n' >"$T/bad.ini"
run "overflowing value" 1 datasheet "$T/bad.ini"
has "overflow named" "$T/err" 'not a finite number'
printf '[gyro]\nnoise_density = 0.01 deg/s/sqrt(Hz)\nnoise_density = 0.02 deg/s/sqrt(Hz)\n' >"$T/bad.ini"
run "line given twice" 1 datasheet "$T/bad.ini"
one_line_error "line given twice"
: >"$T/empty.ini"
run "empty datasheet" 1 datasheet "$T/empty.ini"
one_line_error "empty datasheet"
run "missing capture" 1 datasheet --check "$T/none.csv" "$DS/bmi088.ini"
one_line_error "missing capture"
printf 't,x\n0,1\n0.01,2\n0.02,3\n' >"$T/nounit.csv"
run "capture without units" 1 datasheet --check "$T/nounit.csv" "$DS/bmi088.ini"
one_line_error "capture without units"
# two lines of one term that disagree: which one the terms use is said;
# a line the terms cannot give in doubles is left out, not inf
printf '[gyro]\nbias_instability = 5 deg/h\nin_run_bias_stability = 2 deg/h\n' >"$T/two.ini"
run "datasheet, B given twice" 0 datasheet "$T/two.ini"
has "the disagreement said" "$T/out" "note: bias_instability and in_run_bias_stability give B = .*: the terms below use bias_instability"
printf '[gyro]\nnoise_density = 1e300 deg/s/sqrt(Hz)\n' >"$T/huge.ini"
run "datasheet near the double's end" 0 datasheet "$T/huge.ini"
lacks "no inf" "$T/out" "inf"
# a running motor: its noise fit is rejected, so no verdict on it
run "check on a vibration record" 0 datasheet --check "$SAMPLES/vibration.csv" "$SAMPLES/datasheets/bmi088.ini"
has "vibration: the measured bound has its unit" "$T/out" 'measured below [0-9.]+ ug/sqrt\(Hz\) \(bound\)'
has "vibration: inconclusive, with why" "$T/out" 'indicative only, so inconclusive'
lacks "vibration: never within spec" "$T/out" 'within spec'
run "check on vibration, json" 0 datasheet --format json --check "$SAMPLES/vibration.csv" "$SAMPLES/datasheets/bmi088.ini"
json_check "vibration: every rejected fit's line inconclusive" "$T/out" '[.. | objects | select(has("fit_rejected") and .fit_rejected) | .verdict] | length > 0 and all(. == "inconclusive")'
run "check, a line a static record cannot show" 0 datasheet --check "$SAMPLES/gyro-static.csv" "$SAMPLES/datasheets/stim300.ini"
has "nothing measured: '-', inconclusive as in JSON, why below" "$T/out" 'scale-factor error .* measured - +inconclusive$'

done_testing
