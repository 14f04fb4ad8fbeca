/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Unit tests of analysis/heading.c and analysis/walk.c:
 * - the drift variance: closed forms for white noise and rate random
 *   walk, the Allan identity var(tau = T) = 2 tau^2 AVAR(tau) for each of
 *   Q, N, B, K, R, and a Monte-Carlo check against the library's
 *   simulator for flicker (B), where only the combination is finite;
 * - heading on a simulated drive with stops and a bias drifting with
 *   temperature: stops found, error with re-estimation several times
 *   smaller than with the first bias alone, the envelope holding the
 *   error, Earth rate removed from the stop biases;
 * - the random-walk fan: 95.4 +- 3 % of runs inside +-2 sigma, the implied
 *   N's interval covering the truth, the bias window's inflation;
 * - refused input.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>

#include "check-main.h"
#include "drive-sim.h"

#define PI 3.14159265358979323846
#define D2R (PI / 180)

START_TEST(test_drift_var_closed_forms)
{
	double c[5] = { 0 }, N = 2.3e-4, K = 3.1e-6, tau = 37.5, T = 12.25;

	c[SSCOPE_TERM_N] = N;
	ck_assert_rel(sscope_heading_drift_var(c, tau, T), N * N * (tau + tau * tau / T), 1e-13);
	c[SSCOPE_TERM_N] = 0;
	c[SSCOPE_TERM_K] = K;
	ck_assert_rel(sscope_heading_drift_var(c, tau, T),
		      K * K * (tau * tau * tau + tau * tau * T) / 3, 1e-12);
	/* the Allan identity, term by term and all together */
	for (int term = 0; term <= 5; term++) {
		double cc[5] = { 0 }, all[5] = { 1.1e-5, 2.3e-4, 4.7e-5, 3.1e-6, 2.9e-8 };

		for (int i = 0; i < 5; i++)
			cc[i] = term == 5 || i == term ? all[i] : 0;
		for (double t = 0.01; t < 1e4; t *= 7.3)
			ck_assert_rel(sscope_heading_drift_var(cc, t, t),
				      2 * t * t * sscope_noise_avar(cc, t), 1e-12);
	}
	/* flicker is scale-free: var(a tau, a T) = a^2 var(tau, T) */
	c[SSCOPE_TERM_K] = 0;
	c[SSCOPE_TERM_B] = 4.7e-5;
	ck_assert_rel(sscope_heading_drift_var(c, 10 * tau, 10 * T),
		      100 * sscope_heading_drift_var(c, tau, T), 1e-12);
	/* more averaging helps, longer integration hurts */
	ck_assert(sscope_heading_drift_var(c, tau, 2 * T) < sscope_heading_drift_var(c, tau, T));
	ck_assert(sscope_heading_drift_var(c, 2 * tau, T) > sscope_heading_drift_var(c, tau, T));
	ck_assert(sscope_heading_drift_var(c, 0, T) == 0);
	ck_assert(isnan(sscope_heading_drift_var(c, -1, T)));
	ck_assert(isnan(sscope_heading_drift_var(c, 1, 0)));
	c[0] = -1;
	ck_assert(isnan(sscope_heading_drift_var(c, 1, 1)));
}
END_TEST

