/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The `datasheet` command's file and presentation: a datasheet INI
 * ([datasheet] name, source; [gyro] and [accel] lines with units) read
 * into SI lines, shown as IEEE 952 terms and back, and a capture's
 * verdicts against it (analysis/sscope-datasheet.h computes).
 */
#ifndef SSCOPE_WB_DATASHEET_H
#define SSCOPE_WB_DATASHEET_H

#include "workbench.h"

#define SSC_DS_LINES SSCOPE_DATASHEET_LINE_COUNT_

struct ssc_ds_section {
	const char *name;               /* "gyro" or "accel" */
	enum sscope_quantity quantity;
	size_t n;                       /* lines given */
	struct sscope_datasheet_spec spec[SSC_DS_LINES];
	char written[SSC_DS_LINES][64]; /* value as written */
	char unit[SSC_DS_LINES][40];    /* its unit as written */
	double bandwidth_hz;            /* noise_bandwidth, NaN when absent */
};

struct ssc_datasheet {
	const char *path;
	char name[96];
	char source[256];
	struct ssc_ds_section sec[2];
	size_t n_sec;
};

/* Read a datasheet INI; every error is one line naming the file, line and
 * key.  Returns an exit code (1 for a file that cannot be read or used). */
int ssc_datasheet_load(const char *cmd, const char *path,
		       struct ssc_datasheet *ds);

/* A section's IEEE 952 terms N, B, K, SI (NaN where no line gives one;
 * the first line of each in the order of enum sscope_datasheet_line) and
 * the index in sec->spec of the line each comes from (-1 for none). */
void ssc_datasheet_terms(const struct ssc_ds_section *sec, double t[3],
			 int from[3]);

/* The lines as IEEE 952 terms and the terms as every line (text or JSON
 * to the command's output).  Returns an exit code. */
int ssc_datasheet_convert(const struct ssc_common *co,
			  const struct ssc_datasheet *ds);

/* One channel's checks. */
struct ssc_ds_chan {
	const char *name;
	const struct ssc_ds_section *sec;
	struct sscope_datasheet_check c[SSC_DS_LINES];
};

/* A capture's verdicts (the datasheet stage's result). */
struct ssc_ds_result {
	const struct ssc_datasheet *ds;
	const char *capture;
	double level;
	struct ssc_ds_chan *ch;
	size_t n_ch;
	size_t count[3]; /* per enum sscope_datasheet_verdict */
};

/* Each channel of @p cap (gyro channels against [gyro], accelerometer
 * channels against [accel]) checked at confidence @p level.  Prints
 * errors; returns an exit code and *out on success (it points into ds,
 * cap and capture). */
int ssc_datasheet_check_capture(const char *cmd, const struct ssc_datasheet *ds,
				const struct sscope_capture *cap,
				const char *capture, double level,
				struct ssc_ds_result **out);
/* the stage's presenters (opts unused; result a struct ssc_ds_result);
 * the report rows are one per line checked, the verdict in the note (a
 * line not within spec marked as a warning) */
json_t *ssc_datasheet_result_json(const void *opts, const void *result);
void ssc_datasheet_result_text(FILE *f, const void *opts, const void *result);
void ssc_datasheet_result_summary(json_t *rows, const void *opts,
				  const void *result);
void ssc_datasheet_result_free(void *result);

#endif
