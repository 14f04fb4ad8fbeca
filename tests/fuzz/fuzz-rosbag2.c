/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Fuzz harness of rosbag2 bag folders (io-rosbag2.c and the storage
 * readers behind it: SQLite .db3, MCAP, whole-file zstd).  An input is a
 * folder in one buffer: metadata.yaml, then each storage file after a
 * line "#FILE"; the files are named f0, f1, ... (the seeds' metadata
 * names them so).  The folder is written to a private temporary directory
 * (on /dev/shm when there is one) and read as a user's folder is, through
 * sscope_capture_load, once without and once with --topic, then
 * summarised as info does.
 */
#include "fuzz.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "internal.h"

#define SEP "\n#FILE\n"
#define MAX_PARTS 8

static char dir[64];

static void cleanup(void)
{
	char p[96];

	for (int i = 0; i < MAX_PARTS; i++) {
		snprintf(p, sizeof(p), "%s/f%d", dir, i);
		unlink(p);
	}
	snprintf(p, sizeof(p), "%s/metadata.yaml", dir);
	unlink(p);
	rmdir(dir);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	fuzz_quiet();
	snprintf(dir, sizeof(dir), "%s/sscope-fuzz-XXXXXX",
		 access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp");
	if (!mkdtemp(dir)) {
		perror("fuzz-rosbag2: mkdtemp");
		exit(1);
	}
	atexit(cleanup);
	return 0;
}

static int put(const char *name, const uint8_t *d, size_t n)
{
	char p[96];
	int fd;

	snprintf(p, sizeof(p), "%s/%s", dir, name);
	fd = open(p, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
	if (fd < 0)
		return -1;
	while (n > 0) {
		ssize_t w = write(fd, d, n);

		if (w <= 0) {
			close(fd);
			return -1;
		}
		d += w;
		n -= (size_t)w;
	}
	return close(fd);
}

static void load(const char *topic)
{
	struct sscope_reader_opts o = { 0 };
	struct sscope_capture *cap;
	struct sscope_diag d = { "" };
	struct sscope_stats st;

	o.threads = 1;
	o.topic = topic;
	if (sscope_capture_load(&cap, dir, &o, &d) == 0) {
		for (size_t k = 0; k < cap->n_channels; k++)
			sscope_stats_compute(cap->channels[k].data, 1, cap->n, &st);
		sscope_capture_free(cap);
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const uint8_t *p = data, *end = data + size;
	const uint8_t *s = memmem(p, size, SEP, strlen(SEP));
	int nf = 0;

	if (put("metadata.yaml", p, (size_t)((s ? s : end) - p)))
		return 0;
	while (s && nf < MAX_PARTS) {
		char name[8];
		const uint8_t *q = s + strlen(SEP);

		s = memmem(q, (size_t)(end - q), SEP, strlen(SEP));
		snprintf(name, sizeof(name), "f%d", nf++);
		if (put(name, q, (size_t)((s ? s : end) - q)))
			return 0;
	}
	/* files of the previous input are gone */
	for (int i = nf; i < MAX_PARTS; i++) {
		char n[96];

		snprintf(n, sizeof(n), "%s/f%d", dir, i);
		unlink(n);
	}
	load(NULL);
	load("/imu/data,/imu/temperature");
	return 0;
}
