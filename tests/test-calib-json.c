/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The calib result's JSON codec (src/workbench/calibfile.c): a result of a
 * gyro triad (deg/s in, with g-sensitivity, motions) and an accelerometer
 * triad (g in), encoded by ssc_calib_triad_out_json() and written as the
 * command writes it (15 significant digits), is read back by
 * ssc_calib_res_from_json() as the typed value the calib stage passes:
 * every correction value and uncertainty in SI, the error model and the
 * class; budget --result and navsim --from-calib read it so.  A result of
 * another command, or a malformed triad, is refused.  The calibration
 * file (ssc_calfile_triad_json(), read by ssc_calfile_read() in the file's
 * units, the input units that sscope_capture_open() applies) and the
 * inclinometer look-up table (ssc_inclino_lut_json(), read by
 * ssc_inclino_lut_read()) come back as they were written.
 */
#include "config.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "workbench.h"
#include "calibfile.h"
#include "results.h"
#include "check-main.h"

/* 15 significant digits, one unit conversion */
#define REL 1e-13

static void close_to(double got, double want, const char *what)
{
	if (isnan(want)) {
		ck_assert_msg(isnan(got), "%s: %.17g, want none", what, got);
		return;
	}
	ck_assert_msg(fabs(got - want) <= REL * fmax(fabs(got), fabs(want)) + 1e-300,
		      "%s: %.17g, want %.17g", what, got, want);
}

static void make_triad(struct ssc_calib_triad_out *o, bool gyro)
{
	struct sscope_calib_triad *c = &o->t.c;
	const double d2r = 0.017453292519943295;

	memset(o, 0, sizeof(*o));
	snprintf(o->t.kind, sizeof(o->t.kind), "%s", gyro ? "gyro" : "accel");
	for (int i = 0; i < 3; i++) {
		snprintf(o->t.channels[i], 64, "%s%c", gyro ? "g" : "a", 'x' + i);
		snprintf(o->t.accel_channels[i], 64, "a%c", 'x' + i);
	}
	snprintf(o->t.input_unit, sizeof(o->t.input_unit), "%s", gyro ? "deg/s" : "g");
	snprintf(o->t.output_unit, sizeof(o->t.output_unit), "%s", gyro ? "rad/s" : "m/s^2");
	o->q = gyro ? SSCOPE_QUANTITY_ANGULAR_RATE : SSCOPE_QUANTITY_ACCELERATION;
	sscope_calib_triad_identity(c);
	for (int i = 0; i < 3; i++) {
		/* SI, as the stage holds them */
		c->bias[i] = (gyro ? 0.0123 * d2r : 0.0211 * 9.80665) * (i + 1) * (i == 1 ? -1 : 1);
		c->scale[i] = (1 + 1.7e-3 * (i - 1)) * (gyro ? 1 : 1);
		c->bias_sd[i] = (gyro ? 1e-4 * d2r : 2e-4 * 9.80665) * (i + 2);
		c->scale_sd[i] = i == 2 && !gyro ? (double)NAN : 3.1e-5 * (i + 1);
		for (int j = 0; j < 3; j++) {
			c->mis[i][j] = i == j ? 1 : (i > j ? 1.3e-3 : -0.7e-3) * (i + j);
			c->mis_sd[i][j] = i == j ? 0 : 1e-5 * (i + j + 1);
			if (gyro) {
				c->gsens[i][j] = 2.1e-5 * d2r * (1 + i - j);
				c->gsens_sd[i][j] = 3e-6 * d2r * (1 + i + j);
			}
		}
	}
	c->has_gsens = gyro;
	c->n_params = gyro ? 21 : 12;
	c->poses = gyro ? 18 : 6;
	c->residual_rms = gyro ? 3.21e-3 : 1.7e-3;
	c->iterations = gyro ? 7 : 4;
	c->cond = gyro ? 41.5 : 12.25;
	o->residual_unit = gyro ? "1" : "m/s^2";
	o->noise_density = gyro ? 1.1e-4 : (double)NAN;
	if (gyro) {
		o->n_motion = 17;
		o->motion_rms = 0.013 * d2r;
		o->motion_max = 0.041 * d2r;
		o->motion_rms_bias_only = 0.22 * d2r;
	}
	ssc_calib_triad_finish(o);
}

