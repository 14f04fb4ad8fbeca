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
#include "stage.h"

enum { O_SENSOR = 300, O_PILOT, O_RESOLVE, O_CI, O_PROB, O_LENGTHS, O_SECTION,
       O_MAXLEN };

static const struct ssc_option plan_opts[] = {
	{ "sensor", required_argument, O_SENSOR, "FILE.ini",
	  "the sensor: a [sensor] spec (as simulate takes) or a datasheet INI" },
	{ "pilot", required_argument, O_PILOT, "FILE",
	  "a short pilot record instead (or the operand CAPTURE): its fit (first channel, or -c) is the model" },
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
	.usage = "plan (--sensor FILE.ini | --pilot CAPTURE | CAPTURE) --resolve T:W[,T:W...] [OPTIONS]",
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
		 "model does not have is 'never', with the reason.  --plot draws the\n"
		 "probability against the record length.  In a scene, [plan] plans from\n"
		 "sensor = FILE.ini, else the scene's capture (the pilot), else its [sensor].\n"
		 "Examples:\n"
		 "  sensorscope plan --sensor samples/gyro-mems-250.ini --rate 100 --resolve B:10%,K:30%\n"
		 "  sensorscope plan --pilot pilot.csv --resolve B:25% --format json\n"
		 "Exit status: 0 done, 1 a file that cannot be read or fitted, 2 usage.",
	.no_csv = true,
};

struct opts {
	const char *pilot;
	struct ssc_plan_req q;
};

static void init(void *opts)
{
	static const double def_h[5] = { 1, 3, 6, 12, 24 };
	struct opts *o = opts;

	memset(o, 0, sizeof(*o));
	o->q.po.ci_level = 0.682689492137086;
	o->q.po.probability = 0.9;
	o->q.po.detect_sigma = 3;
	for (o->q.n_len = 0; o->q.n_len < 5; o->q.n_len++)
		o->q.lengths_s[o->q.n_len] = def_h[o->q.n_len] * 3600;
}

static int parse_resolve(struct ssc_plan_req *o, const char *arg)
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

static int parse_lengths(struct ssc_plan_req *o, const char *arg)
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
		rc = ssc_arg_positive("plan", "lengths", tok, "s", &o->lengths_s[o->n_len++]);
	}
	free(s);
	return rc;
}

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;
	struct ssc_plan_req *q = &o->q;

	switch (key) {
	case O_SENSOR:
		q->sensor = arg;
		return 0;
	case O_PILOT:
		o->pilot = arg;
		return 0;
	case O_SECTION:
		if (strcmp(arg, "gyro") && strcmp(arg, "accel"))
			return ssc_usage_error("plan", "--section: gyro or accel");
		q->section = arg;
		return 0;
	case O_RESOLVE:
		return parse_resolve(q, arg);
	case O_LENGTHS:
		return parse_lengths(q, arg);
	case O_MAXLEN:
		return ssc_arg_positive("plan", "max-length", arg, "s", &q->po.max_length_s);
	case O_CI:
		if (ssc_arg_double("plan", "ci", arg, &q->po.ci_level))
			return SSC_EXIT_USAGE;
		return q->po.ci_level > 0 && q->po.ci_level < 1 ? 0 :
			ssc_usage_error("plan", "--ci: a level between 0 and 1");
	case O_PROB:
		if (ssc_arg_double("plan", "probability", arg, &q->po.probability))
			return SSC_EXIT_USAGE;
		return q->po.probability > 0 && q->po.probability < 1 ? 0 :
			ssc_usage_error("plan", "--probability: between 0 and 1 (0.9 for 90 %%)");
	default:
		return ssc_usage_error("plan", "unexpected option");
	}
}

static int check(struct ssc_common *co, void *opts)
{
	struct opts *o = opts;

	if (o->q.sensor && o->pilot)
		return ssc_usage_error(co->cmd, "give one of --sensor FILE.ini and a pilot capture");
	if (!o->q.n_wish)
		return ssc_usage_error(co->cmd, "give the terms wanted: --resolve B:25%%,K:30%%");
	if (co->format == SSC_FMT_CSV)
		return ssc_usage_error(co->cmd, "--format csv: not available (text or json)");
	return 0;
}

/* the model: --sensor, else the pilot (--pilot, or the capture operand,
 * a scene's input), else a scene's [sensor] */
static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	struct opts *o = opts;
	const struct ssc_common *co = env->co;
	struct sscope_capture *own = NULL;
	const struct sscope_capture *pilot = env->n_caps ? env->caps[0] : NULL;
	const char *pilot_path = env->n_caps ? env->paths[0] : NULL;
	int rc;

	if (o->q.sensor && pilot)
		return ssc_usage_error(co->cmd, "give one of --sensor FILE.ini and a pilot capture (the operand '%s')",
				       pilot_path);
	if (o->pilot && pilot)
		return ssc_usage_error(co->cmd, "give the pilot once: --pilot or the operand");
	if (!o->q.sensor && !pilot && !o->pilot && !env->sensor)
		return ssc_usage_error(co->cmd, "give one of --sensor FILE.ini and --pilot CAPTURE");
	if (o->pilot) {
		rc = ssc_load(co, o->pilot, &own);
		if (rc)
			return rc;
		pilot = own;
		pilot_path = o->pilot;
	}
	rc = ssc_plan_run(co, &o->q, pilot, pilot_path, env->sensor,
			  env->sensor_path, (struct ssc_plan_res **)result);
	sscope_capture_free(own);
	return rc;
}

const struct ssc_stage_ops ssc_plan_stage = {
	.spec = &spec,
	.title = "Recording plan",
	.needs = SSC_NEED_DATA | SSC_NEED_DATA_OR_SENSOR,
	.min_files = 0,
	.max_files = 1,
	.opts_size = sizeof(struct opts),
	.init = init,
	.handle = handler,
	.check = check,
	.run = run,
	.json = ssc_plan_json,
	.text = ssc_plan_text,
	.summary = ssc_plan_summary,
	.plot = ssc_plan_plot,
	.free_result = ssc_plan_free,
};

int ssc_cmd_plan(int argc, char **argv)
{
	return ssc_stage_main(&ssc_plan_stage, argc, argv);
}
