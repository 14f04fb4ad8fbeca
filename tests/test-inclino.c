/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Unit tests of analysis/inclino.c.  Oracles: closed-form tilts of exact
 * gravity vectors (contract convention, AN-1057 sensitivity 17.45 mg per
 * degree times cos theta); a simulated 3-axis accelerometer (seeded white
 * noise) with offset drift 0.1 mg/degC, 0.5 % scale change over -20..60
 * degC and 0.5 mrad cross-coupling, calibrated at 5 nodes and validated at
 * untabulated temperatures and random angles within +-60 degrees: <= 0.1
 * degree calibrated, >= 0.3 degree uncompensated (both printed); refusals.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "check-main.h"

#define G0 SSCOPE_CALIB_GRAVITY_STD
#define PI 3.14159265358979323846
#define D2R (PI / 180)
#define MG (1e-3 * G0)

START_TEST(tilt_closed_form)
{
	double r, p, s, a[3];
	double th = 30 * D2R, ph = -20 * D2R;

	a[0] = -G0 * sin(th);
	a[1] = G0 * sin(ph) * cos(th);
	a[2] = G0 * cos(ph) * cos(th);
	ck_assert_int_eq(sscope_inclino_tilt(SSCOPE_INCLINO_3AXIS, a, G0, &r, &p, &s), 0);
	ck_assert_rel(p, th, 1e-14);
	ck_assert_rel(r, ph, 1e-14);
	/* 1-axis: sensitivity 17.45 mg per degree, halved at 60 degrees */
	a[0] = -G0 * sin(60 * D2R);
	ck_assert_int_eq(sscope_inclino_tilt(SSCOPE_INCLINO_1AXIS, a, G0, &r, &p, &s), 0);
	ck_assert_rel(p, 60 * D2R, 1e-14);
	ck_assert(isnan(r));
	ck_assert_rel(s * D2R / MG, 1000 * D2R * 0.5, 1e-12); /* 17.4533 mg per degree, halved */
	/* beyond 1 g: clamped to 90 degrees, zero sensitivity */
	a[0] = -1.01 * G0;
	sscope_inclino_tilt(SSCOPE_INCLINO_1AXIS, a, G0, &r, &p, &s);
	ck_assert_rel(p, 90 * D2R, 1e-15);
	ck_assert(fabs(s) < 1e-9);
	/* 2-axis: full circle in the x-z plane */
	a[0] = -G0 * sin(150 * D2R);
	a[2] = G0 * cos(150 * D2R);
	sscope_inclino_tilt(SSCOPE_INCLINO_2AXIS, a, G0, &r, &p, &s);
	ck_assert_rel(p, 150 * D2R, 1e-14);
	ck_assert_int_eq(sscope_inclino_tilt(7, a, G0, &r, &p, &s), -EINVAL);
}
END_TEST

/* the simulated sensor at temperature T */
static void model(double T, double off[3], double sc[3], double mis[3][3])
{
	static const double o25[3] = { 3, -2, 1.5 }, k[3] = { 0.1, -0.1, 0.1 };

	for (int a = 0; a < 3; a++) {
		double dT = T - 20;

		off[a] = (o25[a] + k[a] * dT + 0.001 * dT * dT) * MG;
		for (int b = 0; b < 3; b++)
			mis[a][b] = a == b ? 0 : 5e-4 * (a < b ? 1 : -1);
	}
	sc[0] = 1 + 0.005 * (T + 20) / 80;
	sc[1] = 1 - 0.005 * (T + 20) / 80;
	sc[2] = 1 + 0.0025 * (T + 20) / 80;
}

