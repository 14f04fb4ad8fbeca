/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark of the ADC report's Monte-Carlo check: the seed's gyros
 * (+-100 deg/s, B 1 deg/h, N 0.1 and 0.005 deg/sqrt(h)) through 16 bits at
 * 100 Hz.  For record lengths 600 s .. 2 h, R realisations each: simulate,
 * digitize, two Allan analyses and fits (what `adc report` does per run);
 * reports the wall time per run and the N and B ratios (mean, sd over the
 * runs, and its standard error sd/sqrt(R)) -- how
 * the verdict's uncertainty shrinks with record length against the time
 * it costs.  Reference: for the dithered (MEMS) gyro the N ratio must be
 * the analytical sqrt(N^2 + q^2/(12 fs)) / N within 4 standard errors, and
 * the B ratio 1 within 4 standard errors (exit 1 otherwise); for the quiet
 * gyro the analytic white-noise model is an upper bound (the quantizer
 * error is not white and not q^2/12 when sigma < q/2), printed beside.
 * Usage: bench-adc [runs]  (default 8).
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sscope-adc.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180)

static double now(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double term(const struct sscope_allan_result *r, int t)
{
	return r->have_fit && r->fit.coef[t].fitted ? r->fit.coef[t].value : (double)NAN;
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
	as.quantity = SSCOPE_QTY_ANGULAR_RATE;
	as.rate_hz = fs;
	as.ref_temp_degc = 25;
	printf("# adc report Monte Carlo: 16 bits over +-100 deg/s at 100 Hz, %zu runs per row\n", R);
	printf("%-6s %7s %9s %8s %8s %9s %8s %8s %9s %9s\n", "ARW", "T_s", "s/run",
	       "N_ratio", "N_sd", "N_se", "B_ratio", "B_sd", "B_se", "N_analyt");
	for (size_t a = 0; a < 2; a++) {
		struct sscope_sensor_spec ss;
		struct sscope_adc_analysis an;

		memset(&ss, 0, sizeof(ss));
		ss.quantity = SSCOPE_QTY_ANGULAR_RATE;
		ss.has = SSCOPE_SPEC_RANGE | SSCOPE_SPEC_N | SSCOPE_SPEC_B;
		ss.range = 100 * DEG;
		ss.n = arws[a] * DEG / 60;
		ss.b = 1 * DEG / 3600;
		if (sscope_adc_analyze(&ss, &as, fs, &an, NULL))
			return 2;
		for (size_t d = 0; d < sizeof(durs) / sizeof(durs[0]); d++) {
			size_t n = (size_t)(durs[d] * fs);
			double *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));
			double sn = 0, sn2 = 0, sb = 0, sb2 = 0, t0, dt;
			size_t kn = 0, kb = 0;

			if (!x || !y)
				return 2;
			t0 = now();
			for (size_t r = 0; r < R; r++) {
				struct sscope_sim_opts so;
				struct sscope_sim *sim;
				struct sscope_adc *adc;
				struct sscope_allan_result *ri = NULL, *ro = NULL;
				double v;

				memset(&so, 0, sizeof(so));
				so.rate_hz = fs;
				so.seed = 1 + r;
				so.flicker_tau_max_s = fmax(1e6, 10 * durs[d]);
				if (sscope_sim_new(&sim, &ss, &so, NULL) ||
				    sscope_sim_generate(sim, NULL, x, NULL, n))
					return 2;
				sscope_sim_free(sim);
				if (sscope_adc_new(&adc, &as, 1, 0, 1 + r, NULL) ||
				    sscope_adc_digitize(adc, x, 1, n, fs, NULL, y, NULL, NULL))
					return 2;
				sscope_adc_free(adc);
				if (sscope_allan_analyze(x, 1, n, fs, SSCOPE_TAUS_DENSE, NULL, NULL,
							 &ri, NULL) ||
				    sscope_allan_analyze(y, 1, n, fs, SSCOPE_TAUS_DENSE, NULL, NULL,
							 &ro, NULL))
					return 2;
				v = term(ro, SSCOPE_TERM_N) / term(ri, SSCOPE_TERM_N);
				if (isfinite(v)) {
					sn += v;
					sn2 += v * v;
					kn++;
				}
				v = term(ro, SSCOPE_TERM_B) / term(ri, SSCOPE_TERM_B);
				if (isfinite(v)) {
					sb += v;
					sb2 += v * v;
					kb++;
				}
				sscope_allan_result_free(ri);
				sscope_allan_result_free(ro);
			}
			dt = (now() - t0) / (double)R;
			{
				double mn = kn ? sn / (double)kn : (double)NAN;
				double mb = kb ? sb / (double)kb : (double)NAN;
				double sdn = kn > 1 ? sqrt(fmax(0, (sn2 - kn * mn * mn) / (double)(kn - 1))) : (double)NAN;
				double sdb = kb > 1 ? sqrt(fmax(0, (sb2 - kb * mb * mb) / (double)(kb - 1))) : (double)NAN;
				double ref = an.n_total / ss.n;

				printf("%-6g %7g %9.3f %8.4f %8.4f %9.4f %8.4f %8.4f %9.4f %9.4f\n",
				       arws[a], durs[d], dt, mn, sdn, sdn / sqrt((double)kn),
				       mb, sdb, sdb / sqrt((double)kb), ref);
				if (a == 0 && (!(fabs(mn - ref) <= 4 * sdn / sqrt((double)kn) + 1e-4) ||
					       !(fabs(mb - 1) <= 4 * sdb / sqrt((double)kb) + 1e-3))) {
					printf("# FAIL: dithered gyro ratios off their reference\n");
					fail = 1;
				}
			}
			free(x);
			free(y);
		}
	}
	return fail;
}
