/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * PSD: equality with scipy.signal.welch / periodogram / get_window on the
 * committed reference (tests/data/psd-ref.txt, made by make-psd-ref.py),
 * closed forms (white-noise level 2 sigma^2 / fs, a sine's A^2 / 2,
 * Parseval, window figures), exact sub-bin interpolation of off-bin tones
 * for every window, streaming = one shot, thread-count independence,
 * IEC 61260-1 bands, spectrogram, degenerate inputs and every error code.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "check-main.h"

#define PI 3.14159265358979323846

/* ------------------------------------------------------------ scipy */

struct refsig {
	char name[32];
	size_t n;
	double fs;
	double *x;
};

static FILE *open_ref(void)
{
	const char *top = getenv("top_srcdir");
	char path[1024];
	FILE *f;

	snprintf(path, sizeof(path), "%s/tests/data/psd-ref.txt",
		 top ? top : "..");
	f = fopen(path, "r");
	if (!f)
		f = fopen("tests/data/psd-ref.txt", "r");
	ck_assert_msg(f != NULL, "cannot open %s", path);
	return f;
}

static int detrend_of(const char *s)
{
	return !strcmp(s, "constant") ? SSCOPE_PSD_DETREND_CONSTANT :
	       !strcmp(s, "linear")   ? SSCOPE_PSD_DETREND_LINEAR :
					SSCOPE_PSD_DETREND_NONE;
}

/* Compare one estimate with scipy's: relative 1e-10 per bin; bins whose
 * reference is below 1e-20 of the largest are rounding noise of an exact
 * zero (the DC bin of a detrended boxcar segment) and must be just as
 * negligible. */
static void compare(const struct sscope_psd_spectrum *s, const double *f,
		    const double *p, size_t nb, const char *what)
{
	double pmax = 0;

	ck_assert_msg(s->n_bins == nb, "%s: %zu bins, scipy %zu", what,
		      s->n_bins, nb);
	for (size_t k = 0; k < nb; k++)
		pmax = fmax(pmax, fabs(p[k]));
	for (size_t k = 0; k < nb; k++) {
		ck_assert_msg(fabs(s->freq_hz[k] - f[k]) <= 1e-12 * fabs(f[k]),
			      "%s: f[%zu] %.17g vs %.17g", what, k,
			      s->freq_hz[k], f[k]);
		if (fabs(p[k]) < 1e-20 * pmax)
			ck_assert_msg(fabs(s->value[k]) < 1e-18 * pmax,
				      "%s: bin %zu %.17g vs ~0", what, k,
				      s->value[k]);
		else
			ck_assert_msg(fabs(s->value[k] - p[k]) <=
					      1e-10 * fabs(p[k]),
				      "%s: bin %zu: %.17g vs scipy %.17g (rel %.3g)",
				      what, k, s->value[k], p[k],
				      fabs(s->value[k] - p[k]) / fabs(p[k]));
	}
}

START_TEST(scipy_reference)
{
	FILE *f = open_ref();
	char line[4096];
	struct refsig sigs[8];
	size_t nsig = 0, ncases = 0, nwin = 0, bigcombo = 0;

	while (fgets(line, sizeof(line), f)) {
		char kind[32], sname[32], win[32], nps[16], nov[16], nff[16];
		char det[16], scal[16], wname[32];
		size_t nb, n;
		double fs;

		if (line[0] == '#')
			continue;
		if (sscanf(line, "signal %31s %zu %lf", sname, &n, &fs) == 3) {
			struct refsig *s = &sigs[nsig++];

			ck_assert(nsig <= 8);
			snprintf(s->name, sizeof(s->name), "%s", sname);
			s->n = n;
			s->fs = fs;
			s->x = malloc(n * sizeof(double));
			for (size_t i = 0; i < n; i++)
				ck_assert(fscanf(f, "%lf", &s->x[i]) == 1);
			continue;
		}
		if (sscanf(line, "window %31s %zu", wname, &n) == 2) {
			enum sscope_psd_window w;
			double *ref = malloc(n * sizeof(double));
			double *got = malloc(n * sizeof(double));

			for (size_t i = 0; i < n; i++)
				ck_assert(fscanf(f, "%lf", &ref[i]) == 1);
			ck_assert_int_eq(sscope_psd_window_from_name(wname, &w), 0);
			ck_assert_int_eq(sscope_psd_window_fill(w, n, got), 0);
			for (size_t i = 0; i < n; i++)
				ck_assert_msg(fabs(got[i] - ref[i]) <= 4e-16,
					      "window %s[%zu] of %zu: %.17g vs %.17g",
					      wname, i, n, got[i], ref[i]);
			free(ref);
			free(got);
			nwin++;
			continue;
		}
		if (sscanf(line, "case %31s %31s %31s %15s %15s %15s %15s %15s %zu",
			   kind, sname, win, nps, nov, nff, det, scal, &nb) == 9) {
			struct refsig *s = NULL;
			double *rf = malloc(nb * sizeof(double));
			double *rp = malloc(nb * sizeof(double));
			struct sscope_psd_spectrum sp;
			enum sscope_psd_window w;
			char what[256];
			int rc;

			for (size_t i = 0; i < nb; i++)
				ck_assert(fscanf(f, "%lf %lf", &rf[i], &rp[i]) == 2);
			for (size_t i = 0; i < nsig; i++)
				if (!strcmp(sigs[i].name, sname))
					s = &sigs[i];
			ck_assert(s != NULL);
			ck_assert_int_eq(sscope_psd_window_from_name(win, &w), 0);
			snprintf(what, sizeof(what), "%s %s %s nperseg %s noverlap %s nfft %s %s %s",
				 kind, sname, win, nps, nov, nff, det, scal);
			if (!strcmp(kind, "welch")) {
				struct sscope_psd_opts o;

				sscope_psd_opts_init(&o);
				o.window = w;
				if (strcmp(nps, "-"))
					o.nperseg = (size_t)atol(nps);
				if (strcmp(nov, "-"))
					o.noverlap = atol(nov) ? (size_t)atol(nov) :
								 SSCOPE_PSD_NO_OVERLAP;
				if (strcmp(nff, "-"))
					o.nfft = (size_t)atol(nff);
				o.detrend = detrend_of(det);
				o.scaling = !strcmp(scal, "density") ?
						    SSCOPE_PSD_SCALING_DENSITY :
						    SSCOPE_PSD_SCALING_SPECTRUM;
				rc = sscope_psd_welch(s->x, 1, s->n, s->fs, &o, &sp);
			} else {
				rc = sscope_psd_periodogram(
					s->x, 1, s->n, s->fs, w,
					strcmp(nff, "-") ? (size_t)atol(nff) : 0,
					detrend_of(det),
					!strcmp(scal, "density") ?
						SSCOPE_PSD_SCALING_DENSITY :
						SSCOPE_PSD_SCALING_SPECTRUM,
					&sp);
			}
			ck_assert_msg(rc == 0, "%s: %s", what, sscope_strerror(rc));
			compare(&sp, rf, rp, nb, what);
			if (strcmp(sname, "one"))
				bigcombo++;
			sscope_psd_spectrum_clear(&sp);
			free(rf);
			free(rp);
			ncases++;
		}
	}
	fclose(f);
	/* 3 signals x 6 windows x 3 detrends x 2 scalings + variants */
	ck_assert_uint_ge(bigcombo, 3 * 6 * 3 * 2 + 12);
	ck_assert_uint_eq(nwin, 18);
	ck_assert_uint_ge(ncases, 122);
	for (size_t i = 0; i < nsig; i++)
		free(sigs[i].x);
}
END_TEST

