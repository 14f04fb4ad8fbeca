#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# make bench: datasheet verdicts on simulated white-noise gyros at 0.8x,
# 1.0x and 1.25x a datasheet's noise (RECORDS records each, default 200):
# the fraction of records whose verdict is "within spec", "inconclusive"
# and "out of spec" respectively (target >= 0.95 each), for two lines: the
# noise density (N from the noise fit, 99 % interval) and the GJB 10 s bias
# stability (1 sigma of 10 s means, chi-squared 99 % interval).
#
# The record: 1 h at 10 Hz.  With white noise alone the 10 s means are
# independent, so the GJB figure has 359 degrees of freedom: its relative
# sd is 1/sqrt(2 * 359) = 3.7 % and the 99 % interval spans about
# [0.91, 1.11] times the estimate; at 0.8x the estimate stays below
# 0.8 * (1 + 1.645 * 0.037) = 0.85 in 95 % of records and its upper bound
# below 0.85 * 1.11 = 0.94 < 1, at 1.25x the lower bound above
# 1.25 * 0.94 * 0.91 = 1.07 > 1.  N is resolved far more tightly
# (36000 samples).  At 1.0x the 99 % interval holds the limit in 99 % of
# records, so at most about 1 % are pass or fail.
set -eu
top_builddir=${top_builddir:-$(cd "$(dirname "$0")/.." && pwd)}
S="$top_builddir/src/sensorscope"
if ! command -v jq >/dev/null 2>&1; then
	echo "bench-datasheet: skipped (no jq)"
	exit 0
fi
records=${RECORDS:-200}
work=$(mktemp -d "${TMPDIR:-/tmp}/sscope-ds.XXXXXX")
trap 'rm -rf "$work"' EXIT
# the datasheet: 0.014 deg/s/sqrt(Hz) (BMI088's gyro) and the GJB 10 s
# figure white noise of that density has: 0.014 / sqrt(10) deg/s =
# 0.014 / 3.16228 * 3600 = 15.9374 deg/h
cat >"$work/ds.ini" <<'INI'
[datasheet]
name = bench gyro
[gyro]
noise_density = 0.014 deg/s/sqrt(Hz)
bias_stability_10s = 15.937402 deg/h
INI
printf '| noise | line | within spec | inconclusive | out of spec | expected | fraction expected | s per record |\n'
printf '|---|---|---|---|---|---|---|---|\n'
status=0
for k in 0.8 1.0 1.25; do
	nd=$(awk "BEGIN { printf \"%.9g\", $k * 0.014 }")
	printf '[sensor]\nnoise_density = %s deg/s/sqrt(Hz)\n' "$nd" >"$work/s.ini"
	: >"$work/v"
	t0=$(date +%s.%N)
	i=1
	while [ "$i" -le "$records" ]; do
		"$S" simulate --sensor "$work/s.ini" --rate 10 --duration 1h \
			--seed "$i" --binary f64 -o "$work/c.bin"
		"$S" datasheet --check "$work/c.bin" "$work/ds.ini" --format json |
			jq -r '.channels[0].checks[] | "\(.key)|\(.verdict)"' >>"$work/v"
		i=$((i + 1))
	done
	t1=$(date +%s.%N)
	case $k in
	0.8) want="within spec" ;;
	1.0) want="inconclusive" ;;
	*) want="out of spec" ;;
	esac
	for line in noise_density bias_stability_10s; do
		w=$(grep -c "^$line|within spec" "$work/v" || true)
		u=$(grep -c "^$line|inconclusive" "$work/v" || true)
		o=$(grep -c "^$line|out of spec" "$work/v" || true)
		got=$(grep -c "^$line|$want" "$work/v" || true)
		frac=$(awk "BEGIN { printf \"%.3f\", $got / $records }")
		per=$(awk "BEGIN { printf \"%.2f\", ($t1 - $t0) / $records }")
		printf '| %sx | %s | %s | %s | %s | %s | %s | %s |\n' "$k" "$line" "$w" "$u" "$o" "$want" "$frac" "$per"
		awk "BEGIN { exit !($got < 0.95 * $records) }" && status=1
	done
done
echo "records per noise level: $records (1 h at 10 Hz, white noise; 99 % guard band)"
exit $status
