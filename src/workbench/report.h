/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The report as a document (report.c): from the summary rows and each
 * stage's JSON result (the contract's objects, so the report reads what
 * users' scripts read), an HTML body with the results as tables (value,
 * interval, unit, status), a banner for every result the analysis itself
 * doubts (the "warnings" the stages attach), figures inline as SVG,
 * formulas in MathML and each section linked to its definitions; and the
 * same summary as a table for the terminal.
 */
#ifndef SSCOPE_REPORT_H
#define SSCOPE_REPORT_H

#include <stdio.h>

#include <jansson.h>

#include "html.h"

/* One stage of a report. */
struct ssc_report_stage {
	const char *name;        /* scene section: "allan" */
	const char *title;       /* "Allan deviation and noise terms" */
	const char *why;         /* why it ran (or NULL) */
	const char *definitions; /* plain-text definitions (or NULL) */
	const json_t *result;    /* its JSON result (borrowed), or NULL */
	const char *text;        /* its text output (or NULL) */
	const char *const *figs; /* SVG files of its figures, NULL-terminated
				    (or NULL) */
	const char *const *links; /* for each figure, the file to link to from
				     its caption (NULL entries: none) */
};

/*
 * Write the report's body into h: summary table, the checks (warnings),
 * one section per stage, the definitions.  summary: the rows
 * {stage, channel, quantity, value, lo, hi, unit, note[, status]}.
 * Returns 0, or -errno when a figure cannot be read (the section then
 * says so; the rest is written).
 */
int ssc_report_body(struct ssc_html *h, const json_t *summary,
		    const struct ssc_report_stage *st, size_t n);

/* The summary rows as a table for people (run and report print it),
 * followed by one line per warning. */
void ssc_report_terminal(FILE *f, const json_t *summary,
			 const struct ssc_report_stage *st, size_t n);

/* Number of warnings in a JSON result (any "warnings" array inside). */
size_t ssc_report_count_warnings(const json_t *result);

#endif
