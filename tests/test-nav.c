/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Unit tests of analysis/nav.c: WGS 84's published constants and normal
 * gravity (equator, pole, the international gravity series at 45 deg, the
 * free-air gradient), geodetic <-> ECEF round trips over the whole globe
 * from -10 km to 1000 km, the poles, the centre and the evolute, frame
 * identities (orthonormal, determinant 1, axes where they belong), the
 * rotation conventions (Euler, DCM, quaternion, rotation vector; gravity
 * in the body as `inclino` reads it), Earth and transport rates and the
 * wander-azimuth frame.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "check-main.h"

#define PI 3.14159265358979323846
#define D2R (PI / 180)

static double det(const double C[3][3])
{
	return C[0][0] * (C[1][1] * C[2][2] - C[1][2] * C[2][1]) -
	       C[0][1] * (C[1][0] * C[2][2] - C[1][2] * C[2][0]) +
	       C[0][2] * (C[1][0] * C[2][1] - C[1][1] * C[2][0]);
}

/* max |C C^T - I| */
static double orth_err(const double C[3][3])
{
	double m = 0;

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) {
			double s = 0;

			for (int k = 0; k < 3; k++)
				s += C[i][k] * C[j][k];
			m = fmax(m, fabs(s - (i == j)));
		}
	return m;
}

static void check_rotation(const double C[3][3])
{
	ck_assert_msg(orth_err(C) < 1e-14, "not orthonormal: %g", orth_err(C));
	ck_assert_msg(fabs(det(C) - 1) < 1e-14, "det %.17g", det(C));
}

START_TEST(test_wgs84_constants)
{
	const struct sscope_nav_wgs84 *w = sscope_nav_wgs84();

	/* TR8350.2 table 3.1 / 3.3 derived values */
	ck_assert(fabs(w->b - 6356752.3142) < 1e-4);
	ck_assert(fabs(w->e2 - 6.69437999014e-3) < 1e-14);
	/* published 0.00193185265241; from the published (rounded)
	 * gamma_e and gamma_p it is 0.0019318526464 */
	ck_assert(fabs(w->k - 0.00193185265241) < 1e-11);
	ck_assert(fabs(w->m - 0.00344978650684) < 1e-13);
}
END_TEST

START_TEST(test_normal_gravity)
{
	double g45, grad;

	/* Somigliana reproduces the published equator and pole values */
	ck_assert_rel(sscope_nav_gravity(0, 0), 9.7803253359, 1e-15);
	ck_assert_rel(sscope_nav_gravity(PI / 2, 0), 9.8321849378, 1e-14);
	ck_assert_rel(sscope_nav_gravity(-PI / 2, 0), 9.8321849378, 1e-14);
	/* at 45 deg: Somigliana with the WGS 84 values evaluated in 30-digit
	 * arithmetic (mpmath) gives 9.80619776934; GRS80's published value
	 * (Moritz's series) is 9.806199203, the two ellipsoids' normal
	 * gravities differing by about 1.4e-6 m/s^2 */
	g45 = sscope_nav_gravity(45 * D2R, 0);
	ck_assert(fabs(g45 - 9.80619776934) < 1e-10);
	ck_assert(fabs(g45 - 9.806199203) < 2e-6);
	/* free-air gradient about -0.3086 mGal/m */
	grad = (sscope_nav_gravity(45 * D2R, 100) - sscope_nav_gravity(45 * D2R, -100)) / 200;
	ck_assert_msg(fabs(grad + 3.086e-6) < 2e-9, "gradient %g", grad);
	/* symmetric in latitude, increasing towards the poles */
	ck_assert_rel(sscope_nav_gravity(-30 * D2R, 50), sscope_nav_gravity(30 * D2R, 50),
		      1e-15);
	ck_assert(sscope_nav_gravity(60 * D2R, 0) > sscope_nav_gravity(30 * D2R, 0));
}
END_TEST

