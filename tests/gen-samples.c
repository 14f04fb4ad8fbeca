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
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "drive-sim.h"
#include "zupt-sim.h"

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
		sp[k].quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
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
		sp[k].quantity = SSCOPE_QUANTITY_ACCELERATION;
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

/* ------------------------------------------------------------------ */
/* Calibration samples (sensorscope calib)                             */
/* ------------------------------------------------------------------ */

static void rot_from_quat(const double q[4], double R[3][3])
{
	double w = q[0], x = q[1], y = q[2], z = q[3];

	R[0][0] = 1 - 2 * (y * y + z * z);
	R[0][1] = 2 * (x * y - w * z);
	R[0][2] = 2 * (x * z + w * y);
	R[1][0] = 2 * (x * y + w * z);
	R[1][1] = 1 - 2 * (x * x + z * z);
	R[1][2] = 2 * (y * z - w * x);
	R[2][0] = 2 * (x * z - w * y);
	R[2][1] = 2 * (y * z + w * x);
	R[2][2] = 1 - 2 * (x * x + y * y);
}

/* R = Ra * exp([u phi]x) */
static void rot_about_axis(const double Ra[3][3], const double u[3], double phi,
			   double R[3][3])
{
	double c = cos(phi), s = sin(phi), E[3][3];

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			E[i][j] = (i == j ? c : 0) + (1 - c) * u[i] * u[j];
	E[0][1] -= s * u[2];
	E[0][2] += s * u[1];
	E[1][0] += s * u[2];
	E[1][2] -= s * u[0];
	E[2][0] -= s * u[1];
	E[2][1] += s * u[0];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			R[i][j] = Ra[i][0] * E[0][j] + Ra[i][1] * E[1][j] +
				  Ra[i][2] * E[2][j];
}

/* y = A u + b (+ G f for the gyro) */
static void err_model(const double A[3][3], const double b[3], const double u[3],
		      double y[3])
{
	for (int i = 0; i < 3; i++)
		y[i] = A[i][0] * u[0] + A[i][1] * u[1] + A[i][2] * u[2] + b[i];
}

/* the inverse of a unit-upper-triangular T times diag(K) */
static void inv_tk(const double T[3][3], const double K[3], double A[3][3])
{
	double C[3][3], d;

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			C[i][j] = T[i][j] * K[j];
	d = C[0][0] * (C[1][1] * C[2][2] - C[1][2] * C[2][1]) -
	    C[0][1] * (C[1][0] * C[2][2] - C[1][2] * C[2][0]) +
	    C[0][2] * (C[1][0] * C[2][1] - C[1][1] * C[2][0]);
	A[0][0] = (C[1][1] * C[2][2] - C[1][2] * C[2][1]) / d;
	A[0][1] = (C[0][2] * C[2][1] - C[0][1] * C[2][2]) / d;
	A[0][2] = (C[0][1] * C[1][2] - C[0][2] * C[1][1]) / d;
	A[1][0] = (C[1][2] * C[2][0] - C[1][0] * C[2][2]) / d;
	A[1][1] = (C[0][0] * C[2][2] - C[0][2] * C[2][0]) / d;
	A[1][2] = (C[0][2] * C[1][0] - C[0][0] * C[1][2]) / d;
	A[2][0] = (C[1][0] * C[2][1] - C[1][1] * C[2][0]) / d;
	A[2][1] = (C[0][1] * C[2][0] - C[0][0] * C[2][1]) / d;
	A[2][2] = (C[0][0] * C[1][1] - C[0][1] * C[1][0]) / d;
}

/*
 * accel-6pos.csv: accelerometer held +-1 g on each axis for 10 s, 3 s
 * turns between the poses, 100 Hz, in g.  Error model (reading = A f + b,
 * A = I + scale errors + misalignments): bias 12.3 / -8.7 / 15.2 mg, scale
 * errors +0.8 / -0.5 / +1.2 %, off-diagonal terms as in the table below;
 * white noise 1 mg per sample.
 */
