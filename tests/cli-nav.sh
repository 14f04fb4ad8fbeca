#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope heading, walk and navsim: the known answers on the bundled
# samples and simulated IMUs (stops, the random-walk fan, Schuler and the
# 137 m figure), their formats, scene stages, and bad input.
. "$(dirname "$0")/lib.sh"

# ------------------------------------------------------------ navsim
run "navsim --help" 0 navsim --help
has "help names the trajectories" "$T/out" 'straight:SPEED'

# a perfect IMU at rest for 1 h at 45 deg, free vertical channel
run "perfect IMU at rest" 0 navsim --runs 1 --duration 1h --latitude 45 --vertical free --format json
json_check "position below 1 mm, attitude below 1e-9 rad" "$T/out" \
	'([.percentiles.p50 | .north_m, .east_m, .down_m | .[] | fabs] | max) < 1e-3 and ([.percentiles.p50 | .roll_rad, .pitch_rad, .yaw_rad | .[] | fabs] | max) < 1e-9'
json_check "contract fields" "$T/out" \
	'.command == "navsim" and .runs == 1 and .vertical == "free" and (.times_s | length) == (.percentiles.p95.north_m | length) and .budget.model == "schuler"'

# 10 deg/h on the east gyro: g b t^3 / 6 = 136.9 m after 120 s
run "gyro bias 10 deg/h" 0 navsim --gyro-bias 0,10deg/h,0 --runs 1 --duration 2min --output-step 10s --format json
json_check "137 m within 2 %" "$T/out" \
	'((.horizontal_m.p50[-1] / (9.80665 * (10 * 3.141592653589793 / 180 / 3600) * 120 * 120 * 120 / 6)) - 1 | fabs) < 0.02'
json_check "the budget's curve beside it" "$T/out" '((.budget.position_m[-1] / .horizontal_m.p50[-1]) - 1 | fabs) < 0.01'

# a north accelerometer bias: the Schuler oscillation, amplitude b R / g
run "accel bias Schuler" 0 navsim --accel-bias 1mg,0,0 --runs 1 --duration 85min --rate 20 --output-step 10s --format json
json_check "peak 2 b R / g near half the Schuler period" "$T/out" \
	'(.horizontal_m.p50 | max) as $m | (.horizontal_m.p50 | index($m)) as $k | ((($m / 2) / (9.80665e-3 * 6367381.8 / 9.8062)) - 1 | fabs) < 0.01 and ((2 * .times_s[$k] / 5063) - 1 | fabs) < 0.01'

# CSV: the contract's columns; one run = that run, else the median
run "navsim csv" 0 navsim --arw 0.2deg/sqrt\(h\) --runs 20 --duration 60 --output-step 10 --format csv
has "csv header" "$T/out" '^time \[s\],north \[m\],east \[m\],down \[m\],roll \[rad\],pitch \[rad\],yaw \[rad\]$'
has "csv says median" "$T/out" '^# sensorscope navsim: median'
cp "$T/out" "$T/nav-median.csv"
run "navsim csv reads back" 0 info "$T/nav-median.csv"
run "csv to a file" 0 navsim --runs 3 --duration 30 --format csv -o "$T/nav.csv"
has "file written" "$T/nav.csv" '^30,'

# the same seed gives the same numbers; --threads does not change them
run "seed 5, one thread" 0 navsim --arw 0.2deg/sqrt\(h\) --vrw 0.05m/s/sqrt\(h\) --runs 8 --duration 30 --seed 5 --threads 1 --format json -o "$T/a.json"
run "seed 5, two threads" 0 navsim --arw 0.2deg/sqrt\(h\) --vrw 0.05m/s/sqrt\(h\) --runs 8 --duration 30 --seed 5 --threads 2 --format json -o "$T/b.json"
if cmp -s "$T/a.json" "$T/b.json"; then ok "thread count does not change the result"; else not_ok "threads change the result"; fi

