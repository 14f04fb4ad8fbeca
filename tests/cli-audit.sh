#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope audit: sensorscope's own Kalibr, OpenVINS and imu_utils
# exports of a simulated gyro + accelerometer audit clean; every finding is
# provoked by a crafted file whose error and corrected value are worked by
# hand below (sqrt(200) = 14.142136, sqrt(100) = 10, sqrt(400) = 20; the
# Allan minimum of a bias-instability floor is sqrt(2 ln 2 / pi) B =
# 0.6642825 B; the N and K lines of the Allan deviation cross at
# tau_c = sqrt(3) N / K); bad input is one line, exit 1 (file) or 2 (usage).
. "$(dirname "$0")/lib.sh"
cd "$T" || exit 1

run "audit --help" 0 audit --help
has "help names --strict" "$T/out" '--strict'
run "no operand" 2 audit
one_line_error "no operand"
run "two operands" 2 audit a.yaml b.yaml
run "csv refused" 2 audit --format csv a.yaml
run "bad --rate" 2 audit --rate 0 a.yaml
one_line_error "bad --rate"
run "missing file" 1 audit "$T/none.yaml"
one_line_error "missing file"
printf 'camera_model: pinhole\nintrinsics: [1, 2, 3, 4]\n' >cam.yaml
run "not a noise file" 1 audit cam.yaml
one_line_error "not a noise file"
has "says what it expects" "$T/err" 'expected a Kalibr .*imu_utils'

# sensorscope's own exports: a gyro (N 0.15 deg/sqrt(h), K 2 deg/h/sqrt(h))
# and an accelerometer (N 60 ug/sqrt(Hz), K 0.002 m/s^2/sqrt(h)), 20 min at
# 50 Hz; K of the gyro is only bounded (marked UPPER BOUND in the files)
printf '[sensor]\nnoise_density = 0.15 deg/sqrt(h)\nrate_random_walk = 2 deg/h/sqrt(h)\n' >g.ini
printf '[sensor]\nnoise_density = 60 ug/sqrt(Hz)\nrate_random_walk = 0.002 m/s^2/sqrt(h)\n' >a.ini
run "simulate gyro" 0 simulate --sensor g.ini --rate 50 --duration 1200 --axes 3 --seed 11 -o g.csv
run "simulate accel" 0 simulate --sensor a.ini --rate 50 --duration 1200 --axes 3 --seed 12 -o a.csv
paste -d, g.csv a.csv | cut -d, -f1-4,6-8 >imu.csv
run "exports" 0 allan -q --export kalibr:k.yaml --export openvins:o.yaml \
	--export imu_utils:u.yaml imu.csv
run "exports inflated" 0 allan -q --inflate 10 --export kalibr:k10.yaml \
	--export openvins:o10.yaml --export imu_utils:u10.yaml imu.csv
for f in k:kalibr o:openvins u:imu_utils k10:kalibr o10:openvins u10:imu_utils; do
	run "own $f" 0 audit --format json "${f%%:*}.yaml"
	json_check "own ${f%%:*}.yaml audits clean" "$T/out" ".clean and .findings == [] and .format == \"${f#*:}\" and .written_by == \"sensorscope\" and (.values | length) == 4"
done
# a 30 s record: K only bounded, the bound large beside N (the lines would
# cross within seconds): the files say so, no finding
run "simulate short gyro" 0 simulate --sensor g.ini --rate 100 --duration 30 --axes 3 --seed 5 -o gs.csv
run "simulate short accel" 0 simulate --sensor a.ini --rate 100 --duration 30 --axes 3 --seed 6 -o as.csv
paste -d, gs.csv as.csv | cut -d, -f1-4,6-8 >short.csv
run "short exports" 0 allan -q --export kalibr:ks.yaml --export openvins:os.yaml \
	--export imu_utils:us.yaml short.csv
for f in ks os us; do
	run "own short $f.yaml" 0 audit --format json --rate 100 $f.yaml
	json_check "own short $f.yaml audits clean" "$T/out" '.clean'
