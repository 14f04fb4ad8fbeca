/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The `datasheet` command's file and presentation (see datasheet.h): the
 * INI of a datasheet read line by line into SI with the unit parser,
 * shown as IEEE 952 terms and back, and a capture checked against it with
 * sscope_datasheet_check() (guard-banded verdicts).
 */
#include "workbench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "datasheet.h"
#include "stage.h"

static const char *const section_names[2] = { "gyro", "accel" };

/* a conventional unit per line (gyro, accelerometer) */
static const char *const conv_unit[SSC_DS_LINES][2] = {
	[SSCOPE_DATASHEET_NOISE_DENSITY] = { "deg/s/sqrt(Hz)", "ug/sqrt(Hz)" },
	[SSCOPE_DATASHEET_RANDOM_WALK] = { "deg/sqrt(h)", "m/s/sqrt(h)" },
	[SSCOPE_DATASHEET_RMS_NOISE] = { "deg/s", "mg" },
	[SSCOPE_DATASHEET_BIAS_INSTABILITY] = { "deg/h", "ug" },
	[SSCOPE_DATASHEET_ALLAN_MINIMUM] = { "deg/h", "ug" },
	[SSCOPE_DATASHEET_RATE_RANDOM_WALK] = { "deg/h/sqrt(h)", "m/s^2/sqrt(h)" },
	[SSCOPE_DATASHEET_GJB_10S] = { "deg/h", "ug" },
	[SSCOPE_DATASHEET_GJB_100S] = { "deg/h", "ug" },
	[SSCOPE_DATASHEET_RUN_TO_RUN_BIAS] = { "deg/h", "mg" },
	[SSCOPE_DATASHEET_SCALE_FACTOR] = { "ppm", "ppm" },
	[SSCOPE_DATASHEET_BIAS_OFFSET] = { "deg/s", "mg" },
	[SSCOPE_DATASHEET_BIAS_TEMPCO] = { "deg/s/K", "ug/K" },
	[SSCOPE_DATASHEET_RATE_RAMP] = { "deg/h/h", "ug/h" },
};

static const char *rate_unit(enum sscope_quantity q)
{
	return q == SSCOPE_QUANTITY_ANGULAR_RATE ? "rad/s" : "m/s^2";
}

/* the SI unit of a line's value */
static void si_unit_of(enum sscope_quantity q, enum sscope_datasheet_line l,
		       char *buf, size_t len)
{
	const struct sscope_datasheet_info *in = sscope_datasheet_info(l);

	if (!strcmp(in->si_suffix, "1"))
		snprintf(buf, len, "1");
	else if (in->term != SSCOPE_TERM_COUNT_ && l != SSCOPE_DATASHEET_RMS_NOISE)
		snprintf(buf, len, "%s", sscope_term_si_unit(q, in->term));
	else
		snprintf(buf, len, "%s%s", rate_unit(q), in->si_suffix);
}

static const char *term_key(enum sscope_term t)
{
	return t == SSCOPE_TERM_N ? "N" : t == SSCOPE_TERM_B ? "B" :
	       t == SSCOPE_TERM_K ? "K" : NULL;
}

