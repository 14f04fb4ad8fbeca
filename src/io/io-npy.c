/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * NumPy .npy files (the format of numpy.lib.format, versions 1.0, 2.0 and
 * 3.0): the magic "\x93NUMPY", a version, the header length (16 bits in
 * 1.0, 32 bits after), and a Python dict literal with 'descr' (e.g. '<f8'),
 * 'fortran_order' and 'shape'; the data follow.  One- and two-dimensional
 * arrays of f4, f8, i1, u1, i2, u2, i4, u4, i8, u8 in either byte order
 * and either memory order become channels col1, col2, ... (the columns of
 * a tall array, the rows of a wide one, as for MAT-files).  The data size
 * must be exactly what the shape says.  Values are read in place.
 */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io-formats.h"
#include "sscope-capture.h"

/* find 'key' in the header dict; returns the text after its colon */
static const char *dict_value(const char *h, const char *key)
{
	char pat[32];
	const char *p;

	snprintf(pat, sizeof(pat), "'%s'", key);
	p = strstr(h, pat);
	if (!p) {
		snprintf(pat, sizeof(pat), "\"%s\"", key);
		p = strstr(h, pat);
	}
	if (!p)
		return NULL;
	p += strlen(pat);
	while (*p == ' ')
		p++;
	if (*p != ':')
		return NULL;
	p++;
	while (*p == ' ')
		p++;
	return p;
}

static int parse_descr(const char *v, enum ssc_vtype *type, size_t *size,
		       bool *swap)
{
	static const struct {
		char kind;
		size_t size;
		enum ssc_vtype t;
	} map[] = { { 'f', 8, SSC_V_F64 }, { 'f', 4, SSC_V_F32 },
		    { 'i', 1, SSC_V_I8 },  { 'u', 1, SSC_V_U8 },
		    { 'i', 2, SSC_V_I16 }, { 'u', 2, SSC_V_U16 },
		    { 'i', 4, SSC_V_I32 }, { 'u', 4, SSC_V_U32 },
		    { 'i', 8, SSC_V_I64 }, { 'u', 8, SSC_V_U64 } };
	const uint16_t one = 1;
	bool little = *(const unsigned char *)&one == 1;
	char q, order, kind;
	unsigned sz;
	int used = 0;

	q = *v;
	if (q != '\'' && q != '"')
		return -1;
	if (sscanf(v + 1, "%c%c%u%n", &order, &kind, &sz, &used) != 3 ||
	    v[1 + used] != q)
		return -1;
	if (order != '<' && order != '>' && order != '|' && order != '=')
		return -1;
	for (size_t i = 0; i < sizeof(map) / sizeof(map[0]); i++)
		if (map[i].kind == kind && map[i].size == sz) {
			*type = map[i].t;
			*size = sz;
			*swap = sz > 1 && ((order == '<' && !little) ||
					   (order == '>' && little));
			return 0;
		}
	return -1;
}

