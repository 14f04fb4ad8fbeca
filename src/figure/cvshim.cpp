// SPDX-License-Identifier: GPL-3.0-or-later
/*
 * OpenCV drawing shim with a C ABI (see cvshim.h): anti-aliased lines and
 * shapes with 4 fractional bits of sub-pixel precision, translucent fills,
 * TrueType text through OpenCV's freetype module when available (Hershey
 * otherwise), viridis images, PNG encoding (libpng, pngenc.c: OpenCV's
 * image codecs pull in some 140 libraries).  No exception crosses the ABI.
 */
#include "config.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#ifdef SSCOPE_HAVE_FREETYPE
#include <opencv2/freetype.hpp>
#endif

#include "cvshim.h"
#include "pngenc.h"

struct ssc_canvas {
	cv::Mat img;
	cv::Rect clip;
	bool clipped = false;
#ifdef SSCOPE_HAVE_FREETYPE
	cv::Ptr<cv::freetype::FreeType2> ft;
	std::string font; /* its file, the key of the width cache */
#endif
};

namespace {

const int SHIFT = 4;
const double ONE = 16.0;

cv::Scalar bgr(uint32_t rgb)
{
	return cv::Scalar(rgb & 0xff, (rgb >> 8) & 0xff, (rgb >> 16) & 0xff);
}

cv::Point fix(double x, double y, const ssc_canvas *c)
{
	if (c->clipped) {
		x -= c->clip.x;
		y -= c->clip.y;
	}
	/* keep far-away points in int range; OpenCV clips the rest */
	x = std::fmax(-1e6, std::fmin(1e6, x));
	y = std::fmax(-1e6, std::fmin(1e6, y));
	return cv::Point((int)std::lround(x * ONE), (int)std::lround(y * ONE));
}

cv::Mat target(ssc_canvas *c)
{
	return c->clipped ? c->img(c->clip) : c->img;
}

int thick(double w)
{
	int t = (int)std::lround(w);
	return t < 1 ? 1 : t;
}

/* Fallback for the Hershey font, which has only ASCII. */
std::string ascii(const char *s)
{
	static const struct {
		const char *u, *a;
	} map[] = {
		{ "\xcf\x84", "tau" },   { "\xcf\x83", "sigma" },
		{ "\xc2\xb0", "deg" },   { "\xe2\x88\x9a", "sqrt" },
		{ "\xc2\xb2", "^2" },    { "\xc2\xb3", "^3" },
		{ "\xc2\xb5", "u" },     { "\xce\xbc", "u" },
		{ "\xc3\x97", "x" },     { "\xe2\x88\x92", "-" },
		{ "\xc2\xb1", "+/-" },   { "\xce\x94", "d" },
		{ "\xcf\x89", "w" },     { "\xe2\x80\x93", "-" },
	};
	std::string out;
	while (*s) {
		bool hit = false;
		for (auto &m : map) {
			size_t n = std::strlen(m.u);
			if (!std::strncmp(s, m.u, n)) {
				out += m.a;
				s += n;
				hit = true;
				break;
			}
		}
		if (hit)
			continue;
		if ((unsigned char)*s < 0x80)
			out += *s;
		else if (((unsigned char)*s & 0xc0) != 0x80)
			out += '?';
		s++;
	}
	return out;
}

const int HFONT = cv::FONT_HERSHEY_SIMPLEX;

double hscale(double px)
{
	return cv::getFontScaleFromHeight(HFONT, (int)std::lround(px * 0.75), 1);
}

#ifdef SSCOPE_HAVE_FREETYPE
/*
 * Widths of the strings measured so far, per font file and pixel size:
 * a figure measures each label several times (its layout is planned on a
 * canvas of its own, then drawn; wrapping and the legend measure again),
 * and FreeType loads and hints every glyph of the string each time (half
 * the drawing time of an allan figure).  The same call gives the same
 * width, so the cache changes no pixel.
 */
std::mutex width_mu;
std::unordered_map<std::string, int> width_memo;

int ft_width(ssc_canvas *c, const char *s, int px)
{
	std::string key = c->font;
	int base = 0, w;

	key += '\0';
	key += std::to_string(px);
	key += '\0';
	key += s;
	{
		std::lock_guard<std::mutex> g(width_mu);
		auto it = width_memo.find(key);
		if (it != width_memo.end())
			return it->second;
	}
	w = c->ft->getTextSize(s, px, -1, &base).width;
	std::lock_guard<std::mutex> g(width_mu);
	if (width_memo.size() >= 65536) /* bounded: labels are few */
		width_memo.clear();
	width_memo.emplace(std::move(key), w);
	return w;
}
#endif

void measure(ssc_canvas *c, const char *s, double px, double *w, double *asc,
	     double *desc)
{
	int base = 0;
#ifdef SSCOPE_HAVE_FREETYPE
	if (c->ft) {
		/* metrics of the font, not of this string, so labels align */
		*w = ft_width(c, s, (int)std::lround(px));
		*asc = 0.78 * px;
		*desc = 0.22 * px;
		return;
	}
#endif
	std::string a = ascii(s);
	cv::Size sz = cv::getTextSize(a, HFONT, hscale(px), 1, &base);
	*w = sz.width;
	*asc = 0.75 * px;
	*desc = 0.25 * px;
}

void draw_text(ssc_canvas *c, cv::Mat &m, double x, double y, const char *s,
	       double px, uint32_t rgb)
{
#ifdef SSCOPE_HAVE_FREETYPE
	if (c->ft) {
		c->ft->putText(m, s, cv::Point((int)std::lround(x),
					       (int)std::lround(y)),
			       (int)std::lround(px), bgr(rgb), -1, cv::LINE_AA,
			       true);
		return;
	}
#endif
	cv::putText(m, ascii(s), cv::Point((int)std::lround(x),
					   (int)std::lround(y)),
		    HFONT, hscale(px), bgr(rgb), 1, cv::LINE_AA);
}

} // namespace

