/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Plot layout: data limits, "nice" linear ticks (Heckbert, "Nice numbers
 * for graph labels", Graphics Gems, 1990), decade ticks on log axes, margins
 * aligned across a grid of axes, dashes, pixel-column decimation of long
 * series (first/min/max/last per column, so a million-sample trace keeps
 * its envelope), legends and notes in a panel beside the axes, outside the
 * data.  The figure is laid out with the text metrics of its surface
 * (canvas.h) and drawn through it: SVG (svg.c) always, PNG through the
 * OpenCV canvas (cvshim.cpp) when built with OpenCV, else
 * ssc_fig_save_png() returns -ENOTSUP.
 */
#include "config.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cli.h"
#include "canvas.h"
#include "plot.h"
#ifdef HAVE_OPENCV
#include "cvshim.h"
#endif

static const uint32_t palette[] = { 0x1f77b4, 0xff7f0e, 0x2ca02c, 0xd62728,
				    0x9467bd, 0x8c564b, 0xe377c2, 0x7f7f7f,
				    0xbcbd22, 0x17becf };

uint32_t ssc_plot_color(size_t k)
{
	return palette[k % (sizeof(palette) / sizeof(palette[0]))];
}

enum kind { IT_LINE, IT_ERRBAR, IT_BAND, IT_VLINE, IT_HLINE, IT_TEXT, IT_NOTE,
	    IT_IMAGE };

struct item {
	enum kind kind;
	struct ssc_style st;
	char *label;
	size_t n;
	double *x, *y, *lo, *hi;
	double alpha;
	char *text;
	int align;
	enum ssc_legend_pos pos;
	/* image */
	double *z;
	size_t nx, ny;
	double x0, x1, y0, y1, zlo, zhi;
	bool zlog;
};

struct ssc_ax {
	char *title, *xlabel, *ylabel;
	bool logx, logy, grid;
	bool xlim_set, ylim_set;
	double xlo, xhi, ylo, yhi;
	enum ssc_legend_pos legend;
	struct item *items;
	size_t n_items, cap;
	size_t next_color;
};

struct ssc_fig {
	int w, h, rows, cols;
	char *title;
	struct ssc_ax *axes;
};

/* ------------------------------------------------------------ building */

struct ssc_fig *ssc_fig_new(int w, int h, int rows, int cols)
{
	struct ssc_fig *f;

	if (w < 100 || h < 100 || rows < 1 || cols < 1 || rows > 16 || cols > 16)
		return NULL;
	f = calloc(1, sizeof(*f));
	if (!f)
		return NULL;
	f->axes = calloc((size_t)(rows * cols), sizeof(*f->axes));
	if (!f->axes) {
		free(f);
		return NULL;
	}
	f->w = w;
	f->h = h;
	f->rows = rows;
	f->cols = cols;
	for (int i = 0; i < rows * cols; i++)
		f->axes[i].grid = true;
	return f;
}

static void free_item(struct item *it)
{
	free(it->label);
	free(it->x);
	free(it->y);
	free(it->lo);
	free(it->hi);
	free(it->text);
	free(it->z);
}

void ssc_fig_free(struct ssc_fig *f)
{
	if (!f)
		return;
	for (int i = 0; i < f->rows * f->cols; i++) {
		struct ssc_ax *ax = &f->axes[i];

		for (size_t k = 0; k < ax->n_items; k++)
			free_item(&ax->items[k]);
		free(ax->items);
		free(ax->title);
		free(ax->xlabel);
		free(ax->ylabel);
	}
	free(f->axes);
	free(f->title);
	free(f);
}

static void set_str(char **dst, const char *s)
{
	free(*dst);
	*dst = s ? strdup(s) : NULL;
}

void ssc_fig_title(struct ssc_fig *f, const char *t)
{
	set_str(&f->title, t);
}

struct ssc_ax *ssc_fig_ax(struct ssc_fig *f, int row, int col)
{
	if (!f || row < 0 || col < 0 || row >= f->rows || col >= f->cols)
		return NULL;
	return &f->axes[row * f->cols + col];
}

void ssc_ax_title(struct ssc_ax *ax, const char *t)
{
	set_str(&ax->title, t);
}

void ssc_ax_xlabel(struct ssc_ax *ax, const char *t)
{
	set_str(&ax->xlabel, t);
}

void ssc_ax_ylabel(struct ssc_ax *ax, const char *t)
{
	set_str(&ax->ylabel, t);
}

void ssc_ax_log(struct ssc_ax *ax, bool logx, bool logy)
{
	ax->logx = logx;
	ax->logy = logy;
}

void ssc_ax_xlim(struct ssc_ax *ax, double lo, double hi)
{
	ax->xlim_set = lo < hi;
	ax->xlo = lo;
	ax->xhi = hi;
}

void ssc_ax_ylim(struct ssc_ax *ax, double lo, double hi)
{
	ax->ylim_set = lo < hi;
	ax->ylo = lo;
	ax->yhi = hi;
}

void ssc_ax_legend(struct ssc_ax *ax, enum ssc_legend_pos pos)
{
	ax->legend = pos;
}

void ssc_ax_grid(struct ssc_ax *ax, bool on)
{
	ax->grid = on;
}

static struct item *new_item(struct ssc_ax *ax, enum kind kind,
			     const struct ssc_style *st, const char *label)
{
	struct item *it;

	if (ax->n_items == ax->cap) {
		size_t nc = ax->cap ? 2 * ax->cap : 8;
		struct item *ni = realloc(ax->items, nc * sizeof(*ni));

		if (!ni)
			return NULL;
		ax->items = ni;
		ax->cap = nc;
	}
	it = &ax->items[ax->n_items];
	memset(it, 0, sizeof(*it));
	it->kind = kind;
	if (st)
		it->st = *st;
	if (it->st.width == 0)
		it->st.width = 2;
	if (it->st.marker_size == 0)
		it->st.marker_size = 7;
	if (it->st.color == 0 && kind != IT_TEXT && kind != IT_NOTE)
		it->st.color = ssc_plot_color(ax->next_color++);
	if (label) {
		it->label = strdup(label);
		if (!it->label)
			return NULL;
	}
	ax->n_items++;
	return it;
}

static double *dup_arr(const double *a, size_t n)
{
	double *d;

	if (!a)
		return NULL;
	d = malloc((n ? n : 1) * sizeof(double));
	if (d)
		memcpy(d, a, n * sizeof(double));
	return d;
}

/* Long series are reduced when added: LINE_BUCKETS runs of consecutive
 * points keep their first, minimum, maximum and last point (in order) and
 * the first invalid point, so the envelope and the breaks survive at any
 * figure width below LINE_BUCKETS pixels; the drawing decimates again per
 * pixel column.  A day at 100 Hz is then 16k points instead of 8.6M. */
#define LINE_BUCKETS SSC_PLOT_LINE_BINS

#define SSC_PCLONES SSC_TARGET_CLONES("avx2", "default")

/* the first i in [i0, i1) whose shown value is v (there is one) */
static inline size_t first_eq(const double *y, size_t i0, size_t i1,
			      double off, double sc, bool same, double v)
{
	size_t i = i0;
#if defined(__GNUC__)
	typedef double pv4 __attribute__((vector_size(32)));
	typedef long long pv4i __attribute__((vector_size(32)));

	for (; i + 4 <= i1; i += 4) {
		pv4 w;
		pv4i m;

		memcpy(&w, y + i, sizeof(w));
		if (!same)
			w = (w - off) / sc;
		m = (pv4i)(w == v);
		if (m[0] | m[1] | m[2] | m[3])
			break;
	}
#endif
	while ((same ? y[i] : (y[i] - off) / sc) != v)
		i++;
	return i;
}

/* A bucket [i0, i1) whose points are all finite (x_ok: its x are known
 * to be): the first indices of
 * its smallest and largest shown value, from the extremes found first
 * without branches (on vectors) and then looked up; false (nothing
 * found) when a point is not finite, for the exact pass.  Same indices as
 * that pass: it keeps the first of equal values. */
SSC_PCLONES static bool bucket_fast(const double *x, bool x_ok,
				    const double *y, size_t i0, size_t i1,
				    double off, double sc, bool same,
				    size_t *imin, size_t *imax)
{
	double lo, hi, zs;
	size_t i = i0;
#if defined(__GNUC__)
	typedef double pv4 __attribute__((vector_size(32)));
	typedef long long pv4i __attribute__((vector_size(32)));
	const pv4 inf = { INFINITY, INFINITY, INFINITY, INFINITY };
	pv4 mn = inf, mx = -inf, z = { 0, 0, 0, 0 };

	for (; i + 4 <= i1; i += 4) {
		pv4 v, t;
		pv4i m;

		memcpy(&v, y + i, sizeof(v));
		if (!same)
			v = (v - off) / sc;
		/* 0 * v and 0 * x are NaN for an infinity or a NaN */
		z += 0 * v;
		if (!x_ok) {
			memcpy(&t, x + i, sizeof(t));
			z += 0 * t;
		}
		m = (pv4i)(v < mn);
		mn = (pv4)(((pv4i)v & m) | ((pv4i)mn & ~m));
		m = (pv4i)(v > mx);
		mx = (pv4)(((pv4i)v & m) | ((pv4i)mx & ~m));
	}
	zs = (z[0] + z[1]) + (z[2] + z[3]);
	lo = mn[0] < mn[1] ? mn[0] : mn[1];
	lo = mn[2] < lo ? mn[2] : lo;
	lo = mn[3] < lo ? mn[3] : lo;
	hi = mx[0] > mx[1] ? mx[0] : mx[1];
	hi = mx[2] > hi ? mx[2] : hi;
	hi = mx[3] > hi ? mx[3] : hi;
#else
	zs = 0;
	lo = INFINITY;
	hi = -INFINITY;
#endif
#define SHOWN(j) (same ? y[j] : (y[j] - off) / sc)
	for (; i < i1; i++) {
		double v = SHOWN(i);

		zs += 0 * v + (x_ok ? 0 : 0 * x[i]);
		lo = v < lo ? v : lo;
		hi = v > hi ? v : hi;
	}
	if (zs != 0)
		return false;
	*imin = first_eq(y, i0, i1, off, sc, same, lo);
	*imax = first_eq(y, i0, i1, off, sc, same, hi);
#undef SHOWN
	return true;
}

/* The largest double whose shown value is v (that of a, shown as
 * (y - off) / sc, sc > 0), stepping up from a; a itself when it is alone
 * with v; NaN when more than a few are (a wide offset). */
static double shown_top(double a, double off, double sc, double v)
{
	for (int k = 0; k < 8; k++) {
		double u = nextafter(a, INFINITY);

		if ((u - off) / sc != v)
			return a;
		a = u;
	}
	return NAN;
}

/* as shown_top(), stepping down */
static double shown_bottom(double a, double off, double sc, double v)
{
	for (int k = 0; k < 8; k++) {
		double u = nextafter(a, -INFINITY);

		if ((u - off) / sc != v)
			return a;
		a = u;
	}
	return NAN;
}

/* bucket_fast()'s indices from the bucket's envelope e, found beforehand:
 * (y - off) / sc with sc > 0 rounds monotonically, so the smallest shown
 * value is that of the smallest sample, and it first shows where the first
 * sample at most the largest double shown as it lies (the first sample
 * equal to the smallest, unless a neighbouring double is shown the same);
 * the same for the largest.  False (nothing found) when a point is not
 * finite or the scale is not positive, for the other passes. */
static bool bucket_envelope(const struct sscope_clip_envelope *e,
			    const double *y, size_t i0, size_t i1, double off,
			    double sc, bool same, size_t *imin, size_t *imax)
{
	double vlo, vhi, top, bottom;
	size_t i;

	if (e->n_nan || !isfinite(e->lo) || !isfinite(e->hi) ||
	    e->i_lo < i0 || e->i_lo >= i1 || e->i_hi < i0 || e->i_hi >= i1)
		return false;
	if (same) {
		*imin = e->i_lo;
		*imax = e->i_hi;
		return true;
	}
	if (!(sc > 0))
		return false;
	vlo = (e->lo - off) / sc;
	vhi = (e->hi - off) / sc;
	if (!isfinite(vlo) || !isfinite(vhi))
		return false;
	top = shown_top(e->lo, off, sc, vlo);
	bottom = shown_bottom(e->hi, off, sc, vhi);
	if (isnan(top))
		*imin = first_eq(y, i0, i1, off, sc, same, vlo);
	else if (top == e->lo)
		*imin = e->i_lo;
	else
		for (*imin = i = i0; y[i] > top; *imin = ++i)
			;
	if (isnan(bottom))
		*imax = first_eq(y, i0, i1, off, sc, same, vhi);
	else if (bottom == e->hi)
		*imax = e->i_hi;
	else
		for (*imax = i = i0; y[i] < bottom; *imax = ++i)
			;
	return true;
}

/* y shown as (y - off) / sc (a unit conversion); env: y's envelope in
 * LINE_BUCKETS bins, or NULL */
static int line_reduced(struct item *it, const double *x, const bool *x_fin,
			const double *y, size_t n, double off, double sc,
			const struct sscope_clip_envelope *env)
{
	size_t cap = 5 * LINE_BUCKETS, m = 0;
	bool same = off == 0 && sc == 1;

	it->x = malloc(cap * sizeof(double));
	it->y = malloc(cap * sizeof(double));
	if (!it->x || !it->y)
		return -ENOMEM;
	for (size_t b = 0; b < LINE_BUCKETS; b++) {
		size_t i0 = n * b / LINE_BUCKETS, i1 = n * (b + 1) / LINE_BUCKETS;
		size_t imin = SIZE_MAX, imax = SIZE_MAX, ibad = SIZE_MAX;
		size_t keep[5], nk = 0;
		double ymin = 0, ymax = 0;

		if (i0 >= i1)
			continue;
		if (env && x_fin && x_fin[b] &&
		    bucket_envelope(&env[b], y, i0, i1, off, sc, same, &imin,
				    &imax))
			goto kept;
		if ((!x_fin || x_fin[b]) &&
		    bucket_fast(x, x_fin != NULL, y, i0, i1, off, sc, same, &imin,
				&imax))
			goto kept;
		for (size_t i = i0; i < i1; i++) {
			double v = same ? y[i] : (y[i] - off) / sc;

			if (!isfinite(x[i]) || !isfinite(v)) {
				if (ibad == SIZE_MAX)
					ibad = i;
				continue;
			}
			if (imin == SIZE_MAX || v < ymin) {
				imin = i;
				ymin = v;
			}
			if (imax == SIZE_MAX || v > ymax) {
				imax = i;
				ymax = v;
			}
		}
kept:
		keep[nk++] = i0;
		if (imin != SIZE_MAX)
			keep[nk++] = imin;
		if (imax != SIZE_MAX)
			keep[nk++] = imax;
		if (ibad != SIZE_MAX)
			keep[nk++] = ibad;
		keep[nk++] = i1 - 1;
		/* in index order, without repeats */
		for (size_t a = 1; a < nk; a++)
			for (size_t c = a; c > 0 && keep[c - 1] > keep[c]; c--) {
				size_t t = keep[c];

				keep[c] = keep[c - 1];
				keep[c - 1] = t;
			}
		for (size_t a = 0; a < nk; a++) {
			if (a && keep[a] == keep[a - 1])
				continue;
			it->x[m] = x[keep[a]];
			it->y[m] = (y[keep[a]] - off) / sc;
			m++;
		}
	}
	it->n = m;
	return 0;
}

bool *ssc_line_x_finite(const double *x, size_t n)
{
	bool *fin;

	if (!x || n <= 8 * LINE_BUCKETS)
		return NULL;
	fin = malloc(LINE_BUCKETS * sizeof(*fin));
	if (!fin)
		return NULL;
	for (size_t b = 0; b < LINE_BUCKETS; b++) {
		size_t i0 = n * b / LINE_BUCKETS, i1 = n * (b + 1) / LINE_BUCKETS;
		double z[4] = { 0, 0, 0, 0 };
		size_t i = i0;

		/* 0 * x is NaN for an infinity or a NaN */
		for (; i + 4 <= i1; i += 4)
			for (int k = 0; k < 4; k++)
				z[k] += 0 * x[i + (size_t)k];
		for (; i < i1; i++)
			z[0] += 0 * x[i];
		fin[b] = (z[0] + z[1]) + (z[2] + z[3]) == 0;
	}
	return fin;
}

int ssc_ax_line_scaled(struct ssc_ax *ax, const double *x, const double *y,
		       size_t n, double offset, double scale,
		       const struct ssc_style *st, const char *label)
{
	return ssc_ax_line_scaled_x(ax, x, NULL, y, n, offset, scale, st,
				    label);
}

int ssc_ax_line_scaled_x(struct ssc_ax *ax, const double *x,
			 const bool *x_finite, const double *y, size_t n,
			 double offset, double scale,
			 const struct ssc_style *st, const char *label)
{
	return ssc_ax_line_envelope_x(ax, x, x_finite, y, n, offset, scale,
				      NULL, st, label);
}

int ssc_ax_line_envelope_x(struct ssc_ax *ax, const double *x,
			   const bool *x_finite, const double *y, size_t n,
			   double offset, double scale,
			   const struct sscope_clip_envelope *env,
			   const struct ssc_style *st, const char *label)
{
	struct item *it = new_item(ax, IT_LINE, st, label);
	bool same = offset == 0 && scale == 1;

	if (!it)
		return -ENOMEM;
	if (n > 8 * LINE_BUCKETS && !ax->logx && !ax->logy && x && y)
		return line_reduced(it, x, x_finite, y, n, offset, scale, env);
	it->n = n;
	it->x = dup_arr(x, n);
	it->y = dup_arr(y, n);
	if (it->y && !same)
		for (size_t i = 0; i < n; i++)
			it->y[i] = (it->y[i] - offset) / scale;
	return (it->x && it->y) ? 0 : -ENOMEM;
}

int ssc_ax_line(struct ssc_ax *ax, const double *x, const double *y, size_t n,
		const struct ssc_style *st, const char *label)
{
	return ssc_ax_line_scaled(ax, x, y, n, 0, 1, st, label);
}

int ssc_ax_errorbar(struct ssc_ax *ax, const double *x, const double *y,
		    const double *lo, const double *hi, size_t n,
		    const struct ssc_style *st, const char *label)
{
	struct item *it = new_item(ax, IT_ERRBAR, st, label);

	if (!it)
		return -ENOMEM;
	it->n = n;
	it->x = dup_arr(x, n);
	it->y = dup_arr(y, n);
	it->lo = dup_arr(lo, n);
	it->hi = dup_arr(hi, n);
	return (it->x && it->y && it->lo && it->hi) ? 0 : -ENOMEM;
}

int ssc_ax_band(struct ssc_ax *ax, const double *x, const double *lo,
		const double *hi, size_t n, uint32_t color, double alpha,
		const char *label)
{
	struct ssc_style st = { .color = color };
	struct item *it = new_item(ax, IT_BAND, &st, label);

	if (!it)
		return -ENOMEM;
	it->n = n;
	it->alpha = alpha > 0 && alpha <= 1 ? alpha : 0.25;
	it->x = dup_arr(x, n);
	it->lo = dup_arr(lo, n);
	it->hi = dup_arr(hi, n);
	return (it->x && it->lo && it->hi) ? 0 : -ENOMEM;
}

static int add_rule(struct ssc_ax *ax, enum kind k, double v,
		    const struct ssc_style *st, const char *label)
{
	struct item *it = new_item(ax, k, st, label);

	if (!it)
		return -ENOMEM;
	it->n = 1;
	it->x = dup_arr(&v, 1);
	return it->x ? 0 : -ENOMEM;
}

int ssc_ax_vline(struct ssc_ax *ax, double x, const struct ssc_style *st,
		 const char *label)
{
	return add_rule(ax, IT_VLINE, x, st, label);
}

int ssc_ax_hline(struct ssc_ax *ax, double y, const struct ssc_style *st,
		 const char *label)
{
	return add_rule(ax, IT_HLINE, y, st, label);
}

int ssc_ax_text(struct ssc_ax *ax, double x, double y, const char *text,
		int align, uint32_t color)
{
	struct ssc_style st = { .color = color };
	struct item *it = new_item(ax, IT_TEXT, &st, NULL);

	if (!it)
		return -ENOMEM;
	it->n = 1;
	it->x = dup_arr(&x, 1);
	it->y = dup_arr(&y, 1);
	it->text = strdup(text);
	it->align = align;
	return (it->x && it->y && it->text) ? 0 : -ENOMEM;
}

int ssc_ax_note(struct ssc_ax *ax, const char *text, enum ssc_legend_pos pos)
{
	struct item *it = new_item(ax, IT_NOTE, NULL, NULL);

	if (!it)
		return -ENOMEM;
	it->text = strdup(text);
	it->pos = pos;
	return it->text ? 0 : -ENOMEM;
}

int ssc_ax_image(struct ssc_ax *ax, const double *z, size_t nx, size_t ny,
		 double x0, double x1, double y0, double y1, double zlo,
		 double zhi, bool zlog, const char *zlabel)
{
	struct item *it;

	if (!nx || !ny || nx > SIZE_MAX / ny || !(zlo < zhi) ||
	    (zlog && !(zlo > 0)))
		return -EINVAL;
	it = new_item(ax, IT_IMAGE, NULL, zlabel);
	if (!it)
		return -ENOMEM;
	it->z = dup_arr(z, nx * ny);
	it->nx = nx;
	it->ny = ny;
	it->x0 = x0;
	it->x1 = x1;
	it->y0 = y0;
	it->y1 = y1;
	it->zlo = zlo;
	it->zhi = zhi;
	it->zlog = zlog;
	return it->z ? 0 : -ENOMEM;
}

/* ------------------------------------------------------------ ticks */

static double nice(double x, bool round_)
{
	double e = floor(log10(x)), f = x / pow(10, e), nf;

	if (round_)
		nf = f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10;
	else
		nf = f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10;
	return nf * pow(10, e);
}

size_t ssc_ticks_linear(double lo, double hi, size_t target, double *ticks,
			size_t max, double *step_out)
{
	double step, first;
	size_t n = 0;

	if (!(hi > lo) || !isfinite(lo) || !isfinite(hi) || target < 2)
		return 0;
	step = nice((hi - lo) / (double)(target - 1), true);
	/* rounding the step up can leave one or two labels on the axis:
	 * the next smaller nice step (5 -> 2 -> 1 -> 0.5) until there are
	 * three, so a reader can interpolate */
	for (int pass = 0; pass < 4; pass++) {
		double m = step / pow(10, floor(log10(step) + 1e-9));

		first = ceil(lo / step - 1e-9) * step;
		if (target < 3 || first + 2 * step <= hi + step * 1e-9)
			break;
		step *= m > 4.5 ? 0.4 : 0.5;
	}
	for (size_t i = 0; n < max; i++) {
		double t = first + (double)i * step;

		if (t > hi + step * 1e-9)
			break;
		if (fabs(t) < step * 1e-9)
			t = 0;
		ticks[n++] = t;
	}
	if (step_out)
		*step_out = step;
	return n;
}

size_t ssc_ticks_log(double lo, double hi, double *major, size_t max_major,
		     double *minor, size_t max_minor, size_t *n_minor)
{
	size_t nm = 0, nn = 0;
	double a, b;

	if (!(lo > 0) || !(hi > lo))
		return 0;
	a = floor(log10(lo) + 1e-9);
	b = ceil(log10(hi) - 1e-9);
	for (double k = a; k <= b; k++) {
		double d = pow(10, k);

		if (d >= lo * (1 - 1e-9) && d <= hi * (1 + 1e-9) &&
		    nm < max_major)
			major[nm++] = d;
		for (int m = 2; m <= 9; m++) {
			double v = m * d;

			if (v >= lo && v <= hi && nn < max_minor)
				minor[nn++] = v;
		}
	}
	if (n_minor)
		*n_minor = nn;
	return nm;
}

/* ------------------------------------------------------------ rendering */

#define MAXT 64

struct axis {
	bool log;
	double lo, hi;
	double major[MAXT], minor[8 * MAXT];
	size_t nmaj, nmin;
	char labels[MAXT][40];
	bool show[MAXT];
	char mult[40]; /* "×10^{k}" multiplier, or "" */
};

struct layout {
	struct axis x, y;
	double left, right, top, bottom; /* margins needed */
	bool image;
	const struct item *img;
	double zmaj[MAXT];
	size_t nz;
	char zlabels[MAXT][40];
	double cbar_w;         /* colour bar and its labels */
	double side_w, side_h; /* legend and notes panel */
};

struct render {
	const struct ssc_surface *S;
	double fs;             /* base font size px */
	double px, py, pw, ph; /* plot rectangle */
	struct layout *L;
};

/* Sizes relative to the base font size. */
#define FS_TICK 0.9
#define FS_LEGEND 0.9
#define FS_NOTE 0.9
#define FS_TEXT 0.85
#define SIDE_GAP 16 /* plot (or colour bar) to the side panel, px */
#define SAMPLE_W 30 /* legend sample line */

static double tx(const struct axis *a, double v)
{
	return a->log ? log10(v) : v;
}

static double X(const struct render *r, double v)
{
	const struct axis *a = &r->L->x;

	return r->px + (tx(a, v) - tx(a, a->lo)) / (tx(a, a->hi) - tx(a, a->lo)) *
			       r->pw;
}

static double Y(const struct render *r, double v)
{
	const struct axis *a = &r->L->y;

	return r->py + r->ph -
	       (tx(a, v) - tx(a, a->lo)) / (tx(a, a->hi) - tx(a, a->lo)) * r->ph;
}

static bool ok_val(const struct axis *a, double v)
{
	return isfinite(v) && (!a->log || v > 0);
}

/* ---- text through the surface */

static double text_w(const struct ssc_surface *S, const char *t, double fs)
{
	return S->ops->text_width(S->ctx, t, fs);
}

static void text_at(const struct ssc_surface *S, double x, double y,
		    const char *t, double fs, uint32_t color, int align)
{
	S->ops->text(S->ctx, x, y, t, fs, color, align, 0);
}

static void group(const struct ssc_surface *S, const char *cls,
		  const char *attrs)
{
	S->ops->group(S->ctx, cls, attrs);
}

static void line2(const struct ssc_surface *S, double x0, double y0,
		  double x1, double y1, uint32_t color, double width)
{
	double p[4] = { x0, y0, x1, y1 };

	S->ops->polyline(S->ctx, p, 2, color, width, NULL);
}

/* Split text at '\n' and break lines wider than maxw at spaces outside
 * markup braces; a word wider than maxw stays whole on its line. */
static size_t wrap(const struct ssc_surface *S, const char *t, double fs,
		   double maxw, char lines[][160], size_t max)
{
	size_t n = 0;

	while (t && *t && n < max) {
		const char *e = strchr(t, '\n');
		size_t len = e ? (size_t)(e - t) : strlen(t), start = 0;
		char para[160];

		if (len > 159)
			len = 159;
		memcpy(para, t, len);
		para[len] = '\0';
		while (n < max) {
			size_t best = 0, depth = 0;
			char cand[160];

			/* the longest prefix ending before a space that fits */
			for (size_t i = start; i <= len; i++) {
				if (para[i] == '{')
					depth++;
				else if (para[i] == '}' && depth)
					depth--;
				if ((para[i] == ' ' && !depth) || i == len) {
					memcpy(cand, para + start, i - start);
					cand[i - start] = '\0';
					if (best && text_w(S, cand, fs) > maxw)
						break;
					best = i;
					if (i == len)
						break;
				}
			}
			if (!best)
				best = len;
			memcpy(lines[n], para + start, best - start);
			lines[n][best - start] = '\0';
			n++;
			start = best;
			while (start < len && para[start] == ' ')
				start++;
			if (start >= len)
				break;
		}
		if (!e)
			break;
		t = e + 1;
	}
	return n;
}

/* ---- limits and ticks */

static void data_range(const struct ssc_ax *ax, bool want_x, bool logv,
		       double *lo, double *hi, bool *img)
{
	*lo = INFINITY;
	*hi = -INFINITY;
	*img = false;
#define TAKE(v)                                                  \
	do {                                                     \
		double v_ = (v);                                 \
		if (isfinite(v_) && (!logv || v_ > 0)) {         \
			if (v_ < *lo)                            \
				*lo = v_;                        \
			if (v_ > *hi)                            \
				*hi = v_;                        \
		}                                                \
	} while (0)
	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];

		switch (it->kind) {
		case IT_LINE:
			for (size_t i = 0; i < it->n; i++)
				if (isfinite(it->x[i]) && isfinite(it->y[i]))
					TAKE(want_x ? it->x[i] : it->y[i]);
			break;
		case IT_ERRBAR:
			for (size_t i = 0; i < it->n; i++) {
				if (want_x) {
					TAKE(it->x[i]);
				} else {
					TAKE(it->y[i]);
					TAKE(it->lo[i]);
					TAKE(it->hi[i]);
				}
			}
			break;
		case IT_BAND:
			for (size_t i = 0; i < it->n; i++) {
				if (want_x) {
					TAKE(it->x[i]);
				} else {
					TAKE(it->lo[i]);
					TAKE(it->hi[i]);
				}
			}
			break;
		case IT_VLINE:
			if (want_x)
				TAKE(it->x[0]);
			break;
		case IT_HLINE:
			if (!want_x)
				TAKE(it->x[0]);
			break;
		case IT_IMAGE:
			*img = true;
			TAKE(want_x ? it->x0 : it->y0);
			TAKE(want_x ? it->x1 : it->y1);
			break;
		default:
			break;
		}
	}
