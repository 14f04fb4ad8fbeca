/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Live acquisition (internal to the sensorscope command; hardware lives
 * only here).
 *
 *   source --next()--> reader thread --SPSC ring--> writer thread --> file
 *
 * A source waits for the next sample (a data-ready edge, a poll tick or a
 * simulated clock), reads and decodes one frame and returns it with its
 * time stamp and the number of samples it knows were lost right before
 * it.  The reader thread adds ring overruns to that count, the writer
 * thread streams rows to a capture file (sscope_writer_*) and marks every
 * gap; nothing is ever interpolated.  The calling thread handles signals
 * and the live view.
 */
#ifndef SSCOPE_ACQ_H
#define SSCOPE_ACQ_H

#include "config.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sensorscope.h"

#define SSC_ACQ_MAX_CH 16

/* Why samples are missing before a row (bit mask). */
enum {
	SSC_GAP_COUNTER = 1u << 0,  /* the device's sample counter jumped */
	SSC_GAP_EVENTS = 1u << 1,   /* data-ready events or poll ticks lost */
	SSC_GAP_RING = 1u << 2,     /* ring overrun: the writer fell behind */
	SSC_GAP_REJECTED = 1u << 3, /* frames refused (checksum) */
};

/* One sample as it travels through the ring. */
struct ssc_acq_sample {
	int64_t t_ns;        /* data-ready time stamp (CLOCK_MONOTONIC) */
	uint32_t missing;    /* samples lost right before this one */
	uint16_t cause;      /* SSC_GAP_* of those */
	uint16_t status;     /* device status word (ADIS DIAG_STAT), 0 ok */
	double temp_degc;    /* NaN without a temperature */
	double v[SSC_ACQ_MAX_CH]; /* SI */
};

/* What a source delivers. */
struct ssc_source_info {
	size_t n_channels;
	char name[SSC_ACQ_MAX_CH][32];
	char unit[SSC_ACQ_MAX_CH][32]; /* unit written to the capture */
	bool has_temp;
	bool has_counter;    /* gaps come from a device sample counter */
	bool nominal_time;   /* time stamps are nominal (simulator) */
	bool can_wait;       /* nothing is lost by holding the source back
				(the unpaced simulator): when the ring is
				full the reader waits for the writer instead
				of dropping the sample */
	double rate_hz;      /* nominal output rate, 0 when unknown */
	char desc[256];      /* "adis16470 on /dev/spidev0.0, ..." */
};

/* Counters kept by a source (written by the reader thread only). */
struct ssc_source_counts {
	uint64_t frames;          /* frames read */
	uint64_t checksum_errors; /* frames refused */
	uint64_t duplicates;      /* same sample read twice */
	uint64_t counter_missing; /* samples lost according to the counter */
	uint64_t events_lost;     /* data-ready events / poll ticks lost */
	uint64_t status_samples;  /* samples with a device status flag */
	uint64_t time_estimated;  /* time stamps moved forward by whole
				     periods (see src-spi.c) */
	uint16_t status_or;       /* OR of every status word */
	double late_max_s;        /* pacing lateness (poll and sim sources) */
	double late_sum2_s2;
	uint64_t late_n;
};

struct ssc_source;

struct ssc_source_ops {
	/*
	 * Wait for and read the next sample.  Returns 0 with *s filled;
	 * -EAGAIN when a frame was refused (counted) and the caller should
	 * call again; -ECANCELED when src->stop_fd became readable;
	 * -ETIMEDOUT when no data arrived within src->timeout_s; another
	 * negative errno for a fatal error (diag says why).
	 */
	int (*next)(struct ssc_source *src, struct ssc_acq_sample *s,
		    struct sscope_diag *diag);
	/* Optional: samples read but not yet returned (after a stop,
	 * timeout or error); 0 with *s, -ENODATA when none is left. */
	int (*flush)(struct ssc_source *src, struct ssc_acq_sample *s);
	void (*close)(struct ssc_source *src);
};

struct ssc_source {
	const struct ssc_source_ops *ops;
	struct ssc_source_info info;
	struct ssc_source_counts counts;
	int stop_fd;        /* readable when a stop is requested, -1 none */
	double timeout_s;   /* data-ready timeout */
	void *priv;
};

/* Close and free a source (NULL is ignored). */
void ssc_source_close(struct ssc_source *src);

