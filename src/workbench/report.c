/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The report as a document (see report.h).  Everything comes from the
 * summary rows and the stages' JSON results -- the same objects report.json
 * holds -- so the HTML says what the machine-readable report says: results
 * in tables with their interval, unit and status; every "warnings" entry a
 * stage attached (a rejected fit, an unresolved term, ...) as a banner at
 * the top and in its section; figures inline as SVG; the definitions with
 * their formulas in MathML (no script, no network), each section linking
 * to its own.
 */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "workbench.h"
#include "report.h"
#include "lot.h"

/* ---------------------------------------------------------------- JSON */

static const char *jstr(const json_t *o, const char *key)
{
	const char *s = json_string_value(json_object_get(o, key));

	return s ? s : "";
}

static double jnum(const json_t *o, const char *key)
{
	const json_t *v = json_object_get(o, key);

	return json_is_number(v) ? json_number_value(v) : (double)NAN;
}

/* a unit string of o as people read it */
static const char *junit(char *buf, size_t len, const json_t *o, const char *key)
{
	ssc_unit_pretty(jstr(o, key), buf, len);
	return buf;
}

static const char *num(char *buf, size_t len, double v, int sig)
{
	if (!isfinite(v)) {
		snprintf(buf, len, "-");
		return buf;
	}
	return ssc_fmt(buf, len, v, sig);
}

/* "[lo, hi]" or "" */
static const char *interval(char *buf, size_t len, double lo, double hi)
{
	char a[32], b[32];

	if (!isfinite(lo) && !isfinite(hi)) {
		buf[0] = '\0';
		return buf;
	}
	snprintf(buf, len, "[%s, %s]", num(a, sizeof(a), lo, 4),
		 num(b, sizeof(b), hi, 4));
	return buf;
}

/* Call f on every entry of every "warnings" array inside j. */
static void walk_warnings(const json_t *j,
			  void (*f)(const json_t *w, void *ctx), void *ctx)
{
	const char *key;
	json_t *v;
	size_t i;

	if (json_is_object(j)) {
		const json_t *w = json_object_get(j, "warnings");

		if (json_is_array(w))
			json_array_foreach(w, i, v)
				f(v, ctx);
		json_object_foreach((json_t *)j, key, v)
			if (strcmp(key, "warnings"))
				walk_warnings(v, f, ctx);
	} else if (json_is_array(j)) {
		json_array_foreach(j, i, v)
			walk_warnings(v, f, ctx);
	}
}

static void count_one(const json_t *w, void *ctx)
{
	(void)w;
	(*(size_t *)ctx)++;
}

size_t ssc_report_count_warnings(const json_t *result)
{
	size_t n = 0;

	walk_warnings(result, count_one, &n);
	return n;
}

/* ---------------------------------------------------------------- HTML */

struct banner_ctx {
	struct ssc_html *h;
	const char *href;
};

static void banner_one(const json_t *w, void *ctx)
{
	struct banner_ctx *b = ctx;
	const char *code = jstr(w, "code");
	const char *title = !strcmp(code, "fit_rejected") ? "Fit rejected." :
			    !strcmp(code, "term_unresolved") ? "Term present, not measured." :
			    !strcmp(code, "fit_failed") ? "No noise terms." :
			    !strcmp(code, "too_few_samples") ? "Too few samples." :
			    !strcmp(code, "zero_spectrum") ? "Zero spectrum." :
			    !strcmp(code, "clipped") ? "Clipped data." :
							  "Check.";

	ssc_html_banner(b->h, "warn", title, jstr(w, "message"), b->href);
}

/* A lot's outlier units and doubtful intervals, which its result keeps
 * outside "warnings": a banner each kind; the number of banners. */
static size_t lot_banners(struct ssc_html *h, const json_t *lot,
			  const char *href)
{
	const json_t *units = json_object_get(lot, "units");
	const json_t *o, *u, *c, *t;
	const char *key;
	size_t i, j, n = 0, doubt = 0;
	char msg[1024];

	json_array_foreach(json_object_get(lot, "outliers"), i, o) {
		snprintf(msg, sizeof(msg), "%s: %s %s lies %.3g standard deviations from the other units (left out of the lot's mean and spread).",
			 jstr(o, "unit"), jstr(o, "channel"), ssc_lot_key_label(jstr(o, "term")),
			 fabs(json_number_value(json_object_get(o, "z"))));
		ssc_html_banner(h, "warn", "Outlier unit.", msg, href);
		n++;
	}
	json_array_foreach(units, i, u)
		json_array_foreach(json_object_get(u, "channels"), j, c)
			json_object_foreach((json_t *)json_object_get(c, "terms"), key, t)
				doubt += json_is_string(json_object_get(t, "doubt"));
	if (doubt) {
		snprintf(msg, sizeof(msg), "%zu interval%s of the units' terms %s doubtful (marked ~ in the table, each with its reason): read %s as indicative.",
			 doubt, doubt > 1 ? "s" : "", doubt > 1 ? "are" : "is",
			 doubt > 1 ? "them" : "it");
		ssc_html_banner(h, "warn", "Doubtful intervals.", msg, href);
		n++;
	}
	return n;
}

