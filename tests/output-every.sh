# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by cli-output-every.sh and cli-output-every-plot.sh: the inputs
# and check(), which writes one command's output over a device, a FIFO, a
# link and its own input.

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

