/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-export.h
 * Noise-parameter files for the estimators and simulators that read them
 * (Kalibr, OpenVINS, imu_utils, VINS-Mono/Fusion, ORB-SLAM3, Basalt,
 * GTSAM, MATLAB imuSensor, gnss-ins-sim, Gazebo), from IEEE 952 fits.
 *
 * Each file states its convention (continuous or discrete, units, what
 * "random walk" means there) in a leading comment.  Every file goes
 * through one gate: a value an adequacy finding of severity doubt or
 * invalid concerns refuses the file unless forced (then it is marked
 * beside the value); a term the record does not establish is written as
 * its upper bound, marked, with a warning; no value is ever written as 0.
 */
#ifndef SSCOPE_EXPORT_H
#define SSCOPE_EXPORT_H

#include <stdbool.h>
#include <stddef.h>

#include "sscope-core.h"
#include "sscope-quantity.h"
#include "sscope-noise.h"
#include "sscope-adequacy.h"

/** One analysed channel: its fit and the adequacy check of that fit. */
struct sscope_export_chan {
	const char *name;                      /**< "gx" */
	enum sscope_quantity quantity;         /**< angular rate or acceleration
						    (others are not exported) */
	const struct sscope_noise_fit *fit;    /**< NULL: not fitted */
	const struct sscope_adequacy *adequacy; /**< NULL: not checked */
};

/** What the file says about its data.  A zero struct is the defaults. */
struct sscope_export_opts {
	double rate_hz;      /**< sample rate, Hz (required) */
	double inflate;      /**< multiplies every value; 0 means 1 */
	const char *source;  /**< the data, for the header ("imu.bag"); NULL "data" */
	const char *topic;   /**< ROS topic of the data, or NULL */
	const char *sensor_name; /**< imu_utils' name, or NULL ("imu") */
	double duration_s;   /**< the longest channel's record, s (0: unknown) */
	bool force;          /**< write values the adequacy check doubts */
};

/** A written file. */
struct sscope_export_file {
	char *text;      /**< the file's bytes, NUL-terminated */
	size_t len;      /**< strlen(text) */
	char *warnings;  /**< one line per warning ('\n'-ended), or NULL */
	bool forcible;   /**< refused (-EDOM) only for doubtful values: force
			      would write it */
};

/** The i-th target's name ("kalibr", ...); NULL past the last. */
const char *sscope_export_target(size_t i);

/** The target's name as sscope_export_target() gives it ("imu-utils" is
 *  "imu_utils": '-' and '_' are the same in names); NULL when unknown. */
const char *sscope_export_name(const char *target);

/** The file a target is written to by default ("imu.yaml"); NULL for an
 *  unknown target. */
const char *sscope_export_default_file(const char *target);

/** The file of one target from the channels of one sensor record.
 *  Returns 0 (out->text set), -EINVAL (an unknown target, no rate),
 *  -EDOM (the gate refuses: the reason in diag, one line; out->forcible
 *  when force would write it) or -ENOMEM.  Free with
 *  sscope_export_file_free(). */
int sscope_export(const char *target, const struct sscope_export_chan *ch,
		  size_t n, const struct sscope_export_opts *opts,
		  struct sscope_export_file *out, struct sscope_diag *diag);

/** Free what sscope_export() put in f (f itself is the caller's). */
void sscope_export_file_free(struct sscope_export_file *f);

#endif
