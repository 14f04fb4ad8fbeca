/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Noise-parameter files for estimators (noise-export.c): Kalibr imu.yaml,
 * OpenVINS kalibr_imu_chain.yaml and the imu_utils parameter YAML, one
 * entry each in a table of targets.  Every target goes through the same
 * gate: a value the adequacy check doubts (the record moves, the fit is
 * rejected, a transient, step or temperature drift biases it) is refused
 * unless forced, and then marked in a comment beside it; a term the
 * record does not establish is written as its upper bound, marked, with a
 * warning; no value is ever written as 0.
 */
#ifndef SSCOPE_NOISE_EXPORT_H
#define SSCOPE_NOISE_EXPORT_H

#include "sensorscope.h"
#include "sscope-allan.h"

struct ssc_common;
struct ssc_export_values; /* the gated values of a file (noise-export.c) */
struct ssc_export_hdr;    /* the leading comment block being written */

/* one analysed channel */
struct ssc_noise_chan {
	const char *name;
	enum sscope_quantity q;            /* of the rate: gyro or accel */
	const struct sscope_noise_fit *fit; /* NULL when not fitted */
	const struct sscope_adequacy *adq;  /* its adequacy check, or NULL */
};

struct ssc_noise_export {
	const struct ssc_noise_chan *ch;
	size_t n;
	double rate_hz;
	double inflate;      /* multiplies every exported value */
	const char *source;  /* for the header comment */
	const char *topic;   /* ROS topic of the data, or NULL */
	const char *name;    /* sensor name (imu_utils), or NULL */
	double duration_s;   /* the longest channel's record length */
	bool force;          /* write values the adequacy check doubts */
};

/* An export target: a new file format is one entry of the table. */
struct ssc_export_target {
	const char *name;   /* "kalibr" (--export TARGET[:FILE]) */
	const char *option; /* its option, "--kalibr" or "--export vins" */
	const char *defname; /* the file when --export names no FILE */
	int style;          /* comment style (SSC_EXPORT_HASH, ...) */
	const char *what;   /* "Kalibr IMU noise model" (header comment) */
	const char *preamble; /* lines before the header, or NULL */
	unsigned need;      /* SSC_EXPORT_GYRO / _ACCEL: sensors it needs
			       (both bits: both; SSC_EXPORT_ANY: either) */
	unsigned terms;     /* terms it writes (bits of enum sscope_term) */
	/* the body after the common header; v holds the gated values */
	void (*body)(FILE *f, const struct ssc_noise_export *e,
		     const struct ssc_export_values *v);
	/* its convention, as lines of the leading comment (note()) */
	void (*notes)(struct ssc_export_hdr *h, const struct ssc_noise_export *e,
		      const struct ssc_export_values *v);
};

/* comment styles of the leading block */
enum {
	SSC_EXPORT_HASH,    /* # (YAML, Python) */
	SSC_EXPORT_PERCENT, /* % (MATLAB) */
	SSC_EXPORT_XML,     /* <!-- --> (SDF) */
	SSC_EXPORT_JSON,    /* a "sensorscope_note" array of strings */
};

/* one requested file: --export TARGET[:FILE] or an alias option */
struct ssc_export_req {
	const struct ssc_export_target *t;
	const char *path;
};

#define SSC_EXPORT_MAX 16

/* Parse TARGET[:FILE] (opt: the option's name, for messages) and append it
 * to req[*n]; a usage error (exit 2) on an unknown target, a repeated file
 * or too many files. */
int ssc_export_parse(const char *opt, const char *arg,
		     struct ssc_export_req *req, size_t *n);

/* The names of the targets, "kalibr, imu_utils, ..." (static). */
const char *ssc_export_target_names(void);

struct ssc_allan_res;
/* Write every requested file from the channels of an allan result. */
int ssc_export_allan(const struct ssc_common *co,
		     const struct ssc_allan_res *R,
		     const struct ssc_export_req *req, size_t n,
		     double inflate, bool force);

enum {
	SSC_EXPORT_GYRO = 1u << 0,
	SSC_EXPORT_ACCEL = 1u << 1,
	SSC_EXPORT_ANY = 1u << 2,
};

/* The targets, NULL-terminated by name. */
extern const struct ssc_export_target ssc_export_targets[];

/* The target of that name, or NULL. */
const struct ssc_export_target *ssc_export_target_find(const char *name);

/* Write one target's file atomically: the adequacy gate, the header, the
 * body.  Prints errors and warnings; returns an exit code (1 when the
 * gate refuses: the reason in one line). */
int ssc_export_write(const struct ssc_common *co,
		     const struct ssc_export_target *t, const char *path,
		     const struct ssc_noise_export *e);

#endif
