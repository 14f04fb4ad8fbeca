/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Raw binary input at memory speed: the block converter of host-order
 * rows against the row-by-row path (the same file in the other byte order,
 * which takes it), gaps and bad values inside a block with their exact
 * location, captures used in place (mapped, read-only) and their pages
 * given back, the Allan engine's release callback (every sample released
 * once, results unchanged), the fit of an all-tau grid on its dense
 * taus, one-pass statistics (vector and scalar blocks), and CSV cells
 * skipped after the last column in use.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include "sscope-allan.h"
#include "check-main.h"

static char dir[64];

static void setup(void)
{
	snprintf(dir, sizeof(dir), "/tmp/sscope-rawfast-XXXXXX");
	ck_assert_ptr_nonnull(mkdtemp(dir));
}

static void teardown(void)
{
	char cmd[128];

	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
	ck_assert_int_eq(system(cmd), 0);
}

static const char *put(const char *name, const void *data, size_t len)
{
	static char path[4][128];
	static int k;
	char *p = path[k++ & 3];
	FILE *f;

	snprintf(p, 128, "%s/%s", dir, name);
	f = fopen(p, "wb");
	ck_assert_ptr_nonnull(f);
	ck_assert_uint_eq(fwrite(data, 1, len, f), len);
	fclose(f);
	return p;
}

/* the bytes of each value reversed */
static void swap_all(unsigned char *b, size_t len, size_t size)
{
	for (size_t i = 0; i + size <= len; i += size)
		for (size_t a = 0, z = size - 1; a < z; a++, z--) {
			unsigned char t = b[i + a];

			b[i + a] = b[i + z];
			b[i + z] = t;
		}
}

static int little_endian(void)
{
	const uint16_t one = 1;

	return *(const unsigned char *)&one;
}

static const struct {
	const char *name;
	size_t size;
} types[] = { { "i16", 2 }, { "u16", 2 }, { "i32", 4 },
	      { "u32", 4 }, { "f32", 4 }, { "f64", 8 } };

/* value v of type t at b */
static void store(int t, unsigned char *b, double v)
{
	switch (t) {
	case 0: {
		int16_t x = (int16_t)v;

		memcpy(b, &x, 2);
		break;
	}
	case 1: {
		uint16_t x = (uint16_t)v;

		memcpy(b, &x, 2);
		break;
	}
	case 2: {
		int32_t x = (int32_t)v;

		memcpy(b, &x, 4);
		break;
	}
	case 3: {
		uint32_t x = (uint32_t)v;

		memcpy(b, &x, 4);
		break;
	}
	case 4: {
		float x = (float)v;

		memcpy(b, &x, 4);
		break;
	}
	default:
		memcpy(b, &v, 8);
		break;
	}
}

#define ROWS 300000
#define CH 3

/* every type, three channels, several 1 MiB blocks: the host-order file
 * (block converter) and its byte-swapped twin (row by row) give the same
 * bits, with scaling, offset, a unit and a time column */
START_TEST(blocks_equal_rows)
{
	for (size_t t = 0; t < sizeof(types) / sizeof(types[0]); t++) {
		size_t len = (size_t)ROWS * CH * types[t].size;
		unsigned char *b = malloc(len);
		struct sscope_reader_opts o = { 0 };
		struct sscope_capture *fast = NULL, *slow = NULL;
		struct sscope_diag d = { "" };
		char spec[2][32];
		const char *pf, *ps;

		ck_assert_ptr_nonnull(b);
		for (size_t i = 0; i < ROWS; i++)
			for (size_t c = 0; c < CH; c++) {
				double v = c == 0 ? (double)(i % 30000) :
					   (double)((i * 7919 + c * 104729) % 20011);

				if (t == 0 || t == 2 || t == 4 || t == 5)
					v -= c ? 10005 : 0;
				if (t >= 4)
					v *= 0.37;
				store((int)t, b + (i * CH + c) * types[t].size, v);
			}
		pf = put("host.bin", b, len);
		swap_all(b, len, types[t].size);
		ps = put("swapped.bin", b, len);
		snprintf(spec[0], sizeof(spec[0]), "%s:%d:%s", types[t].name, CH,
			 little_endian() ? "le" : "be");
		snprintf(spec[1], sizeof(spec[1]), "%s:%d:%s", types[t].name, CH,
			 little_endian() ? "be" : "le");
		o.raw_scale = 0.0123;
		o.raw_offset = 2.5;
		o.default_unit = "deg/s";
		o.time_column = "1";
		o.raw = spec[0];
		ck_assert_int_eq(sscope_capture_load(&fast, pf, &o, &d), 0);
		o.raw = spec[1];
		ck_assert_int_eq(sscope_capture_load(&slow, ps, &o, &d), 0);
		ck_assert_uint_eq(fast->n, ROWS);
		ck_assert_uint_eq(slow->n, ROWS);
		ck_assert_uint_eq(fast->n_channels, CH - 1);
		ck_assert_ptr_null(fast->mapping);
		for (size_t c = 0; c < CH - 1; c++)
			ck_assert(memcmp(fast->channels[c].data, slow->channels[c].data,
					 ROWS * sizeof(double)) == 0);
		ck_assert(memcmp(fast->time_s, slow->time_s,
				 ROWS * sizeof(double)) == 0);
		/* and the values are the documented ones */
		ck_assert(fast->channels[1].data[12345] ==
			  ((double)((12345 * 7919 + 2 * 104729) % 20011 -
				    (t == 0 || t == 2 || t == 4 || t == 5 ? 10005 : 0)) *
				   (t >= 4 ? 0.37 : 1) + 2.5) * 0.0123 *
				  0.017453292519943295 ||
			  t == 4); /* f32 rounds the stored value */
		sscope_capture_free(fast);
		sscope_capture_free(slow);
		free(b);
	}
}
END_TEST

