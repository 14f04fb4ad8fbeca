/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The report's input hashes on their own thread (src/cli/hashjob.c): the
 * hashes are the files' SHA-256 (against ssc_sha256_file() and a known
 * digest) whether the thread finished the work, was taken over at once
 * (the waiting thread finishing it), or never started; a file that cannot
 * be opened gives its -errno and does not stop the others.
 */
#include "config.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hashjob.h"
#include "html.h"
#include "check-main.h"

static char dir[] = "/tmp/sscope-hashjob.XXXXXX";

/* a file of n bytes of a fixed pattern */
static void write_file(const char *path, size_t n)
{
	FILE *f = fopen(path, "wb");

	ck_assert_ptr_nonnull(f);
	for (size_t i = 0; i < n; i++)
		fputc((int)((i * 2654435761u) >> 13) & 0xff, f);
	ck_assert_int_eq(fclose(f), 0);
}

START_TEST(hashes_every_way)
{
	char a[64], b[64], c[64], missing[64];
	char *paths[4] = { a, missing, b, c };
	char want[4][65], got[65];

	ck_assert_ptr_nonnull(mkdtemp(dir));
	snprintf(a, sizeof(a), "%s/a", dir);
	snprintf(b, sizeof(b), "%s/b", dir);
	snprintf(c, sizeof(c), "%s/empty", dir);
	snprintf(missing, sizeof(missing), "%s/missing", dir);
	write_file(a, 24u << 20); /* long enough to be taken over */
	write_file(b, 100003);
	write_file(c, 0);
	for (int i = 0; i < 4; i++)
		if (i != 1)
			ck_assert_int_eq(ssc_sha256_file(paths[i], want[i]), 0);
	/* the empty file's digest, from FIPS 180-2 */
	ck_assert_str_eq(want[3], "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
	for (int way = 0; way < 3; way++) {
		struct ssc_hashjob *j = way == 2 ? NULL : ssc_hashjob_start(paths, 4);

		if (way < 2)
			ck_assert_ptr_nonnull(j);
		if (way == 1)
			usleep(300000); /* let the thread work (perhaps finish) */
		for (int i = 0; i < 4; i++) {
			int rc = ssc_hashjob_get(j, paths, (size_t)i, got);

			if (i == 1) {
				ck_assert_int_eq(rc, -ENOENT);
				continue;
			}
			ck_assert_int_eq(rc, 0);
			ck_assert_str_eq(got, want[i]);
		}
		ssc_hashjob_free(j);
	}
	unlink(a);
	unlink(b);
	unlink(c);
	rmdir(dir);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("hashjob");
	TCase *tc = tcase_create("hashjob");

	tcase_set_timeout(tc, 60);
	tcase_add_test(tc, hashes_every_way);
	suite_add_tcase(s, tc);
	return s;
}
