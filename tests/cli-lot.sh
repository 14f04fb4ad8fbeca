#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope lot: seven simulated gyros of one model whose white noise
# differs from unit to unit (known spread) and one unit far out; the mean
# and the between-unit sd against the truth, the outlier named by its
# file, the scene stage equal to the command, and bad input.
. "$(dirname "$0")/lib.sh"

run "lot --help" 0 lot --help
# six units with N = 0.031 .. 0.036 deg/s/sqrt(Hz), 20 min at 100 Hz: N in
# deg/sqrt(h) is 60 times that, 1.86 .. 2.16, mean 2.01, sd of the six
# 0.1122 (sample sd of 1.86, 1.92, ..., 2.16); a seventh unit at 0.09
# (5.4 deg/sqrt(h)), 30 of its own standard errors out
for i in 1 2 3 4 5 6 7; do
	nd=$([ $i = 7 ] && echo 0.09 || echo "0.03$i")
	printf '[sensor]\nnoise_density = %s deg/s/sqrt(Hz)\n' "$nd" >"$T/s$i.ini"
	run "simulate unit $i" 0 simulate --sensor "$T/s$i.ini" --rate 100 --duration 1200 --seed $i -o "$T/unit$i.csv"
done
run "lot of 7" 0 lot --format json "$T"/unit1.csv "$T"/unit2.csv "$T"/unit3.csv \
	"$T"/unit4.csv "$T"/unit5.csv "$T"/unit6.csv "$T"/unit7.csv
cp "$T/out" "$T/lot.json"
json_check "seven units, per-unit terms" "$T/out" '(.units | length) == 7 and (.units[6].channels[0].terms.N.present)'
json_check "the outlier named by its file" "$T/out" '.outliers == [{"unit": "unit7.csv", "channel": "gx", "term": "N", "z": .outliers[0].z}] and .outliers[0].z > 10'
json_check "N: the six others used" "$T/out" '(.between[] | select(.term == "N") | .units_used == 6 and .units_resolved == 7 and .outliers == ["unit7.csv"])'
json_check "N: mean near 2.01 deg/sqrt(h)" "$T/out" '(.between[] | select(.term == "N") | (.mean - 2.01 | fabs) < 0.05 and .mean_lo < 2.01 and 2.01 < .mean_hi and .unit == "deg/sqrt(h)")'
json_check "N: between-unit sd near 0.112, inside its interval" "$T/out" '(.between[] | select(.term == "N") | (.between_sd - 0.112 | fabs) < 0.04 and .between_sd_lo < 0.112 and 0.112 < .between_sd_hi)'
json_check "B and K: not shown, no spread and no number" "$T/out" '[.between[] | select(.term == "B" or .term == "K") | .why != null and .between_sd == null] | all'
run "lot text" 0 lot "$T"/unit[1-7].csv
has "text: N row with the outlier" "$T/out" '^gx +N +deg/sqrt\(h\) .*unit7\.csv \(z '
has "text: K says why" "$T/out" '^gx +K .*fewer than 3, no spread'