/* value text -> SI, with the unit as written; 0 or an exit code */
static int parse_value(const char *cmd, const char *path, size_t line,
		       const char *key, const char *v, const char *want,
		       double *si, char *unit, size_t ulen)
{
	struct sscope_unit u, w;
	struct sscope_diag d = { "" };
	const char *p = v, *end = v + strlen(v);
	double x;
	size_t k;

	while (*p == ' ' || *p == '\t')
		p++;
	k = ssc_parse_double(p, end, &x);
	if (!k) {
		ssc_err(cmd, "%s: line %zu: %s = %s: not a number", path, line, key, v);
		return SSC_EXIT_FAIL;
	}
	if (!isfinite(x)) {
		ssc_err(cmd, "%s: line %zu: %s = %s: not a finite number", path, line, key, v);
		return SSC_EXIT_FAIL;
	}
	p += k;
	while (*p == ' ' || *p == '\t')
		p++;
	if (!*p) {
		ssc_err(cmd, "%s: line %zu: %s = %s: a unit is needed (e.g. %s)", path,
			line, key, v, want);
		return SSC_EXIT_FAIL;
	}
	if (sscope_quantity_parse(v, si, &u, &d)) {
		ssc_err(cmd, "%s: line %zu: %s = %s: unknown unit '%s'", path, line, key,
			v, p);
		return SSC_EXIT_FAIL;
	}
	sscope_unit_parse(want, &w, NULL);
	if (!sscope_unit_compatible(&u, &w)) {
		ssc_err(cmd, "%s: line %zu: %s = %s: '%s' is not a unit of %s (e.g. %s)",
			path, line, key, v, p, key, want);
		return SSC_EXIT_FAIL;
	}
	if (!(*si > 0) || !isfinite(*si)) {
		ssc_err(cmd, "%s: line %zu: %s = %s: must be positive", path, line, key, v);
		return SSC_EXIT_FAIL;
	}
	snprintf(unit, ulen, "%s", p);
	return 0;
}

static int load_section(const char *cmd, const struct ssc_ini *ini,
			const char *path, size_t s, struct ssc_ds_section *sec)
{
	enum sscope_quantity q = s == 0 ? SSCOPE_QUANTITY_ANGULAR_RATE :
					  SSCOPE_QUANTITY_ACCELERATION;
	size_t nk = ssc_ini_n_keys(ini, section_names[s]);
	bool rms = false;

	memset(sec, 0, sizeof(*sec));
	sec->name = section_names[s];
	sec->quantity = q;
	sec->bandwidth_hz = NAN;
	for (size_t k = 0; k < nk; k++) {
		const char *v, *key;
		size_t line;
		int l, rc;

		key = ssc_ini_key(ini, sec->name, k, &v, &line);
		if (!strcmp(key, "noise_bandwidth")) {
			char u[40];

			rc = parse_value(cmd, path, line, key, v, "100 Hz", &sec->bandwidth_hz,
					 u, sizeof(u));
			if (rc)
				return rc;
			continue;
		}
		l = sscope_datasheet_line_by_key(key);
		if (l < 0) {
			ssc_err(cmd, "%s: line %zu: [%s] %s: unknown line (known: noise_density, random_walk, rms_noise, noise_bandwidth, bias_instability, in_run_bias_stability, rate_random_walk, bias_stability_10s, bias_stability_100s, run_to_run_bias, scale_factor_error, bias_offset, bias_tempco, rate_ramp)",
				path, line, sec->name, key);
			return SSC_EXIT_FAIL;
		}
		for (size_t j = 0; j < sec->n; j++)
			if ((int)sec->spec[j].line == l) {
				ssc_err(cmd, "%s: line %zu: [%s] %s: given twice", path, line,
					sec->name, key);
				return SSC_EXIT_FAIL;
			}
		{
			const struct sscope_datasheet_info *in =
				sscope_datasheet_info((enum sscope_datasheet_line)l);
			char want[64];
			const char *eg = conv_unit[l][s];

			if (!strcmp(in->si_suffix, "1"))
				snprintf(want, sizeof(want), "1");
			else
				snprintf(want, sizeof(want), "%s%s", rate_unit(q), in->si_suffix);
			{
				struct sscope_unit a, b;

				/* the example unit must be of the wanted dimension */
				if (sscope_unit_parse(eg, &a, NULL) ||
				    sscope_unit_parse(want, &b, NULL) ||
				    !sscope_unit_compatible(&a, &b))
					eg = want;
			}
			rc = parse_value(cmd, path, line, key, v, eg,
					 &sec->spec[sec->n].value, sec->unit[sec->n],
					 sizeof(sec->unit[0]));
			if (rc)
				return rc;
		}
		sec->spec[sec->n].line = (enum sscope_datasheet_line)l;
		snprintf(sec->written[sec->n], sizeof(sec->written[0]), "%s", v);
		rms |= l == SSCOPE_DATASHEET_RMS_NOISE;
		sec->n++;
	}
	for (size_t j = 0; j < sec->n; j++)
		sec->spec[j].bandwidth_hz = sec->bandwidth_hz;
	if (rms && isnan(sec->bandwidth_hz)) {
		ssc_err(cmd, "%s: [%s] rms_noise: needs noise_bandwidth (e.g. the ODR / 2 for an unfiltered output)",
			path, sec->name);
		return SSC_EXIT_FAIL;
	}
	return 0;
}