/* a NaN and an infinity deep inside a block: refused at their row and
 * column, or the NaN read as a gap with every other value intact */
START_TEST(bad_values_located)
{
	size_t n = 200000, len = n * CH * sizeof(double);
	double *v = malloc(len);
	struct sscope_reader_opts o = { .raw = little_endian() ? "f64:3:le" : "f64:3:be" };
	struct sscope_capture *cap = NULL;
	struct sscope_diag d = { "" };
	const char *p;

	ck_assert_ptr_nonnull(v);
	for (size_t i = 0; i < n * CH; i++)
		v[i] = 1.5 + (double)(i % 977) * 0.25;
	v[150001 * CH + 1] = NAN;
	p = put("nan.bin", v, len);
	ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), -EBADMSG);
	ck_assert_ptr_nonnull(strstr(d.msg, "row 150002, column 2"));
	ck_assert_ptr_nonnull(strstr(d.msg, "NaN"));
	o.nan_as_gap = true;
	ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), 0);
	ck_assert_uint_eq(cap->n_nan, 1);
	for (size_t i = 0; i < n; i++)
		for (size_t c = 0; c < CH; c++)
			if (i == 150001 && c == 1)
				ck_assert(isnan(cap->channels[c].data[i]));
			else
				ck_assert(cap->channels[c].data[i] == v[i * CH + c]);
	sscope_capture_free(cap);
	v[150001 * CH + 1] = 2.0;
	v[199999 * CH + 2] = -INFINITY;
	p = put("inf.bin", v, len);
	ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), -EBADMSG);
	ck_assert_ptr_nonnull(strstr(d.msg, "row 200000, column 3"));
	ck_assert_ptr_nonnull(strstr(d.msg, "infinite"));
	free(v);
}
END_TEST

/* one host-order float64 channel is used in place: mapped, equal, pages
 * given back and fetched again; anything else is copied */
