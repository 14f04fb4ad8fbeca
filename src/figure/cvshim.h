/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * C interface of the OpenCV drawing shim (cvshim.cpp): the only C++ in
 * sensorscope, linked into the CLI only.  Coordinates are pixels with
 * sub-pixel precision; colours are 0xRRGGBB.
 */
#ifndef SSCOPE_CVSHIM_H
#define SSCOPE_CVSHIM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct ssc_canvas;

/* White canvas; font_path names a TrueType font (NULL or missing: the
 * built-in Hershey font, ASCII only). */
struct ssc_canvas *ssc_canvas_new(int w, int h, const char *font_path);
void ssc_canvas_free(struct ssc_canvas *c);
/* Restrict drawing to a rectangle (w <= 0 removes the restriction). */
void ssc_canvas_clip(struct ssc_canvas *c, int x, int y, int w, int h);
void ssc_canvas_polyline(struct ssc_canvas *c, const double *xy, size_t n,
			 uint32_t rgb, double width);
void ssc_canvas_fill(struct ssc_canvas *c, const double *xy, size_t n,
		     uint32_t rgb, double alpha);
void ssc_canvas_rect(struct ssc_canvas *c, double x, double y, double w,
		     double h, uint32_t rgb, double width, int filled);
void ssc_canvas_circle(struct ssc_canvas *c, double x, double y, double r,
		       uint32_t rgb, double width, int filled);
/* Text with its left end of the baseline at (x, y); vertical != 0 draws it
 * rotated 90 degrees counter-clockwise with (x, y) the left end of the
 * baseline after rotation (bottom of the text). */
void ssc_canvas_text(struct ssc_canvas *c, double x, double y,
		     const char *utf8, double size_px, uint32_t rgb,
		     int vertical);
/* Advance width, ascent and descent of a text. */
void ssc_canvas_text_size(struct ssc_canvas *c, const char *utf8,
			  double size_px, double *w, double *ascent,
			  double *descent);
/* Blit values v[iy * iw + ix] in [0, 1] (NaN: white) coloured by viridis
 * into the rectangle; row 0 goes to the bottom. */
void ssc_canvas_image(struct ssc_canvas *c, int x, int y, int w, int h,
		      const double *v, int iw, int ih);
/* Encode as PNG; *buf is malloc'ed.  Returns 0 or -1. */
int ssc_canvas_png(struct ssc_canvas *c, unsigned char **buf, size_t *len);

#ifdef __cplusplus
}
#endif

#endif
