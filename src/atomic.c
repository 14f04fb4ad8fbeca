/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Atomic output files (see atomic.h): mkstemp beside the destination,
 * fsync, rename(2), which POSIX makes atomic within a file system.
 */
#include "config.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "atomic.h"

int ssc_atomic_open(struct ssc_atomic *a, const char *path)
{
	size_t n;
	int fd;

	memset(a, 0, sizeof(*a));
	if (!path || !*path)
		return -EINVAL;
	if (!strcmp(path, "-")) {
		a->f = stdout;
		return 0;
	}
	n = strlen(path);
	a->path = malloc(n + 1);
	a->tmp = malloc(n + 16);
	if (!a->path || !a->tmp) {
		free(a->path);
		free(a->tmp);
		return -ENOMEM;
	}
	memcpy(a->path, path, n + 1);
	memcpy(a->tmp, path, n);
	memcpy(a->tmp + n, ".tmp.XXXXXX", 12);
	fd = mkstemp(a->tmp);
	if (fd < 0) {
		int e = errno;

		free(a->path);
		free(a->tmp);
		a->path = a->tmp = NULL;
		return -e;
	}
	fchmod(fd, 0644);
	a->f = fdopen(fd, "wb");
	if (!a->f) {
		int e = errno;

		close(fd);
		unlink(a->tmp);
		free(a->path);
		free(a->tmp);
		a->path = a->tmp = NULL;
		return -e;
	}
	return 0;
}

int ssc_atomic_commit(struct ssc_atomic *a)
{
	int rc = 0;

	if (!a->f)
		return -EINVAL;
	if (!a->path) { /* stdout */
		if (fflush(a->f) != 0 || ferror(a->f))
			rc = -EIO;
		a->f = NULL;
		return rc;
	}
	if (fflush(a->f) != 0 || ferror(a->f) || fsync(fileno(a->f)) != 0)
		rc = errno ? -errno : -EIO;
	if (fclose(a->f) != 0 && !rc)
		rc = -EIO;
	a->f = NULL;
	if (!rc && rename(a->tmp, a->path) != 0)
		rc = -errno;
	if (rc)
		unlink(a->tmp);
	free(a->path);
	free(a->tmp);
	a->path = a->tmp = NULL;
	return rc;
}

void ssc_atomic_abort(struct ssc_atomic *a)
{
	if (a->f && a->path)
		fclose(a->f);
	else if (a->f)
		fflush(a->f);
	if (a->tmp)
		unlink(a->tmp);
	free(a->path);
	free(a->tmp);
	memset(a, 0, sizeof(*a));
}
