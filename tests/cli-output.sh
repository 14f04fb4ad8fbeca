#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Outputs that never destroy data: a failed write is one line with the
# errno's text for every command and output size; -o, --plot, --kalibr,
# --save-calibration and report folders write through FIFOs, devices and
# standard output, replace a link's target (the link kept), never replace
# an input (exit 2 before anything is written); a report folder is put in
# place only when every stage succeeded; SIGINT/SIGTERM leave no temporary
# files or staging folders.
. "$(dirname "$0")/lib.sh"

G="$SAMPLES/gyro-static.csv"
V="$SAMPLES/vibration.csv"
AT="$SAMPLES/accel-thermal.csv"
MP="$SAMPLES/imu-multipose.csv"
CAL="$SAMPLES/inclino-cal.csv"
VAL="$SAMPLES/inclino-val.csv"
QUIET="$SAMPLES/gyro-textbook-quiet.ini"
A16="$SAMPLES/adc-textbook-16bit.ini"
# a short capture for the many runs that only test where output goes
head -n 3000 "$G" >"$T/small.csv"
SM="$T/small.csv"
printf '[sensor]\nname = g\nnoise_density = 0.1 deg/sqrt(h)\nbias_instability = 5 deg/h\n' >"$T/s.ini"
ss inclino calibrate -o "$T/lut.json" "$CAL" 2>/dev/null
printf '[input]\nfiles = %s\n[allan]\n[report]\nformats = text, json\noutput = %s\n' "$SM" "$T/rep" >"$T/scene.ini"

# one_err DESC PATTERN: stderr is exactly one line matching PATTERN
one_err() {
	if [ "$(wc -l <"$T/err")" -eq 1 ] && grep -Eq -- "$2" "$T/err"; then
		ok "$1: one line '$2'"
	else
		not_ok "$1: stderr is not one line '$2'"
		diag "$T/err"
	fi
}

# no_temp DESC DIR: no temporary file or staging folder left in DIR
no_temp() {
	if ls -a "$2" | grep -q '\.tmp\.'; then
		not_ok "$1: temporary files left"
		ls -la "$2" | diag
	else
		ok "$1: no temporary file left"
	fi
}

# ------------------------------------------------------------ 3. write errors
# every command, to standard output and to -o, on /dev/full: exit 1 and one
# line with the errno's text (outputs from 100 bytes to 4 MB)
# the first word of each line is a label, the rest the arguments
while read -r name args; do
	[ -n "$name" ] || continue
	# shellcheck disable=SC2086
	eval "set -- $args"
	ss "$@" >/dev/full 2>"$T/err"
	got=$?
	if [ $got -eq 1 ]; then ok "$name > /dev/full (exit 1)"; else not_ok "$name > /dev/full (exit $got, wanted 1)"; fi
	one_err "$name > /dev/full" "^sensorscope: [a-z ]+: standard output: No space left on device$"
	ss "$@" -o /dev/full >"$T/out" 2>"$T/err"
	got=$?
	if [ $got -eq 1 ]; then ok "$name -o /dev/full (exit 1)"; else not_ok "$name -o /dev/full (exit $got, wanted 1)"; fi
	one_err "$name -o /dev/full" "^sensorscope: [a-z ]+: /dev/full: No space left on device$"
done <<EOF
info info -q "$SM"
info-json info -q --format json "$SM"
allan allan -q -c gx "$SM"
psd psd -q -c gx "$SM"
psd-csv-large psd -q --format csv --nperseg 65536 "$V"
vibration vibration -q "$V"
tempbias tempbias -q "$AT"
calib calib accel -q "$MP"
budget budget -q --gyro-bias 10deg/h --time 120
inclino-calibrate inclino calibrate -q "$CAL"
inclino-apply-large inclino apply -q --lut "$T/lut.json" "$VAL"
adc-report adc report -q --sensor "$QUIET" --adc "$A16" --monte-carlo 0
adc-quantize-large adc quantize -q --bits 12 --range -100:100 "$G"
simulate simulate -q --sensor "$T/s.ini" --rate 10 --duration 10
simulate-large simulate -q --sensor "$T/s.ini" --rate 1000 --duration 200
model model accel -q --fn 2.4kHz --zeta 0.7
EOF
# acquire: the capture and its summary
ss acquire -q --source sim:speed=max --count 20000 -o /dev/full >"$T/out" 2>"$T/err"
[ $? -eq 1 ] && ok "acquire -o /dev/full (exit 1)" || not_ok "acquire -o /dev/full"
one_err "acquire -o /dev/full" '^sensorscope: acquire: /dev/full: No space left on device$'
ss acquire -q --source sim:speed=max --count 20000 -o - >/dev/full 2>"$T/err"
[ $? -eq 1 ] && ok "acquire -o - > /dev/full (exit 1)" || not_ok "acquire -o - > /dev/full"
has "acquire -o - > /dev/full: said" "$T/err" '^sensorscope: acquire: standard output: No space left on device$'
ss acquire -q --source sim:speed=max --count 100 -o "$T/acq.csv" >/dev/full 2>"$T/err"
[ $? -eq 1 ] && ok "acquire summary > /dev/full (exit 1)" || not_ok "acquire summary > /dev/full"
one_err "acquire summary > /dev/full" '^sensorscope: acquire: standard output: No space left on device$'