START_TEST(test_drift_var_flicker_mc)
{
	/* e = int_0^tau x - (tau / T) int_-T^0 x over independent streams of
	 * the library's flicker-only simulation */
	struct sscope_sensor_spec sp = { 0 };
	struct sscope_sim_opts so = { 0 };
	const double fs = 10, tau = 60, T = 20, B = 1e-4;
	const size_t nt = (size_t)(tau * fs), nT = (size_t)(T * fs), M = 3000;
	double *x = malloc((nt + nT) * sizeof(double)), ss = 0, c[5] = { 0 }, v, lo, hi;

	sp.b = B;
	so.rate_hz = fs;
	so.seed = 19101;
	for (size_t m = 0; m < M; m++) {
		struct sscope_sim *sim;
		double a = 0, b = 0, e;

		so.stream = m;
		ck_assert_int_eq(sscope_sim_new(&sim, &sp, &so, NULL), 0);
		sscope_sim_generate(sim, NULL, x, NULL, nT + nt);
		sscope_sim_free(sim);
		for (size_t i = 0; i < nT; i++)
			b += x[i] / fs;
		for (size_t i = nT; i < nT + nt; i++)
			a += x[i] / fs;
		e = a - tau / T * b;
		ss += e * e;
	}
	free(x);
	c[SSCOPE_TERM_B] = B;
	v = sscope_heading_drift_var(c, tau, T);
	/* chi-squared bounds at 1e-4 (M dof), widened by 3 % for the
	 * simulator's finite flicker band (sscope-sim.h) */
	lo = gsl_cdf_chisq_Pinv(5e-5, (double)M) / (double)M * 0.97;
	hi = gsl_cdf_chisq_Qinv(5e-5, (double)M) / (double)M * 1.03;
	ck_assert_msg(ss / (double)M / v > lo && ss / (double)M / v < hi,
		      "flicker drift: simulated / predicted = %g (bounds %g, %g)",
		      ss / (double)M / v, lo, hi);
}
END_TEST

static struct sscope_heading_result *run_heading(const struct drive *d,
						 struct sscope_heading_opts *o)
{
	struct sscope_heading_result *r = NULL;
	struct sscope_diag dg = { "" };
	const double *det[3] = { d->acc[0], d->acc[1], d->acc[2] };
	int rc = sscope_heading_compute(d->gz, 1, d->n, det, 1, o, &r, &dg);

	ck_assert_msg(rc == 0, "heading: %d %s", rc, dg.msg);
	return r;
}

START_TEST(test_heading_drive)
{
	struct drive d;
	struct sscope_heading_opts o = { 0 };
	struct sscope_heading_result *r;
	struct sscope_heading_cmp re, once;
	double lat = 48 * D2R;

	ck_assert_int_eq(drive_simulate(&d, 10, 1200, 19102, lat), 0);
	o.rate_hz = d.fs;
	o.latitude_rad = lat;
	o.initial_heading_rad = d.heading[0];
	r = run_heading(&d, &o);
	/* the schedule: 60 s still, then 30 s every 210 s: 6 stops */
	ck_assert_int_eq(r->n_stops, 6);
	for (size_t j = 0; j < r->n_stops; j++) {
		double t0 = j ? 60 + 210.0 * (double)j - 30 : 0;

		ck_assert_msg(fabs(r->stops[j].t_start_s - t0) < 1.5,
			      "stop %zu starts at %g s", j, r->stops[j].t_start_s);
		ck_assert(r->stops[j].t_end_s - r->stops[j].t_start_s > (j ? 26 : 55));
		for (size_t i = r->stops[j].start; i < r->stops[j].end; i++)
			ck_assert(!d.moving[i]);
	}
	/* the stop biases follow the temperature; with the latitude the
	 * Earth rate (-omega sin(lat) along down) is removed */
	ck_assert(r->earth_rate_rad_s < 0);
	ck_assert_rel(r->earth_rate_rad_s, -SSCOPE_NAV_WGS84_OMEGA * sin(lat), 1e-12);
	for (size_t j = 0; j < r->n_stops; j++) {
		const struct sscope_heading_stop *s = &r->stops[j];
		size_t mid = (s->start + s->end) / 2;
		double truth = 0.05 * D2R + 0.002 * D2R * (d.temp[mid] - 20);

		ck_assert_msg(fabs(s->sensor_bias_rad_s - truth) < 5 * s->bias_sd_rad_s + 2e-5,
			      "stop %zu: bias %g, truth %g (sd %g)", j,
			      s->sensor_bias_rad_s, truth, s->bias_sd_rad_s);
		ck_assert(s->bias_sd_rad_s > 0);
	}
	ck_assert(r->coef_from_stops);
	ck_assert_msg(fabs(r->coef[SSCOPE_TERM_N] / (0.3 * D2R / 60) - 1) < 0.1,
		      "N from the stops %g", r->coef[SSCOPE_TERM_N]);
	ck_assert_int_eq(sscope_heading_compare(r->heading_rad, r->sigma_rad, d.heading, 1,
						d.n, r->first, &re),
			 0);
	ck_assert_int_eq(sscope_heading_compare(r->heading_once_rad, r->sigma_once_rad,
						d.heading, 1, d.n, r->first, &once),
			 0);
	/* "several times smaller" */
	ck_assert_msg(once.rms_rad > 4 * re.rms_rad && once.max_abs_rad > 4 * re.max_abs_rad,
		      "rms error %g deg re-estimated, %g deg first bias only",
		      re.rms_rad / D2R, once.rms_rad / D2R);
	/* the heading is held during stops */
	for (size_t j = 1; j < r->n_stops; j++)
		ck_assert(r->heading_rad[r->stops[j].start] ==
			  r->heading_rad[r->stops[j].end - 1]);
	sscope_heading_result_free(r);
	/* post-processing: interpolating the bias between stops does better */
	o.bias_model = SSCOPE_HEADING_INTERPOLATE;
	r = run_heading(&d, &o);
	{
		struct sscope_heading_cmp ip;

		sscope_heading_compare(r->heading_rad, NULL, d.heading, 1, d.n, r->first, &ip);
		ck_assert_msg(ip.rms_rad < re.rms_rad, "interpolated %g deg, held %g deg",
			      ip.rms_rad / D2R, re.rms_rad / D2R);
		ck_assert(isnan(ip.inside_2sigma));
	}
	sscope_heading_result_free(r);
	drive_free(&d);
}
END_TEST