START_TEST(in_place)
{
	size_t n = 1 << 20;
	double *v = malloc(n * sizeof(double));
	struct sscope_reader_opts o = { .raw = little_endian() ? "f64:1:le" : "f64:1:be",
				      .in_place = true };
	struct sscope_capture *cap = NULL;
	struct sscope_diag d = { "" };
	const char *p;

	ck_assert_ptr_nonnull(v);
	for (size_t i = 0; i < n; i++)
		v[i] = sin((double)i * 0.001) * 2.385;
	p = put("one.f64", v, n * sizeof(double));
	ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), 0);
	ck_assert_ptr_nonnull(cap->mapping);
	ck_assert_ptr_eq(cap->channels[0].data, cap->mapping);
	ck_assert_uint_eq(cap->mapping_len, n * sizeof(double));
	ck_assert_uint_eq(cap->n, n);
	ck_assert(memcmp(cap->channels[0].data, v, n * sizeof(double)) == 0);
	/* mapped: its pages may be given back and fetched again */
	ck_assert(sscope_capture_mapped(cap, cap->channels[0].data));
	ck_assert(sscope_capture_mapped(cap, cap->channels[0].data + n - 1));
	ck_assert(!sscope_capture_mapped(cap, v)); /* not the capture's */
	ck_assert(!sscope_capture_mapped(NULL, v));
	madvise((void *)(uintptr_t)cap->mapping, cap->mapping_len, MADV_DONTNEED);
	ck_assert(memcmp(cap->channels[0].data, v, n * sizeof(double)) == 0);
	sscope_capture_free(cap);

	/* a unit to convert, no in_place, two channels: copied */
	o.default_unit = "deg/s";
	ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), 0);
	ck_assert_ptr_null(cap->mapping);
	ck_assert(!sscope_capture_mapped(cap, cap->channels[0].data));
	ck_assert(cap->channels[0].data[777] == v[777] * 0.017453292519943295);
	sscope_capture_free(cap);
	o.default_unit = NULL;
	o.in_place = false;
	ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), 0);
	ck_assert_ptr_null(cap->mapping);
	sscope_capture_free(cap);
	o.in_place = true;
	o.raw = little_endian() ? "f64:2:le" : "f64:2:be";
	ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), 0);
	ck_assert_ptr_null(cap->mapping);
	ck_assert_uint_eq(cap->n, n / 2);
	sscope_capture_free(cap);

	/* gaps in place only when allowed; the message otherwise */
	o.raw = little_endian() ? "f64:1:le" : "f64:1:be";
	v[4321] = NAN;
	p = put("gap.f64", v, n * sizeof(double));
	ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), -EBADMSG);
	ck_assert_ptr_nonnull(strstr(d.msg, "row 4322"));
	o.nan_as_gap = true;
	ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), 0);
	ck_assert_ptr_nonnull(cap->mapping);
	ck_assert_uint_eq(cap->n_nan, 1);
	ck_assert(!cap->values_unchecked);
	sscope_capture_free(cap);

	/* left unchecked: loaded in place as it is, and the check afterwards
	 * gives the reader's message, word for word */
	{
		char want[sizeof(d.msg)];

		o.nan_as_gap = false;
		v[4321] = 1;
		v[n - 5] = INFINITY;
		p = put("inf.f64", v, n * sizeof(double));
		ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), -EBADMSG);
		ck_assert_ptr_nonnull(strstr(d.msg, "infinite value"));
		snprintf(want, sizeof(want), "%s", d.msg);
		o.in_place_unchecked = true;
		ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), 0);
		ck_assert_ptr_nonnull(cap->mapping);
		ck_assert(cap->values_unchecked);
		ck_assert(isinf(cap->channels[0].data[n - 5]));
		d.msg[0] = '\0';
		ck_assert_int_eq(sscope_capture_check_values(cap, false, &d), -EBADMSG);
		ck_assert_str_eq(d.msg, want);
		sscope_capture_free(cap);
		/* a NaN: an error unless gaps are allowed */
		v[n - 5] = 1;
		v[17] = NAN;
		p = put("nan.f64", v, n * sizeof(double));
		o.in_place_unchecked = false;
		ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), -EBADMSG);
		snprintf(want, sizeof(want), "%s", d.msg);
		o.in_place_unchecked = true;
		ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), 0);
		ck_assert_int_eq(sscope_capture_check_values(cap, false, &d), -EBADMSG);
		ck_assert_str_eq(d.msg, want);
		ck_assert_int_eq(sscope_capture_check_values(cap, true, &d), 0);
		sscope_capture_free(cap);
		/* a good file passes; a checked capture is never looked at */
		v[17] = 1;
		p = put("good.f64", v, n * sizeof(double));
		ck_assert_int_eq(sscope_capture_load(&cap, p, &o, &d), 0);
		ck_assert_int_eq(sscope_capture_check_values(cap, false, &d), 0);
		sscope_capture_free(cap);
		ck_assert_int_eq(sscope_capture_check_values(NULL, false, &d), 0);
	}
	free(v);
}
END_TEST


/* resident pages of this process (/proc/self/statm), or 0 */
static size_t resident_pages(void)
{
	FILE *f = fopen("/proc/self/statm", "r");
	size_t size = 0, res = 0;

	if (!f)
		return 0;
	if (fscanf(f, "%zu %zu", &size, &res) != 2)
		res = 0;
	fclose(f);
	return res;
}

/* ssc_par_for(): every item once, each slot below the thread count; a
 * loop asked for from inside an item, or from another thread while one
 * runs, runs on its caller alone and still does every item */
struct par_ctx {
	_Atomic unsigned *hits;
	unsigned threads;
	_Atomic unsigned bad_slot;
	bool nest;
};

