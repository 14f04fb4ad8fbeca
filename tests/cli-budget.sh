#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope budget and sensorscope model: the textbook's numbers, the
# Monte-Carlo envelope check, spec files, and usage errors.
. "$(dirname "$0")/lib.sh"

run "budget --help" 0 budget --help
run "no source" 2 budget --time 10
one_line_error "no source"
run "bad --time" 2 budget --gyro-bias 1deg/h --time soon
one_line_error "bad --time"
run "bad --error unit" 2 budget --gyro-bias 1deg/h --error 3V
run "wrong unit for --gyro-bias" 2 budget --gyro-bias 3m
run "--plot not png" 2 budget --gyro-bias 1deg/h --plot x.jpg
run "operand refused" 2 budget --gyro-bias 1deg/h file.csv

# the textbook: 10 deg/h for 120 s -> g b t^3 / 6 = 136.93 m ("about 140 m")
run "gyro bias 10 deg/h" 0 budget --gyro-bias 10deg/h --time 120 --format json
json_check "137 m after 120 s" "$T/out" '((.sources[] | select(.name == "gyro_bias") | .position_m[0]) - 136.926665 | fabs) < 1e-5'
json_check "contract shape" "$T/out" '.times_s == [120] and (.sources | map(.name)) == ["gyro_bias","accel_bias","arw","vrw","scale_factor"] and (.total.position_m | length) == 1'
json_check "open loop before the switch" "$T/out" '.model == ["open_loop"] and .switch_time_s == 300'
# accelerometer bias: b t^2 / 2
run "accel bias 1 mg" 0 budget --accel-bias 1mg --time 100 --format json
json_check "b t^2 / 2" "$T/out" '((.sources[1].position_m[0]) - 0.5 * 9.80665e-3 * 1e4 | fabs) < 1e-9'
# Schuler bounded: the accelerometer-bias error returns to zero after 84.4 min
run "schuler" 0 budget --accel-bias 1mg --schuler --time 5064.5 --format json
json_check "schuler model used" "$T/out" '.model == ["schuler"] and .sources[1].position_m[0] < 0.01'
# time to an error
run "time to 137 m" 0 budget --gyro-bias 10deg/h --error 136.926665m --format json
json_check "reached at 120 s" "$T/out" '((.time_to[0].sources_s.gyro_bias) - 120 | fabs) < 1e-3'
# Monte Carlo: fraction inside +-2 sigma within 4 binomial sd
run "monte carlo" 0 budget --arw 0.2deg/sqrt\(h\) --vrw 0.1m/s/sqrt\(h\) --time 60,600 --monte-carlo 2000 --seed 7 --format json
json_check "walk fractions within the binomial bound" "$T/out" \
	'all(.monte_carlo[]; . as $m | all(.points[]; ((.walk_inside_2sigma - $m.expected_inside) | fabs) <= 4 * $m.binomial_sd and ((.position_inside_2sigma - $m.expected_inside) | fabs) <= 4 * $m.binomial_sd))'
json_check "random sources flagged" "$T/out" '[.sources[] | select(.random) | .name] == ["arw","vrw"]'
# spec file
cat >"$T/gyro.ini" <<'INI'
[sensor]
name = test gyro
noise_density = 0.15 deg/sqrt(h)
bias_instability = 5 deg/h
INI
run "budget --sensor" 0 budget --sensor "$T/gyro.ini" --time 60 --format json
json_check "spec fields used" "$T/out" '.inputs.gyro_bias_from == "bias_instability" and ((.inputs.arw_rad_sqrt_s - 0.15 * 3.141592653589793 / 180 / 60) | fabs) < 1e-12'
run "budget --sensor missing" 1 budget --sensor "$T/none.ini"
one_line_error "budget --sensor missing"
# a result of allan (CONTRACT shape) and of calib
cat >"$T/allan.json" <<'JSON'
{"command":"allan","channels":[
 {"name":"gx","noise":{"N":{"si":7.3e-5,"si_unit":"rad/s/sqrt(Hz)"},"B":{"si":2.1e-5,"si_unit":"rad/s"}}},
 {"name":"gy","noise":{"N":{"si":9.1e-5,"si_unit":"rad/s/sqrt(Hz)"},"B":{"si":1.7e-5,"si_unit":"rad/s"}}},
 {"name":"ax","noise":{"N":{"si":1.2e-3,"si_unit":"m/s^2/sqrt(Hz)"},"B":{"si":4.0e-4,"si_unit":"m/s^2"}}}]}
