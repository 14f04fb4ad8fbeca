#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: a big ROS 2 recording read in bounded memory.  Generates an
# MCAP of about BENCH_ROS_BIG_GB gigabytes (default 10) in which a 200 Hz
# IMU topic sits among the frames of a 30 Hz camera (zstd chunks of 4 MiB,
# tests/gen-ros mcap-camera), reads it with the whole command
# `sensorscope info --format json` on the default threads and on one
# (/usr/bin/time: wall, CPU, peak RSS), and deletes it.  Needs about
# BENCH_ROS_BIG_GB of free disk in BENCH_ROS_DIR (default a temporary
# folder).  Targets: at least 300 MB/s, peak RSS at most 1 GB.
set -u
: "${top_builddir:=.}"
S="$top_builddir/src/sensorscope"
GEN="$top_builddir/tests/gen-ros"
GB=${BENCH_ROS_BIG_GB:-10}
D=$(mktemp -d "${BENCH_ROS_DIR:-${TMPDIR:-/tmp}}/sscope-bench-ros-big.XXXXXX")
trap 'rm -rf "$D"' EXIT
if [ ! -x /usr/bin/time ]; then
	echo "bench-ros-big: /usr/bin/time (Debian package time) is needed for the peak memory: skipped"
	exit 0
fi
# 4.64 MB of file per second of recording (gen-ros: half of each frame noise)
dur=$(echo "$GB * 1000000000 / 4640000" | bc)
t0=$(date +%s.%N)
"$GEN" "$D" 200 "$dur" mcap-camera || exit 1
t1=$(date +%s.%N)
F="$D/camera-imu-zstd.mcap"
mb=$(echo "$(du -b "$F" | cut -f1) / 1000000" | bc -l)
printf 'generated %.0f MB (%d s of recording) in %.1f s; load average %s\n' \
	"$mb" "$dur" "$(echo "$t1 - $t0" | bc)" "$(cut -d' ' -f1-3 /proc/loadavg)"
for th in default 1; do
	for i in 1 2; do
		if [ "$th" = default ]; then
			/usr/bin/time -f "%e %U %S %M" -o "$D/time" "$S" info --format json "$F" >"$D/out.json" || exit 1
		else
			OMP_NUM_THREADS=1 /usr/bin/time -f "%e %U %S %M" -o "$D/time" "$S" info --format json "$F" >"$D/out.json" || exit 1
		fi
		read -r w us sy kb <"$D/time"
		printf 'info, %s threads, run %d: %.2f s wall, %.2f s CPU, %.0f MB/s, peak RSS %.0f MB\n' \
			"$th" "$i" "$w" "$(echo "$us + $sy" | bc)" "$(echo "$mb / $w" | bc -l)" \
			"$(echo "$kb / 1024" | bc -l)"
	done
done
rows=$(sed -n 's/.*"rows": *\([0-9]*\).*/\1/p' "$D/out.json" | head -n 1)
echo "IMU rows read: $rows (expected about $((dur * 200)))"
