#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: MTIE, TIE rms, MTOTDEV, HTOTDEV and Theo1 of the built
# sensorscope (whole process) beside numpy transcriptions of their
# definitions (tests/bench-family.py), and their scaling from 1e4 to 1e7
# samples.  Needs a Python 3 with numpy: $PYTHON, else Debian's
# /usr/bin/python3, else python3 on PATH; skipped without numpy.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
srcdir=$(cd "$(dirname "$0")/.." && pwd)
for py in "${PYTHON:-}" /usr/bin/python3 python3; do
	[ -n "$py" ] || continue
	if "$py" -c 'import numpy' 2>/dev/null; then
		exec "$py" "$srcdir/tests/bench-family.py" \
			"$top_builddir/src/sensorscope"
	fi
done
echo "bench-family: skipped (no Python 3 with numpy)"
