/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * MATLAB v5 MAT-files through the capture reader: files written by
 * scipy.io.savemat (tests/data/make-mat.py): exact values of a double row
 * vector, an int16 matrix split into columns, a time variable taken as
 * the time column, left-out variables (scalar, char, complex), chunked
 * reading, MATLAB v7 compressed elements (io-matz.c) equal to the v6 file,
 * and the errors (truncated, no numeric array).
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io-mat.h"
#include "check-main.h"

static const char *data_path(const char *name)
{
	static char path[1024];
	const char *top = getenv("top_srcdir");

	snprintf(path, sizeof(path), "%s/tests/data/%s", top ? top : "..", name);
	return path;
}

START_TEST(small_mat)
{
	struct sscope_capture *cap;
	struct sscope_reader_opts o = { 0 };
	struct sscope_diag d = { "" };
	const double x[5] = { 1.5, -2.25, 3, 4e10, 5e-7 };
	const double m1[5] = { 1, 3, 5, 7, 32767 }, m2[5] = { -2, -4, -6, -8, -32768 };

	ck_assert_msg(sscope_capture_load(&cap, data_path("small.mat"), &o, &d) == 0,
		      "%s", d.msg);
	ck_assert_uint_eq(cap->n, 5);
	ck_assert_uint_eq(cap->n_channels, 3);
	ck_assert_str_eq(cap->channels[0].col.name, "x");
	ck_assert_str_eq(cap->channels[1].col.name, "m_1");
	ck_assert_str_eq(cap->channels[2].col.name, "m_2");
	for (int i = 0; i < 5; i++) {
		ck_assert(cap->channels[0].data[i] == x[i]);
		ck_assert(cap->channels[1].data[i] == m1[i]);
		ck_assert(cap->channels[2].data[i] == m2[i]);
	}
	/* "t" is the time column: the rate follows from it */
	ck_assert(cap->time_s != NULL);
	ck_assert_int_eq(cap->rate_source, SSCOPE_CAPTURE_RATE_TIME_COLUMN);
	ck_assert_rel(cap->rate_hz, 10, 1e-12);
	sscope_capture_free(cap);
	/* a default unit and a selection */
	o.default_unit = "g";
	o.columns = "m_2";
	o.rate_hz = 100;
	ck_assert_int_eq(sscope_capture_load(&cap, data_path("small.mat"), &o, &d), 0);
	ck_assert_uint_eq(cap->n_channels, 1);
	ck_assert_rel(cap->channels[0].data[4], -32768 * 9.80665, 1e-15);
	sscope_capture_free(cap);
}
END_TEST

START_TEST(chunked)
{
	struct sscope_reader *r;
	struct sscope_diag d = { "" };
	double a[2], t[2];
	double *data[1] = { a };
	struct sscope_reader_chunk ch = { 2, 0, data, t, NULL };
	struct sscope_reader_opts o = { 0 };
	size_t total = 0;

	o.columns = "x";
	ck_assert_int_eq(sscope_reader_open(&r, data_path("small.mat"), &o, &d), 0);
	for (;;) {
		ck_assert_int_eq(sscope_reader_read(r, &ch, &d), 0);
		if (!ch.rows)
			break;
		if (total == 2)
			ck_assert(a[0] == 3 && a[1] == 4e10 && fabs(t[0] - 0.2) < 1e-15);
		total += ch.rows;
	}
	ck_assert_uint_eq(total, 5);
	sscope_reader_close(r);
}
END_TEST

START_TEST(bad_files)
{
	struct sscope_capture *cap;
	struct sscope_diag d = { "" };
	FILE *f, *g;
	char buf[4096];
	size_t n;
	const char *tmp = "test-mat.tmp.mat";

	/* MATLAB v7 (compressed elements) reads as the same data as v6 */
	{
		struct sscope_capture *plain;

		ck_assert_int_eq(sscope_capture_load(&cap, data_path("small-compressed.mat"), NULL, &d), 0);
		ck_assert_int_eq(sscope_capture_load(&plain, data_path("small.mat"), NULL, &d), 0);
		ck_assert_uint_eq(cap->n, plain->n);
		ck_assert_uint_eq(cap->n_channels, plain->n_channels);
		for (size_t k = 0; k < cap->n_channels; k++)
			ck_assert(!memcmp(cap->channels[k].data, plain->channels[k].data,
					  cap->n * sizeof(double)));
		ck_assert_str_eq(cap->source_info->format,
				 "MATLAB v7 MAT-file (compressed)");
		sscope_capture_free(cap);
		sscope_capture_free(plain);
	}
	/* a compressed element cut short */
	f = fopen(data_path("small-compressed.mat"), "rb");
	n = fread(buf, 1, sizeof(buf), f);
	fclose(f);
	g = fopen(tmp, "wb");
	fwrite(buf, 1, n - 20, g);
	fclose(g);
	ck_assert_int_eq(sscope_capture_load(&cap, tmp, NULL, &d), -EBADMSG);
	ck_assert_msg(strstr(d.msg, "MAT-file") != NULL, "%s", d.msg);
	/* truncated inside an element */
	f = fopen(data_path("small.mat"), "rb");
	n = fread(buf, 1, sizeof(buf), f);
	fclose(f);
	g = fopen(tmp, "wb");
	fwrite(buf, 1, 300, g);
	fclose(g);
	ck_assert_int_eq(sscope_capture_load(&cap, tmp, NULL, &d), -EBADMSG);
	ck_assert(strstr(d.msg, "truncated") != NULL);
	/* the header alone: nothing numeric */
	g = fopen(tmp, "wb");
	fwrite(buf, 1, 128, g);
	fclose(g);
	ck_assert_int_eq(sscope_capture_load(&cap, tmp, NULL, &d), -EDOM);
	/* a bad endian indicator */
	buf[126] = 'X';
	g = fopen(tmp, "wb");
	fwrite(buf, 1, n, g);
	fclose(g);
	ck_assert_int_eq(sscope_capture_load(&cap, tmp, NULL, &d), -EBADMSG);
	ck_assert(strstr(d.msg, "endian") != NULL);
	remove(tmp);
	ck_assert(!ssc_mat_detect("MATLAB 4", 8));
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("mat");
	TCase *tc = tcase_create("mat");

	tcase_add_test(tc, small_mat);
	tcase_add_test(tc, chunked);
	tcase_add_test(tc, bad_files);
	suite_add_tcase(s, tc);
	return s;
}
