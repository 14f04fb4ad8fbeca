/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-sensor.h
 * @brief Gyro and accelerometer specifications.
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_SENSOR_H
#define SSCOPE_SENSOR_H

#include "sscope-quantity.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Fields present in a struct sscope_sensor_spec (bit mask). */
enum {
	SSCOPE_SENSOR_HAS_RANGE = 1u << 0,
	SSCOPE_SENSOR_HAS_Q = 1u << 1,
	SSCOPE_SENSOR_HAS_N = 1u << 2,
	SSCOPE_SENSOR_HAS_B = 1u << 3,
	SSCOPE_SENSOR_HAS_K = 1u << 4,
	SSCOPE_SENSOR_HAS_R = 1u << 5,
	SSCOPE_SENSOR_HAS_BIAS = 1u << 6,
	SSCOPE_SENSOR_HAS_SF = 1u << 7,
	SSCOPE_SENSOR_HAS_TEMPCO = 1u << 8,
	SSCOPE_SENSOR_HAS_TEMPS = 1u << 9,
	SSCOPE_SENSOR_HAS_SENSITIVITY = 1u << 10,
	SSCOPE_SENSOR_HAS_ZERO = 1u << 11,
	SSCOPE_SENSOR_HAS_BANDWIDTH = 1u << 12,
};

/**
 * A gyro or accelerometer specification, SI throughout.  With U the rate
 * unit (rad/s for a gyro, m/s^2 for an accelerometer): range, bias and the
 * bias instability B are in U; quantization Q in U*s; noise density N
 * (angle/velocity random walk) in U/sqrt(Hz); rate random walk K in
 * U/s/sqrt(Hz); rate ramp R in U/s; bias_tempco in U/degC; sensitivity in
 * V per U (analog outputs).  IEEE Std 952-1997 Annex C terms.
 */
struct sscope_sensor_spec {
	char name[64];
	enum sscope_quantity quantity; /**< ANGULAR_RATE or ACCELERATION */
	unsigned has;                  /**< SSCOPE_SENSOR_HAS_* of fields given */
	double range;                  /**< +- full scale, U */
	double q, n, b, k, r;          /**< IEEE 952 noise terms */
	double bias;                   /**< constant bias, U */
	double scale_factor_error;     /**< ratio (ppm * 1e-6) */
	double bias_tempco;            /**< U per degC */
	double temp_min_degc, temp_max_degc;
	double sensitivity;            /**< V per U (analog output) */
	double zero_output_v;          /**< output at zero input, V */
	double bandwidth_hz;           /**< -3 dB bandwidth of the output */
	int filter_order;              /**< order of that filter (default 1) */
};

/** @return the keys a [sensor] section may hold (NULL-terminated). */
const char *const *sscope_sensor_spec_keys(void);

/** Load the [sensor] section of a file.  @return as above, -errno. */
int sscope_sensor_spec_load(const char *path, struct sscope_sensor_spec *spec,
			    struct sscope_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_SENSOR_H */
