/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * ssc_parse_double must be bit-identical to glibc's strtod (correctly
 * rounded) on every input: hard cases from the literature (Paxson, "A
 * program for testing IEEE decimal-binary conversion", 1991; halfway
 * cases), shortest and long representations of random doubles, and random
 * digit strings of every length and exponent.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_rng.h>

#include "check-main.h"
#include "numparse.h"

static void same(const char *s)
{
	double a, b;
	size_t n = ssc_parse_double(s, s + strlen(s), &a);
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
	ck_assert_uint_eq(ssc_parse_double(s, s + strlen(s), &v), 3);
	ck_assert(v == 1.5);
	s = "1e";
	ck_assert_uint_eq(ssc_parse_double(s, s + strlen(s), &v), 1);
	s = "1e+";
	ck_assert_uint_eq(ssc_parse_double(s, s + strlen(s), &v), 1);
	s = "abc";
	ck_assert_uint_eq(ssc_parse_double(s, s + strlen(s), &v), 0);
	s = ".";
	ck_assert_uint_eq(ssc_parse_double(s, s + strlen(s), &v), 0);
	s = "-";
	ck_assert_uint_eq(ssc_parse_double(s, s + strlen(s), &v), 0);
	s = " 1";
	ck_assert_uint_eq(ssc_parse_double(s, s + strlen(s), &v), 0);
	/* not NUL-terminated: stops at end */
	s = "123456";
	ck_assert_uint_eq(ssc_parse_double(s, s + 3, &v), 3);
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
	/* just below a power of two, where the neighbour below is half as
	 * far as the one above: 19 and 18 digits around the lower midpoint */
	for (int e = -80; e <= 80; e++) {
		double d = ldexp(1, e);
		long double below = (long double)d -
				    (long double)(d - nextafter(d, 0)) / 2;

		for (int prec = 16; prec <= 19; prec++) {
			snprintf(buf, sizeof(buf), "%.*Lg", prec, below);
			same(buf);
			snprintf(buf, sizeof(buf), "%.*Lg", prec,
				 (long double)d - (long double)(d - nextafter(d, 0)) / 3);
			same(buf);
			/* nearer the neighbour below than d */
			snprintf(buf, sizeof(buf), "%.*Lg", prec,
				 (long double)d - (long double)(d - nextafter(d, 0)) * 3 / 4);
			same(buf);
		}
	}
	gsl_rng_free(r);
}
END_TEST


/*
 * The known-extent cell parsers of the CSV reader (numparse.h) against
 * strtod: a cell they take must be one ssc_parse_double reads whole,
 * with the same bits and the exact decimal; a cell they refuse is left to
 * ssc_parse_double.  The cell sits at the end of a 16-byte window whose
 * leading bytes are garbage (digits, points, signs), as in a file.
 */
static unsigned long cells_taken;

static void cell_one(const char *cell, size_t len, const char *junk)
{
	char buf[40];
	char *e = buf + 20;
	double v = 0, ref;
	int64_t m = 0;
	int f = 0;
	bool ok;
	char *end, z[32];

	memcpy(buf, junk, 20);
	memcpy(e - len, cell, len);
	memcpy(e, ",9\n", 3);
	memcpy(z, cell, len);
	z[len] = '\0';
	for (int k = 0; k < 2; k++) {
#ifdef SSC_HAVE_PARSE_CELL_SSSE3
		if (k == 1) {
			if (!__builtin_cpu_supports("ssse3"))
				continue;
			ok = ssc_parse_cell_ssse3(e, len, &v, &m, &f);
		} else
#endif
		{
#ifdef SSC_HAVE_PARSE_CELL
			if (k == 1)
				continue;
			ok = ssc_parse_cell(e, len, &v, &m, &f);
#else
			continue;
#endif
		}
		if (!ok)
			continue;
		cells_taken++;
		ref = strtod(z, &end);
		ck_assert_msg(end == z + len && len > 0, "'%s' taken, strtod reads %td",
			      z, end - z);
		ck_assert_msg(memcmp(&v, &ref, sizeof(v)) == 0,
			      "'%s' (parser %d): %.17g != strtod %.17g", z, k, v,
			      ref);
		/* the exact decimal: the digits as written, the count of
		 * digits after the point */
		{
			int64_t em = 0;
			int ef = 0;
			bool point = false;

			for (size_t i = 0; i < len; i++) {
				if (z[i] == '.')
					point = true;
				else if (z[i] >= '0' && z[i] <= '9') {
					em = em * 10 + (z[i] - '0');
					ef += point;
				}
			}
			if (z[0] == '-')
				em = -em;
			ck_assert_msg(m == em && f == ef,
				      "'%s': exact %lld e-%d, expected %lld e-%d",
				      z, (long long)m, f, (long long)em, ef);
		}
	}
}

