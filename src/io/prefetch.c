/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Double-buffered chunk reading: a thread fills one chunk with the reader
 * while the caller works on the other, so a streamed command spends the
 * time of the slower of reading and computing instead of their sum (a
 * Welch estimate over a CSV used to parse with the FFT threads idle and
 * transform with the parser idle).  Chunks are handed over strictly in
 * order; the reader is used by the thread alone until it stops.
 */
#include "config.h"

#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "prefetch.h"
#include "sscope-reader.h"

enum { EMPTY, FULL };

struct slot {
	struct sscope_reader_chunk ch;
	int state, rc;
	struct sscope_diag diag;
};

struct ssc_prefetch {
	struct sscope_reader *rd;
	struct slot slot[2];
	size_t n_channels;
	unsigned next;   /* slot the caller takes next */
	bool held;       /* the caller holds slot next ^ 1 */
	bool stop, done; /* asked to stop; the thread has finished */
	pthread_mutex_t mu;
	pthread_cond_t cv;
	pthread_t tid;
};

static void *producer(void *arg)
{
	struct ssc_prefetch *pf = arg;
	unsigned i = 0;

	for (;;) {
		struct slot *s = &pf->slot[i];
		bool last;

		pthread_mutex_lock(&pf->mu);
		while (s->state != EMPTY && !pf->stop)
			pthread_cond_wait(&pf->cv, &pf->mu);
		if (pf->stop) {
			pthread_mutex_unlock(&pf->mu);
			break;
		}
		pthread_mutex_unlock(&pf->mu);
		s->diag.msg[0] = '\0';
		s->rc = sscope_reader_read(pf->rd, &s->ch, &s->diag);
		last = s->rc || s->ch.rows == 0;
		pthread_mutex_lock(&pf->mu);
		s->state = FULL;
		pthread_cond_broadcast(&pf->cv);
		pthread_mutex_unlock(&pf->mu);
		if (last)
			break;
		i ^= 1;
	}
	pthread_mutex_lock(&pf->mu);
	pf->done = true;
	pthread_cond_broadcast(&pf->cv);
	pthread_mutex_unlock(&pf->mu);
	return NULL;
}

static void free_slots(struct ssc_prefetch *pf)
{
	for (int i = 0; i < 2; i++) {
		struct sscope_reader_chunk *c = &pf->slot[i].ch;

		for (size_t k = 0; c->data && k < pf->n_channels; k++)
			free(c->data[k]);
		free(c->data);
		free(c->time_s);
	}
}

int ssc_prefetch_start(struct ssc_prefetch **out, struct sscope_reader *rd,
		       size_t n_channels, size_t capacity, bool time)
{
	struct ssc_prefetch *pf = calloc(1, sizeof(*pf));

	*out = NULL;
	if (!pf)
		return -ENOMEM;
	pf->rd = rd;
	pf->n_channels = n_channels;
	for (int i = 0; i < 2; i++) {
		struct sscope_reader_chunk *c = &pf->slot[i].ch;

		c->capacity = capacity;
		c->data = calloc(n_channels ? n_channels : 1, sizeof(double *));
		if (!c->data)
			goto nomem;
		for (size_t k = 0; k < n_channels; k++) {
			c->data[k] = malloc(capacity * sizeof(double));
			if (!c->data[k])
				goto nomem;
		}
		if (time) {
			c->time_s = malloc(capacity * sizeof(double));
			if (!c->time_s)
				goto nomem;
		}
	}
	pthread_mutex_init(&pf->mu, NULL);
	pthread_cond_init(&pf->cv, NULL);
	if (pthread_create(&pf->tid, NULL, producer, pf)) {
		pthread_mutex_destroy(&pf->mu);
		pthread_cond_destroy(&pf->cv);
		free_slots(pf);
		free(pf);
		return -EAGAIN;
	}
	*out = pf;
	return 0;
nomem:
	free_slots(pf);
	free(pf);
	return -ENOMEM;
}

int ssc_prefetch_next(struct ssc_prefetch *pf, const struct sscope_reader_chunk **ch,
		      struct sscope_diag *diag)
{
	struct slot *s = &pf->slot[pf->next];

	pthread_mutex_lock(&pf->mu);
	if (pf->held) {
		/* hand the chunk the caller is done with back to the thread */
		pf->slot[pf->next ^ 1].state = EMPTY;
		pthread_cond_broadcast(&pf->cv);
	}
	while (s->state != FULL && !pf->done)
		pthread_cond_wait(&pf->cv, &pf->mu);
	if (s->state != FULL) /* asked again after the end */
		s->ch.rows = 0, s->rc = 0;
	pthread_mutex_unlock(&pf->mu);
	pf->held = true;
	pf->next ^= 1;
	*ch = &s->ch;
	if (s->rc && diag)
		*diag = s->diag;
	return s->rc;
}

void ssc_prefetch_stop(struct ssc_prefetch *pf)
{
	if (!pf)
		return;
	pthread_mutex_lock(&pf->mu);
	pf->stop = true;
	pthread_cond_broadcast(&pf->cv);
	pthread_mutex_unlock(&pf->mu);
	pthread_join(pf->tid, NULL);
	pthread_mutex_destroy(&pf->mu);
	pthread_cond_destroy(&pf->cv);
	free_slots(pf);
	free(pf);
}