START_TEST(test_geodetic_round_trip)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double worst[3] = { 0, 0, 0 };

	gsl_rng_set(r, 19001);
	for (int i = 0; i < 200000; i++) {
		struct sscope_nav_geodetic g, o;
		double x[3], rn, re;

		g.lat_rad = asin(gsl_ran_flat(r, -1, 1));
		/* a share exactly at the poles and the equator */
		if (i % 50 == 0)
			g.lat_rad = (i / 50) % 3 == 0 ? PI / 2 :
				    (i / 50) % 3 == 1 ? -PI / 2 : 0;
		g.lon_rad = gsl_ran_flat(r, -PI, PI);
		g.height_m = gsl_ran_flat(r, -10e3, 1000e3);
		ck_assert_int_eq(sscope_nav_geodetic_to_ecef(&g, x), 0);
		ck_assert_int_eq(sscope_nav_ecef_to_geodetic(x, &o), 0);
		sscope_nav_radii(g.lat_rad, &rn, &re);
		worst[0] = fmax(worst[0], fabs(o.lat_rad - g.lat_rad) * (rn + g.height_m));
		if (fabs(g.lat_rad) < PI / 2)
			worst[1] = fmax(worst[1], fabs(remainder(o.lon_rad - g.lon_rad, 2 * PI)) *
							  (re + g.height_m) * cos(g.lat_rad));
		worst[2] = fmax(worst[2], fabs(o.height_m - g.height_m));
	}
	gsl_rng_free(r);
	/* "well below a millimetre": a few ulps of the ECEF coordinates */
	ck_assert_msg(worst[0] < 1e-7 && worst[1] < 1e-7 && worst[2] < 1e-7,
		      "round trip errors %g %g %g m", worst[0], worst[1], worst[2]);
}
END_TEST

START_TEST(test_ecef_anywhere)
{
	/* ECEF -> geodetic -> ECEF for points anywhere (inside the Earth,
	 * near the centre, in the evolute, far away) gives the point back:
	 * the result is a true foot point on the ellipsoid normal */
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	gsl_rng_set(r, 19002);
	for (int i = 0; i < 100000; i++) {
		double x[3], y[3], rad, d;
		struct sscope_nav_geodetic g;

		rad = i % 4 == 0 ? gsl_ran_flat(r, 0, 60e3) :
				   gsl_ran_flat(r, 0, 2e7);
		for (int k = 0; k < 3; k++)
			x[k] = gsl_ran_gaussian(r, 1);
		d = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
		for (int k = 0; k < 3; k++)
			x[k] *= rad / d;
		if (i % 7 == 0)
			x[2] = 0; /* equatorial plane, evolute included */
		ck_assert_int_eq(sscope_nav_ecef_to_geodetic(x, &g), 0);
		ck_assert(fabs(g.lat_rad) <= PI / 2);
		sscope_nav_geodetic_to_ecef(&g, y);
		for (int k = 0; k < 3; k++)
			ck_assert_msg(fabs(y[k] - x[k]) <
					      1e-8 + 4e-15 * (rad + fabs(g.height_m)),
				      "point %d axis %d: %.17g vs %.17g (r %g)", i, k,
				      y[k], x[k], rad);
	}
	gsl_rng_free(r);
}
END_TEST

