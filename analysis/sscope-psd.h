/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-psd.h
 * @brief Power spectral density: Welch's method and the periodogram with
 * scipy.signal's conventions, windows and their figures, peaks with
 * sub-bin interpolation, band RMS, IEC 61260-1 octave bands, spectrograms.
 *
 * Conventions (those of scipy.signal.welch, which the results equal):
 * - Windows are DFT-even ("periodic"): w[n] = sum_k a_k (-1)^k
 *   cos(2 pi k n / M), n = 0 .. M-1, M = nperseg; a window of one sample
 *   is [1].
 * - Segments start at 0, nperseg - noverlap, ...; samples after the last
 *   whole segment are not used.  Each segment is detrended (its mean or
 *   its least-squares line removed, or nothing), multiplied by the window,
 *   zero-padded to nfft and transformed (FFTW r2c, unnormalised).
 * - One-sided: every bin but DC (and Nyquist for even nfft) is doubled.
 *   "density": |X|^2 / (fs sum w^2), unit^2/Hz; "spectrum": |X|^2 /
 *   (sum w)^2, unit^2 (a sine of amplitude A centred on a bin reads A^2/2).
 *   Frequencies are k fs / nfft.
 * - The estimate is the mean over segments.
 *
 * Threads: a workspace (struct sscope_psd) processes the segments of a
 * batch on up to opts.threads OpenMP threads, each with its own arrays;
 * the per-segment periodograms are then added in segment order, so results
 * do not depend on the number of threads.  FFTW's planner is not
 * thread-safe: create workspaces from one thread at a time (or call
 * fftw_make_planner_thread_safe() first); a workspace is used by one
 * thread at a time.
 */
#ifndef SSCOPE_PSD_H
#define SSCOPE_PSD_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Windows of scipy.signal.get_window (DFT-even). */
enum sscope_psd_window {
	SSCOPE_PSD_WINDOW_HANN = 0,       /**< a = 0.5, 0.5 */
	SSCOPE_PSD_WINDOW_HAMMING,        /**< a = 0.54, 0.46 */
	SSCOPE_PSD_WINDOW_BLACKMAN,       /**< a = 0.42, 0.50, 0.08 */
	SSCOPE_PSD_WINDOW_BLACKMANHARRIS, /**< 4-term, -92 dB sidelobes */
	SSCOPE_PSD_WINDOW_FLATTOP,        /**< 5-term flat top (scipy's) */
	SSCOPE_PSD_WINDOW_BOXCAR,         /**< rectangular */
	SSCOPE_PSD_WINDOW_COUNT_          /**< number of windows (not a window) */
};

/** Detrending of each segment. */
enum sscope_psd_detrend {
	SSCOPE_PSD_DETREND_CONSTANT = 0, /**< remove the mean (scipy's default) */
	SSCOPE_PSD_DETREND_LINEAR,       /**< remove the least-squares line */
	SSCOPE_PSD_DETREND_NONE          /**< nothing */
};

/** Scaling of the estimate. */
enum sscope_psd_scaling {
	SSCOPE_PSD_SCALING_DENSITY = 0, /**< unit^2/Hz, 1 / (fs sum w^2) */
	SSCOPE_PSD_SCALING_SPECTRUM     /**< unit^2, 1 / (sum w)^2 */
};

/** @return the name of @p w ("hann", ...), or NULL; a static string. */
const char *sscope_psd_window_name(enum sscope_psd_window w);

/**
 * Look a window up by name (hann, hamming, blackman, blackmanharris,
 * flattop, boxcar; "hanning" and "rect"/"rectangular" are accepted).
 * @return 0, or -EINVAL for an unknown name.
 */
int sscope_psd_window_from_name(const char *name, enum sscope_psd_window *w);

/**
 * Fill @p out with the DFT-even window of @p n samples.
 * @return 0, or -EINVAL (unknown window, n == 0, out NULL).
 */
int sscope_psd_window_fill(enum sscope_psd_window w, size_t n, double *out);

/** Figures of merit of a window of n samples. */
struct sscope_psd_window_figures {
	double sum;            /**< sum w */
	double sum_sq;         /**< sum w^2 */
	double coherent_gain;  /**< sum w / n: amplitude of a bin-centred
				    tone relative to the rectangular window */
	double enbw_bins;      /**< equivalent noise bandwidth n sum w^2 /
				    (sum w)^2, in bins of fs / n */
	double scalloping_db;  /**< amplitude loss of a tone midway between
				    two bins, dB (negative), for nfft = n */
};

