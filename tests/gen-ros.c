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
 *   rosbag2-zstd/        the rosbag2/ folder with whole-file Zstandard
 *                        (compression_mode FILE: rosbag2_0.db3.zstd)
 * Usage: gen-ros OUTDIR [RATE [DURATION [ONLY]]]; ONLY = csv, mcap (zstd),
 * bag (lz4), bag-none or mcap-none writes that one file (for the big
 * benchmark files), mcap-camera camera-imu-zstd.mcap (the IMU among a
 * camera's frames, streamed: any size; mcap-camera-zst also its chunks'
 * zstd frames as camera-imu-zstd.zst), bag-camera and bag-camera-lz4 the
 * same as camera-imu-{none,lz4}.bag (ROS 1, streamed); ONLY = hostile writes the crafted files of issue 29
 * instead (see write_hostile()); ONLY = small writes everything with the
 * .db3 in pages of 512 bytes (fuzz seeds).
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

static void bag_conn(struct buf *b, uint32_t c, const char *tp, const char *ty)
{
	struct buf h = { 0 }, d = { 0 };
	unsigned char op = 7;

	field(&h, "op", &op, 1);
	field_u32(&h, "conn", c);
	field(&h, "topic", tp, strlen(tp));
	field(&d, "topic", tp, strlen(tp));
	field(&d, "type", ty, strlen(ty));
	field(&d, "md5sum", "*", 1);
	field(&d, "message_definition", "", 0);
	record(b, &h, d.p, d.n);
	free(h.p);
	free(d.p);
}

