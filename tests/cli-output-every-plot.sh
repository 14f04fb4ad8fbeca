#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Every figure option (--plot) of every command keeps what the user owns:
# a device, a FIFO, a link and the command's own input, as in
# cli-output-every.sh.
. "$(dirname "$0")/lib.sh"
. "$(dirname "$0")/output-every.sh"

check "info --plot" "$T/g.csv" info -q --plot @OUT@ "$T/g.csv"
check "allan --plot" "$T/g.csv" allan -q -c gx --plot @OUT@ "$T/g.csv"
check "psd --plot" "$T/v.csv" psd -q --plot @OUT@ "$T/v.csv"
check "vibration --plot" "$T/v.csv" vibration -q --plot @OUT@ "$T/v.csv"
check "tempbias --plot" "$T/at.csv" tempbias -q --plot @OUT@ "$T/at.csv"
check "calib --plot" "$T/mp.csv" calib accel -q --plot @OUT@ "$T/mp.csv"
check "inclino calibrate --plot" "$T/cal.csv" inclino calibrate -q --plot @OUT@ "$T/cal.csv"
check "adc report --plot" "$T/quiet.ini" adc report -q --sensor "$T/quiet.ini" --adc "$T/a16.ini" --monte-carlo 1 --plot @OUT@
check "adc test --plot" "$T/sq.csv" adc test -q --bits 10 --range -1:1 --plot @OUT@ "$T/sq.csv"
check "budget --plot" "$T/s.ini" budget -q --sensor "$T/s.ini" --time 60,600 --plot @OUT@
check "model --plot" - model accel -q --fn 2.4kHz --zeta 0.7 --plot @OUT@
check "navsim --plot" - navsim -q --runs 2 --duration 20 --plot @OUT@
check "heading --plot" "$T/drive.csv" heading -q --reference heading_ref --plot @OUT@ "$T/drive.csv"
check "walk --plot" "$T/g.csv" walk -q --plot @OUT@ "$T/g.csv"
done_testing