static void accel_sixpos(const char *dir)
{
	const double fs = 100, ts = 10, tm = 3;
	const double A[3][3] = { { 1.008, 0.002, -0.003 },
				 { 0.0015, 0.995, 0.001 },
				 { -0.002, 0.0025, 1.012 } };
	const double b[3] = { 0.0123, -0.0087, 0.0152 };
	const int up[6][3] = { { 0, 0, 1 }, { 0, 0, -1 }, { 1, 0, 0 },
			       { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 } };
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "accel-6pos.csv");
	size_t k = 0;

	gsl_rng_set(r, 1006);
	fprintf(f, "# sensorscope sample: six-position accelerometer test (simulated, seed 1006)\n"
		   "time [s],ax [g],ay [g],az [g]\n");
	for (int p = 0; p < 6; p++) {
		size_t ns = (size_t)(ts * fs), nm = p < 5 ? (size_t)(tm * fs) : 0;

		for (size_t i = 0; i < ns + nm; i++, k++) {
			double u[3], y[3];

			if (i < ns) {
				for (int c = 0; c < 3; c++)
					u[c] = up[p][c];
			} else {
				/* a smooth swing from this pose to the next */
				double x = (double)(i - ns + 1) / (double)nm;
				double w = 0.5 - 0.5 * cos(PI * x), n = 0;

				for (int c = 0; c < 3; c++) {
					u[c] = (1 - w) * up[p][c] + w * up[p + 1][c] +
					       (c == 2 && p % 2 == 0 ? 0.3 * sin(PI * x) : 0) +
					       (c == 0 && p % 2 == 1 ? 0.3 * sin(PI * x) : 0);
					n += u[c] * u[c];
				}
				for (int c = 0; c < 3; c++)
					u[c] /= sqrt(n);
			}
			err_model(A, b, u, y);
			fprintf(f, "%.2f", (double)k / fs);
			for (int c = 0; c < 3; c++)
				fprintf(f, ",%.6f", y[c] + 1e-3 * gsl_ran_gaussian_ziggurat(r, 1));
			fputc('\n', f);
		}
	}
	fclose(f);
	gsl_rng_free(r);
}

/*
 * imu-multipose.csv: a 6-axis IMU held still in 20 random orientations
 * (4 s each) and turned between them (1.5 s, about a fixed body axis with a
 * raised-cosine rate), 100 Hz.  Accelerometer (g): the correction of
 * Tedaldi et al. a' = T K (a - b) with b = 21 / -15 / 34 mg, K = 1/1.011,
 * 1/0.993, 1/1.006 (g -> g), T upper triangular (alpha_yz 0.004,
 * alpha_zy -0.003, alpha_zx 0.005), noise 2 mg per sample.  Gyro (deg/s):
 * w' = T K (w - b - G a) with b = 0.31 / -0.17 / 0.52 deg/s, K = 1/1.021,
 * 1/0.976, 1/1.008, T off-diagonal 0.008 -0.004 / 0.006 0.011 /
 * -0.007 0.004 (rows), G = 0.05 deg/s/g on the diagonal, noise
 * 0.05 deg/s per sample.  No Earth rate.
 */
