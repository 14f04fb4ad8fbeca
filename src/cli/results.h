/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Typed results of the stages that other stages read (budget, heading,
 * walk and navsim read allan's noise terms; budget calib's remaining
 * uncertainty, navsim calib's error model): plain structs around the
 * library's result structs, so a later stage takes numbers and quantities
 * directly, never from re-parsed JSON or unit strings.
 */
#ifndef SSCOPE_RESULTS_H
#define SSCOPE_RESULTS_H

#include "stage.h"
#include "calibfile.h"

/* ------------------------------------------------------------ allan */

/* Units of one channel's results (as text for presentation). */
struct ssc_allan_units {
	enum sscope_quantity rq; /* quantity of the rate the deviations are
				    of (angle input: its derivative) */
	char rate[64];           /* the rate unit as text ("deg/s") */
	char rate_si[64];        /* its SI form ("rad/s") */
	char dev[96];            /* unit of the deviation values in JSON */
	double dev_scale;        /* SI per JSON dev unit */
	char show[96];           /* unit of deviations in text/CSV/plot */
	double show_scale;       /* SI per shown unit */
	char term[5][96];        /* conventional unit of each term */
	char term_si[5][96];     /* SI unit of each term */
};

struct ssc_allan_chan {
	const struct sscope_capture_column *col;
	struct ssc_allan_units u;
	struct sscope_allan_result *res; /* deviations and the noise fit */
	struct sscope_adequacy *adq;     /* what the record supports (NULL
					    with --no-fit) */
	size_t n, nan;
};

struct ssc_allan_file {
	const char *path;
	const struct sscope_capture *cap;
	struct ssc_allan_chan *ch;
	size_t n_ch;
};

struct ssc_allan_res {
	struct ssc_allan_file *fr;
	size_t n_files;
	double ci_level; /* level of the channels' intervals (0: none) */
	/* what every channel was computed with (sscope_allan_analyze()'s
	 * grid and options; no release callback, no plan) */
	enum sscope_allan_tau_grid grid;
	struct sscope_allan_opts ao;
	struct sscope_noise_fit_opts fo;
};

/*
 * The result an allan stage computed for the samples data[0..n) at
 * rate_hz (a channel of one of its captures, the very array) with this
 * grid and these options (release and plan ignored), or NULL: a later
 * stage that needs exactly that takes it instead of computing it again.
 */
const struct sscope_allan_result *
ssc_allan_res_find(const struct ssc_allan_res *R, const double *data, size_t n,
		   double rate_hz, enum sscope_allan_tau_grid grid,
		   const struct sscope_allan_opts *ao,
		   const struct sscope_noise_fit_opts *fo);

/* ------------------------------------------------------------ calib */

/* One calibrated triad and what the report derives from it. */
struct ssc_calib_triad_out {
	struct sscope_calib_file_triad t;   /* names, units, the correction (library) */
	enum sscope_quantity q;  /* output quantity */
	const char *residual_unit;
	double noise_density;    /* SI / sqrt(Hz) of the output, NaN unknown */
	bool error_model;        /* input and output of one dimension */
	double A[3][3];          /* error model: reading = A u + b (SI) */
	int grade;               /* row of sscope_calib_grades(), < 0 none */
	double grade_dist;
	/* gyro multi-position: gravity carried over each motion, rad */
	size_t n_motion;
	double motion_rms, motion_max, motion_rms_bias_only;
};

/* The calib stage's result starts with this (cmd-calib.c extends it). */
struct ssc_calib_res {
	struct ssc_calib_triad_out out[2];
	int n_out;
};

#endif
