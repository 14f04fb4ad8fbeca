/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Shaping captures (sscope_capture_select and sscope_capture_view: one
 * rule for a command's -c, a scene's columns and a calibrated capture),
 * what a loaded capture carries (its timing, its gaps, NaN per channel),
 * and the streaming timing psd reads while it streams.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check-main.h"

/* four channels a, b, c, d with values 1.5, 2.5, 3.5, 4.5 (+ 10 k) and
 * file columns 2..5 (column 1 is time) */
static struct sscope_capture *four(void)
{
	static const char *const names[4] = { "a", "b", "c", "d" };
	struct sscope_capture *c = sscope_capture_new(4, 3, false, false);

	ck_assert_ptr_nonnull(c);
	c->source = ssc_strdup("four.csv");
	for (size_t k = 0; k < 4; k++) {
		ck_assert_int_eq(sscope_capture_set_channel(c, k, names[k], "m/s^2"), 0);
		c->channels[k].col.index = k + 1;
		for (size_t i = 0; i < 3; i++)
			c->channels[k].data[i] = 1.5 + (double)k + 10 * (double)i;
	}
	c->channels[2].data[1] = NAN;
	c->channels[2].n_nan = 1;
	c->n_nan = 1;
	return c;
}

static void names_are(const struct sscope_capture *c, const char *want)
{
	char got[64] = "";

	for (size_t k = 0; k < c->n_channels; k++)
		snprintf(got + strlen(got), sizeof(got) - strlen(got), "%s%s",
			 k ? "," : "", c->channels[k].col.name);
	ck_assert_str_eq(got, want);
}

START_TEST(view_order_blanks_indices)
{
	struct sscope_capture *c = four(), *v;
	struct sscope_diag d;

	/* the list's order; blanks around items; an index is the file's
	 * 1-based column (d is column 5); a name twice counts once; case */
	ck_assert_int_eq(sscope_capture_view(c, " d ,\tb, 5,A,,", &v, &d), 0);
	names_are(v, "d,b,a");
	ck_assert(v->is_view);
	/* shares the samples, keeps the NaN counts */
	ck_assert_ptr_eq(v->channels[0].data, c->channels[3].data);
	ck_assert_uint_eq(v->n_nan, 0);
	sscope_capture_free(v);
	ck_assert_int_eq(sscope_capture_view(c, "c", &v, &d), 0);
	ck_assert_uint_eq(v->n_nan, 1);
	ck_assert_uint_eq(v->channels[0].n_nan, 1);
	sscope_capture_free(v);
	/* NULL or "": every channel */
	ck_assert_int_eq(sscope_capture_view(c, NULL, &v, &d), 0);
	names_are(v, "a,b,c,d");
	sscope_capture_free(v);
	ck_assert_int_eq(sscope_capture_view(c, "", &v, &d), 0);
	names_are(v, "a,b,c,d");
	sscope_capture_free(v);
	/* the parent outlives its views and is intact */
	names_are(c, "a,b,c,d");
	ck_assert(c->channels[1].data[2] == 22.5);
	sscope_capture_free(c);
}
END_TEST

START_TEST(unknown_names_are_errors)
{
	struct sscope_capture *c = four(), *v = (void *)1;
	struct sscope_diag d;

	ck_assert_int_eq(sscope_capture_view(c, "a, bogus", &v, &d), -EINVAL);
	ck_assert_ptr_null(v);
	ck_assert_ptr_nonnull(strstr(d.msg, "four.csv: no column 'bogus' (columns: a, b, c, d)"));
	/* an index that is no data column (1 is the time column) */
	ck_assert_int_eq(sscope_capture_view(c, "1", &v, &d), -EINVAL);
	ck_assert_int_eq(sscope_capture_select(c, "a, 9", &d), -EINVAL);
	names_are(c, "a,b,c,d"); /* untouched on failure */
	ck_assert_int_eq(sscope_capture_select(NULL, "a", &d), -EINVAL);
	sscope_capture_free(c);
}
END_TEST

