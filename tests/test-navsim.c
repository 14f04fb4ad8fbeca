/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Unit tests of analysis/strapdown.c and analysis/navsim.c:
 * - a perfect IMU at rest for 1 h at 45 deg (free vertical channel): the
 *   mechanisation, the gravity model and the Earth rate agree (< 1 mm,
 *   < 1e-9 rad); moving along a straight line and a turn, the
 *   mechanisation's closed forms (radii, transport rate, Coriolis) agree
 *   with the reference computed through ECEF;
 * - classical coning and an oscillating roll (sculling) with increments
 *   by fine quadrature: the two-sample corrections keep attitude and
 *   velocity where the uncorrected update drifts;
 * - a north accelerometer bias: Schuler period 2 pi sqrt(R/g) and
 *   amplitude b R / g within 1 %;
 * - a 10 deg/h gyro bias: 137 m after 120 s within 2 % (g b t^3 / 6) and
 *   the Schuler-bounded growth over 4 h, not t^3;
 * - small biases on every gyro and two accelerometers over 4 h: the
 *   errors equal the linearised error model of a stationary
 *   local-level system (Earth-rate coupling, Coriolis, Schuler loop),
 *   integrated here independently by an ODE solver;
 * - angle random walk: the Monte-Carlo spread of the attitude errors
 *   against N sqrt(t) (chi-squared bounds on the variance), percentiles
 *   against the normal quantiles;
 * - a converter: at rest its rounding acts as the fixed biases it makes;
 *   its noise and quantization add to the angle random walk as the
 *   budget (sscope_adc_analyze()) says;
 * - determinism across thread counts, trajectory tables, refused input;
 * - gimballed platform: a gyro bias gives the strapdown system's error
 *   (level, north-pointing body), a gyro scale-factor error acts on the
 *   platform's torquing rate only (closed forms while turning in place);
 * - wander azimuth: a perfect IMU at rest at 89.999 deg and at the poles,
 *   and over the pole at 250 m/s for 2 h; a horizontal gyro bias gives
 *   the same error across the pole as across the equator.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include "check-main.h"

#define PI 3.14159265358979323846
#define D2R (PI / 180)
#define G0 9.80665

static struct sscope_navsim *make(struct sscope_navsim_opts *o)
{
	struct sscope_navsim *ns = NULL;
	struct sscope_diag d = { "" };
	int rc = sscope_navsim_new(&ns, o, &d);

	ck_assert_msg(rc == 0, "navsim_new: %d %s", rc, d.msg);
	return ns;
}

/* max |error| of components [c0, c1) over a run */
static double worst(const double *e, size_t n, int c0, int c1)
{
	double m = 0;

	for (size_t k = 0; k < n; k++)
		for (int c = c0; c < c1; c++)
			m = fmax(m, fabs(e[k * SSCOPE_NAVSIM_N_COMP + c]));
	return m;
}

static double *run1(struct sscope_navsim *ns, const struct sscope_navsim_imu *imu)
{
	size_t n = sscope_navsim_n_out(ns);
	double *e = calloc(n * SSCOPE_NAVSIM_N_COMP, sizeof(double));
	struct sscope_diag d = { "" };

	ck_assert_ptr_nonnull(e);
	ck_assert_msg(sscope_navsim_run(ns, imu, 1, 0, e, NULL, &d) == 0, "%s", d.msg);
	return e;
}

START_TEST(test_perfect_static)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim *ns;
	double *e;
	size_t n;

	o.rate_hz = 100;
	o.duration_s = 3600;
	o.start.lat_rad = 45 * D2R;
	o.start.lon_rad = 7 * D2R;
	o.start.height_m = 250;
	o.roll_rad = 2 * D2R;
	o.pitch_rad = -3 * D2R;
	o.yaw_rad = 120 * D2R;
	o.free_vertical = true;
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	ck_assert_int_eq(sscope_navsim_n_samples(ns), 360000);
	ck_assert(fabs(sscope_navsim_time(ns, n - 1) - 3600) < 1e-9);
	e = run1(ns, &imu);
	ck_assert_msg(worst(e, n, 0, 3) < 1e-3, "position error %g m", worst(e, n, 0, 3));
	ck_assert_msg(worst(e, n, 6, 9) < 1e-9, "attitude error %g rad", worst(e, n, 6, 9));
	free(e);
	sscope_navsim_free(ns);
}
END_TEST

START_TEST(test_perfect_moving)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim *ns;
	struct sscope_navsim_pose p0, p1;
	double *e;
	size_t n;

	/* a straight line at 25 m/s, heading 30 deg, 10 min */
	o.rate_hz = 100;
	o.duration_s = 600;
	o.start.lat_rad = 45 * D2R;
	o.start.height_m = 100;
	o.yaw_rad = 30 * D2R;
	o.motion = SSCOPE_NAVSIM_STRAIGHT;
	o.speed_m_s = 25;
	o.free_vertical = true;
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	sscope_navsim_truth(ns, 0, &p0);
	sscope_navsim_truth(ns, n - 1, &p1);
	/* 15 km along the great circle, height within a metre */
	ck_assert(fabs(p1.pos.height_m - 100) < 1);
	ck_assert(fabs(hypot(p1.v_ned_m_s[0], p1.v_ned_m_s[1]) - 25) < 1e-6);
	e = run1(ns, &imu);
	ck_assert_msg(worst(e, n, 0, 3) < 1e-4, "straight: position %g m", worst(e, n, 0, 3));
	ck_assert_msg(worst(e, n, 3, 6) < 1e-6, "straight: velocity %g m/s", worst(e, n, 3, 6));
	ck_assert_msg(worst(e, n, 6, 9) < 1e-9, "straight: attitude %g rad", worst(e, n, 6, 9));
	free(e);
	sscope_navsim_free(ns);
	/* a turn at 10 deg/s and 10 m/s (radius 57 m) */
	o.motion = SSCOPE_NAVSIM_TURN;
	o.speed_m_s = 10;
	o.turn_rate_rad_s = 10 * D2R;
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	e = run1(ns, &imu);
	ck_assert_msg(worst(e, n, 0, 3) < 1e-3, "turn: position %g m", worst(e, n, 0, 3));
	ck_assert_msg(worst(e, n, 6, 9) < 1e-9, "turn: attitude %g rad", worst(e, n, 6, 9));
	free(e);
	sscope_navsim_free(ns);
}
END_TEST

/* A motion at a fixed point (latitude 45 deg) plus a small translation:
 * attitude q_b^n, body rate relative to NED, velocity and acceleration
 * (NED) of the translation. */
typedef void (*motion_fn)(double t, double q[4], double w_nb[3], double v[3],
			  double a[3]);

/* body rate and specific force (Coriolis included; the transport rate of
 * millimetre motions is below 1e-9 rad/s and left out) */
