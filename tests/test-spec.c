/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * INI parsing and the sensor specification: values with units converted to
 * SI (hand-checked), gyro/accelerometer detection, and every refusal with
 * its file, line and key.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <string.h>

#include "check-main.h"

static int parse(const char *text, struct ssc_ini **ini,
		 struct sscope_diag *d)
{
	d->msg[0] = '\0';
	return ssc_ini_parse(ini, text, strlen(text), "t.ini", d);
}

START_TEST(ini_basics)
{
	struct ssc_ini *ini;
	struct sscope_diag d;
	size_t line;
	const char *v;
	double x;
	long k;

	ck_assert_int_eq(parse("# comment\n; also\n[Sensor]\nName = My gyro  # trailing\n"
			       "range: 250 deg/s\n\n[adc]\nbits = 16\n",
			       &ini, &d), 0);
	ck_assert_uint_eq(ssc_ini_n_sections(ini), 2);
	ck_assert_str_eq(ssc_ini_section(ini, 1, &line), "adc");
	ck_assert_uint_eq(line, 7);
	v = ssc_ini_get(ini, "sensor", "name", &line);
	ck_assert_str_eq(v, "My gyro");
	ck_assert_uint_eq(line, 4);
	ck_assert_int_eq(ssc_ini_quantity(ini, "sensor", "range", "rad/s", &x, &d), 0);
	ck_assert_rel(x, 250 * 0.017453292519943295, 1e-15);
	ck_assert_int_eq(ssc_ini_quantity(ini, "sensor", "absent", "rad/s", &x, &d),
			 -ENOENT);
	ck_assert_int_eq(ssc_ini_quantity(ini, "sensor", "range", "m/s^2", &x, &d),
			 -EINVAL);
	ck_assert_msg(strstr(d.msg, "t.ini: line 5: range = 250 deg/s: wrong unit") != NULL,
		      "%s", d.msg);
	ck_assert_int_eq(ssc_ini_integer(ini, "adc", "bits", 1, 32, &k, &d), 0);
	ck_assert_int_eq(k, 16);
	ck_assert_int_eq(ssc_ini_integer(ini, "adc", "bits", 1, 8, &k, &d), -EINVAL);
	ck_assert_int_eq(ssc_ini_check_keys(ini, "sensor",
					    (const char *const[]){ "name", NULL }, &d),
			 -EINVAL);
	ck_assert_msg(strstr(d.msg, "line 5: unknown key 'range' in [Sensor]") != NULL,
		      "%s", d.msg);
	ssc_ini_free(ini);
	/* a UTF-8 byte-order mark (Windows editors) before the first line */
	ck_assert_int_eq(parse("\xef\xbb\xbf[sensor]\nname = g\n", &ini, &d), 0);
	ck_assert_str_eq(ssc_ini_get(ini, "sensor", "name", &line), "g");
	ck_assert_uint_eq(line, 2);
	ssc_ini_free(ini);
}
END_TEST

START_TEST(ini_errors)
{
	static const struct {
		const char *text, *needle;
	} cases[] = {
		{ "[a\nx=1\n", "line 1: section header without ']'" },
		{ "x = 1\n", "line 1: key outside any [section]" },
		{ "[a]\njust words\n", "line 2: expected 'key = value'" },
		{ "[a]\nx=1\nX=2\n", "line 3: key 'X' repeats line 2" },
		{ "[a]\n[A]\n", "line 2: section [A] repeats line 1" },
		{ "[a]\n = 3\n", "line 2: empty key" },
	};

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		struct ssc_ini *ini = NULL;
		struct sscope_diag d;

		ck_assert_int_eq(parse(cases[i].text, &ini, &d), -EBADMSG);
		ck_assert_msg(strstr(d.msg, cases[i].needle) != NULL, "%zu: %s", i,
			      d.msg);
		ck_assert_ptr_null(ini);
	}
}
END_TEST

