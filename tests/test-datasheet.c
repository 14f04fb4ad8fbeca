/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Datasheet conversions and verdicts (analysis/sscope-datasheet.h): every
 * conversion against a value worked by hand here (the arithmetic is in the
 * comments), the GJB 10 s figure against an independent plain averaging
 * and standard deviation, its interval against printed chi-squared
 * quantiles, and the guard-banded verdicts of simulated white noise.
 */
#include "config.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "check-main.h"
#include "sensorscope.h"

#define D2R (3.14159265358979323846 / 180)

static double rel(double a, double b)
{
	return fabs(a - b) / fabs(b);
}

static double si(const char *text)
{
	double v = NAN;

	ck_assert_int_eq(sscope_quantity_parse(text, &v, NULL, NULL), 0);
	return v;
}

/* datasheet units to SI, by hand */
START_TEST(test_units)
{
	/* 0.3 deg/sqrt(h) = 0.3 * (pi/180) / sqrt(3600 s) = 0.3 * 0.0174533 / 60
	 * = 8.72665e-5 rad/sqrt(s) */
	ck_assert(rel(si("0.3 deg/sqrt(h)"), 0.3 * D2R / 60) < 1e-14);
	ck_assert(rel(si("0.3 deg/sqrt(h)"), 8.726646259971648e-5) < 1e-12);
	/* 0.005 deg/s/sqrt(Hz) is the same N: 0.005 * 60 = 0.3 deg/sqrt(h) */
	ck_assert(rel(si("0.005 deg/s/sqrt(Hz)"), 8.726646259971648e-5) < 1e-12);
	/* 100 ug/sqrt(Hz) = 100e-6 * 9.80665 = 9.80665e-4 m/s^2/sqrt(Hz) */
	ck_assert(rel(si("100 ug/sqrt(Hz)"), 9.80665e-4) < 1e-12);
	/* 0.23 mg/sqrt(Hz) = 0.23e-3 * 9.80665 = 2.2555295e-3 */
	ck_assert(rel(si("0.23 mg/sqrt(Hz)"), 2.2555295e-3) < 1e-12);
	/* 0.06 m/s/sqrt(h) = 0.06 / 60 = 1e-3 m/s^2/sqrt(Hz) (STIM300 VRW) */
	ck_assert(rel(si("0.06 m/s/sqrt(h)"), 1e-3) < 1e-12);
	/* 10 deg/h/sqrt(h) = 10 * (pi/180) / 3600 / 60 = 8.08023e-7 rad/s^1.5 */
	ck_assert(rel(si("10 deg/h/sqrt(h)"), 8.080228018492270e-7) < 1e-12);
	/* 0.5 deg/h = 0.5 * (pi/180) / 3600 = 2.42407e-6 rad/s */
	ck_assert(rel(si("0.5 deg/h"), 2.424068405547680e-6) < 1e-12);
	/* 500 ppm = 5e-4; 3 % = 0.03 */
	ck_assert(rel(si("500 ppm"), 5e-4) < 1e-14);
	ck_assert(rel(si("3 %"), 0.03) < 1e-14);
}
END_TEST

/* line value = f * term, by hand */
START_TEST(test_factors)
{
	double f = 0, n;

	/* rms over W: MPU-6000, 0.05 deg/s rms over 100 Hz: f = sqrt(100) = 10,
	 * N = 0.05 / 10 = 0.005 deg/s/sqrt(Hz), the density it states */
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_RMS_NOISE, 100, &f), 0);
	ck_assert(rel(f, 10) < 1e-15);
	n = 0.05 / f;
	ck_assert(rel(n, 0.005) < 1e-15);
	/* Allan minimum: f = sqrt(2 ln2 / pi) = sqrt(1.386294 / 3.141593) =
	 * sqrt(0.4412712) = 0.6642825; STIM300 0.5 deg/h -> B = 0.5 / 0.6642825 =
	 * 0.7526918 deg/h */
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_ALLAN_MINIMUM, 0, &f), 0);
	ck_assert(rel(f, sqrt(2 * log(2.0) / 3.14159265358979323846)) < 1e-15);
	ck_assert(rel(0.5 / f, 0.7526918) < 1e-7);
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_NOISE_DENSITY, 0, &f), 0);
	ck_assert(f == 1);
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_RANDOM_WALK, 0, &f), 0);
	ck_assert(f == 1);
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_BIAS_INSTABILITY, 0, &f), 0);
	ck_assert(f == 1);
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_RATE_RANDOM_WALK, 0, &f), 0);
	ck_assert(f == 1);
	/* no term, or no bandwidth */
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_GJB_10S, 0, &f), -EINVAL);
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_SCALE_FACTOR, 0, &f), -EINVAL);
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_RMS_NOISE, 0, &f), -EINVAL);
	ck_assert_int_eq(sscope_datasheet_factor(SSCOPE_DATASHEET_RMS_NOISE, NAN, &f), -EINVAL);
}
END_TEST

