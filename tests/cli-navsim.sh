#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope navsim: the known answers on simulated IMUs (the random-walk
# fan, Schuler and the 137 m figure), converters behind the gyros,
# trajectories, its formats and bad input.  heading, walk and the
# navigation scenes are in cli-nav.sh.
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

# the wander-azimuth frame: a perfect IMU at rest at the pole for 1 h, and
# over the pole at 250 m/s (1 h, the pole at 30 min)
run "perfect IMU at the pole" 0 navsim --runs 1 --duration 1h --latitude 90 --vertical free --format json
json_check "at the pole: below 1 mm, strapdown" "$T/out" \
	'.mechanisation == "strapdown" and ([.percentiles.p50 | .north_m, .east_m, .down_m | .[] | fabs] | max) < 1e-3'
run "over the pole" 0 navsim --runs 1 --duration 1h --rate 20 --latitude 85.95 --trajectory straight:250m/s --format json
json_check "over the pole: below 1 m" "$T/out" '(.horizontal_m.p50 | max) < 1'
# a gimballed platform: a z-gyro scale factor of 1000 ppm turning in place at
# 10 deg/s for 60 s: strapdown heading error s r t = 0.6 deg, gimballed
# s W sin(lat) t, 2.5e-6 deg
# a gimballed platform: gyro scale-factor errors of 1000 ppm (1 sigma per
# run and axis) turning in place at 10 deg/s for 60 s: the strapdown heading
# error is s_z r t, an rms of 0.6 deg over the runs (sampling sd 7 % with
# 100 runs); the platform's gyros see only its torquing rate, and its
# heading error s_z W sin(lat) t is 1.8e-4 deg
printf '[sensor]\nrange = 500 deg/s\nscale_factor_error = 1000\n' >"$T/sf.ini"
run "scale factor, strapdown" 0 navsim --sensor "$T/sf.ini" --trajectory turn:10deg/s --runs 100 --duration 60 --format json -o "$T/sf-s.json" --plot-mechanisations "$T/mech.svg"
json_check "strapdown: s r t" "$T/sf-s.json" \
	'.mechanisation == "strapdown" and ((.rms.yaw_rad[-1] * 180 / 3.141592653589793 / 0.6) - 1 | fabs) < 0.25'
has "both mechanisations drawn" "$T/mech.svg" 'gimballed, median'
run "scale factor, gimballed" 0 navsim --sensor "$T/sf.ini" --trajectory turn:10deg/s --runs 100 --duration 60 --format json -o "$T/sf-g.json" --mechanisation gimballed
json_check "gimballed: s W sin(lat) t" "$T/sf-g.json" \
	'.mechanisation == "gimballed" and ((.rms.yaw_rad[-1] * 180 / 3.141592653589793 / 1.8e-4) - 1 | fabs) < 0.25'
run "latitude out of range" 2 navsim --latitude 91
one_line_error "latitude out of range"
run "a turn at the pole" 2 navsim --latitude 90 --trajectory turn:1deg/s
one_line_error "a turn at the pole"
run "unknown mechanisation" 2 navsim --mechanisation platform
one_line_error "unknown mechanisation"
run "gimballed with a converter" 1 navsim --mechanisation gimballed --sensor "$T/fog.ini" --gyro-adc "$T/c16.ini" --runs 1 --duration 10
one_line_error "gimballed with a converter"
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
done_testing
