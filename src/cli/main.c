/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope: command dispatch, --help and --version.
 */
#include "cli.h"

#include <limits.h>
#include <malloc.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>

struct command {
	const char *name;
	const char *summary;
	int (*run)(int argc, char **argv);
};

static const struct command commands[] = {
	{ "info", "channels, units, rate, gaps and statistics of a capture",
	  ssc_cmd_info },
	{ "run", "run a scene: only the stages its outputs need, one HTML report",
	  ssc_cmd_run },
	{ "report", "the characterisation report of captures (scene inferred)",
	  ssc_cmd_report },
	{ "psd", "power spectral density (Welch, scipy's numbers), peaks, bands, spectrogram",
	  ssc_cmd_psd },
	{ "vibration", "machinery vibration: ISO severity, shaft orders, bearing envelope, diagnosis",
	  ssc_cmd_vibration },
	{ "acquire", "record a live sensor (SPI + data-ready line) or the simulator",
	  ssc_cmd_acquire },
	{ "calib", "error-model calibration of accelerometer and gyro triads",
	  ssc_cmd_calib },
	{ "budget", "navigation drift budget per error source against time",
	  ssc_cmd_budget },
	{ "model", "sensor physics: proof-mass accelerometer, Sagnac phase",
	  ssc_cmd_model },
	{ "allan", "Allan deviations with intervals, IEEE 952 noise terms",
	  ssc_cmd_allan },
	{ "simulate", "a capture whose noise obeys a sensor specification",
	  ssc_cmd_simulate },
	{ "tempbias", "bias against temperature: fit, hysteresis, repeatability, table",
	  ssc_cmd_tempbias },
	{ "inclino", "inclinometer: temperature look-up-table calibration, tilt with a still flag",
	  ssc_cmd_inclino },
	{ "adc", "will this ADC degrade the sensor: selection report, re-quantize, IEEE 1241 test",
	  ssc_cmd_adc },
	{ "heading", "heading from a vertical gyro, bias re-estimated at every stop, error envelope",
	  ssc_cmd_heading },
	{ "walk", "the random-walk fan of a stationary gyro against its noise terms",
	  ssc_cmd_walk },
	{ "navsim", "strapdown navigation error simulation over Monte-Carlo runs",
	  ssc_cmd_navsim },
	{ "datasheet", "datasheet lines as IEEE 952 terms and back; a capture's verdicts",
	  ssc_cmd_datasheet },
	{ "plan", "record length for a noise term to be resolved to a wanted width",
	  ssc_cmd_plan },
	{ "audit", "other tools' IMU noise files: convention errors, corrected values",
	  ssc_cmd_audit },
	{ "lot", "many units of one model: the spread of their noise terms, outliers",
	  ssc_cmd_lot },
	{ "nav", "strapdown navigation of a capture with zero-velocity updates at stops", ssc_cmd_nav },
};

#define N_COMMANDS (sizeof(commands) / sizeof(commands[0]))

static void usage(FILE *f)
{
	fprintf(f,
		"Usage: sensorscope [--help|--version] COMMAND [OPTIONS] [FILE...]\n"
		"\n"
		"Characterise inertial sensors (gyroscopes, accelerometers,\n"
		"inclinometers) and the converters that digitise them.\n"
		"\n"
		"Commands:\n");
	for (size_t i = 0; i < N_COMMANDS; i++)
		fprintf(f, "  %-12s %s\n", commands[i].name, commands[i].summary);
	fprintf(f,
		"\n"
		"'sensorscope COMMAND --help' describes a command and its options.\n"
		"FILE '-' reads standard input.\n"
		"Exit status: 0 success, 1 runtime or data error, 2 usage error or\n"
		"feature not built.\n");
}

/* GSL's default for an error it cannot return is abort(): a core dump.
 * Such an error means a computation went outside what its routine
 * handles; the command stops with one line and status 1, its temporary
 * files removed (the exit handlers run). */
static void on_gsl_error(const char *reason, const char *file, int line,
			 int gsl_errno)
{
	(void)gsl_errno;
	fprintf(stderr, "sensorscope: a numerical routine failed (GSL, %s:%d: %s): "
		"no result; please report this with the command line\n",
		file, line, reason);
	exit(SSC_EXIT_FAIL);
}

int main(int argc, char **argv)
{
	int rc;

	ssc_signals_init();
	gsl_set_error_handler(on_gsl_error);
	if (argc < 2) {
		usage(stderr);
		return SSC_EXIT_USAGE;
	}
	if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") ||
	    !strcmp(argv[1], "help")) {
		usage(stdout);
		return ssc_stdout_finish(NULL);
	}
	if (!strcmp(argv[1], "--version") || !strcmp(argv[1], "-V")) {
		printf("sensorscope %s (library %s; plots: %s; acquisition: %s)\n",
		       PACKAGE_VERSION, sscope_version(),
		       ssc_plot_installed() ? "yes" : "no",
#ifdef HAVE_LIBGPIOD
		       "libgpiod"
#else
		       "no"
#endif
		);
		return ssc_stdout_finish(NULL);
	}
	/* Large blocks (capture columns, Allan and Welch workspaces, one
	 * after another per channel) are kept by malloc for the next one
	 * instead of being given back to the kernel and zeroed again on
	 * their next first touch: a report of six 8.64-million-sample
	 * channels spent a sixth of its time clearing pages.  A command is
	 * short-lived; its memory is returned when it exits. */
	mallopt(M_MMAP_THRESHOLD, 1 << 30);
	mallopt(M_TRIM_THRESHOLD, 1 << 30);
	for (size_t i = 0; i < N_COMMANDS; i++)
		if (!strcmp(argv[1], commands[i].name)) {
			/* info starts no OpenMP thread: not run twice */
			ssc_omp_wait_passive(argv, commands[i].run != ssc_cmd_info);
			rc = commands[i].run(argc - 1, argv + 1);
			/* help, plans and summaries printed on stdout */
			if (ssc_stdout_finish(commands[i].name) && !rc)
				rc = SSC_EXIT_FAIL;
			return rc;
		}
	ssc_err(NULL, "unknown command '%s' (see 'sensorscope --help')",
		argv[1]);
	return SSC_EXIT_USAGE;
}
