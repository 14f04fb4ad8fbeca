/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Capture readers and writers: header and unit detection, delimiters,
 * EuRoC time stamps, raw binary layouts, chunked reading, round trips
 * through the writers, and every documented error with its location.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check-main.h"

static char dir[64];

static void setup(void)
{
	snprintf(dir, sizeof(dir), "/tmp/sscope-test-XXXXXX");
	ck_assert_ptr_nonnull(mkdtemp(dir));
}

static void teardown(void)
{
	char cmd[128];

	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
	ck_assert_int_eq(system(cmd), 0);
}

static const char *put(const char *name, const void *data, size_t len)
{
	static char path[128];
	FILE *f;

	snprintf(path, sizeof(path), "%s/%s", dir, name);
	f = fopen(path, "wb");
	ck_assert_ptr_nonnull(f);
	ck_assert_uint_eq(fwrite(data, 1, len, f), len);
	fclose(f);
	return path;
}

static const char *puts_(const char *name, const char *text)
{
	return put(name, text, strlen(text));
}

static int load(const char *path, const struct sscope_reader_opts *o,
		struct sscope_capture **cap, struct sscope_diag *d)
{
	d->msg[0] = '\0';
	return sscope_capture_load(cap, path, o, d);
}

#define D2R 0.017453292519943295

START_TEST(csv_units_and_roles)
{
	struct sscope_capture *cap;
	struct sscope_diag d;
	const char *p = puts_("a.csv",
			      "# a comment\n"
			      "time [s],gx [deg/s],gy (deg/s),az [g],temp [degC]\n"
			      "0.00,1.5,-2,1.0,25.0\n"
			      "0.01,2.5,-3,0.5,25.5\r\n"
			      "\n"
			      "0.02,3.5,-4,0.25,26.0\n");

	ck_assert_int_eq(load(p, NULL, &cap, &d), 0);
	ck_assert_uint_eq(cap->n, 3);
	ck_assert_uint_eq(cap->n_channels, 3);
	ck_assert_str_eq(cap->channels[0].col.name, "gx");
	ck_assert_str_eq(cap->channels[1].col.unit_label, "deg/s");
	ck_assert(cap->channels[0].col.quantity == SSCOPE_QUANTITY_ANGULAR_RATE);
	ck_assert(cap->channels[2].col.quantity == SSCOPE_QUANTITY_ACCELERATION);
	ck_assert_rel(cap->channels[0].data[2], 3.5 * D2R, 1e-15);
	ck_assert_rel(cap->channels[2].data[1], 0.5 * 9.80665, 1e-15);
	ck_assert_ptr_nonnull(cap->time_s);
	ck_assert_ptr_nonnull(cap->temp_degc);
	ck_assert_rel(cap->temp_degc[2], 26.0, 1e-15);
	ck_assert_rel(cap->time_s[2], 0.02, 1e-15);
	ck_assert(cap->rate_source == SSCOPE_CAPTURE_RATE_TIME_COLUMN);
	ck_assert_rel(cap->rate_hz, 100, 1e-12);
	sscope_capture_free(cap);
}
END_TEST

START_TEST(euroc)
{
	struct sscope_capture *cap;
	struct sscope_diag d;
	char *text = malloc(1 << 16);
	size_t used;
	const char *p;

	used = (size_t)sprintf(text,
			       "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],"
			       "w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],"
			       "a_RS_S_z [m s^-2]\n");
	for (int i = 0; i < 400; i++)
		used += (size_t)sprintf(text + used,
					"%lld,-0.0991,0.1340,0.0258,8.1%03d,-0.0262,-2.05\n",
					1403636579758555392LL + 5000000LL * i, i);
	p = put("euroc.csv", text, used);
	free(text);
	ck_assert_int_eq(load(p, NULL, &cap, &d), 0);
	ck_assert_uint_eq(cap->n, 400);
	ck_assert_uint_eq(cap->n_channels, 6);
	ck_assert_str_eq(cap->time_col.name, "timestamp");
	ck_assert_str_eq(cap->channels[0].col.name, "w_RS_S_x");
	ck_assert(cap->channels[0].col.quantity == SSCOPE_QUANTITY_ANGULAR_RATE);
	ck_assert(cap->channels[3].col.quantity == SSCOPE_QUANTITY_ACCELERATION);
	/* nanosecond stamps near 1.4e18 keep full resolution */
	for (int i = 0; i < 400; i++)
		ck_assert_msg(cap->time_s[i] == i * 5000000 * 1e-9,
			      "t[%d] = %.17g", i, cap->time_s[i]);
	ck_assert_rel(cap->rate_hz, 200, 1e-12);
	sscope_capture_free(cap);
}
END_TEST

