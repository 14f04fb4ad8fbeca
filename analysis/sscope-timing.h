/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-timing.h
 * @brief Time stamps: order, sampling rate, gaps, jitter.
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_TIMING_H
#define SSCOPE_TIMING_H

#include "sscope-core.h"

/** The gap factor of captures: an interval longer than this many times
 *  the median interval is a gap (the capture's timing, info, psd). */
#define SSCOPE_TIMING_GAP_FACTOR 1.5

#ifdef __cplusplus
extern "C" {
#endif

/**
 * The values an interval table gives each sample (a rate-table schedule,
 * a tilt table): @p rows holds n_rows rows of START END V1 .. Vk (k =
 * @p n_val; times in s from the record's first sample); sample i, at
 * t = t_s[i] - t_s[0] (or i / rate_hz when t_s is NULL), takes the values
 * of the first row with START <= t < END, NaN outside every row.
 * @param out  n_val arrays of n values.
 * @return 0; -EINVAL (NULL, no time base, n_val 0).
 */
int sscope_timing_intervals_sample(const double *t_s, double rate_hz, size_t n,
				   const double *rows, size_t n_rows, size_t n_val,
				   double *const *out);

/**
 * Order of a time column, fed in pieces (a streaming reader feeds every
 * chunk).  Zero-initialise.  Counts intervals that are not positive and
 * recognises a swapped pair of rows (a backward step whose exchange with
 * the row before restores the order).
 */
struct sscope_timing_order {
	size_t n;            /**< stamps fed */
	size_t n_repeats;    /**< intervals of exactly 0 (a repeated stamp) */
	size_t n_decreasing; /**< negative intervals */
	size_t n_swaps;      /**< of those, swapped pairs of adjacent rows
				  (complete after sscope_timing_order_check) */
	size_t first_row;    /**< 0-based row of the first interval that is
				  not positive (0: none) */
	double first_t_s;    /**< that row's stamp */
	double first_prev_s; /**< and the stamp before it */
	double t0_s;         /**< the first stamp */
	/* private: the last three stamps and a backward step waiting for the
	 * next stamp to tell whether it was a swap */
	double last_s[3];
	int pending;
};

/** Feed the next @p n stamps (seconds); NaN stamps are not expected. */
void sscope_timing_order_feed(struct sscope_timing_order *o, const double *t_s,
			      size_t n);

/**
 * Is the time column usable as sampling times?
 * @param diag  receives the problem as a phrase to follow the column's
 *              name: "has one row", "is constant (every row has the same
 *              stamp)", "decreases in every row (...)", "has rows 3 and 4
 *              in reverse order (...)", "repeats the stamp of row 3 at
 *              row 4 (...)", "goes backwards 2 times (first at row 9:
 *              ...)", with a count of further cases (rows 1-based).
 * @return 0 when the stamps strictly increase (two or more of them);
 *         -EDOM otherwise; -EINVAL for a NULL @p o.
 */
int sscope_timing_order_check(const struct sscope_timing_order *o,
			      struct sscope_diag *diag);

/** Sampling of a time column. */
struct sscope_timing {
	double dt_median_s; /**< median interval */
	double dt_min_s;
	double dt_max_s;
	double jitter_rms_s;  /**< rms deviation of the regular intervals from
				   their mean (gaps excluded) */
	double rate_hz;       /**< 1 / mean regular interval */
	size_t n_gaps;        /**< intervals longer than gap_factor * median */
	size_t n_missing;     /**< samples missing in those gaps (estimated) */
	size_t n_backwards;   /**< non-increasing intervals */
	/** order of the stamps (filled also when the analysis returns
	 *  -EDOM); see sscope_timing_order_check() */
	struct sscope_timing_order order;
};

/** A gap in time stamps. */
struct sscope_timing_gap {
	size_t index;     /**< first sample after the gap */
	double t_s;       /**< its time */
	double length_s;  /**< the interval */
	size_t missing;   /**< round(length / median) - 1 */
};

/**
 * Analyse time stamps.  Intervals that are not positive, and the two
 * around a backward step (a swapped pair of rows makes them long), are
 * neither gaps nor part of the rate.
 * @param t_s         n time stamps in seconds.
 * @param gap_factor  an interval longer than gap_factor times the median is
 *                    a gap (1.5 is usual).
 * @param gaps        optional array receiving up to @p max_gaps gaps.
 * @param n_gaps_out  optional: number written to @p gaps.
 * @param scratch     n - 1 doubles of workspace (for the median; written
 *                    only when the intervals take more than 512 distinct
 *                    values, so an untouched allocation costs no memory).
 * @return 0; -EDOM for n < 2 or a non-positive median interval; -EINVAL.
 */
int sscope_timing_analyze(const double *t_s, size_t n, double gap_factor,
			  struct sscope_timing *tm, struct sscope_timing_gap *gaps,
			  size_t max_gaps, size_t *n_gaps_out, double *scratch);

/**
 * sscope_timing_analyze() as two passes over the stamps that need nothing
 * of each other, for a caller that runs them at the same time (one on
 * another thread), and the step that joins them.  The median pass finds
 * the median interval, the extremes, the backward steps and the order of
 * the stamps; the sums pass the compensated sum, count and largest of the
 * forward intervals and the jitter about their mean as it is when none of
 * them is a gap.  sscope_timing_split_join() gives what
 * sscope_timing_analyze() gives, bit for bit (it makes one more pass when
 * an interval is a gap).  The fields are private.
 */
struct sscope_timing_split {
	/* median pass */
	double median_s, min_s, max_s;
	size_t n_backwards;
	struct sscope_timing_order order;
	/* sums pass */
	double fsum_s, fsum_c, fmax_s, jsum_s, jsum_c;
	size_t n_forward;
};

/**
 * The median pass of @p n stamps (seconds) into @p sp.
 * @param scratch  n - 1 doubles of workspace, as sscope_timing_analyze()'s.
 * @return 0; -EINVAL (NULL).
 */
int sscope_timing_split_median(struct sscope_timing_split *sp,
			       const double *t_s, size_t n, double *scratch);

/**
 * The sums pass of the same stamps into @p sp (other fields than the
 * median pass's: the two may run at the same time on one @p sp).
 * @return 0; -EINVAL (NULL).
 */
int sscope_timing_split_sums(struct sscope_timing_split *sp, const double *t_s,
			     size_t n);

/**
 * Join both passes over the same stamps: sscope_timing_analyze()'s results
 * and return codes for the same arguments.
 * @return 0; -EDOM for n < 2 or a non-positive median interval; -EINVAL.
 */
int sscope_timing_split_join(const struct sscope_timing_split *sp,
			     const double *t_s, size_t n, double gap_factor,
			     struct sscope_timing *tm,
			     struct sscope_timing_gap *gaps, size_t max_gaps,
			     size_t *n_gaps_out);

/**
 * Latency of receive times against the stamps they carry (a ROS
 * container's receive times against the header stamps): rx[i] - t[i].
 * @param scratch  n doubles of workspace.
 * @return 0; -EDOM for n < 1 or non-finite latencies; -EINVAL.
 */
int sscope_timing_latency(const double *rx_s, const double *t_s, size_t n,
			  double *median_s, double *min_s, double *max_s,
			  double *scratch);

/**
 * Whether two timings of one record agree: rates within @p rel_tol and
 * the same counts of gaps and of backward steps.
 */
bool sscope_timing_agree(const struct sscope_timing *a,
			 const struct sscope_timing *b, double rel_tol);

/**
 * Streaming form of sscope_timing_analyze() for a record read in chunks
 * (memory independent of its length).  The median interval is taken over
 * the first SSCOPE_TIMING_STREAM_BLOCK intervals (all of them in a shorter
 * record, where every result but jitter_rms_s equals
 * sscope_timing_analyze()'s exactly); later intervals are classified
 * against it.  Jitter comes from sums about that median.
 */
struct sscope_timing_stream;

/** Intervals the streaming median is taken over. */
#define SSCOPE_TIMING_STREAM_BLOCK 65536

/** @return 0, -EINVAL (gap_factor <= 1), -ENOMEM. */
int sscope_timing_stream_new(struct sscope_timing_stream **ts,
			     double gap_factor);

/** Feed the next @p n stamps (s, any chunking).  @return 0, -EINVAL. */
int sscope_timing_stream_feed(struct sscope_timing_stream *ts,
			      const double *t_s, size_t n);

/**
 * The timing of the stamps fed so far.
 * @return 0; -EDOM for fewer than two stamps or a non-positive median
 *         interval; -EINVAL.
 */
int sscope_timing_stream_result(struct sscope_timing_stream *ts,
				struct sscope_timing *tm);

/** Free (NULL is ignored). */
void sscope_timing_stream_free(struct sscope_timing_stream *ts);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_TIMING_H */
