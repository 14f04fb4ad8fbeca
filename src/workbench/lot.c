/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The lot stage (see lot.h).  Each unit's channel gets the allan stage's
 * analysis (dense taus, the IEEE 952 fit with its 68.3 % intervals); a
 * term present in a unit enters the lot with the half-width of its
 * interval as its standard error, a term a unit does not show is left out
 * of that term's lot (said in the output: "resolved in k of n units").
 * Each unit's bias, drift and temperature sensitivity come from
 * sscope_lot_bias() (batch means), with its standard errors.  The spread
 * of every term is sscope_lot_spread() at the stated level.  --plot draws
 * the units' biases against time (a moving mean, the median and 5-95 %
 * band of the units that are not bias outliers) and their Allan
 * deviations with the median curve.
 */
#include "workbench.h"

#include <malloc.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lot.h"
#include "navcommon.h"
#include "plot.h"
#include "stage.h"

static const char *const term_key[SSC_LOT_NT] = {
	"N", "B", "K", "bias", "bias_drift", "temp_sensitivity"
};
/* the same in words, for text and pages (JSON and CSV keep the keys) */
static const char *const term_label[SSC_LOT_NT] = {
	"N", "B", "K", "bias", "bias drift", "temp sensitivity"
};

static const char *base_of(const char *path)
{
	const char *s = strrchr(path, '/');

	return s ? s + 1 : path;
}

/* a unit's name: the manifest's, else its file's base name */
static const char *unit_name(const struct ssc_lot_result *r, size_t u)
{
	return r->labels && r->labels[u] ? r->labels[u] : base_of(r->paths[u]);
}

/* why a unit's interval of term t is doubtful, or NULL: a wandering
 * bias correlates the block means; the drift's and the temperature
 * sensitivity's intervals take it into account through the unit's noise
 * model when it shows bias instability (B) or a rate random walk (K)
 * (sscope_lot_bias(), unit_bias()), and are too narrow when the block
 * means' residuals are correlated but the model shows neither */
static const char *cell_doubt_corr(const struct ssc_lot_cell *cl, int t)
{
	if ((t == SSC_LOT_DRIFT || t == SSC_LOT_TEMPCO) && cl->present[t] &&
	    cl->bias.resid_correlated && !(cl->model[1] > 0) && !(cl->model[2] > 0))
		return "the block means' residuals are correlated (the bias wanders) but the unit's fit shows neither B nor K: the interval takes them as independent and is too narrow";
	return NULL;
}

/* the reason above, else whether the record cannot rule out flicker (B)
 * or a random walk (K) that would widen the drift's or sensitivity's
 * interval more than SSC_LOT_SE_UPPER_RATIO times (its se_upper: B,
 * then K, at the fit's upper bound, or the upper end of its interval
 * where shown; the verdicts use that interval) */
static const char *cell_doubt(const struct ssc_lot_cell *cl, int t)
{
	double su;
	bool nb = !(cl->model[1] > 0), nk = !(cl->model[2] > 0);

	if (cell_doubt_corr(cl, t))
		return cell_doubt_corr(cl, t);
	if ((t != SSC_LOT_DRIFT && t != SSC_LOT_TEMPCO) || !cl->present[t])
		return NULL;
	su = t == SSC_LOT_DRIFT ? cl->bias.drift_se_upper : cl->bias.tempco_se_upper;
	if (!(su > SSC_LOT_SE_UPPER_RATIO * cl->se[t]))
		return NULL;
	if (nb && nk)
		return "the record cannot rule out flicker (B) or a rate random walk (K) that would make this interval more than 1.5 times wider (each at the fit's upper bound; the verdicts use that wider interval): record longer, or take B and K from a longer record of the model or its datasheet";
	if (!nb && !nk)
		return "B and K at the upper ends of their intervals would make this interval more than 1.5 times wider (the verdicts use that wider interval): record longer, or take B and K from a longer record of the model or its datasheet";
	if (nk)
		return "the record cannot rule out a rate random walk (K) that would make this interval more than 1.5 times wider (K at the fit's upper bound; the verdicts use that wider interval): record longer, or take K from a longer record of the model or its datasheet";
	return "the record cannot rule out flicker (B) that would make this interval more than 1.5 times wider (B at the fit's upper bound; the verdicts use that wider interval): record longer, or take B from a longer record of the model or its datasheet";
}

/* a limit on the magnitude (+-) of a signed term: bias, drift and
 * temperature sensitivity */
static bool magnitude_term(int t)
{
	return t >= SSC_LOT_BIAS;
}

/* the Allan deviation points a unit's channel keeps for the figure */
#define LOT_FIG_ADEV 64

static int unit_fit(const char *cmd, const char *path,
		    const struct sscope_capture_channel *ch, size_t n, double fs,
		    struct sscope_noise_plan *plan, bool guard,
		    struct ssc_lot_cell *cell)
{
	struct sscope_allan_opts ao = { 0 };
	struct sscope_noise_fit_opts fo = { 0 };
	struct sscope_allan_result *res = NULL;
	struct sscope_diag d = { "" };
	int rc;

