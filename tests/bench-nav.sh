#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: the whole `sensorscope nav` command on one hour of a 6-axis
# capture at 200 Hz (720,000 samples, a walk with 5-s stops every 35 s,
# simulated by tests/bench-zupt --hour as navsim's models give it, written
# as CSV), three runs: wall and CPU seconds, the time per sample, against
# the target of 1 s; and `info` on the same file, the cost of reading it.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
S="$top_builddir/src/sensorscope"
T=$(mktemp -d "${TMPDIR:-/tmp}/sscope-bench.XXXXXX")
trap 'rm -rf "$T"' EXIT
"$top_builddir/tests/bench-zupt" --hour "$T/hour.csv"
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg) (wall times grow with it; CPU times do not)"
now() { date +%s.%N; }
cpu() { awk '{ print ($16 + $17) / 100 }' /proc/$$/stat; }
n=$(($(wc -l <"$T/hour.csv") - 1))
for k in 1 2 3; do
	t0=$(now) c0=$(cpu)
	"$S" nav --heading 17.19 --latitude 45.84 --format json -o "$T/nav.json" "$T/hour.csv" 2>/dev/null
	t1=$(now) c1=$(cpu)
	"$S" info "$T/hour.csv" >/dev/null
	t2=$(now)
	awk -v n="$n" -v t0="$t0" -v t1="$t1" -v t2="$t2" -v c0="$c0" -v c1="$c1" \
	    -v k="$k" 'BEGIN { w = t1 - t0; c = c1 - c0; r = t2 - t1;
		printf "nav, run %d: %d samples of 6 axes: %.3f s wall, %.2f s CPU, %.0f ns per sample (target 1 s: %s); info on the same file %.3f s\n",
		       k, n, w, c, 1e9 * w / n, w <= 1 ? "met" : "NOT met", r }'
done
