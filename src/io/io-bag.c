/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * ROS 1 bag files, format version 2.0 (ROS wiki "Bags/Format/2.0"): the
 * line "#ROSBAG V2.0\n", then records of
 *   uint32 header_len, header (fields: uint32 len, "name=value"),
 *   uint32 data_len, data.
 * The header field "op" gives the record type: 0x03 bag header, 0x05
 * chunk (fields compression "none"|"bz2"|"lz4" and size, the uncompressed
 * length; data: more records), 0x07 connection (fields conn, topic; data:
 * fields topic, type, md5sum, message_definition), 0x02 message data
 * (fields conn, time = uint32 sec + uint32 nsec; data: the serialised
 * message), 0x04 index data and 0x06 chunk info (not needed for a
 * sequential read).  Every chunk is read in file order; connection
 * records precede their messages inside each chunk.
 */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io-formats.h"

#define BAG_MAGIC "#ROSBAG V2.0\n"
#define MAX_CONN (1u << 20)
#define MAX_CHUNK (1u << 30)

struct bag {
	struct ssc_ros *c;
	const char *disp;
	size_t *conn;    /* connection id -> topic index + 1 (0: unknown) */
	size_t n_conn;
	struct ssc_chunk_batch batch; /* compressed chunks not yet walked */
	const unsigned char *map; /* the file mapping (pages given back
				     behind the walk), or NULL */
	size_t dropped;
};

static uint32_t le32(const unsigned char *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 |
	       (uint32_t)p[3] << 24;
}

/* a field "name=value" of a header block [h, h + n) */
static bool field(const unsigned char *h, size_t n, const char *name,
		  const unsigned char **val, size_t *vlen)
{
	size_t nl = strlen(name), p = 0;

	while (n - p >= 4) {
		uint32_t fl = le32(h + p);

		p += 4;
		if (fl > n - p)
			return false;
		if (fl > nl && !memcmp(h + p, name, nl) && h[p + nl] == '=') {
			*val = h + p + nl + 1;
			*vlen = fl - nl - 1;
			return true;
		}
		p += fl;
	}
	return false;
}

static bool field_u32(const unsigned char *h, size_t n, const char *name,
		      uint32_t *v)
{
	const unsigned char *p;
	size_t l;

	if (!field(h, n, name, &p, &l) || l != 4)
		return false;
	*v = le32(p);
	return true;
}

static char *field_str(const unsigned char *h, size_t n, const char *name)
{
	const unsigned char *p;
	size_t l;
	char *s;

	if (!field(h, n, name, &p, &l))
		return NULL;
	s = malloc(l + 1);
	if (s) {
		memcpy(s, p, l);
		s[l] = '\0';
	}
	return s;
}

static int bad(struct bag *b, uint64_t at, const char *what,
	       struct sscope_diag *diag)
{
	return ssc_diag(diag, -EBADMSG,
			"%s: ROS bag: %s at byte %llu (truncated or corrupt; `rosbag reindex` repairs an unclosed bag)",
			b->disp, what, (unsigned long long)at);
}

static int connection(struct bag *b, const unsigned char *h, size_t hl,
		      const unsigned char *d, size_t dl, uint64_t at,
		      struct sscope_diag *diag)
{
	uint32_t id;
	char *topic, *type;
	size_t idx;
	int rc;

	if (!field_u32(h, hl, "conn", &id) || id >= MAX_CONN)
		return bad(b, at, "connection record without a valid id", diag);
	if (id < b->n_conn && b->conn[id])
		return 0;
	topic = field_str(h, hl, "topic");
	type = field_str(d, dl, "type");
	if (!topic || !type) {
		free(topic);
		free(type);
		return bad(b, at, "connection record without topic or type",
			   diag);
	}
	rc = ssc_ros_topic(b->c, topic, type, SSC_ENC_ROS1, &idx);
	free(topic);
	free(type);
	if (rc)
		return rc;
	if (id >= b->n_conn) {
		size_t nn = (size_t)id + 1;
		size_t *n = realloc(b->conn, nn * sizeof(*n));

		if (!n)
			return -ENOMEM;
		memset(n + b->n_conn, 0, (nn - b->n_conn) * sizeof(*n));
		b->conn = n;
		b->n_conn = nn;
	}
	b->conn[id] = idx + 1;
	return 0;
}

/* the records of [p, end); base_at is the file offset of p for messages
 * (inside a chunk: the chunk's offset) */
static int records(struct bag *b, const unsigned char *p, size_t n,
		   uint64_t base_at, bool in_chunk, struct sscope_diag *diag);

/* the compressed chunks read so far, decompressed together and walked in
 * file order; then the pages behind them given back */
static int flush(struct bag *b, struct sscope_diag *diag)
{
	struct ssc_chunk_batch *bt = &b->batch;
	struct sscope_diag bd = { "" };
	int brc = bt->n ? ssc_chunk_batch_run(bt, "ROS bag", b->disp, &bd) : 0;
	int rc = 0;

	for (size_t i = 0; i < bt->n && !rc; i++)
		rc = records(b, bt->buf[i], bt->job[i].size, bt->job[i].at, true,
			     diag);
	if (!rc && brc) {
		rc = brc;
		if (diag)
			*diag = bd;
	}
	if (!rc && bt->n && b->map)
		ssc_map_drop_behind(b->map, (size_t)bt->job[bt->n - 1].at,
				    &b->dropped);
	bt->n = 0;
	return rc;
}