/* samples of a pose: raw = b + S t + noise (1 mg per sample) */
static void pose_samples(gsl_rng *g, double T, double roll, double pitch,
			 size_t n, double *ax, double *ay, double *az,
			 double *tt, double *rr, double *pp)
{
	double off[3], sc[3], mis[3][3], t[3], raw[3];

	model(T, off, sc, mis);
	t[0] = -G0 * sin(pitch);
	t[1] = G0 * sin(roll) * cos(pitch);
	t[2] = G0 * cos(roll) * cos(pitch);
	for (int a = 0; a < 3; a++) {
		raw[a] = off[a] + sc[a] * t[a];
		for (int b = 0; b < 3; b++)
			raw[a] += mis[a][b] * t[b];
	}
	for (size_t i = 0; i < n; i++) {
		ax[i] = raw[0] + gsl_ran_gaussian_ziggurat(g, MG);
		ay[i] = raw[1] + gsl_ran_gaussian_ziggurat(g, MG);
		az[i] = raw[2] + gsl_ran_gaussian_ziggurat(g, MG);
		tt[i] = T + gsl_ran_gaussian_ziggurat(g, 0.05);
		rr[i] = roll;
		pp[i] = pitch;
	}
}

START_TEST(lut_calibration)
{
	enum { NS = 200, NPOSE = 25 * 5 };
	static const double nodes[5] = { -20, 0, 20, 40, 60 };
	static const double vtemps[4] = { -10, 10, 30, 50 };
	size_t n = (size_t)NS * NPOSE, np;
	double *ax = malloc(6 * n * sizeof(double)), *ay = ax + n, *az = ay + n,
	       *tt = az + n, *rr = tt + n, *pp = rr + n;
	struct sscope_inclino_pose *poses = malloc(NPOSE * 2 * sizeof(*poses));
	struct sscope_inclino_lut *lut = malloc(sizeof(*lut));
	struct sscope_inclino_plan *plan = NULL;
	struct sscope_inclino_validation v;
	struct sscope_diag d = { "" };
	gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
	size_t k = 0;

	gsl_rng_set(g, 2024);
	for (int t = 0; t < 5; t++)
		for (int i = 0; i < 5; i++)
			for (int j = 0; j < 5; j++) {
				pose_samples(g, nodes[t], (-60 + 30 * i) * D2R,
					     (-60 + 30 * j) * D2R, NS, ax + k, ay + k,
					     az + k, tt + k, rr + k, pp + k);
				k += NS;
			}
	ck_assert_int_eq(sscope_inclino_poses(ax, ay, az, tt, rr, pp, n, 0, poses,
					      NPOSE * 2, &np), 0);
	ck_assert_uint_eq(np, NPOSE);
	ck_assert_msg(sscope_inclino_build(poses, np, G0, 0, lut, &d) == 0, "%s", d.msg);
	ck_assert_uint_eq(lut->n, 5);
	/* node parameters against the model: offsets within 4 sd */
	for (size_t t = 0; t < 5; t++) {
		double off[3], sc[3], mis[3][3];

		model(nodes[t], off, sc, mis);
		ck_assert(fabs(lut->temp_degc[t] - nodes[t]) < 0.05);
		for (int a = 0; a < 3; a++) {
			ck_assert_msg(fabs(lut->p[t].offset[a] - off[a]) < 4 * lut->p[t].offset_sd[a] + 0.02 * MG,
				      "node %zu axis %d: offset %g, true %g, sd %g", t, a,
				      lut->p[t].offset[a], off[a], lut->p[t].offset_sd[a]);
			ck_assert_msg(fabs(lut->p[t].scale[a] - sc[a]) < 4 * lut->p[t].scale_sd[a] + 1e-5, "node %zu axis %d: scale %.8f, true %.8f, sd %g, rms %g, poses %zu", t, a, lut->p[t].scale[a], sc[a], lut->p[t].scale_sd[a], lut->p[t].residual_rms, lut->p[t].poses);
		}
	}
	ck_assert_int_eq(sscope_inclino_plan_new(&plan, lut, false, &d), 0);
	/* validation: untabulated temperatures, random angles within 60 deg */
	k = 0;
	for (int t = 0; t < 4; t++)
		for (int i = 0; i < 25; i++) {
			double roll = gsl_ran_flat(g, -60, 60) * D2R;
			double pitch = gsl_ran_flat(g, -60, 60) * D2R;

			pose_samples(g, vtemps[t], roll, pitch, NS, ax + k, ay + k,
				     az + k, tt + k, rr + k, pp + k);
			k += NS;
		}
	ck_assert_int_eq(sscope_inclino_poses(ax, ay, az, tt, rr, pp, k, 0, poses,
					      NPOSE * 2, &np), 0);
	ck_assert_uint_eq(np, 100);
	ck_assert_int_eq(sscope_inclino_validate(plan, poses, np, &v), 0);
	printf("# validation at -10/10/30/50 degC, 100 random poses within +-60 deg: calibrated max %.4f deg, rms %.4f deg; uncompensated max %.3f deg, rms %.3f deg; residual terms: offset %.3g, scale %.3g, misalignment %.3g deg (dominant: %s)\n",
	       v.max_deg, v.rms_deg, v.max_uncomp_deg, v.rms_uncomp_deg,
	       v.offset_deg, v.scale_deg, v.mis_deg, v.dominant ? v.dominant : "-");
	ck_assert(v.max_deg <= 0.1);
	ck_assert(v.max_uncomp_deg >= 0.3);
	ck_assert_uint_eq(v.clamped, 0);
	ck_assert_ptr_nonnull(v.dominant);
	/* cubic interpolation works too and is not worse than 0.1 deg */
	sscope_inclino_plan_free(plan);
	ck_assert_int_eq(sscope_inclino_plan_new(&plan, lut, true, &d), 0);
	ck_assert_int_eq(sscope_inclino_validate(plan, poses, np, &v), 0);
	printf("# cubic spline: calibrated max %.4f deg\n", v.max_deg);
	ck_assert(v.max_deg <= 0.1);
	/* the per-pose errors are what the summary summarises; a pose past
	 * 85 degrees of pitch is skipped (NaN) */
	{
		double (*e)[2] = malloc(np * sizeof(*e)), (*u)[2] = malloc(np * sizeof(*u));
		double mx = 0, mu = 0, s2 = 0, pitch0 = poses[0].pitch_rad;

		ck_assert_int_eq(sscope_inclino_pose_errors(plan, poses, np, e, u), 0);
		for (size_t i = 0; i < np; i++)
			for (int c = 0; c < 2; c++) {
				mx = fmax(mx, fabs(e[i][c]));
				mu = fmax(mu, fabs(u[i][c]));
				s2 += e[i][c] * e[i][c];
			}
		ck_assert(mx == v.max_deg && mu == v.max_uncomp_deg);
		ck_assert(fabs(sqrt(s2 / (2.0 * (double)np)) - v.rms_deg) < 1e-12 * v.rms_deg);
		poses[0].pitch_rad = 86 * D2R;
		ck_assert_int_eq(sscope_inclino_pose_errors(plan, poses, np, e, NULL), 0);
		ck_assert(isnan(e[0][0]) && isnan(e[0][1]) && isfinite(e[1][0]));
		ck_assert_int_eq(sscope_inclino_pose_errors(plan, poses, 1, e, NULL), -EDOM);
		ck_assert_int_eq(sscope_inclino_pose_errors(plan, NULL, 1, e, NULL), -EINVAL);
		poses[0].pitch_rad = pitch0;
		free(e);
		free(u);
	}
	/* clamping outside the range */
	{
		struct sscope_inclino_params a, b;
		bool cl = false;

		sscope_inclino_params_at(plan, 80, &a, &cl);
		ck_assert(cl);
		sscope_inclino_params_at(plan, lut->temp_degc[4], &b, &cl);
		ck_assert(!cl);
		ck_assert(a.offset[0] == b.offset[0] && a.scale[2] == b.scale[2]);
	}
	sscope_inclino_plan_free(plan);
	/* non-monotonic LUT refused */
	lut->temp_degc[2] = lut->temp_degc[1] - 1;
	ck_assert_int_eq(sscope_inclino_plan_new(&plan, lut, false, &d), -EDOM);
	ck_assert(strstr(d.msg, "increasing"));
	ck_assert_ptr_null(plan);
	/* poses that do not excite every axis: all level */
	for (size_t i = 0; i < 10; i++) {
		poses[i].roll_rad = poses[i].pitch_rad = 0;
		poses[i].temp_degc = 20;
	}
	ck_assert_int_eq(sscope_inclino_fit(poses, 10, G0, &lut->p[0], &d), -EDOM);
	ck_assert_int_eq(sscope_inclino_fit(poses, 4, G0, &lut->p[0], &d), -EDOM);
	free(ax);
	free(poses);
	free(lut);
	gsl_rng_free(g);
}
END_TEST

