/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-vib.h
 * @brief Machinery vibration: velocity severity (ISO 10816 zones), shaft
 * orders, rolling-bearing defect frequencies, envelope analysis (Hilbert
 * transform through FFTW), kurtosis, and diagnosis findings with their
 * evidence.
 *
 * Input is acceleration in m/s^2 sampled at fs; results are SI (m/s^2,
 * m/s, Hz).  Finding texts quote conventional units (mm/s, Hz).
 */
#ifndef SSCOPE_VIB_H
#define SSCOPE_VIB_H

#include "sscope-core.h"
#include "sscope-psd.h"
#include "sscope-psd.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Rolling-bearing geometry. */
struct sscope_vib_bearing {
	unsigned n_elements;      /**< rolling elements n */
	double ball_diameter_m;   /**< d, m (any length unit, as D) */
	double pitch_diameter_m;  /**< D, m */
	double contact_angle_rad; /**< phi, rad */
};

/** Defect frequencies of a bearing at a shaft frequency fr. */
struct sscope_vib_bearing_freqs {
	double bpfo_hz; /**< (n/2) fr (1 - d/D cos phi), outer race */
	double bpfi_hz; /**< (n/2) fr (1 + d/D cos phi), inner race */
	double bsf_hz;  /**< (D/2d) fr (1 - (d/D cos phi)^2), ball spin */
	double ftf_hz;  /**< (fr/2) (1 - d/D cos phi), cage */
};

/**
 * Bearing defect frequencies (outer race fixed, inner race turning at
 * @p shaft_hz).
 * @return 0; -EINVAL (no elements, d or D not positive, d >= D, angle
 *         outside [0, pi/2), shaft_hz not positive).
 */
int sscope_vib_bearing_frequencies(const struct sscope_vib_bearing *b,
				   double shaft_hz, struct sscope_vib_bearing_freqs *f);

/** ISO 10816-1 machine classes. */
enum sscope_vib_iso_class {
	SSCOPE_VIB_ISO_NONE = 0, /**< no class given */
	SSCOPE_VIB_ISO_I,        /**< small machines (up to 15 kW) */
	SSCOPE_VIB_ISO_II,       /**< medium machines (15-75 kW; up to 300 kW
				  on special foundations) */
	SSCOPE_VIB_ISO_III,      /**< large machines, rigid foundations */
	SSCOPE_VIB_ISO_IV        /**< large machines, soft foundations */
};

/** @return the edition the zone table comes from; a static string. */
const char *sscope_vib_iso_edition(void);

/**
 * Zone boundaries A/B, B/C, C/D of a class, velocity RMS in m/s.
 * @return 0, -EINVAL for an unknown class.
 */
int sscope_vib_iso_limits(enum sscope_vib_iso_class c, double limits_m_s[3]);

/**
 * The zone ('A' .. 'D') of a velocity RMS for a class.
 * @return 0, -EINVAL (unknown class, velocity negative or NaN).
 */
int sscope_vib_iso_zone(enum sscope_vib_iso_class c, double v_rms_m_s, char *zone);

/**
 * Mean square velocity in [lo_hz, hi_hz] from an acceleration spectrum
 * (frequency-domain integration: each bin's acceleration density over its
 * interval, as in sscope_psd_spectrum_band_ms(), divided by (2 pi f)^2 and
 * integrated exactly over the interval).
 * @param ms receives the mean square velocity, (m/s)^2.
 * @return 0; -EINVAL (lo_hz not positive, hi_hz < lo_hz, NULL).
 */
int sscope_vib_velocity_ms(const struct sscope_psd_spectrum *accel, double lo_hz,
			   double hi_hz, double *ms);

/**
 * Kurtosis m4 / m2^2 (Pearson's: 3 for a Gaussian, 1.5 for a sine),
 * two passes about the mean (samples beyond 2^+-120 scaled by a power of
 * two first: exact).  Non-finite samples are an error.
 * @return 0; -EDOM (fewer than 4 samples, a constant, a non-finite
 *         sample); -EINVAL.
 */
int sscope_vib_kurtosis(const double *x, size_t stride, size_t n, double *kurt);

/** Envelope workspace for records of n samples (plans made once). */
struct sscope_vib_envelope;

/**
 * @param n record length (>= 4).
 * @return 0, -EINVAL, -ENOMEM.
 */
int sscope_vib_envelope_new(struct sscope_vib_envelope **env, size_t n);

/** Free (NULL is ignored). */
void sscope_vib_envelope_free(struct sscope_vib_envelope *env);

/**
 * Transform a record of the workspace's length (once per record).
 * @return 0; -EDOM (a non-finite sample); -EINVAL.
 */
int sscope_vib_envelope_set(struct sscope_vib_envelope *env, const double *x,
			    size_t stride);

/**
 * Envelope of the record band-passed to [lo_hz, hi_hz]: the magnitude of
 * the analytic signal whose spectrum is twice the record's positive
 * frequencies inside the band and zero elsewhere (an ideal band-pass and
 * the Hilbert transform in one inverse FFT).
 * @param env_out n samples of envelope (may be NULL).
 * @param sk      receives the spectral kurtosis of the band,
 *                <|z|^4> / <|z|^2>^2 - 2 (0 for Gaussian noise, -1 for a
 *                steady tone, large for impulses); may be NULL.
 * @return 0; -EINVAL (band empty or outside [0, fs/2], fs_hz not
 *         positive, no record set); -EDOM (no energy in the band).
 */
int sscope_vib_envelope_band(struct sscope_vib_envelope *env, double fs_hz,
			     double lo_hz, double hi_hz, double *env_out,
			     double *sk);

