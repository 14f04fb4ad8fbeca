/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The random-walk fan of a stationary gyro (see sscope-walk.h): runs of a
 * record integrated after bias removal against the envelope of IEEE Std
 * 952 noise terms (angle random walk N sqrt(t) and the bias-instability
 * and rate-random-walk parts, sscope_heading_drift_var()).  The implied N
 * uses the chi-squared distribution of the mean square of M independent
 * Gaussian runs (GSL quantiles).
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>

#include "sscope-calib.h"
#include "sscope-heading.h"
#include "sscope-walk.h"

/* 90th over 10th percentile of the sliding variance (calib's detector) */
static int still_contrast(const double *x, size_t stride, size_t n, double fs,
			  double *ratio)
{
	size_t w = (size_t)fmax(11, round(fs));
	double *v = ssc_alloc_array(n, sizeof(double)), lo, hi;
	double *work = ssc_alloc_array(n, sizeof(double));
	int rc = v && work ? 0 : -ENOMEM;

	if (!rc)
		rc = sscope_calib_variance_magnitude(x, x, x, stride, n, w, v);
	if (!rc)
		rc = ssc_calib_vs_deciles(v, n, work, 10, &lo, &hi);
	if (!rc)
		*ratio = lo > 0 ? hi / lo : hi > 0 ? (double)INFINITY : 1;
	free(v);
	free(work);
	return rc;
}

void sscope_walk_result_free(struct sscope_walk_result *r)
{
	if (!r)
		return;
	free(r->paths);
	free(r->sigma);
	free(r->spread);
	free(r->inside);
	free(r->var_n1);
	free(r->var_other);
	free(r);
}

int sscope_walk_compute(const double *x, size_t stride, size_t n,
			const struct sscope_walk_opts *o,
			struct sscope_walk_result **resp,
			struct sscope_diag *diag)
{
	struct sscope_walk_result *r;
	size_t L, Lb, block, M, np;
	double dt, gmean = 0;
	bool any = false;

