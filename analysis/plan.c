/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Recording planner: the predicted outcome of the IEEE Std 952 noise fit
 * (noisefit.c) of a record of a given length, from the model alone.  The
 * record's OADEV points on the dense grid (terms np - 2 m, fully
 * overlapping) have the covariance C of sscope_noise_avar_cov(), which is
 * quadratic in the coefficients' squares; from it the generalised
 * least-squares sd of the presence test and the sandwich sd and skewness
 * of the weighted fit of every term give approximations of the
 * probabilities (see sscope-plan.h).  The skewness of h'y, y the AVAR
 * points, uses the third cumulants of Gaussian quadratic forms whose
 * matrices share their eigenvectors, k_abc = (2/3) (C_ab C_ac / mu_a +
 * C_ab C_bc / mu_b + C_ac C_bc / mu_c) (exact for one point: 2 C^2 / mu).
 * References: IEEE Std 952-1997 Annex C; C. A. Greenhall, W. J. Riley,
 * "Uncertainty of stability variances based on finite differences", PTTI
 * 2003 (the covariance of overlapping variances).
 */
#include "allan-internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>

#include "sscope-allan.h"
#include "sscope-noise.h"
#include "sscope-plan.h"

#define NT 5
#define MIN_POINTS 6
#define MAX_POINTS 512

static double basis(int j, double tau)
{
	static const double b2 = 0.4412712003053032; /* 2 ln2 / pi */

	switch (j) {
	case 0:
		return 3 / (tau * tau);
	case 1:
		return 1 / tau;
	case 2:
		return b2;
	case 3:
		return tau / 3;
	default:
		return tau * tau / 2;
	}
}

/* One record length: points, and the covariance of the AVAR points
 * relative to the model (C_ab / (mu_a mu_b)) for a tested value xr of the
 * planned square (relative to its true value) with the other squares
 * restricted to it as the fit's bootstrap does (noisefit.c, boot_pass():
 * the weighted fit of the others with the square held at xr, clamped at
 * 0): sq_at() gives the squares, and the covariance is quadratic in them,
 * sum over pairs k <= l of t_k t_l g[pair]. */
#define NPAIR (NT * (NT + 1) / 2)
struct pdesign {
	size_t n;
	int j;
	double tau[MAX_POINTS];
	double mu[MAX_POINTS];
	double s[NT];    /* true squares */
	double dsq[NT];  /* change of square k per unit of xr (restricted) */
	double sig[NT];  /* sd of estimate k given the estimate of j */
	double eps[NT];  /* the scenario's offsets of the other estimates */
	int frozen[NT];  /* the scenario holds k (clamped at 0: no slope) */
	int npair, pk[NPAIR], pl[NPAIR];
	double *g[NPAIR]; /* n * n each */
	double *cn;       /* under the null's fit (no term) */
	double *work;     /* n * n */
};

static void pdesign_free(struct pdesign *d)
{
	for (int p = 0; p < d->npair; p++)
		free(d->g[p]);
	free(d->cn);
	free(d->work);
}

/* the squares at a tested value xr of square j: the others restricted */
static void sq_at(const struct pdesign *d, double xr, double t[NT])
{
	for (int k = 0; k < NT; k++)
		t[k] = k == d->j ? xr * d->s[k] :
				   fmax(d->s[k] + (d->frozen[k] ? 0 : (xr - 1) * d->dsq[k]) +
						d->eps[k], 0);
}

/* Cholesky-invert the p x p matrix a (scaled to unit diagonal first) */
static int spd_inv(double *a, size_t p)
{
	double s[NT];
	gsl_matrix_view v = gsl_matrix_view_array(a, p, p);
	struct ssc_gsl_quiet quiet;
	int rc;

	for (size_t i = 0; i < p; i++) {
		if (!(a[i * p + i] > 0))
			return -EDOM;
		s[i] = 1 / sqrt(a[i * p + i]);
	}
	for (size_t i = 0; i < p; i++)
		for (size_t k = 0; k < p; k++)
			a[i * p + k] *= s[i] * s[k];
	ssc_gsl_quiet_begin(&quiet);
	rc = gsl_linalg_cholesky_decomp1(&v.matrix);
	if (!rc)
		rc = gsl_linalg_cholesky_invert(&v.matrix);
	ssc_gsl_quiet_end(&quiet);
	if (rc)
		return -EDOM;
	for (size_t i = 0; i < p; i++)
		for (size_t k = 0; k < p; k++)
			a[i * p + k] *= s[i] * s[k];
	return 0;
}

