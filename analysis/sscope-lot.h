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
 *         -EDOM (fewer than 3 units, a value not finite or beyond
 *         1e150 in magnitude, a standard error outside 1e-150 .. 1e150);
 *         -ENOMEM.
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
 * means independent; flicker noise (bias instability B) and a random walk
 * of the bias (K) correlate them, and intervals from the residuals then
 * cover far less than their level (40-48 % for 68.3 % with B = 5 ug over
 * 1 h of 60 ug/sqrt(Hz)).  Given the unit's noise model (its fitted N, B,
 * K in the options), the drift's and the temperature sensitivity's
 * standard errors are also computed under that model: each is a linear
 * estimate sum_j a_j b_j whose weights a_j sum to zero (a row of the
 * pseudo-inverse of the design, SVD), of variance
 * -1/2 sum_jk a_j a_k D(|j - k|) with the structure function of the block
 * means D(d) = E[(b_(j+d) - b_j)^2] of the power-law model
 * (sscope_lot_model_var()).  When the model has B or K, the larger of the
 * two standard errors is used and, when it is the model's, the interval
 * takes the normal quantile (the model comes from the whole record's
 * Allan deviation, not from the m - 3 residual degrees of freedom).
 *
 * A record often cannot show B or K that would still widen these
 * intervals (one hour at 1 Hz of 60 ug/sqrt(Hz) shows B = 5 ug in a
 * quarter of the units): given upper bounds of B and K (b_upper, k_upper:
 * the fit's upper bounds of the terms it does not show, the upper ends
 * of the intervals of those it shows), a conservative standard error is
 * computed with each term in turn at its bound (drift_se_upper,
 * tempco_se_upper, never below the reported one) and its interval.
 * Each bound holds with the other term free, so the two are not put at
 * their bounds together.
 */

/** Options of sscope_lot_bias(); zero means the default. */
struct sscope_lot_bias_opts {
	size_t blocks; /**< batches m (0: 20; at least 5) */
	double level;  /**< interval level (0: 0.682689, one sd) */
	double n;      /**< the unit's white rate noise N (ARW / VRW),
			    U/sqrt(Hz); 0: not shown */
	double b;      /**< its bias instability B (flicker), U; 0: not
			    shown */
	double k;      /**< its rate random walk K, U/s/sqrt(Hz); 0: not
			    shown */
	double b_upper; /**< an upper bound of B: the upper end of its
			     interval, or the fit's upper bound where it
			     does not show it, U; 0: none; INFINITY: the
			     record gives no finite bound */
	double k_upper; /**< the same of K, U/s/sqrt(Hz) */
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
				    sensitivity's intervals from the
				    residuals, which take the blocks as
				    independent, are too narrow */
	double drift_se_resid;  /**< the drift's se from the residuals, U/s */
	double drift_se_model;  /**< under the noise model of the options,
				     U/s (NaN without B and K) */
	bool drift_se_from_model; /**< drift_se is drift_se_model (the
				       larger): normal quantile */
	double tempco_se_resid; /**< U/degC (NaN without have_temp) */
	double tempco_se_model; /**< U/degC (NaN without have_temp or
				     without B and K) */
	bool tempco_se_from_model; /**< tempco_se is tempco_se_model */
	double drift_se_upper; /**< conservative: the largest of drift_se,
				    the se under the model with B at
				    max(b, b_upper) and that with K at
				    max(k, k_upper), the other term as
				    the model has it (INFINITY when such a
				    bound is; drift_se without bounds), U/s */
	double drift_upper_lo, drift_upper_hi; /**< drift -+ the normal
						    quantile x drift_se_upper
						    (drift_lo, drift_hi when
						    that is drift_se), U/s */
	double tempco_se_upper; /**< the same of the sensitivity, U/degC
				     (NaN without have_temp) */
	double tempco_upper_lo, tempco_upper_hi; /**< U/degC */
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

/**
 * The record less the temperature effect that sscope_lot_bias() @p b
 * fitted, sample by sample: r_i = x_i - c (T_i - T_mean), i < n (c =
 * b->tempco_u_degc, T_mean = b->temp_mean_degc): the record a noise model
 * of the unit is fitted to (the bias's response to the temperature would
 * pass for flicker or a random walk in the Allan deviation of the
 * record; the drift is left in, for the fit's rate ramp R).  Used as the
 * options' n, b, k of sscope_lot_bias() in the lot stage.
 * @param x, temp_degc  as given to sscope_lot_bias().
 * @param r          receives n values (caller's; may be x when the
 *                   stride is 1).
 * @return 0; -EINVAL (NULL x, temp_degc, b or r, a stride 0, no
 *         temperature term in @p b: have_temp false).
 */
int sscope_lot_temp_removed(const double *x, size_t stride, size_t n,
			    const double *temp_degc, size_t temp_stride,
			    const struct sscope_lot_bias *b, double *r);

/**
 * The variance of sum_j a[j] b_j, b_j the means of m consecutive blocks of
 * @p block_s seconds of a rate with white noise N, flicker (bias
 * instability) B and a random walk K (IEEE 952 terms; two-sided PSD
 * N^2 + B^2 / (2 pi |f|) + K^2 / (2 pi f)^2), the weights summing to
 * zero (a slope, a contrast: finite although flicker and a random walk
 * have no finite variance).  Closed form through the structure function
 * D(d) = E[(b_(j+d) - b_j)^2] = 2 N^2 / T + (2 B^2 / pi) g(d) +
 * K^2 T (d - 1/3), d >= 1, T = block_s, g(d) = -d^2 ln d +
 * (d+1)^2 ln(d+1) / 2 + (d-1)^2 ln(d-1) / 2 (g(1) = 2 ln 2: D(1) is twice
 * the Allan variance at T for each term), var = -1/2 sum_jk a_j a_k
 * D(|j - k|) (continuous-time averages; exact for white noise).
 * @param a      m weights, U per U (any unit: the result is in its square
 *               times U^2).
 * @param n,b,k  the terms, U/sqrt(Hz), U, U/s/sqrt(Hz) (>= 0).
 * @param var    receives the variance.
 * @return 0; -EINVAL (NULL a or var, block_s not > 0, a term negative or
 *         not finite); -EDOM (m < 2, a weight not finite, weights whose
 *         sum is not zero to 1e-9 of the sum of their magnitudes).
 */
int sscope_lot_model_var(const double *a, size_t m, double block_s, double n,
			 double b, double k, double *var);

#endif
