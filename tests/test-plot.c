/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Plotting layer: tick generation (exact expectations), rendering of a
 * figure that exercises every element (log axes, error bars, bands, dashes,
 * markers, notes, legend, image with colour bar, a million-point series),
 * PNG signature and atomic output; -ENOTSUP without OpenCV.  The same
 * figure as SVG (always built): the document's frame, escaping of hostile
 * text, labelled 1-2-5 ticks on short log axes, font metrics and UTF-8
 * decoding of the layout; the reduction of long lines against its plain
 * definition.  The figures are kept as tests/plot-demo.png and
 * tests/plot-demo.svg for people to look at.
 */
#include "config.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sensorscope.h"
#include "canvas.h"
#include "plot.h"
#include "check-main.h"

START_TEST(linear_ticks)
{
	double t[32], step;
	size_t n = ssc_ticks_linear(0, 1, 6, t, 32, &step);

	ck_assert_uint_eq(n, 6);
	ck_assert(step == 0.2);
	ck_assert(t[0] == 0);
	ck_assert_rel(t[5], 1, 1e-15);
	n = ssc_ticks_linear(-3.7, 12.1, 6, t, 32, &step);
	ck_assert(step == 5);
	ck_assert_uint_eq(n, 3);
	ck_assert(t[0] == 0 && t[1] == 5 && t[2] == 10);
	ck_assert_uint_eq(ssc_ticks_linear(1, 1, 5, t, 32, &step), 0);
	n = ssc_ticks_linear(1e-7, 5e-7, 5, t, 32, &step);
	ck_assert_rel(step, 1e-7, 1e-12);
	ck_assert_uint_eq(n, 5);
	/* the rounded step (0.05) would leave one label: a smaller one */
	n = ssc_ticks_linear(-0.083, -0.017, 3, t, 32, &step);
	ck_assert_rel(step, 0.02, 1e-12);
	ck_assert_uint_eq(n, 4);
	ck_assert_rel(t[0], -0.08, 1e-12);
	ck_assert_rel(t[3], -0.02, 1e-12);
	n = ssc_ticks_linear(0.2811, 0.3189, 3, t, 32, &step);
	ck_assert_uint_ge(n, 3);
}
END_TEST

START_TEST(log_ticks)
{
	double maj[16], mn[128];
	size_t nmin, n = ssc_ticks_log(1e-3, 1e2, maj, 16, mn, 128, &nmin);

	ck_assert_uint_eq(n, 6);
	ck_assert_rel(maj[0], 1e-3, 1e-12);
	ck_assert_rel(maj[5], 1e2, 1e-12);
	ck_assert_uint_eq(nmin, 5 * 8);
	n = ssc_ticks_log(2, 8, maj, 16, mn, 128, &nmin);
	ck_assert_uint_eq(n, 0);
	ck_assert_uint_eq(nmin, 7);
	ck_assert_uint_eq(ssc_ticks_log(-1, 10, maj, 16, mn, 128, &nmin), 0);
}
END_TEST

