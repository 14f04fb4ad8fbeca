/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Capture writers: CSV with "name [unit]" headers, and the sensorscope
 * binary capture:
 *   line 1: "#sensorscope-binary 1 f32|f64 le"
 *   line 2: the CSV header ("time [s],gx [deg/s],...")
 *   then rows of little-endian IEEE 754 values, no padding.
 * Row counts follow from the file size, so a stream can be written without
 * seeking back.  Output is atomic (atomic.c), or goes to a stream the
 * caller owns (sscope_writer_fopen).
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "atomic.h"
#include "sscope-capture.h"
#include "sscope-unit.h"
#include "sscope-writer.h"

struct sscope_writer {
	struct ssc_atomic out; /* when the writer owns the file */
	FILE *f;               /* where rows go (out.f or the caller's) */
	bool own;
	enum sscope_capture_format fmt;
	size_t n_cols;
	struct sscope_unit *units;
	int digits;
};

static bool host_little_endian(void)
{
	const uint16_t one = 1;
	unsigned char b;

	memcpy(&b, &one, 1);
	return b == 1;
}

/* A writer on @p f, or on an atomic file at @p path when f is NULL. */
static int writer_new(struct sscope_writer **wp, const char *path, FILE *f,
		      enum sscope_capture_format fmt,
		      const struct sscope_writer_column *cols, size_t n_cols,
		      int digits, struct sscope_diag *diag)
{
	struct sscope_writer *w;
	int rc;

	*wp = NULL;
	if ((!path && !f) || !cols || n_cols == 0 || digits < 0 ||
	    digits > 17 || fmt > SSCOPE_CAPTURE_BIN64)
		return ssc_diag(diag, -EINVAL, "bad writer parameters");
	w = calloc(1, sizeof(*w));
	if (!w)
		return -ENOMEM;
	w->fmt = fmt;
	w->n_cols = n_cols;
	w->digits = digits ? digits : 17;
	w->units = calloc(n_cols, sizeof(*w->units));
	if (!w->units) {
		free(w);
		return -ENOMEM;
	}
	for (size_t i = 0; i < n_cols; i++) {
		rc = sscope_unit_parse(cols[i].unit ? cols[i].unit : "",
				       &w->units[i], diag);
		if (rc) {
			free(w->units);
			free(w);
			return rc;
		}
	}
	if (!f) {
		rc = ssc_atomic_open(&w->out, path);
		if (rc) {
			free(w->units);
			free(w);
			return ssc_diag(diag, rc, "%s: %s", path,
					sscope_strerror(-rc));
		}
		f = w->out.f;
		w->own = true;
	}
	w->f = f;
	if (fmt != SSCOPE_CAPTURE_CSV)
		fprintf(f, "#sensorscope-binary 1 %s le\n",
			fmt == SSCOPE_CAPTURE_BIN32 ? "f32" : "f64");
	for (size_t i = 0; i < n_cols; i++) {
		const char *u = cols[i].unit ? cols[i].unit : "";

		fprintf(f, "%s%s", i ? "," : "", cols[i].name);
		if (*u)
			fprintf(f, " [%s]", u);
	}
	fputc('\n', f);
	*wp = w;
	return 0;
}

int sscope_writer_open(struct sscope_writer **wp, const char *path,
		       enum sscope_capture_format fmt,
		       const struct sscope_writer_column *cols, size_t n_cols,
		       int digits, struct sscope_diag *diag)
{
	if (!path) {
		*wp = NULL;
		return ssc_diag(diag, -EINVAL, "bad writer parameters");
	}
	return writer_new(wp, path, NULL, fmt, cols, n_cols, digits, diag);
}

int sscope_writer_fopen(struct sscope_writer **wp, FILE *f,
			enum sscope_capture_format fmt,
			const struct sscope_writer_column *cols, size_t n_cols,
			int digits, struct sscope_diag *diag)
{
	if (!f) {
		*wp = NULL;
		return ssc_diag(diag, -EINVAL, "bad writer parameters");
	}
	return writer_new(wp, NULL, f, fmt, cols, n_cols, digits, diag);
}

/* 0, or the stream's error (-errno when the atomic file knows it). */
static int writer_error(const struct sscope_writer *w)
{
	if (w->own)
		return ssc_atomic_error(&w->out);
	return ferror(w->f) ? -EIO : 0;
}

