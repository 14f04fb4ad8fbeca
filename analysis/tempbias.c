/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Temperature dependence of a bias: weighted least squares of a polynomial
 * in the centred and scaled temperature with heating/cooling hysteresis
 * (IEEE Std 528-2019, "hysteresis") and thermal-gradient terms, order by
 * the extra-sum-of-squares F test (Draper & Smith, Applied Regression
 * Analysis, 3rd ed., sec. 6.1), turn-on to turn-on repeatability as the
 * spread of per-run settled biases, in-run stability as the minimum
 * Allan deviation (IEEE Std 952-2020) of the compensated residuals.
 * See sscope-tempbias.h for the model and the choices.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit.h>
#include <gsl/gsl_vector.h>

#include "sscope-allan.h"
#include "sscope-tempbias.h"

#define MAXK SSCOPE_TEMPBIAS_MAX_ORDER
#define NREG (MAXK + 2) /* u^1..u^K, s, dT/dt */

/* Blocks of one run. */
struct blocks {
	size_t nb;
	double dt;       /* block duration, s */
	double *t;       /* block centre, s from the run start */
	double *temp;    /* raw mean temperature (NaN: none) */
	double *x;       /* mean datum (NaN: none) */
	double *c;       /* finite samples in the block */
	double *ts;      /* smoothed temperature */
	double *dtdt;    /* dT/dt, degC/s */
	int *state;      /* -1, 0, +1 */
	size_t *bin;     /* bin of the block (SIZE_MAX: none) */
	size_t first;    /* first block used (after warm-up) */
};

/* Accumulator of a bin. */
struct acc {
	double n, x, temp, dtdt, u[MAXK + 1];
	int state, run;
};

struct fit {
	int K;
	bool hyst, grad;
	size_t p, rows;
	double beta[SSCOPE_TEMPBIAS_MAX_RUNS + NREG];
	double cov[SSCOPE_TEMPBIAS_MAX_RUNS + NREG][SSCOPE_TEMPBIAS_MAX_RUNS + NREG];
	double chisq, dof, rcond;
	double s2; /* chisq / dof: cov = s2 (X'WX)^-1 */
};

static void free_blocks(struct blocks *b)
{
	free(b->t);
	free(b->temp);
	free(b->x);
	free(b->c);
	free(b->ts);
	free(b->dtdt);
	free(b->state);
	free(b->bin);
}

static int make_blocks(const struct sscope_tempbias_run *r, double block_s,
		       struct blocks *b)
{
	size_t m0 = ssc_count(fmax(1, round(r->rate_hz * block_s)));
	size_t nb = (r->n + m0 - 1) / m0;

	memset(b, 0, sizeof(*b));
	b->nb = nb;
	b->dt = (double)m0 / r->rate_hz;
	b->t = ssc_alloc_array(nb, sizeof(double));
	b->temp = ssc_alloc_array(nb, sizeof(double));
	b->x = ssc_alloc_array(nb, sizeof(double));
	b->c = ssc_alloc_array(nb, sizeof(double));
	b->ts = ssc_alloc_array(nb, sizeof(double));
	b->dtdt = ssc_alloc_array(nb, sizeof(double));
	b->state = ssc_alloc_array(nb, sizeof(int));
	b->bin = ssc_alloc_array(nb, sizeof(size_t));
	if (!b->t || !b->temp || !b->x || !b->c || !b->ts || !b->dtdt ||
	    !b->state || !b->bin)
		return -ENOMEM;
	for (size_t i = 0; i < nb; i++) {
		size_t lo = i * m0, hi = lo + m0 < r->n ? lo + m0 : r->n;
		double sx = 0, st = 0, cx = 0, ct = 0;

		for (size_t k = lo; k < hi; k++) {
			double x = r->x[k * r->stride], t = r->temp_degc[k];

			if (isfinite(t)) {
				st += t;
				ct++;
				if (isfinite(x)) {
					sx += x;
					cx++;
				}
			}
		}
		b->t[i] = ((double)lo + (double)(hi - lo - 1) / 2) / r->rate_hz;
		b->temp[i] = ct > 0 ? st / ct : (double)NAN;
		b->x[i] = cx > 0 ? sx / cx : (double)NAN;
		b->c[i] = cx;
	}
	return 0;
}

/* Centred local linear fit of the temperature over +-h blocks. */
static void smooth(struct blocks *b, size_t h)
{
	for (size_t i = 0; i < b->nb; i++) {
		size_t lo = i > h ? i - h : 0, hi = i + h + 1 < b->nb ? i + h + 1 : b->nb;
		double n = 0, st = 0, stt = 0, sy = 0, sty = 0;

		for (size_t k = lo; k < hi; k++) {
			double dt = b->t[k] - b->t[i];

			if (!isfinite(b->temp[k]))
				continue;
			n++;
			st += dt;
			stt += dt * dt;
			sy += b->temp[k];
			sty += dt * b->temp[k];
		}
		if (n < 2) {
			b->ts[i] = n > 0 ? sy / n : (double)NAN;
			b->dtdt[i] = n > 0 ? 0 : (double)NAN;
			continue;
		}
		{
			double den = n * stt - st * st;
			double slope = den > 0 ? (n * sty - st * sy) / den : 0;

			b->dtdt[i] = slope;
			b->ts[i] = (sy - slope * st) / n;
		}
	}
}

/* Turning points of the smoothed temperature: the state changes at an
 * extremum once the temperature has left it by more than band_degc; the
 * samples after the extremum get the new state. */
static void set_states_turning(struct blocks *b, double band)
{
	int s = 0;
	size_t imin = 0, imax = 0, start = 0;

	while (start < b->nb && !isfinite(b->ts[start]))
		b->state[start++] = 0;
	imin = imax = start;
	for (size_t i = start; i < b->nb; i++) {
		double T = b->ts[i];

		b->state[i] = s;
		if (!isfinite(T))
			continue;
		if (T > b->ts[imax])
			imax = i;
		if (T < b->ts[imin])
			imin = i;
		if (s <= 0 && T > b->ts[imin] + band) {
			for (size_t k = imin + 1; k <= i; k++)
				b->state[k] = 1;
			s = 1;
			imax = i;
		} else if (s >= 0 && T < b->ts[imax] - band) {
			for (size_t k = imax + 1; k <= i; k++)
				b->state[k] = -1;
			s = -1;
			imin = i;
		}
	}
}

static void set_states(struct blocks *b, double db)
{
	int s = 0;

	for (size_t i = 0; i < b->nb; i++) {
		if (b->dtdt[i] > db)
			s = 1;
		else if (b->dtdt[i] < -db)
			s = -1;
		b->state[i] = s;
	}
}

static void add_note(struct sscope_tempbias_result *res, const char *text)
{
	size_t l = strlen(res->note);

	snprintf(res->note + l, sizeof(res->note) - l, "%s%s", l ? "; " : "",
		 text);
}

/* Weighted fit of the binned rows; columns: J run offsets, u^1..u^K,
 * s (hyst), dT/dt scaled by gsc (grad). */
static int do_fit(const struct acc *bins, size_t nbins, size_t J, int K,
		  bool hyst, bool grad, double gsc, struct fit *f)
{
	size_t rows = 0, p = J + (size_t)K + hyst + grad;
	gsl_matrix *X, *cov;
	gsl_vector *y, *w, *c;
	gsl_multifit_linear_workspace *ws;
	struct ssc_gsl_quiet quiet;
	bool bad;
	int rc = 0;

	for (size_t i = 0; i < nbins; i++)
		rows += bins[i].n > 0;
	f->K = K;
	f->hyst = hyst;
	f->grad = grad;
	f->p = p;
	f->rows = rows;
	if (rows <= p)
		return -EDOM;
	X = gsl_matrix_calloc(rows, p);
	cov = gsl_matrix_alloc(p, p);
	y = gsl_vector_alloc(rows);
	w = gsl_vector_alloc(rows);
	c = gsl_vector_alloc(p);
	ws = gsl_multifit_linear_alloc(rows, p);
	if (!X || !cov || !y || !w || !c || !ws) {
		rc = -ENOMEM;
		goto out;
	}
	rows = 0;
	for (size_t i = 0; i < nbins; i++) {
		const struct acc *a = &bins[i];
		size_t col = J;

		if (!(a->n > 0))
			continue;
		gsl_matrix_set(X, rows, (size_t)a->run, 1);
		for (int k = 1; k <= K; k++)
			gsl_matrix_set(X, rows, col++, a->u[k] / a->n);
		if (hyst)
			gsl_matrix_set(X, rows, col++, a->state);
		if (grad)
			gsl_matrix_set(X, rows, col++, a->dtdt / a->n / gsc);
		gsl_vector_set(y, rows, a->x / a->n);
		gsl_vector_set(w, rows, a->n);
		rows++;
	}
	/* a rank-deficient design is a result here (-EDOM), not a fault */
	ssc_gsl_quiet_begin(&quiet);
	bad = gsl_multifit_wlinear(X, w, y, c, cov, &f->chisq, ws) != 0;
	if (!bad)
		f->rcond = gsl_multifit_linear_rcond(ws);
	ssc_gsl_quiet_end(&quiet);
	if (bad) {
		rc = -EDOM;
		goto out;
	}
	f->dof = (double)(rows - p);
	f->s2 = f->chisq / f->dof;
	for (size_t i = 0; i < p; i++) {
		f->beta[i] = gsl_vector_get(c, i);
		for (size_t j = 0; j < p; j++)
			f->cov[i][j] = gsl_matrix_get(cov, i, j) * f->chisq / f->dof;
	}
	if (!(f->rcond > 1e-10))
		rc = -EDOM;
out:
	gsl_matrix_free(X);
	gsl_matrix_free(cov);
	gsl_vector_free(y);
	gsl_vector_free(w);
	gsl_vector_free(c);
	if (ws)
		gsl_multifit_linear_free(ws);
	return rc;
}

