/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope simulate: a capture file whose noise obeys a sensor
 * specification (IEEE 952 terms, bias, scale factor, temperature
 * dependence, vibration tones, quantization), written in chunks so that
 * records of any length run in constant memory.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

enum {
	OPT_SENSOR = 3000,
	OPT_DURATION,
	OPT_SEED,
	OPT_AXES,
	OPT_NAMES,
	OPT_UNITS,
	OPT_BINARY,
	OPT_DIGITS,
	OPT_TEMP,
	OPT_TEMP_RAMP,
	OPT_TEMP_CYCLE,
	OPT_TEMP_NOISE,
	OPT_REF_TEMP,
	OPT_TEMP_COEFFS,
	OPT_HYST,
	OPT_HYST_BAND,
	OPT_GRADIENT,
	OPT_TONE,
	OPT_QUANT,
	OPT_INPUT,
	OPT_NO_CLIP,
	OPT_FLICKER,
	OPT_RATE,
	OPT_OUT,
	OPT_QUIET,
	OPT_HELP2,
	OPT_ADC,
};

static const struct ssc_option sim_opts[] = {
	{ "sensor", required_argument, OPT_SENSOR, "SENSOR.ini",
	  "sensor specification ([sensor] section; required)" },
	{ "rate", required_argument, 'r', "HZ", "sample rate (required)" },
	{ "duration", required_argument, OPT_DURATION, "S",
	  "length of the record, s (required; units allowed: 24h, 90 min)" },
	{ "seed", required_argument, OPT_SEED, "N",
	  "seed (default 1); the same seed gives the same file" },
	{ "axes", required_argument, OPT_AXES, "N",
	  "axes, each an independent stream (default 1)" },
	{ "names", required_argument, OPT_NAMES, "A,B,...",
	  "channel names (default gx gy gz, ax ay az)" },
	{ "units", required_argument, 'u', "UNIT",
	  "unit of the data columns (default deg/s for gyros, m/s^2 for accelerometers)" },
	{ "output", required_argument, 'o', "PATH",
	  "write the capture there (default stdout): a file atomically, a FIFO or device written through, never an input" },
	{ "binary", required_argument, OPT_BINARY, "f32|f64",
	  "sensorscope binary capture instead of CSV" },
	{ "digits", required_argument, OPT_DIGITS, "N",
	  "significant digits of CSV values (default 10; 17 is exact)" },
	{ "input", required_argument, OPT_INPUT, "VALUE",
	  "constant true input (e.g. 15.04 deg/h), in --units when bare" },
	{ "temp", required_argument, OPT_TEMP, "T",
	  "constant temperature, degC (adds a temperature column)" },
	{ "temp-ramp", required_argument, OPT_TEMP_RAMP, "FROM:TO:RATE",
	  "temperature ramp, degC and degC/s (e.g. 20:60:0.01)" },
	{ "temp-cycle", required_argument, OPT_TEMP_CYCLE, "LO:HI:PERIOD[:sine|triangle]",
	  "temperature cycle between LO and HI degC with PERIOD s, starting at LO" },
	{ "temp-noise", required_argument, OPT_TEMP_NOISE, "SD",
	  "noise of the temperature reading, degC" },
	{ "ref-temp", required_argument, OPT_REF_TEMP, "T",
	  "reference temperature of the bias polynomial (default: the middle of temp_min..temp_max, else 25 degC)" },
	{ "temp-coeffs", required_argument, OPT_TEMP_COEFFS, "C1[,C2,C3,C4]",
	  "bias(T) = sum Ck (T - Tref)^k, Ck in --units per degC^k (adds to the spec's bias_tempco)" },
	{ "hysteresis", required_argument, OPT_HYST, "H",
	  "bias +H/2 while heating, -H/2 while cooling (--units)" },
	{ "hysteresis-band", required_argument, OPT_HYST_BAND, "R",
	  "|dT/dt| below R degC/s keeps the last state (default 0)" },
	{ "gradient", required_argument, OPT_GRADIENT, "G",
	  "bias per temperature rate, --units per degC/s" },
	{ "tone", required_argument, OPT_TONE, "F:A[:PHASE]",
	  "vibration tone: F Hz, amplitude A (--units), phase in degrees; repeatable" },
	{ "quantize", required_argument, OPT_QUANT, "STEP",
	  "round outputs to multiples of STEP (--units)" },
	{ "adc", required_argument, OPT_ADC, "ADC.ini",
	  "digitize each axis through this converter ([adc] section; analog ranges use the sensor's sensitivity and zero_output)" },
	{ "no-clip", no_argument, OPT_NO_CLIP, NULL,
	  "do not clip to the spec's range" },
	{ "flicker-band", required_argument, OPT_FLICKER, "MIN:MAX",
	  "correlation-time band of the bias-instability model, s (default 1/rate : max(1e6, 10 x duration))" },
	{ "quiet", no_argument, 'q', NULL, "no warnings" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "simulate",
	.usage = "simulate --sensor SENSOR.ini --rate HZ --duration S [OPTIONS]",
	.summary =
		"Write a capture whose noise obeys a sensor specification: the IEEE 952\n"
		"terms quantization Q, random walk N, bias instability B (flicker noise as\n"
		"a sum of Gauss-Markov processes), rate random walk K and rate ramp R,\n"
		"plus bias, scale factor, temperature dependence (polynomial, hysteresis,\n"
		"gradient) along a temperature profile, vibration tones and quantization.\n"
		"Each axis is an independent random stream; the same seed gives the same\n"
		"file.",
	.options = sim_opts,
	.analysis = false,
	.notes = "Examples:\n"
		 "  sensorscope simulate --sensor gyro.ini --rate 100 --duration 2h -o gyro.csv\n"
		 "  sensorscope simulate --sensor gyro.ini --rate 100 --duration 24h --axes 3 \\\n"
		 "      --binary f64 -o day.bin\n"
		 "  sensorscope simulate --sensor accel.ini --rate 10 --duration 4h \\\n"
		 "      --temp-cycle -10:50:7200 --temp-coeffs 0.001,2e-5 -u m/s^2 -o acc.csv\n"
		 "Sensor keys: name, range, noise_density (N), bias_instability (B),\n"
		 "rate_random_walk (K), quantization (Q), rate_ramp (R), bias,\n"
		 "scale_factor_error (ppm), bias_tempco, temp_min, temp_max; values carry\n"
		 "units (noise_density = 0.15 deg/sqrt(h)).",
};

struct args {
	const char *sensor, *names, *units, *out;
	double rate, duration;
	uint64_t seed;
	size_t axes;
	int digits;
	enum sscope_capture_format fmt;
	bool have_temp, have_ref, quiet, have_digits;
	const char *input_text;
	const char *coeffs, *hyst, *grad, *quant;
	const char *adc;
	const char *tones[SSCOPE_SIM_MAX_TONES];
	size_t n_tones;
	struct sscope_sim_opts so;
	double flick_min, flick_max;
};

static int need_double(const char *opt, const char *arg, double *v)
{
	return ssc_arg_double("simulate", opt, arg, v);
}

/* split "a:b[:c[:d]]" into at most 4 fields */
static size_t split(const char *arg, char f[4][64])
{
	size_t n = 0;
	const char *p = arg;

	while (n < 4) {
		const char *c = strchr(p, ':');
		size_t l = c ? (size_t)(c - p) : strlen(p);

		if (l >= 64)
			return 0;
		memcpy(f[n], p, l);
		f[n][l] = '\0';
		n++;
		if (!c)
			break;
		p = c + 1;
	}
	return n;
}

static int handler(int key, const char *arg, void *ctx)
{
	struct args *a = ctx;
	char f[4][64];
	size_t n;

	/* one temperature profile */
	if ((key == OPT_TEMP || key == OPT_TEMP_RAMP || key == OPT_TEMP_CYCLE) &&
	    a->have_temp)
		return ssc_usage_error("simulate", "--temp, --temp-ramp and --temp-cycle: give one temperature profile");
	switch (key) {
	case OPT_SENSOR:
		a->sensor = arg;
		return 0;
	case 'r':
		if (need_double("rate", arg, &a->rate))
			return SSC_EXIT_USAGE;
		if (!(a->rate > 0))
			return ssc_usage_error("simulate", "--rate: must be positive");
		return 0;
	case OPT_DURATION:
		return ssc_arg_positive("simulate", "duration", arg, "s", &a->duration);
	case OPT_SEED: {
		char *end;
		unsigned long long v;

		if (!*arg || *arg == '-')
			goto bad_seed;
		v = strtoull(arg, &end, 0);
		if (*end)
			goto bad_seed;
		a->seed = v;
		return 0;
bad_seed:
		return ssc_usage_error("simulate", "--seed: '%s' is not a non-negative integer", arg);
	}
	case OPT_AXES:
		if (ssc_arg_size("simulate", "axes", arg, &a->axes))
			return SSC_EXIT_USAGE;
		if (a->axes < 1 || a->axes > 64)
			return ssc_usage_error("simulate", "--axes: 1..64");
		return 0;
	case OPT_NAMES:
		a->names = arg;
		return 0;
	case 'u': {
		struct sscope_unit u;

		if (sscope_unit_parse(arg, &u, NULL))
			return ssc_usage_error("simulate", "--units: '%s' is not a unit", arg);
		a->units = arg;
		return 0;
	}
	case 'o':
		a->out = arg;
		return 0;
	case 'q':
		a->quiet = true;
		return 0;
	case OPT_BINARY:
		if (!strcmp(arg, "f32"))
			a->fmt = SSCOPE_CAPTURE_BIN32;
		else if (!strcmp(arg, "f64"))
			a->fmt = SSCOPE_CAPTURE_BIN64;
		else
			return ssc_usage_error("simulate", "--binary: '%s' is not f32 or f64", arg);
		return 0;
	case OPT_DIGITS: {
		size_t d;

		if (ssc_arg_size("simulate", "digits", arg, &d))
			return SSC_EXIT_USAGE;
		if (d < 3 || d > 17)
			return ssc_usage_error("simulate", "--digits: 3..17");
		a->digits = (int)d;
		a->have_digits = true;
		return 0;
	}
	case OPT_INPUT:
		a->input_text = arg;
		return 0;
	case OPT_TEMP:
		if (ssc_arg_quantity("simulate", "temp", arg, "degC", &a->so.temp_degc))
			return SSC_EXIT_USAGE;
		a->so.temp_profile = SSCOPE_SIM_TEMP_CONSTANT;
		a->have_temp = true;
		return 0;
	case OPT_TEMP_RAMP:
		n = split(arg, f);
		if (n != 3 || need_double("temp-ramp", f[0], &a->so.temp_degc) ||
		    need_double("temp-ramp", f[1], &a->so.temp2_degc) ||
		    need_double("temp-ramp", f[2], &a->so.temp_rate_degc_s))
			return ssc_usage_error("simulate", "--temp-ramp: '%s' is not FROM:TO:RATE", arg);
		if (a->so.temp_rate_degc_s == 0 ||
		    (a->so.temp2_degc - a->so.temp_degc) * a->so.temp_rate_degc_s < 0)
			return ssc_usage_error("simulate", "--temp-ramp: RATE must run from FROM towards TO");
		a->so.temp_profile = SSCOPE_SIM_TEMP_RAMP;
		a->have_temp = true;
		return 0;
	case OPT_TEMP_CYCLE:
		n = split(arg, f);
		if ((n != 3 && n != 4) || need_double("temp-cycle", f[0], &a->so.temp_degc) ||
		    need_double("temp-cycle", f[1], &a->so.temp2_degc) ||
		    ssc_arg_quantity("simulate", "temp-cycle", f[2], "s", &a->so.temp_period_s))
			return ssc_usage_error("simulate", "--temp-cycle: '%s' is not LO:HI:PERIOD[:sine|triangle]", arg);
		if (!(a->so.temp_period_s > 0))
			return ssc_usage_error("simulate", "--temp-cycle: PERIOD must be positive");
		if (n == 4 && !strcmp(f[3], "triangle"))
			a->so.temp_wave = SSCOPE_SIM_TRIANGLE;
		else if (n == 4 && strcmp(f[3], "sine"))
			return ssc_usage_error("simulate", "--temp-cycle: shape '%s' is not sine or triangle", f[3]);
		a->so.temp_profile = SSCOPE_SIM_TEMP_CYCLE;
		a->have_temp = true;
		return 0;
	case OPT_TEMP_NOISE:
		if (need_double("temp-noise", arg, &a->so.temp_noise_degc))
			return SSC_EXIT_USAGE;
		if (a->so.temp_noise_degc < 0)
			return ssc_usage_error("simulate", "--temp-noise: must not be negative");
		return 0;
	case OPT_REF_TEMP:
		if (ssc_arg_quantity("simulate", "ref-temp", arg, "degC", &a->so.ref_temp_degc))
			return SSC_EXIT_USAGE;
		a->have_ref = true;
		return 0;
	case OPT_TEMP_COEFFS:
		a->coeffs = arg;
		return 0;
	case OPT_HYST:
		a->hyst = arg;
		return 0;
	case OPT_HYST_BAND:
		if (need_double("hysteresis-band", arg, &a->so.hysteresis_deadband_degc_s))
			return SSC_EXIT_USAGE;
		if (a->so.hysteresis_deadband_degc_s < 0)
			return ssc_usage_error("simulate", "--hysteresis-band: must not be negative");
		return 0;
	case OPT_GRADIENT:
		a->grad = arg;
		return 0;
	case OPT_TONE:
		if (a->n_tones >= SSCOPE_SIM_MAX_TONES)
			return ssc_usage_error("simulate", "--tone: at most %d tones",
					       SSCOPE_SIM_MAX_TONES);
		a->tones[a->n_tones++] = arg;
		return 0;
	case OPT_QUANT:
		a->quant = arg;
		return 0;
	case OPT_NO_CLIP:
		a->so.no_clip = true;
		return 0;
	case OPT_ADC:
		a->adc = arg;
		return 0;
	case OPT_FLICKER:
		n = split(arg, f);
		if (n != 2 || need_double("flicker-band", f[0], &a->flick_min) ||
		    need_double("flicker-band", f[1], &a->flick_max) ||
		    !(a->flick_min > 0) || !(a->flick_max >= a->flick_min))
			return ssc_usage_error("simulate", "--flicker-band: '%s' is not MIN:MAX with 0 < MIN <= MAX", arg);
		return 0;
	default:
		return ssc_usage_error("simulate", "unexpected option");
	}
}

/* a number in the output unit (bare) or with a unit of that dimension,
 * to SI; @p per is appended to the output unit ("/degC") */
static int out_value(const char *opt, const char *arg, const char *unit,
		     const char *per, double *si)
{
	char want[96];

	snprintf(want, sizeof(want), "%s%s", unit, per);
	{
		struct sscope_unit u;
		double v;
		struct sscope_diag d = { "" };

		if (sscope_quantity_parse(arg, &v, &u, &d))
			return ssc_usage_error("simulate", "--%s: %s", opt, d.msg);
		if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS &&
		    u.scale == 1) {
			struct sscope_unit w;

			sscope_unit_parse(want, &w, NULL);
			*si = w.scale * v;
			return 0;
		}
		{
			struct sscope_unit w;

			sscope_unit_parse(want, &w, NULL);
			if (!sscope_unit_compatible(&u, &w))
				return ssc_usage_error("simulate", "--%s: '%s' is not in units of %s",
						       opt, arg, want);
		}
		*si = v;
		return 0;
	}
}

