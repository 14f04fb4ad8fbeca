/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Coverage benchmark of the IEEE 952 noise fit (make bench): simulated
 * gyros at 10 Hz (the library's simulator: Q white angle, N white rate, B flicker
 * rate, K rate random walk, no rate ramp) over records of 1 to 24 h, at
 * least 200 realisations per length (default 1000); for each coefficient it prints how
 * often the reported interval (or, for a term not fitted, the upper bound
 * "not resolved: below X") holds the truth, how often the term is fitted,
 * and the median relative error of the fitted values.  R is zero in the
 * truth: its line counts how often a spurious ramp is reported as fitted.
 * Each coverage has a binomial standard error (se: sqrt(p (1 - p) / runs)
 * at the nominal p, 3.3 points for 200 runs), and the last lines pool
 * each term's coverage over all record lengths.
 *
 * Usage: bench-noisefit [REALISATIONS [HOURS,... [MODEL_ERROR [SEED [CASE]]]]]
 * (default 1000; 1,3,6,12,24; 0; 0; mix: realisation r of the h-th length
 * uses the simulator's seed SEED + max(1000, REALISATIONS) h + r + 1).
 * CASE picks the simulated gyro:
 *   mix    the 10 Hz gyro above (Q, N, B, K; R 0);
 *   nk     white rate and rate random walk only, 100 Hz (N 0.15 deg/sqrt(h),
 *          K 3 deg/h/sqrt(h)): K should be present in >= 90 % of records,
 *          its interval covering at the level;
 *   white  white rate noise only, 100 Hz (N 0.15 deg/sqrt(h)): B, K and R
 *          should be reported present in <= 2 % of records each;
 *   bmix   a five-term mix whose bottom B dominates, 100 Hz (Q 5 arcsec,
 *          N 0.15 deg/sqrt(h), B 3 deg/h, K 3 deg/h/sqrt(h), R 2 deg/h/h):
 *          the classic B read-off, where printed, within +-30 % of the
 *          truth (bread% below).
 * For every case the lines "present%" count how often each term is
 * reported present (for a term whose truth is 0: a false detection).
 * Realisations run in parallel over the cores (OpenMP); run it niced on
 * a shared machine.
 */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sensorscope.h"
#include "sscope-allan.h"
#include "sscope-sim.h"

#define D2R (3.14159265358979323846 / 180)

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return x < y ? -1 : x > y;
}

