/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Gap logic and running statistics of the acquisition path.
 * - Interval statistics: Welford's one-pass mean and variance.
 * - Gaps from time stamps: round(dt / T) - 1 samples lost.
 * - Gaps from a 16-bit wrapping sample counter: the counter difference is
 *   exact modulo 2^16; the time stamps decide how many whole wraps
 *   happened (valid while the time error stays below 2^15 periods).
 * - Live Allan deviation: the non-overlapping estimator (IEEE Std 952,
 *   Annex C) over block averages of m = 1, 10, 100, 1000 samples;
 *   sigma^2 = sum (ybar_{k+1} - ybar_k)^2 / (2 (n - 1)).
 */
#include "acq.h"

#include <math.h>

void ssc_intervals_add(struct ssc_intervals *iv, double dt)
{
	double d;

	iv->n++;
	if (iv->n == 1) {
		iv->mean_s = iv->min_s = iv->max_s = dt;
		iv->m2 = 0;
		return;
	}
	d = dt - iv->mean_s;
	iv->mean_s += d / (double)iv->n;
	iv->m2 += d * (dt - iv->mean_s);
	if (dt < iv->min_s)
		iv->min_s = dt;
	if (dt > iv->max_s)
		iv->max_s = dt;
}

double ssc_intervals_sd(const struct ssc_intervals *iv)
{
	if (iv->n == 0)
		return (double)NAN;
	if (iv->n == 1)
		return 0;
	return sqrt(iv->m2 / (double)(iv->n - 1));
}

uint64_t ssc_gap_from_time(double dt_s, double period_s)
{
	double k;

	if (!(period_s > 0) || !(dt_s > 0) || !isfinite(dt_s))
		return 0;
	k = nearbyint(dt_s / period_s) - 1;
	return k > 0 ? (uint64_t)k : 0;
}

long ssc_gap_from_counter(uint16_t prev, uint16_t cur, double dt_s,
			  double period_s)
{
	long steps = (long)(uint16_t)(cur - prev);

	if (period_s > 0 && dt_s > 0 && isfinite(dt_s)) {
		double wraps = nearbyint((dt_s / period_s - (double)steps) /
					 65536.0);

		if (wraps > 0)
			steps += (long)wraps * 65536;
	}
	return steps == 0 ? -1 : steps - 1;
}

void ssc_run_adev_init(struct ssc_run_adev *a)
{
	size_t m = 1;

	for (size_t k = 0; k < SSC_LIVE_TAUS; k++, m *= 10) {
		a->m[k] = m;
		a->sum2[k] = 0;
		a->n[k] = 0;
	}
	ssc_run_adev_break(a);
}

void ssc_run_adev_break(struct ssc_run_adev *a)
{
	for (size_t k = 0; k < SSC_LIVE_TAUS; k++) {
		a->block[k] = 0;
		a->filled[k] = 0;
		a->have_prev[k] = false;
	}
}

void ssc_run_adev_add(struct ssc_run_adev *a, double x)
{
	for (size_t k = 0; k < SSC_LIVE_TAUS; k++) {
		a->block[k] += x;
		if (++a->filled[k] < a->m[k])
			continue;
		{
			double avg = a->block[k] / (double)a->m[k];

			if (a->have_prev[k]) {
				double d = avg - a->prev[k];

				a->sum2[k] += d * d;
				a->n[k]++;
			}
			a->prev[k] = avg;
			a->have_prev[k] = true;
			a->block[k] = 0;
			a->filled[k] = 0;
		}
	}
}

double ssc_run_adev_get(const struct ssc_run_adev *a, size_t k)
{
	if (k >= SSC_LIVE_TAUS || a->n[k] == 0)
		return (double)NAN;
	return sqrt(a->sum2[k] / (2.0 * (double)a->n[k]));
}

double ssc_source_late_rms(const struct ssc_source_counts *c)
{
	return c->late_n ? sqrt(c->late_sum2_s2 / (double)c->late_n) : (double)NAN;
}
