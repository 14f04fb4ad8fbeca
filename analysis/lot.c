/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The spread of a quantity over a lot of units (see sscope-lot.h for the
 * model, the estimators and their references).  The estimates are centred
 * on their median first, so that a quantity with a large common offset
 * (a bias of 1e3 with units that differ by 1e-3) loses no digits in the
 * weighted sums; the chi-squared and t quantiles and the root of the
 * Q profile come from GSL.  A unit's bias, drift and temperature
 * sensitivity: batch means fitted by least squares (GSL's SVD) on centred
 * and scaled regressors, the block means summed compensated about the
 * record's mean (see sscope_lot_bias()).  The drift's and sensitivity's
 * variance under a unit's noise model: the weights of the estimates (a
 * row of the design's pseudo-inverse, GSL's SVD) against the structure
 * function of the block means of white, flicker and random-walk rate
 * noise, in closed form (sscope_lot_model_var(); IEEE Std 952-1997,
 * Annex C, for the terms' spectra; the flicker term from the integral of
 * its 1/f spectrum against the block filter, checked numerically to 1e-6
 * for d = 1..19).
 */
#include "internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit.h>
#include <gsl/gsl_roots.h>

#include "sscope-lot.h"

#define REML_ITERS 200

/* weighted mean of d with weights 1 / (v + t2), and the sums used */
struct wsum {
	double sw, sw2, sw3, mu, q; /* q: sum w (d - mu)^2 */
};

static void weigh(const double *d, const double *v, size_t k, double t2,
		  struct wsum *s)
{
	struct ssc_ksum a = { 0, 0 }, b = { 0, 0 }, c = { 0, 0 }, e = { 0, 0 },
			q = { 0, 0 };

	for (size_t i = 0; i < k; i++) {
		double w = 1 / (v[i] + t2);

		ssc_ksum_add(&a, w);
		ssc_ksum_add(&b, w * w);
		ssc_ksum_add(&c, w * w * w);
		ssc_ksum_add(&e, w * d[i]);
	}
	s->sw = ssc_ksum_value(&a);
	s->sw2 = ssc_ksum_value(&b);
	s->sw3 = ssc_ksum_value(&c);
	s->mu = ssc_ksum_value(&e) / s->sw;
	for (size_t i = 0; i < k; i++) {
		double r = d[i] - s->mu;

		ssc_ksum_add(&q, r * r / (v[i] + t2));
	}
	s->q = ssc_ksum_value(&q);
}

/* REML tau^2 by Fisher scoring from the DerSimonian-Laird value */
static double reml_tau2(const double *d, const double *v, size_t k)
{
	struct wsum s;
	double t2, c;

	weigh(d, v, k, 0, &s);
	c = s.sw - s.sw2 / s.sw;
	t2 = c > 0 ? fmax(0, (s.q - (double)(k - 1)) / c) : 0;
	for (int it = 0; it < REML_ITERS; it++) {
		struct ssc_ksum r2 = { 0, 0 };
		double score, info, step, next;

		weigh(d, v, k, t2, &s);
		for (size_t i = 0; i < k; i++) {
			double w = 1 / (v[i] + t2), r = d[i] - s.mu;

			ssc_ksum_add(&r2, w * w * r * r);
		}
		score = 0.5 * (ssc_ksum_value(&r2) - (s.sw - s.sw2 / s.sw));
		info = 0.5 * (s.sw2 - 2 * s.sw3 / s.sw + (s.sw2 / s.sw) * (s.sw2 / s.sw));
		if (!(info > 0))
			break;
		step = score / info;
		next = fmax(0, t2 + step);
		/* converged: a step below 1e-12 of tau^2 plus a typical
		 * within-unit variance; or held at zero */
		if (fabs(next - t2) <= 1e-12 * (t2 + (double)k / s.sw) ||
		    (next == 0 && t2 == 0)) {
			t2 = next;
			break;
		}
		t2 = next;
	}
	return t2;
}

struct qprof {
	const double *d, *v;
	size_t k;
	double target;
};

static double q_minus(double t2, void *ctx)
{
	const struct qprof *p = ctx;
	struct wsum s;

	weigh(p->d, p->v, p->k, t2, &s);
	return s.q - p->target;
}

/* the tau^2 where the generalised Q equals target (Q(0) > target):
 * bracketed, then Brent's method */
