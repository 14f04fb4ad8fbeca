#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Every option that writes a file, of every command (issue 13, "must
# show"): what the user owns survives it.  For each command and option:
#   a device      OPT /dev/null: exit 0, /dev/null still a character device;
#   a FIFO        OPT FIFO (a reader on it): exit 0, still a FIFO, the reader
#                 got the output;
#   a link        OPT LINK -> TARGET: exit 0, the link still a link to
#                 TARGET, TARGET holds the new output;
#   an input      OPT INPUT (the capture or spec the command reads): exit 2,
#                 one line, the input byte for byte as it was.
# Report folders (run -o, report -o) are folders, not files: a link to a
# folder and a folder holding the input are tested in cli-output.sh.
. "$(dirname "$0")/lib.sh"

G="$SAMPLES/gyro-static.csv"
head -n 2000 "$G" >"$T/g.csv"
cp "$SAMPLES/vibration.csv" "$T/v.csv"
cp "$SAMPLES/accel-thermal.csv" "$T/at.csv"
cp "$SAMPLES/imu-multipose.csv" "$T/mp.csv"
cp "$SAMPLES/inclino-cal.csv" "$T/cal.csv"
cp "$SAMPLES/inclino-val.csv" "$T/val.csv"
cp "$SAMPLES/drive-stops.csv" "$T/drive.csv"
cp "$SAMPLES/euroc-imu.csv" "$T/euroc.csv"
cp "$SAMPLES/gyro-textbook-quiet.ini" "$T/quiet.ini"
cp "$SAMPLES/adc-textbook-16bit.ini" "$T/a16.ini"
printf '[sensor]\nname = g\nnoise_density = 0.1 deg/sqrt(h)\nbias_instability = 5 deg/h\n' >"$T/s.ini"
ss inclino calibrate -q -o "$T/lut.json" "$T/cal.csv" 2>/dev/null
printf '[sensor]\nname = quiet\nnoise_density = 1e-6 deg/sqrt(h)\n' >"$T/sine.ini"
ss simulate -q --sensor "$T/sine.ini" --rate 1000 --duration 2.048 --tone 37.1234:0.999 \
	--no-clip -o "$T/sine.csv" 2>/dev/null
ss adc quantize -q --bits 10 --range -1:1 -o "$T/sq.csv" "$T/sine.csv" 2>/dev/null

# check LABEL INPUT ARGS...: ARGS with @OUT@ where the output goes; INPUT
# is a file among ARGS (or -).  Figures (--plot) are named *.svg, so their
# device is reached through a link named *.svg, and the input is a copy
# named *.svg given both as input and as output.
check() {
	label=$1 input=$2
	shift 2
	args=$*
	case $label in *--plot*) sfx=.svg ;; *) sfx= ;; esac
	# a device
	dev=/dev/null
	if [ -n "$sfx" ]; then
		rm -f "$T/dev$sfx"
		ln -s /dev/null "$T/dev$sfx"
		dev=$T/dev$sfx
	fi
	# shellcheck disable=SC2086
	eval "set -- $(echo "$args" | sed "s|@OUT@|$dev|g")"
	run "$label /dev/null" 0 "$@"
	[ -c /dev/null ] && ok "$label: /dev/null is still a device" || not_ok "$label: /dev/null replaced"
	# a FIFO with a reader
	rm -f "$T/fifo$sfx" "$T/got"
	mkfifo "$T/fifo$sfx"
	timeout 60 cat "$T/fifo$sfx" >"$T/got" &
	reader=$!
	eval "set -- $(echo "$args" | sed "s|@OUT@|$T/fifo$sfx|g")"
	run "$label FIFO" 0 "$@"
	[ "$got" -eq 0 ] || (: >"$T/fifo$sfx" &) # never opened: release the reader
	wait $reader
	[ -p "$T/fifo$sfx" ] && ok "$label: the FIFO is still a FIFO" || not_ok "$label: the FIFO was replaced"
	[ -s "$T/got" ] && ok "$label: the FIFO's reader got the output" || not_ok "$label: the FIFO's reader got nothing"
	# a symbolic link: its target replaced, the link kept
	echo old >"$T/target$sfx"
	rm -f "$T/link$sfx"
	ln -s "target$sfx" "$T/link$sfx"
	eval "set -- $(echo "$args" | sed "s|@OUT@|$T/link$sfx|g")"
	run "$label link" 0 "$@"
	[ -L "$T/link$sfx" ] && [ "$(readlink "$T/link$sfx")" = "target$sfx" ] && ok "$label: the link is still a link" || not_ok "$label: the link was replaced"
	[ -s "$T/target$sfx" ] && [ "$(cat "$T/target$sfx")" != old ] && ok "$label: the link's target holds the output" || not_ok "$label: the link's target was not written"
	if ls -a "$T" | grep -q '\.tmp\.'; then not_ok "$label: temporary files left"; else ok "$label: no temporary file left"; fi
	# the input itself
	[ "$input" = - ] && return
	in=$input
	if [ -n "$sfx" ]; then
		in=$T/asinput$sfx
		cp "$input" "$in"
	fi
	sum=$(cksum <"$in")
	eval "set -- $(echo "$args" | sed -e "s|$input|$in|g" -e "s|@OUT@|$in|g")"
	run "$label over its input" 2 "$@"
	one_line_error "$label over its input"
	has "$label over its input: said" "$T/err" "refusing to overwrite an input"
	[ "$(cksum <"$in")" = "$sum" ] && ok "$label: the input survived" || not_ok "$label: the input was changed"
}

