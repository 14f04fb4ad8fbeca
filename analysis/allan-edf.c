/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Confidence intervals of Allan-family deviations.
 *
 * Equivalent degrees of freedom: C. A. Greenhall and W. J. Riley,
 * "Uncertainty of stability variances based on finite differences",
 * 35th PTTI Meeting, 2003, eqs (7)-(13) and tables 1-3 -- the algorithm of
 * Stable32 -- with its "basic sum" over the generalised autocovariance of
 * the d-th phase difference; the stride factor S = m / stride covers
 * overlapping (S = m), non-overlapping (S = 1) and strided estimators.
 * For white phase noise with unmodified variances the EDF is computed
 * exactly (the terms are finite combinations of independent phase values),
 * which agrees with the paper's case 4 where that applies and also covers
 * its K <= d branch.  TOTDEV: NIST SP 1065 (Riley 2008) table 7 for the
 * frequency noises and table 5's simple estimates for the phase noises,
 * as Stable32 (checked against its published bounds).
 *
 * Noise identification (NIST SP 1065 section 5.6, as Stable32): with at
 * least 30 analysis points, W. J. Riley and C. A. Greenhall, "Power law
 * noise identification using the lag 1 autocorrelation", 18th EFTF, 2004:
 * the lag-1 autocorrelation r1 of the averaged data (no detrending),
 * differenced until rho = r1 / (1 + r1) < 0.25, gives alpha = -2 (rho + d)
 * (+2 for phase); with fewer, Barnes' B1 ratio (standard over two-sample
 * variance of the averages) against its theoretical values, and R(n) =
 * MVAR / AVAR between white and flicker phase (Howe, Beard, Greenhall,
 * Riley, 32nd PTTI 2000, tables 3-4; NIST TN 1337); with too few averages
 * for B1 the caller carries the last identification.
 *
 * Bounds: sigma^2 edf / chi^2_{(1 +- p)/2}(edf) (NIST SP 1065 eq 45), GSL
 * chi-squared tails; a grid of many taus takes the quantiles from a table
 * of Chebyshev series against edf.
 */
#include "allan-internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_chebyshev.h>

#include "sscope-allan.h"

#define PI_ 3.14159265358979323846

/* ------------------------------------------------------------------ */
/* Greenhall & Riley EDF                                               */
/* ------------------------------------------------------------------ */

/* eq (7): generalised autocovariance of power-law noise */
static inline __attribute__((always_inline)) double sw(double t, int alpha)
{
	double a = fabs(t);

	switch (alpha) {
	case 2:
		return -a;
	case 1:
		return a == 0 ? 0 : t * t * log(a);
	case 0:
		return a * a * a;
	case -1:
		return a == 0 ? 0 : t * t * t * t * log(a);
	case -2:
		return a * a * a * a * a;
	case -3:
		return a == 0 ? 0 : t * t * t * t * t * t * log(a);
	case -4:
		return a * a * a * a * a * a * a;
	default:
		return NAN;
	}
}

/* eq (8): after the pre-filter of factor F (F infinite: the limit) */
static inline __attribute__((always_inline)) double sx(double t, double F, int alpha)
{
	if (isinf(F))
		return sw(t, alpha + 2);
	/* flicker phase with a large F: the second difference of t^2 ln|t|
	 * at step 1/F cancels catastrophically; use its Taylor series */
	if (alpha == 1 && fabs(t) * F >= 64) {
		double t2 = t * t, h2 = 1 / (F * F);

		return -((2 * log(fabs(t)) + 3) - h2 / (6 * t2) -
			 h2 * h2 / (30 * t2 * t2));
	}
	return F * F * (2 * sw(t, alpha) - sw(t - 1 / F, alpha) -
			sw(t + 1 / F, alpha));
}

/* eq (9): the d-th difference */
static inline __attribute__((always_inline)) double sz(double t, double F, int alpha,
						     int d)
{
	switch (d) {
	case 1:
		return 2 * sx(t, F, alpha) - sx(t - 1, F, alpha) -
		       sx(t + 1, F, alpha);
	case 2:
		return 6 * sx(t, F, alpha) -
		       4 * (sx(t - 1, F, alpha) + sx(t + 1, F, alpha)) +
		       sx(t - 2, F, alpha) + sx(t + 2, F, alpha);
	default:
		return 20 * sx(t, F, alpha) -
		       15 * (sx(t - 1, F, alpha) + sx(t + 1, F, alpha)) +
		       6 * (sx(t - 2, F, alpha) + sx(t + 2, F, alpha)) -
		       (sx(t - 3, F, alpha) + sx(t + 3, F, alpha));
	}
}

