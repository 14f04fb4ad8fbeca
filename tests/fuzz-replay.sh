#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Replay the fuzz corpus (tests/fuzz/corpus/NAME: seeds, every input of
# issue 13 and every input a fuzzer found a defect with) through each
# harness: no crash, no hang, and under --enable-sanitizers no report.
. "$(dirname "$0")/lib.sh"

: "${top_builddir:=$top_srcdir}"
for name in text raw mat spec scene json tilt inl rosbag2; do
	h="$top_builddir/tests/fuzz/fuzz-$name"
	dir="$top_srcdir/tests/fuzz/corpus/$name"
	if [ ! -x "$h" ]; then
		not_ok "fuzz-$name: harness not built"
		continue
	fi
	n=$(ls "$dir" | wc -l)
	# files, not the folder: a libFuzzer binary then runs each once
	if $SSCOPE_RUN "$h" "$dir"/* >"$T/out" 2>"$T/err" </dev/null; then
		ok "fuzz-$name: $n inputs replayed"
	else
		not_ok "fuzz-$name: replay failed"
		tail -n 40 "$T/err" | diag
	fi
done
done_testing