START_TEST(test_heading_envelope)
{
	/* no drift, noise terms given: the error stays inside 2 sigma
	 * about 95 % of the time, pooled over independent drives */
	double in = 0, cnt = 0;

	for (unsigned long s = 0; s < 12; s++) {
		struct drive d;
		struct sscope_heading_opts o = { 0 };
		struct sscope_heading_result *r;
		struct sscope_heading_cmp c;

		ck_assert_int_eq(drive_simulate(&d, 10, 1200, 19200 + s, 0), 0);
		/* remove the thermal drift: a constant bias */
		for (size_t i = 0; i < d.n; i++)
			d.gz[i] -= 0.002 * D2R * (d.temp[i] - 20);
		o.rate_hz = d.fs;
		o.latitude_rad = NAN;
		o.initial_heading_rad = d.heading[0];
		o.coef[SSCOPE_TERM_N] = 0.3 * D2R / 60;
		o.coef[SSCOPE_TERM_B] = 5 * D2R / 3600;
		r = run_heading(&d, &o);
		ck_assert(!r->coef_from_stops);
		ck_assert(isnan(r->stops[0].sensor_bias_rad_s));
		sscope_heading_compare(r->heading_rad, r->sigma_rad, d.heading, 1, d.n,
				       r->first, &c);
		in += c.inside_2sigma;
		cnt++;
		sscope_heading_result_free(r);
		drive_free(&d);
	}
	/* samples of one drive are correlated: a loose band around 95 % */
	ck_assert_msg(in / cnt > 0.85 && in / cnt < 0.995, "inside 2 sigma: %g", in / cnt);
}
END_TEST

