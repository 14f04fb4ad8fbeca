/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-unit.h
 * @brief Units: parsing, SI conversion, dimensions.
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_UNIT_H
#define SSCOPE_UNIT_H

#include "sscope-quantity.h"

/** Standard gravity, m/s^2 (CGPM 1901): the "g" of units, data sheets and
 *  the calibration's default; the one definition in the tree. */
#define SSCOPE_UNIT_GRAVITY_STD 9.80665

#ifdef __cplusplus
extern "C" {
#endif

/** Base dimensions.  Angle is kept as a dimension so that rad/s is not Hz. */
enum sscope_unit_dim {
	SSCOPE_UNIT_DIM_LENGTH = 0, /**< metre */
	SSCOPE_UNIT_DIM_TIME,       /**< second */
	SSCOPE_UNIT_DIM_ANGLE,      /**< radian */
	SSCOPE_UNIT_DIM_TEMP,       /**< degree Celsius (kelvin for differences) */
	SSCOPE_UNIT_DIM_VOLTAGE,    /**< volt */
	SSCOPE_UNIT_DIM_COUNTS,     /**< converter counts (LSB) */
	SSCOPE_UNIT_DIM_COUNT       /**< number of base dimensions */
};

/**
 * A parsed unit: SI value = scale * value + offset.  The offset is non-zero
 * only for absolute temperatures given in kelvin or Fahrenheit (the library's
 * temperature unit is the degree Celsius).  Exponents are stored doubled so
 * that sqrt(h) is exact: dim2[SSCOPE_UNIT_DIM_TIME] == 1 means s^(1/2).
 */
struct sscope_unit {
	double scale;
	double offset;
	int8_t dim2[SSCOPE_UNIT_DIM_COUNT];
};

/**
 * Parse a unit expression such as "deg/s", "rad s^-1", "deg/sqrt(h)",
 * "deg/h/sqrt(h)", "ug/sqrt(Hz)", "mV/(deg/s)", "m/s^2" or "°C".
 * Products are written with '*', '·' or a space, quotients with '/', powers
 * with '^' (integer or n/2), and sqrt(...) or '√'.  An empty string or "1"
 * is dimensionless.
 * @param text  the expression (NUL-terminated).
 * @param unit  receives the result.
 * @param diag  optional; names the part not understood.
 * @return 0, or -EINVAL when some part is not a known unit or the syntax is
 *         wrong.
 */
int sscope_unit_parse(const char *text, struct sscope_unit *unit,
		      struct sscope_diag *diag);

/** @return true when @p a and @p b measure the same dimension. */
bool sscope_unit_compatible(const struct sscope_unit *a,
			    const struct sscope_unit *b);

/** @return @p value (in @p unit) expressed in SI. */
double sscope_unit_to_si(const struct sscope_unit *unit, double value);

/** @return the SI value @p si expressed in @p unit. */
double sscope_unit_from_si(const struct sscope_unit *unit, double si);

/**
 * Convert between two units.
 * @return 0, or -EDOM when the dimensions differ (out untouched).
 */
int sscope_unit_convert(double value, const struct sscope_unit *from,
			const struct sscope_unit *to, double *out);

/**
 * Convert a unit expression to another, both given as text: the usual way
 * to print an SI result in a conventional unit.
 * @return 0, -EINVAL for an unknown unit, -EDOM for incompatible units.
 */
int sscope_unit_convert_text(double value, const char *from, const char *to,
			     double *out);

/** @return the quantity measured by @p unit (SSCOPE_QUANTITY_UNKNOWN if none). */
enum sscope_quantity sscope_unit_quantity(const struct sscope_unit *unit);

/**
 * Write @p unit's SI form, e.g. "rad/s/sqrt(Hz)" or "m s^-2", into @p buf.
 * Angular-rate noise densities are written the way the field writes them
 * (rad/s/sqrt(Hz), m/s^2/sqrt(Hz)), other units as products of powers.
 * @return 0, or -ERANGE when @p len is too small (buf holds a truncation).
 */
int sscope_unit_si_string(const struct sscope_unit *unit, char *buf,
			  size_t len);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_UNIT_H */
