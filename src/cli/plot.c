/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Plot layout: data limits, "nice" linear ticks (Heckbert, "Nice numbers
 * for graph labels", Graphics Gems, 1990), decade ticks on log axes, margins
 * aligned across a grid of axes, dashes, pixel-column decimation of long
 * series (first/min/max/last per column, so a million-sample trace keeps
 * its envelope), legends placed where they hide the fewest points.  Pixels
 * are drawn by cvshim.cpp; without OpenCV only the layout code is built and
 * ssc_fig_save_png() returns -ENOTSUP.
 */
#include "config.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
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
#define LINE_BUCKETS 4096

static int line_reduced(struct item *it, const double *x, const double *y,
			size_t n)
{
	size_t cap = 5 * LINE_BUCKETS, m = 0;

	it->x = malloc(cap * sizeof(double));
	it->y = malloc(cap * sizeof(double));
	if (!it->x || !it->y)
		return -ENOMEM;
	for (size_t b = 0; b < LINE_BUCKETS; b++) {
		size_t i0 = n * b / LINE_BUCKETS, i1 = n * (b + 1) / LINE_BUCKETS;
		size_t imin = SIZE_MAX, imax = SIZE_MAX, ibad = SIZE_MAX;
		size_t keep[5], nk = 0;

		if (i0 >= i1)
			continue;
		for (size_t i = i0; i < i1; i++) {
			if (!isfinite(x[i]) || !isfinite(y[i])) {
				if (ibad == SIZE_MAX)
					ibad = i;
				continue;
			}
			if (imin == SIZE_MAX || y[i] < y[imin])
				imin = i;
			if (imax == SIZE_MAX || y[i] > y[imax])
				imax = i;
		}
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
			it->y[m] = y[keep[a]];
			m++;
		}
	}
	it->n = m;
	return 0;
}

int ssc_ax_line(struct ssc_ax *ax, const double *x, const double *y, size_t n,
		const struct ssc_style *st, const char *label)
{
	struct item *it = new_item(ax, IT_LINE, st, label);

	if (!it)
		return -ENOMEM;
	if (n > 8 * LINE_BUCKETS && !ax->logx && !ax->logy && x && y)
		return line_reduced(it, x, y, n);
	it->n = n;
	it->x = dup_arr(x, n);
	it->y = dup_arr(y, n);
	return (it->x && it->y) ? 0 : -ENOMEM;
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
	first = ceil(lo / step - 1e-9) * step;
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

#ifdef HAVE_OPENCV

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
};

struct render {
	struct ssc_canvas *cv;
	double fs;     /* base font size px */
	double px, py, pw, ph; /* plot rectangle */
	struct layout *L;
	unsigned taken; /* corners (1 << pos) holding a note */
};

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

/* ---- rich text: "^{...}" superscript, "_{...}" subscript */

struct run {
	const char *s;
	size_t n;
	int level; /* 0 normal, 1 sup, -1 sub */
};

static size_t split_rich(const char *t, struct run *runs, size_t max)
{
	size_t n = 0;

	while (*t && n < max) {
		if ((t[0] == '^' || t[0] == '_') && t[1] == '{') {
			const char *e = strchr(t + 2, '}');

			if (e) {
				runs[n++] = (struct run){ t + 2, (size_t)(e - t - 2),
							  t[0] == '^' ? 1 : -1 };
				t = e + 1;
				continue;
			}
		}
		{
			const char *e = t;

			while (*e && !((e[0] == '^' || e[0] == '_') && e[1] == '{'))
				e++;
			if (e == t)
				e++;
			runs[n++] = (struct run){ t, (size_t)(e - t), 0 };
			t = e;
		}
	}
	return n;
}

static double rich_width(struct ssc_canvas *cv, const char *t, double fs)
{
	struct run runs[16];
	size_t n = split_rich(t, runs, 16);
	double w = 0;

	for (size_t i = 0; i < n; i++) {
		char buf[256];
		double rw, a, d;
		size_t len = runs[i].n < 255 ? runs[i].n : 255;

		memcpy(buf, runs[i].s, len);
		buf[len] = '\0';
		ssc_canvas_text_size(cv, buf, runs[i].level ? fs * 0.72 : fs,
				     &rw, &a, &d);
		w += rw;
	}
	return w;
}