/* ------------------------------------------------------------ closed forms */

START_TEST(white_noise_level)
{
	/* one-sided white-noise PSD = 2 sigma^2 / fs; the mean over interior
	 * bins estimates the variance from every sample: relative sd about
	 * sqrt(2 / N) (times the window's ENBW for the overlap weighting),
	 * asserted within 4 sd with a fixed seed */
	const size_t n = (size_t)1 << 17;
	const double sigma = 2.385, fs = 250;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double *x = malloc(n * sizeof(double)), mean = 0, tol;
	struct sscope_psd_spectrum s;
	size_t cnt = 0;

	gsl_rng_set(r, 11);
	for (size_t i = 0; i < n; i++)
		x[i] = 7 + gsl_ran_gaussian_ziggurat(r, sigma);
	ck_assert_int_eq(sscope_psd_welch(x, 1, n, fs, NULL, &s), 0);
	ck_assert_uint_eq(s.nperseg, 256);
	ck_assert_uint_eq(s.n_segments, (n - 128) / 128);
	for (size_t k = 1; k + 1 < s.n_bins; k++, cnt++)
		mean += s.value[k];
	mean /= (double)cnt;
	tol = 4 * sqrt(2 * 1.5 / (double)n);
	ck_assert_msg(fabs(mean / (2 * sigma * sigma / fs) - 1) < tol,
		      "white level %.6g vs %.6g (tol %.3g)", mean,
		      2 * sigma * sigma / fs, tol);
	/* overall rms = sqrt(integral) ~ sigma */
	ck_assert_msg(fabs(s.rms / sigma - 1) < tol, "rms %.6g", s.rms);
	sscope_psd_spectrum_clear(&s);
	free(x);
	gsl_rng_free(r);
}
END_TEST

START_TEST(parseval)
{
	/* periodogram, boxcar, no detrend: integral of the density = mean
	 * square exactly; Welch: = mean over segments of sum (w x_d)^2 /
	 * sum w^2 */
	const size_t n = 3001, m = 500, step = 250;
	double *x = malloc(n * sizeof(double)), *w = malloc(m * sizeof(double));
	struct sscope_psd_spectrum s;
	struct sscope_psd_opts o;
	double ms = 0, want = 0, sw2 = 0;
	size_t nseg = 0;

	for (size_t i = 0; i < n; i++)
		x[i] = sin(0.37 * (double)i) + 0.25 * cos(0.0123 * (double)i * (double)i) + 1.5;
	ck_assert_int_eq(sscope_psd_periodogram(x, 1, n, 10, SSCOPE_PSD_WINDOW_BOXCAR, 0,
						SSCOPE_PSD_DETREND_NONE,
						SSCOPE_PSD_SCALING_DENSITY, &s), 0);
	for (size_t i = 0; i < n; i++)
		ms += x[i] * x[i];
	ck_assert_rel(s.rms * s.rms, ms / (double)n, 1e-13);
	ck_assert_int_eq(sscope_psd_spectrum_band_ms(&s, 0, 5, &ms), 0);
	ck_assert_rel(ms, s.rms * s.rms, 1e-13);
	sscope_psd_spectrum_clear(&s);

	sscope_psd_opts_init(&o);
	o.nperseg = m;
	o.window = SSCOPE_PSD_WINDOW_BLACKMAN;
	o.detrend = SSCOPE_PSD_DETREND_LINEAR;
	o.scaling = SSCOPE_PSD_SCALING_SPECTRUM; /* rms is the same number */
	ck_assert_int_eq(sscope_psd_welch(x, 1, n, 10, &o, &s), 0);
	sscope_psd_window_fill(SSCOPE_PSD_WINDOW_BLACKMAN, m, w);
	for (size_t i = 0; i < m; i++)
		sw2 += w[i] * w[i];
	for (size_t st = 0; st + m <= n; st += step, nseg++) {
		/* least-squares line of the segment */
		double sx = 0, sxy = 0, c = (m - 1) / 2.0, b, a, e = 0;

		for (size_t i = 0; i < m; i++)
			sx += x[st + i];
		a = sx / (double)m;
		for (size_t i = 0; i < m; i++)
			sxy += ((double)i - c) * (x[st + i] - a);
		b = sxy / ((double)m * ((double)m * m - 1) / 12);
		for (size_t i = 0; i < m; i++) {
			double v = (x[st + i] - a - b * ((double)i - c)) * w[i];

			e += v * v;
		}
		want += e / sw2;
	}
	ck_assert_uint_eq(s.n_segments, nseg);
	ck_assert_rel(s.rms * s.rms, want / (double)nseg, 1e-12);
	sscope_psd_spectrum_clear(&s);
	free(x);
	free(w);
}
END_TEST

