/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The lot's CSV (one row per unit, channel and term) and its report
 * folder (lot.h): a page for the lot (the spread of every term, the
 * verdicts against the limits, both figures, one row per unit) and a page
 * per unit (each term with its interval, z, outlier flag, verdict and
 * doubt), with the lot's JSON, CSV and figures beside them.
 */
#include "workbench.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "html.h"
#include "lot.h"

static const char *const verdict_text[3] = {
	"inconclusive", "within spec", "out of spec"
};

/* ------------------------------------------------------------- CSV */

static void csv_num(FILE *f, double v)
{
	if (isfinite(v))
		fprintf(f, ",%.10g", v);
	else
		fputc(',', f);
}

static void csv_str(FILE *f, const char *s, bool first)
{
	if (!first)
		fputc(',', f);
	if (!s)
		return;
	if (!strpbrk(s, ",\"\n\r")) {
		fputs(s, f);
		return;
	}
	fputc('"', f);
	for (; *s; s++) {
		if (*s == '"')
			fputc('"', f);
		fputc(*s, f);
	}
	fputc('"', f);
}

void ssc_lot_csv(FILE *f, const void *opts, const void *result)
{
	const struct ssc_lot_result *r = result;

	(void)opts;
	if (r->note[0]) {
		fputs("note\n", f);
		csv_str(f, r->note, true);
		fputc('\n', f);
		return;
	}
	fputs("unit,path,channel,term,value,lo,hi,value_unit,se,present,z,outlier,limit,verdict,doubt,se_upper\n", f);
	for (size_t u = 0; u < r->n_units; u++)
		for (size_t c = 0; c < r->n_chan; c++)
			for (int t = 0; t < SSC_LOT_NT; t++) {
				const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];
				const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
				const char *unit;

				if (t == SSC_LOT_TEMPCO && !r->temp)
					continue;
				ssc_lot_value(r, c, t, 1, &unit);
				csv_str(f, ssc_lot_unit_name(r, u), true);
				csv_str(f, r->paths[u], false);
				csv_str(f, r->chan[c], false);
				csv_str(f, ssc_lot_term_key(t), false);
				csv_num(f, ssc_lot_value(r, c, t, cl->v[t], &unit));
				csv_num(f, ssc_lot_value(r, c, t, cl->lo[t], &unit));
				csv_num(f, ssc_lot_value(r, c, t, cl->hi[t], &unit));
				csv_str(f, unit, false);
				csv_num(f, ssc_lot_value(r, c, t, cl->se[t], &unit));
				csv_str(f, cl->present[t] ? "yes" : "no", false);
				csv_num(f, T->z ? T->z[u] : (double)NAN);
				csv_str(f, T->outlier && T->outlier[u] ? "yes" : "no", false);
				if (cl->has_spec[t]) {
					csv_num(f, ssc_lot_value(r, c, t, T->limit, &unit));
					csv_str(f, verdict_text[cl->verdict[t]], false);
				} else {
					fputs(",,", f);
				}
				csv_str(f, ssc_lot_doubt(cl, t), false);
				if (isinf(ssc_lot_se_upper(cl, t)))
					fputs(",inf", f);
				else
					csv_num(f, ssc_lot_value(r, c, t, ssc_lot_se_upper(cl, t), &unit));
				fputc('\n', f);
			}
}

/* ---------------------------------------------------------- report */

/* "1.23 [1.1, 1.4]" of a unit's term, or why there is none */
static void cell_text(const struct ssc_lot_result *r, size_t c, int t,
		      const struct ssc_lot_cell *cl, char *buf, size_t len)
{
	char a[32], b[32], d[32];
	const char *unit;

	if (!cl->present[t]) {
		snprintf(buf, len, t < SSC_LOT_BIAS ? "not shown by the fit" : "-");
		return;
	}
	snprintf(buf, len, "%s [%s, %s]%s",
		 ssc_fmt(a, sizeof(a), ssc_lot_value(r, c, t, cl->v[t], &unit), 4),
		 ssc_fmt(b, sizeof(b), ssc_lot_value(r, c, t, cl->lo[t], &unit), 3),
		 ssc_fmt(d, sizeof(d), ssc_lot_value(r, c, t, cl->hi[t], &unit), 3),
		 ssc_lot_doubt(cl, t) ? " ~" : "");
}

