/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Summary statistics.  Two-pass algorithm (mean first, then the sum of
 * squared deviations) with Neumaier-compensated sums and the correction
 * term of Chan, Golub & LeVeque ("Algorithms for computing the sample
 * variance", Am. Stat. 1983, eq. 1.7), so a large offset does not eat the
 * digits of a small spread.
 */
#include "internal.h"

#include <math.h>

#include <gsl/gsl_cdf.h>

int sscope_stats_compute(const double *x, size_t stride, size_t n,
			 struct sscope_stats *st)
{
	struct ssc_ksum s = { 0, 0 }, q = { 0, 0 }, c = { 0, 0 };
	size_t used = 0;
	double mean, lo = INFINITY, hi = -INFINITY;

	if (!x || !st || stride == 0)
		return -EINVAL;
	st->n = 0;
	st->n_nan = 0;
	for (size_t i = 0; i < n; i++) {
		double v = x[i * stride];

		if (isnan(v)) {
			st->n_nan++;
			continue;
		}
		ssc_ksum_add(&s, v);
		if (v < lo)
			lo = v;
		if (v > hi)
			hi = v;
		used++;
	}
	if (used == 0)
		return -EDOM;
	mean = ssc_ksum_value(&s) / (double)used;
	for (size_t i = 0; i < n; i++) {
		double v = x[i * stride];

		if (isnan(v))
			continue;
		ssc_ksum_add(&q, (v - mean) * (v - mean));
		ssc_ksum_add(&c, v - mean);
	}
	st->n = used;
	st->mean = mean;
	st->min = lo;
	st->max = hi;
	if (used < 2) {
		st->sd = 0;
	} else {
		double cc = ssc_ksum_value(&c);
		double var = (ssc_ksum_value(&q) - cc * cc / (double)used) /
			     (double)(used - 1);

		st->sd = var > 0 ? sqrt(var) : 0;
	}
	return 0;
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
