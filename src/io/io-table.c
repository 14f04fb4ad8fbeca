/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Decoded tables (columns that are strided, typed views into buffers) and
 * source descriptions: what every container decoder fills (io-container.c
 * recognises the formats and calls the decoders).
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

#include "io-formats.h"
#include "sscope-capture.h"

struct ssc_table *ssc_table_new(const char *format)
{
	struct ssc_table *t = calloc(1, sizeof(*t));

	if (!t)
		return NULL;
	t->src = ssc_source_new(format);
	if (!t->src) {
		free(t);
		return NULL;
	}
	return t;
}

int ssc_table_own(struct ssc_table *t, void *p)
{
	void **n;

	if (!p)
		return 0;
	n = realloc(t->owned, (t->n_owned + 1) * sizeof(*n));
	if (!n) {
		free(p);
		return -ENOMEM;
	}
	t->owned = n;
	t->owned[t->n_owned++] = p;
	return 0;
}

int ssc_table_add(struct ssc_table *t, const char *label, int role,
		  const void *data, size_t stride, enum ssc_vtype type,
		  bool swap)
{
	struct ssc_tcol *n = realloc(t->cols, (t->ncols + 1) * sizeof(*n));

	if (!n)
		return -ENOMEM;
	t->cols = n;
	n[t->ncols] = (struct ssc_tcol){ .label = ssc_strdup(label),
					 .role = role,
					 .data = data,
					 .stride = stride,
					 .type = type,
					 .swap = swap };
	if (!n[t->ncols].label)
		return -ENOMEM;
	t->ncols++;
	return 0;
}

static void load(const struct ssc_tcol *c, size_t row, unsigned char *b,
		 size_t n)
{
	const unsigned char *p = c->data + row * c->stride;

	for (size_t i = 0; i < n; i++)
		b[i] = p[c->swap ? n - 1 - i : i];
}

int64_t ssc_table_i64(const struct ssc_tcol *c, size_t row)
{
	unsigned char b[8];
	int64_t v;

	load(c, row, b, 8);
	memcpy(&v, b, 8);
	return v;
}

double ssc_table_value(const struct ssc_tcol *c, size_t row)
{
	unsigned char b[8];

	switch (c->type) {
	case SSC_V_F64: {
		double v;

		load(c, row, b, 8);
		memcpy(&v, b, 8);
		return v;
	}
	case SSC_V_F32: {
		float v;

		load(c, row, b, 4);
		memcpy(&v, b, 4);
		return v;
	}
	case SSC_V_I8:
		return (int8_t)c->data[row * c->stride];
	case SSC_V_U8:
		return c->data[row * c->stride];
	case SSC_V_I16: {
		int16_t v;

		load(c, row, b, 2);
		memcpy(&v, b, 2);
		return v;
	}
	case SSC_V_U16: {
		uint16_t v;

		load(c, row, b, 2);
		memcpy(&v, b, 2);
		return v;
	}
	case SSC_V_I32: {
		int32_t v;

		load(c, row, b, 4);
		memcpy(&v, b, 4);
		return v;
	}
	case SSC_V_U32: {
		uint32_t v;

		load(c, row, b, 4);
		memcpy(&v, b, 4);
		return v;
	}
	case SSC_V_I64:
		return (double)ssc_table_i64(c, row);
	case SSC_V_U64:
	default: {
		uint64_t v;

		load(c, row, b, 8);
		memcpy(&v, b, 8);
		return (double)v;
	}
	}
}

void ssc_table_free(struct ssc_table *t)
{
	if (!t)
		return;
	for (size_t i = 0; i < t->ncols; i++)
		free(t->cols[i].label);
	free(t->cols);
	for (size_t i = 0; i < t->n_owned; i++)
		free(t->owned[i]);
	free(t->owned);
	free(t->rx_ns);
	ssc_source_free(t->src);
	free(t);
}

/* ------------------------------------------------------------ sources */

struct sscope_capture_source *ssc_source_new(const char *format)
{
	struct sscope_capture_source *s = calloc(1, sizeof(*s));

	if (!s)
		return NULL;
	s->format = ssc_strdup(format ? format : "");
	if (!s->format) {
		free(s);
		return NULL;
	}
	return s;
}

void ssc_source_free(struct sscope_capture_source *s)
{
	if (!s)
		return;
	for (size_t i = 0; i < s->n_topics; i++) {
		free((char *)s->topics[i].name);
		free((char *)s->topics[i].type);
	}
	free((void *)s->topics);
	free((void *)s->format);
	free((void *)s->receive_s);
	free(s);
}

struct sscope_capture_source *ssc_source_copy(const struct sscope_capture_source *s,
					      const int64_t *rx_ns, size_t n,
					      int64_t t0_ns)
{
	struct sscope_capture_source *c = ssc_source_new(s->format);
	struct sscope_capture_topic *tp;

	if (!c)
		return NULL;
	if (s->n_topics) {
		tp = calloc(s->n_topics, sizeof(*tp));
		if (!tp)
			goto fail;
		c->topics = tp;
		for (size_t i = 0; i < s->n_topics; i++) {
			tp[i] = s->topics[i];
			tp[i].name = ssc_strdup(s->topics[i].name);
			tp[i].type = ssc_strdup(s->topics[i].type);
			c->n_topics = i + 1;
			if (!tp[i].name || !tp[i].type)
				goto fail;
		}
	}
	if (rx_ns && n) {
		double *r = ssc_alloc_array(n, sizeof(double));

		if (!r)
			goto fail;
		for (size_t i = 0; i < n; i++) {
			int64_t d;

			/* a corrupt stamp far from t0: the difference in
			 * double, never a signed overflow */
			r[i] = __builtin_sub_overflow(rx_ns[i], t0_ns, &d) ?
				       ((double)rx_ns[i] - (double)t0_ns) * 1e-9 :
				       (double)d * 1e-9;
		}
		c->receive_s = r;
	}
	return c;
fail:
	ssc_source_free(c);
	return NULL;
}
