/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Strapdown mechanisation in the local-level NED frame (see
 * sscope-strapdown.h): Savage's two-sample coning and sculling algorithms
 * (J. Guidance, Control and Dynamics 21(1-2), 1998) with the navigation
 * equations of Groves (2013, sec. 5.4-5.5): quaternion attitude with the
 * frame-rotation correction, the Coriolis theorem for velocity relative
 * to the rotating Earth, v' = C_b^n f - (2 omega_ie + omega_en) x v + g,
 * and trapezoidal position in latitude, longitude and height.
 */
#include "internal.h"

#include <math.h>
#include <string.h>

#include "sscope-nav.h"
#include "sscope-strapdown.h"


static void cross(const double a[3], const double b[3], double r[3])
{
	double x = a[1] * b[2] - a[2] * b[1];
	double y = a[2] * b[0] - a[0] * b[2];
	double z = a[0] * b[1] - a[1] * b[0];

	r[0] = x;
	r[1] = y;
	r[2] = z;
}

int sscope_strapdown_init(struct sscope_strapdown_state *s, double lat,
			  double lon, double h, const double v[3],
			  double roll, double pitch, double yaw)
{
	double C[3][3];

	if (!s || !v || !isfinite(lat) || !isfinite(lon) || !isfinite(h) ||
	    !isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]) ||
	    !isfinite(roll) || !isfinite(pitch) || !isfinite(yaw) ||
	    !(fabs(lat) < PI / 2))
		return -EINVAL;
	s->lat_rad = lat;
	s->lon_rad = lon;
	s->height_m = h;
	memcpy(s->v_ned_m_s, v, 3 * sizeof(double));
	sscope_nav_dcm_from_euler(roll, pitch, yaw, C);
	sscope_nav_quat_from_dcm(C, s->q_bn);
	return 0;
}

void sscope_strapdown_euler(const struct sscope_strapdown_state *s,
			    double *roll, double *pitch, double *yaw)
{
	double C[3][3];

	sscope_nav_dcm_from_quat(s->q_bn, C);
	sscope_nav_euler_from_dcm(C, roll, pitch, yaw);
}

/* The body side of a two-sample update (Savage's two-sample forms): the
 * rotation vector phi with its coning term, and the velocity increment dvb
 * in the body axes at the start, rotation compensated and with its
 * sculling term. */
static void body_two_sample(const double a1[3], const double a2[3],
			    const double v1[3], const double v2[3],
			    double phi[3], double dvb[3])
{
	double a[3], dv[3], c[3];

	for (int i = 0; i < 3; i++) {
		a[i] = a1[i] + a2[i];
		dv[i] = v1[i] + v2[i];
	}
	cross(a1, a2, c);
	for (int i = 0; i < 3; i++)
		phi[i] = a[i] + 2.0 / 3.0 * c[i];
	/* rotation compensation for the whole update, exact for a constant
	 * rate (Savage 1998, eq. 40): (1 - cos|a|)/|a|^2 a x dv +
	 * (1 - sin|a|/|a|)/|a|^2 a x (a x dv), i.e. 1/2 and 1/6 to second
	 * order */
	{
		double t2 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2], k1, k2, cc[3];

		if (t2 < 1e-6) {
			k1 = 0.5 - t2 / 24 + t2 * t2 / 720;
			k2 = 1.0 / 6 - t2 / 120 + t2 * t2 / 5040;
		} else {
			double t = sqrt(t2);

			k1 = (1 - cos(t)) / t2;
			k2 = (1 - sin(t) / t) / t2;
		}
		cross(a, dv, c);
		cross(a, c, cc);
		for (int i = 0; i < 3; i++)
			dvb[i] = dv[i] + k1 * c[i] + k2 * cc[i];
	}
	{
		double s1[3], s2[3];

		cross(a1, v2, s1);
		cross(v1, a2, s2);
		for (int i = 0; i < 3; i++)
			dvb[i] += 2.0 / 3.0 * (s1[i] + s2[i]);
	}
}