done
# the other targets are formats audit does not read: said, not misread
run "other exports" 0 allan -q --export vins:v.yaml --export gtsam:gt.yaml imu.csv
for f in v gt; do
	run "own $f.yaml: not read" 1 audit $f.yaml
	one_line_error "own $f.yaml: not read"
	has "own $f.yaml: named as sensorscope's" "$T/err" 'a sensorscope export for another consumer'
done
run "own imu_utils with --rate" 0 audit --format json --rate 50 u.yaml
json_check "own imu_utils with --rate is clean" "$T/out" '.clean and .update_rate_hz == 50 and .rate_from == "--rate"'
run "own kalibr of a sample" 0 allan -q --export kalibr:s.yaml "$SAMPLES/gyro-static.csv"
run "own kalibr text" 0 audit s.yaml
has "clean text" "$T/out" '^s.yaml: Kalibr imu.yaml written by sensorscope, rate 10 Hz \(update_rate\): no findings$'
run "own kalibr --strict" 0 audit --strict s.yaml

# allan_variance_ros' imu.yaml (its README's example): clean
cat >avr.yaml <<'EOF'
#Accelerometer
accelerometer_noise_density: 0.006308226052016165 
accelerometer_random_walk: 0.00011673723527962174 

#Gyroscope
gyroscope_noise_density: 0.00015198973532354657 
gyroscope_random_walk: 2.664506559330434e-06 

rostopic: '/sensors/imu' #Make sure this is correct
update_rate: 400.0 #Make sure this is correct
EOF
run "allan_variance_ros yaml" 0 audit --format json avr.yaml
json_check "allan_variance_ros yaml: recognised, clean" "$T/out" '.format == "allan_variance_ros" and .clean and .update_rate_hz == 400'

# a zero, a negative, a NaN and a word; no update_rate (Kalibr needs it)
cat >zero.yaml <<'EOF'
accelerometer_noise_density: 0
accelerometer_random_walk: -3e-4
gyroscope_noise_density: nan
gyroscope_random_walk: tiny
EOF
run "zero" 0 audit --format json zero.yaml
json_check "zero: line 1, no corrected value" "$T/out" '.findings[] | select(.key == "accelerometer_noise_density") | .problem == "zero" and .line == 1 and .severity == "error" and .corrected == null'
json_check "negative" "$T/out" '.findings[] | select(.key == "accelerometer_random_walk") | .problem == "invalid_value" and .line == 2'
json_check "NaN" "$T/out" '.findings[] | select(.key == "gyroscope_noise_density") | .problem == "invalid_value" and .line == 3'
json_check "a word" "$T/out" '.findings[] | select(.key == "gyroscope_random_walk") | .problem == "not_a_number" and .line == 4'
json_check "missing update_rate, no line" "$T/out" '.findings[] | select(.key == "update_rate") | .problem == "missing_rate" and .line == null and .corrected == null'
json_check "five findings" "$T/out" '(.findings | length) == 5 and (.clean | not)'
run "zero --rate 200" 0 audit --format json --rate 200 zero.yaml
json_check "missing update_rate: corrected by --rate" "$T/out" '.findings[] | select(.key == "update_rate") | .corrected == 200 and .unit == "Hz"'
run "zero --strict" 1 audit --strict zero.yaml
has "--strict still reports" "$T/out" '^zero.yaml:1: accelerometer_noise_density: 0 is never a valid noise value'

# update_rate 400 for an IMU at 100 Hz (--rate): corrected 100
run "rate mismatch" 0 audit --format json --rate 100 avr.yaml
json_check "update_rate 400 vs 100: rate_mismatch" "$T/out" '(.findings | length) == 1 and .findings[0].problem == "rate_mismatch" and .findings[0].line == 10 and .findings[0].corrected == 100 and .update_rate_hz == 100 and .rate_from == "--rate"'
run "rate agrees" 0 audit --format json --rate 400.0 avr.yaml
json_check "update_rate 400 = --rate 400: clean" "$T/out" '.clean and .rate_from == "file"'

