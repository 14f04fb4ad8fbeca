/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The total, Theo and time-error members of the Allan family, on phase
 * points x[0..np) (rate unit * s), as defined in NIST SP 1065 (W. J.
 * Riley, "Handbook of Frequency Stability Analysis", 2008):
 *
 *  - MTOTDEV, section 5.2.12: each 3m-point phase subsequence has its
 *    linear trend removed by the half-average method (the means of its
 *    first and last halves, floor(3m/2) points each, over the distance
 *    between their centres), is extended by uninverted even reflection at
 *    both ends to 9m points, and the 6m modified-Allan terms z_j (sums of
 *    m second differences at lag m) of the extension are averaged:
 *    Mod tot var = < (1/6m) sum_j z_j^2 >_n / (2 m^2 tau^2), n over the
 *    np - 3m + 1 subsequences.  Cost: O(m) per subsequence (one running
 *    sum of the detrended subsequence, its reflected window sums read in
 *    O(1) each), O((np - 3m) m) per tau; every sum is of values relative
 *    to the subsequence's first point, so that no digit is lost to the
 *    record's wander.
 *  - TTOTDEV, section 5.2.13: tau / sqrt(3) * MTOTDEV.
 *  - HTOTDEV, section 5.2.14: the same construction on the 3m-point
 *    subsequences of the rate y (first differences of phase / tau0), whose
 *    linear trend (rate drift) is removed by the half-average method, with
 *    second differences of m-averages (third differences of phase):
 *    Htot var = < (1/6m) sum_j (z_j / m)^2 >_n / 6; at m = 1 the
 *    overlapping Hadamard variance, as SP 1065 and Stable32.  The bias of
 *    Htot var against the Hadamard variance for the frequency noises,
 *    Htotvar = (1 - a) Hvar with a = 0.005 (white FM), 0.149 (flicker FM),
 *    0.229 (random-walk FM), 0.283 (flicker-walk FM), 0.321 (random-run
 *    FM) (SP 1065 section 5.2.14, as Stable32 applies it), is removed by
 *    the caller once the noise type is known.  Cost O((np - 3m) m) per tau.
 *  - Theo1, section 5.2.15 (eq. 33): m even, 10 <= m <= np - 1, at
 *    tau = 0.75 m tau0: Theo1 = sum_{i < np-m} sum_{d < m/2}
 *    [(x_i - x_{i+m/2-d}) + (x_{i+m} - x_{i+m/2+d})]^2 / (m/2 - d) /
 *    (0.75 (np - m) (m tau0)^2).  Cost: (np - m) m / 2 terms per tau
 *    (O(np m)), four loads and five flops each, vectorised, over the
 *    threads; an octave grid costs about np^2 / 4 terms in all.  The
 *    expansion of the square into correlations (O(np log np) by FFT)
 *    would subtract sums of x^2 that, on a random-walk rate, exceed the
 *    result by (np / m)^3: it is not used.
 *  - TheoBR, section 5.2.16 (eq. 35): Theo1 times the average ratio
 *    AVAR(9 + 3i) / Theo1(12 + 4i), i = 0..n, n = floor(0.1 np / 3) - 3
 *    (both at tau = (9 + 3i) tau0).  The full average costs O(np^3 / 900);
 *    beyond SSC_THEOBR_RATIOS ratios the average is taken over that many
 *    i evenly spread over 0..n (the first and the last included), which
 *    changes it by a fraction of its own sampling scatter (the ratios of
 *    neighbouring i are almost fully correlated) and keeps the cost at
 *    O(SSC_THEOBR_RATIOS np^2 / 30).
 *  - TheoH, section 5.2.17 (eq. 36): the overlapping Allan variance for
 *    tau <= k, k the largest Allan tau within 10 % of the record
 *    (m <= floor(0.1 (np - 1))), and TheoBR for 0.75 m tau0 >= k.
 *  - MTIE, section 5.2.18: the largest peak-to-peak phase over every
 *    window of m + 1 points, by a monotone deque of the window's minima
 *    and maxima: O(np) per tau whatever m (each point enters and leaves
 *    each deque once).
 *  - TIE rms, section 5.2.19: sqrt(< (x_{i+m} - x_i)^2 >), O(np) per tau.
 */
#include "allan-internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#if defined(__GNUC__) && !defined(__clang__)
#define FAM_VEC 1
typedef double fam_v8 __attribute__((vector_size(64)));
#define FV8LOAD(v, p) memcpy(&(v), (p), sizeof(fam_v8))
#endif

/* Theo1 terms per thread before it is worth a second one */
#define THEO_PAR_MIN ((size_t)1 << 16)

