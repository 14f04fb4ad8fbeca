#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope allan (continued from cli-allan.sh): gaps, constant and
# too-short data, the written grids, extreme magnitudes, every usage
# error, and what the fit doubts (presence, rejected fits).
. "$(dirname "$0")/lib.sh"

G="$SAMPLES/gyro-static.csv"
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
json_check "constant: zero deviations, no fit (terms null, not 0), own unit" "$T/out" \
  '([.channels[0].points[].dev] | all(. == 0)) and .channels[0].noise.N.value == null and .channels[0].noise.N.unit == "V/sqrt(Hz)" and .channels[0].noise.Q.si_unit == "V*s"'
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
# --stride only with --taus all or decade: on the other grids (the default
# dense one too, the grid given before or after it) a usage error that
# says why
for g in "" "--taus octave" "--taus dense" "--taus all --taus octave"; do
	# shellcheck disable=SC2086
	run "stride on grid '${g:-default}'" 2 allan --stride 4 $g --no-fit "$G"
	one_line_error "stride on grid '${g:-default}'"
	has "stride on grid '${g:-default}': says why" "$T/err" \
	    '^sensorscope: allan: --stride pays only with --taus all or decade: on the octave and dense grids it saved no time up to 10\^8 samples and lowers the EDF'
done
run "stride, octave grid given first" 2 allan --taus octave --stride 16 "$G"
has "stride, octave grid given first: says why" "$T/err" 'stride pays only with --taus all or decade'
# on the decade grid it is taken: strides m/4 from m = 8, the EDF below
# the full one at the short taus
run "stride on the decade grid" 0 allan --format json --stride 4 --taus decade --no-fit -c gx "$G"
json_check "stride on the decade grid: strides and EDF written" "$T/out" \
  '[.channels[0].points[] | select(.m >= 8)] | length > 3 and all(.stride == ((.m / 4) | floor) and .edf_full > 0) and ([.[] | select(.m <= 100)] | all(.edf < .edf_full))'
# the same rule for a scene's [allan] key, refused before anything runs
printf '[input]\nfiles = gyro-static.csv\n[allan]\nstride = 4\ntaus = octave\n[report]\nformats = json\noutput = sc-stride-octave\n' >"$T/stride-octave.ini"
printf '[input]\nfiles = gyro-static.csv\n[allan]\nstride = 4\n[report]\nformats = json\noutput = sc-stride-dense\n' >"$T/stride-dense.ini"
for v in octave dense; do
	run "scene: stride on the $v grid" 2 run "$T/stride-$v.ini"
	one_line_error "scene: stride on the $v grid"
	has "scene: stride on the $v grid: says why" "$T/err" \
	    "^sensorscope: run: allan: .*stride-$v.ini: stride pays only with taus all or decade"
	if [ -e "$T/sc-stride-$v" ]; then
		not_ok "scene: stride on the $v grid: no report written"
	else
		ok "scene: stride on the $v grid: no report written"
	fi
done
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
has "rejected fit, text warning" "$T/out" '^  warning: ax: fit rejected: chi2 [0-9.e+]+ for [0-9]+ dof, bootstrap p (= [0-9.e-]+|< 0\.001), below 0\.01'
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
