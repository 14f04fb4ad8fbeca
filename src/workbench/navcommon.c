/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Helpers of the navigation commands (see navcommon.h).
 */
#include "navcommon.h"
#include "results.h"
#include "plot.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

int ssc_nav_fail(const char *cmd, int rc, const struct sscope_diag *d,
		 const char *path)
{
	if (!d || !d->msg[0])
		return ssc_fail(cmd, rc, d, path);
	ssc_err(cmd, "%s: %s", path, d->msg);
	return rc == -ENOTSUP ? SSC_EXIT_USAGE : SSC_EXIT_FAIL;
}

int ssc_nav_load_json(const char *cmd, const char *opt, const char *path,
		      json_t **root)
{
	*root = ssc_json_read(cmd, opt, path,
			      !strcmp(opt, "from-calib") ? "a calibration file of 'sensorscope calib'" :
							   "the JSON of 'sensorscope allan'");
	return *root ? SSC_EXIT_OK : SSC_EXIT_FAIL;
}

/* member @p key of a coefficient object ({"value", "unit", "lo", "hi",
 * "si", "si_unit"}) in its SI unit; NaN when null or not convertible */
static double coef_si(const json_t *c, const char *key)
{
	const json_t *v = json_object_get(c, key);
	const char *unit = json_string_value(json_object_get(c, "unit"));
	const char *si_unit = json_string_value(json_object_get(c, "si_unit"));
	double si;

	if (!json_is_number(v) || !unit || !si_unit ||
	    sscope_unit_convert_text(json_number_value(v), unit, si_unit, &si))
		return (double)NAN;
	return si;
}

static void terms_clear(struct ssc_nav_terms *t)
{
	memset(t, 0, sizeof(*t));
	t->n_lo = t->n_hi = (double)NAN;
	for (int i = 0; i < 5; i++)
		t->lo[i] = t->hi[i] = (double)NAN;
}

static int terms_of_channel(const json_t *ch, struct ssc_nav_terms *t)
{
	const json_t *nz = json_object_get(ch, "noise");
	const char *name;
	static const char *const key[5] = { "Q", "N", "B", "K", "R" };

	terms_clear(t);
	if (!json_is_object(nz))
		return -1;
	t->quantity = ssc_allan_json_rate_quantity(ch);
	if (t->quantity != SSCOPE_QUANTITY_ANGULAR_RATE &&
	    t->quantity != SSCOPE_QUANTITY_ACCELERATION)
		return -1;
	name = json_string_value(json_object_get(ch, "name"));
	snprintf(t->name, sizeof(t->name), "%s", name ? name : "");
	t->ci_level = json_number_value(json_object_get(ch, "ci_level"));
	for (int i = 0; i < 5; i++) {
		const json_t *c = json_object_get(nz, key[i]);
		const json_t *si = json_object_get(c, "si");

		if (!json_is_false(json_object_get(c, "fitted")) && json_is_number(si) &&
		    json_number_value(si) > 0) {
			t->coef[i] = json_number_value(si);
			t->have = true;
		}
		t->present[i] = json_is_true(json_object_get(c, "present"));
		t->lo[i] = coef_si(c, "lo");
		t->hi[i] = coef_si(c, "hi");
	}
	{
		/* N's interval in SI: the coefficient's lo/hi scaled like
		 * its value */
		const json_t *c = json_object_get(nz, "N");
		double v = json_number_value(json_object_get(c, "value"));
		double lo = json_number_value(json_object_get(c, "lo"));
		double hi = json_number_value(json_object_get(c, "hi"));

		if (t->coef[1] > 0 && v > 0 && json_is_number(json_object_get(c, "lo")) &&
		    json_is_number(json_object_get(c, "hi"))) {
			t->n_lo = lo / v * t->coef[1];
			t->n_hi = hi / v * t->coef[1];
		}
	}
	return t->have ? 0 : -1;
}

int ssc_nav_terms_from_allan(const char *cmd, const json_t *root,
			     const char *what, struct ssc_nav_terms **out,
			     size_t *n)
{
	const char *c = json_string_value(json_object_get(root, "command"));
	const json_t *files = json_object_get(root, "files");
	size_t nf = json_is_array(files) ? json_array_size(files) : 1, cap = 0;
	struct ssc_nav_terms *t = NULL;

	*out = NULL;
	*n = 0;
	if (!c || strcmp(c, "allan")) {
		ssc_err(cmd, "%s: not a JSON result of 'allan'", what);
		return SSC_EXIT_FAIL;
	}
	for (size_t f = 0; f < nf; f++) {
		const json_t *r = json_is_array(files) ? json_array_get(files, f) : root;
		const json_t *chs = json_object_get(r, "channels");

		cap += json_is_array(chs) ? json_array_size(chs) : 0;
	}
	t = calloc(cap ? cap : 1, sizeof(*t));
	if (!t) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	for (size_t f = 0; f < nf; f++) {
		const json_t *r = json_is_array(files) ? json_array_get(files, f) : root;
		const json_t *chs = json_object_get(r, "channels"), *ch;
		size_t i;

		json_array_foreach(chs, i, ch)
			if (terms_of_channel(ch, &t[*n]) == 0)
				(*n)++;
	}
	if (*n == 0) {
		free(t);
		ssc_err(cmd, "%s: no gyro or accelerometer channel with fitted noise terms",
			what);
		return SSC_EXIT_FAIL;
	}
	*out = t;
	return SSC_EXIT_OK;
}

