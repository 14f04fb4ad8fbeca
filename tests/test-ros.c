/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Tests of the container readers on recordings written by tests/gen-ros
 * from the format specifications: the same samples through every
 * container (ROS 1 bag uncompressed/bz2/lz4, MCAP zstd/lz4/none and with
 * ROS 1 encoding, rosbag2 SQLite and MCAP folders) give bit-identical
 * channels and time stamps, equal to the CSV of the same samples; topics,
 * receive times and the temperature column; topic selection and its
 * errors; and every file cut short or with corrupted bytes is refused
 * with an error (never a crash or a read past the end: run under
 * make check-valgrind or --enable-sanitizers).  Also npy in both memory
 * orders and byte orders, gzip streams, and the rate plausibility hint.
 * The crafted files of issue 29 (gen-ros hostile): .db3 files whose tables
 * are recursive views, computed columns or a b-tree of shared pages, a
 * .db3 of 150 IMU topics, and whole-file zstd bombs in rosbag2 folders,
 * each refused quickly with its reason (or, for the topics, read whole).
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "check-main.h"
#include "io-formats.h"

#define DIR "test-ros.tmp"

static const char *const containers[] = {
	"imu-none.bag", "imu-bz2.bag", "imu-lz4.bag", "imu-zstd.mcap",
	"imu-lz4.mcap", "imu-none.mcap", "imu-ros1.mcap", "rosbag2-mcap",
#ifdef HAVE_SQLITE3
	"rosbag2", "rosbag2/rosbag2_0.db3", "rosbag2-zstd",
#endif
};

static const char *path(const char *name)
{
	static char p[512];

	snprintf(p, sizeof(p), DIR "/%s", name);
	return p;
}

static struct sscope_capture *load(const char *name, const char *topic,
				   int want)
{
	struct sscope_reader_opts o = { 0 };
	struct sscope_capture *cap = NULL;
	struct sscope_diag d = { "" };
	int rc;

	o.topic = topic;
	rc = sscope_capture_load(&cap, path(name), &o, &d);
	ck_assert_msg(rc == want, "%s: %d (%s)", name, rc, d.msg);
	return cap;
}

START_TEST(same_channels_everywhere)
{
	struct sscope_capture *ref = load("imu.csv", NULL, 0);

	ck_assert_uint_eq(ref->n, 200 * 20);
	ck_assert_uint_eq(ref->n_channels, 6);
	for (size_t i = 0; i < sizeof(containers) / sizeof(containers[0]); i++) {
		struct sscope_capture *c = load(containers[i], NULL, 0);

		ck_assert_uint_eq(c->n, ref->n);
		ck_assert_uint_eq(c->n_channels, 6);
		for (size_t k = 0; k < 6; k++) {
			ck_assert_str_eq(c->channels[k].col.name,
					 ref->channels[k].col.name);
			ck_assert_str_eq(c->channels[k].col.unit_label,
					 ref->channels[k].col.unit_label);
			ck_assert_msg(!memcmp(c->channels[k].data,
					      ref->channels[k].data,
					      c->n * sizeof(double)),
				      "%s: channel %zu differs", containers[i], k);
		}
		ck_assert_msg(!memcmp(c->time_s, ref->time_s, c->n * sizeof(double)),
			      "%s: time stamps differ", containers[i]);
		ck_assert(c->rate_hz == 200);
		/* the temperature topic beside the IMU: 25 degC + 0.01/s */
		ck_assert_ptr_nonnull(c->temp_degc);
		ck_assert_rel(c->temp_degc[1000], 25 + 0.01 * 5.0, 1e-12);
		/* receive times: stamps + 1.5 ms */
		ck_assert_ptr_nonnull(c->source_info);
		ck_assert_ptr_nonnull(c->source_info->receive_s);
		ck_assert(fabs(c->source_info->receive_s[777] - c->time_s[777] -
			       0.0015) < 1e-9);
		sscope_capture_free(c);
	}
	sscope_capture_free(ref);
}
END_TEST

