/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The recording planner (analysis/plan.c) against simulation (make bench):
 * for each sensor, term and length, the predicted probability that the fit
 * shows the term present with a relative half-width at most the target,
 * and the fraction of RECORDS simulated records (default 200) fitted as
 * `allan` does that do (tests/plan-sim.h); target |difference| <= 10
 * points.  Records at RATE Hz (default 10 Hz, to keep the run affordable:
 * B and K are read at long tau, where the rate hardly matters).  Then
 * PILOTS 10-minute pilots (default 10) of the first sensor, each fitted
 * and planned from its own terms (a term the pilot does not show present
 * with its estimate, as `plan --pilot`): the needed length of B against the one
 * planned from the spec (target within +-25 %), and the spread of their
 * ratio (median, 10th-90th percentile; each pilot printed up to 20).
 *
 * Sensors: samples/gyro-mems-250.ini (N 0.2 deg/sqrt(h), B 4 deg/h,
 * K 20 deg/h/sqrt(h)) and the STIM300 gyro of samples/datasheets/
 * (N 0.15 deg/sqrt(h), B from the in-run bias stability 0.5 deg/h as the
 * Allan minimum: 0.5 / 0.6643 deg/h; no K given).
 *
 * Usage: bench-plan [RECORDS [RATE [PILOTS [SEED [PILOT_S [ROWS]]]]]] (RECORDS
 * 0: the pilots only; PILOT_S the pilots' length, default 600 s; ROWS the
 * tables run, letters of "msk": m the MEMS gyro's B, s the STIM300's B, k
 * the MEMS gyro's K; default all; r adds to the pilots the range of
 * the needed length as the term moves within the pilot's interval, as
 * `plan` from a pilot shows, and how often it holds the spec's length)
 */
#include "config.h"

#include <math.h>
#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "plan-sim.h"

#define DEG (M_PI / 180)

struct bsensor {
	const char *name;
	double coef[5];
	int term;
	double target;
	double hours[5];
};

static double cpu_s(clock_t t0)
{
	return (double)(clock() - t0) / CLOCKS_PER_SEC;
}

static int run_sensor(const struct bsensor *s, double rate, int records,
		      uint64_t seed, int *worst)
{
	const char *tn = "QNBKR";
	double need;
	clock_t t0 = clock();
	int rc = sscope_plan_needed(s->coef, rate, (enum sscope_term)s->term,
				    s->target, NULL, &need);

	if (rc)
		return rc;
	printf("# %s, %c to %.0f %% at 90 %%: needed %.2f h at %.0f Hz (%.3f s of CPU)\n",
	       s->name, tn[s->term], 100 * s->target, need / 3600, rate,
	       cpu_s(t0));
	printf("%-8s %10s %10s %10s %8s\n", "length", "predicted", "simulated",
	       "diff", "within");
	for (int i = 0; i < 5; i++) {
		struct sscope_plan_point pt;
		double L = s->hours[i] * 3600, f;

		rc = sscope_plan_predict(s->coef, rate, L, (enum sscope_term)s->term,
					 s->target, NULL, &pt);
		if (rc)
			return rc;
		t0 = clock();
		f = plan_sim_fraction(s->coef, rate, L, s->term, s->target,
				      records, seed + 100000u * (uint64_t)i);
		if (!isfinite(f))
			return -EIO;
		printf("%5.1f h  %9.1f%% %9.1f%% %+9.1f %8s   (present %.1f%%, width %.1f%%; %.0f s CPU)\n",
		       s->hours[i], 100 * pt.probability, 100 * f,
		       100 * (pt.probability - f),
		       fabs(pt.probability - f) <= 0.10 ? "yes" : "NO",
		       100 * pt.p_present, 100 * pt.p_width, cpu_s(t0));
		if (fabs(pt.probability - f) > 0.10)
			++*worst;
		fflush(stdout);
	}
	return 0;
}

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return (x > y) - (x < y);
}

/* the q-quantile of sorted v[0..n) (linear between order statistics) */
static double quantile(const double *v, int n, double q)
{
	double h = q * (n - 1);
	int i = (int)floor(h);

	if (n <= 0)
		return NAN;
	if (i >= n - 1)
		return v[n - 1];
	return v[i] + (h - i) * (v[i + 1] - v[i]);
}

