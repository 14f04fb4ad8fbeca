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

enum { O_LEVEL = 300, O_SPEC, O_SMOOTH, O_MANIFEST };

static const struct ssc_option lot_opts[] = {
	{ "ci", required_argument, O_LEVEL, "LEVEL",
	  "level of the lot's intervals (default 0.90)" },
	{ "spec", required_argument, O_SPEC, "FILE",
	  "upper limits of N, B, K (INI with [gyro], [accel], or a datasheet file): each unit within spec, out of spec or inconclusive (its 99 % interval), the lot's Cpk" },
	{ "smooth", required_argument, O_SMOOTH, "SECONDS",
	  "moving mean of the biases in --plot's figure (default 1/100 of the shortest record)" },
	{ "manifest", required_argument, O_MANIFEST, "FILE.csv",
	  "the units: a CSV with columns unit,file[,channels][,temperature] (files relative to it), read after the operands (command line only)" },
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
};

static void init(void *opts)
{
	((struct opts *)opts)->level = 0.90;
	((struct opts *)opts)->spec = NULL;
	((struct opts *)opts)->smooth_s = 0;
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
	(void)opts;
	if (co->format == SSC_FMT_CSV)
		return ssc_usage_error(co->cmd, "--format csv: not available (text or json)");
	return 0;
}

static const char *manifest(const void *opts)
{
	return ((const struct opts *)opts)->manifest;
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const struct opts *o = opts;

	return ssc_lot_run(env, o->level, o->spec, o->smooth_s,
			   (struct ssc_lot_result **)result);
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
	.min_files = 3,
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
	.text = ssc_lot_text,
	.summary = ssc_lot_summary,
	.plot = ssc_lot_plot,
	.free_result = ssc_lot_free,
};

int ssc_cmd_lot(int argc, char **argv)
{
	return ssc_stage_main(&ssc_lot_stage, argc, argv);
}
