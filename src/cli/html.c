/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Self-contained HTML report writer (see html.h).  PNGs are embedded as
 * data: URIs with nettle's base64 encoder; provenance hashes are SHA-256
 * (FIPS 180-4) from nettle.  A short script in the page records, after
 * loading, how many images decoded (data-images="ok/total" on <body>) so
 * a headless browser test can check the page without parsing pixels.
 */
#include "config.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <nettle/base64.h>
#include <nettle/sha2.h>

#include "cli.h"
#include "html.h"

struct ssc_html {
	char *buf;
	size_t len, cap;
	bool failed;
};

static void put(struct ssc_html *h, const char *s, size_t n)
{
	if (h->failed)
		return;
	if (h->len + n + 1 > h->cap) {
		size_t nc = h->cap ? h->cap : 65536;
		char *nb;

		while (h->len + n + 1 > nc)
			nc *= 2;
		nb = realloc(h->buf, nc);
		if (!nb) {
			h->failed = true;
			return;
		}
		h->buf = nb;
		h->cap = nc;
	}
	memcpy(h->buf + h->len, s, n);
	h->len += n;
	h->buf[h->len] = '\0';
}

static void puts_(struct ssc_html *h, const char *s)
{
	put(h, s, strlen(s));
}

static void esc(struct ssc_html *h, const char *s)
{
	for (; s && *s; s++) {
		switch (*s) {
		case '<':
			puts_(h, "&lt;");
			break;
		case '>':
			puts_(h, "&gt;");
			break;
		case '&':
			puts_(h, "&amp;");
			break;
		case '"':
			puts_(h, "&quot;");
			break;
		default:
			put(h, s, 1);
		}
	}
}

static const char style[] =
	"body{font-family:'DejaVu Sans',Arial,sans-serif;margin:2em auto;"
	"max-width:1150px;color:#222;line-height:1.45;padding:0 1em}"
	"h1{font-size:1.7em;border-bottom:2px solid #1f77b4;padding-bottom:.2em}"
	"h2{font-size:1.3em;margin-top:2em;border-bottom:1px solid #ccc}"
	"h3{font-size:1.05em}"
	"table{border-collapse:collapse;margin:.8em 0;font-size:.92em}"
	"th,td{border:1px solid #ccc;padding:.3em .6em;text-align:left;"
	"vertical-align:top}"
	"th{background:#eef3f8}"
	"td.num,th.num{text-align:right;font-variant-numeric:tabular-nums}"
	"table.summary td{font-size:1.02em}"
	"tr:nth-child(even) td{background:#fafafa}"
	"img{max-width:100%;border:1px solid #ddd;margin:.5em 0}"
	"pre{background:#f6f6f6;padding:.7em;overflow-x:auto;font-size:.85em}"
	"p.note{color:#555;font-size:.9em}"
	"dt{font-weight:bold;margin-top:.5em}dd{margin-left:1.5em}"
	"footer{margin-top:3em;color:#777;font-size:.85em}";

struct ssc_html *ssc_html_new(const char *title)
{
	struct ssc_html *h = calloc(1, sizeof(*h));

	if (!h)
		return NULL;
	puts_(h, "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n"
		 "<meta charset=\"utf-8\">\n"
		 "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
		 "<title>");
	esc(h, title);
	puts_(h, "</title>\n<style>");
	puts_(h, style);
	puts_(h, "</style>\n</head>\n<body>\n");
	return h;
}

void ssc_html_free(struct ssc_html *h)
{
	if (!h)
		return;
	free(h->buf);
	free(h);
}

static void tag_text(struct ssc_html *h, const char *open, const char *text,
		     const char *close)
{
	puts_(h, open);
	esc(h, text);
	puts_(h, close);
}

void ssc_html_h1(struct ssc_html *h, const char *text)
{
	tag_text(h, "<h1>", text, "</h1>\n");
}

void ssc_html_h2(struct ssc_html *h, const char *id, const char *text)
{
	puts_(h, "<h2");
	if (id) {
		puts_(h, " id=\"");
		esc(h, id);
		puts_(h, "\"");
	}
	puts_(h, ">");
	esc(h, text);
	puts_(h, "</h2>\n");
}

void ssc_html_h3(struct ssc_html *h, const char *text)
{
	tag_text(h, "<h3>", text, "</h3>\n");
}

static void vpara(struct ssc_html *h, const char *open, const char *fmt,
		  va_list ap)
{
	char buf[4096];

	vsnprintf(buf, sizeof(buf), fmt, ap);
	tag_text(h, open, buf, "</p>\n");
}

void ssc_html_p(struct ssc_html *h, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vpara(h, "<p>", fmt, ap);
	va_end(ap);
}

void ssc_html_note(struct ssc_html *h, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vpara(h, "<p class=\"note\">", fmt, ap);
	va_end(ap);
}

