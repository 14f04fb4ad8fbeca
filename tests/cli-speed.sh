#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# What keeps the command fast, and that the fast paths give the numbers of
# the careful ones: the built program is the real binary; commands that
# draw nothing do not load OpenCV (figures open the drawing module);
# OpenMP threads wait passively; a raw float64 record used in place gives
# the same Allan deviations as the copied one (standard input), and raw
# rows in the host's byte order (block converter) the same spectrum as the
# byte-swapped file (row by row); a streamed psd reading ahead reports a
# bad cell at its line; the report's provenance hash, computed
# beside the reading, is the file's.  The speed itself: make bench.
. "$(dirname "$0")/lib.sh"

if head -c 4 "$SSCOPE" | grep -q 'ELF'; then
	ok "the built program is the binary, not a wrapper script"
else
	not_ok "the built program is the binary, not a wrapper script"
fi

if [ -n "$SSCOPE_RUN" ] || [ "$SSCOPE_SANITIZERS" = 1 ]; then
	skip "--help loads no OpenCV" "under ${SSCOPE_RUN:-sanitizers} (their runtime loads the C++ one)"
	skip "OpenMP waits passively" "under ${SSCOPE_RUN:-sanitizers}"
else
	LD_DEBUG=files "$SSCOPE" --help >/dev/null 2>"$T/ld"
	lacks "--help loads no OpenCV, no C++ runtime" "$T/ld" 'opencv|libstdc\+\+|plot-opencv'
	if [ "$SSCOPE_HAVE_OPENCV" = 1 ]; then
		LD_DEBUG=files "$SSCOPE" info --plot "$T/i.png" \
			"$SAMPLES/gyro-static.csv" >/dev/null 2>"$T/ld"
		has "a figure opens the drawing module" "$T/ld" 'plot-opencv\.so'
	fi
	# libgomp prints its settings when loaded: the second run has them
	OMP_DISPLAY_ENV=true "$SSCOPE" psd --nperseg 256 \
		"$SAMPLES/gyro-static.csv" >/dev/null 2>"$T/omp"
	if grep -q 'OPENMP DISPLAY ENVIRONMENT' "$T/omp"; then
		has "OpenMP waits passively" "$T/omp" "OMP_WAIT_POLICY = 'PASSIVE'"
		OMP_WAIT_POLICY=active OMP_DISPLAY_ENV=true "$SSCOPE" psd \
			--nperseg 256 "$SAMPLES/gyro-static.csv" >/dev/null 2>"$T/omp"
		lacks "a policy the user set is kept" "$T/omp" "PASSIVE"
	else
		skip "OpenMP waits passively" "built without OpenMP"
	fi
fi

# 300000 float64 samples, both byte orders (perl is in every Debian)
perl -e '$s = 1; for (1 .. 300000) { $s = ($s * 16807) % 2147483647;
	print pack("d<", $s / 2147483647 + 0.3) }' >"$T/le.f64"
perl -e '$s = 1; for (1 .. 300000) { $s = ($s * 16807) % 2147483647;
	print pack("d>", $s / 2147483647 + 0.3) }' >"$T/be.f64"

run "allan on a raw float64 file (in place)" 0 allan --raw f64:1:le --rate 10 \
	--format json "$T/le.f64"
sed 's/"file":"[^"]*"//' "$T/out" >"$T/a1"
run_in "allan on the same from standard input (copied)" 0 "$T/le.f64" allan \
	--raw f64:1:le --rate 10 --format json -
sed 's/"file":"[^"]*"//' "$T/out" >"$T/a2"
if [ -s "$T/a1" ] && cmp -s "$T/a1" "$T/a2"; then
	ok "in place and copied give the same JSON"
else
	not_ok "in place and copied give the same JSON"
fi
run "allan --no-fit" 0 allan --raw f64:1:le --rate 10 --no-fit --format json "$T/le.f64"
lacks "allan --no-fit: no noise terms" "$T/out" '"noise":\{'

run "psd, host byte order" 0 psd --raw f64:1:le --rate 10 --nperseg 1024 \
	--format json "$T/le.f64"
sed 's/"file":"[^"]*"//' "$T/out" >"$T/p1"
run "psd, swapped byte order" 0 psd --raw f64:1:be --rate 10 --nperseg 1024 \
	--format json "$T/be.f64"
sed 's/"file":"[^"]*"//' "$T/out" >"$T/p2"
if [ -s "$T/p1" ] && cmp -s "$T/p1" "$T/p2"; then
	ok "block converter and row-by-row reader give the same spectrum"
else
	not_ok "block converter and row-by-row reader give the same spectrum"
fi
# a raw float64 file is fed from its mapping: the spectrum of the copied
# record (standard input), and a value the reader refuses, deep in a
# segment or after the last one, reported as the streamed path does
run_in "psd of the same from standard input" 0 "$T/le.f64" psd --raw f64:1:le \
	--rate 10 --nperseg 1024 --format json -