int ssc_datasheet_load(const char *cmd, const char *path,
		       struct ssc_datasheet *ds)
{
	static const char *const head_keys[] = { "name", "source", NULL };
	struct sscope_diag d = { "" };
	struct ssc_ini *ini = NULL;
	const char *v;
	int rc;

	memset(ds, 0, sizeof(*ds));
	ds->path = path;
	rc = ssc_ini_load(&ini, path, &d);
	if (rc)
		return ssc_fail(cmd, rc, &d, path);
	for (size_t i = 0; i < ssc_ini_n_sections(ini); i++) {
		size_t line;
		const char *s = ssc_ini_section(ini, i, &line);

		if (strcmp(s, "datasheet") && strcmp(s, "gyro") && strcmp(s, "accel")) {
			ssc_err(cmd, "%s: line %zu: [%s]: unknown section (known: datasheet, gyro, accel)",
				path, line, s);
			ssc_ini_free(ini);
			return SSC_EXIT_FAIL;
		}
	}
	if (ssc_ini_has_section(ini, "datasheet") &&
	    (rc = ssc_ini_check_keys(ini, "datasheet", head_keys, &d))) {
		ssc_ini_free(ini);
		return ssc_fail(cmd, rc, &d, path);
	}
	v = ssc_ini_get(ini, "datasheet", "name", NULL);
	snprintf(ds->name, sizeof(ds->name), "%s", v ? v : path);
	v = ssc_ini_get(ini, "datasheet", "source", NULL);
	snprintf(ds->source, sizeof(ds->source), "%s", v ? v : "");
	for (size_t s = 0; s < 2; s++) {
		if (!ssc_ini_has_section(ini, section_names[s]))
			continue;
		rc = load_section(cmd, ini, path, s, &ds->sec[ds->n_sec]);
		if (rc) {
			ssc_ini_free(ini);
			return rc;
		}
		ds->n_sec++;
	}
	ssc_ini_free(ini);
	if (!ds->n_sec) {
		ssc_err(cmd, "%s: no [gyro] or [accel] section", path);
		return SSC_EXIT_FAIL;
	}
	return 0;
}

/* ------------------------------------------------------------ conversion */

/* the section's terms N, B, K (NaN when no line gives them), from the
 * first line of each in the order of enum sscope_datasheet_line */
static void section_terms(const struct ssc_ds_section *sec, double t[3],
			  int from[3])
{
	for (int i = 0; i < 3; i++) {
		t[i] = NAN;
		from[i] = -1;
	}
	for (int l = 0; l < SSC_DS_LINES; l++)
		for (size_t j = 0; j < sec->n; j++) {
			const struct sscope_datasheet_spec *s = &sec->spec[j];
			const struct sscope_datasheet_info *in = sscope_datasheet_info(s->line);
			double f;
			int i = in->term == SSCOPE_TERM_N ? 0 : in->term == SSCOPE_TERM_B ? 1 :
				in->term == SSCOPE_TERM_K ? 2 : -1;

			if ((int)s->line != l || i < 0 || from[i] >= 0 ||
			    sscope_datasheet_factor(s->line, s->bandwidth_hz, &f))
				continue;
			t[i] = s->value / f;
			from[i] = (int)j;
		}
}

void ssc_datasheet_terms(const struct ssc_ds_section *sec, double t[3],
			 int from[3])
{
	section_terms(sec, t, from);
}

