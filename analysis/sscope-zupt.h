/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-zupt.h
 * @brief Strapdown navigation of a recorded 6-axis capture aided by
 *        zero-velocity and zero-angular-rate updates at every stop.
 *
 * Filter: a 15-state error-state (indirect, closed-loop) Kalman filter
 * around the NED strapdown mechanisation of sscope-strapdown.h (Groves,
 * "Principles of GNSS, Inertial, and Multisensor Integrated Navigation
 * Systems", 2nd ed., 2013, sec. 14.2 (error-state model of the local
 * navigation frame) and 15.3.1 (ZUPT/ZARU); E. Foxlin, "Pedestrian
 * tracking with shoe-mounted inertial sensors", IEEE Computer Graphics
 * and Applications 25(6), 2005).  States, estimate minus truth: position
 * (north, east, down, m), velocity (NED, m/s), attitude (small rotation
 * psi of the NED frame, C_est = (I + [psi x]) C, rad), gyro bias (rad/s)
 * and accelerometer bias (m/s^2), both in body axes.  The error dynamics
 * are d(dr)/dt = dv, d(dv)/dt = -[f^n x] psi - C db_a - 2 [w_ie x] dv
 * + (2 g / R) dr_D e_D, d(psi)/dt = -[w_ie x] psi - C db_g, biases random
 * walks; the transition is I + F T over each two-sample update T at rest,
 * and I + sum(F T) over the updates of a propagation interval (default
 * 0.05 s) while moving (the products use the 36 non-zero entries of F).  Process noise: angle random walk
 * N_g^2 T on attitude, velocity random walk N_a^2 T on velocity, and on
 * each bias K^2 T + (B^2 / tau) T (rate random walk plus the bias
 * instability as a random walk reaching B after tau).
 *
 * Initialisation: the capture must start still.  The first still interval
 * (consecutive detector windows passing the variance part of the test
 * below) gives roll and pitch from the accelerometer mean (levelling) and
 * the gyro bias from the gyro mean less the Earth rate; the tilt error
 * that an accelerometer bias causes is entered in the initial covariance
 * with its correlation to that bias.  Heading: the value given, else
 * gyrocompassing (the horizontal Earth rate in the levelled gyro mean)
 * when its predicted 1-sigma error sqrt(sigma_b^2 + N^2 / T) /
 * (Omega cos(lat)) is below a limit, else 0 (unobservable: positions are
 * then in the frame of that assumed heading).
 *
 * Stop detector: a sliding window of W samples ending at the current
 * update, of the generalised likelihood-ratio form of I. Skog et al.,
 * "Zero-velocity detection -- an algorithm evaluation", IEEE Trans.
 * Biomedical Engineering 57(11), 2010: the sum of the squared deviations
 * of each gyro and accelerometer sample from its window mean over the
 * per-sample noise variance (N^2 fs), plus the window mean of the
 * bias-corrected gyro less the Earth rate and of the bias-corrected
 * specific force rotated to NED plus gravity, each over its variance
 * (noise over W plus the filter's variance of that mean, tilt and
 * accelerometer bias with their correlation).  Still when the variance
 * part is below the chi-squared quantile of 6 (W - 1) degrees of freedom
 * and the mean part below that of 6, each at 1 - false_alarm / 2 (white
 * noise at rest).  A motion of constant velocity
 * and attitude is indistinguishable from rest for any IMU-only detector.
 * At every still update: three velocity measurements (zero, sd
 * zupt_sd_m_s) and three angular-rate measurements (the mean of the two
 * samples less the bias estimate and the Earth rate, variance N^2 fs / 2),
 * processed one at a time; the estimated errors are then fed back.
 * Beyond the linear model: after levelling, a horizontal accelerometer
 * bias b_h lengthens the measured gravity by |b_h|^2 / 2g, which the
 * vertical bias estimate takes in until turns make b_h observable; as the
 * horizontal bias variance s falls from s0 to s1, 2 ((s0 - s1) / 2g)^2 (the
 * second moment of that chi-squared term) is added to the variance of the
 * bias along the vertical.
 *
 * Memory: every buffer is allocated once before the pass over the samples.
 */
#ifndef SSCOPE_ZUPT_H
#define SSCOPE_ZUPT_H

#include "sscope-core.h"
#include "sscope-nav.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Number of error states. */
#define SSCOPE_ZUPT_N_STATES 15

