#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope psd: the contract's JSON, scipy's numbers end to end (the
# reference of tests/data/psd-ref.txt through the CLI), streaming from a
# pipe, stress cases (nperseg > N, N = 1, constant, NaN, a long stream in
# bounded memory), bad options, --plot.
. "$(dirname "$0")/lib.sh"

REF="$DATA/psd-ref.txt"

run "psd text" 0 psd --nperseg 2048 "$SAMPLES/vibration.csv"
has "rms line" "$T/out" '^  ax: rms 2\.92'
has "360 Hz tone" "$T/out" '^    36(0|0\.0[0-9]*) +'
has "window figures" "$T/out" 'coherent gain 0\.5, ENBW 1\.5 bins'

run "psd json" 0 psd --format json --nperseg 2048 --bands third --peaks 3 "$SAMPLES/vibration.csv"
cp "$T/out" "$T/v.json"
json_check "contract fields" "$T/v.json" \
  '.command == "psd" and (.channels | length) == 3 and .channels[0].name == "ax" and .channels[0].unit == "m/s^2" and .channels[0].rate_hz == 5000 and .channels[0].scaling == "density" and .channels[0].psd_unit == "(m/s^2)^2/Hz" and (.channels[0].frequency_hz | length) == 1025 and (.channels[0].psd | length) == 1025 and (.channels[0].rms | type) == "number"'
json_check "peaks: 1x first, amplitude 4 m/s^2 within 0.5 %" "$T/v.json" \
  '(.channels[0].peaks | length) == 3 and (.channels[0].peaks[0].frequency_hz - 29.5 | fabs) < 0.01 and (.channels[0].peaks[0].amplitude / 4 - 1 | fabs) < 0.005 and (.channels[0].peaks[0] | has("value"))'
json_check "third-octave bands: IEC nominal centres, contract fields" "$T/v.json" \
  '(.channels[0].bands | length) > 10 and (.channels[0].bands | map(select(.nominal_hz == 31.5)) | length) == 1 and (.channels[0].bands[0] | has("lo_hz") and has("center_hz") and has("hi_hz") and has("rms"))'
json_check "Parseval: rms^2 = sum psd * bin" "$T/v.json" \
  '.channels[0] as $c | (($c.psd | add) * $c.bin_hz / ($c.rms * $c.rms) - 1 | fabs) < 1e-9'
json_check "window figures in JSON" "$T/v.json" \
  '.channels[0].window.name == "hann" and .channels[0].window.enbw_bins == 1.5 and .channels[0].window.coherent_gain == 0.5'

# scipy's numbers through the command line: the "tones" signal of the
# reference file as a CSV (its values are shortest round-trip decimals)
awk '/^signal tones /{on=1; print "# rate: 1000 Hz"; print "x"; next} /^(signal|window|case)/{on=0} on{for(i=1;i<=NF;i++) print $i}' "$REF" >"$T/tones.csv"
cmp_ref() { # DESC CASELINE ARGS...: CSV output against a reference case
	desc=$1 case=$2
	shift 2
	ss psd --format csv "$@" "$T/tones.csv" >"$T/csv" 2>"$T/err"
	awk -v c="$case" '$0 == c {on=1; next} /^(signal|window|case)/{on=0} on' "$REF" >"$T/ref"
	if [ ! -s "$T/ref" ]; then not_ok "$desc: no reference case '$case'"; return; fi
	tail -n +2 "$T/csv" | tr ',' ' ' | paste -d' ' - "$T/ref" | awk '
		{ n++; if ($1 != $3 && ($1 - $3 > 1e-12 * $3 || $3 - $1 > 1e-12 * $3)) badf++;
		  p[n] = $2; r[n] = $4; if (r[n] > m) m = r[n]; if (-r[n] > m) m = -r[n] }
		END { w = 0; for (i = 1; i <= n; i++) { d = p[i] - r[i]; if (d < 0) d = -d;
			a = r[i] < 0 ? -r[i] : r[i];
			if (a < 1e-20 * m) { if (p[i] > 1e-18 * m || -p[i] > 1e-18 * m) w = 1 }
			else if (d / a > w) w = d / a }
		  printf "%d %d %.3g\n", n, badf, w }' >"$T/cmp"
	read -r n badf worst <"$T/cmp"
	nref=$(wc -l <"$T/ref")
	if [ "$n" -eq "$nref" ] && [ "${badf:-0}" -eq 0 ] && awk -v w="$worst" 'BEGIN{exit !(w <= 1e-10)}'; then
		ok "$desc: equals scipy (worst relative $worst over $n bins)"
	else
		not_ok "$desc: $n of $nref bins, frequencies off $badf, worst relative $worst"
		diag "$T/err"
	fi
}
cmp_ref "welch flattop/linear/spectrum" "case welch tones flattop 64 - - linear spectrum 33" \
	--window flattop --nperseg 64 --detrend linear --scaling spectrum
