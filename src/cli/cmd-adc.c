/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope adc: "will this converter degrade my sensor?"
 *   adc report   the ADC-selection report: analytical terms per converter
 *                (LSB, quantization noise, dither and the bias it can hide,
 *                drift over temperature, headroom, minimum word length,
 *                verdict) and a Monte-Carlo check (simulate the sensor,
 *                digitize it, fit the Allan terms with and without the
 *                converter); several converters become a ranked table.
 *   adc quantize re-digitize a capture through a candidate converter.
 *   adc test     IEEE 1241 characterisation from a sine capture.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>


#include "plot.h"
#include "stage.h"

#define MAX_ADC 8

enum {
	O_SENSOR = 3100,
	O_ADC,
	O_MC,
	O_MC_DURATION,
	O_SEED,
	O_BITS,
	O_RANGE,
	O_MODE,
	O_BINARY,
	O_FREQ,
};


/* DNL resolution the histogram test must reach (1 sigma), LSB */
#define ADC_DNL_TOL_LSB 0.1
/* ------------------------------------------------------------ helpers */

static double in_unit(double si, const char *si_unit, const char *unit)
{
	double v;

	if (!unit || !si_unit || !isfinite(si) || sscope_unit_convert_text(si, si_unit, unit, &v))
		return si;
	return v;
}

static const char *qty_unit(enum sscope_quantity q, enum sscope_term t,
			    bool si)
{
	const char *u = si ? sscope_term_si_unit(q, t) : sscope_term_unit(q, t);

	return u ? u : "";
}

/* ------------------------------------------------------------ report */

