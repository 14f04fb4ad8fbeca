#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: run time against error for every option that trades one for
# the other (allan --taus, --stride and the fit, adc report --monte-carlo x
# --mc-duration, navsim --runs, walk --paths, psd --nperseg), the whole
# command each time (tests/bench-knobs.py).  Writes knobs.md and knobs.svg
# into the directory given as argument (default the build directory).
# Needs a Python 3 with numpy: $PYTHON, else Debian's /usr/bin/python3,
# else python3 on PATH; skipped without numpy.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
srcdir=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$top_builddir}
for py in "${PYTHON:-}" /usr/bin/python3 python3; do
	[ -n "$py" ] || continue
	if "$py" -c 'import numpy' 2>/dev/null; then
		exec "$py" "$srcdir/tests/bench-knobs.py" \
			"$top_builddir/src/sensorscope" "$out"
	fi
done
echo "bench-knobs: skipped (no Python 3 with numpy)"