# against limits: N's limit 3 deg/sqrt(h) = 0.05 deg/s/sqrt(Hz); units 1-6
# (N 1.86 .. 2.16) well below, unit 7 (5.4) well above, unit 8 simulated
# exactly at the limit: inconclusive, never within spec; B and K, which no
# unit's fit shows, an upper bound only: within spec under a loose limit,
# inconclusive (never out, never 0) under a tight one
printf '[sensor]\nnoise_density = 0.05 deg/s/sqrt(Hz)\n' >"$T/s8.ini"
run "simulate unit 8 at the limit" 0 simulate --sensor "$T/s8.ini" --rate 100 --duration 1200 --seed 8 -o "$T/unit8.csv"
printf '[gyro]\nrandom_walk = 3 deg/sqrt(h)\nbias_instability = 100 deg/h\nrate_random_walk = 0.001 deg/h/sqrt(h)\n' >"$T/limits.ini"
run "lot --spec" 0 lot --format json --spec "$T/limits.ini" "$T"/unit[1-8].csv
json_check "units 1-6 within spec on N" "$T/out" '[.units[0:6][].channels[0].terms.N.spec.verdict] == ["within spec","within spec","within spec","within spec","within spec","within spec"]'
json_check "unit 7 out of spec on N" "$T/out" '.units[6].channels[0].terms.N.spec | .verdict == "out of spec" and .lo > 3 and .level == 0.99'
json_check "unit 8 at the limit: inconclusive" "$T/out" '.units[7].channels[0].terms.N.spec | .verdict == "inconclusive" and .lo <= 3 and 3 <= .hi'
json_check "K: a bound only, inconclusive, no 0" "$T/out" '[.units[].channels[0].terms.K.spec | .upper_bound_only and .lo == null and .verdict == "inconclusive"] | all'
json_check "B: a bound below 100 deg/h is within spec" "$T/out" '[.units[].channels[0].terms.B.spec | select(.verdict == "within spec") | .upper_bound_only and .hi < 100] | length > 0'
json_check "counts per term" "$T/out" '(.between[] | select(.term == "N") | .within_spec == 6 and .out_of_spec == 1 and .inconclusive == 1 and .limit == 3) and (.between[] | select(.term == "K") | .inconclusive == 8 and .cpk == null and .cpk_why != null)'
json_check "N: Cpk over every unit, its formula, inside its interval" "$T/out" '.between[] | select(.term == "N") | .cpk_units == 8 and ((.cpk - (3 - .cpk_mean) / (3 * .cpk_sigma)) | fabs) < 1e-9 and .cpk_lo < .cpk and .cpk < .cpk_hi and ((.cpk_sigma - ((.cpk_between_sd * .cpk_between_sd + .cpk_within_sd * .cpk_within_sd) | sqrt)) | fabs) < 1e-9'
json_check "the limits file named, nothing left unchecked" "$T/out" '.spec.file == "'"$T/limits.ini"'" and .spec.not_checked == [] and .spec.level == 0.99'
run "lot --spec text" 0 lot --spec "$T/limits.ini" "$T"/unit[1-8].csv
has "text: N counts and Cpk" "$T/out" '^gx +N +deg/sqrt\(h\) +3 +6 +1 +1 +-?[0-9.]+ \['
has "text: unit 8 inconclusive" "$T/out" '^unit8\.csv: gx N inconclusive;'
# a datasheet file as limits (the N line, B from the in-run bias stability)
run "a datasheet as limits" 0 lot --format json --spec "$SAMPLES/datasheets/kvh-dsp-1760.ini" "$T"/unit[1-3].csv
json_check "datasheet: N out of spec for every unit" "$T/out" '.between[] | select(.term == "N") | .out_of_spec == 3'
# a datasheet with two N lines: the first by kind (noise density) is the
# limit, the other and the accelerometer's lines are listed as not checked
run "datasheet: lines not checked" 0 lot --format json --spec "$SAMPLES/datasheets/adis16448.ini" "$T"/unit[1-3].csv
json_check "datasheet: not checked listed" "$T/out" '.spec.not_checked == ["[gyro] random_walk", "[accel] random_walk", "[accel] noise_density"] and (.between[] | select(.term == "N") | .limit - 0.81 | fabs) < 1e-9'
printf '[gyro]\nrandom_walk = 3 deg/sqrt(h)\nbias_wobble = 3 deg/h\n' >"$T/bad1.ini"
run "limits: an unknown key" 1 lot --spec "$T/bad1.ini" "$T"/unit[1-3].csv
one_line_error "limits: an unknown key"
has "names the line" "$T/err" 'line 3: \[gyro\] bias_wobble: unknown'
printf '[gyro]\nrandom_walk = 3\n' >"$T/bad2.ini"
run "limits: no unit" 1 lot --spec "$T/bad2.ini" "$T"/unit[1-3].csv
one_line_error "limits: no unit"
has "says a unit is needed" "$T/err" 'a unit is needed'
printf '[accel]\nrandom_walk = 3 m/s/sqrt(h)\n' >"$T/acc.ini"
run "limits for no channel of the lot" 1 lot --spec "$T/acc.ini" "$T"/unit[1-3].csv
one_line_error "limits for no channel of the lot"