sed 's/"file":"[^"]*"//' "$T/out" >"$T/p3"
if [ -s "$T/p1" ] && cmp -s "$T/p1" "$T/p3"; then
	ok "psd: mapped file and standard input give the same spectrum"
else
	not_ok "psd: mapped file and standard input give the same spectrum"
fi
perl -e '$s = 1; for (1 .. 300000) { $s = ($s * 16807) % 2147483647;
	print pack("d<", $_ == 200001 ? "NaN" : $s / 2147483647 + 0.3) }' >"$T/nan.f64"
run "psd: NaN deep in a mapped raw file" 1 psd --raw f64:1:le --rate 10 \
	--nperseg 1024 "$T/nan.f64"
has "psd: the NaN's row" "$T/err" 'row 200001, column 1 \(ch1\): NaN \(use --allow-nan'
perl -e '$s = 1; for (1 .. 300000) { $s = ($s * 16807) % 2147483647;
	print pack("d<", $_ == 299999 ? "-Inf" : $s / 2147483647 + 0.3) }' >"$T/inf.f64"
run "psd: infinity after the last segment of a mapped raw file" 1 psd \
	--raw f64:1:le --rate 10 --nperseg 1024 "$T/inf.f64"
has "psd: the infinity's row" "$T/err" 'row 299999, column 1 \(ch1\): infinite value'
# allan checks the samples of a file used in place in its own first pass,
# not the reader: the same errors, at the same rows
run "allan: NaN deep in a mapped raw file" 1 allan --raw f64:1:le --rate 10 \
	--taus octave "$T/nan.f64"
has "allan: the NaN's row" "$T/err" 'row 200001, column 1 \(ch1\): NaN \(use --allow-nan'
run "allan: infinity near the end of a mapped raw file" 1 allan \
	--raw f64:1:le --rate 10 --taus octave --no-fit "$T/inf.f64"
has "allan: the infinity's row" "$T/err" 'row 299999, column 1 \(ch1\): infinite value'
run "allan --allow-nan: the NaN is a gap" 0 allan --raw f64:1:le --rate 10 \
	--taus octave --no-fit --allow-nan --format json "$T/nan.f64"
has "allan --allow-nan: one NaN counted" "$T/out" '"nan":1,'
# psd reads the next chunk while it transforms the last: a bad cell three
# chunks in is still reported at its line, and the spectrum of a pipe is
# the file's
awk 'BEGIN { print "t [s],gx [deg/s]"; for (i = 0; i < 200000; i++)
	printf "%.2f,%s\n", i / 100, (i == 150000 ? "oops" : sin(i * 0.37)) }' \
	>"$T/bad.csv"
run "psd: bad cell deep in a streamed CSV" 1 psd "$T/bad.csv"
has "psd: the bad cell's line" "$T/err" "line 150002"
run "psd of a CSV" 0 psd --format json "$SAMPLES/gyro-static.csv"
sed 's/"file":"[^"]*"//' "$T/out" >"$T/s1"
run_in "psd of the same CSV through a pipe" 0 "$SAMPLES/gyro-static.csv" \
	psd --format json -
sed 's/"file":"[^"]*"//' "$T/out" >"$T/s2"
if [ -s "$T/s1" ] && cmp -s "$T/s1" "$T/s2"; then
	ok "psd: file and pipe give the same spectrum"
else
	not_ok "psd: file and pipe give the same spectrum"
fi

# a record used in place and the Allan workspace are never both whole in
# memory: peak RSS at most 1.2 x the file plus the program (GNU time)
if [ -x /usr/bin/time ] && [ -z "$SSCOPE_RUN" ] && [ "$SSCOPE_SANITIZERS" != 1 ]; then
	perl -e '$s = 7; for (1 .. 2000000) { $s = ($s * 16807) % 2147483647;
		print pack("d<", $s / 2147483647) }' >"$T/big.f64"
	/usr/bin/time -f '%M' -o "$T/rss" "$SSCOPE" allan --raw f64:1:le \
		--rate 100 --taus octave --ci none --no-fit "$T/big.f64" >/dev/null
	kb=$(tail -n 1 "$T/rss")
	if [ "$kb" -le $((16000 * 12 / 10 + 10000)) ]; then
		ok "allan in place: peak RSS $kb KiB for a 16 MB record"
	else
		not_ok "allan in place: peak RSS $kb KiB for a 16 MB record"
	fi
	rm -f "$T/big.f64"
else
	skip "allan in place: peak RSS" "no /usr/bin/time, or under ${SSCOPE_RUN:-sanitizers} (shadow memory)"
fi

# the report's provenance hashes (hashed on a thread beside the reading)
run "report of a capture" 0 report -q -o "$T/rep" "$SAMPLES/gyro-static.csv"
if command -v sha256sum >/dev/null 2>&1; then
	h=$(sha256sum "$SAMPLES/gyro-static.csv" | cut -c1-64)
	has "report.html: the capture's SHA-256" "$T/rep/report.html" "$h"
fi
done_testing