/* Draw rich text with its baseline at y; align -1 left, 0 centre, 1 right */
static void rich_text(struct ssc_canvas *cv, double x, double y, const char *t,
		      double fs, uint32_t color, int align)
{
	struct run runs[16];
	size_t n = split_rich(t, runs, 16);
	double w = rich_width(cv, t, fs);

	x -= align == 0 ? w / 2 : align > 0 ? w : 0;
	for (size_t i = 0; i < n; i++) {
		char buf[256];
		double rw, a, d, s = runs[i].level ? fs * 0.72 : fs;
		size_t len = runs[i].n < 255 ? runs[i].n : 255;

		memcpy(buf, runs[i].s, len);
		buf[len] = '\0';
		ssc_canvas_text(cv, x,
				y - (runs[i].level > 0 ? 0.42 * fs :
				     runs[i].level < 0 ? -0.2 * fs : 0),
				buf, s, color, 0);
		ssc_canvas_text_size(cv, buf, s, &rw, &a, &d);
		x += rw;
	}
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
	if (logv && a->lo > 0 && a->hi > a->lo) {
		a->nmaj = ssc_ticks_log(a->lo, a->hi, a->major, MAXT, a->minor,
					8 * MAXT, &a->nmin);
		if (a->nmaj >= 2) {
			size_t every = 1;

			while (a->nmaj / every > target + 1)
				every++;
			a->mult[0] = '\0';
			for (size_t i = 0; i < a->nmaj; i++) {
				int k = (int)lround(log10(a->major[i]));

				if (k == 0)
					snprintf(a->labels[i], 40, "1");
				else if (k == 1)
					snprintf(a->labels[i], 40, "10");
				else
					snprintf(a->labels[i], 40, "10^{%d}", k);
				a->show[i] = (k % (int)every) == 0;
			}
			return;
		}
		/* less than a decade: 1-2-5 ticks, plain labels */
		a->nmaj = 0;
		for (size_t i = 0; i < a->nmin && a->nmaj < MAXT; i++) {
			double m = a->minor[i] /
				   pow(10, floor(log10(a->minor[i]) + 1e-9));

			if (fabs(m - 2) < 1e-6 || fabs(m - 5) < 1e-6)
				a->major[a->nmaj++] = a->minor[i];
		}
		for (size_t i = 0; i < a->nmaj; i++) {
			snprintf(a->labels[i], 40, "%g", a->major[i]);
			a->show[i] = true;
		}
		a->mult[0] = '\0';
		return;
	}
	a->log = false;
	a->nmin = 0;
	a->nmaj = ssc_ticks_linear(a->lo, a->hi, target, a->major, MAXT, &step);
	fmt_linear(a, step);
}

static void plan(struct ssc_canvas *cv, struct ssc_ax *ax, struct layout *L,
		 double cw, double ch, double fs)
{
	double dlo, dhi, w, a, d, maxw = 0;
	bool img;

	memset(L, 0, sizeof(*L));
	data_range(ax, true, ax->logx, &dlo, &dhi, &img);
	make_axis(&L->x, ax->logx, ax->xlim_set, ax->xlo, ax->xhi, dlo, dhi,
		  false, img, cw * 0.8, ax->logx ? 55 : 90);
	data_range(ax, false, ax->logy, &dlo, &dhi, &img);
	make_axis(&L->y, ax->logy, ax->ylim_set, ax->ylo, ax->yhi, dlo, dhi,
		  true, img, ch * 0.75, ax->logy ? 28 : 45);
	for (size_t i = 0; i < L->y.nmaj; i++) {
		w = rich_width(cv, L->y.labels[i], fs * 0.9);
		if (w > maxw)
			maxw = w;
	}
	ssc_canvas_text_size(cv, "0", fs, &w, &a, &d);
	L->left = 10 + maxw + 8 + 6 + (ax->ylabel ? fs * 1.3 + 6 : 0);
	L->bottom = 6 + 4 + fs * 1.2 + (ax->xlabel ? fs * 1.4 + 6 : 0) + 8;
	L->top = (ax->title ? fs * 1.8 : 0) + (L->y.mult[0] ? fs : 0) + 12;
	L->right = 24;
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
					snprintf(L->zlabels[i], 40, "10^{%d}",
						 (int)lround(log10(mj[i])));
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
				w = rich_width(cv, L->zlabels[i], fs * 0.9);
				if (w > zmax)
					zmax = w;
			}
			L->right = 16 + 16 + 6 + zmax + 10 +
				   (it->label ? fs * 1.3 : 0) + 10;
		}
}