static void summary_table(struct ssc_html *h, const json_t *summary,
			  const char *only_stage, const char *only_channel)
{
	static const char *const head[] = { "stage", "channel", "quantity",
					     "value", "interval", "unit",
					     "status / note" };
	size_t i, n = 0;
	json_t *r;

	json_array_foreach(summary, i, r) {
		char v[32], iv[80], un[96];
		const char *cells[7], *cls[7] = { NULL };
		bool warn = !strcmp(jstr(r, "status"), "warning");

		if (only_stage && strcmp(jstr(r, "stage"), only_stage))
			continue;
		if (only_channel && strcmp(jstr(r, "channel"), only_channel))
			continue;
		if (!n++)
			ssc_html_table_begin(h, "summary", head + (only_stage ? 1 : 0),
					     only_stage ? 6 : 7);
		cells[0] = jstr(r, "stage");
		cells[1] = jstr(r, "channel");
		cells[2] = jstr(r, "quantity");
		cells[3] = num(v, sizeof(v), jnum(r, "value"), 5);
		cells[4] = interval(iv, sizeof(iv), jnum(r, "lo"), jnum(r, "hi"));
		cells[5] = junit(un, sizeof(un), r, "unit");
		cells[6] = jstr(r, "note");
		cls[6] = warn ? "warn" : "";
		cls[4] = "num";
		ssc_html_table_row_cls(h, cells + (only_stage ? 1 : 0),
				       cls + (only_stage ? 1 : 0),
				       only_stage ? 6 : 7);
	}
	if (n)
		ssc_html_table_end(h);
}

/* info: one row per channel */
static void info_tables(struct ssc_html *h, const json_t *res)
{
	static const char *const head[] = { "channel", "unit", "quantity",
					     "rate (Hz)", "samples",
					     "duration (s)", "mean", "sd",
					     "min", "max" };
	const json_t *ch = json_object_get(res, "channels"), *c;
	size_t i;

	if (!json_array_size(ch))
		return;
	ssc_html_table_begin(h, "info", head, 10);
	json_array_foreach(ch, i, c) {
		char b[8][32];
		char un[96];
		const char *cells[10] = {
			jstr(c, "name"), junit(un, sizeof(un), c, "unit"),
			jstr(c, "quantity"),
			num(b[0], 32, jnum(c, "rate_hz"), 6),
			num(b[1], 32, jnum(c, "samples"), 12),
			num(b[2], 32, jnum(c, "duration_s"), 6),
			num(b[3], 32, jnum(c, "mean"), 5),
			num(b[4], 32, jnum(c, "sd"), 4),
			num(b[5], 32, jnum(c, "min"), 5),
			num(b[6], 32, jnum(c, "max"), 5),
		};

		ssc_html_table_row(h, cells, 10);
	}
	ssc_html_table_end(h);
	if (json_array_size(json_object_get(res, "gaps")))
		ssc_html_p(h, "Gaps in the time column: %zu (see the JSON for where).",
			   json_array_size(json_object_get(res, "gaps")));
}

