/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Output files (see atomic.h).  Replacement: a temporary file created with
 * O_EXCL beside the (link-resolved) destination, fsync, rename(2), which
 * POSIX makes atomic within a file system; the replaced file's permission
 * bits are kept, a new file gets 0666 less the umask.  Direct writes open
 * the existing node without O_CREAT or O_TRUNC.  The stream is a
 * fopencookie(3) stream over the descriptor so that the errno of a failed
 * write(2) is kept for the message (stdio forgets it).  A file with other
 * hard links is not renamed over (that would part it from its other
 * names): the complete temporary file is copied into it.
 */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

#include "atomic.h"

static ssize_t sink_write(void *cookie, const char *buf, size_t n)
{
	struct ssc_atomic *a = cookie;
	size_t done = 0;

	if (a->discard)
		return (ssize_t)n;
	if (a->err)
		return 0; /* stdio's "error": the first errno is kept */
	while (done < n) {
		ssize_t w = write(a->fd, buf + done, n - done);

		if (w < 0 && errno == EINTR)
			continue;
		if (w <= 0) {
			a->err = w < 0 ? errno : EIO;
			return (ssize_t)done;
		}
		done += (size_t)w;
	}
	return (ssize_t)n;
}

static int sink_close(void *cookie)
{
	struct ssc_atomic *a = cookie;

	if (a->own_fd && a->fd >= 0 && close(a->fd) != 0 && !a->err &&
	    !a->discard)
		a->err = errno;
	a->fd = -1;
	return a->err ? -1 : 0;
}

static int make_stream(struct ssc_atomic *a)
{
	static const cookie_io_functions_t io = {
		.read = NULL, .write = sink_write, .seek = NULL,
		.close = sink_close,
	};

	a->f = fopencookie(a, "w", io);
	if (!a->f)
		return -errno;
	/* large blocks for large captures; stdio's default is 4 KiB */
	setvbuf(a->f, NULL, _IOFBF, 1 << 16);
	return 0;
}

/* "-", /dev/stdout, /dev/stderr, /dev/fd/N: the descriptor, or -1. */
int ssc_named_fd(const char *path)
{
	const char *n = NULL;
	char *end;
	long v;

	if (!strcmp(path, "-") || !strcmp(path, "/dev/stdout"))
		return STDOUT_FILENO;
	if (!strcmp(path, "/dev/stderr"))
		return STDERR_FILENO;
	if (!strncmp(path, "/dev/fd/", 8))
		n = path + 8;
	else if (!strncmp(path, "/proc/self/fd/", 14))
		n = path + 14;
	if (!n || *n < '0' || *n > '9')
		return -1;
	errno = 0;
	v = strtol(n, &end, 10);
	if (*end || errno || v > INT_MAX)
		return -1;
	return (int)v;
}

/* The file a chain of symbolic links ends at (it may not exist).  Returns
 * a malloc'ed path, NULL with errno set. */
char *ssc_resolve_links(const char *path)
{
	char *cur = strdup(path);

	for (int hops = 0; cur; hops++) {
		struct stat st;
		char *buf, *next;
		ssize_t n;
		size_t dl;

		if (lstat(cur, &st) != 0) {
			if (errno == ENOENT)
				return cur; /* a new file (or a dangling link's) */
			break;
		}
		if (!S_ISLNK(st.st_mode))
			return cur;
		if (hops >= 40) {
			errno = ELOOP;
			break;
		}
		buf = malloc(PATH_MAX);
		if (!buf)
			break;
		n = readlink(cur, buf, PATH_MAX - 1);
		if (n < 0) {
			free(buf);
			break;
		}
		buf[n] = '\0';
		if (buf[0] == '/' || !strrchr(cur, '/')) {
			next = buf;
		} else {
			dl = (size_t)(strrchr(cur, '/') - cur) + 1;
			next = malloc(dl + (size_t)n + 1);
			if (next) {
				memcpy(next, cur, dl);
				memcpy(next + dl, buf, (size_t)n + 1);
			}
			free(buf);
			if (!next)
				break;
		}
		free(cur);
		cur = next;
	}
	free(cur);
	return NULL;
}