/* ------------------------------------------------------------------ */
/* Theo1                                                               */
/* ------------------------------------------------------------------ */

/* sum_i ((a_i - b_i) + (c_i - e_i))^2, i < n */
SSC_TARGET_CLONES("avx512f", "avx2", "default")
static double theo_row(const double *a, const double *b, const double *c,
		       const double *e, size_t n)
{
	size_t i = 0;
	double s = 0;

#ifdef FAM_VEC
	fam_v8 s0 = { 0 }, s1 = s0;

	for (; i + 16 <= n; i += 16) {
		fam_v8 a0, b0, c0, e0, a1, b1, c1, e1, d0, d1;

		FV8LOAD(a0, a + i);
		FV8LOAD(b0, b + i);
		FV8LOAD(c0, c + i);
		FV8LOAD(e0, e + i);
		FV8LOAD(a1, a + i + 8);
		FV8LOAD(b1, b + i + 8);
		FV8LOAD(c1, c + i + 8);
		FV8LOAD(e1, e + i + 8);
		d0 = (a0 - b0) + (c0 - e0);
		d1 = (a1 - b1) + (c1 - e1);
		s0 += d0 * d0;
		s1 += d1 * d1;
	}
	s0 += s1;
	s = ((s0[0] + s0[1]) + (s0[2] + s0[3])) +
	    ((s0[4] + s0[5]) + (s0[6] + s0[7]));
#endif
	for (; i < n; i++) {
		double d = (a[i] - b[i]) + (c[i] - e[i]);

		s += d * d;
	}
	return s;
}

/* Parallel sums in SUM_GROUPS groups of consecutive terms fixed by the
 * sizes alone, added in order: the same to the bit on any team. */
#define SUM_GROUPS 64

/* the double sum of eq. 33 (without its normalisation) */
static double theo1_sum(const double *x, size_t np, size_t m, unsigned T,
			struct ssc_xf_ws *ws)
{
	const size_t h = m / 2, ni = np - m;
	double gs[SUM_GROUPS], total = 0;

	/* by transforms where they pay and their rounding bound is below a
	 * part in 10^8 of the sum, 5.10^-9 of the deviation (else by the
	 * definition) */
	if (ws && ssc_theo_fast_pays(np, m)) {
		double err, s = ssc_theo1_sum_fast(ws, m, T, &err);

		if (isfinite(s) && s > 0 && err <= SSC_THEO_FAST_TOL * s)
			return s;
	}

	(void)T;
SSC_OMP(omp parallel for num_threads(T) schedule(dynamic, 1) if (ni * h >= THEO_PAR_MIN))
	for (size_t g = 0; g < SUM_GROUPS; g++) {
		double t = 0;

		for (size_t d = h * g / SUM_GROUPS; d < h * (g + 1) / SUM_GROUPS; d++) {
			double s = 0;

			/* blocks keep each partial sum short (all terms >= 0) */
			for (size_t i0 = 0; i0 < ni; i0 += 8192) {
				size_t len = ni - i0 < 8192 ? ni - i0 : 8192;

				s += theo_row(x + i0, x + i0 + h - d, x + i0 + m,
					      x + i0 + h + d, len);
			}
			t += s / (double)(h - d);
		}
		gs[g] = t;
	}
	for (size_t g = 0; g < SUM_GROUPS; g++)
		total += gs[g];
	return total;
}

double ssc_theo1_var(const double *x, size_t np, size_t m, double tau0,
		     unsigned T, struct ssc_xf_ws *ws)
{
	double md = (double)m * tau0;

	if (m < 10 || (m & 1) || m >= np)
		return NAN;
	return theo1_sum(x, np, m, T, ws) / (0.75 * (double)(np - m) * md * md);
}

/* overlapping Allan variance at m (exact second differences) */
static double avar_plain(const double *x, size_t np, size_t m, double tau0)
{
	struct ssc_ksum acc = { 0, 0 };
	double part = 0, md = (double)m * tau0;
	size_t nt = np - 2 * m;

	for (size_t i = 0; i < nt; i++) {
		double d = (x[i + 2 * m] - x[i + m]) - (x[i + m] - x[i]);

		part += d * d;
		if ((i & 4095) == 4095) {
			ssc_ksum_add(&acc, part);
			part = 0;
		}
	}
	ssc_ksum_add(&acc, part);
	return ssc_ksum_value(&acc) / (2 * md * md * (double)nt);
}

/* the last index n of TheoBR's ratios (eq. 35); < 0: too short */
static long theobr_n(size_t np)
{
	return (long)floor(0.1 * (double)np / 3) - 3;
}