/* the terms as line @p l (SI), NaN when they do not give it; *lower: a
 * lower bound (GJB from terms) */
static double as_line(const struct ssc_ds_section *sec, const double t[3],
		      enum sscope_datasheet_line l, bool *lower)
{
	const struct sscope_datasheet_info *in = sscope_datasheet_info(l);
	double f;

	*lower = false;
	if (in->tau_s > 0) {
		double v;

		*lower = true;
		v = isnan(t[0]) && isnan(t[1]) ? (double)NAN :
			sscope_datasheet_gjb_from_terms(t[0], t[1], t[2], in->tau_s);
		/* terms near the double's end square beyond it: no line */
		return isfinite(v) ? v : (double)NAN;
	}
	if (in->term == SSCOPE_TERM_COUNT_ ||
	    sscope_datasheet_factor(l, sec->bandwidth_hz, &f))
		return NAN;
	return f * t[in->term == SSCOPE_TERM_N ? 0 : in->term == SSCOPE_TERM_B ? 1 : 2];
}

static double to_unit(double si, const char *si_unit, const char *unit)
{
	double v;

	return sscope_unit_convert_text(si, si_unit, unit, &v) ? (double)NAN : v;
}

static json_t *convert_json(const struct ssc_datasheet *ds)
{
	json_t *r = json_object(), *secs = json_array();

	json_object_set_new(r, "command", json_string("datasheet"));
	json_object_set_new(r, "datasheet", json_string(ds->path));
	json_object_set_new(r, "name", json_string(ds->name));
	json_object_set_new(r, "source", json_string(ds->source));
	for (size_t s = 0; s < ds->n_sec; s++) {
		const struct ssc_ds_section *sec = &ds->sec[s];
		json_t *o = json_object(), *lines = json_array(), *terms = json_object(),
		       *back = json_array();
		int ci = sec->quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? 0 : 1;
		double t[3];
		int from[3];

		section_terms(sec, t, from);
		json_object_set_new(o, "section", json_string(sec->name));
		json_object_set_new(o, "quantity", json_string(sscope_quantity_name(sec->quantity)));
		json_object_set_new(o, "noise_bandwidth_hz", ssc_jreal(sec->bandwidth_hz));
		for (size_t j = 0; j < sec->n; j++) {
			const struct sscope_datasheet_spec *sp = &sec->spec[j];
			const struct sscope_datasheet_info *in = sscope_datasheet_info(sp->line);
			json_t *l = json_object();
			char su[48];
			double f;

			si_unit_of(sec->quantity, sp->line, su, sizeof(su));
			json_object_set_new(l, "key", json_string(in->key));
			json_object_set_new(l, "name", json_string(in->name));
			json_object_set_new(l, "definition", json_string(in->definition));
			json_object_set_new(l, "written", json_string(sec->written[j]));
			json_object_set_new(l, "si", ssc_jreal(sp->value));
			json_object_set_new(l, "si_unit", json_string(su));
			if (term_key(in->term) &&
			    !sscope_datasheet_factor(sp->line, sp->bandwidth_hz, &f)) {
				json_object_set_new(l, "term", json_string(term_key(in->term)));
				json_object_set_new(l, "term_si", ssc_jreal(sp->value / f));
				json_object_set_new(l, "term_si_unit",
						    json_string(sscope_term_si_unit(sec->quantity, in->term)));
			} else {
				json_object_set_new(l, "term", json_null());
			}
			json_array_append_new(lines, l);
		}
		for (int i = 0; i < 3; i++) {
			enum sscope_term tt = i == 0 ? SSCOPE_TERM_N : i == 1 ? SSCOPE_TERM_B :
							   SSCOPE_TERM_K;

			if (from[i] < 0) {
				json_object_set_new(terms, term_key(tt), json_null());
				continue;
			}
			json_object_set_new(terms, term_key(tt),
					    ssc_json_coef(t[i], NAN, NAN,
							  sscope_term_unit(sec->quantity, tt),
							  sscope_term_si_unit(sec->quantity, tt),
							  true));
			json_object_set_new(json_object_get(terms, term_key(tt)), "from",
					    json_string(sscope_datasheet_info(sec->spec[from[i]].line)->key));
		}
		for (int l = 0; l < SSC_DS_LINES; l++) {
			bool lower;
			double v = as_line(sec, t, (enum sscope_datasheet_line)l, &lower);
			json_t *b;
			char su[48];

			if (isnan(v))
				continue;
			si_unit_of(sec->quantity, (enum sscope_datasheet_line)l, su, sizeof(su));
			b = json_object();
			json_object_set_new(b, "key", json_string(sscope_datasheet_info((enum sscope_datasheet_line)l)->key));
			json_object_set_new(b, "value", ssc_jreal(to_unit(v, su, conv_unit[l][ci])));
			json_object_set_new(b, "unit", json_string(conv_unit[l][ci]));
			json_object_set_new(b, "si", ssc_jreal(v));
			json_object_set_new(b, "si_unit", json_string(su));
			json_object_set_new(b, "lower_bound", json_boolean(lower));
			json_array_append_new(back, b);
		}
		json_object_set_new(o, "lines", lines);
		json_object_set_new(o, "terms", terms);
		json_object_set_new(o, "as_lines", back);
		json_array_append_new(secs, o);
	}
	json_object_set_new(r, "sections", secs);
	return r;
}

