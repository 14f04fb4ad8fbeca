#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: `sensorscope navsim`, 100 Monte-Carlo runs of 10 min at 100 Hz
# (60,000 samples of six axes per run), timed as the whole command on both
# cores and on one, with its error against the analytic curves: for angle
# and velocity random walk alone the spread of the errors must equal the
# budget's Schuler-bounded single-channel forms (and N sqrt(t) for the
# heading) within the sampling error of 100 runs, 1/sqrt(200) = 7 %.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
S="$top_builddir/src/sensorscope"
T=$(mktemp -d "${TMPDIR:-/tmp}/sscope-bench.XXXXXX")
trap 'rm -rf "$T"' EXIT

cat >"$T/gyro.ini" <<'EOF'
[sensor]
name = MEMS gyro (example)
range = 250 deg/s
noise_density = 0.2 deg/sqrt(h)
bias_instability = 3 deg/h
rate_random_walk = 5 deg/h/sqrt(h)
EOF
cat >"$T/acc.ini" <<'EOF'
[sensor]
name = MEMS accelerometer (example)
range = 8 g
noise_density = 60 ug/sqrt(Hz)
bias_instability = 20 ug
EOF

now() { date +%s.%N; }
# CPU seconds (user + system) of the children so far
cpu() { awk '{ print ($16 + $17) / 100 }' /proc/$$/stat; }
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg) (wall times grow with it; CPU times do not)"

t0=$(now) c0=$(cpu)
"$S" navsim --arw 0.2deg/sqrt\(h\) --vrw 60ug/sqrt\(Hz\) --runs 100 \
	--duration 10min --rate 100 --output-step 60s --seed 3 --format json \
	-o "$T/rw.json"
t1=$(now) c1=$(cpu)
echo "navsim, ARW 0.2 deg/sqrt(h) + VRW 60 ug/sqrt(Hz), 100 runs x 10 min at 100 Hz, both cores: $(echo "$t1 - $t0" | bc) s wall, $(echo "$c1 - $c0" | bc) s CPU"
if command -v jq >/dev/null 2>&1; then
	jq -r '(0.2 * 3.141592653589793 / 180 / 60) as $N |
		[.times_s, .rms.yaw_rad, .rms.roll_rad, .rms.pitch_rad, .rms.north_m, .rms.east_m,
		 .budget.attitude_rad, .budget.position_m] | transpose |
		map(select(.[0] > 0)) |
		"  error against the analytic curves (ratio - 1; sampling sd 0.071):",
		(.[] | "  t = \(.[0]) s: heading/(N sqrt t) \((.[1] / ($N * (.[0] | sqrt)) - 1) * 1000 | round / 1000), roll/budget \((.[2] / .[6] - 1) * 1000 | round / 1000), pitch/budget \((.[3] / .[6] - 1) * 1000 | round / 1000), north/budget \((.[4] / .[7] - 1) * 1000 | round / 1000), east/budget \((.[5] / .[7] - 1) * 1000 | round / 1000)"),
		"  largest |ratio - 1| over the checkpoints: \([.[] | (.[1] / ($N * (.[0] | sqrt))), (.[2] / .[6]), (.[3] / .[6]), (.[4] / .[7]), (.[5] / .[7]) | . - 1 | fabs] | max * 1000 | round / 1000)"' \
		"$T/rw.json"
fi

for th in 2 1; do
	t0=$(now) c0=$(cpu)
	"$S" navsim --sensor "$T/gyro.ini" --sensor "$T/acc.ini" --runs 100 \
		--duration 10min --rate 100 --seed 3 --threads $th --format json \
		-o "$T/mems$th.json"
	t1=$(now) c1=$(cpu)
	echo "navsim, MEMS IMU (N, B, K, range; accelerometer N, B), 100 runs x 10 min at 100 Hz, $th thread(s): $(echo "$t1 - $t0" | bc) s wall, $(echo "$c1 - $c0" | bc) s CPU"