START_TEST(sine_on_bin)
{
	/* a bin-centred sine of amplitude A: "spectrum" peak A^2 / 2 */
	const size_t n = 8192, m = 1024;
	const double fs = 1024, A = 2.385;
	double *x = malloc(n * sizeof(double));
	struct sscope_psd_opts o;
	struct sscope_psd_spectrum s;

	for (size_t i = 0; i < n; i++)
		x[i] = A * sin(2 * PI * 100 * (double)i / fs + 0.3);
	for (int w = 0; w < SSCOPE_PSD_WINDOW_COUNT_; w++) {
		sscope_psd_opts_init(&o);
		o.nperseg = m;
		o.window = (enum sscope_psd_window)w;
		o.scaling = SSCOPE_PSD_SCALING_SPECTRUM;
		ck_assert_int_eq(sscope_psd_welch(x, 1, n, fs, &o, &s), 0);
		ck_assert_rel(s.value[100], A * A / 2, 1e-9);
		sscope_psd_spectrum_clear(&s);
	}
	free(x);
}
END_TEST

START_TEST(sine_off_bin)
{
	/* off-bin tones: interpolated frequency within 0.01 bin and
	 * amplitude within 0.1 % for every window, in density and spectrum
	 * scaling and with zero padding; tones near fs/4 so that the image
	 * at -f leaks less than 1e-3 even through the boxcar */
	const size_t n = 32768, m = 1024;
	const double fs = 1000, A = 2.385;
	const double f0[3] = { 250.37, 251.8, 249.02 };
	double *x = malloc(n * sizeof(double));

	for (int t = 0; t < 3; t++) {
		for (size_t i = 0; i < n; i++)
			x[i] = A * cos(2 * PI * f0[t] * (double)i / fs + 1.1) + 0.7;
		for (int w = 0; w < SSCOPE_PSD_WINDOW_COUNT_; w++)
			for (int v = 0; v < 3; v++) {
				struct sscope_psd_opts o;
				struct sscope_psd_spectrum s;
				struct sscope_psd_peak pk[3];
				size_t np;
				double bin;

				sscope_psd_opts_init(&o);
				o.nperseg = m;
				o.window = (enum sscope_psd_window)w;
				o.scaling = v == 1 ? SSCOPE_PSD_SCALING_SPECTRUM :
						     SSCOPE_PSD_SCALING_DENSITY;
				o.nfft = v == 2 ? 2 * m : 0;
				ck_assert_int_eq(sscope_psd_welch(x, 1, n, fs, &o, &s), 0);
				bin = fs / (double)s.nfft;
				ck_assert_int_eq(sscope_psd_spectrum_peaks(&s, 3, 0, fs / 2, pk, &np), 0);
				ck_assert_uint_ge(np, 1);
				ck_assert_msg(fabs(pk[0].frequency_hz - f0[t]) < 0.01 * bin,
					      "%s v%d f0 %g: %.6f (%.4f bins off)",
					      sscope_psd_window_name(o.window), v, f0[t],
					      pk[0].frequency_hz,
					      (pk[0].frequency_hz - f0[t]) / bin);
				ck_assert_msg(fabs(pk[0].amplitude / A - 1) < 1e-3,
					      "%s v%d f0 %g: amplitude %.6f",
					      sscope_psd_window_name(o.window), v, f0[t],
					      pk[0].amplitude);
				ck_assert_rel(pk[0].rms, pk[0].amplitude / sqrt(2.0), 1e-15);
				sscope_psd_spectrum_clear(&s);
			}
	}
	free(x);
}
END_TEST