	fo.plan = plan;
	fo.ci_level = guard ? SSC_LOT_SPEC_LEVEL : 0;
	rc = sscope_allan_analyze(ch->data, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE, &ao,
				  &fo, &res, &d);
	if (rc) {
		ssc_err(cmd, "%s: channel %s: %s", path, ch->col.name,
			d.msg[0] ? d.msg : sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	for (int t = 0; t < 3 && guard; t++) {
		const struct sscope_noise_coef *c = &res->fit.coef[SSCOPE_TERM_N + t];
		bool pres = res->have_fit && c->present && isfinite(c->value) &&
			    isfinite(c->lo) && c->hi > c->lo;

		/* not shown: an upper bound only (INFINITY or NaN when the
		 * record gives none: inconclusive) */
		cell->gbound[t] = !pres;
		cell->glo[t] = pres ? c->lo : (double)NAN;
		cell->ghi[t] = res->have_fit && c->hi > 0 ? c->hi : (double)NAN;
	}
	for (int t = 0; t < 3 && !guard; t++) {
		const struct sscope_noise_coef *c = &res->fit.coef[SSCOPE_TERM_N + t];

		cell->present[t] = res->have_fit && c->present && isfinite(c->value) &&
				   isfinite(c->lo) && isfinite(c->hi) && c->hi > c->lo;
		cell->v[t] = cell->present[t] ? c->value : (double)NAN;
		cell->lo[t] = cell->present[t] ? c->lo : (double)NAN;
		cell->hi[t] = cell->present[t] ? c->hi : (double)NAN;
		/* a 68.3 % interval: one standard error each side */
		cell->se[t] = 0.5 * (cell->hi[t] - cell->lo[t]);
		/* the upper end of the interval, the fit's upper bound where
		 * not shown (none: INFINITY) */
		cell->model_hi[t] = res->have_fit && c->hi > 0 ? c->hi : (double)INFINITY;
	}
	if (!guard) {
		/* the figure's curve: at most LOT_FIG_ADEV of the (log-spaced)
		 * taus, evenly by index, the first and last kept */
		size_t np = res->n_points, k = np > LOT_FIG_ADEV ? LOT_FIG_ADEV : np;

		cell->tau_s = malloc((k + 1) * sizeof(double));
		cell->adev = malloc((k + 1) * sizeof(double));
		if (!cell->tau_s || !cell->adev) {
			sscope_allan_result_free(res);
			return ssc_fail(cmd, -ENOMEM, NULL, NULL);
		}
		for (size_t i = 0; i < k; i++) {
			size_t j = k < 2 ? i : (i * (np - 1) + (k - 1) / 2) / (k - 1);

			cell->tau_s[i] = res->points[j].tau_s;
			cell->adev[i] = res->points[j].dev;
		}
		cell->n_adev = k;
	}
	sscope_allan_result_free(res);
	return 0;
}

/* the terms N, B, K the fit of x shows (0 for the others) and their
 * upper bounds (the upper end of the interval of a term shown;
 * INFINITY: none finite) */
static int shown_terms(const double *x, size_t n, double fs,
		       struct sscope_noise_plan *plan, double nbk[3], double up[3])
{
	struct sscope_allan_opts ao = { 0 };
	struct sscope_noise_fit_opts fo = { .plan = plan };
	struct sscope_allan_result *res = NULL;
	int rc = sscope_allan_analyze(x, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE, &ao, &fo,
				      &res, NULL);

	for (int t = 0; t < 3 && !rc; t++) {
		const struct sscope_noise_coef *c = &res->fit.coef[SSCOPE_TERM_N + t];

		nbk[t] = res->have_fit && c->present && isfinite(c->value) &&
			 isfinite(c->lo) && isfinite(c->hi) && c->hi > c->lo ? c->value : 0;
		up[t] = res->have_fit && c->hi > 0 ? c->hi : (double)INFINITY;
	}
	sscope_allan_result_free(res);
	return rc;
}

/* the bias, its drift and its temperature sensitivity (batch means),
 * the drift's and sensitivity's standard errors also under the unit's
 * noise model (cell->model): the terms the allan fit shows of the record
 * less the fitted temperature effect (with a temperature; else of the
 * record, cell's N, B, K) */
static int unit_bias(const char *cmd, const char *path,
		     const struct sscope_capture *cap,
		     const struct sscope_capture_channel *ch,
		     struct sscope_noise_plan *plan, struct ssc_lot_cell *cell)
{
	struct sscope_lot_bias_opts o = { .blocks = SSC_LOT_BIAS_BLOCKS };
	struct sscope_lot_bias *b = &cell->bias;
	int rc = sscope_lot_bias(ch->data, 1, cap->n, cap->rate_hz, cap->temp_degc, 1, &o, b);

	for (int t = 0; t < 3; t++)
		cell->model[t] = cell->present[t] ? cell->v[t] : 0;
	if (!rc && b->have_temp) {
		double *r = malloc(cap->n * sizeof(double));

		rc = r ? sscope_lot_temp_removed(ch->data, 1, cap->n, cap->temp_degc, 1, b, r) :
			 -ENOMEM;
		if (!rc)
			rc = shown_terms(r, cap->n, cap->rate_hz, plan, cell->model,
					 cell->model_hi);
		free(r);
	}
	if (!rc && (cell->model[1] > 0 || cell->model[2] > 0 || cell->model_hi[1] > 0 ||
		    cell->model_hi[2] > 0)) {
		o.n = cell->model[0];
		o.b = cell->model[1];
		o.k = cell->model[2];
		o.b_upper = cell->model_hi[1];
		o.k_upper = cell->model_hi[2];
		rc = sscope_lot_bias(ch->data, 1, cap->n, cap->rate_hz, cap->temp_degc, 1, &o, b);
	}
	if (rc) {
		ssc_err(cmd, "%s: channel %s: bias: %s", path, ch->col.name,
			rc == -EDOM ? "the bias terms need at least 40 samples, none of them NaN" :
				      sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	cell->v[SSC_LOT_BIAS] = b->bias;
	cell->lo[SSC_LOT_BIAS] = b->bias_lo;
	cell->hi[SSC_LOT_BIAS] = b->bias_hi;
	cell->se[SSC_LOT_BIAS] = b->bias_se;
	cell->v[SSC_LOT_DRIFT] = b->drift_u_s;
	cell->lo[SSC_LOT_DRIFT] = b->drift_lo;
	cell->hi[SSC_LOT_DRIFT] = b->drift_hi;
	cell->se[SSC_LOT_DRIFT] = b->drift_se;
	cell->v[SSC_LOT_TEMPCO] = b->tempco_u_degc;
	cell->lo[SSC_LOT_TEMPCO] = b->tempco_lo;
	cell->hi[SSC_LOT_TEMPCO] = b->tempco_hi;
	cell->se[SSC_LOT_TEMPCO] = b->tempco_se;
	for (int t = SSC_LOT_BIAS; t < SSC_LOT_NT; t++)
		cell->present[t] = isfinite(cell->v[t]) && cell->se[t] > 0;
	return 0;
}

/* the bias terms' intervals at SSC_LOT_SPEC_LEVEL, for the verdicts */
static int unit_bias_guard(const char *cmd, const char *path,
			   const struct sscope_capture *cap,
			   const struct sscope_capture_channel *ch,
			   struct ssc_lot_cell *cell)
{
	struct sscope_lot_bias_opts o = { .blocks = SSC_LOT_BIAS_BLOCKS,
					  .level = SSC_LOT_SPEC_LEVEL };
	struct sscope_lot_bias b;
	int rc;

	o.n = cell->model[0];
	o.b = cell->model[1];
	o.k = cell->model[2];
	o.b_upper = cell->model_hi[1];
	o.k_upper = cell->model_hi[2];
	rc = sscope_lot_bias(ch->data, 1, cap->n, cap->rate_hz, cap->temp_degc, 1, &o, &b);

	if (rc) {
		ssc_err(cmd, "%s: channel %s: bias: %s", path, ch->col.name,
			sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	cell->glo[SSC_LOT_BIAS] = b.bias_lo;
	cell->ghi[SSC_LOT_BIAS] = b.bias_hi;
	/* the conservative intervals: a unit passes a drift or sensitivity
	 * limit only if B and K at the fit's bounds would not move it out */
	cell->glo[SSC_LOT_DRIFT] = b.drift_upper_lo;
	cell->ghi[SSC_LOT_DRIFT] = b.drift_upper_hi;
	cell->glo[SSC_LOT_TEMPCO] = b.tempco_upper_lo;
	cell->ghi[SSC_LOT_TEMPCO] = b.tempco_upper_hi;
	for (int t = SSC_LOT_BIAS; t < SSC_LOT_NT; t++)
		cell->gbound[t] = false;
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
		for (int t = 0; t < SSC_LOT_NT; t++) {
			struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
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
				se[k++] = cl->se[t];
			}
			T->n_resolved = k;
			if (k < 3)
				continue;
			if (isfinite(T->limit) && magnitude_term(t)) {
				/* +-limit: the Cpk of the nearer side, the
				 * units' values mirrored when their mean is
				 * below 0 (y is not used after) */
				double m = 0;

				for (size_t i = 0; i < k; i++)
					m += y[i];
				if (m < 0)
					for (size_t i = 0; i < k; i++)
						y[i] = -y[i];
				T->cpk_done = !sscope_lot_cpk(y, se, k, T->limit, r->level, &T->cpk);
				if (m < 0 && T->cpk_done)
					T->cpk.mean = -T->cpk.mean;
				for (size_t i = 0; m < 0 && i < k; i++)
					y[i] = -y[i];
			} else {
				T->cpk_done = isfinite(T->limit) &&
					      !sscope_lot_cpk(y, se, k, T->limit, r->level, &T->cpk);
			}
			if (sscope_lot_spread(y, se, k, &o, &T->sp, z, fl))
				continue;
			T->done = true;
			/* N, B, K are amplitudes: the symmetric interval of
			 * their mean cut at 0 (it covers at least as often) */
			if (t <= SSC_LOT_K && T->sp.mean_lo < 0) {
				T->sp.mean_lo = 0;
				T->mean_lo_cut = true;
			}
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

/* the bias term a datasheet line limits (the lines on a magnitude:
 * bias_offset, rate_ramp, bias_tempco), or -1 */
static int bias_term_of(enum sscope_datasheet_line l)
{
	switch (l) {
	case SSCOPE_DATASHEET_BIAS_OFFSET:
		return SSC_LOT_BIAS;
	case SSCOPE_DATASHEET_RATE_RAMP:
		return SSC_LOT_DRIFT;
	case SSCOPE_DATASHEET_BIAS_TEMPCO:
		return SSC_LOT_TEMPCO;
	default:
		return -1;
	}
}

/* the limits of channel c's terms from the spec's section of its
 * quantity; false when the section gives none */
static bool channel_limits(struct ssc_lot_result *r, size_t c)
{
	bool any = false;

	for (size_t t = 0; t < SSC_LOT_NT; t++)
		r->term[c * SSC_LOT_NT + t].limit = NAN;
	for (size_t s = 0; r->spec && s < r->spec->n_sec; s++)
		if (r->spec->sec[s].quantity == r->q[c]) {
			double lim[3];
			int from[3];

			ssc_datasheet_terms(&r->spec->sec[s], lim, from);
			for (size_t t = 0; t < 3; t++) {
				r->term[c * SSC_LOT_NT + t].limit = lim[t];
				any |= isfinite(lim[t]);
			}
			/* the bias terms: limits on their magnitude */
			for (size_t j = 0; j < r->spec->sec[s].n; j++) {
				const struct sscope_datasheet_spec *sp = &r->spec->sec[s].spec[j];
				int t = bias_term_of(sp->line);

				if (t >= 0) {
					r->term[c * SSC_LOT_NT + (size_t)t].limit = sp->value;
					any = true;
				}
			}
		}
	return any;
}


static bool channel_has_spec(const struct ssc_lot_result *r, size_t c)
{
	for (size_t t = 0; t < SSC_LOT_NT; t++)
		if (isfinite(r->term[c * SSC_LOT_NT + t].limit))
			return true;
	return false;
}

/* each unit's verdicts and the counts per channel and term */
static void verdicts(struct ssc_lot_result *r)
{
	for (size_t u = 0; u < r->n_units; u++)
		for (size_t c = 0; c < r->n_chan; c++)
			for (size_t t = 0; t < SSC_LOT_NT; t++) {
				struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];
				struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + t];

				if (!isfinite(T->limit))
					continue;
				cl->has_spec[t] = true;
				/* an interval too narrow (cell_doubt_corr) gives
				 * no verdict; the drift's and sensitivity's
				 * are the conservative ones (unit_bias_guard()) */
				cl->verdict[t] = cell_doubt_corr(cl, (int)t) ?
					SSCOPE_DATASHEET_INCONCLUSIVE :
					magnitude_term((int)t) ?
					sscope_datasheet_verdict_magnitude(cl->glo[t], cl->ghi[t], T->limit) :
					sscope_datasheet_verdict(
						cl->gbound[t] ? 0 : cl->glo[t], cl->ghi[t], T->limit);
				T->count[cl->verdict[t]]++;
			}
}

/* the bias figure's record of a unit's channel (struct ssc_lot_cell) */
#define LOT_FIG_BLOCKS 128

static int unit_figure(const char *cmd, const struct sscope_capture *cap,
		       const struct sscope_capture_channel *ch,
		       struct ssc_lot_cell *cell)
{
	size_t n = cap->n, B = (n + LOT_FIG_BLOCKS - 1) / LOT_FIG_BLOCKS, k;
	double mean = 0, acc = 0, comp = 0;

	if (!B)
		B = 1;
	k = (n + B - 1) / B;
	cell->fig_cs = malloc((k + 1) * sizeof(double));
	if (!cell->fig_cs)
		return ssc_fail(cmd, -ENOMEM, NULL, NULL);
	for (size_t i = 0; i < n; i++)
		mean += ch->data[i];
	mean /= (double)n;
	/* prefix sums about the mean, compensated (Kahan): no digits lost
	 * to the bias or to a long record */
	cell->fig_cs[0] = 0;
	for (size_t i = 0; i < n; i++) {
		double yk = ch->data[i] - mean - comp, tk = acc + yk;

		comp = (tk - acc) - yk;
		acc = tk;
		if ((i + 1) % B == 0 || i + 1 == n)
			cell->fig_cs[(i + B) / B] = acc;
	}
	cell->fig_mean = mean;
	cell->fig_block = B;
	cell->fig_k = k;
	return 0;
}

/* unit u's record: the stage's capture, or read now (*own: free it) */
static int unit_capture(const struct ssc_stage_env *env, size_t u,
			struct sscope_capture **cap, bool *own)
{
	*own = !env->caps;
	if (env->caps) {
		*cap = env->caps[u];
		return 0;
	}
	return env->load(env, u, cap);
}

/* every analysis of unit u's record */
static int unit_all(const char *cmd, struct ssc_lot_result *r, size_t u,
		    const struct sscope_capture *cap,
		    struct sscope_noise_plan *plan)
{
	const char *path = r->paths[u];
	int rc = 0;

	if (!(cap->rate_hz > 0)) {
		return ssc_err_no_rate(cmd, path, cap->rate_note);
	}
	if ((cap->temp_degc != NULL) != r->temp) {
		ssc_err(cmd, "%s: %s temperature column, but %s %s: the units of a lot must have the same columns",
			path, r->temp ? "no" : "a", r->paths[0],
			r->temp ? "has one" : "has none");
		return SSC_EXIT_FAIL;
	}
	r->rate_hz[u] = cap->rate_hz;
	r->n_samples[u] = cap->n;
	for (size_t c = 0; c < r->n_chan && !rc; c++) {
		const struct sscope_capture_channel *ch = NULL;
		struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];

		for (size_t k = 0; k < cap->n_channels; k++)
			if (!strcmp(cap->channels[k].col.name, r->chan[c]) &&
			    cap->channels[k].col.quantity == r->q[c])
				ch = &cap->channels[k];
		if (!ch) {
			ssc_err(cmd, "%s: no channel '%s' of the same quantity as in %s: the units of a lot must have the same channels",
				path, r->chan[c], r->paths[0]);
			return SSC_EXIT_FAIL;
		}
		{
			size_t i = 0;

			while (i < cap->n && !isfinite(ch->data[i]))
				i++;
			cl->constant = i < cap->n;
			for (size_t j = i + 1; cl->constant && j < cap->n; j++)
				cl->constant = !isfinite(ch->data[j]) ||
					       ch->data[j] == ch->data[i];
		}
		rc = unit_fit(cmd, path, ch, cap->n, cap->rate_hz, plan, false, cl);
		if (!rc)
			rc = unit_bias(cmd, path, cap, ch, plan, cl);
		if (!rc && channel_has_spec(r, c))
			rc = unit_fit(cmd, path, ch, cap->n, cap->rate_hz, plan, true, cl);
		if (!rc && channel_has_spec(r, c))
			rc = unit_bias_guard(cmd, path, cap, ch, cl);
		if (!rc)
			rc = unit_figure(cmd, cap, ch, cl);
	}
	return rc;
}

struct ssc_lot_result *ssc_lot_new(const char *cmd, size_t n,
				   const char *const *paths,
				   const char *const *labels, double level,
				   const char *spec_path, double smooth_s,
				   int *rc)
{
	struct ssc_lot_result *r;

	*rc = 0;
	r = calloc(1, sizeof(*r));
	if (!r) {
		*rc = ssc_fail(cmd, -ENOMEM, NULL, NULL);
		return NULL;
	}
	r->n_units = n;
	r->paths = paths;
	r->labels = labels;
	r->level = level;
	r->smooth_s = smooth_s;
	r->rate_hz = calloc(n, sizeof(*r->rate_hz));
	r->n_samples = calloc(n, sizeof(*r->n_samples));
	if (!r->rate_hz || !r->n_samples) {
		*rc = ssc_fail(cmd, -ENOMEM, NULL, NULL);
		ssc_lot_free(r);
		return NULL;
	}
	r->spec_path = spec_path;
	if (spec_path) {
		r->spec = malloc(sizeof(*r->spec));
		if (!r->spec) {
			*rc = ssc_fail(cmd, -ENOMEM, NULL, NULL);
			ssc_lot_free(r);
			return NULL;
		}
		*rc = ssc_datasheet_load(cmd, spec_path, r->spec);
		if (*rc) {
			free(r->spec);
			r->spec = NULL;
			ssc_lot_free(r);
			return NULL;
		}
	}
	return r;
}

int ssc_lot_set_channels(const char *cmd, struct ssc_lot_result *r, bool temp,
			 const char *const *names,
			 const enum sscope_quantity *q, size_t n)
{
	r->temp = temp;
	r->chan = calloc(n + 1, sizeof(*r->chan));
	r->q = calloc(n + 1, sizeof(*r->q));
	if (!r->chan || !r->q)
		return ssc_fail(cmd, -ENOMEM, NULL, NULL);
	for (size_t k = 0; k < n; k++)
		if (noise_channel(q[k])) {
			r->chan[r->n_chan] = strdup(names[k]);
			if (!r->chan[r->n_chan])
				return ssc_fail(cmd, -ENOMEM, NULL, NULL);
			r->q[r->n_chan++] = q[k];
		}
	if (!r->n_chan) {
		ssc_err(cmd, "%s: no angular-rate or acceleration channel (give units, e.g. 'gx [deg/s]' or -u deg/s)",
			r->paths[0]);
		return SSC_EXIT_FAIL;
	}
	r->cell = calloc(r->n_units * r->n_chan, sizeof(*r->cell));
	r->term = calloc(r->n_chan * SSC_LOT_NT, sizeof(*r->term));
	if (!r->cell || !r->term)
		return ssc_fail(cmd, -ENOMEM, NULL, NULL);
	for (size_t c = 0; c < r->n_chan; c++)
		channel_limits(r, c);
	if (r->spec) {
		bool any = false;

		for (size_t c = 0; c < r->n_chan; c++)
			any |= channel_has_spec(r, c);
		if (!any) {
			ssc_err(cmd, "%s: no limit on N, B, K, bias_offset, rate_ramp or bias_tempco for any channel of the lot ([gyro] for angular rates, [accel] for accelerations)",
				r->spec_path);
			return SSC_EXIT_FAIL;
		}
	}
	return 0;
}

int ssc_lot_unit(const char *cmd, struct ssc_lot_result *r, size_t u,
		 const struct sscope_capture *cap, struct sscope_noise_plan *plan)
{
	int rc = 0;

	if (!r->chan) {
		const char **names = calloc(cap->n_channels + 1, sizeof(*names));
		enum sscope_quantity *q = calloc(cap->n_channels + 1, sizeof(*q));

		if (!names || !q) {
			free(names);
			free(q);
			return ssc_fail(cmd, -ENOMEM, NULL, NULL);
		}
		for (size_t k = 0; k < cap->n_channels; k++) {
			names[k] = cap->channels[k].col.name;
			q[k] = cap->channels[k].col.quantity;
		}
		rc = ssc_lot_set_channels(cmd, r, cap->temp_degc != NULL, names, q,
					  cap->n_channels);
		free(names);
		free(q);
	}
	return rc ? rc : unit_all(cmd, r, u, cap, plan);
}

int ssc_lot_finish(const char *cmd, struct ssc_lot_result *r)
{
	int rc = spread(cmd, r);

	if (!rc)
		verdicts(r);
	return rc;
}

int ssc_lot_run(const struct ssc_stage_env *env, double level,
		const char *spec_path, double smooth_s,
		struct ssc_lot_result **out)
{
	const char *cmd = env->co->cmd;
	size_t n = env->n_caps;
	struct ssc_lot_result *r;
	struct sscope_noise_plan *plan = NULL;
	int rc = 0;

	*out = NULL;
	if (n < 3) {
		ssc_err(cmd, "a lot needs at least 3 units (captures), got %zu", n);
		return SSC_EXIT_USAGE;
	}
	r = ssc_lot_new(cmd, n, env->paths, env->labels, level, spec_path,
			smooth_s, &rc);
	if (!r)
		return rc;
	if (sscope_noise_plan_new(&plan))
		plan = NULL; /* each fit computes its own */
#ifdef M_MMAP_THRESHOLD
	/* each unit's record and largest work space mapped and given back:
	 * with glibc's default the threshold rises to the size of the first
	 * record freed, later records come from the heap, and the small
	 * results kept between them fragment it (the peak grew by about
	 * 0.7 MB a unit).  12 units of 17 MB: peak RSS 43.9 MB by default,
	 * 36.0 MB at 4 MiB for 27 % more CPU, 30.7 MB at 1 MiB for 105 %
	 * more (the channels' arrays of 2.9 MB then mapped and zeroed anew
	 * at every use) */
	mallopt(M_MMAP_THRESHOLD, 4 << 20);
#endif
	/* one unit at a time: what the lot keeps of a unit is its fits,
	 * bias terms, Allan deviation and the figure's sums, not its record */
	for (size_t u = 0; u < n && !rc; u++) {
		struct sscope_capture *cap = NULL;
		bool own;

		rc = unit_capture(env, u, &cap, &own);
		if (!rc)
			rc = ssc_lot_unit(cmd, r, u, cap, plan);
		if (own)
			sscope_capture_free(cap);
	}
	sscope_noise_plan_free(plan);
	if (!rc)
		rc = ssc_lot_finish(cmd, r);
	if (rc) {
		ssc_lot_free(r);
		return rc;
	}
	*out = r;
	return 0;
}

/* an SI value in the term's conventional unit: the noise terms and the
 * bias as the fit shows them (deg/h, ug), the drift per hour, the
 * temperature sensitivity per degC */
static double conv(const struct ssc_lot_result *r, size_t c, int t, double si,
		   const char **unit)
{
	static const char *const per_degc[2][2] = {
		{ "deg/h/degC", "rad/s/degC" }, { "ug/degC", "m/s^2/degC" }
	};
	enum sscope_term st = t == SSC_LOT_DRIFT ? SSCOPE_TERM_R :
			      t >= SSC_LOT_BIAS ? SSCOPE_TERM_B :
			      (enum sscope_term)(SSCOPE_TERM_N + t);
	double v = ssc_nav_term_value(si, r->q[c], st, unit);

	if (t == SSC_LOT_TEMPCO)
		*unit = per_degc[r->q[c] == SSCOPE_QUANTITY_ACCELERATION]
				[strcmp(*unit, sscope_term_si_unit(r->q[c], st)) == 0];
	return v;
}

static const char *const verdict_key[3] = { "inconclusive", "within_spec", "out_of_spec" };

double ssc_lot_value(const struct ssc_lot_result *r, size_t c, int t, double si,
		     const char **unit)
{
	return conv(r, c, t, si, unit);
}

void ssc_lot_spread_text(const struct ssc_lot_result *r, size_t c, int t,
			 char *mean, size_t ml, char *sd, size_t sl)
{
	const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
	const struct sscope_lot_spread *s = &T->sp;
	char a[32], b[32], d[32];
	const char *unit;

	snprintf(mean, ml, "%s [%s%s, %s]",
		 ssc_fmt(a, sizeof(a), conv(r, c, t, s->mean, &unit), 4),
		 ssc_fmt(b, sizeof(b), conv(r, c, t, s->mean_lo, &unit), 4),
		 T->mean_lo_cut ? " (cut)" : "",
		 ssc_fmt(d, sizeof(d), conv(r, c, t, s->mean_hi, &unit), 4));
	if (s->between_hi == 0)
		/* an empty Q-profile set: the units agree better than their
		 * own errors imply; no spread can be told */
		snprintf(sd, sl, "0 (agree within errors)");
	else
		snprintf(sd, sl, "%s [%s, %s]",
			 ssc_fmt(a, sizeof(a), conv(r, c, t, s->between_sd, &unit), 3),
			 ssc_fmt(b, sizeof(b), conv(r, c, t, s->between_lo, &unit), 3),
			 ssc_fmt(d, sizeof(d), conv(r, c, t, s->between_hi, &unit), 3));
}

const char *ssc_lot_term_key(int t)
{
	return term_key[t];
}

const char *ssc_lot_term_label(int t)
{
	return term_label[t];
}

const char *ssc_lot_key_label(const char *key)
{
	for (int t = 0; t < SSC_LOT_NT; t++)
		if (!strcmp(key, term_key[t]))
			return term_label[t];
	return key;
}

const char *ssc_lot_unit_name(const struct ssc_lot_result *r, size_t u)
{
	return unit_name(r, u);
}

const char *ssc_lot_doubt(const struct ssc_lot_cell *cl, int t)
{
	return cell_doubt(cl, t);
}

double ssc_lot_se_upper(const struct ssc_lot_cell *cl, int t)
{
	if (!cl->present[t])
		return NAN;
	return t == SSC_LOT_DRIFT ? cl->bias.drift_se_upper :
	       t == SSC_LOT_TEMPCO ? cl->bias.tempco_se_upper : (double)NAN;
}

/* a conservative se: a number, "inf" where the record bounds B or K by
 * none, null where not computed */
static json_t *se_upper_json(double v)
{
	return isinf(v) ? json_string("inf") : ssc_jreal(v);
}

/* a unit's term against its limit */
static json_t *unit_spec_json(const struct ssc_lot_result *r, size_t c, int t,
			      const struct ssc_lot_cell *cl)
{
	json_t *o = json_object();
	const char *unit;

	json_object_set_new(o, "limit", ssc_jreal(conv(r, c, t, r->term[c * SSC_LOT_NT + (size_t)t].limit, &unit)));
	if (magnitude_term(t))
		json_object_set_new(o, "limit_on_magnitude", json_true());
	json_object_set_new(o, "level", json_real(SSC_LOT_SPEC_LEVEL));
	json_object_set_new(o, "upper_bound_only", json_boolean(cl->gbound[t]));
	json_object_set_new(o, "lo", cl->gbound[t] ? json_null() :
				     ssc_jreal(conv(r, c, t, cl->glo[t], &unit)));
	json_object_set_new(o, "hi", ssc_jreal(conv(r, c, t, cl->ghi[t], &unit)));
	json_object_set_new(o, "verdict", json_string(sscope_datasheet_verdict_name(cl->verdict[t])));
	return o;
}

/* a channel's term against its limit over the lot */
static void between_spec_json(json_t *b, const struct ssc_lot_result *r, size_t c, int t)
{
	const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
	const struct sscope_lot_cpk *k = &T->cpk;
	const char *unit;

	if (!isfinite(T->limit))
		return;
	json_object_set_new(b, "limit", ssc_jreal(conv(r, c, t, T->limit, &unit)));
	if (magnitude_term(t))
		json_object_set_new(b, "limit_on_magnitude", json_true());
	for (int v = 0; v < 3; v++)
		json_object_set_new(b, verdict_key[v], json_integer((json_int_t)T->count[v]));
	if (!T->cpk_done) {
		json_object_set_new(b, "cpk", json_null());
		json_object_set_new(b, "cpk_why", json_string("fewer than 3 units show the term: no Cpk"));
		return;
	}
	json_object_set_new(b, "cpk", ssc_jreal(k->cpk));
	json_object_set_new(b, "cpk_lo", ssc_jreal(k->lo));
	json_object_set_new(b, "cpk_hi", ssc_jreal(k->hi));
	json_object_set_new(b, "cpk_units", json_integer((json_int_t)k->n));
	json_object_set_new(b, "cpk_mean", ssc_jreal(conv(r, c, t, k->mean, &unit)));
	json_object_set_new(b, "cpk_sigma", ssc_jreal(conv(r, c, t, k->sigma, &unit)));
	json_object_set_new(b, "cpk_between_sd", ssc_jreal(conv(r, c, t, k->between_sd, &unit)));
	json_object_set_new(b, "cpk_within_sd", ssc_jreal(conv(r, c, t, k->within_sd, &unit)));
	if (k->n < r->n_units)
		json_object_set_new(b, "cpk_note", json_string("over the units that show the term only"));
}

/* the limits file, and its lines no term of the lot is checked against */
static json_t *spec_json(const struct ssc_lot_result *r)
{
	json_t *o = json_object(), *nc = json_array();
	const struct ssc_datasheet *ds = r->spec;

	json_object_set_new(o, "file", json_string(ds->path));
	json_object_set_new(o, "name", json_string(ds->name));
	json_object_set_new(o, "level", json_real(SSC_LOT_SPEC_LEVEL));
	json_object_set_new(o, "rule",
			    json_string("a unit is within spec when its whole interval at the level lies below the limit, out of spec when it lies above, else inconclusive; a term its fit does not show has an upper bound only: within spec when the bound is below the limit, else inconclusive. A limit on the bias, its drift (rate_ramp) or its temperature sensitivity (bias_tempco) is on the magnitude: within spec when the whole interval lies inside +-limit, out of spec when it lies beyond one side; for the drift and the temperature sensitivity that interval is the conservative one (B and K that the unit's fit does not show at their upper bounds; its standard error is se_upper), so a unit passes only if even that wider interval lies inside; a unit whose drift or sensitivity interval is doubtful (the block means' residuals correlated while its fit shows neither B nor K) is inconclusive. Cpk = (limit - mean) / (3 sigma) ((limit - |mean|) / (3 sigma) for a limit on the magnitude), sigma = sqrt(between-unit sd^2 + typical within-unit sd^2), every unit that shows the term (outliers kept), Bissell's interval at the lot's level"));
	for (size_t s = 0; s < ds->n_sec; s++) {
		bool chan = false;

		for (size_t c = 0; c < r->n_chan; c++)
			chan |= r->q[c] == ds->sec[s].quantity;
		double lim[3];
		int from[3];

		ssc_datasheet_terms(&ds->sec[s], lim, from);
		for (size_t j = 0; j < ds->sec[s].n; j++) {
			const struct sscope_datasheet_spec *sp = &ds->sec[s].spec[j];
			char line[96];

			/* checked: the line a term's limit comes from */
			if (chan && (from[0] == (int)j || from[1] == (int)j || from[2] == (int)j ||
				     bias_term_of(sp->line) >= 0))
				continue;
			snprintf(line, sizeof(line), "[%s] %s", ds->sec[s].name,
				 sscope_datasheet_info(sp->line)->key);
			json_array_append_new(nc, json_string(line));
		}
	}
	json_object_set_new(o, "not_checked", nc);
	return o;
}

json_t *ssc_lot_json(const void *opts, const void *result)
{
	const struct ssc_lot_result *r = result;
	json_t *o = json_object(), *units = json_array(), *btw = json_array();
	json_t *outl = json_array();

	(void)opts;
	if (r->note[0]) {
		json_decref(units);
		json_decref(btw);
		json_decref(outl);
		json_object_set_new(o, "command", json_string("lot"));
		json_object_set_new(o, "done", json_string(r->note));
		return o;
	}
	json_object_set_new(o, "command", json_string("lot"));
	json_object_set_new(o, "level", json_real(r->level));
	json_object_set_new(o, "model",
			    json_string("random effects: each unit's value = mean + unit effect (sd between_sd) + its own measurement error (sd from its 68.3 % interval); between_sd by REML with its Q-profile interval (Viechtbauer 2007), the mean by Hartung-Knapp; units beyond the family-wise outlier level left out"));
	json_object_set_new(o, "bias_method",
			    json_string("batch means: the record cut into bias_blocks equal blocks, their means fitted by least squares as bias + bias_drift (t - t_mean) + temp_sensitivity (T - T_mean), t the block centres, T the blocks' mean temperatures (without a temperature column, no T term); bias is the mean of the record; standard errors from the residuals, Student-t 68.3 % intervals with bias_blocks - 3 degrees of freedom (- 2 without temperature); where the unit's noise model (N, B, K the allan fit shows in the record less its fitted temperature effect) has B or K, the drift's and temperature sensitivity's standard errors are the larger of the residuals' and the noise model's (the variance of their weights on the block means under white, flicker and random-walk rate noise; normal quantile; se_from says which); se_upper is a conservative standard error of the drift and the temperature sensitivity, the largest of se and the noise model's with B, then K, at its upper bound (the fit's bound of a term it does not show, the upper end of the interval of one it shows; \"inf\" where the record gives no finite bound): where it exceeds se more than 1.5 times, doubt says so and which term, and a verdict against a drift or temperature-sensitivity limit always uses the interval of se_upper (normal quantile); where temperature follows time (temperature.time_corr near -1 or 1) drift and temperature sensitivity cannot be told apart and both intervals are wide"));
	for (size_t u = 0; u < r->n_units; u++) {
		json_t *ju = json_object(), *chs = json_array();

		json_object_set_new(ju, "unit", json_string(unit_name(r, u)));
		json_object_set_new(ju, "path", json_string(r->paths[u]));
		for (size_t c = 0; c < r->n_chan; c++) {
			const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];
			json_t *jc = json_object(), *terms = json_object();

			json_object_set_new(jc, "name", json_string(r->chan[c]));
			for (int t = 0; t < SSC_LOT_NT; t++) {
				const char *unit;
				json_t *jt = json_object();

				json_object_set_new(jt, "present", json_boolean(cl->present[t]));
				json_object_set_new(jt, "value", ssc_jreal(conv(r, c, t, cl->v[t], &unit)));
				json_object_set_new(jt, "lo", ssc_jreal(conv(r, c, t, cl->lo[t], &unit)));
				json_object_set_new(jt, "hi", ssc_jreal(conv(r, c, t, cl->hi[t], &unit)));
				json_object_set_new(jt, "unit", json_string(unit));
				if (t >= SSC_LOT_BIAS)
					json_object_set_new(jt, "se", ssc_jreal(conv(r, c, t, cl->se[t], &unit)));
				if (t == SSC_LOT_DRIFT || t == SSC_LOT_TEMPCO)
					json_object_set_new(jt, "se_upper",
							    se_upper_json(conv(r, c, t, ssc_lot_se_upper(cl, t), &unit)));
				json_object_set_new(jt, "z", ssc_jreal(r->term[c * SSC_LOT_NT + (size_t)t].z[u]));
				json_object_set_new(jt, "outlier",
						    json_boolean(r->term[c * SSC_LOT_NT + (size_t)t].outlier[u]));
				if ((t == SSC_LOT_DRIFT || t == SSC_LOT_TEMPCO) && cl->present[t])
					json_object_set_new(jt, "se_from", json_string(
						(t == SSC_LOT_DRIFT ? cl->bias.drift_se_from_model :
								      cl->bias.tempco_se_from_model) ?
						"noise model" : "residuals"));
				if (cell_doubt(cl, t))
					json_object_set_new(jt, "doubt", json_string(cell_doubt(cl, t)));
				if (cl->has_spec[t])
					json_object_set_new(jt, "spec", unit_spec_json(r, c, t, cl));
				json_object_set_new(terms, term_key[t], jt);
			}
			json_object_set_new(jc, "terms", terms);
			json_object_set_new(jc, "bias_blocks", json_integer((json_int_t)cl->bias.blocks));
			json_object_set_new(jc, "block_s", ssc_jreal((double)cl->bias.block_n /
								     r->rate_hz[u]));
			json_object_set_new(jc, "residual_lag1", ssc_jreal(cl->bias.resid_lag1));
			json_object_set_new(jc, "constant", json_boolean(cl->constant));
			if (cl->bias.have_temp) {
				json_t *jt = json_object();

				json_object_set_new(jt, "mean_degc", ssc_jreal(cl->bias.temp_mean_degc));
				json_object_set_new(jt, "span_degc", ssc_jreal(cl->bias.temp_span_degc));
				json_object_set_new(jt, "time_corr", ssc_jreal(cl->bias.temp_time_corr));
				json_object_set_new(jc, "temperature", jt);
			} else {
				json_object_set_new(jc, "temperature", json_null());
			}
			json_array_append_new(chs, jc);
		}
		json_object_set_new(ju, "channels", chs);
		json_array_append_new(units, ju);
	}
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < SSC_LOT_NT; t++) {
			const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
			const struct sscope_lot_spread *s = &T->sp;
			json_t *b = json_object(), *fl = json_array();
			const char *unit;

			conv(r, c, t, 1, &unit);
			json_object_set_new(b, "channel", json_string(r->chan[c]));
			json_object_set_new(b, "term", json_string(term_key[t]));
			json_object_set_new(b, "unit", json_string(unit));
			json_object_set_new(b, "units", json_integer((json_int_t)r->n_units));
			json_object_set_new(b, "units_resolved", json_integer((json_int_t)T->n_resolved));
			between_spec_json(b, r, c, t);
			if (!T->done) {
				json_object_set_new(b, "why", json_string(
					t == SSC_LOT_TEMPCO && !r->temp ? "no temperature column: no temperature sensitivity" :
					"fewer than 3 units show the term: no spread"));
				json_array_append_new(btw, b);
				json_decref(fl);
				continue;
			}
			json_object_set_new(b, "units_used", json_integer((json_int_t)s->k_used));
			json_object_set_new(b, "mean", ssc_jreal(conv(r, c, t, s->mean, &unit)));
			json_object_set_new(b, "mean_lo", ssc_jreal(conv(r, c, t, s->mean_lo, &unit)));
			json_object_set_new(b, "mean_lo_cut", json_boolean(T->mean_lo_cut));
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

					json_array_append_new(fl, json_string(unit_name(r, u)));
					json_object_set_new(e, "unit", json_string(unit_name(r, u)));
					json_object_set_new(e, "channel", json_string(r->chan[c]));
					json_object_set_new(e, "term", json_string(term_key[t]));
					json_object_set_new(e, "z", ssc_jreal(T->z[u]));
					json_array_append_new(outl, e);
				}
			json_object_set_new(b, "outliers", fl);
			json_array_append_new(btw, b);
		}
	json_object_set_new(o, "units", units);
	json_object_set_new(o, "between", btw);
	json_object_set_new(o, "outliers", outl);
	if (r->spec)
		json_object_set_new(o, "spec", spec_json(r));
	return o;
}

static void spec_text(FILE *f, const struct ssc_lot_result *r);

/* "v [lo, hi]" of a unit's term in its unit, or "-" */
static const char *cell_text(char *buf, size_t len, const struct ssc_lot_result *r,
			     size_t u, size_t c, int t)
{
	const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];
	const char *unit;
	char a[32], b[32], d[32];

