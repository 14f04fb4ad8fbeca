/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Streaming timing analysis: sscope_timing_analyze() for records read in
 * chunks; and receive times against stamps (latency, agreement).  The
 * first SSCOPE_TIMING_STREAM_BLOCK intervals are held until their median
 * is known (GSL), then every interval is classified against it as
 * sscope_timing_analyze() does, one stamp late (an interval next to a
 * backward step is disorder, neither gap nor regular): an interval longer than gap_factor
 * times the median is a gap, the others are summed in order with
 * Neumaier compensation, so the rate (their count over their sum) is the
 * same number whenever the medians agree.  The jitter comes from
 * compensated sums of (d - median) and (d - median)^2, which do not cancel
 * the way raw second moments would.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_statistics_double.h>

#include "sscope-timing.h"

struct sscope_timing_stream {
	double factor;
	double *block;        /* the first intervals, until the median */
	bool *fwd;            /* which of them are forward (decided ones) */
	double *sorted;       /* scratch for the median */
	size_t n_block;
	bool have_median;
	bool no_median;       /* the first block had no usable median */
	double median;
	/* the last interval waits for the next stamp to tell whether it is
	 * next to a backward step */
	bool have_last, have_pending;
	double last, pending, before; /* last stamp; the waiting interval and
					 the one before it */
	bool have_before;
	size_t n_stamps;
	double lo, hi;
	size_t n_backwards, n_gaps, n_missing, n_regular;
	struct ssc_ksum sum, s1, s2;
	struct sscope_timing_order order;
};

int sscope_timing_stream_new(struct sscope_timing_stream **out,
			     double gap_factor)
{
	struct sscope_timing_stream *ts;

	if (!out)
		return -EINVAL;
	*out = NULL;
	if (!(gap_factor > 1))
		return -EINVAL;
	ts = calloc(1, sizeof(*ts));
	if (!ts)
		return -ENOMEM;
	ts->block = malloc(SSCOPE_TIMING_STREAM_BLOCK * sizeof(double));
	ts->fwd = malloc(SSCOPE_TIMING_STREAM_BLOCK * sizeof(bool));
	ts->sorted = malloc(SSCOPE_TIMING_STREAM_BLOCK * sizeof(double));
	if (!ts->block || !ts->fwd || !ts->sorted) {
		sscope_timing_stream_free(ts);
		return -ENOMEM;
	}
	ts->factor = gap_factor;
	ts->lo = INFINITY;
	ts->hi = -INFINITY;
	*out = ts;
	return 0;
}

void sscope_timing_stream_free(struct sscope_timing_stream *ts)
{
	if (!ts)
		return;
	free(ts->block);
	free(ts->fwd);
	free(ts->sorted);
	free(ts);
}

/* One forward interval once the median is known. */
static void classify(struct sscope_timing_stream *ts, double d)
{
	if (d > ts->factor * ts->median) {
		ts->n_gaps++;
		ts->n_missing += (size_t)llround(d / ts->median) - 1;
		return;
	}
	ssc_ksum_add(&ts->sum, d);
	ssc_ksum_add(&ts->s1, d - ts->median);
	ssc_ksum_add(&ts->s2, (d - ts->median) * (d - ts->median));
	ts->n_regular++;
}

/* The median of the held intervals (all of them, as sscope_timing_analyze
 * takes it), then classify the decided forward ones (false: no usable
 * median). */
static bool settle(struct sscope_timing_stream *ts, size_t n_decided)
{
	if (ts->have_median)
		return true;
	if (!ts->n_block || ts->no_median)
		return false;
	memcpy(ts->sorted, ts->block, ts->n_block * sizeof(double));
	ts->median = gsl_stats_median(ts->sorted, 1, ts->n_block);
	if (!(ts->median > 0) || !isfinite(ts->median))
		return false;
	ts->have_median = true;
	for (size_t i = 0; i < n_decided; i++)
		if (ts->fwd[i])
			classify(ts, ts->block[i]);
	return true;
}

/* The waiting interval is decided: forward when positive and neither the
 * interval before nor the one after (@p next, absent at the end) goes
 * backwards.  Interval k of the record is block[k] while the block fills. */
