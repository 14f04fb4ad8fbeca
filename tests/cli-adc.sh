#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope adc: the textbook's case (+-100 deg/s, 1 deg/h, 100 Hz: 16 bits
# pass for ARW 0.1 deg/sqrt(h), fail for 0.005 deg/sqrt(h)), the
# REFERENCE.md word-length numbers, the Monte-Carlo check, bad specs,
# quantize (composing with allan) and the IEEE 1241 test.
. "$(dirname "$0")/lib.sh"

MEMS="$SAMPLES/gyro-textbook-mems.ini"
QUIET="$SAMPLES/gyro-textbook-quiet.ini"
A16="$SAMPLES/adc-textbook-16bit.ini"
A18="$SAMPLES/adc-textbook-18bit.ini"
# the Monte-Carlo checks are statistical; under valgrind only a short run
if [ -n "$SSCOPE_RUN" ]; then MC="--monte-carlo 2 --mc-duration 20"; else MC="--monte-carlo 3 --mc-duration 1200"; fi

run "adc --help" 0 adc --help
has "adc --help lists the subcommands" "$T/out" 'adc quantize'
run "adc report --help" 0 adc report --help
has "report help shows the thresholds" "$T/out" 'Thresholds'
run "adc quantize --help" 0 adc quantize --help
run "adc test --help" 0 adc test --help
run "no subcommand" 2 adc
one_line_error "no subcommand"
run "unknown subcommand" 2 adc frobnicate
one_line_error "unknown subcommand"
run "report without --adc" 2 adc report --sensor "$MEMS"
one_line_error "report without --adc"

# seed case, MEMS noise: 16 bits pass, LSB 10.99 deg/h, ARW_q 0.00529 deg/sqrt(h)
run "seed MEMS, 16 bits" 0 adc report --sensor "$MEMS" --adc "$A16" $MC --format json
json_check "contract shape" "$T/out" '.command == "adc report" and (.adcs | length) == 1 and (.adcs[0] | has("name") and has("bits") and has("lsb") and has("dithered") and has("min_bits") and has("verdict") and has("margin") and (.terms | has("quantization_arw") and has("bias_resolution") and has("offset_drift_bias") and has("reference_drift_scale_ppm") and has("range_headroom")) and (.monte_carlo | has("N_ratio") and has("B_ratio") and has("K_ratio")))'
json_check "LSB 10.99 deg/h" "$T/out" '.adcs[0].lsb.unit == "deg/h" and ((.adcs[0].lsb.value - 10.986328125) | fabs) < 1e-9'
json_check "ARW_q 0.00529 deg/sqrt(h)" "$T/out" '.adcs[0].terms.quantization_arw.unit == "deg/sqrt(h)" and ((.adcs[0].terms.quantization_arw.value - 0.0052858) | fabs) < 1e-6'
json_check "16 bits pass, dithered" "$T/out" '.adcs[0].verdict == "pass" and .adcs[0].dithered and .adcs[0].min_bits == 14'
if [ -z "$SSCOPE_RUN" ]; then
	# N within 1 %; B, estimated with N and K free over 20 min, within 5 %
	json_check "Monte Carlo: N and B kept within 1 % and 5 %" "$T/out" '.adcs[0].monte_carlo | (.N.lo > 0.99 and .N.hi < 1.01 and .B.lo > 0.95 and .B.hi < 1.05)'
fi

# the text report of a dithered converter: the bias error vanishes like
# exp(-2 pi^2 sigma^2 / q^2); it is said to be below 1e-9 %, not printed as 1e-254 %
run "MEMS, 16 bits, text" 0 adc report --sensor "$MEMS" --adc "$A16"
has "a dithered bias error is below 1e-9 %" "$T/out" 'reads *0.37 deg/h *\(below 1e-9 % error'
lacks "no vanishing percentage printed" "$T/out" 'e-[0-9][0-9][0-9] % error'
run "quiet, 16 bits, text" 0 adc report --sensor "$QUIET" --adc "$A16"
has "an undithered bias error is printed" "$T/out" '\(-46 % error, first harmonic\)'

