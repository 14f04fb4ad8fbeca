/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Chunk decompression for the ROS containers, through the reference
 * libraries: bzip2 (libbz2) and LZ4 frames (liblz4, the LZ4 Frame Format
 * 1.6: ROS bag "lz4" chunks and MCAP "lz4" chunks both use it) and
 * Zstandard frames (libzstd, MCAP "zstd" chunks).  The uncompressed size is
 * always known from the container; a frame that decodes to any other size
 * is malformed.
 *
 * Whole files compressed with Zstandard (rosbag2's compression_mode FILE)
 * have no size outside the stream: they are expanded in steps, never past
 * what the codec can make of the input (RFC 8878: at most a 128 KiB
 * block from 4 bytes), past a cap of half the memory the process may use,
 * or past the size the expanded bytes declare themselves; what they must
 * be is checked on the first MiB, so a bomb stops there.
 */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <bzlib.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>
#include <zstd_errors.h>

#include "io-formats.h"

static const char *const codec_name[] = { "bz2", "lz4", "zstd" };

/* the codecs' libraries, opened on the first chunk that needs them */
#define BZ2_FUNCS(X) X(BZ2_bzBuffToBuffDecompress)
#define LZ4_FUNCS(X)                                                           \
	X(LZ4F_isError) X(LZ4F_createDecompressionContext) X(LZ4F_decompress)  \
	X(LZ4F_freeDecompressionContext)
#define ZSTD_FUNCS(X)                                                          \
	X(ZSTD_isError) X(ZSTD_getErrorCode) X(ZSTD_getErrorName)              \
	X(ZSTD_decompress) X(ZSTD_getFrameContentSize) X(ZSTD_createDCtx)      \
	X(ZSTD_freeDCtx) X(ZSTD_decompressStream)
SSC_LAZY_TABLE(bz, BZ2_FUNCS);
SSC_LAZY_TABLE(lz, LZ4_FUNCS);
SSC_LAZY_TABLE(zs, ZSTD_FUNCS);
SSC_LAZY_LIB(bz2_lib, "libbz2.so.1.0", "libbz2-1.0", bz, BZ2_FUNCS);
SSC_LAZY_LIB(lz4_lib, "liblz4.so.1", "liblz4-1", lz, LZ4_FUNCS);
SSC_LAZY_LIB(zstd_lib, "libzstd.so.1", "libzstd1", zs, ZSTD_FUNCS);

static int lz4_frame(const unsigned char *src, size_t src_len,
		     unsigned char *dst, size_t dst_len, size_t *out)
{
	LZ4F_dctx *ctx;
	size_t in = 0, done = 0, r = 1;

	if (lz.LZ4F_isError(lz.LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION)))
		return -ENOMEM;
	while (r != 0 && in < src_len) {
		size_t si = src_len - in, so = dst_len - done;

		r = lz.LZ4F_decompress(ctx, dst + done, &so, src + in, &si, NULL);
		if (lz.LZ4F_isError(r))
			break;
		in += si;
		done += so;
		if (si == 0 && so == 0)
			break; /* no progress: output full or input exhausted */
	}
	lz.LZ4F_freeDecompressionContext(ctx);
	*out = done;
	return lz.LZ4F_isError(r) || r != 0 ? -EBADMSG : 0;
}

size_t ssc_decompress_bound(enum ssc_codec codec, size_t src_len)
{
	/* LZ4: a match token adds at most 255 bytes per input byte (the
	 * format's maximal ratio); Zstandard: an RLE block of 128 KiB takes a
	 * 3-byte header and one byte (RFC 8878, 3.1.1.2) */
	size_t per = codec == SSC_CODEC_LZ4 ? 255 :
		     codec == SSC_CODEC_ZSTD ? (size_t)128 * 1024 / 4 : 0;

	if (per == 0 || src_len > (SIZE_MAX - 131072) / per)
		return SIZE_MAX;
	return src_len * per + 131072;
}

int ssc_decompress(enum ssc_codec codec, const unsigned char *src,
		   size_t src_len, unsigned char *dst, size_t dst_len,
		   const char *disp, const char *what,
		   struct sscope_diag *diag)
{
	static struct ssc_lazylib *const lib[] = { &bz2_lib, &lz4_lib, &zstd_lib };
	size_t got = 0;
	int rc = ssc_lazylib_load(lib[codec], diag, disp);