/* Model value of the fit for regressors (without the run offset). */
static double model_shape(const struct fit *f, size_t J, double u, int s,
			  double dtdt, double gsc)
{
	double v = 0, uk = 1;
	size_t col = J;

	for (int k = 1; k <= f->K; k++) {
		uk *= u;
		v += f->beta[col++] * uk;
	}
	if (f->hyst)
		v += f->beta[col++] * s;
	if (f->grad)
		v += f->beta[col++] * dtdt / gsc;
	return v;
}

struct ctx {
	const struct sscope_tempbias_opts *o;
	struct blocks *b;
	size_t J;
	double tref, h, tmin, tmax, bin_w, gsc;
	size_t nbt;
	struct acc *bins;
	size_t nbins;
};

/* a block's bin key: run, temperature cell, heating/cooling state and
 * rate class (dT/dt in steps of RATE_CLASS rms dT/dt, clamped) */
#define RATE_CLASS 0.125
#define NCLASS 257
struct keyed {
	uint64_t key;
	size_t j, i;
};

static int cmp_keyed(const void *a, const void *b)
{
	const struct keyed *x = a, *y = b;

	if (x->key != y->key)
		return (x->key > y->key) - (x->key < y->key);
	if (x->j != y->j)
		return (x->j > y->j) - (x->j < y->j);
	return (x->i > y->i) - (x->i < y->i);
}

/*
 * Bins of (run, temperature cell, state, rate class) holding the
 * sample-weighted sums of every regressor.  The rate class keeps passes
 * through the same temperature at different rates apart (a fast and a
 * slow heating ramp): merged, their mean dT/dt would be the same in every
 * heating bin and the gradient term inseparable from the state.
 */
static int fill_bins(struct ctx *c, bool with_state)
{
	struct keyed *k;
	size_t m = 0, nb = 0;

	for (size_t j = 0; j < c->J; j++)
		nb += c->b[j].nb;
	k = ssc_alloc_array(nb ? nb : 1, sizeof(*k));
	if (!k)
		return -ENOMEM;
	for (size_t j = 0; j < c->J; j++) {
		struct blocks *b = &c->b[j];

		for (size_t i = 0; i < b->nb; i++) {
			double T = b->ts[i], cl;
			size_t bi;
			int s = with_state ? b->state[i] : 0;

			b->bin[i] = SIZE_MAX;
			if (i < b->first || !(b->c[i] > 0) || !isfinite(T) ||
			    !isfinite(b->x[i]))
				continue;
			bi = ssc_count(floor((T - c->tmin) / c->bin_w));
			if (bi >= c->nbt)
				bi = c->nbt - 1;
			cl = floor(b->dtdt[i] / (RATE_CLASS * c->gsc)) + NCLASS / 2;
			cl = isfinite(cl) ? fmin(fmax(cl, 0), NCLASS - 1) : NCLASS / 2;
			k[m].key = (((uint64_t)j * c->nbt + bi) * 3 + (uint64_t)(s + 1)) *
					   NCLASS + (uint64_t)cl;
			k[m].j = j;
			k[m].i = i;
			m++;
		}
	}
	qsort(k, m, sizeof(*k), cmp_keyed);
	c->nbins = 0;
	for (size_t e = 0; e < m; e++) {
		struct blocks *b = &c->b[k[e].j];
		size_t i = k[e].i;
		double u, uk = 1, w = b->c[i];
		struct acc *a;

		if (e == 0 || k[e].key != k[e - 1].key) {
			a = &c->bins[c->nbins++];
			memset(a, 0, sizeof(*a));
			a->state = with_state ? b->state[i] : 0;
			a->run = (int)k[e].j;
		}
		a = &c->bins[c->nbins - 1];
		b->bin[i] = c->nbins - 1;
		u = (b->ts[i] - c->tref) / c->h;
		a->n += w;
		a->x += w * b->x[i];
		a->temp += w * b->ts[i];
		a->dtdt += w * b->dtdt[i];
		for (int q = 1; q <= MAXK; q++) {
			uk *= u;
			a->u[q] += w * uk;
		}
	}
	free(k);
	return 0;
}

/* Fit with the terms wanted, dropping gradient, hysteresis, then order
 * while the design is singular. */
static int fit_terms(struct ctx *c, int K, bool *hyst, bool *grad,
		     struct fit *f, char *note, size_t nlen)
{
	int rc;

	for (;;) {
		rc = do_fit(c->bins, c->nbins, c->J, K, *hyst, *grad, c->gsc, f);
		if (rc != -EDOM)
			return rc;
		if (*grad) {
			*grad = false;
			snprintf(note, nlen, "gradient term left out (not separable from the other terms)");
		} else if (*hyst) {
			*hyst = false;
			snprintf(note, nlen, "hysteresis term left out (not separable from the other terms)");
		} else if (K > 0) {
			K--;
		} else {
			return -EDOM;
		}
	}
}

static double f_pvalue(const struct fit *lo, const struct fit *hi)
{
	double F;

	if (!(hi->dof > 0) || !(hi->chisq > 0))
		return 0;
	F = (lo->chisq - hi->chisq) / (hi->chisq / hi->dof);
	if (!(F > 0))
		return 1;
	return gsl_cdf_fdist_Q(F, (double)(hi->p - lo->p), hi->dof);
}

/*
 * Variance inflation factor of the gradient column: 1 / (1 - R^2) of the
 * weighted regression of the bins' mean dT/dt on the other columns (run
 * offsets, u^1..u^K, the heating/cooling state).  Ramps of two rates
 * make dT/dt = a + b s outside the turning points, exactly collinear
 * with the offsets and the state; only a rate that varies within heating
 * or within cooling (a sine cycle, several ramp rates, soaks at constant
 * temperature) separates the two terms.  Returns NAN when not computable.
 */
static double gradient_vif(const struct ctx *c, int K)
{
	struct fit *t = calloc(1, sizeof(*t));
	struct acc *b2 = ssc_alloc_array(c->nbins, sizeof(*b2));
	double vif = NAN, sw = 0, sy = 0, syy = 0;

	if (!t || !b2)
		goto out;
	/* the same bins with y = dT/dt (scaled) */
	for (size_t i = 0; i < c->nbins; i++) {
		b2[i] = c->bins[i];
		b2[i].x = c->bins[i].dtdt / c->gsc;
		if (b2[i].n > 0) {
			double y = b2[i].x / b2[i].n;

			sw += b2[i].n;
			sy += b2[i].n * y;
			syy += b2[i].n * y * y;
		}
	}
	if (!(sw > 0))
		goto out;
	{
		double tss = syy - sy * sy / sw;
		int rc = do_fit(b2, c->nbins, c->J, K, true, false, c->gsc, t);

		if (rc == -EDOM && t->rows > t->p)
			vif = INFINITY; /* singular: collinear */
		else if (!rc && tss > 0)
			vif = tss / fmax(t->chisq, tss * 1e-300);
	}
out:
	free(t);
	free(b2);
	return vif;
}