static void sense(motion_fn m, double lat, double t, double w[3], double f[3])
{
	double q[4], C[3][3], wie[3], wnb[3], v[3], a[3], fn[3];
	double g = sscope_nav_gravity(lat, 0);

	m(t, q, wnb, v, a);
	sscope_nav_dcm_from_quat(q, C);
	sscope_nav_earth_rate(lat, wie);
	fn[0] = a[0] + 2 * (wie[1] * v[2] - wie[2] * v[1]);
	fn[1] = a[1] + 2 * (wie[2] * v[0] - wie[0] * v[2]);
	fn[2] = a[2] + 2 * (wie[0] * v[1] - wie[1] * v[0]) - g;
	for (int i = 0; i < 3; i++) {
		w[i] = wnb[i] + C[0][i] * wie[0] + C[1][i] * wie[1] + C[2][i] * wie[2];
		f[i] = C[0][i] * fn[0] + C[1][i] * fn[1] + C[2][i] * fn[2];
	}
}

/* Gauss-Legendre increments over [t, t + h] in 16 sub-intervals */
static void increments(motion_fn m, double lat, double t, double h, double a[3],
		       double v[3])
{
	const double gx[3] = { -sqrt(0.6), 0, sqrt(0.6) }, gw[3] = { 5.0 / 9, 8.0 / 9, 5.0 / 9 };
	const int sub = 16;

	memset(a, 0, 3 * sizeof(double));
	memset(v, 0, 3 * sizeof(double));
	for (int s = 0; s < sub; s++)
		for (int q = 0; q < 3; q++) {
			double w[3], f[3], hs = h / sub;

			sense(m, lat, t + hs * (s + 0.5 * (1 + gx[q])), w, f);
			for (int i = 0; i < 3; i++) {
				a[i] += 0.5 * hs * gw[q] * w[i];
				v[i] += 0.5 * hs * gw[q] * f[i];
			}
		}
}

/* classical coning: half-angle 1 deg at 2 Hz */
static void coning(double t, double q[4], double w[3], double v[3], double a[3])
{
	double al = 1 * D2R, W = 2 * PI * 2, c = cos(al / 2), s = sin(al / 2);

	q[0] = c;
	q[1] = 0;
	q[2] = s * cos(W * t);
	q[3] = s * sin(W * t);
	w[0] = -2 * s * s * W;
	w[1] = -sin(al) * W * sin(W * t);
	w[2] = sin(al) * W * cos(W * t);
	memset(v, 0, 3 * sizeof(double));
	memset(a, 0, 3 * sizeof(double));
}

/* classical sculling: roll rate about x in phase with an east (body y)
 * acceleration, 1 deg and 2 m/s^2 at 5 Hz */
static void sculling(double t, double q[4], double w[3], double v[3], double a[3])
{
	double th = 1 * D2R, A = 2, W = 2 * PI * 5, r = th * sin(W * t);

	q[0] = cos(r / 2);
	q[1] = sin(r / 2);
	q[2] = q[3] = 0;
	w[0] = th * W * cos(W * t);
	w[1] = w[2] = 0;
	v[0] = v[2] = 0;
	v[1] = A / W * sin(W * t);
	a[0] = a[2] = 0;
	a[1] = A * cos(W * t);
}

/* attitude and velocity error after `secs` at `fs` Hz, with or without
 * the two-sample corrections (without: both halves get the mean
 * increments, so the cross products vanish) */
static void fly(motion_fn m, double fs, double secs, bool corrected,
		double *att_err, double *vel_err)
{
	const double lat = 45 * D2R, dt = 1 / fs;
	struct sscope_strapdown_state s;
	double q0[4], w[3], C[3][3], e[3], v0[3], a0[3];
	size_t n = (size_t)lround(secs * fs / 2);

	m(0, q0, w, v0, a0);
	sscope_nav_dcm_from_quat(q0, C);
	sscope_nav_euler_from_dcm(C, &e[0], &e[1], &e[2]);
	ck_assert_int_eq(sscope_strapdown_init(&s, lat, 0, 0, v0, e[0], e[1], e[2]), 0);
	for (size_t k = 0; k < n; k++) {
		double a1[3], a2[3], v1[3], v2[3], t = 2 * (double)k * dt;

		increments(m, lat, t, dt, a1, v1);
		increments(m, lat, t + dt, dt, a2, v2);
		if (!corrected)
			for (int i = 0; i < 3; i++) {
				a1[i] = a2[i] = 0.5 * (a1[i] + a2[i]);
				v1[i] = v2[i] = 0.5 * (v1[i] + v2[i]);
			}
		sscope_strapdown_step2(&s, a1, a2, v1, v2, dt);
	}
	{
		double qt[4], qc[4], d[4], rv[3], vt[3], at[3];

		m(2 * (double)n * dt, qt, w, vt, at);
		qc[0] = qt[0];
		for (int i = 1; i < 4; i++)
			qc[i] = -qt[i];
		sscope_nav_quat_mul(qc, s.q_bn, d);
		sscope_nav_rotvec_from_quat(d, rv);
		*att_err = sqrt(rv[0] * rv[0] + rv[1] * rv[1] + rv[2] * rv[2]);
		*vel_err = sqrt((s.v_ned_m_s[0] - vt[0]) * (s.v_ned_m_s[0] - vt[0]) +
				(s.v_ned_m_s[1] - vt[1]) * (s.v_ned_m_s[1] - vt[1]) +
				(s.v_ned_m_s[2] - vt[2]) * (s.v_ned_m_s[2] - vt[2]));
	}
}

START_TEST(test_coning_sculling)
{
	double a_c, v_c, a_u, v_u;

	/* the coning body rate is 2 conj(q) q' (central differences) */
	{
		double q[4], w[3], qp[4], qm[4], qd[4], cq[4], r[4], z[3], h = 1e-6;

		coning(0.123, q, w, z, z);
		coning(0.123 + h, qp, r, z, z);
		coning(0.123 - h, qm, r, z, z);
		for (int i = 0; i < 4; i++)
			qd[i] = (qp[i] - qm[i]) / (2 * h);
		cq[0] = q[0];
		for (int i = 1; i < 4; i++)
			cq[i] = -q[i];
		sscope_nav_quat_mul(cq, qd, r);
		for (int i = 0; i < 3; i++)
			ck_assert(fabs(2 * r[i + 1] - w[i]) < 1e-7);
	}
	fly(coning, 100, 60, true, &a_c, &v_c);
	fly(coning, 100, 60, false, &a_u, &v_u);
	ck_assert_msg(a_c < 1e-6 && a_u > 100 * a_c,
		      "coning: attitude error %g rad corrected, %g uncorrected", a_c, a_u);
	fly(sculling, 100, 60, true, &a_c, &v_c);
	fly(sculling, 100, 60, false, &a_u, &v_u);
	ck_assert_msg(v_c < 1e-3 && v_u > 30 * v_c,
		      "sculling: velocity error %g m/s corrected, %g uncorrected", v_c, v_u);
	ck_assert(a_c < 1e-8);
}
END_TEST

