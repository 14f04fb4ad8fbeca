/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Test recordings written from the format specifications, no ROS needed:
 * one deterministic IMU record (sensor_msgs/Imu at RATE Hz for DURATION s,
 * a sensor_msgs/Temperature topic at 1 Hz, a std_msgs/String topic that
 * must be skipped) stored as
 *   imu.csv              the same samples: time [ns] and gx..az, %.17g
 *   imu-{none,bz2,lz4}.bag   ROS 1 bag v2.0 (ROS wiki "Bags/Format/2.0":
 *                        bag header record padded to 4096 bytes, chunks
 *                        with connection and message data records, index
 *                        data after each chunk, connection and chunk info
 *                        records in the index section)
 *   imu-{zstd,lz4,none}.mcap MCAP v0 (mcap.dev/spec: header, schemas,
 *                        channels, chunks with CRC, data end, footer),
 *                        CDR messages as rosbag2 writes them
 *   imu-ros1.mcap        MCAP with ROS 1 message encoding
 *   rosbag2/             metadata.yaml + rosbag2_0.db3 (rosbag2's SQLite
 *                        schema: topics, messages, timestamp index)
 *   rosbag2-mcap/        metadata.yaml + rosbag2_0.mcap
 *   two-imu.mcap         two IMU topics (the reader must ask which)
 * Usage: gen-ros OUTDIR [RATE [DURATION [ONLY]]]; ONLY = csv, mcap (zstd),
 * bag (lz4), bag-none or mcap-none writes that one file (for the big
 * benchmark files).
 */
#include "config.h"

#include <bzlib.h>
#include <errno.h>
#include <lz4frame.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>
#include <zstd.h>
#ifdef HAVE_SQLITE3
#include <sqlite3.h>
#endif

#define T0_NS 1700000000123456789LL
#define LATENCY_NS 1500000

struct buf {
	unsigned char *p;
	size_t n, cap;
};

static void put(struct buf *b, const void *d, size_t n)
{
	if (b->n + n > b->cap) {
		b->cap = (b->n + n) * 2 + 4096;
		b->p = realloc(b->p, b->cap);
		if (!b->p) {
			perror("gen-ros");
			exit(1);
		}
	}
	memcpy(b->p + b->n, d, n);
	b->n += n;
}

static void u8(struct buf *b, unsigned v)
{
	unsigned char c = (unsigned char)v;

	put(b, &c, 1);
}

static void u16(struct buf *b, unsigned v)
{
	unsigned char c[2] = { (unsigned char)v, (unsigned char)(v >> 8) };

	put(b, c, 2);
}

static void u32(struct buf *b, uint32_t v)
{
	unsigned char c[4];

	for (int i = 0; i < 4; i++)
		c[i] = (unsigned char)(v >> (8 * i));
	put(b, c, 4);
}

static void u64(struct buf *b, uint64_t v)
{
	unsigned char c[8];

	for (int i = 0; i < 8; i++)
		c[i] = (unsigned char)(v >> (8 * i));
	put(b, c, 8);
}

static void f64(struct buf *b, double v)
{
	uint64_t u;

	memcpy(&u, &v, 8);
	u64(b, u);
}

static void pad8(struct buf *b, size_t origin)
{
	while ((b->n - origin) % 8)
		u8(b, 0);
}

/* ------------------------------------------------------------ samples */

struct rec {
	size_t n, nt;
	int64_t *stamp;
	double (*v)[6];
	int64_t *tstamp;
	double *temp;
};

/* deterministic noise: xorshift64* and Box-Muller */
static uint64_t rng = 0x2545F4914F6CDD1DULL;

static double unif(void)
{
	rng ^= rng >> 12;
	rng ^= rng << 25;
	rng ^= rng >> 27;
	return ((rng * 2685821657736338717ULL) >> 11) * 0x1.0p-53;
}

static double gauss(void)
{
	double u = unif(), v = unif();

	return sqrt(-2 * log(u + 0x1.0p-60)) * cos(2 * M_PI * v);
}