# sigma sqrt(f) with the continuous value beside it (error): at 200 Hz,
# 1.767767e-4 x 14.142136 = 2.5e-3; the random walk 2.0e-6 is the
# continuous 2.828427e-5 over sqrt(200) (Kalibr's discrete bias step)
cat >disc.yaml <<'EOF'
#gyroscope_noise_density: 1.767767e-4
gyroscope_noise_density: 0.0025
gyroscope_random_walk: 2.0e-6 # continuous 2.828427e-5
accelerometer_noise_density: 2.0e-3 # per-axis 2.0e-3, 2.1e-3
accelerometer_random_walk: 3.0e-5
update_rate: 200
EOF
run "discrete" 0 audit --format json disc.yaml
json_check "sigma sqrt(f) from a commented-out value" "$T/out" '.findings[] | select(.key == "gyroscope_noise_density") | .problem == "discrete_density" and .severity == "error" and .line == 2 and ((.corrected - 1.767767e-4) | fabs) < 1e-10 and .unit == "rad/s/sqrt(Hz)"'
json_check "K / sqrt(f) from the comment" "$T/out" '.findings[] | select(.key == "gyroscope_random_walk") | .problem == "discrete_random_walk" and .line == 3 and ((.corrected - 2.828427e-5) | fabs) < 1e-11'
json_check "equal numbers are no finding (accelerometer)" "$T/out" '(.findings | length) == 2'
run "discrete text" 0 audit disc.yaml
has "text: file, line, key, corrected with unit" "$T/out" '^disc.yaml:2: gyroscope_noise_density: 0.0025 is 0.0001768 times sqrt\(update_rate 200 Hz\).*; corrected: 0.000176777 rad/s/sqrt\(Hz\)$'

# sigma sqrt(f) by magnitude (likely): 0.05 rad/s/sqrt(Hz) > 1 deg/s/sqrt(Hz)
# = 0.01745, while 0.05 / 14.142136 = 3.535534e-3 is plausible; the
# accelerometer's 0.2 m/s^2/sqrt(Hz) > 10 mg/sqrt(Hz) at 100 Hz: 0.2 / 10 = 0.02
printf 'gyroscope_noise_density: 0.05\ngyroscope_random_walk: 4e-5\nupdate_rate: 200\n' >big.yaml
run "big" 0 audit --format json big.yaml
json_check "density above the class: likely sigma sqrt(f)" "$T/out" '.findings | length == 1 and .[0].problem == "discrete_density" and .[0].severity == "likely" and ((.[0].corrected - 3.535534e-3) | fabs) < 1e-9'
printf 'accelerometer_noise_density: 0.2\naccelerometer_random_walk: 1e-3\nupdate_rate: 100\n' >bigacc.yaml
run "big accel" 0 audit --format json bigacc.yaml
json_check "accelerometer density: corrected 0.02" "$T/out" '.findings[0].problem == "discrete_density" and ((.findings[0].corrected - 0.02) | fabs) < 1e-12 and .findings[0].unit == "m/s^2/sqrt(Hz)"'
# without a rate: implausible, no corrected value; and one below 1e-6
printf 'gyroscope_noise_density: 0.05\ngyroscope_random_walk: 4e-5\n' >norate.yaml
run "big, no rate" 0 audit --format json norate.yaml
json_check "implausible without a rate" "$T/out" '(.findings[] | select(.key == "gyroscope_noise_density") | .problem == "implausible_magnitude" and .corrected == null) and (.findings | length) == 2'
printf 'gyroscope_noise_density: 5e-7\ngyroscope_random_walk: 1e-9\nupdate_rate: 100\n' >small.yaml
run "small" 0 audit --format json small.yaml
json_check "below 1e-6 rad/s/sqrt(Hz)" "$T/out" '.findings[0].problem == "implausible_magnitude" and .findings[0].line == 1'

