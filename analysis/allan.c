/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Allan-family deviations (ADEV, OADEV, MDEV, TDEV, HDEV, OHDEV, TOTDEV)
 * as defined in NIST SP 1065 (W. J. Riley, "Handbook of Frequency Stability
 * Analysis", 2008) sections 5.2.2-5.2.11 and IEEE Std 1139-2008, computed
 * on phase data: a rate record is integrated to phase after removing its
 * mean (compensated sums: a bias 1e6 times the noise loses no digit that
 * matters), an angle record is used as phase after removing its linear
 * trend.  Second and third differences are formed as differences of first
 * differences, which are exact for neighbouring phase values.
 *
 * Speed.  Every overlapping term costs a few operations, so OADEV at one
 * tau is O(n) and the work is memory traffic.  The engine therefore
 *  - builds the phase in one parallel pass (chunk sums, then compensated
 *    running sums from each chunk's exact base);
 *  - fuses all "short" taus into that pass: each thread keeps a sliding
 *    window of contiguous phase in cache and runs every short-tau kernel
 *    on it before moving on (one pass over memory for all of them);
 *  - stores the phase "tiled": x[k] at row k mod S, column k / S (S a
 *    power of two chosen so that a row fits in L2).  For m a multiple of S
 *    the three points x[i], x[i+m], x[i+2m] lie in the same row, so every
 *    "long" tau is computed row by row from cache instead of streaming the
 *    whole record three times per tau.  The dense grid is built so that its
 *    long taus are such multiples;
 *  - sums with explicit SIMD vectors (GCC vector extensions, cloned for
 *    AVX-512/AVX2/baseline where available) and compensated block sums.
 *  Untiled OADEV without gaps or strides (every all-tau grid, whose taus
 *  the tiles cannot serve, and records too short for tiles) sums groups of
 *  neighbouring taus together over L1-sized stretches of the contiguous
 *  phase, each tau's vector lanes kept between stretches, so that each
 *  tau's sum is the per-tau kernel's to the last bit.
 * Parallelism is OpenMP; without it the same code runs serially.  The
 * work is cut by the data, never by the team (see set_chunks), so every
 * result is the same to the bit on any number of threads.
 * Non-overlapping, modified, total and strided estimators, and records
 * with gaps, use the contiguous layout and per-tau kernels.
 *
 * Gaps (NaN samples).  The estimator is the complete-terms one: a term
 * (an Allan, Hadamard or modified difference) whose span holds a NaN is
 * left out and the variance is normalised by the number of complete terms,
 * so that every term used is an exact difference of the process and the
 * estimate stays unbiased whatever the gap pattern (I. Sesia and P.
 * Tavella, "Estimating the Allan variance in the presence of long periods
 * of missing data and outliers", Metrologia 45 (2008) S134; the handling
 * of gaps in phase data of Stable32).  No sample is filled in or
 * interpolated.  The EDF is that of a gap-free record with the same number
 * of complete terms: terms split by gaps are less correlated than as many
 * neighbouring ones, so the intervals err on the wide side.  A tau with no
 * complete term is left out of sscope_allan_analyze()'s result with a
 * note saying so (never a NaN deviation), and a record in which no tau has
 * one is refused.  TOTDEV, whose reflected extension has no meaning across
 * a gap, refuses gaps.
 */
#include "allan-internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif
#if defined(__SSE2__) && defined(__x86_64__)
#include <immintrin.h> /* streaming stores; the AVX-512 tile transpose */

#include "sscope-allan.h"
#include "sscope-noise.h"
#include "sscope-quantity.h"
#define SSC_NT_STORES 1
#endif

/* ------------------------------------------------------------------ */
/* SIMD helpers                                                        */
/* ------------------------------------------------------------------ */

/* not under ThreadSanitizer, whose runtime is not up when the loader runs
 * the clones' resolvers */
#define SSC_CLONES SSC_TARGET_CLONES("avx512f", "avx2", "default")

/* GCC vector extensions (__builtin_shuffle is GCC's; clang builds, such
 * as the fuzz harnesses', take the scalar path) */
#if defined(__GNUC__) && !defined(__clang__)
#define SSC_VEC 1
typedef double ssc_v8 __attribute__((vector_size(64)));
#define V8LOAD(v, p) memcpy(&(v), (p), sizeof(ssc_v8))
typedef double ssc_v4 __attribute__((vector_size(32)));
#define V4LOAD(v, p) memcpy(&(v), (p), sizeof(ssc_v4))
#endif

/* Kernels on 64-byte vectors, chosen at run time where the CPU has
 * AVX-512 (the clones above compute on 32-byte halves even there).  They
 * keep the lanes and final additions of the 32-byte kernels, so every
 * sum is the same to the bit on every CPU (with -ffp-contract=off: no
 * fused multiply-adds in any of them). */
#if defined(SSC_VEC) && defined(__x86_64__) && defined(__has_attribute)
#if __has_attribute(target)
#define SSC_K512 __attribute__((target("avx512f")))
#endif
#endif

static bool narrow_only; /* ssc_allan_force_narrow() */
static bool definition_only; /* ssc_allan_force_definition() */

void ssc_allan_force_definition(bool on)
{
	definition_only = on;
}

void ssc_allan_force_narrow(bool on)
{
	narrow_only = on;
}

/* whether the 64-byte kernels run here */
static bool have_wide(void)
{
#ifdef SSC_K512
	return !narrow_only && __builtin_cpu_supports("avx512f");
#else
	return false;
#endif
}

/* Terms summed per kernel call before the partial is added to a
 * compensated accumulator: bounds the rounding of the lanes. */
#define KBLOCK 8192

/*
 * sum_{i<n} (x[i+2m] - 2 x[i+m] + x[i])^2, as ((c - b) - (b - a))^2:
 * sixteen lanes (term i in lane i mod 16), reduced in a fixed order, the
 * terms after the last whole sixteen in order.  Every kernel below that
 * sums these terms (64-byte, grouped, paired) keeps these lanes and this
 * reduction, so all give the same doubles.
 */
/* lanes[r] += d_i^2 over i0 <= i < i1, i = r mod 16 (i0, i1 multiples of
 * 16); without vectors, lanes[0] += d_i^2 in order */
SSC_CLONES static void k2_abc(const double *a, const double *b,
			      const double *c, size_t i0, size_t i1,
			      double *lanes)
{
	size_t i = i0;

#ifdef SSC_VEC
	ssc_v4 s0, s0h, s1, s1h;

	V4LOAD(s0, lanes);
	V4LOAD(s0h, lanes + 4);
	V4LOAD(s1, lanes + 8);
	V4LOAD(s1h, lanes + 12);
	for (; i < i1; i += 16) {
		ssc_v4 a0, b0, c0, a1, b1, c1, a2, b2, c2, a3, b3, c3, d;

		V4LOAD(a0, a + i);
		V4LOAD(b0, b + i);
		V4LOAD(c0, c + i);
		V4LOAD(a1, a + i + 4);
		V4LOAD(b1, b + i + 4);
		V4LOAD(c1, c + i + 4);
		V4LOAD(a2, a + i + 8);
		V4LOAD(b2, b + i + 8);
		V4LOAD(c2, c + i + 8);
		V4LOAD(a3, a + i + 12);
		V4LOAD(b3, b + i + 12);
		V4LOAD(c3, c + i + 12);
		d = (c0 - b0) - (b0 - a0);
		s0 += d * d;
		d = (c1 - b1) - (b1 - a1);
		s0h += d * d;
		d = (c2 - b2) - (b2 - a2);
		s1 += d * d;
		d = (c3 - b3) - (b3 - a3);
		s1h += d * d;
	}
	memcpy(lanes, &s0, sizeof(s0));
	memcpy(lanes + 4, &s0h, sizeof(s0h));
	memcpy(lanes + 8, &s1, sizeof(s1));
	memcpy(lanes + 12, &s1h, sizeof(s1h));
#else
	double s = lanes[0];

	for (; i < i1; i++) {
		double d = (c[i] - b[i]) - (b[i] - a[i]);

		s += d * d;
	}
	lanes[0] = s;
#endif
}

static void k2_lanes(const double *x, size_t m, size_t i0, size_t i1,
		     double *lanes)
{
	k2_abc(x, x + m, x + 2 * m, i0, i1, lanes);
}

#ifdef SSC_K512
/* the same with 8-lane registers (the lanes are k2's: 0..7, 8..15) */
SSC_K512 static void k2_abc512(const double *a, const double *b,
			       const double *c, size_t i0, size_t i1,
			       double *lanes)
{
	ssc_v8 s0, s1;

	V8LOAD(s0, lanes);
	V8LOAD(s1, lanes + 8);
	for (size_t i = i0; i < i1; i += 16) {
		ssc_v8 a0, b0, c0, a1, b1, c1, d;

		V8LOAD(a0, a + i);
		V8LOAD(b0, b + i);
		V8LOAD(c0, c + i);
		V8LOAD(a1, a + i + 8);
		V8LOAD(b1, b + i + 8);
		V8LOAD(c1, c + i + 8);
		d = (c0 - b0) - (b0 - a0);
		s0 += d * d;
		d = (c1 - b1) - (b1 - a1);
		s1 += d * d;
	}
	memcpy(lanes, &s0, sizeof(s0));
	memcpy(lanes + 8, &s1, sizeof(s1));
}

SSC_K512 static void k2_lanes512(const double *x, size_t m, size_t i0,
				 size_t i1, double *lanes)
{
	k2_abc512(x, x + m, x + 2 * m, i0, i1, lanes);
}
#endif

#ifdef SSC_K512
/* k2_abc512 for eight taus at once over the same terms, b[q] and c[q]
 * the points m and 2 m after x (lanes[16 q ..] those of tau q): x[i] is
 * loaded once for the eight, and each lane adds its terms in the same
 * order as k2_abc512's */
SSC_K512 static void k2_lanes512_x8(const double *x,
				    const double *const b[8],
				    const double *const c[8], size_t i0,
				    size_t i1, double *lanes)
{
	ssc_v8 s[8][2];

	for (int q = 0; q < 8; q++) {
		V8LOAD(s[q][0], lanes + 16 * q);
		V8LOAD(s[q][1], lanes + 16 * q + 8);
	}
	for (size_t i = i0; i < i1; i += 16) {
		ssc_v8 a0, a1;

		V8LOAD(a0, x + i);
		V8LOAD(a1, x + i + 8);
		for (int q = 0; q < 8; q++) {
			ssc_v8 b0, c0, b1, c1, d;

			V8LOAD(b0, b[q] + i);
			V8LOAD(c0, c[q] + i);
			V8LOAD(b1, b[q] + i + 8);
			V8LOAD(c1, c[q] + i + 8);
			d = (c0 - b0) - (b0 - a0);
			s[q][0] += d * d;
			d = (c1 - b1) - (b1 - a1);
			s[q][1] += d * d;
		}
	}
	for (int q = 0; q < 8; q++) {
		memcpy(lanes + 16 * q, &s[q][0], sizeof(s[q][0]));
		memcpy(lanes + 16 * q + 8, &s[q][1], sizeof(s[q][1]));
	}
}
#endif

/* the lane reduction of every kernel: lanes r and r + 8 first, then
 * pairs (without vectors the one lane) */
static double lanes_sum(const double *L)
{
#ifdef SSC_VEC
	double s0[4], s0h[4];

	for (int r = 0; r < 4; r++) {
		s0[r] = L[r] + L[r + 8];
		s0h[r] = L[r + 4] + L[r + 12];
	}
	return ((s0[0] + s0[1]) + (s0[2] + s0[3])) +
	       ((s0h[0] + s0h[1]) + (s0h[2] + s0h[3]));
#else
	return L[0];
#endif
}

/* k2's end of a block from its lanes: the lane reduction, then the
 * terms [i, n) in order */
static double k2_finish(const double *x, size_t m, size_t i, size_t n,
			const double *L)
{
	const double *a = x, *b = x + m, *c = x + 2 * m;
	double s = lanes_sum(L);

	for (; i < n; i++) {
		double d = (c[i] - b[i]) - (b[i] - a[i]);

		s += d * d;
	}
	return s;
}

static double k2(const double *x, size_t m, size_t n)
{
	double lanes[16] = { 0 };
	size_t v = n;

#ifdef SSC_VEC
	v = n & ~(size_t)15;
#endif
	k2_lanes(x, m, 0, v, lanes);
	return k2_finish(x, m, v, n, lanes);
}

/*
 * sum_{i<n} (x[i+3m] - 3 x[i+2m] + 3 x[i+m] - x[i])^2, as second
 * differences of first differences, in k2's lanes and reduction.
 */
#define K3TERM(T, LOAD, acc, o)                                                \
	do {                                                                   \
		T a0, b0, c0, e0, d, f, g;                                     \
                                                                               \
		LOAD(a0, a + i + (o));                                         \
		LOAD(b0, b + i + (o));                                         \
		LOAD(c0, c + i + (o));                                         \
		LOAD(e0, e + i + (o));                                         \
		f = b0 - a0;                                                   \
		g = c0 - b0;                                                   \
		d = ((e0 - c0) - g) - (g - f);                                 \
		acc += d * d;                                                  \
	} while (0)

/* lanes[r] += d_i^2 over i0 <= i < i1 as k2_lanes */
SSC_CLONES static void k3_lanes(const double *x, size_t m, size_t i0,
				size_t i1, double *lanes)
{
	const double *a = x, *b = x + m, *c = x + 2 * m, *e = x + 3 * m;
	size_t i = i0;

#ifdef SSC_VEC
	ssc_v4 s0, s0h, s1, s1h;

	V4LOAD(s0, lanes);
	V4LOAD(s0h, lanes + 4);
	V4LOAD(s1, lanes + 8);
	V4LOAD(s1h, lanes + 12);
	for (; i < i1; i += 16) {
		K3TERM(ssc_v4, V4LOAD, s0, 0);
		K3TERM(ssc_v4, V4LOAD, s0h, 4);
		K3TERM(ssc_v4, V4LOAD, s1, 8);
		K3TERM(ssc_v4, V4LOAD, s1h, 12);
	}
	memcpy(lanes, &s0, sizeof(s0));
	memcpy(lanes + 4, &s0h, sizeof(s0h));
	memcpy(lanes + 8, &s1, sizeof(s1));
	memcpy(lanes + 12, &s1h, sizeof(s1h));
#else
	double s = lanes[0];

	for (; i < i1; i++) {
		double f = b[i] - a[i], g = c[i] - b[i];
		double d = ((e[i] - c[i]) - g) - (g - f);

		s += d * d;
	}
	lanes[0] = s;
#endif
}

#ifdef SSC_K512
/* the same with 8-lane registers */
SSC_K512 static void k3_lanes512(const double *x, size_t m, size_t i0,
				 size_t i1, double *lanes)
{
	const double *a = x, *b = x + m, *c = x + 2 * m, *e = x + 3 * m;
	ssc_v8 s0, s1;

	V8LOAD(s0, lanes);
	V8LOAD(s1, lanes + 8);
	for (size_t i = i0; i < i1; i += 16) {
		K3TERM(ssc_v8, V8LOAD, s0, 0);
		K3TERM(ssc_v8, V8LOAD, s1, 8);
	}
	memcpy(lanes, &s0, sizeof(s0));
	memcpy(lanes + 8, &s1, sizeof(s1));
}
#endif
#undef K3TERM

/* k3's end of a block from its lanes, as k2_finish */
static double k3_finish(const double *x, size_t m, size_t i, size_t n,
			const double *L)
{
	const double *a = x, *b = x + m, *c = x + 2 * m, *e = x + 3 * m;
	double s = lanes_sum(L);

	for (; i < n; i++) {
		double f = b[i] - a[i], g = c[i] - b[i];
		double d = ((e[i] - c[i]) - g) - (g - f);

		s += d * d;
	}
	return s;
}

static double k3(const double *x, size_t m, size_t n)
{
	double lanes[16] = { 0 };
	size_t v = n;

#ifdef SSC_VEC
	v = n & ~(size_t)15;
#endif
	k3_lanes(x, m, 0, v, lanes);
	return k3_finish(x, m, v, n, lanes);
}

#ifdef SSC_K512
/*
 * k2 and k3 on 64-byte vectors where AVX-512 is available (the clones
 * above use 32-byte halves everywhere): half the loads and operations.
 * Lane for lane the accumulators of k2 / k3 (the two halves of each
 * eight-lane accumulator side by side) and the same final additions:
 * the same sums to the bit.
 */
SSC_K512 static double k2_512(const double *x, size_t m, size_t n)
{
	double lanes[16] = { 0 };
	size_t v = n & ~(size_t)15;

	k2_lanes512(x, m, 0, v, lanes);
	return k2_finish(x, m, v, n, lanes);
}

SSC_K512 static double k3_512(const double *x, size_t m, size_t n)
{
	double lanes[16] = { 0 };
	size_t v = n & ~(size_t)15;

	k3_lanes512(x, m, 0, v, lanes);
	return k3_finish(x, m, v, n, lanes);
}

/*
 * k2_512 for two lags at once on the same points: the shared x[i] loaded
 * once, and four chains of additions instead of two (one pair of chains
 * bounded the single kernel on points in L1).  Each sum is k2_512's.
 */
SSC_K512 static void k2x2_512(const double *x, size_t m, size_t mb, size_t n,
			      double *r, double *rb)
{
	const double *a = x, *b = x + m, *c = x + 2 * m;
	const double *e = x + mb, *f = x + 2 * mb;
	ssc_v8 s0 = { 0 }, s1 = { 0 }, t0 = { 0 }, t1 = { 0 };
	double s, t;
	size_t i = 0;

	for (; i + 16 <= n; i += 16) {
		ssc_v8 a0, b0, c0, a1, b1, c1, e0, f0, e1, f1, d;

		V8LOAD(a0, a + i);
		V8LOAD(a1, a + i + 8);
		V8LOAD(b0, b + i);
		V8LOAD(c0, c + i);
		V8LOAD(b1, b + i + 8);
		V8LOAD(c1, c + i + 8);
		V8LOAD(e0, e + i);
		V8LOAD(f0, f + i);
		V8LOAD(e1, e + i + 8);
		V8LOAD(f1, f + i + 8);
		d = (c0 - b0) - (b0 - a0);
		s0 += d * d;
		d = (c1 - b1) - (b1 - a1);
		s1 += d * d;
		d = (f0 - e0) - (e0 - a0);
		t0 += d * d;
		d = (f1 - e1) - (e1 - a1);
		t1 += d * d;
	}
	s0 += s1;
	t0 += t1;
	s = ((s0[0] + s0[1]) + (s0[2] + s0[3])) +
	    ((s0[4] + s0[5]) + (s0[6] + s0[7]));
	t = ((t0[0] + t0[1]) + (t0[2] + t0[3])) +
	    ((t0[4] + t0[5]) + (t0[6] + t0[7]));
	for (size_t k = i; k < n; k++) {
		double d = (c[k] - b[k]) - (b[k] - a[k]);

		s += d * d;
	}
	for (size_t k = i; k < n; k++) {
		double d = (f[k] - e[k]) - (e[k] - a[k]);

		t += d * d;
	}
	*r = s;
	*rb = t;
}
#endif

static void k2_pair(const double *x, size_t m, size_t mb, size_t n, double *r,
		    double *rb)
{
#ifdef SSC_K512
	k2x2_512(x, m, mb, n, r, rb);
#else
	*r = k2(x, m, n);
	*rb = k2(x, mb, n);
#endif
}

static double kd(int d, const double *x, size_t m, size_t n)
{
#ifdef SSC_K512
	if (have_wide())
		return d == 2 ? k2_512(x, m, n) : k3_512(x, m, n);
#endif
	return d == 2 ? k2(x, m, n) : k3(x, m, n);
}

/* kd over n terms in blocks, compensated across blocks */
static void kd_total(int d, const double *x, size_t m, size_t n,
		     struct ssc_ksum *acc)
{
	for (size_t i = 0; i < n; i += KBLOCK) {
		size_t k = n - i < KBLOCK ? n - i : KBLOCK;

		ssc_ksum_add(acc, kd(d, x + i, m, k));
	}
}

/*
 * All-tau OADEV: k2's sums for a group of neighbouring taus at once, the
 * record walked in tiles small enough for L1 (x[i], x[i+m], x[i+2m] of
 * every tau of the group), each tau's sixteen lanes kept between tiles.
 * Every lane adds the same terms in the same order as k2 does, so the
 * sums are k2's (kd_total's) to the last bit; the three streams come from
 * L1 instead of L2 for every tau.
 */
#define GRP_TAUS 64   /* taus per group */
#define SHIFTED_MAX_NP ((size_t)1 << 20) /* phase points with shifted copies */
#define GRP_TILE 512  /* terms per tile: a multiple of 16 dividing KBLOCK */

/*
 * The phase shifted by 0..7 points, each copy starting on a cache line
 * (sh + r * stride holds x[r], x[r + 1], ...), so that x[i + m] and
 * x[i + 2m] are read with aligned loads for every m: a load split over
 * two cache lines costs about two, and the unaligned loads made the
 * all-tau kernel 1.7x slower than aligned ones (measured on its access
 * pattern).  The same doubles, so the same sums.  NULL: x itself.
 */
struct shifted {
	double *sh;
	size_t stride;
};

/* x + k, from the copy that puts it on a line when there is one */
static inline const double *shifted_at(const struct shifted *s,
				       const double *x, size_t k)
{
	return s->sh ? s->sh + (k & 7) * s->stride + (k & ~(size_t)7) : x + k;
}

/* kd_total(2, x, m[j], np - 2 m[j], &acc[j]) for the g increasing m[j] */
static void k2_group(const double *x, size_t np, const size_t *m, size_t g,
		     bool wide, const struct shifted *xs, struct ssc_ksum *acc)
{
	double lanes[GRP_TAUS * 16];
	const size_t nt0 = np - 2 * m[0];

	(void)wide; /* without the 64-byte kernels */
	for (size_t ib = 0; ib < nt0; ib += KBLOCK) {
		memset(lanes, 0, sizeof(lanes));
		for (size_t t0 = ib; t0 < ib + KBLOCK && t0 < nt0; t0 += GRP_TILE) {
			size_t j = 0;

#ifdef SSC_K512
			/* eight taus at a time over the terms they all have
			 * in this tile (x[i] loaded once for the eight: 6 %
			 * less time with the aligned copies), each one's rest
			 * alone */
			for (; wide && j + 8 <= g; j += 8) {
				size_t his[8], common = SIZE_MAX;
				bool all = true;

				for (int q = 0; q < 8 && all; q++) {
					size_t nt = np - 2 * m[j + q], nb, vend;

					if (ib >= nt) {
						all = false;
						break;
					}
					nb = nt - ib < KBLOCK ? nt - ib : KBLOCK;
					vend = ib + (nb & ~(size_t)15);
					his[q] = t0 + GRP_TILE < vend ? t0 + GRP_TILE : vend;
					if (his[q] < common)
						common = his[q];
				}
				if (!all)
					break; /* the loop below ends them */
				if (common > t0) {
					const double *b[8], *c[8];

					for (int q = 0; q < 8; q++) {
						b[q] = shifted_at(xs, x, m[j + q]);
						c[q] = shifted_at(xs, x, 2 * m[j + q]);
					}
					k2_lanes512_x8(x, b, c, t0, common,
						       lanes + 16 * j);
				} else {
					common = t0;
				}
				for (int q = 0; q < 8; q++)
					if (his[q] > common)
						k2_abc512(x, shifted_at(xs, x, m[j + q]),
							  shifted_at(xs, x, 2 * m[j + q]),
							  common, his[q],
							  lanes + 16 * (j + q));
			}
#endif
			for (; j < g; j++) {
				size_t nt = np - 2 * m[j], nb, vend, hi;

				if (ib >= nt)
					break; /* and for every larger m */
				nb = nt - ib < KBLOCK ? nt - ib : KBLOCK;
#ifdef SSC_VEC
				vend = ib + (nb & ~(size_t)15);
#else
				vend = ib + nb;
#endif
				hi = t0 + GRP_TILE < vend ? t0 + GRP_TILE : vend;
				if (t0 >= hi)
					continue;
#ifdef SSC_K512
				if (wide)
					k2_abc512(x, shifted_at(xs, x, m[j]),
						  shifted_at(xs, x, 2 * m[j]), t0,
						  hi, lanes + 16 * j);
				else
#endif
					k2_abc(x, shifted_at(xs, x, m[j]),
					       shifted_at(xs, x, 2 * m[j]), t0, hi,
					       lanes + 16 * j);
			}
		}
		for (size_t j = 0; j < g; j++) {
			size_t nt = np - 2 * m[j], nb, vend;

			if (ib >= nt)
				break;
			nb = nt - ib < KBLOCK ? nt - ib : KBLOCK;
#ifdef SSC_VEC
			vend = ib + (nb & ~(size_t)15);
#else
			vend = ib + nb;
#endif
			ssc_ksum_add(&acc[j], k2_finish(x + ib, m[j], vend - ib,
							nb, lanes + 16 * j));
		}
	}
}

/*
 * kd_total of second differences for lags m over n terms and mb over nb
 * terms of the same points: the blocks both have of the same length
 * through the pair kernel, each sum added to its accumulator in the same
 * order as kd_total's.
 */
static void kd_total_pair(const double *x, size_t m, size_t n, size_t mb,
			  size_t nb, struct ssc_ksum *acc, struct ssc_ksum *accb)
{
	for (size_t i = 0; i < n || i < nb; i += KBLOCK) {
		size_t k = i < n ? (n - i < KBLOCK ? n - i : KBLOCK) : 0;
		size_t kb = i < nb ? (nb - i < KBLOCK ? nb - i : KBLOCK) : 0;

		if (k && k == kb) {
			double sa, sb;

			k2_pair(x + i, m, mb, k, &sa, &sb);
			ssc_ksum_add(acc, sa);
			ssc_ksum_add(accb, sb);
			continue;
		}
		if (k)
			ssc_ksum_add(acc, kd(2, x + i, m, k));
		if (kb)
			ssc_ksum_add(accb, kd(2, x + i, mb, kb));
	}
}

/* one term of order d at i, lag m (differences of differences) */
static inline double term(int d, const double *x, size_t i, size_t m)
{
	double f = x[i + m] - x[i], g = x[i + 2 * m] - x[i + m];

	if (d == 2)
		return g - f;
	return ((x[i + 3 * m] - x[i + 2 * m]) - g) - (g - f);
}

/* ------------------------------------------------------------------ */
/* Names, grids, limits                                                */
/* ------------------------------------------------------------------ */

static const char *const dev_names[SSCOPE_ALLAN_DEV_COUNT_] = {
	"oadev", "adev", "mdev", "tdev", "hdev", "ohdev", "totdev",
	"mtotdev", "htotdev", "ttotdev", "theo1", "theobr", "theoh", "mtie",
	"tierms"
};

static const char *const dev_labels[SSCOPE_ALLAN_DEV_COUNT_] = {
	"OADEV", "ADEV", "MDEV", "TDEV", "HDEV", "OHDEV", "TOTDEV",
	"MTOTDEV", "HTOTDEV", "TTOTDEV", "Theo1", "TheoBR", "TheoH", "MTIE",
	"TIE rms"
};

const char *sscope_allan_dev_name(enum sscope_allan_dev dev)
{
	return (unsigned)dev < SSCOPE_ALLAN_DEV_COUNT_ ? dev_names[dev] : "";
}

const char *sscope_allan_dev_label(enum sscope_allan_dev dev)
{
	return (unsigned)dev < SSCOPE_ALLAN_DEV_COUNT_ ? dev_labels[dev] : "";
}

bool sscope_allan_dev_is_time(enum sscope_allan_dev dev)
{
	return dev == SSCOPE_ALLAN_DEV_TDEV || dev == SSCOPE_ALLAN_DEV_TTOTDEV ||
	       dev == SSCOPE_ALLAN_DEV_MTIE || dev == SSCOPE_ALLAN_DEV_TIERMS;
}

bool sscope_allan_dev_has_ci(enum sscope_allan_dev dev)
{
	return dev != SSCOPE_ALLAN_DEV_MTIE && dev != SSCOPE_ALLAN_DEV_TIERMS &&
	       (unsigned)dev < SSCOPE_ALLAN_DEV_COUNT_;
}

/* the deviations of allan-family.c */
static bool fam_dev(enum sscope_allan_dev dev)
{
	return dev >= SSCOPE_ALLAN_DEV_MTOTDEV;
}

static bool theo_dev(enum sscope_allan_dev dev)
{
	return dev == SSCOPE_ALLAN_DEV_THEO1 || dev == SSCOPE_ALLAN_DEV_THEOBR ||
	       dev == SSCOPE_ALLAN_DEV_THEOH;
}

/* TheoH: the largest OADEV m (tau within 10 % of the record) */
static size_t theoh_k(size_t np)
{
	return (size_t)floor(0.1 * (double)(np - 1));
}

/* whether dev takes averaging factor m (m <= max_m already) */
static bool m_valid(enum sscope_allan_dev dev, size_t m, size_t np)
{
	switch (dev) {
	case SSCOPE_ALLAN_DEV_THEO1:
	case SSCOPE_ALLAN_DEV_THEOBR:
		return m >= 10 && !(m & 1);
	case SSCOPE_ALLAN_DEV_THEOH: {
		size_t k = theoh_k(np);

		if (m <= k)
			return m <= (np - 1) / 2;
		return m >= 10 && !(m & 1) && 0.75 * (double)m >= (double)k;
	}
	default:
		return true;
	}
}

int sscope_allan_dev_parse(const char *name, enum sscope_allan_dev *dev)
{
	if (!name || !dev)
		return -EINVAL;
	for (int i = 0; i < SSCOPE_ALLAN_DEV_COUNT_; i++)
		if (!ssc_strcasecmp(name, dev_names[i])) {
			*dev = (enum sscope_allan_dev)i;
			return 0;
		}
	return -EINVAL;
}

int ssc_dev_order(enum sscope_allan_dev dev)
{
	return dev == SSCOPE_ALLAN_DEV_HDEV || dev == SSCOPE_ALLAN_DEV_OHDEV ||
			       dev == SSCOPE_ALLAN_DEV_HTOTDEV ?
		       3 :
		       2;
}

enum sscope_quantity sscope_allan_rate_quantity(enum sscope_quantity q,
						enum sscope_allan_input input)
{
	if (input != SSCOPE_ALLAN_ANGLE)
		return q;
	return q == SSCOPE_QUANTITY_ANGLE ? SSCOPE_QUANTITY_ANGULAR_RATE :
	       q == SSCOPE_QUANTITY_VELOCITY ? SSCOPE_QUANTITY_ACCELERATION :
					  SSCOPE_QUANTITY_UNKNOWN;
}

size_t sscope_allan_n_phase(enum sscope_allan_input input, size_t n)
{
	return input == SSCOPE_ALLAN_ANGLE ? n : n + 1;
}

size_t sscope_allan_max_m(enum sscope_allan_dev dev, size_t np)
{
	if (np < 3)
		return 0;
	switch (dev) {
	case SSCOPE_ALLAN_DEV_MDEV:
	case SSCOPE_ALLAN_DEV_TDEV:
		return np / 3;
	case SSCOPE_ALLAN_DEV_HDEV:
	case SSCOPE_ALLAN_DEV_OHDEV:
	case SSCOPE_ALLAN_DEV_HTOTDEV:
		return (np - 1) / 3;
	case SSCOPE_ALLAN_DEV_MTOTDEV:
	case SSCOPE_ALLAN_DEV_TTOTDEV:
		return np / 3;
	case SSCOPE_ALLAN_DEV_THEO1:
	case SSCOPE_ALLAN_DEV_THEOBR:
		return np > 10 ? np - 1 : 0;
	case SSCOPE_ALLAN_DEV_THEOH:
		return np - 1;
	case SSCOPE_ALLAN_DEV_MTIE:
	case SSCOPE_ALLAN_DEV_TIERMS:
		return np - 1;
	default:
		return (np - 1) / 2;
	}
}

/* 5 significant bits for m >= 32: a multiple of 2^(floor(log2 m) - 4) */
static size_t round5(size_t m)
{
	size_t q;
	int fl = 0;

	if (m < 32)
		return m;
	while ((m >> (fl + 1)) != 0)
		fl++;
	q = (size_t)1 << (fl - 4);
	return (m + q / 2) / q * q;
}

int sscope_allan_grid(enum sscope_allan_tau_grid grid, size_t m_max, size_t *m,
		      size_t cap, size_t *count)
{
	size_t n = 0, last = 0;

	if (!count || (unsigned)grid > SSCOPE_ALLAN_TAUS_ALL)
		return -EINVAL;
#define PUT(v)                                                                \
	do {                                                                  \
		if ((v) > last && (v) <= m_max) {                             \
			if (n < cap && m)                                     \
				m[n] = (v);                                   \
			n++;                                                  \
			last = (v);                                           \
		}                                                             \
	} while (0)
	switch (grid) {
	case SSCOPE_ALLAN_TAUS_OCTAVE:
		for (size_t v = 1; v && v <= m_max; v <<= 1)
			PUT(v);
		break;
	case SSCOPE_ALLAN_TAUS_DECADE:
		for (size_t dec = 1; dec && dec <= m_max; dec *= 10) {
			PUT(dec);
			PUT(2 * dec);
			PUT(4 * dec);
			if (dec > SIZE_MAX / 10)
				break;
		}
		break;
	case SSCOPE_ALLAN_TAUS_ALL:
		for (size_t v = 1; v <= m_max; v++)
			PUT(v);
		break;
	case SSCOPE_ALLAN_TAUS_DENSE:
		for (int k = 0;; k++) {
			double f = pow(10.0, k / 10.0);
			size_t v;

			if (f > (double)m_max + 0.5 || f >= 1.8e19)
				break;
			v = round5((size_t)llround(f));
			PUT(v);
		}
		break;
	}
#undef PUT
	*count = n;
	return 0;
}

/* ------------------------------------------------------------------ */
/* Plan                                                                */
/* ------------------------------------------------------------------ */

/* rows of the tiled layout fit in L2: about sqrt(np / 32) rows */
#define TILE_MIN_NP ((size_t)1 << 17)
/* columns per tile group: one 64-byte line per row */
#define TILE_COLS 8
/* a tau goes to the row pass when m >= BIG_FACTOR * S and S divides m */
#define BIG_FACTOR 16
/* term block of the fused short-tau kernels */
#define SHORT_BLOCK 2048
/* The tiled phase is stored in regions of 2^REGION_SHIFT doubles (2 MiB):
 * region c holds columns [c W, (c + 1) W) of every row, row after row
 * (W = 2^REGION_SHIFT / S columns, at least a tile group).  The phase
 * pass, which advances through the columns of all rows at once, then
 * writes the workspace region after region: each region's pages are
 * mapped in one call as the pass enters it (instead of a page fault per
 * page), and memory becomes resident as the pass goes.  A row is read
 * as one contiguous piece per region. */
#define REGION_SHIFT 18

struct sscope_allan {
	struct sscope_allan_opts opts;
	size_t n_max;
	unsigned nthreads;
	double *x;          /* phase workspace, 64-byte aligned */
	size_t x_cap;       /* doubles */
	double *win;        /* per-thread windows */
	size_t win_cap;     /* doubles per thread */
	uint64_t *nanbits;  /* gap map: bit k = sample/point k is NaN */
	uint32_t *nanpre;   /* NaN count before word w */
	size_t nb_words;
	/* layout of the current record: S rows of Lp columns in regions
	 * of 2^cws columns (see REGION_SHIFT) */
	size_t np, S, shift, Lp, cws;
	/* work chunks of the phase pass (see chunk_len): chunk c is points
	 * [c chunk, (c + 1) chunk) of the np */
	size_t chunk, n_chunk;
	/* a phase computed without the centring pass (see centre_sampled):
	 * chunk t (t < n_off) starts at column off_col[t] and its points
	 * are stored less off[t], which every reader of x adds back */
	size_t n_off, off_cap;
	double *off;
	size_t *off_col;
	/* noise-id scratch, nid_half doubles and bytes (twice) per thread */
	double *nid;
	unsigned char *nidv;
	size_t nid_half;
	bool contiguous; /* ssc_allan_force_contiguous() */
};

void ssc_allan_force_contiguous(struct sscope_allan *p, bool on)
{
	p->contiguous = on;
}

static size_t pick_shift(size_t np)
{
	double s;
	int e;

	if (np <= TILE_MIN_NP)
		return 0;
	s = sqrt((double)np / 32.0);
	e = (int)lround(log2(s));
	return e < 0 ? 0 : (size_t)e;
}

/* padded row length: a multiple of 8 doubles, odd in lines (no 4K
 * aliasing between the rows a kernel reads) */
static size_t row_len(size_t np, size_t shift)
{
	size_t S = (size_t)1 << shift, L = (np + S - 1) / S;

	if (shift == 0)
		return L;
	return TILE_COLS * (2 * ((L + 2 * TILE_COLS - 1) / (2 * TILE_COLS)) + 1);
}

/* log2 of the columns of a region at row shift sh */
static size_t region_cols_shift(size_t sh)
{
	return sh + 3 < REGION_SHIFT ? REGION_SHIFT - sh : 3;
}

/* doubles the layout at shift sh needs for np points */
static size_t layout_size(size_t np, size_t sh)
{
	size_t cw, L;

	if (sh == 0)
		return np;
	cw = (size_t)1 << region_cols_shift(sh);
	L = (row_len(np, sh) + cw - 1) / cw * cw;
	return L << sh;
}

static unsigned want_threads(unsigned req)
{
#ifdef _OPENMP
	int t = req ? (int)req : omp_get_max_threads();

	return t < 1 ? 1 : (unsigned)t;
#else
	(void)req;
	return 1;
#endif
}

int sscope_allan_new(struct sscope_allan **plan,
		     size_t n_max, const struct sscope_allan_opts *opts)
{
	struct sscope_allan *p;
	size_t np, sh, need, S;

	if (!plan)
		return -EINVAL;
	*plan = NULL;
	if (n_max == 0 || (opts && ((unsigned)opts->dev >= SSCOPE_ALLAN_DEV_COUNT_ ||
				    opts->input > SSCOPE_ALLAN_ANGLE ||
				    !(opts->ci_level < 1) ||
				    isnan(opts->ci_level))))
		return -EINVAL;
	if (opts && opts->alpha_fixed && (opts->alpha < -4 || opts->alpha > 2))
		return -EINVAL;
	if (n_max > SIZE_MAX / 64)
		return -ENOMEM;
	p = calloc(1, sizeof(*p));
	if (!p)
		return -ENOMEM;
	if (opts)
		p->opts = *opts;
	p->n_max = n_max;
	p->nthreads = want_threads(p->opts.threads);
	np = n_max + 1;
	sh = pick_shift(np);
	S = (size_t)1 << sh;
	/* compute() may lower the shift: room for every layout up to sh */
	need = np;
	for (size_t s2 = 1; s2 <= sh; s2++)
		if (layout_size(np, s2) > need)
			need = layout_size(np, s2);
	need += 64;
	p->x_cap = need;
	/* on pages (2 MiB where large): each region of the tiled layout is
	 * whole pages */
	p->x = ssc_alloc_huge((need * sizeof(double) + 4095) / 4096, 4096);
	/* window: G + W with W = 3 * BIG_FACTOR * S lookahead */
	{
		size_t W = 3 * BIG_FACTOR * S + SHORT_BLOCK;
		size_t G = W > 16384 ? W : 16384;

		G = (G + TILE_COLS * S - 1) / (TILE_COLS * S) * (TILE_COLS * S);
		p->win_cap = G + W + TILE_COLS * S + 64;
	}
	/* on cache lines: the kernels' loads are then aligned for every
	 * m that is a multiple of 8 (win_cap is one) */
	if (sh && p->win_cap <= SIZE_MAX / sizeof(double) / p->nthreads)
		p->win = aligned_alloc(64, (size_t)p->nthreads * p->win_cap *
						   sizeof(double));
	/* the identification looks at up to n_max + 1 points */
	p->nid_half = (n_max < SSC_NOISE_ID_MAX ? n_max + 1 : SSC_NOISE_ID_MAX) + 2;
	p->nid = ssc_alloc_array((size_t)p->nthreads * 2 * p->nid_half,
				 sizeof(double));
	p->nidv = ssc_alloc_array(p->nthreads, 2 * p->nid_half);
	if (!p->x || (sh && !p->win) || !p->nid || !p->nidv) {
		sscope_allan_free(p);
		return -ENOMEM;
	}
	*plan = p;
	return 0;
}

void sscope_allan_free(struct sscope_allan *p)
{
	if (!p)
		return;
	if ((p->opts.plan_flags & SSCOPE_ALLAN_RELEASE_WORKSPACE) && p->x)
		ssc_release_pages(p->x, p->x_cap * sizeof(double), p->nthreads);
	free(p->x);
	free(p->win);
	free(p->nanbits);
	free(p->nanpre);
	free(p->nid);
	free(p->nidv);
	free(p->off);
	free(p->off_col);
	free(p);
}

/* offset of row rr, column q in the current layout */
static inline size_t xoff(const struct sscope_allan *p, size_t rr, size_t q)
{
	return ((q >> p->cws) << (p->shift + p->cws)) + (rr << p->cws) +
	       (q & (((size_t)1 << p->cws) - 1));
}

/* the chunk offset of column q (see n_off): the chunks are of equal
 * length, chunk / S columns */
static inline double col_off(const struct sscope_allan *p, size_t q)
{
	size_t t = q / (p->chunk >> p->shift);

	return p->off[t < p->n_off ? t : p->n_off - 1];
}

/* phase point k in the current layout */
static inline double xat(const struct sscope_allan *p, size_t k)
{
	double v = p->x[xoff(p, k & (p->S - 1), k >> p->shift)];

	return p->n_off ? v + col_off(p, k >> p->shift) : v;
}

/* dst[i] = src[i] + o, i < n */
static void add_copy(double *restrict dst, const double *restrict src,
		     size_t n, double o)
{
	for (size_t i = 0; i < n; i++)
		dst[i] = src[i] + o;
}

/* row rr of the tiled layout, its columns [0, ncol), into buf, each
 * chunk's offset added (see n_off) */
static void row_copy(const struct sscope_allan *p, size_t rr, size_t ncol,
		     double *buf)
{
	const size_t cw = (size_t)1 << p->cws;
	size_t t = 0; /* the chunk of column q */

	for (size_t q = 0; q < ncol;) {
		const size_t rend = (q / cw + 1) * cw; /* the region's end */
		size_t e = rend < ncol ? rend : ncol;

		while (t + 1 < p->n_off && q >= p->off_col[t + 1])
			t++;
		if (t + 1 < p->n_off && p->off_col[t + 1] < e)
			e = p->off_col[t + 1];
		if (t == 0)
			memcpy(buf + q, p->x + xoff(p, rr, q), (e - q) * sizeof(double));
		else
			add_copy(buf + q, p->x + xoff(p, rr, q), e - q, p->off[t]);
		q = e;
	}
}

/* number of NaN flags in [a, b) of the gap map */
static size_t nan_count(const struct sscope_allan *p, size_t a, size_t b)
{
	size_t wa = a >> 6, wb = b >> 6;
	uint64_t ma = a & 63 ? (((uint64_t)1 << (a & 63)) - 1) : 0;
	uint64_t mb = b & 63 ? (((uint64_t)1 << (b & 63)) - 1) : 0;
	size_t ca = p->nanpre[wa] + (size_t)__builtin_popcountll(p->nanbits[wa] & ma);
	size_t cb = p->nanpre[wb] + (size_t)__builtin_popcountll(p->nanbits[wb] & mb);

	return cb - ca;
}

/* ------------------------------------------------------------------ */
/* Phase                                                               */
/* ------------------------------------------------------------------ */

struct src {
	const double *y;
	size_t stride, n;
	const struct sscope_allan_opts *o; /* the release callback */
	bool angle;
	double m0, delta; /* rate: increment = (y - m0) - delta */
	double spread;    /* centre_sampled: the samples' deviation */
	double y0, slope, fs; /* angle: x = ((y - y0) - slope k) fs */
};

static inline double incr(const struct src *s, size_t k)
{
	double v = s->y[k * s->stride];

	return isnan(v) ? 0.0 : (v - s->m0) - s->delta;
}

static inline double apoint(const struct src *s, size_t k)
{
	double v = s->y[k * s->stride];

	return isnan(v) ? 0.0 : ((v - s->y0) - s->slope * (double)k) * s->fs;
}

/* running phase state of a source */
struct run {
	struct ssc_ksum sum; /* rate: the phase at point k */
	size_t k;            /* index of the next phase point */
	bool nan;            /* rate: a NaN sample met (counted as 0) */
};

/* stretch of points computed from one compensated base */
#define FILL_STRETCH 1024

#ifdef SSC_VEC
typedef long long ssc_v8i __attribute__((vector_size(64)));

/* exclusive prefix sums of r into out[0..8) plus *acc; *acc += sum(r) */
static inline bool scan8(const double *y, double m0, double delta,
			 double bs, double bc, double *acc, double *out)
{
	const ssc_v8 zero = { 0 };
	ssc_v8 v, in;

	V8LOAD(v, y);
	v = (v - m0) - delta;
	in = v + __builtin_shuffle(v, zero, ((ssc_v8i){ 8, 0, 1, 2, 3, 4, 5, 6 }));
	in = in + __builtin_shuffle(in, zero, ((ssc_v8i){ 8, 9, 0, 1, 2, 3, 4, 5 }));
	in = in + __builtin_shuffle(in, zero, ((ssc_v8i){ 8, 9, 10, 11, 0, 1, 2, 3 }));
	if (isnan(in[7]))
		return false;
	v = __builtin_shuffle(in, zero, ((ssc_v8i){ 8, 0, 1, 2, 3, 4, 5, 6 }));
	v = bs + (bc + (*acc + v));
	memcpy(out, &v, sizeof(v));
	*acc += in[7];
	return true;
}
#endif

/*
 * The next cnt phase points.  Rate input: x_{k+1} = x_k + (y_k - mean),
 * summed plainly over stretches of FILL_STRETCH increments from a
 * compensated base (the stretch error, ~FILL_STRETCH ulps of a few
 * increments, is far below the rounding of x itself), eight at a time
 * with an in-register prefix scan.  Angle input: the detrended points.
 */
SSC_CLONES static void fill_phase(const struct src *s, struct run *r,
				  double *out, size_t cnt)
{
	size_t k = r->k;
	const size_t end = k + cnt;

	if (s->angle) {
		for (; k < end; k++)
			*out++ = apoint(s, k);
		r->k = end;
		return;
	}
	while (k < end) {
		size_t len = end - k < FILL_STRETCH ? end - k : FILL_STRETCH;
		double bs = r->sum.s, bc = r->sum.c, acc = 0;
		size_t i = 0;

#ifdef SSC_VEC
		if (s->stride == 1)
			for (; i + 8 <= len && k + i + 8 <= s->n; i += 8)
				if (!scan8(s->y + k + i, s->m0, s->delta, bs, bc,
					   &acc, out + i))
					break;
#endif
		for (; i < len; i++) {
			out[i] = bs + (bc + acc);
			if (k + i < s->n) {
				r->nan |= isnan(s->y[(k + i) * s->stride]);
				acc += incr(s, k + i);
			}
		}
		ssc_ksum_add(&r->sum, acc);
		k += len;
		out += len;
	}
	r->k = end;
}

/*
 * Sum of y - m0 over the finite samples of y[k * stride], k < n, the NaN
 * count and the first infinite sample (*inf_at, SIZE_MAX: none): plain
 * sums over blocks of 512 in eight lanes, blocks added compensated; a
 * block holding NaN is redone sample by sample, one whose sum is still not
 * finite looked through for an infinite sample.
 */
SSC_CLONES static void scan_block(const double *y, size_t stride, size_t n,
				  double m0, struct ssc_ksum *sum,
				  size_t *nan_count, size_t *inf_at)
{
	size_t nn = 0;

	*inf_at = SIZE_MAX;
	for (size_t b = 0; b < n; b += 512) {
		size_t len = n - b < 512 ? n - b : 512, i = 0;
		double part = 0;

#ifdef SSC_VEC
		if (stride == 1) {
			/* eight lanes as two halves (see k2) */
			ssc_v4 a = { 0 }, ah = { 0 };

			for (; i + 8 <= len; i += 8) {
				ssc_v4 v, vh;

				V4LOAD(v, y + b + i);
				V4LOAD(vh, y + b + i + 4);
				a += v - m0;
				ah += vh - m0;
			}
			part = ((a[0] + a[1]) + (a[2] + a[3])) +
			       ((ah[0] + ah[1]) + (ah[2] + ah[3]));
		}
#endif
		for (; i < len; i++)
			part += y[(b + i) * stride] - m0;
		if (isnan(part)) {
			part = 0;
			for (i = 0; i < len; i++) {
				double v = y[(b + i) * stride];

				if (isnan(v))
					nn++;
				else
					part += v - m0;
			}
		}
		if (!isfinite(part) && *inf_at == SIZE_MAX)
			for (i = 0; i < len; i++)
				if (isinf(y[(b + i) * stride])) {
					*inf_at = b + i;
					break;
				}
		ssc_ksum_add(sum, part);
	}
	*nan_count = nn;
}

/*
 * Work chunks.  The passes over the record (scan, phase, fused short
 * taus) are cut into chunks whose boundaries depend only on the record's
 * length and the tau grid, never on the number of threads, scheduled
 * dynamically and combined in chunk order: every sum is the same to the
 * bit on any number of threads, and a thread that loses its core to
 * another process holds the others back by at most one chunk.  About
 * CHUNKS_PER_RECORD chunks, at least CHUNK_MIN points and 8 times the
 * lookahead w that each chunk of the fused pass computes again, a
 * multiple of the layout's quantum q.
 */
#define CHUNKS_PER_RECORD 16
#define CHUNK_MIN ((size_t)1 << 16)

static void set_chunks(struct sscope_allan *p, size_t q, size_t w)
{
	size_t c = p->np / CHUNKS_PER_RECORD;

	if (c < CHUNK_MIN)
		c = CHUNK_MIN;
	if (c < 8 * w)
		c = 8 * w;
	p->chunk = (c + q - 1) / q * q;
	p->n_chunk = (p->np + p->chunk - 1) / p->chunk;
}

/*
 * The team for a parallel loop of `items` iterations and about `terms`
 * terms of work in all: one thread when there is one iteration, or when
 * the work is too small to pay for waking a second thread.  On a busy
 * machine a woken thread may wait a scheduler slice for a core while the
 * loop's end waits for it: `report` on a 36,000-sample gyro ran some 450
 * loops of a few thousand terms each, and two threads beside two
 * CPU-bound competitors took 0.60 s against 0.51 s on one.
 */
#define PAR_MIN_TERMS ((size_t)1 << 21)

static unsigned team_for(unsigned T, size_t items, size_t terms)
{
	return items > 1 && terms >= PAR_MIN_TERMS ? T : 1;
}

/* first point of chunk c (c = n_chunk: np) */
static size_t chunk_at(const struct sscope_allan *p, size_t c)
{
	return c >= p->n_chunk ? p->np : c * p->chunk;
}

/*
 * Statistics of the source: mean of finite samples, NaN count, chunk sums
 * of the increments; fills s->m0/delta (rate) or y0/slope (angle) and the
 * chunk bases.  Returns the number of finite samples (*inf_at: the first
 * infinite sample, SIZE_MAX: none; the rest is then meaningless).
 */
static size_t scan_source(struct sscope_allan *p, struct src *s, unsigned T,
			  struct ssc_ksum *bases, size_t *n_nan,
			  size_t *inf_at)
{
	size_t first = SIZE_MAX, last = 0, nfin = 0, nnan = 0;
	const size_t C = p->n_chunk;
	struct ssc_ksum *cs = bases; /* reused: chunk sums, then bases */
	size_t *cnt = NULL;

	for (size_t k = 0; k < s->n; k++)
		if (!isnan(s->y[k * s->stride])) {
			first = k;
			break;
		}
	*inf_at = SIZE_MAX;
	if (first == SIZE_MAX) {
		*n_nan = s->n;
		return 0;
	}
	for (size_t k = s->n; k-- > first;)
		if (!isnan(s->y[k * s->stride])) {
			last = k;
			break;
		}
	if (s->angle) {
		s->y0 = s->y[first * s->stride];
		s->slope = last > first ? (s->y[last * s->stride] - s->y0) /
						  (double)(last - first) :
					  0;
		/* y0 is taken at index 0 of the trend line */
		s->y0 -= s->slope * (double)first;
		for (size_t k = 0; k < s->n; k++) {
			double v = s->y[k * s->stride];

			if (isnan(v))
				nnan++;
			else if (isinf(v) && *inf_at == SIZE_MAX)
				*inf_at = k;
		}
		*n_nan = nnan;
		return s->n - nnan;
	}
	s->m0 = s->y[first * s->stride];
	s->delta = 0;
	cnt = calloc(C, sizeof(size_t));
	if (!cnt) {
		*n_nan = 0;
		return SIZE_MAX;
	}
	(void)T;
	{
		size_t tot_nan = 0, inf_min = SIZE_MAX;

SSC_OMP(omp parallel for num_threads(C > 1 ? T : 1) schedule(dynamic, 1) reduction(+ : tot_nan) reduction(min : inf_min))
		for (size_t c = 0; c < C; c++) {
			struct ssc_ksum a = { 0, 0 };
			size_t lo, hi, nn = 0, ia = SIZE_MAX;

			/* phase chunk [lo, hi) uses increments k in [lo, hi) */
			lo = chunk_at(p, c);
			hi = chunk_at(p, c + 1);
			if (hi > s->n)
				hi = s->n;
			if (hi > lo)
				scan_block(s->y + lo * s->stride, s->stride, hi - lo,
					   s->m0, &a, &nn, &ia);
			cs[c] = a;
			cnt[c] = hi > lo ? hi - lo - nn : 0;
			tot_nan += nn;
			if (ia != SIZE_MAX && lo + ia < inf_min)
				inf_min = lo + ia;
		}
		nnan = tot_nan;
		*inf_at = inf_min;
	}
	{
		struct ssc_ksum all = { 0, 0 };
		double delta;

		for (size_t c = 0; c < C; c++) {
			ssc_ksum_add(&all, cs[c].s);
			ssc_ksum_add(&all, cs[c].c);
			nfin += cnt[c];
		}
		delta = ssc_ksum_value(&all) / (double)nfin;
		s->delta = delta;
		/* bases: exclusive scan of (chunk sum - count * delta) */
		all.s = all.c = 0;
		for (size_t c = 0; c < C; c++) {
			struct ssc_ksum k = cs[c];
			double pr = (double)cnt[c] * delta;
			double err = fma((double)cnt[c], delta, -pr);

			bases[c] = all;
			ssc_ksum_add(&all, k.s);
			ssc_ksum_add(&all, k.c);
			ssc_ksum_add(&all, -pr);
			ssc_ksum_add(&all, -err);
		}
	}
	free(cnt);
	*n_nan = nnan;
	return nfin;
}

/* one sample in each CENTRE_STEP centres the phase of centre_sampled */
#define CENTRE_STEP 64
#define CENTRE_PART 4096

/*
 * Rate input: m0, the first sample, and delta, the mean of y - m0 over
 * one sample in every CENTRE_STEP, without a pass over every sample; the
 * sample's place in its block is pseudo-random, so that a signal periodic
 * in the block length is not sampled at one phase.  The overlapping second
 * and third differences do not depend on the centring (a constant
 * increment cancels in them); it only keeps the phase small for its
 * rounding.  A mean off by e makes the phase drift by up to n e; from n /
 * 64 samples e is about sigma / sqrt(n / 64), a drift of about 8 sqrt(n)
 * sigma, a few times the phase's own random walk (sigma in spread; the
 * caller checks the drift it got).  False when a sample read is not
 * finite (the caller then takes the full pass).
 */
static bool centre_sampled(struct src *s, unsigned T)
{
	const size_t ns = s->n / CENTRE_STEP;
	/* parts of CENTRE_PART samples (see set_chunks: fixed, whatever
	 * the team), added in order */
	const size_t nparts = (ns + CENTRE_PART - 1) / CENTRE_PART;
	const double y0 = s->y[0];
	struct ssc_ksum *part, all = { 0, 0 }, all2 = { 0, 0 };
	double delta, var;

	if (!isfinite(y0) || ns < 2)
		return false;
	part = calloc(2 * nparts, sizeof(*part));
	if (!part)
		return false;
	(void)T;
SSC_OMP(omp parallel for num_threads(nparts > 1 ? T : 1) schedule(dynamic, 1))
	for (size_t t = 0; t < nparts; t++) {
		size_t a = t * CENTRE_PART;
		size_t b = a + CENTRE_PART < ns ? a + CENTRE_PART : ns;
		struct ssc_ksum k = { 0, 0 }, k2 = { 0, 0 };
		double blk = 0, blk2 = 0;

		/* the pages this part reads (one in 64 samples touches every
		 * page of a mapped file) */
		ssc_prefault_read(s->y + a * CENTRE_STEP * s->stride,
				  (b - a) * CENTRE_STEP * s->stride * sizeof(double));
		for (size_t i = a; i < b; i++) {
			size_t j = (size_t)(((uint64_t)i * 0x9E3779B97F4A7C15u) >> 58);
			double v = s->y[(i * CENTRE_STEP + j) * s->stride] - y0;

			blk += v;
			blk2 += v * v;
			if (((i - a) & 255) == 255) {
				ssc_ksum_add(&k, blk);
				ssc_ksum_add(&k2, blk2);
				blk = blk2 = 0;
			}
		}
		ssc_ksum_add(&k, blk);
		ssc_ksum_add(&k2, blk2);
		part[2 * t] = k;
		part[2 * t + 1] = k2;
	}
	for (size_t t = 0; t < nparts; t++) {
		ssc_ksum_add(&all, part[2 * t].s);
		ssc_ksum_add(&all, part[2 * t].c);
		ssc_ksum_add(&all2, part[2 * t + 1].s);
		ssc_ksum_add(&all2, part[2 * t + 1].c);
	}
	free(part);
	delta = ssc_ksum_value(&all) / (double)ns;
	var = ssc_ksum_value(&all2) / (double)ns - delta * delta;
	if (!isfinite(delta) || !isfinite(var))
		return false;
	s->m0 = y0;
	s->delta = delta;
	s->spread = sqrt(var > 0 ? var : 0);
	return true;
}

/* gap map over the n source samples (rate) or np points (angle) */
static int build_gaps(struct sscope_allan *p, const struct src *s)
{
	size_t nb = s->n, words = (nb >> 6) + 2;

	if (words > p->nb_words) {
		free(p->nanbits);
		free(p->nanpre);
		p->nanbits = calloc(words, sizeof(uint64_t));
		p->nanpre = calloc(words, sizeof(uint32_t));
		if (!p->nanbits || !p->nanpre)
			return -ENOMEM;
		p->nb_words = words;
	} else {
		memset(p->nanbits, 0, words * sizeof(uint64_t));
	}
	if (nb > UINT32_MAX)
		return -ERANGE;
	for (size_t k = 0; k < nb; k++)
		if (isnan(s->y[k * s->stride]))
			p->nanbits[k >> 6] |= (uint64_t)1 << (k & 63);
	p->nanpre[0] = 0;
	for (size_t w = 1; w < words; w++)
		p->nanpre[w] = p->nanpre[w - 1] +
			       (uint32_t)__builtin_popcountll(p->nanbits[w - 1]);
	return 0;
}

/* samples read between release calls */
#define RELEASE_STEP ((size_t)1 << 18)

/* the samples [*done, upto) have been read for the last time: give their
 * whole pages back (SSCOPE_ALLAN_EVICT_INPUT), in steps of RELEASE_STEP
 * or at the end (last) */
static void release_to(const struct src *s, size_t *done, size_t upto,
		       bool last)
{
	if (upto > s->n)
		upto = s->n;
	const char *a, *b;

	if (!(s->o->plan_flags & SSCOPE_ALLAN_EVICT_INPUT) || upto <= *done ||
	    (!last && upto - *done < RELEASE_STEP))
		return;
	a = (const char *)(s->y + *done * s->stride);
	b = (const char *)(s->y + (upto - 1) * s->stride + 1);
	ssc_release_pages((void *)(uintptr_t)a, (size_t)(b - a), 1);
	*done = upto;
}

/* contiguous phase, written in parallel chunks */
static void phase_contiguous(struct sscope_allan *p, const struct src *s,
			     unsigned T, const struct ssc_ksum *bases)
{
	(void)T;
SSC_OMP(omp parallel for num_threads(p->n_chunk > 1 ? T : 1) schedule(dynamic, 1))
	for (size_t c = 0; c < p->n_chunk; c++) {
		struct run r = { { 0, 0 }, 0, false };
		size_t lo = chunk_at(p, c);
		size_t hi = chunk_at(p, c + 1), done = lo;

		r.sum = s->angle ? (struct ssc_ksum){ 0, 0 } : bases[c];
		r.k = lo;
		while (r.k < hi) {
			size_t len = hi - r.k < RELEASE_STEP ? hi - r.k : RELEASE_STEP;

			fill_phase(s, &r, p->x + r.k, len);
			release_to(s, &done, r.k, r.k >= hi);
		}
	}
}

/* ------------------------------------------------------------------ */
/* The fused tiled engine (OADEV, OHDEV)                               */
/* ------------------------------------------------------------------ */

struct tau_set {
	const size_t *m;   /* factors */
	size_t n;
	bool *big;         /* row pass (else fused short pass) */
	size_t mshort_max; /* largest short m */
	int d;
};

#if defined(SSC_K512) && defined(SSC_NT_STORES)
#define SSC_TILE512 1
/*
 * The S rows of a tile group, eight at a time: column c of row r is
 * w[r + c S] (w and S 64-byte aligned, S a multiple of 8); the 8 x 8
 * blocks are transposed in registers and each row's line is streamed to
 * dst + r * rstride (64-byte aligned) past the cache.
 */
SSC_K512 static void tile_group512(const double *w, size_t S, double *dst,
				   size_t rstride)
{
	for (size_t rr = 0; rr < S; rr += 8) {
		const double *c0 = w + rr;
		__m512d a0 = _mm512_load_pd(c0), a1 = _mm512_load_pd(c0 + S);
		__m512d a2 = _mm512_load_pd(c0 + 2 * S), a3 = _mm512_load_pd(c0 + 3 * S);
		__m512d a4 = _mm512_load_pd(c0 + 4 * S), a5 = _mm512_load_pd(c0 + 5 * S);
		__m512d a6 = _mm512_load_pd(c0 + 6 * S), a7 = _mm512_load_pd(c0 + 7 * S);
		/* pairs: t0 = a0[0] a1[0] a0[2] a1[2] ..., t1 the odd ones */
		__m512d t0 = _mm512_unpacklo_pd(a0, a1), t1 = _mm512_unpackhi_pd(a0, a1);
		__m512d t2 = _mm512_unpacklo_pd(a2, a3), t3 = _mm512_unpackhi_pd(a2, a3);
		__m512d t4 = _mm512_unpacklo_pd(a4, a5), t5 = _mm512_unpackhi_pd(a4, a5);
		__m512d t6 = _mm512_unpacklo_pd(a6, a7), t7 = _mm512_unpackhi_pd(a6, a7);
		/* quads: u0 = a0..a3 at elements 0 and 4, u1 at 2 and 6, ... */
		__m512d u0 = _mm512_shuffle_f64x2(t0, t2, 0x88);
		__m512d u1 = _mm512_shuffle_f64x2(t0, t2, 0xDD);
		__m512d u2 = _mm512_shuffle_f64x2(t1, t3, 0x88);
		__m512d u3 = _mm512_shuffle_f64x2(t1, t3, 0xDD);
		__m512d u4 = _mm512_shuffle_f64x2(t4, t6, 0x88);
		__m512d u5 = _mm512_shuffle_f64x2(t4, t6, 0xDD);
		__m512d u6 = _mm512_shuffle_f64x2(t5, t7, 0x88);
		__m512d u7 = _mm512_shuffle_f64x2(t5, t7, 0xDD);
		double *d = dst + rr * rstride;

		_mm512_stream_pd(d, _mm512_shuffle_f64x2(u0, u4, 0x88));
		_mm512_stream_pd(d + rstride, _mm512_shuffle_f64x2(u2, u6, 0x88));
		_mm512_stream_pd(d + 2 * rstride, _mm512_shuffle_f64x2(u1, u5, 0x88));
		_mm512_stream_pd(d + 3 * rstride, _mm512_shuffle_f64x2(u3, u7, 0x88));
		_mm512_stream_pd(d + 4 * rstride, _mm512_shuffle_f64x2(u0, u4, 0xDD));
		_mm512_stream_pd(d + 5 * rstride, _mm512_shuffle_f64x2(u2, u6, 0xDD));
		_mm512_stream_pd(d + 6 * rstride, _mm512_shuffle_f64x2(u1, u5, 0xDD));
		_mm512_stream_pd(d + 7 * rstride, _mm512_shuffle_f64x2(u3, u7, 0xDD));
	}
}
#endif

/*
 * One chunk of the phase pass: compute the phase of chunk
 * [lo, hi) (plus lookahead for the short kernels), write it tiled, and
 * accumulate the short-tau sums of the terms starting in the chunk.
 */
/*
 * The W samples after a chunk's end are read twice: by the chunk, whose
 * short taus look ahead, and by the next chunk, which starts there.  On
 * different threads either may come last, and a read after the other
 * gave the pages back would fetch them again for good (on this kernel a
 * whole 2 MiB folio of the file each time): the second reader gives them
 * back.  seams[b] counts the readers done with the seam after chunk b.
 */
static void seam_read(const struct sscope_allan *p, const struct src *s,
		      unsigned *seams, size_t b, size_t W)
{
	size_t a = chunk_at(p, b + 1), done = a;

	if (__atomic_add_fetch(&seams[b], 1, __ATOMIC_ACQ_REL) == 2)
		release_to(s, &done, a + W < p->np ? a + W : p->np, true);
}

static void fused_chunk(struct sscope_allan *p, const struct src *s,
			struct ssc_ksum base, size_t lo, size_t hi,
			const struct tau_set *ts, double *win,
			struct ssc_ksum *acc, double *end, bool *bad,
			unsigned *seams)
{
	const size_t S = p->S, np = p->np, grp = TILE_COLS * S;
	const size_t W = (size_t)ts->d * ts->mshort_max + SHORT_BLOCK;
	const size_t chunk_no = lo / p->chunk;
	size_t G = W > 16384 ? W : 16384, WB, filled = 0, wbase = lo;
	/* the seam before the chunk is left to seam_read() */
	size_t kend = hi + W < np ? hi + W : np,
	       done = chunk_no > 0 ? (lo + W < hi ? lo + W : hi) : lo;
	struct run r = { base, lo, false };
	/* second differences two taus at a time where the kernel exists */
	const bool pair = ts->d == 2 && have_wide();
	size_t region = SIZE_MAX; /* the region last mapped */
#ifdef SSC_TILE512
	/* (the window is on cache lines: win_cap and G are multiples of 8) */
	const bool wide_tiles = have_wide() && S % 8 == 0 &&
				((uintptr_t)win & 63) == 0;
#endif

	G = (G + grp - 1) / grp * grp;
	WB = G + W;
	if (lo >= hi)
		return;
	for (;;) {
		size_t stop = wbase + WB < kend ? wbase + WB : kend;
		size_t gend = wbase + G < hi ? wbase + G : hi;

		if (stop > wbase + filled)
			fill_phase(s, &r, win + filled, stop - wbase - filled);
		filled = stop - wbase;
		/* centred without the pass that checks the samples (bad set):
		 * on a NaN or a phase that is not finite the caller starts
		 * again with that pass; another thread's: stop too */
		if (bad && (r.nan || !isfinite(r.sum.s)))
			__atomic_store_n(bad, true, __ATOMIC_RELAXED);
		if (bad && __atomic_load_n(bad, __ATOMIC_RELAXED))
			return;
		/* the phase at the chunk's end relative to its start (the
		 * last chunk's last point) */
		if (hi < np && hi >= wbase && hi < wbase + filled)
			*end = win[hi - wbase];
		else if (hi == np && np - 1 >= wbase && np - 1 < wbase + filled)
			*end = win[np - 1 - wbase];
		/* the next chunk's thread reads the lookahead too */
		release_to(s, &done, r.k < hi ? r.k : hi, r.k >= hi);
		/* short taus on terms starting in [wbase, gend), block by
		 * block and every tau on a block before the next: the block's
		 * points are read from L1 by the small taus instead of from L2
		 * once per tau (each tau's blocks are added in the same order) */
		for (size_t i0 = wbase; i0 < gend; i0 += SHORT_BLOCK) {
			const double *w = win + (i0 - wbase);
			size_t pj = SIZE_MAX, pc = 0; /* a tau waiting for a pair */

			for (size_t j = 0; j < ts->n; j++) {
				size_t m = ts->m[j], nt, b, c;

				if (ts->big[j])
					continue;
				nt = np - (size_t)ts->d * m; /* terms i < nt */
				b = gend < nt ? gend : nt;
				if (i0 >= b)
					continue;
				c = b - i0 < SHORT_BLOCK ? b - i0 : SHORT_BLOCK;
				if (!pair) {
					ssc_ksum_add(&acc[j], kd(ts->d, w, m, c));
					continue;
				}
				if (pj != SIZE_MAX && pc == c) {
					double sa, sb;

					k2_pair(w, ts->m[pj], m, c, &sa, &sb);
					ssc_ksum_add(&acc[pj], sa);
					ssc_ksum_add(&acc[j], sb);
					pj = SIZE_MAX;
					continue;
				}
				if (pj != SIZE_MAX)
					ssc_ksum_add(&acc[pj], kd(2, w, ts->m[pj], pc));
				pj = j;
				pc = c;
			}
			if (pj != SIZE_MAX)
				ssc_ksum_add(&acc[pj], kd(2, w, ts->m[pj], pc));
		}
		/* tiles of [wbase, gend): groups of 8 columns */
		for (size_t g0 = wbase; g0 < gend; g0 += grp) {
			size_t q0 = g0 >> p->shift;
			size_t gl = gend - g0 < grp ? gend - g0 : grp;
			const double *w = win + (g0 - wbase);

			if (gl == grp) {
				double *d0 = p->x + xoff(p, 0, q0);

				if (q0 >> p->cws != region) {
					region = q0 >> p->cws;
					ssc_prefault(p->x + (region << (p->shift + p->cws)),
						     sizeof(double) << (p->shift + p->cws));
				}
#ifdef SSC_TILE512
				if (wide_tiles) {
					tile_group512(w, S, d0, (size_t)1 << p->cws);
					continue;
				}
#endif
				for (size_t rr = 0; rr < S; rr++) {
					double *dst = d0 + (rr << p->cws);
#ifdef SSC_NT_STORES
					/* whole lines, streamed past the cache:
					 * the rows are read back much later */
					_mm_stream_pd(dst, _mm_set_pd(w[rr + S], w[rr]));
					_mm_stream_pd(dst + 2, _mm_set_pd(w[rr + 3 * S], w[rr + 2 * S]));
					_mm_stream_pd(dst + 4, _mm_set_pd(w[rr + 5 * S], w[rr + 4 * S]));
					_mm_stream_pd(dst + 6, _mm_set_pd(w[rr + 7 * S], w[rr + 6 * S]));
#else
					for (size_t c = 0; c < TILE_COLS; c++)
						dst[c] = w[rr + c * S];
#endif
				}
			} else {
				for (size_t k = 0; k < gl; k++)
					p->x[xoff(p, k & (S - 1), q0 + (k >> p->shift))] = w[k];
			}
		}
		if (wbase + G >= hi)
			break;
		memmove(win, win + G, (filled - G) * sizeof(double));
		filled -= G;
		wbase += G;
	}
	if (chunk_no > 0)
		seam_read(p, s, seams, chunk_no - 1, W);
	if (hi < np)
		seam_read(p, s, seams, chunk_no, W);
}

/* the taus of m on the current layout: long ones (row pass) are
 * multiples of S from BIG_FACTOR S on */
static void tau_set_init(struct tau_set *ts, const struct sscope_allan *p,
			 const size_t *m, size_t nacc, bool *big, int d)
{
	*ts = (struct tau_set){ m, nacc, big, 0, d };
	for (size_t j = 0; j < nacc; j++) {
		big[j] = m[j] >= BIG_FACTOR * p->S && m[j] % p->S == 0;
		if (!big[j] && m[j] > ts->mshort_max)
			ts->mshort_max = m[j];
	}
}

/* the terms *nq that row rr holds of long tau j of ts (false: none) */
static bool row_terms(const struct sscope_allan *p, const struct tau_set *ts,
		      size_t j, size_t rr, size_t *nq)
{
	size_t nt;

	if (!ts->big[j])
		return false;
	nt = p->np - (size_t)ts->d * ts->m[j];
	if (nt <= rr)
		return false;
	*nq = (nt - rr + p->S - 1) >> p->shift;
	return true;
}

/*
 * Sums of order-d overlapping terms for every m of ts, tiled layout.
 * bases NULL (rate input centred by centre_sampled): each chunk's phase
 * starts from 0 and the chunks' offsets are set once all are done; a NaN
 * or a phase that is not finite gives -EAGAIN (nothing added to acc).
 */
static int sums_tiled(struct sscope_allan *p, const struct src *s,
		      unsigned T, const struct ssc_ksum *bases,
		      const struct tau_set *ts, struct ssc_ksum *acc)
{
	const size_t C = p->n_chunk, S = p->S;
	/* the sums of chunk c at part[c n], of row rr at part[(C + rr) n],
	 * added in that order at the end: the same on any team */
	struct ssc_ksum *part = ssc_alloc_array((C + S) * ts->n, sizeof(*part));
	/* each chunk's end phase, then its seam's readers (fused_chunk) */
	double *ends = calloc(C, sizeof(double) + sizeof(unsigned));
	unsigned *seams = ends ? (unsigned *)(ends + C) : NULL;
	bool bad = false;
	/* a row is read into the thread's window (into rows of its own
	 * when a lowered shift made the rows longer than the window) */
	const size_t rcap = p->Lp <= p->win_cap ? p->win_cap : p->Lp;
	double *rows = NULL;

	if (!part || !ends) {
		free(part);
		free(ends);
		return -ENOMEM;
	}
	memset(part, 0, (C + S) * ts->n * sizeof(*part));
	if (!bases && !s->angle && C > p->off_cap) {
		free(p->off);
		free(p->off_col);
		p->off = calloc(C, sizeof(double));
		p->off_col = calloc(C, sizeof(size_t));
		p->off_cap = p->off && p->off_col ? C : 0;
		if (!p->off_cap) {
			free(part);
			free(ends);
			return -ENOMEM;
		}
	}
	if (p->Lp > p->win_cap) {
		rows = ssc_alloc_array((size_t)T, rcap * sizeof(double));
		if (!rows) {
			free(part);
			free(ends);
			return -ENOMEM;
		}
	}
	const bool pair = ts->d == 2 && have_wide();

SSC_OMP(omp parallel num_threads(T))
	{
		unsigned me = 0;
		double *win;

#ifdef _OPENMP
		me = (unsigned)omp_get_thread_num();
#endif
		win = p->win + (size_t)me * p->win_cap;
SSC_OMP(omp for schedule(dynamic, 1))
		for (size_t c = 0; c < C; c++)
			fused_chunk(p, s,
				    s->angle || !bases ? (struct ssc_ksum){ 0, 0 } : bases[c],
				    chunk_at(p, c), chunk_at(p, c + 1), ts, win,
				    part + c * ts->n, &ends[c],
				    bases ? NULL : &bad, seams);
#ifdef SSC_NT_STORES
		_mm_sfence(); /* streamed tiles visible before the barrier */
#endif
		/* (implicit barrier: every tile is written) */
SSC_OMP(omp single)
		if (!bases && !s->angle && !bad) {
			double o = 0;

			/* chunk c is stored less the phase at its start */
			for (size_t c = 0; c < C; c++) {
				p->off_col[c] = chunk_at(p, c) >> p->shift;
				p->off[c] = o;
				o += ends[c];
			}
			p->n_off = C;
			/* o: the phase's drift over the record, n times what
			 * the sampled mean missed; when far beyond what the
			 * sample promised (a signal the sample aliases), the
			 * full pass centres it exactly */
			bad = !isfinite(o) ||
			      fabs(o) > 32 * s->spread * sqrt((double)s->n);
		}
		/* (implicit barrier: offsets set) */
SSC_OMP(omp for schedule(dynamic, 4))
		for (size_t rr = 0; rr < S; rr++) {
			double *row = (rows ? rows : p->win) + (size_t)me * rcap;
			struct ssc_ksum *my = part + (C + rr) * ts->n;
			size_t pj = SIZE_MAX, pq = 0; /* a tau waiting for a pair */
			size_t ncol = 0;

			if (bad)
				continue;

			/* the columns of the row that the long taus read */
			for (size_t j = 0; j < ts->n; j++) {
				size_t m = ts->m[j], nq;

				if (row_terms(p, ts, j, rr, &nq) &&
				    nq + (size_t)ts->d * (m >> p->shift) > ncol)
					ncol = nq + (size_t)ts->d * (m >> p->shift);
			}
			if (ncol == 0)
				continue;
			row_copy(p, rr, ncol, row);
			for (size_t j = 0; j < ts->n; j++) {
				size_t m = ts->m[j], nq;

				if (!row_terms(p, ts, j, rr, &nq))
					continue;
				if (!pair) {
					kd_total(ts->d, row, m >> p->shift, nq, &my[j]);
				} else if (pj == SIZE_MAX) {
					pj = j;
					pq = nq;
				} else {
					kd_total_pair(row, ts->m[pj] >> p->shift, pq,
						      m >> p->shift, nq, &my[pj], &my[j]);
					pj = SIZE_MAX;
				}
			}
			if (pj != SIZE_MAX)
				kd_total(ts->d, row, ts->m[pj] >> p->shift, pq, &my[pj]);
		}
	}
	if (bad) {
		p->n_off = 0;
		free(part);
		free(ends);
		free(rows);
		return -EAGAIN;
	}
	for (size_t c = 0; c < C + S; c++)
		for (size_t j = 0; j < ts->n; j++) {
			ssc_ksum_add(&acc[j], part[c * ts->n + j].s);
			ssc_ksum_add(&acc[j], part[c * ts->n + j].c);
		}
	free(part);
	free(ends);
	free(rows);
	return 0;
}

/* ------------------------------------------------------------------ */
/* Contiguous per-tau kernels                                          */
/* ------------------------------------------------------------------ */

/* span of a term in samples (rate) or points-1 (angle) for gap checks */
static bool term_ok(const struct sscope_allan *p, bool angle, size_t i,
		    size_t span)
{
	/* rate: increments i .. i+span-1; angle: points i .. i+span */
	return nan_count(p, i, i + span + (angle ? 1 : 0)) == 0;
}

/* order-d terms starting at i = 0, s, 2s, ... < nt */
static void sum_strided(const struct sscope_allan *p, bool angle, bool gaps,
			int d, size_t m, size_t s, size_t nt,
			struct ssc_ksum *acc, size_t *used, size_t *skipped)
{
	const double *x = p->x;
	size_t u = 0, sk = 0;

	if (s == 1 && !gaps) {
		kd_total(d, x, m, nt, acc);
		*used = nt;
		*skipped = 0;
		return;
	}
	{
		double part = 0;
		size_t inblk = 0;

		for (size_t i = 0; i < nt; i += s) {
			double v;

			if (gaps && !term_ok(p, angle, i, (size_t)d * m)) {
				sk++;
				continue;
			}
			v = term(d, x, i, m);
			part += v * v;
			u++;
			if (++inblk == KBLOCK) {
				ssc_ksum_add(acc, part);
				part = 0;
				inblk = 0;
			}
		}
		ssc_ksum_add(acc, part);
	}
	*used = u;
	*skipped = sk;
}

/*
 * MDEV: sum_j (sum_{i=j}^{j+m-1} t_i)^2 over j <= np - 3m, t_i the second
 * difference at lag m; the inner sum is kept as a compensated running sum.
 */
static void sum_mdev(const struct sscope_allan *p, bool angle, bool gaps,
		     size_t m, struct ssc_ksum *acc, size_t *used,
		     size_t *skipped)
{
	const double *x = p->x;
	size_t nj = p->np - 3 * m + 1, u = 0, sk = 0, inblk = 0;
	struct ssc_ksum in = { 0, 0 };
	double part = 0;

	for (size_t i = 0; i < m; i++)
		ssc_ksum_add(&in, term(2, x, i, m));
	for (size_t j = 0; j < nj; j++) {
		double v = ssc_ksum_value(&in);

		if (gaps && !term_ok(p, angle, j, 3 * m - 1)) {
			sk++;
		} else {
			part += v * v;
			u++;
			if (++inblk == KBLOCK) {
				ssc_ksum_add(acc, part);
				part = 0;
				inblk = 0;
			}
		}
		if (j + 1 < nj) {
			ssc_ksum_add(&in, term(2, x, j + m, m));
			ssc_ksum_add(&in, -term(2, x, j, m));
		}
	}
	ssc_ksum_add(acc, part);
	*used = u;
	*skipped = sk;
}

/* TOTDEV: second differences of the reflected extension (SP 1065 eq 25) */
static void sum_totdev(const struct sscope_allan *p, size_t m,
		       struct ssc_ksum *acc, size_t *used)
{
	const double *x = p->x;
	const size_t np = p->np, last = np - 1;
	double part = 0;
	size_t inblk = 0;

	for (size_t i = 1; i + 1 < np; i++) {
		double lo, hi, d;

		/* x*_{-j} = 2 x_0 - x_j, x*_{last+j} = 2 x_last - x_{last-j} */
		if (i >= m)
			lo = x[i - m] - x[i];
		else
			lo = (x[0] - x[m - i]) + (x[0] - x[i]);
		if (i + m <= last)
			hi = x[i + m] - x[i];
		else
			hi = (x[last] - x[last - (i + m - last)]) + (x[last] - x[i]);
		d = hi + lo;
		part += d * d;
		if (++inblk == KBLOCK) {
			ssc_ksum_add(acc, part);
			part = 0;
			inblk = 0;
		}
	}
	ssc_ksum_add(acc, part);
	*used = np - 2;
}

/* contiguous OADEV without gaps or strides on a record too short for the
 * tiles (every all-tau grid, and any grid of such a record): the taus
 * in groups (k2_group), the groups over the threads */
static void sums_grouped(const struct sscope_allan *p, const size_t *m,
			 size_t n, unsigned T, bool copies, struct ssc_ksum *acc,
			 size_t *used, size_t *skipped)
{
	const size_t ng = (n + GRP_TAUS - 1) / GRP_TAUS;
	const bool wide = have_wide();
	struct shifted xs = { NULL, 0 };

	(void)T;
	/* the shifted copies where the phase is on a cache line and they
	 * stay small (8 x 8 MB at most; a long record has few taus here) */
	if (copies && p->np >= 64 && p->np <= SHIFTED_MAX_NP &&
	    !((uintptr_t)p->x & 63)) {
		xs.stride = (p->np + 7) / 8 * 8 + 16;
		xs.sh = aligned_alloc(64, 8 * xs.stride * sizeof(double));
		if (xs.sh)
			for (size_t r = 0; r < 8; r++) {
				double *d = xs.sh + r * xs.stride;

				memcpy(d, p->x + r, (p->np - r) * sizeof(double));
				memset(d + p->np - r, 0,
				       (xs.stride - (p->np - r)) * sizeof(double));
			}
	}
SSC_OMP(omp parallel for num_threads(team_for(T, ng, p->np * n)) schedule(dynamic, 1))
	for (size_t k = 0; k < ng; k++) {
		size_t j0 = k * GRP_TAUS;

		k2_group(p->x, p->np, m + j0,
			 n - j0 < GRP_TAUS ? n - j0 : GRP_TAUS, wide, &xs,
			 acc + j0);
	}
	free(xs.sh);
	for (size_t j = 0; j < n; j++) {
		used[j] = p->np - 2 * m[j];
		skipped[j] = 0;
	}
}

/*
 * OADEV sums of a gap-free contiguous phase.  With xf (a grid of many
 * factors): every factor by transforms (allan-xform.c), keeping those
 * whose rounding bound is within SSC_OADEV_FAST_TOL of the sum, the rest
 * (the short factors of a wandering phase) by the definition.
 */
static void sums_oadev(const struct sscope_allan *p, const size_t *m,
		       size_t n, unsigned T, bool xf, struct ssc_ksum *acc,
		       size_t *used, size_t *skipped)
{
	const size_t D = n ? m[n - 1] : 0;
	struct ssc_xf_ws *ws = NULL;
	double *V = NULL;
	size_t *mr = NULL, nr = 0;
	struct ssc_ksum *ar = NULL;

	if (xf && 2 * D < p->np) {
		ws = ssc_xf_ws_new(p->x, p->np);
		V = ssc_alloc_array(2 * (D + 1), sizeof(double));
		mr = ssc_alloc_array(4 * n, sizeof(size_t));
		ar = calloc(n ? n : 1, sizeof(*ar));
	}
	if (!ws || !V || !mr || !ar ||
	    ssc_oadev_sums_fast(ws, D, T, V, V + D + 1) < 0) {
		sums_grouped(p, m, n, T, true, acc, used, skipped);
		goto out;
	}
	for (size_t j = 0; j < n; j++) {
		double v = V[m[j]], e = V[D + 1 + m[j]];

		if (v > 0 && e <= SSC_OADEV_FAST_TOL * v) {
			acc[j].s = v;
			acc[j].c = 0;
			used[j] = p->np - 2 * m[j];
			skipped[j] = 0;
		} else {
			mr[nr] = m[j];
			mr[n + nr++] = j;
		}
	}
	if (nr) {
		/* (the short factors, and the longest with a few terms:
		 * not worth the shifted copies' page faults) */
		sums_grouped(p, mr, nr, T, false, ar, mr + 2 * n,
			     mr + 2 * n + nr);
		for (size_t r = 0; r < nr; r++) {
			size_t j = mr[n + r];

			acc[j] = ar[r];
			used[j] = mr[2 * n + r];
			skipped[j] = 0;
		}
	}
out:
	free(ar);
	free(mr);
	free(V);
	ssc_xf_ws_free(ws);
}

/* ------------------------------------------------------------------ */
/* Compute                                                             */
/* ------------------------------------------------------------------ */

/* overlapping AVAR at m from the phase (terms touching a gap skipped),
 * for the R(n) ratio of the few-points identification */
static double avar_at(const struct sscope_allan *p, bool gaps, size_t m)
{
	struct ssc_ksum acc = { 0 };
	size_t cnt = 0;

	for (size_t i = 0; i + 2 * m < p->np; i++) {
		double d;

		if (gaps && nan_count(p, i, i + 2 * m + 1))
			continue;
		d = xat(p, i + 2 * m) - 2 * xat(p, i + m) + xat(p, i);
		ssc_ksum_add(&acc, d * d);
		cnt++;
	}
	return cnt ? ssc_ksum_value(&acc) / (2 * (double)m * (double)m * (double)cnt) :
		     (double)NAN;
}

/*
 * Noise type at m: the lag-1 autocorrelation of the decimated phase
 * (angle input) or of the averages (rate input) with at least 30 analysis
 * points, else the B1 ratio (R(n) for the modified deviations), as NIST
 * SP 1065 section 5.6 and Stable32; -EDOM when too few averages remain
 * (the caller carries the last identification).  mvar: the point's
 * modified variance (MDEV/TDEV), else NaN.  TOTDEV takes the
 * identification of the Allan variance at the same m (its term count for
 * B1, its minimum of averages), as Stable32 1.60 does: on PHASE.DAT its
 * TOTDEV is WFM at m = 128 and 256 like its OADEV, where a B1 ratio of
 * the 7 averages at m = 128 reads FPM and would give the interval of 48.6
 * degrees of freedom instead of 11.7.
 */
static int point_alpha(const struct sscope_allan *p, enum sscope_allan_dev dev,
		       bool angle, bool gaps, size_t m, size_t terms,
		       double mvar, unsigned me, int *alpha, bool *unsure)
{
	size_t nvalid;
	size_t K = (p->np - 1) / m + 1; /* points x(k m), k < K */
	const size_t half = p->nid_half;
	double *z = p->nid + (size_t)me * 2 * half;
	unsigned char *v = p->nidv + (size_t)me * 2 * half;
	struct ssc_nid_few few;

	if (K > SSC_NOISE_ID_MAX + 1)
		K = SSC_NOISE_ID_MAX + 1;
	for (size_t k = 0; k < K; k++) {
		z[k] = xat(p, k * m);
		/* validity: rate input flags the average over increments
		 * [k m, (k+1) m), angle input the point itself */
		if (!gaps)
			continue;
		if (angle)
			v[k] = nan_count(p, k * m, k * m + 1) == 0;
		else if (k + 1 < K)
			v[k] = nan_count(p, k * m, (k + 1) * m) == 0;
	}
	few.n_points = dev == SSCOPE_ALLAN_DEV_TOTDEV ?
			       (double)(p->np > 2 * m ? p->np - 2 * m : 1) :
			       (double)terms;
	few.m = m;
	few.min_averages = SSC_B1_MIN_AVERAGES;
	few.rn = NAN;
	if (isfinite(mvar) && (angle ? K : K - 1) < SSC_NOISE_ID_MIN)
		few.rn = mvar / avar_at(p, gaps, m);
	/* the analysis points the series counts: B1 below the minimum, an
	 * unsure type below SSC_NOISE_ID_SURE */
	nvalid = angle ? K : K - 1;
	if (gaps) {
		nvalid = 0;
		for (size_t k = 0; k < (angle ? K : K - 1); k++)
			nvalid += v[k] != 0;
	}
	*unsure = nvalid < SSC_NOISE_ID_SURE;
	return ssc_noise_id_series(z, gaps ? v : NULL, K, !angle,
				   ssc_dev_order(dev), &few, alpha, NULL,
				   z + half, v + half);
}

/* samples needed for one term at averaging factor m */
static size_t min_samples(enum sscope_allan_dev dev, size_t m, bool angle)
{
	size_t np;

	switch (dev) {
	case SSCOPE_ALLAN_DEV_MDEV:
	case SSCOPE_ALLAN_DEV_TDEV:
		np = 3 * m;
		break;
	case SSCOPE_ALLAN_DEV_HDEV:
	case SSCOPE_ALLAN_DEV_OHDEV:
	case SSCOPE_ALLAN_DEV_HTOTDEV:
		np = 3 * m + 1;
		break;
	case SSCOPE_ALLAN_DEV_MTOTDEV:
	case SSCOPE_ALLAN_DEV_TTOTDEV:
		np = 3 * m;
		break;
	case SSCOPE_ALLAN_DEV_THEO1:
	case SSCOPE_ALLAN_DEV_THEOBR:
	case SSCOPE_ALLAN_DEV_THEOH:
		np = (m < 10 ? 10 : m + (m & 1)) + 1;
		if (dev != SSCOPE_ALLAN_DEV_THEO1 && np < SSC_THEOBR_MIN_NP)
			np = SSC_THEOBR_MIN_NP;
		break;
	case SSCOPE_ALLAN_DEV_MTIE:
	case SSCOPE_ALLAN_DEV_TIERMS:
		np = m + 1;
		break;
	default:
		np = 2 * m + 1;
		break;
	}
	return angle ? np : np - 1;
}

static double point_edf(enum sscope_allan_dev dev, int alpha, size_t m, size_t npe,
			size_t stride)
{
	int d = ssc_dev_order(dev);

	switch (dev) {
	case SSCOPE_ALLAN_DEV_MDEV:
	case SSCOPE_ALLAN_DEV_TDEV:
		return sscope_allan_edf(alpha, 2, m, npe, true, 1);
	case SSCOPE_ALLAN_DEV_TOTDEV:
		return ssc_totdev_edf(alpha, m, npe);
	case SSCOPE_ALLAN_DEV_MTOTDEV:
	case SSCOPE_ALLAN_DEV_TTOTDEV:
		return ssc_mtot_edf(alpha, m, npe);
	case SSCOPE_ALLAN_DEV_HTOTDEV:
		return ssc_htot_edf(alpha, m, npe);
	case SSCOPE_ALLAN_DEV_THEO1:
	case SSCOPE_ALLAN_DEV_THEOBR:
		return ssc_theo1_edf(alpha, m, npe);
	case SSCOPE_ALLAN_DEV_THEOH:
		if (m <= theoh_k(npe))
			return sscope_allan_edf(alpha, 2, m, npe, false, 1);
		return ssc_theo1_edf(alpha, m, npe);
	case SSCOPE_ALLAN_DEV_MTIE:
	case SSCOPE_ALLAN_DEV_TIERMS:
		return NAN;
	default:
		return sscope_allan_edf(alpha, d, m, npe, false, stride);
	}
}

/* phase points equivalent to the terms actually used */
static size_t point_npe(enum sscope_allan_dev dev, int d, size_t m,
			size_t used, size_t st, size_t np)
{
	if (dev == SSCOPE_ALLAN_DEV_MDEV || dev == SSCOPE_ALLAN_DEV_TDEV)
		return used + 3 * m - 1;
	if (dev == SSCOPE_ALLAN_DEV_TOTDEV || fam_dev(dev))
		return np;
	return (used - 1) * st + (size_t)d * m + 1;
}

static int clamp_alpha(enum sscope_allan_dev dev, int a)
{
	int lo = ssc_dev_order(dev) == 3 ? -4 : -2;

	return a < lo ? lo : a > 2 ? 2 : a;
}

/*
 * The deviations of allan-family.c at the accepted factors m[0..n) of a
 * gap-free contiguous phase: dev[j] (HTOTDEV before its bias removal) and
 * terms[j] (Theo1, TheoBR: the (np - m) m / 2 terms of eq. 33, as
 * Stable32 counts them).
 */
static int fam_points(struct sscope_allan *p, enum sscope_allan_dev dev,
		      const size_t *m, size_t n, double rate_hz, unsigned T,
		      double *dev_out, size_t *terms, struct sscope_diag *diag)
{
	/* the phase is stored in units of the rate times tau0 (see
	 * apoint()): the variances take tau0 = 1 and the time errors are
	 * scaled by tau0 */
	const double *x = p->x, tau0 = 1, ts = 1 / rate_hz;
	const size_t np = p->np, k = theoh_k(np);
	double ratio = NAN;
	struct ssc_xf_ws *ws = NULL;
	int rc = 0;

	/* Theo1's long factors by transforms (see allan-xform.c): one
	 * workspace for every factor and the bias ratio's */
	if (dev == SSCOPE_ALLAN_DEV_THEO1 || dev == SSCOPE_ALLAN_DEV_THEOBR ||
	    dev == SSCOPE_ALLAN_DEV_THEOH) {
		bool pays = dev != SSCOPE_ALLAN_DEV_THEO1 &&
			    ssc_theo_fast_pays(np, ssc_theobr_mmax(np));

		for (size_t j = 0; j < n && !pays; j++)
			pays = !(m[j] & 1) && m[j] < np &&
			       ssc_theo_fast_pays(np, m[j]);
		if (pays)
			ws = ssc_xf_ws_new(x, np);
	}
	if (dev == SSCOPE_ALLAN_DEV_THEOBR ||
	    (dev == SSCOPE_ALLAN_DEV_THEOH && n && m[n - 1] > k)) {
		ratio = ssc_theobr_ratio(x, np, tau0, T, ws);
		if (!isfinite(ratio)) {
			ssc_xf_ws_free(ws);
			return ssc_diag(diag, -EDOM,
					"too short for %s: %zu phase points (its bias ratio needs at least %d)",
					sscope_allan_dev_name(dev), np,
					SSC_THEOBR_MIN_NP);
		}
	}
	if (dev == SSCOPE_ALLAN_DEV_MTIE || dev == SSCOPE_ALLAN_DEV_TIERMS) {
SSC_OMP(omp parallel for num_threads(T) schedule(dynamic, 1))
		for (size_t j = 0; j < n; j++) {
			size_t *w = NULL;

			terms[j] = np - m[j];
			if (dev == SSCOPE_ALLAN_DEV_TIERMS) {
				dev_out[j] = ssc_tierms(x, np, m[j]) * ts;
				continue;
			}
			w = ssc_alloc_array(ssc_mtie_work(m[j]), sizeof(size_t));
			dev_out[j] = w ? ssc_mtie(x, np, m[j], w) * ts : (double)NAN;
			free(w);
		}
	} else {
		for (size_t j = 0; j < n; j++) {
			const size_t mj = m[j];
			const double tau = (double)mj * ts;
			double v;

			switch (dev) {
			case SSCOPE_ALLAN_DEV_MTOTDEV:
			case SSCOPE_ALLAN_DEV_TTOTDEV:
				v = ssc_mtot_var(x, np, mj, tau0, T);
				terms[j] = np - 3 * mj + 1;
				dev_out[j] = sqrt(v);
				if (dev == SSCOPE_ALLAN_DEV_TTOTDEV)
					dev_out[j] *= tau / sqrt(3.0);
				break;
			case SSCOPE_ALLAN_DEV_HTOTDEV:
				v = ssc_htot_var(x, np, mj, tau0, T);
				terms[j] = mj == 1 ? np - 3 : np - 3 * mj;
				dev_out[j] = sqrt(v);
				break;
			case SSCOPE_ALLAN_DEV_THEOH:
				if (mj <= k) {
					v = avar_at(p, false, mj);
					terms[j] = np - 2 * mj;
					dev_out[j] = sqrt(v);
					break;
				}
				/* fall through */
			default: /* Theo1, TheoBR */
				v = ssc_theo1_var(x, np, mj, tau0, T, ws);
				terms[j] = (np - mj) * (mj / 2);
				dev_out[j] = sqrt(dev == SSCOPE_ALLAN_DEV_THEO1 ? v : v * ratio);
				break;
			}
		}
	}
	ssc_xf_ws_free(ws);
	for (size_t j = 0; j < n; j++)
		if (isnan(dev_out[j]))
			rc = -ENOMEM;
	return rc;
}

/* tau of a point: Theo1 and TheoBR (and TheoH beyond its OADEV part) are
 * at 0.75 m tau0 */
static double point_tau(enum sscope_allan_dev dev, size_t m, size_t np,
			double rate_hz)
{
	if (dev == SSCOPE_ALLAN_DEV_THEO1 || dev == SSCOPE_ALLAN_DEV_THEOBR ||
	    (dev == SSCOPE_ALLAN_DEV_THEOH && m > theoh_k(np)))
		return 0.75 * (double)m / rate_hz;
	return (double)m / rate_hz;
}

static int compute(struct sscope_allan *p, const double *y,
		   size_t stride, size_t n, double rate_hz,
		   const size_t *m, size_t n_m,
		   struct sscope_allan_point *pts, size_t *n_pts,
		   struct sscope_diag *diag)
{
	const enum sscope_allan_dev dev = p ? p->opts.dev : SSCOPE_ALLAN_DEV_OADEV;
	const bool angle = p && p->opts.input == SSCOPE_ALLAN_ANGLE;
	const int d = ssc_dev_order(dev);
	struct src s = { 0 };
	struct ssc_ksum *bases = NULL, *acc = NULL;
	size_t nfin, nnan, mmax, nacc = 0, *used = NULL, *skipped = NULL;
	size_t inf_at, *mf = NULL;
	double *fdev = NULL;
	bool *big = NULL, gaps, tiled, strided, idpar, quick, xf;
	struct tau_set ts;
	unsigned char *idok = NULL;
	int *alph = NULL;
	unsigned T;
	int rc = 0, carry_alpha = 0, carry_ealpha = 0, chain_ealpha = 0;
	bool have_carry = false, have_chain = false;
	size_t chain_m = 0;
	double level;
	struct ssc_ci_level lv;

	if (!p || !y || !m || !pts || !n_pts || stride == 0 ||
	    !(rate_hz > 0) || !isfinite(rate_hz))
		return ssc_diag(diag, -EINVAL, "allan: bad parameters");
	*n_pts = 0;
	if (n > p->n_max)
		return ssc_diag(diag, -EINVAL,
				"allan: %zu samples exceed the plan's %zu", n,
				p->n_max);
	for (size_t j = 0; j < n_m; j++)
		if (m[j] == 0 || (j && m[j] <= m[j - 1]))
			return ssc_diag(diag, -EINVAL,
					"allan: averaging factors must be positive and increasing");
	p->np = sscope_allan_n_phase(p->opts.input, n);
	mmax = sscope_allan_max_m(dev, p->np);
	while (nacc < n_m && m[nacc] <= mmax)
		nacc++;
	if (fam_dev(dev) && nacc) {
		/* the factors the deviation takes (Theo1: even, >= 10) */
		size_t k = 0;

		mf = ssc_alloc_array(nacc, sizeof(size_t));
		if (!mf)
			return -ENOMEM;
		for (size_t j = 0; j < nacc; j++)
			if (m_valid(dev, m[j], p->np))
				mf[k++] = m[j];
		nacc = k;
	}
	if (nacc == 0) {
		free(mf);
		return ssc_diag(diag, -EDOM,
				"too short for %s: %zu sample%s (averaging factor %zu needs %zu)",
				sscope_allan_dev_name(dev), n, n == 1 ? "" : "s",
				n_m ? m[0] : (size_t)1,
				min_samples(dev, n_m ? m[0] : 1, angle));
	}
	if (mf)
		m = mf;
	s.y = y;
	s.stride = stride;
	s.n = n;
	s.o = &p->opts;
	s.angle = angle;
	s.fs = rate_hz;
	T = p->nthreads;
	/* (the contiguous layout's chunks are the most numerous) */
	set_chunks(p, 1, 0);
	bases = calloc(p->n_chunk, sizeof(*bases));
	acc = calloc(nacc, sizeof(*acc));
	used = calloc(nacc, sizeof(size_t));
	skipped = calloc(nacc, sizeof(size_t));
	big = calloc(nacc, sizeof(bool));
	fdev = calloc(nacc, sizeof(double));
	if (!bases || !acc || !used || !skipped || !big || !fdev) {
		rc = -ENOMEM;
		goto out;
	}
	strided = p->opts.stride_div > 0 &&
		  (dev == SSCOPE_ALLAN_DEV_OADEV || dev == SSCOPE_ALLAN_DEV_OHDEV);
	/* OADEV at many factors: by transforms, on the contiguous layout */
	xf = dev == SSCOPE_ALLAN_DEV_OADEV && !strided && !definition_only &&
	     ssc_oadev_fast_pays(p->np, m, nacc);
	/* layout: tiled only for fully overlapping OADEV / OHDEV */
	p->shift = 0;
	if ((dev == SSCOPE_ALLAN_DEV_OADEV || dev == SSCOPE_ALLAN_DEV_OHDEV) && !strided &&
	    !p->contiguous && !xf)
		p->shift = pick_shift(p->np);
	/* every long m must be a multiple of S */
	for (; p->shift > 0; p->shift--) {
		size_t S = (size_t)1 << p->shift;
		bool ok = true;

		for (size_t j = 0; j < nacc; j++)
			if (m[j] >= BIG_FACTOR * S && m[j] % S)
				ok = false;
		if (ok)
			break;
	}
	/* the chunk scan needs the layout's chunk quantum */
	p->S = (size_t)1 << p->shift;
	p->Lp = row_len(p->np, p->shift);
	p->cws = region_cols_shift(p->shift);
	/* rate input on the tiled layout: centred from a sample of the
	 * record and checked as the phase is computed, instead of a pass
	 * over the record first (the full pass below when a sample is not
	 * finite) */
	p->n_off = 0;
	quick = false;
	if (p->shift > 0) {
		tau_set_init(&ts, p, m, nacc, big, d);
		set_chunks(p, TILE_COLS * p->S,
			   (size_t)d * ts.mshort_max + SHORT_BLOCK);
	}
	if (p->shift > 0 && !angle && centre_sampled(&s, T)) {
		rc = sums_tiled(p, &s, T, NULL, &ts, acc);
		if (rc && rc != -EAGAIN)
			goto out;
		quick = rc == 0;
		rc = 0;
	}
	gaps = false;
	if (!quick) {
		nfin = scan_source(p, &s, T, bases, &nnan, &inf_at);
		if (nfin == SIZE_MAX) {
			rc = -ENOMEM;
			goto out;
		}
		/* the samples are checked here, in the pass that needs them anyway */
		if (inf_at != SIZE_MAX) {
			rc = ssc_diag(diag, -EDOM, "infinite sample at index %zu", inf_at);
			goto out;
		}
		if (nnan && p->opts.reject_nan) {
			size_t k = 0;

			while (k < n && !isnan(y[k * stride]))
				k++;
			rc = ssc_diag(diag, -EDOM, "NaN sample at index %zu", k);
			goto out;
		}
		if (nfin < 2) {
			rc = ssc_diag(diag, -EDOM,
				      "fewer than two finite samples (%zu of %zu)",
				      nfin, n);
			goto out;
		}
		gaps = nnan > 0;
		if (gaps && (dev == SSCOPE_ALLAN_DEV_TOTDEV || fam_dev(dev))) {
			rc = ssc_diag(diag, -EDOM,
				      "%s needs a record without gaps (%zu NaN samples): choose another deviation or analyse a stretch without gaps",
				      sscope_allan_dev_name(dev), nnan);
			goto out;
		}
		if (gaps) {
			p->shift = 0;
			p->S = 1;
			p->Lp = p->np;
			p->cws = region_cols_shift(0);
			/* the chunk sums were computed with the tiled quantum:
			 * recompute for contiguous chunks */
			set_chunks(p, 1, 0);
			nfin = scan_source(p, &s, T, bases, &nnan, &inf_at);
			rc = build_gaps(p, &s);
			if (rc)
				goto out;
		}
	}
	tiled = p->shift > 0;
	if (tiled) {
		/* (ts is the layout's: a record with gaps is not tiled) */
		if (!quick) {
			rc = sums_tiled(p, &s, T, bases, &ts, acc);
			if (rc)
				goto out;
		}
		for (size_t j = 0; j < nacc; j++)
			used[j] = p->np - (size_t)d * m[j];
	} else if (dev == SSCOPE_ALLAN_DEV_OADEV && !strided && !gaps) {
		phase_contiguous(p, &s, T, bases);
		sums_oadev(p, m, nacc, T, xf, acc, used, skipped);
	} else if (fam_dev(dev)) {
		phase_contiguous(p, &s, T, bases);
		rc = fam_points(p, dev, m, nacc, rate_hz, T, fdev, used, diag);
		if (rc)
			goto out;
	} else {
		phase_contiguous(p, &s, T, bases);
SSC_OMP(omp parallel for num_threads(team_for(T, nacc, p->np * nacc)) schedule(dynamic, 1))
		for (size_t j = 0; j < nacc; j++) {
			size_t mj = m[j];

			switch (dev) {
			case SSCOPE_ALLAN_DEV_OADEV:
			case SSCOPE_ALLAN_DEV_OHDEV: {
				size_t st = strided ? mj / p->opts.stride_div : 1;

				sum_strided(p, angle, gaps, d, mj, st ? st : 1,
					    p->np - (size_t)d * mj, &acc[j],
					    &used[j], &skipped[j]);
				break;
			}
			case SSCOPE_ALLAN_DEV_ADEV:
			case SSCOPE_ALLAN_DEV_HDEV:
				sum_strided(p, angle, gaps, d, mj, mj,
					    p->np - (size_t)d * mj, &acc[j],
					    &used[j], &skipped[j]);
				break;
			case SSCOPE_ALLAN_DEV_MDEV:
			case SSCOPE_ALLAN_DEV_TDEV:
				sum_mdev(p, angle, gaps, mj, &acc[j], &used[j],
					 &skipped[j]);
				break;
			case SSCOPE_ALLAN_DEV_TOTDEV:
				sum_totdev(p, mj, &acc[j], &used[j]);
				break;
			default:
				break;
			}
		}
	}
	/*
	 * Points, in three steps so that a grid of many taus (--taus all)
	 * uses every thread: deviations and noise identification per tau in
	 * parallel; the carry of the last identified type to the taus with
	 * too few averages, in order; EDF and intervals in parallel.
	 */
	level = p->opts.ci_level == 0 ? 0.682689492137086 : p->opts.ci_level;
	ssc_allan_ci_level(&lv, level);
	idok = calloc(nacc, 1);
	alph = calloc(2 * nacc, sizeof(int));
	if (!idok || !alph) {
		rc = -ENOMEM;
		goto out;
	}
	/* the identification reads up to SSC_NOISE_ID_MAX points per tau:
	 * worth both threads from a few taus of a long record on */
	idpar = nacc > 64 || (nacc > 1 && p->np > 4 * SSC_NOISE_ID_MAX);
SSC_OMP(omp parallel for num_threads(idpar ? T : 1) schedule(dynamic, nacc > 64 ? 8 : 1))
	for (size_t j = 0; j < nacc; j++) {
		struct sscope_allan_point *pt = &pts[j];
		double md = (double)m[j], sum = ssc_ksum_value(&acc[j]), var;
		size_t st = 1;
		unsigned me = 0;
		bool unsure = false;

#ifdef _OPENMP
		me = (unsigned)omp_get_thread_num();
#endif
		memset(pt, 0, sizeof(*pt));
		pt->m = m[j];
		pt->tau_s = point_tau(dev, m[j], p->np, rate_hz);
		pt->terms = used[j];
		pt->skipped = skipped[j];
		if (dev == SSCOPE_ALLAN_DEV_ADEV || dev == SSCOPE_ALLAN_DEV_HDEV)
			st = m[j];
		else if (strided)
			st = m[j] / p->opts.stride_div ? m[j] / p->opts.stride_div : 1;
		pt->stride = st;
		if (used[j] == 0) {
			pt->dev = pt->dev_lo = pt->dev_hi = NAN;
			pt->edf = pt->edf_full = pt->edf_alpha = NAN;
			continue;
		}
		if (fam_dev(dev)) {
			enum sscope_allan_dev idd = SSCOPE_ALLAN_DEV_OADEV;
			size_t mi = m[j], ti;
			double mv = NAN;

			pt->dev = fdev[j];
			var = fdev[j] * fdev[j];
			if (!sscope_allan_dev_has_ci(dev) || p->opts.alpha_fixed ||
			    !isfinite(var))
				continue;
			/* the identification of the deviation it extends */
			if (dev == SSCOPE_ALLAN_DEV_MTOTDEV ||
			    dev == SSCOPE_ALLAN_DEV_TTOTDEV)
				idd = SSCOPE_ALLAN_DEV_MDEV;
			else if (dev == SSCOPE_ALLAN_DEV_HTOTDEV)
				idd = SSCOPE_ALLAN_DEV_OHDEV;
			else if (pt->tau_s * rate_hz < (double)mi)
				mi = (size_t)llround(0.75 * (double)mi);
			ti = p->np - (size_t)ssc_dev_order(idd) * mi +
			     (idd == SSCOPE_ALLAN_DEV_MDEV ? 1 : 0);
			if (idd == SSCOPE_ALLAN_DEV_MDEV &&
			    (angle ? (p->np - 1) / mi + 1 : (p->np - 1) / mi) <
				    SSC_NOISE_ID_MIN) {
				struct ssc_ksum a = { 0, 0 };
				size_t u, sk;
				double mm = (double)mi;

				sum_mdev(p, angle, false, mi, &a, &u, &sk);
				mv = ssc_ksum_value(&a) / (2 * mm * mm * mm * mm * (double)u);
			}
			if (point_alpha(p, idd, angle, false, mi, ti, mv, me,
					&alph[j], &unsure) == 0)
				idok[j] = unsure ? 2 : 1;
			continue;
		}
		switch (dev) {
		case SSCOPE_ALLAN_DEV_MDEV:
		case SSCOPE_ALLAN_DEV_TDEV:
			var = sum / (2 * md * md * md * md * (double)used[j]);
			break;
		case SSCOPE_ALLAN_DEV_HDEV:
		case SSCOPE_ALLAN_DEV_OHDEV:
			var = sum / (6 * md * md * (double)used[j]);
			break;
		case SSCOPE_ALLAN_DEV_TOTDEV:
			var = sum / (2 * md * md * (double)(p->np - 2));
			break;
		default:
			var = sum / (2 * md * md * (double)used[j]);
			break;
		}
		pt->dev = sqrt(var > 0 ? var : 0);
		if (dev == SSCOPE_ALLAN_DEV_TDEV)
			pt->dev *= pt->tau_s / sqrt(3.0);
		/* noise type */
		if (!p->opts.alpha_fixed &&
		    isfinite(var) && /* overflowed: redone scaled */
		    point_alpha(p, dev, angle, gaps, m[j], used[j],
				dev == SSCOPE_ALLAN_DEV_MDEV || dev == SSCOPE_ALLAN_DEV_TDEV ?
					var :
					(double)NAN,
				me, &alph[j], &unsure) == 0)
			idok[j] = unsure ? 2 : 1;
	}
	/*
	 * The carry, in order.  The type reported is Stable32's (the lag-1
	 * autocorrelation from 30 averages, the B1 ratio below, the last type
	 * carried below 8).  The EDF and interval take, where a type read
	 * from fewer than SSC_NOISE_ID_SURE analysis points differs from the
	 * interval's type at the shorter tau, the one of fewer degrees of
	 * freedom (the wider interval).  A misread type is not rare there
	 * and is read on the records whose deviation is high: on white FM
	 * the lag-1 method calls 3-20 % of the records flicker PM at 30 to
	 * 80 averages (r1 <= -0.2), whose EDF is 10-20 times white FM's at
	 * large m, and the 68.3 % intervals of those taus covered 59-67 %
	 * (1000 records of 2e5 samples; 67-69 % this way); the B1 ratio of
	 * 6 to 24 averages calls one in four flicker PM (59-63 % of 400
	 * records of 1e5, 66-74 % this way).  In a sum of power-law noises
	 * the type only falls with tau, and the EDF with it, so a true change
	 * of type keeps its own EDF.  The type carried for the intervals is
	 * that of an octave chain (each point of it at least twice the m of
	 * the last), whatever the grid: with every m (--taus all) a carry
	 * from every point would meet a misread in nearly every record (on
	 * white FM, 3e4 samples, 200 records: intervals widened in 58 % of
	 * the records at m = 4096 against 14 % on the octave grid, covering
	 * 75.5 and 77.5 % at m = 4096 and 8192 against 71.0 and 73.5 %).
	 * ealph = alph + nacc: the type of each point's EDF and interval.
	 */
	for (size_t j = 0; j < nacc; j++) {
		int alpha, ealpha;

		if (used[j] == 0)
			continue;
		if (p->opts.alpha_fixed) {
			alpha = ealpha = p->opts.alpha;
		} else if (idok[j]) {
			size_t npe = point_npe(dev, d, m[j], used[j], pts[j].stride, p->np);

			pts[j].alpha_identified = true;
			alpha = ealpha = alph[j];
			if (idok[j] == 2 && have_chain && alpha != chain_ealpha &&
			    point_edf(dev, clamp_alpha(dev, chain_ealpha), m[j], npe,
				      pts[j].stride) <
				    point_edf(dev, clamp_alpha(dev, alpha), m[j], npe,
					      pts[j].stride))
				ealpha = chain_ealpha;
			carry_alpha = alpha;
			carry_ealpha = ealpha;
			have_carry = true;
			if (!have_chain || m[j] >= 2 * chain_m) {
				chain_ealpha = ealpha;
				chain_m = m[j];
				have_chain = true;
			}
		} else {
			alpha = have_carry ? carry_alpha : 0;
			ealpha = have_carry ? carry_ealpha : 0;
		}
		alph[j] = clamp_alpha(dev, alpha);
		alph[nacc + j] = clamp_alpha(dev, ealpha);
	}
	/* many taus: the quantiles of the intervals from tabulated starts
	 * (without the table on -ENOMEM: the same bounds to ~1e-13) */
	if (nacc >= SSC_CI_STARTS_MIN && p->opts.ci_level >= 0)
		(void)ssc_allan_ci_starts(&lv);
SSC_OMP(omp parallel for num_threads(nacc > 64 ? T : 1) schedule(dynamic, 8))
	for (size_t j = 0; j < nacc; j++) {
		struct sscope_allan_point *pt = &pts[j];
		size_t st = pt->stride, npe;
		int alpha = alph[j], ealpha = alph[nacc + j];

		if (used[j] == 0)
			continue;
		pt->alpha = alpha;
		if (!sscope_allan_dev_has_ci(dev)) {
			/* MTIE, TIE rms: no EDF model */
			pt->alpha = 0;
			pt->alpha_identified = false;
			pt->edf = pt->edf_full = pt->edf_alpha = NAN;
			pt->dev_lo = pt->dev_hi = NAN;
			continue;
		}
		/* Htot var = (1 - a) Hvar for the frequency noises: removed */
		if (dev == SSCOPE_ALLAN_DEV_HTOTDEV && m[j] > 1)
			pt->dev /= sqrt(ssc_htot_bias(alpha));
		/* phase points equivalent to the terms actually used */
		npe = point_npe(dev, d, m[j], used[j], st, p->np);
		/* the interval's type (the wider where the types disagree);
		 * the noise fit keeps weighting by the reported type's */
		pt->edf = point_edf(dev, ealpha, m[j], npe, st);
		pt->edf_alpha = ealpha == alpha ? pt->edf :
						  point_edf(dev, alpha, m[j], npe, st);
		pt->edf_full = st == 1 || dev == SSCOPE_ALLAN_DEV_ADEV ||
					       dev == SSCOPE_ALLAN_DEV_HDEV ?
				       pt->edf :
				       point_edf(dev, ealpha, m[j],
						 p->np - 0, 1);
		if (!(pt->edf > 0) || !(pt->edf_alpha > 0)) {
			pt->edf = pt->edf_full = pt->edf_alpha = NAN;
			pt->dev_lo = pt->dev_hi = NAN;
		} else if (p->opts.ci_level < 0 || !(pt->dev > 0)) {
			pt->dev_lo = pt->dev_hi = p->opts.ci_level < 0 ? NAN : 0;
		} else {
			ssc_allan_ci_at(&lv, pt->dev, pt->edf, &pt->dev_lo,
					&pt->dev_hi);
		}
	}
	ssc_allan_ci_level_free(&lv);
	*n_pts = nacc;
out:
	free(bases);
	free(acc);
	free(used);
	free(skipped);
	free(big);
	free(idok);
	free(alph);
	free(fdev);
	free(mf);
	return rc;
}

/*
 * Extreme magnitudes.  The sums square differences of the phase, so
 * samples beyond about 1e150 overflow and below 1e-150 underflow.  A
 * result that shows it (a deviation not finite, zero or beyond 2^+-450)
 * is computed again from a copy of the samples scaled by a power of two
 * (exact) into [0.5, 1), and scaled back; data in the ordinary range cost
 * nothing more.  Taus must stay within 2^+-200 s so that the fit's tau^2
 * and tau^-2 rows stay in range.
 */
static bool out_of_range(const struct sscope_allan_point *pts, size_t n)
{
	for (size_t j = 0; j < n; j++)
		if (pts[j].terms &&
		    !(pts[j].dev >= 0x1p-450 && pts[j].dev <= 0x1p450))
			return true;
	return false;
}

int sscope_allan_compute(struct sscope_allan *p, const double *y,
			 size_t stride, size_t n, double rate_hz,
			 const size_t *m, size_t n_m,
			 struct sscope_allan_point *pts, size_t *n_pts,
			 struct sscope_diag *diag)
{
	double amax = 0, sc, *copy;
	unsigned flags;
	int rc;

	if (rate_hz > 0 && isfinite(rate_hz) &&
	    !(1 / rate_hz >= 0x1p-200 && (double)n / rate_hz <= 0x1p200))
		return ssc_diag(diag, -ERANGE,
				"a sample rate of %g Hz puts taus outside 2^-200 .. 2^200 s",
				rate_hz);
	rc = compute(p, y, stride, n, rate_hz, m, n_m, pts, n_pts, diag);
	if (rc || !out_of_range(pts, *n_pts))
		return rc;
	for (size_t k = 0; k < n; k++) {
		double a = fabs(y[k * stride]);

		if (a > amax && isfinite(a))
			amax = a;
	}
	sc = ssc_safe_scale(amax);
	if (sc == 1)
		return 0; /* constant data: zero is the answer */
	copy = ssc_alloc_array(n, sizeof(double));
	if (!copy)
		return -ENOMEM;
	for (size_t k = 0; k < n; k++)
		copy[k] = y[k * stride] * sc;
	flags = p->opts.plan_flags; /* the copy lives in memory only */
	p->opts.plan_flags &= ~(unsigned)SSCOPE_ALLAN_EVICT_INPUT;
	rc = compute(p, copy, 1, n, rate_hz, m, n_m, pts, n_pts, diag);
	p->opts.plan_flags = flags;
	free(copy);
	if (rc)
		return rc;
	for (size_t j = 0; j < *n_pts; j++) {
		pts[j].dev /= sc;
		pts[j].dev_lo /= sc;
		pts[j].dev_hi /= sc;
		if (pts[j].terms && !isfinite(pts[j].dev))
			return ssc_diag(diag, -ERANGE,
					"allan: the deviation at tau %g s exceeds the double range",
					pts[j].tau_s);
	}
	return 0;
}

/* The fit on points scaled into an ordinary range (its covariances hold
 * AVAR^2 = dev^4), its coefficients scaled back. */
static int fit_scaled(const struct sscope_allan_point *pts, size_t n,
		      double rate_hz, size_t n_phase,
		      const struct sscope_noise_fit_opts *fopts,
		      struct sscope_noise_fit *fit, struct sscope_diag *diag)
{
	struct sscope_allan_point *q;
	double dmax = 0;
	int rc, e;

	for (size_t j = 0; j < n; j++)
		if (isfinite(pts[j].dev) && pts[j].dev > dmax)
			dmax = pts[j].dev;
	if (!(dmax > 0) || (dmax > 0x1p-100 && dmax < 0x1p100))
		return sscope_noise_fit(pts, n, rate_hz, n_phase, fopts, fit,
					diag);
	frexp(dmax, &e); /* points scaled by 2^-e, results by 2^e */
	q = ssc_alloc_array(n, sizeof(*q));
	if (!q)
		return -ENOMEM;
	for (size_t j = 0; j < n; j++) {
		q[j] = pts[j];
		q[j].dev = ldexp(q[j].dev, -e);
		q[j].dev_lo = ldexp(q[j].dev_lo, -e);
		q[j].dev_hi = ldexp(q[j].dev_hi, -e);
	}
	rc = sscope_noise_fit(q, n, rate_hz, n_phase, fopts, fit, diag);
	free(q);
	for (int t = 0; t < 5; t++) {
		fit->coef[t].value = ldexp(fit->coef[t].value, e);
		fit->coef[t].estimate = ldexp(fit->coef[t].estimate, e);
		fit->coef[t].lo = ldexp(fit->coef[t].lo, e);
		fit->coef[t].hi = ldexp(fit->coef[t].hi, e);
		fit->coef[t].var_sd = ldexp(fit->coef[t].var_sd, 2 * e);
		fit->coef[t].square = ldexp(fit->coef[t].square, 2 * e);
		for (int u = 0; u < 5; u++)
			fit->sq_cov[t][u] = ldexp(fit->sq_cov[t][u], 4 * e);
	}
	fit->readoff.n = ldexp(fit->readoff.n, e);
	fit->readoff.b = ldexp(fit->readoff.b, e);
	fit->readoff.k = ldexp(fit->readoff.k, e);
	return rc;
}

/* ------------------------------------------------------------------ */
/* One call                                                            */
/* ------------------------------------------------------------------ */

static int grid_points(struct sscope_allan *p, const double *x,
		       size_t stride, size_t n, double rate_hz,
		       enum sscope_allan_tau_grid grid,
		       struct sscope_allan_point **pts, size_t *n_pts,
		       struct sscope_diag *diag)
{
	size_t np = sscope_allan_n_phase(p->opts.input, n), cnt, *m;
	size_t mmax = sscope_allan_max_m(p->opts.dev, np);
	int rc = sscope_allan_grid(grid, mmax, NULL, 0, &cnt);

	*pts = NULL;
	*n_pts = 0;
	if (rc)
		return rc;
	if (cnt == 0)
		return ssc_diag(diag, -EDOM,
				"too short for %s: %zu sample%s (averaging factor 1 needs %zu)",
				sscope_allan_dev_name(p->opts.dev), n,
				n == 1 ? "" : "s",
				min_samples(p->opts.dev, 1,
					    p->opts.input == SSCOPE_ALLAN_ANGLE));
	m = ssc_alloc_array(cnt + 1, sizeof(size_t));
	/* (2 MiB pages for an all-tau grid's megabytes: see ssc_hint_huge) */
	*pts = ssc_alloc_huge(cnt + 1, sizeof(**pts));
	if (!m || !*pts) {
		free(m);
		free(*pts);
		*pts = NULL;
		return -ENOMEM;
	}
	sscope_allan_grid(grid, mmax, m, cnt, &cnt);
	/* Theo1 reaches 0.75 of the record: the largest even m ends the grid */
	if (theo_dev(p->opts.dev) && grid != SSCOPE_ALLAN_TAUS_ALL &&
	    (mmax & ~(size_t)1) > m[cnt - 1])
		m[cnt++] = mmax & ~(size_t)1;
	rc = sscope_allan_compute(p, x, stride, n, rate_hz, m, cnt, *pts,
				  n_pts, diag);
	free(m);
	if (rc) {
		free(*pts);
		*pts = NULL;
		*n_pts = 0;
	}
	return rc;
}

/* longest stretch of finite samples of x */
static size_t longest_run(const double *x, size_t stride, size_t n)
{
	size_t best = 0, cur = 0;

	for (size_t k = 0; k < n; k++) {
		cur = isnan(x[k * stride]) ? 0 : cur + 1;
		if (cur > best)
			best = cur;
	}
	return best;
}

/*
 * Gaps: the taus whose every term spans a NaN sample (terms 0) leave the
 * result, counted and explained in res->gap_note; none left is -EDOM.
 */
static int drop_gap_taus(struct sscope_allan_result *res, const double *x,
			 size_t stride, size_t n, double rate_hz,
			 enum sscope_allan_dev dev, struct sscope_diag *diag)
{
	size_t k = 0, run;
	double first = NAN;
	char b[48];

	for (size_t j = 0; j < res->n_points; j++) {
		if (res->points[j].terms == 0) {
			if (isnan(first))
				first = res->points[j].tau_s;
			continue;
		}
		res->points[k++] = res->points[j];
	}
	res->n_gap_omitted = res->n_points - k;
	if (!res->n_gap_omitted)
		return 0;
	run = longest_run(x, stride, n);
	snprintf(b, sizeof(b), "%zu sample%s, %.4g s", run, run == 1 ? "" : "s",
		 (double)run / rate_hz);
	if (k == 0) {
		res->n_points = 0;
		return ssc_diag(diag, -EDOM,
				"NaN gaps leave no %s term without a gap at any tau (the longest stretch without one is %s): fill the gaps or analyse a record with longer gap-free stretches",
				sscope_allan_dev_name(dev), b);
	}
	snprintf(res->gap_note.msg, sizeof(res->gap_note.msg),
		 "NaN gaps leave no %s term without a gap at %zu of the %zu taus (from %.4g s; the longest stretch without a gap is %s): those taus are left out; longer gap-free stretches reach them",
		 sscope_allan_dev_name(dev), res->n_gap_omitted, res->n_points,
		 first, b);
	res->n_points = k;
	return 0;
}

int sscope_allan_analyze(const double *x, size_t stride, size_t n,
			 double rate_hz, enum sscope_allan_tau_grid grid,
			 const struct sscope_allan_opts *aopts,
			 const struct sscope_noise_fit_opts *fopts,
			 struct sscope_allan_result **resp,
			 struct sscope_diag *diag)
{
	struct sscope_allan_opts o = { 0 };
	struct sscope_allan *p = NULL;
	struct sscope_allan_result *res;
	enum sscope_allan_tau_grid fit_grid;
	int rc;

	if (!resp || !x || n == 0)
		return ssc_diag(diag, -EINVAL, "allan: bad parameters");
	*resp = NULL;
	if (aopts)
		o = *aopts;
	res = calloc(1, sizeof(*res));
	if (!res)
		return -ENOMEM;
	rc = sscope_allan_new(&p, n, &o);
	if (rc)
		goto fail;
	res->n_phase = sscope_allan_n_phase(o.input, n);
	rc = grid_points(p, x, stride, n, rate_hz, grid, &res->points,
			 &res->n_points, diag);
	if (rc)
		goto fail;
	rc = drop_gap_taus(res, x, stride, n, rate_hz, o.dev, diag);
	if (rc)
		goto fail;
	/* the fit of an all-tau grid uses the dense grid's points:
	 * neighbouring taus are almost fully correlated, add nothing to the
	 * fit and would make its covariance (quadratic in the points) the
	 * whole cost.  Computed on their own (a few dozen taus): an interval's
	 * type depends on the shorter tau of the grid (compute()), so the
	 * dense points of the all-tau grid are not the dense grid's. */
	fit_grid = grid == SSCOPE_ALLAN_TAUS_ALL ? SSCOPE_ALLAN_TAUS_DENSE : grid;
	if ((o.dev == SSCOPE_ALLAN_DEV_OADEV && fit_grid == grid) ||
	    (fopts && fopts->skip)) {
		res->oadev = res->points;
		res->n_oadev = res->n_points;
	} else {
		struct sscope_diag d2;

		p->opts.dev = SSCOPE_ALLAN_DEV_OADEV;
		p->opts.stride_div = 0;
		rc = grid_points(p, x, stride, n, rate_hz, fit_grid,
				 &res->oadev, &res->n_oadev, &d2);
		if (rc)
			goto fail;
		/* (the fit passes over taus without terms) */
	}
	if (!fopts || !fopts->skip) {
		res->fit_error = fit_scaled(res->oadev, res->n_oadev, rate_hz,
					    res->n_phase, fopts, &res->fit,
					    &res->fit_diag);
		res->have_fit = res->fit_error == 0;
	}
	sscope_allan_free(p);
	*resp = res;
	return 0;
fail:
	sscope_allan_free(p);
	sscope_allan_result_free(res);
	return rc;
}

void sscope_allan_result_free(struct sscope_allan_result *res)
{
	if (!res)
		return;
	if (res->oadev != res->points)
		free(res->oadev);
	free(res->points);
	free(res);
}