static void put_le(FILE *f, const void *v, size_t n)
{
	unsigned char b[8];

	memcpy(b, v, n);
	if (!host_little_endian())
		for (size_t i = 0; i < n / 2; i++) {
			unsigned char t = b[i];

			b[i] = b[n - 1 - i];
			b[n - 1 - i] = t;
		}
	fwrite(b, 1, n, f);
}

int sscope_writer_append(struct sscope_writer *w, const double *values,
			 size_t rows)
{
	FILE *f = w->f;

	for (size_t r = 0; r < rows; r++) {
		const double *row = values + r * w->n_cols;

		for (size_t i = 0; i < w->n_cols; i++) {
			double v = sscope_unit_from_si(&w->units[i], row[i]);

			if (w->fmt == SSCOPE_CAPTURE_CSV) {
				if (i)
					fputc(',', f);
				if (isnan(v))
					fputs("nan", f);
				else
					fprintf(f, "%.*g", w->digits, v);
			} else if (w->fmt == SSCOPE_CAPTURE_BIN32) {
				float x = (float)v;

				put_le(f, &x, 4);
			} else {
				put_le(f, &v, 8);
			}
		}
		if (w->fmt == SSCOPE_CAPTURE_CSV)
			fputc('\n', f);
	}
	return writer_error(w);
}

int sscope_writer_comment(struct sscope_writer *w, const char *text)
{
	if (w->fmt != SSCOPE_CAPTURE_CSV)
		return 0;
	fprintf(w->f, "# %s\n", text);
	return writer_error(w);
}

int sscope_writer_commit(struct sscope_writer *w)
{
	int rc;

	if (w->own)
		rc = ssc_atomic_commit(&w->out);
	else
		rc = fflush(w->f) != 0 || ferror(w->f) ? -EIO : 0;

	free(w->units);
	free(w);
	return rc;
}

void sscope_writer_abort(struct sscope_writer *w)
{
	if (!w)
		return;
	if (w->own)
		ssc_atomic_abort(&w->out);
	free(w->units);
	free(w);
}

static int capture_write(const struct sscope_capture *cap, const char *path,
			 FILE *f, enum sscope_capture_format fmt, int digits,
			 struct sscope_diag *diag)
{
	struct sscope_writer_column *cols;
	struct sscope_writer *w = NULL;
	size_t nc = cap->n_channels + !!cap->time_s + !!cap->temp_degc, c = 0;
	double *row;
	int rc;

	cols = calloc(nc ? nc : 1, sizeof(*cols));
	row = calloc(nc ? nc : 1, sizeof(*row));
	if (!cols || !row) {
		free(cols);
		free(row);
		return -ENOMEM;
	}
	if (cap->time_s)
		cols[c++] = (struct sscope_writer_column){ cap->time_col.name,
							   cap->time_col.unit_label };
	for (size_t k = 0; k < cap->n_channels; k++)
		cols[c++] = (struct sscope_writer_column){
			cap->channels[k].col.name, cap->channels[k].col.unit_label };
	if (cap->temp_degc)
		cols[c++] = (struct sscope_writer_column){ cap->temp_col.name,
							   cap->temp_col.unit_label };
	rc = writer_new(&w, path, f, fmt, cols, nc, digits, diag);
	for (size_t i = 0; !rc && i < cap->n; i++) {
		c = 0;
		if (cap->time_s)
			row[c++] = cap->time_s[i];
		for (size_t k = 0; k < cap->n_channels; k++)
			row[c++] = cap->channels[k].data[i];
		if (cap->temp_degc)
			row[c++] = cap->temp_degc[i];
		rc = sscope_writer_append(w, row, 1);
	}
	if (!rc)
		rc = sscope_writer_commit(w);
	else
		sscope_writer_abort(w);
	if (rc)
		ssc_diag(diag, rc, "%s: %s", path ? path : "(stream)",
			 sscope_strerror(rc));
	free(cols);
	free(row);
	return rc;
}

int sscope_capture_write(const struct sscope_capture *cap, const char *path,
			 enum sscope_capture_format fmt, int digits,
			 struct sscope_diag *diag)
{
	if (!path)
		return ssc_diag(diag, -EINVAL, "bad writer parameters");
	return capture_write(cap, path, NULL, fmt, digits, diag);
}

int sscope_capture_fwrite(const struct sscope_capture *cap, FILE *f,
			  enum sscope_capture_format fmt, int digits,
			  struct sscope_diag *diag)
{
	if (!f)
		return ssc_diag(diag, -EINVAL, "bad writer parameters");
	return capture_write(cap, NULL, f, fmt, digits, diag);
}
