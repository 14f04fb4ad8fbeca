/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-tempbias.h
 * @brief Temperature dependence of a sensor bias: polynomial b(T) about a
 *        reference temperature, heating/cooling hysteresis, a thermal
 *        gradient (dT/dt) term, turn-on to turn-on repeatability over
 *        several power cycles, in-run stability after compensation and a
 *        compensation table.
 *
 * Model (one joint weighted least-squares fit, U the unit of the data):
 *
 *   b = d_j + sum_{k=1..K} a_k u^k + eta * s + g * dT/dt,
 *   u = (T - T_ref) / h,
 *
 * with d_j the settled bias of run (power cycle) j, h the half-span of the
 * temperatures, s = +1 while heating, -1 while cooling (0 before the first
 * excursion): by default from the turning points of the temperature, or
 * with a rate dead band (dT/dt > band: heating, < -band: cooling, the last
 * state in between), so heating minus cooling = 2 eta (IEEE Std 528
 * hysteresis).  The
 * data are averaged into blocks (block_s), temperature is smoothed and
 * differentiated by a centred local linear fit over smooth_s, blocks are
 * averaged into bins of (run, temperature, state, dT/dt class of 1/8 of
 * the rms dT/dt) holding the means of every regressor (so the binned fit
 * is the sample fit of the same linear model, and passes through one
 * temperature at different rates stay apart), and the bins are fitted
 * with weights = samples per bin (gsl_multifit_wlinear, SVD of the
 * centred and scaled design).  The coefficient covariance is the
 * sandwich A^-1 S A^-1 of the time-ordered block scores under a noise
 * model of the block errors, white noise, a random walk of the bias and
 * flicker (bias instability, a bank of Gauss-Markov processes),
 * independent between runs, whose levels are the restricted maximum
 * likelihood (REML) of the residuals given the design (a Kalman filter
 * per run on at most 1024 groups of consecutive blocks; the model with
 * the best REML less one per level); a random walk or bias instability
 * widens the intervals, and for white residuals the covariance is the
 * classical one.  The order (auto) is the largest K whose added term passes an
 * F test at level alpha, capped at one order per 5 degC of span, below
 * the number of distinct temperature levels (cells of span / 20 holding
 * at least 1 % of the data) and at SSCOPE_TEMPBIAS_MAX_ORDER, and
 * lowered when the design is singular (reciprocal condition number below
 * 1e-10).  The gradient term is left out when its variance inflation
 * factor on the other columns exceeds SSCOPE_TEMPBIAS_VIF_MAX (ramps of
 * one rate each way make dT/dt follow the heating/cooling state), and
 * the hysteresis is then the combined heating - cooling gap.  In-run
 * stability is the minimum ADEV among taus whose EDF for white noise is
 * at least 10.  Warm-up (unless given): after a fit, windows of 2 % of
 * the run (>= 5 blocks) of the residuals are compared with the median of
 * all window means in units of their robust spread (1.4826 MAD): a
 * warm-up exists when the first window is beyond 5 spreads, and ends half
 * a window after the first window (sliding from the start, within the
 * first half) within 2 spreads; the fit and the detection are repeated
 * twice.
 */
#ifndef SSCOPE_TEMPBIAS_H
#define SSCOPE_TEMPBIAS_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSCOPE_TEMPBIAS_MAX_ORDER 4 /**< highest polynomial order */
#define SSCOPE_TEMPBIAS_MAX_RUNS 64 /**< power cycles per fit */
/** variance inflation factor above which the gradient term is not
 *  separated from the hysteresis term (the usual rule of thumb: the
 *  coefficient's variance is 10 times what an orthogonal design gives) */
#define SSCOPE_TEMPBIAS_VIF_MAX 10.0

/** One record (power cycle). */
struct sscope_tempbias_run {
	const double *x;         /**< samples x[k * stride], U (NaN: skipped) */
	size_t stride;           /**< >= 1 */
	const double *temp_degc; /**< temperature per sample, degC */
	size_t n;                /**< samples */
	double rate_hz;          /**< sample rate, Hz (> 0) */
};

/** Options.  Zero-initialised = automatic choices (see each field). */
struct sscope_tempbias_opts {
	int order;              /**< polynomial order 0..4; -1 (or
				     order_auto): chosen by the F test */
	bool order_auto;        /**< choose the order (as order = -1) */
	bool ref_temp_set;      /**< use ref_temp_degc (else mid-range) */
	double ref_temp_degc;   /**< T_ref, degC */
	double block_s;         /**< pre-averaging block, s (0: 1 s) */
	double smooth_s;        /**< temperature smoothing / dT/dt window,
				     s (0: 60 s) */
	double bin_degc;        /**< temperature bin, degC (0: span / 100) */
	/** heating/cooling by the rate: dead band of dT/dt, degC/s; 0 with
	 *  rate_deadband: 10 % of the 95th percentile of |dT/dt|; 0 without:
	 *  by turning points (the state changes at a temperature extremum
	 *  once the temperature has left it by max(0.2 degC, 2 % of the
	 *  span)) */
	double deadband_degc_s;
	bool rate_deadband;
	bool no_hysteresis;     /**< leave the eta term out */
	bool no_gradient;       /**< leave the g term out */
	bool warmup_set;        /**< drop warmup_s from each run (else the
				     warm-up is detected) */
	double warmup_s;        /**< s */
	double min_span_degc;   /**< refuse a smaller span, degC (0: 1 degC) */
	double alpha;           /**< F-test level (0: 0.01) */
	double table_step_degc; /**< compensation table step (0: 1, 2 or 5
				     degC giving <= 40 rows) */
};

