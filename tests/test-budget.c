/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Unit tests of analysis/budget.c: the textbook's numbers (10 deg/h for 120 s
 * -> 137 m; accelerometer bias -> b t^2 / 2), the Schuler forms against
 * numerical quadrature of the impulse responses and against their
 * short-time limits, time-to-error inversion, and the Monte-Carlo check of
 * the random walks against the binomial bound of the +-2 sigma fraction.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check-main.h"

#define PI 3.14159265358979323846
#define D2R (PI / 180)
#define G0 9.80665

START_TEST(test_seed_numbers)
{
	struct sscope_budget_params p = { 0 };
	struct sscope_budget_point pt;

	p.gyro_bias_rad_s = 10 * D2R / 3600;
	p.accel_bias_m_s2 = 1e-3 * G0;
	ck_assert_int_eq(sscope_budget_source_eval(&p, SSCOPE_BUDGET_GYRO_BIAS,
						   120, &pt), 0);
	/* the textbook: "approximately 140 m"; g b t^3 / 6 = 136.93 m */
	ck_assert_rel(pt.position_m, G0 * p.gyro_bias_rad_s * 120 * 120 * 120 / 6,
		      1e-14);
	ck_assert(fabs(pt.position_m - 137) < 0.5);
	ck_assert_rel(pt.velocity_m_s, G0 * p.gyro_bias_rad_s * 120 * 120 / 2,
		      1e-14);
	ck_assert_rel(pt.attitude_rad, p.gyro_bias_rad_s * 120, 1e-14);
	ck_assert_int_eq(sscope_budget_source_eval(&p, SSCOPE_BUDGET_ACCEL_BIAS,
						   73.5, &pt), 0);
	ck_assert_rel(pt.position_m, 0.5 * 1e-3 * G0 * 73.5 * 73.5, 1e-14);
	ck_assert_rel(pt.velocity_m_s, 1e-3 * G0 * 73.5, 1e-14);
	ck_assert(pt.attitude_rad == 0);
	/* the random walks, open loop */
	p.arw_rad_sqrt_s = 0.15 * D2R / 60;
	p.vrw_m_s_sqrt_s = 0.03 / 60;
	ck_assert_int_eq(sscope_budget_source_eval(&p, SSCOPE_BUDGET_ARW, 200,
						   &pt), 0);
	ck_assert_rel(pt.attitude_rad, p.arw_rad_sqrt_s * sqrt(200.0), 1e-14);
	ck_assert_rel(pt.position_m,
		      G0 * p.arw_rad_sqrt_s * sqrt(pow(200, 5) / 20), 1e-14);
	ck_assert_int_eq(sscope_budget_source_eval(&p, SSCOPE_BUDGET_VRW, 200,
						   &pt), 0);
	ck_assert_rel(pt.velocity_m_s, p.vrw_m_s_sqrt_s * sqrt(200.0), 1e-14);
	ck_assert_rel(pt.position_m, p.vrw_m_s_sqrt_s * sqrt(200.0 * 200 * 200 / 3),
		      1e-14);
	/* scale factor: 300 ppm at a 10 deg/s turn is a 3e-3 deg/s bias */
	memset(&p, 0, sizeof(p));
	p.gyro_sf = 300e-6;
	p.turn_rate_rad_s = 10 * D2R;
	sscope_budget_source_eval(&p, SSCOPE_BUDGET_SCALE_FACTOR, 60, &pt);
	ck_assert_rel(pt.position_m, G0 * 3e-3 * D2R * 60 * 60 * 60 / 6, 1e-14);
	ck_assert_str_eq(sscope_budget_source_name(SSCOPE_BUDGET_VRW), "vrw");
	ck_assert(sscope_budget_source_name(SSCOPE_BUDGET_N_SOURCES) == NULL);
	ck_assert(sscope_budget_source_random(SSCOPE_BUDGET_ARW));
	ck_assert(!sscope_budget_source_random(SSCOPE_BUDGET_GYRO_BIAS));
	ck_assert_int_eq(sscope_budget_source_eval(&p, SSCOPE_BUDGET_ARW, -1, &pt),
			 -EINVAL);
	p.arw_rad_sqrt_s = NAN;
	ck_assert_int_eq(sscope_budget_source_eval(&p, SSCOPE_BUDGET_ARW, 1, &pt),
			 -EINVAL);
}
END_TEST