/* eq (10) */
static double basic_sum(double J, double M, double S, double F, int alpha,
			int d)
{
	double s0 = sz(0, F, alpha, d), sum = s0 * s0, v;
	long jn = (long)J;

	for (long j = 1; j < jn; j++) {
		v = sz((double)j / S, F, alpha, d);
		sum += 2 * (1 - (double)j / M) * v * v;
	}
	v = sz(J / S, F, alpha, d);
	sum += (1 - J / M) * v * v;
	return sum;
}

/* tables 1 and 2: (a0, a1) for alpha = 2..-4 (rows) and d = 1..3 */
static const double table1[7][3][2] = {
	{ { 2.0 / 3, 1.0 / 3 }, { 7.0 / 9, 1.0 / 2 }, { 22.0 / 25, 2.0 / 3 } },
	{ { 0.840, 0.345 }, { 0.997, 0.616 }, { 1.141, 0.843 } },
	{ { 1.079, 0.368 }, { 1.033, 0.607 }, { 1.184, 0.848 } },
	{ { NAN, NAN }, { 1.048, 0.534 }, { 1.180, 0.816 } },
	{ { NAN, NAN }, { 1.302, 0.535 }, { 1.175, 0.777 } },
	{ { NAN, NAN }, { NAN, NAN }, { 1.194, 0.703 } },
	{ { NAN, NAN }, { NAN, NAN }, { 1.489, 0.702 } },
};

static const double table2[7][3][2] = {
	{ { 3.0 / 2, 1.0 / 2 }, { 35.0 / 18, 1.0 }, { 231.0 / 100, 3.0 / 2 } },
	{ { 78.6, 25.2 }, { 790.0, 410.0 }, { 9950.0, 6520.0 } },
	{ { 2.0 / 3, 1.0 / 6 }, { 2.0 / 3, 1.0 / 3 }, { 7.0 / 9, 1.0 / 2 } },
	{ { NAN, NAN }, { 0.852, 0.375 }, { 0.997, 0.617 } },
	{ { NAN, NAN }, { 1.079, 0.368 }, { 1.033, 0.607 } },
	{ { NAN, NAN }, { NAN, NAN }, { 1.053, 0.553 } },
	{ { NAN, NAN }, { NAN, NAN }, { 1.302, 0.535 } },
};

/* table 3: (b0, b1) for alpha = 1, d = 1..3 */
static const double table3[3][2] = { { 6.0, 4.0 }, { 15.23, 12.0 },
				     { 47.8, 40.0 } };

static double binom(int n, int k)
{
	double r = 1;

	for (int i = 1; i <= k; i++)
		r = r * (n - k + i) / i;
	return r;
}

/*
 * White phase noise, unmodified estimator: the terms are combinations
 * sum_p a_p x(i + p m) of independent phase values, a_p = (-1)^(d-p)
 * C(d, p), so their correlation at a lag of j m is
 * rho_j = (-1)^j C(2d, d+j) / C(2d, d) and nothing else; the variance of
 * the mean of M squared terms at stride s follows exactly.
 */
static double edf_white_pm(int d, size_t m, size_t M, size_t s)
{
	double inv = 0, c0 = binom(2 * d, d);

	for (int j = -d; j <= d; j++) {
		size_t lag = (size_t)(j < 0 ? -j : j) * m;
		double rho, dl;

		if (lag % s)
			continue;
		dl = (double)(lag / s);
		if (dl >= (double)M)
			continue;
		rho = binom(2 * d, d + (j < 0 ? -j : j)) / c0;
		inv += (1 - dl / (double)M) * rho * rho;
	}
	return (double)M / inv;
}