	if (!cl->present[t]) {
		snprintf(buf, len, "-");
		return buf;
	}
	snprintf(buf, len, "%s [%s, %s]%s%s", ssc_fmt(a, sizeof(a), conv(r, c, t, cl->v[t], &unit), 4),
		 ssc_fmt(b, sizeof(b), conv(r, c, t, cl->lo[t], &unit), 3),
		 ssc_fmt(d, sizeof(d), conv(r, c, t, cl->hi[t], &unit), 3),
		 r->term[c * SSC_LOT_NT + (size_t)t].outlier[u] ? " *" : "",
		 cell_doubt(cl, t) ? " ~" : "");
	return buf;
}

/* the reasons of channel c's ~ marks, each once with its units (the
 * first 8 named) */
static void doubt_text(FILE *f, const struct ssc_lot_result *r, size_t c)
{
	const char *seen[2 * 8];
	size_t ns = 0;

	for (size_t u = 0; u < r->n_units; u++)
		for (int t = SSC_LOT_DRIFT; t <= SSC_LOT_TEMPCO; t++) {
			const char *why = cell_doubt(&r->cell[u * r->n_chan + c], t);
			size_t k = 0, named = 0;
			bool dup = false;

			for (size_t i = 0; why && i < ns; i++)
				dup |= seen[i] == why;
			if (!why || dup || ns == sizeof(seen) / sizeof(*seen))
				continue;
			seen[ns++] = why;
			fprintf(f, "~ %s:", why);
			for (size_t v = 0; v < r->n_units; v++)
				for (int e = SSC_LOT_DRIFT; e <= SSC_LOT_TEMPCO; e++) {
					if (cell_doubt(&r->cell[v * r->n_chan + c], e) != why)
						continue;
					if (named++ < 8)
						fprintf(f, "%s %s %s", k ? "," : "", unit_name(r, v),
							e == SSC_LOT_DRIFT ? "drift" : "sensitivity");
					k++;
				}
			fprintf(f, "%s (%zu)\n", named > 8 ? ", ..." : "", k);
		}
}