/* ---- drawing primitives on top of the shim */

static const double dash_on_off[4][4] = {
	{ 0, 0, 0, 0 }, { 9, 5, 9, 5 }, { 2, 4, 2, 4 }, { 9, 4, 2, 4 }
};

/* Draw a polyline (pixel coords) with a dash pattern. */
static void stroke(struct ssc_canvas *cv, const double *xy, size_t n,
		   uint32_t color, double width, enum ssc_dash dash)
{
	double seg[512 * 2];
	size_t ns = 0;
	int phase = 0;
	double left, scale = width > 1.5 ? width / 1.5 : 1;

	if (n < 2)
		return;
	if (dash == SSC_SOLID) {
		ssc_canvas_polyline(cv, xy, n, color, width);
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
				ssc_canvas_polyline(cv, seg, ns, color, width);
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
				ssc_canvas_polyline(cv, seg, ns, color, width);
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
		ssc_canvas_polyline(cv, seg, ns, color, width);
}

static void marker(struct ssc_canvas *cv, double x, double y,
		   enum ssc_marker m, double size, uint32_t color)
{
	double r = size / 2, p[8];

	switch (m) {
	case SSC_MK_CIRCLE:
		ssc_canvas_circle(cv, x, y, r, color, 1, 1);
		break;
	case SSC_MK_SQUARE:
		ssc_canvas_rect(cv, x - r, y - r, 2 * r, 2 * r, color, 1, 1);
		break;
	case SSC_MK_TRIANGLE:
		p[0] = x;
		p[1] = y - r * 1.15;
		p[2] = x + r;
		p[3] = y + r * 0.7;
		p[4] = x - r;
		p[5] = y + r * 0.7;
		ssc_canvas_fill(cv, p, 3, color, 1);
		break;
	case SSC_MK_DIAMOND:
		p[0] = x;
		p[1] = y - r * 1.2;
		p[2] = x + r;
		p[3] = y;
		p[4] = x;
		p[5] = y + r * 1.2;
		p[6] = x - r;
		p[7] = y;
		ssc_canvas_fill(cv, p, 4, color, 1);
		break;
	case SSC_MK_CROSS:
		p[0] = x - r;
		p[1] = y - r;
		p[2] = x + r;
		p[3] = y + r;
		ssc_canvas_polyline(cv, p, 2, color, 2);
		p[0] = x - r;
		p[1] = y + r;
		p[2] = x + r;
		p[3] = y - r;
		ssc_canvas_polyline(cv, p, 2, color, 2);
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
				stroke(r->cv, xy, n, it->st.color, it->st.width,
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
				marker(r->cv, X(r, it->x[i]), Y(r, it->y[i]),
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
		double x, p[4], lo = it->lo[i], hi = it->hi[i];

		if (!ok_val(ax, it->x[i]))
			continue;
		x = X(r, it->x[i]);
		if (ay->log && !(lo > 0))
			lo = ay->lo * 1e-3;
		if (ok_val(ay, hi) && isfinite(lo)) {
			p[0] = x;
			p[1] = Y(r, lo);
			p[2] = x;
			p[3] = Y(r, hi);
			ssc_canvas_polyline(r->cv, p, 2, it->st.color, 1.2);
			p[0] = x - 3.5;
			p[2] = x + 3.5;
			p[1] = p[3] = Y(r, hi);
			ssc_canvas_polyline(r->cv, p, 2, it->st.color, 1.2);
			p[1] = p[3] = Y(r, lo);
			ssc_canvas_polyline(r->cv, p, 2, it->st.color, 1.2);
		}
	}
	{
		struct item line = *it;

		draw_series(r, &line);
	}
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
			ssc_canvas_fill(r->cv, p, m, it->st.color, it->alpha);
		}
		start = end + 1;
	}
	free(p);
}

/* Lines of a note. */
static size_t note_lines(const char *t, char lines[][160], size_t max)
{
	size_t n = 0;

	while (*t && n < max) {
		const char *e = strchr(t, '\n');
		size_t len = e ? (size_t)(e - t) : strlen(t);

		if (len > 159)
			len = 159;
		memcpy(lines[n], t, len);
		lines[n][len] = '\0';
		n++;
		if (!e)
			break;
		t = e + 1;
	}
	return n;
}

/* Count data points of the axes inside a pixel box (legend placement). */
static size_t points_in(const struct render *r, const struct ssc_ax *ax,
			double bx, double by, double bw, double bh)
{
	size_t c = 0;

	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];
		size_t step;

		if (it->kind != IT_LINE && it->kind != IT_ERRBAR &&
		    it->kind != IT_BAND)
			continue;
		step = it->n > 2000 ? it->n / 2000 : 1;
		for (size_t i = 0; i < it->n; i += step) {
			const double *ys[3] = { it->y, it->lo, it->hi };

			if (!ok_val(&r->L->x, it->x[i]))
				continue;
			for (int j = 0; j < 3; j++) {
				double px, py;

				if (!ys[j] || !ok_val(&r->L->y, ys[j][i]))
					continue;
				px = X(r, it->x[i]);
				py = Y(r, ys[j][i]);
				if (px >= bx && px <= bx + bw && py >= by &&
				    py <= by + bh)
					c++;
			}
		}
	}
	return c;
}

