#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope inclino calibrate | apply: the bundled calibration and
# validation sets (0.1 degree class met, uncompensated >= 0.3 degree), the
# LUT round trip through apply, the still flag, and bad inputs: no
# temperature column, tilt column missing, non-monotonic LUT (exit 1),
# usage errors (exit 2).
. "$(dirname "$0")/lib.sh"

CAL="$SAMPLES/inclino-cal.csv"
VAL="$SAMPLES/inclino-val.csv"
run "inclino --help" 0 inclino --help
run "calibrate --help" 0 inclino calibrate --help
run "apply --help" 0 inclino apply --help
run "no subcommand" 2 inclino
one_line_error "no subcommand"

run "calibrate and validate" 0 inclino calibrate --format json --validate "$VAL" "$CAL"
json_check "5 nodes" "$T/out" '(.lut.nodes | length) == 5 and ([.lut.nodes[].temp_degc | round] == [-20, 0, 20, 40, 60])'
json_check "0.1 degree class met, uncompensated >= 0.3 degree" "$T/out" \
  '.validation.max_deg <= 0.1 and .validation.uncompensated_max_deg >= 0.3 and .validation.within_class and .validation.poses == 40'
json_check "dominant term named" "$T/out" '.validation.dominant | IN("offset", "scale", "misalignment")'
# the sample's model at 20 degC: offsets 3 / -2 / 1.5 mg within 4 sd
json_check "offsets at 20 degC" "$T/out" \
  '.lut.nodes[2] as $n | [3, -2, 1.5] as $t | all(range(0;3); (($n.offset_m_s2[.] / 9.80665e-3 - $t[.]) | fabs) <= 4 * $n.offset_sd_m_s2[.] / 9.80665e-3)'
run "text" 0 inclino calibrate --validate "$VAL" "$CAL"
has "text: class" "$T/out" '0\.1 deg class: within'
run "csv" 0 inclino calibrate --format csv "$CAL"
has "csv header" "$T/out" '^temp_degc,axis,offset_mg'
run "-o LUT.json writes JSON" 0 inclino calibrate -o "$T/lut.json" "$CAL"
json_check "LUT file" "$T/lut.json" '.command == "inclino calibrate" and (.lut.nodes | length) == 5'

run "apply" 0 inclino apply --lut "$T/lut.json" -o "$T/tilt.csv" "$VAL"
has "apply header" "$T/tilt.csv" '^time \[s\],temp \[degC\],roll_deg,pitch_deg,still$'
# every validation sample is still; single samples carry 1 mg of noise per
# axis: about 0.06 degree sd, up to 0.12 degree for roll at 60 degrees of
# pitch, so the rms error stays below 0.1 and the max below 0.5 (4 sd)
paste -d, "$T/tilt.csv" "$VAL" | awk -F, '/^[0-9]/ { n++; if ($5 != 1) bad++; d1 = $3 - $11; d2 = $4 - $12; s += d1 * d1 + d2 * d2; if (d1 < 0) d1 = -d1; if (d2 < 0) d2 = -d2; if (d1 > m) m = d1; if (d2 > m) m = d2 } END { printf "%d %d %.4f %.4f\n", n, bad, m, sqrt(s / (2 * n)) }' >"$T/cmp"
if awk '{ exit !($1 == 800 && $2 == 0 && $3 < 0.5 && $4 < 0.1) }' "$T/cmp"; then ok "apply: 800 still samples, max / rms error $(cut -d' ' -f3,4 "$T/cmp") deg"; else not_ok "apply vs reference: $(cat "$T/cmp")"; fi
has "apply summary" "$T/err" '800 samples, 800 still'
# 1-axis mode: the sensitivity column is 17.45 mg/deg * cos(pitch)
run "apply --axes 1" 0 inclino apply --axes 1 --lut "$T/lut.json" -o "$T/t1.csv" "$VAL"
has "1-axis header" "$T/t1.csv" '^time \[s\],temp \[degC\],pitch_deg,sens \[mg/deg\],still$'
if awk -F, '/^[0-9]/ { c = cos($3 * 3.14159265358979 / 180) * 17.4533; d = $4 - c; if (d < 0) d = -d; if (d > m) m = d } END { exit !(m < 0.01) }' "$T/t1.csv"; then ok "1-axis sensitivity = 17.45 cos(pitch)"; else not_ok "1-axis sensitivity"; fi
run "apply --axes 2" 0 inclino apply --axes 2 --lut "$T/lut.json" -o "$T/t2.csv" "$VAL"
run "bad --axes" 2 inclino apply --axes 4 --lut "$T/lut.json" "$VAL"
# motion: |a| = 1.2 g and a turning gyro are flagged, not silently valid
cat >"$T/moving.csv" <<'CSV'
time [s],ax [g],ay [g],az [g],gx [deg/s],gy [deg/s],gz [deg/s],temp [degC]
0,0.003,-0.002,1.0015,0,0,0,20
0.1,0.003,-0.002,1.2015,0,0,0,20
0.2,0.003,-0.002,1.0015,0,0,5,20
0.3,0.003,-0.002,1.0015,0,0,0,70
CSV
run "apply with motion" 0 inclino apply --lut "$T/lut.json" "$T/moving.csv"
if [ "$(grep -E '^[0-9]' "$T/out" | cut -d, -f5 | tr '\n' ' ')" = "1 0 0 1 " ]; then ok "still flags 1 0 0 1"; else not_ok "still flags: $(grep -E '^[0-9]' "$T/out" | cut -d, -f5 | tr '\n' ' ')"; diag "$T/out"; fi
has "clamped temperature warned" "$T/err" 'outside the table.s range'

