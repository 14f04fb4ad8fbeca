/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-adc.h
 * @brief Analog-to-digital converter models: a spec read from INI, a
 *        seeded digitizer (rate-rounding and integrating modes, noise,
 *        offset/gain, INL/DNL), the analytical terms that decide whether a
 *        converter degrades a sensor (quantization noise, dither, drift,
 *        headroom, minimum word length), and IEEE Std 1241-2010 converter
 *        tests from a sine record (sine fits, SINAD, ENOB, THD, SFDR,
 *        code-density DNL/INL).
 *
 * Quantities: the converter's input range is in volts (an analog front end
 * of a sensor with a sensitivity in V per sensor unit) or directly in the
 * sensor's SI unit U (rad/s, m/s^2: a converter inside a digital sensor).
 * "Range units" below means volts or U accordingly.
 */
#ifndef SSCOPE_ADC_H
#define SSCOPE_ADC_H

#include "sscope-core.h"
#include "sscope-quantity.h"
#include "sscope-unit.h"
#include "sscope-sensor.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSCOPE_ADC_MAX_BITS 32   /**< largest word length modelled */
#define SSCOPE_ADC_TABLE_BITS 20 /**< INL/DNL tables up to this length */

/** How samples leave the converter. */
enum sscope_adc_mode {
	/** every sample is rounded to a code: white rate noise q^2 / 12 */
	SSCOPE_ADC_ROUND = 0,
	/** the integral (angle / velocity increments) is counted with the
	 *  residual carried forward: white angle noise, IEEE Q term */
	SSCOPE_ADC_INTEGRATE
};

/** Reference of the converter. */
enum sscope_adc_reference {
	SSCOPE_ADC_ABSOLUTE = 0,  /**< its own reference: drift is scale error */
	SSCOPE_ADC_RATIOMETRIC    /**< shares the sensor's supply: drift cancels */
};

/** Fields given in a spec (bit mask). */
enum {
	SSCOPE_ADC_HAS_RATE = 1u << 0,
	SSCOPE_ADC_HAS_NOISE = 1u << 1,
	SSCOPE_ADC_HAS_ENOB = 1u << 2,
	SSCOPE_ADC_HAS_INL = 1u << 3,
	SSCOPE_ADC_HAS_DNL = 1u << 4,
	SSCOPE_ADC_HAS_OFFSET_DRIFT = 1u << 5,
	SSCOPE_ADC_HAS_GAIN_DRIFT = 1u << 6,
};

/** A converter specification (SI; range units as the file header says). */
struct sscope_adc_spec {
	char name[64];
	int bits;                 /**< word length, 1..SSCOPE_ADC_MAX_BITS */
	double lo, hi;            /**< input range, range units (lo < hi) */
	bool analog;              /**< range in volts (else sensor units) */
	enum sscope_quantity quantity; /**< of the range (VOLTAGE, ...) */
	unsigned has;             /**< SSCOPE_ADC_HAS_* */
	double rate_hz;           /**< sample rate, Hz (0: not given) */
	double noise;             /**< input-referred noise, rms, range units */
	double enob;              /**< effective bits (0: not given) */
	double inl_lsb;           /**< INL bound, LSB (>= 0) */
	double dnl_lsb;           /**< DNL bound, LSB (>= 0, < 1) */
	double offset;            /**< offset error, range units */
	double gain_error;        /**< gain error, ratio */
	double offset_drift;      /**< range units per degC */
	double gain_drift;        /**< ratio per degC (reference and gain) */
	double ref_temp_degc;     /**< temperature of zero drift, degC */
	enum sscope_adc_reference reference;
	enum sscope_adc_mode mode;
	char coding[24];          /**< "twos-complement", "offset-binary", ... */
	/** conversions per output sample (>= 1; 0 counts as 1): the converter
	 *  samples at oversample * rate and averages blocks of that many */
	unsigned oversample;
	/** inl_profile: file of the INL of every transition, LSB, as written
	 *  in the spec ("" when none); relative to the spec file's directory.
	 *  The library does no I/O: the caller reads it and passes it to
	 *  sscope_adc_set_inl() after sscope_adc_new(). */
	char inl_profile[256];
};