/* Create "<path>.tmp.XXXXXX" (or, when that name is too long,
 * "<dir>/.sscope.tmp.XXXXXX") with O_EXCL.  Returns the descriptor, or
 * -errno. */
static int create_temp(const char *path, char **tmp_out)
{
	static const char abc[] =
		"abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789";
	size_t n = strlen(path);
	char *tmp = malloc(n + 24);
	int e = EEXIST;

	if (!tmp)
		return -ENOMEM;
	for (int attempt = 0; attempt < 200; attempt++) {
		unsigned char r[6];
		char *x;
		int fd;

		if (e == ENAMETOOLONG) {
			const char *sl = strrchr(path, '/');
			size_t dl = sl ? (size_t)(sl - path) + 1 : 0;

			memcpy(tmp, path, dl);
			memcpy(tmp + dl, ".sscope.tmp.XXXXXX", 19);
		} else {
			memcpy(tmp, path, n);
			memcpy(tmp + n, ".tmp.XXXXXX", 12);
		}
		x = tmp + strlen(tmp) - 6;
		if (getrandom(r, sizeof(r), GRND_NONBLOCK) != (ssize_t)sizeof(r)) {
			struct timespec ts;
			uint64_t s;

			clock_gettime(CLOCK_MONOTONIC, &ts);
			s = (uint64_t)ts.tv_nsec * 6364136223846793005u +
			    (uint64_t)getpid() * 1442695040888963407u +
			    (uint64_t)attempt;
			for (size_t i = 0; i < sizeof(r); i++)
				r[i] = (unsigned char)(s >> (8 * i));
		}
		for (size_t i = 0; i < sizeof(r); i++)
			x[i] = abc[r[i] % (sizeof(abc) - 1)];
		fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
		if (fd >= 0) {
			*tmp_out = tmp;
			return fd;
		}
		if (errno == ENAMETOOLONG && e != ENAMETOOLONG) {
			e = ENAMETOOLONG;
			continue;
		}
		if (errno != EEXIST) {
			e = errno;
			break;
		}
	}
	free(tmp);
	return e == ENAMETOOLONG ? -ENAMETOOLONG : -e;
}

int ssc_atomic_open(struct ssc_atomic *a, const char *path)
{
	struct stat st;
	int fd, rc;

	memset(a, 0, sizeof(*a));
	a->fd = -1;
	if (!path || !*path)
		return -EINVAL;
	fd = ssc_named_fd(path);
	if (fd >= 0) { /* an open descriptor: written as it is */
		if (fcntl(fd, F_GETFD) < 0)
			return -EBADF;
		if (fd == STDOUT_FILENO)
			fflush(stdout); /* keep the order of what went before */
		a->fd = fd;
		rc = make_stream(a);
		if (rc)
			a->fd = -1;
		return rc;
	}
	if (stat(path, &st) != 0) {
		if (errno != ENOENT)
			return -errno;
	} else if (S_ISDIR(st.st_mode)) {
		return -EISDIR;
	} else if (!S_ISREG(st.st_mode)) {
		/* FIFO, device, socket: never replaced */
		fd = open(path, O_WRONLY | O_NOCTTY | O_CLOEXEC);
		if (fd < 0)
			return -errno;
		a->fd = fd;
		a->own_fd = true;
		rc = make_stream(a);
		if (rc) {
			close(fd);
			a->fd = -1;
			a->own_fd = false;
		}
		return rc;
	}
	a->path = ssc_resolve_links(path);
	if (!a->path)
		return errno ? -errno : -ENOMEM;
	fd = create_temp(a->path, &a->tmp);
	if (fd < 0) {
		free(a->path);
		a->path = NULL;
		return fd;
	}
	if (stat(a->path, &st) == 0 && S_ISREG(st.st_mode)) {
		/* keep what the replaced file had */
		fchmod(fd, st.st_mode & 07777);
		if (geteuid() == 0 && fchown(fd, st.st_uid, st.st_gid) == 0)
			fchmod(fd, st.st_mode & 07777);
	}
	a->fd = fd;
	a->own_fd = true;
	rc = make_stream(a);
	if (rc) {
		close(fd);
		unlink(a->tmp);
		free(a->path);
		free(a->tmp);
		memset(a, 0, sizeof(*a));
		a->fd = -1;
	}
	return rc;
}

