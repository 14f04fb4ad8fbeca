/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * PNG encoder (ISO/IEC 15948, W3C PNG 2nd edition) writing into memory.
 * The settings are the ones OpenCV's own encoder uses when asked for speed
 * (SUB filter, zlib level 1, run-length strategy): plots are mostly flat
 * colour, which these compress well.  A large image is compressed in
 * horizontal bands on several threads, each band a raw deflate stream
 * ended by a sync flush (the last by the end of the stream) so that their
 * concatenation is one deflate stream (RFC 1951; pigz does the same), with
 * the zlib header and the Adler-32 of the whole (adler32_combine) around
 * it (RFC 1950).  libpng compresses on one thread only, and its encoder
 * took half the time of a figure: the container (signature, IHDR, IDAT,
 * IEND, CRC-32 from zlib) is written here.  Pixels are lossless, so a
 * figure is the same image as before; only the compressed bytes differ.
 */
#include "config.h"

#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "pngenc.h"

enum {
	BAND_MIN_PIXELS = 1 << 18, /* a band's least pixels worth a thread */
	MAX_BANDS = 4,
};

struct band {
	const unsigned char *pix;
	size_t stride;
	int w, r0, r1, bgr, last;
	unsigned char *z; /* its raw deflate stream */
	size_t zlen;
	uLong adler; /* Adler-32 of its filtered rows */
	size_t raw;  /* their length */
	int rc;
};

/* row r filtered with SUB (type 1) into f: 1 + 3 w bytes */
static void filter_row(const struct band *b, int r, unsigned char *f)
{
	const unsigned char *p = b->pix + (size_t)r * b->stride;
	unsigned char prev[3] = { 0, 0, 0 };

	f[0] = 1;
	for (int i = 0; i < b->w; i++, p += 3) {
		unsigned char c[3];

		c[0] = b->bgr ? p[2] : p[0];
		c[1] = p[1];
		c[2] = b->bgr ? p[0] : p[2];
		for (int k = 0; k < 3; k++) {
			f[1 + 3 * i + k] = (unsigned char)(c[k] - prev[k]);
			prev[k] = c[k];
		}
	}
}

static void *band_run(void *arg)
{
	struct band *b = arg;
	size_t rowb = 1 + 3 * (size_t)b->w, cap;
	unsigned char *f = malloc(rowb);
	z_stream zs;

	memset(&zs, 0, sizeof(zs));
	b->rc = -ENOMEM;
	b->adler = adler32(0L, Z_NULL, 0);
	b->raw = rowb * (size_t)(b->r1 - b->r0);
	if (!f || deflateInit2(&zs, Z_BEST_SPEED, Z_DEFLATED, -15, 8, Z_RLE) != Z_OK) {
		free(f);
		return NULL;
	}
	/* room for the whole band at once, and the flush's empty block */
	cap = deflateBound(&zs, (uLong)b->raw) + 64;
	if (cap > UINT_MAX) {
		b->rc = -EINVAL; /* a band of over 4 GB */
		goto out;
	}
	b->z = malloc(cap);
	if (!b->z)
		goto out;
	zs.next_out = b->z;
	zs.avail_out = (uInt)cap;
	for (int r = b->r0; r < b->r1; r++) {
		filter_row(b, r, f);
		b->adler = adler32(b->adler, f, (uInt)rowb);
		zs.next_in = f;
		zs.avail_in = (uInt)rowb;
		if (deflate(&zs, Z_NO_FLUSH) != Z_OK || zs.avail_in) {
			b->rc = -EIO;
			goto out;
		}
	}
	if (deflate(&zs, b->last ? Z_FINISH : Z_SYNC_FLUSH) !=
	    (b->last ? Z_STREAM_END : Z_OK) || zs.avail_out == 0) {
		b->rc = -EIO;
		goto out;
	}
	b->zlen = cap - zs.avail_out;
	b->rc = 0;
out:
	deflateEnd(&zs);
	free(f);
	return NULL;
}

static unsigned char *be32(unsigned char *p, uint32_t v)
{
	p[0] = (unsigned char)(v >> 24);
	p[1] = (unsigned char)(v >> 16);
	p[2] = (unsigned char)(v >> 8);
	p[3] = (unsigned char)v;
	return p + 4;
}

/* a chunk of type t (4 letters) whose data are the n bytes at d, written
 * at p; returns the end */