static double now_s(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

struct tally {
	int runs, fitted[5], cover[5], cover_fitted[5], bound_ok[5], bound_n[5];
	int above[5], below[5];
	double *relerr[5], *allerr[5];
	int n_relerr[5], n_allerr[5];
};

static double g_model_error;
static uint64_t g_seed;

/* B read-offs printed, and those within +-30 % of the truth */
static int g_bread_n, g_bread_ok;

static int one_run(const struct sscope_sensor_spec *spec, double fs,
		   size_t n, uint64_t seed, double *y, struct sscope_noise_fit *fit)
{
	struct sscope_sim_opts so = { 0 };
	struct sscope_sim *sim = NULL;
	struct sscope_allan_result *res = NULL;
	int rc;

	so.rate_hz = fs;
	so.seed = seed;
	so.no_clip = true;
	rc = sscope_sim_new(&sim, spec, &so, NULL);
	if (rc)
		return rc;
	rc = sscope_sim_generate(sim, NULL, y, NULL, n);
	sscope_sim_free(sim);
	if (rc)
		return rc;
	{
		struct sscope_allan_opts ao = { 0 };
		struct sscope_noise_fit_opts fo = { 0 };

		ao.threads = 1;
		fo.model_error = g_model_error;
		rc = sscope_allan_analyze(y, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE, &ao,
					  &fo, &res, NULL);
	}
	if (rc)
		return rc;
	if (!res->have_fit) {
		rc = res->fit_error;
	} else {
		*fit = res->fit;
	}
	sscope_allan_result_free(res);
	return rc;
}

int main(int argc, char **argv)
{
	double fs = 10;
	const char *kase = argc > 5 ? argv[5] : "mix";
	int reps = argc > 1 ? atoi(argv[1]) : 1000;
	/* the records of one length never reuse another length's */
	const uint64_t stride = reps > 1000 ? (uint64_t)reps : 1000;
	double hours[16] = { 1, 3, 6, 12, 24 };
	int n_hours = 5;
	struct sscope_sensor_spec spec;
	double truth[5];
	const char *names = "QNBKR";
	const char *units[5] = { "arcsec", "deg/sqrt(h)", "deg/h", "deg/h/sqrt(h)",
				 "deg/h/h" };
	const double to_disp[5] = { 3600 / D2R, 60 / D2R, 3600 / D2R,
				    3600 * 60 / D2R, 3600 * 3600 / D2R };
	double t_all = now_s();
	const double nominal = 0.682689492137086;
	int pool_cover[5] = { 0 }, pool_runs = 0;

	if (argc > 2) {
		char *s = argv[2], *e;

		n_hours = 0;
		while (*s && n_hours < 16) {
			hours[n_hours++] = strtod(s, &e);
			if (e == s)
				break;
			s = *e == ',' ? e + 1 : e;
		}
	}
	if (argc > 3)
		g_model_error = atof(argv[3]);
	if (argc > 4)
		g_seed = strtoull(argv[4], NULL, 10);
	if (reps < 1)
		reps = 1;
	memset(&spec, 0, sizeof(spec));
	spec.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	spec.range = 1e3;
	/* a MEMS-class gyro at 10 Hz: 5 arcsec angle white noise (dominant
	 * below 0.9 s), 0.15 deg/sqrt(h), a 1 deg/h flicker floor, 3
	 * deg/h/sqrt(h) */
	spec.q = 5.0 / 3600 * D2R;
	spec.n = 0.15 / 60 * D2R;
	spec.b = 1.0 / 3600 * D2R;
	spec.k = 3.0 / 3600 / 60 * D2R;
	spec.r = 0;
	if (!strcmp(kase, "nk")) {
		fs = 100;
		spec.q = spec.b = 0;
	} else if (!strcmp(kase, "white")) {
		fs = 100;
		spec.q = spec.b = spec.k = 0;
	} else if (!strcmp(kase, "bmix")) {
		fs = 100;
		spec.b = 3.0 / 3600 * D2R;
		spec.r = 2.0 / 3600 / 3600 * D2R;
	} else if (strcmp(kase, "mix")) {
		fprintf(stderr, "bench-noisefit: unknown case '%s' (mix, nk, white, bmix)\n",
			kase);
		return 2;
	}
	truth[0] = spec.q;
	truth[1] = spec.n;
	truth[2] = spec.b;
	truth[3] = spec.k;
	truth[4] = spec.r;
	printf("# noise-fit coverage (case %s): %d realisations per record length, %g Hz, "
	       "nominal level 68.3 %%\n", kase, reps, fs);
	printf("# truth: Q %.3g %s, N %.3g %s, B %.3g %s, K %.3g %s, R %.3g %s\n",
	       truth[0] * to_disp[0], units[0], truth[1] * to_disp[1], units[1],
	       truth[2] * to_disp[2], units[2], truth[3] * to_disp[3], units[3],
	       truth[4] * to_disp[4], units[4]);
	printf("# cover: truth inside [lo, hi] (a term not present: [0, upper bound]);\n"
	       "# present: share of runs that report the term present; bias: median\n"
	       "# (value/truth - 1) of the present values; bound: upper bound >= truth\n"
	       "# when not present;\n"
	       "# low, high: truth below lo, above hi (the misses by side); est: median\n"
	       "# (estimate/truth - 1) over all runs, the estimate of a term not fitted\n"
	       "# included (a negative square as 0)\n");
	printf("# se: standard error of cover%% at the nominal level\n");
	printf("%6s %4s %8s %5s %8s %9s %10s %7s %7s %7s %7s\n", "hours", "term",
	       "cover%", "se%", "present%", "bias%", "bound_ok%", "low%", "high%",
	       "est%", "time_s");
	for (int h = 0; h < n_hours; h++) {
		size_t n = (size_t)(hours[h] * 3600 * fs);
		struct tally t;
		double t0 = now_s();
		int failed = 0;

		memset(&t, 0, sizeof(t));
		for (int j = 0; j < 5; j++)
			t.relerr[j] = calloc((size_t)reps, sizeof(double));
		for (int j = 0; j < 5; j++)
			t.allerr[j] = calloc((size_t)reps, sizeof(double));
#ifdef _OPENMP
#pragma omp parallel
#endif
		{
			double *y = malloc(n * sizeof(double));

#ifdef _OPENMP
#pragma omp for schedule(dynamic, 1) reduction(+ : failed)
#endif
			for (int r = 0; r < reps; r++) {
				struct sscope_noise_fit fit;

				if (!y || one_run(&spec, fs, n,
						  g_seed + (uint64_t)h * stride +
							  (uint64_t)r + 1,
						  y,
						  &fit)) {
					failed++;
					continue;
				}
#ifdef _OPENMP
#pragma omp critical
#endif
				{
					t.runs++;
					if (getenv("BENCH_NOISEFIT_DEBUG"))
						for (int j = 0; j < 5; j++)
							fprintf(stderr, "%c z %.3g est %.4g lo %.4g hi %.4g %s%s",
								"QNBKR"[j], fit.coef[j].z,
								fit.coef[j].estimate * to_disp[j],
								fit.coef[j].lo * to_disp[j],
								fit.coef[j].hi * to_disp[j],
								fit.coef[j].present ? "P" : "-",
								j == 4 ? "\n" : " | ");
					for (int j = 0; j < 5; j++) {
						const struct sscope_noise_coef *c = &fit.coef[j];
						bool in = truth[j] >= c->lo && truth[j] <= c->hi;

						t.cover[j] += in;
						if (j == 2 && isfinite(fit.readoff.b) &&
						    truth[2] > 0) {
							g_bread_n++;
							g_bread_ok += fabs(fit.readoff.b / truth[2] - 1) <= 0.3;
						}
						t.above[j] += truth[j] > c->hi;
						t.below[j] += truth[j] < c->lo;
						if (truth[j] > 0)
							t.allerr[j][t.n_allerr[j]++] =
								c->estimate / truth[j] - 1;
						if (c->fitted) {
							t.fitted[j]++;
							if (truth[j] > 0)
								t.relerr[j][t.n_relerr[j]++] =
									c->value / truth[j] - 1;
						} else {
							t.bound_n[j]++;
							t.bound_ok[j] += truth[j] <= c->hi;
						}
					}
				}
			}
			free(y);
		}
		for (int j = 0; j < 5; j++) {
			double bias = NAN, est = NAN, runs = t.runs ? t.runs : 1;

			if (t.n_relerr[j]) {
				qsort(t.relerr[j], (size_t)t.n_relerr[j],
				      sizeof(double), cmp_d);
				bias = t.relerr[j][t.n_relerr[j] / 2];
			}
			if (t.n_allerr[j]) {
				qsort(t.allerr[j], (size_t)t.n_allerr[j],
				      sizeof(double), cmp_d);
				est = t.allerr[j][t.n_allerr[j] / 2];
			}
			pool_cover[j] += t.cover[j];
			printf("%6g %4c %8.1f %5.1f %8.1f %9.1f %10.1f %7.1f %7.1f %7.1f %7.1f\n",
			       hours[h], names[j], 100.0 * t.cover[j] / runs,
			       100 * sqrt(nominal * (1 - nominal) / runs),
			       100.0 * t.fitted[j] / runs, 100 * bias,
			       t.bound_n[j] ? 100.0 * t.bound_ok[j] / t.bound_n[j] :
					      (double)NAN,
			       100.0 * t.below[j] / runs, 100.0 * t.above[j] / runs,
			       100 * est, now_s() - t0);
			free(t.relerr[j]);
			free(t.allerr[j]);
		}
		pool_runs += t.runs;
		if (failed)
			printf("# %g h: %d runs failed\n", hours[h], failed);
		fflush(stdout);
	}
	for (int j = 0; j < 5 && pool_runs > 0; j++)
		printf("# pooled %c: cover %.1f %% of %d runs (se %.1f)\n", names[j],
		       100.0 * pool_cover[j] / pool_runs, pool_runs,
		       100 * sqrt(nominal * (1 - nominal) / pool_runs));
	if (truth[2] > 0)
		printf("# B read-off printed in %d runs, within +-30 %% of the truth in %d (bread %.1f %%)\n",
		       g_bread_n, g_bread_ok,
		       g_bread_n ? 100.0 * g_bread_ok / g_bread_n : (double)NAN);
	printf("# total %.1f s\n", now_s() - t_all);
	return 0;
}
