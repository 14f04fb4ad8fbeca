/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * MATLAB v7 MAT-files ("MATLAB 7 MAT-File Format", The MathWorks): the
 * Level 5 layout where each variable is stored as a miCOMPRESSED (15) data
 * element whose payload is a zlib stream holding the uncompressed element
 * (tag included).  The file is rewritten in memory with every compressed
 * array expanded (to the length its tag declares, within deflate's ratio
 * and a cap of half the memory), and the Level 5 decoder (io-mat.c) reads
 * the result.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "io-formats.h"

#define MI_MATRIX 14
#define MI_COMPRESSED 15

struct obuf {
	unsigned char *p;
	size_t len, cap;
};

static int reserve(struct obuf *o, size_t more)
{
	size_t need, nc;
	unsigned char *n;

	if (!ssc_add(o->len, more, &need))
		return -ENOMEM;
	if (need <= o->cap)
		return 0;
	nc = o->cap ? o->cap : 4096;
	while (nc < need)
		if (!ssc_mul(nc, 2, &nc))
			return -ENOMEM;
	n = realloc(o->p, nc);
	if (!n)
		return -ENOMEM;
	o->p = n;
	o->cap = nc;
	return 0;
}

static int append(struct obuf *o, const void *p, size_t n)
{
	int rc = reserve(o, n);

	if (rc)
		return rc;
	memcpy(o->p + o->len, p, n);
	o->len += n;
	return 0;
}

