#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The adequacy check through the command line: allan's text and JSON say
# what a record supports; the exporters refuse a record that moves (the
# rate-table sample) or a rejected fit with one line and exit 1, write it
# with --force and every doubtful value marked, write a term the record
# only bounds as its bound (marked, with a warning), never write 0, and
# imu_utils' avg-axis never averages a bound in; a warm-up transient is
# found and named with the seconds to cut; the DAVAR figure; report on the
# rate-table sample says why it gives no noise terms and infers the
# rate-table calibration.
. "$(dirname "$0")/lib.sh"

G="$SAMPLES/gyro-static.csv"
RT="$SAMPLES/gyro-ratetable.csv"

# ---------------------------------------------------------------- still
run "allan json on the static sample" 0 allan --format json "$G"
cp "$T/out" "$T/g.json"
json_check "adequacy object per channel" "$T/g.json" \
  '[.channels[].adequacy | has("verdict") and has("findings") and has("davar") and .still == true and .fit_rejected == false] | all and length == 3'
json_check "static sample: valid, K only bounded" "$T/g.json" \
  '[.channels[].adequacy | (.verdict == "valid" or .verdict == "bounds") and (.doubtful == []) and (.requested == ["N","B","K"])] | all'
json_check "findings: one line each, with a severity" "$T/g.json" \
  '[.channels[].adequacy.findings[] | (.message | test("\n") | not) and (.severity | IN("note","bound","doubt","invalid"))] | all'
json_check "DAVAR map: windows x taus in the channel unit" "$T/g.json" \
  '.channels[0].adequacy.davar | .unit == "deg/s" and .window_s == 450 and .step_s == 112.5 and (.t_s | length) == 29 and (.dev | length) == 29 and ([.dev[] | length] | unique) == [(.tau_s | length)] and .tau_s[0] == 0.1 and (.model | length) == (.tau_s | length)'
json_check "noise terms carry doubtful: false" "$T/g.json" \
  '[.channels[].noise[] | .doubtful == false] | all'
run "allan text on the static sample" 0 allan -c gx "$G"
has "text: adequacy line" "$T/out" '^  adequacy: valid.*still \(1 s variance spans [0-9.]+ times, at most 9\), fit accepted'
lacks "text: nothing marked doubtful" "$T/out" 'NOT VALID|doubtful \(see'

# a rejected fit whose bootstrap p is at its floor: a bound, said so
run "allan on the six-position sample" 0 allan -c ax "$SAMPLES/accel-6pos.csv"
has "rejected fit: p below the bootstrap floor, not equal to it" "$T/out" 'chi2 469 for 28 dof, bootstrap p < 0\.001\)'
has "the warning says p < 0.001" "$T/out" 'warning: ax: fit rejected: chi2 469 for 28 dof, bootstrap p < 0\.001, below 0\.01'
has "the adequacy finding says p < 0.001" "$T/out" 'chi-squared 469 for 28 dof, p < 0\.001, below 0\.01'
lacks "no 'p = 0.001'" "$T/out" 'p = 0\.001'
run "allan json on the six-position sample" 0 allan --format json -c ax,ay "$SAMPLES/accel-6pos.csv"
json_check "p_value_bound beside p_value, true only at the floor" "$T/out" \
  '([.channels[] | (.fit.p_value_bound == (.fit.p_value <= 0.000999001)) and (.adequacy.fit_p_value_bound == .fit.p_value_bound)] | all) and ([.channels[].fit.p_value_bound] | any)'

# ---------------------------------------------------------------- exports
run "kalibr on the static sample" 0 allan --kalibr "$T/k.yaml" "$G"
has "kalibr: continuous time stated" "$T/k.yaml" '^# continuous-time noise densities'
has "kalibr: K written as its bound, marked" "$T/k.yaml" '^gyroscope_random_walk: [1-9][0-9.]*e-0[67] .*UPPER BOUND'
has "kalibr: bound warned about" "$T/err" 'warning: --kalibr: gyro K is written as its upper bound [0-9.e-]+ rad/s\^2/sqrt\(Hz\) '
lacks "kalibr: N not marked" "$T/k.yaml" '^gyroscope_noise_density: .*(UPPER BOUND|DOUBTFUL)'
run "imu-utils on the static sample" 0 allan --imu-utils "$T/iu.yaml" "$G"
has "imu-utils: continuous time stated" "$T/iu.yaml" 'continuous time'
has "imu-utils: avg-axis of bounds says so" "$T/iu.yaml" '^# avg-axis gyr_w: no axis establishes it: the largest bound'
has "imu-utils: avg-axis gyr_w marked" "$T/iu.yaml" '^      gyr_w: [1-9][0-9.]*e-0[67] .*UPPER BOUND'
for f in "$T/k.yaml" "$T/iu.yaml"; do
	lacks "no value written as 0 ($(basename "$f"))" "$f" ': -?0(\.0*)?(e[-+]?0+)? *(#|$)'
done

