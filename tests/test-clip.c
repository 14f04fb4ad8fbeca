/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Clipped data (analysis/clip.c): Gaussian noise continuous and quantized
 * and sines of many amplitudes are never called clipped (the arcsine
 * bound 1 / (sqrt 2 - 1) on a sine's outermost code is checked too); the
 * same signals limited to a range are, on the side that was limited;
 * constant, NaN and bad arguments; the skipping of blocks against the plain
 * one-pass definition; the clip fed by the statistics' pass against the
 * two calls; the envelopes of bins found in the same pass against their
 * plain definition.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "check-main.h"

#define N 20000

static struct sscope_clip detect(const double *x, size_t n)
{
	struct sscope_clip c;

	ck_assert_int_eq(sscope_clip_detect(x, 1, n, SSCOPE_CLIP_MIN_COUNT,
					    SSCOPE_CLIP_RATIO, &c), 0);
	return c;
}

/* x limited to [lo, hi]; how many were moved on each side */
static void limit(double *x, size_t n, double lo, double hi, size_t *nlo,
		  size_t *nhi)
{
	*nlo = *nhi = 0;
	for (size_t i = 0; i < n; i++) {
		if (x[i] <= lo) {
			x[i] = lo;
			++*nlo;
		} else if (x[i] >= hi) {
			x[i] = hi;
			++*nhi;
		}
	}
}

START_TEST(noise)
{
	double *x = malloc(N * sizeof(double));
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	struct sscope_clip c;
	size_t nlo, nhi;

	ck_assert_ptr_nonnull(x);
	for (unsigned long seed = 1; seed <= 100; seed++) {
		/* continuous, then quantized to 1 LSB at sd 0.45, 0.6, 1.7 and
		 * 23.85 LSB around 2.385 LSB: never clipped */
		static const double sd[] = { 0, 0.45, 0.6, 1.7, 23.85 };

		for (size_t s = 0; s < sizeof(sd) / sizeof(sd[0]); s++) {
			gsl_rng_set(r, seed);
			for (size_t i = 0; i < N; i++) {
				double v = 2.385 + gsl_ran_gaussian_ziggurat(r, sd[s] ? sd[s] : 1);

				x[i] = sd[s] ? round(v) : v;
			}
			c = detect(x, N);
			ck_assert_msg(!c.low && !c.high,
				      "seed %lu sd %g: %zu at %g (next %zu), %zu at %g (next %zu)",
				      seed, sd[s], c.n_lo, c.lo, c.n_lo_next,
				      c.n_hi, c.hi, c.n_hi_next);
			if (!sd[s])
				ck_assert(c.n_hi == 1 && c.n_lo == 1);
		}
	}
	/* the continuous noise limited above at 2 sd: high only, and every
	 * sample moved is counted at the limit */
	gsl_rng_set(r, 7);
	for (size_t i = 0; i < N; i++)
		x[i] = 0.013 * gsl_ran_gaussian_ziggurat(r, 1);
	limit(x, N, -1, 0.026, &nlo, &nhi);
	c = detect(x, N);
	ck_assert(c.high && !c.low);
	ck_assert_uint_eq(c.n_hi, nhi);
	ck_assert_uint_eq(c.n_hi_next, 1);
	ck_assert(c.hi == 0.026);
	/* quantized at sd 23.85 LSB, limited below at -2 sd: low only (the
	 * tail beyond t sd over one code at t, Q(t) / (phi(t) h) for codes
	 * h sd wide, is 10 here; at 3 LSB it would be 1.3: a limit in the
	 * tail of coarsely quantized noise is not told from the tail) */
	gsl_rng_set(r, 8);
	for (size_t i = 0; i < N; i++)
		x[i] = round(23.85 * gsl_ran_gaussian_ziggurat(r, 1));
	limit(x, N, -48, 1000, &nlo, &nhi);
	c = detect(x, N);
	ck_assert(c.low && !c.high);
	ck_assert_uint_eq(c.n_lo, nlo);
	ck_assert(c.lo == -48);
	gsl_rng_free(r);
	free(x);
}
END_TEST

START_TEST(sines)
{
	double *x = malloc(N * sizeof(double)), worst = 0;
	size_t nlo, nhi;

	ck_assert_ptr_nonnull(x);
	/* amplitudes 1.3 .. 400 LSB, quantized, 0.0127321 cycles a sample */
	for (double a = 1.3; a < 400; a *= 1.0371) {
		struct sscope_clip c;

		for (size_t i = 0; i < N; i++)
			x[i] = round(a * sin(2 * M_PI * 0.0127321 * (double)i + 0.3));
		c = detect(x, N);
		ck_assert_msg(!c.low && !c.high, "amplitude %g", a);
		worst = fmax(worst, (double)c.n_hi / (double)c.n_hi_next);
		/* the same sine limited at 97 % of its crest: both sides once
		 * the limit is 3 codes inside it (the pile-up over one code at
		 * the limit is about twice the overshoot in codes) */
		limit(x, N, round(-0.97 * a), round(0.97 * a), &nlo, &nhi);
		c = detect(x, N);
		if (0.03 * a > 3)
			ck_assert_msg(c.low && c.high, "limited, amplitude %g", a);
	}
	/* the arcsine bound, with 3 % for the finite record */
	ck_assert_msg(worst < 1.03 / (sqrt(2) - 1), "worst ratio %g", worst);
	ck_assert_msg(worst > 1.5, "worst ratio %g", worst);
	free(x);
}
END_TEST

START_TEST(edges)
{
	const double k[] = { 3.5, 3.5, 3.5, 3.5, 3.5, 3.5, 3.5, 3.5, 3.5, 3.5 };
	double y[12];
	struct sscope_clip c;

	/* constant: nothing inward, not clipped */
	c = detect(k, 10);
	ck_assert(!c.low && !c.high && c.n_hi == 10 && c.n_hi_next == 0);
	/* NaN and inf are skipped; 9 at the top over 1 below */
	for (size_t i = 0; i < 12; i++)
		y[i] = i < 9 ? 1.25 : -0.5;
	y[9] = NAN;
	y[10] = INFINITY;
	c = detect(y, 12);
	ck_assert(c.high && !c.low && c.n_hi == 9 && c.n_hi_next == 1);
	/* below min_count: not a clip */
	ck_assert_int_eq(sscope_clip_detect(y, 1, 12, 10, 4, &c), 0);
	ck_assert(!c.high);
	/* stride */
	ck_assert_int_eq(sscope_clip_detect(y, 3, 4, 2, 4, &c), 0);
	ck_assert(c.n_hi == 3 && c.n_hi_next == 0 && c.hi == 1.25);
	ck_assert_int_eq(sscope_clip_detect(y + 9, 1, 2, 8, 4, &c), -EDOM);
	ck_assert_int_eq(sscope_clip_detect(NULL, 1, 2, 8, 4, &c), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect(y, 0, 2, 8, 4, &c), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect(y, 1, 2, 1, 4, &c), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect(y, 1, 2, 8, 1, &c), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect(y, 1, 2, 8, NAN, &c), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect(y, 1, 2, 8, 4, NULL), -EINVAL);
}
END_TEST


/* The plain one-pass definition, sample by sample: the oracle for the
 * block skipping of clip.c. */
struct ref_top2 {
	double v, next;
	size_t n, n_next;
};

static void ref_add(struct ref_top2 *t, double x)
{
	if (x > t->v) {
		t->next = t->v;
		t->n_next = t->n;
		t->v = x;
		t->n = 1;
	} else if (x == t->v) {
		t->n++;
	} else if (x > t->next) {
		t->next = x;
		t->n_next = 1;
	} else if (x == t->next) {
		t->n_next++;
	}
}

START_TEST(blocks_equal_plain_pass)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	const size_t n = 5000;
	double *x = malloc(3 * n * sizeof(double));

	ck_assert_ptr_nonnull(x);
	gsl_rng_set(r, 1511);
	for (int t = 0; t < 400; t++) {
		size_t stride = 1 + (size_t)(t % 3), m = 1 + gsl_rng_uniform_int(r, n);
		double q = t % 4 == 0 ? 0 : ldexp(1, -(int)gsl_rng_uniform_int(r, 8));
		struct ref_top2 hi = { -INFINITY, -INFINITY, 0, 0 }, lo = hi;
		struct sscope_clip c;

		for (size_t i = 0; i < m * stride; i++) {
			double v = gsl_ran_gaussian(r, 1.0);

			/* quantized, clipped, the extreme late, NaN and inf */
			if (q > 0)
				v = q * nearbyint(v / q);
			if (t % 5 == 1)
				v = v > 1.5 ? 1.5 : v < -1.5 ? -1.5 : v;
			if (gsl_rng_uniform(r) < 0.001)
				v = (double[]){ NAN, INFINITY, -INFINITY, 9.5, -9.5 }
					[gsl_rng_uniform_int(r, 5)];
			if (t % 7 == 3 && i + 10 * stride > m * stride)
				v = 20 + (double)(i % 2);
			x[i] = v;
		}
		for (size_t i = 0; i < m; i++) {
			double v = x[i * stride];

			if (isfinite(v)) {
				ref_add(&hi, v);
				ref_add(&lo, -v);
			}
		}
		ck_assert_int_eq(sscope_clip_detect(x, stride, m, SSCOPE_CLIP_MIN_COUNT,
						    SSCOPE_CLIP_RATIO, &c), 0);
		ck_assert(c.hi == hi.v && c.lo == -lo.v);
		ck_assert_uint_eq(c.n_hi, hi.n);
		ck_assert_uint_eq(c.n_lo, lo.n);
		ck_assert_uint_eq(c.n_hi_next, hi.n_next);
		ck_assert_uint_eq(c.n_lo_next, lo.n_next);
	}
	free(x);
	gsl_rng_free(r);
}
END_TEST

