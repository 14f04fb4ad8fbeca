/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * SVG surface (canvas.h): the figure as SVG 1.1 text, sharp at any zoom
 * and in print.  Text stays text (DejaVu Sans first in the font list, the
 * font whose advance widths the layout uses), superscripts are tspans with
 * a dy shift, dashes are stroke-dasharray, clipping is a clipPath, and the
 * semantic groups of the layout (axes, plot area, data, legend, labels)
 * become <g class="..."> elements that tests and style sheets can find.
 * Text is escaped for XML; invalid UTF-8 and control characters are
 * replaced, so any column or file name gives a well-formed document.
 * Images (spectrograms) are embedded as PNG data (PNG 1.2: 8-bit RGB rows,
 * filter 0, deflated by zlib, CRCs by zlib's crc32; base64 by nettle),
 * drawn with pixelated scaling, so the SVG needs no OpenCV.
 */
#include "config.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <zlib.h>

#include "canvas.h"
#include "base64.h"

struct ssc_svg {
	char *buf;
	size_t len, cap;
	bool failed;
	double w, h;
	char prefix[40];
	unsigned n_clip;
	bool clipped;
};

static void put(struct ssc_svg *s, const char *p, size_t n)
{
	if (s->failed)
		return;
	if (s->len + n + 1 > s->cap) {
		size_t nc = s->cap ? s->cap : 65536;
		char *nb;

		while (s->len + n + 1 > nc)
			nc *= 2;
		nb = realloc(s->buf, nc);
		if (!nb) {
			s->failed = true;
			return;
		}
		s->buf = nb;
		s->cap = nc;
	}
	memcpy(s->buf + s->len, p, n);
	s->len += n;
	s->buf[s->len] = '\0';
}

static void puts_(struct ssc_svg *s, const char *p)
{
	put(s, p, strlen(p));
}

static void __attribute__((format(printf, 2, 3)))
putf(struct ssc_svg *s, const char *fmt, ...)
{
	char tmp[512];
	va_list ap;
	int n;

	va_start(ap, fmt);
	n = vsnprintf(tmp, sizeof(tmp), fmt, ap);
	va_end(ap);
	if (n < 0)
		return;
	put(s, tmp, (size_t)n < sizeof(tmp) ? (size_t)n : sizeof(tmp) - 1);
}

/* A coordinate with two decimals, without "-0" and trailing zeros: what
 * "%.2f" prints, trimmed.  The digits come from the integer nearest to
 * 100 |v| (at most 1e8, so the product is within 2^-26 of the exact one
 * and its nearest integer is the exact one's unless the fraction is
 * within 1e-6 of a half); those near-ties are left to snprintf, which
 * rounds the exact binary value.  A figure has hundreds of thousands of
 * coordinates. */
static void num(struct ssc_svg *s, double v)
{
	char b[40], d[24];
	size_t n = 0, k = 0;
	double a, c, r, f;
	unsigned long long q;
	unsigned ip, fr;

	if (!isfinite(v))
		v = 0;
	v = fmax(-1e6, fmin(1e6, v));
	a = fabs(v);
	c = a * 100;
	r = floor(c);
	f = c - r;
	if (fabs(f - 0.5) < 1e-6) {
		n = (size_t)snprintf(b, sizeof(b), "%.2f", v);
		while (n > 1 && b[n - 1] == '0')
			n--;
		if (b[n - 1] == '.')
			n--;
		b[n] = '\0';
		if (!strcmp(b, "-0"))
			strcpy(b, "0");
		puts_(s, b);
		return;
	}
	q = (unsigned long long)r + (f > 0.5);
	ip = (unsigned)(q / 100);
	fr = (unsigned)(q % 100);
	if (q && v < 0)
		b[n++] = '-';
	do {
		d[k++] = (char)('0' + ip % 10);
		ip /= 10;
	} while (ip);
	while (k)
		b[n++] = d[--k];
	if (fr) {
		b[n++] = '.';
		b[n++] = (char)('0' + fr / 10);
		if (fr % 10)
			b[n++] = (char)('0' + fr % 10);
	}
	put(s, b, n);
}

/* ' x="" y="" width="" height=""' of a rectangle */
static void xywh(struct ssc_svg *s, double x, double y, double w, double h)
{
	puts_(s, " x=\"");
	num(s, x);
	puts_(s, "\" y=\"");
	num(s, y);
	puts_(s, "\" width=\"");
	num(s, w);
	puts_(s, "\" height=\"");
	num(s, h);
	puts_(s, "\"");
}

static void color(struct ssc_svg *s, uint32_t rgb)
{
	putf(s, "#%06x", (unsigned)(rgb & 0xffffff));
}

/* XML text: escaped, valid UTF-8, no control characters. */
static void esc_n(struct ssc_svg *s, const char *t, size_t n)
{
	const char *p = t, *end = t + n;

	while (p < end && *p) {
		const char *start = p;
		unsigned cp = ssc_utf8_next(&p, end);

		if (cp == '<')
			puts_(s, "&lt;");
		else if (cp == '>')
			puts_(s, "&gt;");
		else if (cp == '&')
			puts_(s, "&amp;");
		else if (cp == '"')
			puts_(s, "&quot;");
		else if (cp < 0x20 || cp == 0x7f || (cp >= 0x80 && cp < 0xa0))
			puts_(s, "\xef\xbf\xbd");
		else if (cp == 0xfffd)
			puts_(s, "\xef\xbf\xbd");
		else
			put(s, start, (size_t)(p - start));
	}
}

static void points(struct ssc_svg *s, const double *xy, size_t n)
{
	puts_(s, " points=\"");
	for (size_t i = 0; i < n; i++) {
		if (i)
			puts_(s, " ");
		num(s, xy[2 * i]);
		puts_(s, ",");
		num(s, xy[2 * i + 1]);
	}
	puts_(s, "\"");
}

static void sv_clip(void *ctx, double x, double y, double w, double h)
{
	struct ssc_svg *s = ctx;

	if (s->clipped) {
		puts_(s, "</g>\n");
		s->clipped = false;
	}
	if (w <= 0 || h <= 0)
		return;
	s->n_clip++;
	putf(s, "<clipPath id=\"%s-clip%u\"><rect", s->prefix, s->n_clip);
	xywh(s, x, y, w, h);
	putf(s, "/></clipPath>\n<g clip-path=\"url(#%s-clip%u)\">\n",
	     s->prefix, s->n_clip);
	s->clipped = true;
}

static void stroke_attrs(struct ssc_svg *s, uint32_t rgb, double width)
{
	puts_(s, " fill=\"none\" stroke=\"");
	color(s, rgb);
	puts_(s, "\" stroke-width=\"");
	num(s, width > 0 ? width : 1);
	puts_(s, "\"");
}

static void sv_polyline(void *ctx, const double *xy, size_t n, uint32_t rgb,
			double width, const double *dash)
{
	struct ssc_svg *s = ctx;

	if (n < 2)
		return;
	puts_(s, "<polyline");
	points(s, xy, n);
	stroke_attrs(s, rgb, width);
	puts_(s, " stroke-linejoin=\"round\" stroke-linecap=\"butt\"");
	if (dash) {
		puts_(s, " stroke-dasharray=\"");
		for (int i = 0; i < 4; i++) {
			if (i)
				puts_(s, ",");
			num(s, dash[i]);
		}
		puts_(s, "\"");
	}
	puts_(s, "/>\n");
}

static void sv_fill(void *ctx, const double *xy, size_t n, uint32_t rgb,
		    double alpha)
{
	struct ssc_svg *s = ctx;

	if (n < 3)
		return;
	puts_(s, "<polygon");
	points(s, xy, n);
	puts_(s, " fill=\"");
	color(s, rgb);
	puts_(s, "\" stroke=\"none\"");
	if (alpha < 1) {
		puts_(s, " fill-opacity=\"");
		num(s, alpha > 0 ? alpha : 0);
		puts_(s, "\"");
	}
	puts_(s, "/>\n");
}

static void sv_rect(void *ctx, double x, double y, double w, double h,
		    uint32_t rgb, double width, int filled)
{
	struct ssc_svg *s = ctx;

	puts_(s, "<rect");
	xywh(s, w < 0 ? x + w : x, h < 0 ? y + h : y, fabs(w), fabs(h));
	if (filled) {
		puts_(s, " fill=\"");
		color(s, rgb);
		puts_(s, "\"");
	} else {
		stroke_attrs(s, rgb, width);
	}
	puts_(s, "/>\n");
}

static void sv_circle(void *ctx, double x, double y, double r, uint32_t rgb,
		      double width, int filled)
{
	struct ssc_svg *s = ctx;

	puts_(s, "<circle cx=\"");
	num(s, x);
	puts_(s, "\" cy=\"");
	num(s, y);
	puts_(s, "\" r=\"");
	num(s, r);
	puts_(s, "\"");
	if (filled) {
		puts_(s, " fill=\"");
		color(s, rgb);
		puts_(s, "\"");
	} else {
		stroke_attrs(s, rgb, width);
	}
	puts_(s, "/>\n");
}

static double sv_text_width(void *ctx, const char *rich, double size)
{
	struct ssc_rich_run runs[32];
	size_t n = ssc_rich_split(rich, runs, 32);
	double w = 0;

	(void)ctx;
	for (size_t i = 0; i < n; i++) {
		const char *p = runs[i].s, *end = runs[i].s + runs[i].n;
		double em = 0;

		while (p < end)
			em += ssc_font_advance_em(ssc_utf8_next(&p, end));
		w += em * (runs[i].level ? size * SSC_SCRIPT_SCALE : size);
	}
	return w;
}

static void sv_text(void *ctx, double x, double y, const char *rich,
		    double size, uint32_t rgb, int align, int vertical)
{
	struct ssc_svg *s = ctx;
	struct ssc_rich_run runs[32];
	size_t n = ssc_rich_split(rich, runs, 32);
	double shift = 0;

	if (!n)
		return;
	puts_(s, "<text xml:space=\"preserve\" x=\"");
	num(s, x);
	puts_(s, "\" y=\"");
	num(s, y);
	puts_(s, "\" font-size=\"");
	num(s, size);
	puts_(s, "\" fill=\"");
	color(s, rgb);
	puts_(s, "\"");
	if (align == 0)
		puts_(s, " text-anchor=\"middle\"");
	else if (align > 0)
		puts_(s, " text-anchor=\"end\"");
	if (vertical) {
		puts_(s, " transform=\"rotate(-90 ");
		num(s, x);
		puts_(s, " ");
		num(s, y);
		puts_(s, ")\"");
	}
	puts_(s, ">");
	for (size_t i = 0; i < n; i++) {
		double want = runs[i].level > 0 ? -SSC_SUP_SHIFT * size :
			      runs[i].level < 0 ? SSC_SUB_SHIFT * size :
						  0;

		if (!runs[i].level && shift == 0) {
			esc_n(s, runs[i].s, runs[i].n);
			continue;
		}
		puts_(s, "<tspan");
		if (want != shift) {
			puts_(s, " dy=\"");
			num(s, want - shift);
			puts_(s, "\"");
			shift = want;
		}
		if (runs[i].level) {
			puts_(s, " font-size=\"");
			num(s, size * SSC_SCRIPT_SCALE);
			puts_(s, "\"");
		}
		puts_(s, ">");
		esc_n(s, runs[i].s, runs[i].n);
		puts_(s, "</tspan>");
	}
	puts_(s, "</text>\n");
}

/* A PNG chunk: length, type, data, CRC of type and data. */
static unsigned char *chunk(unsigned char *o, const char *type,
			    const unsigned char *data, uint32_t len)
{
	uLong crc;

	o[0] = (unsigned char)(len >> 24);
	o[1] = (unsigned char)(len >> 16);
	o[2] = (unsigned char)(len >> 8);
	o[3] = (unsigned char)len;
	memcpy(o + 4, type, 4);
	if (len)
		memcpy(o + 8, data, len);
	crc = crc32(0L, o + 4, 4 + len);
	o[8 + len] = (unsigned char)(crc >> 24);
	o[9 + len] = (unsigned char)(crc >> 16);
	o[10 + len] = (unsigned char)(crc >> 8);
	o[11 + len] = (unsigned char)crc;
	return o + 12 + len;
}

/* The image's cells coloured by viridis (NaN white) as a PNG in memory;
 * row 0 of v is the bottom row.  NULL when out of memory. */
static unsigned char *png_of(const double *v, int iw, int ih, size_t *len)
{
	size_t raw_len = (size_t)ih * (3 * (size_t)iw + 1);
	uLongf zlen = compressBound((uLong)raw_len);
	unsigned char *raw = malloc(raw_len), *z = malloc(zlen), *png = NULL;
	unsigned char ihdr[13] = { 0 };

	if (!raw || !z)
		goto out;
	for (int r = 0; r < ih; r++) {
		unsigned char *row = raw + (size_t)r * (3 * (size_t)iw + 1);
		const double *src = v + (size_t)(ih - 1 - r) * (size_t)iw;

		row[0] = 0; /* filter: none */
		for (int k = 0; k < iw; k++) {
			uint32_t c = isfinite(src[k]) ? ssc_viridis(src[k]) :
							0xffffff;

			row[1 + 3 * k] = (unsigned char)(c >> 16);
			row[2 + 3 * k] = (unsigned char)(c >> 8);
			row[3 + 3 * k] = (unsigned char)c;
		}
	}
	if (compress2(z, &zlen, raw, (uLong)raw_len, 9) != Z_OK)
		goto out;
	png = malloc(8 + 25 + 12 + zlen + 12);
	if (!png)
		goto out;
	memcpy(png, "\x89PNG\r\n\x1a\n", 8);
	for (int i = 0; i < 4; i++) {
		ihdr[i] = (unsigned char)((unsigned)iw >> (24 - 8 * i));
		ihdr[4 + i] = (unsigned char)((unsigned)ih >> (24 - 8 * i));
	}
	ihdr[8] = 8; /* bit depth */
	ihdr[9] = 2; /* truecolour */
	{
		unsigned char *o = chunk(png + 8, "IHDR", ihdr, 13);

		o = chunk(o, "IDAT", z, (uint32_t)zlen);
		o = chunk(o, "IEND", NULL, 0);
		*len = (size_t)(o - png);
	}
out:
	free(raw);
	free(z);
	return png;
}

static void sv_image(void *ctx, double x, double y, double w, double h,
		     const double *v, int iw, int ih)
{
	struct ssc_svg *s = ctx;
	unsigned char *png;
	char *txt;
	size_t len = 0, n = 0;

	if (w <= 0 || h <= 0 || iw <= 0 || ih <= 0)
		return;
	png = png_of(v, iw, ih, &len);
	txt = png ? ssc_base64(png, len, &n) : NULL;
	if (!txt) {
		free(png);
		s->failed = true;
		return;
	}
	puts_(s, "<image class=\"image\"");
	xywh(s, x, y, w, h);
	puts_(s, " preserveAspectRatio=\"none\" "
		 "style=\"image-rendering:pixelated\" "
		 "xlink:href=\"data:image/png;base64,");
	put(s, txt, n);
	puts_(s, "\"/>\n");
	free(txt);
	free(png);
}

static void sv_group(void *ctx, const char *cls, const char *attrs)
{
	struct ssc_svg *s = ctx;

	if (!cls) {
		puts_(s, "</g>\n");
		return;
	}
	puts_(s, "<g class=\"");
	esc_n(s, cls, strlen(cls));
	puts_(s, "\"");
	if (attrs && *attrs) {
		puts_(s, " ");
		puts_(s, attrs);
	}
	puts_(s, ">\n");
}

static const struct ssc_surface_ops svg_ops = {
	.clip = sv_clip,
	.polyline = sv_polyline,
	.fill = sv_fill,
	.rect = sv_rect,
	.circle = sv_circle,
	.text = sv_text,
	.text_width = sv_text_width,
	.image = sv_image,
	.group = sv_group,
};

struct ssc_svg *ssc_svg_new(double w, double h, const char *id_prefix,
			    struct ssc_surface *out)
{
	struct ssc_svg *s = calloc(1, sizeof(*s));
	size_t k = 0;

	if (!s)
		return NULL;
	s->w = w;
	s->h = h;
	/* ids: letters, digits, '-' and '_' only */
	for (const char *p = id_prefix && *id_prefix ? id_prefix : "fig";
	     *p && k + 1 < sizeof(s->prefix); p++)
		s->prefix[k++] = (char)((*p >= 'a' && *p <= 'z') ||
						(*p >= 'A' && *p <= 'Z') ||
						(*p >= '0' && *p <= '9') ||
						*p == '-' || *p == '_' ?
					*p :
					'_');
	puts_(s, "<svg xmlns=\"http://www.w3.org/2000/svg\" "
		 "xmlns:xlink=\"http://www.w3.org/1999/xlink\" version=\"1.1\" "
		 "width=\"");
	num(s, w);
	puts_(s, "\" height=\"");
	num(s, h);
	puts_(s, "\" viewBox=\"0 0 ");
	num(s, w);
	puts_(s, " ");
	num(s, h);
	puts_(s, "\" font-family=\"'DejaVu Sans', Verdana, Arial, sans-serif\">\n"
		 "<rect class=\"background\" x=\"0\" y=\"0\" width=\"100%\" "
		 "height=\"100%\" fill=\"#ffffff\"/>\n");
	if (s->failed) {
		ssc_svg_free(s);
		return NULL;
	}
	out->ops = &svg_ops;
	out->ctx = s;
	out->native_dash = true;
	return s;
}

int ssc_svg_finish(struct ssc_svg *s, char **buf, size_t *len)
{
	int rc = 0;

	sv_clip(s, 0, 0, 0, 0);
	puts_(s, "</svg>\n");
	if (s->failed) {
		rc = -ENOMEM;
	} else {
		*buf = s->buf;
		*len = s->len;
		s->buf = NULL;
	}
	ssc_svg_free(s);
	return rc;
}

void ssc_svg_free(struct ssc_svg *s)
{
	if (!s)
		return;
	free(s->buf);
	free(s);
}