static void make_record(struct rec *r, double rate, double dur)
{
	int64_t dt = (int64_t)llround(1e9 / rate);
	double walk = 0;

	r->n = (size_t)(rate * dur);
	r->nt = (size_t)dur + 1;
	r->stamp = malloc(r->n * sizeof(*r->stamp));
	r->v = malloc(r->n * sizeof(*r->v));
	r->tstamp = malloc(r->nt * sizeof(*r->tstamp));
	r->temp = malloc(r->nt * sizeof(*r->temp));
	if (!r->stamp || !r->v || !r->tstamp || !r->temp) {
		perror("gen-ros");
		exit(1);
	}
	for (size_t i = 0; i < r->n; i++) {
		r->stamp[i] = T0_NS + (int64_t)i * dt;
		walk += 1e-6 * gauss();
		/* white rate noise 0.005 rad/s per sample plus a bias walk */
		for (int k = 0; k < 3; k++)
			r->v[i][k] = 0.01234 + walk + 0.005 * gauss();
		for (int k = 3; k < 6; k++)
			r->v[i][k] = (k == 5 ? 9.80665 : 0.0123) + 0.02 * gauss();
	}
	for (size_t i = 0; i < r->nt; i++) {
		r->tstamp[i] = T0_NS + (int64_t)i * 1000000000;
		r->temp[i] = 25.0 + 0.01 * (double)i;
	}
}

/* ------------------------------------------------------------ messages */

enum { M_IMU, M_TEMP, M_STR };

/* serialise message k of kind m in ROS 1 or CDR */
static void message(struct buf *b, const struct rec *r, int m, size_t k,
		    bool cdr)
{
	int64_t s = m == M_TEMP ? r->tstamp[k] : m == M_IMU ? r->stamp[k] : 0;
	size_t o = 0;

	if (cdr) {
		u8(b, 0);
		u8(b, 1);
		u16(b, 0);
		o = b->n;
	}
	if (m == M_STR) {
		const char *txt = "hello";

		u32(b, (uint32_t)strlen(txt) + cdr);
		put(b, txt, strlen(txt) + cdr);
		return;
	}
	if (!cdr)
		u32(b, (uint32_t)k); /* seq */
	u32(b, (uint32_t)(s / 1000000000));
	u32(b, (uint32_t)(s % 1000000000));
	u32(b, 3 + cdr);
	put(b, "imu", 3 + cdr);
	if (cdr)
		pad8(b, o);
	if (m == M_TEMP) {
		f64(b, r->temp[k]);
		f64(b, 0.01);
		return;
	}
	for (int i = 0; i < 4; i++)
		f64(b, i == 3 ? 1.0 : 0.0);
	for (int i = 0; i < 9; i++)
		f64(b, i == 0 ? -1.0 : 0.0);
	for (int i = 0; i < 3; i++)
		f64(b, r->v[k][i]);
	for (int i = 0; i < 9; i++)
		f64(b, 0.0);
	for (int i = 3; i < 6; i++)
		f64(b, r->v[k][i]);
	for (int i = 0; i < 9; i++)
		f64(b, 0.0);
}

/* the record as one time-ordered message stream: (kind, index) */
struct ev {
	int m;
	size_t k;
	int64_t rx;
};

static struct ev *events(const struct rec *r, size_t *n)
{
	struct ev *e = malloc((r->n + 2 * r->nt) * sizeof(*e));
	size_t i = 0, j = 0, c = 0;

	while (i < r->n || j < r->nt) {
		if (j < r->nt && (i >= r->n || r->tstamp[j] <= r->stamp[i])) {
			e[c++] = (struct ev){ M_TEMP, j, r->tstamp[j] + LATENCY_NS };
			e[c++] = (struct ev){ M_STR, j, r->tstamp[j] + LATENCY_NS + 1 };
			j++;
		} else {
			e[c++] = (struct ev){ M_IMU, i, r->stamp[i] + LATENCY_NS };
			i++;
		}
	}
	*n = c;
	return e;
}

static const char *const topic[] = { "/imu/data", "/imu/temperature", "/chatter" };
static const char *const type1[] = { "sensor_msgs/Imu", "sensor_msgs/Temperature",
				     "std_msgs/String" };
static const char *const type2[] = { "sensor_msgs/msg/Imu",
				     "sensor_msgs/msg/Temperature",
				     "std_msgs/msg/String" };

static void write_file(const char *dir, const char *name, const struct buf *b)
{
	char p[4096];
	FILE *f;

	snprintf(p, sizeof(p), "%s/%s", dir, name);
	f = fopen(p, "wb");
	if (!f || fwrite(b->p, 1, b->n, f) != b->n || fclose(f)) {
		perror(p);
		exit(1);
	}
}

/* ------------------------------------------------------------ CSV */