int ssc_datasheet_convert(const struct ssc_common *co,
			  const struct ssc_datasheet *ds)
{
	struct ssc_out out;
	int rc;

	if (co->format == SSC_FMT_JSON)
		return ssc_emit_json(co, convert_json(ds));
	if (co->format == SSC_FMT_CSV)
		return ssc_usage_error(co->cmd, "--format csv: not available (text or json)");
	rc = ssc_out_open(co, &out);
	if (rc)
		return rc;
	fprintf(out.f, "%s%s%s\n", ds->name, ds->source[0] ? " -- " : "", ds->source);
	for (size_t s = 0; s < ds->n_sec; s++) {
		const struct ssc_ds_section *sec = &ds->sec[s];
		int ci = sec->quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? 0 : 1;
		double t[3];
		int from[3];
		char a[32], b[32];

		section_terms(sec, t, from);
		fprintf(out.f, "[%s] %s\n", sec->name, sscope_quantity_name(sec->quantity));
		for (size_t j = 0; j < sec->n; j++) {
			const struct sscope_datasheet_spec *sp = &sec->spec[j];
			const struct sscope_datasheet_info *in = sscope_datasheet_info(sp->line);
			char su[48];
			double f;

			si_unit_of(sec->quantity, sp->line, su, sizeof(su));
			fprintf(out.f, "  %-22s = %-24s %s %s", in->key, sec->written[j],
				ssc_fmt(a, sizeof(a), sp->value, 6),
				strcmp(su, "1") ? su : "(ratio)");
			if (term_key(in->term) &&
			    !sscope_datasheet_factor(sp->line, sp->bandwidth_hz, &f))
				fprintf(out.f, "  ->  %s = %s %s", term_key(in->term),
					ssc_fmt(b, sizeof(b), sp->value / f, 6),
					sscope_term_si_unit(sec->quantity, in->term));
			fprintf(out.f, "\n      %s\n", in->definition);
		}
		/* two lines of one term that disagree: the first is used,
		 * and the user reads which */
		for (size_t j = 0; j < sec->n; j++) {
			const struct sscope_datasheet_spec *sp = &sec->spec[j];
			const struct sscope_datasheet_info *in = sscope_datasheet_info(sp->line);
			int i = in->term == SSCOPE_TERM_N ? 0 : in->term == SSCOPE_TERM_B ? 1 :
				in->term == SSCOPE_TERM_K ? 2 : -1;
			double f;

			if (i < 0 || from[i] < 0 || (size_t)from[i] == j ||
			    sscope_datasheet_factor(sp->line, sp->bandwidth_hz, &f) ||
			    fabs(sp->value / f - t[i]) <= 0.05 * fabs(t[i]))
				continue;
			fprintf(out.f, "  note: %s and %s give %s = %s and %s %s: the terms below use %s\n",
				sscope_datasheet_info(sec->spec[from[i]].line)->key, in->key,
				term_key(in->term), ssc_fmt(a, sizeof(a), t[i], 4),
				ssc_fmt(b, sizeof(b), sp->value / f, 4),
				sscope_term_si_unit(sec->quantity, in->term),
				sscope_datasheet_info(sec->spec[from[i]].line)->key);
		}
		fprintf(out.f, "  the terms as datasheet lines:\n");
		for (int l = 0; l < SSC_DS_LINES; l++) {
			bool lower;
			double v = as_line(sec, t, (enum sscope_datasheet_line)l, &lower);
			const struct sscope_datasheet_info *in =
				sscope_datasheet_info((enum sscope_datasheet_line)l);
			char su[48], name[64];

			if (isnan(v))
				continue;
			si_unit_of(sec->quantity, (enum sscope_datasheet_line)l, su, sizeof(su));
			if (l == SSCOPE_DATASHEET_RMS_NOISE)
				snprintf(name, sizeof(name), "rms noise over %s Hz",
					 ssc_fmt(b, sizeof(b), sec->bandwidth_hz, 4));
			else
				snprintf(name, sizeof(name), "%s", in->name);
			fprintf(out.f, "    %-40s %s%s %s\n", name, lower ? ">= " : "",
				ssc_fmt(a, sizeof(a), to_unit(v, su, conv_unit[l][ci]), 4),
				conv_unit[l][ci]);
		}
		if (from[0] < 0 && from[1] < 0)
			fprintf(out.f, "    (no noise line: nothing to convert)\n");
	}
	return ssc_out_close(co, &out, !ferror(out.f));
}