START_TEST(window_figures)
{
	/* periodic cosine sums (n > 2K): sum w = n a0, sum w^2 = n (a0^2 +
	 * sum_{k>0} a_k^2 / 2), so CG = a0, ENBW = (a0^2 + sum a_k^2/2)/a0^2;
	 * scalloping losses as tabulated by Harris (1978) */
	static const struct {
		enum sscope_psd_window w;
		double a[5];
		double scallop_db;
	} t[] = {
		{ SSCOPE_PSD_WINDOW_HANN, { 0.5, 0.5 }, -1.42 },
		{ SSCOPE_PSD_WINDOW_HAMMING, { 0.54, 0.46 }, -1.75 },
		{ SSCOPE_PSD_WINDOW_BLACKMAN, { 0.42, 0.50, 0.08 }, -1.10 },
		{ SSCOPE_PSD_WINDOW_BLACKMANHARRIS,
		  { 0.35875, 0.48829, 0.14128, 0.01168 }, -0.83 },
		{ SSCOPE_PSD_WINDOW_FLATTOP,
		  { 0.21557895, 0.41663158, 0.277263158, 0.083578947, 0.006947368 },
		  -0.02 },
		{ SSCOPE_PSD_WINDOW_BOXCAR, { 1 }, -3.92 },
	};
	for (size_t i = 0; i < sizeof(t) / sizeof(t[0]); i++) {
		struct sscope_psd_window_figures f;
		double q = t[i].a[0] * t[i].a[0];

		for (int k = 1; k < 5; k++)
			q += t[i].a[k] * t[i].a[k] / 2;
		ck_assert_int_eq(sscope_psd_window_figures(t[i].w, 1024, &f), 0);
		ck_assert_rel(f.coherent_gain, t[i].a[0], 1e-13);
		ck_assert_rel(f.enbw_bins, q / (t[i].a[0] * t[i].a[0]), 1e-12);
		ck_assert_msg(fabs(f.scalloping_db - t[i].scallop_db) < 0.02,
			      "%s scalloping %.4f dB",
			      sscope_psd_window_name(t[i].w), f.scalloping_db);
		/* the closed-form transform: sum w at 0, zeros at whole bins
		 * beyond the main lobe */
		ck_assert_rel(sscope_psd_window_response(t[i].w, 1024, 1024, 0), f.sum, 1e-12);
		ck_assert(sscope_psd_window_response(t[i].w, 1024, 1024, 7) < 1e-9 * f.sum);
	}
	/* hann by hand: ENBW exactly 1.5 bins */
	{
		struct sscope_psd_window_figures f;

		ck_assert_int_eq(sscope_psd_window_figures(SSCOPE_PSD_WINDOW_HANN, 8, &f), 0);
		ck_assert_rel(f.sum, 4, 1e-15);
		ck_assert_rel(f.sum_sq, 3, 1e-15);
		ck_assert_rel(f.enbw_bins, 1.5, 1e-15);
	}
	/* the response against a direct DTFT sum at an odd offset */
	{
		double w[37], re = 0, im = 0, nu = 2.3 / 64;

		sscope_psd_window_fill(SSCOPE_PSD_WINDOW_BLACKMANHARRIS, 37, w);
		for (int j = 0; j < 37; j++) {
			re += w[j] * cos(2 * PI * nu * j);
			im -= w[j] * sin(2 * PI * nu * j);
		}
		ck_assert_rel(sscope_psd_window_response(SSCOPE_PSD_WINDOW_BLACKMANHARRIS, 37, 64, 2.3),
			      hypot(re, im), 1e-12);
	}
}
END_TEST

/* ------------------------------------------------------------ streaming */

START_TEST(streaming_equals_one_shot)
{
	const size_t n = 200003;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double *x = malloc(2 * n * sizeof(double));
	struct sscope_psd_opts o;
	struct sscope_psd_spectrum a, b, c;
	struct sscope_psd *p;
	size_t done = 0;

	gsl_rng_set(r, 12);
	for (size_t i = 0; i < 2 * n; i++)
		x[i] = gsl_ran_gaussian_ziggurat(r, 1) + (double)(i % 2) * 5;
	sscope_psd_opts_init(&o);
	o.nperseg = 1000;
	o.noverlap = 333;
	o.nfft = 1024;
	o.window = SSCOPE_PSD_WINDOW_FLATTOP;
	o.threads = 1;
	/* one shot of the odd channel (stride 2) */
	ck_assert_int_eq(sscope_psd_welch(x + 1, 2, n, 3, &o, &a), 0);
	/* chunks of random sizes */
	ck_assert_int_eq(sscope_psd_new(&p, &o), 0);
	while (done < n) {
		size_t k = gsl_rng_uniform_int(r, 5000);

		if (k > n - done)
			k = n - done;
		ck_assert_int_eq(sscope_psd_feed(p, x + 1 + 2 * done, 2, k), 0);
		done += k;
		if (gsl_rng_uniform(r) < 0.01) {
			/* an intermediate result does not disturb the stream */
			ck_assert_int_eq(sscope_psd_result(p, 3, &c), 0);
			sscope_psd_spectrum_clear(&c);
		}
	}
	ck_assert_int_eq(sscope_psd_result(p, 3, &b), 0);
	ck_assert_uint_eq(a.n_segments, b.n_segments);
	ck_assert_uint_eq(a.n_segments, (n - 333) / 667);
	/* the last segment ends where the next one would not fit */
	ck_assert_uint_eq(sscope_psd_segments_end(p, n),
			  (a.n_segments - 1) * 667 + 1000);
	ck_assert_uint_eq(sscope_psd_segments_end(p, 999), 0);
	ck_assert_uint_eq(sscope_psd_segments_end(p, 1666), 1000);
	ck_assert_uint_eq(sscope_psd_segments_end(p, 1667), 1667);
	ck_assert_uint_eq(sscope_psd_segments_end(NULL, n), 0);
	for (size_t k = 0; k < a.n_bins; k++)
		ck_assert(a.value[k] == b.value[k]);
	sscope_psd_spectrum_clear(&b);
	/* more threads: bit-identical */
	o.threads = 3;
	ck_assert_int_eq(sscope_psd_welch(x + 1, 2, n, 3, &o, &b), 0);
	for (size_t k = 0; k < a.n_bins; k++)
		ck_assert(a.value[k] == b.value[k]);
	sscope_psd_spectrum_clear(&b);
	/* reset forgets */
	sscope_psd_reset(p);
	ck_assert_int_eq(sscope_psd_result(p, 3, &b), -EDOM);
	ck_assert_int_eq(sscope_psd_feed(p, x + 1, 2, n), 0);
	ck_assert_int_eq(sscope_psd_result(p, 3, &b), 0);
	for (size_t k = 0; k < a.n_bins; k++)
		ck_assert(a.value[k] == b.value[k]);
	sscope_psd_spectrum_clear(&a);
	sscope_psd_spectrum_clear(&b);
	sscope_psd_free(p);
	free(x);
	gsl_rng_free(r);
}
END_TEST

/* A record fed in pieces larger than a batch (after a piece that left
 * samples staged, the next is read in place past the stage) equals the
 * one-shot estimate bit for bit, with the same segment and sample
 * counts. */