START_TEST(delimiters)
{
	static const char *const files[] = {
		"t [s]\tgx [deg/s]\tgy [deg/s]\n0\t1\t2\n0.5\t3\t4\n",
		"t [s];gx [deg/s];gy [deg/s]\n0;1;2\n0.5;3;4\n",
		"  t [s]   gx [deg/s]  gy [deg/s]\n 0  1  2\n  0.5 3   4\n",
		"t (s), gx (deg/s), gy (deg/s)\n0, 1, 2\n0.5, 3, 4\n",
		"\xef\xbb\xbft,gx [deg/s],gy [deg/s]\n0,1,2\n0.5,3,4\n",
	};

	for (size_t i = 0; i < sizeof(files) / sizeof(files[0]); i++) {
		struct sscope_capture *cap;
		struct sscope_diag d;
		const char *p = puts_("d.txt", files[i]);

		ck_assert_msg(load(p, NULL, &cap, &d) == 0, "file %zu: %s", i,
			      d.msg);
		ck_assert_uint_eq(cap->n, 2);
		ck_assert_uint_eq(cap->n_channels, 2);
		ck_assert_str_eq(cap->channels[1].col.name, "gy");
		ck_assert_rel(cap->channels[1].data[1], 4 * D2R, 1e-15);
		ck_assert_rel(cap->rate_hz, 2, 1e-15);
		sscope_capture_free(cap);
	}
}
END_TEST

START_TEST(no_header_and_selection)
{
	struct sscope_capture *cap;
	struct sscope_diag d;
	struct sscope_reader_opts o = { 0 };
	const char *p = puts_("n.csv", "1,2,3\n4,5,6\n7,8,9\n");

	o.default_unit = "mg";
	o.rate_hz = 50;
	o.columns = "3,col1";
	ck_assert_int_eq(load(p, &o, &cap, &d), 0);
	ck_assert_uint_eq(cap->n_channels, 2);
	ck_assert_str_eq(cap->channels[0].col.name, "col3");
	ck_assert_str_eq(cap->channels[1].col.name, "col1");
	ck_assert_str_eq(cap->channels[0].col.unit_label, "mg");
	ck_assert_rel(cap->channels[0].data[2], 9 * 9.80665e-3, 1e-15);
	ck_assert(cap->rate_source == SSCOPE_CAPTURE_RATE_GIVEN);
	ck_assert_ptr_null(cap->time_s);
	sscope_capture_free(cap);
}
END_TEST

START_TEST(header_rate_comment)
{
	struct sscope_capture *cap;
	struct sscope_diag d;
	const char *p = puts_("r.csv", "# sensor: test\n# rate: 2 kHz\n"
				       "gx [deg/s]\n1\n2\n");

	ck_assert_int_eq(load(p, NULL, &cap, &d), 0);
	ck_assert(cap->rate_source == SSCOPE_CAPTURE_RATE_HEADER);
	ck_assert_rel(cap->rate_hz, 2000, 1e-15);
	sscope_capture_free(cap);
	p = puts_("r2.csv", "# fs = 100\ngx\n1\n2\n");
	ck_assert_int_eq(load(p, NULL, &cap, &d), 0);
	ck_assert_rel(cap->rate_hz, 100, 1e-15);
	ck_assert(cap->channels[0].col.quantity == SSCOPE_QUANTITY_UNKNOWN);
	ck_assert_str_eq(cap->rate_note, "");
	sscope_capture_free(cap);
	/* a rate comment that gives none is kept to say why the rate is
	 * unknown: zero, negative, not a frequency, not a number */
	{
		static const char *const bad[] = { "0 Hz", "-5 Hz", "10 m",
						   "abc", "1e400 Hz" };

		for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
			char text[96], want[64];

			snprintf(text, sizeof(text), "# sensor: x\n# rate: %s\ngx\n1\n2\n",
				 bad[i]);
			snprintf(want, sizeof(want), "line 2: '# rate: %s' is not a sample rate",
				 bad[i]);
			p = puts_("r3.csv", text);
			ck_assert_int_eq(load(p, NULL, &cap, &d), 0);
			ck_assert(cap->rate_source == SSCOPE_CAPTURE_RATE_NONE);
			ck_assert_double_eq(cap->rate_hz, 0);
			ck_assert_msg(strstr(cap->rate_note, want) == cap->rate_note,
				      "%s: %s", bad[i], cap->rate_note);
			sscope_capture_free(cap);
		}
	}
	/* a later comment with a rate, or a rate from the time column:
	 * no note */
	p = puts_("r4.csv", "# rate: 0 Hz\n# fs: 50\ngx\n1\n2\n");
	ck_assert_int_eq(load(p, NULL, &cap, &d), 0);
	ck_assert_rel(cap->rate_hz, 50, 1e-15);
	ck_assert_str_eq(cap->rate_note, "");
	sscope_capture_free(cap);
	p = puts_("r5.csv", "# rate: fast\nt [s],gx\n0,1\n0.5,2\n1,3\n");
	ck_assert_int_eq(load(p, NULL, &cap, &d), 0);
	ck_assert_rel(cap->rate_hz, 2, 1e-12);
	ck_assert_str_eq(cap->rate_note, "");
	sscope_capture_free(cap);
}
END_TEST