START_TEST(select_in_place)
{
	struct sscope_capture *c = four(), *v;
	struct sscope_diag d;

	ck_assert_int_eq(sscope_capture_select(c, "c, a", &d), 0);
	names_are(c, "c,a");
	ck_assert(!c->is_view);
	ck_assert_uint_eq(c->n_nan, 1);
	ck_assert(c->channels[1].data[2] == 21.5);
	/* selecting again by the same rule: an identity */
	ck_assert_int_eq(sscope_capture_select(c, "c,a", &d), 0);
	names_are(c, "c,a");
	/* a view cannot be shaped in place */
	ck_assert_int_eq(sscope_capture_view(c, "a", &v, &d), 0);
	ck_assert_int_eq(sscope_capture_select(v, "a", &d), -EINVAL);
	sscope_capture_free(v);
	sscope_capture_free(c); /* the dropped channels were freed already */
}
END_TEST

/* a 100 Hz record with two gaps (3 samples lost) and one NaN */
START_TEST(loaded_capture_carries_timing)
{
	char dir[] = "/tmp/sscope-cap-XXXXXX", path[64];
	struct sscope_capture *c;
	struct sscope_reader_opts o = { 0 };
	struct sscope_diag d;
	double t[2000], scratch[2000];
	struct sscope_timing tm;
	size_t n = 0;
	FILE *f;

	ck_assert_ptr_nonnull(mkdtemp(dir));
	snprintf(path, sizeof(path), "%s/t.csv", dir);
	f = fopen(path, "w");
	ck_assert_ptr_nonnull(f);
	fprintf(f, "time [s],gx [deg/s],gy [deg/s]\n");
	for (size_t i = 0; i < 2003; i++) {
		if (i == 700 || i == 701 || i == 1500)
			continue;
		t[n++] = (double)i * 0.01;
		fprintf(f, "%.17g,%.17g,%s\n", (double)i * 0.01, 0.25 * (double)(i % 7),
			i == 42 ? "nan" : "1.25");
	}
	fclose(f);
	o.nan_as_gap = true;
	ck_assert_int_eq(sscope_capture_load(&c, path, &o, &d), 0);
	ck_assert_int_eq(sscope_timing_analyze(t, n, 1.5, &tm, NULL, 0, NULL,
					       scratch), 0);
	ck_assert(c->has_timing);
	ck_assert_uint_eq(c->timing.n_gaps, 2);
	ck_assert_uint_eq(c->timing.n_missing, 3);
	ck_assert(c->timing.rate_hz == tm.rate_hz);
	ck_assert(c->rate_hz == tm.rate_hz);
	ck_assert_uint_eq(c->n_gaps, 2);
	ck_assert_uint_eq(c->gaps[0].index, 700);
	ck_assert_uint_eq(c->gaps[1].missing, 1);
	ck_assert_uint_eq(c->channels[0].n_nan, 0);
	ck_assert_uint_eq(c->channels[1].n_nan, 1);
	ck_assert_uint_eq(c->n_nan, 1);
	sscope_capture_free(c);
	/* a given rate is the rate; the time column is still analysed */
	o.rate_hz = 50;
	ck_assert_int_eq(sscope_capture_load(&c, path, &o, &d), 0);
	ck_assert(c->rate_hz == 50);
	ck_assert(c->has_timing && c->timing.rate_hz == tm.rate_hz);
	sscope_capture_free(c);
	unlink(path);
	rmdir(dir);
}
END_TEST

/* the streaming form gives sscope_timing_analyze()'s numbers whatever the
 * chunking (every field but the jitter exactly, on a record shorter than
 * its median block) */
