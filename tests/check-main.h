/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Shared main() of the Check unit tests: runs the suite made by
 * make_suite() and reports in TAP on stdout for automake's TAP driver.
 */
#ifndef SSCOPE_CHECK_MAIN_H
#define SSCOPE_CHECK_MAIN_H

#include <check.h>
#include <stdlib.h>

static Suite *make_suite(void);

int main(void)
{
	SRunner *sr = srunner_create(make_suite());

	srunner_set_tap(sr, "-");
	srunner_run_all(sr, CK_SILENT);
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
