/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-walk.h
 * @brief The random-walk fan: a stationary record cut into runs, each run
 *        integrated after its bias is removed, against the envelope its
 *        noise terms predict.
 *
 * Each run integrates the rate over run_s seconds (angle for a gyro,
 * velocity for an accelerometer).  The bias removed is either the mean
 * of the bias_s seconds just before the run (the record is cut into
 * blocks of bias_s + run_s) or, with bias_s = 0, the mean of the whole
 * record.  The predicted 1-sigma spread at time t of a run is
 * sqrt(sscope_heading_drift_var(coef, t, T)) with T the bias window (the
 * whole record for the global mean, an approximation: the global window
 * contains the run); for angle random walk alone and a long window it is
 * N sqrt(t), the textbook's fan (95.4 % of runs inside +-2 N sqrt(t)).
 */
#ifndef SSCOPE_WALK_H
#define SSCOPE_WALK_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Options.  Zero-initialise, then set rate_hz, run_s and coef. */
struct sscope_walk_opts {
	double rate_hz;  /**< sample rate, Hz */
	double run_s;    /**< integration length of each run, s */
	double bias_s;   /**< bias window before each run, s; 0: the
			      record's mean */
	double coef[5];  /**< Q, N, B, K, R of the channel (SI), for the
			      envelope and the implied N */
	double k_sigma;  /**< envelope half-width in sigmas (0 -> 2) */
	/** the record must be still: the 90th percentile of the variance
	 *  over sliding windows of max(1 s, 11 samples) may be at most this
	 *  multiple of the 10th percentile (0 -> 9, the contrast rule of
	 *  sscope-heading.h; negative: no check) */
	double max_contrast;
	/** runs whose paths are kept in the result, the first ones (0: all;
	 *  the statistics always use every run) */
	size_t keep_paths;
	/** The terms as estimated from the record by the noise fit: when
	 *  have_sq, the envelope and the implied N take the signed squares
	 *  sq[] (U^2; struct sscope_noise_coef's square) instead of coef[]^2
	 *  (an estimate^2 floored at 0 is biased up, most for a term that is
	 *  absent or barely there: the envelope too wide, the implied N too
	 *  low); sq_cov (the covariance of the squares, U^4, row-major 5 x 5;
	 *  struct sscope_noise_fit's sq_cov) gives var_other_sd.  coef[] is
	 *  still checked and must hold a term. */
	bool have_sq;
	double sq[5];
	double sq_cov[25];
};

/** The fan. */
struct sscope_walk_result {
	size_t n_runs;
	size_t n_points;  /**< points per run: samples per run + 1 (t = 0) */
	double dt_s;      /**< sample interval */
	double est_s;     /**< bias window (the record length for the global
			       mean) */
	bool global;      /**< the record's mean was removed */
	double k_sigma;
	size_t n_paths;   /**< runs whose paths are kept: n_runs, or
			       keep_paths when that is fewer */
	double *paths;    /**< n_paths x n_points integrated values, U s
			       (the first runs) */
	double *sigma;    /**< n_points: predicted 1-sigma (root mean square
			       over the runs for the record's mean) */
	double *spread;   /**< n_points: root mean square over the runs */
	double *inside;   /**< n_points: fraction with |path| <= k sigma
			       (NaN at t = 0) */
	double inside_mean; /**< mean of inside over t > 0 */
	double inside_expected; /**< the fraction a Gaussian puts inside
				     +-k sigma: erf(k / sqrt 2) */
	double inside_sd;   /**< binomial sd of one point's fraction over
				 n_runs runs: sqrt(p (1 - p) / n_runs) */
	double *var_n1;     /**< n_points: mean predicted variance for N = 1
				 and no other term (t + t^2 / T for a window) */
	double *var_other;  /**< n_points: mean predicted variance of the
				 terms other than N (may be below 0 with
				 have_sq: an estimate) */
	double *var_other_sd; /**< n_points: standard deviation of var_other
				   from the terms' uncertainty (0 without
				   have_sq) */
};

/**
 * Cut, integrate (compensated sums) and compare.
 * @param x       the record, rate unit U (SI), x[k * stride].
 * @param res     receives the result; free with sscope_walk_result_free().
 * @return 0; -EINVAL (NULL, rate or run length not positive, negative or
 *         non-finite noise terms, every term zero, non-finite samples);
 *         -EDOM (fewer than 2 runs fit in the record, a run shorter than
 *         2 samples, a record that moves); -ENOMEM.
 */
int sscope_walk_compute(const double *x, size_t stride, size_t n,
			const struct sscope_walk_opts *o,
			struct sscope_walk_result **res,
			struct sscope_diag *diag);

/** Free (NULL is ignored). */
void sscope_walk_result_free(struct sscope_walk_result *res);

/** The angle random walk implied by the spread of the runs at a point. */
struct sscope_walk_implied {
	double t_s;
	double n;       /**< implied N, U/sqrt(Hz); NaN when the other terms
			     explain the whole spread */
	double lo, hi;  /**< interval at the level (chi-squared with n_runs
			     degrees of freedom on the mean square; the other
			     terms' part, estimated from the same record, is
			     subtracted as it is: its error is correlated with
			     the spread's, coverage checked in make bench) */
};

/**
 * N implied by the spread at point @p k: the mean square over the runs,
 * less the predicted variance of the terms other than N (var_other),
 * divided by the variance per unit N^2 (var_n1).
 * @param level  confidence level in (0, 1) (0 -> 0.6827).
 * @return 0; -EINVAL (k = 0 or out of range, bad level).
 */
int sscope_walk_implied_n(const struct sscope_walk_result *r, size_t k,
			  double level, struct sscope_walk_implied *out);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_WALK_H */
