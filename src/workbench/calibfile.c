/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Calibration files: written by `sensorscope calib`, applied to captures
 * by the shared option --calibration FILE (read here, applied by
 * sscope_capture_open() when ssc_load() reads a capture).
 *
 * Format (JSON, one object):
 *   {"format": "sensorscope-calibration", "version": 1,
 *    "created_by": "sensorscope 0.1.0 calib accel",
 *    "triads": [{"kind": "accel" | "gyro",
 *                "channels": ["ax", "ay", "az"],
 *                "input_unit": "g",            (unit of the raw channels)
 *                "output_unit": "m/s^2",       (unit after correction)
 *                "bias": [3],                  (input units)
 *                "scale": [3],                 (output unit per input unit)
 *                "misalignment": [[3], [3], [3]],  (unit diagonal)
 *                "g_sensitivity": [[3], [3], [3]] or null
 *                                              (input units per m/s^2),
 *                "accel_channels": ["ax", "ay", "az"] (gyros with G)}]}
 * Correction: u' = T K (y - b - G a'), a' the corrected accelerometer.
 * Triads are applied in file order (accelerometers before gyros).
 */
#include "workbench.h"
#include "calibfile.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* a vector and a matrix, each value times @p mul */
static json_t *vec3(const double v[3], double mul)
{
	json_t *a = json_array();

	for (int i = 0; i < 3; i++)
		json_array_append_new(a, ssc_jreal(v[i] * mul));
	return a;
}

static json_t *mat3(const double m[3][3], double mul)
{
	json_t *a = json_array();

	for (int i = 0; i < 3; i++)
		json_array_append_new(a, vec3(m[i], mul));
	return a;
}

/* SI scale of a unit label ("" or unknown dimension: 1) */
double ssc_calfile_unit_scale(const char *unit)
{
	struct sscope_unit u;

	if (!unit || !*unit || sscope_unit_parse(unit, &u, NULL))
		return 1;
	return u.scale;
}

json_t *ssc_calfile_triad_json(const struct sscope_calib_file_triad *t)
{
	json_t *o = json_object(), *ch = json_array();
	double s = ssc_calfile_unit_scale(t->input_unit);
	double b[3], k[3], G[3][3];

	for (int i = 0; i < 3; i++) {
		json_array_append_new(ch, json_string(t->channels[i]));
		b[i] = t->c.bias[i] / s;
		k[i] = t->c.scale[i] * s;
		for (int j = 0; j < 3; j++)
			G[i][j] = t->c.gsens[i][j] / s;
	}
	json_object_set_new(o, "kind", json_string(t->kind));
	json_object_set_new(o, "channels", ch);
	json_object_set_new(o, "input_unit", json_string(t->input_unit));
	json_object_set_new(o, "output_unit", json_string(t->output_unit));
	json_object_set_new(o, "bias", vec3(b, 1));
	json_object_set_new(o, "scale", vec3(k, 1));
	json_object_set_new(o, "misalignment", mat3(t->c.mis, 1));
	if (t->c.has_gsens) {
		json_t *ac = json_array();

		json_object_set_new(o, "g_sensitivity", mat3(G, 1));
		for (int i = 0; i < 3; i++)
			json_array_append_new(ac, json_string(t->accel_channels[i]));
		json_object_set_new(o, "accel_channels", ac);
	} else {
		json_object_set_new(o, "g_sensitivity", json_null());
	}
	return o;
}

int ssc_calfile_write(const struct ssc_common *co, const char *path,
		      const struct sscope_calib_file_triad *t, size_t n)
{
	struct ssc_common c2 = *co;
	json_t *root = json_object(), *arr = json_array();
	char by[128];

	snprintf(by, sizeof(by), "sensorscope %s %s", PACKAGE_VERSION, co->cmd);
	json_object_set_new(root, "format", json_string("sensorscope-calibration"));
	json_object_set_new(root, "version", json_integer(1));
	json_object_set_new(root, "created_by", json_string(by));
	for (size_t i = 0; i < n; i++)
		json_array_append_new(arr, ssc_calfile_triad_json(&t[i]));
	json_object_set_new(root, "triads", arr);
	c2.output = path;
	{
		struct ssc_out out;
		int rc = ssc_out_open(&c2, &out);
		bool ok;

		if (rc) {
			json_decref(root);
			return rc;
		}
		ok = json_dumpf(root, out.f, JSON_REAL_PRECISION(17) |
					     JSON_INDENT(1)) == 0;
		if (ok)
			fputc('\n', out.f);
		json_decref(root);
		return ssc_out_close(&c2, &out, ok);
	}
}