static void cov_at(const struct pdesign *d, double xr, double *c)
{
	size_t nn = d->n * d->n;
	double t[NT];

	sq_at(d, xr, t);
	memset(c, 0, nn * sizeof(double));
	for (int p = 0; p < d->npair; p++) {
		double f = t[d->pk[p]] * t[d->pl[p]];

		if (f != 0)
			for (size_t i = 0; i < nn; i++)
				c[i] += f * d->g[p][i];
	}
}

/*
 * sd of square j (relative to its true value s) in the weighted fit of the
 * terms of mask when the square is xr * s: weights 1 / var of each point,
 * the sandwich g' C g with g = W A (A'WA)^-1 e_j; gam (optional) gets its
 * skewness.
 */
static double wls_sd(const struct pdesign *d, unsigned mask, int j, double s,
		     double xr, double *gam)
{
	size_t n = d->n, p = 0, aj = 0;
	double M[NT * NT] = { 0 }, g, t[NT];
	double *c = d->work, var = 0, k3 = 0;
	double *w = malloc(2 * n * sizeof(double)), *gv;
	int cols[NT];

	if (!w)
		return NAN;
	for (int k = 0; k < NT; k++)
		if (mask & (1u << k)) {
			if (k == j)
				aj = p;
			cols[p++] = k;
		}
	gv = w + n;
	cov_at(d, xr, c);
	for (size_t i = 0; i < n; i++) {
		if (!(c[i * n + i] > 0)) {
			free(w);
			return NAN;
		}
		w[i] = 1 / c[i * n + i];
	}
	for (size_t a = 0; a < p; a++)
		for (size_t b = 0; b < p; b++)
			for (size_t i = 0; i < n; i++)
				M[a * p + b] += basis(cols[a], d->tau[i]) *
						basis(cols[b], d->tau[i]) * w[i] /
						(d->mu[i] * d->mu[i]);
	if (spd_inv(M, p)) {
		free(w);
		return NAN;
	}
	for (size_t i = 0; i < n; i++) {
		g = 0;
		for (size_t a = 0; a < p; a++)
			g += basis(cols[a], d->tau[i]) / d->mu[i] * M[a * p + aj];
		gv[i] = g * w[i];
	}
	sq_at(d, xr, t);
	for (size_t a = 0; a < n; a++) {
		double r = 0, m = 0;

		for (size_t b = 0; b < n; b++)
			r += c[a * n + b] * gv[b];
		var += gv[a] * r;
		for (int k = 0; k < NT; k++)
			m += t[k] * basis(k, d->tau[a]);
		m /= d->mu[a];
		if (m > 0)
			k3 += gv[a] / m * r * r;
	}
	free(w);
	if (gam)
		*gam = var > 0 ? 2 * k3 / (var * sqrt(var)) : 0;
	return var > 0 ? sqrt(var) / s : (double)NAN;
}

/* P(X <= x) for X of mean 0, sd 1 and skewness gam: a Pearson type III
 * (shifted gamma) law, the normal for a small skew */
static double skew_P(double x, double gam)
{
	double k, g;

	if (!(fabs(gam) > 1e-3))
		return gsl_cdf_ugaussian_P(x);
	/* G ~ Gamma(k) with k = 4 / gam^2, X = (G - k) / sqrt(k) sign(gam);
	 * the Wilson-Hilferty normal form of G's distribution */
	k = 4 / (gam * gam);
	g = k + (gam > 0 ? x : -x) * sqrt(k);
	if (!(g > 0))
		return gam > 0 ? 0 : 1;
	x = (cbrt(g / k) - 1 + 1 / (9 * k)) * sqrt(9 * k);
	return gam > 0 ? gsl_cdf_ugaussian_P(x) : gsl_cdf_ugaussian_Q(x);
}

