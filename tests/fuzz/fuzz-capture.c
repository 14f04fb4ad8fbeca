/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Fuzz harness of the capture readers, built three times:
 *   FUZZ_TEXT  delimited text and the sensorscope binary capture (the
 *              format is detected from the bytes, as for a user's file);
 *   FUZZ_RAW   raw binary: the input's first line is the --raw layout
 *              (checked by sscope_reader_raw_layout_check), the rest the data;
 *   FUZZ_MAT   MATLAB 5 MAT-files (an input without the 128-byte header
 *              is given one).
 * Each input is read three ways: from an exact-size memory buffer in
 * chunks of 7 rows (ASan sees any read past its end), as a file through
 * sscope_capture_load (mmap, row counting, time-column analysis), and as
 * a pipe on standard input (the sliding buffer; see below).  What was read is then
 * summarised (statistics, timing) as info does, and its first channel
 * analysed as allan (OADEV, noise fit), psd (Welch) and vibration
 * (kurtosis) do: the sums of squares of any finite samples (issue 13,
 * item 8) under UBSan.
 */
#include "fuzz.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "sensorscope.h"
#include "sscope-allan.h"
#include "sscope-psd.h"
#include "sscope-vib.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	fuzz_quiet();
	return 0;
}

/* The analyses that square sums, on the first channel, serially. */
static void analyse(const struct sscope_capture *cap)
{
	const double *x = cap->channels[0].data;
	const double fs = cap->rate_hz > 0 ? cap->rate_hz : 100;
	struct sscope_allan_opts ao = { .threads = 1 };
	struct sscope_allan_result *ar = NULL;
	struct sscope_psd_opts po;
	struct sscope_psd_spectrum sp = { 0 };
	struct sscope_diag d = { "" };
	double k;

	if (cap->n < 8 || cap->n > 4096)
		return;
	if (sscope_allan_analyze(x, 1, cap->n, fs, SSCOPE_ALLAN_TAUS_OCTAVE, &ao,
				 NULL, &ar, &d) == 0)
		sscope_allan_result_free(ar);
	sscope_psd_opts_init(&po);
	po.nperseg = 16;
	po.noverlap = 8;
	po.skip_nonfinite = true;
	po.threads = 1;
	if (sscope_psd_welch(x, 1, cap->n, fs, &po, &sp) == 0)
		sscope_psd_spectrum_clear(&sp);
	sscope_vib_kurtosis(x, 1, cap->n, &k);
}

static void summarise(const struct sscope_capture *cap)
{
	struct sscope_stats st;

	for (size_t k = 0; k < cap->n_channels; k++)
		sscope_stats_compute(cap->channels[k].data, 1, cap->n, &st);
	if (cap->time_s && cap->n >= 2) {
		double *scratch = malloc((cap->n - 1) * sizeof(double));
		struct sscope_timing tm;
		struct sscope_timing_gap gaps[4];
		size_t ng;

		if (scratch)
			sscope_timing_analyze(cap->time_s, cap->n, 1.5, &tm, gaps,
					      4, &ng, scratch);
		free(scratch);
	}
	if (cap->n_channels)
		analyse(cap);
}

static void load(const char *path, const struct sscope_reader_opts *o)
{
	struct sscope_capture *cap;
	struct sscope_diag d = { "" };

	if (sscope_capture_load(&cap, path, o, &d) == 0) {
		summarise(cap);
		sscope_capture_free(cap);
	}
}

static void chunks(const uint8_t *data, size_t size,
		   const struct sscope_reader_opts *o)
{
	struct sscope_reader *r;
	struct sscope_diag d = { "" };
	double *cols[64], buf[64][7], t[7], temp[7];
	struct sscope_reader_chunk ch = { 7, 0, cols, t, temp };
	size_t n;

	if (ssc_reader_open_mem(&r, data, size, "fuzz", o, &d))
		return;
	n = sscope_reader_n_channels(r);
	for (size_t k = 0; k < 64; k++)
		cols[k] = k < n ? buf[k] : NULL;
	if (n <= 64) {
		for (int guard = 0; guard < 1 << 20; guard++) {
			if (sscope_reader_read(r, &ch, &d) || ch.rows == 0)
				break;
		}
		sscope_reader_unterminated(r);
	}
	sscope_reader_close(r);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct sscope_reader_opts o = { 0 };
	char path[64];
	int fd;
#ifdef FUZZ_RAW
	char layout[40];
	const uint8_t *nl = memchr(data, '\n', size < 40 ? size : 40);

	if (!nl)
		return 0;
	memcpy(layout, data, (size_t)(nl - data));
	layout[nl - data] = '\0';
	if (sscope_reader_raw_layout_check(layout, NULL, NULL, NULL))
		return 0;
	size -= (size_t)(nl + 1 - data);
	data = nl + 1;
	o.raw = layout;
	o.rate_hz = 100;
	o.raw_scale = 0.01;
#endif
#ifdef FUZZ_MAT
	/* a body without the 128-byte header gets one, so mutations are
	 * spent on the data elements */
	uint8_t *whole = NULL;

	if (size < 19 || memcmp(data, "MATLAB 5.0 MAT-file", 19)) {
		whole = malloc(128 + size);
		if (!whole)
			return 0;
		memset(whole, ' ', 124);
		memcpy(whole, "MATLAB 5.0 MAT-file, fuzz", 25);
		memcpy(whole + 124, "\0\1IM", 4);
		memcpy(whole + 128, data, size);
		data = whole;
		size += 128;
	}
#endif
	o.threads = 1;
	o.nan_as_gap = true;
	chunks(data, size, &o);
	o.nan_as_gap = false;
	fd = fuzz_file(data, size, path, sizeof(path));
	if (fd >= 0) {
		load(path, &o);
		fuzz_file_close(fd);
	}
	/* the pipe path costs 5 times the others (a 4 MiB block and 64 Ki
	 * rows of every channel allocated, and under ASan poisoned, per
	 * input): while fuzzing, one input size in four takes it; a replay
	 * takes it for every input */
	if ((fuzz_replay || size % 4 == 0) && fuzz_stdin(data, size) == 0) {
		load("-", &o);
		fuzz_stdin_restore();
	}
#ifdef FUZZ_MAT
	free(whole);
#endif
	return 0;
}