# limits on the bias terms (their magnitude), on the sample lot: bias
# within +-1.5 mg except unit 07 (1.8 mg); the temperature sensitivity
# (truth 41-58 ug/degC) against +-70: within spec exactly where its
# conservative 99 % interval (B, K at the fit's bounds where not shown:
# se_upper, normal quantile) lies inside, which the reported interval
# alone would pass more often; the Cpk of the nearer side
printf '[accel]\nbias_offset = 1.5 mg\nrate_ramp = 100 ug/h\nbias_tempco = 70 ug/degC\n' >"$T/bias-lim.ini"
run "lot --spec on the bias terms" 0 lot --format json --spec "$T/bias-lim.ini" "$SAMPLES/lot"
json_check "bias: unit 07 out of spec, the others within" "$T/out" \
	'[.units[].channels[0].terms.bias.spec.verdict] == ["within spec","within spec","within spec","within spec","within spec","within spec","out of spec","within spec","within spec","within spec","within spec","within spec"]'
json_check "a limit on the magnitude, the 99 % interval" "$T/out" \
	'.units[0].channels[0].terms.bias.spec | .limit_on_magnitude and .level == 0.99 and .lo < .hi and .limit == 1500'
json_check "sensitivity within spec where its conservative interval is inside" "$T/out" \
	'[.units[].channels[0].terms.temp_sensitivity | (.spec.verdict == "within spec") == (.spec.lo > -70 and .spec.hi < 70 and ((.doubt // "") | test("residuals are correlated") | not))] | all'
json_check "the verdict's interval is that of se_upper where it is wider" "$T/out" \
	'[.units[].channels[0].terms.temp_sensitivity | select(.se_upper > 1.0001 * .se) | ((.spec.hi - .spec.lo) / 2 - 2.5758293035489 * .se_upper | fabs) < 1e-6 * .se_upper] | length > 0 and all'
json_check "a unit the reported 99 % interval would pass is inconclusive" "$T/out" \
	'[.units[].channels[0].terms.temp_sensitivity | select((.value | fabs) + 2.8982 * .se < 70 and .spec.verdict == "inconclusive")] | length > 0'
json_check "Cpk = (limit - |mean|) / (3 sigma)" "$T/out" \
	'.between[] | select(.term == "bias") | .limit_on_magnitude and ((.cpk - (1500 - (.cpk_mean | fabs)) / (3 * .cpk_sigma)) | fabs) < 1e-6'
json_check "every line checked" "$T/out" '.spec.not_checked == []'
printf '[accel]\nbias_offset = -1 mg\n' >"$T/neg-lim.ini"
run "limits: a negative magnitude" 1 lot --spec "$T/neg-lim.ini" "$SAMPLES/lot"
one_line_error "limits: a negative magnitude"

# the scene's stage is the command
cat >"$T/lot.scene.ini" <<EOS
[input]
files = unit1.csv, unit2.csv, unit3.csv, unit4.csv, unit5.csv, unit6.csv, unit7.csv

[lot]
EOS
run "lot as a scene stage" 0 run -q -o "$T/scene-out" "$T/lot.scene.ini"
if [ -f "$T/scene-out/lot.json" ] && command -v jq >/dev/null 2>&1; then
	jq -S 'del(.units[].path)' "$T/scene-out/lot.json" >"$T/a.json"
	jq -S 'del(.units[].path)' "$T/lot.json" >"$T/b.json"
	if cmp -s "$T/a.json" "$T/b.json"; then ok "scene stage: the command's JSON"; else not_ok "scene stage: the command's JSON"; diff "$T/a.json" "$T/b.json" | head -5 | diag /dev/stdin; fi