START_TEST(timing_stream_equals_whole)
{
	enum { N = 5000 };
	static double t[N], scratch[N];
	struct sscope_timing a, b;
	struct sscope_timing_stream *ts;
	static const size_t chunks[] = { 1, 2, 7, 4999, 5000 };
	size_t k = 0;

	for (size_t i = 0; k < N; i++) {
		if (i % 997 == 5)
			continue; /* gaps */
		/* 1 kHz, stamps rounded to 1 us, wobbling by 3 us */
		t[k++] = round(((double)i * 1e-3 + 3e-6 * sin(0.37 * (double)i)) * 1e6) / 1e6;
	}
	ck_assert_int_eq(sscope_timing_analyze(t, N, 1.5, &a, NULL, 0, NULL, scratch), 0);
	for (size_t c = 0; c < sizeof(chunks) / sizeof(chunks[0]); c++) {
		ck_assert_int_eq(sscope_timing_stream_new(&ts, 1.5), 0);
		for (size_t i = 0; i < N; i += chunks[c])
			ck_assert_int_eq(sscope_timing_stream_feed(ts, t + i,
				i + chunks[c] <= N ? chunks[c] : N - i), 0);
		ck_assert_int_eq(sscope_timing_stream_result(ts, &b), 0);
		ck_assert(b.rate_hz == a.rate_hz);
		ck_assert(b.dt_median_s == a.dt_median_s);
		ck_assert(b.dt_min_s == a.dt_min_s && b.dt_max_s == a.dt_max_s);
		ck_assert_uint_eq(b.n_gaps, a.n_gaps);
		ck_assert_uint_eq(b.n_missing, a.n_missing);
		ck_assert_uint_eq(b.n_backwards, a.n_backwards);
		ck_assert_rel(b.jitter_rms_s, a.jitter_rms_s, 1e-9);
		sscope_timing_stream_free(ts);
	}
	ck_assert_uint_eq(a.n_gaps, 6);
	/* disorder: a swapped pair and a step back at the end are neither
	 * gaps nor regular intervals, in both forms; the interval after a
	 * repeated stamp (rows 1 and 2000) is a gap of two periods; the
	 * order is described alike */
	t[1] = t[0];
	{
		double x = t[100];

		t[100] = t[101];
		t[101] = x;
	}
	t[2000] = t[1999];
	t[N - 1] = t[N - 3];
	ck_assert_int_eq(sscope_timing_analyze(t, N, 1.5, &a, NULL, 0, NULL, scratch), 0);
	ck_assert_uint_eq(a.n_gaps, 8);
	for (size_t c = 0; c < sizeof(chunks) / sizeof(chunks[0]); c++) {
		ck_assert_int_eq(sscope_timing_stream_new(&ts, 1.5), 0);
		for (size_t i = 0; i < N; i += chunks[c])
			ck_assert_int_eq(sscope_timing_stream_feed(ts, t + i,
				i + chunks[c] <= N ? chunks[c] : N - i), 0);
		ck_assert_int_eq(sscope_timing_stream_result(ts, &b), 0);
		ck_assert(b.rate_hz == a.rate_hz);
		ck_assert_uint_eq(b.n_gaps, a.n_gaps);
		ck_assert_uint_eq(b.n_missing, a.n_missing);
		ck_assert_uint_eq(b.n_backwards, a.n_backwards);
		ck_assert_uint_eq(b.order.n_swaps, a.order.n_swaps);
		ck_assert_uint_eq(b.order.n_repeats, a.order.n_repeats);
		ck_assert_uint_eq(b.order.first_row, a.order.first_row);
		ck_assert_rel(b.jitter_rms_s, a.jitter_rms_s, 1e-9);
		sscope_timing_stream_free(ts);
	}
}
END_TEST

