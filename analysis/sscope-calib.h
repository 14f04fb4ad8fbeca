/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-calib.h
 * @brief Error-model calibration of accelerometer and gyro triads.
 *
 * The error model per axis (textbook eqs 93-94): a gyro axis reads
 * delta_omega = b + b_g a + s_f omega_x + m_y omega_y + m_z omega_z + eta,
 * an accelerometer axis delta_f = b + s_f a_x + m_y a_y + m_z a_z + eta.
 * In matrix form the measurement is y = A u + b (+ G a for a gyro), with
 * A = I + S + M (scale-factor errors on the diagonal, misalignments off
 * it).  This module reports the *correction* that maps a reading back to
 * the physical quantity:
 *
 *     u' = T * K * (y - b - G * a'),
 *
 * K = diag(scale) in output SI units per input unit, T a misalignment
 * matrix with a unit diagonal, b the bias in input units and G the
 * g-sensitivity (gyros only; input units per m/s^2).  "Input units" are the
 * units of the samples given to the library (SI when the capture's column
 * has a physical unit, counts otherwise).
 *
 * Methods:
 * - multi-position calibration without external equipment (Tedaldi,
 *   Pretto and Menegatti, "A robust and easy to implement method for IMU
 *   calibration without external equipments", ICRA 2014): static intervals
 *   are found automatically from the variance of the accelerometer, the
 *   accelerometer's 9 parameters (3 bias, 3 scale, 3 misalignment with T
 *   upper triangular) minimise sum(|g| - |a'|)^2 by Levenberg-Marquardt,
 *   then the gyro's 9 parameters (3 scale, 6 misalignment; bias from the
 *   static intervals) make the integrated rotation between consecutive
 *   static poses carry the calibrated gravity direction of one pose onto
 *   the next;
 * - known-reference fits (six-position accelerometer test, rate table,
 *   centrifuge or tilt table): linear least squares of y = b + A r with a
 *   full 3x3 A (12 parameters), optionally with quadratic and cubic terms
 *   of each axis' own input (scale-factor non-linearity);
 * - g-dependent gyro bias from static poses: omega = b + G a.
 *
 * Uncertainties are 1-sigma, from the residual variance times the inverse
 * of J^T J (Levenberg-Marquardt) or the least-squares covariance.
 */
#ifndef SSCOPE_CALIB_H
#define SSCOPE_CALIB_H

#include "sscope-core.h"
#include "sscope-quantity.h"
#include "sscope-unit.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Standard gravity, m/s^2 (the default local gravity). */
#define SSCOPE_CALIB_GRAVITY_STD SSCOPE_UNIT_GRAVITY_STD

/** A half-open range of samples [start, end). */
struct sscope_calib_interval {
	size_t start;
	size_t end;
};

/**
 * Static-interval detection after Tedaldi et al. 2014, sec. IV-A.
 * varsigma(i) = sqrt(var_x^2 + var_y^2 + var_z^2) over a centred window of
 * window_s seconds; sample i is static when varsigma(i) < k * reference.
 * The reference ("the stated rule"): with init_static_s > 0 the value of
 * varsigma over the first init_static_s seconds (Tedaldi's initial static
 * period); otherwise the 10th percentile of varsigma over the capture,
 * which is a noise-only value whenever at least 10 % of the capture is
 * static.  Runs of static samples shorter than min_static_s are dropped.
 */
struct sscope_calib_detect {
	double window_s;      /**< in: variance window, s (0 -> 1 s) */
	double min_static_s;  /**< in: shortest interval kept, s (0 -> 2 s) */
	double init_static_s; /**< in: initial static period, s (0 -> the
				   percentile rule) */
	double k;             /**< in: threshold multiple (0 -> automatic:
				   the k in 2..10 with the smallest residual,
				   as Tedaldi et al.); out: the k used */
	double reference;     /**< out: varsigma reference, (input unit)^2 */
	double threshold;     /**< out: k * reference */
	size_t n_intervals;   /**< out: static intervals found (on a failed
				   fit: those of the last threshold tried) */
};

/**
 * Variance magnitude varsigma(i) of three channels over a centred window of
 * @p window samples (odd; an even value is rounded up).  Samples closer than
 * window/2 to either end get +infinity.
 * @param x,y,z   channels, sample k at x[k * stride].
 * @param out     n values, (input unit)^2.
 * @return 0; -EINVAL (NULL, stride 0, window < 3); -EDOM (n < window).
 */