static const struct ssc_option report_opts[] = {
	{ "sensor", required_argument, O_SENSOR, "SENSOR.ini",
	  "sensor specification ([sensor] section)" },
	{ "adc", required_argument, O_ADC, "ADC.ini",
	  "converter specification ([adc] section); repeat for a ranked selection (up to 8)" },
	{ "rate", required_argument, 'r', "HZ",
	  "sample rate (default: each converter's rate)" },
	{ "monte-carlo", required_argument, O_MC, "RUNS",
	  "simulated records per converter (default 4; 0: no Monte-Carlo check)" },
	{ "mc-duration", required_argument, O_MC_DURATION, "S",
	  "length of each simulated record (default 3600 s, at most 30 d; units allowed: 2h)" },
	{ "seed", required_argument, O_SEED, "N", "Monte-Carlo seed (default 1)" },
	{ "plot", required_argument, 'p', "PATH.svg|PATH.png",
	  "ADEV of the sensor alone and through each converter (PNG needs OpenCV)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec report_spec = {
	.name = "adc report",
	.usage = "adc report --sensor SENSOR.ini --adc ADC.ini [--adc ADC2.ini ...] [OPTIONS]",
	.summary =
		"The ADC-selection report: for each converter the LSB in sensor units,\n"
		"the quantization noise (q/sqrt(12 fs)) against the sensor's noise\n"
		"density, the dither criterion (per-sample noise against q/2) with the\n"
		"bias a too-quiet input loses ((q/pi) exp(-2 pi^2 sigma^2/q^2)), offset\n"
		"and reference drift over the temperature range, range headroom, the\n"
		"minimum word length and a verdict (pass / marginal / fail) with its\n"
		"margin and limiting term; then a Monte-Carlo check: the sensor is\n"
		"simulated, digitized and its Allan terms N, B, K fitted with and without\n"
		"the converter (ratios with 68 % intervals over the runs).",
	.options = report_opts,
	.output_opts = true,
	.notes = "Examples:\n"
		 "  sensorscope adc report --sensor samples/gyro-textbook-mems.ini \\\n"
		 "      --adc samples/adc-16bit.ini --adc samples/adc-12bit.ini\n"
		 "  sensorscope adc report --sensor samples/gyro-textbook-quiet.ini \\\n"
		 "      --adc samples/adc-16bit.ini --format json\n"
		 "Thresholds: noise-density increase <= 5 % pass, > 20 % fail; lost bias\n"
		 "<= 0.1 B pass, > 0.5 B fail; drifts <= 0.3 of the sensor's own pass,\n"
		 "> 1 fail; a converter range below the sensor's range fails (clipping).",
};

struct ropts {
	const char *sensor;
	const char *adc[MAX_ADC];
	int n_adc;
	double rate;
	size_t mc;
	double mc_duration;
	unsigned long seed;
	const char *plot;
	const char *mc_opt; /* --mc-duration or --seed given */
};

static void r_init(void *p)
{
	struct ropts *o = p;

	o->mc = 4;
	o->mc_duration = 3600;
	o->seed = 1;
}

static int r_handle(int key, const char *arg, void *ctx)
{
	struct ropts *o = ctx;
	const char *cmd = report_spec.name;

	switch (key) {
	case O_SENSOR:
		o->sensor = arg;
		return 0;
	case O_ADC:
		if (o->n_adc >= MAX_ADC)
			return ssc_usage_error(cmd, "--adc: at most %d converters", MAX_ADC);
		o->adc[o->n_adc++] = arg;
		return 0;
	case 'r':
		return ssc_arg_positive(cmd, "rate", arg, "Hz", &o->rate);
	case O_MC:
		if (ssc_arg_size(cmd, "monte-carlo", arg, &o->mc))
			return SSC_EXIT_USAGE;
		if (o->mc > 1000)
			return ssc_usage_error(cmd, "--monte-carlo: at most 1000 runs");
		return 0;
	case O_MC_DURATION:
		if (ssc_arg_quantity(cmd, "mc-duration", arg, "s", &o->mc_duration))
			return SSC_EXIT_USAGE;
		if (!(o->mc_duration > 0))
			return ssc_usage_error(cmd, "--mc-duration: must be positive");
		if (o->mc_duration > 30 * 86400.0)
			return ssc_usage_error(cmd, "--mc-duration: at most 30 d (each run simulates the whole record)");
		o->mc_opt = "mc-duration";
		return 0;
	case O_SEED: {
		size_t v;

		if (ssc_arg_size(cmd, "seed", arg, &v))
			return SSC_EXIT_USAGE;
		o->seed = (unsigned long)v;
		o->mc_opt = "seed";
		return 0;
	}
	case 'p': {
		int rc = ssc_plot_check(cmd, arg);

		if (rc)
			return rc;
		o->plot = arg;
		return 0;
	}
	default:
		return ssc_usage_error(cmd, "unknown option");
	}
}

struct adc_res {
	const char *path;
	struct sscope_adc_spec spec;
	struct ssc_inl_profile prof; /* inl_profile, or empty */
	struct sscope_adc_analysis an;
	bool mc_done;
	struct sscope_adc_mc mc;  /* ratios, bias shift, ADEV curves of run 0 */
	int rank;
};

static json_t *jratio(const struct sscope_adc_mc_ratio *r)
{
	json_t *o = json_object();

	json_object_set_new(o, "value", ssc_jreal(r->mean));
	json_object_set_new(o, "lo", ssc_jreal(r->lo));
	json_object_set_new(o, "hi", ssc_jreal(r->hi));
	json_object_set_new(o, "runs", json_integer((json_int_t)r->runs));
	json_object_set_new(o, "se", ssc_jreal(r->se));
	return o;
}

static json_t *sensor_json(const struct sscope_sensor_spec *ss, const char *path)
{
	json_t *o = json_object();
	enum sscope_quantity q = ss->quantity;

	json_object_set_new(o, "name", json_string(ss->name));
	json_object_set_new(o, "file", path ? json_string(path) : json_null());
	json_object_set_new(o, "quantity", json_string(sscope_quantity_name(q)));
	if (ss->has & SSCOPE_SENSOR_HAS_RANGE)
		json_object_set_new(o, "range",
				    ssc_json_coef(ss->range, (double)NAN, (double)NAN,
						  q == SSCOPE_QUANTITY_ANGULAR_RATE ? "deg/s" : NULL,
						  sscope_quantity_si_unit(q), true));
	if (ss->has & SSCOPE_SENSOR_HAS_N)
		json_object_set_new(o, "N", ssc_json_coef(ss->n, (double)NAN, (double)NAN,
							  qty_unit(q, SSCOPE_TERM_N, false),
							  qty_unit(q, SSCOPE_TERM_N, true), true));
	if (ss->has & SSCOPE_SENSOR_HAS_B)
		json_object_set_new(o, "B", ssc_json_coef(ss->b, (double)NAN, (double)NAN,
							  qty_unit(q, SSCOPE_TERM_B, false),
							  qty_unit(q, SSCOPE_TERM_B, true), true));
	if (ss->has & SSCOPE_SENSOR_HAS_K)
		json_object_set_new(o, "K", ssc_json_coef(ss->k, (double)NAN, (double)NAN,
							  qty_unit(q, SSCOPE_TERM_K, false),
							  qty_unit(q, SSCOPE_TERM_K, true), true));
	if (ss->has & SSCOPE_SENSOR_HAS_SENSITIVITY)
		json_object_set_new(o, "sensitivity_si", json_real(ss->sensitivity));
	return o;
}

static json_t *adc_json(const struct sscope_sensor_spec *ss, const struct adc_res *ar)
{
	const struct sscope_adc_analysis *a = &ar->an;
	enum sscope_quantity q = ss->quantity;
	const char *bu = qty_unit(q, SSCOPE_TERM_B, false), *bsi = qty_unit(q, SSCOPE_TERM_B, true);
	const char *nu = qty_unit(q, SSCOPE_TERM_N, false), *nsi = qty_unit(q, SSCOPE_TERM_N, true);
	json_t *o = json_object(), *lsb = json_object(), *terms = json_object();
	json_t *checks = json_array();

	json_object_set_new(o, "name", json_string(ar->spec.name));
	json_object_set_new(o, "file", json_string(ar->path));
	json_object_set_new(o, "bits", json_integer(ar->spec.bits));
	json_object_set_new(o, "mode", json_string(ar->spec.mode == SSCOPE_ADC_INTEGRATE ?
							   "integrate" : "round"));
	json_object_set_new(o, "rate_hz", json_real(a->rate_hz));
	json_object_set_new(o, "oversample", json_integer(ar->spec.oversample > 1 ?
							   ar->spec.oversample : 1));
	json_object_set_new(lsb, "value", ssc_jreal(in_unit(a->lsb, bsi, bu)));
	json_object_set_new(lsb, "unit", json_string(bu));
	json_object_set_new(lsb, "si", ssc_jreal(a->lsb));
	json_object_set_new(o, "lsb", lsb);
	/* INL: the spec's bound, or max |INL| of its inl_profile */
	json_object_set_new(o, "inl_lsb", (ar->spec.has & SSCOPE_ADC_HAS_INL) ?
						 json_real(ar->spec.inl_lsb) : json_null());
	json_object_set_new(o, "inl_from", !(ar->spec.has & SSCOPE_ADC_HAS_INL) ? json_null() :
					   json_string(ar->spec.inl_profile[0] ? "profile" : "bound"));
	json_object_set_new(o, "inl_profile", ar->spec.inl_profile[0] ?
						     json_string(ar->spec.inl_profile) : json_null());
	json_object_set_new(o, "dithered", json_boolean(a->dithered));
	json_object_set_new(o, "sigma_over_q", ssc_jreal(a->sigma_over_q));
	json_object_set_new(o, "min_bits", a->min_bits > 0 ? json_integer(a->min_bits) :
							     json_null());
	json_object_set_new(o, "verdict", json_string(sscope_adc_verdict_name(a->verdict)));
	json_object_set_new(o, "margin", ssc_jreal(a->margin));
	json_object_set_new(o, "limiting", json_string(sscope_adc_term_name(a->limiting)));
	json_object_set_new(o, "rank", json_integer(ar->rank));
	/* integrating mode: white angle noise Q; its ARW entry is the density
	 * sqrt(3) Q with the same AVAR at tau = 1 s (what the noise term uses) */
	if (ar->spec.mode == SSCOPE_ADC_INTEGRATE)
		json_object_set_new(terms, "quantization_Q",
				    ssc_json_coef(a->q_quant, (double)NAN, (double)NAN,
						  qty_unit(q, SSCOPE_TERM_Q, false),
						  qty_unit(q, SSCOPE_TERM_Q, true), true));
	json_object_set_new(terms, "quantization_arw",
			    ssc_json_coef(ar->spec.mode == SSCOPE_ADC_INTEGRATE ?
						  sqrt(3.0) * a->q_quant : a->n_quant,
					  (double)NAN, (double)NAN, nu, nsi, true));
	json_object_set_new(terms, "converter_noise_arw",
			    ssc_json_coef(a->n_adc, (double)NAN, (double)NAN, nu, nsi, true));
	json_object_set_new(terms, "noise_degradation", ssc_jreal(a->noise_degradation));
	json_object_set_new(terms, "adev_q_100s",
			    ssc_json_coef(a->adev_q_100s, (double)NAN, (double)NAN, bu, bsi,
					  true));
	json_object_set_new(terms, "bias_resolution",
			    ssc_json_coef(a->bias_bound, (double)NAN, (double)NAN, bu, bsi,
					  true));
	json_object_set_new(terms, "offset_drift_bias",
			    ssc_json_coef(a->offset_drift_bias, (double)NAN, (double)NAN,
					  bu, bsi, true));
	json_object_set_new(terms, "reference_drift_scale_ppm", ssc_jreal(a->scale_drift * 1e6));
	json_object_set_new(terms, "range_headroom", ssc_jreal(a->headroom));
	if ((ss->has & SSCOPE_SENSOR_HAS_BIAS) && ar->spec.mode == SSCOPE_ADC_ROUND)
		json_object_set_new(terms, "sensor_bias_error",
				    ssc_json_coef(sscope_adc_bias_error(a->lsb, a->sigma_over_q * a->lsb,
									ss->bias),
						  (double)NAN, (double)NAN, bu, bsi, true));
	json_object_set_new(terms, "temp_span_degc", ssc_jreal(a->temp_span_degc));
	json_object_set_new(terms, "temp_span_assumed", json_boolean(a->temp_span_default));
	json_object_set_new(o, "terms", terms);
	for (int t = 0; t < SSCOPE_ADC_T_COUNT_; t++) {
		const struct sscope_adc_term_result *tr = &a->term[t];
		json_t *c = json_object();

		json_object_set_new(c, "term", json_string(sscope_adc_term_name((enum sscope_adc_term)t)));
		json_object_set_new(c, "ratio", ssc_jreal(tr->ratio));
		json_object_set_new(c, "pass_limit", ssc_jreal(tr->pass_limit));
		json_object_set_new(c, "fail_limit", ssc_jreal(tr->fail_limit));
		json_object_set_new(c, "verdict", json_string(sscope_adc_verdict_name(tr->verdict)));
		json_array_append_new(checks, c);
	}
	json_object_set_new(o, "checks", checks);
	if (ar->mc_done) {
		json_t *m = json_object();

		json_object_set_new(m, "N_ratio", ssc_jreal(ar->mc.ratio[0].mean));
		json_object_set_new(m, "B_ratio", ssc_jreal(ar->mc.ratio[1].mean));
		json_object_set_new(m, "K_ratio", ssc_jreal(ar->mc.ratio[2].mean));
		json_object_set_new(m, "N", jratio(&ar->mc.ratio[0]));
		json_object_set_new(m, "B", jratio(&ar->mc.ratio[1]));
		json_object_set_new(m, "K", jratio(&ar->mc.ratio[2]));
		json_object_set_new(m, "bias_shift",
				    ssc_json_coef(ar->mc.bias_shift.mean, ar->mc.bias_shift.lo,
						  ar->mc.bias_shift.hi, bu, bsi, true));
		json_object_set_new(m, "runs", json_integer((json_int_t)ar->mc.runs));
		json_object_set_new(m, "duration_s", json_real(ar->mc.duration_s));
		json_object_set_new(m, "interval_level", json_real(0.6827));
		json_object_set_new(m, "clipped_samples", json_integer((json_int_t)ar->mc.clipped));
		json_object_set_new(o, "monte_carlo", m);
	} else {
		json_object_set_new(o, "monte_carlo", json_null());
	}
	return o;
}

static const char *fmtu(char *buf, size_t len, double si, const char *si_unit,
			const char *unit, int sig)
{
	char v[48];

	snprintf(buf, len, "%s %s", ssc_fmt(v, sizeof(v), in_unit(si, si_unit, unit), sig),
		 unit);
	return buf;
}

static void adc_text(FILE *f, const struct sscope_sensor_spec *ss, const struct adc_res *ar)
{
	const struct sscope_adc_analysis *a = &ar->an;
	enum sscope_quantity q = ss->quantity;
	const char *bu = qty_unit(q, SSCOPE_TERM_B, false), *bsi = qty_unit(q, SSCOPE_TERM_B, true);
	const char *nu = qty_unit(q, SSCOPE_TERM_N, false), *nsi = qty_unit(q, SSCOPE_TERM_N, true);
	char b1[64], b2[64], b3[64];

	fprintf(f, "\n== %s (%s): %d bits, %s, %s Hz", ar->spec.name, ar->path,
		ar->spec.bits, ar->spec.mode == SSCOPE_ADC_INTEGRATE ? "integrating" : "rate rounding",
		ssc_fmt(b1, sizeof(b1), a->rate_hz, 6));
	if (ar->spec.oversample > 1)
		fprintf(f, " (%u conversions averaged per sample)", ar->spec.oversample);
	fputc('\n', f);
	fprintf(f, "  LSB                     %s  (range %s .. %s)\n",
		fmtu(b1, sizeof(b1), a->lsb, bsi, bu, 4),
		fmtu(b2, sizeof(b2), a->range_lo, sscope_quantity_si_unit(q),
		     q == SSCOPE_QUANTITY_ANGULAR_RATE ? "deg/s" : sscope_quantity_si_unit(q), 5),
		fmtu(b3, sizeof(b3), a->range_hi, sscope_quantity_si_unit(q),
		     q == SSCOPE_QUANTITY_ANGULAR_RATE ? "deg/s" : sscope_quantity_si_unit(q), 5));
	if (ar->spec.has & SSCOPE_ADC_HAS_INL)
		fprintf(f, "  INL                     %s LSB = %s  (%s%s)\n",
			ssc_fmt(b1, sizeof(b1), ar->spec.inl_lsb, 3),
			fmtu(b2, sizeof(b2), ar->spec.inl_lsb * a->lsb, bsi, bu, 3),
			ar->spec.inl_profile[0] ? "max |INL| of the profile " : "bound",
			ar->spec.inl_profile);
	if (ar->spec.mode == SSCOPE_ADC_INTEGRATE)
		fprintf(f, "  quantization Q          %s  (residual carried: no lost bias)\n",
			fmtu(b1, sizeof(b1), a->q_quant, qty_unit(q, SSCOPE_TERM_Q, true),
			     qty_unit(q, SSCOPE_TERM_Q, false), 3));
	else
		fprintf(f, "  quantization ARW        %s  (q/sqrt(12 %sfs); ADEV at 100 s %s)\n",
			fmtu(b1, sizeof(b1), a->n_quant, nsi, nu, 3),
			ar->spec.oversample > 1 ? "M " : "",
			fmtu(b2, sizeof(b2), a->adev_q_100s, bsi, bu, 3));
	if (a->n_adc > 0)
		fprintf(f, "  converter noise ARW     %s\n", fmtu(b1, sizeof(b1), a->n_adc, nsi, nu, 3));
	if (isfinite(a->noise_degradation))
		fprintf(f, "  noise density           %s -> %s  (+%s %%)  %s\n",
			fmtu(b1, sizeof(b1), ss->n, nsi, nu, 3),
			fmtu(b2, sizeof(b2), a->n_total, nsi, nu, 3),
			ssc_fmt(b3, sizeof(b3), 100 * a->noise_degradation, 2),
			sscope_adc_verdict_name(a->term[SSCOPE_ADC_T_NOISE].verdict));
	fprintf(f, "  dither                  sigma/q = %s: %s\n",
		ssc_fmt(b1, sizeof(b1), a->sigma_over_q, 3),
		a->dithered ? "dithered (sigma >= q/2): sub-LSB signals survive" :
		a->sigma_over_q < 0.3 ? "NOT dithered (sigma < 0.3 q): sub-LSB bias is lost, ADEV can collapse" :
					"weakly dithered (0.3 q <= sigma < q/2)");
	if (a->bias_bound < 1e-9 * a->lsb) {
		/* below what the double's arithmetic resolves: a bound, in
		 * the same unit as B */
		char t[48];

		snprintf(b1, sizeof(b1), "< %s", fmtu(t, sizeof(t), 1e-9 * a->lsb, bsi, bu, 2));
	}
	fprintf(f, "  bias it can hide        %s%s%s  %s\n",
		a->bias_bound < 1e-9 * a->lsb ? b1 :
		fmtu(b1, sizeof(b1), a->bias_bound, bsi, bu, 3),
		(ss->has & SSCOPE_SENSOR_HAS_B) ? " vs B " : "",
		(ss->has & SSCOPE_SENSOR_HAS_B) ? fmtu(b2, sizeof(b2), ss->b, bsi, bu, 3) : "",
		sscope_adc_verdict_name(a->term[SSCOPE_ADC_T_BIAS].verdict));
	if (isfinite(a->offset_drift_bias))
		fprintf(f, "  offset drift -> bias    %s over %s degC%s  %s\n",
			fmtu(b1, sizeof(b1), a->offset_drift_bias, bsi, bu, 3),
			ssc_fmt(b2, sizeof(b2), a->temp_span_degc, 3),
			a->temp_span_default ? " (assumed)" : "",
			sscope_adc_verdict_name(a->term[SSCOPE_ADC_T_OFFSET_DRIFT].verdict));
	else
		fprintf(f, "  offset drift -> bias    unknown: the converter's spec gives no offset_drift\n");
	if (isfinite(a->scale_drift))
		fprintf(f, "  reference drift -> SF   %s ppm%s  %s\n",
			ssc_fmt(b1, sizeof(b1), a->scale_drift * 1e6, 3),
			ar->spec.reference == SSCOPE_ADC_RATIOMETRIC ? " (ratiometric: cancels)" : "",
			sscope_adc_verdict_name(a->term[SSCOPE_ADC_T_SCALE_DRIFT].verdict));
	else
		fprintf(f, "  reference drift -> SF   unknown: the converter's spec gives no gain_drift\n");
	if (isfinite(a->headroom))
		fprintf(f, "  range headroom          x%s  %s\n",
			ssc_fmt(b1, sizeof(b1), a->headroom, 4),
			a->headroom < 1 ? "fail: the sensor's range clips" : "pass");
	if (a->min_bits > 0)
		fprintf(f, "  minimum word length     %d bits\n", a->min_bits);
	else
		fprintf(f, "  minimum word length     none up to %d bits (converter noise too high)\n",
			SSCOPE_ADC_MAX_BITS);
	fprintf(f, "  verdict                 %s (limiting: %s, margin x%s)\n",
		sscope_adc_verdict_name(a->verdict), sscope_adc_term_name(a->limiting),
		ssc_fmt(b1, sizeof(b1), a->margin, 3));
	if ((ss->has & SSCOPE_SENSOR_HAS_BIAS) && ss->bias != 0 &&
	    ar->spec.mode == SSCOPE_ADC_ROUND) {
		double e = sscope_adc_bias_error(a->lsb, a->sigma_over_q * a->lsb, ss->bias);
		double pct = 100 * e / ss->bias;

		/* Dither makes the first harmonic vanish like exp(-2 pi^2
		 * sigma^2 / q^2): below 1e-9 % say so instead of printing a
		 * number like 1e-254 that no instrument could see. */
		if (fabs(pct) < 1e-9)
			snprintf(b3, sizeof(b3), "below 1e-9");
		else
			ssc_fmt(b3, sizeof(b3), pct, 2);
		fprintf(f, "  sensor bias %s reads    %s  (%s %% error, first harmonic)\n",
			fmtu(b1, sizeof(b1), ss->bias, bsi, bu, 3),
			fmtu(b2, sizeof(b2), ss->bias + e, bsi, bu, 3), b3);
	}
	if (ar->mc_done) {
		static const char tn[] = "NBK";

		fprintf(f, "  Monte Carlo (%zu x %s s): fitted term with / without converter\n",
			ar->mc.runs, ssc_fmt(b1, sizeof(b1), ar->mc.duration_s, 6));
		for (int t = 0; t < 3; t++) {
			const struct sscope_adc_mc_ratio *r = &ar->mc.ratio[t];

			if (!isfinite(r->mean)) {
				fprintf(f, "    %c ratio  not fitted in both\n", tn[t]);
				continue;
			}
			fprintf(f, "    %c ratio  %s", tn[t], ssc_fmt(b1, sizeof(b1), r->mean, 4));
			if (isfinite(r->lo))
				fprintf(f, "  [%s, %s]", ssc_fmt(b2, sizeof(b2), r->lo, 4),
					ssc_fmt(b3, sizeof(b3), r->hi, 4));
			if (isfinite(r->se))
				fprintf(f, "  se %s", ssc_fmt(b2, sizeof(b2), r->se, 2));
			fputc('\n', f);
		}
		fprintf(f, "    bias shift %s", fmtu(b1, sizeof(b1), ar->mc.bias_shift.mean, bsi, bu, 3));
		if (isfinite(ar->mc.bias_shift.lo))
			fprintf(f, "  [%s, %s]", ssc_fmt(b2, sizeof(b2), in_unit(ar->mc.bias_shift.lo, bsi, bu), 3),
				ssc_fmt(b3, sizeof(b3), in_unit(ar->mc.bias_shift.hi, bsi, bu), 3));
		fputc('\n', f);
	}
}

/* Top: ADEV of the sensor alone and through each converter, the median of
 * the Monte-Carlo runs with their 10-90 % band; bottom: the ratio of the
 * two in each run (same realisation, so the sensor's own scatter cancels),
 * which is what the verdict is about. */
static int plot_report(const char *path, const struct sscope_sensor_spec *ss,
		       const struct adc_res *ar, int n)
{
	struct ssc_fig *fig = ssc_fig_new(1000, 1000, 2, 1);
	struct ssc_ax *ax = ssc_fig_ax(fig, 0, 0), *rx = ssc_fig_ax(fig, 1, 0);
	enum sscope_quantity q = ss->quantity;
	const char *bu = qty_unit(q, SSCOPE_TERM_B, false), *bsi = qty_unit(q, SSCOPE_TERM_B, true);
	double scale = in_unit(1, bsi, bu);
	char buf[200];
	int rc, drawn = 0;
	size_t runs = 0;

	ssc_ax_log(ax, true, true);
	ssc_ax_grid(ax, true);
	ssc_ax_xlabel(ax, "averaging time \xcf\x84 (s)");
	snprintf(buf, sizeof(buf), "ADEV (%s)", bu);
	ssc_ax_ylabel(ax, buf);
	snprintf(buf, sizeof(buf), "%s: alone and through each converter", ss->name);
	ssc_ax_title(ax, buf);
	ssc_ax_log(rx, true, false);
	ssc_ax_grid(rx, true);
	ssc_ax_xlabel(rx, "averaging time \xcf\x84 (s)");
	ssc_ax_ylabel(rx, "ADEV through / ADEV alone");
	ssc_ax_title(rx, "what each converter adds, run by run");
	for (int i = 0; i < n; i++) {
		const struct adc_res *a = &ar[i];
		size_t np = a->mc.n_points, nr = a->mc.n_runs;
		double *m = malloc(3 * np * sizeof(double));
		double *lo = malloc(3 * np * sizeof(double));
		double *hi = malloc(3 * np * sizeof(double));
		uint32_t col = ssc_plot_color((size_t)i + 1);
		struct ssc_style st = { .color = col, .width = 2, .dash = SSC_DASHED };

		if (!np || !nr) {
			free(m);
			free(lo);
			free(hi);
			continue;
		}
		if (!m || !lo || !hi) {
			free(m);
			free(lo);
			free(hi);
			ssc_fig_free(fig);
			return -ENOMEM;
		}
		runs = nr;
		for (size_t k = 0; k < np; k++) {
			double qv[3];

			sscope_adc_mc_band(&a->mc, SSCOPE_ADC_MC_ALONE, k, qv);
			lo[k] = qv[0] * scale;
			m[k] = qv[1] * scale;
			hi[k] = qv[2] * scale;
			sscope_adc_mc_band(&a->mc, SSCOPE_ADC_MC_THROUGH, k, qv);
			lo[np + k] = qv[0] * scale;
			m[np + k] = qv[1] * scale;
			hi[np + k] = qv[2] * scale;
			sscope_adc_mc_band(&a->mc, SSCOPE_ADC_MC_RATIO, k, qv);
			lo[2 * np + k] = qv[0];
			m[2 * np + k] = qv[1];
			hi[2 * np + k] = qv[2];
		}
		if (!drawn) {
			struct ssc_style s0 = { .color = 0x202020, .width = 2.5 };

			ssc_ax_band(ax, a->mc.tau_s, lo, hi, np, 0x202020, 0.15, NULL);
			ssc_ax_line(ax, a->mc.tau_s, m, np, &s0, "sensor alone");
		}
		snprintf(buf, sizeof(buf), "%s (%d b): %s", a->spec.name, a->spec.bits,
			 sscope_adc_verdict_name(a->an.verdict));
		ssc_ax_band(ax, a->mc.tau_s, lo + np, hi + np, np, col, 0.18, NULL);
		ssc_ax_line(ax, a->mc.tau_s, m + np, np, &st, buf);
		st.dash = SSC_SOLID;
		ssc_ax_band(rx, a->mc.tau_s, lo + 2 * np, hi + 2 * np, np, col, 0.2, NULL);
		ssc_ax_line(rx, a->mc.tau_s, m + 2 * np, np, &st, buf);
		drawn++;
		free(m);
		free(lo);
		free(hi);
	}
	if (!drawn) {
		ssc_fig_free(fig);
		return -EDOM;
	}
	{
		struct ssc_style one = { .color = 0x202020, .width = 1.2, .dash = SSC_DOTTED };

		ssc_ax_hline(rx, 1, &one, "no change");
	}
	snprintf(buf, sizeof(buf), "lines: median of %zu Monte-Carlo runs\nbands: 10-90 %% of the runs\nsensor alone: the first converter's runs; each converter has its own realisations (compare below)", runs);
	ssc_ax_note(ax, buf, SSC_LEGEND_AUTO);
	rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	return rc;
}

struct report_res {
	struct sscope_sensor_spec ss; /* the sensor */
	const char *spath;
	struct adc_res ar[MAX_ADC];
	int n, order[MAX_ADC];
};

static void r_free(void *result)
{
	struct report_res *R = result;

	for (int i = 0; i < R->n; i++) {
		ssc_adc_profile_free(&R->ar[i].prof);
		sscope_adc_mc_clear(&R->ar[i].mc);
	}
	free(R);
}

static int r_check(struct ssc_common *co, void *opts)
{
	struct ropts *o = opts;

	if (o->plot)
		co->plot = o->plot;
	/* options that would be ignored */
	if (o->mc_opt && o->mc == 0)
		return ssc_usage_error(co->cmd, "--%s: no Monte-Carlo check (--monte-carlo 0)",
				       o->mc_opt);
	return SSC_EXIT_OK;
}

/* the Monte-Carlo check's progress: converter and run */
struct mc_progress {
	const struct ssc_common *co;
	int i, n;
};

static void mc_progress(void *ctx, size_t done, size_t total)
{
	const struct mc_progress *p = ctx;

	if (!ssc_progress_on(p->co))
		return;
	fprintf(stderr, "\r%s: Monte Carlo: converter %d of %d, run %zu of %zu   ",
		p->co->cmd, p->i + 1, p->n, done, total);
	fflush(stderr);
}

static int r_run(const struct ssc_stage_env *env, void *opts, void **result)
{
	struct ropts *o = opts;
	const char *cmd = env->co->cmd;
	const struct sscope_sensor_spec *sp;
	const char *paths[MAX_ADC];
	struct report_res *R = calloc(1, sizeof(*R));
	struct adc_res *ar;
	int n = 0, inline_at = -1, rc;

	if (!R) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = R;
	ar = R->ar;
	if (o->sensor) {
		rc = ssc_load_sensor(cmd, o->sensor, &R->ss);
		if (rc)
			return rc;
		R->spath = o->sensor;
	} else if (env->sensor) {
		R->ss = *env->sensor;
		R->spath = env->sensor_path;
	} else {
		return ssc_usage_error(cmd, "no sensor: give --sensor SENSOR.ini");
	}
	sp = &R->ss;
	for (int i = 0; i < o->n_adc; i++)
		paths[n++] = o->adc[i];
	for (size_t i = 0; i < env->n_adc && n < MAX_ADC; i++)
		paths[n++] = env->adc_paths[i];
	if (env->adc_ini && n < MAX_ADC) {
		inline_at = n;
		paths[n++] = ssc_ini_name(env->adc_ini);
	}
	if (!n)
		return ssc_usage_error(cmd, "no converter: give --adc ADC.ini");
	for (int i = 0; i < n; i++, R->n++) {
		struct sscope_diag d = { "" };
		int e;

		ar[i].path = paths[i];
		e = i == inline_at ?
			    ssc_adc_spec_from_ini(env->adc_ini, "adc", &ar[i].spec, &d) :
			    sscope_adc_spec_load(paths[i], &ar[i].spec, &d);
		if (e) {
			R->n++;
			return ssc_fail(cmd, e, &d, "adc spec");
		}
		rc = ssc_adc_profile_load(cmd, paths[i], &ar[i].spec, &ar[i].prof);
		if (rc) {
			R->n++;
			return rc;
		}
		e = sscope_adc_analyze(sp, &ar[i].spec, o->rate, &ar[i].an, &d);
		if (e) {
			R->n++;
			ssc_err(cmd, "%s: %s", paths[i], d.msg[0] ? d.msg : sscope_strerror(e));
			return SSC_EXIT_FAIL;
		}
	}
	for (int i = 0; i < n; i++) {
		struct sscope_diag d = { "" };
		struct mc_progress mp = { env->co, i, n };
		struct sscope_adc_mc_opts mo = { o->mc, o->mc_duration, o->seed,
						 0.6827, ar[i].an.rate_hz,
						 mc_progress, &mp };
		int e;

		if (!o->mc)
			break;
		mc_progress(&mp, 0, o->mc);
		e = sscope_adc_monte_carlo(sp, &ar[i].spec, ar[i].prof.inl,
					   ar[i].prof.n, sp->sensitivity,
					   (sp->has & SSCOPE_SENSOR_HAS_ZERO) ?
						   sp->zero_output_v : 0,
					   &mo, &ar[i].mc, &d);
		if (e) {
			ssc_progress_end(env->co);
			ssc_err(cmd, "Monte Carlo of %s: %s", paths[i],
				d.msg[0] ? d.msg : sscope_strerror(e));
			return SSC_EXIT_FAIL;
		}
		ar[i].mc_done = true;
	}
	ssc_progress_end(env->co);
	{
		struct sscope_adc_analysis an[MAX_ADC];
		int bits[MAX_ADC];
		size_t order[MAX_ADC];

		for (int i = 0; i < n; i++) {
			an[i] = ar[i].an;
			bits[i] = ar[i].spec.bits;
		}
		sscope_adc_rank(an, bits, (size_t)n, order);
		for (int i = 0; i < n; i++)
			R->order[i] = (int)order[i];
	}
	for (int i = 0; i < n; i++)
		ar[R->order[i]].rank = i + 1;
	return SSC_EXIT_OK;
}

static json_t *r_json(const void *opts, const void *result)
{
	const struct report_res *R = result;
	json_t *root = json_object(), *arr = json_array();

	(void)opts;
	json_object_set_new(root, "command", json_string("adc report"));
	json_object_set_new(root, "sensor", sensor_json(&R->ss, R->spath));
	for (int i = 0; i < R->n; i++)
		json_array_append_new(arr, adc_json(&R->ss, &R->ar[i]));
	json_object_set_new(root, "adcs", arr);
	return root;
}

static void r_text(FILE *f, const void *opts, const void *result)
{
	const struct report_res *R = result;
	const struct sscope_sensor_spec *sp = &R->ss;
	char b1[64], b2[64];
	enum sscope_quantity q = sp->quantity;

	(void)opts;
	fprintf(f, "sensor %s (%s)", sp->name, R->spath ? R->spath : "[sensor]");
	if (sp->has & SSCOPE_SENSOR_HAS_N)
		fprintf(f, ": N %s", fmtu(b1, sizeof(b1), sp->n, qty_unit(q, SSCOPE_TERM_N, true),
					   qty_unit(q, SSCOPE_TERM_N, false), 3));
	if (sp->has & SSCOPE_SENSOR_HAS_B)
		fprintf(f, ", B %s", fmtu(b2, sizeof(b2), sp->b, qty_unit(q, SSCOPE_TERM_B, true),
					   qty_unit(q, SSCOPE_TERM_B, false), 3));
	fputc('\n', f);
	for (int i = 0; i < R->n; i++)
		adc_text(f, sp, &R->ar[i]);
	fprintf(f, "\nselection (pass first, then fewest bits, then margin):\n");
	fprintf(f, "  %-4s %-24s %4s %12s %8s %-9s %-16s %s\n", "rank", "converter",
		"bits", "LSB", "min bits", "verdict", "limiting", "margin");
	for (int k = 0; k < R->n; k++) {
		const struct adc_res *a = &R->ar[R->order[k]];
		char l[64], m[32], mbits[16];

		if (a->an.min_bits > 0)
			snprintf(mbits, sizeof(mbits), "%d", a->an.min_bits);
		else
			snprintf(mbits, sizeof(mbits), "none");
		fprintf(f, "  %-4d %-24.24s %4d %12s %8s %-9s %-16s x%s\n", k + 1,
			a->spec.name, a->spec.bits,
			fmtu(l, sizeof(l), a->an.lsb, qty_unit(q, SSCOPE_TERM_B, true),
			     qty_unit(q, SSCOPE_TERM_B, false), 4),
			mbits, sscope_adc_verdict_name(a->an.verdict),
			sscope_adc_term_name(a->an.limiting),
			ssc_fmt(m, sizeof(m), a->an.margin, 3));
	}
}

/* CSV: the selection table */
static void r_csv(FILE *f, const void *opts, const void *result)
{
	const struct report_res *R = result;

	(void)opts;
	fprintf(f, "rank,name,file,bits,lsb_si,min_bits,verdict,limiting,margin,N_ratio,B_ratio,K_ratio\n");
	for (int k = 0; k < R->n; k++) {
		const struct adc_res *a = &R->ar[R->order[k]];
		char mbits[16] = "";

		if (a->an.min_bits > 0)
			snprintf(mbits, sizeof(mbits), "%d", a->an.min_bits);
		fprintf(f, "%d,\"%s\",\"%s\",%d,%.10g,%s,%s,%s,%.6g,%.6g,%.6g,%.6g\n",
			k + 1, a->spec.name, a->path, a->spec.bits, a->an.lsb,
			mbits, sscope_adc_verdict_name(a->an.verdict),
			sscope_adc_term_name(a->an.limiting), a->an.margin,
			a->mc.ratio[0].mean, a->mc.ratio[1].mean, a->mc.ratio[2].mean);
	}
}

static void r_summary(json_t *rows, const void *opts, const void *result)
{
	const struct report_res *R = result;

	(void)opts;
	for (int i = 0; i < R->n; i++) {
		const struct adc_res *a = &R->ar[i];
		char note[96];

		snprintf(note, sizeof(note), "%d bits, limiting %s", a->spec.bits,
			 sscope_adc_term_name(a->an.limiting));
		ssc_summary_add(rows, a->spec.name,
				a->an.verdict == SSCOPE_ADC_PASS ? "ADC verdict: pass, margin" :
				a->an.verdict == SSCOPE_ADC_MARGINAL ? "ADC verdict: marginal, margin" :
									"ADC verdict: fail, margin",
				a->an.margin, (double)NAN, (double)NAN, "x", note);
	}
}

static int r_plot(const struct ssc_common *co, const void *opts,
		  const void *result, const char *path)
{
	const struct report_res *R = result;
	int e = plot_report(path, &R->ss, R->ar, R->n);

	(void)opts;
	if (e == -EDOM)
		return ssc_usage_error(co->cmd, "--plot needs the Monte-Carlo check (--monte-carlo > 0)");
	return e ? ssc_write_failed(co->cmd, path, e) : SSC_EXIT_OK;
}


const struct ssc_stage_ops ssc_adc_stage = {
	.spec = &report_spec,
	.title = "ADC selection",
	.needs = SSC_NEED_SENSOR | SSC_NEED_ADC,
	.min_files = 0,
	.max_files = 0,
	.opts_size = sizeof(struct ropts),
	.init = r_init,
	.handle = r_handle,
	.check = r_check,
	.run = r_run,
	.json = r_json,
	.text = r_text,
	.csv = r_csv,
	.summary = r_summary,
	.plot = r_plot,
	.free_result = r_free,
};

/* ------------------------------------------------------------ quantize */

static const struct ssc_option quant_opts[] = {
	{ "bits", required_argument, O_BITS, "N", "word length (1..32)" },
	{ "range", required_argument, O_RANGE, "LO:HI[ UNIT]",
	  "input range (bare numbers: the channel's unit), e.g. -100:100 or '-2:2 deg/s'" },
	{ "mode", required_argument, O_MODE, "round|integrate",
	  "round each sample (default) or count the integral with the residual carried" },
	{ "adc", required_argument, O_ADC, "ADC.ini",
	  "take bits, range (in sensor units), mode, noise and non-linearity from a converter spec" },
	{ "seed", required_argument, O_SEED, "N", "seed of converter noise (default 1)" },
	{ "binary", required_argument, O_BINARY, "f32|f64",
	  "write a sensorscope binary capture instead of CSV" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec quant_spec = {
	.name = "adc quantize",
	.usage = "adc quantize (--bits N --range LO:HI | --adc ADC.ini) [OPTIONS] FILE",
	.summary =
		"Re-digitize a capture through a candidate converter -- \"what would my\n"
		"recording look like through a cheaper ADC\". The output is a capture\n"
		"(time, the selected channels, temperature) that `allan` and the other\n"
		"commands read; codes are mid-tread, clipped at the range.",
	.options = quant_opts,
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope adc quantize --bits 12 --range -100:100 samples/gyro-static.csv -o q12.csv\n"
		 "  sensorscope adc quantize --bits 14 --range -100:100 samples/gyro-static.csv | \\\n"
		 "      sensorscope allan -",
};

struct qopts {
	long bits;
	const char *range;
	const char *adc;
	int mode; /* -1 not given */
	unsigned long seed;
	enum sscope_capture_format fmt;
};

static int q_handle(int key, const char *arg, void *ctx)
{
	struct qopts *o = ctx;
	const char *cmd = quant_spec.name;

	switch (key) {
	case O_BITS: {
		size_t v;

		if (ssc_arg_size(cmd, "bits", arg, &v))
			return SSC_EXIT_USAGE;
		if (v < 1 || v > SSCOPE_ADC_MAX_BITS)
			return ssc_usage_error(cmd, "--bits: between 1 and %d", SSCOPE_ADC_MAX_BITS);
		o->bits = (long)v;
		return 0;
	}
	case O_RANGE:
		o->range = arg;
		return 0;
	case O_ADC:
		o->adc = arg;
		return 0;
	case O_MODE:
		if (!strcmp(arg, "round"))
			o->mode = SSCOPE_ADC_ROUND;
		else if (!strcmp(arg, "integrate"))
			o->mode = SSCOPE_ADC_INTEGRATE;
		else
			return ssc_usage_error(cmd, "--mode: 'round' or 'integrate', not '%s'", arg);
		return 0;
	case O_SEED: {
		size_t v;

		if (ssc_arg_size(cmd, "seed", arg, &v))
			return SSC_EXIT_USAGE;
		o->seed = (unsigned long)v;
		return 0;
	}
	case O_BINARY:
		if (!strcmp(arg, "f32"))
			o->fmt = SSCOPE_CAPTURE_BIN32;
		else if (!strcmp(arg, "f64"))
			o->fmt = SSCOPE_CAPTURE_BIN64;
		else
			return ssc_usage_error(cmd, "--binary: 'f32' or 'f64'");
		return 0;
	default:
		return ssc_usage_error(cmd, "unknown option");
	}
}

static int cmd_quantize(int argc, char **argv)
{
	struct ssc_common co;
	struct qopts o = { .bits = 0, .mode = -1, .seed = 1, .fmt = SSCOPE_CAPTURE_CSV };
	struct sscope_capture *cap = NULL;
	struct sscope_adc_spec spec;
	struct ssc_inl_profile prof = { NULL, 0 };
	struct sscope_diag d = { "" };
	double *buf = NULL;
	size_t clipped = 0;
	bool added_time = false;
	struct ssc_out sink;
	int first, rc;

	rc = ssc_parse(&quant_spec, argc, argv, &co, q_handle, &o, &first);
	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	if (argc - first != 1)
		return ssc_usage_error(co.cmd, argc - first ? "one input file" : "no input file");
	if (!o.adc && (!o.bits || !o.range))
		return ssc_usage_error(co.cmd, "give --bits N and --range LO:HI, or --adc ADC.ini");
	if (o.adc && (o.bits || o.range))
		return ssc_usage_error(co.cmd, "--adc replaces --bits and --range");
	if (co.plot)
		return ssc_usage_error(co.cmd, "--plot: no figure here (quantize writes a capture)");
	if (co.format != SSC_FMT_TEXT)
		return ssc_usage_error(co.cmd, "--format: the output is a capture (CSV, or --binary)");
	memset(&spec, 0, sizeof(spec));
	if (o.adc) {
		rc = sscope_adc_spec_load(o.adc, &spec, &d);
		if (rc)
			return ssc_fail(co.cmd, rc, &d, "adc spec");
		if (spec.analog)
			return ssc_usage_error(co.cmd,
					       "%s: range in volts; quantize needs a range in the channel's units",
					       o.adc);
		if (spec.oversample > 1)
			return ssc_usage_error(co.cmd,
					       "%s: oversample: a recorded capture cannot be oversampled",
					       o.adc);
		rc = ssc_adc_profile_load(co.cmd, o.adc, &spec, &prof);
		if (rc)
			return rc;
	}
	rc = ssc_load(&co, argv[first], &cap);
	if (rc)
		goto done;
	if (!o.adc) {
		spec.bits = (int)o.bits;
		spec.ref_temp_degc = 25;
		snprintf(spec.name, sizeof(spec.name), "%ld-bit", o.bits);
	}
	if (o.mode >= 0)
		spec.mode = (enum sscope_adc_mode)o.mode;
	if (spec.mode == SSCOPE_ADC_INTEGRATE) {
		rc = ssc_time_check(&co, argv[first], cap, true);
		if (rc)
			goto done;
	}
	if (spec.mode == SSCOPE_ADC_INTEGRATE && !(cap->rate_hz > 0)) {
		rc = ssc_usage_error(co.cmd, "--mode integrate needs the sample rate (--rate or a time column)");
		goto done;
	}
	buf = malloc((cap->n ? cap->n : 1) * sizeof(double));
	if (!buf) {
		ssc_err(co.cmd, "out of memory");
		rc = SSC_EXIT_FAIL;
		goto done;
	}
	for (size_t c = 0; c < cap->n_channels; c++) {
		struct sscope_capture_channel *ch = &cap->channels[c];
		struct sscope_adc_spec s = spec;
		struct sscope_adc *adc = NULL;
		char b1[48], b2[48];

		if (!o.adc) {
			struct sscope_unit u;

			rc = sscope_adc_range_parse(o.range, &s.lo, &s.hi, &u, &d);
			if (rc) {
				rc = ssc_usage_error(co.cmd, "--range: %s", d.msg);
				goto done;
			}
			if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS && u.scale == 1) {
				/* bare: the channel's unit */
				s.lo = sscope_unit_to_si(&ch->col.unit, s.lo);
				s.hi = sscope_unit_to_si(&ch->col.unit, s.hi);
			} else if (!sscope_unit_compatible(&u, &ch->col.unit)) {
				rc = ssc_usage_error(co.cmd, "--range: '%s' is not in the unit of %s (%s)",
						     o.range, ch->col.name, ch->col.unit_label);
				goto done;
			}
			s.quantity = ch->col.quantity;
		} else if (s.quantity != ch->col.quantity) {
			rc = ssc_usage_error(co.cmd, "%s: range in %s units, channel %s measures %s",
					     o.adc, sscope_quantity_name(s.quantity), ch->col.name,
					     sscope_quantity_name(ch->col.quantity));
			goto done;
		}
		{
			/* an LSB wider than the data: every sample in a code
			 * or two (a range of +-1e308) */
			double lo = INFINITY, hi = -INFINITY;
			double lsb = (s.hi - s.lo) / ldexp(1, s.bits);

			for (size_t i = 0; i < cap->n; i++)
				if (isfinite(ch->data[i])) {
					lo = fmin(lo, ch->data[i]);
					hi = fmax(hi, ch->data[i]);
				}
			if (hi > lo && lsb > hi - lo)
				ssc_warn(&co, "%s: the LSB (%s %s) is wider than the data's span (%s %s): every sample lands in one or two codes; check --range and --bits",
					 ch->col.name,
					 ssc_fmt(b1, sizeof(b1), sscope_unit_from_si(&ch->col.unit, lsb), 3),
					 ch->col.unit_label,
					 ssc_fmt(b2, sizeof(b2), sscope_unit_from_si(&ch->col.unit, hi) -
								 sscope_unit_from_si(&ch->col.unit, lo), 3),
					 ch->col.unit_label);
		}
		rc = ssc_adc_new(&adc, &s, &prof, 1, 0, o.seed + c, &d);
		if (!rc)
			rc = sscope_adc_digitize(adc, ch->data, 1, cap->n,
						 cap->rate_hz > 0 ? cap->rate_hz : 1, cap->temp_degc,
						 buf, NULL, &clipped);
		sscope_adc_free(adc);
		if (rc) {
			rc = ssc_fail(co.cmd, rc, &d, ch->col.name);
			goto done;
		}
		/* NaN gaps stay gaps */
		for (size_t i = 0; i < cap->n; i++)
			ch->data[i] = isfinite(ch->data[i]) ? buf[i] : (double)NAN;
	}
	if (!cap->time_s && cap->rate_hz > 0) {
		/* keep the rate: write a time column */
		cap->time_s = malloc((cap->n ? cap->n : 1) * sizeof(double));
		if (!cap->time_s) {
			ssc_err(co.cmd, "out of memory");
			rc = SSC_EXIT_FAIL;
			goto done;
		}
		for (size_t i = 0; i < cap->n; i++)
			cap->time_s[i] = (double)i / cap->rate_hz;
		memset(&cap->time_col, 0, sizeof(cap->time_col));
		cap->time_col.name = "t";
		cap->time_col.unit_label = "s";
		cap->time_col.role = SSCOPE_CAPTURE_ROLE_TIME;
		cap->time_col.quantity = SSCOPE_QUANTITY_TIME;
		added_time = true;
	}
	rc = ssc_out_open(&co, &sink);
	if (!rc) {
		int e = sscope_capture_fwrite(cap, sink.f, o.fmt, 0, &d);

		if (e && !ferror(sink.f)) /* not a write error: said here */
			ssc_fail(co.cmd, e, &d, co.output ? co.output : "standard output");
		rc = ssc_out_close(&co, &sink, e == 0);
	}
	if (added_time) {
		/* not owned by the capture's allocator: give it back ourselves */
		free(cap->time_s);
		cap->time_s = NULL;
		memset(&cap->time_col, 0, sizeof(cap->time_col));
	}
	if (rc)
		goto done;
	if (clipped)
		ssc_warn(&co, "%zu samples clipped at the range", clipped);
	rc = SSC_EXIT_OK;
done:
	ssc_adc_profile_free(&prof);
	free(buf);
	sscope_capture_free(cap);
	return rc;
}

/* ------------------------------------------------------------ test */

static const struct ssc_option test_opts[] = {
	{ "bits", required_argument, O_BITS, "N",
	  "word length: enables the code-density DNL/INL test (with --range)" },
	{ "range", required_argument, O_RANGE, "LO:HI[ UNIT]",
	  "full-scale range (bare numbers: the channel's unit): ENOB from the FSR" },
	{ "adc", required_argument, O_ADC, "ADC.ini", "take bits and range from a converter spec" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec test_spec = {
	.name = "adc test",
	.usage = "adc test [--bits N --range LO:HI | --adc ADC.ini] [OPTIONS] FILE",
	.summary =
		"Characterise a converter from a sine capture (IEEE Std 1241): four-\n"
		"parameter sine fit, SINAD, ENOB (log2(FSR / (NAD sqrt 12)) with a range,\n"
		"else (SINAD - 1.76) / 6.02), THD, SFDR, SNR; with --bits and --range the\n"
		"code-density (histogram) test of the arcsine distribution gives DNL and\n"
		"INL per code (the sine should overdrive the range slightly); --plot\n"
		"draws them.",
	.options = test_opts,
	.analysis = true,
	.notes = "Example (an ideal 10-bit converter: ENOB 10):\n"
		 "  sensorscope simulate --sensor clean.ini --rate 1000 --duration 8.192 \\\n"
		 "      --tone 37.1234:0.999 --no-clip -o sine.csv\n"
		 "  sensorscope adc quantize --bits 10 --range -1:1 sine.csv -o sine10.csv\n"
		 "  sensorscope adc test --bits 10 --range -1:1 sine10.csv",
	.no_csv = true,
};

struct topts {
	long bits;
	const char *range;
	const char *adc;
};

static int t_handle(int key, const char *arg, void *ctx)
{
	struct topts *o = ctx;
	const char *cmd = test_spec.name;

	switch (key) {
	case O_BITS: {
		size_t v;

		if (ssc_arg_size(cmd, "bits", arg, &v))
			return SSC_EXIT_USAGE;
		if (v < 2 || v > 24)
			return ssc_usage_error(cmd, "--bits: between 2 and 24 for a histogram test");
		o->bits = (long)v;
		return 0;
	}
	case O_RANGE:
		o->range = arg;
		return 0;
	case O_ADC:
		o->adc = arg;
		return 0;
	default:
		return ssc_usage_error(cmd, "unknown option");
	}
}

static int plot_dnl_inl(const char *path, const char *name, const double *dnl,
			const double *inl, size_t nc)
{
	struct ssc_fig *fig = ssc_fig_new(1000, 800, 2, 1);
	double *k = malloc(nc * sizeof(double));
	struct ssc_style st = { .color = 0x1f77b4, .width = 1 };
	char buf[160];
	int rc;

	if (!fig || !k) {
		ssc_fig_free(fig);
		free(k);
		return -ENOMEM;
	}
	for (size_t i = 0; i < nc; i++)
		k[i] = (double)i;
	snprintf(buf, sizeof(buf), "%s: code-density test (IEEE 1241), %zu codes", name, nc);
	ssc_fig_title(fig, buf);
	for (int r = 0; r < 2; r++) {
		struct ssc_ax *ax = ssc_fig_ax(fig, r, 0);

		ssc_ax_grid(ax, true);
		ssc_ax_xlabel(ax, "code");
		ssc_ax_ylabel(ax, r ? "INL (LSB)" : "DNL (LSB)");
		ssc_ax_title(ax, r ? "integral non-linearity (best-fit line removed)" :
				     "differential non-linearity");
		ssc_ax_line(ax, k, r ? inl : dnl, nc, &st, r ? "INL" : "DNL");
		ssc_ax_legend(ax, SSC_LEGEND_NONE);
	}
	rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	free(k);
	return rc;
}

static int cmd_test(int argc, char **argv)
{
	struct ssc_common co;
	struct topts o = { 0 };
	struct sscope_capture *cap = NULL;
	struct sscope_diag d = { "" };
	json_t *root = NULL, *chans;
	struct ssc_membuf mb = { NULL, NULL, 0 };
	double lo = 0, hi = 0;
	bool have_range = false;
	int first, rc, bits = 0;

	rc = ssc_parse(&test_spec, argc, argv, &co, t_handle, &o, &first);
	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	if (argc - first != 1)
		return ssc_usage_error(co.cmd, argc - first ? "one input file" : "no input file");
	if (o.adc && (o.bits || o.range))
		return ssc_usage_error(co.cmd, "--adc replaces --bits and --range");
	if (o.bits && !o.range)
		return ssc_usage_error(co.cmd, "--bits needs --range");
	if (co.plot && !(o.bits && o.range) && !o.adc)
		return ssc_usage_error(co.cmd, "--plot draws DNL and INL: give --bits and --range (or --adc)");
	if (o.adc) {
		struct sscope_adc_spec s;

		rc = sscope_adc_spec_load(o.adc, &s, &d);
		if (rc)
			return ssc_fail(co.cmd, rc, &d, "adc spec");
		lo = s.lo;
		hi = s.hi;
		bits = s.bits <= 24 ? s.bits : 0;
		have_range = true;
	}
	bits = o.bits ? (int)o.bits : bits;
	rc = ssc_load(&co, argv[first], &cap);
	if (rc)
		return rc;
	rc = ssc_time_check(&co, argv[first], cap, true);
	if (rc)
		goto done;
	if (!(cap->rate_hz > 0)) {
		rc = ssc_err_no_rate(co.cmd, argv[first], cap->rate_note);
		goto done;
	}
	if (o.range) {
		struct sscope_unit u;

		if (sscope_adc_range_parse(o.range, &lo, &hi, &u, &d)) {
			rc = ssc_usage_error(co.cmd, "--range: %s", d.msg);
			goto done;
		}
		if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS && u.scale == 1 &&
		    cap->n_channels) {
			lo = sscope_unit_to_si(&cap->channels[0].col.unit, lo);
			hi = sscope_unit_to_si(&cap->channels[0].col.unit, hi);
		}
		have_range = true;
	}
	root = json_object();
	chans = json_array();
	json_object_set_new(root, "command", json_string("adc test"));
	json_object_set_new(root, "file", json_string(argv[first]));
	if (ssc_membuf_open(&mb)) {
		rc = SSC_EXIT_FAIL;
		goto done;
	}
	for (size_t c = 0; c < cap->n_channels; c++) {
		struct sscope_capture_channel *ch = &cap->channels[c];
		struct sscope_adc_dynamic dy;
		json_t *j = json_object(), *fit = json_object();
		double sc = sscope_unit_from_si(&ch->col.unit, 1);
		const char *un = ch->col.unit_label;
		char b1[48], b2[48], b3[48], b4[48];

		rc = sscope_adc_dynamic_test(ch->data, cap->n, cap->rate_hz,
					     have_range ? hi - lo : 0, &dy);
		if (!rc && (!(dy.fit.amplitude > 2 * dy.fit.rms_residual) ||
			    !(dy.fit.amplitude > 1e-9 * fabs(dy.fit.offset)))) {
			/* a constant or a record of noise: no sine to judge */
			ssc_err(co.cmd, "%s: channel %s: no sine in the record (fitted amplitude %s, residual %s rms): the test needs a sine input",
				argv[first], ch->col.name,
				ssc_fmt(b1, sizeof(b1), dy.fit.amplitude * sc, 3),
				ssc_fmt(b2, sizeof(b2), dy.fit.rms_residual * sc, 3));
			json_decref(j);
			json_decref(fit);
			rc = SSC_EXIT_FAIL;
			goto done_json;
		}
		if (rc) {
			json_decref(j);
			json_decref(fit);
			rc = ssc_fail(co.cmd, rc, NULL, ch->col.name);
			goto done_json;
		}
		if (have_range && 2 * dy.fit.amplitude < 0.5 * (hi - lo))
			ssc_warn(&co, "%s: channel %s: the sine spans %s %% of --range: the ENOB from the full-scale range is meaningful for a sine near full scale (IEEE 1241); check --range",
				 argv[first], ch->col.name,
				 ssc_fmt(b1, sizeof(b1), 100 * 2 * dy.fit.amplitude / (hi - lo), 2));
		json_object_set_new(j, "name", json_string(ch->col.name));
		json_object_set_new(j, "unit", json_string(un));
		json_object_set_new(j, "rate_hz", json_real(cap->rate_hz));
		json_object_set_new(j, "samples", json_integer((json_int_t)cap->n));
		json_object_set_new(fit, "frequency_hz", json_real(dy.fit.freq_hz));
		json_object_set_new(fit, "amplitude", json_real(dy.fit.amplitude * sc));
		json_object_set_new(fit, "offset", json_real(dy.fit.offset * sc));
		json_object_set_new(fit, "phase_rad", json_real(dy.fit.phase_rad));
		json_object_set_new(fit, "rms_residual", json_real(dy.fit.rms_residual * sc));
		json_object_set_new(j, "sine_fit", fit);
		json_object_set_new(j, "sinad_db", ssc_jreal(dy.sinad_db));
		json_object_set_new(j, "enob", ssc_jreal(dy.enob));
		json_object_set_new(j, "enob_from", json_string(have_range ? "fsr" : "sinad"));
		json_object_set_new(j, "thd_db", ssc_jreal(dy.thd_db));
		json_object_set_new(j, "sfdr_db", ssc_jreal(dy.sfdr_db));
		json_object_set_new(j, "snr_db", ssc_jreal(dy.snr_db));
		fprintf(mb.f, "%s [%s]: %zu samples at %s Hz\n", ch->col.name, un, cap->n,
			ssc_fmt(b1, sizeof(b1), cap->rate_hz, 6));
		fprintf(mb.f, "  sine fit    %s Hz, amplitude %s, offset %s, NAD %s\n",
			ssc_fmt(b1, sizeof(b1), dy.fit.freq_hz, 9),
			ssc_fmt(b2, sizeof(b2), dy.fit.amplitude * sc, 6),
			ssc_fmt(b3, sizeof(b3), dy.fit.offset * sc, 4),
			ssc_fmt(b4, sizeof(b4), dy.fit.rms_residual * sc, 4));
		fprintf(mb.f, "  SINAD %s dB  ENOB %s bits (%s)  THD %s dB  SFDR %s dB  SNR %s dB\n",
			ssc_fmt(b1, sizeof(b1), dy.sinad_db, 4), ssc_fmt(b2, sizeof(b2), dy.enob, 4),
			have_range ? "from the full-scale range" : "from SINAD, no --range",
			ssc_fmt(b3, sizeof(b3), dy.thd_db, 4), ssc_fmt(b4, sizeof(b4), dy.sfdr_db, 4),
			ssc_fmt(b1, sizeof(b1), dy.snr_db, 4));
		if (bits && have_range) {
			size_t nc = (size_t)1 << bits;
			double dmax = 0, imax = 0;
			int64_t *codes = malloc((cap->n ? cap->n : 1) * sizeof(int64_t));
			double *dnl = malloc(nc * sizeof(double)), *inl = malloc(nc * sizeof(double));
			int e;

			if (!codes || !dnl || !inl) {
				free(codes);
				free(dnl);
				free(inl);
				json_decref(j);
				ssc_err(co.cmd, "out of memory");
				rc = SSC_EXIT_FAIL;
				goto done_json;
			}
			e = sscope_adc_codes(ch->data, 1, cap->n, lo, hi, nc, codes, NULL);
			if (!e)
				e = sscope_adc_histogram_test(codes, cap->n, nc, dnl, inl,
							      &dmax, &imax);
			if (!e) {
				json_t *h = json_object(), *jd = json_array(), *ji = json_array();
				struct sscope_adc_hist_quality hq;

				sscope_adc_histogram_quality(codes, cap->n, ADC_DNL_TOL_LSB, &hq);
				json_object_set_new(h, "samples_per_code", json_real(hq.samples_per_code));
				json_object_set_new(h, "dnl_sd_lsb", json_real(hq.dnl_sd_lsb));
				json_object_set_new(h, "samples_needed", json_real(hq.samples_needed));
				json_object_set_new(h, "resolved", json_boolean(hq.resolved));

				for (size_t k = 0; k < nc; k++) {
					json_array_append_new(jd, ssc_jreal(dnl[k]));
					json_array_append_new(ji, ssc_jreal(inl[k]));
				}
				json_object_set_new(h, "bits", json_integer(bits));
				json_object_set_new(h, "dnl_max", json_real(dmax));
				json_object_set_new(h, "inl_max", json_real(imax));
				json_object_set_new(h, "dnl", jd);
				json_object_set_new(h, "inl", ji);
				json_object_set_new(j, "histogram", h);
				fprintf(mb.f, "  histogram   %d bits: max |DNL| %s LSB, max |INL| %s LSB (best-fit line)\n",
					bits, ssc_fmt(b1, sizeof(b1), dmax, 3),
					ssc_fmt(b2, sizeof(b2), imax, 3));
				if (!hq.resolved)
					fprintf(mb.f, "  warning     DNL/INL not resolved: %s samples per code give DNL an sd of %s LSB; %s samples (%s per code) are needed for %g LSB\n",
						ssc_fmt(b1, sizeof(b1), hq.samples_per_code, 3),
						ssc_fmt(b2, sizeof(b2), hq.dnl_sd_lsb, 3),
						ssc_fmt(b3, sizeof(b3), hq.samples_needed, 3),
						ssc_fmt(b4, sizeof(b4), hq.samples_needed / (double)hq.codes_spanned, 3),
						ADC_DNL_TOL_LSB);
				if (co.plot && c == 0) {
					int pe = plot_dnl_inl(co.plot, ch->col.name, dnl, inl, nc);

					if (pe) {
						free(codes);
						free(dnl);
						free(inl);
						json_decref(j);
						rc = ssc_write_failed(co.cmd, co.plot, pe);
						goto done_json;
					}
				}
			} else {
				json_object_set_new(j, "histogram", json_null());
				fprintf(mb.f, "  histogram   not possible: %s\n", sscope_strerror(e));
			}
			free(codes);
			free(dnl);
			free(inl);
		}
		json_array_append_new(chans, j);
	}
	json_object_set_new(root, "channels", chans);
	chans = NULL;
	{
		char *text = ssc_membuf_take(&mb);

		if (co.format == SSC_FMT_JSON) {
			free(text);
			rc = ssc_emit_json(&co, root);
			root = NULL;
		} else if (co.format == SSC_FMT_CSV) {
			free(text);
			rc = ssc_usage_error(co.cmd, "--format csv is not available here");
		} else {
			struct ssc_out so;

			rc = text ? ssc_out_open(&co, &so) : SSC_EXIT_FAIL;
			if (!rc) {
				fputs(text, so.f);
				rc = ssc_out_close(&co, &so, !ferror(so.f));
			}
			free(text);
		}
	}
done_json:
	if (mb.f)
		free(ssc_membuf_take(&mb));
	json_decref(chans);
	json_decref(root);
done:
	sscope_capture_free(cap);
	return rc;
}

/* ------------------------------------------------------------ dispatch */

int ssc_cmd_adc(int argc, char **argv)
{
	if (argc >= 2 && !strcmp(argv[1], "report"))
		return ssc_stage_main(&ssc_adc_stage, argc - 1, argv + 1);
	if (argc >= 2 && !strcmp(argv[1], "quantize"))
		return cmd_quantize(argc - 1, argv + 1);
	if (argc >= 2 && !strcmp(argv[1], "test"))
		return cmd_test(argc - 1, argv + 1);
	if (argc >= 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
		printf("Usage: sensorscope adc report|quantize|test [OPTIONS]\n\n"
		       "Converters and sensors:\n"
		       "  adc report    will this ADC degrade the sensor? (ranked selection,\n"
		       "                analytical terms and a Monte-Carlo check)\n"
		       "  adc quantize  re-digitize a capture through a candidate converter\n"
		       "  adc test      IEEE 1241 test of a converter from a sine capture\n\n"
		       "'sensorscope adc SUBCOMMAND --help' describes each.\n\n"
		       "Exit status: 0 success, 1 runtime or data error, 2 usage error.\n");
		return SSC_EXIT_OK;
	}
	if (argc < 2)
		return ssc_usage_error("adc", "give a subcommand: report, quantize or test");
	return ssc_usage_error("adc", "unknown subcommand '%s' (report, quantize, test)", argv[1]);
}