# progress on stderr only when asked (stderr is not a terminal here)
run "navsim --progress" 0 navsim --arw 0.1deg/sqrt\(h\) --runs 3 --duration 20 --progress
has "progress counts the runs" "$T/err" 'Monte-Carlo run 3 of 3'
run "navsim without --progress" 0 navsim --arw 0.1deg/sqrt\(h\) --runs 3 --duration 20
if [ -s "$T/err" ]; then not_ok "quiet stderr by default"; diag "$T/err"; else ok "quiet stderr by default"; fi

# sources: a spec, an allan result, a calib result
run "navsim --sensor" 0 navsim --sensor "$SAMPLES/gyro-mems-250.ini" --runs 4 --duration 30 --format json
json_check "spec's terms and random constants" "$T/out" \
	'.imu.gyro.noise.N.fitted and .imu.gyro.scale_factor_sd == 0.03 and .imu.gyro.range > 4.3 and (.imu.sources[0] | startswith("spec"))'
run "allan result" 0 allan -c gz --format json -o "$T/allan.json" "$SAMPLES/gyro-static.csv"
run "navsim --from-allan" 0 navsim --from-allan "$T/allan.json" --runs 4 --duration 30 --format json
json_check "allan's resolved terms" "$T/out" '.imu.gyro.noise.N.fitted and (.imu.gyro.noise.N.value - 0.15 | fabs) < 0.01 and ([.imu.gyro.noise[] | select(.fitted)] | length) >= 1'
run "calib result" 0 calib accel -c ax,ay,az --format json -o "$T/cal.json" "$SAMPLES/imu-multipose.csv"
run "navsim --from-calib" 0 navsim --from-calib "$T/cal.json" --runs 1 --duration 30 --format json
json_check "calib's bias and misalignment" "$T/out" '(.imu.accel.bias[0] - 0.206 | fabs) < 0.01 and (.imu.accel.error_matrix[0][1] | fabs) > 1e-4'

# a converter behind the gyros: a 16-bit rounding converter over +-500 deg/s
# (LSB 55 deg/h) behind a quiet gyro rounds the Earth rate (10.6 and -10.6
# deg/h on x and z at rest at 45 deg) to zero, a bias of that size; integrating, or
# with 24 bits, the error is the gyro's own
cat >"$T/fog.ini" <<'EOF2'
[sensor]
range = 500 deg/s
noise_density = 0.01 deg/sqrt(h)
EOF2
printf '[adc]\nname = c16\nbits = 16\nrange = -500:500 deg/s\n' >"$T/c16.ini"
printf '[adc]\nbits = 16\nrange = -500:500 deg/s\nmode = integrate\n' >"$T/c16i.ini"
printf '[adc]\nbits = 24\nrange = -500:500 deg/s\n' >"$T/c24.ini"
printf '[adc]\nbits = 10\nrange = -8:8 g\n' >"$T/a10.ini"
printf '[adc]\nbits = 16\nrange = 0:5 V\n' >"$T/volts.ini"
for c in c16 c16i c24; do
	run "navsim --gyro-adc $c" 0 navsim --sensor "$T/fog.ini" --gyro-adc "$T/$c.ini" --runs 4 --duration 2min --rate 50 --format json -o "$T/$c.json"
done
run "navsim without a converter" 0 navsim --sensor "$T/fog.ini" --runs 4 --duration 2min --rate 50 --format json -o "$T/c0.json"
command -v jq >/dev/null 2>&1 &&
	jq -s . "$T/c0.json" "$T/c16.json" "$T/c16i.json" "$T/c24.json" >"$T/adc-all.json"
json_check "the 16-bit converter's lost Earth rate" "$T/adc-all.json" \
	'.[1].imu.gyro.adc.bits == 16 and (.[1].imu.gyro.adc.lsb_si / (3.141592653589793 / 180 / 3600) - 54.93 | fabs) < 0.01 and .[1].horizontal_m.p50[-1] > 20 * .[0].horizontal_m.p95[-1] and .[1].budget.position_m[-1] > 0.5 * .[1].horizontal_m.p50[-1]'
