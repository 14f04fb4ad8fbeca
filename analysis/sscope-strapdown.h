/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-strapdown.h
 * @brief Strapdown inertial navigation in the local-level (NED) frame on
 *        the WGS 84 ellipsoid.
 *
 * The mechanisation integrates gyro angle increments and accelerometer
 * velocity increments (the integrals of angular rate and specific force
 * over each sample interval, body axes FRD) to attitude, velocity and
 * geodetic position, taking two samples per update:
 * - attitude by quaternion: body rotation vector
 *   phi = a1 + a2 + (2/3) a1 x a2 (two-sample coning correction), frame
 *   rotation zeta = (omega_ie + omega_en) T at the mid-point,
 *   q(k) = exp(-zeta) q(k-1) exp(phi);
 * - velocity: specific-force increment in the body frame of the start of
 *   the update dv = v + k1 a x v + k2 a x (a x v) + (2/3)(a1 x v2 + v1 x a2)
 *   with a = a1 + a2, v = v1 + v2, k1 = (1 - cos|a|)/|a|^2 ~ 1/2,
 *   k2 = (1 - sin|a|/|a|)/|a|^2 ~ 1/6 (rotation compensation, exact for a
 *   constant rate) and the two-sample sculling correction, rotated by
 *   (I - [zeta x] / 2) C_b^n, plus (g - (2 omega_ie + omega_en) x v) T
 *   (normal gravity, Coriolis and transport-rate terms) at the mid-point;
 * - position: trapezoidal integration of v_N / (R_N + h),
 *   v_E / ((R_E + h) cos lat) and -v_D.
 * Mid-point quantities come from one predictor-corrector pass, so the
 * update is second-order accurate in the update interval.  References:
 * P. G. Savage, "Strapdown inertial navigation integration algorithm
 * design", J. Guidance, Control and Dynamics 21(1-2), 1998; P. D. Groves,
 * "Principles of GNSS, Inertial, and Multisensor Integrated Navigation
 * Systems", 2nd ed., 2013, sec. 5.4-5.5.
 */
#ifndef SSCOPE_STRAPDOWN_H
#define SSCOPE_STRAPDOWN_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Navigation state. */
struct sscope_strapdown_state {
	double lat_rad, lon_rad, height_m; /**< geodetic position (WGS 84) */
	double v_ned_m_s[3];               /**< velocity relative to the
					        Earth, NED */
	double q_bn[4];                    /**< attitude q_b^n (unit) */
};

/**
 * Initialise a state from position, velocity and Euler angles (roll,
 * pitch, yaw of the body in NED, rad).
 * @return 0, or -EINVAL (NULL, non-finite, |lat| >= pi/2).
 */
int sscope_strapdown_init(struct sscope_strapdown_state *s, double lat_rad,
			  double lon_rad, double height_m, const double v_ned[3],
			  double roll_rad, double pitch_rad, double yaw_rad);

/**
 * One update over two samples of interval @p dt_s each.
 * @param dth1, dth2  angle increments of the two samples, body, rad.
 * @param dv1, dv2    velocity increments of the two samples, body, m/s.
 * @param dt_s        sample interval, s (the update spans 2 dt_s).
 * No checks in this hot path: the caller passes finite values and a
 * latitude away from the poles (the transport rate has tan(lat)).
 */
void sscope_strapdown_step2(struct sscope_strapdown_state *s,
			    const double dth1[3], const double dth2[3],
			    const double dv1[3], const double dv2[3],
			    double dt_s);

/** Roll, pitch, yaw (rad) of a state's attitude. */
void sscope_strapdown_euler(const struct sscope_strapdown_state *s,
			    double *roll_rad, double *pitch_rad,
			    double *yaw_rad);

