/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Generator of the bundled samples (make samples).  Deterministic: every
 * file has its own fixed seed for GSL's MT19937, Gaussian deviates by the
 * ziggurat method.  The static gyro and the thermal accelerometer come
 * from the library's sensor simulator (sscope_sim_*); the vibration, EuRoC
 * and raw samples use simple direct models (tones, white noise);
 * samples/README.md states each file's parameters.
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

/* one axis per stream of the library's simulator (analysis/sim.c) */
static void sim_axes(const struct sscope_sensor_spec *spec,
		     const struct sscope_sim_opts *base, size_t axes,
		     const double *input, double *const *out, double *temp,
		     size_t n)
{
	for (size_t k = 0; k < axes; k++) {
		struct sscope_sim_opts o = *base;
		struct sscope_sim *sim;
		struct sscope_diag d;

		o.stream = k;
		if (sscope_sim_new(&sim, &spec[k], &o, &d)) {
			fprintf(stderr, "gen-samples: %s\n", d.msg);
			exit(1);
		}
		sscope_sim_generate(sim, input ? input + k * n : NULL, out[k],
				    k == 0 ? temp : NULL, n);
		sscope_sim_free(sim);
	}
}

/*
 * gyro-static.csv: 3-axis MEMS-class gyro at rest, 10 Hz, 1 h, deg/s with
 * 5 decimals, from the library's simulator (seed 1001, streams 0-2):
 * N = 0.15 deg/sqrt(h), B = 2 deg/h (flicker), K = 10 deg/h/sqrt(h),
 * biases 0.12 / -0.05 / 0.31 deg/s.  The Allan curve shows the -1/2 slope,
 * the bias-instability floor from about 50 to 200 s and the +1/2 slope.
 */
static void gyro_static(const char *dir)
{
	const double fs = 10, T = 3600;
	const double bias[3] = { 0.12 * D2R, -0.05 * D2R, 0.31 * D2R };
	size_t n = (size_t)(fs * T);
	struct sscope_sensor_spec sp[3];
	struct sscope_sim_opts o = { 0 };
	double *y[3];
	FILE *f = open_out(dir, "gyro-static.csv");

	for (int k = 0; k < 3; k++) {
		memset(&sp[k], 0, sizeof(sp[k]));
		sp[k].quantity = SSCOPE_QTY_ANGULAR_RATE;
		sp[k].n = 0.15 * D2R / 60;             /* 0.15 deg/sqrt(h) */
		sp[k].b = 2.0 * D2R / 3600;            /* 2 deg/h */
		sp[k].k = 10.0 * D2R / 3600 / 60;      /* 10 deg/h/sqrt(h) */
		sp[k].bias = bias[k];
		y[k] = malloc(n * sizeof(double));
	}
	o.rate_hz = fs;
	o.seed = 1001;
	sim_axes(sp, &o, 3, NULL, y, NULL, n);
	fprintf(f, "# sensorscope sample: static MEMS gyro (simulated by sensorscope, seed 1001)\n"
		   "# rate: 10 Hz\n"
		   "gx [deg/s],gy [deg/s],gz [deg/s]\n");
	for (size_t i = 0; i < n; i++)
		fprintf(f, "%.5f,%.5f,%.5f\n", y[0][i] / D2R, y[1][i] / D2R,
			y[2][i] / D2R);
	fclose(f);
	for (int k = 0; k < 3; k++)
		free(y[k]);
}

/*
 * accel-thermal.csv: static 3-axis accelerometer (z up) at 1 Hz for 4 h
 * while the temperature cycles -10 .. 50 degC (raised cosine, period 2 h,
 * reading noise 0.05 degC), from the simulator (seed 1002): bias(T) a
 * cubic about 20 degC per axis, white noise 120 ug/sqrt(Hz).
 */
static void accel_thermal(const char *dir)
{
	const double fs = 1, T = 4 * 3600, g = 9.80665;
	const double c1[3] = { 0.08e-3, -0.05e-3, 0.12e-3 }; /* g/degC */
	const double c2[3] = { 1.5e-6, 2e-6, -1e-6 };        /* g/degC^2 */
	const double c3[3] = { 2e-8, -1e-8, 3e-8 };          /* g/degC^3 */
	const double b0[3] = { 2.1e-3, -1.4e-3, 3.3e-3 };    /* g */
	size_t n = (size_t)(fs * T);
	double *y[3], *temp = malloc(n * sizeof(double));
	double *in = calloc(3 * n, sizeof(double));
	struct sscope_sensor_spec sp[3];
	struct sscope_sim_opts o = { 0 };
	FILE *f = open_out(dir, "accel-thermal.csv");

	for (int k = 0; k < 3; k++) {
		memset(&sp[k], 0, sizeof(sp[k]));
		sp[k].quantity = SSCOPE_QTY_ACCELERATION;
		sp[k].n = 120e-6 * g; /* 120 ug/sqrt(Hz) */
		sp[k].bias = b0[k] * g;
		y[k] = malloc(n * sizeof(double));
	}
	for (size_t i = 0; i < n; i++)
		in[2 * n + i] = g; /* gravity on z */
	o.rate_hz = fs;
	o.seed = 1002;
	o.temp_profile = SSCOPE_SIM_TEMP_CYCLE;
	o.temp_wave = SSCOPE_SIM_SINE;
	o.temp_degc = -10;
	o.temp2_degc = 50;
	o.temp_period_s = 2 * 3600;
	o.temp_noise_degc = 0.05;
	o.ref_temp_degc = 20;
	for (int k = 0; k < 3; k++) {
		struct sscope_sim_opts ok = o;
		double *out1[1] = { y[k] };

		ok.bias_poly[0] = c1[k] * g;
		ok.bias_poly[1] = c2[k] * g;
		ok.bias_poly[2] = c3[k] * g;
		ok.stream = (uint64_t)k;
		{
			struct sscope_sim *sim;
			struct sscope_diag d;

			if (sscope_sim_new(&sim, &sp[k], &ok, &d)) {
				fprintf(stderr, "gen-samples: %s\n", d.msg);
				exit(1);
			}
			sscope_sim_generate(sim, in + (size_t)k * n, out1[0],
					    k == 0 ? temp : NULL, n);
			sscope_sim_free(sim);
		}
	}
	fprintf(f, "# sensorscope sample: static accelerometer, thermal cycle (simulated by sensorscope, seed 1002)\n"
		   "time [s],ax [g],ay [g],az [g],temp [degC]\n");
	for (size_t i = 0; i < n; i++)
		fprintf(f, "%zu,%.6f,%.6f,%.6f,%.2f\n", i, y[0][i] / g,
			y[1][i] / g, y[2][i] / g, temp[i]);
	fclose(f);
	for (int k = 0; k < 3; k++)
		free(y[k]);
	free(temp);
	free(in);
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

int main(int argc, char **argv)
{
	const char *dir = argc > 1 ? argv[1] : "samples";

	gyro_static(dir);
	accel_thermal(dir);
	vibration(dir);
	euroc(dir);
	imu_raw(dir);
	return 0;
}