/* each unit's bias, drift and temperature sensitivity */
static void unit_text(FILE *f, const struct ssc_lot_result *r)
{
	const char *ub, *ud, *ut;

	for (size_t c = 0; c < r->n_chan; c++) {
		conv(r, c, SSC_LOT_BIAS, 1, &ub);
		conv(r, c, SSC_LOT_DRIFT, 1, &ud);
		conv(r, c, SSC_LOT_TEMPCO, 1, &ut);
		fprintf(f, "\n%s: each unit's bias, drift and temperature sensitivity (68.3 %% intervals, batch means of %d blocks; * an outlier; ~ doubtful, why below)\n",
			r->chan[c], SSC_LOT_BIAS_BLOCKS);
		fprintf(f, "%-20s %-34s %-34s %s\n", "unit", ub, ud, r->temp ? ut : "(no temperature column)");
		for (size_t u = 0; u < r->n_units; u++) {
			char x[80], y[80], z[80];

			if (r->cell[u * r->n_chan + c].constant) {
				fprintf(f, "%-20s constant record: every sample %s %s (a stuck sensor?): left out of every spread\n",
					unit_name(r, u),
					ssc_fmt(x, sizeof(x),
						conv(r, c, SSC_LOT_BIAS,
						     r->cell[u * r->n_chan + c].bias.bias, &ub), 6),
					ub);
				continue;
			}
			fprintf(f, "%-20s %-34s %-34s %s\n", unit_name(r, u),
				cell_text(x, sizeof(x), r, u, c, SSC_LOT_BIAS),
				cell_text(y, sizeof(y), r, u, c, SSC_LOT_DRIFT),
				r->temp ? cell_text(z, sizeof(z), r, u, c, SSC_LOT_TEMPCO) : "");
		}
		doubt_text(f, r, c);
	}
}

