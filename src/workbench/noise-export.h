/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The export options of `allan` (noise-export.c): --export TARGET[:FILE]
 * and its aliases --kalibr, --imu-utils, --openvins; each file made by the
 * library's sscope_export() (sscope-export.h) and written atomically.
 */
#ifndef SSCOPE_NOISE_EXPORT_H
#define SSCOPE_NOISE_EXPORT_H

#include <stdbool.h>
#include <stddef.h>

struct ssc_common;
struct ssc_allan_res;

/* one requested file: --export TARGET[:FILE] or an alias option */
struct ssc_export_req {
	const char *target; /* the library's name, "kalibr" */
	char option[48];    /* for messages: "--kalibr", "--export vins" */
	const char *path;
};

#define SSC_EXPORT_MAX 16

/* Parse TARGET[:FILE] (opt: the option's name without "--": "export",
 * "kalibr", "imu-utils", "openvins") and append it to req[*n]; a usage
 * error (exit 2) on an unknown target, a repeated file or too many
 * files. */
int ssc_export_parse(const char *opt, const char *arg,
		     struct ssc_export_req *req, size_t *n);

/* Write every requested file from the channels of an allan result. */
int ssc_export_allan(const struct ssc_common *co,
		     const struct ssc_allan_res *R,
		     const struct ssc_export_req *req, size_t n,
		     double inflate, bool force);

#endif
