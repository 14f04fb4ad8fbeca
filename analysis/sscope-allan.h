/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-allan.h
 * @brief Allan-family deviations with confidence intervals, and the IEEE
 *        Std 952 noise-term fit with uncertainties.
 *
 * Conventions of this module:
 * - Input is a rate (frequency-like: deg/s, m/s^2, V, ...) or an angle
 *   (phase-like: the integral of a rate) sampled at rate_hz.  Every
 *   deviation is reported for the *rate*, in the rate's SI unit (an angle
 *   input in rad gives deviations in rad/s), except TDEV which is an angle
 *   (rate unit * s).  tau = m / rate_hz.
 * - Definitions are those of NIST SP 1065 (Riley 2008) and IEEE Std
 *   1139-2008 on phase data x: a rate record of n samples is integrated to
 *   n + 1 phase points (after removing its mean, which no deviation sees),
 *   an angle record of n samples is n phase points.
 * - A tau is computed only when its estimator has at least one term:
 *   ADEV, OADEV, TOTDEV m <= (np - 1) / 2; MDEV, TDEV m <= np / 3; HDEV,
 *   OHDEV m <= (np - 1) / 3 (np phase points).  This is Stable32's limit;
 *   the last points carry few degrees of freedom and wide intervals.
 *   MTOTDEV, TTOTDEV m <= np / 3; HTOTDEV m <= (np - 1) / 3; Theo1,
 *   TheoBR m even, 10 <= m <= np - 1, at tau = 0.75 m / rate_hz (SP 1065
 *   eq. 33: Theo1 reaches 0.75 of the record); TheoH the OADEV points with
 *   m <= 0.1 (np - 1) and the TheoBR points with 0.75 m >= 0.1 (np - 1)
 *   (other m of a request are skipped); MTIE, TIE rms m <= np - 1.
 * - NaN samples are gaps: a term whose span touches a NaN is skipped and
 *   counted in sscope_allan_point::skipped; the variance averages the
 *   complete terms only (Sesia & Tavella, Metrologia 45 (2008) S134), and
 *   the EDF is that of a gap-free record with as many terms.  A point with
 *   no complete term has terms 0 and NaN deviation, bounds and EDF from
 *   sscope_allan_compute(); sscope_allan_analyze() leaves such taus out
 *   (sscope_allan_result::n_gap_omitted, gap_note).  TOTDEV and the
 *   deviations after it in enum sscope_allan_dev refuse gaps (-EDOM).
 * - Confidence intervals: equivalent degrees of freedom (EDF) after
 *   Greenhall & Riley (PTTI 2003, as Stable32), for TOTDEV NIST SP 1065
 *   table 7, MTOTDEV/TTOTDEV table 8, HTOTDEV table 9 (the Hadamard EDF
 *   at m = 1 and for phase noises), Theo1/TheoBR the Howe-Tasset
 *   formulas of section 5.2.15 (TheoH: OADEV's and TheoBR's by part);
 *   MTIE and TIE rms have none (NaN bounds and EDF); the dominant
 *   power-law noise at each tau from the lag-1
 *   autocorrelation (Riley & Greenhall 2004) unless given; chi-squared
 *   bounds from GSL.
 */
#ifndef SSCOPE_ALLAN_H
#define SSCOPE_ALLAN_H

#include "sscope-core.h"
#include "sscope-quantity.h"
#include "sscope-noise.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Deviation estimators. */
enum sscope_allan_dev {
	SSCOPE_ALLAN_DEV_OADEV = 0, /**< overlapping Allan deviation (default) */
	SSCOPE_ALLAN_DEV_ADEV,      /**< non-overlapping Allan deviation */
	SSCOPE_ALLAN_DEV_MDEV,      /**< modified Allan deviation */
	SSCOPE_ALLAN_DEV_TDEV,      /**< time deviation tau * MDEV / sqrt(3) */
	SSCOPE_ALLAN_DEV_HDEV,      /**< non-overlapping Hadamard deviation */
	SSCOPE_ALLAN_DEV_OHDEV,     /**< overlapping Hadamard deviation */
	SSCOPE_ALLAN_DEV_TOTDEV,    /**< total deviation (reflected extension) */
	SSCOPE_ALLAN_DEV_MTOTDEV,   /**< modified total deviation */
	SSCOPE_ALLAN_DEV_HTOTDEV,   /**< Hadamard total deviation (bias removed) */
	SSCOPE_ALLAN_DEV_TTOTDEV,   /**< time total deviation tau * MTOTDEV / sqrt(3) */
	SSCOPE_ALLAN_DEV_THEO1,     /**< Theo1 at tau = 0.75 m / rate_hz */
	SSCOPE_ALLAN_DEV_THEOBR,    /**< bias-removed Theo1 */
	SSCOPE_ALLAN_DEV_THEOH,     /**< hybrid: OADEV to 10 % of the record, TheoBR beyond */
	SSCOPE_ALLAN_DEV_MTIE,      /**< maximum time interval error (no interval) */
	SSCOPE_ALLAN_DEV_TIERMS,    /**< rms time interval error (no interval) */
	SSCOPE_ALLAN_DEV_COUNT_
};