static json_t *encode_decode(const struct ssc_calib_res *r, const char *cmd)
{
	json_t *root = json_object(), *tr = json_array(), *back;
	char *text;
	json_error_t err;

	json_object_set_new(root, "command", json_string(cmd));
	for (int k = 0; k < r->n_out; k++)
		json_array_append_new(tr, ssc_calib_triad_out_json(&r->out[k]));
	json_object_set_new(root, "triads", tr);
	text = json_dumps(root, JSON_REAL_PRECISION(15) | JSON_COMPACT);
	ck_assert_ptr_nonnull(text);
	back = json_loads(text, 0, &err);
	ck_assert_msg(back != NULL, "%s", err.text);
	free(text);
	json_decref(root);
	return back;
}

static void same_vec(const double *g, const double *w, size_t n, const char *what)
{
	char buf[64];

	for (size_t i = 0; i < n; i++) {
		snprintf(buf, sizeof(buf), "%s[%zu]", what, i);
		close_to(g[i], w[i], buf);
	}
}

static void same_triad(const struct ssc_calib_triad_out *g,
		       const struct ssc_calib_triad_out *w)
{
	const struct sscope_calib_triad *a = &g->t.c, *b = &w->t.c;

	ck_assert_str_eq(g->t.kind, w->t.kind);
	ck_assert_str_eq(g->t.input_unit, w->t.input_unit);
	ck_assert_str_eq(g->t.output_unit, w->t.output_unit);
	for (int i = 0; i < 3; i++) {
		ck_assert_str_eq(g->t.channels[i], w->t.channels[i]);
		if (b->has_gsens)
			ck_assert_str_eq(g->t.accel_channels[i], w->t.accel_channels[i]);
	}
	ck_assert_int_eq(g->q, w->q);
	same_vec(a->bias, b->bias, 3, "bias");
	same_vec(a->scale, b->scale, 3, "scale");
	same_vec(&a->mis[0][0], &b->mis[0][0], 9, "misalignment");
	same_vec(a->bias_sd, b->bias_sd, 3, "bias_sd");
	same_vec(a->scale_sd, b->scale_sd, 3, "scale_sd");
	same_vec(&a->mis_sd[0][0], &b->mis_sd[0][0], 9, "misalignment_sd");
	ck_assert_int_eq(a->has_gsens, b->has_gsens);
	if (b->has_gsens) {
		same_vec(&a->gsens[0][0], &b->gsens[0][0], 9, "g_sensitivity");
		same_vec(&a->gsens_sd[0][0], &b->gsens_sd[0][0], 9, "g_sensitivity_sd");
	}
	ck_assert_uint_eq(a->n_params, b->n_params);
	ck_assert_uint_eq(a->poses, b->poses);
	ck_assert_uint_eq(a->iterations, b->iterations);
	close_to(a->residual_rms, b->residual_rms, "residual_rms");
	close_to(a->cond, b->cond, "condition");
	ck_assert_ptr_nonnull(g->residual_unit);
	ck_assert_str_eq(g->residual_unit, w->residual_unit);
	close_to(g->noise_density, w->noise_density, "noise_density");
	ck_assert_int_eq(g->error_model, w->error_model);
	if (w->error_model)
		same_vec(&g->A[0][0], &w->A[0][0], 9, "error model A");
	ck_assert_int_eq(g->grade, w->grade);
	if (w->grade >= 0)
		ck_assert(fabs(g->grade_dist - w->grade_dist) < 1e-9);
	ck_assert_uint_eq(g->n_motion, w->n_motion);
	if (w->n_motion) {
		close_to(g->motion_rms, w->motion_rms, "motion rms");
		close_to(g->motion_max, w->motion_max, "motion max");
		close_to(g->motion_rms_bias_only, w->motion_rms_bias_only, "motion rms bias only");
	}
}