else
	skip "scene stage: the command's JSON" "no lot.json or no jq"
fi
cp "$T/limits.ini" "$T/scene-limits.ini"
cat >"$T/lot-spec.scene.ini" <<EOS
[input]
files = unit1.csv, unit2.csv, unit7.csv

[lot]
spec = scene-limits.ini
EOS
run "scene: spec relative to the scene" 0 run -q -o "$T/scene-spec" "$T/lot-spec.scene.ini"
json_check "scene: verdicts" "$T/scene-spec/lot.json" '.between[0].within_spec == 2 and .between[0].out_of_spec == 1'

# the bundled lot (tests/gen-sample-lot.sh: the truth is in the script):
# twelve accelerometers, unit 07 1.80 mg against 0.88..1.21 mg; the lot's
# means of the temperature sensitivity (truth: the mean of the script's
# list, 50.25 ug/degC) and of the drift (7.58 ug/h) inside their
# intervals, unit 07 the only bias outlier
L="$SAMPLES/lot"
run "the bundled lot" 0 lot --format json --plot "$T/lot.svg" "$L"/unit*.csv
cp "$T/out" "$T/sample.json"
json_check "unit07 the only outlier, in bias" "$T/out" '[.outliers[] | [.unit, .term]] == [["unit07.csv", "bias"]]'
json_check "temperature sensitivity: mean covers 50.25 ug/degC" "$T/out" '.between[] | select(.term == "temp_sensitivity") | .unit == "ug/degC" and .mean_lo < 50.25 and 50.25 < .mean_hi and .units_used == 12'
json_check "drift: mean covers 7.58 ug/h" "$T/out" '.between[] | select(.term == "bias_drift") | .unit == "ug/h" and .mean_lo < 7.58 and 7.58 < .mean_hi'
json_check "bias: 11 units used, unit07 far out" "$T/out" '(.between[] | select(.term == "bias") | .units_used == 11 and .mean_lo < 1061 and 1061 < .mean_hi) and (.units[6].channels[0].terms.bias | .outlier and .value > 1700 and .se > 0)'
json_check "per unit: bias within its interval, temperature said" "$T/out" '[.units[].channels[0] | .terms.bias.lo < .terms.bias.value and .terms.bias.value < .terms.bias.hi and .temperature.span_degc > 4 and (.temperature.time_corr | fabs) < 0.3 and .bias_blocks == 20] | all'
if [ -s "$T/lot.svg" ] && [ -s "$T/lot-adev.svg" ]; then ok "--plot: two figures"; else not_ok "--plot: two figures"; fi
has "bias figure: the outlier named" "$T/lot.svg" 'unit07\.csv \(outlier\)'
has "bias figure: the population band" "$T/lot.svg" '5-95 % of the units'
has "adev figure: the median" "$T/lot-adev.svg" 'median of the units'
if command -v "$PYTHON3" >/dev/null 2>&1 && "$PYTHON3" "$top_srcdir/tests/svgcheck.py" "$T/lot.svg" "$T/lot-adev.svg" >"$T/check" 2>&1; then
	ok "figures: SVG structure"
elif ! command -v "$PYTHON3" >/dev/null 2>&1; then
	skip "figures: SVG structure" "no python3"
else
	not_ok "figures: SVG structure"; diag "$T/check"
