/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Navigation frames, rotations and the WGS 84 Earth model (NIMA TR8350.2,
 * 3rd ed., 2000: defining constants, Somigliana's normal gravity, eq. 4-1,
 * and its series in height, eq. 4-3).  Frame and rotation conventions are
 * those of P. D. Groves, "Principles of GNSS, Inertial, and Multisensor
 * Integrated Navigation Systems", 2nd ed., 2013, ch. 2 (DCMs C_a^b,
 * Euler Z-Y-X, Hamilton quaternions) and D. H. Titterton and J. L. Weston,
 * "Strapdown Inertial Navigation Technology", 2nd ed., 2004, ch. 3
 * (wander azimuth).
 *
 * ECEF to geodetic: the height is the signed distance to the nearest point
 * of the ellipsoid, found in the meridian plane by D. Eberly's robust
 * method ("Distance from a point to an ellipse, an ellipsoid, or a
 * hyperellipsoid", 2013): the nearest point x of the ellipse with semi-axes
 * (e0, e1) to a point y of the first quadrant satisfies
 * x_i = e_i^2 y_i / (t + e_i^2) for the unique root t > -e1^2 of the
 * decreasing function F(t) = sum (e_i y_i / (t + e_i^2))^2 - 1; Newton's
 * method kept inside Eberly's bracket finds it to the last bit in scaled
 * variables, with no loss near the poles, the equator or the centre (the
 * cases closed-form methods such as Vermeille's or Heikkinen's treat
 * separately).
 */
#include "internal.h"

#include <math.h>
#include <string.h>

#include "sscope-nav.h"


static const struct sscope_nav_wgs84 wgs84 = {
	.a = SSCOPE_NAV_WGS84_A,
	.f = 1 / SSCOPE_NAV_WGS84_INV_F,
	/* b = a (1 - f) */
	.b = SSCOPE_NAV_WGS84_A * (1 - 1 / SSCOPE_NAV_WGS84_INV_F),
	/* e^2 = f (2 - f) */
	.e2 = (1 / SSCOPE_NAV_WGS84_INV_F) * (2 - 1 / SSCOPE_NAV_WGS84_INV_F),
	/* k = b gamma_p / (a gamma_e) - 1 */
	.k = (1 - 1 / SSCOPE_NAV_WGS84_INV_F) * SSCOPE_NAV_WGS84_GAMMA_P /
		     SSCOPE_NAV_WGS84_GAMMA_E -
	     1,
	/* m = omega^2 a^2 b / GM */
	.m = SSCOPE_NAV_WGS84_OMEGA * SSCOPE_NAV_WGS84_OMEGA * SSCOPE_NAV_WGS84_A *
	     SSCOPE_NAV_WGS84_A * SSCOPE_NAV_WGS84_A * (1 - 1 / SSCOPE_NAV_WGS84_INV_F) /
	     SSCOPE_NAV_WGS84_GM,
};

const struct sscope_nav_wgs84 *sscope_nav_wgs84(void)
{
	return &wgs84;
}

int sscope_nav_geodetic_to_ecef(const struct sscope_nav_geodetic *g,
				double r[3])
{
	double s, c, N;

	if (!g || !r || !isfinite(g->lat_rad) || !isfinite(g->lon_rad) ||
	    !isfinite(g->height_m) || fabs(g->lat_rad) > PI / 2)
		return -EINVAL;
	s = sin(g->lat_rad);
	c = cos(g->lat_rad);
	N = wgs84.a / sqrt(1 - wgs84.e2 * s * s);
	r[0] = (N + g->height_m) * c * cos(g->lon_rad);
	r[1] = (N + g->height_m) * c * sin(g->lon_rad);
	r[2] = (N * (1 - wgs84.e2) + g->height_m) * s;
	return 0;
}

/*
 * Root of Eberly's F(s) = (r0 z0 / (s + r0))^2 + (z1 / (s + 1))^2 - 1
 * (r0 = (e0 / e1)^2, z_i = y_i / e_i, g = F(0)), written in u = s + 1 so
 * that points near the centre, where the root approaches s = -1, keep
 * full relative precision: F(u) = (n0 / (u + e))^2 + (z1 / u)^2 - 1 with
 * n0 = r0 z0 and e = r0 - 1 (the second eccentricity squared).  The root
 * is bracketed by [z1, 1] inside and [1, |(n0, z1)|] outside, where F is
 * decreasing and convex; Newton's method from u = 1, safeguarded by the
 * bracket (a step leaving it bisects instead), converges quadratically and
 * ends when the step is below the resolution of u.
 */
static double eberly_root(double n0, double e, double z1, double g)
{
	double lo, hi, u = 1;

	if (g > 0) {
		lo = 1;
		hi = hypot(n0, z1);
	} else {
		lo = z1;
		hi = 1;
	}
	for (int i = 0; i < 2200; i++) {
		double a = n0 / (u + e), b = z1 / u;
		double f = a * a + b * b - 1, step, t;

		if (f > 0)
			lo = u;
		else if (f < 0)
			hi = u;
		else
			break;
		/* F' = -2 (a^2 / (u + e) + b^2 / u) */
		step = f / (2 * (a * a / (u + e) + b * b / u));
		t = u + step;
		if (!(t > lo && t < hi)) {
			t = 0.5 * (lo + hi);
			if (t == lo || t == hi)
				break;
		} else if (fabs(step) <= 0x1p-60 * u) {
			u = t;
			break;
		}
		u = t;
	}
	return u;
}

int sscope_nav_ecef_to_geodetic(const double r[3],
				struct sscope_nav_geodetic *g)
{
	const double e0 = wgs84.a, e1 = wgs84.b;
	double y0, y1, x0, x1, d;
	bool inside;

	if (!r || !g || !isfinite(r[0]) || !isfinite(r[1]) || !isfinite(r[2]))
		return -EINVAL;
	y0 = hypot(r[0], r[1]);
	y1 = fabs(r[2]);
	if (y1 > 0) {
		if (y0 > 0) {
			double z0 = y0 / e0, z1 = y1 / e1;
			double gg = z0 * z0 + z1 * z1 - 1;

			if (gg != 0) {
				double r0 = (e0 / e1) * (e0 / e1);
				/* r0 - 1 without cancellation */
				double e = (e0 - e1) * (e0 + e1) / (e1 * e1);
				double u = eberly_root(r0 * z0, e, z1, gg);

				x0 = r0 * y0 / (u + e);
				x1 = y1 / u;
			} else {
				x0 = y0;
				x1 = y1;
			}
			inside = gg < 0;
		} else {
			x0 = 0;
			x1 = e1;
			inside = y1 < e1;
		}
	} else {
		double num = e0 * y0, den = e0 * e0 - e1 * e1;

		if (num < den) {
			double xd = num / den;

			x0 = e0 * xd;
			x1 = e1 * sqrt(1 - xd * xd);
		} else {
			x0 = e0;
			x1 = 0;
		}
		inside = y0 < e0;
	}
	d = hypot(x0 - y0, x1 - y1);
	/* the normal at (x0, x1) is (x0 / e0^2, x1 / e1^2) */
	g->lat_rad = atan2(x1 * e0 * e0, x0 * e1 * e1);
	if (r[2] < 0)
		g->lat_rad = -g->lat_rad;
	g->lon_rad = y0 > 0 ? atan2(r[1], r[0]) : 0;
	g->height_m = inside ? -d : d;
	return 0;
}

double sscope_nav_geocentric_latitude(const struct sscope_nav_geodetic *g)
{
	double r[3];

	if (sscope_nav_geodetic_to_ecef(g, r))
		return (double)NAN;
	return atan2(r[2], hypot(r[0], r[1]));
}

void sscope_nav_dcm_ecef_to_ned(double lat, double lon, double C[3][3])
{
	double sp = sin(lat), cp = cos(lat), sl = sin(lon), cl = cos(lon);

	C[0][0] = -sp * cl;
	C[0][1] = -sp * sl;
	C[0][2] = cp;
	C[1][0] = -sl;
	C[1][1] = cl;
	C[1][2] = 0;
	C[2][0] = -cp * cl;
	C[2][1] = -cp * sl;
	C[2][2] = -sp;
}

void sscope_nav_dcm_ecef_to_enu(double lat, double lon, double C[3][3])
{
	double N[3][3];

	sscope_nav_dcm_ecef_to_ned(lat, lon, N);
	for (int j = 0; j < 3; j++) {
		C[0][j] = N[1][j];
		C[1][j] = N[0][j];
		C[2][j] = -N[2][j];
	}
}

int sscope_nav_dcm_ecef_to_geocentric(const double r[3], double C[3][3])
{
	double p;

	if (!r || !C || !isfinite(r[0]) || !isfinite(r[1]) || !isfinite(r[2]))
		return -EINVAL;
	p = hypot(r[0], r[1]);
	if (p == 0)
		return -EDOM;
	sscope_nav_dcm_ecef_to_ned(atan2(r[2], p), atan2(r[1], r[0]), C);
	return 0;
}

void sscope_nav_dcm_ned_to_wander(double alpha, double C[3][3])
{
	double s = sin(alpha), c = cos(alpha);

	C[0][0] = c;
	C[0][1] = s;
	C[0][2] = 0;
	C[1][0] = -s;
	C[1][1] = c;
	C[1][2] = 0;
	C[2][0] = 0;
	C[2][1] = 0;
	C[2][2] = 1;
}

static void mat_mul(const double A[3][3], const double B[3][3], double R[3][3])
{
	double T[3][3];

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			T[i][j] = A[i][0] * B[0][j] + A[i][1] * B[1][j] +
				  A[i][2] * B[2][j];
	memcpy(R, T, sizeof(T));
}

void sscope_nav_dcm_ecef_to_wander(double lat, double lon, double alpha,
				   double C[3][3])
{
	double Cn[3][3], Cw[3][3];

	sscope_nav_dcm_ecef_to_ned(lat, lon, Cn);
	sscope_nav_dcm_ned_to_wander(alpha, Cw);
	mat_mul(Cw, Cn, C);
}

void sscope_nav_dcm_eci_to_ecef(double t_s, double C[3][3])
{
	double a = SSCOPE_NAV_WGS84_OMEGA * t_s, s = sin(a), c = cos(a);

	C[0][0] = c;
	C[0][1] = s;
	C[0][2] = 0;
	C[1][0] = -s;
	C[1][1] = c;
	C[1][2] = 0;
	C[2][0] = 0;
	C[2][1] = 0;
	C[2][2] = 1;
}

int sscope_nav_ltp_init(struct sscope_nav_ltp *t,
			const struct sscope_nav_geodetic *origin)
{
	int rc;

	if (!t)
		return -EINVAL;
	rc = sscope_nav_geodetic_to_ecef(origin, t->r0_m);
	if (rc)
		return rc;
	t->origin = *origin;
	sscope_nav_dcm_ecef_to_ned(origin->lat_rad, origin->lon_rad, t->C);
	return 0;
}

void sscope_nav_ltp_from_ecef(const struct sscope_nav_ltp *t,
			      const double r[3], double ned[3])
{
	double d[3] = { r[0] - t->r0_m[0], r[1] - t->r0_m[1], r[2] - t->r0_m[2] };

	for (int i = 0; i < 3; i++)
		ned[i] = t->C[i][0] * d[0] + t->C[i][1] * d[1] + t->C[i][2] * d[2];
}

void sscope_nav_ltp_to_ecef(const struct sscope_nav_ltp *t,
			    const double ned[3], double r[3])
{
	double v[3] = { ned[0], ned[1], ned[2] };

	for (int i = 0; i < 3; i++)
		r[i] = t->r0_m[i] + (t->C[0][i] * v[0] + t->C[1][i] * v[1] +
				     t->C[2][i] * v[2]);
}

void sscope_nav_ned_enu(const double in[3], double out[3])
{
	double a = in[0], b = in[1], c = in[2];

	out[0] = b;
	out[1] = a;
	out[2] = -c;
}

/* ------------------------------------------------------------ rotations */

void sscope_nav_dcm_from_euler(double roll, double pitch, double yaw,
			       double C[3][3])
{
	double sr = sin(roll), cr = cos(roll), sp = sin(pitch), cp = cos(pitch);
	double sy = sin(yaw), cy = cos(yaw);

	C[0][0] = cp * cy;
	C[0][1] = -cr * sy + sr * sp * cy;
	C[0][2] = sr * sy + cr * sp * cy;
	C[1][0] = cp * sy;
	C[1][1] = cr * cy + sr * sp * sy;
	C[1][2] = -sr * cy + cr * sp * sy;
	C[2][0] = -sp;
	C[2][1] = sr * cp;
	C[2][2] = cr * cp;
}

void sscope_nav_euler_from_dcm(const double C[3][3], double *roll,
			       double *pitch, double *yaw)
{
	double h = hypot(C[0][0], C[1][0]);

	*pitch = atan2(-C[2][0], h);
	if (h > 1e-12 * fabs(C[2][0])) {
		*roll = atan2(C[2][1], C[2][2]);
		*yaw = atan2(C[1][0], C[0][0]);
	} else {
		/* gimbal lock: only yaw -+ roll is defined */
		*roll = 0;
		*yaw = atan2(-C[0][1], C[1][1]);
	}
}

void sscope_nav_dcm_from_quat(const double q[4], double C[3][3])
{
	double w = q[0], x = q[1], y = q[2], z = q[3];

	C[0][0] = 1 - 2 * (y * y + z * z);
	C[0][1] = 2 * (x * y - w * z);
	C[0][2] = 2 * (x * z + w * y);
	C[1][0] = 2 * (x * y + w * z);
	C[1][1] = 1 - 2 * (x * x + z * z);
	C[1][2] = 2 * (y * z - w * x);
	C[2][0] = 2 * (x * z - w * y);
	C[2][1] = 2 * (y * z + w * x);
	C[2][2] = 1 - 2 * (x * x + y * y);
}

void sscope_nav_quat_from_dcm(const double C[3][3], double q[4])
{
	/* Shepperd: divide by the largest of the four candidates */
	double tr = C[0][0] + C[1][1] + C[2][2];
	double v[4] = { 1 + tr, 1 + 2 * C[0][0] - tr, 1 + 2 * C[1][1] - tr,
			1 + 2 * C[2][2] - tr };
	int k = 0;

	for (int i = 1; i < 4; i++)
		if (v[i] > v[k])
			k = i;
	{
		double s = 0.5 * sqrt(v[k]), f = 0.25 / s;

		switch (k) {
		case 0:
			q[0] = s;
			q[1] = (C[2][1] - C[1][2]) * f;
			q[2] = (C[0][2] - C[2][0]) * f;
			q[3] = (C[1][0] - C[0][1]) * f;
			break;
		case 1:
			q[1] = s;
			q[0] = (C[2][1] - C[1][2]) * f;
			q[2] = (C[0][1] + C[1][0]) * f;
			q[3] = (C[0][2] + C[2][0]) * f;
			break;
		case 2:
			q[2] = s;
			q[0] = (C[0][2] - C[2][0]) * f;
			q[1] = (C[0][1] + C[1][0]) * f;
			q[3] = (C[1][2] + C[2][1]) * f;
			break;
		default:
			q[3] = s;
			q[0] = (C[1][0] - C[0][1]) * f;
			q[1] = (C[0][2] + C[2][0]) * f;
			q[2] = (C[1][2] + C[2][1]) * f;
			break;
		}
	}
	if (q[0] < 0)
		for (int i = 0; i < 4; i++)
			q[i] = -q[i];
	sscope_nav_quat_normalize(q);
}

void sscope_nav_quat_mul(const double p[4], const double q[4], double r[4])
{
	double w = p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3];
	double x = p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2];
	double y = p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1];
	double z = p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0];

	r[0] = w;
	r[1] = x;
	r[2] = y;
	r[3] = z;
}