/** @return the keys an [adc] section may hold (NULL-terminated). */
const char *const *sscope_adc_spec_keys(void);

/** Load the [adc] section of a file.  @return as above, -errno. */
int sscope_adc_spec_load(const char *path, struct sscope_adc_spec *spec,
			 struct sscope_diag *diag);

/**
 * Parse a range "LO:HI [UNIT]" (e.g. "-2.5:2.5 V", "-100:100 deg/s").
 * @param unit  receives the unit (dimensionless when none is written).
 * @return 0 or -EINVAL (syntax, lo >= hi, a unit on each side that differ).
 */
int sscope_adc_range_parse(const char *text, double *lo_si, double *hi_si,
			   struct sscope_unit *unit, struct sscope_diag *diag);

/* ------------------------------------------------------------------ */
/* Digitizer                                                           */
/* ------------------------------------------------------------------ */

/** A converter between the sensor's SI unit U and codes. */
struct sscope_adc;

/**
 * Make a digitizer.  For an analog converter, the front end maps U to
 * volts as v = zero_v + sensitivity * x; for a converter in sensor units
 * sensitivity is 1 and zero_v 0.  Codes are mid-tread: code k covers
 * [lo + (k - 1/2) q, lo + (k + 1/2) q), k = 0 .. 2^bits - 1, q =
 * (hi - lo) / 2^bits, and decodes to lo + k q; INL/DNL bounds become a
 * seeded table of transition levels (bits <= SSCOPE_ADC_TABLE_BITS).
 * @param sensitivity  V per U (analog), > 0; ignored otherwise.
 * @param zero_v       front-end output at zero input, V (analog).
 * @param seed         seed of the converter's noise and non-linearity.
 * @return 0, -EINVAL, -ENOMEM.
 */
int sscope_adc_new(struct sscope_adc **adc, const struct sscope_adc_spec *spec,
		   double sensitivity, double zero_v, uint64_t seed,
		   struct sscope_diag *diag);

/** Free (NULL is ignored). */
void sscope_adc_free(struct sscope_adc *adc);

/** @return the LSB in sensor units U. */
double sscope_adc_lsb(const struct sscope_adc *adc);

/**
 * Replace the transition levels by the ideal ones plus an INL profile:
 * transition k (between codes k - 1 and k, k = 1 .. 2^bits - 1) at
 * lo + (k - 1/2 + inl_lsb[k]) q.  inl_lsb[0] is ignored.
 * @return 0, -EINVAL (bits above SSCOPE_ADC_TABLE_BITS, n != 2^bits,
 *         non-monotonic levels), -ENOMEM.
 */
int sscope_adc_set_inl(struct sscope_adc *adc, const double *inl_lsb, size_t n);

/**
 * Digitize @p n samples x (U) at rate_hz: front end, offset and gain
 * error (with drift at @p temp_degc when given), input noise, the
 * transfer function, clipping; the output is the decoded value back in U.
 * In integrating mode the running integral is counted in steps of q /
 * rate_hz with the residual carried between samples and calls (reset with
 * sscope_adc_reset()).
 * @param codes      optional: receives the codes (NULL: not wanted).
 * @param temp_degc  optional temperatures (NULL: ref_temp).
 * @param clipped    optional: incremented per clipped sample.
 * @return 0, -EINVAL.
 */
int sscope_adc_digitize(struct sscope_adc *adc, const double *x, size_t stride,
			size_t n, double rate_hz, const double *temp_degc,
			double *out, int64_t *codes, size_t *clipped);

/** Restart noise and the integrating residual. */
void sscope_adc_reset(struct sscope_adc *adc);

/* ------------------------------------------------------------------ */
/* Analytical terms                                                     */
/* ------------------------------------------------------------------ */

/** Verdicts. */
enum sscope_adc_verdict {
	SSCOPE_ADC_PASS = 0,
	SSCOPE_ADC_MARGINAL,
	SSCOPE_ADC_FAIL,
	SSCOPE_ADC_INFO /**< no sensor figure to compare with */
};

/** @return "pass", "marginal", "fail" or "info". */
const char *sscope_adc_verdict_name(enum sscope_adc_verdict v);