START_TEST(render_demo)
{
	struct ssc_fig *fig = ssc_fig_new(1200, 900, 2, 2);
	struct ssc_ax *a = ssc_fig_ax(fig, 0, 0), *b = ssc_fig_ax(fig, 0, 1),
		      *c = ssc_fig_ax(fig, 1, 0), *d = ssc_fig_ax(fig, 1, 1);
	double tau[40], dev[40], lo[40], hi[40], fit[40], wn[40];
	size_t n = 40, big = 1000000;
	double *x = malloc(big * sizeof(double)), *y = malloc(big * sizeof(double));
	double z[64 * 48];
	char path[256];
	FILE *f;
	unsigned char sig[8];
	int rc;

	ck_assert_ptr_nonnull(fig);
	ck_assert_ptr_null(ssc_fig_ax(fig, 2, 0));
	ssc_fig_title(fig, "sensorscope plot test: \xcf\x83(\xcf\x84), 10^{-3} \xc2\xb0/h");
	for (size_t i = 0; i < n; i++) {
		tau[i] = 0.01 * pow(10, (double)i / 8);
		wn[i] = 0.2 / sqrt(tau[i]);
		fit[i] = sqrt(wn[i] * wn[i] + 0.0016 + 1e-4 * tau[i]);
		dev[i] = fit[i] * (1 + 0.05 * sin((double)i));
		lo[i] = dev[i] * (1 - 0.3 * tau[i] / 10);
		hi[i] = dev[i] * (1 + 0.4 * tau[i] / 10);
	}
	ssc_ax_log(a, true, true);
	ssc_ax_title(a, "Allan deviation");
	ssc_ax_xlabel(a, "\xcf\x84 (s)");
	ssc_ax_ylabel(a, "\xcf\x83(\xcf\x84) (\xc2\xb0/h)");
	ssc_ax_band(a, tau, lo, hi, n, 0x1f77b4, 0.2, "68 % interval");
	ssc_ax_errorbar(a, tau, dev, lo, hi, n,
			&(struct ssc_style){ .marker = SSC_MK_CIRCLE, .width = -1 },
			"OADEV");
	ssc_ax_line(a, tau, fit, n, &(struct ssc_style){ .color = 0xd62728 },
		    "fit");
	ssc_ax_line(a, tau, wn, n,
		    &(struct ssc_style){ .dash = SSC_DASHED, .width = 1.5 },
		    "N = 0.2 \xc2\xb0/\xe2\x88\x9ah");
	ssc_ax_note(a, "N = 0.200 \xc2\xb0/\xe2\x88\x9ah [0.19, 0.21]\nB = 0.040 \xc2\xb0/h",
		    SSC_LEGEND_LL);
	for (size_t i = 0; i < big; i++) {
		x[i] = (double)i / 1000;
		y[i] = sin(x[i] * 0.01) * 1e6 + ((i * 2654435761u) % 1000) * 100.0;
	}
	ssc_ax_line(b, x, y, big, &(struct ssc_style){ .width = 1 }, "1e6 points");
	ssc_ax_xlabel(b, "time (s)");
	ssc_ax_ylabel(b, "a (m/s^{2})");
	ssc_ax_hline(b, 0, &(struct ssc_style){ .color = 0x000000, .dash = SSC_DOTTED }, NULL);
	ssc_ax_vline(b, 500, &(struct ssc_style){ .color = 0x2ca02c, .dash = SSC_DASHDOT }, "event");
	for (int m = SSC_MK_CIRCLE; m <= SSC_MK_CROSS; m++) {
		double px[5], py[5];

		for (int i = 0; i < 5; i++) {
			px[i] = i;
			py[i] = m + 0.1 * i;
		}
		ssc_ax_line(c, px, py, 5, &(struct ssc_style){ .marker = (enum ssc_marker)m },
			    NULL);
	}
	ssc_ax_text(c, 2, 3.5, "text at (2, 3.5)", 0, 0);
	ssc_ax_title(c, "markers");
	for (int iy = 0; iy < 48; iy++)
		for (int ix = 0; ix < 64; ix++)
			z[iy * 64 + ix] = pow(10, -6 + 4.0 * ix / 64) * (1 + iy % 5);
	rc = ssc_ax_image(d, z, 64, 48, 0, 10, 0, 500, 1e-6, 1e-1, true,
			  "PSD (g^{2}/Hz)");
	ck_assert_int_eq(rc, 0);
	ck_assert_int_eq(ssc_ax_image(d, z, 64, 48, 0, 10, 0, 500, 1, 1, true, NULL),
			 -EINVAL);
	ssc_ax_xlabel(d, "time (s)");
	ssc_ax_ylabel(d, "frequency (Hz)");
	ssc_ax_title(d, "spectrogram");

#ifdef HAVE_OPENCV
	/* the drawing module, which the command finds next to itself */
	if (!getenv("SSCOPE_PLOT_MODULE") && getenv("top_builddir")) {
		snprintf(path, sizeof(path), "%s/src/cli/.libs/plot-opencv.so",
			 getenv("top_builddir"));
		setenv("SSCOPE_PLOT_MODULE", path, 1);
	}
#endif
	snprintf(path, sizeof(path), "%s/tests/plot-demo.png",
		 getenv("top_builddir") ? getenv("top_builddir") : ".");
	rc = ssc_fig_save_png(fig, path);
#ifdef HAVE_OPENCV
	ck_assert_int_eq(rc, 0);
	f = fopen(path, "rb");
	ck_assert_ptr_nonnull(f);
	ck_assert_uint_eq(fread(sig, 1, 8, f), 8);
	fclose(f);
	ck_assert(memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0);
	ck_assert_int_eq(ssc_fig_save_png(fig, "/nonexistent/dir/x.png"), -ENOENT);
#else
	ck_assert_int_eq(rc, -ENOTSUP);
	(void)f;
	(void)sig;
#endif
	snprintf(path, sizeof(path), "%s/tests/plot-demo.svg",
		 getenv("top_builddir") ? getenv("top_builddir") : ".");
	ck_assert_int_eq(ssc_fig_save(fig, path), 0);
	f = fopen(path, "rb");
	ck_assert_ptr_nonnull(f);
	{
		char head[64] = "";

		ck_assert_uint_gt(fread(head, 1, sizeof(head) - 1, f), 40);
		ck_assert(strncmp(head, "<svg xmlns=\"http://www.w3.org/2000/svg\" ",
				  40) == 0);
	}
	fclose(f);
	ck_assert_int_eq(ssc_fig_save(fig, "/nonexistent/dir/x.svg"), -ENOENT);
	ck_assert_int_eq(ssc_fig_save(fig, "x.jpg"), -EINVAL);
	ssc_fig_free(fig);
	free(x);
	free(y);
}
END_TEST