/*
 * The fit's interval of the square for an estimate xr (relative to the true
 * square), by the Neyman construction of its bootstrap (noisefit.c,
 * boot_solve()) with Pearson type III margins: the estimate at a tested
 * value b has sd s(b) and skewness g(b) (wls_sd()), and the acceptance region leaves below it
 * beta(b) = alpha (1 - Phi(b / s(b) - zdet) / 2) and above it
 * alpha - beta(b): one-sided for a b the record cannot resolve, central for
 * one it resolves.  The bounds are the smallest and largest b that accept
 * xr; returns the relative half-width (hi - lo) / (2 sqrt(xr)) of the
 * coefficient's interval, INFINITY when lo = 0 (the fit's interval is then
 * a bound, not two-sided) or hi has no finite value.
 */
struct ney {
	const struct pdesign *d;
	int j;
	double s, alpha, zdet;
};

static double ney_beta(const struct ney *c, double b, double *sd, double *gam)
{
	*sd = wls_sd(c->d, (1u << NT) - 1, c->j, c->s, b, gam);
	if (!(*sd > 0))
		return NAN;
	return c->alpha * (1 - gsl_cdf_ugaussian_P(b / *sd - c->zdet) / 2);
}

/* does the acceptance region of b hold x? side -1: its upper limit (for
 * the lower bound), +1 its lower limit */
static int ney_in(const struct ney *c, double b, double x, int side)
{
	double sd, gam, beta = ney_beta(c, b, &sd, &gam);

	if (isnan(beta))
		return -1;
	if (side < 0)
		return 1 - skew_P((x - b) / sd, gam) >= c->alpha - beta;
	return skew_P((x - b) / sd, gam) >= beta;
}

static double rel_width(const struct pdesign *d, int j, double s, double xr,
			double level, double zdet)
{
	struct ney c = { d, j, s, 1 - level, zdet };
	double lo = 0, hi = xr, l2, h2;
	int in = ney_in(&c, 0, xr, -1);

	if (in < 0)
		return NAN;
	if (in)
		return INFINITY; /* lo = 0 */
	while (hi / (lo > 0 ? lo : hi * 1e-12) > 1 + 1e-7 && hi - lo > 1e-9 * hi) {
		double m = (lo + hi) / 2;

		in = ney_in(&c, m, xr, -1);
		if (in < 0)
			return NAN;
		if (in)
			hi = m;
		else
			lo = m;
	}
	l2 = hi;
	lo = xr;
	hi = 2 * xr;
	while ((in = ney_in(&c, hi, xr, +1)) == 1) {
		lo = hi;
		hi *= 2;
		if (hi > 1e9 * xr)
			return INFINITY;
	}
	if (in < 0)
		return NAN;
	while (hi - lo > 1e-7 * hi) {
		double m = (lo + hi) / 2;

		in = ney_in(&c, m, xr, +1);
		if (in < 0)
			return NAN;
		if (in)
			lo = m;
		else
			hi = m;
	}
	h2 = lo;
	return (sqrt(h2) - sqrt(l2)) / (2 * sqrt(xr));
}

/*
 * The presence test: the GLS fit of the model's terms (whitened by C at
 * the truth), sd1 of the term's square, and sd0 = sqrt(h' Cn h), h its hat
 * row, Cn the covariance under the fit without the term (the test's null).
 */
