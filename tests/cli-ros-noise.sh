#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# ROS inputs, second half (the first is cli-ros.sh): the Kalibr, OpenVINS
# and imu_utils noise files from a bag with --inflate; two IMU topics and
# --topic; a scene that names its topic; allan on a 1 h 200 Hz IMU topic
# equals allan on the same data as CSV.
. "$(dirname "$0")/lib.sh"

GEN="$top_builddir/tests/gen-ros"
"$GEN" "$T/r" 200 30 || { not_ok "gen-ros"; done_testing; exit 0; }

# noise files for estimators, from the bag: values = the fit x --inflate
run "allan exports" 0 allan --format json --kalibr "$T/k.yaml" --openvins "$T/ov.yaml" \
	--imu-utils "$T/iu.yaml" --inflate 3 "$T/r/imu-lz4.bag"
gn=$(jq '[.channels[] | select(.quantity == "angular rate") | .noise.N.si] | max' "$T/out")
gx=$(jq '[.channels[] | select(.name == "gx") | .noise.N.si] | max' "$T/out")
close() { awk -v a="$1" -v b="$2" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 2e-6 * (a < 0 ? -a : a)) }'; }
v=$(sed -n 's/^  gyroscope_noise_density: \([^ ]*\).*/\1/p' "$T/ov.yaml")
if close "$v" "$(awk -v x="$gn" 'BEGIN { printf "%.17g", 3 * x }')"; then
	ok "openvins: gyroscope_noise_density = 3 x the largest gyro N ($v)"
else
	not_ok "openvins: gyroscope_noise_density $v, fit $gn x 3"
fi
has "openvins: layout" "$T/ov.yaml" '^%YAML:1.0'
has "openvins: imu0 with T_i_b" "$T/ov.yaml" '^  T_i_b:'
has "openvins: the bag's topic and rate" "$T/ov.yaml" '^  rostopic: /imu/data$'
has "openvins: update_rate" "$T/ov.yaml" '^  update_rate: 200$'
has "openvins: model" "$T/ov.yaml" '^  model: "kalibr"$'
for key in accelerometer_noise_density accelerometer_random_walk gyroscope_random_walk; do
	has "openvins: $key" "$T/ov.yaml" "^  $key: [0-9.]+e-0[0-9] +# \\["
done
v=$(sed -n 's/^gyroscope_noise_density: \([^ ]*\).*/\1/p' "$T/k.yaml")
if close "$v" "$(awk -v x="$gn" 'BEGIN { printf "%.17g", 3 * x }')"; then
	ok "kalibr: inflated like openvins"
else
	not_ok "kalibr: gyroscope_noise_density $v"
fi
has "kalibr: states the factor" "$T/k.yaml" 'times 3 \(--inflate\)'
has "imu_utils: layout" "$T/iu.yaml" '^%YAML:1.0$'
has "imu_utils: Gyr block in rad/s" "$T/iu.yaml" '^Gyr:$'
has "imu_utils: Acc unit" "$T/iu.yaml" '^   unit: " m/s\^2"$'
v=$(awk '/^   x-axis:/ { getline; print $2; exit }' "$T/iu.yaml")
if close "$v" "$(awk -v x="$gx" 'BEGIN { printf "%.17g", 3 * x }')"; then
	ok "imu_utils: x-axis gyr_n = 3 x N of gx"
else
	not_ok "imu_utils: x-axis gyr_n $v, gx N $gx"
fi
run "--inflate below 1" 2 allan --inflate 0.5 --kalibr "$T/k2.yaml" "$T/r/imu-lz4.bag"
one_line_error "--inflate below 1"
run "openvins without accelerometer" 1 allan -c gx,gy,gz --openvins "$T/ov2.yaml" "$T/r/imu-lz4.bag"
has "openvins without accelerometer: says what it needs" "$T/err" 'needs both a gyro .* and an accelerometer'
if [ -e "$T/ov2.yaml" ]; then not_ok "openvins: no file on failure"; else ok "openvins: no file on failure"; fi

# a scene names the topic in [input]
cp "$T/r/two-imu.mcap" "$T/two.mcap"
printf '[input]\nfiles = two.mcap\ntopic = /imu1/data\n[allan]\n[report]\nformats = json\noutput = sc\n' >"$T/s.ini"
run "scene with [input] topic" 0 run "$T/s.ini"
json_check "scene: allan on the named topic" "$T/sc/report.json" \
  '.results.allan.channels[0].samples == 6000 and (.results.allan.channels | length) == 6'

# allan on a 1 h 200 Hz IMU topic equals allan on the same data as CSV
"$GEN" "$T/h" 200 3600 csv && "$GEN" "$T/h" 200 3600 mcap || not_ok "gen-ros 1 h"
run "allan on the 1 h MCAP" 0 allan --format json -c gx,az "$T/h/imu-zstd.mcap"
sed 's/"file": *"[^"]*"/"file":""/' "$T/out" >"$T/allan-mcap.json"
run "allan on the 1 h CSV" 0 allan --format json -c gx,az "$T/h/imu.csv"
sed 's/"file": *"[^"]*"/"file":""/' "$T/out" >"$T/allan-csv.json"
if cmp -s "$T/allan-mcap.json" "$T/allan-csv.json"; then
	ok "allan: MCAP and CSV give the same JSON"
else
	not_ok "allan: MCAP and CSV differ"
	diff "$T/allan-mcap.json" "$T/allan-csv.json" | head -5 | diag
fi
json_check "allan on the MCAP: 720000 samples at 200 Hz" "$T/allan-mcap.json" \
  '.channels[0].samples == 720000 and .channels[0].rate_hz == 200 and .channels[0].unit == "rad/s"'

done_testing