static uint32_t rd32(const unsigned char *p, bool swap)
{
	uint32_t v = (uint32_t)p[0] | (uint32_t)p[1] << 8 |
		     (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;

	if (swap)
		v = (v >> 24) | ((v >> 8) & 0xff00) | ((v << 8) & 0xff0000) |
		    (v << 24);
	return v;
}

/* Inflate up to `want` bytes of the zlib stream z onto the end of o;
 * returns zlib's last code, or a negative errno. */
static int inflate_some(z_stream *z, struct obuf *o, size_t want)
{
	int zr = Z_OK;

	while (want > 0 && zr != Z_STREAM_END) {
		size_t k = want > (1u << 30) ? 1u << 30 : want;
		uInt before;

		z->next_out = o->p + o->len;
		z->avail_out = (uInt)k;
		before = z->avail_out;
		zr = inflate(z, Z_NO_FLUSH);
		o->len += before - z->avail_out;
		want -= before - z->avail_out;
		if (zr == Z_MEM_ERROR)
			return -ENOMEM;
		if (zr != Z_OK && zr != Z_STREAM_END)
			return -EBADMSG;
		if (zr == Z_OK && z->avail_in == 0 && z->avail_out != 0)
			return -EBADMSG; /* input ended inside the stream */
	}
	return zr;
}

static int nomem(const char *disp, size_t at, struct sscope_diag *diag)
{
	return ssc_diag(diag, -ENOMEM,
			"%s: MAT-file: out of memory expanding the compressed element at byte %zu",
			disp, at);
}

/* Inflate one zlib stream (a compressed element) onto the end of o, then
 * pad to 8 bytes.  Its first 8 bytes are the tag of the element it holds:
 * an array (miMATRIX) is expanded to the length its tag declares -- no
 * more than deflate's ratio (1032:1, zlib's zlib.h) makes of n bytes and
 * no more than cap in all; other elements are skipped (the reader would
 * ignore them) without expanding them. */
static int inflate_element(struct obuf *o, const unsigned char *src,
			   size_t n, bool swap, size_t cap, const char *disp,
			   size_t at, struct sscope_diag *diag)
{
	z_stream z;
	size_t start = o->len, nd, total;
	uint32_t t;
	int rc, zr;

	memset(&z, 0, sizeof(z));
	if (inflateInit(&z) != Z_OK)
		return nomem(disp, at, diag);
	z.next_in = (unsigned char *)src;
	z.avail_in = (uInt)(n > UINT32_MAX ? UINT32_MAX : n);
	rc = reserve(o, 8);
	zr = rc ? rc : inflate_some(&z, o, 8);
	if (zr < 0 || o->len - start < 8) {
		inflateEnd(&z);
		o->len = start;
		return zr == -ENOMEM ? nomem(disp, at, diag) : -EBADMSG;
	}
	t = rd32(o->p + start, swap);
	if (t != MI_MATRIX) {
		inflateEnd(&z);
		o->len = start;
		return 0;
	}
	nd = rd32(o->p + start + 4, swap);
	total = 8 + nd;
	if (nd / 1032 > n) {
		inflateEnd(&z);
		o->len = start;
		return -EBADMSG;
	}
	if (total > cap || o->len - 8 > cap - total) {
		inflateEnd(&z);
		o->len = start;
		return ssc_diag(diag, -ENOMEM,
				"%s: MAT-file: the compressed element at byte %zu holds %zu bytes, more than the %.0f MiB a decompressed file may take here (half the memory this process may use): save it uncompressed (-v6) or in parts",
				disp, at, total, (double)cap / 1048576.0);
	}
	/* one byte more than declared: a stream that goes on is corrupt */
	rc = reserve(o, nd + 1);
	if (rc) {
		inflateEnd(&z);
		return nomem(disp, at, diag);
	}
	zr = zr == Z_STREAM_END ? Z_STREAM_END : inflate_some(&z, o, nd + 1);
	inflateEnd(&z);
	if (zr == -ENOMEM)
		return nomem(disp, at, diag);
	if (zr < 0)
		return zr;
	if (zr != Z_STREAM_END || o->len - start > total)
		return -EBADMSG;
	while (o->len % 8) {
		rc = append(o, "", 1);
		if (rc)
			return rc;
	}
	return 0;
}

int ssc_matz_expand(const unsigned char *buf, size_t len, unsigned char **out,
		    size_t *out_len, const char *disp,
		    struct sscope_diag *diag)
{
	struct obuf o = { 0 };
	size_t pos = 128, cap = ssc_expand_cap();
	bool swap, any = false;
	int rc;

	*out = NULL;
	*out_len = 0;
	if (len < 128)
		return 0; /* io-mat.c reports it */
	swap = buf[126] == 'M' && buf[127] == 'I';
	/* a first pass: any compressed element at all? */
	for (size_t p = 128; p + 8 <= len;) {
		uint32_t t = rd32(buf + p, swap), n;

		if (t >> 16)
			break; /* small element at top level: io-mat.c judges */
		n = rd32(buf + p + 4, swap);
		if (t == MI_COMPRESSED) {
			any = true;
			break;
		}
		if (len - p - 8 < n)
			break;
		p += 8 + (t == MI_COMPRESSED ? n : ((size_t)n + 7) / 8 * 8);
	}
	if (!any)
		return 0;
	rc = append(&o, buf, 128);
	while (!rc && pos + 8 <= len) {
		uint32_t t = rd32(buf + pos, swap), n = rd32(buf + pos + 4, swap);
		size_t body;

		if (t >> 16 || len - pos - 8 < n) {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: MAT-file: truncated or malformed element at byte %zu",
				      disp, pos);
			break;
		}
		if (t == MI_COMPRESSED) {
			rc = inflate_element(&o, buf + pos + 8, n, swap, cap,
					     disp, pos, diag);
			if (rc == -EBADMSG)
				rc = ssc_diag(diag, -EBADMSG,
					      "%s: MAT-file: corrupt or truncated compressed element at byte %zu",
					      disp, pos);
			/* compressed elements are not padded */
			pos += 8 + (size_t)n;
			continue;
		}
		body = ((size_t)n + 7) / 8 * 8;
		if (body > len - pos - 8)
			body = len - pos - 8;
		rc = append(&o, buf + pos, 8 + body);
		pos += 8 + body;
	}
	if (rc) {
		free(o.p);
		return rc;
	}
	*out = o.p;
	*out_len = o.len;
	return 0;
}