static void par_inner(void *ctx, size_t i, unsigned slot)
{
	struct par_ctx *c = ctx;

	if (slot != 0) /* a nested loop runs on its caller, slot 0 */
		atomic_fetch_add(&c->bad_slot, 1);
	atomic_fetch_add(&c->hits[i], 1);
}

static void par_item(void *ctx, size_t i, unsigned slot)
{
	struct par_ctx *c = ctx;

	if (slot >= c->threads)
		atomic_fetch_add(&c->bad_slot, 1);
	atomic_fetch_add(&c->hits[i], 1);
	if (c->nest && i % 97 == 0) {
		_Atomic unsigned inner[5] = { 0 };
		struct par_ctx ic = { inner, 1, 0, false };

		ssc_par_for(5, 4, par_inner, &ic);
		for (int k = 0; k < 5; k++)
			if (inner[k] != 1)
				atomic_fetch_add(&c->bad_slot, 1);
		if (ic.bad_slot)
			atomic_fetch_add(&c->bad_slot, 1);
	}
}

struct par_thread {
	_Atomic unsigned *hits;
	size_t n;
	unsigned bad;
};

static void *par_other(void *arg)
{
	struct par_thread *t = arg;
	struct par_ctx c = { t->hits, 3, 0, false };

	for (int rep = 0; rep < 50; rep++)
		ssc_par_for(t->n, 3, par_item, &c);
	t->bad = c.bad_slot;
	return NULL;
}

START_TEST(par_for_items)
{
	enum { N = 1000 };
	static _Atomic unsigned hits[N], hits2[N];
	struct par_ctx c = { hits, 3, 0, true };
	struct par_thread t = { hits2, N, 0 };
	pthread_t tid;

	for (int rep = 0; rep < 200; rep++) {
		for (size_t i = 0; i < N; i++)
			hits[i] = 0;
		ssc_par_for(N, 3, par_item, &c);
		for (size_t i = 0; i < N; i++)
			ck_assert_msg(hits[i] == 1, "rep %d: item %zu run %u times",
				      rep, i, hits[i]);
	}
	ck_assert_uint_eq(c.bad_slot, 0);
	/* two callers at once: each loop complete */
	for (size_t i = 0; i < N; i++)
		hits[i] = hits2[i] = 0;
	c.nest = false;
	ck_assert_int_eq(pthread_create(&tid, NULL, par_other, &t), 0);
	for (int rep = 0; rep < 50; rep++)
		ssc_par_for(N, 3, par_item, &c);
	ck_assert_int_eq(pthread_join(tid, NULL), 0);
	for (size_t i = 0; i < N; i++) {
		ck_assert_uint_eq(hits[i], 50);
		ck_assert_uint_eq(hits2[i], 50);
	}
	ck_assert_uint_eq(c.bad_slot + t.bad, 0);
	/* one thread, one item, none */
	for (size_t i = 0; i < N; i++)
		hits[i] = 0;
	ssc_par_for(N, 1, par_item, &c);
	ssc_par_for(1, 4, par_item, &c);
	ssc_par_for(0, 4, par_item, &c);
	ck_assert_uint_eq(hits[0], 2);
	ck_assert_uint_eq(hits[N - 1], 1);
	/* a child of fork() (the helpers started above are not in it) */
	{
		pid_t pid = fork();
		int st = -1;

		ck_assert_int_ge(pid, 0);
		if (pid == 0) {
			for (size_t i = 0; i < N; i++)
				hits[i] = 0;
			c.bad_slot = 0;
			ssc_par_for(N, 3, par_item, &c);
			for (size_t i = 0; i < N; i++)
				if (hits[i] != 1)
					_exit(1);
			_exit(c.bad_slot ? 2 : 0);
		}
		ck_assert_int_eq(waitpid(pid, &st, 0), pid);
		ck_assert_msg(WIFEXITED(st) && WEXITSTATUS(st) == 0,
			      "the loop in a child of fork: status %d", st);
	}
}
END_TEST

/* ssc_release_pages() gives back exactly the whole pages inside the range
 * (they read as zeros, the process's resident set shrinks by them; the
 * partial pages at both ends keep their data), on two threads; and an
 * analysis whose plan gives its workspace back so is the same. */