START_TEST(topics_listed)
{
	struct sscope_capture *c = load("imu-lz4.bag", NULL, 0);
	const struct sscope_capture_source *s = c->source_info;
	bool imu = false, chatter = false;

	ck_assert_str_eq(s->format, "ROS 1 bag v2.0 (lz4 chunks)");
	ck_assert_uint_eq(s->n_topics, 3);
	for (size_t i = 0; i < s->n_topics; i++) {
		if (!strcmp(s->topics[i].name, "/imu/data")) {
			imu = true;
			ck_assert(s->topics[i].selected && s->topics[i].readable);
			ck_assert_uint_eq(s->topics[i].messages, 4000);
		}
		if (!strcmp(s->topics[i].name, "/chatter")) {
			chatter = true;
			ck_assert(!s->topics[i].selected && !s->topics[i].readable);
			ck_assert_uint_eq(s->topics[i].messages, 21);
		}
	}
	ck_assert(imu && chatter);
	sscope_capture_free(c);
}
END_TEST

START_TEST(topic_selection)
{
	struct sscope_reader_opts o = { 0 };
	struct sscope_capture *c;
	struct sscope_diag d = { "" };

	ck_assert_int_eq(sscope_capture_load(&c, path("two-imu.mcap"), NULL, &d),
			 -EINVAL);
	ck_assert_msg(strstr(d.msg, "--topic") && strstr(d.msg, "/imu1/data"),
		      "%s", d.msg);
	c = load("two-imu.mcap", "/imu1/data", 0);
	ck_assert_uint_eq(c->n, 4000);
	ck_assert_ptr_null(c->temp_degc); /* not asked for */
	sscope_capture_free(c);
	c = load("two-imu.mcap", "imu1/data,/imu/temperature", 0);
	ck_assert_ptr_nonnull(c->temp_degc);
	sscope_capture_free(c);
	/* a temperature topic alone is a data channel */
	c = load("imu-zstd.mcap", "/imu/temperature", 0);
	ck_assert_uint_eq(c->n, 21);
	ck_assert_str_eq(c->channels[0].col.name, "temperature");
	sscope_capture_free(c);
	load("imu-zstd.mcap", "/nope", -EINVAL);
	load("imu-zstd.mcap", "/chatter", -EINVAL);
	o.topic = "/imu/data";
	ck_assert_int_eq(sscope_capture_load(&c, path("imu.csv"), &o, &d), -EINVAL);
	ck_assert(strstr(d.msg, "--topic") != NULL);
}
END_TEST

static unsigned char *slurp(const char *p, size_t *n)
{
	FILE *f = fopen(p, "rb");
	unsigned char *b;
	long l;

	ck_assert_ptr_nonnull(f);
	fseek(f, 0, SEEK_END);
	l = ftell(f);
	fseek(f, 0, SEEK_SET);
	b = malloc((size_t)l);
	ck_assert_uint_eq(fread(b, 1, (size_t)l, f), (size_t)l);
	fclose(f);
	*n = (size_t)l;
	return b;
}

static int try_bytes(const unsigned char *b, size_t n, struct sscope_diag *d)
{
	const char *tmp = DIR "/cut.bin";
	struct sscope_capture *c = NULL;
	FILE *f = fopen(tmp, "wb");
	int rc;

	ck_assert_ptr_nonnull(f);
	ck_assert_uint_eq(fwrite(b, 1, n, f), n);
	fclose(f);
	rc = sscope_capture_load(&c, tmp, NULL, d);
	sscope_capture_free(c);
	return rc;
}

