/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope audit: another tool's IMU noise file checked for the known
 * convention errors (src/workbench/audit.c reads and checks).
 */
#include "cli.h"

#include "audit.h"

static const struct ssc_option audit_opts[] = {
	{ "rate", required_argument, 'r', "HZ",
	  "the IMU's rate: used when the file gives none (imu_utils never does), a finding when update_rate differs" },
	{ "strict", no_argument, 300, NULL,
	  "exit 1 when there are findings (for CI); the report is written all the same" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "audit",
	.usage = "audit [OPTIONS] FILE.yaml",
	.summary =
		"Check another tool's IMU noise file - Kalibr imu.yaml, OpenVINS\n"
		"kalibr_imu_chain.yaml (imu0), imu_utils' parameter YAML (avg-axis),\n"
		"allan_variance_ros' imu.yaml or its printed summary - for the known\n"
		"convention errors: a bias instability in a random-walk field, a\n"
		"missing 0.6643 (Allan minimum as B), a per-sample sigma*sqrt(f) as a\n"
		"density, a discrete value in a continuous field, 0, negative or NaN\n"
		"values, a missing update_rate, implausible magnitudes.  One line per\n"
		"finding: file, line, key, what is wrong and why, the corrected value.",
	.options = audit_opts,
	.output_opts = true,
	.notes = "Severity: 'error' when the file proves it, 'likely' when the evidence is\n"
		 "circumstantial (a magnitude or a ratio).\n"
		 "Example: sensorscope audit --format json imu.yaml\n"
		 "Exit status: 0 the file was read (findings or not; with --strict 1 when\n"
		 "there are findings), 1 a file that cannot be read or is none of these\n"
		 "formats, 2 usage.",
	.no_csv = true,
};

struct opts {
	double rate;
	bool strict;
};

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;

	if (key == 300) {
		o->strict = true;
		return 0;
	}
	if (key != 'r')
		return ssc_usage_error("audit", "unexpected option");
	if (ssc_arg_double("audit", "rate", arg, &o->rate))
		return SSC_EXIT_USAGE;
	return o->rate > 0 && o->rate < 1e12 ? 0 :
		ssc_usage_error("audit", "--rate: a rate in Hz above 0");
}

int ssc_cmd_audit(int argc, char **argv)
{
	struct ssc_common co;
	struct opts o = { 0, false };
	int first, rc = ssc_parse(&spec, argc, argv, &co, handler, &o, &first);

	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	if (first >= argc)
		return ssc_usage_error(co.cmd, "give the noise file (FILE.yaml)");
	if (first + 1 < argc)
		return ssc_usage_error(co.cmd, "one file at a time (unexpected '%s')",
				       argv[first + 1]);
	if (co.format == SSC_FMT_CSV)
		return ssc_usage_error(co.cmd, "--format csv: not available (text or json)");
	return ssc_audit_run(&co, argv[first], o.rate, o.strict);
}
