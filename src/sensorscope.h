/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sensorscope.h
 * @brief libsensorscope: characterisation of inertial sensors and converters.
 *
 * Conventions, stated once for the whole library:
 * - Every fallible function returns 0 on success or a negative errno:
 *   -EINVAL  a bad parameter (the caller's mistake, e.g. a negative rate);
 *   -EDOM    the data do not fit the request (too short, constant, NaN);
 *   -ERANGE  clipping or overflow (a count that does not fit, a value out of
 *            a converter's range);
 *   -ENOMEM  out of memory;
 *   -ENOTSUP a feature that was compiled out;
 *   -EIO, -ETIMEDOUT, -ENODEV  acquisition failures;
 *   -EBADMSG a malformed file or frame.
 *   sscope_strerror() gives a short text for each.
 * - Values are SI inside the library: rad, rad/s, m/s^2, m/s, m, s, Hz, V
 *   and degrees Celsius for temperature.  Conventional units (deg/h, g, ...)
 *   appear only through the unit functions below.  Physical parameters carry
 *   their unit as a suffix (_s, _hz, _rad_s, _m_s2, _degc, _v).
 * - 1-D data are passed as (const double *x, size_t stride, size_t n): the
 *   k-th sample is x[k * stride], so one column of an interleaved buffer is
 *   analysed without a copy.
 * - One-sided PSDs are in unit^2/Hz normalised by fs * sum(w^2) (scipy's
 *   "density"); FFTs are unnormalised.  Allan deviations follow IEEE 952/1554
 *   with tau = m / fs.  An ideal quantizer is mid-tread with LSB = span / 2^N.
 * - The caller owns every array it passes.  Objects returned by *_new or
 *   *_load are freed by the matching *_free.
 * - Nothing in the library prints, exits or keeps mutable static state.
 */
#ifndef SENSORSCOPE_H
#define SENSORSCOPE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ */
/* Version, errors                                                     */
/* ------------------------------------------------------------------ */

/** @return the library version, e.g. "0.1.0"; a static string. */
const char *sscope_version(void);

/**
 * Short description of an error code.
 * @param err a negative errno returned by this library (a positive value is
 *            accepted too).
 * @return a static string; never NULL.
 */
const char *sscope_strerror(int err);

/**
 * Human-readable detail of a failure: which file, line, column, key or unit
 * was at fault.  Functions that take a `struct sscope_diag *` fill it when
 * they fail (it may be NULL when the caller does not want the detail).
 */
struct sscope_diag {
	char msg[320]; /**< NUL-terminated; empty when nothing was said */
};

/* ------------------------------------------------------------------ */
/* Units                                                               */
/* ------------------------------------------------------------------ */

/** Base dimensions.  Angle is kept as a dimension so that rad/s is not Hz. */
enum sscope_dim {
	SSCOPE_DIM_LENGTH = 0, /**< metre */
	SSCOPE_DIM_TIME,       /**< second */
	SSCOPE_DIM_ANGLE,      /**< radian */
	SSCOPE_DIM_TEMP,       /**< degree Celsius (kelvin for differences) */
	SSCOPE_DIM_VOLTAGE,    /**< volt */
	SSCOPE_DIM_COUNTS,     /**< converter counts (LSB) */
	SSCOPE_DIM_COUNT       /**< number of base dimensions */
};

/**
 * A parsed unit: SI value = scale * value + offset.  The offset is non-zero
 * only for absolute temperatures given in kelvin or Fahrenheit (the library's
 * temperature unit is the degree Celsius).  Exponents are stored doubled so
 * that sqrt(h) is exact: dim2[SSCOPE_DIM_TIME] == 1 means s^(1/2).
 */
struct sscope_unit {
	double scale;
	double offset;
	int8_t dim2[SSCOPE_DIM_COUNT];
};

/** What a unit measures, so reports can choose conventional units. */
enum sscope_quantity {
	SSCOPE_QTY_UNKNOWN = 0,   /**< no unit, or a combination not listed */
	SSCOPE_QTY_DIMENSIONLESS, /**< ratio, ppm, % */
	SSCOPE_QTY_COUNTS,        /**< raw converter codes */
	SSCOPE_QTY_ANGULAR_RATE,  /**< rad/s */
	SSCOPE_QTY_ACCELERATION,  /**< m/s^2 */
	SSCOPE_QTY_ANGLE,         /**< rad */
	SSCOPE_QTY_VELOCITY,      /**< m/s */
	SSCOPE_QTY_LENGTH,        /**< m */
	SSCOPE_QTY_TIME,          /**< s */
	SSCOPE_QTY_FREQUENCY,     /**< Hz */
	SSCOPE_QTY_TEMPERATURE,   /**< degC */
	SSCOPE_QTY_VOLTAGE,       /**< V */
	SSCOPE_QTY_ANGULAR_ACCEL, /**< rad/s^2 */
	SSCOPE_QTY_JERK,          /**< m/s^3 */
	SSCOPE_QTY_COUNT_         /**< number of quantities (not a quantity) */
};

/**
 * Parse a unit expression such as "deg/s", "rad s^-1", "deg/sqrt(h)",
 * "deg/h/sqrt(h)", "ug/sqrt(Hz)", "mV/(deg/s)", "m/s^2" or "°C".
 * Products are written with '*', '·' or a space, quotients with '/', powers
 * with '^' (integer or n/2), and sqrt(...) or '√'.  An empty string or "1"
 * is dimensionless.
 * @param text  the expression (NUL-terminated).
 * @param unit  receives the result.
 * @param diag  optional; names the part not understood.
 * @return 0, or -EINVAL when some part is not a known unit or the syntax is
 *         wrong.
 */
int sscope_unit_parse(const char *text, struct sscope_unit *unit,
		      struct sscope_diag *diag);

/** @return true when @p a and @p b measure the same dimension. */
bool sscope_unit_compatible(const struct sscope_unit *a,
			    const struct sscope_unit *b);

/** @return @p value (in @p unit) expressed in SI. */
double sscope_unit_to_si(const struct sscope_unit *unit, double value);

/** @return the SI value @p si expressed in @p unit. */
double sscope_unit_from_si(const struct sscope_unit *unit, double si);

/**
 * Convert between two units.
 * @return 0, or -EDOM when the dimensions differ (out untouched).
 */
int sscope_unit_convert(double value, const struct sscope_unit *from,
			const struct sscope_unit *to, double *out);

/**
 * Convert a unit expression to another, both given as text: the usual way
 * to print an SI result in a conventional unit.
 * @return 0, -EINVAL for an unknown unit, -EDOM for incompatible units.
 */
int sscope_convert(double value, const char *from, const char *to,
		   double *out);

/** @return the quantity measured by @p unit (SSCOPE_QTY_UNKNOWN if none). */
enum sscope_quantity sscope_unit_quantity(const struct sscope_unit *unit);

/** @return a short name of @p q ("angular rate", ...); static string. */
const char *sscope_quantity_name(enum sscope_quantity q);

/**
 * @return the SI unit of @p q as text ("rad/s", "m/s^2", "degC", ...), or ""
 *         for unknown quantities; static string.
 */
const char *sscope_quantity_si_unit(enum sscope_quantity q);

/** Terms of the IEEE 952 error model and related figures, for units. */
enum sscope_term {
	SSCOPE_TERM_Q = 0, /**< quantization (angle / velocity) */
	SSCOPE_TERM_N,     /**< angle / velocity random walk */
	SSCOPE_TERM_B,     /**< bias instability */
	SSCOPE_TERM_K,     /**< rate random walk */
	SSCOPE_TERM_R,     /**< rate ramp */
	SSCOPE_TERM_RATE,  /**< the measured quantity itself (bias, range) */
	SSCOPE_TERM_COUNT_
};

/**
 * Conventional unit of a term for gyros (deg/sqrt(h), deg/h, ...) and
 * accelerometers (m/s/sqrt(h), ug, ...).
 * @return a static string, or NULL for other quantities (use the data's
 *         own unit then).
 */
const char *sscope_term_unit(enum sscope_quantity q, enum sscope_term t);

/**
 * SI unit of a term as the JSON contract writes it: Q rad, N
 * rad/s/sqrt(Hz), B rad/s, K rad/s^2/sqrt(Hz), R rad/s^2 for angular rate;
 * m/s, m/s^2/sqrt(Hz), m/s^2, m/s^3/sqrt(Hz), m/s^3 for acceleration.
 * @return a static string, or NULL for other quantities.
 */
const char *sscope_term_si_unit(enum sscope_quantity q, enum sscope_term t);

/**
 * Write @p unit's SI form, e.g. "rad/s/sqrt(Hz)" or "m s^-2", into @p buf.
 * Angular-rate noise densities are written the way the field writes them
 * (rad/s/sqrt(Hz), m/s^2/sqrt(Hz)), other units as products of powers.
 * @return 0, or -ERANGE when @p len is too small (buf holds a truncation).
 */
int sscope_unit_si_string(const struct sscope_unit *unit, char *buf,
			  size_t len);

/**
 * Parse a quantity with its unit, e.g. "0.15 deg/sqrt(h)" or "-100 deg/s".
 * @param text      the text.
 * @param value_si  receives the value in SI.
 * @param unit      receives the unit as written (may be NULL).  A number
 *                  without a unit yields a dimensionless unit.
 * @param diag      optional detail.
 * @return 0, or -EINVAL (not a number, or unknown unit).
 */
int sscope_quantity_parse(const char *text, double *value_si,
			  struct sscope_unit *unit, struct sscope_diag *diag);

/* ------------------------------------------------------------------ */
/* Number parsing                                                      */
/* ------------------------------------------------------------------ */

/**
 * Parse a decimal floating-point number from [p, end), correctly rounded
 * (bit-identical to strtod in the C locale).  Accepts an optional sign,
 * digits with an optional '.', an optional exponent, and "nan"/"inf"
 * (any case).  Leading blanks are not skipped.
 * @param p, end  the text (need not be NUL-terminated).
 * @param out     receives the value.
 * @return the number of bytes consumed, or 0 when no number starts at @p p.
 */
size_t sscope_parse_double(const char *p, const char *end, double *out);

/* ------------------------------------------------------------------ */
/* Captures                                                            */
/* ------------------------------------------------------------------ */

/** Role of a column of a capture file. */
enum sscope_role {
	SSCOPE_ROLE_DATA = 0, /**< a measured channel */
	SSCOPE_ROLE_TIME,     /**< time stamps */
	SSCOPE_ROLE_TEMP      /**< temperature */
};

/** Description of one column of a capture source. */
struct sscope_column {
	const char *name;       /**< header name without its unit */
	const char *unit_label; /**< unit as written (or given); "" if none */
	struct sscope_unit unit;        /**< file unit -> SI */
	enum sscope_quantity quantity;  /**< what it measures */
	enum sscope_role role;          /**< data, time or temperature */
	size_t index;                   /**< 0-based position in the source */
};

/** How the nominal sample rate of a capture was established. */
enum sscope_rate_source {
	SSCOPE_RATE_NONE = 0,   /**< unknown: no time column, no rate given */
	SSCOPE_RATE_GIVEN,      /**< from the caller (--rate) */
	SSCOPE_RATE_TIME_COLUMN, /**< from the median time-stamp interval */
	SSCOPE_RATE_HEADER      /**< from a "# rate: 100 Hz" header comment */
};

/** Options for opening a capture.  Zero-initialise, then set what you need. */
struct sscope_read_opts {
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
	 *  one per online CPU, at most 8. */
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
};

/** A topic (message stream) of a ROS bag, rosbag2 or MCAP file. */
struct sscope_topic {
	const char *name;  /**< e.g. "/imu/data" */
	const char *type;  /**< e.g. "sensor_msgs/Imu", "sensor_msgs/msg/Imu" */
	uint64_t messages; /**< messages of the topic in the file */
	bool readable; /**< sensor_msgs/Imu, sensor_msgs/Temperature or
			    geometry_msgs/Vector3Stamped */
	bool selected; /**< read into the capture (data or temperature) */
};

/**
 * What a container or compressed input held beyond its channels: the
 * format, the topics of a bag, and the receive (log) times of the rows.
 */
struct sscope_source {
	const char *format;  /**< e.g. "ROS 1 bag v2.0 (lz4 chunks)" */
	size_t n_topics;
	const struct sscope_topic *topics;
	/** Receive time of each row (the bag's or MCAP's log time), s, on
	 *  the time axis of the capture (0 = the first header stamp); NULL
	 *  when the format has none.  In a capture: cap->n values. */
	const double *receive_s;
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
		       const struct sscope_read_opts *opts,
		       struct sscope_diag *diag);

/**
 * Check a raw binary layout "TYPE:CHANNELS[:le|be]" (sscope_read_opts.raw)
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
int sscope_raw_layout_check(const char *layout, size_t *channels,
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
const struct sscope_column *
sscope_reader_channel(const struct sscope_reader *reader, size_t k);

/** @return the time column, or NULL when there is none. */
const struct sscope_column *
sscope_reader_time_column(const struct sscope_reader *reader);

/** @return the temperature column, or NULL when there is none. */
const struct sscope_column *
sscope_reader_temp_column(const struct sscope_reader *reader);

/** @return the number of columns of the source (all roles). */
size_t sscope_reader_n_columns(const struct sscope_reader *reader);

/** @return column @p k (0-based, all roles) of the source. */
const struct sscope_column *
sscope_reader_column(const struct sscope_reader *reader, size_t k);

/**
 * @return the rate declared by a header comment ("# rate: 100 Hz",
 *         "# sample_rate = 1 kHz", "# fs: 200"), or 0 when none.
 */
double sscope_reader_header_rate(const struct sscope_reader *reader);

/** @return the source size in bytes, 0 when unknown (a pipe). */
uint64_t sscope_reader_size(const struct sscope_reader *reader);

/**
 * @return the container details of the source (format, topics), owned by
 *         @p reader, or NULL for delimited text, raw and sensorscope binary
 *         files.  receive_s is NULL here (see struct sscope_capture).
 */
const struct sscope_source *
sscope_reader_source(const struct sscope_reader *reader);

/** Caller-owned destination of sscope_reader_read(). */
struct sscope_chunk {
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
		       struct sscope_chunk *chunk, struct sscope_diag *diag);

/** Close a reader (NULL is ignored). */
void sscope_reader_close(struct sscope_reader *reader);

/**
 * Mean of the finite values of x[k*stride], k < n, with its Student-t
 * interval mean -+ t(level, k - 1) s / sqrt(k) (s the sample sd of the k
 * finite values) -- the interval of a mean over a few runs.
 * @param level  two-sided level in (0, 1), e.g. 0.6827.
 * @param lo, hi receive the interval (NaN with fewer than two values).
 * @param used   receives k (may be NULL).
 * @return 0; -EDOM when no value is finite (mean NaN); -EINVAL.
 */
int sscope_stats_mean_interval(const double *x, size_t stride, size_t n,
			       double level, double *mean, double *lo,
			       double *hi, size_t *used);

/**
 * The values an interval table gives each sample (a rate-table schedule,
 * a tilt table): @p rows holds n_rows rows of START END V1 .. Vk (k =
 * @p n_val; times in s from the record's first sample); sample i, at
 * t = t_s[i] - t_s[0] (or i / rate_hz when t_s is NULL), takes the values
 * of the first row with START <= t < END, NaN outside every row.
 * @param out  n_val arrays of n values.
 * @return 0; -EINVAL (NULL, no time base, n_val 0).
 */
int sscope_intervals_sample(const double *t_s, double rate_hz, size_t n,
			    const double *rows, size_t n_rows, size_t n_val,
			    double *const *out);

/**
 * Order of a time column, fed in pieces (a streaming reader feeds every
 * chunk).  Zero-initialise.  Counts intervals that are not positive and
 * recognises a swapped pair of rows (a backward step whose exchange with
 * the row before restores the order).
 */
struct sscope_time_order {
	size_t n;            /**< stamps fed */
	size_t n_repeats;    /**< intervals of exactly 0 (a repeated stamp) */
	size_t n_decreasing; /**< negative intervals */
	size_t n_swaps;      /**< of those, swapped pairs of adjacent rows
				  (complete after sscope_time_order_check) */
	size_t first_row;    /**< 0-based row of the first interval that is
				  not positive (0: none) */
	double first_t_s;    /**< that row's stamp */
	double first_prev_s; /**< and the stamp before it */
	double t0_s;         /**< the first stamp */
	/* private: the last three stamps and a backward step waiting for the
	 * next stamp to tell whether it was a swap */
	double last_s[3];
	int pending;
};

/** Feed the next @p n stamps (seconds); NaN stamps are not expected. */
void sscope_time_order_feed(struct sscope_time_order *o, const double *t_s,
			    size_t n);

/**
 * Is the time column usable as sampling times?
 * @param diag  receives the problem as a phrase to follow the column's
 *              name: "has one row", "is constant (every row has the same
 *              stamp)", "decreases in every row (...)", "has rows 3 and 4
 *              in reverse order (...)", "repeats the stamp of row 3 at
 *              row 4 (...)", "goes backwards 2 times (first at row 9:
 *              ...)", with a count of further cases (rows 1-based).
 * @return 0 when the stamps strictly increase (two or more of them);
 *         -EDOM otherwise; -EINVAL for a NULL @p o.
 */
int sscope_time_order_check(const struct sscope_time_order *o,
			    struct sscope_diag *diag);

/** Sampling of a time column. */
struct sscope_timing {
	double dt_median_s; /**< median interval */
	double dt_min_s;
	double dt_max_s;
	double jitter_rms_s;  /**< rms deviation of the regular intervals from
				   their mean (gaps excluded) */
	double rate_hz;       /**< 1 / mean regular interval */
	size_t n_gaps;        /**< intervals longer than gap_factor * median */
	size_t n_missing;     /**< samples missing in those gaps (estimated) */
	size_t n_backwards;   /**< non-increasing intervals */
	/** order of the stamps (filled also when the analysis returns
	 *  -EDOM); see sscope_time_order_check() */
	struct sscope_time_order order;
};

/** A gap in time stamps. */
struct sscope_gap {
	size_t index;     /**< first sample after the gap */
	double t_s;       /**< its time */
	double length_s;  /**< the interval */
	size_t missing;   /**< round(length / median) - 1 */
};

/** One data channel of a loaded capture. */
struct sscope_channel {
	struct sscope_column col; /**< name, unit, quantity (owned) */
	double *data;             /**< n samples in SI (owned) */
	size_t n_nan;             /**< NaN samples (gaps) among them */
};

/** A capture in memory. */
struct sscope_capture {
	char *source;           /**< path given to the loader, "-" for stdin */
	size_t n;               /**< samples per channel */
	size_t n_channels;
	struct sscope_channel *channels;
	double *time_s;         /**< NULL without a time column */
	double *temp_degc;      /**< NULL without a temperature column */
	struct sscope_column time_col; /**< valid when time_s != NULL */
	struct sscope_column temp_col; /**< valid when temp_degc != NULL */
	double rate_hz;         /**< nominal rate; 0 when unknown */
	enum sscope_rate_source rate_source;
	size_t n_nan;           /**< NaN cells read as gaps */
	/** Container details (format, topics, receive times), or NULL for
	 *  delimited text, raw and sensorscope binary files (owned). */
	struct sscope_source *source_info;
	/** A read-only file mapping that holds the channel data (read with
	 *  sscope_read_opts.in_place), released by sscope_capture_free();
	 *  NULL otherwise.  Such data must not be written, freed or
	 *  reallocated by the caller. */
	void *mapping;
	size_t mapping_len;     /**< bytes of the mapping */
	/** the last data line had no newline (sscope_reader_unterminated) */
	bool unterminated;
	/** Sampling of the time column (sscope_timing_analyze() with gap
	 *  factor 1.5), valid when has_timing: loaded captures with a time
	 *  column of two or more increasing stamps. */
	struct sscope_timing timing;
	bool has_timing;
	/** The first SSCOPE_CAPTURE_GAPS gaps of the time column (n_gaps of
	 *  them; timing.n_gaps counts all). */
	struct sscope_gap *gaps;
	size_t n_gaps;
	/** A view made by sscope_capture_view(): samples, names, time and
	 *  temperature belong to another capture. */
	bool is_view;
};

/** Gaps of the time column a loaded capture lists (struct sscope_capture). */
#define SSCOPE_CAPTURE_GAPS 100

/**
 * Read a whole capture (the selected columns only).
 * @param cap   receives the capture; free it with sscope_capture_free().
 * @return as sscope_reader_open() and sscope_reader_read(); -EDOM when the
 *         file holds no data rows or no data column.
 */
int sscope_capture_load(struct sscope_capture **cap, const char *path,
			const struct sscope_read_opts *opts,
			struct sscope_diag *diag);

/**
 * Make an empty capture of @p n_channels channels with @p n samples each
 * (zero-filled), for generators and writers.
 * @param with_time  allocate time_s.
 * @param with_temp  allocate temp_degc.
 * @return the capture, or NULL when out of memory or on overflow.
 */
struct sscope_capture *sscope_capture_new(size_t n_channels, size_t n,
					  bool with_time, bool with_temp);

/**
 * Set the name and unit of channel @p k of a capture made by
 * sscope_capture_new() (copies the strings).
 * @return 0, -EINVAL (unknown unit, k out of range), -ENOMEM.
 */
int sscope_capture_set_channel(struct sscope_capture *cap, size_t k,
			       const char *name, const char *unit);

/** Free a capture (NULL is ignored). */
void sscope_capture_free(struct sscope_capture *cap);

/**
 * Say that samples x[k * stride], from <= k < from + n, of a channel of
 * @p capture (a struct sscope_capture *) will not be read for a while: when
 * the capture is mapped from its file (sscope_read_opts.in_place) their
 * memory pages are given back (a later read fetches them from the file
 * again, or from the page cache); otherwise nothing happens.  Meant as
 * sscope_allan_opts.release, so that a record and the Allan workspace are
 * never both whole in memory.  Thread-safe.
 */
void sscope_capture_release(void *capture, const double *x, size_t stride,
			    size_t from, size_t n);

/** @return the index of channel @p name, or -1. */
long sscope_capture_find(const struct sscope_capture *cap, const char *name);

/**
 * Keep only the channels a column list names, in the list's order: the one
 * rule by which channels are chosen everywhere (a command's -c, a scene's
 * columns, after a calibration is applied).  The list is
 * "NAME|INDEX[,...]": a NAME is a channel's name (exact, else ignoring
 * case), an INDEX the 1-based column of the source file; blanks around an
 * item are ignored, empty items skipped, an item naming a channel already
 * chosen counts once.
 * @param cap      the capture, changed in place (dropped channels freed).
 * @param columns  the list; NULL or "" keeps every channel.
 * @return 0; -EINVAL when an item names no data channel of @p cap (diag
 *         names it and lists the channels); -ENOMEM.
 */
int sscope_capture_select(struct sscope_capture *cap, const char *columns,
			  struct sscope_diag *diag);

/**
 * sscope_capture_select() as a view: a capture holding the chosen channels
 * of @p cap without copying samples.  The view is valid while @p cap is;
 * sscope_capture_free() frees only what the view owns.
 * @return as sscope_capture_select().
 */
int sscope_capture_view(const struct sscope_capture *cap, const char *columns,
			struct sscope_capture **view, struct sscope_diag *diag);

/**
 * Is the rate derived from the time column plausible (1e-3 .. 1e7 Hz)?
 * An implausible one usually means time stamps in another unit than their
 * header says (nanoseconds read as seconds).
 * @param cap   a loaded capture.
 * @param hint  receives, when implausible, one sentence naming the rate,
 *              the likely unit and the fix.
 * @return 0 (plausible, or the rate did not come from a time column), or
 *         -EDOM with @p hint filled.
 */
int sscope_capture_check_rate(const struct sscope_capture *cap,
			      struct sscope_diag *hint);

/* ------------------------------------------------------------------ */
/* Capture writers                                                     */
/* ------------------------------------------------------------------ */

/** File formats a capture can be written in. */
enum sscope_capture_format {
	SSCOPE_CAPTURE_CSV = 0, /**< comma-separated, units in the header */
	SSCOPE_CAPTURE_BIN32,   /**< sensorscope binary, float32 samples */
	SSCOPE_CAPTURE_BIN64    /**< sensorscope binary, float64 samples */
};

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

/**
 * Write a whole capture (time, channels, temperature) atomically.
 * Channel values are written in their own unit_label units.
 * @return as the streaming writer.
 */
int sscope_capture_write(const struct sscope_capture *cap, const char *path,
			 enum sscope_capture_format fmt, int digits,
			 struct sscope_diag *diag);

/** As sscope_capture_write(), on a stream the caller owns (see
 * sscope_writer_fopen()). */
int sscope_capture_fwrite(const struct sscope_capture *cap, FILE *f,
			  enum sscope_capture_format fmt, int digits,
			  struct sscope_diag *diag);

/* ------------------------------------------------------------------ */
/* Statistics and timing (analysis/stats.c, analysis/timing.c)          */
/* ------------------------------------------------------------------ */

/** Summary statistics of a channel. */
struct sscope_stats {
	size_t n;      /**< finite samples used */
	size_t n_nan;  /**< NaN samples skipped */
	double mean;
	double sd;     /**< sample standard deviation (n - 1) */
	double min;
	double max;
};

/**
 * Mean, standard deviation, extremes of x[k*stride], k < n, skipping NaN.
 * One pass over memory, each cache-sized block in two passes, blocks merged
 * pairwise, sums compensated: exact to a few ulps even with an offset 1e9
 * times the spread, and for any finite samples (1e308 or 1e-300: summed
 * again scaled by a power of two).
 * @return 0; -EDOM when fewer than one finite sample (sd needs two: with
 *         one sample sd is 0); -ERANGE when the sd exceeds the double
 *         range (samples near +-1.8e308, or infinite ones; the other
 *         fields are set); -EINVAL for stride 0.
 */
int sscope_stats_compute(const double *x, size_t stride, size_t n,
			 struct sscope_stats *st);

/**
 * Analyse time stamps.  Intervals that are not positive, and the two
 * around a backward step (a swapped pair of rows makes them long), are
 * neither gaps nor part of the rate.
 * @param t_s         n time stamps in seconds.
 * @param gap_factor  an interval longer than gap_factor times the median is
 *                    a gap (1.5 is usual).
 * @param gaps        optional array receiving up to @p max_gaps gaps.
 * @param n_gaps_out  optional: number written to @p gaps.
 * @param scratch     n - 1 doubles of workspace (for the median).
 * @return 0; -EDOM for n < 2 or a non-positive median interval; -EINVAL.
 */
int sscope_timing_analyze(const double *t_s, size_t n, double gap_factor,
			  struct sscope_timing *tm, struct sscope_gap *gaps,
			  size_t max_gaps, size_t *n_gaps_out, double *scratch);

/**
 * Latency of receive times against the stamps they carry (a ROS
 * container's receive times against the header stamps): rx[i] - t[i].
 * @param scratch  n doubles of workspace.
 * @return 0; -EDOM for n < 1 or non-finite latencies; -EINVAL.
 */
int sscope_timing_latency(const double *rx_s, const double *t_s, size_t n,
			  double *median_s, double *min_s, double *max_s,
			  double *scratch);

/**
 * Whether two timings of one record agree: rates within @p rel_tol and
 * the same counts of gaps and of backward steps.
 */
bool sscope_timing_agree(const struct sscope_timing *a,
			 const struct sscope_timing *b, double rel_tol);

/**
 * Streaming form of sscope_timing_analyze() for a record read in chunks
 * (memory independent of its length).  The median interval is taken over
 * the first SSCOPE_TIMING_STREAM_BLOCK intervals (all of them in a shorter
 * record, where every result but jitter_rms_s equals
 * sscope_timing_analyze()'s exactly); later intervals are classified
 * against it.  Jitter comes from sums about that median.
 */
struct sscope_timing_stream;

/** Intervals the streaming median is taken over. */
#define SSCOPE_TIMING_STREAM_BLOCK 65536

/** @return 0, -EINVAL (gap_factor <= 1), -ENOMEM. */
int sscope_timing_stream_new(struct sscope_timing_stream **ts,
			     double gap_factor);

/** Feed the next @p n stamps (s, any chunking).  @return 0, -EINVAL. */
int sscope_timing_stream_feed(struct sscope_timing_stream *ts,
			      const double *t_s, size_t n);

/**
 * The timing of the stamps fed so far.
 * @return 0; -EDOM for fewer than two stamps or a non-positive median
 *         interval; -EINVAL.
 */
int sscope_timing_stream_result(struct sscope_timing_stream *ts,
				struct sscope_timing *tm);

/** Free (NULL is ignored). */
void sscope_timing_stream_free(struct sscope_timing_stream *ts);


/* ------------------------------------------------------------------ */
/* INI specifications (src/spec.c)                                     */
/* ------------------------------------------------------------------ */

/** A parsed INI file: [sections] of "key = value" lines (keys and section
 *  names case-insensitive; '#' and ';' comments). */
struct sscope_ini;

/**
 * Parse INI text.
 * @param name  file name used in messages.
 * @return 0; -EBADMSG (syntax: the line is named), -ENOMEM.
 */
int sscope_ini_parse(struct sscope_ini **ini, const char *text, size_t len,
		     const char *name, struct sscope_diag *diag);

/** Read and parse an INI file.  @return as sscope_ini_parse(), -errno. */
int sscope_ini_load(struct sscope_ini **ini, const char *path,
		    struct sscope_diag *diag);

/** Free (NULL is ignored). */
void sscope_ini_free(struct sscope_ini *ini);

/** @return the file name given to the parser (owned by @p ini). */
const char *sscope_ini_name(const struct sscope_ini *ini);
size_t sscope_ini_n_sections(const struct sscope_ini *ini);
/** @return the name of section @p i (line number in *line), or NULL. */
const char *sscope_ini_section(const struct sscope_ini *ini, size_t i,
			       size_t *line);
bool sscope_ini_has_section(const struct sscope_ini *ini, const char *section);
size_t sscope_ini_n_keys(const struct sscope_ini *ini, const char *section);
/** @return key @p k of @p section with its value and line, or NULL. */
const char *sscope_ini_key(const struct sscope_ini *ini, const char *section,
			   size_t k, const char **value, size_t *line);
/** @return the value of @p key in @p section (NULL when absent). */
const char *sscope_ini_get(const struct sscope_ini *ini, const char *section,
			   const char *key, size_t *line);
/**
 * Refuse keys not in @p allowed (a NULL-terminated list).
 * @return 0, or -EINVAL naming the file, line and key.
 */
int sscope_ini_check_keys(const struct sscope_ini *ini, const char *section,
			  const char *const *allowed, struct sscope_diag *diag);
/**
 * A value with an optional unit, converted to SI.  A bare number is taken
 * in the SI unit @p si_unit.
 * @return 0; -ENOENT when the key is absent (diag untouched); -EINVAL for a
 *         malformed value or a unit of another dimension (file, line, key).
 */
int sscope_ini_quantity(const struct sscope_ini *ini, const char *section,
			const char *key, const char *si_unit, double *out,
			struct sscope_diag *diag);
/** An integer in [lo, hi].  @return 0, -ENOENT, -EINVAL. */
int sscope_ini_integer(const struct sscope_ini *ini, const char *section,
		       const char *key, long lo, long hi, long *out,
		       struct sscope_diag *diag);

/** Fields present in a struct sscope_sensor_spec (bit mask). */
enum {
	SSCOPE_SPEC_RANGE = 1u << 0,
	SSCOPE_SPEC_Q = 1u << 1,
	SSCOPE_SPEC_N = 1u << 2,
	SSCOPE_SPEC_B = 1u << 3,
	SSCOPE_SPEC_K = 1u << 4,
	SSCOPE_SPEC_R = 1u << 5,
	SSCOPE_SPEC_BIAS = 1u << 6,
	SSCOPE_SPEC_SF = 1u << 7,
	SSCOPE_SPEC_TEMPCO = 1u << 8,
	SSCOPE_SPEC_TEMPS = 1u << 9,
	SSCOPE_SPEC_SENSITIVITY = 1u << 10,
	SSCOPE_SPEC_ZERO = 1u << 11,
	SSCOPE_SPEC_BANDWIDTH = 1u << 12,
};

/**
 * A gyro or accelerometer specification, SI throughout.  With U the rate
 * unit (rad/s for a gyro, m/s^2 for an accelerometer): range, bias and the
 * bias instability B are in U; quantization Q in U*s; noise density N
 * (angle/velocity random walk) in U/sqrt(Hz); rate random walk K in
 * U/s/sqrt(Hz); rate ramp R in U/s; bias_tempco in U/degC; sensitivity in
 * V per U (analog outputs).  IEEE Std 952-1997 Annex C terms.
 */
struct sscope_sensor_spec {
	char name[64];
	enum sscope_quantity quantity; /**< ANGULAR_RATE or ACCELERATION */
	unsigned has;                  /**< SSCOPE_SPEC_* of fields given */
	double range;                  /**< +- full scale, U */
	double q, n, b, k, r;          /**< IEEE 952 noise terms */
	double bias;                   /**< constant bias, U */
	double scale_factor_error;     /**< ratio (ppm * 1e-6) */
	double bias_tempco;            /**< U per degC */
	double temp_min_degc, temp_max_degc;
	double sensitivity;            /**< V per U (analog output) */
	double zero_output_v;          /**< output at zero input, V */
	double bandwidth_hz;           /**< -3 dB bandwidth of the output */
	int filter_order;              /**< order of that filter (default 1) */
};

/** @return the keys a [sensor] section may hold (NULL-terminated). */
const char *const *sscope_sensor_spec_keys(void);

/**
 * Read a sensor specification from section @p section of @p ini.  The
 * quantity (gyro or accelerometer) follows from the units of range or
 * noise_density; every value with a unit of the wrong dimension, every
 * unknown key and every negative magnitude is refused with file, line and
 * key.  A bare scale_factor_error is in ppm.
 * @return 0 or -EINVAL.
 */
int sscope_sensor_spec_from_ini(const struct sscope_ini *ini,
				const char *section,
				struct sscope_sensor_spec *spec,
				struct sscope_diag *diag);

/** Load the [sensor] section of a file.  @return as above, -errno. */
int sscope_sensor_spec_load(const char *path, struct sscope_sensor_spec *spec,
			    struct sscope_diag *diag);

#ifdef __cplusplus
}
#endif

/*
 * Analysis and converter modules: one public header each (analysis/sscope-
 * *.h, adc/sscope-*.h), installed beside this one and included here, so
 * that <sensorscope.h> declares the whole library.
 */
#include "sscope-psd.h"
#include "sscope-vibration.h"
#include "sscope-adis.h"
#include "sscope-spiadc.h"
#include "sscope-calib.h"
#include "sscope-budget.h"
#include "sscope-model.h"
#include "sscope-allan.h"
#include "sscope-sim.h"
#include "sscope-tempbias.h"
#include "sscope-inclino.h"
#include "sscope-adc.h"
#include "sscope-nav.h"
#include "sscope-strapdown.h"
#include "sscope-navsim.h"
#include "sscope-heading.h"
#include "sscope-walk.h"
#include "sscope-clip.h"

#endif /* SENSORSCOPE_H */
