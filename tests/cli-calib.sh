#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope calib on the bundled calibration samples (their true
# parameters are in samples/README.md and tests/gen-samples.c), the
# calibration file and --calibration, and failures with clear messages.
# Tolerances: 4 reported standard deviations.
. "$(dirname "$0")/lib.sh"

MP="$SAMPLES/imu-multipose.csv"
SIX="$SAMPLES/accel-6pos.csv"
RT="$SAMPLES/gyro-ratetable.csv"

run "calib --help" 0 calib --help
has "help names the method" "$T/out" 'Tedaldi'
run "calib without accel|gyro" 2 calib "$MP"
one_line_error "calib without accel|gyro"
run "calib accel without file" 2 calib accel
run "bad --mode" 2 calib accel --mode spin "$MP"
one_line_error "bad --mode"
run "tilt mode is gyro only" 2 calib accel --mode tilt "$MP"
run "rate-table needs --reference" 2 calib gyro --mode rate-table "$RT"
run "six poses need the six-position mode" 1 calib accel "$SIX"
has "six poses: the mode named" "$T/err" '6 static poses: the 9-parameter accelerometer model needs at least 10; six poses of \+-g on each axis are the six-position test: --mode sixpos$'

# accelerometer, multi-position (truth: b = 21/-15/34 mg, K = 1/1.011,
# 1/0.993, 1/1.006 g per g, alpha_yz 0.004, alpha_zy -0.003, alpha_zx 0.005)
run "calib accel multipos" 0 calib accel --format json "$MP"
cp "$T/out" "$T/acc.json"

# raw units: any affine change of the raw columns (here x' = 1e3 x + 1e4 on
# counts) gives the same calibration: bias' = 1e3 b + 1e4, scale' =
# scale / 1e3, misalignment and residual equal, within 1e-9 relative
awk -F, 'NR==1{print;next} NR==2{print "time [s],gx [counts],gy [counts],gz [counts],ax [counts],ay [counts],az [counts]";next} {print}' "$MP" >"$T/raw.csv"
awk -F, 'NR<=2{print;next} {printf "%s",$1; for(i=2;i<=7;i++) printf ",%.17g",1e3*$i+1e4; print ""}' "$T/raw.csv" >"$T/raw2.csv"
for triad in accel gyro; do
	run "calib $triad on counts" 0 calib $triad --accel ax,ay,az --gyro gx,gy,gz --format json "$T/raw.csv"
	cp "$T/out" "$T/r1.json"
	run "calib $triad on 1e3 counts + 1e4" 0 calib $triad --accel ax,ay,az --gyro gx,gy,gz --format json "$T/raw2.csv"
	cp "$T/out" "$T/r2.json"
	if ! command -v jq >/dev/null 2>&1; then
		skip "calib $triad: affine change of the raw units" "jq not installed"
	elif jq -e -n --slurpfile a "$T/r1.json" --slurpfile b "$T/r2.json" '
		[range($a[0].triads | length) as $k | $a[0].triads[$k] as $p | $b[0].triads[$k] as $q |
		 (range(3) as $i | ((($q.bias[$i] - 1e4) / 1e3 - $p.bias[$i]) / $p.bias[$i] | fabs),
		  ($q.scale[$i] * 1e3 / $p.scale[$i] - 1 | fabs),
		  (range(3) as $j | ($q.misalignment[$i][$j] - $p.misalignment[$i][$j]) | fabs)),
		 ($q.residual_rms / $p.residual_rms - 1 | fabs)] | max < 1e-9 and
		$a[0].detection.intervals == $b[0].detection.intervals' >/dev/null; then
		ok "calib $triad: affine change of the raw units gives the same calibration (1e-9)"
	else
		not_ok "calib $triad: affine change of the raw units gives the same calibration (1e-9)"
	fi
done
json_check "20 static intervals found" "$T/acc.json" '.detection.intervals == 20 and .triads[0].poses == 20'
json_check "threshold rule reported" "$T/acc.json" '(.detection.rule | test("percentile")) and .detection.k >= 2 and .detection.threshold > 0'
json_check "accel bias within 4 sd" "$T/acc.json" \
	'.triads[0] as $t | [0.021,-0.015,0.034] as $b | all(range(3); (($t.bias[.] - $b[.]) | fabs) <= 4 * $t.bias_sd[.])'
json_check "accel scale within 4 sd" "$T/acc.json" \
	'.triads[0] as $t | [9.80665/1.011, 9.80665/0.993, 9.80665/1.006] as $k | all(range(3); (($t.scale[.] - $k[.]) | fabs) <= 4 * $t.scale_sd[.])'
json_check "accel misalignment within 4 sd" "$T/acc.json" \
	'.triads[0] as $t | ((($t.misalignment[0][1] + 0.004) | fabs) <= 4 * $t.misalignment_sd[0][1]) and ((($t.misalignment[1][2] + 0.005) | fabs) <= 4 * $t.misalignment_sd[1][2])'