START_TEST(test_poles_centre)
{
	const struct sscope_nav_wgs84 *w = sscope_nav_wgs84();
	struct sscope_nav_geodetic g;
	double x[3] = { 0, 0, 0 };

	ck_assert_int_eq(sscope_nav_ecef_to_geodetic(x, &g), 0);
	ck_assert(g.lat_rad == PI / 2 && g.lon_rad == 0);
	ck_assert_rel(g.height_m, -w->b, 1e-15);
	x[2] = w->b + 1234.5;
	sscope_nav_ecef_to_geodetic(x, &g);
	ck_assert(g.lat_rad == PI / 2);
	ck_assert(fabs(g.height_m - 1234.5) < 1e-9);
	x[2] = -(w->b - 4321.25);
	sscope_nav_ecef_to_geodetic(x, &g);
	ck_assert(g.lat_rad == -PI / 2);
	ck_assert(fabs(g.height_m + 4321.25) < 1e-9);
	/* the equator */
	x[0] = 0;
	x[1] = -(w->a + 250);
	x[2] = 0;
	sscope_nav_ecef_to_geodetic(x, &g);
	ck_assert(g.lat_rad == 0);
	ck_assert_rel(g.lon_rad, -PI / 2, 1e-15);
	ck_assert(fabs(g.height_m - 250) < 1e-9);
	/* inside the evolute on the equator: foot points off the plane */
	x[0] = 10e3;
	x[1] = 0;
	sscope_nav_ecef_to_geodetic(x, &g);
	ck_assert(g.lat_rad > 0 && g.height_m < -6e6);
	/* bad input */
	x[0] = NAN;
	ck_assert_int_eq(sscope_nav_ecef_to_geodetic(x, &g), -EINVAL);
	g.lat_rad = 1.6;
	g.lon_rad = 0;
	g.height_m = 0;
	ck_assert_int_eq(sscope_nav_geodetic_to_ecef(&g, x), -EINVAL);
	ck_assert_int_eq(sscope_nav_geodetic_to_ecef(NULL, x), -EINVAL);
	ck_assert(isnan(sscope_nav_geocentric_latitude(&g)));
}
END_TEST

START_TEST(test_geocentric)
{
	struct sscope_nav_geodetic g = { 45 * D2R, 10 * D2R, 0 };
	const struct sscope_nav_wgs84 *w = sscope_nav_wgs84();
	double psi = sscope_nav_geocentric_latitude(&g), C[3][3], x[3];

	/* on the ellipsoid tan(psi) = (1 - e^2) tan(lat); about 0.192 deg
	 * less than the geodetic latitude at 45 deg */
	ck_assert_rel(tan(psi), (1 - w->e2) * tan(g.lat_rad), 1e-14);
	ck_assert(fabs((g.lat_rad - psi) / D2R - 0.1924) < 1e-3);
	sscope_nav_geodetic_to_ecef(&g, x);
	ck_assert_int_eq(sscope_nav_dcm_ecef_to_geocentric(x, C), 0);
	check_rotation(C);
	/* its down axis points at the centre */
	for (int k = 0; k < 3; k++)
		ck_assert(fabs(C[2][k] + x[k] / sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2])) <
			  1e-15);
	x[0] = x[1] = 0;
	ck_assert_int_eq(sscope_nav_dcm_ecef_to_geocentric(x, C), -EDOM);
}
END_TEST