/* the same oracle on long records whose blocks are mostly skipped
 * (quantized noise with NaN and inf, a ramp up, a ramp down, stride 3) */
START_TEST(long_records)
{
	const size_t n = 300001;
	double *x = malloc(n * sizeof(double));
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	ck_assert(x && r);
	gsl_rng_set(r, 2385);
	for (int kind = 0; kind < 4; kind++) {
		size_t stride = kind == 3 ? 3 : 1, m = n / stride;
		struct ref_top2 hi = { -INFINITY, -INFINITY, 0, 0 }, lo = hi;
		struct sscope_clip c;

		for (size_t i = 0; i < n; i++)
			x[i] = kind == 1 ? (double)i * 0.25 :
			       kind == 2 ? -(double)i * 0.25 :
			       round(gsl_ran_gaussian(r, 2.385) * 8) / 8;
		if (kind == 0)
			for (size_t i = 0; i < n; i += 1009)
				x[i] = i % 2 ? (double)NAN : (double)INFINITY;
		for (size_t i = 0; i < m; i++) {
			double v = x[i * stride];

			if (isfinite(v)) {
				ref_add(&hi, v);
				ref_add(&lo, -v);
			}
		}
		ck_assert_int_eq(sscope_clip_detect(x, stride, m, 2, 4, &c), 0);
		ck_assert_msg(c.hi == hi.v && c.lo == -lo.v && c.n_hi == hi.n &&
				      c.n_hi_next == hi.n_next && c.n_lo == lo.n &&
				      c.n_lo_next == lo.n_next,
			      "kind %d: %g x%zu %g x%zu vs %g x%zu %g x%zu", kind,
			      c.hi, c.n_hi, c.lo, c.n_lo, hi.v, hi.n, -lo.v, lo.n);
	}
	gsl_rng_free(r);
	free(x);
}
END_TEST