/* not inlined: GCC 12 then takes the returned text for a pointer to the
 * local that received it (-Wdangling-pointer) */
__attribute__((noinline)) static char *svg_of(struct ssc_fig *fig)
{
	char *buf = NULL;
	size_t len = 0;

	ck_assert_int_eq(ssc_fig_svg(fig, "t", &buf, &len), 0);
	ck_assert_uint_eq(strlen(buf), len);
	ck_assert(strncmp(buf, "<svg ", 5) == 0);
	ck_assert(strcmp(buf + len - 7, "</svg>\n") == 0);
	return buf;
}

START_TEST(svg_text)
{
	struct ssc_fig *fig = ssc_fig_new(800, 500, 1, 1);
	struct ssc_ax *ax = ssc_fig_ax(fig, 0, 0);
	double x[3] = { 1, 2, 3 }, y[3] = { 1.5, 7.25, 29 };
	char *svg, *p;

	/* an empty figure has nothing to draw */
	ck_assert_int_eq(ssc_fig_svg(fig, NULL, &svg, &(size_t){ 0 }), -EINVAL);
	/* markup, XML specials, a control byte and invalid UTF-8 */
	ssc_fig_title(fig, "a<b & \"c\" \x01 \xff\xfe end");
	ssc_ax_xlabel(ax, "\xcf\x84 (s)");
	ssc_ax_ylabel(ax, "a (m/s^{2})");
	ssc_ax_log(ax, false, true);
	ck_assert_int_eq(ssc_ax_line(ax, x, y, 3, NULL, "line"), 0);
	ck_assert_int_eq(ssc_ax_note(ax, "N = 0.15 \xc2\xb0/\xe2\x88\x9ah", SSC_LEGEND_LL), 0);
	svg = svg_of(fig);
	ck_assert_ptr_nonnull(strstr(svg, "a&lt;b &amp; &quot;c&quot; \xef\xbf\xbd \xef\xbf\xbd\xef\xbf\xbd end"));
	ck_assert_ptr_null(strchr(svg, '\x01'));
	ck_assert_ptr_null(strstr(svg, "\xff"));
	/* the superscript is a raised, smaller tspan */
	ck_assert_ptr_nonnull(strstr(svg, "a (m/s<tspan dy=\"-"));
	/* one to 30 on a log axis: 2, 5, 10 and 20 are labelled too */
	ck_assert_ptr_nonnull(strstr(svg, ">2</text>"));
	ck_assert_ptr_nonnull(strstr(svg, ">5</text>"));
	ck_assert_ptr_nonnull(strstr(svg, ">20</text>"));
	/* the legend and the note sit right of the plot area */
	p = strstr(svg, "class=\"legend\"");
	ck_assert_ptr_nonnull(p);
	ck_assert_ptr_nonnull(strstr(p, "class=\"note\""));
	ck_assert_ptr_nonnull(strstr(svg, "class=\"plot-area\""));
	ck_assert_ptr_nonnull(strstr(svg, "clip-path=\"url(#t-clip1)\""));
	free(svg);
	ssc_fig_free(fig);
}
END_TEST

