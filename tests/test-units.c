/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Unit parser and conversions against hand-checked values:
 * 1 deg/h = pi/180/3600 rad/s = 4.8481368e-6 rad/s;
 * 1 deg/sqrt(h) = pi/180/60 rad/sqrt(s) = 2.9088821e-4 rad/s/sqrt(Hz);
 * 1 g = 9.80665 m/s^2 (CGPM 1901).
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check-main.h"

static double conv(const char *from, const char *to)
{
	double out = NAN;
	int rc = sscope_unit_convert_text(1.0, from, to, &out);

	ck_assert_msg(rc == 0, "%s -> %s: %d", from, to, rc);
	return out;
}

START_TEST(hand_checked)
{
	ck_assert_rel(conv("deg/h", "rad/s"), 4.8481368110953599e-6, 1e-15);
	ck_assert_rel(conv("deg/sqrt(h)", "rad/s/sqrt(Hz)"), 2.9088820866572158e-4,
		      1e-15);
	ck_assert_rel(conv("g", "m/s^2"), 9.80665, 1e-16);
	ck_assert_rel(conv("mg", "m/s^2"), 9.80665e-3, 1e-15);
	ck_assert_rel(conv("ug", "m/s^2"), 9.80665e-6, 1e-15);
	ck_assert_rel(conv("deg/s", "rad/s"), 0.017453292519943295, 1e-16);
	ck_assert_rel(conv("dps", "deg/s"), 1, 1e-16);
	ck_assert_rel(conv("rpm", "rad/s"), 0.10471975511965977, 1e-15);
	/* K: deg/h/sqrt(h) = pi/180/3600/60 rad/s^1.5 */
	ck_assert_rel(conv("deg/h/sqrt(h)", "rad/s^2/sqrt(Hz)"),
		      8.0802280184922665e-8, 1e-14);
	ck_assert_rel(conv("ug/sqrt(Hz)", "m/s^2/sqrt(Hz)"), 9.80665e-6, 1e-15);
	/* VRW: 1 m/s/sqrt(h) = 1/60 m/s^1.5 */
	ck_assert_rel(conv("m/s/sqrt(h)", "m/s^2/sqrt(Hz)"), 1.0 / 60, 1e-15);
	ck_assert_rel(conv("mV/(deg/s)", "V/(rad/s)"), 0.057295779513082323,
		      1e-15);
	ck_assert_rel(conv("uV/degC", "V/degC"), 1e-6, 1e-15);
	ck_assert_rel(conv("ppm", "1"), 1e-6, 1e-15);
	ck_assert_rel(conv("%", "ppm"), 1e4, 1e-15);
	ck_assert_rel(conv("arcsec", "rad"), 4.8481368110953599e-6, 1e-15);
	ck_assert_rel(conv("ns", "s"), 1e-9, 1e-15);
	ck_assert_rel(conv("kHz", "Hz"), 1e3, 1e-15);
	ck_assert_rel(conv("deg/h/h", "rad/s^2"), 1.3467046697487111e-9, 1e-14);
}
END_TEST

START_TEST(syntax_forms)
{
	/* EuRoC spellings, Unicode, implicit products, exponents */
	ck_assert_rel(conv("rad s^-1", "rad/s"), 1, 1e-16);
	ck_assert_rel(conv("m s^-2", "m/s^2"), 1, 1e-16);
	ck_assert_rel(conv("m/s2", "m/s^2"), 1, 1e-16);
	ck_assert_rel(conv("m/s\xc2\xb2", "m/s^2"), 1, 1e-16);
	ck_assert_rel(conv("\xc2\xb0/s", "deg/s"), 1, 1e-16);
	ck_assert_rel(conv("\xc2\xb5g", "ug"), 1, 1e-16);
	ck_assert_rel(conv("deg/\xe2\x88\x9ah", "deg/sqrt(h)"), 1, 1e-16);
	ck_assert_rel(conv("deg/h^0.5", "deg/sqrt(h)"), 1, 1e-15);
	ck_assert_rel(conv("deg/h^(1/2)", "deg/sqrt(h)"), 1, 1e-15);
	ck_assert_rel(conv("deg*s^-1", "deg/s"), 1, 1e-16);
	ck_assert_rel(conv("deg\xc2\xb7s^-1", "deg/s"), 1, 1e-16);
	ck_assert_rel(conv("1/s", "Hz"), 1, 1e-16);
	ck_assert_rel(conv(" deg / s ", "deg/s"), 1, 1e-16);
}
END_TEST