/* past the median block: the rate of a long regular record is exact */
START_TEST(timing_stream_long)
{
	const size_t n = 3 * SSCOPE_TIMING_STREAM_BLOCK + 17;
	struct sscope_timing_stream *ts;
	struct sscope_timing tm;
	double chunk[1000];
	size_t done = 0;

	ck_assert_int_eq(sscope_timing_stream_new(&ts, 1.5), 0);
	while (done < n) {
		size_t m = n - done < 1000 ? n - done : 1000;

		for (size_t i = 0; i < m; i++)
			chunk[i] = (double)(done + i) * 0.0025; /* 400 Hz */
		ck_assert_int_eq(sscope_timing_stream_feed(ts, chunk, m), 0);
		done += m;
	}
	ck_assert_int_eq(sscope_timing_stream_result(ts, &tm), 0);
	ck_assert_rel(tm.rate_hz, 400, 1e-12);
	ck_assert_uint_eq(tm.n_gaps, 0);
	ck_assert(tm.jitter_rms_s < 1e-12);
	sscope_timing_stream_free(ts);
	/* errors */
	ck_assert_int_eq(sscope_timing_stream_new(&ts, 1), -EINVAL);
	ck_assert_int_eq(sscope_timing_stream_new(&ts, 1.5), 0);
	ck_assert_int_eq(sscope_timing_stream_feed(ts, NULL, 3), -EINVAL);
	ck_assert_int_eq(sscope_timing_stream_result(ts, &tm), -EDOM);
	chunk[0] = chunk[1] = chunk[2] = 4;
	ck_assert_int_eq(sscope_timing_stream_feed(ts, chunk, 3), 0);
	ck_assert_int_eq(sscope_timing_stream_result(ts, &tm), -EDOM);
	ck_assert_uint_eq(tm.n_backwards, 2);
	sscope_timing_stream_free(ts);
}
END_TEST

/* A calibration file's triads on a capture: parameters in the file's
 * units (g), data held in SI: corrected = T K (y - b), output units, file
 * columns kept; partial triads, other units and missing ones refused. */
START_TEST(calibration_applied)
{
	static const char *const names[4] = { "ax", "ay", "az", "gx" };
	struct sscope_capture *c = sscope_capture_new(4, 2, false, false);
	struct sscope_calib_file_triad t[2];
	struct sscope_diag d;
	unsigned skipped;
	size_t applied;
	const double G = 9.80665;

	ck_assert_ptr_nonnull(c);
	c->source = ssc_strdup("imu.csv");
	for (size_t k = 0; k < 4; k++) {
		ck_assert_int_eq(sscope_capture_set_channel(c, k, names[k],
							    k < 3 ? "g" : "rad/s"), 0);
		c->channels[k].col.index = k + 1;
		for (size_t i = 0; i < 2; i++)
			c->channels[k].data[i] = (k < 3 ? G : 1) * (0.25 * (double)k + (double)i);
	}
	memset(t, 0, sizeof(t));
	strcpy(t[0].kind, "accel");
	strcpy(t[0].input_unit, "g");
	strcpy(t[0].output_unit, "m/s^2");
	for (int i = 0; i < 3; i++)
		strcpy(t[0].channels[i], names[i]);
	sscope_calib_triad_identity(&t[0].c);
	t[0].c.bias[0] = 0.01;        /* g */
	t[0].c.scale[1] = 2 * G;      /* m/s^2 per g */
	t[0].c.mis[0][1] = 0.5;
	t[1] = t[0];
	strcpy(t[1].kind, "gyro");
	strcpy(t[1].channels[0], "gx");
	strcpy(t[1].channels[1], "gy");
	strcpy(t[1].channels[2], "gz");
	ck_assert_int_eq(sscope_capture_apply_calib(c, t, 1, &skipped, &applied, &d), 0);
	ck_assert_uint_eq(applied, 1);
	ck_assert_uint_eq(skipped, 0);
	/* row 1: y = (1, 1.25, 1.5) g; K = (1, 2 G, 1) m/s^2 per g, so
	 * K (y - b) = (0.99, 2.5 G, 1.5) m/s^2, then T adds 0.5 of the second
	 * to the first */
	ck_assert_rel(c->channels[0].data[1], 0.99 + 0.5 * 2.5 * G, 1e-14);
	ck_assert_rel(c->channels[1].data[1], 2.5 * G, 1e-14);
	ck_assert_str_eq(c->channels[0].col.unit_label, "m/s^2");
	ck_assert_int_eq(c->channels[0].col.quantity, SSCOPE_QUANTITY_ACCELERATION);
	ck_assert_uint_eq(c->channels[2].col.index, 3);
	/* the gyro triad: only gx is there */
	ck_assert_int_eq(sscope_capture_apply_calib(c, t + 1, 1, NULL, NULL, &d), -EINVAL);
	ck_assert_ptr_nonnull(strstr(d.msg, "needs all three channels"));
	/* a triad in g on a channel in rad/s */
	strcpy(t[1].channels[1], "ay");
	strcpy(t[1].channels[2], "az");
	ck_assert_int_eq(sscope_capture_apply_calib(c, t + 1, 1, NULL, NULL, &d), -EINVAL);
	ck_assert_ptr_nonnull(strstr(d.msg, "channel gx is in rad/s, the calibration expects g"));
	/* no channel of it */
	strcpy(t[1].channels[0], "wx");
	strcpy(t[1].channels[1], "wy");
	strcpy(t[1].channels[2], "wz");
	ck_assert_int_eq(sscope_capture_apply_calib(c, t + 1, 1, NULL, &applied, &d), -EDOM);
	ck_assert_uint_eq(applied, 0);
	ck_assert_ptr_nonnull(strstr(d.msg, "imu.csv"));
	sscope_capture_free(c);
}
END_TEST