/*
 * The simulator: white noise like a 6-axis IMU.  OPTS is "" or a comma
 * list: rate=HZ (1000), channels=1..6 (6), seed=N (1), arw=Q (angle random
 * walk, default 0.34 deg/sqrt(h)), vrw=Q (velocity random walk, default
 * 0.037 m/s/sqrt(h)), temp=DEGC (25), speed=X|max (1: real time; X times
 * faster; max: unpaced).
 */
int ssc_source_sim_open(struct ssc_source **src, const char *opts,
			struct sscope_diag *diag);

/* Options of the SPI sources. */
struct ssc_spi_opts {
	const char *spi;      /* /dev/spidevB.C */
	const char *device;   /* "adis16470", ..., or "spiadc:FRAME" */
	const char *drdy;     /* CHIP:LINE, NULL to poll */
	int drdy_edge;        /* 0 from the device, 1 rising, -1 falling */
	double rate_hz;       /* ADIS: program DEC_RATE; spiadc: poll rate */
	uint32_t speed_hz;    /* SPI clock cap, 0 for the device default */
};

/*
 * Open a device on spidev: an ADIS1646x/1647x (checks PROD_ID) or a
 * generic converter frame.  Returns 0, -ENOTSUP (data-ready line asked
 * for but built without libgpiod), -ENODEV (wrong or silent device),
 * -EINVAL (bad options), -errno from the OS.
 */
int ssc_source_spi_open(struct ssc_source **src, const struct ssc_spi_opts *o,
			struct sscope_diag *diag);

/* Is this build able to wait for data-ready lines?  Which API? */
bool ssc_drdy_available(void);
const char *ssc_drdy_api(void);

/* ------------------------------------------------------------------ */
/* Single-producer single-consumer ring of samples (lock-free).        */

struct ssc_ring {
	struct ssc_acq_sample *buf;
	size_t mask;
	_Alignas(64) atomic_size_t head; /* next slot to fill (producer) */
	_Alignas(64) atomic_size_t tail; /* next slot to read (consumer) */
};

/* capacity is rounded up to a power of two (>= 2).  0, -EINVAL, -ENOMEM */
int ssc_ring_init(struct ssc_ring *r, size_t capacity);
void ssc_ring_free(struct ssc_ring *r);
/* Producer: false when the ring is full (nothing is overwritten). */
bool ssc_ring_push(struct ssc_ring *r, const struct ssc_acq_sample *s);
/* Consumer: move up to max samples out; returns how many. */
size_t ssc_ring_pop(struct ssc_ring *r, struct ssc_acq_sample *out,
		    size_t max);
size_t ssc_ring_capacity(const struct ssc_ring *r);

/* ------------------------------------------------------------------ */
/* The recording file (recfile.c): rows reach NAME.partial within       */
/* SSC_REC_FLUSH_S, a clean stop renames it to NAME, a failed write     */
/* cuts it at its last complete row and keeps it.                       */

#define SSC_REC_FLUSH_S 0.2  /* rows formatted are written at least so often */
#define SSC_REC_SYNC_S 1.0   /* and synced to the disk so often */

struct ssc_recfile;

struct ssc_rec_opts {
	const char *path;        /* "-" and devices are written directly */
	bool overwrite;          /* replace an existing NAME at the end */
	enum sscope_capture_format format;
	const struct sscope_writer_column *cols;
	size_t n_cols;
	const char *const *comments; /* CSV comment lines after the header */
	uint64_t fail_after_bytes;   /* tests: the disk is full after so many
					bytes of the file (0: never) */
};

struct ssc_rec_end {
	uint64_t rows;     /* rows in the file */
	bool kept;         /* a file holds them (NAME, or NAME.partial) */
	bool removed;      /* no row: the file was removed */
	bool trailer_lost; /* the end line did not fit */
	int rename_err;    /* -EEXIST: NAME appeared meanwhile; the rows are
			      in NAME.partial (where) */
	char where[4200];  /* the file that holds the rows */
};

/*
 * Create NAME.partial and write the header and comments.  Returns 0,
 * -EEXIST (NAME exists without overwrite, or NAME.partial exists), -EISDIR,
 * -errno of the OS (diag says which file and why).
 */
int ssc_recfile_open(struct ssc_recfile **rf, const struct ssc_rec_opts *o,
		     struct sscope_diag *diag);
/* Format rows (row-major, SI) or a comment into memory: 0, -ENOMEM, or
 * the error of an earlier write. */