/* the GJB figure the terms imply, by hand */
START_TEST(test_gjb_from_terms)
{
	double n = 0.15 * D2R / 60;
	double b = 0.5 / sqrt(2 * log(2.0) / 3.14159265358979323846) * D2R / 3600;
	double v;

	/* STIM300 gyro: N = 0.15 deg/sqrt(h) = 0.0025 deg/s/sqrt(Hz); at 10 s
	 * N / sqrt(10) = 7.90569e-4 deg/s = 2.846050 deg/h; the flicker part is
	 * 0.6643 B = the Allan minimum 0.5 deg/h; sqrt(2.846050^2 + 0.5^2) =
	 * sqrt(8.100000 + 0.25) = 2.889637 deg/h */
	v = sscope_datasheet_gjb_from_terms(n, b, NAN, 10) / D2R * 3600;
	ck_assert(rel(v, 2.889637) < 1e-6);
	/* K alone at tau = 3 s: K^2 tau / 3 = K^2, so the value is K */
	ck_assert(rel(sscope_datasheet_gjb_from_terms(NAN, NAN, 2.5, 3), 2.5) < 1e-15);
	/* N alone at 100 s: N / 10 */
	ck_assert(rel(sscope_datasheet_gjb_from_terms(0.7, NAN, NAN, 100), 0.07) < 1e-15);
	ck_assert(isnan(sscope_datasheet_gjb_from_terms(NAN, NAN, NAN, 10)));
	ck_assert(isnan(sscope_datasheet_gjb_from_terms(1, 1, 1, 0)));
}
END_TEST

static double *record(size_t n, double fs, double sigma, double bias,
		      double k, unsigned long seed)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double *x = malloc(n * sizeof(*x)), w = 0;

	ck_assert_ptr_nonnull(x);
	gsl_rng_set(r, seed);
	for (size_t i = 0; i < n; i++) {
		w += k * sqrt(1 / fs) * gsl_ran_gaussian_ziggurat(r, 1);
		x[i] = bias + w + gsl_ran_gaussian_ziggurat(r, sigma);
	}
	gsl_rng_free(r);
	return x;
}

/* the 1 sigma of 10 s means against plain averaging and a standard
 * deviation written out here, to 1e-12 relative */
START_TEST(test_gjb_plain)
{
	const double fs = 100;
	const size_t n = 123457; /* 123 full 10 s means, a partial one dropped */
	double *x = record(n, fs, 0.0123, 1.7e-3, 2e-5, 11);
	struct sscope_datasheet_gjb g;
	double means[200], mean = 0, ss = 0, sd;
	size_t nb = 0;

	ck_assert_int_eq(sscope_datasheet_gjb(x, 1, n, fs, 10, 0.95, &g, NULL), 0);
	for (size_t b = 0; (b + 1) * 1000 <= n; b++, nb++) {
		double s = 0;

		for (size_t i = 0; i < 1000; i++)
			s += x[b * 1000 + i];
		means[b] = s / 1000;
	}
	ck_assert_uint_eq(nb, 123);
	for (size_t b = 0; b < nb; b++)
		mean += means[b];
	mean /= (double)nb;
	for (size_t b = 0; b < nb; b++)
		ss += (means[b] - mean) * (means[b] - mean);
	sd = sqrt(ss / (double)(nb - 1));
	ck_assert_uint_eq(g.n_means, 123);
	ck_assert_uint_eq(g.m, 1000);
	ck_assert_msg(rel(g.value, sd) < 1e-12, "%.17g vs %.17g", g.value, sd);
	ck_assert(g.lo < g.value && g.value < g.hi);
	/* every second sample (stride 2) at 50 Hz: the same 10 s blocks */
	{
		struct sscope_datasheet_gjb h;

		ck_assert_int_eq(sscope_datasheet_gjb(x, 2, n / 2, fs / 2, 10, 0.95, &h,
							NULL), 0);
		ck_assert_uint_eq(h.m, 500);
	}
	free(x);
}
END_TEST

/* the interval against printed chi-squared quantiles: 11 means (10
 * degrees of freedom), 95 %: chi2(0.975, 10) = 20.483, chi2(0.025, 10) =
 * 3.247, so lo = s sqrt(10 / 20.483) = 0.69872 s and hi = s sqrt(10 /
 * 3.247) = 1.75494 s */
