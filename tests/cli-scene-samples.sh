#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope run and report, second half (the first is cli-scene.sh):
# every sample scene runs, and the report of a capture with its outputs,
# its resolved terms and the HTML in a headless browser.
. "$(dirname "$0")/lib.sh"

cp "$SAMPLES/gyro-static.csv" "$T/"

# every sample scene runs
for sc in "$SAMPLES"/*.scene.ini; do
	b=$(basename "$sc" .scene.ini)
	run "sample scene $b" 0 run -o "$T/sample-$b" "$sc"
	if [ -s "$T/sample-$b/report.json" ]; then ok "$b: report.json"; else not_ok "$b: report.json"; fi
done
json_check "inclino scene: within 0.1 deg calibrated, not uncompensated" "$T/sample-inclino/inclino.json" '.validation.max_deg < 0.1 and .validation.uncompensated_max_deg > 0.3'

run "report --format json refused" 2 report --format json "$T/gyro-static.csv"
one_line_error "report --format json refused"

if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "report" 0 report -o "$T/rep" "$T/gyro-static.csv"
	for f in report.html report.json report.txt info.png allan.png psd.png allan.json; do
		if [ -s "$T/rep/$f" ]; then ok "report wrote $f"; else not_ok "report wrote $f"; fi
	done
	# the resolved terms (N on every axis; B, K where the hour resolves
	# them) with their intervals
	json_check "summary has the resolved terms of each axis with intervals" "$T/rep/report.json" \
		'[.summary[] | select(.stage == "allan")] as $a | ([$a[] | select(.quantity == "angle random walk N")] | length) == 3 and ($a | all(.lo != null and .hi != null and .lo <= .value and .value <= .hi))'
	json_check "N near the sample's 0.15 deg/sqrt(h)" "$T/rep/report.json" \
		'[.summary[] | select(.quantity == "angle random walk N") | .value] | all(. > 0.14 and . < 0.16)'
	has "report text has the Allan section" "$T/rep/report.txt" '^== Allan deviation'
	# the HTML in a real browser: every image decodes, no console errors
	BROWSER=$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)
	if ! long_tier; then
		skip "browser laid out the inline figures" "$LONG_ONLY"
		skip "no console messages" "$LONG_ONLY"
		skip "browser screenshot" "$LONG_ONLY"
	elif [ -n "$BROWSER" ]; then
		HOME="$T" timeout 120 "$BROWSER" --headless=new --no-sandbox --disable-gpu \
			--enable-logging=stderr --v=0 --user-data-dir="$T/chr" \
			--dump-dom "file://$T/rep/report.html" >"$T/dom" 2>"$T/chr.err"
		n=$(grep -c '<figure>' "$T/rep/report.html")
		if [ "$n" -ge 3 ] && grep -q "data-figures=\"$n figures, min text [0-9.]* px, 0 overlaps" "$T/dom"; then
			ok "browser laid out the $n inline figures"
		else
			not_ok "browser laid out the $n inline figures"
			grep -o 'data-figures="[^"]*"' "$T/dom" | diag
		fi
		lacks "no console messages" "$T/chr.err" 'CONSOLE'
		HOME="$T" timeout 120 "$BROWSER" --headless=new --no-sandbox --disable-gpu \
			--user-data-dir="$T/chr" --window-size=1200,1600 \
			--screenshot="$T/shot.png" "file://$T/rep/report.html" >/dev/null 2>&1
		if [ "$(od -An -tx1 -N8 "$T/shot.png" 2>/dev/null | tr -d ' \n')" = 89504e470d0a1a0a ]; then
			ok "browser screenshot"
		else
			not_ok "browser screenshot"
		fi
	else
		skip "browser laid out the inline figures" "no chromium"
		skip "no console messages" "no chromium"
		skip "browser screenshot" "no chromium"
	fi
else
	run "report without OpenCV" 0 report -o "$T/rep" "$T/gyro-static.csv"
	if [ -s "$T/rep/report.html" ]; then ok "HTML without figures"; else not_ok "HTML without figures"; fi
fi

done_testing
