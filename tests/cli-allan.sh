#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope allan on the static-gyro sample: the JSON contract, text,
# CSV, every option, Kalibr YAML, the plot and angle input; gaps, constant
# and too-short data, usage and data errors, the fit's doubts: cli-allan-data.sh.
. "$(dirname "$0")/lib.sh"

G="$SAMPLES/gyro-static.csv"

run "allan text" 0 allan "$G"
has "text: table header" "$T/out" 'tau \(s\) +m +terms +oadev'
has "text: coefficients" "$T/out" 'N  angle random walk +0\.1[45][0-9]* deg/sqrt\(h\)'
has "text: read-offs" "$T/out" 'classic read-offs where the fit says the term dominates \(a present term, at least 3/4 of the fitted model with the others at their upper bounds, EDF >= 10\): N = sigma\(1 s\)'

run "allan json" 0 allan --format json "$G"
cp "$T/out" "$T/a.json"
json_check "json: contract fields" "$T/a.json" \
  '.command == "allan" and .file == "'"$G"'" and (.channels | length) == 3 and .channels[0].name == "gx" and .channels[0].unit == "deg/s" and .channels[0].rate_hz == 10 and .channels[0].samples == 36000 and .channels[0].deviation == "oadev"'
json_check "json: points" "$T/a.json" \
  '.channels[0].points[0] | (.tau_s == 0.1 and .m == 1 and .terms == 35999 and .dev > 0.007 and .dev < 0.009 and .dev_lo < .dev and .dev_hi > .dev and .edf > 1000)'
json_check "json: dense grid, Stable32 limit" "$T/a.json" \
  '[.channels[0].points[].m] | (.[0:8] == [1,2,3,4,5,6,8,10] and (last <= 18000) and length > 30)'
json_check "json: noise objects" "$T/a.json" \
  '.channels[0].noise | to_entries | map(.value | has("value") and has("unit") and has("lo") and has("hi") and has("si") and has("si_unit") and has("fitted")) | all and length == 5'
json_check "json: gyro units" "$T/a.json" \
  '.channels[0].noise | .Q.si_unit == "rad" and .N.unit == "deg/sqrt(h)" and .N.si_unit == "rad/s/sqrt(Hz)" and .B.unit == "deg/h" and .B.si_unit == "rad/s" and .K.unit == "deg/h/sqrt(h)" and .K.si_unit == "rad/s^2/sqrt(Hz)" and .R.si_unit == "rad/s^2"'
# the sample is N = 0.15 deg/sqrt(h), B = 2 deg/h, K = 10 deg/h/sqrt(h):
# N resolved on every axis, B resolved or bounded above 1, K (not resolved
# in 1 h) bounded above 3
json_check "json: the sample's terms are found" "$T/a.json" \
  '[.channels[].noise | (.N.fitted and .N.value > 0.145 and .N.value < 0.155 and (if .B.fitted then .B.value > 1 and .B.value < 3 else .B.hi > 1 end) and (if .K.fitted then .K.value > 3 and .K.value < 30 else .K.hi > 3 end))] | all'
json_check "json: SI and conventional agree" "$T/a.json" \
  '.channels[0].noise.N | ((.value * 3.141592653589793 / 180 / 60) / .si - 1 | fabs) < 1e-9'
json_check "json: unfitted terms carry an upper limit" "$T/a.json" \
  '.channels[0].noise.Q | (.fitted == false and .value == null and .lo == 0 and .hi > 0)'
json_check "json: fit and read-offs" "$T/a.json" \
  '(.channels[0].fit.terms | index("N") != null and index("B") != null) and .channels[0].fit.dof > 20 and (.channels[0].readoff.N.value - 0.15 | fabs) < 0.01'

run "allan csv" 0 allan --format csv -c gx "$G"
has "csv header" "$T/out" '^file,channel,deviation,unit,tau_s,m,terms,dev,dev_lo,dev_hi,edf,alpha$'
has "csv row" "$T/out" 'gyro-static.csv,gx,oadev,deg/s,0.1,1,35999,'
run "csv --dev-unit" 0 allan --format csv -c gx --dev-unit deg/h "$G"
has "csv in deg/h" "$T/out" 'gyro-static.csv,gx,oadev,deg/h,0.1,1,35999,28\.'

