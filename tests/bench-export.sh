#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: the round trip of every allan --export target on 200 records
# (tests/export-roundtrip.py): the fraction of (record, sensor, term) whose
# value, as the consumer reads it, is inside the 95 % interval of the
# capture and of the noise the consumer generates from it (target >= 0.9).
# Needs a Python 3 with numpy: $PYTHON, else /usr/bin/python3, else python3.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
srcdir=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/sscope-export.XXXXXX")
trap 'rm -rf "$work"' EXIT
for py in "${PYTHON:-}" /usr/bin/python3 python3; do
	[ -n "$py" ] || continue
	if "$py" -c 'import numpy' 2>/dev/null; then
		"$py" "$srcdir/tests/export-roundtrip.py" \
			"$top_builddir/src/sensorscope" "$work/rt" "${RECORDS:-200}" 0.95
		exit $?
	fi
done
echo "bench-export: skipped (no Python 3 with numpy)"
