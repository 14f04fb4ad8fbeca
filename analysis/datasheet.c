/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Datasheet lines in IEEE Std 952-1997 (Annex C) terms and back, and a
 * record's guard-banded verdict against them (see sscope-datasheet.h for
 * every definition and its source).  The terms of a record come from the
 * noise fit of its overlapping Allan deviation (noisefit.c); the GJB 2426A
 * bias stability is the plain standard deviation of non-overlapping
 * means, with the chi-squared interval of a sample variance; the verdict
 * follows ISO 14253-1's guard band (conformance only when the whole
 * interval is inside the specification).
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>

#include "sscope-allan.h"
#include "sscope-datasheet.h"
#include "sscope-lot.h"
#include "sscope-noise.h"

static const struct sscope_datasheet_info infos[SSCOPE_DATASHEET_LINE_COUNT_] = {
	[SSCOPE_DATASHEET_NOISE_DENSITY] = {
		"noise_density", "noise density",
		"noise density D of the rate or the acceleration; N = D (the field's convention: IEEE 952 N, Allan deviation at 1 s, ARW = 60 D)",
		"/sqrt(Hz)", SSCOPE_TERM_N, 0 },
	[SSCOPE_DATASHEET_RANDOM_WALK] = {
		"random_walk", "angle/velocity random walk",
		"angle (velocity) random walk, IEEE 952 N, per sqrt(h) or sqrt(s)",
		"/sqrt(Hz)", SSCOPE_TERM_N, 0 },
	[SSCOPE_DATASHEET_RMS_NOISE] = {
		"rms_noise", "rms noise",
		"total rms noise over the noise bandwidth W: N = rms / sqrt(W) (the datasheets' relation)",
		"", SSCOPE_TERM_N, 0 },
	[SSCOPE_DATASHEET_BIAS_INSTABILITY] = {
		"bias_instability", "bias instability (IEEE)",
		"IEEE 952 bias instability B: the Allan deviation plateau is 0.6643 B",
		"", SSCOPE_TERM_B, 0 },
	[SSCOPE_DATASHEET_ALLAN_MINIMUM] = {
		"in_run_bias_stability", "in-run bias stability (Allan minimum)",
		"minimum of the Allan deviation (MEMS Industry Group SSPPD, IEEE 2700): B = minimum / 0.6643",
		"", SSCOPE_TERM_B, 0 },
	[SSCOPE_DATASHEET_RATE_RANDOM_WALK] = {
		"rate_random_walk", "rate random walk",
		"IEEE 952 rate random walk K (Allan deviation at 3 s of the +1/2 line)",
		"/s/sqrt(Hz)", SSCOPE_TERM_K, 0 },
	[SSCOPE_DATASHEET_GJB_10S] = {
		"bias_stability_10s", "bias stability, 10 s (GJB)",
		"GJB 2426A: 1 sigma of consecutive 10 s means (from terms: about the Allan deviation at 10 s, a lower bound)",
		"", SSCOPE_TERM_COUNT_, 10 },
	[SSCOPE_DATASHEET_GJB_100S] = {
		"bias_stability_100s", "bias stability, 100 s (GJB)",
		"GJB 2426A: 1 sigma of consecutive 100 s means (from terms: about the Allan deviation at 100 s, a lower bound)",
		"", SSCOPE_TERM_COUNT_, 100 },
	[SSCOPE_DATASHEET_RUN_TO_RUN_BIAS] = {
		"run_to_run_bias", "run-to-run bias",
		"bias repeatability from turn-on to turn-on, 1 sigma (several power cycles)",
		"", SSCOPE_TERM_COUNT_, 0 },
	[SSCOPE_DATASHEET_SCALE_FACTOR] = {
		"scale_factor_error", "scale-factor error",
		"scale-factor error, a ratio (ppm or %; a rate table or turns)",
		"1", SSCOPE_TERM_COUNT_, 0 },
	[SSCOPE_DATASHEET_BIAS_OFFSET] = {
		"bias_offset", "bias offset",
		"zero-rate (zero-g) offset, a magnitude: the record's mean by batch means; it includes the Earth's rate and gravity along the axis",
		"", SSCOPE_TERM_COUNT_, 0, true },
	[SSCOPE_DATASHEET_BIAS_TEMPCO] = {
		"bias_tempco", "bias temperature sensitivity",
		"change of the bias per kelvin (per degC), a magnitude: the slope of the block means on their temperatures",
		"/K", SSCOPE_TERM_COUNT_, 0, true },
	[SSCOPE_DATASHEET_RATE_RAMP] = {
		"rate_ramp", "rate ramp (bias drift)",
		"IEEE 952 rate ramp R, the bias's linear change per unit time, a magnitude: the slope of the block means on time",
		"/s", SSCOPE_TERM_COUNT_, 0, true },
};

