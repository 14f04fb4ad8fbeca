/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Heading from a vertical gyro with the bias estimated at stops (see
 * sscope-heading.h).  Stops come from the calibration module's static
 * detector (Tedaldi, Pretto and Menegatti, ICRA 2014, sec. IV-A:
 * sscope_calib_variance_magnitude() and sscope_calib_static_intervals()).
 *
 * The drift variance: an integrated rate with a bias estimate removed is a
 * combination sum c_i X(t_i) of the integral X of the rate at a few times,
 * with sum c_i = 0 and sum c_i t_i = 0 (e.g. X(tau) - (1 + c) X(0) +
 * c X(-T), c = tau / T, for a bias from the T seconds before 0).  For a
 * noise with stationary increments and structure function
 * D(t) = E[(X(s + t) - X(s))^2] / 2 its variance is
 * -2 sum_{i<j} c_i c_j D(|t_i - t_j|) (the identity behind the Allan
 * variance: at tau = T it is 2 tau^2 AVAR(tau)).  White noise gives
 * D = N^2 t / 2, rate random walk -K^2 t^3 / 12 and flicker
 * -(B^2 / 2 pi) t^2 ln t once the terms that cancel in the combination are
 * dropped (the flicker integral itself diverges at low frequency: only the
 * combination is finite, the reason a bias must be estimated from data at
 * all); white angle noise gives Q^2, and a rate ramp the deterministic
 * (R / 2 sum c_i t_i^2)^2.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sscope-calib.h"
#include "sscope-heading.h"
#include "sscope-nav.h"
#include "sscope-term.h"


double sscope_heading_drift_var_points(const double coef[5], const double *t,
					const double *c, size_t n)
{
	double v = 0, scale = 0, m2 = 0;
	const double Q2 = coef[SSCOPE_TERM_Q] * coef[SSCOPE_TERM_Q];
	const double N2 = coef[SSCOPE_TERM_N] * coef[SSCOPE_TERM_N];
	const double B2 = coef[SSCOPE_TERM_B] * coef[SSCOPE_TERM_B] / (2 * PI);
	const double K2 = coef[SSCOPE_TERM_K] * coef[SSCOPE_TERM_K];

	for (size_t i = 0; i < n; i++)
		for (size_t j = i + 1; j < n; j++)
			scale = fmax(scale, fabs(t[i] - t[j]));
	/* -2 sum_{i<j} c_i c_j D(|t_i - t_j|); the flicker logarithm taken
	 * relative to the largest distance (the sum of c_i c_j d^2 is 0) */
	for (size_t i = 0; i < n; i++)
		for (size_t j = i + 1; j < n; j++) {
			double d = fabs(t[i] - t[j]), D;

			if (d == 0)
				continue;
			D = Q2 + N2 * d / 2 - K2 * d * d * d / 12;
			if (B2 > 0)
				D -= B2 * d * d * log(d / scale);
			v -= 2 * c[i] * c[j] * D;
		}
	/* the rate ramp: deterministic, (R / 2 sum c_i t_i^2)^2 */
	for (size_t i = 0; i < n; i++)
		m2 += c[i] * t[i] * t[i];
	v += coef[SSCOPE_TERM_R] * coef[SSCOPE_TERM_R] * m2 * m2 / 4;
	return v > 0 ? v : 0;
}

double sscope_heading_drift_var(const double coef[5], double tau, double T)
{
	double c, t[3], w[3];

	if (!coef || !(tau >= 0) || !(T > 0) || !isfinite(tau) || !isfinite(T))
		return (double)NAN;
	for (int i = 0; i < 5; i++)
		if (!(coef[i] >= 0) || !isfinite(coef[i]))
			return (double)NAN;
	if (tau == 0)
		return 0;
	/* X(tau) - (1 + c) X(0) + c X(-T), X the integral of the rate */
	c = tau / T;
	t[0] = tau;
	t[1] = 0;
	t[2] = -T;
	w[0] = 1;
	w[1] = -(1 + c);
	w[2] = c;
	return sscope_heading_drift_var_points(coef, t, w, 3);
}

void sscope_heading_result_free(struct sscope_heading_result *r)
{
	if (!r)
		return;
	free(r->heading_rad);
	free(r->heading_once_rad);
	free(r->sigma_rad);
	free(r->sigma_once_rad);
	free(r->still);
	free(r->stops);
	free(r);
}

