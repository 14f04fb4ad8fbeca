#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Reading speed of ROS containers against CSV (make bench): about 1 GB of
# ROS 1 bag (uncompressed chunks) and of MCAP (zstd chunks) holding a
# 200 Hz IMU topic, and the same samples as CSV (time [ns] and six %.17g
# columns), each read by the whole command `sensorscope info --format json`
# (start-up, reading, statistics), best of 3 runs, in one session.
# Environment: top_builddir; BENCH_ROS_DIR (default a temporary folder;
# needs about 4 GB).
set -u
: "${top_builddir:=.}"
S="$top_builddir/src/sensorscope"
GEN="$top_builddir/tests/gen-ros"
D=${BENCH_ROS_DIR:-$(mktemp -d "${TMPDIR:-/tmp}/sscope-bench-ros.XXXXXX")}
[ -n "${BENCH_ROS_DIR:-}" ] || trap 'rm -rf "$D"' EXIT
mkdir -p "$D"

best() { # best wall time of 3 runs of: sensorscope info FILE
	b=
	for i in 1 2 3; do
		t0=$(date +%s.%N)
		"$S" info --format json "$1" >/dev/null || { echo "FAIL $1"; exit 1; }
		t1=$(date +%s.%N)
		t=$(echo "$t1 - $t0" | bc)
		if [ -z "$b" ] || [ "$(echo "$t < $b" | bc)" = 1 ]; then b=$t; fi
	done
	echo "$b"
}
size() { du -b "$1" | cut -f1; }
report() { # NAME FILE CSV_TIME
	t=$(best "$2")
	printf '%-28s %6.0f MB  %7.3f s  %7.1f MB/s  %5.2fx the CSV speed (rows per s)\n' \
		"$1" "$(echo "$(size "$2") / 1000000" | bc -l)" "$t" \
		"$(echo "$(size "$2") / 1000000 / $t" | bc -l)" "$(echo "$3 / $t" | bc -l)"
}

# 1 GB of uncompressed bag: 374 bytes per message -> 4 h at 200 Hz
[ -f "$D/b/imu-none.bag" ] || "$GEN" "$D/b" 200 14400 bag-none
[ -f "$D/b/imu.csv" ] || "$GEN" "$D/b" 200 14400 csv
tc=$(best "$D/b/imu.csv")
printf '%-28s %6.0f MB  %7.3f s  %7.1f MB/s\n' "CSV (2.88e6 rows)" \
	"$(echo "$(size "$D/b/imu.csv") / 1000000" | bc -l)" "$tc" \
	"$(echo "$(size "$D/b/imu.csv") / 1000000 / $tc" | bc -l)"
report "ROS 1 bag, no compression" "$D/b/imu-none.bag" "$tc"
rm -f "$D/b/imu.csv"
# 1 GB of zstd MCAP: about 60 bytes per message -> 23 h at 200 Hz
[ -f "$D/m/imu-zstd.mcap" ] || "$GEN" "$D/m" 200 82800 mcap
[ -f "$D/m/imu.csv" ] || "$GEN" "$D/m" 200 82800 csv
tc=$(best "$D/m/imu.csv")
printf '%-28s %6.0f MB  %7.3f s  %7.1f MB/s\n' "CSV (1.66e7 rows)" \
	"$(echo "$(size "$D/m/imu.csv") / 1000000" | bc -l)" "$tc" \
	"$(echo "$(size "$D/m/imu.csv") / 1000000 / $tc" | bc -l)"
report "MCAP, zstd chunks" "$D/m/imu-zstd.mcap" "$tc"