# seed case, quiet gyro: 16 bits fail (sigma/q = 0.27), 18 needed
run "seed quiet, 16 bits" 0 adc report --sensor "$QUIET" --adc "$A16" $MC --format json
json_check "16 bits fail, not dithered" "$T/out" '.adcs[0].verdict == "fail" and (.adcs[0].dithered | not) and ((.adcs[0].sigma_over_q - 0.273) | fabs) < 0.002 and .adcs[0].min_bits == 18'
json_check "the 0.37 deg/h bias is mis-estimated by 46 %" "$T/out" '((.adcs[0].terms.sensor_bias_error.value / 0.37 + 0.46) | fabs) < 0.01'
if [ -z "$SSCOPE_RUN" ]; then
	json_check "Monte Carlo: B lost, N inflated" "$T/out" '.adcs[0].monte_carlo | (.B.hi < 1 and .N.lo > 1.05)'
fi
# oversampling 16x: the quiet gyro's white noise to 800 Hz dithers the
# conversions (sigma/q 1.09) and the average gains 2 bits: 16 bits pass
run "seed quiet, 16 bits oversampled" 0 adc report --sensor "$QUIET" --adc "$SAMPLES/adc-textbook-16bit-os16.ini" $MC --format json
json_check "oversampled 16 bits pass" "$T/out" '.adcs[0].verdict == "pass" and .adcs[0].dithered and .adcs[0].oversample == 16 and ((.adcs[0].terms.quantization_arw.value - 0.0052858 / 4) | fabs) < 1e-6'
if [ -z "$SSCOPE_RUN" ]; then
	json_check "Monte Carlo: N ratio 1.034 (analytic), B kept" "$T/out" '.adcs[0].monte_carlo | (((.N.value - 1.0342) | fabs) < 0.01 and .B.lo > 0.97 and .B.hi < 1.03)'
fi
run "seed quiet, ranked" 0 adc report --sensor "$QUIET" --adc "$A16" --adc "$A18" --monte-carlo 0
has "18 bits ranked first" "$T/out" '^  1 +18-bit'
has "16 bits ranked second, failing" "$T/out" '^  2 +16-bit.* fail '
run "csv selection table" 0 adc report --sensor "$QUIET" --adc "$A16" --adc "$A18" --monte-carlo 0 --format csv
has "csv header" "$T/out" '^rank,name,file,bits'
run "analog converters" 0 adc report --sensor "$SAMPLES/gyro-mems-250.ini" --adc "$SAMPLES/adc-12bit.ini" --adc "$SAMPLES/adc-16bit.ini" --monte-carlo 0 --format json
json_check "16-bit SAR passes, 12-bit MCU fails" "$T/out" '[.adcs[] | .verdict] == ["fail","pass"] and .adcs[1].rank == 1 and ((.adcs[1].terms.range_headroom - 1.1) | fabs) < 1e-9'
printf '[adc]\nbits = 16\nrange = -8:8 g\nrate = 200 Hz\n' >"$T/acc.ini"
run "analog converter needs a sensitivity" 1 adc report --sensor "$MEMS" --adc "$SAMPLES/adc-16bit.ini" --monte-carlo 0
one_line_error "analog converter needs a sensitivity"
has "names the converter file" "$T/err" 'adc-16bit.ini: .*sensitivity'
run "converter of another quantity" 1 adc report --sensor "$MEMS" --adc "$T/acc.ini" --monte-carlo 0
one_line_error "converter of another quantity"

# integrating (delta-v counter) mode on an accelerometer: IEEE Q term
# q/(fs sqrt 12), no lost bias
printf '[sensor]\nrange = 8 g\nnoise_density = 50 ug/sqrt(Hz)\nbias_instability = 20 ug\n' >"$T/accs.ini"
printf '[adc]\nbits = 16\nrange = -8:8 g\nrate = 200 Hz\nmode = integrate\n' >"$T/acci.ini"
run "integrating converter" 0 adc report --sensor "$T/accs.ini" --adc "$T/acci.ini" --monte-carlo 0 --format json
json_check "Q = q/(fs sqrt 12), ARW entry sqrt(3) Q, no lost bias" "$T/out" '.adcs[0] | (.mode == "integrate" and ((.terms.quantization_Q.si / (16 * 9.80665 / 65536 / (200 * (12 | sqrt))) - 1) | fabs) < 1e-12 and ((.terms.quantization_arw.si / .terms.quantization_Q.si - (3 | sqrt)) | fabs) < 1e-12 and .terms.bias_resolution.si == 0 and .lsb.unit == "ug")'