/* One channel of a typed allan result: the terms its JSON carries. */
static int terms_of_chan(const struct ssc_allan_chan *c, double ci_level,
			 struct ssc_nav_terms *t)
{
	const struct sscope_noise_fit *ft = &c->res->fit;
	const struct sscope_noise_coef *cn = &ft->coef[SSCOPE_TERM_N];

	terms_clear(t);
	if (c->u.rq != SSCOPE_QUANTITY_ANGULAR_RATE &&
	    c->u.rq != SSCOPE_QUANTITY_ACCELERATION)
		return -1;
	t->quantity = c->u.rq;
	snprintf(t->name, sizeof(t->name), "%s", c->col->name);
	t->ci_level = ci_level;
	for (int i = 0; i < 5; i++) {
		const struct sscope_noise_coef *cf = &ft->coef[i];

		if (cf->fitted && cf->value > 0) {
			t->coef[i] = cf->value;
			t->have = true;
		}
		/* as the JSON has them: an infinite bound is none (null) */
		t->present[i] = cf->present;
		t->lo[i] = isfinite(cf->lo) ? cf->lo : (double)NAN;
		t->hi[i] = isfinite(cf->hi) ? cf->hi : (double)NAN;
	}
	if (t->coef[SSCOPE_TERM_N] > 0 && isfinite(cn->lo) && isfinite(cn->hi)) {
		t->n_lo = cn->lo;
		t->n_hi = cn->hi;
	}
	return t->have ? 0 : -1;
}

int ssc_nav_terms_from_allan_res(const char *cmd,
				 const struct ssc_allan_res *a,
				 const char *what, struct ssc_nav_terms **out,
				 size_t *n)
{
	struct ssc_nav_terms *t;
	size_t cap = 0;

	*out = NULL;
	*n = 0;
	for (size_t f = 0; f < a->n_files; f++)
		cap += a->fr[f].n_ch;
	t = calloc(cap ? cap : 1, sizeof(*t));
	if (!t) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	for (size_t f = 0; f < a->n_files; f++)
		for (size_t k = 0; k < a->fr[f].n_ch; k++)
			if (a->fr[f].ch[k].res &&
			    terms_of_chan(&a->fr[f].ch[k], a->ci_level, &t[*n]) == 0)
				(*n)++;
	if (*n == 0) {
		free(t);
		ssc_err(cmd, "%s: no gyro or accelerometer channel with fitted noise terms",
			what);
		return SSC_EXIT_FAIL;
	}
	*out = t;
	return SSC_EXIT_OK;
}

const struct ssc_nav_terms *ssc_nav_terms_pick(const struct ssc_nav_terms *t,
					       size_t n, const char *name,
					       enum sscope_quantity q)
{
	const struct ssc_nav_terms *best = NULL;

	for (size_t i = 0; name && i < n; i++)
		if (!strcmp(t[i].name, name))
			return &t[i];
	for (size_t i = 0; i < n; i++)
		if (t[i].quantity == q && (!best || t[i].coef[1] > best->coef[1]))
			best = &t[i];
	return best;
}

void ssc_nav_terms_from_spec(const struct sscope_sensor_spec *s,
			     struct ssc_nav_terms *t)
{
	terms_clear(t);
	snprintf(t->name, sizeof(t->name), "%s", s->name);
	t->quantity = s->quantity;
	t->coef[SSCOPE_TERM_Q] = s->q;
	t->coef[SSCOPE_TERM_N] = s->n;
	t->coef[SSCOPE_TERM_B] = s->b;
	t->coef[SSCOPE_TERM_K] = s->k;
	t->coef[SSCOPE_TERM_R] = s->r;
	for (int i = 0; i < 5; i++)
		t->have |= t->coef[i] > 0;
}