START_TEST(test_schuler_accel_bias)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim *ns;
	double *e, rn, g, b = 1e-3 * G0, Ts, best = 0, t_best = 0;
	size_t n;

	o.rate_hz = 20;
	o.start.lat_rad = 45 * D2R;
	sscope_nav_radii(o.start.lat_rad, &rn, NULL);
	g = sscope_nav_gravity(o.start.lat_rad, 0);
	Ts = 2 * PI * sqrt(rn / g);
	ck_assert(fabs(Ts / 60 - 84.4) < 0.1);
	o.duration_s = Ts;
	o.output_step_s = 1;
	imu.accel_bias_m_s2[0] = b; /* north (yaw 0) */
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	e = run1(ns, &imu);
	for (size_t k = 0; k < n; k++) {
		double h = hypot(e[k * SSCOPE_NAVSIM_N_COMP], e[k * SSCOPE_NAVSIM_N_COMP + 1]);

		if (h > best) {
			best = h;
			t_best = sscope_navsim_time(ns, k);
		}
	}
	/* (b R / g)(1 - cos(w t)) (turned slowly by the Earth rate, so the
	 * horizontal magnitude): peak 2 b R / g at half the period */
	ck_assert_msg(fabs(best / 2 / (b * rn / g) - 1) < 0.01,
		      "amplitude %g m, b R / g = %g m", best / 2, b * rn / g);
	ck_assert_msg(fabs(2 * t_best / Ts - 1) < 0.01, "period %g s, expected %g s",
		      2 * t_best, Ts);
	/* the down error is held at zero by the aided vertical channel */
	ck_assert(worst(e, n, 2, 3) == 0);
	free(e);
	sscope_navsim_free(ns);
}
END_TEST

START_TEST(test_gyro_bias)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_budget_params bp;
	struct sscope_budget_point sch, t3;
	struct sscope_navsim *ns;
	double *e, bg = 10 * D2R / 3600, h120 = -1, h4;
	size_t n;

	o.rate_hz = 20;
	o.start.lat_rad = 45 * D2R;
	o.duration_s = 4 * 3600;
	o.output_step_s = 10;
	imu.gyro_bias_rad_s[1] = bg; /* east axis: pitch, north error */
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	e = run1(ns, &imu);
	for (size_t k = 0; k < n; k++)
		if (fabs(sscope_navsim_time(ns, k) - 120) < 1e-9)
			h120 = hypot(e[k * SSCOPE_NAVSIM_N_COMP], e[k * SSCOPE_NAVSIM_N_COMP + 1]);
	/* the open-loop figure g b t^3 / 6 = 136.9 m */
	ck_assert_msg(fabs(h120 / (G0 * bg * 120 * 120 * 120 / 6) - 1) < 0.02,
		      "120 s: %g m", h120);
	h4 = hypot(e[(n - 1) * SSCOPE_NAVSIM_N_COMP], e[(n - 1) * SSCOPE_NAVSIM_N_COMP + 1]);
	sscope_navsim_budget(ns, &imu, &bp);
	ck_assert(bp.model == SSCOPE_BUDGET_SCHULER && bp.gyro_bias_rad_s == bg);
	sscope_budget_source_eval(&bp, SSCOPE_BUDGET_GYRO_BIAS, 4 * 3600, &sch);
	bp.model = SSCOPE_BUDGET_OPEN_LOOP;
	sscope_budget_source_eval(&bp, SSCOPE_BUDGET_GYRO_BIAS, 4 * 3600, &t3);
	/* bounded as the Schuler solution R b (t - sin(w t) / w): within
	 * 15 % after 4 h (the single channel leaves out the Earth-rate
	 * coupling, which test_linear_error_model checks, and the attitude
	 * error of 40 deg is far from small), and 50 times below t^3 */
	ck_assert_msg(fabs(h4 / sch.position_m - 1) < 0.15 && t3.position_m > 50 * h4,
		      "4 h: %g m, Schuler %g m, t^3 %g m", h4, sch.position_m,
		      t3.position_m);
	free(e);
	sscope_navsim_free(ns);
}
END_TEST

/*
 * The linearised error model of a stationary local-level (NED) system
 * with the vertical channel aided (Titterton & Weston, ch. 12; Groves,
 * sec. 14.2): states dr_N, dr_E (m), dv_N, dv_E (m/s) and the attitude
 * error e (rad; Euler angle errors of a level, north-pointing body),
 *   e'  = b_g - dw_in - w_ie x e,
 *   dw_in = (-W sinL dL + dv_E/R_E, -dv_N/R_N, -W cosL dL - dv_E tanL/R_E),
 *   dv' = e x (0, 0, -g) + b_a - 2 w_ie x dv,   dr' = dv,  dL = dr_N/R_N.
 */
struct lin_model {
	double lat, rn, re, g, w[3], bg[3], ba[2];
};

static int lin_rhs(double t, const double y[], double f[], void *p)
{
	const struct lin_model *m = p;
	const double *w = m->w, *e = y + 4;
	double dl = y[0] / m->rn, win[3];

	(void)t;
	win[0] = w[2] * dl + y[3] / m->re; /* w[2] = -W sinL */
	win[1] = -y[2] / m->rn;
	win[2] = -w[0] * dl - y[3] * tan(m->lat) / m->re; /* w[0] = W cosL */
	f[0] = y[2];
	f[1] = y[3];
	/* w x dv with dv_D = 0 */
	f[2] = -m->g * e[1] + m->ba[0] + 2 * w[2] * y[3];
	f[3] = m->g * e[0] + m->ba[1] - 2 * w[2] * y[2];
	f[4] = m->bg[0] - win[0] - (w[1] * e[2] - w[2] * e[1]);
	f[5] = m->bg[1] - win[1] - (w[2] * e[0] - w[0] * e[2]);
	f[6] = m->bg[2] - win[2] - (w[0] * e[1] - w[1] * e[0]);
	return GSL_SUCCESS;
}

/*
 * navsim against the model for biases times @p scale: the largest
 * departure of each state over 4 h relative to its peak (rel), and the
 * size of the second-order terms the model leaves out (the largest
 * attitude error, or horizontal position error over R_N).
 */