START_TEST(known_cells)
{
	static const char *const fixed[] = {
		"0", "-0", "+0", "0.0", "-0.000", "5.", ".5", "-.5", "+.5",
		"-5.", "123456789012345", "12345678901234.5",
		"0.00000000000001", "-0.0000000000001", "999999999999999",
		"9007199254740993", "1e5", "1.5e-3", "nan", "-inf", "Infinity",
		".", "-", "+", "-.", "+.", "..5", "1.2.3", "--1", "+-1", "1-",
		" 1", "1 ", "1\r", "\r", "", "0x10", "1,5", "\t2", "1..",
		"3.14159265358979", "-3.1415926535897", "0.1", "0.2", "0.3",
		"1.7976931348623", "4.9406564584124", "00000000000001",
		"-00000000000.01",
	};
	static const char alpha[] = "0123456789.-+e \r\0xn";
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	char junk[20], cell[16];

	gsl_rng_set(r, 15151);
	for (int t = 0; t < 4; t++) {
		for (size_t i = 0; i < sizeof(junk); i++)
			junk[i] = "0123456789.-+,\n"[gsl_rng_uniform_int(r, 15)];
		for (size_t i = 0; i < sizeof(fixed) / sizeof(fixed[0]); i++)
			cell_one(fixed[i], strlen(fixed[i]), junk);
		/* NULs inside */
		cell_one("1\0", 2, junk);
		cell_one("\0", 1, junk);
		cell_one("5\0.5", 4, junk);
		cell_one("-\0", 2, junk);
	}
	/* random cells: mostly digits with a point and a sign, every length
	 * 0-16, every position of the point */
	for (int i = 0; i < 1000000; i++) {
		size_t len = gsl_rng_uniform_int(r, 17);

		for (size_t k = 0; k < sizeof(junk); k++)
			junk[k] = "0123456789.-+,\n"[gsl_rng_uniform_int(r, 15)];
		for (size_t k = 0; k < len; k++)
			cell[k] = (char)('0' + gsl_rng_uniform_int(r, 10));
		if (len && gsl_rng_uniform(r) < 0.8)
			cell[gsl_rng_uniform_int(r, len)] = '.';
		if (len && gsl_rng_uniform(r) < 0.4)
			cell[0] = gsl_rng_uniform(r) < 0.8 ? '-' : '+';
		if (len && gsl_rng_uniform(r) < 0.1)
			cell[gsl_rng_uniform_int(r, len)] =
				alpha[gsl_rng_uniform_int(r, sizeof(alpha) - 1)];
		cell_one(cell, len, junk);
	}
	/* printf's renderings of random doubles that fit */
	for (int i = 0; i < 300000; i++) {
		char buf[64];
		double d = ldexp(gsl_rng_uniform(r) - 0.5,
				 (int)gsl_rng_uniform_int(r, 60) - 40);
		int n;

		n = snprintf(buf, sizeof(buf), "%.*g",
			     1 + (int)gsl_rng_uniform_int(r, 16), d);
		if (n <= 16)
			cell_one(buf, (size_t)n, "00000000000000000000");
		n = snprintf(buf, sizeof(buf), "%.*f",
			     (int)gsl_rng_uniform_int(r, 14), d * 1000);
		if (n <= 16)
			cell_one(buf, (size_t)n, "1.1.1.1.1.1.1.1.1.1.");
	}
	gsl_rng_free(r);
#if defined(SSC_HAVE_PARSE_CELL)
	ck_assert_uint_gt(cells_taken, 500000);
#endif
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
	tcase_add_test(tc, known_cells);
	suite_add_tcase(s, tc);
	return s;
}