static int gls_sds(const struct pdesign *d, unsigned mask, int j,
		   double *sd1, double *sd0)
{
	size_t n = d->n, p = 0;
	int cols[NT], aj = -1;
	double *L = NULL, *X = NULL, *h = NULL, M[NT * NT] = { 0 };
	struct ssc_gsl_quiet quiet;
	int rc = 0;

	for (int k = 0; k < NT; k++)
		if (mask & (1u << k)) {
			if (k == j)
				aj = (int)p;
			cols[p++] = k;
		}
	L = malloc(n * n * sizeof(double));
	X = malloc(n * p * sizeof(double));
	h = malloc(n * sizeof(double));
	if (!L || !X || !h) {
		rc = -ENOMEM;
		goto out;
	}
	{
		gsl_matrix_view v = gsl_matrix_view_array(L, n, n);

		/* neighbouring points of a long record are correlated
		 * almost fully: a ridge of 1e-12 .. 1e-6 of the diagonal
		 * where the factor fails in double precision */
		ssc_gsl_quiet_begin(&quiet);
		for (double ridge = 0; ridge <= 1e-6; ridge = ridge > 0 ? ridge * 100 : 1e-12) {
			cov_at(d, 1, L);
			for (size_t i = 0; i < n; i++)
				L[i * n + i] *= 1 + ridge;
			rc = gsl_linalg_cholesky_decomp1(&v.matrix);
			if (!rc)
				break;
		}
		ssc_gsl_quiet_end(&quiet);
		if (rc) {
			rc = -EDOM; /* the fit's own fallback: see predict() */
			goto out;
		}
	}
	/* X = L^-1 A (relative) */
	for (size_t a = 0; a < p; a++) {
		for (size_t i = 0; i < n; i++) {
			double t = basis(cols[a], d->tau[i]) / d->mu[i];

			for (size_t k = 0; k < i; k++)
				t -= L[i * n + k] * X[k * p + a];
			X[i * p + a] = t / L[i * n + i];
		}
	}
	for (size_t a = 0; a < p; a++)
		for (size_t b = 0; b < p; b++)
			for (size_t i = 0; i < n; i++)
				M[a * p + b] += X[i * p + a] * X[i * p + b];
	if ((rc = spd_inv(M, p)))
		goto out;
	*sd1 = sqrt(M[aj * (int)p + aj]);
	/* h = L^-T X M e_j */
	for (size_t i = 0; i < n; i++) {
		double t = 0;

		for (size_t a = 0; a < p; a++)
			t += X[i * p + a] * M[a * p + (size_t)aj];
		h[i] = t;
	}
	for (size_t i = n; i-- > 0;) {
		double t = h[i];

		for (size_t k = i + 1; k < n; k++)
			t -= L[k * n + i] * h[k];
		h[i] = t / L[i * n + i];
	}
	{
		double v = 0;

		for (size_t a = 0; a < n; a++) {
			double r = 0;

			for (size_t b = 0; b < n; b++)
				r += d->cn[a * n + b] * h[b];
			v += h[a] * r;
		}
		*sd0 = v > 0 ? sqrt(v) : *sd1;
	}
out:
	free(L);
	free(X);
	free(h);
	return rc;
}

/* the expected squares of the model's terms without j: the GLS-free
 * weighted fit of the noise-free curve by the other terms, clamped at 0 */
static void null_coef(const struct pdesign *d, const double coef[NT],
		      unsigned mask, int j, double out[NT])
{
	double M[NT * NT] = { 0 }, r[NT] = { 0 };
	int cols[NT];
	size_t p = 0;

	memcpy(out, coef, NT * sizeof(double));
	out[j] = 0;
	for (int k = 0; k < NT; k++)
		if (k != j && (mask & (1u << k)))
			cols[p++] = k;
	if (!p)
		return;
	for (size_t a = 0; a < p; a++) {
		for (size_t i = 0; i < d->n; i++) {
			double ba = basis(cols[a], d->tau[i]) / d->mu[i];

			r[a] += ba; /* y / mu = 1 */
			for (size_t b = 0; b < p; b++)
				M[a * p + b] += ba * basis(cols[b], d->tau[i]) /
						d->mu[i];
		}
	}
	if (spd_inv(M, p))
		return;
	for (size_t a = 0; a < p; a++) {
		double t = 0;

		for (size_t b = 0; b < p; b++)
			t += M[a * p + b] * r[b];
		out[cols[a]] = sqrt(fmax(t, 0));
	}
}

/*
 * The restricted direction: with square j held at xr s (the fit's bootstrap
 * tests a value b so), the weighted fit of every other term moves by
 * (xr - 1) s D_jk, D_jk = (A'WA)^-1_kj / (A'WA)^-1_jj (noisefit.c,
 * hat_rows()), W the inverse variances c of the points at the truth.
 */
