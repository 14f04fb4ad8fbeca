/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The recording planner (analysis/plan.c): every documented error; a term
 * the model lacks is never reached; the needed length is where the
 * predicted probability crosses the wanted one, and a looser width or a
 * lower probability needs less; and against simulation (the oracle of
 * tests/plan-sim.h, the fast version of tests/bench-plan.c): at the
 * lengths planned for 50 % and 90 % of a MEMS gyro's B to 10 % at 2 Hz
 * (its own plan), the fraction of 100 simulated and fitted records that get
 * there is within 10 points plus 3 binomial sd of the prediction.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>

#include "check-main.h"
#include "plan-sim.h"

#define DEG (M_PI / 180)

/* samples/gyro-mems-250.ini: N 0.2 deg/sqrt(h), B 4 deg/h,
 * K 20 deg/h/sqrt(h) */
static const double mems[5] = { 0, 0.2 * DEG / 60, 4 * DEG / 3600,
				20 * DEG / 3600 / 60, 0 };

START_TEST(errors)
{
	struct sscope_plan_point p;
	struct sscope_plan_opts o = { 0 };
	double c[5], L;

	ck_assert_int_eq(sscope_plan_predict(NULL, 10, 3600, SSCOPE_TERM_B, 0.2,
					     NULL, &p), -EINVAL);
	ck_assert_int_eq(sscope_plan_predict(mems, 10, 3600, SSCOPE_TERM_B, 0.2,
					     NULL, NULL), -EINVAL);
	ck_assert_int_eq(sscope_plan_needed(mems, 10, SSCOPE_TERM_B, 0.2, NULL,
					    NULL), -EINVAL);
	ck_assert_int_eq(sscope_plan_predict(mems, 0, 3600, SSCOPE_TERM_B, 0.2,
					     NULL, &p), -EINVAL);
	ck_assert_int_eq(sscope_plan_predict(mems, 10, 0, SSCOPE_TERM_B, 0.2,
					     NULL, &p), -EINVAL);
	ck_assert_int_eq(sscope_plan_predict(mems, 10, NAN, SSCOPE_TERM_B, 0.2,
					     NULL, &p), -EINVAL);
	ck_assert_int_eq(sscope_plan_predict(mems, 10, 3600, SSCOPE_TERM_RATE,
					     0.2, NULL, &p), -EINVAL);
	ck_assert_int_eq(sscope_plan_predict(mems, 10, 3600, SSCOPE_TERM_B, 0,
					     NULL, &p), -EINVAL);
	for (int k = 0; k < 2; k++) {
		for (int j = 0; j < 5; j++)
			c[j] = mems[j];
		c[2] = k ? (double)NAN : -mems[2];
		ck_assert_int_eq(sscope_plan_predict(c, 10, 3600, SSCOPE_TERM_B,
						     0.2, NULL, &p), -EINVAL);
	}
	o.ci_level = 1.5;
	ck_assert_int_eq(sscope_plan_needed(mems, 10, SSCOPE_TERM_B, 0.2, &o, &L),
			 -EINVAL);
	o.ci_level = 0;
	o.probability = 1;
	ck_assert_int_eq(sscope_plan_needed(mems, 10, SSCOPE_TERM_B, 0.2, &o, &L),
			 -EINVAL);
	o.probability = 0;
	o.max_length_s = -1;
	ck_assert_int_eq(sscope_plan_needed(mems, 10, SSCOPE_TERM_B, 0.2, &o, &L),
			 -EINVAL);
}
END_TEST

START_TEST(absent_term)
{
	struct sscope_plan_point p;
	double L = 0;

	/* R is 0 in the model: never, probabilities 0 */
	ck_assert_int_eq(sscope_plan_needed(mems, 10, SSCOPE_TERM_R, 0.3, NULL, &L),
			 0);
	ck_assert(isinf(L));
	ck_assert_int_eq(sscope_plan_predict(mems, 10, 86400, SSCOPE_TERM_R, 0.3,
					     NULL, &p), 0);
	ck_assert(p.probability == 0 && p.p_present == 0 && p.p_width == 0);
	/* a width the longest record considered cannot reach: never */
	{
		struct sscope_plan_opts o = { 0 };

		o.max_length_s = 600;
		ck_assert_int_eq(sscope_plan_needed(mems, 10, SSCOPE_TERM_K, 0.1,
						    &o, &L), 0);
		ck_assert(isinf(L));
	}
}
END_TEST

START_TEST(needed_is_the_crossing)
{
	struct sscope_plan_opts o = { 0 };
	struct sscope_plan_point a, b;
	double L, L_loose, L_half;

	ck_assert_int_eq(sscope_plan_needed(mems, 10, SSCOPE_TERM_B, 0.1, NULL, &L),
			 0);
	ck_assert(isfinite(L) && L > 0);
	ck_assert_int_eq(sscope_plan_predict(mems, 10, L, SSCOPE_TERM_B, 0.1, NULL,
					     &a), 0);
	ck_assert_int_eq(sscope_plan_predict(mems, 10, L / 1.02, SSCOPE_TERM_B,
					     0.1, NULL, &b), 0);
	ck_assert_msg(a.probability >= 0.9 && b.probability < 0.9,
		      "P(%g s) = %g, P(%g s) = %g", L, a.probability, L / 1.02,
		      b.probability);
	ck_assert(a.probability <= a.p_present && a.probability <= a.p_width);
	ck_assert_int_eq(sscope_plan_needed(mems, 10, SSCOPE_TERM_B, 0.2, NULL,
					    &L_loose), 0);
	o.probability = 0.5;
	ck_assert_int_eq(sscope_plan_needed(mems, 10, SSCOPE_TERM_B, 0.1, &o,
					    &L_half), 0);
	ck_assert(L_loose < L && L_half < L);
}
END_TEST

/* the fraction of simulated records against the plan */
static void against_sim(double prob, uint64_t seed)
{
	const double fs = 2, target = 0.10;
	const int records = 100;
	struct sscope_plan_opts o = { 0 };
	struct sscope_plan_point p;
	double L, f, tol;

	o.probability = prob;
	ck_assert_int_eq(sscope_plan_needed(mems, fs, SSCOPE_TERM_B, target, &o,
					    &L), 0);
	ck_assert(isfinite(L));
	ck_assert_int_eq(sscope_plan_predict(mems, fs, L, SSCOPE_TERM_B, target,
					     NULL, &p), 0);
	f = plan_sim_fraction(mems, fs, L, SSCOPE_TERM_B, target, records, seed);
	ck_assert(isfinite(f));
	tol = 0.10 + 3 * sqrt(p.probability * (1 - p.probability) / records);
	ck_assert_msg(fabs(f - p.probability) <= tol,
		      "%.0f s: predicted %.3f, simulated %.3f (tolerance %.3f)", L,
		      p.probability, f, tol);
}

START_TEST(simulation_at_50)
{
	against_sim(0.5, 424242);
}
END_TEST

START_TEST(simulation_at_90)
{
	against_sim(0.9, 535353);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("plan");
	TCase *tc = tcase_create("plan");
	TCase *sim = tcase_create("simulation");

	tcase_set_timeout(tc, 60);
	tcase_add_test(tc, errors);
	tcase_add_test(tc, absent_term);
	tcase_add_test(tc, needed_is_the_crossing);
	suite_add_tcase(s, tc);
	tcase_set_timeout(sim, 300);
	tcase_add_test(sim, simulation_at_50);
	tcase_add_test(sim, simulation_at_90);
	suite_add_tcase(s, sim);
	return s;
}
