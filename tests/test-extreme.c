/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Samples at the ends of the double range (issue 13): every analysis that
 * squares sums gives the right answer for any finite input, or -ERANGE.
 * Oracle: scale equivariance by powers of two, which are exact -- the
 * statistics, deviations and spectra of x * 2^k are those of x scaled by
 * 2^k (2^2k for spectra) -- checked where the plain sums would overflow
 * (2^k = 2^900, 2^1000) or underflow (2^-900, 2^-1000); the kurtosis does
 * not change at all.  Data: a seeded Gaussian record (GSL), one spike.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "sscope-allan.h"
#include "sscope-budget.h"
#include "sscope-psd.h"
#include "sscope-vib.h"
#include "check-main.h"

#define N 4096

static double *record(unsigned long seed, double spike)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double *x = malloc(N * sizeof(double));

	ck_assert_ptr_nonnull(r);
	ck_assert_ptr_nonnull(x);
	gsl_rng_set(r, seed);
	for (size_t i = 0; i < N; i++)
		x[i] = 2.385 * gsl_ran_gaussian_ziggurat(r, 1) + 0.731;
	if (spike != 0)
		x[N / 2] = spike;
	gsl_rng_free(r);
	return x;
}

static double *scaled(const double *x, int k)
{
	double *y = malloc(N * sizeof(double));

	ck_assert_ptr_nonnull(y);
	for (size_t i = 0; i < N; i++)
		y[i] = ldexp(x[i], k);
	return y;
}

static const int ks[] = { 1000, 900, 500, -500, -900, -1000 };

START_TEST(stats_scaled)
{
	double *x = record(11, 0);
	struct sscope_stats a, b;

	ck_assert_int_eq(sscope_stats_compute(x, 1, N, &a), 0);
	for (size_t j = 0; j < sizeof(ks) / sizeof(ks[0]); j++) {
		double *y = scaled(x, ks[j]);

		ck_assert_int_eq(sscope_stats_compute(y, 1, N, &b), 0);
		ck_assert_rel(b.mean, ldexp(a.mean, ks[j]), 1e-15);
		ck_assert_rel(b.sd, ldexp(a.sd, ks[j]), 1e-15);
		ck_assert(b.max == ldexp(a.max, ks[j]));
		free(y);
	}
	/* one sample of 1e308 among unit noise: mean 1e308 / N, sd
	 * 1e308 / sqrt(N) (the rest is below its rounding) */
	x[0] = 1e308;
	ck_assert_int_eq(sscope_stats_compute(x, 1, N, &b), 0);
	ck_assert_rel(b.mean, 1e308 / N, 1e-12);
	ck_assert_rel(b.sd, 1e308 / sqrt((double)N), 1e-12);
	/* +-1.7e308: the sd, 2.4e308, exceeds the double range */
	x[0] = 1.7e308;
	x[1] = -1.7e308;
	ck_assert_int_eq(sscope_stats_compute(x, 1, 2, &b), -ERANGE);
	free(x);
}
END_TEST

static void oadev(const double *x, const struct sscope_allan_opts *o,
		  struct sscope_allan_point *pts, size_t *n)
{
	static const size_t m[] = { 1, 2, 4, 16, 64, 256 };
	struct sscope_allan *p;
	struct sscope_diag d = { "" };

	ck_assert_int_eq(sscope_allan_new(&p, N, o), 0);
	ck_assert_msg(sscope_allan_compute(p, x, 1, N, 100, m, 6, pts, n, &d) == 0,
		      "%s", d.msg);
	ck_assert_uint_eq(*n, 6);
	sscope_allan_free(p);
}

START_TEST(allan_scaled)
{
	static const enum sscope_allan_dev devs[] = { SSCOPE_ALLAN_DEV_OADEV,
						SSCOPE_ALLAN_DEV_MDEV,
						SSCOPE_ALLAN_DEV_OHDEV,
						SSCOPE_ALLAN_DEV_TOTDEV };
	double *x = record(12, 0);
	struct sscope_allan_point a[6], b[6];
	size_t na, nb;

	for (size_t dv = 0; dv < sizeof(devs) / sizeof(devs[0]); dv++) {
		struct sscope_allan_opts o = { .dev = devs[dv] };

		oadev(x, &o, a, &na);
		for (size_t j = 0; j < sizeof(ks) / sizeof(ks[0]); j++) {
			double *y = scaled(x, ks[j]);

			oadev(y, &o, b, &nb);
			for (size_t i = 0; i < na; i++) {
				ck_assert_rel(b[i].dev, ldexp(a[i].dev, ks[j]), 1e-13);
				ck_assert_rel(b[i].dev_hi, ldexp(a[i].dev_hi, ks[j]),
					      1e-13);
				ck_assert_int_eq(b[i].alpha, a[i].alpha);
			}
			free(y);
		}
	}
	free(x);
}
END_TEST