static void decide(struct sscope_timing_stream *ts, size_t k, bool has_next,
		   double next)
{
	bool fwd = ts->pending > 0 && !(ts->have_before && ts->before < 0) &&
		   !(has_next && next < 0);

	if (ts->have_median) {
		if (fwd)
			classify(ts, ts->pending);
	} else if (k < ts->n_block) {
		ts->fwd[k] = fwd;
	}
}

int sscope_timing_stream_feed(struct sscope_timing_stream *ts,
			      const double *t_s, size_t n)
{
	if (!ts || (!t_s && n))
		return -EINVAL;
	sscope_timing_order_feed(&ts->order, t_s, n);
	for (size_t i = 0; i < n; i++) {
		double t = t_s[i], d;
		size_t k; /* index of the new interval */

		ts->n_stamps++;
		if (!ts->have_last) {
			ts->have_last = true;
			ts->last = t;
			continue;
		}
		d = t - ts->last;
		ts->last = t;
		k = ts->n_stamps - 2;
		if (d < ts->lo)
			ts->lo = d;
		if (d > ts->hi)
			ts->hi = d;
		if (!(d > 0))
			ts->n_backwards++;
		if (ts->have_pending) {
			decide(ts, k - 1, true, d);
			ts->before = ts->pending;
			ts->have_before = true;
		}
		ts->pending = d;
		ts->have_pending = true;
		if (ts->have_median || ts->no_median)
			continue;
		ts->block[ts->n_block++] = d;
		/* the block's last interval is still waiting */
		if (ts->n_block == SSCOPE_TIMING_STREAM_BLOCK &&
		    !settle(ts, ts->n_block - 1))
			ts->no_median = true; /* the result says so */
	}
	return 0;
}

int sscope_timing_stream_result(struct sscope_timing_stream *stream,
				struct sscope_timing *tm)
{
	struct sscope_timing_stream c, *ts = &c;
	double mean, m1, var;

	if (!stream || !tm)
		return -EINVAL;
	/* on a copy: more stamps may follow */
	c = *stream;
	memset(tm, 0, sizeof(*tm));
	tm->order = ts->order;
	if (ts->have_pending)
		decide(ts, ts->n_stamps - 2, false, 0);
	if (ts->n_stamps < 2)
		return -EDOM;
	tm->dt_min_s = ts->lo;
	tm->dt_max_s = ts->hi;
	tm->n_backwards = ts->n_backwards;
	if (!settle(ts, ts->n_block))
		return -EDOM;
	tm->dt_median_s = ts->median;
	tm->n_gaps = ts->n_gaps;
	tm->n_missing = ts->n_missing;
	mean = ts->n_regular ? ssc_ksum_value(&ts->sum) / (double)ts->n_regular :
			       ts->median;
	if (!(mean > 0))
		return -EDOM;
	tm->rate_hz = 1 / mean;
	if (ts->n_regular) {
		m1 = ssc_ksum_value(&ts->s1) / (double)ts->n_regular;
		var = ssc_ksum_value(&ts->s2) / (double)ts->n_regular - m1 * m1;
		tm->jitter_rms_s = var > 0 ? sqrt(var) : 0;
	}
	return 0;
}

int sscope_timing_latency(const double *rx_s, const double *t_s, size_t n,
			  double *median_s, double *min_s, double *max_s,
			  double *scratch)
{
	if (!rx_s || !t_s || !median_s || !min_s || !max_s || !scratch)
		return -EINVAL;
	if (n < 1)
		return -EDOM;
	*min_s = INFINITY;
	*max_s = -INFINITY;
	for (size_t i = 0; i < n; i++) {
		scratch[i] = rx_s[i] - t_s[i];
		if (!isfinite(scratch[i]))
			return -EDOM;
		*min_s = fmin(*min_s, scratch[i]);
		*max_s = fmax(*max_s, scratch[i]);
	}
	/* quickselect: scratch is reordered */
	*median_s = gsl_stats_median(scratch, 1, n);
	return 0;
}

bool sscope_timing_agree(const struct sscope_timing *a,
			 const struct sscope_timing *b, double rel_tol)
{
	return a && b && fabs(a->rate_hz / b->rate_hz - 1) <= rel_tol &&
	       a->n_gaps == b->n_gaps && a->n_backwards == b->n_backwards;
}