START_TEST(large_pieces_equal_one_shot)
{
	const size_t n = 3000017;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double *x = malloc(n * sizeof(double));
	struct sscope_psd_opts o;
	struct sscope_psd_spectrum a, b;
	struct sscope_psd *p;
	size_t done = 0, pieces = 0;

	gsl_rng_set(r, 21);
	for (size_t i = 0; i < n; i++)
		x[i] = gsl_ran_gaussian_ziggurat(r, 1.7) + 2.385;
	sscope_psd_opts_init(&o);
	o.nperseg = 1000;
	o.noverlap = 333;
	o.nfft = 1024;
	o.threads = 2;
	ck_assert_int_eq(sscope_psd_welch(x, 1, n, 3, &o, &a), 0);
	ck_assert_int_eq(sscope_psd_new(&p, &o), 0);
	while (done < n) {
		/* up to 1.5 M samples: past a batch (about 0.7 M here) */
		size_t k = 1 + gsl_rng_uniform_int(r, 1500000);

		if (k > n - done)
			k = n - done;
		ck_assert_int_eq(sscope_psd_feed(p, x + done, 1, k), 0);
		done += k;
		pieces++;
	}
	ck_assert_uint_ge(pieces, 3);
	ck_assert_int_eq(sscope_psd_result(p, 3, &b), 0);
	ck_assert_uint_eq(a.n_segments, b.n_segments);
	ck_assert_uint_eq(b.n_segments, (n - 333) / 667);
	ck_assert_uint_eq(a.n_samples, b.n_samples);
	ck_assert_uint_eq(b.n_samples, n);
	for (size_t k = 0; k < a.n_bins; k++)
		ck_assert(a.value[k] == b.value[k]);
	sscope_psd_spectrum_clear(&a);
	sscope_psd_spectrum_clear(&b);
	sscope_psd_free(p);
	free(x);
	gsl_rng_free(r);
}
END_TEST

START_TEST(spectrogram)
{
	/* 60 Hz for the first half, 140 Hz for the second; 400 segments
	 * folded into at most 64 columns */
	const size_t n = 51300, m = 256;
	const double fs = 1000;
	double *x = malloc(n * sizeof(double));
	struct sscope_psd_opts o;
	struct sscope_psd *p;
	struct sscope_psd_spectrogram sg;
	struct sscope_psd_spectrum s;
	size_t used = 0;

	for (size_t i = 0; i < n; i++)
		x[i] = sin(2 * PI * (i < n / 2 ? 60.0 : 140.0) * (double)i / fs);
	sscope_psd_opts_init(&o);
	o.nperseg = m;
	o.spectrogram_cols = 64;
	ck_assert_int_eq(sscope_psd_new(&p, &o), 0);
	ck_assert_int_eq(sscope_psd_spectrogram(p, fs, &sg), -EDOM);
	ck_assert_int_eq(sscope_psd_feed(p, x, 1, n), 0);
	ck_assert_int_eq(sscope_psd_spectrogram(p, fs, &sg), 0);
	ck_assert_int_eq(sscope_psd_result(p, fs, &s), 0);
	ck_assert_uint_le(sg.n_times, 64);
	ck_assert_uint_ge(sg.n_times, 32);
	ck_assert_uint_eq(sg.n_bins, m / 2 + 1);
	for (size_t t = 0; t < sg.n_times; t++) {
		const double *col = sg.value + t * sg.n_bins;
		size_t best = 1;
		double tc = sg.time_s[t];

		for (size_t k = 1; k < sg.n_bins; k++)
			if (col[k] > col[best])
				best = k;
		if (t)
			ck_assert(sg.time_s[t] > sg.time_s[t - 1]);
		if (tc < n / 2 / fs - 1)
			ck_assert_msg(fabs(sg.freq_hz[best] - 60) < 4, "t %g: %g Hz", tc, sg.freq_hz[best]);
		else if (tc > n / 2 / fs + 1)
			ck_assert_msg(fabs(sg.freq_hz[best] - 140) < 4, "t %g: %g Hz", tc, sg.freq_hz[best]);
	}
	/* the first column's time is the centre of its segments */
	ck_assert_rel(sg.time_s[0],
		      ((double)(sg.segments_per_column - 1) * 128 / 2 + 128) / fs, 1e-12);
	/* the segment-weighted mean of the columns is the Welch estimate */
	for (size_t k = 0; k < sg.n_bins; k += 7) {
		double sum = 0;

		used = 0;
		for (size_t t = 0; t < sg.n_times; t++) {
			size_t cnt = t + 1 < sg.n_times ? sg.segments_per_column :
				     s.n_segments - (sg.n_times - 1) * sg.segments_per_column;

			sum += sg.value[t * sg.n_bins + k] * (double)cnt;
			used += cnt;
		}
		ck_assert_uint_eq(used, s.n_segments);
		ck_assert_rel(sum / (double)used, s.value[k], 1e-9);
	}
	sscope_psd_spectrogram_clear(&sg);
	sscope_psd_spectrum_clear(&s);
	sscope_psd_free(p);
	/* no spectrogram asked for */
	o.spectrogram_cols = 0;
	ck_assert_int_eq(sscope_psd_new(&p, &o), 0);
	ck_assert_int_eq(sscope_psd_spectrogram(p, fs, &sg), -EINVAL);
	sscope_psd_free(p);
	free(x);
}
END_TEST

/* ------------------------------------------------------------ bands */