int ssc_npy_open(struct ssc_table **out, const unsigned char *buf, size_t len,
		 const char *disp, struct sscope_diag *diag)
{
	struct ssc_table *t = NULL;
	size_t hlen, off, shape[2] = { 0, 0 }, ndim = 0, esz, total = 1;
	size_t rows, cols;
	enum ssc_vtype type;
	bool swap, fortran = false;
	const char *v;
	char *h;
	char fmt[64];
	int rc = 0;

	*out = NULL;
	if (len < 10)
		return ssc_diag(diag, -EBADMSG, "%s: npy: truncated header", disp);
	if (buf[6] == 1) {
		hlen = (size_t)buf[8] | (size_t)buf[9] << 8;
		off = 10;
	} else if (buf[6] == 2 || buf[6] == 3) {
		if (len < 12)
			return ssc_diag(diag, -EBADMSG, "%s: npy: truncated header",
					disp);
		hlen = (size_t)buf[8] | (size_t)buf[9] << 8 |
		       (size_t)buf[10] << 16 | (size_t)buf[11] << 24;
		off = 12;
	} else {
		return ssc_diag(diag, -EBADMSG,
				"%s: npy format version %u.%u is not known (1.0 to 3.0 are)",
				disp, buf[6], buf[7]);
	}
	if (hlen > len - off)
		return ssc_diag(diag, -EBADMSG,
				"%s: npy: truncated header (%zu bytes announced, %zu present)",
				disp, hlen, len - off);
	h = malloc(hlen + 1);
	if (!h)
		return -ENOMEM;
	memcpy(h, buf + off, hlen);
	h[hlen] = '\0';
	off += hlen;
	snprintf(fmt, sizeof(fmt), "NumPy .npy %u.%u", buf[6], buf[7]);
	v = dict_value(h, "descr");
	if (!v || parse_descr(v, &type, &esz, &swap)) {
		char d[40] = "?";

		if (v)
			snprintf(d, sizeof(d), "%.*s", (int)strcspn(v, ",}"), v);
		rc = ssc_diag(diag, -EBADMSG,
			      "%s: npy dtype %s is not read (f4 f8 i1 u1 i2 u2 i4 u4 i8 u8 are; save a plain numeric array, not a structured one)",
			      disp, d);
		goto out;
	}
	v = dict_value(h, "fortran_order");
	if (!v || (strncmp(v, "True", 4) && strncmp(v, "False", 5))) {
		rc = ssc_diag(diag, -EBADMSG, "%s: npy: bad header (fortran_order)",
			      disp);
		goto out;
	}
	fortran = !strncmp(v, "True", 4);
	v = dict_value(h, "shape");
	if (!v || *v != '(') {
		rc = ssc_diag(diag, -EBADMSG, "%s: npy: bad header (shape)", disp);
		goto out;
	}
	for (v++;;) {
		char *end;
		unsigned long long d;

		while (*v == ' ' || *v == ',')
			v++;
		if (*v == ')')
			break;
		d = strtoull(v, &end, 10);
		if (end == v || *v == '-' || ndim == 2) {
			rc = ssc_diag(diag, ndim == 2 ? -EDOM : -EBADMSG,
				      ndim == 2 ? "%s: npy array has more than two dimensions (a capture is a vector or a samples x channels matrix)" :
						  "%s: npy: bad header (shape)",
				      disp);
			goto out;
		}
		shape[ndim++] = (size_t)d;
		if ((unsigned long long)shape[ndim - 1] != d ||
		    !ssc_mul(total, shape[ndim - 1], &total)) {
			rc = ssc_diag(diag, -EBADMSG, "%s: npy: shape too large", disp);
			goto out;
		}
		v = end;
	}
	if (ndim == 0) {
		rc = ssc_diag(diag, -EDOM, "%s: npy holds a scalar, not samples",
			      disp);
		goto out;
	}
	if (!ssc_mul(total, esz, &total) || total != len - off) {
		rc = ssc_diag(diag, -EBADMSG,
			      "%s: npy data are %zu bytes where the shape (%zu%s%.0zu) and dtype need %zu (truncated?)",
			      disp, len - off, shape[0], ndim == 2 ? ", " : "",
			      ndim == 2 ? shape[1] : 0, total);
		goto out;
	}
	if (total == 0) {
		rc = ssc_diag(diag, -EDOM, "%s: npy array is empty", disp);
		goto out;
	}
	t = ssc_table_new(fmt);
	if (!t) {
		rc = -ENOMEM;
		goto out;
	}
	rows = shape[0];
	cols = ndim == 2 ? shape[1] : 1;
	{
		/* element (i, j) sits at (i*cols + j) in C order, (i + j*rows)
		 * in Fortran order */
		size_t si = fortran ? 1 : cols, sj = fortran ? rows : 1;
		bool wide = ndim == 2 && cols > rows;
		size_t nch = wide ? rows : cols;

		if (nch > 4096) {
			rc = ssc_diag(diag, -EDOM,
				      "%s: npy array of %zu x %zu: more than 4096 channels",
				      disp, shape[0], cols);
			goto out;
		}
		t->nrows = wide ? cols : rows;
		for (size_t k = 0; k < nch && !rc; k++) {
			char lab[24];

			snprintf(lab, sizeof(lab), "col%zu", k + 1);
			rc = ssc_table_add(t, lab, SSCOPE_CAPTURE_ROLE_DATA,
					   buf + off + k * (wide ? si : sj) * esz,
					   (wide ? sj : si) * esz, type, swap);
		}
	}
out:
	free(h);
	if (rc) {
		ssc_table_free(t);
		return rc;
	}
	*out = t;
	return 0;
}