json_check "integrating or 24 bits: the gyro's own error" "$T/adc-all.json" \
	'(.[2].horizontal_m.p50[-1] / .[0].horizontal_m.p50[-1] - 1 | fabs) < 0.05 and (.[3].horizontal_m.p50[-1] / .[0].horizontal_m.p50[-1] - 1 | fabs) < 0.05'
run "converter of the wrong quantity" 2 navsim --sensor "$T/fog.ini" --gyro-adc "$T/a10.ini"
one_line_error "converter of the wrong quantity"
run "converter in volts without a sensitivity" 2 navsim --sensor "$T/fog.ini" --gyro-adc "$T/volts.ini"
has "says sensitivity" "$T/err" 'sensitivity'
run "missing converter spec" 1 navsim --gyro-adc "$T/none.ini"

# a trajectory file
run "navsim --trajectory file" 0 navsim --trajectory "$SAMPLES/drive-trajectory.csv" --runs 1 --format json
json_check "a perfect IMU follows the drive" "$T/out" \
	'.trajectory.kind == "file" and .duration_s == 600 and ([.percentiles.p50.north_m[], .percentiles.p50.east_m[] | fabs] | max) < 1e-3'
run "trajectory shorter than --duration" 0 navsim --trajectory "$SAMPLES/drive-trajectory.csv" --duration 1h --runs 1
has "says the span" "$T/err" 'spans 600 s'
run "too much memory" 1 navsim --trajectory straight:10m/s --rate 10000 --duration 2h
one_line_error "too much memory"
run "turn" 0 navsim --trajectory turn:10deg/s:10m/s --runs 1 --duration 60 --format json
json_check "a perfect IMU turning" "$T/out" '([.percentiles.p50.yaw_rad[] | fabs] | max) < 1e-8'

# bad input
run "latitude out of range" 2 navsim --latitude 91
one_line_error "latitude out of range"
run "latitude at the pole" 2 navsim --latitude 90
run "bad trajectory" 2 navsim --trajectory straight:-3m/s
run "bad unit" 2 navsim --gyro-bias 3m
run "two values" 2 navsim --gyro-bias 1deg/h,2deg/h
run "operand refused" 2 navsim file.csv
run "--plot neither png nor svg" 2 navsim --plot x.jpg
printf 'north [m],east [m],yaw [deg]\n0,0,0\n1,0,0\n2,0,0\n3,0,0\n' >"$T/notime.csv"
run "trajectory without time" 1 navsim --trajectory "$T/notime.csv"
one_line_error "trajectory without time"
has "says time" "$T/err" 'no time column'
printf 'time [s],north [m],yaw [deg]\n0,0,0\n1,0,0\n2,0,0\n' >"$T/noeast.csv"
run "trajectory without east" 1 navsim --trajectory "$T/noeast.csv"
has "names the column" "$T/err" "no 'east' column"
printf 'time [s],north [m],east [m],yaw [deg]\n0,0,0,0\n1,0,0,0\n' >"$T/short.csv"
run "two-row trajectory" 1 navsim --trajectory "$T/short.csv"
one_line_error "two-row trajectory"
run "missing trajectory file" 1 navsim --trajectory "$T/none.csv"
run "allan result missing" 1 navsim --from-allan "$T/none.json"
printf '{"command":"psd"}\n' >"$T/psd.json"
run "not an allan result" 1 navsim --from-allan "$T/psd.json"
one_line_error "not an allan result"

# ------------------------------------------------------------ heading
run "heading --help" 0 heading --help
run "heading with reference" 0 heading --reference heading_ref --latitude 48 --format json "$SAMPLES/drive-stops.csv"
json_check "six stops, several times smaller error" "$T/out" \
	'(.stops | length) == 6 and .reference.rms_ratio > 3 and .reference.reestimated.rms_deg < 6'
json_check "Earth rate removed from the stop biases" "$T/out" \
	'.earth_rate_deg_h as $e | ($e + 15.041 * (48 * 3.141592653589793 / 180 | sin) | fabs) < 0.01 and all(.stops[]; (.sensor_bias_deg_h - .bias_deg_h + $e | fabs) < 1e-9)'