START_TEST(nan_gaps)
{
	struct sscope_capture *cap;
	struct sscope_diag d;
	struct sscope_reader_opts o = { 0 };
	const char *p = puts_("g.csv", "t,a [g]\n0,1\n1,nan\n2,\n3,4\n");

	ck_assert_int_eq(load(p, NULL, &cap, &d), -EBADMSG);
	ck_assert_msg(strstr(d.msg, "line 3, column 2 (a)") != NULL, "%s", d.msg);
	o.nan_as_gap = true;
	ck_assert_int_eq(load(p, &o, &cap, &d), 0);
	ck_assert_uint_eq(cap->n_nan, 2);
	ck_assert(isnan(cap->channels[0].data[1]));
	ck_assert(isnan(cap->channels[0].data[2]));
	ck_assert_rel(cap->channels[0].data[3], 4 * 9.80665, 1e-15);
	sscope_capture_free(cap);
	/* a NaN time stamp is never a gap */
	p = puts_("g2.csv", "t,a [g]\n0,1\nnan,2\n");
	ck_assert_int_eq(load(p, &o, &cap, &d), -EBADMSG);
	ck_assert_msg(strstr(d.msg, "NaN time stamp") != NULL, "%s", d.msg);
}
END_TEST

START_TEST(errors_located)
{
	static const struct {
		const char *text;
		int rc;
		const char *needle;
	} cases[] = {
		{ "t,a\n0,1\n1,2,3\n", -EBADMSG, "line 3: 3 columns" },
		{ "t,a\n0,1\n1\n", -EBADMSG, "line 3: 1 columns" },
		{ "t,a\n0,1\n1,abc\n", -EBADMSG, "line 3, column 2 (a): not a number 'abc'" },
		{ "t,a\n0,1\n1,1e999\n", -EBADMSG, "infinite" },
		{ "", -EDOM, "empty" },
		{ "# only a comment\n", -EDOM, "no data" },
		{ "t,a\n", -EDOM, "no data" },
		{ "t,temp\n0,1\n", -EDOM, "no data column" },
		{ "t,a [furlong]\n0,1\n", -EINVAL, "furlong" },
		{ "t [deg],a\n0,1\n", -EINVAL, "not a time" },
		{ "t,temp [V],a\n0,1,2\n", -EINVAL, "not a temperature" },
		{ "a,b\n1,2\n\0\0\0", -EBADMSG, "binary" },
	};

	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		struct sscope_capture *cap = NULL;
		struct sscope_diag d;
		size_t len = strlen(cases[i].text);
		const char *p;
		int rc;

		if (i == sizeof(cases) / sizeof(cases[0]) - 1)
			len += 3;
		p = put("e.csv", cases[i].text, len);
		rc = load(p, NULL, &cap, &d);
		ck_assert_msg(rc == cases[i].rc, "case %zu: rc %d (%s)", i, rc,
			      d.msg);
		ck_assert_msg(strstr(d.msg, cases[i].needle) != NULL,
			      "case %zu: '%s' lacks '%s'", i, d.msg,
			      cases[i].needle);
		ck_assert_ptr_null(cap);
	}
}
END_TEST