int ssc_nav_calib_errors_res(const struct ssc_calib_res *c, const char *kind,
			     double bias[3], double M[3][3])
{
	for (int k = 0; k < c->n_out; k++) {
		const struct ssc_calib_triad_out *o = &c->out[k];

		if (strcmp(o->t.kind, kind) || !o->error_model)
			continue;
		for (size_t a = 0; a < 3; a++) {
			bias[a] = o->t.c.bias[a];
			for (size_t j = 0; j < 3; j++)
				/* as its JSON says: no scale factor without
				 * its uncertainty */
				M[a][j] = a != j ? o->A[a][j] :
					  isfinite(o->t.c.scale_sd[a]) ?
					  o->A[a][a] - 1 : 0;
		}
		return 0;
	}
	return 1;
}

int ssc_nav_arg_vec3(const char *cmd, const char *opt, const char *arg,
		     const char *si, double out[3])
{
	char *s = strdup(arg), *save = NULL, *tok;
	size_t k = 0;
	int rc = 0;

	if (!s) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	for (tok = strtok_r(s, ",", &save); tok && !rc; tok = strtok_r(NULL, ",", &save)) {
		if (k == 3) {
			rc = ssc_usage_error(cmd, "--%s: one value or three (x,y,z)", opt);
			break;
		}
		rc = ssc_arg_quantity(cmd, opt, tok, si, &out[k++]);
	}
	free(s);
	if (!rc && k == 1)
		out[1] = out[2] = out[0];
	else if (!rc && k != 3)
		rc = ssc_usage_error(cmd, "--%s: one value or three (x,y,z)", opt);
	return rc;
}

double ssc_nav_term_value(double si, enum sscope_quantity q, enum sscope_term t,
			  const char **unit)
{
	const char *u = sscope_term_unit(q, t), *s = sscope_term_si_unit(q, t);
	double v = si;

	*unit = s ? s : "";
	if (u && s && sscope_unit_convert_text(si, s, u, &v) == 0)
		*unit = u;
	return v;
}

void ssc_nav_terms_text(const struct ssc_nav_terms *t, char *buf, size_t len)
{
	size_t o = 0;

	buf[0] = '\0';
	for (int i = 0; i < 5 && o < len; i++) {
		const char *u;
		double v;
		char a[32];

		if (!(t->coef[i] > 0))
			continue;
		v = ssc_nav_term_value(t->coef[i], t->quantity, (enum sscope_term)i, &u);
		o += (size_t)snprintf(buf + o, len - o, "%s%c %s %s", o ? ", " : "",
				      "QNBKR"[i], ssc_fmt(a, sizeof(a), v, 4), u);
	}
	if (!o)
		snprintf(buf, len, "none");
}

json_t *ssc_nav_terms_json(const struct ssc_nav_terms *t)
{
	json_t *o = json_object();
	static const char *const key[5] = { "Q", "N", "B", "K", "R" };

	for (int i = 0; i < 5; i++) {
		const char *u = sscope_term_unit(t->quantity, (enum sscope_term)i);

		json_object_set_new(o, key[i],
				    ssc_json_coef(t->coef[i],
						  i == 1 ? t->n_lo : (double)NAN,
						  i == 1 ? t->n_hi : (double)NAN, u,
						  sscope_term_si_unit(t->quantity,
								      (enum sscope_term)i),
						  t->coef[i] > 0));
	}
	return o;
}

/* ---------------------------------------------------- trajectories */

static int column(const char *cmd, const char *path, const struct sscope_capture *cap,
		  const char *name, enum sscope_quantity q, bool need, const double **out)
{
	long k = sscope_capture_find(cap, name);
	enum sscope_quantity have;

	*out = NULL;
	if (k < 0) {
		if (!need)
			return 0;
		ssc_err(cmd, "%s: no '%s' column (a trajectory needs time, north, east and yaw)",
			path, name);
		return SSC_EXIT_FAIL;
	}
	have = cap->channels[k].col.quantity;
	if (have != q && have != SSCOPE_QUANTITY_DIMENSIONLESS && have != SSCOPE_QUANTITY_UNKNOWN) {
		ssc_err(cmd, "%s: column '%s' is in %s, not %s", path, name,
			cap->channels[k].col.unit_label, sscope_quantity_si_unit(q));
		return SSC_EXIT_FAIL;
	}
	*out = cap->channels[k].data;
	return 0;
}

