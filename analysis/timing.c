/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Sampling analysis of a time column: the median interval (robust to gaps
 * and outliers) separates gaps (intervals longer than a stated factor of
 * it) from regular intervals; the rate is the number of regular intervals
 * over their compensated sum (their mean, which for an unbroken record is
 * the span over n - 1: one rounding, where a median of differences of
 * rounded stamps would carry their rounding); jitter is the rms deviation
 * of the regular intervals from that mean.
 */
#include "internal.h"

#include <math.h>
#include <string.h>

#include <gsl/gsl_statistics_double.h>

int sscope_timing_analyze(const double *t_s, size_t n, double gap_factor,
			  struct sscope_timing *tm, struct sscope_gap *gaps,
			  size_t max_gaps, size_t *n_gaps_out, double *scratch)
{
	struct ssc_ksum j = { 0, 0 }, sum = { 0, 0 };
	size_t nj = 0, ng = 0;
	double med, mean, lo = INFINITY, hi = -INFINITY;

	if (!t_s || !tm || !scratch || !(gap_factor > 1))
		return -EINVAL;
	memset(tm, 0, sizeof(*tm));
	if (n_gaps_out)
		*n_gaps_out = 0;
	if (n < 2)
		return -EDOM;
	for (size_t i = 1; i < n; i++) {
		double d = t_s[i] - t_s[i - 1];

		scratch[i - 1] = d;
		if (d < lo)
			lo = d;
		if (d > hi)
			hi = d;
		if (!(d > 0))
			tm->n_backwards++;
	}
	med = gsl_stats_median(scratch, 1, n - 1);
	tm->dt_min_s = lo;
	tm->dt_max_s = hi;
	if (!(med > 0) || !isfinite(med))
		return -EDOM;
	tm->dt_median_s = med;
	for (size_t i = 1; i < n; i++) {
		double d = t_s[i] - t_s[i - 1];

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
	for (size_t i = 1; i < n; i++) {
		double d = t_s[i] - t_s[i - 1];

		if (d > gap_factor * med)
			continue;
		ssc_ksum_add(&j, (d - mean) * (d - mean));
	}
	tm->jitter_rms_s = nj ? sqrt(ssc_ksum_value(&j) / (double)nj) : 0;
	if (n_gaps_out)
		*n_gaps_out = ng;
	return 0;
}