json_check "units of the contract" "$T/acc.json" '.triads[0].bias_unit == "g" and .triads[0].output_unit == "m/s^2" and (.triads[0].misalignment | length) == 3'
json_check "grade reported as typical" "$T/acc.json" '(.triads[0].grade.class | test("accelerometer")) and (.triads[0].grade.basis | test("typical"))'

# gyro, multi-position with g-sensitivity (truth: b = 0.31/-0.17/0.52 deg/s,
# K = 1/1.021 ... (deg/s -> deg/s), T01 = 0.008, G = 0.05 deg/s/g diagonal)
run "calib gyro multipos" 0 calib gyro --g-sensitivity --format json \
	--save-calibration "$T/cal.json" "$MP"
cp "$T/out" "$T/gyr.json"
json_check "gyro triad present" "$T/gyr.json" '(.triads | length) == 2 and .triads[1].kind == "gyro"'
json_check "gyro bias within 4 sd" "$T/gyr.json" \
	'.triads[1] as $t | [0.31,-0.17,0.52] as $b | all(range(3); (($t.bias[.] - $b[.]) | fabs) <= 4 * $t.bias_sd[.])'
json_check "gyro scale within 4 sd" "$T/gyr.json" \
	'.triads[1] as $t | (3.141592653589793/180) as $d | [$d/1.021, $d/0.976, $d/1.008] as $k | all(range(3); (($t.scale[.] - $k[.]) | fabs) <= 4 * $t.scale_sd[.])'
json_check "gyro misalignment within 4 sd" "$T/gyr.json" \
	'.triads[1] as $t | ((($t.misalignment[0][1] - 0.008) | fabs) <= 4 * $t.misalignment_sd[0][1]) and ((($t.misalignment[1][2] - 0.011) | fabs) <= 4 * $t.misalignment_sd[1][2])'
json_check "g-sensitivity within 4 sd" "$T/gyr.json" \
	'.triads[1] as $t | all(range(3); (($t.g_sensitivity[.][.] * 9.80665 - 0.05) | fabs) <= 4 * $t.g_sensitivity_sd[.][.] * 9.80665)'
json_check "seed-terms error model" "$T/gyr.json" '.triads[1].error_model.scale_factor_ppm[0] > 20000 and .triads[1].error_model.scale_factor_ppm[0] < 22000'
json_check "calibration file written" "$T/cal.json" '.format == "sensorscope-calibration" and (.triads | length) == 2'

# applying it
run "info --calibration" 0 info --format json --calibration "$T/cal.json" "$MP"
json_check "calibrated units" "$T/out" '[.channels[] | .unit] == ["rad/s","rad/s","rad/s","m/s^2","m/s^2","m/s^2"]'
run "calib accel on calibrated data" 0 calib accel --format json --calibration "$T/cal.json" "$MP"
json_check "recalibration is the identity" "$T/out" \
	'.triads[0] as $t | all(range(3); (($t.bias[.]) | fabs) <= 4 * $t.bias_sd[.] and (($t.scale[.] - 1) | fabs) <= 4 * $t.scale_sd[.])'
run "--calibration with -c" 0 info --format json --calibration "$T/cal.json" -c gz,5 "$MP"
json_check "-c order kept" "$T/out" '[.channels[] | .name] == ["gz","ax"]'
run "--calibration missing file" 1 info --calibration "$T/none.json" "$MP"
one_line_error "--calibration missing file"
printf '{"format":"sensorscope-calibration","version":1,"triads":[{"kind":"accel"}]}\n' >"$T/bad.json"
run "--calibration malformed" 1 info --calibration "$T/bad.json" "$MP"
one_line_error "--calibration malformed"
run "--calibration on other channels" 1 info --calibration "$T/cal.json" "$SAMPLES/euroc-imu.csv"
one_line_error "--calibration on other channels"

# six-position (truth: b = 12.3/-8.7/15.2 mg, scale errors 0.8/-0.5/1.2 %)
run "calib accel sixpos" 0 calib accel --mode sixpos --format json "$SIX"
json_check "sixpos: 6 poses, 12 parameters" "$T/out" '.triads[0].poses == 6 and .triads[0].parameters == 12'
json_check "sixpos bias" "$T/out" '.triads[0] as $t | [0.0123,-0.0087,0.0152] as $b | all(range(3); (($t.bias[.] - $b[.]) | fabs) < 3e-4)'
json_check "sixpos scale-factor errors" "$T/out" '.triads[0].error_model.scale_factor_ppm as $s | [8000,-5000,12000] as $w | all(range(3); (($s[.] - $w[.]) | fabs) < 300)'
run "multipos with six poses" 1 calib accel "$SIX"
one_line_error "multipos with six poses"
has "names the pose count" "$T/err" 'at least 10'
run "one static pose" 1 calib accel "$SAMPLES/accel-thermal.csv"
one_line_error "one static pose"
run "gyro without accelerometer" 1 calib gyro "$SAMPLES/gyro-static.csv"
one_line_error "gyro without accelerometer"