START_TEST(sensor_gyro)
{
	struct ssc_ini *ini;
	struct sscope_diag d;
	struct sscope_sensor_spec s;

	ck_assert_int_eq(parse("[sensor]\nname = textbook gyro\nrange = 100 deg/s\n"
			       "noise_density = 0.15 deg/sqrt(h)\n"
			       "bias_instability = 1 deg/h\n"
			       "rate_random_walk = 0.5 deg/h/sqrt(h)\n"
			       "quantization = 2 arcsec\nrate_ramp = 3 deg/h/h\n"
			       "bias = -0.2 deg/s\nscale_factor_error = 300\n"
			       "bias_tempco = 0.01 deg/s/degC\ntemp_min = -40 degC\n"
			       "temp_max = 85\nsensitivity = 6 mV/(deg/s)\n"
			       "zero_output = 2.5 V\nbandwidth = 40 Hz\nfilter_order = 2\n",
			       &ini, &d), 0);
	ck_assert_int_eq(ssc_sensor_spec_from_ini(ini, "sensor", &s, &d), 0);
	ck_assert_str_eq(s.name, "textbook gyro");
	ck_assert(s.quantity == SSCOPE_QUANTITY_ANGULAR_RATE);
	ck_assert_rel(s.range, 1.7453292519943295, 1e-15);
	ck_assert_rel(s.n, 0.15 * 2.9088820866572158e-4, 1e-14);
	ck_assert_rel(s.b, 4.8481368110953599e-6, 1e-14);
	ck_assert_rel(s.k, 0.5 * 8.0802280184922665e-8, 1e-13);
	ck_assert_rel(s.q, 2 * 4.8481368110953599e-6, 1e-14);
	ck_assert_rel(s.r, 3 * 1.3467046697487111e-9, 1e-13);
	ck_assert_rel(s.bias, -0.2 * 0.017453292519943295, 1e-15);
	ck_assert_rel(s.scale_factor_error, 300e-6, 1e-15);
	ck_assert_rel(s.bias_tempco, 0.01 * 0.017453292519943295, 1e-15);
	ck_assert_rel(s.temp_min_degc, -40, 1e-15);
	ck_assert_rel(s.temp_max_degc, 85, 1e-15);
	ck_assert_rel(s.sensitivity, 0.006 / 0.017453292519943295, 1e-15);
	ck_assert_rel(s.zero_output_v, 2.5, 1e-15);
	ck_assert_rel(s.bandwidth_hz, 40, 1e-15);
	ck_assert_int_eq(s.filter_order, 2);
	ck_assert_uint_eq(s.has, 0x1fffu);
	ssc_ini_free(ini);
}
END_TEST

START_TEST(sensor_accel)
{
	struct ssc_ini *ini;
	struct sscope_diag d;
	struct sscope_sensor_spec s;

	ck_assert_int_eq(parse("[sensor]\nnoise_density = 60 ug/sqrt(Hz)\n"
			       "bias_instability = 20 ug\nrate_random_walk = 0.02 m/s^2/s/sqrt(Hz)\n"
			       "scale_factor_error = 0.1 %\n",
			       &ini, &d), 0);
	ck_assert_int_eq(ssc_sensor_spec_from_ini(ini, "sensor", &s, &d), 0);
	ck_assert(s.quantity == SSCOPE_QUANTITY_ACCELERATION);
	ck_assert_rel(s.n, 60 * 9.80665e-6, 1e-15);
	ck_assert_rel(s.b, 20 * 9.80665e-6, 1e-15);
	ck_assert_rel(s.scale_factor_error, 1e-3, 1e-15);
	ck_assert_int_eq(s.filter_order, 1);
	ssc_ini_free(ini);
}
END_TEST

START_TEST(sensor_refusals)
{
	static const struct {
		const char *text, *needle;
	} cases[] = {
		{ "[sensor]\nrange = 100 deg/s\nnoise = 3\n", "line 3: unknown key 'noise' in [sensor]" },
		{ "[sensor]\nrange = 100 deg/s\nnoise_density = 1 m/s\n", "line 3: noise_density = 1 m/s: wrong unit" },
		{ "[sensor]\nname = x\n", "cannot tell a gyro from an accelerometer" },
		{ "[sensor]\nrange = -100 deg/s\n", "range must be a non-negative number" },
		{ "[sensor]\nrange = 100 furlongs/s\n", "cannot tell" },
		{ "[sensor]\nrange = 100 deg/s\ntemp_min = 50\ntemp_max = 10\n", "temp_max must exceed temp_min" },
		{ "[sensor]\nrange = 100 deg/s\nfilter_order = 12\n", "filter_order = 12: outside 1..8" },
		{ "[sensor]\nrange = 100 deg/s\nbias = 1 deg\n", "line 3: bias = 1 deg: wrong unit" },
		{ "[other]\nx=1\n", "no [sensor] section" },
	};

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		struct ssc_ini *ini;
		struct sscope_diag d;
		struct sscope_sensor_spec s;

		ck_assert_int_eq(parse(cases[i].text, &ini, &d), 0);
		ck_assert_int_eq(ssc_sensor_spec_from_ini(ini, "sensor", &s, &d),
				 -EINVAL);
		ck_assert_msg(strstr(d.msg, cases[i].needle) != NULL, "%zu: %s", i,
			      d.msg);
		ssc_ini_free(ini);
	}
}
END_TEST

START_TEST(load_file)
{
	struct sscope_sensor_spec s;
	struct sscope_diag d = { "" };

	ck_assert_int_eq(sscope_sensor_spec_load("/nonexistent.ini", &s, &d), -ENOENT);
	ck_assert_msg(strstr(d.msg, "/nonexistent.ini") != NULL, "%s", d.msg);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("spec");
	TCase *tc = tcase_create("spec");

	tcase_add_test(tc, ini_basics);
	tcase_add_test(tc, ini_errors);
	tcase_add_test(tc, sensor_gyro);
	tcase_add_test(tc, sensor_accel);
	tcase_add_test(tc, sensor_refusals);
	tcase_add_test(tc, load_file);
	suite_add_tcase(s, tc);
	return s;
}