size_t ssc_theobr_mmax(size_t np)
{
	long n = theobr_n(np);

	return n < 0 ? 0 : 12 + 4 * (size_t)n;
}

/* TheoBR's bias ratio (eq. 35): NAN when np is too short (n < 0) */
double ssc_theobr_ratio(const double *x, size_t np, double tau0, unsigned T,
			struct ssc_xf_ws *ws)
{
	long n = theobr_n(np);
	size_t cnt, k;
	struct ssc_ksum acc = { 0, 0 };

	if (n < 0)
		return NAN;
	cnt = (size_t)n + 1 < SSC_THEOBR_RATIOS ? (size_t)n + 1 : SSC_THEOBR_RATIOS;
	for (k = 0; k < cnt; k++) {
		size_t i = cnt == 1 ? 0 : (size_t)llround((double)k * (double)n /
							   (double)(cnt - 1));
		double a = avar_plain(x, np, 9 + 3 * i, tau0);
		double t = ssc_theo1_var(x, np, 12 + 4 * i, tau0, T, ws);

		ssc_ksum_add(&acc, t > 0 ? a / t : 0);
	}
	return ssc_ksum_value(&acc) / (double)cnt;
}

/* ------------------------------------------------------------------ */
/* MTOTDEV, HTOTDEV                                                    */
/* ------------------------------------------------------------------ */

/*
 * sum over the subsequences v[n .. n + 3m), n < nsub, of
 * (1/6m) sum_j z_j^2 of the half-average-detrended, reflected extension
 * (see the file comment).  Work space: C, 3m + 1 doubles; W, 8m + 1.
 */
SSC_TARGET_CLONES("avx512f", "avx2", "default")
static double tot_subseq(const double *v, size_t m, double *C, double *W)
{
	const size_t L = 3 * m, hl = L / 2;
	double m1 = 0, m2 = 0, s, C3;
	struct ssc_ksum acc = { 0, 0 };
	double part;
	const double v0 = v[0];

	/* half averages of the values relative to v[0] */
	for (size_t k = 0; k < hl; k++) {
		m1 += v[k] - v0;
		m2 += v[L - hl + k] - v0;
	}
	s = (m2 - m1) / (double)hl / (double)(L - hl);
	/* the running sum in four quarters at once (four independent chains
	 * of additions instead of one), each then moved up by the sum of
	 * the quarters before it */
	{
		const size_t q = L / 4;
		double a0 = 0, a1 = 0, a2 = 0, a3 = 0;

		C[0] = 0;
		for (size_t k = 0; k < q; k++) {
			a0 += (v[k] - v0) - s * (double)k;
			a1 += (v[k + q] - v0) - s * (double)(k + q);
			a2 += (v[k + 2 * q] - v0) - s * (double)(k + 2 * q);
			a3 += (v[k + 3 * q] - v0) - s * (double)(k + 3 * q);
			C[k + 1] = a0;
			C[k + q + 1] = a1;
			C[k + 2 * q + 1] = a2;
			C[k + 3 * q + 1] = a3;
		}
		for (size_t k = 4 * q; k < L; k++) {
			a3 += (v[k] - v0) - s * (double)k;
			C[k + 1] = a3;
		}
		for (size_t k = q + 1; k <= 2 * q; k++)
			C[k] += C[q];
		for (size_t k = 2 * q + 1; k <= 3 * q; k++)
			C[k] += C[2 * q];
		for (size_t k = 3 * q + 1; k <= L; k++)
			C[k] += C[3 * q];
	}
	C3 = C[L];
	/* window sums of the 9m-point extension x*, windows [t, t + m) */
	for (size_t t = 0; t <= 2 * m; t++)
		W[t] = C[3 * m - t] - C[2 * m - t];
	for (size_t t = 2 * m + 1; t < 3 * m; t++)
		W[t] = C[3 * m - t] + C[t - 2 * m];
	for (size_t t = 3 * m; t <= 5 * m; t++)
		W[t] = C[t - 2 * m] - C[t - 3 * m];
	for (size_t t = 5 * m + 1; t < 6 * m; t++)
		W[t] = (C3 - C[t - 3 * m]) + (C3 - C[8 * m - t]);
	for (size_t t = 6 * m; t <= 8 * m; t++)
		W[t] = C[9 * m - t] - C[8 * m - t];
	/* four lanes: the sum is not one chain of dependent additions */
	for (size_t j0 = 0; j0 < 6 * m; j0 += 1024) {
		size_t j1 = 6 * m - j0 < 1024 ? 6 * m : j0 + 1024, j = j0;
		double p0 = 0, p1 = 0, p2 = 0, p3 = 0;

		for (; j + 4 <= j1; j += 4) {
			double z0 = (W[j + 2 * m] - W[j + m]) - (W[j + m] - W[j]);
			double z1 = (W[j + 1 + 2 * m] - W[j + 1 + m]) -
				    (W[j + 1 + m] - W[j + 1]);
			double z2 = (W[j + 2 + 2 * m] - W[j + 2 + m]) -
				    (W[j + 2 + m] - W[j + 2]);
			double z3 = (W[j + 3 + 2 * m] - W[j + 3 + m]) -
				    (W[j + 3 + m] - W[j + 3]);

			p0 += z0 * z0;
			p1 += z1 * z1;
			p2 += z2 * z2;
			p3 += z3 * z3;
		}
		for (; j < j1; j++) {
			double z = (W[j + 2 * m] - W[j + m]) - (W[j + m] - W[j]);

			p0 += z * z;
		}
		part = (p0 + p1) + (p2 + p3);
		ssc_ksum_add(&acc, part);
	}
	return ssc_ksum_value(&acc) / (double)(6 * m);
}