double sscope_allan_edf(int alpha, int d, size_t m, size_t N, bool modified,
			size_t stride)
{
	const double Jmax = 100;
	double F, S, L, M, J, r, inv;
	int row = 2 - alpha;

	if (d < 1 || d > 3 || alpha < -4 || alpha > 2 || alpha + 2 * d <= 1 ||
	    m == 0 || stride == 0 || (modified && stride != 1))
		return NAN;
	F = modified ? 1 : (double)m;
	S = (double)m / (double)stride;
	L = (double)m / F + (double)m * d;
	if ((double)N < L)
		return NAN;
	M = 1 + floor(S * ((double)N - L) / (double)m);
	J = fmin(M, floor((d + 1) * S));
	r = M / S;
	if (modified) {
		/* case 1 */
		if (J <= Jmax) {
			double z = sz(0, 1, alpha, d);

			inv = basic_sum(J, M, S, 1, alpha, d) / (z * z * M);
		} else if (r > d + 1) {
			inv = (table1[row][d - 1][0] -
			       table1[row][d - 1][1] / r) / r;
		} else {
			double mp = Jmax / r, z = sz(0, 1, alpha, d);

			inv = basic_sum(Jmax, Jmax, mp, 1, alpha, d) /
			      (z * z * Jmax);
		}
		return 1 / inv;
	}
	if (alpha <= 0) {
		/* case 2 */
		if (J <= Jmax) {
			double Fp = (double)m * (d + 1) <= Jmax ? (double)m :
								  (double)INFINITY;
			double z = sz(0, Fp, alpha, d);

			inv = basic_sum(J, M, S, Fp, alpha, d) / (z * z * M);
		} else if (r > d + 1) {
			inv = (table2[row][d - 1][0] -
			       table2[row][d - 1][1] / r) / r;
		} else {
			double mp = Jmax / r, z = sz(0, INFINITY, alpha, d);

			inv = basic_sum(Jmax, Jmax, mp, INFINITY, alpha, d) /
			      (z * z * Jmax);
		}
		return 1 / inv;
	}
	if (alpha == 1) {
		/* case 3 */
		const double b0 = table3[d - 1][0], b1 = table3[d - 1][1];

		if (J <= Jmax) {
			double z = sz(0, (double)m, 1, d);

			inv = basic_sum(J, M, S, (double)m, 1, d) / (z * z * M);
		} else if (r > d + 1) {
			double b = b0 + b1 * log((double)m);

			inv = (table2[row][d - 1][0] -
			       table2[row][d - 1][1] / r) / (b * b * r);
		} else {
			double mp = Jmax / r, b = b0 + b1 * log((double)m);

			inv = basic_sum(Jmax, Jmax, mp, mp, 1, d) / (b * b * Jmax);
		}
		return 1 / inv;
	}
	/* case 4: white phase, exact */
	return edf_white_pm(d, m, (size_t)M, stride);
}

double ssc_totdev_edf(int alpha, size_t m, size_t np)
{
	/* NIST SP 1065 table 7: edf = b T / tau - c for the frequency
	 * noises; for phase noises Stable32 uses the simple estimates of
	 * SP 1065 table 5 (white phase, flicker phase) */
	static const double bc[3][2] = { { 1.50, 0 }, { 1.17, 0.22 },
					 { 0.93, 0.36 } };
	double N = (double)np, md = (double)m;

	if (alpha == 2)
		return (N + 1) * (N - 2 * md) / (2 * (N - md));
	if (alpha == 1)
		return exp(sqrt(log((N - 1) / (2 * md)) *
				log((2 * md + 1) * (N - 1) / 4)));
	if (alpha < -2)
		alpha = -2;
	return bc[-alpha][0] * N / md - bc[-alpha][1];
}

/*
 * Quantile of chi-squared with nu degrees of freedom.  For nu >= 1000 the
 * Cornish-Fisher expansion to the nu^-3/2 term (relative error below 1e-9
 * there, checked against GSL); below, Wilson-Hilferty as a start and
 * safeguarded Newton steps on the tail probability.  GSL's own inverse,
 * and its incomplete gamma at very large nu, call the global error
 * handler (abort by default) when they do not converge, which a library
 * must not trigger.  Here with the normal score z of p and, for nu below
 * 1000, lgh = lgamma(nu / 2) + nu / 2 log 2, which the two bounds of an
 * interval share and a grid's intervals share z of.
 */