static void write_csv(const char *dir, const struct rec *r)
{
	char p[4096];
	FILE *f;

	snprintf(p, sizeof(p), "%s/imu.csv", dir);
	f = fopen(p, "w");
	fprintf(f, "time [ns],gx [rad/s],gy [rad/s],gz [rad/s],ax [m/s^2],ay [m/s^2],az [m/s^2]\n");
	for (size_t i = 0; i < r->n; i++)
		fprintf(f, "%lld,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n",
			(long long)r->stamp[i], r->v[i][0], r->v[i][1],
			r->v[i][2], r->v[i][3], r->v[i][4], r->v[i][5]);
	if (fclose(f)) {
		perror(p);
		exit(1);
	}
}

/* ------------------------------------------------------------ ROS 1 bag */

/* a header field name=value */
static void field(struct buf *h, const char *name, const void *v, size_t n)
{
	u32(h, (uint32_t)(strlen(name) + 1 + n));
	put(h, name, strlen(name));
	put(h, "=", 1);
	put(h, v, n);
}

static void field_u32(struct buf *h, const char *name, uint32_t v)
{
	unsigned char c[4];

	for (int i = 0; i < 4; i++)
		c[i] = (unsigned char)(v >> (8 * i));
	field(h, name, c, 4);
}

static void field_time(struct buf *h, const char *name, int64_t ns)
{
	unsigned char c[8];
	uint32_t s = (uint32_t)(ns / 1000000000), n = (uint32_t)(ns % 1000000000);

	for (int i = 0; i < 4; i++) {
		c[i] = (unsigned char)(s >> (8 * i));
		c[4 + i] = (unsigned char)(n >> (8 * i));
	}
	field(h, name, c, 8);
}

static void record(struct buf *b, const struct buf *h, const void *d, size_t n)
{
	u32(b, (uint32_t)h->n);
	put(b, h->p, h->n);
	u32(b, (uint32_t)n);
	put(b, d, n);
}

static void connection(struct buf *b, int c)
{
	struct buf h = { 0 }, d = { 0 };
	unsigned char op = 7;

	field(&h, "op", &op, 1);
	field_u32(&h, "conn", (uint32_t)c);
	field(&h, "topic", topic[c], strlen(topic[c]));
	field(&d, "topic", topic[c], strlen(topic[c]));
	field(&d, "type", type1[c], strlen(type1[c]));
	field(&d, "md5sum", "*", 1);
	field(&d, "message_definition", "", 0);
	record(b, &h, d.p, d.n);
	free(h.p);
	free(d.p);
}

