/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The "points" array of an allan channel's JSON written as text, byte for
 * byte what jansson dumps of the tree (ssc_json_real_text), without the
 * tree: on an all-tau grid the tree costs more than the analysis.  A long
 * grid has its later half formatted on a second thread while the first
 * half is written.
 */
#include "workbench.h"
#include "results.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

const char *ssc_allan_noise_name(int alpha)
{
	static const char *const n[] = { "RWHM", "FWHM", "RWFM", "FFM", "WFM",
					 "FPM", "WPM" };

	return alpha >= -4 && alpha <= 2 ? n[alpha + 4] : "?";
}

/* append key (a literal) and a value's JSON text at *p */
#define PUT_KEY(p, key) (memcpy(p, key, sizeof(key) - 1), p += sizeof(key) - 1)

static char *put_real(char *p, double v)
{
	return p + ssc_json_real_text(p, v);
}

static char *put_int(char *p, long long v)
{
	char t[24];
	int n = 0;
	unsigned long long a = v < 0 ? 0 - (unsigned long long)v :
				       (unsigned long long)v;

	if (v < 0)
		*p++ = '-';
	do {
		t[n++] = (char)('0' + a % 10);
		a /= 10;
	} while (a);
	while (n)
		*p++ = t[--n];
	return p;
}

/* the JSON text of one point (a leading comma unless first) into line,
 * at most POINT_LINE_MAX bytes; returns its length */
#define POINT_LINE_MAX 512 /* 9 numbers of at most 24 characters, keys, a name */
static size_t point_line(char *line, const struct sscope_allan_point *pt,
			 enum sscope_allan_dev dev, double sc, bool first)
{
	const char *nn = ssc_allan_noise_name(pt->alpha);
	char *p = line;

	if (!first)
		*p++ = ',';
	PUT_KEY(p, "{\"tau_s\":");
	p = put_real(p, pt->tau_s);
	PUT_KEY(p, ",\"m\":");
	p = put_int(p, (long long)pt->m);
	PUT_KEY(p, ",\"terms\":");
	p = put_int(p, (long long)pt->terms);
	PUT_KEY(p, ",\"dev\":");
	p = put_real(p, pt->dev / sc);
	PUT_KEY(p, ",\"dev_lo\":");
	p = put_real(p, pt->dev_lo / sc);
	PUT_KEY(p, ",\"dev_hi\":");
	p = put_real(p, pt->dev_hi / sc);
	PUT_KEY(p, ",\"edf\":");
	p = put_real(p, pt->edf);
	if (!sscope_allan_dev_has_ci(dev)) {
		/* MTIE, TIE rms: no noise type, no interval */
		PUT_KEY(p, ",\"alpha\":null,\"noise\":null");
	} else {
		PUT_KEY(p, ",\"alpha\":");
		p = put_int(p, pt->alpha);
		PUT_KEY(p, ",\"noise\":\"");
		memcpy(p, nn, strlen(nn));
		p += strlen(nn);
		*p++ = '"';
	}
	if (pt->skipped) {
		PUT_KEY(p, ",\"skipped\":");
		p = put_int(p, (long long)pt->skipped);
	}
	if (pt->stride != 1 && dev != SSCOPE_ALLAN_DEV_ADEV &&
	    dev != SSCOPE_ALLAN_DEV_HDEV) {
		PUT_KEY(p, ",\"stride\":");
		p = put_int(p, (long long)pt->stride);
		PUT_KEY(p, ",\"edf_full\":");
		p = put_real(p, pt->edf_full);
	}
	*p++ = '}';
	return (size_t)(p - line);
}

/* points [lo, hi) of a channel formatted into one buffer (the later half
 * of a long grid, on a second thread while the first half is written) */
struct points_part {
	const struct sscope_allan_point *pts;
	enum sscope_allan_dev dev;
	double sc;
	size_t lo, hi;
	char *buf; /* (hi - lo) * POINT_LINE_MAX bytes */
	size_t len;
	pthread_t tid;
};

static void *points_part_run(void *arg)
{
	struct points_part *pp = arg;
	char *p = pp->buf;

	for (size_t i = pp->lo; i < pp->hi; i++)
		p += point_line(p, &pp->pts[i], pp->dev, pp->sc, i == 0);
	pp->len = (size_t)(p - pp->buf);
	return NULL;
}

/* grids from this many points split their text in two halves */
#define POINTS_SPLIT 2048

bool ssc_allan_points_text(FILE *f, const struct sscope_allan_point *pts,
			   size_t n, double dev_scale,
			   enum sscope_allan_dev dev, bool two_threads)
{
	struct points_part pp = { 0 };
	bool ok, split = false;
	size_t upto = n;

	if (n >= POINTS_SPLIT && two_threads) {
		pp.pts = pts;
		pp.dev = dev;
		pp.sc = dev_scale;
		pp.lo = n / 2;
		pp.hi = n;
		pp.buf = malloc((pp.hi - pp.lo) * POINT_LINE_MAX);
		if (pp.buf && pthread_create(&pp.tid, NULL, points_part_run, &pp) == 0) {
			split = true;
			upto = pp.lo;
		}
	}
	ok = fputc('[', f) != EOF;
	for (size_t i = 0; ok && i < upto; i++) {
		char line[POINT_LINE_MAX];
		size_t len = point_line(line, &pts[i], dev, dev_scale, i == 0);

		ok = fwrite(line, 1, len, f) == len;
	}
	if (split) {
		pthread_join(pp.tid, NULL);
		ok = ok && fwrite(pp.buf, 1, pp.len, f) == pp.len;
	}
	free(pp.buf);
	return ok && fputc(']', f) != EOF;
}
