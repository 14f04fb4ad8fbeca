#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# `report` and its commands are one code path: for `report` on every
# sample capture, each stage's JSON equals the JSON of the standalone
# command that `report --dry-run` names for it (see cli-equivalence.sh).
# This half: the samples a-f and a raw float64 record, which the allan
# command reads in place and checks in its own pass (the scene's reader
# checks it); cli-equivalence-report-g-z.sh the others.
. "$(dirname "$0")/lib.sh"
. "$top_srcdir/tests/equivalence.sh"

perl -e '$s = 1; for (1 .. 200000) { $s = ($s * 16807) % 2147483647;
	print pack("d<", $s / 2147483647 * 0.01 + 0.3) }' >"$T/gyro-f64.raw"
report_equivalence "$SAMPLES"/[a-f]*.csv "$T/gyro-f64.raw"
done_testing