/* Weighted polynomial of order K in u on bins of one state; y corrected. */
static int split_fit(const struct ctx *c, const struct fit *f, int state,
		     double *coef, double *umin, double *umax)
{
	size_t rows = 0, p = (size_t)f->K + 1;
	gsl_matrix *X = NULL, *cov = NULL;
	gsl_vector *y = NULL, *w = NULL, *cv = NULL;
	gsl_multifit_linear_workspace *ws = NULL;
	double chisq, dmean = 0;
	int rc = -EDOM;

	for (size_t j = 0; j < c->J; j++)
		dmean += f->beta[j] / (double)c->J;
	for (size_t i = 0; i < c->nbins; i++)
		rows += c->bins[i].n > 0 && c->bins[i].state == state;
	if (rows < p + 2)
		return -EDOM;
	X = gsl_matrix_alloc(rows, p);
	cov = gsl_matrix_alloc(p, p);
	y = gsl_vector_alloc(rows);
	w = gsl_vector_alloc(rows);
	cv = gsl_vector_alloc(p);
	ws = gsl_multifit_linear_alloc(rows, p);
	if (!X || !cov || !y || !w || !cv || !ws) {
		rc = -ENOMEM;
		goto out;
	}
	*umin = INFINITY;
	*umax = -INFINITY;
	rows = 0;
	for (size_t i = 0; i < c->nbins; i++) {
		const struct acc *a = &c->bins[i];
		double v = a->x / a->n - (f->beta[a->run] - dmean);
		double u = (a->temp / a->n - c->tref) / c->h;

		if (!(a->n > 0) || a->state != state)
			continue;
		if (f->grad)
			v -= f->beta[c->J + (size_t)f->K + f->hyst] * a->dtdt / a->n / c->gsc;
		gsl_matrix_set(X, rows, 0, 1);
		for (int k = 1; k <= f->K; k++)
			gsl_matrix_set(X, rows, (size_t)k, a->u[k] / a->n);
		gsl_vector_set(y, rows, v);
		gsl_vector_set(w, rows, a->n);
		*umin = fmin(*umin, u);
		*umax = fmax(*umax, u);
		rows++;
	}
	if (gsl_multifit_wlinear(X, w, y, cv, cov, &chisq, ws) ||
	    !(gsl_multifit_linear_rcond(ws) > 1e-10))
		goto out;
	for (size_t k = 0; k < p; k++)
		coef[k] = gsl_vector_get(cv, k);
	rc = 0;
out:
	gsl_matrix_free(X);
	gsl_matrix_free(cov);
	gsl_vector_free(y);
	gsl_vector_free(w);
	gsl_vector_free(cv);
	if (ws)
		gsl_multifit_linear_free(ws);
	return rc;
}

static double horner(const double *a, int K, double u)
{
	double v = 0;

	for (int k = K; k >= 0; k--)
		v = v * u + a[k];
	return v;
}

/* Residual of block i of run j under fit f. */
static double block_resid(const struct ctx *c, const struct fit *f, size_t j,
			  size_t i)
{
	const struct blocks *b = &c->b[j];

	if (!(b->c[i] > 0) || !isfinite(b->ts[i]) || !isfinite(b->x[i]))
		return (double)NAN;
	return b->x[i] - f->beta[j] -
	       model_shape(f, c->J, (b->ts[i] - c->tref) / c->h,
			   f->hyst ? b->state[i] : 0, b->dtdt[i], c->gsc);
}

/*
 * Coefficient covariance under a noise model of the block errors: white
 * noise (variance sigma^2 for a full block of cbar samples, sigma^2 cbar /
 * c_i for c_i samples), a random walk of the bias (variance lambda
 * sigma^2 per second: IEEE 952's rate random walk K, or any slow
 * wander) and flicker (bias instability B: a bank of Gauss-Markov
 * processes of variance g sigma^2 each, time constants 10^(2/3) apart,
 * which has a 1/f spectrum between its first and last), independent
 * between runs.  The binned estimate is beta =
 * A^-1 sum_i h_i y_i over the blocks i in time order (A = X'WX of the
 * bins, h_i = c_i xbar_b(i), xbar the mean regressors of block i's bin),
 * so its covariance is A^-1 (sum_ij h_i h_j' Cov(e_i, e_j)) A^-1 =
 * sigma^2 A^-1 (cbar sum_i c_i xbar xbar' + lambda sum_k dt_k R_k R_k')
 * A^-1, with R_k = sum_{i >= k} h_i and dt_k the time from block k - 1
 * to k: the walk's covariance min(t_i, t_j) summed by parts (its value at
 * the run's first block is the run offset d_j).  lambda and sigma^2 are
 * the restricted maximum likelihood (REML, Patterson & Thompson 1971) of
 * the residuals given the design: the generalised least squares of the
 * design under the model, by a Kalman filter per run (the local-level
 * model, with the processes in its state; the filter's innovations over
 * their sd are the whitened vectors), the run offsets profiled out, each
 * level on a grid in its log then by golden sections; the model (white,
 * walk, flicker, or walk and flicker) is the best REML less one per level
 * (Akaike).  The flicker part of the covariance is g sigma^2 sum_ij
 * exp(-|t_i - t_j| / tc) h_i h_j' per process.  The model is fitted and
 * applied on groups of consecutive blocks (at most RW_GROUPS per run),
 * which keeps the filter's cost at that of the walk alone on the blocks.
 *
 * Why a model and not a kernel: a random walk's residuals are not
 * stationary, and the Bartlett (Newey-West) long-run covariance with a
 * bandwidth of 1/25 of the run, used before, was 1.4-1.5 times too
 * narrow on ramps of unequal rates and 1.35-2 times too wide on a sine
 * cycle with a rate random walk of 3 deg/h/sqrt(h) (tests/bench-tempbias.c
 * coverage).  Without flicker in the model, its slow part went into
 * lambda, and on those ramps with bias instability the intervals were
 * too wide (93 / 96 % for 68.3 %, rms z 0.53; a bank of three processes
 * with a free time constant: 77 / 83 %; the whole bank: 70 / 72 %).  For
 * white residuals lambda and g are 0 and the covariance is the classical
 * one with the REML variance.
 * Returns 0, or -ENOMEM.
 */
struct rwrun {
	size_t m;       /* used blocks */
	double *t;      /* their times, s */
	double *d;      /* cbar / c_i */
	double *z;      /* m x (q + 1): 1, the regressors, the residual */
	double *h;      /* m x q: the scores' regressors c_i xbar */
};

#define RW_V (NREG + 2) /* vectors of the filter: 1, regressors, e */
#define GM_MAXN 10        /* flicker: at most this many processes */
#define GM_S (GM_MAXN + 1) /* the filter's state: the walk, the processes */
#define SSC_GM_RATIO 4.6415888336127788 /* 10^(2/3) */

/* the noise model's levels relative to sigma^2: the walk's variance per
 * second lambda and flicker g: a sum of ngm first-order Gauss-Markov
 * processes of variance g each, time constants tc[], a constant ratio
 * apart (equal variances per ratio of time constant: a 1/f spectrum
 * between the first and the last; g 0: none) */
struct rwpar {
	double lambda, g;
	int ngm;
	double tc[GM_MAXN];
};

/* REML log-likelihood at p (sigma^2 profiled out); s2 receives sigma^2.
 * -inf when not computable.  The filter's state is the walk and the
 * Gauss-Markov processes (their sum plus the white noise is observed). */