static void imu_multipose(const char *dir)
{
	const double fs = 100, ts = 4, tm = 1.5;
	const size_t poses = 20, ns = (size_t)(ts * fs), nm = (size_t)(tm * fs);
	const double Ta[3][3] = { { 1, -0.004, -0.003 }, { 0, 1, -0.005 },
				  { 0, 0, 1 } };
	const double Ka[3] = { 1 / 1.011, 1 / 0.993, 1 / 1.006 };
	const double ba[3] = { 0.021, -0.015, 0.034 };
	const double Tg[3][3] = { { 1, 0.008, -0.004 }, { 0.006, 1, 0.011 },
				  { -0.007, 0.004, 1 } };
	const double Kg[3] = { 1 / 1.021, 1 / 0.976, 1 / 1.008 };
	const double bg[3] = { 0.31, -0.17, 0.52 }, Gd = 0.05;
	double Aa[3][3], Ag[3][3], (*R)[3][3] = malloc(poses * sizeof(*R));
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "imu-multipose.csv");
	size_t k = 0;

	inv_tk(Ta, Ka, Aa);
	inv_tk(Tg, Kg, Ag);
	gsl_rng_set(r, 1007);
	for (size_t p = 0; p < poses; p++) {
		double q[4], n = 0;

		for (int i = 0; i < 4; i++) {
			q[i] = gsl_ran_gaussian_ziggurat(r, 1);
			n += q[i] * q[i];
		}
		for (int i = 0; i < 4; i++)
			q[i] /= sqrt(n);
		rot_from_quat(q, R[p]);
	}
	fprintf(f, "# sensorscope sample: multi-position IMU calibration run (simulated, seed 1007)\n"
		   "time [s],gx [deg/s],gy [deg/s],gz [deg/s],ax [g],ay [g],az [g]\n");
	for (size_t p = 0; p < poses; p++) {
		double ax[3] = { 1, 0, 0 }, ang = 0;

		if (p + 1 < poses) {
			/* body-frame rotation from pose p to p + 1 */
			double D[3][3], s;

			for (int i = 0; i < 3; i++)
				for (int j = 0; j < 3; j++)
					D[i][j] = R[p][0][i] * R[p + 1][0][j] +
						  R[p][1][i] * R[p + 1][1][j] +
						  R[p][2][i] * R[p + 1][2][j];
			ang = acos(fmax(-1, fmin(1, (D[0][0] + D[1][1] + D[2][2] - 1) / 2)));
			ax[0] = D[2][1] - D[1][2];
			ax[1] = D[0][2] - D[2][0];
			ax[2] = D[1][0] - D[0][1];
			s = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
			for (int i = 0; i < 3; i++)
				ax[i] /= s;
		}
		for (size_t i = 0; i < ns + (p + 1 < poses ? nm : 0); i++, k++) {
			double Rt[3][3], w[3] = { 0, 0, 0 }, fb[3], ya[3], yg[3];

			if (i < ns) {
				memcpy(Rt, R[p], sizeof(Rt));
			} else {
				double t = (double)(i - ns + 1) / fs;
				double phi = ang * (t / tm - sin(2 * PI * t / tm) / (2 * PI));
				double rate = ang / tm * (1 - cos(2 * PI * t / tm));

				rot_about_axis(R[p], ax, phi, Rt);
				for (int c = 0; c < 3; c++)
					w[c] = ax[c] * rate / D2R; /* deg/s */
			}
			for (int c = 0; c < 3; c++)
				fb[c] = Rt[2][c]; /* g */
			err_model(Aa, ba, fb, ya);
			err_model(Ag, bg, w, yg);
			for (int c = 0; c < 3; c++)
				yg[c] += Gd * fb[c];
			fprintf(f, "%.2f", (double)k / fs);
			for (int c = 0; c < 3; c++)
				fprintf(f, ",%.5f", yg[c] + 0.05 * gsl_ran_gaussian_ziggurat(r, 1));
			for (int c = 0; c < 3; c++)
				fprintf(f, ",%.6f", ya[c] + 2e-3 * gsl_ran_gaussian_ziggurat(r, 1));
			fputc('\n', f);
		}
	}
	free(R);
	fclose(f);
	gsl_rng_free(r);
}

/*
 * gyro-ratetable.csv: a gyro with x on a rate table, 13 steps of 5 s from
 * -300 to +300 deg/s, 100 Hz, commanded rate in rate_cmd.  x reads
 * 0.21 + 1.0085 w - 4e-7 w^3 (w in deg/s: a cubic scale-factor
 * non-linearity), y and z see cross-axis sensitivities 0.0042 and -0.0031
 * and biases -0.12 / 0.08 deg/s; first-order response (20 ms), white noise
 * 0.05 deg/s per sample.
 */
