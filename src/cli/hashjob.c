/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Provenance hashes of a report's inputs (SHA-256, html.c) computed on a
 * thread started before the captures are read: hashing a 750 MB capture
 * takes about half a second on one core, which would otherwise come after
 * everything else; beside the reading and the stages it uses the time the
 * other core has.
 */
#include "config.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "hashjob.h"
#include "html.h"

struct ssc_hashjob {
	pthread_t tid;
	char *const *paths;
	size_t n;
	char (*hex)[65];
	int *rc;
	bool joined;
};

static void *work(void *arg)
{
	struct ssc_hashjob *j = arg;

#ifdef SCHED_IDLE
	{
		/* only on a core nothing else wants: the reading and the
		 * stages come first (join() raises it again) */
		struct sched_param sp = { 0 };

		pthread_setschedparam(pthread_self(), SCHED_IDLE, &sp);
	}
#endif

	for (size_t i = 0; i < j->n; i++)
		j->rc[i] = ssc_sha256_file(j->paths[i], j->hex[i]);
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
	if (!j->hex || !j->rc || pthread_create(&j->tid, NULL, work, j)) {
		free(j->hex);
		free(j->rc);
		free(j);
		return NULL;
	}
	return j;
}

static void join(struct ssc_hashjob *j)
{
	if (!j->joined) {
#ifdef SCHED_IDLE
		struct sched_param sp = { 0 };

		/* needed now: an ordinary thread again, whatever else runs */
		pthread_setschedparam(j->tid, SCHED_OTHER, &sp);
#endif
		pthread_join(j->tid, NULL);
		j->joined = true;
	}
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
	free(j->hex);
	free(j->rc);
	free(j);
}
