/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Sums of the Allan family by Fourier transforms, where the definitions
 * cost too much: Theo1 at long factors, and the overlapping Allan
 * variance at every factor at once (--taus all).
 *
 * Theo1's double sum (NIST SP 1065 eq. 33) at long averaging factors in
 * O(np log^2 np) instead of O((np - m) m / 2).
 *
 * With h = m / 2, w_d = 1 / (h - d), S_i = x_i + x_{i+m} and the centre
 * c = i + h, the sum over i < np - m and d < h of
 *     w_d (S_i - x_{c-d} - x_{c+d})^2
 * expands into four parts, each a sum of products of two phase values:
 *   A = W sum_i S_i^2                         (W = sum_d w_d)
 *   B = sum_i S_i sum_j k_j x_{c+j}           (k_j = w_|j|, k_0 = 2 w_0)
 *   C = sum_c sum_j k_j x_{c+j}^2             (prefix sums of x^2)
 *   E = sum_c sum_d w_d x_{c-d} x_{c+d}
 * and the sum is A - 2B + C + 2E.  B is a cross-correlation of S with x
 * at the lags 1 .. m - 1 (one transform of the record); E is the weighted
 * autocorrelation of the whole record (computed once for every m) less
 * the pairs whose centre lies within h of either end.  Those pairs, a
 * triangle of the product matrix below an anti-diagonal, are a square
 * block (a cross-correlation) and two triangles half the size, down to
 * 64 points where they are summed directly: O(h log^2 h).
 *
 * Why by hand: no library computes Theo1 other than by its definition
 * (allantools and Stable32 both sum the (np - m) m / 2 terms); FFTW does
 * every transform.
 *
 * Rounding: the expansion adds terms of the size of the phase's squares,
 * where the definition adds squares of its differences.  The phase is
 * first freed of its least-squares line (Theo1 is blind to one) and
 * quadratic (which adds to every term's D a constant of its own, put
 * back exactly from prefix sums: on an integrated random walk this divides
 * the squares by about 18), and the
 * result comes with a bound of its rounding error; the caller uses the
 * definition where the bound exceeds a part in 10^8 of the sum (the bound
 * runs 10 to 100 times the error met in the tests).
 *
 * The overlapping Allan variance's sums V(m) = sum_{i < np - 2m}
 * (x_{i+2m} - 2 x_{i+m} + x_i)^2 for every m <= D at once: squares from
 * prefix sums, and the products from the record's autocorrelation R less
 * the pairs (t, t + m) with t < m (the head H) or t >= np - 2m (the head
 * of the reversed record):
 *     V(m) = squares - 8 R(m) + 4 H(m) + 4 Hrev(m) + 2 R(2m).
 * H(d) = sum_{a < d} x_a x_{a+d} for every d is a triangle of the (a, d)
 * plane: a rectangle (one cross-correlation) and two half triangles, down
 * to 64: O(np log^2 np) for the D = np / 2 factors the definition sums in
 * O(np^2 / 4).  The same rounding bound, and the definition where it
 * exceeds the caller's tolerance.
 */
#include "allan-internal.h"
#include "internal.h"

#include <fftw3.h>
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

/* triangles up to this side are summed directly */
#define TRI_DIRECT 64
/* records up to 2^22 phase points (the workspace is then 416 MiB) */
#define LOG2_MAX 22

/* FFTW's planner is not thread-safe */
static pthread_mutex_t plan_lock = PTHREAD_MUTEX_INITIALIZER;

struct ssc_xf_ws {
	size_t np, M;        /* M: the power of two >= np */
	double *z;           /* the phase less its line, np */
	double *p2;          /* prefix sums of z^2, np + 1 */
	double *R;           /* R[d] = sum_t z_t z_{t+d}, d < np */
	double *rev;         /* the reversed record, np */
	double *H, *Hr;      /* the heads of the record and reversed, np/2+1 */
	double *buf;         /* 2 sets of 2 complex arrays of M, then z.. */
	double *Z;           /* prefix sums of z, np + 1 */
	double zerr;         /* bound of the rounding of each z */
	double zabs;         /* sum |z| */
	double qc;           /* the quadratic removed: qc (i - (np-1)/2)^2 */
	int lmax;            /* log2 M */
};

