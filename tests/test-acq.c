/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The acquisition path without hardware: the lock-free ring (sequential
 * and with a concurrent producer and consumer), interval statistics, gap
 * logic from time stamps and from a wrapping counter, the running Allan
 * deviation (closed forms: alternating and white noise), the simulator
 * (seeded, sd = N sqrt(fs)), and the engine driven by a scripted source:
 * count, duration, gaps marked in the capture, ring overruns accounted
 * exactly, timeouts, held samples flushed, binary output, write errors.
 * The recording file: rows reach NAME.partial while the run goes on, a
 * full disk cuts it at its last complete row and keeps it, an existing
 * file is never replaced unless asked, and a source that can wait is held
 * back instead of losing samples.
 */
#include "config.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <sys/stat.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "acq/acq.h"
#include "check-main.h"

static bool slow(void)
{
	const char *r = getenv("SSCOPE_RUN");

	return r && *r;
}

static char tmpdir[128];

static const char *tmp(const char *name)
{
	static char buf[4][256];
	static int i;

	if (!tmpdir[0]) {
		snprintf(tmpdir, sizeof(tmpdir), "%s/sscope-acq-XXXXXX",
			 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
		ck_assert_ptr_nonnull(mkdtemp(tmpdir));
	}
	i = (i + 1) % 4;
	snprintf(buf[i], sizeof(buf[i]), "%s/%s", tmpdir, name);
	return buf[i];
}

/* ------------------------------------------------------------ ring */

START_TEST(ring_sequential)
{
	struct ssc_ring r;
	struct ssc_acq_sample s, out[16];

	ck_assert_int_eq(ssc_ring_init(&r, 1), -EINVAL);
	ck_assert_int_eq(ssc_ring_init(&r, 5), 0);
	ck_assert_uint_eq(ssc_ring_capacity(&r), 8);
	memset(&s, 0, sizeof(s));
	/* many laps around the ring: order kept, full and empty exact */
	for (int lap = 0, next = 0, got = 0; lap < 50; lap++) {
		int n = 0;

		while (true) {
			s.t_ns = next;
			if (!ssc_ring_push(&r, &s))
				break;
			next++;
			n++;
		}
		ck_assert_int_eq(n, lap ? 8 : 8);
		n = (int)ssc_ring_pop(&r, out, 3);
		ck_assert_int_eq(n, 3);
		for (int i = 0; i < 3; i++)
			ck_assert_int_eq(out[i].t_ns, got++);
		n = (int)ssc_ring_pop(&r, out, 16);
		ck_assert_int_eq(n, 5);
		for (int i = 0; i < 5; i++)
			ck_assert_int_eq(out[i].t_ns, got++);
		ck_assert_uint_eq(ssc_ring_pop(&r, out, 16), 0);
	}
	ssc_ring_free(&r);
}
END_TEST

struct spsc {
	struct ssc_ring r;
	long n;
	long errors;
};

static void *producer(void *arg)
{
	struct spsc *q = arg;
	struct ssc_acq_sample s;

	memset(&s, 0, sizeof(s));
	for (long i = 0; i < q->n; i++) {
		s.t_ns = i;
		s.v[0] = (double)i * 0.5;
		s.v[15] = -(double)i;
		while (!ssc_ring_push(&q->r, &s))
			sched_yield();
	}
	return NULL;
}

START_TEST(ring_concurrent)
{
	struct spsc q = { .n = slow() ? 20000 : 1000000 };
	struct ssc_acq_sample out[64];
	pthread_t t;
	long next = 0;

	ck_assert_int_eq(ssc_ring_init(&q.r, 64), 0);
	ck_assert_int_eq(pthread_create(&t, NULL, producer, &q), 0);
	while (next < q.n) {
		size_t n = ssc_ring_pop(&q.r, out, 64);

		if (!n)
			sched_yield();
		for (size_t i = 0; i < n; i++, next++)
			if (out[i].t_ns != next || out[i].v[0] != (double)next * 0.5 ||
			    out[i].v[15] != -(double)next)
				q.errors++;
	}
	pthread_join(t, NULL);
	/* every item once, in order, with its payload intact */
	ck_assert_int_eq(next, q.n);
	ck_assert_int_eq(q.errors, 0);
	ck_assert_uint_eq(ssc_ring_pop(&q.r, out, 64), 0);
	ssc_ring_free(&q.r);
}
END_TEST

/* ------------------------------------------------------------ stats */

START_TEST(intervals)
{
	struct ssc_intervals iv;
	const double x[] = { 2.5e-3, 2.0e-3, 3.5e-3, 2.0e-3 };

	memset(&iv, 0, sizeof(iv));
	ck_assert(isnan(ssc_intervals_sd(&iv)));
	for (int i = 0; i < 4; i++)
		ssc_intervals_add(&iv, x[i]);
	ck_assert_uint_eq(iv.n, 4);
	ck_assert_rel(iv.mean_s, 2.5e-3, 1e-15);
	/* deviations 0, -0.5, 1, -0.5 ms: sum of squares 1.5e-6 / 3 */
	ck_assert_rel(ssc_intervals_sd(&iv), sqrt(1.5e-6 / 3), 1e-12);
	ck_assert(iv.min_s == 2.0e-3 && iv.max_s == 3.5e-3);
}
END_TEST

START_TEST(gaps_from_time)
{
	const double T = 1.0 / 2000;

	ck_assert_uint_eq(ssc_gap_from_time(T, T), 0);
	ck_assert_uint_eq(ssc_gap_from_time(1.4 * T, T), 0);
	ck_assert_uint_eq(ssc_gap_from_time(1.6 * T, T), 1);
	ck_assert_uint_eq(ssc_gap_from_time(8 * T, T), 7);
	ck_assert_uint_eq(ssc_gap_from_time(0.3 * T, T), 0);
	ck_assert_uint_eq(ssc_gap_from_time(-5 * T, T), 0);
	ck_assert_uint_eq(ssc_gap_from_time(3 * T, 0), 0);
	ck_assert_uint_eq(ssc_gap_from_time(NAN, T), 0);
}
END_TEST

START_TEST(gaps_from_counter)
{
	const double T = 1.0 / 2000;

	ck_assert_int_eq(ssc_gap_from_counter(5, 6, T, T), 0);
	ck_assert_int_eq(ssc_gap_from_counter(5, 9, 4 * T, T), 3);
	ck_assert_int_eq(ssc_gap_from_counter(65535, 0, T, T), 0);
	ck_assert_int_eq(ssc_gap_from_counter(65530, 3, 9 * T, T), 8);
	/* a repeat, unless the time says a whole wrap went by */
	ck_assert_int_eq(ssc_gap_from_counter(7, 7, 0.2 * T, T), -1);
	ck_assert_int_eq(ssc_gap_from_counter(7, 7, 65536 * T, T), 65535);
	/* 10 steps, or 10 + 65536 when 65546 periods passed */
	ck_assert_int_eq(ssc_gap_from_counter(10, 20, 10 * T, T), 9);
	ck_assert_int_eq(ssc_gap_from_counter(10, 20, 65546 * T, T), 65545);
	/* the time decides wraps only: jitter of a few periods is ignored */
	ck_assert_int_eq(ssc_gap_from_counter(10, 20, 13 * T, T), 9);
	/* without a period the counter alone */
	ck_assert_int_eq(ssc_gap_from_counter(10, 20, 65546 * T, 0), 9);
}
END_TEST

START_TEST(run_adev_closed_forms)
{
	struct ssc_run_adev a;
	gsl_rng *rng;
	size_t n = slow() ? 100000 : 1000000;
	const double sigma = 2.385;

	/* constant: zero */
	ssc_run_adev_init(&a);
	for (int i = 0; i < 3000; i++)
		ssc_run_adev_add(&a, 9.80665);
	for (size_t k = 0; k < 4; k++)
		ck_assert(ssc_run_adev_get(&a, k) == 0);
	/* +1, -1, ...: m = 1 differences are +-2, AVAR = 4 / 2; blocks of
	 * 10 and more average to 0 */
	ssc_run_adev_init(&a);
	for (int i = 0; i < 4000; i++)
		ssc_run_adev_add(&a, i % 2 ? -1.0 : 1.0);
	ck_assert_rel(ssc_run_adev_get(&a, 0), sqrt(2.0), 1e-15);
	ck_assert(ssc_run_adev_get(&a, 1) == 0);
	ck_assert(ssc_run_adev_get(&a, 3) == 0);
	/* too few blocks: NaN; a break restarts the blocks */
	ssc_run_adev_init(&a);
	for (int i = 0; i < 1500; i++)
		ssc_run_adev_add(&a, (double)i);
	ck_assert(isnan(ssc_run_adev_get(&a, 3)));
	ssc_run_adev_break(&a);
	for (int i = 0; i < 1500; i++)
		ssc_run_adev_add(&a, (double)i);
	ck_assert(isnan(ssc_run_adev_get(&a, 3)));
	/* white noise: ADEV(m) = sigma / sqrt(m); the non-overlapping
	 * estimator over K = n/m blocks has relative sd 1/sqrt(2 (K - 1));
	 * accept 4 of those */
	rng = gsl_rng_alloc(gsl_rng_mt19937);
	gsl_rng_set(rng, 20240607);
	ssc_run_adev_init(&a);
	for (size_t i = 0; i < n; i++)
		ssc_run_adev_add(&a, gsl_ran_gaussian_ziggurat(rng, sigma));
	for (size_t k = 0; k < 4; k++) {
		double m = (double)a.m[k], K = (double)n / m;

		ck_assert_rel(ssc_run_adev_get(&a, k), sigma / sqrt(m),
			      4 / sqrt(2 * (K - 1)));
	}
	gsl_rng_free(rng);
}
END_TEST

/* ------------------------------------------------------------ sim */

START_TEST(sim_source)
{
	struct ssc_source *s1, *s2, *s3;
	struct sscope_diag d = { "" };
	struct ssc_acq_sample a, b;
	size_t n = slow() ? 20000 : 200000;
	double sum = 0, sum2 = 0, mz = 0;
	/* 0.5 deg/sqrt(h) at 2 kHz: per-sample sd = N sqrt(fs) */
	const double N = 0.5 * M_PI / 180 / 60, fs = 2000;

	ck_assert_int_eq(ssc_source_sim_open(&s1, "rate=2kHz,seed=7,speed=max,arw=0.5deg/sqrt(h)",
					     &d), 0);
	ck_assert_int_eq(ssc_source_sim_open(&s2, "seed=7,speed=max,rate=2000,arw=0.5deg/sqrt(h)",
					     &d), 0);
	ck_assert_int_eq(ssc_source_sim_open(&s3, "rate=2000,seed=8,speed=max", &d),
			 0);
	ck_assert_uint_eq(s1->info.n_channels, 6);
	ck_assert(s1->info.rate_hz == 2000);
	ck_assert(s1->info.has_temp && !s1->info.has_counter);
	ck_assert_str_eq(s1->info.name[5], "az");
	ck_assert_str_eq(s1->info.unit[0], "deg/s");
	for (size_t i = 0; i < n; i++) {
		ck_assert_int_eq(s1->ops->next(s1, &a, &d), 0);
		ck_assert_int_eq(s2->ops->next(s2, &b, &d), 0);
		/* same seed, same values; nominal time stamps */
		ck_assert(a.v[0] == b.v[0] && a.v[5] == b.v[5]);
		ck_assert_int_eq(a.t_ns, (int64_t)i * 500000);
		sum += a.v[0];
		sum2 += a.v[0] * a.v[0];
		mz += a.v[5];
	}
	ck_assert_int_eq(s3->ops->next(s3, &b, &d), 0);
	ck_assert_int_eq(s1->ops->next(s1, &a, &d), 0);
	ck_assert(a.v[0] != b.v[0]);
	{
		double sd = sqrt(sum2 / (double)n - sum * sum / ((double)n * n));
		double want = N * sqrt(fs);

		/* sd of a sample sd: sigma / sqrt(2 n); 4 of those */
		ck_assert_rel(sd, want, 4 / sqrt(2.0 * (double)n));
		/* az mean: g within 4 sigma / sqrt(n) */
		ck_assert(fabs(mz / (double)n - 9.80665) <
			  4 * 0.037 / 60 * sqrt(fs) / sqrt((double)n));
	}
	ssc_source_close(s1);
	ssc_source_close(s2);
	ssc_source_close(s3);
	/* refusals */
	ck_assert_int_eq(ssc_source_sim_open(&s1, "rate=0", &d), -EINVAL);
	ck_assert_int_eq(ssc_source_sim_open(&s1, "channels=7", &d), -EINVAL);
	ck_assert_int_eq(ssc_source_sim_open(&s1, "arw=3m/s", &d), -EINVAL);
	ck_assert_int_eq(ssc_source_sim_open(&s1, "speed=-1", &d), -EINVAL);
	ck_assert_int_eq(ssc_source_sim_open(&s1, "bogus=1", &d), -EINVAL);
	ck_assert_int_eq(ssc_source_sim_open(&s1, "rate", &d), -EINVAL);
	ck_assert_ptr_nonnull(strstr(d.msg, "key=value"));
	ck_assert_int_eq(ssc_source_sim_open(&s1, "channels=2,temp=-10", &d), 0);
	ck_assert_uint_eq(s1->info.n_channels, 2);
	ck_assert_int_eq(s1->ops->next(s1, &a, &d), 0);
	ck_assert(a.temp_degc == -10);
	ssc_source_close(s1);
}
END_TEST

/* ------------------------------------------------------------ engine */

/* A scripted source: n samples at period T (time stamps k T + t0),
 * values v[c] = k + c / 10; extra gaps, refusals and an end by timeout
 * or by holding samples for flush. */
struct script {
	long n;          /* samples before the end */
	long k;          /* next sample */
	int64_t T;
	long skip_at;    /* sample index after a gap of skip_len */
	long skip_len;
	bool counter;    /* report the gap itself (like a device counter) */
	long eagain_at;  /* return -EAGAIN once before this sample */
	bool eagain_done;
	int end_rc;      /* -ETIMEDOUT or 0 (0: samples forever) */
	long hold;       /* samples held back at the end, for flush */
	long flushed;
	atomic_bool *wait; /* after n samples, wait until it is true, then
			      end with end_rc */
	long pause_at;     /* before this sample, wait until *resume */
	atomic_bool *resume;
};

static int script_next(struct ssc_source *src, struct ssc_acq_sample *s,
		       struct sscope_diag *diag)
{
	struct script *p = src->priv;
	long k;

	if (p->k == p->eagain_at && !p->eagain_done) {
		p->eagain_done = true;
		return -EAGAIN;
	}
	while (p->resume && p->k == p->pause_at && !atomic_load(p->resume)) {
		struct timespec ts = { 0, 1000000 };

		nanosleep(&ts, NULL);
	}
	if (p->wait && p->k >= p->n) {
		while (!atomic_load(p->wait)) {
			struct timespec ts = { 0, 1000000 };

			nanosleep(&ts, NULL);
		}
		snprintf(diag->msg, sizeof(diag->msg), "script: the end");
		return p->end_rc;
	}
	if (p->end_rc && p->k >= p->n - p->hold) {
		snprintf(diag->msg, sizeof(diag->msg), "script: the end");
		return p->end_rc;
	}
	k = p->k++;
	if (p->skip_at >= 0 && k >= p->skip_at)
		k += p->skip_len;
	s->t_ns = 1000000000 + k * p->T;
	for (size_t c = 0; c < src->info.n_channels; c++)
		s->v[c] = (double)k + (double)c / 10;
	s->temp_degc = 20 + (double)(k % 7);
	if (p->counter && k == p->skip_at + p->skip_len && p->skip_len) {
		s->missing = (uint32_t)p->skip_len;
		s->cause = SSC_GAP_COUNTER;
	}
	return 0;
}

static int script_flush(struct ssc_source *src, struct ssc_acq_sample *s)
{
	struct script *p = src->priv;
	long k;

	if (p->flushed >= p->hold)
		return -ENODATA;
	k = p->k++;
	p->flushed++;
	s->t_ns = 1000000000 + k * p->T;
	for (size_t c = 0; c < src->info.n_channels; c++)
		s->v[c] = (double)k + (double)c / 10;
	s->temp_degc = 20 + (double)(k % 7);
	return 0;
}

static void script_close(struct ssc_source *src)
{
	(void)src;
}

static const struct ssc_source_ops script_ops = { script_next, script_flush,
						  script_close };

static void script_source(struct ssc_source *src, struct script *p,
			  size_t nch, double rate, bool counter)
{
	memset(src, 0, sizeof(*src));
	src->ops = &script_ops;
	src->priv = p;
	src->stop_fd = -1;
	src->info.n_channels = nch;
	for (size_t c = 0; c < nch; c++) {
		snprintf(src->info.name[c], sizeof(src->info.name[c]), "c%zu", c);
		snprintf(src->info.unit[c], sizeof(src->info.unit[c]), "V");
	}
	src->info.has_temp = true;
	src->info.has_counter = counter;
	src->info.rate_hz = rate;
	snprintf(src->info.desc, sizeof(src->info.desc), "script");
	p->T = llround(1e9 / rate);
	p->counter = counter;
	if (!p->skip_len)
		p->skip_at = -1;
	if (!p->eagain_at)
		p->eagain_at = -1;
}

static void base_cfg(struct ssc_acq_config *cfg, struct ssc_source *src,
		     const char *path)
{
	memset(cfg, 0, sizeof(*cfg));
	cfg->src = src;
	cfg->path = path;
	cfg->timeout_s = 1;
	cfg->ring_capacity = 4096;
}

static struct sscope_capture *load(const char *path)
{
	struct sscope_capture *cap = NULL;
	struct sscope_diag d = { "" };

	ck_assert_msg(sscope_capture_load(&cap, path, NULL, &d) == 0, "%s",
		      d.msg);
	return cap;
}

static bool has_line(const char *path, const char *text)
{
	FILE *f = fopen(path, "r");
	char line[512];
	bool found = false;

	while (f && !found && fgets(line, sizeof(line), f))
		found = strstr(line, text) != NULL;
	if (f)
		fclose(f);
	return found;
}

START_TEST(engine_count_exact)
{
	struct script p = { .n = 0, .eagain_at = 5 };
	struct ssc_source src;
	struct ssc_acq_config cfg;
	struct ssc_acq_result r;
	struct sscope_diag d = { "" };
	const char *comments[] = { "hello", NULL };
	struct sscope_capture *cap;

	script_source(&src, &p, 3, 1000, false);
	base_cfg(&cfg, &src, tmp("count.csv"));
	cfg.count = 1234;
	cfg.comments = comments;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), 0);
	ck_assert_int_eq(r.stop, SSC_STOP_COUNT);
	ck_assert_uint_eq(r.samples, 1234);
	ck_assert_uint_eq(r.missing, 0);
	ck_assert(r.committed);
	ck_assert_uint_eq(r.iv.n, 1233);
	ck_assert_rel(r.iv.mean_s, 1e-3, 1e-12);
	ck_assert(ssc_intervals_sd(&r.iv) < 1e-15);
	ck_assert_rel(r.effective_rate_hz, 1000, 1e-12);
	ck_assert_rel(r.duration_s, 1.233, 1e-12);
	ck_assert(has_line(cfg.path, "# hello"));
	ck_assert(has_line(cfg.path, "# end: 1234 samples, 0 missing in 0 gaps"));
	cap = load(cfg.path);
	ck_assert_uint_eq(cap->n, 1234);
	ck_assert_uint_eq(cap->n_channels, 3);
	for (size_t i = 0; i < cap->n; i++) {
		ck_assert(fabs(cap->time_s[i] - (double)i * 1e-3) < 1e-12);
		ck_assert(cap->channels[2].data[i] == (double)i + 0.2);
		ck_assert(cap->temp_degc[i] == 20 + (double)(i % 7));
	}
	sscope_capture_free(cap);
}
END_TEST