static int q_root(const double *d, const double *v, size_t k, double target,
		  double scale, double *out)
{
	struct qprof p = { d, v, k, target };
	gsl_function F = { q_minus, &p };
	gsl_root_fsolver *s;
	double lo = 0, hi = scale > 0 ? scale : 1;
	int status, it = 0;

	for (int g = 0; q_minus(hi, &p) > 0; g++) {
		if (g > 200)
			return -EDOM;
		lo = hi;
		hi *= 4;
	}
	s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
	if (!s)
		return -ENOMEM;
	if (gsl_root_fsolver_set(s, &F, lo, hi)) {
		gsl_root_fsolver_free(s);
		return -EDOM;
	}
	do {
		status = gsl_root_fsolver_iterate(s);
		lo = gsl_root_fsolver_x_lower(s);
		hi = gsl_root_fsolver_x_upper(s);
		if (!status)
			status = gsl_root_test_interval(lo, hi, 0, 1e-13);
	} while (status == GSL_CONTINUE && ++it < 300);
	*out = gsl_root_fsolver_root(s);
	gsl_root_fsolver_free(s);
	return 0;
}

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return x < y ? -1 : x > y;
}

static double median_of(double *w, size_t k)
{
	qsort(w, k, sizeof(double), cmp_d);
	return k % 2 ? w[k / 2] : 0.5 * (w[k / 2 - 1] + w[k / 2]);
}

/* mean, tau and their intervals, Q and I^2 of n centred estimates d with
 * variances v (c: the centre added back to the mean) */
static int estimate(const double *d, const double *v, size_t n, double c,
		    double level, struct sscope_lot_spread *out)
{
	struct wsum s;
	struct ssc_ksum m = { 0, 0 }, ss = { 0, 0 };
	double t2, lo2 = 0, hi2 = 0, a = 1 - level, qlo, qhi, scale, mean;
	int rc = 0;

	for (size_t i = 0; i < n; i++)
		ssc_ksum_add(&m, d[i]);
	mean = ssc_ksum_value(&m) / (double)n;
	for (size_t i = 0; i < n; i++)
		ssc_ksum_add(&ss, (d[i] - mean) * (d[i] - mean));
	out->total_sd = sqrt(ssc_ksum_value(&ss) / (double)(n - 1));
	/* Cochran's Q, I^2 */
	weigh(d, v, n, 0, &s);
	out->q = s.q;
	out->q_p = gsl_cdf_chisq_Q(s.q, (double)(n - 1));
	t2 = reml_tau2(d, v, n);
	{
		double typ = (double)(n - 1) * s.sw / (s.sw * s.sw - s.sw2);

		out->i2 = t2 > 0 && isfinite(typ) ? t2 / (t2 + typ) : 0;
	}
	out->between_sd = sqrt(t2);
	/* the Q profile of tau^2 between the chi-squared quantiles */
	qhi = gsl_cdf_chisq_Qinv(a / 2, (double)(n - 1));
	qlo = gsl_cdf_chisq_Pinv(a / 2, (double)(n - 1));
	scale = fmax(t2, out->total_sd * out->total_sd);
	if (!(scale > 0))
		scale = (double)n / s.sw;
	if (s.q > qhi)
		rc = q_root(d, v, n, qhi, scale, &lo2);
	if (!rc && s.q > qlo)
		rc = q_root(d, v, n, qlo, scale, &hi2);
	if (rc)
		return rc;
	out->between_lo = sqrt(lo2);
	out->between_hi = sqrt(hi2);
	/* the mean and its Hartung-Knapp interval */
	weigh(d, v, n, t2, &s);
	{
		double var = s.q / (double)(n - 1) / s.sw;
		double tq = gsl_cdf_tdist_Pinv(1 - a / 2, (double)(n - 1));

		out->mean = c + s.mu;
		out->mean_lo = out->mean - tq * sqrt(var);
		out->mean_hi = out->mean + tq * sqrt(var);
	}
	return 0;
}