const struct sscope_datasheet_info *
sscope_datasheet_info(enum sscope_datasheet_line line)
{
	if ((unsigned)line >= SSCOPE_DATASHEET_LINE_COUNT_)
		return NULL;
	return &infos[line];
}

int sscope_datasheet_line_by_key(const char *key)
{
	if (!key)
		return -1;
	for (int i = 0; i < SSCOPE_DATASHEET_LINE_COUNT_; i++)
		if (!strcmp(infos[i].key, key))
			return i;
	return -1;
}

int sscope_datasheet_factor(enum sscope_datasheet_line line,
			    double bandwidth_hz, double *f)
{
	if (!f)
		return -EINVAL;
	switch (line) {
	case SSCOPE_DATASHEET_NOISE_DENSITY:
	case SSCOPE_DATASHEET_RANDOM_WALK:
	case SSCOPE_DATASHEET_BIAS_INSTABILITY:
	case SSCOPE_DATASHEET_RATE_RANDOM_WALK:
		*f = 1;
		return 0;
	case SSCOPE_DATASHEET_RMS_NOISE:
		if (!(bandwidth_hz > 0) || !isfinite(bandwidth_hz))
			return -EINVAL;
		*f = sqrt(bandwidth_hz);
		return 0;
	case SSCOPE_DATASHEET_ALLAN_MINIMUM:
		*f = SSCOPE_DATASHEET_FLICKER_PLATEAU;
		return 0;
	default:
		return -EINVAL;
	}
}

double sscope_datasheet_gjb_from_terms(double n, double b, double k,
				       double tau_s)
{
	double v;

	if (!(tau_s > 0) || !isfinite(tau_s) || (isnan(n) && isnan(b) && isnan(k)))
		return (double)NAN;
	n = isnan(n) ? 0 : n;
	b = isnan(b) ? 0 : b;
	k = isnan(k) ? 0 : k;
	v = n * n / tau_s +
	    SSCOPE_DATASHEET_FLICKER_PLATEAU * SSCOPE_DATASHEET_FLICKER_PLATEAU * b * b +
	    k * k * tau_s / 3;
	return sqrt(v);
}

int sscope_datasheet_gjb(const double *x, size_t stride, size_t n,
			 double rate_hz, double tau_s, double level,
			 struct sscope_datasheet_gjb *out,
			 struct sscope_diag *diag)
{
	double mf, mean = 0, ss = 0, x0, dof;
	size_t m, nb;
	double *means;

	if (!x || !out || stride == 0)
		return ssc_diag(diag, -EINVAL, "no record");
	if (!(rate_hz > 0) || !isfinite(rate_hz) || !(tau_s > 0) || !isfinite(tau_s))
		return ssc_diag(diag, -EINVAL, "rate and averaging time must be positive");
	if (!(level > 0 && level < 1))
		return ssc_diag(diag, -EINVAL, "confidence level outside (0, 1)");
	mf = floor(tau_s * rate_hz + 0.5);
	if (mf < 1 || mf > (double)n)
		return ssc_diag(diag, -EDOM,
				"a record of %zu samples holds fewer than two %g s means",
				n, tau_s);
	m = (size_t)mf;
	nb = n / m;
	if (nb < 2)
		return ssc_diag(diag, -EDOM,
				"a record of %zu samples holds fewer than two %g s means",
				n, tau_s);
	means = malloc(nb * sizeof(*means));
	if (!means)
		return -ENOMEM;
	/* each mean about x0 (the first sample) so a large common bias does
	 * not cost digits; compensated sums within a block */
	x0 = x[0];
	for (size_t b = 0; b < nb; b++) {
		double s = 0, c = 0;

		for (size_t i = 0; i < m; i++) {
			double v = x[(b * m + i) * stride];
			double y, t;

			if (!isfinite(v)) {
				free(means);
				return ssc_diag(diag, -EDOM,
						"sample %zu is not a finite number",
						b * m + i);
			}
			y = (v - x0) - c;
			t = s + y;
			c = (t - s) - y;
			s = t;
		}
		means[b] = s / (double)m;
	}
	for (size_t b = 0; b < nb; b++)
		mean += means[b];
	mean /= (double)nb;
	for (size_t b = 0; b < nb; b++)
		ss += (means[b] - mean) * (means[b] - mean);
	free(means);
	dof = (double)(nb - 1);
	out->value = sqrt(ss / dof);
	out->lo = out->value * sqrt(dof / gsl_cdf_chisq_Pinv((1 + level) / 2, dof));
	out->hi = out->value * sqrt(dof / gsl_cdf_chisq_Pinv((1 - level) / 2, dof));
	out->n_means = nb;
	out->m = m;
	return 0;
}