/* one thread's transform arrays, M complex values each: the product
 * sums read from the real parts of a after xcorr() */
struct tbuf {
	fftw_complex *a, *b;
};

#define XC(t, j) ((t).a[j][0])

static struct tbuf tbuf_of(struct ssc_xf_ws *w, int k)
{
	/* each part a multiple of 8 doubles: every array 64-byte aligned */
	const size_t part = 2 * w->M + 8;
	double *base = w->buf + (size_t)k * 2 * part;
	struct tbuf t = { (fftw_complex *)(void *)base,
			  (fftw_complex *)(void *)(base + part) };

	return t;
}

static int log2_at_least(size_t n)
{
	int k = 0;

	while (((size_t)1 << k) < n)
		k++;
	return k;
}

/* the plans of every size are kept for the process, made once under a
 * lock (a slot, once set, is only read: a workspace reads the sizes its
 * own plan_all() made or found under the lock): complex transforms (FFTW plans them in a fifth of the time of
 * the real ones, which cost more to plan than to run here) */
static fftw_plan plan_fwd[LOG2_MAX + 2], plan_inv[LOG2_MAX + 2];

static int plan_all(struct ssc_xf_ws *w, int kmax)
{
	struct tbuf t = tbuf_of(w, 0);
	int rc = 0;

	pthread_mutex_lock(&plan_lock);
	for (int k = 1; k <= kmax && !rc; k++) {
		int n = 1 << k;

		if (!plan_fwd[k])
			plan_fwd[k] = fftw_plan_dft_1d(n, t.a, t.b, FFTW_FORWARD,
						       FFTW_ESTIMATE);
		if (!plan_inv[k])
			plan_inv[k] = fftw_plan_dft_1d(n, t.b, t.a, FFTW_BACKWARD,
						       FFTW_ESTIMATE);
		if (!plan_fwd[k] || !plan_inv[k])
			rc = -ENOMEM;
	}
	pthread_mutex_unlock(&plan_lock);
	return rc;
}

void ssc_xf_ws_free(struct ssc_xf_ws *w)
{
	if (!w)
		return;
	free(w->buf);
	free(w);
}

/* XC(t, j mod n) = sum_a u_a v_{a+j}, n = 2^k >= lu + lv - 1 (or >= the
 * reach of the lags read, see the callers): u and v packed into one
 * complex transform, split by its symmetry */
static void xcorr(struct tbuf t, int k, const double *u, size_t lu,
		  const double *v, size_t lv)
{
	const size_t n = (size_t)1 << k;
	const double s = 1.0 / (double)n, q = 0.25 * s;
	const bool self = v == u && lv == lu;

	for (size_t i = 0; i < n; i++) {
		t.a[i][0] = i < lu ? u[i] : 0;
		t.a[i][1] = !self && i < lv ? v[i] : 0;
	}
	fftw_execute_dft(plan_fwd[k], t.a, t.b);
	if (self) {
		for (size_t f = 0; f < n; f++) {
			double re = t.b[f][0], im = t.b[f][1];

			t.b[f][0] = (re * re + im * im) * s;
			t.b[f][1] = 0;
		}
	} else {
		/* U = (C_f + conj C_g) / 2, V = -i (C_f - conj C_g) / 2 with
		 * g = -f: the product conj(U) V at f, its conjugate at g */
		for (size_t f = 0; f <= n / 2; f++) {
			size_t g = (n - f) & (n - 1);
			double cr = t.b[f][0], ci = t.b[f][1];
			double dr = t.b[g][0], di = -t.b[g][1]; /* conj C_g */
			double ur = cr + dr, ui = ci + di;      /* 2U */
			double vr = ci - di, vi = dr - cr;      /* 2V = -i(C - D) */
			double pr = (ur * vr + ui * vi) * q;
			double pi = (ur * vi - ui * vr) * q;

			t.b[f][0] = pr;
			t.b[f][1] = pi;
			t.b[g][0] = pr;
			t.b[g][1] = -pi;
		}
	}
	fftw_execute_dft(plan_inv[k], t.b, t.a);
}

