/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Statistics and timing: exact small cases, a large offset that naive
 * one-pass formulas destroy, NaN handling, strides, gaps and jitter.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <string.h>
#include <stdlib.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "check-main.h"

START_TEST(exact_small)
{
	const double x[] = { 2, 4, 4, 4, 5, 5, 7, 9 };
	struct sscope_stats s;

	ck_assert_int_eq(sscope_stats_compute(x, 1, 8, &s), 0);
	ck_assert_uint_eq(s.n, 8);
	ck_assert(s.mean == 5);
	ck_assert_rel(s.sd, sqrt(32.0 / 7.0), 1e-15);
	ck_assert(s.min == 2 && s.max == 9);
	/* stride 2 picks 2, 4, 5, 7 */
	ck_assert_int_eq(sscope_stats_compute(x, 2, 4, &s), 0);
	ck_assert(s.mean == 4.5);
	ck_assert_rel(s.sd, sqrt(13.0 / 3.0), 1e-15);
}
END_TEST

START_TEST(large_offset)
{
	/* offset 1e9 times the spread: the variance must survive */
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	size_t n = 100000;
	double *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));
	struct sscope_stats a, b;

	gsl_rng_set(r, 7);
	for (size_t i = 0; i < n; i++) {
		y[i] = gsl_ran_gaussian_ziggurat(r, 2.385);
		x[i] = 2.385e9 + y[i];
	}
	ck_assert_int_eq(sscope_stats_compute(y, 1, n, &b), 0);
	ck_assert_int_eq(sscope_stats_compute(x, 1, n, &a), 0);
	/* x = y + c is exact to half an ulp of 2.4e9 (2.4e-7) per sample:
	 * sd agrees to ~1e-7 relative */
	ck_assert_rel(a.sd, b.sd, 3e-7);
	ck_assert_msg(fabs(a.mean - 2.385e9 - b.mean) < 1e-6, "mean %.17g", a.mean);
	free(x);
	free(y);
	gsl_rng_free(r);
}
END_TEST

START_TEST(nan_and_edges)
{
	const double x[] = { NAN, 1, NAN, 3 };
	const double z[] = { NAN, NAN };
	struct sscope_stats s;

	ck_assert_int_eq(sscope_stats_compute(x, 1, 4, &s), 0);
	ck_assert_uint_eq(s.n_nan, 2);
	ck_assert(s.mean == 2);
	ck_assert_int_eq(sscope_stats_compute(z, 1, 2, &s), -EDOM);
	ck_assert_int_eq(sscope_stats_compute(x, 0, 2, &s), -EINVAL);
	ck_assert_int_eq(sscope_stats_compute(x + 1, 1, 1, &s), 0);
	ck_assert(s.sd == 0);
	{
		/* subnormal samples: the rescaling once overflowed to inf
		 * (mean NaN); 4 and 6 units of 2^-1074 apart by 2 */
		const double t[] = { 0x1p-1072, 0x1.8p-1072 };

		ck_assert_int_eq(sscope_stats_compute(t, 1, 2, &s), 0);
		ck_assert_msg(s.mean == 0x1.4p-1072, "mean %a", s.mean);
		/* sqrt(2) units, to the unit (the sd is subnormal too) */
		ck_assert_msg(fabs(s.sd / 0x1p-1074 - sqrt(2.0)) <= 0.5,
			      "sd %a", s.sd);
	}
}
END_TEST

START_TEST(timing_gaps)
{
	double t[1000], scratch[999];
	struct sscope_timing tm;
	struct sscope_timing_gap g[4];
	size_t ng, k = 0;

	for (size_t i = 0; i < 1003; i++) {
		if (i == 100 || i == 101 || i == 500)
			continue; /* three samples lost, in two gaps */
		/* every 4th stamp late by 10 us: intervals 10.01, 9.99, 10,
		 * 10 ms, so the median is 10 ms and the rms deviation
		 * 10 us / sqrt(2) */
		t[k++] = (double)i * 0.01 + ((i % 4 == 0) ? 1e-5 : 0);
	}
	ck_assert_int_eq(sscope_timing_analyze(t, 1000, 1.5, &tm, g, 4, &ng,
					       scratch), 0);
	ck_assert_rel(tm.dt_median_s, 0.01, 1e-12);
	ck_assert_uint_eq(tm.n_gaps, 2);
	ck_assert_uint_eq(ng, 2);
	ck_assert_uint_eq(tm.n_missing, 3);
	ck_assert_uint_eq(g[0].index, 100);
	ck_assert_uint_eq(g[0].missing, 2);
	ck_assert_uint_eq(g[1].missing, 1);
	ck_assert_rel(tm.jitter_rms_s, 1e-5 / sqrt(2), 0.01);
	ck_assert_rel(tm.rate_hz, 100, 1e-5); /* first stamp late by 10 us */
	ck_assert_int_eq(sscope_timing_analyze(t, 1, 1.5, &tm, NULL, 0, NULL,
					       scratch), -EDOM);
	for (size_t i = 0; i < 10; i++)
		t[i] = 5;
	ck_assert_int_eq(sscope_timing_analyze(t, 10, 1.5, &tm, NULL, 0, NULL,
					       scratch), -EDOM);
	ck_assert_int_eq(sscope_timing_analyze(t, 10, 0.5, &tm, NULL, 0, NULL,
					       scratch), -EINVAL);
}
END_TEST