#undef TAKE
}

static void fmt_linear(struct axis *a, double step)
{
	double m = 0;
	int e = 0, dec;

	for (size_t i = 0; i < a->nmaj; i++)
		if (fabs(a->major[i]) > m)
			m = fabs(a->major[i]);
	a->mult[0] = '\0';
	if (m >= 1e5 || (m > 0 && m < 1e-3)) {
		e = (int)floor(log10(m));
		snprintf(a->mult, sizeof(a->mult), "\xc3\x97" "10^{%d}", e);
	}
	step /= pow(10, e);
	dec = (int)ceil(-log10(step) - 1e-9);
	if (dec < 0)
		dec = 0;
	if (dec > 12)
		dec = 12;
	for (size_t i = 0; i < a->nmaj; i++) {
		double v = a->major[i] / pow(10, e);

		snprintf(a->labels[i], sizeof(a->labels[i]), "%.*f", dec, v);
		if (!strncmp(a->labels[i], "-0", 2) && strspn(a->labels[i] + 1, "0.") ==
							     strlen(a->labels[i] + 1))
			memmove(a->labels[i], a->labels[i] + 1,
				strlen(a->labels[i]));
		a->show[i] = true;
	}
}

/* Label of a tick m x 10^k on a log axis: plain from 0.01 to 1000 (and
 * from 10^-3 when plain is asked for), else 10^{k} or m×10^{k}. */
