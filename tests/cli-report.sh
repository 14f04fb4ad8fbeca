#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The report as a document: the quick-start report of the README (report
# samples/gyro-static.csv) has its results in tables, figures inline as
# SVG, formulas in MathML, print CSS and the summary on the terminal; in a
# headless browser at 1280 px no figure text is under 10 px and no legend
# or note box overlaps a plot area, and at the A4 column (703 px) none is
# under 7 px; it prints to PDF.  The thermal scene's rejected fits show in
# the text, JSON and HTML; a white-noise capture lists no peak; a clipped
# capture and a record too short to measure a term are flagged.  The pages
# and the PDF a reviewer looks at are left in tests/ of the build tree
# (report-1280.png, report-print.png, report.pdf).
. "${top_srcdir:-$(dirname "$0")/..}/tests/lib.sh"
: "${PYTHON3:=python3}"
: "${top_builddir:=$top_srcdir}"

R="$T/rep"
run "quick-start report" 0 report -o "$R" "$SAMPLES/gyro-static.csv"
has "terminal: the summary table" "$T/out" '^section/channel +quantity +value +interval +unit +note$'
has "terminal: gx's random walk with its interval" "$T/out" \
	'^allan/gx +angle random walk N +0\.1[45][0-9]* +\[0\.1[45][0-9]*, 0\.1[45][0-9]*\] +deg/sqrt\(h\)'
H="$R/report.html"
has "summary in a table" "$H" '<table class="summary">'
has "noise terms in tables with a status" "$H" '<td class="ok">resolved</td>'
has "info in a table" "$H" '<table class="info">'
has "figures inline as SVG" "$H" '^<svg xmlns="http://www.w3.org/2000/svg"'
has "a link to each figure alone" "$H" '<a href="allan.svg">Open the figure alone</a>'
has "formulas in MathML" "$H" '<math display="block">'
has "each section links its definitions" "$H" '<a href="#def-allan">'
has "definitions are there" "$H" '<dt id="def-allan">'
has "print style" "$H" '@media print\{'
if [ "$(grep -c '<pre>' "$H")" = "$(grep -c '<details>' "$H")" ]; then
	ok "command-line text only in collapsed details"
else
	not_ok "command-line text only in collapsed details"
fi
lacks "no network resource" "$H" '(src|href)="https?:'
for f in info allan psd; do
	if [ -s "$R/$f.svg" ]; then ok "report wrote $f.svg"; else not_ok "report wrote $f.svg"; fi