START_TEST(test_heading_refused)
{
	struct drive d;
	struct sscope_heading_opts o = { 0 };
	struct sscope_heading_result *r = NULL;
	struct sscope_diag dg = { "" };
	const double *det[3];

	ck_assert_int_eq(drive_simulate(&d, 10, 300, 19103, 0), 0);
	det[0] = d.acc[0];
	det[1] = d.acc[1];
	det[2] = d.acc[2];
	o.rate_hz = 10;
	o.latitude_rad = NAN;
	/* always moving: cut off the first 60 s and stop at 230 s */
	ck_assert_int_eq(sscope_heading_compute(d.gz + 600, 1, 1700, (const double *const[3]){
							d.acc[0] + 600, d.acc[1] + 600, d.acc[2] + 600 },
						1, &o, &r, &dg),
			 -EDOM);
	ck_assert(strstr(dg.msg, "cannot tell stops from motion") != NULL);
	ck_assert_ptr_null(r);
	/* too short for the window */
	ck_assert_int_eq(sscope_heading_compute(d.gz, 1, 5, det, 1, &o, &r, &dg), -EDOM);
	/* constant detector channels */
	{
		double *z = calloc(d.n, sizeof(double));
		const double *zz[3] = { z, z, z };

		ck_assert_int_eq(sscope_heading_compute(d.gz, 1, d.n, zz, 1, &o, &r, &dg),
				 -EDOM);
		free(z);
	}
	d.gz[100] = NAN;
	ck_assert_int_eq(sscope_heading_compute(d.gz, 1, d.n, det, 1, &o, &r, &dg), -EINVAL);
	d.gz[100] = 0;
	o.latitude_rad = 2;
	ck_assert_int_eq(sscope_heading_compute(d.gz, 1, d.n, det, 1, &o, &r, &dg), -EINVAL);
	o.latitude_rad = NAN;
	o.rate_hz = 0;
	ck_assert_int_eq(sscope_heading_compute(d.gz, 1, d.n, det, 1, &o, &r, &dg), -EINVAL);
	o.rate_hz = 10;
	o.coef[1] = -1;
	ck_assert_int_eq(sscope_heading_compute(d.gz, 1, d.n, det, 1, &o, &r, &dg), -EINVAL);
	o.coef[1] = 0;
	o.init_static_s = 1000;
	ck_assert_int_eq(sscope_heading_compute(d.gz, 1, d.n, det, 1, &o, &r, &dg), -EDOM);
	/* the initial still period as the reference works as well */
	o.init_static_s = 30;
	ck_assert_int_eq(sscope_heading_compute(d.gz, 1, d.n, det, 1, &o, &r, &dg), 0);
	ck_assert(r->n_stops >= 1 && r->stops[0].start < 10);
	sscope_heading_result_free(r);
	{
		struct sscope_heading_cmp c;
		double nanv = NAN;

		ck_assert_int_eq(sscope_heading_compare(&nanv, NULL, &nanv, 1, 1, 0, &c), -EDOM);
		ck_assert_int_eq(sscope_heading_compare(NULL, NULL, &nanv, 1, 1, 0, &c), -EINVAL);
	}
	drive_free(&d);
}
END_TEST

START_TEST(test_static_reference)
{
	/* calib's detector reference, shared with heading */
	double x[200], vs[200], work[200], ref = 0;
	struct sscope_diag d = { "" };

	for (int i = 0; i < 200; i++)
		x[i] = sin(0.37 * i) * (i < 100 ? 1 : 10);
	ck_assert_int_eq(sscope_calib_variance_magnitude(x, x, x, 1, 200, 11, vs), 0);
	ck_assert_int_eq(sscope_calib_static_reference(x, x, x, 1, 200, 10, 0, vs, work,
						       &ref, &d), 0);
	ck_assert(ref > 0 && ref < 1);
	/* the first 5 s (quiet half): sqrt(3 var^2) of those samples */
	ck_assert_int_eq(sscope_calib_static_reference(x, x, x, 1, 200, 10, 5, vs, work,
						       &ref, &d), 0);
	{
		struct sscope_stats st;

		sscope_stats_compute(x, 1, 50, &st);
		ck_assert_rel(ref, sqrt(3.0) * st.sd * st.sd, 1e-14);
	}
	ck_assert_int_eq(sscope_calib_static_reference(x, x, x, 1, 200, 10, 30, vs, work,
						       &ref, &d), -EDOM);
	ck_assert_int_eq(sscope_calib_static_reference(x, x, x, 1, 200, 0, 0, vs, work,
						       &ref, &d), -EINVAL);
	ck_assert_int_eq(sscope_calib_static_reference(x, x, NULL, 1, 200, 10, 0, vs, work,
						       &ref, &d), -EINVAL);
	for (int i = 0; i < 200; i++)
		x[i] = 2.5;
	sscope_calib_variance_magnitude(x, x, x, 1, 200, 11, vs);
	ck_assert_int_eq(sscope_calib_static_reference(x, x, x, 1, 200, 10, 0, vs, work,
						       &ref, &d), -EDOM);
	for (int i = 0; i < 200; i++)
		vs[i] = INFINITY;
	ck_assert_int_eq(sscope_calib_static_reference(x, x, x, 1, 200, 10, 0, vs, work,
						       &ref, &d), -EDOM);
}
END_TEST