fi
run "a folder: its files, sorted" 0 lot --format json "$L"
if cmp -s "$T/out" "$T/sample.json"; then ok "a folder: the same JSON as its files"; else not_ok "a folder: the same JSON as its files"; fi
mkdir "$T/empty"
touch "$T/empty/notes.md" "$T/empty/.hidden"
run "a folder without captures" 1 lot "$T/empty"
one_line_error "a folder without captures"
# a manifest: the units' names, their files relative to it, channels and
# temperature column per unit; the same numbers as the files
mkdir "$T/m"
cp "$L"/unit*.csv "$T/m/"
{
	echo "unit,file,channels,temperature"
	for i in 01 02 03 04 05 06 07 08 09 10 11 12; do echo "SN-$i,unit$i.csv,ax,temp"; done
} >"$T/m/lot.csv"
run "a manifest" 0 lot --format json "$T/m/lot.csv"
json_check "manifest: names, the outlier by name" "$T/out" '[.units[].unit][6] == "SN-07" and .outliers[0].unit == "SN-07" and (.units | length) == 12'
jq -S '[.between[] | del(.outliers)]' "$T/out" >"$T/m1.json" 2>/dev/null
jq -S '[.between[] | del(.outliers)]' "$T/sample.json" >"$T/m2.json" 2>/dev/null
if cmp -s "$T/m1.json" "$T/m2.json"; then ok "manifest: the files' numbers"; else not_ok "manifest: the files' numbers"; fi
run "--manifest" 0 lot --format json --manifest "$T/m/lot.csv"
json_check "--manifest: the same units" "$T/out" '[.units[].unit][6] == "SN-07" and (.units | length) == 12'
printf 'unit,file\nA,unit01.csv\nB,\n' >"$T/m/bad.csv"
run "manifest: a unit without a file" 1 lot "$T/m/bad.csv"
one_line_error "manifest: a unit without a file"
has "manifest: names the line" "$T/err" 'bad\.csv: line 3: a unit and a file are needed'
printf 'unit,file,temperature\nA,unit01.csv,temp\nB,unit02.csv,tc\nC,unit03.csv,temp\n' >"$T/m/badt.csv"
run "manifest: a temperature column that is not there" 1 lot "$T/m/badt.csv"
one_line_error "manifest: a temperature column that is not there"
run "text: each unit's bias" 0 lot "$L"/unit0[1-7].csv
has "text: unit07's bias marked" "$T/out" '^unit07\.csv +[0-9.]+ \[[0-9.]+, [0-9.]+\] \*'
cut -d, -f1,2 "$L/unit02.csv" >"$T/notemp.csv"
run "a unit without the temperature column" 1 lot "$L/unit01.csv" "$T/notemp.csv" "$L/unit03.csv"
one_line_error "a unit without the temperature column"
has "says which" "$T/err" 'notemp\.csv: no temperature column, but .*unit01\.csv has one'
cut -d, -f1,2 "$L/unit01.csv" >"$T/notemp1.csv"
cut -d, -f1,2 "$L/unit03.csv" >"$T/notemp3.csv"
run "no temperature anywhere: no sensitivity" 0 lot --format json "$T/notemp1.csv" "$T/notemp.csv" "$T/notemp3.csv"
json_check "no temperature: said, no number" "$T/out" '(.between[] | select(.term == "temp_sensitivity") | .why == "no temperature column: no temperature sensitivity") and ([.units[].channels[0].temperature] | all(. == null))'
run "--smooth 0" 2 lot --smooth 0 "$L"/unit0[1-3].csv
one_line_error "--smooth 0"
run "--smooth longer than the record" 1 lot --smooth 20000 --plot "$T/x.svg" "$L"/unit0[1-3].csv
one_line_error "--smooth longer than the record"

# a lot whose units show bias instability: their drift and sensitivity
# intervals come from the noise model (the block means correlated), not
# marked too narrow (a doubt names only K, the term not shown); the
# text's legend of the mark
printf '[sensor]\nnoise_density = 20 ug/sqrt(Hz)\nbias_instability = 50 ug\nbias = 1 mg\nbias_tempco = 50 ug/degC\n' >"$T/flk.ini"
for i in 1 2 3; do
	run "simulate flicker unit $i" 0 simulate -q --sensor "$T/flk.ini" --rate 10 --duration 2h --names ax -u g --temp-cycle 21:26:7200 --seed $i -o "$T/flk$i.csv"