run "kalibr on a moving record" 1 allan --kalibr "$T/rt.yaml" -c gx,gy,gz "$RT"
one_line_error "kalibr on a moving record"
has "kalibr refusal names the cause" "$T/err" '^sensorscope: allan: --kalibr: not written: gx: the record moves .*--force'
if [ -e "$T/rt.yaml" ]; then not_ok "refused: no file"; else ok "refused: no file"; fi
run "openvins on a moving record" 1 allan --openvins "$T/ov.yaml" "$RT"
run "imu-utils on a moving record" 1 allan --imu-utils "$T/iu2.yaml" -c gx,gy,gz "$RT"
one_line_error "imu-utils on a moving record"
run "kalibr --force on a moving record" 0 allan --kalibr "$T/rt.yaml" --force -c gx,gy,gz "$RT"
has "forced: the file says so" "$T/rt.yaml" '^# written with --force'
has "forced: N marked doubtful" "$T/rt.yaml" '^gyroscope_noise_density: .*DOUBTFUL, written by --force: g[xyz]: the record moves'
has "forced: K marked doubtful" "$T/rt.yaml" '^gyroscope_random_walk: .*DOUBTFUL'
has "forced: warned" "$T/err" 'warning: --kalibr: gyro [NK] written although doubtful'
lacks "forced: no value written as 0" "$T/rt.yaml" ': -?0(\.0*)?(e[-+]?0+)? *(#|$)'
run "force without an export" 2 allan --force "$G"
one_line_error "force without an export"

run "allan json on a moving record" 0 allan --format json -c gx "$RT"
json_check "moving: not valid, the cause first" "$T/out" \
  '.channels[0].adequacy | .verdict == "not_valid" and .still == false and .findings[0].cause == "moves" and .findings[0].severity == "invalid" and .findings[0].t_start_s >= 0'
json_check "moving: every term doubtful, with the reason" "$T/out" \
  '[.channels[0].noise[] | .doubtful == true and (.doubt | test("moves"))] | all'
json_check "moving: a warning for the report" "$T/out" \
  '[.channels[0].warnings[] | select(.code == "adequacy_moves")] | length == 1'
run "allan text on a moving record" 0 allan -c gx "$RT"
has "text: terms marked not valid" "$T/out" 'K  rate random walk .*<- NOT VALID \(see adequacy\)'
has "text: read-offs marked" "$T/out" 'classic read-offs \(NOT VALID: see adequacy\)'
has "text: the finding" "$T/out" '^  adequacy \(invalid\): the record moves'

# ---------------------------------------------------------------- warm-up
cat >"$T/g.ini" <<EOF
[sensor]
name = test gyro
range = 250 deg/s
noise_density = 0.15 deg/sqrt(h)
bias_instability = 1 deg/h
rate_random_walk = 3 deg/h/sqrt(h)
EOF
run "simulate a 2 h gyro" 0 simulate --sensor "$T/g.ini" --rate 10 --duration 7200 --seed 7 -o "$T/sim.csv"
# 200 deg/h decaying with 600 s
awk -F, 'NR == 1 { print; next } { printf "%s,%.10g\n", $1, $2 + 200 / 3600 * exp(-$1 / 600) }' \
	"$T/sim.csv" >"$T/warm.csv"
run "allan json on a warm-up" 0 allan --format json "$T/warm.csv"
json_check "warm-up found, with the seconds to cut" "$T/out" \
  '[.channels[0].adequacy.findings[] | select(.cause == "warm_up")] | length == 1 and .[0].severity == "doubt" and .[0].t_start_s == 0 and .[0].action_s > 1800 and .[0].action_s < 7200 and (.[0].message | test("cut the first"))'
json_check "warm-up: no step in its tail" "$T/out" \
  '[.channels[0].adequacy.findings[] | select(.cause == "step")] | length == 0'
json_check "warm-up: not stationary" "$T/out" '.channels[0].adequacy.stationary == false'
run "kalibr on a warm-up" 1 allan --kalibr "$T/w.yaml" "$T/warm.csv"
one_line_error "kalibr on a warm-up"
run "the stationary part" 0 allan --format json "$T/sim.csv"
json_check "the same noise without the warm-up: stationary" "$T/out" \
  '.channels[0].adequacy.stationary == true'

# ---------------------------------------------------------------- DAVAR
run "davar svg" 0 allan --davar "$T/davar.svg" -q "$G"
has "davar svg: a figure" "$T/davar.svg" '<svg'
has "davar svg: its colour bar label" "$T/davar.svg" 'window deviation / fitted model'
run "davar with a bad name" 2 allan --davar "$T/davar.txt" "$G"
one_line_error "davar with a bad name"
if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "davar png" 0 allan --davar "$T/davar.png" -q "$G"
	if [ -s "$T/davar.png" ]; then ok "davar png written"; else not_ok "davar png written"; fi
else
	run "davar png without OpenCV" 2 allan --davar "$T/davar.png" -q "$G"
fi

# ---------------------------------------------------------------- report
run "report on the rate-table sample" 0 report -q -o "$T/rep" "$RT"
json_check "report: the rate-table calibration inferred" "$T/rep/report.json" \
  '.results.calib != null'
json_check "report: no noise term of the moving record as if valid" "$T/rep/report.json" \
  '[.summary[] | select(.stage == "allan") | select(.value != null)] | length == 0'
json_check "report: says why" "$T/rep/report.json" \
  '([.summary[] | select(.stage == "allan") | select(.note | test("^not valid: the (record|sensor) moves"))] | length == 3) and ([.summary[] | select(.stage == "allan") | .status] | unique == ["warning"])'
json_check "report: the commanded rate is not a gyro channel" "$T/rep/report.json" \
  '[.summary[] | select(.stage == "allan") | .channel] | index("rate_cmd") == null'
run "report plan on the rate-table sample" 0 report --dry-run "$RT"
has "plan: calib inferred from the commanded rate" "$T/out" 'calib +inferred: a gyro with a commanded-rate column \(rate_cmd\)'

# a held value then motion: the 1 s variance is zero in places, so the
# spread of variances is infinite; said in words, never "inf times"
run "allan on the rate table's commanded rate" 0 allan -c rate_cmd "$RT"
has "held value then motion: said in words" "$T/out" 'moves \(1 s variance zero in places, not in others\)'
lacks "no infinite spread printed" "$T/out" 'inf times'

done_testing
