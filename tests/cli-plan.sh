#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope plan: a sensor spec, a datasheet and a pilot capture; the
# JSON's keys and their relations (the needed length between the lengths
# where the probability is below and above the wanted one); a term the
# model lacks is "never" with the reason; usage and file errors.  The
# predictions themselves are checked against simulation in tests/test-plan.c
# and make bench (tests/bench-plan.c).
. "$(dirname "$0")/lib.sh"

S=$top_srcdir/samples
run "plan --help" 0 plan --help
has "help names --resolve" "$T/out" "--resolve"
run "no sensor" 2 plan --resolve B:25%
one_line_error "no sensor"
run "no wish" 2 plan --sensor "$S/gyro-mems-250.ini" --rate 10
one_line_error "no wish"
run "spec without --rate" 2 plan --sensor "$S/gyro-mems-250.ini" --resolve B:25%
one_line_error "spec without --rate"
run "bad term" 2 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve X:25%
one_line_error "bad term"
run "bad width" 2 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:-5%
run "bad probability" 2 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:25% --probability 1.5
run "both sources" 2 plan --sensor "$S/gyro-mems-250.ini" --pilot "$S/gyro-static.csv" --resolve B:25%
run "a spec and a pilot operand" 2 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:25% "$S/gyro-static.csv"
one_line_error "a spec and a pilot operand"
run "two pilots" 2 plan --pilot "$S/gyro-static.csv" --resolve B:25% "$S/gyro-static.csv"
run "two operands" 2 plan --resolve B:25% "$S/gyro-static.csv" "$S/gyro-static.csv"
run "csv refused" 2 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:25% --format csv
run "missing spec" 1 plan --sensor "$T/none.ini" --rate 10 --resolve B:25%
one_line_error "missing spec"

run "spec, json" 0 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:10%,K:30%,R:50% --lengths 0.5h,1h,2h,6h,12h --format json
json_check "shape" "$T/out" '.command == "plan" and .source == "sensor spec" and .rate_hz == 10 and (.terms | map(.term)) == ["B","K","R"] and all(.terms[]; (.lengths | map(.length_s)) == [1800,3600,7200,21600,43200])'
json_check "probabilities in [0, 1], rising with the length" "$T/out" \
	'all(.terms[]; [.lengths[].probability] as $p | all($p[]; . >= 0 and . <= 1) and ($p == ($p | sort)))'
json_check "the probability is the smaller of presence and width" "$T/out" \
	'all(.terms[].lengths[]; .probability <= .p_present and .probability <= .p_width)'
json_check "needed between the lengths below and above 90 %" "$T/out" \
	'all(.terms[] | select(.needed_s != null); . as $t | all(.lengths[]; (.probability < 0.9 and .length_s < $t.needed_s) or (.probability >= 0.9 and .length_s >= $t.needed_s / 1.01)))'
json_check "a spec: no pilot range" "$T/out" 'all(.terms[]; has("needed_range_s") | not)'
json_check "R never, with the reason" "$T/out" \
	'(.terms[2] | .needed_s == null and (.never | test("no R")) and all(.lengths[]; .probability == 0))'
json_check "the model in the contract's coefficient shape" "$T/out" \
	'.noise.B.unit == "deg/h" and ((.noise.B.value - 4) | fabs) < 1e-9 and .noise.R.fitted == false'
run "spec, text" 0 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:10%,R:50%
has "text: never with the reason" "$T/out" "^R .*never +the sensor spec has no R"
has "text: header" "$T/out" "^term +target +needed"

run "looser probability" 0 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:10% --probability 0.5 --format json
cp "$T/out" "$T/p50.json"
run "default probability" 0 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:10% --format json
if command -v jq >/dev/null 2>&1; then
	a=$(jq '.terms[0].needed_s' "$T/p50.json")
	b=$(jq '.terms[0].needed_s' "$T/out")
	if awk "BEGIN { exit !($a < $b) }"; then ok "50 % needs less than 90 % ($a s < $b s)"
	else not_ok "50 % needs less than 90 % ($a s, $b s)"; fi
fi

run "datasheet" 0 plan --sensor "$S/datasheets/stim300.ini" --rate 10 --resolve B:25%,K:30% --format json
json_check "datasheet: gyro section, K never" "$T/out" \
	'.source == "datasheet" and .name == "STIM300 gyro" and .terms[0].needed_s > 0 and (.terms[1].never | test("datasheet gives no K"))'
run "datasheet accel" 0 plan --sensor "$S/datasheets/stim300.ini" --section accel --rate 10 --resolve N:5% --format json
json_check "datasheet: accel section" "$T/out" '.name == "STIM300 accel" and .noise.N.si_unit == "m/s^2/sqrt(Hz)"'

