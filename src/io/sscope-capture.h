/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-capture.h
 * @brief Captures in memory: channels, columns, containers, loading, selecting, writing.
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_CAPTURE_H
#define SSCOPE_CAPTURE_H

#include <stdio.h>
#include "sscope-unit.h"
#include "sscope-timing.h"

#ifdef __cplusplus
extern "C" {
#endif

struct sscope_reader_opts;

/** Role of a column of a capture file. */
enum sscope_capture_role {
	SSCOPE_CAPTURE_ROLE_DATA = 0, /**< a measured channel */
	SSCOPE_CAPTURE_ROLE_TIME,     /**< time stamps */
	SSCOPE_CAPTURE_ROLE_TEMP      /**< temperature */
};

/** Description of one column of a capture source. */
struct sscope_capture_column {
	const char *name;       /**< header name without its unit */
	const char *unit_label; /**< unit as written (or given); "" if none */
	struct sscope_unit unit;        /**< file unit -> SI */
	enum sscope_quantity quantity;  /**< what it measures */
	enum sscope_capture_role role;          /**< data, time or temperature */
	size_t index;                   /**< 0-based position in the source */
};

/** How the nominal sample rate of a capture was established. */
enum sscope_capture_rate_source {
	SSCOPE_CAPTURE_RATE_NONE = 0,   /**< unknown: no time column, no rate given */
	SSCOPE_CAPTURE_RATE_GIVEN,      /**< from the caller (--rate) */
	SSCOPE_CAPTURE_RATE_TIME_COLUMN, /**< from the median time-stamp interval */
	SSCOPE_CAPTURE_RATE_HEADER      /**< from a "# rate: 100 Hz" header comment */
};

/** Longest text of a rate note (struct sscope_capture, rate_note), with
 *  its '\0'. */
#define SSCOPE_CAPTURE_RATE_NOTE_MAX 160

/** A topic (message stream) of a ROS bag, rosbag2 or MCAP file. */
struct sscope_capture_topic {
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
struct sscope_capture_source {
	const char *format;  /**< e.g. "ROS 1 bag v2.0 (lz4 chunks)" */
	size_t n_topics;
	const struct sscope_capture_topic *topics;
	/** Receive time of each row (the bag's or MCAP's log time), s, on
	 *  the time axis of the capture (0 = the first header stamp); NULL
	 *  when the format has none.  In a capture: cap->n values. */
	const double *receive_s;
};

/** One data channel of a loaded capture. */
struct sscope_capture_channel {
	struct sscope_capture_column col; /**< name, unit, quantity (owned) */
	double *data;             /**< n samples in SI (owned) */
	size_t n_nan;             /**< NaN samples (gaps) among them */
};

/** A capture in memory. */
struct sscope_capture {
	char *source;           /**< path given to the loader, "-" for stdin */
	size_t n;               /**< samples per channel */
	size_t n_channels;
	struct sscope_capture_channel *channels;
	double *time_s;         /**< NULL without a time column */
	double *temp_degc;      /**< NULL without a temperature column */
	struct sscope_capture_column time_col; /**< valid when time_s != NULL */
	struct sscope_capture_column temp_col; /**< valid when temp_degc != NULL */
	double rate_hz;         /**< nominal rate; 0 when unknown */
	enum sscope_capture_rate_source rate_source;
	size_t n_nan;           /**< NaN cells read as gaps */
	/** Container details (format, topics, receive times), or NULL for
	 *  delimited text, raw and sensorscope binary files (owned). */
	struct sscope_capture_source *source_info;
	/** A read-only file mapping that holds the channel data (read with
	 *  sscope_reader_opts.in_place), released by sscope_capture_free();
	 *  NULL otherwise.  Such data must not be written, freed or
	 *  reallocated by the caller. */
	void *mapping;
	size_t mapping_len;     /**< bytes of the mapping */
	/** the last data line had no newline (sscope_reader_unterminated) */
	bool unterminated;
	/** Sampling of the time column (sscope_timing_analyze() with
	 *  SSCOPE_TIMING_GAP_FACTOR), valid when has_timing: loaded captures
	 *  with a time column of two or more increasing stamps. */
	struct sscope_timing timing;
	bool has_timing;
	/** The first SSCOPE_CAPTURE_GAPS gaps of the time column (n_gaps of
	 *  them; timing.n_gaps counts all). */
	struct sscope_timing_gap *gaps;
	size_t n_gaps;
	/** A view made by sscope_capture_view(): samples, names, time and
	 *  temperature belong to another capture. */
	bool is_view;
	/** Read with sscope_reader_opts.in_place_unchecked and used in
	 *  place: the samples may hold NaN and infinities that the reader
	 *  did not report (see sscope_capture_check_values()). */
	bool values_unchecked;
	/** Why a header comment that names a rate gave none, when the rate
	 *  is unknown ("line 2: '# rate: 0 Hz' is not a sample rate (...)");
	 *  "" otherwise (sscope_reader_header_rate_note()). */
	char rate_note[SSCOPE_CAPTURE_RATE_NOTE_MAX];
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
			const struct sscope_reader_opts *opts,
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
 * Whether @p x (a channel's samples) lies in the read-only file mapping
 * of @p cap (sscope_reader_opts.in_place): its pages can be given back
 * and fetched again from the file, so the Allan engine may evict them
 * behind its pass (SSCOPE_ALLAN_EVICT_INPUT).  False for NULL.
 */
bool sscope_capture_mapped(const struct sscope_capture *cap, const double *x);

/**
 * The reader's check of a capture's samples, for a capture read with
 * sscope_reader_opts.in_place_unchecked (values_unchecked): the first NaN
 * (unless @p allow_nan) or infinite sample is reported as the reader
 * reports it (file, row, column).
 * @return 0 (also for a capture whose samples the reader checked),
 *         -EBADMSG.
 */
int sscope_capture_check_values(const struct sscope_capture *cap,
				bool allow_nan, struct sscope_diag *diag);

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

/** File formats a capture can be written in. */
enum sscope_capture_format {
	SSCOPE_CAPTURE_CSV = 0, /**< comma-separated, units in the header */
	SSCOPE_CAPTURE_BIN32,   /**< sensorscope binary, float32 samples */
	SSCOPE_CAPTURE_BIN64    /**< sensorscope binary, float64 samples */
};

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

struct sscope_calib_file_triad; /* sscope-calib.h */

/**
 * Apply calibration triads to a loaded capture, in their order
 * (accelerometers before the gyros whose G uses them): each triad whose
 * channels the capture holds is converted to the units the capture holds
 * them in (SI of the channel's unit, or raw values for channels without
 * one), applied in place (sscope_calib_apply()), and the channels take
 * the output unit (names and file columns kept).  A triad of which the
 * capture holds none of the channels is skipped.
 * @param gsens_skipped  receives bit i set when triad i has G but the
 *                       capture lacks its accelerometer channels (G is
 *                       then not corrected); may be NULL.
 * @param applied        receives the triads applied; may be NULL.
 * @return 0; -EINVAL (a triad of which only some channels are present, a
 *         channel in a unit the triad does not expect: diag names them);
 *         -EDOM when no triad applies; -ENOMEM.
 */
int sscope_capture_apply_calib(struct sscope_capture *cap,
				const struct sscope_calib_file_triad *t,
				size_t n, unsigned *gsens_skipped,
				size_t *applied, struct sscope_diag *diag);

/** Options of sscope_capture_open(); zero-initialised means the
 *  defaults (every data column, no calibration). */
struct sscope_capture_open_opts {
	/** How to read the file (NULL: the defaults); its columns are the
	 *  selection, applied after the calibration. */
	const struct sscope_reader_opts *read;
	/** Calibration triads applied before the selection (a calibration
	 *  file's, sscope-calib.h), or NULL; owned by the caller. */
	const struct sscope_calib_file_triad *calib;
	size_t n_calib;
};

/** The stage sscope_capture_open() was at (where it failed). */
enum sscope_capture_stage {
	SSCOPE_CAPTURE_STAGE_READ = 0,  /**< reading the file */
	SSCOPE_CAPTURE_STAGE_CALIBRATE, /**< applying the calibration */
	SSCOPE_CAPTURE_STAGE_SELECT,    /**< choosing the columns */
	SSCOPE_CAPTURE_STAGE_DONE       /**< all done */
};

/** What sscope_capture_open() found worth saying; none is an error. */
struct sscope_capture_notes {
	enum sscope_capture_stage stage; /**< reached (failed there, or DONE) */
	bool unterminated;      /**< the last line had no newline ... */
	size_t rows_read;       /**< ... of these rows */
	/** bit i: triad i has a g-sensitivity but the capture lacks its
	 *  accelerometer channels (not corrected) */
	unsigned calib_gsens_skipped;
	/** read->default_unit was given but every channel's header names
	 *  its own unit: it changed nothing */
	bool unit_unused;
	/** the rate from the time column is implausible; rate_hint says
	 *  why and the fix (sscope_capture_check_rate()) */
	bool rate_implausible;
	struct sscope_diag rate_hint;
	/** read->rate_hz was given and the time column implies a rate more
	 *  than 1 % away: time_column_rate_hz */
	bool rate_disagrees;
	double time_column_rate_hz;
};

/**
 * Open a capture in one call, the one way every command, scene and the
 * Python module reads one: read the file (sscope_capture_load(), every
 * channel when calibrating), apply the calibration
 * (sscope_capture_apply_calib()), keep the channels the columns of read names
 * (sscope_capture_select()) and judge the rate (plausible, and as given in read->rate_hz).
 * @param cap    receives the capture (free it with sscope_capture_free());
 *               NULL on failure.
 * @param opts   options, or NULL for the defaults.
 * @param notes  receives what is worth a warning and the stage reached
 *               (on failure: the stage that failed); may be NULL.
 * @return 0, or the failing stage's error (as its function; diag says).
 */
int sscope_capture_open(struct sscope_capture **cap, const char *path,
			const struct sscope_capture_open_opts *opts,
			struct sscope_capture_notes *notes,
			struct sscope_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_CAPTURE_H */