cmp_ref "welch hann, overlap 30, nfft 256" "case welch tones hann 100 30 256 constant density 129" \
	--nperseg 100 --overlap 0.3 --nfft 256
cmp_ref "welch blackman, no overlap, odd nfft" "case welch tones blackman 64 0 65 none density 33" \
	--window blackman --nperseg 64 --overlap 0 --nfft 65 --detrend none
cmp_ref "welch defaults" "case welch tones hamming - - - constant density 129" --window hamming
cmp_ref "periodogram boxcar" "case periodogram tones boxcar - - - constant density 751" \
	--method periodogram --window boxcar

# stdin streams to the same numbers as the file
run_in "psd from stdin" 0 "$SAMPLES/vibration.csv" psd --format json --nperseg 2048 -
cp "$T/out" "$T/stdin.json"
if [ "$(jq -c '.channels[0].psd' "$T/stdin.json" 2>/dev/null)" = "$(jq -c '.channels[0].psd' "$T/v.json" 2>/dev/null)" ]; then
	ok "stdin = file"
else
	not_ok "stdin = file"
fi

run "csv" 0 psd --format csv -c ay "$SAMPLES/vibration.csv"
has "csv header" "$T/out" '^frequency_hz,ay \[\(m/s\^2\)\^2/Hz\]$'
run "spectrogram json" 0 psd --format json --spectrogram --spectrogram-columns 16 -c ax "$SAMPLES/vibration.csv"
json_check "spectrogram fields" "$T/out" \
  '.channels[0].spectrogram as $g | ($g.time_s | length) <= 16 and ($g.time_s | length) >= 8 and ($g.psd | length) == ($g.time_s | length) and ($g.psd[0] | length) == 129 and ($g.frequency_hz | length) == 129'

# stress: nperseg longer than the record, one sample, a constant, NaN
printf '# rate: 100 Hz\nx\n' >"$T/short.csv"
awk 'BEGIN { for (i = 0; i < 100; i++) print sin(i * 0.3) }' >>"$T/short.csv"
run "nperseg > N" 0 psd --format json --nperseg 4096 "$T/short.csv"
json_check "nperseg > N: one segment of N (scipy's rule)" "$T/out" \
  '.channels[0].window.nperseg == 100 and .channels[0].segments == 1 and (.channels[0].psd | length) == 51'
has "nperseg > N warns" "$T/err" 'warning: .*--nperseg 4096 is longer than the record \(100 samples\)'
printf '# rate: 100 Hz\nx\n2.385\n' >"$T/one.csv"
run "N = 1" 0 psd --format json "$T/one.csv"
json_check "N = 1: one zero bin" "$T/out" '.channels[0].psd == [0] and .channels[0].frequency_hz == [0] and .channels[0].rms == 0'
printf '# rate: 100 Hz\nx\n' >"$T/const.csv"
awk 'BEGIN { for (i = 0; i < 1000; i++) print 2.385 }' >>"$T/const.csv"
run "constant" 0 psd --format json "$T/const.csv"
json_check "constant: zero spectrum, no peaks" "$T/out" '(.channels[0].psd | map(select(. != 0)) | length) == 0 and (.channels[0].peaks | length) == 0'
has "constant warns" "$T/err" 'constant input'
printf '# rate: 100 Hz\nx\n' >"$T/nan.csv"
awk 'BEGIN { for (i = 0; i < 1000; i++) print (i == 500 ? "nan" : sin(i)) }' >>"$T/nan.csv"
run "NaN refused" 1 psd "$T/nan.csv"
one_line_error "NaN refused"
has "NaN message" "$T/err" 'NaN \(use --allow-nan'
run "NaN with --allow-nan" 0 psd --format json --allow-nan "$T/nan.csv"
json_check "NaN: its segments skipped" "$T/out" '.channels[0].segments_skipped == 2 and .channels[0].segments == 4'
printf 'x\n1\n2\n3\n4\n' >"$T/norate.csv"
run "no rate" 1 psd "$T/norate.csv"
one_line_error "no rate"
has "no rate message" "$T/err" 'give --rate'

