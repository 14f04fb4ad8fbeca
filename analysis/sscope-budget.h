/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-budget.h
 * @brief Drift budget: navigation error against time from each sensor
 *        error source (textbook eqs 95-101).
 *
 * One horizontal channel of a strapdown navigator, errors small and
 * independent.  With g gravity, R the Earth's radius and
 * omega_s = sqrt(g/R) the Schuler frequency (period 84.4 min):
 *
 * | source | open loop (t << 1/omega_s) | Schuler-bounded |
 * |---|---|---|
 * | gyro bias b | att b t, vel g b t^2/2, pos g b t^3/6 | att (b/w) sin wt, vel R b (1 - cos wt), pos R b (t - sin(wt)/w) |
 * | accel bias b | att 0, vel b t, pos b t^2/2 | att (b/g)(1 - cos wt), vel (b/w) sin wt, pos (b/w^2)(1 - cos wt) |
 * | ARW N (1 sigma) | att N sqrt(t), vel g N sqrt(t^3/3), pos g N sqrt(t^5/20) | integrals of the Schuler impulse responses (budget.c) |
 * | VRW N (1 sigma) | vel N sqrt(t), pos N sqrt(t^3/3) | idem |
 * | scale factor | a gyro bias s_g * turn rate plus an accel bias s_a * acceleration of the motion profile |
 *
 * The total is the root sum of squares of the sources (biases taken as
 * 1-sigma values of random constants).
 */
#ifndef SSCOPE_BUDGET_H
#define SSCOPE_BUDGET_H

#include "sscope-core.h"
#include "sscope-quantity.h"
#include "sscope-calib.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Mean Earth radius used for the Schuler frequency, m. */
#define SSCOPE_BUDGET_EARTH_RADIUS_M 6371000.0

/** Error sources of the budget (JSON names in sscope_budget_source_name). */
enum sscope_budget_source {
	SSCOPE_BUDGET_GYRO_BIAS = 0, /**< "gyro_bias" */
	SSCOPE_BUDGET_ACCEL_BIAS,    /**< "accel_bias" */
	SSCOPE_BUDGET_ARW,           /**< "arw" (angle random walk) */
	SSCOPE_BUDGET_VRW,           /**< "vrw" (velocity random walk) */
	SSCOPE_BUDGET_SCALE_FACTOR,  /**< "scale_factor" */
	SSCOPE_BUDGET_N_SOURCES
};

/** Which formulas. */
enum sscope_budget_model {
	SSCOPE_BUDGET_AUTO = 0,  /**< open loop up to switch_time_s, then
				      Schuler-bounded */
	SSCOPE_BUDGET_OPEN_LOOP, /**< open loop at every time */
	SSCOPE_BUDGET_SCHULER    /**< Schuler-bounded at every time */
};

/** Inputs, SI.  Zero switches a source off. */
struct sscope_budget_params {
	double gyro_bias_rad_s;
	double accel_bias_m_s2;
	double arw_rad_sqrt_s;     /**< angle random walk N, rad/sqrt(s) */
	double vrw_m_s_sqrt_s;     /**< velocity random walk N, m/s/sqrt(s) */
	double gyro_sf;            /**< gyro scale-factor error, ratio */
	double accel_sf;           /**< accelerometer scale-factor error, ratio */
	double turn_rate_rad_s;    /**< motion profile: sustained turn rate */
	double accel_profile_m_s2; /**< motion profile: sustained acceleration */
	double gravity_m_s2;       /**< 0 -> 9.80665 */
	double radius_m;           /**< 0 -> SSCOPE_BUDGET_EARTH_RADIUS_M */
	enum sscope_budget_model model;
	double switch_time_s;      /**< AUTO switch; 0 -> 300 s (the t^3 form
				        is then 0.7 % above the Schuler form) */
};

/** Errors of one source (1 sigma for the random walks). */
struct sscope_budget_point {
	double position_m;
	double velocity_m_s;
	double attitude_rad;
};

