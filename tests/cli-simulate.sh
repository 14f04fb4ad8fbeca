#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope simulate: files that info and allan read back, determinism,
# axes and names, binary output, temperature profiles, tones, the
# simulate -> allan round trip, and every usage and data error.
. "$(dirname "$0")/lib.sh"

cat >"$T/gyro.ini" <<'EOF'
[sensor]
name = test gyro
range = 250 deg/s
noise_density = 0.15 deg/sqrt(h)
bias_instability = 2 deg/h
bias = 0.1 deg/s
EOF
cat >"$T/acc.ini" <<'EOF'
[sensor]
noise_density = 100 ug/sqrt(Hz)
bias = 2 mg
bias_tempco = 0.1 mg/degC
EOF

run "simulate" 0 simulate --sensor "$T/gyro.ini" --rate 100 --duration 60 -o "$T/g.csv"
has "header" "$T/g.csv" '^t \[s\],gx \[deg/s\]$'
run "info reads it" 0 info --format json "$T/g.csv"
json_check "info: 100 Hz, 6000 samples, deg/s, mean = bias" "$T/out" \
  '.rate_hz == 100 and .channels[0].samples == 6000 and .channels[0].unit == "deg/s" and (.channels[0].mean - 0.1 | fabs) < 0.01'

run "same seed" 0 simulate --sensor "$T/gyro.ini" --rate 100 --duration 60 -o "$T/g2.csv"
if cmp -s "$T/g.csv" "$T/g2.csv"; then ok "same seed, same file"; else not_ok "same seed, same file"; fi
run "other seed" 0 simulate --sensor "$T/gyro.ini" --rate 100 --duration 60 --seed 2 -o "$T/g3.csv"
if cmp -s "$T/g.csv" "$T/g3.csv"; then not_ok "other seed differs"; else ok "other seed differs"; fi

run "three axes, names" 0 simulate --sensor "$T/gyro.ini" --rate 50 --duration 10 --axes 3 --names x,y,z -u deg/h
has "three named columns in deg/h" "$T/out" '^t \[s\],x \[deg/h\],y \[deg/h\],z \[deg/h\]$'
run "default names" 0 simulate --sensor "$T/gyro.ini" --rate 50 --duration 1 --axes 3
has "gx gy gz" "$T/out" '^t \[s\],gx \[deg/s\],gy \[deg/s\],gz \[deg/s\]$'

run "binary f64" 0 simulate --sensor "$T/gyro.ini" --rate 100 --duration 2min --binary f64 -o "$T/g.bin"
run "info reads binary" 0 info --format json "$T/g.bin"
json_check "binary: 12000 samples at 100 Hz" "$T/out" '.channels[0].samples == 12000 and .rate_hz == 100'

# temperature: accelerometer with a triangle cycle and a bias polynomial
run "temperature cycle" 0 simulate --sensor "$T/acc.ini" --rate 10 --duration 600 \
	--temp-cycle 0:40:300:triangle --temp-noise 0.01 --temp-coeffs 0.001 -u g -o "$T/a.csv"
run "info: temperature column" 0 info --format json "$T/a.csv"
json_check "temperature range and unit" "$T/out" \
  '.temperature.min < 0.1 and .temperature.max > 39.9 and .channels[0].unit == "g" and .channels[0].name == "ax"'
run "temperature ramp" 0 simulate --sensor "$T/acc.ini" --rate 1 --duration 300 \
	--temp-ramp 20:30:0.05 --hysteresis 0.5mg --gradient 0.01 -o "$T/r.csv"
has "ramp ends held at 30" "$T/r.csv" ',30$'
run "tone and input" 0 simulate --sensor "$T/gyro.ini" --rate 100 --duration 10 \
	--tone 10:0.5 --tone 20:0.1:90 --input "15 deg/h" --quantize 0.001 -o "$T/t.csv"
run "tone: amplitude shows in the spread" 0 info --format json "$T/t.csv"
json_check "tone sd ~ 0.5/sqrt(2)" "$T/out" '(.channels[0].sd - 0.36 | fabs) < 0.03'

# round trip: the fitted N and B bracket the spec at 95 %
run "simulate 2 h" 0 simulate --sensor "$T/gyro.ini" --rate 20 --duration 2h --binary f64 -o "$T/long.bin"
run "allan of the simulation" 0 allan --format json --ci 0.95 "$T/long.bin"
json_check "N and B inside their 95 % intervals" "$T/out" \
  '.channels[0].noise | (.N.lo <= 0.15 and .N.hi >= 0.15 and .B.lo <= 2 and .B.hi >= 2)'

# errors
run "no sensor" 2 simulate --rate 100 --duration 1
one_line_error "no sensor"
run "no rate" 2 simulate --sensor "$T/gyro.ini" --duration 1
run "no duration" 2 simulate --sensor "$T/gyro.ini" --rate 100
run "zero duration" 2 simulate --sensor "$T/gyro.ini" --rate 100 --duration 0
run "bad unit" 2 simulate --sensor "$T/gyro.ini" --rate 100 --duration 1 -u m/s^2
one_line_error "bad unit"
run "bad tone" 2 simulate --sensor "$T/gyro.ini" --rate 100 --duration 1 --tone x
run "tone above Nyquist" 1 simulate --sensor "$T/gyro.ini" --rate 100 --duration 1 --tone 60:1
one_line_error "tone above Nyquist"
run "bad ramp" 2 simulate --sensor "$T/gyro.ini" --rate 100 --duration 1 --temp-ramp 30:20:0.1
run "bad cycle" 2 simulate --sensor "$T/gyro.ini" --rate 100 --duration 1 --temp-cycle 0:1
run "missing spec file" 1 simulate --sensor "$T/none.ini" --rate 100 --duration 1
one_line_error "missing spec file"
run "--names t" 2 simulate --sensor "$T/gyro.ini" --rate 10 --duration 1 --names t
has "--names t: the time column's name" "$T/err" "--names: 't' twice"
run "--names a,a" 2 simulate --sensor "$T/gyro.ini" --rate 10 --duration 1 --axes 2 --names a,a
run "--names a,b,c for two axes" 2 simulate --sensor "$T/gyro.ini" --rate 10 --duration 1 --axes 2 --names a,b,c
has "surplus names: said" "$T/err" "more names than the 2 axes \('c' left\)"
run "--temp and --temp-ramp" 2 simulate --sensor "$T/gyro.ini" --rate 10 --duration 1 --temp 20 --temp-ramp 20:60:1
has "two temperature profiles: refused" "$T/err" "give one temperature profile"
run "a directory as the spec" 1 simulate --sensor "$T" --rate 100 --duration 1
has "a directory as the spec: says so" "$T/err" "$T: is a directory$"
printf '[sensor]\nnoise_density = -1 deg/sqrt(h)\n' >"$T/neg.ini"
run "negative noise" 1 simulate --sensor "$T/neg.ini" --rate 100 --duration 1
one_line_error "negative noise"
run "operand" 2 simulate --sensor "$T/gyro.ini" --rate 100 --duration 1 extra
run "into a missing directory" 1 simulate --sensor "$T/gyro.ini" --rate 100 --duration 1 -o "$T/no/x.csv"
one_line_error "into a missing directory"
done_testing
