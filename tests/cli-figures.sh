#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Every figure sensorscope draws, as SVG (built with or without OpenCV):
# each command's --plot FILE.svg on the samples, then a real XML parser
# (Python's xml.etree) checks each document's structure (tests/svgcheck.py):
# well-formed, axis labels on every axes with data, legends and notes
# outside every plot area and inside the figure, and no text under 10 px
# with the figure shown at the report's 1100 px column; then all of them in
# a headless browser at 1280 px and at the A4 column.
. "${top_srcdir:-$(dirname "$0")/..}/tests/lib.sh"
: "${PYTHON3:=python3}"

F="$T/fig"
mkdir -p "$F"
printf '[sensor]\nname = quiet\nnoise_density = 1e-6 deg/sqrt(h)\n' >"$T/s.ini"
ss simulate --sensor "$T/s.ini" --rate 1000 --duration 2.048 --tone 37.1234:0.999 \
	--no-clip -o "$T/sine.csv" >/dev/null 2>&1
ss adc quantize --bits 10 --range -1:1 "$T/sine.csv" -o "$T/sq.csv" >/dev/null 2>&1

run "info" 0 info --plot "$F/info.svg" "$SAMPLES/accel-thermal.csv"
run "allan" 0 allan --plot "$F/allan.svg" "$SAMPLES/gyro-static.csv"
run "allan, accelerometer" 0 allan --terms N,B,K -c ax,ay,az --plot "$F/allan-accel.svg" \
	"$SAMPLES/accel-thermal.csv"
run "psd" 0 psd --plot "$F/psd.svg" --nperseg 1024 "$SAMPLES/vibration.csv"
run "psd --spectrogram" 0 psd --spectrogram --plot "$F/spectrogram.svg" "$SAMPLES/vibration.csv"
run "vibration" 0 vibration --rpm 1797 --bearing 9,7.94,39.04 --plot "$F/vibration.svg" \
	"$SAMPLES/bearing-outer.csv"
run "tempbias" 0 tempbias -c az --plot "$F/tempbias.svg" "$SAMPLES/accel-thermal.csv"
run "inclino calibrate, validated" 0 inclino calibrate --validate "$SAMPLES/inclino-val.csv" \
	--plot "$F/inclino.svg" "$SAMPLES/inclino-cal.csv"
grep -c "class=\"axes\"" "$F/inclino.svg" | grep -qx 3 && ok "inclino: the validation panel is drawn" || not_ok "inclino: the validation panel is drawn"
run "calib gyro" 0 calib gyro --plot "$F/calib-gyro.svg" "$SAMPLES/imu-multipose.csv"
run "calib accel" 0 calib accel --plot "$F/calib-accel.svg" "$SAMPLES/imu-multipose.csv"
run "calib gyro rate table" 0 calib gyro --mode rate-table --reference rate_cmd \
	--plot "$F/calib-ratetable.svg" "$SAMPLES/gyro-ratetable.csv"
run "budget" 0 budget --gyro-bias 10deg/h --accel-bias 1mg --arw 0.1deg/sqrt\(h\) \
	--vrw 0.05m/s/sqrt\(h\) --time 60 --plot "$F/budget.svg"
run "model accel" 0 model accel --fn 2.4kHz --zeta 0.7 --plot "$F/model-accel.svg"
run "model fog" 0 model fog --radius 5cm --turns 1000 --wavelength 1550nm --plot "$F/model-fog.svg"
run "adc report" 0 adc report --sensor "$SAMPLES/gyro-textbook-mems.ini" \
	--adc "$SAMPLES/adc-textbook-16bit.ini" --adc "$SAMPLES/adc-textbook-16bit-os16.ini" \
	--monte-carlo 4 --mc-duration 600 --plot "$F/adc-report.svg"
run "adc test" 0 adc test --bits 10 --range -1:1 --plot "$F/adc-test.svg" "$T/sq.csv"
run "navsim" 0 navsim --arw 0.2deg/sqrt\(h\) --runs 5 --duration 60 --plot "$F/navsim.svg"
run "heading" 0 heading --reference heading_ref --plot "$F/heading.svg" "$SAMPLES/drive-stops.csv"
run "walk" 0 walk -c gz --plot "$F/walk.svg" "$SAMPLES/gyro-static.csv"

