/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-inclino.h
 * @brief Inclinometer: tilt from accelerations (1-, 2- and 3-axis), and a
 *        look-up table of per-axis offset, scale and misalignment against
 *        temperature (ADI AN-1057), interpolated by GSL (linear, or cubic
 *        spline with three or more nodes) and clamped outside its range.
 *
 * Convention (3-axis): a level, still sensor reads (0, 0, +g); for roll
 * phi and pitch theta (aerospace Z-Y-X) a = g (-sin theta, sin phi cos
 * theta, cos phi cos theta), so theta = atan2(-a_x, sqrt(a_y^2 + a_z^2))
 * and phi = atan2(a_y, a_z).  1-axis: the x axis, horizontal when level:
 * theta = asin(-a_x / g), sensitivity g cos theta per radian (17.45 mg per
 * degree at 0, halved at 60 degrees, zero at 90).  2-axis: x and z in the
 * pitch plane: theta = atan2(-a_x, a_z), full circle, sensitivity
 * sqrt(a_x^2 + a_z^2) per radian.
 *
 * Error model per temperature node: raw_i = b_i + s_i t_i + sum_{j != i}
 * m_ij t_j with t = the true specific force of the pose (SI), fitted per
 * axis by linear least squares over the static poses (offset b, scale s,
 * cross-coupling m = misalignment times scale).  Poses are runs of samples
 * with constant reference angles and a temperature within pose_tol_degc of
 * the run's first sample; nodes are clusters of pose temperatures
 * separated by more than node_gap_degc.
 */
#ifndef SSCOPE_INCLINO_H
#define SSCOPE_INCLINO_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSCOPE_INCLINO_MAX_NODES 64 /**< temperature nodes of a LUT */

/** Tilt mode. */
enum sscope_inclino_axes {
	SSCOPE_INCLINO_1AXIS = 1, /**< asin of the x axis */
	SSCOPE_INCLINO_2AXIS = 2, /**< atan2 of x and z */
	SSCOPE_INCLINO_3AXIS = 3  /**< roll and pitch */
};

/**
 * Tilt of one sample.
 * @param axes      mode.
 * @param a         specific force (x, y, z), m/s^2 (y unused by 1- and
 *                  2-axis, z unused by 1-axis).
 * @param g_m_s2    gravity, m/s^2 (1-axis only).
 * @param roll_rad  receives roll, rad (NaN for 1- and 2-axis).
 * @param pitch_rad receives pitch, rad.
 * @param sens      receives the sensitivity of the pitch reading, m/s^2
 *                  per rad (may be NULL).
 * @return 0, or -EINVAL (NULL pointer, bad mode).
 */
int sscope_inclino_tilt(enum sscope_inclino_axes axes, const double a[3],
			double g_m_s2, double *roll_rad, double *pitch_rad,
			double *sens);

/** Error-model parameters at one temperature (SI). */
struct sscope_inclino_params {
	double offset[3];   /**< b, m/s^2 */
	double scale[3];    /**< s (1 = perfect) */
	double mis[3][3];   /**< cross-coupling m_ij (diagonal 0) */
	double offset_sd[3], scale_sd[3], mis_sd[3][3]; /**< sd */
	double residual_rms; /**< of the pose means, m/s^2 */
	size_t poses;
};

/** Look-up table. */
struct sscope_inclino_lut {
	size_t n;                 /**< nodes (>= 1) */
	double gravity_m_s2;      /**< local gravity used, m/s^2 */
	double temp_degc[SSCOPE_INCLINO_MAX_NODES]; /**< increasing */
	struct sscope_inclino_params p[SSCOPE_INCLINO_MAX_NODES];
};

/** A static pose (mean of its samples). */
struct sscope_inclino_pose {
	double a[3];       /**< mean specific force, m/s^2 */
	double temp_degc;  /**< mean temperature */
	double roll_rad, pitch_rad; /**< reference angles */
	size_t n;          /**< samples */
};

/**
 * Cut samples into poses.
 * @param ax, ay, az  accelerations, m/s^2 (contiguous, n each).
 * @param temp_degc   temperature, degC.
 * @param roll_rad, pitch_rad  reference angles, rad (constant in a pose).
 * @param n           samples.
 * @param pose_tol_degc  temperature tolerance within a pose (0: 1 degC).
 * @param poses       receives up to @p cap poses.
 * @param n_poses     receives the number of poses found (may exceed cap).
 * @return 0, -EINVAL (NULL pointer), -EDOM (no finite sample), -ERANGE
 *         (samples beyond 2^+-250).
 */
int sscope_inclino_poses(const double *ax, const double *ay, const double *az,
			 const double *temp_degc, const double *roll_rad,
			 const double *pitch_rad, size_t n, double pose_tol_degc,
			 struct sscope_inclino_pose *poses, size_t cap,
			 size_t *n_poses);

/**
 * Fit the error model to poses at one temperature.
 * @return 0, -EINVAL (NULL), -EDOM (fewer than 5 poses, or poses that do
 *         not excite every axis: singular design), -ENOMEM.
 */
int sscope_inclino_fit(const struct sscope_inclino_pose *poses, size_t n,
		       double g_m_s2, struct sscope_inclino_params *p,
		       struct sscope_diag *diag);

/**
 * Build a LUT: cluster the poses by temperature (gaps > node_gap_degc, 0:
 * 3 degC), fit each cluster.
 * @return 0, -EINVAL, -EDOM (a cluster that cannot be fitted; more than
 *         SSCOPE_INCLINO_MAX_NODES clusters), -ENOMEM.
 */