static double *white(size_t n, double fs, double N, double B, double K,
		     unsigned long seed)
{
	struct sscope_sensor_spec sp = { 0 };
	struct sscope_sim_opts so = { 0 };
	struct sscope_sim *sim;
	double *x = malloc(n * sizeof(double));

	sp.n = N;
	sp.b = B;
	sp.k = K;
	sp.bias = 0.0123;
	so.rate_hz = fs;
	so.seed = seed;
	ck_assert_int_eq(sscope_sim_new(&sim, &sp, &so, NULL), 0);
	sscope_sim_generate(sim, NULL, x, NULL, n);
	sscope_sim_free(sim);
	return x;
}

START_TEST(test_walk_fan)
{
	/* 10 h at 10 Hz of angle random walk: 600 runs of 50 s, each after
	 * a 10 s bias window */
	const double fs = 10, N = 0.15 * D2R / 60;
	const size_t n = 360000;
	double *x = white(n, fs, N, 0, 0, 19104);
	struct sscope_walk_opts o = { 0 };
	struct sscope_walk_result *r = NULL, *r7 = NULL;
	struct sscope_walk_implied im;
	double p = erf(sqrt(2.0));

	o.rate_hz = fs;
	o.run_s = 50;
	o.bias_s = 10;
	o.coef[SSCOPE_TERM_N] = N;
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &r, NULL), 0);
	ck_assert_int_eq(r->n_runs, 600);
	ck_assert_int_eq(r->n_points, 501);
	ck_assert(!r->global && r->est_s == 10);
	/* the textbook's figure: 95.4 % inside +-2 sigma (+-3 points) */
	ck_assert_msg(fabs(r->inside_mean - p) < 0.03, "inside %g", r->inside_mean);
	/* what a Gaussian puts inside, and its binomial sd over the runs
	 * (0.9544997361036416, sqrt(p (1 - p) / 600) = 0.0085093...) */
	ck_assert_rel(r->inside_expected, 0.9544997361036416, 1e-15);
	ck_assert_rel(r->inside_sd, sqrt(0.9544997361036416 * 0.0455002638963584 / 600),
		      1e-14);
	ck_assert_msg(fabs(r->inside[r->n_points - 1] - p) < 0.03, "inside at 50 s %g",
		      r->inside[r->n_points - 1]);
	/* the bias window inflates the spread: N^2 (t + t^2 / T) */
	ck_assert_rel(r->sigma[500], N * sqrt(50 + 2500 / 10.0), 1e-12);
	ck_assert(isnan(r->inside[0]) && r->sigma[0] == 0 && r->paths[0] == 0);
	ck_assert_int_eq(sscope_walk_implied_n(r, 500, 0.99, &im), 0);
	ck_assert_msg(im.lo < N && N < im.hi, "implied N %g [%g, %g], truth %g", im.n,
		      im.lo, im.hi, N);
	ck_assert(fabs(im.t_s - 50) < 1e-12);
	ck_assert_int_eq(r->n_paths, 600);
	/* keeping the first 7 paths: the same statistics and paths, to the
	 * bit; more than the runs keeps them all */
	o.keep_paths = 7;
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &r7, NULL), 0);
	ck_assert_int_eq(r7->n_paths, 7);
	ck_assert_int_eq(r7->n_runs, 600);
	ck_assert(!memcmp(r7->paths, r->paths, 7 * 501 * sizeof(double)));
	ck_assert(!memcmp(r7->sigma, r->sigma, 501 * sizeof(double)));
	ck_assert(!memcmp(r7->spread, r->spread, 501 * sizeof(double)));
	ck_assert(!memcmp(r7->inside + 1, r->inside + 1, 500 * sizeof(double)));
	ck_assert(!memcmp(r7->var_n1, r->var_n1, 501 * sizeof(double)));
	ck_assert(!memcmp(r7->var_other, r->var_other, 501 * sizeof(double)));
	ck_assert(r7->inside_mean == r->inside_mean);
	sscope_walk_result_free(r7);
	o.keep_paths = 601;
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &r7, NULL), 0);
	ck_assert_int_eq(r7->n_paths, 600);
	ck_assert(!memcmp(r7->paths, r->paths, 600 * 501 * sizeof(double)));
	sscope_walk_result_free(r7);
	o.keep_paths = 0;
	sscope_walk_result_free(r);
	/* the global mean: the plain N sqrt(t) fan */
	o.bias_s = 0;
	o.run_s = 60;
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &r, NULL), 0);
	ck_assert(r->global && r->n_runs == 600);
	ck_assert_msg(fabs(r->inside_mean - p) < 0.03, "global: inside %g", r->inside_mean);
	/* the run lies inside the mean's window: N^2 (t - t^2 / T) */
	ck_assert_rel(r->sigma[600], N * sqrt(60 - 3600 / 36000.0), 1e-12);
	ck_assert_int_eq(sscope_walk_implied_n(r, 600, 0, &im), 0);
	ck_assert(fabs(im.n / N - 1) < 0.05);
	ck_assert_int_eq(sscope_walk_implied_n(r, 0, 0, &im), -EINVAL);
	sscope_walk_result_free(r);
	free(x);
}
END_TEST

