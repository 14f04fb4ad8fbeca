/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The drawing shim (cvshim.cpp, OpenCV and the libpng encoder) is a module,
 * plot-opencv.so, opened with dlopen() on the first figure.  Linked into the
 * command, OpenCV's libraries and the C++ runtime cost 5-8 ms at every start
 * (relocations and static constructors), which commands that draw nothing
 * should not pay.  This file gives plot.c the shim's C interface (cvshim.h)
 * by forwarding each call through a pointer found with dlsym(); a function
 * added to cvshim.h needs one line in CANVAS_FUNCS below.
 *
 * The module is looked for, in order, at $SSCOPE_PLOT_MODULE (tests and
 * developers), next to the program as libtool leaves it in the build tree
 * (DIR/cli/.libs/ for DIR/sensorscope), and in the installed package
 * library directory.
 */
#include "config.h"

#include <dlfcn.h>
#include <errno.h>
#include <limits.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cvload.h"
#include "cvshim.h"

#define MODULE "plot-opencv.so"

/* X(return type, name, parameters, arguments, value when not loaded),
 * V(name, parameters, arguments) for functions returning void */
#define CANVAS_FUNCS(X, V)                                                    \
	X(struct ssc_canvas *, ssc_canvas_new,                                 \
	  (int w, int h, const char *font_path), (w, h, font_path), NULL)      \
	V(ssc_canvas_free, (struct ssc_canvas * c), (c))                       \
	V(ssc_canvas_clip, (struct ssc_canvas * c, int x, int y, int w, int h), \
	  (c, x, y, w, h))                                                     \
	V(ssc_canvas_polyline,                                                 \
	  (struct ssc_canvas * c, const double *xy, size_t n, uint32_t rgb,    \
	   double width),                                                      \
	  (c, xy, n, rgb, width))                                              \
	V(ssc_canvas_fill,                                                     \
	  (struct ssc_canvas * c, const double *xy, size_t n, uint32_t rgb,    \
	   double alpha),                                                      \
	  (c, xy, n, rgb, alpha))                                              \
	V(ssc_canvas_rect,                                                     \
	  (struct ssc_canvas * c, double x, double y, double w, double h,      \
	   uint32_t rgb, double width, int filled),                            \
	  (c, x, y, w, h, rgb, width, filled))                                 \
	V(ssc_canvas_circle,                                                   \
	  (struct ssc_canvas * c, double x, double y, double r, uint32_t rgb,  \
	   double width, int filled),                                          \
	  (c, x, y, r, rgb, width, filled))                                    \
	V(ssc_canvas_text,                                                     \
	  (struct ssc_canvas * c, double x, double y, const char *utf8,        \
	   double size_px, uint32_t rgb, int vertical),                        \
	  (c, x, y, utf8, size_px, rgb, vertical))                             \
	V(ssc_canvas_text_size,                                                \
	  (struct ssc_canvas * c, const char *utf8, double size_px, double *w, \
	   double *ascent, double *descent),                                   \
	  (c, utf8, size_px, w, ascent, descent))                              \
	V(ssc_canvas_image,                                                    \
	  (struct ssc_canvas * c, int x, int y, int w, int h, const double *v, \
	   int iw, int ih),                                                    \
	  (c, x, y, w, h, v, iw, ih))                                          \
	X(int, ssc_canvas_png,                                                 \
	  (struct ssc_canvas * c, unsigned char **buf, size_t *len),           \
	  (c, buf, len), -1)

#define PTR(ret, name, params, args, fail) ret(*name) params;
#define VPTR(name, params, args) void(*name) params;
static struct {
	CANVAS_FUNCS(PTR, VPTR)
} fn;

static pthread_once_t once = PTHREAD_ONCE_INIT;
static int load_rc;
static char load_why[512];

static void *try_open(const char *path)
{
	void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);

	if (!h) {
		const char *e = dlerror();

		snprintf(load_why, sizeof(load_why), "%.480s", e ? e : path);
	}
	return h;
}

/* the module's path, in the order above: 0, or -ENOENT */
static int module_path(char *path, size_t len)
{
	const char *env = getenv("SSCOPE_PLOT_MODULE");
	char exe[PATH_MAX];
	ssize_t n;

	if (env && *env) {
		snprintf(path, len, "%s", env);
		return 0;
	}
	n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
	if (n > 0) {
		char *slash;

		exe[n] = '\0';
		slash = strrchr(exe, '/');
		if (slash) {
			*slash = '\0';
			snprintf(path, len, "%s/cli/.libs/" MODULE, exe);
			if (!access(path, F_OK))
				return 0;
		}
	}
	snprintf(path, len, "%s", SSCOPE_PKGLIBDIR "/" MODULE);
	return access(path, F_OK) ? -ENOENT : 0;
}

static void *open_module(void)
{
	char path[PATH_MAX + 64];

	module_path(path, sizeof(path));
	return try_open(path);
}

bool ssc_cv_installed(void)
{
	char path[PATH_MAX + 64];

	return module_path(path, sizeof(path)) == 0 && !access(path, R_OK);
}

static void load(void)
{
	void *h = open_module();

	if (!h) {
		load_rc = -ENOENT;
		return;
	}
#define LOOK(name)                                                             \
	do {                                                                   \
		*(void **)&fn.name = dlsym(h, #name);                          \
		if (!fn.name) {                                                \
			snprintf(load_why, sizeof(load_why),                   \
				 "%s lacks %s", MODULE, #name);                \
			load_rc = -ENOEXEC;                                    \
			return;                                                \
		}                                                              \
	} while (0)
#define XLOOK(ret, name, params, args, fail) LOOK(name);
#define VLOOK(name, params, args) LOOK(name);
	CANVAS_FUNCS(XLOOK, VLOOK)
}

int ssc_cv_load(char *why, size_t len)
{
	pthread_once(&once, load);
	if (load_rc && why && len)
		snprintf(why, len, "%s", load_why);
	return load_rc;
}

/* Without the module no canvas can be made, and the rest do nothing. */
#define DEF(ret, name, params, args, fail)                                     \
	ret name params                                                        \
	{                                                                      \
		if (ssc_cv_load(NULL, 0))                                      \
			return fail;                                           \
		return fn.name args;                                           \
	}
#define VDEF(name, params, args)                                               \
	void name params                                                       \
	{                                                                      \
		if (!ssc_cv_load(NULL, 0))                                     \
			fn.name args;                                          \
	}
CANVAS_FUNCS(DEF, VDEF)

