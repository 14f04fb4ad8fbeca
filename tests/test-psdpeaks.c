/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Significant spectral peaks: the equivalent degrees of freedom of Welch
 * estimates against closed forms (2K without overlap, the Hann half-overlap
 * correction rho = 1/6, 2 for a periodogram); the false-alarm rate of the
 * peak test on white noise by simulation (a spectrum lists a peak with
 * probability at most about alpha, Welch and periodogram); detection of a
 * weak tone at its frequency; one line, not its skirts, for a tone 90 dB
 * above the noise; the documented error codes.
 */
#include "config.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "sensorscope.h"
#include "check-main.h"

#define PI 3.14159265358979323846

static void noise(gsl_rng *r, double *x, size_t n, double sd)
{
	for (size_t i = 0; i < n; i++)
		x[i] = sd * gsl_ran_gaussian_ziggurat(r, 1);
}

static void welch(const double *x, size_t n, enum sscope_psd_window w,
		  size_t nperseg, size_t noverlap, struct sscope_psd_spectrum *s)
{
	struct sscope_psd_opts o;

	sscope_psd_opts_init(&o);
	o.window = w;
	o.nperseg = nperseg;
	o.noverlap = noverlap ? noverlap : SSCOPE_PSD_NO_OVERLAP;
	ck_assert_int_eq(sscope_psd_welch(x, 1, n, 1000, &o, s), 0);
}

START_TEST(edf_closed_forms)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double *x = malloc(8192 * sizeof(double));
	struct sscope_psd_spectrum s = { 0 };
	double K;

	gsl_rng_set(r, 11);
	noise(r, x, 8192, 1);
	/* boxcar, no overlap: independent segments, 2 K */
	welch(x, 8192, SSCOPE_PSD_WINDOW_BOXCAR, 256, 0, &s);
	ck_assert_uint_eq(s.n_segments, 32);
	ck_assert(fabs(sscope_psd_spectrum_edf(&s) - 64) < 1e-12);
	sscope_psd_spectrum_clear(&s);
	/* Hann at half overlap: rho(N/2) = (N/16) / (3N/8) = 1/6 */
	welch(x, 8192, SSCOPE_PSD_WINDOW_HANN, 256, 128, &s);
	K = (double)s.n_segments;
	ck_assert_uint_eq(s.n_segments, 63);
	ck_assert(fabs(sscope_psd_spectrum_edf(&s) -
		       2 * K / (1 + 2 * (1 - 1 / K) / 36)) < 1e-9);
	sscope_psd_spectrum_clear(&s);
	/* one segment */
	ck_assert_int_eq(sscope_psd_periodogram(x, 1, 1000, 1000, SSCOPE_PSD_WINDOW_HANN,
						0, SSCOPE_PSD_DETREND_CONSTANT,
						SSCOPE_PSD_SCALING_DENSITY, &s), 0);
	ck_assert(sscope_psd_spectrum_edf(&s) == 2);
	sscope_psd_spectrum_clear(&s);
	ck_assert(isnan(sscope_psd_spectrum_edf(NULL)));
	free(x);
	gsl_rng_free(r);
}
END_TEST

/* Records of white noise with at least one listed peak, out of R. */
static int false_alarms(int R, int periodogram, double alpha)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double *x = malloc(8192 * sizeof(double));
	int hits = 0;

	gsl_rng_set(r, periodogram ? 303 : 202);
	for (int k = 0; k < R; k++) {
		struct sscope_psd_spectrum s = { 0 };
		struct sscope_psd_sig_peak pk[4];
		size_t n;

		noise(r, x, 8192, 2.385);
		if (periodogram)
			ck_assert_int_eq(sscope_psd_periodogram(x, 1, 2048, 1000,
								SSCOPE_PSD_WINDOW_HANN, 0,
								SSCOPE_PSD_DETREND_CONSTANT,
								SSCOPE_PSD_SCALING_DENSITY, &s), 0);
		else
			welch(x, 8192, SSCOPE_PSD_WINDOW_HANN, 256, 128, &s);
		ck_assert_int_eq(sscope_psd_spectrum_significant_peaks(&s, 4, 0, 500, alpha,
								       pk, &n, NULL), 0);
		hits += n > 0;
		sscope_psd_spectrum_clear(&s);
	}
	free(x);
	gsl_rng_free(r);
	return hits;
}

/* A spectrum of noise alone lists a peak with probability about alpha at
 * most: over R records the count stays under alpha R + 3 binomial sd. */
START_TEST(false_alarm_rate)
{
	const int R = 300;
	const double alpha = 0.05;
	double bound = alpha * R + 3 * sqrt(alpha * (1 - alpha) * R);
	int w = false_alarms(R, 0, alpha), p = false_alarms(R, 1, alpha);

	printf("# white noise, alpha %.2f: a peak listed in %d of %d Welch spectra and %d of %d periodograms (bound %.1f)\n",
	       alpha, w, R, p, R, bound);
	ck_assert_msg(w <= bound, "Welch: %d of %d", w, R);
	ck_assert_msg(p <= bound, "periodogram: %d of %d", p, R);
}
END_TEST

