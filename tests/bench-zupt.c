/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark of the zero-velocity-aided navigation (analysis/zupt.c) on
 * captures simulated by navsim's trajectory and sensor models
 * (tests/zupt-sim.h), 100 runs each of a vehicle (10 min, 11 legs of 40 s
 * at up to 10 m/s, 15-s stops) and a walk (10.5 min, 18 legs of 30 s at up
 * to 1.4 m/s, 5-s stops), turn-on biases drawn per run from the prior the
 * filter is given; and both again with biases that drift with the
 * temperature of a warm-up (T rises 15 degC as 1 - exp(-t / 300 s), each
 * axis's coefficient drawn per run: gyro sd 18 deg/h/degC, accelerometer
 * sd 0.2 mg/degC), the filter's rate random walk K set so that over one
 * leg and stop it matches the sd of the drift at the fastest warming (the
 * truth at a stop: the bias at its last update):
 * - coverage: the share of (stop, axis) bias estimates within 2 sigma of
 *   the truth, per axis and over all (target 95 %);
 * - the horizontal error at the end with the stop updates and without them
 *   (median, 95th percentile, the smallest ratio; target >= 10);
 * - the filter's time per sample.
 * Exit status 1 when the error ratio misses its target; the coverage is
 * reported against its target.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "zupt-sim.h"

#define D2R (3.14159265358979323846 / 180)
#define RUNS 100

static int cmp(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return (x > y) - (x < y);
}

