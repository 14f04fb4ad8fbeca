/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-adequacy.h
 * @brief What a record can and cannot support: the adequacy check of an
 *        IEEE 952 noise fit (is the record still, long enough for each
 *        requested term, described by the fit, stationary), with the
 *        dynamic Allan deviation (DAVAR) map over time and tau.
 *
 * One check, used by every consumer of noise terms (allan, report, run,
 * the exporters, Python): each finding is one line that names the cause,
 * the time or tau range at fault and what to do, with a severity that
 * says whether the numbers stand (a note), are only bounds, are in doubt,
 * or are not valid at all (exports refuse them).
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_ADEQUACY_H
#define SSCOPE_ADEQUACY_H

#include "sscope-core.h"
#include "sscope-noise.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Cause of a finding. */
enum sscope_adequacy_cause {
	SSCOPE_ADEQUACY_MOVES = 0,    /**< the record is not still */
	SSCOPE_ADEQUACY_NO_FIT,       /**< no noise fit to judge */
	SSCOPE_ADEQUACY_FIT_REJECTED, /**< the five-term model does not describe
				       the record (chi-squared test) */
	SSCOPE_ADEQUACY_SHORT,        /**< a requested term is not established */
	SSCOPE_ADEQUACY_WARMUP,       /**< a transient at the start */
	SSCOPE_ADEQUACY_STEP,         /**< a bias step */
	SSCOPE_ADEQUACY_TEMPERATURE,  /**< the rate follows the temperature */
	SSCOPE_ADEQUACY_RAMP,         /**< a rate ramp over the record */
	SSCOPE_ADEQUACY_UNCHECKED,    /**< a test could not run (too short, gaps) */
	SSCOPE_ADEQUACY_CAUSE_COUNT_
};

/** How much a finding matters, in increasing order. */
enum sscope_adequacy_severity {
	SSCOPE_ADEQUACY_NOTE = 0, /**< information: the numbers stand */
	SSCOPE_ADEQUACY_BOUND,    /**< a term is only bounded, not measured */
	SSCOPE_ADEQUACY_DOUBT,    /**< the terms named are biased by it */
	SSCOPE_ADEQUACY_INVALID   /**< the noise terms are not valid */
};

/** One finding. */
struct sscope_adequacy_finding {
	enum sscope_adequacy_cause cause;
	enum sscope_adequacy_severity severity;
	unsigned terms;     /**< terms it concerns: bits (1u << SSCOPE_TERM_*) */
	double t_start_s, t_end_s;   /**< time range at fault, s from the
					  first sample (NaN: none) */
	double tau_min_s, tau_max_s; /**< tau range at fault, s (NaN: none) */
	double statistic;   /**< the test's statistic (contrast, |t|, F,
				 chi-squared; NaN: none) */
	double p_value;     /**< its p-value, for the largest statistic over
				 the candidates tried (NaN: none) */
	double action_s;    /**< the time of the action: cut the first
				 action_s seconds (warm-up), cut at it
				 (step), record at least it (short); NaN */
	char message[400];  /**< one line: cause, range, what to do */
};

/** Options.  Zero-initialise, then set rate_hz. */
struct sscope_adequacy_opts {
	double rate_hz;          /**< sample rate, Hz */
	/** the record is an angle (integrated rate): it is differenced */
	bool angle;
	/** SI unit of the rate for the messages ("rad/s"); NULL: "SI" */
	const char *unit;
	/** optional temperature of each sample, degC
	 *  (temp_degc[k * temp_stride]); NULL: none */
	const double *temp_degc;
	size_t temp_stride;      /**< 0 means 1 */
	/** terms the caller needs (bits of enum sscope_term); 0 selects
	 *  N, B and K */
	unsigned requested;
	/** stillness: largest 90/10 percentile ratio of the 1 s variance
	 *  (0 selects 9, walk's rule; negative: not tested) */
	double max_contrast;
	/** fit rejected when its chi-squared p-value is below this (0
	 *  selects 0.01) */
	double fit_p_level;
	/** false-alarm probability of the stationarity tests together (warm-
	 *  up, step, temperature, alpha / 3 each); 0 selects 0.02 */
	double alpha;
	/** blocks of the stationarity tests (0 selects 64; at least 8) */
	size_t blocks;
	/** DAVAR window and step, s (0: an eighth of the record, a quarter of
	 *  the window); no_davar: no map */
	double davar_window_s, davar_step_s;
	bool no_davar;
	/** another channel of the same sensor moves (its name; NULL: none):
	 *  the sensor is not still, whatever this channel shows (a gyro axis
	 *  across a rate table's axis sees little of its motion) */
	const char *moving_channel;
	double moving_contrast; /**< that channel's contrast */
};