START_TEST(test_frames)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	gsl_rng_set(r, 19003);
	for (int i = 0; i < 2000; i++) {
		double lat = gsl_ran_flat(r, -PI / 2, PI / 2);
		double lon = gsl_ran_flat(r, -PI, PI), alpha = gsl_ran_flat(r, -PI, PI);
		double h = gsl_ran_flat(r, -1e3, 1e5);
		double N[3][3], E[3][3], W[3][3], Wn[3][3], x0[3], x1[3];
		struct sscope_nav_geodetic g = { lat, lon, h };

		sscope_nav_dcm_ecef_to_ned(lat, lon, N);
		sscope_nav_dcm_ecef_to_enu(lat, lon, E);
		sscope_nav_dcm_ecef_to_wander(lat, lon, alpha, W);
		sscope_nav_dcm_ned_to_wander(alpha, Wn);
		check_rotation(N);
		check_rotation(E);
		check_rotation(W);
		check_rotation(Wn);
		/* down is the ellipsoid normal: a height step moves along it */
		sscope_nav_geodetic_to_ecef(&g, x0);
		g.height_m += 1;
		sscope_nav_geodetic_to_ecef(&g, x1);
		for (int k = 0; k < 3; k++) {
			ck_assert(fabs(-(x1[k] - x0[k]) - N[2][k]) < 1e-8);
			/* ENU = (E, N, -D) */
			ck_assert(E[0][k] == N[1][k] && E[1][k] == N[0][k] &&
				  E[2][k] == -N[2][k]);
			/* wander: still level, x at alpha from north */
			ck_assert(fabs(W[2][k] - N[2][k]) < 1e-15);
			ck_assert(fabs(W[0][k] - (cos(alpha) * N[0][k] +
						  sin(alpha) * N[1][k])) < 1e-15);
		}
		/* north points to increasing latitude */
		g.height_m -= 1;
		g.lat_rad = fmin(lat + 1e-7, PI / 2);
		if (fabs(lat) < 1.5) {
			double d[3], n;

			sscope_nav_geodetic_to_ecef(&g, x1);
			for (int k = 0; k < 3; k++)
				d[k] = x1[k] - x0[k];
			n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
			for (int k = 0; k < 3; k++)
				ck_assert(fabs(d[k] / n - N[0][k]) < 1e-6);
		}
	}
	gsl_rng_free(r);
	{
		/* one sidereal day turns ECI back onto ECEF */
		double C[3][3];

		sscope_nav_dcm_eci_to_ecef(2 * PI / SSCOPE_NAV_WGS84_OMEGA, C);
		check_rotation(C);
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				ck_assert(fabs(C[i][j] - (i == j)) < 1e-12);
		sscope_nav_dcm_eci_to_ecef(3600, C);
		ck_assert_rel(atan2(C[0][1], C[0][0]), SSCOPE_NAV_WGS84_OMEGA * 3600, 1e-14);
	}
}
END_TEST

START_TEST(test_tangent_plane)
{
	struct sscope_nav_ltp t;
	struct sscope_nav_geodetic o = { 48.1 * D2R, 11.6 * D2R, 520 }, g;
	double ned[3] = { 1234.5, -987.25, -42.125 }, x[3], back[3], up[3];

	ck_assert_int_eq(sscope_nav_ltp_init(&t, &o), 0);
	sscope_nav_ltp_to_ecef(&t, ned, x);
	sscope_nav_ltp_from_ecef(&t, x, back);
	for (int k = 0; k < 3; k++)
		ck_assert(fabs(back[k] - ned[k]) < 1e-9);
	/* the origin maps to zero; a point 1 km above it is at down -1000 */
	g = o;
	g.height_m += 1000;
	sscope_nav_geodetic_to_ecef(&g, x);
	sscope_nav_ltp_from_ecef(&t, x, back);
	ck_assert(fabs(back[0]) < 1e-8 && fabs(back[1]) < 1e-8 &&
		  fabs(back[2] + 1000) < 1e-8);
	/* 10 km north along the plane drops below it by about d^2 / 2R */
	ned[0] = 10e3;
	ned[1] = ned[2] = 0;
	sscope_nav_ltp_to_ecef(&t, ned, x);
	sscope_nav_ecef_to_geodetic(x, &g);
	ck_assert(g.height_m - o.height_m > 7.5 && g.height_m - o.height_m < 8.2);
	sscope_nav_ned_enu(back, up);
	ck_assert(up[0] == back[1] && up[1] == back[0] && up[2] == -back[2]);
	ck_assert_int_eq(sscope_nav_ltp_init(&t, NULL), -EINVAL);
}
END_TEST

