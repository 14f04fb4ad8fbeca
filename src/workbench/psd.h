/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The psd stage's analysis and its JSON (psd.c): Welch's estimate
 * streamed through the chunked reader (or from a capture a scene has
 * loaded, or the periodogram of the whole record), peaks, band RMS, the
 * spectrogram.  src/cli/cmd-psd.c parses the options and presents.
 */
#ifndef SSCOPE_WB_PSD_H
#define SSCOPE_WB_PSD_H

#include "workbench.h"

/* The command's options (cmd-psd.c fills them). */
struct ssc_psd_args {
	struct sscope_psd_opts po;
	double overlap;
	size_t peaks;
	double peak_alpha;
	const char *bands;
	bool spectrogram;
	size_t sg_cols;
	bool periodogram;
	bool nperseg_set, overlap_set, sg_cols_set;
};

struct ssc_psd_bandset {
	size_t n;
	struct sscope_psd_band *b;
	bool nominal;
};

/* One channel's estimate. */
struct ssc_psd_chan {
	struct sscope_capture_column col; /* name and unit (strings owned) */
	struct sscope_psd *p;
	struct sscope_psd_spectrum s;
	struct sscope_psd_spectrogram sg;
	bool have_sg;
	struct sscope_psd_sig_peak peaks[100];
	size_t n_peaks;
	struct sscope_psd_peak_test test;
	double *band_rms;
};

/* The stage's result. */
struct ssc_psd_run {
	struct ssc_psd_args a;
	const char *path;
	size_t nch;
	struct ssc_psd_chan *ch;
	uint64_t rows;
	double fs;
	const char *rate_source;
	struct ssc_psd_bandset bands;
	struct sscope_psd_window_figures wf;
	size_t time_gaps;
};

/* SI per unit of the channel (1 when it has none). */
double ssc_psd_uscale(const struct ssc_psd_chan *c);
/* The unit of the channel's spectrum values under scaling @p sc. */
void ssc_psd_unit(const struct ssc_psd_chan *c, enum sscope_psd_scaling sc, char *buf,
		  size_t len);
const char *ssc_psd_detrend_name(enum sscope_psd_detrend d);
const char *ssc_psd_scaling_name(enum sscope_psd_scaling s);

/*
 * The estimate of R->path with the options R->a: from @p cap when a scene
 * has loaded it (or for the periodogram), else streamed from the file;
 * then the warnings, peaks and bands.  Prints errors; returns an exit
 * code.  Free R's arrays with ssc_psd_run_free() in either case.
 */
int ssc_psd_compute(const struct ssc_common *co, struct ssc_psd_run *R,
		    const struct sscope_capture *cap);
void ssc_psd_run_free(struct ssc_psd_run *R);
/* The result's JSON object, a new reference. */
json_t *ssc_psd_json(const struct ssc_psd_run *R);

#endif