json_check "bias rises with the temperature" "$T/out" '.stops[0].sensor_bias_deg_h < .stops[-1].sensor_bias_deg_h'
run "heading interpolate" 0 heading --reference heading_ref --bias-model interpolate --format json "$SAMPLES/drive-stops.csv"
json_check "interpolating between stops does better" "$T/out" '.reference.reestimated.rms_deg < 2'
run "heading csv" 0 heading --reference heading_ref --format csv "$SAMPLES/drive-stops.csv"
has "heading csv header" "$T/out" '^time \[s\],heading \[deg\],heading_first_bias \[deg\],sigma \[deg\],sigma_first_bias \[deg\],still,reference \[deg\],error \[deg\],error_first_bias \[deg\]$'
cp "$T/out" "$T/heading.csv"
run "heading csv reads back" 0 info "$T/heading.csv"
run "heading text" 0 heading --arw 0.3deg/sqrt\(h\) --bias-instability 5deg/h "$SAMPLES/drive-stops.csv"
has "noise terms from options" "$T/out" 'N 0.3 deg/sqrt\(h\), B 5 deg/h \(options\)'
run "heading --from-allan" 0 heading --from-allan "$T/allan.json" --format json "$SAMPLES/drive-stops.csv"
json_check "allan's terms for the envelope" "$T/out" '.noise_from == "allan" and .noise.N.fitted'

# bad input
run "no vertical-axis channel" 1 heading -c ax,ay,az "$SAMPLES/drive-stops.csv"
one_line_error "no vertical-axis channel"
has "says vertical" "$T/err" 'no vertical-axis channel'
run "several rate channels, none z" 1 heading -c gx,gy "$SAMPLES/gyro-static.csv"
run "no stationary interval" 1 heading -c gz "$SAMPLES/gyro-static.csv"
one_line_error "no stationary interval"
has "says stationary" "$T/err" 'no stationary interval'
run "reference is not an angle" 1 heading --reference temp "$SAMPLES/drive-stops.csv"
run "heading latitude out of range" 2 heading --latitude 100 "$SAMPLES/drive-stops.csv"
one_line_error "heading latitude out of range"
run "heading two files" 2 heading "$SAMPLES/drive-stops.csv" "$SAMPLES/drive-stops.csv"
run "unknown --axis" 1 heading --axis wz "$SAMPLES/drive-stops.csv"
printf '[sensor]\nnoise_density = 60 ug/sqrt(Hz)\n' >"$T/acc.ini"
run "heading --sensor of an accelerometer" 1 heading --sensor "$T/acc.ini" "$SAMPLES/drive-stops.csv"
has "says gyro" "$T/err" 'not a gyro specification'
run "heading --sensor of a gyro" 0 heading --sensor "$SAMPLES/gyro-mems-250.ini" --format json "$SAMPLES/drive-stops.csv"
json_check "spec's terms for the envelope" "$T/out" '.noise_from == "sensor spec" and .noise.K.fitted and .final.sigma_deg > 0'
printf '[input]\nfiles = %s\n[sensor]\nnoise_density = 60 ug/sqrt(Hz)\n[heading]\nreference = heading_ref\n[report]\nformats = json\n' "$SAMPLES/drive-stops.csv" >"$T/hs.ini"
run "heading in a scene with an accelerometer [sensor]" 0 run "$T/hs.ini" -o "$T/hs" -q
json_check "the scene's accelerometer spec is not the gyro's" "$T/hs/heading.json" '.noise_from == "N from the scatter within the stops"'

# ------------------------------------------------------------ walk
run "walk --help" 0 walk --help
run "walk gyro-static" 0 walk -c gz --format json "$SAMPLES/gyro-static.csv"
json_check "fan inside the envelope" "$T/out" \
	'.channels[0].runs == 30 and .channels[0].bias_window_s == 60 and (.channels[0].inside.mean - 0.9545 | fabs) < 3 * .channels[0].inside.binomial_sd'