/** Terms of the report. */
enum sscope_adc_term {
	SSCOPE_ADC_T_NOISE = 0,   /**< quantization + converter noise vs N */
	SSCOPE_ADC_T_BIAS,        /**< dither bias bound vs B */
	SSCOPE_ADC_T_OFFSET_DRIFT, /**< offset drift over the temperature span */
	SSCOPE_ADC_T_SCALE_DRIFT, /**< reference/gain drift over the span */
	SSCOPE_ADC_T_RANGE,       /**< range headroom (clipping) */
	SSCOPE_ADC_T_COUNT_
};

/** @return "noise", "bias_resolution", "offset_drift", "scale_drift",
 *  "range" for a term. */
const char *sscope_adc_term_name(enum sscope_adc_term t);

/** One term: a value, the sensor's figure it is compared with, the ratio
 *  that the thresholds judge and the verdict. */
struct sscope_adc_term_result {
	double value;      /**< the converter's contribution (unit per term) */
	double reference;  /**< the sensor's figure (NaN: none) */
	double ratio;      /**< the judged ratio (see sscope_adc_analyze()) */
	double pass_limit; /**< ratio <= pass_limit passes (RANGE: >=) */
	double fail_limit; /**< ratio > fail_limit fails (RANGE: <) */
	enum sscope_adc_verdict verdict;
};

/** Everything sscope_adc_analyze() computes (SI, U the rate unit). */
struct sscope_adc_analysis {
	double lsb;             /**< q, U */
	double rate_hz;         /**< rate used, Hz */
	double sigma_sensor;    /**< per-sample sensor noise, U */
	double sigma_adc;       /**< per-sample converter noise, U */
	double sigma_over_q;    /**< (sensor + converter) noise / q */
	bool dithered;          /**< sigma >= q / 2 */
	double n_quant;         /**< quantization noise density q/sqrt(12 fs),
				     U/sqrt(Hz) (round mode; NaN otherwise) */
	double q_quant;         /**< IEEE Q of integrating mode q/(fs sqrt 12),
				     U s (NaN in round mode) */
	double n_adc;           /**< converter noise density, U/sqrt(Hz) */
	double n_total;         /**< sensor + converter noise density */
	double noise_degradation; /**< n_total / sensor N - 1 */
	double adev_q_100s;     /**< quantization ADEV at tau = 100 s, U */
	double bias_bound;      /**< (q/pi) exp(-2 pi^2 sigma^2 / q^2), U */
	double temp_span_degc;  /**< temperature span used, degC */
	bool temp_span_default; /**< the sensor gave none: 60 degC assumed */
	double offset_drift_bias; /**< offset drift * span, U (NaN: the spec gives none) */
	double scale_drift;     /**< gain/reference drift * span, ratio (NaN: none given) */
	double range_lo, range_hi; /**< converter range in U */
	double headroom;        /**< converter range / sensor range (>= 1 ok) */
	int min_bits;           /**< smallest word length whose word-length
				     terms (noise, bias) pass; -1: none <= 32 */
	struct sscope_adc_term_result term[SSCOPE_ADC_T_COUNT_];
	enum sscope_adc_verdict verdict; /**< worst term */
	enum sscope_adc_term limiting;   /**< term with the smallest margin */
	double margin;          /**< pass_limit / ratio of that term (> 1:
				     passes with room; RANGE: ratio / limit) */
};

