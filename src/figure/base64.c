/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Base64 (RFC 4648, through nettle): images inlined in an SVG figure or an
 * HTML page.
 */
#include "config.h"

#include <stdlib.h>

#include <nettle/base64.h>

#include "base64.h"

char *ssc_base64(const unsigned char *data, size_t len, size_t *out_len)
{
	struct base64_encode_ctx ctx;
	char *b64 = malloc(BASE64_ENCODE_LENGTH(len) + BASE64_ENCODE_FINAL_LENGTH + 1);
	size_t done;

	if (!b64)
		return NULL;
	base64_encode_init(&ctx);
	done = base64_encode_update(&ctx, b64, len, data);
	done += base64_encode_final(&ctx, b64 + done);
	b64[done] = '\0';
	*out_len = done;
	return b64;
}
