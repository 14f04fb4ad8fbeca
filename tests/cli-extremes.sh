#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Option values at the ends of the double range and numbers given without
# their unit: a duration times a rate beyond any count of samples once
# crashed walk, nav, navsim and tempbias (a floating-point exception) and a
# rate of 1e-300 Hz hung tempbias; a bare --arw 0.3 was read as 0.3
# rad/sqrt(s) (1031 deg/sqrt(h)) without a word.  Each case states its exit
# status and what the user reads.
. "$(dirname "$0")/lib.sh"

SIM="$T/sim.csv"
run "a gyro record" 0 simulate --sensor "$SAMPLES/gyro-mems-250.ini" -r 100 \
	--duration 10min --axes 3 -o "$SIM"
# a temperature ramp 20 -> 50 degC at 1 Hz, the bias following it
awk 'BEGIN { print "time [s],ax [g],temp [degC]";
	for (i = 0; i < 3000; i++) { T = 20 + 30 * i / 3000;
		printf "%d,%.6f,%.3f\n", i, 0.001 * T + 1e-4 * sin(i * 1.7), T } }' \
	>"$T/tb.csv"

# counts of samples beyond any record: clear errors, no crash
run "walk --run-length 1e20" 1 walk --run-length 1e20 -c gx "$SIM"
one_line_error "walk --run-length 1e20"
has "walk --run-length 1e20: says the record holds no run" "$T/err" \
	"hold 0 runs of 1e\+20 s"
run "tempbias -r 1e20" 1 tempbias -q -r 1e20 "$T/tb.csv"
one_line_error "tempbias -r 1e20"
run "nav --output-step 1e20" 0 nav -q --output-step 1e20 "$SAMPLES/walk-stops.csv"
run "nav --window 1e308" 1 nav --window 1e308 "$SAMPLES/walk-stops.csv"
one_line_error "nav --window 1e308"
has "nav --window 1e308: the window against the record, in seconds" "$T/err" \
	"14250 samples \(285 s\): the initial still interval needs 1e\+308 s"
run "navsim --output-step 1e20" 0 navsim --runs 1 --threads 1 --duration 30s \
	--gyro-bias 1deg/h --output-step 1e20

# a rate of 1e-300 Hz: the record spans 3e303 s; an answer, not a hang
timeout 120 $SSCOPE_RUN "$SSCOPE" tempbias -q -r 1e-300 "$T/tb.csv" \
	>"$T/out" 2>"$T/err"
rc=$?
if [ "$rc" -eq 0 ]; then
	ok "tempbias -r 1e-300 ends (exit 0)"
else
	not_ok "tempbias -r 1e-300 (exit $rc, 124: still running after 120 s)"
	diag "$T/err"
fi

# temperatures no sensor sees
awk -F, 'NR == 1 { print; next } { print $1 "," $2 "," $3 - 320 }' "$T/tb.csv" >"$T/cold.csv"
run "tempbias below absolute zero" 1 tempbias "$T/cold.csv"
has "below absolute zero: said, with the file and channel" "$T/err" \
	"cold.csv: channel ax: the temperature runs from -300 to -270 degC: below absolute zero"
run "tempbias --ref-temp -300" 2 tempbias --ref-temp -300 "$T/tb.csv"
run "tempbias --ref-temp 1000" 0 tempbias --ref-temp 1000 "$T/tb.csv"
has "a reference far outside the data: warned" "$T/err" \
	"--ref-temp 1000 degC lies far outside the data's 20 .. 50 degC"
run "tempbias --table-step 1e-6" 1 tempbias --table-step 1e-6 "$T/tb.csv"
has "a table of 3e7 rows: refused, not one row" "$T/err" "makes more than 100000 rows"
run "tempbias --ref-temp 40" 0 tempbias --ref-temp 40 "$T/tb.csv"
lacks "a reference inside the data: no warning" "$T/err" "warning"

# a bare number for a noise term or a rate is SI, and said so with its
# value in the field's unit
run "budget --arw 0.002" 0 budget --arw 0.002
has "budget --arw 0.002: the value in deg/sqrt(h)" "$T/err" \
	"warning: --arw 0.002 has no unit: read as 0.002 rad/sqrt\(s\), that is 6.875 deg/sqrt\(h\)"