static double rw_reml(const struct rwrun *rr, size_t J, size_t q,
		      const struct rwpar *p, double *s2)
{
	size_t nv = q + 1, nx = q - 1, n_tot = 0;
	double W[RW_V][RW_V] = { { 0 } }, logdet = 0, logda = 0, Q;
	double Cx[RW_V][RW_V];
	const double lambda = p->lambda, g = p->g;
	const int ns = g > 0 ? 1 + p->ngm : 1;

	for (size_t j = 0; j < J; j++) {
		const struct rwrun *r = &rr[j];
		double Wj[RW_V][RW_V] = { { 0 } }, x[RW_V][GM_S] = { { 0 } };
		double P[GM_S][GM_S] = { { 0 } }, phi[GM_S], dtp = -1;

		if (r->m == 0)
			continue;
		for (int a = 1; a < ns; a++)
			P[a][a] = g;
		phi[0] = 1;
		for (size_t k = 0; k < r->m; k++) {
			const double *z = r->z + k * nv;
			double F, K[GM_S], sF, w[RW_V];

			if (k > 0) {
				double dt = r->t[k] - r->t[k - 1];

				if (dt != dtp)
					for (int a = 1; a < ns; a++)
						phi[a] = exp(-dt / p->tc[a - 1]);
				for (int a = 0; a < ns; a++)
					for (int b = 0; b <= a; b++)
						P[a][b] *= phi[a] * phi[b];
				P[0][0] += lambda * dt;
				for (int a = 1; a < ns; a++)
					P[a][a] += g * (1 - phi[a] * phi[a]);
				for (size_t v = 0; v < nv; v++)
					for (int a = 1; a < ns; a++)
						x[v][a] *= phi[a];
				dtp = dt;
			}
			F = r->d[k];
			for (int a = 0; a < ns; a++) {
				K[a] = 0;
				for (int b = 0; b < ns; b++)
					K[a] += b <= a ? P[a][b] : P[b][a];
				F += K[a];
			}
			for (int a = 0; a < ns; a++)
				K[a] /= F;
			sF = sqrt(F);
			logdet += log(F);
			for (size_t a = 0; a < nv; a++) {
				double v = z[a];

				for (int b = 0; b < ns; b++)
					v -= x[a][b];
				w[a] = v / sF;
				for (int b = 0; b < ns; b++)
					x[a][b] += K[b] * v;
			}
			for (size_t a = 0; a < nv; a++)
				for (size_t b = 0; b <= a; b++)
					Wj[a][b] += w[a] * w[b];
			if (ns == 1)
				P[0][0] *= r->d[k] / F;
			else
				for (int a = 0; a < ns; a++)
					for (int b = 0; b <= a; b++)
						P[a][b] -= K[a] * K[b] * F;
		}
		/* the run offset (vector 0) profiled out: Schur complement */
		if (!(Wj[0][0] > 0))
			return -INFINITY;
		logda += log(Wj[0][0]);
		for (size_t a = 1; a < nv; a++)
			for (size_t b = 1; b <= a; b++)
				W[a - 1][b - 1] += Wj[a][b] - Wj[a][0] * Wj[b][0] / Wj[0][0];
		n_tot += r->m;
	}
	/* the regressors (nx) profiled out of the residual (index nx) */
	for (size_t a = 0; a <= nx; a++)
		for (size_t b = 0; b <= a; b++)
			Cx[a][b] = W[a][b];
	for (size_t c = 0; c < nx; c++) {
		double piv = Cx[c][c];

		if (!(piv > 0))
			return -INFINITY;
		logda += log(piv);
		for (size_t a = c + 1; a <= nx; a++)
			for (size_t b = c + 1; b <= a; b++)
				Cx[a][b] -= Cx[a][c] * Cx[b][c] / piv;
	}
	Q = Cx[nx][nx];
	if (!(Q > 0) || n_tot <= J + nx)
		return -INFINITY;
	*s2 = Q / (double)(n_tot - J - nx);
	return -0.5 * (logdet + logda + (double)(n_tot - J - nx) * log(Q));
}

/* the REML (negated, for a minimum) with one level of p at exp(x) / div */
struct reml_ctx {
	const struct rwrun *rr;
	size_t J, q;
	struct rwpar *p;
	double *lvl, div;
};

static double neg_reml_at(double x, void *ctx)
{
	const struct reml_ctx *c = ctx;
	double t2;

	*c->lvl = exp(x) / c->div;
	return -rw_reml(c->rr, c->J, c->q, c->p, &t2);
}

/* golden-section maximum of the REML over one level of p, *lvl =
 * exp(x) / div, x in [a, b]; *lvl, *x and *best updated when it
 * improves on *best (else *lvl is restored) */
static void rw_golden(const struct rwrun *rr, size_t J, size_t q,
		      struct rwpar *p, double *lvl, double div, double a,
		      double b, double *x, double *best)
{
	struct reml_ctx c = { rr, J, q, p, lvl, div };
	struct ssc_golden g;
	double keep = *lvl, f1, f2;

	ssc_golden_min(neg_reml_at, &c, a, b, 16, 0, true, &g);
	f1 = -g.f1;
	f2 = -g.f2;
	*lvl = keep;
	if (f1 >= f2 && f1 > *best) {
		*best = f1;
		*x = g.x1;
		*lvl = exp(g.x1) / div;
	} else if (f2 > *best) {
		*best = f2;
		*x = g.x2;
		*lvl = exp(g.x2) / div;
	}
}

/* the blocks of a run merged into at most RW_GROUPS groups of
 * consecutive blocks (their sample-weighted means, summed scores): the
 * noise model is fitted and applied on the groups, which keeps the
 * filter's cost small with flicker in its state */
#define RW_GROUPS 1024

static void rw_group(struct rwrun *r, size_t q, double cbar)
{
	size_t G = (r->m + RW_GROUPS - 1) / RW_GROUPS, m = 0, nv = q + 1;

	if (G < 2)
		return;
	for (size_t k0 = 0; k0 < r->m; k0 += G) {
		size_t k1 = k0 + G < r->m ? k0 + G : r->m;
		double cs = 0, ts = 0, z[RW_V] = { 0 }, h[RW_V] = { 0 };

		for (size_t k = k0; k < k1; k++) {
			double ck = cbar / r->d[k];

			cs += ck;
			ts += ck * r->t[k];
			for (size_t a = 0; a < nv; a++)
				z[a] += ck * r->z[k * nv + a];
			for (size_t a = 0; a < q; a++)
				h[a] += r->h[k * q + a];
		}
		r->t[m] = ts / cs;
		r->d[m] = cbar / cs;
		for (size_t a = 0; a < nv; a++)
			r->z[m * nv + a] = z[a] / cs;
		for (size_t a = 0; a < q; a++)
			r->h[m * q + a] = h[a];
		m++;
	}
	r->m = m;
}

