/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-nav.h
 * @brief Navigation frames, rotations and the Earth model (WGS 84).
 *
 * Frames (all right-handed):
 * - i, inertial: origin at the Earth's centre, z along the spin axis, x at
 *   the Greenwich meridian at t = 0 (the Earth turns at SSCOPE_NAV_WGS84_OMEGA
 *   about z);
 * - e, ECEF (Earth-centred Earth-fixed): x at the equator and Greenwich
 *   meridian, z along the spin axis;
 * - n, local level NED: north, east, down (down along the normal of the
 *   WGS 84 ellipsoid, i.e. geodetic); ENU is (east, north, up);
 * - w, wander azimuth: local level with x rotated by the wander angle
 *   alpha from north towards east about down, kept so that the frame does
 *   not turn about the vertical relative to the Earth
 *   (alpha' = lon' sin(lat));
 * - c, geocentric local level: as NED but with the geocentric latitude
 *   (down towards the Earth's centre);
 * - t, local geodetic (fixed tangent plane): NED axes of one origin point,
 *   fixed to the Earth, positions relative to that origin;
 * - b, body: x forward, y right, z down (FRD).
 *
 * Rotations: C_a^b is the direction-cosine matrix that takes a vector's
 * components in frame a to frame b (v_b = C_a^b v_a).  Euler angles are
 * aerospace Z-Y-X: C_b^n = Rz(yaw) Ry(pitch) Rx(roll), the convention of
 * `inclino`: gravity seen in the body of a still sensor is
 * C_n^b (0, 0, g) = g (-sin(pitch), sin(roll) cos(pitch),
 * cos(roll) cos(pitch)).  Quaternions are Hamilton, scalar first,
 * q = (w, x, y, z), and q_b^n rotates body vectors into n:
 * v_n = q v_b q*.
 *
 * Earth: WGS 84 (NIMA TR8350.2, 3rd ed., 2000): semi-major axis a,
 * flattening f, angular rate omega, GM; normal gravity on the ellipsoid by
 * Somigliana's closed formula from the published equatorial and polar
 * values, and above it by the second-order series in height of TR8350.2
 * eq. 4-3 (relative error below 1e-6 up to 20 km, about (h / a)^3 beyond).
 */
#ifndef SSCOPE_NAV_H
#define SSCOPE_NAV_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** WGS 84 semi-major axis, m. */
#define SSCOPE_NAV_WGS84_A 6378137.0
/** WGS 84 inverse flattening. */
#define SSCOPE_NAV_WGS84_INV_F 298.257223563
/** WGS 84 angular rate of the Earth, rad/s. */
#define SSCOPE_NAV_WGS84_OMEGA 7.292115e-5
/** WGS 84 gravitational constant GM (with the atmosphere), m^3/s^2. */
#define SSCOPE_NAV_WGS84_GM 3.986004418e14
/** WGS 84 normal gravity at the equator, m/s^2. */
#define SSCOPE_NAV_WGS84_GAMMA_E 9.7803253359
/** WGS 84 normal gravity at the poles, m/s^2. */
#define SSCOPE_NAV_WGS84_GAMMA_P 9.8321849378

/** A point in geodetic coordinates (WGS 84). */
struct sscope_nav_geodetic {
	double lat_rad;  /**< geodetic latitude, [-pi/2, pi/2] */
	double lon_rad;  /**< longitude, (-pi, pi] on output */
	double height_m; /**< height above the ellipsoid */
};

/** Derived WGS 84 constants. */
struct sscope_nav_wgs84 {
	double a, f, b; /**< semi-axes (m) and flattening */
	double e2;      /**< first eccentricity squared f (2 - f) */
	double k;       /**< Somigliana's constant b gamma_p / (a gamma_e) - 1 */
	double m;       /**< omega^2 a^2 b / GM */
};

/** @return the WGS 84 constants (a static object). */
const struct sscope_nav_wgs84 *sscope_nav_wgs84(void);

/**
 * Geodetic to ECEF.
 * @param g    the point (|lat| <= pi/2).
 * @param r_m  receives x, y, z, m.
 * @return 0, or -EINVAL (NULL, a non-finite value, |lat| > pi/2).
 */
int sscope_nav_geodetic_to_ecef(const struct sscope_nav_geodetic *g,
				double r_m[3]);

/**
 * ECEF to geodetic: the nearest point of the ellipsoid found in the
 * meridian plane as the root of Eberly's monotone function ("Distance from
 * a point to an ellipse, an ellipsoid, or a hyperellipsoid", Geometric
 * Tools, 2013), solved by Newton's method safeguarded by bisection to the
 * last bit of a double.  Accurate
 * to the rounding of the input everywhere (a few nanometres at the Earth's
 * surface), poles and the centre included.  On the spin axis the longitude
 * is 0; at the centre the result is the north pole with height -b; inside
 * the ellipsoid's evolute in the equatorial plane (|r| < a e^2, about
 * 43 km) the nearest point is not unique and the northern one is returned.
 * @return 0, or -EINVAL (NULL, non-finite coordinates).
 */
int sscope_nav_ecef_to_geodetic(const double r_m[3],
				struct sscope_nav_geodetic *g);

/**
 * Geocentric latitude of a point: atan2(z, sqrt(x^2 + y^2)) of its ECEF
 * position (on the ellipsoid tan(psi) = (1 - e^2) tan(lat)).
 * @return the latitude, rad (NaN for invalid input).
 */
double sscope_nav_geocentric_latitude(const struct sscope_nav_geodetic *g);

/** C_e^n: ECEF to local level NED at latitude and longitude (rad). */
void sscope_nav_dcm_ecef_to_ned(double lat_rad, double lon_rad,
				double C[3][3]);

/** C_e^n for ENU axes (east, north, up). */
void sscope_nav_dcm_ecef_to_enu(double lat_rad, double lon_rad,
				double C[3][3]);

/**
 * C_e^c: ECEF to the geocentric local-level frame (north, east, towards
 * the centre) of an ECEF position.
 * @return 0, or -EDOM on the spin axis (no north), -EINVAL.
 */
int sscope_nav_dcm_ecef_to_geocentric(const double r_m[3], double C[3][3]);

/** C_n^w: local level NED to the wander-azimuth frame of angle alpha. */
void sscope_nav_dcm_ned_to_wander(double alpha_rad, double C[3][3]);

/** C_e^w = C_n^w C_e^n. */
void sscope_nav_dcm_ecef_to_wander(double lat_rad, double lon_rad,
				   double alpha_rad, double C[3][3]);

/** C_i^e at time t: rotation by omega t about z. */
void sscope_nav_dcm_eci_to_ecef(double t_s, double C[3][3]);

/** A local geodetic frame: NED axes fixed at an origin point. */
struct sscope_nav_ltp {
	struct sscope_nav_geodetic origin;
	double r0_m[3];   /**< origin, ECEF */
	double C[3][3];   /**< C_e^t (ECEF to the tangent plane's NED) */
};

/**
 * Set up a tangent plane at @p origin.
 * @return 0 or -EINVAL (as sscope_nav_geodetic_to_ecef()).
 */
int sscope_nav_ltp_init(struct sscope_nav_ltp *t,
			const struct sscope_nav_geodetic *origin);

/** ECEF position to tangent-plane coordinates (north, east, down), m. */
void sscope_nav_ltp_from_ecef(const struct sscope_nav_ltp *t,
			      const double r_m[3], double ned_m[3]);

/** Tangent-plane coordinates (north, east, down) to ECEF, m. */
void sscope_nav_ltp_to_ecef(const struct sscope_nav_ltp *t,
			    const double ned_m[3], double r_m[3]);

/** (north, east, down) to (east, north, up) or back (the same map). */
void sscope_nav_ned_enu(const double in[3], double out[3]);

/* ------------------------------------------------------------------ */
/* Rotations                                                           */
/* ------------------------------------------------------------------ */

/** C_b^n from roll, pitch, yaw (rad), Z-Y-X. */
void sscope_nav_dcm_from_euler(double roll_rad, double pitch_rad,
			       double yaw_rad, double C[3][3]);

/**
 * Roll, pitch, yaw (rad) of C_b^n; pitch in [-pi/2, pi/2], roll and yaw
 * in (-pi, pi].  At pitch +-90 degrees (gimbal lock) roll is set to 0.
 */
void sscope_nav_euler_from_dcm(const double C[3][3], double *roll_rad,
			       double *pitch_rad, double *yaw_rad);

/** C_b^n of a unit quaternion q_b^n. */
void sscope_nav_dcm_from_quat(const double q[4], double C[3][3]);

/** The unit quaternion (w >= 0) of an orthonormal C_b^n (Shepperd). */
void sscope_nav_quat_from_dcm(const double C[3][3], double q[4]);

/** r = p q (Hamilton product). */
void sscope_nav_quat_mul(const double p[4], const double q[4], double r[4]);

/** The quaternion of a rotation vector (angle |v| about v / |v|), rad. */
void sscope_nav_quat_from_rotvec(const double v_rad[3], double q[4]);

/** The rotation vector of a unit quaternion (angle in [0, pi]), rad. */
void sscope_nav_rotvec_from_quat(const double q[4], double v_rad[3]);

/** Scale @p q to unit norm. */
void sscope_nav_quat_normalize(double q[4]);

/* ------------------------------------------------------------------ */
/* Earth model                                                         */
/* ------------------------------------------------------------------ */

/**
 * Radii of curvature at latitude @p lat_rad: meridian
 * R_N = a (1 - e^2) / (1 - e^2 sin^2)^(3/2) and transverse (prime
 * vertical) R_E = a / sqrt(1 - e^2 sin^2), m.
 */
void sscope_nav_radii(double lat_rad, double *r_n_m, double *r_e_m);

/**
 * Normal gravity (gravitation plus centrifugal) at latitude and height:
 * Somigliana on the ellipsoid, TR8350.2 eq. 4-3 above it, m/s^2.  Its
 * direction is the ellipsoid normal (down in NED); the deflection above
 * the ellipsoid (below 1e-5 rad at 20 km) is neglected.
 */
double sscope_nav_gravity(double lat_rad, double height_m);

/** The Earth model at one point, computed once for several uses. */
struct sscope_nav_earth {
	double sin_lat, cos_lat;
	double r_n_m, r_e_m;    /**< sscope_nav_radii() */
	double gravity_m_s2;    /**< sscope_nav_gravity() */
};

/** Fill @p e for latitude and height (one sine, one cosine, one root). */
void sscope_nav_earth_at(double lat_rad, double height_m,
			 struct sscope_nav_earth *e);

/**
 * Earth rate and transport rate in NED at the point of @p e (as
 * sscope_nav_earth_rate() and sscope_nav_transport_rate()); either output
 * may be NULL.
 */
void sscope_nav_rates_at(const struct sscope_nav_earth *e, double height_m,
			 const double v_ned[3], double w_ie[3], double w_en[3]);

/** Earth rate in NED: omega (cos lat, 0, -sin lat), rad/s. */
void sscope_nav_earth_rate(double lat_rad, double w_ned[3]);

/**
 * Transport rate (rate of NED relative to ECEF) in NED:
 * (v_E / (R_E + h), -v_N / (R_N + h), -v_E tan(lat) / (R_E + h)), rad/s.
 */
void sscope_nav_transport_rate(double lat_rad, double height_m,
			       const double v_ned[3], double w_ned[3]);

/**
 * Rate of the wander angle that keeps the wander frame from turning
 * about the vertical relative to the Earth: lon' sin(lat), with
 * lon' = v_E / ((R_E + h) cos(lat)), rad/s.
 */
double sscope_nav_wander_rate(double lat_rad, double height_m,
			      const double v_ned[3]);

/**
 * Transport rate of the wander frame in its own axes,
 * C_n^w (omega_en^n + (0, 0, alpha')): its vertical component is zero.
 */
void sscope_nav_transport_rate_wander(double lat_rad, double height_m,
				      const double v_ned[3], double alpha_rad,
				      double w_w[3]);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_NAV_H */