/* sscope_clip_detect_stats() against the two calls it stands for: the same
 * return, statistics and clip, bit for bit, over quantized and clipped
 * noise with leading NaN, inf, huge samples (the statistics' scaled second
 * pass), strides and lengths across the blocks; all NaN; bad arguments. */
START_TEST(stats_clip_equals_two_calls)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	const size_t n = 9000;
	double *x = malloc(2 * n * sizeof(double));
	struct sscope_stats s1, s2;
	struct sscope_clip c1, c2;

	ck_assert(x && r);
	gsl_rng_set(r, 4242);
	for (int t = 0; t < 300; t++) {
		size_t stride = 1 + (size_t)(t % 2), m = 1 + gsl_rng_uniform_int(r, n);
		size_t lead = t % 3 == 0 ? gsl_rng_uniform_int(r, 50) : 0;
		double q = t % 4 == 0 ? 0 : ldexp(1, -(int)gsl_rng_uniform_int(r, 8));
		double big = t % 11 == 5 ? 1e300 : 1;
		int rc1, rc2, rc3;

		for (size_t i = 0; i < m * stride; i++) {
			double v = gsl_ran_gaussian(r, 1.0) + (t % 6 == 2 ? 1e9 : 0);

			if (q > 0)
				v = q * nearbyint(v / q);
			if (t % 5 == 1)
				v = v > 1.5 ? 1.5 : v < -1.5 ? -1.5 : v;
			if (t % 13 == 7 && gsl_rng_uniform(r) < 0.001)
				v = (double[]){ NAN, INFINITY, -INFINITY }
					[gsl_rng_uniform_int(r, 3)];
			x[i] = i / stride < lead ? (double)NAN : v * big;
		}
		memset(&c1, 0x5a, sizeof(c1));
		memset(&c2, 0x5a, sizeof(c2));
		rc1 = sscope_stats_compute(x, stride, m, &s1);
		rc3 = sscope_clip_detect(x, stride, m, SSCOPE_CLIP_MIN_COUNT,
					 SSCOPE_CLIP_RATIO, &c1);
		rc2 = sscope_clip_detect_stats(x, stride, m, SSCOPE_CLIP_MIN_COUNT,
					       SSCOPE_CLIP_RATIO, &s2, &c2);
		ck_assert_int_eq(rc1, rc2);
		ck_assert_msg(memcmp(&s1, &s2, sizeof(s1)) == 0, "t %d: stats differ", t);
		ck_assert_msg(rc3 == 0 || rc3 == -EDOM, "t %d: clip %d", t, rc3);
		ck_assert_msg(c1.hi == c2.hi && c1.lo == c2.lo && c1.n_hi == c2.n_hi &&
				      c1.n_lo == c2.n_lo && c1.n_hi_next == c2.n_hi_next &&
				      c1.n_lo_next == c2.n_lo_next &&
				      c1.high == c2.high && c1.low == c2.low,
			      "t %d: clip differs", t);
		/* without a clip: the statistics alone */
		ck_assert_int_eq(sscope_clip_detect_stats(x, stride, m, 0, 0, &s2, NULL), rc1);
		ck_assert(memcmp(&s1, &s2, sizeof(s1)) == 0);
	}
	/* nothing finite: the statistics' -EDOM, the clip untouched */
	for (size_t i = 0; i < 100; i++)
		x[i] = NAN;
	memset(&c2, 0x5a, sizeof(c2));
	memset(&c1, 0x5a, sizeof(c1));
	ck_assert_int_eq(sscope_clip_detect_stats(x, 1, 100, 8, 4, &s2, &c2), -EDOM);
	ck_assert(memcmp(&c1, &c2, sizeof(c1)) == 0);
	ck_assert_int_eq(sscope_clip_detect_stats(NULL, 1, 100, 8, 4, &s2, &c2), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect_stats(x, 0, 100, 8, 4, &s2, &c2), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect_stats(x, 1, 100, 8, 4, NULL, &c2), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect_stats(x, 1, 100, 1, 4, &s2, &c2), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect_stats(x, 1, 100, 8, 1, &s2, &c2), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect_stats(x, 1, 100, 8, INFINITY, &s2, &c2), -EINVAL);
	gsl_rng_free(r);
	free(x);
}
END_TEST