# bad specs: one line naming the key, exit 1
printf '[adc]\nrange = -100:100 deg/s\n' >"$T/nobits.ini"
run "missing bits" 1 adc report --sensor "$MEMS" --adc "$T/nobits.ini"
one_line_error "missing bits"
has "names bits" "$T/err" 'nobits.ini: \[adc\] bits: missing'
printf '[adc]\nbits = 16\nrange = -100 deg/s\n' >"$T/neg.ini"
run "negative range" 1 adc report --sensor "$MEMS" --adc "$T/neg.ini"
one_line_error "negative range"
has "names range" "$T/err" 'range: .*positive'
printf '[adc]\nbits = 16\nrange = -100:100 parsecs/s\n' >"$T/unit.ini"
run "unknown unit" 1 adc report --sensor "$MEMS" --adc "$T/unit.ini"
one_line_error "unknown unit"
has "names range and the unit" "$T/err" 'range: .*parsecs'

# quantize: values on the grid, composes with allan
run "quantize 8 bits" 0 adc quantize --bits 8 --range -1:1 -c gx "$SAMPLES/gyro-static.csv" -o "$T/q.csv"
awk -F, 'NR > 1 { v = $NF * 128; d = v - int(v + (v < 0 ? -0.5 : 0.5)); if (d > 1e-9 || d < -1e-9) bad++ } END { exit bad > 0 }' "$T/q.csv" \
	&& ok "quantized values are multiples of 1/128 deg/s" || not_ok "quantized values are multiples of 1/128 deg/s"
has "quantize keeps the rate as a time column" "$T/q.csv" '^t \[s\],gx \[deg/s\]'
if ss adc quantize --bits 12 --range -1:1 "$SAMPLES/gyro-static.csv" 2>"$T/err" |
	ss allan - --format json >"$T/allan.json" 2>>"$T/err"; then
	ok "quantize | allan"
else
	not_ok "quantize | allan"
	diag "$T/err"
fi
json_check "allan reads the quantized capture" "$T/allan.json" '.command == "allan" and (.channels | length) == 3'
run "quantize integrate" 0 adc quantize --bits 8 --range -1:1 --mode integrate -c gz "$SAMPLES/gyro-static.csv" -o "$T/qi.csv"
run "quantize without range" 2 adc quantize --bits 8 "$SAMPLES/gyro-static.csv"
one_line_error "quantize without range"

# IEEE 1241 test: an ideal 10-bit quantizer has ENOB 10 within 0.1
printf '[sensor]\nname = quiet\nnoise_density = 1e-6 deg/sqrt(h)\n' >"$T/s.ini"
run "sine" 0 simulate --sensor "$T/s.ini" --rate 1000 --duration 8.192 --tone 37.1234:0.999 --no-clip -o "$T/sine.csv"
run "sine through 10 bits" 0 adc quantize --bits 10 --range -1:1 "$T/sine.csv" -o "$T/sq.csv"
run "adc test" 0 adc test --bits 10 --range -1:1 "$T/sq.csv" --format json
cp "$T/out" "$T/out.json"
json_check "ENOB 10 within 0.1, frequency found" "$T/out" '.channels[0] | ((.enob - 10) | fabs) < 0.1 and ((.sine_fit.frequency_hz - 37.1234) | fabs) < 1e-4 and .histogram.bits == 10'
run "adc test --plot without --bits" 2 adc test "$T/sq.csv" --plot "$T/x.png"
one_line_error "adc test --plot without --bits"
run "adc test text" 0 adc test "$T/sq.csv"
has "text shows SINAD" "$T/out" 'SINAD'
# the histogram needs about 157 samples per code for DNL to 0.1 LSB: 8192
# samples resolve 4 bits, not 10 or 16 (0.125 samples per code)
json_check "10 bits, 8 samples per code: DNL not resolved" "$T/out.json" \
	'.channels[0].histogram | .resolved == false and ((.samples_per_code - 8) | fabs) < 0.2 and ((.dnl_sd_lsb - 0.443) | fabs) < 0.01'
run "sine through 16 bits" 0 adc quantize --bits 16 --range -1:1 "$T/sine.csv" -o "$T/sq16.csv"
run "adc test 16 bits" 0 adc test --bits 16 --range -1:1 "$T/sq16.csv"
has "16 bits: DNL/INL flagged" "$T/out" 'DNL/INL not resolved'
run "sine through 4 bits" 0 adc quantize --bits 4 --range -1:1 "$T/sine.csv" -o "$T/sq4.csv"
run "adc test 4 bits" 0 adc test --bits 4 --range -1:1 "$T/sq4.csv" --format json
json_check "4 bits, 512 samples per code: resolved" "$T/out" '.channels[0].histogram.resolved == true'

