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
 * Then BLOTS lots (default 200) of 12 simulated accelerometers: the
 * coverage of each unit's bias, drift and temperature sensitivity
 * intervals and the planted bias outlier (see bias_lots()).
 *
 * The accelerometers' records are HOURS long (default 1).
 *
 * Usage: bench-lot [LOTS [UNITS [SHIFT [SEED [AT [BLOTS [HOURS]]]]]]]
 */
#include "config.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>

#include "sensorscope.h"

/* the conservative se more than this times the reported one: the lot
 * stage's flag (SSC_LOT_SE_UPPER_RATIO) */
#define SE_UPPER_RATIO 1.5

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

/*
 * Lots of 12 accelerometers at rest as in samples/lot/ (1 h at 1 Hz,
 * white noise 60 ug/sqrt(Hz), the ambient temperature one sine period
 * 21..27 degC): unit i's bias 1 mg + N(0, 0.1 mg), drift (rate ramp)
 * uniform 0..60 ug/h, temperature sensitivity 50 + N(0, 8) ug/degC; unit
 * 0 planted 2 mg above.  Each unit analysed by sscope_lot_bias() as the
 * lot stage does: the coverage of the 68.27 % intervals of the three
 * terms (target 68.3 -+ 4 binomial sd), the planted unit flagged, the
 * false flags; white noise only, with bias instability B = 5 ug
 * (flicker) and with a rate random walk K = 0.5 ug/s/sqrt(Hz): the block
 * means are correlated.  Each unit's noise terms are fitted to its record
 * less the temperature effect (the allan stage's fit, dense taus) and
 * given to sscope_lot_bias() as the lot stage does; the drift's and sensitivity's coverage is printed with the
 * intervals used (the noise model's where it shows B or K) and with the
 * residuals' alone (Student t, as before the noise model).  Then the
 * conservative intervals (each unit's fit's upper bounds of B and K as
 * b_upper and k_upper, as the lot stage): their coverage, the ratio of
 * the conservative to the reported se, the share above
 * SE_UPPER_RATIO (flagged) and the reported intervals' coverage over the
 * units not flagged.
 */
