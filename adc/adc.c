/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Converter model and the analytical "will this ADC degrade the sensor"
 * terms.  Quantization noise q^2/12 and the dither bound follow Widrow &
 * Kollar, "Quantization Noise" (Cambridge, 2008), ch. 4-5 and 11 (bias of
 * a quantizer under Gaussian input: (q/pi) exp(-2 pi^2 sigma^2 / q^2));
 * the Allan-variance forms (q^2/(12 fs tau) for rate rounding, 3 Q^2 /
 * tau^2 for integrating counters) are IEEE Std 952-1997 Annex C; transfer
 * function, transition levels and code conventions follow IEEE Std
 * 1241-2010 section 4.
 */
#include "internal.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_rng.h>
#include <gsl/gsl_randist.h>

#include "sscope-adc.h"
#include "sscope-quantity.h"
#include "sscope-sensor.h"
#include "sscope-unit.h"


static const char *const adc_keys[] = {
	"name", "bits", "range", "rate", "noise", "snr", "enob", "inl", "dnl",
	"offset", "gain_error", "offset_drift", "gain_drift", "ref_temp",
	"reference", "mode", "coding", "oversample", "inl_profile", NULL
};

const char *const *sscope_adc_spec_keys(void)
{
	return adc_keys;
}

/* ------------------------------------------------------------ parsing */

static const char *skip_ws(const char *p)
{
	while (*p && isspace((unsigned char)*p))
		p++;
	return p;
}

int sscope_adc_range_parse(const char *text, double *lo_si, double *hi_si,
			   struct sscope_unit *unit, struct sscope_diag *diag)
{
	const char *colon = strchr(text, ':');
	const char *end = text + strlen(text);
	struct sscope_unit u1, u2;
	struct sscope_diag d = { "" };
	double lo, hi, v;
	size_t k;
	int rc;

	if (!colon) {
		/* "R UNIT": +-R */
		rc = sscope_quantity_parse(text, &v, unit, &d);
		if (rc)
			return ssc_diag(diag, -EINVAL, "%s", d.msg);
		if (!(v > 0))
			return ssc_diag(diag, -EINVAL,
					"'%s': a single value means +-value and must be positive",
					text);
		*lo_si = -v;
		*hi_si = v;
		return 0;
	}
	/* LO (maybe with a unit) */
	{
		char buf[128];
		size_t len = (size_t)(colon - text);

		if (len >= sizeof(buf))
			return ssc_diag(diag, -EINVAL, "'%s': too long", text);
		memcpy(buf, text, len);
		buf[len] = 0;
		k = ssc_parse_double(skip_ws(buf), buf + len, &lo);
		if (!k)
			return ssc_diag(diag, -EINVAL, "'%s': LO is not a number", text);
		if (*skip_ws(skip_ws(buf) + k)) {
			rc = sscope_quantity_parse(buf, &lo, &u1, &d);
			if (rc)
				return ssc_diag(diag, -EINVAL, "%s", d.msg);
		} else {
			rc = sscope_unit_parse("", &u1, NULL);
			if (rc)
				return rc;
		}
	}
	{
		const char *h = skip_ws(colon + 1);

		k = ssc_parse_double(h, end, &hi);
		if (!k)
			return ssc_diag(diag, -EINVAL, "'%s': HI is not a number", text);
		if (*skip_ws(h + k)) {
			double raw = hi;

			rc = sscope_quantity_parse(h, &hi, &u2, &d);
			if (rc)
				return ssc_diag(diag, -EINVAL, "%s", d.msg);
			/* a unit written only after HI applies to both */
			if (sscope_unit_quantity(&u1) == SSCOPE_QUANTITY_DIMENSIONLESS &&
			    u1.scale == 1)
				lo = sscope_unit_to_si(&u2, lo);
			else if (!sscope_unit_compatible(&u1, &u2))
				return ssc_diag(diag, -EINVAL,
						"'%s': LO and HI have different units", text);
			(void)raw;
		} else {
			u2 = u1;
		}
	}
	if (!isfinite(lo) || !isfinite(hi) || !(lo < hi))
		return ssc_diag(diag, -EINVAL, "'%s': LO must be below HI", text);
	if (!isfinite(hi - lo))
		return ssc_diag(diag, -EINVAL, "'%s': the span HI - LO exceeds the double range",
				text);
	*lo_si = lo;
	*hi_si = hi;
	if (unit)
		*unit = u2;
	return 0;
}

