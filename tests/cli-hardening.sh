#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Hardening of the input side (issue 13): inputs that once read out of
# bounds, numbers at the ends of the double range, time columns that are
# not time, silently accepted inputs and malformed --raw layouts.  Each
# case states its exit status and the message a user gets.
. "$(dirname "$0")/lib.sh"

CORPUS="$top_srcdir/tests/fuzz/corpus"

bad() { # DESC RC PATTERN ARGS...
	desc=$1 rc=$2 pat=$3
	shift 3
	run "$desc" "$rc" "$@"
	one_line_error "$desc"
	has "$desc: message" "$T/err" "$pat"
}

bad_in() { # DESC RC PATTERN INPUT ARGS...
	desc=$1 rc=$2 pat=$3 input=$4
	shift 4
	run_in "$desc" "$rc" "$input" "$@"
	one_line_error "$desc"
	has "$desc: message" "$T/err" "$pat"
}

# ---- 1. a last comment or blank line without a newline (read past the
# end of the buffer before): a file and a pipe, each "no data rows"
for f in comment-no-newline rate-comment-no-newline blanks-no-newline \
	comment-4096; do
	bad "$f (file)" 1 "$f.csv: no data rows" info "$CORPUS/text/$f.csv"
	bad_in "$f (stdin)" 1 '\(stdin\): no data rows' "$CORPUS/text/$f.csv" \
		info -
done

# ---- 2. MAT-file dimensions whose product wraps around (2^31 x 2^30
# doubles in 0 bytes): refused, never read outside the file
for f in dims-overflow dims-overflow-positive; do
	bad "MAT $f" 1 "$f.mat: MAT-file: malformed array at byte 128" \
		info "$CORPUS/mat/$f.mat"
	bad "MAT $f, one column" 1 "malformed array" \
		info -c x_1 "$CORPUS/mat/$f.mat"
done

# ---- 12. a malformed --raw layout is a usage error (exit 2, one line that
# says what is wrong), on the command line and in a scene; '' is refused
raw_bad() { # LAYOUT PATTERN
	bad "--raw '$1'" 2 "info: --raw: $2" info --raw "$1" -r 100 \
		"$SAMPLES/imu-raw.bin"
}
raw_bad i16:0 "bad raw layout 'i16:0': channels must be 1 to 4096"
raw_bad u64:1 "bad raw layout 'u64:1': unknown type"
raw_bad i16:3:xx "bad raw layout 'i16:3:xx': byte order 'xx' is not le or be"
raw_bad i16:-1 "bad raw layout 'i16:-1': the channel count is not a whole number"
raw_bad : "bad raw layout ':': missing type"
raw_bad i16:65536 "bad raw layout 'i16:65536': channels must be 1 to 4096"
raw_bad i16:18446744073709551617 "bad raw layout .i16:18446744073709551617.: channels must be 1 to 4096"
raw_bad i16 "bad raw layout 'i16': no channel count"
raw_bad '' "empty raw layout"
run "--raw i16:6:be reads" 0 info --raw i16:6:be -r 100 "$SAMPLES/imu-raw.bin"
cp "$SAMPLES/imu-raw.bin" "$T/imu-raw.bin"
printf '[input]\nfiles = imu-raw.bin\nraw = i16:0\nrate = 100\n[allan]\n' \
	>"$T/raw.scene.ini"
bad "scene raw = i16:0" 2 'raw.scene.ini: line 3: raw: bad raw layout .i16:0.' \
	run --dry-run "$T/raw.scene.ini"

