/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Calibration files (JSON) of `sensorscope calib`, applied by the shared
 * option --calibration FILE (see calibfile.c for the format), and the
 * calib result's triads: their JSON written and read back.
 */
#ifndef SSCOPE_CALIBFILE_H
#define SSCOPE_CALIBFILE_H

#include "workbench.h"

/* SI scale of a unit label; 1 for "" */
double ssc_calfile_unit_scale(const char *unit);
/* The file's triad object (parameters converted to input units). */
json_t *ssc_calfile_triad_json(const struct sscope_calib_file_triad *t);
/* Write a calibration file atomically; prints errors, returns exit code. */
int ssc_calfile_write(const struct ssc_common *co, const char *path,
		      const struct sscope_calib_file_triad *t, size_t n);
/* Read one; *out is freed by the caller. */
int ssc_calfile_read(const char *cmd, const char *path,
		     struct sscope_calib_file_triad **out, size_t *n_out);

/* ------------------------------------------------ calib results */

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

/* The JSON of a calibrated triad as 'calib' writes it: the calibration
 * file's triad (ssc_calfile_triad_json) with the uncertainties, the error
 * model, the noise density and the grade .  A new reference. */
json_t *ssc_calib_triad_out_json(const struct ssc_calib_triad_out *o);

/* The calib stage's result starts with this (cmd-calib.c extends it). */
struct ssc_calib_res {
	struct ssc_calib_triad_out out[2];
	int n_out;
};

/* The error model (when input and output have one dimension) and the
 * class of the sensor of @p o, from its correction, units and noise
 * density. */
void ssc_calib_triad_finish(struct ssc_calib_triad_out *o);

/*
 * The triads of a saved 'calib' JSON result (ssc_calib_triad_out_json()
 * of each, under "triads") as the calib stage holds them: SI values, the
 * error model and class derived again by ssc_calib_triad_finish().  The
 * one reader of that JSON (budget --result, navsim --from-calib).
 * Returns 0; -EINVAL when @p root is not a calib result, or a triad is
 * malformed; -E2BIG past the triads a result can hold (out is then
 * filled as far as it goes).
 */
int ssc_calib_res_from_json(const json_t *root, struct ssc_calib_res *out);

#endif
