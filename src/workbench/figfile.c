/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Figures written to files: the bytes that src/figure/ draws (ssc_fig_svg,
 * ssc_fig_png) go through the output layer (ssc_file_put: atomically), one
 * format by the path's extension, or both from one drawing with the SVG
 * drawn on a thread of its own while the PNG is drawn.
 */
#include "config.h"

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "workbench.h"
#include "plot.h"

static int write_file(const char *path, const void *buf, size_t len)
{
	return ssc_file_put(path, buf, len);
}

/* the SVG document of the figure saved as path */
static int fig_svg_for(struct ssc_fig *f, const char *path, char **buf,
		       size_t *len)
{
	char id[48];
	const char *b = strrchr(path, '/');

	/* ids from the file name: figures inlined in one page stay apart */
	snprintf(id, sizeof(id), "f-%s", b ? b + 1 : path);
	if (strrchr(id, '.'))
		*strrchr(id, '.') = '\0';
	return ssc_fig_svg(f, id, buf, len);
}

int ssc_fig_save_svg(struct ssc_fig *f, const char *path)
{
	char *buf = NULL;
	size_t len = 0;
	int rc = fig_svg_for(f, path, &buf, &len);

	if (rc)
		return rc;
	rc = write_file(path, buf, len);
	free(buf);
	return rc;
}

int ssc_fig_save_png(struct ssc_fig *f, const char *path)
{
	unsigned char *png = NULL;
	size_t len = 0;
	int rc = ssc_fig_png(f, &png, &len);

	if (!rc)
		rc = write_file(path, png, len);
	free(png);
	return rc;
}

/* The SVG document drawn on a thread of its own while the PNG is drawn:
 * the figure is only read by both. */
struct svg_job {
	struct ssc_fig *f;
	const char *path;
	char *buf;
	size_t len;
	int rc;
};

static void *svg_thread(void *arg)
{
	struct svg_job *j = arg;

	j->rc = fig_svg_for(j->f, j->path, &j->buf, &j->len);
	return NULL;
}

/* the figure as p.svg and p.png (p.svg first, p.png only when it was
 * written), the two drawn at the same time */
static int save_both(struct ssc_fig *f, char *p, size_t stem)
{
	struct svg_job j = { .f = f, .path = p };
	unsigned char *png = NULL;
	size_t len = 0;
	pthread_t tid;
	bool two;
	int rc;

	strcpy(p + stem, ".svg");
	two = !pthread_create(&tid, NULL, svg_thread, &j);
	rc = ssc_fig_png(f, &png, &len);
	if (two)
		pthread_join(tid, NULL);
	else
		svg_thread(&j);
	if (!j.rc)
		j.rc = write_file(p, j.buf, j.len);
	free(j.buf);
	if (!j.rc && !rc) {
		strcpy(p + stem, ".png");
		rc = write_file(p, png, len);
	}
	free(png);
	return j.rc ? j.rc : rc;
}

int ssc_fig_save(struct ssc_fig *f, const char *path)
{
	size_t l = path ? strlen(path) : 0, k = strlen(SSC_PLOT_SVG_AND_PNG);

	if (l > k && !strcmp(path + l - k, SSC_PLOT_SVG_AND_PNG)) {
		char *p = malloc(l + 1);
		int rc;

		if (!p)
			return -ENOMEM;
		memcpy(p, path, l - k);
		rc = save_both(f, p, l - k);
		free(p);
		return rc;
	}
	switch (ssc_plot_format_of(path)) {
	case SSC_PLOT_PNG:
		return ssc_fig_save_png(f, path);
	case SSC_PLOT_SVG:
		return ssc_fig_save_svg(f, path);
	default:
		return -EINVAL;
	}
}