START_TEST(test_gjb_interval)
{
	double x[11];
	struct sscope_datasheet_gjb g;

	for (int i = 0; i < 11; i++)
		x[i] = (i % 3) * 0.25 - (i % 2) * 0.5; /* 1 sample per mean */
	ck_assert_int_eq(sscope_datasheet_gjb(x, 1, 11, 1, 1, 0.95, &g, NULL), 0);
	ck_assert_uint_eq(g.n_means, 11);
	ck_assert(rel(g.lo / g.value, 0.69872) < 1e-4);
	ck_assert(rel(g.hi / g.value, 1.75494) < 1e-4);
}
END_TEST

START_TEST(test_gjb_errors)
{
	double x[30] = { 0 };
	struct sscope_datasheet_gjb g;
	struct sscope_diag d = { "" };

	/* 30 samples at 2 Hz hold one 10 s mean */
	ck_assert_int_eq(sscope_datasheet_gjb(x, 1, 30, 2, 10, 0.95, &g, &d), -EDOM);
	ck_assert(d.msg[0]);
	x[3] = NAN;
	ck_assert_int_eq(sscope_datasheet_gjb(x, 1, 30, 10, 1, 0.95, &g, NULL), -EDOM);
	ck_assert_int_eq(sscope_datasheet_gjb(x, 1, 30, 10, 1, 1, &g, NULL), -EINVAL);
	ck_assert_int_eq(sscope_datasheet_gjb(x, 1, 30, 10, 0, 0.9, &g, NULL), -EINVAL);
	ck_assert_int_eq(sscope_datasheet_gjb(x, 1, 30, 0, 1, 0.9, &g, NULL), -EINVAL);
	ck_assert_int_eq(sscope_datasheet_gjb(NULL, 1, 30, 10, 1, 0.9, &g, NULL), -EINVAL);
}
END_TEST

START_TEST(test_verdict)
{
	ck_assert_int_eq(sscope_datasheet_verdict(0.8, 0.9, 1), SSCOPE_DATASHEET_WITHIN);
	ck_assert_int_eq(sscope_datasheet_verdict(1.1, 1.2, 1), SSCOPE_DATASHEET_OUT);
	ck_assert_int_eq(sscope_datasheet_verdict(0.9, 1.1, 1), SSCOPE_DATASHEET_INCONCLUSIVE);
	ck_assert_int_eq(sscope_datasheet_verdict(0, 0.9, 1), SSCOPE_DATASHEET_WITHIN);
	ck_assert_int_eq(sscope_datasheet_verdict(0, INFINITY, 1),
			 SSCOPE_DATASHEET_INCONCLUSIVE);
	ck_assert_int_eq(sscope_datasheet_verdict(NAN, NAN, 1), SSCOPE_DATASHEET_INCONCLUSIVE);
	ck_assert_str_eq(sscope_datasheet_verdict_name(SSCOPE_DATASHEET_WITHIN), "within spec");
	ck_assert_str_eq(sscope_datasheet_verdict_name(SSCOPE_DATASHEET_OUT), "out of spec");
	ck_assert_str_eq(sscope_datasheet_verdict_name(SSCOPE_DATASHEET_INCONCLUSIVE),
			 "inconclusive");
}
END_TEST

START_TEST(test_info)
{
	for (int l = 0; l < SSCOPE_DATASHEET_LINE_COUNT_; l++) {
		const struct sscope_datasheet_info *in = sscope_datasheet_info(l);

		ck_assert_ptr_nonnull(in);
		ck_assert_int_eq(sscope_datasheet_line_by_key(in->key), l);
	}
	ck_assert_ptr_null(sscope_datasheet_info(SSCOPE_DATASHEET_LINE_COUNT_));
	ck_assert_int_eq(sscope_datasheet_line_by_key("noise"), -1);
	ck_assert(sscope_datasheet_info(SSCOPE_DATASHEET_GJB_100S)->tau_s == 100);
}
END_TEST

/* white noise of known N = sigma / sqrt(fs): verdicts against limits at
 * 0.8 N (out) and 1.25 N (within); the relative sd of N from 60000
 * samples is about 1/sqrt(2 * 60000) = 0.3 %, so a 99 % interval is a
 * few tenths of a per cent wide */