static void restricted_dir(struct pdesign *d, const double *c)
{
	double M[NT * NT] = { 0 }, Bm[NT * NT] = { 0 }, V[NT * NT] = { 0 };
	double *wa = NULL;
	size_t n = d->n;
	int j = d->j;

	memset(d->dsq, 0, sizeof(d->dsq));
	memset(d->sig, 0, sizeof(d->sig));
	for (int a = 0; a < NT; a++)
		for (int b = 0; b < NT; b++)
			for (size_t i = 0; i < n; i++)
				M[a * NT + b] += basis(a, d->tau[i]) *
						 basis(b, d->tau[i]) /
						 (c[i * n + i] * d->mu[i] * d->mu[i]);
	if (spd_inv(M, NT))
		return; /* unrestricted */
	for (int k = 0; k < NT; k++)
		if (k != j)
			d->dsq[k] = M[k * NT + j] / M[j * NT + j] * d->s[j];
	/* the sandwich covariance V = M A'W C W A M of the estimates */
	wa = malloc(NT * n * sizeof(double));
	if (!wa)
		return;
	for (int a = 0; a < NT; a++)
		for (size_t i = 0; i < n; i++)
			wa[a * n + i] = basis(a, d->tau[i]) /
					(d->mu[i] * c[i * n + i]);
	for (int a = 0; a < NT; a++)
		for (int b = a; b < NT; b++) {
			double t = 0;

			for (size_t i = 0; i < n; i++) {
				double r = 0;

				for (size_t k = 0; k < n; k++)
					r += c[i * n + k] * wa[b * n + k];
				t += wa[a * n + i] * r;
			}
			Bm[a * NT + b] = Bm[b * NT + a] = t;
		}
	free(wa);
	for (int a = 0; a < NT; a++)
		for (int b = 0; b < NT; b++)
			for (int k = 0; k < NT; k++)
				for (int l = 0; l < NT; l++)
					V[a * NT + b] += M[a * NT + k] * Bm[k * NT + l] *
							 M[l * NT + b];
	for (int k = 0; k < NT; k++)
		if (k != j && V[j * NT + j] > 0)
			d->sig[k] = sqrt(fmax(V[k * NT + k] - V[k * NT + j] * V[k * NT + j] /
						      V[j * NT + j], 0));
}

/* the covariances: under the null's fit (d->cn), and the pair matrices of
 * cov_at() from the terms that enter at some tested value */
static int pdesign_cov(struct pdesign *d, const double coef[NT], unsigned mask,
		       double rate_hz, const size_t *m, const size_t *terms)
{
	size_t n = d->n, nn = n * n, nset = 0;
	double sets[2 + NT + NPAIR][NT], sc[NT], *all;
	int act[NT], na = 0, rc;

	memset(sets, 0, sizeof(sets));
	memcpy(sets[0], coef, sizeof(sets[0]));
	null_coef(d, coef, mask, d->j, sets[1]);
	all = malloc(2 * nn * sizeof(double));
	if (!all)
		return -ENOMEM;
	rc = ssc_noise_avar_cov_many((const double(*)[5])sets, 2, rate_hz, m,
				     terms, n, all);
	if (rc) {
		free(all);
		return rc;
	}
	for (size_t a = 0; a < n; a++)
		for (size_t b = 0; b < n; b++) {
			double scale = d->mu[a] * d->mu[b];

			all[a * n + b] /= scale;
			d->cn[a * n + b] = all[nn + a * n + b] / scale;
		}
	restricted_dir(d, all);
	free(all);
	memset(sets, 0, sizeof(sets));
	for (int k = 0; k < NT; k++) {
		sc[k] = d->s[k] > 0 ? d->s[k] : fmax(fabs(d->dsq[k]), d->sig[k]);
		if (sc[k] > 0)
			act[na++] = k;
	}
	for (int a = 0; a < na; a++)
		sets[nset++][act[a]] = sqrt(sc[act[a]]);
	for (int a = 0; a < na; a++)
		for (int b = a + 1; b < na; b++) {
			sets[nset][act[a]] = sqrt(sc[act[a]]);
			sets[nset++][act[b]] = sqrt(sc[act[b]]);
		}
	all = malloc(nset * nn * sizeof(double));
	if (!all)
		return -ENOMEM;
	rc = ssc_noise_avar_cov_many((const double(*)[5])sets, nset, rate_hz, m,
				     terms, n, all);
	if (rc) {
		free(all);
		return rc;
	}
	nset = (size_t)na;
	for (int a = 0; a < na; a++)
		for (int b = a; b < na; b++) {
			int p = d->npair;
			const double *ca = all + (size_t)a * nn;
			const double *cb = all + (size_t)b * nn;
			const double *cab = all + (a == b ? (size_t)a : nset++) * nn;

			d->g[p] = malloc(nn * sizeof(double));
			if (!d->g[p]) {
				free(all);
				return -ENOMEM;
			}
			d->pk[p] = act[a];
			d->pl[p] = act[b];
			d->npair++;
			for (size_t i = 0; i < nn; i++) {
				double v = a == b ? ca[i] : cab[i] - ca[i] - cb[i];

				d->g[p][i] = v / (sc[act[a]] * sc[act[b]] *
						  d->mu[i / n] * d->mu[i % n]);
			}
		}
	free(all);
	return 0;
}

