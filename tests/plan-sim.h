/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The planner's oracle (tests/test-plan.c, tests/bench-plan.c): records of
 * a simulated sensor (analysis/sim.c, the same generator as `simulate`)
 * fitted as `allan` does (dense taus, OADEV, the default fit), counting
 * those where the term is present and its interval's relative half-width
 * (hi - lo) / (2 value) is at most the target.
 */
#ifndef PLAN_SIM_H
#define PLAN_SIM_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sensorscope.h"

/* the fraction of `records` records (seeds seed0, seed0 + 1, ...) of
 * length_s at rate_hz that resolve term j to `target`; NaN on failure */
static double plan_sim_fraction(const double coef[5], double rate_hz,
				double length_s, int j, double target,
				int records, uint64_t seed0)
{
	struct sscope_sensor_spec spec;
	struct sscope_noise_plan *np = NULL;
	size_t n = (size_t)llround(length_s * rate_hz);
	double *x = malloc(n * sizeof(double));
	int hits = 0, done = 0;

	memset(&spec, 0, sizeof(spec));
	spec.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	spec.range = 1e6;
	spec.q = coef[0];
	spec.n = coef[1];
	spec.b = coef[2];
	spec.k = coef[3];
	spec.r = coef[4];
	if (!x || sscope_noise_plan_new(&np)) {
		free(x);
		return NAN;
	}
	for (int r = 0; r < records; r++) {
		struct sscope_sim_opts so;
		struct sscope_sim *sim = NULL;
		struct sscope_allan_result *res = NULL;
		struct sscope_noise_fit_opts fo = { 0 };
		const struct sscope_noise_coef *c;

		memset(&so, 0, sizeof(so));
		so.rate_hz = rate_hz;
		so.seed = seed0 + (uint64_t)r;
		so.no_clip = true;
		if (sscope_sim_new(&sim, &spec, &so, NULL))
			break;
		sscope_sim_generate(sim, NULL, x, NULL, n);
		sscope_sim_free(sim);
		fo.plan = np;
		if (sscope_allan_analyze(x, 1, n, rate_hz,
					 SSCOPE_ALLAN_TAUS_DENSE, NULL, &fo,
					 &res, NULL))
			break;
		done++;
		c = &res->fit.coef[j];
		if (res->have_fit && c->present && c->value > 0 &&
		    (c->hi - c->lo) / (2 * c->value) <= target)
			hits++;
		sscope_allan_result_free(res);
	}
	sscope_noise_plan_free(np);
	free(x);
	return done == records ? (double)hits / records : (double)NAN;
}

#endif /* PLAN_SIM_H */