/* the unit's marks in term t of channel c: outlier, verdict */
static void marks(const struct ssc_lot_result *r, size_t c, int t, size_t u,
		  char *buf, size_t len)
{
	const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
	const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];
	char z[32];

	snprintf(buf, len, "%s%s%s%s",
		 T->outlier && T->outlier[u] ? "OUTLIER (z " : "",
		 T->outlier && T->outlier[u] ? ssc_fmt(z, sizeof(z), T->z[u], 3) : "",
		 T->outlier && T->outlier[u] ? ") " : "",
		 cl->has_spec[t] ? verdict_text[cl->verdict[t]] : "");
}

static int unit_page(const struct ssc_lot_result *r, size_t u, const char *path)
{
	struct ssc_html *h;
	static const char *const head[] = {
		"channel", "term", "value [68.3 % interval]", "unit", "z in the lot",
		"outlier, verdict", "doubt"
	};
	char title[256];
	int rc;

	snprintf(title, sizeof(title), "Unit %s of a lot of %zu", ssc_lot_unit_name(r, u),
		 r->n_units);
	h = ssc_html_new(title);
	if (!h)
		return -ENOMEM;
	ssc_html_h1(h, title);
	ssc_html_p(h, "Capture: %s, %.10g Hz, %zu samples (%.4g s).",
		   r->paths[u], r->rate_hz[u], r->n_samples[u],
		   (double)r->n_samples[u] / r->rate_hz[u]);
	ssc_html_raw(h, "<p><a href=\"../index.html\">Back to the lot</a></p>\n");
	ssc_html_table_begin(h, "data", head, 7);
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < SSC_LOT_NT; t++) {
			const struct ssc_lot_cell *cl = &r->cell[u * r->n_chan + c];
			const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
			char v[96], m[96], z[32];
			const char *unit, *cells[7];

			if (t == SSC_LOT_TEMPCO && !r->temp)
				continue;
			ssc_lot_value(r, c, t, 1, &unit);
			cell_text(r, c, t, cl, v, sizeof(v));
			marks(r, c, t, u, m, sizeof(m));
			cells[0] = r->chan[c];
			cells[1] = ssc_lot_term_label(t);
			cells[2] = v;
			cells[3] = unit;
			cells[4] = T->z && isfinite(T->z[u]) ? ssc_fmt(z, sizeof(z), T->z[u], 3) : "-";
			cells[5] = m[0] ? m : "-";
			cells[6] = ssc_lot_doubt(cl, t) ? ssc_lot_doubt(cl, t) : "";
			ssc_html_table_row(h, cells, 7);
		}
	ssc_html_table_end(h);
	ssc_html_note(h, "A term the unit's fit does not show is left out of that term's lot; ~ marks an interval that is too narrow, or that flicker or a random walk the record cannot rule out would widen more than 1.5 times (see doubt; a verdict on the drift or temperature sensitivity uses that wider interval).");
	rc = ssc_html_write(h, path);
	ssc_html_free(h);
	return rc;
}

static bool empty_dir(const char *dir)
{
	DIR *d = opendir(dir);
	struct dirent *e;
	bool empty = true;

	if (!d)
		return false;
	while ((e = readdir(d)))
		if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
			empty = false;
	closedir(d);
	return empty;
}