/* the weight of a pair at lag d: w_{d/2} for even d < 2h, else 0 */
static inline double pair_w(long d, size_t h)
{
	if (d < 0 || (d & 1) || (size_t)d / 2 >= h)
		return 0;
	return 1.0 / (double)(h - (size_t)d / 2);
}

/*
 * sum over a, b in [0, n) with a + b < n of f(D + b - a) u[A + a] u[B + b]
 * (D = B - A > 0: the b block lies after the a block)
 */
static double tri(struct tbuf t, const double *u, size_t A, size_t B,
		  size_t n, size_t h)
{
	const long D = (long)B - (long)A;

	if (n <= TRI_DIRECT) {
		double s = 0;

		for (size_t a = 0; a < n; a++) {
			double ps = 0;
			/* b of the parity that makes the lag even */
			size_t b0 = ((size_t)D + a) & 1;

			for (size_t b = b0; b < n - a; b += 2)
				ps += pair_w(D + (long)b - (long)a, h) * u[B + b];
			s += ps * u[A + a];
		}
		return s;
	}
	{
		const size_t p = n / 2, q = n - p;
		const int k = log2_at_least(p + q - 1);
		const size_t nn = (size_t)1 << k;
		double s = 0;

		/* block a < p, b < q: lags b - a in (-p, q) */
		xcorr(t, k, u + A, p, u + B, q);
		for (long j = -(long)p + 1; j < (long)q; j++) {
			double f = pair_w(D + j, h);

			if (f != 0)
				s += f * XC(t, j < 0 ? nn - (size_t)(-j) : (size_t)j);
		}
		s += tri(t, u, A, B + q, p, h);
		s += tri(t, u, A + p, B, q, h);
		return s;
	}
}

/* the pairs a <= b of u with centre (a + b) / 2 < h, weighted by lag */
static double head(struct tbuf t, const double *u, size_t h)
{
	const int k = log2_at_least(2 * h - 1);
	double s = 0;

	/* both in [0, h): every lag d < h */
	xcorr(t, k, u, h, u, h);
	for (size_t d = 0; d < h; d += 2)
		s += pair_w((long)d, h) * XC(t, d);
	/* a in [0, h), b in [h, 2h), a + (b - h) < h */
	return s + tri(t, u, 0, h, h, h);
}

struct ssc_xf_ws *ssc_xf_ws_new(const double *x, size_t np)
{
	struct ssc_xf_ws *w;
	double tm = 0.5 * (double)(np - 1), sxx = 0, sxt = 0, sx = 0, slope,
	       mean;
	struct ssc_ksum k2 = { 0, 0 };
	size_t part;

