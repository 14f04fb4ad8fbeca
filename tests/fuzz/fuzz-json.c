/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Fuzz harness of the JSON files sensorscope reads back: a calibration
 * file of 'calib' (--calibration, applied to a capture with accelerometer
 * and gyro channels) and an inclinometer look-up table of 'inclino
 * calibrate' (inclino apply --lut, then interpolated and applied).
 */
#include "fuzz.h"

#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "calibfile.h"
#include "sscope-inclino.h"

static struct sscope_capture *capture(void)
{
	static const char *const names[] = { "ax", "ay", "az", "gx", "gy", "gz" };
	static const char *const units[] = { "m/s^2", "m/s^2", "m/s^2",
					     "rad/s", "rad/s", "rad/s" };
	struct sscope_capture *cap = sscope_capture_new(6, 16, true, true);

	if (!cap)
		return NULL;
	cap->rate_hz = 100;
	for (size_t k = 0; k < 6; k++) {
		sscope_capture_set_channel(cap, k, names[k], units[k]);
		for (size_t i = 0; i < 16; i++)
			cap->channels[k].data[i] = (k == 2 ? 9.81 : 0.01) +
						   1e-3 * (double)(i * (k + 1) % 7);
	}
	for (size_t i = 0; i < 16; i++) {
		cap->time_s[i] = 0.01 * (double)i;
		cap->temp_degc[i] = -40 + 8.5 * (double)i;
	}
	return cap;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	fuzz_quiet();
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct sscope_inclino_lut *lut = malloc(sizeof(*lut));
	struct sscope_capture *cap = capture();
	char path[64];
	int fd = fuzz_file(data, size, path, sizeof(path));

	if (fd >= 0 && cap) {
		/* what sscope_capture_open() does with --calibration */
		struct sscope_calib_file_triad *t;
		struct sscope_diag d = { "" };
		size_t n;

		if (ssc_calfile_read("info", path, &t, &n) == 0) {
			sscope_capture_apply_calib(cap, t, n, NULL, NULL, &d);
			free(t);
		}
	}
	if (fd >= 0 && lut && ssc_inclino_lut_read("inclino", path, lut) == 0) {
		struct sscope_inclino_plan *plan;
		struct sscope_diag d = { "" };

		for (int cubic = 0; cubic < 2; cubic++) {
			if (sscope_inclino_plan_new(&plan, lut, cubic, &d))
				continue;
			for (int i = 0; i < 8; i++) {
				double raw[3] = { 0.3, -0.2, 9.8 }, out[3];
				bool clamped;

				sscope_inclino_correct(plan, -60 + 20.5 * i, raw,
						       out, &clamped);
			}
			sscope_inclino_plan_free(plan);
		}
	}
	fuzz_file_close(fd);
	sscope_capture_free(cap);
	free(lut);
	return 0;
}