START_TEST(octave_bands)
{
	struct sscope_psd_band b[64];
	size_t n;
	const double g = pow(10, 0.3);
	static const double oct_nominal[] = { 31.5, 63, 125, 250, 500, 1000,
					      2000, 4000, 8000, 16000 };

	/* third octaves of the audio range: 25 Hz .. 16 kHz */
	ck_assert_int_eq(sscope_psd_octave_bands(3, 20, 20000, b, 64, &n), 0);
	ck_assert_uint_eq(n, 29);
	ck_assert_rel(b[0].nominal_hz, 25, 1e-15);
	ck_assert_rel(b[28].nominal_hz, 16000, 1e-15);
	for (size_t i = 0; i < n; i++) {
		ck_assert_rel(b[i].hi_hz / b[i].lo_hz, pow(g, 1.0 / 3), 1e-13);
		ck_assert_rel(b[i].center_hz, sqrt(b[i].lo_hz * b[i].hi_hz), 1e-13);
		ck_assert_msg(fabs(b[i].center_hz / b[i].nominal_hz - 1) < 0.03,
			      "%g vs nominal %g", b[i].center_hz, b[i].nominal_hz);
		if (i)
			ck_assert_rel(b[i].lo_hz, b[i - 1].hi_hz, 1e-13);
	}
	ck_assert_rel(b[16].center_hz, 1000, 1e-15); /* x = 0 */
	ck_assert_rel(b[6].center_hz, 100, 1e-13);   /* x = -10 */
	/* octaves */
	ck_assert_int_eq(sscope_psd_octave_bands(1, 20, 23000, b, 64, &n), 0);
	ck_assert_uint_eq(n, 10);
	for (size_t i = 0; i < n; i++) {
		ck_assert_rel(b[i].nominal_hz, oct_nominal[i], 1e-14);
		ck_assert_rel(b[i].hi_hz / b[i].lo_hz, g, 1e-13);
	}
	/* counting, too small an array */
	ck_assert_int_eq(sscope_psd_octave_bands(3, 20, 20000, NULL, 0, &n), 0);
	ck_assert_uint_eq(n, 29);
	ck_assert_int_eq(sscope_psd_octave_bands(3, 20, 20000, b, 4, &n), -ERANGE);
	ck_assert_uint_eq(n, 4);
	/* even fraction: centres at G^((2x+1)/2b) */
	ck_assert_int_eq(sscope_psd_octave_bands(2, 900, 1500, b, 64, &n), 0);
	ck_assert_uint_ge(n, 1);
	ck_assert_rel(b[0].center_hz, 1000 * pow(g, 0.25), 1e-13);
	ck_assert_int_eq(sscope_psd_octave_bands(0, 20, 200, b, 64, &n), -EINVAL);
	ck_assert_int_eq(sscope_psd_octave_bands(3, 0, 200, b, 64, &n), -EINVAL);
	ck_assert_int_eq(sscope_psd_octave_bands(3, 300, 200, b, 64, &n), -EINVAL);
}
END_TEST

START_TEST(band_rms_partition)
{
	/* adjacent bands add up to the total; a tone's band holds A^2/2 */
	const size_t n = 40000;
	const double fs = 2000, A = 1.3;
	double *x = malloc(n * sizeof(double)), tot = 0, ms, edges[6] = { 0, 33.3, 100, 250.1, 700, 1000 };
	struct sscope_psd_spectrum s;
	struct sscope_psd_opts o;

	for (size_t i = 0; i < n; i++)
		x[i] = A * sin(2 * PI * 400.3 * (double)i / fs) + 0.1 * sin(2 * PI * 51 * (double)i / fs);
	sscope_psd_opts_init(&o);
	o.nperseg = 2000;
	o.window = SSCOPE_PSD_WINDOW_BLACKMANHARRIS;
	ck_assert_int_eq(sscope_psd_welch(x, 1, n, fs, &o, &s), 0);
	for (int i = 0; i < 5; i++) {
		ck_assert_int_eq(sscope_psd_spectrum_band_ms(&s, edges[i], edges[i + 1], &ms), 0);
		tot += ms;
	}
	ck_assert_rel(tot, s.rms * s.rms, 1e-12);
	ck_assert_int_eq(sscope_psd_spectrum_band_ms(&s, 380, 420, &ms), 0);
	ck_assert_rel(ms, A * A / 2, 1e-6);
	ck_assert_int_eq(sscope_psd_spectrum_band_ms(&s, 420, 380, &ms), -EINVAL);
	{
		struct sscope_psd_peak pk;

		ck_assert_int_eq(sscope_psd_spectrum_peak_near(&s, 51, 2, &pk), 0);
		ck_assert(fabs(pk.frequency_hz - 51) < 0.01);
		ck_assert_rel(pk.amplitude, 0.1, 1e-3);
		ck_assert_int_eq(sscope_psd_spectrum_peak_near(&s, 800, 2, &pk), -ENOENT);
		ck_assert_int_eq(sscope_psd_spectrum_peak_at(&s, 0, &pk), -EINVAL);
		ck_assert_int_eq(sscope_psd_spectrum_peak_at(&s, s.n_bins - 1, &pk), -EINVAL);
	}
	sscope_psd_spectrum_clear(&s);
	free(x);
}
END_TEST

/* ------------------------------------------------------------ edge cases */

