/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * A parallel loop that does not wait for a helper that never ran.
 *
 * An OpenMP team ends at a barrier every thread must reach: on a machine
 * whose cores are taken by other work, a helper woken for a loop of a few
 * milliseconds may wait a scheduler slice for a core, and the caller,
 * its own share long done, waits with it.  `allan` on the 36,000-sample
 * gyro ran 45 such loops (the bootstrap of the noise fit) and took 19 %
 * longer on two threads than on one beside two CPU-bound processes.
 *
 * Here the items are claimed one at a time from a counter that carries
 * the loop's generation; the caller claims items too and returns when
 * every item is done.  A helper that wakes after that finds the counter
 * of a finished (or a later) loop and claims nothing.  The caller never
 * needs a helper: with none running it does every item itself.
 *
 * The helpers are started on first use and kept for the process.  One
 * loop runs at a time; a loop asked for while another runs (from another
 * thread, or from inside an item) runs on its caller alone.  Which thread
 * runs an item changes from run to run, so an item's result must not
 * depend on it: `slot` (0 for the caller, 1..threads-1 for helpers) only
 * picks per-thread scratch.
 */
#include "internal.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>

#define POOL_MAX 64

typedef void (*item_fn)(void *ctx, size_t i, unsigned slot);

static struct {
	pthread_mutex_t job;  /* held by the loop that runs */
	pthread_mutex_t mu;   /* the fields below, but the atomics */
	pthread_cond_t work;  /* a new loop */
	pthread_cond_t done_cv;
	unsigned started;     /* helpers running (slots 1..started) */
	uint32_t gen;         /* the current loop's generation */
	item_fn fn;
	void *ctx;
	size_t n;
	unsigned want;        /* helpers wanted by the current loop */
	_Atomic uint64_t next; /* gen << 32 | the next item to claim */
	_Atomic size_t done;   /* items finished in the current loop */
} P = { .job = PTHREAD_MUTEX_INITIALIZER, .mu = PTHREAD_MUTEX_INITIALIZER,
	.work = PTHREAD_COND_INITIALIZER, .done_cv = PTHREAD_COND_INITIALIZER };

/* claim and run items of loop g until none is left */
static void run_items(uint32_t g, item_fn fn, void *ctx, size_t n,
		      unsigned slot)
{
	for (;;) {
		uint64_t cur = atomic_load_explicit(&P.next, memory_order_acquire);
		size_t i = (size_t)(cur & 0xFFFFFFFFu);

		if ((uint32_t)(cur >> 32) != g || i >= n)
			return;
		if (!atomic_compare_exchange_weak_explicit(
			    &P.next, &cur, cur + 1, memory_order_acq_rel,
			    memory_order_acquire))
			continue;
		fn(ctx, i, slot);
		if (atomic_fetch_add_explicit(&P.done, 1, memory_order_acq_rel) + 1 == n) {
			pthread_mutex_lock(&P.mu);
			pthread_cond_signal(&P.done_cv);
			pthread_mutex_unlock(&P.mu);
		}
	}
}

static void *helper(void *arg)
{
	const unsigned slot = (unsigned)(uintptr_t)arg;
	uint32_t seen;

	pthread_mutex_lock(&P.mu);
	/* started by a loop being set up: that loop is one to join */
	seen = P.gen - 1;
	for (;;) {
		uint32_t g;
		item_fn fn;
		void *ctx;
		size_t n;

		while (P.gen == seen)
			pthread_cond_wait(&P.work, &P.mu);
		seen = g = P.gen;
		if (slot > P.want)
			continue;
		fn = P.fn;
		ctx = P.ctx;
		n = P.n;
		pthread_mutex_unlock(&P.mu);
		run_items(g, fn, ctx, n, slot);
		pthread_mutex_lock(&P.mu);
	}
	return NULL;
}

/* A child of fork() has none of the helpers, and a lock a helper held
 * at the fork would stay held: the child starts with an empty pool (the
 * parent holds both locks across the fork, so their state is known). */
static void fork_prepare(void)
{
	pthread_mutex_lock(&P.job);
	pthread_mutex_lock(&P.mu);
}

static void fork_parent(void)
{
	pthread_mutex_unlock(&P.mu);
	pthread_mutex_unlock(&P.job);
}

static void fork_child(void)
{
	P.started = 0;
	pthread_mutex_init(&P.mu, NULL);
	pthread_mutex_init(&P.job, NULL);
	pthread_cond_init(&P.work, NULL);
	pthread_cond_init(&P.done_cv, NULL);
}

static pthread_once_t fork_once = PTHREAD_ONCE_INIT;

static void fork_register(void)
{
	pthread_atfork(fork_prepare, fork_parent, fork_child);
}

void ssc_par_for(size_t n, unsigned threads, item_fn fn, void *ctx)
{
	uint32_t g;

	if (threads > POOL_MAX)
		threads = POOL_MAX;
	if (threads <= 1 || n <= 1 || n >= ((uint64_t)1 << 32) ||
	    pthread_mutex_trylock(&P.job)) {
		for (size_t i = 0; i < n; i++)
			fn(ctx, i, 0);
		return;
	}
	pthread_once(&fork_once, fork_register);
	pthread_mutex_lock(&P.mu);
	while (P.started + 1 < threads) {
		pthread_attr_t at;
		pthread_t t;
		int rc;

		if (pthread_attr_init(&at))
			break;
		pthread_attr_setdetachstate(&at, PTHREAD_CREATE_DETACHED);
		rc = pthread_create(&t, &at, helper,
				    (void *)(uintptr_t)(P.started + 1));
		pthread_attr_destroy(&at);
		if (rc)
			break; /* fewer helpers: the caller does the rest */
		P.started++;
	}
	g = ++P.gen;
	P.fn = fn;
	P.ctx = ctx;
	P.n = n;
	P.want = threads - 1;
	atomic_store_explicit(&P.done, 0, memory_order_relaxed);
	atomic_store_explicit(&P.next, (uint64_t)g << 32, memory_order_release);
	pthread_cond_broadcast(&P.work);
	pthread_mutex_unlock(&P.mu);
	run_items(g, fn, ctx, n, 0);
	/* the items others claimed; a helper that claimed none is not
	 * waited for */
	if (atomic_load_explicit(&P.done, memory_order_acquire) != n) {
		pthread_mutex_lock(&P.mu);
		while (atomic_load_explicit(&P.done, memory_order_acquire) != n)
			pthread_cond_wait(&P.done_cv, &P.mu);
		pthread_mutex_unlock(&P.mu);
	}
	pthread_mutex_unlock(&P.job);
}
