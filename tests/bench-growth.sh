#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: how the time and memory of info, allan, the noise fit, psd
# and report grow from 1e4 to 1e8 samples (1e9 with BENCH_GROWTH_MAX=1e9),
# tests/bench-growth.py.  Needs a Python 3 with numpy: $PYTHON, else
# Debian's /usr/bin/python3, else python3 on PATH; skipped without numpy.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
export top_builddir
srcdir=$(cd "$(dirname "$0")/.." && pwd)
for py in "${PYTHON:-}" /usr/bin/python3 python3; do
	[ -n "$py" ] || continue
	if "$py" -c 'import numpy' 2>/dev/null; then
		exec "$py" "$srcdir/tests/bench-growth.py"
	fi
done
echo "bench-growth: skipped (no Python 3 with numpy)"