/** Options.  sscope_zupt_opts_init() sets the defaults noted. */
struct sscope_zupt_opts {
	double rate_hz;              /**< sample rate, Hz (> 0, no default) */
	struct sscope_nav_geodetic start; /**< start point (latitude 45 deg,
					       height 0); |lat| < 89 deg */
	double heading_rad;          /**< initial heading when given */
	bool heading_given;          /**< use heading_rad (no gyrocompass) */
	double heading_sd_rad;       /**< its 1-sigma (default 0) */
	/** gyro: angle random walk N (rad/sqrt(s), default 0.3 deg/sqrt(h)),
	 *  bias instability B (rad/s, default 10 deg/h), rate random walk
	 *  K (rad/s/sqrt(s), default 0) */
	double gyro_n, gyro_b, gyro_k;
	/** accelerometer: VRW N (m/s/sqrt(s), default 0.1 m/s/sqrt(h)),
	 *  B (m/s^2, default 0.1 mg), K (m/s^2/sqrt(s), default 0) */
	double accel_n, accel_b, accel_k;
	/** 1-sigma turn-on biases before the first stop: gyro (rad/s,
	 *  default 0.5 deg/s), accelerometer (m/s^2, default 20 mg) */
	double gyro_bias_sd_rad_s, accel_bias_sd_m_s2;
	double bias_time_s;   /**< tau of the bias instability (default 100 s) */
	double window_s;      /**< detector window (default 0.5 s, >= 3 samples) */
	double false_alarm;   /**< detector level at rest (default 1e-3) */
	double min_level_s;   /**< shortest initial still interval (default 1 s) */
	double zupt_sd_m_s;   /**< velocity measurement sd (default 0.01 m/s) */
	double gyrocompass_max_rad; /**< gyrocompass when its sd is below
					 (default 5 deg) */
	double propagate_s;   /**< covariance propagation interval while
				   moving, rounded to whole updates (default
				   0.05 s; at rest: every update) */
	double output_step_s; /**< records every this many seconds, rounded to
				   whole updates (0: about 1000 records) */
	bool no_zupt;         /**< detect stops but apply no update */
};

/** Fill @p o with the defaults (rate_hz 0: the caller sets it). */
void sscope_zupt_opts_init(struct sscope_zupt_opts *o);

/** One output record. */
struct sscope_zupt_rec {
	double t_s;              /**< from the first sample */
	double ned_m[3];         /**< in the tangent plane of the start */
	double lat_rad, lon_rad, height_m;
	double v_ned_m_s[3];
	double euler_rad[3];     /**< roll, pitch, yaw */
	double gyro_bias_rad_s[3], accel_bias_m_s2[3];
	/** 1-sigma of the same (yaw's includes the initial heading's) */
	double sd_ned_m[3], sd_v_m_s[3], sd_euler_rad[3];
	double sd_gyro_bias_rad_s[3], sd_accel_bias_m_s2[3];
	bool still;              /**< the detector's verdict at this update */
};

/** A stop: a run of still updates. */
struct sscope_zupt_stop {
	double t_start_s;  /**< first sample of the first still window */
	double t_end_s;    /**< last still update */
	/** the bias estimates and their 1-sigma at the end of the stop */
	double gyro_bias_rad_s[3], accel_bias_m_s2[3];
	double sd_gyro_bias_rad_s[3], sd_accel_bias_m_s2[3];
};

/** How the initial heading was set. */
enum sscope_zupt_heading {
	SSCOPE_ZUPT_HEADING_GIVEN = 0,
	SSCOPE_ZUPT_HEADING_GYROCOMPASS,
	SSCOPE_ZUPT_HEADING_ASSUMED  /**< unobservable: the value given or 0 */
};

/** Result (sscope_zupt_result_free()). */
struct sscope_zupt_result {
	struct sscope_zupt_rec *rec;
	size_t n_rec;
	struct sscope_zupt_stop *stops;
	size_t n_stops;
	size_t n_updates, n_still; /**< two-sample updates, still ones */
	double level_s;            /**< initial still interval */
	double roll0_rad, pitch0_rad, heading0_rad, heading0_sd_rad;
	enum sscope_zupt_heading heading_from;
	double gyrocompass_sd_rad; /**< predicted sd of gyrocompassing */
	size_t window;             /**< detector window, samples */
	double threshold;          /**< detector threshold, variance part */
	double threshold_mean;     /**< detector threshold, mean part */
};

/**
 * Navigate a capture.
 * @param gyro   x, y, z angular rate, rad/s, body FRD axes.
 * @param accel  x, y, z specific force, m/s^2.
 * @param stride distance between samples of one axis, elements.
 * @param n      samples (an odd last sample is not used).
 * @param res    receives the result (caller frees).
 * @return 0; -EINVAL (NULL, a bad option: rate, noise terms not positive
 *         and finite, latitude); -EDOM (a non-finite sample, fewer samples
 *         than the initial interval needs, not still at the start);
 *         -ENOMEM.
 */
int sscope_zupt_run(const double *const gyro[3], const double *const accel[3],
		    size_t stride, size_t n, const struct sscope_zupt_opts *o,
		    struct sscope_zupt_result **res, struct sscope_diag *diag);

/** Free (NULL is ignored). */
void sscope_zupt_result_free(struct sscope_zupt_result *r);

/** @return "given", "gyrocompass", "assumed"; NULL out of range. */
const char *sscope_zupt_heading_name(enum sscope_zupt_heading h);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_ZUPT_H */
