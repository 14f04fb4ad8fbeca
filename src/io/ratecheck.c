/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Plausibility of a sample rate derived from time stamps.  Inertial
 * captures run between about 1e-3 Hz (a temperature log) and 1e7 Hz (a
 * converter test); a rate outside that range from a time column nearly
 * always means stamps in another unit than the header says (rostopic's
 * and EuRoC's nanoseconds read as seconds gives "2e-07 Hz").  The hint
 * names the unit that brings the rate closest to the usual IMU band.
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>

#include "sscope-capture.h"

int sscope_capture_check_rate(const struct sscope_capture *cap,
			      struct sscope_diag *hint)
{
	static const struct {
		double f; /* true rate = rate * f when the stamps are in... */
		const char *unit;
	} c[] = { { 1e9, "ns" }, { 1e6, "us" }, { 1e3, "ms" }, { 1, "s" },
		  { 1e-3, "ks" } };
	double rate, best = INFINITY;
	const char *label, *likely = NULL;
	size_t bi = 0;

	if (!cap || cap->rate_source != SSCOPE_CAPTURE_RATE_TIME_COLUMN)
		return 0;
	rate = cap->rate_hz;
	if (rate >= 1e-3 && rate <= 1e7)
		return 0;
	/* the stamps' unit as labelled scales them to s; try the others */
	for (size_t i = 0; i < sizeof(c) / sizeof(c[0]); i++) {
		double r = rate * c[i].f * cap->time_col.unit.scale;
		double d = fabs(log10(r) - 2.5); /* ~300 Hz */

		if (r >= 1e-3 && r <= 1e7 && d < best) {
			best = d;
			bi = i;
			likely = c[i].unit;
		}
	}
	label = cap->time_col.unit_label && cap->time_col.unit_label[0] ?
			cap->time_col.unit_label : "s";
	if (likely)
		ssc_diag(hint, -EDOM,
			 "rate %.3g Hz from the time column '%s' (read as %s) is implausible: if its stamps are in %s the rate is %.6g Hz; name the unit in the header ('%s [%s]') or give --rate",
			 rate, cap->time_col.name, label, likely,
			 rate * c[bi].f * cap->time_col.unit.scale,
			 cap->time_col.name, likely);
	else
		ssc_diag(hint, -EDOM,
			 "rate %.3g Hz from the time column '%s' (read as %s) is implausible: check the stamps' unit or give --rate",
			 rate, cap->time_col.name, label);
	return -EDOM;
}