int sscope_lot_spread(const double *y, const double *se, size_t k,
		      const struct sscope_lot_opts *opts,
		      struct sscope_lot_spread *out, double *z, bool *outlier)
{
	double level = opts && opts->level > 0 ? opts->level : 0.90;
	double alpha_o = opts && opts->outlier_alpha > 0 ? opts->outlier_alpha : 0.01;
	double *d, *v, *w, *dc, *vc, c, mad, med_v, thr, thr_fw, mu = 0, t2;
	bool *fl, *ex, keep;
	size_t n = 0;
	struct ssc_gsl_quiet quiet;
	int rc = 0;

	if (!y || !se || !out)
		return -EINVAL;
	if (!(level < 1) || !(alpha_o < 1))
		return -EINVAL;
	memset(out, 0, sizeof(*out));
	if (k < 3)
		return -EDOM;
	/* squares and weights stay finite and non-zero */
	for (size_t i = 0; i < k; i++)
		if (!(fabs(y[i]) <= 1e150) || !(se[i] >= 1e-150 && se[i] <= 1e150))
			return -EDOM;
	d = ssc_alloc_array(k, sizeof(double));
	v = ssc_alloc_array(k, sizeof(double));
	w = ssc_alloc_array(k, sizeof(double));
	dc = ssc_alloc_array(k, sizeof(double));
	vc = ssc_alloc_array(k, sizeof(double));
	fl = calloc(k, sizeof(bool));
	ex = calloc(k, sizeof(bool));
	if (!d || !v || !w || !dc || !vc || !fl || !ex) {
		rc = -ENOMEM;
		goto done;
	}
	ssc_gsl_quiet_begin(&quiet);
	memcpy(w, y, k * sizeof(double));
	c = median_of(w, k);
	for (size_t i = 0; i < k; i++) {
		d[i] = y[i] - c;
		v[i] = se[i] * se[i];
	}
	out->k = k;
	out->level = level;
	thr = gsl_cdf_ugaussian_Qinv(alpha_o / 2);
	out->outlier_z = thr;

	/* The yardstick: the mean and tau (REML) of the units that do not
	 * stand out beyond a family-wise level (the per-unit rate divided by
	 * the number of units, Bonferroni): first judged against the median
	 * and the spread the median absolute deviation implies, then
	 * against the yardstick itself until that set settles.  Excluding
	 * only these keeps the yardstick from being trimmed by the units a
	 * per-unit test flags by chance (which would narrow it and flag
	 * more). */
	thr_fw = gsl_cdf_ugaussian_Qinv(alpha_o / 2 / (double)k);
	for (size_t i = 0; i < k; i++)
		w[i] = fabs(d[i]);
	mad = 1.482602218505602 * median_of(w, k);
	memcpy(w, v, k * sizeof(double));
	med_v = median_of(w, k);
	t2 = fmax(0, mad * mad - med_v);
	for (int it = 0; it < 20; it++) {
		bool changed = false;

		for (size_t i = 0; i < k; i++) {
			bool f = fabs(d[i] - mu) / sqrt(v[i] + t2) > thr_fw;

			changed |= f != ex[i];
			ex[i] = f;
		}
		if (!changed && it > 0)
			break;
		n = 0;
		for (size_t i = 0; i < k; i++)
			if (!ex[i]) {
				dc[n] = d[i];
				vc[n++] = v[i];
			}
		if (n < 3)
			break; /* most units stand out: no yardstick */
		t2 = reml_tau2(dc, vc, n);
		{
			struct wsum s;

			weigh(dc, vc, n, t2, &s);
			mu = s.mu;
		}
	}
	/* each unit against the yardstick at the per-unit rate */
	out->n_outliers = 0;
	for (size_t i = 0; i < k; i++) {
		double zi = (d[i] - mu) / sqrt(v[i] + t2);

		fl[i] = fabs(zi) > thr;
		out->n_outliers += fl[i];
		if (z)
			z[i] = zi;
		if (outlier)
			outlier[i] = fl[i];
	}
	/* the lot's spread: without the units beyond the family-wise
	 * level unless asked, or when fewer than three would remain */
	n = 0;
	for (size_t i = 0; i < k; i++)
		n += !ex[i];
	keep = (opts && opts->keep_outliers) || n < 3;
	n = 0;
	for (size_t i = 0; i < k; i++)
		if (!ex[i] || keep) {
			dc[n] = d[i];
			vc[n++] = v[i];
		}
	out->k_used = n;
	rc = estimate(dc, vc, n, c, level, out);
	ssc_gsl_quiet_end(&quiet);
done:
	free(d);
	free(v);
	free(w);
	free(dc);
	free(vc);
	free(fl);
	free(ex);
	return rc;
}