static int rw_cov(const struct ctx *c, struct fit *f)
{
	size_t p = f->p, q = 1 + (size_t)f->K + f->hyst + f->grad;
	size_t nv = q + 1, idx[NREG + 1];
	double (*S)[SSCOPE_TEMPBIAS_MAX_RUNS + NREG] = calloc(p, sizeof(*S));
	struct rwrun *rr = calloc(c->J, sizeof(*rr));
	double cbar = 0, Tmax = 0, s2 = NAN, best, dtmin = INFINITY;
	struct rwpar pr = { 0 };
	int rc = -ENOMEM;

	if (!S || !rr)
		goto out;
	for (size_t j = 0; j < c->J; j++) {
		const struct blocks *b = &c->b[j];

		for (size_t i = b->first; i < b->nb; i++)
			cbar = fmax(cbar, b->c[i]);
	}
	for (size_t j = 0; j < c->J; j++) {
		const struct blocks *b = &c->b[j];
		struct rwrun *r = &rr[j];
		size_t T = b->nb - b->first;

		if (T == 0)
			continue;
		r->t = ssc_alloc_array(T, sizeof(double));
		r->d = ssc_alloc_array(T, sizeof(double));
		r->z = ssc_alloc_array(T, nv * sizeof(double));
		r->h = ssc_alloc_array(T, q * sizeof(double));
		if (!r->t || !r->d || !r->z || !r->h)
			goto out;
		for (size_t i = b->first; i < b->nb; i++) {
			double e = block_resid(c, f, j, i), *z = r->z + r->m * nv;
			const struct acc *a;
			size_t col = 0;

			if (!isfinite(e) || b->bin[i] == SIZE_MAX)
				continue;
			a = &c->bins[b->bin[i]];
			z[col++] = 1;
			for (int k = 1; k <= f->K; k++)
				z[col++] = a->u[k] / a->n;
			if (f->hyst)
				z[col++] = a->state;
			if (f->grad)
				z[col++] = a->dtdt / a->n / c->gsc;
			z[col] = e;
			for (size_t k = 0; k < q; k++)
				r->h[r->m * q + k] = b->c[i] * z[k];
			r->t[r->m] = b->t[i];
			r->d[r->m] = cbar / b->c[i];
			r->m++;
		}
		rw_group(r, q, cbar);
		for (size_t k = 1; k < r->m; k++)
			dtmin = fmin(dtmin, r->t[k] - r->t[k - 1]);
		if (r->m > 1)
			Tmax = fmax(Tmax, r->t[r->m - 1] - r->t[0]);
	}
	/* lambda: 0, a grid in v = log(lambda T^2) from -7 to log(1e3 T^2
	 * / dt) (the walk over one block a thousand times the white noise),
	 * then golden sections around the best grid point */
	best = rw_reml(rr, c->J, q, &pr, &s2);
	if (Tmax > 0 && dtmin > 0 && isfinite(dtmin)) {
		double vlo = -7, vhi = log(1e3 * Tmax * Tmax / dtmin), step = 1.5;
		double vb = NAN, lb = -INFINITY, t2;

		/* (in logs when T^2 overflows: a rate of 1e-150 Hz looped for
		 * ever) */
		if (!isfinite(vhi))
			vhi = log(1e3) + 2 * log(Tmax) - log(dtmin);
		for (double v = vlo; v <= vhi + 1e-9 && isfinite(vhi); v += step) {
			double l;

			pr.lambda = exp(v) / (Tmax * Tmax);
			l = rw_reml(rr, c->J, q, &pr, &t2);
			if (l > lb) {
				lb = l;
				vb = v;
			}
		}
		pr.lambda = 0;
		if (isfinite(lb)) {
			double x = vb;

			pr.lambda = exp(vb) / (Tmax * Tmax);
			rw_golden(rr, c->J, q, &pr, &pr.lambda, Tmax * Tmax,
				  vb - step, vb + step, &x, &lb);
			if (lb > best)
				best = rw_reml(rr, c->J, q, &pr, &s2);
			else
				pr.lambda = 0;
		}
		/* flicker, alone and beside the walk: processes from the
		 * groups' spacing to ten times the run (at most GM_MAXN),
		 * SSC_GM_RATIO apart; its level g on a grid of e^-8 .. e^5
		 * of a full block's white noise, then golden sections in
		 * each log level in turn.  The model kept is the best by the
		 * REML less one per level (Akaike): white, walk, flicker, or
		 * both */
		{
			struct rwpar tp = pr, pg[2];
			double lg[2] = { -INFINITY, -INFINITY }, xg[2] = { 0, 0 };
			double score = best - (pr.lambda > 0), xl;
			int n = 0;

			/* from the groups' mean spacing (not the shortest: a
			 * short last group or a gap would spend the bank's
			 * processes below it) */
			for (double tc = fmax(dtmin, Tmax / RW_GROUPS);
			     n < GM_MAXN && tc < 10 * Tmax * SSC_GM_RATIO;
			     tc *= SSC_GM_RATIO)
				tp.tc[n++] = tc;
			tp.ngm = n;
			pg[0] = pg[1] = tp;
			for (double v = -8; v <= 5 + 1e-9; v += step)
				for (int w = 0; w < 2; w++) {
					double l;

					if (w && !(pr.lambda > 0))
						continue;
					tp.g = exp(v);
					tp.lambda = w ? pr.lambda : 0;
					l = rw_reml(rr, c->J, q, &tp, &t2);
					if (l > lg[w]) {
						lg[w] = l;
						pg[w] = tp;
						xg[w] = v;
					}
				}
			for (int w = 0; w < 2; w++) {
				if (!isfinite(lg[w]))
					continue;
				for (int round = 0; round < 1 + w; round++) {
					rw_golden(rr, c->J, q, &pg[w], &pg[w].g, 1,
						  xg[w] - step, xg[w] + step, &xg[w],
						  &lg[w]);
					if (w) {
						xl = log(pg[w].lambda * Tmax * Tmax);
						rw_golden(rr, c->J, q, &pg[w], &pg[w].lambda,
							  Tmax * Tmax, xl - step,
							  xl + step, &xl, &lg[w]);
					}
				}
				if (lg[w] - 1 - w > score) {
					score = lg[w] - 1 - w;
					pr = pg[w];
				}
			}
			if (pr.g > 0)
				best = rw_reml(rr, c->J, q, &pr, &s2);
		}
	}
	if (!isfinite(best) || !(s2 > 0)) {
		/* not computable: the classical covariance stays */
		rc = 0;
		goto out;
	}
	/* S = sigma^2 (cbar sum c_i xbar xbar' + lambda sum dt_k R_k R_k'
	 * + g sum_gm sum_ij exp(-|t_i - t_j| / tc) h_i h_j') */
	for (size_t j = 0; j < c->J; j++) {
		const struct rwrun *r = &rr[j];
		double R[NREG + 1] = { 0 };

		if (r->m == 0)
			continue;
		idx[0] = j;
		for (size_t k = 1; k < q; k++)
			idx[k] = c->J + k - 1;
		for (size_t k = r->m; k-- > 0;) {
			const double *h = r->h + k * q;
			double dtk = k > 0 ? r->t[k] - r->t[k - 1] : 0;

			for (size_t a = 0; a < q; a++)
				R[a] += h[a];
			for (size_t a = 0; a < q; a++)
				for (size_t bb = 0; bb < q; bb++)
					S[idx[a]][idx[bb]] +=
						s2 * (r->d[k] * h[a] * h[bb] +
						      pr.lambda * dtk * R[a] * R[bb]);
		}
		/* each Gauss-Markov process, with G the decayed sum of the
		 * earlier h */
		for (int gi = 0; gi < pr.ngm && pr.g > 0; gi++) {
			double G[NREG + 1] = { 0 }, tc = pr.tc[gi];

			for (size_t k = 0; k < r->m; k++) {
				const double *h = r->h + k * q;

				if (k > 0) {
					double ph = exp(-(r->t[k] - r->t[k - 1]) / tc);

					for (size_t a = 0; a < q; a++)
						G[a] = ph * (G[a] + r->h[(k - 1) * q + a]);
				}
				for (size_t a = 0; a < q; a++)
					for (size_t bb = 0; bb < q; bb++)
						S[idx[a]][idx[bb]] +=
							s2 * pr.g *
							(h[a] * h[bb] + h[a] * G[bb] +
							 G[a] * h[bb]);
			}
		}
	}
	/* cov = A^-1 S A^-1, A^-1 = cov / s2 */
	{
		double (*M)[SSCOPE_TEMPBIAS_MAX_RUNS + NREG] = calloc(p, sizeof(*M));

		if (!M)
			goto out;
		for (size_t a = 0; a < p; a++)
			for (size_t bb = 0; bb < p; bb++) {
				double v = 0;

				for (size_t k = 0; k < p; k++)
					v += f->cov[a][k] / f->s2 * S[k][bb];
				M[a][bb] = v;
			}
		for (size_t a = 0; a < p; a++)
			for (size_t bb = 0; bb < p; bb++) {
				double v = 0;

				for (size_t k = 0; k < p; k++)
					v += M[a][k] * f->cov[k][bb] / f->s2;
				S[a][bb] = v;
			}
		free(M);
		for (size_t a = 0; a < p; a++)
			for (size_t bb = 0; bb < p; bb++)
				f->cov[a][bb] = S[a][bb];
	}
	rc = 0;
out:
	if (rr)
		for (size_t j = 0; j < c->J; j++) {
			free(rr[j].t);
			free(rr[j].d);
			free(rr[j].z);
			free(rr[j].h);
		}
	free(rr);
	free(S);
	return rc;
}

/*
 * Warm-up: a transient at the start of a run that the temperature model
 * does not explain.  The block residuals of the fit are averaged in
 * windows of W blocks (2 % of the run, >= 5); the settled level and the
 * spread of a window mean are the median and the scaled MAD (1.4826) of
 * the means of the run's non-overlapping windows, so correlated noise
 * and slow model misfit widen the threshold as they widen the spread.
 * A warm-up exists when the first window's mean lies beyond WARMUP_Z
 * spreads of the settled level; it ends half a window after the start of
 * the first window (sliding by one block, within the first half) within
 * WARMUP_Z_END spreads (the half window: that window still averages the
 * tail of the transient).  A departure anywhere later in the
 * run is not a warm-up.
 */
#define WARMUP_Z 5.0
#define WARMUP_Z_END 2.0
static size_t detect_warmup(const struct ctx *c, const struct fit *f, size_t j)
{
	const struct blocks *b = &c->b[j];
	size_t nb = b->nb, half = nb / 2, W, nw, m = 0, k = 0;
	double *r = ssc_alloc_array(nb, sizeof(double)), *mw = NULL;
	double L, sd, s = 0, n = 0;

	if (!r || nb < 20)
		goto out;
	W = nb / 50 > 5 ? nb / 50 : 5;
	nw = nb / W;
	mw = ssc_alloc_array(nw, sizeof(double));
	if (!mw || nw < 10)
		goto out;
	for (size_t i = 0; i < nb; i++)
		r[i] = block_resid(c, f, j, i);
	for (size_t w = 0; w < nw; w++) {
		s = n = 0;
		for (size_t i = w * W; i < (w + 1) * W; i++)
			if (isfinite(r[i])) {
				s += r[i];
				n++;
			}
		if (n >= 0.5 * (double)W)
			mw[m++] = s / n;
	}
	if (m < 10)
		goto out;
	qsort(mw, m, sizeof(double), ssc_cmp_double);
	L = mw[m / 2];
	for (size_t i = 0; i < m; i++)
		mw[i] = fabs(mw[i] - L);
	qsort(mw, m, sizeof(double), ssc_cmp_double);
	sd = 1.4826 * mw[m / 2];
	if (!(sd > 0))
		goto out;
	/* sliding window sums from the start */
	s = n = 0;
	for (size_t i = 0; i < W; i++)
		if (isfinite(r[i])) {
			s += r[i];
			n++;
		}
	for (k = 0; k + W <= half; k++) {
		/* a warm-up is established by a first window beyond
		 * WARMUP_Z spreads; it then lasts while the windows stay
		 * beyond WARMUP_Z_END */
		double z = k == 0 ? WARMUP_Z : WARMUP_Z_END;

		if (n > 0 && !(fabs(s / n - L) > z * sd))
			break;
		if (isfinite(r[k])) {
			s -= r[k];
			n--;
		}
		if (k + W < nb && isfinite(r[k + W])) {
			s += r[k + W];
			n++;
		}
	}
	if (k + W > half)
		k = 0; /* never settles in the first half: not a warm-up */
	else if (k > 0)
		k += W / 2; /* the first settled window still holds the tail */
out:
	free(r);
	free(mw);
	return k;
}