void ssc_lot_text(FILE *f, const void *opts, const void *result)
{
	const struct ssc_lot_result *r = result;
	char a[32];

	(void)opts;
	if (r->note[0]) {
		fprintf(f, "%s\n", r->note);
		return;
	}
	fprintf(f, "lot of %zu units; %s %% intervals; spread between units separated from each unit's own uncertainty\n",
		r->n_units, ssc_fmt(a, sizeof(a), 100 * r->level, 3));
	fprintf(f, "%-8s %-16s %-16s %-30s %-30s %-8s %s\n", "channel", "term", "unit",
		"mean [interval]", "between-unit sd [interval]", "units", "outliers");
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < SSC_LOT_NT; t++) {
			const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
			const struct sscope_lot_spread *s = &T->sp;
			const char *unit;
			char m[64], bs[64], un[32];
			bool any = false;

			conv(r, c, t, 1, &unit);
			if (t == SSC_LOT_TEMPCO && !r->temp)
				continue;
			if (!T->done) {
				fprintf(f, "%-8s %-16s %-16s shown in %zu of %zu units: fewer than 3, no spread\n",
					r->chan[c], term_label[t], unit, T->n_resolved, r->n_units);
				continue;
			}
			ssc_lot_spread_text(r, c, t, m, sizeof(m), bs, sizeof(bs));
			snprintf(un, sizeof(un), "%zu/%zu", s->k_used, r->n_units);
			fprintf(f, "%-8s %-16s %-16s %-30s %-30s %-8s", r->chan[c], term_label[t],
				unit, m, bs, un);
			for (size_t u = 0; u < r->n_units; u++)
				if (T->outlier[u]) {
					fprintf(f, "%s%s (z %s)", any ? ", " : "",
						unit_name(r, u),
						ssc_fmt(a, sizeof(a), T->z[u], 3));
					any = true;
				}
			fprintf(f, "%s\n", any ? "" : "-");
		}
	for (size_t i = 0; i < r->n_chan * SSC_LOT_NT; i++)
		if (r->term[i].mean_lo_cut) {
			fprintf(f, "(cut): the interval's lower end cut at 0 (N, B and K are not negative)\n");
			break;
		}
	unit_text(f, r);
	if (r->spec)
		spec_text(f, r);
}