	if (!resp)
		return -EINVAL;
	*resp = NULL;
	if (!x || !o || stride == 0 || !(o->rate_hz > 0) || !isfinite(o->rate_hz) ||
	    !(o->run_s > 0) || !isfinite(o->run_s) || !(o->bias_s >= 0) ||
	    !isfinite(o->bias_s) || o->k_sigma < 0 || !isfinite(o->k_sigma))
		return ssc_diag(diag, -EINVAL, "bad parameter");
	for (int i = 0; i < 5; i++) {
		if (!(o->coef[i] >= 0) || !isfinite(o->coef[i]))
			return ssc_diag(diag, -EINVAL,
					"noise terms must be finite and non-negative");
		any |= o->coef[i] > 0;
	}
	if (!any)
		return ssc_diag(diag, -EINVAL, "no noise term for the envelope");
	dt = 1 / o->rate_hz;
	L = (size_t)lround(o->run_s * o->rate_hz);
	Lb = (size_t)lround(o->bias_s * o->rate_hz);
	if (L < 2)
		return ssc_diag(diag, -EDOM, "a run of %g s is shorter than 2 samples",
				o->run_s);
	if (o->bias_s > 0 && Lb < 2)
		return ssc_diag(diag, -EDOM,
				"a bias window of %g s is shorter than 2 samples",
				o->bias_s);
	block = L + Lb;
	M = n / block;
	if (M < 2)
		return ssc_diag(diag, -EDOM,
				"%zu samples hold %zu run%s of %g s%s: need at least 2",
				n, M, M == 1 ? "" : "s", o->run_s,
				o->bias_s > 0 ? " plus the bias window" : "");
	for (size_t i = 0; i < n; i++)
		if (!isfinite(x[i * stride]))
			return ssc_diag(diag, -EINVAL, "sample %zu is not finite",
					i + 1);
	if (o->max_contrast >= 0) {
		double c = o->max_contrast > 0 ? o->max_contrast : 9, ratio;
		int rc = still_contrast(x, stride, n, o->rate_hz, &ratio);

		if (rc)
			return ssc_diag(diag, rc, "%s", rc == -ENOMEM ?
					"out of memory" : "record too short to check that it is still");
		if (!(ratio <= c))
			return ssc_diag(diag, -EDOM,
					"the record moves (its variance over 1 s windows spans %.3g times, a still record at most %g): the fan needs a stationary record",
					ratio, c);
	}
	if (Lb == 0) {
		struct sscope_stats st;

		sscope_stats_compute(x, stride, n, &st);
		gmean = st.mean;
	}
	np = L + 1;
	r = calloc(1, sizeof(*r));
	if (!r)
		return -ENOMEM;
	r->paths = ssc_alloc_array(M, np * sizeof(double));
	r->sigma = ssc_alloc_array(np, sizeof(double));
	r->spread = ssc_alloc_array(np, sizeof(double));
	r->inside = ssc_alloc_array(np, sizeof(double));
	r->var_n1 = ssc_alloc_array(np, sizeof(double));
	r->var_other = ssc_alloc_array(np, sizeof(double));
	if (!r->paths || !r->sigma || !r->spread || !r->inside || !r->var_n1 ||
	    !r->var_other) {
		sscope_walk_result_free(r);
		return -ENOMEM;
	}
	r->n_runs = M;
	r->n_points = np;
	r->dt_s = dt;
	r->global = Lb == 0;
	r->est_s = Lb ? (double)Lb * dt : (double)n * dt;
	r->k_sigma = o->k_sigma > 0 ? o->k_sigma : 2;
	for (size_t j = 0; j < M; j++) {
		const double *p = x + j * block * stride;
		double b = gmean, *path = r->paths + j * np;
		struct ssc_ksum s = { 0, 0 };

		if (Lb) {
			struct sscope_stats st;

			sscope_stats_compute(p, stride, Lb, &st);
			b = st.mean;
		}
		path[0] = 0;
		for (size_t i = 0; i < L; i++) {
			ssc_ksum_add(&s, (p[(Lb + i) * stride] - b) * dt);
			path[i + 1] = ssc_ksum_value(&s);
		}
	}
	{
		struct ssc_ksum in_sum = { 0, 0 };
		double cN[5] = { 0, 1, 0, 0, 0 }, co[5];
		double T = (double)n * dt;

		memcpy(co, o->coef, sizeof(co));
		co[SSCOPE_TERM_N] = 0;
		for (size_t k = 0; k < np; k++) {
			double t = (double)k * dt, s2 = 0, v1 = 0, vo = 0, vall = 0;
			double vw = 0;
			size_t in = 0;

			if (Lb) {
				/* a window before each run: the same for all */
				v1 = sscope_heading_drift_var(cN, t, r->est_s);
				vo = sscope_heading_drift_var(co, t, r->est_s);
				vw = sscope_heading_drift_var(o->coef, t, r->est_s);
			}
			for (size_t j = 0; j < M; j++) {
				double v = r->paths[j * np + k], var = vw;

				if (!Lb && k) {
					/* X(a + t) - X(a) - (t / T)(X(T) - X(0)):
					 * depends on where the run lies */
					double a = (double)(j * block) * dt;
					double tt[4] = { a + t, a, T, 0 };
					double cc[4] = { 1, -1, -t / T, t / T };

					var = sscope_heading_drift_var_points(o->coef, tt, cc, 4);
					v1 += sscope_heading_drift_var_points(cN, tt, cc, 4) / (double)M;
					vo += sscope_heading_drift_var_points(co, tt, cc, 4) / (double)M;
				}
				s2 += v * v;
				vall += var;
				in += fabs(v) <= r->k_sigma * sqrt(var);
			}
			r->sigma[k] = sqrt(vall / (double)M);
			r->var_n1[k] = v1;
			r->var_other[k] = vo;
			r->spread[k] = sqrt(s2 / (double)M);
			r->inside[k] = k ? (double)in / (double)M : (double)NAN;
			if (k)
				ssc_ksum_add(&in_sum, r->inside[k]);
		}
		r->inside_mean = ssc_ksum_value(&in_sum) / (double)L;
	}
	r->inside_expected = erf(r->k_sigma / sqrt(2.0));
	r->inside_sd = sqrt(r->inside_expected * (1 - r->inside_expected) /
			    (double)r->n_runs);
	*resp = r;
	return 0;
}

int sscope_walk_implied_n(const struct sscope_walk_result *r, size_t k,
			  double level, struct sscope_walk_implied *out)
{
	double g, other, s2, M, a;

	if (!r || !out || k == 0 || k >= r->n_points || level < 0 || level >= 1)
		return -EINVAL;
	if (level == 0)
		level = 0.6827;
	other = r->var_other[k];
	g = r->var_n1[k];
	M = (double)r->n_runs;
	s2 = r->spread[k] * r->spread[k];
	a = (1 - level) / 2;
	out->t_s = (double)k * r->dt_s;
	out->n = s2 > other ? sqrt((s2 - other) / g) : (double)NAN;
	{
		double lo2 = M * s2 / gsl_cdf_chisq_Qinv(a, M) - other;
		double hi2 = M * s2 / gsl_cdf_chisq_Pinv(a, M) - other;

		out->lo = lo2 > 0 ? sqrt(lo2 / g) : 0;
		out->hi = hi2 > 0 ? sqrt(hi2 / g) : 0;
	}
	return 0;
}