# rate table (truth: 1.0085, cubic -4e-7 (deg/s)^-2 = -1.3131e-3 (rad/s)^-2,
# cross-axis 0.0042 / -0.0031, bias 0.21 deg/s)
run "calib gyro rate-table" 0 calib gyro --mode rate-table --reference rate_cmd --cubic --format json "$RT"
json_check "rate table: axis x found" "$T/out" '.rate_table.axes[0].excited and (.rate_table.axes[1].excited | not)'
json_check "rate table: full scale null on an axis not excited" "$T/out" '.rate_table.axes[0].full_scale_si > 5 and .rate_table.axes[1].full_scale_si == null'
json_check "scale factor within 4 sd" "$T/out" '.rate_table.axes[0] | ((.scale_factor - 1.0085) | fabs) <= 4 * .scale_factor_sd'
json_check "cubic within 4 sd" "$T/out" '.rate_table.axes[0] | ((.c3 + 4e-7 * (180/3.141592653589793) * (180/3.141592653589793)) | fabs) <= 4 * .c3_sd'
json_check "cross-axis within 4 sd" "$T/out" '.rate_table.axes[1] | ((.sensitivity_row[0] - 0.0042) | fabs) <= 4 * .sensitivity_row_sd[0]'
json_check "non-linearity in % FS" "$T/out" '.rate_table.axes[0].nonlinearity_percent_fs > 1 and .rate_table.axes[0].nonlinearity_percent_fs < 1.3'
run "calib gyro rate-table, text" 0 calib gyro --mode rate-table --reference rate_cmd --cubic "$RT"
has "rate table text: full scale in the input's unit" "$T/out" 'NL \(% FS\) +FS \(deg/s\)$'
has "rate table text: gx's full scale 300 deg/s" "$T/out" '^ +gx +yes .* 300$'
has "rate table text: an axis not excited has no full scale" "$T/out" '^ +gy +no +- +[-0-9.]+ +- +-$'
run "rate table, no full triad to save" 1 calib gyro --mode rate-table --reference rate_cmd --save-calibration "$T/rt.json" "$RT"
one_line_error "rate table, no full triad to save"
run "rate table, unknown reference" 1 calib gyro --mode rate-table --reference nope "$RT"

# the same run described by a schedule instead of the reference column
i=0
for w in -300 -250 -200 -150 -100 -50 0 50 100 150 200 250 300; do
	echo "$((5 * i)) $((5 * i + 5)) ${w}deg/s"
	i=$((i + 1))
done >"$T/sched.txt"
run "rate table from a schedule" 0 calib gyro --mode rate-table --schedule "$T/sched.txt" --gyro gx,gy,gz --cubic --format json "$RT"
json_check "schedule: 13 steps, same scale factor" "$T/out" '.rate_table.points == 13 and (.rate_table.axes[0] | ((.scale_factor - 1.0085) | fabs) <= 4 * .scale_factor_sd)'
printf '0 5\n' >"$T/badsched.txt"
run "malformed schedule" 1 calib gyro --mode rate-table --schedule "$T/badsched.txt" --gyro gx,gy,gz "$RT"
one_line_error "malformed schedule"
run "schedule and reference together" 2 calib gyro --mode rate-table --schedule "$T/sched.txt" --reference rate_cmd "$RT"

# tilt: g-dependent bias from the static poses
run "calib gyro tilt" 0 calib gyro --mode tilt --format json "$MP"
json_check "tilt: G diagonal near 0.05 deg/s/g" "$T/out" \
	'.triads[0] as $t | all(range(3); (($t.g_sensitivity[.][.] * 9.80665 - 0.05) | fabs) <= 4 * $t.g_sensitivity_sd[.][.] * 9.80665)'

run "text output" 0 calib gyro "$MP"
has "text names the error model" "$T/out" 'error model \(textbook eqs 93-94\)'
has "error model in words" "$T/out" 'per axis: bias [-0-9.]+ m?g, scale-factor error [-0-9.]+ ppm; bias'
has "detector threshold with its unit" "$T/out" 'threshold [0-9.e-]+ \(m/s\^2\)\^2, '
lacks "no symbols for the error model" "$T/out" 's_f=|b='

run "csv output" 0 calib accel --format csv "$MP"
has "csv header" "$T/out" '^kind,channel,input_unit'

if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "calib --plot" 0 calib gyro --plot "$T/c.png" "$MP"
	if [ -s "$T/c.png" ]; then ok "plot written"; else not_ok "plot written"; fi
	run "rate-table --plot" 0 calib gyro --mode rate-table --reference rate_cmd --plot "$T/r.png" "$RT"
else
	run "calib --plot without OpenCV" 2 calib gyro --plot "$T/c.png" "$MP"
fi

# the calibrated gyro carries gravity over each motion far better than the
# bias-corrected raw gyro (the sample's scale errors are 1-2 %)
run "gyro motion errors" 0 calib gyro --format json "$MP"
json_check "gyro motion errors: calibrated well under the raw" "$T/out" \
	'.triads[1].motion_error_deg | .motions == 19 and .rms < 0.1 and .max < 0.2 and .rms_bias_only > 20 * .rms'
done_testing