START_TEST(engine_gaps_marked)
{
	struct script p = { .skip_at = 100, .skip_len = 3 };
	struct ssc_source src;
	struct ssc_acq_config cfg;
	struct ssc_acq_result r;
	struct sscope_capture *cap;

	/* a counter source reports its own gap */
	script_source(&src, &p, 2, 500, true);
	base_cfg(&cfg, &src, tmp("gap.csv"));
	cfg.count = 300;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, NULL), 0);
	ck_assert_uint_eq(r.samples, 300);
	ck_assert_uint_eq(r.missing, 3);
	ck_assert_uint_eq(r.gaps, 1);
	ck_assert_uint_eq(r.events_gap, 0);
	ck_assert_uint_eq(r.iv.n, 298);
	ck_assert(has_line(cfg.path,
			   "# gap: 3 samples missing before the next row (device counter)"));
	cap = load(cfg.path);
	ck_assert(cap->channels[0].data[99] == 99 && cap->channels[0].data[100] == 103);
	ck_assert(fabs(cap->time_s[100] - 103 * 2e-3) < 1e-12);
	sscope_capture_free(cap);

	/* without a counter, the time stamps and the rate find it */
	memset(&p, 0, sizeof(p));
	p.skip_at = 50;
	p.skip_len = 2;
	script_source(&src, &p, 1, 500, false);
	base_cfg(&cfg, &src, tmp("gap2.csv"));
	cfg.count = 100;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, NULL), 0);
	ck_assert_uint_eq(r.missing, 2);
	ck_assert_uint_eq(r.events_gap, 2);
	ck_assert(has_line(cfg.path,
			   "# gap: 2 samples missing before the next row (data-ready events)"));
}
END_TEST