	if (rc)
		return rc;
	switch (codec) {
	case SSC_CODEC_BZ2: {
		unsigned int n = (unsigned int)dst_len;

		if (dst_len > UINT32_MAX || src_len > UINT32_MAX) {
			rc = -EBADMSG;
			break;
		}
		rc = bz.BZ2_bzBuffToBuffDecompress((char *)dst, &n, (char *)src,
						(unsigned int)src_len, 0, 0);
		if (rc == BZ_MEM_ERROR)
			return -ENOMEM;
		got = rc == BZ_OK ? n : 0;
		rc = rc == BZ_OK ? 0 : -EBADMSG;
		break;
	}
	case SSC_CODEC_LZ4:
		rc = lz4_frame(src, src_len, dst, dst_len, &got);
		break;
	case SSC_CODEC_ZSTD: {
		size_t r = zs.ZSTD_decompress(dst, dst_len, src, src_len);

		if (zs.ZSTD_isError(r))
			rc = zs.ZSTD_getErrorCode(r) == ZSTD_error_memory_allocation ?
				     -ENOMEM : -EBADMSG;
		else
			got = r;
		break;
	}
	}
	if (rc == -ENOMEM)
		return rc;
	if (rc || got != dst_len)
		return ssc_diag(diag, -EBADMSG,
				"%s: %s: corrupt %s data (%zu bytes decoded, %zu expected)",
				disp, what, codec_name[codec], got, dst_len);
	return 0;
}

int ssc_chunk_batch_run(struct ssc_chunk_batch *b, const char *kind,
			const char *disp, struct sscope_diag *diag)
{
	int rc[SSC_CHUNK_BATCH];
	struct sscope_diag d[SSC_CHUNK_BATCH];
	long n = (long)b->n;

	for (size_t i = 0; i < b->n; i++) {
		size_t need = b->job[i].size ? b->job[i].size : 1;

		if (need > b->cap[i]) {
			unsigned char *s = realloc(b->buf[i], need);

			if (!s)
				return ssc_diag(diag, -ENOMEM,
						"%s: out of memory for a chunk of %zu bytes at byte %llu",
						disp, b->job[i].size,
						(unsigned long long)b->job[i].at);
			b->buf[i] = s;
			b->cap[i] = need;
		}
	}
	/* one chunk to a thread at a time: a thread that loses its core
	 * holds back one chunk */
SSC_OMP(omp parallel for schedule(dynamic, 1) if (n > 1))
	for (long i = 0; i < n; i++) {
		const struct ssc_chunk_job *j = &b->job[i];
		char what[80];

		d[i].msg[0] = '\0';
		snprintf(what, sizeof(what), "%s chunk at byte %llu", kind,
			 (unsigned long long)j->at);
		rc[i] = ssc_decompress(j->codec, j->src, j->src_len, b->buf[i],
				       j->size, disp, what, &d[i]);
	}
	for (size_t i = 0; i < b->n; i++)
		if (rc[i]) {
			if (diag)
				*diag = d[i];
			b->n = i; /* the good chunks before it */
			return rc[i];
		}
	return 0;
}

void ssc_chunk_batch_free(struct ssc_chunk_batch *b)
{
	for (size_t i = 0; i < SSC_CHUNK_BATCH; i++)
		free(b->buf[i]);
	memset(b, 0, sizeof(*b));
}

void ssc_map_drop_behind(const unsigned char *base, size_t upto,
			 size_t *dropped)
{
	long pg = sysconf(_SC_PAGESIZE);
	size_t p = pg > 0 ? (size_t)pg : 4096, to = upto / p * p;

	if (to < *dropped + ((size_t)4 << 20))
		return;
	madvise((void *)(uintptr_t)(base + *dropped), to - *dropped,
		MADV_DONTNEED);
	*dropped = to;
}

uint32_t ssc_crc32(const unsigned char *p, size_t n)
{
	uLong c = crc32(0L, Z_NULL, 0);

	while (n) {
		uInt k = n > (1u << 30) ? 1u << 30 : (uInt)n;

		c = crc32(c, p, k);
		p += k;
		n -= k;
	}
	return (uint32_t)c;
}

size_t ssc_expand_cap(void)
{
	long pages = sysconf(_SC_PHYS_PAGES), psz = sysconf(_SC_PAGESIZE);
	size_t cap = SIZE_MAX / 2;
	struct rlimit rl;

	if (pages > 0 && psz > 0 &&
	    (unsigned long long)pages * (unsigned long long)psz / 2 < cap)
		cap = (size_t)((unsigned long long)pages *
			       (unsigned long long)psz / 2);
	if (!getrlimit(RLIMIT_AS, &rl) && rl.rlim_cur != RLIM_INFINITY &&
	    rl.rlim_cur / 2 < cap)
		cap = (size_t)(rl.rlim_cur / 2);
	if (!getrlimit(RLIMIT_DATA, &rl) && rl.rlim_cur != RLIM_INFINITY &&
	    rl.rlim_cur / 2 < cap)
		cap = (size_t)(rl.rlim_cur / 2);
	return cap;
}

static double mib(size_t n)
{
	return (double)n / (1024.0 * 1024.0);
}

