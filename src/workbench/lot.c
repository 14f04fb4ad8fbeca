/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The lot stage (see lot.h).  Each unit's channel gets the allan stage's
 * analysis (dense taus, the IEEE 952 fit with its 68.3 % intervals); a
 * term present in a unit enters the lot with the half-width of its
 * interval as its standard error, a term a unit does not show is left out
 * of that term's lot (said in the output: "resolved in k of n units").
 * The spread is sscope_lot_spread() at the stated level.
 */
#include "workbench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lot.h"
#include "navcommon.h"
#include "stage.h"

static const char term_key[3] = { 'N', 'B', 'K' };

static const char *base_of(const char *path)
{
	const char *s = strrchr(path, '/');

	return s ? s + 1 : path;
}

static int unit_fit(const char *cmd, const char *path,
		    const struct sscope_capture_channel *ch, size_t n, double fs,
		    struct sscope_noise_plan *plan, struct ssc_lot_cell *cell)
{
	struct sscope_allan_opts ao = { 0 };
	struct sscope_noise_fit_opts fo = { 0 };
	struct sscope_allan_result *res = NULL;
	struct sscope_diag d = { "" };
	int rc;

	fo.plan = plan;
	rc = sscope_allan_analyze(ch->data, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE, &ao,
				  &fo, &res, &d);
	if (rc) {
		ssc_err(cmd, "%s: channel %s: %s", path, ch->col.name,
			d.msg[0] ? d.msg : sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	for (int t = 0; t < 3; t++) {
		const struct sscope_noise_coef *c = &res->fit.coef[SSCOPE_TERM_N + t];

		cell->present[t] = res->have_fit && c->present && isfinite(c->value) &&
				   isfinite(c->lo) && isfinite(c->hi) && c->hi > c->lo;
		cell->v[t] = cell->present[t] ? c->value : (double)NAN;
		cell->lo[t] = cell->present[t] ? c->lo : (double)NAN;
		cell->hi[t] = cell->present[t] ? c->hi : (double)NAN;
	}
	sscope_allan_result_free(res);
	return 0;
}

static bool noise_channel(enum sscope_quantity q)
{
	return q == SSCOPE_QUANTITY_ANGULAR_RATE || q == SSCOPE_QUANTITY_ACCELERATION;
}

static int spread(const char *cmd, struct ssc_lot_result *r)
{
	size_t U = r->n_units;
	double *y = calloc(U, sizeof(double)), *se = calloc(U, sizeof(double));
	double *z = calloc(U, sizeof(double));
	bool *fl = calloc(U, sizeof(bool));
	size_t *idx = calloc(U, sizeof(size_t));
	int rc = 0;

	if (!y || !se || !z || !fl || !idx) {
		rc = ssc_fail(cmd, -ENOMEM, NULL, NULL);
		goto out;
	}
	for (size_t c = 0; c < r->n_chan && !rc; c++)
		for (int t = 0; t < 3; t++) {
			struct ssc_lot_term *T = &r->term[c * 3 + (size_t)t];
			struct sscope_lot_opts o = { .level = r->level };
			size_t k = 0;

			T->outlier = calloc(U, sizeof(bool));
			T->z = malloc(U * sizeof(double));
			if (!T->outlier || !T->z) {
				rc = ssc_fail(cmd, -ENOMEM, NULL, NULL);
				break;
			}
			for (size_t u = 0; u < U; u++) {
				const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];

				T->z[u] = NAN;
				if (!cl->present[t])
					continue;
				idx[k] = u;
				y[k] = cl->v[t];
				/* a 68.3 % interval: one standard error each side */
				se[k++] = 0.5 * (cl->hi[t] - cl->lo[t]);
			}
			T->n_resolved = k;
			if (k < 3)
				continue;
			if (sscope_lot_spread(y, se, k, &o, &T->sp, z, fl))
				continue;
			T->done = true;
			for (size_t i = 0; i < k; i++) {
				T->outlier[idx[i]] = fl[i];
				T->z[idx[i]] = z[i];
			}
		}
out:
	free(y);
	free(se);
	free(z);
	free(fl);
	free(idx);
	return rc;
}

int ssc_lot_run(const char *cmd, struct sscope_capture *const *caps,
		const char *const *paths, size_t n, double level,
		struct ssc_lot_result **out)
{
	struct ssc_lot_result *r;
	struct sscope_noise_plan *plan = NULL;
	const struct sscope_capture *c0 = caps[0];
	int rc = 0;