START_TEST(temperature)
{
	double v;

	ck_assert_int_eq(sscope_unit_convert_text(32, "degF", "degC", &v), 0);
	ck_assert_rel(v + 1, 1, 1e-15);
	ck_assert_int_eq(sscope_unit_convert_text(300, "K", "degC", &v), 0);
	ck_assert_rel(v, 26.85, 1e-14);
	ck_assert_int_eq(sscope_unit_convert_text(25, "\xc2\xb0" "C", "degC", &v), 0);
	ck_assert_rel(v, 25, 1e-16);
	/* in a compound, a temperature is a difference: no offset */
	ck_assert_int_eq(sscope_unit_convert_text(1, "mV/K", "mV/degC", &v), 0);
	ck_assert_rel(v, 1, 1e-16);
	ck_assert_int_eq(sscope_unit_convert_text(9, "ppm/degF", "ppm/degC", &v), 0);
	ck_assert_rel(v, 16.2, 1e-14);
}
END_TEST

START_TEST(errors)
{
	struct sscope_unit u;
	struct sscope_diag d = { "" };
	double v;
	static const char *const bad[] = { "furlong/s", "deg/", "(deg", "deg^x",
					   "sqrt(deg", "deg)", "sqrt(sqrt(h))",
					   "deg^0.3", "s^(1/0)", "m//s" };

	ck_assert_int_eq(sscope_unit_parse("furlong/fortnight", &u, &d), -EINVAL);
	ck_assert_msg(strstr(d.msg, "furlong") != NULL, "%s", d.msg);
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++)
		ck_assert_msg(sscope_unit_parse(bad[i], &u, NULL) == -EINVAL,
			      "'%s' accepted", bad[i]);
	/* an unknown unit names the nearest known spellings (edit distance
	 * <= max(1, length / 3), case-blind first), nothing when none is near */
	ck_assert_int_eq(sscope_unit_parse("degs", &u, &d), -EINVAL);
	ck_assert_str_eq(d.msg, "unknown unit 'degs' (nearest known: deg/s, deg, degC)");
	ck_assert_int_eq(sscope_unit_parse("deg/hh", &u, &d), -EINVAL);
	ck_assert_msg(strstr(d.msg, "unknown unit 'hh' in 'deg/hh' (nearest known: deg/h") != NULL,
		      "%s", d.msg);
	ck_assert_int_eq(sscope_unit_parse("ug/sqrt(hz)", &u, &d), -EINVAL);
	ck_assert_msg(strstr(d.msg, "(nearest known: ug/sqrt(Hz), Hz") != NULL, "%s", d.msg);
	ck_assert_int_eq(sscope_unit_parse("blorbs", &u, &d), -EINVAL);
	ck_assert_str_eq(d.msg, "unknown unit 'blorbs'");
	ck_assert_int_eq(sscope_unit_convert_text(1, "deg/s", "m/s^2", &v), -EDOM);
	ck_assert_int_eq(sscope_unit_convert_text(1, "deg/s", "nonsense", &v), -EINVAL);
}
END_TEST

START_TEST(quantities)
{
	static const struct {
		const char *u;
		enum sscope_quantity q;
	} cases[] = {
		{ "deg/s", SSCOPE_QUANTITY_ANGULAR_RATE },
		{ "rad s^-1", SSCOPE_QUANTITY_ANGULAR_RATE },
		{ "rpm", SSCOPE_QUANTITY_ANGULAR_RATE },
		{ "g", SSCOPE_QUANTITY_ACCELERATION },
		{ "m s^-2", SSCOPE_QUANTITY_ACCELERATION },
		{ "deg", SSCOPE_QUANTITY_ANGLE },
		{ "mV", SSCOPE_QUANTITY_VOLTAGE },
		{ "degC", SSCOPE_QUANTITY_TEMPERATURE },
		{ "ns", SSCOPE_QUANTITY_TIME },
		{ "Hz", SSCOPE_QUANTITY_FREQUENCY },
		{ "counts", SSCOPE_QUANTITY_COUNTS },
		{ "ppm", SSCOPE_QUANTITY_DIMENSIONLESS },
		{ "m/s", SSCOPE_QUANTITY_VELOCITY },
		{ "deg/s^2", SSCOPE_QUANTITY_ANGULAR_ACCEL },
		{ "deg/sqrt(h)", SSCOPE_QUANTITY_UNKNOWN },
	};

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		struct sscope_unit u;

		ck_assert_int_eq(sscope_unit_parse(cases[i].u, &u, NULL), 0);
		ck_assert_msg(sscope_unit_quantity(&u) == cases[i].q, "%s: %s",
			      cases[i].u,
			      sscope_quantity_name(sscope_unit_quantity(&u)));
	}
	ck_assert_str_eq(sscope_quantity_si_unit(SSCOPE_QUANTITY_ANGULAR_RATE), "rad/s");
	ck_assert_str_eq(sscope_quantity_name(SSCOPE_QUANTITY_ACCELERATION),
			 "acceleration");
}
END_TEST