/** @return "gyro_bias", "accel_bias", "arw", "vrw", "scale_factor", or
 *          NULL for an unknown source. */
const char *sscope_budget_source_name(enum sscope_budget_source s);

/** @return true for the random-walk sources (values are 1 sigma). */
bool sscope_budget_source_random(enum sscope_budget_source s);

/** @return the Schuler angular frequency sqrt(g/R) of @p p, rad/s. */
double sscope_budget_schuler_rad_s(const struct sscope_budget_params *p);

/** @return whether @p p uses the Schuler-bounded form at @p t_s. */
bool sscope_budget_is_schuler(const struct sscope_budget_params *p,
			      double t_s);

/**
 * Error of one source at time @p t_s (absolute values).
 * @return 0; -EINVAL (NULL, t < 0, negative or non-finite inputs, unknown
 *         source).
 */
int sscope_budget_source_eval(const struct sscope_budget_params *p,
			      enum sscope_budget_source s, double t_s,
			      struct sscope_budget_point *out);

/** Root sum of squares of every source at @p t_s (scaled by the largest:
 *  no overflow of the squares).  @return as above; -ERANGE when a total
 *  is beyond the double range. */
int sscope_budget_total(const struct sscope_budget_params *p, double t_s,
			struct sscope_budget_point *out);

/**
 * The source with the largest position error at @p t_s.
 * @param position_m  receives that error, m (may be NULL; 0 when none).
 * @return the source, or -1 when every source is zero at @p t_s (or the
 *         parameters are invalid).
 */
int sscope_budget_dominant(const struct sscope_budget_params *p, double t_s,
			   double *position_m);

/** A change of the dominant source. */
struct sscope_budget_crossover {
	double t_s;                       /**< where it changes */
	enum sscope_budget_source from;   /**< dominant before */
	enum sscope_budget_source to;     /**< dominant after */
};

/**
 * Times in [t0_s, t1_s] where the dominant source changes: a log-spaced
 * scan (ratio 1.01) finds each change, 60 bisection steps place it (the
 * first time the new source dominates, to about 1e-18 relative).
 * @param out    receives up to @p max changes, in time order.
 * @param n_out  receives the number written.
 * @return 0; -EINVAL (NULL, t0_s <= 0, t1_s < t0_s).
 */
int sscope_budget_crossovers(const struct sscope_budget_params *p,
			     double t0_s, double t1_s,
			     struct sscope_budget_crossover *out, size_t max,
			     size_t *n_out);

/**
 * Budget sources from the measured noise terms of one sensor axis (an
 * Allan fit, a datasheet): for a gyro (@p q angular rate) N is the angle
 * random walk and B the gyro bias (bias instability taken as a 1-sigma
 * bias), for an accelerometer the velocity random walk and the
 * accelerometer bias.  Several axes: call once per axis; each source keeps
 * the worst (largest) value.  Non-finite values are ignored.
 * @param n_si  N, rad/s/sqrt(Hz) or m/s^2/sqrt(Hz) (NaN: none).
 * @param b_si  B, rad/s or m/s^2 (NaN: none).
 * @param keep  sources to leave alone (bit 1 << source: given otherwise).
 * @param used  receives whether the axis counts (a gyro or an
 *              accelerometer with a source not kept); may be NULL.
 * @return the sources whose value this axis raised (bits 1 << source).
 */
unsigned sscope_budget_take_noise(struct sscope_budget_params *p,
				  enum sscope_quantity q, double n_si,
				  double b_si, unsigned keep, bool *used);

/**
 * Budget sources from what a calibration leaves: the 1-sigma uncertainty
 * of the bias (bias_sd through the scale, output SI) as the bias, the
 * relative uncertainty of the scale factor (scale_sd / scale) as the
 * scale-factor error, and the noise density as the random walk; the worst
 * axis of the triad counts, and of several triads (call once per triad).
 * @param q              the triad's output quantity.
 * @param noise_density  its noise density, SI/sqrt(Hz) (NaN: none).
 * @param keep           as sscope_budget_take_noise() (the scale factor
 *                       is always raised to the worst value).
 * @return the sources raised (bias and random walk only), as above.
 */