/* ------------------------------------------------------------ verdicts */


/* a measured SI value in the unit the line was written in */
static double in_written(const struct ssc_ds_section *sec, size_t j, double si)
{
	char su[48];

	if (isnan(si))
		return NAN;
	si_unit_of(sec->quantity, sec->spec[j].line, su, sizeof(su));
	return to_unit(si, su, sec->unit[j]);
}

static json_t *verdict_json(const struct ssc_datasheet *ds, const char *capture,
			    double level, const struct ssc_ds_chan *ch, size_t n_ch,
			    const size_t count[3])
{
	json_t *r = json_object(), *chans = json_array(), *sum = json_object();

	json_object_set_new(r, "command", json_string("datasheet"));
	json_object_set_new(r, "datasheet", json_string(ds->path));
	json_object_set_new(r, "name", json_string(ds->name));
	json_object_set_new(r, "source", json_string(ds->source));
	json_object_set_new(r, "capture", json_string(capture));
	json_object_set_new(r, "level", json_real(level));
	for (size_t k = 0; k < n_ch; k++) {
		const struct ssc_ds_section *sec = ch[k].sec;
		json_t *o = json_object(), *arr = json_array();

		json_object_set_new(o, "channel", json_string(ch[k].name));
		json_object_set_new(o, "section", json_string(sec->name));
		for (size_t j = 0; j < sec->n; j++) {
			const struct sscope_datasheet_check *c = &ch[k].c[j];
			const struct sscope_datasheet_info *in = sscope_datasheet_info(c->line);
			json_t *l = json_object(), *lim = json_object();
			char su[48];

			si_unit_of(sec->quantity, c->line, su, sizeof(su));
			json_object_set_new(l, "key", json_string(in->key));
			json_object_set_new(l, "name", json_string(in->name));
			json_object_set_new(l, "definition", json_string(in->definition));
			json_object_set_new(lim, "value", ssc_jreal(in_written(sec, j, c->limit)));
			json_object_set_new(lim, "unit", json_string(sec->unit[j]));
			json_object_set_new(lim, "si", ssc_jreal(c->limit));
			json_object_set_new(lim, "si_unit", json_string(su));
			json_object_set_new(l, "limit", lim);
			json_object_set_new(l, "value", ssc_jreal(in_written(sec, j, c->value)));
			json_object_set_new(l, "lo", ssc_jreal(in_written(sec, j, c->lo)));
			json_object_set_new(l, "hi", ssc_jreal(in_written(sec, j, c->hi)));
			json_object_set_new(l, "unit", json_string(sec->unit[j]));
			json_object_set_new(l, "si", ssc_jreal(c->value));
			json_object_set_new(l, "si_lo", ssc_jreal(c->lo));
			json_object_set_new(l, "si_hi", ssc_jreal(c->hi));
			json_object_set_new(l, "si_unit", json_string(su));
			json_object_set_new(l, "bound", json_boolean(c->bound));
			json_object_set_new(l, "verdict",
					    json_string(sscope_datasheet_verdict_name(c->verdict)));
			json_object_set_new(l, "why", c->why ? json_string(c->why) : json_null());
			json_object_set_new(l, "fit_rejected", json_boolean(c->fit_rejected));
			json_array_append_new(arr, l);
		}
		json_object_set_new(o, "checks", arr);
		json_array_append_new(chans, o);
	}
	json_object_set_new(r, "channels", chans);
	json_object_set_new(sum, "within_spec", json_integer((json_int_t)count[SSCOPE_DATASHEET_WITHIN]));
	json_object_set_new(sum, "out_of_spec", json_integer((json_int_t)count[SSCOPE_DATASHEET_OUT]));
	json_object_set_new(sum, "inconclusive",
			    json_integer((json_int_t)count[SSCOPE_DATASHEET_INCONCLUSIVE]));
	json_object_set_new(r, "summary", sum);
	return r;
}