static void log_label(char *buf, size_t len, double v, bool plain)
{
	int k = (int)floor(log10(v) + 1e-9);
	int m = (int)lround(v / pow(10, k));

	if (m >= 10) {
		m /= 10;
		k++;
	}
	if (k >= (plain ? -3 : -2) && k <= 3)
		snprintf(buf, len, "%.*f", k < 0 ? -k : 0, m * pow(10, k));
	else if (m == 1)
		snprintf(buf, len, "10^{%d}", k);
	else
		snprintf(buf, len, "%d\xc3\x97" "10^{%d}", m, k);
}

static void make_axis(struct axis *a, bool logv, bool set, double slo,
		      double shi, double dlo, double dhi, bool pad, bool img,
		      double px_len, double px_per_tick)
{
	size_t target = (size_t)(px_len / px_per_tick);
	double step = 1;

	if (target < 3)
		target = 3;
	a->log = logv;
	if (set) {
		a->lo = slo;
		a->hi = shi;
	} else if (!(dlo <= dhi)) {
		a->lo = logv ? 1 : 0;
		a->hi = logv ? 10 : 1;
	} else if (logv) {
		a->lo = pow(10, floor(log10(dlo) + 1e-9));
		a->hi = pow(10, ceil(log10(dhi) - 1e-9));
		if (a->hi <= a->lo)
			a->hi = a->lo * 10;
	} else {
		double span = dhi - dlo;

		if (span <= 0)
			span = dlo != 0 ? fabs(dlo) * 0.2 : 1;
		a->lo = dlo;
		a->hi = dhi;
		if (dhi == dlo) {
			a->lo -= span / 2;
			a->hi += span / 2;
		}
		if (pad && !img) {
			a->lo -= 0.05 * span;
			a->hi += 0.05 * span;
		}
	}
	a->mult[0] = '\0';
	if (logv && a->lo > 0 && a->hi > a->lo) {
		double decades = log10(a->hi / a->lo);

		a->nmaj = ssc_ticks_log(a->lo, a->hi, a->major, MAXT, a->minor,
					8 * MAXT, &a->nmin);
		if (a->nmaj >= 2 && decades > 2.6) {
			size_t every = 1;

			while (a->nmaj / every > target + 1)
				every++;
			for (size_t i = 0; i < a->nmaj; i++) {
				int k = (int)lround(log10(a->major[i]));

				log_label(a->labels[i], 40, a->major[i], false);
				a->show[i] = (k % (int)every) == 0;
			}
			return;
		}
		/* up to about two decades: 1-2-5 ticks, labelled, so a
		 * reader finds values without counting minor ticks */
		{
			double all[MAXT];
			size_t n = 0, i = 0, j = 0;

			for (size_t k = 0; k < a->nmin && n < MAXT; k++) {
				double m = a->minor[k] /
					   pow(10, floor(log10(a->minor[k]) + 1e-9));

				if (fabs(m - 2) < 1e-6 || fabs(m - 5) < 1e-6)
					all[n++] = a->minor[k];
			}
			/* merge the decades and the 2s and 5s in order */
			{
				double merged[MAXT];
				size_t nm = 0;

				while ((i < a->nmaj || j < n) && nm < MAXT) {
					if (j >= n || (i < a->nmaj &&
						       a->major[i] < all[j]))
						merged[nm++] = a->major[i++];
					else
						merged[nm++] = all[j++];
				}
				memcpy(a->major, merged, nm * sizeof(double));
				a->nmaj = nm;
			}
		}
		for (size_t i = 0; i < a->nmaj; i++) {
			log_label(a->labels[i], 40, a->major[i], true);
			a->show[i] = true;
		}
		return;
	}
	a->log = false;
	a->nmin = 0;
	a->nmaj = ssc_ticks_linear(a->lo, a->hi, target, a->major, MAXT, &step);
	fmt_linear(a, step);
}