/**
 * Compute the figures of the window of @p n samples.
 * @return 0, or -EINVAL (unknown window, n == 0, f NULL).
 */
int sscope_psd_window_figures(enum sscope_psd_window w, size_t n,
			      struct sscope_psd_window_figures *f);

/**
 * Magnitude of the window's discrete-time Fourier transform (the
 * continuous spectrum of the n-sample window) at an offset of @p bins bins
 * of width 1/nfft cycles per sample, in closed form (sums of Dirichlet
 * kernels).  At 0 it equals sum w.
 * @return the magnitude, or NaN for bad arguments.
 */
double sscope_psd_window_response(enum sscope_psd_window w, size_t n, size_t nfft,
				  double bins);

/** noverlap: the default, nperseg / 2, as scipy (zero, as in a
 *  zero-initialised struct). */
#define SSCOPE_PSD_HALF_OVERLAP ((size_t)0)
/** noverlap: segments that share no sample. */
#define SSCOPE_PSD_NO_OVERLAP ((size_t)-1)

/** nfft at most this many times nperseg (zero padding beyond only
 * interpolates the spectrum). */
#define SSCOPE_PSD_MAX_PAD 64

/** Options of a Welch estimate.  A zero-initialised struct asks for
 *  scipy's defaults (hann, 256, half overlap, constant detrend,
 *  density), as every options struct of the library. */
struct sscope_psd_opts {
	enum sscope_psd_window window;   /**< default hann */
	size_t nperseg;              /**< samples per segment; 0: 256 */
	size_t noverlap;             /**< samples shared by neighbouring
					  segments, < nperseg; 0
					  (SSCOPE_PSD_HALF_OVERLAP): nperseg
					  / 2; none: SSCOPE_PSD_NO_OVERLAP */
	size_t nfft;                 /**< FFT length >= nperseg (zero
					  padding), at most
					  SSCOPE_PSD_MAX_PAD nperseg; 0:
					  nperseg */
	enum sscope_psd_detrend detrend; /**< default constant */
	enum sscope_psd_scaling scaling; /**< default density */
	/** Segments holding a NaN or an infinity are left out of the mean
	 *  (counted in n_skipped) instead of failing with -EDOM. */
	bool skip_nonfinite;
	/** When the record ends before the first whole segment, use the
	 *  whole record as the one segment (scipy's behaviour for nperseg >
	 *  n; an FFT plan of that length is made then).  Otherwise such a
	 *  record gives -EDOM. */
	bool shorten;
	/** Keep a spectrogram of at most this many time columns (0: none).
	 *  When a record has more segments, neighbouring columns are
	 *  merged in pairs, so memory stays bounded. */
	size_t spectrogram_cols;
	/** FFTW_MEASURE planning (slower set-up, faster transforms: worth it
	 *  for long records) instead of FFTW_ESTIMATE. */
	bool measure;
	unsigned threads; /**< OpenMP threads; 0: the OpenMP default */
};

/** The noverlap of an overlap @p fraction in [0, 1) of @p nperseg
 *  samples: floor(fraction nperseg), at most nperseg - 1, and
 *  SSCOPE_PSD_NO_OVERLAP when that is no sample. */
size_t sscope_psd_noverlap(double fraction, size_t nperseg);

/** Zero @p o: scipy.signal.welch's defaults (hann, 256, half overlap,
 *  constant detrend, density), as `struct sscope_psd_opts o = { 0 }`;
 *  kept for callers written when zero meant no overlap. */
void sscope_psd_opts_init(struct sscope_psd_opts *o);

/** A one-sided spectrum (the result of an estimate). */
struct sscope_psd_spectrum {
	size_t n_bins;       /**< nfft / 2 + 1 */
	double *freq_hz;     /**< n_bins frequencies k fs / nfft (owned) */
	double *value;       /**< n_bins values: unit^2/Hz (density) or
				  unit^2 (spectrum) (owned) */
	double fs_hz;        /**< sample rate */
	enum sscope_psd_scaling scaling;
	enum sscope_psd_window window;
	enum sscope_psd_detrend detrend;
	size_t nperseg, noverlap, nfft; /**< as used (nperseg may have been
					     shortened) */
	size_t n_segments;   /**< segments averaged */
	size_t n_skipped;    /**< segments left out (non-finite samples) */
	uint64_t n_samples;  /**< samples fed */
	double enbw_hz;      /**< fs sum w^2 / (sum w)^2 */
	double bin_hz;       /**< fs / nfft */
	double rms;          /**< sqrt(sum density * bin_hz): the RMS of the
				  detrended, windowed segments (Parseval) */
};

