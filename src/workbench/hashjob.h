/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * SHA-256 of input files on a thread of its own (hashjob.c), so that the
 * provenance of a report costs no wall time beside the reading.
 */
#ifndef SSCOPE_HASHJOB_H
#define SSCOPE_HASHJOB_H

#include <stddef.h>

struct ssc_hashjob;

/* Start hashing paths[0..n) (the strings must outlive the job); NULL
 * when no thread could be started (ssc_hashjob_get() then hashes). */
struct ssc_hashjob *ssc_hashjob_start(char *const *paths, size_t n);
/* The hash of paths[i] in hex, waiting for the job; 0 or -errno.  With
 * job NULL, paths[i] is hashed now. */
int ssc_hashjob_get(struct ssc_hashjob *job, char *const *paths, size_t i,
		    char hex[65]);
/* Wait for the job and free it (NULL is ignored). */
void ssc_hashjob_free(struct ssc_hashjob *job);

#endif