	if (np < 16 || log2_at_least(np) > LOG2_MAX)
		return NULL;
	w = calloc(1, sizeof(*w));
	if (!w)
		return NULL;
	w->np = np;
	w->lmax = log2_at_least(np);
	w->M = (size_t)1 << w->lmax;
	part = 2 * w->M + 8;
	/* one block (its pages faulted 2 MiB at a time): two sets of two
	 * complex arrays of M (for the record's autocorrelation, one set of
	 * two of 2M), then the arrays of the phase */
	w->buf = ssc_alloc_huge(4 * part + 6 * np + 4, sizeof(double));
	if (!w->buf || plan_all(w, w->lmax + 1) < 0) {
		ssc_xf_ws_free(w);
		return NULL;
	}
	w->z = w->buf + 4 * part;
	w->p2 = w->z + np;
	w->R = w->p2 + np + 1;
	w->rev = w->R + np;
	w->H = w->rev + np;
	w->Hr = w->H + np / 2 + 1;
	w->Z = w->Hr + np / 2 + 1;
	/* least-squares line and quadratic, centred: 1, t, t^2 - mean(t^2)
	 * (t = i - tm) are orthogonal on the record's points */
	for (size_t i = 0; i < np; i++)
		sx += x[i];
	mean = sx / (double)np;
	for (size_t i = 0; i < np; i++) {
		double dt = (double)i - tm;

		sxt += dt * (x[i] - mean);
		sxx += dt * dt;
	}
	slope = sxt / sxx;
	{
		/* mean of t^2 over the points: (np^2 - 1) / 12 */
		const double q0 = ((double)np * (double)np - 1) / 12;
		double sq = 0, sqq = 0;

		for (size_t i = 0; i < np; i++) {
			double dt = (double)i - tm, g = dt * dt - q0;

			sq += g * (x[i] - mean);
			sqq += g * g;
		}
		w->qc = sqq > 0 ? sq / sqq : 0;
		w->p2[0] = 0;
		w->Z[0] = 0;
		{
			double dmax = 0, zm = 0;

			for (size_t i = 0; i < np; i++) {
				double dt = (double)i - tm;
				double z = ((x[i] - mean) - slope * dt) -
					   w->qc * (dt * dt - q0);

				w->z[i] = z;
				dmax = fmax(dmax, fabs(x[i] - mean));
				zm = fmax(zm, fabs(z));
			}
			/* x - mean, the products and the subtractions each
			 * round once: at most twice these */
			w->zerr = 2 * DBL_EPSILON *
				  (dmax + fabs(slope) * tm +
				   fabs(w->qc) * tm * tm + zm);
		}
	}
	{
		struct ssc_ksum k1 = { 0, 0 };

		w->zabs = 0;
		for (size_t i = 0; i < np; i++) {
			double z = w->z[i];

			ssc_ksum_add(&k2, z * z);
			w->p2[i + 1] = ssc_ksum_value(&k2);
			ssc_ksum_add(&k1, z);
			w->Z[i + 1] = ssc_ksum_value(&k1);
			w->zabs += fabs(z);
		}
	}
	/* the autocorrelation at every lag: a transform of 2M >= 2 np - 1 */
	{
		struct tbuf t = { (fftw_complex *)(void *)w->buf,
				  (fftw_complex *)(void *)(w->buf + 2 * part) };

		xcorr(t, w->lmax + 1, w->z, np, w->z, np);
		for (size_t d = 0; d < np; d++)
			w->R[d] = XC(t, d);
	}
	return w;
}

bool ssc_theo_fast_pays(size_t np, size_t m)
{
	/* measured on two threads: the definition's (np - m) m / 2 terms at
	 * 6.10^9 a second; the transforms 1.2 ns np log2(np) (10^5: 1.2 ms
	 * against 30 ms at m = 4096; 10^6: 18 ms against 214 ms) */
	double direct, fast;

	if (m < 2 * TRI_DIRECT || m >= np)
		return false;
	direct = (double)(np - m) * (double)(m / 2) / 6e9;
	fast = 1.2e-9 * (double)np * log2((double)np);
	return direct > fast;
}

/* k_j of B and C at j = h + dj, dj in (-h, h): w_|dj|, twice w_0 */
static inline double kern(size_t j, size_t h)
{
	size_t a = j > h ? j - h : h - j;

	return (a == 0 ? 2.0 : 1.0) / (double)(h - a);
}

