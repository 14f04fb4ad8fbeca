/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The acquisition engine: a reader thread that takes samples from a
 * source as they become ready (optionally at SCHED_FIFO priority), a
 * lock-free single-producer single-consumer ring (ring.c), and a writer
 * thread that streams rows to the capture file and keeps the live
 * statistics.  The calling thread waits for SIGINT/SIGTERM/SIGHUP with
 * sigtimedwait (the three signals blocked in every thread of the run), feeds
 * the live view and decides the end.
 *
 * Gaps: a source reports how many samples it knows were lost before each
 * sample (device counter, data-ready sequence numbers); without a counter
 * the reader also infers losses from the time stamps and the nominal
 * period; when the ring is full the reader drops the sample and adds it
 * to the next one's count.  The writer writes every gap as a comment line
 * (CSV) just before the first row after it, and the time column keeps the
 * real time stamps, so a gap is never filled or interpolated.
 *
 * A source that loses nothing by waiting (the unpaced simulator) is held
 * back instead: when the ring is full the reader sleeps until the writer
 * has made room, so no sample is dropped.
 *
 * The file (recfile.c) gets the rows the writer formats at least every
 * SSC_REC_FLUSH_S, and the calling thread syncs it every SSC_REC_SYNC_S,
 * so a kill or a power cut leaves all but the last moments in the file.
 */
#include "acq.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/eventfd.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#define BATCH 512
#define FLUSH_ROWS (8 * BATCH) /* rows formatted before a write at most */
#define THREAD_STACK (256 * 1024)

struct engine {
	const struct ssc_acq_config *cfg;
	struct ssc_source *src;
	struct ssc_ring ring;
	struct ssc_recfile *rf;
	atomic_bool stop;
	atomic_bool reader_done;
	atomic_bool writer_dead; /* the writer stopped taking samples */
	atomic_bool until_hit;   /* cfg->until asked for the stop */
	int stop_fd;
	/* reader results (read after join) */
	enum ssc_acq_stop stop_reason;
	int reader_err;
	struct sscope_diag rdiag;
	uint64_t pushed, drops_ring, events_gap;
	struct ssc_intervals iv;
	int64_t t_first, t_last;
	double reader_cpu;
	int rt_errno;
	/* writer results */
	int writer_err;
	uint64_t written, missing, gaps;
	/* time stamps of the rows not yet in the file, to know the last
	 * one the file holds after a failed write */
	int64_t *t_rows;
	size_t n_trows;
	uint64_t rows_flushed;
	int64_t t_file_last;
	double writer_cpu;
	/* live view */
	pthread_mutex_t live_mu;
	struct ssc_acq_live live;
};

static double thread_cpu_s(void)
{
	struct timespec ts;

	if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts))
		return (double)NAN;
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void request_stop(struct engine *e)
{
	uint64_t one = 1;

	atomic_store(&e->stop, true);
	if (write(e->stop_fd, &one, sizeof(one)) < 0) {
		/* the flag alone stops the reader at its next sample */
	}
}

struct reader_state {
	double period;       /* nominal, 0 unknown */
	int64_t dur_ns;      /* 0: no duration limit */
	uint64_t pending;    /* samples dropped by ring overruns, not yet
				marked on a row */
	uint16_t pending_cause;
	bool have_prev;
	int64_t t_prev;
};

/* A source that can wait: sleep until the writer makes room in the ring
 * (true), or gives up (false). */
static bool wait_for_room(struct engine *e, const struct ssc_acq_sample *s)
{
	if (!e->src->info.can_wait)
		return false;
	while (!atomic_load(&e->writer_dead)) {
		struct timespec ts = { 0, 200000 };

		nanosleep(&ts, NULL);
		if (ssc_ring_push(&e->ring, s))
			return true;
	}
	return false;
}

/* Gap logic, limits and the hand-over to the ring for one sample.
 * Returns true when the run must stop (count or duration reached). */
static bool accept(struct engine *e, struct reader_state *st,
		   struct ssc_acq_sample *s)
{
	const struct ssc_acq_config *cfg = e->cfg;

