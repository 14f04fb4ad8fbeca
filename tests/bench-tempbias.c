/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark of sscope_tempbias_fit(): a 24 h, 100 Hz accelerometer record
 * from the simulator (temperature cycled -10..50 degC, period 4 h, cubic
 * bias, hysteresis, gradient term, white noise 120 ug/sqrt(Hz)): run time
 * and peak memory of the fit, then the fit error (max |b_fit(T) -
 * b_true(T)| over the range, and the error of c1 in its sd) against the
 * temperature bin width / number of bins.
 */
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <time.h>

#define C1 8e-4
#define C2 2e-5
#define C3 3e-7
#define TREF 20.0

static double now(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static long maxrss_kib(void)
{
	struct rusage u;

	getrusage(RUSAGE_SELF, &u);
	return u.ru_maxrss;
}

static double truth(double T)
{
	double u = T - TREF;

	return 0.02 + u * (C1 + u * (C2 + u * C3));
}

int main(void)
{
	size_t n = 24 * 3600 * 100;
	double *x = malloc(n * sizeof(double)), *t = malloc(n * sizeof(double));
	struct sscope_sensor_spec sp = { 0 };
	struct sscope_sim_opts o = { 0 };
	struct sscope_sim *s = NULL;
	struct sscope_diag d = { "" };
	static const double bins[] = { 0.03, 0.1, 0.3, 0.6, 1, 2, 5, 10 };
	double t0;
	long rss0;

	if (!x || !t)
		return 1;
	sp.quantity = SSCOPE_QUANTITY_ACCELERATION;
	sp.n = 1.2e-3;
	sp.bias = 0.02;
	o.rate_hz = 100;
	o.seed = 31;
	o.temp_profile = SSCOPE_SIM_TEMP_CYCLE;
	o.temp_degc = -10;
	o.temp2_degc = 50;
	o.temp_period_s = 4 * 3600;
	o.temp_noise_degc = 0.01;
	o.ref_temp_degc = TREF;
	o.bias_poly[0] = C1;
	o.bias_poly[1] = C2;
	o.bias_poly[2] = C3;
	o.hysteresis = 3e-3;
	o.gradient = 0.05;
	o.no_clip = true;
	if (sscope_sim_new(&s, &sp, &o, &d)) {
		fprintf(stderr, "%s\n", d.msg);
		return 1;
	}
	t0 = now();
	sscope_sim_generate(s, NULL, x, t, n);
	printf("simulated %zu samples (24 h at 100 Hz) in %.2f s\n", n, now() - t0);
	sscope_sim_free(s);
	rss0 = maxrss_kib();
	for (size_t b = 0; b < sizeof(bins) / sizeof(bins[0]); b++) {
		struct sscope_tempbias_run r = { x, 1, t, n, 100 };
		struct sscope_tempbias_opts to = { .order = 3, .ref_temp_set = true,
						   .ref_temp_degc = TREF,
						   .bin_degc = bins[b] };
		struct sscope_tempbias_result *res = NULL;
		double best = INFINITY, err = 0;

		for (int rep = 0; rep < 3; rep++) {
			double t1 = now();

			sscope_tempbias_result_free(res);
			res = NULL;
			if (sscope_tempbias_fit(&r, 1, &to, &res, &d)) {
				fprintf(stderr, "fit: %s\n", d.msg);
				return 1;
			}
			best = fmin(best, now() - t1);
		}
		for (int i = 0; i <= 600; i++) {
			double T = -10 + 0.1 * i;

			err = fmax(err, fabs(sscope_tempbias_eval(res, T) - truth(T)));
		}
		printf("bin %5.2f degC (%4zu bins): fit %.3f s (best of 3), max |b_fit - b_true| %.3g m/s^2 (%.3g mg), c1 error %.2f sd, hysteresis %.4g (true 0.003)\n",
		       bins[b], res->n_bins, best, err, err / 9.80665e-3,
		       (res->coef[1] - C1) / res->coef_sd[1], res->hysteresis);
		if (b == 0)
			printf("peak memory: %ld KiB before the fits (data: %zu KiB), %ld KiB after\n",
			       rss0, 2 * n * sizeof(double) / 1024, maxrss_kib());
		sscope_tempbias_result_free(res);
	}
	free(x);
	free(t);
	return 0;
}