START_TEST(unselected_unknown_unit_ok)
{
	struct sscope_capture *cap;
	struct sscope_diag d;
	struct sscope_reader_opts o = { .columns = "a" };
	const char *p = puts_("u.csv", "a [g],b [furlong]\n1,2\n3,4\n");

	ck_assert_int_eq(load(p, &o, &cap, &d), 0);
	ck_assert_uint_eq(cap->n_channels, 1);
	sscope_capture_free(cap);
	o.columns = "zz";
	ck_assert_int_eq(load(p, &o, &cap, &d), -EINVAL);
	ck_assert_msg(strstr(d.msg, "no column 'zz' (columns: a, b)") != NULL,
		      "%s", d.msg);
	o.columns = "9";
	ck_assert_int_eq(load(p, &o, &cap, &d), -EINVAL);
}
END_TEST

START_TEST(missing_file)
{
	struct sscope_capture *cap;
	struct sscope_diag d;

	ck_assert_int_eq(load("/nonexistent/x.csv", NULL, &cap, &d), -ENOENT);
	ck_assert_int_eq(load(dir, NULL, &cap, &d), -EISDIR);
}
END_TEST

START_TEST(raw_layouts)
{
	struct sscope_capture *cap;
	struct sscope_diag d;
	struct sscope_reader_opts o = { 0 };
	unsigned char le16[] = { 0x01, 0x00, 0xff, 0xff, 0x00, 0x80, 0xff, 0x7f };
	unsigned char be16[] = { 0x00, 0x01, 0xff, 0xff, 0x80, 0x00, 0x7f, 0xff };
	unsigned char i24[] = { 0xff, 0xff, 0xff, 0x00, 0x00, 0x80 };
	float f[4] = { 1.5f, -2.25f, 3.0f, 4.0f };
	const char *p;

	o.raw = "i16:2:le";
	o.raw_scale = 0.5;
	o.raw_offset = 1;
	o.default_unit = "deg/s";
	o.rate_hz = 10;
	p = put("le.bin", le16, sizeof(le16));
	ck_assert_int_eq(load(p, &o, &cap, &d), 0);
	ck_assert_uint_eq(cap->n, 2);
	ck_assert_uint_eq(cap->n_channels, 2);
	ck_assert_str_eq(cap->channels[1].col.name, "ch2");
	ck_assert_rel(cap->channels[0].data[0], (1 + 1) * 0.5 * D2R, 1e-15);
	ck_assert(cap->channels[1].data[0] == 0);
	ck_assert_rel(cap->channels[0].data[1], (-32768 + 1) * 0.5 * D2R, 1e-15);
	ck_assert_rel(cap->channels[1].data[1], (32767 + 1) * 0.5 * D2R, 1e-15);
	sscope_capture_free(cap);
	o.raw = "i16:2:be";
	p = put("be.bin", be16, sizeof(be16));
	ck_assert_int_eq(load(p, &o, &cap, &d), 0);
	ck_assert_rel(cap->channels[1].data[1], (32767 + 1) * 0.5 * D2R, 1e-15);
	sscope_capture_free(cap);
	o.raw = "i24:1";
	o.raw_scale = 1;
	o.raw_offset = 0;
	o.default_unit = NULL;
	p = put("i24.bin", i24, sizeof(i24));
	ck_assert_int_eq(load(p, &o, &cap, &d), 0);
	ck_assert(cap->channels[0].data[0] == -1);
	ck_assert(cap->channels[0].data[1] == -8388608);
	sscope_capture_free(cap);
	o.raw = "f32:2";
	p = put("f.bin", f, sizeof(f));
	ck_assert_int_eq(load(p, &o, &cap, &d), 0);
	ck_assert(cap->channels[1].data[0] == -2.25);
	sscope_capture_free(cap);
	/* truncated: 7 bytes of 2-byte pairs */
	o.raw = "i16:2";
	p = put("t.bin", le16, 7);
	ck_assert_int_eq(load(p, &o, &cap, &d), -EBADMSG);
	ck_assert_msg(strstr(d.msg, "truncated") != NULL, "%s", d.msg);
	o.raw = "i17:2";
	ck_assert_int_eq(load(p, &o, &cap, &d), -EINVAL);
	o.raw = "i16:0";
	ck_assert_int_eq(load(p, &o, &cap, &d), -EINVAL);
	o.raw = "i16:2:xe";
	ck_assert_int_eq(load(p, &o, &cap, &d), -EINVAL);
}
END_TEST