static void lot_table(struct ssc_html *h, const struct ssc_lot_result *r)
{
	static const char *const head[] = {
		"channel", "term", "unit", "units showing it", "mean [interval]",
		"between-unit sd [interval]", "outliers"
	};
	char lvl[32];

	ssc_html_h2(h, "spread", "Spread between the units");
	ssc_html_p(h, "%s %% intervals; the spread between units separated from each unit's own uncertainty (random effects: REML, Q-profile interval; the mean by Hartung-Knapp); outliers by a robust z at 1 %% per unit.",
		   ssc_fmt(lvl, sizeof(lvl), 100 * r->level, 3));
	ssc_html_table_begin(h, "data", head, 7);
	for (size_t c = 0; c < r->n_chan; c++)
		for (int t = 0; t < SSC_LOT_NT; t++) {
			const struct ssc_lot_term *T = &r->term[c * SSC_LOT_NT + (size_t)t];
			char shown[32], m[96], b[96], out[1024] = "";
			const char *unit, *cells[7];

			if (t == SSC_LOT_TEMPCO && !r->temp)
				continue;
			ssc_lot_value(r, c, t, 1, &unit);
			snprintf(shown, sizeof(shown), "%zu of %zu", T->n_resolved, r->n_units);
			if (T->done) {
				ssc_lot_spread_text(r, c, t, m, sizeof(m), b, sizeof(b));
			} else {
				snprintf(m, sizeof(m), "fewer than 3 units: no spread");
				b[0] = 0;
			}
			for (size_t u = 0; T->outlier && u < r->n_units; u++)
				if (T->outlier[u]) {
					size_t l = strlen(out);

					snprintf(out + l, sizeof(out) - l, "%s%s", l ? ", " : "",
						 ssc_lot_unit_name(r, u));
				}
			cells[0] = r->chan[c];
			cells[1] = ssc_lot_term_label(t);
			cells[2] = unit;
			cells[3] = shown;
			cells[4] = m;
			cells[5] = b;
			cells[6] = out[0] ? out : "-";
			ssc_html_table_row(h, cells, 7);
		}
	ssc_html_table_end(h);
}

static void units_table(struct ssc_html *h, const struct ssc_lot_result *r)
{
	ssc_html_h2(h, "units", "The units");
	ssc_html_p(h, "Each unit's N, B, K and bias with their 68.3 %% intervals; OUTLIER and the verdict against the limits beside a value; the unit's page has every term.");
	ssc_html_raw(h, "<table class=\"data\"><thead><tr><th>unit</th><th>capture</th><th>channel</th><th>N</th><th>B</th><th>K</th><th>bias</th></tr></thead><tbody>\n");
	for (size_t u = 0; u < r->n_units; u++)
		for (size_t c = 0; c < r->n_chan; c++) {
			char link[96];

			ssc_html_raw(h, "<tr><td>");
			if (c == 0) {
				snprintf(link, sizeof(link), "<a href=\"units/unit-%zu.html\">", u);
				ssc_html_raw(h, link);
				ssc_html_text(h, ssc_lot_unit_name(r, u));
				ssc_html_raw(h, "</a>");
			}
			ssc_html_raw(h, "</td><td>");
			if (c == 0)
				ssc_html_text(h, r->paths[u]);
			ssc_html_raw(h, "</td><td>");
			ssc_html_text(h, r->chan[c]);
			ssc_html_raw(h, "</td>");
			for (int t = 0; t <= SSC_LOT_BIAS; t++) {
				char v[96], m[96], cell[200];
				const char *unit;

				ssc_lot_value(r, c, t, 1, &unit);
				cell_text(r, c, t, &r->cell[u * r->n_chan + c], v, sizeof(v));
				marks(r, c, t, u, m, sizeof(m));
				snprintf(cell, sizeof(cell), "%s %s%s%s", v, unit, m[0] ? "; " : "", m);
				ssc_html_raw(h, "<td>");
				ssc_html_text(h, cell);
				ssc_html_raw(h, "</td>");
			}
			ssc_html_raw(h, "</tr>\n");
		}
	ssc_html_raw(h, "</tbody></table>\n");
}