/** Free the arrays of @p s (not @p s itself); NULL is ignored. */
void sscope_psd_spectrum_clear(struct sscope_psd_spectrum *s);

/** A spectrogram: short-time PSDs over time. */
struct sscope_psd_spectrogram {
	size_t n_times;      /**< columns */
	size_t n_bins;       /**< rows per column */
	double *time_s;      /**< n_times: centre of each column's segments,
				  s from the first sample (owned) */
	double *freq_hz;     /**< n_bins (owned) */
	double *value;       /**< value[t * n_bins + k], scaled as the
				  spectrum (owned) */
	size_t segments_per_column; /**< segments averaged in each full
					 column */
};

/** Free the arrays of @p s (not @p s itself); NULL is ignored. */
void sscope_psd_spectrogram_clear(struct sscope_psd_spectrogram *s);

/** A Welch workspace: plans and buffers made once, then fed any number of
 *  samples in chunks (streaming); memory does not grow with the record. */
struct sscope_psd;

/**
 * Create a workspace.
 * @param psd  receives the workspace; free with sscope_psd_free().
 * @param opts options (NULL: the defaults).
 * @return 0; -EINVAL (noverlap >= nperseg, nfft < nperseg,
 *         unknown window/detrend/scaling); -ENOMEM.
 */
int sscope_psd_new(struct sscope_psd **psd, const struct sscope_psd_opts *opts);

/**
 * Feed samples x[k * stride], k < n (continuing the record).
 * Segments are transformed in batches as they fill, so a non-finite
 * sample is reported by the call that completes its batch (or by
 * sscope_psd_result()); samples after the last whole segment are never
 * looked at, as in scipy.
 * @return 0; -EINVAL (x NULL with n > 0, stride 0); -EDOM for a non-finite
 *         sample when skip_nonfinite is off (the workspace is then in an
 *         undefined state: reset or free it).
 */
int sscope_psd_feed(struct sscope_psd *psd, const double *x, size_t stride,
		    size_t n);

/**
 * Where the last whole segment of a record of @p n samples ends: the
 * samples from there on are never looked at (0 when no segment fits, or
 * @p psd is NULL).
 */
size_t sscope_psd_segments_end(const struct sscope_psd *psd, size_t n);

/**
 * The estimate of everything fed so far (feeding may continue after).
 * @param fs_hz sample rate, Hz (> 0).
 * @param out   receives the spectrum; free its arrays with
 *              sscope_psd_spectrum_clear().
 * @return 0; -EINVAL (fs_hz not positive); -EDOM when no segment could be
 *         averaged (record shorter than nperseg without opts.shorten, no
 *         sample, every segment non-finite) or when a segment still
 *         waiting to be transformed holds a non-finite sample and
 *         skip_nonfinite is off; -ERANGE when the spectrum leaves the
 *         double range (a value overflows, or the largest lies below
 *         2^-970 so its neighbours would be subnormal; or fs_hz / nfft
 *         is not a normal double) -- segments of extreme samples are
 *         transformed scaled by powers of two, so any finite record whose
 *         spectrum is representable gets it; -ENOMEM.
 */
int sscope_psd_result(struct sscope_psd *psd, double fs_hz,
		      struct sscope_psd_spectrum *out);

/**
 * The spectrogram of everything fed so far (needs opts.spectrogram_cols).
 * @param fs_hz sample rate, Hz.
 * @param out   receives it; free with sscope_psd_spectrogram_clear().
 * @return 0; -EINVAL (no spectrogram was asked for, bad fs_hz); -EDOM (no
 *         segment yet); -ERANGE as sscope_psd_result(); -ENOMEM.
 */
int sscope_psd_spectrogram(struct sscope_psd *psd, double fs_hz,
			   struct sscope_psd_spectrogram *out);

/** Forget everything fed (plans and buffers are kept). */
void sscope_psd_reset(struct sscope_psd *psd);

/** Free a workspace (NULL is ignored). */
void sscope_psd_free(struct sscope_psd *psd);

/**
 * Welch's estimate of a whole buffer, as scipy.signal.welch(x, fs, ...):
 * nperseg larger than n is shortened to n (scipy warns and does the same;
 * the default overlap is then recomputed).
 * @param out receives the spectrum (free with sscope_psd_spectrum_clear()).
 * @return as sscope_psd_new() and sscope_psd_result(); -EDOM for n == 0 or
 *         a non-finite sample (unless skip_nonfinite).
 */