static void lin_compare(double scale, double rel[7], double *second)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct lin_model m;
	struct sscope_navsim *ns;
	gsl_odeiv2_system sys = { lin_rhs, NULL, 7, &m };
	gsl_odeiv2_driver *drv;
	double *e, y[7] = { 0 }, t = 0, peak[7] = { 0 }, dev[7] = { 0 };
	/* navsim's components for the model's states */
	const int comp[7] = { SSCOPE_NAVSIM_NORTH, SSCOPE_NAVSIM_EAST,
			      SSCOPE_NAVSIM_VN, SSCOPE_NAVSIM_VE,
			      SSCOPE_NAVSIM_ROLL, SSCOPE_NAVSIM_PITCH,
			      SSCOPE_NAVSIM_YAW };
	size_t n;

	o.rate_hz = 20;
	o.start.lat_rad = 45 * D2R;
	o.duration_s = 4 * 3600;
	o.output_step_s = 60;
	imu.gyro_bias_rad_s[0] = scale * 0.0123 * D2R / 3600;
	imu.gyro_bias_rad_s[1] = scale * -0.0187 * D2R / 3600;
	imu.gyro_bias_rad_s[2] = scale * 0.0315 * D2R / 3600;
	imu.accel_bias_m_s2[0] = scale * 23.85e-6 * G0;
	imu.accel_bias_m_s2[1] = scale * -17.2e-6 * G0;
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	e = run1(ns, &imu);

	memset(&m, 0, sizeof(m));
	m.lat = o.start.lat_rad;
	sscope_nav_radii(m.lat, &m.rn, &m.re);
	m.g = sscope_nav_gravity(m.lat, 0);
	sscope_nav_earth_rate(m.lat, m.w);
	memcpy(m.bg, imu.gyro_bias_rad_s, sizeof(m.bg));
	memcpy(m.ba, imu.accel_bias_m_s2, sizeof(m.ba));
	drv = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1, 1e-14, 1e-12);
	ck_assert_ptr_nonnull(drv);
	for (size_t k = 0; k < n; k++) {
		ck_assert_int_eq(gsl_odeiv2_driver_apply(drv, &t, sscope_navsim_time(ns, k), y),
				 GSL_SUCCESS);
		for (int i = 0; i < 7; i++) {
			peak[i] = fmax(peak[i], fabs(y[i]));
			dev[i] = fmax(dev[i], fabs(e[k * SSCOPE_NAVSIM_N_COMP + comp[i]] - y[i]));
		}
	}
	gsl_odeiv2_driver_free(drv);
	*second = fmax(fmax(peak[4], peak[5]), fmax(peak[6], hypot(peak[0], peak[1]) / m.rn));
	for (int i = 0; i < 7; i++) {
		ck_assert_msg(peak[i] > 0, "state %d stays zero", i);
		rel[i] = dev[i] / peak[i];
	}
	free(e);
	sscope_navsim_free(ns);
}

START_TEST(test_linear_error_model)
{
	double rel1[7], rel4[7], s1, s4;

	/* biases of a navigation-grade IMU (0.01-0.03 deg/h, 20 ug) */
	lin_compare(1, rel1, &s1);
	lin_compare(0.25, rel4, &s4);
	for (int i = 0; i < 7; i++) {
		/* navsim equals the model up to the terms it leaves out ... */
		ck_assert_msg(rel1[i] < 2 * s1,
			      "state %d: navsim departs from the linear model by %g of its peak (second-order terms %g)",
			      i, rel1[i], s1);
		/* ... and the departure is of second order: a quarter of
		 * the biases leaves a sixteenth of the error (a quarter of
		 * it relative to the peak) */
		ck_assert_msg(rel4[i] < 0.3 * rel1[i],
			      "state %d: departure %g at 1/4 of the biases, %g at full: not second order",
			      i, rel4[i], rel1[i]);
	}
}
END_TEST

START_TEST(test_arw_monte_carlo)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim *ns;
	struct sscope_navsim_stat *st;
	const size_t M = 300;
	double N = 0.15 * D2R / 60, lo, hi;
	size_t n;

	o.rate_hz = 50;
	o.duration_s = 120;
	o.output_step_s = 30;
	o.start.lat_rad = 45 * D2R;
	imu.gyro.n = N;
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	st = calloc(n, sizeof(*st));
	ck_assert_int_eq(sscope_navsim_monte_carlo(ns, &imu, M, 3, st, NULL, NULL, NULL), 0);
	/* M s^2 / sigma^2 ~ chi^2_M (zero-mean errors): two-sided 1e-4 */
	lo = gsl_cdf_chisq_Pinv(5e-5, (double)M) / (double)M;
	hi = gsl_cdf_chisq_Qinv(5e-5, (double)M) / (double)M;
	for (size_t k = 1; k < n; k++) {
		double t = st[k].t_s, s2 = N * N * t;

		for (int c = SSCOPE_NAVSIM_ROLL; c <= SSCOPE_NAVSIM_YAW; c++) {
			double r = st[k].rms[c] * st[k].rms[c] / s2;

			/* Schuler and Earth-rate coupling change the
			 * variance by less than 0.1 % within 2 min */
			ck_assert_msg(r > lo && r < hi,
				      "t %g comp %d: rms^2 / (N^2 t) = %g outside [%g, %g]",
				      t, c, r, lo, hi);
		}
		/* percentiles of a normal: +-1.645 sigma, loose (sampling) */
		ck_assert(fabs(st[k].p95[SSCOPE_NAVSIM_YAW] - st[k].p05[SSCOPE_NAVSIM_YAW]) /
				  (2 * 1.645 * N * sqrt(t)) > 0.75);
		ck_assert(fabs(st[k].p95[SSCOPE_NAVSIM_YAW] - st[k].p05[SSCOPE_NAVSIM_YAW]) /
				  (2 * 1.645 * N * sqrt(t)) < 1.25);
		ck_assert(st[k].horiz_p50 <= st[k].horiz_p95);
		/* the rms's Monte-Carlo standard error: for normal errors
		 * sigma / sqrt(2 M); the estimate's own relative sd is about
		 * sqrt(14 / M) / 2 = 11 % at M = 300 (x^2 has kurtosis 15):
		 * within +-40 % (3.7 of those) */
		for (int c = SSCOPE_NAVSIM_ROLL; c <= SSCOPE_NAVSIM_YAW; c++) {
			double q = st[k].rms_se[c] / st[k].rms[c] * sqrt(2.0 * (double)M);

			ck_assert_msg(q > 0.6 && q < 1.4,
				      "t %g comp %d: rms_se sqrt(2M) / rms = %g", t, c, q);
		}
		ck_assert(st[k].horiz_rms_se > 0 && st[k].horiz_rms_se < st[k].horiz_rms);
	}
	/* one run: no standard error */
	ck_assert_int_eq(sscope_navsim_monte_carlo(ns, &imu, 1, 3, st, NULL, NULL, NULL), 0);
	ck_assert(isnan(st[n - 1].rms_se[SSCOPE_NAVSIM_YAW]) && isnan(st[n - 1].horiz_rms_se));
	free(st);
	sscope_navsim_free(ns);
}
END_TEST

/* a converter in sensor units: bits, +-half range, round mode */
static struct sscope_adc_spec adc_spec(enum sscope_quantity q, int bits,
				       double half, double noise)
{
	struct sscope_adc_spec a;

	memset(&a, 0, sizeof(a));
	a.bits = bits;
	a.lo = -half;
	a.hi = half;
	a.quantity = q;
	a.noise = noise;
	a.mode = SSCOPE_ADC_ROUND;
	return a;
}

