/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-noise.h
 * @brief The IEEE Std 952 noise-term fit of Allan variances, with uncertainties.
 *
 * Part of libsensorscope: the conventions (errors, units, names,
 * lifetimes) are stated once in sensorscope.h, which includes every
 * public header.
 */
#ifndef SSCOPE_NOISE_H
#define SSCOPE_NOISE_H

#include "sscope-core.h"
#include "sscope-term.h"

#ifdef __cplusplus
extern "C" {
#endif

struct sscope_allan_point;

/**
 * Allan variance of the five IEEE Std 952-1997 (Annex C) rate-noise terms:
 * 3 Q^2 / tau^2 + N^2 / tau + (2 ln2 / pi) B^2 + K^2 tau / 3 +
 * R^2 tau^2 / 2.
 * @param coef   Q (U s), N (U/sqrt(Hz)), B (U), K (U/s/sqrt(Hz)), R (U/s),
 *               indexed by enum sscope_term; U the rate unit.
 * @param tau_s  averaging time, s.
 * @return the Allan variance, U^2.
 */
double sscope_noise_avar(const double coef[5], double tau_s);

/**
 * Why a term is or is not reported as present (struct sscope_noise_coef's
 * why).  Presence is decided by a model-selection test on nested fits
 * (sscope_noise_fit()), not by the precision of the term.
 */
enum sscope_noise_why {
	/** present: the selection test keeps it; value and a central
	 *  interval [lo, hi] (however wide) are reported */
	SSCOPE_NOISE_PRESENT = 0,
	/** not among the terms the options allow: nothing is reported
	 *  (value, lo, hi NaN) */
	SSCOPE_NOISE_NOT_ALLOWED,
	/** not shown present: the nested fit without the term describes the
	 *  curve (its square is below the test's threshold there); hi is an
	 *  upper bound (> 0), lo = 0, value NaN */
	SSCOPE_NOISE_NOT_NEEDED,
	/** not shown present: the test keeps it with the other present
	 *  terms, but with every allowed term free its square is not
	 *  positive (it trades off with a term the selection dropped); hi is
	 *  an upper bound (> 0), lo = 0, value NaN */
	SSCOPE_NOISE_NOT_SEPARABLE,
};

/** A fitted noise coefficient, SI (units as sscope_noise_avar()). */
struct sscope_noise_coef {
	double value;  /**< estimate; NaN when the term is not present */
	double lo, hi; /**< interval at the fit's confidence level; for a term
			    not present lo = 0 and hi an upper limit (> 0;
			    INFINITY when the record gives no finite bound);
			    NaN for a term not allowed */
	double var_sd; /**< standard deviation of the estimate of the
			    coefficient squared (the fitted variable), with
			    every allowed term free */
	double estimate; /**< sqrt(max(0, estimated square)) with every
			      allowed term free, present or not (for
			      comparisons of two fits of the same noise), U */
	bool fitted;   /**< the same as present (the older name) */
	bool present;  /**< shown present by the selection test (forced
			    terms always): value and [lo, hi] are reported */
	enum sscope_noise_why why; /**< why present or not */
	double z;      /**< the selection test's statistic: the square over
			    its standard deviation in the nested fit of the
			    present terms with this one (the last fit that
			    held it); NaN for a term not allowed */
	double square; /**< the estimate of the square with every allowed
			    term free, signed (unbiased: a prediction that
			    adds the terms' variances, as walk's envelope,
			    takes it rather than estimate^2, whose floor at 0
			    biases it up); 0 for a term not allowed, U^2 */
};

/** The classic slope read-offs (IEEE 952 Annex C; NaN when not found).
 *  sscope_noise_readoff() picks the points by local slope alone; the
 *  read-offs in struct sscope_noise_fit use the fitted model of the
 *  terms instead: a term is read only when it is present, at a point
 *  whose EDF is at least 10 and where the term's share of the model Allan
 *  variance is at least 3/4 with its square at its lower bound and every
 *  other term at its upper bound (the others then add at most 15 % to the
 *  deviation read, with confidence); of those points, the one where the
 *  read-off's expected relative error (bias of the other terms and
 *  sampling spread 1/sqrt(2 EDF) together) is least.  NaN otherwise: the
 *  term dominates nowhere the curve is precise. */
struct sscope_noise_readoff {
	double n;       /**< sigma(1 s) on the -1/2 line through the point
			     used, U/sqrt(Hz) */
	double n_tau_s; /**< that point's tau, s */
	double b;       /**< minimum deviation / 0.6643, U */
	double b_tau_s; /**< where that minimum is, s */
	double k;       /**< sigma(3 s) on the +1/2 line through the point
			     used, U/s/sqrt(Hz) */
	double k_tau_s; /**< that point's tau, s */
};

struct sscope_noise_plan;

/** Options of the fit.  Zero-initialised = every term allowed, 68.27 %
 *  intervals, no model error, terms resolved at 3 sd, the whole curve. */
struct sscope_noise_fit_opts {
	/** Confidence level of the intervals; 0 selects 0.6827. */
	double ci_level;
	/** Terms that may be fitted: bits (1u << SSCOPE_TERM_Q) ... (1u <<
	 *  SSCOPE_TERM_R); 0 allows all five. */
	unsigned allowed;
	/** Terms that must be fitted (must be allowed); the selection only
	 *  adds to them.  0: fully automatic. */
	unsigned forced;
	/** Relative standard deviation of the five-term model itself at each
	 *  tau, added (independently per point) to the sampling covariance,
	 *  for sensors that are not five power laws.  0 or negative: none
	 *  (the sampling covariance is exact for the five processes; the
	 *  intervals' coverage is checked by simulation in make bench). */
	double model_error;
	/** Threshold of the presence test, in standard deviations: a term
	 *  is present when its square exceeds this many standard deviations
	 *  in the nested fit (one-sided level Phi(-detect_sigma)); 0 selects
	 *  3 (0.135 %). */
	double detect_sigma;
	/** Fit only points with tau_min_s <= tau <= tau_max_s (0: no limit). */
	double tau_min_s, tau_max_s;
	/** sscope_allan_analyze(): the deviations only, no fit (have_fit
	 *  false, fit_error 0). */
	bool skip;
	/** Optional plan (sscope_noise_plan_new()) shared by the fits of
	 *  several records of one rate and length: NULL computes everything
	 *  per fit.  The fit fills it and later fits reuse it. */
	struct sscope_noise_plan *plan;
};

/** Result of the noise fit. */
struct sscope_noise_fit {
	struct sscope_noise_coef coef[5]; /**< indexed by enum sscope_term */
	unsigned terms;     /**< bit mask of the fitted terms */
	double ci_level;    /**< level of the intervals */
	size_t n_points;    /**< points used */
	double chi2;        /**< generalised chi-squared r' C^-1 r of the
				 fit's residuals (C: see above) */
	double dof;         /**< n_points - number of allowed terms */
	double p_value;     /**< P(chi2 >= observed) under the fitted
				 model, from the parametric bootstrap of the
				 intervals (1000 replicates refitted; at least
				 1/1001); the chi-squared distribution with
				 dof only when no replicate can be drawn */
	double aic;         /**< chi2 + 2 p, p the allowed terms */
	size_t n_plausible; /**< always 0 (kept for the layout) */
	struct sscope_noise_readoff readoff; /**< classic read-offs */
	unsigned present;   /**< bit mask of the terms shown present (the
				 same as terms) */
	double select_z;    /**< threshold of the presence test, sd */
	double sq_cov[5][5]; /**< covariance of the coefficients' squares
				  (the sandwich covariance of the fit of every
				  allowed term), U^4; 0 for terms not allowed */
};

/**
 * Fit the five IEEE 952 terms to overlapping Allan variances.
 *
 * Method: one weighted least-squares fit of every allowed term on AVAR,
 * rows a(tau) = [3/tau^2, 1/tau, 2 ln2/pi, tau/3, tau^2/2], unknowns the
 * squares (Q^2, N^2, B^2, K^2, R^2) free of sign, weights EDF / (2 model^2)
 * iterated with the model.
 *
 * Presence, then precision.  Which terms are present is decided by
 * backward elimination on nested fits: starting from every allowed term,
 * the term whose square is the fewest standard deviations (its sandwich
 * sd under that fit's model) above zero is dropped when below
 * detect_sigma (a one-sided Wald test at level Phi(-detect_sigma), 0.135 %
 * by default), the rest refitted, until every remaining term passes;
 * forced terms are never dropped.  A present term is reported with its
 * value and interval from the fit of every allowed term (the interval
 * does not pretend the selection was free), however wide; a term not
 * shown present with an upper bound above zero and the reason (why).  The covariance C of
 * the overlapping AVAR estimates under the fitted model (Q white angle, N
 * white rate, B flicker rate, K random-walk rate, exact for the sampled
 * processes of Q, N, K; R deterministic; Gaussian fourth moments; plus the
 * model_error term) gives the sandwich covariance (A'WA)^-1 A'W C W A
 * (A'WA)^-1 of the squares and chi2 = r' C^-1 r.  Intervals are Neyman intervals from a parametric bootstrap of the
 * estimator: for a tested value b of a square, 1000 replicates of the
 * AVAR points are drawn from the fitted model with that square set to b
 * (Gamma margins of the model's mean and variance, Gaussian copula with
 * the correlation of C, a fixed generator seed) and pushed through the
 * estimator; the bounds are the b at which the estimate lies at the tail
 * probability of the level.  The acceptance regions run from one-sided
 * (a b the record cannot resolve) to central (a b it resolves), so that
 * the interval of a resolved term and the "not resolved: below hi" of
 * the others cover at the level together (checked by simulation in make
 * bench).  Skewed estimates (few degrees of freedom at long tau) get
 * skewed intervals.
 *
 * @param pts      OADEV points (stride 1 or strided; dev > 0) from
 *                 sscope_allan_compute() of a rate or angle record.
 * @param n_pts    number of points.
 * @param rate_hz  sample rate of the record, Hz.
 * @param n_phase  phase points of the record.
 * @param opts     options (NULL: defaults).
 * @param fit      receives the result.
 * @param diag     optional detail.
 * @return 0; -EINVAL (NULL, bad option); -EDOM (fewer points than needed,
 *         every deviation zero: then every coefficient is 0 with lo = hi =
 *         0 and fitted false); -ENOMEM.
 */
int sscope_noise_fit(const struct sscope_allan_point *pts, size_t n_pts,
		     double rate_hz, size_t n_phase,
		     const struct sscope_noise_fit_opts *opts,
		     struct sscope_noise_fit *fit, struct sscope_diag *diag);

/**
 * A plan for sscope_noise_fit(): a cache of what the fit computes that
 * depends only on the sample rate and the points' averaging factors and
 * term counts (the sums of the AVAR covariance over every pair of points,
 * the bootstrap's random numbers and quantile table), not on the data.
 * The fits of several channels of one capture (or of records of one
 * length and rate) through one plan compute these once; the results are
 * the same numbers as without a plan.  A plan starts empty, is filled by
 * the first fit that uses it and refilled when a fit's points differ; it
 * is owned by the caller and must not be used by two fits at once (one
 * plan per thread).
 * @param plan  receives the plan; free with sscope_noise_plan_free().
 * @return 0, -EINVAL (NULL), -ENOMEM.
 */
int sscope_noise_plan_new(struct sscope_noise_plan **plan);

/** Free a plan (NULL is ignored). */
void sscope_noise_plan_free(struct sscope_noise_plan *plan);

/**
 * Whether a fit's chi-squared test rejects the five-term model at level
 * @p p_level (its p-value below it; 0.01 is usual): a deterministic trend
 * or a process outside the model, the terms indicative only.
 */
bool sscope_noise_fit_rejected(const struct sscope_noise_fit *fit,
			       double p_level);

/** Whether a term is resolved: present, and its interval excludes zero. */
bool sscope_noise_coef_resolved(const struct sscope_noise_coef *c);

/**
 * The classic read-offs alone (no fit).
 * @param pts    deviation points (OADEV or ADEV), increasing tau.
 * @return 0, or -EDOM when fewer than 3 positive points.
 */
int sscope_noise_readoff(const struct sscope_allan_point *pts, size_t n_pts,
			 struct sscope_noise_readoff *r);

/**
 * Covariance matrix of overlapping Allan variance estimates for the
 * five-term model (the matrix the fit uses), for users who want to weigh
 * their own fits or check a design.
 * @param coef     model coefficients (SI, as sscope_noise_avar()).
 * @param rate_hz  sample rate, Hz.
 * @param m        averaging factors of the points.
 * @param terms    terms of each estimate (np - 2 m for a full record).
 * @param n        number of points.
 * @param cov      receives n * n values, row-major, U^4.
 * @return 0, -EINVAL, -ENOMEM.
 */
int sscope_noise_avar_cov(const double coef[5], double rate_hz,
			  const size_t *m, const size_t *terms, size_t n,
			  double *cov);

/**
 * Is a fit's p_value a bound rather than an estimate?  At the bootstrap's
 * floor (1/1001: no replicate reached the observed chi-squared) the true
 * p is only known to be below it; say "p < 0.001", not "p = 0.001".
 */
bool sscope_noise_p_is_bound(double p_value);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_NOISE_H */
