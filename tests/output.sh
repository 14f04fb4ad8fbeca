# SPDX-License-Identifier: GPL-3.0-or-later
# Sourced by cli-output.sh and cli-output-folders.sh (after lib.sh): the
# inputs and the checks of one-line errors and left-over temporary files.
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