START_TEST(svg_helpers)
{
	const char *s = "A\xcf\x84\xe2\x88\x9a\xc0\xaf\xed\xa0\x80z", *e;

	ck_assert_int_eq(ssc_plot_format_of("a.SVG"), SSC_PLOT_SVG);
	ck_assert_int_eq(ssc_plot_format_of("b.png"), SSC_PLOT_PNG);
	ck_assert_int_eq(ssc_plot_format_of("c.pdf"), SSC_PLOT_NONE);
	ck_assert_int_eq(ssc_plot_format_of(".svg"), SSC_PLOT_NONE);
	/* DejaVu Sans: 'A' is 1401/2048 em, tau 1233, an unknown 0.6 em */
	ck_assert(fabs(ssc_font_advance_em('A') - 1401 / 2048.0) < 1e-12);
	ck_assert(fabs(ssc_font_advance_em(0x3c4) - 1233 / 2048.0) < 1e-12);
	ck_assert(fabs(ssc_font_advance_em(0x10000) - 0.6) < 1e-12);
	/* UTF-8: overlong and surrogate forms are replaced byte by byte */
	e = s + strlen(s);
	ck_assert_uint_eq(ssc_utf8_next(&s, e), 'A');
	ck_assert_uint_eq(ssc_utf8_next(&s, e), 0x3c4);
	ck_assert_uint_eq(ssc_utf8_next(&s, e), 0x221a);
	ck_assert_uint_eq(ssc_utf8_next(&s, e), 0xfffd);
	ck_assert_uint_eq(ssc_utf8_next(&s, e), 0xfffd);
	ck_assert_uint_eq(ssc_utf8_next(&s, e), 0xfffd);
	ck_assert_uint_eq(ssc_utf8_next(&s, e), 0xfffd);
	ck_assert_uint_eq(ssc_utf8_next(&s, e), 0xfffd);
	ck_assert_uint_eq(ssc_utf8_next(&s, e), 'z');
	ck_assert(s == e);
	/* viridis ends */
	ck_assert_uint_eq(ssc_viridis(0), 0x440154);
	ck_assert_uint_eq(ssc_viridis(1), 0xfde725);
	ck_assert_uint_eq(ssc_viridis(NAN), 0x440154);
}
END_TEST

/* The reduction of a long line against the plain definition, written out
 * here: 4096 buckets keep their first point, the first of their smallest
 * and largest shown value, their first non-finite point and their last,
 * in order; the reduced series drawn as a short line (kept whole) must
 * give the same SVG.  Ties (quantized values), NaN and inf in x and y,
 * a unit conversion, the time column checked once, and the buckets taken
 * from the envelopes of the statistics' pass (neighbouring doubles shown
 * as one value, an offset that swamps the samples). */
#define RB 4096
static size_t plain_reduce(const double *x, const double *y, size_t n,
			   double off, double sc, double *rx, double *ry)
{
	size_t m = 0;

	for (size_t b = 0; b < RB; b++) {
		size_t i0 = n * b / RB, i1 = n * (b + 1) / RB, keep[5], nk = 0;
		size_t imin = SIZE_MAX, imax = SIZE_MAX, ibad = SIZE_MAX;

		if (i0 >= i1)
			continue;
		for (size_t i = i0; i < i1; i++) {
			double v = (y[i] - off) / sc;

			if (!isfinite(x[i]) || !isfinite(v)) {
				if (ibad == SIZE_MAX)
					ibad = i;
			} else {
				if (imin == SIZE_MAX || v < (y[imin] - off) / sc)
					imin = i;
				if (imax == SIZE_MAX || v > (y[imax] - off) / sc)
					imax = i;
			}
		}
		keep[nk++] = i0;
		if (imin != SIZE_MAX)
			keep[nk++] = imin;
		if (imax != SIZE_MAX)
			keep[nk++] = imax;
		if (ibad != SIZE_MAX)
			keep[nk++] = ibad;
		keep[nk++] = i1 - 1;
		for (size_t a = 1; a < nk; a++)
			for (size_t c = a; c > 0 && keep[c - 1] > keep[c]; c--) {
				size_t t = keep[c];

				keep[c] = keep[c - 1];
				keep[c - 1] = t;
			}
		for (size_t a = 0; a < nk; a++)
			if (!a || keep[a] != keep[a - 1]) {
				rx[m] = x[keep[a]];
				ry[m] = (y[keep[a]] - off) / sc;
				m++;
			}
	}
	return m;
}

