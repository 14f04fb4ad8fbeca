/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark: Welch PSD of 1e7 samples with nperseg 4096 and 65536 (hann,
 * half overlap, constant detrend: scipy.signal.welch's defaults), best of
 * 3 including the workspace and its FFT plan, with FFTW_ESTIMATE and
 * FFTW_MEASURE planning; the error of the estimate against a long-double
 * direct-DFT reference on a short case; and a 1e8-sample stream fed in
 * chunks (memory bounded by the workspace) checked against the closed form
 * of its white-noise level.  scipy's time is measured separately (see the
 * README's benchmark table for the command).
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define PI 3.14159265358979323846

static double now(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static uint64_t lcg_state = 42;

/* uniform on [-0.5, 0.5): variance 1/12 */
static double uni(void)
{
	lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
	return (double)(lcg_state >> 11) / 9007199254740992.0 - 0.5;
}

static double time_welch(const double *x, size_t n, size_t nperseg,
			 bool measure, unsigned threads, size_t *nseg)
{
	double best = 1e9;

	for (int rep = 0; rep < 3; rep++) {
		struct sscope_psd_opts o;
		struct sscope_psd_spectrum s;
		double t0 = now();

		sscope_psd_opts_init(&o);
		o.nperseg = nperseg;
		o.measure = measure;
		o.threads = threads;
		if (sscope_psd_welch(x, 1, n, 1000, &o, &s))
			return -1;
		t0 = now() - t0;
		if (t0 < best)
			best = t0;
		*nseg = s.n_segments;
		sscope_psd_spectrum_clear(&s);
	}
	return best;
}

/* Welch by a direct DFT in long double: the reference */
static void reference(const double *x, size_t n, size_t m, long double *p)
{
	long double *w = malloc(m * sizeof(long double));
	long double *seg = malloc(m * sizeof(long double));
	long double sw2 = 0, *cs = malloc(m * sizeof(long double));
	long double *sn = malloc(m * sizeof(long double));
	size_t step = m / 2, nseg = 0, nb = m / 2 + 1;
	const long double pi = 3.141592653589793238462643383279502884L;

	for (size_t i = 0; i < m; i++) {
		w[i] = 0.5L - 0.5L * cosl(2 * pi * (long double)i / (long double)m);
		sw2 += w[i] * w[i];
		cs[i] = cosl(2 * pi * (long double)i / (long double)m);
		sn[i] = sinl(2 * pi * (long double)i / (long double)m);
	}
	for (size_t k = 0; k < nb; k++)
		p[k] = 0;
	for (size_t st = 0; st + m <= n; st += step, nseg++) {
		long double mean = 0;

		for (size_t i = 0; i < m; i++)
			mean += x[st + i];
		mean /= (long double)m;
		for (size_t i = 0; i < m; i++)
			seg[i] = ((long double)x[st + i] - mean) * w[i];
		for (size_t k = 0; k < nb; k++) {
			long double re = 0, im = 0;

			for (size_t i = 0; i < m; i++) {
				size_t j = (k * i) % m;

				re += seg[i] * cs[j];
				im -= seg[i] * sn[j];
			}
			p[k] += (re * re + im * im) * (k == 0 || k == m / 2 ? 1 : 2);
		}
	}
	for (size_t k = 0; k < nb; k++)
		p[k] /= (long double)nseg * 1000.0L * sw2;
	free(w);
	free(seg);
	free(cs);
	free(sn);
}

int main(void)
{
	const size_t n = 10000000;
	double *x = malloc(n * sizeof(double));
	int rc = 0;

	if (!x)
		return 1;
	for (size_t i = 0; i < n; i++)
		x[i] = uni() + 0.3 * sin(2 * PI * 123.4 * (double)i / 1000) + 2.5;
	for (int k = 0; k < 2; k++)
		for (unsigned th = 1; th <= 2; th++) {
			size_t m = k ? 65536 : 4096, nseg = 0;
			double te = time_welch(x, n, m, false, th == 1 ? 1 : 0, &nseg);
			double tm = time_welch(x, n, m, true, th == 1 ? 1 : 0, &nseg);

			printf("welch 1e7 samples, nperseg %5zu (%zu segments), %s: %.3f s (FFTW_ESTIMATE), %.3f s (FFTW_MEASURE, planning included)\n",
			       m, nseg, th == 1 ? "1 thread" : "OpenMP default threads",
			       te, tm);
			rc |= te < 0 || tm < 0;
		}
	/* accuracy on a short case */
	{
		const size_t ns = 16384, m = 1024, nb = m / 2 + 1;
		long double *ref = malloc(nb * sizeof(long double));
		struct sscope_psd_opts o;
		struct sscope_psd_spectrum s;
		double worst = 0, t0 = now();

		reference(x, ns, m, ref);
		t0 = now() - t0;
		sscope_psd_opts_init(&o);
		o.nperseg = m;
		sscope_psd_welch(x, 1, ns, 1000, &o, &s);
		for (size_t k = 1; k < nb; k++) {
			double e = (double)fabsl(((long double)s.value[k] - ref[k]) / ref[k]);

			worst = e > worst ? e : worst;
		}
		printf("error against a long-double direct DFT (16384 samples, nperseg 1024, hann): max relative %.2e over bins 1..%zu (reference took %.2f s)\n",
		       worst, nb - 1, t0);
		rc |= !(worst < 1e-12);
		sscope_psd_spectrum_clear(&s);
		free(ref);
	}
	/* 1e8 samples streamed in chunks: white noise level 2 (1/12) / fs */
	{
		const size_t total = 100000000, chunk = 65536;
		struct sscope_psd_opts o;
		struct sscope_psd *p;
		struct sscope_psd_spectrum s;
		double t0 = now(), mean = 0, want = 2.0 / 12 / 1000, tol;
		size_t done = 0;

		sscope_psd_opts_init(&o);
		o.nperseg = 4096;
		if (sscope_psd_new(&p, &o))
			return 1;
		while (done < total) {
			for (size_t i = 0; i < chunk; i++)
				x[i] = uni();
			sscope_psd_feed(p, x, 1, chunk < total - done ? chunk : total - done);
			done += chunk;
		}
		sscope_psd_result(p, 1000, &s);
		t0 = now() - t0;
		for (size_t k = 1; k + 1 < s.n_bins; k++)
			mean += s.value[k];
		mean /= (double)(s.n_bins - 2);
		tol = 4 * sqrt(2 * 1.5 / (double)total);
		printf("1e8 samples streamed in chunks of %zu (generation included): %.2f s, %zu segments, white level %.6g vs 2 sigma^2/fs = %.6g (relative %.1e, 4 sd = %.1e)\n",
		       chunk, t0, s.n_segments, mean, want, mean / want - 1, tol);
		rc |= !(fabs(mean / want - 1) < tol);
		sscope_psd_spectrum_clear(&s);
		sscope_psd_free(p);
	}
	free(x);
	return rc;
}
