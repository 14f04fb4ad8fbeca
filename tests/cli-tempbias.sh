#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope tempbias: the thermal sample's known coefficients (within 4
# reported sd), the contract's JSON shape, several power cycles from the
# simulator, CSV, the plot, and every usage and data error (exit 2 usage,
# exit 1 data).
. "$(dirname "$0")/lib.sh"

TH="$SAMPLES/accel-thermal.csv"
run "tempbias --help" 0 tempbias --help
has "help names the repeatability definition" "$T/out" 'Turn-on repeatability: 1 sigma'

# samples/accel-thermal.csv: c1 0.08/-0.05/0.12 mg/degC, c2 1.5/2/-1 ug/degC^2,
# c3 0.02/-0.01/0.03 ug/degC^3 about 20 degC, offsets 2.1/-1.4/3.3 mg (+1 g on z)
run "thermal sample" 0 tempbias --format json --ref-temp 20 "$TH"
json_check "contract shape" "$T/out" \
  '.command == "tempbias" and (.channels | length) == 3 and all(.channels[]; (.fit | has("ref_temp_degc") and has("coefficients") and has("coefficient_sd") and has("residual_rms")) and (.hysteresis | has("max") and has("at_degc")) and has("gradient_sensitivity") and (.table | length) > 5 and (.table[0] | has("temp_degc") and has("bias")))'
json_check "order 3 chosen, T_ref 20" "$T/out" 'all(.channels[]; .fit.order == 3 and .fit.ref_temp_degc == 20 and .unit == "mg")'
json_check "coefficients within 4 sd of the truth" "$T/out" '
  [[2.1, 0.08, 0.0015, 0.00002], [-1.4, -0.05, 0.002, -0.00001], [1003.3, 0.12, -0.001, 0.00003]] as $truth
  | . as $r | all(range(0;3) as $c | range(0;4) as $k | [$c, $k];
        . as [$c, $k] | $r.channels[$c].fit as $f
        | (($f.coefficients[$k] - $truth[$c][$k]) | fabs) <= 4 * $f.coefficient_sd[$k])'
json_check "coefficient sd method named (random walk, REML)" "$T/out" 'all(.channels[]; .fit.coefficient_sd_method | test("random walk.*REML"))'
json_check "stability from the Allan module" "$T/out" 'all(.channels[]; .stability.adev_min > 0 and .stability.tau_s > 0)'
run "text" 0 tempbias -c az "$TH"
has "text: fit line" "$T/out" 'fit: order 3'
has "text: table" "$T/out" 'compensation table'
run "csv" 0 tempbias -c ax --format csv "$TH"
has "csv header" "$T/out" '^channel,unit,temp_degc,bias$'
run "fixed order 1" 0 tempbias -c ax --order 1 --format json "$TH"
json_check "order 1: two coefficients" "$T/out" '.channels[0].fit.order == 1 and (.channels[0].fit.coefficients | length) == 2'
# order 0 (no temperature term): the sensitivity is unknown, never 0
run "fixed order 0" 0 tempbias -c ax --order 0 --format json "$TH"
json_check "order 0: sensitivity and peak-to-peak null" "$T/out" '.channels[0].fit.order == 0 and .channels[0].sensitivity == null and .channels[0].sensitivity_sd == null'
run "fixed order 0, text" 0 tempbias -c ax --order 0 "$TH"
has "order 0: not estimated, said" "$T/out" 'sensitivity and peak-to-peak: not estimated \(order 0 requested'
lacks "order 0: no sensitivity 0" "$T/out" 'sensitivity at T_ref 0 '
# a moving record's gyro: the F test keeps no temperature term
run "order 0 chosen, text" 0 tempbias -c gz "$SAMPLES/drive-stops.csv"
has "order 0 chosen by the F test" "$T/out" 'fit: order 0 \(auto'
has "order 0 chosen: not resolved, said" "$T/out" 'sensitivity and peak-to-peak: not resolved \(no temperature term passes the F test'

# several power cycles: 3 files from the simulator with different seeds
cat >"$T/acc.ini" <<'INI'
[sensor]
noise_density = 100 ug/sqrt(Hz)
bias = 2 mg
bias_tempco = 0.1 mg/degC
INI
for s in 1 2 3; do
	ss simulate --sensor "$T/acc.ini" --rate 1 --duration 2h --seed $s --temp-cycle 0:40:3600 \
	   --temp-noise 0.01 --hysteresis 0.5mg --units mg -o "$T/p$s.csv" 2>"$T/err" ||
		{ not_ok "simulate $s"; diag "$T/err"; }
done
run "three power cycles" 0 tempbias --format json "$T/p1.csv" "$T/p2.csv" "$T/p3.csv"
json_check "repeatability over 3 runs" "$T/out" '.channels[0].turn_on_repeatability.runs == 3 and .channels[0].turn_on_repeatability.sd >= 0 and (.channels[0].runs | length) == 3'
json_check "slope 0.1 mg/degC within 4 sd" "$T/out" '((.channels[0].sensitivity - 0.1) | fabs) <= 4 * .channels[0].sensitivity_sd'
json_check "hysteresis 0.5 mg within 10 %" "$T/out" '((.channels[0].hysteresis.term - 0.5) | fabs) <= 0.05'