int sscope_psd_welch(const double *x, size_t stride, size_t n, double fs_hz,
		     const struct sscope_psd_opts *opts,
		     struct sscope_psd_spectrum *out);

/**
 * The periodogram, as scipy.signal.periodogram(x, fs, window, nfft,
 * detrend, scaling=...): one segment of the whole record.
 * @param nfft FFT length (0: n).
 * @return as sscope_psd_welch().
 */
int sscope_psd_periodogram(const double *x, size_t stride, size_t n,
			   double fs_hz, enum sscope_psd_window window,
			   size_t nfft, enum sscope_psd_detrend detrend,
			   enum sscope_psd_scaling scaling,
			   struct sscope_psd_spectrum *out);

/** A spectral peak. */
struct sscope_psd_peak {
	size_t bin;          /**< index of the local maximum */
	double frequency_hz; /**< interpolated frequency */
	double offset_bins;  /**< interpolated offset from bin, bins */
	double value;        /**< spectrum value at bin (its scaling) */
	double amplitude;    /**< amplitude (peak, unit) of the sine that
				  explains the peak, corrected for the window
				  and the scalloping loss */
	double rms;          /**< amplitude / sqrt(2) */
};

/**
 * The @p max strongest local maxima of @p s between @p fmin_hz and
 * @p fmax_hz, strongest first.
 *
 * Interpolation (exact for one noise-free sine): with the larger of the
 * two neighbours of the peak bin, the ratio of their values is matched to
 * |W(1 - d)|^2 / |W(d)|^2, W the window's transform in closed form
 * (sscope_psd_window_response()), solved for the offset d in [0, 1/2] by
 * bisection; the amplitude follows from the peak bin's value divided by
 * |W(d) / W(0)|^2.
 * @param n_found receives the number of peaks written.
 * @return 0; -EINVAL (NULL arguments).
 */
int sscope_psd_spectrum_peaks(const struct sscope_psd_spectrum *s, size_t max,
			      double fmin_hz, double fmax_hz,
			      struct sscope_psd_peak *peaks, size_t *n_found);

/**
 * Interpolate the peak at local-maximum bin @p bin of @p s (see
 * sscope_psd_spectrum_peaks()).
 * @return 0; -EINVAL (bin out of range or not an interior bin).
 */
int sscope_psd_spectrum_peak_at(const struct sscope_psd_spectrum *s, size_t bin,
				struct sscope_psd_peak *pk);

/**
 * The strongest local maximum within @p tol_hz of @p f_hz, interpolated.
 * @return 0; -ENOENT when there is no local maximum in that range;
 *         -EINVAL.
 */
int sscope_psd_spectrum_peak_near(const struct sscope_psd_spectrum *s, double f_hz,
				  double tol_hz, struct sscope_psd_peak *pk);

/**
 * Equivalent degrees of freedom of each bin (away from DC and Nyquist) of
 * a Welch estimate: the estimate over its expectation is chi-square with
 * nu degrees of freedom over nu, nu = 2K / (1 + 2 sum_{j=1}^{K-1} (1 - j/K)
 * rho(jD)^2) for K segments shifted by D samples, rho(m) = sum w[n]
 * w[n+m] / sum w^2 (Percival & Walden 1993, eq. 292b: the overlap
 * correction; 2K without overlap, 2 for a periodogram).
 * @return nu, or NaN for an empty spectrum.
 */
double sscope_psd_spectrum_edf(const struct sscope_psd_spectrum *s);

/** How sscope_psd_spectrum_significant_peaks() decided (for reports). */
struct sscope_psd_peak_test {
	double alpha;            /**< probability of listing a peak in a
				      spectrum of noise alone */
	double edf;              /**< nu of each bin */
	double floor_edf;        /**< equivalent dof of the floor estimate */
	size_t bins_tested;      /**< M: bins searched (Bonferroni) */
	double p_threshold;      /**< alpha / M */
	double ratio_threshold;  /**< value / floor needed with no leakage */
	size_t floor_half_width; /**< neighbours each side for the floor */
	size_t lobe_half_width;  /**< main-lobe bins left out each side */
};

/** A peak that passed the test. */
struct sscope_psd_sig_peak {
	struct sscope_psd_peak peak; /**< interpolated as sscope_psd_spectrum_peak_at */
	double floor;            /**< local noise floor at its bin (the
				      spectrum's scaling) */
	double ratio;            /**< value / (floor + leakage of stronger
				      peaks) */
	double p_value;          /**< of that ratio under noise alone */
};