START_TEST(engine_duration_binary)
{
	struct script p = { 0 };
	struct ssc_source src;
	struct ssc_acq_config cfg;
	struct ssc_acq_result r;
	struct sscope_capture *cap;

	script_source(&src, &p, 4, 2000, false);
	base_cfg(&cfg, &src, tmp("dur.bin"));
	cfg.format = SSCOPE_CAPTURE_BIN64;
	cfg.duration_s = 0.25; /* [0, 0.25): 500 samples */
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, NULL), 0);
	ck_assert_int_eq(r.stop, SSC_STOP_DURATION);
	ck_assert_uint_eq(r.samples, 500);
	cap = load(cfg.path);
	ck_assert_uint_eq(cap->n, 500);
	for (size_t i = 0; i < cap->n; i++)
		ck_assert(cap->channels[3].data[i] == (double)i + 0.3);
	sscope_capture_free(cap);
}
END_TEST

START_TEST(engine_ring_overrun)
{
	struct script p = { 0 };
	struct ssc_source src;
	struct ssc_acq_config cfg;
	struct ssc_acq_result r;
	struct sscope_capture *cap;
	const long N = 5000;
	uint64_t sum = 0;
	long last;
	FILE *f;
	char line[256];

	/* an unpaced source, a 16-sample ring and a writer that sleeps
	 * 2 ms per batch: the ring overflows */
	script_source(&src, &p, 1, 10000, false);
	base_cfg(&cfg, &src, tmp("ring.csv"));
	cfg.ring_capacity = 16;
	cfg.writer_delay_us = 2000;
	cfg.duration_s = (double)N / 10000;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, NULL), 0);
	ck_assert(r.drops_ring > 0);
	/* every sample is either written or counted as a ring drop */
	ck_assert_uint_eq(r.samples + r.drops_ring, (uint64_t)N);
	/* the gap comments add up to the marked losses */
	f = fopen(cfg.path, "r");
	while (fgets(line, sizeof(line), f)) {
		unsigned m;

		if (sscanf(line, "# gap: %u sample", &m) == 1) {
			sum += m;
			ck_assert(strstr(line, "ring overrun") != NULL);
		}
	}
	fclose(f);
	ck_assert_uint_eq(sum, r.missing);
	/* drops after the last written row are counted, not marked */
	cap = load(cfg.path);
	last = lround(cap->channels[0].data[cap->n - 1]);
	ck_assert_uint_eq(r.missing + (uint64_t)(N - 1 - last), r.drops_ring);
	/* rows are the samples, never anything made up */
	for (size_t i = 0; i < cap->n; i++)
		ck_assert(fabs(cap->time_s[i] - cap->channels[0].data[i] * 1e-4) < 1e-12);
	sscope_capture_free(cap);
}
END_TEST