#define HEAD (1u << 20)

int ssc_unzstd(const unsigned char *src, size_t n, size_t cap,
	       ssc_expand_check_fn check, void *ctx, unsigned char **out,
	       size_t *out_len, const char *disp, struct sscope_diag *diag)
{
	ZSTD_DCtx *z;
	ZSTD_inBuffer in = { src, n, 0 };
	unsigned char *b = NULL;
	size_t bcap = 0, len = 0, limit, r = 1;
	unsigned long long fcs;
	bool checked = false, ratio_bound, declared = false;
	int rc;

	*out = NULL;
	*out_len = 0;
	rc = ssc_lazylib_load(&zstd_lib, diag, disp);
	if (rc)
		return rc;
	fcs = zs.ZSTD_getFrameContentSize(src, n);
	limit = ssc_decompress_bound(SSC_CODEC_ZSTD, n);
	ratio_bound = limit <= cap;
	if (!ratio_bound)
		limit = cap;
	if (fcs != ZSTD_CONTENTSIZE_UNKNOWN && fcs != ZSTD_CONTENTSIZE_ERROR &&
	    fcs > limit)
		return ssc_diag(diag, ratio_bound ? -EBADMSG : -ENOMEM,
				ratio_bound ?
				"%s: corrupt zstd data (a frame of %.0f MiB from %.3g MiB of input)" :
				"%s: zstd data of %.0f MiB: more than the %.0f MiB a decompressed file may take here (half the memory this process may use): convert the bag with `ros2 bag convert` to uncompressed storage",
				disp, mib((size_t)(fcs > SIZE_MAX ? SIZE_MAX : fcs)),
				ratio_bound ? mib(n) : mib(cap));
	z = zs.ZSTD_createDCtx();
	if (!z)
		return ssc_diag(diag, -ENOMEM, "%s: out of memory", disp);
	for (;;) {
		ZSTD_outBuffer o;

		if (bcap - len < HEAD && bcap < limit + 1) {
			/* the first frame's declared size, else doubling */
			size_t want = fcs != ZSTD_CONTENTSIZE_UNKNOWN &&
					      fcs != ZSTD_CONTENTSIZE_ERROR && !bcap ?
					      (size_t)fcs + 1 :
					      bcap ? 2 * bcap : 4 * n + HEAD;
			unsigned char *nb;

			if (want < len + HEAD)
				want = len + HEAD;
			if (want > limit + 1 || want < bcap)
				want = limit + 1;
			nb = realloc(b, want);
			if (!nb) {
				rc = ssc_diag(diag, -ENOMEM,
					      "%s: out of memory expanding the zstd data (%.0f MiB so far): free memory, or convert the bag with `ros2 bag convert` to uncompressed storage",
					      disp, mib(len));
				break;
			}
			b = nb;
			bcap = want;
		}
		o = (ZSTD_outBuffer){ b + len, bcap - len, 0 };
		r = zs.ZSTD_decompressStream(z, &o, &in);
		if (zs.ZSTD_isError(r)) {
			rc = zs.ZSTD_getErrorCode(r) == ZSTD_error_memory_allocation ?
				ssc_diag(diag, -ENOMEM, "%s: out of memory expanding the zstd data",
					 disp) :
				ssc_diag(diag, -EBADMSG, "%s: corrupt zstd data (%s)",
					 disp, zs.ZSTD_getErrorName(r));
			break;
		}
		len += o.pos;
		if (!checked && (len >= HEAD || (r == 0 && in.pos == in.size))) {
			size_t l = limit;

			checked = true;
			rc = check ? check(b, len, &l, ctx, disp, diag) : 0;
			if (rc)
				break;
			if (l < limit) {
				limit = l;
				declared = true;
			}
		}
		if (len > limit) {
			rc = declared ?
				ssc_diag(diag, -EBADMSG,
					 "%s: corrupt zstd data (they go on past the %zu bytes the file declares)",
					 disp, limit) :
			     ratio_bound ?
				ssc_diag(diag, -EBADMSG,
					 "%s: corrupt zstd data (more than %.0f MiB from %.3g MiB of input)",
					 disp, mib(limit), mib(n)) :
				ssc_diag(diag, -ENOMEM,
					 "%s: zstd data expand to more than the %.0f MiB a decompressed file may take here (half the memory this process may use): convert the bag with `ros2 bag convert` to uncompressed storage",
					 disp, mib(cap));
			break;
		}
		if (r == 0 && in.pos == in.size)
			break;
		if (in.pos == in.size && o.pos < o.size) {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: zstd data truncated (the file ends inside a frame)",
				      disp);
			break;
		}
	}
	zs.ZSTD_freeDCtx(z);
	if (rc) {
		free(b);
		return rc;
	}
	*out = b;
	*out_len = len;
	return 0;
}