START_TEST(workspace_release)
{
	const long pg = sysconf(_SC_PAGESIZE);
	const size_t ps = pg > 0 ? (size_t)pg : 4096, pages = 8192;
	unsigned char *buf = aligned_alloc(ps, (pages + 2) * ps);
	unsigned char *a = buf + ps / 2; /* starts and ends mid-page */
	const size_t len = pages * ps;
	size_t before, after, n = 400000;
	double *y = malloc(n * sizeof(double));
	struct sscope_allan_result *r1 = NULL, *r2 = NULL;
	struct sscope_allan_opts ao = { .ci_level = -1, .threads = 2 };
	struct sscope_noise_fit_opts fo = { .skip = true };

	ck_assert_ptr_nonnull(buf);
	ck_assert_ptr_nonnull(y);
	memset(buf, 0x5a, (pages + 2) * ps);
	/* the threads started first (on pages never touched): their stacks
	 * are not in the count */
	{
		void *w = aligned_alloc(ps, 2 * pages * ps);

		ck_assert_ptr_nonnull(w);
		ssc_release_pages(w, 2 * pages * ps, 2);
		free(w);
	}
	before = resident_pages();
	ssc_release_pages(a, len, 2);
	after = resident_pages();
	/* pages - 1 whole pages inside: the half pages at the ends stay */
	for (size_t i = 0; i < len; i++) {
		bool inside = i >= ps / 2 && i < len - ps / 2;

		if (a[i] != (inside ? 0 : 0x5a))
			ck_abort_msg("byte %zu: %d", i, a[i]);
	}
	/* (an eighth of slack for what else the process maps meanwhile:
	 * under the sanitizers, more) */
	if (before && after)
		ck_assert_msg(before + pages / 8 >= after + pages - 1,
			      "resident %zu -> %zu pages", before, after);
	free(buf);
	for (size_t i = 0; i < n; i++)
		y[i] = 0.3 + 0.01 * sin((double)i * 2.385) + 1e-3 * (double)(i % 7);
	ck_assert_int_eq(sscope_allan_analyze(y, 1, n, 100, SSCOPE_ALLAN_TAUS_OCTAVE,
					      &ao, &fo, &r1, NULL), 0);
	ao.plan_flags = SSCOPE_ALLAN_RELEASE_WORKSPACE;
	ck_assert_int_eq(sscope_allan_analyze(y, 1, n, 100, SSCOPE_ALLAN_TAUS_OCTAVE,
					      &ao, &fo, &r2, NULL), 0);
	ck_assert_uint_eq(r1->n_points, r2->n_points);
	for (size_t j = 0; j < r1->n_points; j++)
		ck_assert(r1->points[j].dev == r2->points[j].dev);
	sscope_allan_result_free(r1);
	sscope_allan_result_free(r2);
	free(y);
}
END_TEST

/* resident kB of the mapping that starts at @p addr (/proc/self/smaps:
 * that mapping's own pages, whatever the heap does), or -1 */
static long mapping_rss_kb(const void *addr)
{
	FILE *f = fopen("/proc/self/smaps", "r");
	char line[512];
	bool in = false;
	long kb = -1;

	if (!f)
		return -1;
	while (fgets(line, sizeof(line), f)) {
		unsigned long lo, hi;

		if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2 && strchr(line, '-') < strchr(line, ' ')) {
			in = lo == (unsigned long)(uintptr_t)addr;
			continue;
		}
		if (in && sscanf(line, "Rss: %ld kB", &kb) == 1)
			break;
	}
	fclose(f);
	return kb;
}

/* SSCOPE_ALLAN_EVICT_INPUT on a record mapped from its file: the tiled
 * and the contiguous engines give its pages back behind their pass (the
 * mapping's resident pages, /proc/self/smaps: none kept, where without the
 * flag the whole record stays), and the points do not change */