static int chunk(struct bag *b, const unsigned char *h, size_t hl,
		 const unsigned char *d, size_t dl, uint64_t at,
		 struct sscope_diag *diag)
{
	char *comp = field_str(h, hl, "compression");
	uint32_t size;
	enum ssc_codec codec;
	int rc;

	if (!comp || !field_u32(h, hl, "size", &size)) {
		free(comp);
		return bad(b, at, "chunk record without compression or size",
			   diag);
	}
	if (!strcmp(comp, "none")) {
		free(comp);
		ssc_ros_note(b->c, "uncompressed chunks");
		if (size != dl)
			return bad(b, at, "uncompressed chunk of the wrong size",
				   diag);
		rc = flush(b, diag);
		if (!rc)
			rc = records(b, d, dl, at, true, diag);
		if (!rc && b->map)
			ssc_map_drop_behind(b->map, (size_t)at, &b->dropped);
		return rc;
	}
	if (!strcmp(comp, "bz2")) {
		codec = SSC_CODEC_BZ2;
	} else if (!strcmp(comp, "lz4")) {
		codec = SSC_CODEC_LZ4;
	} else {
		rc = ssc_diag(diag, -EBADMSG,
			      "%s: ROS bag chunk at byte %llu: compression '%.20s' is not none, bz2 or lz4",
			      b->disp, (unsigned long long)at, comp);
		free(comp);
		return rc;
	}
	ssc_ros_note(b->c, codec == SSC_CODEC_BZ2 ? "bz2 chunks" : "lz4 chunks");
	free(comp);
	/* rosbag writes chunks of about 768 KiB: a size field of gigabytes
	 * is corruption, not a reason to allocate it */
	if (size > MAX_CHUNK)
		return bad(b, at, "chunk larger than 1 GiB", diag);
	if (size > ssc_decompress_bound(codec, dl))
		return bad(b, at, "chunk larger than its compressed data can hold",
			   diag);
	/* decompressed with the next ones, walked in order */
	b->batch.job[b->batch.n++] = (struct ssc_chunk_job){ codec, d, dl, size, at };
	return b->batch.n == SSC_CHUNK_BATCH ? flush(b, diag) : 0;
}

static int records(struct bag *b, const unsigned char *p, size_t n,
		   uint64_t base_at, bool in_chunk, struct sscope_diag *diag)
{
	size_t pos = 0;
	int rc = 0;

	while (pos < n && !rc) {
		uint64_t at = in_chunk ? base_at : base_at + pos;
		const unsigned char *h, *d, *opv;
		size_t hl, dl, ol;
		uint32_t v;

		if (n - pos < 4)
			return bad(b, at, "record header cut short", diag);
		hl = le32(p + pos);
		if (hl > n - pos - 4 || n - pos - 4 - hl < 4)
			return bad(b, at, "record header cut short", diag);
		h = p + pos + 4;
		dl = le32(h + hl);
		if (dl > n - pos - 8 - hl)
			return bad(b, at, "record data cut short", diag);
		d = h + hl + 4;
		pos += 8 + hl + dl;
		if (!field(h, hl, "op", &opv, &ol) || ol != 1)
			return bad(b, at, "record without an op code", diag);
		/* a connection or message follows the chunks before it (the
		 * bag header, index data and chunk info do not matter here) */
		if (!in_chunk && b->batch.n && (*opv == 0x07 || *opv == 0x02)) {
			rc = flush(b, diag);
			if (rc)
				break;
		}
		switch (*opv) {
		case 0x05:
			if (in_chunk)
				return bad(b, at, "chunk inside a chunk", diag);
			rc = chunk(b, h, hl, d, dl, at, diag);
			break;
		case 0x07:
			rc = connection(b, h, hl, d, dl, at, diag);
			break;
		case 0x02: {
			const unsigned char *tv;
			size_t tl;
			int64_t rx;

			if (!field_u32(h, hl, "conn", &v) ||
			    !field(h, hl, "time", &tv, &tl) || tl != 8)
				return bad(b, at, "message record without conn or time",
					   diag);
			if (v >= b->n_conn || !b->conn[v])
				return bad(b, at, "message of an unknown connection",
					   diag);
			rx = (int64_t)le32(tv) * 1000000000 + le32(tv + 4);
			rc = ssc_ros_message(b->c, b->conn[v] - 1, d, dl, rx, at,
					     diag);
			break;
		}
		default: /* bag header, index data, chunk info */
			break;
		}
	}
	return rc;
}

int ssc_bag_read(const unsigned char *buf, size_t len, bool mapped,
		 struct ssc_ros *c, const char *disp, struct sscope_diag *diag)
{
	struct bag b = { .c = c, .disp = disp, .map = mapped ? buf : NULL };
	size_t ml = strlen(BAG_MAGIC);
	int rc;

	if (len < ml || memcmp(buf, BAG_MAGIC, ml)) {
		size_t l = 0;

		while (l < 20 && l < len && buf[l] != '\n' && buf[l] >= ' ')
			l++;
		return ssc_diag(diag, -EBADMSG,
				"%s: '%.*s': only ROS bag format 2.0 is read (migrate older bags with `rosbag fix`)",
				disp, (int)l, (const char *)buf);
	}
	rc = records(&b, buf + ml, len - ml, ml, false, diag);
	if (!rc)
		rc = flush(&b, diag);
	free(b.conn);
	ssc_chunk_batch_free(&b.batch);
	return rc;
}
