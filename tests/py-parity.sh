#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The Python module refuses and warns where the command does, for the same
# reasons: tests/python/test_parity.py, run as tests/py-module.sh runs
# test_module.py.
py_test=test_parity.py
. "$(dirname "$0")/py-module.sh"
