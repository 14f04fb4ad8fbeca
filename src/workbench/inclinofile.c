/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The look-up table that 'inclino calibrate' saves: its JSON written
 * (the "lut" object) and read back (that object, or the whole result)
 * into the library's struct, every field the writer wrote (an uncertainty
 * a hand-written table leaves out is NaN), and checked
 * (sscope_inclino_check()).
 */
#include "workbench.h"

#include <math.h>
#include <string.h>

/* v from a JSON array of 3 numbers, NaN where absent or null (the
 * uncertainties a hand-written table may leave out) */
static void get3_nan(json_t *a, double v[3])
{
	for (int i = 0; i < 3; i++) {
		json_t *x = json_array_get(a, (size_t)i);

		v[i] = json_is_number(x) ? json_number_value(x) : (double)NAN;
	}
}

static int get3(json_t *a, double v[3])
{
	if (!json_is_array(a) || json_array_size(a) != 3)
		return -1;
	for (int i = 0; i < 3; i++) {
		json_t *x = json_array_get(a, (size_t)i);

		if (!json_is_number(x))
			return -1;
		v[i] = json_number_value(x);
	}
	return 0;
}

int ssc_inclino_lut_read(const char *cmd, const char *path,
			 struct sscope_inclino_lut *lut)
{
	json_t *root = ssc_json_read(cmd, "lut", path,
				     "a look-up table of 'sensorscope inclino calibrate'"),
	       *l, *nodes, *g;
	struct sscope_diag d = { "" };
	int rc = SSC_EXIT_FAIL;

	if (!root)
		return SSC_EXIT_FAIL;
	l = json_object_get(root, "lut");
	if (!l)
		l = root;
	nodes = json_object_get(l, "nodes");
	g = json_object_get(l, "gravity_m_s2");
	memset(lut, 0, sizeof(*lut));
	if (!json_is_array(nodes) || !json_is_number(g)) {
		ssc_err(cmd, "%s: not a look-up table (no \"lut\" with \"nodes\" and \"gravity_m_s2\")",
			path);
		goto out;
	}
	lut->gravity_m_s2 = json_number_value(g);
	if (json_array_size(nodes) > SSCOPE_INCLINO_MAX_NODES) {
		ssc_err(cmd, "%s: more than %d nodes", path, SSCOPE_INCLINO_MAX_NODES);
		goto out;
	}
	lut->n = json_array_size(nodes);
	for (size_t i = 0; i < lut->n; i++) {
		json_t *n = json_array_get(nodes, i), *t = json_object_get(n, "temp_degc"),
		       *m = json_object_get(n, "misalignment");
		struct sscope_inclino_params *p = &lut->p[i];

		if (!json_is_number(t) || get3(json_object_get(n, "offset_m_s2"), p->offset) ||
		    get3(json_object_get(n, "scale"), p->scale) || !json_is_array(m) ||
		    json_array_size(m) != 3 || get3(json_array_get(m, 0), p->mis[0]) ||
		    get3(json_array_get(m, 1), p->mis[1]) || get3(json_array_get(m, 2), p->mis[2])) {
			ssc_err(cmd, "%s: node %zu: needs temp_degc, offset_m_s2[3], scale[3], misalignment[3][3]",
				path, i + 1);
			goto out;
		}
		lut->temp_degc[i] = json_number_value(t);
		get3_nan(json_object_get(n, "offset_sd_m_s2"), p->offset_sd);
		get3_nan(json_object_get(n, "scale_sd"), p->scale_sd);
		for (int a = 0; a < 3; a++) {
			p->mis[a][a] = 0;
			get3_nan(json_array_get(json_object_get(n, "misalignment_sd"), (size_t)a),
				 p->mis_sd[a]);
		}
		t = json_object_get(n, "residual_rms_m_s2");
		p->residual_rms = json_is_number(t) ? json_number_value(t) : (double)NAN;
		p->poses = (size_t)json_integer_value(json_object_get(n, "poses"));
	}
	if (sscope_inclino_check(lut, &d)) {
		ssc_err(cmd, "%s: %s", path, d.msg);
		goto out;
	}
	rc = 0;
out:
	json_decref(root);
	return rc;
}

static json_t *jv3(const double v[3])
{
	json_t *a = json_array();

	for (int i = 0; i < 3; i++)
		json_array_append_new(a, ssc_jreal(v[i]));
	return a;
}

json_t *ssc_inclino_lut_json(const struct sscope_inclino_lut *lut, bool cubic)
{
	json_t *l = json_object(), *nodes = json_array();

	json_object_set_new(l, "gravity_m_s2", json_real(lut->gravity_m_s2));
	json_object_set_new(l, "interpolation", json_string(cubic ? "cubic" : "linear"));
	json_object_set_new(l, "model", json_string(
		"raw_i = offset_i + scale_i * t_i + sum_j misalignment_ij * t_j (t: true specific force, m/s^2)"));
	for (size_t i = 0; i < lut->n; i++) {
		const struct sscope_inclino_params *p = &lut->p[i];
		json_t *n = json_object(), *m = json_array(), *msd = json_array();

		json_object_set_new(n, "temp_degc", json_real(lut->temp_degc[i]));
		json_object_set_new(n, "offset_m_s2", jv3(p->offset));
		json_object_set_new(n, "offset_sd_m_s2", jv3(p->offset_sd));
		json_object_set_new(n, "scale", jv3(p->scale));
		json_object_set_new(n, "scale_sd", jv3(p->scale_sd));
		for (int a = 0; a < 3; a++) {
			json_array_append_new(m, jv3(p->mis[a]));
			json_array_append_new(msd, jv3(p->mis_sd[a]));
		}
		json_object_set_new(n, "misalignment", m);
		json_object_set_new(n, "misalignment_sd", msd);
		json_object_set_new(n, "residual_rms_m_s2", ssc_jreal(p->residual_rms));
		json_object_set_new(n, "poses", json_integer((json_int_t)p->poses));
		json_array_append_new(nodes, n);
	}
	json_object_set_new(l, "nodes", nodes);
	return l;
}