/* One way in: sscope_capture_open() is load, calibration, selection and
 * the rate checks, in that order; its notes and its failing stage. */
START_TEST(open_in_one_call)
{
	char dir[] = "/tmp/sscope-open-XXXXXX", path[64];
	struct sscope_capture_open_opts o;
	struct sscope_reader_opts ro2;
	struct sscope_capture_notes nt;
	struct sscope_calib_file_triad t;
	struct sscope_capture *c, *ref;
	struct sscope_diag d;
	FILE *f;

	ck_assert_ptr_nonnull(mkdtemp(dir));
	snprintf(path, sizeof(path), "%s/imu.csv", dir);
	f = fopen(path, "w");
	ck_assert_ptr_nonnull(f);
	fprintf(f, "time [s],ax [g],ay [g],az [g],gx [rad/s]\n");
	for (int i = 0; i < 50; i++)
		fprintf(f, "%g,%g,%g,%g,%g\n", 0.01 * i, 0.001 * i, 0.5, 1.0,
			0.002 * (i % 7));
	ck_assert_int_eq(fclose(f), 0);

	/* an accelerometer triad (g in, m/s^2 out), then select "gx, ay" */
	memset(&t, 0, sizeof(t));
	strcpy(t.kind, "accel");
	strcpy(t.input_unit, "g");
	strcpy(t.output_unit, "m/s^2");
	strcpy(t.channels[0], "ax");
	strcpy(t.channels[1], "ay");
	strcpy(t.channels[2], "az");
	sscope_calib_triad_identity(&t.c);
	t.c.bias[1] = 0.25;
	memset(&o, 0, sizeof(o));
	memset(&ro2, 0, sizeof(ro2));
	o.read = &ro2;
	ro2.columns = "gx, ay";
	ro2.rate_hz = 50; /* the time column says 100 Hz */
	o.calib = &t;
	o.n_calib = 1;
	ck_assert_int_eq(sscope_capture_open(&c, path, &o, &nt, &d), 0);
	ck_assert_int_eq(nt.stage, SSCOPE_CAPTURE_STAGE_DONE);
	names_are(c, "gx,ay");
	ck_assert_str_eq(c->channels[1].col.unit_label, "m/s^2");
	/* (scale 1 m/s^2 per g: the identity of the triad's units) */
	ck_assert_rel(c->channels[1].data[3], 0.5 - 0.25, 1e-12);
	ck_assert(nt.rate_disagrees);
	ck_assert_rel(nt.time_column_rate_hz, 100, 1e-9);
	ck_assert(!nt.unit_unused && !nt.unterminated);

	/* the same as the four calls it replaces */
	{
		struct sscope_reader_opts ro = { 0 };

		ro.rate_hz = 50;
		ck_assert_int_eq(sscope_capture_load(&ref, path, &ro, &d), 0);
		ck_assert_int_eq(sscope_capture_apply_calib(ref, &t, 1, NULL, NULL, &d), 0);
		ck_assert_int_eq(sscope_capture_select(ref, "gx, ay", &d), 0);
		for (size_t k = 0; k < 2; k++)
			ck_assert_mem_eq(ref->channels[k].data, c->channels[k].data,
					 50 * sizeof(double));
		sscope_capture_free(ref);
	}
	sscope_capture_free(c);

	/* a default unit no channel takes; an unknown column fails in the
	 * reader (which reads only the columns named), or at the selection
	 * after a calibration (which reads them all), with no capture */
	memset(&o, 0, sizeof(o));
	memset(&ro2, 0, sizeof(ro2));
	o.read = &ro2;
	ro2.default_unit = "deg/s";
	ck_assert_int_eq(sscope_capture_open(&c, path, &o, &nt, &d), 0);
	ck_assert(nt.unit_unused && !nt.rate_disagrees);
	sscope_capture_free(c);
	ro2.default_unit = NULL;
	ro2.columns = "ax, bogus";
	ck_assert_int_eq(sscope_capture_open(&c, path, &o, &nt, &d), -EINVAL);
	ck_assert_ptr_null(c);
	ck_assert_int_eq(nt.stage, SSCOPE_CAPTURE_STAGE_READ);
	ck_assert_ptr_nonnull(strstr(d.msg, "no column 'bogus'"));
	strcpy(t.channels[0], "ax");
	o.calib = &t;
	o.n_calib = 1;
	ck_assert_int_eq(sscope_capture_open(&c, path, &o, &nt, &d), -EINVAL);
	ck_assert_ptr_null(c);
	ck_assert_int_eq(nt.stage, SSCOPE_CAPTURE_STAGE_SELECT);
	ck_assert_ptr_nonnull(strstr(d.msg, "no column 'bogus'"));
	/* a calibration whose channels are missing fails at its stage */
	memset(&o, 0, sizeof(o));
	strcpy(t.channels[0], "wx");
	o.calib = &t;
	o.n_calib = 1;
	ck_assert_int_eq(sscope_capture_open(&c, path, &o, &nt, &d), -EINVAL);
	ck_assert_int_eq(nt.stage, SSCOPE_CAPTURE_STAGE_CALIBRATE);
	ck_assert_ptr_null(c);
	unlink(path);
	rmdir(dir);
}
END_TEST