/* Widest text a legend or note may have before it wraps. */
static double side_text_max(double cw)
{
	return fmax(160, 0.27 * cw);
}

/* Size of the legend box and of each note box in the side panel. */
static void side_boxes(const struct ssc_surface *S, const struct ssc_ax *ax,
		       double fs, double cw, double *legend_w, double *legend_h,
		       size_t *n_legend, double *note_w, double *note_h)
{
	double fl = fs * FS_LEGEND, fn = fs * FS_NOTE, maxt = side_text_max(cw);
	char lines[16][160];
	size_t nl = 0;

	*legend_w = *legend_h = *note_w = *note_h = 0;
	*n_legend = 0;
	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];

		if (it->kind == IT_NOTE) {
			size_t n = wrap(S, it->text, fn, maxt, lines, 16);

			for (size_t i = 0; i < n; i++)
				*note_w = fmax(*note_w,
					       text_w(S, lines[i], fn) + 20);
			*note_h += fn * 1.4 * (double)n + 10 + 10;
			continue;
		}
		if (!it->label || it->kind == IT_IMAGE ||
		    ax->legend == SSC_LEGEND_NONE)
			continue;
		{
			size_t n = wrap(S, it->label, fl, maxt, lines, 16);

			for (size_t i = 0; i < n; i++)
				*legend_w = fmax(*legend_w,
						 10 + SAMPLE_W + 8 +
							 text_w(S, lines[i], fl) +
							 10);
			nl += n;
			(*n_legend)++;
		}
	}
	if (*n_legend)
		*legend_h = 8 + fl * 1.45 * (double)nl + 4;
}

/* The axes draws points without lines only (a scatter plot). */
static bool markers_only(const struct ssc_ax *ax)
{
	bool any = false;

	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];

		if (it->kind == IT_BAND || it->kind == IT_IMAGE ||
		    (it->kind == IT_LINE && it->st.width > 0))
			return false;
		if (it->kind == IT_LINE || it->kind == IT_ERRBAR)
			any = true;
	}
	return any;
}

static void plan(const struct ssc_surface *S, struct ssc_ax *ax,
		 struct layout *L, double cw, double ch, double fs)
{
	double dlo, dhi, w, maxw = 0, lw, lh, nw, nh;
	size_t nlg;
	bool img;

	memset(L, 0, sizeof(*L));
	data_range(ax, true, ax->logx, &dlo, &dhi, &img);
	/* markers alone would sit half outside a frame drawn at their ends */
	make_axis(&L->x, ax->logx, ax->xlim_set, ax->xlo, ax->xhi, dlo, dhi,
		  markers_only(ax), img, cw * 0.6, ax->logx ? 55 : 100);
	data_range(ax, false, ax->logy, &dlo, &dhi, &img);
	make_axis(&L->y, ax->logy, ax->ylim_set, ax->ylo, ax->yhi, dlo, dhi,
		  true, img, ch * 0.7, ax->logy ? 30 : 48);
	for (size_t i = 0; i < L->y.nmaj; i++) {
		w = text_w(S, L->y.labels[i], fs * FS_TICK);
		if (w > maxw)
			maxw = w;
	}
	L->left = 10 + maxw + 8 + 6 + (ax->ylabel ? fs * 1.3 + 6 : 0);
	L->bottom = 6 + 4 + fs * 1.2 + (ax->xlabel ? fs * 1.4 + 6 : 0) + 8;
	L->top = (ax->title ? fs * 1.8 : 0) + (L->y.mult[0] ? fs : 0) + 12;
	for (size_t k = 0; k < ax->n_items; k++)
		if (ax->items[k].kind == IT_IMAGE) {
			const struct item *it = &ax->items[k];
			double zmax = 0;

			L->image = true;
			L->img = it;
			if (it->zlog) {
				double mj[MAXT], mn[8 * MAXT];
				size_t nn;

				L->nz = ssc_ticks_log(it->zlo, it->zhi, mj, MAXT,
						      mn, 8 * MAXT, &nn);
				for (size_t i = 0; i < L->nz; i++) {
					L->zmaj[i] = mj[i];
					log_label(L->zlabels[i], 40, mj[i], false);
				}
			} else {
				struct axis za;
				double st;

				za.nmaj = ssc_ticks_linear(it->zlo, it->zhi, 6,
							   za.major, MAXT, &st);
				fmt_linear(&za, st);
				L->nz = za.nmaj;
				for (size_t i = 0; i < L->nz; i++) {
					L->zmaj[i] = za.major[i];
					memcpy(L->zlabels[i], za.labels[i], 40);
				}
			}
			for (size_t i = 0; i < L->nz; i++) {
				w = text_w(S, L->zlabels[i], fs * FS_TICK);
				if (w > zmax)
					zmax = w;
			}
			L->cbar_w = 16 + 16 + 8 + zmax + 10 +
				    (it->label ? fs * 1.3 : 0);
		}
	side_boxes(S, ax, fs, cw, &lw, &lh, &nlg, &nw, &nh);
	L->side_w = fmax(lw, nw);
	L->side_h = lh + (lh > 0 && nh > 0 ? 10 : 0) + nh;
	L->right = L->cbar_w + (L->side_w > 0 ? SIDE_GAP + L->side_w : 0) + 24;
}

/* ---- drawing primitives on the surface */

