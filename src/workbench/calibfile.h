/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Calibration files (JSON) of `sensorscope calib`, applied by the shared
 * option --calibration FILE (see calibfile.c for the format).
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

#endif
