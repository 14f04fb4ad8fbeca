/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Sampling analysis of a time column: the median interval (robust to gaps
 * and outliers) separates gaps (intervals longer than a stated factor of
 * it) from regular intervals; the rate is the number of regular intervals
 * over their compensated sum (their mean, which for an unbroken record is
 * the span over n - 1: one rounding, where a median of differences of
 * rounded stamps would carry their rounding); jitter is the rms deviation
 * of the regular intervals from that mean.  Intervals that are not
 * positive, and the two around a backward step (rows swapped), are
 * disorder, counted and described (sscope_timing_order_*) but neither gaps
 * nor regular intervals.
 */
#include "internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_statistics_double.h>

#include <stdio.h>

#include "sscope-timing.h"

/*
 * Order of the stamps: a backward step at row i is a swapped pair when
 * exchanging rows i - 1 and i restores the order around them, t[i-2] <
 * t[i] and t[i-1] < t[i+1]; the second condition waits for the next stamp
 * (o->pending), or for the end of the data.
 */
void sscope_timing_order_feed(struct sscope_timing_order *o, const double *t_s,
			      size_t n)
{
	/* the state in locals: the stores to *o could otherwise alias t_s */
	struct sscope_timing_order s = *o;

	for (size_t k = 0; k < n; k++) {
		double t = t_s[k], prev = s.last_s[0];

		if (s.n == 0) {
			s.t0_s = t;
		} else {
			if (s.pending) {
				if (s.last_s[1] < t)
					s.n_swaps++;
				s.pending = 0;
			}
			if (!(t > prev)) {
				if (t == prev) {
					s.n_repeats++;
				} else {
					s.n_decreasing++;
					s.pending = s.n < 2 || s.last_s[1] < t;
				}
				if (s.n_repeats + s.n_decreasing == 1) {
					s.first_row = s.n;
					s.first_t_s = t;
					s.first_prev_s = prev;
				}
			}
		}
		s.last_s[2] = s.last_s[1];
		s.last_s[1] = s.last_s[0];
		s.last_s[0] = t;
		s.n++;
	}
	*o = s;
}

int sscope_timing_order_check(const struct sscope_timing_order *o,
			      struct sscope_diag *diag)
{
	size_t swaps, bad, more;
	char tail[64] = "", count[32];

	if (!o)
		return -EINVAL;
	if (o->n < 2)
		return ssc_diag(diag, -EDOM, o->n ? "has one row" : "has no rows");
	if (o->n_repeats == o->n - 1)
		return ssc_diag(diag, -EDOM,
				"is constant (every row has the same stamp)");
	if (o->n_decreasing == o->n - 1)
		return ssc_diag(diag, -EDOM,
				"decreases in every row (the last stamp is %.9g s before the first)",
				o->t0_s - o->last_s[0]);
	bad = o->n_repeats + o->n_decreasing;
	if (bad == 0)
		return 0;
	more = bad - 1;
	swaps = o->n_swaps + (o->pending ? 1 : 0);
	if (more)
		snprintf(tail, sizeof(tail), " and %zu more %s", more,
			 o->n_repeats ? (more > 1 ? "times" : "time") :
			 more > 1 ? "swapped pairs" : "swapped pair");
	if (o->n_repeats == 0 && swaps == o->n_decreasing)
		return ssc_diag(diag, -EDOM,
				"has rows %zu and %zu in reverse order (%.9g s and %.9g s from the first stamp)%s",
				o->first_row, o->first_row + 1,
				o->first_prev_s - o->t0_s, o->first_t_s - o->t0_s,
				tail);
	if (o->n_decreasing == 0)
		return ssc_diag(diag, -EDOM,
				"repeats the stamp of row %zu at row %zu (%.9g s from the first stamp)%s",
				o->first_row, o->first_row + 1,
				o->first_t_s - o->t0_s, tail);
	if (o->n_repeats)
		snprintf(tail, sizeof(tail), ", repeats a stamp %zu time%s,",
			 o->n_repeats, o->n_repeats > 1 ? "s" : "");
	if (o->n_decreasing == 1)
		snprintf(count, sizeof(count), "once");
	else
		snprintf(count, sizeof(count), "%zu times", o->n_decreasing);
	return ssc_diag(diag, -EDOM,
			"goes backwards %s%s (first at row %zu: %.9g s after %.9g s from the first stamp)",
			count, tail, o->first_row + 1,
			o->first_t_s - o->t0_s, o->first_prev_s - o->t0_s);
}

/* Interval i (from row i - 1 to row i) can be a regular interval or a gap:
 * positive and not next to a backward step. */
static inline bool forward(const double *t, size_t n, size_t i)
{
	return t[i] > t[i - 1] && !(i >= 2 && t[i - 1] < t[i - 2]) &&
	       !(i + 1 < n && t[i + 1] < t[i]);
}