# bad inputs
cut -d, -f1-4,6,7 "$CAL" >"$T/notemp.csv"
run "no temperature column" 1 inclino calibrate "$T/notemp.csv"
one_line_error "no temperature column"
cut -d, -f1-5,7 "$CAL" >"$T/noroll.csv"
run "tilt column missing" 1 inclino calibrate "$T/noroll.csv"
one_line_error "tilt column missing"
has "names the column" "$T/err" "no tilt reference column 'roll_ref'"
jq '.lut.nodes[2].temp_degc = -30' "$T/lut.json" >"$T/bad.json" 2>/dev/null || cp "$T/lut.json" "$T/bad.json"
if command -v jq >/dev/null 2>&1; then
	run "non-monotonic LUT" 1 inclino apply --lut "$T/bad.json" "$VAL"
	one_line_error "non-monotonic LUT"
	has "says why" "$T/err" 'not strictly increasing'
else
	skip "non-monotonic LUT" "jq not installed"
fi
echo '{"lut":{}}' >"$T/empty.json"
run "not a LUT" 1 inclino apply --lut "$T/empty.json" "$VAL"
one_line_error "not a LUT"
run "apply without --lut" 2 inclino apply "$VAL"
one_line_error "apply without --lut"
run "missing LUT file" 1 inclino apply --lut "$T/nope.json" "$VAL"
# all poses level: the axes cannot be separated
awk -F, 'NR <= 2 || $7 == "0.0000" && $6 == "0.0000"' "$CAL" >"$T/level.csv"
run "poses do not excite every axis" 1 inclino calibrate "$T/level.csv"
one_line_error "poses do not excite every axis"

if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "calibrate --plot" 0 inclino calibrate --plot "$T/i.png" "$CAL"
	if [ -s "$T/i.png" ]; then ok "plot written"; else not_ok "plot written"; fi
fi
# tilts from a tilt table instead of reference columns: the same poses, the same table
awk -F, 'NR==2 {print "time [s],ax [g],ay [g],az [g],temp [degC]"; next} NR>2 {print $1","$2","$3","$4","$5}' "$SAMPLES/inclino-cal.csv" >"$T/noref.csv"
awk -F, 'NR>2 { if ($6 != r || $7 != p) { if (NR > 3) printf "%s %s %s %s\n", s, t + 0.05, r, p; s = $1 - 0.05; r = $6; p = $7 } t = $1 } END { printf "%s %s %s %s\n", s, t + 0.05, r, p }' "$SAMPLES/inclino-cal.csv" >"$T/tilts.txt"
run "calibrate from reference columns" 0 inclino calibrate --format json "$SAMPLES/inclino-cal.csv"
mv "$T/out" "$T/cols.json"
run "calibrate from a tilt table" 0 inclino calibrate --format json --tilt-table "$T/tilts.txt" "$T/noref.csv"
if jq -e --slurpfile c "$T/cols.json" '.lut == $c[0].lut and (.lut.nodes | length) == 5' "$T/out" >/dev/null 2>&1; then
	ok "tilt table gives the same table"
else
	not_ok "tilt table gives the same table"
fi
run "no reference and no tilt table" 1 inclino calibrate "$T/noref.csv"
has "suggests --tilt-table" "$T/err" 'tilt-table'
printf '0 2 -60\n' >"$T/bad-tilts.txt"
run "malformed tilt table" 1 inclino calibrate --tilt-table "$T/bad-tilts.txt" "$T/noref.csv"
one_line_error "malformed tilt table"
has "names the line" "$T/err" 'bad-tilts.txt:1: want'

done_testing