/* every file cut at many lengths, and with bytes overwritten */
START_TEST(cut_and_corrupt)
{
	static const char *const files[] = {
		"imu-none.bag", "imu-lz4.bag", "imu-bz2.bag", "imu-zstd.mcap",
		"imu-lz4.mcap", "imu-none.mcap", "a.npy", "c.csv.gz",
#ifdef HAVE_SQLITE3
		"rosbag2/rosbag2_0.db3",
#endif
	};
	const char *f = files[_i];
	size_t n;
	unsigned char *b = slurp(path(f), &n);
	struct sscope_diag d = { "" };
	uint64_t x = 88172645463325252ULL;

	for (size_t k = 1; k < 60; k++) {
		size_t cut = k < 30 ? k * 7 : n - n / (k - 28);
		int rc;

		if (cut >= n)
			continue;
		d.msg[0] = '\0';
		rc = try_bytes(b, cut, &d);
		/* the SQLite file keeps its tables in the first pages: a
		 * cut may leave a readable database with fewer messages */
		ck_assert_msg(rc < 0 || strstr(f, ".db3"),
			      "%s cut at %zu: accepted", f, cut);
		ck_assert_msg(rc == 0 || rc == -EBADMSG || rc == -EDOM,
			      "%s cut at %zu: %d (%s)", f, cut, rc, d.msg);
		ck_assert_msg(rc == 0 || d.msg[0], "%s cut at %zu: no message",
			      f, cut);
	}
	for (size_t k = 0; k < 40; k++) {
		unsigned char *c = malloc(n);
		int rc;

		memcpy(c, b, n);
		for (int j = 0; j < 8; j++) {
			x ^= x << 13;
			x ^= x >> 7;
			x ^= x << 17;
			c[16 + x % (n - 16)] ^= (unsigned char)(1 + (x >> 32) % 255);
		}
		rc = try_bytes(c, n, &d);
		ck_assert_msg(rc == 0 || rc == -EBADMSG || rc == -EDOM ||
				      rc == -EINVAL,
			      "%s corrupted: %d (%s)", f, rc, d.msg);
		free(c);
	}
	free(b);
}
END_TEST

START_TEST(npy_layouts)
{
	struct sscope_capture *a = load("a.npy", NULL, 0);
	static const char *const same[] = { "af.npy", "w.npy", "be.npy",
					    "a.npy.gz" };

	ck_assert_uint_eq(a->n, 500);
	ck_assert_uint_eq(a->n_channels, 3);
	ck_assert_str_eq(a->channels[2].col.name, "col3");
	ck_assert(a->channels[1].data[7] == 1.5 * 7 + 1);
	for (size_t i = 0; i < 4; i++) {
		struct sscope_capture *b = load(same[i], NULL, 0);

		ck_assert_uint_eq(b->n, a->n);
		ck_assert_uint_eq(b->n_channels, a->n_channels);
		for (size_t k = 0; k < 3; k++)
			ck_assert_msg(!memcmp(a->channels[k].data, b->channels[k].data,
					      a->n * sizeof(double)),
				      "%s: channel %zu differs", same[i], k);
		sscope_capture_free(b);
	}
	sscope_capture_free(a);
	a = load("i2.npy", NULL, 0);
	ck_assert(a->channels[0].data[3] == -3);
	sscope_capture_free(a);
	load("cube.npy", NULL, -EDOM);
	load("rec.npy", NULL, -EBADMSG);
}
END_TEST

START_TEST(gzip_and_rate_hint)
{
	struct sscope_capture *a = load("c.csv", NULL, 0), *b = load("c.csv.gz", NULL, 0);
	struct sscope_diag h = { "" };

	ck_assert_uint_eq(a->n, b->n);
	ck_assert(!memcmp(a->channels[0].data, b->channels[0].data, a->n * 8));
	ck_assert_str_eq(b->source_info->format, "gzip-compressed text");
	ck_assert_ptr_null(a->source_info);
	ck_assert_int_eq(sscope_capture_check_rate(a, &h), 0);
	sscope_capture_free(a);
	sscope_capture_free(b);
	a = load("ns.csv", NULL, 0);
	ck_assert_int_eq(sscope_capture_check_rate(a, &h), -EDOM);
	ck_assert_msg(strstr(h.msg, "ns") && strstr(h.msg, "200 Hz"), "%s", h.msg);
	sscope_capture_free(a);
	/* a rostopic echo -p CSV: string frame_id skipped, %time in ns */
	a = load("rostopic.csv", NULL, 0);
	ck_assert_uint_eq(a->n_channels, 6);
	ck_assert_str_eq(a->channels[0].col.name, "gx");
	ck_assert_str_eq(a->time_col.unit_label, "ns");
	ck_assert(a->rate_hz == 200);
	sscope_capture_free(a);
}
END_TEST

/* ------------------------------------------------------------ issue 29 */

