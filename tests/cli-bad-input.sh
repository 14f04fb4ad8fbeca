#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Bad inputs: each gives exit 1 (data) or 2 (usage) and one line naming
# the file, line and column -- never a crash or a hang.
. "$(dirname "$0")/lib.sh"

bad() { # DESC RC PATTERN ARGS...
	desc=$1 rc=$2 pat=$3
	shift 3
	run "$desc" "$rc" "$@"
	one_line_error "$desc"
	has "$desc: message" "$T/err" "$pat"
}

: >"$T/empty.csv"
bad "empty file" 1 'empty file' info "$T/empty.csv"
bad "header only" 1 'no data rows' info "$DATA/header-only.csv"
bad "ragged row" 1 'ragged.csv: line 4: 2 columns where the header has 3' info "$DATA/ragged.csv"
bad "non-numeric cell" 1 'line 3, column 2 \(gx\): not a number .abc.' info "$DATA/text-cell.csv"
bad "NaN cell" 1 'line 3, column 3 \(gy\): NaN \(use --allow-nan' info "$DATA/nan.csv"
run "NaN allowed" 0 info --format json --allow-nan "$DATA/nan.csv"
json_check "NaN counted" "$T/out" '.channels[1].nan == 1 and .channels[1].samples == 3'
bad "no data column" 1 'no data column' info "$DATA/time-only.csv"
bad "unknown unit" 1 "unknown unit 'furlong'" info "$DATA/bad-unit.csv"
bad "missing file" 1 'no-such-file.csv: no such file' info "$T/no-such-file.csv"
bad "directory" 1 'is a directory' info "$T"
bad "unknown column" 1 "no column 'gq' \(columns: t, gx, gy\)" info -c gq "$DATA/nan.csv"
bad "unknown -u unit" 2 "-u: unknown unit 'blorbs'" info -u blorbs "$DATA/nan.csv"
bad "near -u unit: suggestions, usage" 2 "unknown unit 'degs' \\(nearest known: deg/s, deg, degC\\)" info -u degs "$DATA/nan.csv"
bad "bad raw layout" 2 "bad raw layout 'q16:6'" info --raw q16:6 -r 1 "$SAMPLES/imu-raw.bin"
head -c 1001 "$SAMPLES/imu-raw.bin" >"$T/trunc.bin"
bad "truncated raw" 1 'truncated' info --raw i16:6:le -r 100 "$T/trunc.bin"
{ head -n 102 "$SAMPLES/vibration.csv"; printf '0.0200,1.25'; } >"$T/trunc.csv"
bad "truncated text (cut mid-row)" 1 'trunc.csv: line 103: 2 columns where the header has 4' info "$T/trunc.csv"
printf 'a,b\n1,2\n\000\000\000\000' >"$T/bin.csv"
bad "binary junk" 1 'binary data' info "$T/bin.csv"
bad "infinite value" 1 'infinite value' info "$DATA/inf.csv"
bad "NaN time stamp" 1 'NaN time stamp' info --allow-nan "$DATA/nan-time.csv"
bad "time column of wrong unit" 1 "time column 't' has unit 'deg'" info "$DATA/bad-time-unit.csv"

