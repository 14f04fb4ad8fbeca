#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# sensorscope.plan() gives the numbers of `sensorscope plan --format json`:
# tests/python/test_plan.py, run as tests/py-module.sh runs test_module.py.
py_test=test_plan.py
. "$(dirname "$0")/py-module.sh"
