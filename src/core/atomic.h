/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Output files that never destroy what the user owns.  A regular file (or
 * a name that does not exist yet) is written to a temporary file beside it
 * and renamed over it only when complete, so an error never leaves a
 * half-written result; a symbolic link is followed and its target replaced
 * the same way (the link stays a link).  A file with other hard links is
 * written in place once the output is complete (blocks reserved first), so
 * every name keeps sharing it.  Everything else is written
 * directly and never replaced: "-", /dev/stdout, /dev/stderr and /dev/fd/N
 * (the open descriptor), FIFOs, character and block devices.  The first
 * write error's errno is kept, so "No space left on device" can be said
 * whatever the size of the output.  Compiled into both the library and
 * the CLI.
 */
#ifndef SSCOPE_ATOMIC_H
#define SSCOPE_ATOMIC_H

#include <stdbool.h>
#include <stdio.h>

struct ssc_atomic {
	FILE *f;      /* write here */
	char *path;   /* file renamed over at commit (links resolved), or
			 NULL when written directly */
	char *tmp;    /* temporary name, or NULL when written directly */
	int fd;       /* descriptor under f */
	int err;      /* errno of the first failed write, 0 if none */
	bool own_fd;  /* close fd at the end (not for standard output) */
	bool discard; /* aborting: drop what is still buffered */
};

/* "-", /dev/stdout, /dev/stderr, /dev/fd/N: the descriptor, or -1. */
int ssc_named_fd(const char *path);

/* The file a chain of symbolic links ends at (it may not exist).  Returns
 * a malloc'ed path, NULL with errno set. */
char *ssc_resolve_links(const char *path);

/* Open; returns 0 or -errno.  @p a must stay at its address until
 * commit or abort (the stream refers to it). */
int ssc_atomic_open(struct ssc_atomic *a, const char *path);

/* The write error so far: 0, or -errno (-EIO when the stream failed
 * without one). */
int ssc_atomic_error(const struct ssc_atomic *a);

/* Flush, sync, close and rename into place; returns 0 or -errno.  On
 * failure the temporary file is removed. */
int ssc_atomic_commit(struct ssc_atomic *a);

/* Drop what is buffered, close and remove the temporary file (safe after a
 * failed commit). */
void ssc_atomic_abort(struct ssc_atomic *a);

#endif