/* a number with an optional trailing "LSB" */
static int parse_lsb(const char *v, double *out)
{
	const char *p = skip_ws(v), *end = p + strlen(p);
	size_t k = ssc_parse_double(p, end, out);

	if (!k || !isfinite(*out))
		return -EINVAL;
	p = skip_ws(p + k);
	if (*p && strncasecmp(p, "lsb", 3) != 0)
		return -EINVAL;
	if (*p && *skip_ws(p + 3))
		return -EINVAL;
	return 0;
}

/* a ratio: bare numbers in ppm; ppm, %, ... allowed */
static int parse_ratio(const char *v, double per_degc, double *out,
		       const char **why)
{
	struct sscope_unit u, want;
	double x;

	if (sscope_quantity_parse(v, &x, &u, NULL)) {
		*why = "unknown unit";
		return -EINVAL;
	}
	if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS && u.scale == 1 &&
	    !per_degc) {
		*out = x * 1e-6;
		return 0;
	}
	if (per_degc) {
		if (sscope_unit_parse("ppm/degC", &want, NULL))
			return -EINVAL;
		if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS &&
		    u.scale == 1) {
			*out = x * 1e-6;
			return 0;
		}
		if (!sscope_unit_compatible(&u, &want)) {
			*why = "wrong unit (expected ppm/degC)";
			return -EINVAL;
		}
		*out = x; /* SI: ratio per degC */
		return 0;
	}
	if (sscope_unit_quantity(&u) != SSCOPE_QUANTITY_DIMENSIONLESS) {
		*why = "wrong unit (expected a ratio, e.g. ppm or %)";
		return -EINVAL;
	}
	*out = x;
	return 0;
}

int ssc_adc_spec_from_ini(const struct ssc_ini *ini, const char *section,
			  struct sscope_adc_spec *s, struct sscope_diag *diag)
{
	const char *file = ssc_ini_name(ini), *v, *why = "";
	struct sscope_diag d = { "" };
	struct sscope_unit ru;
	char si[64];
	long bits;
	size_t line;
	int rc;

