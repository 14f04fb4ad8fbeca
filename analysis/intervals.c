/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Interval tables against a record's time base: the value a schedule
 * (START END VALUE...) gives each sample, for rate-table runs without a
 * reference column and tilt tables of inclinometer calibrations.
 */
#include "internal.h"

#include <math.h>

#include "sscope-timing.h"

int sscope_timing_intervals_sample(const double *t_s, double rate_hz, size_t n,
				   const double *rows, size_t n_rows, size_t n_val,
				   double *const *out)
{
	size_t w = 2 + n_val;

	if (!out || n_val == 0 || (!rows && n_rows) || (!t_s && !(rate_hz > 0)))
		return -EINVAL;
	for (size_t i = 0; i < n; i++) {
		double t = t_s ? t_s[i] - t_s[0] : (double)i / rate_hz;
		size_t q;

		for (q = 0; q < n_rows; q++)
			if (t >= rows[w * q] && t < rows[w * q + 1])
				break;
		for (size_t v = 0; v < n_val; v++)
			out[v][i] = q < n_rows ? rows[w * q + 2 + v] : (double)NAN;
	}
	return 0;
}
