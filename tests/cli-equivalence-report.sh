#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# `report` and its commands are one code path: for `report` on every
# sample capture, each stage's JSON equals the JSON of the standalone
# command that `report --dry-run` names for it (see cli-equivalence.sh).
. "$(dirname "$0")/lib.sh"
. "$top_srcdir/tests/equivalence.sh"

# report on every sample capture (imu-raw.bin with its documented layout),
# and on a raw float64 record, which the allan command reads in place and
# checks in its own pass (the scene's reader checks it)
perl -e '$s = 1; for (1 .. 200000) { $s = ($s * 16807) % 2147483647;
	print pack("d<", $s / 2147483647 * 0.01 + 0.3) }' >"$T/gyro-f64.raw"
for cap in "$SAMPLES"/*.csv "$SAMPLES"/imu-raw.bin "$T/gyro-f64.raw"; do
	b=$(basename "$cap")
	set --
	case $b in
	*.bin) set -- --raw i16:6:le --scale 0.01 -u deg/s -r 100 ;;
	*.raw) set -- --raw f64:1:le -u rad/s -r 100 ;;
	esac
	out="$T/report-$b"
	run "report $b: plan" 0 report --dry-run -o "$out" "$@" "$cap"
	cp "$T/out" "$T/plan-$b"
	run "report $b: run" 0 report -q -o "$out" "$@" "$cap"
	cp "$T/err" "$out.err"
	compare "$out" "$T/plan-$b" "report $b"
done

done_testing