START_TEST(test_rotations)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	gsl_rng_set(r, 19004);
	for (int i = 0; i < 5000; i++) {
		double e[3] = { gsl_ran_flat(r, -PI, PI), gsl_ran_flat(r, -1.5, 1.5),
				gsl_ran_flat(r, -PI, PI) };
		double C[3][3], C2[3][3], q[4], o[3], v[3], q2[4];

		sscope_nav_dcm_from_euler(e[0], e[1], e[2], C);
		check_rotation(C);
		sscope_nav_euler_from_dcm(C, &o[0], &o[1], &o[2]);
		for (int k = 0; k < 3; k++)
			ck_assert(fabs(remainder(o[k] - e[k], 2 * PI)) < 1e-12);
		sscope_nav_quat_from_dcm(C, q);
		ck_assert(q[0] >= 0);
		sscope_nav_dcm_from_quat(q, C2);
		for (int a = 0; a < 3; a++)
			for (int b = 0; b < 3; b++)
				ck_assert(fabs(C2[a][b] - C[a][b]) < 1e-14);
		sscope_nav_rotvec_from_quat(q, v);
		sscope_nav_quat_from_rotvec(v, q2);
		for (int k = 0; k < 4; k++)
			ck_assert(fabs(q2[k] - q[k]) < 1e-14);
		/* gravity in the body, as `inclino` reads it */
		{
			double g = 9.80665, a[3], roll, pitch;

			for (int k = 0; k < 3; k++)
				a[k] = C[2][k] * g; /* C_n^b (0, 0, g) */
			ck_assert(fabs(a[0] + g * sin(e[1])) < 1e-13);
			ck_assert(fabs(a[1] - g * sin(e[0]) * cos(e[1])) < 1e-13);
			ck_assert(fabs(a[2] - g * cos(e[0]) * cos(e[1])) < 1e-13);
			ck_assert_int_eq(sscope_inclino_tilt(SSCOPE_INCLINO_3AXIS, a, g,
							     &roll, &pitch, NULL),
					 0);
			ck_assert(fabs(remainder(roll - e[0], 2 * PI)) < 1e-12);
			ck_assert(fabs(pitch - e[1]) < 1e-12);
		}
	}
	gsl_rng_free(r);
	{
		/* Z-Y-X order: yaw 90 then roll 90 takes body y onto down */
		double C[3][3], q1[4], q2[4], q[4], Cq[3][3], v[3];

		sscope_nav_dcm_from_euler(PI / 2, 0, PI / 2, C);
		ck_assert(fabs(C[2][1] - 1) < 1e-15);
		/* composition: q(yaw) q(roll) is the same rotation */
		v[0] = v[1] = 0;
		v[2] = PI / 2;
		sscope_nav_quat_from_rotvec(v, q1);
		v[2] = 0;
		v[0] = PI / 2;
		sscope_nav_quat_from_rotvec(v, q2);
		sscope_nav_quat_mul(q1, q2, q);
		sscope_nav_dcm_from_quat(q, Cq);
		for (int a = 0; a < 3; a++)
			for (int b = 0; b < 3; b++)
				ck_assert(fabs(Cq[a][b] - C[a][b]) < 1e-15);
		/* small and near-pi rotation vectors */
		v[0] = 1e-12;
		v[1] = -2e-12;
		v[2] = 3e-13;
		sscope_nav_quat_from_rotvec(v, q);
		sscope_nav_rotvec_from_quat(q, q1);
		for (int k = 0; k < 3; k++)
			ck_assert_rel(q1[k], v[k], 1e-14);
		v[0] = PI - 1e-9;
		v[1] = v[2] = 0;
		sscope_nav_quat_from_rotvec(v, q);
		sscope_nav_rotvec_from_quat(q, q1);
		ck_assert_rel(q1[0], v[0], 1e-14);
		/* gimbal lock: yaw - roll kept */
		sscope_nav_dcm_from_euler(0.3, PI / 2, 0.5, C);
		sscope_nav_euler_from_dcm(C, &v[0], &v[1], &v[2]);
		ck_assert(v[0] == 0 && fabs(v[1] - PI / 2) < 1e-7);
		ck_assert(fabs(v[2] - (0.5 - 0.3)) < 1e-7);
	}
}
END_TEST