/* the verdicts and Cpk against the limits */
static void spec_text(FILE *f, const struct ssc_lot_result *r)
{
	char a[32], b[32], c3[32], d[32];

	fprintf(f, "\nagainst the limits of %s (%s): each unit's %s %% interval (an upper bound where its fit does not show the term) below the limit: within spec, above: out of spec, else inconclusive\n",
		r->spec->name, r->spec->path, ssc_fmt(a, sizeof(a), 100 * SSC_LOT_SPEC_LEVEL, 3));
	{
		json_t *sj = spec_json(r), *nc = json_object_get(sj, "not_checked");

		if (json_array_size(nc))
			fprintf(f, "not checked (no channel of its kind, a line the lot does not measure, or another line gives the term):");
		for (size_t i = 0; i < json_array_size(nc); i++)
			fprintf(f, "%s %s", i ? "," : "", json_string_value(json_array_get(nc, i)));
		if (json_array_size(nc))
			fprintf(f, "\n");
		json_decref(sj);
	}
	fprintf(f, "%-8s %-16s %-16s %-10s %-7s %-7s %-13s %s\n", "channel", "term", "unit", "limit",
		"within", "out", "inconclusive", "Cpk [interval]");
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < SSC_LOT_NT; t++) {
			const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
			const char *unit;
			char cp[80];

			if (!isfinite(T->limit))
				continue;
			if (T->cpk_done)
				snprintf(cp, sizeof(cp), "%s [%s, %s]%s",
					 ssc_fmt(b, sizeof(b), T->cpk.cpk, 3),
					 ssc_fmt(c3, sizeof(c3), T->cpk.lo, 3),
					 ssc_fmt(d, sizeof(d), T->cpk.hi, 3),
					 T->cpk.n < r->n_units ? " (units showing the term only)" : "");
			else
				snprintf(cp, sizeof(cp), "- (fewer than 3 units show the term)");
			a[0] = '+';
			a[1] = '-';
			ssc_fmt(a + 2, sizeof(a) - 2, conv(r, c, t, T->limit, &unit), 4);
			fprintf(f, "%-8s %-16s %-16s %-10s %-7zu %-7zu %-13zu %s\n", r->chan[c],
				term_label[t], unit, magnitude_term(t) ? a : a + 2, T->count[SSCOPE_DATASHEET_WITHIN],
				T->count[SSCOPE_DATASHEET_OUT],
				T->count[SSCOPE_DATASHEET_INCONCLUSIVE], cp);
		}
	fprintf(f, "Cpk = (limit - mean) / (3 sigma) (+-limit: (limit - |mean|) / (3 sigma), the nearer side), sigma = sqrt(between-unit sd^2 + typical within-unit sd^2), every unit showing the term; %s %% interval (Bissell 1990); a bias term's verdict is inconclusive where its block means are correlated while the fit shows neither B nor K; drift and temperature sensitivity are judged by their conservative intervals (B, K at the fit's upper bounds where not shown)\n",
		ssc_fmt(a, sizeof(a), 100 * r->level, 3));
	for (size_t u = 0; u < r->n_units; u++) {
		bool first = true;

		fprintf(f, "%s:", unit_name(r, u));
		for (size_t c = 0; c < r->n_chan; c++)
			for (int t = 0; t < SSC_LOT_NT; t++) {
				const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];

				if (!cl->has_spec[t])
					continue;
				fprintf(f, "%s %s %s %s", first ? "" : ";", r->chan[c], term_label[t],
					sscope_datasheet_verdict_name(cl->verdict[t]));
				if (cl->gbound[t])
					fprintf(f, " (not shown, bound %s)",
						isfinite(cl->ghi[t]) ?
						ssc_fmt(a, sizeof(a), conv(r, c, t, cl->ghi[t], &(const char *){ 0 }), 3) :
						"none");
				first = false;
			}
		fprintf(f, "\n");
	}
}

