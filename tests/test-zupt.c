/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Unit tests of analysis/zupt.c on captures simulated by navsim's
 * trajectory and sensor models (tests/zupt-sim.h):
 * - at rest, white noise only: the gyro bias estimate against its closed
 *   form sd N / sqrt(t) (the filter's sd within 10 %, the error within
 *   4 sd), the levelled roll and pitch against the truth;
 * - biases drawn per run from the prior the filter is given, a walk of
 *   10.5 min with 19 stops: the bias estimates within their 2 sigma at
 *   >= 95 % of (stop, axis) pairs over 8 runs (95.4 % for a consistent
 *   filter; tests/bench-zupt.c runs 100), and over 4 runs of a vehicle
 *   route of 10 min with 12 stops; the end position within 4 sigma, and
 *   the horizontal error at 10 min with the stop updates at least 10 times
 *   smaller than without them;
 * - gyrocompassing: a tactical gyro (N 0.005 deg/sqrt(h), turn-on bias
 *   0.005 deg/h) still for 2 min finds the heading within 4 of its
 *   predicted sd (sqrt(sigma_b^2 + N^2 / T) / (Omega cos(lat)), 0.15 deg)
 *   in each of 10 runs; the MEMS gyro cannot, and the heading is assumed;
 * - refused input: NaN, too short, moving at the start, bad options.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check-main.h"
#include "zupt-sim.h"

#define D2R (3.14159265358979323846 / 180)

static int run_filter(const struct zsim *z, const struct sscope_zupt_opts *o,
		      struct sscope_zupt_result **r)
{
	const double *g[3], *a[3];

	for (int i = 0; i < 3; i++) {
		g[i] = z->imu + i;
		a[i] = z->imu + 3 + i;
	}
	return sscope_zupt_run(g, a, 6, z->n, o, r, NULL);
}

START_TEST(test_static)
{
	struct zsim_route r = { .stop_s = 120, .lat_rad = 0.7, .heading_rad = 0.4 };
	struct sscope_navsim_imu imu;
	struct sscope_zupt_opts o;
	struct sscope_zupt_result *res = NULL;
	struct zsim z;
	const struct sscope_zupt_rec *e;
	double sd_expect;

	zsim_imu(&imu);
	ck_assert_int_eq(zsim_build(&z, &r, 100, 1, &imu, 7, 0), 0);
	zsim_opts(&o, &z, &r, &imu, 1);
	ck_assert_int_eq(run_filter(&z, &o, &res), 0);
	ck_assert_int_eq(res->n_stops, 1);
	ck_assert(res->n_still > res->n_updates * 99 / 100);
	e = &res->rec[res->n_rec - 1];
	/* gyro bias: all the samples' mean, sd N / sqrt(t) */
	sd_expect = imu.gyro.n / sqrt(120);
	for (int i = 0; i < 3; i++) {
		double err = e->gyro_bias_rad_s[i] - z.bias[i];

		ck_assert_msg(fabs(e->sd_gyro_bias_rad_s[i] / sd_expect - 1) < 0.1,
			      "sd %g expected %g", e->sd_gyro_bias_rad_s[i], sd_expect);
		ck_assert_msg(fabs(err) < 4 * sd_expect, "axis %d error %g", i, err);
	}
	/* level within the tilt an accelerometer bias makes (5 mg: 0.3 deg) */
	ck_assert(fabs(res->roll0_rad) < 4 * 0.005 && fabs(res->pitch0_rad) < 4 * 0.005);
	ck_assert(fabs(res->heading0_rad - 0.4) < 1e-12);
	ck_assert(hypot(e->ned_m[0], e->ned_m[1]) < 0.05);
	sscope_zupt_result_free(res);
	zsim_free(&z);
}
END_TEST