/**
 * The analytical terms of a converter behind a sensor.
 *
 * - noise: n_total / N - 1 (noise-density degradation); pass <= 0.05,
 *   fail > 0.20.  n_quant = q / sqrt(12 fs) (AVAR q^2 / (12 fs tau));
 *   in integrating mode the quantization term is white angle noise
 *   (AVAR 3 Q^2 / tau^2, Q = q / (fs sqrt 12)), counted as the density
 *   sqrt(3) Q that gives the same AVAR at tau = 1 s, and it loses no bias
 *   (bias_bound 0: the residual is carried).
 * - bias_resolution: bias_bound / B with the Widrow-Kollar bound; pass
 *   <= 0.1, fail > 0.5 (without B: info).
 * - offset_drift: offset drift * span / sensitivity over the sensor's own
 *   bias_tempco * span (or over B when it has none); pass <= 0.3, fail > 1.
 * - scale_drift: gain_drift * span (0 when ratiometric) over the sensor's
 *   scale_factor_error; pass <= 0.3, fail > 1 (without it: info).
 * - range: converter range / sensor range; pass >= 1, fail < 1 (clips).
 * With oversampling M every per-sample figure is taken at the conversion
 * rate M fs and the densities follow from it (n_quant = q/sqrt(12 M fs)
 * when dithered; averaging does not recover a bias the quantizer loses).
 * Per-sample sensor noise: N sqrt(2 NBW), NBW = min(fs/2, bandwidth *
 * k(order)) with k = pi/2, 1.1107, 1.0262 (1-pole, 2nd-, 4th-order
 * Butterworth) -- N sqrt(fs) without a bandwidth.
 * @param rate_hz  sample rate (0: the spec's).
 * @return 0, -EINVAL (no rate, analog converter without a sensitivity).
 */
int sscope_adc_analyze(const struct sscope_sensor_spec *sensor,
		       const struct sscope_adc_spec *adc, double rate_hz,
		       struct sscope_adc_analysis *res,
		       struct sscope_diag *diag);

/** A ratio of the Monte-Carlo check over its runs. */
struct sscope_adc_mc_ratio {
	double mean;    /**< mean over the runs that gave a value */
	double lo, hi;  /**< mean -+ t s / sqrt(k), Student t with k - 1
			     degrees of freedom at the level asked (NaN with
			     fewer than two values) */
	size_t runs;    /**< runs that gave a value */
	double se;      /**< Monte-Carlo standard error of mean: s / sqrt(k),
			     s the sample sd over the k runs (NaN with fewer
			     than two values) */
};

/** Options of sscope_adc_monte_carlo(). */
struct sscope_adc_mc_opts {
	size_t runs;          /**< simulated records (>= 1) */
	double duration_s;    /**< length of each record (>= 1000 samples) */
	unsigned long seed;   /**< run r simulates and converts with seed + r */
	double ci_level;      /**< level of the ratio intervals (0: 0.6827) */
	double rate_hz;       /**< output rate (0: the converter's) */
	/** called after each run with the runs done and their number (NULL:
	 *  none); from the calling thread */
	void (*progress)(void *ctx, size_t done, size_t total);
	void *progress_ctx;
};

/** What the Monte-Carlo check found. */
struct sscope_adc_mc {
	/** N, B, K fitted through the converter over the sensor alone
	 *  (SSCOPE_TERM_N + i for i = 0, 1, 2); a run whose fits lack the
	 *  term gives no value */
	struct sscope_adc_mc_ratio ratio[3];
	struct sscope_adc_mc_ratio bias_shift; /**< mean(through) - mean(alone), U */
	size_t clipped;       /**< converted samples clipped, all runs */
	size_t runs;
	double duration_s;    /**< of each record (whole samples) */
	double rate_hz;       /**< output rate used */
	/** ADEV of every run, alone and through the converter: run r at
	 *  dev_in[r * n_points + i], tau tau_s[i] (owned:
	 *  sscope_adc_mc_clear()); n_runs runs (each has the same grid) */
	double *tau_s, *dev_in, *dev_out;
	size_t n_points, n_runs;
};

/** Which curve of a Monte-Carlo result. */
enum sscope_adc_mc_curve {
	SSCOPE_ADC_MC_ALONE = 0, /**< ADEV of the sensor alone */
	SSCOPE_ADC_MC_THROUGH,   /**< ADEV through the converter */
	SSCOPE_ADC_MC_RATIO      /**< through / alone, run by run (the
				      sensor's own scatter cancels) */
};

/**
 * The 10, 50 and 90 % points over the runs of a Monte-Carlo curve at tau
 * point @p i (GSL quantiles of the sorted positive finite values).
 * @param q  receives them (NaN when no run has a value).
 * @return 0; -EINVAL (i out of range); -ENOMEM.
 */
int sscope_adc_mc_band(const struct sscope_adc_mc *mc,
		       enum sscope_adc_mc_curve which, size_t i, double q[3]);

