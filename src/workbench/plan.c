/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The `plan` command's model (a sensor spec, a datasheet or a pilot
 * capture's fit) and its text and JSON (analysis/plan.c computes).
 */
#include "plan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "acq/acq.h"
#include "datasheet.h"
#include "plot.h"
#include "stage.h"

static const char term_name[5] = { 'Q', 'N', 'B', 'K', 'R' };

/* a datasheet INI has a [datasheet], [gyro] or [accel] section */
static bool is_datasheet(const char *path)
{
	FILE *f = fopen(path, "r");
	char line[512];
	bool ds = false;

	if (!f)
		return false;
	while (!ds && fgets(line, sizeof(line), f)) {
		const char *p = line + strspn(line, " \t");

		ds = !strncmp(p, "[datasheet]", 11) || !strncmp(p, "[gyro]", 6) ||
		     !strncmp(p, "[accel]", 7);
	}
	fclose(f);
	return ds;
}

static int from_datasheet(const struct ssc_common *co, const char *path,
			  const char *section, struct ssc_plan_model *m)
{
	struct ssc_datasheet ds;
	const struct ssc_ds_section *sec = NULL;
	double t[3];
	int from[3], rc = ssc_datasheet_load(co->cmd, path, &ds);

	if (rc)
		return rc;
	for (size_t k = 0; k < ds.n_sec && !sec; k++)
		if (section ? !strcmp(ds.sec[k].name, section) :
			      ds.sec[k].quantity == SSCOPE_QUANTITY_ANGULAR_RATE)
			sec = &ds.sec[k];
	if (!sec && !section && ds.n_sec)
		sec = &ds.sec[0];
	if (!sec) {
		ssc_err(co->cmd, "%s: no [%s] section", path, section ? section : "gyro");
		return SSC_EXIT_FAIL;
	}
	m->kind = "datasheet";
	m->quantity = sec->quantity;
	snprintf(m->name, sizeof(m->name), "%s %s", ds.name, sec->name);
	ssc_datasheet_terms(sec, t, from);
	for (int i = 0; i < 3; i++) {
		m->coef[i + 1] = isfinite(t[i]) && t[i] > 0 ? t[i] : 0;
		if (!(m->coef[i + 1] > 0))
			snprintf(m->why[i + 1], sizeof(m->why[0]),
				 "the datasheet gives no %c", term_name[i + 1]);
	}
	snprintf(m->why[0], sizeof(m->why[0]), "the datasheet gives no Q");
	snprintf(m->why[4], sizeof(m->why[0]), "the datasheet gives no R");
	return SSC_EXIT_OK;
}

/* the model of the pilot capture's first channel, fitted as `allan`
 * does (dense taus) */
static int from_pilot(const struct ssc_common *co,
		      const struct sscope_capture *cap, const char *path,
		      struct ssc_plan_model *m)
{
	struct sscope_allan_result *res = NULL;
	struct sscope_diag d = { "" };
	const struct sscope_capture_channel *ch;
	double fs = co->rate_hz > 0 ? co->rate_hz : cap->rate_hz;
	int rc;