/** The dynamic Allan deviation: OADEV in sliding windows. */
struct sscope_adequacy_davar {
	size_t n_win, n_tau;
	double window_s, step_s;
	double *t_s;    /**< n_win window centres, s from the first sample */
	double *tau_s;  /**< n_tau averaging times (octaves), s */
	double *dev;    /**< n_win x n_tau deviations (row = window), rate
			     unit; NaN where the window is too short */
	double *edf;    /**< n_win x n_tau equivalent degrees of freedom */
	double *model;  /**< n_tau: the fitted model's deviation (NaN without
			     a fit) */
};

/** Result of the check. */
struct sscope_adequacy {
	double duration_s;
	bool still_tested;
	bool still;          /**< passed (or not tested) */
	double contrast;     /**< 90/10 ratio of the 1 s variance (NaN) */
	double max_contrast;
	bool have_fit;
	bool fit_rejected;
	double fit_p_value;  /**< NaN without a fit */
	bool stationarity_tested;
	bool stationary;     /**< no warm-up, step or temperature finding */
	unsigned requested;  /**< terms asked for */
	unsigned established; /**< terms the fit establishes */
	unsigned doubtful;   /**< terms a finding of severity DOUBT or
				  INVALID concerns */
	enum sscope_adequacy_severity verdict; /**< worst severity */
	size_t n_findings;
	struct sscope_adequacy_finding *findings; /**< worst first */
	struct sscope_adequacy_davar davar;       /**< n_win 0: no map */
};

/**
 * Whether a fitted term is established by its record (the fit's decision
 * that the term is present; today: fitted, and its interval excludes 0).
 * Every consumer asks this one function.
 */
bool sscope_adequacy_term_established(const struct sscope_noise_coef *c);

/**
 * Judge a record and its noise fit.
 *
 * Stillness: the test of sscope-walk.h (90th over 10th percentile of the
 * variance over sliding windows of max(1 s, 11 samples), at most 9);
 * a record that fails it moves, and its noise terms are not valid.
 * Fit: rejected when the chi-squared p-value is below fit_p_level.
 * Length: each requested term the fit does not establish is a bound; the
 * finding gives the tau range where that term at its bound would
 * dominate the fitted model and the record length that would reach it
 * (ten times the start of that range).
 * Stationarity: the record is cut into blocks; the differences of the
 * block means (the terms of the Allan variance at tau = one block) have
 * under the noise terms a known covariance (the structure function of
 * sscope_heading_drift_var_points()), with Q and N from the fit and B and
 * K estimated by maximum likelihood under each hypothesis (so that an
 * anomaly the fit absorbed into B or K is not explained away by them).
 * Likelihood-ratio tests, with a rate ramp as nuisance, of a bias step (at
 * every half block), of a warm-up transient exp(-t / T_w) (T_w from half a
 * block to a quarter of the record) and, with a temperature column, of a
 * linear and quadratic dependence on the block temperature (chi-squared,
 * 2 dof); the step and transient p-values are those of the largest
 * statistic over their candidates, from 2000 draws of the whitened null
 * (a fixed seed); each family at alpha / 3.  A rate ramp is a note (the
 * fit's R term).  The tau range at fault is where the detected component
 * raises the noise model's Allan variance by more than 21 % (the
 * deviation by 10 %); a detected component that raises it nowhere that
 * much is a note.
 * DAVAR: OADEV at octave averaging factors (at most a quarter of the
 * window) in windows of davar_window_s every davar_step_s.
 *
 * @param x      the record, x[k * stride], k < n: rate (SI unit U) or
 *               angle (U s, opts->angle); NaN marks a gap (the stillness
 *               and stationarity tests then do not run: noted).
 * @param fit    the record's noise fit (sscope_noise_fit() or
 *               sscope_allan_analyze()), NULL when there is none.
 * @param o      options.
 * @param res    receives the result; free with sscope_adequacy_free().
 * @param diag   optional detail of an error.
 * @return 0; -EINVAL (NULL, rate not positive, an infinite sample, bad
 *         option); -EDOM (fewer than 2 samples); -ENOMEM.
 */
int sscope_adequacy_check(const double *x, size_t stride, size_t n,
			  const struct sscope_noise_fit *fit,
			  const struct sscope_adequacy_opts *o,
			  struct sscope_adequacy **res,
			  struct sscope_diag *diag);

/** Free a result (NULL is ignored). */
void sscope_adequacy_free(struct sscope_adequacy *res);

/** Short name of a cause ("moves", "warm_up", ...), for JSON. */
const char *sscope_adequacy_cause_name(enum sscope_adequacy_cause c);

/** Short name of a severity ("note", "bound", "doubt", "invalid"). */
const char *sscope_adequacy_severity_name(enum sscope_adequacy_severity s);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_ADEQUACY_H */
