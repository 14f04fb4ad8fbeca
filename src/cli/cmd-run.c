/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope run SCENE.ini: run a scene (scene.c); --dry-run prints the
 * plan: the stages to run and why, the stages skipped and why, the columns
 * read, the outputs.
 * sensorscope report FILE...: the same with a scene inferred from the data.
 */
#include "cli.h"
#include "scene.h"

#include <string.h>

enum { OPT_DRY_RUN = 2000 };

static const struct ssc_option run_opts[] = {
	{ "dry-run", no_argument, OPT_DRY_RUN, NULL,
	  "print the plan (stages run and skipped, with reasons; columns read; outputs) and stop" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec run_spec = {
	.name = "run",
	.usage = "run [OPTIONS] SCENE.ini",
	.summary =
		"Run a scene: an INI file naming the inputs ([input] files, columns,\n"
		"rate, units, temp_column), the sensor and ADC specifications\n"
		"([sensor], [adc]: 'spec = FILE' or inline keys), one section per\n"
		"wanted output whose keys are that command's long options, and\n"
		"[report] formats = text,json,html,png,svg and output = DIR.  Only\n"
		"the stages the outputs need are run, each once; each capture is read\n"
		"once, with only the columns in use.  Paths are relative to the scene\n"
		"file; -o DIR overrides the scene's output directory.  The report is\n"
		"built in a staging folder beside DIR and replaces DIR only when every\n"
		"stage succeeded; an existing DIR may hold only report files, no input.\n"
		"The summary table and any warning are printed on standard output;\n"
		"report.html has the results as tables, a banner for each result the\n"
		"analysis doubts, the figures inline as SVG and the formulas in MathML.",
	.options = run_opts,
	.output_opts = true,
	.output_dir = true,
	.notes = "Example:\n  sensorscope run samples/gyro-static.scene.ini\n"
		 "  sensorscope run --dry-run samples/gyro-static.scene.ini",
};

struct run_opts {
	bool dry_run;
};

static int run_handle(int key, const char *arg, void *ctx)
{
	struct run_opts *o = ctx;

	(void)arg;
	if (key == OPT_DRY_RUN) {
		o->dry_run = true;
		return 0;
	}
	return SSC_EXIT_USAGE;
}

int ssc_cmd_run(int argc, char **argv)
{
	struct ssc_common co;
	struct run_opts o = { false };
	struct ssc_scene *sc;
	int first, rc;

	rc = ssc_parse(&run_spec, argc, argv, &co, run_handle, &o, &first);
	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	if (argc - first != 1)
		return ssc_usage_error(co.cmd, "expected one scene file");
	if (co.format != SSC_FMT_TEXT)
		return ssc_usage_error(co.cmd,
				       "--format: a report is a folder; its formats are the scene's [report] formats");
	/* errors of the stages say "sensorscope: run: STAGE: ..." */
	ssc_set_outer(co.cmd);
	rc = ssc_scene_load(co.cmd, argv[first], ssc_scene_graph(), &sc);
	if (rc)
		return rc;
	if (co.output)
		ssc_scene_set_output(sc, co.output);
	if (o.dry_run) {
		ssc_scene_plan(sc, stdout);
	} else {
		rc = ssc_scene_run(sc, &co);
	}
	ssc_scene_free(sc);
	return rc;
}

static const struct ssc_command_spec report_spec = {
	.name = "report",
	.usage = "report [OPTIONS] FILE...",
	.summary =
		"Characterise captures with a scene inferred from the data, and write\n"
		"the HTML report (with its PNG figures and JSON) into the directory\n"
		"given by -o (default sensorscope-report/).  --dry-run prints what\n"
		"would be run and why.  Inference per capture: accelerations with\n"
		"roll_ref/pitch_ref columns and a temperature -> inclino only;\n"
		"inertial channels with a temperature column -> tempbias; rate gyros\n"
		"and accelerometers below 500 Hz -> allan; accelerometers at 500 Hz\n"
		"and above -> vibration; a gyro with a true heading column (an angle\n"
		"named *heading*) -> heading against it; any other gyro record\n"
		"without temperature -> walk (refused when it moves); every data\n"
		"channel -> psd.  An inferred analysis the data refuse is left out of\n"
		"the report with its reason.",
	.options = run_opts,
	.analysis = true,
	.output_dir = true,
	.notes = "Example:\n  sensorscope report samples/gyro-static.csv\n"
		 "  sensorscope report -o thermal-report samples/accel-thermal.csv",
};

int ssc_cmd_report(int argc, char **argv)
{
	struct ssc_common co;
	struct run_opts o = { false };
	struct ssc_scene *sc;
	int first, rc;

	rc = ssc_parse(&report_spec, argc, argv, &co, run_handle, &o, &first);
	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	if (argc - first < 1)
		return ssc_usage_error(co.cmd, "no input file");
	if (co.format != SSC_FMT_TEXT)
		return ssc_usage_error(co.cmd,
				       "--format: a report is a directory of text, JSON, PNG and HTML");
	if (co.plot)
		return ssc_usage_error(co.cmd, "--plot: the report draws every figure itself");
	ssc_set_outer(co.cmd);
	rc = ssc_check_inputs(co.cmd, (const char *const *)argv + first,
			      (size_t)(argc - first));
	if (rc)
		return rc;
	rc = ssc_scene_infer(&co, argv + first, (size_t)(argc - first),
			     co.output ? co.output : "sensorscope-report",
			     ssc_scene_graph(), &sc);
	if (rc)
		return rc;
	if (o.dry_run)
		ssc_scene_plan(sc, stdout);
	else
		rc = ssc_scene_run(sc, &co);
	ssc_scene_free(sc);
	return rc;
}
