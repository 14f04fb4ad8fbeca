/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-heading.h
 * @brief Heading from a vertical gyro, with the bias estimated at every
 *        stop, and the predicted heading-error envelope from the gyro's
 *        noise terms.
 *
 * The rate about the vertical axis is integrated to heading after the
 * bias is removed.  The bias is the mean rate over a stationary interval
 * ("stop"), found by the static detector of calibration (Tedaldi et al.,
 * see sscope-calib.h: variance magnitude over a sliding window below k
 * times a noise reference); the first stop starts the heading, and every
 * later stop re-estimates the bias while the heading is held (a zero
 * angular-rate update).  The same record is also integrated with the
 * first stop's bias alone, so the gain of re-estimation shows.
 *
 * Predicted error: between stops the heading error is the integral of the
 * rate noise minus the error of the last bias estimate, whose variance
 * for the IEEE 952 terms is sscope_heading_drift_var(); it adds to the
 * error carried from earlier segments (stops hold it).
 */
#ifndef SSCOPE_HEADING_H
#define SSCOPE_HEADING_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Variance of e(tau) = int_0^tau x dt - (tau / T) int_-T^0 x dt for a
 * rate x whose noise has the IEEE 952 terms @p coef: the drift of an
 * integrated rate whose bias was taken as the mean of the T = @p est_s
 * seconds just before 0.  With c = tau / T and the structure function
 * D(t) = Q^2 + N^2 t / 2 - (B^2 / 2 pi) t^2 ln t - K^2 t^3 / 12 (Q for
 * t > 0):
 *   var = -2c D(tau + T) + 2 (1 + c) D(tau) + 2 c (1 + c) D(T)
 *         + R^2 tau^2 (tau + T)^2 / 4,
 * i.e. N^2 (tau + tau^2 / T) for white noise, K^2 (tau^3 + tau^2 T) / 3
 * for a rate random walk, and for flicker (B, one-sided spectrum
 * B^2 / (pi f)) the finite combination of the logarithms that its
 * divergent integral leaves.  At tau = T it equals 2 tau^2 times the Allan
 * variance sscope_noise_avar(coef, tau).
 * @param coef   Q, N, B, K, R (SI of the rate unit U; enum sscope_term).
 * @param tau_s  time since the estimate, s (>= 0).
 * @param est_s  length of the estimate's window, s (> 0).
 * @return the variance, (U s)^2; NaN for bad arguments.
 */
double sscope_heading_drift_var(const double coef[5], double tau_s,
				double est_s);

/**
 * Variance of sum_i c_i X(t_i), X the integral of a rate with the IEEE 952
 * terms @p coef, for coefficients with sum c_i = 0 and sum c_i t_i = 0
 * (any integral of the rate minus a bias estimated as a mean over other
 * times is such a combination): -2 sum_{i<j} c_i c_j D(|t_i - t_j|) with
 * the structure function above, plus the rate ramp's (R/2 sum c t^2)^2.
 * @param t, c  @p n times (s) and coefficients.
 * @return the variance, (U s)^2 (no argument checks: a hot path).
 */
double sscope_heading_drift_var_points(const double coef[5], const double *t,
				       const double *c, size_t n);

/** How the bias between stops is formed. */
enum sscope_heading_bias {
	SSCOPE_HEADING_HOLD = 0,  /**< the last stop's estimate (causal) */
	SSCOPE_HEADING_INTERPOLATE /**< linear between the stops' centres
				       (post-processing) */
};

/** Options.  Zero-initialise, then set rate_hz (and latitude_rad to NaN
 *  when no Earth-rate correction is wanted). */