static void box_at(const struct render *r, const struct ssc_ax *ax,
		   enum ssc_legend_pos pos, double bw, double bh, double *bx,
		   double *by)
{
	const double m = 10;
	enum ssc_legend_pos cand[4] = { SSC_LEGEND_UR, SSC_LEGEND_UL,
					SSC_LEGEND_LR, SSC_LEGEND_LL };
	size_t best = SIZE_MAX;

	if (pos == SSC_LEGEND_AUTO) {
		for (int i = 0; i < 4; i++) {
			double x, y;
			size_t c;

			box_at(r, ax, cand[i], bw, bh, &x, &y);
			c = points_in(r, ax, x, y, bw, bh);
			if (r->taken & (1u << cand[i]))
				c = SIZE_MAX - 1; /* a note is there */
			if (c < best) {
				best = c;
				pos = cand[i];
			}
		}
	}
	*bx = (pos == SSC_LEGEND_UL || pos == SSC_LEGEND_LL) ?
		      r->px + m :
		      r->px + r->pw - m - bw;
	*by = (pos == SSC_LEGEND_UL || pos == SSC_LEGEND_UR) ?
		      r->py + m :
		      r->py + r->ph - m - bh;
}

static void draw_legend(struct render *r, const struct ssc_ax *ax)
{
	double fs = r->fs * 0.88, lh = fs * 1.45, maxw = 0, bw, bh, bx, by;
	size_t n = 0, i = 0;

	if (ax->legend == SSC_LEGEND_NONE)
		return;
	for (size_t k = 0; k < ax->n_items; k++)
		if (ax->items[k].label && ax->items[k].kind != IT_IMAGE) {
			double w = rich_width(r->cv, ax->items[k].label, fs);

			if (w > maxw)
				maxw = w;
			n++;
		}
	if (!n)
		return;
	bw = 12 + 30 + 8 + maxw + 12;
	bh = 8 + lh * (double)n + 4;
	box_at(r, ax, ax->legend, bw, bh, &bx, &by);
	{
		double p[8] = { bx, by, bx + bw, by, bx + bw, by + bh, bx, by + bh };

		ssc_canvas_fill(r->cv, p, 4, 0xffffff, 0.88);
		ssc_canvas_rect(r->cv, bx, by, bw, bh, 0xb0b0b0, 1, 0);
	}
	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];
		double y = by + 8 + lh * (double)i + lh * 0.5, x = bx + 12;

		if (!it->label || it->kind == IT_IMAGE)
			continue;
		if (it->kind == IT_BAND) {
			double p[8] = { x, y - 6, x + 30, y - 6, x + 30, y + 6,
					x, y + 6 };

			ssc_canvas_fill(r->cv, p, 4, it->st.color, it->alpha);
		} else {
			double p[4] = { x, y, x + 30, y };

			if (it->st.width > 0)
				stroke(r->cv, p, 2, it->st.color,
				       it->st.width, it->st.dash);
			if (it->kind == IT_ERRBAR) {
				double q[4] = { x + 15, y - 7, x + 15, y + 7 };

				ssc_canvas_polyline(r->cv, q, 2, it->st.color,
						    1.2);
			}
			if (it->st.marker)
				marker(r->cv, x + 15, y, it->st.marker,
				       it->st.marker_size, it->st.color);
		}
		rich_text(r->cv, x + 38, y + fs * 0.35, it->label, fs, 0x202020,
			  -1);
		i++;
	}
}