	memset(s, 0, sizeof(*s));
	s->ref_temp_degc = 25;
	s->oversample = 1;
	if (!ssc_ini_has_section(ini, section))
		return ssc_diag(diag, -EINVAL, "%s: no [%s] section", file, section);
	rc = ssc_ini_check_keys(ini, section, adc_keys, diag);
	if (rc)
		return rc;
	v = ssc_ini_get(ini, section, "name", &line);
	snprintf(s->name, sizeof(s->name), "%s", v ? v : file);
	rc = ssc_ini_integer(ini, section, "bits", 1, SSCOPE_ADC_MAX_BITS,
			     &bits, &d);
	if (rc == -ENOENT)
		return ssc_diag(diag, -EINVAL, "%s: [%s] bits: missing", file, section);
	if (rc)
		return ssc_diag(diag, -EINVAL, "%s (bits: an integer 1..%d)", d.msg,
				SSCOPE_ADC_MAX_BITS);
	s->bits = (int)bits;
	v = ssc_ini_get(ini, section, "range", &line);
	if (!v)
		return ssc_diag(diag, -EINVAL, "%s: [%s] range: missing", file, section);
	rc = sscope_adc_range_parse(v, &s->lo, &s->hi, &ru, &d);
	if (rc)
		return ssc_diag(diag, -EINVAL, "%s: line %zu: range: %s", file, line,
				d.msg);
	s->quantity = sscope_unit_quantity(&ru);
	switch (s->quantity) {
	case SSCOPE_QUANTITY_VOLTAGE:
		s->analog = true;
		break;
	case SSCOPE_QUANTITY_ANGULAR_RATE:
	case SSCOPE_QUANTITY_ACCELERATION:
		break;
	default:
		return ssc_diag(diag, -EINVAL,
				"%s: line %zu: range: '%s' needs a unit: volts (V, mV) or a sensor rate unit (deg/s, m/s^2, g)",
				file, line, v);
	}
	snprintf(si, sizeof(si), "%s", sscope_quantity_si_unit(s->quantity));
	rc = ssc_ini_quantity(ini, section, "rate", "Hz", &s->rate_hz, diag);
	if (rc && rc != -ENOENT)
		return rc;
	if (!rc) {
		if (!(s->rate_hz > 0))
			return ssc_diag(diag, -EINVAL, "%s: [%s] rate: must be positive",
					file, section);
		s->has |= SSCOPE_ADC_HAS_RATE;
	}
	rc = ssc_ini_quantity(ini, section, "noise", si, &s->noise, diag);
	if (rc && rc != -ENOENT)
		return rc;
	if (!rc) {
		if (!(s->noise >= 0))
			return ssc_diag(diag, -EINVAL, "%s: [%s] noise: must not be negative",
					file, section);
		s->has |= SSCOPE_ADC_HAS_NOISE;
	}
	v = ssc_ini_get(ini, section, "enob", &line);
	if (v) {
		if (parse_lsb(v, &s->enob) || !(s->enob > 0) || s->enob > s->bits)
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: enob: '%s' is not a number in (0, bits]",
					file, line, v);
		s->has |= SSCOPE_ADC_HAS_ENOB;
	}
	v = ssc_ini_get(ini, section, "snr", &line);
	if (v) {
		double db;
		const char *p = skip_ws(v);
		size_t k = ssc_parse_double(p, p + strlen(p), &db);

		if (!k || (*skip_ws(p + k) && strcasecmp(skip_ws(p + k), "dB")))
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: snr: '%s' is not a number of dB",
					file, line, v);
		if (s->has & SSCOPE_ADC_HAS_ENOB)
			return ssc_diag(diag, -EINVAL, "%s: [%s] snr: give snr or enob, not both",
					file, section);
		s->enob = (db - 1.76) / 6.02;
		if (!(s->enob > 0))
			return ssc_diag(diag, -EINVAL, "%s: line %zu: snr: too low", file, line);
		if (s->enob > s->bits)
			s->enob = s->bits;
		s->has |= SSCOPE_ADC_HAS_ENOB;
	}
	if ((s->has & SSCOPE_ADC_HAS_ENOB) && (s->has & SSCOPE_ADC_HAS_NOISE))
		return ssc_diag(diag, -EINVAL, "%s: [%s] noise: give noise or enob/snr, not both",
				file, section);
	v = ssc_ini_get(ini, section, "inl", &line);
	if (v) {
		if (parse_lsb(v, &s->inl_lsb) || s->inl_lsb < 0)
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: inl: '%s' is not a non-negative number of LSB",
					file, line, v);
		s->has |= SSCOPE_ADC_HAS_INL;
	}
	v = ssc_ini_get(ini, section, "dnl", &line);
	if (v) {
		if (parse_lsb(v, &s->dnl_lsb) || s->dnl_lsb < 0 || s->dnl_lsb >= 1)
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: dnl: '%s' is not a number of LSB in [0, 1)",
					file, line, v);
		s->has |= SSCOPE_ADC_HAS_DNL;
	}
	v = ssc_ini_get(ini, section, "inl_profile", &line);
	if (v) {
		if (!*v)
			return ssc_diag(diag, -EINVAL, "%s: line %zu: inl_profile: empty (a file name)",
					file, line);
		if (strlen(v) >= sizeof(s->inl_profile))
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: inl_profile: file name longer than %zu characters",
					file, line, sizeof(s->inl_profile) - 1);
		if (s->bits > SSCOPE_ADC_TABLE_BITS)
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: inl_profile: a profile needs bits <= %d (this converter has %d: 2^%d values)",
					file, line, SSCOPE_ADC_TABLE_BITS, s->bits, s->bits);
		if (s->has & (SSCOPE_ADC_HAS_INL | SSCOPE_ADC_HAS_DNL))
			return ssc_diag(diag, -EINVAL,
					"%s: [%s] inl_profile: give inl_profile or the inl/dnl bounds, not both (the profile defines them)",
					file, section);
		snprintf(s->inl_profile, sizeof(s->inl_profile), "%s", v);
	}
	rc = ssc_ini_quantity(ini, section, "offset", si, &s->offset, diag);
	if (rc && rc != -ENOENT)
		return rc;
	v = ssc_ini_get(ini, section, "gain_error", &line);
	if (v && parse_ratio(v, 0, &s->gain_error, &why))
		return ssc_diag(diag, -EINVAL, "%s: line %zu: gain_error: '%s': %s",
				file, line, v, why);
	{
		char per[80];

		snprintf(per, sizeof(per), "%s/degC", si);
		rc = ssc_ini_quantity(ini, section, "offset_drift", per,
				      &s->offset_drift, diag);
		if (rc && rc != -ENOENT)
			return rc;
		if (!rc) {
			if (s->offset_drift < 0)
				return ssc_diag(diag, -EINVAL,
						"%s: [%s] offset_drift: must not be negative (a magnitude)",
						file, section);
			s->has |= SSCOPE_ADC_HAS_OFFSET_DRIFT;
		}
	}
	v = ssc_ini_get(ini, section, "gain_drift", &line);
	if (v) {
		if (parse_ratio(v, 1, &s->gain_drift, &why))
			return ssc_diag(diag, -EINVAL, "%s: line %zu: gain_drift: '%s': %s",
					file, line, v, why);
		if (s->gain_drift < 0)
			return ssc_diag(diag, -EINVAL,
					"%s: [%s] gain_drift: must not be negative (a magnitude)",
					file, section);
		s->has |= SSCOPE_ADC_HAS_GAIN_DRIFT;
	}
	rc = ssc_ini_quantity(ini, section, "ref_temp", "degC",
			      &s->ref_temp_degc, diag);
	if (rc && rc != -ENOENT)
		return rc;
	v = ssc_ini_get(ini, section, "reference", &line);
	if (v) {
		if (!strcasecmp(v, "absolute"))
			s->reference = SSCOPE_ADC_ABSOLUTE;
		else if (!strcasecmp(v, "ratiometric"))
			s->reference = SSCOPE_ADC_RATIOMETRIC;
		else
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: reference: '%s' (absolute|ratiometric)",
					file, line, v);
	}
	v = ssc_ini_get(ini, section, "mode", &line);
	if (v) {
		if (!strcasecmp(v, "round"))
			s->mode = SSCOPE_ADC_ROUND;
		else if (!strcasecmp(v, "integrate"))
			s->mode = SSCOPE_ADC_INTEGRATE;
		else
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: mode: '%s' (round|integrate)",
					file, line, v);
	}
	{
		long os = 1;

		rc = ssc_ini_integer(ini, section, "oversample", 1, 65536, &os, &d);
		if (rc && rc != -ENOENT)
			return ssc_diag(diag, -EINVAL, "%s (oversample: an integer 1..65536)",
					d.msg);
		s->oversample = (unsigned)os;
	}
	v = ssc_ini_get(ini, section, "coding", &line);
	if (v) {
		static const char *const codings[] = {
			"twos-complement", "offset-binary", "straight-binary",
			"sign-magnitude", NULL
		};
		size_t i;

		for (i = 0; codings[i]; i++)
			if (!strcasecmp(v, codings[i]))
				break;
		if (!codings[i])
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: coding: '%s' (twos-complement|offset-binary|straight-binary|sign-magnitude)",
					file, line, v);
		snprintf(s->coding, sizeof(s->coding), "%s", codings[i]);
	} else {
		snprintf(s->coding, sizeof(s->coding), "%s",
			 s->lo < 0 ? "twos-complement" : "straight-binary");
	}
	return 0;
}

