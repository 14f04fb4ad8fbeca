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
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check-main.h"

#define DIR "test-ros.tmp"

static const char *const containers[] = {
	"imu-none.bag", "imu-bz2.bag", "imu-lz4.bag", "imu-zstd.mcap",
	"imu-lz4.mcap", "imu-none.mcap", "imu-ros1.mcap", "rosbag2-mcap",
#ifdef HAVE_SQLITE3
	"rosbag2", "rosbag2/rosbag2_0.db3",
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
	tcase_add_test(tc, gzip_and_rate_hint);
	suite_add_tcase(s, tc);
	return s;
}