# simulate --adc: the quiet gyro through 16 bits reads multiples of the LSB
run "simulate --adc" 0 simulate --sensor "$QUIET" --adc "$A16" --rate 100 --duration 10 -o "$T/sa.csv"
awk -F, 'NR > 1 { v = $2 * 32768 / 100; d = v - int(v + (v < 0 ? -0.5 : 0.5)); if (d > 1e-6 || d < -1e-6) bad++ } END { exit bad > 0 }' "$T/sa.csv" \
	&& ok "simulated values on the 16-bit grid" || not_ok "simulated values on the 16-bit grid"
run "simulate --adc in volts without sensitivity" 2 simulate --sensor "$QUIET" --adc "$SAMPLES/adc-12bit.ini" --rate 100 --duration 1
one_line_error "simulate --adc in volts without sensitivity"
run "simulate --adc analog" 0 simulate --sensor "$SAMPLES/gyro-mems-250.ini" --adc "$SAMPLES/adc-12bit.ini" --rate 1000 --duration 1 -o "$T/sb.csv"

# inl_profile: a measured INL profile (LSB per transition) in the spec.
# An S-shaped profile of 0.8 LSB on 8 bits, a sine digitized through it
# (quasi-uniform phase: the step 0.381966 of a cycle is near the golden
# ratio), and the IEEE 1241 code-density test recovers it after removing
# the least-squares line (gain and offset are not INL) within 0.05 LSB,
# the bound test-adc's injected-profile check uses for 2^18 samples.
mkdir -p "$T/specs"
awk 'BEGIN { print "# S-shaped INL, 0.8 LSB"; for (k = 0; k < 256; k++) printf "%.9f\n", 0.8 * sin(2 * 3.14159265358979 * k / 256) }' >"$T/specs/s8.txt"
printf '[adc]\nname = S-8\nbits = 8\nrange = -1:1 deg/s\nrate = 1000 Hz\ninl_profile = s8.txt\n' >"$T/specs/s8.ini"
if [ -n "$SSCOPE_RUN" ]; then NS=65.536; TOL=0.1; else NS=262.144; TOL=0.05; fi
run "sine for the profile" 0 simulate --sensor "$T/s.ini" --rate 1000 --duration $NS --tone 381.966011:1.03 --no-clip -o "$T/sine8.csv"
run "quantize through the profile (path relative to the spec)" 0 adc quantize --adc "$T/specs/s8.ini" "$T/sine8.csv" -o "$T/s8q.csv"
run "adc test of the profiled converter" 0 adc test --adc "$T/specs/s8.ini" "$T/s8q.csv" --format json
json_check "the histogram sees the INL" "$T/out" '.channels[0].histogram.bits == 8 and .channels[0].histogram.inl_max > 0.5'
if command -v jq >/dev/null 2>&1; then
	jq -r '.channels[0].histogram.inl[] | if . == null then "x" else . end' "$T/out" >"$T/s8r.txt"
	grep -v '^#' "$T/specs/s8.txt" | paste - "$T/s8r.txt" | awk -v tol=$TOL '
		{ k = NR - 1; p[k] = $1; r[k] = $2; if ($2 != "x") { m++; sx += k; sy += $1; sxx += k * k; sxy += k * $1 } }
		END {
			if (m < 200) { print "only " m " codes"; exit 1 }
			sl = (m * sxy - sx * sy) / (m * sxx - sx * sx); ic = (sy - sl * sx) / m
			for (k = 0; k < NR; k++) if (r[k] != "x") {
				d = r[k] - (p[k] - ic - sl * k) / (1 + sl); if (d < 0) d = -d
				if (d > mx) { mx = d; at = k }
			}
			print "max |recovered - injected| " mx " LSB at code " at " (" m " codes)"
			exit mx > tol
		}' >"$T/cmp" && ok "injected INL recovered within $TOL LSB" || not_ok "injected INL recovered within $TOL LSB"
	diag "$T/cmp"
else
	skip "injected INL recovered (no jq)"