/* sscope_reader_raw_layout_check: every malformed layout is -EINVAL with a
 * message; good ones give their channels and value size */
START_TEST(raw_layout_check)
{
	static const char *const bad[] = { "", ":", "i16", "i16:", "i16:0",
					   "u64:1", "i16:3:xx", "i16:-1",
					   "i16:+1", "i16: 3", "i16:65536",
					   "i16:4097", "i16:18446744073709551617",
					   "i16:2:le:", "I16:2", "i16:2x" };
	struct sscope_diag d;
	size_t ch = 0, sz = 0;

	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		d.msg[0] = '\0';
		ck_assert_msg(sscope_reader_raw_layout_check(bad[i], &ch, &sz, &d) == -EINVAL,
			      "'%s' accepted", bad[i]);
		ck_assert_msg(d.msg[0] != '\0', "'%s': no message", bad[i]);
	}
	ck_assert_int_eq(sscope_reader_raw_layout_check(NULL, NULL, NULL, NULL), -EINVAL);
	ck_assert_int_eq(sscope_reader_raw_layout_check("i24:4096:be", &ch, &sz, &d), 0);
	ck_assert_uint_eq(ch, 4096);
	ck_assert_uint_eq(sz, 3);
	ck_assert_int_eq(sscope_reader_raw_layout_check("f64:1", &ch, &sz, NULL), 0);
	ck_assert_uint_eq(ch, 1);
	ck_assert_uint_eq(sz, 8);
}
END_TEST

static struct sscope_capture *sample_capture(size_t n)
{
	struct sscope_capture *cap = sscope_capture_new(2, n, true, true);

	ck_assert_ptr_nonnull(cap);
	ck_assert_int_eq(sscope_capture_set_channel(cap, 0, "gx", "deg/h"), 0);
	ck_assert_int_eq(sscope_capture_set_channel(cap, 1, "az", "mg"), 0);
	for (size_t i = 0; i < n; i++) {
		cap->time_s[i] = (double)i / 3.0;
		cap->channels[0].data[i] = sin((double)i * 0.7) * 1e-3 + 2.385e-5;
		cap->channels[1].data[i] = 9.80665 + cos((double)i) * 1e-4;
		cap->temp_degc[i] = 20 + 0.01 * (double)i;
	}
	return cap;
}

START_TEST(round_trips)
{
	static const enum sscope_capture_format fmts[] = {
		SSCOPE_CAPTURE_CSV, SSCOPE_CAPTURE_BIN64, SSCOPE_CAPTURE_BIN32
	};
	struct sscope_capture *a = sample_capture(1000), *b;
	struct sscope_diag d;
	char path[128];

	snprintf(path, sizeof(path), "%s/rt.cap", dir);
	for (size_t f = 0; f < 3; f++) {
		double tol = fmts[f] == SSCOPE_CAPTURE_BIN32 ? 1e-6 : 1e-15;

		ck_assert_int_eq(sscope_capture_write(a, path, fmts[f], 0, &d), 0);
		ck_assert_int_eq(load(path, NULL, &b, &d), 0);
		ck_assert_uint_eq(b->n, a->n);
		ck_assert_uint_eq(b->n_channels, 2);
		ck_assert_str_eq(b->channels[0].col.unit_label, "deg/h");
		for (size_t i = 0; i < a->n; i++) {
			ck_assert_rel(b->channels[0].data[i], a->channels[0].data[i], tol);
			ck_assert_rel(b->channels[1].data[i], a->channels[1].data[i], tol);
			ck_assert_rel(b->temp_degc[i], a->temp_degc[i], tol);
			ck_assert_rel(b->time_s[i], a->time_s[i], tol);
		}
		ck_assert_rel(b->rate_hz, 3, tol);
		sscope_capture_free(b);
	}
	sscope_capture_free(a);
}
END_TEST

