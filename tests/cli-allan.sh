#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope allan on the static-gyro sample: the JSON contract, text,
# CSV, every option, Kalibr YAML, the plot, angle input, gaps, constant
# and too-short data, and every usage and data error.
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
json_check "tdev is an angle" "$T/out" '.channels[0].dev_unit == "deg/s*s"'

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
run "stride" 0 allan --format json --stride 4 --taus octave -c gx "$G"
# Greenhall's branches (basic sum for the strided estimator, tables for
# the full one at large m) agree to about 2 %, so at the longest taus the
# strided EDF can come out a little above the full one
json_check "stride: reported with its EDF loss" "$T/out" \
  '[.channels[0].points[] | select(.m >= 8)] | all(.stride == (.m / 4) and .edf <= .edf_full * 1.03) and ([.[] | select(.m <= 64)] | all(.edf < .edf_full))'

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

# gaps, constant data, short data, no rate
awk 'NR <= 3 || NR > 8 { print; next } { print "nan,nan,nan" }' "$G" >"$T/gaps.csv"
run "NaN refused without --allow-nan" 1 allan "$T/gaps.csv"
one_line_error "NaN refused"
run "gaps with --allow-nan" 0 allan --allow-nan --format json -c gx --taus octave "$T/gaps.csv"
# NaN samples 0..4: at m = 1 the terms starting at 0..4 touch them
json_check "gaps skipped and counted" "$T/out" \
  '.channels[0].nan == 5 and .channels[0].points[0].skipped == 5 and .channels[0].points[0].terms == 35994'
# a NaN every 97 samples: no OADEV term of 2m > 96 samples is complete,
# so the taus from 0.5 s are left out with a warning (never a NaN at
# exit 0), in the command and in a scene; NaN everywhere but every other
# sample: refused
awk 'BEGIN { srand(97); print "time [s],gx [rad/s]"; for (i = 0; i < 9700; i++) printf "%.2f,%s\n", i / 100, i % 97 ? sprintf("%.6f", rand() - 0.5) : "nan" }' >"$T/gap97.csv"
run "NaN every 97 samples" 0 allan --allow-nan "$T/gap97.csv"
lacks "NaN every 97: no nan in the table" "$T/out" '(^|[^A-Za-z])nan([^A-Za-z]|$)'
has "NaN every 97: the omitted taus said" "$T/err" 'warning: .*gx: NaN gaps leave no oadev term without a gap at [0-9]+ of the [0-9]+ taus \(from 0\.5 s; the longest stretch without a gap is 96 samples, 0\.96 s\): those taus are left out'
run "NaN every 97: JSON" 0 allan --allow-nan --format json "$T/gap97.csv"
json_check "NaN every 97: no null deviation, taus up to 0.48 s, omitted counted" "$T/out" \
  '.channels[0] as $c | ([$c.points[] | .dev, .dev_lo, .dev_hi, .edf | numbers] | length) == 4 * ($c.points | length) and ($c.points | last | .m) <= 48 and $c.gap_omitted_taus > 10 and ($c.warnings | map(.code) | index("gap_taus_omitted")) != null'
for dv in mdev hdev ohdev adev; do
	run "NaN every 97: $dv" 0 allan --allow-nan --no-fit --dev $dv "$T/gap97.csv"
	lacks "NaN every 97: $dv: no nan" "$T/out" '(^|[^A-Za-z])nan([^A-Za-z]|$)'
done
run "NaN every 97: totdev refused" 1 allan --allow-nan --dev totdev "$T/gap97.csv"
one_line_error "NaN every 97: totdev"
has "NaN every 97: totdev says what to do" "$T/err" 'choose another deviation or analyse a stretch without gaps'
printf '[input]\nfiles = gap97.csv\nallow_nan = yes\n[allan]\ntaus = dense\n[report]\nformats = json, text\noutput = sc-gap97\n' >"$T/gap97.ini"
(cd "$T" && ss run gap97.ini >/dev/null 2>"$T/err")
json_check "NaN every 97: scene: no null deviation, the warning kept" "$T/sc-gap97/allan.json" \
  '.channels[0] as $c | ([$c.points[] | .dev | numbers] | length) == ($c.points | length) and ($c.warnings | map(.code) | index("gap_taus_omitted")) != null'