run "budget --arw 0.1deg/sqrt(h)" 0 budget --arw "0.1 deg/sqrt(h)"
lacks "budget with the unit: no warning" "$T/err" "warning"
run "budget --arw 0.002 -q" 0 budget --arw 0.002 -q
lacks "budget -q after the value: no warning" "$T/err" "warning"
run "walk --arw 0.2" 0 walk --arw 0.2 -c gx "$SIM"
has "walk --arw 0.2: read as rad/s/sqrt(Hz), said in deg/sqrt(h)" "$T/err" \
	"that is 687.5 deg/sqrt\(h\)"
run "budget --gyro-bias 1e305" 0 budget --gyro-bias 1e305 --time 1
lacks "a value beyond the field's unit: no inf in the warning" "$T/err" "inf"

# values no sensor has
run "budget --arw -0.1 deg/sqrt(h)" 2 budget --arw "-0.1 deg/sqrt(h)"
has "a negative random walk: refused" "$T/err" "--arw: a random walk is not negative"
run "budget --gravity 1e308" 2 budget --gravity 1e308 --arw "0.1 deg/sqrt(h)"
has "a gravity of 1e308: refused" "$T/err" "is not a local gravity"
run "calib --gravity 0.01" 2 calib accel --gravity 0.01 "$SAMPLES/accel-6pos.csv"

# models and motions no device has
run "model accel --fn 1e-300" 2 model accel --fn 1e-300 --zeta 0.7
has "fn outside the devices' range" "$T/err" "--fn: '1e-300' is outside 1 mHz .. 10 MHz"
run "model accel --duration 1e308" 2 model accel --fn 2.4kHz --zeta 0.7 --duration 1e308
run "model fog --wavelength 1550" 2 model fog --radius 5cm --turns 1000 --wavelength 1550
has "a bare wavelength: metres, said" "$T/err" "bare numbers are metres: write 1550 nm"
run "model fog --wavelength 1550nm" 0 model fog --radius 5cm --turns 1000 --wavelength 1550nm
run "navsim turn:1e308deg/s" 2 navsim --runs 1 --threads 1 --duration 30s --trajectory turn:1e308deg/s
has "a turn beyond any gyro: refused" "$T/err" "is beyond any gyro's range"

# units: days and milli-degrees per second
run "plan --max-length 30d" 0 plan --sensor "$SAMPLES/gyro-mems-250.ini" -r 100 \
	--resolve B:25% --max-length 30d
run "simulate -u mdps" 0 simulate --sensor "$SAMPLES/gyro-mems-250.ini" -r 10 \
	--duration 0.001d -u mdps --input "5 deg/s" -o "$T/mdps.csv"
run "info on mdps" 0 info --format json "$T/mdps.csv"
json_check "mdps: 5 deg/s (plus the spec's bias) is about 5000 mdps, 864 samples" "$T/out" \
	'.channels[0].unit == "mdps" and (.channels[0].mean - 5000 | fabs) < 500 and .channels[0].samples == 864'

# what the data cannot give is unknown, never 0
printf '# rate: 10 Hz\ngx [deg/s]\n0.5\n' >"$T/one.csv"
run "info on one sample" 0 info "$T/one.csv"
has "one sample: sd '-'" "$T/out" "gx +deg/s +angular rate +0.5 +- +0.5 +0.5"
run "info --format json on one sample" 0 info --format json "$T/one.csv"
json_check "one sample: sd null" "$T/out" '.channels[0].sd == null and .channels[0].mean == 0.5'
printf 'gx [deg/s]\n0.5\n0.6\n' >"$T/norate.csv"
run "info --format csv, no rate" 0 info --format csv "$T/norate.csv"
has "no rate: nan, not 0" "$T/out" "^.*norate.csv,gx,deg/s,angular rate,nan,2,"
printf '# rate: 10 Hz\ngx [deg/s]\n' >"$T/const.csv"
for i in 1 2 3 4 5 6 7 8 9 10; do echo 0.5 >>"$T/const.csv"; done
run "allan --format json on constant data" 0 allan -q --format json "$T/const.csv"
json_check "no fit: the terms' numbers null" "$T/out" \
	'[.channels[0].noise[] | .value, .lo, .hi, .si, .estimate, .test_z] | all(. == null)'