double ssc_theo1_sum_fast(struct ssc_xf_ws *w, size_t m, unsigned T,
			  double *err)
{
	const size_t np = w->np, h = m / 2, ni = np - m;
	const double *z = w->z;
	double A = 0, B = 0, C = 0, E = 0, W = 0, hd = 0, tl = 0, s2 = 0;

	if (m < 2 * TRI_DIRECT || (m & 1) || m >= np)
		return NAN;
	(void)T;
SSC_OMP(omp parallel sections num_threads(T > 1 ? 2 : 1))
	{
SSC_OMP(omp section)
		{
			struct tbuf t = tbuf_of(w, 0);
			double *S = (double *)(void *)t.b;

			hd = head(t, z, h);
			/* B: G(l) = sum_{i < ni} S_i z_{i+l} at l in [1, m): no
			 * lag read wraps on a transform of >= np points (S in
			 * b's storage: packed into a before b is written) */
			for (size_t i = 0; i < ni; i++) {
				S[i] = z[i] + z[i + m];
				s2 += S[i] * S[i];
			}
			xcorr(t, w->lmax, S, ni, z, np);
			for (size_t j = 1; j < m; j++)
				B += kern(j, h) * XC(t, j);
		}
SSC_OMP(omp section)
		{
			struct tbuf t = tbuf_of(w, 1);

			for (size_t i = 0; i < 2 * h; i++)
				w->rev[i] = z[np - 1 - i];
			tl = head(t, w->rev, h);
		}
	}
	/* C: sum_j k_j sum_{c in [h, np - h)} z_{c+j}^2 */
	for (size_t j = 1; j < m; j++)
		C += kern(j, h) * (w->p2[np - m + j] - w->p2[j]);
	{
		/* the quadratic removed: each term's D grows by qc g_d,
		 * g_d = 2h^2 - 2d^2, whatever i: the cross sum needs
		 * sum_i D_z(i, d) from the prefix sums */
		const double *Z = w->Z;
		double cross = 0, sqr = 0, gw = 0, sum, z2, lg;

		/* one pass over d: W, E and the corrections' sums */
		for (size_t d = 0; d < h; d++) {
			double g = 2.0 * ((double)h * (double)h - (double)d * (double)d);
			double wd = 1.0 / (double)(h - d);
			double t1 = Z[ni] + (Z[ni + m] - Z[m]) -
				    (Z[ni + h - d] - Z[h - d]) -
				    (Z[ni + h + d] - Z[h + d]);

			W += wd;
			E += w->R[2 * d] / (double)(h - d);
			cross += wd * g * t1;
			sqr += wd * g * g;
			gw += wd * g;
		}
		A = W * s2;
		E -= hd + tl;
		sum = A - 2 * B + C + 2 * E;
		z2 = w->p2[np];
		lg = (double)(w->lmax + 1);
		cross *= 2 * w->qc;
		sqr *= w->qc * w->qc * (double)ni;
		/* transforms: eps log2 n per product sum, every part bounded
		 * by W (sum S^2 + 4 sum z^2 + 2 |S| |z|); the line: each of
		 * the four values of a term D off by zerr at most, so the
		 * sum by 8 zerr sum w |D| + 16 zerr^2 ni W, and
		 * sum w |D| <= sqrt(ni W sum) */
		double mag = W * (s2 + 4 * z2 + 2 * sqrt(s2 * z2));
		double e = 32 * DBL_EPSILON * lg * mag +
			   16 * w->zerr * w->zerr * (double)ni * W;

		/* the corrections: each prefix difference off by 4 eps
		 * sum|z| at most (8 of them in t1), and their own rounding */
		e += 2 * fabs(w->qc) * gw * 32 * DBL_EPSILON * w->zabs +
		     8 * DBL_EPSILON * (fabs(cross) + sqr);
		sum += cross + sqr;
		if (sum > 0)
			e += 8 * w->zerr * sqrt((double)ni * W * sum);
		*err = e;
		return sum;
	}
}

/* ------------------------------------------------------------------ */
/* The overlapping Allan variance at every factor                      */
/* ------------------------------------------------------------------ */

/* H[d] += sum over a in [a0, a1), d in [d0, d1) of u_a u_{a+d}, a < d
 * everywhere (a1 <= d0) */
static void heads_rect(struct tbuf t, const double *u, size_t a0, size_t a1,
		       size_t d0, size_t d1, double *H)
{
	const size_t la = a1 - a0, ld = d1 - d0, lv = la + ld - 1;
	const int k = log2_at_least(lv);

	/* r[j] = sum_a u_{a0+a} u_{a0+d0+a+j}, j < ld: no lag read wraps */
	xcorr(t, k, u + a0, la, u + a0 + d0, lv);
	for (size_t j = 0; j < ld; j++)
		H[d0 + j] += XC(t, j);
}