check "info -o" "$T/g.csv" info -q -o @OUT@ "$T/g.csv"
check "info --plot" "$T/g.csv" info -q --plot @OUT@ "$T/g.csv"
check "allan -o" "$T/g.csv" allan -q -c gx -o @OUT@ "$T/g.csv"
check "allan --plot" "$T/g.csv" allan -q -c gx --plot @OUT@ "$T/g.csv"
check "allan --kalibr" "$T/g.csv" allan -q -c gx --kalibr @OUT@ "$T/g.csv"
check "allan --openvins" "$T/euroc.csv" allan -q --openvins @OUT@ "$T/euroc.csv"
check "allan --imu-utils" "$T/g.csv" allan -q -c gx --imu-utils @OUT@ "$T/g.csv"
check "psd -o" "$T/v.csv" psd -q -o @OUT@ "$T/v.csv"
check "psd --plot" "$T/v.csv" psd -q --plot @OUT@ "$T/v.csv"
check "vibration -o" "$T/v.csv" vibration -q -o @OUT@ "$T/v.csv"
check "vibration --plot" "$T/v.csv" vibration -q --plot @OUT@ "$T/v.csv"
check "tempbias -o" "$T/at.csv" tempbias -q -o @OUT@ "$T/at.csv"
check "tempbias --plot" "$T/at.csv" tempbias -q --plot @OUT@ "$T/at.csv"
check "calib -o" "$T/mp.csv" calib accel -q -o @OUT@ "$T/mp.csv"
check "calib --plot" "$T/mp.csv" calib accel -q --plot @OUT@ "$T/mp.csv"
check "calib --save-calibration" "$T/mp.csv" calib accel -q --save-calibration @OUT@ "$T/mp.csv"
check "inclino calibrate -o" "$T/cal.csv" inclino calibrate -q -o @OUT@ "$T/cal.csv"
check "inclino calibrate --plot" "$T/cal.csv" inclino calibrate -q --plot @OUT@ "$T/cal.csv"
check "inclino apply -o" "$T/val.csv" inclino apply -q --lut "$T/lut.json" -o @OUT@ "$T/val.csv"
check "inclino apply -o (the LUT)" "$T/lut.json" inclino apply -q --lut "$T/lut.json" -o @OUT@ "$T/val.csv"
check "adc report -o" "$T/a16.ini" adc report -q --sensor "$T/quiet.ini" --adc "$T/a16.ini" --monte-carlo 0 -o @OUT@
check "adc report --plot" "$T/quiet.ini" adc report -q --sensor "$T/quiet.ini" --adc "$T/a16.ini" --monte-carlo 1 --plot @OUT@
check "adc quantize -o" "$T/g.csv" adc quantize -q --bits 12 --range -100:100 -o @OUT@ "$T/g.csv"
check "adc test -o" "$T/sq.csv" adc test -q --bits 10 --range -1:1 -o @OUT@ "$T/sq.csv"
check "adc test --plot" "$T/sq.csv" adc test -q --bits 10 --range -1:1 --plot @OUT@ "$T/sq.csv"
check "simulate -o" "$T/s.ini" simulate -q --sensor "$T/s.ini" --rate 10 --duration 5 -o @OUT@
check "budget -o" "$T/s.ini" budget -q --sensor "$T/s.ini" --time 60 -o @OUT@
check "budget --plot" "$T/s.ini" budget -q --sensor "$T/s.ini" --time 60,600 --plot @OUT@
check "model -o" - model accel -q --fn 2.4kHz --zeta 0.7 -o @OUT@
check "model --plot" - model accel -q --fn 2.4kHz --zeta 0.7 --plot @OUT@
check "navsim -o" - navsim -q --runs 2 --duration 20 -o @OUT@
check "navsim --plot" - navsim -q --runs 2 --duration 20 --plot @OUT@
check "heading -o" "$T/drive.csv" heading -q --reference heading_ref -o @OUT@ "$T/drive.csv"
check "heading --plot" "$T/drive.csv" heading -q --reference heading_ref --plot @OUT@ "$T/drive.csv"
check "walk -o" "$T/g.csv" walk -q -o @OUT@ "$T/g.csv"
check "walk --plot" "$T/g.csv" walk -q --plot @OUT@ "$T/g.csv"
# acquire replaces an existing file only with --overwrite (a recording is
# never lost by accident)
check "acquire -o" - acquire -q --source sim:speed=max --count 200 --overwrite -o @OUT@
done_testing
