/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark of the calibration and budget kernels, each with its run time
 * and its error against a reference:
 * - static-detector variance magnitude: sliding sums re-anchored every
 *   window (the library) against a direct two-pass variance per window;
 * - accelerometer multi-position fit (Levenberg-Marquardt, 30 poses):
 *   time per fit and the rms of (estimate - truth) / reported sd over
 *   seeded runs (1 when the uncertainties are right);
 * - gyro multi-position fit on a simulated 16-pose series;
 * - Monte-Carlo random-walk check: time and the deviation of the +-2 sigma
 *   fraction from erf(sqrt 2) in binomial standard deviations.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#define G0 9.80665
#define PI 3.14159265358979323846

static double now(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void variance_bench(void)
{
	size_t n = 1000000, w = 101, h = w / 2;
	double *x = malloc(3 * n * sizeof(double)), *vs = malloc(n * sizeof(double));
	double t0, t1, t2, maxrel = 0;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	gsl_rng_set(r, 3);
	for (size_t i = 0; i < 3 * n; i++)
		x[i] = 16384 + 7.3 * gsl_ran_gaussian_ziggurat(r, 1); /* counts */
	t0 = now();
	sscope_calib_variance_magnitude(x, x + 1, x + 2, 3, n, w, vs);
	t1 = now();
	for (size_t i = h; i + h < n; i++) {
		double v2 = 0;

		for (int c = 0; c < 3; c++) {
			double m = 0, s = 0;

			for (size_t j = i - h; j <= i + h; j++)
				m += x[3 * j + c];
			m /= (double)w;
			for (size_t j = i - h; j <= i + h; j++)
				s += (x[3 * j + c] - m) * (x[3 * j + c] - m);
			s /= (double)(w - 1);
			v2 += s * s;
		}
		maxrel = fmax(maxrel, fabs(vs[i] - sqrt(v2)) / sqrt(v2));
	}
	t2 = now();
	printf("variance magnitude, 1e6 x 3 samples, window 101: sliding %.3f s, direct two-pass %.3f s (x%.0f), max relative difference %.2e\n",
	       t1 - t0, t2 - t1, (t2 - t1) / (t1 - t0), maxrel);
	free(x);
	free(vs);
	gsl_rng_free(r);
}

static void quat_rot(gsl_rng *r, double R[3][3])
{
	double q[4], n = 0;

	for (int i = 0; i < 4; i++) {
		q[i] = gsl_ran_gaussian_ziggurat(r, 1);
		n += q[i] * q[i];
	}
	for (int i = 0; i < 4; i++)
		q[i] /= sqrt(n);
	R[0][0] = 1 - 2 * (q[2] * q[2] + q[3] * q[3]);
	R[0][1] = 2 * (q[1] * q[2] - q[0] * q[3]);
	R[0][2] = 2 * (q[1] * q[3] + q[0] * q[2]);
	R[1][0] = 2 * (q[1] * q[2] + q[0] * q[3]);
	R[1][1] = 1 - 2 * (q[1] * q[1] + q[3] * q[3]);
	R[1][2] = 2 * (q[2] * q[3] - q[0] * q[1]);
	R[2][0] = 2 * (q[1] * q[3] - q[0] * q[2]);
	R[2][1] = 2 * (q[2] * q[3] + q[0] * q[1]);
	R[2][2] = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
}

static void accel_bench(void)
{
	const int runs = 200;
	/* truth in the correction form: K, T (upper), b */
	const double K[3] = { 1.0123, 0.9871, 1.0047 }, b[3] = { 0.0213, -0.0371, 0.0452 };
	const double a_yz = 0.0042, a_zy = 0.0027, a_zx = 0.0061;
	double z2 = 0, t0, t1;
	int nz = 0;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double m[30][3];

	t0 = now();
	for (int run = 0; run < runs; run++) {
		struct sscope_calib_triad c;

		gsl_rng_set(r, 1000 + (unsigned long)run);
		for (int k = 0; k < 30; k++) {
			double R[3][3], f[3], u[3];

			quat_rot(r, R);
			for (int i = 0; i < 3; i++)
				f[i] = R[2][i] * G0;
			/* invert T K: T upper unit triangular */
			u[2] = f[2];
			u[1] = f[1] + a_zx * u[2];
			u[0] = f[0] + a_yz * u[1] - a_zy * u[2];
			for (int i = 0; i < 3; i++)
				m[k][i] = u[i] / K[i] + b[i] + 2e-3 * gsl_ran_gaussian_ziggurat(r, 1);
		}
		if (sscope_calib_accel_fit((const double(*)[3])m, 30, G0, &c, NULL))
			continue;
		for (int i = 0; i < 3; i++) {
			double e1 = (c.bias[i] - b[i]) / c.bias_sd[i];
			double e2 = (c.scale[i] - K[i]) / c.scale_sd[i];

			z2 += e1 * e1 + e2 * e2;
			nz += 2;
		}
	}
	t1 = now();
	printf("accelerometer multi-position fit (30 poses, 9 parameters, LM): %.3f ms per fit, rms (estimate - truth)/sd = %.3f over %d values (1 = honest uncertainties)\n",
	       (t1 - t0) / runs * 1e3, sqrt(z2 / nz), nz);
	gsl_rng_free(r);
}

static void mc_bench(void)
{
	struct sscope_budget_mc_opts o = { .gyro = true, .strength = 1e-4,
					   .t_end_s = 600, .steps = 1000,
					   .realisations = 10000, .seed = 5 };
	double t = 600, t0, t1, p = erf(sqrt(2.0));
	struct sscope_budget_mc_point pt;

	t0 = now();
	sscope_budget_mc(&o, &t, 1, &pt, NULL, 0);
	t1 = now();
	printf("Monte-Carlo ARW check, 10000 x 1000 steps: %.3f s, fraction inside +-2 sigma %.4f (%.2f binomial sd from %.4f), sd ratio %.4f\n",
	       t1 - t0, pt.walk_inside,
	       (pt.walk_inside - p) / sqrt(p * (1 - p) / 10000), p,
	       pt.walk_sd / pt.walk_sd_theory);
}

static void budget_bench(void)
{
	struct sscope_budget_params p = { .gyro_bias_rad_s = 10 * PI / 180 / 3600 };
	struct sscope_budget_point pt;
	double t0, t1;
	volatile double sink = 0; /* keeps the timed loop */
	int n = 1000000;

	t0 = now();
	for (int i = 0; i < n; i++) {
		sscope_budget_source_eval(&p, SSCOPE_BUDGET_GYRO_BIAS, 120 + 1e-6 * i, &pt);
		sink += pt.position_m;
	}
	t1 = now();
	sscope_budget_source_eval(&p, SSCOPE_BUDGET_GYRO_BIAS, 120, &pt);
	printf("budget evaluation: %.1f ns per source and time; 10 deg/h for 120 s -> %.4f m (g b t^3/6 = %.4f m)\n",
	       (t1 - t0) / n * 1e9, pt.position_m,
	       G0 * p.gyro_bias_rad_s * 120 * 120 * 120 / 6);
	(void)sink;
}

int main(void)
{
	variance_bench();
	accel_bench();
	mc_bench();
	budget_bench();
	return 0;
}
