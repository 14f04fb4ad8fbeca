#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: `sensorscope report` on a 24 h, 100 Hz, 6-axis capture
# (8.64 million rows: a simulated MEMS gyro triad and accelerometer triad
# with known noise terms), total wall time and the time of each stage
# (report.json "wall_time_s"), and the error of the recovered angle random
# walk against the simulated one.  BENCH_HOURS=N shortens the record.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
S="$top_builddir/src/sensorscope"
H=${BENCH_HOURS:-24}
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

t0=$(date +%s.%N)
"$S" simulate --sensor "$T/gyro.ini" --rate 100 --duration "${H}h" --axes 3 \
	--digits 8 --seed 21 -o "$T/g.csv"
"$S" simulate --sensor "$T/acc.ini" --rate 100 --duration "${H}h" --axes 3 \
	--digits 8 --seed 22 --names ax,ay,az -o "$T/a.csv"
# one 6-axis file: time and gyro columns, then the accelerometer columns
cut -d, -f2- "$T/a.csv" | paste -d, "$T/g.csv" - >"$T/imu.csv"
rm -f "$T/g.csv" "$T/a.csv"
t1=$(date +%s.%N)
rows=$(($(wc -l <"$T/imu.csv") - 1))
mb=$(du -m "$T/imu.csv" | cut -f1)
echo "capture: $rows rows x 6 channels, $mb MB of CSV (simulated in $(echo "$t1 - $t0" | bc) s)"

t0=$(date +%s.%N)
if [ -x /usr/bin/time ]; then
	# CPU time (user + system, every thread) and peak RSS beside the
	# wall time: on a loaded machine the wall time is mostly waiting
	/usr/bin/time -f '%U %S %M' -o "$T/cpu" "$S" report -q -o "$T/rep" "$T/imu.csv"
else
	"$S" report -q -o "$T/rep" "$T/imu.csv"
fi
t1=$(date +%s.%N)
echo "report: $(echo "$t1 - $t0" | bc) s wall in total (load average $(cut -d' ' -f1 /proc/loadavg))"
if [ -s "$T/cpu" ]; then
	read -r u s m <"$T/cpu"
	echo "  CPU $(echo "$u + $s" | bc) s (user $u, system $s), peak RSS $((m / 1024)) MB"
fi
if command -v jq >/dev/null 2>&1; then
	jq -r '.wall_time_s | to_entries[] | "  \(.key): \(.value * 1000 | round / 1000) s"' "$T/rep/report.json"
	# the simulated N is 0.2 deg/sqrt(h) on each gyro axis
	jq -r '[.summary[] | select(.quantity == "angle random walk N")] |
		"  angle random walk N: " + (map("\(.value * 10000 | round / 10000)") | join(", ")) +
		" deg/sqrt(h) (simulated 0.2; largest relative error " +
		(map((.value - 0.2) / 0.2 | fabs) | max * 1e4 | round / 1e4 | tostring) + ")"' \
		"$T/rep/report.json"
fi