int sscope_adc_spec_load(const char *path, struct sscope_adc_spec *spec,
			 struct sscope_diag *diag)
{
	struct ssc_ini *ini = NULL;
	int rc = ssc_ini_load(&ini, path, diag);

	if (rc)
		return rc;
	rc = ssc_adc_spec_from_ini(ini, "adc", spec, diag);
	ssc_ini_free(ini);
	return rc;
}

/* ------------------------------------------------------------ digitizer */

struct sscope_adc {
	struct sscope_adc_spec s;
	double sens, zero;   /* U -> range units */
	double q;            /* LSB, range units */
	int64_t max_code;
	double *trans;       /* transition levels (k = 1..max_code), or NULL */
	gsl_rng *rng;
	uint64_t seed;
	double acc;          /* integrating: running integral, range units s */
	int64_t count;       /* integrating: counts emitted */
	double enob_sd;      /* converter noise implied by the ENOB */
};

static uint64_t splitmix64(uint64_t x)
{
	x += 0x9E3779B97F4A7C15ull;
	x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
	x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
	return x ^ (x >> 31);
}

static unsigned long seed32(uint64_t seed, uint64_t salt)
{
	return (unsigned long)(splitmix64(seed ^ splitmix64(salt)) & 0xffffffffu);
}

int sscope_adc_new(struct sscope_adc **out, const struct sscope_adc_spec *spec,
		   double sensitivity, double zero_v, uint64_t seed,
		   struct sscope_diag *diag)
{
	struct sscope_adc *a;

