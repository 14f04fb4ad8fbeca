/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-writer.h
 * @brief Writing a capture file atomically, row by row.
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_WRITER_H
#define SSCOPE_WRITER_H

#include <stdio.h>
#include "sscope-capture.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Streaming capture writer (atomic: nothing appears until commit). */
struct sscope_writer;

/** Column of a writer: values are given in SI and written in @p unit. */
struct sscope_writer_column {
	const char *name; /**< header name */
	const char *unit; /**< unit written in the header ("" for none) */
};

/**
 * Create a capture file.  Data go to a temporary file beside @p path which
 * sscope_writer_commit() renames; sscope_writer_abort() removes it.  A
 * symbolic link's target is replaced (the link stays); "-" (standard
 * output), /dev/stdout, FIFOs and devices are written directly, never
 * replaced.
 * @param digits  significant digits for CSV (0 -> 17, exact round trip).
 * @return 0, -EINVAL (unknown unit, no columns), -errno from the OS.
 */
int sscope_writer_open(struct sscope_writer **w, const char *path,
		       enum sscope_capture_format fmt,
		       const struct sscope_writer_column *cols, size_t n_cols,
		       int digits, struct sscope_diag *diag);

/**
 * As sscope_writer_open(), on a stream the caller owns (a pipe, or a file
 * the caller replaces atomically itself): sscope_writer_commit() flushes
 * and checks @p f but neither closes nor renames it.
 * @return 0, -EINVAL (unknown unit, no columns, NULL stream).
 */
int sscope_writer_fopen(struct sscope_writer **w, FILE *f,
			enum sscope_capture_format fmt,
			const struct sscope_writer_column *cols, size_t n_cols,
			int digits, struct sscope_diag *diag);

/**
 * Append @p rows rows; @p values is row-major, n_cols values per row, in SI.
 * @return 0, or -errno of the failed write (-EIO when not known).
 */
int sscope_writer_append(struct sscope_writer *w, const double *values,
			 size_t rows);

/** Append a comment line ("# ..."); CSV only, ignored for binary. */
int sscope_writer_comment(struct sscope_writer *w, const char *text);

/** Flush, sync and rename into place; frees @p w.
 * @return 0, or -errno of the failed write, sync or rename (-EIO when not
 * known). */
int sscope_writer_commit(struct sscope_writer *w);

/** Discard the temporary file; frees @p w (NULL is ignored). */
void sscope_writer_abort(struct sscope_writer *w);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_WRITER_H */