static void draw_note(struct render *r, const struct ssc_ax *ax,
		      const struct item *it)
{
	char lines[16][160];
	size_t n = note_lines(it->text, lines, 16);
	double fs = r->fs * 0.85, lh = fs * 1.4, maxw = 0, bw, bh, bx, by;

	for (size_t i = 0; i < n; i++) {
		double w = rich_width(r->cv, lines[i], fs);

		if (w > maxw)
			maxw = w;
	}
	enum ssc_legend_pos pos = it->pos;

	bw = maxw + 20;
	bh = lh * (double)n + 10;
	if (pos == SSC_LEGEND_NONE || pos == SSC_LEGEND_AUTO) {
		/* the free corner with the fewest points */
		static const enum ssc_legend_pos c4[4] = {
			SSC_LEGEND_UR, SSC_LEGEND_UL, SSC_LEGEND_LR, SSC_LEGEND_LL
		};
		size_t best = SIZE_MAX;

		for (int i = 0; i < 4; i++) {
			double x, y;
			size_t c;

			if (r->taken & (1u << c4[i]))
				continue;
			box_at(r, ax, c4[i], bw, bh, &x, &y);
			c = points_in(r, ax, x, y, bw, bh);
			if (c < best) {
				best = c;
				pos = c4[i];
			}
		}
		if (best == SIZE_MAX)
			pos = SSC_LEGEND_UR;
	}
	r->taken |= 1u << pos;
	box_at(r, ax, pos, bw, bh, &bx, &by);
	{
		double p[8] = { bx, by, bx + bw, by, bx + bw, by + bh, bx, by + bh };

		ssc_canvas_fill(r->cv, p, 4, 0xfffff4, 0.9);
		ssc_canvas_rect(r->cv, bx, by, bw, bh, 0xb0b0b0, 1, 0);
	}
	for (size_t i = 0; i < n; i++)
		rich_text(r->cv, bx + 10, by + 5 + lh * (double)i + lh * 0.72,
			  lines[i], fs, 0x202020, -1);
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
	ssc_canvas_image(r->cv, (int)lround(fmin(x0, x1)),
			 (int)lround(fmin(y0, y1)), (int)lround(fabs(x1 - x0)),
			 (int)lround(fabs(y1 - y0)), v, (int)it->nx,
			 (int)it->ny);
	free(v);
}

static void draw_colorbar(struct render *r)
{
	const struct item *it = r->L->img;
	double bx = r->px + r->pw + 16, by = r->py, bw = 16, bh = r->ph;
	double v[256], lo, hi, fs = r->fs * 0.9, maxw = 0;

	for (int i = 0; i < 256; i++)
		v[i] = i / 255.0;
	ssc_canvas_image(r->cv, (int)bx, (int)by, (int)bw, (int)bh, v, 1, 256);
	ssc_canvas_rect(r->cv, bx, by, bw, bh, 0x000000, 1, 0);
	lo = it->zlog ? log10(it->zlo) : it->zlo;
	hi = it->zlog ? log10(it->zhi) : it->zhi;
	for (size_t i = 0; i < r->L->nz; i++) {
		double z = it->zlog ? log10(r->L->zmaj[i]) : r->L->zmaj[i];
		double y = by + bh - (z - lo) / (hi - lo) * bh, p[4], w;

		p[0] = bx + bw;
		p[1] = p[3] = y;
		p[2] = bx + bw + 5;
		ssc_canvas_polyline(r->cv, p, 2, 0, 1);
		rich_text(r->cv, bx + bw + 8, y + fs * 0.35, r->L->zlabels[i],
			  fs, 0x202020, -1);
		w = rich_width(r->cv, r->L->zlabels[i], fs);
		if (w > maxw)
			maxw = w;
	}
	if (it->label) {
		char flat[256];

		flatten_sup(it->label, flat, sizeof(flat));
		ssc_canvas_text(r->cv, bx + bw + 8 + maxw + 8 + r->fs,
				by + bh / 2 + rich_width(r->cv, flat, r->fs) / 2,
				flat, r->fs, 0x202020, 1);
	}
}