ss info --help >/dev/full 2>"$T/err"
[ $? -eq 1 ] && ok "--help > /dev/full (exit 1)" || not_ok "--help > /dev/full"
one_err "--help > /dev/full" '^sensorscope: info: standard output: No space left on device$'
ss run --dry-run "$T/scene.ini" >/dev/full 2>"$T/err"
[ $? -eq 1 ] && ok "run --dry-run > /dev/full (exit 1)" || not_ok "run --dry-run > /dev/full"
one_err "run --dry-run > /dev/full" '^sensorscope: run: standard output: No space left on device$'

# a full file system for a regular file (the size limit stands in for
# it): the old file is kept, no temporary file is left
echo "old" >"$T/keep.csv"
(trap '' XFSZ; ulimit -f 64; exec "$SSCOPE" simulate -q --sensor "$T/s.ini" --rate 1000 --duration 100 -o "$T/keep.csv") 2>"$T/err"
got=$?
[ $got -eq 1 ] && ok "simulate over the size limit (exit 1)" || not_ok "simulate over the size limit (exit $got)"
one_err "simulate over the size limit" "^sensorscope: simulate: $T/keep.csv: File too large$"
[ "$(cat "$T/keep.csv")" = old ] && ok "the old file is kept" || not_ok "the old file is kept"
no_temp "size limit" "$T"
(trap '' XFSZ; ulimit -f 64; exec "$SSCOPE" psd -q --format csv --nperseg 65536 -o "$T/keep.csv" "$V") 2>"$T/err"
[ $? -eq 1 ] && ok "psd csv over the size limit (exit 1)" || not_ok "psd csv over the size limit"
one_err "psd csv over the size limit" "^sensorscope: psd: $T/keep.csv: File too large$"
no_temp "psd size limit" "$T"

# the other writing options
run "--kalibr /dev/full" 1 allan -q -c gx --kalibr /dev/full "$SM"
one_err "--kalibr /dev/full" '^sensorscope: allan: /dev/full: No space left on device$'
run "--save-calibration /dev/full" 1 calib accel -q --save-calibration /dev/full "$MP"
one_err "--save-calibration /dev/full" '^sensorscope: calib accel: /dev/full: No space left on device$'
ln -sf /dev/full "$T/full.svg"
run "--plot through a link to /dev/full" 1 info -q --plot "$T/full.svg" "$SM"
one_err "--plot through a link to /dev/full" "^sensorscope: info: $T/full.svg: No space left on device$"
[ -L "$T/full.svg" ] && [ -c /dev/full ] && ok "the link and /dev/full are kept" || not_ok "the link or /dev/full replaced"
run "--plot into a missing folder" 1 info -q --plot "$T/no/such.svg" "$SM"
one_err "--plot into a missing folder" "^sensorscope: info: $T/no/such.svg: No such file or directory$"