START_TEST(test_gyrocompass)
{
	struct zsim_route r = { .stop_s = 120, .lat_rad = 0.8, .heading_rad = 0.3 };
	struct sscope_navsim_imu imu = { 0 };
	double ss = 0;

	imu.gyro.n = 0.005 * D2R / 60;
	imu.gyro.bias = 0.005 * D2R / 3600;
	imu.accel.n = 0.02 / 60;
	imu.accel.bias = 1e-4 * 9.80665;
	for (uint64_t run = 0; run < 10; run++) {
		struct zsim z;
		struct sscope_zupt_opts o;
		struct sscope_zupt_result *res = NULL;
		double sd, expect;

		ck_assert_int_eq(zsim_build(&z, &r, 100, 1, &imu, 3, run), 0);
		zsim_opts(&o, &z, &r, &imu, 1);
		o.heading_given = false;
		o.heading_rad = 0;
		ck_assert_int_eq(run_filter(&z, &o, &res), 0);
		ck_assert_int_eq(res->heading_from, SSCOPE_ZUPT_HEADING_GYROCOMPASS);
		sd = res->heading0_sd_rad;
		expect = sqrt(imu.gyro.bias * imu.gyro.bias + imu.gyro.n * imu.gyro.n / res->level_s) /
			 (SSCOPE_NAV_WGS84_OMEGA * cos(r.lat_rad));
		ck_assert_msg(fabs(sd / expect - 1) < 1e-9, "sd %g expected %g", sd, expect);
		ck_assert_msg(fabs(res->heading0_rad - 0.3) < 4 * sd, "run %u: heading %g",
			      (unsigned)run, res->heading0_rad);
		ss += pow((res->heading0_rad - 0.3) / sd, 2);
		sscope_zupt_result_free(res);
		zsim_free(&z);
	}
	/* chi-squared, 10 dof: 99.9 % below 29.6 */
	ck_assert_msg(ss < 29.6, "sum of squares %g", ss);
	{
		struct zsim z;
		struct sscope_zupt_opts o;
		struct sscope_zupt_result *res = NULL;

		zsim_imu(&imu);
		r.stop_s = 20;
		ck_assert_int_eq(zsim_build(&z, &r, 100, 1, &imu, 3, 0), 0);
		zsim_opts(&o, &z, &r, &imu, 1);
		o.heading_given = false;
		o.heading_rad = 0.1;
		ck_assert_int_eq(run_filter(&z, &o, &res), 0);
		ck_assert_int_eq(res->heading_from, SSCOPE_ZUPT_HEADING_ASSUMED);
		ck_assert(res->heading0_rad == 0.1 && res->gyrocompass_sd_rad > 1);
		sscope_zupt_result_free(res);
		zsim_free(&z);
	}
}
END_TEST

static const struct zsim_route vehicle = {
	.stop_s = 15, .leg_s = 40, .ramp_s = 4, .speed_m_s = 10, .turn_rad = 90 * D2R,
	.legs = 11, .lat_rad = 0.8, .heading_rad = 0.3
};

static const struct zsim_route walk = {
	.stop_s = 5, .leg_s = 30, .ramp_s = 1, .speed_m_s = 1.4, .turn_rad = 90 * D2R,
	.legs = 18, .walk = true, .lat_rad = 0.8, .heading_rad = 0.3
};

