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

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_STRAPDOWN_H */
