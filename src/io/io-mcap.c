/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * MCAP files (the MCAP specification, version 0: https://mcap.dev/spec):
 * the magic "\x89MCAP0\r\n", then records of uint8 opcode, uint64 length
 * and content, little endian; strings are uint32 length + bytes.
 *   0x03 Schema:  uint16 id, string name, string encoding, bytes data
 *   0x04 Channel: uint16 id, uint16 schema_id, string topic,
 *                 string message_encoding, map metadata
 *   0x05 Message: uint16 channel_id, uint32 sequence, uint64 log_time,
 *                 uint64 publish_time, data (the rest)
 *   0x06 Chunk:   uint64 start, uint64 end, uint64 uncompressed_size,
 *                 uint32 uncompressed_crc (0: none), string compression
 *                 ("", "lz4", "zstd"), uint64 length + records
 *   0x0F Data End closes the data section; 0x02 Footer ends the file.
 * The data section is read in file order; message encodings "cdr" (ROS 2)
 * and "ros1" are decoded, others are counted.
 */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io-formats.h"

#define MCAP_MAGIC "\x89MCAP0\r\n"

struct mcap {
	struct ssc_ros *c;
	const char *disp;
	char *schema[65536];   /* schema id -> name */
	size_t n_schema;       /* highest schema id named + 1 */
	uint32_t chan[65536];  /* channel id -> topic index + 1 */
	struct ssc_chunk_batch batch; /* compressed chunks not yet walked */
	const unsigned char *map; /* the file mapping (pages given back
				     behind the walk), or NULL */
	size_t dropped;
};

static uint64_t le(const unsigned char *p, int n)
{
	uint64_t v = 0;

	for (int i = n - 1; i >= 0; i--)
		v = v << 8 | p[i];
	return v;
}

static int bad(struct mcap *m, uint64_t at, const char *what,
	       struct sscope_diag *diag)
{
	return ssc_diag(diag, -EBADMSG,
			"%s: MCAP: %s at byte %llu (truncated or corrupt; `mcap recover` repairs an unclosed file)",
			m->disp, what, (unsigned long long)at);
}

/* a length-prefixed string at *p within [*p, end) */
static bool str(const unsigned char **p, const unsigned char *end,
		const unsigned char **s, size_t *n)
{
	uint32_t l;

	if (end - *p < 4)
		return false;
	l = (uint32_t)le(*p, 4);
	if ((size_t)(end - *p - 4) < l)
		return false;
	*s = *p + 4;
	*n = l;
	*p += 4 + l;
	return true;
}

static char *dup_n(const unsigned char *s, size_t n)
{
	char *d = malloc(n + 1);

	if (d) {
		memcpy(d, s, n);
		d[n] = '\0';
	}
	return d;
}

static int records(struct mcap *m, const unsigned char *p, size_t n,
		   uint64_t base_at, bool in_chunk, bool *end,
		   struct sscope_diag *diag);
static int flush(struct mcap *m, struct sscope_diag *diag);

static int chunk(struct mcap *m, const unsigned char *p,
		 const unsigned char *e, uint64_t at, struct sscope_diag *diag)
{
	const unsigned char *cs;
	size_t cl;
	uint64_t usize, rlen;
	uint32_t crc;
	enum ssc_codec codec;
	const unsigned char *data = NULL;
	bool end = false;
	int rc;

	if (e - p < 28)
		return bad(m, at, "chunk record cut short", diag);
	usize = le(p + 16, 8);
	crc = (uint32_t)le(p + 24, 4);
	p += 28;
	if (!str(&p, e, &cs, &cl) || e - p < 8)
		return bad(m, at, "chunk record cut short", diag);
	rlen = le(p, 8);
	p += 8;
	if ((uint64_t)(e - p) < rlen)
		return bad(m, at, "chunk records cut short", diag);
	if (cl == 0) {
		ssc_ros_note(m->c, "uncompressed chunks");
		if (rlen != usize)
			return bad(m, at, "uncompressed chunk of the wrong size",
				   diag);
		data = p;
	} else {
		if (cl == 3 && !memcmp(cs, "lz4", 3))
			codec = SSC_CODEC_LZ4;
		else if (cl == 4 && !memcmp(cs, "zstd", 4))
			codec = SSC_CODEC_ZSTD;
		else
			return ssc_diag(diag, -EBADMSG,
					"%s: MCAP chunk at byte %llu: compression '%.*s' is not lz4 or zstd",
					m->disp, (unsigned long long)at,
					(int)(cl > 20 ? 20 : cl), (const char *)cs);
		ssc_ros_note(m->c, codec == SSC_CODEC_LZ4 ? "lz4 chunks" :
							     "zstd chunks");
		/* writers make chunks of a few MiB: a size of gigabytes is
		 * corruption, not a reason to allocate it */
		if (usize > ((uint64_t)1 << 30))
			return bad(m, at, "chunk larger than 1 GiB", diag);
		if (usize > ssc_decompress_bound(codec, rlen))
			return bad(m, at, "chunk larger than its compressed data can hold",
				   diag);
		/* decompressed with the next ones, walked in order */
		m->batch.job[m->batch.n++] = (struct ssc_chunk_job){
			codec, p, (size_t)rlen, (size_t)usize, at };
		return m->batch.n == SSC_CHUNK_BATCH ? flush(m, diag) : 0;
	}
	rc = flush(m, diag);
	if (rc)
		return rc;
	/* a compressed chunk is checked by its decoder and its exact size;
	 * the CRC (12 % of the time of a read) guards uncompressed ones */
	if (crc && ssc_crc32(data, usize) != crc)
		return bad(m, at, "chunk CRC mismatch", diag);
	rc = records(m, data, usize, at, true, &end, diag);
	if (!rc && m->map)
		ssc_map_drop_behind(m->map, (size_t)at, &m->dropped);
	return rc;
}

/* the compressed chunks read so far, decompressed together and walked in
 * file order; then the pages behind them given back */
static int flush(struct mcap *m, struct sscope_diag *diag)
{
	struct ssc_chunk_batch *b = &m->batch;
	struct sscope_diag bd = { "" };
	int brc = b->n ? ssc_chunk_batch_run(b, "MCAP", m->disp, &bd) : 0;
	int rc = 0;

	for (size_t i = 0; i < b->n && !rc; i++) {
		bool end = false;

		rc = records(m, b->buf[i], b->job[i].size, b->job[i].at, true,
			     &end, diag);
	}
	if (!rc && brc) {
		rc = brc;
		if (diag)
			*diag = bd;
	}
	if (!rc && b->n && m->map)
		ssc_map_drop_behind(m->map, (size_t)b->job[b->n - 1].at, &m->dropped);
	b->n = 0;
	return rc;
}

static int records(struct mcap *m, const unsigned char *p, size_t n,
		   uint64_t base_at, bool in_chunk, bool *end,
		   struct sscope_diag *diag)
{
	size_t pos = 0;
	int rc = 0;

	while (pos < n && !rc && !*end) {
		uint64_t at = in_chunk ? base_at : base_at + pos;
		const unsigned char *r, *e;
		uint64_t len;
		int op;

		if (n - pos < 9)
			return bad(m, at, "record cut short", diag);
		op = p[pos];
		len = le(p + pos + 1, 8);
		if (len > n - pos - 9)
			return bad(m, at, "record cut short", diag);
		r = p + pos + 9;
		e = r + len;
		pos += 9 + len;
		/* a schema, channel, message or end follows the chunks before
		 * it (indexes, statistics, attachments and metadata do not
		 * matter here) */
		if (!in_chunk && m->batch.n &&
		    (op == 0x02 || op == 0x03 || op == 0x04 || op == 0x05 || op == 0x0f)) {
			rc = flush(m, diag);
			if (rc)
				break;
		}
		switch (op) {
		case 0x03: { /* schema */
			const unsigned char *s;
			size_t sl;
			uint16_t id;

			if (len < 2)
				return bad(m, at, "schema record cut short", diag);
			id = (uint16_t)le(r, 2);
			r += 2;
			if (!str(&r, e, &s, &sl))
				return bad(m, at, "schema record cut short", diag);
			if (!m->schema[id]) {
				m->schema[id] = dup_n(s, sl);
				if (!m->schema[id])
					return -ENOMEM;
				if (id >= m->n_schema)
					m->n_schema = (size_t)id + 1;
			}
			break;
		}
		case 0x04: { /* channel */
			const unsigned char *t, *en;
			size_t tl, el, idx;
			uint16_t id, sid;
			enum ssc_ros_enc enc = SSC_ENC_UNKNOWN;
			char *topic;

			if (len < 4)
				return bad(m, at, "channel record cut short", diag);
			id = (uint16_t)le(r, 2);
			sid = (uint16_t)le(r + 2, 2);
			r += 4;
			if (!str(&r, e, &t, &tl) || !str(&r, e, &en, &el))
				return bad(m, at, "channel record cut short", diag);
			if (m->chan[id])
				break;
			if (el == 3 && !memcmp(en, "cdr", 3))
				enc = SSC_ENC_CDR;
			else if (el == 4 && !memcmp(en, "ros1", 4))
				enc = SSC_ENC_ROS1;
			topic = dup_n(t, tl);
			if (!topic)
				return -ENOMEM;
			rc = ssc_ros_topic(m->c, topic,
					   sid && m->schema[sid] ? m->schema[sid] : "",
					   enc, &idx);
			free(topic);
			if (!rc)
				m->chan[id] = (uint32_t)idx + 1;
			break;
		}
		case 0x05: { /* message */
			uint16_t id;

			if (len < 22)
				return bad(m, at, "message record cut short", diag);
			id = (uint16_t)le(r, 2);
			if (!m->chan[id])
				return bad(m, at, "message of an unknown channel",
					   diag);
			rc = ssc_ros_message(m->c, m->chan[id] - 1, r + 22,
					     len - 22, (int64_t)le(r + 6, 8), at,
					     diag);
			break;
		}
		case 0x06:
			if (in_chunk)
				return bad(m, at, "chunk inside a chunk", diag);
			rc = chunk(m, r, e, at, diag);
			break;
		case 0x0f: /* data end: the summary repeats what we have */
		case 0x02: /* footer */
			if (!in_chunk)
				*end = true;
			break;
		default:
			break;
		}
	}
	return rc;
}

int ssc_mcap_read(const unsigned char *buf, size_t len, bool mapped,
		  struct ssc_ros *c, const char *disp, struct sscope_diag *diag)
{
	struct mcap *m;
	bool end = false;
	int rc;

	if (len < 8 || memcmp(buf, MCAP_MAGIC, 8))
		return ssc_diag(diag, -EBADMSG,
				"%s: not MCAP version 0 (bad magic)", disp);
	m = calloc(1, sizeof(*m));
	if (!m)
		return -ENOMEM;
	m->c = c;
	m->disp = disp;
	m->map = mapped ? buf : NULL;
	rc = records(m, buf + 8, len - 8, 8, false, &end, diag);
	if (!rc)
		rc = flush(m, diag);
	if (!rc && !end)
		rc = bad(m, len, "no data end or footer record (file cut short)",
			 diag);
	/* only the ids named: 65536 calls of free() cost more than a small
	 * file's whole read */
	for (size_t i = 0; i < m->n_schema; i++)
		free(m->schema[i]);
	ssc_chunk_batch_free(&m->batch);
	free(m);
	return rc;
}
