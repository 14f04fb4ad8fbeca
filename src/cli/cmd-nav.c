/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope nav: strapdown navigation of a recorded 6-axis capture with
 * zero-velocity updates at every stop (src/workbench/nav.c presents,
 * analysis/zupt.c computes).
 */
#include "cli.h"

#include "nav.h"
#include "stage.h"

static const struct ssc_option nav_opts[] = {
	{ "latitude", required_argument, SSC_NAV_O_LAT, "DEG", "start latitude (default 45)" },
	{ "longitude", required_argument, SSC_NAV_O_LON, "DEG", "start longitude (default 0)" },
	{ "height", required_argument, SSC_NAV_O_HEIGHT, "H", "start height above the WGS 84 ellipsoid (default 0 m)" },
	{ "heading", required_argument, SSC_NAV_O_HEADING, "DEG",
	  "initial heading (default: gyrocompassing when the gyro can sense the Earth rate, else 0 with a warning)" },
	{ "from-allan", required_argument, SSC_NAV_O_ALLAN, "RESULT.json",
	  "noise terms N, B, K of the worst gyro and accelerometer channels of an 'allan' result" },
	{ "spec", required_argument, SSC_NAV_O_SPEC, "FILE",
	  "noise terms from a datasheet INI ([gyro] and [accel] lines, as 'datasheet')" },
	{ "no-zupt", no_argument, SSC_NAV_O_NO_ZUPT, NULL,
	  "detect the stops but apply no update (free inertial, for comparison)" },
	{ "window", required_argument, SSC_NAV_O_WINDOW, "T", "stop detector window (default 0.5 s)" },
	{ "output-step", required_argument, SSC_NAV_O_STEP, "T",
	  "a trajectory record every T (default: about 1000 records)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "nav",
	.usage = "nav [OPTIONS] FILE",
	.summary =
		"Strapdown navigation of a 6-axis capture (three gyro and three\n"
		"accelerometer channels, body axes x forward, y right, z down) that starts\n"
		"still: levelling on the first still interval, gyrocompassing when the gyro\n"
		"allows, then a 15-state error-state Kalman filter with zero-velocity and\n"
		"zero-angular-rate updates at every stop found by a sliding-window\n"
		"detector; the gyro and accelerometer biases are re-estimated at every stop.\n"
		"Output: the trajectory with its 1-sigma, the stops, the biases against time.",
	.options = nav_opts,
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope nav --heading 30 samples/walk-stops.csv\n"
		 "  sensorscope nav --from-allan allan.json --format csv -o track.csv imu.bag\n"
		 "Noise terms without --from-allan or --spec: gyro N 0.3 deg/sqrt(h),\n"
		 "B 10 deg/h; accelerometer N 0.1 m/s/sqrt(h), B 0.1 mg; turn-on biases\n"
		 "0.5 deg/s and 20 mg (1 sigma).  --format csv writes navsim's trajectory\n"
		 "columns (time, north, east, down, roll, pitch, yaw) first.\n"
		 "Exit status: 0 done, 1 a capture that cannot be navigated (no three\n"
		 "gyro or accelerometer channels, NaN, too short, not still at the start),\n"
		 "2 usage.",
};

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const struct ssc_result *up = ssc_stage_upstream(env, &ssc_allan_stage, NULL);

	return ssc_nav_run(env, up ? up->data : NULL, opts, result);
}

const struct ssc_stage_ops ssc_nav_stage = {
	.spec = &spec,
	.title = "Navigation with stop updates",
	.needs = SSC_NEED_DATA,
	.min_files = 1,
	.max_files = 1,
	.opts_size = sizeof(struct ssc_nav_opts),
	.init = ssc_nav_init,
	.handle = ssc_nav_handle,
	.check = ssc_nav_check,
	.run = run,
	.json = ssc_nav_json,
	.text = ssc_nav_text,
	.csv = ssc_nav_csv,
	.summary = ssc_nav_summary,
	.plot = ssc_nav_plot,
	.free_result = ssc_nav_free,
};

int ssc_cmd_nav(int argc, char **argv)
{
	return ssc_stage_main(&ssc_nav_stage, argc, argv);
}