/* The Student-t interval of a mean: with two values t has one degree of
 * freedom (Cauchy, quantile tan(pi (p - 1/2))): level 0.5 -> t = 1, so
 * {1, 3} gives 2 -+ s / sqrt(2) = 2 -+ 1; NaN values are skipped. */
START_TEST(mean_interval)
{
	double x[] = { 1, NAN, 3 }, m, lo, hi;
	size_t k;

	ck_assert_int_eq(sscope_stats_mean_interval(x, 1, 3, 0.5, &m, &lo, &hi, &k), 0);
	ck_assert_uint_eq(k, 2);
	ck_assert(m == 2);
	ck_assert_rel(lo, 1, 1e-12);
	ck_assert_rel(hi, 3, 1e-12);
	/* level 0.9: tan(0.45 pi) = 6.3138 */
	ck_assert_int_eq(sscope_stats_mean_interval(x, 1, 3, 0.9, &m, &lo, &hi, NULL), 0);
	ck_assert_rel(hi - m, tan(0.45 * 3.14159265358979323846), 1e-9);
	/* one value: a mean, no interval; none: -EDOM */
	ck_assert_int_eq(sscope_stats_mean_interval(x, 2, 1, 0.5, &m, &lo, &hi, &k), 0);
	ck_assert(m == 1 && isnan(lo) && isnan(hi) && k == 1);
	ck_assert_int_eq(sscope_stats_mean_interval(x + 1, 1, 1, 0.5, &m, &lo, &hi, &k), -EDOM);
	ck_assert(isnan(m) && k == 0);
	ck_assert_int_eq(sscope_stats_mean_interval(x, 1, 3, 1, &m, &lo, &hi, &k), -EINVAL);
}
END_TEST

/* feed t in pieces of `piece` stamps and check; returns the code and
 * leaves the message in d */
static int order_of(const double *t, size_t n, size_t piece,
		    struct sscope_timing_order *o, struct sscope_diag *d)
{
	*o = (struct sscope_timing_order){ 0 };
	for (size_t i = 0; i < n; i += piece)
		sscope_timing_order_feed(o, t + i, n - i < piece ? n - i : piece);
	d->msg[0] = '\0';
	return sscope_timing_order_check(o, d);
}

/* Time columns that are not increasing: each problem named, the same
 * whether fed at once or stamp by stamp (a streaming reader's chunks) */