done
run "lot with flicker" 0 lot --format json "$T"/flk[1-3].csv
json_check "drift and sensitivity from the noise model where B is shown, not doubted" "$T/out" '[.units[].channels[0] | select(.terms.B.present) | (.terms.bias_drift.se_from == "noise model" and .terms.temp_sensitivity.se_from == "noise model" and ([.terms.bias_drift.doubt, .terms.temp_sensitivity.doubt] | map(. // "" | test("correlated|flicker")) | any | not))] | length == 3 and all'
run "lot with flicker, text" 0 lot "$T"/flk[1-3].csv
has "the mark's legend" "$T/out" '~ doubtful, why below'
# the sample lot's units (bias instability 8 ug): a unit is flagged only
# where its block means' residuals are correlated (lag 1 above 1.645 /
# sqrt(20)) and its noise model shows neither B nor K, with that reason,
# or where its conservative se exceeds the reported one 1.5 times
run "sample lot: flags from the residuals" 0 lot --format json "$L"
json_check "flagged units: correlated residuals, drift and sensitivity only" "$T/out" \
	'[.units[].channels[] | . as $c | .terms | to_entries[] | select(.value.doubt) | (.key == "bias_drift" or .key == "temp_sensitivity") and (($c.residual_lag1 > 0.3678 and (.value.doubt | test("residuals are correlated"))) or (.value.se_upper > 1.5 * .value.se and (.value.doubt | test("cannot rule out"))))] | all'
json_check "units with uncorrelated residuals unflagged" "$T/out" \
	'[.units[].channels[] | select(.residual_lag1 <= 0.3678) | .terms[] | select(.doubt and ((.se_upper > 1.5 * .se) | not))] | length == 0'
json_check "conservative se flagged exactly above 1.5 times the reported" "$T/out" \
	'[.units[].channels[] | select(.residual_lag1 <= 0.3678) | .terms.bias_drift, .terms.temp_sensitivity | (.doubt != null) == (.se_upper > 1.5 * .se)] | all'

# bad input
run "two units" 2 lot "$T/unit1.csv" "$T/unit2.csv"
one_line_error "two units"
run "bad --ci" 2 lot --ci 2 "$T"/unit[1-3].csv
one_line_error "bad --ci"
# CSV: one row per unit, channel and term, the JSON's numbers; the
# report folder: the lot's page, a page per unit, the JSON equal to
# --format json's, never into a folder that holds something
run "csv" 0 lot --format csv "$L"/unit*.csv
[ "$(wc -l <"$T/out")" -eq 73 ] && ok "csv: 12 units x 6 terms and a header" || not_ok "csv: 12 units x 6 terms and a header"
has "csv: header" "$T/out" '^unit,path,channel,term,value,lo,hi,value_unit,se,present,z,outlier,limit,verdict,doubt,se_upper$'
has "csv: the outlier's bias" "$T/out" '^unit07.csv,.*,ax,bias,1822\.[0-9]*,.*,ug,.*,yes,[0-9.]*,yes,,,,$'
n1=$(jq -r '.units[0].channels[0].terms.N.value' "$T/sample.json" 2>/dev/null)
n2=$(awk -F, '$1 == "unit01.csv" && $4 == "N" { print $5 }' "$T/out")
awk -v a="$n1" -v b="$n2" 'BEGIN { exit !(b != "" && (a - b) ^ 2 <= (1e-9 * a) ^ 2) }' &&
	ok "csv: unit01's N is the JSON's ($n2)" || not_ok "csv: unit01's N is the JSON's ($n1 / $n2)"
run "report" 0 lot --report "$T/rep" --format json "$L"/unit*.csv
for f in index.html lot.json lot.csv lot.svg lot-adev.svg units/unit-0.html units/unit-11.html; do
	[ -s "$T/rep/$f" ] && ok "report: $f" || not_ok "report: $f"
done
cmp -s "$T/rep/lot.json" "$T/sample.json" && ok "report: its lot.json is --format json's" ||
	not_ok "report: its lot.json is --format json's"
