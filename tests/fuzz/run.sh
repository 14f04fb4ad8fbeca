#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make fuzz: run every libFuzzer harness for SECONDS, seeded from
# tests/fuzz/corpus/NAME; new inputs and crash artifacts go to
# BUILDDIR/fuzz-out/NAME/.  PARALLEL harnesses run at once (default 1; the
# libFuzzer processes are independent).  Prints each harness's executions
# and the total; exits 1 when any harness found a crash, a hang (-timeout)
# or a sanitizer report, naming the artifact to add to the corpus after
# the fix.
# Usage: run.sh BUILDDIR SRCDIR SECONDS [PARALLEL [NAME...]]
set -u
build=$1 src=$2 secs=$3
par=${4:-1}
[ $# -ge 4 ] && shift 4 || shift 3
names=${*:-text raw mat spec scene json tilt inl rosbag2}
total=0 status=0 start=$(date +%s)

# The longest input each surface needs, in bytes (libFuzzer's cost per
# input grows with its length, and mutations of a shorter input are more
# likely to hit a field that matters): text captures and the containers
# recognised by their leading bytes 16 KiB (past the 4 KiB comment and
# header cases of the corpus); capture harnesses analyse at most 4096
# samples; INI, tilt tables and INL profiles 4 KiB (more than 32 levels of
# parentheses, every line kind); scenes and JSON 8 KiB (past the 4 KB value
# an error message cuts); rosbag2 folders 24 KiB (metadata and a .db3 of
# 512-byte pages).
max_len() {
	case $1 in
	text) echo 16384 ;;
	rosbag2) echo 24576 ;;
	scene | json) echo 8192 ;;
	*) echo 4096 ;;
	esac
}

one() { # NAME: run one harness, its log in fuzz-out/NAME/log
	h="$build/tests/fuzz/fuzz-$1"
	out="$build/fuzz-out/$1"
	mkdir -p "$out/corpus" "$out/artifacts"
	"$h" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
		-max_len="$(max_len "$1")" -close_fd_mask=3 -print_final_stats=1 \
		-artifact_prefix="$out/artifacts/" \
		"$out/corpus" "$src/tests/fuzz/corpus/$1" >"$out/log" 2>&1
	echo $? >"$out/rc"
}

running=0
for name in $names; do
	one "$name" &
	running=$((running + 1))
	if [ "$running" -ge "$par" ]; then
		wait
		running=0
	fi
done
wait
for name in $names; do
	out="$build/fuzz-out/$name"
	rc=$(cat "$out/rc" 2>/dev/null || echo 1)
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
