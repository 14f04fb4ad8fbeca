/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Benchmark of the Allan engine: N = 1e6, 1e7, 1e8 rate samples (white
 * noise plus a random walk on a bias 2.4e6 times the noise), octave and
 * dense grids, for each method variant:
 *   fused     the default engine (tiled phase, short taus fused into the
 *             phase pass, long taus row by row), all threads
 *   fused/1   the same on one thread
 *   per-tau   the straightforward engine: contiguous phase, one pass over
 *             it per tau (parallel over taus)
 *   +CI       the default engine plus noise identification, EDF and
 *             chi-squared bounds (what `sensorscope allan` does)
 *   strided8  the strided-overlap estimator, terms every m/8 samples
 * reporting wall time (best of several runs), peak memory (each variant
 * runs in its own child process: peak RSS over the input size, and the
 * engine's own allocation over the input size) and the largest relative
 * error of the Allan variance against a long-double reference computed
 * from the same data (compensated phase, compensated sums; for strided8
 * the strided estimator's own reference).  Exits non-zero when an error
 * exceeds 1e-9, so a faster but wrong kernel cannot pass.
 * Usage: bench-allan [max_n]  (default 1e8).
 */
#include "allan-internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

enum { M_FUSED = 0, M_FUSED1, M_PERTAU, M_CI, M_STRIDED, M_COUNT };
static const char *const mname[M_COUNT] = { "fused", "fused/1", "per-tau",
					    "+CI", "strided8" };

static double now(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static double rss_mb(void)
{
	struct rusage ru;

	getrusage(RUSAGE_SELF, &ru);
	return (double)ru.ru_maxrss / 1024.0;
}

/* deterministic test data: splitmix64 uniforms, Irwin-Hall normals */
static uint64_t sm(uint64_t *x)
{
	uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);

	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
	return z ^ (z >> 31);
}

static double gauss(uint64_t *s)
{
	double u = 0;

	for (int i = 0; i < 4; i++)
		u += (double)(sm(s) >> 11) * 0x1.0p-53;
	return (u - 2) * sqrt(3.0);
}

static double *make_data(size_t n)
{
	double *y = malloc(n * sizeof(double)), w = 0;
	uint64_t s = 2385;

	if (!y)
		return NULL;
	for (size_t i = 0; i < n; i++) {
		w += 1e-3 * gauss(&s);
		y[i] = 2.385e6 + gauss(&s) + w;
	}
	return y;
}

static size_t grid(int dense, size_t n, size_t *m, size_t cap)
{
	size_t c;

	sscope_allan_grid(dense ? SSCOPE_ALLAN_TAUS_DENSE : SSCOPE_ALLAN_TAUS_OCTAVE,
			  sscope_allan_max_m(SSCOPE_ALLAN_DEV_OADEV, n + 1), m, cap, &c);
	return c < cap ? c : cap;
}

/* long-double reference of AVAR (stride 1, or m / div) */
static void reference(const double *y, size_t n, const size_t *m, size_t nm,
		      size_t div, double *out)
{
	long double mean = 0, c = 0, *x = malloc((n + 1) * sizeof(long double));

	for (size_t i = 0; i < n; i++) {
		long double t = mean + y[i];

		c += (mean - t) + y[i];
		mean = t;
	}
	mean = (mean + c) / (long double)n;
	x[0] = 0;
	{
		long double s = 0, cc = 0;

		for (size_t i = 0; i < n; i++) {
			long double v = (long double)y[i] - mean, t = s + v;

			cc += (s - t) + v;
			s = t;
			x[i + 1] = s + cc;
		}
	}
SSC_OMP(omp parallel for schedule(dynamic, 1))
	for (size_t j = 0; j < nm; j++) {
		size_t s = div ? (m[j] / div ? m[j] / div : 1) : 1;
		size_t nt = n + 1 - 2 * m[j], terms = 0;
		long double acc = 0, cc = 0;

		for (size_t i = 0; i < nt; i += s) {
			long double d = x[i + 2 * m[j]] - 2 * x[i + m[j]] + x[i];
			long double v = d * d, t = acc + v;

			cc += (acc - t) + v;
			acc = t;
			terms++;
		}
		out[j] = (double)((acc + cc) /
				  (2.0L * (long double)m[j] * (long double)m[j] *
				   (long double)terms));
	}
	free(x);
}

struct result {
	double ms, rss_ratio, extra_ratio;
	size_t nm;
	int ok;
};

/* run one variant in a child; results and values through a pipe */
static int run_child(int method, size_t n, int dense, struct result *r,
		     double *vals, int is_ref)
{
	int fd[2];
	pid_t pid;

	if (pipe(fd))
		return -1;
	pid = fork();
	if (pid < 0)
		return -1;
	if (pid == 0) {
		size_t m[256], nm = grid(dense, n, m, 256);
		double *y, base, *v = calloc(nm, sizeof(double));
		struct result res = { 0 };

		close(fd[0]);
		y = make_data(n);
		base = rss_mb();
		if (!y || !v)
			_exit(1);
		if (is_ref) {
			reference(y, n, m, nm, method == M_STRIDED ? 8 : 0, v);
		} else {
			struct sscope_allan_opts o = { 0 };
			struct sscope_allan *p;
			struct sscope_allan_point *pt = calloc(nm, sizeof(*pt));
			size_t np;
			int reps = n >= 100000000 ? 2 : 5;

			o.ci_level = method == M_CI ? 0 : -1;
			o.alpha_fixed = method != M_CI;
			o.threads = method == M_FUSED1 ? 1 : 0;
			o.stride_div = method == M_STRIDED ? 8 : 0;
			if (sscope_allan_new(&p, n, &o))
				_exit(1);
			ssc_allan_force_contiguous(p, method == M_PERTAU);
			res.ms = INFINITY;
			for (int k = 0; k <= reps; k++) {
				double t = now();

				if (sscope_allan_compute(p, y, 1, n, 1, m, nm, pt,
							 &np, NULL))
					_exit(1);
				t = now() - t;
				/* the first run also faults in the workspace */
				if (k && t * 1e3 < res.ms)
					res.ms = t * 1e3;
			}
			for (size_t j = 0; j < nm; j++)
				v[j] = pt[j].dev * pt[j].dev;
			sscope_allan_free(p);
			free(pt);
		}
		res.nm = nm;
		res.rss_ratio = rss_mb() * 1048576.0 / (8.0 * (double)n);
		res.extra_ratio = (rss_mb() - base) * 1048576.0 / (8.0 * (double)n);
		res.ok = 1;
		if (write(fd[1], &res, sizeof(res)) != (ssize_t)sizeof(res) ||
		    write(fd[1], v, nm * sizeof(double)) != (ssize_t)(nm * sizeof(double)))
			_exit(1);
		_exit(0);
	}
	close(fd[1]);
	{
		size_t got = 0;
		ssize_t k;
		char *dst = (char *)r;

		while (got < sizeof(*r) && (k = read(fd[0], dst + got, sizeof(*r) - got)) > 0)
			got += (size_t)k;
		if (got == sizeof(*r)) {
			size_t want = r->nm * sizeof(double);

			got = 0;
			dst = (char *)vals;
			while (got < want && (k = read(fd[0], dst + got, want - got)) > 0)
				got += (size_t)k;
		}
	}
	close(fd[0]);
	{
		int st;

		waitpid(pid, &st, 0);
		if (!WIFEXITED(st) || WEXITSTATUS(st))
			return -1;
	}
	return 0;
}

int main(int argc, char **argv)
{
	double max_n = argc > 1 ? atof(argv[1]) : 1e8;
	const size_t sizes[3] = { 1000000, 10000000, 100000000 };
	int bad = 0;
	unsigned threads = 1;

#ifdef _OPENMP
	threads = (unsigned)omp_get_max_threads();
#endif
	printf("Allan engine, OADEV of N rate samples (bias 2.4e6 x noise), %u threads available\n",
	       threads);
	printf("%-10s %-7s %-9s %5s %10s %9s %9s %11s\n", "N", "grid", "method",
	       "taus", "time ms", "RSS/in", "extra/in", "max relerr");
	for (int si = 0; si < 3; si++) {
		size_t n = sizes[si];

		if ((double)n > max_n)
			break;
		for (int dense = 0; dense < 2; dense++) {
			double ref[256], ref8[256], v[256];
			struct result r;

			if (run_child(M_FUSED, n, dense, &r, ref, 1) ||
			    run_child(M_STRIDED, n, dense, &r, ref8, 1)) {
				fprintf(stderr, "bench-allan: reference failed\n");
				return 1;
			}
			for (int me = 0; me < M_COUNT; me++) {
				double err = 0;
				const double *rf = me == M_STRIDED ? ref8 : ref;

				/* the per-tau engine at 1e8 on a dense grid
				 * takes minutes: skipped, said so */
				if (me == M_PERTAU && n >= 100000000 && dense) {
					printf("%-10zu %-7s %-9s %5s %10s\n", n,
					       "dense", mname[me], "-", "skipped");
					continue;
				}
				if (run_child(me, n, dense, &r, v, 0)) {
					fprintf(stderr, "bench-allan: %s failed\n", mname[me]);
					return 1;
				}
				for (size_t j = 0; j < r.nm; j++)
					err = fmax(err, fabs(v[j] / rf[j] - 1));
				printf("%-10zu %-7s %-9s %5zu %10.1f %9.2f %9.2f %11.2e\n",
				       n, dense ? "dense" : "octave", mname[me], r.nm,
				       r.ms, r.rss_ratio, r.extra_ratio, err);
				fflush(stdout);
				if (!(err < 1e-9))
					bad = 1;
			}
		}
	}
	if (bad)
		fprintf(stderr, "bench-allan: an error above 1e-9\n");
	return bad;
}