# ---- 9. a time column that is not increasing is named as such: info
# warns (exit 0), allan and psd refuse (exit 1) unless --rate is given
# (then a warning); a swapped pair is not "2 gaps", a repeated stamp not
# a missing sample
time_case() { # FILE PROBLEM
	f="$CORPUS/text/$1.csv"
	run "info $1" 0 info "$f"
	has "info $1: warning" "$T/err" "warning: .*$1.csv: time column 't' $2"
	lacks "info $1: no gaps claimed" "$T/out" 'missing|no time column'
	for cmd in allan psd; do
		bad "$cmd $1" 1 "$cmd: .*$1.csv: time column 't' $2.*give --rate" $cmd "$f"
		bad_in "$cmd $1 (stdin)" 1 "$cmd: \(stdin\): time column 't' $2" "$f" $cmd -
	done
	[ "$1" = time-one-row ] && return # too short for allan anyway
	run "allan -r 100 $1" 0 allan -r 100 "$f"
	has "allan -r 100 $1: warning" "$T/err" "time column 't' $2.*: the samples are taken as evenly spaced at the given rate"
}
time_case time-decreasing 'decreases in every row'
time_case time-constant 'is constant \(every row has the same stamp\)'
time_case time-one-row 'has one row'
time_case time-swapped 'has rows 3 and 4 in reverse order'
time_case time-repeated 'repeats the stamp of row 3 at row 4'
run "info swapped: rate from the ordered intervals" 0 info --format json "$CORPUS/text/time-swapped.csv"
json_check "info swapped: 100 Hz, no gaps" "$T/out" '(.channels[0].rate_hz - 100 | fabs) < 1e-9 and (.gaps | length) == 0'

# ---- found by fuzzing: 2555 raw channels on a pipe allocated 64 Ki rows of
# each (1.3 GB) before reading a byte; now the arrays start small and grow
head -c 81760 /dev/zero >"$T/zeros.bin"
if (ulimit -v 400000 && ss --version) >/dev/null 2>&1; then
	(ulimit -v 400000 && cat "$T/zeros.bin" |
		ss info --raw f64:2555 -r 1 - >"$T/out" 2>"$T/err")
	if [ $? -eq 0 ] && grep -q 'rows: *4$' "$T/out"; then
		ok "2555 raw channels from a pipe in 400 MB of address space"
	else
		not_ok "2555 raw channels from a pipe in 400 MB of address space"
		diag "$T/err"
	fi
else
	skip "2555 raw channels from a pipe" "no address-space limit under this build"
fi

# ---- found by make fuzz (issue 13, item 13): two columns named by the same
# number ("1") were looked up as column 1 (an index out of range); units
# nested in thousands of parentheses overflowed the parser's stack
printf 't,0,1,1\n0,1,2,3\n1,2,3,4\n' >"$T/numnames.csv"
bad "columns named by one number" 1 "columns 3 and 4 are both named '1'" info "$T/numnames.csv"
bad "the fuzzer's input" 1 "columns 2 and 4 are both named '0'" info "$CORPUS/text/numeric-names-twice.csv"
printf 'ax [%s g]\n1\n2\n' "$(head -c 5000 /dev/zero | tr '\0' '(')" >"$T/paren.csv"
bad "units nested 5000 deep" 1 "parentheses nested deeper than 32" info -r 1 "$T/paren.csv"

# ---- 10. inputs once accepted silently
# duplicate column names: the channels could not be told apart
DUP="$CORPUS/text/duplicate-columns.csv"
bad "columns named alike" 1 "columns 2, 3 and 4 are all named 'gx': rename them" info "$DUP"
bad "-c naming several columns" 1 "'gx' names columns 2, 3 and 4: select one by its number" info -c gx "$DUP"
bad "allan on columns named alike" 1 "all named 'gx'" allan "$DUP"
run "-c 3 picks one of them" 0 info --format json -c 3 "$DUP"
json_check "-c 3: column 3's values" "$T/out" '.channels | length == 1 and .[0].mean == 2'
# the same capture twice: two power cycles that agree to 1e-15, or a pipe
# read twice; every multi-file command and scenes refuse it (exit 2)
TH="$SAMPLES/accel-thermal.csv"
bad "tempbias, one file twice" 2 "inputs 1 and 2 .* are the same file: give each capture once" \
	tempbias "$TH" "$TH"
ln -s "$TH" "$T/link.csv"
bad "tempbias, a file and a link to it" 2 "are the same file" tempbias "$TH" "$T/link.csv"
bad "tempbias - - from a pipe" 2 "standard input \('-'\) is given twice" tempbias - - <"$TH"
cat "$SAMPLES/vibration.csv" | ss info - - >"$T/out" 2>"$T/err"
[ $? -eq 2 ] && ok "info - - from a pipe (exit 2)" || not_ok "info - - from a pipe"
has "info - - from a pipe: message" "$T/err" "standard input \('-'\) is given twice \(inputs 1 and 2\)"
bad "info FILE - with FILE on stdin" 2 "inputs 1 and 2 .* are the same file" \
	info "$SAMPLES/vibration.csv" - <"$SAMPLES/vibration.csv"
