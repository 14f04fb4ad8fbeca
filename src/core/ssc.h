/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Functions of the library shared with the command and the tests but not
 * part of the public API: not installed, not exported from the shared
 * library (the ssc_ prefix).  The INI parser lives here: scenes and
 * specification files are the command's formats, not the library's.
 */
#ifndef SSC_SSC_H
#define SSC_SSC_H

#include "sscope-core.h"
#include "sscope-sensor.h"

struct sscope_adc_spec;

/* Function clones for the processor found at load time (GCC on x86-64
 * glibc): SSC_TARGET_CLONES("avx2", "default").  None under
 * ThreadSanitizer, whose runtime is not up yet when the loader runs the
 * clones' resolvers. */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) &&      \
	defined(__GLIBC__) && defined(__has_attribute) &&                  \
	!defined(__SANITIZE_THREAD__)
#if __has_attribute(target_clones)
#define SSC_TARGET_CLONES(...) __attribute__((target_clones(__VA_ARGS__)))
#endif
#endif
#ifndef SSC_TARGET_CLONES
#define SSC_TARGET_CLONES(...)
#endif

/* pi, once for the whole tree (files of tests that define PI alike may
 * keep doing so: the same definition) */
#define PI 3.14159265358979323846

/* qsort() comparison of doubles, ascending (NaN compares equal to all) */
int ssc_cmp_double(const void *a, const void *b);

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Parse a decimal floating-point number from [p, end), correctly rounded
 * (bit-identical to strtod in the C locale).  Accepts an optional sign,
 * digits with an optional '.', an optional exponent, and "nan"/"inf"
 * (any case).  Leading blanks are not skipped.
 * @param p, end  the text (need not be NUL-terminated).
 * @param out     receives the value.
 * @return the number of bytes consumed, or 0 when no number starts at @p p.
 */
size_t ssc_parse_double(const char *p, const char *end, double *out);

/** A parsed INI file: [sections] of "key = value" lines (keys and section
 *  names case-insensitive; '#' and ';' comments). */
struct ssc_ini;

/**
 * Parse INI text.
 * @param name  file name used in messages.
 * @return 0; -EBADMSG (syntax: the line is named), -ENOMEM.
 */
int ssc_ini_parse(struct ssc_ini **ini, const char *text, size_t len,
		  const char *name, struct sscope_diag *diag);

/** Read and parse an INI file.  @return as ssc_ini_parse(), -errno. */
int ssc_ini_load(struct ssc_ini **ini, const char *path,
		 struct sscope_diag *diag);

/** Free (NULL is ignored). */
void ssc_ini_free(struct ssc_ini *ini);

/** @return the file name given to the parser (owned by @p ini). */
const char *ssc_ini_name(const struct ssc_ini *ini);

size_t ssc_ini_n_sections(const struct ssc_ini *ini);

/** @return the name of section @p i (line number in *line), or NULL. */
const char *ssc_ini_section(const struct ssc_ini *ini, size_t i,
			    size_t *line);

bool ssc_ini_has_section(const struct ssc_ini *ini, const char *section);

size_t ssc_ini_n_keys(const struct ssc_ini *ini, const char *section);

/** @return key @p k of @p section with its value and line, or NULL. */
const char *ssc_ini_key(const struct ssc_ini *ini, const char *section,
			size_t k, const char **value, size_t *line);

/** @return the value of @p key in @p section (NULL when absent). */
const char *ssc_ini_get(const struct ssc_ini *ini, const char *section,
			const char *key, size_t *line);

/**
 * Refuse keys not in @p allowed (a NULL-terminated list).
 * @return 0, or -EINVAL naming the file, line and key.
 */
int ssc_ini_check_keys(const struct ssc_ini *ini, const char *section,
		       const char *const *allowed, struct sscope_diag *diag);

/**
 * A value with an optional unit, converted to SI.  A bare number is taken
 * in the SI unit @p si_unit.
 * @return 0; -ENOENT when the key is absent (diag untouched); -EINVAL for a
 *         malformed value or a unit of another dimension (file, line, key).
 */
int ssc_ini_quantity(const struct ssc_ini *ini, const char *section,
		     const char *key, const char *si_unit, double *out,
		     struct sscope_diag *diag);

/** An integer in [lo, hi].  @return 0, -ENOENT, -EINVAL. */
int ssc_ini_integer(const struct ssc_ini *ini, const char *section,
		    const char *key, long lo, long hi, long *out,
		    struct sscope_diag *diag);

/**
 * Read a sensor specification from section @p section of @p ini.  The
 * quantity (gyro or accelerometer) follows from the units of range or
 * noise_density; every value with a unit of the wrong dimension, every
 * unknown key and every negative magnitude is refused with file, line and
 * key.  A bare scale_factor_error is in ppm.
 * @return 0 or -EINVAL.
 */
int ssc_sensor_spec_from_ini(const struct ssc_ini *ini,
			     const char *section,
			     struct sscope_sensor_spec *spec,
			     struct sscope_diag *diag);

/**
 * Read a converter spec from section @p section of @p ini.  Keys: name,
 * bits, range ("LO:HI UNIT"), rate, noise (rms, e.g. "30 uV") or snr (dB)
 * or enob, inl, dnl (LSB), offset, gain_error (ppm), offset_drift
 * ("2 uV/degC"), gain_drift (ppm/degC), ref_temp, reference
 * (absolute|ratiometric), mode (round|integrate), coding, oversample
 * (conversions averaged per output sample), inl_profile (a file of 2^bits
 * INL values, stored as written; not with inl or dnl, which it defines,
 * and only for bits <= SSCOPE_ADC_TABLE_BITS).  Every error
 * names the file and the key ("A.ini: [adc] bits: missing").
 * @return 0 or -EINVAL.
 */
int ssc_adc_spec_from_ini(const struct ssc_ini *ini, const char *section,
			  struct sscope_adc_spec *spec,
			  struct sscope_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* SSC_SSC_H */