	*out = NULL;
	if (n < 3) {
		ssc_err(cmd, "a lot needs at least 3 units (captures), got %zu", n);
		return SSC_EXIT_USAGE;
	}
	r = calloc(1, sizeof(*r));
	if (!r)
		return ssc_fail(cmd, -ENOMEM, NULL, NULL);
	r->n_units = n;
	r->paths = paths;
	r->level = level;
	r->chan = calloc(c0->n_channels + 1, sizeof(*r->chan));
	r->q = calloc(c0->n_channels + 1, sizeof(*r->q));
	if (!r->chan || !r->q) {
		ssc_lot_free(r);
		return ssc_fail(cmd, -ENOMEM, NULL, NULL);
	}
	for (size_t k = 0; k < c0->n_channels; k++)
		if (noise_channel(c0->channels[k].col.quantity)) {
			r->chan[r->n_chan] = c0->channels[k].col.name;
			r->q[r->n_chan++] = c0->channels[k].col.quantity;
		}
	if (!r->n_chan) {
		ssc_err(cmd, "%s: no angular-rate or acceleration channel (give units, e.g. 'gx [deg/s]' or -u deg/s)",
			paths[0]);
		ssc_lot_free(r);
		return SSC_EXIT_FAIL;
	}
	r->cell = calloc(n * r->n_chan, sizeof(*r->cell));
	r->term = calloc(r->n_chan * 3, sizeof(*r->term));
	if (!r->cell || !r->term) {
		ssc_lot_free(r);
		return ssc_fail(cmd, -ENOMEM, NULL, NULL);
	}
	if (sscope_noise_plan_new(&plan))
		plan = NULL; /* each fit computes its own */
	for (size_t u = 0; u < n && !rc; u++) {
		const struct sscope_capture *cap = caps[u];

		if (!(cap->rate_hz > 0)) {
			ssc_err(cmd, "%s: no sample rate (give --rate or a time column)", paths[u]);
			rc = SSC_EXIT_FAIL;
			break;
		}
		for (size_t c = 0; c < r->n_chan && !rc; c++) {
			const struct sscope_capture_channel *ch = NULL;

			for (size_t k = 0; k < cap->n_channels; k++)
				if (!strcmp(cap->channels[k].col.name, r->chan[c]) &&
				    cap->channels[k].col.quantity == r->q[c])
					ch = &cap->channels[k];
			if (!ch) {
				ssc_err(cmd, "%s: no channel '%s' of the same quantity as in %s: the units of a lot must have the same channels",
					paths[u], r->chan[c], paths[0]);
				rc = SSC_EXIT_FAIL;
				break;
			}
			rc = unit_fit(cmd, paths[u], ch, cap->n, cap->rate_hz, plan,
				      &r->cell[u * r->n_chan + c]);
		}
	}
	sscope_noise_plan_free(plan);
	if (!rc)
		rc = spread(cmd, r);
	if (rc) {
		ssc_lot_free(r);
		return rc;
	}
	*out = r;
	return 0;
}

/* an SI value in the term's conventional unit */
static double conv(const struct ssc_lot_result *r, size_t c, int t, double si,
		   const char **unit)
{
	return ssc_nav_term_value(si, r->q[c], (enum sscope_term)(SSCOPE_TERM_N + t), unit);
}

json_t *ssc_lot_json(const void *opts, const void *result)
{
	const struct ssc_lot_result *r = result;
	json_t *o = json_object(), *units = json_array(), *btw = json_array();
	json_t *outl = json_array();

	(void)opts;
	json_object_set_new(o, "command", json_string("lot"));
	json_object_set_new(o, "level", json_real(r->level));
	json_object_set_new(o, "model",
			    json_string("random effects: each unit's value = mean + unit effect (sd between_sd) + its own measurement error (sd from its 68.3 % interval); between_sd by REML with its Q-profile interval (Viechtbauer 2007), the mean by Hartung-Knapp; units beyond the family-wise outlier level left out"));
	for (size_t u = 0; u < r->n_units; u++) {
		json_t *ju = json_object(), *chs = json_array();

		json_object_set_new(ju, "unit", json_string(base_of(r->paths[u])));
		json_object_set_new(ju, "path", json_string(r->paths[u]));
		for (size_t c = 0; c < r->n_chan; c++) {
			const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];
			json_t *jc = json_object(), *terms = json_object();

			json_object_set_new(jc, "name", json_string(r->chan[c]));
			for (int t = 0; t < 3; t++) {
				const char *unit;
				json_t *jt = json_object();

				json_object_set_new(jt, "present", json_boolean(cl->present[t]));
				json_object_set_new(jt, "value", ssc_jreal(conv(r, c, t, cl->v[t], &unit)));
				json_object_set_new(jt, "lo", ssc_jreal(conv(r, c, t, cl->lo[t], &unit)));
				json_object_set_new(jt, "hi", ssc_jreal(conv(r, c, t, cl->hi[t], &unit)));
				json_object_set_new(jt, "unit", json_string(unit));
				json_object_set_new(jt, "z", ssc_jreal(r->term[c * 3 + (size_t)t].z[u]));
				json_object_set_new(jt, "outlier",
						    json_boolean(r->term[c * 3 + (size_t)t].outlier[u]));
				json_object_set_new(terms, (char[2]){ term_key[t], 0 }, jt);
			}
			json_object_set_new(jc, "terms", terms);
			json_array_append_new(chs, jc);
		}
		json_object_set_new(ju, "channels", chs);
		json_array_append_new(units, ju);
	}
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < 3; t++) {
			const struct ssc_lot_term *T = &r->term[c * 3 + (size_t)t];
			const struct sscope_lot_spread *s = &T->sp;
			json_t *b = json_object(), *fl = json_array();
			const char *unit;

			conv(r, c, t, 1, &unit);
			json_object_set_new(b, "channel", json_string(r->chan[c]));
			json_object_set_new(b, "term", json_string((char[2]){ term_key[t], 0 }));
			json_object_set_new(b, "unit", json_string(unit));
			json_object_set_new(b, "units", json_integer((json_int_t)r->n_units));
			json_object_set_new(b, "units_resolved", json_integer((json_int_t)T->n_resolved));
			if (!T->done) {
				json_object_set_new(b, "why", json_string("fewer than 3 units show the term: no spread"));
				json_array_append_new(btw, b);
				json_decref(fl);
				continue;
			}
			json_object_set_new(b, "units_used", json_integer((json_int_t)s->k_used));
			json_object_set_new(b, "mean", ssc_jreal(conv(r, c, t, s->mean, &unit)));
			json_object_set_new(b, "mean_lo", ssc_jreal(conv(r, c, t, s->mean_lo, &unit)));
			json_object_set_new(b, "mean_hi", ssc_jreal(conv(r, c, t, s->mean_hi, &unit)));
			json_object_set_new(b, "between_sd", ssc_jreal(conv(r, c, t, s->between_sd, &unit)));
			json_object_set_new(b, "between_sd_lo", ssc_jreal(conv(r, c, t, s->between_lo, &unit)));
			json_object_set_new(b, "between_sd_hi", ssc_jreal(conv(r, c, t, s->between_hi, &unit)));
			json_object_set_new(b, "total_sd", ssc_jreal(conv(r, c, t, s->total_sd, &unit)));
			json_object_set_new(b, "q_p_value", ssc_jreal(s->q_p));
			json_object_set_new(b, "i2", ssc_jreal(s->i2));
			json_object_set_new(b, "outlier_z", ssc_jreal(s->outlier_z));
			for (size_t u = 0; u < r->n_units; u++)
				if (T->outlier[u]) {
					json_t *e = json_object();

					json_array_append_new(fl, json_string(base_of(r->paths[u])));
					json_object_set_new(e, "unit", json_string(base_of(r->paths[u])));
					json_object_set_new(e, "channel", json_string(r->chan[c]));
					json_object_set_new(e, "term", json_string((char[2]){ term_key[t], 0 }));
					json_object_set_new(e, "z", ssc_jreal(T->z[u]));
					json_array_append_new(outl, e);
				}
			json_object_set_new(b, "outliers", fl);
			json_array_append_new(btw, b);
		}
	json_object_set_new(o, "units", units);
	json_object_set_new(o, "between", btw);
	json_object_set_new(o, "outliers", outl);
	return o;
}

