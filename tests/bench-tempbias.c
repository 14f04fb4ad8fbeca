/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark of sscope_tempbias_fit(): a 24 h, 100 Hz accelerometer record
 * from the simulator (temperature cycled -10..50 degC, period 4 h, cubic
 * bias, hysteresis, gradient term, white noise 120 ug/sqrt(Hz)): run time
 * and peak memory of the fit, then the fit error (max |b_fit(T) -
 * b_true(T)| over the range, and the error of c1 in its sd) against the
 * temperature bin width / number of bins.
 *
 * Then the coverage table: on profiles where hysteresis and the dT/dt
 * gradient are identifiable (a sine cycle; ramps of unequal rates, fast
 * heating first), over R simulated 8 h records per case with white rate
 * noise, white + bias instability, and white + bias instability + rate
 * random walk, the fraction of records whose +-1 sd (68.3 %) and +-2 sd
 * (95.4 %) intervals of the hysteresis and of the gradient cover the
 * truth, the mean and rms of (estimate - truth) / sd, how often the two
 * terms were called collinear, and the share of each record the warm-up
 * detector removed (the records have no warm-up: it should be 0).  A
 * last row adds a warm-up transient and reports what was removed.
 */
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
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

/* gyro in deg/h: N 0.15 deg/sqrt(h) = 9 deg/h/sqrt(Hz), B 0.5 deg/h,
 * K 3 deg/h/sqrt(h) = 0.05 deg/h/sqrt(s); 2 deg/h/degC, hysteresis
 * 3 deg/h, gradient 60 deg/h per degC/s */
#define CR_HYST 3.0
#define CR_GRAD 60.0
#define CR_N 9.0
#define CR_B 0.5
#define CR_K 0.05
#define CR_DUR (8 * 3600)

/* fast heating (20 min), slow cooling (60), slow heating (60), fast
 * cooling (20) between -10 and 50 degC */
static double ramps(double t)
{
	static const double len[4] = { 1200, 3600, 3600, 1200 };
	double P = 9600, ph = fmod(t, P);

	for (int i = 0; i < 4; i++) {
		if (ph < len[i]) {
			double f = ph / len[i];

			return i % 2 == 0 ? -10 + 60 * f : 50 - 60 * f;
		}
		ph -= len[i];
	}
	return -10;
}

struct cr_case {
	const char *profile, *noise;
	bool sine, b, k, warm;
};