void sscope_nav_quat_from_rotvec(const double v[3], double q[4])
{
	double t2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], c, s;

	if (t2 < 1e-10) {
		/* series: cos(t/2) and sin(t/2)/t to below 1e-25 */
		c = 1 - t2 / 8 + t2 * t2 / 384;
		s = 0.5 - t2 / 48 + t2 * t2 / 3840;
	} else {
		double t = sqrt(t2);

		c = cos(t / 2);
		s = sin(t / 2) / t;
	}
	q[0] = c;
	q[1] = s * v[0];
	q[2] = s * v[1];
	q[3] = s * v[2];
}

void sscope_nav_rotvec_from_quat(const double q[4], double v[3])
{
	double w = q[0], x = q[1], y = q[2], z = q[3];
	double sn = sqrt(x * x + y * y + z * z), k;

	if (w < 0) {
		w = -w;
		x = -x;
		y = -y;
		z = -z;
	}
	/* angle = 2 atan2(|xyz|, w), accurate for small and large angles */
	k = sn > 0 ? 2 * atan2(sn, w) / sn : 2 / w;
	v[0] = k * x;
	v[1] = k * y;
	v[2] = k * z;
}

void sscope_nav_quat_normalize(double q[4])
{
	double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);

	for (int i = 0; i < 4; i++)
		q[i] /= n;
}

