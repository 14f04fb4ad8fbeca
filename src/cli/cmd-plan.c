/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope plan: how long to record for the noise fit to show a term
 * present and resolve it to a wanted relative half-width, with a stated
 * probability (analysis/plan.c computes, src/workbench/plan.c presents).
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "plan.h"

enum { O_SENSOR = 300, O_PILOT, O_RESOLVE, O_CI, O_PROB, O_LENGTHS, O_SECTION,
       O_MAXLEN };

static const struct ssc_option plan_opts[] = {
	{ "sensor", required_argument, O_SENSOR, "SPEC.ini",
	  "the sensor: a [sensor] spec (as simulate takes) or a datasheet INI" },
	{ "pilot", required_argument, O_PILOT, "CAPTURE",
	  "a short pilot record instead: its fit (first channel, or -c) is the model" },
	{ "resolve", required_argument, O_RESOLVE, "T:W[,T:W...]",
	  "terms (Q N B K R) and the relative half-width wanted, e.g. B:25%,K:30%" },
	{ "ci", required_argument, O_CI, "LEVEL",
	  "level of the interval (default 0.683)" },
	{ "probability", required_argument, O_PROB, "P",
	  "probability of getting there (default 0.9)" },
	{ "lengths", required_argument, O_LENGTHS, "L[,L...]",
	  "record lengths to show the probability at (default 1h,3h,6h,12h,24h)" },
	{ "section", required_argument, O_SECTION, "gyro|accel",
	  "section of a datasheet (default gyro when it has one)" },
	{ "max-length", required_argument, O_MAXLEN, "L",
	  "longest record considered (default 30 d)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "plan",
	.usage = "plan (--sensor SPEC.ini | --pilot CAPTURE) --resolve T:W[,T:W...] [OPTIONS]",
	.summary =
		"Record length needed for each wanted IEEE 952 term (Q, N, B, K, R) to be\n"
		"shown present by the fit's selection test and its interval to reach a\n"
		"relative half-width ((hi - lo) / (2 value)), with a stated probability,\n"
		"and that probability at a few lengths.  Predicted from the model (the\n"
		"covariance of the record's Allan variances and the fit's information),\n"
		"not simulated: see the man page for the method and its validation.",
	.options = plan_opts,
	.analysis = true,
	.notes = "The rate is --rate, else the pilot's; a spec needs --rate.  A term the\n"
		 "model does not have is 'never', with the reason.\n"
		 "Examples:\n"
		 "  sensorscope plan --sensor samples/gyro-mems-250.ini --rate 100 --resolve B:10%,K:30%\n"
		 "  sensorscope plan --pilot pilot.csv --resolve B:25% --format json\n"
		 "Exit status: 0 done, 1 a file that cannot be read or fitted, 2 usage.",
};

struct opts {
	const char *sensor, *pilot, *section;
	struct ssc_plan_wish wish[5];
	size_t n_wish;
	double lengths[SSC_PLAN_MAX_LENGTHS];
	size_t n_len;
	struct sscope_plan_opts po;
};

static int parse_resolve(struct opts *o, const char *arg)
{
	char *s = strdup(arg), *save = NULL, *tok;
	int rc = 0;

	if (!s)
		return ssc_usage_error("plan", "--resolve: out of memory");
	o->n_wish = 0;
	for (tok = strtok_r(s, ",", &save); tok && !rc; tok = strtok_r(NULL, ",", &save)) {
		const char *t = strchr("QNBKR", tok[0]);
		char *end;
		double v;

		if (!tok[0] || !t || tok[1] != ':') {
			rc = ssc_usage_error("plan", "--resolve: '%s' is not TERM:WIDTH (TERM one of Q N B K R)", tok);
			break;
		}
		v = strtod(tok + 2, &end);
		if (end != tok + 2 && *end == '%' && end[1] == 0)
			v /= 100;
		else if (end == tok + 2 || *end)
			v = NAN;
		if (!(v > 0) || !isfinite(v) || o->n_wish == 5) {
			rc = ssc_usage_error("plan", "--resolve: '%s': the width must be a positive number or percentage (25%% or 0.25), at most 5 terms", tok);
			break;
		}
		o->wish[o->n_wish].term = (int)(t - "QNBKR");
		o->wish[o->n_wish++].target = v;
	}
	free(s);
	return rc;
}

static int parse_lengths(struct opts *o, const char *arg)
{
	char *s = strdup(arg), *save = NULL, *tok;
	int rc = 0;

	if (!s)
		return ssc_usage_error("plan", "--lengths: out of memory");
	o->n_len = 0;
	for (tok = strtok_r(s, ",", &save); tok && !rc; tok = strtok_r(NULL, ",", &save)) {
		if (o->n_len == SSC_PLAN_MAX_LENGTHS) {
			rc = ssc_usage_error("plan", "--lengths: at most %d lengths", SSC_PLAN_MAX_LENGTHS);
			break;
		}
		rc = ssc_arg_positive("plan", "lengths", tok, "s", &o->lengths[o->n_len++]);
	}
	free(s);
	return rc;
}

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;

	switch (key) {
	case O_SENSOR:
		o->sensor = arg;
		return 0;
	case O_PILOT:
		o->pilot = arg;
		return 0;
	case O_SECTION:
		if (strcmp(arg, "gyro") && strcmp(arg, "accel"))
			return ssc_usage_error("plan", "--section: gyro or accel");
		o->section = arg;
		return 0;
	case O_RESOLVE:
		return parse_resolve(o, arg);
	case O_LENGTHS:
		return parse_lengths(o, arg);
	case O_MAXLEN:
		return ssc_arg_positive("plan", "max-length", arg, "s", &o->po.max_length_s);
	case O_CI:
		if (ssc_arg_double("plan", "ci", arg, &o->po.ci_level))
			return SSC_EXIT_USAGE;
		return o->po.ci_level > 0 && o->po.ci_level < 1 ? 0 :
			ssc_usage_error("plan", "--ci: a level between 0 and 1");
	case O_PROB:
		if (ssc_arg_double("plan", "probability", arg, &o->po.probability))
			return SSC_EXIT_USAGE;
		return o->po.probability > 0 && o->po.probability < 1 ? 0 :
			ssc_usage_error("plan", "--probability: between 0 and 1 (0.9 for 90 %%)");
	default:
		return ssc_usage_error("plan", "unexpected option");
	}
}

