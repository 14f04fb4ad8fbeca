#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope run and sensorscope report: the plan (what runs, what is
# skipped and why), proof from the trace that each capture is read once
# with only the columns in use and that unrequested stages do not run,
# bad scenes and the outputs (every sample scene and the HTML report in a
# headless browser: cli-scene-samples.sh).
. "$(dirname "$0")/lib.sh"

cp "$SAMPLES/gyro-static.csv" "$SAMPLES/imu-multipose.csv" "$T/"

scene() { f=$1; shift; printf "$@" >"$T/$f"; }

run "run --help" 0 run --help
run "report --help" 0 report --help

# ---- the plan
run "dry run of a sample scene" 0 run --dry-run "$SAMPLES/gyro-static.scene.ini"
has "allan requested" "$T/out" '^  [0-9]\. allan +requested by \[allan\]'
has "budget uses allan" "$T/out" 'budget +requested by \[budget\]; uses the results of allan'
has "psd skipped with its reason" "$T/out" '^  psd +not requested \(no \[psd\] section\)'
lacks "dry run writes nothing" "$T/out" 'wrote'

# budget alone measures its noise terms with allan
scene b.ini '[input]\nfiles = gyro-static.csv\n[budget]\ntime = 60\n'
run "budget pulls in allan" 0 run --dry-run "$T/b.ini"
has "allan added for budget" "$T/out" 'allan +its results are used by \[budget\]'

# ---- the trace: one read, only the columns in use, no stage not needed
scene one.ini '[input]\nfiles = gyro-static.csv\n[allan]\ncolumns = gx\ntaus = octave\n[report]\nformats = json\n'
SSCOPE_TRACE=1 run "allan on one column" 0 run -o "$T/one" "$T/one.ini"
has "one read of gx only" "$T/err" '^trace: read .*gyro-static.csv columns gx$'
if [ "$(grep -c '^trace: read' "$T/err")" -eq 1 ]; then ok "the capture is read once"; else not_ok "the capture is read once"; diag "$T/err"; fi
lacks "psd does not run" "$T/err" '^trace: stage psd'
lacks "budget does not run" "$T/err" '^trace: stage budget'
json_check "allan.json has one channel" "$T/one/allan.json" '.command == "allan" and (.channels | map(.name)) == ["gx"]'
json_check "report.json lists the stages run" "$T/one/report.json" '(.results | keys) == ["allan", "info"]'
if [ -e "$T/one/report.html" ]; then not_ok "formats = json writes no HTML"; else ok "formats = json writes no HTML"; fi

scene two.ini '[input]\nfiles = gyro-static.csv\n[allan]\ncolumns = gy\ntaus = octave\nno-fit = yes\n[psd]\ncolumns = gx\n[report]\nformats = json\n'
SSCOPE_TRACE=1 run "two stages, two columns" 0 run -o "$T/two" "$T/two.ini"
has "one read of the union" "$T/err" '^trace: read .*gyro-static.csv columns gy,gx$'
json_check "each stage saw its own column" "$T/two/report.json" '(.results.allan.channels | map(.name)) == ["gy"] and (.results.psd.channels | map(.name)) == ["gx"]'