START_TEST(engine_timeout_keeps_data)
{
	struct script p = { .n = 40, .end_rc = -ETIMEDOUT, .hold = 3 };
	struct ssc_source src;
	struct ssc_acq_config cfg;
	struct ssc_acq_result r;
	struct sscope_diag d = { "" };
	struct sscope_capture *cap;

	script_source(&src, &p, 1, 100, false);
	base_cfg(&cfg, &src, tmp("to.csv"));
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), -ETIMEDOUT);
	ck_assert_int_eq(r.stop, SSC_STOP_TIMEOUT);
	ck_assert_str_eq(d.msg, "script: the end");
	/* the 37 read plus the 3 the source still held */
	ck_assert_uint_eq(r.samples, 40);
	ck_assert(r.committed);
	cap = load(cfg.path);
	ck_assert_uint_eq(cap->n, 40);
	sscope_capture_free(cap);

	/* nothing read: no file */
	memset(&p, 0, sizeof(p));
	p.n = 0;
	p.end_rc = -ETIMEDOUT;
	script_source(&src, &p, 1, 100, false);
	base_cfg(&cfg, &src, tmp("none.csv"));
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), -ETIMEDOUT);
	ck_assert(!r.committed);
	ck_assert_int_ne(access(cfg.path, F_OK), 0);
}
END_TEST

