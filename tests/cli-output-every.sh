#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Every option that writes a file, of every command (issue 13, "must
# show"): what the user owns survives it.  For each command and option:
#   a device      OPT /dev/null: exit 0, /dev/null still a character device;
#   a FIFO        OPT FIFO (a reader on it): exit 0, still a FIFO, the reader
#                 got the output;
#   a link        OPT LINK -> TARGET: exit 0, the link still a link to
#                 TARGET, TARGET holds the new output;
#   an input      OPT INPUT (the capture or spec the command reads): exit 2,
#                 one line, the input byte for byte as it was.
# The figures (--plot) are in cli-output-every-plot.sh.
# Report folders (run -o, report -o) are folders, not files: a link to a
# folder and a folder holding the input are tested in cli-output.sh.
. "$(dirname "$0")/lib.sh"
. "$(dirname "$0")/output-every.sh"

check "info -o" "$T/g.csv" info -q -o @OUT@ "$T/g.csv"
check "allan -o" "$T/g.csv" allan -q -c gx -o @OUT@ "$T/g.csv"
check "allan --kalibr" "$T/g.csv" allan -q -c gx --kalibr @OUT@ "$T/g.csv"
check "allan --openvins" "$T/euroc.csv" allan -q --openvins @OUT@ "$T/euroc.csv"
check "allan --imu-utils" "$T/g.csv" allan -q -c gx --imu-utils @OUT@ "$T/g.csv"
check "psd -o" "$T/v.csv" psd -q -o @OUT@ "$T/v.csv"
check "vibration -o" "$T/v.csv" vibration -q -o @OUT@ "$T/v.csv"
check "tempbias -o" "$T/at.csv" tempbias -q -o @OUT@ "$T/at.csv"
check "calib -o" "$T/mp.csv" calib accel -q -o @OUT@ "$T/mp.csv"
check "calib --save-calibration" "$T/mp.csv" calib accel -q --save-calibration @OUT@ "$T/mp.csv"
check "inclino calibrate -o" "$T/cal.csv" inclino calibrate -q -o @OUT@ "$T/cal.csv"
check "inclino apply -o" "$T/val.csv" inclino apply -q --lut "$T/lut.json" -o @OUT@ "$T/val.csv"
check "inclino apply -o (the LUT)" "$T/lut.json" inclino apply -q --lut "$T/lut.json" -o @OUT@ "$T/val.csv"
check "adc report -o" "$T/a16.ini" adc report -q --sensor "$T/quiet.ini" --adc "$T/a16.ini" --monte-carlo 0 -o @OUT@
check "adc quantize -o" "$T/g.csv" adc quantize -q --bits 12 --range -100:100 -o @OUT@ "$T/g.csv"
check "adc test -o" "$T/sq.csv" adc test -q --bits 10 --range -1:1 -o @OUT@ "$T/sq.csv"
check "simulate -o" "$T/s.ini" simulate -q --sensor "$T/s.ini" --rate 10 --duration 5 -o @OUT@
check "budget -o" "$T/s.ini" budget -q --sensor "$T/s.ini" --time 60 -o @OUT@
check "model -o" - model accel -q --fn 2.4kHz --zeta 0.7 -o @OUT@
check "navsim -o" - navsim -q --runs 2 --duration 20 -o @OUT@
check "heading -o" "$T/drive.csv" heading -q --reference heading_ref -o @OUT@ "$T/drive.csv"
check "walk -o" "$T/g.csv" walk -q -o @OUT@ "$T/g.csv"
# acquire replaces an existing file only with --overwrite (a recording is
# never lost by accident)
check "acquire -o" - acquire -q --source sim:speed=max --count 200 --overwrite -o @OUT@
done_testing