done
if cmp -s "$T/mems1.json" "$T/mems2.json"; then
	echo "  one thread and two give the same numbers (bit for bit)"
else
	echo "  ERROR: the thread count changed the result" >&2
	exit 1
fi
if command -v jq >/dev/null 2>&1; then
	jq -r '"  after 10 min: horizontal error median \(.horizontal_m.p50[-1] | round) m, 95 % \(.horizontal_m.p95[-1] | round) m; heading rms \(.rms.yaw_rad[-1] * 180 / 3.141592653589793 * 1000 | round / 1000) deg"' "$T/mems2.json"
fi

# the wander-azimuth frame over the pole: 250 m/s for 2 h along a meridian,
# crossing the pole (and, the same route, the equator) after 1 h, at 100 Hz;
# a perfect IMU, then 0.01 deg/h on the gyro along, across and about the
# vertical: the horizontal gyros' errors must agree within 5 % (the
# vertical one's differ: its heading error meets the Earth rate at the
# equator only)
for lat in 81.9424 -8.1122; do
	t0=$(now) c0=$(cpu)
	"$S" navsim --runs 1 --duration 2h --rate 100 --latitude $lat \
		--trajectory straight:250m/s --format json -o "$T/pole-$lat.json"
	t1=$(now) c1=$(cpu)
	echo "navsim, perfect IMU, 2 h at 250 m/s from $lat deg at 100 Hz: $(echo "$t1 - $t0" | bc) s wall, $(echo "$c1 - $c0" | bc) s CPU"
	for ax in x y z; do
		case $ax in x) b=0.01deg/h,0,0 ;; y) b=0,0.01deg/h,0 ;; *) b=0,0,0.01deg/h ;; esac
		"$S" navsim --runs 1 --duration 2h --rate 100 --latitude $lat \
			--trajectory straight:250m/s --gyro-bias $b --format json \
			-o "$T/pole-$lat-$ax.json"
	done
done
if command -v jq >/dev/null 2>&1; then
	for lat in 81.9424 -8.1122; do
		jq -r --arg l "$lat" '"  perfect IMU from \($l) deg: largest position error \([.percentiles.p50 | .north_m, .east_m | .[] | fabs] | max * 1e6 | round / 1000) mm"' "$T/pole-$lat.json"
	done
	for ax in x y z; do
		jq -s -r --arg b "$ax" '"  0.01 deg/h on the \($b) gyro: after 1 h \(.[0].horizontal_m.p50[300] | round) m at the pole, \(.[1].horizontal_m.p50[300] | round) m at the equator; after 2 h \(.[0].horizontal_m.p50[-1] | round) m, \(.[1].horizontal_m.p50[-1] | round) m (ratio \(.[0].horizontal_m.p50[-1] / .[1].horizontal_m.p50[-1] * 1000 | round / 1000))"' \
			"$T/pole-81.9424-$ax.json" "$T/pole--8.1122-$ax.json"
	done
fi

# a gimballed platform against strapdown, the MEMS IMU turning at 10 deg/s
for m in strapdown gimballed; do
	t0=$(now) c0=$(cpu)
	"$S" navsim --sensor "$T/gyro.ini" --sensor "$T/acc.ini" --runs 100 \
		--duration 10min --rate 100 --seed 3 --trajectory turn:10deg/s:10m/s \
		--mechanisation $m --format json -o "$T/mech-$m.json"
	t1=$(now) c1=$(cpu)
	echo "navsim, MEMS IMU, 100 runs x 10 min turning, $m: $(echo "$t1 - $t0" | bc) s wall, $(echo "$c1 - $c0" | bc) s CPU"
	command -v jq >/dev/null 2>&1 &&
		jq -r '"  after 10 min: horizontal error median \(.horizontal_m.p50[-1] | round) m, 95 % \(.horizontal_m.p95[-1] | round) m; heading rms \(.rms.yaw_rad[-1] * 180 / 3.141592653589793 * 1000 | round / 1000) deg"' "$T/mech-$m.json"
done