int ssc_nav_table_load(const char *cmd, const char *path, struct ssc_nav_table *t)
{
	struct sscope_diag d = { "" };
	const double *c[6];
	static const char *const names[6] = { "north", "east", "down",
					      "roll", "pitch", "yaw" };
	int rc;

	memset(t, 0, sizeof(*t));
	rc = sscope_capture_load(&t->cap, path, NULL, &d);
	if (rc)
		return ssc_fail(cmd, rc, &d, path);
	if (!t->cap->time_s) {
		ssc_err(cmd, "%s: no time column (a trajectory needs 'time [s]')", path);
		return SSC_EXIT_FAIL;
	}
	for (int i = 0; i < 6; i++) {
		rc = column(cmd, path, t->cap, names[i],
			    i < 3 ? SSCOPE_QUANTITY_LENGTH : SSCOPE_QUANTITY_ANGLE,
			    i == 0 || i == 1 || i == 5, &c[i]);
		if (rc)
			return rc;
	}
	t->ned = calloc(t->cap->n, 3 * sizeof(double));
	t->eu = calloc(t->cap->n, 3 * sizeof(double));
	if (!t->ned || !t->eu) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	for (size_t i = 0; i < t->cap->n; i++)
		for (int k = 0; k < 3; k++) {
			t->ned[3 * i + k] = c[k] ? c[k][i] : 0;
			t->eu[3 * i + k] = c[3 + k] ? c[3 + k][i] : 0;
		}
	return 0;
}

void ssc_nav_table_free(struct ssc_nav_table *t)
{
	sscope_capture_free(t->cap);
	free(t->ned);
	free(t->eu);
}

int ssc_navsim_mech_plot(const char *cmd, struct sscope_navsim *ns,
			 const struct sscope_navsim_imu *imu, size_t runs,
			 uint64_t seed, const struct sscope_navsim_stat *st,
			 enum sscope_navsim_mech mech, const char *traj,
			 const char *path)
{
	const double d2r = PI / 180;
	size_t n = sscope_navsim_n_out(ns);
	enum sscope_navsim_mech other = mech == SSCOPE_NAVSIM_STRAPDOWN ?
						SSCOPE_NAVSIM_GIMBALLED :
						SSCOPE_NAVSIM_STRAPDOWN;
	struct sscope_navsim_stat *s2 = calloc(n, sizeof(*s2));
	double *t = calloc(n, sizeof(double)), *y = calloc(n, sizeof(double));
	struct ssc_fig *fig = ssc_fig_new(1100, 1100, 2, 1);
	struct sscope_diag d = { "" };
	bool minutes = sscope_navsim_time(ns, n - 1) > 1200;
	char title[256];
	int rc = -ENOMEM;

	if (!s2 || !t || !y || !fig)
		goto out;
	sscope_navsim_set_mechanisation(ns, other);
	rc = sscope_navsim_monte_carlo(ns, imu, runs, seed, s2, NULL, NULL, &d);
	sscope_navsim_set_mechanisation(ns, mech);
	if (rc) {
		rc = ssc_fail(cmd, rc, &d, sscope_navsim_mech_name(other));
		goto done;
	}
	snprintf(title, sizeof(title), "strapdown and gimballed platform, the same sensor: %zu run%s, trajectory %s",
		 runs, runs == 1 ? "" : "s", traj);
	ssc_fig_title(fig, title);
	for (size_t k = 0; k < n; k++)
		t[k] = sscope_navsim_time(ns, k) / (minutes ? 60 : 1);
	for (int p = 0; p < 2; p++) {
		struct ssc_ax *ax = ssc_fig_ax(fig, p, 0);

		for (int m = 0; m < 2; m++) {
			const struct sscope_navsim_stat *x = (m == (int)mech) ? st : s2;
			struct ssc_style ls = { .color = ssc_plot_color((size_t)m), .width = 2 };
			char lab[96];

			for (int q = 0; q < (p ? 1 : 2); q++) {
				for (size_t k = 0; k < n; k++)
					y[k] = p ? x[k].rms[SSCOPE_NAVSIM_YAW] / d2r :
					       q ? x[k].horiz_p95 : x[k].horiz_p50;
				ls.dash = q ? SSC_DASHED : 0;
				snprintf(lab, sizeof(lab), "%s, %s", sscope_navsim_mech_name(m),
					 p ? "rms" : q ? "95 %" : "median");
				ssc_ax_line(ax, t, y, n, &ls, lab);
			}
		}
		ssc_ax_xlabel(ax, minutes ? "time (min)" : "time (s)");
		ssc_ax_ylabel(ax, p ? "heading error (deg)" : "horizontal position error (m)");
		ssc_ax_legend(ax, SSC_LEGEND_UL);
	}
	rc = ssc_fig_save(fig, path);
	rc = rc ? ssc_write_failed(cmd, path, rc) : SSC_EXIT_OK;
	goto done;
out:
	ssc_err(cmd, "out of memory");
	rc = SSC_EXIT_FAIL;
done:
	ssc_fig_free(fig);
	free(s2);
	free(t);
	free(y);
	return rc;
}
