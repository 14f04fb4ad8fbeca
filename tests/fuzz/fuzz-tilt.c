/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Fuzz harness of interval tables: inclino --tilt-table (START END ROLL
 * PITCH, bare angles in degrees) and calib --schedule share this reader
 * (ssc_read_intervals); read as a tilt table and as a one-value table.
 */
#include "fuzz.h"

#include <stdlib.h>

#include "cli.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	fuzz_quiet();
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct ssc_common co = { .cmd = "inclino" };
	char path[64];
	double *v;
	size_t rows;
	int fd = fuzz_file(data, size, path, sizeof(path));

	if (fd < 0)
		return 0;
	if (ssc_read_intervals(&co, "tilt-table", path, "ROLL PITCH", 2, "rad",
			       "deg", &v, &rows) == SSC_EXIT_OK)
		free(v);
	co.cmd = "calib";
	if (ssc_read_intervals(&co, "schedule", path, "VALUE", 1, "rad/s",
			       NULL, &v, &rows) == SSC_EXIT_OK)
		free(v);
	fuzz_file_close(fd);
	return 0;
}