/* mean over the nsub subsequences of v of tot_subseq(); -ENOMEM: NAN */
static double tot_mean(const double *v, size_t nv, size_t m, unsigned T)
{
	const size_t nsub = nv - 3 * m + 1;
	double gs[SUM_GROUPS], total = 0;
	bool oom = false;

	(void)T;
SSC_OMP(omp parallel num_threads(T) if (nsub * m >= THEO_PAR_MIN))
	{
		double *C = ssc_alloc_array(3 * m + 1, sizeof(double));
		double *W = ssc_alloc_array(8 * m + 1, sizeof(double));

		if (!C || !W) {
SSC_OMP(omp atomic write)
			oom = true;
		}
SSC_OMP(omp for schedule(dynamic, 1))
		for (size_t g = 0; g < SUM_GROUPS; g++) {
			double t = 0;

			for (size_t n = nsub * g / SUM_GROUPS;
			     n < nsub * (g + 1) / SUM_GROUPS; n++)
				if (C && W)
					t += tot_subseq(v + n, m, C, W);
			gs[g] = t;
		}
		free(C);
		free(W);
	}
	for (size_t g = 0; g < SUM_GROUPS; g++)
		total += gs[g];
	return oom ? (double)NAN : total / (double)nsub;
}

double ssc_mtot_var(const double *x, size_t np, size_t m, double tau0,
		    unsigned T)
{
	double md = (double)m, tau = md * tau0;

	if (m == 0 || 3 * m > np)
		return NAN;
	return tot_mean(x, np, m, T) / (2 * md * md * tau * tau);
}

double ssc_htot_var(const double *x, size_t np, size_t m, double tau0,
		    unsigned T)
{
	double *y, r, md = (double)m;

	if (m == 0 || np < 4 || 3 * m > np - 1)
		return NAN;
	if (m == 1) {
		/* overlapping Hadamard variance */
		struct ssc_ksum acc = { 0, 0 };
		size_t nt = np - 3;

		for (size_t i = 0; i < nt; i++) {
			double a = x[i + 1] - x[i], b = x[i + 2] - x[i + 1];
			double c = x[i + 3] - x[i + 2];
			double d = (c - b) - (b - a);

			ssc_ksum_add(&acc, d * d);
		}
		return ssc_ksum_value(&acc) / (6 * tau0 * tau0 * (double)nt);
	}
	y = ssc_alloc_array(np - 1, sizeof(double));
	if (!y)
		return NAN;
	for (size_t k = 0; k + 1 < np; k++)
		y[k] = (x[k + 1] - x[k]) / tau0;
	r = tot_mean(y, np - 1, m, T) / (6 * md * md);
	free(y);
	return r;
}

/* ------------------------------------------------------------------ */
/* MTIE, TIE rms                                                       */
/* ------------------------------------------------------------------ */

/* ring capacity of the deques: a power of two >= m + 1 (indices masked,
 * not divided) */
size_t ssc_mtie_work(size_t m)
{
	size_t c = 1;

	while (c < m + 1)
		c <<= 1;
	return 2 * c;
}

/* largest max - min over the windows x[i .. i + m], i < np - m; work:
 * ssc_mtie_work(m) indices */
