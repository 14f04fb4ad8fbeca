/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-term.h
 * @brief The IEEE Std 952 noise terms and their conventional units.
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_TERM_H
#define SSCOPE_TERM_H

#include "sscope-quantity.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Terms of the IEEE 952 error model and related figures, for units. */
enum sscope_term {
	SSCOPE_TERM_Q = 0, /**< quantization (angle / velocity) */
	SSCOPE_TERM_N,     /**< angle / velocity random walk */
	SSCOPE_TERM_B,     /**< bias instability */
	SSCOPE_TERM_K,     /**< rate random walk */
	SSCOPE_TERM_R,     /**< rate ramp */
	SSCOPE_TERM_RATE,  /**< the measured quantity itself (bias, range) */
	SSCOPE_TERM_COUNT_
};

/**
 * Conventional unit of a term for gyros (deg/sqrt(h), deg/h, ...) and
 * accelerometers (m/s/sqrt(h), ug, ...).
 * @return a static string, or NULL for other quantities (use the data's
 *         own unit then).
 */
const char *sscope_term_unit(enum sscope_quantity q, enum sscope_term t);

/**
 * SI unit of a term as the JSON contract writes it: Q rad, N
 * rad/s/sqrt(Hz), B rad/s, K rad/s^2/sqrt(Hz), R rad/s^2 for angular rate;
 * m/s, m/s^2/sqrt(Hz), m/s^2, m/s^3/sqrt(Hz), m/s^3 for acceleration.
 * @return a static string, or NULL for other quantities.
 */
const char *sscope_term_si_unit(enum sscope_quantity q, enum sscope_term t);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_TERM_H */