START_TEST(engine_refusals)
{
	struct script p = { 0 };
	struct ssc_source src;
	struct ssc_acq_config cfg;
	struct ssc_acq_result r;
	struct sscope_diag d = { "" };

	script_source(&src, &p, 1, 100, false);
	base_cfg(&cfg, &src, "/nonexistent-dir/x.csv");
	cfg.count = 10;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), -ENOENT);
	ck_assert_ptr_nonnull(strstr(d.msg, "/nonexistent-dir/x.csv"));
	base_cfg(&cfg, &src, tmp("x.csv"));
	cfg.timeout_s = 0;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), -EINVAL);
	base_cfg(&cfg, &src, tmp("x.csv"));
	cfg.ring_capacity = 1;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), -EINVAL);
	ck_assert_int_ne(access(tmp("x.csv"), F_OK), 0);
}
END_TEST

/* data rows of a CSV file; *complete: it ends with a newline */
static long csv_rows(const char *path, bool *complete)
{
	FILE *f = fopen(path, "r");
	long rows = 0;
	int c, prev = '\n', first = 0;

	if (!f)
		return -1;
	while ((c = fgetc(f)) != EOF) {
		if (prev == '\n')
			first = c;
		if (c == '\n' && first != '#' && first != 't')
			rows++;
		prev = c;
	}
	fclose(f);
	if (complete)
		*complete = prev == '\n';
	return rows;
}

