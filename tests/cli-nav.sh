#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope heading, walk and nav: the known answers on the bundled
# samples (stops, the random-walk fan, the biases of a simulated walk),
# their formats, the navigation scene stages and figures, and bad input.
# navsim alone is in cli-navsim.sh.
. "$(dirname "$0")/lib.sh"

# inputs shared with the navsim tests: an allan result, a quiet gyro and
# a 16-bit converter
ss allan -c gz --format json -o "$T/allan.json" "$SAMPLES/gyro-static.csv" 2>/dev/null
cat >"$T/fog.ini" <<'EOF2'
[sensor]
range = 500 deg/s
noise_density = 0.01 deg/sqrt(h)
EOF2
printf '[adc]\nname = c16\nbits = 16\nrange = -500:500 deg/s\n' >"$T/c16.ini"

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
# a record all still: no stops to tell from motion, said so
run "heading on a still record" 1 heading -c gz "$SAMPLES/gyro-static.csv"
one_line_error "heading on a still record"
has "heading on a still record: why and what to do" "$T/err" 'cannot tell stops from motion: .* all still or all moving .*heading needs a record with both'
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
# late in a run B and K explain the spread: no implied N, said so (never nan)
run "walk: the other terms explain the spread" 0 walk -c gz --run-length 2min --bias-window 30s "$SAMPLES/gyro-static.csv"
has "walk: no N left, said" "$T/out" ' 120 .* - \(the other terms explain the spread: none left for N\)$'
has "walk: a bound where there is one" "$T/out" ' 84 .* - \(below [0-9.]+ deg/sqrt\(h\): the other terms explain the spread\)$'
lacks "walk: no nan" "$T/out" 'nan'
run "walk csv" 0 walk -c gx --format csv "$SAMPLES/gyro-static.csv"
has "walk csv header" "$T/out" '^channel,t_s,sigma,spread,inside,unit$'
awk 'BEGIN { print "# rate: 100 Hz"; print "gx [deg/s]"; for (i = 0; i < 5000; i++) print "0.1" }' >"$T/flat.csv"
run "walk on constant data" 1 walk "$T/flat.csv"
has "walk: why allan's fit gave no terms" "$T/err" "channel 'gx': no noise terms for the envelope \\(allan's fit: every deviation is zero \\(constant data\\): no noise to fit; give --arw\\)"
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
has "walk refused with its reason" "$T/moving/report.html" "Analysis 'walk': inferred, but refused by the data.*moves"
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

# ------------------------------------------------------------ nav
# walk-stops.csv's true biases (tests/gen-samples.c, stated in its header)
W="$SAMPLES/walk-stops.csv"
run "nav --help" 0 nav --help
run "nav on the walk" 0 nav --heading 30 --latitude 48 --format json "$W"
json_check "nine stops, heading given" "$T/out" \
	'(.stops | length) == 9 and .start.heading_from == "given" and .zupt and .noise.source == "defaults"'
json_check "biases at the last stop within 3 sigma of the truth" "$T/out" \
	'.stops[-1] as $s | [-0.10044, -0.14836, 0.17863] as $g | [-0.02144, -0.00013, -0.00494] as $a
	 | all(range(3); (($s.gyro_bias_rad_s[.] - $g[.] * 3.141592653589793 / 180) | fabs) < 3 * $s.gyro_bias_sd_rad_s[.])
	 and all(range(3); (($s.accel_bias_m_s2[.] - $a[.]) | fabs) < 3 * $s.accel_bias_sd_m_s2[.])'
json_check "levelled, trajectory columns" "$T/out" \
	'(.start.roll_deg | fabs) < 1 and .start.level_s >= 4.9 and (.trajectory.time_s | length) == (.trajectory.north_m | length) and .end.horizontal_sd_m > 0'