static int bias_lots(gsl_rng *g, int lots, double b_ug, double k_ug, double hours)
{
	const double ug = 9.80665e-6, fs = 1, dur = 3600 * hours;
	const size_t n = (size_t)dur, U = 12;
	double *x = malloc(n * sizeof(double)), *T = malloc(n * sizeof(double));
	double *x0 = malloc(n * sizeof(double));
	double y[3][12], se[3][12];
	bool fl[12];
	long cov[3] = { 0, 0, 0 }, cov_rec = 0, units = 0, found = 0, wrong = 0;
	long flagged = 0, cov_ok[2] = { 0, 0 }, cov_res[2] = { 0, 0 }, model[2] = { 0, 0 };
	long shows = 0, cov_mod[2] = { 0, 0 }, cov_true[2] = { 0, 0 };
	long cov_up[2] = { 0, 0 }, upflag[2] = { 0, 0 }, cov_unfl[2] = { 0, 0 };
	double *ratio[2] = { malloc((size_t)lots * U * sizeof(double)),
			     malloc((size_t)lots * U * sizeof(double)) };
	struct sscope_noise_plan *plan = NULL;
	int failed = 0;
	clock_t t0 = clock();

	if (!x || !T || !x0 || !ratio[0] || !ratio[1]) {
		free(ratio[0]);
		free(ratio[1]);
		free(x);
		free(x0);
		free(T);
		return 1;
	}
	if (sscope_noise_plan_new(&plan))
		plan = NULL;
	for (int l = 0; l < lots; l++) {
		for (size_t u = 0; u < U; u++) {
			struct sscope_lot_bias_opts bo = { 0 }, bt = { 0 };
			struct sscope_lot_bias b0;
			struct sscope_allan_opts ao = { 0 };
			struct sscope_noise_fit_opts fo = { .plan = plan };
			struct sscope_allan_result *res = NULL;
			double tq;
			struct sscope_sensor_spec sp = { 0 };
			struct sscope_sim_opts so = { 0 };
			struct sscope_sim *sim = NULL;
			struct sscope_lot_bias b;
			double truth[3], tm = 0, Tm = 0, fm = 0;

			sp.n = 60 * ug;
			sp.b = b_ug * ug;
			sp.k = k_ug * ug;
			sp.bias = (1000 + gsl_ran_gaussian(g, 100) + (u == 0 ? 2000 : 0)) * ug;
			sp.r = 60 * gsl_rng_uniform(g) * ug / 3600;
			sp.bias_tempco = (50 + gsl_ran_gaussian(g, 8)) * ug;
			so.rate_hz = fs;
			so.seed = gsl_rng_get(g);
			so.temp_profile = SSCOPE_SIM_TEMP_CYCLE;
			so.temp_degc = 21;
			so.temp2_degc = 27;
			so.temp_period_s = dur;
			so.ref_temp_degc = 24;
			so.no_clip = true;
			if (sscope_sim_new(&sim, &sp, &so, NULL) ||
			    sscope_sim_generate(sim, NULL, x, T, n) ||
			    sscope_lot_bias(x, 1, n, fs, T, 1, NULL, &b) || !b.have_temp ||
			    sscope_lot_temp_removed(x, 1, n, T, 1, &b, x0) ||
			    sscope_allan_analyze(x0, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE, &ao, &fo,
						 &res, NULL)) {
				sscope_sim_free(sim);
				failed++;
				continue;
			}
			/* the terms the fit of the record less its fitted
			 * temperature effect shows, as src/workbench/lot.c */
			for (int t = 0; t < 3 && res->have_fit; t++) {
				const struct sscope_noise_coef *c = &res->fit.coef[SSCOPE_TERM_N + t];
				double v = c->present && isfinite(c->value) && isfinite(c->lo) &&
					   isfinite(c->hi) && c->hi > c->lo ? c->value : 0;

				*(t == 0 ? &bo.n : t == 1 ? &bo.b : &bo.k) = v;
				/* the upper end of the term's interval, the
				 * fit's upper bound where not shown (none
				 * finite: INFINITY), as src/workbench/lot.c */
				if (t)
					*(t == 1 ? &bo.b_upper : &bo.k_upper) =
						c->hi > 0 ? c->hi : (double)INFINITY;
			}
			if (!res->have_fit)
				bo.b_upper = bo.k_upper = INFINITY;
			sscope_allan_result_free(res);
			shows += bo.b > 0 || bo.k > 0;
			if (sscope_lot_bias(x, 1, n, fs, T, 1, &bo, &b) || !b.have_temp) {
				sscope_sim_free(sim);
				failed++;
				continue;
			}
			sscope_sim_free(sim);
			sim = NULL;
			/* the flicker and random walk alone: the same streams
			 * without them (each term has its own generator) */
			sp.b = 0;
			sp.k = 0;
			if (sscope_sim_new(&sim, &sp, &so, NULL) ||
			    sscope_sim_generate(sim, NULL, x0, NULL, n)) {
				sscope_sim_free(sim);
				failed++;
				continue;
			}
			sscope_sim_free(sim);
			/* the truth over the samples the blocks use */
			for (size_t i = 0; i < b.blocks * b.block_n; i++) {
				tm += (double)i / fs;
				Tm += T[i];
				fm += x[i] - x0[i];
			}
			fm /= (double)(b.blocks * b.block_n);
			tm /= (double)(b.blocks * b.block_n);
			Tm /= (double)(b.blocks * b.block_n);
			truth[0] = sp.bias + sp.r * tm + sp.bias_tempco * (Tm - 24);
			truth[1] = sp.r;
			truth[2] = sp.bias_tempco;
			/* the noise model's intervals with the true terms */
			bt.n = sp.n;
			bt.b = b_ug * ug;
			bt.k = k_ug * ug;
			if (!sscope_lot_bias(x, 1, n, fs, T, 1, &bt, &b0)) {
				cov_true[0] += b0.drift_lo <= truth[1] && truth[1] <= b0.drift_hi;
				cov_true[1] += b0.tempco_lo <= truth[2] && truth[2] <= b0.tempco_hi;
			}
			cov[0] += b.bias_lo <= truth[0] && truth[0] <= b.bias_hi;
			cov_rec += b.bias_lo <= truth[0] + fm && truth[0] + fm <= b.bias_hi;
			cov[1] += b.drift_lo <= truth[1] && truth[1] <= b.drift_hi;
			cov[2] += b.tempco_lo <= truth[2] && truth[2] <= b.tempco_hi;
			/* the residuals' intervals alone (t, m - 3 dof) */
			tq = gsl_cdf_tdist_Pinv(0.5 + b.level / 2, (double)(b.blocks - 3));
			cov_res[0] += fabs(b.drift_u_s - truth[1]) <= tq * b.drift_se_resid;
			cov_res[1] += fabs(b.tempco_u_degc - truth[2]) <= tq * b.tempco_se_resid;
			model[0] += b.drift_se_from_model;
			model[1] += b.tempco_se_from_model;
			cov_mod[0] += b.drift_se_from_model && b.drift_lo <= truth[1] &&
				      truth[1] <= b.drift_hi;
			cov_mod[1] += b.tempco_se_from_model && b.tempco_lo <= truth[2] &&
				      truth[2] <= b.tempco_hi;
			/* the conservative intervals (B, then K, at the
			 * upper end of its interval or its bound), the flag (se_upper more
			 * than SE_UPPER_RATIO times the reported se) and
			 * the coverage of the units not flagged */
			for (int e = 0; e < 2; e++) {
				double tr = truth[e + 1];
				double lo = e ? b.tempco_lo : b.drift_lo, hi = e ? b.tempco_hi : b.drift_hi;
				double ulo = e ? b.tempco_upper_lo : b.drift_upper_lo;
				double uhi = e ? b.tempco_upper_hi : b.drift_upper_hi;
				double se0 = e ? b.tempco_se : b.drift_se;
				double su = e ? b.tempco_se_upper : b.drift_se_upper;
				bool fl_e = !(su <= SE_UPPER_RATIO * se0);

				cov_up[e] += ulo <= tr && tr <= uhi;
				upflag[e] += fl_e;
				cov_unfl[e] += !fl_e && lo <= tr && tr <= hi;
				ratio[e][units] = su / se0;
			}
			flagged += b.resid_correlated;
			if (!b.resid_correlated) {
				cov_ok[0] += b.drift_lo <= truth[1] && truth[1] <= b.drift_hi;
				cov_ok[1] += b.tempco_lo <= truth[2] && truth[2] <= b.tempco_hi;
			}
			units++;
			y[0][u] = b.bias;
			se[0][u] = b.bias_se;
		}
		if (!sscope_lot_spread(y[0], se[0], U, NULL, &(struct sscope_lot_spread){ 0 },
				       NULL, fl)) {
			found += fl[0];
			for (size_t u = 1; u < U; u++)
				wrong += fl[u];
		} else {
			failed++;
		}
	}
	printf("# %d lots of 12 accelerometers (%g h, 1 Hz, N 60 ug/sqrt(Hz), B %g ug, K %g ug/s/sqrt(Hz), temperature 21..27 degC), unit 0 planted 2 mg (20 between-unit sd) above\n",
	       lots, hours, b_ug, k_ug);
	printf("fit shows B or K                        %6.1f %% of units\n", 100.0 * shows / units);
	printf("bias 68.3 %% interval covers              %6.1f %%   target 68.3 -+ %.1f\n",
	       100.0 * cov[0] / units, 400 * sqrt(0.6827 * 0.3173 / units));
	printf("  the record's bias (flicker's mean in)   %6.1f %%\n",
	       100.0 * cov_rec / units);
	printf("drift 68.3 %% interval covers             %6.1f %%   target 68.3 -+ 5 (noise model's se on %.1f %%)\n",
	       100.0 * cov[1] / units, 100.0 * model[0] / units);
	printf("  from the residuals alone (t)          %6.1f %%\n", 100.0 * cov_res[0] / units);
	printf("  with the true N, B, K                 %6.1f %%\n", 100.0 * cov_true[0] / units);
	printf("  where the noise model's se            %6.1f %%\n",
	       model[0] ? 100.0 * cov_mod[0] / model[0] : (double)NAN);
	printf("temp. sensitivity 68.3 %% interval covers %6.1f %%   target 68.3 -+ 5 (noise model's se on %.1f %%)\n",
	       100.0 * cov[2] / units, 100.0 * model[1] / units);
	printf("  where the noise model's se            %6.1f %%\n",
	       model[1] ? 100.0 * cov_mod[1] / model[1] : (double)NAN);
	printf("  from the residuals alone (t)          %6.1f %%\n", 100.0 * cov_res[1] / units);
	printf("  with the true N, B, K                 %6.1f %%\n", 100.0 * cov_true[1] / units);
	printf("residuals called correlated (doubt)     %6.1f %% of units\n", 100.0 * flagged / units);
	printf("  drift / sensitivity covers, the others %6.1f %% / %.1f %%\n",
	       units > flagged ? 100.0 * cov_ok[0] / (units - flagged) : (double)NAN,
	       units > flagged ? 100.0 * cov_ok[1] / (units - flagged) : (double)NAN);
	for (int e = 0; e < 2; e++) {
		gsl_sort(ratio[e], 1, (size_t)units);
		printf("%s conservative interval (B, then K, at its upper bound) covers %6.1f %%\n",
		       e ? "sensitivity" : "drift", 100.0 * cov_up[e] / units);
		printf("  se_upper / se: median %.2f, 90th percentile %.2f; above %.1f (flagged) %6.1f %% of units\n",
		       gsl_stats_median_from_sorted_data(ratio[e], 1, (size_t)units),
		       gsl_stats_quantile_from_sorted_data(ratio[e], 1, (size_t)units, 0.9),
		       SE_UPPER_RATIO, 100.0 * upflag[e] / units);
		printf("  the reported interval covers, units not flagged %6.1f %% (%ld units)\n",
		       units > upflag[e] ? 100.0 * cov_unfl[e] / (units - upflag[e]) : (double)NAN,
		       units - upflag[e]);
	}
	printf("planted bias outlier flagged            %6.1f %% of lots\n", 100.0 * found / lots);
	printf("false bias flags per lot (mean)         %6.2f   (0.01 x 11 = 0.11 expected)\n",
	       (double)wrong / lots);
	printf("# %d failed; %.2f s of CPU\n", failed, (double)(clock() - t0) / CLOCKS_PER_SEC);
	sscope_noise_plan_free(plan);
	free(ratio[0]);
	free(ratio[1]);
	free(x);
	free(x0);
	free(T);
	return failed != 0;
}

