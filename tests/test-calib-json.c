/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The calib result's JSON codec (src/workbench/calibfile.c): a result of a
 * gyro triad (deg/s in, with g-sensitivity, motions) and an accelerometer
 * triad (g in), encoded by ssc_calib_triad_out_json() and written as the
 * command writes it (15 significant digits), is read back by
 * ssc_calib_res_from_json() as the typed value the calib stage passes:
 * every correction value and uncertainty in SI, the error model and the
 * class; budget --result and navsim --from-calib read it so.  A result of
 * another command, or a malformed triad, is refused.
 */
#include "config.h"

#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

static Suite *make_suite(void)
{
	Suite *s = suite_create("calib-json");
	TCase *tc = tcase_create("calib-json");

	tcase_set_timeout(tc, 60);
	tcase_add_test(tc, triads_round_trip);
	tcase_add_test(tc, refuses_what_it_cannot_read);
	suite_add_tcase(s, tc);
	return s;
}