int ssc_atomic_error(const struct ssc_atomic *a)
{
	if (a->err)
		return -a->err;
	return a->f && ferror(a->f) ? -EIO : 0;
}

/*
 * A regular file with other hard links: renaming over it would leave the
 * other names with the old content, so the complete temporary file is
 * copied into it instead.  Its blocks are reserved first (fallocate
 * without changing the size), so a full file system is found before the
 * old content is touched; then written, cut to size, synced.
 */
static int copy_into(const char *tmp, const char *path)
{
	_Alignas(8) char buf[1 << 16];
	struct stat st;
	int in, out, rc = 0;
	off_t off = 0;

	in = open(tmp, O_RDONLY | O_CLOEXEC);
	if (in < 0)
		return -errno;
	out = open(path, O_WRONLY | O_NOCTTY | O_CLOEXEC);
	if (out < 0 || fstat(in, &st) != 0) {
		rc = -errno;
		goto out;
	}
	if (st.st_size > 0 &&
	    fallocate(out, FALLOC_FL_KEEP_SIZE, 0, st.st_size) != 0 &&
	    errno != EOPNOTSUPP && errno != ENOSYS) {
		rc = -errno;
		goto out;
	}
	for (;;) {
		ssize_t n = read(in, buf, sizeof(buf)), w = 0;

		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0) {
			rc = -errno;
			goto out;
		}
		if (n == 0)
			break;
		while (w < n) {
			ssize_t k = pwrite(out, buf + w, (size_t)(n - w), off);

			if (k < 0 && errno == EINTR)
				continue;
			if (k <= 0) {
				rc = k < 0 ? -errno : -EIO;
				goto out;
			}
			w += k;
			off += k;
		}
	}
	if (ftruncate(out, off) != 0 || fsync(out) != 0)
		rc = -errno;
out:
	if (out >= 0 && close(out) != 0 && !rc)
		rc = -errno;
	close(in);
	return rc;
}

static bool has_other_links(const char *path)
{
	struct stat st;

	return stat(path, &st) == 0 && S_ISREG(st.st_mode) && st.st_nlink > 1;
}

int ssc_atomic_commit(struct ssc_atomic *a)
{
	int rc = 0;

	if (!a->f)
		return -EINVAL;
	if (fflush(a->f) != 0 || ferror(a->f))
		rc = a->err ? -a->err : -EIO;
	if (!rc && a->tmp && fsync(a->fd) != 0)
		rc = -errno;
	if (fclose(a->f) != 0 && !rc)
		rc = a->err ? -a->err : -EIO;
	a->f = NULL;
	if (!rc && a->tmp && has_other_links(a->path)) {
		rc = copy_into(a->tmp, a->path);
		unlink(a->tmp);
	} else if (!rc && a->tmp && rename(a->tmp, a->path) != 0) {
		rc = -errno;
	}
	if (rc && a->tmp)
		unlink(a->tmp);
	free(a->path);
	free(a->tmp);
	a->path = a->tmp = NULL;
	return rc;
}

void ssc_atomic_abort(struct ssc_atomic *a)
{
	int err = a->err;

	if (a->f) {
		a->discard = true;
		fclose(a->f);
	}
	if (a->tmp)
		unlink(a->tmp);
	free(a->path);
	free(a->tmp);
	memset(a, 0, sizeof(*a));
	a->fd = -1;
	a->err = err;
}