	if (!out || !spec)
		return -EINVAL;
	*out = NULL;
	if (spec->bits < 1 || spec->bits > SSCOPE_ADC_MAX_BITS || !(spec->lo < spec->hi) ||
	    !isfinite(spec->hi - spec->lo))
		return ssc_diag(diag, -EINVAL, "bad converter word length or range");
	if (spec->analog && !(sensitivity > 0))
		return ssc_diag(diag, -EINVAL,
				"an analog converter needs the sensor's sensitivity (V per unit)");
	a = calloc(1, sizeof(*a));
	if (!a)
		return -ENOMEM;
	a->s = *spec;
	a->sens = spec->analog ? sensitivity : 1;
	a->zero = spec->analog ? zero_v : 0;
	a->q = (spec->hi - spec->lo) / ldexp(1, spec->bits);
	a->max_code = (int64_t)((UINT64_C(1) << spec->bits) - 1);
	a->seed = seed;
	if (spec->enob > 0 && !(spec->noise > 0)) {
		double tot = (spec->hi - spec->lo) / (pow(2, spec->enob) * sqrt(12.0));
		double e2 = tot * tot - a->q * a->q / 12;

		a->enob_sd = e2 > 0 ? sqrt(e2) : 0;
	}
	a->rng = gsl_rng_alloc(gsl_rng_mt19937);
	if (!a->rng) {
		free(a);
		return -ENOMEM;
	}
	if ((spec->inl_lsb > 0 || spec->dnl_lsb > 0) &&
	    spec->bits <= SSCOPE_ADC_TABLE_BITS) {
		/* an S-shaped INL of amplitude inl (zero at the ends and at
		 * mid-scale, so it adds no offset at a bipolar zero) plus
		 * independent transition jitter of +-dnl/2 (widths then differ
		 * by at most dnl) */
		gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
		size_t nc = (size_t)a->max_code + 1;

		a->trans = malloc(nc * sizeof(double));
		if (!r || !a->trans) {
			gsl_rng_free(r);
			sscope_adc_free(a);
			return -ENOMEM;
		}
		gsl_rng_set(r, seed32(seed, 0x1D1));
		a->trans[0] = -INFINITY;
		for (size_t k = 1; k < nc; k++) {
			double bow = spec->inl_lsb * sin(2 * PI * (double)k / (double)nc);
			double j = spec->dnl_lsb * (gsl_rng_uniform(r) - 0.5);

			a->trans[k] = spec->lo + ((double)k - 0.5 + bow + j) * a->q;
		}
		gsl_rng_free(r);
	}
	sscope_adc_reset(a);
	*out = a;
	return 0;
}

void sscope_adc_free(struct sscope_adc *adc)
{
	if (!adc)
		return;
	gsl_rng_free(adc->rng);
	free(adc->trans);
	free(adc);
}

double sscope_adc_lsb(const struct sscope_adc *adc)
{
	return adc->q / adc->sens;
}

void sscope_adc_reset(struct sscope_adc *adc)
{
	gsl_rng_set(adc->rng, seed32(adc->seed, 0xADC));
	adc->acc = 0;
	adc->count = 0;
}

int sscope_adc_set_inl(struct sscope_adc *adc, const double *inl, size_t n)
{
	size_t nc;
	double *t;

	if (!adc || !inl || adc->s.bits > SSCOPE_ADC_TABLE_BITS)
		return -EINVAL;
	nc = (size_t)adc->max_code + 1;
	if (n != nc)
		return -EINVAL;
	t = malloc(nc * sizeof(double));
	if (!t)
		return -ENOMEM;
	t[0] = -INFINITY;
	for (size_t k = 1; k < nc; k++) {
		t[k] = adc->s.lo + ((double)k - 0.5 + inl[k]) * adc->q;
		if (!isfinite(t[k]) || (k > 1 && !(t[k] > t[k - 1]))) {
			free(t);
			return -EINVAL;
		}
	}
	free(adc->trans);
	adc->trans = t;
	return 0;
}

static int64_t to_code(const struct sscope_adc *a, double v)
{
	double f = floor((v - a->s.lo) / a->q + 0.5);
	int64_t k;

	if (!(f > 0))
		k = 0;
	else if (f >= (double)a->max_code)
		k = a->max_code;
	else
		k = (int64_t)f;
	if (a->trans) {
		while (k < a->max_code && v >= a->trans[k + 1])
			k++;
		while (k > 0 && v < a->trans[k])
			k--;
	}
	return k;
}

