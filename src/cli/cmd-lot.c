/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope lot: many captures of one model, one unit each; the spread
 * of their noise terms between units (src/workbench/lot.c presents,
 * analysis/lot.c computes).
 */
#include "cli.h"

#include <string.h>

#include "lot.h"
#include "stage.h"

enum { O_LEVEL = 300, O_SPEC, O_SMOOTH, O_MANIFEST, O_PLAN, O_JOB, O_MERGE, O_REPORT };

static const struct ssc_option lot_opts[] = {
	{ "ci", required_argument, O_LEVEL, "LEVEL",
	  "level of the lot's intervals (default 0.90)" },
	{ "spec", required_argument, O_SPEC, "FILE",
	  "upper limits of N, B, K (INI with [gyro], [accel], or a datasheet file): each unit within spec, out of spec or inconclusive (its 99 % interval), the lot's Cpk" },
	{ "smooth", required_argument, O_SMOOTH, "SECONDS",
	  "moving mean of the biases in --plot's figure (default 1/100 of the shortest record)" },
	{ "manifest", required_argument, O_MANIFEST, "FILE.csv",
	  "the units: a CSV with columns unit,file[,channels][,temperature] (files relative to it), read after the operands (command line only)" },
	{ "report", required_argument, O_REPORT, "DIR",
	  "write DIR (new or empty): index.html (the spread, the verdicts, both figures, one row per unit linking to its page units/unit-N.html), lot.json, lot.csv, the figures" },
	{ "plan-jobs", required_argument, O_PLAN, "slurm|parallel DIR",
	  "analyse nothing: write DIR (new; also written ENGINE:DIR) with plan.json and a Slurm job-array script (lot.sbatch) or a GNU parallel command file (jobs.txt), one task per unit" },
	{ "job", required_argument, O_JOB, "DIR:I",
	  "one task of a plan: unit I analysed into DIR/unit-I.json (no operands)" },
	{ "merge", required_argument, O_MERGE, "DIR",
	  "the lot of a plan's task results (no operands): the same output as lot on one machine" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "lot",
	.usage = "lot [OPTIONS] FILE FILE FILE...|FOLDER|MANIFEST.csv",
	.summary =
		"Many units of one model, one capture each (at rest): every gyro and\n"
		"accelerometer channel's N, B, K with their 68.3 % intervals, and per\n"
		"channel and term the population mean, the spread between units\n"
		"separated from each unit's own uncertainty (random effects: REML,\n"
		"Q-profile interval) and the outlier units (robust z, 1 % per unit);\n"
		"the same for each unit's bias, its drift over the record and its\n"
		"temperature sensitivity (batch means of 20 blocks). --plot F.svg:\n"
		"the biases against time in F.svg, the Allan deviations in F-adev.svg.",
	.options = lot_opts,
	.analysis = true,
	.notes = "Example:\n"
		 "  sensorscope lot --format json unit*.csv\n"
		 "  sensorscope lot --spec limits.ini unit*.csv\n"
		 "  sensorscope lot --plot lot.svg samples/lot   (a folder: its files)\n"
		 "  sensorscope lot lot.csv   (a manifest: columns unit,file[,channels][,temperature])\n"
		 "Exit status: 0 done, 1 a capture that cannot be read or analysed\n"
		 "or a limits file that cannot be used,\n"
		 "2 usage (fewer than 3 captures).",
};

struct opts {
	double level;
	const char *spec, *manifest;
	double smooth_s;
	const char *plan, *job, *merge; /* split over machines */
	const char *report;             /* --report DIR */
};

static void init(void *opts)
{
	((struct opts *)opts)->level = 0.90;
	((struct opts *)opts)->spec = NULL;
	((struct opts *)opts)->smooth_s = 0;
	((struct opts *)opts)->plan = NULL;
	((struct opts *)opts)->job = NULL;
	((struct opts *)opts)->merge = NULL;
	((struct opts *)opts)->report = NULL;
}

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;

	if (key == O_SPEC) {
		o->spec = arg;
		return 0;
	}
	if (key == O_MANIFEST) {
		o->manifest = arg;
		return 0;
	}
	if (key == O_PLAN) {
		if (strncmp(arg, "slurm:", 6) && strncmp(arg, "parallel:", 9))
			return ssc_usage_error("lot", "--plan-jobs: '%s' is not slurm DIR or parallel DIR (or slurm:DIR, parallel:DIR)", arg);
		if (!strchr(arg, ':')[1])
			return ssc_usage_error("lot", "--plan-jobs: %s: no folder after ':'", arg);
		o->plan = arg;
		return 0;
	}
	if (key == O_JOB) {
		o->job = arg;
		return 0;
	}
	if (key == O_MERGE) {
		o->merge = arg;
		return 0;
	}
	if (key == O_REPORT) {
		o->report = arg;
		return 0;
	}
	if (key == O_SMOOTH)
		return ssc_arg_double("lot", "smooth", arg, &o->smooth_s) ? SSC_EXIT_USAGE :
		       o->smooth_s > 0 ? 0 : ssc_usage_error("lot", "--smooth: a time > 0 s");
	if (key != O_LEVEL)
		return ssc_usage_error("lot", "unexpected option");
	if (ssc_arg_double("lot", "ci", arg, &o->level))
		return SSC_EXIT_USAGE;
	return o->level > 0 && o->level < 1 ? 0 :
		ssc_usage_error("lot", "--ci: a level between 0 and 1");
}