int ssc_recfile_append(struct ssc_recfile *rf, const double *rows, size_t n);
int ssc_recfile_comment(struct ssc_recfile *rf, const char *text);
/* Write what was formatted.  On failure (-ENOSPC, -EDQUOT, -EFBIG, -EIO)
 * the file ends at its last complete row and every later call fails. */
int ssc_recfile_flush(struct ssc_recfile *rf);
bool ssc_recfile_dirty(const struct ssc_recfile *rf);
uint64_t ssc_recfile_buffered(const struct ssc_recfile *rf);
uint64_t ssc_recfile_rows(const struct ssc_recfile *rf);
const char *ssc_recfile_name(const struct ssc_recfile *rf);
/* fdatasync (from any thread); an error shows at the next flush. */
void ssc_recfile_sync(struct ssc_recfile *rf);
/*
 * The end: the trailer line (CSV; after a failed write only if it fits),
 * sync, close, rename NAME.partial to NAME (a file without rows is
 * removed instead).  *end says where the rows are.  Returns 0 or the
 * write error (the rows written before it are kept).  Then free.
 */
int ssc_recfile_close(struct ssc_recfile *rf, const char *trailer,
		      struct ssc_rec_end *end);
void ssc_recfile_free(struct ssc_recfile *rf);

/* ------------------------------------------------------------------ */
/* Running statistics                                                  */

/* Intervals between data-ready time stamps (Welford). */
struct ssc_intervals {
	uint64_t n;
	double mean_s, m2, min_s, max_s;
};
void ssc_intervals_add(struct ssc_intervals *iv, double dt_s);
double ssc_intervals_sd(const struct ssc_intervals *iv);
/* rms pacing lateness of a source, s (NaN before any) */
double ssc_source_late_rms(const struct ssc_source_counts *c);

/*
 * Samples lost between two time stamps dt_s apart at a nominal period:
 * round(dt / period) - 1, never negative.
 */
uint64_t ssc_gap_from_time(double dt_s, double period_s);

/*
 * Samples lost between two readings of a 16-bit wrapping counter, using
 * the time between them to resolve wraps: the counter gives the count
 * modulo 65536, the time stamps (when period_s > 0) the number of wraps.
 * Returns -1 for a repeated value (the same sample twice).
 */
long ssc_gap_from_counter(uint16_t prev, uint16_t cur, double dt_s,
			  double period_s);

/* Non-overlapping Allan deviation at a few averaging factors, updated
 * sample by sample (for the live view). */
#define SSC_LIVE_TAUS 4
struct ssc_run_adev {
	size_t m[SSC_LIVE_TAUS];       /* 1, 10, 100, 1000 */
	double block[SSC_LIVE_TAUS];   /* sum of the current block */
	size_t filled[SSC_LIVE_TAUS];
	double prev[SSC_LIVE_TAUS];    /* previous block average */
	bool have_prev[SSC_LIVE_TAUS];
	double sum2[SSC_LIVE_TAUS];    /* sum of squared differences */
	uint64_t n[SSC_LIVE_TAUS];
};
void ssc_run_adev_init(struct ssc_run_adev *a);
void ssc_run_adev_add(struct ssc_run_adev *a, double x);
/* A gap: blocks never straddle it. */
void ssc_run_adev_break(struct ssc_run_adev *a);
/* ADEV at averaging factor index k, NaN until two blocks exist. */
double ssc_run_adev_get(const struct ssc_run_adev *a, size_t k);

/* ------------------------------------------------------------------ */
/* The engine                                                          */

struct ssc_acq_live {
	const struct ssc_source_info *info;
	double elapsed_s;        /* data time since the first sample */
	uint64_t samples;
	uint64_t missing;
	uint64_t checksum_errors;
	double rate_hz;          /* over the last update period */
	double last[SSC_ACQ_MAX_CH];
	double mean[SSC_ACQ_MAX_CH];
	double temp_degc;
	double tau_s[SSC_LIVE_TAUS];
	double adev[SSC_ACQ_MAX_CH][SSC_LIVE_TAUS];
};