/**
 * The @p max strongest peaks between @p fmin_hz and @p fmax_hz that stand
 * out of the local noise floor, strongest first.
 *
 * Test: at a local maximum k, the floor is the median of the 2L bins
 * around it (L = max(32, 4h)) outside its main lobe (h bins each side,
 * about twice the window's ENBW), divided by the median of chi2(nu)/nu,
 * nu = sscope_psd_spectrum_edf().  Under noise alone the ratio of the bin to
 * the floor is F-distributed with (nu, nuf) degrees of freedom, nuf the
 * equivalent dof of a median of that many independent bins (large-sample
 * variance of a median).  A peak is listed when P(F > ratio) < alpha / M,
 * M the bins searched (Bonferroni): a spectrum of noise alone lists a peak
 * with probability at most about alpha.  Peaks are taken strongest first;
 * a weaker one is tested against its floor plus the leakage of the
 * stronger ones already listed (their window's response, its envelope over
 * half a bin), so the skirts of a strong tone are not listed as lines.
 * @param alpha   family-wise false-alarm probability; 0 selects 0.01.
 * @param test    receives the test's figures (may be NULL).
 * @return 0; -EINVAL (NULL, alpha outside (0, 1), fmax < fmin, empty
 *         spectrum); -ENOMEM.
 */
int sscope_psd_spectrum_significant_peaks(const struct sscope_psd_spectrum *s,
					  size_t max, double fmin_hz,
					  double fmax_hz, double alpha,
					  struct sscope_psd_sig_peak *peaks,
					  size_t *n_found,
					  struct sscope_psd_peak_test *test);

/**
 * Mean square of the signal in [lo_hz, hi_hz): each bin's power
 * (density * bin width) is spread evenly over its interval [f - bin/2,
 * f + bin/2] clipped to [0, fs/2], so adjacent bands add up and the whole
 * band [0, fs/2] gives rms^2 exactly.
 * @param ms receives the mean square, unit^2.
 * @return 0; -EINVAL (hi < lo, NULL).
 */
int sscope_psd_spectrum_band_ms(const struct sscope_psd_spectrum *s, double lo_hz,
				double hi_hz, double *ms);

/** A frequency band. */
struct sscope_psd_band {
	double lo_hz;      /**< lower edge */
	double center_hz;  /**< exact mid-band frequency */
	double hi_hz;      /**< upper edge */
	double nominal_hz; /**< nominal mid-band frequency (IEC 61260-1 /
				ISO 266 R10 series for octaves and
				thirds) */
	double rms;        /**< filled by the caller (NaN here) */
};

/**
 * IEC 61260-1:2014 base-10 fractional-octave bands: G = 10^(3/10),
 * mid-band frequencies 1000 G^(x/b) Hz for odd b (1000 G^((2x+1)/(2b))
 * for even b), edges at G^(-+1/(2b)) times the mid-band frequency.  Lists
 * the bands lying inside [fmin_hz, fmax_hz], lowest first.
 * @param fraction b: 1 for octaves, 3 for third-octaves (1..24).
 * @param n_found  receives the number of bands (all of them when @p bands
 *                 is NULL: call once to size the array).
 * @return 0; -EINVAL (fraction out of range, fmin_hz not positive,
 *         fmax_hz < fmin_hz); -ERANGE when @p max is too small (the first
 *         max bands are written).
 */
int sscope_psd_octave_bands(unsigned fraction, double fmin_hz, double fmax_hz,
			    struct sscope_psd_band *bands, size_t max,
			    size_t *n_found);

/**
 * A band between two edges for a spectrum of Nyquist frequency
 * @p nyquist_hz: the upper edge clipped to it, the centre the geometric
 * mean of the edges, no nominal frequency (NaN).
 * @return 0; -EINVAL (lo < 0, hi <= lo, not finite); -EDOM when the band
 *         starts at or above the Nyquist frequency.
 */
int sscope_psd_band_edges(double lo_hz, double hi_hz, double nyquist_hz,
			  struct sscope_psd_band *band);

/**
 * The fractional-octave bands (sscope_psd_octave_bands()) a spectrum
 * resolves: inside [bin/2, fs/2] and at least one bin wide (a narrower
 * band says nothing).
 * @param bands, max, n_found  as sscope_psd_octave_bands().
 * @return as sscope_psd_octave_bands().
 */
int sscope_psd_spectrum_octave_bands(const struct sscope_psd_spectrum *s,
				     unsigned fraction, struct sscope_psd_band *bands,
				     size_t max, size_t *n_found);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_PSD_H */