/**
 * The Monte-Carlo check of a converter behind a sensor: each run simulates
 * the sensor (sscope_sim, constant temperature) at the conversion rate M
 * fs (M the spec's oversampling), digitizes it, averages blocks of M
 * samples of both (the sensor alone the same way), fits the Allan terms of
 * both records (sscope_allan_analyze, dense grid) and keeps the ratios of
 * N, B and K and the bias shift; the ratios' intervals are Student-t
 * intervals of the mean over the runs.
 * @param inl_lsb  optional INL profile of the converter (n_inl values,
 *                 sscope_adc_set_inl()), or NULL.
 * @param sensitivity, zero_v  the analog front end (sscope_adc_new()).
 * @return 0; -EINVAL (NULL, no runs, no rate); -EDOM (a record shorter
 *         than 1000 samples: diag says so); -ENOMEM; errors of the
 *         simulator, converter and Allan analysis.
 */
int sscope_adc_monte_carlo(const struct sscope_sensor_spec *sensor,
			   const struct sscope_adc_spec *spec,
			   const double *inl_lsb, size_t n_inl,
			   double sensitivity, double zero_v,
			   const struct sscope_adc_mc_opts *o,
			   struct sscope_adc_mc *out, struct sscope_diag *diag);

/** Free what a Monte-Carlo result owns (NULL is ignored). */
void sscope_adc_mc_clear(struct sscope_adc_mc *mc);

/**
 * Order converters for a selection: passing before marginal before
 * failing (and informational); among passing ones the fewest bits first
 * (the cheapest that passes); then the largest margin (a non-finite margin
 * counts as infinite).  A stable order.
 * @param an, bits  n converters' analyses and word lengths.
 * @param order     receives the indices 0..n-1 in rank order.
 */
void sscope_adc_rank(const struct sscope_adc_analysis *an, const int *bits,
		     size_t n, size_t *order);

/**
 * Widrow-Kollar bound of the mean error of a quantizer of step q under
 * Gaussian noise of sd sigma: (q/pi) exp(-2 pi^2 sigma^2 / q^2).
 */
double sscope_adc_dither_bound(double q, double sigma);

/**
 * Mean error of a mid-tread quantizer (levels at multiples of q) for a
 * Gaussian input of mean mu and sd sigma, to the first harmonic of its
 * Fourier series: -(q/pi) exp(-2 pi^2 sigma^2/q^2) sin(2 pi mu/q).  The
 * bias a quiet sensor loses (e.g. -0.168 deg/h of 0.37 deg/h at q = 10.99
 * deg/h, sigma/q = 0.273).
 */
double sscope_adc_bias_error(double q, double sigma, double mu);

/** NBW / f3dB of a Butterworth filter of order 1..8 (1-pole: pi/2). */
double sscope_adc_nbw_factor(int order);

/* ------------------------------------------------------------------ */
/* IEEE Std 1241 tests                                                 */
/* ------------------------------------------------------------------ */

/** A fitted sine x = A cos(w t) + B sin(w t) + C. */
struct sscope_adc_sine_fit {
	double freq_hz;
	double amplitude;  /**< sqrt(A^2 + B^2) */
	double phase_rad;  /**< x = amplitude cos(w t + phase) + offset */
	double offset;
	double a, b;
	double rms_residual; /**< NAD: rms of the residuals */
	int iterations;    /**< 4-parameter fit: solver iterations */
};

/**
 * Three-parameter fit (known frequency) by linear least squares (GSL).
 * @return 0, -EINVAL, -EDOM (n < 4), -ENOMEM.
 */
int sscope_adc_sine_fit3(const double *x, size_t n, double rate_hz, double freq_hz,
			 struct sscope_adc_sine_fit *fit);

/**
 * Four-parameter fit: start from the interpolated FFT peak (FFTW) and a
 * three-parameter fit, then Levenberg-Marquardt (gsl_multifit_nlinear).
 * @param freq_hz  starting frequency (0: from the spectrum).
 * @return 0, -EINVAL, -EDOM, -ENOMEM, -ERANGE (no convergence).
 */
int sscope_adc_sine_fit4(const double *x, size_t n, double rate_hz, double freq_hz,
			 struct sscope_adc_sine_fit *fit);

