/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Plotting layer for every figure sensorscope draws: figures with a grid of
 * axes, linear or logarithmic scales with decade ticks, lines, markers,
 * error bars, shaded bands, images (spectrograms) with a colour bar,
 * legends, titles and labels.  Layout and ticks are computed here in C from
 * one description; it is drawn as SVG (always available) or as PNG by the
 * OpenCV shim (cvshim.cpp).  Text may use the markup "^{...}" for
 * superscripts and "_{...}" for subscripts.
 */
#ifndef SSCOPE_PLOT_H
#define SSCOPE_PLOT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

struct ssc_fig;
struct ssc_ax;

enum ssc_dash { SSC_SOLID = 0, SSC_DASHED, SSC_DOTTED, SSC_DASHDOT };

enum ssc_marker {
	SSC_MK_NONE = 0,
	SSC_MK_CIRCLE,
	SSC_MK_SQUARE,
	SSC_MK_TRIANGLE,
	SSC_MK_DIAMOND,
	SSC_MK_CROSS,
	SSC_MK_TRIANGLE_DOWN, /* an upper bound */
};

/* Legends and notes are drawn in a panel right of the axes, outside the
 * data, in the order they were added (legend first); SSC_LEGEND_NONE hides
 * an axes' legend.  The corner values are kept for callers and mean the
 * same panel. */
enum ssc_legend_pos {
	SSC_LEGEND_AUTO = 0,
	SSC_LEGEND_UR,
	SSC_LEGEND_UL,
	SSC_LEGEND_LR,
	SSC_LEGEND_LL,
	SSC_LEGEND_NONE,
};

/* Style of a series.  color 0 takes the next colour of the palette. */
struct ssc_style {
	uint32_t color;   /* 0xRRGGBB, or 0 for automatic */
	double width;     /* line width in px; 0 -> 2; < 0 -> no line */
	enum ssc_dash dash;
	enum ssc_marker marker;
	double marker_size; /* px; 0 -> 7 */
};

/* The palette (matplotlib's "tab10"), for callers that pair colours. */
uint32_t ssc_plot_color(size_t k);

struct ssc_fig *ssc_fig_new(int width_px, int height_px, int rows, int cols);
void ssc_fig_free(struct ssc_fig *fig);
void ssc_fig_title(struct ssc_fig *fig, const char *title);
/* Axes at (row, col); NULL when out of range. */
struct ssc_ax *ssc_fig_ax(struct ssc_fig *fig, int row, int col);

void ssc_ax_title(struct ssc_ax *ax, const char *title);
void ssc_ax_xlabel(struct ssc_ax *ax, const char *label);
void ssc_ax_ylabel(struct ssc_ax *ax, const char *label);
void ssc_ax_log(struct ssc_ax *ax, bool logx, bool logy);
void ssc_ax_xlim(struct ssc_ax *ax, double lo, double hi);
void ssc_ax_ylim(struct ssc_ax *ax, double lo, double hi);
void ssc_ax_legend(struct ssc_ax *ax, enum ssc_legend_pos pos);
void ssc_ax_grid(struct ssc_ax *ax, bool on);

/* Series (data are copied).  Non-finite points break lines; on log axes
 * non-positive points are skipped. */
int ssc_ax_line(struct ssc_ax *ax, const double *x, const double *y, size_t n,
		const struct ssc_style *st, const char *label);
/* The same with y shown as (y - offset) / scale (a unit conversion as
 * sscope_unit_from_si()), without a converted copy of a long series. */
int ssc_ax_line_scaled(struct ssc_ax *ax, const double *x, const double *y,
		       size_t n, double offset, double scale,
		       const struct ssc_style *st, const char *label);
/* Series that share one long x (the channels of a capture against its
 * time column): which stretches of x are finite, looked up once (NULL
 * when x is short enough to be kept whole, or out of memory; free()),
 * then given with each series.  The same figure as ssc_ax_line_scaled(). */
bool *ssc_line_x_finite(const double *x, size_t n);
int ssc_ax_line_scaled_x(struct ssc_ax *ax, const double *x,
			 const bool *x_finite, const double *y, size_t n,
			 double offset, double scale,
			 const struct ssc_style *st, const char *label);
/* How many runs of points a long line keeps: the bins of the envelopes
 * ssc_ax_line_envelope_x() takes. */