/* Applying a table: tilt and the still flag per sample.  A one-node table
 * of the ideal sensor leaves the readings as they are, so roll and pitch
 * are the closed forms; a norm 2 % off g, a rotation of 1 deg/s or a NaN
 * temperature is not still. */
START_TEST(apply_record)
{
	struct sscope_inclino_lut *lut = calloc(1, sizeof(*lut));
	struct sscope_inclino_plan *plan = NULL;
	struct sscope_inclino_apply_stats st;
	double roll = 12.5 * D2R, pitch = -31 * D2R;
	double ax[4], ay[4], az[4], T[4] = { 25, 25, 25, NAN };
	double wx[4] = { 0, 0, 1 * D2R, 0 }, wy[4] = { 0 }, wz[4] = { 0 };
	const double *a[3] = { ax, ay, az }, *w[3] = { wx, wy, wz };
	double r[4], p[4], sens[4];
	bool still[4];

	ck_assert_ptr_nonnull(lut);
	lut->n = 1;
	lut->gravity_m_s2 = G0;
	lut->temp_degc[0] = 20;
	for (int i = 0; i < 3; i++)
		lut->p[0].scale[i] = 1;
	ck_assert_int_eq(sscope_inclino_plan_new(&plan, lut, false, NULL), 0);
	for (int k = 0; k < 4; k++) {
		double f = k == 1 ? 1.02 : 1;

		ax[k] = -G0 * sin(pitch) * f;
		ay[k] = G0 * sin(roll) * cos(pitch) * f;
		az[k] = G0 * cos(roll) * cos(pitch) * f;
	}
	ck_assert_int_eq(sscope_inclino_apply(plan, SSCOPE_INCLINO_3AXIS, G0, a, T, w,
					      4, 0.01 * G0, 0.5 * D2R, r, p, sens,
					      still, &st), 0);
	ck_assert(fabs(r[0] - roll) < 1e-12 && fabs(p[0] - pitch) < 1e-12);
	ck_assert(still[0] && !still[1] && !still[2] && !still[3]);
	ck_assert(isnan(r[3]) && isnan(p[3]));
	ck_assert_uint_eq(st.n_still, 1);
	ck_assert_uint_eq(st.n_bad, 1);
	ck_assert_uint_eq(st.n_clamped, 3); /* 25 degC is outside a one-node table */
	/* without gyros the rotation is not looked at */
	ck_assert_int_eq(sscope_inclino_apply(plan, SSCOPE_INCLINO_3AXIS, G0, a, T, NULL,
					      4, 0.01 * G0, 0.5 * D2R, NULL, p, NULL,
					      still, &st), 0);
	ck_assert(still[2]);
	ck_assert_int_eq(sscope_inclino_apply(plan, SSCOPE_INCLINO_3AXIS, 0, a, T, NULL,
					      4, 0.01 * G0, 0.5 * D2R, NULL, p, NULL,
					      still, &st), -EINVAL);
	sscope_inclino_plan_free(plan);
	free(lut);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("inclino");
	TCase *tc = tcase_create("core");

	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, tilt_closed_form);
	tcase_add_test(tc, lut_calibration);
	tcase_add_test(tc, apply_record);
	suite_add_tcase(s, tc);
	return s;
}