static void write_bag(const char *dir, const char *name, const struct rec *r,
		      const char *comp)
{
	struct buf out = { 0 }, ch = { 0 }, idx[3], msg = { 0 }, h = { 0 };
	struct buf chunkinfo = { 0 };
	size_t n, i = 0, nchunks = 0;
	struct ev *e = events(r, &n);
	bool seen[3] = { false, false, false };
	unsigned char op;
	size_t hdr_at;
	uint64_t index_pos;

	put(&out, "#ROSBAG V2.0\n", 13);
	hdr_at = out.n;
	out.n += 4096; /* bag header record, written last */
	if (out.n > out.cap) {
		out.cap = out.n * 2;
		out.p = realloc(out.p, out.cap);
	}
	while (i < n) {
		uint32_t cnt[3] = { 0, 0, 0 };
		int64_t tmin = INT64_MAX, tmax = INT64_MIN;
		uint64_t chunk_pos = out.n;
		unsigned char *cd = NULL;
		size_t cl;

		ch.n = 0;
		for (int c = 0; c < 3; c++)
			idx[c] = (struct buf){ 0 };
		while (i < n && ch.n < 768 * 1024) {
			int c = e[i].m;

			if (!seen[c]) {
				connection(&ch, c);
				seen[c] = true;
			}
			h.n = 0;
			op = 2;
			field(&h, "op", &op, 1);
			field_u32(&h, "conn", (uint32_t)c);
			field_time(&h, "time", e[i].rx);
			msg.n = 0;
			message(&msg, r, c, e[i].k, false);
			u64(&idx[c], (uint64_t)(e[i].rx / 1000000000) |
					     (uint64_t)(e[i].rx % 1000000000) << 32);
			u32(&idx[c], (uint32_t)ch.n);
			record(&ch, &h, msg.p, msg.n);
			cnt[c]++;
			tmin = e[i].rx < tmin ? e[i].rx : tmin;
			tmax = e[i].rx > tmax ? e[i].rx : tmax;
			i++;
		}
		if (!strcmp(comp, "bz2")) {
			unsigned int dl = (unsigned int)(ch.n + ch.n / 100 + 600);

			cd = malloc(dl);
			if (BZ2_bzBuffToBuffCompress((char *)cd, &dl, (char *)ch.p,
						     (unsigned int)ch.n, 9, 0, 0) != BZ_OK)
				exit(1);
			cl = dl;
		} else if (!strcmp(comp, "lz4")) {
			size_t bound = LZ4F_compressFrameBound(ch.n, NULL);

			cd = malloc(bound);
			cl = LZ4F_compressFrame(cd, bound, ch.p, ch.n, NULL);
			if (LZ4F_isError(cl))
				exit(1);
		} else {
			cl = ch.n;
		}
		h.n = 0;
		op = 5;
		field(&h, "op", &op, 1);
		field(&h, "compression", comp, strlen(comp));
		field_u32(&h, "size", (uint32_t)ch.n);
		record(&out, &h, cd ? cd : ch.p, cl);
		free(cd);
		for (int c = 0; c < 3; c++) {
			if (!cnt[c]) {
				free(idx[c].p);
				continue;
			}
			h.n = 0;
			op = 4;
			field(&h, "op", &op, 1);
			field_u32(&h, "ver", 1);
			field_u32(&h, "conn", (uint32_t)c);
			field_u32(&h, "count", cnt[c]);
			record(&out, &h, idx[c].p, idx[c].n);
			free(idx[c].p);
		}
		/* chunk info for the index section */
		{
			struct buf d = { 0 };
			unsigned char pos[8];
			uint32_t nc = 0;

			for (int c = 0; c < 3; c++)
				if (cnt[c]) {
					u32(&d, (uint32_t)c);
					u32(&d, cnt[c]);
					nc++;
				}
			h.n = 0;
			op = 6;
			field(&h, "op", &op, 1);
			field_u32(&h, "ver", 1);
			for (int k = 0; k < 8; k++)
				pos[k] = (unsigned char)(chunk_pos >> (8 * k));
			field(&h, "chunk_pos", pos, 8);
			field_time(&h, "start_time", tmin);
			field_time(&h, "end_time", tmax);
			field_u32(&h, "count", nc);
			record(&chunkinfo, &h, d.p, d.n);
			free(d.p);
		}
		nchunks++;
	}
	index_pos = out.n;
	for (int c = 0; c < 3; c++)
		connection(&out, c);
	put(&out, chunkinfo.p, chunkinfo.n);
	/* the bag header record, padded with spaces to 4096 bytes */
	{
		struct buf bh = { 0 };
		unsigned char ip[8];
		size_t save = out.n;

		op = 3;
		field(&bh, "op", &op, 1);
		for (int k = 0; k < 8; k++)
			ip[k] = (unsigned char)(index_pos >> (8 * k));
		field(&bh, "index_pos", ip, 8);
		field_u32(&bh, "conn_count", 3);
		field_u32(&bh, "chunk_count", (uint32_t)nchunks);
		out.n = hdr_at;
		u32(&out, (uint32_t)bh.n);
		put(&out, bh.p, bh.n);
		u32(&out, (uint32_t)(4096 - 8 - bh.n));
		memset(out.p + out.n, ' ', 4096 - 8 - bh.n);
		out.n = save;
		free(bh.p);
	}
	write_file(dir, name, &out);
	free(out.p);
	free(ch.p);
	free(msg.p);
	free(h.p);
	free(chunkinfo.p);
	free(e);
}

/* ------------------------------------------------------------ MCAP */

static void mstr(struct buf *b, const char *s)
{
	u32(b, (uint32_t)strlen(s));
	put(b, s, strlen(s));
}

static void mrec(struct buf *b, int op, const struct buf *c)
{
	u8(b, (unsigned)op);
	u64(b, c->n);
	put(b, c->p, c->n);
}