static double chi2_quantile_z(double p, double z, double nu, double lgh)
{
	double h, x, lo = 0, hi = INFINITY, target;
	bool upper;

	if (nu >= 1000) {
		double s = sqrt(2 * nu), z2 = z * z;

		return nu + s * z + 2.0 / 3 * (z2 - 1) + (z2 * z - 7 * z) / (9 * s) -
		       (6 * z2 * z2 + 14 * z2 - 32) / (405 * nu) +
		       (9 * z2 * z2 * z + 256 * z2 * z - 433 * z) / (4860 * nu * s);
	}
	h = 2 / (9 * nu);
	x = nu * pow(1 - h + z * sqrt(h), 3);
	upper = p > 0.5;
	target = upper ? 1 - p : p;
	if (!(x > 0) || !isfinite(x))
		x = nu * 1e-3 + 1e-300;
	/* Halley steps (the density's log-derivative is (nu/2 - 1)/x - 1/2):
	 * from the start above, and a last step taken without the evaluation
	 * that would confirm it: one or two tail evaluations, not four or
	 * five as Newton's, which an all-tau grid pays 30,000 times */
	for (int it = 0; it < 200; it++) {
		double F = upper ? gsl_cdf_chisq_Q(x, nu) : gsl_cdf_chisq_P(x, nu);
		double f = exp((nu / 2 - 1) * log(x) - x / 2 - lgh), nx, dx;
		bool below = upper ? F > target : F < target;

		/* x is below the quantile when the lower tail is too small */
		if (below)
			lo = x;
		else
			hi = x;
		if (fabs(F - target) <= 1e-14 * target)
			break;
		dx = f > 0 ? (upper ? (F - target) : (target - F)) / f : (double)NAN;
		nx = x + dx / (1 + 0.5 * dx * ((nu / 2 - 1) / x - 0.5));
		if (!(nx > lo && nx < hi) || !isfinite(nx))
			nx = isinf(hi) ? 2 * x + 1 : 0.5 * (lo + hi);
		else if (fabs(nx - x) <= 1e-6 * x)
			return nx; /* Halley's error cubes: now ~1e-18 */
		if (fabs(nx - x) <= 1e-13 * x)
			break;
		x = nx;
	}
	return x;
}

static double chi2_lgh(double nu)
{
	return nu < 1000 ? lgamma(nu / 2) + nu / 2 * 0.69314718055994531 : 0;
}

double ssc_chi2_quantile(double p, double nu)
{
	if (!(p > 0 && p < 1) || !(nu > 0))
		return NAN;
	return chi2_quantile_z(p, gsl_cdf_ugaussian_Pinv(p), nu, chi2_lgh(nu));
}

/*
 * The quantiles of a grid of many taus from a table: ln q against ln nu
 * over [CI_TAB_NU_LO, 1000) (Cornish-Fisher above), in pieces CI_TAB_W
 * wide, each a Chebyshev series (GSL) of order CI_TAB_ORDER through the
 * quantiles computed in full at its nodes.  ln q is smooth in ln nu (at
 * small nu it goes as 2 ln(p Gamma(nu/2 + 1)) / nu), so the series agree
 * with the full computation to its own precision (within 3e-14 at levels
 * 0.683 and 0.95, tested to 1e-13; 1.1e-13 at a level of 1 - 1e-12): one
 * series instead of one or two evaluations of the incomplete
 * gamma function per quantile, which was a third of an all-tau grid's
 * run.  Built on the threads: 2 x 16 series of 25 nodes.
 */
#define CI_TAB_NU_LO 0.5
#define CI_TAB_NU_HI 1000.0
#define CI_TAB_W 0.5
#define CI_TAB_ORDER 24

struct ssc_ci_start {
	double u_lo;
	size_t np;             /* pieces */
	gsl_cheb_series **cs;  /* 2 np: each piece's lower, upper quantile */
};

void ssc_allan_ci_level_free(struct ssc_ci_level *cl)
{
	if (!cl->start)
		return;
	for (size_t k = 0; k < 2 * cl->start->np; k++)
		if (cl->start->cs[k])
			gsl_cheb_free(cl->start->cs[k]);
	free(cl->start->cs);
	free(cl->start);
	cl->start = NULL;
}

struct ln_q_par {
	double p, z;
};

/* ln of the chi-squared quantile at p (normal score z), of ln nu */
static double ln_q(double u, void *par)
{
	const struct ln_q_par *q = par;
	double nu = exp(u);

	return log(chi2_quantile_z(q->p, q->z, nu, chi2_lgh(nu)));
}

