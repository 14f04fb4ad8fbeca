/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope psd, the analysis: Welch estimates stream the capture
 * through the chunked reader (a prefetch thread), so memory does not grow
 * with the record; the periodogram and a scene's loaded capture are
 * estimated in memory.  Then the peaks (with their significance), the band
 * RMS and the JSON of the result.
 */
#include "workbench.h"
#include "psd.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "prefetch.h"



/* Parse --bands once the spectrum (its rate and bins) is known. */
static int make_bands(const char *cmd, const char *arg, double fs,
		      const struct sscope_psd_spectrum *sp, struct ssc_psd_bandset *bs)
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



double ssc_psd_uscale(const struct ssc_psd_chan *c)
{
	return c->col.unit.scale != 0 ? c->col.unit.scale : 1;
}

void ssc_psd_unit(const struct ssc_psd_chan *c, enum sscope_psd_scaling sc, char *buf,
		     size_t len)
{
	const char *u = c->col.unit_label;

	if (!u || !*u)
		snprintf(buf, len, "%s", sc == SSCOPE_PSD_SCALING_DENSITY ? "1/Hz" : "1");
	else
		snprintf(buf, len, "(%s)^2%s", u,
			 sc == SSCOPE_PSD_SCALING_DENSITY ? "/Hz" : "");
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
static int check_shown(const struct ssc_common *co, const struct ssc_psd_run *R,
		       const struct ssc_psd_chan *c)
{
	double vmax = 0, u = ssc_psd_uscale(c);

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
static int stream(const struct ssc_common *co, struct ssc_psd_run *R)
{
	struct sscope_reader_opts ro;
	struct sscope_reader *rd = NULL;
	struct sscope_diag d = { "" };
	struct ssc_prefetch *pf = NULL;
	const struct sscope_reader_chunk *cur;
	struct ssc_read_progress pc;
	const size_t cap = 65536;
	struct sscope_timing_stream *ts = NULL;
	struct sscope_timing tm;
	bool use_time, disorder = false, have_result = false;
	int rc, ex = SSC_EXIT_FAIL;

	ssc_read_opts(co, &ro);
	ssc_read_progress_on(co, R->path, &pc, &ro);
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
		ssc_err_no_rate(co->cmd, R->path,
				sscope_reader_header_rate_note(rd));
		goto out;
	}
	for (size_t k = 0; k < R->nch; k++) {
		struct ssc_psd_chan *c = &R->ch[k];

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
static int from_capture(const struct ssc_common *co, struct ssc_psd_run *R,
			const struct sscope_capture *cap)
{
	int rc;

	rc = ssc_time_check(co, R->path, cap, true);
	if (rc)
		return rc;
	if (!(cap->rate_hz > 0))
		return ssc_err_no_rate(co->cmd, R->path, cap->rate_note);
	R->fs = cap->rate_hz;
	R->rate_source = rate_source_name(cap);
	R->rows = cap->n;
	/* gaps, unless the stamps are out of order (said above) */
	R->time_gaps = ssc_time_gaps(cap);
	R->nch = cap->n_channels;
	R->ch = calloc(R->nch ? R->nch : 1, sizeof(*R->ch));
	if (!R->ch)
		return SSC_EXIT_FAIL;
	for (size_t k = 0; k < R->nch; k++) {
		struct ssc_psd_chan *c = &R->ch[k];

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

static void finish(struct ssc_psd_run *R)
{
	for (size_t k = 0; k < R->nch; k++) {
		struct ssc_psd_chan *c = &R->ch[k];
		double sc = ssc_psd_uscale(c);

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

void ssc_psd_run_free(struct ssc_psd_run *R)
{
	for (size_t k = 0; R->ch && k < R->nch; k++) {
		struct ssc_psd_chan *c = &R->ch[k];

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


const char *ssc_psd_detrend_name(enum sscope_psd_detrend d)
{
	return d == SSCOPE_PSD_DETREND_CONSTANT ? "constant" :
	       d == SSCOPE_PSD_DETREND_LINEAR   ? "linear" :
					      "none";
}

const char *ssc_psd_scaling_name(enum sscope_psd_scaling s)
{
	return s == SSCOPE_PSD_SCALING_DENSITY ? "density" : "spectrum";
}

/* why a spectrum is zero: its segments fitted exactly by the detrending,
 * or a signal that is zero once detrended */
static const char *zero_why(const struct sscope_psd_spectrum *s, char *buf,
			    size_t len)
{
	if (s->nperseg <= (s->detrend == SSCOPE_PSD_DETREND_LINEAR ? 2u :
			   s->detrend == SSCOPE_PSD_DETREND_CONSTANT ? 1u : 0u))
		snprintf(buf, len, "segments of %zu sample%s are zero once their %s is removed: the spectrum is zero (give a longer --nperseg)",
			 s->nperseg, s->nperseg == 1 ? "" : "s",
			 s->detrend == SSCOPE_PSD_DETREND_LINEAR ? "line" : "mean");
	else
		snprintf(buf, len, "the detrended signal is zero (constant input): the spectrum is zero");
	return buf;
}

json_t *ssc_psd_json(const struct ssc_psd_run *R)
{
	json_t *root = json_object(), *chs = json_array();

	json_object_set_new(root, "command", json_string("psd"));
	json_object_set_new(root, "file", json_string(R->path));
	json_object_set_new(root, "method", json_string(R->a.periodogram ? "periodogram" : "welch"));
	json_object_set_new(root, "peak_interpolation",
			    json_string("least-squares fit of the window's exact response to 5 bins; amplitude corrected for window and scalloping"));
	for (size_t k = 0; k < R->nch; k++) {
		const struct ssc_psd_chan *c = &R->ch[k];
		const struct sscope_psd_spectrum *s = &c->s;
		double sc = ssc_psd_uscale(c), sc2 = sc * sc;
		json_t *o = json_object(), *f = json_array(), *p = json_array();
		json_t *pk = json_array(), *w = json_object();
		char pu[96];
		struct sscope_psd_window_figures wf;

		ssc_psd_unit(c, s->scaling, pu, sizeof(pu));
		json_object_set_new(o, "name", json_string(c->col.name));
		json_object_set_new(o, "unit", json_string(c->col.unit_label));
		json_object_set_new(o, "rate_hz", json_real(R->fs));
		json_object_set_new(o, "rate_source", json_string(R->rate_source));
		json_object_set_new(o, "samples", json_integer((json_int_t)s->n_samples));
		json_object_set_new(o, "scaling", json_string(ssc_psd_scaling_name(s->scaling)));
		json_object_set_new(o, "psd_unit", json_string(pu));
		sscope_psd_window_figures(s->window, s->nperseg, &wf);
		json_object_set_new(w, "name", json_string(sscope_psd_window_name(s->window)));
		json_object_set_new(w, "nperseg", json_integer((json_int_t)s->nperseg));
		json_object_set_new(w, "noverlap", json_integer((json_int_t)s->noverlap));
		json_object_set_new(w, "nfft", json_integer((json_int_t)s->nfft));
		json_object_set_new(w, "detrend", json_string(ssc_psd_detrend_name(s->detrend)));
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
	if (R->nch && R->ch[0].s.rms == 0) {
		char why[128];

		ssc_json_warn(root, "zero_spectrum", "%s: %s", R->path,
			      zero_why(&R->ch[0].s, why, sizeof(why)));
	}
	if (R->nch && R->ch[0].s.nperseg < R->a.po.nperseg && !R->a.periodogram)
		ssc_json_warn(root, "too_few_samples",
			      "%s: %llu samples, fewer than one segment of %zu: the spectrum is a single periodogram, each bin with 2 degrees of freedom (its sd equals its value)",
			      R->path, (unsigned long long)R->rows, R->a.po.nperseg);
	return root;
}


/* Everything after the estimate: warnings, peaks, bands. */
static int finish_run(const struct ssc_common *co, struct ssc_psd_run *R)
{
	int rc;

	ssc_warn_time_gaps(co, R->path, R->time_gaps);
	if (R->nch && R->ch[0].s.nperseg < R->a.po.nperseg && !R->a.periodogram)
		ssc_warn(co, "%s: --nperseg %zu is longer than the record (%llu samples): one segment of %zu",
			 R->path, R->a.po.nperseg, (unsigned long long)R->rows,
			 R->ch[0].s.nperseg);
	for (size_t k = 0; k < R->nch; k++)
		if (R->ch[k].s.n_skipped)
			ssc_warn(co, "%s: channel %s: %zu of %zu segments skipped (NaN gaps)",
				 R->path, R->ch[k].col.name, R->ch[k].s.n_skipped,
				 R->ch[k].s.n_skipped + R->ch[k].s.n_segments);
	if (R->nch && R->ch[0].s.rms == 0) {
		char why[128];

		ssc_warn(co, "%s: %s", R->path, zero_why(&R->ch[0].s, why, sizeof(why)));
	}
	rc = make_bands(co->cmd, R->a.bands, R->fs, R->nch ? &R->ch[0].s : NULL,
			&R->bands);
	if (rc)
		return rc;
	finish(R);
	return SSC_EXIT_OK;
}

int ssc_psd_compute(const struct ssc_common *co, struct ssc_psd_run *R,
		    const struct sscope_capture *cap)
{
	int rc = cap ? from_capture(co, R, cap) : stream(co, R);

	return rc ? rc : finish_run(co, R);
}