int sscope_adc_digitize(struct sscope_adc *a, const double *x, size_t stride,
			size_t n, double rate_hz, const double *temp_degc,
			double *out, int64_t *codes, size_t *clipped)
{
	const struct sscope_adc_spec *s;
	double vmin, vmax;

	if (!a || (!x && n) || (!out && n) || !stride || !(rate_hz > 0))
		return -EINVAL;
	s = &a->s;
	vmin = s->lo - 0.5 * a->q;
	vmax = s->hi - 0.5 * a->q;
	for (size_t i = 0; i < n; i++) {
		double v = a->zero + a->sens * x[i * stride];
		double dt = temp_degc ? temp_degc[i] - s->ref_temp_degc : 0;
		double g = s->gain_error;
		int64_t k;

		if (s->reference == SSCOPE_ADC_ABSOLUTE)
			g += s->gain_drift * dt;
		v = s->offset + s->offset_drift * dt + (1 + g) * v;
		if (s->noise > 0)
			v += gsl_ran_gaussian_ziggurat(a->rng, s->noise);
		else if (a->enob_sd > 0)
			v += gsl_ran_gaussian_ziggurat(a->rng, a->enob_sd);
		if (clipped && (v < vmin || v >= vmax))
			(*clipped)++;
		if (s->mode == SSCOPE_ADC_INTEGRATE) {
			double c = a->zero;
			double u = fmin(fmax(v, vmin), vmax) - c;
			int64_t cnt;

			a->acc += u / rate_hz;
			cnt = (int64_t)llround(a->acc * rate_hz / a->q);
			k = cnt - a->count;
			a->count = cnt;
			out[i] = (double)k * a->q / a->sens;
			if (codes)
				codes[i] = k;
			continue;
		}
		k = to_code(a, v);
		if (codes)
			codes[i] = k;
		out[i] = (s->lo + (double)k * a->q - a->zero) / a->sens;
	}
	return 0;
}

/* ------------------------------------------------------------ analysis */

const char *sscope_adc_verdict_name(enum sscope_adc_verdict v)
{
	switch (v) {
	case SSCOPE_ADC_PASS:
		return "pass";
	case SSCOPE_ADC_MARGINAL:
		return "marginal";
	case SSCOPE_ADC_FAIL:
		return "fail";
	default:
		return "info";
	}
}

const char *sscope_adc_term_name(enum sscope_adc_term t)
{
	static const char *const names[] = { "noise", "bias_resolution",
					     "offset_drift", "scale_drift", "range" };

	return (unsigned)t < SSCOPE_ADC_T_COUNT_ ? names[t] : "?";
}

double sscope_adc_dither_bound(double q, double sigma)
{
	if (!(q > 0))
		return 0;
	return q / PI * exp(-2 * PI * PI * sigma * sigma / (q * q));
}

double sscope_adc_bias_error(double q, double sigma, double mu)
{
	/* first harmonic of the mean error of a mid-tread quantizer,
	 * E[Q(x) - x] for x ~ N(mu, sigma^2) */
	return -sscope_adc_dither_bound(q, sigma) * sin(2 * PI * mu / q);
}

double sscope_adc_nbw_factor(int order)
{
	/* ENBW / f3dB of Butterworth low-passes: (pi/2n) / sin(pi/2n) */
	if (order < 1)
		order = 1;
	if (order > 8)
		order = 8;
	return (PI / (2.0 * order)) / sin(PI / (2.0 * order));
}

static void judge(struct sscope_adc_term_result *t, double value, double ref,
		  double ratio, double pass, double fail, bool higher_better)
{
	t->value = value;
	t->reference = ref;
	t->ratio = ratio;
	t->pass_limit = pass;
	t->fail_limit = fail;
	if (!isfinite(ratio))
		t->verdict = SSCOPE_ADC_INFO;
	else if (higher_better)
		t->verdict = ratio >= pass ? SSCOPE_ADC_PASS :
			     ratio < fail ? SSCOPE_ADC_FAIL : SSCOPE_ADC_MARGINAL;
	else
		t->verdict = ratio <= pass ? SSCOPE_ADC_PASS :
			     ratio > fail ? SSCOPE_ADC_FAIL : SSCOPE_ADC_MARGINAL;
}

/* noise and bias terms of a word length with LSB q (U) */
static void wordlength_terms(const struct sscope_sensor_spec *ss,
			     const struct sscope_adc_spec *as, double q,
			     double fs, double sig_s, double sig_a,
			     struct sscope_adc_analysis *r)
{
	double sig = sqrt(sig_s * sig_s + sig_a * sig_a);
	double nq2, na = sig_a / sqrt(fs), N = (ss->has & SSCOPE_SENSOR_HAS_N) ? ss->n : (double)NAN;