/* Receive times against stamps: latency statistics, agreement. */
START_TEST(latency_and_agreement)
{
	double t[5] = { 0, 0.01, 0.02, 0.03, 0.04 }, rx[5], sc[5], med, lo, hi;
	struct sscope_timing a = { .rate_hz = 100, .n_gaps = 1, .n_backwards = 0 };
	struct sscope_timing b = a;

	for (int i = 0; i < 5; i++)
		rx[i] = t[i] + 0.001 * (i == 3 ? 7 : i + 1);
	ck_assert_int_eq(sscope_timing_latency(rx, t, 5, &med, &lo, &hi, sc), 0);
	ck_assert_rel(med, 0.003, 1e-12);
	ck_assert_rel(lo, 0.001, 1e-12);
	ck_assert_rel(hi, 0.007, 1e-12);
	rx[2] = NAN;
	ck_assert_int_eq(sscope_timing_latency(rx, t, 5, &med, &lo, &hi, sc), -EDOM);
	ck_assert_int_eq(sscope_timing_latency(rx, t, 0, &med, &lo, &hi, sc), -EDOM);
	ck_assert(sscope_timing_agree(&a, &b, 1e-3));
	b.rate_hz = 100.2;
	ck_assert(!sscope_timing_agree(&a, &b, 1e-3));
	b.rate_hz = 100.05;
	ck_assert(sscope_timing_agree(&a, &b, 1e-3));
	b.n_backwards = 1;
	ck_assert(!sscope_timing_agree(&a, &b, 1e-3));
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("capture");
	TCase *tc = tcase_create("capture");

	tcase_add_test(tc, view_order_blanks_indices);
	tcase_add_test(tc, unknown_names_are_errors);
	tcase_add_test(tc, select_in_place);
	tcase_add_test(tc, loaded_capture_carries_timing);
	tcase_add_test(tc, timing_stream_equals_whole);
	tcase_add_test(tc, timing_stream_long);
	tcase_add_test(tc, calibration_applied);
	tcase_add_test(tc, latency_and_agreement);
	tcase_add_test(tc, open_in_one_call);
	suite_add_tcase(s, tc);
	return s;
}