struct ssc_acq_config {
	struct ssc_source *src;
	const char *path;           /* capture file, NULL: none (live only) */
	enum sscope_capture_format format;
	uint64_t count;             /* stop after so many samples (0: none) */
	double duration_s;          /* stop after this span of data (0: none) */
	double timeout_s;           /* data-ready timeout (> 0) */
	size_t ring_capacity;       /* samples */
	int rt_priority;            /* SCHED_FIFO priority of the reader, 0 */
	bool lock_memory;           /* mlockall */
	bool handle_signals;        /* stop cleanly on SIGINT, SIGTERM, SIGHUP */
	const char *const *comments;/* CSV comment lines after the header */
	bool overwrite;             /* replace an existing file at the end
				       (else it is refused: -EEXIST) */
	void (*live)(const struct ssc_acq_live *snap, void *ctx);
	void *live_ctx;
	double live_period_s;
	/* Optional: called by the writer thread with each batch of samples
	 * it has handed to the file (elapsed_s: data time of the last);
	 * returning true ends the run as a signal would (SSC_STOP_UNTIL):
	 * every sample read is still written.  Its time is the writer's: a
	 * paced source must have a ring that holds that long. */
	bool (*until)(const struct ssc_acq_sample *s, size_t n,
		      double elapsed_s, void *ctx);
	void *until_ctx;
	unsigned writer_delay_us;   /* tests: slow the writer down per batch */
	uint64_t disk_bytes;        /* tests: the disk fills after so many
				       bytes of the capture (0: never) */
};

enum ssc_acq_stop {
	SSC_STOP_COUNT = 0,
	SSC_STOP_DURATION,
	SSC_STOP_SIGNAL,
	SSC_STOP_TIMEOUT,
	SSC_STOP_ERROR,
	SSC_STOP_FULL,      /* the capture could not grow: disk full,
			       quota or file size limit (res->error) */
	SSC_STOP_UNTIL,     /* cfg->until said so */
};

struct ssc_acq_result {
	uint64_t samples;         /* rows written */
	uint64_t drops_ring;      /* samples lost in ring overruns */
	uint64_t missing;         /* rows missing from the capture, all causes */
	uint64_t gaps;            /* places where rows are missing */
	uint64_t events_gap;      /* missing found from time stamps */
	struct ssc_source_counts src;
	double duration_s;        /* last minus first time stamp */
	double effective_rate_hz; /* (samples - 1) / duration */
	struct ssc_intervals iv;  /* regular data-ready intervals */
	double reader_cpu_s, writer_cpu_s, wall_s;
	int rt_errno;             /* 0 when SCHED_FIFO was set (or not asked) */
	int mlock_errno;
	enum ssc_acq_stop stop;
	int signal;
	int error;                /* negative errno for TIMEOUT/ERROR */
	bool committed;           /* the capture file exists */
	uint64_t unsaved;         /* samples read but not in the file (after
				     a failed write) */
	bool trailer_lost;        /* the end line did not fit */
	int rename_err;           /* the file stayed NAME.partial: -EEXIST
				     (NAME appeared meanwhile) or -errno */
	char file[4200];          /* where the samples are */
};

/*
 * Run an acquisition until count, duration, a signal, a timeout or an
 * error.  Samples are recorded into PATH.partial (recfile above): within
 * SSC_REC_FLUSH_S of being read they are in the file, which any command
 * reads.  At the end everything read is written and the file renamed to
 * PATH when at least one sample was written, even after a timeout, a
 * device error or a failed write (a full disk: the file ends at its last
 * complete row; res->stop SSC_STOP_FULL).  A file without samples is
 * removed.  Returns 0 when the run ended by count, duration or signal;
 * the source's error or -ETIMEDOUT; the write error (res->committed says
 * whether samples were kept); -EEXIST when PATH or PATH.partial exists
 * (PATH: unless cfg->overwrite), -errno when the file could not be
 * created (diag says why in each case).
 */
int ssc_acq_run(const struct ssc_acq_config *cfg, struct ssc_acq_result *res,
		struct sscope_diag *diag);

/* Helpers shared by the sources (src/acq/util.c). */
int64_t ssc_now_ns(void);
/* Wait until fd is readable (1), the timeout passes (0) or stop_fd is
 * readable (-ECANCELED); timeout_s < 0 waits forever. */
int ssc_wait_fd(int fd, int stop_fd, double timeout_s);
/* Sleep until the absolute CLOCK_MONOTONIC time, 0 or -ECANCELED. */
int ssc_sleep_until(int64_t t_ns, int stop_fd);
/* Why a capture could not grow, in words: "disk full" (-ENOSPC), "disk
 * quota full" (-EDQUOT), "file size limit" (-EFBIG). */
const char *ssc_acq_full_words(int err);
/* Is err one of those three? */
bool ssc_acq_storage_full(int err);
/* printf into diag, returns err */
int ssc_acq_diag(struct sscope_diag *d, int err, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

#endif