/* allan: the five terms of each channel with their status */
static void allan_tables(struct ssc_html *h, const json_t *res)
{
	static const char *const head[] = { "term", "value", "interval",
					     "unit", "SI value", "SI unit",
					     "status" };
	static const char *const names[5] = { "Q quantization",
					       "N random walk",
					       "B bias instability",
					       "K rate random walk",
					       "R rate ramp" };
	static const char *const key[5] = { "Q", "N", "B", "K", "R" };
	const json_t *ch = json_object_get(res, "channels"), *c;
	size_t i;

	json_array_foreach(ch, i, c) {
		const json_t *nz = json_object_get(c, "noise");
		const json_t *fit = json_object_get(c, "fit");
		char cap[512], b1[32], b2[32], b3[32], dev[16] = "";
		bool rejected = json_is_true(json_object_get(fit, "rejected"));

		if (json_is_string(json_object_get(c, "deviation_label")))
			snprintf(dev, sizeof(dev), "%s", jstr(c, "deviation_label"));
		else
			for (size_t q = 0; q + 1 < sizeof(dev) && jstr(c, "deviation")[q]; q++)
				dev[q] = (char)(jstr(c, "deviation")[q] & ~0x20);

		if (!json_is_object(nz))
			continue;
		if (json_object_get(fit, "p_value"))
			snprintf(cap, sizeof(cap),
				 "%s: %s, fit on %s points, chi-squared %s for %s dof, bootstrap p %s: %s",
				 jstr(c, "name"), dev,
				 num(b1, sizeof(b1), jnum(fit, "points"), 4),
				 num(b2, sizeof(b2), jnum(fit, "chi2"), 3),
				 num(b3, sizeof(b3), jnum(fit, "dof"), 3),
				 ssc_fmt_p((char[32]){ 0 }, 32, jnum(fit, "p_value")),
				 rejected ? "the model is rejected, the terms are indicative only" :
					    "the model is accepted");
		else
			snprintf(cap, sizeof(cap), "%s: %s (not fitted: %s)",
				 jstr(c, "name"), dev,
				 jstr(fit, "error"));
		ssc_html_raw(h, "<table class=\"terms\"><caption>");
		ssc_html_text(h, cap);
		ssc_html_raw(h, "</caption>\n<tr>");
		for (int k = 0; k < 7; k++) {
			ssc_html_raw(h, "<th>");
			ssc_html_text(h, head[k]);
			ssc_html_raw(h, "</th>");
		}
		ssc_html_raw(h, "</tr>\n");
		for (int t = 0; t < 5; t++) {
			const json_t *cf = json_object_get(nz, key[t]);
			bool fitted = json_is_true(json_object_get(cf, "fitted"));
			bool resolved = json_is_true(json_object_get(cf, "resolved"));
			double hi = jnum(cf, "hi");
			char v[32], iv[80], si[32], un[96];
			const char *status, *cells[7], *cls[7] = { NULL };
			char why[320];

			if (!cf)
				continue;
			if (fitted && resolved)
				status = rejected ? "fitted, model rejected" : "resolved";
			else if (fitted)
				status = "present, but the interval reaches 0";
			else {
				/* why the term is only bounded (or not fitted), in
				 * the JSON's words */
				const char *r = jstr(cf, "reason");

				snprintf(why, sizeof(why), "%s%s%s",
					 isfinite(hi) ? "not shown present" : "not fitted",
					 *r ? ": " : "", r);
				status = why;
			}
			if (fitted) {
				num(v, sizeof(v), jnum(cf, "value"), 4);
				interval(iv, sizeof(iv), jnum(cf, "lo"), hi);
				num(si, sizeof(si), jnum(cf, "si"), 4);
			} else {
				snprintf(v, sizeof(v), isfinite(hi) ? "< %s" : "-",
					 num(b1, sizeof(b1), hi, 3));
				iv[0] = '\0';
				snprintf(si, sizeof(si), "-");
			}
			cells[0] = names[t];
			cells[1] = v;
			cells[2] = iv;
			cells[3] = junit(un, sizeof(un), cf, "unit");
			cells[4] = si;
			cells[5] = jstr(cf, "si_unit");
			cells[6] = status;
			cls[1] = "num";
			cls[2] = "num";
			cls[6] = (fitted && (!resolved || rejected)) ? "warn" :
				 fitted ? "ok" : "";
			ssc_html_table_row_cls(h, cells, cls, 7);
		}
		ssc_html_raw(h, "</table>\n");
	}
}

/* psd: the RMS and the peaks that pass the noise-floor test */
static void psd_tables(struct ssc_html *h, const json_t *res)
{
	static const char *const head[] = { "frequency (Hz)", "amplitude",
					     "over the floor", "p-value" };
	const json_t *ch = json_object_get(res, "channels"), *c;
	size_t i;

	json_array_foreach(ch, i, c) {
		const json_t *pk = json_object_get(c, "peaks"), *p;
		const json_t *t = json_object_get(c, "peak_test");
		char b1[32], b2[32], b3[32], line[512];
		size_t k;

		char u1[96], u2[96];

		snprintf(line, sizeof(line),
			 "%s: RMS %s %s over 0 to %s Hz (%s, %s segments).",
			 jstr(c, "name"), num(b1, sizeof(b1), jnum(c, "rms"), 5),
			 junit(u1, sizeof(u1), c, "unit"),
			 num(b2, sizeof(b2), jnum(c, "rate_hz") / 2, 5),
			 junit(u2, sizeof(u2), c, "psd_unit"),
			 num(b3, sizeof(b3), jnum(c, "segments"), 8));
		ssc_html_p(h, "%s", line);
		if (!json_array_size(pk)) {
			snprintf(line, sizeof(line),
				 "No peak stands out of the noise floor (F test at false-alarm probability %s over %s bins, %s degrees of freedom per bin).",
				 num(b1, sizeof(b1), jnum(t, "alpha"), 2),
				 num(b2, sizeof(b2), jnum(t, "bins_tested"), 8),
				 num(b3, sizeof(b3), jnum(t, "edf"), 3));
			ssc_html_banner(h, "ok", "No spectral line.", line,
					"#def-psd");
			continue;
		}
		ssc_html_table_begin(h, "peaks", head, 4);
		json_array_foreach(pk, k, p) {
			char c1[32], c2[160], c3[32], c4[32];
			const char *cells[4] = {
				num(c1, sizeof(c1), jnum(p, "frequency_hz"), 6), c2,
				num(c3, sizeof(c3), jnum(p, "ratio"), 3),
				num(c4, sizeof(c4), jnum(p, "p_value"), 2),
			};

			snprintf(c2, sizeof(c2), "%s %s",
				 num(b1, sizeof(b1), jnum(p, "amplitude"), 4), u1);
			ssc_html_table_row(h, cells, 4);
		}
		ssc_html_table_end(h);
		snprintf(line, sizeof(line),
			 "Each peak listed passed the noise-floor test: p-value below %s (false-alarm probability %s over %s bins).",
			 num(b1, sizeof(b1), jnum(t, "p_threshold"), 2),
			 num(b2, sizeof(b2), jnum(t, "alpha"), 2),
			 num(b3, sizeof(b3), jnum(t, "bins_tested"), 8));
		ssc_html_note(h, "%s", line);
	}
}