int sscope_lot_cpk(const double *y, const double *se, size_t k, double usl,
		   double level, struct sscope_lot_cpk *out)
{
	struct sscope_lot_opts o = { .keep_outliers = true };
	struct sscope_lot_spread sp;
	struct ssc_ksum sw = { 0, 0 }, sw2 = { 0, 0 };
	double typ, z, var;
	int rc;

	if (!y || !se || !out || !isfinite(usl))
		return -EINVAL;
	if (level == 0)
		level = 0.90;
	if (!(level > 0 && level < 1))
		return -EINVAL;
	o.level = level;
	rc = sscope_lot_spread(y, se, k, &o, &sp, NULL, NULL);
	if (rc)
		return rc;
	for (size_t i = 0; i < k; i++) {
		double w = 1 / (se[i] * se[i]);

		ssc_ksum_add(&sw, w);
		ssc_ksum_add(&sw2, w * w);
	}
	/* typical within-unit variance (Higgins and Thompson): the common
	 * se^2 when all are equal */
	typ = (double)(k - 1) * ssc_ksum_value(&sw) /
	      (ssc_ksum_value(&sw) * ssc_ksum_value(&sw) - ssc_ksum_value(&sw2));
	memset(out, 0, sizeof(*out));
	out->n = k;
	out->level = level;
	out->usl = usl;
	out->mean = sp.mean;
	out->between_sd = sp.between_sd;
	out->within_sd = sqrt(typ);
	out->sigma = sqrt(sp.between_sd * sp.between_sd + typ);
	if (!(out->sigma > 0) || !isfinite(out->sigma))
		return -EDOM;
	out->cpk = (usl - sp.mean) / (3 * out->sigma);
	/* Bissell (1990): var(Cpk) ~ 1 / (9 n) + Cpk^2 / (2 (n - 1)) */
	var = 1 / (9.0 * (double)k) + out->cpk * out->cpk / (2.0 * (double)(k - 1));
	z = gsl_cdf_ugaussian_Pinv(0.5 + level / 2);
	out->lo = out->cpk - z * sqrt(var);
	out->hi = out->cpk + z * sqrt(var);
	return 0;
}

/* the least-squares line of y_j on (x_j - mean) / sd, j < m: slope per
 * unit of x, intercept (the mean of y), their standard errors from the
 * residuals (m - 2 degrees of freedom); false when x is constant */
static bool line_fit(const double *x, const double *y, size_t m, double *a,
		     double *a_se, double *b, double *b_se)
{
	double xm = 0, sxx = 0, sxy = 0, ym = 0, rss = 0, s2, sd;

	for (size_t j = 0; j < m; j++) {
		xm += x[j];
		ym += y[j];
	}
	xm /= (double)m;
	ym /= (double)m;
	for (size_t j = 0; j < m; j++)
		sxx += (x[j] - xm) * (x[j] - xm);
	sd = sqrt(sxx / (double)m);
	if (!(sd > 0) || !isfinite(sd))
		return false;
	/* centred and scaled regressor u = (x - xm) / sd: sum u^2 = m */
	for (size_t j = 0; j < m; j++)
		sxy += (x[j] - xm) / sd * (y[j] - ym);
	for (size_t j = 0; j < m; j++) {
		double r = y[j] - ym - sxy / (double)m * (x[j] - xm) / sd;

		rss += r * r;
	}
	s2 = rss / (double)(m - 2);
	*a = ym;
	*a_se = sqrt(s2 / (double)m);
	*b = sxy / (double)m / sd;
	*b_se = sqrt(s2 / (double)m) / sd;
	return true;
}

/* the joint least-squares fit y_j = a + d u_j + c v_j, u and v the
 * centred and scaled x and w (SVD, GSL): a, d per unit of x, c per unit
 * of w and their standard errors from the residuals (m - 3 degrees of
 * freedom); false when a regressor is constant or the fit fails */
