/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The "points" array of an allan channel's JSON written as text, byte for
 * byte what jansson dumps of the tree (ssc_json_real_text), without the
 * tree: on an all-tau grid the tree costs more than the analysis.  A long
 * grid has its later half formatted on a second thread while the first
 * half is written.  Also the adequacy object of a channel.
 */
#include "workbench.h"
#include "results.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

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
	size_t upto = n;

	if (n >= POINTS_SPLIT && two_threads) {
		pp.pts = pts;
		pp.dev = dev;
		pp.sc = dev_scale;
		pp.lo = n / 2;
		pp.hi = n;
		pp.buf = malloc((pp.hi - pp.lo) * POINT_LINE_MAX);
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
	free(pp.buf);
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