START_TEST(atomic_abort)
{
	struct sscope_writer *w;
	struct sscope_writer_column c[1] = { { "x", "V" } };
	char path[128];
	double v = 1;

	snprintf(path, sizeof(path), "%s/never.csv", dir);
	ck_assert_int_eq(sscope_writer_open(&w, path, SSCOPE_CAPTURE_CSV, c, 1, 0,
					    NULL), 0);
	ck_assert_int_eq(sscope_writer_append(w, &v, 1), 0);
	sscope_writer_abort(w);
	ck_assert_int_ne(access(path, F_OK), 0);
	{
		char cmd[160];

		snprintf(cmd, sizeof(cmd), "test -z \"$(ls -A '%s')\"", dir);
		ck_assert_int_eq(system(cmd), 0); /* no temporary left */
	}
	ck_assert_int_eq(sscope_writer_open(&w, "/nonexistent/dir/x.csv",
					    SSCOPE_CAPTURE_CSV, c, 1, 0, NULL),
			 -ENOENT);
	c[0].unit = "bogons";
	ck_assert_int_eq(sscope_writer_open(&w, path, SSCOPE_CAPTURE_CSV, c, 1, 0,
					    NULL), -EINVAL);
}
END_TEST

START_TEST(chunked_equals_whole)
{
	struct sscope_capture *a = sample_capture(1001), *b;
	struct sscope_reader *r;
	struct sscope_diag d;
	char path[128];
	double c0[7], c1[7], t[7], tc[7], *ptr[2] = { c0, c1 };
	struct sscope_reader_chunk ch = { 7, 0, ptr, t, tc };
	size_t got = 0;

	snprintf(path, sizeof(path), "%s/ch.csv", dir);
	ck_assert_int_eq(sscope_capture_write(a, path, SSCOPE_CAPTURE_CSV, 0, &d), 0);
	ck_assert_int_eq(load(path, NULL, &b, &d), 0);
	ck_assert_int_eq(sscope_reader_open(&r, path, NULL, &d), 0);
	ck_assert_uint_eq(sscope_reader_n_channels(r), 2);
	ck_assert_uint_eq(sscope_reader_n_columns(r), 4);
	ck_assert_ptr_nonnull(sscope_reader_time_column(r));
	ck_assert_ptr_nonnull(sscope_reader_temp_column(r));
	ck_assert_str_eq(sscope_reader_channel(r, 1)->name, "az");
	ck_assert_str_eq(sscope_reader_column(r, 3)->name, "temp");
	for (;;) {
		ck_assert_int_eq(sscope_reader_read(r, &ch, &d), 0);
		if (!ch.rows)
			break;
		for (size_t i = 0; i < ch.rows; i++) {
			ck_assert(c0[i] == b->channels[0].data[got + i]);
			ck_assert(c1[i] == b->channels[1].data[got + i]);
			ck_assert(t[i] == b->time_s[got + i]);
			ck_assert(tc[i] == b->temp_degc[got + i]);
		}
		got += ch.rows;
	}
	ck_assert_uint_eq(got, 1001);
	sscope_reader_close(r);
	sscope_capture_free(a);
	sscope_capture_free(b);
}
END_TEST


/*
 * The reader's fast path (cells located 64 bytes at a time, plain numbers
 * converted without a loop) against strtod, cell by cell, on a file large
 * enough to be split between two threads: short and 17-digit numbers,
 * exponents, signs, "5." and ".5", blanks around cells, CR LF, comments,
 * blank lines, with and without a final newline; then a bad cell and a
 * ragged line deep in the file, reported at their line as before.
 */
static uint64_t lcg_state;

static double lcg(void)
{
	lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
	return (double)(lcg_state >> 11) / 9007199254740992.0;
}

static size_t random_cell(char *b, size_t cap)
{
	double u = lcg(), x = (lcg() - 0.5) * pow(10, (int)(lcg() * 8) - 4);

	if (u < 0.55)
		return (size_t)snprintf(b, cap, "%.9g", x);
	if (u < 0.65)
		return (size_t)snprintf(b, cap, "%.17g", x);
	if (u < 0.72)
		return (size_t)snprintf(b, cap, "%.4e", x);
	if (u < 0.78)
		return (size_t)snprintf(b, cap, "+%.6f", fabs(x));
	if (u < 0.82)
		return (size_t)snprintf(b, cap, "%d.", (int)(x * 100));
	if (u < 0.86)
		return (size_t)snprintf(b, cap, "%s.%06d", x < 0 ? "-" : "",
					(int)(lcg() * 999999));
	if (u < 0.88)
		return (size_t)snprintf(b, cap, " %.5f\t", x);
	if (u < 0.90)
		return (size_t)snprintf(b, cap, "%015.8f", x);
	return (size_t)snprintf(b, cap, "%.12g", x);
}