/* vibration: severity and the diagnosis with its evidence */
static void vibration_tables(struct ssc_html *h, const json_t *res)
{
	static const char *const head[] = { "channel", "finding", "evidence" };
	const json_t *ch = json_object_get(res, "channels"), *c;
	size_t i, n = 0;

	json_array_foreach(ch, i, c) {
		const json_t *dg = json_object_get(c, "diagnosis"), *d;
		size_t k;

		json_array_foreach(dg, k, d) {
			const char *cells[3] = { jstr(c, "name"), jstr(d, "finding"),
						 jstr(d, "evidence") };

			if (!n++)
				ssc_html_table_begin(h, "findings", head, 3);
			ssc_html_table_row(h, cells, 3);
		}
	}
	if (n)
		ssc_html_table_end(h);
	else if (json_array_size(ch))
		ssc_html_p(h, "No machinery finding (unbalance, misalignment or a bearing defect) in %s.",
			   json_array_size(ch) > 1 ? "these channels" : "this channel");
}

/* ------------------------------------------------------- definitions */

/* MathML of the formulas each stage uses. */
static const struct {
	const char *stage;
	const char *html;
} defs[] = {
	{ "allan",
	  "<p>Overlapping Allan variance of a rate sampled every "
	  "<math><msub><mi>&#964;</mi><mn>0</mn></msub></math>, with "
	  "<math><msub><mi>x</mi><mi>i</mi></msub></math> its integral (angle) "
	  "and <math><mi>&#964;</mi><mo>=</mo><mi>m</mi><msub><mi>&#964;</mi>"
	  "<mn>0</mn></msub></math> (NIST SP 1065):</p>"
	  "<math display=\"block\"><msup><mi>&#963;</mi><mn>2</mn></msup><mo>(</mo>"
	  "<mi>&#964;</mi><mo>)</mo><mo>=</mo><mfrac><mn>1</mn><mrow><mn>2</mn>"
	  "<msup><mi>&#964;</mi><mn>2</mn></msup><mo>(</mo><mi>N</mi><mo>&#8722;</mo>"
	  "<mn>2</mn><mi>m</mi><mo>)</mo></mrow></mfrac><munderover><mo>&#8721;</mo>"
	  "<mrow><mi>i</mi><mo>=</mo><mn>1</mn></mrow><mrow><mi>N</mi><mo>&#8722;</mo>"
	  "<mn>2</mn><mi>m</mi></mrow></munderover><msup><mrow><mo>(</mo><msub><mi>x</mi>"
	  "<mrow><mi>i</mi><mo>+</mo><mn>2</mn><mi>m</mi></mrow></msub><mo>&#8722;</mo>"
	  "<mn>2</mn><msub><mi>x</mi><mrow><mi>i</mi><mo>+</mo><mi>m</mi></mrow></msub>"
	  "<mo>+</mo><msub><mi>x</mi><mi>i</mi></msub><mo>)</mo></mrow><mn>2</mn></msup>"
	  "</math>"
	  "<p>The five IEEE 952 terms, every allowed one fitted at once by "
	  "weighted least squares on the overlapping Allan variance. A term is "
	  "shown present by stepwise likelihood-ratio tests of nested "
	  "generalised-least-squares fits (it enters when its square exceeds "
	  "three standard deviations of what it would be without it, one-sided "
	  "0.135 %); a term not shown present is given as an upper bound, and a "
	  "present term whose interval reaches zero is present but not measured. "
	  "The fit is rejected when the p-value of its chi-squared (from a parametric bootstrap of the fitted model, not the chi-squared distribution) is below 0.01:</p>"
	  "<math display=\"block\"><msup><mi>&#963;</mi><mn>2</mn></msup><mo>(</mo>"
	  "<mi>&#964;</mi><mo>)</mo><mo>=</mo><mfrac><mrow><mn>3</mn><msup><mi>Q</mi>"
	  "<mn>2</mn></msup></mrow><msup><mi>&#964;</mi><mn>2</mn></msup></mfrac><mo>+</mo>"
	  "<mfrac><msup><mi>N</mi><mn>2</mn></msup><mi>&#964;</mi></mfrac><mo>+</mo>"
	  "<mfrac><mrow><mn>2</mn><mo>ln</mo><mn>2</mn></mrow><mi>&#960;</mi></mfrac>"
	  "<msup><mi>B</mi><mn>2</mn></msup><mo>+</mo><mfrac><mrow><msup><mi>K</mi>"
	  "<mn>2</mn></msup><mi>&#964;</mi></mrow><mn>3</mn></mfrac><mo>+</mo>"
	  "<mfrac><mrow><msup><mi>R</mi><mn>2</mn></msup><msup><mi>&#964;</mi><mn>2</mn>"
	  "</msup></mrow><mn>2</mn></mfrac></math>"
	  "<p>so the bias-instability plateau lies at "
	  "<math><msqrt><mn>2</mn><mo>ln</mo><mn>2</mn><mo>/</mo><mi>&#960;</mi></msqrt>"
	  "<mi>B</mi><mo>=</mo><mn>0.664</mn><mi>B</mi></math>.  Each deviation's "
	  "interval comes from the chi-squared distribution with the equivalent "
	  "degrees of freedom <math><mi>&#957;</mi></math> of Greenhall and Riley:</p>"
	  "<math display=\"block\"><mfrac><mrow><mi>&#957;</mi><msup><mover><mi>&#963;</mi>"
	  "<mo>^</mo></mover><mn>2</mn></msup></mrow><msubsup><mi>&#967;</mi><mrow>"
	  "<mi>&#957;</mi><mo>,</mo><mo>(</mo><mn>1</mn><mo>+</mo><mi>p</mi><mo>)</mo>"
	  "<mo>/</mo><mn>2</mn></mrow><mn>2</mn></msubsup></mfrac><mo>&#8804;</mo>"
	  "<msup><mi>&#963;</mi><mn>2</mn></msup><mo>&#8804;</mo><mfrac><mrow><mi>&#957;</mi>"
	  "<msup><mover><mi>&#963;</mi><mo>^</mo></mover><mn>2</mn></msup></mrow>"
	  "<msubsup><mi>&#967;</mi><mrow><mi>&#957;</mi><mo>,</mo><mo>(</mo><mn>1</mn>"
	  "<mo>&#8722;</mo><mi>p</mi><mo>)</mo><mo>/</mo><mn>2</mn></mrow><mn>2</mn>"
	  "</msubsup></mfrac></math>" },
	{ "psd",
	  "<p>Welch's estimate (one-sided density, scipy's conventions): the mean "
	  "over <math><mi>K</mi></math> segments of <math><mi>N</mi></math> samples, "
	  "each detrended and multiplied by the window "
	  "<math><msub><mi>w</mi><mi>n</mi></msub></math>:</p>"
	  "<math display=\"block\"><mover><mi>S</mi><mo>^</mo></mover><mo>(</mo>"
	  "<msub><mi>f</mi><mi>k</mi></msub><mo>)</mo><mo>=</mo><mfrac><mn>2</mn>"
	  "<mrow><mi>K</mi><msub><mi>f</mi><mi>s</mi></msub><msub><mo>&#8721;</mo>"
	  "<mi>n</mi></msub><msubsup><mi>w</mi><mi>n</mi><mn>2</mn></msubsup></mrow>"
	  "</mfrac><munderover><mo>&#8721;</mo><mrow><mi>j</mi><mo>=</mo><mn>1</mn>"
	  "</mrow><mi>K</mi></munderover><msup><mrow><mo>|</mo><munderover>"
	  "<mo>&#8721;</mo><mrow><mi>n</mi><mo>=</mo><mn>0</mn></mrow><mrow><mi>N</mi>"
	  "<mo>&#8722;</mo><mn>1</mn></mrow></munderover><msub><mi>w</mi><mi>n</mi>"
	  "</msub><msub><mi>x</mi><mrow><mi>j</mi><mo>,</mo><mi>n</mi></mrow></msub>"
	  "<msup><mi>e</mi><mrow><mo>&#8722;</mo><mn>2</mn><mi>&#960;</mi><mi>i</mi>"
	  "<mi>k</mi><mi>n</mi><mo>/</mo><mi>N</mi></mrow></msup><mo>|</mo></mrow>"
	  "<mn>2</mn></msup></math>"
	  "<p>Each bin is chi-squared: <math><mi>&#957;</mi><mover><mi>S</mi><mo>^</mo>"
	  "</mover><mo>/</mo><mi>S</mi><mo>&#8764;</mo><msubsup><mi>&#967;</mi>"
	  "<mi>&#957;</mi><mn>2</mn></msubsup></math> with the overlap correction "
	  "(Percival and Walden 1993) for segments shifted by <math><mi>D</mi></math>:</p>"
	  "<math display=\"block\"><mi>&#957;</mi><mo>=</mo><mfrac><mrow><mn>2</mn>"
	  "<mi>K</mi></mrow><mrow><mn>1</mn><mo>+</mo><mn>2</mn><munderover>"
	  "<mo>&#8721;</mo><mrow><mi>j</mi><mo>=</mo><mn>1</mn></mrow><mrow><mi>K</mi>"
	  "<mo>&#8722;</mo><mn>1</mn></mrow></munderover><mo>(</mo><mn>1</mn>"
	  "<mo>&#8722;</mo><mfrac><mi>j</mi><mi>K</mi></mfrac><mo>)</mo><msup>"
	  "<mi>&#961;</mi><mn>2</mn></msup><mo>(</mo><mi>j</mi><mi>D</mi><mo>)</mo>"
	  "</mrow></mfrac><mo>,</mo><mspace width=\"1em\"/><mi>&#961;</mi><mo>(</mo>"
	  "<mi>m</mi><mo>)</mo><mo>=</mo><mfrac><mrow><msub><mo>&#8721;</mo><mi>n</mi>"
	  "</msub><msub><mi>w</mi><mi>n</mi></msub><msub><mi>w</mi><mrow><mi>n</mi>"
	  "<mo>+</mo><mi>m</mi></mrow></msub></mrow><mrow><msub><mo>&#8721;</mo>"
	  "<mi>n</mi></msub><msubsup><mi>w</mi><mi>n</mi><mn>2</mn></msubsup></mrow>"
	  "</mfrac></math>"
	  "<p>A peak is listed when the ratio of its bin to the local floor "
	  "<math><mover><mi>F</mi><mo>^</mo></mover></math> (median of the "
	  "neighbouring bins over the median of "
	  "<math><msubsup><mi>&#967;</mi><mi>&#957;</mi><mn>2</mn></msubsup><mo>/</mo>"
	  "<mi>&#957;</mi></math>) passes an F test at the level "
	  "<math><mi>&#945;</mi><mo>/</mo><mi>M</mi></math> over the "
	  "<math><mi>M</mi></math> bins searched, so noise alone lists a peak in a "
	  "fraction <math><mi>&#945;</mi></math> of spectra:</p>"
	  "<math display=\"block\"><mi>P</mi><mrow><mo>(</mo><msub><mi>F</mi><mrow>"
	  "<mi>&#957;</mi><mo>,</mo><msub><mi>&#957;</mi><mi>f</mi></msub></mrow></msub>"
	  "<mo>&gt;</mo><mover><mi>S</mi><mo>^</mo></mover><mo>(</mo><msub><mi>f</mi>"
	  "<mi>k</mi></msub><mo>)</mo><mo>/</mo><mover><mi>F</mi><mo>^</mo></mover>"
	  "<mo>)</mo></mrow><mo>&lt;</mo><mfrac><mi>&#945;</mi><mi>M</mi></mfrac>"
	  "</math>" },
	{ "tempbias",
	  "<p>Bias against temperature about the reference "
	  "<math><msub><mi>T</mi><mi>ref</mi></msub></math>, the order "
	  "<math><mi>K</mi></math> chosen by an F test:</p>"
	  "<math display=\"block\"><mi>b</mi><mo>(</mo><mi>T</mi><mo>)</mo><mo>=</mo>"
	  "<munderover><mo>&#8721;</mo><mrow><mi>k</mi><mo>=</mo><mn>0</mn></mrow>"
	  "<mi>K</mi></munderover><msub><mi>c</mi><mi>k</mi></msub><msup><mrow><mo>(</mo>"
	  "<mi>T</mi><mo>&#8722;</mo><msub><mi>T</mi><mi>ref</mi></msub><mo>)</mo></mrow>"
	  "<mi>k</mi></msup><mo>+</mo><mi>g</mi><mfrac><mrow><mi>d</mi><mi>T</mi></mrow>"
	  "<mrow><mi>d</mi><mi>t</mi></mrow></mfrac></math>" },
	{ "vibration",
	  "<p>Velocity RMS over 10 to 1000 Hz from the acceleration PSD "
	  "<math><msub><mi>S</mi><mi>a</mi></msub></math>, and the bearing defect "
	  "frequencies for a shaft at <math><msub><mi>f</mi><mi>r</mi></msub></math> "
	  "with <math><mi>n</mi></math> elements of diameter <math><mi>d</mi></math> "
	  "on a pitch diameter <math><mi>D</mi></math>:</p>"
	  "<math display=\"block\"><msub><mi>v</mi><mi>rms</mi></msub><mo>=</mo>"
	  "<msqrt><msubsup><mo>&#8747;</mo><mn>10</mn><mn>1000</mn></msubsup><mfrac>"
	  "<mrow><msub><mi>S</mi><mi>a</mi></msub><mo>(</mo><mi>f</mi><mo>)</mo></mrow>"
	  "<msup><mrow><mo>(</mo><mn>2</mn><mi>&#960;</mi><mi>f</mi><mo>)</mo></mrow>"
	  "<mn>2</mn></msup></mfrac><mi>d</mi><mi>f</mi></msqrt><mo>,</mo><mspace width=\"1em\"/>"
	  "<mi>BPFO</mi><mo>=</mo><mfrac><mi>n</mi><mn>2</mn></mfrac><msub><mi>f</mi>"
	  "<mi>r</mi></msub><mrow><mo>(</mo><mn>1</mn><mo>&#8722;</mo><mfrac><mi>d</mi>"
	  "<mi>D</mi></mfrac><mo>cos</mo><mi>&#966;</mi><mo>)</mo></mrow></math>" },
};

