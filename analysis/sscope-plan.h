/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-plan.h
 * @brief Recording planner: how long a static record must be for the noise
 *        fit (sscope_noise_fit()) to show a term present and resolve it to a
 *        wanted relative half-width, with a stated probability.
 *
 * The prediction is analytic, from the model alone (no simulation): the
 * record's OADEV points on the dense tau grid, their covariance under the
 * model (sscope_noise_avar_cov()), then
 * - presence: the fit's selection test of the term (generalised least
 *   squares of the model's terms, z = square / its sd without the term,
 *   threshold detect_sigma) passes with probability
 *   Phi((s - zsel sd0) / sd1), s the true square, sd1 its GLS sd, sd0 its
 *   sd were the term absent;
 * - precision: the fit's interval is a Neyman construction on its
 *   bootstrap (noisefit.c), modelled here with the sd s(b) of the square's
 *   weighted least-squares estimate (every term free) at a tested value b,
 *   the other terms restricted to b as the bootstrap does (the weighted
 *   fit of the others with the square held at b, clamped at 0), and a
 *   Pearson type III margin of the estimate's skewness (the AVAR points'
 *   Gamma-like margins); its lower end is 0 (unbounded relative width)
 *   while b = 0 still accepts the estimate.  The width falls with the
 *   estimate x: it is below the target when x exceeds the x* where it
 *   equals the target, with probability Phi((s - x*) / s(s)), averaged
 *   over two scenarios of the terms absent from the model (estimated
 *   1 sd above 0 and restricted, or held at 0);
 * - both: the two events follow the same estimate, so the probability of
 *   both is taken as the smaller of the two.
 * The fit's own intervals come from a parametric bootstrap and its weights
 * from the points' EDF; the normal approximations here are checked against
 * simulated and fitted records in make bench (tests/bench/README.md).
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_PLAN_H
#define SSCOPE_PLAN_H

#include "sscope-core.h"
#include "sscope-term.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Options of the planner.  Zero-initialised = 68.27 % intervals, 90 %
 *  probability, the fit's 3-sd presence test, lengths up to 30 days. */
struct sscope_plan_opts {
	double ci_level;     /**< level of the interval; 0 selects 0.6827 */
	double probability;  /**< wanted probability; 0 selects 0.9 */
	double detect_sigma; /**< presence threshold, sd; 0 selects 3 */
	double max_length_s; /**< longest record considered, s; 0: 30 days */
};

/** The prediction for one record length. */
struct sscope_plan_point {
	double length_s;       /**< record length, s */
	double p_present;      /**< probability the term is shown present */
	double p_width;        /**< probability its relative half-width is
				    at most the target */
	double probability;    /**< probability of both (the smaller) */
	double rel_half_width; /**< relative half-width at the true value
				    (INFINITY when not resolved there) */
};

/**
 * Predict, for a record of @p length_s at @p rate_hz of a sensor with the
 * IEEE 952 coefficients @p coef, the fit's outcome for @p term.
 * @param coef        Q, N, B, K, R, SI as sscope_noise_avar() (>= 0).
 * @param rate_hz     sample rate, Hz (> 0).
 * @param length_s    record length, s (> 0).
 * @param term        the term (SSCOPE_TERM_Q .. SSCOPE_TERM_R).
 * @param target      wanted relative half-width of its interval (> 0;
 *                    0.25 for 25 %).
 * @param opts        options (NULL: defaults).
 * @param out         receives the prediction.  A term that is 0 in the
 *                    model, or a record too short for the fit (fewer than
 *                    6 tau points), gets probabilities 0.
 * @return 0; -EINVAL (NULL, a negative or non-finite coefficient, a bad
 *         rate, length, term, target or option); -EDOM (the fit's design is
 *         singular at this length); -ENOMEM.
 */
int sscope_plan_predict(const double coef[5], double rate_hz, double length_s,
			enum sscope_term term, double target,
			const struct sscope_plan_opts *opts,
			struct sscope_plan_point *out);

/**
 * The shortest record length whose predicted probability
 * (sscope_plan_predict()) reaches opts->probability, to 1 %: lengths from
 * 32 samples up in octaves to the first that reaches it, then bisection on
 * the logarithm of the length.
 * @param length_s  receives the length, s; INFINITY when the term is 0 in
 *                  the model or the probability is not reached within
 *                  opts->max_length_s.
 * @return as sscope_plan_predict().
 */
int sscope_plan_needed(const double coef[5], double rate_hz,
		       enum sscope_term term, double target,
		       const struct sscope_plan_opts *opts, double *length_s);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_PLAN_H */
