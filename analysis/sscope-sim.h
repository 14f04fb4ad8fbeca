/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-sim.h
 * @brief Streaming simulator of a gyro or accelerometer axis that obeys a
 *        sensor specification (IEEE Std 952 noise terms, bias, scale
 *        factor, temperature dependence, vibration tones, quantization).
 *
 * With U the rate unit of the spec (rad/s for a gyro, m/s^2 for an
 * accelerometer), sample i of a stream is
 *
 *   out = (1 + sf) * input + bias + bias(T) + hyst(T) + g * dT/dt
 *         + q + n + b + k + R t + sum_j A_j sin(2 pi f_j t + phi_j)
 *
 * then rounded to a multiple of quant_step (mid-tread) and clipped to
 * +-range, with t = i / rate_hz from the first sample of the stream and
 * T the temperature of the profile:
 * - q: angle quantization Q (U s): white angle noise of sd Q,
 *   differentiated, AVAR 3 Q^2 / tau^2;
 * - n: white rate noise of density N (U/sqrt(Hz)): per-sample sd
 *   N sqrt(rate_hz), AVAR N^2 / tau;
 * - b: bias instability B (U) as flicker rate noise: a sum of first-order
 *   Gauss-Markov (AR(1)) processes with correlation times spaced by
 *   10^(2/3) from flicker_tau_min_s to flicker_tau_max_s, each of variance
 *   B^2 ln(10^(2/3)) / pi, whose spectrum approximates B^2 / (pi f): its
 *   Allan variance (sscope_sim_avar() gives it exactly) is the plateau
 *   (2 ln2 / pi) B^2 within 0.7 % from 100 flicker_tau_min_s to
 *   flicker_tau_max_s / 100; with the default band (the sample period to
 *   1e6 s, rates of 1 Hz and more) within 0.5 % there, within 2 % from
 *   20 flicker_tau_min_s to flicker_tau_max_s / 30 and within 7 % from
 *   flicker_tau_min_s (white rate noise usually dominates there anyway);
 *   a later band start rolls off more below 100 flicker_tau_min_s;
 * - k: rate random walk K (U/s/sqrt(Hz)): increments of sd K sqrt(dt),
 *   AVAR K^2 tau / 3 + K^2 dt^2 / (6 tau);
 * - R t: rate ramp R (U/s), AVAR R^2 tau^2 / 2.
 *
 * Random numbers: GSL's MT19937, one generator per noise term and stream,
 * seeded with a 32-bit SplitMix64 hash of (seed, stream, term) so that
 * streams and terms are independent and switching a term on or off does
 * not change the others; Gaussian deviates by the ziggurat method.
 * Not simulated: the output filter of the spec (bandwidth, filter_order),
 * analog sensitivity and zero output, cross-axis effects.
 */
#ifndef SSCOPE_SIM_H
#define SSCOPE_SIM_H

#include "sscope-core.h"
#include "sscope-sensor.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSCOPE_SIM_MAX_TONES 8 /**< vibration tones per stream */
#define SSCOPE_SIM_MAX_POLY 4  /**< order of the bias polynomial */

/** Temperature profile. */
enum sscope_sim_temp {
	SSCOPE_SIM_TEMP_CONSTANT = 0, /**< temp_degc throughout */
	/** temp_degc + temp_rate_degc_s * t, held at temp2_degc once reached */
	SSCOPE_SIM_TEMP_RAMP,
	/** between temp_degc and temp2_degc with period temp_period_s,
	 *  starting at temp_degc (temp_wave: sine or triangle) */
	SSCOPE_SIM_TEMP_CYCLE,
	/** the caller gives the temperature of every sample in the temp_degc
	 *  array of sscope_sim_generate() (read, not written) */
	SSCOPE_SIM_TEMP_GIVEN
};

/** Shape of a temperature cycle. */
enum sscope_sim_wave {
	SSCOPE_SIM_SINE = 0,  /**< raised cosine */
	SSCOPE_SIM_TRIANGLE   /**< constant |dT/dt| */
};

/** A vibration tone added to the output. */
struct sscope_sim_tone {
	double freq_hz;   /**< frequency, Hz (>= 0, < rate_hz / 2) */
	double amplitude; /**< peak amplitude, U */
	double phase_rad; /**< phase at t = 0, rad */
};

/** Options of a stream.  Zero-initialise, then set rate_hz and what you
 *  need: the zero profile is a constant 0 degC with T_ref = 0 degC. */