/* ---------------------------------------------------------------- body */

int ssc_report_body(struct ssc_html *h, const json_t *summary,
		    const struct ssc_report_stage *st, size_t n)
{
	size_t warnings = 0;
	int rc = 0;

	ssc_html_raw(h, "<nav class=\"toc\"><a href=\"#summary\">Summary</a>"
			"<a href=\"#checks\">Checks</a>");
	for (size_t i = 0; i < n; i++) {
		ssc_html_raw(h, "<a href=\"#");
		ssc_html_text(h, st[i].name);
		ssc_html_raw(h, "\">");
		ssc_html_text(h, st[i].title);
		ssc_html_raw(h, "</a>");
	}
	ssc_html_raw(h, "<a href=\"#definitions\">Definitions</a>"
			"<a href=\"#provenance\">Provenance</a></nav>\n");
	ssc_html_h2(h, "summary", "Summary");
	summary_table(h, summary, NULL, NULL);
	ssc_html_h2(h, "checks", "Checks");
	for (size_t i = 0; i < n; i++) {
		char href[80];
		struct banner_ctx b = { h, href };

		snprintf(href, sizeof(href), "#%s", st[i].name);
		warnings += ssc_report_count_warnings(st[i].result);
		walk_warnings(st[i].result, banner_one, &b);
		if (st[i].result && !strcmp(st[i].name, "lot"))
			warnings += lot_banners(h, st[i].result, href);
		if (!st[i].result && st[i].why) {
			/* an analysis the data refused */
			char msg[1024];

			snprintf(msg, sizeof(msg), "%s: %s.", st[i].title,
				 st[i].why);
			ssc_html_banner(h, "warn", "Not in the report.", msg,
					href);
			warnings++;
		}
	}
	{
		/* the warnings the analyses said on the terminal */
		size_t i;
		json_t *r;

		json_array_foreach(summary, i, r)
			if (!strcmp(jstr(r, "quantity"), "warning")) {
				char href[80];

				snprintf(href, sizeof(href), "#%s", jstr(r, "stage"));
				ssc_html_banner(h, "warn", "Warning.", jstr(r, "note"),
						href);
				warnings++;
			}
	}
	if (!warnings)
		ssc_html_banner(h, "ok", "Nothing flagged.",
				"No analysis doubts its own result: every fit is accepted, every term reported is resolved, no channel is clipped.",
				NULL);
	for (size_t i = 0; i < n; i++) {
		char href[80];
		struct banner_ctx b = { h, NULL };

		ssc_html_section(h, st[i].name);
		ssc_html_h2(h, NULL, st[i].title);
		if (st[i].why)
			ssc_html_note(h, "Analysis '%s': %s.", st[i].name, st[i].why);
		snprintf(href, sizeof(href), "#def-%s", st[i].name);
		ssc_html_raw(h, "<p class=\"note\">Definitions and formulas: <a href=\"");
		ssc_html_text(h, href);
		ssc_html_raw(h, "\">");
		ssc_html_text(h, st[i].title);
		ssc_html_raw(h, "</a>.</p>\n");
		walk_warnings(st[i].result, banner_one, &b);
		for (size_t f = 0; st[i].figs && st[i].figs[f]; f++) {
			char cap[256];
			int e;

			snprintf(cap, sizeof(cap), "%s%s.", st[i].title,
				 st[i].figs[1] ? " (one figure per capture)" : "");
			e = ssc_html_svg(h, st[i].figs[f], cap,
					 st[i].links ? st[i].links[f] : NULL);
			if (e) {
				ssc_html_note(h, "The figure %s could not be read: %s.",
					      st[i].figs[f], sscope_strerror(-e));
				rc = e;
			}
		}
		if (!strcmp(st[i].name, "info"))
			info_tables(h, st[i].result);
		else if (!strcmp(st[i].name, "allan"))
			allan_tables(h, st[i].result);
		else if (!strcmp(st[i].name, "psd"))
			psd_tables(h, st[i].result);
		else if (!strcmp(st[i].name, "vibration"))
			vibration_tables(h, st[i].result);
		if (strcmp(st[i].name, "allan"))
			summary_table(h, summary, st[i].name, NULL);
		if (st[i].text)
			ssc_html_details(h, "The command's text output", st[i].text);
		ssc_html_section_end(h);
	}
	ssc_html_h2(h, "definitions", "Definitions");
	ssc_html_raw(h, "<dl>\n");
	for (size_t i = 0; i < n; i++) {
		ssc_html_raw(h, "<dt id=\"def-");
		ssc_html_text(h, st[i].name);
		ssc_html_raw(h, "\">");
		ssc_html_text(h, st[i].title);
		ssc_html_raw(h, "</dt><dd>");
		for (size_t d = 0; d < sizeof(defs) / sizeof(defs[0]); d++)
			if (!strcmp(defs[d].stage, st[i].name))
				ssc_html_raw(h, defs[d].html);
		if (st[i].definitions) {
			ssc_html_raw(h, "<p>");
			ssc_html_text(h, st[i].definitions);
			ssc_html_raw(h, "</p>");
		}
		ssc_html_raw(h, "</dd>\n");
	}
	ssc_html_raw(h, "</dl>\n");
	return rc;
}