	if (!st->have_prev)
		e->t_first = s->t_ns;
	if (st->dur_ns && s->t_ns - e->t_first >= st->dur_ns) {
		e->stop_reason = SSC_STOP_DURATION;
		return true;
	}
	if (st->have_prev) {
		double dt = 1e-9 * (double)(s->t_ns - st->t_prev);

		if (!e->src->info.has_counter && st->period > 0) {
			uint64_t k = ssc_gap_from_time(dt, st->period);

			if (k > s->missing) {
				e->events_gap += k - s->missing;
				s->missing = k > UINT32_MAX ? UINT32_MAX
							    : (uint32_t)k;
				s->cause |= SSC_GAP_EVENTS;
			}
		}
		if (s->missing == 0)
			ssc_intervals_add(&e->iv, dt);
	} else {
		/* samples lost before the first one do not exist in the
		 * capture: it starts here */
		s->missing = 0;
		s->cause = 0;
	}
	st->t_prev = s->t_ns;
	st->have_prev = true;
	if (st->pending) {
		uint64_t m = s->missing + st->pending;

		s->missing = m > UINT32_MAX ? UINT32_MAX : (uint32_t)m;
		s->cause |= st->pending_cause;
	}
	if (!ssc_ring_push(&e->ring, s) && !wait_for_room(e, s)) {
		if (atomic_load(&e->writer_dead))
			return true; /* nothing more can be saved */
		e->drops_ring++;
		st->pending = (uint64_t)s->missing + 1;
		st->pending_cause = (uint16_t)(s->cause | SSC_GAP_RING);
		return false;
	}
	st->pending = 0;
	st->pending_cause = 0;
	e->t_last = s->t_ns;
	e->pushed++;
	if (cfg->count && e->pushed >= cfg->count) {
		e->stop_reason = SSC_STOP_COUNT;
		return true;
	}
	return false;
}

static void *reader_main(void *arg)
{
	struct engine *e = arg;
	struct ssc_source *src = e->src;
	const struct ssc_acq_config *cfg = e->cfg;
	struct reader_state st = {
		.period = src->info.rate_hz > 0 ? 1.0 / src->info.rate_hz : 0,
		.dur_ns = cfg->duration_s > 0 ? llround(cfg->duration_s * 1e9)
					      : 0,
	};
	struct ssc_acq_sample s;
	bool limit = false;

	/* sleep to the microsecond, not the default 50 us slack */
	prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
	if (cfg->rt_priority > 0) {
		struct sched_param sp = { .sched_priority = cfg->rt_priority };

		e->rt_errno = pthread_setschedparam(pthread_self(), SCHED_FIFO,
						    &sp);
	}
	while (!limit) {
		int rc;

		if (atomic_load(&e->stop)) {
			e->stop_reason = SSC_STOP_SIGNAL;
			break;
		}
		memset(&s, 0, sizeof(s));
		s.temp_degc = (double)NAN;
		rc = src->ops->next(src, &s, &e->rdiag);
		if (rc == -EAGAIN)
			continue;
		if (rc == -ECANCELED) {
			e->stop_reason = SSC_STOP_SIGNAL;
			break;
		}
		if (rc < 0) {
			e->stop_reason = rc == -ETIMEDOUT ? SSC_STOP_TIMEOUT
							  : SSC_STOP_ERROR;
			e->reader_err = rc;
			break;
		}
		limit = accept(e, &st, &s);
	}
	/* samples the source read but still holds belong to the capture */
	while (!limit && src->ops->flush && !atomic_load(&e->writer_dead)) {
		memset(&s, 0, sizeof(s));
		s.temp_degc = (double)NAN;
		if (src->ops->flush(src, &s))
			break;
		limit = accept(e, &st, &s);
	}
	e->reader_cpu = thread_cpu_s();
	atomic_store_explicit(&e->reader_done, true, memory_order_release);
	return NULL;
}

static const char *cause_text(unsigned cause, char *buf, size_t len)
{
	static const char *const names[] = { "device counter",
					     "data-ready events",
					     "ring overrun",
					     "frames refused" };
	size_t used = 0;

	buf[0] = '\0';
	for (unsigned b = 0; b < 4; b++)
		if (cause & (1u << b)) {
			int n = snprintf(buf + used, len - used, "%s%s",
					 used ? ", " : "", names[b]);

			if (n < 0 || (size_t)n >= len - used)
				break;
			used += (size_t)n;
		}
	return buf;
}