const char *sscope_datasheet_verdict_name(enum sscope_datasheet_verdict v)
{
	switch (v) {
	case SSCOPE_DATASHEET_WITHIN:
		return "within spec";
	case SSCOPE_DATASHEET_OUT:
		return "out of spec";
	default:
		return "inconclusive";
	}
}

enum sscope_datasheet_verdict
sscope_datasheet_verdict(double lo, double hi, double limit)
{
	if (isnan(lo) || isnan(hi) || isnan(limit))
		return SSCOPE_DATASHEET_INCONCLUSIVE;
	if (hi < limit)
		return SSCOPE_DATASHEET_WITHIN;
	if (lo > limit)
		return SSCOPE_DATASHEET_OUT;
	return SSCOPE_DATASHEET_INCONCLUSIVE;
}

enum sscope_datasheet_verdict
sscope_datasheet_verdict_magnitude(double lo, double hi, double limit)
{
	if (isnan(lo) || isnan(hi) || isnan(limit) || lo > hi)
		return SSCOPE_DATASHEET_INCONCLUSIVE;
	if (-limit < lo && hi < limit)
		return SSCOPE_DATASHEET_WITHIN;
	if (lo > limit || hi < -limit)
		return SSCOPE_DATASHEET_OUT;
	return SSCOPE_DATASHEET_INCONCLUSIVE;
}

/* the least Allan deviation of the record, in c (a bound when the curve
 * still falls at its longest tau) */
static void allan_minimum(const struct sscope_allan_result *r,
			  struct sscope_datasheet_check *c)
{
	size_t best = 0;

	for (size_t i = 1; i < r->n_oadev; i++)
		if (r->oadev[i].dev < r->oadev[best].dev)
			best = i;
	if (best + 1 == r->n_oadev) {
		c->bound = true;
		c->hi = r->oadev[best].dev_hi;
		c->why = "the Allan deviation still falls at the longest tau: record too short for its minimum";
		return;
	}
	c->value = r->oadev[best].dev;
	c->lo = r->oadev[best].dev_lo;
	c->hi = r->oadev[best].dev_hi;
}

static void from_term(const struct sscope_allan_result *r,
		      const struct sscope_datasheet_spec *s,
		      struct sscope_datasheet_check *c)
{
	const struct sscope_noise_coef *k;
	double f;

	if (!r->have_fit) {
		c->why = "the noise fit failed on this record";
		return;
	}
	if (sscope_datasheet_factor(s->line, s->bandwidth_hz, &f))
		return;
	k = &r->fit.coef[infos[s->line].term];
	c->fit_rejected = sscope_noise_fit_rejected(&r->fit, 0.01);
	if (k->present && isfinite(k->value)) {
		c->value = f * k->value;
		c->lo = f * k->lo;
		c->hi = f * k->hi;
		return;
	}
	c->bound = true;
	c->hi = f * k->hi;
	c->why = "the term is not resolved in this record: an upper bound only";
}

int sscope_datasheet_check(const double *x, size_t stride, size_t n,
			   double rate_hz,
			   const struct sscope_datasheet_spec *spec,
			   size_t n_spec,
			   const struct sscope_datasheet_opts *opts,
			   struct sscope_datasheet_check *out,
			   struct sscope_diag *diag)
{
	double level = opts && opts->level != 0 ? opts->level : 0.99;
	struct sscope_allan_result *res = NULL;
	bool need_allan = false, moves = false;
	int rc;

