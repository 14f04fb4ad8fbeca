/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark: reading a 1,000,000-row, 7-column CSV (time + 6 channels,
 * values printed with %.9g as IMU loggers do, and again with %.17g as
 * pandas does), reported as MB/s, and the parse checked value by value
 * against strtod (correctly rounded) -- run time against error.  With a
 * file argument: the load of that capture instead (`bench-read FILE
 * [COLUMNS]`), e.g. the 24 h capture of tests/bench-report.sh.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double lcg(uint64_t *s)
{
	*s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
	return (double)(*s >> 11) / 9007199254740992.0;
}

static int run(const char *path, int digits, size_t rows)
{
	FILE *f = fopen(path, "w");
	uint64_t seed = 42;
	struct sscope_capture *cap;
	struct sscope_diag d;
	struct sscope_reader_opts o = { 0 };
	double t0, best = 1e9, mb;
	size_t bytes, bad = 0;
	char *line = NULL;
	size_t cap_line = 0;

	if (!f)
		return 1;
	fprintf(f, "t [s],gx [rad/s],gy [rad/s],gz [rad/s],ax [m/s^2],ay [m/s^2],az [m/s^2]\n");
	for (size_t i = 0; i < rows; i++) {
		fprintf(f, "%.6f", (double)i * 0.005);
		for (int k = 0; k < 6; k++)
			fprintf(f, ",%.*g", digits,
				(lcg(&seed) - 0.5) * (k < 3 ? 0.02 : 0.5) +
					(k == 5 ? 9.80665 : 0));
		fputc('\n', f);
	}
	bytes = (size_t)ftell(f);
	fclose(f);
	mb = (double)bytes / 1e6;
	o.no_time = false;
	for (int rep = 0; rep < 5; rep++) {
		t0 = now();
		if (sscope_capture_load(&cap, path, &o, &d)) {
			fprintf(stderr, "load failed: %s\n", d.msg);
			return 1;
		}
		t0 = now() - t0;
		if (t0 < best)
			best = t0;
		if (rep < 4)
			sscope_capture_free(cap);
	}
	/* every value equal to strtod's */
	f = fopen(path, "r");
	if (getline(&line, &cap_line, f) < 0)
		return 1;
	for (size_t i = 0; i < rows && getline(&line, &cap_line, f) > 0; i++) {
		char *p = line;

		strtod(p, &p);
		for (int k = 0; k < 6; k++) {
			double v = strtod(p + 1, &p);

			if (cap->channels[k].data[i] != v)
				bad++;
		}
	}
	fclose(f);
	free(line);
	printf("read %zu rows x 7 columns (%%.%dg, %.1f MB): best of 5 %.3f s = %.0f MB/s; values differing from strtod: %zu\n",
	       rows, digits, mb, best, mb / best, bad);
	sscope_capture_free(cap);
	remove(path);
	return bad != 0;
}

/* `bench-read FILE [COLUMNS]`: the load of a capture the user has (all
 * columns, or those named), best of 3 on one and on all processors */
static int run_file(const char *path, const char *columns)
{
	for (unsigned th = 1; th <= 2; th++) {
		struct sscope_reader_opts o = { .columns = columns,
					      .threads = th == 1 ? 1 : 0 };
		struct sscope_capture *cap;
		struct sscope_diag d;
		double best = 1e9, t0;
		size_t n = 0;

		for (int rep = 0; rep < 3; rep++) {
			t0 = now();
			if (sscope_capture_load(&cap, path, &o, &d)) {
				fprintf(stderr, "load failed: %s\n", d.msg);
				return 1;
			}
			t0 = now() - t0;
			if (t0 < best)
				best = t0;
			n = cap->n;
			sscope_capture_free(cap);
		}
		printf("%s (%s): %zu rows, %s: best of 3 %.3f s\n", path,
		       columns ? columns : "all columns", n,
		       th == 1 ? "one thread" : "every processor", best);
	}
	return 0;
}

int main(int argc, char **argv)
{
	const char *path = "bench-read.tmp.csv";
	int rc;

	if (argc > 1)
		return run_file(argv[1], argc > 2 ? argv[2] : NULL);
	rc = run(path, 9, 1000000);
	rc |= run(path, 17, 1000000);
	return rc;
}