static char *line_svg(const double *x, const bool *xf, const double *y,
		      size_t n, double off, double sc, int how)
{
	struct ssc_fig *fig = ssc_fig_new(600, 300, 1, 1);
	struct ssc_style st = { .color = 0x1f77b4, .width = 1 };
	char *buf = NULL;
	size_t len;

	ck_assert_ptr_nonnull(fig);
	if (how == 0) {
		ck_assert_int_eq(ssc_ax_line_scaled(ssc_fig_ax(fig, 0, 0), x, y, n,
						    off, sc, &st, NULL), 0);
	} else if (how == 1) {
		ck_assert_int_eq(ssc_ax_line_scaled_x(ssc_fig_ax(fig, 0, 0), x, xf,
						      y, n, off, sc, &st, NULL), 0);
	} else {
		/* from the envelopes of the statistics' pass */
		struct sscope_clip_envelope *e =
			malloc(SSC_PLOT_LINE_BINS * sizeof(*e));
		struct sscope_stats ss;

		ck_assert_ptr_nonnull(e);
		ck_assert_int_ge(sscope_clip_detect_stats_envelope(
					 y, 1, n, 0, 0, &ss, NULL,
					 SSC_PLOT_LINE_BINS, e), -ERANGE);
		ck_assert_int_eq(ssc_ax_line_envelope_x(ssc_fig_ax(fig, 0, 0), x,
							xf, y, n, off, sc, e,
							&st, NULL), 0);
		free(e);
	}
	ck_assert_int_eq(ssc_fig_svg(fig, "r", &buf, &len), 0);
	ssc_fig_free(fig);
	return buf;
}

START_TEST(long_line_reduction)
{
	const size_t n = 40 * RB + 123;
	double *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));
	double *rx = malloc(5 * RB * sizeof(double)), *ry = malloc(5 * RB * sizeof(double));
	unsigned long long s = 88172645463325252ULL;

	ck_assert(x && y && rx && ry);
	ck_assert_int_eq(RB, SSC_PLOT_LINE_BINS);
	for (int t = 0; t < 7; t++) {
		double off = t % 2 ? 273.15 : 0, sc = t % 2 ? 0.017453292519943295 : 1;
		bool *xf;
		char *a, *b, *c, *d;
		size_t m;

		if (t == 4) { /* neighbouring doubles shown the same */
			off = 0;
			sc = 0.017453292519943295;
		} else if (t >= 5) { /* many of them: an offset swamps y */
			off = t == 5 ? 1e6 : -2.5e3;
			sc = t == 5 ? 3 : 0.5;
		}
		for (size_t i = 0; i < n; i++) {
			s ^= s << 13;
			s ^= s >> 7;
			s ^= s << 17;
			x[i] = 0.01 * (double)i;
			/* few distinct values: many ties at the extremes */
			y[i] = (double)(s % (t < 2 ? 7 : 100003)) * 0.125 - 0.3;
			if (t == 4) /* neighbouring doubles */
				y[i] = 1.5 + (double)(s % 64) * 0x1p-52;
			else if (t >= 5) /* every bit of the mantissa */
				y[i] = (double)(s >> 11) * 0x1p-53 *
				       (t == 5 ? 1e-9 : 1e-10);
		}
		if (t == 2 || t == 3 || t == 6)
			for (size_t i = 17; i < n; i += 7919) {
				y[i] = i % 3 ? (double)NAN : (double)INFINITY;
				x[i + 3] = i % 2 ? (double)NAN : -(double)INFINITY;
			}
		m = plain_reduce(x, y, n, off, sc, rx, ry);
		ck_assert_uint_lt(m, 8 * RB); /* drawn whole */
		xf = ssc_line_x_finite(x, n);
		ck_assert_ptr_nonnull(xf);
		a = line_svg(rx, NULL, ry, m, 0, 1, 0);
		b = line_svg(x, NULL, y, n, off, sc, 0);
		c = line_svg(x, xf, y, n, off, sc, 1);
		d = line_svg(x, xf, y, n, off, sc, 2);
		ck_assert_msg(strcmp(a, b) == 0, "t %d: reduced line differs", t);
		ck_assert_msg(strcmp(a, c) == 0, "t %d: with x checked once", t);
		ck_assert_msg(strcmp(a, d) == 0, "t %d: from the envelopes", t);
		free(a);
		free(b);
		free(c);
		free(d);
		free(xf);
	}
	ck_assert_ptr_null(ssc_line_x_finite(x, 8 * RB));
	free(x);
	free(y);
	free(rx);
	free(ry);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("plot");
	TCase *tc = tcase_create("plot");

	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, linear_ticks);
	tcase_add_test(tc, log_ticks);
	tcase_add_test(tc, render_demo);
	tcase_add_test(tc, svg_text);
	tcase_add_test(tc, svg_helpers);
	tcase_add_test(tc, long_line_reduction);
	suite_add_tcase(s, tc);
	return s;
}