START_TEST(tones)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	size_t n = 65536, found;
	double *x = malloc(n * sizeof(double)), f0 = 123.4567;
	struct sscope_psd_spectrum s = { 0 };
	struct sscope_psd_sig_peak pk[8];
	struct sscope_psd_peak_test t;

	gsl_rng_set(r, 7);
	/* a weak tone: its bin stands about 7x above the floor */
	noise(r, x, n, 1);
	for (size_t i = 0; i < n; i++)
		x[i] += 0.2 * sin(2 * PI * f0 * (double)i / 1000);
	welch(x, n, SSCOPE_PSD_WINDOW_HANN, 1024, 512, &s);
	ck_assert_int_eq(sscope_psd_spectrum_significant_peaks(&s, 8, 0, 500, 0, pk,
							       &found, &t), 0);
	ck_assert_uint_eq(found, 1);
	ck_assert(fabs(pk[0].peak.frequency_hz - f0) < 0.1 * s.bin_hz);
	ck_assert(pk[0].ratio > t.ratio_threshold && pk[0].p_value < t.p_threshold);
	ck_assert(t.alpha == 0.01 && t.bins_tested == s.n_bins - 2 && t.lobe_half_width == 3);
	ck_assert(fabs(t.edf - sscope_psd_spectrum_edf(&s)) < 1e-12);
	sscope_psd_spectrum_clear(&s);
	/* 90 dB above the noise: one line, its skirts are not listed */
	noise(r, x, n, 1e-3);
	for (size_t i = 0; i < n; i++)
		x[i] += 30 * sin(2 * PI * f0 * (double)i / 1000);
	welch(x, n, SSCOPE_PSD_WINDOW_HANN, 1024, 512, &s);
	ck_assert_int_eq(sscope_psd_spectrum_significant_peaks(&s, 8, 0, 500, 0, pk,
							       &found, NULL), 0);
	ck_assert_msg(found == 1, "%zu peaks, the second at %g Hz", found,
		      found > 1 ? pk[1].peak.frequency_hz : 0);
	ck_assert(fabs(pk[0].peak.amplitude - 30) < 0.03);
	/* errors */
	ck_assert_int_eq(sscope_psd_spectrum_significant_peaks(&s, 8, 0, 500, 1, pk,
							       &found, NULL), -EINVAL);
	ck_assert_int_eq(sscope_psd_spectrum_significant_peaks(&s, 8, 10, 5, 0, pk,
							       &found, NULL), -EINVAL);
	ck_assert_int_eq(sscope_psd_spectrum_significant_peaks(NULL, 8, 0, 500, 0, pk,
							       &found, NULL), -EINVAL);
	sscope_psd_spectrum_clear(&s);
	free(x);
	gsl_rng_free(r);
}
END_TEST

/* The estimate of 1e9 samples (hann, nperseg 256, half overlap: 7812499
 * segments, nu 1.48e7): GSL's F tail is NaN near a ratio of 1 there,
 * which made the threshold 0.9998 and every local maximum of white
 * noise a peak.  The reference threshold is scipy 1.10's
 * stats.f.isf(0.01 / 127, nu, nuf) for the nu and nuf printed. */
START_TEST(huge_edf)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	struct sscope_psd_spectrum s = { 0 };
	struct sscope_psd_sig_peak pk[8];
	struct sscope_psd_peak_test t;
	size_t found;
	double sd;

	gsl_rng_set(r, 11);
	s.n_bins = 129;
	s.fs_hz = 100;
	s.window = SSCOPE_PSD_WINDOW_HANN;
	s.nperseg = s.nfft = 256;
	s.noverlap = 128;
	s.n_segments = 7812499;
	s.bin_hz = s.fs_hz / 256;
	s.freq_hz = malloc(s.n_bins * sizeof(double));
	s.value = malloc(s.n_bins * sizeof(double));
	ck_assert(s.freq_hz && s.value);
	sd = sqrt(2 / sscope_psd_spectrum_edf(&s));
	for (size_t k = 0; k < s.n_bins; k++) {
		s.freq_hz[k] = (double)k * s.bin_hz;
		s.value[k] = 2e-6 * (1 + sd * gsl_ran_ugaussian(r));
	}
	ck_assert_int_eq(sscope_psd_spectrum_significant_peaks(&s, 8, 0, 50, 0, pk,
							       &found, &t), 0);
	ck_assert(fabs(t.edf / 14802629.7839335 - 1) < 1e-9);
	ck_assert(fabs(t.floor_edf / 546571479.571976 - 1) < 1e-6);
	ck_assert_msg(fabs(t.ratio_threshold - 1.0014083706786465) < 1e-7,
		      "threshold %.10f", t.ratio_threshold);
	ck_assert_msg(found == 0, "%zu peaks in white noise", found);
	/* a line 10 sd above the floor is found */
	s.value[40] = 2e-6 * (1 + 10 * sd);
	ck_assert_int_eq(sscope_psd_spectrum_significant_peaks(&s, 8, 0, 50, 0, pk,
							       &found, &t), 0);
	ck_assert_uint_eq(found, 1);
	ck_assert_uint_eq(pk[0].peak.bin, 40);
	ck_assert(pk[0].p_value > 0 && pk[0].p_value < t.p_threshold);
	sscope_psd_spectrum_clear(&s);
	gsl_rng_free(r);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("psdpeaks");
	TCase *tc = tcase_create("core");

	tcase_set_timeout(tc, 300);
	tcase_add_test(tc, edf_closed_forms);
	tcase_add_test(tc, false_alarm_rate);
	tcase_add_test(tc, tones);
	tcase_add_test(tc, huge_edf);
	suite_add_tcase(s, tc);
	return s;
}
