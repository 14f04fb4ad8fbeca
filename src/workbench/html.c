/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Self-contained HTML report writer (see html.h).  SVG figures are inline,
 * PNGs embedded as data: URIs with nettle's base64 encoder; provenance
 * hashes are SHA-256 (FIPS 180-4) from nettle.  A short script in the page
 * records, after loading, how many images decoded (data-images="ok/total")
 * and, for the inline figures as laid out at the window's width, the
 * smallest text in px and the legend or note boxes that overlap a plot
 * area (data-figures="N figures, min text X px, K overlaps") on <body>, so
 * a headless browser test can check the page without parsing pixels.
 */
#include "config.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <nettle/sha2.h>

#include "workbench.h"
#include "base64.h"
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
	"table{border-collapse:collapse;margin:.8em 0;font-size:.92em;"
	"display:block;overflow-x:auto;max-width:100%}"
	"th,td{border:1px solid #ccc;padding:.3em .6em;text-align:left;"
	"vertical-align:top}"
	"th{background:#eef3f8}"
	"td.num,th.num{text-align:right;font-variant-numeric:tabular-nums;"
	"white-space:nowrap}"
	"table.summary td{font-size:1.02em}"
	"tr:nth-child(even) td{background:#fafafa}"
	"img{max-width:100%;border:1px solid #ddd;margin:.5em 0}"
	"figure{margin:1em 0}"
	"figure svg{display:block;max-width:100%;height:auto;border:1px solid #ddd}"
	"figcaption{color:#555;font-size:.88em;margin-top:.3em}"
	"pre{background:#f6f6f6;padding:.7em;overflow-x:auto;font-size:.85em}"
	"p.note{color:#555;font-size:.9em}"
	"dt{font-weight:bold;margin-top:.8em}dd{margin-left:1.5em}"
	"math[display=block]{margin:.5em 0 .5em 1em}"
	"nav.toc{font-size:.92em;margin:.5em 0 1em}nav.toc a{margin-right:1em}"
	".banner{border-left:5px solid #999;background:#f4f4f4;padding:.5em .8em;"
	"margin:.6em 0}"
	".banner.warn{border-color:#d68a00;background:#fff6e0}"
	".banner.ok{border-color:#2ca02c;background:#eef8ee}"
	"td.warn{background:#fff0cc!important;font-weight:bold}"
	"td.ok{color:#1b6e1b}"
	"caption{text-align:left;font-weight:bold;padding:.3em 0}"
	"details{margin:.6em 0}summary{cursor:pointer;color:#1f5f9f}"
	"footer{margin-top:3em;color:#777;font-size:.85em}"
	"@page{size:A4;margin:14mm 12mm}"
	"@media print{body{max-width:none;margin:0;padding:0;font-size:10pt}"
	"nav.toc,details{display:none}h1,h2,h3{break-after:avoid}"
	"table{font-size:8.5pt;display:table}"
	"figure,table,.banner,dl{break-inside:avoid}"
	"figure svg{border:none;max-height:235mm}"
	"a{color:inherit;text-decoration:none}"
	"tr:nth-child(even) td{background:none}th{background:#eee}}";

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

void ssc_html_raw(struct ssc_html *h, const char *markup)
{
	puts_(h, markup);
}

void ssc_html_text(struct ssc_html *h, const char *text)
{
	esc(h, text);
}

void ssc_html_banner(struct ssc_html *h, const char *cls, const char *title,
		     const char *text, const char *href)
{
	puts_(h, "<div class=\"banner ");
	esc(h, cls);
	puts_(h, "\" role=\"note\"><strong>");
	esc(h, title);
	puts_(h, "</strong> ");
	esc(h, text);
	if (href) {
		puts_(h, " <a href=\"");
		esc(h, href);
		puts_(h, "\">(details)</a>");
	}
	puts_(h, "</div>\n");
}

void ssc_html_details(struct ssc_html *h, const char *summary, const char *text)
{
	tag_text(h, "<details><summary>", summary, "</summary>\n");
	tag_text(h, "<pre>", text, "</pre></details>\n");
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

void ssc_html_table_row_cls(struct ssc_html *h, const char *const *cells,
			    const char *const *cls, size_t n)
{
	puts_(h, "<tr>");
	for (size_t i = 0; i < n; i++) {
		const char *c = cls && cls[i] ? cls[i] :
				numeric(cells[i]) ? "num" : NULL;

		puts_(h, "<td");
		if (c && *c) {
			puts_(h, " class=\"");
			esc(h, c);
			puts_(h, "\"");
		}
		puts_(h, ">");
		esc(h, cells[i] ? cells[i] : "");
		puts_(h, "</td>");
	}
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
	size_t len, done = 0;
	char *b64;
	int rc = read_file(png_path, &data, &len);

	if (rc)
		return rc;
	b64 = ssc_base64(data, len, &done);
	if (!b64) {
		free(data);
		return -ENOMEM;
	}
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

int ssc_html_svg(struct ssc_html *h, const char *svg_path, const char *caption,
		 const char *link)
{
	unsigned char *data;
	size_t len;
	int rc = read_file(svg_path, &data, &len);

	if (rc)
		return rc;
	if (len < 5 || memcmp(data, "<svg ", 5)) {
		free(data);
		return -EBADMSG;
	}
	data[len] = '\0';
	puts_(h, "<figure>\n");
	put(h, (const char *)data, len);
	puts_(h, "<figcaption>");
	esc(h, caption);
	if (link) {
		puts_(h, " <a href=\"");
		esc(h, link);
		puts_(h, "\">Open the figure alone</a>.");
	}
	puts_(h, "</figcaption></figure>\n");
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
		 "  var svgs = document.querySelectorAll('figure > svg'), min = 1e9, over = 0;\n"
		 "  svgs.forEach(function (s) {\n"
		 "    var k = s.getBoundingClientRect().width / s.viewBox.baseVal.width;\n"
		 "    s.querySelectorAll('text, tspan').forEach(function (t) {\n"
		 "      var own = Array.prototype.some.call(t.childNodes, function (c) {\n"
		 "        return c.nodeType === 3 && c.nodeValue.trim(); });\n"
		 "      if (own) min = Math.min(min, parseFloat(getComputedStyle(t).fontSize) * k);\n"
		 "    });\n"
		 "    s.querySelectorAll('g.axes').forEach(function (a) {\n"
		 "      var f = a.querySelector('g.plot-area > rect');\n"
		 "      if (!f) return;\n"
		 "      var p = f.getBoundingClientRect();\n"
		 "      a.querySelectorAll('g.legend > rect:first-of-type, g.note > rect:first-of-type').forEach(function (b) {\n"
		 "        var r = b.getBoundingClientRect();\n"
		 "        if (r.left < p.right && p.left < r.right && r.top < p.bottom && p.top < r.bottom) over++;\n"
		 "      });\n"
		 "    });\n"
		 "  });\n"
		 "  document.body.setAttribute('data-figures', svgs.length + ' figures, min text ' +\n"
		 "    (svgs.length ? min.toFixed(1) : 'none') + ' px, ' + over + ' overlaps, ' +\n"
		 "    document.querySelectorAll('table').length + ' tables, ' +\n"
		 "    document.querySelectorAll('math').length + ' formulas, width ' + document.body.clientWidth);\n"
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