static void publish_live(struct engine *e, const double *last,
			 const struct ssc_intervals *mean,
			 const struct ssc_run_adev *adev, double temp,
			 double elapsed, uint64_t samples)
{
	const struct ssc_source_info *info = &e->src->info;

	pthread_mutex_lock(&e->live_mu);
	e->live.info = info;
	e->live.elapsed_s = elapsed;
	e->live.samples = samples;
	e->live.missing = e->missing;
	e->live.checksum_errors = e->src->counts.checksum_errors;
	e->live.temp_degc = temp;
	for (size_t c = 0; c < info->n_channels; c++) {
		e->live.last[c] = last[c];
		e->live.mean[c] = mean[c].n ? mean[c].mean_s : (double)NAN;
		for (size_t k = 0; k < SSC_LIVE_TAUS; k++)
			e->live.adev[c][k] = ssc_run_adev_get(&adev[c], k);
	}
	for (size_t k = 0; k < SSC_LIVE_TAUS; k++)
		e->live.tau_s[k] = info->rate_hz > 0
					   ? (double)adev[0].m[k] / info->rate_hz
					   : (double)NAN;
	pthread_mutex_unlock(&e->live_mu);
}

/* After rows went to the file (or some of them, rc < 0): the time stamp
 * of the last one there. */
static void file_rows_done(struct engine *e)
{
	uint64_t in_file = ssc_recfile_rows(e->rf), k;

	k = in_file - e->rows_flushed;
	if (k > 0 && k <= e->n_trows)
		e->t_file_last = e->t_rows[k - 1];
	e->rows_flushed = in_file;
	e->n_trows = 0;
}

static int file_flush(struct engine *e)
{
	int rc = ssc_recfile_flush(e->rf);

	file_rows_done(e);
	return rc;
}

static void *writer_main(void *arg)
{
	struct engine *e = arg;
	const struct ssc_source_info *info = &e->src->info;
	size_t nc = info->n_channels, ncol = 1 + nc + (info->has_temp ? 1 : 0);
	struct ssc_acq_sample *batch = malloc(BATCH * sizeof(*batch));
	double *rows = malloc(BATCH * ncol * sizeof(double));
	double last[SSC_ACQ_MAX_CH] = { 0 }, temp = (double)NAN;
	struct ssc_intervals mean[SSC_ACQ_MAX_CH];
	struct ssc_run_adev adev[SSC_ACQ_MAX_CH];
	int64_t t0 = 0, next_pub = 0, flush_due = 0;
	const int64_t flush_ns = (int64_t)(SSC_REC_FLUSH_S * 1e9);
	bool have_t0 = false;
	double elapsed = 0;

	memset(mean, 0, sizeof(mean));
	for (size_t c = 0; c < nc; c++)
		ssc_run_adev_init(&adev[c]);
	if (!batch || !rows) {
		e->writer_err = -ENOMEM;
		atomic_store(&e->writer_dead, true);
		request_stop(e);
		goto out;
	}
	for (;;) {
		bool done = atomic_load_explicit(&e->reader_done,
						 memory_order_acquire);
		size_t n = ssc_ring_pop(&e->ring, batch, BATCH), nr = 0;
		int rc = 0;

		if (n == 0) {
			struct timespec ts = { 0, 1000000 };

			if (done)
				break;
			/* rows formatted reach the file even when no
			 * sample comes */
			if (e->rf && ssc_recfile_dirty(e->rf) &&
			    ssc_now_ns() >= flush_due) {
				rc = file_flush(e);
				flush_due = ssc_now_ns() + flush_ns;
				if (rc) {
					e->writer_err = rc;
					atomic_store(&e->writer_dead, true);
					request_stop(e);
					break;
				}
			}
			nanosleep(&ts, NULL);
			continue;
		}
		for (size_t i = 0; i < n && !rc; i++) {
			const struct ssc_acq_sample *s = &batch[i];
			double *row;

			if (!have_t0) {
				t0 = s->t_ns;
				have_t0 = true;
			}
			if (s->missing) {
				e->missing += s->missing;
				e->gaps++;
				for (size_t c = 0; c < nc; c++)
					ssc_run_adev_break(&adev[c]);
				if (e->rf && nr) {
					rc = ssc_recfile_append(e->rf, rows,
								nr);
					nr = 0;
				}
				if (e->rf && !rc) {
					char line[160], why[80];

					snprintf(line, sizeof(line),
						 "gap: %u sample%s missing before the next row (%s)",
						 (unsigned)s->missing,
						 s->missing == 1 ? "" : "s",
						 cause_text(s->cause, why,
							    sizeof(why)));
					rc = ssc_recfile_comment(e->rf, line);
				}
			}
			row = rows + nr * ncol;
			elapsed = 1e-9 * (double)(s->t_ns - t0);
			if (e->t_rows)
				e->t_rows[e->n_trows++] = s->t_ns;
			row[0] = elapsed;
			for (size_t c = 0; c < nc; c++) {
				row[1 + c] = s->v[c];
				last[c] = s->v[c];
				ssc_intervals_add(&mean[c], s->v[c]);
				ssc_run_adev_add(&adev[c], s->v[c]);
			}
			if (info->has_temp)
				row[1 + nc] = temp = s->temp_degc;
			nr++;
		}
		if (e->rf && nr && !rc)
			rc = ssc_recfile_append(e->rf, rows, nr);
		if (e->rf && !rc &&
		    (ssc_now_ns() >= flush_due ||
		     ssc_recfile_buffered(e->rf) >= FLUSH_ROWS)) {
			rc = file_flush(e);
			flush_due = ssc_now_ns() + flush_ns;
		}
		if (rc) {
			e->writer_err = rc;
			atomic_store(&e->writer_dead, true);
			request_stop(e);
			break;
		}
		e->written += n;
		if (e->cfg->until && !atomic_load(&e->until_hit) &&
		    e->cfg->until(batch, n, elapsed, e->cfg->until_ctx)) {
			atomic_store(&e->until_hit, true);
			request_stop(e);
		}
		if (e->cfg->live) {
			int64_t now = ssc_now_ns();

			if (now >= next_pub) {
				publish_live(e, last, mean, adev, temp, elapsed,
					     e->written);
				next_pub = now + 50000000;
			}
		}
		if (e->cfg->writer_delay_us) {
			struct timespec ts = {
				0, 1000L * (long)e->cfg->writer_delay_us
			};

			nanosleep(&ts, NULL);
		}
	}
	if (e->cfg->live && have_t0)
		publish_live(e, last, mean, adev, temp, elapsed, e->written);
out:
	free(batch);
	free(rows);
	e->writer_cpu = thread_cpu_s();
	return NULL;
}