static void gyro_ratetable(const char *dir)
{
	const double fs = 100, tstep = 5;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "gyro-ratetable.csv");
	double lag = 0, a = exp(-1 / (fs * 0.02));
	size_t k = 0;

	gsl_rng_set(r, 1008);
	fprintf(f, "# sensorscope sample: single-axis rate-table run (simulated, seed 1008)\n"
		   "time [s],rate_cmd [deg/s],gx [deg/s],gy [deg/s],gz [deg/s]\n");
	for (int s = -6; s <= 6; s++) {
		double cmd = 50.0 * s;

		for (size_t i = 0; i < (size_t)(tstep * fs); i++, k++) {
			double w, y[3];

			lag = a * lag + (1 - a) * cmd;
			w = lag;
			y[0] = 0.21 + 1.0085 * w - 4e-7 * w * w * w;
			y[1] = -0.12 + 0.0042 * w;
			y[2] = 0.08 - 0.0031 * w;
			fprintf(f, "%.2f,%.1f", (double)k / fs, cmd);
			for (int c = 0; c < 3; c++)
				fprintf(f, ",%.5f", y[c] + 0.05 * gsl_ran_gaussian_ziggurat(r, 1));
			fputc('\n', f);
		}
	}
	fclose(f);
	gsl_rng_free(r);
}

/*
 * inclino-cal.csv / inclino-val.csv: 3-axis accelerometer inclinometer at
 * known tilts, 10 Hz, 2 s (20 samples) per pose, white noise 1 mg per
 * sample, temperature reading noise 0.05 degC.  Error model raw = b(T) +
 * s(T) t + m t: offsets 3 / -2 / 1.5 mg at 20 degC drifting 0.1 / -0.1 /
 * 0.1 mg/degC plus 0.001 mg/degC^2, scales 1 + 0.5 % / 1 - 0.5 % / 1 +
 * 0.25 % times (T + 20) / 80, cross-coupling +-0.5 mrad.  cal: nodes -20,
 * 0, 20, 40, 60 degC, roll and pitch on -60:30:60 deg (125 poses, seed
 * 1010); val: -10, 10, 30, 50 degC, 10 uniform random poses within +-60
 * deg each (seed 1011).
 */
static void inclino_model(double T, const double t[3], double raw[3])
{
	static const double o20[3] = { 3, -2, 1.5 }, k[3] = { 0.1, -0.1, 0.1 };
	double sc[3] = { 1 + 0.005 * (T + 20) / 80, 1 - 0.005 * (T + 20) / 80,
			 1 + 0.0025 * (T + 20) / 80 };

	for (int a = 0; a < 3; a++) {
		double dT = T - 20;

		raw[a] = (o20[a] + k[a] * dT + 0.001 * dT * dT) * 1e-3 * SSCOPE_CALIB_GRAVITY_STD +
			 sc[a] * t[a];
		for (int b = 0; b < 3; b++)
			if (a != b)
				raw[a] += 5e-4 * (a < b ? 1 : -1) * t[b];
	}
}

static void inclino_pose(FILE *f, gsl_rng *r, double *time, double T,
			 double roll, double pitch)
{
	double g = SSCOPE_CALIB_GRAVITY_STD, t[3], raw[3];

	t[0] = -g * sin(pitch * D2R);
	t[1] = g * sin(roll * D2R) * cos(pitch * D2R);
	t[2] = g * cos(roll * D2R) * cos(pitch * D2R);
	inclino_model(T, t, raw);
	for (int i = 0; i < 20; i++) {
		fprintf(f, "%.1f", *time);
		for (int a = 0; a < 3; a++)
			fprintf(f, ",%.6f", (raw[a] + gsl_ran_gaussian_ziggurat(r, 1e-3 * g)) / g);
		fprintf(f, ",%.2f,%.4f,%.4f\n", T + gsl_ran_gaussian_ziggurat(r, 0.05), roll, pitch);
		*time += 0.1;
	}
}