# N and K crossing at tau_c = sqrt(3) 1.7e-4 / 5e-5 = 5.89 s < 10 s:
# likely a bias instability in the random-walk field
printf 'gyroscope_noise_density: 1.7e-4\ngyroscope_random_walk: 5e-5\nupdate_rate: 200\n' >bi.yaml
run "bias instability as K" 0 audit --format json bi.yaml
json_check "tau_c 5.89 s: likely B in K" "$T/out" '.findings | length == 1 and .[0].key == "gyroscope_random_walk" and .[0].problem == "bias_instability_in_random_walk" and .[0].severity == "likely" and .[0].corrected == null and (.[0].message | test("5.89 s"))'
# tau_c = sqrt(3) 2e-3 / 2e-8 = 1.732e5 s > 1e5 s, and / sqrt(400) = 8660 s:
# likely sigma sqrt(f): 2e-3 / 20 = 1e-4
printf 'gyroscope_noise_density: 2e-3\ngyroscope_random_walk: 2e-8\nupdate_rate: 400\n' >far.yaml
run "far crossing" 0 audit --format json far.yaml
json_check "tau_c 1.73e5 s: likely sigma sqrt(f), corrected 1e-4" "$T/out" '.findings | length == 1 and .[0].key == "gyroscope_noise_density" and .[0].problem == "discrete_density" and ((.[0].corrected - 1e-4) | fabs) < 1e-12'

# OpenVINS: keys under imu0, a zero random walk
cat >chain.yaml <<'EOF'
%YAML:1.0 # need to specify the file type at the top!

imu0:
  T_i_b:
    - [1.0, 0.0, 0.0, 0.0]
    - [0.0, 1.0, 0.0, 0.0]
    - [0.0, 0.0, 1.0, 0.0]
    - [0.0, 0.0, 0.0, 1.0]
  accelerometer_noise_density: 2.0000e-3  # [ m / s^2 / sqrt(Hz) ]   ( accel "white noise" )
  accelerometer_random_walk: 3.0000e-3    # [ m / s^3 / sqrt(Hz) ].  ( accel bias diffusion )
  gyroscope_noise_density: 1.6968e-04      # [ rad / s / sqrt(Hz) ]   ( gyro "white noise" )
  gyroscope_random_walk: 0.0        # [ rad / s^2 / sqrt(Hz) ] ( gyro bias diffusion )
  rostopic: /imu0
  time_offset: 0.0
  update_rate: 400.0
  model: "kalibr"
EOF
run "openvins" 0 audit --format json chain.yaml
json_check "openvins: zero under imu0, line 12" "$T/out" '.format == "openvins" and (.findings[] | select(.key == "imu0.gyroscope_random_walk") | .problem == "zero" and .line == 12)'
# accelerometer: tau_c = sqrt(3) 2e-3 / 3e-3 = 1.15 s: likely B in K
json_check "openvins: accelerometer random walk likely B" "$T/out" '.findings[] | select(.key == "imu0.accelerometer_random_walk") | .problem == "bias_instability_in_random_walk"'

# imu_utils (its own sample output, DJI A3): *_w with no word on what it
# is: the Allan minimum; as B, 2.9438676e-5 / 0.6642825 = 4.431650e-5 rad/s
# and 6.3249252e-4 / 0.6642825 = 9.521439e-4 m/s^2
cat >A3_imu_param.yaml <<'EOF'
%YAML:1.0
---
type: IMU
name: A3
Gyr:
   unit: " rad/s"
   avg-axis:
      gyr_n: 1.0351286977809465e-04
      gyr_w: 2.9438676109223402e-05
   x-axis:
      gyr_n: 1.0312669892959053e-04
      gyr_w: 3.3765827874234673e-05
Acc:
   unit: " m/s^2"
   avg-axis:
      acc_n: 1.3985049290745563e-03
      acc_w: 6.3249251509920116e-04
EOF
run "imu_utils" 0 audit --format json A3_imu_param.yaml
json_check "imu_utils gyr_w: likely B, read as B" "$T/out" '.format == "imu_utils" and (.findings[] | select(.key == "Gyr.avg-axis.gyr_w") | .line == 9 and .severity == "likely" and .problem == "bias_instability_in_random_walk" and ((.as_bias_instability - 4.431650e-5) | fabs) < 1e-10)'
json_check "imu_utils acc_w: read as B" "$T/out" '.findings[] | select(.key == "Acc.avg-axis.acc_w") | .line == 17 and ((.as_bias_instability - 9.521439e-4) | fabs) < 1e-9'
json_check "imu_utils: two findings" "$T/out" '(.findings | length) == 2'
run "imu_utils --strict" 1 audit --strict A3_imu_param.yaml