int ssc_lot_report(const struct ssc_common *co, const struct ssc_lot_result *r,
		   const char *dir)
{
	const char *cmd = co->cmd;
	struct ssc_common cj = *co;
	struct ssc_html *h = NULL;
	char *p = NULL, *ud = NULL, name[64], title[128];
	struct ssc_out at;
	int rc = 0;

	if (r->note[0])
		return 0;
	if (!empty_dir(dir) && mkdir(dir, 0777)) {
		ssc_err(cmd, "--report: %s: %s", dir, errno == EEXIST ?
			"exists and is not an empty folder: give a new one (nothing in it is overwritten)" :
			sscope_strerror(errno));
		return SSC_EXIT_FAIL;
	}
	ud = ssc_path_join(dir, "units");
	if (!ud || (mkdir(ud, 0777) && errno != EEXIST)) {
		ssc_err(cmd, "--report: %s: %s", ud ? ud : dir, sscope_strerror(ud ? errno : ENOMEM));
		free(ud);
		return SSC_EXIT_FAIL;
	}
	/* the figures, the JSON and the CSV */
	p = ssc_path_join(dir, "lot.svg");
	rc = p ? ssc_lot_plot(co, NULL, r, p) : ssc_fail(cmd, -ENOMEM, NULL, NULL);
	free(p);
	p = ssc_path_join(dir, "lot.json");
	cj.output = p;
	if (!rc)
		rc = p ? ssc_emit_json(&cj, ssc_lot_json(NULL, r)) : ssc_fail(cmd, -ENOMEM, NULL, NULL);
	free(p);
	p = ssc_path_join(dir, "lot.csv");
	if (!rc && !(rc = p ? ssc_file_open(cmd, p, &at) : ssc_fail(cmd, -ENOMEM, NULL, NULL))) {
		ssc_lot_csv(at.f, NULL, r);
		rc = ssc_file_close(&at, !ferror(at.f));
	}
	free(p);
	for (size_t u = 0; u < r->n_units && !rc; u++) {
		snprintf(name, sizeof(name), "unit-%zu.html", u);
		p = ssc_path_join(ud, name);
		rc = p ? unit_page(r, u, p) : -ENOMEM;
		if (rc)
			rc = ssc_write_failed(cmd, p ? p : ud, rc);
		free(p);
	}
	/* the lot's page */
	snprintf(title, sizeof(title), "Lot of %zu units", r->n_units);
	if (!rc && !(h = ssc_html_new(title)))
		rc = ssc_fail(cmd, -ENOMEM, NULL, NULL);
	if (!rc) {
		ssc_html_h1(h, title);
		ssc_html_p(h, "Made by sensorscope %s lot. The lot's numbers: lot.json, lot.csv (one row per unit, channel and term).",
			   PACKAGE_VERSION);
		lot_table(h, r);
		ssc_html_h2(h, "figures", "Figures");
		p = ssc_path_join(dir, "lot.svg");
		if (p)
			ssc_html_svg(h, p, "Each unit's bias against time (a moving mean), outliers thick red and named, the median and 5-95 % band of the others.", "lot.svg");
		free(p);
		p = ssc_path_join(dir, "lot-adev.svg");
		if (p)
			ssc_html_svg(h, p, "Each unit's Allan deviation with the median of the units (outliers in N, B or K thick red).", "lot-adev.svg");
		free(p);
		units_table(h, r);
		{
			char *text = NULL;
			size_t len = 0;
			FILE *m = open_memstream(&text, &len);

			if (m) {
				ssc_lot_text(m, NULL, r);
				if (!fclose(m) && text)
					ssc_html_details(h, r->spec ?
						"The lot as text, with the verdicts against the limits and Cpk" :
						"The lot as text", text);
			}
			free(text);
		}
		p = ssc_path_join(dir, "index.html");
		rc = p ? ssc_html_write(h, p) : -ENOMEM;
		if (rc)
			rc = ssc_write_failed(cmd, p ? p : dir, rc);
		free(p);
	}
	ssc_html_free(h);
	free(ud);
	return rc;
}