static void stability(const struct ctx *c, const struct fit *f,
		      struct sscope_tempbias_result *res)
{
	size_t jl = 0, n;
	double *r;
	struct sscope_allan_result *ar = NULL;

	res->stability = NAN;
	res->stability_tau_s = NAN;
	for (size_t j = 1; j < c->J; j++)
		if (c->b[j].nb - c->b[j].first > c->b[jl].nb - c->b[jl].first)
			jl = j;
	n = c->b[jl].nb - c->b[jl].first;
	if (n < 16)
		return;
	r = ssc_alloc_array(n, sizeof(double));
	if (!r)
		return;
	for (size_t i = 0; i < n; i++)
		r[i] = block_resid(c, f, jl, c->b[jl].first + i);
	if (!sscope_allan_analyze(r, 1, n, 1 / c->b[jl].dt, SSCOPE_ALLAN_TAUS_OCTAVE,
				  NULL, NULL, &ar, NULL)) {
		for (size_t i = 0; i < ar->n_points; i++)
			/* reliable points: 10 degrees of freedom for white
			 * rate noise, whatever the identification says at
			 * few averages */
			if (isfinite(ar->points[i].dev) &&
			    sscope_allan_edf(0, 2, ar->points[i].m, n + 1,
					     false, 1) >= 10 &&
			    !(ar->points[i].dev >= res->stability)) {
				res->stability = ar->points[i].dev;
				res->stability_tau_s = ar->points[i].tau_s;
			}
	}
	sscope_allan_result_free(ar);
	free(r);
}

double sscope_tempbias_eval(const struct sscope_tempbias_result *res,
			    double temp_degc)
{
	double T;

	if (!res)
		return NAN;
	T = fmin(fmax(temp_degc, res->temp_min_degc), res->temp_max_degc);
	return horner(res->coef, res->order, T - res->ref_temp_degc);
}

void sscope_tempbias_result_free(struct sscope_tempbias_result *res)
{
	if (!res)
		return;
	free(res->runs);
	free(res->bins);
	free(res->table_temp_degc);
	free(res->table_bias);
	free(res);
}

static int results(struct ctx *c, const struct fit *f,
		   struct sscope_tempbias_result *res)
{
	size_t J = c->J;
	double hk[MAXK + 1];
	double step, n_tab;

	res->order = f->K;
	res->dof = f->dof;
	hk[0] = 1;
	for (int k = 1; k <= MAXK; k++)
		hk[k] = hk[k - 1] * c->h;
	/* coef[0]: mean of the run offsets */
	res->coef[0] = 0;
	for (size_t j = 0; j < J; j++)
		res->coef[0] += f->beta[j] / (double)J;
	{
		double v = 0;

		for (size_t i = 0; i < J; i++)
			for (size_t j = 0; j < J; j++)
				v += f->cov[i][j];
		res->coef_sd[0] = sqrt(v) / (double)J;
	}
	for (int k = 1; k <= f->K; k++) {
		size_t col = J + (size_t)k - 1;

		res->coef[k] = f->beta[col] / hk[k];
		res->coef_sd[k] = sqrt(f->cov[col][col]) / hk[k];
	}
	for (int k = f->K + 1; k <= MAXK; k++)
		res->coef[k] = res->coef_sd[k] = NAN;
	/* order 0: no temperature term, so none is known (not zero) */
	res->sensitivity = f->K >= 1 ? res->coef[1] : (double)NAN;
	res->sensitivity_sd = f->K >= 1 ? res->coef_sd[1] : (double)NAN;
	res->have_hysteresis = f->hyst;
	res->hysteresis = res->hysteresis_sd = NAN;
	if (f->hyst) {
		size_t col = J + (size_t)f->K;

		res->hysteresis = 2 * f->beta[col];
		res->hysteresis_sd = 2 * sqrt(f->cov[col][col]);
	}
	{
		double nh = 0, sh = 0, nc = 0, sc = 0;

		for (size_t i = 0; i < c->nbins; i++) {
			const struct acc *a = &c->bins[i];

			if (!(a->n > 0))
				continue;
			if (a->state > 0) {
				nh += a->n;
				sh += a->dtdt;
			} else if (a->state < 0) {
				nc += a->n;
				sc += a->dtdt;
			}
		}
		res->rate_heat_degc_s = nh > 0 ? sh / nh : (double)NAN;
		res->rate_cool_degc_s = nc > 0 ? sc / nc : (double)NAN;
	}
	res->have_gradient = f->grad;
	res->gradient = res->gradient_sd = NAN;
	if (f->grad) {
		size_t col = J + (size_t)f->K + f->hyst;

		res->gradient = f->beta[col] / c->gsc;
		res->gradient_sd = sqrt(f->cov[col][col]) / c->gsc;
	}
	/* runs */
	{
		double mn = INFINITY, mx = -INFINITY, s = 0;

		for (size_t j = 0; j < J; j++) {
			struct sscope_tempbias_runinfo *ri = &res->runs[j];
			const struct blocks *b = &c->b[j];
			double st = 0, n = 0;

			ri->offset = f->beta[j];
			ri->offset_sd = sqrt(f->cov[j][j]);
			ri->warmup_s = (double)b->first * b->dt;
			for (size_t i = b->first; i < b->nb; i++)
				if (b->c[i] > 0 && isfinite(b->ts[i])) {
					st += b->c[i] * b->ts[i];
					n += b->c[i];
				}
			ri->mean_temp_degc = n > 0 ? st / n : (double)NAN;
			ri->used = (size_t)n;
			res->used += (size_t)n;
			mn = fmin(mn, ri->offset);
			mx = fmax(mx, ri->offset);
			s += ri->offset;
		}
		res->repeat_sd = res->repeat_range = NAN;
		if (J >= 2) {
			double m = s / (double)J, v = 0;

			for (size_t j = 0; j < J; j++)
				v += (res->runs[j].offset - m) * (res->runs[j].offset - m);
			res->repeat_sd = sqrt(v / (double)(J - 1));
			res->repeat_range = mx - mn;
		}
	}
	/* residual RMS of blocks */
	{
		double s = 0, n = 0;

		for (size_t j = 0; j < J; j++)
			for (size_t i = c->b[j].first; i < c->b[j].nb; i++) {
				double r = block_resid(c, f, j, i);

				if (isfinite(r)) {
					s += c->b[j].c[i] * r * r;
					n += c->b[j].c[i];
				}
			}
		res->residual_rms = n > 0 ? sqrt(s / n) : (double)NAN;
	}
	/* bins */
	res->bins = ssc_alloc_array(c->nbins, sizeof(*res->bins));
	if (!res->bins)
		return -ENOMEM;
	for (size_t i = 0; i < c->nbins; i++) {
		const struct acc *a = &c->bins[i];
		struct sscope_tempbias_bin *o;
		double shape = 0;

		if (!(a->n > 0))
			continue;
		o = &res->bins[res->n_bins++];
		o->temp_degc = a->temp / a->n;
		o->bias = a->x / a->n;
		o->dtdt = a->dtdt / a->n;
		o->n = a->n;
		o->state = a->state;
		o->run = a->run;
		for (int k = 1; k <= f->K; k++)
			shape += f->beta[J + (size_t)k - 1] * a->u[k] / a->n;
		if (f->hyst)
			shape += f->beta[J + (size_t)f->K] * a->state;
		if (f->grad)
			shape += f->beta[J + (size_t)f->K + f->hyst] * o->dtdt / c->gsc;
		o->resid = o->bias - f->beta[a->run] - shape;
	}
	/* separate heating / cooling fits */
	{
		double ah[MAXK + 1], ac[MAXK + 1], h0, h1, c0, c1;

		res->hysteresis_max = res->hysteresis_at_degc = NAN;
		if (f->hyst && !split_fit(c, f, 1, ah, &h0, &h1) &&
		    !split_fit(c, f, -1, ac, &c0, &c1)) {
			double lo = fmax(h0, c0), hi = fmin(h1, c1);

			res->have_split = true;
			for (int k = 0; k <= f->K; k++) {
				res->heat_coef[k] = ah[k] / hk[k];
				res->cool_coef[k] = ac[k] / hk[k];
			}
			for (int i = 0; i <= 200 && hi > lo; i++) {
				double u = lo + (hi - lo) * i / 200;
				double g = horner(ah, f->K, u) - horner(ac, f->K, u);

				if (!(fabs(g) <= fabs(res->hysteresis_max))) {
					res->hysteresis_max = g;
					res->hysteresis_at_degc = c->tref + c->h * u;
				}
			}
		}
	}
	/* peak to peak */
	{
		double mn = INFINITY, mx = -INFINITY;

		for (int i = 0; i <= 400; i++) {
			double T = res->temp_min_degc +
				   (res->temp_max_degc - res->temp_min_degc) * i / 400;
			double v = sscope_tempbias_eval(res, T);

			mn = fmin(mn, v);
			mx = fmax(mx, v);
		}
		res->peak_to_peak = res->order >= 1 ? mx - mn : (double)NAN;
	}
	/* table */
	step = c->o->table_step_degc;
	if (!(step > 0)) {
		double span = res->temp_max_degc - res->temp_min_degc;
		static const double steps[] = { 0.1, 0.2, 0.5, 1, 2, 5, 10, 20 };

		step = 20;
		for (size_t i = 0; i < sizeof(steps) / sizeof(steps[0]); i++)
			if (span / steps[i] <= 40) {
				step = steps[i];
				break;
			}
	}
	{
		double t0 = ceil(res->temp_min_degc / step - 1e-9) * step;

		n_tab = floor((res->temp_max_degc - t0) / step + 1e-9) + 1;
		if (n_tab > 1e5)
			return -E2BIG; /* said by the caller */
		if (!(n_tab >= 1))
			n_tab = 1;
		res->n_table = (size_t)n_tab;
		res->table_temp_degc = ssc_alloc_array(res->n_table, sizeof(double));
		res->table_bias = ssc_alloc_array(res->n_table, sizeof(double));
		if (!res->table_temp_degc || !res->table_bias)
			return -ENOMEM;
		for (size_t i = 0; i < res->n_table; i++) {
			double T = res->n_table == 1 && !(t0 <= res->temp_max_degc) ?
				   res->ref_temp_degc : t0 + step * (double)i;

			res->table_temp_degc[i] = T;
			res->table_bias[i] = sscope_tempbias_eval(res, T);
		}
	}
	stability(c, f, res);
	return 0;
}