START_TEST(test_adc_quantization)
{
	/* At rest a perfect IMU reads the Earth rate and -g: a coarse
	 * converter rounds them to its levels (multiples of q), and the
	 * navigation error is that of the fixed biases the rounding makes */
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu adc = { 0 }, eq = { 0 };
	struct sscope_adc_spec ga, aa;
	struct sscope_navsim *ns;
	double *e1, *e2, w[3], g, qg, qa, f[3];
	uint64_t clipped = 1;
	size_t n;

	o.rate_hz = 50;
	o.duration_s = 600;
	o.output_step_s = 10;
	o.start.lat_rad = 45 * D2R;
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	ga = adc_spec(SSCOPE_QUANTITY_ANGULAR_RATE, 12, 2048 * 3.7e-5, 0);
	aa = adc_spec(SSCOPE_QUANTITY_ACCELERATION, 10, 20.48, 0);
	qg = 3.7e-5;
	qa = 0.04;
	adc.gyro_adc = &ga;
	adc.accel_adc = &aa;
	/* body = NED (level, north): the readings and their levels */
	sscope_nav_earth_rate(o.start.lat_rad, w);
	g = sscope_nav_gravity(o.start.lat_rad, 0);
	f[0] = f[1] = 0;
	f[2] = -g;
	for (int i = 0; i < 3; i++) {
		eq.gyro_bias_rad_s[i] = round(w[i] / qg) * qg - w[i];
		eq.accel_bias_m_s2[i] = round(f[i] / qa) * qa - f[i];
	}
	ck_assert(fabs(eq.gyro_bias_rad_s[0]) > 1e-6 && fabs(eq.accel_bias_m_s2[2]) > 1e-3);
	e1 = calloc(n * SSCOPE_NAVSIM_N_COMP, sizeof(double));
	ck_assert_ptr_nonnull(e1);
	ck_assert_int_eq(sscope_navsim_run(ns, &adc, 1, 0, e1, &clipped, NULL), 0);
	ck_assert(clipped == 0);
	e2 = run1(ns, &eq);
	for (int c = 0; c < SSCOPE_NAVSIM_N_COMP; c++) {
		double peak = worst(e2, n, c, c + 1);

		if (c == SSCOPE_NAVSIM_DOWN || c == SSCOPE_NAVSIM_VD)
			continue; /* aided */
		ck_assert_msg(peak > 0, "component %d", c);
		for (size_t k = 0; k < n; k++)
			ck_assert_msg(fabs(e1[k * SSCOPE_NAVSIM_N_COMP + c] -
					   e2[k * SSCOPE_NAVSIM_N_COMP + c]) <= 1e-9 * peak,
				      "component %d at %zu: %g with the converter, %g with its biases",
				      c, k, e1[k * SSCOPE_NAVSIM_N_COMP + c],
				      e2[k * SSCOPE_NAVSIM_N_COMP + c]);
	}
	/* a range too small clips, and says so */
	ga = adc_spec(SSCOPE_QUANTITY_ANGULAR_RATE, 12, 4e-5, 0);
	ck_assert_int_eq(sscope_navsim_run(ns, &adc, 1, 0, e1, &clipped, NULL), 0);
	ck_assert(clipped >= 2 * sscope_navsim_n_samples(ns));
	/* a converter the library refuses */
	ga.bits = 0;
	ck_assert_int_eq(sscope_navsim_run(ns, &adc, 1, 0, e1, NULL, NULL), -EINVAL);
	free(e1);
	free(e2);
	sscope_navsim_free(ns);
}
END_TEST

START_TEST(test_adc_noise_monte_carlo)
{
	/* A gyro of N at fs behind a converter with input noise sigma_a and
	 * step q, both of the size of the sensor's per-sample noise sigma
	 * (so the quantization error is uniform and white): the attitude
	 * errors grow as the density sqrt(N^2 + (sigma_a^2 + q^2/12)/fs)
	 * that the budget takes from sscope_adc_analyze() */
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_budget_params bp;
	struct sscope_adc_spec ga;
	struct sscope_navsim *ns;
	struct sscope_navsim_stat *st;
	const size_t M = 200;
	double N = 0.15 * D2R / 60, fs = 50, sig, ntot, lo, hi;
	size_t n;

	o.rate_hz = fs;
	o.duration_s = 120;
	o.output_step_s = 30;
	o.start.lat_rad = 45 * D2R;
	sig = N * sqrt(fs);
	ga = adc_spec(SSCOPE_QUANTITY_ANGULAR_RATE, 16, 32768 * sig, sig);
	imu.gyro.n = N;
	imu.gyro_adc = &ga;
	ns = make(&o);
	sscope_navsim_budget(ns, &imu, &bp);
	ntot = sqrt(N * N + (sig * sig + sig * sig / 12) / fs);
	ck_assert_msg(fabs(bp.arw_rad_sqrt_s / ntot - 1) < 1e-12, "budget ARW %g, expected %g",
		      bp.arw_rad_sqrt_s, ntot);
	n = sscope_navsim_n_out(ns);
	st = calloc(n, sizeof(*st));
	ck_assert_int_eq(sscope_navsim_monte_carlo(ns, &imu, M, 5, st, NULL, NULL, NULL), 0);
	/* M s^2 / sigma^2 ~ chi^2_M: two-sided 1e-4 */
	lo = gsl_cdf_chisq_Pinv(5e-5, (double)M) / (double)M;
	hi = gsl_cdf_chisq_Qinv(5e-5, (double)M) / (double)M;
	for (size_t k = 1; k < n; k++)
		for (int c = SSCOPE_NAVSIM_ROLL; c <= SSCOPE_NAVSIM_YAW; c++) {
			double r = st[k].rms[c] * st[k].rms[c] / (ntot * ntot * st[k].t_s);

			ck_assert_msg(r > lo && r < hi,
				      "t %g comp %d: rms^2 / (N_total^2 t) = %g outside [%g, %g]",
				      st[k].t_s, c, r, lo, hi);
		}
	free(st);
	sscope_navsim_free(ns);
}
END_TEST

START_TEST(test_deterministic)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim *ns1, *ns2;
	double *a, *b;
	size_t n, M = 5;
	struct sscope_navsim_stat *st;

	o.rate_hz = 50;
	o.duration_s = 60;
	o.start.lat_rad = -33 * D2R;
	o.motion = SSCOPE_NAVSIM_TURN;
	o.turn_rate_rad_s = -5 * D2R;
	o.speed_m_s = 8;
	imu.gyro.n = 0.2 * D2R / 60;
	imu.gyro.b = 3 * D2R / 3600;
	imu.gyro.bias = 5 * D2R / 3600;
	imu.accel.n = 1e-3;
	imu.accel.scale_factor_error = 300e-6;
	imu.accel_m[0][1] = 1e-3;
	o.threads = 1;
	ns1 = make(&o);
	o.threads = 2;
	ns2 = make(&o);
	n = sscope_navsim_n_out(ns1);
	a = calloc(M * n * SSCOPE_NAVSIM_N_COMP, sizeof(double));
	b = calloc(M * n * SSCOPE_NAVSIM_N_COMP, sizeof(double));
	st = calloc(n, sizeof(*st));
	ck_assert_int_eq(sscope_navsim_monte_carlo(ns1, &imu, M, 42, st, a, NULL, NULL), 0);
	ck_assert_int_eq(sscope_navsim_monte_carlo(ns2, &imu, M, 42, st, b, NULL, NULL), 0);
	ck_assert(memcmp(a, b, M * n * SSCOPE_NAVSIM_N_COMP * sizeof(double)) == 0);
	/* run r of the Monte Carlo is sscope_navsim_run(seed, r) */
	{
		double *c = calloc(n * SSCOPE_NAVSIM_N_COMP, sizeof(double));

		ck_assert_int_eq(sscope_navsim_run(ns1, &imu, 42, 3, c, NULL, NULL), 0);
		ck_assert(memcmp(c, a + 3 * n * SSCOPE_NAVSIM_N_COMP,
				 n * SSCOPE_NAVSIM_N_COMP * sizeof(double)) == 0);
		/* another seed differs */
		ck_assert_int_eq(sscope_navsim_run(ns1, &imu, 43, 3, c, NULL, NULL), 0);
		ck_assert(memcmp(c, a + 3 * n * SSCOPE_NAVSIM_N_COMP,
				 n * SSCOPE_NAVSIM_N_COMP * sizeof(double)) != 0);
		free(c);
	}
	free(a);
	free(b);
	free(st);
	sscope_navsim_free(ns1);
	sscope_navsim_free(ns2);
}
END_TEST

