/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Generator of the bundled samples (make samples).  Deterministic: every
 * file has its own fixed seed for GSL's MT19937, Gaussian deviates by the
 * ziggurat method.  Models are deliberately simple (white noise, a random
 * walk, a first-order Gauss-Markov bias, tones); samples/README.md states
 * each file's parameters.
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#define PI 3.14159265358979323846
#define D2R (PI / 180)

static FILE *open_out(const char *dir, const char *name)
{
	char path[512];
	FILE *f;

	snprintf(path, sizeof(path), "%s/%s", dir, name);
	f = fopen(path, "w");
	if (!f) {
		perror(path);
		exit(1);
	}
	return f;
}

/*
 * gyro-static.csv: 3-axis MEMS-class gyro, 10 Hz output, 1 h, deg/s.
 * Per axis: bias, white rate noise of density N, a Gauss-Markov bias
 * (sigma_b, tau_c = 300 s) for a bias-instability plateau, and a rate
 * random walk K.
 */
static void gyro_static(const char *dir)
{
	const double fs = 10, T = 3600;
	const double N = 0.15 * D2R / 60;          /* 0.15 deg/sqrt(h) */
	const double K = 3.0 * D2R / 3600 / 60;    /* 3 deg/h/sqrt(h) */
	const double sb = 4.0 * D2R / 3600, tc = 300; /* GM bias, 4 deg/h */
	const double bias[3] = { 0.12 * D2R, -0.05 * D2R, 0.31 * D2R };
	size_t n = (size_t)(fs * T);
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "gyro-static.csv");
	double gm[3] = { 0 }, rw[3] = { 0 }, a = exp(-1 / (fs * tc));

	gsl_rng_set(r, 1001);
	fprintf(f, "# sensorscope sample: static MEMS gyro (simulated, seed 1001)\n"
		   "# rate: 10 Hz\n"
		   "gx [deg/s],gy [deg/s],gz [deg/s]\n");
	for (size_t i = 0; i < n; i++) {
		for (int k = 0; k < 3; k++) {
			double w;

			gm[k] = a * gm[k] + sb * sqrt(1 - a * a) *
						    gsl_ran_gaussian_ziggurat(r, 1);
			rw[k] += K * sqrt(1 / fs) * gsl_ran_gaussian_ziggurat(r, 1);
			w = bias[k] + gm[k] + rw[k] +
			    N * sqrt(fs) * gsl_ran_gaussian_ziggurat(r, 1);
			fprintf(f, "%s%.5f", k ? "," : "", w / D2R);
		}
		fputc('\n', f);
	}
	fclose(f);
	gsl_rng_free(r);
}

/*
 * accel-thermal.csv: static 3-axis accelerometer (z up) at 1 Hz for 4 h
 * while the temperature cycles -10 .. 50 degC; bias(T) is a cubic about
 * 20 degC, white noise 120 ug/sqrt(Hz).
 */
static void accel_thermal(const char *dir)
{
	const double fs = 1, T = 4 * 3600, nd = 120e-6 * 9.80665;
	size_t n = (size_t)(fs * T);
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "accel-thermal.csv");
	const double c1[3] = { 0.08e-3, -0.05e-3, 0.12e-3 }; /* g/degC */
	const double c2[3] = { 1.5e-6, 2e-6, -1e-6 };        /* g/degC^2 */
	const double c3[3] = { 2e-8, -1e-8, 3e-8 };          /* g/degC^3 */
	const double b0[3] = { 2.1e-3, -1.4e-3, 3.3e-3 };    /* g */

	gsl_rng_set(r, 1002);
	fprintf(f, "# sensorscope sample: static accelerometer, thermal cycle (simulated, seed 1002)\n"
		   "time [s],ax [g],ay [g],az [g],temp [degC]\n");
	for (size_t i = 0; i < n; i++) {
		double t = (double)i / fs;
		double temp = 20 - 30 * cos(2 * PI * t / (2 * 3600)) +
			      0.05 * gsl_ran_gaussian_ziggurat(r, 1);
		double d = temp - 20;

		fprintf(f, "%.0f", t);
		for (int k = 0; k < 3; k++) {
			double g = (k == 2 ? 1 : 0) + b0[k] + c1[k] * d +
				   c2[k] * d * d + c3[k] * d * d * d +
				   nd * sqrt(fs / 2) / 9.80665 *
					   gsl_ran_gaussian_ziggurat(r, 1);

			fprintf(f, ",%.6f", g);
		}
		fprintf(f, ",%.2f\n", temp);
	}
	fclose(f);
	gsl_rng_free(r);
}

/*
 * vibration.csv: accelerometer on a motor at 1770 rpm (29.5 Hz), 5 kHz,
 * 2 s: unbalance (strong 1x), some 2x and 3x, a 360 Hz structural tone,
 * broadband noise.
 */
static void vibration(const char *dir)
{
	const double fs = 5000, T = 2, fr = 1770.0 / 60;
	size_t n = (size_t)(fs * T);
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "vibration.csv");

	gsl_rng_set(r, 1003);
	fprintf(f, "# sensorscope sample: motor vibration, 1770 rpm (simulated, seed 1003)\n"
		   "t [s],ax [m/s^2],ay [m/s^2],az [m/s^2]\n");
	for (size_t i = 0; i < n; i++) {
		double t = (double)i / fs, w = 2 * PI * fr * t;
		double ax = 4.0 * sin(w + 0.3) + 0.8 * sin(2 * w + 1.1) +
			    0.3 * sin(3 * w) + 0.5 * sin(2 * PI * 360 * t) +
			    0.2 * gsl_ran_gaussian_ziggurat(r, 1);
		double ay = 3.6 * cos(w + 0.3) + 0.6 * sin(2 * w) +
			    0.2 * gsl_ran_gaussian_ziggurat(r, 1);
		double az = 0.4 * sin(w) + 0.25 * gsl_ran_gaussian_ziggurat(r, 1);

		fprintf(f, "%.4f,%.4f,%.4f,%.4f\n", t, ax, ay, az);
	}
	fclose(f);
	gsl_rng_free(r);
}