static const double dash_on_off[4][4] = {
	{ 0, 0, 0, 0 }, { 9, 5, 9, 5 }, { 2, 4, 2, 4 }, { 9, 4, 2, 4 }
};

/* Draw a polyline (pixel coords) with a dash pattern. */
static void stroke(const struct ssc_surface *S, const double *xy, size_t n,
		   uint32_t color, double width, enum ssc_dash dash)
{
	double seg[512 * 2];
	size_t ns = 0;
	int phase = 0;
	double left, scale = width > 1.5 ? width / 1.5 : 1;

	if (n < 2)
		return;
	if (dash == SSC_SOLID) {
		S->ops->polyline(S->ctx, xy, n, color, width, NULL);
		return;
	}
	if (S->native_dash) {
		double d[4];

		for (int i = 0; i < 4; i++)
			d[i] = dash_on_off[dash][i] * scale;
		S->ops->polyline(S->ctx, xy, n, color, width, d);
		return;
	}
	left = dash_on_off[dash][0] * scale;
	seg[0] = xy[0];
	seg[1] = xy[1];
	ns = 1;
	for (size_t i = 1; i < n; i++) {
		double x0 = xy[2 * i - 2], y0 = xy[2 * i - 1];
		double x1 = xy[2 * i], y1 = xy[2 * i + 1];
		double len = hypot(x1 - x0, y1 - y0), pos = 0;

		while (len - pos > left) {
			double t;

			pos += left;
			t = pos / len;
			if (!(phase & 1)) { /* end of an "on" piece */
				seg[2 * ns] = x0 + t * (x1 - x0);
				seg[2 * ns + 1] = y0 + t * (y1 - y0);
				ns++;
				S->ops->polyline(S->ctx, seg, ns, color, width,
						 NULL);
				ns = 0;
			} else { /* start of an "on" piece */
				seg[0] = x0 + t * (x1 - x0);
				seg[1] = y0 + t * (y1 - y0);
				ns = 1;
			}
			phase = (phase + 1) & 3;
			left = dash_on_off[dash][phase] * scale;
		}
		left -= len - pos;
		if (!(phase & 1)) {
			if (ns == 512) {
				S->ops->polyline(S->ctx, seg, ns, color, width,
						 NULL);
				seg[0] = seg[2 * ns - 2];
				seg[1] = seg[2 * ns - 1];
				ns = 1;
			}
			seg[2 * ns] = x1;
			seg[2 * ns + 1] = y1;
			ns++;
		}
	}
	if (!(phase & 1) && ns >= 2)
		S->ops->polyline(S->ctx, seg, ns, color, width, NULL);
}

static void marker(const struct ssc_surface *S, double x, double y,
		   enum ssc_marker m, double size, uint32_t color)
{
	double r = size / 2, p[8];

	switch (m) {
	case SSC_MK_CIRCLE:
		S->ops->circle(S->ctx, x, y, r, color, 1, 1);
		break;
	case SSC_MK_SQUARE:
		S->ops->rect(S->ctx, x - r, y - r, 2 * r, 2 * r, color, 1, 1);
		break;
	case SSC_MK_TRIANGLE:
	case SSC_MK_TRIANGLE_DOWN: {
		double sgn = m == SSC_MK_TRIANGLE ? 1 : -1;

		p[0] = x;
		p[1] = y - sgn * r * 1.15;
		p[2] = x + r;
		p[3] = y + sgn * r * 0.7;
		p[4] = x - r;
		p[5] = y + sgn * r * 0.7;
		S->ops->fill(S->ctx, p, 3, color, 1);
		break;
	}
	case SSC_MK_DIAMOND:
		p[0] = x;
		p[1] = y - r * 1.2;
		p[2] = x + r;
		p[3] = y;
		p[4] = x;
		p[5] = y + r * 1.2;
		p[6] = x - r;
		p[7] = y;
		S->ops->fill(S->ctx, p, 4, color, 1);
		break;
	case SSC_MK_CROSS:
		line2(S, x - r, y - r, x + r, y + r, color, 2);
		line2(S, x - r, y + r, x + r, y - r, color, 2);
		break;
	default:
		break;
	}
}

/* Emit a series in pixel space, broken at invalid points, decimated to
 * first/min/max/last per pixel column when much denser than the pixels. */
static void draw_series(struct render *r, const struct item *it)
{
	const struct axis *ax = &r->L->x, *ay = &r->L->y;
	size_t cap = 4096, n = 0;
	double *xy = malloc(cap * 2 * sizeof(double));
	bool decimate = it->n > (size_t)(4 * r->pw);
	long col = LONG_MIN;
	double cmin = 0, cmax = 0, cfirst = 0, clast = 0, cx = 0;
	bool have = false;

	if (!xy)
		return;
#define PUSH(X_, Y_)                                                       \
	do {                                                               \
		if (n == cap) {                                            \
			double *nx_ = realloc(xy, cap * 4 * sizeof(double)); \
			if (!nx_)                                          \
				goto out;                                  \
			xy = nx_;                                          \
			cap *= 2;                                          \
		}                                                          \
		xy[2 * n] = (X_);                                          \
		xy[2 * n + 1] = (Y_);                                      \
		n++;                                                       \
	} while (0)
#define FLUSH_COL()                                                  \
	do {                                                         \
		if (have) {                                          \
			PUSH(cx, cfirst);                            \
			if (cmin != cfirst && cmin != clast)         \
				PUSH(cx, cmin);                      \
			if (cmax != cfirst && cmax != clast)         \
				PUSH(cx, cmax);                      \
			if (clast != cfirst)                         \
				PUSH(cx, clast);                     \
			have = false;                                \
		}                                                    \
	} while (0)
	for (size_t i = 0; i <= it->n; i++) {
		bool valid = i < it->n && ok_val(ax, it->x[i]) &&
			     ok_val(ay, it->y[i]);
		double px, py;

		if (!valid) {
			if (decimate)
				FLUSH_COL();
			if (it->st.width > 0)
				stroke(r->S, xy, n, it->st.color, it->st.width,
				       it->st.dash);
			n = 0;
			col = LONG_MIN;
			continue;
		}
		px = X(r, it->x[i]);
		py = Y(r, it->y[i]);
		if (!decimate) {
			PUSH(px, py);
			continue;
		}
		if (lround(px) != col) {
			FLUSH_COL();
			col = lround(px);
			cx = px;
			cfirst = cmin = cmax = clast = py;
			have = true;
		} else {
			if (py < cmin)
				cmin = py;
			if (py > cmax)
				cmax = py;
			clast = py;
		}
	}
	if (it->st.marker != SSC_MK_NONE && it->n <= 5000)
		for (size_t i = 0; i < it->n; i++)
			if (ok_val(ax, it->x[i]) && ok_val(ay, it->y[i]))
				marker(r->S, X(r, it->x[i]), Y(r, it->y[i]),
				       it->st.marker, it->st.marker_size,
				       it->st.color);
out:
	free(xy);
#undef PUSH
#undef FLUSH_COL
}

static void draw_errbar(struct render *r, const struct item *it)
{
	const struct axis *ax = &r->L->x, *ay = &r->L->y;

	for (size_t i = 0; i < it->n; i++) {
		double x, lo = it->lo[i], hi = it->hi[i];

		if (!ok_val(ax, it->x[i]))
			continue;
		x = X(r, it->x[i]);
		if (ay->log && !(lo > 0))
			lo = ay->lo * 1e-3;
		if (ok_val(ay, hi) && isfinite(lo)) {
			line2(r->S, x, Y(r, lo), x, Y(r, hi), it->st.color, 1.2);
			line2(r->S, x - 3.5, Y(r, hi), x + 3.5, Y(r, hi),
			      it->st.color, 1.2);
			line2(r->S, x - 3.5, Y(r, lo), x + 3.5, Y(r, lo),
			      it->st.color, 1.2);
		}
	}
	draw_series(r, it);
}

static void draw_band(struct render *r, const struct item *it)
{
	const struct axis *ax = &r->L->x, *ay = &r->L->y;
	double *p = malloc((2 * it->n + 2) * 2 * sizeof(double));
	size_t start = 0;

	if (!p)
		return;
	while (start < it->n) {
		size_t end = start, m = 0;

		while (end < it->n && ok_val(ax, it->x[end]) &&
		       ok_val(ay, it->lo[end]) && ok_val(ay, it->hi[end]))
			end++;
		if (end - start >= 2) {
			for (size_t i = start; i < end; i++) {
				p[2 * m] = X(r, it->x[i]);
				p[2 * m + 1] = Y(r, it->hi[i]);
				m++;
			}
			for (size_t i = end; i-- > start;) {
				p[2 * m] = X(r, it->x[i]);
				p[2 * m + 1] = Y(r, it->lo[i]);
				m++;
			}
			r->S->ops->fill(r->S->ctx, p, m, it->st.color,
					it->alpha);
		}
		start = end + 1;
	}
	free(p);
}

static void box(const struct ssc_surface *S, double x, double y, double w,
		double h, uint32_t bg)
{
	double p[8] = { x, y, x + w, y, x + w, y + h, x, y + h };

	S->ops->fill(S->ctx, p, 4, bg, 1);
	S->ops->rect(S->ctx, x, y, w, h, 0xb0b0b0, 1, 0);
}