double ssc_mtie(const double *x, size_t np, size_t m, size_t *work)
{
	const size_t cap = ssc_mtie_work(m) / 2, mask = cap - 1;
	size_t *qmax = work, *qmin = work + cap;
	size_t hmax = 0, tmax = 0, hmin = 0, tmin = 0; /* ring buffers */
	double best = 0;

	if (m == 0 || m >= np)
		return NAN;
	for (size_t k = 0; k < np; k++) {
		const double v = x[k];

		/* drop what left the window [k - m, k] */
		if (tmax != hmax && qmax[hmax & mask] + m < k)
			hmax++;
		if (tmin != hmin && qmin[hmin & mask] + m < k)
			hmin++;
		while (tmax != hmax && x[qmax[(tmax - 1) & mask]] <= v)
			tmax--;
		qmax[tmax++ & mask] = k;
		while (tmin != hmin && x[qmin[(tmin - 1) & mask]] >= v)
			tmin--;
		qmin[tmin++ & mask] = k;
		if (k >= m) {
			double pp = x[qmax[hmax & mask]] - x[qmin[hmin & mask]];

			if (pp > best)
				best = pp;
		}
	}
	return best;
}

double ssc_tierms(const double *x, size_t np, size_t m)
{
	struct ssc_ksum acc = { 0, 0 };
	double part = 0;
	size_t nt;

	if (m == 0 || m >= np)
		return NAN;
	nt = np - m;
	for (size_t i = 0; i < nt; i++) {
		double d = x[i + m] - x[i];

		part += d * d;
		if ((i & 4095) == 4095) {
			ssc_ksum_add(&acc, part);
			part = 0;
		}
	}
	ssc_ksum_add(&acc, part);
	return sqrt(ssc_ksum_value(&acc) / (double)nt);
}

/* ------------------------------------------------------------------ */
/* Degrees of freedom                                                  */
/* ------------------------------------------------------------------ */

/* NIST SP 1065 table 8 (MTOTDEV, TTOTDEV): edf = b N / m - c */
double ssc_mtot_edf(int alpha, size_t m, size_t np)
{
	static const double bc[5][2] = { { 1.90, 2.1 }, { 1.20, 1.40 },
					 { 1.10, 1.2 }, { 0.85, 0.50 },
					 { 0.75, 0.31 } };
	int k = 2 - (alpha < -2 ? -2 : alpha > 2 ? 2 : alpha);

	return bc[k][0] * (double)np / (double)m - bc[k][1];
}

/* NIST SP 1065 table 9 (HTOTDEV, the frequency noises):
 * edf = (N / m) / (b0 + b1 m / N) */
double ssc_htot_edf(int alpha, size_t m, size_t np)
{
	static const double b[3][2] = { { 0.559, 1.004 }, { 0.868, 1.140 },
					{ 0.938, 1.696 } };
	double N = (double)np, md = (double)m;
	int k = alpha < -2 ? 2 : -alpha;

	if (m == 1 || alpha > 0)
		return sscope_allan_edf(alpha, 3, m, np, false, 1);
	return N / md / (b[k][0] + b[k][1] * md / N);
}

/* NIST SP 1065 section 5.2.15, the Theo1 EDF of Howe & Tasset (r = 0.75 m,
 * the Theo1 tau in units of tau0; N phase points) */
double ssc_theo1_edf(int alpha, size_t m, size_t np)
{
	double r = 0.75 * (double)m, N = (double)np;

	switch (alpha < -2 ? -2 : alpha > 2 ? 2 : alpha) {
	case 2:
		return 0.86 * (N + 1) * (N - 4 * r / 3) / (N - r) * (r / (r + 1.14));
	case 1:
		return (4.798 * N * N - 6.374 * r * N + 12.387 * r) /
		       (sqrt(r + 36.6) * (N - r)) * (r / (r + 0.3));
	case 0:
		return ((4.1 * N + 0.8) / r - (3.1 * N + 6.5) / N) *
		       (pow(r, 1.5) / (pow(r, 1.5) + 5.2));
	case -1:
		return (2 * N * N - 1.3 * r * N - 3.5 * r) / (r * N) *
		       (r * r * r / (r * r * r + 2.3));
	default: {
		double a = 4.4 * N;

		return (a - 2) / (2.9 * r) *
		       (((a - 1) * (a - 1) - 8.6 * r * (a - 1) + 11.4 * r * r) /
			((a - 3) * (a - 3)));
	}
	}
}

/* SP 1065 section 5.2.14: Htotvar = (1 - a) Hvar for the frequency noises */
double ssc_htot_bias(int alpha)
{
	static const double a[5] = { 0.005, 0.149, 0.229, 0.283, 0.321 };

	if (alpha > 0)
		return 1;
	return 1 - a[alpha < -4 ? 4 : -alpha];
}