static void coverage(const struct zsim_route *route, uint64_t runs, double min_in)
{
	struct sscope_navsim_imu imu;
	size_t in = 0, total = 0;
	double worst_ratio = 1e300;

	zsim_imu(&imu);
	for (uint64_t run = 0; run < runs; run++) {
		struct zsim z;
		struct sscope_zupt_opts o;
		struct sscope_zupt_result *res = NULL, *raw = NULL;
		double e1, e0;

		ck_assert_int_eq(zsim_build(&z, route, 100, 1, &imu, 11, run), 0);
		zsim_opts(&o, &z, route, &imu, 1);
		ck_assert_int_eq(run_filter(&z, &o, &res), 0);
		/* the stops: the first, one per leg */
		ck_assert_msg(res->n_stops == route->legs + 1, "%zu stops", res->n_stops);
		for (size_t s = 0; s < res->n_stops; s++) {
			const struct sscope_zupt_stop *sp = &res->stops[s];

			for (int i = 0; i < 3; i++) {
				in += fabs(sp->gyro_bias_rad_s[i] - z.bias[i]) <=
				      2 * sp->sd_gyro_bias_rad_s[i];
				in += fabs(sp->accel_bias_m_s2[i] - z.bias[3 + i]) <=
				      2 * sp->sd_accel_bias_m_s2[i];
				total += 2;
			}
		}
		o.no_zupt = true;
		ck_assert_int_eq(run_filter(&z, &o, &raw), 0);
		ck_assert_int_eq(raw->n_rec, res->n_rec);
		e1 = zsim_horiz_err(&z, res->rec, res->n_rec - 1);
		e0 = zsim_horiz_err(&z, raw->rec, raw->n_rec - 1);
		if (e0 / e1 < worst_ratio)
			worst_ratio = e0 / e1;
		/* the filter's 1-sigma covers the error (4 sigma) */
		ck_assert_msg(e1 < 4 * hypot(res->rec[res->n_rec - 1].sd_ned_m[0],
					     res->rec[res->n_rec - 1].sd_ned_m[1]),
			      "run %u: error %g m", (unsigned)run, e1);
		sscope_zupt_result_free(res);
		sscope_zupt_result_free(raw);
		zsim_free(&z);
	}
	ck_assert_msg((double)in >= min_in * (double)total, "%zu of %zu within 2 sigma", in,
		      total);
	ck_assert_msg(worst_ratio >= 10, "error ratio %g", worst_ratio);
}

START_TEST(test_walk_coverage)
{
	coverage(&walk, 8, 0.95);
}
END_TEST

START_TEST(test_vehicle_coverage)
{
	coverage(&vehicle, 4, 0.95);
}
END_TEST

START_TEST(test_refused)
{
	struct zsim_route r = { .stop_s = 5, .leg_s = 10, .ramp_s = 1, .speed_m_s = 2,
				.turn_rad = 1, .legs = 1, .lat_rad = 0.8 };
	struct sscope_navsim_imu imu;
	struct sscope_zupt_opts o;
	struct sscope_zupt_result *res = NULL;
	const double *g[3], *a[3];
	struct zsim z;
	size_t skip;

	zsim_imu(&imu);
	ck_assert_int_eq(zsim_build(&z, &r, 100, 1, &imu, 3, 0), 0);
	zsim_opts(&o, &z, &r, &imu, 1);
	ck_assert_int_eq(run_filter(&z, &o, &res), 0);
	sscope_zupt_result_free(res);
	/* too short */
	for (int i = 0; i < 3; i++) {
		g[i] = z.imu + i;
		a[i] = z.imu + 3 + i;
	}
	ck_assert_int_eq(sscope_zupt_run(g, a, 6, 50, &o, &res, NULL), -EDOM);
	ck_assert_ptr_null(res);
	/* moving at the start: begin in the middle of the leg */
	skip = (size_t)(10 * 100);
	for (int i = 0; i < 3; i++) {
		g[i] = z.imu + 6 * skip + i;
		a[i] = z.imu + 6 * skip + 3 + i;
	}
	ck_assert_int_eq(sscope_zupt_run(g, a, 6, z.n - skip, &o, &res, NULL), -EDOM);
	/* NaN */
	z.imu[6 * 700 + 4] = NAN;
	ck_assert_int_eq(run_filter(&z, &o, &res), -EDOM);
	/* options */
	o.gyro_n = 0;
	ck_assert_int_eq(run_filter(&z, &o, &res), -EINVAL);
	zsim_opts(&o, &z, &r, &imu, 1);
	o.start.lat_rad = 1.56;
	ck_assert_int_eq(run_filter(&z, &o, &res), -EINVAL);
	ck_assert_int_eq(sscope_zupt_run(g, a, 6, z.n, &o, NULL, NULL), -EINVAL);
	zsim_free(&z);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("zupt");
	TCase *tc = tcase_create("core");

	tcase_set_timeout(tc, 60);
	tcase_add_test(tc, test_static);
	tcase_add_test(tc, test_gyrocompass);
	tcase_add_test(tc, test_walk_coverage);
	tcase_add_test(tc, test_vehicle_coverage);
	tcase_add_test(tc, test_refused);
	suite_add_tcase(s, tc);
	return s;
}
