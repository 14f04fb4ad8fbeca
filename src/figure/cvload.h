/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Loading of the drawing module (cvshim.cpp with OpenCV and libpng), which
 * the command opens only when it draws a figure; see cvload.c.
 */
#ifndef SSCOPE_CVLOAD_H
#define SSCOPE_CVLOAD_H

#include <stdbool.h>
#include <stddef.h>

/*
 * Open the drawing module once (later calls return the first outcome).
 * Returns 0, or -ENOENT/-ENOEXEC with the reason in why[len] (why may be
 * NULL).
 */
int ssc_cv_load(char *why, size_t len);
/* Whether the module's file is where ssc_cv_load() would open it, without
 * opening it (OpenCV's start-up costs tens of milliseconds): for
 * `--version`. */
bool ssc_cv_installed(void);

#endif
