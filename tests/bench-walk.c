/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The random-walk fan (sscope_walk_compute(), `sensorscope walk`) on
 * simulated gyros with bias instability and rate random walk (make
 * bench): for each record, the envelope's terms come from the noise fit
 * on the record itself as `walk` takes them (N, B, K as estimated, Q and
 * R when present), the runs are 60 s after a 60 s bias window (walk's
 * defaults), and the table counts
 *   cover%   how often the implied N's interval at the end of the runs
 *            holds the truth (nominal 68.3 %),
 *   inside%  the fraction of runs inside +-2 sigma, averaged over the
 *            run and the records (nominal 95.45 %),
 *   ratio    the median of implied N / truth,
 * with the fitted terms as estimate^2 ("fitted": what walk did before
 * it took the signed squares), as walk takes them now (the signed
 * squares and their covariance: "fitted-walk"), and with the true terms
 * (the formula alone).  The standard error of cover% is sqrt(0.683 0.317 / records).
 *
 * Usage: bench-walk [RECORDS [HOURS [SEED [CASE]]]] (default 100 records
 * of 2 h at 10 Hz; record r uses the simulator's seed SEED + r + 1; CASE
 * nbk (default: N, B and K), nb or nk: the terms simulated).
 */
#include "config.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sensorscope.h"
#include "sscope-allan.h"
#include "sscope-sim.h"
#include "sscope-walk.h"

#define D2R (3.14159265358979323846 / 180)

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return x < y ? -1 : x > y;
}

struct tally {
	int runs, cover, low, high;
	double inside, *ratio;
};

/* the terms `walk` takes from allan on the record */
static int fitted_terms(const double *y, size_t n, double fs, double coef[5],
			double sq[5], double cov[25])
{
	struct sscope_allan_opts ao = { 0 };
	struct sscope_noise_fit_opts fo = { 0 };
	struct sscope_allan_result *res = NULL;
	int rc;

	ao.threads = 1;
	rc = sscope_allan_analyze(y, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE, &ao, &fo,
				  &res, NULL);
	if (rc)
		return rc;
	if (!res->have_fit) {
		sscope_allan_result_free(res);
		return -EDOM;
	}
	for (int i = 0; i < 5; i++) {
		const struct sscope_noise_coef *c = &res->fit.coef[i];

		coef[i] = 0;
		if (i == 1 || i == 2 || i == 3)
			coef[i] = c->estimate > 0 ? c->estimate : 0;
		else if (c->present && c->value > 0)
			coef[i] = c->value;
		/* the signed squares: N, B, K always, Q and R when present */
		sq[i] = i == 1 || i == 2 || i == 3 || c->present ? c->square : 0;
		for (int j = 0; j < 5; j++)
			cov[i * 5 + j] = res->fit.sq_cov[i][j];
	}
	sscope_allan_result_free(res);
	return 0;
}

static void one(struct tally *t, const double *y, size_t n, double fs,
		const double coef[5], const double *sq, const double *cov,
		double truth_n)
{
	struct sscope_walk_opts wo = { 0 };
	struct sscope_walk_result *w = NULL;
	struct sscope_walk_implied im;

	wo.rate_hz = fs;
	wo.run_s = 60;
	wo.bias_s = 60;
	wo.keep_paths = 1;
	memcpy(wo.coef, coef, sizeof(wo.coef));
	if (sq) {
		wo.have_sq = true;
		memcpy(wo.sq, sq, sizeof(wo.sq));
		memcpy(wo.sq_cov, cov, sizeof(wo.sq_cov));
	}
	if (sscope_walk_compute(y, 1, n, &wo, &w, NULL))
		return;
	if (sscope_walk_implied_n(w, w->n_points - 1, 0.682689492137086, &im) == 0) {
		t->cover += truth_n >= im.lo && truth_n <= im.hi;
		t->low += truth_n < im.lo;
		t->high += truth_n > im.hi;
		t->ratio[t->runs] = isfinite(im.n) ? im.n / truth_n : 0;
		t->inside += w->inside_mean;
		t->runs++;
	}
	sscope_walk_result_free(w);
}

