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
 *
 * bench-allan coverage [N [records [seed]]] (default 1e7, 100, 1): the
 * 68.3 % intervals of OADEV on white FM records (N Gaussian rate samples,
 * GSL's ziggurat): per dense tau with at most 400 averages, the share of
 * records read white FM, the share whose EDF is above twice Greenhall's
 * for white FM, and how often the interval holds the truth 1 / sqrt(m),
 * with the EDF of each tau's own type (Stable32's intervals) and as
 * sensorscope reports it; pooled over 30 to 80 averages at the end.
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

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

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

/* see the file's comment: bench-allan coverage [N [records [seed]]] */
static int coverage(size_t n, size_t R, unsigned long seed)
{
	const double level = 0.682689492137086;
	size_t m[256], nm, np, a0[256] = { 0 }, high[256] = { 0 }, hown[256] = { 0 };
	size_t own[256] = { 0 }, rep[256] = { 0 }, pc = 0, pown = 0, prep = 0;
	struct sscope_allan_point pt[256];
	struct sscope_allan_opts o = { 0 };
	struct sscope_allan *p;
	struct sscope_diag d = { "" };
	double *y = malloc(n * sizeof(double));
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	if (!y || !r || n < 1000)
		return 1;
	nm = grid(1, n, m, 256);
	o.dev = SSCOPE_ALLAN_DEV_OADEV;
	o.input = SSCOPE_ALLAN_RATE;
	if (sscope_allan_new(&p, n, &o))
		return 1;
	gsl_rng_set(r, seed);
	for (size_t rec = 0; rec < R; rec++) {
		for (size_t k = 0; k < n; k++)
			y[k] = gsl_ran_gaussian_ziggurat(r, 1.0);
		if (sscope_allan_compute(p, y, 1, n, 1.0, m, nm, pt, &np, &d)) {
			fprintf(stderr, "bench-allan: %s\n", d.msg);
			return 1;
		}
		for (size_t j = 0; j < np; j++) {
			double want = 1 / sqrt((double)pt[j].m), lo, hi, eo;
			double wfm = sscope_allan_edf(0, 2, pt[j].m, n + 1, false, 1);
			int a = pt[j].alpha < -2 ? -2 : pt[j].alpha;

			if ((double)n / (double)pt[j].m > 400)
				continue;
			a0[j] += pt[j].alpha == 0;
			high[j] += !(pt[j].edf <= 2 * wfm);
			rep[j] += pt[j].dev_lo <= want && want <= pt[j].dev_hi;
			eo = sscope_allan_edf(a, 2, pt[j].m, n + 1, false, 1);
			hown[j] += !(eo <= 2 * wfm);
			ssc_allan_ci(pt[j].dev, eo, level, &lo, &hi);
			own[j] += lo <= want && want <= hi;
		}
	}
	printf("OADEV of white FM, %zu samples, %zu records (seed %lu); 68.3 %% "
	       "intervals, binomial se %.1f points\n", n, R, seed,
	       100 * sqrt(level * (1 - level) / (double)R));
	printf("%10s %8s %8s %21s %22s\n", "", "", "",
	       "EDF > 2x WFM's, %", "interval covers, %");
	printf("%10s %8s %8s %10s %10s %10s %10s\n", "m", "averages", "WFM %",
	       "own type", "reported", "own type", "reported");
	for (size_t j = 0; j < np; j++) {
		double av = (double)n / (double)m[j];

		if (av > 400)
			continue;
		printf("%10zu %8.1f %8.1f %10.1f %10.1f %10.1f %10.1f\n", m[j], av,
		       100.0 * (double)a0[j] / (double)R,
		       100.0 * (double)hown[j] / (double)R,
		       100.0 * (double)high[j] / (double)R,
		       100.0 * (double)own[j] / (double)R,
		       100.0 * (double)rep[j] / (double)R);
		if (av >= 30 && av <= 80) {
			pc += R;
			pown += own[j];
			prep += rep[j];
		}
	}
	if (pc)
		printf("pooled 30-80 averages: own type %.1f %%, reported %.1f %%\n",
		       100.0 * (double)pown / (double)pc,
		       100.0 * (double)prep / (double)pc);
	sscope_allan_free(p);
	gsl_rng_free(r);
	free(y);
	return 0;
}

int main(int argc, char **argv)
{
	double max_n = argc > 1 ? atof(argv[1]) : 1e8;
	const size_t sizes[3] = { 1000000, 10000000, 100000000 };
	int bad = 0;
	unsigned threads = 1;

	if (argc > 1 && !strcmp(argv[1], "coverage"))
		return coverage(argc > 2 ? (size_t)atof(argv[2]) : 10000000,
				argc > 3 ? (size_t)atof(argv[3]) : 100,
				argc > 4 ? strtoul(argv[4], NULL, 10) : 1);
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