/** @return "oadev", "adev", ... for @p dev; "" when out of range. */
const char *sscope_allan_dev_name(enum sscope_allan_dev dev);

/** @return the name as Stable32 and SP 1065 print it ("OADEV", "MTOTDEV",
 *  "Theo1", "TheoBR", "TheoH", "MTIE", "TIE rms"); "" when out of range. */
const char *sscope_allan_dev_label(enum sscope_allan_dev dev);

/** @return whether @p dev is a time (angle) quantity in rate unit * s
 *  (TDEV, TTOTDEV, MTIE, TIE rms) rather than a rate. */
bool sscope_allan_dev_is_time(enum sscope_allan_dev dev);

/** @return whether @p dev has confidence intervals (all but MTIE and TIE
 *  rms, whose distribution has no EDF model). */
bool sscope_allan_dev_has_ci(enum sscope_allan_dev dev);

/**
 * Parse a deviation name ("oadev", "adev", "mdev", "tdev", "hdev",
 * "ohdev", "totdev", "mtotdev", "htotdev", "ttotdev", "theo1", "theobr",
 * "theoh", "mtie", "tierms"; any case).
 * @return 0, or -EINVAL for an unknown name.
 */
int sscope_allan_dev_parse(const char *name, enum sscope_allan_dev *dev);

/** What the samples are. */
enum sscope_allan_input {
	SSCOPE_ALLAN_RATE = 0, /**< rate / frequency-like (gyro rate) */
	SSCOPE_ALLAN_ANGLE     /**< angle / phase-like (integrated rate) */
};

/** Grids of averaging factors m (tau = m / rate_hz). */
enum sscope_allan_tau_grid {
	/** about 10 per decade: m = round(10^(k/10)), distinct, and from
	 *  m >= 32 rounded to 5 significant bits (multiples of
	 *  2^(floor(log2 m) - 4), at most 3.1 % off the logarithmic
	 *  spacing) so that every large m shares the power-of-two factors
	 *  the fast engine uses: 1 2 3 4 5 6 8 10 13 16 20 25 32 40 50 64 80
	 *  100 128 160 200 248 320 400 496 640 800 992 ... */
	SSCOPE_ALLAN_TAUS_DENSE = 0,
	SSCOPE_ALLAN_TAUS_OCTAVE, /**< m = 1, 2, 4, 8, ... */
	SSCOPE_ALLAN_TAUS_DECADE, /**< m = 1, 2, 4, 10, 20, 40, 100, ... (Stable32) */
	SSCOPE_ALLAN_TAUS_ALL     /**< every m (O(n^2) work: small records only) */
};

/**
 * Number of phase points of a record of @p n samples.
 * @return n + 1 for rate input, n for angle input.
 */
size_t sscope_allan_n_phase(enum sscope_allan_input input, size_t n);

/**
 * The quantity whose noise terms an analysis of samples of quantity @p q
 * gives: @p q itself for rate input; for angle input its rate (an angle
 * gives an angular rate, a velocity an acceleration, anything else
 * SSCOPE_QUANTITY_UNKNOWN).
 */
enum sscope_quantity sscope_allan_rate_quantity(enum sscope_quantity q,
						enum sscope_allan_input input);

/**
 * Largest averaging factor @p dev accepts for @p n_phase phase points (the
 * limits in the file comment).
 * @return the largest m, or 0 when even m = 1 has no term.
 */