has "NaN every 97: scene: warned" "$T/err" 'those taus are left out'
awk 'BEGIN { print "# rate: 100 Hz"; print "gx [rad/s]"; for (i = 0; i < 400; i++) print i % 2 ? "nan" : 0.1 * sin(i * 2.385) }' >"$T/alt.csv"
run "NaN every other sample: refused" 1 allan --allow-nan "$T/alt.csv"
one_line_error "NaN every other sample"
has "NaN every other sample: why and what to do" "$T/err" 'no oadev term without a gap at any tau .*: fill the gaps'
{ echo "# rate: 100 Hz"; echo "x [V]"; i=0; while [ $i -lt 200 ]; do echo 1.25; i=$((i + 1)); done; } >"$T/const.csv"
run "constant data" 0 allan --format json "$T/const.csv"
json_check "constant: zero deviations, zero coefficients, own unit" "$T/out" \
  '([.channels[0].points[].dev] | all(. == 0)) and .channels[0].noise.N.value == 0 and .channels[0].noise.N.unit == "V/sqrt(Hz)" and .channels[0].noise.Q.si_unit == "V*s"'
has "constant: the fit says why" "$T/err" 'constant data'
printf '# rate: 10 Hz\nx [deg/s]\n0.5\n' >"$T/one.csv"
run "one sample" 1 allan "$T/one.csv"
one_line_error "one sample"
has "one sample: too short" "$T/err" 'too short for oadev: 1 sample'
printf 'x [deg/s]\n0.5\n0.6\n0.7\n' >"$T/norate.csv"
run "no rate" 1 allan "$T/norate.csv"
one_line_error "no rate"
has "no rate: says --rate" "$T/err" 'give --rate'
run "--rate makes it work" 0 allan -r 10 --no-fit "$T/norate.csv"
run "kalibr without a gyro" 1 allan --kalibr "$T/v.yaml" -q "$T/const.csv"
one_line_error "kalibr without a gyro"

# the command writes an all-tau grid's points as text, a scene dumps the
# tree: the same bytes, also with gaps (skipped terms) and a stride
# (edf_full), two channels
cp "$G" "$T/gyro-static.csv"
printf '[input]\nfiles = gyro-static.csv\ncolumns = gx,gy\n[allan]\ntaus = all\n[report]\nformats = json\noutput = sc-plain\n' >"$T/all-plain.ini"
printf '[input]\nfiles = gaps.csv\ncolumns = gx,gy\nallow_nan = yes\n[allan]\ntaus = all\nstride = 4\n[report]\nformats = json\noutput = sc-gaps\n' >"$T/all-gaps.ini"
# deviations near 1e-15 and 1e15: exponents both ways, the switch of
# "%.15g" to an exponent at 1e15
awk -F, 'NR <= 2 { print; next } NR == 3 { print "gx [deg/s],gy [deg/s]"; next } { printf "%.6e,%.6e\n", $1 * 1e-13, $2 * 1e18 }' "$G" >"$T/wide.csv"
printf '[input]\nfiles = wide.csv\ncolumns = gx,gy\n[allan]\ntaus = all\n[report]\nformats = json\noutput = sc-wide\n' >"$T/all-wide.ini"
for v in "plain gyro-static.csv" "gaps gaps.csv --allow-nan --stride 4" "wide wide.csv"; do
	# shellcheck disable=SC2086
	set -- $v
	name=$1 in=$2
	shift 2
	(cd "$T" && ss allan --format json --taus all -c gx,gy "$@" "$in" >"all-$name.json" &&
	 ss run -q "all-$name.ini" >/dev/null)
	if [ -s "$T/all-$name.json" ] && cmp -s "$T/all-$name.json" "$T/sc-$name/allan.json"; then
		ok "all taus, $name: the command's JSON is the scene's allan.json"
	else
		not_ok "all taus, $name: the command's JSON is the scene's allan.json"
	fi
done
json_check "all taus: every point of both channels" "$T/all-plain.json" \
	'[.channels[] | (.points | length) == 18000 and .points[17999].m == 18000 and (.points[0].dev > 0)] == [true, true]'
# the points of a long grid are written in two halves: each once, in order
json_check "all taus: points in order, each once" "$T/all-plain.json" \
	'[.channels[] | [.points[].m] == [range(1; 18001)]] == [true, true]'