static bool exists(const char *path)
{
	return access(path, F_OK) == 0;
}

START_TEST(engine_disk_full)
{
	const char *path = tmp("full.csv");
	char partial[300];
	int with_end = 0, without_end = 0;

	snprintf(partial, sizeof(partial), "%s.partial", path);
	/* the disk fills at 40 places within a few rows of each other: the
	 * file always ends at a complete row, holds exactly the samples
	 * reported, and gets its end line when the cut left room for it */
	for (uint64_t limit = 5000; limit < 5000 + 40 * 29; limit += 29) {
		struct script p = { 0 };
		struct ssc_source src;
		struct ssc_acq_config cfg;
		struct ssc_acq_result r;
		struct sscope_diag d = { "" };
		struct sscope_capture *cap;
		struct stat st;
		bool complete;
		long rows;

		unlink(path);
		script_source(&src, &p, 3, 1000, false);
		base_cfg(&cfg, &src, path);
		cfg.count = 1000;
		cfg.disk_bytes = limit;
		ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), -ENOSPC);
		ck_assert_int_eq(r.stop, SSC_STOP_FULL);
		ck_assert_int_eq(r.error, -ENOSPC);
		ck_assert(r.committed);
		ck_assert_str_eq(r.file, path);
		ck_assert(!exists(partial));
		ck_assert_ptr_nonnull(strstr(d.msg, "no space left on device"));
		ck_assert_int_eq(stat(path, &st), 0);
		ck_assert((uint64_t)st.st_size <= limit);
		rows = csv_rows(path, &complete);
		ck_assert(complete);
		ck_assert_int_eq(rows, (long)r.samples);
		ck_assert(r.samples > 10 && r.samples < 1000);
		ck_assert(r.unsaved > 0 && r.samples + r.unsaved <= 1000);
		ck_assert_rel(r.duration_s, (double)(r.samples - 1) * 1e-3,
			      1e-12);
		if (has_line(path, "# end: ")) {
			char want[80];

			snprintf(want, sizeof(want),
				 "# end: %llu samples; stopped: disk full",
				 (unsigned long long)r.samples);
			ck_assert(has_line(path, want));
			ck_assert(!r.trailer_lost);
			with_end++;
		} else {
			ck_assert(r.trailer_lost);
			without_end++;
		}
		/* the rows are the first samples, whole */
		cap = load(path);
		ck_assert_uint_eq(cap->n, r.samples);
		for (size_t i = 0; i < cap->n; i++)
			ck_assert(cap->channels[2].data[i] == (double)i + 0.2);
		sscope_capture_free(cap);
	}
	ck_assert(with_end > 0 && without_end > 0);

	/* binary: whole rows of 5 float64 after the header */
	{
		struct script p = { 0 };
		struct ssc_source src;
		struct ssc_acq_config cfg;
		struct ssc_acq_result r;
		struct stat st;
		struct sscope_capture *cap;
		const char *bin = tmp("full.bin");

		script_source(&src, &p, 3, 1000, false);
		base_cfg(&cfg, &src, bin);
		cfg.format = SSCOPE_CAPTURE_BIN64;
		cfg.count = 1000;
		cfg.disk_bytes = 20003;
		ck_assert_int_eq(ssc_acq_run(&cfg, &r, NULL), -ENOSPC);
		ck_assert(r.committed);
		ck_assert_int_eq(stat(bin, &st), 0);
		cap = load(bin);
		ck_assert_uint_eq(cap->n, r.samples);
		ck_assert(20003 - st.st_size < 5 * 8);
		ck_assert(cap->channels[0].data[cap->n - 1] == (double)cap->n - 1);
		sscope_capture_free(cap);
	}
	/* full before the first row: nothing recorded, no file */
	{
		struct script p = { 0 };
		struct ssc_source src;
		struct ssc_acq_config cfg;
		struct ssc_acq_result r;

		unlink(path);
		script_source(&src, &p, 3, 1000, false);
		base_cfg(&cfg, &src, path);
		cfg.count = 1000;
		cfg.disk_bytes = 20; /* inside the header */
		ck_assert_int_eq(ssc_acq_run(&cfg, &r, NULL), -ENOSPC);
		ck_assert(!r.committed);
		ck_assert(!exists(path) && !exists(partial));
	}
}
END_TEST

struct run_ctx {
	const struct ssc_acq_config *cfg;
	struct ssc_acq_result r;
	struct sscope_diag d;
	int rc;
};