/* The plain definition of a bin's envelope: samples k of
 * [n b / nb, n (b + 1) / nb) (products exact for these sizes), their
 * smallest and largest non-NaN value, the first index of each, NaN count. */
static void envelope_plain(const double *x, size_t stride, size_t n,
			   size_t nb, size_t b, struct sscope_clip_envelope *e)
{
	size_t i0 = n * b / nb, i1 = n * (b + 1) / nb;

	e->lo = e->hi = NAN;
	e->i_lo = e->i_hi = SIZE_MAX;
	e->n_nan = 0;
	for (size_t i = i0; i < i1; i++) {
		double v = x[i * stride];

		if (isnan(v)) {
			e->n_nan++;
			continue;
		}
		if (e->i_lo == SIZE_MAX || v < e->lo) {
			e->lo = v;
			e->i_lo = i;
		}
		if (e->i_hi == SIZE_MAX || v > e->hi) {
			e->hi = v;
			e->i_hi = i;
		}
	}
}

/* sscope_clip_detect_stats_envelope(): the statistics and clip of
 * sscope_clip_detect_stats() bit for bit, and each bin's envelope as the
 * plain definition finds it (values ==, same indices), over quantized
 * noise with ties, signed zeros, NaN runs, infinities, strides, leading
 * NaN, bins smaller and larger than the statistics' blocks, more bins than
 * samples; all NaN; no sample; bad arguments. */