int sscope_tempbias_fit(const struct sscope_tempbias_run *runs, size_t n_runs,
			const struct sscope_tempbias_opts *opts,
			struct sscope_tempbias_result **out,
			struct sscope_diag *diag)
{
	static const struct sscope_tempbias_opts defaults = { .order_auto = true };
	const struct sscope_tempbias_opts *o = opts ? opts : &defaults;
	struct ctx c = { .o = o };
	struct sscope_tempbias_result *res = NULL;
	struct fit *f = NULL, *g = NULL;
	double block_s, smooth_s, span, min_span, alpha, db;
	int K, cap, rc = 0;
	bool hyst, grad, want_auto, hyst_ok, grad_ok;
	const char *cap_why = NULL;
	size_t nfin = 0;

	if (!runs || !out || n_runs == 0)
		return ssc_diag(diag, -EINVAL, "no runs");
	*out = NULL;
	if (n_runs > SSCOPE_TEMPBIAS_MAX_RUNS)
		return ssc_diag(diag, -EINVAL, "at most %d runs",
				SSCOPE_TEMPBIAS_MAX_RUNS);
	want_auto = o->order_auto || o->order < 0;
	if (!want_auto && o->order > MAXK)
		return ssc_diag(diag, -EINVAL, "order %d: at most %d", o->order,
				MAXK);
	for (size_t j = 0; j < n_runs; j++)
		if (!runs[j].x || !runs[j].temp_degc || runs[j].stride == 0 ||
		    !(runs[j].rate_hz > 0) || !isfinite(runs[j].rate_hz))
			return ssc_diag(diag, -EINVAL, "run %zu: bad record", j + 1);
	/* centred, scaled polynomial fits still square the samples */
	for (size_t j = 0; j < n_runs; j++)
		if ((rc = ssc_magnitude_check(runs[j].x, runs[j].stride, runs[j].n,
					      250, "tempbias", diag)) ||
		    (rc = ssc_magnitude_check(runs[j].temp_degc, 1, runs[j].n,
					      250, "tempbias temperature", diag)))
			return rc;
	/* every sample the same value: a stuck sensor or a constant column;
	 * a fit would read orders into its rounding */
	{
		double first = NAN;
		bool varies = false;

		for (size_t j = 0; j < n_runs && !varies; j++)
			for (size_t i = 0; i < runs[j].n && !varies; i++) {
				double v = runs[j].x[i * runs[j].stride];

				if (isnan(v))
					continue;
				if (isnan(first))
					first = v;
				else if (v != first)
					varies = true;
			}
		if (!varies && !isnan(first))
			return ssc_diag(diag, -EDOM, "every sample is %g (constant data): no bias to fit against temperature; a stuck sensor or a constant column",
					first);
	}
	block_s = o->block_s > 0 ? o->block_s : 1;
	smooth_s = o->smooth_s > 0 ? o->smooth_s : 60;
	min_span = o->min_span_degc > 0 ? o->min_span_degc : 1;
	alpha = o->alpha > 0 && o->alpha < 1 ? o->alpha : 0.01;
	c.J = n_runs;
	c.b = calloc(n_runs, sizeof(*c.b));
	res = calloc(1, sizeof(*res));
	f = malloc(sizeof(*f));
	g = malloc(sizeof(*g));
	if (!c.b || !res || !f || !g) {
		rc = -ENOMEM;
		goto fail;
	}
	res->hyst_grad_vif = NAN;
	res->runs = calloc(n_runs, sizeof(*res->runs));
	if (!res->runs) {
		rc = -ENOMEM;
		goto fail;
	}
	res->n_runs = n_runs;
	c.tmin = INFINITY;
	c.tmax = -INFINITY;
	for (size_t j = 0; j < n_runs; j++) {
		size_t h;

		rc = make_blocks(&runs[j], block_s, &c.b[j]);
		if (rc)
			goto fail;
		h = ssc_count(fmax(2, round(smooth_s / (2 * c.b[j].dt))));
		smooth(&c.b[j], h);
		for (size_t i = 0; i < c.b[j].nb; i++) {
			if (c.b[j].c[i] > 0 && isfinite(c.b[j].ts[i])) {
				c.tmin = fmin(c.tmin, c.b[j].ts[i]);
				c.tmax = fmax(c.tmax, c.b[j].ts[i]);
				nfin++;
			}
		}
		res->dropped += runs[j].n;
	}
	if (nfin < 3) {
		double rec_s = 0;

		for (size_t j = 0; j < n_runs; j++)
			if (runs[j].rate_hz > 0)
				rec_s += (double)runs[j].n / runs[j].rate_hz;
		rc = ssc_diag(diag, -EDOM, "fewer than 3 blocks of %g s with finite data and temperature (the record%s %.3g s at its rate)",
			      block_s, n_runs > 1 ? "s span" : " spans", rec_s);
		goto fail;
	}
	/* below absolute zero, or hotter than any sensor survives: a
	 * column in another unit (K read as degC stays above) or not a
	 * temperature */
	if (c.tmin < -273.15 || c.tmax > 1000) {
		rc = ssc_diag(diag, -EDOM,
			      "the temperature runs from %.4g to %.4g degC: %s; check the temperature column and its unit",
			      c.tmin, c.tmax,
			      c.tmin < -273.15 ? "below absolute zero" : "beyond any sensor's range");
		goto fail;
	}
	span = c.tmax - c.tmin;
	if (span < min_span && n_runs == 1) {
		/* a constant column's smoothed blocks differ by rounding */
		if (span <= 1e-9 * (fabs(c.tmax) + 1))
			rc = ssc_diag(diag, -EDOM,
				      "the temperature does not change (%.4g degC throughout): no temperature curve can be fitted",
				      c.tmax);
		else
			rc = ssc_diag(diag, -EDOM,
				      "temperature span %.3g degC is below %.3g degC: no temperature curve can be fitted",
				      span, min_span);
		goto fail;
	}
	/* dead band */
	db = o->deadband_degc_s;
	if (!(db > 0) && !o->rate_deadband) {
		db = NAN;
	} else if (!(db > 0)) {
		double *a = ssc_alloc_array(nfin, sizeof(double));
		size_t m = 0;

		if (!a) {
			rc = -ENOMEM;
			goto fail;
		}
		for (size_t j = 0; j < n_runs; j++)
			for (size_t i = 0; i < c.b[j].nb; i++)
				if (c.b[j].c[i] > 0 && isfinite(c.b[j].ts[i]))
					a[m++] = fabs(c.b[j].dtdt[i]);
		qsort(a, m, sizeof(double), ssc_cmp_double);
		db = 0.1 * a[(size_t)(0.95 * (double)(m - 1))];
		free(a);
		if (!(db > 0))
			db = 1e-6;
	}
	res->deadband_degc_s = db;
	/* gradient scale: rms dT/dt */
	{
		double s = 0, n = 0;

		res->turn_band_degc = fmax(0.2, 0.02 * span);
		for (size_t j = 0; j < n_runs; j++) {
			if (isnan(db))
				set_states_turning(&c.b[j], res->turn_band_degc);
			else
				set_states(&c.b[j], db);
			for (size_t i = 0; i < c.b[j].nb; i++)
				if (c.b[j].c[i] > 0 && isfinite(c.b[j].ts[i])) {
					s += c.b[j].dtdt[i] * c.b[j].dtdt[i];
					n++;
				}
		}
		c.gsc = n > 0 && s > 0 ? sqrt(s / n) : 1;
	}
	c.tref = o->ref_temp_set ? o->ref_temp_degc : (c.tmin + c.tmax) / 2;
	c.h = fmax(fabs(c.tmax - c.tref), fabs(c.tmin - c.tref));
	if (!(c.h > 0))
		c.h = 1;
	c.bin_w = o->bin_degc > 0 ? o->bin_degc : fmax(span / 100, 1e-3);
	c.nbt = (size_t)fmin(1e5, floor(span / c.bin_w) + 1);
	c.bins = ssc_alloc_array(nfin, sizeof(*c.bins));
	if (!c.bins) {
		rc = -ENOMEM;
		goto fail;
	}
	res->ref_temp_degc = c.tref;
	res->half_span_degc = c.h;
	res->smooth_s = smooth_s;
	res->block_s = block_s;
	res->bin_degc = c.bin_w;
	res->temp_min_degc = c.tmin;
	res->temp_max_degc = c.tmax;
	cap = span < min_span ? 0 : (int)fmin(MAXK, fmax(1, floor(span / 5)));
	/* distinct temperature levels: cells of span / 20 holding >= 1 % of
	 * the samples; the order stays below their number */
	if (cap > 0) {
		double cell[20] = { 0 }, tot = 0;
		int levels = 0;

		for (size_t j = 0; j < n_runs; j++)
			for (size_t i = 0; i < c.b[j].nb; i++)
				if (c.b[j].c[i] > 0 && isfinite(c.b[j].ts[i])) {
					int k = (int)floor((c.b[j].ts[i] - c.tmin) / span * 20);

					cell[k < 0 ? 0 : k > 19 ? 19 : k] += c.b[j].c[i];
					tot += c.b[j].c[i];
				}
		for (int k = 0; k < 20; k++)
			levels += cell[k] >= 0.01 * tot;
		res->levels = levels;
		if (levels - 1 < cap) {
			cap = levels - 1 > 0 ? levels - 1 : 0;
			cap_why = "distinct temperature levels";
		}
	}
	res->order_cap = cap;
	res->order_requested = want_auto ? -1 : o->order;
	K = want_auto ? cap : o->order;
	if (K > cap) {
		res->order_lowered = true;
		snprintf(res->note, sizeof(res->note),
			 "order %d lowered to %d: %s", K, cap,
			 cap_why ? cap_why : "at most one order per 5 degC of span");
		K = cap;
	}
	if (o->warmup_set)
		for (size_t j = 0; j < n_runs; j++)
			c.b[j].first = (size_t)fmin((double)c.b[j].nb,
						    ceil(o->warmup_s / c.b[j].dt));
	/* identifiability: hysteresis needs >= 10 % of the samples both
	 * heating and cooling; the gradient term needs dT/dt to vary (sd
	 * >= 30 % of its rms) */
	{
		double nh = 0, nc = 0, n = 0, s1 = 0, s2 = 0;

		for (size_t j = 0; j < n_runs; j++)
			for (size_t i = 0; i < c.b[j].nb; i++)
				if (c.b[j].c[i] > 0 && isfinite(c.b[j].ts[i])) {
					nh += c.b[j].state[i] > 0;
					nc += c.b[j].state[i] < 0;
					s1 += c.b[j].dtdt[i];
					s2 += c.b[j].dtdt[i] * c.b[j].dtdt[i];
					n++;
				}
		hyst_ok = !o->no_hysteresis && nh >= 0.1 * n && nc >= 0.1 * n;
		if (hyst_ok) {
			/* heating and cooling must overlap in temperature:
			 * sum over 20 cells of min(heating share, cooling
			 * share) >= 0.2 */
			double ch[20] = { 0 }, cc[20] = { 0 }, ov = 0;

			for (size_t j = 0; j < n_runs; j++)
				for (size_t i = 0; i < c.b[j].nb; i++)
					if (c.b[j].c[i] > 0 && isfinite(c.b[j].ts[i]) &&
					    c.b[j].state[i]) {
						int k = (int)floor((c.b[j].ts[i] - c.tmin) / fmax(span, 1e-9) * 20);

						k = k < 0 ? 0 : k > 19 ? 19 : k;
						if (c.b[j].state[i] > 0)
							ch[k]++;
						else
							cc[k]++;
					}
			for (int k = 0; k < 20; k++)
				ov += fmin(ch[k] / nh, cc[k] / nc);
			hyst_ok = ov >= 0.2;
		}
		grad_ok = !o->no_gradient && n > 0 &&
			  s2 / n - (s1 / n) * (s1 / n) >= 0.09 * s2 / n;
		if (!o->no_hysteresis && !hyst_ok)
			add_note(res, "no hysteresis term: heating and cooling not each >= 10 % of the data over a common temperature range");
		else if (!o->no_gradient && !grad_ok)
			add_note(res, "no gradient term: dT/dt does not vary enough");
	}
	for (int pass = 0; pass < 3; pass++) {
		int Kf;
		char note[200] = "";

		hyst = hyst_ok;
		grad = grad_ok;
		rc = fill_bins(&c, hyst);
		if (rc)
			goto fail;
		res->hyst_grad_collinear = false;
		res->hyst_grad_vif = NAN;
		if (hyst && grad) {
			res->hyst_grad_vif = gradient_vif(&c, K);
			if (!(res->hyst_grad_vif <= SSCOPE_TEMPBIAS_VIF_MAX)) {
				grad = false;
				res->hyst_grad_collinear = true;
			}
		}
		rc = fit_terms(&c, K, &hyst, &grad, f, note, sizeof(note));
		if (rc == -EDOM) {
			rc = ssc_diag(diag, -EDOM,
				      "too few distinct temperatures or samples for a fit (%zu blocks)",
				      nfin);
			goto fail;
		}
		if (rc)
			goto fail;
		if (*note && pass == 0)
			add_note(res, note);
		Kf = f->K;
		if (Kf < K && !want_auto) {
			char b[120];

			res->order_lowered = true;
			snprintf(b, sizeof(b),
				 "order %d lowered to %d: the design is singular (too few distinct temperatures)",
				 K, Kf);
			if (pass == 0)
				add_note(res, b);
		}
		if (want_auto) {
			while (f->K > 0) {
				bool h2 = f->hyst, g2 = f->grad;

				if (do_fit(c.bins, c.nbins, c.J, f->K - 1, h2, g2, c.gsc, g))
					break;
				if (f_pvalue(g, f) < alpha)
					break;
				*f = *g;
			}
		}
		if (pass == 2 || o->warmup_set)
			break;
		/* auto warm-up, then refit */
		{
			bool any = false;

			for (size_t j = 0; j < n_runs; j++) {
				c.b[j].first = detect_warmup(&c, f, j);
				any |= c.b[j].first > 0;
			}
			if (!any)
				break;
		}
	}
	if (res->hyst_grad_collinear) {
		char b[200];

		snprintf(b, sizeof(b),
			 "hysteresis and gradient collinear (VIF %.3g): hysteresis is their combined heating-cooling gap",
			 res->hyst_grad_vif);
		add_note(res, b);
	}
	rc = rw_cov(&c, f);
	if (rc)
		goto fail;
	rc = results(&c, f, res);
	if (rc == -E2BIG)
		rc = ssc_diag(diag, -EINVAL,
			      "a compensation table step of %g degC over %.3g .. %.3g degC makes more than 100000 rows",
			      c.o->table_step_degc, res->temp_min_degc, res->temp_max_degc);
	if (rc)
		goto fail;
	res->dropped -= res->used;
	for (size_t j = 0; j < n_runs; j++)
		free_blocks(&c.b[j]);
	free(c.b);
	free(c.bins);
	free(f);
	free(g);
	*out = res;
	return 0;
fail:
	if (c.b)
		for (size_t j = 0; j < n_runs; j++)
			free_blocks(&c.b[j]);
	free(c.b);
	free(c.bins);
	free(f);
	free(g);
	sscope_tempbias_result_free(res);
	return rc == -ENOMEM ? ssc_diag(diag, rc, "out of memory") : rc;
}