size_t sscope_allan_max_m(enum sscope_allan_dev dev, size_t n_phase);

/**
 * Averaging factors of a grid, increasing, each <= @p m_max.
 * @param m      receives up to @p cap values (may be NULL with cap 0 to
 *               count them).
 * @param count  receives the number of grid values <= m_max (may exceed
 *               @p cap: then only the first @p cap were written).
 * @return 0, or -EINVAL (unknown grid, NULL count).
 */
int sscope_allan_grid(enum sscope_allan_tau_grid grid, size_t m_max, size_t *m,
		      size_t cap, size_t *count);

/** Plan flags: memory policy, as FFTW's planner flags (bits of
 *  sscope_allan_opts.plan_flags).  Results do not depend on them. */
enum sscope_allan_plan_flag {
	/** The record can be fetched again: a read-only mapping of a file
	 *  (sscope_capture_mapped()).  Once the engine has read a range of
	 *  samples for the last time in a computation, the whole pages
	 *  inside it are given back (a later read fetches them from the
	 *  file or the page cache), so that the record and the phase
	 *  workspace are never both whole in memory.  Never for memory
	 *  the record lives in only (allocated or written): its pages
	 *  would read back as zeros. */
	SSCOPE_ALLAN_EVICT_INPUT = 1u << 0,
	/** When the plan is freed (sscope_allan_free(), and at the end of
	 *  sscope_allan_analyze()), give its workspace's pages back to the
	 *  system on all its threads at once: for the last analysis of a
	 *  process, whose exit would otherwise free them on one core, or of
	 *  a program that will not allocate as much again.  Without it the
	 *  memory goes back to malloc(), and a next plan of the same size
	 *  may reuse its pages without the system clearing them. */
	SSCOPE_ALLAN_RELEASE_WORKSPACE = 1u << 1,
};

/** Options of the deviation engine.  Zero-initialised = OADEV on a rate,
 *  68.27 % intervals, noise type identified, all threads. */
struct sscope_allan_opts {
	enum sscope_allan_dev dev;
	enum sscope_allan_input input;
	/** Confidence level of the intervals in (0, 1); 0 selects 0.6827
	 *  (1 sigma); a negative value computes no interval (lo/hi NaN, the
	 *  EDF is still reported). */
	double ci_level;
	/** Use @p alpha (power-law exponent of the rate PSD: 2 white angle,
	 *  1 flicker angle, 0 white rate, -1 flicker rate, -2 random-walk
	 *  rate, -3, -4 for Hadamard) for every tau instead of identifying
	 *  it from the data. */
	bool alpha_fixed;
	int alpha;
	/** Strided-overlap estimator for very long records (OADEV and OHDEV
	 *  only): terms start every s = max(1, floor(m / stride_div)) samples
	 *  instead of every sample, so a tau costs about stride_div * n / m
	 *  operations instead of n.  The EDF is computed for the estimator
	 *  actually used (Greenhall's stride factor), and the EDF of the full
	 *  estimator is reported beside it so the loss is visible.
	 *  0 = full overlap (the default). */
	size_t stride_div;
	/** OpenMP threads; 0 = the OpenMP default; 1 = serial.  Ignored
	 *  when built without OpenMP.  Results do not depend on it beyond
	 *  the last bits of a sum. */
	unsigned threads;
	/** NaN samples are an error (-EDOM), as infinite ones always are,
	 *  instead of gaps: for callers whose data may hold no gaps, which
	 *  then need not check the samples themselves (the engine does, as
	 *  it reads them). */
	bool reject_nan;
	/** Plan flags (SSCOPE_ALLAN_EVICT_INPUT,
	 *  SSCOPE_ALLAN_RELEASE_WORKSPACE): how the plan uses memory,
	 *  never what it computes; 0: keep everything. */
	unsigned plan_flags;
};