# a file another command wrote: missing, a folder, or something else
run "walk --from-allan missing" 1 walk --from-allan "$T/none.json" -c gx "$SIM"
has "missing: the option, the file, why" "$T/err" "^sensorscope: walk: --from-allan: .*none.json: no such file or directory$"
run "walk --from-allan a folder" 1 walk --from-allan "$T" -c gx "$SIM"
has "a folder: says so" "$T/err" "--from-allan: .*: is a directory$"
run "info --calibration a CSV" 1 info --calibration "$SIM" "$SIM"
has "a CSV as a calibration: not a calibration file" "$T/err" \
	"--calibration: .*sim.csv: not a calibration file of 'sensorscope calib' \(JSON error at line 1"

# walk --from-allan matches channels by name, and says when it cannot
run "allan on gx" 0 allan --format json -c gx -o "$T/al.json" "$SIM"
run "walk gy --from-allan (gx only)" 0 walk --from-allan "$T/al.json" -c gy "$SIM"
has "walk: the other channel's terms, said" "$T/err" \
	"channel 'gy': .*al.json has no channel of that name: the terms of its 'gx' are used"
run "walk gx --from-allan" 0 walk --from-allan "$T/al.json" -c gx "$SIM"
lacks "walk: the same channel, no warning" "$T/err" "warning"

# '-' is standard input for specifications and results too
run_in "datasheet -" 0 "$SAMPLES/datasheets/bmi088.ini" datasheet -
has "datasheet -: read" "$T/out" "^\[gyro\] angular rate"
run_in "walk --from-allan -" 0 "$T/al.json" walk --from-allan - -c gx "$SIM"
has "walk --from-allan -: the result's terms" "$T/out" "\(allan result\)"

# heading on samples too large to square: said, not "capture too short"
awk -F, 'NR <= 3 { print; next } { printf "%s", $1 * 1e300; for (i = 2; i <= NF; i++) printf ",%s", $i * 1e300; print "" }' \
	"$SAMPLES/drive-stops.csv" >"$T/hbig.csv"
run "heading on 1e300-scale samples" 1 heading "$T/hbig.csv"
has "too large to square: said" "$T/err" "too large to square"

# a rate read as an angle, a pilot too short to fit: said, with the file
run "allan --input angle on a rate" 0 allan --input angle -c gx "$SIM"
has "a rate read as an angle: warned" "$T/err" "channel gx is in deg/s, a rate, but --input angle"
printf '# rate: 100 Hz\ngx [deg/s]\n0.1\n0.2\n' >"$T/two.csv"
run "plan --pilot of two samples" 1 plan --pilot "$T/two.csv" --resolve N:25%
has "the pilot's file and channel named" "$T/err" "two.csv: channel gx: noise fit: "

# the help lists what each command takes
run "run --help" 0 run --help
lacks "run --help: no --format" "$T/out" "--format"
has "run --help: -o names a folder" "$T/out" "-o, --output DIR"
run "datasheet --help" 0 datasheet --help
has "datasheet --help: text or json" "$T/out" "--format text\|json "
lacks "datasheet --help: no --plot" "$T/out" "--plot PATH"
run "allan --help" 0 allan --help
has "allan --help: csv too" "$T/out" "--format text\|json\|csv"

# no sample rate: the same words and exit 1 (the file lacks it) everywhere
printf 'ax,ay,az,temp\n0.1,0.2,9.8,20\n0.1,0.2,9.8,21\n0.1,0.2,9.8,22\n' >"$T/norate.csv"
for c in "adc test" "calib accel" tempbias allan; do
	run "$c without a rate" 1 $c "$T/norate.csv"
	has "$c without a rate: said, with what to do" "$T/err" "norate.csv: no sample rate: no time column and no '# rate:' comment; give --rate\$"
done

# --rate with a unit, as a scene's rate
run "--rate with a unit" 0 info -r "1 kHz" "$T/norate.csv"
has "--rate with a unit: read in Hz" "$T/out" 'rate: +1000 Hz \(given\)'
run "--rate in another dimension" 2 info -r "10 deg" "$T/norate.csv"
has "--rate in another dimension: said" "$T/err" "'10 deg' is not in units of Hz"

done_testing