/*
 * What the median pass gathers besides the median: the extremes of the
 * intervals and the non-increasing ones.  The forward intervals' sum, count
 * and largest are the other pass's (sscope_timing_split_sums), which needs
 * no median: when no forward interval turns out to be a gap (the usual
 * record) its sum is the sum over the regular intervals, taken in the same
 * order, and the jitter about their mean, also formed there, is final.
 */
struct pass1 {
	double lo, hi;
	size_t nb;
};

static void pass1_init(struct pass1 *a)
{
	*a = (struct pass1){ INFINITY, -INFINITY, 0 };
}

static inline void pass1_add(struct pass1 *a, double d)
{
	if (d < a->lo)
		a->lo = d;
	if (d > a->hi)
		a->hi = d;
	if (!(d > 0))
		a->nb++;
}

/*
 * The intervals of a sampled record take few distinct values (stamps k/fs
 * rounded to double: some 25 over a day at 100 Hz).  Their median is then
 * found from a table of the distinct values and their counts, in one pass
 * and without writing the n - 1 intervals out: the two middle order
 * statistics are looked up, and combined by gsl_stats_median() itself (on
 * those two values, so exactly as it combines them in the whole series).
 * Returns 1 when the intervals hold more distinct values than the table.
 */
enum { FEW_SLOTS = 1024, FEW_MAX = FEW_SLOTS / 2 };

struct few {
	double v;
	size_t count;
};

static int cmp_few(const void *a, const void *b)
{
	double x = ((const struct few *)a)->v, y = ((const struct few *)b)->v;

	return (x > y) - (x < y);
}

/* stamps fed to the order check at a time, each block's intervals
 * examined while it is in cache (one pass over the stamps for both) */
enum { ORDER_BLOCK = 4096 };

/* feed the block of stamps from `from`; returns how many */
static size_t feed_block(struct sscope_timing_order *o, const double *t_s,
			 size_t n, size_t from)
{
	size_t k = n - from < ORDER_BLOCK ? n - from : ORDER_BLOCK;

	sscope_timing_order_feed(o, t_s + from, k);
	return k;
}

static int median_few(const double *t_s, size_t n, double *med,
		      struct pass1 *a, struct sscope_timing_order *o)
{
	struct few *tab = calloc(FEW_SLOTS, sizeof(*tab));
	unsigned char *used = calloc(FEW_SLOTS, 1);
	size_t distinct = 0, m = n - 1, cum = 0, rank[2], j = 0, fed = 0;
	double mid[2] = { 0, 0 };
	int rc = 0;

	if (!tab || !used) {
		rc = 1;
		goto out;
	}
	for (size_t i = 1; i < n; i++) {
		double d = t_s[i] - t_s[i - 1];
		uint64_t b;
		size_t k;

		if (i - 1 == fed)
			fed += feed_block(o, t_s, n, fed);
		pass1_add(a, d);
		if (isnan(d)) {
			rc = 1;
			goto out;
		}
		memcpy(&b, &d, sizeof(b));
		k = (size_t)((b * 0x9e3779b97f4a7c15ull) >> 54);
		while (used[k] && memcmp(&tab[k].v, &d, sizeof(d)))
			k = (k + 1) & (FEW_SLOTS - 1);
		if (!used[k]) {
			if (distinct == FEW_MAX) {
				rc = 1;
				goto out;
			}
			used[k] = 1;
			tab[k].v = d;
			distinct++;
		}
		tab[k].count++;
	}
	if (fed < n)
		feed_block(o, t_s, n, fed);
	for (size_t k = 0; k < FEW_SLOTS; k++)
		if (used[k])
			tab[j++] = tab[k];
	qsort(tab, distinct, sizeof(*tab), cmp_few);
	rank[0] = (m - 1) / 2;
	rank[1] = m / 2;
	for (size_t k = 0, r = 0; k < distinct && r < 2; k++) {
		cum += tab[k].count;
		while (r < 2 && rank[r] < cum)
			mid[r++] = tab[k].v;
	}
	*med = rank[0] == rank[1] ? mid[0] : gsl_stats_median(mid, 1, 2);
out:
	free(tab);
	free(used);
	return rc;
}

int sscope_timing_split_median(struct sscope_timing_split *sp,
				const double *t_s, size_t n, double *scratch)
{
	struct pass1 a;
	double med;

	if (!sp || !t_s || !scratch)
		return -EINVAL;
	memset(&sp->order, 0, sizeof(sp->order));
	sp->median_s = NAN;
	sp->min_s = sp->max_s = 0;
	sp->n_backwards = 0;
	if (n < 2) {
		sscope_timing_order_feed(&sp->order, t_s, n);
		return 0;
	}
	pass1_init(&a);
	if (median_few(t_s, n, &med, &a, &sp->order)) {
		size_t fed = 0;

		pass1_init(&a);
		memset(&sp->order, 0, sizeof(sp->order));
		for (size_t i = 1; i < n; i++) {
			double d = t_s[i] - t_s[i - 1];

			if (i - 1 == fed)
				fed += feed_block(&sp->order, t_s, n, fed);
			scratch[i - 1] = d;
			pass1_add(&a, d);
		}
		if (fed < n)
			feed_block(&sp->order, t_s, n, fed);
		med = gsl_stats_median(scratch, 1, n - 1);
	}
	sp->median_s = med;
	sp->min_s = a.lo;
	sp->max_s = a.hi;
	sp->n_backwards = a.nb;
	return 0;
}

