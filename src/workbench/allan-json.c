/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The "points" array of an allan channel's JSON written as text, byte for
 * byte what jansson dumps of the tree (ssc_json_real_text), without the
 * tree: on an all-tau grid the tree costs more than the analysis.  A long
 * grid has its later half formatted on a second thread while the first
 * half is written.  Also the adequacy object of a channel, and the whole
 * result's JSON (ssc_allan_json()) with the words the command's text
 * shares with it (why a term is absent, the fit's warnings, ...); the
 * result is read back by ssc_nav_terms_from_allan() (navcommon.c).
 */
#include "workbench.h"
#include "results.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

const char *ssc_allan_noise_name(int alpha)
{
	static const char *const n[] = { "RWHM", "FWHM", "RWFM", "FFM", "WFM",
					 "FPM", "WPM" };

	return alpha >= -4 && alpha <= 2 ? n[alpha + 4] : "?";
}

/* append key (a literal) and a value's JSON text at *p */
#define PUT_KEY(p, key) (memcpy(p, key, sizeof(key) - 1), p += sizeof(key) - 1)

static char *put_real(char *p, double v)
{
	return p + ssc_json_real_text(p, v);
}

static char *put_int(char *p, long long v)
{
	char t[24];
	int n = 0;
	unsigned long long a = v < 0 ? 0 - (unsigned long long)v :
				       (unsigned long long)v;

	if (v < 0)
		*p++ = '-';
	do {
		t[n++] = (char)('0' + a % 10);
		a /= 10;
	} while (a);
	while (n)
		*p++ = t[--n];
	return p;
}

/* the JSON text of one point (a leading comma unless first) into line,
 * at most POINT_LINE_MAX bytes; returns its length */
#define POINT_LINE_MAX 512 /* 9 numbers of at most 24 characters, keys, a name */
static size_t point_line(char *line, const struct sscope_allan_point *pt,
			 enum sscope_allan_dev dev, double sc, bool first)
{
	const char *nn = ssc_allan_noise_name(pt->alpha);
	char *p = line;

	if (!first)
		*p++ = ',';
	PUT_KEY(p, "{\"tau_s\":");
	p = put_real(p, pt->tau_s);
	PUT_KEY(p, ",\"m\":");
	p = put_int(p, (long long)pt->m);
	PUT_KEY(p, ",\"terms\":");
	p = put_int(p, (long long)pt->terms);
	PUT_KEY(p, ",\"dev\":");
	p = put_real(p, pt->dev / sc);
	PUT_KEY(p, ",\"dev_lo\":");
	p = put_real(p, pt->dev_lo / sc);
	PUT_KEY(p, ",\"dev_hi\":");
	p = put_real(p, pt->dev_hi / sc);
	PUT_KEY(p, ",\"edf\":");
	p = put_real(p, pt->edf);
	if (!sscope_allan_dev_has_ci(dev)) {
		/* MTIE, TIE rms: no noise type, no interval */
		PUT_KEY(p, ",\"alpha\":null,\"noise\":null");
	} else {
		PUT_KEY(p, ",\"alpha\":");
		p = put_int(p, pt->alpha);
		PUT_KEY(p, ",\"noise\":\"");
		memcpy(p, nn, strlen(nn));
		p += strlen(nn);
		*p++ = '"';
	}
	if (pt->skipped) {
		PUT_KEY(p, ",\"skipped\":");
		p = put_int(p, (long long)pt->skipped);
	}
	if (pt->stride != 1 && dev != SSCOPE_ALLAN_DEV_ADEV &&
	    dev != SSCOPE_ALLAN_DEV_HDEV) {
		PUT_KEY(p, ",\"stride\":");
		p = put_int(p, (long long)pt->stride);
		PUT_KEY(p, ",\"edf_full\":");
		p = put_real(p, pt->edf_full);
	}
	*p++ = '}';
	return (size_t)(p - line);
}

/* points [lo, hi) of a channel formatted into one buffer (the later half
 * of a long grid, on a second thread while the first half is written) */
struct points_part {
	const struct sscope_allan_point *pts;
	enum sscope_allan_dev dev;
	double sc;
	size_t lo, hi;
	char *buf; /* (hi - lo) * POINT_LINE_MAX bytes */
	size_t len;
	pthread_t tid;
};

static void *points_part_run(void *arg)
{
	struct points_part *pp = arg;
	char *p = pp->buf;

	for (size_t i = pp->lo; i < pp->hi; i++)
		p += point_line(p, &pp->pts[i], pp->dev, pp->sc, i == 0);
	pp->len = (size_t)(p - pp->buf);
	return NULL;
}

/* grids from this many points split their text in two halves */
#define POINTS_SPLIT 2048

bool ssc_allan_points_text(FILE *f, const struct sscope_allan_point *pts,
			   size_t n, double dev_scale,
			   enum sscope_allan_dev dev, bool two_threads)
{
	struct points_part pp = { 0 };
	bool ok, split = false;
	size_t upto = n, cap = 0;

	if (n >= POINTS_SPLIT && two_threads) {
		pp.pts = pts;
		pp.dev = dev;
		pp.sc = dev_scale;
		pp.lo = n / 2;
		pp.hi = n;
		/* the pages the second half needs at the middle point's line
		 * length (and an eighth more) mapped in one call before the
		 * writing starts, the rest up to the longest line's on
		 * demand: faulted one by one while the first half goes into
		 * a pipe they cost a virtual machine's page tables several
		 * times the formatting (an all-tau grid of 90,000 taus into
		 * `| cat`: 2.0 s against 0.2 s) */
		char probe[POINT_LINE_MAX];
		size_t est = point_line(probe, &pts[n / 2], dev, dev_scale, false);

		cap = (pp.hi - pp.lo) * POINT_LINE_MAX;
		pp.buf = mmap(NULL, cap, PROT_READ | PROT_WRITE,
			      MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
		if (pp.buf == MAP_FAILED)
			pp.buf = NULL;
#ifdef MADV_POPULATE_WRITE
		if (pp.buf)
			(void)madvise(pp.buf, (pp.hi - pp.lo) * (est + est / 8),
				      MADV_POPULATE_WRITE);
#endif
		if (pp.buf && pthread_create(&pp.tid, NULL, points_part_run, &pp) == 0) {
			split = true;
			upto = pp.lo;
		}
	}
	ok = fputc('[', f) != EOF;
	for (size_t i = 0; ok && i < upto; i++) {
		char line[POINT_LINE_MAX];
		size_t len = point_line(line, &pts[i], dev, dev_scale, i == 0);

		ok = fwrite(line, 1, len, f) == len;
	}
	if (split) {
		pthread_join(pp.tid, NULL);
		ok = ok && fwrite(pp.buf, 1, pp.len, f) == pp.len;
	}
	if (pp.buf)
		munmap(pp.buf, cap);
	return ok && fputc(']', f) != EOF;
}

/* ------------------------------------------------------------------ */

static json_t *term_list(unsigned mask)
{
	json_t *a = json_array();

	for (int t = 0; t < 5; t++)
		if ((mask >> t) & 1)
			json_array_append_new(a, json_stringn(&"QNBKR"[t], 1));
	return a;
}

json_t *ssc_adequacy_json(const struct sscope_adequacy *q, const char *rate_unit)
{
	const struct sscope_adequacy_davar *d = &q->davar;
	json_t *o = json_object(), *fs = json_array();
	struct sscope_unit u;
	double sc = sscope_unit_parse(rate_unit, &u, NULL) ? (double)NAN : u.scale;

	json_object_set_new(o, "verdict", json_string(
		q->verdict == SSCOPE_ADEQUACY_INVALID ? "not_valid" :
		q->verdict == SSCOPE_ADEQUACY_DOUBT ? "doubtful" :
		q->verdict == SSCOPE_ADEQUACY_BOUND ? "bounds" : "valid"));
	json_object_set_new(o, "still", q->still_tested ? json_boolean(q->still) :
							  json_null());
	json_object_set_new(o, "contrast", ssc_jreal(q->contrast));
	json_object_set_new(o, "max_contrast", json_real(q->max_contrast));
	json_object_set_new(o, "fit_rejected", q->have_fit ?
				json_boolean(q->fit_rejected) : json_null());
	json_object_set_new(o, "fit_p_value", ssc_jreal(q->fit_p_value));
	json_object_set_new(o, "fit_p_value_bound",
			    json_boolean(sscope_noise_p_is_bound(q->fit_p_value)));
	json_object_set_new(o, "stationary", q->stationarity_tested ?
				json_boolean(q->stationary) : json_null());
	json_object_set_new(o, "requested", term_list(q->requested));
	json_object_set_new(o, "established", term_list(q->established));
	json_object_set_new(o, "doubtful", term_list(q->doubtful));
	for (size_t i = 0; i < q->n_findings; i++) {
		const struct sscope_adequacy_finding *f = &q->findings[i];
		json_t *j = json_object();

		json_object_set_new(j, "cause",
				    json_string(sscope_adequacy_cause_name(f->cause)));
		json_object_set_new(j, "severity",
				    json_string(sscope_adequacy_severity_name(f->severity)));
		json_object_set_new(j, "terms", term_list(f->terms));
		json_object_set_new(j, "t_start_s", ssc_jreal(f->t_start_s));
		json_object_set_new(j, "t_end_s", ssc_jreal(f->t_end_s));
		json_object_set_new(j, "tau_min_s", ssc_jreal(f->tau_min_s));
		json_object_set_new(j, "tau_max_s", ssc_jreal(f->tau_max_s));
		json_object_set_new(j, "statistic", ssc_jreal(f->statistic));
		json_object_set_new(j, "p_value", ssc_jreal(f->p_value));
		json_object_set_new(j, "action_s", ssc_jreal(f->action_s));
		json_object_set_new(j, "message", json_string(f->message));
		json_array_append_new(fs, j);
	}
	json_object_set_new(o, "findings", fs);
	if (d->n_win) {
		json_t *dv = json_object(), *ts = json_array(), *tau = json_array();
		json_t *dev = json_array(), *model = json_array();

		json_object_set_new(dv, "deviation", json_string("oadev"));
		json_object_set_new(dv, "unit", json_string(rate_unit));
		json_object_set_new(dv, "window_s", json_real(d->window_s));
		json_object_set_new(dv, "step_s", json_real(d->step_s));
		for (size_t i = 0; i < d->n_win; i++)
			json_array_append_new(ts, json_real(d->t_s[i]));
		for (size_t j = 0; j < d->n_tau; j++) {
			json_array_append_new(tau, json_real(d->tau_s[j]));
			json_array_append_new(model, ssc_jreal(d->model[j] / sc));
		}
		for (size_t i = 0; i < d->n_win; i++) {
			json_t *row = json_array();

			for (size_t j = 0; j < d->n_tau; j++)
				json_array_append_new(row, ssc_jreal(d->dev[i * d->n_tau + j] / sc));
			json_array_append_new(dev, row);
		}
		json_object_set_new(dv, "t_s", ts);
		json_object_set_new(dv, "tau_s", tau);
		json_object_set_new(dv, "dev", dev);
		json_object_set_new(dv, "model", model);
		json_object_set_new(o, "davar", dv);
	}
	return o;
}

/* ------------------------------------------------------------------ */
/* The result's JSON                                                   */
/* ------------------------------------------------------------------ */

/* the fit is rejected below SSC_ALLAN_FIT_REJECT_P (results.h) */
bool ssc_allan_fit_rejected(const struct sscope_noise_fit *ft)
{
	return sscope_noise_fit_rejected(ft, SSC_ALLAN_FIT_REJECT_P);
}

/* why a term is not reported present, in words (NULL when present) */
const char *ssc_allan_absent_reason(const struct sscope_noise_coef *cf)
{
	switch (cf->why) {
	case SSCOPE_NOISE_PRESENT:
		return NULL;
	case SSCOPE_NOISE_NOT_ALLOWED:
		return "not among the terms allowed (--terms)";
	case SSCOPE_NOISE_NOT_SEPARABLE:
		return "the test keeps it, but with every term free it trades off with the others: not separable on this record";
	default:
		return "the fit without it describes the curve (presence test not passed)";
	}
}

/* why a read-off is not given */
const char *ssc_allan_readoff_absent(const struct sscope_noise_fit *ft, int t)
{
	if (!ft->coef[t].present)
		return "none (the term is not present)";
	return "none (it is not surely 3/4 of the model at any tau with EDF >= 10)";
}

/* the presence test, in words, with its level */
const char *ssc_allan_select_words(const struct sscope_noise_fit *ft, char *buf,
				   size_t len)
{
	snprintf(buf, len,
		 "present by stepwise likelihood-ratio tests of nested generalised-least-squares fits, one-sided at %.3g %% (%.3g sd of the estimate without the term, raised for the skew of the long-tau points)",
		 100 * 0.5 * erfc(ft->select_z / sqrt(2.0)), ft->select_z);
	return buf;
}

/* value (SI) in unit; NaN stays NaN */
double ssc_allan_in_unit(double si, const char *si_unit, const char *unit)
{
	double v;

	if (!isfinite(si))
		return si;
	if (sscope_unit_convert_text(si, si_unit, unit, &v))
		return NAN;
	return v;
}

/* why the noise fit failed */
const char *ssc_allan_fit_msg(const struct ssc_allan_chan *c)
{
	return c->res->fit_diag.msg[0] ? c->res->fit_diag.msg :
					 sscope_strerror(c->res->fit_error);
}

/* the first finding of severity doubt or invalid concerning term t */
const struct sscope_adequacy_finding *
ssc_allan_term_doubt(const struct ssc_allan_chan *c, int t)
{
	for (size_t i = 0; c->adq && i < c->adq->n_findings; i++) {
		const struct sscope_adequacy_finding *f = &c->adq->findings[i];

		if (f->severity >= SSCOPE_ADEQUACY_DOUBT && ((f->terms >> t) & 1))
			return f;
	}
	return NULL;
}

size_t ssc_allan_chan_warnings(const struct ssc_allan_json_opts *a,
			       const struct ssc_allan_chan *c,
			       struct ssc_allan_warn *w, size_t max)
{
	const struct sscope_noise_fit *ft = &c->res->fit;
	const struct ssc_allan_units *u = &c->u;
	char b1[32], b2[32], b3[32];
	bool resolved = false;
	size_t n = 0;

	if (a->no_fit)
		return 0;
	if (!c->res->have_fit) {
		/* too short a record, too few points: said, not hidden */
		if (max) {
			w[0].code = "fit_failed";
			snprintf(w[0].msg, sizeof(w[0].msg),
				 "%s: no noise terms: %s", c->col->name,
				 c->res->fit_diag.msg[0] || c->res->fit_error ?
				 ssc_allan_fit_msg(c) : "the fit failed");
			return 1;
		}
		return 0;
	}
	if (ssc_allan_fit_rejected(ft) && n < max) {
		w[n].code = "fit_rejected";
		snprintf(w[n].msg, sizeof(w[n].msg),
			 "%s: fit rejected: chi2 %s for %s dof, bootstrap p %s, below %g: the five-term noise model does not describe this record (a deterministic trend such as a temperature effect, or a process outside the model); read the terms as indicative only",
			 c->col->name, ssc_fmt(b1, sizeof(b1), ft->chi2, 3),
			 ssc_fmt(b2, sizeof(b2), ft->dof, 3),
			 ssc_fmt_p(b3, sizeof(b3), ft->p_value), SSC_ALLAN_FIT_REJECT_P);
		n++;
	}
	for (int t = 0; t < 5 && n < max; t++) {
		const struct sscope_noise_coef *cf = &ft->coef[t];

		if (!cf->fitted || sscope_noise_coef_resolved(cf))
			continue;
		w[n].code = "term_unresolved";
		snprintf(w[n].msg, sizeof(w[n].msg),
			 "%s: %c present, but its %s %% interval [0, %s] %s reaches zero: the record shows it, it does not measure it",
			 c->col->name, "QNBKR"[t],
			 ssc_fmt(b1, sizeof(b1), 100 * ft->ci_level, 3),
			 ssc_fmt(b2, sizeof(b2), ssc_allan_in_unit(cf->hi, u->term_si[t], u->term[t]), 3),
			 u->term[t]);
		n++;
	}
	/* nothing resolved: the record is too short to measure a term */
	for (int t = 0; t < 5; t++)
		resolved |= sscope_noise_coef_resolved(&ft->coef[t]);
	if (n < max && !resolved) {
		w[n].code = "too_few_samples";
		snprintf(w[n].msg, sizeof(w[n].msg),
			 "%s: no noise term present with an interval clear of zero: %zu samples are too few to measure any; the record only bounds them",
			 c->col->name, c->n);
		n++;
	}
	return n;
}

static json_t *jval(double si, const char *si_unit, const char *unit)
{
	json_t *o = json_object();

	json_object_set_new(o, "value", ssc_jreal(ssc_allan_in_unit(si, si_unit, unit)));
	json_object_set_new(o, "unit", json_string(unit));
	json_object_set_new(o, "si", ssc_jreal(si));
	json_object_set_new(o, "si_unit", json_string(si_unit));
	return o;
}

/* A channel's JSON; its "points" are @p slot when given (a placeholder
 * ssc_allan_json_points() fills in). */
static json_t *json_chan(const struct ssc_allan_json_opts *a,
			 const struct ssc_allan_file *fr,
			 const struct ssc_allan_chan *c, json_t *slot)
{
	const struct sscope_allan_result *r = c->res;
	const struct ssc_allan_units *u = &c->u;
	json_t *o = json_object(), *pts = slot ? slot : json_array();

	json_object_set_new(o, "name", json_string(c->col->name));
	json_object_set_new(o, "unit", json_string(c->col->unit_label));
	json_object_set_new(o, "quantity",
			    json_string(sscope_quantity_name(c->col->quantity)));
	json_object_set_new(o, "rate_hz", json_real(fr->cap->rate_hz));
	json_object_set_new(o, "samples", json_integer((json_int_t)c->n));
	json_object_set_new(o, "nan", json_integer((json_int_t)c->nan));
	json_object_set_new(o, "input", json_string(a->input == SSCOPE_ALLAN_ANGLE ?
							   "angle" : "rate"));
	json_object_set_new(o, "deviation", json_string(sscope_allan_dev_name(a->dev)));
	json_object_set_new(o, "deviation_label",
			    json_string(sscope_allan_dev_label(a->dev)));
	json_object_set_new(o, "dev_unit", json_string(u->dev));
	json_object_set_new(o, "ci_level", a->ci < 0 ? json_null() :
					   json_real(a->ci));
	for (size_t i = 0; !slot && i < r->n_points; i++) {
		const struct sscope_allan_point *p = &r->points[i];
		json_t *q = json_object();

		json_object_set_new(q, "tau_s", json_real(p->tau_s));
		json_object_set_new(q, "m", json_integer((json_int_t)p->m));
		json_object_set_new(q, "terms", json_integer((json_int_t)p->terms));
		json_object_set_new(q, "dev", ssc_jreal(p->dev / u->dev_scale));
		json_object_set_new(q, "dev_lo", ssc_jreal(p->dev_lo / u->dev_scale));
		json_object_set_new(q, "dev_hi", ssc_jreal(p->dev_hi / u->dev_scale));
		json_object_set_new(q, "edf", ssc_jreal(p->edf));
		if (sscope_allan_dev_has_ci(a->dev)) {
			json_object_set_new(q, "alpha", json_integer(p->alpha));
			json_object_set_new(q, "noise",
					    json_string(ssc_allan_noise_name(p->alpha)));
		} else {
			json_object_set_new(q, "alpha", json_null());
			json_object_set_new(q, "noise", json_null());
		}
		if (p->skipped)
			json_object_set_new(q, "skipped",
					    json_integer((json_int_t)p->skipped));
		if (p->stride != 1 && a->dev != SSCOPE_ALLAN_DEV_ADEV &&
		    a->dev != SSCOPE_ALLAN_DEV_HDEV) {
			json_object_set_new(q, "stride",
					    json_integer((json_int_t)p->stride));
			json_object_set_new(q, "edf_full", ssc_jreal(p->edf_full));
		}
		json_array_append_new(pts, q);
	}
	json_object_set_new(o, "points", pts);
	if (r->n_gap_omitted) {
		json_object_set_new(o, "gap_omitted_taus",
				    json_integer((json_int_t)r->n_gap_omitted));
		ssc_json_warn(o, "gap_taus_omitted", "%s: %s", c->col->name,
			      r->gap_note.msg);
	}
	if (a->no_fit)
		return o;
	{
		json_t *nz = json_object(), *fit = json_object(), *terms = json_array();
		const struct sscope_noise_fit *ft = &r->fit;
		static const char *const key[5] = { "Q", "N", "B", "K", "R" };

		for (int t = 0; t < 5; t++) {
			struct sscope_noise_coef cf_k = ft->coef[t];
			const struct sscope_noise_coef *cf = &cf_k;
			json_t *jc;

			/* no fit: every number unknown (null), not 0 */
			if (!r->have_fit)
				cf_k.value = cf_k.lo = cf_k.hi = cf_k.z =
					cf_k.estimate = (double)NAN;
			jc = ssc_json_coef(cf->value, cf->lo, cf->hi, u->term[t],
					   u->term_si[t], cf->fitted);

			json_object_set_new(jc, "resolved",
					    json_boolean(sscope_noise_coef_resolved(cf)));
			json_object_set_new(jc, "present", json_boolean(cf->present));
			json_object_set_new(jc, "reason", cf->present ? json_null() :
					    json_string(ssc_allan_absent_reason(cf)));
			json_object_set_new(jc, "test_z", ssc_jreal(cf->z));
			if (!cf->present && cf->why != SSCOPE_NOISE_NOT_ALLOWED)
				json_object_set_new(jc, "bound",
						    isfinite(cf->hi) && cf->hi > 0 ?
						    ssc_jreal(ssc_allan_in_unit(cf->hi, u->term_si[t], u->term[t])) :
						    json_null());
			/* the unconstrained point estimate, resolved or not:
			 * what a prediction (walk, navsim, heading) uses */
			{
				double ev;

				json_object_set_new(jc, "si_estimate",
						    ssc_jreal(cf->estimate));
				if (sscope_unit_convert_text(cf->estimate, u->term_si[t],
							     u->term[t], &ev))
					ev = cf->estimate;
				json_object_set_new(jc, "estimate", ssc_jreal(ev));
			}
			{
				const struct sscope_adequacy_finding *fd = ssc_allan_term_doubt(c, t);

				json_object_set_new(jc, "doubtful", json_boolean(fd != NULL));
				if (fd)
					json_object_set_new(jc, "doubt",
							    json_string(fd->message));
			}
			json_object_set_new(nz, key[t], jc);
			if (cf->fitted)
				json_array_append_new(terms, json_string(key[t]));
		}
		json_object_set_new(o, "noise", nz);
		if (r->have_fit) {
			json_object_set_new(fit, "terms", terms);
			json_object_set_new(fit, "method",
					    json_string("weighted least squares of every allowed term on OADEV (EDF weights); which terms are present is decided by stepwise likelihood-ratio tests of nested generalised-least-squares fits (see selection); intervals and 'below' bounds are Neyman intervals from a parametric bootstrap of the fit of every allowed term under the fitted model (1000 replicates), one-sided for a value the test would seldom detect, central for one it detects"));
			{
				json_t *sj = json_object();
				char sw[320];

				json_object_set_new(sj, "test", json_string(ssc_allan_select_words(ft, sw, sizeof(sw))));
				json_object_set_new(sj, "level", json_real(0.5 * erfc(ft->select_z / sqrt(2.0))));
				json_object_set_new(sj, "z", json_real(ft->select_z));
				json_object_set_new(fit, "selection", sj);
			}
			json_object_set_new(fit, "ci_level", json_real(ft->ci_level));
			json_object_set_new(fit, "points", json_integer((json_int_t)ft->n_points));
			json_object_set_new(fit, "chi2", ssc_jreal(ft->chi2));
			json_object_set_new(fit, "dof", ssc_jreal(ft->dof));
			json_object_set_new(fit, "p_value", ssc_jreal(ft->p_value));
			/* at the bootstrap's floor p is only known to be below */
			json_object_set_new(fit, "p_value_bound",
					    json_boolean(sscope_noise_p_is_bound(ft->p_value)));
			json_object_set_new(fit, "rejected",
					    json_boolean(ssc_allan_fit_rejected(ft)));
			json_object_set_new(fit, "reject_below_p",
					    json_real(SSC_ALLAN_FIT_REJECT_P));
			json_object_set_new(fit, "model_error",
					    json_real(a->model_error > 0 ? a->model_error : 0));
		} else {
			json_decref(terms);
			json_object_set_new(fit, "error", json_string(ssc_allan_fit_msg(c)));
		}
		json_object_set_new(o, "fit", fit);
		{
			json_t *ro = json_object();

			json_object_set_new(ro, "N", jval(ft->readoff.n, u->term_si[1], u->term[1]));
			json_object_set_new(ro, "B", jval(ft->readoff.b, u->term_si[2], u->term[2]));
			json_object_set_new(ro, "B_tau_s", ssc_jreal(ft->readoff.b_tau_s));
			json_object_set_new(ro, "N_tau_s", ssc_jreal(ft->readoff.n_tau_s));
			json_object_set_new(ro, "K", jval(ft->readoff.k, u->term_si[3], u->term[3]));
			json_object_set_new(ro, "K_tau_s", ssc_jreal(ft->readoff.k_tau_s));
			json_object_set_new(ro, "rule", json_string("a present term only, at a tau where it is at least 3/4 of the fitted model (its square at its lower bound, the others at their upper bounds) and the EDF is at least 10 (null otherwise)"));
			if (!isfinite(ft->readoff.n))
				json_object_set_new(json_object_get(ro, "N"), "reason", json_string(ssc_allan_readoff_absent(ft, 1)));
			if (!isfinite(ft->readoff.b))
				json_object_set_new(json_object_get(ro, "B"), "reason", json_string(ssc_allan_readoff_absent(ft, 2)));
			if (!isfinite(ft->readoff.k))
				json_object_set_new(json_object_get(ro, "K"), "reason", json_string(ssc_allan_readoff_absent(ft, 3)));
			json_object_set_new(o, "readoff", ro);
		}
		{
			struct ssc_allan_warn w[7];
			size_t nw = ssc_allan_chan_warnings(a, c, w, 7);

			for (size_t i = 0; i < nw; i++)
				ssc_json_warn(o, w[i].code, "%s", w[i].msg);
		}
		for (size_t i = 0; c->adq && i < c->adq->n_findings; i++) {
			const struct sscope_adequacy_finding *f = &c->adq->findings[i];
			char code[48];

			/* the fit's own warnings say rejected and failed */
			if (f->severity < SSCOPE_ADEQUACY_DOUBT ||
			    f->cause == SSCOPE_ADEQUACY_FIT_REJECTED ||
			    f->cause == SSCOPE_ADEQUACY_NO_FIT)
				continue;
			snprintf(code, sizeof(code), "adequacy_%s",
				 sscope_adequacy_cause_name(f->cause));
			ssc_json_warn(o, code, "%s: %s", c->col->name, f->message);
		}
		if (c->adq)
			json_object_set_new(o, "adequacy", ssc_adequacy_json(c->adq, c->u.rate));
	}
	return o;
}

/* slot: the next slot number when the points are slots, else NULL */
static json_t *json_file(const struct ssc_allan_json_opts *a,
			 const struct ssc_allan_file *fr, size_t *slot)
{
	json_t *o = json_object(), *chs = json_array();

	json_object_set_new(o, "command", json_string("allan"));
	json_object_set_new(o, "file", json_string(fr->path));
	for (size_t k = 0; k < fr->n_ch; k++)
		json_array_append_new(chs, json_chan(a, fr, &fr->ch[k],
						     slot ? ssc_json_slot((*slot)++) :
							    NULL));
	json_object_set_new(o, "channels", chs);
	return o;
}

json_t *ssc_allan_json(const struct ssc_allan_json_opts *o,
		       const struct ssc_allan_res *R, size_t *slot)
{
	json_t *root, *files;

	if (R->n_files == 1)
		return json_file(o, &R->fr[0], slot);
	root = json_object();
	files = json_array();
	json_object_set_new(root, "command", json_string("allan"));
	for (size_t i = 0; i < R->n_files; i++)
		json_array_append_new(files, json_file(o, &R->fr[i], slot));
	json_object_set_new(root, "files", files);
	return root;
}

bool ssc_allan_json_points(FILE *f, const struct ssc_allan_json_opts *o,
			   const struct ssc_allan_res *R, size_t slot)
{
	const struct ssc_allan_chan *c = NULL;

	/* slots number the channels of the files in order */
	for (size_t i = 0; i < R->n_files && !c; i++) {
		if (slot < R->fr[i].n_ch)
			c = &R->fr[i].ch[slot];
		else
			slot -= R->fr[i].n_ch;
	}
	if (!c)
		return false;
	return ssc_allan_points_text(f, c->res->points, c->res->n_points,
				     c->u.dev_scale, o->dev, o->two_threads);
}
