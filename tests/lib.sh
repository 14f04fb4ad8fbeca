# SPDX-License-Identifier: GPL-3.0-or-later
# TAP helpers for shell tests of the real sensorscope binary.
# Environment (set by make check): SSCOPE (the binary), SSCOPE_RUN (a
# prefix such as valgrind, may be empty), top_srcdir, SSCOPE_HAVE_OPENCV.

set -u
: "${top_srcdir:=$(cd "$(dirname "$0")/.." && pwd)}"
: "${SSCOPE:=$top_srcdir/src/sensorscope}"
: "${SSCOPE_RUN:=}"
: "${SSCOPE_HAVE_OPENCV:=0}"
SAMPLES="$top_srcdir/samples"
DATA="$top_srcdir/tests/data"
T=$(mktemp -d "${TMPDIR:-/tmp}/sscope-sh.XXXXXX")
trap 'rm -rf "$T"' EXIT
tap_n=0

ss() { $SSCOPE_RUN "$SSCOPE" "$@"; }

ok() { tap_n=$((tap_n + 1)); echo "ok $tap_n - $*"; }
not_ok() { tap_n=$((tap_n + 1)); echo "not ok $tap_n - $*"; }
skip() { tap_n=$((tap_n + 1)); echo "ok $tap_n - $1 # SKIP $2"; }
diag() { sed 's/^/# /' "$@"; }

# run DESC RC ARGS...: run sensorscope, expect exit code RC; output in
# $T/out and $T/err
run() {
	desc=$1 want=$2
	shift 2
	ss "$@" >"$T/out" 2>"$T/err"
	got=$?
	if [ "$got" -eq "$want" ]; then
		ok "$desc (exit $want)"
	else
		not_ok "$desc (exit $got, wanted $want)"
		diag "$T/err"
	fi
}

# run_in DESC RC INPUT ARGS...: as run, with INPUT on standard input
run_in() {
	desc=$1 want=$2 input=$3
	shift 3
	ss "$@" <"$input" >"$T/out" 2>"$T/err"
	got=$?
	if [ "$got" -eq "$want" ]; then
		ok "$desc (exit $want)"
	else
		not_ok "$desc (exit $got, wanted $want)"
		diag "$T/err"
	fi
}

# has DESC FILE PATTERN: FILE contains the extended regexp PATTERN
has() {
	if grep -Eq -- "$3" "$2"; then
		ok "$1"
	else
		not_ok "$1: '$3' not in $2"
		diag "$2"
	fi
}

# lacks DESC FILE PATTERN
lacks() {
	if grep -Eq -- "$3" "$2"; then
		not_ok "$1: '$3' found in $2"
		diag "$2"
	else
		ok "$1"
	fi
}

# one_line_error DESC: stderr is exactly one "sensorscope: CMD: ..." line
one_line_error() {
	if [ "$(wc -l <"$T/err")" -eq 1 ] && grep -q '^sensorscope: ' "$T/err"; then
		ok "$1: one-line error"
	else
		not_ok "$1: stderr is not one 'sensorscope: ...' line"
		diag "$T/err"
	fi
}

# json_check DESC FILE JQ-EXPR: the jq filter evaluates to true on FILE
json_check() {
	desc=$1 file=$2 expr=$3
	if ! command -v jq >/dev/null 2>&1; then
		skip "$desc" "jq not installed"
		return
	fi
	if jq -e "$expr" "$file" >/dev/null 2>"$T/jqerr"; then
		ok "$desc"
	else
		not_ok "$desc: jq '$expr' is not true"
		diag "$T/jqerr"
		{ head -c 2000 "$file"; echo; } | diag
	fi
}

done_testing() { echo "1..$tap_n"; }

# long_tier: true in make check-long (SSCOPE_TEST_TIER=long, or all: the
# quick and the long parts, as CI runs the release tarball's tests), where the
# parts that take long run (a real browser, every example of the manual);
# make check skips them with a reason
long_tier() { [ "${SSCOPE_TEST_TIER:-}" = long ] || [ "${SSCOPE_TEST_TIER:-}" = all ]; }
LONG_ONLY="in make check-long"