static unsigned char *chunk(unsigned char *p, const char *t,
			    const unsigned char *d, size_t n)
{
	uLong crc = crc32(0L, (const Bytef *)t, 4);

	p = be32(p, (uint32_t)n);
	memcpy(p, t, 4);
	p += 4;
	if (n) {
		memcpy(p, d, n);
		crc = crc32(crc, d, (uInt)n);
		p += n;
	}
	return be32(p, (uint32_t)crc);
}

int ssc_png_encode(const unsigned char *pix, int w, int h, size_t stride,
		   int bgr, unsigned char **out, size_t *len)
{
	long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
	size_t nb = w > 0 && h > 0 ? (size_t)w * (size_t)h / BAND_MIN_PIXELS : 1;

	if (ncpu > 0 && nb > (size_t)ncpu)
		nb = (size_t)ncpu;
	return ssc_png_encode_bands(pix, w, h, stride, bgr,
				    nb > MAX_BANDS ? MAX_BANDS : nb < 1 ? 1 : (int)nb,
				    out, len);
}

int ssc_png_encode_bands(const unsigned char *pix, int w, int h,
			 size_t stride, int bgr, int nb, unsigned char **out,
			 size_t *len)
{
	static const unsigned char sig[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
	struct band bands[MAX_BANDS];
	pthread_t tid[MAX_BANDS];
	bool started[MAX_BANDS] = { false };
	unsigned char ihdr[13], *buf = NULL, *idat = NULL, *p;
	size_t zlen = 0, n;
	int rc = 0;
	uLong adler;

	if (w <= 0 || h <= 0 || stride < (size_t)w * 3 || w > (1 << 24) ||
	    h > (1 << 24) || nb < 1 || nb > MAX_BANDS)
		return -EINVAL;
	if (nb > h)
		nb = h;
	for (int i = 0; i < nb; i++)
		bands[i] = (struct band){ .pix = pix, .stride = stride, .w = w,
					  .r0 = (int)((long long)h * i / nb),
					  .r1 = (int)((long long)h * (i + 1) / nb),
					  .bgr = bgr, .last = i == nb - 1 };
	for (int i = 1; i < nb; i++)
		started[i] = pthread_create(&tid[i], NULL, band_run, &bands[i]) == 0;
	band_run(&bands[0]);
	for (int i = 1; i < nb; i++) {
		if (started[i])
			pthread_join(tid[i], NULL);
		else
			band_run(&bands[i]); /* no thread: here */
	}
	for (int i = 0; i < nb; i++) {
		if (bands[i].rc && !rc)
			rc = bands[i].rc;
		zlen += bands[i].zlen;
	}
	if (rc)
		goto out;
	/* the zlib stream: header (deflate, 32 KiB window, fastest: 0x78
	 * 0x01, a multiple of 31), the bands, the Adler-32 of all rows */
	idat = malloc(zlen + 6);
	if (!idat) {
		rc = -ENOMEM;
		goto out;
	}
	idat[0] = 0x78;
	idat[1] = 0x01;
	p = idat + 2;
	adler = bands[0].adler;
	for (int i = 0; i < nb; i++) {
		memcpy(p, bands[i].z, bands[i].zlen);
		p += bands[i].zlen;
		if (i)
			adler = adler32_combine(adler, bands[i].adler,
						(z_off_t)bands[i].raw);
	}
	p = be32(p, (uint32_t)adler);
	zlen = (size_t)(p - idat);
	/* IDAT chunks of at most 1 GiB (a chunk's length is below 2^31) */
	n = sizeof(sig) + (12 + 13) + 12 + (zlen / (1u << 30) + 1) * 12 + zlen;
	buf = malloc(n);
	if (!buf) {
		rc = -ENOMEM;
		goto out;
	}
	memcpy(buf, sig, sizeof(sig));
	p = be32(ihdr, (uint32_t)w);
	p = be32(p, (uint32_t)h);
	p[0] = 8; /* bits per sample */
	p[1] = 2; /* colour type: RGB */
	p[2] = p[3] = p[4] = 0; /* deflate, adaptive filters, no interlace */
	p = chunk(buf + sizeof(sig), "IHDR", ihdr, sizeof(ihdr));
	for (size_t o = 0; o < zlen; o += (size_t)1 << 30) {
		size_t k = zlen - o < ((size_t)1 << 30) ? zlen - o : (size_t)1 << 30;

		p = chunk(p, "IDAT", idat + o, k);
	}
	p = chunk(p, "IEND", NULL, 0);
	*out = buf;
	*len = (size_t)(p - buf);
	buf = NULL;
out:
	for (int i = 0; i < nb; i++)
		free(bands[i].z);
	free(idat);
	free(buf);
	return rc;
}