	if (!cap->n_channels) {
		ssc_err(co->cmd, "%s: no data column", path);
		return SSC_EXIT_FAIL;
	}
	if (!(fs > 0))
		return ssc_err_no_rate(co->cmd, path, cap->rate_note);
	ch = &cap->channels[0];
	if (ch->col.quantity != SSCOPE_QUANTITY_ANGULAR_RATE &&
	    ch->col.quantity != SSCOPE_QUANTITY_ACCELERATION) {
		ssc_err(co->cmd, "%s: channel %s is %s%s%s: a pilot is a record of angular rate or acceleration (its unit, e.g. 'gx [deg/s]', or -u deg/s)",
			path, ch->col.name,
			ch->col.unit_label[0] ? "in " : "without a unit",
			ch->col.unit_label,
			ch->col.quantity == SSCOPE_QUANTITY_ANGLE ? " (an angle: its rate is what the noise terms describe)" : "");
		return SSC_EXIT_FAIL;
	}
	rc = sscope_allan_analyze(ch->data, 1, cap->n, fs, SSCOPE_ALLAN_TAUS_DENSE,
				  NULL, NULL, &res, &d);
	if (rc == 0 && !res->have_fit) {
		rc = res->fit_error;
		d = res->fit_diag;
	}
	if (rc) {
		/* the fit's words know no file: said with it */
		if (d.msg[0])
			ssc_err(co->cmd, "%s: channel %s: %s", path, ch->col.name, d.msg);
		else
			ssc_fail(co->cmd, rc, &d, path);
		sscope_allan_result_free(res);
		return SSC_EXIT_FAIL;
	}
	m->kind = "pilot";
	m->path = path;
	m->rate_hz = fs;
	m->pilot_s = (double)cap->n / fs;
	m->quantity = ch->col.quantity;
	m->ci_level = res->fit.ci_level;
	snprintf(m->name, sizeof(m->name), "%s", ch->col.name);
	for (int j = 0; j < 5; j++) {
		const struct sscope_noise_coef *c = &res->fit.coef[j];

		m->lo[j] = isfinite(c->lo) && c->lo > 0 ? c->lo : 0;
		m->hi[j] = isfinite(c->hi) ? c->hi : (double)INFINITY;
		/* a term the pilot does not show present enters with its
		 * estimate (every term free), and says so */
		m->coef[j] = c->present && c->value > 0 ? c->value :
			     isfinite(c->estimate) ? c->estimate : 0;
		if (!(m->coef[j] > 0))
			snprintf(m->why[j], sizeof(m->why[0]),
				 "the pilot gives no %c (its estimate is 0: a longer pilot may)",
				 term_name[j]);
		else if (!c->present)
			m->unshown |= 1u << j;
	}
	sscope_allan_result_free(res);
	return SSC_EXIT_OK;
}

static void from_spec(const struct sscope_sensor_spec *spec, const char *path,
		      struct ssc_plan_model *m)
{
	m->kind = "sensor spec";
	m->path = path;
	m->quantity = spec->quantity;
	snprintf(m->name, sizeof(m->name), "%s", spec->name);
	m->coef[0] = spec->q;
	m->coef[1] = spec->n;
	m->coef[2] = spec->b;
	m->coef[3] = spec->k;
	m->coef[4] = spec->r;
	for (int j = 0; j < 5; j++)
		if (!(m->coef[j] > 0))
			snprintf(m->why[j], sizeof(m->why[0]),
				 "the sensor spec has no %c (0)", term_name[j]);
}

static int model_load(const struct ssc_common *co, const struct ssc_plan_req *q,
		      const struct sscope_capture *pilot, const char *pilot_path,
		      const struct sscope_sensor_spec *sensor,
		      const char *sensor_path, struct ssc_plan_model *m)
{
	struct sscope_sensor_spec spec;
	int rc;

	memset(m, 0, sizeof(*m));
	if (!q->sensor && pilot)
		return from_pilot(co, pilot, pilot_path, m);
	if (!q->sensor) {
		if (!sensor) {
			ssc_err(co->cmd, "no sensor: give --sensor FILE.ini or a pilot capture");
			return SSC_EXIT_USAGE;
		}
		from_spec(sensor, sensor_path ? sensor_path : "[sensor]", m);
		return SSC_EXIT_OK;
	}
	m->path = q->sensor;
	if (is_datasheet(q->sensor))
		return from_datasheet(co, q->sensor, q->section, m);
	rc = ssc_load_sensor(co->cmd, q->sensor, &spec);
	if (!rc)
		from_spec(&spec, q->sensor, m);
	return rc;
}

static void fmt_len(char *buf, size_t len, double s)
{
	if (!isfinite(s))
		snprintf(buf, len, "never");
	else if (s < 120)
		snprintf(buf, len, "%.0f s", s);
	else if (s < 3600)
		snprintf(buf, len, "%.1f min", s / 60);
	else if (s < 4 * 86400.0)
		snprintf(buf, len, "%.3g h", s / 3600);
	else
		snprintf(buf, len, "%.1f d", s / 86400);
}

