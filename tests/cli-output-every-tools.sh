#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Every option that writes a file keeps what the user owns (see
# cli-output-every.sh): inclino, adc, simulate, budget, model, navsim,
# heading, walk and acquire.
. "$(dirname "$0")/lib.sh"
. "$(dirname "$0")/output-every.sh"

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