/* pilots of pilot_s each, fitted; the plan of B from the pilot's terms */
static int pilots(const struct bsensor *s, double rate, int count,
		  uint64_t seed, double pilot_s, bool ranges)
{
	struct sscope_sensor_spec spec = { 0 };
	size_t n = (size_t)llround(pilot_s * rate);
	double *x = malloc(n * sizeof(double)), ref;
	double *ratio = malloc((size_t)count * sizeof(double));
	int within = 0, planned = 0, covered = 0;

	if (!x || !ratio) {
		free(x);
		free(ratio);
		return -ENOMEM;
	}
	if (sscope_plan_needed(s->coef, rate, (enum sscope_term)s->term,
			       s->target, NULL, &ref)) {
		free(x);
		free(ratio);
		return -EDOM;
	}
	spec.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	spec.range = 1e6;
	spec.q = s->coef[0];
	spec.n = s->coef[1];
	spec.b = s->coef[2];
	spec.k = s->coef[3];
	spec.r = s->coef[4];
	printf("# %d pilots of %.0f min at %.0f Hz of %s: needed length of B from each pilot's fit, against %.2f h from the spec\n",
	       count, pilot_s / 60, rate, s->name, ref / 3600);
	for (int p = 0; p < count; p++)
		ratio[p] = INFINITY; /* not planned: never */
	for (int p = 0; p < count; p++) {
		struct sscope_sim_opts so = { 0 };
		struct sscope_sim *sim = NULL;
		struct sscope_allan_result *res = NULL;
		double c[5], need = INFINITY, lo, hi, rg[2] = { INFINITY, INFINITY };

		so.rate_hz = rate;
		so.seed = seed + 7777u + (uint64_t)p;
		so.no_clip = true;
		if (sscope_sim_new(&sim, &spec, &so, NULL))
			break;
		sscope_sim_generate(sim, NULL, x, NULL, n);
		sscope_sim_free(sim);
		if (sscope_allan_analyze(x, 1, n, rate, SSCOPE_ALLAN_TAUS_DENSE,
					 NULL, NULL, &res, NULL) || !res->have_fit) {
			sscope_allan_result_free(res);
			continue;
		}
		/* as `plan --pilot`: a term not shown present by the pilot
		 * enters with its estimate (every term free) */
		for (int j = 0; j < 5; j++)
			c[j] = res->fit.coef[j].present ? res->fit.coef[j].value :
				res->fit.coef[j].estimate;
		lo = res->fit.coef[s->term].lo;
		hi = res->fit.coef[s->term].hi;
		sscope_allan_result_free(res);
		/* as `plan` from a pilot: the needed length with the term at
		 * the upper and the lower end of the pilot's interval */
		if (ranges) {
			double cr[5];

			memcpy(cr, c, sizeof(cr));
			cr[s->term] = hi;
			if (isfinite(hi) && hi > 0)
				sscope_plan_needed(cr, rate, (enum sscope_term)s->term,
						   s->target, NULL, &rg[0]);
			cr[s->term] = lo;
			if (lo > 0)
				sscope_plan_needed(cr, rate, (enum sscope_term)s->term,
						   s->target, NULL, &rg[1]);
			covered += rg[0] <= ref && ref <= rg[1];
		}
		if (sscope_plan_needed(c, rate, (enum sscope_term)s->term,
				       s->target, NULL, &need) == 0 &&
		    isfinite(need)) {
			planned++;
			ratio[p] = need / ref;
			if (fabs(need / ref - 1) <= 0.25)
				within++;
		}
		if (count > 20)
			continue; /* the summary only */
		printf("pilot %2d: N %.3f deg/sqrt(h)  B %.2f deg/h  K %.1f deg/h/sqrt(h)  needed %.2f h (%+.0f %%)",
		       p + 1, c[1] / DEG * 60, c[2] / DEG * 3600,
		       c[3] / DEG * 3600 * 60, need / 3600,
		       100 * (need / ref - 1));
		if (ranges)
			printf("  range %.2f - %.2f h", rg[0] / 3600, rg[1] / 3600);
		putchar('\n');
	}
	printf("within +-25 %%: %d of %d pilots (%d planned)\n", within, count,
	       planned);
	qsort(ratio, (size_t)count, sizeof(double), cmp_d);
	printf("needed / spec's: median %.2f, 10th-90th percentile %.2f - %.2f (%.1fx)\n",
	       quantile(ratio, count, 0.5), quantile(ratio, count, 0.1),
	       quantile(ratio, count, 0.9),
	       quantile(ratio, count, 0.9) / quantile(ratio, count, 0.1));
	if (ranges)
		printf("the spec's length within the pilot's range (the term within its 68.3 %% interval): %d of %d pilots\n",
		       covered, count);
	free(ratio);
	free(x);
	return 0;
}

int main(int argc, char **argv)
{
	int records = argc > 1 ? atoi(argv[1]) : 200;
	double rate = argc > 2 ? atof(argv[2]) : 10;
	int npil = argc > 3 ? atoi(argv[3]) : 10;
	uint64_t seed = argc > 4 ? strtoull(argv[4], NULL, 10) : 20261202u;
	double pilot_s = argc > 5 ? atof(argv[5]) : 600;
	const char *rows = argc > 6 ? argv[6] : "msk";
	const struct bsensor s[2] = {
		{ "gyro-mems-250.ini",
		  { 0, 0.2 * DEG / 60, 4 * DEG / 3600, 20 * DEG / 3600 / 60, 0 },
		  SSCOPE_TERM_B, 0.10, { 0.5, 0.75, 1, 1.5, 2 } },
		{ "STIM300 gyro (datasheet)",
		  { 0, 0.15 * DEG / 60, 0.5 / 0.66428 * DEG / 3600, 0, 0 },
		  SSCOPE_TERM_B, 0.25, { 1, 2, 3, 4, 6 } },
	};
	int worst = 0, rc;

	if (records < 0 || !(rate > 0) || !(pilot_s > 0))
		return 2;
	for (int i = 0; i < 2 && records > 0; i++) {
		if (!strchr(rows, "ms"[i]))
			continue;
		rc = run_sensor(&s[i], rate, records, seed + 1000000u * (uint64_t)i,
				&worst);
		if (rc) {
			fprintf(stderr, "bench-plan: %s: %s\n", s[i].name,
				sscope_strerror(rc));
			return 1;
		}
	}
	if (records > 0 && strchr(rows, 'k')) {
		struct bsensor k = s[0];

		k.term = SSCOPE_TERM_K;
		k.target = 0.30;
		k.hours[0] = 1;
		k.hours[1] = 2;
		k.hours[2] = 3;
		k.hours[3] = 4;
		k.hours[4] = 6;
		rc = run_sensor(&k, rate, records, seed + 3000000u, &worst);
		if (rc)
			return 1;
	}
	printf("# %d rows outside +-10 points\n", worst);
	if (npil > 0 && pilots(&s[0], rate, npil, seed, pilot_s,
			       strchr(rows, 'r') != NULL))
		return 1;
	return 0;
}
