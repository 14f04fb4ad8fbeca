/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Chunk decompression for the ROS containers, through the reference
 * libraries: bzip2 (libbz2) and LZ4 frames (liblz4, the LZ4 Frame Format
 * 1.6: ROS bag "lz4" chunks and MCAP "lz4" chunks both use it) and
 * Zstandard frames (libzstd, MCAP "zstd" chunks).  The uncompressed size is
 * always known from the container; a frame that decodes to any other size
 * is malformed.
 */
#include "internal.h"

#include <bzlib.h>
#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>
#include <zstd_errors.h>

#include "io-formats.h"

static const char *const codec_name[] = { "bz2", "lz4", "zstd" };

static int lz4_frame(const unsigned char *src, size_t src_len,
		     unsigned char *dst, size_t dst_len, size_t *out)
{
	LZ4F_dctx *ctx;
	size_t in = 0, done = 0, r = 1;

	if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION)))
		return -ENOMEM;
	while (r != 0 && in < src_len) {
		size_t si = src_len - in, so = dst_len - done;

		r = LZ4F_decompress(ctx, dst + done, &so, src + in, &si, NULL);
		if (LZ4F_isError(r))
			break;
		in += si;
		done += so;
		if (si == 0 && so == 0)
			break; /* no progress: output full or input exhausted */
	}
	LZ4F_freeDecompressionContext(ctx);
	*out = done;
	return LZ4F_isError(r) || r != 0 ? -EBADMSG : 0;
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
	size_t got = 0;
	int rc = 0;

	switch (codec) {
	case SSC_CODEC_BZ2: {
		unsigned int n = (unsigned int)dst_len;

		if (dst_len > UINT32_MAX || src_len > UINT32_MAX) {
			rc = -EBADMSG;
			break;
		}
		rc = BZ2_bzBuffToBuffDecompress((char *)dst, &n, (char *)src,
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
		size_t r = ZSTD_decompress(dst, dst_len, src, src_len);

		if (ZSTD_isError(r))
			rc = ZSTD_getErrorCode(r) == ZSTD_error_memory_allocation ?
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
