/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Unit tests of analysis/model.c: Sagnac phases computed by hand, the
 * analytic step response of the second-order accelerometer against a
 * Runge-Kutta integration, bandwidth and overshoot against their
 * definitions.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>

#include "check-main.h"

#define PI 3.14159265358979323846
#define D2R (PI / 180)

START_TEST(test_fog)
{
	struct sscope_model_fog f;

	/* R 5 cm, 1000 turns, 1550 nm, 10 deg/s: by hand
	 * 8 pi^2 * 1000 * 0.0025 * 0.1745329 / (1.55e-6 * 299792458)
	 * = 34.4508 / 464.678 = 0.0741404 rad */
	ck_assert_int_eq(sscope_model_fog_coil(0.05, 1000, 1550e-9, &f), 0);
	ck_assert_rel(sscope_model_fog_phase(&f, 10 * D2R), 0.0741403629, 1e-9);
	ck_assert_rel(f.fibre_length_m, 314.159265, 1e-8);
	/* +-90 deg open-loop range: 211.87 deg/s */
	ck_assert_rel(f.max_rate_rad_s / D2R, 211.867904, 1e-8);
	ck_assert_rel(sscope_model_fog_phase(&f, f.max_rate_rad_s), PI / 2, 1e-14);
	/* R 4 cm, 2500 turns, 850 nm, Earth rate 15 deg/h: 9.0131e-5 rad */
	sscope_model_fog_coil(0.04, 2500, 850e-9, &f);
	ck_assert_rel(sscope_model_fog_phase(&f, 15 * D2R / 3600), 9.01314216e-5,
		      1e-8);
	ck_assert_int_eq(sscope_model_fog_coil(0, 1, 1, &f), -EINVAL);
	ck_assert_int_eq(sscope_model_fog_coil(1, 1, -1, &f), -EINVAL);
}
END_TEST

START_TEST(test_accel_step)
{
	const double zetas[4] = { 0.05, 0.3, 1.0, 2.5 };

	for (int q = 0; q < 4; q++) {
		struct sscope_model_accel m;
		enum { N = 4000 };
		double t[N], xa[N], xr[N], dt, peak = 0;

		ck_assert_int_eq(sscope_model_accel_fn(1234.5, zetas[q], &m), 0);
		dt = 1 / (m.fn_hz * 400);
		for (int i = 0; i < N; i++)
			t[i] = i * dt;
		ck_assert_int_eq(sscope_model_accel_step(&m, 9.80665, t, N, xa), 0);
		ck_assert_int_eq(sscope_model_accel_step_rk4(&m, 9.80665, dt, N, xr),
				 0);
		/* RK4 global error ~ (w dt)^4 = (2 pi / 400)^4 = 6e-8 */
		for (int i = 0; i < N; i++) {
			ck_assert_msg(fabs(xa[i] - xr[i]) <
					      1e-6 * m.displacement_per_g_m,
				      "zeta %g t %g: %g vs %g", zetas[q], t[i],
				      xa[i], xr[i]);
			peak = fmax(peak, xa[i]);
		}
		/* overshoot from the formula vs the response itself */
		if (zetas[q] < 1)
			ck_assert_rel(peak / m.displacement_per_g_m - 1, m.overshoot,
				      1e-4);
		else
			ck_assert(peak <= m.displacement_per_g_m * (1 + 1e-12));
		/* |H| at the bandwidth is 1/sqrt(2) of the static gain */
		{
			double r = m.bandwidth_hz / m.fn_hz;
			double h = 1 / sqrt((1 - r * r) * (1 - r * r) +
					    4 * zetas[q] * zetas[q] * r * r);

			ck_assert_rel(h, 1 / sqrt(2.0), 1e-12);
		}
		/* the step has settled within 2 % after the settling time */
		{
			double x1;
			double ts = m.settling_time_s * 1.0001;

			sscope_model_accel_step(&m, 1, &ts, 1, &x1);
			ck_assert(fabs(x1 * m.omega_n_rad_s * m.omega_n_rad_s - 1) <=
				  0.02);
		}
	}
}
END_TEST

/* The cross-check the command reports: RK4 at 400 steps per period
 * agrees with the analytic response to (w dt)^4 ~ 6e-8 of the static
 * deflection; a step cap lengthens dt to cover the span. */
START_TEST(test_accel_rk4_check)
{
	struct sscope_model_accel m;
	struct sscope_model_rk4_check chk;
	double *x = NULL, T;

	ck_assert_int_eq(sscope_model_accel_fn(812.3, 0.4, &m), 0);
	T = 1.5 * m.settling_time_s;
	ck_assert_int_eq(sscope_model_accel_rk4_check(&m, 9.80665, T, 20000000,
						      &x, &chk), 0);
	ck_assert_rel(chk.dt_s, 1 / (812.3 * 400), 1e-15);
	ck_assert_uint_eq(chk.n, (size_t)ceil(T / chk.dt_s) + 2);
	ck_assert(chk.max_dev_m > 0 && chk.max_dev_m < 1e-6 * m.displacement_per_g_m);
	ck_assert(x[0] == 0);
	free(x);
	ck_assert_int_eq(sscope_model_accel_rk4_check(&m, 9.80665, T, 100, NULL,
						      &chk), 0);
	ck_assert_uint_eq(chk.n, 100);
	ck_assert_rel(chk.dt_s * 98, T, 1e-15);
	ck_assert_int_eq(sscope_model_accel_rk4_check(&m, 9.80665, 0, 100, NULL,
						      &chk), -EINVAL);
}
END_TEST

START_TEST(test_accel_mkc)
{
	struct sscope_model_accel m;

	/* 1 ug proof mass, 1 N/m, c for zeta 0.7 */
	ck_assert_int_eq(sscope_model_accel_mkc(1e-9, 1, 2 * 0.7 * sqrt(1e-9),
						&m), 0);
	ck_assert_rel(m.omega_n_rad_s, sqrt(1e9), 1e-14);
	ck_assert_rel(m.zeta, 0.7, 1e-14);
	/* displacement per g = m g / k */
	ck_assert_rel(m.displacement_per_g_m, 1e-9 * 9.80665, 1e-14);
	ck_assert_rel(m.q_factor, 1 / 1.4, 1e-14);
	/* critically damped: no overshoot, fd undefined; zeta = 1/sqrt2:
	 * bandwidth = fn */
	sscope_model_accel_fn(100, 1, &m);
	ck_assert(m.overshoot == 0 && isnan(m.fd_hz));
	sscope_model_accel_fn(100, sqrt(0.5), &m);
	ck_assert_rel(m.bandwidth_hz, 100, 1e-12);
	ck_assert_int_eq(sscope_model_accel_mkc(-1, 1, 1, &m), -EINVAL);
	ck_assert_int_eq(sscope_model_accel_fn(100, 0, &m), -EINVAL);
	ck_assert_int_eq(sscope_model_accel_step_rk4(&m, 1, 0, 1, NULL), -EINVAL);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("model");
	TCase *tc = tcase_create("core");

	tcase_add_test(tc, test_fog);
	tcase_add_test(tc, test_accel_step);
	tcase_add_test(tc, test_accel_mkc);
	tcase_add_test(tc, test_accel_rk4_check);
	suite_add_tcase(s, tc);
	return s;
}