/** One tau of a deviation. */
struct sscope_allan_point {
	double tau_s;   /**< m / rate_hz, s */
	size_t m;       /**< averaging factor */
	size_t terms;   /**< terms summed (after skipping gaps) */
	size_t skipped; /**< terms skipped because they touch a NaN */
	size_t stride;  /**< samples between terms (1: fully overlapping; m:
			     non-overlapping estimators) */
	double dev;     /**< the deviation, rate SI unit (TDEV: rate unit * s) */
	double dev_lo;  /**< lower bound at the confidence level (NaN: none) */
	double dev_hi;  /**< upper bound (NaN: none) */
	double edf;     /**< equivalent degrees of freedom of dev^2, those of
			     the interval: alpha's, or where alpha was read
			     from fewer than 225 analysis points and differs
			     from the shorter tau's type, the fewer of the
			     two types' */
	double edf_full; /**< EDF of the fully overlapping estimator (equals
			      edf unless stride_div was used) */
	double edf_alpha; /**< EDF of alpha's type (the noise fit's weights
			       and read-offs; equals edf unless edf says
			       otherwise) */
	int alpha;      /**< power-law noise exponent identified (as
			     Stable32), given or carried; the EDF's unless
			     edf says otherwise */
	bool alpha_identified; /**< alpha came from this tau's own data (false:
				    given, or carried over from a shorter tau
				    because fewer than 30 averages remain) */
};

/** A deviation plan: workspace for records of up to n_max samples. */
struct sscope_allan;

/**
 * Make a plan.  All memory the engine needs is allocated here: one phase
 * buffer of about n_max doubles (the only copy of the data; strided and
 * interleaved inputs are read in place) plus per-thread windows of a few
 * hundred kilobytes; a record with NaN gaps adds a bitmap of n_max / 8
 * bytes and counts of n_max / 16 bytes.
 * @param plan   receives the plan; free it with sscope_allan_free().
 * @param n_max  largest record (samples) compute() will be given.
 * @param opts   options (NULL: the defaults); copied.
 * @return 0, -EINVAL (n_max 0, bad option), -ENOMEM.
 */
int sscope_allan_new(struct sscope_allan **plan, size_t n_max,
		     const struct sscope_allan_opts *opts);

/** Free a plan (NULL is ignored). */
void sscope_allan_free(struct sscope_allan *plan);

/**
 * Compute the deviation at the averaging factors @p m.
 * @param plan     a plan with n_max >= n.
 * @param x        samples x[k * stride], k < n: rate (SI unit U) or angle
 *                 (U * s), see opts.input; NaN marks a gap.
 * @param stride   distance between samples (>= 1).
 * @param n        number of samples.
 * @param rate_hz  sample rate, Hz (> 0).
 * @param m        averaging factors, strictly increasing, >= 1; those
 *                 beyond sscope_allan_max_m() are ignored.
 * @param n_m      number of factors.
 * @param pts      receives one point per accepted factor (caller-owned
 *                 array of n_m).
 * @param n_pts    receives the number of points written.
 * @param diag     optional detail of a failure.
 * @return 0; -EINVAL (NULL pointer, stride 0, rate not positive, n > n_max,
 *         m not increasing or 0); -EDOM (record too short for any given m,
 *         fewer than two finite samples, gaps with TOTDEV, an infinite
 *         sample, a NaN with opts.reject_nan); -ERANGE (a
 *         rate that puts 1/rate_hz below 2^-200 s or n/rate_hz above
 *         2^200 s; a deviation beyond the double range); -ENOMEM.
 *         Samples of any finite magnitude are handled: when the squared
 *         sums leave the double range (beyond about 1e150, below 1e-150)
 *         the record is computed again from a copy scaled by a power of
 *         two (exact) and the deviations scaled back.
 */
int sscope_allan_compute(struct sscope_allan *plan, const double *x,
			 size_t stride, size_t n, double rate_hz,
			 const size_t *m, size_t n_m,
			 struct sscope_allan_point *pts, size_t *n_pts,
			 struct sscope_diag *diag);

/* ------------------------------------------------------------------ */
/* Equivalent degrees of freedom and noise identification              */
/* ------------------------------------------------------------------ */

/**
 * Greenhall & Riley EDF of a variance estimator built on d-th differences
 * of phase ("Uncertainty of stability variances based on finite
 * differences", 35th PTTI, 2003), the algorithm Stable32 uses.
 * @param alpha   power-law exponent of the rate PSD, -4..2, with
 *                alpha + 2 d > 1.
 * @param d       difference order: 2 Allan, 3 Hadamard.
 * @param m       averaging factor.
 * @param n_phase number of phase points.
 * @param modified true for MDEV/TDEV (filter factor 1), false otherwise.
 * @param stride  samples between terms: 1 overlapping, m non-overlapping,
 *                or anything between (strided estimator).
 * @return the EDF, or NaN for parameters outside the method.
 */