int ssc_allan_ci_starts(struct ssc_ci_level *cl)
{
	const double u_lo = log(CI_TAB_NU_LO), u_hi = log(CI_TAB_NU_HI);
	const size_t np = (size_t)ceil((u_hi - u_lo) / CI_TAB_W);
	const struct ln_q_par par[2] = { { cl->pl, cl->zl }, { cl->ph, cl->zh } };
	struct ssc_ci_start *st;
	bool bad = false;

	if (!cl->ok || cl->start)
		return 0;
	st = calloc(1, sizeof(*st));
	if (st)
		st->cs = calloc(2 * np, sizeof(*st->cs));
	if (!st || !st->cs) {
		free(st);
		return -ENOMEM;
	}
	st->u_lo = u_lo;
	st->np = np;
	cl->start = st;
SSC_OMP(omp parallel for schedule(dynamic, 1) reduction(|| : bad))
	for (size_t k = 0; k < 2 * np; k++) {
		double a = u_lo + CI_TAB_W * (double)(k / 2);
		gsl_function F = { ln_q, (void *)&par[k % 2] };
		gsl_cheb_series *cs = gsl_cheb_alloc(CI_TAB_ORDER);

		/* the last piece ends at nu = 1000: no node where the full
		 * computation switches to Cornish-Fisher */
		if (!cs || gsl_cheb_init(cs, &F, a, fmin(a + CI_TAB_W, u_hi))) {
			bad = true;
		} else {
			const double *c = gsl_cheb_coeffs(cs);

			/* a level so extreme that a quantile underflows */
			for (size_t i = 0; i <= CI_TAB_ORDER; i++)
				if (!isfinite(c[i]))
					bad = true;
		}
		st->cs[k] = cs;
	}
	if (bad)
		ssc_allan_ci_level_free(cl); /* the full computation */
	return 0;
}

void ssc_allan_ci_level(struct ssc_ci_level *cl, double level)
{
	cl->pl = (1 - level) / 2;
	cl->ph = 1 - cl->pl;
	cl->ok = cl->pl > 0 && cl->pl < 1 && cl->ph > 0 && cl->ph < 1;
	cl->zl = cl->ok ? gsl_cdf_ugaussian_Pinv(cl->pl) : (double)NAN;
	cl->zh = cl->ok ? gsl_cdf_ugaussian_Pinv(cl->ph) : (double)NAN;
	cl->start = NULL;
}

void ssc_allan_ci_at(const struct ssc_ci_level *lv, double dev, double edf,
		     double *lo, double *hi)
{
	double cl, ch, lgh;

	if (!(edf > 0) || !isfinite(dev)) {
		*lo = *hi = NAN;
		return;
	}
	if (!lv->ok) {
		cl = ch = NAN;
	} else if (lv->start && edf >= CI_TAB_NU_LO && edf < CI_TAB_NU_HI) {
		double u = log(edf);
		size_t k = (size_t)((u - lv->start->u_lo) / CI_TAB_W);

		if (k >= lv->start->np)
			k = lv->start->np - 1;
		cl = exp(gsl_cheb_eval(lv->start->cs[2 * k], u));
		ch = exp(gsl_cheb_eval(lv->start->cs[2 * k + 1], u));
	} else {
		lgh = chi2_lgh(edf);
		cl = chi2_quantile_z(lv->pl, lv->zl, edf, lgh);
		ch = chi2_quantile_z(lv->ph, lv->zh, edf, lgh);
	}
	*lo = dev * sqrt(edf / ch);
	*hi = cl > 0 ? dev * sqrt(edf / cl) : (double)INFINITY;
}

void ssc_allan_ci(double dev, double edf, double level, double *lo,
		  double *hi)
{
	struct ssc_ci_level lv;

	ssc_allan_ci_level(&lv, level);
	ssc_allan_ci_at(&lv, dev, edf, lo, hi);
}

/* ------------------------------------------------------------------ */
/* Noise identification                                                */
/* ------------------------------------------------------------------ */

/* the sums of lag1() over n points all valid, in eight interleaved
 * lanes (one chain of additions bounded it: 65536 points per tau) */