void ssc_html_pre(struct ssc_html *h, const char *text)
{
	tag_text(h, "<pre>", text, "</pre>\n");
}

static bool numeric(const char *s)
{
	char *end;

	if (!s || !*s)
		return false;
	strtod(s, &end);
	return end != s && (*end == '\0' || *end == ' ');
}

void ssc_html_table_begin(struct ssc_html *h, const char *cls,
			  const char *const *head, size_t n)
{
	puts_(h, "<table");
	if (cls) {
		puts_(h, " class=\"");
		esc(h, cls);
		puts_(h, "\"");
	}
	puts_(h, ">\n<tr>");
	for (size_t i = 0; i < n; i++)
		tag_text(h, "<th>", head[i], "</th>");
	puts_(h, "</tr>\n");
}

void ssc_html_table_row(struct ssc_html *h, const char *const *cells, size_t n)
{
	puts_(h, "<tr>");
	for (size_t i = 0; i < n; i++)
		tag_text(h, numeric(cells[i]) ? "<td class=\"num\">" : "<td>",
			 cells[i] ? cells[i] : "", "</td>");
	puts_(h, "</tr>\n");
}

void ssc_html_table_end(struct ssc_html *h)
{
	puts_(h, "</table>\n");
}

void ssc_html_def(struct ssc_html *h, const char *term, const char *text)
{
	tag_text(h, "<dl><dt>", term, "</dt>");
	tag_text(h, "<dd>", text, "</dd></dl>\n");
}

void ssc_html_section(struct ssc_html *h, const char *id)
{
	puts_(h, "<section id=\"");
	esc(h, id);
	puts_(h, "\">\n");
}

void ssc_html_section_end(struct ssc_html *h)
{
	puts_(h, "</section>\n");
}

static int read_file(const char *path, unsigned char **data, size_t *len)
{
	FILE *f = fopen(path, "rb");
	long n;

	if (!f)
		return -errno;
	if (fseek(f, 0, SEEK_END) || (n = ftell(f)) < 0 || fseek(f, 0, SEEK_SET)) {
		fclose(f);
		return -EIO;
	}
	*data = malloc((size_t)n + 1);
	if (!*data) {
		fclose(f);
		return -ENOMEM;
	}
	if (fread(*data, 1, (size_t)n, f) != (size_t)n) {
		free(*data);
		fclose(f);
		return -EIO;
	}
	fclose(f);
	*len = (size_t)n;
	return 0;
}

int ssc_html_image(struct ssc_html *h, const char *png_path, const char *alt)
{
	unsigned char *data;
	size_t len;
	char *b64;
	struct base64_encode_ctx ctx;
	size_t done;
	int rc = read_file(png_path, &data, &len);

	if (rc)
		return rc;
	b64 = malloc(BASE64_ENCODE_LENGTH(len) + BASE64_ENCODE_FINAL_LENGTH + 1);
	if (!b64) {
		free(data);
		return -ENOMEM;
	}
	base64_encode_init(&ctx);
	done = base64_encode_update(&ctx, b64, len, data);
	done += base64_encode_final(&ctx, b64 + done);
	puts_(h, "<figure><img alt=\"");
	esc(h, alt);
	puts_(h, "\" src=\"data:image/png;base64,");
	put(h, b64, done);
	puts_(h, "\"><figcaption>");
	esc(h, alt);
	puts_(h, "</figcaption></figure>\n");
	free(b64);
	free(data);
	return 0;
}

int ssc_html_write(struct ssc_html *h, const char *path)
{
	puts_(h, "<script>\n"
		 "window.addEventListener('load', function () {\n"
		 "  var im = document.images, ok = 0;\n"
		 "  for (var i = 0; i < im.length; i++)\n"
		 "    if (im[i].complete && im[i].naturalWidth > 0) ok++;\n"
		 "  document.body.setAttribute('data-images', ok + '/' + im.length);\n"
		 "});\n</script>\n</body>\n</html>\n");
	if (h->failed)
		return -ENOMEM;
	return ssc_file_put(path, h->buf, h->len);
}

int ssc_sha256_file(const char *path, char hex[65])
{
	struct sha256_ctx ctx;
	uint8_t digest[SHA256_DIGEST_SIZE], buf[65536];
	FILE *f = fopen(path, "rb");
	size_t n;

	if (!f)
		return -errno;
	sha256_init(&ctx);
	while ((n = fread(buf, 1, sizeof(buf), f)) > 0)
		sha256_update(&ctx, n, buf);
	if (ferror(f)) {
		fclose(f);
		return -EIO;
	}
	fclose(f);
	sha256_digest(&ctx, sizeof(digest), digest);
	for (size_t i = 0; i < sizeof(digest); i++)
		snprintf(hex + 2 * i, 3, "%02x", digest[i]);
	return 0;
}