void sscope_strapdown_step2(struct sscope_strapdown_state *s,
			    const double a1[3], const double a2[3],
			    const double v1[3], const double v2[3], double dt)
{
	const double T = 2 * dt;
	double phi[3], dvb[3], C[3][3], fn[3];
	double lat = s->lat_rad, h = s->height_m, *v = s->v_ned_m_s;
	double lat_m = lat, h_m = h, vm[3] = { v[0], v[1], v[2] };
	double vn[3], latn = lat, lonn = s->lon_rad, hn = h, zeta[3];
	/* the Earth model at the old latitude, the mid point and the new
	 * latitude (each computed once) */
	struct sscope_nav_earth e0, em, en;

	/* body side: coning and sculling */
	body_two_sample(a1, a2, v1, v2, phi, dvb);
	sscope_nav_dcm_from_quat(s->q_bn, C);
	for (int i = 0; i < 3; i++)
		fn[i] = C[i][0] * dvb[0] + C[i][1] * dvb[1] + C[i][2] * dvb[2];
	sscope_nav_earth_at(lat, h, &e0);
	en = e0;
	/* navigation side: predictor (start values), then corrector (mid) */
	for (int pass = 0; pass < 2; pass++) {
		double wie[3], wen[3], w2[3], cor[3], zf[3], g;

		if (pass)
			sscope_nav_earth_at(lat_m, h_m, &em);
		else
			em = e0;
		sscope_nav_rates_at(&em, h_m, vm, wie, wen);
		g = em.gravity_m_s2;
		for (int i = 0; i < 3; i++) {
			zeta[i] = (wie[i] + wen[i]) * T;
			w2[i] = 2 * wie[i] + wen[i];
		}
		cross(w2, vm, cor);
		cross(zeta, fn, zf);
		for (int i = 0; i < 3; i++)
			vn[i] = v[i] + fn[i] - 0.5 * zf[i] - cor[i] * T;
		vn[2] += g * T;
		/* position: trapezoid, radii at the old and the new latitude
		 * (the new one from the previous estimate, then updated) */
		hn = h - 0.5 * T * (v[2] + vn[2]);
		latn = lat + 0.5 * T * (v[0] / (e0.r_n_m + h) + vn[0] / (en.r_n_m + hn));
		sscope_nav_earth_at(latn, hn, &en);
		lonn = s->lon_rad +
		       0.5 * T * (v[1] / ((e0.r_e_m + h) * e0.cos_lat) +
				  vn[1] / ((en.r_e_m + hn) * en.cos_lat));
		lat_m = 0.5 * (lat + latn);
		h_m = 0.5 * (h + hn);
		for (int i = 0; i < 3; i++)
			vm[i] = 0.5 * (v[i] + vn[i]);
	}
	/* attitude: q(k) = exp(-zeta) q(k-1) exp(phi) */
	{
		double qb[4], qn[4], t[4], mz[3] = { -zeta[0], -zeta[1], -zeta[2] };

		sscope_nav_quat_from_rotvec(phi, qb);
		sscope_nav_quat_from_rotvec(mz, qn);
		sscope_nav_quat_mul(s->q_bn, qb, t);
		sscope_nav_quat_mul(qn, t, s->q_bn);
		sscope_nav_quat_normalize(s->q_bn);
	}
	memcpy(v, vn, sizeof(vn));
	s->lat_rad = latn;
	s->lon_rad = remainder(lonn, 2 * PI);
	s->height_m = hn;
}

/* ------------------------------------------------------------ wander */

void sscope_strapdown_wander_position(const struct sscope_strapdown_wander *s,
				      double *lat, double *lon, double *alpha,
				      double C_we[3][3])
{
	double C[3][3];

	sscope_nav_dcm_from_quat(s->q_we, C);
	/* the down axis in ECEF is -(cos lat cos lon, cos lat sin lon,
	 * sin lat); the polar axis in w is (cos lat cos alpha,
	 * -cos lat sin alpha, -sin lat) */
	if (lat)
		*lat = atan2(-C[2][2], hypot(C[0][2], C[1][2]));
	if (lon)
		*lon = (C[0][2] == 0 && C[1][2] == 0) ? 0 : atan2(-C[1][2], -C[0][2]);
	if (alpha)
		*alpha = (C[2][0] == 0 && C[2][1] == 0) ? 0 : atan2(-C[2][1], C[2][0]);
	if (C_we)
		memcpy(C_we, C, sizeof(C));
}