static void refused(const char *name, int want, const char *msg)
{
	struct sscope_reader_opts o = { 0 };
	struct sscope_capture *c = NULL;
	struct sscope_diag d = { "" };
	int rc;

	rc = sscope_capture_load(&c, path(name), &o, &d);
	ck_assert_msg(rc == want, "%s: %d, wanted %d (%s)", name, rc, want, d.msg);
	ck_assert_msg(strstr(d.msg, msg) != NULL, "%s: '%s' not in '%s'", name,
		      msg, d.msg);
	ck_assert_msg(strstr(d.msg, name) != NULL, "%s: file not named: %s",
		      name, d.msg);
	ck_assert_ptr_null(c);
}

#ifdef HAVE_SQLITE3
/* a table replaced by a recursive view ran forever; a computed column
 * is code of the file's; a b-tree whose pages share children holds 8e9
 * rows in 4 KiB: refused, the last by the work budget */
START_TEST(db3_schema_refused)
{
	refused("hostile/view-messages.db3", -EBADMSG, "'messages' is a view, not a table");
	refused("hostile/view-topics.db3", -EBADMSG, "'topics' is a view, not a table");
	refused("hostile/computed.db3", -EBADMSG,
		"column 'timestamp' of 'messages' is computed at each read");
	refused("hostile/dag.db3", -EBADMSG,
		"takes more work than a file of its size can need");
}
END_TEST

/* 150 IMU topics: the query of the readable topics' messages drops none
 * (a 1 KiB query buffer stopped adding topic ids at about 120) */
START_TEST(db3_many_topics)
{
	static const char *const names[] = { "/imu0", "/imu77", "/imu149" };
	static const double t[] = { 0, 77, 149 };

	for (size_t i = 0; i < 3; i++) {
		struct sscope_capture *c = load("hostile/many-topics.db3", names[i], 0);

		ck_assert_uint_eq(c->n, 40);
		for (size_t k = 0; k < c->n; k++)
			ck_assert_msg(c->channels[0].data[k] == t[i] + (double)k / 1000,
				      "%s: gx[%zu] = %.17g", names[i], k,
				      c->channels[0].data[k]);
		sscope_capture_free(c);
	}
	load("hostile/many-topics.db3", NULL, -EINVAL); /* 150: choose one */
}
END_TEST
#endif

/* whole-file zstd in a rosbag2 folder: 8 GiB from 256 KiB stop on the
 * first MiB when it is not what the storage needs, at the declared size
 * of a SQLite file, or at the cap */
START_TEST(zstd_bombs)
{
	unsigned char *b, *out = NULL;
	size_t n, on = 0;
	struct sscope_diag d = { "" };
	int rc;

	refused("hostile/bomb-text", -EBADMSG,
		"not a SQLite (.db3) or MCAP file once decompressed");
	refused("hostile/bomb-mcap-zeros", -EBADMSG,
		"not an MCAP file once decompressed (record at byte 8)");
	refused("hostile/bomb-db3", -EBADMSG,
		"corrupt zstd data (they go on past the 8192 bytes the file declares)");
	refused("hostile/bomb-db3-huge", -ENOMEM,
		"holds a SQLite database of 134217728 MiB (says its header), more than the");
	/* the cap itself: 16 MiB here (half the memory in use) */
	b = slurp(path("hostile/bomb-mcap/rosbag2_0.mcap.zstd"), &n);
	rc = ssc_unzstd(b, n, 16u << 20, NULL, NULL, &out, &on, "x.zstd", &d);
	ck_assert_int_eq(rc, -ENOMEM);
	ck_assert_ptr_null(out);
	ck_assert_msg(strstr(d.msg, "x.zstd: zstd data expand to more than the 16 MiB") &&
			      strstr(d.msg, "ros2 bag convert"),
		      "%s", d.msg);
	/* the codec's ratio: 128 KiB from 4 bytes, so 256 KiB cannot make
	 * more than 8 GiB + 128 KiB; cut to 400 bytes: at most 12.9 MiB */
	rc = ssc_unzstd(b, 400, SIZE_MAX / 2, NULL, NULL, &out, &on, "x.zstd", &d);
	ck_assert_int_eq(rc, -EBADMSG);
	ck_assert_msg(strstr(d.msg, "truncated"), "%s", d.msg);
	ck_assert_uint_le(ssc_decompress_bound(SSC_CODEC_ZSTD, 400),
			  (size_t)400 * 32768 + 131072);
	free(b);
#ifdef HAVE_SQLITE3
	/* a real one expands to the very bytes of the .db3 */
	{
		size_t rn;
		unsigned char *ref = slurp(path("rosbag2/rosbag2_0.db3"), &rn);

		b = slurp(path("rosbag2-zstd/rosbag2_0.db3.zstd"), &n);
		ck_assert_int_eq(ssc_unzstd(b, n, 16u << 20, NULL, NULL, &out,
					    &on, "x", &d), 0);
		ck_assert_uint_eq(on, rn);
		ck_assert(!memcmp(out, ref, rn));
		free(out);
		/* a cap below its size: refused, not corrupt */
		ck_assert_int_eq(ssc_unzstd(b, n, rn - 1, NULL, NULL, &out, &on,
					    "x", &d), -ENOMEM);
		free(b);
		free(ref);
	}
#endif
}
END_TEST

