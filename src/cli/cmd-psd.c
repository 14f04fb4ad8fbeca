/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope psd: Welch power spectral density (scipy.signal.welch's
 * conventions and numbers) or the periodogram, window figures, peaks with
 * sub-bin interpolation, band RMS (IEC 61260-1 octaves and thirds, or
 * given bands), the spectrogram.  Welch estimates stream the capture
 * through the chunked reader, so memory does not grow with the record.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "plot.h"
#include "prefetch.h"
#include "stage.h"

enum {
	OPT_WINDOW = 256,
	OPT_NPERSEG,
	OPT_OVERLAP,
	OPT_NFFT,
	OPT_DETREND,
	OPT_SCALING,
	OPT_PEAKS,
	OPT_BANDS,
	OPT_METHOD,
	OPT_SPECTROGRAM,
	OPT_SG_COLS,
	OPT_PEAK_ALPHA,
};

static const struct ssc_option psd_opts[] = {
	{ "window", required_argument, OPT_WINDOW, "NAME",
	  "hann (default), hamming, blackman, blackmanharris, flattop, boxcar" },
	{ "nperseg", required_argument, OPT_NPERSEG, "N",
	  "samples per segment (default 256; longer than the record: the record)" },
	{ "overlap", required_argument, OPT_OVERLAP, "F",
	  "overlap of segments, fraction in [0, 1) (default 0.5)" },
	{ "nfft", required_argument, OPT_NFFT, "N",
	  "FFT length >= nperseg, zero padding (default nperseg)" },
	{ "detrend", required_argument, OPT_DETREND, "constant|linear|none",
	  "remove each segment's mean (default), line, or nothing" },
	{ "scaling", required_argument, OPT_SCALING, "density|spectrum",
	  "unit^2/Hz (default) or unit^2 (a sine of amplitude A reads A^2/2)" },
	{ "method", required_argument, OPT_METHOD, "welch|periodogram",
	  "Welch's average (default, streamed) or one periodogram of the whole record" },
	{ "peaks", required_argument, OPT_PEAKS, "K",
	  "report the K strongest peaks that stand out of the noise (default 5; 0: none)" },
	{ "peak-alpha", required_argument, OPT_PEAK_ALPHA, "A",
	  "false-alarm probability of the peak test per spectrum (default 0.01)" },
	{ "bands", required_argument, OPT_BANDS, "octave|third|LO:HI[,...]",
	  "band RMS: IEC 61260-1 octaves or thirds, or the given bands in Hz" },
	{ "spectrogram", no_argument, OPT_SPECTROGRAM, NULL,
	  "add the spectrogram (short-time PSDs) to the JSON output" },
	{ "spectrogram-columns", required_argument, OPT_SG_COLS, "N",
	  "at most N time columns (default 400; neighbours are averaged)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "psd",
	.usage = "psd [OPTIONS] FILE",
	.summary =
		"Power spectral density by Welch's method with scipy.signal.welch's\n"
		"conventions (DFT-even windows, per-segment detrending, one-sided,\n"
		"density = |X|^2 / (fs sum w^2), spectrum = |X|^2 / (sum w)^2; the numbers\n"
		"equal scipy's), or the periodogram.  Reports the window's figures\n"
		"(coherent gain, equivalent noise bandwidth, scalloping loss), the\n"
		"overall RMS (square root of the integral), the strongest peaks with\n"
		"their frequency and sine amplitude interpolated between bins (a\n"
		"least-squares fit of the window's exact response to five bins, so\n"
		"the amplitude is corrected for the window and the scalloping loss),\n"
		"listed only when they stand out of the local noise floor (each bin\n"
		"is chi-square with the estimate's equivalent degrees of freedom, the\n"
		"overlap correction included; an F test against the median of the\n"
		"neighbouring bins at the level --peak-alpha divided by the bins\n"
		"searched, so noise alone lists a peak in about 1 spectrum in 100),\n"
		"band RMS, and the spectrogram.  The capture is streamed: memory does\n"
		"not grow with the record length (except --method periodogram).",
	.options = psd_opts,
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope psd samples/vibration.csv\n"
		 "  sensorscope psd --nperseg 4096 --window flattop --scaling spectrum --peaks 3 samples/vibration.csv\n"
		 "  sensorscope psd --bands third --format json -c ax samples/vibration.csv\n"
		 "  sensorscope psd --plot psd.png samples/gyro-static.csv\n"
		 "  sensorscope psd --raw i16:1 -r 1000 --format csv - < big.bin\n"
		 "\n"
		 "Values are in the channel's unit: PSD (unit)^2/Hz, RMS and amplitudes\n"
		 "in the unit.  With --allow-nan, segments that hold a NaN gap are left\n"
		 "out of the average (and counted).",
};

struct args {
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

static int handle(int key, const char *arg, void *ctx)
{
	struct args *a = ctx;
	size_t v;

	switch (key) {
	case OPT_WINDOW:
		if (sscope_psd_window_from_name(arg, &a->po.window))
			return ssc_usage_error("psd",
					       "--window: '%s' is not hann, hamming, blackman, blackmanharris, flattop or boxcar",
					       arg);
		return 0;
	case OPT_NPERSEG:
		if (ssc_arg_size("psd", "nperseg", arg, &v))
			return SSC_EXIT_USAGE;
		if (v < 1 || v > ((size_t)1 << 30))
			return ssc_usage_error("psd", "--nperseg: must be 1 to 2^30");
		a->po.nperseg = v;
		a->nperseg_set = true;
		return 0;
	case OPT_OVERLAP:
		if (ssc_arg_double("psd", "overlap", arg, &a->overlap))
			return SSC_EXIT_USAGE;
		if (!(a->overlap >= 0 && a->overlap < 1))
			return ssc_usage_error("psd", "--overlap: must be in [0, 1)");
		a->overlap_set = true;
		return 0;
	case OPT_NFFT:
		if (ssc_arg_size("psd", "nfft", arg, &v))
			return SSC_EXIT_USAGE;
		if (v < 1 || v > ((size_t)1 << 30))
			return ssc_usage_error("psd", "--nfft: must be 1 to 2^30");
		a->po.nfft = v;
		return 0;
	case OPT_DETREND:
		if (!strcmp(arg, "constant"))
			a->po.detrend = SSCOPE_PSD_DETREND_CONSTANT;
		else if (!strcmp(arg, "linear"))
			a->po.detrend = SSCOPE_PSD_DETREND_LINEAR;
		else if (!strcmp(arg, "none"))
			a->po.detrend = SSCOPE_PSD_DETREND_NONE;
		else
			return ssc_usage_error("psd", "--detrend: '%s' is not constant, linear or none", arg);
		return 0;
	case OPT_SCALING:
		if (!strcmp(arg, "density"))
			a->po.scaling = SSCOPE_PSD_SCALING_DENSITY;
		else if (!strcmp(arg, "spectrum"))
			a->po.scaling = SSCOPE_PSD_SCALING_SPECTRUM;
		else
			return ssc_usage_error("psd", "--scaling: '%s' is not density or spectrum", arg);
		return 0;
	case OPT_METHOD:
		if (!strcmp(arg, "welch"))
			a->periodogram = false;
		else if (!strcmp(arg, "periodogram"))
			a->periodogram = true;
		else
			return ssc_usage_error("psd", "--method: '%s' is not welch or periodogram", arg);
		return 0;
	case OPT_PEAKS:
		if (ssc_arg_size("psd", "peaks", arg, &a->peaks))
			return SSC_EXIT_USAGE;
		if (a->peaks > 100)
			return ssc_usage_error("psd", "--peaks: at most 100");
		return 0;
	case OPT_PEAK_ALPHA:
		if (ssc_arg_double("psd", "peak-alpha", arg, &a->peak_alpha))
			return SSC_EXIT_USAGE;
		if (!(a->peak_alpha > 0 && a->peak_alpha < 1))
			return ssc_usage_error("psd", "--peak-alpha: a probability between 0 and 1, exclusive");
		return 0;
	case OPT_BANDS:
		a->bands = arg;
		return 0;
	case OPT_SPECTROGRAM:
		a->spectrogram = true;
		return 0;
	case OPT_SG_COLS:
		if (ssc_arg_size("psd", "spectrogram-columns", arg, &v))
			return SSC_EXIT_USAGE;
		if (v < 2 || v > 100000)
			return ssc_usage_error("psd", "--spectrogram-columns: must be 2 to 100000");
		a->sg_cols = v;
		a->sg_cols_set = true;
		return 0;
	default:
		return ssc_usage_error("psd", "unexpected option");
	}
}

/* ------------------------------------------------------------ bands */

struct bandset {
	size_t n;
	struct sscope_psd_band *b;
	bool nominal;
};

/* Parse --bands once the spectrum (its rate and bins) is known. */
static int make_bands(const char *cmd, const char *arg, double fs,
		      const struct sscope_psd_spectrum *sp, struct bandset *bs)
{
	size_t n = 0;

	memset(bs, 0, sizeof(*bs));
	if (!arg)
		return 0;
	if (!strcmp(arg, "octave") || !strcmp(arg, "third")) {
		unsigned frac = arg[0] == 'o' ? 1 : 3;
		size_t all;

		if (!sp || sscope_psd_spectrum_octave_bands(sp, frac, NULL, 0, &all) ||
		    all == 0)
			return 0;
		bs->b = calloc(all, sizeof(*bs->b));
		if (!bs->b)
			return SSC_EXIT_FAIL;
		sscope_psd_spectrum_octave_bands(sp, frac, bs->b, all, &bs->n);
		bs->nominal = true;
		return 0;
	}
	for (const char *p = arg; *p; p++)
		n += *p == ',';
	bs->b = calloc(n + 1, sizeof(*bs->b));
	if (!bs->b)
		return SSC_EXIT_FAIL;
	for (const char *p = arg; *p;) {
		const char *e = strchr(p, ','), *c;
		char buf[64];
		size_t l = e ? (size_t)(e - p) : strlen(p);
		double lo, hi;
		int rc;

		if (l >= sizeof(buf))
			goto bad;
		memcpy(buf, p, l);
		buf[l] = '\0';
		c = strchr(buf, ':');
		if (!c)
			goto bad;
		if (ssc_parse_double(buf, c, &lo) != (size_t)(c - buf) ||
		    ssc_parse_double(c + 1, buf + l, &hi) != strlen(c + 1))
			goto bad;
		rc = sscope_psd_band_edges(lo, hi, fs / 2, &bs->b[bs->n]);
		if (rc == -EDOM) {
			ssc_err(cmd, "--bands: %g:%g lies above the Nyquist frequency %g Hz",
				lo, hi, fs / 2);
			return SSC_EXIT_USAGE;
		}
		if (rc)
			goto bad;
		bs->n++;
		p += l + (e ? 1 : 0);
	}
	return 0;
bad:
	return ssc_usage_error(cmd, "--bands: '%s' is not octave, third or LO:HI[,LO:HI...] in Hz",
			       arg);
}

/* ------------------------------------------------------------ analysis */

struct chan {
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

struct run {
	struct args a;
	const char *path;
	size_t nch;
	struct chan *ch;
	uint64_t rows;
	double fs;
	const char *rate_source;
	struct bandset bands;
	struct sscope_psd_window_figures wf;
	size_t time_gaps;
};

static double uscale(const struct chan *c)
{
	return c->col.unit.scale != 0 ? c->col.unit.scale : 1;
}

static void psd_unit(const struct chan *c, enum sscope_psd_scaling sc, char *buf,
		     size_t len)
{
	const char *u = c->col.unit_label;

	if (!u || !*u)
		snprintf(buf, len, "%s", sc == SSCOPE_PSD_SCALING_DENSITY ? "1/Hz" : "1");
	else
		snprintf(buf, len, "(%s)^2%s", u,
			 sc == SSCOPE_PSD_SCALING_DENSITY ? "/Hz" : "");
}

struct progress_ctx {
	const struct ssc_common *co;
	const char *label;
};

static void read_progress(void *ctx, uint64_t done, uint64_t total)
{
	struct progress_ctx *p = ctx;

	ssc_progress(p->co, p->label, (double)done, (double)total);
}

static int copy_col(struct sscope_capture_column *dst, const struct sscope_capture_column *src)
{
	*dst = *src;
	dst->name = strdup(src->name);
	dst->unit_label = strdup(src->unit_label ? src->unit_label : "");
	return dst->name && dst->unit_label ? 0 : -ENOMEM;
}

/* A spectrum finite in SI can overflow in the channel's unit (mg, uV):
 * an error, never "inf" in a table.  Returns an exit code. */
static int check_shown(const struct ssc_common *co, const struct run *R,
		       const struct chan *c)
{
	double vmax = 0, u = uscale(c);

	for (size_t k = 0; k < c->s.n_bins; k++)
		vmax = c->s.value[k] > vmax ? c->s.value[k] : vmax;
	if (isfinite(vmax / u / u) && isfinite(c->s.rms / u))
		return SSC_EXIT_OK;
	ssc_err(co->cmd, "%s: channel %s: spectrum values up to %g in SI units exceed the double range in %s",
		R->path, c->col.name, vmax, c->col.unit_label);
	return SSC_EXIT_FAIL;
}

/* Why sscope_psd_result() failed, for -EDOM and -ERANGE. */
static const char *result_error(int rc, double fs)
{
	static char buf[200];

	if (rc == -EDOM)
		return "every segment holds a NaN gap";
	snprintf(buf, sizeof(buf),
		 "at %g Hz the spectrum leaves the double range (values above 1.8e308 or all below 1e-292 in SI units): check --rate and the data's unit",
		 fs);
	return buf;
}

/* end of the last whole segment of n samples */
/* Streamed Welch estimate of every selected channel. */
static int stream(const struct ssc_common *co, struct run *R)
{
	struct sscope_reader_opts ro;
	struct sscope_reader *rd = NULL;
	struct sscope_diag d = { "" };
	struct ssc_prefetch *pf = NULL;
	const struct sscope_reader_chunk *cur;
	struct progress_ctx pc = { co, R->path };
	const size_t cap = 65536;
	struct sscope_timing_stream *ts = NULL;
	struct sscope_timing tm;
	bool use_time, disorder = false, have_result = false;
	int rc, ex = SSC_EXIT_FAIL;

	ssc_read_opts(co, &ro);
	if (ssc_progress_on(co)) {
		ro.progress = read_progress;
		ro.progress_ctx = &pc;
	}
	rc = sscope_reader_open(&rd, R->path, &ro, &d);
	if (rc) {
		if (rc == -EINVAL && co->raw && !d.msg[0])
			return ssc_usage_error(co->cmd, "bad --raw '%s'", co->raw);
		return ssc_fail(co->cmd, rc, &d, R->path);
	}
	R->nch = sscope_reader_n_channels(rd);
	R->ch = calloc(R->nch ? R->nch : 1, sizeof(*R->ch));
	if (!R->ch)
		goto nomem;
	/* the time column as the capture loader reads it (its streaming
	 * form): rate and gaps */
	use_time = sscope_reader_time_column(rd) != NULL;
	if (use_time) {
		if (sscope_timing_stream_new(&ts, SSCOPE_TIMING_GAP_FACTOR))
			goto nomem;
	}
	for (size_t k = 0; k < R->nch; k++) {
		if (copy_col(&R->ch[k].col, sscope_reader_channel(rd, k)))
			goto nomem;
		rc = sscope_psd_new(&R->ch[k].p, &R->a.po);
		if (rc) {
			ssc_fail(co->cmd, rc, NULL, "psd");
			goto out;
		}
	}
	if (!use_time && ssc_psd_fed_from_mapping(co, R->path, R->nch, rd,
						     R->ch[0].p, &R->ch[0].s,
						     &R->rows)) {
		have_result = true;
		goto fed;
	}
	/* the next chunk is read while this one is transformed */
	rc = ssc_prefetch_start(&pf, rd, R->nch, cap, use_time);
	if (rc)
		goto nomem;
	for (;;) {
		rc = ssc_prefetch_next(pf, &cur, &d);
		if (rc) {
			ssc_fail(co->cmd, rc, &d, R->path);
			goto out;
		}
		if (cur->rows == 0)
			break;
		for (size_t k = 0; k < R->nch; k++) {
			rc = sscope_psd_feed(R->ch[k].p, cur->data[k], 1, cur->rows);
			if (rc) {
				ssc_err(co->cmd, "%s: channel %s: %s", R->path,
					R->ch[k].col.name, sscope_strerror(rc));
				goto out;
			}
		}
		if (use_time)
			sscope_timing_stream_feed(ts, cur->time_s, cur->rows);
		R->rows += cur->rows;
	}
fed:
	ssc_progress_end(co);
	if (R->rows == 0) {
		ssc_err(co->cmd, "%s: no data rows", R->path);
		goto out;
	}
	if (sscope_reader_unterminated(rd))
		ssc_warn_unterminated(co, R->path, R->rows);
	if (use_time) {
		int trc = sscope_timing_stream_result(ts, &tm);

		if (sscope_timing_order_check(&tm.order, NULL)) {
			/* an error naming the problem, or a warning when
			 * --rate or a header gives the rate (as allan) */
			disorder = true;
			if (ssc_time_verdict(co, R->path,
					     sscope_reader_time_column(rd)->name,
					     &tm.order,
					     co->rate_hz > 0 ? SSCOPE_CAPTURE_RATE_GIVEN :
					     sscope_reader_header_rate(rd) > 0 ?
					     SSCOPE_CAPTURE_RATE_HEADER : SSCOPE_CAPTURE_RATE_NONE,
					     true))
				goto out;
		}
		use_time = trc == 0 && !disorder;
	}
	if (use_time)
		R->time_gaps = tm.n_gaps;
	if (co->rate_hz > 0) {
		R->fs = co->rate_hz;
		R->rate_source = "given";
	} else if (use_time) {
		R->fs = tm.rate_hz;
		R->rate_source = "time column";
	} else if (sscope_reader_header_rate(rd) > 0) {
		R->fs = sscope_reader_header_rate(rd);
		R->rate_source = "header";
	} else {
		ssc_err(co->cmd, "%s: no sample rate (no time column or '# rate:' comment): give --rate",
			R->path);
		goto out;
	}
	for (size_t k = 0; k < R->nch; k++) {
		struct chan *c = &R->ch[k];

		rc = have_result ? 0 : sscope_psd_result(c->p, R->fs, &c->s);
		if (rc == -EDOM || rc == -ERANGE) {
			ssc_err(co->cmd, "%s: channel %s: %s", R->path,
				c->col.name, result_error(rc, R->fs));
			goto out;
		}
		if (rc) {
			ssc_fail(co->cmd, rc, NULL, R->path);
			goto out;
		}
		if (check_shown(co, R, c))
			goto out;
		if (R->a.po.spectrogram_cols) {
			if (c->s.nperseg == R->a.po.nperseg) {
				rc = sscope_psd_spectrogram(c->p, R->fs, &c->sg);
				c->have_sg = rc == 0;
			}
		}
	}
	ex = SSC_EXIT_OK;
	goto out;
nomem:
	ssc_err(co->cmd, "out of memory");
out:
	ssc_prefetch_stop(pf);
	sscope_timing_stream_free(ts);
	sscope_reader_close(rd);
	return ex;
}

static const char *rate_source_name(const struct sscope_capture *cap)
{
	return cap->rate_source == SSCOPE_CAPTURE_RATE_GIVEN ? "given" :
	       cap->rate_source == SSCOPE_CAPTURE_RATE_TIME_COLUMN ? "time column" :
	       cap->rate_source == SSCOPE_CAPTURE_RATE_HEADER ? "header" : "unknown";
}

/* The estimate from a capture in memory: the periodogram (which needs the
 * whole record), or Welch's average when a scene has already loaded it. */
static int from_capture(const struct ssc_common *co, struct run *R,
			const struct sscope_capture *cap)
{
	int rc;

	rc = ssc_time_check(co, R->path, cap, true);
	if (rc)
		return rc;
	if (!(cap->rate_hz > 0)) {
		ssc_err(co->cmd, "%s: no sample rate (no time column or '# rate:' comment): give --rate",
			R->path);
		return SSC_EXIT_FAIL;
	}
	R->fs = cap->rate_hz;
	R->rate_source = rate_source_name(cap);
	R->rows = cap->n;
	/* gaps, unless the stamps are out of order (said above) */
	R->time_gaps = cap->has_timing &&
		       !sscope_timing_order_check(&cap->timing.order, NULL) ?
		       cap->timing.n_gaps : 0;
	R->nch = cap->n_channels;
	R->ch = calloc(R->nch ? R->nch : 1, sizeof(*R->ch));
	if (!R->ch)
		return SSC_EXIT_FAIL;
	for (size_t k = 0; k < R->nch; k++) {
		struct chan *c = &R->ch[k];

		if (copy_col(&c->col, &cap->channels[k].col))
			return SSC_EXIT_FAIL;
		if (R->a.periodogram) {
			rc = sscope_psd_periodogram(cap->channels[k].data, 1, cap->n,
						    R->fs, R->a.po.window,
						    R->a.po.nfft > cap->n ? R->a.po.nfft : 0,
						    R->a.po.detrend, R->a.po.scaling,
						    &c->s);
			if (rc) {
				ssc_err(co->cmd, "%s: channel %s: %s", R->path,
					c->col.name,
					rc == -EDOM ? "NaN gaps: the periodogram needs a gap-free record" :
						      sscope_strerror(rc));
				return SSC_EXIT_FAIL;
			}
			continue;
		}
		rc = sscope_psd_new(&c->p, &R->a.po);
		if (!rc)
			rc = sscope_psd_feed(c->p, cap->channels[k].data, 1, cap->n);
		if (!rc)
			rc = sscope_psd_result(c->p, R->fs, &c->s);
		if (rc) {
			ssc_err(co->cmd, "%s: channel %s: %s", R->path, c->col.name,
				rc == -EDOM || rc == -ERANGE ?
					result_error(rc, R->fs) :
					sscope_strerror(rc));
			return SSC_EXIT_FAIL;
		}
		if (check_shown(co, R, c))
			return SSC_EXIT_FAIL;
		if (R->a.po.spectrogram_cols && c->s.nperseg == R->a.po.nperseg)
			c->have_sg = sscope_psd_spectrogram(c->p, R->fs, &c->sg) == 0;
	}
	return SSC_EXIT_OK;
}

static void finish(struct run *R)
{
	for (size_t k = 0; k < R->nch; k++) {
		struct chan *c = &R->ch[k];
		double sc = uscale(c);

		sscope_psd_spectrum_significant_peaks(&c->s, R->a.peaks, 0, R->fs / 2,
						      R->a.peak_alpha, c->peaks,
						      &c->n_peaks, &c->test);
		if (R->bands.n) {
			c->band_rms = calloc(R->bands.n, sizeof(double));
			for (size_t i = 0; c->band_rms && i < R->bands.n; i++) {
				double ms = 0;

				sscope_psd_spectrum_band_ms(&c->s, R->bands.b[i].lo_hz,
							    R->bands.b[i].hi_hz, &ms);
				c->band_rms[i] = sqrt(ms) / sc;
			}
		}
	}
}

static void free_run(struct run *R)
{
	for (size_t k = 0; R->ch && k < R->nch; k++) {
		struct chan *c = &R->ch[k];

		sscope_psd_free(c->p);
		sscope_psd_spectrum_clear(&c->s);
		sscope_psd_spectrogram_clear(&c->sg);
		free(c->band_rms);
		free((char *)c->col.name);
		free((char *)c->col.unit_label);
	}
	free(R->ch);
	free(R->bands.b);
}

/* ------------------------------------------------------------ output */

static const char *detrend_name(enum sscope_psd_detrend d)
{
	return d == SSCOPE_PSD_DETREND_CONSTANT ? "constant" :
	       d == SSCOPE_PSD_DETREND_LINEAR   ? "linear" :
					      "none";
}

static const char *scaling_name(enum sscope_psd_scaling s)
{
	return s == SSCOPE_PSD_SCALING_DENSITY ? "density" : "spectrum";
}

static json_t *json_run(const struct run *R)
{
	json_t *root = json_object(), *chs = json_array();

	json_object_set_new(root, "command", json_string("psd"));
	json_object_set_new(root, "file", json_string(R->path));
	json_object_set_new(root, "method", json_string(R->a.periodogram ? "periodogram" : "welch"));
	json_object_set_new(root, "peak_interpolation",
			    json_string("least-squares fit of the window's exact response to 5 bins; amplitude corrected for window and scalloping"));
	for (size_t k = 0; k < R->nch; k++) {
		const struct chan *c = &R->ch[k];
		const struct sscope_psd_spectrum *s = &c->s;
		double sc = uscale(c), sc2 = sc * sc;
		json_t *o = json_object(), *f = json_array(), *p = json_array();
		json_t *pk = json_array(), *w = json_object();
		char pu[96];
		struct sscope_psd_window_figures wf;

		psd_unit(c, s->scaling, pu, sizeof(pu));
		json_object_set_new(o, "name", json_string(c->col.name));
		json_object_set_new(o, "unit", json_string(c->col.unit_label));
		json_object_set_new(o, "rate_hz", json_real(R->fs));
		json_object_set_new(o, "rate_source", json_string(R->rate_source));
		json_object_set_new(o, "samples", json_integer((json_int_t)s->n_samples));
		json_object_set_new(o, "scaling", json_string(scaling_name(s->scaling)));
		json_object_set_new(o, "psd_unit", json_string(pu));
		sscope_psd_window_figures(s->window, s->nperseg, &wf);
		json_object_set_new(w, "name", json_string(sscope_psd_window_name(s->window)));
		json_object_set_new(w, "nperseg", json_integer((json_int_t)s->nperseg));
		json_object_set_new(w, "noverlap", json_integer((json_int_t)s->noverlap));
		json_object_set_new(w, "nfft", json_integer((json_int_t)s->nfft));
		json_object_set_new(w, "detrend", json_string(detrend_name(s->detrend)));
		json_object_set_new(w, "coherent_gain", json_real(wf.coherent_gain));
		json_object_set_new(w, "enbw_bins", json_real(wf.enbw_bins));
		json_object_set_new(w, "enbw_hz", json_real(s->enbw_hz));
		json_object_set_new(w, "scalloping_loss_db", ssc_jreal(wf.scalloping_db));
		json_object_set_new(o, "window", w);
		json_object_set_new(o, "segments", json_integer((json_int_t)s->n_segments));
		json_object_set_new(o, "segments_skipped", json_integer((json_int_t)s->n_skipped));
		json_object_set_new(o, "bin_hz", json_real(s->bin_hz));
		for (size_t i = 0; i < s->n_bins; i++) {
			json_array_append_new(f, json_real(s->freq_hz[i]));
			json_array_append_new(p, ssc_jreal(s->value[i] / sc2));
		}
		json_object_set_new(o, "frequency_hz", f);
		json_object_set_new(o, "psd", p);
		json_object_set_new(o, "rms", ssc_jreal(s->rms / sc));
		for (size_t i = 0; i < c->n_peaks; i++) {
			const struct sscope_psd_sig_peak *sp = &c->peaks[i];
			json_t *e = json_object();

			json_object_set_new(e, "frequency_hz", ssc_jreal(sp->peak.frequency_hz));
			json_object_set_new(e, "value", ssc_jreal(sp->peak.value / sc2));
			json_object_set_new(e, "amplitude", ssc_jreal(sp->peak.amplitude / sc));
			json_object_set_new(e, "rms", ssc_jreal(sp->peak.rms / sc));
			json_object_set_new(e, "bin", json_integer((json_int_t)sp->peak.bin));
			json_object_set_new(e, "floor", ssc_jreal(sp->floor / sc2));
			json_object_set_new(e, "ratio", ssc_jreal(sp->ratio));
			json_object_set_new(e, "p_value", ssc_jreal(sp->p_value));
			json_array_append_new(pk, e);
		}
		json_object_set_new(o, "peaks", pk);
		{
			const struct sscope_psd_peak_test *t = &c->test;
			json_t *e = json_object();

			json_object_set_new(e, "method", json_string(
				"F test of each local maximum against the local noise floor (median of the neighbouring bins outside the main lobe, over the median of chi2(nu)/nu), nu the Welch estimate's equivalent degrees of freedom with the overlap correction (Percival & Walden 1993), at the level alpha / bins (Bonferroni); weaker peaks also against the leakage of stronger ones"));
			json_object_set_new(e, "alpha", json_real(t->alpha));
			json_object_set_new(e, "edf", ssc_jreal(t->edf));
			json_object_set_new(e, "floor_edf", ssc_jreal(t->floor_edf));
			json_object_set_new(e, "bins_tested", json_integer((json_int_t)t->bins_tested));
			json_object_set_new(e, "p_threshold", ssc_jreal(t->p_threshold));
			json_object_set_new(e, "ratio_threshold", ssc_jreal(t->ratio_threshold));
			json_object_set_new(e, "floor_half_width_bins",
					    json_integer((json_int_t)t->floor_half_width));
			json_object_set_new(o, "peak_test", e);
		}
		if (R->a.bands) {
			json_t *b = json_array();

			for (size_t i = 0; i < R->bands.n; i++) {
				json_t *e = json_object();

				json_object_set_new(e, "lo_hz", json_real(R->bands.b[i].lo_hz));
				json_object_set_new(e, "center_hz", json_real(R->bands.b[i].center_hz));
				json_object_set_new(e, "hi_hz", json_real(R->bands.b[i].hi_hz));
				if (R->bands.nominal)
					json_object_set_new(e, "nominal_hz", json_real(R->bands.b[i].nominal_hz));
				json_object_set_new(e, "rms", c->band_rms ? ssc_jreal(c->band_rms[i]) : json_null());
				json_array_append_new(b, e);
			}
			json_object_set_new(o, "bands", b);
		}
		if (R->a.spectrogram && c->have_sg) {
			json_t *g = json_object(), *t = json_array(), *gf = json_array(), *gv = json_array();

			for (size_t i = 0; i < c->sg.n_times; i++) {
				json_t *col = json_array();

				json_array_append_new(t, json_real(c->sg.time_s[i]));
				for (size_t j = 0; j < c->sg.n_bins; j++)
					json_array_append_new(col, ssc_jreal(c->sg.value[i * c->sg.n_bins + j] / sc2));
				json_array_append_new(gv, col);
			}
			for (size_t j = 0; j < c->sg.n_bins; j++)
				json_array_append_new(gf, json_real(c->sg.freq_hz[j]));
			json_object_set_new(g, "time_s", t);
			json_object_set_new(g, "frequency_hz", gf);
			json_object_set_new(g, "psd", gv);
			json_object_set_new(g, "segments_per_column",
					    json_integer((json_int_t)c->sg.segments_per_column));
			json_object_set_new(o, "spectrogram", g);
		}
		json_array_append_new(chs, o);
	}
	json_object_set_new(root, "channels", chs);
	if (R->nch && R->ch[0].s.nperseg < R->a.po.nperseg && !R->a.periodogram)
		ssc_json_warn(root, "too_few_samples",
			      "%s: %llu samples, fewer than one segment of %zu: the spectrum is a single periodogram, each bin with 2 degrees of freedom (its sd equals its value)",
			      R->path, (unsigned long long)R->rows, R->a.po.nperseg);
	return root;
}

static void text_run(FILE *f, const struct run *R)
{
	char a[32], b[32], c3[32], d[32];

	fprintf(f, "%s\n", strcmp(R->path, "-") ? R->path : "(stdin)");
	fprintf(f, "  rate:     %s Hz (%s), %llu samples\n",
		ssc_fmt(a, sizeof(a), R->fs, 8), R->rate_source,
		(unsigned long long)R->rows);
	if (R->nch) {
		const struct sscope_psd_spectrum *s = &R->ch[0].s;
		struct sscope_psd_window_figures wf;

		sscope_psd_window_figures(s->window, s->nperseg, &wf);
		fprintf(f, "  method:   %s, %s window, nperseg %zu, noverlap %zu, nfft %zu, detrend %s, %s\n",
			R->a.periodogram ? "periodogram" : "Welch",
			sscope_psd_window_name(s->window), s->nperseg, s->noverlap,
			s->nfft, detrend_name(s->detrend), scaling_name(s->scaling));
		fprintf(f, "  window:   coherent gain %s, ENBW %s bins = %s Hz, scalloping loss %s dB\n",
			ssc_fmt(a, sizeof(a), wf.coherent_gain, 5),
			ssc_fmt(b, sizeof(b), wf.enbw_bins, 5),
			ssc_fmt(c3, sizeof(c3), s->enbw_hz, 5),
			ssc_fmt(d, sizeof(d), wf.scalloping_db, 3));
		fprintf(f, "  segments: %zu averaged%s, resolution %s Hz\n",
			s->n_segments, s->n_skipped ? " (some skipped: NaN gaps)" : "",
			ssc_fmt(a, sizeof(a), s->bin_hz, 6));
	}
	for (size_t k = 0; k < R->nch; k++) {
		const struct chan *c = &R->ch[k];
		double sc = uscale(c);
		const char *u = c->col.unit_label[0] ? c->col.unit_label : "";
		char pu[96];

		psd_unit(c, c->s.scaling, pu, sizeof(pu));
		fprintf(f, "\n  %s: rms %s %s", c->col.name,
			ssc_fmt(a, sizeof(a), c->s.rms / sc, 6), u);
		if (c->s.n_skipped)
			fprintf(f, " (%zu segments with NaN skipped)", c->s.n_skipped);
		fputc('\n', f);
		if (R->a.peaks && c->n_peaks) {
			fprintf(f, "    %-14s %-16s %-14s %s\n", "peak (Hz)",
				c->s.scaling == SSCOPE_PSD_SCALING_DENSITY ? "PSD" : "spectrum",
				"amplitude", "over floor");
			for (size_t i = 0; i < c->n_peaks; i++)
				fprintf(f, "    %-14s %-16s %-14s %s\n",
					ssc_fmt(a, sizeof(a), c->peaks[i].peak.frequency_hz, 7),
					ssc_fmt(b, sizeof(b), c->peaks[i].peak.value / (sc * sc), 5),
					ssc_fmt(c3, sizeof(c3), c->peaks[i].peak.amplitude / sc, 5),
					ssc_fmt((char[32]){ 0 }, 32, c->peaks[i].ratio, 3));
			fprintf(f, "    (PSD in %s; amplitude: of the sine, peak, in %s)\n",
				pu, *u ? u : "the data's unit");
		}
		if (R->a.peaks)
			fprintf(f, "    %s peak stands out of the noise floor at false-alarm probability %s (F test per bin at %s over %zu bins, %s dof)\n",
				c->n_peaks ? "each listed" : "no", ssc_fmt(a, sizeof(a), c->test.alpha, 2),
				ssc_fmt(b, sizeof(b), c->test.p_threshold, 2), c->test.bins_tested,
				ssc_fmt(c3, sizeof(c3), c->test.edf, 3));
		if (R->a.bands && R->bands.n) {
			fprintf(f, "    %-12s %-12s %-12s %s\n", "band lo (Hz)",
				R->bands.nominal ? "centre" : "centre (geo)",
				"hi (Hz)", "rms");
			for (size_t i = 0; i < R->bands.n; i++)
				fprintf(f, "    %-12s %-12s %-12s %s\n",
					ssc_fmt(a, sizeof(a), R->bands.b[i].lo_hz, 5),
					ssc_fmt(b, sizeof(b), R->bands.nominal ?
						R->bands.b[i].nominal_hz : R->bands.b[i].center_hz, 5),
					ssc_fmt(c3, sizeof(c3), R->bands.b[i].hi_hz, 5),
					c->band_rms ? ssc_fmt(d, sizeof(d), c->band_rms[i], 5) : "-");
		}
	}
	fprintf(f, "\n  (the spectrum itself: --format json or csv)\n");
}

static void csv_run(FILE *f, const struct run *R)
{
	fprintf(f, "frequency_hz");
	for (size_t k = 0; k < R->nch; k++) {
		char pu[96];

		psd_unit(&R->ch[k], R->ch[k].s.scaling, pu, sizeof(pu));
		fprintf(f, ",%s [%s]", R->ch[k].col.name, pu);
	}
	fputc('\n', f);
	if (!R->nch)
		return;
	for (size_t i = 0; i < R->ch[0].s.n_bins; i++) {
		fprintf(f, "%.17g", R->ch[0].s.freq_hz[i]);
		for (size_t k = 0; k < R->nch; k++) {
			double sc = uscale(&R->ch[k]);

			fprintf(f, ",%.17g", R->ch[k].s.value[i] / (sc * sc));
		}
		fputc('\n', f);
	}
}

static int plot_fig(const struct ssc_common *co, const void *opts,
		    const void *result, const char *path)
{
	const struct run *R = result;
	size_t nch = R->nch < 6 ? R->nch : 6;
	const struct chan *c0 = &R->ch[0];
	bool sg = c0->have_sg && c0->sg.n_times >= 2;
	struct ssc_fig *fig = ssc_fig_new(1100, sg ? 1000 : 600, sg ? 2 : 1, 1);
	struct ssc_ax *ax;
	char buf[256], pu[96];
	double *y = NULL;
	int rc;

	(void)opts;
	if (!fig)
		return SSC_EXIT_FAIL;
	snprintf(buf, sizeof(buf), "%s: %s, %s window, nperseg %zu", R->path,
		 R->a.periodogram ? "periodogram" : "Welch PSD",
		 sscope_psd_window_name(c0->s.window), c0->s.nperseg);
	ssc_fig_title(fig, buf);
	ax = ssc_fig_ax(fig, 0, 0);
	ssc_ax_log(ax, true, true);
	y = malloc(c0->s.n_bins * sizeof(double));
	if (!y) {
		ssc_fig_free(fig);
		return SSC_EXIT_FAIL;
	}
	for (size_t k = 0; k < nch; k++) {
		const struct chan *c = &R->ch[k];
		struct ssc_style st = { .color = ssc_plot_color(k), .width = 1.3 };
		struct ssc_style mk = { .color = ssc_plot_color(k), .width = -1,
					.marker = SSC_MK_CIRCLE, .marker_size = 7 };
		double sc2 = uscale(c) * uscale(c);

		for (size_t i = 0; i < c->s.n_bins; i++)
			y[i] = c->s.value[i] / sc2;
		ssc_ax_line(ax, c->s.freq_hz, y, c->s.n_bins, &st, c->col.name);
		/* the significant peaks only */
		for (size_t i = 0; i < c->n_peaks && i < 5; i++) {
			double px = c->peaks[i].peak.frequency_hz;
			double py = c->peaks[i].peak.value / sc2;

			ssc_ax_line(ax, &px, &py, 1, &mk, NULL);
			if (k == 0) {
				snprintf(buf, sizeof(buf), "%.4g Hz", px);
				ssc_ax_text(ax, px, py * 1.6, buf, 0, ssc_plot_color(k));
			}
		}
	}
	ssc_ax_xlabel(ax, "frequency (Hz)");
	if (c0->s.n_bins > 1)
		ssc_ax_xlim(ax, c0->s.freq_hz[1], R->fs / 2);
	psd_unit(c0, c0->s.scaling, pu, sizeof(pu));
	snprintf(buf, sizeof(buf), "%s (%s)",
		 c0->s.scaling == SSCOPE_PSD_SCALING_DENSITY ? "PSD" : "power spectrum", pu);
	ssc_ax_ylabel(ax, buf);
	ssc_ax_grid(ax, true);
	if (nch > 1)
		ssc_ax_legend(ax, SSC_LEGEND_AUTO);
	else
		ssc_ax_legend(ax, SSC_LEGEND_NONE);
	if (sg) {
		/* the spectrogram of the first channel, frequency rows
		 * averaged down to at most 400 */
		const struct sscope_psd_spectrogram *g = &c0->sg;
		size_t ny = g->n_bins > 400 ? 400 : g->n_bins, nx = g->n_times;
		size_t per = (g->n_bins + ny - 1) / ny;
		double *z, zlo = INFINITY, zhi = 0, sc2 = uscale(c0) * uscale(c0);
		double dt = (g->time_s[nx - 1] - g->time_s[0]) / (double)(nx - 1);

		ny = (g->n_bins + per - 1) / per;
		z = calloc(nx * ny, sizeof(double));
		if (z) {
			for (size_t t = 0; t < nx; t++)
				for (size_t r = 0; r < ny; r++) {
					double s = 0;
					size_t cnt = 0;

					for (size_t j = r * per; j < (r + 1) * per && j < g->n_bins; j++, cnt++)
						s += g->value[t * g->n_bins + j];
					z[r * nx + t] = cnt ? s / (double)cnt / sc2 : (double)NAN;
				}
			for (size_t i = 0; i < nx * ny; i++)
				if (z[i] > 0) {
					zlo = fmin(zlo, z[i]);
					zhi = fmax(zhi, z[i]);
				}
			/* colour range: the top 100 dB */
			if (zhi > 0 && zlo < zhi * 1e-10)
				zlo = zhi * 1e-10;
			for (size_t i = 0; i < nx * ny; i++)
				if (!(z[i] >= zlo))
					z[i] = zlo;
			ax = ssc_fig_ax(fig, 1, 0);
			if (zhi > 0) {
				if (!(zhi > zlo))
					zlo = zhi / 10;
				ssc_ax_image(ax, z, nx, ny, g->time_s[0] - dt / 2,
					     g->time_s[nx - 1] + dt / 2, 0,
					     R->fs / 2, zlo, zhi, true, pu);
			}
			snprintf(buf, sizeof(buf), "spectrogram of %s", c0->col.name);
			ssc_ax_title(ax, buf);
			ssc_ax_xlabel(ax, "time (s)");
			ssc_ax_ylabel(ax, "frequency (Hz)");
			free(z);
		}
	}
	rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	free(y);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *path)
{
	const struct run *R = result;

	return R->nch ? plot_fig(co, opts, result, path) : SSC_EXIT_OK;
}

static void init(void *opts)
{
	struct args *a = opts;

	memset(a, 0, sizeof(*a));
	sscope_psd_opts_init(&a->po);
	a->po.nperseg = 256;
	a->overlap = 0.5;
	a->peaks = 5;
	a->peak_alpha = 0.01;
	a->sg_cols = 400;
	a->po.shorten = true; /* a scene's stage too: the record, if shorter */
}

/* Cross-checks of the options, and the estimator's options from them. */
static int check(struct ssc_common *co, void *opts)
{
	struct args *a = opts;

	if (a->po.nfft && a->po.nfft < a->po.nperseg)
		return ssc_usage_error(co->cmd, "--nfft %zu is shorter than --nperseg %zu",
				       a->po.nfft, a->po.nperseg);
	if (a->periodogram && (a->spectrogram || a->nperseg_set || a->overlap_set))
		return ssc_usage_error(co->cmd, "--method periodogram takes no --nperseg, --overlap or --spectrogram");
	/* options that would be ignored */
	if (a->spectrogram && co->format != SSC_FMT_JSON && !co->plot)
		return ssc_usage_error(co->cmd, "--spectrogram: the spectrogram is part of the JSON output (--format json) and of the figure (--plot)");
	if (a->sg_cols_set && !a->spectrogram && !co->plot)
		return ssc_usage_error(co->cmd, "--spectrogram-columns: no --spectrogram or --plot");
	a->po.noverlap = sscope_psd_noverlap(a->overlap, a->po.nperseg);
	a->po.skip_nonfinite = co->allow_nan;
	a->po.shorten = true;
	a->po.spectrogram_cols = a->spectrogram || co->plot ? a->sg_cols : 0;
	return SSC_EXIT_OK;
}

/* Everything after the estimate: warnings, peaks, bands. */
static int finish_run(const struct ssc_common *co, struct run *R)
{
	int rc;

	if (R->time_gaps)
		ssc_warn(co, "%s: %zu gaps in the time stamps: the spectrum assumes uniform sampling",
			 R->path, R->time_gaps);
	if (R->nch && R->ch[0].s.nperseg < R->a.po.nperseg && !R->a.periodogram)
		ssc_warn(co, "%s: --nperseg %zu is longer than the record (%llu samples): one segment of %zu",
			 R->path, R->a.po.nperseg, (unsigned long long)R->rows,
			 R->ch[0].s.nperseg);
	for (size_t k = 0; k < R->nch; k++)
		if (R->ch[k].s.n_skipped)
			ssc_warn(co, "%s: channel %s: %zu of %zu segments skipped (NaN gaps)",
				 R->path, R->ch[k].col.name, R->ch[k].s.n_skipped,
				 R->ch[k].s.n_skipped + R->ch[k].s.n_segments);
	if (R->nch && R->ch[0].s.rms == 0)
		ssc_warn(co, "%s: the detrended signal is zero (constant input): the spectrum is zero",
			 R->path);
	rc = make_bands(co->cmd, R->a.bands, R->fs, R->nch ? &R->ch[0].s : NULL,
			&R->bands);
	if (rc)
		return rc;
	finish(R);
	return SSC_EXIT_OK;
}

/* Welch's estimate streams the file when the command reads it itself;
 * the periodogram needs the whole record. */
static bool streams(const void *opts)
{
	return !((const struct args *)opts)->periodogram;
}

static void free_result(void *result)
{
	free_run(result);
	free(result);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	struct run *R = calloc(1, sizeof(*R));
	int rc;

	if (!R) {
		ssc_err(env->co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = R;
	R->a = *(struct args *)opts;
	if (env->n_caps != 1) {
		ssc_err(env->co->cmd, "one input capture at a time");
		return SSC_EXIT_USAGE;
	}
	R->path = env->paths[0];
	rc = env->caps ? from_capture(env->co, R, env->caps[0]) :
			 stream(env->co, R);
	return rc ? rc : finish_run(env->co, R);
}

static void text(FILE *f, const void *opts, const void *result)
{
	(void)opts;
	text_run(f, result);
}

static void csv(FILE *f, const void *opts, const void *result)
{
	(void)opts;
	csv_run(f, result);
}

static json_t *json(const void *opts, const void *result)
{
	(void)opts;
	return json_run(result);
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct run *R = result;

	(void)opts;
	for (size_t k = 0; k < R->nch; k++) {
		const struct chan *c = &R->ch[k];
		const char *u = c->col.unit_label;

		ssc_summary_add(rows, c->col.name, "RMS (PSD integral)",
				c->s.rms / uscale(c), NAN, NAN, u, NULL);
		if (c->n_peaks) {
			char note[96];

			snprintf(note, sizeof(note), "amplitude %.4g %s, %.3g x the noise floor",
				 c->peaks[0].peak.amplitude / uscale(c), u,
				 c->peaks[0].ratio);
			ssc_summary_add(rows, c->col.name, "strongest peak",
					c->peaks[0].peak.frequency_hz, NAN, NAN, "Hz",
					note);
		}
	}
}

const struct ssc_stage_ops ssc_psd_stage = {
	.spec = &spec,
	.title = "Power spectral density",
	.needs = SSC_NEED_DATA,
	.min_files = 1,
	.max_files = 1,
	.opts_size = sizeof(struct args),
	.init = init,
	.handle = handle,
	.check = check,
	.streams = streams,
	.run = run,
	.json = json,
	.text = text,
	.csv = csv,
	.summary = summary,
	.plot = plot,
	.free_result = free_result,
};

int ssc_cmd_psd(int argc, char **argv)
{
	return ssc_stage_main(&ssc_psd_stage, argc, argv);
}
