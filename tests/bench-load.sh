#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: start-up against /bin/true, and the default thread team
# against one and two threads, idle and beside a CPU-bound competitor
# (tests/bench-load.py, whole process).  Needs a Python 3 with
# numpy: $PYTHON, else Debian's /usr/bin/python3, else python3 on PATH;
# skipped without numpy.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
srcdir=$(cd "$(dirname "$0")/.." && pwd)
for py in "${PYTHON:-}" /usr/bin/python3 python3; do
	[ -n "$py" ] || continue
	if "$py" -c 'import numpy' 2>/dev/null; then
		exec "$py" "$srcdir/tests/bench-load.py" \
			"$top_builddir/src/sensorscope"
	fi
done
echo "bench-load: skipped (no Python 3 with numpy)"