void sscope_heading_set_initial(struct sscope_heading_result *r, double h)
{
	double d;

	if (!r || r->first >= r->n || !isfinite(h))
		return;
	d = h - r->heading_rad[r->first];
	for (size_t i = r->first; i < r->n; i++) {
		r->heading_rad[i] = remainder(r->heading_rad[i] + d, 2 * PI);
		r->heading_once_rad[i] = remainder(r->heading_once_rad[i] + d, 2 * PI);
	}
}

/* bias between the centres of stop j and the next (constant outside) */
static double interp_bias(const struct sscope_heading_result *r, size_t j,
			  double t)
{
	const struct sscope_heading_stop *a = &r->stops[j], *b;
	double ca, cb;

	if (j + 1 >= r->n_stops)
		return a->bias_rad_s;
	b = a + 1;
	ca = 0.5 * (a->t_start_s + a->t_end_s);
	cb = 0.5 * (b->t_start_s + b->t_end_s);
	return a->bias_rad_s + (b->bias_rad_s - a->bias_rad_s) * (t - ca) / (cb - ca);
}

int sscope_heading_compute(const double *rate, size_t stride, size_t n,
			   const double *const det[3], size_t ds,
			   const struct sscope_heading_opts *o,
			   struct sscope_heading_result **resp,
			   struct sscope_diag *diag)
{
	struct sscope_heading_result *r = NULL;
	struct sscope_calib_interval *iv = NULL;
	double *vs = NULL, *work = NULL, dt, win_s, min_s, k, sgn, p10, p90 = 0, contrast;
	size_t window, min_len, cnt, max_iv;
	int rc = 0;