/*
 * Wander-azimuth mechanisation, valid at every latitude (Titterton &
 * Weston, "Strapdown Inertial Navigation Technology", 2nd ed., 2004,
 * sec. 3.7; P. G. Savage, "Strapdown Analytics", 2nd ed., 2007, ch. 4-5;
 * C. Jekeli, "Inertial Navigation Systems with Geodetic Applications",
 * 2001, sec. 4.3).  The navigation frame w is local level (down shared
 * with NED) and does not turn about the vertical relative to the Earth;
 * its x axis is at the wander angle alpha from north, towards east.
 * Position is the direction-cosine matrix C_w^e (kept as a quaternion)
 * and the height, integrated as C_w^e' = C_w^e [rho x] with the transport
 * rate rho = (w_y, -w_x, 0), w = v_h / (R_E + h) + kappa z_h (z_h . v_h),
 * z_h the horizontal part of the polar axis in w (cos(lat) times the
 * north unit vector) and kappa = a e^2 / ((1 - e^2 sin^2)^(3/2)
 * (R_N + h)(R_E + h)): neither tan(lat) nor the longitude rate appears,
 * and the wander angle is read from C_w^e, never integrated.  Velocity
 * and attitude are updated as in the NED mechanisation above (the same
 * coning, sculling, Coriolis and gravity), with omega_ie^w =
 * Omega C_e^w z_e.
 */

/** Wander-azimuth navigation state. */
struct sscope_strapdown_wander {
	double q_we[4];     /**< position and wander angle: C_w^e (unit) */
	double height_m;    /**< height above the WGS 84 ellipsoid */
	double v_w_m_s[3];  /**< velocity relative to the Earth, wander axes */
	double q_bw[4];     /**< attitude q_b^w (unit) */
};

/**
 * Errors of a gimballed platform (the sensors on a platform torqued to
 * the navigation frame, see sscope_strapdown_wander_step2()); all in
 * platform axes.
 */
struct sscope_strapdown_platform {
	double gyro_m[3][3];   /**< gyro error matrix (scale factors on the
				    diagonal, misalignments off it), ratio */
	double accel_m[3][3];  /**< accelerometer error matrix, ratio */
	double dtheta_rad[3];  /**< gyro bias and noise over the update, rad */
	double dv_m_s[3];      /**< accelerometer bias and noise over the
				    update, m/s */
};

/**
 * Initialise from geodetic position (any latitude, poles included),
 * velocity (NED) and Euler angles; the wander angle starts at 0 (at a
 * pole, north is that of the longitude given).
 * @return 0, or -EINVAL (NULL, non-finite, |lat| > pi/2).
 */
int sscope_strapdown_wander_init(struct sscope_strapdown_wander *s,
				 double lat_rad, double lon_rad, double height_m,
				 const double v_ned[3], double roll_rad,
				 double pitch_rad, double yaw_rad);

/**
 * One update over two samples (see sscope_strapdown_step2()).
 * @param pe  NULL: strapdown (the increments are the sensors' readings in
 *            body axes).  Otherwise a gimballed platform: the increments
 *            are the true body motion (they only carry the attitude the
 *            gimbal pick-offs read), the accelerometers on the platform
 *            read the specific force in platform axes through
 *            (I + accel_m) plus dv_m_s, and the platform, torqued at the
 *            computed rate omega_ie + rho of the navigation frame, drifts
 *            by its gyros' error on that commanded rate,
 *            gyro_m (omega_ie + rho) T + dtheta_rad: body rates never
 *            reach its gyros.
 */
void sscope_strapdown_wander_step2(struct sscope_strapdown_wander *s,
				   const double dth1[3], const double dth2[3],
				   const double dv1[3], const double dv2[3],
				   double dt_s,
				   const struct sscope_strapdown_platform *pe);

/**
 * Geodetic position (latitude by atan2, accurate at the poles; longitude
 * 0 on the axis), the wander angle and C_w^e of a state; any output may
 * be NULL.
 */
void sscope_strapdown_wander_position(const struct sscope_strapdown_wander *s,
				      double *lat_rad, double *lon_rad,
				      double *alpha_rad, double C_we[3][3]);

/**
 * The same state in the NED form (latitude, longitude, NED velocity,
 * q_b^n) through the wander angle: meaningful away from the poles, where
 * north is defined.
 */
void sscope_strapdown_wander_to_ned(const struct sscope_strapdown_wander *s,
				    struct sscope_strapdown_state *n);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_STRAPDOWN_H */