void ssc_lot_text(FILE *f, const void *opts, const void *result)
{
	const struct ssc_lot_result *r = result;
	char a[32], b[32], c3[32], d[32], e[32], g[32];

	(void)opts;
	fprintf(f, "lot of %zu units; %s %% intervals; spread between units separated from each unit's own uncertainty\n",
		r->n_units, ssc_fmt(a, sizeof(a), 100 * r->level, 3));
	fprintf(f, "%-8s %-4s %-16s %-30s %-30s %-8s %s\n", "channel", "term", "unit",
		"mean [interval]", "between-unit sd [interval]", "units", "outliers");
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < 3; t++) {
			const struct ssc_lot_term *T = &r->term[c * 3 + (size_t)t];
			const struct sscope_lot_spread *s = &T->sp;
			const char *unit;
			char m[64], bs[64], un[32];
			bool any = false;

			conv(r, c, t, 1, &unit);
			if (!T->done) {
				fprintf(f, "%-8s %-4c %-16s shown in %zu of %zu units: fewer than 3, no spread\n",
					r->chan[c], term_key[t], unit, T->n_resolved, r->n_units);
				continue;
			}
			snprintf(m, sizeof(m), "%s [%s, %s]",
				 ssc_fmt(a, sizeof(a), conv(r, c, t, s->mean, &unit), 4),
				 ssc_fmt(b, sizeof(b), conv(r, c, t, s->mean_lo, &unit), 4),
				 ssc_fmt(c3, sizeof(c3), conv(r, c, t, s->mean_hi, &unit), 4));
			snprintf(bs, sizeof(bs), "%s [%s, %s]",
				 ssc_fmt(d, sizeof(d), conv(r, c, t, s->between_sd, &unit), 3),
				 ssc_fmt(e, sizeof(e), conv(r, c, t, s->between_lo, &unit), 3),
				 ssc_fmt(g, sizeof(g), conv(r, c, t, s->between_hi, &unit), 3));
			snprintf(un, sizeof(un), "%zu/%zu", s->k_used, r->n_units);
			fprintf(f, "%-8s %-4c %-16s %-30s %-30s %-8s", r->chan[c], term_key[t],
				unit, m, bs, un);
			for (size_t u = 0; u < r->n_units; u++)
				if (T->outlier[u]) {
					fprintf(f, "%s%s (z %s)", any ? ", " : "",
						base_of(r->paths[u]),
						ssc_fmt(a, sizeof(a), T->z[u], 3));
					any = true;
				}
			fprintf(f, "%s\n", any ? "" : "-");
		}
}

