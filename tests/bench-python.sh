#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Speed of the Python module's OADEV (make bench): sensorscope.allan() on
# 1e7 samples (dense taus, intervals and the noise fit) against the C
# engine called directly (the same sscope_allan_analyze() through ctypes,
# no wrapper) and against an allantools-style numpy OADEV (allantools'
# algorithm: phase = cumsum / rate, one vectorised second difference per
# tau) on the same taus; best of 3 (numpy: one run); values compared.
set -u
: "${top_builddir:=.}"
: "${top_srcdir:=$(cd "$(dirname "$0")/.." && pwd)}"
py=${PYTHON_NUMPY:-/usr/bin/python3}
PYTHONPATH="$top_srcdir/src/python" \
SENSORSCOPE_LIB="$top_builddir/src/.libs/libsensorscope.so" \
	exec "$py" "$top_srcdir/tests/python/bench_allan.py"
