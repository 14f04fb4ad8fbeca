#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Outputs that never destroy data (continued from cli-output.sh): a report
# folder is put in place only when every stage succeeded; SIGINT/SIGTERM
# leave no temporary files or staging folders; ignored options say so;
# names are escaped.
. "$(dirname "$0")/lib.sh"
. "$(dirname "$0")/output.sh"
cp "$SM" "$T/cap.csv"

# ------------------------------------------------------------ 6. report folders
run "run into a new folder" 0 run -q "$T/scene.ini"
[ -s "$T/rep/report.json" ] && ok "report written" || not_ok "report written"
old=$(cat "$T/rep"/* | cksum)
# the allan stage fails when it writes its Kalibr file, after info wrote
printf '[input]\nfiles = %s\n[allan]\nkalibr = %s\n[report]\nformats = text, json\noutput = %s\n' "$SM" "$T/no/such/imu.yaml" "$T/rep" >"$T/fail.ini"
run "a later stage fails" 1 run -q "$T/fail.ini"
[ "$(cat "$T/rep"/* | cksum)" = "$old" ] && ok "the old report is untouched" || not_ok "the old report was changed"
lacks "no allan.json of the failed run" "$T/err" 'wrote'
no_temp "failed run" "$T"
run "run again replaces it" 0 run -q "$T/scene.ini"
[ -s "$T/rep/report.json" ] && ok "replaced" || not_ok "replaced"
no_temp "run again" "$T"
mkdir -p "$T/real"
ln -sfn real "$T/replink"
run "a linked report folder" 0 run -q -o "$T/replink" "$T/scene.ini"
[ -L "$T/replink" ] && [ -s "$T/real/report.json" ] && ok "the link is kept, its target written" || not_ok "linked report folder"
echo notes >"$T/rep/notes.txt"
run "a folder with other files" 2 run -q "$T/scene.ini"
one_err "a folder with other files" "holds 'notes.txt', which is not part of a report"
[ -s "$T/rep/notes.txt" ] && ok "notes kept" || not_ok "notes lost"
run "report folder is a file" 1 run -q -o "$T/cap.csv" "$T/scene.ini"
# a stage's output inside the report folder would leave with the old
# folder: refused before anything is written, the folder there or not
rm -f "$T/rep/notes.txt"
old=$(cat "$T/rep"/* | cksum)
for k in rep/imu.yaml rep/allan.json ./rep/../rep/imu.yaml; do
	printf '[input]\nfiles = %s\n[allan]\nkalibr = %s\n[report]\nformats = text, json\noutput = rep\n' "$SM" "$k" >"$T/inrep.ini"
	run "stage output $k in the report folder" 2 run -q "$T/inrep.ini"
	one_err "stage output $k in the report folder" "^sensorscope: run: kalibr = $T/$k: inside the report folder $T/rep, which is replaced as a whole"
done
[ "$(cat "$T/rep"/* | cksum)" = "$old" ] && ok "the report folder is untouched" || not_ok "the report folder was changed"
printf '[input]\nfiles = %s\n[allan]\nkalibr = newrep/imu.yaml\n[report]\noutput = newrep\n' "$SM" >"$T/inrep.ini"
run "stage output in a report folder not made yet" 2 run -q "$T/inrep.ini"
one_err "stage output in a report folder not made yet" "inside the report folder $T/newrep, which is replaced"
[ ! -e "$T/newrep" ] && ok "no folder made" || not_ok "a folder was made"

# ------------------------------------------------------------ 7. signals
# a long simulate interrupted: no temporary file, the old file kept
for sig in 2 15; do
	echo old >"$T/sig.csv"
	env --default-signal=INT "$SSCOPE" simulate -q --sensor "$T/s.ini" --rate 1000 --duration 20h -o "$T/sig.csv" &
	pid=$!
	i=0
	while ! ls "$T" | grep -q 'sig\.csv\.tmp\.' && [ $i -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
	kill -$sig $pid
	wait $pid
	got=$?
	want=$((128 + sig))
	[ $got -eq $want ] && ok "simulate: signal $sig re-raised (exit $got)" || not_ok "simulate: signal $sig (exit $got, wanted $want)"
	[ "$(cat "$T/sig.csv")" = old ] && ok "simulate: signal $sig: old file kept" || not_ok "simulate: signal $sig: old file lost"
	no_temp "simulate signal $sig" "$T"
done
# run interrupted while it waits for its input, and while a stage writes
# into a FIFO (files already in the staging folder): no staging folder left
rm -f "$T/fifo"
mkfifo "$T/fifo"
printf '[input]\nfiles = fifo\n[allan]\n[report]\noutput = sigrep\n' >"$T/sig1.ini"
"$SSCOPE" run -q "$T/sig1.ini" &
pid=$!
sleep 0.3
kill -TERM $pid
wait $pid
[ $? -eq 143 ] && ok "run: SIGTERM re-raised" || not_ok "run: SIGTERM"
no_temp "run SIGTERM while reading" "$T"
printf '[input]\nfiles = cap.csv\n[allan]\nkalibr = fifo\n[report]\noutput = sigrep\n' >"$T/sig2.ini"
env --default-signal=INT "$SSCOPE" run -q "$T/sig2.ini" &
pid=$!
i=0
while ! ls "$T"/sigrep.tmp.*/info.json >/dev/null 2>&1 && [ $i -lt 100 ]; do sleep 0.05; i=$((i + 1)); done
kill -INT $pid
wait $pid
[ $? -eq 130 ] && ok "run: SIGINT re-raised" || not_ok "run: SIGINT"
no_temp "run SIGINT with staged files" "$T"
[ ! -e "$T/sigrep" ] && ok "no half report folder" || not_ok "a half report folder"

# ------------------------------------------------------------ 10. ignored options
run "--dev-unit m/s on a deg/s channel" 2 allan --dev-unit m/s -c gx "$SM"
one_err "--dev-unit" "^sensorscope: allan: --dev-unit: 'm/s' does not fit the deviations of gx \\(deg/s\\)"
ss inclino calibrate --format csv "$CAL" >/dev/null 2>&1
printf 'not a table\n' >"$T/bad-tilts.txt"
run "--tilt-table BAD with reference columns" 1 inclino calibrate --tilt-table "$T/bad-tilts.txt" "$CAL"
has "--tilt-table given: the columns are not used" "$T/err" "warning: .*: --tilt-table gives the tilts: the reference columns 'roll_ref' and 'pitch_ref' are not used"
run "--tilt-table BAD, quiet" 1 inclino calibrate -q --tilt-table "$T/bad-tilts.txt" "$CAL"
one_err "--tilt-table BAD" "tilt-table: .*bad-tilts.txt:1: want 'START END ROLL PITCH'"
run "--scale without --raw" 2 info --scale 2 "$SM"
printf '[input]\nfiles = %s\nscale = 2\n[allan]\n' "$SM" >"$T/scale.ini"
run "scene scale without raw" 2 run --dry-run "$T/scale.ini"
run "run --format json" 2 run --format json "$T/scene.ini"
ss calib accel -q --save-calibration "$T/acc-cal.json" "$MP" >/dev/null 2>&1
run "report --calibration" 0 report -q -o "$T/calrep" --calibration "$T/acc-cal.json" "$MP"
json_check "report --calibration is applied" "$T/calrep/report.json" \
	'[.results.info.channels[] | select(.name == "ax") | .unit] == ["m/s^2"]' 
run "psd --spectrogram in text" 2 psd --spectrogram -c gx "$SM"
run "psd --spectrogram-columns alone" 2 psd --spectrogram-columns 10 -c gx "$SM"
run "psd periodogram --overlap" 2 psd --method periodogram --overlap 0.3 -c gx "$SM"
run "vibration --tolerance without --rpm" 2 vibration --tolerance 0.1 "$V"
run "budget --switch-time with open-loop" 2 budget --gyro-bias 1deg/h --model open-loop --switch-time 100
run "budget --seed without Monte Carlo" 2 budget --arw 0.1deg/sqrt\(h\) --monte-carlo 0 --seed 3
run "budget --turn-rate without a scale factor" 0 budget --gyro-bias 1deg/h --turn-rate 10deg/s
has "budget --turn-rate: warned" "$T/err" 'warning: the gyro scale-factor term needs both'
run "adc report --seed without Monte Carlo" 2 adc report --sensor "$QUIET" --adc "$A16" --monte-carlo 0 --seed 3
run "model fog with --mass" 2 model fog --radius 5cm --turns 1000 --wavelength 1550nm --mass 1
one_err "model fog with --mass" "^sensorscope: model: --mass: an option of 'model accel', not of 'model fog'"
run "calib --cubic in multipos" 2 calib accel --cubic "$MP"
run "calib --g-sensitivity for accel" 2 calib accel --g-sensitivity "$MP"
run "inclino apply --format json" 2 inclino apply --lut "$T/lut.json" --format json "$VAL"
run "inclino apply --plot" 2 inclino apply --lut "$T/lut.json" --plot "$T/a.svg" "$VAL"
run "simulate --digits with --binary" 2 simulate --sensor "$T/s.ini" --rate 10 --duration 1 --binary f32 --digits 5
run "simulate --temp-noise without temperature" 2 simulate --sensor "$T/s.ini" --rate 10 --duration 1 --temp-noise 0.1
run "simulate --hysteresis-band without --hysteresis" 2 simulate --sensor "$T/s.ini" --rate 10 --duration 1 --hysteresis-band 0.1

# ------------------------------------------------------------ 11. escaping
esc=$(printf '\033')
printf 't,g%s[2Jx [deg/s]\n0,1\n0.1,2\n0.2,3\n' "$esc" >"$T/esc.csv"
run "an escape sequence echoed" 1 allan -r 10 -c "$(printf 'a\033[2Jb')" "$T/esc.csv"
if grep -q "$esc" "$T/err"; then not_ok "no raw ESC on stderr"; diag "$T/err"; else ok "no raw ESC on stderr"; fi
has "ESC written as \\x1b" "$T/err" 'a\\x1b\[2Jb'
printf 't,gx [deg/s]\n0,1\n0.1,%sbad\n' "$esc" >"$T/esc2.csv"
ss info "$T/esc2.csv" >/dev/null 2>"$T/err"
if grep -q "$esc" "$T/err"; then not_ok "bad cell: no raw ESC"; diag "$T/err"; else ok "bad cell: no raw ESC"; fi
printf '{"format": "sensorscope-calibration", "triads": [{"kind": "\033]0;pwned\007"}]}\n' >"$T/cal.json"
ss info --calibration "$T/cal.json" "$SM" >/dev/null 2>"$T/err"
if grep -q "$(printf '\007')" "$T/err" || grep -q "$esc" "$T/err"; then not_ok "--calibration: no raw control bytes"; diag "$T/err"; else ok "--calibration: no raw control bytes"; fi
# C1 controls and bytes that are not UTF-8 are escaped; UTF-8 text is kept
run "C1 and invalid bytes" 1 allan -r 10 -c "$(printf 'x\302\233y\377z\303\251')" "$T/esc.csv"
has "C1 escaped, invalid byte escaped, UTF-8 kept" "$T/err" 'x\\xc2\\x9by\\xffz'"$(printf '\303\251')"
# a 4 KB scene value is cut
long=$(head -c 4096 /dev/zero | tr '\0' A)
printf '[input]\nfiles = %s\n[allan]\ntaus = %s\n' "$SM" "$long" >"$T/long.ini"
run "a 4 KB scene value" 2 run --dry-run "$T/long.ini"
one_err "a 4 KB scene value" "'A{48}\\.\\.\\.' \\(4096 bytes\\) is not"
[ "$(wc -c <"$T/err")" -lt 300 ] && ok "the line is short" || not_ok "the line is $(wc -c <"$T/err") bytes"

# ------------------------------------------------------------ 12. the rest
run "-o ''" 2 info -o '' "$SM"
one_err "-o ''" "^sensorscope: info: -o: an empty file name"
run "--kalibr ''" 2 allan --kalibr '' "$SM"
# a read-only folder: the real reason (as root, the check runs as nobody)
mkdir -p "$T/ro"
cp "$SM" "$T/ro/in.csv"
chmod 755 "$T"
chmod 555 "$T/ro"
if [ "$(id -u)" != 0 ]; then asuser=; elif command -v setpriv >/dev/null 2>&1; then
	asuser="setpriv --reuid=65534 --regid=65534 --clear-groups"; else asuser=none; fi
if [ "$asuser" = none ]; then
	skip "read-only folder" "root without setpriv"
else
	$asuser "$SSCOPE" info -q -o "$T/ro/x.txt" "$T/ro/in.csv" >/dev/null 2>"$T/err"
	[ $? -eq 1 ] && ok "-o in a read-only folder (exit 1)" || not_ok "-o in a read-only folder"
	one_err "-o in a read-only folder" "^sensorscope: info: $T/ro/x.txt: permission denied$"
	$asuser "$SSCOPE" info -q --plot "$T/ro/x.svg" "$T/ro/in.csv" >/dev/null 2>"$T/err"
	[ $? -eq 1 ] && ok "--plot in a read-only folder (exit 1)" || not_ok "--plot in a read-only folder"
	one_err "--plot in a read-only folder" "^sensorscope: info: $T/ro/x.svg: permission denied$"
fi
chmod 755 "$T/ro"
# errors inside run name the command, then the stage
run "an error inside run" 1 run -q -o "$T/rep2" "$T/fail.ini"
[ ! -e "$T/rep2" ] && ok "a failed run makes no report folder" || not_ok "a failed run made a folder"
one_err "an error inside run" "^sensorscope: run: allan: $T/no/such/imu.yaml: no such file or directory$"
printf '[input]\nfiles = %s\n[allan]\ntaus = weekly\n' "$SM" >"$T/badkey.ini"
run "a stage option error inside run" 2 run --dry-run "$T/badkey.ini"
one_err "a stage option error inside run" "^sensorscope: run: allan: $T/badkey.ini: line 4: taus: "
# files named like an analysis' but no report beside them are the user's
mkdir -p "$T/notes"
echo "my notes" >"$T/notes/calib.json"
echo "a,b" >"$T/notes/psd.csv"
run "a folder of the user's files named like a report's" 2 run -o "$T/notes" "$SAMPLES/bearing.scene.ini"
has "the user's folder: refused, said" "$T/err" "holds '(calib.json|psd.csv)' but no report"
has "the user's files kept" "$T/notes/calib.json" '^my notes$'
# a report of figures only is still the next run's to replace
printf '[input]\nfiles = %s\n[allan]\n[report]\nformats = svg\n' "$SAMPLES/gyro-static.csv" >"$T/svgonly.ini"
run "a report of figures only" 0 run -q -o "$T/svgonly" "$T/svgonly.ini"
run "the same report again" 0 run -q -o "$T/svgonly" "$T/svgonly.ini"

done_testing