json_check "all taus, gaps: skipped terms, strides and edf_full written" "$T/all-gaps.json" \
	'.channels[0].points[0].skipped > 0 and .channels[0].points[99].stride == 25 and .channels[0].points[99].edf_full > 0'

# usage errors
for bad in "--dev xdev" "--taus weekly" "--input phase" "--ci 1.5" "--ci x" \
	   "--noise-type pink" "--terms N,X" "--fit-tau 5:1" "--stride 0" \
	   "--model-error 2" "--dev-unit furlong" "--threads 0"; do
	# shellcheck disable=SC2086
	run "usage: $bad" 2 allan $bad "$G"
	one_line_error "usage: $bad"
done
run "stride with mdev" 2 allan --stride 4 --dev mdev "$G"
run "kalibr with no-fit" 2 allan --kalibr "$T/x.yaml" --no-fit "$G"
run "no file" 2 allan

# -o is atomic
run "-o" 0 allan -o "$T/r.txt" -c gx --no-fit "$G"
has "-o content" "$T/r.txt" 'gyro-static.csv: gx'

if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "--plot" 0 allan --plot "$T/allan.png" "$G"
	if head -c 8 "$T/allan.png" | od -An -c | grep -q 'P   N   G'; then ok "PNG written"; else not_ok "PNG written"; fi
else
	run "--plot without OpenCV" 2 allan --plot "$T/allan.png" "$G"
fi

# what the fit doubts: the README's accelerometer example (a thermal run)
# is rejected in text and JSON; the static gyro's fits are not, and a term
# is resolved exactly when fitted with an interval above zero, flagged
# with a warning otherwise
A="$SAMPLES/accel-thermal.csv"
run "rejected fit, text" 0 allan --ci 0.95 --terms N,B,K -c ax,ay,az "$A"
has "rejected fit, text warning" "$T/out" '^  warning: ax: fit rejected: chi2 [0-9.e+]+ for [0-9]+ dof, p = [0-9.e-]+ < 0.01'
run "rejected fit, JSON" 0 allan --ci 0.95 --terms N,B,K -c ax,ay,az --format json "$A"
json_check "rejected fit, JSON warning" "$T/out" '[.channels[] | .fit.rejected and (.warnings | map(.code) | index("fit_rejected") != null)] | all'
run "static gyro, JSON" 0 allan --format json "$G"
json_check "static gyro: fits accepted" "$T/out" '[.channels[].fit.rejected] == [false, false, false]'
# presence is a test on nested fits, the interval that of the fit of every
# term: a term is resolved when present with an interval clear of 0; a
# present term whose interval reaches 0 (K on gz over this 1 h record, 10
# deg/h/sqrt(h)) carries a "term_unresolved" warning; an absent one has no
# value, lo 0, a bound above 0 and its reason
json_check "static gyro: presence, resolution and the warnings agree" "$T/out" \
	'[.channels[] | ((.warnings // []) | map(.code)) as $w | .noise | to_entries[] | .value | select(type == "object") | (.present == .fitted) and (.resolved == (.present and .lo > 0)) and (if .present then (.lo <= .value and .value <= .hi and .reason == null and ((.lo > 0) or ($w | index("term_unresolved") != null))) else (.value == null and .lo == 0 and .bound > 0 and .bound == .hi and (.reason | type) == "string") end)] | all'
json_check "static gyro: every term has its point estimate, equal to the value when fitted" "$T/out" \
	'[.channels[].noise[] | select(type == "object") | (.estimate >= 0) and (.si_estimate >= 0) and ((.fitted | not) or (.estimate == .value))] | all'
json_check "static gyro: the presence test and its level are stated" "$T/out" \
	'[.channels[].fit.selection | (.z == 3) and (.level > 0.00134 and .level < 0.00136) and (.test | test("likelihood-ratio"))] | all'
json_check "static gyro: no read-off of an absent term, a reason instead" "$T/out" \
	'[.channels[] | . as $c | ["N","B","K"][] as $t | $c.readoff[$t] | if .value == null then (.reason | type) == "string" else $c.noise[$t].present end] | all'
json_check "static gyro: K bounded, not resolved, on 1 h" "$T/out" \
	'[.channels[] | .noise.K | (.resolved | not) and .lo == 0 and .hi > 0] | all'
done_testing