static void inclino(const char *dir)
{
	static const double nodes[5] = { -20, 0, 20, 40, 60 }, vt[4] = { -10, 10, 30, 50 };
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	FILE *f = open_out(dir, "inclino-cal.csv");
	double time = 0;

	gsl_rng_set(r, 1010);
	fprintf(f, "# sensorscope sample: inclinometer calibration poses at 5 temperatures (seed 1010; samples/README.md)\n"
		   "time [s],ax [g],ay [g],az [g],temp [degC],roll_ref [deg],pitch_ref [deg]\n");
	for (int n = 0; n < 5; n++)
		for (int i = 0; i < 5; i++)
			for (int j = 0; j < 5; j++)
				inclino_pose(f, r, &time, nodes[n], -60 + 30 * i, -60 + 30 * j);
	fclose(f);
	f = open_out(dir, "inclino-val.csv");
	time = 0;
	gsl_rng_set(r, 1011);
	fprintf(f, "# sensorscope sample: inclinometer validation poses between the nodes (seed 1011; samples/README.md)\n"
		   "time [s],ax [g],ay [g],az [g],temp [degC],roll_ref [deg],pitch_ref [deg]\n");
	for (int n = 0; n < 4; n++)
		for (int i = 0; i < 10; i++) {
			double roll = round(gsl_ran_flat(r, -60, 60) * 100) / 100;
			double pitch = round(gsl_ran_flat(r, -60, 60) * 100) / 100;

			inclino_pose(f, r, &time, vt[n], roll, pitch);
		}
	fclose(f);
	gsl_rng_free(r);
}

/*
 * drive-stops.csv: a car's vertical gyro and accelerometers on a 20-min
 * drive with stops (tests/drive-sim.h, seed 1012, latitude 48 deg), 10 Hz:
 * still for the first 60 s, then 30 s stops every 180 s of driving;
 * the gyro bias follows the warming engine bay (20 -> 45 degC), so the
 * heading drifts unless the bias is re-estimated at the stops; the true
 * heading is in heading_ref.
 */
static void drive_stops(const char *dir)
{
	struct drive d;
	FILE *f = open_out(dir, "drive-stops.csv");

	if (drive_simulate(&d, 10, 1200, 1012, 48 * D2R)) {
		fprintf(stderr, "gen-samples: drive simulation failed\n");
		exit(1);
	}
	fprintf(f, "# sensorscope sample: vertical gyro on a drive with stops (simulated by sensorscope, seed 1012; samples/README.md)\n"
		   "# rate: 10 Hz\n"
		   "gz [deg/s],ax [m/s^2],ay [m/s^2],az [m/s^2],temp [degC],heading_ref [deg]\n");
	for (size_t i = 0; i < d.n; i++) {
		double h = fmod(d.heading[i] / D2R, 360);

		fprintf(f, "%.5f,%.3f,%.3f,%.3f,%.2f,%.4f\n", d.gz[i] / D2R, d.acc[0][i],
			d.acc[1][i], d.acc[2][i], d.temp[i], h < 0 ? h + 360 : h);
	}
	fclose(f);
	drive_free(&d);
}

/*
 * drive-trajectory.csv: true motion of a 10-min drive for `navsim
 * --trajectory`, 1 Hz rows (the simulator interpolates them by cubic
 * splines): speed up to 15 m/s in 20 s, six turns (raised-cosine yaw-rate
 * pulses of +-6 to 12 deg/s over 10 s) with the body banking into them
 * (roll 0.5 v r / g), slowing to a stop over the last 20 s; flat (down 0).
 * Deterministic, no random numbers.
 */