int sscope_strapdown_wander_init(struct sscope_strapdown_wander *s, double lat,
				 double lon, double h, const double v[3],
				 double roll, double pitch, double yaw)
{
	double C[3][3], Cwe[3][3];

	if (!s || !v || !isfinite(lat) || !isfinite(lon) || !isfinite(h) ||
	    !isfinite(v[0]) || !isfinite(v[1]) || !isfinite(v[2]) ||
	    !isfinite(roll) || !isfinite(pitch) || !isfinite(yaw) ||
	    !(fabs(lat) <= PI / 2))
		return -EINVAL;
	sscope_nav_dcm_ecef_to_ned(lat, lon, C); /* alpha = 0: w = n */
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			Cwe[i][j] = C[j][i];
	sscope_nav_quat_from_dcm(Cwe, s->q_we);
	s->height_m = h;
	memcpy(s->v_w_m_s, v, 3 * sizeof(double));
	sscope_nav_dcm_from_euler(roll, pitch, yaw, C);
	sscope_nav_quat_from_dcm(C, s->q_bw);
	return 0;
}

void sscope_strapdown_wander_to_ned(const struct sscope_strapdown_wander *s,
				    struct sscope_strapdown_state *n)
{
	double alpha, ca, sa, rv[3], qa[4];

	sscope_strapdown_wander_position(s, &n->lat_rad, &n->lon_rad, &alpha, NULL);
	n->height_m = s->height_m;
	ca = cos(alpha);
	sa = sin(alpha);
	/* C_w^n: x_w is at azimuth alpha */
	n->v_ned_m_s[0] = ca * s->v_w_m_s[0] - sa * s->v_w_m_s[1];
	n->v_ned_m_s[1] = sa * s->v_w_m_s[0] + ca * s->v_w_m_s[1];
	n->v_ned_m_s[2] = s->v_w_m_s[2];
	rv[0] = rv[1] = 0;
	rv[2] = alpha;
	sscope_nav_quat_from_rotvec(rv, qa);
	sscope_nav_quat_mul(qa, s->q_bw, n->q_bn);
	sscope_nav_quat_normalize(n->q_bn);
}

/* the Earth at a wander position: Earth rate, gravity and the terms of
 * the transport rate */
struct wgeo {
	double wie[3], g, k_e, kappa, zx, zy;
};

static void wander_geo(const double C[3][3], double h, struct wgeo *w)
{
	const struct sscope_nav_wgs84 *m = sscope_nav_wgs84();
	double sl = -C[2][2], lat = atan2(sl, hypot(C[0][2], C[1][2]));
	double q = 1 - m->e2 * sl * sl, sq = sqrt(q);
	double rn = m->a * (1 - m->e2) / (q * sq), re = m->a / sq;

	for (int i = 0; i < 3; i++)
		w->wie[i] = SSCOPE_NAV_WGS84_OMEGA * C[2][i];
	w->k_e = 1 / (re + h);
	w->kappa = m->a * m->e2 / (q * sq * (rn + h) * (re + h));
	w->zx = C[2][0];
	w->zy = C[2][1];
	w->g = sscope_nav_gravity(lat, h);
}

/* transport rate (w_y, -w_x, 0), w = v_h / (R_E + h) + kappa z_h (z_h . v) */
static void wander_rho(const struct wgeo *w, const double v[3], double rho[3])
{
	double zv = w->zx * v[0] + w->zy * v[1];

	rho[0] = w->k_e * v[1] + w->kappa * w->zy * zv;
	rho[1] = -(w->k_e * v[0] + w->kappa * w->zx * zv);
	rho[2] = 0;
}

