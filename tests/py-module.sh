#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The Python module from the build tree (PYTHONPATH=src/python, the
# library found beside it): tests/python/test_module.py, with an
# interpreter that has numpy (configure's PYTHON_NUMPY); another script of
# tests/python when py_test names it (tests/py-parity.sh).
. "$(dirname "$0")/lib.sh"

py=${PYTHON_NUMPY:-}
if [ -z "$py" ] || ! "$py" -c 'import numpy' 2>/dev/null; then
	echo "1..0 # SKIP no Python 3 with numpy (apt-get install python3-numpy)"
	exit 0
fi
# a sanitizer build's library needs the ASan runtime loaded first: preloaded
# into the interpreter (whose own allocations are not checked for leaks)
if [ "${SSCOPE_SANITIZERS:-0}" = 1 ]; then
	if [ ! -f "${SSCOPE_ASAN_LIB:-}" ]; then
		echo "1..0 # SKIP sanitizer build without a libasan.so to preload"
		exit 0
	fi
	LD_PRELOAD="$SSCOPE_ASAN_LIB${LD_PRELOAD:+:$LD_PRELOAD}"
	ASAN_OPTIONS="detect_leaks=0${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
	export LD_PRELOAD ASAN_OPTIONS
fi
PYTHONPATH="$top_srcdir/src/python${PYTHONPATH:+:$PYTHONPATH}" \
SENSORSCOPE_LIB="$top_builddir/src/.libs/libsensorscope.so" \
	exec "$py" "$top_srcdir/tests/python/${py_test:-test_module.py}"