START_TEST(time_order)
{
	double t[64], scratch[63];
	struct sscope_timing_order o;
	struct sscope_timing tm;
	struct sscope_diag d;
	const size_t n = 40;

	for (size_t piece = 1; piece <= n; piece += 13) {
		for (size_t i = 0; i < n; i++)
			t[i] = 0.01 * (double)i;
		ck_assert_int_eq(order_of(t, n, piece, &o, &d), 0);
		ck_assert_int_eq(order_of(t, 1, piece, &o, &d), -EDOM);
		ck_assert_str_eq(d.msg, "has one row");
		/* one swapped pair (rows 3 and 4, 1-based) */
		t[2] = 0.03;
		t[3] = 0.02;
		ck_assert_int_eq(order_of(t, n, piece, &o, &d), -EDOM);
		ck_assert_msg(strstr(d.msg, "has rows 3 and 4 in reverse order"),
			      "%s", d.msg);
		ck_assert_uint_eq(o.n_decreasing, 1);
		/* a second pair, at the very end */
		t[n - 2] = 0.01 * (double)(n - 1);
		t[n - 1] = 0.01 * (double)(n - 2);
		ck_assert_int_eq(order_of(t, n, piece, &o, &d), -EDOM);
		ck_assert_msg(strstr(d.msg, "and 1 more swapped pair"), "%s", d.msg);
		/* a repeated stamp (row 4 repeats row 3) */
		for (size_t i = 0; i < n; i++)
			t[i] = 0.01 * (double)i;
		t[3] = t[2];
		ck_assert_int_eq(order_of(t, n, piece, &o, &d), -EDOM);
		ck_assert_msg(strstr(d.msg, "repeats the stamp of row 3 at row 4"),
			      "%s", d.msg);
		ck_assert_uint_eq(o.n_repeats, 1);
		ck_assert_uint_eq(o.n_decreasing, 0);
		/* a clock reset: backwards, not a swap */
		for (size_t i = 0; i < n; i++)
			t[i] = 0.01 * (double)(i < 20 ? i + 100 : i);
		ck_assert_int_eq(order_of(t, n, piece, &o, &d), -EDOM);
		ck_assert_msg(strstr(d.msg, "goes backwards once (first at row 21"),
			      "%s", d.msg);
		/* constant; decreasing */
		for (size_t i = 0; i < n; i++)
			t[i] = 2.5;
		ck_assert_int_eq(order_of(t, n, piece, &o, &d), -EDOM);
		ck_assert_msg(strstr(d.msg, "is constant"), "%s", d.msg);
		for (size_t i = 0; i < n; i++)
			t[i] = -0.01 * (double)i;
		ck_assert_int_eq(order_of(t, n, piece, &o, &d), -EDOM);
		ck_assert_msg(strstr(d.msg, "decreases in every row"), "%s", d.msg);
	}
	ck_assert_int_eq(sscope_timing_order_check(NULL, NULL), -EINVAL);
	/* the analysis: a swapped pair is neither two gaps nor part of the
	 * rate; a repeated stamp does not lower the rate */
	for (size_t i = 0; i < n; i++)
		t[i] = 0.01 * (double)i;
	t[10] = 0.11;
	t[11] = 0.10;
	ck_assert_int_eq(sscope_timing_analyze(t, n, 1.5, &tm, NULL, 0, NULL,
					       scratch), 0);
	ck_assert_uint_eq(tm.n_gaps, 0);
	ck_assert_uint_eq(tm.n_backwards, 1);
	ck_assert_rel(tm.rate_hz, 100, 1e-12);
	ck_assert_int_eq(sscope_timing_order_check(&tm.order, NULL), -EDOM);
	for (size_t i = 0; i < n; i++)
		t[i] = 0.01 * (double)(i < 10 ? i : i - 1);
	ck_assert_int_eq(sscope_timing_analyze(t, n, 1.5, &tm, NULL, 0, NULL,
					       scratch), 0);
	ck_assert_uint_eq(tm.n_gaps, 0);
	ck_assert_uint_eq(tm.order.n_repeats, 1);
	ck_assert_rel(tm.rate_hz, 100, 1e-12);
	/* -EDOM analyses still describe the order */
	ck_assert_int_eq(sscope_timing_analyze(t, 1, 1.5, &tm, NULL, 0, NULL,
					       scratch), -EDOM);
	ck_assert_uint_eq(tm.order.n, 1);
}
END_TEST

/* The median interval: from the table of distinct intervals (scratch
 * untouched) and, past 512 distinct values, from the intervals written
 * to scratch; an even count takes the mean of the two middle values. */
static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return (x > y) - (x < y);
}

START_TEST(timing_median)
{
	enum { N = 2001 };
	double *t = malloc(N * sizeof(double)), *scratch = malloc(N * sizeof(double));
	double *d = malloc(N * sizeof(double));
	struct sscope_timing tm;

	ck_assert(t && scratch && d);
	for (int many = 0; many < 2; many++) {
		for (size_t n = 8; n <= N; n += n < 100 ? 1 : 331) {
			double want;

			t[0] = 2.385;
			for (size_t i = 1; i < n; i++)
				t[i] = t[i - 1] + (many ? 0.01 + 1e-7 * (double)((i * 7919) % 1000) :
							  (i % 3 ? 0.01 : 0.013));
			for (size_t i = 1; i < n; i++)
				d[i - 1] = t[i] - t[i - 1];
			qsort(d, n - 1, sizeof(double), cmp_d);
			want = (n - 1) % 2 ? d[(n - 2) / 2] :
					     (d[(n - 1) / 2 - 1] + d[(n - 1) / 2]) / 2;
			for (size_t i = 0; i < n; i++)
				scratch[i] = -1;
			ck_assert_int_eq(sscope_timing_analyze(t, n, 1.5, &tm, NULL, 0, NULL,
							       scratch), 0);
			ck_assert_msg(tm.dt_median_s == want, "n %zu: median %.17g, want %.17g",
				      n, tm.dt_median_s, want);
			ck_assert(tm.dt_min_s == d[0] && tm.dt_max_s == d[n - 2]);
			if (!many || n < 600)
				ck_assert(scratch[0] == -1 && scratch[n - 2] == -1);
			else
				ck_assert(scratch[0] != -1);
		}
	}
	free(t);
	free(scratch);
	free(d);
}
END_TEST

