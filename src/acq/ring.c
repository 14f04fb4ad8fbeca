/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Lock-free single-producer single-consumer ring (Lamport's queue with
 * C11 acquire/release atomics): the producer owns head, the consumer
 * owns tail, each reads the other's index with acquire ordering and
 * publishes its own with release ordering, so a slot's contents are
 * visible before the index that hands it over.  Indices run freely and
 * are masked on use (capacity a power of two); the ring is full when
 * head - tail == capacity.  Neither side ever blocks or overwrites.
 */
#include "acq.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

int ssc_ring_init(struct ssc_ring *r, size_t capacity)
{
	size_t cap = 2;

	memset(r, 0, sizeof(*r));
	if (capacity < 2 || capacity > ((size_t)1 << 30))
		return -EINVAL;
	while (cap < capacity)
		cap <<= 1;
	r->buf = calloc(cap, sizeof(*r->buf)); /* touched: resident */
	if (!r->buf)
		return -ENOMEM;
	r->mask = cap - 1;
	atomic_init(&r->head, 0);
	atomic_init(&r->tail, 0);
	return 0;
}

void ssc_ring_free(struct ssc_ring *r)
{
	free(r->buf);
	r->buf = NULL;
}

size_t ssc_ring_capacity(const struct ssc_ring *r)
{
	return r->mask + 1;
}

bool ssc_ring_push(struct ssc_ring *r, const struct ssc_acq_sample *s)
{
	size_t h = atomic_load_explicit(&r->head, memory_order_relaxed);
	size_t t = atomic_load_explicit(&r->tail, memory_order_acquire);

	if (h - t > r->mask)
		return false;
	r->buf[h & r->mask] = *s;
	atomic_store_explicit(&r->head, h + 1, memory_order_release);
	return true;
}

size_t ssc_ring_pop(struct ssc_ring *r, struct ssc_acq_sample *out,
		    size_t max)
{
	size_t t = atomic_load_explicit(&r->tail, memory_order_relaxed);
	size_t h = atomic_load_explicit(&r->head, memory_order_acquire);
	size_t n = h - t;

	if (n > max)
		n = max;
	for (size_t i = 0; i < n; i++)
		out[i] = r->buf[(t + i) & r->mask];
	atomic_store_explicit(&r->tail, t + n, memory_order_release);
	return n;
}