START_TEST(allan_evict_input)
{
	size_t n = 3000000, m[64], nm = 0;
	const long file_kb = (long)(n * sizeof(double) / 1024);
	double *y = malloc(n * sizeof(double));
	struct sscope_allan_point *a = calloc(64, sizeof(*a)), *b = calloc(64, sizeof(*b));
	uint64_t s = 88172645463325252ull;
	char path[] = "/tmp/ssc-evict-XXXXXX";
	int fd = mkstemp(path);
	const double *map;

	ck_assert_ptr_nonnull(y);
	ck_assert_int_ge(fd, 0);
	for (size_t i = 0; i < n; i++) {
		s ^= s << 13;
		s ^= s >> 7;
		s ^= s << 17;
		y[i] = 0.3 + (double)(s >> 11) * 0x1p-53;
	}
	ck_assert(write(fd, y, n * sizeof(double)) == (ssize_t)(n * sizeof(double)));
	map = mmap(NULL, n * sizeof(double), PROT_READ, MAP_PRIVATE, fd, 0);
	ck_assert(map != MAP_FAILED);
	close(fd);
	unlink(path);
	ck_assert_int_eq(sscope_allan_grid(SSCOPE_ALLAN_TAUS_OCTAVE, n / 2, m, 64, &nm), 0);
	for (int dev = 0; dev < 2; dev++) {
		struct sscope_allan_opts o = { .dev = dev ? SSCOPE_ALLAN_DEV_MDEV : SSCOPE_ALLAN_DEV_OADEV,
					       .ci_level = -1 };
		struct sscope_allan *p = NULL;
		size_t na = 0, nb = 0;
		long kept = -1, evicted = -1;

		ck_assert_int_eq(sscope_allan_new(&p, n, &o), 0);
		ck_assert_int_eq(sscope_allan_compute(p, y, 1, n, 100, m, nm, a, &na, NULL), 0);
		sscope_allan_free(p);
		/* without the flag the mapped record stays resident; with
		 * it, the pages go back */
		for (int flag = 0; flag < 2; flag++) {
			madvise((void *)(uintptr_t)map, n * sizeof(double), MADV_DONTNEED);
			o.plan_flags = flag ? SSCOPE_ALLAN_EVICT_INPUT : 0;
			ck_assert_int_eq(sscope_allan_new(&p, n, &o), 0);
			ck_assert_int_eq(sscope_allan_compute(p, map, 1, n, 100, m, nm, b, &nb,
							      NULL), 0);
			sscope_allan_free(p);
			*(flag ? &evicted : &kept) = mapping_rss_kb(map);
			ck_assert_uint_eq(na, nb);
			for (size_t j = 0; j < na; j++)
				ck_assert(a[j].dev == b[j].dev);
		}
		/* the mapping's own resident pages: all of the record
		 * without the flag, at most a 64th with it (on two threads
		 * the W samples after a chunk are read by both chunks: a
		 * read after the other chunk gave them back fetched a whole
		 * 2 MiB of the file again for good) */
		if (access("/proc/self/smaps", R_OK) == 0)
			ck_assert_msg(kept >= 0 && evicted >= 0,
				      "the mapping is not in /proc/self/smaps");
		if (kept >= 0 && evicted >= 0) {
			ck_assert_msg(kept >= file_kb * 7 / 8,
				      "without the flag: %ld kB of the %ld kB record resident",
				      kept, file_kb);
			ck_assert_msg(evicted <= file_kb / 64,
				      "with the flag: %ld kB of the %ld kB record resident",
				      evicted, file_kb);
		}
	}
	munmap((void *)(uintptr_t)map, n * sizeof(double));
	free(y);
	free(a);
	free(b);
}
END_TEST

/* sscope_allan_analyze() without the fit: OADEV alone, no fit error */
START_TEST(analyze_skip_fit)
{
	size_t n = 20000;
	double *y = malloc(n * sizeof(double));
	struct sscope_noise_fit_opts fo = { .skip = true };
	struct sscope_allan_opts ao = { .dev = SSCOPE_ALLAN_DEV_MDEV };
	struct sscope_allan_result *r = NULL;

	ck_assert_ptr_nonnull(y);
	for (size_t i = 0; i < n; i++)
		y[i] = sin((double)i * 1.7) + 0.01 * (double)(i % 13);
	ck_assert_int_eq(sscope_allan_analyze(y, 1, n, 10, SSCOPE_ALLAN_TAUS_OCTAVE, &ao,
					      &fo, &r, NULL), 0);
	ck_assert(!r->have_fit);
	ck_assert_int_eq(r->fit_error, 0);
	ck_assert_ptr_eq(r->oadev, r->points);
	ck_assert_uint_gt(r->n_points, 5);
	sscope_allan_result_free(r);
	fo.skip = false;
	ck_assert_int_eq(sscope_allan_analyze(y, 1, n, 10, SSCOPE_ALLAN_TAUS_OCTAVE, &ao,
					      &fo, &r, NULL), 0);
	ck_assert(r->oadev != r->points);
	sscope_allan_result_free(r);
	free(y);
}
END_TEST

/* an all-tau grid is fitted on its dense taus: the same fit as the dense
 * grid's, from points equal to the dense grid's own */