json_check "implied and allan's N" "$T/out" '.channels[0].implied_N[0].unit == "deg/sqrt(h)" and (.channels[0].allan_N.value - 0.15 | fabs) < 0.01'
run "walk with a bias window" 0 walk -c gx --run-length 30s --bias-window 30s --format json "$SAMPLES/gyro-static.csv"
json_check "window mode" "$T/out" '.channels[0].bias == "window before each run" and .channels[0].runs == 60 and .channels[0].bias_window_s == 30'
run "walk csv" 0 walk -c gx --format csv "$SAMPLES/gyro-static.csv"
has "walk csv header" "$T/out" '^channel,t_s,sigma,spread,inside,unit$'
# 95 +- 3 % on a simulated angle-random-walk capture (6 h at 10 Hz)
cat >"$T/arw.ini" <<'INI'
[sensor]
noise_density = 0.1 deg/sqrt(h)
bias = 0.2 deg/s
INI
run "simulate ARW" 0 simulate --sensor "$T/arw.ini" --rate 10 --duration 6h --seed 19 -o "$T/arw.csv"
run "walk on the simulated capture" 0 walk --run-length 20s --arw 0.1deg/sqrt\(h\) --format json "$T/arw.csv"
json_check "95 +- 3 % inside +-2 sigma" "$T/out" '(.channels[0].inside.mean - 0.95 | fabs) <= 0.03 and .channels[0].runs == 540'
run "walk on it with the record's mean" 0 walk --run-length 20s --bias-window 0 --arw 0.1deg/sqrt\(h\) --format json "$T/arw.csv"
json_check "95 +- 3 % with the record's mean too" "$T/out" '(.channels[0].inside.mean - 0.95 | fabs) <= 0.03 and .channels[0].runs == 1080 and .channels[0].bias == "record mean"'
run "walk: too short" 1 walk --run-length 40min "$SAMPLES/gyro-static.csv"
one_line_error "walk: too short"
run "walk: no inertial channel" 1 walk -c temp "$SAMPLES/accel-thermal.csv"
run "walk: bad --sigma" 2 walk --sigma 0 "$SAMPLES/gyro-static.csv"

# ------------------------------------------------------------ scenes
# json_close DESC A B: the two JSON files are equal, numbers within 1e-9
# relative (a scene's stages read allan's terms directly, a command from
# the JSON file written with 15 digits)
json_close() {
	if ! command -v jq >/dev/null 2>&1; then
		skip "$1" "jq not installed"
		return
	fi
	if jq -e -n --slurpfile a "$2" --slurpfile b "$3" '
		def close(x; y):
			if (x | type) == "number" and (y | type) == "number" then
				((x - y) | fabs) <= 1e-9 * ([(x | fabs), (y | fabs), 1e-300] | max)
			elif (x | type) == "object" and (y | type) == "object" then
				(x | keys) == (y | keys) and all(x | keys[]; . as $k | close(x[$k]; y[$k]))
			elif (x | type) == "array" and (y | type) == "array" then
				(x | length) == (y | length) and all(range(x | length); . as $i | close(x[$i]; y[$i]))
			else x == y end;
		close($a[0]; $b[0])' >/dev/null; then
		ok "$1"
	else
		not_ok "$1"
	fi
}

