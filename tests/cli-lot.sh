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
json_check "B and K: not shown, no spread and no number" "$T/out" '[.between[] | select(.term != "N") | .why != null and .between_sd == null] | all'
run "lot text" 0 lot "$T"/unit[1-7].csv
has "text: N row with the outlier" "$T/out" '^gx +N +deg/sqrt\(h\) .*unit7\.csv \(z '
has "text: K says why" "$T/out" '^gx +K .*fewer than 3, no spread'

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

# bad input
run "two units" 2 lot "$T/unit1.csv" "$T/unit2.csv"
one_line_error "two units"
run "bad --ci" 2 lot --ci 2 "$T"/unit[1-3].csv
one_line_error "bad --ci"
run "csv refused" 2 lot --format csv "$T"/unit[1-3].csv
one_line_error "csv refused"
sed '1s/gx/gy/' "$T/unit1.csv" >"$T/other.csv"
run "a unit without the first's channel" 1 lot "$T/unit1.csv" "$T/unit2.csv" "$T/other.csv"
one_line_error "a unit without the first's channel"
has "names the channel" "$T/err" "no channel 'gx'"
run "a missing unit" 1 lot "$T/unit1.csv" "$T/unit2.csv" "$T/none.csv"
one_line_error "a missing unit"

done_testing