struct sscope_heading_opts {
	double rate_hz;       /**< sample rate, Hz */
	double window_s;      /**< detector window, s (0 -> 1 s) */
	double min_static_s;  /**< shortest stop, s (0 -> 2 s) */
	double k;             /**< threshold multiple of the reference
				   (0 -> 3) */
	/** detector reference from the first init_static_s seconds (which
	 *  must be still); 0: the 10th percentile of the variance magnitude
	 *  (a noise-only value when at least 10 % of the record is still) */
	double init_static_s;
	/** the 90th percentile of the variance magnitude must exceed this
	 *  multiple of the reference, or the record is taken to hold no
	 *  stop (a relative threshold alone finds "stops" in any record)
	 *  (0 -> k^2) */
	double min_contrast;
	bool axis_up;         /**< the axis points up: heading is minus its
				   integral */
	double latitude_rad;  /**< for the Earth-rate part of the stop biases
				   (NaN: not corrected) */
	enum sscope_heading_bias bias_model;
	double initial_heading_rad; /**< heading at the first stop */
	/** Q, N, B, K, R of the axis (SI) for the envelope; all zero: N
	 *  from the pooled scatter of the rate within the stops (valid when
	 *  white noise dominates the samples), no other term */
	double coef[5];
};

/** A stationary interval. */
struct sscope_heading_stop {
	size_t start, end;          /**< samples [start, end) */
	double t_start_s, t_end_s;
	double bias_rad_s;          /**< mean rate over the stop (what the
				         axis reads at rest, Earth rate
				         included) */
	double bias_sd_rad_s;       /**< its standard error from the noise
				         terms (N / sqrt(T) and the B, K part) */
	double sensor_bias_rad_s;   /**< minus the vertical Earth rate (NaN
				         without a latitude) */
};

/** Result of sscope_heading_compute(). */
struct sscope_heading_result {
	size_t n;                   /**< samples */
	size_t first;               /**< first sample with a heading (start
				         of the first stop) */
	double *heading_rad;        /**< n: bias re-estimated at every stop
				         (NaN before @p first) */
	double *heading_once_rad;   /**< n: first stop's bias only */
	double *sigma_rad;          /**< n: predicted 1-sigma error of
				         heading_rad (hold model) */
	double *sigma_once_rad;     /**< n: of heading_once_rad */
	unsigned char *still;       /**< n: 1 inside a stop */
	struct sscope_heading_stop *stops;
	size_t n_stops;
	double reference;           /**< detector reference, (input unit)^2 */
	double threshold;           /**< k * reference */
	double coef[5];             /**< noise terms used for the envelope */
	bool coef_from_stops;       /**< N came from the stops' scatter */
	double earth_rate_rad_s;    /**< vertical Earth rate along the axis
				         (0 without a latitude) */
};

/**
 * Heading from a vertical-axis rate.
 * @param rate    rate about the axis, rad/s, rate[k * stride].
 * @param det     three channels for the static detector (accelerometers,
 *                or the gyro triad, or the rate three times), sample k
 *                at det[i][k * det_stride].
 * @param res     receives the result; free with
 *                sscope_heading_result_free().
 * @return 0; -EINVAL (NULL, rate <= 0, bad option, non-finite samples);
 *         -EDOM (shorter than the detector window, no variance at all, no
 *         stationary interval, or no contrast between stops and motion);
 *         -ENOMEM.
 */
int sscope_heading_compute(const double *rate, size_t stride, size_t n,
			   const double *const det[3], size_t det_stride,
			   const struct sscope_heading_opts *o,
			   struct sscope_heading_result **res,
			   struct sscope_diag *diag);

/** Free (NULL is ignored). */
void sscope_heading_result_free(struct sscope_heading_result *res);

/**
 * Turn both heading series so that the heading at the first stop is
 * @p heading_rad (e.g. a reference's value found only after detection).
 */
void sscope_heading_set_initial(struct sscope_heading_result *res,
				double heading_rad);

/** Heading error against a reference. */
struct sscope_heading_cmp {
	double rms_rad;       /**< root mean square error */
	double max_abs_rad;   /**< largest |error| */
	double final_rad;     /**< error at the last sample */
	double inside_2sigma; /**< fraction of samples (with sigma > 0) whose
				   |error| <= 2 sigma; NaN when none */
	size_t n;             /**< samples compared */
};

/**
 * Compare headings with a reference from sample @p first on (errors
 * wrapped to (-pi, pi]).
 * @param sigma  predicted 1-sigma (may be NULL).
 * @return 0; -EINVAL; -EDOM (nothing to compare).
 */
int sscope_heading_compare(const double *heading, const double *sigma,
			   const double *ref, size_t ref_stride, size_t n,
			   size_t first, struct sscope_heading_cmp *c);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_HEADING_H */