START_TEST(all_grid_fit_dense)
{
	size_t n = 6000;
	double *y = malloc(n * sizeof(double));
	struct sscope_allan_result *all = NULL, *dense = NULL;
	uint64_t s = 88172645463325252ull;
	double w = 0;

	ck_assert_ptr_nonnull(y);
	for (size_t i = 0; i < n; i++) {
		s ^= s << 13;
		s ^= s >> 7;
		s ^= s << 17;
		w += ((double)(s >> 11) * 0x1p-53 - 0.5) * 0.01;
		y[i] = (double)(s >> 11) * 0x1p-53 + w;
	}
	for (int dev = 0; dev < 2; dev++) {
		struct sscope_allan_opts ao = { .dev = dev ? SSCOPE_ALLAN_DEV_MDEV :
							     SSCOPE_ALLAN_DEV_OADEV };

		ck_assert_int_eq(sscope_allan_analyze(y, 1, n, 10, SSCOPE_ALLAN_TAUS_ALL,
						      &ao, NULL, &all, NULL), 0);
		ck_assert_int_eq(sscope_allan_analyze(y, 1, n, 10, SSCOPE_ALLAN_TAUS_DENSE,
						      &ao, NULL, &dense, NULL), 0);
		ck_assert_uint_eq(all->n_points, dev ? n / 3 : n / 2);
		ck_assert(all->oadev != all->points);
		ck_assert_uint_eq(all->n_oadev, dense->n_oadev);
		for (size_t j = 0; j < dense->n_oadev; j++) {
			ck_assert_uint_eq(all->oadev[j].m, dense->oadev[j].m);
			ck_assert(all->oadev[j].dev == dense->oadev[j].dev);
			ck_assert(all->oadev[j].edf == dense->oadev[j].edf);
		}
		ck_assert(all->have_fit && dense->have_fit);
		ck_assert_uint_eq(all->fit.terms, dense->fit.terms);
		for (int t = 0; t < 5; t++) {
			ck_assert(all->fit.coef[t].value == dense->fit.coef[t].value ||
				  (isnan(all->fit.coef[t].value) &&
				   isnan(dense->fit.coef[t].value)));
			ck_assert(all->fit.coef[t].hi == dense->fit.coef[t].hi ||
				  (isnan(all->fit.coef[t].hi) &&
				   isnan(dense->fit.coef[t].hi)));
		}
		sscope_allan_result_free(all);
		sscope_allan_result_free(dense);
	}
	free(y);
}
END_TEST

/* one-pass statistics: the vector blocks, the sample-by-sample blocks
 * (strided, or holding NaN) and a long-double two-pass reference agree */
START_TEST(stats_one_pass)
{
	const size_t n = 100003;
	double *x = malloc(2 * n * sizeof(double));
	uint64_t s = 88172645463325252ull;

	ck_assert_ptr_nonnull(x);
	for (int pass = 0; pass < 3; pass++) {
		struct sscope_stats a, b;
		/* compensated sums in long double: under valgrind, whose x87
		 * long double has a double's precision, still a reference */
		long double m = 0, mc = 0, v = 0, vc = 0, t;
		size_t c = 0, nn = 0;
		double lo = INFINITY, hi = -INFINITY;

		for (size_t i = 0; i < n; i++) {
			s ^= s << 13;
			s ^= s >> 7;
			s ^= s << 17;
			x[2 * i] = (pass == 2 ? 2.385e9 : 0.7) +
				   ((double)(s >> 11) * 0x1p-53 - 0.5) * 2.385;
			x[2 * i + 1] = NAN;
			if (pass == 1 && i % 9973 == 17)
				x[2 * i] = NAN;
		}
		for (size_t i = 0; i < n; i++) {
			double y = x[2 * i];

			if (isnan(y)) {
				nn++;
				continue;
			}
			t = m + y;
			mc += fabsl(m) >= fabsl((long double)y) ? (m - t) + y : (y - t) + m;
			m = t;
			c++;
			lo = fmin(lo, y);
			hi = fmax(hi, y);
		}
		m = (m + mc) / (long double)c;
		for (size_t i = 0; i < n; i++)
			if (!isnan(x[2 * i])) {
				long double d2 = (x[2 * i] - m) * (x[2 * i] - m);

				t = v + d2;
				vc += v >= d2 ? (v - t) + d2 : (d2 - t) + v;
				v = t;
			}
		v = sqrtl((v + vc) / (long double)(c - 1));
		/* strided: sample by sample */
		ck_assert_int_eq(sscope_stats_compute(x, 2, n, &a), 0);
		/* contiguous: vectors */
		for (size_t i = 0; i < n; i++)
			x[i] = x[2 * i];
		ck_assert_int_eq(sscope_stats_compute(x, 1, n, &b), 0);
		ck_assert_uint_eq(a.n, c);
		ck_assert_uint_eq(b.n, c);
		ck_assert_uint_eq(a.n_nan, nn);
		ck_assert_uint_eq(b.n_nan, nn);
		ck_assert(a.min == lo && b.min == lo && a.max == hi && b.max == hi);
		{
			double md = (double)m;
			long double ulp = nextafter(fabs(md), INFINITY) - fabs(md);

			/* two ulps of the mean, or 1e-17 of the spread */
			ck_assert_msg(fabsl(a.mean - m) <= 2 * ulp + 1e-17L &&
				      fabsl(b.mean - m) <= 2 * ulp + 1e-17L,
				      "mean %.17g %.17g %.17Lg", a.mean, b.mean, m);
		}
		ck_assert_rel(a.sd, (double)v, pass == 2 ? 1e-6 : 1e-14);
		ck_assert_rel(b.sd, (double)v, pass == 2 ? 1e-6 : 1e-14);
	}
	free(x);
}
END_TEST