int main(int argc, char **argv)
{
	int records = argc > 1 ? atoi(argv[1]) : 100;
	double hours = argc > 2 ? atof(argv[2]) : 2;
	unsigned long long seed = argc > 3 ? strtoull(argv[3], NULL, 10) : 0;
	const char *kase = argc > 4 ? argv[4] : "nbk";
	const double fs = 10;
	size_t n = (size_t)(hours * 3600 * fs);
	struct sscope_sensor_spec spec;
	struct tally tf = { 0 }, ts = { 0 }, tt = { 0 };
	double *y = malloc(n * sizeof(double)), truth[5];
	clock_t c0 = clock();

	if (!y || records < 1 || !(hours > 0))
		return 2;
	tf.ratio = calloc((size_t)records, sizeof(double));
	tt.ratio = calloc((size_t)records, sizeof(double));
	ts.ratio = calloc((size_t)records, sizeof(double));
	if (!tf.ratio || !tt.ratio || !ts.ratio)
		return 2;
	memset(&spec, 0, sizeof(spec));
	spec.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	spec.range = 1e3;
	/* the static sample's gyro: N 0.15 deg/sqrt(h), B 2 deg/h, K 10
	 * deg/h/sqrt(h) */
	spec.n = 0.15 / 60 * D2R;
	spec.b = 2.0 / 3600 * D2R;
	spec.k = 10.0 / 3600 / 60 * D2R;
	if (!strcmp(kase, "nb"))
		spec.k = 0;
	else if (!strcmp(kase, "nk"))
		spec.b = 0;
	truth[0] = spec.q;
	truth[1] = spec.n;
	truth[2] = spec.b;
	truth[3] = spec.k;
	truth[4] = spec.r;
	for (int r = 0; r < records; r++) {
		struct sscope_sim_opts so = { 0 };
		struct sscope_sim *sim = NULL;
		double coef[5], sq[5], cov[25];

		so.rate_hz = fs;
		so.seed = seed + (unsigned long long)r + 1;
		so.no_clip = true;
		if (sscope_sim_new(&sim, &spec, &so, NULL) ||
		    sscope_sim_generate(sim, NULL, y, NULL, n)) {
			sscope_sim_free(sim);
			continue;
		}
		sscope_sim_free(sim);
		if (fitted_terms(y, n, fs, coef, sq, cov) == 0) {
			one(&tf, y, n, fs, coef, NULL, NULL, truth[1]);
			one(&ts, y, n, fs, coef, sq, cov, truth[1]);
		}
		one(&tt, y, n, fs, truth, NULL, NULL, truth[1]);
	}
	printf("# walk fan: %d records of %g h at %g Hz, N 0.15 deg/sqrt(h), B %g deg/h, K %g deg/h/sqrt(h); runs of 60 s after 60 s bias windows\n",
	       records, hours, fs, spec.b * 3600 / D2R, spec.k * 3600 * 60 / D2R);
	printf("# cover: implied N's 68.3 %% interval at t = 60 s holds the truth (se %.1f); inside: +-2 sigma (nominal 95.45)\n",
	       100 * sqrt(0.683 * 0.317 / records));
	printf("%-14s %7s %7s %7s %8s %8s\n", "terms", "cover%", "low%", "high%",
	       "inside%", "ratio");
	for (int k = 0; k < 3; k++) {
		static const char *const name[3] = { "fitted", "fitted-walk", "true" };
		struct tally *t = k == 0 ? &tf : k == 1 ? &ts : &tt;

		if (!t->runs)
			continue;
		qsort(t->ratio, (size_t)t->runs, sizeof(double), cmp_d);
		printf("%-14s %7.1f %7.1f %7.1f %8.2f %8.3f\n",
		       name[k], 100.0 * t->cover / t->runs,
		       100.0 * t->low / t->runs, 100.0 * t->high / t->runs,
		       100 * t->inside / t->runs, t->ratio[t->runs / 2]);
	}
	printf("# %.1f s of CPU\n", (double)(clock() - c0) / CLOCKS_PER_SEC);
	free(y);
	free(tf.ratio);
	free(tt.ratio);
	free(ts.ratio);
	return 0;
}