	r->lsb = q;
	r->sigma_over_q = sig / q;
	r->dithered = sig >= q / 2;
	r->n_adc = na;
	if (as->mode == SSCOPE_ADC_INTEGRATE) {
		r->n_quant = (double)NAN;
		r->q_quant = q / (fs * sqrt(12.0));
		nq2 = 3 * r->q_quant * r->q_quant; /* 3 Q^2 / tau at tau = 1 s */
		r->adev_q_100s = sqrt(3.0) * r->q_quant / 100;
		r->bias_bound = 0; /* the residual is carried: no lost bias */
	} else {
		r->n_quant = q / sqrt(12 * fs);
		r->q_quant = (double)NAN;
		nq2 = r->n_quant * r->n_quant;
		r->adev_q_100s = q / sqrt(12 * fs * 100);
		r->bias_bound = sscope_adc_dither_bound(q, sig);
	}
	r->n_total = sqrt((isfinite(N) ? N * N : 0) + nq2 + na * na);
	r->noise_degradation = N > 0 ? r->n_total / N - 1 : (double)NAN;
	judge(&r->term[SSCOPE_ADC_T_NOISE], sqrt(nq2 + na * na), N,
	      r->noise_degradation, 0.05, 0.20, false);
	{
		double B = (ss->has & SSCOPE_SENSOR_HAS_B) && ss->b > 0 ? ss->b : (double)NAN;

		judge(&r->term[SSCOPE_ADC_T_BIAS], r->bias_bound, B,
		      r->bias_bound / B, 0.1, 0.5, false);
	}
}

int sscope_adc_analyze(const struct sscope_sensor_spec *ss,
		       const struct sscope_adc_spec *as, double fs,
		       struct sscope_adc_analysis *r, struct sscope_diag *diag)
{
	double sens = 1, zero = 0, fsr_u, sig_s, sig_a = 0, nbw;
	enum sscope_quantity uq;

	if (!ss || !as || !r)
		return -EINVAL;
	memset(r, 0, sizeof(*r));
	if (!(fs > 0))
		fs = as->rate_hz;
	if (!(fs > 0))
		return ssc_diag(diag, -EINVAL,
				"no sample rate: give the converter's rate or --rate");
	uq = ss->quantity;
	if (as->analog) {
		if (!(ss->has & SSCOPE_SENSOR_HAS_SENSITIVITY) || !(ss->sensitivity > 0))
			return ssc_diag(diag, -EINVAL,
					"the converter's range is in volts but the sensor spec gives no sensitivity");
		sens = ss->sensitivity;
		zero = (ss->has & SSCOPE_SENSOR_HAS_ZERO) ? ss->zero_output_v : 0;
	} else if (as->quantity != uq && uq != SSCOPE_QUANTITY_UNKNOWN) {
		return ssc_diag(diag, -EINVAL,
				"the converter's range is in %s units, the sensor measures %s",
				sscope_quantity_name(as->quantity),
				sscope_quantity_name(uq));
	}
	r->rate_hz = fs;
	fs *= as->oversample > 1 ? (double)as->oversample : 1.0; /* conversion rate */
	r->range_lo = (as->lo - zero) / sens;
	r->range_hi = (as->hi - zero) / sens;
	fsr_u = r->range_hi - r->range_lo;
	nbw = fs / 2;
	if ((ss->has & SSCOPE_SENSOR_HAS_BANDWIDTH) && ss->bandwidth_hz > 0)
		nbw = fmin(nbw, ss->bandwidth_hz *
				sscope_adc_nbw_factor(ss->filter_order > 0 ?
						      ss->filter_order : 1));
	sig_s = (ss->has & SSCOPE_SENSOR_HAS_N) ? ss->n * sqrt(2 * nbw) : 0;
	if (as->has & SSCOPE_ADC_HAS_NOISE) {
		sig_a = as->noise / sens;
	} else if (as->has & SSCOPE_ADC_HAS_ENOB) {
		double q = fsr_u / ldexp(1, as->bits);
		double tot = fsr_u / (pow(2, as->enob) * sqrt(12.0));
		double e2 = tot * tot - q * q / 12;

		sig_a = e2 > 0 ? sqrt(e2) : 0;
	}
	r->sigma_sensor = sig_s;
	r->sigma_adc = sig_a;
	wordlength_terms(ss, as, fsr_u / ldexp(1, as->bits), fs, sig_s, sig_a, r);

