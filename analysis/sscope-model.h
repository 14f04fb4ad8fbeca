/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-model.h
 * @brief Sensor physics calculators (textbook section 5.1): the second-order
 *        proof-mass accelerometer and the Sagnac phase of a fibre-optic
 *        gyro.
 *
 * Accelerometer: a proof mass m on a spring k with damping c in a case
 * accelerated by a(t): m x'' + c x' + k x = m a (x the deflection relative
 * to the case, positive with a), so x'' + 2 zeta w_n x' + w_n^2 x = a with
 * w_n = sqrt(k/m), zeta = c / (2 sqrt(k m)); static deflection a / w_n^2.
 *
 * Fibre-optic gyro (interferometric, open loop): the Sagnac phase between
 * the two counter-propagating beams of a coil of N turns of radius R is
 * dphi = 8 pi^2 N R^2 Omega / (lambda c) = (2 pi L D / (lambda c)) Omega
 * with L = 2 pi R N the fibre length and D = 2 R the coil diameter.  (The
 * seed prints its eq. 92 without R^2 and lambda; this is the dimensionally
 * correct form.)  The open-loop output cos(dphi) biased to sin(dphi) is
 * unambiguous for |dphi| <= pi/2.
 */
#ifndef SSCOPE_MODEL_H
#define SSCOPE_MODEL_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Speed of light in vacuum, m/s (exact). */
#define SSCOPE_MODEL_SPEED_OF_LIGHT 299792458.0

/** Second-order accelerometer. */
struct sscope_model_accel {
	double mass_kg;           /**< NaN when built from fn and zeta */
	double stiffness_n_m;     /**< NaN when built from fn and zeta */
	double damping_n_s_m;     /**< NaN when built from fn and zeta */
	double omega_n_rad_s;     /**< natural angular frequency */
	double fn_hz;             /**< natural frequency */
	double zeta;              /**< damping ratio */
	double q_factor;          /**< 1 / (2 zeta) */
	double fd_hz;             /**< damped natural frequency (NaN if
				       zeta >= 1) */
	double bandwidth_hz;      /**< -3 dB frequency of |X/A| */
	double peak_gain;         /**< resonance peak of |X/A| / (1/w_n^2)
				       (1 when zeta >= 1/sqrt 2) */
	double displacement_per_g_m; /**< static deflection for 1 g */
	double overshoot;         /**< step overshoot, ratio (0 if zeta >= 1) */
	double rise_time_s;       /**< 10-90 % of the step */
	double settling_time_s;   /**< into +-2 % for good */
};

/**
 * Build from mass, stiffness and damping.
 * @param mass_kg        > 0, kg.
 * @param stiffness_n_m  > 0, N/m.
 * @param damping_n_s_m  > 0, N s/m.
 * @return 0, -EINVAL.
 */
int sscope_model_accel_mkc(double mass_kg, double stiffness_n_m,
			   double damping_n_s_m, struct sscope_model_accel *o);

/**
 * Build from the natural frequency and damping ratio (mass-free).
 * @param fn_hz  > 0, Hz.
 * @param zeta   > 0.
 * @return 0, -EINVAL.
 */
int sscope_model_accel_fn(double fn_hz, double zeta,
			  struct sscope_model_accel *o);

/**
 * Analytic step response: deflection x(t) for a step of @p a_m_s2 applied
 * at t = 0 to a mass at rest (under-, critically and over-damped forms).
 * @param t_s   n times, s (negative times give 0).
 * @param x_m   n deflections, m.
 * @return 0, -EINVAL.
 */
int sscope_model_accel_step(const struct sscope_model_accel *m, double a_m_s2,
			    const double *t_s, size_t n, double *x_m);

/**
 * The same step response by numerical integration (classical Runge-Kutta,
 * step @p dt_s), for cross-checking: x_m[i] at t = i dt.
 * @return 0, -EINVAL.
 */
int sscope_model_accel_step_rk4(const struct sscope_model_accel *m,
				double a_m_s2, double dt_s, size_t n,
				double *x_m);

/** The Runge-Kutta cross-check of the analytic step response. */
struct sscope_model_rk4_check {
	double dt_s;        /**< RK4 step: 1 / (400 fn), or longer so that at
			       most @p max_steps steps cover the span */
	size_t n;           /**< RK4 samples, at t = i dt_s */
	double max_dev_m;   /**< largest |analytic - RK4| where the grids
			       meet (every 1 + n/5000-th sample) */
};

/**
 * Integrate the step response over [0, t_end_s] by classical Runge-Kutta
 * on a grid of 400 steps per natural period (at most @p max_steps) and
 * compare it with sscope_model_accel_step().
 * @param x_m   receives the RK4 deflections (n values, caller frees with
 *              free()), or NULL to discard them.
 * @return 0; -EINVAL (t_end <= 0, max_steps < 3); -ENOMEM.
 */
int sscope_model_accel_rk4_check(const struct sscope_model_accel *m,
				 double a_m_s2, double t_end_s,
				 size_t max_steps, double **x_m,
				 struct sscope_model_rk4_check *chk);

/** Interferometric fibre-optic gyro coil. */
struct sscope_model_fog {
	double radius_m;
	double turns;
	double wavelength_m;
	double fibre_length_m;  /**< 2 pi R N */
	double scale_factor_s;  /**< dphi / Omega, rad per rad/s */
	double max_rate_rad_s;  /**< rate giving dphi = pi/2 */
};

/**
 * Coil parameters.
 * @param radius_m      > 0, m.
 * @param turns         > 0.
 * @param wavelength_m  > 0, m (vacuum).
 * @return 0, -EINVAL.
 */
int sscope_model_fog_coil(double radius_m, double turns, double wavelength_m,
			  struct sscope_model_fog *o);

/** @return the Sagnac phase, rad, at rate @p rate_rad_s. */
double sscope_model_fog_phase(const struct sscope_model_fog *f,
			      double rate_rad_s);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_MODEL_H */
