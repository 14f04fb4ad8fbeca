/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark of the acquisition path: the simulator records 1,000,000
 * samples at an equivalent 10 kHz (time stamps k / 10 kHz) through the
 * reader thread, the lock-free ring and the writer thread into a CSV
 * capture, paced 10 times faster than real time (100,000 samples/s), then
 * 100,000 samples in real time.  Reported: wall time, sustained samples
 * per second, CPU of the writer and the reader, drops (must be 0), pacing
 * lateness; and the error against a reference: every value of the capture
 * read back and compared with the same seeded simulator run directly
 * (17 significant digits round-trip; only the deg/s <-> rad/s conversion
 * rounds, a few ulp), every time stamp with k / fs.
 * Finally the unpaced source shows the writer's ceiling for CSV and f64:
 * it waits for the writer when the ring is full, so it must drop nothing.
 *
 * Environment: BENCH_ACQ_N (samples, default 1000000), TMPDIR.
 */
#include "config.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "acq/acq.h"

static int record(const char *opts, uint64_t n, const char *path,
		  enum sscope_capture_format fmt, struct ssc_acq_result *r)
{
	struct ssc_source *src;
	struct ssc_acq_config cfg;
	struct sscope_diag d = { "" };
	int rc = ssc_source_sim_open(&src, opts, &d);

	if (rc) {
		fprintf(stderr, "bench-acq: %s\n", d.msg);
		return rc;
	}
	memset(&cfg, 0, sizeof(cfg));
	cfg.src = src;
	cfg.path = path;
	cfg.format = fmt;
	cfg.count = n;
	cfg.timeout_s = 5;
	cfg.ring_capacity = 16384;
	cfg.overwrite = true; /* one scratch file for every run */
	rc = ssc_acq_run(&cfg, r, &d);
	if (rc)
		fprintf(stderr, "bench-acq: %s\n", d.msg);
	ssc_source_close(src);
	return rc;
}

/* compare the capture with the simulator run directly */
static int verify(const char *path, uint64_t n, double fs, double *max_err,
		  double *max_terr)
{
	struct sscope_capture *cap = NULL;
	struct sscope_diag d = { "" };
	struct ssc_source *ref;
	struct ssc_acq_sample s;
	char opts[64];
	int rc = sscope_capture_load(&cap, path, NULL, &d);

	if (rc) {
		fprintf(stderr, "bench-acq: %s\n", d.msg);
		return rc;
	}
	snprintf(opts, sizeof(opts), "rate=%g,speed=max", fs);
	rc = ssc_source_sim_open(&ref, opts, &d);
	*max_err = *max_terr = 0;
	if (!rc && cap->n != n)
		rc = -EDOM;
	for (uint64_t i = 0; !rc && i < n; i++) {
		ref->ops->next(ref, &s, &d);
		for (size_t c = 0; c < cap->n_channels; c++) {
			double e = fabs(cap->channels[c].data[i] - s.v[c]) /
				   fmax(1e-300, fabs(s.v[c]));

			if (e > *max_err)
				*max_err = e;
		}
		if (fabs(cap->time_s[i] - (double)i / fs) > *max_terr)
			*max_terr = fabs(cap->time_s[i] - (double)i / fs);
	}
	ssc_source_close(ref);
	sscope_capture_free(cap);
	return rc;
}

static void report(const char *what, const struct ssc_acq_result *r)
{
	printf("%-44s %8.3f s wall, %8.0f samples/s sustained, writer CPU %.3f s (%.1f %% of wall, %.2f us/sample), reader CPU %.3f s, drops %llu",
	       what, r->wall_s, (double)r->samples / r->wall_s, r->writer_cpu_s,
	       100 * r->writer_cpu_s / r->wall_s,
	       1e6 * r->writer_cpu_s / (double)r->samples, r->reader_cpu_s,
	       (unsigned long long)r->drops_ring);
	if (r->src.late_n)
		printf(", pacing late %.0f us rms / %.0f us max",
		       1e6 * sqrt(r->src.late_sum2_s2 / (double)r->src.late_n),
		       1e6 * r->src.late_max_s);
	putchar('\n');
}

int main(void)
{
	const char *env = getenv("BENCH_ACQ_N");
	uint64_t n = env ? strtoull(env, NULL, 10) : 1000000;
	char path[256];
	struct ssc_acq_result r;
	double err, terr;
	int fails = 0;

	snprintf(path, sizeof(path), "%s/bench-acq-%d.csv",
		 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (int)getpid());

	/* 1 M samples at an equivalent 10 kHz, paced at 100 kHz */
	if (record("rate=10000,speed=10", n, path, SSCOPE_CAPTURE_CSV, &r))
		return 1;
	report("sim 10 kHz x10 pace -> CSV (1 M samples)", &r);
	if (r.drops_ring || r.missing || r.samples != n) {
		printf("FAIL: %llu of %llu samples, %llu dropped\n",
		       (unsigned long long)r.samples, (unsigned long long)n,
		       (unsigned long long)r.drops_ring);
		fails++;
	}
	if (verify(path, n, 10000, &err, &terr)) {
		printf("FAIL: the capture does not read back\n");
		fails++;
	} else {
		printf("%-44s max relative error of values %.3g, of time stamps %.3g s\n",
		       "  read back vs the simulator run directly:", err, terr);
		if (err > 1e-15 || terr > 1e-12)
			fails++;
	}

	/* real time: 100,000 samples at 10 kHz (10 s) */
	if (record("rate=10000,speed=1", n / 10, path, SSCOPE_CAPTURE_CSV, &r))
		return 1;
	report("sim 10 kHz real time -> CSV (100 k samples)", &r);
	if (r.drops_ring || r.missing || r.samples != n / 10)
		fails++;

	/* the writer's ceiling: unpaced source */
	if (record("rate=10000,speed=max", n, path, SSCOPE_CAPTURE_CSV, &r))
		return 1;
	report("sim unpaced -> CSV (writer ceiling)", &r);
	if (r.drops_ring || r.samples != n)
		fails++;
	printf("%-44s %.0f samples/s per writer CPU second\n", "  writer capacity, CSV:",
	       (double)r.samples / r.writer_cpu_s);
	if (record("rate=10000,speed=max", n, path, SSCOPE_CAPTURE_BIN64, &r))
		return 1;
	report("sim unpaced -> f64 binary (writer ceiling)", &r);
	if (r.drops_ring || r.samples != n)
		fails++;
	printf("%-44s %.0f samples/s per writer CPU second\n", "  writer capacity, f64:",
	       (double)r.samples / r.writer_cpu_s);
	unlink(path);
	if (fails)
		printf("FAIL: %d check(s)\n", fails);
	return fails ? 1 : 0;
}