static int check(struct ssc_common *co, void *opts)
{
	const struct opts *o = opts;

	if (!!o->plan + !!o->job + !!o->merge > 1)
		return ssc_usage_error(co->cmd, "--plan-jobs, --job and --merge exclude each other");
	if ((o->job || o->merge) && (o->spec || o->manifest || o->smooth_s > 0))
		return ssc_usage_error(co->cmd, "%s: the plan holds the options (give --spec, --smooth, --ci, --manifest to --plan-jobs)",
				       o->job ? "--job" : "--merge");
	if ((o->plan || o->job) && (co->plot || o->report))
		return ssc_usage_error(co->cmd, "%s: of the merged lot (with --merge)",
				       co->plot ? "--plot" : "--report");
	return 0;
}

static const char *manifest(const void *opts)
{
	return ((const struct opts *)opts)->manifest;
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const struct opts *o = opts;

	struct ssc_lot_result *r = NULL;
	int rc;

	if (o->merge || o->job) {
		if (env->n_caps)
			return ssc_usage_error(env->co->cmd, "%s takes no input files (the plan names them)",
					       o->merge ? "--merge" : "--job");
		if (o->merge)
			return ssc_lot_merge(env->co, o->merge,
					     (struct ssc_lot_result **)result);
		r = calloc(1, sizeof(*r));
		rc = r ? ssc_lot_job(env->co, o->job, r->note, sizeof(r->note)) :
			 SSC_EXIT_FAIL;
	} else if (!env->n_caps) {
		return ssc_usage_error(env->co->cmd, "no input file");
	} else if (o->plan) {
		if (env->n_caps < 3)
			return ssc_usage_error(env->co->cmd, "a lot needs at least 3 units (captures), got %zu",
					       env->n_caps);
		r = calloc(1, sizeof(*r));
		rc = r ? ssc_lot_plan_jobs(env, o->plan[0] == 's' ? "slurm" : "parallel",
					   strchr(o->plan, ':') + 1, o->level, o->spec,
					   o->smooth_s, r->note, sizeof(r->note)) :
			 SSC_EXIT_FAIL;
	} else {
		return ssc_lot_run(env, o->level, o->spec, o->smooth_s,
				   (struct ssc_lot_result **)result);
	}
	if (rc) {
		free(r);
		return rc;
	}
	*result = r;
	return 0;
}

static int write_files(const struct ssc_common *co, const void *opts,
		       const void *result)
{
	const struct opts *o = opts;

	return o->report ? ssc_lot_report(co, result, o->report) : 0;
}

/* one unit's record at a time (memory of one record, whatever the lot) */
static bool streams(const void *opts)
{
	(void)opts;
	return true;
}

const struct ssc_stage_ops ssc_lot_stage = {
	.spec = &spec,
	.title = "Lot statistics",
	.needs = SSC_NEED_DATA,
	.min_files = 0, /* 3, but none with --job and --merge (run()) */
	.max_files = -1,
	.folders = true,
	.manifest = manifest,
	.opts_size = sizeof(struct opts),
	.init = init,
	.handle = handler,
	.check = check,
	.streams = streams,
	.run = run,
	.json = ssc_lot_json,
	.csv = ssc_lot_csv,
	.write = write_files,
	.text = ssc_lot_text,
	.summary = ssc_lot_summary,
	.plot = ssc_lot_plot,
	.free_result = ssc_lot_free,
};

/* "--plan-jobs ENGINE DIR": the folder as the operand right after the
 * engine, which becomes "ENGINE:DIR" (both spellings are documented) */
int ssc_cmd_lot(int argc, char **argv)
{
	static char joined[4096];

	for (int i = 1; i + 2 < argc; i++) {
		const char *e = argv[i + 1];

		if (!strcmp(argv[i], "--"))
			break;
		if (strcmp(argv[i], "--plan-jobs") || strchr(e, ':') ||
		    (strcmp(e, "slurm") && strcmp(e, "parallel")) ||
		    argv[i + 2][0] == '-')
			continue;
		snprintf(joined, sizeof(joined), "%s:%s", e, argv[i + 2]);
		argv[i + 1] = joined;
		for (int k = i + 2; k + 1 < argc; k++)
			argv[k] = argv[k + 1];
		argc--;
		break;
	}
	return ssc_stage_main(&ssc_lot_stage, argc, argv);
}