fi
run "simulate --adc with the profile" 0 simulate --sensor "$T/s.ini" --adc "$T/specs/s8.ini" --rate 1000 --duration 1 --tone 381.966011:1.03 --no-clip -o "$T/s8sim.csv"
cmp -s "$T/s8sim.csv" "$T/sine8.csv" && not_ok "simulate --adc digitizes" || ok "simulate --adc digitizes"
printf '[sensor]\nrange = 1 deg/s\nnoise_density = 0.005 deg/sqrt(h)\nbias_instability = 1 deg/h\n' >"$T/s1.ini"
run "report with the profile" 0 adc report --sensor "$T/s1.ini" --adc "$T/specs/s8.ini" --monte-carlo 1 --mc-duration 20 --format json
json_check "INL bound = max |profile| = 0.8 LSB" "$T/out" '.adcs[0] | (((.inl_lsb - 0.8) | fabs) < 1e-6 and .inl_from == "profile" and .inl_profile == "s8.txt" and .monte_carlo.runs == 1)'
run "report text with the profile" 0 adc report --sensor "$T/s1.ini" --adc "$T/specs/s8.ini" --monte-carlo 0
has "text shows the INL from the profile" "$T/out" '^  INL +0\.8 LSB = 22\.5 deg/h +\(max |INL| of the profile s8\.txt\)'
# bad profiles: one line naming the file (and the line), exit 1
bad_profile() { # DESC CONTENT-FILE REGEX
	printf '[adc]\nbits = 8\nrange = -1:1 deg/s\ninl_profile = %s\n' "$2" >"$T/specs/bad.ini"
	run "$1" 1 adc quantize --adc "$T/specs/bad.ini" "$T/sine8.csv" -o "$T/bad.csv"
	one_line_error "$1"
	has "$1: message" "$T/err" "$3"
}
bad_profile "missing profile" nothere.txt "bad.ini: inl_profile: .*specs/nothere.txt: no such file"
head -n 101 "$T/specs/s8.txt" >"$T/specs/short.txt"
bad_profile "short profile" short.txt 'short.txt: 100 values, need 256'
{ cat "$T/specs/s8.txt"; echo 0; } >"$T/specs/long.txt"
bad_profile "long profile" long.txt 'long.txt: line 258: more than 256 values'
sed '11s/.*/0.1 LSB/' "$T/specs/s8.txt" >"$T/specs/word.txt"
bad_profile "non-numeric line" word.txt "word.txt: line 11: '0.1 LSB' is not a number"
sed '51s/.*/-1.5/' "$T/specs/s8.txt" >"$T/specs/mono.txt"
bad_profile "non-monotonic transitions" mono.txt 'mono.txt: line 51: transition 49 at or below transition 48'
run "report with a bad profile" 1 adc report --sensor "$T/s1.ini" --adc "$T/specs/bad.ini" --monte-carlo 0
one_line_error "report with a bad profile"
run "simulate with a bad profile" 1 simulate --sensor "$T/s.ini" --adc "$T/specs/bad.ini" --rate 1000 --duration 1
one_line_error "simulate with a bad profile"
printf '[adc]\nbits = 24\nrange = -1:1 deg/s\ninl_profile = s8.txt\n' >"$T/specs/b24.ini"
run "profile above the table bits" 1 adc report --sensor "$T/s1.ini" --adc "$T/specs/b24.ini" --monte-carlo 0
one_line_error "profile above the table bits"
has "names the limit" "$T/err" 'b24.ini: line 4: inl_profile: a profile needs bits <= 20'
printf '[adc]\nbits = 8\nrange = -1:1 deg/s\ninl = 1\ninl_profile = s8.txt\n' >"$T/specs/both.ini"
run "profile and bound" 1 adc report --sensor "$T/s1.ini" --adc "$T/specs/both.ini" --monte-carlo 0
one_line_error "profile and bound"
has "profile or bound" "$T/err" 'give inl_profile or the inl/dnl bounds, not both'