/* euroc-imu.csv: 5 s of a 200 Hz IMU in EuRoC's format and units. */
static void euroc(const char *dir)
{
	const double fs = 200;
	size_t n = 1000;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "euroc-imu.csv");
	long long t0 = 1403636579758555392LL;

	gsl_rng_set(r, 1004);
	fprintf(f, "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],"
		   "w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],"
		   "a_RS_S_z [m s^-2]\n");
	for (size_t i = 0; i < n; i++) {
		double g[3], a[3];

		for (int k = 0; k < 3; k++) {
			g[k] = 0.002 * (k + 1) + 1.7e-4 * sqrt(fs) *
							 gsl_ran_gaussian_ziggurat(r, 1);
			a[k] = (k == 0 ? 9.80665 : 0) +
			       2e-3 * sqrt(fs) * gsl_ran_gaussian_ziggurat(r, 1);
		}
		fprintf(f, "%lld,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
			t0 + (long long)i * 5000000LL, g[0], g[1], g[2], a[0],
			a[1], a[2]);
	}
	fclose(f);
	gsl_rng_free(r);
}

/*
 * imu-raw.bin: 60 s of a 6-axis IMU at 100 Hz as little-endian int16
 * (gx gy gz ax ay az); read with --raw i16:6:le --scale 0.01 -u deg/s
 * for the gyro columns (1 LSB = 0.01 deg/s; the accelerometer columns use
 * 1 LSB = 0.5 mg).
 */
static void imu_raw(const char *dir)
{
	size_t n = 6000;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "imu-raw.bin");

	gsl_rng_set(r, 1005);
	for (size_t i = 0; i < n; i++) {
		for (int k = 0; k < 6; k++) {
			double v = k < 3 ? (0.1 * (k + 1) +
					    0.05 * gsl_ran_gaussian_ziggurat(r, 1)) / 0.01 :
					   ((k == 5 ? 1000 : 0) +
					    2 * gsl_ran_gaussian_ziggurat(r, 1)) / 0.5;
			int16_t s = (int16_t)lround(v);
			unsigned char b[2] = { (unsigned char)(s & 0xff),
					       (unsigned char)((s >> 8) & 0xff) };

			fwrite(b, 1, 2, f);
		}
	}
	fclose(f);
	gsl_rng_free(r);
}

/*
 * bearing-outer.csv: accelerometer on a motor at 1797 rpm with an
 * outer-race defect in its SKF 6205 bearing (9 balls, d = 7.94 mm,
 * D = 39.04 mm: BPFO = 3.5848 x 29.95 Hz = 107.4 Hz), 12 kHz, 2 s: each
 * ball pass strikes the defect (interval jittered by 1 %, the balls'
 * slip) and rings a 3 kHz structural resonance (decay 0.6 ms, 1.5 m/s^2),
 * plus 1x (0.3 m/s^2), 2x (0.1 m/s^2) and white noise (0.5 m/s^2 rms).
 */
static void bearing_outer(const char *dir)
{
	const double fs = 12000, T = 2, fr = 1797.0 / 60;
	const double r = 7.94 / 39.04, bpfo = 9 / 2.0 * fr * (1 - r);
	size_t n = (size_t)(fs * T);
	double *x = calloc(n, sizeof(double)), ti = 0.01;
	gsl_rng *g = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "bearing-outer.csv");

	if (!x)
		exit(1);
	gsl_rng_set(g, 1006);
	for (size_t i = 0; i < n; i++) {
		double w = 2 * PI * fr * (double)i / fs;

		x[i] = 0.3 * sin(w + 0.4) + 0.1 * sin(2 * w + 1.3) +
		       gsl_ran_gaussian_ziggurat(g, 0.5);
	}
	while (ti < T) {
		size_t i0 = (size_t)ceil(ti * fs);

		for (size_t i = i0; i < n && i < i0 + 72; i++) {
			double dt = (double)i / fs - ti;

			x[i] += 1.5 * exp(-dt / 0.6e-3) * sin(2 * PI * 3000 * dt);
		}
		ti += (1 + 0.01 * gsl_ran_gaussian_ziggurat(g, 1)) / bpfo;
	}
	fprintf(f, "# sensorscope sample: outer-race bearing defect, 1797 rpm, SKF 6205 (simulated, seed 1006)\n"
		   "# rate: 12000 Hz\n"
		   "acc [m/s^2]\n");
	for (size_t i = 0; i < n; i++)
		fprintf(f, "%.4f\n", x[i]);
	fclose(f);
	free(x);
	gsl_rng_free(g);
}

int main(int argc, char **argv)
{
	const char *dir = argc > 1 ? argv[1] : "samples";

	gyro_static(dir);
	accel_thermal(dir);
	vibration(dir);
	euroc(dir);
	imu_raw(dir);
	bearing_outer(dir);
	return 0;
}