START_TEST(degenerate_inputs)
{
	double x[300], c[300];
	struct sscope_psd_spectrum s;
	struct sscope_psd_opts o;
	struct sscope_psd_peak pk[4];
	size_t np;

	for (int i = 0; i < 300; i++) {
		x[i] = sin(i * 0.3) * 3 + i * 0.01;
		c[i] = 2.385;
	}
	/* nperseg > n: shortened to n, like scipy */
	sscope_psd_opts_init(&o);
	o.nperseg = 1000;
	ck_assert_int_eq(sscope_psd_welch(x, 1, 300, 10, &o, &s), 0);
	ck_assert_uint_eq(s.nperseg, 300);
	ck_assert_uint_eq(s.noverlap, 150);
	ck_assert_uint_eq(s.n_bins, 151);
	ck_assert_uint_eq(s.n_segments, 1);
	sscope_psd_spectrum_clear(&s);
	/* ... and in a stream only with opts.shorten */
	{
		struct sscope_psd *p;

		ck_assert_int_eq(sscope_psd_new(&p, &o), 0);
		ck_assert_int_eq(sscope_psd_feed(p, x, 1, 300), 0);
		ck_assert_int_eq(sscope_psd_result(p, 10, &s), -EDOM);
		sscope_psd_free(p);
		o.shorten = true;
		ck_assert_int_eq(sscope_psd_new(&p, &o), 0);
		ck_assert_int_eq(sscope_psd_feed(p, x, 1, 300), 0);
		ck_assert_int_eq(sscope_psd_result(p, 10, &s), 0);
		ck_assert_uint_eq(s.nperseg, 300);
		sscope_psd_spectrum_clear(&s);
		sscope_psd_free(p);
	}
	/* N = 1: one bin, zero after detrending */
	ck_assert_int_eq(sscope_psd_welch(x + 5, 1, 1, 10, NULL, &s), 0);
	ck_assert_uint_eq(s.n_bins, 1);
	ck_assert(s.value[0] == 0 && s.freq_hz[0] == 0 && s.rms == 0);
	ck_assert_int_eq(sscope_psd_spectrum_peaks(&s, 4, 0, 5, pk, &np), 0);
	ck_assert_uint_eq(np, 0);
	sscope_psd_spectrum_clear(&s);
	/* a constant: exact zeros, no peaks, for every detrend but none */
	for (int d = 0; d < 2; d++) {
		sscope_psd_opts_init(&o);
		o.nperseg = 64;
		o.detrend = d ? SSCOPE_PSD_DETREND_LINEAR : SSCOPE_PSD_DETREND_CONSTANT;
		ck_assert_int_eq(sscope_psd_welch(c, 1, 300, 10, &o, &s), 0);
		for (size_t k = 0; k < s.n_bins; k++)
			ck_assert(s.value[k] == 0);
		ck_assert(s.rms == 0);
		ck_assert_int_eq(sscope_psd_spectrum_peaks(&s, 4, 0, 5, pk, &np), 0);
		ck_assert_uint_eq(np, 0);
		sscope_psd_spectrum_clear(&s);
	}
	/* NaN: -EDOM, or the segments holding it are skipped */
	x[100] = NAN;
	sscope_psd_opts_init(&o);
	o.nperseg = 50;
	ck_assert_int_eq(sscope_psd_welch(x, 1, 300, 10, &o, &s), -EDOM);
	o.skip_nonfinite = true;
	ck_assert_int_eq(sscope_psd_welch(x, 1, 300, 10, &o, &s), 0);
	ck_assert_uint_eq(s.n_skipped, 2); /* segments at 75 and 100 */
	ck_assert_uint_eq(s.n_segments, 11 - 2);
	sscope_psd_spectrum_clear(&s);
	x[100] = INFINITY;
	o.skip_nonfinite = false;
	ck_assert_int_eq(sscope_psd_welch(x, 1, 300, 10, &o, &s), -EDOM);
	/* every segment non-finite */
	for (int i = 0; i < 300; i++)
		c[i] = NAN;
	o.skip_nonfinite = true;
	ck_assert_int_eq(sscope_psd_welch(c, 1, 300, 10, &o, &s), -EDOM);
	/* no sample */
	ck_assert_int_eq(sscope_psd_welch(x, 1, 0, 10, NULL, &s), -EDOM);
	ck_assert_int_eq(sscope_psd_periodogram(x, 1, 0, 10, SSCOPE_PSD_WINDOW_HANN, 0,
						SSCOPE_PSD_DETREND_NONE,
						SSCOPE_PSD_SCALING_DENSITY, &s), -EDOM);
}
END_TEST

/* a zero-initialised struct is scipy's defaults, spelled out; no overlap
 * has its own name */
START_TEST(zero_options_are_defaults)
{
	struct sscope_psd_opts z = { 0 }, d = { 0 };
	struct sscope_psd_spectrum a, b;
	double x[1024];
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	for (size_t i = 0; i < 1024; i++)
		x[i] = gsl_ran_gaussian_ziggurat(r, 1);
	gsl_rng_free(r);
	d.window = SSCOPE_PSD_WINDOW_HANN;
	d.nperseg = 256;
	d.noverlap = 128;
	d.detrend = SSCOPE_PSD_DETREND_CONSTANT;
	d.scaling = SSCOPE_PSD_SCALING_DENSITY;
	ck_assert_int_eq(sscope_psd_welch(x, 1, 1024, 100, &z, &a), 0);
	ck_assert_int_eq(sscope_psd_welch(x, 1, 1024, 100, &d, &b), 0);
	ck_assert_uint_eq(a.nperseg, 256);
	ck_assert_uint_eq(a.noverlap, 128);
	ck_assert_uint_eq(a.n_segments, 7);
	ck_assert_uint_eq(a.n_bins, b.n_bins);
	for (size_t k = 0; k < a.n_bins; k++)
		ck_assert(a.value[k] == b.value[k]);
	sscope_psd_spectrum_clear(&a);
	z.noverlap = SSCOPE_PSD_NO_OVERLAP;
	ck_assert_int_eq(sscope_psd_welch(x, 1, 1024, 100, &z, &a), 0);
	ck_assert_uint_eq(a.noverlap, 0);
	ck_assert_uint_eq(a.n_segments, 4);
	ck_assert_uint_eq(sscope_psd_noverlap(0, 256), SSCOPE_PSD_NO_OVERLAP);
	ck_assert_uint_eq(sscope_psd_noverlap(0.5, 256), 128);
	ck_assert_uint_eq(sscope_psd_noverlap(0.9999, 256), 255);
	sscope_psd_spectrum_clear(&a);
	sscope_psd_spectrum_clear(&b);
}
END_TEST

