/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Streaming with the read of the next block overlapped with the work on
 * the last (prefetch.c): a thread reads chunks ahead of the caller.
 */
#ifndef SSCOPE_PREFETCH_H
#define SSCOPE_PREFETCH_H

#include <stdbool.h>
#include <stddef.h>

#include "sscope-reader.h"

struct ssc_prefetch;

/*
 * Start reading rd (which must stay open) on a thread into two chunks of
 * capacity rows with n_channels data arrays, and time stamps if time.
 * Returns 0, -ENOMEM, or -EAGAIN when no thread could be started.
 */
int ssc_prefetch_start(struct ssc_prefetch **pf, struct sscope_reader *rd,
		       size_t n_channels, size_t capacity, bool time);

/*
 * The next chunk, in order (rows == 0 at the end of the data), valid until
 * the next call, which hands it back to the reading thread.  Returns 0 or
 * the reader's error with its detail in diag (the end of the stream).
 */
int ssc_prefetch_next(struct ssc_prefetch *pf, const struct sscope_reader_chunk **ch,
		      struct sscope_diag *diag);

/* Stop the thread (after the chunk it is reading) and free (NULL ok). */
void ssc_prefetch_stop(struct ssc_prefetch *pf);

#endif