START_TEST(triads_round_trip)
{
	struct ssc_calib_res r = { 0 }, back;
	json_t *root;

	make_triad(&r.out[0], false);
	make_triad(&r.out[1], true);
	r.n_out = 2;
	/* the case is worth testing: both have an error model, the
	 * units differ from SI, the gyro has G and motions */
	ck_assert(r.out[0].error_model && r.out[1].error_model);
	root = encode_decode(&r, "calib");
	ck_assert_int_eq(ssc_calib_res_from_json(root, &back), 0);
	ck_assert_int_eq(back.n_out, 2);
	same_triad(&back.out[0], &r.out[0]);
	same_triad(&back.out[1], &r.out[1]);
	json_decref(root);
}
END_TEST

START_TEST(refuses_what_it_cannot_read)
{
	struct ssc_calib_res r = { 0 }, back;
	json_t *root, *t;

	make_triad(&r.out[0], true);
	r.n_out = 1;
	root = encode_decode(&r, "allan");
	ck_assert_int_eq(ssc_calib_res_from_json(root, &back), -EINVAL);
	json_decref(root);
	root = encode_decode(&r, "calib");
	t = json_array_get(json_object_get(root, "triads"), 0);
	json_object_set_new(t, "bias", json_null());
	ck_assert_int_eq(ssc_calib_res_from_json(root, &back), -EINVAL);
	json_decref(root);
	/* more triads than a result holds */
	r.out[1] = r.out[0];
	r.n_out = 2;
	root = encode_decode(&r, "calib");
	json_array_append(json_object_get(root, "triads"),
			  json_array_get(json_object_get(root, "triads"), 0));
	ck_assert_int_eq(ssc_calib_res_from_json(root, &back), -E2BIG);
	ck_assert_int_eq(back.n_out, 2);
	json_decref(root);
}
END_TEST

/* text of @p j in a new temporary file (its path in @p path) */
static void put_json(json_t *j, char *path)
{
	int fd = mkstemp(path);
	FILE *f;

	ck_assert_int_ge(fd, 0);
	f = fdopen(fd, "w");
	ck_assert_ptr_nonnull(f);
	ck_assert_int_eq(json_dumpf(j, f, JSON_REAL_PRECISION(17) | JSON_INDENT(1)), 0);
	ck_assert_int_eq(fclose(f), 0);
}

START_TEST(calibration_file_round_trip)
{
	struct ssc_calib_triad_out o[2];
	json_t *root = json_object(), *arr = json_array();
	struct sscope_calib_file_triad *t = NULL;
	size_t n = 0;
	char path[] = "/tmp/ssc-calfile-XXXXXX";

	make_triad(&o[0], false);
	make_triad(&o[1], true);
	json_object_set_new(root, "format", json_string("sensorscope-calibration"));
	json_object_set_new(root, "version", json_integer(1));
	for (int k = 0; k < 2; k++)
		json_array_append_new(arr, ssc_calfile_triad_json(&o[k].t));
	json_object_set_new(root, "triads", arr);
	put_json(root, path);
	json_decref(root);
	ck_assert_int_eq(ssc_calfile_read("test", path, &t, &n), 0);
	unlink(path);
	ck_assert_uint_eq(n, 2);
	for (int k = 0; k < 2; k++) {
		const struct sscope_calib_triad *w = &o[k].t.c, *g = &t[k].c;
		/* the file holds input units: bias / s, scale * s, G / s */
		double s = ssc_calfile_unit_scale(o[k].t.input_unit);

		ck_assert(s != 1);
		ck_assert_str_eq(t[k].kind, o[k].t.kind);
		ck_assert_str_eq(t[k].input_unit, o[k].t.input_unit);
		ck_assert_str_eq(t[k].output_unit, o[k].t.output_unit);
		for (int i = 0; i < 3; i++) {
			ck_assert_str_eq(t[k].channels[i], o[k].t.channels[i]);
			close_to(g->bias[i] * s, w->bias[i], "bias");
			close_to(g->scale[i] / s, w->scale[i], "scale");
			for (int j = 0; j < 3; j++) {
				close_to(g->mis[i][j], w->mis[i][j], "misalignment");
				close_to(g->gsens[i][j] * s, w->gsens[i][j], "g_sensitivity");
			}
		}
		ck_assert_int_eq(g->has_gsens, w->has_gsens);
	}
	free(t);
}
END_TEST