START_TEST(error_codes)
{
	struct sscope_psd_opts o;
	struct sscope_psd *p;
	struct sscope_psd_spectrum s;
	enum sscope_psd_window w;
	double x[64] = { 0 }, buf[4];
	struct sscope_psd_window_figures f;

	sscope_psd_opts_init(&o);
	o.noverlap = 256; /* the default nperseg */
	ck_assert_int_eq(sscope_psd_new(&p, &o), -EINVAL);
	sscope_psd_opts_init(&o);
	o.nfft = 100;
	ck_assert_int_eq(sscope_psd_new(&p, &o), -EINVAL);
	sscope_psd_opts_init(&o);
	o.window = SSCOPE_PSD_WINDOW_COUNT_;
	ck_assert_int_eq(sscope_psd_new(&p, &o), -EINVAL);
	sscope_psd_opts_init(&o);
	o.detrend = (enum sscope_psd_detrend)7;
	ck_assert_int_eq(sscope_psd_new(&p, &o), -EINVAL);
	ck_assert_int_eq(sscope_psd_new(NULL, NULL), -EINVAL);
	ck_assert_int_eq(sscope_psd_new(&p, NULL), 0);
	ck_assert_int_eq(sscope_psd_feed(p, NULL, 1, 5), -EINVAL);
	ck_assert_int_eq(sscope_psd_feed(p, x, 0, 5), -EINVAL);
	ck_assert_int_eq(sscope_psd_result(p, 0, &s), -EINVAL);
	ck_assert_int_eq(sscope_psd_result(p, NAN, &s), -EINVAL);
	ck_assert_int_eq(sscope_psd_result(p, 1, &s), -EDOM);
	sscope_psd_free(p);
	sscope_psd_free(NULL);
	ck_assert_int_eq(sscope_psd_welch(x, 1, 64, -1, NULL, &s), -EINVAL);
	sscope_psd_opts_init(&o);
	o.noverlap = 100;
	ck_assert_int_eq(sscope_psd_welch(x, 1, 64, 1, &o, &s), -EINVAL);
	ck_assert_int_eq(sscope_psd_window_from_name("kaiser", &w), -EINVAL);
	ck_assert_int_eq(sscope_psd_window_from_name("Hanning", &w), 0);
	ck_assert_int_eq(w, SSCOPE_PSD_WINDOW_HANN);
	ck_assert_int_eq(sscope_psd_window_fill(SSCOPE_PSD_WINDOW_HANN, 0, buf), -EINVAL);
	ck_assert_int_eq(sscope_psd_window_figures(SSCOPE_PSD_WINDOW_COUNT_, 4, &f), -EINVAL);
	ck_assert(isnan(sscope_psd_window_response(SSCOPE_PSD_WINDOW_HANN, 0, 4, 0)));
	ck_assert(sscope_psd_window_name(SSCOPE_PSD_WINDOW_COUNT_) == NULL);
	ck_assert_str_eq(sscope_psd_window_name(SSCOPE_PSD_WINDOW_BLACKMANHARRIS), "blackmanharris");
	sscope_psd_spectrum_clear(NULL);
	sscope_psd_spectrogram_clear(NULL);
}
END_TEST

/* Bands a spectrum resolves and its floor.  A 1 kHz record with 1 Hz bins
 * (1024-point periodogram at 1024 Hz): the octave bands inside [0.5, 512]
 * Hz at least one bin wide; the floor of white noise is the median of its
 * periodogram's exponentially distributed bins, ln 2 of their mean
 * (sampling error of the median of 511 bins about 7 %: 20 % is 3 sd);
 * given edges clipped at the Nyquist frequency. */
START_TEST(bands_and_floor)
{
	enum { N = 1024 };
	double x[N];
	struct sscope_psd_spectrum sp = { 0 };
	struct sscope_psd_band b[32];
	size_t n, m;

	uint64_t st = 2385;

	for (int i = 0; i < N; i++) { /* uniform white noise (64-bit LCG) */
		st = st * 6364136223846793005ULL + 1442695040888963407ULL;
		x[i] = 1.7 * ((double)(st >> 11) / 9007199254740992.0 - 0.5);
	}
	ck_assert_int_eq(sscope_psd_periodogram(x, 1, N, 1024, SSCOPE_PSD_WINDOW_BOXCAR, 0,
						SSCOPE_PSD_DETREND_CONSTANT,
						SSCOPE_PSD_SCALING_DENSITY, &sp), 0);
	ck_assert_int_eq(sscope_psd_spectrum_octave_bands(&sp, 1, b, 32, &n), 0);
	ck_assert_uint_ge(n, 5);
	for (size_t i = 0; i < n; i++) {
		ck_assert(b[i].hi_hz - b[i].lo_hz >= sp.bin_hz);
		ck_assert(b[i].lo_hz >= sp.bin_hz / 2 && b[i].hi_hz <= 512 * (1 + 1e-12));
	}
	ck_assert_int_eq(sscope_psd_spectrum_octave_bands(&sp, 1, b, 1, &m), -ERANGE);
	ck_assert_uint_eq(m, n);
	ck_assert_int_eq(sscope_psd_band_edges(10, 900, 512, &b[0]), 0);
	ck_assert(b[0].hi_hz == 512);
	ck_assert_rel(b[0].center_hz, sqrt(10 * 512.0), 1e-15);
	ck_assert(isnan(b[0].nominal_hz));
	ck_assert_int_eq(sscope_psd_band_edges(600, 900, 512, &b[0]), -EDOM);
	ck_assert_int_eq(sscope_psd_band_edges(20, 10, 512, &b[0]), -EINVAL);
	sscope_psd_spectrum_clear(&sp);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("psd");
	TCase *tc = tcase_create("psd");

	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, scipy_reference);
	tcase_add_test(tc, white_noise_level);
	tcase_add_test(tc, parseval);
	tcase_add_test(tc, sine_on_bin);
	tcase_add_test(tc, sine_off_bin);
	tcase_add_test(tc, window_figures);
	tcase_add_test(tc, streaming_equals_one_shot);
	tcase_add_test(tc, large_pieces_equal_one_shot);
	tcase_add_test(tc, spectrogram);
	tcase_add_test(tc, octave_bands);
	tcase_add_test(tc, band_rms_partition);
	tcase_add_test(tc, degenerate_inputs);
	tcase_add_test(tc, zero_options_are_defaults);
	tcase_add_test(tc, error_codes);
	tcase_add_test(tc, bands_and_floor);
	suite_add_tcase(s, tc);
	return s;
}
