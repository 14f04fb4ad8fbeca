/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The `audit` command: another tool's IMU noise file (Kalibr imu.yaml,
 * OpenVINS kalibr_imu_chain.yaml, imu_utils' parameter YAML,
 * allan_variance_ros' imu.yaml or its printed summary) read by hand (flat
 * "key: value # comment" lines) and checked for the known convention
 * errors, each finding with its reason and the corrected value.
 */
#ifndef SSCOPE_WB_AUDIT_H
#define SSCOPE_WB_AUDIT_H

#include "workbench.h"

/* Audit @p path ("-": standard input) and present the findings (text or
 * JSON to the command's output).  @p rate_hz: the IMU's rate when the
 * file gives none (0: not given).  Returns an exit code: 0 the file was
 * read (findings or not; with @p strict, 1 when there are findings),
 * 1 a file that cannot be read or is no noise file this reads. */
int ssc_audit_run(const struct ssc_common *co, const char *path,
		  double rate_hz, bool strict);

#endif
