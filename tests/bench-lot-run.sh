#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: the whole `sensorscope lot` command on 10, 30 and 100 units
# of 1 h at 100 Hz with 6 axes (simulated gyros, sensorscope binary f64:
# 17.3 MB of samples per unit, 20.2 MB with the time column), one unit's
# record in memory at a time: wall and CPU seconds, the time per unit, and
# the peak resident memory against one unit's data (targets: 100 units in
# 60 s; peak at most 2x one unit's data per worker; lot reads and
# analyses one unit at a time: one worker).  The files are generated here
# and deleted after (about 2 GB for 100 units).
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
top_srcdir=${top_srcdir:-$(cd "$(dirname "$0")/.." && pwd)}
S="$top_builddir/src/sensorscope"
U=${BENCH_LOT_UNITS:-100}
T=$(mktemp -d "${TMPDIR:-/tmp}/sscope-bench.XXXXXX")
trap 'rm -rf "$T"' EXIT
if [ ! -x /usr/bin/time ]; then
	echo "bench-lot-run: /usr/bin/time (Debian package time) is needed for the peak memory: skipped"
	exit 0
fi
i=1
while [ "$i" -le "$U" ]; do
	"$S" simulate -q --sensor "$top_srcdir/samples/gyro-mems-250.ini" --rate 100 \
		--duration 1h --axes 6 --binary f64 --seed "$i" -o "$T/u$(printf %03d "$i").bin"
	i=$((i + 1))
done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg) (wall times grow with it; CPU times do not)"
base=$(/usr/bin/time -f %M "$S" --version 2>&1 >/dev/null | tail -1)
unit_kb=$((360000 * 6 * 8 / 1024))
for n in 10 30 100; do
	[ "$n" -le "$U" ] || continue
	ls "$T"/u*.bin | head -n "$n" >"$T/list"
	/usr/bin/time -f "%e %U %S %M" -o "$T/time" "$S" lot --format json -o "$T/lot.json" \
		$(cat "$T/list") 2>"$T/err" || { cat "$T/err"; exit 1; }
	read -r w us sy kb <"$T/time"
	awk -v n="$n" -v w="$w" -v c="$us + $sy" -v us="$us" -v sy="$sy" -v kb="$kb" \
	    -v base="$base" -v unit="$unit_kb" 'BEGIN { c = us + sy;
		printf "lot of %d units (1 h, 100 Hz, 6 axes): %.2f s wall, %.2f s CPU, %.3f s per unit; peak RSS %.1f MB = %.2fx one unit'"'"'s data (%.2fx above the %.1f MB of an idle process)%s\n",
		       n, w, c, w / n, kb / 1024, kb / unit, (kb - base) / unit, base / 1024,
		       n == 100 ? sprintf("; targets: 60 s %s, 2x %s", w <= 60 ? "met" : "NOT met", (kb - base) / unit <= 2 ? "met" : "NOT met") : "" }'
done