# white noise through a pipe: uniform on [-0.5, 0.5) has variance 1/12,
# one-sided level 2 / (12 fs); the mean of 1025 bins of 97 segments
# estimates it within a few per cent
n=100000
[ -n "$SSCOPE_RUN" ] && n=20000
awk -v n=$n 'BEGIN { srand(7); print "# rate: 50 Hz"; print "x"; for (i = 0; i < n; i++) print rand() - 0.5 }' >"$T/white.csv"
run_in "white noise via stdin" 0 "$T/white.csv" psd --format json --nperseg 2048 --window blackmanharris -
json_check "white level 2 sigma^2 / fs" "$T/out" \
  '.channels[0].psd[1:-1] | (add / length) / (2 / 12 / 50) | . > 0.95 and . < 1.05'

# a long stream in bounded memory: 2e7 int16 samples (40 MB; 160 MB as
# doubles) through a pipe take no more memory than 2000 samples do
if [ -z "$SSCOPE_RUN" ] && [ -x /usr/bin/time ]; then
	yes 'sensorscope stream test' | head -c 4000 | /usr/bin/time -f '%M' -o "$T/rss0" "$SSCOPE" psd --raw i16:1 -r 1000 --nperseg 256 - >/dev/null 2>&1
	yes 'sensorscope stream test' | head -c 40000000 | /usr/bin/time -f '%M' -o "$T/rss" "$SSCOPE" psd --raw i16:1 -r 1000 --format json --nperseg 256 - >"$T/out" 2>"$T/err"
	json_check "2e7 samples streamed: every segment" "$T/out" '.channels[0].samples == 20000000 and .channels[0].segments == 156249'
	rss0=$(tail -n 1 "$T/rss0") rss=$(tail -n 1 "$T/rss")
	if [ "${rss:-999999}" -lt $((${rss0:-0} + 30000)) ]; then
		ok "streaming: RSS ${rss} kB for 2e7 samples, ${rss0} kB for 2000"
	else
		not_ok "streaming: RSS ${rss} kB for 2e7 samples, ${rss0} kB for 2000"
	fi
else
	skip "2e7 samples streamed" "under valgrind or without /usr/bin/time"
	skip "streaming RSS" "under valgrind or without /usr/bin/time"
fi

# a time column out of order: refused without --rate; with --rate the
# samples are taken as evenly spaced, with the same warning as allan's
awk 'BEGIN { srand(11); print "time [s],ax [m/s^2]"; for (i = 0; i < 600; i++) printf "%.2f,%.6f\n", (599 - i) / 100, rand() - 0.5 }' >"$T/dec.csv"
awk 'BEGIN { srand(12); print "time [s],ax [m/s^2]"; for (i = 0; i < 600; i++) printf "0,%.6f\n", rand() - 0.5 }' >"$T/tconst.csv"
for f in dec tconst; do
	run "time column $f: no --rate" 1 psd "$T/$f.csv"
	one_line_error "time column $f: no --rate"
	has "time column $f: asks for --rate" "$T/err" 'give --rate to take the samples as evenly spaced'
	for meth in "--nperseg 64" "--method periodogram"; do
		# shellcheck disable=SC2086
		run "time column $f: -r 100 $meth" 0 psd -r 100 $meth "$T/$f.csv"
		sed 's/^sensorscope: psd: /sensorscope: CMD: /' "$T/err" >"$T/psd-warn"
		ss allan -r 100 --no-fit "$T/$f.csv" 2>&1 >/dev/null | sed 's/^sensorscope: allan: /sensorscope: CMD: /' >"$T/allan-warn"
		if [ -s "$T/psd-warn" ] && grep -q 'evenly spaced at the given rate' "$T/psd-warn" && cmp -s "$T/psd-warn" "$T/allan-warn"; then
			ok "time column $f: -r 100 $meth: allan's warning"
		else
			not_ok "time column $f: -r 100 $meth: warning differs from allan's"
			diag "$T/psd-warn" "$T/allan-warn"
		fi
	done
done

# usage errors
for bad in "--window kaiser" "--overlap 1" "--nperseg 0" "--nperseg 64 --nfft 32" "--detrend quadratic" "--scaling power" "--bands 5:1" "--bands octaves" "--method burg" "--peaks 1000" "--method periodogram --nperseg 64"; do
	# shellcheck disable=SC2086
	run "usage: $bad" 2 psd $bad "$SAMPLES/vibration.csv"
	one_line_error "usage: $bad"