static int open_writer(struct engine *e, struct sscope_diag *diag)
{
	const struct ssc_acq_config *cfg = e->cfg;
	const struct ssc_source_info *info = &e->src->info;
	struct sscope_writer_column cols[SSC_ACQ_MAX_CH + 2];
	size_t n = 0;
	int rc;

	cols[n++] = (struct sscope_writer_column){ "time", "s" };
	for (size_t c = 0; c < info->n_channels; c++)
		cols[n++] = (struct sscope_writer_column){ info->name[c],
							   info->unit[c] };
	if (info->has_temp)
		cols[n++] = (struct sscope_writer_column){ "temp", "degC" };
	{
		struct ssc_rec_opts ro = {
			.path = cfg->path, .overwrite = cfg->overwrite,
			.format = cfg->format, .cols = cols, .n_cols = n,
			.comments = cfg->comments,
			.fail_after_bytes = cfg->disk_bytes,
		};

		rc = ssc_recfile_open(&e->rf, &ro, diag);
	}
	return rc;
}

/* The end of the file: its end line, the rename, and what the result says
 * about it.  Returns rc, or the write or rename error. */
static int finish_file(struct engine *e, struct ssc_acq_result *res, int rc,
		       struct sscope_diag *diag)
{
	const struct ssc_acq_config *cfg = e->cfg;
	struct ssc_rec_end end;
	char line[400];
	int err;