START_TEST(test_earth_rates)
{
	double w[3], t[3], ww[3], rn, re;
	double v[3] = { 12.5, -7.25, 0.5 }, lat = 52 * D2R, h = 300;
	const struct sscope_nav_wgs84 *g = sscope_nav_wgs84();

	sscope_nav_earth_rate(lat, w);
	ck_assert_rel(sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]),
		      SSCOPE_NAV_WGS84_OMEGA, 1e-15);
	ck_assert(w[1] == 0 && w[2] < 0);
	/* the Earth rate is the ECEF z axis seen in NED */
	{
		double C[3][3];

		sscope_nav_dcm_ecef_to_ned(lat, 0.7, C);
		for (int k = 0; k < 3; k++)
			ck_assert(fabs(C[k][2] * SSCOPE_NAV_WGS84_OMEGA - w[k]) < 1e-19);
	}
	/* radii */
	sscope_nav_radii(0, &rn, &re);
	ck_assert_rel(re, g->a, 1e-15);
	ck_assert_rel(rn, g->a * (1 - g->e2), 1e-15);
	sscope_nav_radii(PI / 2, &rn, &re);
	ck_assert_rel(rn, re, 1e-15);
	ck_assert_rel(re, g->a * g->a / g->b, 1e-15);
	/* transport rate: rates of latitude and longitude */
	sscope_nav_radii(lat, &rn, &re);
	sscope_nav_transport_rate(lat, h, v, t);
	ck_assert_rel(-t[1], v[0] / (rn + h), 1e-15);
	ck_assert_rel(t[0], v[1] / (re + h), 1e-15);
	ck_assert_rel(t[2], -t[0] * tan(lat), 1e-15);
	/* wander azimuth: no rotation about the vertical relative to Earth */
	sscope_nav_transport_rate_wander(lat, h, v, 0.4, ww);
	ck_assert(fabs(ww[2]) < 1e-20);
	ck_assert_rel(hypot(ww[0], ww[1]), hypot(t[0], t[1]), 1e-14);
	ck_assert_rel(sscope_nav_wander_rate(lat, h, v),
		      v[1] / ((re + h) * cos(lat)) * sin(lat), 1e-14);
	/* the Earth model at one point equals the single functions */
	for (double la = -89.5; la <= 89.5; la += 7.25) {
		struct sscope_nav_earth e;
		double wi[3], wn[3], w1[3], w2[3];

		sscope_nav_earth_at(la * D2R, h, &e);
		sscope_nav_radii(la * D2R, &rn, &re);
		ck_assert_rel(e.r_n_m, rn, 1e-15);
		ck_assert_rel(e.r_e_m, re, 1e-15);
		ck_assert_rel(e.gravity_m_s2, sscope_nav_gravity(la * D2R, h), 1e-15);
		sscope_nav_rates_at(&e, h, v, wi, wn);
		sscope_nav_earth_rate(la * D2R, w1);
		sscope_nav_transport_rate(la * D2R, h, v, w2);
		for (int k = 0; k < 3; k++) {
			ck_assert(wi[k] == w1[k]);
			ck_assert(fabs(wn[k] - w2[k]) <= 1e-15 * fabs(w2[k]));
		}
		/* against the closed forms with tan */
		ck_assert_rel(wn[2], -v[1] * tan(la * D2R) / (re + h), 1e-14);
	}
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("nav");
	TCase *tc = tcase_create("core");

	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, test_wgs84_constants);
	tcase_add_test(tc, test_normal_gravity);
	tcase_add_test(tc, test_geodetic_round_trip);
	tcase_add_test(tc, test_ecef_anywhere);
	tcase_add_test(tc, test_poles_centre);
	tcase_add_test(tc, test_geocentric);
	tcase_add_test(tc, test_frames);
	tcase_add_test(tc, test_tangent_plane);
	tcase_add_test(tc, test_rotations);
	tcase_add_test(tc, test_earth_rates);
	suite_add_tcase(s, tc);
	return s;
}
