/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-quantity.h
 * @brief What a unit measures (angular rate, acceleration, ...).
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_QUANTITY_H
#define SSCOPE_QUANTITY_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

struct sscope_unit;

/** What a unit measures, so reports can choose conventional units. */
enum sscope_quantity {
	SSCOPE_QUANTITY_UNKNOWN = 0,   /**< no unit, or a combination not listed */
	SSCOPE_QUANTITY_DIMENSIONLESS, /**< ratio, ppm, % */
	SSCOPE_QUANTITY_COUNTS,        /**< raw converter codes */
	SSCOPE_QUANTITY_ANGULAR_RATE,  /**< rad/s */
	SSCOPE_QUANTITY_ACCELERATION,  /**< m/s^2 */
	SSCOPE_QUANTITY_ANGLE,         /**< rad */
	SSCOPE_QUANTITY_VELOCITY,      /**< m/s */
	SSCOPE_QUANTITY_LENGTH,        /**< m */
	SSCOPE_QUANTITY_TIME,          /**< s */
	SSCOPE_QUANTITY_FREQUENCY,     /**< Hz */
	SSCOPE_QUANTITY_TEMPERATURE,   /**< degC */
	SSCOPE_QUANTITY_VOLTAGE,       /**< V */
	SSCOPE_QUANTITY_ANGULAR_ACCEL, /**< rad/s^2 */
	SSCOPE_QUANTITY_JERK,          /**< m/s^3 */
	SSCOPE_QUANTITY_COUNT_         /**< number of quantities (not a quantity) */
};

/** @return a short name of @p q ("angular rate", ...); static string. */
const char *sscope_quantity_name(enum sscope_quantity q);

/**
 * @return the SI unit of @p q as text ("rad/s", "m/s^2", "degC", ...), or ""
 *         for unknown quantities; static string.
 */
const char *sscope_quantity_si_unit(enum sscope_quantity q);

/**
 * Parse a quantity with its unit, e.g. "0.15 deg/sqrt(h)" or "-100 deg/s".
 * @param text      the text.
 * @param value_si  receives the value in SI.
 * @param unit      receives the unit as written (may be NULL).  A number
 *                  without a unit yields a dimensionless unit.
 * @param diag      optional detail.
 * @return 0, or -EINVAL (not a number, or unknown unit).
 */
int sscope_quantity_parse(const char *text, double *value_si,
			  struct sscope_unit *unit, struct sscope_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_QUANTITY_H */