run "mdev octave" 0 allan --format json --dev mdev --taus octave -c gy "$G"
json_check "mdev octave" "$T/out" \
  '.channels[0].deviation == "mdev" and ([.channels[0].points[].m] == [1,2,4,8,16,32,64,128,256,512,1024,2048,4096,8192]) and .channels[0].fit.terms != null'
run "totdev decade" 0 allan --format json --dev totdev --taus decade -c gz --no-fit "$G"
json_check "decade grid, no fit" "$T/out" \
  '([.channels[0].points[].m] | .[0:7] == [1,2,4,10,20,40,100]) and (.channels[0] | has("noise") | not)'
run "tdev unit" 0 allan --format json --dev tdev --taus octave -c gx --no-fit "$G"
json_check "tdev is an angle" "$T/out" '.channels[0].dev_unit == "deg"'

run "ci none" 0 allan --format json --ci none -c gx --no-fit "$G"
json_check "ci none: no bounds" "$T/out" '.channels[0].points[0].dev_lo == null and .channels[0].ci_level == null'
run "ci 0.95" 0 allan --format json --ci 0.95 -c gx "$G"
json_check "ci 0.95: wider than 0.683" "$T/out" \
  '.channels[0].ci_level == 0.95 and (.channels[0].points[5] | (.dev_hi - .dev_lo)) > ('"$(jq '.channels[0].points[5] | (.dev_hi - .dev_lo)' "$T/a.json" 2>/dev/null || echo 0)"')'
run "noise-type" 0 allan --format json --noise-type wfm --taus octave -c gx "$G"
json_check "noise-type fixes alpha" "$T/out" '[.channels[0].points[].alpha] | all(. == 0)'
run "terms" 0 allan --format json --terms N,B -c gx "$G"
json_check "terms restrict the fit" "$T/out" \
  '(.channels[0].fit.terms - ["N","B"] | length) == 0 and .channels[0].noise.K.fitted == false and .channels[0].noise.K.hi == null'
run "fit-tau" 0 allan --format json --fit-tau 1: -c gx "$G"
json_check "fit-tau drops short taus" "$T/out" '.channels[0].fit.points < ([.channels[0].points[]] | length)'
# --stride with --taus all (or decade; refused on the octave and dense grids:
# cli-allan-data.sh);
# the grid may come after it
run "stride" 0 allan --format json --stride 4 --taus all -c gx "$G"
# terms every floor(m/4) samples, written from m = 8 (below, the stride is
# 1: the full estimator, no stride or edf_full written).  Greenhall's
# branches (basic sum for the strided estimator, tables for the full one at
# large m) agree to about 2 % while there are some 30 strided terms (m up
# to about N/8 = 4500), so there the strided EDF can come out a little
# above the full one; with a handful of terms left they part further
json_check "stride: reported with its EDF loss" "$T/out" \
  '[.channels[0].points[]] | ([.[] | select(.m < 8)] | length == 7 and all(has("stride") | not) and all(has("edf_full") | not)) and ([.[] | select(.m >= 8)] | length > 17000 and all(.stride == ((.m / 4) | floor) and .edf > 0 and .edf_full > 0)) and ([.[] | select(.m >= 8 and .m <= 4000)] | all(.edf <= .edf_full * 1.03)) and ([.[] | select(.m >= 8 and .m <= 64)] | all(.edf < .edf_full))'

# angle input: the integrated gyro gives the same deviations
awk -F, 'BEGIN { print "# rate: 10 Hz"; print "theta [deg]"; a = 0 }
	 /^[-0-9]/ { printf "%.15g\n", a; a += $1 / 10 } END { printf "%.15g\n", a }' "$G" >"$T/angle.csv"
run "angle input" 0 allan --format json --input angle --taus octave --no-fit "$T/angle.csv"
cp "$T/out" "$T/angle.json"
run "rate input" 0 allan --format json --taus octave --no-fit -c gx "$G"
json_check "angle: rate unit" "$T/angle.json" '.channels[0].dev_unit == "deg/s" and .channels[0].input == "angle"'
json_check "angle equals rate" "$T/angle.json" \
  '.channels[0].points[3].dev / '"$(jq '.channels[0].points[3].dev' "$T/out" 2>/dev/null || echo 1)"' - 1 | fabs < 1e-6'

