/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope datasheet: datasheet lines as IEEE 952 terms and back, and
 * a capture's guard-banded verdicts against them (src/workbench/
 * datasheet.c presents, analysis/datasheet.c computes).
 */
#include "cli.h"

#include <string.h>

#include "datasheet.h"

enum { O_CHECK = 300, O_CI };

static const struct ssc_option ds_opts[] = {
	{ "check", required_argument, O_CHECK, "CAPTURE",
	  "check a stationary capture against the datasheet: per line the measured value, its interval and the verdict" },
	{ "ci", required_argument, O_CI, "LEVEL",
	  "confidence level of the intervals that guard-band the verdicts (default 0.99)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "datasheet",
	.usage = "datasheet [OPTIONS] [--check CAPTURE] SPEC.ini",
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
		 "bias_stability_10s, bias_stability_100s, run_to_run_bias, scale_factor_error.\n"
		 "Examples:\n"
		 "  sensorscope datasheet samples/datasheets/bmi088.ini\n"
		 "  sensorscope datasheet --check gyro.csv --format json samples/datasheets/stim300.ini\n"
		 "Exit status: 0 done (whatever the verdicts), 1 a file that cannot be read\n"
		 "or used (the line and key named), 2 usage.",
};

struct opts {
	const char *check;
	double ci;
};

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;

	switch (key) {
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

int ssc_cmd_datasheet(int argc, char **argv)
{
	struct ssc_common co;
	struct opts o = { NULL, 0.99 };
	struct ssc_datasheet ds;
	int first, rc;

	rc = ssc_parse(&spec, argc, argv, &co, handler, &o, &first);
	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	if (first >= argc)
		return ssc_usage_error(co.cmd, "give the datasheet file (SPEC.ini)");
	if (first + 1 < argc)
		return ssc_usage_error(co.cmd, "unexpected operand '%s' (the capture goes after --check)",
				       argv[first + 1]);
	if (co.plot)
		return ssc_usage_error(co.cmd, "--plot: this command draws no figure");
	if (co.format == SSC_FMT_CSV)
		return ssc_usage_error(co.cmd, "--format csv: not available (text or json)");
	rc = ssc_datasheet_load(co.cmd, argv[first], &ds);
	if (rc)
		return rc;
	if (o.check)
		return ssc_datasheet_verdicts(&co, &ds, o.check, o.ci);
	return ssc_datasheet_convert(&co, &ds);
}
