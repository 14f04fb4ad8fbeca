/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Atomic output files: data go to a temporary file in the destination's
 * directory, which is renamed over the destination only when complete, so
 * an error never leaves a half-written result.  "-" is standard output
 * (written directly).  Compiled into both the library and the CLI.
 */
#ifndef SSCOPE_ATOMIC_H
#define SSCOPE_ATOMIC_H

#include <stdio.h>

struct ssc_atomic {
	FILE *f;      /* write here */
	char *path;   /* destination, NULL for stdout */
	char *tmp;    /* temporary name */
};

/* Open; returns 0 or -errno. */
int ssc_atomic_open(struct ssc_atomic *a, const char *path);

/* Flush, sync, close and rename into place; returns 0 or -errno. */
int ssc_atomic_commit(struct ssc_atomic *a);

/* Close and remove the temporary file (safe after a failed commit). */
void ssc_atomic_abort(struct ssc_atomic *a);

#endif