/* A MATLAB v7 file of one compressed element: the zlib stream of an
 * 8-byte tag (type, declared length) followed by `zeros` zero bytes. */
static void write_matz(const char *name, uint32_t type, uint32_t declared,
		       size_t zeros)
{
	unsigned char hdr[128], tag[8];
	size_t n = 8 + zeros;
	unsigned char *raw = calloc(1, n);
	uLongf zl = compressBound((uLong)n);
	unsigned char *z = malloc(zl);
	uint32_t et[2] = { 15, 0 };
	FILE *f = fopen(path(name), "wb");

	if (!raw || !z || !f) {
		perror(name);
		exit(1);
	}
	memset(hdr, ' ', sizeof(hdr));
	memcpy(hdr, "MATLAB 5.0 MAT-file, test", 25);
	memcpy(hdr + 124, "\0\1IM", 4);
	memcpy(tag, &type, 4);
	memcpy(tag + 4, &declared, 4);
	memcpy(raw, tag, 8);
	if (compress2(z, &zl, raw, (uLong)n, 1) != Z_OK)
		exit(1);
	et[1] = (uint32_t)zl;
	fwrite(hdr, 1, 128, f);
	fwrite(et, 4, 2, f);
	fwrite(z, 1, zl, f);
	fclose(f);
	free(raw);
	free(z);
}

/* MATLAB v7: a compressed array expands to the length its tag declares
 * (no more, and no more than deflate's 1032:1 makes of its bytes); an
 * element the reader ignores is not expanded */
START_TEST(matz_bounded)
{
	refused("over.mat", -EBADMSG, "corrupt or truncated compressed element at byte 128");
	refused("ratio.mat", -EBADMSG, "corrupt or truncated compressed element at byte 128");
	refused("int8.mat", -EDOM, "holds no real numeric vector or matrix");
}
END_TEST

/* small files of the other formats, written here */
static void write_npy(const char *name, const char *descr, bool fortran,
		      const char *shape, const void *data, size_t bytes)
{
	char h[128];
	FILE *f = fopen(path(name), "wb");
	size_t l = (size_t)snprintf(h, sizeof(h),
				    "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }",
				    descr, fortran ? "True" : "False", shape);

	while ((10 + l + 1) % 64)
		h[l++] = ' ';
	h[l++] = '\n';
	fwrite("\x93NUMPY\x01\x00", 1, 8, f);
	fputc((int)(l & 0xff), f);
	fputc((int)(l >> 8), f);
	fwrite(h, 1, l, f);
	fwrite(data, 1, bytes, f);
	fclose(f);
}

