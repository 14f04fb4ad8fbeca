/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Output files (src/atomic.c) and the writers on them: a regular file is
 * replaced atomically with its mode kept, a link's target is replaced and
 * the link kept, FIFOs and devices are written through, a failed write
 * returns its errno (ENOSPC on /dev/full) for any size, and a name too
 * long for the temporary suffix still works.
 */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "atomic.h"
#include "check-main.h"
#include "sensorscope.h"

static char dir[64];

static void setup(void)
{
	snprintf(dir, sizeof(dir), "/tmp/sscope-atomic.XXXXXX");
	ck_assert_ptr_nonnull(mkdtemp(dir));
}

static void teardown(void)
{
	char cmd[128];

	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
	ck_assert_int_eq(system(cmd), 0);
}

static void put(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");

	ck_assert_ptr_nonnull(f);
	fputs(text, f);
	ck_assert_int_eq(fclose(f), 0);
}

static void slurp(const char *path, char *buf, size_t len)
{
	FILE *f = fopen(path, "r");
	size_t n;

	ck_assert_ptr_nonnull(f);
	n = fread(buf, 1, len - 1, f);
	buf[n] = '\0';
	fclose(f);
}

/* Nothing but the names given is left in the folder. */
static void only(size_t n_names)
{
	char cmd[160];

	snprintf(cmd, sizeof(cmd), "test $(ls -A '%s' | wc -l) -eq %zu", dir,
		 n_names);
	ck_assert_int_eq(system(cmd), 0);
}

static int write_text(const char *path, const char *text)
{
	struct ssc_atomic a;
	int rc = ssc_atomic_open(&a, path);

	if (rc)
		return rc;
	fputs(text, a.f);
	return ssc_atomic_commit(&a);
}

START_TEST(replace_keeps_mode)
{
	char p[128], buf[64];
	struct stat st;

	snprintf(p, sizeof(p), "%s/f.txt", dir);
	put(p, "old\n");
	ck_assert_int_eq(chmod(p, 0640), 0);
	ck_assert_int_eq(write_text(p, "new\n"), 0);
	slurp(p, buf, sizeof(buf));
	ck_assert_str_eq(buf, "new\n");
	ck_assert_int_eq(stat(p, &st), 0);
	ck_assert_int_eq(st.st_mode & 07777, 0640);
	only(1);
}
END_TEST

START_TEST(link_target_replaced)
{
	char p[128], l[128], buf[64];
	struct stat st;

	snprintf(p, sizeof(p), "%s/target.txt", dir);
	snprintf(l, sizeof(l), "%s/link.txt", dir);
	put(p, "old\n");
	ck_assert_int_eq(symlink("target.txt", l), 0);
	ck_assert_int_eq(write_text(l, "new\n"), 0);
	ck_assert_int_eq(lstat(l, &st), 0);
	ck_assert(S_ISLNK(st.st_mode));
	slurp(p, buf, sizeof(buf));
	ck_assert_str_eq(buf, "new\n");
	/* a dangling link: its target is created */
	ck_assert_int_eq(unlink(p), 0);
	ck_assert_int_eq(write_text(l, "made\n"), 0);
	ck_assert_int_eq(lstat(l, &st), 0);
	ck_assert(S_ISLNK(st.st_mode));
	slurp(p, buf, sizeof(buf));
	ck_assert_str_eq(buf, "made\n");
	only(2);
}
END_TEST

START_TEST(fifo_written_through)
{
	char p[128], buf[64];
	struct ssc_atomic a;
	struct stat st;
	ssize_t n;
	int rd;

	snprintf(p, sizeof(p), "%s/fifo", dir);
	ck_assert_int_eq(mkfifo(p, 0600), 0);
	rd = open(p, O_RDONLY | O_NONBLOCK);
	ck_assert_int_ge(rd, 0);
	ck_assert_int_eq(write_text(p, "through\n"), 0);
	n = read(rd, buf, sizeof(buf) - 1);
	ck_assert_int_eq(n, 8);
	buf[n] = '\0';
	ck_assert_str_eq(buf, "through\n");
	/* an abort drops what is still buffered */
	ck_assert_int_eq(ssc_atomic_open(&a, p), 0);
	fputs("never\n", a.f);
	ssc_atomic_abort(&a);
	ck_assert_int_le(read(rd, buf, sizeof(buf)), 0);
	close(rd);
	ck_assert_int_eq(stat(p, &st), 0);
	ck_assert(S_ISFIFO(st.st_mode));
	only(1);
}
END_TEST

START_TEST(devices_written_through)
{
	struct sscope_writer *w;
	struct sscope_writer_column c[1] = { { "x", "V" } };
	double *v = calloc(100000, sizeof(double));
	struct stat st;

	ck_assert_ptr_nonnull(v);
	ck_assert_int_eq(write_text("/dev/null", "nothing\n"), 0);
	ck_assert_int_eq(stat("/dev/null", &st), 0);
	ck_assert(S_ISCHR(st.st_mode));
	/* /dev/full: ENOSPC when the buffer is flushed, small or large */
	ck_assert_int_eq(write_text("/dev/full", "x\n"), -ENOSPC);
	ck_assert_int_eq(sscope_writer_open(&w, "/dev/full", SSCOPE_CAPTURE_CSV,
					    c, 1, 0, NULL), 0);
	ck_assert_int_eq(sscope_writer_append(w, v, 100000), -ENOSPC);
	ck_assert_int_eq(sscope_writer_commit(w), -ENOSPC);
	ck_assert_int_eq(stat("/dev/full", &st), 0);
	ck_assert(S_ISCHR(st.st_mode));
	free(v);
}
END_TEST