/* ------------------------------------------------------------ Earth */

/* radii from s = sin(lat); sw receives sqrt(1 - e^2 s^2) */
static void radii_sin(double s, double *r_n, double *r_e, double *sw_out)
{
	double w = 1 - wgs84.e2 * s * s, sw = sqrt(w);

	if (r_n)
		*r_n = wgs84.a * (1 - wgs84.e2) / (w * sw);
	if (r_e)
		*r_e = wgs84.a / sw;
	if (sw_out)
		*sw_out = sw;
}

/* normal gravity from s2 = sin^2(lat) and sw = sqrt(1 - e^2 s2) */
static double gravity_sin(double s2, double sw, double h)
{
	double g0 = SSCOPE_NAV_WGS84_GAMMA_E * (1 + wgs84.k * s2) / sw;

	return g0 * (1 - 2 / wgs84.a * (1 + wgs84.f + wgs84.m - 2 * wgs84.f * s2) * h +
		     3 * h * h / (wgs84.a * wgs84.a));
}

void sscope_nav_radii(double lat, double *r_n, double *r_e)
{
	radii_sin(sin(lat), r_n, r_e, NULL);
}

double sscope_nav_gravity(double lat, double h)
{
	double s = sin(lat);

	return gravity_sin(s * s, sqrt(1 - wgs84.e2 * s * s), h);
}