int sscope_inclino_build(const struct sscope_inclino_pose *poses, size_t n,
			 double g_m_s2, double node_gap_degc,
			 struct sscope_inclino_lut *lut, struct sscope_diag *diag);

/**
 * Check a LUT read from a file.
 * @return 0, -EDOM (no node, too many, temperatures not strictly
 *         increasing, a non-finite value, a scale not positive, gravity
 *         not positive).
 */
int sscope_inclino_check(const struct sscope_inclino_lut *lut,
			 struct sscope_diag *diag);

/** Interpolator of a LUT. */
struct sscope_inclino_plan;

/**
 * Make an interpolator (GSL gsl_interp: linear, or cubic spline when
 * @p cubic and the LUT has three or more nodes).
 * @return 0, -EDOM (LUT fails sscope_inclino_check()), -ENOMEM.
 */
int sscope_inclino_plan_new(struct sscope_inclino_plan **plan,
			    const struct sscope_inclino_lut *lut, bool cubic,
			    struct sscope_diag *diag);

/** Free (NULL ignored). */
void sscope_inclino_plan_free(struct sscope_inclino_plan *plan);

/**
 * Parameters at @p temp_degc (clamped to the LUT's range).
 * @param clamped  receives whether it was outside (may be NULL).
 */
void sscope_inclino_params_at(struct sscope_inclino_plan *plan,
			      double temp_degc, struct sscope_inclino_params *p,
			      bool *clamped);

/**
 * Correct a raw sample: solve raw = b + S t for t.
 * @param raw      raw specific force, m/s^2.
 * @param out      receives the corrected specific force, m/s^2.
 * @param clamped  receives whether the temperature was outside the LUT.
 * @return 0, -EDOM (singular model).
 */
int sscope_inclino_correct(struct sscope_inclino_plan *plan, double temp_degc,
			   const double raw[3], double out[3], bool *clamped);

/** Counts of sscope_inclino_apply(). */
struct sscope_inclino_apply_stats {
	size_t n_bad;     /**< samples without a value (non-finite input) */
	size_t n_clamped; /**< temperatures outside the table (clamped) */
	size_t n_still;   /**< samples flagged still */
};

/**
 * Apply a table to a record: per sample the corrected acceleration
 * (sscope_inclino_correct()), the tilt (sscope_inclino_tilt(): roll and
 * pitch, or pitch and its sensitivity for 1 and 2 axes) and the still
 * flag -- the tilt is valid only when the platform is still: the norm of
 * the corrected acceleration within @p still_tol of g and, with gyro
 * channels, the rotation rate's norm at most @p rate_tol.  A sample with a
 * non-finite temperature or reading gets NaN and is not still.
 * @param a      three accelerometer channels, m/s^2.
 * @param temp   temperatures, degC.
 * @param w      three gyro channels, rad/s, or NULL.
 * @param roll, pitch, sens  n values each (roll or sens may be NULL).
 * @param still  n flags.
 * @return 0, -EINVAL.
 */
int sscope_inclino_apply(struct sscope_inclino_plan *plan,
			 enum sscope_inclino_axes axes, double g_m_s2,
			 const double *const a[3], const double *temp,
			 const double *const w[3], size_t n, double still_tol,
			 double rate_tol, double *roll, double *pitch,
			 double *sens, bool *still,
			 struct sscope_inclino_apply_stats *st);

/** Validation against reference poses. */
struct sscope_inclino_validation {
	size_t poses;
	double max_deg, rms_deg;           /**< calibrated, roll and pitch */
	double max_uncomp_deg, rms_uncomp_deg; /**< raw (no correction) */
	/** residual model error at the validation temperatures (the LUT's
	 *  interpolated parameters against a direct fit of the validation
	 *  poses, when they can be fitted), as the tilt error each term alone
	 *  would cause (AN-1057: 1.745 mg offset, 0.35 % scale or 1.745 mrad
	 *  misalignment = 0.1 degree), deg; NaN when not fitted */
	double offset_deg, scale_deg, mis_deg;
	const char *dominant;              /**< "offset", "scale",
					        "misalignment" or NULL */
	size_t clamped;                    /**< poses outside the LUT range */
};

/**
 * Tilt errors of reference poses with the LUT and without correction
 * (3-axis roll and pitch; poses beyond +-85 degrees of pitch skipped).
 * @return 0, -EINVAL, -EDOM (no usable pose).
 */
int sscope_inclino_validate(struct sscope_inclino_plan *plan,
			    const struct sscope_inclino_pose *poses, size_t n,
			    struct sscope_inclino_validation *v);

/**
 * The roll and pitch error of each reference pose that
 * sscope_inclino_validate() summarises: with the LUT and, when @p raw_deg
 * is not NULL, without correction; NaN for a pose it skips (beyond +-85
 * degrees of pitch).
 * @param err_deg  receives n (roll, pitch) errors, deg (caller's array).
 * @param raw_deg  receives n uncorrected errors, deg, or NULL.
 * @return 0, -EINVAL, -EDOM (no usable pose).
 */
int sscope_inclino_pose_errors(struct sscope_inclino_plan *plan,
			       const struct sscope_inclino_pose *poses,
			       size_t n, double (*err_deg)[2],
			       double (*raw_deg)[2]);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_INCLINO_H */