START_TEST(test_table)
{
	/* the turn sampled at 10 Hz into a table: the spline reference is
	 * close to the analytic one and a perfect IMU follows it */
	struct sscope_navsim_opts o = { 0 }, ot;
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim *ns, *nt;
	const size_t rows = 1201;
	double *t = calloc(rows, sizeof(double)), (*x)[3] = calloc(rows, sizeof(*x));
	double (*eu)[3] = calloc(rows, sizeof(*eu)), *e;
	double r = 6 * D2R, v = 5, y0 = 0.3;
	size_t n;

	for (size_t i = 0; i < rows; i++) {
		double ti = 0.1 * (double)i, y = y0 + r * ti;

		t[i] = 1000 + ti; /* times need not start at 0 */
		x[i][0] = v / r * (sin(y) - sin(y0));
		x[i][1] = -v / r * (cos(y) - cos(y0));
		x[i][2] = 0;
		eu[i][0] = 0.01;
		eu[i][1] = -0.02;
		eu[i][2] = remainder(y, 2 * PI);
	}
	o.rate_hz = 50;
	o.duration_s = 120;
	o.output_step_s = 10;
	o.start.lat_rad = 10 * D2R;
	o.motion = SSCOPE_NAVSIM_TURN;
	o.turn_rate_rad_s = r;
	o.speed_m_s = v;
	o.yaw_rad = y0;
	o.roll_rad = 0.01;
	o.pitch_rad = -0.02;
	ot = o;
	ot.motion = SSCOPE_NAVSIM_TABLE;
	ot.duration_s = 0; /* the table's span */
	ot.table_t_s = t;
	ot.table_ned_m = (const double(*)[3])x;
	ot.table_euler_rad = (const double(*)[3])eu;
	ot.n_table = rows;
	ns = make(&o);
	nt = make(&ot);
	n = sscope_navsim_n_out(nt);
	ck_assert_int_eq(n, sscope_navsim_n_out(ns));
	for (size_t k = 0; k < n; k++) {
		struct sscope_navsim_pose a, b;

		sscope_navsim_truth(ns, k, &a);
		sscope_navsim_truth(nt, k, &b);
		ck_assert(fabs(a.pos.lat_rad - b.pos.lat_rad) * 6.4e6 < 1e-3);
		/* the natural spline's end conditions (zero acceleration)
		 * bend the ends; compare velocities inside */
		if (k > 0 && k + 1 < n)
			ck_assert(fabs(a.v_ned_m_s[0] - b.v_ned_m_s[0]) < 1e-3);
		ck_assert(fabs(remainder(a.euler_rad[2] - b.euler_rad[2], 2 * PI)) < 1e-6);
	}
	e = run1(nt, &imu);
	ck_assert_msg(worst(e, n, 0, 3) < 0.01, "table: position %g m", worst(e, n, 0, 3));
	ck_assert_msg(worst(e, n, 6, 9) < 1e-7, "table: attitude %g rad", worst(e, n, 6, 9));
	free(e);
	sscope_navsim_free(ns);
	sscope_navsim_free(nt);
	/* refused tables */
	ot.n_table = 2;
	ck_assert_int_eq(sscope_navsim_new(&nt, &ot, NULL), -EINVAL);
	ot.n_table = rows;
	t[5] = t[4];
	ck_assert_int_eq(sscope_navsim_new(&nt, &ot, NULL), -EINVAL);
	t[5] = t[4] + 0.1;
	eu[7][1] = 89.5 * D2R;
	ck_assert_int_eq(sscope_navsim_new(&nt, &ot, NULL), -EINVAL);
	eu[7][1] = -0.02;
	x[3][1] = NAN;
	ck_assert_int_eq(sscope_navsim_new(&nt, &ot, NULL), -EINVAL);
	free(t);
	free(x);
	free(eu);
}
END_TEST

/* horizontal error magnitude of record k */
static double horiz(const double *e, size_t k)
{
	return hypot(e[k * SSCOPE_NAVSIM_N_COMP + SSCOPE_NAVSIM_NORTH],
		     e[k * SSCOPE_NAVSIM_N_COMP + SSCOPE_NAVSIM_EAST]);
}

START_TEST(test_gimballed_gyro_bias)
{
	/* At rest, level and north-pointing, body and platform axes are the
	 * same: a gyro bias drifts both frames alike, so the two
	 * mechanisations give the same Schuler-bounded error (to 1 % of its
	 * peak, component by component: a wrong sign of the platform's
	 * drift flips them), bounded as R b (t - sin(w t) / w) within 15 %
	 * (test_gyro_bias) and far below the open-loop g b t^3 / 6. */
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_budget_params bp;
	struct sscope_budget_point sch;
	struct sscope_navsim *ns;
	double *es, *eg, peak = 0, dev = 0, bg = 0.1 * D2R / 3600, T = 4 * 3600;
	size_t n;

	o.rate_hz = 10;
	o.start.lat_rad = 45 * D2R;
	o.duration_s = T;
	o.output_step_s = 60;
	imu.gyro_bias_rad_s[1] = bg;
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	es = run1(ns, &imu);
	sscope_navsim_free(ns);
	o.mechanisation = SSCOPE_NAVSIM_GIMBALLED;
	ns = make(&o);
	eg = run1(ns, &imu);
	for (size_t k = 0; k < n; k++)
		for (int c = 0; c < 2; c++) {
			size_t i = k * SSCOPE_NAVSIM_N_COMP + (size_t)c;

			peak = fmax(peak, fabs(es[i]));
			dev = fmax(dev, fabs(es[i] - eg[i]));
		}
	sscope_navsim_budget(ns, &imu, &bp);
	sscope_budget_source_eval(&bp, SSCOPE_BUDGET_GYRO_BIAS, T, &sch);
	ck_assert_msg(dev < 0.01 * peak, "strapdown and gimballed differ by %g m (peak %g m)",
		      dev, peak);
	ck_assert_msg(fabs(horiz(eg, n - 1) / sch.position_m - 1) < 0.15 &&
			      G0 * bg * T * T * T / 6 > 50 * horiz(eg, n - 1),
		      "gimballed after 4 h: %g m, Schuler %g m", horiz(eg, n - 1),
		      sch.position_m);
	free(es);
	free(eg);
	sscope_navsim_free(ns);
}
END_TEST

/* yaw error after `secs` turning in place at `rate` with a z-gyro scale
 * factor error s */