extern "C" {

struct ssc_canvas *ssc_canvas_new(int w, int h, const char *font_path)
{
	try {
		ssc_canvas *c = new ssc_canvas;
		c->img = cv::Mat(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
#ifdef SSCOPE_HAVE_FREETYPE
		if (font_path && *font_path) {
			FILE *f = std::fopen(font_path, "rb");
			if (f) {
				std::fclose(f);
				c->ft = cv::freetype::createFreeType2();
				c->ft->loadFontData(font_path, 0);
				c->font = font_path;
			}
		}
#else
		(void)font_path;
#endif
		return c;
	} catch (...) {
		return nullptr;
	}
}

void ssc_canvas_free(struct ssc_canvas *c)
{
	delete c;
}

void ssc_canvas_clip(struct ssc_canvas *c, int x, int y, int w, int h)
{
	if (w <= 0 || h <= 0) {
		c->clipped = false;
		return;
	}
	c->clip = cv::Rect(x, y, w, h) & cv::Rect(0, 0, c->img.cols, c->img.rows);
	c->clipped = c->clip.area() > 0;
}

void ssc_canvas_polyline(struct ssc_canvas *c, const double *xy, size_t n,
			 uint32_t rgb, double width)
{
	try {
		if (n < 2)
			return;
		std::vector<cv::Point> p(n);
		for (size_t i = 0; i < n; i++)
			p[i] = fix(xy[2 * i], xy[2 * i + 1], c);
		cv::Mat m = target(c);
		cv::polylines(m, p, false, bgr(rgb), thick(width), cv::LINE_AA,
			      SHIFT);
	} catch (...) {
	}
}

void ssc_canvas_fill(struct ssc_canvas *c, const double *xy, size_t n,
		     uint32_t rgb, double alpha)
{
	try {
		if (n < 3)
			return;
		std::vector<cv::Point> p(n);
		for (size_t i = 0; i < n; i++)
			p[i] = fix(xy[2 * i], xy[2 * i + 1], c);
		cv::Mat m = target(c);
		if (alpha >= 1) {
			cv::fillPoly(m, std::vector<std::vector<cv::Point>>{ p },
				     bgr(rgb), cv::LINE_AA, SHIFT);
			return;
		}
		cv::Mat overlay = m.clone();
		cv::fillPoly(overlay, std::vector<std::vector<cv::Point>>{ p },
			     bgr(rgb), cv::LINE_AA, SHIFT);
		cv::addWeighted(overlay, alpha, m, 1 - alpha, 0, m);
	} catch (...) {
	}
}

void ssc_canvas_rect(struct ssc_canvas *c, double x, double y, double w,
		     double h, uint32_t rgb, double width, int filled)
{
	try {
		cv::Mat m = target(c);
		cv::rectangle(m, fix(x, y, c), fix(x + w, y + h, c), bgr(rgb),
			      filled ? cv::FILLED : thick(width), cv::LINE_AA,
			      SHIFT);
	} catch (...) {
	}
}

void ssc_canvas_circle(struct ssc_canvas *c, double x, double y, double r,
		       uint32_t rgb, double width, int filled)
{
	try {
		cv::Mat m = target(c);
		cv::circle(m, fix(x, y, c), (int)std::lround(r * ONE), bgr(rgb),
			   filled ? cv::FILLED : thick(width), cv::LINE_AA, SHIFT);
	} catch (...) {
	}
}

void ssc_canvas_text_size(struct ssc_canvas *c, const char *utf8,
			  double size_px, double *w, double *ascent,
			  double *descent)
{
	try {
		measure(c, utf8, size_px, w, ascent, descent);
	} catch (...) {
		*w = *ascent = *descent = 0;
	}
}

void ssc_canvas_text(struct ssc_canvas *c, double x, double y,
		     const char *utf8, double size_px, uint32_t rgb,
		     int vertical)
{
	try {
		if (!vertical) {
			draw_text(c, c->img, x, y, utf8, size_px, rgb);
			return;
		}
		double w, a, d;
		measure(c, utf8, size_px, &w, &a, &d);
		int tw = (int)std::ceil(w) + 4, th = (int)std::ceil(a + d) + 4;
		cv::Mat tmp(th, tw, CV_8UC3, cv::Scalar(255, 255, 255));
		draw_text(c, tmp, 2, 2 + a, utf8, size_px, rgb);
		cv::Mat rot;
		cv::rotate(tmp, rot, cv::ROTATE_90_COUNTERCLOCKWISE);
		/* after rotation the baseline runs upwards at x = 2 + a */
		int x0 = (int)std::lround(x - (2 + a));
		int y0 = (int)std::lround(y - rot.rows + 2);
		cv::Rect dst(x0, y0, rot.cols, rot.rows);
		cv::Rect in = dst & cv::Rect(0, 0, c->img.cols, c->img.rows);
		if (in.area() <= 0)
			return;
		cv::Mat src = rot(cv::Rect(in.x - x0, in.y - y0, in.width,
					   in.height));
		cv::Mat d2 = c->img(in);
		cv::min(d2, src, d2); /* dark text over a light background */
	} catch (...) {
	}
}

void ssc_canvas_image(struct ssc_canvas *c, int x, int y, int w, int h,
		      const double *v, int iw, int ih)
{
	try {
		if (w <= 0 || h <= 0 || iw <= 0 || ih <= 0)
			return;
		cv::Mat g(ih, iw, CV_8UC1), mask(ih, iw, CV_8UC1);
		for (int r = 0; r < ih; r++)
			for (int k = 0; k < iw; k++) {
				double t = v[(size_t)r * iw + k];
				bool ok = std::isfinite(t);
				t = ok ? std::fmin(1, std::fmax(0, t)) : 0;
				g.at<uint8_t>(ih - 1 - r, k) =
					(uint8_t)std::lround(t * 255);
				mask.at<uint8_t>(ih - 1 - r, k) = ok ? 255 : 0;
			}
		cv::Mat col;
		cv::applyColorMap(g, col, cv::COLORMAP_VIRIDIS);
		col.setTo(cv::Scalar(255, 255, 255), mask == 0);
		cv::Mat big;
		cv::resize(col, big, cv::Size(w, h), 0, 0, cv::INTER_NEAREST);
		cv::Rect dst(x, y, w, h);
		cv::Rect in = dst & cv::Rect(0, 0, c->img.cols, c->img.rows);
		if (in.area() <= 0)
			return;
		big(cv::Rect(in.x - x, in.y - y, in.width, in.height))
			.copyTo(c->img(in));
	} catch (...) {
	}
}

int ssc_canvas_png(struct ssc_canvas *c, unsigned char **buf, size_t *len)
{
	const cv::Mat &m = c->img;

	if (m.type() != CV_8UC3)
		return -1;
	return ssc_png_encode(m.ptr<unsigned char>(0), m.cols, m.rows,
			      m.step[0], 1, buf, len) ? -1 : 0;
}

} // extern "C"