/* the figure's lengths: from a tenth of the shortest needed (or asked)
 * length to twice the longest, log-spaced */
static void curve_lengths(const struct ssc_plan_res *r, double *len_s)
{
	double lo = INFINITY, hi = 0;

	for (size_t i = 0; i < r->req.n_wish; i++)
		if (isfinite(r->needed_s[i])) {
			lo = fmin(lo, r->needed_s[i]);
			hi = fmax(hi, r->needed_s[i]);
		}
	for (size_t k = 0; k < r->req.n_len; k++) {
		lo = fmin(lo, r->req.lengths_s[k]);
		hi = fmax(hi, r->req.lengths_s[k]);
	}
	lo = fmax(lo / 10, 60);
	hi = fmin(fmax(2 * hi, 2 * lo), r->req.po.max_length_s);
	for (size_t k = 0; k < SSC_PLAN_CURVE; k++)
		len_s[k] = lo * pow(hi / lo, (double)k / (SSC_PLAN_CURVE - 1));
}

/* the needed length as the planned term moves within the pilot's
 * interval (the other terms as fitted), shortest first: a short pilot's B
 * scatters by tens of percent and the length goes as about B^-2
 * (tests/bench/README.md) */
static int pilot_range(const struct ssc_plan_res *r, enum sscope_term t,
		       double w, double range_s[2])
{
	double c[5];
	int rc;

	range_s[0] = range_s[1] = INFINITY;
	memcpy(c, r->m.coef, sizeof(c));
	if (isfinite(r->m.hi[t]) && r->m.hi[t] > 0) {
		c[t] = r->m.hi[t];
		rc = sscope_plan_needed(c, r->rate_hz, t, w, &r->req.po, &range_s[0]);
		if (rc)
			return rc;
	}
	if (r->m.lo[t] > 0) {
		c[t] = r->m.lo[t];
		rc = sscope_plan_needed(c, r->rate_hz, t, w, &r->req.po, &range_s[1]);
		if (rc)
			return rc;
	}
	if (range_s[0] > range_s[1]) {
		double x = range_s[0];

		range_s[0] = range_s[1];
		range_s[1] = x;
	}
	return 0;
}

int ssc_plan_run(const struct ssc_common *co, const struct ssc_plan_req *req,
		 const struct sscope_capture *pilot, const char *pilot_path,
		 const struct sscope_sensor_spec *sensor, const char *sensor_path,
		 struct ssc_plan_res **out)
{
	struct ssc_plan_res *r = calloc(1, sizeof(*r));
	int rc;