START_TEST(test_check)
{
	const double fs = 100, sigma = 0.01;
	const size_t n = 60000;
	double *x = record(n, fs, sigma, 0.02, 0, 5);
	double nn = sigma / sqrt(fs);
	struct sscope_datasheet_spec spec[6] = {
		{ SSCOPE_DATASHEET_NOISE_DENSITY, 0.8 * nn, 0 },
		{ SSCOPE_DATASHEET_RMS_NOISE, 1.25 * nn * sqrt(50.0), 50 },
		{ SSCOPE_DATASHEET_GJB_10S, 1.25 * nn / sqrt(10.0), 0 },
		{ SSCOPE_DATASHEET_RUN_TO_RUN_BIAS, 1e-3, 0 },
		{ SSCOPE_DATASHEET_RATE_RANDOM_WALK, 1e-12, 0 },
		{ SSCOPE_DATASHEET_SCALE_FACTOR, 1e-3, 0 },
	};
	struct sscope_datasheet_check c[6];
	struct sscope_datasheet_gjb g;
	struct sscope_datasheet_opts o = { 0 };

	ck_assert_int_eq(sscope_datasheet_check(x, 1, n, fs, spec, 6, &o, c, NULL), 0);
	ck_assert_int_eq(c[0].verdict, SSCOPE_DATASHEET_OUT);
	ck_assert(rel(c[0].value, nn) < 0.02);
	ck_assert(c[0].lo < c[0].value && c[0].value < c[0].hi);
	ck_assert_int_eq(c[1].verdict, SSCOPE_DATASHEET_WITHIN);
	ck_assert(rel(c[1].value, nn * sqrt(50.0)) < 0.02);
	/* the GJB line is sscope_datasheet_gjb() at the default 99 % */
	ck_assert_int_eq(sscope_datasheet_gjb(x, 1, n, fs, 10, 0.99, &g, NULL), 0);
	ck_assert(c[2].value == g.value && c[2].hi == g.hi);
	/* 60 means: sd of the sd about 9 %; 1.25 is above the 99 % interval
	 * in most records, and never below it */
	ck_assert_int_ne(c[2].verdict, SSCOPE_DATASHEET_OUT);
	/* nothing measured: never a 0 */
	ck_assert_int_eq(c[3].verdict, SSCOPE_DATASHEET_INCONCLUSIVE);
	ck_assert(isnan(c[3].value) && c[3].why);
	ck_assert_int_eq(c[5].verdict, SSCOPE_DATASHEET_INCONCLUSIVE);
	ck_assert(isnan(c[5].value) && c[5].why);
	/* white noise has no K: a bound above 0, the limit far below it */
	ck_assert(c[4].bound && isnan(c[4].value) && c[4].hi > 0 && c[4].why);
	ck_assert_int_eq(c[4].verdict, SSCOPE_DATASHEET_INCONCLUSIVE);
	/* white noise: the five-term model describes it */
	ck_assert(!c[0].fit_rejected && !c[1].fit_rejected);
	o.level = 1.5;
	ck_assert_int_eq(sscope_datasheet_check(x, 1, n, fs, spec, 6, &o, c, NULL), -EINVAL);
	free(x);
}
END_TEST

/* a tone of 40 s period well above the noise is outside the five-term
 * model: the N line is flagged, the GJB line (no fit) is not */
START_TEST(test_check_rejected)
{
	const double fs = 100, sigma = 0.01;
	const size_t n = 60000;
	double *x = record(n, fs, sigma, 0, 0, 9);
	struct sscope_datasheet_spec spec[2] = {
		{ SSCOPE_DATASHEET_NOISE_DENSITY, sigma / sqrt(fs), 0 },
		{ SSCOPE_DATASHEET_GJB_10S, 1, 0 },
	};
	struct sscope_datasheet_check c[2];

	for (size_t i = 0; i < n; i++)
		x[i] += 0.01 * sin(2 * 3.14159265358979323846 * (double)i / fs / 40);
	ck_assert_int_eq(sscope_datasheet_check(x, 1, n, fs, spec, 2, NULL, c, NULL), 0);
	ck_assert(c[0].fit_rejected);
	ck_assert(!c[1].fit_rejected);
	free(x);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("datasheet");
	TCase *tc = tcase_create("core");

	tcase_add_test(tc, test_units);
	tcase_add_test(tc, test_factors);
	tcase_add_test(tc, test_gjb_from_terms);
	tcase_add_test(tc, test_gjb_plain);
	tcase_add_test(tc, test_gjb_interval);
	tcase_add_test(tc, test_gjb_errors);
	tcase_add_test(tc, test_verdict);
	tcase_add_test(tc, test_info);
	tcase_add_test(tc, test_check);
	tcase_add_test(tc, test_check_rejected);
	tcase_set_timeout(tc, 60);
	suite_add_tcase(s, tc);
	return s;
}