static void *run_thread(void *arg)
{
	struct run_ctx *c = arg;

	c->rc = ssc_acq_run(c->cfg, &c->r, &c->d);
	return NULL;
}

static double now_s(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* wait until the CSV file has `want` data rows, ending in a newline
 * (as long as it takes, up to 60 s: a timing bound alone would fail on
 * a busy machine); the seconds it took */
static double wait_rows(const char *path, long want)
{
	double t0 = now_s();
	bool complete = false;

	while (!(csv_rows(path, &complete) == want && complete) &&
	       now_s() - t0 < 60) {
		struct timespec ts = { 0, 5000000 };

		nanosleep(&ts, NULL);
	}
	ck_assert_int_eq(csv_rows(path, &complete), want);
	ck_assert(complete);
	return now_s() - t0;
}

START_TEST(engine_rows_reach_the_file)
{
	atomic_bool go, resume;
	struct script p = { .n = 300, .end_rc = -ETIMEDOUT, .wait = &go,
			    .pause_at = 100, .resume = &resume };
	struct ssc_source src;
	struct ssc_acq_config cfg;
	struct run_ctx c = { .cfg = &cfg };
	const char *path = tmp("live.csv");
	char partial[300];
	pthread_t t;
	double waited;

	/* 100 samples, a pause, 200 more, then the source waits: the rows
	 * of both bursts reach NAME.partial while the run goes on */
	atomic_init(&go, false);
	atomic_init(&resume, false);
	snprintf(partial, sizeof(partial), "%s.partial", path);
	script_source(&src, &p, 2, 1000, false);
	base_cfg(&cfg, &src, path);
	ck_assert_int_eq(pthread_create(&t, NULL, run_thread, &c), 0);
	wait_rows(partial, 100);
	atomic_store(&resume, true);
	waited = wait_rows(partial, 300);
	ck_assert(!exists(path));
	/* the reader takes NAME.partial as it is */
	{
		struct sscope_capture *cap = load(partial);

		ck_assert_uint_eq(cap->n, 300);
		sscope_capture_free(cap);
	}
	printf("# the second burst in the file %.3f s after it (flush period %.1f s)\n",
	       waited, SSC_REC_FLUSH_S);
	atomic_store(&go, true);
	pthread_join(t, NULL);
	ck_assert_int_eq(c.rc, -ETIMEDOUT);
	ck_assert(c.r.committed);
	ck_assert(exists(path) && !exists(partial));
	ck_assert(has_line(path, "# end: 300 samples"));
}
END_TEST

static void write_text(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");

	ck_assert_ptr_nonnull(f);
	fputs(text, f);
	fclose(f);
}

static bool same_text(const char *path, const char *text)
{
	char buf[256] = "";
	FILE *f = fopen(path, "r");
	size_t n;

	if (!f)
		return false;
	n = fread(buf, 1, sizeof(buf) - 1, f);
	buf[n] = '\0';
	fclose(f);
	return !strcmp(buf, text);
}

START_TEST(engine_existing_files)
{
	struct script p = { 0 };
	struct ssc_source src;
	struct ssc_acq_config cfg;
	struct ssc_acq_result r;
	struct sscope_diag d = { "" };
	const char *path = tmp("old.csv");
	char partial[300];

	snprintf(partial, sizeof(partial), "%s.partial", path);
	/* an existing file is refused, untouched, nothing left */
	write_text(path, "old data\n");
	script_source(&src, &p, 1, 100, false);
	base_cfg(&cfg, &src, path);
	cfg.count = 10;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), -EEXIST);
	ck_assert_ptr_nonnull(strstr(d.msg, "--overwrite"));
	ck_assert(same_text(path, "old data\n"));
	ck_assert(!exists(partial));
	/* an interrupted recording is refused even with overwrite */
	write_text(partial, "t,x\n0,1\n");
	memset(&p, 0, sizeof(p));
	script_source(&src, &p, 1, 100, false);
	base_cfg(&cfg, &src, path);
	cfg.count = 10;
	cfg.overwrite = true;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), -EEXIST);
	ck_assert_ptr_nonnull(strstr(d.msg, ".partial exists"));
	ck_assert(same_text(partial, "t,x\n0,1\n"));
	ck_assert(same_text(path, "old data\n"));
	unlink(partial);
	/* overwrite: replaced at the end */
	memset(&p, 0, sizeof(p));
	script_source(&src, &p, 1, 100, false);
	base_cfg(&cfg, &src, path);
	cfg.count = 10;
	cfg.overwrite = true;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, &d), 0);
	ck_assert(r.committed);
	ck_assert(has_line(path, "# end: 10 samples"));
	ck_assert(!exists(partial));
}
END_TEST