# ---- bad scenes: one line naming the scene, its line and the reason
scene u.ini '[input]\nfiles = gyro-static.csv\n[allen]\n'
run "unknown section" 2 run "$T/u.ini"
one_line_error "unknown section"
has "names the line and the sections" "$T/err" 'u.ini: line 3: unknown section \[allen\] .*allan'
scene k.ini '[input]\nfiles = gyro-static.csv\n[allan]\ndevv = adev\n'
run "unknown key" 2 run "$T/k.ini"
has "names the key" "$T/err" "k.ini: line 4: unknown key 'devv' in \\[allan\\]"
scene v.ini '[input]\nfiles = gyro-static.csv\n[allan]\ndev = bogus\n'
run "bad value" 2 run "$T/v.ini"
one_line_error "bad value"
has "the option's own message, at its line" "$T/err" "v.ini: line 4: dev: 'bogus'"
scene m.ini '[input]\nfiles = missing.csv\n[allan]\n'
run "missing input file" 1 run "$T/m.ini"
one_line_error "missing input file"
has "names the file" "$T/err" 'line 2: files: .*missing.csv'
scene c.ini '[input]\nfiles = imu-multipose.csv\n[calib]\ntriad = accel\nuses = budget\n[budget]\ntime = 10\n'
run "impossible request" 2 run "$T/c.ini"
one_line_error "impossible request"
has "says why" "$T/err" "impossible request: \\[calib\\] cannot use the results of 'budget'"
scene d.ini '[allan]\ntaus = octave\n'
run "analysis without captures" 2 run "$T/d.ini"
has "asks for files" "$T/err" 'impossible request: \[allan\] needs captures'
scene e.ini '[input]\nfiles = gyro-static.csv\n'
run "nothing to do" 2 run "$T/e.ini"
has "says so" "$T/err" 'nothing to do'
run "scene file missing" 1 run "$T/none.ini"
one_line_error "scene file missing"
scene s.ini '[input]\nfiles = gyro-static.csv\n[allan]\nsyntax error here\n'
run "malformed scene" 2 run "$T/s.ini"
one_line_error "malformed scene"

# a budget from its own keys needs no captures
scene bk.ini '[budget]\ntime = 120\ngyro-bias = 10deg/h\n[report]\nformats = json\n'
run "budget without captures" 0 run -o "$T/bk" "$T/bk.ini"
json_check "the textbook's 137 m" "$T/bk/budget.json" '((.sources[] | select(.name == "gyro_bias") | .position_m[0]) - 136.926665 | fabs) < 1e-5'

# ---- report: the scene inferred from the data
run "report dry run" 0 report --dry-run "$T/gyro-static.csv"
has "allan inferred for a gyro" "$T/out" 'allan +inferred: a rate-gyro record'
has "psd inferred" "$T/out" 'psd +inferred'
lacks "no vibration for a 10 Hz gyro" "$T/out" '^  [0-9]\. vibration'
# several captures: each stage on the files it fits, one-file stages once per file
run "report of three kinds of capture, planned" 0 report --dry-run "$SAMPLES/accel-thermal.csv" "$SAMPLES/vibration.csv" "$SAMPLES/euroc-imu.csv"
has "vibration only on the 5 kHz record" "$T/out" 'vibration +inferred.*; files: [^ ]*vibration.csv$'
has "allan not on the vibration record" "$T/out" 'allan +inferred.*; files: [^ ]*accel-thermal.csv [^ ]*euroc-imu.csv$'
has "psd once per file" "$T/out" 'psd +inferred.*; once per file$'
run "report of three kinds of capture" 0 report -o "$T/three" "$SAMPLES/accel-thermal.csv" "$SAMPLES/vibration.csv" "$SAMPLES/euroc-imu.csv"
json_check "psd per file, allan on two files" "$T/three/report.json" '(.results.psd.files | length) == 3 and (.results.allan.files | length) == 2 and .results.vibration.file != null'
json_check "summary rows name their file" "$T/three/report.json" '[.summary[] | select(.stage == "psd") | .channel] | any(startswith("vibration.csv: "))'
# temperature column -> tempbias; a tilt table -> inclino (and nothing else)
run "report of a thermal run and a tilt table, planned" 0 report --dry-run "$SAMPLES/accel-thermal.csv" "$SAMPLES/inclino-cal.csv"
has "tempbias inferred for the thermal run" "$T/out" 'tempbias +inferred: inertial channels with a temperature column.*files: [^ ]*accel-thermal.csv$'
has "inclino inferred for the tilt table" "$T/out" 'inclino +inferred: .*reference tilts.*files: [^ ]*inclino-cal.csv$'
has "no allan on the tilt table" "$T/out" 'allan +inferred.*files: [^ ]*accel-thermal.csv$'
# without a scene file, an analysis not run was not inferred (no section
# was missing)
run "report --dry-run of a vibration record" 0 report --dry-run "$SAMPLES/vibration.csv"
has "allan: not inferred" "$T/out" "^  allan +not inferred from these data$"
lacks "no section named" "$T/out" "no \[allan\] section"
# an inferred analysis the data refuse is left out, with its reason
printf '# rate: 10 Hz\ngx [deg/s],temp [degC]\n' >"$T/flat.csv"
awk 'BEGIN { srand(7); for (i = 0; i < 3000; i++) printf "%.6f,25.0\n", rand() - 0.5 }' >>"$T/flat.csv"
run "report with a constant temperature" 0 report -o "$T/flat" "$T/flat.csv"
has "tempbias refusal shown" "$T/err" 'tempbias: not in the report'
json_check "allan reported, tempbias not" "$T/flat/report.json" '(.results | has("allan")) and (.results | has("tempbias") | not)'
has "the HTML says why" "$T/flat/report.html" "Analysis 'tempbias': inferred, but refused by the data: .*flat.csv: channel gx: the temperature does not change \\(25 degC throughout\\)"