done
# segments the detrending fits exactly: zeros, said so (not the rounding
# of a line through two samples, nor "constant input")
run "nperseg 2, linear detrend" 0 psd --nperseg 2 --detrend linear --format json "$SAMPLES/gyro-static.csv"
json_check "nperseg 2, linear: an exact zero spectrum" "$T/out" 'all(.channels[].psd[]; . == 0)'
json_check "nperseg 2, linear: the JSON warns why" "$T/out" '[.warnings[] | select(.code == "zero_spectrum") | .message | test("segments of 2 samples are zero once their line is removed")] == [true]'
has "nperseg 2, linear: says why" "$T/err" 'segments of 2 samples are zero once their line is removed: the spectrum is zero \(give a longer --nperseg\)'
run "nperseg 1" 0 psd --nperseg 1 "$SAMPLES/gyro-static.csv"
has "nperseg 1: says why" "$T/err" 'segments of 1 sample are zero once their mean is removed'
run "nperseg 2, constant detrend" 0 psd --nperseg 2 --format json "$SAMPLES/gyro-static.csv"
json_check "nperseg 2, constant: not zero" "$T/out" 'all(.channels[].psd[]; . > 0)'
json_check "nperseg 2, constant: no zero warning in the JSON" "$T/out" '[.warnings[]? | select(.code == "zero_spectrum")] == []'
lacks "nperseg 2, constant: no zero warning" "$T/err" 'zero'
run "two files" 2 psd "$SAMPLES/vibration.csv" "$SAMPLES/vibration.csv"
run "--bands above Nyquist" 2 psd --bands 3000:4000 "$SAMPLES/vibration.csv"
run "missing file" 1 psd "$T/nope.csv"
one_line_error "missing file"

if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "--plot" 0 psd --plot "$T/psd.png" --nperseg 1024 "$SAMPLES/vibration.csv"
	if head -c 8 "$T/psd.png" | od -An -c | grep -q 'P   N   G'; then ok "PNG written"; else not_ok "PNG written"; fi
else
	run "--plot without OpenCV" 2 psd --plot "$T/psd.png" "$SAMPLES/vibration.csv"
fi

# peaks are listed only when they stand out of the local noise floor:
# none in white noise (so no "strongest peak"), the four tones of the
# vibration sample, each with its test
printf '[sensor]\nname = white\nnoise_density = 0.2 deg/sqrt(h)\n' >"$T/white.ini"
run "white noise capture" 0 simulate --sensor "$T/white.ini" --rate 100 --duration 600 --axes 3 -o "$T/white.csv"
run "white noise: JSON" 0 psd --format json "$T/white.csv"
json_check "white noise: no peak, the test stated" "$T/out" \
	'[.channels[] | (.peaks == []) and .peak_test.alpha == 0.01 and .peak_test.bins_tested == 127 and .peak_test.edf > 100] | all'
run "white noise: text" 0 psd "$T/white.csv"
has "white noise: the text says no peak stands out" "$T/out" 'no peak stands out of the noise floor at false-alarm probability 0.01'
run "tones: JSON" 0 psd --format json --nperseg 1024 -c ax "$SAMPLES/vibration.csv"
json_check "tones: the four lines, each past the threshold" "$T/out" \
	'.channels[0] as $c | ($c.peaks | length) == 4 and ([$c.peaks[] | .p_value < $c.peak_test.p_threshold and .ratio > $c.peak_test.ratio_threshold] | all)
	 and ([$c.peaks[].frequency_hz | round] | sort) == [29, 59, 89, 360]'
for bad in 0 1 -0.1 x; do
	run "--peak-alpha $bad" 2 psd --peak-alpha "$bad" "$SAMPLES/vibration.csv"
done
one_line_error "--peak-alpha x"
# a huge zero padding only interpolates: refused at once (it hung)
run "psd: nfft beyond 64 times nperseg" 2 psd --nfft 1073741824 "$SAMPLES/vibration.csv"
has "psd: nfft beyond 64 times nperseg, said" "$T/err" 'more than 64 times --nperseg 256: zero padding beyond that only interpolates'
run "psd: nfft of 64 times nperseg" 0 psd --nperseg 4 --nfft 256 "$SAMPLES/vibration.csv"
run "psd: nfft one beyond 64 times nperseg" 2 psd --nperseg 4 --nfft 257 "$SAMPLES/vibration.csv"
run "periodogram: nfft against the record, not 256" 0 psd --method periodogram --nfft 20000 "$SAMPLES/vibration.csv"

run "third-octave bands, text" 0 psd --bands third -c ax "$SAMPLES/vibration.csv"
has "bands: those the resolution cannot show are said" "$T/out" 'bands below [0-9.]+ Hz left out: narrower than the resolution, 19.53 Hz'
has "bands: headers with units" "$T/out" 'centre \(Hz\) +hi \(Hz\) +rms \(m/s\^2\)'
has "method in words" "$T/out" 'segments of 256 samples overlapping by 128, FFT of 256'

done_testing