void sscope_strapdown_wander_step2(struct sscope_strapdown_wander *s,
				   const double a1[3], const double a2[3],
				   const double v1[3], const double v2[3], double dt,
				   const struct sscope_strapdown_platform *pe)
{
	const double T = 2 * dt;
	double phi[3], dvb[3], C[3][3], fn[3];
	double *v = s->v_w_m_s, h = s->height_m, h_m = h;
	double vm[3] = { v[0], v[1], v[2] }, vn[3], hn = h, zeta[3];
	double rho_m[3] = { 0, 0, 0 }, q_m[4], q_new[4];

	/* body side: coning and sculling */
	body_two_sample(a1, a2, v1, v2, phi, dvb);
	sscope_nav_dcm_from_quat(s->q_bw, C);
	for (int i = 0; i < 3; i++)
		fn[i] = C[i][0] * dvb[0] + C[i][1] * dvb[1] + C[i][2] * dvb[2];
	if (pe) {
		/* the platform's accelerometers read the increment in its axes */
		double e[3];

		for (int i = 0; i < 3; i++)
			e[i] = pe->accel_m[i][0] * fn[0] + pe->accel_m[i][1] * fn[1] +
			       pe->accel_m[i][2] * fn[2] + pe->dv_m_s[i];
		for (int i = 0; i < 3; i++)
			fn[i] += e[i];
	}
	memcpy(q_m, s->q_we, sizeof(q_m));
	/* predictor (start values), then corrector (mid-point values) */
	for (int pass = 0; pass < 2; pass++) {
		struct wgeo geo;
		double rho[3], w2[3], cor[3], zf[3], Cm[3][3], *wie = geo.wie;

		if (pass) {
			/* the mid-point position from the predictor's rate */
			double r[3], qr[4];

			for (int i = 0; i < 3; i++)
				r[i] = 0.5 * T * rho_m[i];
			sscope_nav_quat_from_rotvec(r, qr);
			sscope_nav_quat_mul(s->q_we, qr, q_m);
		}
		sscope_nav_dcm_from_quat(q_m, Cm);
		wander_geo(Cm, h_m, &geo);
		wander_rho(&geo, vm, rho);
		for (int i = 0; i < 3; i++) {
			zeta[i] = (wie[i] + rho[i]) * T;
			w2[i] = 2 * wie[i] + rho[i];
		}
		if (pe) {
			/* the platform drifts by its gyros' error on the rate
			 * it is torqued at */
			double z0[3] = { zeta[0], zeta[1], zeta[2] };

			for (int i = 0; i < 3; i++)
				zeta[i] -= pe->gyro_m[i][0] * z0[0] + pe->gyro_m[i][1] * z0[1] +
					   pe->gyro_m[i][2] * z0[2] + pe->dtheta_rad[i];
		}
		cross(w2, vm, cor);
		cross(zeta, fn, zf);
		for (int i = 0; i < 3; i++)
			vn[i] = v[i] + fn[i] - 0.5 * zf[i] - cor[i] * T;
		vn[2] += geo.g * T;
		hn = h - 0.5 * T * (v[2] + vn[2]);
		h_m = 0.5 * (h + hn);
		for (int i = 0; i < 3; i++)
			vm[i] = 0.5 * (v[i] + vn[i]);
		/* transport rate at the mid point for the position (the
		 * height's change over half an update is left out) */
		wander_rho(&geo, vm, rho_m);
	}
	{
		double r[3], qr[4];

		for (int i = 0; i < 3; i++)
			r[i] = rho_m[i] * T;
		sscope_nav_quat_from_rotvec(r, qr);
		sscope_nav_quat_mul(s->q_we, qr, q_new);
		sscope_nav_quat_normalize(q_new);
	}
	{
		double qb[4], qn[4], t[4], mz[3] = { -zeta[0], -zeta[1], -zeta[2] };

		sscope_nav_quat_from_rotvec(phi, qb);
		sscope_nav_quat_from_rotvec(mz, qn);
		sscope_nav_quat_mul(s->q_bw, qb, t);
		sscope_nav_quat_mul(qn, t, s->q_bw);
		sscope_nav_quat_normalize(s->q_bw);
	}
	memcpy(s->q_we, q_new, sizeof(q_new));
	memcpy(v, vn, sizeof(vn));
	s->height_m = hn;
}
