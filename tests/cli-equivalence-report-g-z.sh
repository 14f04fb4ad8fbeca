#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# `report` and its commands are one code path: for `report` on every
# sample capture, each stage's JSON equals the JSON of the standalone
# command that `report --dry-run` names for it (see cli-equivalence.sh).
# This half: the samples g-z and imu-raw.bin (with its documented
# layout); cli-equivalence-report.sh the others.
. "$(dirname "$0")/lib.sh"
. "$top_srcdir/tests/equivalence.sh"

report_equivalence "$SAMPLES"/[g-z]*.csv "$SAMPLES"/imu-raw.bin
done_testing