/* CSV cells after the last column in use are skipped by a count of the
 * delimiters: the values equal those of an all-column read, and a row with
 * too few or too many cells, CRLF endings and a last line without newline
 * behave as before */
START_TEST(csv_skipped_columns)
{
	char *text = malloc(1 << 20), *q = text;
	struct sscope_reader_opts o = { .columns = "gx" };
	struct sscope_capture *one = NULL, *all = NULL;
	struct sscope_diag d = { "" };
	const char *p;

	ck_assert_ptr_nonnull(text);
	q += sprintf(q, "time [s],gx [deg/s],gy [deg/s],gz [deg/s],note,ax [g],ay [g]\r\n");
	for (int i = 0; i < 5000; i++)
		q += sprintf(q, "%.2f,%.9g,%.9g,%d,x%d,%.6g,%.3g%s", i * 0.01,
			     sin(i * 0.1) * 2.385, cos(i * 0.3), i, i % 7,
			     i * 1e-4, 1.5, i == 4999 ? "" : i % 2 ? "\r\n" : "\n");
	p = put("seven.csv", text, (size_t)(q - text));
	ck_assert_int_eq(sscope_capture_load(&one, p, &o, &d), 0);
	o.columns = "gx,gy,gz,ax,ay";
	ck_assert_int_eq(sscope_capture_load(&all, p, &o, &d), 0);
	ck_assert_uint_eq(one->n, 5000);
	ck_assert_uint_eq(all->n, 5000);
	ck_assert(memcmp(one->channels[0].data, all->channels[0].data,
			 5000 * sizeof(double)) == 0);
	ck_assert(memcmp(one->time_s, all->time_s, 5000 * sizeof(double)) == 0);
	/* deg/s to rad/s of a value written with 9 digits */
	ck_assert_rel(one->channels[0].data[1234],
		      sin(1234 * 0.1) * 2.385 * 0.017453292519943295, 1e-8);
	sscope_capture_free(one);
	sscope_capture_free(all);
	/* a missing and an extra cell after the last used column */
	o.columns = "gx";
	q = text;
	q += sprintf(q, "t,gx,gy,gz\n1,2,3,4\n2,3,4,5\n3,4,5\n");
	p = put("short.csv", text, (size_t)(q - text));
	ck_assert_int_eq(sscope_capture_load(&one, p, &o, &d), -EBADMSG);
	ck_assert_ptr_nonnull(strstr(d.msg, "line 4: 3 columns where the header has 4"));
	q = text;
	q += sprintf(q, "t,gx,gy,gz\n1,2,3,4\n2,3,4,5,6\n3,4,5,6\n");
	p = put("long.csv", text, (size_t)(q - text));
	ck_assert_int_eq(sscope_capture_load(&one, p, &o, &d), -EBADMSG);
	ck_assert_ptr_nonnull(strstr(d.msg, "line 3: 5 columns where the header has 4"));
	free(text);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("rawfast");
	TCase *tc = tcase_create("rawfast");

	tcase_add_checked_fixture(tc, setup, teardown);
	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, blocks_equal_rows);
	tcase_add_test(tc, bad_values_located);
	tcase_add_test(tc, in_place);
	tcase_add_test(tc, allan_evict_input);
	tcase_add_test(tc, workspace_release);
	tcase_add_test(tc, analyze_skip_fit);
	tcase_add_test(tc, all_grid_fit_dense);
	tcase_add_test(tc, stats_one_pass);
	tcase_add_test(tc, csv_skipped_columns);
	tcase_add_test(tc, par_for_items);
	suite_add_tcase(s, tc);
	return s;
}