# text input that says what is wrong: units row, decimal comma, text columns
printf 't,gx\ns,deg/s\n0,0.1\n0.01,0.2\n0.02,0.15\n' >"$T/units-row.csv"
run "units row under the header is read" 0 info --format json "$T/units-row.csv"
json_check "units row: gx in deg/s, 3 samples" "$T/out" '.channels[0].unit == "deg/s" and .channels[0].samples == 3 and .channels[0].quantity == "angular rate"'
printf 't,gx\ns,degs\n0,0.1\n0.01,0.2\n' >"$T/units-bad.csv"
bad "units row with a cell that is no unit" 1 "units-bad.csv: line 2 looks like a units row, but unknown unit 'degs' \\(nearest known: deg/s" info "$T/units-bad.csv"
printf 't;gx;gy\n0;0,1;0,3\n0,01;0,2;0,1\n' >"$T/comma.csv"
bad "decimal comma" 1 "comma.csv: line 2, column 2 \\(gx\\): '0,1' has a decimal comma: write decimal points \\(the separator is ';'" info "$T/comma.csv"
printf 't;gx\n0;1\n0,5;2\n' >"$T/comma-time.csv"
bad "decimal comma in the time column" 1 "line 3, column 1 \\(t\\): not a number '0,5'" info "$T/comma-time.csv"
printf 't,frame,node\n0,imu,a\n0.01,imu,b\n' >"$T/text-cols.csv"
bad "text columns only" 1 "no numeric data column: line 2 holds text in columns 2 \\(frame\\), 3 \\(node\\) \\(first 'imu'\\): select numeric columns with -c" info "$T/text-cols.csv"
printf 't,gx,gy\n0,0.1,abc\n0.01,0.2,0.3\n' >"$T/first-bad.csv"
bad "text in the first row only is a bad cell" 1 "line 2, column 3 \\(gy\\): not a number 'abc'" info "$T/first-bad.csv"
printf 't,gx [deg/s]\n0,0.1\n0.01,0.2\n0.02,0.1\n' >"$T/named.csv"
run "-u on a file that names its units" 0 info -u deg/h "$T/named.csv"
has "-u that changes nothing warns" "$T/err" 'warning: .*named.csv: -u deg/h changes nothing: the file names the unit of every channel \(gx: deg/s\)'
printf 't,gx\n0,0.1\n0.01,0.2\n0.02,0.1\n' >"$T/unnamed.csv"
run "-u fills a missing unit" 0 info -u deg/h --format json "$T/unnamed.csv"
json_check "-u: gx in deg/h" "$T/out" '.channels[0].unit == "deg/h"'
lacks "-u that applies does not warn" "$T/err" 'changes nothing'

# a rate comment that gives no rate: every command that needs the rate
# says which line and why, info shows it, --rate settles it
awk 'BEGIN { print "# sensor: test"; print "# rate: 10 furlongs"; print "gx [deg/s]"; for (i = 0; i < 400; i++) print (i % 7) * 0.001 }' >"$T/rate-bad.csv"
why="rate-bad.csv: no sample rate: line 2: '# rate: 10 furlongs' is not a sample rate \\(a positive frequency, as in '# rate: 100 Hz'\\); give --rate"
bad "allan: the rate comment it could not read" 1 "$why" allan "$T/rate-bad.csv"
bad "psd: the rate comment it could not read" 1 "$why" psd "$T/rate-bad.csv"
bad "walk: the rate comment it could not read" 1 "$why" walk "$T/rate-bad.csv"
run "info: rate comment it could not read" 0 info "$T/rate-bad.csv"
has "info: says why the rate is unknown" "$T/out" "rate: +unknown \\(line 2: '# rate: 10 furlongs' is not a sample rate"
run "info json: rate note" 0 info --format json "$T/rate-bad.csv"
json_check "info json: rate_note, rate null" "$T/out" '.rate_hz == null and (.rate_note | startswith("line 2: '"'"'# rate: 10 furlongs'"'"' is not"))'
run "info json: --rate settles it" 0 info --format json --rate 100 "$T/rate-bad.csv"
json_check "info json: no rate_note with a rate" "$T/out" '.rate_hz == 100 and (has("rate_note") | not)'
printf 'gx\n1\n2\n3\n' >"$T/rate-none.csv"
bad "allan: no rate at all" 1 "rate-none.csv: no sample rate: no time column and no '# rate:' comment; give --rate" allan "$T/rate-none.csv"

# huge: a 2-million-row file streamed through a pipe (no hang, bounded time)
awk 'BEGIN { print "gx [deg/s]"; for (i = 0; i < 2000000; i++) print (i % 7) * 0.001 }' >"$T/huge.csv"
run "huge via stdin" 0 info --format json -r 1000 - <"$T/huge.csv"
json_check "huge: all rows" "$T/out" '.channels[0].samples == 2000000'
done_testing