static void render_ax(struct ssc_canvas *cv, struct ssc_ax *ax,
		      struct layout *L, double cx, double cy, double cw,
		      double ch, double left, double right, double top,
		      double bottom, double fs)
{
	struct render r = { .cv = cv, .fs = fs, .L = L };
	double p[4];

	r.px = cx + left;
	r.py = cy + top;
	r.pw = cw - left - right;
	r.ph = ch - top - bottom;
	if (r.pw < 20 || r.ph < 20)
		return;
	/* grid */
	if (ax->grid) {
		for (size_t i = 0; i < L->x.nmin; i++) {
			p[0] = p[2] = X(&r, L->x.minor[i]);
			p[1] = r.py;
			p[3] = r.py + r.ph;
			ssc_canvas_polyline(cv, p, 2, 0xf0f0f0, 1);
		}
		for (size_t i = 0; i < L->y.nmin; i++) {
			p[1] = p[3] = Y(&r, L->y.minor[i]);
			p[0] = r.px;
			p[2] = r.px + r.pw;
			ssc_canvas_polyline(cv, p, 2, 0xf0f0f0, 1);
		}
		for (size_t i = 0; i < L->x.nmaj; i++) {
			p[0] = p[2] = X(&r, L->x.major[i]);
			p[1] = r.py;
			p[3] = r.py + r.ph;
			ssc_canvas_polyline(cv, p, 2, 0xd8d8d8, 1);
		}
		for (size_t i = 0; i < L->y.nmaj; i++) {
			p[1] = p[3] = Y(&r, L->y.major[i]);
			p[0] = r.px;
			p[2] = r.px + r.pw;
			ssc_canvas_polyline(cv, p, 2, 0xd8d8d8, 1);
		}
	}
	/* data, clipped to the plot rectangle */
	ssc_canvas_clip(cv, (int)floor(r.px), (int)floor(r.py),
			(int)ceil(r.pw) + 1, (int)ceil(r.ph) + 1);
	for (size_t k = 0; k < ax->n_items; k++)
		if (ax->items[k].kind == IT_IMAGE) {
			ssc_canvas_clip(cv, 0, 0, 0, 0);
			draw_image(&r, &ax->items[k]);
			ssc_canvas_clip(cv, (int)floor(r.px), (int)floor(r.py),
					(int)ceil(r.pw) + 1,
					(int)ceil(r.ph) + 1);
		}
	for (size_t k = 0; k < ax->n_items; k++)
		if (ax->items[k].kind == IT_BAND)
			draw_band(&r, &ax->items[k]);
	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];

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
				stroke(cv, p, 2, it->st.color, it->st.width,
				       it->st.dash);
			}
			break;
		case IT_HLINE:
			if (ok_val(&L->y, it->x[0])) {
				p[1] = p[3] = Y(&r, it->x[0]);
				p[0] = r.px;
				p[2] = r.px + r.pw;
				stroke(cv, p, 2, it->st.color, it->st.width,
				       it->st.dash);
			}
			break;
		default:
			break;
		}
	}
	ssc_canvas_clip(cv, 0, 0, 0, 0);
	for (size_t k = 0; k < ax->n_items; k++) {
		const struct item *it = &ax->items[k];

		if (it->kind == IT_TEXT && ok_val(&L->x, it->x[0]) &&
		    ok_val(&L->y, it->y[0]))
			rich_text(cv, X(&r, it->x[0]), Y(&r, it->y[0]),
				  it->text, fs * 0.85,
				  it->st.color ? it->st.color : 0x202020,
				  it->align);
	}
	/* frame and ticks */
	ssc_canvas_rect(cv, r.px, r.py, r.pw, r.ph, 0x000000, 1, 0);
	for (size_t i = 0; i < L->x.nmaj; i++) {
		double x = X(&r, L->x.major[i]);

		p[0] = p[2] = x;
		p[1] = r.py + r.ph;
		p[3] = r.py + r.ph + 6;
		ssc_canvas_polyline(cv, p, 2, 0, 1);
		if (L->x.show[i])
			rich_text(cv, x, r.py + r.ph + 10 + fs * 0.9,
				  L->x.labels[i], fs * 0.9, 0x202020, 0);
	}
	for (size_t i = 0; i < L->x.nmin; i++) {
		p[0] = p[2] = X(&r, L->x.minor[i]);
		p[1] = r.py + r.ph;
		p[3] = r.py + r.ph + 3;
		ssc_canvas_polyline(cv, p, 2, 0, 1);
	}
	for (size_t i = 0; i < L->y.nmaj; i++) {
		double y = Y(&r, L->y.major[i]);

		p[1] = p[3] = y;
		p[0] = r.px - 6;
		p[2] = r.px;
		ssc_canvas_polyline(cv, p, 2, 0, 1);
		if (L->y.show[i])
			rich_text(cv, r.px - 10, y + fs * 0.32, L->y.labels[i],
				  fs * 0.9, 0x202020, 1);
	}
	for (size_t i = 0; i < L->y.nmin; i++) {
		p[1] = p[3] = Y(&r, L->y.minor[i]);
		p[0] = r.px - 3;
		p[2] = r.px;
		ssc_canvas_polyline(cv, p, 2, 0, 1);
	}
	if (L->x.mult[0])
		rich_text(cv, r.px + r.pw, r.py + r.ph + 10 + fs * 2.1,
			  L->x.mult, fs * 0.9, 0x202020, 1);
	if (L->y.mult[0])
		rich_text(cv, r.px, r.py - 6, L->y.mult, fs * 0.9, 0x202020, -1);
	if (ax->xlabel)
		rich_text(cv, r.px + r.pw / 2, cy + ch - 10, ax->xlabel, fs,
			  0x000000, 0);
	if (ax->ylabel) {
		char flat[256];
		double w;

		flatten_sup(ax->ylabel, flat, sizeof(flat));
		w = rich_width(cv, flat, fs);
		ssc_canvas_text(cv, cx + 8 + fs, r.py + r.ph / 2 + w / 2, flat, fs,
				0x000000, 1);
	}
	if (ax->title)
		rich_text(cv, r.px + r.pw / 2,
			  r.py - (L->y.mult[0] ? fs : 0) - 12, ax->title,
			  fs * 1.08, 0x000000, 0);
	if (L->image)
		draw_colorbar(&r);
	for (size_t k = 0; k < ax->n_items; k++)
		if (ax->items[k].kind == IT_NOTE)
			draw_note(&r, ax, &ax->items[k]);
	draw_legend(&r, ax);
}

