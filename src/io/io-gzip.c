/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * gzip-compressed inputs (RFC 1952) read as a stream through zlib's
 * inflate: the capture reader sees the decompressed bytes and recognises
 * what they hold (text, npy, a bag...) as for an uncompressed file.
 * Concatenated members (what `cat a.gz b.gz` makes) are read one after
 * the other, as gzip does; input that ends inside a member is an error.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include <zlib.h>

#include "io-formats.h"

#define INBUF (1u << 20)

struct ssc_gz {
	z_stream z;
	const unsigned char *pre; /* compressed bytes given up front */
	size_t npre, used_pre;
	int fd;
	unsigned char *in;        /* buffer for bytes read from fd */
	void *map;
	size_t map_len;
	unsigned char *own;       /* copy of `pre` read from a pipe */
	bool in_member;           /* inside a member (its end not seen) */
	bool done;
};

int ssc_gz_open(struct ssc_gz **out, const unsigned char *pre, size_t npre,
		int fd, void *map, size_t map_len)
{
	struct ssc_gz *g = calloc(1, sizeof(*g));

	*out = NULL;
	if (!g)
		return -ENOMEM;
	if (!map && npre) {
		/* the caller's buffer is reused for the decompressed bytes */
		g->own = malloc(npre);
		if (!g->own) {
			free(g);
			return -ENOMEM;
		}
		memcpy(g->own, pre, npre);
		pre = g->own;
	}
	g->pre = pre;
	g->npre = npre;
	g->fd = fd;
	g->map = map;
	g->map_len = map_len;
	/* 15 + 16: gzip wrapper only */
	if (inflateInit2(&g->z, 15 + 16) != Z_OK) {
		free(g->own);
		free(g);
		return -ENOMEM;
	}
	*out = g;
	return 0;
}

/* more compressed input: 1 got some, 0 at the end, < 0 error */
static int refill(struct ssc_gz *g)
{
	if (g->used_pre < g->npre) {
		size_t k = g->npre - g->used_pre;

		if (k > (1u << 30))
			k = 1u << 30;
		g->z.next_in = (unsigned char *)g->pre + g->used_pre;
		g->z.avail_in = (uInt)k;
		g->used_pre += k;
		return 1;
	}
	if (g->fd < 0)
		return 0;
	if (!g->in) {
		g->in = malloc(INBUF);
		if (!g->in)
			return -ENOMEM;
	}
	for (;;) {
		ssize_t n = read(g->fd, g->in, INBUF);

		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0)
			return -EIO;
		g->z.next_in = g->in;
		g->z.avail_in = (uInt)n;
		return n > 0;
	}
}

ssize_t ssc_gz_read(struct ssc_gz *g, void *buf, size_t n, const char *disp,
		    struct sscope_diag *diag)
{
	size_t done = 0;

	if (n > (1u << 30))
		n = 1u << 30;
	while (done < n && !g->done) {
		int rc;

		if (g->z.avail_in == 0) {
			rc = refill(g);
			if (rc < 0)
				return ssc_diag(diag, rc, "%s: read error", disp);
			if (rc == 0) {
				g->done = true;
				if (g->in_member)
					return ssc_diag(diag, -EBADMSG,
							"%s: gzip data truncated (the file ends inside a compressed stream)",
							disp);
				break;
			}
		}
		g->z.next_out = (unsigned char *)buf + done;
		g->z.avail_out = (uInt)(n - done);
		g->in_member = true;
		rc = inflate(&g->z, Z_NO_FLUSH);
		done = n - g->z.avail_out;
		if (rc == Z_STREAM_END) {
			g->in_member = false;
			inflateReset(&g->z);
			continue;
		}
		if (rc == Z_MEM_ERROR)
			return -ENOMEM;
		if (rc != Z_OK && rc != Z_BUF_ERROR)
			return ssc_diag(diag, -EBADMSG, "%s: corrupt gzip data: %s",
					disp, g->z.msg ? g->z.msg : "inflate failed");
	}
	return (ssize_t)done;
}

void ssc_gz_close(struct ssc_gz *g)
{
	if (!g)
		return;
	inflateEnd(&g->z);
	free(g->in);
	free(g->own);
	if (g->map)
		munmap(g->map, g->map_len);
	free(g);
}