int sscope_calib_variance_magnitude(const double *x, const double *y,
				    const double *z, size_t stride, size_t n,
				    size_t window, double *out);

/**
 * The detector's noise reference (the rule of struct sscope_calib_detect):
 * with @p init_static_s > 0, varsigma of the first init_static_s seconds
 * (the root sum of the channels' variances squared), else the 10th
 * percentile of the finite values of @p vs.
 * @param vs      n values from sscope_calib_variance_magnitude().
 * @param work    n doubles of workspace.
 * @param reference  receives the reference, (input unit)^2.
 * @return 0; -EINVAL (NULL, rate not positive); -EDOM (the initial period
 *         does not fit the record, no finite value, a zero reference).
 */
int sscope_calib_static_reference(const double *x, const double *y,
				  const double *z, size_t stride, size_t n,
				  double rate_hz, double init_static_s,
				  const double *vs, double *work,
				  double *reference, struct sscope_diag *diag);

/**
 * Static runs of @p vs (from sscope_calib_variance_magnitude()) below
 * @p threshold that last at least @p min_len samples.
 * @param iv      receives up to @p max intervals.
 * @param n_iv    receives the number found (may exceed max: only max are
 *                written).
 * @return 0 or -EINVAL.
 */
int sscope_calib_static_intervals(const double *vs, size_t n, double threshold,
				  size_t min_len,
				  struct sscope_calib_interval *iv, size_t max,
				  size_t *n_iv);

/**
 * Mean and sample standard deviation of x over an interval.
 * @return 0, -EINVAL (empty interval).
 */
int sscope_calib_interval_mean(const double *x, size_t stride,
			       const struct sscope_calib_interval *iv,
			       double *mean, double *sd);

/**
 * Static intervals at a fixed threshold det->k * reference (k > 1):
 * sscope_calib_variance_magnitude() over det->window_s into @p work,
 * sscope_calib_static_reference() into det->reference, then
 * sscope_calib_static_intervals() with det->min_static_s; det->threshold
 * and det->n_intervals are set.
 * @param work, work2  n doubles each (work receives varsigma).
 * @return 0; -EINVAL (k <= 1, NULL); -EDOM (shorter than the window, an
 *         initial period that does not fit, zero noise: diag says which).
 */
int sscope_calib_detect_static(const double *x, const double *y,
			       const double *z, size_t stride, size_t n,
			       double rate_hz, struct sscope_calib_detect *det,
			       struct sscope_calib_interval *iv, size_t max_iv,
			       double *work, double *work2,
			       struct sscope_diag *diag);

/** A calibrated triad: the correction u' = T K (y - b - G a'). */
struct sscope_calib_triad {
	double bias[3];        /**< b, input units */
	double scale[3];       /**< diag of K, output SI unit per input unit */
	double mis[3][3];      /**< T, unit diagonal */
	double gsens[3][3];    /**< G, input units per m/s^2 (gyros) */
	double bias_sd[3];
	double scale_sd[3];
	double mis_sd[3][3];
	double gsens_sd[3][3];
	bool has_gsens;        /**< G was estimated (else zero) */
	unsigned n_params;     /**< parameters estimated */
	size_t poses;          /**< static poses (or reference points) used */
	double residual_rms;   /**< rms residual: m/s^2 for the accelerometer
				    norm fit, dimensionless (unit-vector
				    difference) for the gyro, input units for
				    the linear fits */
	unsigned iterations;   /**< Levenberg-Marquardt iterations (0 for
				    linear fits) */
	double cond;           /**< condition number of the scaled Jacobian
				    or design matrix */
};

/** Set @p c to the identity correction (scale 1, no bias). */
void sscope_calib_triad_identity(struct sscope_calib_triad *c);

