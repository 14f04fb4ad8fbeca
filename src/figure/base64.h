/* SPDX-License-Identifier: GPL-3.0-or-later */
/* Base64 of bytes (base64.c). */
#ifndef SSCOPE_BASE64_H
#define SSCOPE_BASE64_H

#include <stddef.h>

/* Base64 of data (RFC 4648, nettle), malloc'ed and NUL-terminated, its
 * length in *out_len; NULL when out of memory. */
char *ssc_base64(const unsigned char *data, size_t len, size_t *out_len);

#endif
