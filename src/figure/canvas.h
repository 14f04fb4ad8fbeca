/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Drawing surfaces behind the plotting layer (plot.c): the figure is laid
 * out once in pixels and drawn through one of these, the OpenCV raster
 * canvas (cvshim.cpp, PNG) or the SVG writer (svg.c).  Text carries the
 * markup "^{...}" (superscript) and "_{...}" (subscript).
 */
#ifndef SSCOPE_CANVAS_H
#define SSCOPE_CANVAS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Size of super- and subscripts relative to their text, and their shift
 * of the baseline in units of the text's size. */
#define SSC_SCRIPT_SCALE 0.85
#define SSC_SUP_SHIFT 0.42
#define SSC_SUB_SHIFT 0.2

struct ssc_surface_ops {
	/* Restrict drawing to a rectangle; w <= 0 lifts the restriction. */
	void (*clip)(void *ctx, double x, double y, double w, double h);
	/* dash: NULL for a solid line, else 4 on/off lengths in px */
	void (*polyline)(void *ctx, const double *xy, size_t n, uint32_t rgb,
			 double width, const double *dash);
	void (*fill)(void *ctx, const double *xy, size_t n, uint32_t rgb,
		     double alpha);
	void (*rect)(void *ctx, double x, double y, double w, double h,
		     uint32_t rgb, double width, int filled);
	void (*circle)(void *ctx, double x, double y, double r, uint32_t rgb,
		       double width, int filled);
	/* Text with markup; (x, y) on the baseline, align -1 left, 0 centre,
	 * 1 right of x; vertical != 0 turns it 90 degrees counter-clockwise
	 * about (x, y). */
	void (*text)(void *ctx, double x, double y, const char *rich,
		     double size_px, uint32_t rgb, int align, int vertical);
	double (*text_width)(void *ctx, const char *rich, double size_px);
	/* Values v[iy * iw + ix] in [0, 1] (NaN: white) coloured by viridis
	 * into the rectangle; row 0 at the bottom. */
	void (*image)(void *ctx, double x, double y, double w, double h,
		      const double *v, int iw, int ih);
	/* Open a named group of what follows (cls != NULL; attrs: extra
	 * name="value" pairs or NULL) or close the last one (cls == NULL).
	 * Raster surfaces ignore groups. */
	void (*group)(void *ctx, const char *cls, const char *attrs);
};

struct ssc_surface {
	const struct ssc_surface_ops *ops;
	void *ctx;
	bool native_dash; /* the surface draws dashes itself */
};

/* One run of rich text: level 0 normal, 1 superscript, -1 subscript. */
struct ssc_rich_run {
	const char *s;
	size_t n;
	int level;
};

/* Split rich text into at most max runs; returns their number.  Besides
 * the braces, a caret before an integer ("m/s^2", "Hz^-1") raises it. */
size_t ssc_rich_split(const char *text, struct ssc_rich_run *runs, size_t max);

/* Advance width of a Unicode character in DejaVu Sans, in ems. */
double ssc_font_advance_em(unsigned codepoint);

/* Decode one UTF-8 character at *s (advancing *s); invalid bytes decode
 * as U+FFFD one at a time. */
unsigned ssc_utf8_next(const char **s, const char *end);

/* viridis colour (0xRRGGBB) of t in [0, 1]. */
uint32_t ssc_viridis(double t);

/* The SVG surface (svg.c).  id_prefix makes the ids of clip paths unique
 * when several figures share one HTML page. */
struct ssc_svg;
struct ssc_svg *ssc_svg_new(double w, double h, const char *id_prefix,
			    struct ssc_surface *out);
/* Finish the document; *buf (malloc'ed, NUL-terminated) goes to the
 * caller.  Returns 0, -ENOMEM.  The writer is freed in any case. */
int ssc_svg_finish(struct ssc_svg *s, char **buf, size_t *len);
void ssc_svg_free(struct ssc_svg *s);

#endif