static int get_vec(json_t *o, const char *key, double v[3])
{
	json_t *a = json_object_get(o, key);

	if (!json_is_array(a) || json_array_size(a) != 3)
		return -1;
	for (int i = 0; i < 3; i++) {
		json_t *x = json_array_get(a, (size_t)i);

		if (!json_is_number(x))
			return -1;
		v[i] = json_number_value(x);
		if (!isfinite(v[i]))
			return -1;
	}
	return 0;
}

static int get_mat(json_t *o, const char *key, double m[3][3])
{
	json_t *a = json_object_get(o, key);

	if (!json_is_array(a) || json_array_size(a) != 3)
		return -1;
	for (int i = 0; i < 3; i++) {
		json_t *row = json_array_get(a, (size_t)i);

		if (!json_is_array(row) || json_array_size(row) != 3)
			return -1;
		for (int j = 0; j < 3; j++) {
			json_t *x = json_array_get(row, (size_t)j);

			if (!json_is_number(x))
				return -1;
			m[i][j] = json_number_value(x);
			if (!isfinite(m[i][j]))
				return -1;
		}
	}
	return 0;
}

static int get_names(json_t *o, const char *key, char names[3][64])
{
	json_t *a = json_object_get(o, key);

	if (!json_is_array(a) || json_array_size(a) != 3)
		return -1;
	for (int i = 0; i < 3; i++) {
		json_t *x = json_array_get(a, (size_t)i);

		if (!json_is_string(x) || strlen(json_string_value(x)) >= 64)
			return -1;
		strcpy(names[i], json_string_value(x));
	}
	return 0;
}

int ssc_calfile_read(const char *cmd, const char *path,
		     struct sscope_calib_file_triad **out, size_t *n_out)
{
	json_t *root = ssc_json_read(cmd, "calibration", path,
				     "a calibration file of 'sensorscope calib'"), *arr;
	struct sscope_calib_file_triad *t = NULL;
	size_t n;

