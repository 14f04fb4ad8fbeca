#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Soak test of acquire: the simulator paced in real time (default 10 kHz,
# six channels, a CSV capture) for SOAK_DURATION seconds.  While it runs,
# the resident memory of the process (VmRSS in /proc/PID/status) and the
# capture's size are sampled every SOAK_EVERY seconds and printed as TAP
# comments.  Passes when every sample is in the capture (count exact, no
# drop, no gap, read back by info) and the memory stays flat: after the
# first sample taken once the capture has bytes (its buffers exist), VmRSS
# never rises more than SOAK_RSS_SLACK_KB above it.
#
# Like a real recording, it needs its share of the CPU: about 7 % of a core
# at 10 kHz, but a paced source outruns a writer that gets less (a nice'd
# run on an overloaded machine), and the drops are counted and marked.
# make check runs it for 3 s (a larger ring, so that a busy machine cannot
# make a paced writer fall behind); make soak-acquire runs it for an hour:
#   make soak-acquire SOAK_DURATION=3600 [SOAK_RATE=10000] [SOAK_EVERY=60]
# Environment: SOAK_DURATION (s, default 3), SOAK_RATE (Hz, 10000),
# SOAK_EVERY (s, 1), SOAK_RING (samples, acquire's default when empty),
# SOAK_RSS_SLACK_KB (1024), SOAK_FORMAT (csv|f32|f64), TMPDIR.
. "$(dirname "$0")/lib.sh"

dur=${SOAK_DURATION:-3}
rate=${SOAK_RATE:-10000}
every=${SOAK_EVERY:-1}
ring=${SOAK_RING-131072}
slack=${SOAK_RSS_SLACK_KB:-1024}
fmt=${SOAK_FORMAT:-csv}
if [ -n "$SSCOPE_RUN" ]; then
	# under valgrind: a tenth of the rate, and no memory verdict
	rate=$((rate / 10))
	slack=
fi
n=$((rate * dur))
ringopt=
[ -n "$ring" ] && ringopt="--ring $ring"

echo "# soak: simulator at $rate Hz paced in real time, $dur s, $n samples, $fmt, ring ${ring:-default}"
# shellcheck disable=SC2086
$SSCOPE_RUN "$SSCOPE" acquire --source "sim:rate=$rate" --count "$n" \
	$ringopt --capture-format "$fmt" --format json -o "$T/soak.$fmt" \
	>"$T/out" 2>"$T/err" &
pid=$!
rss() { sed -n 's/^VmRSS:[[:space:]]*\([0-9]*\) kB/\1/p' "/proc/$pid/status" 2>/dev/null; }
t=0 first= max=0 last=
echo "# t [s]  VmRSS [kB]  capture [bytes]"
while kill -0 "$pid" 2>/dev/null; do
	sleep "$every"
	t=$((t + every))
	r=$(rss)
	[ -n "$r" ] || break
	size=$(stat -c %s "$T/soak.$fmt.partial" 2>/dev/null || echo 0)
	echo "# $t  $r  $size"
	# the reference is the first sample once the recording writes: on a
	# busy machine the first second can end before its buffers exist
	if [ -z "$first" ]; then
		[ "$size" -gt 0 ] && first=$r
	elif [ "$r" -gt "$max" ]; then
		max=$r
	fi
	last=$r
done
wait "$pid"
got=$?
if [ $got -eq 0 ]; then ok "soak: exit 0"; else not_ok "soak: exit $got"; diag "$T/err"; fi
json_check "soak: $n samples, no drop, no gap" "$T/out" \
	".samples == $n and .drops.total == 0 and .missing == 0 and .gaps == 0 and .unsaved == 0"
lacks "soak: no warning" "$T/err" 'warning'
if command -v jq >/dev/null 2>&1; then
	echo "# pacing: $(jq -r '"late by at most \(.pacing_late_max_s) s; writer CPU \(.writer_cpu_s) s, reader CPU \(.reader_cpu_s) s in \(.wall_s) s"' "$T/out")"
fi
if [ -z "$slack" ]; then
	skip "soak: memory flat" "under $SSCOPE_RUN"
elif [ -z "$first" ] || [ "$max" -eq 0 ]; then
	skip "soak: memory flat" "too short to sample the memory twice"
elif [ $((max - first)) -le "$slack" ]; then
	ok "soak: memory flat (VmRSS $first kB after ${every} s, at most $max kB, last $last kB)"
else
	not_ok "soak: memory grew from $first kB to $max kB"
fi
run "soak: info reads the capture" 0 info --format json "$T/soak.$fmt"
json_check "soak: info finds every sample at $rate Hz, no gap" "$T/out" \
	".rows == $n and (.rate_hz - $rate | fabs) < 1e-3 * $rate and (.gaps | length) == 0"
rm -f "$T/soak.$fmt"
done_testing
