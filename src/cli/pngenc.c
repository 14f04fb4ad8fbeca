/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * PNG encoder (ISO/IEC 15948) through libpng, writing into a growing memory
 * buffer.  The settings are the ones OpenCV's own encoder uses when asked for
 * speed (SUB filter, zlib level 1, run-length strategy): plots are mostly
 * flat colour, which these compress well, and encoding stays a few
 * milliseconds.  Pixels are lossless, so a figure is the same image as
 * before; only the compressed bytes may differ.
 */
#include "config.h"

#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "pngenc.h"

struct membuf {
	unsigned char *p;
	size_t n, cap;
	int err;
};

static void put(png_structp png, png_bytep data, size_t n)
{
	struct membuf *b = png_get_io_ptr(png);

	if (n > b->cap - b->n) {
		size_t cap = b->cap ? b->cap : 1 << 16;
		unsigned char *q;

		while (n > cap - b->n) {
			if (cap > SIZE_MAX / 2) {
				b->err = -ENOMEM;
				png_error(png, "image too large");
			}
			cap *= 2;
		}
		q = realloc(b->p, cap);
		if (!q) {
			b->err = -ENOMEM;
			png_error(png, "out of memory");
		}
		b->p = q;
		b->cap = cap;
	}
	memcpy(b->p + b->n, data, n);
	b->n += n;
}

static void flush(png_structp png)
{
	(void)png;
}

/* libpng reports through longjmp; keep its messages off stderr */
static void quiet(png_structp png, png_const_charp msg)
{
	(void)png;
	(void)msg;
}

static void fail(png_structp png, png_const_charp msg)
{
	(void)msg;
	png_longjmp(png, 1);
}

int ssc_png_encode(const unsigned char *pix, int w, int h, size_t stride,
		   int bgr, unsigned char **out, size_t *len)
{
	struct membuf *b;
	png_structp png;
	png_infop info = NULL;
	int rc;

	if (w <= 0 || h <= 0 || stride < (size_t)w * 3)
		return -EINVAL;
	b = calloc(1, sizeof(*b));
	if (!b)
		return -ENOMEM;
	png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, fail, quiet);
	if (png)
		info = png_create_info_struct(png);
	if (!png || !info) {
		png_destroy_write_struct(&png, NULL);
		free(b);
		return -ENOMEM;
	}
	if (setjmp(png_jmpbuf(png))) {
		rc = b->err ? b->err : -EIO;
		png_destroy_write_struct(&png, &info);
		free(b->p);
		free(b);
		return rc;
	}
	png_set_write_fn(png, b, put, flush);
	png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8,
		     PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
		     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
	png_set_compression_level(png, Z_BEST_SPEED);
	png_set_compression_strategy(png, Z_RLE);
	png_write_info(png, info);
	if (bgr)
		png_set_bgr(png);
	for (int r = 0; r < h; r++)
		png_write_row(png, pix + (size_t)r * stride);
	png_write_end(png, info);
	png_destroy_write_struct(&png, &info);
	*out = b->p;
	*len = b->n;
	free(b);
	return 0;
}