static bool plane_fit(const double *x, const double *w, const double *y, size_t m,
		      double est[3], double se[3])
{
	double xm = 0, wm = 0, sx = 0, sw = 0, chisq;
	gsl_matrix *X = gsl_matrix_alloc(m, 3), *cov = gsl_matrix_alloc(3, 3);
	gsl_vector *c = gsl_vector_alloc(3);
	gsl_multifit_linear_workspace *ws = gsl_multifit_linear_alloc(m, 3);
	gsl_vector_const_view yv = gsl_vector_const_view_array(y, m);
	bool ok = false;

	if (!X || !cov || !c || !ws)
		goto out;
	for (size_t j = 0; j < m; j++) {
		xm += x[j];
		wm += w[j];
	}
	xm /= (double)m;
	wm /= (double)m;
	for (size_t j = 0; j < m; j++) {
		sx += (x[j] - xm) * (x[j] - xm);
		sw += (w[j] - wm) * (w[j] - wm);
	}
	sx = sqrt(sx / (double)m);
	sw = sqrt(sw / (double)m);
	/* constant up to the rounding of the block means: no slope */
	if (!(sx > 64 * DBL_EPSILON * fabs(xm)) || !(sw > 64 * DBL_EPSILON * fabs(wm)) ||
	    !isfinite(sx) || !isfinite(sw))
		goto out;
	for (size_t j = 0; j < m; j++) {
		gsl_matrix_set(X, j, 0, 1);
		gsl_matrix_set(X, j, 1, (x[j] - xm) / sx);
		gsl_matrix_set(X, j, 2, (w[j] - wm) / sw);
	}
	if (gsl_multifit_linear(X, &yv.vector, c, cov, &chisq, ws))
		goto out;
	est[0] = gsl_vector_get(c, 0);
	est[1] = gsl_vector_get(c, 1) / sx;
	est[2] = gsl_vector_get(c, 2) / sw;
	se[0] = sqrt(gsl_matrix_get(cov, 0, 0));
	se[1] = sqrt(gsl_matrix_get(cov, 1, 1)) / sx;
	se[2] = sqrt(gsl_matrix_get(cov, 2, 2)) / sw;
	ok = isfinite(est[2]) && isfinite(se[2]);
out:
	gsl_matrix_free(X);
	gsl_matrix_free(cov);
	gsl_vector_free(c);
	if (ws)
		gsl_multifit_linear_free(ws);
	return ok;
}

/* g(d) of the flicker's block-mean structure function (sscope-lot.h):
 * -d^2 ln d + (d+1)^2 ln(d+1) / 2 + (d-1)^2 ln(d-1) / 2 with the logs
 * about ln d (the d^2 ln d terms cancel: log1p keeps the digits) */
static double flicker_g(double d)
{
	if (d == 1)
		return 2 * M_LN2;
	return log(d) + 0.5 * (d + 1) * (d + 1) * log1p(1 / d) +
	       0.5 * (d - 1) * (d - 1) * log1p(-1 / d);
}

int sscope_lot_model_var(const double *a, size_t m, double block_s, double n,
			 double b, double k, double *var)
{
	struct ssc_ksum sa = { 0, 0 }, v = { 0, 0 };
	double mag = 0, mean, s2 = 0;

	if (!a || !var || !(block_s > 0) || !isfinite(block_s) || !(n >= 0) ||
	    !(b >= 0) || !(k >= 0) || !isfinite(n) || !isfinite(b) || !isfinite(k))
		return -EINVAL;
	if (m < 2)
		return -EDOM;
	for (size_t j = 0; j < m; j++) {
		if (!isfinite(a[j]))
			return -EDOM;
		ssc_ksum_add(&sa, a[j]);
		mag += fabs(a[j]);
	}
	mean = ssc_ksum_value(&sa) / (double)m;
	if (!(fabs(mean) * (double)m <= 1e-9 * mag))
		return -EDOM;
	/* white: sum a^2 N^2 / T exactly (rounding of the weights' sum
	 * removed with their mean) */
	for (size_t j = 0; j < m; j++)
		s2 += (a[j] - mean) * (a[j] - mean);
	ssc_ksum_add(&v, n * n / block_s * s2);
	/* flicker and random walk: -sum_d D(d) sum_j a_j a_(j+d) */
	for (size_t d = 1; d < m && (b > 0 || k > 0); d++) {
		double dd = (double)d, c = 0;
		double D = 2 * b * b / M_PI * flicker_g(dd) +
			   k * k * block_s * (dd - 1.0 / 3);

		for (size_t j = 0; j + d < m; j++)
			c += (a[j] - mean) * (a[j + d] - mean);
		ssc_ksum_add(&v, -D * c);
	}
	*var = fmax(0, ssc_ksum_value(&v));
	return 0;
}