START_TEST(inclinometer_table_round_trip)
{
	struct sscope_inclino_lut lut, back;
	json_t *root = json_object();
	char path[] = "/tmp/ssc-lut-XXXXXX";

	memset(&lut, 0, sizeof(lut));
	lut.n = 3;
	lut.gravity_m_s2 = 9.80943;
	for (size_t k = 0; k < lut.n; k++) {
		struct sscope_inclino_params *p = &lut.p[k];

		lut.temp_degc[k] = -20.5 + 31.25 * (double)k;
		for (int i = 0; i < 3; i++) {
			p->offset[i] = 0.0123 * (i + 1) - 0.002 * (double)k;
			p->scale[i] = 1 + 1.1e-3 * (i - 1) + 2e-5 * (double)k;
			p->offset_sd[i] = 1.7e-4 * (i + 1);
			p->scale_sd[i] = 2.3e-5 * (i + 2);
			for (int j = 0; j < 3; j++) {
				p->mis[i][j] = i == j ? 0 : 1.9e-3 * (i - j) + 1e-4 * (double)k;
				p->mis_sd[i][j] = 3e-5 * (i + j + 1);
			}
		}
		p->residual_rms = 4.1e-4 + 1e-5 * (double)k;
		p->poses = 12 + k;
	}
	json_object_set_new(root, "command", json_string("inclino"));
	json_object_set_new(root, "lut", ssc_inclino_lut_json(&lut, true));
	put_json(root, path);
	json_decref(root);
	ck_assert_int_eq(ssc_inclino_lut_read("test", path, &back), 0);
	unlink(path);
	ck_assert_uint_eq(back.n, lut.n);
	close_to(back.gravity_m_s2, lut.gravity_m_s2, "gravity");
	for (size_t k = 0; k < lut.n; k++) {
		const struct sscope_inclino_params *p = &lut.p[k], *q = &back.p[k];

		close_to(back.temp_degc[k], lut.temp_degc[k], "temperature");
		same_vec(q->offset, p->offset, 3, "offset");
		same_vec(q->scale, p->scale, 3, "scale");
		same_vec(&q->mis[0][0], &p->mis[0][0], 9, "misalignment");
		same_vec(q->offset_sd, p->offset_sd, 3, "offset_sd");
		same_vec(q->scale_sd, p->scale_sd, 3, "scale_sd");
		same_vec(&q->mis_sd[0][0], &p->mis_sd[0][0], 9, "misalignment_sd");
		close_to(q->residual_rms, p->residual_rms, "residual_rms");
		ck_assert_uint_eq(q->poses, p->poses);
	}
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("calib-json");
	TCase *tc = tcase_create("calib-json");

	tcase_set_timeout(tc, 60);
	tcase_add_test(tc, triads_round_trip);
	tcase_add_test(tc, refuses_what_it_cannot_read);
	tcase_add_test(tc, calibration_file_round_trip);
	tcase_add_test(tc, inclinometer_table_round_trip);
	suite_add_tcase(s, tc);
	return s;
}