/*
 * The envelope from the fit's signed squares (have_sq): the predicted
 * variance is linear in the squares, so squares equal to coef^2 give the
 * same numbers as coef (to rounding), a negative square lowers the
 * others' part by exactly its share, and var_other_sd is the sd of that
 * part from the squares' covariance (here K's variance alone:
 * unit_K(t) sd(K^2), unit_K(t) = K^2 (t^3 + t^2 T) / 3 per unit K^2).
 */
START_TEST(test_walk_signed_squares)
{
	const double fs = 10, N = 0.15 * D2R / 60, B = 2 * D2R / 3600,
		     K = 10 * D2R / 3600 / 60;
	const size_t n = 36000;
	double *x = white(n, fs, N, B, K, 19105);
	struct sscope_walk_opts o = { 0 };
	struct sscope_walk_result *r = NULL, *rs = NULL;
	struct sscope_diag d = { "" };

	o.rate_hz = fs;
	o.run_s = 60;
	o.bias_s = 60;
	o.coef[SSCOPE_TERM_N] = N;
	o.coef[SSCOPE_TERM_B] = B;
	o.coef[SSCOPE_TERM_K] = K;
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &r, NULL), 0);
	o.have_sq = true;
	for (int j = 0; j < 5; j++)
		o.sq[j] = o.coef[j] * o.coef[j];
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &rs, NULL), 0);
	for (size_t k = 1; k < r->n_points; k++) {
		ck_assert_rel(rs->sigma[k], r->sigma[k], 1e-12);
		ck_assert_rel(rs->var_other[k], r->var_other[k], 1e-12);
		ck_assert(rs->var_other_sd[k] == 0 && r->var_other_sd[k] == 0);
	}
	sscope_walk_result_free(rs);
	/* B^2 estimated below zero; K^2 with an sd of half its value */
	o.sq[SSCOPE_TERM_B] = -0.25 * B * B;
	o.sq_cov[SSCOPE_TERM_K * 5 + SSCOPE_TERM_K] = 0.25 * K * K * K * K;
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &rs, NULL), 0);
	for (size_t k = 1; k < r->n_points; k += 50) {
		double t = (double)k / fs, T = 60;
		double eb[5] = { 0, 0, 1, 0, 0 };
		double uk = (t * t * t + t * t * T) / 3;
		double ub = sscope_heading_drift_var(eb, t, T);

		ck_assert_rel(rs->var_other[k], r->var_other[k] - 1.25 * B * B * ub,
			      1e-9);
		ck_assert_rel(rs->var_other_sd[k], uk * 0.5 * K * K, 1e-9);
	}
	sscope_walk_result_free(rs);
	o.sq[SSCOPE_TERM_K] = NAN;
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &rs, &d), -EINVAL);
	ck_assert_ptr_null(rs);
	sscope_walk_result_free(r);
	free(x);
}
END_TEST