static int coverage_row(const struct cr_case *cc, int R, double *x, double *t,
			double *tn)
{
	size_t n = CR_DUR;
	int c1h = 0, c1g = 0, c2h = 0, c2g = 0, coll = 0, fails = 0, with = 0;
	double szh = 0, szg = 0, szh2 = 0, szg2 = 0, wmax = 0, wsum = 0;
	double cpu0 = (double)clock() / CLOCKS_PER_SEC;

	for (int r = 0; r < R; r++) {
		struct sscope_sensor_spec sp = { 0 }, tsp = { 0 };
		struct sscope_sim_opts o = { 0 }, to2 = { 0 };
		struct sscope_sim *s = NULL;
		struct sscope_diag d = { "" };
		struct sscope_tempbias_run run = { x, 1, tn, n, 1 };
		struct sscope_tempbias_opts fo = { .order_auto = true, .order = -1 };
		struct sscope_tempbias_result *res = NULL;
		double zh, zg, w;

		sp.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
		sp.n = CR_N;
		sp.b = cc->b ? CR_B : 0;
		sp.k = cc->k ? CR_K : 0;
		o.rate_hz = 1;
		o.seed = 5000 + (uint64_t)r;
		o.ref_temp_degc = 20;
		o.bias_poly[0] = 2;
		o.hysteresis = CR_HYST;
		o.gradient = CR_GRAD;
		o.no_clip = true;
		if (cc->sine) {
			o.temp_profile = SSCOPE_SIM_TEMP_CYCLE;
			o.temp_wave = SSCOPE_SIM_SINE;
			o.temp_degc = -10;
			o.temp2_degc = 50;
			o.temp_period_s = 7200;
		} else {
			o.temp_profile = SSCOPE_SIM_TEMP_GIVEN;
			for (size_t i = 0; i < n; i++)
				t[i] = ramps((double)i);
		}
		if (sscope_sim_new(&s, &sp, &o, &d) ||
		    sscope_sim_generate(s, NULL, x, t, n)) {
			fprintf(stderr, "simulate: %s\n", d.msg);
			return 1;
		}
		sscope_sim_free(s);
		/* reading noise of the thermometer, 0.01 degC */
		tsp.quantity = SSCOPE_QUANTITY_ACCELERATION;
		tsp.n = 0.01;
		to2.rate_hz = 1;
		to2.seed = 9000 + (uint64_t)r;
		if (sscope_sim_new(&s, &tsp, &to2, &d) ||
		    sscope_sim_generate(s, NULL, tn, NULL, n)) {
			fprintf(stderr, "simulate: %s\n", d.msg);
			return 1;
		}
		sscope_sim_free(s);
		for (size_t i = 0; i < n; i++) {
			tn[i] += t[i];
			if (cc->warm)
				x[i] += 20 * exp(-(double)i / 600);
		}
		if (sscope_tempbias_fit(&run, 1, &fo, &res, &d)) {
			fails++;
			continue;
		}
		w = res->runs[0].warmup_s / (double)n;
		wmax = fmax(wmax, w);
		wsum += w;
		with += res->runs[0].warmup_s > 0;
		if (!res->have_hysteresis || !res->have_gradient) {
			coll++;
			sscope_tempbias_result_free(res);
			continue;
		}
		zh = (res->hysteresis - CR_HYST) / res->hysteresis_sd;
		zg = (res->gradient - CR_GRAD) / res->gradient_sd;
		c1h += fabs(zh) <= 1;
		c1g += fabs(zg) <= 1;
		c2h += fabs(zh) <= 2;
		c2g += fabs(zg) <= 2;
		szh += zh;
		szg += zg;
		szh2 += zh * zh;
		szg2 += zg * zg;
		sscope_tempbias_result_free(res);
	}
	{
		int m = R - fails - coll;

		printf("%-13s %-20s %4d %3d %3d | %5.1f %5.1f %+5.2f %4.2f | %5.1f %5.1f %+5.2f %4.2f | %3d %5.2f %6.3f %5.1f\n",
		       cc->profile, cc->noise, R, fails, coll,
		       100.0 * c1h / m, 100.0 * c2h / m, szh / m, sqrt(szh2 / m),
		       100.0 * c1g / m, 100.0 * c2g / m, szg / m, sqrt(szg2 / m),
		       with, 100 * wmax, 100 * wsum / (R - fails),
		       (double)clock() / CLOCKS_PER_SEC - cpu0);
	}
	return 0;
}

static int coverage_table(void)
{
	static const struct cr_case cases[] = {
		{ "sine", "white", true, false, false, false },
		{ "sine", "white+B", true, true, false, false },
		{ "sine", "white+B+K", true, true, true, false },
		{ "unequal-ramps", "white", false, false, false, false },
		{ "unequal-ramps", "white+B", false, true, false, false },
		{ "unequal-ramps", "white+B+K", false, true, true, false },
		{ "sine", "white, warm-up 600 s", true, false, false, true },
	};
	const int R = 300;
	size_t n = CR_DUR;
	double *x = malloc(n * sizeof(double)), *t = malloc(n * sizeof(double));
	double *tn = malloc(n * sizeof(double));
	int rc = 0;

	if (!x || !t || !tn)
		return 1;
	printf("\ncoverage of the hysteresis (3 deg/h) and gradient (60 deg/h per degC/s) intervals, %d records of 8 h at 1 Hz per case\n"
	       "(defaults: order auto, warm-up detected, turning points; stated level +-1 sd = 68.3 %%, +-2 sd = 95.4 %%;\n"
	       " with R = %d a 68.3 %% coverage lies within +-%.1f points at 2 sigma; z = (estimate - truth) / sd)\n",
	       R, R, 200 * sqrt(0.683 * 0.317 / R));
	printf("%-13s %-20s %4s %3s %3s | %-24s | %-24s | %-23s\n", "profile", "noise",
	       "R", "err", "col", "hysteresis: 1sd% 2sd% z rms", "gradient: 1sd% 2sd% z rms",
	       "warm-up: n max% mean% cpu_s");
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]) && !rc; i++)
		rc = coverage_row(&cases[i], R, x, t, tn);
	free(x);
	free(t);
	free(tn);
	return rc;
}

static double truth(double T)
{
	double u = T - TREF;

	return 0.02 + u * (C1 + u * (C2 + u * C3));
}

int main(int argc, char **argv)
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
	if (argc > 1 && !strcmp(argv[1], "coverage")) {
		free(x);
		free(t);
		return coverage_table();
	}
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
	return coverage_table();
}