START_TEST(envelope_equals_plain)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	const size_t n = 12000, nbs[] = { 1, 3, 7, 64, 4096, 20000 };
	double *x = malloc(2 * n * sizeof(double));
	struct sscope_clip_envelope *e = malloc(20000 * sizeof(*e)), p;
	struct sscope_stats s1, s2;
	struct sscope_clip c1, c2;
	size_t checked_ties = 0;

	ck_assert(x && e && r);
	gsl_rng_set(r, 2385);
	for (int t = 0; t < 240; t++) {
		size_t stride = 1 + (size_t)(t % 2), m = 1 + gsl_rng_uniform_int(r, n);
		size_t nb = nbs[t % 6];
		size_t lead = t % 3 == 0 ? gsl_rng_uniform_int(r, 3000) : 0;
		double q = t % 4 == 0 ? 0 : ldexp(1, -(int)gsl_rng_uniform_int(r, 3));
		int rc1, rc2;

		for (size_t i = 0; i < m * stride; i++) {
			double v = gsl_ran_gaussian(r, 1.0);

			if (q > 0)
				v = q * nearbyint(v / q); /* ties, and -0 */
			if (t % 5 == 1 && gsl_rng_uniform(r) < 0.01)
				v = (double[]){ NAN, INFINITY, -INFINITY, -0.0 }
					[gsl_rng_uniform_int(r, 4)];
			if (t % 7 == 3 && (i / stride) % 3000 < 700)
				v = NAN; /* runs of NaN across bins */
			x[i] = i / stride < lead ? (double)NAN : v;
		}
		memset(e, 0x5a, nb * sizeof(*e));
		memset(&c1, 0x5a, sizeof(c1)); /* the padding too */
		memset(&c2, 0x5a, sizeof(c2));
		rc1 = sscope_clip_detect_stats(x, stride, m, SSCOPE_CLIP_MIN_COUNT,
					       SSCOPE_CLIP_RATIO, &s1, &c1);
		rc2 = sscope_clip_detect_stats_envelope(
			x, stride, m, SSCOPE_CLIP_MIN_COUNT, SSCOPE_CLIP_RATIO,
			&s2, &c2, nb, e);
		ck_assert_int_eq(rc1, rc2);
		ck_assert_msg(memcmp(&s1, &s2, sizeof(s1)) == 0, "t %d: stats differ", t);
		ck_assert_msg(rc1 == -EDOM || memcmp(&c1, &c2, sizeof(c1)) == 0,
			      "t %d: clip differs", t);
		for (size_t b = 0; b < nb; b++) {
			envelope_plain(x, stride, m, nb, b, &p);
			ck_assert_msg(p.n_nan == e[b].n_nan && p.i_lo == e[b].i_lo &&
					      p.i_hi == e[b].i_hi,
				      "t %d bin %zu: nan %zu/%zu lo at %zu/%zu hi at %zu/%zu",
				      t, b, e[b].n_nan, p.n_nan, e[b].i_lo, p.i_lo,
				      e[b].i_hi, p.i_hi);
			ck_assert_msg((isnan(p.lo) && isnan(e[b].lo)) || p.lo == e[b].lo,
				      "t %d bin %zu: lo", t, b);
			ck_assert_msg((isnan(p.hi) && isnan(e[b].hi)) || p.hi == e[b].hi,
				      "t %d bin %zu: hi", t, b);
			if (q > 0 && p.i_lo != SIZE_MAX)
				checked_ties++;
		}
	}
	ck_assert(checked_ties > 1000);
	/* nothing finite: -EDOM, every bin all NaN */
	for (size_t i = 0; i < 100; i++)
		x[i] = NAN;
	ck_assert_int_eq(sscope_clip_detect_stats_envelope(x, 1, 100, 8, 4, &s2, &c2,
							   7, e), -EDOM);
	for (size_t b = 0; b < 7; b++) {
		envelope_plain(x, 1, 100, 7, b, &p);
		ck_assert(isnan(e[b].lo) && isnan(e[b].hi) &&
			  e[b].i_lo == SIZE_MAX && e[b].i_hi == SIZE_MAX &&
			  e[b].n_nan == p.n_nan);
	}
	/* no sample: every bin empty */
	ck_assert_int_eq(sscope_clip_detect_stats_envelope(x, 1, 0, 8, 4, &s2, NULL,
							   3, e), -EDOM);
	for (size_t b = 0; b < 3; b++)
		ck_assert(isnan(e[b].lo) && e[b].i_hi == SIZE_MAX && e[b].n_nan == 0);
	/* no bins: the statistics alone */
	ck_assert_int_eq(sscope_clip_detect_stats_envelope(x, 1, 100, 8, 4, &s2, NULL,
							   0, NULL), -EDOM);
	ck_assert_int_eq(sscope_clip_detect_stats_envelope(x, 1, 100, 8, 4, &s2, NULL,
							   3, NULL), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect_stats_envelope(x, 1, 100, 8, 4, &s2, NULL,
							   SIZE_MAX, e), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect_stats_envelope(x, 0, 100, 8, 4, &s2, NULL,
							   3, e), -EINVAL);
	ck_assert_int_eq(sscope_clip_detect_stats_envelope(x, 1, 100, 1, 4, &s2, &c2,
							   3, e), -EINVAL);
	gsl_rng_free(r);
	free(e);
	free(x);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("clip");
	TCase *tc = tcase_create("clip");

	tcase_set_timeout(tc, 60);
	tcase_add_test(tc, noise);
	tcase_add_test(tc, sines);
	tcase_add_test(tc, edges);
	tcase_add_test(tc, blocks_equal_plain_pass);
	tcase_add_test(tc, long_records);
	tcase_add_test(tc, stats_clip_equals_two_calls);
	tcase_add_test(tc, envelope_equals_plain);
	suite_add_tcase(s, tc);
	return s;
}