unsigned sscope_budget_take_calib(struct sscope_budget_params *p,
				  enum sscope_quantity q,
				  const struct sscope_calib_triad *c,
				  double noise_density, unsigned keep);

/** Which error of a point. */
enum sscope_budget_quantity {
	SSCOPE_BUDGET_POSITION = 0,
	SSCOPE_BUDGET_VELOCITY,
	SSCOPE_BUDGET_ATTITUDE
};

/**
 * First time at which a source (or the total, @p source < 0) reaches
 * @p target (log-spaced scan from 1e-3 s, then bisection to 1e-9
 * relative).
 * @param t_max_s  search limit, s.
 * @param t_s      receives the time.
 * @return 0; -EDOM when the error stays below target up to t_max_s;
 *         -EINVAL.
 */
int sscope_budget_time_to(const struct sscope_budget_params *p, int source,
			  enum sscope_budget_quantity what, double target,
			  double t_max_s, double *t_s);

/** Monte-Carlo check of a random-walk term. */
struct sscope_budget_mc_opts {
	bool gyro;             /**< true: ARW (walk = attitude); false: VRW
				    (walk = velocity) */
	double strength;       /**< N: rad/sqrt(s) or m/s/sqrt(s) */
	double gravity_m_s2;   /**< 0 -> 9.80665 (ARW position chain) */
	double t_end_s;        /**< simulated span */
	size_t steps;          /**< time steps over t_end_s */
	size_t realisations;   /**< independent runs */
	unsigned long seed;    /**< GSL MT19937 seed */
};

/** Monte-Carlo statistics at one time. */
struct sscope_budget_mc_point {
	double t_s;             /**< the time asked (the grid is split there) */
	double walk_sd;         /**< sample sd of the walk (attitude or
				     velocity) over the realisations */
	double walk_sd_theory;  /**< N sqrt(t) */
	double walk_inside;     /**< fraction with |walk| <= 2 N sqrt(t) */
	double pos_sd;          /**< sample sd of the position error */
	double pos_sd_theory;   /**< open-loop closed form */
	double pos_inside;      /**< fraction inside +-2 pos_sd_theory */
};

/**
 * Integrate @p o->realisations seeded white-noise realisations through the
 * open-loop chain (ARW: attitude -> g * attitude -> velocity -> position;
 * VRW: velocity -> position) with the exact discrete transition (the
 * state increments over a step are drawn jointly from their covariance),
 * on a uniform grid of @p o->steps steps split at each of @p times (any
 * order), and measure the fraction inside +-2 sigma at those times.  The
 * expected fraction is erf(sqrt(2)) = 0.9545; its binomial sd is
 * sqrt(0.9545 * 0.0455 / realisations).
 * @param paths   optional (NULL): receives the walk of the first
 *                @p n_paths realisations, (steps + 1) values each.
 * @return 0; -EINVAL (zero steps or realisations, t_end <= 0, strength
 *         <= 0, a time outside (0, t_end]); -ENOMEM.
 */
/**
 * What sscope_budget_mc()'s fractions should be: a Gaussian walk stays
 * inside +-2 sigma with probability erf(sqrt(2)) = 0.9545, and a fraction
 * over @p realisations runs has the binomial sd sqrt(p (1 - p) / runs).
 * @param sd  receives that sd (may be NULL; NaN for no runs).
 * @return the expected fraction.
 */
double sscope_budget_mc_expected(size_t realisations, double *sd);

int sscope_budget_mc(const struct sscope_budget_mc_opts *o,
		     const double *times, size_t n_times,
		     struct sscope_budget_mc_point *out, double *paths,
		     size_t n_paths);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_BUDGET_H */
