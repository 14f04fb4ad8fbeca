/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Calibration files: written by `sensorscope calib`, applied to captures
 * by the shared option --calibration FILE when ssc_load() reads them.
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

#include <math.h>
#include <stdlib.h>
#include <string.h>

static json_t *vec3(const double v[3])
{
	json_t *a = json_array();

	for (int i = 0; i < 3; i++)
		json_array_append_new(a, ssc_jreal(v[i]));
	return a;
}

static json_t *mat3(const double m[3][3])
{
	json_t *a = json_array();

	for (int i = 0; i < 3; i++)
		json_array_append_new(a, vec3(m[i]));
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
	json_object_set_new(o, "bias", vec3(b));
	json_object_set_new(o, "scale", vec3(k));
	json_object_set_new(o, "misalignment", mat3(t->c.mis));
	if (t->c.has_gsens) {
		json_t *ac = json_array();

		json_object_set_new(o, "g_sensitivity", mat3(G));
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
	json_error_t err;
	json_t *root = json_load_file(path, 0, &err), *arr;
	struct sscope_calib_file_triad *t = NULL;
	size_t n;

	*out = NULL;
	*n_out = 0;
	if (!root) {
		ssc_err(cmd, "--calibration: %s: %s (line %d)", path, err.text,
			err.line);
		return SSC_EXIT_FAIL;
	}
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

int ssc_calibration_apply(const struct ssc_common *co, const char *path,
			  struct sscope_capture *cap)
{
	struct sscope_calib_file_triad *t;
	struct sscope_diag d = { "" };
	unsigned skipped;
	size_t n;
	int rc = ssc_calfile_read(co->cmd, co->calibration, &t, &n);

	if (rc)
		return rc;
	rc = sscope_capture_apply_calib(cap, t, n, &skipped, NULL, &d);
	if (rc == -ENOMEM) {
		ssc_err(co->cmd, "out of memory");
	} else if (rc) {
		ssc_err(co->cmd, "--calibration: %s: %s: %s", co->calibration,
			path, d.msg[0] ? d.msg : sscope_strerror(rc));
	} else {
		for (size_t i = 0; i < n && i < 8 * sizeof(unsigned); i++)
			if (skipped & (1u << i))
				ssc_warn(co, "%s: no accelerometer channels %s,%s,%s: g-sensitivity not corrected",
					 path, t[i].accel_channels[0],
					 t[i].accel_channels[1],
					 t[i].accel_channels[2]);
	}
	free(t);
	return rc ? SSC_EXIT_FAIL : SSC_EXIT_OK;
}
