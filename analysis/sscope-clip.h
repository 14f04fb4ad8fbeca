/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-clip.h
 * @brief Clipped data: samples piled up at a channel's extreme, the mark
 *        of a sensor or converter driven into the limit of its range.
 *
 * A signal that stays inside the range takes its largest value once (a
 * continuous value) or, quantized, no more often than the code next to
 * it: noise quantized to a few codes has a histogram that falls towards
 * its tails, and even a sine, whose density peaks at its extremes, puts
 * at most about 2.4 times as many samples in its outermost code as in the
 * next one inward (near a crest at height A the arcsine density puts
 * sqrt(A - e) in the part of the last code above its lower edge e and
 * sqrt(A - e + 1) - sqrt(A - e) in the code below, in LSB; the ratio
 * grows with A - e up to 1 / (sqrt 2 - 1) = 2.41 at a full code).  A clipped signal piles every sample beyond the
 * limit onto one value.  So a side counts as clipped when at least
 * min_count samples equal its extreme and more than ratio times as many
 * as equal the next distinct value inward.
 */
#ifndef SSCOPE_CLIP_H
#define SSCOPE_CLIP_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Defaults for sscope_clip_detect(): at least 8 samples at the extreme
 *  and more than 4 times the next value inward (above a sine's 2.4). */
#define SSCOPE_CLIP_MIN_COUNT 8
#define SSCOPE_CLIP_RATIO 4.0

/** What sits at the extremes of a channel. */
struct sscope_clip {
	double lo, hi;        /**< smallest and largest finite sample */
	size_t n_lo, n_hi;    /**< samples equal to lo, to hi */
	size_t n_lo_next;     /**< samples equal to the smallest value > lo */
	size_t n_hi_next;     /**< samples equal to the largest value < hi */
	bool low, high;       /**< a pile-up at lo, at hi */
};

/**
 * The extremes of the finite values of x[k*stride], k < n, how many
 * samples sit on each and on the next distinct value inward, and whether
 * either side is clipped (see the file comment).  One pass, no
 * allocation.  A constant record (lo == hi) is not clipped.
 * @param min_count fewest samples at an extreme that count as a clip
 *                  (>= 2; SSCOPE_CLIP_MIN_COUNT)
 * @param ratio     how many times the next value's count the extreme
 *                  must exceed (> 1; SSCOPE_CLIP_RATIO)
 * @param c         receives the result (caller's storage).
 * @return 0; -EINVAL (NULL, stride 0, min_count < 2, ratio <= 1 or not
 *         finite); -EDOM when no sample is finite.
 */
int sscope_clip_detect(const double *x, size_t stride, size_t n,
		       size_t min_count, double ratio, struct sscope_clip *c);

struct sscope_stats;

/**
 * sscope_stats_compute() and sscope_clip_detect() of the same samples in
 * one pass over memory (each block of the statistics looked at for the
 * clip while it is in the cache): the same results as the two calls.
 * @param st    receives the statistics, as sscope_stats_compute().
 * @param c     receives the clip result as sscope_clip_detect() writes it;
 *              left untouched when no sample is finite; NULL: none.
 * @return sscope_stats_compute()'s value, or -EINVAL for NULL x or st,
 *         stride 0, or (with c) min_count < 2, ratio <= 1 or not finite.
 */
int sscope_clip_detect_stats(const double *x, size_t stride, size_t n,
			     size_t min_count, double ratio,
			     struct sscope_stats *st, struct sscope_clip *c);

/** The envelope of one bin of samples: what a plot keeps of it. */
struct sscope_clip_envelope {
	double lo, hi;      /**< smallest and largest sample that is not NaN
			     *   (infinities count); NaN when there is none */
	size_t i_lo, i_hi;  /**< index k of the first sample equal (==) to
			     *   lo, to hi; SIZE_MAX when there is none */
	size_t n_nan;       /**< NaN samples in the bin */
};

/**
 * sscope_clip_detect_stats(), and in the same pass over memory the
 * envelope of each of n_bins consecutive bins of the samples: bin b holds
 * k = floor(n b / n_bins) .. floor(n (b + 1) / n_bins) - 1 (a bin is empty
 * when n < n_bins: lo and hi NaN, no index, no NaN).  A long record drawn
 * as a line keeps each bin's first, smallest, largest and last sample; this
 * finds them while the statistics read the samples.
 * @param n_bins number of bins (0: none; n_bins (n_bins - 1) must not
 *               exceed SIZE_MAX: about 2^32 bins with a 64-bit size_t).
 * @param bins   receives n_bins envelopes (caller's storage; may be NULL
 *               when n_bins is 0); filled even when no sample is finite.
 * @return as sscope_clip_detect_stats(); -EINVAL also for bins NULL with
 *         n_bins > 0, or too many bins.
 */
int sscope_clip_detect_stats_envelope(const double *x, size_t stride,
				      size_t n, size_t min_count, double ratio,
				      struct sscope_stats *st,
				      struct sscope_clip *c, size_t n_bins,
				      struct sscope_clip_envelope *bins);

#ifdef __cplusplus
}
#endif

#endif