int main(int argc, char **argv)
{
	int lots = argc > 1 ? atoi(argv[1]) : 500;
	int units = argc > 2 ? atoi(argv[2]) : 100;
	double shift = argc > 3 ? atof(argv[3]) : 6;
	unsigned long seed = argc > 4 ? strtoul(argv[4], NULL, 10) : 34;
	double hours = argc > 7 ? atof(argv[7]) : 1;
	gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
	double *y = calloc((size_t)units, sizeof(double));
	double *se = calloc((size_t)units, sizeof(double));
	bool *fl = calloc((size_t)units, sizeof(bool));
	int cov_t = 0, cov_m = 0, cov_t_clean = 0, all3 = 0, le1 = 0, failed = 0;
	long false_flags = 0;
	clock_t t0 = clock();

	if (!g || !y || !se || !fl || lots < 1 || units < 10 || !(hours >= 0.1))
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
	failed += bias_lots(g, argc > 6 ? atoi(argv[6]) : 200, 0, 0, hours);
	failed += bias_lots(g, argc > 6 ? atoi(argv[6]) : 200, 5, 0, hours);
	failed += bias_lots(g, argc > 6 ? atoi(argv[6]) : 200, 0, 0.5, hours);
	gsl_rng_free(g);
	free(y);
	free(se);
	free(fl);
	return failed != 0;
}