int sscope_timing_split_sums(struct sscope_timing_split *sp, const double *t_s,
			     size_t n)
{
	struct ssc_ksum f = { 0, 0 }, j = { 0, 0 };
	double fmax = -INFINITY, mean;
	size_t fn = 0;

	if (!sp || !t_s)
		return -EINVAL;
	for (size_t i = 1; i < n; i++) {
		double d = t_s[i] - t_s[i - 1];

		if (forward(t_s, n, i)) {
			ssc_ksum_add(&f, d);
			fn++;
			if (d > fmax)
				fmax = d;
		}
	}
	/* the jitter as it is when no forward interval is a gap */
	mean = fn ? ssc_ksum_value(&f) / (double)fn : 0;
	for (size_t i = 1; i < n && fn; i++) {
		double d = t_s[i] - t_s[i - 1];

		if (forward(t_s, n, i))
			ssc_ksum_add(&j, (d - mean) * (d - mean));
	}
	sp->fsum_s = f.s;
	sp->fsum_c = f.c;
	sp->fmax_s = fmax;
	sp->n_forward = fn;
	sp->jsum_s = j.s;
	sp->jsum_c = j.c;
	return 0;
}

int sscope_timing_split_join(const struct sscope_timing_split *sp,
			     const double *t_s, size_t n, double gap_factor,
			     struct sscope_timing *tm,
			     struct sscope_timing_gap *gaps, size_t max_gaps,
			     size_t *n_gaps_out)
{
	struct ssc_ksum j = { 0, 0 }, sum = { 0, 0 };
	size_t nj = 0, ng = 0;
	double med, mean;
	bool gapped;

	if (!sp || !t_s || !tm || !(gap_factor > 1))
		return -EINVAL;
	memset(tm, 0, sizeof(*tm));
	if (n_gaps_out)
		*n_gaps_out = 0;
	tm->order = sp->order;
	if (n < 2)
		return -EDOM;
	med = sp->median_s;
	tm->n_backwards = sp->n_backwards;
	tm->dt_min_s = sp->min_s;
	tm->dt_max_s = sp->max_s;
	if (!(med > 0) || !isfinite(med))
		return -EDOM;
	tm->dt_median_s = med;
	gapped = sp->fmax_s > gap_factor * med;
	if (!gapped) {
		/* no gap: the forward intervals are the regular ones */
		sum = (struct ssc_ksum){ sp->fsum_s, sp->fsum_c };
		nj = sp->n_forward;
	}
	for (size_t i = 1; i < n && gapped; i++) {
		double d = t_s[i] - t_s[i - 1];

		if (!forward(t_s, n, i))
			continue;
		if (d > gap_factor * med) {
			size_t miss = (size_t)llround(d / med) - 1;

			if (gaps && ng < max_gaps) {
				gaps[ng].index = i;
				gaps[ng].t_s = t_s[i];
				gaps[ng].length_s = d;
				gaps[ng].missing = miss;
				ng++;
			}
			tm->n_gaps++;
			tm->n_missing += miss;
			continue;
		}
		ssc_ksum_add(&sum, d);
		nj++;
	}
	mean = nj ? ssc_ksum_value(&sum) / (double)nj : med;
	if (!(mean > 0))
		return -EDOM;
	tm->rate_hz = 1 / mean;
	if (!gapped)
		j = (struct ssc_ksum){ sp->jsum_s, sp->jsum_c };
	for (size_t i = 1; i < n && gapped; i++) {
		double d = t_s[i] - t_s[i - 1];

		if (!forward(t_s, n, i) || d > gap_factor * med)
			continue;
		ssc_ksum_add(&j, (d - mean) * (d - mean));
	}
	tm->jitter_rms_s = nj ? sqrt(ssc_ksum_value(&j) / (double)nj) : 0;
	if (n_gaps_out)
		*n_gaps_out = ng;
	return 0;
}

int sscope_timing_analyze(const double *t_s, size_t n, double gap_factor,
			  struct sscope_timing *tm, struct sscope_timing_gap *gaps,
			  size_t max_gaps, size_t *n_gaps_out, double *scratch)
{
	struct sscope_timing_split sp;

	if (!t_s || !tm || !scratch || !(gap_factor > 1))
		return -EINVAL;
	sscope_timing_split_median(&sp, t_s, n, scratch);
	sscope_timing_split_sums(&sp, t_s, n);
	return sscope_timing_split_join(&sp, t_s, n, gap_factor, tm, gaps,
					  max_gaps, n_gaps_out);
}