# allan_variance_ros' printed summary (its README's example): each "Bias
# Instability" is the Allan minimum: B = 0.00049 / 0.6642825 = 7.376380e-4
# deg/s (X gyro), 0.00153 / 0.6642825 = 2.303237e-3 m/s^2 (Y accelerometer)
cat >avr.txt <<'EOF'
ACCELEROMETER:
X Velocity Random Walk:  0.00333 m/s/sqrt(s)  0.19983 m/s/sqrt(hr)
Y Velocity Random Walk:  0.01079 m/s/sqrt(s)  0.64719 m/s/sqrt(hr)
Z Velocity Random Walk:  0.00481 m/s/sqrt(s)  0.28846 m/s/sqrt(hr)
X Bias Instability:  0.00055 m/s^2  7173.28800 m/hr^2
Y Bias Instability:  0.00153 m/s^2  19869.01200 m/hr^2
Z Bias Instability:  0.00052 m/s^2  6701.58000 m/hr^2
X Accel Random Walk:  0.00008 m/s^2/sqrt(s)
Y Accel Random Walk:  0.00020 m/s^2/sqrt(s)
Z Accel Random Walk:  0.00007 m/s^2/sqrt(s)
GYROSCOPE:
X Angle Random Walk:  0.00787 deg/sqrt(s)  0.47215 deg/sqrt(hr)
Y Angle Random Walk:  0.00987 deg/sqrt(s)  0.59204 deg/sqrt(hr)
Z Angle Random Walk:  0.00839 deg/sqrt(s)  0.50331 deg/sqrt(hr)
X Bias Instability:  0.00049 deg/s  1.76568 deg/hr
Y Bias Instability:  0.00136 deg/s  4.88153 deg/hr
Z Bias Instability:  0.00088 deg/s  3.15431 deg/hr
X Rate Random Walk:  0.00007 deg/s/sqrt(s)
Y Rate Random Walk:  0.00000 deg/s/sqrt(s)
Z Rate Random Walk:  0.00011 deg/s/sqrt(s)
EOF
run "allan_variance_ros summary" 0 audit --format json avr.txt
json_check "summary: recognised" "$T/out" '.format == "allan_variance_ros_text"'
json_check "summary: X gyro B = min / 0.6643" "$T/out" '.findings[] | select(.line == 15) | .problem == "allan_minimum_as_b" and .severity == "error" and .unit == "deg/s" and ((.corrected - 7.376380e-4) | fabs) < 1e-9'
json_check "summary: Y accelerometer B" "$T/out" '.findings[] | select(.line == 6) | .unit == "m/s^2" and ((.corrected - 2.303237e-3) | fabs) < 1e-9'
json_check "summary: a printed 0 is a finding" "$T/out" '.findings[] | select(.line == 19) | .problem == "zero"'
json_check "summary: seven findings" "$T/out" '(.findings | length) == 7'
run "summary text" 0 audit avr.txt
has "summary text line" "$T/out" '^avr.txt:15: X Bias Instability: 0.00049 deg/s \(GYROSCOPE\) is the minimum of the Allan deviation.*; corrected: 0.000737638 deg/s$'
# a byte-order mark (Windows editors), a rate of 0, a sensor's term missing
printf '\357\273\277update_rate: 200\ngyroscope_noise_density: 1.7e-4\ngyroscope_random_walk: 2.0e-6\n' >"$T/bom.yaml"
run "audit a file with a byte-order mark" 0 audit "$T/bom.yaml"
lacks "a BOM: update_rate still read" "$T/out" "update_rate: missing"
printf 'update_rate: 0\ngyroscope_noise_density: 1.7e-4\ngyroscope_random_walk: 2.0e-6\n' >"$T/r0.yaml"
run "audit update_rate 0" 0 audit "$T/r0.yaml"
has "a rate of 0: a rate's words, not a noise value's" "$T/out" "update_rate: 0 Hz: a sample rate is a positive frequency"
printf 'update_rate: 200\ngyroscope_noise_density: 1.7e-4\n' >"$T/half.yaml"
run "audit a gyro without its random walk" 0 audit "$T/half.yaml"
has "the missing random walk: a finding" "$T/out" "gyroscope_random_walk: missing: a filter reading the file needs the gyro's random walk"
lacks "no accelerometer: nothing asked of it" "$T/out" "accelerometer"
done_testing