/* ------------------------------------------------------------ terminal */

static void term_warning(const json_t *w, void *ctx)
{
	fprintf(ctx, "  warning: %s\n", jstr(w, "message"));
}

void ssc_report_terminal(FILE *f, const json_t *summary,
			 const struct ssc_report_stage *st, size_t n)
{
	size_t i, wc = 15, wq = 8, wv = 5, wi = 8, wu = 4;
	json_t *r;

	/* column widths from the contents */
	json_array_foreach(summary, i, r) {
		char v[32], iv[80];
		size_t lc = strlen(jstr(r, "channel")), lq = strlen(jstr(r, "quantity"));

		num(v, sizeof(v), jnum(r, "value"), 5);
		interval(iv, sizeof(iv), jnum(r, "lo"), jnum(r, "hi"));
		wc = lc + strlen(jstr(r, "stage")) + 1 > wc ?
			     lc + strlen(jstr(r, "stage")) + 1 : wc;
		wq = lq > wq ? lq : wq;
		wv = strlen(v) > wv ? strlen(v) : wv;
		wi = strlen(iv) > wi ? strlen(iv) : wi;
		wu = strlen(jstr(r, "unit")) > wu ? strlen(jstr(r, "unit")) : wu;
	}
	fprintf(f, "%-*s  %-*s  %*s  %-*s  %-*s  %s\n", (int)wc, "section/channel",
		(int)wq, "quantity", (int)wv, "value", (int)wi, "interval",
		(int)wu, "unit", "note");
	json_array_foreach(summary, i, r) {
		char v[32], iv[80], sc[128];
		const char *ch = jstr(r, "channel");

		snprintf(sc, sizeof(sc), "%s%s%s", jstr(r, "stage"), *ch ? "/" : "",
			 ch);
		num(v, sizeof(v), jnum(r, "value"), 5);
		interval(iv, sizeof(iv), jnum(r, "lo"), jnum(r, "hi"));
		fprintf(f, "%-*s  %-*s  %*s  %-*s  %-*s  %s%s\n", (int)wc, sc,
			(int)wq, jstr(r, "quantity"), (int)wv, v, (int)wi, iv,
			(int)wu, jstr(r, "unit"),
			!strcmp(jstr(r, "status"), "warning") ? "[!] " : "",
			jstr(r, "note"));
	}
	for (size_t k = 0; k < n; k++)
		walk_warnings(st[k].result, term_warning, f);
}