START_TEST(engine_name_taken_meanwhile)
{
	atomic_bool go;
	struct script p = { .n = 50, .end_rc = -ETIMEDOUT, .wait = &go };
	struct ssc_source src;
	struct ssc_acq_config cfg;
	struct run_ctx c = { .cfg = &cfg };
	const char *path = tmp("meanwhile.csv");
	char partial[300];
	pthread_t t;
	double t0;

	/* NAME appears during the run: it is not replaced, the recording
	 * stays NAME.partial and the run says so */
	atomic_init(&go, false);
	snprintf(partial, sizeof(partial), "%s.partial", path);
	script_source(&src, &p, 1, 100, false);
	base_cfg(&cfg, &src, path);
	ck_assert_int_eq(pthread_create(&t, NULL, run_thread, &c), 0);
	t0 = now_s();
	while (!exists(partial) && now_s() - t0 < 100) {
		struct timespec ts = { 0, 2000000 };

		nanosleep(&ts, NULL);
	}
	write_text(path, "someone else's\n");
	atomic_store(&go, true);
	pthread_join(t, NULL);
	ck_assert_int_eq(c.rc, -ETIMEDOUT); /* the run's own end */
	ck_assert_int_eq(c.r.rename_err, -EEXIST);
	ck_assert(c.r.committed);
	ck_assert_str_eq(c.r.file, partial);
	ck_assert(same_text(path, "someone else's\n"));
	ck_assert_int_eq(csv_rows(partial, NULL), 50);
}
END_TEST

START_TEST(engine_source_that_waits)
{
	struct script p = { 0 };
	struct ssc_source src, *sim;
	struct ssc_acq_config cfg;
	struct ssc_acq_result r;
	struct sscope_capture *cap;
	const long N = 3000;

	/* the overrun set-up of engine_ring_overrun (16-sample ring, slow
	 * writer), with a source that can wait: nothing is lost */
	script_source(&src, &p, 1, 10000, false);
	src.info.can_wait = true;
	base_cfg(&cfg, &src, tmp("wait.csv"));
	cfg.ring_capacity = 16;
	cfg.writer_delay_us = 2000;
	cfg.count = (uint64_t)N;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, NULL), 0);
	ck_assert_uint_eq(r.drops_ring, 0);
	ck_assert_uint_eq(r.missing, 0);
	ck_assert_uint_eq(r.samples, (uint64_t)N);
	cap = load(cfg.path);
	ck_assert_uint_eq(cap->n, (size_t)N);
	for (size_t i = 0; i < cap->n; i++)
		ck_assert(cap->channels[0].data[i] == (double)i);
	sscope_capture_free(cap);

	/* the unpaced simulator is such a source, the paced one is not */
	ck_assert_int_eq(ssc_source_sim_open(&sim, "speed=max", NULL), 0);
	ck_assert(sim->info.can_wait);
	base_cfg(&cfg, sim, tmp("simwait.csv"));
	cfg.ring_capacity = 16;
	cfg.writer_delay_us = 500;
	cfg.count = 5000;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, NULL), 0);
	ck_assert_uint_eq(r.drops_ring, 0);
	ck_assert_uint_eq(r.samples, 5000);
	ssc_source_close(sim);
	ck_assert_int_eq(ssc_source_sim_open(&sim, "speed=2", NULL), 0);
	ck_assert(!sim->info.can_wait);
	ssc_source_close(sim);
}
END_TEST

struct live_seen {
	int calls;
	uint64_t samples;
	double adev0;
};

static void live_cb(const struct ssc_acq_live *l, void *ctx)
{
	struct live_seen *s = ctx;

	s->calls++;
	s->samples = l->samples;
	s->adev0 = l->adev[0][0];
}

START_TEST(engine_live_only)
{
	struct ssc_source *src;
	struct ssc_acq_config cfg;
	struct ssc_acq_result r;
	struct live_seen seen = { 0 };

	/* the simulator, paced 20 times faster than real time, no file */
	ck_assert_int_eq(ssc_source_sim_open(&src, "rate=1000,speed=20", NULL), 0);
	base_cfg(&cfg, src, NULL);
	cfg.count = 4000;
	cfg.live = live_cb;
	cfg.live_ctx = &seen;
	cfg.live_period_s = 0.05;
	ck_assert_int_eq(ssc_acq_run(&cfg, &r, NULL), 0);
	ck_assert_uint_eq(r.samples, 4000);
	ck_assert(!r.committed);
	ck_assert(seen.calls >= 1);
	ck_assert_uint_eq(seen.samples, 4000);
	/* gyro white noise at m = 1: ADEV = per-sample sd = N sqrt(fs) */
	ck_assert_rel(seen.adev0, 0.34 * M_PI / 180 / 60 * sqrt(1000.0),
		      4 / sqrt(2 * 3999.0));
	ck_assert(r.src.late_n == 4000);
	ssc_source_close(src);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("acq");
	TCase *t = tcase_create("core");

	tcase_set_timeout(t, 300);
	tcase_add_test(t, ring_sequential);
	tcase_add_test(t, ring_concurrent);
	tcase_add_test(t, intervals);
	tcase_add_test(t, gaps_from_time);
	tcase_add_test(t, gaps_from_counter);
	tcase_add_test(t, run_adev_closed_forms);
	tcase_add_test(t, sim_source);
	tcase_add_test(t, engine_count_exact);
	tcase_add_test(t, engine_gaps_marked);
	tcase_add_test(t, engine_duration_binary);
	tcase_add_test(t, engine_ring_overrun);
	tcase_add_test(t, engine_timeout_keeps_data);
	tcase_add_test(t, engine_refusals);
	tcase_add_test(t, engine_live_only);
	tcase_add_test(t, engine_disk_full);
	tcase_add_test(t, engine_rows_reach_the_file);
	tcase_add_test(t, engine_existing_files);
	tcase_add_test(t, engine_name_taken_meanwhile);
	tcase_add_test(t, engine_source_that_waits);
	suite_add_tcase(s, t);
	return s;
}