static void lag1_sums(const double *u, size_t n, double *mu_out,
		      double *a_out, double *b_out)
{
	double s[8] = { 0 }, sa[8] = { 0 }, sb[8] = { 0 }, mu, a, b;
	size_t k = 0;

	for (; k + 8 <= n; k += 8)
		for (int r = 0; r < 8; r++)
			s[r] += u[k + r];
	mu = ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
	for (; k < n; k++)
		mu += u[k];
	mu /= (double)n;
	k = 0;
	for (; k + 9 <= n; k += 8)
		for (int r = 0; r < 8; r++) {
			double e = u[k + r] - mu;

			sb[r] += e * e;
			sa[r] += e * (u[k + r + 1] - mu);
		}
	a = ((sa[0] + sa[1]) + (sa[2] + sa[3])) +
	    ((sa[4] + sa[5]) + (sa[6] + sa[7]));
	b = ((sb[0] + sb[1]) + (sb[2] + sb[3])) +
	    ((sb[4] + sb[5]) + (sb[6] + sb[7]));
	for (; k < n; k++) {
		b += (u[k] - mu) * (u[k] - mu);
		if (k + 1 < n)
			a += (u[k] - mu) * (u[k + 1] - mu);
	}
	*mu_out = mu;
	*a_out = a;
	*b_out = b;
}

/* lag-1 autocorrelation over valid points (pairs both valid), scaled by
 * (c - 1) / c as Stable32 does (c valid points); v NULL: all valid */
static int lag1(const double *u, const unsigned char *v, size_t n, double *r1)
{
	double mu = 0, a = 0, b = 0;
	size_t c = 0;

	if (!v) {
		if (n < 2)
			return -EDOM;
		lag1_sums(u, n, &mu, &a, &b);
		if (!(b > 0))
			return -EDOM;
		*r1 = a / b * (double)(n - 1) / (double)n;
		return 0;
	}

	for (size_t k = 0; k < n; k++)
		if (!v || v[k]) {
			mu += u[k];
			c++;
		}
	if (c < 2)
		return -EDOM;
	mu /= (double)c;
	for (size_t k = 0; k < n; k++) {
		if (v && !v[k])
			continue;
		b += (u[k] - mu) * (u[k] - mu);
		if (k + 1 < n && (!v || v[k + 1]))
			a += (u[k] - mu) * (u[k + 1] - mu);
	}
	if (!(b > 0))
		return -EDOM;
	*r1 = a / b * (double)(c - 1) / (double)c;
	return 0;
}

/*
 * Barnes' B1 bias function: expected ratio of the N-sample to the
 * two-sample variance for an AVAR exponent mu (Howe, Beard, Greenhall,
 * Riley, 32nd PTTI 2000, table 3), written so that large N cannot
 * overflow.
 */
static double b1_theory(double N, int mu)
{
	switch (mu) {
	case -2:
		return (N + 1) / (1.5 * N);
	case -1:
		return 1;
	case 0:
		return N * log(N) / (2 * (N - 1) * log(2.0));
	case 1:
		return N / 2;
	default:
		return N * (N + 1) / 6;
	}
}

/* R(n) = MVAR / AVAR expected for flicker phase (NIST TN 1337 A-6, the
 * measurement bandwidth 1 / (2 tau0)); white phase gives 1 / m */
static double rn_fpm(double m)
{
	return 3.37 / (1.04 + 3 * log(PI_ * m));
}

/*
 * B1-ratio identification (NIST SP 1065 section 5.6, as Stable32 for
 * fewer than 30 analysis points): the standard variance of the averages
 * over their two-sample variance, compared with B1 at the geometric means
 * of neighbouring noise types (arithmetic between mu = 1 and 2); white
 * and flicker phase (mu = -2) are told apart by R(n) when the caller has
 * it, else flicker phase is taken.
 */
