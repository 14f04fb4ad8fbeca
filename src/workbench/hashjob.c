/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Provenance hashes of a report's inputs (SHA-256, nettle) computed on a
 * thread started before the captures are read: hashing a 750 MB capture
 * takes about half a second on one core, which would otherwise come after
 * everything else.  The thread runs under SCHED_IDLE, so that it takes
 * only a core nothing else of the report (the parsing threads, the
 * stages' OpenMP threads) wants: at normal priority it slowed the
 * parallel read of that capture by 0.3 s.  When the report needs a hash
 * that is not done, the waiting thread takes the work over at the end of
 * the thread's current 64 KiB and finishes it at its own priority: an
 * unprivileged thread cannot leave SCHED_IDLE, which on a machine kept
 * busy by other programs would leave it almost no time at all.
 */
#include "config.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <nettle/sha2.h>

#include "hashjob.h"
#include "html.h"

enum { CHUNK = 65536 };

struct ssc_hashjob {
	pthread_t tid;
	bool joined;
	char *const *paths;
	size_t n;
	char (*hex)[65];
	int *rc;
	/* the work, owned by whoever holds mu or has set taken */
	pthread_mutex_t mu;
	pthread_cond_t cv;
	bool taken; /* the waiting thread does the rest */
	bool busy;  /* the job's thread is inside a step */
	size_t file; /* the file being hashed (n: all done) */
	FILE *f;
	struct sha256_ctx ctx;
	uint8_t buf[CHUNK];
};

/* One step of the work: open the next file, hash a chunk of it, or finish
 * it.  The caller owns the state. */
static void step(struct ssc_hashjob *j)
{
	uint8_t digest[SHA256_DIGEST_SIZE];
	size_t got;

	if (!j->f) {
		j->f = fopen(j->paths[j->file], "rb");
		if (!j->f) {
			j->rc[j->file++] = -errno;
			return;
		}
		sha256_init(&j->ctx);
		return;
	}
	got = fread(j->buf, 1, sizeof(j->buf), j->f);
	if (got) {
		sha256_update(&j->ctx, got, j->buf);
		return;
	}
	if (ferror(j->f)) {
		j->rc[j->file] = -EIO;
	} else {
		sha256_digest(&j->ctx, sizeof(digest), digest);
		for (size_t i = 0; i < sizeof(digest); i++)
			snprintf(j->hex[j->file] + 2 * i, 3, "%02x", digest[i]);
		j->rc[j->file] = 0;
	}
	fclose(j->f);
	j->f = NULL;
	j->file++;
}

static void *work(void *arg)
{
	struct ssc_hashjob *j = arg;

#ifdef SCHED_IDLE
	{
		struct sched_param sp = { 0 };

		pthread_setschedparam(pthread_self(), SCHED_IDLE, &sp);
	}
#endif
	pthread_mutex_lock(&j->mu);
	while (!j->taken && j->file < j->n) {
		j->busy = true;
		pthread_mutex_unlock(&j->mu);
		step(j);
		pthread_mutex_lock(&j->mu);
		j->busy = false;
		pthread_cond_signal(&j->cv);
	}
	pthread_mutex_unlock(&j->mu);
	return NULL;
}

struct ssc_hashjob *ssc_hashjob_start(char *const *paths, size_t n)
{
	struct ssc_hashjob *j = calloc(1, sizeof(*j));

	if (!j)
		return NULL;
	j->paths = paths;
	j->n = n;
	j->hex = calloc(n ? n : 1, sizeof(*j->hex));
	j->rc = calloc(n ? n : 1, sizeof(*j->rc));
	if (!j->hex || !j->rc || pthread_mutex_init(&j->mu, NULL)) {
		free(j->hex);
		free(j->rc);
		free(j);
		return NULL;
	}
	if (pthread_cond_init(&j->cv, NULL) ||
	    pthread_create(&j->tid, NULL, work, j)) {
		/* no thread: ssc_hashjob_get() does the work */
		pthread_mutex_destroy(&j->mu);
		free(j->hex);
		free(j->rc);
		free(j);
		return NULL;
	}
	return j;
}

/* the rest of the work here, then the job's thread gone */
static void join(struct ssc_hashjob *j)
{
	if (j->joined)
		return;
	pthread_mutex_lock(&j->mu);
	j->taken = true;
	while (j->busy)
		pthread_cond_wait(&j->cv, &j->mu);
	pthread_mutex_unlock(&j->mu);
	while (j->file < j->n)
		step(j);
	pthread_join(j->tid, NULL);
	j->joined = true;
}

int ssc_hashjob_get(struct ssc_hashjob *j, char *const *paths, size_t i,
		    char hex[65])
{
	if (!j || i >= j->n)
		return ssc_sha256_file(paths[i], hex);
	join(j);
	memcpy(hex, j->hex[i], 65);
	return j->rc[i];
}

void ssc_hashjob_free(struct ssc_hashjob *j)
{
	if (!j)
		return;
	join(j);
	pthread_cond_destroy(&j->cv);
	pthread_mutex_destroy(&j->mu);
	free(j->hex);
	free(j->rc);
	free(j);
}
