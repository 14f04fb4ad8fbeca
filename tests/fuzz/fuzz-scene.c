/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Fuzz harness of scene files (sensorscope run SCENE.ini): the INI parser,
 * every section's keys (stage options parsed as the command's own, inline
 * or referenced sensor/ADC specs, report formats), the stage graph, and
 * the printed plan (run --dry-run).  Nothing is run.  The scene is written
 * into a private folder that also holds small files under the names the
 * bundled scenes use, so paths in the corpus resolve.
 */
#include "fuzz.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "scene.h"

static FILE *devnull;
static char dir[256], scene[300];

static const char capture_text[] = "t [s],gx [deg/s],ax [g],temp [degC]\n"
				   "0,0.1,0.01,20\n0.01,0.2,0.02,20.5\n";
static const char sensor_text[] = "[sensor]\nname = g\nrange = 100 deg/s\n"
				  "noise_density = 0.005 deg/sqrt(h)\n"
				  "bias_instability = 1 deg/h\n";
static const char adc_text[] = "[adc]\nname = a\nbits = 16\n"
			       "range = -100:100 deg/s\nrate = 100 Hz\n";
static const struct {
	const char *name, *text;
} files[] = {
	{ "bearing-outer.csv", capture_text },
	{ "gyro-static.csv", capture_text },
	{ "imu-multipose.csv", capture_text },
	{ "inclino-cal.csv", capture_text },
	{ "inclino-val.csv", capture_text },
	{ "accel-thermal.csv", capture_text },
	{ "capture.csv", capture_text },
	{ "gyro.ini", sensor_text },
	{ "gyro-textbook-quiet.ini", sensor_text },
	{ "adc-textbook-16bit.ini", adc_text },
	{ "adc-textbook-18bit.ini", adc_text },
	{ "adc-textbook-16bit-os16.ini", adc_text },
	{ "adc.ini", adc_text },
};

static void write_file(const char *path, const void *data, size_t size)
{
	FILE *f = fopen(path, "wb");

	if (f) {
		fwrite(data, 1, size, f);
		fclose(f);
	}
}

static void cleanup(void)
{
	char p[400];

	for (size_t i = 0; i < sizeof(files) / sizeof(files[0]); i++) {
		snprintf(p, sizeof(p), "%s/%s", dir, files[i].name);
		unlink(p);
	}
	unlink(scene);
	rmdir(dir);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	const char *tmp = getenv("TMPDIR");
	char p[400];

	(void)argc;
	(void)argv;
	fuzz_quiet();
	devnull = fopen("/dev/null", "w");
	snprintf(dir, sizeof(dir), "%s/sscope-fuzz-scene.XXXXXX",
		 tmp && *tmp ? tmp : "/tmp");
	if (!mkdtemp(dir))
		abort();
	for (size_t i = 0; i < sizeof(files) / sizeof(files[0]); i++) {
		snprintf(p, sizeof(p), "%s/%s", dir, files[i].name);
		write_file(p, files[i].text, strlen(files[i].text));
	}
	snprintf(scene, sizeof(scene), "%s/fuzz.scene.ini", dir);
	atexit(cleanup);
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct ssc_scene *sc;

	write_file(scene, data, size);
	if (ssc_scene_load("run", scene, ssc_scene_graph(), &sc) == SSC_EXIT_OK) {
		if (devnull)
			ssc_scene_plan(sc, devnull);
		ssc_scene_free(sc);
	}
	return 0;
}