has "report: the lot's page links each unit" "$T/rep/index.html" 'href="units/unit-6.html">unit07.csv</a>'
has "report: the outlier marked on its page" "$T/rep/units/unit-6.html" 'OUTLIER \(z 7'
has "report: figures inline" "$T/rep/index.html" '<svg'
run "report into a folder that holds something" 1 lot --report "$T/rep" "$L"/unit*.csv
one_line_error "report into a folder that holds something"
sed '1s/gx/gy/' "$T/unit1.csv" >"$T/other.csv"
run "a unit without the first's channel" 1 lot "$T/unit1.csv" "$T/unit2.csv" "$T/other.csv"
one_line_error "a unit without the first's channel"
has "names the channel" "$T/err" "no channel 'gx'"
run "a missing unit" 1 lot "$T/unit1.csv" "$T/unit2.csv" "$T/none.csv"
one_line_error "a missing unit"

# four units and a stuck one (every sample 1 mg): the stuck unit said,
# K's interval (three units) cut at 0
mkdir -p "$T/stuck"
cp "$SAMPLES/lot/unit01.csv" "$SAMPLES/lot/unit02.csv" "$SAMPLES/lot/unit03.csv" \
	"$SAMPLES/lot/unit04.csv" "$T/stuck/"
awk -F, 'NR == 1 { print; next } { print $1 ",0.001,20" }' "$SAMPLES/lot/unit01.csv" \
	>"$T/stuck/unit05.csv"
run "lot with a stuck unit" 0 lot "$T/stuck"
has "the stuck unit: said" "$T/out" "unit05.csv +constant record: every sample 1000 ug \(a stuck sensor\?\): left out of every spread"
has "K: the interval cut at 0" "$T/out" "K +ug/sqrt\(h\) +[0-9.]+ \[0 \(cut\), "
has "the cut explained" "$T/out" "^\(cut\): the interval's lower end cut at 0"
lacks "no negative interval" "$T/out" "\[-"
# a manifest with a misnamed column, and one naming a unit twice
printf 'unit,path\nA,%s\nB,%s\nC,%s\n' "$SAMPLES/lot/unit01.csv" "$SAMPLES/lot/unit02.csv" \
	"$SAMPLES/lot/unit03.csv" >"$T/badcol.csv"
run "lot manifest without a file column" 1 lot "$T/badcol.csv"
has "the file column named" "$T/err" "a manifest names its columns unit and file .*no column 'file'"
printf 'unit,file\nA,%s\nA,%s\nC,%s\n' "$SAMPLES/lot/unit01.csv" "$SAMPLES/lot/unit02.csv" \
	"$SAMPLES/lot/unit03.csv" >"$T/twice.csv"
run "lot manifest naming a unit twice" 1 lot "$T/twice.csv"
has "the unit named twice: said" "$T/err" "line 3: unit 'A' is named twice"
# the bundled lot's report: its outlier and doubtful intervals among the
# checks, never "Nothing flagged"
run "the bundled lot's scene" 0 run -q -o "$T/lot-sample" "$SAMPLES/lot.scene.ini"
has "report: the outlier unit flagged" "$T/lot-sample/report.html" 'Outlier unit\.</strong> unit07\.csv: ax bias lies [0-9.]+ standard deviations'
has "report: the doubtful intervals flagged" "$T/lot-sample/report.html" 'Doubtful intervals\.</strong> [0-9]+ intervals'
lacks "report: not 'Nothing flagged'" "$T/lot-sample/report.html" 'Nothing flagged'
json_check "report summary: each file's rate names its file" "$T/lot-sample/report.json" '[.summary[] | select(.quantity == "sample rate" and .channel == "unit12.csv")] | length == 1'

run "the bundled lot, text" 0 lot "$SAMPLES"/lot/unit*.csv
has "lot text: terms in words" "$T/out" '^ax +bias drift +ug/h '
has "lot text: temperature sensitivity in words" "$T/out" '^ax +temp sensitivity +ug/degC '
lacks "lot text: no JSON keys" "$T/out" 'bias_drift|temp_sensitivity'

done_testing