void ssc_lot_summary(json_t *rows, const void *opts, const void *result)
{
	const struct ssc_lot_result *r = result;

	(void)opts;
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < SSC_LOT_NT; t++) {
			const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
			const char *unit;
			char q[48], note[96];
			size_t n_out = 0;

			if (!T->done)
				continue;
			for (size_t u = 0; u < r->n_units; u++)
				n_out += T->outlier[u];
			conv(r, c, t, 1, &unit); /* before the call that reads it */
			snprintf(q, sizeof(q), "%s between-unit sd", term_label[t]);
			snprintf(note, sizeof(note), "%zu of %zu units; %zu outlier%s",
				 T->sp.k_used, r->n_units, n_out, n_out == 1 ? "" : "s");
			ssc_summary_add(rows, r->chan[c], q,
					conv(r, c, t, T->sp.between_sd, &unit),
					conv(r, c, t, T->sp.between_lo, &unit),
					conv(r, c, t, T->sp.between_hi, &unit), unit, note);
			if (n_out)
				ssc_summary_warn_last(rows);
		}
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < SSC_LOT_NT; t++) {
			const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
			const char *unit;
			char q[96], note[128], a[32];

			if (!isfinite(T->limit))
				continue;
			ssc_fmt(a, sizeof(a), conv(r, c, t, T->limit, &unit), 4);
			snprintf(q, sizeof(q), "%s Cpk (limit %s %s)", term_label[t], a, unit);
			snprintf(note, sizeof(note), "%zu within spec, %zu out of spec, %zu inconclusive of %zu units%s",
				 T->count[SSCOPE_DATASHEET_WITHIN], T->count[SSCOPE_DATASHEET_OUT],
				 T->count[SSCOPE_DATASHEET_INCONCLUSIVE], r->n_units,
				 T->cpk_done ? "" : "; fewer than 3 units show the term: no Cpk");
			ssc_summary_add(rows, r->chan[c], q, T->cpk_done ? T->cpk.cpk : (double)NAN,
					T->cpk_done ? T->cpk.lo : (double)NAN,
					T->cpk_done ? T->cpk.hi : (double)NAN, "", note);
			if (T->count[SSCOPE_DATASHEET_OUT] || !T->cpk_done)
				ssc_summary_warn_last(rows);
		}
}

void ssc_lot_merged_free(struct ssc_lot_merged *m)
{
	for (size_t i = 0; m->units && i < m->n; i++)
		json_decref(m->units[i]);
	free(m->units);
	free(m->paths);
	free(m->labels);
	json_decref(m->plan);
	memset(m, 0, sizeof(*m));
}

void ssc_lot_free(void *result)
{
	struct ssc_lot_result *r = result;

	if (!r)
		return;
	for (size_t i = 0; r->cell && i < r->n_units * r->n_chan; i++) {
		free(r->cell[i].tau_s);
		free(r->cell[i].adev);
		free(r->cell[i].fig_cs);
	}
	for (size_t c = 0; r->chan && r->chan[c]; c++)
		free(r->chan[c]);
	for (size_t i = 0; r->term && i < r->n_chan * SSC_LOT_NT; i++) {
		free(r->term[i].outlier);
		free(r->term[i].z);
	}
	free(r->term);
	free(r->cell);
	free(r->chan);
	free(r->q);
	free(r->spec);
	free(r->rate_hz);
	free(r->n_samples);
	if (r->merged) {
		ssc_lot_merged_free(r->merged);
		free(r->merged);
	}
	free(r);
}

/* ------------------------------------------------------------ figures */

#define LOT_MAX_PANELS 6

static int cmp_dbl(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return (x > y) - (x < y);
}

/* the p-quantile (0..1) of the finite w[0..k), sorted in place; NaN
 * when none */
static double quantile_of(double *w, size_t k, double p)
{
	size_t m = 0;
	double h;

	for (size_t i = 0; i < k; i++)
		if (isfinite(w[i]))
			w[m++] = w[i];
	if (!m)
		return NAN;
	qsort(w, m, sizeof(double), cmp_dbl);
	h = p * (double)(m - 1);
	return w[(size_t)h] + (h - floor(h)) * (w[(size_t)ceil(h)] - w[(size_t)h]);
}

/* PATH with @p tag before its extension (".{svg,png}" kept whole) */
static char *tagged_path(const char *path, const char *tag)
{
	size_t l = strlen(path), k = strlen(SSC_PLOT_SVG_AND_PNG);
	const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
	size_t at = l;
	char *p;

	if (l > k && !strcmp(path + l - k, SSC_PLOT_SVG_AND_PNG))
		at = l - k;
	else if (dot && (!slash || dot > slash))
		at = (size_t)(dot - path);
	p = malloc(l + strlen(tag) + 1);
	if (p)
		sprintf(p, "%.*s%s%s", (int)at, path, tag, path + at);
	return p;
}

/* the shortest record, s */
static double shortest_s(const struct ssc_lot_result *r)
{
	double d = INFINITY;

	for (size_t u = 0; u < r->n_units; u++)
		d = fmin(d, (double)r->n_samples[u] / r->rate_hz[u]);
	return d;
}

/* the compensated sum of a unit's samples before sample i (real: linear
 * within a block of the figure's record; exact at the block ends) */
static double sum_before(const struct ssc_lot_cell *cl, size_t n, double i)
{
	size_t j = (size_t)(i / (double)cl->fig_block), a, b;

	if (j >= cl->fig_k)
		return cl->fig_cs[cl->fig_k];
	a = j * cl->fig_block;
	b = a + cl->fig_block < n ? a + cl->fig_block : n;
	return cl->fig_cs[j] + (i - (double)a) / (double)(b - a) *
				       (cl->fig_cs[j + 1] - cl->fig_cs[j]);
}

/* unit u's moving mean of channel c over w_s at the times t[0..m), in
 * SI; NaN where the window holds no sample */
static void moving_mean(const struct ssc_lot_result *r, size_t u, size_t c,
			double w_s, const double *t, size_t m, double *out)
{
	const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];
	size_t n = r->n_samples[u];
	double fs = r->rate_hz[u];

	for (size_t j = 0; j < m; j++) {
		double a = (t[j] - w_s / 2) * fs, b = (t[j] + w_s / 2) * fs;
		size_t i0 = a <= 0 ? 0 : (size_t)fmin(a, (double)n);
		size_t i1 = b <= 0 ? 0 : (size_t)fmin(b, (double)n);

		out[j] = i1 > i0 ? cl->fig_mean + (sum_before(cl, n, (double)i1) -
						   sum_before(cl, n, (double)i0)) /
						  (double)(i1 - i0) :
				   (double)NAN;
	}
}

