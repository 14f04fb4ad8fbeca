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
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_statistics_double.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "sscope-calib.h"
#include "sscope-heading.h"
#include "sscope-walk.h"
#include "sscope-stats.h"
#include "sscope-term.h"

#define NT_W 5 /* the IEEE 952 terms Q N B K R */

/*
 * The record's moving variance as sscope_calib_variance_magnitude() gives
 * it for one channel given three times (the same sliding sums, re-anchored
 * every w steps, the same operations in the same order), streamed one
 * sample at a time, never stored.  What is streamed is u = s2 - s1^2 / w
 * (0 for u <= 0): the detector's value, sqrt(3 v^2) with v = u / (w - 1),
 * is a non-decreasing function of u in floating point too (each step is a
 * correctly rounded monotone operation), so the order statistics of the
 * values are that function of the order statistics of u.
 */
struct slide {
	const double *x;
	size_t stride, n, h, w, i, anchor;
	double s1, s2, shift;
};

/* positions whose window starts in [lo0, lo1), lo0 a multiple of w (an
 * anchor: the sums there are what the whole run has there) */
static void slide_init(struct slide *s, const double *x, size_t stride,
		       size_t n, size_t window, size_t lo0, size_t lo1)
{
	*s = (struct slide){ .x = x, .stride = stride };
	s->h = window / 2;
	s->w = 2 * s->h + 1;
	s->i = lo0 + s->h;
	s->anchor = lo0;
	/* i + h < n and i - h < lo1 */
	s->n = lo1 + 2 * s->h < n ? lo1 + 2 * s->h : n;
}

/* u at the next position; false past the last */
static inline bool slide_next(struct slide *s, double *out)
{
	const double *x = s->x;
	size_t st = s->stride, i = s->i, h = s->h, w = s->w, lo;
	double u;

	if (i + h >= s->n)
		return false;
	lo = i - h;
	if (lo == s->anchor) {
		s->anchor += w;
		s->shift = x[lo * st];
		s->s1 = s->s2 = 0;
		for (size_t j = lo; j < lo + w; j++) {
			double d = x[j * st] - s->shift;

			s->s1 += d;
			s->s2 += d * d;
		}
	} else {
		double dout = x[(lo - 1) * st] - s->shift;
		double din = x[(i + h) * st] - s->shift;

		s->s1 += din - dout;
		s->s2 += din * din - dout * dout;
	}
	u = s->s2 - s->s1 * s->s1 / (double)w;
	*out = u <= 0 ? 0 : u; /* also -0: a zero variance */
	s->i++;
	return true;
}

/* the detector's value of u: sqrt(v^2 + v^2 + v^2), v = u / (w - 1) */
static double slide_value(const struct slide *s, double u)
{
	double v = u / (double)(s->w - 1), v2 = 0;

	if (v < 0)
		v = 0;
	for (int c = 0; c < 3; c++)
		v2 += v * v;
	return sqrt(v2);
}

/* the detector counts only finite values: those of large u are checked */
static inline bool slide_finite(const struct slide *s, double u)
{
	return u < 1e150 || isfinite(slide_value(s, u));
}

/* histogram bin of a non-negative double: its top bits, which order such
 * doubles as their values (sign clear, exponent, 8 bits of mantissa) */
enum { BIN_SHIFT = 44, N_BINS = 1 << (63 - BIN_SHIFT) };

static inline size_t bin_of(double v)
{
	uint64_t b;

	memcpy(&b, &v, sizeof(b));
	return (size_t)(b >> BIN_SHIFT);
}

/*
 * The 10th and 90th percentiles (order statistics (nf - 1) / 10 and
 * (nf - 1) * 9 / 10 of the nf finite values, as ssc_calib_vs_deciles()
 * takes them) of the streamed moving variance, by a radix selection: one
 * pass counts the values per bin, a second keeps the values of the two
 * bins that hold the wanted ranks, GSL's selection finishes.  Both passes
 * run on the threads in pieces that start at anchors (the same values);
 * each piece writes its values at its own offset.  Returns 1 when those
 * bins hold too many values to be worth it (a record of a few distinct
 * values): the caller stores the whole series instead.
 */
enum { MAX_PIECES = 16 };