double sscope_allan_edf(int alpha, int d, size_t m, size_t n_phase,
			bool modified, size_t stride);

/**
 * Dominant power-law noise at averaging factor @p m by the lag-1
 * autocorrelation method (Riley & Greenhall, "Power law noise
 * identification using the lag 1 autocorrelation", EFTF 2004; NIST SP
 * 1065 section 5.6), on phase points: averaged rate (first differences of
 * the phase decimated by m) or decimated phase, mean removed, r1 scaled by
 * (n - 1) / n as Stable32, differenced until rho = r1 / (1 + r1) < 0.25 or
 * d = dmax.  No trend is removed: a polynomial fit to a few dozen points
 * pulls r1 towards 0 (a random walk of 56 points detrended to second
 * order reads as white phase); remove deterministic drift beforehand.
 * sscope_allan_compute() falls back to the B1 ratio (and R(n)) below 30
 * analysis points, as Stable32.
 * @param phase     np phase points (any units).
 * @param np        number of phase points.
 * @param m         averaging factor.
 * @param rate_like true: start from the averaged rate (rate input);
 *                  false: from the decimated phase (angle input).
 * @param dmax      2 for Allan-family, 3 for Hadamard deviations.
 * @param alpha     receives the integer exponent (-4..2).
 * @param alpha_est receives the fractional estimate (may be NULL).
 * @return 0; -EDOM when fewer than 30 averages remain or the averages are
 *         constant; -EINVAL.
 */
int sscope_allan_noise_id(const double *phase, size_t np, size_t m,
			  bool rate_like, int dmax, int *alpha,
			  double *alpha_est);

/* ------------------------------------------------------------------ */
/* One call                                                            */
/* ------------------------------------------------------------------ */

/** Everything sscope_allan_analyze() computes. */
struct sscope_allan_result {
	size_t n_points;
	struct sscope_allan_point *points; /**< the requested deviation */
	/** OADEV points the fit used: the same array as points when the
	 *  deviation is OADEV or no fit was asked for (skip), else a
	 *  separate one.  For SSCOPE_ALLAN_TAUS_ALL these are the taus of the
	 *  dense grid (about ten per decade): neighbouring taus are almost
	 *  fully correlated and add nothing to the fit but cost. */
	struct sscope_allan_point *oadev;
	size_t n_oadev;
	size_t n_phase;     /**< phase points of the record */
	bool have_fit;      /**< false when the fit failed (fit_error) */
	int fit_error;      /**< the fit's return code */
	struct sscope_noise_fit fit;
	struct sscope_diag fit_diag; /**< why the fit failed (may be empty) */
	/** Taus of the grid left out of points because every one of their
	 *  terms spans a NaN gap (0: none). */
	size_t n_gap_omitted;
	/** Why, in a sentence for the user (empty when n_gap_omitted is 0). */
	struct sscope_diag gap_note;
};

/**
 * Deviation on a grid plus the noise fit, in one call (plan made and
 * freed inside).
 * @param x, stride, n, rate_hz  the record (see sscope_allan_compute()).
 * @param grid     tau grid.
 * @param aopts    deviation options (NULL: defaults).
 * @param fopts    fit options (NULL: defaults).
 * @param res      receives the result; free with sscope_allan_result_free().
 * @param diag     optional detail.
 * @return as sscope_allan_compute(), and -EDOM when NaN gaps leave no
 *         tau with a complete term; a failing fit is not an error (see
 *         have_fit / fit_error).
 */
int sscope_allan_analyze(const double *x, size_t stride, size_t n,
			 double rate_hz, enum sscope_allan_tau_grid grid,
			 const struct sscope_allan_opts *aopts,
			 const struct sscope_noise_fit_opts *fopts,
			 struct sscope_allan_result **res,
			 struct sscope_diag *diag);

/** Free a result (NULL is ignored). */
void sscope_allan_result_free(struct sscope_allan_result *res);


#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_ALLAN_H */
