#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Every example of the documentation runs as written: the shell blocks of
# the README's tour (and in make check-long those of the man page's
# EXAMPLES too) are run, in order, in an
# empty scratch folder where "samples" links to the bundled samples, with the
# built sensorscope first on PATH.  Each block must exit 0 and leave nothing
# in the source tree: the listing of samples/ (names, sizes, times) is the
# same before and after, and no example names a path outside the scratch
# folder (in distcheck the source tree is read-only, so a write there
# fails the block too).  Blocks that
# need hardware (/dev/spidev) are skipped, with the reason.
. "$(dirname "$0")/lib.sh"

bindir=$(cd "$(dirname "$SSCOPE")" && pwd)
man="$top_srcdir/src/sensorscope.1"
readme="$top_srcdir/README.md"

# blocks: one file per example block, in order, named NN-SOURCE
mkdir "$T/blocks"
# the man page: .EX/.EE blocks after ".SH EXAMPLES", groff escapes undone
awk -v d="$T/blocks" '
	/^\.SH / { ex = ($0 == ".SH EXAMPLES") }
	ex && /^\.EX/ { n++; f = sprintf("%s/%02d-man", d, n); inblk = 1; next }
	inblk && /^\.EE/ { inblk = 0; close(f); next }
	inblk { gsub(/\\-/, "-"); gsub(/\\e/, "\\"); gsub(/\\\(en/, "-"); print > f }
' "$man"
# the README: ```sh blocks between "## Tour" and the next "## " heading
awk -v d="$T/blocks" '
	/^## / { tour = ($0 ~ /^## Tour/) }
	tour && /^```sh/ { n++; f = sprintf("%s/%02d-readme", d, 50 + n); inblk = 1; next }
	inblk && /^```/ { inblk = 0; close(f); next }
	inblk { print > f }
' "$readme"

nman=$(ls "$T/blocks" | grep -c -- '-man$')
nreadme=$(ls "$T/blocks" | grep -c -- '-readme$')
if [ "$nman" -ge 15 ]; then ok "man EXAMPLES has $nman blocks"; else not_ok "man EXAMPLES has $nman blocks"; fi
if [ "$nreadme" -ge 1 ]; then ok "README tour has $nreadme blocks"; else not_ok "README tour has $nreadme blocks"; fi

# the examples' own set-up line, run from the top of the source tree
setup=$(sed -n '1p' "$T/blocks/01-man")
case $setup in
*mktemp*"ln -s"*samples*) ok "man EXAMPLES starts with the scratch set-up" ;;
*) not_ok "man EXAMPLES starts with the scratch set-up: $setup" ;;
esac

# every command of --help has its section under COMMANDS and an example
ss --help | sed -n 's/^  \([a-z][a-z-]*\)  .*/\1/p' >"$T/cmds"
awk '/^\.SH /{c = ($0 == ".SH COMMANDS")} c && /^\.SS /{print $2}' "$man" >"$T/man-cmds"
cat "$T"/blocks/*-man >"$T/all-examples"
if [ -s "$T/cmds" ]; then ok "--help lists the commands"; else not_ok "--help lists the commands"; fi
while read -r c; do
	if grep -qx "$c" "$T/man-cmds"; then ok "COMMANDS has '$c'"; else not_ok "COMMANDS has '$c'"; fi
	has "EXAMPLES runs '$c'" "$T/all-examples" "^sensorscope $c "
done <"$T/cmds"

# the manual formats without a groff warning (when groff is installed)
if command -v groff >/dev/null 2>&1; then
	groff -man -Tutf8 -ww -z "$man" >"$T/groff" 2>&1
	if [ ! -s "$T/groff" ]; then
		ok "groff formats the manual without warnings"
	else
		not_ok "groff formats the manual without warnings"
		diag "$T/groff"
	fi
else
	skip "groff formats the manual without warnings" "no groff"
fi

# the README's install command installs what CI installs
pk() { tr ' \t\\' '\n\n\n' | sed -n '/^install$/,$p' | grep -v '^-\|^$\|^install$\|^&&$\|^||$\|status=1' | sed '/^&&/q' | grep -v '^&&' | sort; }
sed -n '/^```sh/{n;p;q}' "$readme" | sed 's/ && autoreconf.*//' | pk >"$T/pk-readme"
sed -n '/apt-get install/,/|| status/p' "$top_srcdir/.ci/run" | pk >"$T/pk-ci"
if [ -s "$T/pk-ci" ] && cmp -s "$T/pk-readme" "$T/pk-ci"; then
	ok "README's first command installs the packages .ci/run installs"
else
	not_ok "README's first command installs the packages .ci/run installs"
	diff "$T/pk-readme" "$T/pk-ci" | diag /dev/stdin
fi

# examples reach the source tree only through the samples link: no
# absolute path (devices aside) and no way up out of the scratch folder
cat "$T"/blocks/* | grep -n '\.\./\|[ =]/[a-z]' | grep -v ' /dev/' >"$T/paths"
if [ ! -s "$T/paths" ]; then
	ok "examples name no path outside the scratch folder"
else
	not_ok "examples name no path outside the scratch folder"
	diag "$T/paths"
fi
snapshot() { (cd "$top_srcdir" && ls -lAR --time-style=full-iso samples); }
snapshot >"$T/before"

PATH="$bindir:$PATH"
export PATH
# no progress bars or terminal checks: the examples are not on a terminal
work=$(cd "$top_srcdir" && TMPDIR="$T" sh -c "$setup"' && pwd')
if [ -n "$work" ] && [ -L "$work/samples" ] && [ -z "$(ls -A "$work" | grep -v '^samples$')" ]; then
	ok "set-up gives an empty scratch folder with samples"
else
	not_ok "set-up gives an empty scratch folder with samples ($work)"
	done_testing
	exit 0
fi

# the README's tour starts with the same set-up
rsetup=$(ls "$T/blocks" | grep -- '-readme$' | head -n 1)
if [ -n "$rsetup" ] && [ "$(cat "$T/blocks/$rsetup")" = "$setup" ]; then
	ok "README tour starts with the same set-up"
else
	not_ok "README tour starts with the same set-up"
fi

# the README's tour in make check; the manual's examples too in make
# check-long
for b in "$T"/blocks/*; do
	name=$(basename "$b")
	[ "$name" = 01-man ] || [ "$name" = "$rsetup" ] && continue
	if ! long_tier && [ "${name#*-}" = man ]; then
		skip "$name: $(grep -m 1 sensorscope "$b" | cut -c1-70)" "$LONG_ONLY"
		continue
	fi
	first=$(grep -m 1 sensorscope "$b" | cut -c1-70)
	if grep -q '/dev/spidev' "$b"; then
		skip "$name: $first" "needs an SPI device"
		continue
	fi
	if (cd "$work" && bash -e -o pipefail "$b") >"$T/out" 2>"$T/err"; then
		ok "$name runs: $first"
	else
		not_ok "$name runs: $first"
		diag "$T/err"
	fi
done

snapshot >"$T/after"
if cmp -s "$T/before" "$T/after"; then
	ok "the examples leave the source tree as it was"
else
	not_ok "the examples leave the source tree as it was"
	diff "$T/before" "$T/after" | diag /dev/stdin
fi
done_testing
