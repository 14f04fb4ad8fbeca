/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Clipped data (see sscope-clip.h): one pass keeps, for each side, the
 * extreme, the next distinct value inward and how many samples equal
 * each; a side is clipped when its extreme holds at least min_count
 * samples and more than ratio times the next value's.  The bound on an
 * unclipped signal is the arcsine density's (a sine's) largest ratio of
 * its outermost code to the next, 2.41; noise has tails that fall.
 * Blocks of samples that all lie strictly between the two runners-up are
 * skipped after a branch-free look at their extremes: they could change
 * nothing.
 */
#include "internal.h"

#include <math.h>

#include "sscope-clip.h"

/* samples whose extremes are looked at before the exact pass */
#define CLIP_BLOCK 512

static void top2_add(struct ssc_top2 *t, double x)
{
	if (x > t->v) {
		t->next = t->v;
		t->n_next = t->n;
		t->v = x;
		t->n = 1;
	} else if (x == t->v) {
		t->n++;
	} else if (x > t->next) {
		t->next = x;
		t->n_next = 1;
	} else if (x == t->next) {
		t->n_next++;
	}
}

void ssc_clip_init(struct ssc_clip_acc *a)
{
	a->hi = (struct ssc_top2){ -INFINITY, -INFINITY, 0, 0 };
	a->lo = (struct ssc_top2){ -INFINITY, -INFINITY, 0, 0 };
}

void ssc_clip_feed(struct ssc_clip_acc *a, const double *x, size_t stride,
		   size_t n)
{
	struct ssc_top2 hi = a->hi, lo = a->lo;

	for (size_t i0 = 0; i0 < n; i0 += CLIP_BLOCK) {
		size_t i1 = n - i0 < CLIP_BLOCK ? n : i0 + CLIP_BLOCK;

		/* a block strictly inside both runners-up changes nothing:
		 * its extremes (branch-free, four chains) tell */
		if (isfinite(hi.next) && isfinite(lo.next)) {
			double mx[4] = { -INFINITY, -INFINITY, -INFINITY, -INFINITY };
			double mn[4] = { INFINITY, INFINITY, INFINITY, INFINITY };
			size_t i = i0;

			for (; i + 4 <= i1; i += 4)
				for (int k = 0; k < 4; k++) {
					double v = x[(i + (size_t)k) * stride];

					mx[k] = v > mx[k] ? v : mx[k];
					mn[k] = v < mn[k] ? v : mn[k];
				}
			for (; i < i1; i++) {
				double v = x[i * stride];

				mx[0] = v > mx[0] ? v : mx[0];
				mn[0] = v < mn[0] ? v : mn[0];
			}
			for (int k = 1; k < 4; k++) {
				mx[0] = mx[k] > mx[0] ? mx[k] : mx[0];
				mn[0] = mn[k] < mn[0] ? mn[k] : mn[0];
			}
			if (mx[0] < hi.next && -mn[0] < lo.next)
				continue;
		}
		for (size_t i = i0; i < i1; i++) {
			double v = x[i * stride];

			if (!isfinite(v))
				continue;
			top2_add(&hi, v);
			top2_add(&lo, -v); /* the bottom, mirrored */
		}
	}
	a->hi = hi;
	a->lo = lo;
}

int ssc_clip_finish(const struct ssc_clip_acc *a, size_t min_count,
		    double ratio, struct sscope_clip *c)
{
	const struct ssc_top2 *hi = &a->hi, *lo = &a->lo;

	if (hi->n == 0)
		return -EDOM;
	c->hi = hi->v;
	c->lo = -lo->v;
	c->n_hi = hi->n;
	c->n_lo = lo->n;
	c->n_hi_next = hi->n_next;
	c->n_lo_next = lo->n_next;
	c->high = hi->n_next && hi->n >= min_count &&
		  (double)hi->n > ratio * (double)hi->n_next;
	c->low = lo->n_next && lo->n >= min_count &&
		 (double)lo->n > ratio * (double)lo->n_next;
	return 0;
}

bool ssc_clip_args_ok(size_t min_count, double ratio)
{
	return min_count >= 2 && ratio > 1 && isfinite(ratio);
}

int sscope_clip_detect(const double *x, size_t stride, size_t n,
		       size_t min_count, double ratio, struct sscope_clip *c)
{
	struct ssc_clip_acc a;

	if (!x || !c || stride == 0 || !ssc_clip_args_ok(min_count, ratio))
		return -EINVAL;
	ssc_clip_init(&a);
	ssc_clip_feed(&a, x, stride, n);
	return ssc_clip_finish(&a, min_count, ratio, c);
}