# [adc]: files or an inline specification; the ADC report needs a sensor
cp "$SAMPLES/gyro-textbook-mems.ini" "$T/"
scene adc1.ini '[sensor]\nspec = gyro-textbook-mems.ini\n\n[adc]\nname = inline 16\nbits = 16\nrange = -100:100 deg/s\nrate = 100 Hz\nmonte-carlo = 0\n[report]\nformats = json\n'
run "inline [adc]" 0 run -o "$T/adc1" "$T/adc1.ini"
json_check "the textbook's LSB from the inline spec" "$T/adc1/adc.json" '(.adcs[0].lsb.value - 10.986 | fabs) < 0.01 and .adcs[0].verdict == "pass"'
# an inline [adc] with an inl_profile: the path is relative to the scene
mkdir -p "$T/prof" && cp "$SAMPLES/gyro-textbook-mems.ini" "$T/prof/"
awk 'BEGIN { for (k = 0; k < 256; k++) printf "%.9f\n", 0.5 * sin(2 * 3.14159265358979 * k / 256) }' >"$T/prof/inl.txt"
scene prof/adcp.ini '[sensor]\nspec = gyro-textbook-mems.ini\n\n[adc]\nbits = 8\nrange = -100:100 deg/s\nrate = 100 Hz\ninl_profile = inl.txt\nmonte-carlo = 0\n[report]\nformats = json\n'
run "inline [adc] with an inl_profile" 0 run -o "$T/adcp" "$T/prof/adcp.ini"
json_check "the INL bound from the profile" "$T/adcp/adc.json" '.adcs[0] | ((.inl_lsb - 0.5) | fabs) < 1e-6 and .inl_from == "profile"'
scene adc2.ini '[sensor]\nspec = gyro-textbook-mems.ini\n\n[adc]\nbits = 16\nrange = -100:100 deg/sfoo\n'
run "inline [adc] with a bad unit" 2 run "$T/adc2.ini"
one_line_error "inline [adc] with a bad unit"
has "names the scene line" "$T/err" "adc2.ini: line 6: range: unknown unit"
scene adc3.ini '[adc]\nspec = %s\n' "$SAMPLES/adc-16bit.ini"
run "[adc] without a sensor" 2 run "$T/adc3.ini"
has "impossible without [sensor]" "$T/err" 'impossible request: \[adc\] needs a \[sensor\]'

# ---- a stage in a scene is its command: check() runs, the intervals
# are the fit's, -c shapes the captures the same way everywhere
run "bearing scene" 0 run -q -o "$T/bear" "$SAMPLES/bearing.scene.ini"
json_check "the scene finds the outer-race defect, as the command does" "$T/bear/vibration.json" \
	'[.diagnosis[].finding] | any(test("outer-race"))'
