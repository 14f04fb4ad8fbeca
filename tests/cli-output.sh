#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Outputs that never destroy data: a failed write is one line with the
# errno's text for every command and output size; -o, --plot, --kalibr,
# --save-calibration and report folders write through FIFOs, devices and
# standard output, replace a link's target (the link kept), never replace
# an input (exit 2 before anything is written); a report folder is put in
# place only when every stage succeeded; SIGINT/SIGTERM leave no temporary
# files or staging folders.
# Report folders, signals, ignored options and escaping are in
# cli-output-folders.sh.
. "$(dirname "$0")/lib.sh"
. "$(dirname "$0")/output.sh"

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
	one_err "$name > /dev/full" "^sensorscope: [a-z ]+: standard output: no space left on device$"
	ss "$@" -o /dev/full >"$T/out" 2>"$T/err"
	got=$?
	if [ $got -eq 1 ]; then ok "$name -o /dev/full (exit 1)"; else not_ok "$name -o /dev/full (exit $got, wanted 1)"; fi
	one_err "$name -o /dev/full" "^sensorscope: [a-z ]+: /dev/full: no space left on device$"
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
one_err "acquire -o /dev/full" '^sensorscope: acquire: /dev/full: no space left on device$'
ss acquire -q --source sim:speed=max --count 20000 -o - >/dev/full 2>"$T/err"
[ $? -eq 1 ] && ok "acquire -o - > /dev/full (exit 1)" || not_ok "acquire -o - > /dev/full"
has "acquire -o - > /dev/full: said" "$T/err" '^sensorscope: acquire: standard output: no space left on device$'
ss acquire -q --source sim:speed=max --count 100 -o "$T/acq.csv" >/dev/full 2>"$T/err"
[ $? -eq 1 ] && ok "acquire summary > /dev/full (exit 1)" || not_ok "acquire summary > /dev/full"
one_err "acquire summary > /dev/full" '^sensorscope: acquire: standard output: no space left on device$'

ss info --help >/dev/full 2>"$T/err"
[ $? -eq 1 ] && ok "--help > /dev/full (exit 1)" || not_ok "--help > /dev/full"
one_err "--help > /dev/full" '^sensorscope: info: standard output: no space left on device$'
ss run --dry-run "$T/scene.ini" >/dev/full 2>"$T/err"
[ $? -eq 1 ] && ok "run --dry-run > /dev/full (exit 1)" || not_ok "run --dry-run > /dev/full"
one_err "run --dry-run > /dev/full" '^sensorscope: run: standard output: no space left on device$'

# a full file system for a regular file (the size limit stands in for
# it): the old file is kept, no temporary file is left
echo "old" >"$T/keep.csv"
(trap '' XFSZ; ulimit -f 64; exec "$SSCOPE" simulate -q --sensor "$T/s.ini" --rate 1000 --duration 100 -o "$T/keep.csv") 2>"$T/err"
got=$?
[ $got -eq 1 ] && ok "simulate over the size limit (exit 1)" || not_ok "simulate over the size limit (exit $got)"
one_err "simulate over the size limit" "^sensorscope: simulate: $T/keep.csv: file too large$"
[ "$(cat "$T/keep.csv")" = old ] && ok "the old file is kept" || not_ok "the old file is kept"
no_temp "size limit" "$T"
# an output that cannot fit in the free space (about 40 TB): refused after
# its first rows, with both sizes, the old file kept, nothing left behind
"$SSCOPE" simulate -q --sensor "$T/s.ini" --rate 1e9 --duration 999 -o "$T/keep.csv" 2>"$T/err"
[ $? -eq 1 ] && ok "simulate larger than the free space (exit 1)" || not_ok "simulate larger than the free space"
one_err "simulate larger than the free space" "^sensorscope: simulate: $T/keep.csv: about [0-9.]+ TB to write, [0-9.]+ [kMGT]?B free on its file system: shorten --duration, lower --rate or write --binary f32$"
[ "$(cat "$T/keep.csv")" = old ] && ok "free space: the old file is kept" || not_ok "free space: the old file is kept"
no_temp "free space" "$T"
(trap '' XFSZ; ulimit -f 64; exec "$SSCOPE" psd -q --format csv --nperseg 65536 -o "$T/keep.csv" "$V") 2>"$T/err"
[ $? -eq 1 ] && ok "psd csv over the size limit (exit 1)" || not_ok "psd csv over the size limit"
one_err "psd csv over the size limit" "^sensorscope: psd: $T/keep.csv: file too large$"
no_temp "psd size limit" "$T"

# the other writing options
run "--kalibr /dev/full" 1 allan -q -c gx --kalibr /dev/full "$SM"
one_err "--kalibr /dev/full" '^sensorscope: allan: /dev/full: no space left on device$'
run "--save-calibration /dev/full" 1 calib accel -q --save-calibration /dev/full "$MP"
one_err "--save-calibration /dev/full" '^sensorscope: calib accel: /dev/full: no space left on device$'
ln -sf /dev/full "$T/full.svg"
run "--plot through a link to /dev/full" 1 info -q --plot "$T/full.svg" "$SM"
one_err "--plot through a link to /dev/full" "^sensorscope: info: $T/full.svg: no space left on device$"
[ -L "$T/full.svg" ] && [ -c /dev/full ] && ok "the link and /dev/full are kept" || not_ok "the link or /dev/full replaced"
run "--plot into a missing folder" 1 info -q --plot "$T/no/such.svg" "$SM"
one_err "--plot into a missing folder" "^sensorscope: info: --plot $T/no/such.svg: no folder $T/no to write it in$"
# one output into a missing folder: said before any work, no other output
# left written
rm -f "$T/side.svg"
run "--plot and --kalibr into a missing folder" 1 allan -q -c gx --plot "$T/side.svg" \
	--kalibr "$T/no/k.yaml" "$SM"
[ ! -e "$T/side.svg" ] && ok "no figure left when another output cannot be written" ||
	not_ok "the figure was written before the refusal"

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
one_err "-o a folder" ": is a directory$"
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
done_testing
