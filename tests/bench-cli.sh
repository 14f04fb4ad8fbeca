#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: the whole process of the built sensorscope, as a user runs it,
# beside the Python peers (scipy.signal.welch, pandas.read_csv,
# numpy.loadtxt and an allantools-style numpy OADEV) in the same run: times,
# ratios, peak RSS and the error of each result against the peer's.  Needs a
# Python 3 with numpy (scipy and pandas for their rows): $PYTHON, else
# Debian's /usr/bin/python3, else python3 on PATH; skipped without numpy.
# Run twice: on the machine as it is, then beside one CPU-bound competitor
# (BENCH_COMPETITORS=1), unless BENCH_COMPETITORS is set.
# BENCH_REPEAT, BENCH_N, BENCH_ROWS, BENCH_ALL_N: see tests/bench-cli.py.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
srcdir=$(cd "$(dirname "$0")/.." && pwd)
for py in "${PYTHON:-}" /usr/bin/python3 python3; do
	[ -n "$py" ] || continue
	if "$py" -c 'import numpy' 2>/dev/null; then
		for c in ${BENCH_COMPETITORS:-0 1}; do
			BENCH_COMPETITORS=$c "$py" "$srcdir/tests/bench-cli.py" \
				"$top_builddir/src/sensorscope" "$srcdir/samples"
			echo
		done
		exit 0
	fi
done
echo "bench-cli: skipped (no Python 3 with numpy)"