	/* the end line (after a failed write, recfile.c writes a short
	 * one instead if it fits) */
	snprintf(line, sizeof(line),
		 "end: %llu samples, %llu missing in %llu gaps "
		 "(ring overruns %llu), checksum errors %llu",
		 (unsigned long long)e->written,
		 (unsigned long long)e->missing,
		 (unsigned long long)e->gaps,
		 (unsigned long long)e->drops_ring,
		 (unsigned long long)cfg->src->counts.checksum_errors);
	err = ssc_recfile_close(e->rf, line, &end);
	file_rows_done(e);
	if (e->writer_err)
		err = e->writer_err;
	ssc_recfile_free(e->rf);
	e->rf = NULL;
	res->samples = end.rows;
	res->duration_s = end.rows ? 1e-9 * (double)(e->t_file_last -
						      e->t_first)
				   : 0;
	res->unsaved = e->pushed > end.rows ? e->pushed - end.rows : 0;
	res->committed = end.kept;
	res->trailer_lost = end.trailer_lost;
	res->rename_err = end.rename_err;
	snprintf(res->file, sizeof(res->file), "%s", end.where);
	if (err) {
		res->error = err;
		res->stop = ssc_acq_storage_full(err) ? SSC_STOP_FULL : SSC_STOP_ERROR;
		return ssc_acq_diag(diag, err, "%s: %s", cfg->path &&
				    strcmp(cfg->path, "-") ? cfg->path
							   : "standard output",
				    sscope_strerror(-err));
	}
	if (end.rename_err && !rc) {
		if (end.rename_err == -EEXIST)
			return ssc_acq_diag(diag, end.rename_err,
					    "%s appeared during the recording and was not replaced: the samples are in %s",
					    cfg->path, end.where);
		return ssc_acq_diag(diag, end.rename_err,
				    "%s: %s: the samples are in %s", cfg->path,
				    sscope_strerror(-end.rename_err), end.where);
	}
	return rc;
}

static int start_thread(pthread_t *t, void *(*fn)(void *), void *arg)
{
	pthread_attr_t a;
	int rc;

	pthread_attr_init(&a);
	/* small stacks: with mlockall(MCL_FUTURE) every stack page is
	 * locked and counts against RLIMIT_MEMLOCK */
	pthread_attr_setstacksize(&a, THREAD_STACK);
	rc = pthread_create(t, &a, fn, arg);
	pthread_attr_destroy(&a);
	return -rc;
}

int ssc_acq_run(const struct ssc_acq_config *cfg, struct ssc_acq_result *res,
		struct sscope_diag *diag)
{
	struct engine *e;
	struct sigaction xfsz_ign = { .sa_handler = SIG_IGN }, xfsz_old;
	sigset_t set, old;
	pthread_t rt, wt;
	int64_t wall0, live_next, sync_next;
	int rc;