/* Simpson's rule of f over [0, t] with n (even) intervals */
static double simpson(double (*f)(double, double), double w, double t, int n)
{
	double h = t / n, s = f(0, w) + f(t, w);

	for (int i = 1; i < n; i++)
		s += (i % 2 ? 4 : 2) * f(i * h, w);
	return s * h / 3;
}

static double omc2(double u, double w)
{
	double c = 1 - cos(w * u);

	return c * c;
}

static double sin2(double u, double w)
{
	return sin(w * u) * sin(w * u);
}

static double cos2(double u, double w)
{
	return cos(w * u) * cos(w * u);
}

START_TEST(test_schuler)
{
	struct sscope_budget_params p = { 0 };
	struct sscope_budget_point pt, ol;
	double w, g = G0, R = SSCOPE_BUDGET_EARTH_RADIUS_M;

	p.model = SSCOPE_BUDGET_SCHULER;
	w = sscope_budget_schuler_rad_s(&p);
	ck_assert_rel(w, 1.2407e-3, 1e-4);
	ck_assert_rel(2 * PI / w / 60, 84.41, 1e-3); /* Schuler period, min */
	/* ARW and VRW: closed forms against quadrature of the responses */
	p.arw_rad_sqrt_s = 0.05 * D2R / 60;
	p.vrw_m_s_sqrt_s = 0.02 / 60;
	for (double t = 100; t < 20000; t *= 3.7) {
		double N = p.arw_rad_sqrt_s, V = p.vrw_m_s_sqrt_s;

		sscope_budget_source_eval(&p, SSCOPE_BUDGET_ARW, t, &pt);
		ck_assert_rel(pt.position_m,
			      g * N / (w * w) * sqrt(simpson(omc2, w, t, 20000)),
			      1e-9);
		ck_assert_rel(pt.velocity_m_s,
			      g * N / w * sqrt(simpson(sin2, w, t, 20000)), 1e-9);
		ck_assert_rel(pt.attitude_rad, N * sqrt(simpson(cos2, w, t, 20000)),
			      1e-9);
		sscope_budget_source_eval(&p, SSCOPE_BUDGET_VRW, t, &pt);
		ck_assert_rel(pt.position_m, V / w * sqrt(simpson(sin2, w, t, 20000)),
			      1e-9);
		ck_assert_rel(pt.velocity_m_s, V * sqrt(simpson(cos2, w, t, 20000)),
			      1e-9);
		ck_assert_rel(pt.attitude_rad,
			      V / (R * w) * sqrt(simpson(sin2, w, t, 20000)), 1e-9);
	}
	/* short times: Schuler -> open loop, relative gap (w t)^2 / 20 for the
	 * gyro-bias position; continuity across the series switch */
	p.gyro_bias_rad_s = 1 * D2R / 3600;
	p.accel_bias_m_s2 = 1e-4;
	for (double t = 1; t < 400; t *= 2.3) {
		struct sscope_budget_params q = p;

		q.model = SSCOPE_BUDGET_OPEN_LOOP;
		sscope_budget_source_eval(&p, SSCOPE_BUDGET_GYRO_BIAS, t, &pt);
		sscope_budget_source_eval(&q, SSCOPE_BUDGET_GYRO_BIAS, t, &ol);
		ck_assert_rel(ol.position_m / pt.position_m - 1,
			      w * w * t * t / 20, 0.02);
		sscope_budget_source_eval(&p, SSCOPE_BUDGET_ARW, t, &pt);
		sscope_budget_source_eval(&q, SSCOPE_BUDGET_ARW, t, &ol);
		ck_assert_rel(pt.position_m, ol.position_m, w * w * t * t);
	}
	{
		double x0 = 0.05 / w, a, b;

		sscope_budget_source_eval(&p, SSCOPE_BUDGET_ARW, x0 * (1 - 1e-12), &pt);
		a = pt.position_m;
		sscope_budget_source_eval(&p, SSCOPE_BUDGET_ARW, x0 * (1 + 1e-12), &pt);
		b = pt.position_m;
		ck_assert_rel(a, b, 1e-9);
	}
	/* accel bias: bounded, back to zero after a Schuler period */
	sscope_budget_source_eval(&p, SSCOPE_BUDGET_ACCEL_BIAS, PI / w, &pt);
	ck_assert_rel(pt.position_m, 2 * p.accel_bias_m_s2 / (w * w), 1e-12);
	sscope_budget_source_eval(&p, SSCOPE_BUDGET_ACCEL_BIAS, 2 * PI / w, &pt);
	ck_assert(pt.position_m < 1e-9 * 2 * p.accel_bias_m_s2 / (w * w));
	/* gyro bias: velocity bounded by 2 R b, position ~ R b t */
	sscope_budget_source_eval(&p, SSCOPE_BUDGET_GYRO_BIAS, PI / w, &pt);
	ck_assert_rel(pt.velocity_m_s, 2 * R * p.gyro_bias_rad_s, 1e-12);
	/* automatic switch at 300 s */
	p.model = SSCOPE_BUDGET_AUTO;
	ck_assert(!sscope_budget_is_schuler(&p, 300));
	ck_assert(sscope_budget_is_schuler(&p, 300.001));
	p.switch_time_s = 60;
	ck_assert(sscope_budget_is_schuler(&p, 61));
}
END_TEST

