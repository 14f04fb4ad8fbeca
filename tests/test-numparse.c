/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sscope_parse_double must be bit-identical to glibc's strtod (correctly
 * rounded) on every input: hard cases from the literature (Paxson, "A
 * program for testing IEEE decimal-binary conversion", 1991; halfway
 * cases), shortest and long representations of random doubles, and random
 * digit strings of every length and exponent.
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_rng.h>

#include "check-main.h"

static void same(const char *s)
{
	double a, b;
	size_t n = sscope_parse_double(s, s + strlen(s), &a);
	char *end;

	b = strtod(s, &end);
	ck_assert_msg(n == (size_t)(end - s), "'%s': consumed %zu, strtod %td", s,
		      n, end - s);
	if (isnan(a) && isnan(b))
		return;
	ck_assert_msg(memcmp(&a, &b, sizeof(a)) == 0,
		      "'%s': %.17g != strtod %.17g", s, a, b);
}

START_TEST(hard_cases)
{
	static const char *const cases[] = {
		"0", "-0", "0.0", "1", "-1", "0.1", "0.2", "0.3", "1e23",
		"8.988465674311579e+307", "1.7976931348623157e308", "1e309",
		"2.2250738585072011e-308", "2.2250738585072014e-308", "4.9e-324",
		"2e-324", "1e-400", "9007199254740993", "9007199254740992",
		"9007199254740994", "9007199254740995", "18014398509481985",
		"123456789012345678901234567890", "0.000000000000000000001",
		"1.00000000000000011102230246251565404236316680908203125",
		"1.00000000000000011102230246251565404236316680908203124",
		"1.00000000000000011102230246251565404236316680908203126",
		"7.038531e-26", "9214843084008499", "30078505129381147446200",
		"1.2345678901234567e-5", "5e-1", "12.5e+2", ".5", "5.", "+3.25",
		"1403636579758555392", "1403636579.758555392", "3.0e22",
		"4.35679114e21", "1e22", "1e-22", "1e27", "1e-27", "1e28",
		"NaN", "nan", "-nan", "inf", "-Infinity", "INF",
		"0.000001234567890123456789", "89255.0e-22", "2.4e-0",
		"358416272e-33", "4.9406564584124654e-324",
	};

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++)
		same(cases[i]);
}
END_TEST

START_TEST(partial_and_invalid)
{
	double v;
	const char *s;

	s = "1.5abc";
	ck_assert_uint_eq(sscope_parse_double(s, s + strlen(s), &v), 3);
	ck_assert(v == 1.5);
	s = "1e";
	ck_assert_uint_eq(sscope_parse_double(s, s + strlen(s), &v), 1);
	s = "1e+";
	ck_assert_uint_eq(sscope_parse_double(s, s + strlen(s), &v), 1);
	s = "abc";
	ck_assert_uint_eq(sscope_parse_double(s, s + strlen(s), &v), 0);
	s = ".";
	ck_assert_uint_eq(sscope_parse_double(s, s + strlen(s), &v), 0);
	s = "-";
	ck_assert_uint_eq(sscope_parse_double(s, s + strlen(s), &v), 0);
	s = " 1";
	ck_assert_uint_eq(sscope_parse_double(s, s + strlen(s), &v), 0);
	/* not NUL-terminated: stops at end */
	s = "123456";
	ck_assert_uint_eq(sscope_parse_double(s, s + 3, &v), 3);
	ck_assert(v == 123);
}
END_TEST

START_TEST(random_doubles)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	char buf[64];

	gsl_rng_set(r, 20261122);
	for (int i = 0; i < 300000; i++) {
		uint64_t bits = ((uint64_t)gsl_rng_get(r) << 32) ^ gsl_rng_get(r);
		double d;
		int prec = 1 + (int)gsl_rng_uniform_int(r, 17);

		memcpy(&d, &bits, sizeof(d));
		if (!isfinite(d))
			continue;
		snprintf(buf, sizeof(buf), "%.*g", prec, d);
		same(buf);
		snprintf(buf, sizeof(buf), "%.*f", prec,
			 fmod(d, 1e6) == fmod(d, 1e6) ? fmod(d, 1e6) : 0);
		same(buf);
	}
	gsl_rng_free(r);
}
END_TEST

START_TEST(random_digits)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	char buf[96];

	gsl_rng_set(r, 314159);
	for (int i = 0; i < 300000; i++) {
		int nd = 1 + (int)gsl_rng_uniform_int(r, 25), p = 0;
		int dot = (int)gsl_rng_uniform_int(r, (unsigned long)nd + 1);
		int e = (int)gsl_rng_uniform_int(r, 81) - 40;

		if (gsl_rng_uniform(r) < 0.3)
			buf[p++] = '-';
		for (int k = 0; k < nd; k++) {
			if (k == dot)
				buf[p++] = '.';
			buf[p++] = (char)('0' + gsl_rng_uniform_int(r, 10));
		}
		if (gsl_rng_uniform(r) < 0.7)
			p += snprintf(buf + p, sizeof(buf) - (size_t)p, "e%d", e);
		buf[p] = '\0';
		same(buf);
	}
	gsl_rng_free(r);
}
END_TEST

START_TEST(halfway_near)
{
	/* decimal strings at and next to exact double midpoints, where the
	 * extended-precision path must defer to strtod */
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	char buf[96];

	gsl_rng_set(r, 2718);
	for (int i = 0; i < 20000; i++) {
		double d = ldexp(gsl_rng_uniform(r) + 1, (int)gsl_rng_uniform_int(r, 120) - 60);
		long double mid = (long double)d +
				  (long double)(nextafter(d, INFINITY) - d) / 2;

		snprintf(buf, sizeof(buf), "%.25Lg", mid);
		same(buf);
		snprintf(buf, sizeof(buf), "%.19Lg", mid);
		same(buf);
		snprintf(buf, sizeof(buf), "%.18Lg", mid);
		same(buf);
	}
	gsl_rng_free(r);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("numparse");
	TCase *tc = tcase_create("numparse");

	tcase_add_test(tc, hard_cases);
	tcase_add_test(tc, partial_and_invalid);
	tcase_add_test(tc, random_doubles);
	tcase_add_test(tc, random_digits);
	tcase_add_test(tc, halfway_near);
	suite_add_tcase(s, tc);
	return s;
}