	memset(res, 0, sizeof(*res));
	if (!cfg->src || !(cfg->timeout_s > 0) ||
	    cfg->src->info.n_channels == 0 ||
	    cfg->src->info.n_channels > SSC_ACQ_MAX_CH)
		return ssc_acq_diag(diag, -EINVAL, "bad acquisition parameters");
	e = calloc(1, sizeof(*e));
	if (!e)
		return -ENOMEM;
	e->cfg = cfg;
	e->src = cfg->src;
	/* from here on SIGINT/SIGTERM/SIGHUP (a closed terminal or ssh
	 * session) only ask for a clean stop: blocked before any file
	 * exists, so none is left behind */
	sigemptyset(&set);
	sigaddset(&set, SIGINT);
	sigaddset(&set, SIGTERM);
	sigaddset(&set, SIGHUP);
	if (cfg->handle_signals) {
		pthread_sigmask(SIG_BLOCK, &set, &old);
		/* a file size limit (RLIMIT_FSIZE) fails the write with
		 * EFBIG, handled like a full disk, instead of killing the
		 * process with the recording unfinished */
		sigaction(SIGXFSZ, &xfsz_ign, &xfsz_old);
	}
	atomic_init(&e->stop, false);
	atomic_init(&e->reader_done, false);
	atomic_init(&e->writer_dead, false);
	pthread_mutex_init(&e->live_mu, NULL);
	rc = ssc_ring_init(&e->ring, cfg->ring_capacity);
	if (rc) {
		ssc_acq_diag(diag, rc, "ring of %zu samples: %s",
			     cfg->ring_capacity, sscope_strerror(rc));
		goto out_free;
	}
	/* make the ring resident before the first sample */
	memset(e->ring.buf, 0, ssc_ring_capacity(&e->ring) *
				       sizeof(*e->ring.buf));
	e->stop_fd = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
	if (e->stop_fd < 0) {
		rc = -errno;
		goto out_ring;
	}
	if (cfg->path) {
		/* a flush comes at most FLUSH_ROWS + BATCH rows late */
		e->t_rows = malloc((FLUSH_ROWS + BATCH) * sizeof(*e->t_rows));
		if (!e->t_rows) {
			rc = -ENOMEM;
			goto out_fd;
		}
		rc = open_writer(e, diag);
		if (rc)
			goto out_fd;
	}
	cfg->src->stop_fd = e->stop_fd;
	cfg->src->timeout_s = cfg->timeout_s;
	if (cfg->lock_memory && mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
		res->mlock_errno = errno;
	wall0 = ssc_now_ns();
	rc = start_thread(&wt, writer_main, e);
	if (rc)
		goto out_signals;
	rc = start_thread(&rt, reader_main, e);
	if (rc) {
		atomic_store(&e->reader_done, true);
		pthread_join(wt, NULL);
		goto out_signals;
	}
	live_next = wall0 + (int64_t)(cfg->live_period_s * 1e9);
	sync_next = wall0 + (int64_t)(SSC_REC_SYNC_S * 1e9);
	while (!atomic_load(&e->reader_done)) {
		struct timespec ts = { 0, 50000000 };

		if (cfg->handle_signals) {
			int sig = sigtimedwait(&set, NULL, &ts);

			if (sig > 0 && !atomic_load(&e->stop)) {
				res->signal = sig;
				request_stop(e);
			}
		} else {
			nanosleep(&ts, NULL);
		}
		if (cfg->live && cfg->live_period_s > 0 &&
		    ssc_now_ns() >= live_next) {
			struct ssc_acq_live snap;

			pthread_mutex_lock(&e->live_mu);
			snap = e->live;
			pthread_mutex_unlock(&e->live_mu);
			if (snap.info)
				cfg->live(&snap, cfg->live_ctx);
			live_next += (int64_t)(cfg->live_period_s * 1e9);
		}
		/* what the writer wrote survives a power cut */
		if (e->rf && ssc_now_ns() >= sync_next) {
			ssc_recfile_sync(e->rf);
			sync_next = ssc_now_ns() + (int64_t)(SSC_REC_SYNC_S * 1e9);
		}
	}
	pthread_join(rt, NULL);
	pthread_join(wt, NULL);
	if (cfg->live && e->live.info)
		cfg->live(&e->live, cfg->live_ctx);

	res->samples = e->written;
	res->drops_ring = e->drops_ring;
	res->missing = e->missing;
	res->gaps = e->gaps;
	res->events_gap = e->events_gap;
	res->src = cfg->src->counts;
	res->iv = e->iv;
	res->duration_s = e->pushed ? 1e-9 * (double)(e->t_last - e->t_first)
				    : 0;
	res->reader_cpu_s = e->reader_cpu;
	res->writer_cpu_s = e->writer_cpu;
	res->rt_errno = e->rt_errno;
	res->stop = e->stop_reason;
	if (res->stop == SSC_STOP_SIGNAL && atomic_load(&e->until_hit))
		res->stop = SSC_STOP_UNTIL;
	res->error = e->reader_err;
	rc = e->reader_err;
	if (rc && diag)
		*diag = e->rdiag;
	res->wall_s = 1e-9 * (double)(ssc_now_ns() - wall0);
	if (e->rf)
		rc = finish_file(e, res, rc, diag);
	res->effective_rate_hz = res->duration_s > 0 && res->samples >= 2
					 ? (double)(res->samples - 1) /
						   res->duration_s
					 : (double)NAN;
out_signals:
	cfg->src->stop_fd = -1;
	if (e->rf) { /* threads not started: nothing recorded */
		struct ssc_rec_end end;

		ssc_recfile_close(e->rf, NULL, &end);
		ssc_recfile_free(e->rf);
		e->rf = NULL;
	}
out_fd:
	close(e->stop_fd);
out_ring:
	ssc_ring_free(&e->ring);
out_free:
	if (cfg->handle_signals) {
		struct timespec zero = { 0, 0 };

		/* swallow signals that came during the drain, so that
		 * unblocking them does not kill the process now */
		while (sigtimedwait(&set, NULL, &zero) > 0)
			;
		pthread_sigmask(SIG_SETMASK, &old, NULL);
		sigaction(SIGXFSZ, &xfsz_old, NULL);
	}
	pthread_mutex_destroy(&e->live_mu);
	free(e->t_rows);
	free(e);
	return rc;
}
