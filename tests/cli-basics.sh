#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# The command line itself: help, version, unknown commands and options,
# exit codes, and that the man page and README document every command.
. "$(dirname "$0")/lib.sh"

run "--help" 0 --help
has "--help lists info" "$T/out" '^  info '
run "--version" 0 --version
has "--version names the package" "$T/out" '^sensorscope [0-9]+\.[0-9]+'
run "no command" 2
run "unknown command" 2 frobnicate
one_line_error "unknown command"
has "unknown command message" "$T/err" "^sensorscope: unknown command 'frobnicate'"
run "info --help" 0 info --help
has "info --help shows the shared options" "$T/out" '--column'
has "info --help shows exit codes" "$T/out" 'Exit status'
run "unknown option" 2 info --bogus "$SAMPLES/gyro-static.csv"
one_line_error "unknown option"
run "bad --format" 2 info --format xml "$SAMPLES/gyro-static.csv"
one_line_error "bad --format"
run "bad --rate" 2 info --rate fast "$SAMPLES/gyro-static.csv"
one_line_error "bad --rate"
run "negative --rate" 2 info --rate -5 "$SAMPLES/gyro-static.csv"
run "missing file operand" 2 info
one_line_error "missing file operand"
run "--plot not png" 2 info --plot x.jpg "$SAMPLES/gyro-static.csv"

# OpenMP's threads wait passively (GOMP_SPINCOUNT 0) without the command
# running itself twice: the policy reaches libgomp before it starts
# (libgomp prints its settings once per start with OMP_DISPLAY_ENV)
omp_env() { # DESC WANT_STARTS WANT_SPIN ENV...
	desc=$1 starts=$2 spin=$3
	shift 3
	env "$@" OMP_DISPLAY_ENV=verbose "$SSCOPE" allan --help >/dev/null 2>"$T/omp"
	n=$(grep -c 'OPENMP DISPLAY ENVIRONMENT BEGIN' "$T/omp")
	last=$(sed -n "s/^ *GOMP_SPINCOUNT = '\([0-9]*\)'.*/\1/p" "$T/omp" | tail -n 1)
	if [ "$n" = "$starts" ] && { [ "$last" = "$spin" ] || { [ "$spin" = "+" ] && [ "${last:-0}" -gt 0 ]; }; }; then
		ok "$desc"
	else
		not_ok "$desc (started $n times, spin count '$last')"
		diag "$T/omp"
	fi
}
if "$SSCOPE" --version >/dev/null && OMP_DISPLAY_ENV=true "$SSCOPE" --version 2>&1 | grep -q 'OPENMP DISPLAY'; then
	omp_env "OpenMP waits passively, one start" 1 0 _=/bin/sh
	omp_env "OpenMP waits passively without a shell's _" 1 0 -u _ HOME=/nowhere
	omp_env "an empty environment: started again with the policy" 2 0 -i
	omp_env "the user's OMP_WAIT_POLICY is kept" 1 + OMP_WAIT_POLICY=active
else
	skip "OpenMP wait policy" "built without OpenMP"
fi

# every command of --help is in the man page and the README
ss --help | sed -n 's/^  \([a-z][a-z-]*\)  .*/\1/p' >"$T/cmds"
if [ -s "$T/cmds" ]; then ok "commands listed"; else not_ok "commands listed"; fi
while read -r c; do
	has "man page documents '$c'" "$top_srcdir/src/sensorscope.1" "^\\.SS $c\\b|^\\.B $c\\b|^\\.SH.*$c"
	has "README documents '$c'" "$top_srcdir/README.md" "sensorscope $c\\b"
done <"$T/cmds"
done_testing
