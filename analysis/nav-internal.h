/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Helpers shared by the navigation modules (not installed).
 */
#ifndef SSCOPE_NAV_INTERNAL_H
#define SSCOPE_NAV_INTERNAL_H

#include <stddef.h>

/* 10th and 90th percentiles of the finite values of a sliding variance
 * (sscope_calib_variance_magnitude()), through @p work (n doubles).
 * Returns 0, or -EDOM when fewer than 10 values are finite. */
int ssc_nav_vs_percentiles(const double *vs, size_t n, double *work,
			   double *p10, double *p90);

#endif