static void make_files(void)
{
	char cmd[1024];
	const char *top = getenv("top_builddir");
	static double a[500][3], at[3][500];
	static unsigned char be[500 * 3 * 8];
	int16_t i2[20];
	FILE *f;

	snprintf(cmd, sizeof(cmd), "rm -rf " DIR " && %s/tests/gen-ros " DIR " 200 20",
		 top ? top : ".");
	if (system(cmd) != 0) {
		fprintf(stderr, "gen-ros failed\n");
		exit(1);
	}
	snprintf(cmd, sizeof(cmd), "mkdir " DIR "/hostile && %s/tests/gen-ros " DIR
		 "/hostile 200 1 hostile", top ? top : ".");
	if (system(cmd) != 0) {
		fprintf(stderr, "gen-ros hostile failed\n");
		exit(1);
	}
	for (int i = 0; i < 500; i++)
		for (int k = 0; k < 3; k++) {
			a[i][k] = 1.5 * i + k + 0.001 * (i % 7);
			at[k][i] = a[i][k];
		}
	a[7][1] = 1.5 * 7 + 1;
	at[1][7] = a[7][1];
	for (size_t i = 0; i < 500 * 3; i++) {
		unsigned char *p = (unsigned char *)&a[0][0] + 8 * i;

		for (int j = 0; j < 8; j++)
			be[8 * i + j] = p[7 - j];
	}
	write_npy("a.npy", "<f8", false, "(500, 3)", a, sizeof(a));
	write_npy("af.npy", "<f8", true, "(500, 3)", at, sizeof(at));
	write_npy("w.npy", "<f8", false, "(3, 500)", at, sizeof(at));
	write_npy("be.npy", ">f8", false, "(500, 3)", be, sizeof(be));
	for (int i = 0; i < 20; i++)
		i2[i] = (int16_t)-i;
	write_npy("i2.npy", "<i2", false, "(20,)", i2, sizeof(i2));
	write_npy("cube.npy", "<f8", false, "(5, 10, 10)", a, 500 * 8);
	write_npy("rec.npy", "[('a', '<f8')]", false, "(500,)", a, 500 * 8);
	f = fopen(path("c.csv"), "w");
	fprintf(f, "time [s],gx [deg/s]\n");
	for (int i = 0; i < 3000; i++)
		fprintf(f, "%.2f,%.6f\n", i / 100.0, sin(i * 0.1));
	fclose(f);
	f = fopen(path("ns.csv"), "w");
	fprintf(f, "t,gx\n");
	for (int i = 0; i < 100; i++)
		fprintf(f, "%lld,%d\n", 1700000000000000000LL + 5000000LL * i, i % 3);
	fclose(f);
	f = fopen(path("rostopic.csv"), "w");
	fprintf(f, "%%time,field.header.seq,field.header.stamp,field.header.frame_id,"
		   "field.orientation.x,field.orientation.y,field.orientation.z,field.orientation.w,"
		   "field.angular_velocity.x,field.angular_velocity.y,field.angular_velocity.z,"
		   "field.linear_acceleration.x,field.linear_acceleration.y,field.linear_acceleration.z\n");
	for (int i = 0; i < 100; i++)
		fprintf(f, "%lld,%d,%lld,imu_link,0,0,0,1,0.01,0.02,0.03,0.1,0.2,9.8\n",
			1700000000001500000LL + 5000000LL * i, i,
			1700000000000000000LL + 5000000LL * i);
	fclose(f);
	/* 32 MiB after a tag declaring 64 bytes; 4 GiB declared from a
	 * stream of a few bytes; 32 MiB in an int8 element */
	write_matz("over.mat", 14, 64, 32u << 20);
	write_matz("ratio.mat", 14, 0xfffffff0u, 0);
	write_matz("int8.mat", 1, 32u << 20, 32u << 20);
	if (system("gzip -c " DIR "/c.csv > " DIR "/c.csv.gz && gzip -c " DIR
		   "/a.npy > " DIR "/a.npy.gz") != 0)
		exit(1);
}

static Suite *make_suite(void)
{
	Suite *s = suite_create("ros");
	TCase *tc = tcase_create("ros");

	make_files();
	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, same_channels_everywhere);
	tcase_add_test(tc, topics_listed);
	tcase_add_test(tc, topic_selection);
	tcase_add_loop_test(tc, cut_and_corrupt, 0,
#ifdef HAVE_SQLITE3
			    9
#else
			    8
#endif
	);
	tcase_add_test(tc, npy_layouts);
#ifdef HAVE_SQLITE3
	tcase_add_test(tc, db3_schema_refused);
	tcase_add_test(tc, db3_many_topics);
#endif
	tcase_add_test(tc, zstd_bombs);
	tcase_add_test(tc, matz_bounded);
	tcase_add_test(tc, gzip_and_rate_hint);
	suite_add_tcase(s, tc);
	return s;
}