static int check_args(const double coef[NT], double rate_hz,
		      enum sscope_term term, double target,
		      const struct sscope_plan_opts *opts,
		      struct sscope_plan_opts *o)
{
	if (!coef || !(rate_hz > 0) || !isfinite(rate_hz) ||
	    (int)term < 0 || (int)term >= NT || !(target > 0) ||
	    !isfinite(target))
		return -EINVAL;
	for (int k = 0; k < NT; k++)
		if (!(coef[k] >= 0) || !isfinite(coef[k]))
			return -EINVAL;
	memset(o, 0, sizeof(*o));
	if (opts)
		*o = *opts;
	if (o->ci_level == 0)
		o->ci_level = 0.682689492137086;
	if (o->probability == 0)
		o->probability = 0.9;
	if (o->detect_sigma == 0)
		o->detect_sigma = 3;
	if (o->max_length_s == 0)
		o->max_length_s = 30 * 86400.0;
	if (!(o->ci_level > 0 && o->ci_level < 1) ||
	    !(o->probability > 0 && o->probability < 1) ||
	    !(o->detect_sigma > 0) || !isfinite(o->detect_sigma) ||
	    !(o->max_length_s > 0) || !isfinite(o->max_length_s))
		return -EINVAL;
	return 0;
}

static int predict(const double coef[NT], double rate_hz, double length_s,
		   int j, double target, const struct sscope_plan_opts *o,
		   struct sscope_plan_point *out)
{
	struct pdesign d = { 0 };
	size_t m[MAX_POINTS], terms[MAX_POINTS], count, np, nsamp;
	double s = coef[j] * coef[j], sd1, sd0, xs;
	unsigned mask = 0;
	int rc;