int ssc_cmd_plan(int argc, char **argv)
{
	static const double def_h[5] = { 1, 3, 6, 12, 24 };
	struct ssc_common co;
	struct ssc_plan_model m;
	struct opts o;
	double rate;
	int first, rc;

	memset(&o, 0, sizeof(o));
	o.po.ci_level = 0.682689492137086;
	o.po.probability = 0.9;
	o.po.detect_sigma = 3;
	rc = ssc_parse(&spec, argc, argv, &co, handler, &o, &first);
	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	if (first < argc)
		return ssc_usage_error(co.cmd, "unexpected operand '%s' (the sensor goes after --sensor, a pilot after --pilot)",
				       argv[first]);
	if (!o.sensor == !o.pilot)
		return ssc_usage_error(co.cmd, "give one of --sensor SPEC.ini and --pilot CAPTURE");
	if (!o.n_wish)
		return ssc_usage_error(co.cmd, "give the terms wanted: --resolve B:25%%,K:30%%");
	if (co.plot)
		return ssc_usage_error(co.cmd, "--plot: this command draws no figure");
	if (co.format == SSC_FMT_CSV)
		return ssc_usage_error(co.cmd, "--format csv: not available (text or json)");
	if (o.sensor && !(co.rate_hz > 0))
		return ssc_usage_error(co.cmd, "give the sample rate of the planned record: --rate HZ");
	if (!o.n_len)
		for (o.n_len = 0; o.n_len < 5; o.n_len++)
			o.lengths[o.n_len] = def_h[o.n_len] * 3600;
	rc = ssc_plan_model_load(&co, o.sensor, o.pilot, o.section, &m);
	if (rc)
		return rc;
	rate = co.rate_hz > 0 ? co.rate_hz : m.rate_hz;
	return ssc_plan_report(&co, &m, o.wish, o.n_wish, o.lengths, o.n_len, rate,
			       &o.po);
}