#define SSCOPE_VIB_ORDERS 3      /**< shaft orders reported (1x .. 3x) */
#define SSCOPE_VIB_ENV_PEAKS 10  /**< envelope peaks reported */
#define SSCOPE_VIB_FINDINGS 8    /**< findings at most */

/** n_peaks: report no spectrum peak. */
#define SSCOPE_VIB_NO_PEAKS ((size_t)-1)

/** Options of a vibration analysis.  A zero-initialised struct asks for
 *  the defaults, as every options struct of the library. */
struct sscope_vib_opts {
	/** Spectrum of the acceleration (default: hann, nperseg chosen by
	 *  the caller; see sscope_vib_default_nperseg()). */
	struct sscope_psd_opts psd;
	double iso_lo_hz, iso_hi_hz; /**< velocity band; 0, 0: 10-1000 Hz */
	enum sscope_vib_iso_class iso_class; /**< SSCOPE_VIB_ISO_NONE: report no
					      zone; the unbalance and
					      misalignment gate then uses
					      class I */
	double shaft_hz;  /**< shaft frequency (rpm / 60); 0: unknown */
	bool have_bearing;
	struct sscope_vib_bearing bearing;
	double tolerance; /**< relative tolerance of matches (slip); 0: 0.02;
			       negative: exact matches */
	double env_lo_hz, env_hi_hz; /**< envelope band; 0, 0: chosen by
					  the largest spectral kurtosis */
	size_t n_peaks;   /**< spectrum peaks reported; 0: 5; none:
			       SSCOPE_VIB_NO_PEAKS */
};

/** Zero @p o (the defaults: ISO band 10-1000 Hz, tolerance 2 %, 5
 *  peaks), as `struct sscope_vib_opts o = { 0 }`; kept for earlier
 *  callers. */
void sscope_vib_opts_init(struct sscope_vib_opts *o);

/** A default segment length for a record: a power of two giving at
 *  least about eight 50 %-overlapping segments, between 256 and 65536
 *  (shorter records: n). */
size_t sscope_vib_default_nperseg(size_t n);

/** A shaft order. */
struct sscope_vib_order {
	unsigned order;         /**< 1, 2, 3 */
	double expected_hz;     /**< order * shaft_hz */
	bool found;             /**< a spectral peak lies within tolerance */
	struct sscope_psd_peak peak;   /**< that peak (interpolated) */
	double velocity_rms_m_s;  /**< amplitude / (2 pi f) / sqrt 2 */
};

/** An envelope-spectrum peak and what it matches. */
struct sscope_vib_env_peak {
	struct sscope_psd_peak peak; /**< amplitude in m/s^2 of envelope */
	double snr;          /**< value over the local median floor */
	char match[16];      /**< "BPFO", "2xBPFI", "1x", ... or "" */
	double expected_hz;  /**< the matched frequency (NaN: none) */
};

/** A diagnosis line. */
struct sscope_vib_finding {
	char finding[64];   /**< e.g. "unbalance" */
	char evidence[400]; /**< the numbers behind it */
};

/** Result of sscope_vib_analyze(). */
struct sscope_vib_result {
	struct sscope_psd_spectrum accel;   /**< acceleration PSD (owned) */
	double accel_rms_m_s2;          /**< overall (detrended) RMS */
	double velocity_rms_m_s;        /**< in [iso_lo_hz, iso_hi_hz] */
	double iso_lo_hz, iso_hi_hz;    /**< band used (hi capped at fs/2) */
	char zone;                      /**< 'A'..'D', 0 without a class */
	double kurtosis;                /**< of the acceleration */
	size_t n_peaks;
	struct sscope_psd_peak peaks[16];   /**< strongest spectrum peaks */
	size_t n_orders;                /**< 0 without shaft_hz */
	struct sscope_vib_order orders[SSCOPE_VIB_ORDERS];
	bool have_bearing;
	struct sscope_vib_bearing_freqs bearing;
	struct sscope_psd_spectrum envelope; /**< envelope spectrum, "spectrum"
					      scaling (owned; empty
					      without a bearing) */
	double env_lo_hz, env_hi_hz;    /**< envelope band */
	double env_sk;                  /**< spectral kurtosis of the band */
	double env_threshold;           /**< SNR a peak needs to count */
	size_t n_env_peaks;
	struct sscope_vib_env_peak env_peaks[SSCOPE_VIB_ENV_PEAKS];
	size_t n_findings;
	struct sscope_vib_finding findings[SSCOPE_VIB_FINDINGS];
};

/**
 * Analyse an acceleration record.
 *
 * Findings:
 * - unbalance (reported when the velocity RMS reaches zone C, the B/C
 *   boundary of the class, class I when none is given): the 1x order carries at least half the velocity power of
 *   the ISO band and 2x is below half of 1x;
 * - misalignment (same gate): 2x is at least half of 1x (velocity) and
 *   carries at least a fifth of the velocity power;
 * - bearing faults (with a bearing): at least two harmonics of a defect
 *   frequency (BPFO, BPFI, 2xBSF family, FTF) among the envelope-spectrum
 *   peaks within the tolerance, each above the noise threshold (a Gamma
 *   quantile for the number of averaged segments, false-alarm probability
 *   1e-3 per bin).
 * @param diag optional detail of a failure.
 * @return 0; -EINVAL (bad options, fs_hz not positive); -EDOM (record too
 *         short, non-finite samples, a constant); -ERANGE (samples beyond
 *         2^+-120, where the envelope's 4th powers leave the double
 *         range); -ENOMEM.
 */
int sscope_vib_analyze(const double *x, size_t stride, size_t n,
		       double fs_hz, const struct sscope_vib_opts *o,
		       struct sscope_vib_result *r,
		       struct sscope_diag *diag);

/** Free the arrays of a result (not the struct); NULL is ignored. */
void sscope_vib_result_clear(struct sscope_vib_result *r);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_VIB_H */
