/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Noise-parameter files for estimators (noise-export.c): Kalibr imu.yaml,
 * OpenVINS kalibr_imu_chain.yaml and the imu_utils parameter YAML.
 */
#ifndef SSCOPE_NOISE_EXPORT_H
#define SSCOPE_NOISE_EXPORT_H

#include "sensorscope.h"
#include "sscope-allan.h"

/* one analysed channel */
struct ssc_noise_chan {
	const char *name;
	enum sscope_quantity q;            /* of the rate: gyro or accel */
	const struct sscope_noise_fit *fit; /* NULL when not fitted */
};

struct ssc_noise_export {
	const struct ssc_noise_chan *ch;
	size_t n;
	double rate_hz;
	double inflate;      /* multiplies every exported value */
	const char *source;  /* for the header comment */
	const char *topic;   /* ROS topic of the data, or NULL */
	const char *name;    /* sensor name (imu_utils), or NULL */
};

/* Each writes its file atomically; prints errors; returns an exit code. */
int ssc_export_kalibr(const char *cmd, const char *path,
		      const struct ssc_noise_export *e);
int ssc_export_openvins(const char *cmd, const char *path,
			const struct ssc_noise_export *e);
int ssc_export_imu_utils(const char *cmd, const char *path,
			 const struct ssc_noise_export *e);

#endif