START_TEST(si_strings)
{
	static const struct {
		const char *u, *si;
	} cases[] = {
		{ "deg/sqrt(h)", "rad/s/sqrt(Hz)" },
		{ "deg/h/sqrt(h)", "rad/s^2/sqrt(Hz)" },
		{ "ug/sqrt(Hz)", "m/s^2/sqrt(Hz)" },
		{ "m/s/sqrt(h)", "m/s^2/sqrt(Hz)" },
		{ "deg/h", "rad/s" },
		{ "g", "m/s^2" },
		{ "mV/(deg/s)", "V*s/rad" },
		{ "deg", "rad" },
		{ "ppm", "1" },
		{ "mg/degC", "m/s^2/degC" },
	};
	char buf[64];

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		struct sscope_unit u;

		ck_assert_int_eq(sscope_unit_parse(cases[i].u, &u, NULL), 0);
		ck_assert_int_eq(sscope_unit_si_string(&u, buf, sizeof(buf)), 0);
		ck_assert_str_eq(buf, cases[i].si);
	}
	ck_assert_int_eq(sscope_unit_si_string(&(struct sscope_unit){ 1, 0, { 0 } },
					       buf, 1), -ERANGE);
}
END_TEST

START_TEST(quantity_values)
{
	double v;
	struct sscope_unit u;
	struct sscope_diag d = { "" };

	ck_assert_int_eq(sscope_quantity_parse("0.15 deg/sqrt(h)", &v, &u, NULL), 0);
	ck_assert_rel(v, 0.15 * 2.9088820866572158e-4, 1e-15);
	ck_assert_int_eq(sscope_quantity_parse("-100 deg/s", &v, NULL, NULL), 0);
	ck_assert_rel(v, -1.7453292519943295, 1e-15);
	ck_assert_int_eq(sscope_quantity_parse("2.5", &v, &u, NULL), 0);
	ck_assert_rel(v, 2.5, 1e-16);
	ck_assert(sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS);
	ck_assert_int_eq(sscope_quantity_parse("fast", &v, &u, &d), -EINVAL);
	ck_assert_int_eq(sscope_quantity_parse("3 parsecs", &v, &u, &d), -EINVAL);
	ck_assert_msg(strstr(d.msg, "parsecs") != NULL, "%s", d.msg);
	ck_assert_int_eq(sscope_quantity_parse("nan deg", &v, &u, &d), -EINVAL);
}
END_TEST

START_TEST(strerror_all)
{
	ck_assert_str_eq(sscope_strerror(-EDOM), "data do not fit the request");
	ck_assert_str_eq(sscope_strerror(EBADMSG), "malformed file or frame");
	ck_assert_ptr_nonnull(sscope_strerror(-12345));
	ck_assert_str_eq(sscope_version(), PACKAGE_VERSION);
}
END_TEST

START_TEST(term_units_consistent)
{
	/* every conventional unit converts to its SI unit, and the SI unit
	 * has the dimension of the term: Q = U*s, N = U/sqrt(Hz), B = U,
	 * K = U/s/sqrt(Hz), R = U/s */
	static const char *const suffix[] = { "*s", "/sqrt(Hz)", "", "/s/sqrt(Hz)",
					      "/s", "" };
	static const enum sscope_quantity qs[] = { SSCOPE_QUANTITY_ANGULAR_RATE,
						   SSCOPE_QUANTITY_ACCELERATION };

	for (int i = 0; i < 2; i++)
		for (int t = 0; t < SSCOPE_TERM_COUNT_; t++) {
			char want[64];
			double v;

			snprintf(want, sizeof(want), "%s%s",
				 i ? "m/s^2" : "rad/s", suffix[t]);
			ck_assert_int_eq(sscope_unit_convert_text(1, sscope_term_unit(qs[i], t),
								  sscope_term_si_unit(qs[i], t), &v), 0);
			ck_assert_int_eq(sscope_unit_convert_text(1, sscope_term_si_unit(qs[i], t),
								  want, &v), 0);
			ck_assert_rel(v, 1, 1e-15);
		}
	ck_assert_ptr_null(sscope_term_unit(SSCOPE_QUANTITY_VOLTAGE, SSCOPE_TERM_N));
	ck_assert_str_eq(sscope_term_unit(SSCOPE_QUANTITY_ANGULAR_RATE, SSCOPE_TERM_B), "deg/h");
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("units");
	TCase *tc = tcase_create("units");

	tcase_add_test(tc, hand_checked);
	tcase_add_test(tc, syntax_forms);
	tcase_add_test(tc, temperature);
	tcase_add_test(tc, errors);
	tcase_add_test(tc, quantities);
	tcase_add_test(tc, si_strings);
	tcase_add_test(tc, quantity_values);
	tcase_add_test(tc, strerror_all);
	tcase_add_test(tc, term_units_consistent);
	suite_add_tcase(s, tc);
	return s;
}