bad "report, one file twice" 2 "are the same file" report -o "$T/rep" "$TH" "$TH"
cp "$TH" "$T/th.csv"
printf '[input]\nfiles = th.csv, ./th.csv\n[tempbias]\n' >"$T/twice.scene.ini"
bad "scene naming one file twice" 2 "are the same file" run --dry-run "$T/twice.scene.ini"
run "tempbias, two different files" 0 tempbias "$TH" "$T/th.csv"
lacks "different paths, different files: no refusal" "$T/err" "same file"
# a last data line without a newline (cut short?): read, with a warning
CUT="$CORPUS/text/last-line-cut.csv"
run "last line without newline" 0 info -r 10 "$CUT"
has "last line: warning" "$T/err" "warning: .*last-line-cut.csv: the last line \(row 3\) has no newline: was the capture cut short\?"
run_in "last line without newline, stdin" 0 "$CUT" psd -r 10 -
has "last line, stdin: warning" "$T/err" "\(stdin\): the last line \(row 3\) has no newline"
run "a complete last line" 0 info -r 10 "$SAMPLES/vibration.csv"
lacks "complete: no warning" "$T/err" "no newline"

# ---- 8. samples at the ends of the double range: the right answer, or
# exit 1 naming the range -- never 0, nan or inf at exit 0.  Oracle: the
# same record scaled into the ordinary range by sensorscope itself, the
# results scaled back (relative 1e-9: the decimal scaling rounds).
# gen FILE FACTOR SPIKE: 2000 rows of a fixed pseudo-random walk-free
# sequence times FACTOR, row 1000 replaced by SPIKE (0: none)
gen() {
	awk -v f="$2" -v s="$3" 'BEGIN {
		print "gx [deg/s]"; x = 12345
		for (i = 0; i < 2000; i++) {
			x = (x * 1103515245 + 12345) % 2147483648
			v = (x / 2147483648 - 0.5) * 2.385 * f
			if (i == 1000 && s != 0) v = s
			printf "%.17g\n", v
		}
	}' >"$1"
}
# num FILE JQ: one number from a JSON file
num() { jq -r "$2" "$1"; }
# close A B: |A/B - 1| <= 1e-9
close() { awk -v a="$1" -v b="$2" 'BEGIN { d = a / b - 1; exit !(d <= 1e-9 && d >= -1e-9) }'; }
if command -v jq >/dev/null 2>&1; then
	for case in "308 1e308 1e-300" "200 1e200 1e-200" "160 1e160 1e-150" \
		"tiny 0 1e300"; do
		set -- $case
		if [ "$1" = tiny ]; then
			gen "$T/x.csv" 1e-300 0
			gen "$T/ref.csv" 1 0
		else
			gen "$T/x.csv" 1 "$2"
			gen "$T/ref.csv" "$3" "$(awk -v a="$2" -v b="$3" 'BEGIN { printf "%.17g", a * b }')"
		fi
		sc=$(awk -v s="$3" 'BEGIN { printf "%.17g", 1 / s }')
		run "allan, spike $1" 0 allan -r 100 --taus octave --dev-unit deg/s --format json --no-fit "$T/x.csv"
		cp "$T/out" "$T/a.json"
		ss allan -r 100 --taus octave --dev-unit deg/s --format json --no-fit "$T/ref.csv" >"$T/b.json"
		a=$(num "$T/a.json" '.channels[0].points[2].dev')
		b=$(num "$T/b.json" '.channels[0].points[2].dev')
		if close "$a" "$(awk -v b="$b" -v s="$sc" 'BEGIN { printf "%.17g", b * s }')"; then
			ok "allan, spike $1: oadev(4 tau0) $a = the scaled record's"
		else
			not_ok "allan, spike $1: oadev $a, scaled record gives $b x $sc"
		fi
		run "info, spike $1" 0 info --format json "$T/x.csv"
		cp "$T/out" "$T/a.json"
		ss info --format json "$T/ref.csv" >"$T/b.json"
		a=$(num "$T/a.json" '.channels[0].sd')
		b=$(num "$T/b.json" '.channels[0].sd')
		if close "$a" "$(awk -v b="$b" -v s="$sc" 'BEGIN { printf "%.17g", b * s }')"; then
			ok "info, spike $1: sd $a = the scaled record's"
		else
			not_ok "info, spike $1: sd $a, scaled record gives $b x $sc"
		fi
	done
	# the deviations of 1e308 deg/s in deg/h (the default display) and
	# the noise terms do not fit a double: exit 1 saying so
	gen "$T/x.csv" 1 1e308
	bad "allan, 1e308 in deg/h" 1 "deviations up to .* exceed the double range in deg/h; give --dev-unit" \
		allan -r 100 "$T/x.csv"
	bad "allan, 1e308 noise terms" 1 "term .* exceeds the double range in .*; give --no-fit" \
		allan -r 100 --dev-unit rad/s "$T/x.csv"
	# spectra: 1e308 (1e616 per Hz) and 1e160 refused; 1e150 right
	bad "psd, spike 1e308" 1 "the spectrum leaves the double range" psd -r 100 "$T/x.csv"
	gen "$T/x.csv" 1 1e160
	bad "psd, spike 1e160" 1 "the spectrum leaves the double range" psd -r 100 "$T/x.csv"
	gen "$T/x.csv" 1 1e150
	gen "$T/ref.csv" 1e-150 1
	run "psd, spike 1e150" 0 psd -r 100 --format json "$T/x.csv"
	cp "$T/out" "$T/a.json"
	ss psd -r 100 --format json "$T/ref.csv" >"$T/b.json"
	a=$(num "$T/a.json" '.channels[0].rms')
	b=$(num "$T/b.json" '.channels[0].rms')
	if close "$a" "$(awk -v b="$b" 'BEGIN { printf "%.17g", b * 1e150 }')"; then
		ok "psd, spike 1e150: rms $a = the scaled record's"
	else
		not_ok "psd, spike 1e150: rms $a, scaled record gives $b x 1e150"
	fi
	# N(0, 1e-300): a spectrum of 1e-600 per Hz is refused, not "rms 0"
	gen "$T/x.csv" 1e-300 0
	bad "psd, N(0, 1e-300)" 1 "the spectrum leaves the double range" psd -r 100 "$T/x.csv"
	# rates at the ends: no frequency step, or a density of 1e-308
	gen "$T/x.csv" 1 0
	bad "psd -r 4.9e-324" 1 "at 4.94066e-324 Hz the spectrum leaves the double range" \
		psd -r 4.9e-324 "$T/x.csv"
	bad "psd -r 1e308" 1 "at 1e\+308 Hz the spectrum leaves the double range" \
		psd -r 1e308 "$T/x.csv"
	lacks "psd -r 1e308: no 'constant input'" "$T/err" "constant"
	bad "allan -r 4.9e-324" 1 "puts taus outside 2\^-200 .. 2\^200 s" allan -r 4.9e-324 "$T/x.csv"
	# a value finite in g and infinite in m/s^2
	printf 'ax [g]\n1\n1e308\n' >"$T/g.csv"
	bad "1e308 g" 1 "row 2: the value in g exceeds the double range in SI units" info -r 1 "$T/g.csv"
	# random bytes read as f64: read, and every command exits 0 with
	# finite numbers or 1 with one line
	for cmd in info allan psd; do
		ss $cmd --raw f64:3 -r 100 "$DATA/random-f64.bin" >"$T/out" 2>"$T/err"
		rc=$?
		# (the input's name left out: its directory may spell "inf")
		if [ $rc -eq 0 ] &&
		   ! sed "s|$DATA/random-f64.bin||g" "$T/out" | grep -qiE 'nan|inf'; then
			ok "$cmd on random f64 bytes: exit 0, finite numbers"
		elif [ $rc -eq 1 ] && [ "$(wc -l <"$T/err")" -eq 1 ]; then
			ok "$cmd on random f64 bytes: exit 1, one line"
		else
			not_ok "$cmd on random f64 bytes (exit $rc)"
			diag "$T/err"
		fi
	done
	bad "vibration on random f64 bytes" 1 "lies outside 2\^-120 .. 2\^120" \
		vibration --raw f64:3 -u m/s^2 -r 1000 "$DATA/random-f64.bin"
	bad "budget beyond the double range" 1 "exceeds the double range: check the sources" \
		budget --gyro-bias 1e305rad/s --accel-bias 1 --arw "1 rad/sqrt(s)" --vrw "1 m/s/sqrt(s)" --time 1000
else
	skip "extreme values" "jq not installed"
fi

done_testing
