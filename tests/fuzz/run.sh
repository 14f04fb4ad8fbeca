#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make fuzz: run every libFuzzer harness for SECONDS, seeded from
# tests/fuzz/corpus/NAME; new inputs and crash artifacts go to
# BUILDDIR/fuzz-out/NAME/.  Prints each harness's executions and the total;
# exits 1 when any harness found a crash, a hang (-timeout) or a sanitizer
# report, naming the artifact to add to the corpus after the fix.
# Usage: run.sh BUILDDIR SRCDIR SECONDS [NAME...]
set -u
build=$1 src=$2 secs=$3
shift 3
names=${*:-text raw mat spec scene json tilt inl}
total=0 status=0 start=$(date +%s)
for name in $names; do
	h="$build/tests/fuzz/fuzz-$name"
	out="$build/fuzz-out/$name"
	mkdir -p "$out/corpus" "$out/artifacts"
	"$h" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
		-max_len=65536 -close_fd_mask=3 -print_final_stats=1 \
		-artifact_prefix="$out/artifacts/" \
		"$out/corpus" "$src/tests/fuzz/corpus/$name" >"$out/log" 2>&1
	rc=$?
	execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$out/log" | tail -n 1)
	execs=${execs:-0}
	total=$((total + execs))
	if [ "$rc" -eq 0 ]; then
		echo "fuzz-$name: $execs executions in ${secs} s, no crash"
	else
		status=1
		echo "fuzz-$name: FAILED after $execs executions (exit $rc); log $out/log:"
		grep -E 'ERROR|SUMMARY|Test unit written' "$out/log" | head -n 10
	fi
done
echo "fuzz: $total executions in $(($(date +%s) - start)) s"
exit $status