/**
 * Accelerometer multi-position fit (Tedaldi et al. 2014, 9 parameters)
 * from the mean readings of static poses.
 * @param means    n_poses x 3 mean readings, input units.
 * @param gravity_m_s2  local gravity magnitude, m/s^2.
 * @return 0; -EINVAL (NULL, gravity <= 0, non-finite means); -EDOM with
 *         fewer than 10 poses (9 parameters need one more equation), poses
 *         that do not determine the parameters (the excitation rule: the
 *         smallest eigenvalue of sum(m m^T) / sum(|m|^2) over the poses is
 *         below 0.01, i.e. gravity never points along some direction; or a
 *         condition number of the column-scaled Jacobian above 1e8), or no
 *         convergence.
 */
int sscope_calib_accel_fit(const double (*means)[3], size_t n_poses,
			   double gravity_m_s2, struct sscope_calib_triad *c,
			   struct sscope_diag *diag);

/**
 * Detection and fit in one: static intervals of the accelerometer
 * channels, then sscope_calib_accel_fit(); with det->k == 0 every k in
 * 2..10 is tried and the one with the smallest residual kept.
 * @param iv       caller array of @p max_iv intervals: receives the static
 *                 intervals of the chosen k.
 * @param work     n doubles of workspace (variance magnitude).
 * @param work2    n doubles of workspace (percentile).
 * @return as sscope_calib_accel_fit(); -EINVAL for rate_hz <= 0; -ERANGE
 *         for samples beyond 2^+-250.
 */
int sscope_calib_accel_multipos(const double *x, const double *y,
				const double *z, size_t stride, size_t n,
				double rate_hz, double gravity_m_s2,
				struct sscope_calib_detect *det,
				struct sscope_calib_interval *iv, size_t max_iv,
				struct sscope_calib_triad *c, double *work,
				double *work2, struct sscope_diag *diag);

/**
 * Apply a triad correction in place: u' = T K (y - b - G a).
 * @param a   calibrated accelerometer samples for the G term (three
 *            pointers with stride @p astride), or NULL to skip it.
 */
void sscope_calib_apply(const struct sscope_calib_triad *c, double *x,
			double *y, double *z, size_t stride, size_t n,
			const double *const a[3], size_t astride);

/**
 * Gyro multi-position fit (Tedaldi et al. 2014): bias = mean of the gyro
 * over the static intervals (and G when @p with_gsens: linear fit of the
 * static means against the calibrated gravity), then T (6) and K (3) by
 * Levenberg-Marquardt so that the rotation integrated between the end of
 * interval k-1 and the start of interval k maps the calibrated gravity
 * direction of pose k-1 onto that of pose k.
 * @param g           gyro channels (input units, rate), stride @p stride.
 * @param accel_cal   calibrated accelerometer channels (m/s^2), same
 *                    indexing as @p g (used for gravity and the G term).
 * @param iv          the static intervals (ascending, non-overlapping).
 * @param scale_guess starting value of the scale factors, output SI per
 *                    input unit (1 for a rate in rad/s); 0 scans a log grid
 *                    from 1e-9 to 1e3 (counts of unknown weight).
 * @param with_gsens  also estimate the g-sensitivity matrix G (needs 5 or
 *                    more poses that are not coplanar).
 * @return 0; -EINVAL; -ERANGE (samples beyond 2^+-250); -EDOM with fewer
 *         than 6 poses (5 rotations), motions
 *         that do not determine the parameters (the excitation rule: the
 *         smallest eigenvalue of sum(w w^T) / sum(|w|^2) over the motion
 *         samples is below 0.01, e.g. all rotations about one axis; or a
 *         condition number above 1e8), poses that do not tilt gravity onto
 *         all three axes when @p with_gsens, or no convergence.
 */
int sscope_calib_gyro_fit(const double *const g[3],
			  const double *const accel_cal[3], size_t stride,
			  size_t n, double rate_hz, double scale_guess,
			  const struct sscope_calib_interval *iv, size_t n_iv,
			  bool with_gsens, struct sscope_calib_triad *c,
			  struct sscope_diag *diag);

/**
 * How well a gyro correction predicts the motions between static poses:
 * for each motion k (from the end of interval k to the start of k + 1) the
 * angle between the calibrated gravity direction of pose k + 1 and that of
 * pose k carried by the rotation the corrected gyro integrates (the check
 * sscope_calib_gyro_fit() minimises, as an angle).  With the fitted triad
 * the rms of 2 sin(angle / 2) is the fit's residual_rms; with a triad that
 * only removes the bias it shows the uncalibrated error.
 * @param g, accel_cal, stride, n, rate_hz, iv, n_iv  as
 *                    sscope_calib_gyro_fit().
 * @param c           the correction (its bias, T K and, when has_gsens, G).
 * @param angle_rad   n_iv - 1 angles, rad (caller's array).
 * @return 0; -EINVAL (NULL, fewer than 2 intervals, bad intervals or
 *         rate); -EDOM when the accelerometer reads zero in a pose.
 */