void sscope_nav_earth_at(double lat, double h, struct sscope_nav_earth *e)
{
	double sw;

	e->sin_lat = sin(lat);
	e->cos_lat = cos(lat);
	radii_sin(e->sin_lat, &e->r_n_m, &e->r_e_m, &sw);
	e->gravity_m_s2 = gravity_sin(e->sin_lat * e->sin_lat, sw, h);
}

void sscope_nav_rates_at(const struct sscope_nav_earth *e, double h,
			 const double v[3], double w_ie[3], double w_en[3])
{
	if (w_ie) {
		w_ie[0] = SSCOPE_NAV_WGS84_OMEGA * e->cos_lat;
		w_ie[1] = 0;
		w_ie[2] = -SSCOPE_NAV_WGS84_OMEGA * e->sin_lat;
	}
	if (w_en) {
		w_en[0] = v[1] / (e->r_e_m + h);
		w_en[1] = -v[0] / (e->r_n_m + h);
		w_en[2] = -v[1] * (e->sin_lat / e->cos_lat) / (e->r_e_m + h);
	}
}

void sscope_nav_earth_rate(double lat, double w[3])
{
	struct sscope_nav_earth e = { .sin_lat = sin(lat), .cos_lat = cos(lat) };

	sscope_nav_rates_at(&e, 0, NULL, w, NULL);
}

void sscope_nav_transport_rate(double lat, double h, const double v[3],
			       double w[3])
{
	struct sscope_nav_earth e;

	sscope_nav_earth_at(lat, h, &e);
	sscope_nav_rates_at(&e, h, v, NULL, w);
}

double sscope_nav_wander_rate(double lat, double h, const double v[3])
{
	double re;

	sscope_nav_radii(lat, NULL, &re);
	/* lon' sin(lat) = v_E tan(lat) / (R_E + h) */
	return v[1] * tan(lat) / (re + h);
}

void sscope_nav_transport_rate_wander(double lat, double h, const double v[3],
				      double alpha, double w_w[3])
{
	double wn[3], C[3][3];

	sscope_nav_transport_rate(lat, h, v, wn);
	wn[2] += sscope_nav_wander_rate(lat, h, v);
	sscope_nav_dcm_ned_to_wander(alpha, C);
	for (int i = 0; i < 3; i++)
		w_w[i] = C[i][0] * wn[0] + C[i][1] * wn[1] + C[i][2] * wn[2];
}