static void write_mcap(const char *dir, const char *name, const struct rec *r,
		       const char *comp, bool ros1, int n_imu)
{
	struct buf out = { 0 }, c = { 0 }, ch = { 0 }, m = { 0 };
	size_t n, i = 0;
	struct ev *e = events(r, &n);
	int nt = 3 + (n_imu > 1);

	put(&out, "\x89MCAP0\r\n", 8);
	mstr(&c, ros1 ? "ros1" : "ros2");
	mstr(&c, "sensorscope gen-ros");
	mrec(&out, 0x01, &c);
	for (int t = 0; t < nt; t++) {
		int k = t < 3 ? t : 0;

		c.n = 0; /* schema t + 1 */
		u16(&c, (unsigned)t + 1);
		mstr(&c, ros1 ? type1[k] : type2[k]);
		mstr(&c, ros1 ? "ros1msg" : "ros2msg");
		u32(&c, 0);
		mrec(&out, 0x03, &c);
		c.n = 0; /* channel t */
		u16(&c, (unsigned)t);
		u16(&c, (unsigned)t + 1);
		mstr(&c, t < 3 ? topic[t] : "/imu1/data");
		mstr(&c, ros1 ? "ros1" : "cdr");
		u32(&c, 0); /* empty metadata map */
		mrec(&out, 0x04, &c);
	}
	while (i < n) {
		int64_t tmin = INT64_MAX, tmax = INT64_MIN;
		unsigned char *cd = NULL;
		size_t cl;

		ch.n = 0;
		while (i < n && ch.n < 1024 * 1024) {
			for (int dup = 0; dup < (e[i].m == M_IMU && n_imu > 1 ? 2 : 1); dup++) {
				m.n = 0;
				u16(&m, dup ? 3u : (unsigned)e[i].m);
				u32(&m, (uint32_t)e[i].k);
				u64(&m, (uint64_t)e[i].rx);
				u64(&m, (uint64_t)e[i].rx);
				message(&m, r, e[i].m, e[i].k, !ros1);
				mrec(&ch, 0x05, &m);
			}
			tmin = e[i].rx < tmin ? e[i].rx : tmin;
			tmax = e[i].rx > tmax ? e[i].rx : tmax;
			i++;
		}
		if (!strcmp(comp, "zstd")) {
			size_t bound = ZSTD_compressBound(ch.n);

			cd = malloc(bound);
			cl = ZSTD_compress(cd, bound, ch.p, ch.n, 3);
			if (ZSTD_isError(cl))
				exit(1);
		} else if (!strcmp(comp, "lz4")) {
			size_t bound = LZ4F_compressFrameBound(ch.n, NULL);

			cd = malloc(bound);
			cl = LZ4F_compressFrame(cd, bound, ch.p, ch.n, NULL);
			if (LZ4F_isError(cl))
				exit(1);
		} else {
			cl = ch.n;
		}
		c.n = 0;
		u64(&c, (uint64_t)tmin);
		u64(&c, (uint64_t)tmax);
		u64(&c, ch.n);
		u32(&c, (uint32_t)crc32(crc32(0, NULL, 0), ch.p, (uInt)ch.n));
		mstr(&c, comp);
		u64(&c, cl);
		put(&c, cd ? cd : ch.p, cl);
		mrec(&out, 0x06, &c);
		free(cd);
	}
	c.n = 0;
	u32(&c, 0);
	mrec(&out, 0x0f, &c); /* data end */
	c.n = 0;
	u64(&c, 0);
	u64(&c, 0);
	u32(&c, 0);
	mrec(&out, 0x02, &c); /* footer */
	put(&out, "\x89MCAP0\r\n", 8);
	write_file(dir, name, &out);
	free(out.p);
	free(c.p);
	free(ch.p);
	free(m.p);
	free(e);
}

/* ------------------------------------------------------------ rosbag2 */

static void write_metadata(const char *dir, const char *storage,
			   const char *file, const struct rec *r)
{
	char p[4096];
	FILE *f;

	snprintf(p, sizeof(p), "%s/metadata.yaml", dir);
	f = fopen(p, "w");
	fprintf(f, "rosbag2_bagfile_information:\n"
		   "  version: 5\n"
		   "  storage_identifier: %s\n"
		   "  duration:\n    nanoseconds: %lld\n"
		   "  starting_time:\n    nanoseconds_since_epoch: %lld\n"
		   "  message_count: %zu\n"
		   "  topics_with_message_count:\n",
		storage, (long long)(r->stamp[r->n - 1] - r->stamp[0]),
		(long long)r->stamp[0], r->n + 2 * r->nt);
	for (int t = 0; t < 3; t++)
		fprintf(f, "    - topic_metadata:\n        name: %s\n        type: %s\n"
			   "        serialization_format: cdr\n        offered_qos_profiles: \"\"\n"
			   "      message_count: %zu\n",
			topic[t], type2[t], t ? r->nt : r->n);
	fprintf(f, "  compression_format: \"\"\n  compression_mode: \"\"\n"
		   "  relative_file_paths:\n    - %s\n"
		   "  files:\n    - path: %s\n", file, file);
	if (fclose(f)) {
		perror(p);
		exit(1);
	}
}

