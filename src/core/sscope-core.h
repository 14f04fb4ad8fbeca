/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-core.h
 * @brief Library-wide names: version, error codes, diagnostics.
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_CORE_H
#define SSCOPE_CORE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** @return the library version, e.g. "0.1.0"; a static string. */
const char *sscope_version(void);

/**
 * Short description of an error code.
 * @param err a negative errno returned by this library (a positive value is
 *            accepted too).
 * @return a static string; never NULL.
 */
const char *sscope_strerror(int err);

/**
 * Human-readable detail of a failure: which file, line, column, key or unit
 * was at fault.  Functions that take a `struct sscope_diag *` fill it when
 * they fail (it may be NULL when the caller does not want the detail).
 */
struct sscope_diag {
	char msg[320]; /**< NUL-terminated; empty when nothing was said */
};

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_CORE_H */