/* The order check is fed block by block beside the intervals: every
 * stamp once, the last one too (a record one stamp past a block, its last
 * stamp a step back), on the table path and on the scratch path. */
START_TEST(timing_order_blocks)
{
	static const size_t sizes[] = { 4097, 8193, 8192, 5000 };
	double *t = malloc(8200 * sizeof(double)), *scratch = malloc(8200 * sizeof(double));

	ck_assert(t && scratch);
	for (int many = 0; many < 2; many++)
		for (size_t k = 0; k < sizeof(sizes) / sizeof(sizes[0]); k++) {
			size_t n = sizes[k];
			struct sscope_timing tm;
			struct sscope_timing_order whole;

			memset(&whole, 0, sizeof(whole));
			for (size_t i = 0; i < n; i++)
				t[i] = 2.385 + 0.01 * (double)i +
				       (many ? 1e-7 * (double)((i * 7919) % 1000) : 0);
			t[n - 1] = t[n - 2] - 0.005;
			sscope_timing_order_feed(&whole, t, n);
			ck_assert_int_eq(sscope_timing_analyze(t, n, 1.5, &tm, NULL, 0, NULL,
							       scratch), 0);
			ck_assert_uint_eq(tm.order.n, n);
			ck_assert_uint_eq(tm.order.n_decreasing, 1);
			ck_assert(!memcmp(&tm.order, &whole, sizeof(whole)));
		}
	free(t);
	free(scratch);
}
END_TEST

/* The two passes of sscope_timing_split_*, in either order, joined: the
 * numbers of the plain definitions (intervals sorted for the median;
 * forward intervals, gaps, then the regular ones summed in order with the
 * same compensated sum for the rate and the jitter), and every field of
 * sscope_timing_analyze()'s results, on regular, gapped, swapped,
 * repeating and jittered stamps. */
static void plain_timing(const double *t, size_t n, double gf, double *med,
			 double *rate, double *jitter, size_t *n_gaps,
			 size_t *missing)
{
	double *d = malloc(n * sizeof(double));
	struct ssc_ksum s = { 0, 0 }, j = { 0, 0 };
	size_t nj = 0, m = n - 1;
	double mean;
	bool *fw = calloc(n, sizeof(bool));

	ck_assert(d && fw);
	for (size_t i = 1; i < n; i++) {
		d[i - 1] = t[i] - t[i - 1];
		fw[i] = t[i] > t[i - 1] && !(i >= 2 && t[i - 1] < t[i - 2]) &&
			!(i + 1 < n && t[i + 1] < t[i]);
	}
	qsort(d, m, sizeof(double), cmp_d);
	*med = m % 2 ? d[m / 2] : (d[m / 2 - 1] + d[m / 2]) / 2;
	*n_gaps = *missing = 0;
	for (size_t i = 1; i < n; i++) {
		double x = t[i] - t[i - 1];

		if (!fw[i])
			continue;
		if (x > gf * *med) {
			++*n_gaps;
			*missing += (size_t)llround(x / *med) - 1;
		} else {
			ssc_ksum_add(&s, x);
			nj++;
		}
	}
	mean = ssc_ksum_value(&s) / (double)nj;
	*rate = 1 / mean;
	for (size_t i = 1; i < n; i++) {
		double x = t[i] - t[i - 1];

		if (fw[i] && !(x > gf * *med))
			ssc_ksum_add(&j, (x - mean) * (x - mean));
	}
	*jitter = sqrt(ssc_ksum_value(&j) / (double)nj);
	free(d);
	free(fw);
}

