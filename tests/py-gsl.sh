#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# A GSL error never aborts an interpreter that imported sensorscope
# (tests/python/test_gsl.py).
py_test=test_gsl.py
. "$(dirname "$0")/py-module.sh"