/* the one-call analysis: deviations and the noise fit's coefficients */
START_TEST(allan_fit_scaled)
{
	double *x = record(13, 0);
	struct sscope_allan_result *a, *b;
	struct sscope_diag d = { "" };

	ck_assert_int_eq(sscope_allan_analyze(x, 1, N, 100, SSCOPE_ALLAN_TAUS_OCTAVE,
					      NULL, NULL, &a, &d), 0);
	ck_assert(a->have_fit);
	for (size_t j = 0; j < sizeof(ks) / sizeof(ks[0]); j++) {
		double *y = scaled(x, ks[j]);

		ck_assert_msg(sscope_allan_analyze(y, 1, N, 100, SSCOPE_ALLAN_TAUS_OCTAVE,
						   NULL, NULL, &b, &d) == 0,
			      "%s", d.msg);
		ck_assert(b->have_fit);
		ck_assert_uint_eq(b->fit.terms, a->fit.terms);
		for (int t = 0; t < 5; t++) {
			if (!a->fit.coef[t].fitted)
				continue;
			ck_assert_rel(b->fit.coef[t].value,
				      ldexp(a->fit.coef[t].value, ks[j]), 1e-9);
			ck_assert_rel(b->fit.coef[t].hi,
				      ldexp(a->fit.coef[t].hi, ks[j]), 1e-9);
		}
		sscope_allan_result_free(b);
		free(y);
	}
	sscope_allan_result_free(a);
	free(x);
}
END_TEST

/* one spike of 1e308 (or 1e200, 1e160) in unit noise: the deviation of
 * the record scaled down by 2^-1000 (where nothing overflows), scaled
 * back -- not the zero a squared sum that overflowed once gave */
START_TEST(allan_spike)
{
	static const double spikes[] = { 1e308, 1e200, 1e160, 1e-300 };
	struct sscope_allan_opts o = { 0 };

	for (size_t s = 0; s < 4; s++) {
		double *x = record(14, spikes[s]), *y;
		struct sscope_allan_point a[6], b[6];
		size_t na, nb;
		int k = spikes[s] > 1 ? -1000 : 900;

		if (spikes[s] < 1) /* N(0, 1e-300): all of it tiny */
			for (size_t i = 0; i < N; i++)
				x[i] *= 1e-300;
		oadev(x, &o, a, &na);
		y = scaled(x, k);
		oadev(y, &o, b, &nb);
		for (size_t i = 0; i < na; i++) {
			ck_assert(a[i].dev > 0 && isfinite(a[i].dev));
			ck_assert_rel(a[i].dev, ldexp(b[i].dev, -k), 1e-13);
		}
		free(x);
		free(y);
	}
}
END_TEST

START_TEST(allan_rate_range)
{
	double *x = record(15, 0);
	struct sscope_allan_result *r;
	struct sscope_diag d = { "" };

	ck_assert_int_eq(sscope_allan_analyze(x, 1, N, 4.9e-324,
					      SSCOPE_ALLAN_TAUS_OCTAVE, NULL, NULL,
					      &r, &d), -ERANGE);
	ck_assert_msg(strstr(d.msg, "outside 2^-200"), "%s", d.msg);
	ck_assert_int_eq(sscope_allan_analyze(x, 1, N, 1e308, SSCOPE_ALLAN_TAUS_OCTAVE,
					      NULL, NULL, &r, &d), -ERANGE);
	free(x);
}
END_TEST

static int welch(const double *x, double fs, struct sscope_psd_spectrum *s)
{
	struct sscope_psd_opts o;

	sscope_psd_opts_init(&o);
	o.nperseg = 512;
	o.spectrogram_cols = 0;
	return sscope_psd_welch(x, 1, N, fs, &o, s);
}

START_TEST(psd_scaled)
{
	double *x = record(16, 0), x0;
	struct sscope_psd_spectrum a, b;

	/* data times 2^k at 100 * 2^kf Hz: a density 2^(2k - kf) times,
	 * chosen within the double range */
	static const int kk[][2] = { { 1000, 1000 }, { 900, 900 }, { 500, 0 },
				     { -500, -500 }, { -900, -1000 } };

	ck_assert_int_eq(welch(x, 100, &a), 0);
	for (size_t j = 0; j < sizeof(kk) / sizeof(kk[0]); j++) {
		int k = kk[j][0], kf = kk[j][1];
		double *y = scaled(x, k), fs = ldexp(100, kf);

		ck_assert_int_eq(welch(y, fs, &b), 0);
		ck_assert_uint_eq(b.n_bins, a.n_bins);
		for (size_t i = 0; i < a.n_bins; i++) {
			ck_assert_rel(b.value[i], ldexp(a.value[i], 2 * k - kf),
				      1e-13);
			ck_assert_rel(b.freq_hz[i], ldexp(a.freq_hz[i], kf), 1e-15);
		}
		ck_assert_rel(b.rms, ldexp(a.rms, k), 1e-13);
		sscope_psd_spectrum_clear(&b);
		free(y);
	}
	/* beyond the range: 1e308 data at 100 Hz (1e616 per Hz), any data
	 * at 4.9e-324 Hz (no frequency step) or at 1e300 Hz (1e-300 per Hz,
	 * where the bins beside the largest are subnormal) */
	x0 = x[0];
	x[0] = 1e308;
	ck_assert_int_eq(welch(x, 100, &b), -ERANGE);
	x[0] = x0;
	ck_assert_int_eq(welch(x, 4.9e-324, &b), -ERANGE);
	{
		/* 2^-1000 data at 2^-1000 Hz: 1e-302 per Hz, refused */
		double *y = scaled(x, -1000);

		ck_assert_int_eq(welch(y, ldexp(100, -1000), &b), -ERANGE);
		free(y);
	}
	ck_assert_int_eq(welch(x, 1e300, &b), -ERANGE);
	ck_assert_int_eq(welch(x, 1e200, &b), 0); /* 1e-200 per Hz: fine */
	ck_assert_rel(b.rms, a.rms, 1e-13);
	sscope_psd_spectrum_clear(&b);
	sscope_psd_spectrum_clear(&a);
	free(x);
}
END_TEST

