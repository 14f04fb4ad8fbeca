/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Helpers of the fuzz harnesses (see fuzz.h). */
#include "fuzz.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

int fuzz_replay;
static int saved_stdin = -1;

int fuzz_file(const void *data, size_t size, char *path, size_t len)
{
	int fd = memfd_create("fuzz-input", MFD_CLOEXEC);
	const char *p = data;

	if (fd < 0)
		return -1;
	while (size > 0) {
		ssize_t w = write(fd, p, size);

		if (w < 0) {
			if (errno == EINTR)
				continue;
			close(fd);
			return -1;
		}
		p += w;
		size -= (size_t)w;
	}
	snprintf(path, len, "/proc/self/fd/%d", fd);
	return fd;
}

void fuzz_file_close(int fd)
{
	if (fd >= 0)
		close(fd);
}

int fuzz_stdin(const void *data, size_t size)
{
	int p[2];
	const char *d = data;

	if (size > 65536 || pipe(p))
		return -1;
	if (fcntl(p[1], F_SETPIPE_SZ, 65536) < 0 && size > 4096) {
		close(p[0]);
		close(p[1]);
		return -1;
	}
	while (size > 0) {
		ssize_t w = write(p[1], d, size);

		if (w <= 0) {
			close(p[0]);
			close(p[1]);
			return -1;
		}
		d += w;
		size -= (size_t)w;
	}
	close(p[1]);
	if (saved_stdin < 0)
		saved_stdin = dup(STDIN_FILENO);
	dup2(p[0], STDIN_FILENO);
	close(p[0]);
	return 0;
}

void fuzz_stdin_restore(void)
{
	if (saved_stdin >= 0)
		dup2(saved_stdin, STDIN_FILENO);
}

void fuzz_quiet(void)
{
	int null = open("/dev/null", O_WRONLY | O_CLOEXEC);

	if (null < 0)
		return;
	dup2(null, STDOUT_FILENO);
	close(null);
}