/* the weights of the least-squares coefficients of y on the p centred
 * and scaled columns of X (m x p, the first all ones) by its SVD: w
 * (p x m) with coefficient i = sum_j w[i m + j] y_j; false when the SVD
 * fails or a singular value is 0 */
static bool fit_weights(gsl_matrix *X, double *w)
{
	size_t m = X->size1, p = X->size2;
	gsl_matrix *V = gsl_matrix_alloc(p, p);
	gsl_vector *S = gsl_vector_alloc(p), *wk = gsl_vector_alloc(p);
	bool ok = false;

	if (!V || !S || !wk || gsl_linalg_SV_decomp(X, V, S, wk))
		goto out;
	if (!(gsl_vector_get(S, p - 1) > 64 * DBL_EPSILON * gsl_vector_get(S, 0)))
		goto out;
	for (size_t i = 0; i < p; i++)
		for (size_t j = 0; j < m; j++) {
			double c = 0;

			for (size_t l = 0; l < p; l++)
				c += gsl_matrix_get(V, i, l) / gsl_vector_get(S, l) *
				     gsl_matrix_get(X, j, l);
			w[i * m + j] = c;
		}
	ok = true;
out:
	gsl_matrix_free(V);
	gsl_vector_free(S);
	gsl_vector_free(wk);
	return ok;
}

/* the se of the drift (and of the sensitivity, w not NULL) under the
 * noise model n, b, k of blocks block_s long: the weights of the fit on
 * the centred and scaled block times x (and temperatures w) */
static void model_se(const double *x, const double *w, size_t m, double block_s,
		     double n, double b, double k, double se[2])
{
	size_t p = w ? 3 : 2;
	gsl_matrix *X = gsl_matrix_alloc(m, p);
	double *wt = malloc(p * m * sizeof(double)), xm = 0, wm = 0, sx = 0, sw = 0;
	double v;

	se[0] = se[1] = NAN;
	if (!X || !wt)
		goto out;
	for (size_t j = 0; j < m; j++) {
		xm += x[j];
		wm += w ? w[j] : 0;
	}
	xm /= (double)m;
	wm /= (double)m;
	for (size_t j = 0; j < m; j++) {
		sx += (x[j] - xm) * (x[j] - xm);
		sw += w ? (w[j] - wm) * (w[j] - wm) : 0;
	}
	sx = sqrt(sx / (double)m);
	sw = sqrt(sw / (double)m);
	for (size_t j = 0; j < m; j++) {
		gsl_matrix_set(X, j, 0, 1);
		gsl_matrix_set(X, j, 1, (x[j] - xm) / sx);
		if (w)
			gsl_matrix_set(X, j, 2, (w[j] - wm) / sw);
	}
	if (!fit_weights(X, wt))
		goto out;
	if (!sscope_lot_model_var(wt + m, m, block_s, n, b, k, &v))
		se[0] = sqrt(v) / sx;
	if (w && !sscope_lot_model_var(wt + 2 * m, m, block_s, n, b, k, &v))
		se[1] = sqrt(v) / sw;
out:
	gsl_matrix_free(X);
	free(wt);
}

/* the lag-1 autocorrelation of the residuals of y_j = a + d (x_j - xm)
 * [+ c (w_j - wm)] (the fits above, centred) and its one-sided 5 % test */
static void resid_test(const double *x, const double *w, const double *y,
		       size_t m, const double est[3], struct sscope_lot_bias *out)
{
	double xm = 0, wm = 0, r0 = 0, r1 = 0, prev = 0;

	for (size_t j = 0; j < m; j++) {
		xm += x[j];
		wm += w ? w[j] : 0;
	}
	xm /= (double)m;
	wm /= (double)m;
	for (size_t j = 0; j < m; j++) {
		double r = y[j] - est[0] - est[1] * (x[j] - xm) -
			   (w ? est[2] * (w[j] - wm) : 0);

		r0 += r * r;
		if (j)
			r1 += r * prev;
		prev = r;
	}
	out->resid_lag1 = r0 > 0 ? r1 / r0 : (double)NAN;
	out->resid_correlated = out->resid_lag1 > 1.6448536269514722 / sqrt((double)m);
}