/* A big CSV; every data cell's text kept for the oracle. */
static char *big_csv(size_t rows, bool final_newline, char ***cells,
		     size_t *len)
{
	size_t cap = rows * 120 + 256, n = 0;
	char *t = malloc(cap);

	*cells = calloc(rows * 4, sizeof(**cells));
	ck_assert(t && *cells);
	n += (size_t)sprintf(t, "t [s],a,b,c,d\n");
	for (size_t i = 0; i < rows; i++) {
		double u = lcg();

		if (u < 0.005)
			n += (size_t)sprintf(t + n, "# comment %zu\n", i);
		else if (u < 0.01)
			n += (size_t)sprintf(t + n, "%s", lcg() < 0.5 ? "\n" : " \r\n");
		n += (size_t)sprintf(t + n, "%zu.%02zu", i / 100, i % 100);
		for (int k = 0; k < 4; k++) {
			char c[64];
			size_t l = random_cell(c, sizeof(c));

			t[n++] = ',';
			memcpy(t + n, c, l);
			n += l;
			(*cells)[i * 4 + (size_t)k] = strndup(c, l);
		}
		if (i + 1 < rows || final_newline)
			n += (size_t)sprintf(t + n, "%s", lcg() < 0.1 ? "\r\n" : "\n");
	}
	*len = n;
	return t;
}

START_TEST(fast_path_equals_strtod)
{
	const size_t rows = 130000; /* about 10 MB: two threads */

	lcg_state = 1515;
	for (int nl = 0; nl < 2; nl++) {
		char **cells, *text;
		size_t len;
		const char *p;

		text = big_csv(rows, nl, &cells, &len);
		p = put("big.csv", text, len);
		/* (8 threads: more pieces to count than threads) */
		for (unsigned th = 1; th <= 8; th = th == 2 ? 8 : th + 1) {
			struct sscope_reader_opts o = { .threads = th };
			struct sscope_capture *cap;
			struct sscope_diag d;

			ck_assert_msg(load(p, &o, &cap, &d) == 0, "%s", d.msg);
			ck_assert_uint_eq(cap->n, rows);
			ck_assert_uint_eq(cap->n_channels, 4);
			for (size_t i = 0; i < rows; i++) {
				ck_assert_msg(cap->time_s[i] == (double)i / 100,
					      "row %zu: t %.17g", i, cap->time_s[i]);
				for (size_t k = 0; k < 4; k++) {
					/* the unit's scale and offset (1, 0)
					 * applied: -0 reads as +0 */
					double ref = strtod(cells[i * 4 + k], NULL) *
							     1.0 + 0.0;

					ck_assert_msg(memcmp(&ref, &cap->channels[k].data[i],
							     8) == 0,
						      "row %zu '%s': %.17g != strtod %.17g",
						      i, cells[i * 4 + k],
						      cap->channels[k].data[i], ref);
				}
			}
			sscope_capture_free(cap);
			/* one column selected: the cells after it are only
			 * counted (to the line's end), the same values */
			if (th == 2) {
				size_t k = nl ? 2 : 0, bad = 0, first = rows;

				o.columns = k ? "c" : "a";
				ck_assert_msg(load(p, &o, &cap, &d) == 0, "%s", d.msg);
				ck_assert_uint_eq(cap->n, rows);
				ck_assert_uint_eq(cap->n_channels, 1);
				for (size_t i = 0; i < rows; i++) {
					double ref = strtod(cells[i * 4 + k], NULL) + 0.0;

					if (cap->time_s[i] != (double)i / 100 ||
					    memcmp(&ref, &cap->channels[0].data[i], 8)) {
						bad++;
						first = first < i ? first : i;
					}
				}
				ck_assert_msg(bad == 0, "-c %s: %zu rows differ, the first %zu",
					      o.columns, bad, first);
				sscope_capture_free(cap);
			}
		}
		/* from memory, in chunks of 777 rows */
		{
			struct sscope_reader *r;
			struct sscope_diag d;
			double c[4][777], t[777];
			double *ptr[4] = { c[0], c[1], c[2], c[3] };
			struct sscope_reader_chunk ch = { 777, 0, ptr, t, NULL };
			size_t got = 0;

			ck_assert_int_eq(ssc_reader_open_mem(&r, text, len, "m", NULL, &d), 0);
			for (;;) {
				ck_assert_int_eq(sscope_reader_read(r, &ch, &d), 0);
				if (!ch.rows)
					break;
				for (size_t i = 0; i < ch.rows; i++)
					for (size_t k = 0; k < 4; k++)
						ck_assert(c[k][i] ==
							  strtod(cells[(got + i) * 4 + k], NULL));
				got += ch.rows;
			}
			ck_assert_uint_eq(got, rows);
			sscope_reader_close(r);
		}
		for (size_t i = 0; i < rows * 4; i++)
			free(cells[i]);
		free(cells);
		free(text);
	}
}
END_TEST