/* The legend in the side panel, right of the plot: returns its height. */
static double draw_legend(struct render *r, const struct ssc_ax *ax,
			  double bx, double by, double bw, double cw)
{
	const struct ssc_surface *S = r->S;
	double fs = r->fs * FS_LEGEND, lh = fs * 1.45, y = by + 8, lw, lhh, nw,
	       nh;
	char lines[16][160];
	size_t n;

	side_boxes(S, ax, r->fs, cw, &lw, &lhh, &n, &nw, &nh);
	if (!n)
		return 0;
	group(S, "legend", NULL);
	box(S, bx, by, bw, lhh, 0xffffff);
	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];
		double x = bx + 10, yc = y + lh * 0.5;
		size_t nl;

		if (!it->label || it->kind == IT_IMAGE || it->kind == IT_NOTE)
			continue;
		nl = wrap(S, it->label, fs, side_text_max(cw), lines, 16);
		group(S, "legend-entry", NULL);
		if (it->kind == IT_BAND) {
			double p[8] = { x, yc - 6, x + SAMPLE_W, yc - 6,
					x + SAMPLE_W, yc + 6, x, yc + 6 };

			S->ops->fill(S->ctx, p, 4, it->st.color, it->alpha);
		} else {
			double p[4] = { x, yc, x + SAMPLE_W, yc };

			if (it->st.width > 0)
				stroke(S, p, 2, it->st.color, it->st.width,
				       it->st.dash);
			if (it->kind == IT_ERRBAR)
				line2(S, x + SAMPLE_W / 2.0, yc - 7,
				      x + SAMPLE_W / 2.0, yc + 7, it->st.color,
				      1.2);
			if (it->st.marker)
				marker(S, x + SAMPLE_W / 2.0, yc, it->st.marker,
				       it->st.marker_size, it->st.color);
		}
		for (size_t i = 0; i < nl; i++)
			text_at(S, x + SAMPLE_W + 8,
				y + lh * (double)i + lh * 0.5 + fs * 0.35,
				lines[i], fs, 0x202020, -1);
		group(S, NULL, NULL);
		y += lh * (double)nl;
	}
	group(S, NULL, NULL);
	return lhh;
}

/* A note box in the side panel: returns its height. */
static double draw_note(struct render *r, const struct item *it, double bx,
			double by, double bw, double cw)
{
	const struct ssc_surface *S = r->S;
	char lines[16][160];
	double fs = r->fs * FS_NOTE, lh = fs * 1.4, bh;
	size_t n = wrap(S, it->text, fs, side_text_max(cw), lines, 16);

	bh = lh * (double)n + 10;
	group(S, "note", NULL);
	box(S, bx, by, bw, bh, 0xfffff4);
	for (size_t i = 0; i < n; i++)
		text_at(S, bx + 10, by + 5 + lh * (double)i + lh * 0.72,
			lines[i], fs, 0x202020, -1);
	group(S, NULL, NULL);
	return bh;
}

static void draw_image(struct render *r, const struct item *it)
{
	size_t n = it->nx * it->ny;
	double *v = malloc(n * sizeof(double));
	double lo = it->zlog ? log10(it->zlo) : it->zlo;
	double hi = it->zlog ? log10(it->zhi) : it->zhi;
	double x0 = X(r, it->x0), x1 = X(r, it->x1), y0 = Y(r, it->y0),
	       y1 = Y(r, it->y1);

	if (!v)
		return;
	for (size_t i = 0; i < n; i++) {
		double z = it->z[i];

		if (it->zlog)
			z = z > 0 ? log10(z) : (double)NAN;
		v[i] = isfinite(z) ? (z - lo) / (hi - lo) : (double)NAN;
	}
	r->S->ops->image(r->S->ctx, fmin(x0, x1), fmin(y0, y1), fabs(x1 - x0),
			 fabs(y1 - y0), v, (int)it->nx, (int)it->ny);
	free(v);
}

static void draw_colorbar(struct render *r)
{
	const struct ssc_surface *S = r->S;
	const struct item *it = r->L->img;
	double bx = r->px + r->pw + 16, by = r->py, bw = 16, bh = r->ph;
	double v[256], lo, hi, fs = r->fs * FS_TICK, maxw = 0;

	group(S, "colorbar", NULL);
	for (int i = 0; i < 256; i++)
		v[i] = i / 255.0;
	S->ops->image(S->ctx, bx, by, bw, bh, v, 1, 256);
	S->ops->rect(S->ctx, bx, by, bw, bh, 0x000000, 1, 0);
	lo = it->zlog ? log10(it->zlo) : it->zlo;
	hi = it->zlog ? log10(it->zhi) : it->zhi;
	for (size_t i = 0; i < r->L->nz; i++) {
		double z = it->zlog ? log10(r->L->zmaj[i]) : r->L->zmaj[i];
		double y = by + bh - (z - lo) / (hi - lo) * bh, w;

		line2(S, bx + bw, y, bx + bw + 5, y, 0, 1);
		text_at(S, bx + bw + 8, y + fs * 0.35, r->L->zlabels[i], fs,
			0x202020, -1);
		w = text_w(S, r->L->zlabels[i], fs);
		if (w > maxw)
			maxw = w;
	}
	if (it->label)
		S->ops->text(S->ctx, bx + bw + 8 + maxw + 8 + r->fs,
			     by + bh / 2, it->label, r->fs, 0x202020, 0, 1);
	group(S, NULL, NULL);
}

static void render_ax(const struct ssc_surface *S, struct ssc_ax *ax,
		      struct layout *L, double cx, double cy, double cw,
		      double ch, double left, double right, double top,
		      double bottom, double fs)
{
	struct render r = { .S = S, .fs = fs, .L = L };
	double fx = fs * FS_TICK;

	r.px = cx + left;
	r.py = cy + top;
	r.pw = cw - left - right;
	r.ph = ch - top - bottom;
	if (r.pw < 20 || r.ph < 20)
		return;
	group(S, "axes", NULL);
	if (ax->grid) {
		group(S, "grid", NULL);
		for (size_t i = 0; i < L->x.nmin; i++)
			line2(S, X(&r, L->x.minor[i]), r.py,
			      X(&r, L->x.minor[i]), r.py + r.ph, 0xf0f0f0, 1);
		for (size_t i = 0; i < L->y.nmin; i++)
			line2(S, r.px, Y(&r, L->y.minor[i]), r.px + r.pw,
			      Y(&r, L->y.minor[i]), 0xf0f0f0, 1);
		for (size_t i = 0; i < L->x.nmaj; i++)
			line2(S, X(&r, L->x.major[i]), r.py,
			      X(&r, L->x.major[i]), r.py + r.ph, 0xd8d8d8, 1);
		for (size_t i = 0; i < L->y.nmaj; i++)
			line2(S, r.px, Y(&r, L->y.major[i]), r.px + r.pw,
			      Y(&r, L->y.major[i]), 0xd8d8d8, 1);
		group(S, NULL, NULL);
	}
	/* data, clipped to the plot rectangle */
	group(S, "data", NULL);
	for (size_t k = 0; k < ax->n_items; k++)
		if (ax->items[k].kind == IT_IMAGE)
			draw_image(&r, &ax->items[k]);
	S->ops->clip(S->ctx, r.px, r.py, r.pw, r.ph);
	for (size_t k = 0; k < ax->n_items; k++)
		if (ax->items[k].kind == IT_BAND)
			draw_band(&r, &ax->items[k]);
	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];
		double p[4];

		switch (it->kind) {
		case IT_LINE:
			draw_series(&r, it);
			break;
		case IT_ERRBAR:
			draw_errbar(&r, it);
			break;
		case IT_VLINE:
			if (ok_val(&L->x, it->x[0])) {
				p[0] = p[2] = X(&r, it->x[0]);
				p[1] = r.py;
				p[3] = r.py + r.ph;
				stroke(S, p, 2, it->st.color, it->st.width,
				       it->st.dash);
			}
			break;
		case IT_HLINE:
			if (ok_val(&L->y, it->x[0])) {
				p[1] = p[3] = Y(&r, it->x[0]);
				p[0] = r.px;
				p[2] = r.px + r.pw;
				stroke(S, p, 2, it->st.color, it->st.width,
				       it->st.dash);
			}
			break;
		default:
			break;
		}
	}
	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];

		if (it->kind == IT_TEXT && ok_val(&L->x, it->x[0]) &&
		    ok_val(&L->y, it->y[0]))
			text_at(S, X(&r, it->x[0]), Y(&r, it->y[0]), it->text,
				fs * FS_TEXT,
				it->st.color ? it->st.color : 0x202020,
				it->align);
	}
	S->ops->clip(S->ctx, 0, 0, 0, 0);
	group(S, NULL, NULL);
	/* frame and ticks */
	group(S, "plot-area", NULL);
	S->ops->rect(S->ctx, r.px, r.py, r.pw, r.ph, 0x000000, 1, 0);
	group(S, NULL, NULL);
	group(S, "xaxis", NULL);
	for (size_t i = 0; i < L->x.nmaj; i++) {
		double x = X(&r, L->x.major[i]);

		line2(S, x, r.py + r.ph, x, r.py + r.ph + 6, 0, 1);
		if (L->x.show[i])
			text_at(S, x, r.py + r.ph + 10 + fx, L->x.labels[i], fx,
				0x202020, 0);
	}
	for (size_t i = 0; i < L->x.nmin; i++)
		line2(S, X(&r, L->x.minor[i]), r.py + r.ph,
		      X(&r, L->x.minor[i]), r.py + r.ph + 3, 0, 1);
	if (L->x.mult[0])
		text_at(S, r.px + r.pw, r.py + r.ph + 10 + fs * 2.1, L->x.mult,
			fx, 0x202020, 1);
	if (ax->xlabel) {
		group(S, "xlabel", NULL);
		text_at(S, r.px + r.pw / 2, cy + ch - 10, ax->xlabel, fs,
			0x000000, 0);
		group(S, NULL, NULL);
	}
	group(S, NULL, NULL);
	group(S, "yaxis", NULL);
	for (size_t i = 0; i < L->y.nmaj; i++) {
		double y = Y(&r, L->y.major[i]);

		line2(S, r.px - 6, y, r.px, y, 0, 1);
		if (L->y.show[i])
			text_at(S, r.px - 10, y + fs * 0.32, L->y.labels[i], fx,
				0x202020, 1);
	}
	for (size_t i = 0; i < L->y.nmin; i++)
		line2(S, r.px - 3, Y(&r, L->y.minor[i]), r.px,
		      Y(&r, L->y.minor[i]), 0, 1);
	if (L->y.mult[0])
		text_at(S, r.px, r.py - 6, L->y.mult, fx, 0x202020, -1);
	if (ax->ylabel) {
		group(S, "ylabel", NULL);
		S->ops->text(S->ctx, cx + 8 + fs, r.py + r.ph / 2, ax->ylabel,
			     fs, 0x000000, 0, 1);
		group(S, NULL, NULL);
	}
	group(S, NULL, NULL);
	if (ax->title) {
		group(S, "title", NULL);
		text_at(S, r.px + r.pw / 2, r.py - (L->y.mult[0] ? fs : 0) - 12,
			ax->title, fs * 1.08, 0x000000, 0);
		group(S, NULL, NULL);
	}
	if (L->image)
		draw_colorbar(&r);
	if (L->side_w > 0) {
		double bx = r.px + r.pw + L->cbar_w + SIDE_GAP, by = r.py;
		double bw = right - 24 - L->cbar_w - SIDE_GAP;

		by += draw_legend(&r, ax, bx, by, bw, cw);
		for (size_t k = 0; k < ax->n_items; k++)
			if (ax->items[k].kind == IT_NOTE) {
				by += 10;
				by += draw_note(&r, &ax->items[k], bx, by, bw,
						cw);
			}
	}
	group(S, NULL, NULL);
}