/** Per-run outcome. */
struct sscope_tempbias_runinfo {
	double warmup_s;     /**< warm-up dropped, s */
	double offset;       /**< settled bias d_j at T_ref, U */
	double offset_sd;    /**< its standard deviation, U */
	double mean_temp_degc; /**< mean temperature used, degC */
	size_t used;         /**< samples used */
};

/** A bin of the fit (for plots and tables). */
struct sscope_tempbias_bin {
	double temp_degc;  /**< mean smoothed temperature, degC */
	double bias;       /**< mean bias, U */
	double dtdt;       /**< mean dT/dt, degC/s */
	double resid;      /**< bias minus the fitted model, U */
	double n;          /**< samples */
	int state;         /**< +1 heating, -1 cooling, 0 undecided */
	int run;           /**< run index */
};

/** Result of sscope_tempbias_fit(). */
struct sscope_tempbias_result {
	int order;               /**< polynomial order used */
	int order_requested;     /**< -1 for auto */
	int order_cap;           /**< cap from the span and the levels */
	int levels;              /**< distinct temperature levels: cells of
				      span / 20 holding >= 1 % of the data */
	bool order_lowered;      /**< requested order not possible */
	char note[200];          /**< why an order was lowered / terms left out */
	double ref_temp_degc;    /**< T_ref, degC */
	double half_span_degc;   /**< h, degC */
	double temp_min_degc, temp_max_degc; /**< range of the fitted bins */
	/** b(T) = sum_k coef[k] (T - T_ref)^k (k = 0..order), U/degC^k;
	 *  coef[0] is the mean of the runs' settled biases */
	double coef[SSCOPE_TEMPBIAS_MAX_ORDER + 1];
	double coef_sd[SSCOPE_TEMPBIAS_MAX_ORDER + 1]; /**< sd of coef */
	double dof;              /**< degrees of freedom of the fit */
	bool have_hysteresis;    /**< eta fitted */
	double hysteresis;       /**< 2 eta: heating minus cooling, U */
	double hysteresis_sd;    /**< U */
	/** separate heating and cooling fits (gradient term removed): max
	 *  |b_heat - b_cool| over their common range and where, U / degC */
	double hysteresis_max, hysteresis_at_degc;
	bool have_split;
	double heat_coef[SSCOPE_TEMPBIAS_MAX_ORDER + 1];
	double cool_coef[SSCOPE_TEMPBIAS_MAX_ORDER + 1];
	/** the hysteresis and gradient columns are (nearly) collinear:
	 *  variance inflation factor of the gradient term above
	 *  SSCOPE_TEMPBIAS_VIF_MAX (ramps of one rate up and one rate down:
	 *  dT/dt = a + b s); the gradient term is then left out and
	 *  hysteresis is the combined heating - cooling gap 2 eta + g (r_heat
	 *  + r_cool) at the profile's rates */
	bool hyst_grad_collinear;
	double hyst_grad_vif;    /**< that factor (NaN: not computed) */
	double rate_heat_degc_s; /**< mean dT/dt while heating, degC/s */
	double rate_cool_degc_s; /**< mean dT/dt while cooling, degC/s */
	bool have_gradient;      /**< g fitted */
	double gradient;         /**< g, U per degC/s */
	double gradient_sd;      /**< U per degC/s */
	double deadband_degc_s;  /**< rate dead band used, NaN: turning points */
	double turn_band_degc;   /**< turning-point band, degC */
	double smooth_s, block_s, bin_degc; /**< choices used */
	double residual_rms;     /**< RMS of block residuals, U */
	double sensitivity;      /**< db/dT at T_ref = coef[1], U/degC;
				      NaN at order 0 (none resolved) */
	double sensitivity_sd;
	double peak_to_peak;     /**< of the polynomial over the range, U;
				      NaN at order 0 */
	size_t n_runs;
	struct sscope_tempbias_runinfo *runs;
	double repeat_sd;        /**< sd (n-1) of the settled biases, U */
	double repeat_range;     /**< max - min of them, U */
	/** in-run stability: minimum overlapping Allan deviation of the
	 *  block residuals of the longest run (analysis/allan.c), U, and
	 *  its tau, s (NaN when too short) */
	double stability, stability_tau_s;
	size_t n_bins;
	struct sscope_tempbias_bin *bins;
	size_t n_table;          /**< compensation table rows */
	double *table_temp_degc; /**< grid, degC */
	double *table_bias;      /**< b(T) on the grid, U */
	size_t used, dropped;    /**< samples used / dropped (warm-up, NaN) */
};

/**
 * Fit the temperature model to one or more runs.
 * @param runs    records; all must share the unit U.
 * @param n_runs  1 .. SSCOPE_TEMPBIAS_MAX_RUNS.
 * @param opts    options (NULL: defaults).
 * @param res     receives the result; free with
 *                sscope_tempbias_result_free().
 * @param diag    optional detail of a refusal.
 * @return 0; -EINVAL (NULL pointer, no runs, rate not positive, bad
 *         option); -EDOM (temperature span below min_span_degc with one
 *         run, too few samples or bins for any fit, non-finite
 *         temperatures only); -ERANGE (samples or temperatures beyond
 *         2^+-250); -ENOMEM.
 */
int sscope_tempbias_fit(const struct sscope_tempbias_run *runs, size_t n_runs,
			const struct sscope_tempbias_opts *opts,
			struct sscope_tempbias_result **res,
			struct sscope_diag *diag);

/**
 * The fitted polynomial at @p temp_degc, clamped to the fitted range.
 * @return b(T), U (NaN for a NULL result).
 */
double sscope_tempbias_eval(const struct sscope_tempbias_result *res,
			    double temp_degc);

/** Free a result (NULL is ignored). */
void sscope_tempbias_result_free(struct sscope_tempbias_result *res);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_TEMPBIAS_H */
