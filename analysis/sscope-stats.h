/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-stats.h
 * @brief Summary statistics of a channel.
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_STATS_H
#define SSCOPE_STATS_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Mean of the finite values of x[k*stride], k < n, with its Student-t
 * interval mean -+ t(level, k - 1) s / sqrt(k) (s the sample sd of the k
 * finite values) -- the interval of a mean over a few runs.
 * @param level  two-sided level in (0, 1), e.g. 0.6827.
 * @param lo, hi receive the interval (NaN with fewer than two values).
 * @param used   receives k (may be NULL).
 * @return 0; -EDOM when no value is finite (mean NaN); -EINVAL.
 */
int sscope_stats_mean_interval(const double *x, size_t stride, size_t n,
			       double level, double *mean, double *lo,
			       double *hi, size_t *used);

/** Summary statistics of a channel. */
struct sscope_stats {
	size_t n;      /**< finite samples used */
	size_t n_nan;  /**< NaN samples skipped */
	double mean;
	double sd;     /**< sample standard deviation (n - 1) */
	double min;
	double max;
};

/**
 * Mean, standard deviation, extremes of x[k*stride], k < n, skipping NaN.
 * One pass over memory, each cache-sized block in two passes, blocks merged
 * pairwise, sums compensated: exact to a few ulps even with an offset 1e9
 * times the spread, and for any finite samples (1e308 or 1e-300: summed
 * again scaled by a power of two).
 * @return 0; -EDOM when fewer than one finite sample (sd needs two: with
 *         one sample sd is 0); -ERANGE when the sd exceeds the double
 *         range (samples near +-1.8e308, or infinite ones; the other
 *         fields are set); -EINVAL for stride 0.
 */
int sscope_stats_compute(const double *x, size_t stride, size_t n,
			 struct sscope_stats *st);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_STATS_H */