START_TEST(test_total_and_time_to)
{
	struct sscope_budget_params p = { 0 };
	struct sscope_budget_point tot, a, b;
	double t;

	p.gyro_bias_rad_s = 10 * D2R / 3600;
	p.accel_bias_m_s2 = 2e-3 * G0;
	sscope_budget_total(&p, 100, &tot);
	sscope_budget_source_eval(&p, SSCOPE_BUDGET_GYRO_BIAS, 100, &a);
	sscope_budget_source_eval(&p, SSCOPE_BUDGET_ACCEL_BIAS, 100, &b);
	ck_assert_rel(tot.position_m, hypot(a.position_m, b.position_m), 1e-14);
	/* 137 m of gyro-bias error is reached just after 120 s */
	ck_assert_int_eq(sscope_budget_time_to(&p, SSCOPE_BUDGET_GYRO_BIAS,
					       SSCOPE_BUDGET_POSITION, 136.92666487,
					       3600, &t), 0);
	ck_assert_rel(t, 120, 1e-8);
	/* accel bias alone: (1/2) b t^2 = 50 m at t = sqrt(100 / b) */
	ck_assert_int_eq(sscope_budget_time_to(&p, SSCOPE_BUDGET_ACCEL_BIAS,
					       SSCOPE_BUDGET_POSITION, 50, 3600,
					       &t), 0);
	ck_assert_rel(t, sqrt(100 / p.accel_bias_m_s2), 1e-8);
	/* the total reaches 50 m earlier */
	{
		double tt;

		ck_assert_int_eq(sscope_budget_time_to(&p, -1, SSCOPE_BUDGET_POSITION,
						       50, 3600, &tt), 0);
		ck_assert(tt < t);
	}
	/* Schuler-bounded accel bias never exceeds 2 b / w^2 */
	p.model = SSCOPE_BUDGET_SCHULER;
	ck_assert_int_eq(sscope_budget_time_to(&p, SSCOPE_BUDGET_ACCEL_BIAS,
					       SSCOPE_BUDGET_POSITION, 1e6, 1e6,
					       &t), -EDOM);
	ck_assert_int_eq(sscope_budget_time_to(&p, 9, SSCOPE_BUDGET_POSITION, 1,
					       10, &t), -EINVAL);
	ck_assert_int_eq(sscope_budget_time_to(&p, -1, SSCOPE_BUDGET_POSITION, 0,
					       10, &t), -EINVAL);
}
END_TEST