static int deciles_streamed(const double *x, size_t stride, size_t n,
			    size_t window, double *lo, double *hi)
{
	size_t w = 2 * (window / 2) + 1, npos = n - w + 1, np = 1;
	size_t *count[MAX_PIECES] = { NULL }, cut[MAX_PIECES + 1], nfp[MAX_PIECES];
	size_t nf = 0, k[2], bin[2] = { 0, 0 }, below[2] = { 0, 0 }, tot[2];
	size_t off[2][MAX_PIECES];
	double *buf[2] = { NULL, NULL };
	struct slide s;
	int rc = 0;

#ifdef _OPENMP
	if (npos >= ((size_t)1 << 20)) {
		int t = omp_get_max_threads();

		np = t < 1 ? 1 : (size_t)t;
		if (np > MAX_PIECES)
			np = MAX_PIECES;
	}
#endif
	/* piece p: window starts [cut[p], cut[p + 1]), cuts at anchors */
	for (size_t p = 0; p <= np; p++)
		cut[p] = p == np ? npos : npos / np * p / w * w;
	for (size_t p = 0; p < np && !rc; p++) {
		count[p] = calloc(N_BINS, sizeof(size_t));
		if (!count[p])
			rc = -ENOMEM;
	}
	if (rc)
		goto out;
	SSC_OMP(omp parallel for num_threads((int)np) schedule(static, 1) private(s))
	for (size_t p = 0; p < np; p++) {
		size_t *c = count[p], f = 0;
		double u;

		slide_init(&s, x, stride, n, window, cut[p], cut[p + 1]);
		while (slide_next(&s, &u))
			if (slide_finite(&s, u)) {
				c[bin_of(u)]++;
				f++;
			}
		nfp[p] = f;
	}
	for (size_t p = 0; p < np; p++)
		nf += nfp[p];
	for (size_t p = 1; p < np; p++)
		for (size_t b = 0; b < N_BINS; b++)
			count[0][b] += count[p][b];
	if (nf < 10) {
		rc = -EDOM;
		goto out;
	}
	k[0] = (nf - 1) / 10;
	k[1] = (nf - 1) * 9 / 10;
	for (int j = 0; j < 2; j++) {
		size_t cum = 0, b = 0;

		while (cum + count[0][b] <= k[j])
			cum += count[0][b++];
		bin[j] = b;
		below[j] = cum;
	}
	tot[0] = count[0][bin[0]];
	tot[1] = bin[1] != bin[0] ? count[0][bin[1]] : 0;
	if (tot[0] + tot[1] > nf / 8 + 1024) {
		rc = 1;
		goto out;
	}
	/* each piece's share of the two bins (count[0] now holds the sums:
	 * a piece's own counts are the sums less the other pieces') */
	memset(off, 0, sizeof(off));
	for (int j = 0; j < (bin[1] != bin[0] ? 2 : 1); j++) {
		size_t o = 0;

		for (size_t p = np; p-- > 1;) {
			size_t cp = count[p][bin[j]];

			off[j][p] = tot[j] - o - cp;
			o += cp;
		}
		off[j][0] = 0;
	}
	buf[0] = ssc_alloc_array(tot[0], sizeof(double));
	buf[1] = bin[1] == bin[0] ? buf[0] : ssc_alloc_array(tot[1], sizeof(double));
	if (!buf[0] || !buf[1]) {
		rc = -ENOMEM;
		goto out;
	}
	SSC_OMP(omp parallel for num_threads((int)np) schedule(static, 1) private(s))
	for (size_t p = 0; p < np; p++) {
		double *b0 = buf[0] + off[0][p], *b1 = buf[1] + off[1][p], u;

		slide_init(&s, x, stride, n, window, cut[p], cut[p + 1]);
		while (slide_next(&s, &u)) {
			size_t b;

			if (!slide_finite(&s, u))
				continue;
			b = bin_of(u);
			if (b == bin[0])
				*b0++ = u;
			else if (b == bin[1])
				*b1++ = u;
		}
	}
	if (bin[1] == bin[0])
		tot[1] = tot[0];
	slide_init(&s, x, stride, n, window, 0, npos);
	*lo = slide_value(&s, gsl_stats_select(buf[0], 1, tot[0], k[0] - below[0]));
	*hi = slide_value(&s, gsl_stats_select(buf[1], 1, tot[1], k[1] - below[1]));
out:
	if (buf[1] != buf[0])
		free(buf[1]);
	free(buf[0]);
	for (size_t p = 0; p < np; p++)
		free(count[p]);
	return rc;
}

/* 90th over 10th percentile of the sliding variance (calib's detector);
 * the stillness test of walk and of the adequacy check (internal.h) */