# Kalibr
run "kalibr" 0 allan --kalibr "$T/imu.yaml" -q "$G"
has "kalibr: noise density" "$T/imu.yaml" '^gyroscope_noise_density: 4\.[0-9]+e-05 '
has "kalibr: random walk" "$T/imu.yaml" '^gyroscope_random_walk: [0-9.]+e-0[67] '
has "kalibr: update rate" "$T/imu.yaml" '^update_rate: 10 '
lacks "kalibr: no accelerometer keys" "$T/imu.yaml" '^accelerometer_'
# a temperature cycle: the fit is rejected, the export refused unless forced
run "kalibr accelerometer, rejected fit" 1 allan --kalibr "$T/acc.yaml" -q -c ax,az "$SAMPLES/accel-thermal.csv"
one_line_error "kalibr accelerometer, rejected fit"
run "kalibr accelerometer, forced" 0 allan --kalibr "$T/acc.yaml" --force -q -c ax,az "$SAMPLES/accel-thermal.csv"
has "kalibr: accelerometer keys, marked" "$T/acc.yaml" '^accelerometer_noise_density: .* DOUBTFUL'
# the total, Theo and time-error deviations: names, labels, units, no
# interval for MTIE and TIE rms, Theo1 to 0.75 of the record, gaps refused
run "mtotdev octave" 0 allan --format json --dev mtotdev --taus octave -c gz --no-fit "$G"
json_check "mtotdev: label, m <= N/3, intervals" "$T/out" \
  '.channels[0].deviation == "mtotdev" and .channels[0].deviation_label == "MTOTDEV" and ([.channels[0].points[].m] | last) == 8192 and (.channels[0].points[0] | .dev_lo < .dev and .dev_hi > .dev and .edf > 0 and .noise == "WFM")'
run "theo1 text" 0 allan --dev theo1 --taus octave -c gz --no-fit "$G"
has "theo1: name in the table" "$T/out" 'tau \(s\) +m +terms +theo1'
has "theo1: ends at 0.75 of the record" "$T/out" '^ +2700 +36000 '
run "mtie json" 0 allan --format json --dev mtie --taus octave -c gz --no-fit "$G"
json_check "mtie: time unit, no interval, no noise type" "$T/out" \
  '.channels[0].dev_unit == "deg" and ([.channels[0].points[] | (.dev > 0 and .dev_lo == null and .dev_hi == null and .edf == null and .alpha == null and .noise == null)] | all)'
run "mtie csv" 0 allan --format csv --dev mtie --taus octave -c gz --no-fit "$G"
has "mtie csv: empty interval, edf and alpha" "$T/out" 'gyro-static.csv,gz,mtie,deg,0\.1,1,36000,[0-9.e-]+,,,,$'
run "tierms text" 0 allan --dev tierms --taus decade -c gx --no-fit "$G"
has "tierms: no interval said" "$T/out" 'none \(no EDF model\)'
run "theoh with the fit" 0 allan --format json --dev theoh --taus octave -c gx "$G"
json_check "theoh: OADEV then TheoBR taus, the fit on OADEV" "$T/out" \
  '([.channels[0].points[].tau_s] | . == sort and last == 2700) and .channels[0].noise.N.fitted'
printf 'gx [rad/s]\n1\n2\n3\n1\n2\n3\n1\n2\n' >"$T/short8.csv"
run "theo1: 8 samples" 1 allan --dev theo1 -r 10 "$T/short8.csv"
one_line_error "theo1: 8 samples"
has "theo1: too short said" "$T/err" 'too short for theo1: 8 samples'
head -81 "$G" >"$T/short80.csv"
run "theobr: 80 samples" 1 allan --dev theobr -c gx --no-fit "$T/short80.csv"
has "theobr: its bias ratio said" "$T/err" 'too short for theobr: [0-9]+ phase points \(its bias ratio needs at least 90\)'
run "bad --dev lists the names" 2 allan --dev theo2 "$G"
has "bad --dev: the list" "$T/err" 'mtotdev, htotdev, ttotdev, theo1, theobr, theoh, mtie or tierms'
done_testing
