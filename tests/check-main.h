/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Shared main() of the Check unit tests: runs the suite made by
 * make_suite() and reports in TAP on stdout for automake's TAP driver.
 *
 * Two tiers.  `make check` runs every test case except those tagged
 * "long" (statistical coverage over many records, exhaustive sweeps: more
 * than a few seconds of CPU each); `make check-long` (SSCOPE_TEST_TIER=long
 * in the environment) runs only those; SSCOPE_TEST_TIER=all runs both (CI
 * runs the release tarball's tests so).  Tag a test case with long_tcase()
 * below.
 */
#ifndef SSCOPE_CHECK_MAIN_H
#define SSCOPE_CHECK_MAIN_H

#include <check.h>
#include <stdlib.h>
#include <string.h>

/*
 * Check's assertions record the place of every one that passes, so that a
 * test that crashes can be located: one system call each (a write to the
 * forked test's pipe).  Inside the loops of the exhaustive tests that was
 * most of the suite's time, half of it in the kernel (the PNG round trips:
 * 31 s of system time in 60 s).  Here a passing assertion costs nothing; a
 * failing one reports as before (file, line, expression, message), and
 * mark_point() still marks a place where it helps.
 */
#undef ck_assert_msg
#define ck_assert_msg(expr, ...)                                              \
	do {                                                                  \
		if (!(expr))                                                  \
			_ck_assert_failed(__FILE__, __LINE__,                 \
					  "Assertion '" #expr "' failed",     \
					  ##__VA_ARGS__);                     \
	} while (0)

static Suite *make_suite(void);

/* A test case of the long tier: tagged, with a wall-clock limit of
 * @p timeout_s (at least ten times its time on an idle machine). */
static inline TCase *long_tcase(const char *name, double timeout_s)
{
	TCase *tc = tcase_create(name);

	tcase_set_tags(tc, "long");
	tcase_set_timeout(tc, timeout_s);
	return tc;
}

int main(void)
{
	SRunner *sr = srunner_create(make_suite());
	const char *tier = getenv("SSCOPE_TEST_TIER");
	int is_long = tier && !strcmp(tier, "long");
	int is_all = tier && !strcmp(tier, "all");

	srunner_set_tap(sr, "-");
	srunner_run_tagged(sr, NULL, NULL, is_long ? "long" : NULL,
			   is_long || is_all ? NULL : "long", CK_SILENT);
	srunner_free(sr);
	return 0; /* failures are reported in TAP */
}

/* relative closeness helper */
#define ck_assert_rel(a, b, tol)                                              \
	do {                                                                  \
		double a_ = (a), b_ = (b);                                    \
		double d_ = fabs(a_ - b_), m_ = fmax(fabs(a_), fabs(b_));     \
		ck_assert_msg(d_ <= (tol) * m_ || d_ == 0,                    \
			      "%s = %.17g, %s = %.17g: relative difference " \
			      "%.3g > %.3g",                                  \
			      #a, a_, #b, b_, m_ > 0 ? d_ / m_ : d_,          \
			      (double)(tol));                                 \
	} while (0)

#endif
