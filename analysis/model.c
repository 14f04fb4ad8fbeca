/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Sensor physics calculators (textbook section 5.1).
 *
 * Second-order accelerometer: the mass-spring-damper of any textbook on
 * vibration (e.g. W. T. Thomson, "Theory of Vibration with Applications",
 * ch. 2-4): w_n = sqrt(k/m), zeta = c / (2 sqrt(k m)); |H(r)|^2 =
 * 1 / ((1 - r^2)^2 + (2 zeta r)^2) with r = w / w_n, so the -3 dB point is
 * r^2 = 1 - 2 zeta^2 + sqrt((1 - 2 zeta^2)^2 + 1); the resonance peak
 * 1 / (2 zeta sqrt(1 - zeta^2)) for zeta < 1/sqrt 2; step overshoot
 * exp(-pi zeta / sqrt(1 - zeta^2)).  Rise and settling times are found on
 * the analytic step response.
 *
 * Fibre-optic gyro: Sagnac phase dphi = 2 pi L D Omega / (lambda c)
 * = 8 pi^2 N R^2 Omega / (lambda c) (H. C. Lefevre, "The Fiber-Optic
 * Gyroscope", Artech House, ch. 2).
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>

#include "sscope-model.h"
#include "sscope-unit.h"


static double step_unit(const struct sscope_model_accel *m, double t)
{
	double w = m->omega_n_rad_s, z = m->zeta;

	if (!(t > 0))
		return 0;
	if (fabs(z - 1) < 1e-9) {
		return 1 - exp(-w * t) * (1 + w * t);
	} else if (z < 1) {
		double wd = w * sqrt(1 - z * z);

		return 1 - exp(-z * w * t) *
				   (cos(wd * t) + z / sqrt(1 - z * z) * sin(wd * t));
	} else {
		double q = sqrt(z * z - 1), s1 = -w * (z - q), s2 = -w * (z + q);

		return 1 + (s2 * exp(s1 * t) - s1 * exp(s2 * t)) / (s1 - s2);
	}
}

static void finish(struct sscope_model_accel *o)
{
	double w = o->omega_n_rad_s, z = o->zeta, u, tmax, t10 = NAN, t90 = NAN;
	double a = 1 - 2 * z * z;
	const size_t nscan = 200000;

	o->fn_hz = w / (2 * PI);
	o->q_factor = 1 / (2 * z);
	o->fd_hz = z < 1 ? o->fn_hz * sqrt(1 - z * z) : (double)NAN;
	u = a + sqrt(a * a + 1);
	o->bandwidth_hz = o->fn_hz * sqrt(u);
	o->peak_gain = z < sqrt(0.5) ? 1 / (2 * z * sqrt(1 - z * z)) : 1;
	o->displacement_per_g_m = SSCOPE_UNIT_GRAVITY_STD / (w * w);
	o->overshoot = z < 1 ? exp(-PI * z / sqrt(1 - z * z)) : 0;
	/* scan the analytic response: the slowest mode decays with
	 * exp(-w (z - sqrt(z^2 - 1)) t) (or exp(-z w t)) */
	{
		double decay = z < 1 ? z * w : w * (z - sqrt(z * z - 1));

		tmax = 20 / decay + 10 / w;
	}
	o->settling_time_s = 0;
	for (size_t i = 1; i <= nscan; i++) {
		double t = tmax * (double)i / (double)nscan;
		double y = step_unit(o, t);

		if (isnan(t10) && y >= 0.1)
			t10 = t;
		if (isnan(t90) && y >= 0.9)
			t90 = t;
		if (fabs(y - 1) > 0.02)
			o->settling_time_s = t;
	}
	o->rise_time_s = t90 - t10;
}

int sscope_model_accel_mkc(double mass_kg, double stiffness_n_m,
			   double damping_n_s_m, struct sscope_model_accel *o)
{
	if (!o || !(mass_kg > 0) || !(stiffness_n_m > 0) ||
	    !(damping_n_s_m > 0) || !isfinite(mass_kg) ||
	    !isfinite(stiffness_n_m) || !isfinite(damping_n_s_m))
		return -EINVAL;
	o->mass_kg = mass_kg;
	o->stiffness_n_m = stiffness_n_m;
	o->damping_n_s_m = damping_n_s_m;
	o->omega_n_rad_s = sqrt(stiffness_n_m / mass_kg);
	o->zeta = damping_n_s_m / (2 * sqrt(stiffness_n_m * mass_kg));
	finish(o);
	return 0;
}

int sscope_model_accel_fn(double fn_hz, double zeta,
			  struct sscope_model_accel *o)
{
	if (!o || !(fn_hz > 0) || !(zeta > 0) || !isfinite(fn_hz) ||
	    !isfinite(zeta))
		return -EINVAL;
	o->mass_kg = o->stiffness_n_m = o->damping_n_s_m = NAN;
	o->omega_n_rad_s = 2 * PI * fn_hz;
	o->zeta = zeta;
	finish(o);
	return 0;
}

int sscope_model_accel_step(const struct sscope_model_accel *m, double a_m_s2,
			    const double *t_s, size_t n, double *x_m)
{
	if (!m || (n && (!t_s || !x_m)) || !isfinite(a_m_s2) ||
	    !(m->omega_n_rad_s > 0) || !(m->zeta > 0))
		return -EINVAL;
	for (size_t i = 0; i < n; i++)
		x_m[i] = a_m_s2 / (m->omega_n_rad_s * m->omega_n_rad_s) *
			 step_unit(m, t_s[i]);
	return 0;
}

int sscope_model_accel_step_rk4(const struct sscope_model_accel *m,
				double a_m_s2, double dt_s, size_t n,
				double *x_m)
{
	double x = 0, v = 0, w2, c;

	if (!m || (n && !x_m) || !(dt_s > 0) || !isfinite(a_m_s2) ||
	    !(m->omega_n_rad_s > 0) || !(m->zeta > 0))
		return -EINVAL;
	w2 = m->omega_n_rad_s * m->omega_n_rad_s;
	c = 2 * m->zeta * m->omega_n_rad_s;
	for (size_t i = 0; i < n; i++) {
		double k1x, k1v, k2x, k2v, k3x, k3v, k4x, k4v;

		x_m[i] = x;
		k1x = v;
		k1v = a_m_s2 - c * v - w2 * x;
		k2x = v + 0.5 * dt_s * k1v;
		k2v = a_m_s2 - c * k2x - w2 * (x + 0.5 * dt_s * k1x);
		k3x = v + 0.5 * dt_s * k2v;
		k3v = a_m_s2 - c * k3x - w2 * (x + 0.5 * dt_s * k2x);
		k4x = v + dt_s * k3v;
		k4v = a_m_s2 - c * k4x - w2 * (x + dt_s * k3x);
		x += dt_s / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
		v += dt_s / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
	}
	return 0;
}

int sscope_model_fog_coil(double radius_m, double turns, double wavelength_m,
			  struct sscope_model_fog *o)
{
	if (!o || !(radius_m > 0) || !(turns > 0) || !(wavelength_m > 0) ||
	    !isfinite(radius_m) || !isfinite(turns) || !isfinite(wavelength_m))
		return -EINVAL;
	o->radius_m = radius_m;
	o->turns = turns;
	o->wavelength_m = wavelength_m;
	o->fibre_length_m = 2 * PI * radius_m * turns;
	o->scale_factor_s = 8 * PI * PI * turns * radius_m * radius_m /
			    (wavelength_m * SSCOPE_MODEL_SPEED_OF_LIGHT);
	o->max_rate_rad_s = (PI / 2) / o->scale_factor_s;
	return 0;
}

double sscope_model_fog_phase(const struct sscope_model_fog *f,
			      double rate_rad_s)
{
	return f->scale_factor_s * rate_rad_s;
}

int sscope_model_accel_rk4_check(const struct sscope_model_accel *m,
				 double a_m_s2, double t_end_s,
				 size_t max_steps, double **x_m,
				 struct sscope_model_rk4_check *chk)
{
	double dt, *xr, maxdev = 0;
	size_t nr;

	if (x_m)
		*x_m = NULL;
	if (!m || !chk || !(t_end_s > 0) || !isfinite(t_end_s) || max_steps < 3 ||
	    !(m->fn_hz > 0))
		return -EINVAL;
	dt = 1 / (m->fn_hz * 400);
	if (ceil(t_end_s / dt) + 2 > (double)max_steps) {
		nr = max_steps;
		dt = t_end_s / (double)(nr - 2);
	} else {
		nr = ssc_count(ceil(t_end_s / dt)) + 2;
	}
	xr = malloc(nr * sizeof(double));
	if (!xr)
		return -ENOMEM;
	sscope_model_accel_step_rk4(m, a_m_s2, dt, nr, xr);
	/* compare where the grids meet: analytic at k dt */
	for (size_t k = 0; k < nr; k += 1 + nr / 5000) {
		double tk = (double)k * dt, xk;

		sscope_model_accel_step(m, a_m_s2, &tk, 1, &xk);
		maxdev = fmax(maxdev, fabs(xk - xr[k]));
	}
	chk->dt_s = dt;
	chk->n = nr;
	chk->max_dev_m = maxdev;
	if (x_m)
		*x_m = xr;
	else
		free(xr);
	return 0;
}