START_TEST(refusals)
{
	struct ssc_atomic a;
	char p[128];

	ck_assert_int_eq(ssc_atomic_open(&a, ""), -EINVAL);
	ck_assert_int_eq(ssc_atomic_open(&a, NULL), -EINVAL);
	ck_assert_int_eq(ssc_atomic_open(&a, dir), -EISDIR);
	ck_assert_int_eq(ssc_atomic_open(&a, "/dev/fd/1000"), -EBADF);
	snprintf(p, sizeof(p), "%s/no/such.txt", dir);
	ck_assert_int_eq(ssc_atomic_open(&a, p), -ENOENT);
	only(0);
}
END_TEST

START_TEST(long_name)
{
	char p[PATH_MAX], buf[16];
	size_t n;

	/* a 255-byte name leaves no room for ".tmp.XXXXXX" */
	n = (size_t)snprintf(p, sizeof(p), "%s/", dir);
	memset(p + n, 'n', 255);
	p[n + 255] = '\0';
	ck_assert_int_eq(write_text(p, "ok\n"), 0);
	slurp(p, buf, sizeof(buf));
	ck_assert_str_eq(buf, "ok\n");
	only(1);
}
END_TEST

START_TEST(writer_on_a_stream)
{
	struct sscope_writer *w;
	struct sscope_writer_column c[2] = { { "t", "s" }, { "x", "mV" } };
	double rows[4] = { 0, 0.0015, 0.1, -0.002 };
	char *buf = NULL, p[128], file[256];
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);

	ck_assert_ptr_nonnull(f);
	ck_assert_int_eq(sscope_writer_fopen(&w, NULL, SSCOPE_CAPTURE_CSV, c, 2,
					     0, NULL), -EINVAL);
	ck_assert_int_eq(sscope_writer_fopen(&w, f, SSCOPE_CAPTURE_CSV, c, 2,
					     0, NULL), 0);
	ck_assert_int_eq(sscope_writer_append(w, rows, 2), 0);
	ck_assert_int_eq(sscope_writer_commit(w), 0);
	ck_assert_int_eq(fclose(f), 0); /* the caller's stream: still open */
	/* the same text as the writer on a file */
	snprintf(p, sizeof(p), "%s/w.csv", dir);
	ck_assert_int_eq(sscope_writer_open(&w, p, SSCOPE_CAPTURE_CSV, c, 2, 0,
					    NULL), 0);
	ck_assert_int_eq(sscope_writer_append(w, rows, 2), 0);
	ck_assert_int_eq(sscope_writer_commit(w), 0);
	slurp(p, file, sizeof(file));
	ck_assert_str_eq(buf, file);
	free(buf);
}
END_TEST

START_TEST(capture_on_a_stream)
{
	struct sscope_capture *cap;
	struct sscope_diag d = { "" };
	char p[128], *buf = NULL, file[4096];
	size_t len = 0;
	FILE *f;

	snprintf(p, sizeof(p), "%s/in.csv", dir);
	put(p, "t [s],gx [deg/s]\n0,1.25\n0.1,2.5\n0.2,-3.75\n");
	ck_assert_int_eq(sscope_capture_load(&cap, p, NULL, &d), 0);
	f = open_memstream(&buf, &len);
	ck_assert_ptr_nonnull(f);
	ck_assert_int_eq(sscope_capture_fwrite(cap, NULL, SSCOPE_CAPTURE_CSV, 0,
					       &d), -EINVAL);
	ck_assert_int_eq(sscope_capture_fwrite(cap, f, SSCOPE_CAPTURE_CSV, 0,
					       &d), 0);
	ck_assert_int_eq(fclose(f), 0);
	snprintf(p, sizeof(p), "%s/out.csv", dir);
	ck_assert_int_eq(sscope_capture_write(cap, p, SSCOPE_CAPTURE_CSV, 0,
					      &d), 0);
	slurp(p, file, sizeof(file));
	ck_assert_str_eq(buf, file);
	free(buf);
	sscope_capture_free(cap);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("atomic");
	TCase *tc = tcase_create("atomic");

	tcase_add_checked_fixture(tc, setup, teardown);
	tcase_add_test(tc, replace_keeps_mode);
	tcase_add_test(tc, link_target_replaced);
	tcase_add_test(tc, fifo_written_through);
	tcase_add_test(tc, devices_written_through);
	tcase_add_test(tc, refusals);
	tcase_add_test(tc, long_name);
	tcase_add_test(tc, writer_on_a_stream);
	tcase_add_test(tc, capture_on_a_stream);
	suite_add_tcase(s, tc);
	return s;
}