# The printed Monte-Carlo se of a ratio against the spread of the ratio over
# 20 seeds (16 runs each, seeds 100 apart: no run shared): var(ratio over
# seeds) / mean(se^2) follows F(19, 20 x 15) when se = s / sqrt(runs);
# accepted within its 0.05 and 99.95 % quantiles [0.253, 2.54] (numpy,
# 4e6 draws).  An se without the sqrt(runs) would give 1/16.
if [ -z "$SSCOPE_RUN" ] && command -v jq >/dev/null 2>&1; then
	: >"$T/se.txt"
	for i in 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19; do
		ss adc report --sensor "$MEMS" --adc "$A16" --monte-carlo 16 --mc-duration 100 \
			--seed $((1 + 100 * i)) --format json 2>/dev/null |
			jq -r '.adcs[0].monte_carlo.N | "\(.value) \(.se)"' >>"$T/se.txt"
	done
	f=$(awk 'NF == 2 && $2 != "null" { n++; s += $1; ss += $1 * $1; q += $2 * $2 }
		END { if (n != 20) { print "bad"; exit } m = s / n
		      printf "%.4f", (ss - n * m * m) / (n - 1) / (q / n) }' "$T/se.txt")
	if awk -v f="$f" 'BEGIN { exit !(f + 0 > 0.253 && f + 0 < 2.54) }' && [ "$f" != bad ]; then
		ok "Monte-Carlo se of the N ratio matches its spread over seeds (F $f)"
	else
		not_ok "Monte-Carlo se of the N ratio matches its spread over seeds (F $f)"
		diag "$T/se.txt"
	fi
	run "text gives the se" 0 adc report --sensor "$MEMS" --adc "$A16" --monte-carlo 4 --mc-duration 100
	has "text se" "$T/out" 'N ratio  [0-9.]*  \[[0-9., ]*\]  se '
fi

if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "adc test plot" 0 adc test --bits 10 --range -1:1 "$T/sq.csv" --plot "$T/dnl.png"
	[ -s "$T/dnl.png" ] && ok "DNL/INL plot written" || not_ok "DNL/INL plot written"
	run "report plot" 0 adc report --sensor "$QUIET" --adc "$A16" --adc "$A18" --monte-carlo 1 --mc-duration 60 --plot "$T/adc.png"
	[ -s "$T/adc.png" ] && ok "plot written" || not_ok "plot written"
else
	run "report plot without OpenCV" 2 adc report --sensor "$QUIET" --adc "$A16" --plot "$T/adc.png"
fi
# --progress counts the Monte-Carlo runs (it stayed at 0 % before)
run "adc report --progress" 0 adc report --sensor "$SAMPLES/gyro-mems-250.ini" \
	--adc "$SAMPLES/adc-16bit.ini" --monte-carlo 2 --mc-duration 600 --progress
has "progress: run 2 of 2" "$T/err" "Monte Carlo: converter 1 of 1, run 2 of 2"
# a drift the converter's spec does not give is unknown, not "0 pass"
printf '[adc]\nbits = 16\nrange = -300:300 deg/s\nrate = 1kHz\n' >"$T/nodrift.ini"
run "adc report, no drift given" 0 adc report --sensor "$SAMPLES/gyro-mems-250.ini" \
	--adc "$T/nodrift.ini" --monte-carlo 0
has "no offset drift: unknown" "$T/out" "offset drift -> bias +unknown: the converter's spec gives no offset_drift"
has "no gain drift: unknown" "$T/out" "reference drift -> SF +unknown: the converter's spec gives no gain_drift"
run "adc report --format json, no drift given" 0 adc report --format json \
	--sensor "$SAMPLES/gyro-mems-250.ini" --adc "$T/nodrift.ini" --monte-carlo 0
json_check "no drift: null in the JSON, verdict still pass" "$T/out" \
	'.adcs[0].terms.offset_drift_bias.value == null and .adcs[0].terms.scale_drift == null and .adcs[0].verdict == "pass"'
# adc test on a constant: no sine, said; a sine on 1 % of --range: warned
awk 'BEGIN { print "t [s],ax [m/s^2]"; for (i = 0; i < 1000; i++) print i "," 1.0 }' >"$T/flat.csv"
run "adc test on a constant" 1 adc test --bits 10 --range -1:1 "$T/flat.csv"
has "a constant: no sine in the record" "$T/err" "channel ax: no sine in the record"
awk 'BEGIN { print "# rate: 1000 Hz"; print "ax [m/s^2]";
	for (i = 0; i < 8192; i++) printf "%.6f\n", 0.999 * sin(2 * 3.14159265358979 * 37.1234 * i / 1000) }' >"$T/sine.csv"
run "adc test, --range 100 times the sine" 0 adc test --bits 10 --range -100:100 "$T/sine.csv"
has "a small sine: the range checked" "$T/err" "the sine spans 1 % of --range"
run "adc test, --range the sine's" 0 adc test --bits 10 --range -1:1 "$T/sine.csv"
lacks "a full-scale sine: no warning" "$T/err" "warning"
# quantize with an LSB wider than the data; a span beyond the doubles
run "adc quantize, LSB beyond the data" 0 adc quantize --bits 12 --range -1e300:1e300 \
	-o "$T/q.csv" "$T/sine.csv"
has "an LSB of 5e296: said" "$T/err" "the LSB \(4.88e\+296 m/s\^2\) is wider than the data's span"
run "adc quantize, a span of 2e308" 2 adc quantize --bits 12 --range -1e308:1e308 \
	-o "$T/q2.csv" "$T/sine.csv"
has "a span of 2e308: refused" "$T/err" "the span HI - LO exceeds the double range"
done_testing