done
if command -v "$PYTHON3" >/dev/null 2>&1; then
	if "$PYTHON3" "$top_srcdir/tests/svgcheck.py" "$R"/*.svg >"$T/check" 2>&1; then
		ok "report figures: $(tr '\n' ';' <"$T/check")"
	else
		not_ok "report figures"
		diag "$T/check"
	fi
else
	skip "report figures" "python3 not installed"
fi

# the thermal scene: fits rejected, said in text, JSON and HTML
run "thermal scene" 0 run -o "$T/th" "$SAMPLES/thermal.scene.ini"
has "thermal: terminal warning" "$T/out" '^  warning: ax: fit rejected: chi2'
has "thermal: text warning" "$T/th/report.txt" '^  warning: ax: fit rejected: chi2'
json_check "thermal: JSON fits rejected, summary rows flagged" "$T/th/report.json" \
	'(.results.allan.channels | map(.fit.rejected) | all) and
	 ([.summary[] | select(.stage == "allan") | .status == "warning"] | all)'
has "thermal: HTML banner" "$T/th/report.html" '<div class="banner warn" role="note"><strong>Fit rejected.</strong> ax: fit rejected'
has "thermal: HTML table status" "$T/th/report.html" '<td class="warn">fitted, model rejected</td>'

# white noise: no peak stands out, so no "strongest peak"
printf '[sensor]\nname = white\nnoise_density = 0.2 deg/sqrt(h)\n' >"$T/white.ini"
run "white-noise capture" 0 simulate --sensor "$T/white.ini" --rate 100 --duration 600 --axes 3 -o "$T/white.csv"
run "white-noise report" 0 report -o "$T/wn" "$T/white.csv"
json_check "white noise: no strongest peak, no peak" "$T/wn/report.json" \
	'([.summary[] | select(.quantity == "strongest peak")] | length == 0) and ([.results.psd.channels[].peaks | length] | all(. == 0))'
has "white noise: the HTML says no line" "$T/wn/report.html" 'No spectral line.'
lacks "white noise: no strongest peak in the terminal" "$T/out" 'strongest peak'

# a capture driven into its range: clipped, said in text, JSON, the
# summary and a banner; a sample that is not clipped says nothing
printf '[sensor]\nname = small range\nrange = 100 deg/s\nnoise_density = 0.2 deg/sqrt(h)\n' >"$T/clip.ini"
run "clipped capture" 0 simulate --sensor "$T/clip.ini" --rate 200 --duration 60 --tone 3.1:120 -o "$T/clip.csv"
run "clipped: info" 0 info "$T/clip.csv"
has "clipped: text warning" "$T/out" '^  warning: gx: clipped: [0-9]+ samples \([0-9.]+ %\) sit at its smallest value -100 deg/s or its largest 100 deg/s'
run "clipped: info JSON" 0 info --format json "$T/clip.csv"
json_check "clipped: JSON counts and warning" "$T/out" \
	'(.channels[0].clipped | .low > 1000 and .high > 1000) and (.warnings[0].code == "clipped")'
run "clipped: report" 0 report -o "$T/cr" "$T/clip.csv"
has "clipped: terminal summary flagged" "$T/out" '^info/gx +clipped samples +[0-9]+ +\[!\] at the end of the range'
has "clipped: HTML banner" "$T/cr/report.html" '<strong>Clipped data.</strong> gx: clipped'
run "not clipped: info JSON" 0 info --format json "$SAMPLES/gyro-static.csv"
json_check "not clipped: counts 0, no warning" "$T/out" \
	'([.channels[].clipped | .low + .high] | add == 0) and (has("warnings") | not)'

# a record too short to measure anything: said, and the analyses it
# refused are listed among the checks
head -n 200 "$SAMPLES/gyro-static.csv" >"$T/short.csv"
run "short record: report" 0 report -o "$T/sr" "$T/short.csv"
# 197 samples of white rate noise measure N (the presence test keeps it,
# its interval clear of 0) and only bound the other terms
has "short record: N with its interval" "$T/out" '^allan/gx +angle random walk N .*fit, 68\.3 % interval'
json_check "short record: N measured, the other terms bounded" "$T/sr/report.json" \
	'[.results.allan.channels[].noise | .N.resolved and ([.Q, .B, .K, .R][] | (.present | not) and (.bound == null or .bound > 0))] | all'
# a term not shown present says why, in the table and on the figure, and
# no bound is ever 0 or negative
has "short record: the table says why a term is only bounded" "$T/sr/report.html" \
	'<td>not shown present: the fit without it describes the curve \(presence test not passed\)</td>'
has "short record: the figure says 'not shown present'" "$T/sr/allan.svg" '&lt; [^<]* \(not shown present\)'
for f in "$T/out" "$T/sr/report.txt" "$T/sr/report.html"; do
	lacks "short record: no bound at or below 0 ($(basename "$f"))" "$f" 'below (-|0([^.0-9]|$)|0\.0*([^0-9]|$))'
done
has "short record: refused analysis listed" "$T/sr/report.html" '<strong>Not in the report.</strong> Random-walk fan: inferred, but refused by the data'
lacks "short record: nothing claims all is well" "$T/sr/report.html" 'Nothing flagged'
json_check "short record: the spectrum of the record (one segment), said" "$T/sr/report.json" \
	'(.results.psd.channels | length == 3) and (.results.psd.warnings[0].code == "too_few_samples")'
has "short record: the spectrum's banner" "$T/sr/report.html" '<strong>Too few samples.</strong> [^<]*short.csv: 197 samples, fewer than one segment of 256'

# a real browser at 1280 px and at the A4 column, and printed
BROWSER=$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)
# chrome K ARGS...: one headless run with a fresh profile $T/chrK
chrome() {
	k=$1
	shift
	HOME="$T" timeout 180 "$BROWSER" --headless --no-sandbox --disable-gpu \
		--disable-quic --no-first-run --disable-background-networking \
		--disable-component-update --disable-sync \
		--user-data-dir="$T/chr$k" "$@" 2>/dev/null
}
if ! long_tier; then
	for t in "at 1280 px" "at the A4 column" "screenshot" "printed"; do
		skip "$t" "$LONG_ONLY"
	done
elif [ -n "$BROWSER" ]; then
	chrome 1 --window-size=1280,1000 --dump-dom "file://$H" >"$T/dom1280"
	f=$(grep -o 'data-figures="[^"]*"' "$T/dom1280")
	# data-figures="N figures, min text X px, K overlaps, T tables, ..."
	if echo "$f" | awk '{ sub(/.*min text /, ""); split($0, a, " "); exit !(a[1] >= 10) }' &&
		echo "$f" | grep -q "\"$(grep -c '<figure>' "$H") figures, .* 0 overlaps, [0-9]* tables"; then
		ok "at 1280 px: $f"
	else
		not_ok "at 1280 px: $f"
	fi
	chrome 2 --window-size=718,1000 --dump-dom "file://$H" >"$T/dom703"
	f=$(grep -o 'data-figures="[^"]*"' "$T/dom703")
	if echo "$f" | awk '{ sub(/.*min text /, ""); split($0, a, " "); exit !(a[1] >= 7) }' &&
		echo "$f" | grep -q '0 overlaps.*width 70[0-9]\"'; then
		ok "at the A4 column: $f"
	else
		not_ok "at the A4 column: $f"
	fi
	chrome 3 --window-size=1280,4000 --hide-scrollbars \
		--screenshot="$top_builddir/tests/report-1280.png" "file://$H" >/dev/null
	chrome 4 --window-size=718,4000 --hide-scrollbars \
		--screenshot="$top_builddir/tests/report-print.png" "file://$H" >/dev/null
	if [ "$(od -An -tx1 -N8 "$top_builddir/tests/report-1280.png" 2>/dev/null | tr -d ' \n')" = 89504e470d0a1a0a ]; then
		ok "screenshot tests/report-1280.png"
	else
		not_ok "screenshot tests/report-1280.png"
	fi
	chrome 5 --no-pdf-header-footer --print-to-pdf="$top_builddir/tests/report.pdf" "file://$H" >/dev/null
	pages=$(grep -ao '/Count [0-9]*' "$top_builddir/tests/report.pdf" 2>/dev/null | head -n 1 | cut -d' ' -f2)
	if [ "$(head -c 5 "$top_builddir/tests/report.pdf" 2>/dev/null)" = "%PDF-" ] && [ "${pages:-0}" -ge 2 ]; then
		ok "printed to tests/report.pdf ($pages pages)"
	else
		not_ok "printed to tests/report.pdf"
	fi
else
	for t in "at 1280 px" "at the A4 column" "screenshot" "printed"; do
		skip "$t" "no chromium"
	done
fi
# a true heading column is the heading's reference, not a sensor channel
run "report plan of a drive with a true heading" 0 report --dry-run "$SAMPLES/drive-stops.csv"
has "drive: allan without the reference" "$T/out" 'allan .*channels: gz,ax,ay,az$'
has "drive: tempbias without the reference" "$T/out" 'tempbias .*channels: gz,ax,ay,az$'
has "drive: heading against it" "$T/out" 'heading --reference=heading_ref'
run "report plan of the drive beside another file" 0 report --dry-run "$SAMPLES/drive-stops.csv" "$SAMPLES/gyro-static.csv"
has "two files: allan on every data column of each" "$T/out" 'allan .*channels: all data columns$'

# the plan names each output file, and the run writes exactly those
run "report plan of two files" 0 report --dry-run -o "$T/rep2" "$SAMPLES/lot/unit01.csv" "$SAMPLES/lot/unit02.csv"
sed -n 's/^outputs in [^:]*: //p' "$T/out" | tr ' ' '\n' | sort >"$T/planned"
run "report of two files" 0 report -q -o "$T/rep2" "$SAMPLES/lot/unit01.csv" "$SAMPLES/lot/unit02.csv"
ls "$T/rep2" | sort >"$T/written"
if [ -s "$T/planned" ] && cmp -s "$T/planned" "$T/written"; then
	ok "report: the files the plan names are the files written"
else
	not_ok "report: the files the plan names are the files written"
	diff "$T/planned" "$T/written" | diag /dev/stdin
fi

# a sensitivity whose interval holds 0 is flagged in the summary
run "report of the drive" 0 report -q -o "$T/rep-drive" "$SAMPLES/drive-stops.csv"
json_check "tempbias: an interval holding 0 flagged" "$T/rep-drive/report.json" '[.summary[] | select(.stage == "tempbias" and .quantity == "bias sensitivity at 31.9 degC" and .lo != null and .lo < 0 and .hi > 0)] | length > 0 and all(.status == "warning" and (.note | test("holds 0")))'
run "report of two files" 0 report -q -o "$T/rep-two" "$SAMPLES/lot/unit01.csv" "$SAMPLES/lot/unit02.csv"
json_check "allan rows of two files name their file" "$T/rep-two/report.json" '[.summary[] | select(.stage == "allan") | .channel] | (index("unit01.csv: ax") != null and index("unit02.csv: ax") != null)'

# inferred calibrations put their results in the summary
run "report of the rate-table record" 0 report -q -o "$T/rep-rt" "$SAMPLES/gyro-ratetable.csv"
json_check "rate table: scale factor and linearity in the summary" "$T/rep-rt/report.json" '[.summary[] | select(.stage == "calib" and .channel == "gx") | .quantity] == ["scale factor", "non-linearity"]'
run "report of the tilt-table record" 0 report -q -o "$T/rep-inc" "$SAMPLES/inclino-cal.csv"
json_check "inclinometer table: its worst fit in the summary" "$T/rep-inc/report.json" '[.summary[] | select(.stage == "inclino" and (.quantity | test("fit residual")) and .unit == "mg" and .value > 0)] | length == 1'

done_testing
