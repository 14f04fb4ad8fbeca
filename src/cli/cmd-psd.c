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

#include "plot.h"
#include "psd.h"
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
	  "FFT length, nperseg to 64 nperseg: zero padding (default nperseg)" },
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


static int handle(int key, const char *arg, void *ctx)
{
	struct ssc_psd_args *a = ctx;
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

/* ------------------------------------------------------------ output */

static void text_run(FILE *f, const struct ssc_psd_run *R)
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
		fprintf(f, "  method:   %s, %s window, segments of %zu samples overlapping by %zu, FFT of %zu, detrend %s, %s\n",
			R->a.periodogram ? "periodogram" : "Welch",
			sscope_psd_window_name(s->window), s->nperseg, s->noverlap,
			s->nfft, ssc_psd_detrend_name(s->detrend), ssc_psd_scaling_name(s->scaling));
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
		const struct ssc_psd_chan *c = &R->ch[k];
		double sc = ssc_psd_uscale(c);
		const char *u = c->col.unit_label[0] ? c->col.unit_label : "";
		char pu[96];

		ssc_psd_unit(c, c->s.scaling, pu, sizeof(pu));
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
			char ru[64];

			snprintf(ru, sizeof(ru), "rms%s%s%s", u[0] ? " (" : "", u, u[0] ? ")" : "");
			/* standard bands narrower than a bin are not resolved */
			if (R->bands.nominal && R->bands.b[0].lo_hz > 2 * c->s.bin_hz)
				fprintf(f, "    (bands below %s Hz left out: narrower than the resolution, %s Hz; %s resolves them)\n",
					ssc_fmt(a, sizeof(a), R->bands.b[0].lo_hz, 4),
					ssc_fmt(b, sizeof(b), c->s.bin_hz, 4),
					/* segments as long as the record: only more
					 * record narrows the bins */
					c->s.n_segments <= 1 ? "a longer record" : "a longer --nperseg");
			fprintf(f, "    %-12s %-12s %-12s %s\n", "band lo (Hz)",
				R->bands.nominal ? "centre (Hz)" : "centre (geo, Hz)",
				"hi (Hz)", ru);
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

static void csv_run(FILE *f, const struct ssc_psd_run *R)
{
	fprintf(f, "frequency_hz");
	for (size_t k = 0; k < R->nch; k++) {
		char pu[96];

		ssc_psd_unit(&R->ch[k], R->ch[k].s.scaling, pu, sizeof(pu));
		fprintf(f, ",%s [%s]", R->ch[k].col.name, pu);
	}
	fputc('\n', f);
	if (!R->nch)
		return;
	for (size_t i = 0; i < R->ch[0].s.n_bins; i++) {
		fprintf(f, "%.17g", R->ch[0].s.freq_hz[i]);
		for (size_t k = 0; k < R->nch; k++) {
			double sc = ssc_psd_uscale(&R->ch[k]);

			fprintf(f, ",%.17g", R->ch[k].s.value[i] / (sc * sc));
		}
		fputc('\n', f);
	}
}

static int plot_fig(const struct ssc_common *co, const void *opts,
		    const void *result, const char *path)
{
	const struct ssc_psd_run *R = result;
	size_t nch = R->nch < 6 ? R->nch : 6;
	const struct ssc_psd_chan *c0 = &R->ch[0];
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
		const struct ssc_psd_chan *c = &R->ch[k];
		struct ssc_style st = { .color = ssc_plot_color(k), .width = 1.3 };
		struct ssc_style mk = { .color = ssc_plot_color(k), .width = -1,
					.marker = SSC_MK_CIRCLE, .marker_size = 7 };
		double sc2 = ssc_psd_uscale(c) * ssc_psd_uscale(c);

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
	ssc_psd_unit(c0, c0->s.scaling, pu, sizeof(pu));
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
		double *z, zlo = INFINITY, zhi = 0, sc2 = ssc_psd_uscale(c0) * ssc_psd_uscale(c0);
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
	const struct ssc_psd_run *R = result;

	return R->nch ? plot_fig(co, opts, result, path) : SSC_EXIT_OK;
}

static void init(void *opts)
{
	struct ssc_psd_args *a = opts;

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
	struct ssc_psd_args *a = opts;

	if (a->po.nfft && a->po.nfft < a->po.nperseg)
		return ssc_usage_error(co->cmd, "--nfft %zu is shorter than --nperseg %zu",
				       a->po.nfft, a->po.nperseg);
	/* (a periodogram's segment is the record: checked when it is read) */
	if (!a->periodogram &&
	    a->po.nfft > (size_t)SSCOPE_PSD_MAX_PAD * (a->po.nperseg ? a->po.nperseg : 256))
		return ssc_usage_error(co->cmd, "--nfft %zu is more than %d times --nperseg %zu: zero padding beyond that only interpolates the spectrum",
				       a->po.nfft, SSCOPE_PSD_MAX_PAD,
				       a->po.nperseg ? a->po.nperseg : (size_t)256);
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

/* Welch's estimate streams the file when the command reads it itself;
 * the periodogram needs the whole record. */
static bool streams(const void *opts)
{
	return !((const struct ssc_psd_args *)opts)->periodogram;
}

static void free_result(void *result)
{
	ssc_psd_run_free(result);
	free(result);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	struct ssc_psd_run *R = calloc(1, sizeof(*R));

	if (!R) {
		ssc_err(env->co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = R;
	R->a = *(struct ssc_psd_args *)opts;
	if (env->n_caps != 1) {
		ssc_err(env->co->cmd, "one input capture at a time");
		return SSC_EXIT_USAGE;
	}
	R->path = env->paths[0];
	return ssc_psd_compute(env->co, R, env->caps ? env->caps[0] : NULL);
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
	return ssc_psd_json(result);
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct ssc_psd_run *R = result;

	(void)opts;
	for (size_t k = 0; k < R->nch; k++) {
		const struct ssc_psd_chan *c = &R->ch[k];
		const char *u = c->col.unit_label;

		ssc_summary_add(rows, c->col.name, "RMS (PSD integral)",
				c->s.rms / ssc_psd_uscale(c), NAN, NAN, u, NULL);
		if (c->n_peaks) {
			char note[96];

			snprintf(note, sizeof(note), "amplitude %.4g %s, %.3g x the noise floor",
				 c->peaks[0].peak.amplitude / ssc_psd_uscale(c), u,
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
	.opts_size = sizeof(struct ssc_psd_args),
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