int sscope_lot_bias(const double *x, size_t stride, size_t n, double fs,
		    const double *temp_degc, size_t temp_stride,
		    const struct sscope_lot_bias_opts *opts,
		    struct sscope_lot_bias *out)
{
	size_t m = opts && opts->blocks ? opts->blocks : 20, L, mt = 0;
	double level = opts && opts->level > 0 ? opts->level : 0.682689492137086;
	double nn = opts ? opts->n : 0, nb = opts ? opts->b : 0, nk = opts ? opts->k : 0;
	double bu = opts ? opts->b_upper : 0, ku = opts ? opts->k_upper : 0;
	double mse[2] = { NAN, NAN }, use[2] = { NAN, NAN }, zq;
	double *t, *b, *tb, tq, mean = 0, tmin = INFINITY, tmax = -INFINITY;
	double est[3] = { NAN, NAN, NAN }, se[3] = { NAN, NAN, NAN };
	struct ssc_ksum ks = { 0, 0 };

	if (!x || !out || !stride || !(fs > 0) || !isfinite(fs) || m < 5 ||
	    !(level < 1) || (temp_degc && !temp_stride) || !(nn >= 0) ||
	    !(nb >= 0) || !(nk >= 0) || !isfinite(nn) || !isfinite(nb) ||
	    !isfinite(nk) || !(bu >= 0) || !(ku >= 0))
		return -EINVAL;
	memset(out, 0, sizeof(*out));
	L = n / m;
	if (L < 2)
		return -EDOM;
	for (size_t i = 0; i < m * L; i++) {
		if (!isfinite(x[i * stride]))
			return -EDOM;
		ssc_ksum_add(&ks, x[i * stride]);
	}
	/* block means about the record mean: no digits lost to an offset */
	mean = ssc_ksum_value(&ks) / (double)(m * L);
	t = malloc(3 * m * sizeof(double));
	if (!t)
		return -ENOMEM;
	b = t + m;
	tb = b + m;
	for (size_t j = 0; j < m; j++) {
		struct ssc_ksum s = { 0, 0 }, st = { 0, 0 };
		bool tok = temp_degc != NULL;

		for (size_t i = j * L; i < (j + 1) * L; i++) {
			ssc_ksum_add(&s, x[i * stride] - mean);
			if (tok) {
				double T = temp_degc[i * temp_stride];

				if (isfinite(T))
					ssc_ksum_add(&st, T);
				else
					tok = false;
			}
		}
		t[j] = ((double)j + 0.5) * (double)L / fs;
		b[j] = ssc_ksum_value(&s) / (double)L;
		tb[j] = tok ? ssc_ksum_value(&st) / (double)L : (double)NAN;
		if (tok) {
			mt++;
			tmin = fmin(tmin, tb[j]);
			tmax = fmax(tmax, tb[j]);
		}
	}
	out->blocks = m;
	out->block_n = L;
	out->level = level;
	out->tempco_u_degc = out->tempco_se = out->tempco_lo = out->tempco_hi = NAN;
	out->temp_mean_degc = out->temp_span_degc = out->temp_time_corr = NAN;
	out->have_temp = mt == m && plane_fit(t, tb, b, m, est, se);
	if (out->have_temp) {
		double tm = 0, sxx = 0, syy = 0, sxy = 0, tt = (double)m * 0.5 * (double)L / fs;

		tq = gsl_cdf_tdist_Pinv(0.5 + level / 2, (double)(m - 3));
		out->tempco_u_degc = est[2];
		out->tempco_se = se[2];
		out->tempco_lo = est[2] - tq * se[2];
		out->tempco_hi = est[2] + tq * se[2];
		for (size_t j = 0; j < m; j++)
			tm += tb[j];
		tm /= (double)m;
		for (size_t j = 0; j < m; j++) {
			sxx += (t[j] - tt) * (t[j] - tt);
			syy += (tb[j] - tm) * (tb[j] - tm);
			sxy += (t[j] - tt) * (tb[j] - tm);
		}
		out->temp_mean_degc = tm;
		out->temp_span_degc = tmax - tmin;
		out->temp_time_corr = sxy / sqrt(sxx * syy);
	} else {
		line_fit(t, b, m, &est[0], &se[0], &est[1], &se[1]);
		tq = gsl_cdf_tdist_Pinv(0.5 + level / 2, (double)(m - 2));
	}
	out->drift_u_s = est[1];
	out->drift_se = se[1];
	out->drift_lo = est[1] - tq * se[1];
	out->drift_hi = est[1] + tq * se[1];
	/* under the unit's noise model when it shows flicker or a random
	 * walk: the larger se, the normal quantile when the model's */
	if (nb > 0 || nk > 0)
		model_se(t, out->have_temp ? tb : NULL, m, (double)L / fs, nn, nb, nk, mse);
	zq = gsl_cdf_ugaussian_Pinv(0.5 + level / 2);
	out->drift_se_resid = se[1];
	out->drift_se_model = mse[0];
	out->tempco_se_resid = out->have_temp ? se[2] : (double)NAN;
	out->tempco_se_model = out->have_temp ? mse[1] : (double)NAN;
	out->drift_se_from_model = mse[0] > se[1];
	if (out->drift_se_from_model) {
		out->drift_se = mse[0];
		out->drift_lo = est[1] - zq * mse[0];
		out->drift_hi = est[1] + zq * mse[0];
	}
	out->tempco_se_from_model = out->have_temp && mse[1] > se[2];
	if (out->tempco_se_from_model) {
		out->tempco_se = mse[1];
		out->tempco_lo = est[2] - zq * mse[1];
		out->tempco_hi = est[2] + zq * mse[1];
	}
	/* conservative: B at its bound, then K at its bound, the other as
	 * the model has it (each bound holds with the other term free; both
	 * at once the record would mostly reject); the larger (an infinite
	 * bound: no finite se) */
	use[0] = use[1] = -1; /* no bound above the model: as reported */
	for (int e = 0; e < 2; e++) {
		double eb = e ? nb : fmax(nb, bu), ek = e ? fmax(nk, ku) : nk, v[2];

		if (eb == nb && ek == nk)
			continue;
		if (isinf(eb) || isinf(ek)) {
			use[0] = use[1] = INFINITY;
			break;
		}
		model_se(t, out->have_temp ? tb : NULL, m, (double)L / fs, nn, eb, ek, v);
		use[0] = isnan(v[0]) ? (double)NAN : fmax(use[0], v[0]);
		use[1] = isnan(v[1]) ? (double)NAN : fmax(use[1], v[1]);
	}
	out->drift_se_upper = out->drift_se;
	out->drift_upper_lo = out->drift_lo;
	out->drift_upper_hi = out->drift_hi;
	if (use[0] > out->drift_se || isnan(use[0])) {
		/* NaN: the model's variance failed; no finite bound */
		out->drift_se_upper = isnan(use[0]) ? (double)INFINITY : use[0];
		out->drift_upper_lo = est[1] - zq * out->drift_se_upper;
		out->drift_upper_hi = est[1] + zq * out->drift_se_upper;
	}
	out->tempco_se_upper = out->tempco_se;
	out->tempco_upper_lo = out->tempco_lo;
	out->tempco_upper_hi = out->tempco_hi;
	if (out->have_temp && (use[1] > out->tempco_se || isnan(use[1]))) {
		out->tempco_se_upper = isnan(use[1]) ? (double)INFINITY : use[1];
		out->tempco_upper_lo = est[2] - zq * out->tempco_se_upper;
		out->tempco_upper_hi = est[2] + zq * out->tempco_se_upper;
	}
	out->bias = mean + est[0];
	out->bias_se = se[0];
	out->bias_lo = out->bias - tq * se[0];
	out->bias_hi = out->bias + tq * se[0];
	resid_test(t, out->have_temp ? tb : NULL, b, m, est, out);
	free(t);
	return 0;
}

int sscope_lot_temp_removed(const double *x, size_t stride, size_t n,
			    const double *temp_degc, size_t temp_stride,
			    const struct sscope_lot_bias *b, double *r)
{
	if (!x || !temp_degc || !b || !r || !stride || !temp_stride || !b->have_temp)
		return -EINVAL;
	for (size_t i = 0; i < n; i++)
		r[i] = x[i * stride] -
		       b->tempco_u_degc * (temp_degc[i * temp_stride] - b->temp_mean_degc);
	return 0;
}