	*out = NULL;
	if (!r)
		return ssc_fail(co->cmd, -ENOMEM, NULL, NULL);
	r->req = *req;
	if (r->req.po.max_length_s == 0)
		r->req.po.max_length_s = 30 * 86400.0;
	rc = model_load(co, req, pilot, pilot_path, sensor, sensor_path, &r->m);
	if (rc) {
		free(r);
		return rc;
	}
	r->rate_hz = co->rate_hz > 0 ? co->rate_hz : r->m.rate_hz;
	if (!(r->rate_hz > 0)) {
		free(r);
		return ssc_usage_error(co->cmd, "give the sample rate of the planned record: --rate HZ");
	}
	/* the planner's records hold at most 1e15 samples */
	{
		double L = r->req.po.max_length_s, fs = r->rate_hz;

		for (size_t k = 0; k < req->n_len; k++)
			L = fmax(L, req->lengths_s[k]);
		if (!(L * fs <= 1e15)) {
			free(r);
			return ssc_usage_error(co->cmd, "a record of %g s at %g Hz holds more than 1e15 samples: check --lengths, --max-length and --rate",
					       L, fs);
		}
	}
	for (size_t i = 0; i < req->n_wish && !rc; i++) {
		enum sscope_term t = (enum sscope_term)req->wish[i].term;
		double w = req->wish[i].target;

		rc = sscope_plan_needed(r->m.coef, r->rate_hz, t, w, &r->req.po,
					&r->needed_s[i]);
		for (size_t k = 0; k < req->n_len && !rc; k++)
			rc = sscope_plan_predict(r->m.coef, r->rate_hz,
						 req->lengths_s[k], t, w,
						 &r->req.po, &r->pt[i][k]);
		if (!rc && r->m.ci_level > 0 && r->m.coef[t] > 0)
			rc = pilot_range(r, t, w, r->range_s[i]);
	}
	if (!rc && co->plot) {
		double len_s[SSC_PLAN_CURVE];

		curve_lengths(r, len_s);
		r->n_curve = SSC_PLAN_CURVE;
		for (size_t i = 0; i < req->n_wish && !rc; i++)
			for (size_t k = 0; k < SSC_PLAN_CURVE && !rc; k++)
				rc = sscope_plan_predict(
					r->m.coef, r->rate_hz, len_s[k],
					(enum sscope_term)req->wish[i].term,
					req->wish[i].target, &r->req.po,
					&r->curve[i][k]);
	}
	if (rc) {
		free(r);
		ssc_err(co->cmd, "the noise model gives no prediction for this request (%s)",
			sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	*out = r;
	return SSC_EXIT_OK;
}

static json_t *model_json(const struct ssc_plan_model *m)
{
	json_t *o = json_object();

	for (int j = 0; j < 5; j++) {
		const char *u = sscope_term_unit(m->quantity, (enum sscope_term)j);
		const char *si = sscope_term_si_unit(m->quantity, (enum sscope_term)j);

		json_object_set_new(o, (char[]){ term_name[j], 0 },
				    ssc_json_coef(m->coef[j], NAN, NAN, u, si,
						  m->coef[j] > 0));
	}
	return o;
}

static const char *never_why(const struct ssc_plan_res *r, size_t i)
{
	return r->m.coef[r->req.wish[i].term] > 0 ?
		       "not reached within the longest record considered (--max-length)" :
		       r->m.why[r->req.wish[i].term];
}

json_t *ssc_plan_json(const void *opts, const void *result)
{
	const struct ssc_plan_res *r = result;
	const struct ssc_plan_model *m = &r->m;
	const struct sscope_plan_opts *po = &r->req.po;
	json_t *root = json_object(), *arr = json_array();

	(void)opts;
	json_object_set_new(root, "command", json_string("plan"));
	json_object_set_new(root, "source", json_string(m->kind));
	json_object_set_new(root, "file", json_string(m->path));
	json_object_set_new(root, "name", json_string(m->name));
	if (m->pilot_s > 0)
		json_object_set_new(root, "pilot_s", ssc_jreal(m->pilot_s));
	json_object_set_new(root, "rate_hz", ssc_jreal(r->rate_hz));
	json_object_set_new(root, "ci_level", ssc_jreal(po->ci_level));
	json_object_set_new(root, "probability_wanted", ssc_jreal(po->probability));
	json_object_set_new(root, "detect_sigma", ssc_jreal(po->detect_sigma));
	json_object_set_new(root, "noise", model_json(m));
	for (int j = 0; j < 5; j++)
		if (m->unshown & (1u << j))
			ssc_json_warn(root, "term_not_shown",
				      "the pilot does not show %c present: the plan uses its estimate and is indicative only",
				      term_name[j]);
	for (size_t i = 0; i < r->req.n_wish; i++) {
		json_t *t = json_object(), *ls = json_array();

		json_object_set_new(t, "term", json_string((char[]){ term_name[r->req.wish[i].term], 0 }));
		json_object_set_new(t, "target", ssc_jreal(r->req.wish[i].target));
		json_object_set_new(t, "needed_s", ssc_jreal(r->needed_s[i]));
		json_object_set_new(t, "never",
				    isfinite(r->needed_s[i]) ? json_null() :
				    json_string(never_why(r, i)));
		if (m->ci_level > 0 && m->coef[r->req.wish[i].term] > 0) {
			/* from a pilot: its own uncertainty (null: never) */
			json_object_set_new(t, "needed_range_s",
					    json_pack("[o,o]", ssc_jreal(r->range_s[i][0]),
						      ssc_jreal(r->range_s[i][1])));
			json_object_set_new(t, "needed_range_level", ssc_jreal(m->ci_level));
		}
		for (size_t k = 0; k < r->req.n_len; k++) {
			const struct sscope_plan_point *p = &r->pt[i][k];
			json_t *l = json_object();

			json_object_set_new(l, "length_s", ssc_jreal(p->length_s));
			json_object_set_new(l, "probability", ssc_jreal(p->probability));
			json_object_set_new(l, "p_present", ssc_jreal(p->p_present));
			json_object_set_new(l, "p_width", ssc_jreal(p->p_width));
			json_object_set_new(l, "rel_half_width", ssc_jreal(p->rel_half_width));
			json_array_append_new(ls, l);
		}
		json_object_set_new(t, "lengths", ls);
		json_array_append_new(arr, t);
	}
	json_object_set_new(root, "terms", arr);
	return root;
}

void ssc_plan_text(FILE *f, const void *opts, const void *result)
{
	const struct ssc_plan_res *r = result;
	const struct ssc_plan_model *m = &r->m;
	const struct sscope_plan_opts *po = &r->req.po;

	(void)opts;
	fprintf(f, "%s (%s %s), %g Hz: record length for each term to be shown present\n"
		"and resolved to the relative half-width of its %.1f %% interval, with %.0f %% probability\n",
		m->name[0] ? m->name : "sensor", m->kind, m->path, r->rate_hz,
		100 * po->ci_level, 100 * po->probability);
	for (int j = 0; j < 5; j++)
		if (m->unshown & (1u << j))
			fprintf(f, "note: the pilot does not show %c present: the plan uses its estimate and is indicative only\n",
				term_name[j]);
	fprintf(f, "%-4s %7s %11s", "term", "target", "needed");
	for (size_t k = 0; k < r->req.n_len; k++) {
		char b[32];

		fmt_len(b, sizeof(b), r->req.lengths_s[k]);
		fprintf(f, " %8s", b);
	}
	fputc('\n', f);
	for (size_t i = 0; i < r->req.n_wish; i++) {
		int t = r->req.wish[i].term;
		char b[32];

		fmt_len(b, sizeof(b), r->needed_s[i]);
		if (!isfinite(r->needed_s[i]) && m->coef[t] > 0) {
			/* not within the search: longer, not never */
			char c[24];

			fmt_len(c, sizeof(c), po->max_length_s);
			snprintf(b, sizeof(b), "> %s", c);
		}
		fprintf(f, "%-4c %6.0f%% %11s", term_name[t],
			100 * r->req.wish[i].target, b);
		if (!isfinite(r->needed_s[i]) && !(m->coef[t] > 0)) {
			fprintf(f, "  %s\n", m->why[t]);
			continue;
		}
		for (size_t k = 0; k < r->req.n_len; k++)
			fprintf(f, " %7.0f%%", 100 * r->pt[i][k].probability);
		if (!isfinite(r->needed_s[i]))
			fprintf(f, "  (the search ends at --max-length)");
		fputc('\n', f);
	}
	if (!(m->ci_level > 0))
		return;
	fprintf(f, "from a pilot of %.3g min: the needed length as the term moves within the pilot's %.1f %% interval\n",
		m->pilot_s / 60, 100 * m->ci_level);
	for (size_t i = 0; i < r->req.n_wish; i++) {
		int t = r->req.wish[i].term;
		char a[32], b[32];

		if (!(m->coef[t] > 0))
			continue;
		fmt_len(a, sizeof(a), r->range_s[i][0]);
		fmt_len(b, sizeof(b), r->range_s[i][1]);
		fprintf(f, "%-4c %6.0f%% %11s .. %s", term_name[t],
			100 * r->req.wish[i].target, a, b);
		if (isfinite(r->range_s[i][1]) && r->range_s[i][0] > 0 &&
		    r->range_s[i][1] > 1.5 * r->range_s[i][0])
			fprintf(f, " (a factor of %.1f: a longer pilot narrows it)",
				r->range_s[i][1] / r->range_s[i][0]);
		fputc('\n', f);
	}
}

void ssc_plan_summary(json_t *rows, const void *opts, const void *result)
{
	const struct ssc_plan_res *r = result;

	(void)opts;
	for (size_t i = 0; i < r->req.n_wish; i++) {
		char q[96], note[160];

		snprintf(q, sizeof(q), "record length for %c to %.0f %%",
			 term_name[r->req.wish[i].term], 100 * r->req.wish[i].target);
		if (isfinite(r->needed_s[i]))
			snprintf(note, sizeof(note),
				 "shown present and resolved with %.0f %% probability (%s)",
				 100 * r->req.po.probability, r->m.kind);
		else
			snprintf(note, sizeof(note), "never: %s", never_why(r, i));
		ssc_summary_add(rows, NULL, q,
				isfinite(r->needed_s[i]) ? r->needed_s[i] / 3600 : (double)NAN,
				NAN, NAN, "h", note);
		if (!isfinite(r->needed_s[i]) || r->m.unshown)
			ssc_summary_warn_last(rows);
	}
}

int ssc_plan_plot(const struct ssc_common *co, const void *opts,
		  const void *result, const char *path)
{
	const struct ssc_plan_res *r = result;
	struct ssc_fig *fig;
	struct ssc_ax *ax;
	double x[SSC_PLAN_CURVE], y[SSC_PLAN_CURVE];
	char buf[320];
	int rc;

	(void)opts;
	if (!r->n_curve)
		return SSC_EXIT_OK;
	fig = ssc_fig_new(1000, 620, 1, 1);
	if (!fig)
		return ssc_fail(co->cmd, -ENOMEM, NULL, NULL);
	ax = ssc_fig_ax(fig, 0, 0);
	snprintf(buf, sizeof(buf), "%s (%s), %g Hz: chance of each wish against record length",
		 r->m.name[0] ? r->m.name : "sensor", r->m.kind, r->rate_hz);
	ssc_fig_title(fig, buf);
	ssc_ax_log(ax, true, false);
	for (size_t i = 0; i < r->req.n_wish; i++) {
		struct ssc_style st = { .color = ssc_plot_color(i), .width = 2 };

		for (size_t k = 0; k < r->n_curve; k++) {
			x[k] = r->curve[i][k].length_s / 3600;
			y[k] = 100 * r->curve[i][k].probability;
		}
		snprintf(buf, sizeof(buf), "%c to ±%.0f %%", term_name[r->req.wish[i].term],
			 100 * r->req.wish[i].target);
		ssc_ax_line(ax, x, y, r->n_curve, &st, buf);
		if (isfinite(r->needed_s[i])) {
			struct ssc_style vs = st;

			vs.width = 1;
			vs.dash = SSC_DOTTED;
			ssc_ax_vline(ax, r->needed_s[i] / 3600, &vs, NULL);
		}
	}
	{
		struct ssc_style hs = { .color = 0x7f7f7f, .width = 1, .dash = SSC_DASHED };

		snprintf(buf, sizeof(buf), "wanted: %.0f %%", 100 * r->req.po.probability);
		ssc_ax_hline(ax, 100 * r->req.po.probability, &hs, buf);
	}
	if (r->m.unshown)
		ssc_ax_note(ax, "a term the pilot does not show present is planned with its estimate: indicative",
			    SSC_LEGEND_LR);
	ssc_ax_ylim(ax, 0, 100);
	ssc_ax_xlabel(ax, "record length (h)");
	snprintf(buf, sizeof(buf), "probability present and resolved (%%; %.1f %% intervals)",
		 100 * r->req.po.ci_level);
	ssc_ax_ylabel(ax, buf);
	ssc_ax_legend(ax, SSC_LEGEND_UL);
	rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	return rc ? ssc_write_failed(co->cmd, path, rc) : SSC_EXIT_OK;
}

void ssc_plan_free(void *result)
{
	free(result);
}

/* ------------------------------------------------------------------ */
/* acquire --until                                                      */

struct ssc_until {
	const char *cmd;
	size_t channel;
	char name[32];
	int term;
	double target, rate_hz;
	bool quiet, reached;
	double *x;
	size_t n, cap, next_fit;
	double width, fitted_s;
	unsigned fits;
	struct sscope_noise_plan *plan;
};

int ssc_until_new(const char *cmd, size_t channel, const char *chan_name,
		  int term, double target, double rate_hz, bool quiet,
		  struct ssc_until **out)
{
	struct ssc_until *u = calloc(1, sizeof(*u));

	*out = NULL;
	if (!u)
		return -ENOMEM;
	if (!(rate_hz > 0) || term < 0 || term > 4 || !(target > 0)) {
		free(u);
		return -EINVAL;
	}
	u->cmd = cmd;
	u->channel = channel;
	snprintf(u->name, sizeof(u->name), "%s", chan_name);
	u->term = term;
	u->target = target;
	u->rate_hz = rate_hz;
	u->quiet = quiet;
	u->width = INFINITY;
	u->next_fit = (size_t)fmax(64, 60 * rate_hz);
	if (sscope_noise_plan_new(&u->plan))
		u->plan = NULL;
	*out = u;
	return 0;
}

static void until_fit(struct ssc_until *u)
{
	struct sscope_allan_result *res = NULL;
	struct sscope_noise_fit_opts fo = { 0 };
	const struct sscope_noise_coef *c;
	char len[32];

	fo.plan = u->plan;
	u->fits++;
	u->fitted_s = (double)u->n / u->rate_hz;
	fmt_len(len, sizeof(len), u->fitted_s);
	if (sscope_allan_analyze(u->x, 1, u->n, u->rate_hz,
				 SSCOPE_ALLAN_TAUS_DENSE, NULL, &fo, &res, NULL) ||
	    !res->have_fit) {
		sscope_allan_result_free(res);
		return;
	}
	c = &res->fit.coef[u->term];
	u->width = c->present && c->value > 0 && c->lo > 0 ?
			   (c->hi - c->lo) / (2 * c->value) : (double)INFINITY;
	u->reached = u->width <= u->target;
	if (!u->quiet) {
		if (isfinite(u->width))
			fprintf(stderr, "sensorscope: %s: %s after %s: %c to %.1f %% (wanted %.1f %%)%s\n",
				u->cmd, u->name, len, term_name[u->term],
				100 * u->width, 100 * u->target,
				u->reached ? ": resolved, stopping" : "");
		else
			fprintf(stderr, "sensorscope: %s: %s after %s: %c not yet resolved (%s)\n",
				u->cmd, u->name, len, term_name[u->term],
				c->present ? "its interval reaches 0" : "not shown present");
	}
	sscope_allan_result_free(res);
}

bool ssc_until_check(const struct ssc_acq_sample *s, size_t n,
		     double elapsed_s, void *ctx)
{
	struct ssc_until *u = ctx;

	(void)elapsed_s;
	if (u->reached)
		return true;
	if (u->n + n > u->cap) {
		size_t cap = u->cap ? 2 * u->cap : 65536;
		double *x;

		while (cap < u->n + n)
			cap *= 2;
		x = realloc(u->x, cap * sizeof(double));
		if (!x)
			return false; /* no more refits; the cap still stops */
		u->x = x;
		u->cap = cap;
	}
	for (size_t i = 0; i < n; i++) {
		/* a gap: NaN rows as the capture's reader gives them */
		for (uint32_t k = 0; k < s[i].missing && u->n < u->cap; k++)
			u->x[u->n++] = (double)NAN;
		if (u->n < u->cap)
			u->x[u->n++] = s[i].v[u->channel];
	}
	if (u->n >= u->next_fit) {
		until_fit(u);
		u->next_fit = u->n + (size_t)fmax(1, 0.05 * (double)u->n);
	}
	return u->reached;
}

void ssc_until_state(const struct ssc_until *u, double *width,
		     double *fitted_s, unsigned *fits, bool *reached)
{
	*width = u->width;
	*fitted_s = u->fitted_s;
	*fits = u->fits;
	*reached = u->reached;
}

void ssc_until_free(struct ssc_until *u)
{
	if (!u)
		return;
	sscope_noise_plan_free(u->plan);
	free(u->x);
	free(u);
}