int sscope_calib_gyro_motion_errors(const double *const g[3],
				    const double *const accel_cal[3],
				    size_t stride, size_t n, double rate_hz,
				    const struct sscope_calib_interval *iv,
				    size_t n_iv,
				    const struct sscope_calib_triad *c,
				    double *angle_rad);

/**
 * Result of a fit against known stimuli (rate table, centrifuge, six
 * positions): y = b + A r + c2 .* r_own^2 + c3 .* r_own^3, where r_own is
 * each output axis' own input.
 */
struct sscope_calib_linear {
	double bias[3], bias_sd[3];   /**< input units */
	double A[3][3], A_sd[3][3];   /**< input units per SI unit: diagonal
					   = scale factor, off-diagonal =
					   cross-axis sensitivity */
	double c2[3], c2_sd[3];       /**< per SI unit^2 (when nonlinear) */
	double c3[3], c3_sd[3];       /**< per SI unit^3 (when nonlinear) */
	double full_scale[3];         /**< max |r| on each axis, SI */
	double nonlinearity[3];       /**< best-fit-straight-line
					   non-linearity: max |residual of the
					   linear model| / (|A_ii| FS), ratio */
	double residual_rms[3];       /**< of the linear model, input units */
	double sf_bfsl[3];            /**< slope of the best-fit straight line
					   of each axis (equals A_ii without
					   the non-linear terms) */
	double cond;                  /**< largest condition number of the
					   (column-scaled) design matrices */
	bool nonlinear;               /**< c2, c3 were estimated */
	bool axis_excited[3];         /**< the data moved this input axis */
	size_t points;
};

/**
 * Fit y = b + A r (+ own-axis quadratic and cubic terms).  Input axes that
 * the data never excite get A columns of zero (and a flag), so one
 * single-axis rate-table run still yields its axis' scale factor and the
 * cross-axis terms of that column.
 * @param y         n x 3 measured means, input units.
 * @param r         n x 3 reference stimuli, SI.
 * @param nonlinear estimate c2 and c3 (needs 3 or more distinct levels on
 *                  the axis beyond the linear ones).
 * @return 0; -EINVAL; -EDOM (too few points for the parameters, nothing
 *         excited, a singular design).
 */
int sscope_calib_linear_fit(const double (*y)[3], const double (*r)[3],
			    size_t n, bool nonlinear,
			    struct sscope_calib_linear *out,
			    struct sscope_diag *diag);

/**
 * Convert a linear fit with all three axes excited into the correction
 * form: K T = A^-1 (first-order uncertainties).
 * @return 0; -EDOM when not all axes were excited or A is singular.
 */
int sscope_calib_linear_to_triad(const struct sscope_calib_linear *lf,
				 struct sscope_calib_triad *c);

/**
 * The six-position accelerometer test: every pose is classified by the
 * axis and sign of its largest mean reading (+g or -g on x, y or z) and
 * y = b + A r fitted with r = +-g e_i (12 parameters).
 * @return 0; -EINVAL; -EDOM when the six orientations are not all
 *         present or A is singular.
 */
int sscope_calib_accel_sixpos(const double (*means)[3], size_t n_poses,
			      double gravity_m_s2,
			      struct sscope_calib_linear *lf,
			      struct sscope_calib_triad *c,
			      struct sscope_diag *diag);

/**
 * Segments of constant reference (rate table, centrifuge, dividing head):
 * maximal runs where |r - r_first| <= tol, minus the first @p settle
 * samples, kept when at least @p min_len samples remain.  Non-finite
 * reference samples belong to no segment.
 * @return 0, -EINVAL.
 */
int sscope_calib_constant_segments(const double *r, size_t stride, size_t n,
				   double tol, size_t settle, size_t min_len,
				   struct sscope_calib_interval *iv,
				   size_t max, size_t *n_iv);