static int b1_id(const double *z, const unsigned char *valid, size_t n,
		 bool rate_like, const struct ssc_nid_few *few, int *alpha,
		 double *alpha_est)
{
	double s = 0, s2 = 0, a2 = 0, mean, svar, avar, b1;
	size_t c = 0, ca = 0, prev = SIZE_MAX;
	int mu = -2;

	for (size_t k = 0; k + 1 < n; k++) {
		bool ok = !valid ||
			  (rate_like ? valid[k] : valid[k] && valid[k + 1]);
		double yk = z[k + 1] - z[k];

		if (!ok) {
			prev = SIZE_MAX;
			continue;
		}
		s += yk;
		c++;
		if (prev != SIZE_MAX) {
			double dy = yk - (z[prev + 1] - z[prev]);

			a2 += dy * dy;
			ca++;
		}
		prev = k;
	}
	if (c < few->min_averages || c < 2 || ca == 0)
		return -EDOM;
	mean = s / (double)c;
	for (size_t k = 0; k + 1 < n; k++) {
		bool ok = !valid ||
			  (rate_like ? valid[k] : valid[k] && valid[k + 1]);
		double yk = z[k + 1] - z[k] - mean;

		if (ok)
			s2 += yk * yk;
	}
	svar = s2 / (double)(c - 1);
	avar = a2 / (2 * (double)ca);
	if (!(avar > 0) || !isfinite(svar))
		return -EDOM;
	b1 = svar / avar;
	for (int m = -1; m <= 2; m++) {
		double lo = b1_theory(few->n_points, m - 1);
		double hi = b1_theory(few->n_points, m);
		double bound = m == 2 ? 0.5 * (lo + hi) : sqrt(lo * hi);

		if (b1 > bound)
			mu = m;
	}
	if (mu == -2) {
		double rn_b = sqrt(rn_fpm((double)few->m) / (double)few->m);

		*alpha = isfinite(few->rn) && few->rn < rn_b ? 2 : 1;
	} else {
		*alpha = -mu - 1;
	}
	if (alpha_est)
		*alpha_est = *alpha;
	return 0;
}

int ssc_noise_id_series(const double *z, const unsigned char *valid,
			size_t n, bool rate_like, int dmax,
			const struct ssc_nid_few *few, int *alpha,
			double *alpha_est, double *u, unsigned char *vw)
{
	size_t len, nvalid = 0;
	bool all_valid;
	int d = 0;

	if (n < 2)
		return -EDOM;
	if (rate_like) {
		len = n - 1;
		for (size_t k = 0; k < len; k++)
			u[k] = z[k + 1] - z[k];
	} else {
		len = n;
		memcpy(u, z, len * sizeof(double));
	}
	if (valid) {
		memcpy(vw, valid, len);
		for (size_t k = 0; k < len; k++)
			nvalid += vw[k];
	} else {
		memset(vw, 1, len);
		nvalid = len;
	}
	if (nvalid < SSC_NOISE_ID_MIN)
		return few ? b1_id(z, valid, n, rate_like, few, alpha, alpha_est) :
			     -EDOM;
	/* (every point valid: so are all their differences) */
	all_valid = nvalid == len;
	for (;;) {
		double r1, rho;
		int rc = lag1(u, all_valid ? NULL : vw, len, &r1);

		if (rc)
			return rc;
		rho = r1 / (1 + r1);
		if (rho < 0.25 || d >= dmax) {
			double add = rate_like ? 0 : 2;
			int a = (int)(-lround(2 * rho) - 2 * d + (int)add);

			if (alpha_est)
				*alpha_est = -2 * (rho + d) + add;
			*alpha = a < -4 ? -4 : a > 2 ? 2 : a;
			return 0;
		}
		for (size_t k = 0; k + 1 < len; k++)
			u[k] = u[k + 1] - u[k];
		for (size_t k = 0; !all_valid && k + 1 < len; k++)
			vw[k] = vw[k] && vw[k + 1];
		len--;
		d++;
		if (len < 2)
			return -EDOM;
	}
}

int sscope_allan_noise_id(const double *phase, size_t np, size_t m,
			  bool rate_like, int dmax, int *alpha,
			  double *alpha_est)
{
	size_t K;
	double *buf;
	unsigned char *vw;
	int rc;

	if (!phase || !alpha || m == 0 || np < 2 || dmax < 1 || dmax > 3)
		return -EINVAL;
	K = (np - 1) / m + 1;
	if (K > SSC_NOISE_ID_MAX + 1)
		K = SSC_NOISE_ID_MAX + 1;
	buf = ssc_alloc_array(2 * K, sizeof(double));
	vw = malloc(K);
	if (!buf || !vw) {
		free(buf);
		free(vw);
		return -ENOMEM;
	}
	for (size_t k = 0; k < K; k++)
		buf[k] = phase[k * m];
	rc = ssc_noise_id_series(buf, NULL, K, rate_like, dmax, NULL, alpha,
				 alpha_est, buf + K, vw);
	free(buf);
	free(vw);
	return rc;
}