JSON
run "budget --result allan" 0 budget --result "$T/allan.json" --time 60 --format json
json_check "worst axis of allan N and B" "$T/out" '.inputs.arw_rad_sqrt_s == 9.1e-5 and .inputs.gyro_bias_rad_s == 2.1e-5 and .inputs.vrw_m_s_sqrt_s == 1.2e-3 and .inputs.accel_bias_m_s2 == 4.0e-4'
run "calib result" 0 calib gyro --format json -o "$T/cal.json" "$SAMPLES/imu-multipose.csv"
run "budget --result calib" 0 budget --result "$T/cal.json" --time 60 --format json
json_check "calibration uncertainty used" "$T/out" '.inputs.gyro_bias_from == "calib bias uncertainty" and .inputs.gyro_bias_rad_s > 0 and .inputs.gyro_bias_rad_s < 1e-4 and .inputs.arw_from == "calib noise density"'
printf '{"command":"info"}\n' >"$T/info.json"
run "budget --result of another command" 1 budget --result "$T/info.json"
one_line_error "budget --result of another command"
run "budget text" 0 budget --gyro-bias 1deg/h --accel-bias 100ug --arw 0.1deg/sqrt\(h\) --error 100m
has "dominant source reported" "$T/out" 'dominant source changes'
has "time to error reported" "$T/out" 'time to position error 100 m'
run "budget csv" 0 budget --gyro-bias 1deg/h --format csv --time 10
has "csv rows" "$T/out" '^10,total,'

# model fog: R 5 cm, 1000 turns, 1550 nm, 10 deg/s -> 0.0741404 rad (by hand)
run "model fog" 0 model fog --radius 5cm --turns 1000 --wavelength 1550nm --rate 10deg/s --format json
json_check "Sagnac phase" "$T/out" '((.rates[0].phase_rad - 0.0741403629) | fabs) < 1e-9 and ((.max_rate_deg_s - 211.8679) | fabs) < 1e-3'
run "model fog text" 0 model fog --radius 5cm --turns 1000 --wavelength 1550nm
has "notes the textbook's eq. 92" "$T/out" 'omits R\^2 and lambda'
run "model accel" 0 model accel --mass 1e-9 --stiffness 1 --damping 6.3245553e-5 --format json
json_check "displacement per g = m g / k" "$T/out" '((.displacement_per_g_m - 9.80665e-9) | fabs) < 1e-20 and ((.damping_ratio - 1) | fabs) < 1e-6'
json_check "analytic step matches Runge-Kutta" "$T/out" '.step.max_rk4_deviation_m < 1e-6 * .displacement_per_g_m'
run "model accel fn" 0 model accel --fn 2.4kHz --zeta 0.7071067811865476 --format json
json_check "bandwidth = fn at zeta 1/sqrt2" "$T/out" '((.bandwidth_hz - 2400) | fabs) < 1e-6'
run "model accel incomplete" 2 model accel --mass 1
one_line_error "model accel incomplete"
run "model fog incomplete" 2 model fog --radius 5cm
run "model without accel|fog" 2 model
run "model bad turns" 2 model fog --radius 5cm --turns -3 --wavelength 1550nm
if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
	run "budget --plot" 0 budget --gyro-bias 1deg/h --arw 0.1deg/sqrt\(h\) --plot "$T/b.png"
	if [ -s "$T/b.png" ]; then ok "budget plot written"; else not_ok "budget plot written"; fi
	run "model accel --plot" 0 model accel --fn 100 --zeta 0.3 --plot "$T/m.png"
	run "model fog --plot" 0 model fog --radius 5cm --turns 1000 --wavelength 1550nm --plot "$T/f.png"
else
	run "budget --plot without OpenCV" 2 budget --gyro-bias 1deg/h --plot "$T/b.png"
fi
# sources not given are said so, in words, never a measured-looking 0
run "budget with one source" 0 budget --gyro-bias 10deg/h --time 120
has "budget: sources not given, said" "$T/out" 'sources: gyro bias 10 deg/h \(option\), accel bias not given, ARW not given, VRW not given'
has "budget: columns in words, '-' for a source not given" "$T/out" '^ +120 +136\.9 +- +- +- +- +136\.9 +gyro bias +open loop$'
has "budget: header in words" "$T/out" 't \(s\) +gyro bias +accel bias +ARW +VRW +scale factor'

run "budget from a gyro spec, json" 0 budget --sensor "$SAMPLES/gyro-mems-250.ini" --time 60 --format json
json_check "sources: where each came from, 'not given' for none" "$T/out" '.inputs.gyro_bias_from == "bias_instability" and .inputs.arw_from == "noise_density" and .inputs.accel_bias_from == "not given" and .inputs.vrw_from == "not given"'
run "budget of accelerometer sources only" 0 budget --accel-bias 100ug --time 60
has "no gyro source: attitude '-', not 0" "$T/out" '^ +60 +[0-9.]+ +-$'

run "budget beyond a year" 2 budget --gyro-bias 1deg/h --time 1e30
has "beyond a year: said" "$T/err" "'1e30' is beyond a year"

done_testing