run "nav scene" 0 run "$SAMPLES/nav.scene.ini" -o "$T/nav" -q
run "walk as a command" 0 walk -c gz --format json -o "$T/walk.json" "$SAMPLES/gyro-static.csv"
json_close "walk: the scene's JSON equals the command's" "$T/nav/walk.json" "$T/walk.json"
run "navsim as a command" 0 navsim --from-allan "$T/nav/allan.json" --runs 20 --duration 5min --seed 7 --format json -o "$T/navsim.json"
jq 'del(.imu.sources)' "$T/nav/navsim.json" >"$T/n1.json" 2>/dev/null
jq 'del(.imu.sources)' "$T/navsim.json" >"$T/n2.json" 2>/dev/null
json_close "navsim: the scene's JSON equals the command's" "$T/n1.json" "$T/n2.json"
has "report names the stages" "$T/nav/report.txt" '^== Random-walk fan \(walk\)'
has "report has navsim" "$T/nav/report.txt" '^== Navigation error simulation \(navsim\)'
# report infers heading for a gyro with a true heading column
run "report on the drive" 0 report -o "$T/drive" -q "$SAMPLES/drive-stops.csv"
if [ -s "$T/drive/heading.json" ]; then ok "heading inferred"; else not_ok "heading inferred"; fi
run "heading as a command" 0 heading --reference heading_ref --format json -o "$T/heading.json" "$SAMPLES/drive-stops.csv"
json_close "heading: the report's JSON equals the command's" "$T/drive/heading.json" "$T/heading.json"
# and the fan for a stationary gyro record; a moving one is left out
run "report on two gyros" 0 report -o "$T/gyros" "$SAMPLES/gyro-static.csv"
if [ -s "$T/gyros/walk.json" ]; then ok "walk inferred"; else not_ok "walk inferred"; fi
run "report on a moving IMU" 0 report -o "$T/moving" "$SAMPLES/imu-multipose.csv"
has "walk refused with its reason" "$T/moving/report.html" "Stage 'walk': inferred, but refused by the data.*moves"
mkdir -p "$T/sc"
cp "$SAMPLES/drive-trajectory.csv" "$T/sc/drive.csv"
printf '[navsim]\ngyro-bias = 0,10deg/h,0\nruns = 1\nduration = 2 min\ntrajectory-file = drive.csv\n\n[report]\nformats = text\n' >"$T/sc/ns.ini"
run "navsim scene, trajectory relative to the scene" 0 run "$T/sc/ns.ini" -o "$T/sc/out" -q
has "the scene's trajectory" "$T/sc/out/report.txt" 'trajectory .*sc/drive.csv'
cp "$T/c16.ini" "$T/sc/conv.ini"
printf '[navsim]\nsensor = %s\ngyro-adc = conv.ini\nruns = 2\nduration = 1 min\n\n[report]\nformats = text\n' "$T/fog.ini" >"$T/sc/adc.ini"
run "navsim scene, converter relative to the scene" 0 run "$T/sc/adc.ini" -o "$T/sc/adcout" -q
has "the scene's converter" "$T/sc/adcout/report.txt" 'gyro converter c16: 16 bits'
printf '[navsim]\ngyro-bias = 0,10deg/h,0\nruns = 1\nduration = 2 min\n\n[report]\nformats = text\n' >"$T/ns.ini"
run "navsim in a scene without captures" 0 run "$T/ns.ini" -o "$T/ns" -q
has "navsim's own keys" "$T/ns/report.txt" 'fixed gyro bias \(x, y, z\): 0, 10, 0 deg/h'

# ------------------------------------------------------------ figures
if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "navsim --plot" 0 navsim --arw 0.2deg/sqrt\(h\) --runs 5 --duration 60 --plot "$T/n.png"
	run "heading --plot" 0 heading --reference heading_ref --plot "$T/h.png" "$SAMPLES/drive-stops.csv"
	run "walk --plot" 0 walk -c gz --plot "$T/w.png" "$SAMPLES/gyro-static.csv"
	for f in n h w; do
		if [ -s "$T/$f.png" ] && [ "$(head -c 4 "$T/$f.png" | tail -c 3)" = PNG ]; then ok "$f.png written"; else not_ok "$f.png"; fi
	done
else
	run "navsim --plot without OpenCV" 2 navsim --plot "$T/n.png"
fi
run "navsim --plot svg" 0 navsim --runs 2 --duration 30 --plot "$T/n.svg"
run "heading --plot svg" 0 heading --plot "$T/h.svg" "$SAMPLES/drive-stops.csv"
run "walk --plot svg" 0 walk -c gz --plot "$T/w.svg" "$SAMPLES/gyro-static.csv"
for f in n h w; do
	if grep -q '<svg' "$T/$f.svg" 2>/dev/null; then ok "$f.svg written"; else not_ok "$f.svg"; fi
done

done_testing
