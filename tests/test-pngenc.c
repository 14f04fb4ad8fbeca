/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The PNG encoder of figures (src/cli/pngenc.c) against libpng's reader:
 * every image, whatever its size, row stride, byte order and number of
 * bands compressed on their own threads, decodes (chunk CRCs, zlib stream
 * and Adler-32 checked by libpng) to exactly its pixels; bad sizes are
 * refused.
 */
#include "config.h"

#include <errno.h>
#include <png.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "pngenc.h"
#include "check-main.h"

/* a test image: flat areas, lines and noise, as a plot has */
static unsigned char *image(int h, size_t stride, uint32_t seed)
{
	unsigned char *p = malloc(stride * (size_t)h);
	uint32_t s = seed * 2654435761u + 1;

	for (int r = 0; r < h; r++)
		for (size_t i = 0; i < stride; i++) {
			unsigned char v = 255;

			s = s * 1664525u + 1013904223u;
			if ((r / 7 + (int)i / 21) % 5 == 0)
				v = (unsigned char)(s >> 24); /* noise */
			else if (r % 50 == 0 || i % 97 == 0)
				v = (unsigned char)(40 + i % 3 * 60); /* lines */
			p[(size_t)r * stride + i] = v;
		}
	return p;
}

/* encode with nb bands (0: the automatic count), decode, compare */
static void round_trip(int w, int h, size_t stride, int bgr, int nb)
{
	unsigned char *pix = image(h, stride, (uint32_t)(w * 131 + h + nb)), *png = NULL, *back;
	size_t len = 0;
	png_image im;
	int rc = nb ? ssc_png_encode_bands(pix, w, h, stride, bgr, nb, &png, &len) :
		      ssc_png_encode(pix, w, h, stride, bgr, &png, &len);

	ck_assert_msg(rc == 0, "%dx%d, %d bands: rc %d", w, h, nb, rc);
	memset(&im, 0, sizeof(im));
	im.version = PNG_IMAGE_VERSION;
	ck_assert_msg(png_image_begin_read_from_memory(&im, png, len),
		      "%dx%d, %d bands: %s", w, h, nb, im.message);
	ck_assert_int_eq(im.width, w);
	ck_assert_int_eq(im.height, h);
	im.format = PNG_FORMAT_RGB;
	back = malloc(PNG_IMAGE_SIZE(im));
	ck_assert_msg(png_image_finish_read(&im, NULL, back, 0, NULL),
		      "%dx%d, %d bands: %s", w, h, nb, im.message);
	for (int r = 0; r < h; r++)
		for (int i = 0; i < w; i++) {
			const unsigned char *a = pix + (size_t)r * stride + 3 * (size_t)i;
			const unsigned char *b = back + ((size_t)r * w + i) * 3;

			ck_assert_msg(b[0] == a[bgr ? 2 : 0] && b[1] == a[1] &&
					      b[2] == a[bgr ? 0 : 2],
				      "%dx%d, %d bands: pixel (%d, %d) differs", w,
				      h, nb, i, r);
		}
	free(back);
	free(png);
	free(pix);
}

START_TEST(round_trips)
{
	static const int sz[][2] = { { 1, 1 }, { 2, 3 }, { 17, 5 }, { 640, 480 },
				     { 1100, 1740 }, { 3, 2000 } };

	for (size_t k = 0; k < sizeof(sz) / sizeof(sz[0]); k++)
		for (int nb = 0; nb <= 4; nb++) {
			int w = sz[k][0], h = sz[k][1];

			round_trip(w, h, 3 * (size_t)w, 1, nb);
			round_trip(w, h, 3 * (size_t)w + 5, 0, nb);
		}
}
END_TEST

START_TEST(bands_change_no_pixel)
{
	/* more bands than rows: one a row */
	round_trip(40, 3, 120, 1, 4);
	/* a large figure: the automatic count uses the processors */
	round_trip(2200, 1800, 6600, 1, 0);
}
END_TEST

START_TEST(bad_sizes)
{
	unsigned char px[12] = { 0 }, *out = NULL;
	size_t len = 0;

	ck_assert_int_eq(ssc_png_encode(px, 0, 1, 3, 0, &out, &len), -EINVAL);
	ck_assert_int_eq(ssc_png_encode(px, 1, 0, 3, 0, &out, &len), -EINVAL);
	ck_assert_int_eq(ssc_png_encode(px, 2, 1, 5, 0, &out, &len), -EINVAL);
	ck_assert_int_eq(ssc_png_encode_bands(px, 1, 1, 3, 0, 0, &out, &len), -EINVAL);
	ck_assert_int_eq(ssc_png_encode_bands(px, 1, 1, 3, 0, 5, &out, &len), -EINVAL);
	ck_assert_ptr_null(out);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("pngenc");
	TCase *tc = tcase_create("pngenc");

	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, round_trips);
	tcase_add_test(tc, bands_change_no_pixel);
	tcase_add_test(tc, bad_sizes);
	suite_add_tcase(s, tc);
	return s;
}