/* ---- the figure on a surface */

struct fig_layout {
	struct layout *L;
	double fs, top, cw, ch, h;
	double *left, *right, *tops, *bottoms;
};

static void fig_layout_free(struct fig_layout *fl)
{
	free(fl->L);
	free(fl->left);
	memset(fl, 0, sizeof(*fl));
}

/* Lay the figure out for the surface's text metrics; fl->h may exceed the
 * figure's height when a side panel needs taller rows. */
static int fig_layout(struct ssc_fig *f, const struct ssc_surface *S,
		      double h, struct fig_layout *fl)
{
	int n = f->rows * f->cols;
	double need = 0;

	memset(fl, 0, sizeof(*fl));
	fl->L = calloc((size_t)n, sizeof(*fl->L));
	fl->left = calloc((size_t)(2 * f->cols + 2 * f->rows), sizeof(double));
	if (!fl->L || !fl->left) {
		fig_layout_free(fl);
		return -ENOMEM;
	}
	fl->right = fl->left + f->cols;
	fl->tops = fl->right + f->cols;
	fl->bottoms = fl->tops + f->rows;
	/* text no smaller than 15 px at the figure's own size */
	fl->fs = fmax(15, fmin(22, f->w / 72.0));
	fl->top = f->title ? fl->fs * 2.4 : 4;
	fl->cw = f->w / (double)f->cols;
	fl->ch = (h - fl->top) / (double)f->rows;
	for (int i = 0; i < n; i++) {
		int row = i / f->cols, col = i % f->cols;
		struct layout *L = &fl->L[i];

		plan(S, &f->axes[i], L, fl->cw, fl->ch, fl->fs);
		fl->left[col] = fmax(fl->left[col], L->left);
		fl->right[col] = fmax(fl->right[col], L->right);
		fl->tops[row] = fmax(fl->tops[row], L->top);
		fl->bottoms[row] = fmax(fl->bottoms[row], L->bottom);
	}
	for (int i = 0; i < n; i++) {
		int row = i / f->cols;

		need = fmax(need, fl->tops[row] + fl->bottoms[row] +
					  fmax(fl->L[i].side_h, 100));
	}
	if (need > fl->ch)
		fl->ch = ceil(need);
	fl->h = fl->top + fl->ch * f->rows;
	return 0;
}

static void fig_draw(struct ssc_fig *f, const struct ssc_surface *S,
		     const struct fig_layout *fl)
{
	if (f->title) {
		group(S, "figure-title", NULL);
		text_at(S, f->w / 2.0, fl->fs * 1.7, f->title, fl->fs * 1.25, 0,
			0);
		group(S, NULL, NULL);
	}
	for (int i = 0; i < f->rows * f->cols; i++) {
		int row = i / f->cols, col = i % f->cols;
		struct ssc_ax *ax = &f->axes[i];

		if (!ax->n_items && !ax->title)
			continue;
		render_ax(S, ax, &fl->L[i], col * fl->cw, fl->top + row * fl->ch,
			  fl->cw, fl->ch, fl->left[col], fl->right[col],
			  fl->tops[row], fl->bottoms[row], fl->fs);
	}
}

static int write_file(const char *path, const void *buf, size_t len)
{
	return ssc_file_put(path, buf, len);
}

static bool fig_empty(const struct ssc_fig *f)
{
	for (int i = 0; i < f->rows * f->cols; i++)
		if (f->axes[i].n_items || f->axes[i].title)
			return false;
	return true;
}

int ssc_fig_svg(struct ssc_fig *f, const char *id_prefix, char **buf,
		size_t *len)
{
	struct ssc_surface S;
	struct fig_layout fl;
	struct ssc_svg *svg;
	double h = f->h;
	int rc;

	if (!f || fig_empty(f))
		return -EINVAL;
	/* lay out with the metrics of the SVG surface, then write */
	svg = ssc_svg_new(f->w, h, id_prefix, &S);
	if (!svg)
		return -ENOMEM;
	rc = fig_layout(f, &S, h, &fl);
	ssc_svg_free(svg);
	if (rc)
		return rc;
	svg = ssc_svg_new(f->w, fl.h, id_prefix, &S);
	if (!svg) {
		fig_layout_free(&fl);
		return -ENOMEM;
	}
	fig_draw(f, &S, &fl);
	fig_layout_free(&fl);
	return ssc_svg_finish(svg, buf, len);
}

/* the SVG document of the figure saved as path */
static int fig_svg_for(struct ssc_fig *f, const char *path, char **buf,
		       size_t *len)
{
	char id[48];
	const char *b = strrchr(path, '/');

	/* ids from the file name: figures inlined in one page stay apart */
	snprintf(id, sizeof(id), "f-%s", b ? b + 1 : path);
	if (strrchr(id, '.'))
		*strrchr(id, '.') = '\0';
	return ssc_fig_svg(f, id, buf, len);
}

int ssc_fig_save_svg(struct ssc_fig *f, const char *path)
{
	char *buf = NULL;
	size_t len = 0;
	int rc = fig_svg_for(f, path, &buf, &len);

	if (rc)
		return rc;
	rc = write_file(path, buf, len);
	free(buf);
	return rc;
}

#ifdef HAVE_OPENCV

/* The OpenCV canvas as a surface: rich text is drawn run by run; vertical
 * text, which the canvas draws in one piece, maps "^{2}" to Unicode
 * superscripts. */

static void cv_clip(void *c, double x, double y, double w, double h)
{
	if (w <= 0 || h <= 0)
		ssc_canvas_clip(c, 0, 0, 0, 0);
	else
		ssc_canvas_clip(c, (int)floor(x), (int)floor(y),
				(int)ceil(w) + 1, (int)ceil(h) + 1);
}

static void cv_polyline(void *c, const double *xy, size_t n, uint32_t rgb,
			double width, const double *dash)
{
	(void)dash; /* native_dash is false: plot.c cuts the dashes */
	ssc_canvas_polyline(c, xy, n, rgb, width);
}

static void cv_fill(void *c, const double *xy, size_t n, uint32_t rgb,
		    double alpha)
{
	ssc_canvas_fill(c, xy, n, rgb, alpha);
}

static void cv_rect(void *c, double x, double y, double w, double h,
		    uint32_t rgb, double width, int filled)
{
	ssc_canvas_rect(c, x, y, w, h, rgb, width, filled);
}

static void cv_circle(void *c, double x, double y, double r, uint32_t rgb,
		      double width, int filled)
{
	ssc_canvas_circle(c, x, y, r, rgb, width, filled);
}

static void run_str(const struct ssc_rich_run *run, char *buf, size_t len)
{
	size_t n = run->n < len - 1 ? run->n : len - 1;

	memcpy(buf, run->s, n);
	buf[n] = '\0';
}

static double cv_text_width(void *c, const char *t, double fs)
{
	struct ssc_rich_run runs[32];
	size_t n = ssc_rich_split(t, runs, 32);
	double w = 0;

	for (size_t i = 0; i < n; i++) {
		char buf[256];
		double rw, a, d;

		run_str(&runs[i], buf, sizeof(buf));
		ssc_canvas_text_size(c, buf,
				     runs[i].level ? fs * SSC_SCRIPT_SCALE : fs,
				     &rw, &a, &d);
		w += rw;
	}
	return w;
}

/* Vertical labels cannot carry runs: map "^{2}" to Unicode superscripts. */
static void flatten_sup(const char *in, char *out, size_t len)
{
	static const char *const sup[] = { "\xe2\x81\xb0", "\xc2\xb9",
					   "\xc2\xb2", "\xc2\xb3",
					   "\xe2\x81\xb4", "\xe2\x81\xb5",
					   "\xe2\x81\xb6", "\xe2\x81\xb7",
					   "\xe2\x81\xb8", "\xe2\x81\xb9" };
	size_t o = 0;

	while (*in && o + 8 < len) {
		if (in[0] == '^' && in[1] == '{') {
			const char *e = strchr(in + 2, '}');
			bool conv = e != NULL;

			for (const char *p = in + 2; conv && p < e; p++)
				if (!((*p >= '0' && *p <= '9') || *p == '-'))
					conv = false;
			if (conv) {
				for (const char *p = in + 2; p < e && o + 8 < len;
				     p++) {
					const char *s = *p == '-' ? "\xe2\x81\xbb" :
								    sup[*p - '0'];

					memcpy(out + o, s, strlen(s));
					o += strlen(s);
				}
				in = e + 1;
				continue;
			}
		}
		/* units as users write them: "m/s^2", "Hz^-1" */
		if (in[0] == '^' && ((in[1] >= '0' && in[1] <= '9') ||
				     (in[1] == '-' && in[2] >= '0' && in[2] <= '9'))) {
			if (*++in == '-') {
				memcpy(out + o, "\xe2\x81\xbb", 3);
				o += 3;
				in++;
			}
			for (; *in >= '0' && *in <= '9' && o + 8 < len; in++) {
				memcpy(out + o, sup[*in - '0'], strlen(sup[*in - '0']));
				o += strlen(sup[*in - '0']);
			}
			continue;
		}
		if ((in[0] == '^' || in[0] == '_') && in[1] == '{') {
			const char *e = strchr(in + 2, '}');

			if (e) {
				out[o++] = in[0];
				out[o++] = '(';
				for (const char *p = in + 2; p < e && o + 4 < len; p++)
					out[o++] = *p;
				out[o++] = ')';
				in = e + 1;
				continue;
			}
		}
		out[o++] = *in++;
	}
	out[o] = '\0';
}