static void drive_trajectory(const char *dir)
{
	const double fs = 100, T = 600, g = 9.80665;
	const double turn_t[6] = { 60, 140, 230, 320, 410, 500 };
	const double turn_r[6] = { 8, -12, 6, 10, -9, -6 };
	FILE *f = open_out(dir, "drive-trajectory.csv");
	double n = 0, e = 0, yaw = 20 * D2R;

	fprintf(f, "# sensorscope sample: true motion of a 10-min drive, tangent plane of the start (samples/README.md)\n"
		   "time [s],north [m],east [m],down [m],roll [deg],pitch [deg],yaw [deg]\n");
	for (size_t i = 0; i <= (size_t)(T * fs); i++) {
		double t = (double)i / fs, v, r = 0;

		v = t < 20 ? 15 * 0.5 * (1 - cos(PI * t / 20)) :
		    t > T - 20 ? 15 * 0.5 * (1 + cos(PI * (t - T + 20) / 20)) : 15;
		for (int k = 0; k < 6; k++)
			if (t >= turn_t[k] && t < turn_t[k] + 10)
				r = turn_r[k] * D2R * 0.5 * (1 - cos(2 * PI * (t - turn_t[k]) / 10));
		if (i % (size_t)fs == 0)
			fprintf(f, "%.0f,%.4f,%.4f,0,%.5f,0,%.5f\n", t, n, e,
				0.5 * v * r / g / D2R, yaw / D2R);
		n += v * cos(yaw) / fs;
		e += v * sin(yaw) / fs;
		yaw += r / fs;
	}
	fclose(f);
}

/*
 * walk-stops.csv: a person walking with stops, 6-axis IMU at 50 Hz for
 * 285 s (tests/zupt-sim.h: navsim's trajectory and sensor models, seed
 * 1013, run 0): still 5 s, then eight 30-s legs at up to 1.4 m/s, each
 * turning by 90 deg with a +-5 deg weave, a 3 cm bob and a 3 deg sway, and
 * a 5-s stop after each; latitude 48 deg, initial heading 30 deg; gyro N
 * 0.2 deg/sqrt(h), accelerometer N 0.05 m/s/sqrt(h), turn-on biases drawn
 * with 1-sigma 0.2 deg/s and 5 mg (their values are in samples/README.md).
 */
static void walk_stops(const char *dir)
{
	struct zsim_route r = { .stop_s = 5, .leg_s = 30, .ramp_s = 1,
				.speed_m_s = 1.4, .turn_rad = 90 * D2R, .legs = 8,
				.walk = true, .lat_rad = 48 * D2R,
				.heading_rad = 30 * D2R };
	struct sscope_navsim_imu imu = { 0 };
	struct zsim z;
	FILE *f = open_out(dir, "walk-stops.csv");

	zsim_imu(&imu);
	if (zsim_build(&z, &r, 50, 1, &imu, 1013, 0)) {
		fprintf(stderr, "gen-samples: walk simulation failed\n");
		exit(1);
	}
	fprintf(f, "# sensorscope sample: 6-axis IMU of a walk with stops (simulated by sensorscope, seed 1013; samples/README.md)\n"
		   "# biases: gyro %.5f %.5f %.5f deg/s, accelerometer %.5f %.5f %.5f m/s^2\n"
		   "time [s],gx [deg/s],gy [deg/s],gz [deg/s],ax [m/s^2],ay [m/s^2],az [m/s^2]\n",
		z.bias[0] / D2R, z.bias[1] / D2R, z.bias[2] / D2R, z.bias[3], z.bias[4], z.bias[5]);
	for (size_t i = 0; i < z.n; i++) {
		const double *u = z.imu + 6 * i;

		fprintf(f, "%.2f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f\n", (double)i / 50, u[0] / D2R,
			u[1] / D2R, u[2] / D2R, u[3], u[4], u[5]);
	}
	fclose(f);
	zsim_free(&z);
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
	accel_sixpos(dir);
	imu_multipose(dir);
	gyro_ratetable(dir);
	inclino(dir);
	drive_stops(dir);
	drive_trajectory(dir);
	walk_stops(dir);
	return 0;
}
