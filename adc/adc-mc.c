/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The Monte-Carlo check of the ADC-selection report ("does this converter
 * degrade this gyro's spec?", IEEE Std 952 terms): simulate the sensor
 * (sscope_sim), digitize it through the converter (sscope_adc), fit the
 * Allan terms with and without the converter (sscope_allan_analyze) and
 * compare N, B and K over several seeded runs, with Student-t intervals of
 * the mean ratios; and the ranking of converters for a selection.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_statistics_double.h>

#include "sscope-adc.h"
#include "sscope-allan.h"
#include "sscope-noise.h"
#include "sscope-sensor.h"
#include "sscope-sim.h"
#include "sscope-stats.h"
#include "sscope-term.h"

/* records are simulated and converted in blocks of this many output
 * samples (M conversions each) */
#define MC_BLOCK 4096

void sscope_adc_mc_clear(struct sscope_adc_mc *mc)
{
	if (!mc)
		return;
	free(mc->tau_s);
	free(mc->dev_in);
	free(mc->dev_out);
	mc->tau_s = mc->dev_in = mc->dev_out = NULL;
	mc->n_points = mc->n_runs = 0;
}

/* The ADEV curves of run r, alone and through the converter (every run
 * has the grid of run 0: same length and rate). */
static int keep_curves(const struct sscope_allan_result *in,
		       const struct sscope_allan_result *out, size_t r,
		       size_t runs, struct sscope_adc_mc *mc)
{
	size_t np = in->n_points;

	if (r == 0) {
		if (np != out->n_points || !np)
			return 0;
		mc->tau_s = ssc_alloc_array(np, sizeof(double));
		mc->dev_in = ssc_alloc_array(runs * np, sizeof(double));
		mc->dev_out = ssc_alloc_array(runs * np, sizeof(double));
		if (!mc->tau_s || !mc->dev_in || !mc->dev_out)
			return -ENOMEM;
		for (size_t i = 0; i < np; i++)
			mc->tau_s[i] = in->points[i].tau_s;
		mc->n_points = np;
	}
	if (!mc->n_points || np != mc->n_points || out->n_points != np ||
	    mc->n_runs != r)
		return 0;
	for (size_t i = 0; i < np; i++) {
		mc->dev_in[r * np + i] = in->points[i].dev;
		mc->dev_out[r * np + i] = out->points[i].dev;
	}
	mc->n_runs = r + 1;
	return 0;
}

int sscope_adc_mc_band(const struct sscope_adc_mc *mc,
		       enum sscope_adc_mc_curve which, size_t i, double q[3])
{
	size_t np, k = 0;
	double *s;

	if (!mc || !q || i >= mc->n_points)
		return -EINVAL;
	np = mc->n_points;
	q[0] = q[1] = q[2] = NAN;
	s = ssc_alloc_array(mc->n_runs ? mc->n_runs : 1, sizeof(double));
	if (!s)
		return -ENOMEM;
	for (size_t r = 0; r < mc->n_runs; r++) {
		double v = which == SSCOPE_ADC_MC_ALONE ? mc->dev_in[r * np + i] :
			   which == SSCOPE_ADC_MC_THROUGH ? mc->dev_out[r * np + i] :
			   mc->dev_out[r * np + i] / mc->dev_in[r * np + i];

		if (isfinite(v) && v > 0)
			s[k++] = v;
	}
	if (k) {
		qsort(s, k, sizeof(double), ssc_cmp_double);
		q[0] = gsl_stats_quantile_from_sorted_data(s, 1, k, 0.1);
		q[1] = gsl_stats_quantile_from_sorted_data(s, 1, k, 0.5);
		q[2] = gsl_stats_quantile_from_sorted_data(s, 1, k, 0.9);
	}
	free(s);
	return 0;
}

/* One run: the record alone (x) and through the converter (y), n output
 * samples at fs, each the mean of M conversions. */
static int one_run(const struct sscope_sensor_spec *sensor,
		   const struct sscope_adc_spec *spec, const double *inl,
		   size_t n_inl, double sensitivity, double zero_v,
		   struct sscope_sim_opts *so, unsigned long seed, double fs,
		   size_t M, size_t n, double *x, double *y, double *fx,
		   double *fy, size_t *clipped, struct sscope_diag *diag)
{
	struct sscope_sim *sim = NULL;
	struct sscope_adc *adc = NULL;
	int rc;

	so->seed = seed;
	rc = sscope_sim_new(&sim, sensor, so, diag);
	if (!rc)
		rc = sscope_adc_new(&adc, spec, sensitivity, zero_v, seed, diag);
	if (!rc && inl) {
		rc = sscope_adc_set_inl(adc, inl, n_inl);
		if (rc)
			ssc_diag(diag, rc, "inl_profile: %s", sscope_strerror(rc));
	}
	for (size_t i0 = 0; !rc && i0 < n; i0 += MC_BLOCK) {
		size_t b = n - i0 < MC_BLOCK ? n - i0 : MC_BLOCK;

		rc = sscope_sim_generate(sim, NULL, fx, NULL, b * M);
		if (!rc)
			rc = sscope_adc_digitize(adc, fx, 1, b * M, fs * (double)M,
						 NULL, fy, NULL, clipped);
		for (size_t i = 0; !rc && i < b; i++) {
			double sx = 0, sy = 0;

			for (size_t j = 0; j < M; j++) {
				sx += fx[i * M + j];
				sy += fy[i * M + j];
			}
			x[i0 + i] = sx / (double)M;
			y[i0 + i] = sy / (double)M;
		}
	}
	sscope_sim_free(sim);
	sscope_adc_free(adc);
	return rc;
}

int sscope_adc_monte_carlo(const struct sscope_sensor_spec *sensor,
			   const struct sscope_adc_spec *spec,
			   const double *inl_lsb, size_t n_inl,
			   double sensitivity, double zero_v,
			   const struct sscope_adc_mc_opts *o,
			   struct sscope_adc_mc *out, struct sscope_diag *diag)
{
	double fs, level, *x = NULL, *y = NULL, *vals = NULL, *fx = NULL,
	       *fy = NULL;
	size_t n, R, M;
	struct sscope_sim_opts so;
	struct sscope_noise_plan *plan = NULL;
	int rc = 0;

	if (!sensor || !spec || !o || !out || o->runs == 0)
		return ssc_diag(diag, -EINVAL, "adc Monte Carlo: bad parameters");
	memset(out, 0, sizeof(*out));
	fs = o->rate_hz > 0 ? o->rate_hz : spec->rate_hz;
	if (!(fs > 0) || !(o->duration_s > 0))
		return ssc_diag(diag, -EINVAL, "adc Monte Carlo: no sample rate or duration");
	level = o->ci_level > 0 ? o->ci_level : 0.6827;
	n = ssc_count(round(o->duration_s * fs));
	R = o->runs;
	M = spec->oversample > 1 ? spec->oversample : 1;
	if (n < 1000)
		return ssc_diag(diag, -EDOM,
				"--mc-duration gives %zu samples (need 1000)", n);
	x = malloc(n * sizeof(double));
	y = malloc(n * sizeof(double));
	vals = malloc(4 * R * sizeof(double));
	fx = malloc(MC_BLOCK * M * sizeof(double));
	fy = malloc(MC_BLOCK * M * sizeof(double));
	if (!x || !y || !vals || !fx || !fy) {
		rc = -ENOMEM;
		goto done;
	}
	/* every run's two fits are of one length, rate and grid: the fit's
	 * covariance sums are computed once (the same numbers) */
	if (sscope_noise_plan_new(&plan))
		plan = NULL;
	memset(&so, 0, sizeof(so));
	so.rate_hz = fs * (double)M; /* the conversion rate */
	so.temp_profile = SSCOPE_SIM_TEMP_CONSTANT;
	so.flicker_tau_max_s = fmax(1e6, 10 * o->duration_s);
	for (size_t r = 0; r < R && !rc; r++) {
		struct sscope_allan_result *ri = NULL, *ro = NULL;
		struct ssc_ksum sin_ = { 0, 0 }, sout = { 0, 0 };
		struct sscope_noise_fit_opts fo = { 0 };

		rc = one_run(sensor, spec, inl_lsb, n_inl, sensitivity, zero_v,
			     &so, o->seed + r, fs, M, n, x, y, fx, fy,
			     &out->clipped, diag);
		if (o->progress)
			o->progress(o->progress_ctx, r + 1, R);
		/* the terms compared (the simulated sensor has no ramp and its
		 * quantization is what is being judged): a free R or Q would
		 * only add estimation noise to B and K */
		fo.allowed = (1u << SSCOPE_TERM_N) | (1u << SSCOPE_TERM_B) |
			     (1u << SSCOPE_TERM_K);
		fo.plan = plan;
		if (!rc)
			rc = sscope_allan_analyze(x, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE,
						  NULL, &fo, &ri, diag);
		if (!rc)
			rc = sscope_allan_analyze(y, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE,
						  NULL, &fo, &ro, diag);
		for (int t = 0; !rc && t < 3; t++) {
			const struct sscope_noise_coef *ci = &ri->fit.coef[SSCOPE_TERM_N + t];
			const struct sscope_noise_coef *co = &ro->fit.coef[SSCOPE_TERM_N + t];

			/* the estimates, resolved or not: the same noise
			 * realization goes in and out */
			vals[(size_t)t * R + r] = ri->have_fit && ro->have_fit &&
							  ci->estimate > 0 &&
							  co->estimate > 0 ?
						  co->estimate / ci->estimate :
						  (double)NAN;
		}
		for (size_t i = 0; !rc && i < n; i++) {
			ssc_ksum_add(&sin_, x[i]);
			ssc_ksum_add(&sout, y[i]);
		}
		if (!rc)
			vals[3 * R + r] = (ssc_ksum_value(&sout) - ssc_ksum_value(&sin_)) /
					  (double)n;
		if (!rc)
			rc = keep_curves(ri, ro, r, R, out);
		sscope_allan_result_free(ri);
		sscope_allan_result_free(ro);
	}
	if (rc)
		goto done;
	for (int t = 0; t < 4; t++) {
		struct sscope_adc_mc_ratio *q = t < 3 ? &out->ratio[t] : &out->bias_shift;

		struct sscope_stats st;

		sscope_stats_mean_interval(vals + (size_t)t * R, 1, R, level,
					   &q->mean, &q->lo, &q->hi, &q->runs);
		q->se = NAN;
		if (!sscope_stats_compute(vals + (size_t)t * R, 1, R, &st) &&
		    st.n >= 2)
			q->se = st.sd / sqrt((double)st.n);
	}
	out->runs = R;
	out->duration_s = (double)n / fs;
	out->rate_hz = fs;
done:
	if (rc)
		sscope_adc_mc_clear(out);
	sscope_noise_plan_free(plan);
	free(x);
	free(y);
	free(fx);
	free(fy);
	free(vals);
	return rc;
}

/* -1 when a ranks before b */
static int rank_cmp(const struct sscope_adc_analysis *a, int abits,
		    const struct sscope_adc_analysis *b, int bbits)
{
	double ma = isfinite(a->margin) ? a->margin : (double)INFINITY;
	double mb = isfinite(b->margin) ? b->margin : (double)INFINITY;

	if (a->verdict != b->verdict)
		return a->verdict < b->verdict ? -1 : 1;
	if (a->verdict == SSCOPE_ADC_PASS && abits != bbits)
		return abits < bbits ? -1 : 1; /* cheapest passing */
	return ma > mb ? -1 : ma < mb ? 1 : 0;
}

void sscope_adc_rank(const struct sscope_adc_analysis *an, const int *bits,
		     size_t n, size_t *order)
{
	for (size_t i = 0; i < n; i++)
		order[i] = i;
	for (size_t i = 1; i < n; i++) /* insertion sort: stable, n small */
		for (size_t j = i; j > 0 && rank_cmp(&an[order[j]], bits[order[j]],
						     &an[order[j - 1]],
						     bits[order[j - 1]]) < 0; j--) {
			size_t t = order[j];

			order[j] = order[j - 1];
			order[j - 1] = t;
		}
}