static void cv_text(void *c, double x, double y, const char *t, double fs,
		    uint32_t color, int align, int vertical)
{
	struct ssc_rich_run runs[32];
	size_t n;
	double w;

	if (vertical) {
		char flat[256];

		flatten_sup(t, flat, sizeof(flat));
		w = cv_text_width(c, flat, fs);
		/* the canvas anchors vertical text at its bottom end */
		ssc_canvas_text(c, x,
				y + (align == 0 ? w / 2 : align > 0 ? w : 0),
				flat, fs, color, 1);
		return;
	}
	n = ssc_rich_split(t, runs, 32);
	w = cv_text_width(c, t, fs);
	x -= align == 0 ? w / 2 : align > 0 ? w : 0;
	for (size_t i = 0; i < n; i++) {
		char buf[256];
		double rw, a, d,
			s = runs[i].level ? fs * SSC_SCRIPT_SCALE : fs;

		run_str(&runs[i], buf, sizeof(buf));
		ssc_canvas_text(c, x,
				y - (runs[i].level > 0 ? SSC_SUP_SHIFT * fs :
				     runs[i].level < 0 ? -SSC_SUB_SHIFT * fs :
							 0),
				buf, s, color, 0);
		ssc_canvas_text_size(c, buf, s, &rw, &a, &d);
		x += rw;
	}
}

static void cv_image(void *c, double x, double y, double w, double h,
		     const double *v, int iw, int ih)
{
	ssc_canvas_image(c, (int)lround(x), (int)lround(y), (int)lround(w),
			 (int)lround(h), v, iw, ih);
}

static void cv_group(void *c, const char *cls, const char *attrs)
{
	(void)c;
	(void)cls;
	(void)attrs;
}

static const struct ssc_surface_ops cv_ops = {
	.clip = cv_clip,
	.polyline = cv_polyline,
	.fill = cv_fill,
	.rect = cv_rect,
	.circle = cv_circle,
	.text = cv_text,
	.text_width = cv_text_width,
	.image = cv_image,
	.group = cv_group,
};

/* the PNG file of the figure, in memory (free()) */
static int fig_png(struct ssc_fig *f, unsigned char **png, size_t *len)
{
	const char *font = getenv("SSCOPE_FONT");
	struct ssc_canvas *cv = NULL;
	struct ssc_surface S;
	struct fig_layout fl = { 0 };
	double h = f->h;
	int rc;

	if (fig_empty(f))
		return -EINVAL;
	for (int pass = 0; pass < 2; pass++) {
		ssc_canvas_free(cv);
		fig_layout_free(&fl);
		cv = ssc_canvas_new(f->w, (int)ceil(h),
				    font && *font ? font : SSCOPE_FONT_PATH);
		if (!cv)
			return -ENOMEM;
		S = (struct ssc_surface){ .ops = &cv_ops, .ctx = cv };
		rc = fig_layout(f, &S, h, &fl);
		if (rc) {
			ssc_canvas_free(cv);
			return rc;
		}
		if (fl.h <= ceil(h))
			break;
		h = fl.h;
	}
	fig_draw(f, &S, &fl);
	fig_layout_free(&fl);
	rc = ssc_canvas_png(cv, png, len) ? -EIO : 0;
	ssc_canvas_free(cv);
	return rc;
}

#else /* !HAVE_OPENCV */

static int fig_png(struct ssc_fig *f, unsigned char **png, size_t *len)
{
	(void)f;
	(void)png;
	(void)len;
	return -ENOTSUP;
}

#endif

int ssc_fig_save_png(struct ssc_fig *f, const char *path)
{
	unsigned char *png = NULL;
	size_t len = 0;
	int rc = fig_png(f, &png, &len);

	if (!rc)
		rc = write_file(path, png, len);
	free(png);
	return rc;
}

/* The SVG document drawn on a thread of its own while the PNG is drawn:
 * the figure is only read by both. */
struct svg_job {
	struct ssc_fig *f;
	const char *path;
	char *buf;
	size_t len;
	int rc;
};

static void *svg_thread(void *arg)
{
	struct svg_job *j = arg;

	j->rc = fig_svg_for(j->f, j->path, &j->buf, &j->len);
	return NULL;
}

/* the figure as p.svg and p.png (p.svg first, p.png only when it was
 * written), the two drawn at the same time */
static int save_both(struct ssc_fig *f, char *p, size_t stem)
{
	struct svg_job j = { .f = f, .path = p };
	unsigned char *png = NULL;
	size_t len = 0;
	pthread_t tid;
	bool two;
	int rc;

	strcpy(p + stem, ".svg");
	two = !pthread_create(&tid, NULL, svg_thread, &j);
	rc = fig_png(f, &png, &len);
	if (two)
		pthread_join(tid, NULL);
	else
		svg_thread(&j);
	if (!j.rc)
		j.rc = write_file(p, j.buf, j.len);
	free(j.buf);
	if (!j.rc && !rc) {
		strcpy(p + stem, ".png");
		rc = write_file(p, png, len);
	}
	free(png);
	return j.rc ? j.rc : rc;
}

enum ssc_plot_format ssc_plot_format_of(const char *path)
{
	size_t l = path ? strlen(path) : 0;

	if (l > 4 && !strcasecmp(path + l - 4, ".png"))
		return SSC_PLOT_PNG;
	if (l > 4 && !strcasecmp(path + l - 4, ".svg"))
		return SSC_PLOT_SVG;
	return SSC_PLOT_NONE;
}

int ssc_fig_save(struct ssc_fig *f, const char *path)
{
	size_t l = path ? strlen(path) : 0, k = strlen(SSC_PLOT_SVG_AND_PNG);

	if (l > k && !strcmp(path + l - k, SSC_PLOT_SVG_AND_PNG)) {
		char *p = malloc(l + 1);
		int rc;

		if (!p)
			return -ENOMEM;
		memcpy(p, path, l - k);
		rc = save_both(f, p, l - k);
		free(p);
		return rc;
	}
	switch (ssc_plot_format_of(path)) {
	case SSC_PLOT_PNG:
		return ssc_fig_save_png(f, path);
	case SSC_PLOT_SVG:
		return ssc_fig_save_svg(f, path);
	default:
		return -EINVAL;
	}
}

/* ------------------------------------------------------------ DAVAR */

int ssc_plot_davar(struct ssc_ax *ax, const struct sscope_adequacy *q,
		   const char *title)
{
	const struct sscope_adequacy_davar *d = &q->davar;
	size_t nx = d->n_win, ny = d->n_tau;
	double *z, *ref, *col, x0, x1;
	bool model = true;
	int rc;

	if (!nx || !ny)
		return -EDOM;
	z = calloc(nx * ny, sizeof(double));
	ref = calloc(ny, sizeof(double));
	col = calloc(nx, sizeof(double));
	if (!z || !ref || !col) {
		free(z);
		free(ref);
		free(col);
		return -ENOMEM;
	}
	/* the reference of each tau: the fitted model, else the median of
	 * the windows */
	for (size_t j = 0; j < ny; j++) {
		ref[j] = d->model[j];
		if (!(ref[j] > 0)) {
			size_t k = 0;

			model = false;
			for (size_t i = 0; i < nx; i++)
				if (d->dev[i * ny + j] > 0)
					col[k++] = d->dev[i * ny + j];
			for (size_t a = 1; a < k; a++)
				for (size_t b = a; b > 0 && col[b - 1] > col[b]; b--) {
					double t = col[b];

					col[b] = col[b - 1];
					col[b - 1] = t;
				}
			ref[j] = k ? col[k / 2] : (double)NAN;
		}
	}
	for (size_t j = 0; j < ny; j++)
		for (size_t i = 0; i < nx; i++) {
			double v = d->dev[i * ny + j] / ref[j];

			/* the colour scale spans 1/4 to 4 */
			z[j * nx + i] = isfinite(v) && v > 0 ?
				fmin(4, fmax(0.25, v)) : (double)NAN;
		}
	ssc_ax_log(ax, false, true);
	ssc_ax_title(ax, title);
	ssc_ax_xlabel(ax, "window centre (s)");
	ssc_ax_ylabel(ax, "averaging time \xcf\x84 (s)");
	x0 = d->t_s[0] - (nx > 1 ? (d->t_s[1] - d->t_s[0]) / 2 : d->window_s / 2);
	x1 = d->t_s[nx - 1] + (nx > 1 ? (d->t_s[1] - d->t_s[0]) / 2 : d->window_s / 2);
	ssc_ax_ylim(ax, d->tau_s[0] / sqrt(2), d->tau_s[ny - 1] * sqrt(2));
	ssc_ax_xlim(ax, x0, x1);
	rc = ssc_ax_image(ax, z, nx, ny, x0, x1, d->tau_s[0] / sqrt(2),
			  d->tau_s[ny - 1] * sqrt(2), 0.25, 4, true,
			  model ? "window deviation / fitted model" :
				  "window deviation / median of the windows");
	/* where the findings put the fault */
	for (size_t i = 0; !rc && i < q->n_findings; i++) {
		const struct sscope_adequacy_finding *f = &q->findings[i];
		struct ssc_style st = { .color = 0xd62728, .width = 1.5,
					.dash = SSC_DASHED };
		char lab[64];

		if (f->severity < SSCOPE_ADEQUACY_DOUBT || !isfinite(f->t_start_s))
			continue;
		snprintf(lab, sizeof(lab), "%s", sscope_adequacy_cause_name(f->cause));
		for (char *p = lab; *p; p++)
			if (*p == '_')
				*p = '-';
		if (f->t_start_s > x0)
			rc = ssc_ax_vline(ax, f->t_start_s, &st, lab);
		if (!rc && isfinite(f->t_end_s) && f->t_end_s < x1)
			rc = ssc_ax_vline(ax, f->t_end_s, &st,
					  f->t_start_s > x0 ? NULL : lab);
	}
	free(z);
	free(ref);
	free(col);
	return rc;
}