START_TEST(fast_path_errors_located)
{
	const size_t rows = 130000;
	char **cells, *text, *q;
	size_t len, line;

	lcg_state = 2727;
	text = big_csv(rows, true, &cells, &len);
	/* a line far into the second half: find its start */
	q = text;
	for (line = 1; line < 120001; line++)
		q = strchr(q, '\n') + 1;
	for (int c = 0; c < 2; c++) {
		char *bad = malloc(len + 16), expect[128];
		const char *p;
		size_t at = (size_t)(q - text);

		memcpy(bad, text, at);
		if (c == 0) { /* a cell that is no number */
			memcpy(bad + at, "1.25,1.2.3,", 11);
			snprintf(expect, sizeof(expect),
				 "line %zu, column 2 (a): not a number '1.2.3'", line);
		} else { /* a short line */
			memcpy(bad + at, "1.25,1.5\n", 9);
			snprintf(expect, sizeof(expect),
				 "line %zu: 2 columns where the header has 5", line);
		}
		memcpy(bad + at + (c ? 9 : 11), text + at, len - at);
		p = put("bad.csv", bad, len + (c ? 9 : 11));
		for (unsigned th = 1; th <= 2; th++) {
			struct sscope_reader_opts o = { .threads = th };
			struct sscope_capture *cap = NULL;
			struct sscope_diag d;

			ck_assert_int_eq(load(p, &o, &cap, &d), -EBADMSG);
			ck_assert_msg(strstr(d.msg, expect), "'%s' lacks '%s'",
				      d.msg, expect);
		}
		free(bad);
	}
	/* lines with cells too many or too few after the one column in use
	 * (a line longer than the 64-byte blocks among them): located too */
	for (int c = 0; c < 3; c++) {
		static const char *const ins[3] = { "1.25,1.5,2,3,4,5\n", "1.25,1.5,2\n",
			"1.25,1.5,22222222222222222222222222,33333333333333333333333333333333,"
			"44444444444444444444444444,55555555555555555555555\n" };
		static const size_t ncol[3] = { 6, 3, 6 };
		size_t il = strlen(ins[c]), at = (size_t)(q - text);
		char *bad = malloc(len + il), expect[128];
		const char *p;

		memcpy(bad, text, at);
		memcpy(bad + at, ins[c], il);
		memcpy(bad + at + il, text + at, len - at);
		snprintf(expect, sizeof(expect), "line %zu: %zu columns where the header has 5",
			 line, ncol[c]);
		p = put("bad.csv", bad, len + il);
		for (unsigned th = 1; th <= 2; th++) {
			struct sscope_reader_opts o = { .threads = th, .columns = "a" };
			struct sscope_capture *cap = NULL;
			struct sscope_diag d;

			ck_assert_int_eq(load(p, &o, &cap, &d), -EBADMSG);
			ck_assert_msg(strstr(d.msg, expect), "'%s' lacks '%s'",
				      d.msg, expect);
		}
		free(bad);
	}
	for (size_t i = 0; i < rows * 4; i++)
		free(cells[i]);
	free(cells);
	free(text);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("reader");
	TCase *tc = tcase_create("reader");

	tcase_add_checked_fixture(tc, setup, teardown);
	tcase_add_test(tc, csv_units_and_roles);
	tcase_add_test(tc, euroc);
	tcase_add_test(tc, delimiters);
	tcase_add_test(tc, no_header_and_selection);
	tcase_add_test(tc, header_rate_comment);
	tcase_add_test(tc, nan_gaps);
	tcase_add_test(tc, errors_located);
	tcase_add_test(tc, unselected_unknown_unit_ok);
	tcase_add_test(tc, missing_file);
	tcase_add_test(tc, raw_layouts);
	tcase_add_test(tc, raw_layout_check);
	tcase_add_test(tc, round_trips);
	tcase_add_test(tc, atomic_abort);
	tcase_add_test(tc, chunked_equals_whole);
	tcase_add_test(tc, fast_path_equals_strtod);
	tcase_add_test(tc, fast_path_errors_located);
	suite_add_tcase(s, tc);
	return s;
}
