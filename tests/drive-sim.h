/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * A simulated drive with stops for the heading tests and the bundled
 * sample (shared by tests/test-heading.c and tests/gen-samples.c).
 *
 * The vehicle waits 60 s, then drives and stops for 30 s every 180 s of
 * driving.  While driving it turns (raised-cosine yaw-rate pulses of 4 to
 * 10 s, up to 25 deg/s, at random times) and the accelerometers see
 * vibration (0.4 m/s^2 rms per axis); at rest only their noise
 * (0.02 m/s^2 rms).  The vertical gyro (axis down) reads the yaw rate
 * plus the vertical Earth rate at the latitude, a bias that follows the
 * temperature of a warming engine bay (20 degC rising to 45 degC with a
 * 400 s time constant; 0.05 deg/s at 20 degC, 0.002 deg/s per degC) and
 * noise from the library's simulator (N 0.3 deg/sqrt(h), B 5 deg/h).
 * GSL MT19937 with the given seed for the motion and the accelerometers,
 * the simulator's stream 0 of the same seed for the gyro.
 */
#ifndef SSCOPE_DRIVE_SIM_H
#define SSCOPE_DRIVE_SIM_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

struct drive {
	size_t n;
	double fs;
	double *gz;      /* rad/s, axis down */
	double *acc[3];  /* m/s^2 */
	double *temp;    /* degC */
	double *heading; /* true heading, rad (unwrapped) */
	unsigned char *moving;
};

static void drive_free(struct drive *d)
{
	free(d->gz);
	for (int i = 0; i < 3; i++)
		free(d->acc[i]);
	free(d->temp);
	free(d->heading);
	free(d->moving);
	memset(d, 0, sizeof(*d));
}

static int drive_simulate(struct drive *d, double fs, double secs,
			  unsigned long seed, double lat_rad)
{
	const double pi = 3.14159265358979323846, d2r = pi / 180;
	size_t n = (size_t)(fs * secs);
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	struct sscope_sensor_spec sp = { 0 };
	struct sscope_sim_opts so = { 0 };
	struct sscope_sim *sim = NULL;
	double *w;
	int rc;

	memset(d, 0, sizeof(*d));
	d->n = n;
	d->fs = fs;
	d->gz = calloc(n, sizeof(double));
	d->temp = calloc(n, sizeof(double));
	d->heading = calloc(n, sizeof(double));
	d->moving = calloc(n, 1);
	w = calloc(n, sizeof(double));
	for (int i = 0; i < 3; i++)
		d->acc[i] = calloc(n, sizeof(double));
	if (!r || !d->gz || !d->temp || !d->heading || !d->moving || !w ||
	    !d->acc[0] || !d->acc[1] || !d->acc[2]) {
		free(w);
		gsl_rng_free(r);
		drive_free(d);
		return -ENOMEM;
	}
	gsl_rng_set(r, seed);
	/* schedule: still 60 s, then 180 s driving / 30 s still */
	for (size_t i = 0; i < n; i++) {
		double t = (double)i / fs;

		d->moving[i] = t >= 60 && fmod(t - 60, 210) < 180;
	}
	/* turns: raised-cosine pulses placed while moving */
	for (size_t i = 0; i < n;) {
		double len = gsl_ran_flat(r, 4, 10), amp = gsl_ran_flat(r, -25, 25);
		size_t m = (size_t)(len * fs), gap = (size_t)(gsl_ran_flat(r, 3, 20) * fs);
		bool ok = i + m < n;

		for (size_t k = 0; ok && k < m; k++)
			ok = d->moving[i + k];
		for (size_t k = 0; ok && k < m; k++)
			w[i + k] = amp * d2r * 0.5 * (1 - cos(2 * pi * (double)k / (double)m));
		i += ok ? m + gap : 1;
	}
	d->heading[0] = 0.3;
	for (size_t i = 1; i < n; i++)
		d->heading[i] = d->heading[i - 1] + w[i] / fs;
	for (size_t i = 0; i < n; i++) {
		double t = (double)i / fs;

		d->temp[i] = 20 + 25 * (1 - exp(-t / 400));
		for (int a = 0; a < 3; a++)
			d->acc[a][i] = gsl_ran_gaussian_ziggurat(r, d->moving[i] ? 0.4 : 0.02);
		d->acc[2][i] -= 9.80665;
	}
	sp.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	sp.n = 0.3 * d2r / 60;
	sp.b = 5 * d2r / 3600;
	sp.bias = 0.05 * d2r - 7.292115e-5 * sin(lat_rad);
	sp.bias_tempco = 0.002 * d2r;
	so.rate_hz = fs;
	so.seed = seed;
	so.temp_profile = SSCOPE_SIM_TEMP_GIVEN;
	so.ref_temp_degc = 20;
	rc = sscope_sim_new(&sim, &sp, &so, NULL);
	if (!rc)
		rc = sscope_sim_generate(sim, w, d->gz, d->temp, n);
	sscope_sim_free(sim);
	free(w);
	gsl_rng_free(r);
	if (rc)
		drive_free(d);
	return rc;
}

#endif
