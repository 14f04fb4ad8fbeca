/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * PNG encoding of an 8-bit, 3-channel image into memory (zlib, bands
 * compressed on several threads), used by the drawing shim so that no
 * OpenCV image codec is needed.
 */
#ifndef SSCOPE_PNGENC_H
#define SSCOPE_PNGENC_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Encode the w x h image whose row r starts at pix + r * stride (3 bytes a
 * pixel, in B, G, R order when bgr != 0, else R, G, B) as PNG.  On success
 * *out is a malloc'ed buffer of *len bytes that the caller frees.
 * Large images are compressed in bands on up to four threads (one per
 * processor).  Returns 0, -EINVAL for a bad size, -ENOMEM, or -EIO if
 * zlib fails.
 */
int ssc_png_encode(const unsigned char *pix, int w, int h, size_t stride,
		   int bgr, unsigned char **out, size_t *len);

/* The same in nb bands (1 to 4, at most one per row), each compressed on
 * a thread of its own: the same image for any nb. */
int ssc_png_encode_bands(const unsigned char *pix, int w, int h,
			 size_t stride, int bgr, int nb, unsigned char **out,
			 size_t *len);

#ifdef __cplusplus
}
#endif

#endif
