/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-datasheet.h
 * @brief Datasheet lines in IEEE Std 952 terms and back, and a record's
 *        verdict against them.
 *
 * A datasheet states a sensor's noise in one of several definitions; each
 * is named here with its source and turned into the IEEE Std 952-1997
 * (Annex C) term it measures.  U is the rate unit (rad/s for a gyro,
 * m/s^2 for an accelerometer); every value is SI.
 *
 * - noise density D, U/sqrt(Hz) (deg/s/sqrt(Hz), mg/sqrt(Hz),
 *   ug/sqrt(Hz)): N = D, the field's convention (IEEE 952's N, Allan
 *   deviation at 1 s; ARW [deg/sqrt(h)] = 60 D [deg/s/sqrt(Hz)]);
 * - angle / velocity random walk per sqrt(h): N itself, in other units;
 * - total rms noise over a stated noise bandwidth W (an ODR's Nyquist
 *   band ODR/2, or a filter's equivalent noise bandwidth): D = rms /
 *   sqrt(W), the datasheets' own relation (MPU-6000: 0.005 deg/s/sqrt(Hz)
 *   and 0.05 deg/s rms at 100 Hz);
 * - bias instability B, IEEE 952: the flicker coefficient, whose Allan
 *   deviation plateau is sqrt(2 ln2 / pi) B = 0.6643 B;
 * - in-run bias stability, the minimum of the Allan deviation (MEMS
 *   Industry Group "Standardized Sensor Performance Parameter
 *   Definitions", IEEE 2700; Sensonor, Analog Devices): B = min / 0.6643;
 * - rate random walk K, U/s/sqrt(Hz) (deg/h/sqrt(h));
 * - bias stability 10 s / 100 s of GJB 2426A (the Chinese military
 *   standard for fibre-optic gyros): the standard deviation (1 sigma) of
 *   consecutive non-overlapping 10 s (100 s) means of the output.  From
 *   N, B and K it is about the Allan deviation at that tau,
 *   sqrt(N^2/tau + 0.4413 B^2 + K^2 tau / 3): equal for white noise alone,
 *   larger in a long record with flicker or random walk (their standard
 *   deviation grows with the record), so it is a lower bound;
 * - run-to-run bias (bias repeatability, turn-on to turn-on, 1 sigma) and
 *   scale-factor error (ratio, from ppm or %): converted, but one static
 *   record cannot establish them.
 *
 * Verdicts are guard-banded by the interval of the measured value (ISO
 * 14253-1's rule for conformance): within spec only when the whole
 * interval lies below the limit, out of spec when the whole interval lies
 * above it, inconclusive otherwise.  A term the record does not resolve
 * has only an upper bound hi: within spec when hi is below the limit,
 * else inconclusive with that bound (never "0").
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_DATASHEET_H
#define SSCOPE_DATASHEET_H

#include "sscope-core.h"
#include "sscope-term.h"

#ifdef __cplusplus
extern "C" {
#endif

/** The datasheet lines known (INI keys in struct sscope_datasheet_info). */
enum sscope_datasheet_line {
	SSCOPE_DATASHEET_NOISE_DENSITY = 0, /**< D, U/sqrt(Hz) */
	SSCOPE_DATASHEET_RANDOM_WALK,       /**< ARW / VRW, U/sqrt(Hz) */
	SSCOPE_DATASHEET_RMS_NOISE,         /**< rms over a bandwidth, U */
	SSCOPE_DATASHEET_BIAS_INSTABILITY,  /**< IEEE 952 B, U */
	SSCOPE_DATASHEET_ALLAN_MINIMUM,     /**< in-run bias stability, U */
	SSCOPE_DATASHEET_RATE_RANDOM_WALK,  /**< K, U/s/sqrt(Hz) */
	SSCOPE_DATASHEET_GJB_10S,           /**< 1 sigma of 10 s means, U */
	SSCOPE_DATASHEET_GJB_100S,          /**< 1 sigma of 100 s means, U */
	SSCOPE_DATASHEET_RUN_TO_RUN_BIAS,   /**< bias repeatability, U */
	SSCOPE_DATASHEET_SCALE_FACTOR,      /**< scale-factor error, ratio */
	SSCOPE_DATASHEET_BIAS_OFFSET,       /**< bias (zero-rate / zero-g
						 offset), a magnitude, U */
	SSCOPE_DATASHEET_BIAS_TEMPCO,       /**< bias temperature sensitivity,
						 a magnitude, U/K */
	SSCOPE_DATASHEET_RATE_RAMP,         /**< IEEE 952 rate ramp R: the
						 bias's drift, a magnitude,
						 U/s */
	SSCOPE_DATASHEET_LINE_COUNT_        /**< number of lines (not one) */
};

/** What a line is (static strings). */
struct sscope_datasheet_info {
	const char *key;        /**< INI key, e.g. "noise_density" */
	const char *name;       /**< "noise density" */
	const char *definition; /**< the definition and its source */
	const char *si_suffix;  /**< SI unit after U ("/sqrt(Hz)"), or
				     "1" for a ratio */
	enum sscope_term term;  /**< the IEEE 952 term it gives, or
				     SSCOPE_TERM_COUNT_ for none */
	double tau_s;           /**< averaging time of the GJB lines, s
				     (0 for the others) */
	bool magnitude;         /**< a limit on the magnitude of a signed
				     value (+-): bias, its drift and its
				     temperature sensitivity */
};

/** @return the description of @p line, or NULL when out of range. */
const struct sscope_datasheet_info *
sscope_datasheet_info(enum sscope_datasheet_line line);

/** @return the line whose key is @p key (case-sensitive), or -1. */
int sscope_datasheet_line_by_key(const char *key);

/** sqrt(2 ln2 / pi) = 0.664282...: the Allan deviation plateau of flicker
 *  rate noise per unit B (IEEE 952 Annex C). */
#define SSCOPE_DATASHEET_FLICKER_PLATEAU 0.66428247026796010

/**
 * The factor f with line value = f * term (the IEEE 952 term of the line:
 * N, B or K): 1 for the density, random walk, B and K lines; sqrt(W) for
 * the rms noise over the noise bandwidth W; 0.6643 for the Allan minimum.
 * @param line          the line.
 * @param bandwidth_hz  W for SSCOPE_DATASHEET_RMS_NOISE (ignored else).
 * @param f             receives the factor.
 * @return 0; -EINVAL for a line without a term (GJB, run-to-run, scale
 *         factor) or a bandwidth not positive and finite for rms noise.
 */
int sscope_datasheet_factor(enum sscope_datasheet_line line,
			    double bandwidth_hz, double *f);

/**
 * The Allan deviation at @p tau_s of the terms N, B, K (U/sqrt(Hz), U,
 * U/s/sqrt(Hz); NaN counts as 0): the GJB bias stability the terms imply
 * at tau, a lower bound (see the file comment).
 * @return the value, U; NaN when tau_s is not positive or every term is
 *         NaN.
 */
double sscope_datasheet_gjb_from_terms(double n, double b, double k,
				       double tau_s);

/** The GJB bias stability of a record: 1 sigma of non-overlapping means. */
struct sscope_datasheet_gjb {
	double value;   /**< sample standard deviation of the means, U */
	double lo, hi;  /**< its interval at the level asked (chi-squared
			     with n_means - 1 degrees of freedom) */
	size_t n_means; /**< means used */
	size_t m;       /**< samples per mean (round(tau * rate)) */
};

/**
 * The 1 sigma of consecutive non-overlapping tau-means of a record (GJB
 * 2426A's bias stability): means of m = round(tau * rate) samples (a
 * trailing partial block dropped), their sample standard deviation s
 * (divisor n_means - 1), and s's interval at @p level from the
 * chi-squared distribution of (n_means - 1) s^2 / sigma^2.
 * @param x, stride, n  the record (rate, U).
 * @param rate_hz       sample rate, Hz.
 * @param tau_s         averaging time, s.
 * @param level         confidence level in (0, 1).
 * @param out           receives the result.
 * @param diag          optional detail.
 * @return 0; -EINVAL (NULL, rate, tau or level out of range); -EDOM
 *         (fewer than two means, or a sample not finite).
 */
int sscope_datasheet_gjb(const double *x, size_t stride, size_t n,
			 double rate_hz, double tau_s, double level,
			 struct sscope_datasheet_gjb *out,
			 struct sscope_diag *diag);

/** A verdict against a limit. */
enum sscope_datasheet_verdict {
	SSCOPE_DATASHEET_INCONCLUSIVE = 0, /**< the interval holds the limit,
					        or nothing was measured */
	SSCOPE_DATASHEET_WITHIN,           /**< the whole interval below */
	SSCOPE_DATASHEET_OUT               /**< the whole interval above */
};

/** @return "within spec", "out of spec" or "inconclusive" (static). */
const char *sscope_datasheet_verdict_name(enum sscope_datasheet_verdict v);

/**
 * The guard-banded verdict of a measured interval [lo, hi] against an
 * upper @p limit: WITHIN when hi < limit, OUT when lo > limit, else
 * INCONCLUSIVE (also when any is NaN).  For an upper bound alone pass
 * lo = 0.
 */
enum sscope_datasheet_verdict
sscope_datasheet_verdict(double lo, double hi, double limit);

/**
 * The verdict of a signed value's interval [lo, hi] against a limit on
 * its magnitude, +-@p limit: WITHIN when -limit < lo and hi < limit, OUT
 * when the interval lies wholly above limit or below -limit, else
 * INCONCLUSIVE (also when any is NaN).
 */
enum sscope_datasheet_verdict
sscope_datasheet_verdict_magnitude(double lo, double hi, double limit);

/** One line of a datasheet, SI. */
struct sscope_datasheet_spec {
	enum sscope_datasheet_line line;
	double value;        /**< the limit, SI (U for rate lines) */
	double bandwidth_hz; /**< noise bandwidth of an rms-noise line */
};

/** The record's measurement of one line and the verdict. */
struct sscope_datasheet_check {
	enum sscope_datasheet_line line;
	double limit;   /**< the line's value (as given) */
	double value;   /**< measured, in the line's definition; NaN when
			     the record does not establish it */
	double lo, hi;  /**< interval at the level; lo NaN and hi the upper
			     bound when only a bound is known; both NaN
			     when nothing is */
	bool bound;     /**< only an upper bound (term not resolved) */
	enum sscope_datasheet_verdict verdict;
	const char *why; /**< why nothing or only a bound was measured
			      (static; NULL when measured) */
	bool fit_rejected; /**< a term line whose noise fit the chi-squared
			        test rejects at p < 0.01
			        (sscope_noise_fit_rejected()): the value and
			        its interval are indicative only, the verdict
			        inconclusive (as on a moving record) */
};

/** Options of sscope_datasheet_check(); zero means the default. */
struct sscope_datasheet_opts {
	double level; /**< confidence level of the guard band (default 0.99) */
};

/**
 * Check a stationary record against datasheet lines.  The N, B and K
 * lines take the IEEE 952 term from the noise fit of the overlapping
 * Allan deviation (sscope_allan_analyze(), dense grid, intervals at the
 * level), scaled to the line's definition (sscope_datasheet_factor());
 * the Allan-minimum line takes the least point of that Allan deviation
 * with its interval, a bound only when the curve still falls at the
 * longest tau; the GJB lines sscope_datasheet_gjb().  Run-to-run bias and
 * scale factor are inconclusive with a reason.
 * @param x, stride, n, rate_hz  the record (U, Hz).
 * @param spec     the lines (limits, SI).
 * @param n_spec   number of lines.
 * @param opts     options (NULL: defaults).
 * @param out      receives n_spec results (caller's array).
 * @param diag     optional detail.
 * @return 0; -EINVAL (NULL, level outside (0, 1), a line out of range);
 *         -EDOM (a record too short for any Allan deviation); -ENOMEM.
 */
int sscope_datasheet_check(const double *x, size_t stride, size_t n,
			   double rate_hz,
			   const struct sscope_datasheet_spec *spec,
			   size_t n_spec,
			   const struct sscope_datasheet_opts *opts,
			   struct sscope_datasheet_check *out,
			   struct sscope_diag *diag);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_DATASHEET_H */