# ------------------------------------------------------------ 4. write through
# -o and the writing options through a device, a FIFO, standard output and
# a link; the device stays a device, the FIFO a FIFO, the link a link
for o in "info -q -o" "allan -q -c gx --kalibr" "calib accel -q --save-calibration" \
	 "simulate -q --sensor $T/s.ini --rate 10 --duration 5 -o"; do
	set -- $o
	case $1 in calib) in=$MP ;; simulate) in= ;; *) in=$SM ;; esac
	label="$1 $(eval echo "\${$#}")"
	run "$label /dev/null" 0 "$@" /dev/null $in
	if [ -c /dev/null ]; then ok "$label: /dev/null is still a device"; else not_ok "$label: /dev/null replaced"; fi
	rm -f "$T/fifo" "$T/got"
	mkfifo "$T/fifo"
	timeout 20 cat "$T/fifo" >"$T/got" &
	reader=$!
	run "$label FIFO" 0 "$@" "$T/fifo" $in
	wait $reader
	[ -p "$T/fifo" ] && ok "$label: the FIFO is still a FIFO" || not_ok "$label: the FIFO was replaced"
	[ -s "$T/got" ] && ok "$label: the FIFO's reader got the output" || not_ok "$label: the FIFO's reader got nothing"
	echo old >"$T/target"
	ln -sf target "$T/link"
	run "$label link" 0 "$@" "$T/link" $in
	[ -L "$T/link" ] && [ "$(readlink "$T/link")" = target ] && ok "$label: the link is still a link" || not_ok "$label: the link was replaced"
	[ "$(cat "$T/target")" != old ] && [ -s "$T/target" ] && ok "$label: the link's target was written" || not_ok "$label: the link's target was not written"
	rm -f "$T/target"
	run "$label dangling link" 0 "$@" "$T/link" $in
	[ -L "$T/link" ] && [ -s "$T/target" ] && ok "$label: a dangling link's target is created" || not_ok "$label: dangling link"
	no_temp "$label" "$T"
done
run "-o /dev/stdout" 0 info -q -o /dev/stdout "$SM"
has "-o /dev/stdout writes standard output" "$T/out" 'rows: +2997'
run "-o -" 0 info -q -o - "$SM"
has "-o - writes standard output" "$T/out" 'rows: +2997'
chmod 640 "$T/target"
run "replacing keeps the mode" 0 info -q -o "$T/target" "$SM"
[ "$(stat -c %a "$T/target")" = 640 ] && ok "mode 640 kept" || not_ok "mode $(stat -c %a "$T/target") instead of 640"
# a file with another hard link: written in place, both names share it
echo old >"$T/hl-a.txt"
ln -f "$T/hl-a.txt" "$T/hl-b.txt"
run "-o a file with another hard link" 0 info -q -o "$T/hl-b.txt" "$SM"
[ "$(stat -c %i "$T/hl-a.txt")" = "$(stat -c %i "$T/hl-b.txt")" ] && cmp -s "$T/hl-a.txt" "$T/hl-b.txt" &&
	grep -q 'rows: *2997' "$T/hl-a.txt" && ok "hard link: both names share the new content" ||
	not_ok "hard link: the names were parted"
run "-o a shorter output over a hard-linked file" 0 info -q --format json -o "$T/hl-a.txt" "$SM"
ss info -q --format json "$SM" >"$T/hl-want.json" 2>/dev/null
cmp -s "$T/hl-b.txt" "$T/hl-want.json" && ok "hard link: cut to the new size" || not_ok "hard link: old bytes left after the new content"
no_temp "hard link" "$T"
run "-o a folder" 1 info -q -o "$T" "$SM"
one_err "-o a folder" ": Is a directory$"
rm -f "$T/fifo.svg" "$T/got"
mkfifo "$T/fifo.svg"
timeout 20 cat "$T/fifo.svg" >"$T/got" &
reader=$!
run "--plot FIFO" 0 info -q --plot "$T/fifo.svg" "$SM"
wait $reader
[ -p "$T/fifo.svg" ] && grep -q '^<svg' "$T/got" && ok "--plot: the FIFO got the figure" || not_ok "--plot: FIFO"
ln -sf fig.svg "$T/figlink.svg"
run "--plot link" 0 info -q --plot "$T/figlink.svg" "$SM"
[ -L "$T/figlink.svg" ] && [ -s "$T/fig.svg" ] && ok "--plot: the link's target is written" || not_ok "--plot: link"
ln -sf /dev/null "$T/null.svg"
run "--plot a link to /dev/null" 0 info -q --plot "$T/null.svg" "$SM"
[ -c /dev/null ] && ok "--plot: /dev/null is still a device" || not_ok "--plot: /dev/null replaced"
if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	rm -f "$T/fifo.png" "$T/got"
	mkfifo "$T/fifo.png"
	timeout 20 cat "$T/fifo.png" >"$T/got" &
	reader=$!
	run "--plot FIFO (PNG)" 0 info -q --plot "$T/fifo.png" "$SM"
	wait $reader
	[ -p "$T/fifo.png" ] && head -c 8 "$T/got" | grep -q PNG && ok "--plot: the FIFO got the PNG" || not_ok "--plot: FIFO (PNG)"
else
	skip "--plot FIFO (PNG)" "built without OpenCV"
fi

# ------------------------------------------------------------ 5. input = output
cp "$SM" "$T/cap.csv"
cp "$MP" "$T/mp.csv"
cp "$T/s.ini" "$T/spec.ini"
sum_before=$(cat "$T/cap.csv" "$T/mp.csv" "$T/spec.ini" "$T/lut.json" | cksum)
run "info -o cap.csv cap.csv" 2 info -o "$T/cap.csv" "$T/cap.csv"
one_err "info -o cap.csv cap.csv" "^sensorscope: info: -o $T/cap.csv: the same file as the input $T/cap.csv: refusing to overwrite an input$"
run "calib --save-calibration mp.csv mp.csv" 2 calib accel --save-calibration "$T/mp.csv" "$T/mp.csv"
one_err "--save-calibration input" "refusing to overwrite an input"
run "--kalibr input" 2 allan --kalibr "$T/cap.csv" "$T/cap.csv"
cp "$T/cap.csv" "$T/capin.svg"
run "--plot input" 2 info --plot "$T/capin.svg" "$T/capin.svg"
ln -sf cap.csv "$T/cap.svg"
run "--plot through a link to the input" 2 info --plot "$T/cap.svg" "$T/cap.csv"
ln -f "$T/cap.csv" "$T/hard.csv"
run "-o a hard link of the input" 2 info -o "$T/hard.csv" "$T/cap.csv"
run "simulate -o its spec" 2 simulate --sensor "$T/spec.ini" --rate 10 --duration 1 -o "$T/spec.ini"
run "adc quantize -o input" 2 adc quantize --bits 12 --range -100:100 -o "$T/cap.csv" "$T/cap.csv"
run "inclino apply -o its LUT" 2 inclino apply --lut "$T/lut.json" -o "$T/lut.json" "$VAL"
run "budget --result X -o X" 2 budget --result "$T/lut.json" -o "$T/lut.json"
run "-o the input read from standard input" 2 info -o "$T/cap.csv" - <"$T/cap.csv"
one_err "stdin" "the same file as the input \\(standard input\\)"
ss info "$T/cap.csv" >>"$T/cap.csv" 2>"$T/err"
[ $? -eq 2 ] && ok "stdout appended to the input (exit 2)" || not_ok "stdout appended to the input"
one_err "stdout appended to the input" "^sensorscope: info: standard output: the same file as the input"
run "two outputs, one file" 2 allan -c gx --plot "$T/x.svg" -o "$T/x.svg" "$SM"
one_err "two outputs, one file" "the same file: give each output its own"
run "report into the folder of its input" 2 report -o "$T" "$T/cap.csv"
one_err "report into the folder of its input" "holds the input"
printf '[input]\nfiles = cap.csv\n[allan]\n[report]\noutput = .\n' >"$T/dot.ini"
run "scene report folder holds its input" 2 run "$T/dot.ini"
printf '[input]\nfiles = cap.csv\n[allan]\nkalibr = cap.csv\n' >"$T/kal.ini"
run "scene stage writes over its input" 2 run -o "$T/kalrep" "$T/kal.ini"
[ "$(cat "$T/cap.csv" "$T/mp.csv" "$T/spec.ini" "$T/lut.json" | cksum)" = "$sum_before" ] &&
	ok "every input survived" || not_ok "an input was changed"
[ ! -e "$T/kalrep" ] && ok "nothing written before the refusal" || not_ok "the report folder was made"

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
	one_err "stage output $k in the report folder" "^sensorscope: run: --kalibr $T/$k: inside the report folder $T/rep, which is replaced as a whole"
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
	one_err "-o in a read-only folder" "^sensorscope: info: $T/ro/x.txt: Permission denied$"
	$asuser "$SSCOPE" info -q --plot "$T/ro/x.svg" "$T/ro/in.csv" >/dev/null 2>"$T/err"
	[ $? -eq 1 ] && ok "--plot in a read-only folder (exit 1)" || not_ok "--plot in a read-only folder"
	one_err "--plot in a read-only folder" "^sensorscope: info: $T/ro/x.svg: Permission denied$"
fi
chmod 755 "$T/ro"
# errors inside run name the command, then the stage
run "an error inside run" 1 run -q -o "$T/rep2" "$T/fail.ini"
[ ! -e "$T/rep2" ] && ok "a failed run makes no report folder" || not_ok "a failed run made a folder"
one_err "an error inside run" "^sensorscope: run: allan: $T/no/such/imu.yaml: No such file or directory$"
printf '[input]\nfiles = %s\n[allan]\ntaus = weekly\n' "$SM" >"$T/badkey.ini"
run "a stage option error inside run" 2 run --dry-run "$T/badkey.ini"
one_err "a stage option error inside run" "^sensorscope: run: allan: $T/badkey.ini: line 4: --taus: "
done_testing
