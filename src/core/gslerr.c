/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * GSL's errors recorded instead of abort() (sscope-gsl.h), and the quiet
 * stretches where the library handles a GSL failure from its return code.
 *
 * GSL's error handler is one process-wide function pointer
 * (gsl_set_error_handler()), so this file holds the library's only
 * process-wide mutable state: whether the recorder is installed, and the
 * record of errors raised on threads that keep none of their own (the
 * library's OpenMP and reader workers).  That record is a small lock-free
 * slot: EMPTY -> WRITING -> FULL by the first error (later ones are
 * dropped while it is full), FULL -> READING -> EMPTY by the one taker.
 * Everything else is thread-local (C11 _Thread_local).
 */
#include "internal.h"

#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "sscope-gsl.h"

struct gsl_rec {
	bool full;
	int code;
	int line;
	char file[80];
	char reason[200];
};

enum { SLOT_EMPTY, SLOT_WRITING, SLOT_FULL, SLOT_READING };

/* how long one side waits for the other's few stores (yields): bounded,
 * so that a child forked in the middle of one never hangs */
#define SLOT_WAITS 100000

static atomic_bool recording;
static atomic_int slot_state;
static struct gsl_rec slot;

static _Thread_local struct gsl_rec own;
static _Thread_local bool own_kept;
static _Thread_local unsigned quiet_depth;

static void fill(struct gsl_rec *r, const char *reason, const char *file,
		 int line, int code)
{
	snprintf(r->reason, sizeof(r->reason), "%s", reason ? reason : "?");
	snprintf(r->file, sizeof(r->file), "%s", file ? file : "?");
	r->line = line;
	r->code = code;
	r->full = true;
}

static void publish(const char *reason, const char *file, int line, int code)
{
	for (int i = 0; i < SLOT_WAITS; i++) {
		int s = SLOT_EMPTY;

		if (atomic_compare_exchange_strong(&slot_state, &s,
						   SLOT_WRITING)) {
			fill(&slot, reason, file, line, code);
			atomic_store(&slot_state, SLOT_FULL);
			return;
		}
		/* one is being written or waits: this later one is dropped;
		 * one being taken leaves the slot empty in a few stores */
		if (s != SLOT_READING)
			return;
		sched_yield();
	}
}

static void on_gsl_error(const char *reason, const char *file, int line,
			 int gsl_errno)
{
	if (quiet_depth)
		return;
	if (!own_kept)
		publish(reason, file, line, gsl_errno);
	else if (!own.full)
		fill(&own, reason, file, line, gsl_errno);
}

void sscope_gsl_errors_record(void)
{
	own_kept = true;
	gsl_set_error_handler(on_gsl_error);
	atomic_store(&recording, true);
}

bool sscope_gsl_error_pending(void)
{
	int s;

	own_kept = true;
	if (own.full)
		return true;
	s = atomic_load(&slot_state);
	return s == SLOT_WRITING || s == SLOT_FULL;
}

static bool take_slot(struct gsl_rec *r)
{
	for (int i = 0; i < SLOT_WAITS; i++) {
		int s = SLOT_FULL;

		if (atomic_compare_exchange_strong(&slot_state, &s,
						   SLOT_READING)) {
			*r = slot;
			atomic_store(&slot_state, SLOT_EMPTY);
			return true;
		}
		/* WRITING: an error is a few stores from FULL; wait for it,
		 * so that pending() and take() agree */
		if (s != SLOT_WRITING)
			return false;
		sched_yield();
	}
	return false;
}

int sscope_gsl_error_take(int *gsl_errno, char *buf, size_t len)
{
	struct gsl_rec r;
	bool got = false;

	own_kept = true;
	if (own.full) {
		r = own;
		own.full = false;
		got = true;
	} else {
		got = take_slot(&r);
	}
	if (gsl_errno)
		*gsl_errno = got ? r.code : 0;
	if (buf && len) {
		if (got)
			snprintf(buf, len, "%s:%d: %s", r.file, r.line,
				 r.reason);
		else
			buf[0] = '\0';
	}
	return got;
}

void ssc_gsl_quiet_begin(struct ssc_gsl_quiet *q)
{
	quiet_depth++;
	q->swapped = !atomic_load(&recording);
	if (q->swapped)
		q->old = gsl_set_error_handler_off();
}

void ssc_gsl_quiet_end(struct ssc_gsl_quiet *q)
{
	if (q->swapped)
		gsl_set_error_handler(q->old);
	quiet_depth--;
}
