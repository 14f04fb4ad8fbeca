/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Lot statistics on simulated lots with known truth (make bench; issue
 * 34): LOTS lots (default 500) of UNITS units (default 100); unit i has
 * its own standard error se_i, uniform in 0.3..2 times the between-unit
 * sd tau = 1, and estimate y_i = 5 + u_i + e_i.  Three units per lot are
 * planted SHIFT (default 6) total sd sqrt(1 + se_i^2) away from the mean.
 * Prints the coverage of the 90 % intervals of tau (target 86-94 %) and
 * of the mean, with the three outliers left in and taken out, how often
 * all three outliers are flagged at a false-alarm rate of 0.01 per unit,
 * and the false flags per lot.
 *
 * Then AT units (default 200) simulated exactly at a spec limit: white
 * gyro noise N = 0.05 deg/s/sqrt(Hz), 20 min at 100 Hz, each analysed as
 * `lot --spec` does (the allan stage's fit, dense taus, its interval at
 * the verdict's 99 %) against the limit N = 0.05 deg/s/sqrt(Hz): the share
 * called inconclusive (target >= 95 %), within spec (target 0) and out of
 * spec.
 *
 * Usage: bench-lot [LOTS [UNITS [SHIFT [SEED [AT]]]]]
 */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "sensorscope.h"

/* units simulated exactly at the limit: their verdicts */
static int at_limit(gsl_rng *g, int units)
{
	const double fs = 100, nd = 0.05 * M_PI / 180; /* rad/s/sqrt(Hz) */
	const size_t n = 120000;
	double *x = malloc(n * sizeof(double));
	struct sscope_noise_plan *plan = NULL;
	int count[3] = { 0, 0, 0 }, failed = 0;
	clock_t t0 = clock();

	if (!x || units < 1) {
		free(x);
		return 1;
	}
	if (sscope_noise_plan_new(&plan))
		plan = NULL;
	for (int u = 0; u < units; u++) {
		struct sscope_allan_opts ao = { 0 };
		struct sscope_noise_fit_opts fo = { 0 };
		struct sscope_allan_result *res = NULL;
		const struct sscope_noise_coef *c;

		for (size_t i = 0; i < n; i++)
			x[i] = gsl_ran_gaussian(g, nd * sqrt(fs));
		fo.plan = plan;
		fo.ci_level = 0.99; /* SSC_LOT_SPEC_LEVEL */
		if (sscope_allan_analyze(x, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE, &ao, &fo,
					 &res, NULL)) {
			failed++;
			continue;
		}
		c = &res->fit.coef[SSCOPE_TERM_N];
		/* as src/workbench/lot.c: a term not shown has lo 0 */
		count[sscope_datasheet_verdict(res->have_fit && c->present ? c->lo : 0,
					       res->have_fit ? c->hi : (double)NAN, nd)]++;
		sscope_allan_result_free(res);
	}
	sscope_noise_plan_free(plan);
	printf("# %d units simulated exactly at the limit N = 0.05 deg/s/sqrt(Hz) (20 min, 100 Hz), verdicts at 99 %%\n",
	       units);
	printf("inconclusive                            %6.1f %%   target >= 95\n",
	       100.0 * count[SSCOPE_DATASHEET_INCONCLUSIVE] / units);
	printf("within spec                             %6.1f %%   target 0 (0.5 expected)\n",
	       100.0 * count[SSCOPE_DATASHEET_WITHIN] / units);
	printf("out of spec                             %6.1f %%\n",
	       100.0 * count[SSCOPE_DATASHEET_OUT] / units);
	printf("# %d units failed; %.2f s of CPU\n", failed,
	       (double)(clock() - t0) / CLOCKS_PER_SEC);
	free(x);
	return failed != 0;
}

int main(int argc, char **argv)
{
	int lots = argc > 1 ? atoi(argv[1]) : 500;
	int units = argc > 2 ? atoi(argv[2]) : 100;
	double shift = argc > 3 ? atof(argv[3]) : 6;
	unsigned long seed = argc > 4 ? strtoul(argv[4], NULL, 10) : 34;
	gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
	double *y = calloc((size_t)units, sizeof(double));
	double *se = calloc((size_t)units, sizeof(double));
	bool *fl = calloc((size_t)units, sizeof(bool));
	int cov_t = 0, cov_m = 0, cov_t_clean = 0, all3 = 0, le1 = 0, failed = 0;
	long false_flags = 0;
	clock_t t0 = clock();

	if (!g || !y || !se || !fl || lots < 1 || units < 10)
		return 1;
	gsl_rng_set(g, seed);
	for (int l = 0; l < lots; l++) {
		struct sscope_lot_spread r, c;
		int found = 0, wrong = 0;

		for (int i = 0; i < units; i++) {
			se[i] = 0.3 + 1.7 * gsl_rng_uniform(g);
			y[i] = 5 + gsl_ran_gaussian(g, 1) + gsl_ran_gaussian(g, se[i]);
		}
		/* the clean lot first (the outliers replace units 0..2) */
		if (sscope_lot_spread(y + 3, se + 3, (size_t)units - 3, NULL, &c, NULL, NULL)) {
			failed++;
			continue;
		}
		cov_t_clean += c.between_lo <= 1 && 1 <= c.between_hi;
		for (int i = 0; i < 3; i++)
			y[i] = 5 + (i == 1 ? -shift : shift) * sqrt(1 + se[i] * se[i]);
		if (sscope_lot_spread(y, se, (size_t)units, NULL, &r, NULL, fl)) {
			failed++;
			continue;
		}
		cov_t += r.between_lo <= 1 && 1 <= r.between_hi;
		cov_m += r.mean_lo <= 5 && 5 <= r.mean_hi;
		for (int i = 0; i < units; i++) {
			if (i < 3)
				found += fl[i];
			else
				wrong += fl[i];
		}
		all3 += found == 3;
		le1 += wrong <= 1;
		false_flags += wrong;
	}
	printf("# lot statistics: %d lots of %d units, tau 1, se 0.3..2, three outliers at %g total sd; seed %lu\n",
	       lots, units, shift, seed);
	printf("tau 90 %% interval covers (outliers out)   %6.1f %%   target 86-94\n",
	       100.0 * cov_t_clean / lots);
	printf("tau 90 %% interval covers (outliers in)    %6.1f %%\n", 100.0 * cov_t / lots);
	printf("mean 90 %% interval covers (outliers in)   %6.1f %%\n", 100.0 * cov_m / lots);
	printf("all three outliers flagged              %6.1f %% of lots\n", 100.0 * all3 / lots);
	printf("false flags per lot (mean)              %6.2f   (0.01 x %d = %.2f expected)\n",
	       (double)false_flags / lots, units - 3, 0.01 * (units - 3));
	printf("lots with at most one false flag        %6.1f %%\n", 100.0 * le1 / lots);
	printf("# %d lots failed; %.2f s of CPU\n", failed,
	       (double)(clock() - t0) / CLOCKS_PER_SEC);
	failed += at_limit(g, argc > 5 ? atoi(argv[5]) : 200);
	gsl_rng_free(g);
	free(y);
	free(se);
	free(fl);
	return failed != 0;
}