has "the text report says so" "$T/bear/report.txt" 'outer-race defect: .*BPFO'
run "gyro scene" 0 run -q -o "$T/gyro" "$SAMPLES/gyro-static.scene.ini"
lacks "no report says 0% intervals" "$T/gyro/report.txt" ' 0% interval'
lacks "no HTML report says 0% intervals" "$T/gyro/report.html" ' 0% interval'
has "the text prints the JSON's level" "$T/gyro/report.txt" '68\.3% intervals'
json_check "the JSON's level" "$T/gyro/allan.json" '[.channels[].fit.ci_level] | all(. == 0.683)'
# (a present term whose interval reaches 0 says so after the level)
json_check "summary notes the JSON's level" "$T/gyro/report.json" \
	'[.summary[] | select(.stage == "allan") | .note] | all(. == "fit, 68.3 % interval" or . == "fit, 68.3 % interval; present, but the interval reaches 0")'
cp "$SAMPLES/imu-multipose.csv" "$T/imu.csv"
run "a calibration file" 0 calib gyro --save-calibration "$T/cal.json" -q "$T/imu.csv"
run "-c 'ax, ay'" 0 info --format json -c 'ax, ay' "$T/imu.csv"
json_check "-c 'ax, ay': two channels in order" "$T/out" '(.channels | map(.name)) == ["ax", "ay"]'
run "-c 'ax, ay' with --calibration" 0 info --format json --calibration "$T/cal.json" -c 'ax, ay' "$T/imu.csv"
json_check "-c 'ax, ay' with --calibration: the same channels" "$T/out" '(.channels | map(.name)) == ["ax", "ay"] and (.channels | map(.unit)) == ["m/s^2", "m/s^2"]'
run "-c ' ay,2 ' (a file column index)" 0 info --format json -c ' ay,2 ' "$T/imu.csv"
json_check "-c ' ay,2 ': ay then column 2" "$T/out" '(.channels | map(.name)) == ["ay", "gx"]'
scene col.ini '[input]\nfiles = imu.csv\ncolumns = ax, ay\n[psd]\n[report]\nformats = json\n'
run "columns = ax, ay in a scene" 0 run -o "$T/col" "$T/col.ini"
json_check "the scene's stages get ax, ay" "$T/col/report.json" '(.results.psd.channels | map(.name)) == ["ax", "ay"] and (.results.info.channels | map(.name)) == ["ax", "ay"]'
scene colc.ini '[input]\nfiles = imu.csv\ncalibration = cal.json\n[psd]\ncolumns = ax, ay\n[report]\nformats = json\n'
run "columns = ax, ay with a calibration in a scene" 0 run -o "$T/colc" "$T/colc.ini"
json_check "the calibrated ax, ay" "$T/colc/psd.json" '(.channels | map(.name)) == ["ax", "ay"] and (.channels | map(.unit)) == ["m/s^2", "m/s^2"]'
# unknown names are errors everywhere (a scene used to drop them)
run "-c with an unknown name" 1 info -c 'ax, bogus' "$T/imu.csv"
has "names it" "$T/err" "no column 'bogus'"
run "-c with an unknown name and --calibration" 1 info --calibration "$T/cal.json" -c 'ax, bogus' "$T/imu.csv"
has "names it" "$T/err" "no column 'bogus'"
scene colu.ini '[input]\nfiles = imu.csv\n[psd]\ncolumns = ax, bogus\n[report]\nformats = json\n'
run "an unknown column in a scene" 1 run -o "$T/colu" "$T/colu.ini"
has "names it" "$T/err" "no column 'bogus'"

