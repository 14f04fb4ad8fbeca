/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark of the ADC report's Monte-Carlo check, the shipped code
 * (sscope_adc_monte_carlo, what `adc report` runs per converter): the
 * textbook's gyros (+-100 deg/s, B 1 deg/h, N 0.1 and 0.005 deg/sqrt(h))
 * through 16 bits at 100 Hz.  For record lengths 600 s .. 2 h, R runs
 * each; reports the wall time per run and the N and B ratios (mean and
 * standard error over the runs, from their 68.27 % Student-t interval) --
 * how the verdict's uncertainty shrinks with record length against the
 * time it costs.  Reference: for the dithered (MEMS) gyro the N ratio must be the
 * analytical sqrt(N^2 + q^2/(12 fs)) / N and the B ratio 1, each within 4
 * standard errors (exit 1 otherwise); for the quiet gyro the analytic
 * white-noise model is an upper bound (the quantizer error is not white
 * and not q^2/12 when sigma < q/2), printed beside.
 * Usage: bench-adc [runs]  (default 8).
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_cdf.h>

#include "sscope-adc.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180)

static double now(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* standard error of the mean ratio: the half width of its 68.27 %
 * Student-t interval over t(0.84135, runs - 1) */
static double se_of(const struct sscope_adc_mc_ratio *r)
{
	if (r->runs < 2)
		return NAN;
	return (r->hi - r->lo) / 2 /
	       gsl_cdf_tdist_Pinv(0.5 + 0.6827 / 2, (double)(r->runs - 1));
}

int main(int argc, char **argv)
{
	static const double durs[] = { 600, 1800, 3600, 7200 };
	static const double arws[] = { 0.1, 0.005 };
	size_t R = argc > 1 ? (size_t)atoi(argv[1]) : 8;
	double fs = 100;
	int fail = 0;
	struct sscope_adc_spec as;

	if (R < 2)
		R = 2;
	memset(&as, 0, sizeof(as));
	as.bits = 16;
	as.lo = -100 * DEG;
	as.hi = 100 * DEG;
	as.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	as.rate_hz = fs;
	as.ref_temp_degc = 25;
	printf("# adc report Monte Carlo (sscope_adc_monte_carlo): 16 bits over +-100 deg/s at 100 Hz, %zu runs per row\n", R);
	printf("%-6s %7s %9s %8s %9s %8s %9s %9s\n", "ARW", "T_s", "s/run",
	       "N_ratio", "N_se", "B_ratio", "B_se", "N_analyt");
	for (size_t a = 0; a < 2; a++) {
		struct sscope_sensor_spec ss;
		struct sscope_adc_analysis an;

		memset(&ss, 0, sizeof(ss));
		ss.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
		ss.has = SSCOPE_SENSOR_HAS_RANGE | SSCOPE_SENSOR_HAS_N | SSCOPE_SENSOR_HAS_B;
		ss.range = 100 * DEG;
		ss.n = arws[a] * DEG / 60;
		ss.b = 1 * DEG / 3600;
		if (sscope_adc_analyze(&ss, &as, fs, &an, NULL))
			return 2;
		for (size_t d = 0; d < sizeof(durs) / sizeof(durs[0]); d++) {
			struct sscope_adc_mc_opts mo = { .runs = R, .duration_s = durs[d], .seed = 1,
							  .ci_level = 0.6827, .rate_hz = fs };
			struct sscope_adc_mc mc;
			struct sscope_diag dg = { "" };
			double t0 = now(), dt, ref = an.n_total / ss.n;
			double sen, seb;

			if (sscope_adc_monte_carlo(&ss, &as, NULL, 0, 1, 0, &mo, &mc, &dg)) {
				fprintf(stderr, "bench-adc: %s\n", dg.msg);
				return 2;
			}
			dt = (now() - t0) / (double)R;
			sen = se_of(&mc.ratio[0]);
			seb = se_of(&mc.ratio[1]);
			printf("%-6g %7g %9.3f %8.4f %9.4f %8.4f %9.4f %9.4f\n",
			       arws[a], durs[d], dt, mc.ratio[0].mean, sen,
			       mc.ratio[1].mean, seb, ref);
			if (a == 0 && (!(fabs(mc.ratio[0].mean - ref) <= 4 * sen + 1e-4) ||
				       !(fabs(mc.ratio[1].mean - 1) <= 4 * seb + 1e-3))) {
				printf("# FAIL: dithered gyro ratios off their reference\n");
				fail = 1;
			}
			sscope_adc_mc_clear(&mc);
		}
	}
	return fail;
}