void ssc_lot_summary(json_t *rows, const void *opts, const void *result)
{
	const struct ssc_lot_result *r = result;

	(void)opts;
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < 3; t++) {
			const struct ssc_lot_term *T = &r->term[c * 3 + (size_t)t];
			const char *unit;
			char q[48], note[96];
			size_t n_out = 0;

			if (!T->done)
				continue;
			for (size_t u = 0; u < r->n_units; u++)
				n_out += T->outlier[u];
			snprintf(q, sizeof(q), "%c between-unit sd", term_key[t]);
			snprintf(note, sizeof(note), "%zu of %zu units; %zu outlier%s",
				 T->sp.k_used, r->n_units, n_out, n_out == 1 ? "" : "s");
			ssc_summary_add(rows, r->chan[c], q,
					conv(r, c, t, T->sp.between_sd, &unit),
					conv(r, c, t, T->sp.between_lo, &unit),
					conv(r, c, t, T->sp.between_hi, &unit), unit, note);
			if (n_out)
				ssc_summary_warn_last(rows);
		}
}

void ssc_lot_free(void *result)
{
	struct ssc_lot_result *r = result;

	if (!r)
		return;
	for (size_t i = 0; r->term && i < r->n_chan * 3; i++) {
		free(r->term[i].outlier);
		free(r->term[i].z);
	}
	free(r->term);
	free(r->cell);
	free(r->chan);
	free(r->q);
	free(r);
}