int ssc_cmd_simulate(int argc, char **argv)
{
	struct ssc_common co;
	struct args a;
	struct sscope_sensor_spec sp;
	struct sscope_sim **sims = NULL;
	struct sscope_adc **adcs = NULL;
	struct sscope_adc_spec aspec;
	struct ssc_inl_profile prof = { NULL, 0 };
	size_t adc_clipped = 0;
	struct sscope_writer *w = NULL;
	struct ssc_out sink = { NULL, NULL };
	struct sscope_writer_column *cols = NULL;
	char (*names)[64] = NULL;
	double **outb = NULL, *temp = NULL, *rows = NULL, *inb = NULL;
	double **inp = NULL, **tp = NULL;
	const char *unit;
	int first, rc;
	size_t ncol, n, chunk = 65536;
	double projected = 0; /* bytes of the output, from its first chunk */
	struct sscope_diag d = { "" };

	memset(&a, 0, sizeof(a));
	a.seed = 1;
	a.axes = 1;
	a.digits = 10;
	a.fmt = SSCOPE_CAPTURE_CSV;
	rc = ssc_parse(&spec, argc, argv, &co, handler, &a, &first);
	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	co.quiet = a.quiet;
	if (first < argc)
		return ssc_usage_error(co.cmd, "unexpected operand '%s'", argv[first]);
	if (!a.sensor)
		return ssc_usage_error(co.cmd, "--sensor is required");
	if (!(a.rate > 0))
		return ssc_usage_error(co.cmd, "--rate is required");
	if (!(a.duration > 0))
		return ssc_usage_error(co.cmd, "--duration is required");
	/* options that would be ignored */
	if (a.have_digits && a.fmt != SSCOPE_CAPTURE_CSV)
		return ssc_usage_error(co.cmd, "--digits: a binary capture keeps every digit");
	if (a.so.temp_noise_degc > 0 && !a.have_temp)
		return ssc_usage_error(co.cmd, "--temp-noise: no temperature column (give --temp, --temp-ramp or --temp-cycle)");
	if (a.so.hysteresis_deadband_degc_s > 0 && !a.hyst)
		return ssc_usage_error(co.cmd, "--hysteresis-band: no --hysteresis");
	if (a.duration * a.rate > 1e12)
		return ssc_usage_error(co.cmd, "--duration x --rate: more than 1e12 samples");
	n = (size_t)llround(a.duration * a.rate);
	if (n == 0)
		return ssc_usage_error(co.cmd, "--duration x --rate is less than one sample");
	rc = ssc_load_sensor(co.cmd, a.sensor, &sp);
	if (!rc && a.adc) {
		rc = sscope_adc_spec_load(a.adc, &aspec, &d);
		if (rc)
			return ssc_fail(co.cmd, rc, &d, "adc spec");
		if (aspec.analog && !((sp.has & SSCOPE_SENSOR_HAS_SENSITIVITY) && sp.sensitivity > 0))
			return ssc_usage_error(co.cmd,
					       "--adc: %s has a range in volts but %s gives no sensitivity",
					       a.adc, a.sensor);
		if (aspec.oversample > 1)
			return ssc_usage_error(co.cmd,
					       "--adc: %s: oversample is modelled by 'adc report' only",
					       a.adc);
		if (!aspec.analog && aspec.quantity != sp.quantity)
			return ssc_usage_error(co.cmd, "--adc: %s converts %s, the sensor measures %s",
					       a.adc, sscope_quantity_name(aspec.quantity),
					       sscope_quantity_name(sp.quantity));
	}
	if (rc)
		return rc;
	unit = a.units ? a.units :
	       sp.quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? "deg/s" : "m/s^2";
	{
		struct sscope_unit u, want;

		sscope_unit_parse(unit, &u, NULL);
		sscope_unit_parse(sp.quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? "rad/s" : "m/s^2",
				  &want, NULL);
		if (!sscope_unit_compatible(&u, &want))
			return ssc_usage_error(co.cmd, "--units: %s is not a unit of %s",
					       unit, sscope_quantity_name(sp.quantity));
	}
	/* options in the output unit */
	if (a.coeffs) {
		const char *p = a.coeffs;

		for (int k = 0; k < SSCOPE_SIM_MAX_POLY && *p; k++) {
			char buf[64], per[32];
			const char *c = strchr(p, ',');
			size_t l = c ? (size_t)(c - p) : strlen(p);

			if (l >= sizeof(buf))
				return ssc_usage_error(co.cmd, "--temp-coeffs: bad list");
			memcpy(buf, p, l);
			buf[l] = '\0';
			snprintf(per, sizeof(per), k ? "/degC^%d" : "/degC", k + 1);
			rc = out_value("temp-coeffs", buf, unit, per, &a.so.bias_poly[k]);
			if (rc)
				return rc;
			p = c ? c + 1 : p + l;
			if (c && k == SSCOPE_SIM_MAX_POLY - 1)
				return ssc_usage_error(co.cmd, "--temp-coeffs: at most %d coefficients",
						       SSCOPE_SIM_MAX_POLY);
		}
	}
	if ((a.hyst && out_value("hysteresis", a.hyst, unit, "", &a.so.hysteresis)) ||
	    (a.grad && out_value("gradient", a.grad, unit, "/(degC/s)", &a.so.gradient)) ||
	    (a.quant && out_value("quantize", a.quant, unit, "", &a.so.quant_step)))
		return SSC_EXIT_USAGE;
	for (size_t i = 0; i < a.n_tones; i++) {
		char f[4][64];
		size_t k = split(a.tones[i], f);
		double ph = 0;

		if ((k != 2 && k != 3) ||
		    need_double("tone", f[0], &a.so.tones[i].freq_hz) ||
		    out_value("tone", f[1], unit, "", &a.so.tones[i].amplitude) ||
		    (k == 3 && need_double("tone", f[2], &ph)))
			return ssc_usage_error(co.cmd, "--tone: '%s' is not F:A[:PHASE]", a.tones[i]);
		a.so.tones[i].phase_rad = ph * 3.14159265358979323846 / 180;
	}
	a.so.n_tones = a.n_tones;
	if (a.input_text) {
		double v;

		if (out_value("input", a.input_text, unit, "", &v))
			return SSC_EXIT_USAGE;
		inb = malloc(chunk * sizeof(double));
		if (!inb)
			goto oom;
		for (size_t i = 0; i < chunk; i++)
			inb[i] = v;
	}
	if (!a.have_ref)
		a.so.ref_temp_degc = (sp.has & SSCOPE_SENSOR_HAS_TEMPS) ?
					     (sp.temp_min_degc + sp.temp_max_degc) / 2 :
					     25;
	if (!a.have_temp)
		a.so.temp_degc = a.so.ref_temp_degc;
	a.so.rate_hz = a.rate;
	a.so.seed = a.seed;
	a.so.flicker_tau_min_s = a.flick_min;
	a.so.flicker_tau_max_s = a.flick_max > 0 ? a.flick_max :
				 fmax(1e6, 10 * a.duration);
	/* channels */
	if (a.adc) {
		rc = ssc_adc_profile_load(co.cmd, a.adc, &aspec, &prof);
		if (rc)
			goto done;
	}
	names = calloc(a.axes, sizeof(*names));
	sims = calloc(a.axes, sizeof(*sims));
	adcs = calloc(a.axes, sizeof(*adcs));
	outb = calloc(a.axes, sizeof(*outb));
	inp = calloc(a.axes, sizeof(*inp));
	tp = calloc(a.axes, sizeof(*tp));
	ncol = 1 + a.axes + (a.have_temp ? 1 : 0);
	cols = calloc(ncol, sizeof(*cols));
	temp = malloc(chunk * sizeof(double));
	rows = malloc(chunk * ncol * sizeof(double)); /* ncol <= 66 */
	if (!names || !sims || !adcs || !outb || !inp || !tp || !cols || !temp || !rows)
		goto oom;
	{
		const char *p = a.names;
		char base = sp.quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? 'g' : 'a';

		for (size_t k = 0; k < a.axes; k++) {
			if (p && *p) {
				const char *c = strchr(p, ',');
				size_t l = c ? (size_t)(c - p) : strlen(p);

				if (l == 0 || l >= sizeof(names[k])) {
					rc = ssc_usage_error(co.cmd, "--names: bad list '%s'", a.names);
					goto done;
				}
				memcpy(names[k], p, l);
				names[k][l] = '\0';
				p = c ? c + 1 : p + l;
			} else if (a.names) {
				rc = ssc_usage_error(co.cmd, "--names: %zu names for %zu axes",
						     k, a.axes);
				goto done;
			} else if (a.axes <= 3) {
				snprintf(names[k], sizeof(names[k]), "%c%c", base,
					 "xyz"[k]);
			} else {
				snprintf(names[k], sizeof(names[k]), "%c%zu", base, k + 1);
			}
			/* a name the reader could not tell apart: refused
			 * here, not in the file (info refused it) */
			for (size_t j = 0; j <= k; j++)
				if (!strcasecmp(names[k], j < k ? names[j] : "t") ||
				    (a.have_temp && !strcasecmp(names[k], "temp"))) {
					rc = ssc_usage_error(co.cmd, "--names: '%s' twice (the time column is 't'%s)",
							     names[k], a.have_temp ? ", the temperature 'temp'" : "");
					goto done;
				}
		}
		if (p && *p) {
			rc = ssc_usage_error(co.cmd, "--names: more names than the %zu axes ('%s' left)",
					     a.axes, p);
			goto done;
		}
	}
	cols[0].name = "t";
	cols[0].unit = "s";
	for (size_t k = 0; k < a.axes; k++) {
		struct sscope_sim_opts o = a.so;

		cols[1 + k].name = names[k];
		cols[1 + k].unit = unit;
		o.stream = k;
		rc = sscope_sim_new(&sims[k], &sp, &o, &d);
		if (rc) {
			rc = ssc_fail(co.cmd, rc, &d, a.sensor);
			goto done;
		}
		if (a.adc) {
			rc = ssc_adc_new(&adcs[k], &aspec, &prof, sp.sensitivity,
					 (sp.has & SSCOPE_SENSOR_HAS_ZERO) ? sp.zero_output_v : 0,
					 a.seed + k, &d);
			if (rc) {
				rc = ssc_fail(co.cmd, rc, &d, a.adc);
				goto done;
			}
		}
		outb[k] = malloc(chunk * sizeof(double));
		if (!outb[k])
			goto oom;
		inp[k] = inb;
		tp[k] = k == 0 && a.have_temp ? temp : NULL;
	}
	if (a.have_temp) {
		cols[ncol - 1].name = "temp";
		cols[ncol - 1].unit = "degC";
	}
	rc = ssc_file_open(co.cmd, a.out, &sink);
	if (rc)
		goto done;
	rc = sscope_writer_fopen(&w, sink.f, a.fmt, cols, ncol, a.digits, &d);
	if (rc) {
		rc = ssc_fail(co.cmd, rc, &d, a.out ? a.out : "(stdout)");
		goto done;
	}
	for (size_t done_n = 0; done_n < n;) {
		size_t c = n - done_n < chunk ? n - done_n : chunk;

		rc = sscope_sim_generate_multi(sims, a.axes,
					       (const double *const *)inp, outb,
					       tp, c);
		if (rc) {
			rc = ssc_fail(co.cmd, rc, NULL, "simulation");
			sscope_writer_abort(w);
			w = NULL;
			goto done;
		}
		for (size_t k = 0; a.adc && k < a.axes; k++) {
			rc = sscope_adc_digitize(adcs[k], outb[k], 1, c, a.rate,
						 a.have_temp ? temp : NULL, outb[k], NULL,
						 &adc_clipped);
			if (rc) {
				rc = ssc_fail(co.cmd, rc, NULL, a.adc);
				sscope_writer_abort(w);
				w = NULL;
				goto done;
			}
		}
		for (size_t i = 0; i < c; i++) {
			double *r = rows + i * ncol;

			r[0] = (double)(done_n + i) / a.rate;
			for (size_t k = 0; k < a.axes; k++)
				r[1 + k] = outb[k][i];
			if (a.have_temp)
				r[ncol - 1] = temp[i];
		}
		if (sscope_writer_append(w, rows, c)) {
			rc = SSC_EXIT_FAIL; /* said when the sink is closed */
			goto done;
		}
		done_n += c;
		/* after the first chunk: the whole output fits, or nothing
		 * is left behind */
		if (done_n == c && done_n < n) {
			rc = ssc_out_room(co.cmd, &sink, (double)done_n, (double)n,
					  "shorten --duration, lower --rate or write --binary f32",
					  &projected);
			if (rc)
				goto done;
		}
		if (projected > 0 && done_n < n)
			ssc_progress(&co, "simulate", projected * (double)done_n / (double)n,
				     projected);
	}
	if (projected > 0)
		ssc_progress_end(&co);
	rc = sscope_writer_commit(w);
	w = NULL;
	rc = ssc_file_close(&sink, rc == 0);
	if (rc)
		goto done;
	for (size_t k = 0; k < a.axes; k++)
		if (sscope_sim_clipped(sims[k]))
			ssc_warn(&co, "%s: %llu samples clipped to the range %g %s",
				 names[k], (unsigned long long)sscope_sim_clipped(sims[k]),
				 sp.range, sp.quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? "rad/s" : "m/s^2");
	if (adc_clipped)
		ssc_warn(&co, "%s: %zu samples clipped at the converter's range", a.adc,
			 adc_clipped);
	rc = SSC_EXIT_OK;
	goto done;
oom:
	ssc_err(co.cmd, "out of memory");
	rc = SSC_EXIT_FAIL;
done:
	if (w)
		sscope_writer_abort(w);
	if (sink.priv)
		ssc_file_close(&sink, false);
	for (size_t k = 0; sims && k < a.axes; k++) {
		sscope_sim_free(sims[k]);
		if (adcs)
			sscope_adc_free(adcs[k]);
		if (outb)
			free(outb[k]);
	}
	free(sims);
	free(adcs);
	free(outb);
	free(inp);
	free(tp);
	free(cols);
	free(names);
	free(temp);
	free(rows);
	free(inb);
	ssc_adc_profile_free(&prof);
	return rc;
}