struct sscope_sim_opts {
	double rate_hz;  /**< sample rate, Hz (> 0) */
	uint64_t seed;   /**< seed of the experiment */
	uint64_t stream; /**< stream index (e.g. the axis): independent
			      streams of one seed */
	enum sscope_sim_temp temp_profile;
	double temp_degc;        /**< constant / start / low temperature, degC */
	double temp2_degc;       /**< ramp end / cycle high temperature, degC */
	double temp_rate_degc_s; /**< ramp slope, degC/s (any sign) */
	double temp_period_s;    /**< cycle period, s (> 0 for CYCLE) */
	enum sscope_sim_wave temp_wave; /**< cycle shape */
	/** sd of the noise on the reported temperature (not on the
	 *  temperature that drives the bias), degC */
	double temp_noise_degc;
	double ref_temp_degc; /**< T_ref of the bias polynomial, degC */
	/** bias(T) = sum_k bias_poly[k-1] (T - T_ref)^k, k = 1..4, in
	 *  U/degC^k; the spec's bias_tempco adds to the linear term */
	double bias_poly[SSCOPE_SIM_MAX_POLY];
	/** heating/cooling hysteresis: +hysteresis/2 (U) while dT/dt >
	 *  hysteresis_deadband_degc_s, -hysteresis/2 while dT/dt < -deadband,
	 *  the last state in between (0 before the first change) */
	double hysteresis;
	double hysteresis_deadband_degc_s; /**< degC/s, >= 0 */
	double gradient; /**< bias per temperature rate, U / (degC/s) */
	struct sscope_sim_tone tones[SSCOPE_SIM_MAX_TONES];
	size_t n_tones; /**< tones used */
	double quant_step; /**< output rounded to multiples of it, U; 0: off */
	/** correlation-time band of the flicker (B) model, s; 0 selects
	 *  1 / rate_hz and 1e6 s */
	double flicker_tau_min_s, flicker_tau_max_s;
	bool no_clip; /**< do not clip to the spec's range */
};

/** A simulation stream. */
struct sscope_sim;

/**
 * Make a stream.  Everything is allocated here; generate() allocates
 * nothing.
 * @param sim   receives the stream; free with sscope_sim_free().
 * @param spec  sensor specification (SI, see struct sscope_sensor_spec);
 *              copied.
 * @param opts  options; copied.
 * @param diag  optional detail of a refused parameter.
 * @return 0, -EINVAL (NULL, rate not positive, a negative noise term,
 *         too many tones, a tone at or above Nyquist, a bad temperature
 *         profile, a negative quantization step, a bad flicker band),
 *         -ENOMEM.
 */
int sscope_sim_new(struct sscope_sim **sim,
		   const struct sscope_sensor_spec *spec,
		   const struct sscope_sim_opts *opts,
		   struct sscope_diag *diag);

/**
 * The next @p n samples of the stream (state carries over between calls,
 * so any split of a record into calls gives the same samples).
 * @param input      true input (U) per sample, or NULL for zero.
 * @param out        receives n outputs, U.
 * @param temp_degc  receives the reported temperature (degC) per sample
 *                   (NULL: not wanted); with SSCOPE_SIM_TEMP_GIVEN it
 *                   holds the temperatures instead and must not be NULL.
 * @param n          number of samples.
 * @return 0, or -EINVAL (NULL out; NULL temp_degc with a given profile;
 *         a non-finite given temperature).
 */
int sscope_sim_generate(struct sscope_sim *sim, const double *input,
			double *out, double *temp_degc, size_t n);

/**
 * Generate @p n samples of several streams at once, in parallel (OpenMP)
 * when built with it: the same samples as calling generate() on each.
 * @param in, out, temp  arrays of n_sims pointers (in and temp may be NULL
 *                       as a whole, or hold NULL entries).
 * @return 0 or the first error of a stream.
 */
int sscope_sim_generate_multi(struct sscope_sim *const *sims, size_t n_sims,
			      const double *const *in, double *const *out,
			      double *const *temp, size_t n);

/** Restart the stream from sample 0 with its seeds (same output again). */
void sscope_sim_reset(struct sscope_sim *sim);

/** @return samples generated since creation or the last reset. */
uint64_t sscope_sim_position(const struct sscope_sim *sim);

/** @return outputs clipped to the range so far. */
uint64_t sscope_sim_clipped(const struct sscope_sim *sim);

/**
 * Exact Allan variance of the stream's noise terms (Q, N, B as simulated,
 * K, R; not bias, temperature, tones or quantization) at tau, for tau a
 * multiple of the sample period (rounded to the nearest, at least one).
 * @return AVAR, U^2.
 */
double sscope_sim_avar(const struct sscope_sim *sim, double tau_s);

/** Free (NULL is ignored). */
void sscope_sim_free(struct sscope_sim *sim);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_SIM_H */
