/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope datasheet: datasheet lines as IEEE 952 terms and back, and
 * a capture's guard-banded verdicts against them (src/workbench/
 * datasheet.c presents, analysis/datasheet.c computes).
 */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

#include "datasheet.h"
#include "stage.h"

enum { O_CHECK = 300, O_CI, O_SPEC };

static const struct ssc_option ds_opts[] = {
	{ "spec", required_argument, O_SPEC, "FILE",
	  "the datasheet INI to check the capture operand against (a scene's [datasheet] spec = FILE)" },
	{ "check", required_argument, O_CHECK, "CAPTURE",
	  "check a stationary capture against the datasheet operand: per line the measured value, its interval and the verdict" },
	{ "ci", required_argument, O_CI, "LEVEL",
	  "confidence level of the intervals that guard-band the verdicts (default 0.99)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "datasheet",
	.usage = "datasheet [OPTIONS] SPEC.ini | --spec SPEC.ini CAPTURE | --check CAPTURE SPEC.ini",
	.summary =
		"A datasheet's lines (an INI file: [datasheet] name, source; [gyro] and\n"
		"[accel] lines with units) as IEEE 952 terms N, B, K and the terms as\n"
		"every other definition: noise density, ARW/VRW, rms noise over a noise\n"
		"bandwidth, bias instability (IEEE) and in-run bias stability (Allan\n"
		"minimum, MEMS Industry Group), rate random walk, GJB 10 s / 100 s bias\n"
		"stability (1 sigma of 10 s / 100 s means), run-to-run bias, scale-factor\n"
		"error.  With --check, each gyro (accelerometer) channel of the capture\n"
		"against [gyro] ([accel]): 'within spec' only when the whole interval is\n"
		"below the line, 'out of spec' when it is above, else 'inconclusive'.",
	.options = ds_opts,
	.analysis = true,
	.notes = "Keys of [gyro] and [accel]: noise_density, random_walk, rms_noise with\n"
		 "noise_bandwidth, bias_instability, in_run_bias_stability, rate_random_walk,\n"
		 "bias_stability_10s, bias_stability_100s, run_to_run_bias, scale_factor_error;\n"
		 "limits on a magnitude (+-): bias_offset, rate_ramp, bias_tempco.\n"
		 "Examples:\n"
		 "  sensorscope datasheet samples/datasheets/bmi088.ini\n"
		 "  sensorscope datasheet --check gyro.csv --format json samples/datasheets/stim300.ini\n"
		 "Exit status: 0 done (whatever the verdicts), 1 a file that cannot be read\n"
		 "or used (the line and key named), 2 usage.",
	.no_csv = true,
	.no_plot = true,
};

struct opts {
	const char *spec;
	const char *check;
	double ci;
	struct ssc_datasheet ds;
};

static void init(void *opts)
{
	struct opts *o = opts;

	memset(o, 0, sizeof(*o));
	o->ci = 0.99;
}

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;

	switch (key) {
	case O_SPEC:
		o->spec = arg;
		return 0;
	case O_CHECK:
		o->check = arg;
		return 0;
	case O_CI:
		if (ssc_arg_double("datasheet", "ci", arg, &o->ci))
			return SSC_EXIT_USAGE;
		return o->ci > 0 && o->ci < 1 ? 0 :
			ssc_usage_error("datasheet", "--ci: a level between 0 and 1");
	default:
		return ssc_usage_error("datasheet", "unexpected option");
	}
}

static int formats(const struct ssc_common *co)
{
	if (co->plot)
		return ssc_usage_error(co->cmd, "--plot: this command draws no figure");
	if (co->format == SSC_FMT_CSV)
		return ssc_usage_error(co->cmd, "--format csv: not available (text or json)");
	return 0;
}

/* the verdicts: a stage (the capture its operand, or a scene's input) */
static int check(struct ssc_common *co, void *opts)
{
	struct opts *o = opts;
	int rc = formats(co);

	if (rc)
		return rc;
	if (o->check)
		return ssc_usage_error(co->cmd, "--check: with --spec the capture is the operand");
	if (!o->spec)
		return ssc_usage_error(co->cmd, "give the datasheet: --spec SPEC.ini");
	return ssc_datasheet_load(co->cmd, o->spec, &o->ds);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	struct opts *o = opts;

	return ssc_datasheet_check_capture(env->co->cmd, &o->ds, env->caps[0],
					   env->paths[0], o->ci,
					   (struct ssc_ds_result **)result);
}

const struct ssc_stage_ops ssc_datasheet_stage = {
	.spec = &spec,
	.title = "Datasheet verdicts",
	.needs = SSC_NEED_DATA,
	.min_files = 1,
	.max_files = 1,
	.opts_size = sizeof(struct opts),
	.init = init,
	.handle = handler,
	.check = check,
	.run = run,
	.json = ssc_datasheet_result_json,
	.text = ssc_datasheet_result_text,
	.summary = ssc_datasheet_result_summary,
	.free_result = ssc_datasheet_result_free,
};

int ssc_cmd_datasheet(int argc, char **argv)
{
	struct ssc_common co;
	struct opts o;
	int first, rc;

	for (int i = 1; i < argc; i++)
		if (!strcmp(argv[i], "--spec") || !strncmp(argv[i], "--spec=", 7))
			return ssc_stage_main(&ssc_datasheet_stage, argc, argv);
	init(&o);
	rc = ssc_parse(&spec, argc, argv, &co, handler, &o, &first);
	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	if (first >= argc)
		return ssc_usage_error(co.cmd, "give the datasheet file (SPEC.ini)");
	if (first + 1 < argc)
		return ssc_usage_error(co.cmd, "unexpected operand '%s' (the capture goes after --check)",
				       argv[first + 1]);
	rc = formats(&co);
	if (rc)
		return rc;
	if (o.check) {
		/* --check CAPTURE SPEC.ini: the stage, as --spec SPEC.ini
		 * CAPTURE with the options parsed above */
		char **av = calloc((size_t)argc + 3, sizeof(char *));
		int n = 0;

		if (!av)
			return ssc_fail(co.cmd, -ENOMEM, NULL, NULL);
		av[n++] = argv[0];
		for (int i = 1; i < first; i++) {
			if (!strcmp(argv[i], "--check")) {
				i++;
				continue;
			}
			if (strncmp(argv[i], "--check=", 8))
				av[n++] = argv[i];
		}
		av[n++] = (char *)"--spec";
		av[n++] = argv[first];
		av[n++] = (char *)o.check;
		rc = ssc_stage_main(&ssc_datasheet_stage, n, av);
		free(av);
		return rc;
	}
	rc = ssc_datasheet_load(co.cmd, argv[first], &o.ds);
	if (rc)
		return rc;
	return ssc_datasheet_convert(&co, &o.ds);
}