/**
 * The six-position test on a capture: static poses at each threshold k in
 * 2..10 (or det->k when given), sscope_calib_accel_sixpos() on their
 * means, the k with the smallest residual kept (det, @p iv, @p lf and
 * @p c describe it).
 * @param work, work2  n doubles each.
 * @return 0; -EINVAL; -EDOM when no k gives the six orientations (diag
 *         says why); -ENOMEM.
 */
int sscope_calib_accel_sixpos_run(const double *x, const double *y,
				  const double *z, size_t stride, size_t n,
				  double rate_hz, double gravity_m_s2,
				  struct sscope_calib_detect *det,
				  struct sscope_calib_interval *iv, size_t max_iv,
				  struct sscope_calib_linear *lf,
				  struct sscope_calib_triad *c, double *work,
				  double *work2, struct sscope_diag *diag);

/**
 * The g-dependent gyro bias from static tilts: static poses of the
 * accelerometer @p a (threshold det->k, 4 when not given), then
 * omega = b + G a fitted to the poses' means; @p c receives b, G and
 * their sd (scale and misalignment not estimated: identity, scale_sd
 * NaN), 12 parameters.
 * @param g, a  gyro (rate, SI) and accelerometer (m/s^2) channels.
 * @return 0; -EINVAL; -EDOM (detection, too few poses, poses that do not
 *         tilt gravity onto all three axes); -ENOMEM.
 */
int sscope_calib_gyro_gsens_run(const double *const g[3],
				const double *const a[3], size_t stride,
				size_t n, double rate_hz,
				struct sscope_calib_detect *det,
				struct sscope_calib_interval *iv, size_t max_iv,
				struct sscope_calib_triad *c, double *work,
				double *work2, struct sscope_diag *diag);

/**
 * The noise density of a calibrated triad from its static poses: the sd
 * of each channel pooled over the intervals (sum of (len - 1) sd^2 over
 * the sum of (len - 1)), through |scale|, as sqrt(mean over the axes of
 * sd^2 / rate_hz) -- white noise per axis, output SI / sqrt(Hz).
 * @return 0; -EINVAL; -EDOM when no interval has two samples.
 */
int sscope_calib_noise_density(const double *const ch[3], size_t stride,
			       const struct sscope_calib_interval *iv,
			       size_t n_iv, const double scale[3],
			       double rate_hz, double *nd);

/**
 * The error model of a triad whose readings have the output's dimension
 * (textbook eqs 93-94): reading = A u + b with A = (T K)^-1; A_ii - 1 are the
 * scale-factor errors, A_ij (i != j) the misalignments.
 * @return 0; -EDOM when T K is singular; -EINVAL.
 */
int sscope_calib_error_model(const struct sscope_calib_triad *c,
			     double A[3][3]);

/**
 * The class of a calibrated triad (sscope_calib_grade()): from the
 * largest |bias|, the largest |A_ii - 1| and |G_ij| when @p A (the error
 * model) is given; for raw readings (A NULL) from the bias in output units
 * |T K b| alone, with the noise density in both cases.
 * @return as sscope_calib_grade().
 */
int sscope_calib_triad_grade(enum sscope_quantity q,
			     const struct sscope_calib_triad *c,
			     const double (*A)[3], double noise_density,
			     double *distance);

/**
 * How far each static pose's norm is from gravity before and after a
 * correction: before[k] = |m_k| - g (0 when the readings are not in SI,
 * @p raw_is_si false), after[k] = |T K (m_k - b)| - g, m_k the pose mean.
 * @return 0 or -EINVAL.
 */
int sscope_calib_pose_errors(const double *const ch[3], size_t stride,
			     const struct sscope_calib_interval *iv,
			     size_t n_iv, const struct sscope_calib_triad *c,
			     double gravity_m_s2, bool raw_is_si,
			     double *before, double *after);

/** sscope_calib_motion_summary()'s figures. */
struct sscope_calib_motion {
	size_t motions;             /**< n_iv - 1 */
	double rms_rad;             /**< rms gravity error, calibrated */
	double max_rad;             /**< largest, calibrated */
	double rms_bias_only_rad;   /**< rms with the bias removed only */
};