START_TEST(test_monte_carlo)
{
	const char *v = getenv("SSCOPE_RUN"), *f = getenv("CK_FORK");
	bool slow = (v && *v) || (f && !strcmp(f, "no"));
	struct sscope_budget_mc_opts o = { 0 };
	const double times[3] = { 17.3, 60, 120 }; /* 17.3 s is off the grid */
	struct sscope_budget_mc_point pt[3];
	double p95 = erf(sqrt(2.0)), M, bsd;

	o.gyro = true;
	o.strength = 0.1 * D2R / 60;
	o.t_end_s = 120;
	o.steps = slow ? 120 : 600;
	o.realisations = slow ? 1000 : 4000;
	o.seed = 20;
	M = (double)o.realisations;
	bsd = sqrt(p95 * (1 - p95) / M);
	for (int gy = 1; gy >= 0; gy--) {
		o.gyro = gy;
		if (!gy)
			o.strength = 0.05 / 60;
		ck_assert_int_eq(sscope_budget_mc(&o, times, 3, pt, NULL, 0), 0);
		for (int j = 0; j < 3; j++) {
			ck_assert(fabs(pt[j].t_s - times[j]) < 1e-9);
			/* fraction inside +-2 sigma sqrt(t): binomial, 4 sd */
			ck_assert_msg(fabs(pt[j].walk_inside - p95) < 4 * bsd,
				      "walk inside %g", pt[j].walk_inside);
			ck_assert_msg(fabs(pt[j].pos_inside - p95) < 4 * bsd,
				      "pos inside %g", pt[j].pos_inside);
			/* rms about zero: relative sd 1/sqrt(2M) */
			ck_assert_rel(pt[j].walk_sd, pt[j].walk_sd_theory,
				      4 / sqrt(2 * M));
			ck_assert_rel(pt[j].pos_sd, pt[j].pos_sd_theory,
				      4 / sqrt(2 * M));
		}
	}
	/* same seed, same numbers; paths start at 0 */
	{
		double *paths = malloc(2 * (o.steps + 1) * sizeof(double));
		struct sscope_budget_mc_point q[3];

		ck_assert_int_eq(sscope_budget_mc(&o, times, 3, q, paths, 2), 0);
		ck_assert(q[2].walk_sd == pt[2].walk_sd);
		ck_assert(paths[0] == 0 && paths[o.steps + 1] == 0);
		free(paths);
	}
	{
		double bad = 500;

		ck_assert_int_eq(sscope_budget_mc(&o, &bad, 1, pt, NULL, 0), -EINVAL);
		o.steps = 0;
		ck_assert_int_eq(sscope_budget_mc(&o, times, 3, pt, NULL, 0), -EINVAL);
	}
}
END_TEST

/* Dominant source and its changes: open loop, an accelerometer bias a
 * (a t^2 / 2) dominates until the gyro bias b (g b t^3 / 6) overtakes it
 * at t = 3 a / (g b) exactly. */
START_TEST(test_dominant_crossovers)
{
	struct sscope_budget_params p = { 0 };
	struct sscope_budget_crossover c[4];
	double a = 2.385e-3 * G0, b = 7.3 * D2R / 3600, tx = 3 * a / (G0 * b), v;
	size_t n;

	p.accel_bias_m_s2 = a;
	p.gyro_bias_rad_s = b;
	p.model = SSCOPE_BUDGET_OPEN_LOOP;
	ck_assert_int_eq(sscope_budget_dominant(&p, tx / 2, &v), SSCOPE_BUDGET_ACCEL_BIAS);
	ck_assert_rel(v, a * tx * tx / 8, 1e-14);
	ck_assert_int_eq(sscope_budget_dominant(&p, 2 * tx, NULL), SSCOPE_BUDGET_GYRO_BIAS);
	ck_assert_int_eq(sscope_budget_crossovers(&p, 1, 1e4, c, 4, &n), 0);
	ck_assert_uint_eq(n, 1);
	ck_assert_int_eq(c[0].from, SSCOPE_BUDGET_ACCEL_BIAS);
	ck_assert_int_eq(c[0].to, SSCOPE_BUDGET_GYRO_BIAS);
	ck_assert_rel(c[0].t_s, tx, 1e-12);
	/* no change inside the span, none at all without sources */
	ck_assert_int_eq(sscope_budget_crossovers(&p, 2 * tx, 1e4, c, 4, &n), 0);
	ck_assert_uint_eq(n, 0);
	memset(&p, 0, sizeof(p));
	ck_assert_int_eq(sscope_budget_dominant(&p, 10, &v), -1);
	ck_assert(v == 0);
	ck_assert_int_eq(sscope_budget_crossovers(&p, 1, 1e4, c, 4, &n), 0);
	ck_assert_uint_eq(n, 0);
	ck_assert_int_eq(sscope_budget_crossovers(&p, 0, 1e4, c, 4, &n), -EINVAL);
	ck_assert_int_eq(sscope_budget_crossovers(&p, 10, 1, c, 4, &n), -EINVAL);
}
END_TEST