#ifdef HAVE_SQLITE3
static void write_db3(const char *dir, const struct rec *r)
{
	char p[4200];
	sqlite3 *db;
	sqlite3_stmt *st;
	size_t n;
	struct ev *e = events(r, &n);
	struct buf m = { 0 };

	snprintf(p, sizeof(p), "%s/rosbag2_0.db3", dir);
	remove(p);
	if (sqlite3_open(p, &db) != SQLITE_OK)
		exit(1);
	sqlite3_exec(db,
		     "PRAGMA journal_mode=MEMORY; PRAGMA synchronous=OFF;"
		     "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
		     "INSERT INTO schema VALUES (3, 'humble');"
		     "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
		     " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
		     "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
		     " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
		     "CREATE INDEX timestamp_idx ON messages (timestamp ASC);"
		     "BEGIN;",
		     NULL, NULL, NULL);
	for (int t = 0; t < 3; t++) {
		sqlite3_prepare_v2(db, "INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')",
				   -1, &st, NULL);
		sqlite3_bind_int(st, 1, t + 1);
		sqlite3_bind_text(st, 2, topic[t], -1, SQLITE_STATIC);
		sqlite3_bind_text(st, 3, type2[t], -1, SQLITE_STATIC);
		sqlite3_step(st);
		sqlite3_finalize(st);
	}
	sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
			   -1, &st, NULL);
	for (size_t i = 0; i < n; i++) {
		m.n = 0;
		message(&m, r, e[i].m, e[i].k, true);
		sqlite3_bind_int(st, 1, e[i].m + 1);
		sqlite3_bind_int64(st, 2, e[i].rx);
		sqlite3_bind_blob(st, 3, m.p, (int)m.n, SQLITE_STATIC);
		if (sqlite3_step(st) != SQLITE_DONE)
			exit(1);
		sqlite3_reset(st);
	}
	sqlite3_finalize(st);
	sqlite3_exec(db, "COMMIT;", NULL, NULL, NULL);
	if (sqlite3_close(db) != SQLITE_OK)
		exit(1);
	free(m.p);
	free(e);
}
#endif

int main(int argc, char **argv)
{
	struct rec r;
	const char *dir, *only;
	char p[2048];

	if (argc < 2) {
		fprintf(stderr, "usage: gen-ros OUTDIR [RATE [DURATION [csv|mcap|bag]]]\n");
		return 2;
	}
	dir = argv[1];
	only = argc > 4 ? argv[4] : NULL;
	mkdir(dir, 0777);
	make_record(&r, argc > 2 ? atof(argv[2]) : 200, argc > 3 ? atof(argv[3]) : 60);
	if (!only || !strcmp(only, "csv"))
		write_csv(dir, &r);
	if (!only || !strcmp(only, "mcap"))
		write_mcap(dir, "imu-zstd.mcap", &r, "zstd", false, 1);
	if (!only || !strcmp(only, "bag"))
		write_bag(dir, "imu-lz4.bag", &r, "lz4");
	if (only && !strcmp(only, "bag-none"))
		write_bag(dir, "imu-none.bag", &r, "none");
	if (only && !strcmp(only, "mcap-none"))
		write_mcap(dir, "imu-none.mcap", &r, "", false, 1);
	if (only)
		return 0;
	write_bag(dir, "imu-none.bag", &r, "none");
	write_bag(dir, "imu-bz2.bag", &r, "bz2");
	write_mcap(dir, "imu-lz4.mcap", &r, "lz4", false, 1);
	write_mcap(dir, "imu-none.mcap", &r, "", false, 1);
	write_mcap(dir, "imu-ros1.mcap", &r, "", true, 1);
	write_mcap(dir, "two-imu.mcap", &r, "zstd", false, 2);
	snprintf(p, sizeof(p), "%s/rosbag2-mcap", dir);
	mkdir(p, 0777);
	write_mcap(p, "rosbag2_0.mcap", &r, "zstd", false, 1);
	write_metadata(p, "mcap", "rosbag2_0.mcap", &r);
#ifdef HAVE_SQLITE3
	snprintf(p, sizeof(p), "%s/rosbag2", dir);
	mkdir(p, 0777);
	write_db3(p, &r);
	write_metadata(p, "sqlite3", "rosbag2_0.db3", &r);
#endif
	return 0;
}