int ssc_still_contrast(const double *x, size_t stride, size_t n, double fs,
			  double *ratio)
{
	size_t w = ssc_count(fmax(11, round(fs)));
	double *v, *work, lo, hi;
	int rc;

	if (2 * (w / 2) + 1 > n)
		return -EDOM;
	rc = deciles_streamed(x, stride, n, w, &lo, &hi);
	if (rc == 1) {
		v = ssc_alloc_array(n, sizeof(double));
		work = ssc_alloc_array(n, sizeof(double));
		rc = v && work ? 0 : -ENOMEM;
		if (!rc)
			rc = sscope_calib_variance_magnitude(x, x, x, stride, n, w, v);
		if (!rc)
			rc = ssc_calib_vs_deciles(v, n, work, 10, &lo, &hi);
		free(v);
		free(work);
	}
	if (!rc)
		*ratio = lo > 0 ? hi / lo : hi > 0 ? (double)INFINITY : 1;
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
	free(r->var_other_sd);
	free(r);
}

int sscope_walk_compute(const double *x, size_t stride, size_t n,
			const struct sscope_walk_opts *o,
			struct sscope_walk_result **resp,
			struct sscope_diag *diag)
{
	struct sscope_walk_result *r;
	size_t L, Lb, block, M, np;
	double dt, gmean = 0, *thr = NULL, *unit = NULL, s2[NT_W];
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
	for (int i = 0; i < NT_W; i++)
		s2[i] = o->coef[i] * o->coef[i];
	if (o->have_sq) {
		for (int i = 0; i < NT_W; i++) {
			if (!isfinite(o->sq[i]))
				return ssc_diag(diag, -EINVAL,
						"the squared noise terms must be finite");
			s2[i] = o->sq[i];
		}
		for (int i = 0; i < NT_W * NT_W; i++)
			if (!isfinite(o->sq_cov[i]))
				return ssc_diag(diag, -EINVAL,
						"the covariance of the noise terms must be finite");
	}
	dt = 1 / o->rate_hz;
	L = ssc_count(round(o->run_s * o->rate_hz));
	Lb = ssc_count(round(o->bias_s * o->rate_hz));
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
		int rc = ssc_still_contrast(x, stride, n, o->rate_hz, &ratio);