/* a unit's line: outliers (in the terms @p lo..hi) thick and named so */
static void unit_style(const struct ssc_lot_result *r, size_t c, size_t u, int lo, int hi,
		       struct ssc_style *st, char *label, size_t len)
{
	bool out = false;

	for (int t = lo; t <= hi; t++)
		out |= r->term[c * SSC_LOT_NT + (size_t)t].outlier[u];
	memset(st, 0, sizeof(*st));
	/* the palette without its red, which marks the outliers */
	st->color = out ? 0xd62728 : ssc_plot_color(u % 9 + (u % 9 >= 3));
	st->width = out ? 3 : 1.2;
	st->dash = out ? SSC_SOLID : u >= 9 ? SSC_DASHED : SSC_SOLID;
	snprintf(label, len, "%s%s", unit_name(r, u), out ? " (outlier)" : "");
}

static int bias_panel(struct ssc_ax *ax, const struct ssc_lot_result *r, size_t c,
		      double w_s, double dur_s)
{
	size_t U = r->n_units, m = 400;
	double *t = malloc(m * sizeof(double)), *tp = malloc(m * sizeof(double));
	double *y = malloc(U * m * sizeof(double)), *w = malloc(U * sizeof(double));
	double *lo = malloc(m * sizeof(double)), *hi = malloc(m * sizeof(double));
	double *med = malloc(m * sizeof(double)), ts = dur_s >= 3 * 3600 ? 3600 :
						     dur_s >= 180 ? 60 : 1;
	const char *unit;
	double sc = conv(r, c, SSC_LOT_BIAS, 1, &unit);
	char lab[160];
	int rc = 0;

	if (!t || !tp || !y || !w || !lo || !hi || !med) {
		rc = -ENOMEM;
		goto out;
	}
	for (size_t j = 0; j < m; j++) {
		t[j] = w_s / 2 + (dur_s - w_s) * (double)j / (double)(m - 1);
		tp[j] = t[j] / ts;
	}
	for (size_t u = 0; u < U; u++) {
		moving_mean(r, u, c, w_s, t, m, y + u * m);
		for (size_t j = 0; j < m; j++)
			y[u * m + j] *= sc;
	}
	for (size_t j = 0; j < m && !rc; j++) {
		size_t k = 0;

		for (size_t u = 0; u < U; u++)
			if (!r->term[c * SSC_LOT_NT + SSC_LOT_BIAS].outlier[u])
				w[k++] = y[u * m + j];
		lo[j] = quantile_of(w, k, 0.05);
		hi[j] = quantile_of(w, k, 0.95);
		med[j] = quantile_of(w, k, 0.5);
	}
	if (!rc)
		rc = ssc_ax_band(ax, tp, lo, hi, m, 0x7f7f7f, 0.25,
				 "5-95 % of the units (outliers out)");
	for (size_t u = 0; u < U && !rc; u++) {
		struct ssc_style st;

		unit_style(r, c, u, SSC_LOT_BIAS, SSC_LOT_TEMPCO, &st, lab, sizeof(lab));
		rc = ssc_ax_line(ax, tp, y + u * m, m, &st, lab);
	}
	if (!rc) {
		struct ssc_style st = { .color = 0x010101, .width = 2.5, .dash = SSC_DASHED };

		rc = ssc_ax_line(ax, tp, med, m, &st, "median of the units");
	}
	if (!rc) {
		char a[32];

		snprintf(lab, sizeof(lab), "%s: bias, moving mean over %s s", r->chan[c],
			 ssc_fmt(a, sizeof(a), w_s, 3));
		ssc_ax_title(ax, lab);
		ssc_ax_xlabel(ax, ts == 3600 ? "time [h]" : ts == 60 ? "time [min]" : "time [s]");
		snprintf(lab, sizeof(lab), "bias [%s]", unit);
		ssc_ax_ylabel(ax, lab);
		ssc_ax_grid(ax, true);
	}
out:
	free(t);
	free(tp);
	free(y);
	free(w);
	free(lo);
	free(hi);
	free(med);
	return rc;
}

static int adev_panel(struct ssc_ax *ax, const struct ssc_lot_result *r, size_t c)
{
	const struct ssc_lot_cell *c0 = &r->cell[c];
	size_t U = r->n_units, m = c0->n_adev;
	double *med = malloc((m + 1) * sizeof(double)), *w = malloc(U * sizeof(double));
	double *y = NULL;
	const char *unit;
	double sc = conv(r, c, SSC_LOT_BIAS, 1, &unit);
	char lab[160];
	int rc = 0;

	if (!med || !w) {
		rc = -ENOMEM;
		goto out;
	}
	for (size_t u = 0; u < U && !rc; u++) {
		const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];
		struct ssc_style st;

		free(y);
		y = malloc((cl->n_adev + 1) * sizeof(double));
		if (!y) {
			rc = -ENOMEM;
			break;
		}
		for (size_t i = 0; i < cl->n_adev; i++)
			y[i] = cl->adev[i] * sc;
		unit_style(r, c, u, SSC_LOT_N, SSC_LOT_K, &st, lab, sizeof(lab));
		rc = ssc_ax_line(ax, cl->tau_s, y, cl->n_adev, &st, lab);
	}
	/* the median at the first unit's taus, over the units with that tau
	 * (all of them when the records are alike) */
	for (size_t i = 0; i < m && !rc; i++) {
		size_t k = 0;

		for (size_t u = 0; u < U; u++) {
			const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];

			for (size_t j = 0; j < cl->n_adev; j++)
				if (fabs(cl->tau_s[j] - c0->tau_s[i]) <= 1e-9 * c0->tau_s[i]) {
					w[k++] = cl->adev[j] * sc;
					break;
				}
		}
		med[i] = 2 * k > U ? quantile_of(w, k, 0.5) : (double)NAN;
	}
	if (!rc) {
		struct ssc_style st = { .color = 0x010101, .width = 2.5, .dash = SSC_DASHED };

		rc = ssc_ax_line(ax, c0->tau_s, med, m, &st, "median of the units");
	}
	if (!rc) {
		snprintf(lab, sizeof(lab), "%s: Allan deviation (OADEV) of each unit", r->chan[c]);
		ssc_ax_title(ax, lab);
		ssc_ax_log(ax, true, true);
		ssc_ax_xlabel(ax, "tau [s]");
		snprintf(lab, sizeof(lab), "Allan deviation [%s]", unit);
		ssc_ax_ylabel(ax, lab);
		ssc_ax_grid(ax, true);
	}
out:
	free(y);
	free(med);
	free(w);
	return rc;
}

int ssc_lot_plot(const struct ssc_common *co, const void *opts,
		 const void *result, const char *path)
{
	const struct ssc_lot_result *r = result;
	size_t n = r->n_chan < LOT_MAX_PANELS ? r->n_chan : LOT_MAX_PANELS;
	double dur = shortest_s(r), w = r->smooth_s > 0 ? r->smooth_s : dur / 100;
	char *apath = tagged_path(path, "-adev"), title[160];
	int rc = 0;

	(void)opts;
	if (!apath)
		return ssc_fail(co->cmd, -ENOMEM, NULL, NULL);
	if (r->n_chan > n)
		ssc_warn(co, "--plot: %zu channels; the figures show the first %d", r->n_chan,
			 LOT_MAX_PANELS);
	if (w >= dur / 2) {
		ssc_err(co->cmd, "--smooth: %g s is not shorter than half the shortest record (%g s)",
			w, dur);
		free(apath);
		return SSC_EXIT_FAIL;
	}
	snprintf(title, sizeof(title), "Lot of %zu units: biases against time", r->n_units);
	for (int f = 0; f < 2 && !rc; f++) {
		struct ssc_fig *fig = ssc_fig_new(1050, (int)(n * 420 + 60), (int)n, 1);
		const char *p = f ? apath : path;

		if (!fig) {
			rc = -ENOMEM;
			break;
		}
		ssc_fig_title(fig, f ? "Lot: Allan deviations of the units" : title);
		for (size_t c = 0; c < n && !rc; c++)
			rc = f ? adev_panel(ssc_fig_ax(fig, (int)c, 0), r, c) :
				 bias_panel(ssc_fig_ax(fig, (int)c, 0), r, c, w, dur);
		if (!rc) {
			rc = ssc_fig_save(fig, p);
			if (rc) {
				ssc_fig_free(fig);
				rc = ssc_write_failed(co->cmd, p, rc);
				free(apath);
				return rc;
			}
		}
		ssc_fig_free(fig);
	}
	free(apath);
	return rc ? ssc_fail(co->cmd, rc, NULL, NULL) : SSC_EXIT_OK;
}