# inside a scene, a message names the scene's keys, not the options
printf 'gx,gy\n0.1,0.2\n0.1,0.2\n0.1,0.2\n' >"$T/norate.csv"
printf '[input]\nfiles = norate.csv\n[allan]\n[report]\noutput = sc-norate\n' >"$T/norate.ini"
run "scene without a rate" 1 run "$T/norate.ini"
has "scene without a rate: the key to give" "$T/err" "no sample rate: .*; give rate in \[input\]$"
printf '[input]\nfiles = %s\n[tempbias]\n[report]\noutput = sc-notemp\n' "$SAMPLES/gyro-static.csv" >"$T/notemp.ini"
run "scene without a temperature column" 1 run "$T/notemp.ini"
has "scene without a temperature: the key to give" "$T/err" 'no temperature column \(give temp_column = NAME in \[input\]\)'

# a stage's keys keep the option's name (run-length, not run_length), and
# --sensor is the [sensor] section
printf '[budget]\ntime = 10, 60\n[report]\noutput = sc-budget0\n' >"$T/budget0.ini"
run "scene: a budget without sources" 2 run "$T/budget0.ini"
has "scene: the section and keys to give" "$T/err" 'give \[sensor\] or gyro-bias, accel-bias, arw, vrw$'
printf '[input]\nfiles = %s\n[walk]\n[report]\noutput = sc-walk0\n' "$SAMPLES/euroc-imu.csv" >"$T/walk0.ini"
run "scene: a walk too short" 1 run "$T/walk0.ini"
has "scene: the walk's own key" "$T/err" '\(give run-length\)$'
# report infers its scene: its messages keep the command's words
run "report on a record too short for the walk" 0 report -q -o "$T/rep-euroc" "$SAMPLES/euroc-imu.csv"
has "report: the command's option, not a key" "$T/err" 'walk: .*\(give --run-length\)$'

printf '[input]\nfiles = %s\n[allan]\n[report]\nformats =\noutput = sc-nofmt\n' "$SAMPLES/gyro-static.csv" >"$T/nofmt.ini"
run "scene: formats empty" 2 run "$T/nofmt.ini"
has "formats empty: said at its line" "$T/err" 'nofmt.ini: line 5: formats: empty'
if [ -e "$T/sc-nofmt" ]; then not_ok "formats empty: no folder made"; else ok "formats empty: no folder made"; fi

# a warning a stage says reaches its report (and is said once)
printf '[budget]\ngyro-bias = 10\naccel-bias = 1 mg\ntime = 60\n[report]\noutput = sc-bare\n' >"$T/bare.ini"
run "scene: a bare number" 0 run -q "$T/bare.ini"
json_check "the warning in the report's summary, flagged" "$T/sc-bare/report.json" '[.summary[] | select(.quantity == "warning" and .status == "warning" and (.note | test("gyro-bias = 10 has no unit")))] | length == 1'
has "the warning a banner" "$T/sc-bare/report.html" 'Warning\.</strong> gyro-bias = 10 has no unit'
lacks "not 'Nothing flagged'" "$T/sc-bare/report.html" 'Nothing flagged'
run "scene: a bare number, said" 0 run "$T/bare.ini"
if [ "$(grep -c 'gyro-bias = 10 has no unit' "$T/err")" = 1 ]; then ok "the warning said once"; else not_ok "the warning said once"; diag "$T/err"; fi

# a section's columns within [input]'s
printf '[input]\nfiles = %s\ncolumns = gx\n[walk]\ncolumns = gz\n[report]\noutput = sc-cols\n' "$SAMPLES/gyro-static.csv" >"$T/cols.ini"
run "scene: a section's column outside [input]'s" 2 run "$T/cols.ini"
has "outside [input]'s columns: said at its line" "$T/err" "cols.ini: line 5: columns: 'gz' is not among \[input\]'s columns \(gx\)"
printf '[input]\nfiles = %s\ncolumns = gx, gz\n[walk]\ncolumns = gz\n[report]\noutput = sc-cols2\nformats = json\n' "$SAMPLES/gyro-static.csv" >"$T/cols2.ini"
run "scene: a section's column among [input]'s" 0 run -q "$T/cols2.ini"
json_check "info describes [input]'s columns" "$T/sc-cols2/info.json" '[.channels[].name] == ["gx", "gz"]'

done_testing