/** Results of a dynamic test. */
struct sscope_adc_dynamic {
	struct sscope_adc_sine_fit fit; /**< four-parameter fit */
	double sinad_db;  /**< 20 log10((A/sqrt2) / NAD) */
	double enob;      /**< log2(FSR / (NAD sqrt 12)), or (SINAD - 1.76)
			       / 6.02 when no FSR was given */
	double thd_db;    /**< harmonics 2..10 over the fundamental (dB) */
	double sfdr_db;   /**< fundamental over the largest spur (dB) */
	double snr_db;    /**< SINAD without the harmonics (dB) */
};

/**
 * SINAD, ENOB, THD, SFDR of a sine record (IEEE 1241 sections 7-8).
 * Spectrum: 4-term Blackman-Harris window, FFTW; a tone takes +-4 bins.
 * @param fsr  full-scale range (hi - lo) in the unit of x, or 0.
 * @return as sscope_adc_sine_fit4(); -ERANGE for samples beyond 2^+-250.
 */
int sscope_adc_dynamic_test(const double *x, size_t n, double rate_hz,
			    double fsr, struct sscope_adc_dynamic *res);

/**
 * The codes an ideal mid-tread converter gives for decoded values:
 * k = floor((x - lo) / q + 1/2) with q = (hi - lo) / n_codes, clamped to
 * 0 .. n_codes - 1 (the inverse of decoding to lo + k q).
 * @param x        n values in the unit of lo and hi, x[i * stride].
 * @param codes    receives n codes.
 * @param clipped  optional: receives how many values were clamped.
 * @return 0, -EINVAL (NULL, stride 0, n_codes < 2, hi <= lo or not
 *         finite), -EDOM (a sample is NaN or infinite).
 */
int sscope_adc_codes(const double *x, size_t stride, size_t n, double lo,
		     double hi, size_t n_codes, int64_t *codes, size_t *clipped);

/**
 * Code-density (histogram) test with a sine (IEEE 1241 section 6.3):
 * transition levels from the cumulative histogram, T_k = -cos(pi CH_{k-1}
 * / S), gain and offset removed by a least-squares line over the codes
 * that were hit from both sides; DNL_k = width_k / mean width - 1, INL_k =
 * (T_k - line_k) in LSB.
 * @param codes  n codes in 0 .. n_codes - 1.
 * @param dnl    receives n_codes values (NaN at the end codes), LSB.
 * @param inl    receives n_codes values (transition k), LSB (NaN: unknown).
 * @param dnl_max, inl_max  receive the largest magnitudes (may be NULL).
 * @return 0, -EINVAL, -EDOM (fewer than 3 codes hit), -ENOMEM.
 */
int sscope_adc_histogram_test(const int64_t *codes, size_t n, size_t n_codes,
			      double *dnl, double *inl, double *dnl_max,
			      double *inl_max);

/** How well a histogram test's counts resolve DNL (IEEE 1241 section
 *  6.4: the count of a mid-scale code of a sine histogram is binomial,
 *  mean 2 S / (pi n), so DNL there has sd sqrt(pi n / (2 S)) LSB). */
struct sscope_adc_hist_quality {
	size_t codes_spanned;    /**< n: highest minus lowest code hit, + 1 */
	double samples_per_code; /**< S / n */
	double dnl_sd_lsb;       /**< sd of a mid-scale DNL estimate, LSB */
	/** samples for dnl_sd_lsb = tolerance: pi n / (2 tol^2) (IEEE 1241's
	 *  pi 2^(N-1) Z^2 / beta^2 with Z = 1) */
	double samples_needed;
	bool resolved;           /**< dnl_sd_lsb <= tolerance */
};

/**
 * Whether @p n codes hold enough samples for the histogram test to
 * resolve DNL to @p dnl_tol_lsb (1 sigma).
 * @param codes       n codes (any values; only min and max are used).
 * @param dnl_tol_lsb wanted DNL standard deviation, LSB (> 0).
 * @param q           receives the assessment.
 * @return 0, -EINVAL (NULL, n = 0, tolerance not positive).
 */
int sscope_adc_histogram_quality(const int64_t *codes, size_t n,
				 double dnl_tol_lsb,
				 struct sscope_adc_hist_quality *q);


#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_ADC_H */