static void connection(struct buf *b, int c)
{
	bag_conn(b, (uint32_t)c, topic[c], type1[c]);
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

/* the noisy lower half of a camera frame of n bytes */
static void camera_noise(unsigned char *img, size_t n, uint64_t *x)
{
	for (size_t i = n / 2; i + 8 <= n; i += 8) {
		*x ^= *x << 13;
		*x ^= *x >> 7;
		*x ^= *x << 17;
		memcpy(img + i, x, 8);
	}
}

/* An MCAP as a robot writes it, streamed to the file chunk by chunk
 * (any size in bounded memory): the IMU topic among the frames of a
 * camera (sensor_msgs/msg/Image, 640 x 480 mono8 at 30 Hz, 9.2 MB/s; half
 * of each frame smooth, half noise, so zstd at level 1 halves it about),
 * zstd chunks of 4 MiB.  The camera's messages are counted, not decoded,
 * by the reader. */
static void write_mcap_camera(const char *dir, const struct rec *r, bool zst)
{
	enum { W = 640, H = 480, FPS = 30 };
	char path[4096];
	FILE *f, *fz = NULL;
	struct buf c = { 0 }, ch = { 0 }, m = { 0 }, hdr = { 0 };
	unsigned char *cd = NULL, *img = malloc((size_t)W * H);
	size_t cap = 0, k = 0, frames = 0;
	int64_t t_end = r->stamp[r->n - 1], dt_cam = 1000000000 / FPS;
	int64_t t = T0_NS, tmin = INT64_MAX, tmax = INT64_MIN;
	uint64_t x = 0x9E3779B97F4A7C15ULL;

	snprintf(path, sizeof(path), "%s/camera-imu-zstd.mcap", dir);
	f = fopen(path, "wb");
	if (!f || !img) {
		perror(path);
		exit(1);
	}
	/* the chunks' zstd frames alone, one after the other: a zstd stream
	 * for `zstd -d` to decompress beside the reader */
	snprintf(path, sizeof(path), "%s/camera-imu-zstd.zst", dir);
	if (zst && !(fz = fopen(path, "wb"))) {
		perror(path);
		exit(1);
	}
	snprintf(path, sizeof(path), "%s/camera-imu-zstd.mcap", dir);
	put(&hdr, "\x89MCAP0\r\n", 8);
	mstr(&c, "ros2");
	mstr(&c, "sensorscope gen-ros");
	mrec(&hdr, 0x01, &c);
	for (unsigned id = 0; id < 2; id++) {
		c.n = 0;
		u16(&c, id + 1);
		mstr(&c, id ? "sensor_msgs/msg/Image" : "sensor_msgs/msg/Imu");
		mstr(&c, "ros2msg");
		u32(&c, 0);
		mrec(&hdr, 0x03, &c);
		c.n = 0;
		u16(&c, id);
		u16(&c, id + 1);
		mstr(&c, id ? "/camera/image_raw" : topic[0]);
		mstr(&c, "cdr");
		u32(&c, 0);
		mrec(&hdr, 0x04, &c);
	}
	fwrite(hdr.p, 1, hdr.n, f);
	for (size_t i = 0; i < (size_t)W * H; i++)
		img[i] = (unsigned char)((i % W) / 3 + (i / W) / 5);
	while (t <= t_end) {
		/* the IMU messages up to this frame, then the frame */
		for (; k < r->n && r->stamp[k] <= t; k++) {
			m.n = 0;
			u16(&m, 0);
			u32(&m, (uint32_t)k);
			u64(&m, (uint64_t)(r->stamp[k] + LATENCY_NS));
			u64(&m, (uint64_t)(r->stamp[k] + LATENCY_NS));
			message(&m, r, M_IMU, k, true);
			mrec(&ch, 0x05, &m);
		}
		camera_noise(img, (size_t)W * H, &x);
		m.n = 0;
		u16(&m, 1);
		u32(&m, (uint32_t)frames);
		u64(&m, (uint64_t)(t + LATENCY_NS));
		u64(&m, (uint64_t)(t + LATENCY_NS));
		u8(&m, 0);
		u8(&m, 1);
		u16(&m, 0);
		u32(&m, (uint32_t)(t / 1000000000));
		u32(&m, (uint32_t)(t % 1000000000));
		u32(&m, 4);
		put(&m, "cam", 4);
		u32(&m, H);
		u32(&m, W);
		u32(&m, 6);
		put(&m, "mono8", 6);
		u8(&m, 0);
		while (m.n % 4)
			u8(&m, 0);
		u32(&m, W);
		u32(&m, (uint32_t)W * H);
		put(&m, img, (size_t)W * H);
		mrec(&ch, 0x05, &m);
		tmin = t < tmin ? t : tmin;
		tmax = t;
		frames++;
		t += dt_cam;
		if (ch.n >= ((size_t)4 << 20) || t > t_end) {
			size_t bound = ZSTD_compressBound(ch.n), cl;

			if (bound > cap) {
				cd = realloc(cd, bound);
				cap = bound;
			}
			cl = ZSTD_compress(cd, bound, ch.p, ch.n, 1);
			if (!cd || ZSTD_isError(cl))
				exit(1);
			c.n = 0;
			u8(&c, 0x06);
			u64(&c, 8 + 8 + 8 + 4 + 4 + 4 + 8 + cl);
			u64(&c, (uint64_t)tmin);
			u64(&c, (uint64_t)tmax);
			u64(&c, ch.n);
			u32(&c, 0); /* no CRC */
			mstr(&c, "zstd");
			u64(&c, cl);
			if (fwrite(c.p, 1, c.n, f) != c.n || fwrite(cd, 1, cl, f) != cl ||
			    (fz && fwrite(cd, 1, cl, fz) != cl)) {
				perror(path);
				exit(1);
			}
			ch.n = 0;
			tmin = INT64_MAX;
		}
	}
	c.n = 0;
	hdr.n = 0;
	u32(&c, 0);
	mrec(&hdr, 0x0f, &c);
	c.n = 0;
	u64(&c, 0);
	u64(&c, 0);
	u32(&c, 0);
	mrec(&hdr, 0x02, &c);
	put(&hdr, "\x89MCAP0\r\n", 8);
	if (fwrite(hdr.p, 1, hdr.n, f) != hdr.n || fclose(f) || (fz && fclose(fz))) {
		perror(path);
		exit(1);
	}
	free(c.p);
	free(ch.p);
	free(m.p);
	free(hdr.p);
	free(cd);
	free(img);
}

/* a chunk of a streamed bag being filled: its records, the index data of
 * each connection, the message counts and the time span */
struct bag_chunk {
	struct buf d, idx[2], h;
	uint32_t cnt[2];
	bool seen[2];
	int64_t tmin, tmax;
};

static void bag_chunk_msg(struct bag_chunk *k, uint32_t c, int64_t rx,
			  const struct buf *msg)
{
	static const char *const tp[] = { "/imu/data", "/camera/image_raw" };
	static const char *const ty[] = { "sensor_msgs/Imu", "sensor_msgs/Image" };
	unsigned char op = 2;

	if (!k->seen[c]) {
		bag_conn(&k->d, c, tp[c], ty[c]);
		k->seen[c] = true;
	}
	k->h.n = 0;
	field(&k->h, "op", &op, 1);
	field_u32(&k->h, "conn", c);
	field_time(&k->h, "time", rx);
	u64(&k->idx[c], (uint64_t)(rx / 1000000000) | (uint64_t)(rx % 1000000000) << 32);
	u32(&k->idx[c], (uint32_t)k->d.n);
	record(&k->d, &k->h, msg->p, msg->n);
	k->cnt[c]++;
	k->tmin = rx < k->tmin ? rx : k->tmin;
	k->tmax = rx > k->tmax ? rx : k->tmax;
}

/* The recording of write_mcap_camera() as a ROS 1 bag v2.0, streamed to
 * the file (any size in bounded memory): chunks of 768 KiB (rosbag's
 * chunk_threshold), uncompressed or lz4, each followed by the index data
 * of its connections; the index section holds the connection and chunk
 * info records, and the bag header, written last at byte 13, its
 * position.  Every IMU message of the record is written (the ones after
 * the last frame too), the camera's messages are sensor_msgs/Image. */
static void write_bag_camera(const char *dir, const struct rec *r, const char *comp)
{
	enum { W = 640, H = 480, FPS = 30 };
	char path[4096];
	FILE *f;
	struct bag_chunk k = { .tmin = INT64_MAX, .tmax = INT64_MIN };
	struct buf out = { 0 }, msg = { 0 }, info = { 0 };
	unsigned char *cd = NULL, *img = malloc((size_t)W * H), op;
	size_t cap = 0, j = 0, frames = 0, nchunks = 0;
	int64_t t_end = r->stamp[r->n - 1], dt_cam = 1000000000 / FPS, t = T0_NS;
	uint64_t pos, x = 0x9E3779B97F4A7C15ULL;
	bool lz4 = !strcmp(comp, "lz4");

	snprintf(path, sizeof(path), "%s/camera-imu-%s.bag", dir, comp);
	f = fopen(path, "wb");
	if (!f || !img) {
		perror(path);
		exit(1);
	}
	put(&out, "#ROSBAG V2.0\n", 13);
	for (int i = 0; i < 4096; i++)
		u8(&out, 0); /* the bag header record, written last */
	pos = out.n;
	if (fwrite(out.p, 1, out.n, f) != out.n) {
		perror(path);
		exit(1);
	}
	for (size_t i = 0; i < (size_t)W * H; i++)
		img[i] = (unsigned char)((i % W) / 3 + (i / W) / 5);
	while (t <= t_end) {
		for (; j < r->n && r->stamp[j] <= t; j++) {
			msg.n = 0;
			message(&msg, r, M_IMU, j, false);
			bag_chunk_msg(&k, 0, r->stamp[j] + LATENCY_NS, &msg);
		}
		camera_noise(img, (size_t)W * H, &x);
		msg.n = 0;
		u32(&msg, (uint32_t)frames);
		u32(&msg, (uint32_t)(t / 1000000000));
		u32(&msg, (uint32_t)(t % 1000000000));
		u32(&msg, 3);
		put(&msg, "cam", 3);
		u32(&msg, H);
		u32(&msg, W);
		u32(&msg, 5);
		put(&msg, "mono8", 5);
		u8(&msg, 0);
		u32(&msg, W);
		u32(&msg, (uint32_t)W * H);
		put(&msg, img, (size_t)W * H);
		bag_chunk_msg(&k, 1, t + LATENCY_NS, &msg);
		frames++;
		t += dt_cam;
		for (; t > t_end && j < r->n; j++) {
			msg.n = 0;
			message(&msg, r, M_IMU, j, false);
			bag_chunk_msg(&k, 0, r->stamp[j] + LATENCY_NS, &msg);
		}
		if (k.d.n >= 768 * 1024 || t > t_end) {
			const unsigned char *data = k.d.p;
			size_t cl = k.d.n;
			uint32_t nc = 0;
			struct buf d = { 0 };
			unsigned char cp[8];
			uint64_t chunk_pos;

			if (lz4) {
				size_t bound = LZ4F_compressFrameBound(k.d.n, NULL);

				if (bound > cap) {
					cd = realloc(cd, bound);
					cap = bound;
				}
				if (!cd)
					exit(1);
				cl = LZ4F_compressFrame(cd, bound, k.d.p, k.d.n, NULL);
				if (LZ4F_isError(cl))
					exit(1);
				data = cd;
			}
			out.n = 0;
			k.h.n = 0;
			op = 5;
			field(&k.h, "op", &op, 1);
			field(&k.h, "compression", comp, strlen(comp));
			field_u32(&k.h, "size", (uint32_t)k.d.n);
			u32(&out, (uint32_t)k.h.n);
			put(&out, k.h.p, k.h.n);
			u32(&out, (uint32_t)cl);
			if (fwrite(out.p, 1, out.n, f) != out.n || fwrite(data, 1, cl, f) != cl) {
				perror(path);
				exit(1);
			}
			chunk_pos = pos;
			pos += out.n + cl;
			out.n = 0;
			for (uint32_t c = 0; c < 2; c++) {
				if (!k.cnt[c])
					continue;
				k.h.n = 0;
				op = 4;
				field(&k.h, "op", &op, 1);
				field_u32(&k.h, "ver", 1);
				field_u32(&k.h, "conn", c);
				field_u32(&k.h, "count", k.cnt[c]);
				record(&out, &k.h, k.idx[c].p, k.idx[c].n);
				k.idx[c].n = 0;
				u32(&d, c);
				u32(&d, k.cnt[c]);
				nc++;
			}
			if (fwrite(out.p, 1, out.n, f) != out.n) {
				perror(path);
				exit(1);
			}
			pos += out.n;
			/* the chunk info for the index section */
			k.h.n = 0;
			op = 6;
			field(&k.h, "op", &op, 1);
			field_u32(&k.h, "ver", 1);
			for (int b = 0; b < 8; b++)
				cp[b] = (unsigned char)(chunk_pos >> (8 * b));
			field(&k.h, "chunk_pos", cp, 8);
			field_time(&k.h, "start_time", k.tmin);
			field_time(&k.h, "end_time", k.tmax);
			field_u32(&k.h, "count", nc);
			record(&info, &k.h, d.p, d.n);
			free(d.p);
			nchunks++;
			k.d.n = 0;
			k.cnt[0] = k.cnt[1] = 0;
			k.tmin = INT64_MAX;
			k.tmax = INT64_MIN;
		}
	}
	/* the index section, then the bag header pointing at it */
	out.n = 0;
	bag_conn(&out, 0, "/imu/data", "sensor_msgs/Imu");
	bag_conn(&out, 1, "/camera/image_raw", "sensor_msgs/Image");
	put(&out, info.p, info.n);
	if (fwrite(out.p, 1, out.n, f) != out.n) {
		perror(path);
		exit(1);
	}
	{
		struct buf bh = { 0 };
		unsigned char ip[8];

		op = 3;
		field(&bh, "op", &op, 1);
		for (int b = 0; b < 8; b++)
			ip[b] = (unsigned char)(pos >> (8 * b));
		field(&bh, "index_pos", ip, 8);
		field_u32(&bh, "conn_count", 2);
		field_u32(&bh, "chunk_count", (uint32_t)nchunks);
		out.n = 0;
		u32(&out, (uint32_t)bh.n);
		put(&out, bh.p, bh.n);
		u32(&out, (uint32_t)(4096 - 8 - bh.n));
		while (out.n < 4096)
			u8(&out, ' ');
		free(bh.p);
	}
	if (fseek(f, 13, SEEK_SET) || fwrite(out.p, 1, out.n, f) != out.n || fclose(f)) {
		perror(path);
		exit(1);
	}
	free(out.p);
	free(msg.p);
	free(info.p);
	free(k.d.p);
	free(k.h.p);
	free(k.idx[0].p);
	free(k.idx[1].p);
	free(cd);
	free(img);
}

/* ------------------------------------------------------------ rosbag2 */

static void write_metadata(const char *dir, const char *storage,
			   const char *file, const struct rec *r)
{
	char p[4096];
	FILE *f;

	if (snprintf(p, sizeof(p), "%s/metadata.yaml", dir) >= (int)sizeof(p)) {
		fprintf(stderr, "gen-ros: path too long: %s\n", dir);
		exit(1);
	}
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
/* page size of the .db3 files (0: SQLite's default; 512 for fuzz seeds) */
static int db3_page_size;

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
	if (db3_page_size) {
		char q[64];

		snprintf(q, sizeof(q), "PRAGMA page_size=%d;", db3_page_size);
		sqlite3_exec(db, q, NULL, NULL, NULL);
	}
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

/* ------------------------------------------------------------ hostile */

static void write_metadata_zstd(const char *dir, const char *storage,
				const char *file)
{
	char p[4096];
	FILE *f;

	if (snprintf(p, sizeof(p), "%s/metadata.yaml", dir) >= (int)sizeof(p)) {
		fprintf(stderr, "gen-ros: path too long: %s\n", dir);
		exit(1);
	}
	f = fopen(p, "w");
	if (!f) {
		perror(p);
		exit(1);
	}
	fprintf(f, "rosbag2_bagfile_information:\n"
		   "  version: 5\n"
		   "  storage_identifier: %s\n"
		   "  compression_format: zstd\n  compression_mode: FILE\n"
		   "  relative_file_paths:\n    - %s\n", storage, file);
	if (fclose(f)) {
		perror(p);
		exit(1);
	}
}

#ifdef HAVE_SQLITE3
static void slurp_file(const char *path, struct buf *b)
{
	FILE *f = fopen(path, "rb");
	unsigned char tmp[65536];
	size_t k;

	if (!f) {
		perror(path);
		exit(1);
	}
	while ((k = fread(tmp, 1, sizeof(tmp), f)) > 0)
		put(b, tmp, k);
	fclose(f);
}

/* a folder dir/NAME with metadata.yaml and the whole-file zstd of src */
static void write_zstd_folder(const char *dir, const char *name,
			      const char *src, const char *storage,
			      const char *file)
{
	char p[4096];
	struct buf in = { 0 }, out = { 0 };
	size_t bound, cl;

	snprintf(p, sizeof(p), "%s/%s", dir, name);
	mkdir(p, 0777);
	slurp_file(src, &in);
	bound = ZSTD_compressBound(in.n);
	out.p = malloc(bound);
	cl = ZSTD_compress(out.p, bound, in.p, in.n, 3);
	if (!out.p || ZSTD_isError(cl))
		exit(1);
	out.n = cl;
	write_file(p, file, &out);
	write_metadata_zstd(p, storage, file);
	free(in.p);
	free(out.p);
}
#endif

/* A Zstandard frame (RFC 8878) written block by block: the bytes `head`
 * as a raw block, then `rle` blocks of 128 KiB of the byte `fill`, each
 * from 4 bytes (a 3-byte block header and the byte) -- the codec's
 * largest ratio, so `rle` = 65536 makes 8 GiB from 256 KiB. */
static void zstd_bomb(struct buf *b, const void *head, size_t hn,
		      unsigned char fill, size_t rle)
{
	const uint32_t blk = 128 * 1024;

	u32(b, 0xFD2FB528u);
	u8(b, 0x00);            /* no content size, window descriptor follows */
	u8(b, (17 - 10) << 3);  /* window 2^17 = 128 KiB */
	u8(b, (unsigned)(hn << 3) & 0xff); /* raw block of hn bytes */
	u8(b, (unsigned)(hn >> 5) & 0xff);
	u8(b, (unsigned)(hn >> 13) & 0xff);
	put(b, head, hn);
	for (size_t i = 0; i < rle; i++) {
		uint32_t h = (blk << 3) | 1u << 1 | (i + 1 == rle);

		u8(b, h & 0xff);
		u8(b, (h >> 8) & 0xff);
		u8(b, (h >> 16) & 0xff);
		u8(b, fill);
	}
}

static void bomb_folder(const char *dir, const char *name, const void *head,
			size_t hn, const char *storage, const char *file,
			size_t rle)
{
	char p[4096];
	struct buf b = { 0 };

	snprintf(p, sizeof(p), "%s/%s", dir, name);
	mkdir(p, 0777);
	zstd_bomb(&b, head, hn, 0, rle);
	write_file(p, file, &b);
	write_metadata_zstd(p, storage, file);
	free(b.p);
}

/* a SQLite header (sqlite.org/fileformat.html, 1.3) of `pages` pages of
 * `psz` bytes, valid (version-valid-for = change counter) */
static void sqlite_header(unsigned char h[100], uint32_t psz, uint32_t pages)
{
	memset(h, 0, 100);
	memcpy(h, "SQLite format 3", 16);
	h[16] = (unsigned char)(psz == 65536 ? 0 : psz >> 8);
	h[17] = (unsigned char)(psz == 65536 ? 1 : psz & 0xff);
	h[18] = h[19] = 1;
	h[21] = 64;
	h[22] = h[23] = 32;
	h[27] = 1; /* change counter */
	for (int i = 0; i < 4; i++)
		h[28 + i] = (unsigned char)(pages >> (24 - 8 * i));
	h[43] = 1;  /* schema cookie */
	h[47] = 4;  /* schema format */
	h[59] = 1;  /* UTF-8 */
	h[95] = 1;  /* version-valid-for */
	h[96] = 0x00; h[97] = 0x2e; h[98] = 0x5f; h[99] = 0x41; /* 3040001 */
}

static void varint(struct buf *b, uint64_t v)
{
	unsigned char t[10];
	int n = 0;

	/* SQLite varints: 7 bits a byte, big-endian, for values < 2^56 */
	do {
		t[n++] = (unsigned char)(v & 0x7f);
		v >>= 7;
	} while (v);
	while (n > 1)
		u8(b, t[--n] | 0x80);
	u8(b, t[0]);
}

/* a record of ncol values: NULL (s NULL, i < 0), integer i, or text s */
struct val {
	const char *s;
	int64_t i;
	const unsigned char *blob;
	size_t bn;
};

static void sql_record(struct buf *b, const struct val *v, size_t n)
{
	struct buf h = { 0 }, body = { 0 };

	for (size_t k = 0; k < n; k++) {
		if (v[k].blob) {
			varint(&h, 12 + 2 * v[k].bn);
			put(&body, v[k].blob, v[k].bn);
		} else if (v[k].s) {
			varint(&h, 13 + 2 * strlen(v[k].s));
			put(&body, v[k].s, strlen(v[k].s));
		} else if (v[k].i < 0) {
			varint(&h, 0);
		} else {
			varint(&h, 6); /* 8-byte big-endian integer */
			for (int j = 7; j >= 0; j--)
				u8(&body, (unsigned)(v[k].i >> (8 * j)) & 0xff);
		}
	}
	varint(b, h.n + 1); /* the header size counts itself (< 128) */
	put(b, h.p, h.n);
	put(b, body.p, body.n);
	free(h.p);
	free(body.p);
}

/* a b-tree page (leaf 0x0d or interior 0x05) of psz bytes at offset `at`
 * of the file (page 1: after the 100-byte header) holding `cells` */
static void btree_page(unsigned char *pg, size_t psz, size_t hdr_at, int type,
		       struct buf *cells, size_t n, uint32_t right)
{
	size_t top = psz, h = hdr_at, ptrs = hdr_at + (type == 5 ? 12 : 8);

	pg[h] = (unsigned char)type;
	pg[h + 3] = (unsigned char)(n >> 8);
	pg[h + 4] = (unsigned char)n;
	for (size_t i = 0; i < n; i++) {
		top -= cells[i].n;
		memcpy(pg + top, cells[i].p, cells[i].n);
		pg[ptrs + 2 * i] = (unsigned char)(top >> 8);
		pg[ptrs + 2 * i + 1] = (unsigned char)top;
	}
	if (ptrs + 2 * n > top) {
		fprintf(stderr, "gen-ros: b-tree page overflow\n");
		exit(1);
	}
	pg[h + 5] = (unsigned char)(top >> 8);
	pg[h + 6] = (unsigned char)top;
	if (type == 5)
		for (int i = 0; i < 4; i++)
			pg[h + 8 + i] = (unsigned char)(right >> (24 - 8 * i));
}

static void table_cell(struct buf *c, int64_t rowid, const struct val *v,
		       size_t n)
{
	struct buf r = { 0 };

	sql_record(&r, v, n);
	varint(c, r.n);
	varint(c, (uint64_t)rowid);
	put(c, r.p, r.n);
	free(r.p);
}

/* A .db3 of 8 pages of 512 bytes whose messages b-tree is a tower: each
 * of its 5 interior pages has 60 cells (and the right-most pointer) all
 * pointing to the next page, the last to one leaf of 10 IMU messages:
 * a scan meets 61^5 x 10 = 8.4e9 rows in a 4 KiB file (the tables are
 * real, the schema is rosbag2's; only the work budget stops it). */
#define DAG_PSZ 512
#define DAG_LEVELS 5
#define DAG_FAN 60
static void write_dag_db3(const char *dir, const struct rec *r)
{
	const uint32_t npages = 3 + DAG_LEVELS;
	unsigned char *f = calloc(npages, DAG_PSZ);
	struct buf cells[DAG_FAN], m = { 0 }, out = { 0 };
	static const char *const sql[] = {
		"CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, serialization_format TEXT NOT NULL)",
		"CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, data BLOB NOT NULL)",
	};
	static const char *const name[] = { "topics", "messages" };

	if (!f)
		exit(1);
	sqlite_header(f, DAG_PSZ, npages);
	/* page 1: the schema; topics at page 2, messages at page 3 */
	for (int i = 0; i < 2; i++) {
		struct val v[5] = { { "table", 0, NULL, 0 }, { name[i], 0, NULL, 0 },
				    { name[i], 0, NULL, 0 }, { NULL, 2 + i, NULL, 0 },
				    { sql[i], 0, NULL, 0 } };

		memset(&cells[i], 0, sizeof(cells[i]));
		table_cell(&cells[i], i + 1, v, 5);
	}
	btree_page(f, DAG_PSZ, 100, 0x0d, cells, 2, 0);
	free(cells[0].p);
	free(cells[1].p);
	{
		struct val v[4] = { { NULL, -1, NULL, 0 }, { topic[0], 0, NULL, 0 },
				    { type2[0], 0, NULL, 0 }, { "cdr", 0, NULL, 0 } };

		memset(&cells[0], 0, sizeof(cells[0]));
		table_cell(&cells[0], 1, v, 4);
		btree_page(f + DAG_PSZ, DAG_PSZ, 0, 0x0d, cells, 1, 0);
		free(cells[0].p);
	}
	/* pages 3 .. 3 + LEVELS - 1: interior, every child the next page */
	for (uint32_t l = 0; l < DAG_LEVELS; l++) {
		uint32_t next = 3 + l + 1;

		for (int i = 0; i < DAG_FAN; i++) {
			memset(&cells[i], 0, sizeof(cells[i]));
			u8(&cells[i], next >> 24);
			u8(&cells[i], (next >> 16) & 0xff);
			u8(&cells[i], (next >> 8) & 0xff);
			u8(&cells[i], next & 0xff);
			varint(&cells[i], (uint64_t)(10 * (i + 1)));
		}
		btree_page(f + (size_t)(2 + l) * DAG_PSZ, DAG_PSZ, 0, 0x05, cells,
			   DAG_FAN, next);
		for (int i = 0; i < DAG_FAN; i++)
			free(cells[i].p);
	}
	/* the leaf: IMU messages small enough to stay on the page (the data
	 * blob is a truncated message: the scan, not the decoder, is tested) */
	for (int i = 0; i < 10; i++) {
		struct val v[4] = { { NULL, -1, NULL, 0 }, { NULL, 1, NULL, 0 },
				    { NULL, r->stamp[i], NULL, 0 }, { NULL, 0, NULL, 0 } };

		m.n = 0;
		message(&m, r, M_IMU, (size_t)i, true);
		v[3].blob = m.p;
		v[3].bn = 24;
		memset(&cells[i], 0, sizeof(cells[i]));
		table_cell(&cells[i], i + 1, v, 4);
	}
	btree_page(f + (size_t)(2 + DAG_LEVELS) * DAG_PSZ, DAG_PSZ, 0, 0x0d, cells,
		   10, 0);
	for (int i = 0; i < 10; i++)
		free(cells[i].p);
	out.p = f;
	out.n = (size_t)npages * DAG_PSZ;
	write_file(dir, "dag.db3", &out);
	free(f);
	free(m.p);
}

#ifdef HAVE_SQLITE3
static void sql_file(const char *dir, const char *name, const char *sql)
{
	char p[4200];
	sqlite3 *db;

	snprintf(p, sizeof(p), "%s/%s", dir, name);
	remove(p);
	if (sqlite3_open(p, &db) != SQLITE_OK ||
	    sqlite3_exec(db, sql, NULL, NULL, NULL) != SQLITE_OK) {
		fprintf(stderr, "gen-ros: %s: %s\n", name, sqlite3_errmsg(db));
		exit(1);
	}
	sqlite3_close(db);
}

#define TOPICS_SQL \
	"CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL," \
	" serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
#define MESSAGES_SQL \
	"CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL," \
	" timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
#define ENDLESS "WITH RECURSIVE r(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM r) "

/* NTOPICS IMU topics /imu0.. of 40 messages each at 200 Hz, interleaved
 * in time; message k of topic t has gx = t + k / 1000.  The topic ids
 * start at 100001 (rosbag2 numbers topics as SQLite assigns rows): a
 * query of 1 KiB held about 130 of them. */
static void write_many_topics(const char *dir, size_t ntopics)
{
	char p[4200];
	sqlite3 *db;
	sqlite3_stmt *st;
	struct rec r;
	struct buf m = { 0 };

	make_record(&r, 200, 0.2);
	snprintf(p, sizeof(p), "%s/many-topics.db3", dir);
	remove(p);
	if (sqlite3_open(p, &db) != SQLITE_OK)
		exit(1);
	sqlite3_exec(db, "PRAGMA journal_mode=MEMORY; PRAGMA synchronous=OFF;"
			 TOPICS_SQL MESSAGES_SQL "BEGIN;", NULL, NULL, NULL);
	sqlite3_prepare_v2(db, "INSERT INTO topics VALUES (?, ?, 'sensor_msgs/msg/Imu', 'cdr', '')",
			   -1, &st, NULL);
	for (size_t t = 0; t < ntopics; t++) {
		char name[32];

		snprintf(name, sizeof(name), "/imu%zu", t);
		sqlite3_bind_int64(st, 1, (sqlite3_int64)t + 100001);
		sqlite3_bind_text(st, 2, name, -1, SQLITE_TRANSIENT);
		if (sqlite3_step(st) != SQLITE_DONE)
			exit(1);
		sqlite3_reset(st);
	}
	sqlite3_finalize(st);
	sqlite3_prepare_v2(db, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
			   -1, &st, NULL);
	for (size_t k = 0; k < r.n; k++)
		for (size_t t = 0; t < ntopics; t++) {
			r.v[k][0] = (double)t + (double)k / 1000;
			m.n = 0;
			message(&m, &r, M_IMU, k, true);
			sqlite3_bind_int64(st, 1, (sqlite3_int64)t + 100001);
			sqlite3_bind_int64(st, 2, r.stamp[k] + LATENCY_NS);
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
	free(r.stamp);
	free(r.v);
	free(r.tstamp);
	free(r.temp);
}
#endif

/* The crafted inputs of issue 29, each small:
 *   view-messages.db3, view-topics.db3  a table replaced by a recursive
 *                        view (endless rows from an 8 KiB file)
 *   computed.db3         messages.timestamp a generated column
 *   dag.db3              real tables, a b-tree whose pages share children
 *   many-topics.db3      150 IMU topics of 40 messages (no topic dropped)
 *   bomb-text/, bomb-db3/, bomb-db3-huge/, bomb-mcap-zeros/, bomb-mcap/
 *                        rosbag2 folders with whole-file zstd expanding to
 *                        8 GiB of zeros: after "not a database" bytes,
 *                        after a SQLite header declaring 8 KiB or 128 TiB,
 *                        after the MCAP magic, after the magic, a Header
 *                        record and a 6 MiB private record (only a cap on
 *                        the expansion stops this one) */
static void write_hostile(const char *dir)
{
	unsigned char h[100];
	struct rec r;

	make_record(&r, 200, 1);
	write_dag_db3(dir, &r);
	free(r.stamp);
	free(r.v);
	free(r.tstamp);
	free(r.temp);
#ifdef HAVE_SQLITE3
	sql_file(dir, "view-messages.db3",
		 TOPICS_SQL
		 "INSERT INTO topics VALUES (1, '/imu/data', 'sensor_msgs/msg/Imu', 'cdr', '');"
		 "CREATE VIEW messages AS " ENDLESS
		 "SELECT i AS id, 1 AS topic_id, i AS timestamp, x'00010000' AS data FROM r;");
	sql_file(dir, "view-topics.db3",
		 "CREATE VIEW topics AS " ENDLESS
		 "SELECT i AS id, '/t' || i AS name, 'std_msgs/msg/String' AS type,"
		 " 'cdr' AS serialization_format FROM r;" MESSAGES_SQL);
	sql_file(dir, "computed.db3",
		 TOPICS_SQL
		 "INSERT INTO topics VALUES (1, '/imu/data', 'sensor_msgs/msg/Imu', 'cdr', '');"
		 "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
		 " t INTEGER, timestamp INTEGER AS (t * 2) VIRTUAL, data BLOB NOT NULL);");
	write_many_topics(dir, 150);
#endif
	bomb_folder(dir, "bomb-text", "this is not a database", 22, "sqlite3",
		    "rosbag2_0.db3.zstd", 65536);
	sqlite_header(h, 4096, 2);
	bomb_folder(dir, "bomb-db3", h, 100, "sqlite3", "rosbag2_0.db3.zstd", 65536);
	bomb_folder(dir, "bomb-db3-small", h, 100, "sqlite3", "rosbag2_0.db3.zstd", 16);
	sqlite_header(h, 65536, 0x7fffffffu);
	bomb_folder(dir, "bomb-db3-huge", h, 100, "sqlite3", "rosbag2_0.db3.zstd", 65536);
	bomb_folder(dir, "bomb-mcap-zeros", "\x89MCAP0\r\n", 8, "mcap",
		    "rosbag2_0.mcap.zstd", 65536);
	/* the magic, a Header record (op 1: two empty strings) and a private
	 * record (op 0x80) of 6 MiB: valid as far as the first MiB shows */
	bomb_folder(dir, "bomb-mcap",
		    "\x89MCAP0\r\n"
		    "\x01\x08\0\0\0\0\0\0\0" "\0\0\0\0\0\0\0\0"
		    "\x80\0\0\x60\0\0\0\0\0", 34, "mcap", "rosbag2_0.mcap.zstd", 65536);
	bomb_folder(dir, "bomb-mcap-small",
		    "\x89MCAP0\r\n"
		    "\x01\x08\0\0\0\0\0\0\0" "\0\0\0\0\0\0\0\0"
		    "\x80\0\0\x60\0\0\0\0\0", 34, "mcap", "rosbag2_0.mcap.zstd", 16);
}

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
	if (only && (!strcmp(only, "mcap-camera") || !strcmp(only, "mcap-camera-zst")))
		write_mcap_camera(dir, &r, !strcmp(only, "mcap-camera-zst"));
	if (only && !strcmp(only, "bag-camera"))
		write_bag_camera(dir, &r, "none");
	if (only && !strcmp(only, "bag-camera-lz4"))
		write_bag_camera(dir, &r, "lz4");
	if (only && !strcmp(only, "mcap-none"))
		write_mcap(dir, "imu-none.mcap", &r, "", false, 1);
	if (only && !strcmp(only, "hostile"))
		write_hostile(dir);
#ifdef HAVE_SQLITE3
	if (only && !strcmp(only, "small")) {
		/* everything, the .db3 in pages of 512 bytes (fuzz seeds) */
		db3_page_size = 512;
		only = NULL;
	}
#endif
	if (only)
		goto out;
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
	snprintf(p, sizeof(p), "%s/rosbag2/rosbag2_0.db3", dir);
	write_zstd_folder(dir, "rosbag2-zstd", p, "sqlite3", "rosbag2_0.db3.zstd");
#endif
out:
	free(r.stamp);
	free(r.v);
	free(r.tstamp);
	free(r.temp);
	return 0;
}
