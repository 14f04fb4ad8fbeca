/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Summary statistics in one pass over memory.  The record is taken in
 * blocks of a few kilobytes; each block, while it is in the L1 cache, gets
 * the two-pass treatment (its mean, then the sum of squared deviations from
 * it with the correction term of Chan, Golub & LeVeque, "Algorithms for
 * computing the sample variance", Am. Stat. 1983, eq. 1.7), and the blocks
 * are merged with the pairwise update of the same paper (eq. 1.5b).  Values
 * are shifted by the first finite sample and the block sums and merged
 * squares are added with Neumaier compensation, so an offset 1e9 times the
 * spread still leaves the mean and the spread their digits.  Contiguous
 * blocks without NaN run on vectors (GCC vector extensions, lanes summed
 * in a fixed order); a block holding NaN is redone sample by sample.
 * Samples whose largest magnitude lies outside [2^-300, 2^300] are summed
 * again, sample by sample, scaled by a power of two (exact), so that
 * neither the differences (1e308 - -1e308) nor the squares (1e200^2,
 * 1e-300^2) leave the double range; the results are scaled back.
 * The envelope of bins of the record (smallest and largest sample, where
 * each first shows, NaN count) is gathered in the same pass: a block that
 * lies in one bin gives its extremes as found for the statistics, one cut
 * by a bin's edge is looked at again in pieces while it is in the cache,
 * and each bin's extremes are looked up, once, in the piece they came from.
 */
#include "internal.h"

#include <math.h>
#include <string.h>

#include "sscope-clip.h"
#include "sscope-stats.h"

#define SBLOCK 1024

#define SSC_SCLONES SSC_TARGET_CLONES("avx2", "default")

#if defined(__GNUC__)
typedef double ssc_sv4 __attribute__((vector_size(32)));
typedef long long ssc_sv4i __attribute__((vector_size(32)));
#define SV4LOAD(v, p) memcpy(&(v), (p), sizeof(ssc_sv4))
#endif

double ssc_safe_scale(double amax)
{
	int e;

	if (!(amax > 0x1p-300 && amax < 0x1p300) && amax > 0 && isfinite(amax)) {
		frexp(amax, &e);
		/* a subnormal amax has e below -1022: 2^-e would overflow */
		return ldexp(1.0, -e > 1000 ? 1000 : -e);
	}
	return 1;
}

int ssc_magnitude_check(const double *x, size_t stride, size_t n, int lim,
			const char *what, struct sscope_diag *diag)
{
	double amax = 0;

	for (size_t k = 0; k < n; k++) {
		double a = fabs(x[k * stride]);

		if (a > amax && isfinite(a))
			amax = a;
	}
	if (amax > ldexp(1.0, lim) || (amax > 0 && amax < ldexp(1.0, -lim)))
		return ssc_diag(diag, -ERANGE,
				"%s: the largest magnitude, %g, lies outside 2^-%d .. 2^%d, the range this analysis squares without overflow or underflow",
				what, amax, lim, lim);
	return 0;
}

struct blk {
	size_t cnt, nan;
	double sum, q, c; /* shifted sum; squares and sum of deviations */
	double lo, hi;
};

/* one block of contiguous samples without NaN, on vectors; false when a
 * NaN shows (the caller redoes the block) */
SSC_SCLONES static bool block_vec(const double *x, size_t len, double v0,
				  struct blk *o)
{
#if defined(__GNUC__)
	const ssc_sv4 inf = { INFINITY, INFINITY, INFINITY, INFINITY };
	ssc_sv4 a = { 0 }, ah = { 0 }, lo = inf, hi = -inf, q = { 0 },
		qh = { 0 }, c = { 0 }, ch = { 0 };
	double mb;
	size_t i;

	if (len % 8)
		return false;
	for (i = 0; i < len; i += 8) {
		ssc_sv4 v, vh;
		ssc_sv4i m;

		SV4LOAD(v, x + i);
		SV4LOAD(vh, x + i + 4);
		a += v - v0;
		ah += vh - v0;
		m = (ssc_sv4i)(v < lo);
		lo = (ssc_sv4)(((ssc_sv4i)v & m) | ((ssc_sv4i)lo & ~m));
		m = (ssc_sv4i)(vh < lo);
		lo = (ssc_sv4)(((ssc_sv4i)vh & m) | ((ssc_sv4i)lo & ~m));
		m = (ssc_sv4i)(v > hi);
		hi = (ssc_sv4)(((ssc_sv4i)v & m) | ((ssc_sv4i)hi & ~m));
		m = (ssc_sv4i)(vh > hi);
		hi = (ssc_sv4)(((ssc_sv4i)vh & m) | ((ssc_sv4i)hi & ~m));
	}
	a += ah;
	o->sum = (a[0] + a[1]) + (a[2] + a[3]);
	if (isnan(o->sum))
		return false;
	o->cnt = len;
	o->nan = 0;
	o->lo = fmin(fmin(lo[0], lo[1]), fmin(lo[2], lo[3]));
	o->hi = fmax(fmax(hi[0], hi[1]), fmax(hi[2], hi[3]));
	mb = o->sum / (double)len;
	for (i = 0; i < len; i += 8) {
		ssc_sv4 v, vh, d, dh;

		SV4LOAD(v, x + i);
		SV4LOAD(vh, x + i + 4);
		d = (v - v0) - mb;
		dh = (vh - v0) - mb;
		q += d * d;
		qh += dh * dh;
		c += d;
		ch += dh;
	}
	q += qh;
	c += ch;
	o->q = (q[0] + q[1]) + (q[2] + q[3]);
	o->c = (c[0] + c[1]) + (c[2] + c[3]);
	return true;
#else
	(void)x;
	(void)len;
	(void)v0;
	(void)o;
	return false;
#endif
}

/* any block, sample by sample, samples times sc (a power of two) */
static void block_scalar(const double *x, size_t stride, size_t len,
			 double v0, double sc, struct blk *o)
{
	double a[4] = { 0, 0, 0, 0 }, q[4] = { 0, 0, 0, 0 };
	double c[4] = { 0, 0, 0, 0 }, lo = INFINITY, hi = -INFINITY, mb;
	size_t nan = 0;

	for (size_t i = 0; i < len; i++) {
		double v = x[i * stride] * sc;

		if (isnan(v)) {
			nan++;
			continue;
		}
		a[i & 3] += v - v0;
		lo = v < lo ? v : lo;
		hi = v > hi ? v : hi;
	}
	o->cnt = len - nan;
	o->nan = nan;
	o->lo = lo;
	o->hi = hi;
	o->sum = (a[0] + a[1]) + (a[2] + a[3]);
	if (!o->cnt)
		return;
	mb = o->sum / (double)o->cnt;
	for (size_t i = 0; i < len; i++) {
		double v = x[i * stride] * sc, d;

		if (isnan(v))
			continue;
		d = (v - v0) - mb;
		q[i & 3] += d * d;
		c[i & 3] += d;
	}
	o->q = (q[0] + q[1]) + (q[2] + q[3]);
	o->c = (c[0] + c[1]) + (c[2] + c[3]);
}

#include <gsl/gsl_cdf.h>

/* the bins' envelopes, gathered block by block */
struct env_acc {
	struct sscope_clip_envelope *bins;
	const double *x;
	size_t stride, n, nb;
	size_t b, i0, i1; /* the current bin and its samples */
	double lo, hi;
	size_t lo_at, lo_len, hi_at, hi_len; /* pieces of its first lo, hi */
	size_t seen, nan; /* samples not NaN, NaN, so far */
};

/* first sample of bin b: floor(n b / nb) without overflow (b (n % nb)
 * < nb (nb - 1), checked by the caller) */
static size_t bin_start(const struct env_acc *a, size_t b)
{
	return b * (a->n / a->nb) + b * (a->n % a->nb) / a->nb;
}

static void env_start(struct env_acc *a, size_t b)
{
	a->b = b;
	a->i0 = bin_start(a, b);
	a->i1 = bin_start(a, b + 1);
	a->lo = INFINITY;
	a->hi = -INFINITY;
	a->seen = 0;
	a->nan = 0;
}

/* the first k in [at, at + len) with x[k] == v (there is one) */
SSC_SCLONES static size_t first_equal(const double *x, size_t stride,
				      size_t at, size_t len, double v)
{
	size_t i = at, end = at + len;

#if defined(__GNUC__)
	if (stride == 1) {
		const ssc_sv4 vv = { v, v, v, v };

		for (; i + 4 <= end; i += 4) {
			ssc_sv4 w;
			ssc_sv4i m;

			SV4LOAD(w, x + i);
			m = (ssc_sv4i)(w == vv);
			if (m[0] | m[1] | m[2] | m[3])
				break;
		}
	}
#endif
	while (x[i * stride] != v)
		i++;
	return i;
}

static void env_close(struct env_acc *a)
{
	struct sscope_clip_envelope *e = &a->bins[a->b];

	e->n_nan = a->nan;
	if (!a->seen) {
		e->lo = e->hi = NAN;
		e->i_lo = e->i_hi = SIZE_MAX;
		return;
	}
	e->lo = a->lo;
	e->hi = a->hi;
	e->i_lo = first_equal(a->x, a->stride, a->lo_at, a->lo_len, a->lo);
	e->i_hi = first_equal(a->x, a->stride, a->hi_at, a->hi_len, a->hi);
}

/* samples [i, i + len) of the current bin: extremes lo, hi of those not
 * NaN, nan of them NaN */
static void env_piece(struct env_acc *a, size_t i, size_t len, double lo,
		      double hi, size_t nan)
{
	a->nan += nan;
	if (nan == len)
		return;
	if (!a->seen || lo < a->lo) {
		a->lo = lo;
		a->lo_at = i;
		a->lo_len = len;
	}
	if (!a->seen || hi > a->hi) {
		a->hi = hi;
		a->hi_at = i;
		a->hi_len = len;
	}
	a->seen += len - nan;
}

/* extremes and NaN count of a piece (the block's own when it is whole) */
SSC_SCLONES static void piece_scan(const double *x, size_t stride, size_t len,
				   double *plo, double *phi, size_t *pnan)
{
	double lo = INFINITY, hi = -INFINITY;
	size_t i = 0, nan = 0;

#if defined(__GNUC__)
	if (stride == 1 && len >= 4) {
		const ssc_sv4 inf = { INFINITY, INFINITY, INFINITY, INFINITY };
		ssc_sv4 l = inf, h = -inf;
		ssc_sv4i c = { 0, 0, 0, 0 };

		for (; i + 4 <= len; i += 4) {
			ssc_sv4 v;
			ssc_sv4i m;

			SV4LOAD(v, x + i);
			c -= (ssc_sv4i)(v != v);
			m = (ssc_sv4i)(v < l);
			l = (ssc_sv4)(((ssc_sv4i)v & m) | ((ssc_sv4i)l & ~m));
			m = (ssc_sv4i)(v > h);
			h = (ssc_sv4)(((ssc_sv4i)v & m) | ((ssc_sv4i)h & ~m));
		}
		for (int k = 0; k < 4; k++) {
			lo = l[k] < lo ? l[k] : lo;
			hi = h[k] > hi ? h[k] : hi;
			nan += (size_t)c[k];
		}
	}
#endif
	for (; i < len; i++) {
		double v = x[i * stride];

		if (isnan(v)) {
			nan++;
			continue;
		}
		lo = v < lo ? v : lo;
		hi = v > hi ? v : hi;
	}
	*plo = lo;
	*phi = hi;
	*pnan = nan;
}

/* samples [i, i + len); k: the block's statistics (NULL: all NaN) */
static void env_feed(struct env_acc *a, size_t i, size_t len,
		     const struct blk *k)
{
	bool whole = true; /* [i, i + len) is still the whole block */

	for (; len; whole = false) {
		size_t m;
		double lo, hi;
		size_t nan;

		while (i >= a->i1) {
			env_close(a);
			env_start(a, a->b + 1);
		}
		m = a->i1 - i < len ? a->i1 - i : len;
		if (!k) {
			lo = INFINITY;
			hi = -INFINITY;
			nan = m;
		} else if (whole && m == len) {
			/* the whole block: its extremes are known */
			lo = k->lo;
			hi = k->hi;
			nan = k->nan;
		} else {
			piece_scan(a->x + i * a->stride, a->stride, m, &lo, &hi,
				   &nan);
		}
		env_piece(a, i, m, lo, hi, nan);
		i += m;
		len -= m;
	}
}

/* one pass; sc != 1: samples scaled by sc, sample by sample, and not
 * shifted (one huge sample first would leave its rounding in every term) */
static void pass(const double *x, size_t stride, size_t n, size_t first,
		 double sc, struct sscope_stats *st, struct ssc_clip_acc *ca,
		 struct env_acc *ea)
{
	struct ssc_ksum s = { 0, 0 }, m2 = { 0, 0 };
	size_t used = 0, nan = first;
	double v0 = sc == 1 ? x[first * stride] : 0, lo = INFINITY,
	       hi = -INFINITY, m2v;

	for (size_t b = first; b < n; b += SBLOCK) {
		const size_t len = n - b < SBLOCK ? n - b : SBLOCK;
		struct blk k;
		double mb;

		if (sc != 1 || stride != 1 || !block_vec(x + b, len, v0, &k))
			block_scalar(x + b * stride, stride, len, v0, sc, &k);
		/* the block is in the cache; one strictly inside both of the
		 * clip's runners-up (its extremes as found above) changes
		 * nothing there */
		if (ca && !(isfinite(ca->hi.next) && isfinite(ca->lo.next) &&
			    k.hi < ca->hi.next && -k.lo < ca->lo.next))
			ssc_clip_feed(ca, x + b * stride, stride, len);
		if (ea)
			env_feed(ea, b, len, &k);
		nan += k.nan;
		if (k.cnt == 0)
			continue;
		lo = k.lo < lo ? k.lo : lo;
		hi = k.hi > hi ? k.hi : hi;
		mb = k.sum / (double)k.cnt;
		/* M2 += M2_b + delta^2 n_a n_b / (n_a + n_b) */
		ssc_ksum_add(&m2, k.q - k.c * k.c / (double)k.cnt);
		if (used) {
			double delta = mb - ssc_ksum_value(&s) / (double)used;

			ssc_ksum_add(&m2, delta * delta *
						  ((double)used * (double)k.cnt /
						   (double)(used + k.cnt)));
		}
		ssc_ksum_add(&s, k.sum);
		used += k.cnt;
	}
	m2v = ssc_ksum_value(&m2);
	st->n = used;
	st->n_nan = nan;
	st->mean = (v0 + ssc_ksum_value(&s) / (double)used) / sc;
	st->min = lo / sc;
	st->max = hi / sc;
	st->sd = used < 2 || !(m2v > 0) ? 0 :
					  sqrt(m2v / (double)(used - 1)) / sc;
}

/* the statistics, and the clip detection fed when ca */
static int stats_clip(const double *x, size_t stride, size_t n,
		      struct sscope_stats *st, struct ssc_clip_acc *ca,
		      struct env_acc *ea)
{
	size_t first = 0;
	double lo, hi, sc;

	st->n = 0;
	st->n_nan = 0;
	while (first < n && isnan(x[first * stride]))
		first++;
	if (ea && first)
		env_feed(ea, 0, first, NULL);
	if (first == n) {
		st->n_nan = n;
		return -EDOM;
	}
	pass(x, stride, n, first, 1, st, ca, ea);
	/* extremes: the sums again, scaled; min and max as found */
	sc = ssc_safe_scale(fmax(fabs(st->min), fabs(st->max)));
	if (sc != 1) {
		lo = st->min;
		hi = st->max;
		pass(x, stride, n, first, sc, st, NULL, NULL);
		st->min = lo;
		st->max = hi;
	}
	/* the mean lies within [min, max]; only the sd (up to sqrt(2) times
	 * the largest magnitude) can leave the range */
	if (!isfinite(st->sd))
		return -ERANGE;
	return 0;
}

int sscope_stats_compute(const double *x, size_t stride, size_t n,
			 struct sscope_stats *st)
{
	if (!x || !st || stride == 0)
		return -EINVAL;
	return stats_clip(x, stride, n, st, NULL, NULL);
}

int sscope_clip_detect_stats(const double *x, size_t stride, size_t n,
			     size_t min_count, double ratio,
			     struct sscope_stats *st, struct sscope_clip *c)
{
	return sscope_clip_detect_stats_envelope(x, stride, n, min_count,
						 ratio, st, c, 0, NULL);
}

int sscope_clip_detect_stats_envelope(const double *x, size_t stride,
				      size_t n, size_t min_count, double ratio,
				      struct sscope_stats *st,
				      struct sscope_clip *c, size_t n_bins,
				      struct sscope_clip_envelope *bins)
{
	struct ssc_clip_acc ca;
	struct env_acc ea, *pe = NULL;
	int rc;

	if (!x || !st || stride == 0 ||
	    (c && !ssc_clip_args_ok(min_count, ratio)) ||
	    (n_bins && !bins) ||
	    (n_bins > 1 && n_bins > SIZE_MAX / (n_bins - 1)))
		return -EINVAL;
	if (n_bins) {
		ea = (struct env_acc){ .bins = bins, .x = x, .stride = stride,
				       .n = n, .nb = n_bins };
		env_start(&ea, 0);
		pe = &ea;
	}
	if (c)
		ssc_clip_init(&ca);
	rc = stats_clip(x, stride, n, st, c ? &ca : NULL, pe);
	/* the leading NaN the statistics skip hold nothing finite */
	if (c)
		ssc_clip_finish(&ca, min_count, ratio, c);
	if (pe) {
		/* the last bin with samples, then the empty ones after it */
		for (;;) {
			env_close(pe);
			if (pe->b + 1 >= n_bins)
				break;
			env_start(pe, pe->b + 1);
		}
	}
	return rc;
}

int sscope_stats_mean_interval(const double *x, size_t stride, size_t n,
			       double level, double *mean, double *lo,
			       double *hi, size_t *used)
{
	struct ssc_ksum s = { 0, 0 }, q = { 0, 0 };
	size_t k = 0;
	double m;

	if (!x || !mean || !lo || !hi || stride == 0 || !(level > 0 && level < 1))
		return -EINVAL;
	*mean = *lo = *hi = NAN;
	if (used)
		*used = 0;
	for (size_t i = 0; i < n; i++)
		if (isfinite(x[i * stride])) {
			ssc_ksum_add(&s, x[i * stride]);
			k++;
		}
	if (used)
		*used = k;
	if (!k)
		return -EDOM;
	m = ssc_ksum_value(&s) / (double)k;
	*mean = m;
	if (k < 2)
		return 0;
	for (size_t i = 0; i < n; i++)
		if (isfinite(x[i * stride]))
			ssc_ksum_add(&q, (x[i * stride] - m) * (x[i * stride] - m));
	{
		double se = sqrt(ssc_ksum_value(&q) / (double)(k - 1) / (double)k);
		double t = gsl_cdf_tdist_Pinv(0.5 + level / 2, (double)(k - 1));

		*lo = m - t * se;
		*hi = m + t * se;
	}
	return 0;
}
