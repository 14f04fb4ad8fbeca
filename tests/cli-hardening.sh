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

done_testing
