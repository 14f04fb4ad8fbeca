#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The Python module from the build tree (PYTHONPATH=src/python, the
# library found beside it): tests/python/test_module.py, with an
# interpreter that has numpy (configure's PYTHON_NUMPY).
. "$(dirname "$0")/lib.sh"

py=${PYTHON_NUMPY:-}
if [ -z "$py" ] || ! "$py" -c 'import numpy' 2>/dev/null; then
	echo "1..0 # SKIP no Python 3 with numpy (apt-get install python3-numpy)"
	exit 0
fi
PYTHONPATH="$top_srcdir/src/python${PYTHONPATH:+:$PYTHONPATH}" \
SENSORSCOPE_LIB="$top_builddir/src/.libs/libsensorscope.so" \
	exec "$py" "$top_srcdir/tests/python/test_module.py"