START_TEST(test_walk_all_terms)
{
	/* N, B and K together over 20 h at 5 Hz: the envelope with the B
	 * and K parts still holds 95 %; without them the runs escape */
	const double fs = 5, N = 0.15 * D2R / 60, B = 2 * D2R / 3600;
	const double K = 10 * D2R / 3600 / 60;
	const size_t n = 360000;
	double *x = white(n, fs, N, B, K, 19105), p = erf(sqrt(2.0)), full;
	struct sscope_walk_opts o = { 0 };
	struct sscope_walk_result *r = NULL;

	o.rate_hz = fs;
	o.run_s = 200;
	o.bias_s = 100;
	o.coef[SSCOPE_TERM_N] = N;
	o.coef[SSCOPE_TERM_B] = B;
	o.coef[SSCOPE_TERM_K] = K;
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &r, NULL), 0);
	ck_assert_int_eq(r->n_runs, 240);
	full = r->inside[r->n_points - 1];
	ck_assert_msg(fabs(full - p) < 0.06, "inside with N, B, K: %g", full);
	sscope_walk_result_free(r);
	o.coef[SSCOPE_TERM_B] = o.coef[SSCOPE_TERM_K] = 0;
	ck_assert_int_eq(sscope_walk_compute(x, 1, n, &o, &r, NULL), 0);
	ck_assert_msg(r->inside[r->n_points - 1] < full - 0.05, "N only: %g",
		      r->inside[r->n_points - 1]);
	sscope_walk_result_free(r);
	free(x);
}
END_TEST

START_TEST(test_walk_refused)
{
	double x[100] = { 0 };
	struct sscope_walk_opts o = { 0 };
	struct sscope_walk_result *r = NULL;
	struct sscope_diag d = { "" };

	o.rate_hz = 10;
	o.run_s = 2;
	ck_assert_int_eq(sscope_walk_compute(x, 1, 100, &o, &r, &d), -EINVAL); /* no terms */
	o.coef[1] = 1e-3;
	o.run_s = 6;
	ck_assert_int_eq(sscope_walk_compute(x, 1, 100, &o, &r, &d), -EDOM); /* 1 run */
	ck_assert(strstr(d.msg, "need at least 2") != NULL);
	o.run_s = 0.1;
	ck_assert_int_eq(sscope_walk_compute(x, 1, 100, &o, &r, &d), -EDOM);
	o.run_s = 2;
	o.bias_s = 0.1;
	ck_assert_int_eq(sscope_walk_compute(x, 1, 100, &o, &r, &d), -EDOM);
	o.bias_s = 0;
	x[7] = INFINITY;
	ck_assert_int_eq(sscope_walk_compute(x, 1, 100, &o, &r, &d), -EINVAL);
	x[7] = 0;
	o.coef[2] = NAN;
	ck_assert_int_eq(sscope_walk_compute(x, 1, 100, &o, &r, &d), -EINVAL);
	o.coef[2] = 0;
	ck_assert_int_eq(sscope_walk_compute(x, 1, 100, &o, &r, &d), 0);
	ck_assert_int_eq(r->n_runs, 5);
	sscope_walk_result_free(r);
	{
		/* a record that moves: quiet, then rotating back and forth */
		double *y = white(2000, 10, 1e-3, 0, 0, 19106);

		for (size_t i = 1000; i < 2000; i++)
			y[i] += 0.5 * sin(0.3 * (double)i);
		ck_assert_int_eq(sscope_walk_compute(y, 1, 2000, &o, &r, &d), -EDOM);
		ck_assert(strstr(d.msg, "moves") != NULL);
		o.max_contrast = -1;
		ck_assert_int_eq(sscope_walk_compute(y, 1, 2000, &o, &r, &d), 0);
		free(y);
	}
	ck_assert_int_eq(sscope_walk_implied_n(r, 3, 1.5, NULL), -EINVAL);
	sscope_walk_result_free(r);
	sscope_walk_result_free(NULL);
}
END_TEST