	memset(out, 0, sizeof(*out));
	out->length_s = length_s;
	out->rel_half_width = INFINITY;
	if (!(length_s > 0) || !isfinite(length_s) ||
	    length_s * rate_hz > 1e15)
		return -EINVAL;
	if (!(s > 0))
		return 0;
	for (int k = 0; k < NT; k++)
		if (coef[k] > 0)
			mask |= 1u << k;
	nsamp = ssc_count(round(length_s * rate_hz));
	np = sscope_allan_n_phase(SSCOPE_ALLAN_RATE, nsamp);
	rc = sscope_allan_grid(SSCOPE_ALLAN_TAUS_DENSE,
			       sscope_allan_max_m(SSCOPE_ALLAN_DEV_OADEV, np), m,
			       MAX_POINTS, &count);
	if (rc)
		return rc;
	if (count > MAX_POINTS)
		count = MAX_POINTS;
	if (count < MIN_POINTS)
		return 0;
	d.n = count;
	for (size_t i = 0; i < count; i++) {
		terms[i] = np - 2 * m[i];
		d.tau[i] = (double)m[i] / rate_hz;
		d.mu[i] = sscope_noise_avar(coef, d.tau[i]);
		if (!(d.mu[i] > 0))
			return -EINVAL;
	}
	d.j = j;
	for (int k = 0; k < NT; k++)
		d.s[k] = coef[k] * coef[k];
	d.cn = malloc(count * count * sizeof(double));
	d.work = malloc(count * count * sizeof(double));
	if (!d.cn || !d.work) {
		rc = -ENOMEM;
		goto out;
	}
	rc = pdesign_cov(&d, coef, mask, rate_hz, m, terms);
	if (rc)
		goto out;
	/* presence */
	rc = gls_sds(&d, mask, j, &sd1, &sd0);
	if (rc == -EDOM) {
		/* the covariance cannot be factored in double precision (long
		 * records: neighbouring points almost fully correlated): the
		 * fit then selects by backward elimination on the weighted
		 * nested fits' sandwich z, and so does the prediction */
		sd1 = sd0 = s * wls_sd(&d, mask, j, s, 1, NULL);
		rc = isfinite(sd1) ? 0 : -EDOM;
	}
	if (rc)
		goto out;
	out->p_present = gsl_cdf_ugaussian_P((s - o->detect_sigma * sd0) / sd1);
	/* precision: x* where the relative half-width reaches the target */
	out->rel_half_width = rel_width(&d, j, s, 1, o->ci_level, o->detect_sigma);
	xs = wls_sd(&d, (1u << NT) - 1, j, s, 1, NULL);
	if (isnan(out->rel_half_width) || !isfinite(xs)) {
		rc = -EDOM;
		goto out;
	}
	/* a term absent from the model is estimated about 0 and clamped
	 * there (noisefit.c, boot_pass()), which splits records in two
	 * (measured: STIM300 B over 4 h, widths about 0.2 and 0.5 at the
	 * same estimate): estimated above 0 it follows the tested value as
	 * the restricted fit says and widens the interval, below 0 it stays
	 * at 0.  Two scenarios of equal weight: every absent term 1 sd (given
	 * the estimate of j) above 0 and restricted, or held at 0 */
	out->p_width = 0;
	for (int sc = -1; sc <= 1; sc += 2) {
		double lo = 1e-6, hi = 1e6, wl, wh;

		for (int k = 0; k < NT; k++) {
			d.eps[k] = d.s[k] > 0 ? 0 : sc * d.sig[k];
			d.frozen[k] = sc < 0 && !(d.s[k] > 0);
		}
		wl = rel_width(&d, j, s, lo, o->ci_level, o->detect_sigma);
		wh = rel_width(&d, j, s, hi, o->ci_level, o->detect_sigma);
		if (!(wh <= target))
			continue;
		if (wl <= target) {
			out->p_width += 0.5;
			continue;
		}
		while (hi / lo > 1 + 1e-4) {
			double mid = sqrt(lo * hi);
			double w = rel_width(&d, j, s, mid, o->ci_level, o->detect_sigma);

			if (w <= target)
				hi = mid;
			else
				lo = mid;
		}
		out->p_width += 0.5 * gsl_cdf_ugaussian_P((1 - hi) / xs);
	}
	out->probability = fmin(out->p_present, out->p_width);
out:
	pdesign_free(&d);
	return rc;
}

int sscope_plan_predict(const double coef[5], double rate_hz, double length_s,
			enum sscope_term term, double target,
			const struct sscope_plan_opts *opts,
			struct sscope_plan_point *out)
{
	struct sscope_plan_opts o;
	int rc;

	if (!out)
		return -EINVAL;
	rc = check_args(coef, rate_hz, term, target, opts, &o);
	if (rc)
		return rc;
	return predict(coef, rate_hz, length_s, (int)term, target, &o, out);
}

int sscope_plan_needed(const double coef[5], double rate_hz,
		       enum sscope_term term, double target,
		       const struct sscope_plan_opts *opts, double *length_s)
{
	struct sscope_plan_opts o;
	struct sscope_plan_point pt;
	double lo, hi;
	int rc;

	if (!length_s)
		return -EINVAL;
	rc = check_args(coef, rate_hz, term, target, opts, &o);
	if (rc)
		return rc;
	*length_s = INFINITY;
	if (!(coef[term] > 0))
		return 0;
	/* up in octaves to the first length that reaches the probability
	 * (not from the longest: a model with a ramp or a strong random walk
	 * can lose the term again in very long records), then bisect */
	hi = fmin(o.max_length_s, 32 / rate_hz);
	lo = 0;
	for (;;) {
		if ((rc = predict(coef, rate_hz, hi, (int)term, target, &o, &pt)))
			return rc;
		if (pt.probability >= o.probability)
			break;
		if (hi >= o.max_length_s)
			return 0;
		lo = hi;
		hi = fmin(2 * hi, o.max_length_s);
	}
	if (lo == 0) {
		*length_s = hi;
		return 0;
	}
	while (hi / lo > 1.01) {
		double mid = sqrt(lo * hi);

		rc = predict(coef, rate_hz, mid, (int)term, target, &o, &pt);
		if (rc)
			return rc;
		if (pt.probability >= o.probability)
			hi = mid;
		else
			lo = mid;
	}
	*length_s = hi;
	return 0;
}