	/* temperature terms */
	if ((ss->has & SSCOPE_SENSOR_HAS_TEMPS) && ss->temp_max_degc > ss->temp_min_degc) {
		r->temp_span_degc = ss->temp_max_degc - ss->temp_min_degc;
	} else {
		r->temp_span_degc = 60;
		r->temp_span_default = true;
	}
	/* a drift the spec does not give (no flag, no value) is unknown
	 * (its verdict "info"), not 0 */
	r->offset_drift_bias = (as->has & SSCOPE_ADC_HAS_OFFSET_DRIFT) ||
			       as->offset_drift != 0 ?
			       as->offset_drift * r->temp_span_degc / sens :
			       (double)NAN;
	{
		double ref = (double)NAN;

		if ((ss->has & SSCOPE_SENSOR_HAS_TEMPCO) && ss->bias_tempco > 0)
			ref = ss->bias_tempco * r->temp_span_degc;
		else if ((ss->has & SSCOPE_SENSOR_HAS_B) && ss->b > 0)
			ref = ss->b;
		judge(&r->term[SSCOPE_ADC_T_OFFSET_DRIFT], r->offset_drift_bias, ref,
		      r->offset_drift_bias / ref, 0.3, 1, false);
	}
	r->scale_drift = as->reference == SSCOPE_ADC_RATIOMETRIC ? 0 :
			 (as->has & SSCOPE_ADC_HAS_GAIN_DRIFT) || as->gain_drift != 0 ?
			 as->gain_drift * r->temp_span_degc : (double)NAN;
	{
		double ref = (ss->has & SSCOPE_SENSOR_HAS_SF) && ss->scale_factor_error > 0 ?
			     ss->scale_factor_error : (double)NAN;

		judge(&r->term[SSCOPE_ADC_T_SCALE_DRIFT], r->scale_drift, ref,
		      r->scale_drift / ref, 0.3, 1, false);
	}
	if ((ss->has & SSCOPE_SENSOR_HAS_RANGE) && ss->range > 0) {
		double cover = r->range_lo < 0 ? fmin(r->range_hi, -r->range_lo) :
						 r->range_hi;

		r->headroom = cover / ss->range;
		judge(&r->term[SSCOPE_ADC_T_RANGE], r->headroom, ss->range,
		      r->headroom, 1 - 1e-9, 1 - 1e-9, true);
	} else {
		r->headroom = (double)NAN;
		judge(&r->term[SSCOPE_ADC_T_RANGE], (double)NAN, (double)NAN,
		      (double)NAN, 1, 1, true);
	}

	/* minimum word length for the word-length terms */
	r->min_bits = -1;
	for (int b = 1; b <= SSCOPE_ADC_MAX_BITS; b++) {
		struct sscope_adc_analysis t = *r;

		wordlength_terms(ss, as, fsr_u / ldexp(1, b), fs, sig_s, sig_a, &t);
		if (t.term[SSCOPE_ADC_T_NOISE].verdict != SSCOPE_ADC_FAIL &&
		    t.term[SSCOPE_ADC_T_NOISE].verdict != SSCOPE_ADC_MARGINAL &&
		    t.term[SSCOPE_ADC_T_BIAS].verdict != SSCOPE_ADC_FAIL &&
		    t.term[SSCOPE_ADC_T_BIAS].verdict != SSCOPE_ADC_MARGINAL) {
			r->min_bits = b;
			break;
		}
	}

	/* verdict: the worst term; margin of the tightest */
	r->verdict = SSCOPE_ADC_PASS;
	r->margin = INFINITY;
	r->limiting = SSCOPE_ADC_T_NOISE;
	for (int t = 0; t < SSCOPE_ADC_T_COUNT_; t++) {
		const struct sscope_adc_term_result *tr = &r->term[t];
		double m;

		if (tr->verdict == SSCOPE_ADC_INFO)
			continue;
		if (tr->verdict > r->verdict)
			r->verdict = tr->verdict;
		if (t == SSCOPE_ADC_T_RANGE) {
			/* a gate: it limits only when it clips */
			if (tr->verdict != SSCOPE_ADC_FAIL)
				continue;
			m = tr->ratio;
		} else
			m = tr->ratio > 0 ? tr->pass_limit / tr->ratio : (double)INFINITY;
		if (m < r->margin) {
			r->margin = m;
			r->limiting = (enum sscope_adc_term)t;
		}
	}
	if (!isfinite(r->margin))
		r->margin = (double)NAN;
	return 0;
}