static void verdict_text(FILE *f, const struct ssc_datasheet *ds,
			 const char *capture, double level,
			 const struct ssc_ds_chan *ch, size_t n_ch)
{
	char a[32], b[32], c3[32];

	fprintf(f, "%s against %s (%s), guard band: %s %% intervals\n", capture, ds->name,
		ds->path, ssc_fmt(a, sizeof(a), level * 100, 4));
	for (size_t k = 0; k < n_ch; k++) {
		const struct ssc_ds_section *sec = ch[k].sec;

		fprintf(f, "%s [%s]\n", ch[k].name, sec->name);
		for (size_t j = 0; j < sec->n; j++) {
			const struct sscope_datasheet_check *c = &ch[k].c[j];
			const struct sscope_datasheet_info *in = sscope_datasheet_info(c->line);
			char meas[128];

			if (!isnan(c->value))
				snprintf(meas, sizeof(meas), "%s [%s, %s] %s",
					 ssc_fmt(a, sizeof(a), in_written(sec, j, c->value), 4),
					 ssc_fmt(b, sizeof(b), in_written(sec, j, c->lo), 4),
					 ssc_fmt(c3, sizeof(c3), in_written(sec, j, c->hi), 4),
					 sec->unit[j]);
			else if (c->bound && !isnan(c->hi))
				snprintf(meas, sizeof(meas), "below %s %s (bound)",
					 ssc_fmt(a, sizeof(a), in_written(sec, j, c->hi), 4),
					 sec->unit[j]);
			else
				snprintf(meas, sizeof(meas), "-");
			fprintf(f, "  %-38s limit %-24s measured %-36s %s\n", in->name,
				sec->written[j], meas, sscope_datasheet_verdict_name(c->verdict));
			if (c->why)
				fprintf(f, "      (%s)\n", c->why);
			if (c->fit_rejected)
				fprintf(f, "      (the noise fit is rejected by its chi-squared test, p < 0.01: indicative only, so inconclusive)\n");
		}
	}
}

int ssc_datasheet_check_capture(const char *cmd, const struct ssc_datasheet *ds,
				const struct sscope_capture *cap,
				const char *capture, double level,
				struct ssc_ds_result **out)
{
	struct ssc_ds_result *r;
	struct sscope_datasheet_opts o = { level };

