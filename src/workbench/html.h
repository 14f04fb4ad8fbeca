/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * A small writer of self-contained HTML reports: one file with its style
 * sheet (screen and print) inline and its figures embedded (SVG inline,
 * PNG as base64 data), so it can be mailed, archived or printed alone.
 */
#ifndef SSCOPE_HTML_H
#define SSCOPE_HTML_H

#include <stdbool.h>
#include <stddef.h>

struct ssc_html;

struct ssc_html *ssc_html_new(const char *title);
void ssc_html_free(struct ssc_html *h);

/* Text is escaped; "fmt" variants take printf formats. */
void ssc_html_h1(struct ssc_html *h, const char *text);
void ssc_html_h2(struct ssc_html *h, const char *id, const char *text);
void ssc_html_h3(struct ssc_html *h, const char *text);
void ssc_html_p(struct ssc_html *h, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
void ssc_html_note(struct ssc_html *h, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
void ssc_html_pre(struct ssc_html *h, const char *text);
void ssc_html_table_begin(struct ssc_html *h, const char *cls,
			  const char *const *head, size_t n);
void ssc_html_table_row(struct ssc_html *h, const char *const *cells,
			size_t n);
void ssc_html_table_end(struct ssc_html *h);
/* A definition list entry. */
void ssc_html_def(struct ssc_html *h, const char *term, const char *text);
/* Embed a PNG file; returns 0 or -errno (nothing is written on error). */
int ssc_html_image(struct ssc_html *h, const char *png_path, const char *alt);
/* Inline an SVG file (written by sensorscope: no XML declaration, ids
 * unique per figure) as a figure with its caption and, when link is not
 * NULL, a link to the file; 0 or -errno (nothing is written on error). */
int ssc_html_svg(struct ssc_html *h, const char *svg_path, const char *caption,
		 const char *link);
/* Trusted markup (MathML, generated tables) as is. */
void ssc_html_raw(struct ssc_html *h, const char *markup);
/* Escaped text without a tag. */
void ssc_html_text(struct ssc_html *h, const char *text);
/* A banner: cls "warn" or "ok"; title in bold, then the text. */
void ssc_html_banner(struct ssc_html *h, const char *cls, const char *title,
		     const char *text, const char *href);
/* A table row whose cells carry classes (cls[i] NULL: "num" for numbers). */
void ssc_html_table_row_cls(struct ssc_html *h, const char *const *cells,
			    const char *const *cls, size_t n);
/* A collapsed block of preformatted text (hidden in print). */
void ssc_html_details(struct ssc_html *h, const char *summary, const char *text);
/* Open / close a <section>. */
void ssc_html_section(struct ssc_html *h, const char *id);
void ssc_html_section_end(struct ssc_html *h);

/* Write atomically; 0 or -errno (-ENOMEM when building failed). */
int ssc_html_write(struct ssc_html *h, const char *path);

/* Lower-case hex SHA-256 of a file (65 bytes); 0 or -errno. */
int ssc_sha256_file(const char *path, char hex[65]);

#endif