/* Sources from measured terms: the worst axis, kept sources untouched. */
START_TEST(test_take_noise_and_calib)
{
	struct sscope_budget_params p = { 0 };
	struct sscope_calib_triad c;
	unsigned r;
	bool used;

	r = sscope_budget_take_noise(&p, SSCOPE_QUANTITY_ANGULAR_RATE, 7.3e-5, 2.1e-5, 0, &used);
	ck_assert(used);
	ck_assert_uint_eq(r, (1u << SSCOPE_BUDGET_ARW) | (1u << SSCOPE_BUDGET_GYRO_BIAS));
	r = sscope_budget_take_noise(&p, SSCOPE_QUANTITY_ANGULAR_RATE, 9.1e-5, 1.7e-5, 0, &used);
	ck_assert_uint_eq(r, 1u << SSCOPE_BUDGET_ARW);
	ck_assert(p.arw_rad_sqrt_s == 9.1e-5 && p.gyro_bias_rad_s == 2.1e-5);
	r = sscope_budget_take_noise(&p, SSCOPE_QUANTITY_ACCELERATION, 1.2e-3, NAN, 0, &used);
	ck_assert_uint_eq(r, 1u << SSCOPE_BUDGET_VRW);
	ck_assert(p.vrw_m_s_sqrt_s == 1.2e-3 && p.accel_bias_m_s2 == 0);
	/* a source given otherwise is kept; other quantities do not count */
	r = sscope_budget_take_noise(&p, SSCOPE_QUANTITY_ANGULAR_RATE, 1, 1,
				     (1u << SSCOPE_BUDGET_ARW) | (1u << SSCOPE_BUDGET_GYRO_BIAS),
				     &used);
	ck_assert_uint_eq(r, 0);
	ck_assert(!used && p.arw_rad_sqrt_s == 9.1e-5);
	ck_assert_uint_eq(sscope_budget_take_noise(&p, SSCOPE_QUANTITY_VOLTAGE, 1, 1, 0, &used), 0);
	ck_assert(!used);
	/* a calibration leaves bias_sd * scale (output SI), scale_sd / scale */
	memset(&p, 0, sizeof(p));
	sscope_calib_triad_identity(&c);
	c.bias_sd[0] = 1e-3;
	c.bias_sd[1] = 3e-3;
	c.bias_sd[2] = NAN;
	c.scale[0] = 2.5;
	c.scale[1] = 0.5;
	c.scale_sd[0] = 2.5e-4;
	c.scale_sd[1] = 1e-5;
	c.scale_sd[2] = NAN;
	r = sscope_budget_take_calib(&p, SSCOPE_QUANTITY_ACCELERATION, &c, 4e-4, 0);
	ck_assert_uint_eq(r, (1u << SSCOPE_BUDGET_ACCEL_BIAS) | (1u << SSCOPE_BUDGET_VRW));
	ck_assert_rel(p.accel_bias_m_s2, 2.5e-3, 1e-15);
	ck_assert_rel(p.accel_sf, 1e-4, 1e-15);
	ck_assert(p.vrw_m_s_sqrt_s == 4e-4 && p.gyro_bias_rad_s == 0);
	r = sscope_budget_take_calib(&p, SSCOPE_QUANTITY_ANGULAR_RATE, &c, NAN,
				     1u << SSCOPE_BUDGET_GYRO_BIAS);
	ck_assert_uint_eq(r, 0);
	ck_assert(p.gyro_bias_rad_s == 0 && p.arw_rad_sqrt_s == 0);
	ck_assert_rel(p.gyro_sf, 1e-4, 1e-15); /* the scale factor always */
	/* what the Monte-Carlo fractions should be */
	{
		double sd, e = sscope_budget_mc_expected(1000, &sd);

		ck_assert_rel(e, 0.954499736103642, 1e-14);
		ck_assert_rel(sd, sqrt(e * (1 - e) / 1000), 1e-15);
		sscope_budget_mc_expected(0, &sd);
		ck_assert(isnan(sd));
	}
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("budget");
	TCase *tc = tcase_create("core");

	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, test_seed_numbers);
	tcase_add_test(tc, test_schuler);
	tcase_add_test(tc, test_total_and_time_to);
	tcase_add_test(tc, test_monte_carlo);
	tcase_add_test(tc, test_dominant_crossovers);
	tcase_add_test(tc, test_take_noise_and_calib);
	suite_add_tcase(s, tc);
	return s;
}