	if (!x || (n_spec && (!spec || !out)))
		return ssc_diag(diag, -EINVAL, "no record or no lines");
	if (!(level > 0 && level < 1))
		return ssc_diag(diag, -EINVAL, "confidence level outside (0, 1)");
	for (size_t i = 0; i < n_spec; i++) {
		if ((unsigned)spec[i].line >= SSCOPE_DATASHEET_LINE_COUNT_)
			return ssc_diag(diag, -EINVAL, "line %zu: unknown kind", i);
		if (infos[spec[i].line].term != SSCOPE_TERM_COUNT_ ||
		    spec[i].line == SSCOPE_DATASHEET_RATE_RAMP)
			need_allan = true;
	}
	if (need_allan) {
		struct sscope_allan_opts ao = { 0 };
		struct sscope_noise_fit_opts fo = { 0 };

		ao.ci_level = level;
		fo.ci_level = level;
		rc = sscope_allan_analyze(x, stride, n, rate_hz,
					  SSCOPE_ALLAN_TAUS_DENSE, &ao, &fo,
					  &res, diag);
		if (rc)
			return rc;
	}
	/* a moving record measures the motion, not the sensor: no verdict
	 * on it (the stillness test of walk and the adequacy check) */
	if (n_spec) {
		double ratio;

		if (!ssc_still_contrast(x, stride, n, rate_hz, &ratio) &&
		    !(ratio <= 9))
			moves = true;
	}
	for (size_t i = 0; i < n_spec; i++) {
		const struct sscope_datasheet_spec *s = &spec[i];
		struct sscope_datasheet_check *c = &out[i];
		bool doubt = false;

		memset(c, 0, sizeof(*c));
		c->line = s->line;
		c->limit = s->value;
		c->value = c->lo = c->hi = (double)NAN;
		switch (s->line) {
		case SSCOPE_DATASHEET_ALLAN_MINIMUM:
			allan_minimum(res, c);
			break;
		case SSCOPE_DATASHEET_GJB_10S:
		case SSCOPE_DATASHEET_GJB_100S: {
			struct sscope_datasheet_gjb g;

			if (sscope_datasheet_gjb(x, stride, n, rate_hz,
						 infos[s->line].tau_s, level,
						 &g, NULL)) {
				double m = floor(infos[s->line].tau_s * rate_hz + 0.5);

				c->why = m >= 1 && (double)n >= 2 * m ?
						 "the record has a gap (a sample not finite) in its means" :
						 "the record holds fewer than two such means";
				break;
			}
			c->value = g.value;
			c->lo = g.lo;
			c->hi = g.hi;
			break;
		}
		case SSCOPE_DATASHEET_RUN_TO_RUN_BIAS:
			c->why = "one record cannot show it: it needs several turn-ons";
			break;
		case SSCOPE_DATASHEET_BIAS_TEMPCO:
			c->why = "the record's temperatures are not given here (sensorscope lot and tempbias check it with a temperature column)";
			break;
		case SSCOPE_DATASHEET_BIAS_OFFSET:
		case SSCOPE_DATASHEET_RATE_RAMP: {
			struct sscope_lot_bias_opts bo = { 0 };
			struct sscope_lot_bias b;
			bool drift = s->line == SSCOPE_DATASHEET_RATE_RAMP;

			bo.level = level;
			/* the noise model of the ramp's interval: the terms the
			 * fit shows (flicker and a random walk correlate the
			 * block means) */
			for (int t = 0; t < 3 && res && res->have_fit; t++) {
				const struct sscope_noise_coef *k = &res->fit.coef[SSCOPE_TERM_N + t];

				*(t == 0 ? &bo.n : t == 1 ? &bo.b : &bo.k) =
					k->present && isfinite(k->value) ? k->value : 0;
			}
			if (sscope_lot_bias(x, stride, n, rate_hz, NULL, 0, &bo, &b)) {
				c->why = "the bias needs at least 40 samples, none of them NaN";
				break;
			}
			c->value = drift ? b.drift_u_s : b.bias;
			c->lo = drift ? b.drift_lo : b.bias_lo;
			c->hi = drift ? b.drift_hi : b.bias_hi;
			/* block means correlated beyond what the noise model
			 * (B, K) explains: the ramp's interval, which then
			 * takes them as independent, is too narrow */
			if (drift && b.resid_correlated && !(bo.b > 0) && !(bo.k > 0)) {
				c->why = "the bias wanders (the block means' residuals correlated while the fit shows neither B nor K), which a ramp's interval does not allow for: inconclusive";
				doubt = true;
			}
			break;
		}
		case SSCOPE_DATASHEET_SCALE_FACTOR:
			c->why = "a static record cannot show it: it needs known rates (a rate table)";
			break;
		default:
			from_term(res, s, c);
			break;
		}
		/* measured on a moving record, or from a fit the chi-squared
		 * test rejects: indicative only, no verdict */
		if (moves && (!isnan(c->value) || c->bound)) {
			c->why = "the record moves (its variance over 1 s windows spans more than 9 times): a datasheet check needs the sensor at rest: inconclusive";
			doubt = true;
		}
		if (c->fit_rejected)
			doubt = true;
		c->verdict = doubt ? SSCOPE_DATASHEET_INCONCLUSIVE :
			infos[s->line].magnitude ?
			sscope_datasheet_verdict_magnitude(c->lo, c->hi, c->limit) :
			sscope_datasheet_verdict(c->bound ? 0 : c->lo, c->hi,
						 c->limit);
	}
	sscope_allan_result_free(res);
	return 0;
}