cp "$T/out" "$T/nav.json"
run "nav --no-zupt" 0 nav --heading 30 --latitude 48 --no-zupt --format json "$W"
jq -s '.[0].end.horizontal_sd_m as $a | .[1].end.horizontal_sd_m as $b | $b > 100 * $a' "$T/nav.json" "$T/out" 2>/dev/null | grep -q true &&
	ok "without the stop updates the 1 sigma grows 100 times" || not_ok "--no-zupt 1 sigma"
run "nav heading unobservable" 0 nav --format json "$W"
has "warns of the heading" "$T/err" 'heading is unobservable'
json_check "heading assumed" "$T/out" '.start.heading_from == "assumed" and .start.heading_deg == 0'
run "nav csv" 0 nav --heading 30 --latitude 48 --format csv -o "$T/track.csv" "$W"
has "navsim's trajectory columns first" "$T/track.csv" '^time \[s\],north \[m\],east \[m\],down \[m\],roll \[rad\],pitch \[rad\],yaw \[rad\],v_north'
run "nav csv is a navsim trajectory" 0 navsim --trajectory "$T/track.csv" --latitude 48 --runs 1 --format json
run "nav text" 0 nav --heading 30 "$W"
has "stops table" "$T/out" '^stops: 9 '
run "nav --from-allan" 0 nav --heading 30 --from-allan "$T/allan.json" --format json "$W"
json_check "allan's gyro terms" "$T/out" '.noise.source == "allan"'
has "says the accelerometer N is the default" "$T/err" 'accelerometer N: the default'
printf '[gyro]\nrandom_walk = 0.2 deg/sqrt(h)\n[accel]\nrandom_walk = 0.05 m/s/sqrt(h)\n' >"$T/walk-ds.ini"
run "nav --spec" 0 nav --heading 30 --spec "$T/walk-ds.ini" --format json "$W"
json_check "datasheet's N" "$T/out" '.noise.source == "datasheet" and (.noise.gyro_n_rad_s_sqrt_hz * 60 * 180 / 3.141592653589793 - 0.2 | fabs) < 1e-9'
run "nav --plot svg" 0 nav --heading 30 --plot "$T/nav.svg" "$W"
if grep -q '<svg' "$T/nav.svg" 2>/dev/null; then ok "nav.svg written"; else not_ok "nav.svg"; fi
printf '[input]\nfiles = %s\n[nav]\nheading = 30\nlatitude = 48\n[report]\nformats = json\n' "$W" >"$T/nv.ini"
run "nav in a scene" 0 run "$T/nv.ini" -o "$T/nv" -q
json_check "the scene's nav stage" "$T/nv/nav.json" '.command == "nav" and (.stops | length) == 9'
run "nav command as the scene runs it" 0 nav --heading 30 --latitude 48 --format json -o "$T/nv-cmd.json" "$W"
json_close "nav: the scene's JSON equals the command's" "$T/nv/nav.json" "$T/nv-cmd.json"
# bad input
run "nav: no accelerometer channels" 1 nav -c gx,gy,gz "$W"
one_line_error "nav: no accelerometer channels"
has "says three are needed" "$T/err" 'acceleration channels: three are needed'
{ sed -n 1,3p "$W"; sed -n '1004,3000p' "$W"; } >"$T/moving.csv"
run "nav: moving at the start" 1 nav "$T/moving.csv"
one_line_error "nav: moving at the start"
has "says not still" "$T/err" 'not still at the start'
sed -n 1,40p "$W" >"$T/short.csv"
run "nav: too short" 1 nav "$T/short.csv"
one_line_error "nav: too short"
{ sed -n 1,300p "$W"; echo '6.00,NaN,0,0,0,0,-9.8'; sed -n 302,900p "$W"; } >"$T/nan.csv"
run "nav: NaN" 1 nav "$T/nan.csv"
one_line_error "nav: NaN"
run "nav: latitude out of range" 2 nav --latitude 95 "$W"
one_line_error "nav: latitude out of range"
run "nav: two files" 2 nav "$W" "$W"
run "nav: two noise sources" 2 nav --spec "$T/walk-ds.ini" --from-allan "$T/allan.json" "$W"

done_testing