# an upper-case extension is an SVG too; anything else is a usage error
run "--plot X.SVG" 0 info --plot "$T/upper.SVG" "$SAMPLES/accel-thermal.csv"
run "--plot X.pdf" 2 info --plot "$T/x.pdf" "$SAMPLES/accel-thermal.csv"
one_line_error "--plot X.pdf"
has "--plot X.pdf names the formats" "$T/err" "must end in .png or .svg"

if command -v "$PYTHON3" >/dev/null 2>&1; then
	# one interpreter for all of them: a line per figure, or its errors
	"$PYTHON3" "$top_srcdir/tests/svgcheck.py" "$F"/*.svg "$T/upper.SVG" >"$T/check" 2>&1
	for f in "$F"/*.svg "$T/upper.SVG"; do
		b=$(basename "$f")
		if grep -q "^$b: well-formed, " "$T/check"; then
			ok "$(grep "^$b: well-formed, " "$T/check")"
		else
			not_ok "structure of $b"
			grep "^$b: " "$T/check" | diag /dev/stdin
		fi
	done
else
	skip "SVG structure" "python3 not installed"
fi

# every figure laid out by a real browser, as the report shows it (a
# 1150 px column at a 1280 px window) and at the A4 column (703 px): the
# smallest text and any legend or note box over a plot area, measured by
# the page itself
BROWSER=$(command -v chromium || command -v chromium-browser || true)
if ! long_tier; then
	skip "browser at 1280 px" "$LONG_ONLY"
	skip "browser at 718 px" "$LONG_ONLY"
elif [ -n "$BROWSER" ]; then
	{
		echo '<!DOCTYPE html><html><head><meta charset="utf-8"><style>'
		echo 'body{max-width:1150px;margin:0 auto;padding:0}figure{margin:0}svg{display:block;max-width:100%;height:auto}</style></head><body>'
		for f in "$F"/*.svg; do echo "<figure id=\"$(basename "$f" .svg)\">"; cat "$f"; echo '</figure>'; done
		cat <<'JS'
<script>
window.addEventListener('load', function () {
  var out = [];
  document.querySelectorAll('figure').forEach(function (fig) {
    var s = fig.querySelector('svg'), k = s.getBoundingClientRect().width / s.viewBox.baseVal.width;
    var min = 1e9, over = 0;
    s.querySelectorAll('text, tspan').forEach(function (t) {
      for (var c = t.firstChild; c; c = c.nextSibling)
        if (c.nodeType === 3 && c.nodeValue.trim()) {
          min = Math.min(min, parseFloat(getComputedStyle(t).fontSize) * k);
          break;
        }
    });
    s.querySelectorAll('g.axes').forEach(function (a) {
      var p = a.querySelector('g.plot-area > rect').getBoundingClientRect();
      a.querySelectorAll('g.legend > rect:first-of-type, g.note > rect:first-of-type').forEach(function (b) {
        var r = b.getBoundingClientRect();
        if (r.left < p.right && p.left < r.right && r.top < p.bottom && p.top < r.bottom) over++;
      });
    });
    out.push(fig.id + ' ' + min.toFixed(1) + ' ' + over);
  });
  document.body.setAttribute('data-check', out.join(';'));
});
</script></body></html>
JS
	} >"$T/page.html"
	for w in 1280:10 718:7; do
		win=${w%:*} least=${w#*:}
		HOME="$T" timeout 180 "$BROWSER" --headless --no-sandbox --disable-gpu \
			--disable-quic --no-first-run --disable-background-networking \
			--disable-component-update --disable-sync --user-data-dir="$T/chr$win" \
			--window-size="$win,1000" --dump-dom "file://$T/page.html" 2>/dev/null |
			grep -o 'data-check="[^"]*"' | sed 's/^data-check="//; s/"$//' | tr ';' '\n' >"$T/laid$win"
		if [ "$(wc -l <"$T/laid$win")" -eq "$(ls "$F"/*.svg | wc -l)" ] &&
			awk -v m="$least" '$2 < m || $3 != 0 { bad = 1 } END { exit bad }' "$T/laid$win"; then
			ok "browser at $win px: every figure's text >= $least px, no box over the data (smallest $(sort -k2 -n "$T/laid$win" | head -n 1))"
		else
			not_ok "browser at $win px"
			diag "$T/laid$win"
		fi
	done
else
	skip "browser at 1280 px" "no chromium"
	skip "browser at 718 px" "no chromium"
fi
done_testing