/* The stillness check against its definition: the 90th over the 10th
 * percentile of calib's moving variance, the order statistics taken by a
 * sort.  A limit equal to that ratio passes and the next double below
 * fails, on a record long enough to be split between threads (2^20 +
 * positions) and on a short one. */
static int cmp_dbl(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return (x > y) - (x < y);
}

START_TEST(test_walk_still_ratio)
{
	static const size_t sizes[2] = { 5000, 1200000 };

	for (int k = 0; k < 2; k++) {
		const size_t n = sizes[k], w = 11; /* fs 10: 11-sample windows */
		double *y = white(n, 10, 1e-3, 0, 0, 19107 + (unsigned)k);
		double *v = malloc(n * sizeof(double)), ratio;
		struct sscope_walk_opts o = { 0 };
		struct sscope_walk_result *r = NULL;
		struct sscope_diag d = { "" };
		size_t nf = 0;

		ck_assert(v != NULL);
		/* a slowly swelling noise: percentiles far apart */
		for (size_t i = 0; i < n; i++)
			y[i] *= 1 + 0.8 * sin(6.2831853 * (double)i / (double)n);
		ck_assert_int_eq(sscope_calib_variance_magnitude(y, y, y, 1, n, w, v), 0);
		for (size_t i = 0; i < n; i++)
			if (isfinite(v[i]))
				v[nf++] = v[i];
		qsort(v, nf, sizeof(double), cmp_dbl);
		ratio = v[(nf - 1) * 9 / 10] / v[(nf - 1) / 10];
		ck_assert(ratio > 1.5);
		o.rate_hz = 10;
		o.run_s = 2;
		o.coef[SSCOPE_TERM_N] = 1e-3;
		o.max_contrast = ratio;
		ck_assert_msg(sscope_walk_compute(y, 1, n, &o, &r, &d) == 0, "n %zu: %s", n,
			      d.msg);
		sscope_walk_result_free(r);
		o.max_contrast = nextafter(ratio, 0);
		ck_assert_int_eq(sscope_walk_compute(y, 1, n, &o, &r, &d), -EDOM);
		ck_assert(strstr(d.msg, "moves") != NULL);
		free(v);
		free(y);
	}
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("heading");
	TCase *tc = tcase_create("core");

	tcase_set_timeout(tc, 300);
	tcase_add_test(tc, test_drift_var_closed_forms);
	tcase_add_test(tc, test_drift_var_flicker_mc);
	tcase_add_test(tc, test_heading_drive);
	tcase_add_test(tc, test_heading_envelope);
	tcase_add_test(tc, test_heading_refused);
	tcase_add_test(tc, test_static_reference);
	tcase_add_test(tc, test_walk_fan);
	tcase_add_test(tc, test_walk_all_terms);
	tcase_add_test(tc, test_walk_signed_squares);
	tcase_add_test(tc, test_walk_refused);
	tcase_add_test(tc, test_walk_still_ratio);
	suite_add_tcase(s, tc);
	return s;
}