static double sf_yaw(enum sscope_navsim_mech m, double rate, double s, double secs)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim *ns;
	double *e, y;
	size_t n;

	o.rate_hz = 100;
	o.start.lat_rad = 45 * D2R;
	o.duration_s = secs;
	o.motion = SSCOPE_NAVSIM_TURN;
	o.turn_rate_rad_s = rate;
	o.mechanisation = m;
	imu.gyro_m[2][2] = s;
	ns = make(&o);
	n = sscope_navsim_n_out(ns);
	e = run1(ns, &imu);
	y = e[(n - 1) * SSCOPE_NAVSIM_N_COMP + SSCOPE_NAVSIM_YAW];
	free(e);
	sscope_navsim_free(ns);
	return y;
}

START_TEST(test_gimballed_scale_factor)
{
	/* Turning in place at r with a z-gyro scale-factor error s, for T:
	 * strapdown, the gyro senses r - W sin(lat) (down axis) and the
	 * heading error is s (r - W sin(lat)) T, growing with r; gimballed,
	 * the platform's gyro senses only its torquing rate, the vertical
	 * Earth rate -W sin(lat) (the wander frame has no vertical transport
	 * rate), and the heading error is -s W sin(lat) T whatever r. */
	const double s = 1e-4, T = 300, r1 = 10 * D2R, r2 = 20 * D2R;
	const double wz = -SSCOPE_NAV_WGS84_OMEGA * sin(45 * D2R);
	double s1 = sf_yaw(SSCOPE_NAVSIM_STRAPDOWN, r1, s, T);
	double s2 = sf_yaw(SSCOPE_NAVSIM_STRAPDOWN, r2, s, T);
	double g1 = sf_yaw(SSCOPE_NAVSIM_GIMBALLED, r1, s, T);
	double g2 = sf_yaw(SSCOPE_NAVSIM_GIMBALLED, r2, s, T);

	ck_assert_msg(fabs(s1 / (s * (r1 + wz) * T) - 1) < 0.01 &&
			      fabs(s2 / (s * (r2 + wz) * T) - 1) < 0.01,
		      "strapdown: %g and %g rad, expected %g and %g", s1, s2,
		      s * (r1 + wz) * T, s * (r2 + wz) * T);
	ck_assert_msg(fabs(g1 / (s * wz * T) - 1) < 0.02 && fabs(g2 / (s * wz * T) - 1) < 0.02,
		      "gimballed: %g and %g rad, expected %g", g1, g2, s * wz * T);
}
END_TEST

START_TEST(test_wander_pole_static)
{
	/* a perfect IMU at rest near and at a pole for 1 h (free vertical
	 * channel): the wander-azimuth mechanisation stays within 1 mm */
	const double lats[3] = { 89.999, 90, -90 };

	for (int i = 0; i < 3; i++) {
		struct sscope_navsim_opts o = { 0 };
		struct sscope_navsim_imu imu = { 0 };
		struct sscope_navsim *ns;
		double *e;
		size_t n;

		o.rate_hz = 100;
		o.duration_s = 3600;
		o.start.lat_rad = lats[i] * D2R;
		o.start.lon_rad = 30 * D2R;
		o.start.height_m = 100;
		o.roll_rad = 1 * D2R;
		o.yaw_rad = 70 * D2R;
		o.free_vertical = true;
		ns = make(&o);
		n = sscope_navsim_n_out(ns);
		e = run1(ns, &imu);
		ck_assert_msg(worst(e, n, 0, 3) < 1e-3, "%g deg: position error %g m",
			      lats[i], worst(e, n, 0, 3));
		ck_assert_msg(worst(e, n, 6, 9) < 1e-9, "%g deg: attitude error %g rad",
			      lats[i], worst(e, n, 6, 9));
		free(e);
		sscope_navsim_free(ns);
	}
}
END_TEST

/* 250 m/s for 2 h along a meridian, crossing the pole (or the equator)
 * at 1 h */
static struct sscope_navsim *polar_route(double lat_cross_deg, size_t *n)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim *ns;
	double rn, re, half = 250.0 * 3600;

	sscope_nav_radii(lat_cross_deg * D2R, &rn, &re);
	o.rate_hz = 20;
	o.duration_s = 7200;
	o.output_step_s = 60;
	o.start.lat_rad = lat_cross_deg * D2R - half / sqrt(rn * re);
	o.start.lon_rad = 10 * D2R;
	o.motion = SSCOPE_NAVSIM_STRAIGHT;
	o.speed_m_s = 250;
	ns = make(&o);
	*n = sscope_navsim_n_out(ns);
	return ns;
}

START_TEST(test_wander_pole_route)
{
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim_pose p;
	size_t n;
	struct sscope_navsim *ns = polar_route(90, &n);
	double *e;

	/* the reference does cross the pole */
	sscope_navsim_truth(ns, (n - 1) / 2, &p);
	ck_assert_msg(p.pos.lat_rad > 89.99 * D2R, "lat at 1 h %g", p.pos.lat_rad / D2R);
	sscope_navsim_truth(ns, n - 1, &p);
	ck_assert(fabs(remainder(p.pos.lon_rad - 190 * D2R, 2 * PI)) < 1e-6);
	e = run1(ns, &imu);
	ck_assert_msg(worst(e, n, 0, 3) < 1, "position error %g m", worst(e, n, 0, 3));
	free(e);
	sscope_navsim_free(ns);
}
END_TEST

START_TEST(test_wander_pole_equator)
{
	/*
	 * A 0.01 deg/h bias of a horizontal gyro (along or across the track)
	 * tilts the platform and drives a Schuler-bounded error that does
	 * not depend on latitude to first order: on the same route across
	 * the pole and across the equator the horizontal errors agree within
	 * 5 % from 10 min on, and after 1 h both are R b (t - sin(w t) / w)
	 * within 3 % (the Earth rate couples only over longer spans).  A
	 * vertical gyro's bias is left out: its heading error meets the
	 * horizontal Earth rate at the equator and not at the pole (the
	 * errors then differ by about 15 % after 2 h, as they should).
	 */
	struct sscope_navsim_imu imu = { 0 };
	size_t n, m;
	struct sscope_navsim *np = polar_route(90, &n), *ne = polar_route(0, &m);
	const double b = 0.01 * D2R / 3600;

	ck_assert_int_eq(n, m);
	for (int ax = 0; ax < 2; ax++) {
		double *ep, *ee;

		memset(&imu, 0, sizeof(imu));
		imu.gyro_bias_rad_s[ax] = b;
		ep = run1(np, &imu);
		ee = run1(ne, &imu);
		for (size_t k = 0; k < n; k++) {
			double t = sscope_navsim_time(np, k);

			if (t < 600)
				continue;
			ck_assert_msg(fabs(horiz(ep, k) / horiz(ee, k) - 1) < 0.05,
				      "gyro %d, %g s: %g m at the pole, %g m at the equator",
				      ax, t, horiz(ep, k), horiz(ee, k));
			if (fabs(t - 3600) < 1e-6) {
				double rn, re, R, ws, sch;

				sscope_nav_radii(0, &rn, &re);
				R = sqrt(rn * re);
				ws = sqrt(sscope_nav_gravity(0, 0) / R);
				sch = R * b * (t - sin(ws * t) / ws);
				ck_assert_msg(fabs(horiz(ep, k) / sch - 1) < 0.03 &&
						      fabs(horiz(ee, k) / sch - 1) < 0.03,
					      "gyro %d, 1 h: %g m at the pole, %g m at the equator, Schuler %g m",
					      ax, horiz(ep, k), horiz(ee, k), sch);
			}
		}
		free(ep);
		free(ee);
	}
	sscope_navsim_free(np);
	sscope_navsim_free(ne);
}
END_TEST