	if (!resp)
		return -EINVAL;
	*resp = NULL;
	if (!rate || !det || !det[0] || !det[1] || !det[2] || !o || stride == 0 ||
	    ds == 0 || !(o->rate_hz > 0) || !isfinite(o->rate_hz))
		return ssc_diag(diag, -EINVAL, "bad parameter");
	if (o->window_s < 0 || o->min_static_s < 0 || o->k < 0 || o->min_contrast < 0 ||
	    o->init_static_s < 0 || !isfinite(o->initial_heading_rad) ||
	    (unsigned)o->bias_model > SSCOPE_HEADING_INTERPOLATE ||
	    (!isnan(o->latitude_rad) && !(fabs(o->latitude_rad) <= PI / 2)))
		return ssc_diag(diag, -EINVAL, "bad option");
	for (int i = 0; i < 5; i++)
		if (!(o->coef[i] >= 0) || !isfinite(o->coef[i]))
			return ssc_diag(diag, -EINVAL,
					"noise terms must be finite and non-negative");
	for (size_t i = 0; i < n; i++)
		if (!isfinite(rate[i * stride]) || !isfinite(det[0][i * ds]) ||
		    !isfinite(det[1][i * ds]) || !isfinite(det[2][i * ds]))
			return ssc_diag(diag, -EINVAL,
					"sample %zu is not finite", i + 1);
	dt = 1 / o->rate_hz;
	win_s = o->window_s > 0 ? o->window_s : 1.0;
	min_s = o->min_static_s > 0 ? o->min_static_s : 2.0;
	k = o->k > 0 ? o->k : 3.0;
	sgn = o->axis_up ? -1 : 1;
	window = ssc_count(round(win_s * o->rate_hz));
	if (window < 3)
		window = 3;
	min_len = ssc_count(round(min_s * o->rate_hz));
	if (min_len < 2)
		min_len = 2;
	if (n < window)
		return ssc_diag(diag, -EDOM,
				"%zu samples: shorter than the %g s detector window",
				n, win_s);
	r = calloc(1, sizeof(*r));
	vs = ssc_alloc_array(n, sizeof(double));
	work = ssc_alloc_array(n, sizeof(double));
	if (!r || !vs || !work) {
		rc = -ENOMEM;
		goto fail;
	}
	r->n = n;
	rc = sscope_calib_variance_magnitude(det[0], det[1], det[2], ds, n,
					     window, vs);
	if (rc) {
		rc = rc == -EDOM ?
			ssc_diag(diag, rc, "%zu samples: shorter than the still detector's window of %zu samples (%g s)",
				 n, window | 1, win_s) :
			ssc_diag(diag, rc, "the still detector refused the record");
		goto fail;
	}
	rc = sscope_calib_static_reference(det[0], det[1], det[2], ds, n, o->rate_hz,
					   o->init_static_s, vs, work, &r->reference,
					   diag);
	if (!rc)
		rc = ssc_calib_vs_deciles(vs, n, work, 10, &p10, &p90) ?
			     ssc_diag(diag, -EDOM, "fewer than 10 detector windows with a finite variance: the record is too short, or its samples too large to square (beyond about 1e154)") : 0;
	if (rc)
		goto fail;
	r->threshold = k * r->reference;
	/* a relative threshold finds "stops" in any record: require that
	 * the record also moves clearly (contrast with the reference) */
	contrast = o->min_contrast > 0 ? o->min_contrast : k * k;
	if (!(p90 >= contrast * r->reference)) {
		rc = ssc_diag(diag, -EDOM,
			      "cannot tell stops from motion: the detector channels vary alike everywhere, as in a record all still or all moving (90th percentile of the window variance %.3g times the reference, stops and motion need %g); heading needs a record with both, or a lower contrast",
			      p90 / r->reference, contrast);
		goto fail;
	}
	sscope_calib_static_intervals(vs, n, r->threshold, min_len, NULL, 0, &cnt);
	if (cnt == 0) {
		rc = ssc_diag(diag, -EDOM,
			      "no stationary interval of %g s or more (threshold %.3g = %g x reference %.3g)",
			      min_s, r->threshold, k, r->reference);
		goto fail;
	}
	max_iv = cnt;
	iv = ssc_alloc_array(max_iv, sizeof(*iv));
	r->stops = calloc(max_iv, sizeof(*r->stops));
	r->heading_rad = ssc_alloc_array(n, sizeof(double));
	r->heading_once_rad = ssc_alloc_array(n, sizeof(double));
	r->sigma_rad = ssc_alloc_array(n, sizeof(double));
	r->sigma_once_rad = ssc_alloc_array(n, sizeof(double));
	r->still = calloc(n, 1);
	if (!iv || !r->stops || !r->heading_rad || !r->heading_once_rad ||
	    !r->sigma_rad || !r->sigma_once_rad || !r->still) {
		rc = -ENOMEM;
		goto fail;
	}
	sscope_calib_static_intervals(vs, n, r->threshold, min_len, iv, max_iv,
				      &cnt);
	/* the detector cannot judge the half windows at the ends: a stop
	 * reaching them holds to the end */
	if (iv[0].start <= window / 2)
		iv[0].start = 0;
	if (iv[cnt - 1].end + window / 2 >= n)
		iv[cnt - 1].end = n;
	r->n_stops = cnt;
	/* per-stop bias and the pooled within-stop scatter */
	{
		double ss = 0, dof = 0;

		for (size_t j = 0; j < cnt; j++) {
			struct sscope_heading_stop *s = &r->stops[j];
			double mean, sd;

			sscope_calib_interval_mean(rate, stride, &iv[j], &mean, &sd);
			s->start = iv[j].start;
			s->end = iv[j].end;
			s->t_start_s = (double)s->start * dt;
			s->t_end_s = (double)s->end * dt;
			s->bias_rad_s = mean;
			if (s->end - s->start > 1) {
				ss += sd * sd * (double)(s->end - s->start - 1);
				dof += (double)(s->end - s->start - 1);
			}
			for (size_t i = s->start; i < s->end; i++)
				r->still[i] = 1;
		}
		memcpy(r->coef, o->coef, sizeof(r->coef));
		if (r->coef[0] == 0 && r->coef[1] == 0 && r->coef[2] == 0 &&
		    r->coef[3] == 0 && r->coef[4] == 0 && dof > 0) {
			r->coef[SSCOPE_TERM_N] = sqrt(ss / dof * dt);
			r->coef_from_stops = true;
		}
	}
	if (!isnan(o->latitude_rad))
		r->earth_rate_rad_s = -sgn * SSCOPE_NAV_WGS84_OMEGA *
				      sin(o->latitude_rad);
	for (size_t j = 0; j < cnt; j++) {
		struct sscope_heading_stop *s = &r->stops[j];
		double T = s->t_end_s - s->t_start_s;

		/* the scatter of consecutive means over T: the Allan
		 * deviation at T (N / sqrt(T) for white noise) */
		s->bias_sd_rad_s = sqrt(sscope_heading_drift_var(r->coef, T, T) / 2) / T;
		s->sensor_bias_rad_s = isnan(o->latitude_rad) ?
					       (double)NAN :
					       s->bias_rad_s - r->earth_rate_rad_s;
	}
	r->first = r->stops[0].start;
	for (size_t i = 0; i < r->first; i++) {
		r->heading_rad[i] = r->heading_once_rad[i] = (double)NAN;
		r->sigma_rad[i] = r->sigma_once_rad[i] = (double)NAN;
	}
	/* integration: compensated sums (records of hours) */
	{
		struct ssc_ksum h = { o->initial_heading_rad, 0 };
		struct ssc_ksum h1 = { o->initial_heading_rad, 0 };
		const struct sscope_heading_stop *s0 = &r->stops[0];
		double b0 = s0->bias_rad_s, T0 = s0->t_end_s - s0->t_start_s;
		double carry = 0, seg = 0, bias = b0, Tl = T0;
		size_t j = 0, last_end = s0->end;

		for (size_t i = r->first; i < n; i++) {
			double w = rate[i * stride];

			/* next stop reached: hold; at its end take its bias */
			while (j + 1 < cnt && i >= r->stops[j + 1].start) {
				j++;
				carry += seg;
				seg = 0;
			}
			if (r->still[i]) {
				if (i + 1 == r->stops[j].end) {
					carry += seg;
					seg = 0;
					Tl = r->stops[j].t_end_s - r->stops[j].t_start_s;
					last_end = r->stops[j].end;
					bias = r->stops[j].bias_rad_s;
				}
			} else {
				double b = bias;

				if (o->bias_model == SSCOPE_HEADING_INTERPOLATE)
					b = interp_bias(r, j, (double)i * dt);
				ssc_ksum_add(&h, sgn * (w - b) * dt);
				seg = sscope_heading_drift_var(
					r->coef, (double)(i + 1 - last_end) * dt, Tl);
			}
			r->heading_rad[i] = remainder(ssc_ksum_value(&h), 2 * PI);
			r->sigma_rad[i] = sqrt(carry + seg);
			ssc_ksum_add(&h1, sgn * (w - b0) * dt);
			r->heading_once_rad[i] = remainder(ssc_ksum_value(&h1), 2 * PI);
			r->sigma_once_rad[i] =
				i + 1 > s0->end ?
					sqrt(sscope_heading_drift_var(
						r->coef, (double)(i + 1 - s0->end) * dt, T0)) :
					0;
		}
	}
	free(iv);
	free(vs);
	free(work);
	*resp = r;
	return 0;
fail:
	free(iv);
	free(vs);
	free(work);
	sscope_heading_result_free(r);
	return rc;
}

int sscope_heading_compare(const double *hd, const double *sigma,
			   const double *ref, size_t rs, size_t n, size_t first,
			   struct sscope_heading_cmp *c)
{
	struct ssc_ksum s2 = { 0, 0 };
	size_t m = 0, in = 0, ns = 0;

	if (!hd || !ref || !c || rs == 0)
		return -EINVAL;
	memset(c, 0, sizeof(*c));
	for (size_t i = first; i < n; i++) {
		double e;

		if (!isfinite(hd[i]) || !isfinite(ref[i * rs]))
			continue;
		e = remainder(hd[i] - ref[i * rs], 2 * PI);
		ssc_ksum_add(&s2, e * e);
		c->max_abs_rad = fmax(c->max_abs_rad, fabs(e));
		c->final_rad = e;
		m++;
		if (sigma && sigma[i] > 0) {
			ns++;
			in += fabs(e) <= 2 * sigma[i];
		}
	}
	if (m == 0)
		return -EDOM;
	c->n = m;
	c->rms_rad = sqrt(ssc_ksum_value(&s2) / (double)m);
	c->inside_2sigma = ns ? (double)in / (double)ns : (double)NAN;
	return 0;
}
