/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-lot.h
 * @brief Many units of one model: the population mean of a quantity, the
 *        true spread between units, and the units that stand out.
 *
 * Each unit i gives an estimate y_i of the quantity (a noise term, a bias)
 * and its own standard error s_i (from its interval).  The random-effects
 * model y_i = mu + u_i + e_i, u_i ~ N(0, tau^2), e_i ~ N(0, s_i^2)
 * separates the spread between units (tau) from each unit's measurement
 * uncertainty (s_i), which the plain standard deviation of the y_i mixes.
 *
 * - tau^2 by restricted maximum likelihood (REML, Fisher scoring from the
 *   DerSimonian-Laird value; W. Viechtbauer, "Bias and efficiency of
 *   meta-analytic variance estimators in the random-effects model",
 *   J. Educ. Behav. Stat. 30, 261-293, 2005);
 * - its interval by the Q-profile method: the generalised Q statistic
 *   sum w_i (y_i - mu_w)^2, w_i = 1 / (s_i^2 + tau^2), is chi-squared with
 *   k - 1 degrees of freedom at the true tau^2 and decreases with tau^2,
 *   so the interval is where it lies between the chi-squared quantiles:
 *   exact under the model (W. Viechtbauer, "Confidence intervals for the
 *   amount of heterogeneity in meta-analysis", Stat. Med. 26, 37-52, 2007);
 * - mu, weighted by 1 / (s_i^2 + tau^2), its interval by Hartung and
 *   Knapp's t interval with k - 1 degrees of freedom (J. Hartung,
 *   G. Knapp, Stat. Med. 20, 3875-3889, 2001);
 * - outliers by a robust z, z_i = (y_i - mu) / sqrt(s_i^2 + tau^2), with
 *   mu and tau (REML) of the units that do not stand out beyond the
 *   family-wise level (the per-unit rate / k, Bonferroni), found from the
 *   median and the median absolute deviation and refined until that set
 *   settles: the outliers do not widen the yardstick that tests them, and
 *   the yardstick is not trimmed by units a per-unit test flags by
 *   chance.  A unit is flagged when |z| exceeds the normal quantile of
 *   the per-unit false-alarm rate.  The mean, tau and their intervals are
 *   those of the units within the family-wise level (unless asked to keep
 *   every unit).
 *
 * Against an upper specification limit USL, the lot's process capability
 * Cpu = (USL - mean) / (3 sigma) (the one-sided Cpk), with the population
 * sd sigma = sqrt(tau^2 + s^2) of the values a test of one unit measures:
 * the between-unit sd tau combined with the typical within-unit standard
 * error s (Higgins and Thompson's typical within-study variance,
 * s^2 = (k - 1) sum w / ((sum w)^2 - sum w^2), w = 1 / se^2; the common
 * se when all are equal).  Mean and tau are those of every unit (outliers
 * kept: a capability index that leaves out the worst units would flatter
 * the lot).  Its interval is Bissell's normal approximation,
 * Cpu -+ z sqrt(1 / (9 n) + Cpu^2 / (2 (n - 1))) (A. F. Bissell, "How
 * reliable is your capability index?", Appl. Stat. 39, 331-340, 1990).
 */
#ifndef SSCOPE_LOT_H
#define SSCOPE_LOT_H

#include <stdbool.h>
#include <stddef.h>

#include "sscope-core.h"

/** Options of sscope_lot_spread(); zero means the default. */
struct sscope_lot_opts {
	double level;         /**< interval level (0: 0.90) */
	double outlier_alpha; /**< per-unit false-alarm rate of the outlier
				   test, two-sided (0: 0.01) */
	bool keep_outliers;   /**< estimate the spread with every unit in
				   (default: without those beyond the
				   family-wise level) */
};

/** A lot's spread of one quantity (units of the y_i). */
struct sscope_lot_spread {
	size_t k;             /**< units given */
	size_t k_used;        /**< units in the estimates (k less those
				   beyond the family-wise level, unless
				   kept) */
	double level;         /**< level of the intervals */
	double mean;          /**< population mean mu */
	double mean_lo, mean_hi; /**< its Hartung-Knapp interval */
	double between_sd;    /**< tau (REML), 0 when the data show none */
	double between_lo, between_hi; /**< its Q-profile interval (lo 0 when
					    the data are consistent with no
					    spread at the lower quantile) */
	double total_sd;      /**< plain standard deviation of the y_i */
	double q;             /**< Cochran's Q about the fixed-effect mean */
	double q_p;           /**< its chi-squared p-value (k - 1 dof):
				   small when units differ beyond their
				   own uncertainty */
	double i2;            /**< Higgins' I^2: tau^2 / (tau^2 + typical
				   s^2), 0..1 */
	size_t n_outliers;    /**< units flagged */
	double outlier_z;     /**< the |z| a unit must exceed */
};

/**
 * The spread of @p y (k estimates, stride 1) over a lot, each with its
 * standard error @p se (> 0).  @p z (k values, may be NULL) receives each
 * unit's robust z and @p outlier (k flags, may be NULL) whether it is
 * flagged.
 * @return 0; -EINVAL (NULL y, se or out; an option out of range);
 *         -EDOM (fewer than 3 units, a non-finite value, a standard
 *         error not > 0); -ENOMEM.
 */
int sscope_lot_spread(const double *y, const double *se, size_t k,
		      const struct sscope_lot_opts *opts,
		      struct sscope_lot_spread *out, double *z, bool *outlier);

/** A lot's capability against an upper limit (units of the y_i). */
struct sscope_lot_cpk {
	size_t n;          /**< units */
	double level;      /**< level of the interval */
	double usl;        /**< the upper limit */
	double mean;       /**< population mean (REML weights, every unit) */
	double between_sd; /**< tau (REML, every unit) */
	double within_sd;  /**< typical within-unit standard error */
	double sigma;      /**< sqrt(between_sd^2 + within_sd^2) */
	double cpk;        /**< (usl - mean) / (3 sigma) */
	double lo, hi;     /**< Bissell's interval at the level */
};

/**
 * The lot's one-sided Cpk against the upper limit @p usl (see the file
 * comment), from k estimates @p y with standard errors @p se (> 0).
 * @param level  interval level (0: 0.90).
 * @return 0; -EINVAL (NULL y, se or out; level out of (0, 1); usl not
 *         finite); -EDOM (fewer than 3 units, a non-finite value, a
 *         standard error not > 0, no spread at all: sigma 0); -ENOMEM.
 */
int sscope_lot_cpk(const double *y, const double *se, size_t k, double usl,
		   double level, struct sscope_lot_cpk *out);

/*
 * One unit's bias over its record, the drift of that bias and its
 * temperature sensitivity, by batch means (B. Schmeiser, "Batch size
 * effects in the analysis of simulation output", Oper. Res. 30, 556-568,
 * 1982): the record is cut into m contiguous blocks of equal length (the
 * last n mod m samples left out), the block means b_j are taken as
 * independent with a common variance, and fitted by least squares (GSL,
 * SVD of the centred and scaled design):
 *
 *   b_j = a + d (t_j - t_mean) + c (T_j - T_mean)
 *
 * with t_j the block centres and T_j the blocks' mean temperatures (the
 * c term only with a temperature in every block, not constant).  The
 * bias is the mean of the record (a), the drift d (the slope over the
 * record), the temperature sensitivity c; their standard errors come
 * from the residuals, the intervals are Student-t with m - 3 degrees of
 * freedom (m - 2 without temperature).  Time and temperature are fitted
 * together, so a drift is not taken for a temperature effect nor the
 * other way round; where the temperature follows time (temp_time_corr
 * near -1 or 1) the two cannot be told apart and both intervals widen.
 *
 * Blocks far longer than the noise's correlation time make the block
 * means independent; flicker noise (bias instability) and a random walk
 * of the bias correlate them and the intervals then cover somewhat less
 * than their level.
 */

/** Options of sscope_lot_bias(); zero means the default. */
struct sscope_lot_bias_opts {
	size_t blocks; /**< batches m (0: 20; at least 5) */
	double level;  /**< interval level (0: 0.682689, one sd) */
};

/** One unit's bias terms (U the unit of the samples). */
struct sscope_lot_bias {
	size_t blocks;      /**< m */
	size_t block_n;     /**< samples per block */
	double level;       /**< level of the intervals */
	double bias;        /**< mean of the m blocks (a), U */
	double bias_se, bias_lo, bias_hi;   /**< U */
	double drift_u_s;   /**< slope over the record, U/s */
	double drift_se, drift_lo, drift_hi; /**< U/s */
	bool have_temp;     /**< temperature in every block, not constant:
				 the c term fitted */
	double tempco_u_degc; /**< c, U/degC (NaN without have_temp) */
	double tempco_se, tempco_lo, tempco_hi; /**< U/degC */
	double temp_mean_degc, temp_span_degc; /**< of the block means */
	double temp_time_corr; /**< correlation of the block temperatures
				    with time, -1..1 */
	double resid_lag1;  /**< lag-1 autocorrelation of the block means'
				 residuals from the fit */
	bool resid_correlated; /**< resid_lag1 above 1.645 / sqrt(m) (a
				    one-sided 5 % test of independence):
				    the bias wanders (flicker, a random
				    walk) and the drift's and temperature
				    sensitivity's intervals, which take the
				    blocks as independent, are too narrow */
};

/**
 * The bias, its drift and its temperature sensitivity of one record x[k *
 * stride], k < n, sampled at @p fs, by batch means (see above).
 * @param temp_degc  temperature per sample (stride @p temp_stride), or
 *                   NULL; a NaN temperature leaves the c term out.
 * @return 0; -EINVAL (NULL x or out, stride 0, fs not > 0, an option out
 *         of range); -EDOM (fewer than 2 samples per block, a non-finite
 *         sample); -ENOMEM.
 */
int sscope_lot_bias(const double *x, size_t stride, size_t n, double fs,
		    const double *temp_degc, size_t temp_stride,
		    const struct sscope_lot_bias_opts *opts,
		    struct sscope_lot_bias *out);

#endif