int ssc_fig_save_png(struct ssc_fig *f, const char *path)
{
	struct ssc_canvas *cv;
	struct layout *L;
	double fs, top, cw, ch, *left, *right, *tops, *bottoms;
	unsigned char *png = NULL;
	size_t len = 0;
	int rc = 0, n = f->rows * f->cols;
	const char *font = getenv("SSCOPE_FONT");

	cv = ssc_canvas_new(f->w, f->h, font && *font ? font : SSCOPE_FONT_PATH);
	L = calloc((size_t)n, sizeof(*L));
	left = calloc((size_t)(2 * f->cols + 2 * f->rows), sizeof(double));
	if (!cv || !L || !left) {
		ssc_canvas_free(cv);
		free(L);
		free(left);
		return -ENOMEM;
	}
	right = left + f->cols;
	tops = right + f->cols;
	bottoms = tops + f->rows;
	fs = fmin(f->w, f->h) / 48.0;
	if (fs < 12)
		fs = 12;
	if (fs > 20)
		fs = 20;
	top = f->title ? fs * 2.4 : 4;
	cw = f->w / (double)f->cols;
	ch = (f->h - top) / (double)f->rows;
	for (int i = 0; i < n; i++) {
		int row = i / f->cols, col = i % f->cols;

		plan(cv, &f->axes[i], &L[i], cw, ch, fs);
		left[col] = fmax(left[col], L[i].left);
		right[col] = fmax(right[col], L[i].right);
		tops[row] = fmax(tops[row], L[i].top);
		bottoms[row] = fmax(bottoms[row], L[i].bottom);
	}
	if (f->title)
		rich_text(cv, f->w / 2.0, fs * 1.7, f->title, fs * 1.25, 0, 0);
	for (int i = 0; i < n; i++) {
		int row = i / f->cols, col = i % f->cols;
		struct ssc_ax *ax = &f->axes[i];

		if (!ax->n_items && !ax->title)
			continue;
		render_ax(cv, ax, &L[i], col * cw, top + row * ch, cw, ch,
			  left[col], right[col], tops[row], bottoms[row], fs);
	}
	if (ssc_canvas_png(cv, &png, &len))
		rc = -EIO;
	ssc_canvas_free(cv);
	free(L);
	free(left);
	if (rc)
		return rc;
	rc = ssc_file_put(path, png, len);
	free(png);
	return rc;
}

#else /* !HAVE_OPENCV */

int ssc_fig_save_png(struct ssc_fig *f, const char *path)
{
	(void)f;
	(void)path;
	return -ENOTSUP;
}

#endif