# hysteresis vs gradient: on ramps of equal |dT/dt| up and down dT/dt is
# +-r with the heating/cooling state, so the two terms are collinear: the
# fit names it and reports the combined heating - cooling gap (truth 3 deg/h
# of hysteresis, no gradient) within 4 of its sd; on a sine cycle the rate
# varies within heating and cooling and both terms are recovered (truth
# 3 deg/h and 0.5 deg/h per degC/min) within 4 sd
cat >"$T/gyro.ini" <<'INI'
[sensor]
noise_density = 0.15 deg/sqrt(h)
bias_tempco = 2 deg/h/degC
INI
ss simulate --sensor "$T/gyro.ini" --rate 1 --duration 8h --seed 7 --temp-cycle -10:50:7200:triangle \
   --temp-noise 0.01 --hysteresis 3 --units deg/h -o "$T/tri.csv" 2>"$T/err" || { not_ok "simulate triangle"; diag "$T/err"; }
run "symmetric ramps" 0 tempbias --format json --order 1 "$T/tri.csv"
json_check "symmetric ramps: collinearity named, combined gap 3 deg/h within 4 sd" "$T/out" \
  '.channels[0].hysteresis as $h | $h.collinear_with_gradient == true and $h.gradient_vif > 10 and ($h.separate_with | test("sine")) and ((($h.combined_gap.value - 3) | fabs) <= 4 * $h.combined_gap.sd) and .channels[0].gradient_sensitivity == null'
run "symmetric ramps, text" 0 tempbias --order 1 "$T/tri.csv"
has "text names the collinearity" "$T/out" 'collinear on this profile'
ss simulate --sensor "$T/gyro.ini" --rate 1 --duration 8h --seed 7 --temp-cycle -10:50:7200:sine \
   --temp-noise 0.01 --hysteresis 3 --gradient 30 --units deg/h -o "$T/sine.csv" 2>"$T/err" || { not_ok "simulate sine"; diag "$T/err"; }
run "sine cycle" 0 tempbias --format json --order 1 "$T/sine.csv"
json_check "sine cycle: hysteresis and gradient both within 4 sd" "$T/out" \
  '.channels[0] as $c | $c.hysteresis.collinear_with_gradient == false and ((($c.hysteresis.term - 3) | fabs) <= 4 * $c.hysteresis.term_sd) and ((($c.gradient_sensitivity - 30) | fabs) <= 4 * $c.gradient_sensitivity_sd)'

# errors
cat >"$T/notemp.csv" <<'CSV'
time [s],ax [g]
0,0.001
1,0.002
2,0.001
CSV
run "no temperature column" 1 tempbias "$T/notemp.csv"
one_line_error "no temperature column"
has "names the option" "$T/err" 'no temperature column \(give --temp-column'
ss simulate --sensor "$T/acc.ini" --rate 10 --duration 600 --temp 25 --temp-noise 0.05 -o "$T/const.csv" 2>/dev/null
run "one temperature" 1 tempbias "$T/const.csv"
one_line_error "one temperature"
has "refusal names the span" "$T/err" 'span'
awk 'BEGIN { print "# rate: 10 Hz"; print "ax [m/s^2],temp [degC]"; for (i = 0; i < 6000; i++) printf "%.4f,25\n", (i % 7) * 1e-4 }' >"$T/flat.csv"
run "a temperature column that never changes" 1 tempbias "$T/flat.csv"
has "refusal says it does not change (no rounding residue as a span)" "$T/err" 'the temperature does not change \(25 degC throughout\)'
run "order too high" 2 tempbias --order 7 "$TH"
one_line_error "order too high"
run "order not a number" 2 tempbias --order cubic "$TH"
run "channels differ" 1 tempbias "$TH" "$T/p1.csv"
one_line_error "channels differ"
run "missing file" 1 tempbias "$T/nope.csv"

if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "tempbias --plot" 0 tempbias -c az --plot "$T/t.png" "$TH"
	if [ -s "$T/t.png" ]; then ok "plot written"; else not_ok "plot written"; fi
else
	run "tempbias --plot without OpenCV" 2 tempbias --plot "$T/t.png" "$TH"
fi
# a constant channel: refused, not fitted to its rounding
awk 'BEGIN { print "# rate: 1"; print "ax [m/s^2],temp [degC]"; for (i = 0; i < 3600; i++) printf "2.94,%.3f\n", 20 + i / 360 }' >"$T/const.csv"
run "tempbias on a constant channel" 1 tempbias "$T/const.csv"
has "constant channel: said" "$T/err" 'every sample is 2.94 \(constant data\)'

done_testing
