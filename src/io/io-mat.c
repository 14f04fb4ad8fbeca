/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * MATLAB Level 5 MAT-file decoder ("MATLAB 7 MAT-File Format", The
 * MathWorks, 2013: a 128-byte header, then tagged data elements; miMATRIX
 * elements hold array flags, dimensions, a name and the real part in any
 * numeric storage type).  Numeric, real, two-dimensional arrays become
 * channels: a vector is one channel named after the variable, the columns
 * of a matrix are channels NAME_1, NAME_2, ... (its rows when it is wider
 * than tall).  Channels must share one length: those of the largest
 * length are kept, shorter ones (scalars such as an RPM value) are left
 * out.  Compressed elements (MATLAB's default -v7 format) are refused with
 * a clear message; -v6 and -v4-free files, and scipy.io.savemat's, read.
 * The data are read in place from the caller's buffer (no copy).
 */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io-mat.h"

#define MAT_MAGIC "MATLAB 5.0 MAT-file"

enum { MI_INT8 = 1, MI_UINT8, MI_INT16, MI_UINT16, MI_INT32, MI_UINT32,
       MI_SINGLE, MI_DOUBLE = 9, MI_INT64 = 12, MI_UINT64, MI_MATRIX,
       MI_COMPRESSED, MI_UTF8 };

struct mchan {
	char name[72];
	const unsigned char *data; /* first element of the channel */
	size_t step;               /* elements between rows */
	int type;                  /* MI_* storage type */
	size_t len;
};

struct ssc_mat {
	bool swap;
	size_t n, cap;
	struct mchan *ch;
	size_t rows;
};

bool ssc_mat_detect(const char *buf, size_t len)
{
	return len >= 128 && !memcmp(buf, MAT_MAGIC, strlen(MAT_MAGIC));
}

static uint32_t rd32(const struct ssc_mat *m, const unsigned char *p)
{
	uint32_t v = (uint32_t)p[0] | (uint32_t)p[1] << 8 |
		     (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;

	if (m->swap)
		v = (v >> 24) | ((v >> 8) & 0xff00) | ((v << 8) & 0xff0000) |
		    (v << 24);
	return v;
}

static size_t type_size(int t)
{
	switch (t) {
	case MI_INT8:
	case MI_UINT8:
	case MI_UTF8:
		return 1;
	case MI_INT16:
	case MI_UINT16:
		return 2;
	case MI_INT32:
	case MI_UINT32:
	case MI_SINGLE:
		return 4;
	case MI_DOUBLE:
	case MI_INT64:
	case MI_UINT64:
		return 8;
	default:
		return 0;
	}
}

/* One element at p (inside [p, end)): its type, data and size; *next is
 * the following element (8-byte aligned). */
static int element(const struct ssc_mat *m, const unsigned char *p,
		   const unsigned char *end, int *type,
		   const unsigned char **data, size_t *nbytes,
		   const unsigned char **next)
{
	uint32_t t, n;
	size_t pad;

	if (end - p < 8)
		return -EBADMSG;
	t = rd32(m, p);
	if (t >> 16) { /* small data element: 4 bytes of tag, 4 of data */
		n = t >> 16;
		if (n > 4)
			return -EBADMSG;
		*type = (int)(t & 0xffff);
		*data = p + 4;
		*nbytes = n;
		*next = p + 8;
		return 0;
	}
	n = rd32(m, p + 4);
	if ((size_t)(end - p - 8) < n)
		return -EBADMSG;
	*type = (int)t;
	*data = p + 8;
	*nbytes = n;
	/* the last element of a file may lack its padding (in size_t: n + 7
	 * may not fit 32 bits) */
	pad = ((size_t)n + 7) & ~(size_t)7;
	*next = (size_t)(end - p - 8) >= pad ? p + 8 + pad : end;
	return 0;
}

static int add_chan(struct ssc_mat *m, const char *name, int idx,
		    const unsigned char *data, size_t step, int type,
		    size_t len)
{
	struct mchan *c;

	if (m->n == m->cap) {
		size_t nc = m->cap ? 2 * m->cap : 8;
		void *p = realloc(m->ch, nc * sizeof(*m->ch));

		if (!p)
			return -ENOMEM;
		m->ch = p;
		m->cap = nc;
	}
	c = &m->ch[m->n++];
	if (idx)
		snprintf(c->name, sizeof(c->name), "%s_%d", name, idx);
	else
		snprintf(c->name, sizeof(c->name), "%s", name);
	c->data = data;
	c->step = step;
	c->type = type;
	c->len = len;
	return 0;
}

/* A miMATRIX element: keep it when it is a real numeric 2-D array. */
static int matrix(struct ssc_mat *m, const unsigned char *p,
		  const unsigned char *end)
{
	const unsigned char *d, *next;
	size_t nb, rows, cols, esz, count, bytes;
	int t, rc, cls;
	uint32_t flags;
	char name[64];

	/* array flags */
	rc = element(m, p, end, &t, &d, &nb, &next);
	if (rc || t != MI_UINT32 || nb < 8)
		return rc ? rc : -EBADMSG;
	flags = rd32(m, d);
	cls = (int)(flags & 0xff);
	p = next;
	/* dimensions */
	rc = element(m, p, end, &t, &d, &nb, &next);
	if (rc || t != MI_INT32 || nb < 8)
		return rc ? rc : -EBADMSG;
	if (nb != 8)
		return 0; /* more than two dimensions: not a capture */
	rows = rd32(m, d);
	cols = rd32(m, d + 4);
	if (rows > INT32_MAX || cols > INT32_MAX)
		return -EBADMSG; /* negative int32 dimensions */
	p = next;
	/* name */
	rc = element(m, p, end, &t, &d, &nb, &next);
	if (rc || (t != MI_INT8 && t != MI_UINT8 && t != MI_UTF8))
		return rc ? rc : -EBADMSG;
	if (nb >= sizeof(name))
		nb = sizeof(name) - 1;
	memcpy(name, d, nb);
	name[nb] = '\0';
	p = next;
	/* numeric classes 6 (double) .. 15 (uint64), real, not sparse; every
	 * product of dimensions overflow-checked (a crafted file must not
	 * wrap rows * cols * esz to the size of its data) */
	if (!ssc_mul(rows, cols, &count))
		return -EBADMSG;
	if (cls < 6 || cls > 15 || (flags & 0x800) || count < 2 || !name[0])
		return 0;
	rc = element(m, p, end, &t, &d, &nb, &next);
	if (rc)
		return rc;
	esz = type_size(t);
	if (!esz || t == MI_UTF8 || !ssc_mul(count, esz, &bytes) || nb != bytes)
		return -EBADMSG;
	if (rows == 1 || cols == 1)
		return add_chan(m, name, 0, d, 1, t, count);
	if (rows >= cols) {
		for (size_t c = 0; c < cols && c < 4096; c++) {
			rc = add_chan(m, name, (int)c + 1, d + c * rows * esz, 1,
				      t, rows);
			if (rc)
				return rc;
		}
	} else {
		for (size_t r = 0; r < rows && r < 4096; r++) {
			rc = add_chan(m, name, (int)r + 1, d + r * esz, rows, t,
				      cols);
			if (rc)
				return rc;
		}
	}
	return 0;
}

int ssc_mat_open(struct ssc_mat **out, const unsigned char *buf, size_t len,
		 const char *disp, struct sscope_diag *diag)
{
	struct ssc_mat *m;
	const unsigned char *p = buf + 128, *end = buf + len;
	size_t keep = 0;
	int rc = 0;

	*out = NULL;
	if (len < 128 || !ssc_mat_detect((const char *)buf, len))
		return ssc_diag(diag, -EBADMSG, "%s: not a MATLAB 5 MAT-file",
				disp);
	m = calloc(1, sizeof(*m));
	if (!m)
		return -ENOMEM;
	if (buf[126] == 'I' && buf[127] == 'M') {
		m->swap = false;
	} else if (buf[126] == 'M' && buf[127] == 'I') {
		m->swap = true;
	} else {
		rc = ssc_diag(diag, -EBADMSG, "%s: MAT-file: bad endian indicator",
			      disp);
		goto fail;
	}
	while (p < end) {
		const unsigned char *d, *next;
		size_t nb;
		int t;

		if (end - p < 8)
			break; /* trailing padding */
		rc = element(m, p, end, &t, &d, &nb, &next);
		if (rc) {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: MAT-file: truncated or malformed element at byte %zu",
				      disp, (size_t)(p - buf));
			goto fail;
		}
		if (t == MI_COMPRESSED) {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: compressed MAT-file element (MATLAB's -v7 default): save with -v6, or with scipy.io.savemat",
				      disp);
			goto fail;
		}
		if (t == MI_MATRIX) {
			rc = matrix(m, d, d + nb);
			if (rc) {
				rc = ssc_diag(diag, rc == -ENOMEM ? -ENOMEM : -EBADMSG,
					      "%s: MAT-file: malformed array at byte %zu",
					      disp, (size_t)(p - buf));
				goto fail;
			}
		}
		p = next;
	}
	for (size_t i = 0; i < m->n; i++)
		if (m->ch[i].len > m->rows)
			m->rows = m->ch[i].len;
	for (size_t i = 0; i < m->n; i++)
		if (m->ch[i].len == m->rows)
			m->ch[keep++] = m->ch[i];
	m->n = keep;
	if (m->n == 0) {
		rc = ssc_diag(diag, -EDOM,
			      "%s: MAT-file holds no real numeric vector or matrix",
			      disp);
		goto fail;
	}
	*out = m;
	return 0;
fail:
	ssc_mat_free(m);
	return rc;
}

size_t ssc_mat_n_channels(const struct ssc_mat *m)
{
	return m->n;
}

const char *ssc_mat_channel_name(const struct ssc_mat *m, size_t k)
{
	return k < m->n ? m->ch[k].name : NULL;
}

size_t ssc_mat_rows(const struct ssc_mat *m)
{
	return m->rows;
}

double ssc_mat_value(const struct ssc_mat *m, size_t k, size_t row)
{
	const struct mchan *c = &m->ch[k];
	size_t esz = type_size(c->type);
	const unsigned char *p = c->data + row * c->step * esz;
	unsigned char b[8];

	for (size_t i = 0; i < esz; i++)
		b[i] = p[m->swap ? esz - 1 - i : i];
	switch (c->type) {
	case MI_INT8:
		return (int8_t)b[0];
	case MI_UINT8:
		return b[0];
	case MI_INT16: {
		int16_t v;

		memcpy(&v, b, 2);
		return v;
	}
	case MI_UINT16: {
		uint16_t v;

		memcpy(&v, b, 2);
		return v;
	}
	case MI_INT32: {
		int32_t v;

		memcpy(&v, b, 4);
		return v;
	}
	case MI_UINT32: {
		uint32_t v;

		memcpy(&v, b, 4);
		return v;
	}
	case MI_SINGLE: {
		float v;

		memcpy(&v, b, 4);
		return v;
	}
	case MI_INT64: {
		int64_t v;

		memcpy(&v, b, 8);
		return (double)v;
	}
	case MI_UINT64: {
		uint64_t v;

		memcpy(&v, b, 8);
		return (double)v;
	}
	default: {
		double v;

		memcpy(&v, b, 8);
		return v;
	}
	}
}

void ssc_mat_free(struct ssc_mat *m)
{
	if (!m)
		return;
	free(m->ch);
	free(m);
}