/**
 * sscope_calib_gyro_motion_errors() of a fitted gyro triad and of the
 * same triad with only its bias (and G) applied at the nominal scale (1
 * for a rate in SI, @p rate_in_si; else the mean |scale|), with their rms
 * and maximum: what the calibration gains over the motions.
 * @param after, before  n_iv - 1 angles each, rad.
 * @return as sscope_calib_gyro_motion_errors().
 */
int sscope_calib_motion_summary(const double *const g[3],
				const double *const accel_cal[3],
				size_t stride, size_t n, double rate_hz,
				const struct sscope_calib_interval *iv,
				size_t n_iv, const struct sscope_calib_triad *c,
				bool rate_in_si, double *after, double *before,
				struct sscope_calib_motion *sum);

/**
 * The steps of a rate-table (or centrifuge) run: where the commanded
 * reference (one channel, or three of a three-axis command) stays
 * constant, less @p settle_s after each change and at least 0.5 s long
 * (sscope_calib_constant_segments() with a tolerance of 1e-9 of the
 * largest |reference|); per step the mean of the sensor's three channels
 * (@p ym) and of the references (@p rm, zero for missing ones).
 * @param seg         receives up to @p max steps.
 * @param n_steps     receives their number.
 * @return 0; -EDOM with fewer than two steps; -EINVAL; -ENOMEM.
 */
int sscope_calib_rate_table_steps(const double *const y[3],
				  const double *const ref[3], size_t n_ref,
				  size_t stride, size_t n, double rate_hz,
				  double settle_s,
				  struct sscope_calib_interval *seg, size_t max,
				  double (*ym)[3], double (*rm)[3],
				  size_t *n_steps);

/**
 * The sensor axis a single reference drives: the one whose step means
 * have the largest |slope| against the reference (rm[k][0]).
 * @return 0, 1 or 2 (0 when no slope is defined).
 */
int sscope_calib_table_axis(const double (*ym)[3], const double (*rm)[3],
			    size_t n);

/**
 * A triad of a calibration file (what `calib --save-calibration` writes):
 * the channels it corrects and the correction, its parameters in the
 * file's units -- bias in @p input_unit (the raw channels' unit; "" for
 * raw counts), scale in @p output_unit per input unit, G in input units
 * per m/s^2.
 */
struct sscope_calib_file_triad {
	char kind[8];               /**< "accel" or "gyro" */
	char channels[3][64];
	char accel_channels[3][64]; /**< the accelerometer for G (gyros) */
	char input_unit[32];
	char output_unit[32];
	struct sscope_calib_triad c;
};

/** A class of sensors with typical performance ranges. */
struct sscope_calib_class {
	const char *name;
	enum sscope_quantity quantity; /**< ANGULAR_RATE or ACCELERATION */
	double bias_lo, bias_hi;       /**< |bias| (g-independent), SI */
	double sf_lo, sf_hi;           /**< scale-factor error, ratio */
	double noise_lo, noise_hi;     /**< noise density N, SI/sqrt(Hz) */
	double gsens_lo, gsens_hi;     /**< g-dependent bias, rad/s per
					    m/s^2 (0, 0: not applicable) */
};

/**
 * The table of typical sensor classes: gyros (ring laser, fibre optic,
 * ceramic and silicon vibrating-structure gyros) and accelerometer grades.
 * The values are typical orders of magnitude (see calib.c for the source),
 * not limits of any product.
 * @param n   receives the number of rows.
 * @return a static array.
 */
const struct sscope_calib_class *sscope_calib_grades(size_t *n);

/**
 * Classify a sensor against sscope_calib_grades(): for each class of the
 * same quantity the distance is the sum over the figures given (finite,
 * > 0) of the decades by which the figure lies outside the class range
 * (0 inside); the class with the smallest distance wins (ties: the first
 * in the table).
 * @param bias   |bias|, SI (NaN: not used).
 * @param sf     |scale-factor error|, ratio (NaN: not used).
 * @param noise  noise density, SI/sqrt(Hz) (NaN: not used).
 * @param gsens  g-dependent bias, rad/s per m/s^2 (NaN: not used).
 * @param distance  receives the winner's distance (may be NULL).
 * @return the row index, or -EDOM when no figure was given, -EINVAL for
 *         another quantity.
 */
int sscope_calib_grade(enum sscope_quantity q, double bias, double sf,
		       double noise, double gsens, double *distance);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_CALIB_H */