/* the triangle a in [L0, L0 + L), d in [L0, L0 + L), a < d */
static void heads_tri(struct tbuf t, const double *u, size_t L0, size_t L,
		      double *H)
{
	if (L <= TRI_DIRECT) {
		for (size_t d = L0 + 1; d < L0 + L; d++) {
			double s = 0;

			for (size_t a = L0; a < d; a++)
				s += u[a] * u[a + d];
			H[d] += s;
		}
		return;
	}
	{
		const size_t h = L / 2, M = L0 + h;

		heads_rect(t, u, L0, M, M, L0 + L, H);
		heads_tri(t, u, L0, h, H);
		heads_tri(t, u, M, L - h, H);
	}
}

bool ssc_oadev_fast_pays(size_t np, const size_t *m, size_t n)
{
	double direct = 0, fast;

	if (np < 1024 || log2_at_least(np) > LOG2_MAX)
		return false;
	for (size_t j = 0; j < n; j++)
		if (2 * m[j] < np)
			direct += (double)(np - 2 * m[j]);
	/* 10^10 terms a second against the transforms' ~ 0.3 ns np log2^2 */
	fast = 3e-10 * (double)np * log2((double)np) * log2((double)np);
	return direct / 1e10 > fast;
}

int ssc_oadev_sums_fast(struct ssc_xf_ws *w, size_t D, unsigned T,
			double *V, double *err)
{
	size_t np;
	const double *z, *p2;
	double lg, z2;

	if (!w || D == 0 || 2 * D >= w->np)
		return -EINVAL;
	np = w->np;
	z = w->z;
	p2 = w->p2;
	lg = (double)(w->lmax + 1);
	z2 = p2[np];
	memset(w->H, 0, (D + 1) * sizeof(double));
	memset(w->Hr, 0, (D + 1) * sizeof(double));
	(void)T;
SSC_OMP(omp parallel sections num_threads(T > 1 ? 2 : 1))
	{
SSC_OMP(omp section)
		heads_tri(tbuf_of(w, 0), z, 0, D + 1, w->H);
SSC_OMP(omp section)
		{
			for (size_t i = 0; i < np; i++)
				w->rev[i] = z[np - 1 - i];
			heads_tri(tbuf_of(w, 1), w->rev, 0, D + 1, w->Hr);
		}
	}
	for (size_t m = 1; m <= D; m++) {
		const size_t n = np - 2 * m;
		double sq = (p2[np] - p2[2 * m]) + 4 * (p2[np - m] - p2[m]) + p2[n];
		double v = sq - 8 * w->R[m] + 4 * (w->H[m] + w->Hr[m]) +
			   2 * w->R[2 * m];
		/* the quadratic removed adds qc 2m^2 to every D: the cross
		 * sum from the prefix sums of z (5 differences) */
		const double *Z = w->Z;
		double g = 2.0 * (double)m * (double)m;
		double s1 = (Z[n + 2 * m] - Z[2 * m]) -
			    2 * (Z[n + m] - Z[m]) + Z[n];
		double cross = 2 * w->qc * g * s1;
		double sqr = w->qc * w->qc * g * g * (double)n;
		/* every part at most 6 sum z^2 (squares) or sum z^2 (each
		 * product sum): 24 sum z^2 in all, eps log2 n each; the
		 * line's rounding through sum |D| <= sqrt(n V); the
		 * corrections as for Theo1 */
		double e = 32 * DBL_EPSILON * lg * 24 * z2 +
			   16 * w->zerr * w->zerr * (double)n +
			   2 * fabs(w->qc) * g * 24 * DBL_EPSILON * w->zabs +
			   8 * DBL_EPSILON * (fabs(cross) + sqr);

		v += cross + sqr;

		if (v > 0)
			e += 8 * w->zerr * sqrt((double)n * v);
		V[m] = v;
		err[m] = e;
	}
	return 0;
}
