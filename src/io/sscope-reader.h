/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-reader.h
 * @brief Reading a capture in chunks (streaming).
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_READER_H
#define SSCOPE_READER_H

#include "sscope-capture.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Options for opening a capture.  Zero-initialise, then set what you need. */
struct sscope_reader_opts {
	/** Raw binary layout "TYPE:CHANNELS[:le|be]" (TYPE one of i16, u16,
	 *  i24, i32, u32, f32, f64), or NULL for delimited text / the
	 *  sensorscope binary capture (detected by its first line). */
	const char *raw;
	double raw_scale;  /**< raw: physical = (raw + offset) * scale; 0 -> 1 */
	double raw_offset; /**< raw: added before scaling */
	/** Unit of data columns whose header names none (NULL: leave them
	 *  without a unit). */
	const char *default_unit;
	/** Comma-separated channel names or 1-based column indices to read;
	 *  NULL or "" selects every data column. */
	const char *columns;
	const char *time_column; /**< name of the time column, NULL: detect */
	const char *temp_column; /**< temperature column, NULL: detect */
	double rate_hz; /**< nominal rate; 0 derives it from the time column */
	bool nan_as_gap; /**< accept NaN/empty cells as gaps (else -EBADMSG) */
	bool no_time;    /**< ignore the time column even if one is present */
	/** Threads for parsing a whole text file (sscope_capture_load); 0:
	 *  OpenMP's default team (one per CPU unless OMP_NUM_THREADS says
	 *  otherwise), at most 8. */
	unsigned threads;
	/** sscope_capture_load(): a raw file of one float64 channel in the
	 *  host's byte order with no scaling (the common dump of a logger)
	 *  is used in place, memory-mapped read-only instead of copied (see
	 *  sscope_capture.mapping); the caller promises not to write the
	 *  channel data. */
	bool in_place;
	/** Progress callback (may be NULL): @p done of @p total bytes read;
	 *  total is 0 when unknown (a pipe). */
	void (*progress)(void *ctx, uint64_t done, uint64_t total);
	void *progress_ctx;
	/** ROS bag, rosbag2 and MCAP inputs: the topic to read, or
	 *  "DATA,TEMPERATURE" (a sensor_msgs/Temperature topic interpolated
	 *  at the data topic's stamps); NULL: the only IMU topic. */
	const char *topic;
	/** With in_place: a file used in place is not checked for NaN
	 *  (unless nan_as_gap) and infinite samples when it is read, saving
	 *  a pass over it; the caller's analysis rejects them (such as
	 *  sscope_allan_opts.reject_nan) and sscope_capture_check_values()
	 *  then reports the reader's error.  Sets
	 *  sscope_capture.values_unchecked. */
	bool in_place_unchecked;
};

/** An open capture source read in chunks (streaming). */
struct sscope_reader;

/**
 * Open a capture for chunked reading.  "-" reads standard input.  Delimited
 * text files are memory-mapped; pipes are read in large blocks.
 * @param reader receives the reader; free it with sscope_reader_close().
 * @param path   file name or "-".
 * @param opts   options (may be NULL for the defaults).
 * @param diag   optional detail: file, line and column of a problem.
 * @return 0; -ENOENT/-EACCES/... from the OS; -EBADMSG for a malformed
 *         header or an empty file; -EINVAL for a bad option (unknown column,
 *         bad --raw layout, unknown unit); -ENOMEM.
 */
int sscope_reader_open(struct sscope_reader **reader, const char *path,
		       const struct sscope_reader_opts *opts,
		       struct sscope_diag *diag);

/**
 * Check a raw binary layout "TYPE:CHANNELS[:le|be]" (sscope_reader_opts.raw)
 * without opening anything, so that a caller can refuse a bad one as a
 * usage error before reading.
 * @param layout      the layout text.
 * @param channels    receives the channel count (1..4096; may be NULL).
 * @param value_bytes receives the bytes per value (may be NULL).
 * @param diag        optional: what is wrong, in one line.
 * @return 0; -EINVAL for an empty or malformed layout (unknown type, a
 *         channel count that is not a whole number in 1..4096, a byte
 *         order other than le or be).
 */
int sscope_reader_raw_layout_check(const char *layout, size_t *channels,
				   size_t *value_bytes, struct sscope_diag *diag);

/**
 * @return true when the reader has read a text capture to its end and
 *         the last data line has no newline: the capture may have been
 *         cut short (that line was read as a row; a cell cut off entirely
 *         is an error, a number cut short is not detectable).
 */
bool sscope_reader_unterminated(const struct sscope_reader *reader);

/** @return the number of selected data channels. */
size_t sscope_reader_n_channels(const struct sscope_reader *reader);

/** @return the description of selected channel @p k (owned by @p reader). */
const struct sscope_capture_column *
sscope_reader_channel(const struct sscope_reader *reader, size_t k);

/** @return the time column, or NULL when there is none. */
const struct sscope_capture_column *
sscope_reader_time_column(const struct sscope_reader *reader);

/** @return the temperature column, or NULL when there is none. */
const struct sscope_capture_column *
sscope_reader_temp_column(const struct sscope_reader *reader);

/** @return the number of columns of the source (all roles). */
size_t sscope_reader_n_columns(const struct sscope_reader *reader);

/** @return column @p k (0-based, all roles) of the source. */
const struct sscope_capture_column *
sscope_reader_column(const struct sscope_reader *reader, size_t k);

/**
 * @return the rate declared by a header comment ("# rate: 100 Hz",
 *         "# sample_rate = 1 kHz", "# fs: 200"), or 0 when none.
 */
double sscope_reader_header_rate(const struct sscope_reader *reader);

/**
 * @return why a header comment that names a rate ("# rate: 0 Hz",
 *         "# rate: 10 furlongs") gave none: "line 2: '# rate: 0 Hz' is
 *         not a sample rate (...)"; NULL when the source declares a rate
 *         or has no such comment.  Valid until the reader is closed.
 */
const char *sscope_reader_header_rate_note(const struct sscope_reader *reader);

/** @return the source size in bytes, 0 when unknown (a pipe). */
uint64_t sscope_reader_size(const struct sscope_reader *reader);

/**
 * @return the container details of the source (format, topics), owned by
 *         @p reader, or NULL for delimited text, raw and sensorscope binary
 *         files.  receive_s is NULL here (see struct sscope_capture).
 */
const struct sscope_capture_source *
sscope_reader_source(const struct sscope_reader *reader);

/** Caller-owned destination of sscope_reader_read(). */
struct sscope_reader_chunk {
	size_t capacity;   /**< rows each array can hold */
	size_t rows;       /**< rows filled by the last read */
	double **data;     /**< [n_channels] arrays, SI (entries may be NULL
				to skip a channel) */
	double *time_s;    /**< time since the first sample, s (may be NULL) */
	double *temp_degc; /**< temperature, degC (may be NULL) */
};

/**
 * Read up to chunk->capacity rows.  chunk->rows == 0 means end of data.
 * Time stamps are relative to the first row of the source, computed from
 * the exact decimal text so that large epoch stamps (EuRoC's nanoseconds)
 * keep their resolution.
 * @return 0, -EBADMSG (non-numeric cell, ragged row, NaN without
 *         nan_as_gap; diag names file, line and column), -EIO.
 */
int sscope_reader_read(struct sscope_reader *reader,
		       struct sscope_reader_chunk *chunk, struct sscope_diag *diag);

/** Close a reader (NULL is ignored). */
void sscope_reader_close(struct sscope_reader *reader);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_READER_H */