#define SSC_PLOT_LINE_BINS 4096
struct sscope_clip_envelope;
/* ssc_ax_line_scaled_x() with the envelope of y in SSC_PLOT_LINE_BINS bins
 * found beforehand (sscope_clip_detect_stats_envelope(), NULL: none): a
 * long line's runs of points are then mostly taken from it instead of
 * reading y again.  The same figure. */
int ssc_ax_line_envelope_x(struct ssc_ax *ax, const double *x,
			   const bool *x_finite, const double *y, size_t n,
			   double offset, double scale,
			   const struct sscope_clip_envelope *env,
			   const struct ssc_style *st, const char *label);
/* Vertical error bars from lo[i] to hi[i] at x[i], with the point y[i]. */
int ssc_ax_errorbar(struct ssc_ax *ax, const double *x, const double *y,
		    const double *lo, const double *hi, size_t n,
		    const struct ssc_style *st, const char *label);
/* A band between lo and hi filled with translucent colour. */
int ssc_ax_band(struct ssc_ax *ax, const double *x, const double *lo,
		const double *hi, size_t n, uint32_t color, double alpha,
		const char *label);
int ssc_ax_vline(struct ssc_ax *ax, double x, const struct ssc_style *st,
		 const char *label);
int ssc_ax_hline(struct ssc_ax *ax, double y, const struct ssc_style *st,
		 const char *label);
/* Text at data coordinates; align -1 left, 0 centre, 1 right. */
int ssc_ax_text(struct ssc_ax *ax, double x, double y, const char *text,
		int align, uint32_t color);
/* A boxed note of one or more lines ('\n') in a corner of the axes. */
int ssc_ax_note(struct ssc_ax *ax, const char *text, enum ssc_legend_pos pos);
/* An image z[iy * nx + ix] over [x0,x1]x[y0,y1] (row 0 at y0), coloured by
 * viridis between zlo and zhi (log10 first when zlog); a colour bar with
 * @p zlabel is drawn beside the axes. */
int ssc_ax_image(struct ssc_ax *ax, const double *z, size_t nx, size_t ny,
		 double x0, double x1, double y0, double y1, double zlo,
		 double zhi, bool zlog, const char *zlabel);

/* Render and write a PNG atomically.  Returns 0, -ENOTSUP without OpenCV,
 * -EINVAL for an empty figure, -errno from the file system.  A figure may
 * come out taller than asked when its legends need the room. */
int ssc_fig_save_png(struct ssc_fig *fig, const char *path);
/* The same as an SVG file (no OpenCV needed). */
int ssc_fig_save_svg(struct ssc_fig *fig, const char *path);
/* The figure as an SVG document in memory (*buf malloc'ed, NUL-terminated)
 * whose ids start with id_prefix (NULL: "fig"), for embedding in HTML.
 * Returns 0, -EINVAL for an empty figure, -ENOMEM. */
int ssc_fig_svg(struct ssc_fig *fig, const char *id_prefix, char **buf,
		size_t *len);

enum ssc_plot_format { SSC_PLOT_NONE = 0, SSC_PLOT_PNG, SSC_PLOT_SVG };
/* The format a figure path asks for, by its extension (.png, .svg, any
 * case). */
enum ssc_plot_format ssc_plot_format_of(const char *path);
/* Write in the format of the path's extension (-EINVAL for another); a
 * path ending in SSC_PLOT_SVG_AND_PNG writes both files, BASE.svg and
 * BASE.png, from one drawing (scenes that keep both). */
#define SSC_PLOT_SVG_AND_PNG ".{svg,png}"
int ssc_fig_save(struct ssc_fig *fig, const char *path);

/* Tick computation (exported for tests): up to max ticks. */
size_t ssc_ticks_linear(double lo, double hi, size_t target, double *ticks,
			size_t max, double *step);
/* Decade ticks 10^k in [lo, hi] (major) and minor ticks 2..9 x 10^k. */
size_t ssc_ticks_log(double lo, double hi, double *major, size_t max_major,
		     double *minor, size_t max_minor, size_t *n_minor);

/* The dynamic Allan deviation of one channel (sscope-adequacy.h) on ax:
 * each window's deviation over the fitted model's (else the median of the
 * windows at that tau) as an image over the window centre and tau (log),
 * coloured on a log scale from 1/4 to 4, with the time ranges of the
 * findings that doubt the terms as dashed lines.  Returns 0, -EDOM (no
 * map), -ENOMEM. */
struct sscope_adequacy;
int ssc_plot_davar(struct ssc_ax *ax, const struct sscope_adequacy *q,
		   const char *title);

#endif
