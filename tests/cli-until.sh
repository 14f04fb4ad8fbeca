#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# acquire --until on the simulator (gyro with bias instability, paced 500x
# faster than real time): the recording stops once the fit resolves B to
# the width, before the --duration cap; the file is complete (every sample
# the summary counts, the end line) and its own fit shows B present; the
# stop comes near the plan's 50 % length (within a factor 3: one run of a
# random stopping time); usage errors.
. "$(dirname "$0")/lib.sh"

cat >"$T/u.ini" <<'INI'
[sensor]
name = until test
noise_density = 0.2 deg/sqrt(h)
bias_instability = 5 deg/h
INI
sim="sim:rate=10,channels=1,arw=0.2deg/sqrt(h),bi=5deg/h,speed=500,seed=4"

run "--until without --duration" 2 acquire --source "$sim" --until B:25% -o "$T/a.csv"
one_line_error "--until without --duration"
run "--until bad term" 2 acquire --source "$sim" --until X:25% --duration 1h -o "$T/a.csv"
one_line_error "--until bad term"
run "--until bad width" 2 acquire --source "$sim" --until B:0% --duration 1h -o "$T/a.csv"
run "--until unknown channel" 2 acquire --source "$sim" --until az:B:25% --duration 1h -o "$T/a.csv"
one_line_error "--until unknown channel"
run "sim bad bi" 2 acquire --source "sim:bi=-1" --duration 1 -o "$T/a.csv"

run "until B:25%" 0 acquire --format json --source "$sim" --until gx:B:25% --duration 4h -o "$T/u.csv"
json_check "stopped by until, before the cap, resolved" "$T/out" \
	'.stop == "until" and .duration_s < 14400 and .until.reached and .until.rel_half_width <= 0.25 and .until.fits >= 1 and .until.term == "B"'
has "progress on stderr" "$T/err" "gx after .*: B to [0-9.]+ % \(wanted 25.0 %\): resolved, stopping"
ss info --format json "$T/u.csv" >"$T/info.json" 2>"$T/err"
if command -v jq >/dev/null 2>&1; then
	n=$(jq '.samples' "$T/out")
	rows=$(jq '.rows' "$T/info.json")
	if [ "$n" = "$rows" ] && [ "$n" -gt 600 ]; then ok "the file holds every sample recorded ($rows rows)"
	else not_ok "the file holds $rows rows, the summary $n samples"; fi
fi
has "the file is complete (end line)" "$T/u.csv" "^# end: [0-9]+ samples"
run "allan on the file" 0 allan --format json "$T/u.csv"
json_check "the file's fit shows B present" "$T/out" '.channels[0].noise.B.fitted'
run "plan at 50 %" 0 plan --sensor "$T/u.ini" --rate 10 --resolve B:25% --probability 0.5 --format json
if command -v jq >/dev/null 2>&1; then
	p50=$(jq '.terms[0].needed_s' "$T/out")
	d=$(ss acquire --format json --source "$sim" --until gx:B:25% --duration 4h -o "$T/u2.csv" 2>/dev/null | jq '.until.fitted_s')
	if awk "BEGIN { exit !($d > $p50 / 3 && $d < 3 * $p50) }"; then ok "stopped at $d s of data, the plan's 50 % length $p50 s"
	else not_ok "stopped at $d s of data, the plan's 50 % length $p50 s"; fi
fi
done_testing