START_TEST(timing_split)
{
	enum { N = 30011 };
	double *t = malloc(N * sizeof(double)), *scratch = malloc(N * sizeof(double));
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	ck_assert(t && scratch && r);
	gsl_rng_set(r, 2385);
	for (int kind = 0; kind < 6; kind++) {
		for (size_t n = 3; n <= N; n = n * 3 + 7) {
			struct sscope_timing a, b;
			struct sscope_timing_split sp;
			struct sscope_timing_gap ga[4], gb[4];
			size_t nga = 0, ngb = 0, ng, miss;
			double med, rate, jit;

			for (size_t i = 0; i < n; i++)
				t[i] = 1.7e9 + (double)i / 238.5 +
				       (kind == 4 ? 1e-6 * gsl_rng_uniform(r) : 0);
			if (kind == 1 || kind == 5) /* gaps */
				for (size_t i = n / 3; i < n; i++)
					t[i] += (double)(1 + (i > n / 2)) / 238.5 * 2.5;
			if ((kind == 2 || kind == 5) && n > 4) { /* a swap */
				double x = t[n / 4];

				t[n / 4] = t[n / 4 + 1];
				t[n / 4 + 1] = x;
			}
			if (kind == 3 && n > 4) /* a repeat */
				t[n / 2] = t[n / 2 - 1];
			ck_assert_int_eq(sscope_timing_analyze(t, n, 1.5, &a, ga, 4, &nga,
							       scratch), 0);
			memset(&sp, 0x5a, sizeof(sp));
			if (n % 2) {
				ck_assert_int_eq(sscope_timing_split_sums(&sp, t, n), 0);
				ck_assert_int_eq(sscope_timing_split_median(&sp, t, n, scratch), 0);
			} else {
				ck_assert_int_eq(sscope_timing_split_median(&sp, t, n, scratch), 0);
				ck_assert_int_eq(sscope_timing_split_sums(&sp, t, n), 0);
			}
			ck_assert_int_eq(sscope_timing_split_join(&sp, t, n, 1.5, &b, gb, 4,
								    &ngb), 0);
			plain_timing(t, n, 1.5, &med, &rate, &jit, &ng, &miss);
			ck_assert_msg(b.dt_median_s == med && b.rate_hz == rate &&
				      b.jitter_rms_s == jit,
				      "kind %d n %zu: %.17g %.17g %.17g, want %.17g %.17g %.17g",
				      kind, n, b.dt_median_s, b.rate_hz, b.jitter_rms_s,
				      med, rate, jit);
			ck_assert_uint_eq(b.n_gaps, ng);
			ck_assert_uint_eq(b.n_missing, miss);
			/* the cases are what they are meant to be (a repeated
			 * stamp leaves a double interval after it) */
			if (n > 100)
				ck_assert_msg(b.n_gaps == (kind == 1 || kind == 5 ? 2u :
							   kind == 3 ? 1u : 0u),
					      "kind %d: %zu gaps", kind, b.n_gaps);
			ck_assert(a.dt_median_s == b.dt_median_s && a.rate_hz == b.rate_hz &&
				  a.jitter_rms_s == b.jitter_rms_s &&
				  a.dt_min_s == b.dt_min_s && a.dt_max_s == b.dt_max_s);
			ck_assert(a.n_gaps == b.n_gaps && a.n_missing == b.n_missing &&
				  a.n_backwards == b.n_backwards);
			ck_assert(!memcmp(&a.order, &b.order, sizeof(a.order)));
			ck_assert_uint_eq(nga, ngb);
			ck_assert(!memcmp(ga, gb, nga * sizeof(ga[0])));
		}
	}
	{
		struct sscope_timing_split sp;
		struct sscope_timing tm;

		/* one stamp: its order, and -EDOM as from the one call */
		ck_assert_int_eq(sscope_timing_split_median(&sp, t, 1, scratch), 0);
		ck_assert_int_eq(sscope_timing_split_sums(&sp, t, 1), 0);
		ck_assert_int_eq(sscope_timing_split_join(&sp, t, 1, 1.5, &tm, NULL, 0,
							    NULL), -EDOM);
		ck_assert_uint_eq(tm.order.n, 1);
		ck_assert_int_eq(sscope_timing_split_median(NULL, t, 5, scratch), -EINVAL);
		ck_assert_int_eq(sscope_timing_split_median(&sp, t, 5, NULL), -EINVAL);
		ck_assert_int_eq(sscope_timing_split_sums(&sp, NULL, 5), -EINVAL);
		ck_assert_int_eq(sscope_timing_split_join(&sp, t, 5, 1, &tm, NULL, 0,
							    NULL), -EINVAL);
		ck_assert_int_eq(sscope_timing_split_join(NULL, t, 5, 1.5, &tm, NULL, 0,
							    NULL), -EINVAL);
	}
	gsl_rng_free(r);
	free(t);
	free(scratch);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("stats");
	TCase *tc = tcase_create("stats");

	tcase_add_test(tc, exact_small);
	tcase_add_test(tc, large_offset);
	tcase_add_test(tc, nan_and_edges);
	tcase_add_test(tc, timing_gaps);
	tcase_add_test(tc, mean_interval);
	tcase_add_test(tc, time_order);
	tcase_add_test(tc, timing_median);
	tcase_add_test(tc, timing_order_blocks);
	tcase_add_test(tc, timing_split);
	suite_add_tcase(s, tc);
	return s;
}