START_TEST(test_refused)
{
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim *ns = NULL;
	struct sscope_diag d = { "" };
	double e[SSCOPE_NAVSIM_N_COMP * 4];

	ck_assert_int_eq(sscope_navsim_new(&ns, &o, &d), -EINVAL); /* rate */
	o.rate_hz = 100;
	ck_assert_int_eq(sscope_navsim_new(&ns, &o, &d), -EINVAL); /* duration */
	o.duration_s = 0.01;
	ck_assert_int_eq(sscope_navsim_new(&ns, &o, &d), -EDOM); /* 1 sample */
	o.duration_s = 10;
	o.start.lat_rad = 91 * D2R;
	ck_assert_int_eq(sscope_navsim_new(&ns, &o, &d), -EINVAL);
	ck_assert(strstr(d.msg, "latitude") != NULL);
	/* a turn is given relative to north: not within 0.1 deg of a pole */
	o.start.lat_rad = 89.95 * D2R;
	o.motion = SSCOPE_NAVSIM_TURN;
	o.turn_rate_rad_s = 0.1;
	ck_assert_int_eq(sscope_navsim_new(&ns, &o, &d), -EINVAL);
	ck_assert(strstr(d.msg, "89.9") != NULL);
	o.turn_rate_rad_s = 0;
	o.motion = SSCOPE_NAVSIM_STATIC;
	o.mechanisation = (enum sscope_navsim_mech)2;
	ck_assert_int_eq(sscope_navsim_new(&ns, &o, &d), -EINVAL);
	o.mechanisation = SSCOPE_NAVSIM_STRAPDOWN;
	o.start.lat_rad = 0;
	o.motion = SSCOPE_NAVSIM_STRAIGHT;
	ck_assert_int_eq(sscope_navsim_new(&ns, &o, &d), -EINVAL); /* speed */
	o.motion = SSCOPE_NAVSIM_TURN;
	ck_assert_int_eq(sscope_navsim_new(&ns, &o, &d), -EINVAL); /* rate 0 */
	o.motion = SSCOPE_NAVSIM_TABLE;
	ck_assert_int_eq(sscope_navsim_new(&ns, &o, &d), -EINVAL); /* no data */
	o.motion = SSCOPE_NAVSIM_STATIC;
	o.output_step_s = 1;
	ns = make(&o);
	ck_assert_int_eq(sscope_navsim_n_out(ns), 11);
	imu.gyro.n = -1;
	ck_assert_int_eq(sscope_navsim_run(ns, &imu, 1, 0, e, NULL, &d), -EINVAL);
	imu.gyro.n = 0;
	imu.accel_m[1][2] = INFINITY;
	ck_assert_int_eq(sscope_navsim_run(ns, &imu, 1, 0, e, NULL, &d), -EINVAL);
	imu.accel_m[1][2] = 0;
	ck_assert_int_eq(sscope_navsim_monte_carlo(ns, &imu, 0, 1, NULL, NULL, NULL, &d),
			 -EINVAL);
	{
		struct sscope_navsim_pose p;

		ck_assert_int_eq(sscope_navsim_truth(ns, 11, &p), -EINVAL);
	}
	/* a gimballed platform has no converters */
	{
		struct sscope_adc_spec a = { 0 };

		imu.gyro_adc = &a;
		ck_assert_int_eq(sscope_navsim_set_mechanisation(ns, SSCOPE_NAVSIM_GIMBALLED), 0);
		ck_assert_int_eq(sscope_navsim_run(ns, &imu, 1, 0, e, NULL, &d), -EINVAL);
		ck_assert(strstr(d.msg, "gimballed") != NULL);
		ck_assert_int_eq(sscope_navsim_set_mechanisation(ns, (enum sscope_navsim_mech)2),
				 -EINVAL);
		imu.gyro_adc = NULL;
	}
	ck_assert_str_eq(sscope_navsim_mech_name(SSCOPE_NAVSIM_GIMBALLED), "gimballed");
	ck_assert_ptr_null(sscope_navsim_mech_name((enum sscope_navsim_mech)2));
	ck_assert_str_eq(sscope_navsim_comp_name(SSCOPE_NAVSIM_YAW), "yaw");
	ck_assert_ptr_null(sscope_navsim_comp_name(SSCOPE_NAVSIM_N_COMP));
	sscope_navsim_free(ns);
	sscope_navsim_free(NULL);
}
END_TEST

START_TEST(test_clipping)
{
	/* a turn faster than the gyro's range is clipped and counted */
	struct sscope_navsim_opts o = { 0 };
	struct sscope_navsim_imu imu = { 0 };
	struct sscope_navsim *ns;
	struct sscope_navsim_stat st[11];
	uint64_t clipped = 0;

	o.rate_hz = 50;
	o.duration_s = 10;
	o.output_step_s = 1;
	o.motion = SSCOPE_NAVSIM_TURN;
	o.turn_rate_rad_s = 150 * D2R;
	imu.gyro.has = SSCOPE_SENSOR_HAS_RANGE;
	imu.gyro.range = 100 * D2R;
	ns = make(&o);
	ck_assert_int_eq(sscope_navsim_monte_carlo(ns, &imu, 1, 1, st, NULL, &clipped, NULL), 0);
	ck_assert_int_eq(clipped, 500);
	/* the heading lags by 50 deg/s: -500 deg after 10 s */
	ck_assert(fabs(st[10].p50[SSCOPE_NAVSIM_YAW] - remainder(-500 * D2R, 2 * PI)) < 1e-3);
	sscope_navsim_free(ns);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("navsim");
	TCase *tc = tcase_create("core");

	tcase_set_timeout(tc, 300);
	tcase_add_test(tc, test_perfect_static);
	tcase_add_test(tc, test_perfect_moving);
	tcase_add_test(tc, test_coning_sculling);
	tcase_add_test(tc, test_schuler_accel_bias);
	tcase_add_test(tc, test_gyro_bias);
	tcase_add_test(tc, test_linear_error_model);
	tcase_add_test(tc, test_arw_monte_carlo);
	tcase_add_test(tc, test_adc_quantization);
	tcase_add_test(tc, test_adc_noise_monte_carlo);
	tcase_add_test(tc, test_deterministic);
	tcase_add_test(tc, test_table);
	tcase_add_test(tc, test_refused);
	tcase_add_test(tc, test_clipping);
	tcase_add_test(tc, test_gimballed_gyro_bias);
	tcase_add_test(tc, test_gimballed_scale_factor);
	tcase_add_test(tc, test_wander_pole_static);
	tcase_add_test(tc, test_wander_pole_route);
	tcase_add_test(tc, test_wander_pole_equator);
	suite_add_tcase(s, tc);
	return s;
}