	*out = NULL;
	*n_out = 0;
	if (!root)
		return SSC_EXIT_FAIL;
	if (!json_is_string(json_object_get(root, "format")) ||
	    strcmp(json_string_value(json_object_get(root, "format")),
		   "sensorscope-calibration") ||
	    json_integer_value(json_object_get(root, "version")) != 1 ||
	    !json_is_array(arr = json_object_get(root, "triads"))) {
		ssc_err(cmd, "--calibration: %s: not a sensorscope calibration file (version 1)",
			path);
		json_decref(root);
		return SSC_EXIT_FAIL;
	}
	n = json_array_size(arr);
	t = calloc(n ? n : 1, sizeof(*t));
	if (!t) {
		json_decref(root);
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	for (size_t i = 0; i < n; i++) {
		json_t *o = json_array_get(arr, i), *g;
		const char *kind = json_string_value(json_object_get(o, "kind"));
		const char *iu = json_string_value(json_object_get(o, "input_unit"));
		const char *ou = json_string_value(json_object_get(o, "output_unit"));
		struct sscope_unit u;

		sscope_calib_triad_identity(&t[i].c);
		if (!kind || !iu || !ou || strlen(iu) >= sizeof(t[i].input_unit) ||
		    strlen(ou) >= sizeof(t[i].output_unit) ||
		    (strcmp(kind, "accel") && strcmp(kind, "gyro")) ||
		    get_names(o, "channels", t[i].channels) ||
		    get_vec(o, "bias", t[i].c.bias) ||
		    get_vec(o, "scale", t[i].c.scale) ||
		    get_mat(o, "misalignment", t[i].c.mis) ||
		    (*iu && sscope_unit_parse(iu, &u, NULL)) ||
		    sscope_unit_parse(ou, &u, NULL)) {
			ssc_err(cmd, "--calibration: %s: triad %zu is malformed",
				path, i + 1);
			free(t);
			json_decref(root);
			return SSC_EXIT_FAIL;
		}
		strcpy(t[i].kind, kind);
		strcpy(t[i].input_unit, iu);
		strcpy(t[i].output_unit, ou);
		g = json_object_get(o, "g_sensitivity");
		if (g && !json_is_null(g)) {
			if (get_mat(o, "g_sensitivity", t[i].c.gsens) ||
			    get_names(o, "accel_channels", t[i].accel_channels)) {
				ssc_err(cmd, "--calibration: %s: triad %zu: bad g_sensitivity",
					path, i + 1);
				free(t);
				json_decref(root);
				return SSC_EXIT_FAIL;
			}
			t[i].c.has_gsens = true;
		}
	}
	json_decref(root);
	*out = t;
	*n_out = n;
	return SSC_EXIT_OK;
}

json_t *ssc_calib_triad_out_json(const struct ssc_calib_triad_out *o)
{
	json_t *j = ssc_calfile_triad_json(&o->t);
	const struct sscope_calib_triad *c = &o->t.c;
	double s = ssc_calfile_unit_scale(o->t.input_unit);
	char buf[96];
	size_t ng;
	const struct sscope_calib_class *gr = sscope_calib_grades(&ng);

	json_object_set_new(j, "bias_unit", json_string(o->t.input_unit));
	json_object_set_new(j, "bias_sd", vec3(c->bias_sd, 1 / s));
	snprintf(buf, sizeof(buf), "%s per %s", o->t.output_unit,
		 o->t.input_unit[0] ? o->t.input_unit : "count");
	json_object_set_new(j, "scale_unit", json_string(buf));
	json_object_set_new(j, "scale_sd", vec3(c->scale_sd, s));
	json_object_set_new(j, "misalignment_sd", mat3(c->mis_sd, 1));
	if (c->has_gsens) {
		snprintf(buf, sizeof(buf), "%s per m/s^2",
			 o->t.input_unit[0] ? o->t.input_unit : "count");
		json_object_set_new(j, "g_sensitivity_sd", mat3(c->gsens_sd, 1 / s));
		json_object_set_new(j, "g_sensitivity_unit", json_string(buf));
	}
	json_object_set_new(j, "residual_rms", ssc_jreal(c->residual_rms));
	json_object_set_new(j, "residual_unit", json_string(o->residual_unit));
	json_object_set_new(j, "poses", json_integer((json_int_t)c->poses));
	json_object_set_new(j, "parameters", json_integer(c->n_params));
	json_object_set_new(j, "iterations", json_integer(c->iterations));
	json_object_set_new(j, "condition", ssc_jreal(c->cond));
	if (o->n_motion) {
		json_t *m = json_object();

		json_object_set_new(m, "motions", json_integer((json_int_t)o->n_motion));
		json_object_set_new(m, "rms", ssc_jreal(o->motion_rms * 180 / PI));
		json_object_set_new(m, "max", ssc_jreal(o->motion_max * 180 / PI));
		json_object_set_new(m, "rms_bias_only",
				    ssc_jreal(o->motion_rms_bias_only * 180 / PI));
		json_object_set_new(j, "motion_error_deg", m);
	}
	if (o->error_model) {
		json_t *em = json_object(), *sf = json_array();
		const char *si = sscope_quantity_si_unit(o->q);
		const char *bu = sscope_term_unit(o->q, SSCOPE_TERM_B);
		double mis[3][3];

		for (int i = 0; i < 3; i++) {
			json_array_append_new(sf, isfinite(c->scale_sd[i]) ?
						      ssc_jreal((o->A[i][i] - 1) * 1e6) :
						      json_null());
			for (int j2 = 0; j2 < 3; j2++)
				mis[i][j2] = i == j2 ? 0 : o->A[i][j2] + 0.0;
		}
		{
			json_t *b = json_array();

			for (int i = 0; i < 3; i++)
				json_array_append_new(b, ssc_json_coef(c->bias[i],
						      c->bias[i] - c->bias_sd[i],
						      c->bias[i] + c->bias_sd[i],
						      bu, si, true));
			json_object_set_new(em, "bias", b);
		}
		json_object_set_new(em, "scale_factor_ppm", sf);
		json_object_set_new(em, "misalignment_rad", mat3(mis, 1));
		if (c->has_gsens) {
			double G[3][3];

			for (int i = 0; i < 3; i++)
				for (int j2 = 0; j2 < 3; j2++)
					G[i][j2] = c->gsens[i][j2] * 180 / PI *
						   3600 * SSCOPE_UNIT_GRAVITY_STD;
			json_object_set_new(em, "g_dependent_bias_deg_h_per_g",
					    mat3(G, 1));
		}
		json_object_set_new(j, "error_model", em);
	} else {
		json_object_set_new(j, "error_model", json_null());
	}
	if (isfinite(o->noise_density))
		json_object_set_new(j, "noise_density",
				    ssc_json_coef(o->noise_density, NAN, NAN,
						  sscope_term_unit(o->q, SSCOPE_TERM_N),
						  sscope_term_si_unit(o->q, SSCOPE_TERM_N),
						  false));
	else
		json_object_set_new(j, "noise_density", json_null());
	if (o->grade >= 0) {
		json_t *g = json_object();

		json_object_set_new(g, "class", json_string(gr[o->grade].name));
		json_object_set_new(g, "distance_decades", ssc_jreal(o->grade_dist));
		json_object_set_new(g, "basis", json_string(
			"typical technology ranges (Titterton & Weston 2004; Groves 2013), "
			"from |bias|, scale-factor error, noise density and g-sensitivity"));
		json_object_set_new(j, "grade", g);
	} else {
		json_object_set_new(j, "grade", json_null());
	}
	return j;
}

void ssc_calib_triad_finish(struct ssc_calib_triad_out *o)
{
	struct sscope_unit iu, ou;

	o->error_model = o->t.input_unit[0] &&
			 !sscope_unit_parse(o->t.input_unit, &iu, NULL) &&
			 !sscope_unit_parse(o->t.output_unit, &ou, NULL) &&
			 sscope_unit_compatible(&iu, &ou) &&
			 sscope_calib_error_model(&o->t.c, o->A) == 0;
	o->grade = sscope_calib_triad_grade(o->q, &o->t.c,
					    o->error_model ? (const double(*)[3])o->A :
							     NULL,
					    o->noise_density, &o->grade_dist);
}

/* A number of a JSON result (NaN when absent or null). */
static double jnum(const json_t *j)
{
	return json_is_number(j) ? json_number_value(j) : (double)NAN;
}

/* v[i] = key[i] * mul; NaN where null */
static void get_vec_nan(const json_t *o, const char *key, double v[3], double mul)
{
	for (size_t i = 0; i < 3; i++)
		v[i] = jnum(json_array_get(json_object_get(o, key), i)) * mul;
}

static void get_mat_nan(const json_t *o, const char *key, double m[3][3],
			double mul)
{
	for (size_t i = 0; i < 3; i++)
		for (size_t j = 0; j < 3; j++)
			m[i][j] = jnum(json_array_get(json_array_get(json_object_get(o, key), i),
						      j)) * mul;
}

/* the residual's unit as the calib stage names it */
static const char *residual_unit(const char *u, const struct sscope_calib_file_triad *t)
{
	static const char *const known[] = { "m/s^2", "1", "counts" };

	if (u && !strcmp(u, t->input_unit))
		return t->input_unit;
	for (size_t i = 0; u && i < sizeof(known) / sizeof(known[0]); i++)
		if (!strcmp(u, known[i]))
			return known[i];
	return NULL;
}

static int triad_from_json(json_t *o, struct ssc_calib_triad_out *out)
{
	const char *kind = json_string_value(json_object_get(o, "kind"));
	const char *iu = json_string_value(json_object_get(o, "input_unit"));
	const char *ou = json_string_value(json_object_get(o, "output_unit"));
	const json_t *g = json_object_get(o, "g_sensitivity"), *mo;
	struct sscope_calib_file_triad *t = &out->t;
	struct sscope_calib_triad *c = &t->c;
	double s;

	memset(out, 0, sizeof(*out));
	sscope_calib_triad_identity(c);
	if (!kind || !iu || !ou || (strcmp(kind, "accel") && strcmp(kind, "gyro")) ||
	    strlen(iu) >= sizeof(t->input_unit) || strlen(ou) >= sizeof(t->output_unit) ||
	    get_names(o, "channels", t->channels) || get_vec(o, "bias", c->bias) ||
	    get_vec(o, "scale", c->scale) || get_mat(o, "misalignment", c->mis))
		return -EINVAL;
	strcpy(t->kind, kind);
	strcpy(t->input_unit, iu);
	strcpy(t->output_unit, ou);
	out->q = !strcmp(kind, "gyro") ? SSCOPE_QUANTITY_ANGULAR_RATE :
					 SSCOPE_QUANTITY_ACCELERATION;
	if (g && !json_is_null(g)) {
		if (get_mat(o, "g_sensitivity", c->gsens) ||
		    get_names(o, "accel_channels", t->accel_channels))
			return -EINVAL;
		c->has_gsens = true;
	}
	/* the file's units back to the SI the stage holds (as
	 * ssc_calfile_triad_json() and ssc_calib_triad_out_json() divide) */
	s = ssc_calfile_unit_scale(iu);
	for (int i = 0; i < 3; i++) {
		c->bias[i] *= s;
		c->scale[i] /= s;
		for (int j = 0; j < 3; j++)
			c->gsens[i][j] *= s;
	}
	get_vec_nan(o, "bias_sd", c->bias_sd, s);
	get_vec_nan(o, "scale_sd", c->scale_sd, 1 / s);
	get_mat_nan(o, "misalignment_sd", c->mis_sd, 1);
	if (c->has_gsens)
		get_mat_nan(o, "g_sensitivity_sd", c->gsens_sd, s);
	c->residual_rms = jnum(json_object_get(o, "residual_rms"));
	c->poses = (size_t)json_integer_value(json_object_get(o, "poses"));
	c->n_params = (unsigned)json_integer_value(json_object_get(o, "parameters"));
	c->iterations = (unsigned)json_integer_value(json_object_get(o, "iterations"));
	c->cond = jnum(json_object_get(o, "condition"));
	out->residual_unit = residual_unit(json_string_value(json_object_get(o, "residual_unit")),
					   t);
	out->noise_density = jnum(json_object_get(json_object_get(o, "noise_density"), "si"));
	mo = json_object_get(o, "motion_error_deg");
	if (json_is_object(mo)) {
		out->n_motion = (size_t)json_integer_value(json_object_get(mo, "motions"));
		out->motion_rms = jnum(json_object_get(mo, "rms")) * PI / 180;
		out->motion_max = jnum(json_object_get(mo, "max")) * PI / 180;
		out->motion_rms_bias_only = jnum(json_object_get(mo, "rms_bias_only")) * PI / 180;
	}
	ssc_calib_triad_finish(out);
	return 0;
}

int ssc_calib_res_from_json(const json_t *root, struct ssc_calib_res *out)
{
	const char *cmd = json_string_value(json_object_get(root, "command"));
	const json_t *arr = json_object_get(root, "triads");
	size_t n;

	memset(out, 0, sizeof(*out));
	if (!cmd || strncmp(cmd, "calib", 5) || !json_is_array(arr))
		return -EINVAL;
	n = json_array_size(arr);
	for (size_t i = 0; i < n; i++) {
		if (out->n_out == (int)(sizeof(out->out) / sizeof(out->out[0])))
			return -E2BIG;
		if (triad_from_json(json_array_get(arr, i), &out->out[out->n_out]))
			return -EINVAL;
		out->n_out++;
	}
	return 0;
}