		if (rc)
			return ssc_diag(diag, rc, "%s", rc == -ENOMEM ?
					"out of memory" : "record too short to check that it is still");
		if (!(ratio <= c) && !isfinite(ratio))
			return ssc_diag(diag, -EDOM,
					"the record may move (its variance over 1 s windows is zero in some windows and not in others: a held value then motion, or a quantisation coarse beside the noise): the fan needs a stationary record");
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
	r->n_paths = o->keep_paths && o->keep_paths < M ? o->keep_paths : M;
	/* the runs not kept are integrated into one buffer after the kept */
	r->paths = ssc_alloc_array(r->n_paths + (r->n_paths < M), np * sizeof(double));
	r->sigma = ssc_alloc_array(np, sizeof(double));
	r->spread = ssc_alloc_array(np, sizeof(double));
	r->inside = ssc_alloc_array(np, sizeof(double));
	r->var_n1 = ssc_alloc_array(np, sizeof(double));
	r->var_other = ssc_alloc_array(np, sizeof(double));
	r->var_other_sd = ssc_alloc_array(np, sizeof(double));
	unit = ssc_alloc_array(np, NT_W * sizeof(double));
	if (!r->paths || !r->sigma || !r->spread || !r->inside || !r->var_n1 ||
	    !r->var_other || !r->var_other_sd || !unit) {
		free(unit);
		sscope_walk_result_free(r);
		return -ENOMEM;
	}
	r->n_runs = M;
	r->n_points = np;
	r->dt_s = dt;
	r->global = Lb == 0;
	r->est_s = Lb ? (double)Lb * dt : (double)n * dt;
	r->k_sigma = o->k_sigma > 0 ? o->k_sigma : 2;
	/*
	 * Run by run (each path is summed into the per-point sums while it is
	 * in cache), the sums of each point taken over the runs in the same
	 * order as point by point.  sigma, spread and inside hold the sums of
	 * the predicted variances, of the squares and the counts inside until
	 * the end.
	 */
	for (size_t k = 0; k < np; k++) {
		r->sigma[k] = r->spread[k] = r->inside[k] = 0;
		r->var_n1[k] = r->var_other[k] = r->var_other_sd[k] = 0;
		for (int j = 0; j < NT_W; j++)
			unit[k * NT_W + j] = 0;
	}
	/*
	 * The predicted variance is linear in the squares of the terms:
	 * unit[k][j] holds term j's variance per unit square at point k (the
	 * mean over the runs for the record's mean), so that the squares
	 * may be the fit's signed estimates and var_other's uncertainty
	 * follows from their covariance.
	 */
	if (Lb) {
		/* a window before each run: the same for all */
		thr = ssc_alloc_array(np, 2 * sizeof(double));
		if (!thr) {
			free(unit);
			sscope_walk_result_free(r);
			return -ENOMEM;
		}
		for (size_t k = 0; k < np; k++) {
			double t = (double)k * dt, vw = 0;

			for (int j = 0; j < NT_W; j++) {
				double e[NT_W] = { 0 };

				e[j] = 1;
				unit[k * NT_W + j] = sscope_heading_drift_var(e, t, r->est_s);
				vw += s2[j] * unit[k * NT_W + j];
			}
			vw = fmax(vw, 0);
			thr[2 * k] = vw;
			thr[2 * k + 1] = r->k_sigma * sqrt(vw);
		}
	}
	for (size_t j = 0; j < M; j++) {
		const double *p = x + j * block * stride;
		double b = gmean;
		double *path = r->paths + (j < r->n_paths ? j : r->n_paths) * np;
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
		if (Lb) {
			for (size_t k = 0; k < np; k++) {
				double v = path[k];

				r->spread[k] += v * v;
				r->sigma[k] += thr[2 * k];
				r->inside[k] += fabs(v) <= thr[2 * k + 1];
			}
			continue;
		}
		for (size_t k = 0; k < np; k++) {
			double v = path[k], var = 0;

			if (k) {
				/* X(a + t) - X(a) - (t / T)(X(T) - X(0)):
				 * depends on where the run lies */
				double t = (double)k * dt, T = (double)n * dt;
				double a = (double)(j * block) * dt;
				double tt[4] = { a + t, a, T, 0 };
				double cc[4] = { 1, -1, -t / T, t / T };

				for (int q = 0; q < NT_W; q++) {
					double e[NT_W] = { 0 }, u;

					e[q] = 1;
					u = sscope_heading_drift_var_points(e, tt, cc, 4);
					var += s2[q] * u;
					unit[k * NT_W + q] += u / (double)M;
				}
				var = fmax(var, 0);
			}
			r->spread[k] += v * v;
			r->sigma[k] += var;
			r->inside[k] += fabs(v) <= r->k_sigma * sqrt(var);
		}
	}
	free(thr);
	/* N's unit variance, the others' part and its uncertainty */
	for (size_t k = 0; k < np; k++) {
		const double *u = unit + k * NT_W;
		double vo = 0, vv = 0;

		r->var_n1[k] = u[SSCOPE_TERM_N];
		for (int a = 0; a < NT_W; a++) {
			if (a == SSCOPE_TERM_N)
				continue;
			vo += s2[a] * u[a];
			for (int b = 0; b < NT_W && o->have_sq; b++)
				if (b != SSCOPE_TERM_N)
					vv += u[a] * u[b] * o->sq_cov[a * NT_W + b];
		}
		r->var_other[k] = vo;
		r->var_other_sd[k] = vv > 0 ? sqrt(vv) : 0;
	}
	free(unit);
	{
		struct ssc_ksum in_sum = { 0, 0 };

		for (size_t k = 0; k < np; k++) {
			r->sigma[k] = sqrt(r->sigma[k] / (double)M);
			r->spread[k] = sqrt(r->spread[k] / (double)M);
			r->inside[k] = k ? r->inside[k] / (double)M : (double)NAN;
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
		/* the mean square's interval (chi-squared).  The others' part
		 * is estimated from the same record, its error correlated with
		 * the spread's: adding its sd (var_other_sd) in quadrature
		 * over-covers (76.8 % for 68.3 % over 400 simulated hours,
		 * tests/bench-walk.c), leaving it out covers 68-72 % */
		double lo2 = M * s2 / gsl_cdf_chisq_Qinv(a, M) - other;
		double hi2 = M * s2 / gsl_cdf_chisq_Pinv(a, M) - other;

		out->lo = lo2 > 0 ? sqrt(lo2 / g) : 0;
		out->hi = hi2 > 0 ? sqrt(hi2 / g) : 0;
	}
	return 0;
}