START_TEST(kurtosis_scaled)
{
	double *x = record(17, 0), ka, kb;

	ck_assert_int_eq(sscope_vib_kurtosis(x, 1, N, &ka), 0);
	for (size_t j = 0; j < sizeof(ks) / sizeof(ks[0]); j++) {
		double *y = scaled(x, ks[j]);

		ck_assert_int_eq(sscope_vib_kurtosis(y, 1, N, &kb), 0);
		ck_assert_rel(kb, ka, 1e-14);
		free(y);
	}
	free(x);
}
END_TEST

/* entry points that do not scale refuse magnitudes they would square
 * out of range */
START_TEST(refusals)
{
	double *x = record(18, 1e200);
	struct sscope_vib_opts vo;
	struct sscope_vib_result vr;
	struct sscope_diag d = { "" };

	sscope_vib_opts_init(&vo);
	ck_assert_int_eq(sscope_vib_analyze(x, 1, N, 1000, &vo, &vr, &d),
			 -ERANGE);
	ck_assert_msg(strstr(d.msg, "lies outside 2^-120 .. 2^120"), "%s", d.msg);
	x[N / 2] = 1e70;
	ck_assert_int_eq(ssc_magnitude_check(x, 1, N, 250, "t", NULL), 0);
	x[1] = 1e300;
	ck_assert_int_eq(ssc_magnitude_check(x, 1, N, 250, "t", NULL), -ERANGE);
	free(x);
}
END_TEST

START_TEST(budget_extremes)
{
	struct sscope_budget_params p = { 0 };
	struct sscope_budget_point a, b;
	struct sscope_budget_mc_opts mo = { 0 };
	struct sscope_budget_mc_point ma, mb;
	double t = 100;

	p.gyro_bias_rad_s = 1e-5;
	p.accel_bias_m_s2 = 2e-3;
	p.arw_rad_sqrt_s = 3e-4;
	p.vrw_m_s_sqrt_s = 1e-3;
	ck_assert_int_eq(sscope_budget_total(&p, t, &a), 0);
	/* every source 2^k times: the total 2^k times, where the squares
	 * of the sources overflow or underflow */
	for (size_t j = 0; j < sizeof(ks) / sizeof(ks[0]); j++) {
		struct sscope_budget_params q = p;

		q.gyro_bias_rad_s = ldexp(p.gyro_bias_rad_s, ks[j] / 2);
		q.accel_bias_m_s2 = ldexp(p.accel_bias_m_s2, ks[j] / 2);
		q.arw_rad_sqrt_s = ldexp(p.arw_rad_sqrt_s, ks[j] / 2);
		q.vrw_m_s_sqrt_s = ldexp(p.vrw_m_s_sqrt_s, ks[j] / 2);
		ck_assert_int_eq(sscope_budget_total(&q, t, &b), 0);
		ck_assert_rel(b.position_m, ldexp(a.position_m, ks[j] / 2), 1e-14);
	}
	p.gyro_bias_rad_s = 1e305;
	ck_assert_int_eq(sscope_budget_total(&p, 1000, &b), -ERANGE);
	/* the Monte Carlo walks are linear in the strength */
	mo.steps = 100;
	mo.realisations = 200;
	mo.t_end_s = t;
	mo.strength = 3e-4;
	mo.seed = 5;
	ck_assert_int_eq(sscope_budget_mc(&mo, &t, 1, &ma, NULL, 0), 0);
	mo.strength = ldexp(3e-4, -1000);
	ck_assert_int_eq(sscope_budget_mc(&mo, &t, 1, &mb, NULL, 0), 0);
	ck_assert_rel(mb.walk_sd, ldexp(ma.walk_sd, -1000), 1e-13);
	ck_assert(mb.walk_inside == ma.walk_inside);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("extreme");
	TCase *tc = tcase_create("extreme");

	tcase_add_test(tc, stats_scaled);
	tcase_add_test(tc, allan_scaled);
	tcase_add_test(tc, allan_fit_scaled);
	tcase_add_test(tc, allan_spike);
	tcase_add_test(tc, allan_rate_range);
	tcase_add_test(tc, psd_scaled);
	tcase_add_test(tc, kurtosis_scaled);
	tcase_add_test(tc, refusals);
	tcase_add_test(tc, budget_extremes);
	suite_add_tcase(s, tc);
	return s;
}