# a pilot: the samples' static gyro record, first channel
run "pilot" 0 plan --pilot "$S/gyro-static.csv" --resolve N:5% --lengths 600 --format json
json_check "pilot: its rate and length" "$T/out" '.source == "pilot" and .rate_hz > 0 and .pilot_s > 0 and .terms[0].needed_s > 0'
json_check "pilot: the needed length's range from the pilot's interval" "$T/out" \
	'.terms[0].needed_range_level > 0.68 and .terms[0].needed_range_level < 0.69 and (.terms[0].needed_range_s | length == 2 and .[0] > 0 and .[0] <= .[1])'
cp "$T/out" "$T/pilot.json"
run "pilot as the operand" 0 plan --resolve N:5% --lengths 600 --format json "$S/gyro-static.csv"
if cmp -s "$T/out" "$T/pilot.json"; then ok "operand: the same JSON as --pilot"; else not_ok "operand: the same JSON as --pilot"; fi
run "pilot, text" 0 plan --pilot "$S/gyro-static.csv" --resolve B:25% --lengths 3600
if grep -q "the needed length as the term moves within the pilot's 68.3 % interval" "$T/out" &&
   grep -Eq '^B +25% +[0-9.]+ (h|min) \.\. [0-9.]+ (h|min)' "$T/out"; then ok "pilot, text: the range"
else not_ok "pilot, text: the range"; fi

# the figure: each wish's probability against the length
run "plot" 0 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:25%,K:30% --plot "$T/plan.svg"
if grep -q '<svg' "$T/plan.svg" 2>/dev/null && grep -q "K to ±30" "$T/plan.svg"; then ok "plan.svg with a curve per wish"; else not_ok "plan.svg"; fi
run "plot, json" 0 plan --sensor "$S/gyro-mems-250.ini" --rate 10 --resolve B:25%,K:30% --format json
cp "$T/out" "$T/spec.json"

# a scene: [plan] with the scene's [sensor] and no capture, then with a
# capture as the pilot: the stage's JSON is the command's
printf '[sensor]\nspec = %s\n[input]\nrate = 10\n[plan]\nresolve = B:25%%,K:30%%\n[report]\nformats = json\n' \
	"$S/gyro-mems-250.ini" >"$T/sp.ini"
run "scene: plan from the sensor" 0 run "$T/sp.ini" -o "$T/sp" -q
json_check "scene: the sensor's plan" "$T/sp/plan.json" '.command == "plan" and .source == "sensor spec" and (.terms | length) == 2'
json_check "scene: the same numbers as the command" "$T/sp/plan.json" "[.terms[].needed_s] == $(jq -c '[.terms[].needed_s]' "$T/spec.json" 2>/dev/null || echo null)"
json_check "scene: summary rows in hours" "$T/sp/report.json" '[.summary[] | select(.stage == "plan")] | length == 2 and all(.unit == "h")'
printf '[input]\nfiles = %s\n[plan]\nresolve = N:5%%\nlengths = 600\n[report]\nformats = json\n' \
	"$S/gyro-static.csv" >"$T/pp.ini"
run "scene: plan from a pilot" 0 run "$T/pp.ini" -o "$T/pp" -q
run "the command as the scene runs it" 0 plan --resolve N:5% --lengths 600 --format json -o "$T/pp-cmd.json" "$S/gyro-static.csv"
if command -v jq >/dev/null 2>&1; then
	if [ "$(jq -S . "$T/pp/plan.json")" = "$(jq -S . "$T/pp-cmd.json")" ]; then ok "scene: the pilot's plan equals the command's"
	else not_ok "scene: the pilot's plan equals the command's"; fi
fi
printf '[plan]\nresolve = N:5%%\n[report]\nformats = json\n' >"$T/none.ini"
run "scene: neither sensor nor capture" 2 run "$T/none.ini" -o "$T/none" -q
one_line_error "scene: neither sensor nor capture"
# lengths beyond the planner, a search cut short, an angle as the pilot
G="$SAMPLES/gyro-mems-250.ini"
run "plan --lengths 1e308" 2 plan --sensor "$G" -r 100 --resolve B:25% --lengths 1e308
has "1e308 s: more than 1e15 samples" "$T/err" "a record of 1e\+308 s at 100 Hz holds more than 1e15 samples"
lacks "no doubled prefix" "$T/err" "plan: plan:"
run "plan --max-length 1min" 0 plan --sensor "$G" -r 100 --resolve B:10% --max-length 1min
has "beyond the search: '> 60 s', not never" "$T/out" "^B +10% +> 60 s .*\(the search ends at --max-length\)"
awk 'BEGIN { print "# rate: 100 Hz"; print "th [deg]"; for (i = 0; i < 2000; i++) print i * 0.001 }' >"$T/angle.csv"
run "plan --pilot of an angle" 1 plan --pilot "$T/angle.csv" --resolve N:25%
has "an angle pilot: said" "$T/err" "channel th is in deg \(an angle: .*a pilot is a record of angular rate or acceleration"
done_testing
