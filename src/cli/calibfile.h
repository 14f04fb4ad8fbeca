/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Calibration files (JSON) of `sensorscope calib`, applied by the shared
 * option --calibration FILE (see calibfile.c for the format).
 */
#ifndef SSCOPE_CALIBFILE_H
#define SSCOPE_CALIBFILE_H

#include "cli.h"

/* One triad of a calibration file.  The parameters in c are in the units
 * the capture holds the data in: SI of input_unit ("" for raw values). */
struct ssc_caltriad {
	char kind[8];              /* "accel" or "gyro" */
	char channels[3][64];
	char accel_channels[3][64]; /* for the g-sensitivity term */
	char input_unit[32];
	char output_unit[32];
	struct sscope_calib_triad c;
};

/* SI scale of a unit label; 1 for "" */
double ssc_calfile_unit_scale(const char *unit);
/* The file's triad object (parameters converted to input units). */
json_t *ssc_calfile_triad_json(const struct ssc_caltriad *t);
/* Write a calibration file atomically; prints errors, returns exit code. */
int ssc_calfile_write(const struct ssc_common *co, const char *path,
		      const struct ssc_caltriad *t, size_t n);
/* Read one; *out is freed by the caller. */
int ssc_calfile_read(const char *cmd, const char *path,
		     struct ssc_caltriad **out, size_t *n_out);

#endif