static double now(void)
{
	struct timespec t;

	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* warm-up profile: degC above the start at t */
#define WARM_DEGC 15.0
#define WARM_TAU_S 300.0
static double warm(double t)
{
	return WARM_DEGC * (1 - exp(-t / WARM_TAU_S));
}

/* a standard normal from a 64-bit state (xorshift, Box-Muller) */
static double gauss(uint64_t *s)
{
	double u[2];

	for (int i = 0; i < 2; i++) {
		*s ^= *s << 13;
		*s ^= *s >> 7;
		*s ^= *s << 17;
		u[i] = ((double)(*s >> 11) + 0.5) * 0x1p-53;
	}
	return sqrt(-2 * log(u[0])) * cos(2 * 3.14159265358979323846 * u[1]);
}

static int bench(const char *name, const struct zsim_route *r, bool thermal)
{
	/* temperature coefficients' sd: gyro rad/s per degC, accel m/s^2 per degC */
	const double csd[2] = { 18.0 / 3600 * D2R, 0.2e-3 * 9.80665 };
	struct sscope_navsim_imu imu = { 0 };
	size_t in[6] = { 0 }, total = 0, samples = 0;
	double e1[RUNS], e0[RUNS], ratio = 1e300, secs = 0;
	static const char *const comp[6] = { "gx", "gy", "gz", "ax", "ay", "az" };

	zsim_imu(&imu);
	for (uint64_t run = 0; run < RUNS; run++) {
		struct zsim z;
		struct sscope_zupt_opts o;
		struct sscope_zupt_result *res = NULL, *raw = NULL;
		const double *g[3], *a[3];
		double t0, c[6] = { 0 };

		if (zsim_build(&z, r, 100, 1, &imu, 2024, run)) {
			fprintf(stderr, "bench-zupt: simulation failed\n");
			return 1;
		}
		zsim_opts(&o, &z, r, &imu, 1);
		if (thermal) {
			uint64_t st = 0x9e3779b97f4a7c15ull ^ (run + 1) * 0xbf58476d1ce4e5b9ull;
			double gap = r->leg_s + r->stop_s;

			for (int i = 0; i < 6; i++)
				c[i] = csd[i / 3] * gauss(&st);
			for (size_t k = 0; k < z.n; k++)
				for (int i = 0; i < 6; i++)
					z.imu[k * 6 + i] += c[i] * warm((double)k / z.fs);
			/* K: the drift's sd over a leg and stop at the fastest
			 * warming (t = 0) */
			o.gyro_k = csd[0] * WARM_DEGC / WARM_TAU_S * sqrt(gap);
			o.accel_k = csd[1] * WARM_DEGC / WARM_TAU_S * sqrt(gap);
		}
		for (int i = 0; i < 3; i++) {
			g[i] = z.imu + i;
			a[i] = z.imu + 3 + i;
		}
		t0 = now();
		if (sscope_zupt_run(g, a, 6, z.n, &o, &res, NULL)) {
			fprintf(stderr, "bench-zupt: navigation failed\n");
			return 1;
		}
		secs += now() - t0;
		samples += z.n;
		o.no_zupt = true;
		if (sscope_zupt_run(g, a, 6, z.n, &o, &raw, NULL)) {
			fprintf(stderr, "bench-zupt: navigation failed\n");
			return 1;
		}
		for (size_t s = 0; s < res->n_stops; s++) {
			const struct sscope_zupt_stop *sp = &res->stops[s];

			double dT = warm(sp->t_end_s);

			for (int i = 0; i < 3; i++) {
				in[i] += fabs(sp->gyro_bias_rad_s[i] - z.bias[i] - c[i] * dT) <=
					 2 * sp->sd_gyro_bias_rad_s[i];
				in[3 + i] += fabs(sp->accel_bias_m_s2[i] - z.bias[3 + i] -
						  c[3 + i] * dT) <=
					     2 * sp->sd_accel_bias_m_s2[i];
			}
			total++;
		}
		e1[run] = zsim_horiz_err(&z, res->rec, res->n_rec - 1);
		e0[run] = zsim_horiz_err(&z, raw->rec, raw->n_rec - 1);
		if (e0[run] / e1[run] < ratio)
			ratio = e0[run] / e1[run];
		sscope_zupt_result_free(res);
		sscope_zupt_result_free(raw);
		zsim_free(&z);
	}
	qsort(e1, RUNS, sizeof(double), cmp);
	qsort(e0, RUNS, sizeof(double), cmp);
	{
		size_t all = 0;

		printf("%s: %d runs, %zu stops; bias within 2 sigma (target 95 %%):", name, RUNS, total);
		for (int i = 0; i < 6; i++) {
			printf(" %s %.1f %%", comp[i], 100.0 * (double)in[i] / (double)total);
			all += in[i];
		}
		printf("; all %.1f %% (%s)\n", 100.0 * (double)all / (6.0 * (double)total),
		       (double)all >= 0.95 * 6.0 * (double)total ? "met" : "NOT met");
	}
	printf("%s: horizontal error at the end, with stop updates median %.3g m, p95 %.3g m; without median %.3g m; smallest ratio %.3g (target 10)\n",
	       name, e1[RUNS / 2], e1[RUNS * 95 / 100], e0[RUNS / 2], ratio);
	printf("%s: filter %.0f ns per sample (%zu samples)\n", name, 1e9 * secs / (double)samples,
	       samples);
	return ratio >= 10 ? 0 : 1;
}

/* an hour of a walk with stops at 200 Hz, as the CSV the nav command
 * reads (tests/bench-nav.sh times the whole command on it) */
static int write_hour(const char *path)
{
	const struct zsim_route r = {
		.stop_s = 5, .leg_s = 30, .ramp_s = 1, .speed_m_s = 1.4,
		.turn_rad = 90 * D2R, .legs = 103, .walk = true, .lat_rad = 0.8,
		.heading_rad = 0.3
	};
	struct sscope_navsim_imu imu = { 0 };
	struct zsim z;
	FILE *f = fopen(path, "w");

	zsim_imu(&imu);
	if (!f || zsim_build(&z, &r, 200, 1, &imu, 7, 0)) {
		fprintf(stderr, "bench-zupt: %s: cannot write the hour\n", path);
		return 1;
	}
	fprintf(f, "time [s],gx [rad/s],gy [rad/s],gz [rad/s],ax [m/s^2],ay [m/s^2],az [m/s^2]\n");
	for (size_t i = 0; i < z.n; i++) {
		const double *u = z.imu + 6 * i;

		fprintf(f, "%.3f,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e\n", (double)i / 200, u[0], u[1],
			u[2], u[3], u[4], u[5]);
	}
	zsim_free(&z);
	return fclose(f) ? 1 : 0;
}

int main(int argc, char **argv)
{
	const struct zsim_route vehicle = {
		.stop_s = 15, .leg_s = 40, .ramp_s = 4, .speed_m_s = 10,
		.turn_rad = 90 * D2R, .legs = 11, .lat_rad = 0.8, .heading_rad = 0.3
	};
	const struct zsim_route walk = {
		.stop_s = 5, .leg_s = 30, .ramp_s = 1, .speed_m_s = 1.4,
		.turn_rad = 90 * D2R, .legs = 18, .walk = true, .lat_rad = 0.8,
		.heading_rad = 0.3
	};
	int rc;

	if (argc == 3 && !strcmp(argv[1], "--hour"))
		return write_hour(argv[2]);
	rc = bench("vehicle", &vehicle, false);

	rc |= bench("walk", &walk, false);
	rc |= bench("vehicle, bias drifting with temperature", &vehicle, true);
	return bench("walk, bias drifting with temperature", &walk, true) | rc;
}