	*out = NULL;
	if (!(cap->rate_hz > 0)) {
		return ssc_err_no_rate(cmd, capture, cap->rate_note);
	}
	r = calloc(1, sizeof(*r));
	if (r)
		r->ch = calloc(cap->n_channels ? cap->n_channels : 1, sizeof(*r->ch));
	if (!r || !r->ch) {
		free(r);
		return ssc_fail(cmd, -ENOMEM, NULL, capture);
	}
	r->ds = ds;
	r->capture = capture;
	r->level = level;
	for (size_t k = 0; k < cap->n_channels; k++) {
		const struct sscope_capture_channel *c = &cap->channels[k];
		const struct ssc_ds_section *sec = NULL;
		struct sscope_diag d = { "" };
		int rc;

		for (size_t s = 0; s < ds->n_sec; s++)
			if (ds->sec[s].quantity == c->col.quantity)
				sec = &ds->sec[s];
		if (!sec)
			continue;
		r->ch[r->n_ch].name = c->col.name;
		r->ch[r->n_ch].sec = sec;
		rc = sscope_datasheet_check(c->data, 1, cap->n, cap->rate_hz, sec->spec,
					    sec->n, &o, r->ch[r->n_ch].c, &d);
		if (rc) {
			ssc_err(cmd, "%s: channel %s: %s", capture, c->col.name,
				d.msg[0] ? d.msg : sscope_strerror(rc));
			ssc_datasheet_result_free(r);
			return SSC_EXIT_FAIL;
		}
		for (size_t j = 0; j < sec->n; j++)
			r->count[r->ch[r->n_ch].c[j].verdict]++;
		r->n_ch++;
	}
	if (!r->n_ch) {
		ssc_err(cmd, "%s: no channel is a %s: give their units with -u (e.g. -u deg/s)",
			capture, ds->n_sec == 2 ? "gyro or an accelerometer" :
			ds->sec[0].quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? "gyro" :
									    "accelerometer");
		ssc_datasheet_result_free(r);
		return SSC_EXIT_FAIL;
	}
	*out = r;
	return SSC_EXIT_OK;
}

json_t *ssc_datasheet_result_json(const void *opts, const void *result)
{
	const struct ssc_ds_result *r = result;

	(void)opts;
	return verdict_json(r->ds, r->capture, r->level, r->ch, r->n_ch, r->count);
}

void ssc_datasheet_result_text(FILE *f, const void *opts, const void *result)
{
	const struct ssc_ds_result *r = result;

	(void)opts;
	verdict_text(f, r->ds, r->capture, r->level, r->ch, r->n_ch);
}

void ssc_datasheet_result_summary(json_t *rows, const void *opts,
				  const void *result)
{
	const struct ssc_ds_result *r = result;

	(void)opts;
	for (size_t k = 0; k < r->n_ch; k++) {
		const struct ssc_ds_section *sec = r->ch[k].sec;

		for (size_t j = 0; j < sec->n; j++) {
			const struct sscope_datasheet_check *c = &r->ch[k].c[j];
			const struct sscope_datasheet_info *in = sscope_datasheet_info(c->line);
			char note[160];

			snprintf(note, sizeof(note), "%s (limit %s)%s",
				 sscope_datasheet_verdict_name(c->verdict), sec->written[j],
				 c->bound ? ", upper bound" : "");
			ssc_summary_add(rows, r->ch[k].name, in->name,
					c->bound ? (double)NAN : in_written(sec, j, c->value),
					in_written(sec, j, c->lo), in_written(sec, j, c->hi),
					sec->unit[j], note);
			if (c->verdict != SSCOPE_DATASHEET_WITHIN || c->fit_rejected)
				ssc_summary_warn_last(rows);
		}
	}
}

void ssc_datasheet_result_free(void *result)
{
	struct ssc_ds_result *r = result;

	if (r) {
		free(r->ch);
		free(r);
	}
}
