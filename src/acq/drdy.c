/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Data-ready lines through libgpiod: edge events of one GPIO line with
 * kernel time stamps (CLOCK_MONOTONIC).  libgpiod 1.6 (Debian 12, GPIO
 * character device uAPI v1) or libgpiod 2.x (uAPI v2, line and global
 * sequence numbers), chosen by configure (SSCOPE_GPIOD_API); without
 * libgpiod ssc_drdy_open() returns -ENOTSUP.
 *
 * Every wake-up reads all queued events: the last one's time stamp
 * belongs to the frame read next; the others are edges whose frames were
 * never read.  The v1 kernel queue holds only 16 events per line and
 * drops newer ones silently, so losses are counted here where the uAPI
 * shows them (v2 sequence numbers, queued extra edges) and otherwise
 * found by the caller from the device counter or the time stamps.
 */
#include "acq.h"
#include "drdy.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef HAVE_LIBGPIOD
#include <gpiod.h>
#endif

#define MAX_EVENTS 64
#define SSC_ACQ_UNUSED __attribute__((unused)) /* without libgpiod */

bool ssc_drdy_available(void)
{
#ifdef HAVE_LIBGPIOD
	return true;
#else
	return false;
#endif
}

const char *ssc_drdy_api(void)
{
#if defined(HAVE_LIBGPIOD) && SSCOPE_GPIOD_API == 2
	return "libgpiod v2";
#elif defined(HAVE_LIBGPIOD)
	return "libgpiod v1";
#else
	return "none";
#endif
}

/* "CHIP:LINE": chip name, number or path; line offset or name */
static int split_spec(const char *spec, char *chip, size_t chip_len,
		      char *line, size_t line_len, struct sscope_diag *diag)
{
	const char *c = spec ? strrchr(spec, ':') : NULL;

	if (!c || c == spec || !c[1] || (size_t)(c - spec) >= chip_len ||
	    strlen(c + 1) >= line_len)
		return ssc_acq_diag(diag, -EINVAL,
				    "--drdy: '%s' is not CHIP:LINE (e.g. gpiochip0:25)",
				    spec ? spec : "");
	memcpy(chip, spec, (size_t)(c - spec));
	chip[c - spec] = '\0';
	strcpy(line, c + 1);
	return 0;
}

static SSC_ACQ_UNUSED bool parse_offset(const char *s, unsigned *out)
{
	char *end;
	unsigned long v;

	if (!*s || *s == '-' || *s == '+')
		return false;
	errno = 0;
	v = strtoul(s, &end, 10);
	if (*end || errno || v > 4095)
		return false;
	*out = (unsigned)v;
	return true;
}

#ifndef HAVE_LIBGPIOD

struct ssc_drdy {
	int unused;
};

int ssc_drdy_open(struct ssc_drdy **d, const char *spec, bool falling,
		  const char *consumer, struct sscope_diag *diag)
{
	char chip[64], line[64];
	int rc = split_spec(spec, chip, sizeof(chip), line, sizeof(line), diag);

	(void)falling;
	(void)consumer;
	*d = NULL;
	if (rc)
		return rc;
	return ssc_acq_diag(diag, -ENOTSUP,
			    "--drdy: data-ready lines need libgpiod, and this "
			    "sensorscope was built without it (rebuild with "
			    "libgpiod-dev installed, or poll without --drdy)");
}

int ssc_drdy_fd(const struct ssc_drdy *d)
{
	(void)d;
	return -1;
}

int ssc_drdy_read(struct ssc_drdy *d, struct ssc_drdy_events *ev)
{
	(void)d;
	(void)ev;
	return -ENOTSUP;
}

const char *ssc_drdy_name(const struct ssc_drdy *d)
{
	(void)d;
	return "";
}

void ssc_drdy_close(struct ssc_drdy *d)
{
	free(d);
}

#elif SSCOPE_GPIOD_API == 2

struct ssc_drdy {
	struct gpiod_chip *chip;
	struct gpiod_line_request *req;
	struct gpiod_edge_event_buffer *buf;
	unsigned offset;
	bool have_seq;
	unsigned long last_seq;
	char name[128];
};

static int chip_path(const char *chip, char *path, size_t len)
{
	unsigned n;

	if (chip[0] == '/')
		return snprintf(path, len, "%s", chip) < (int)len ? 0 : -EINVAL;
	if (parse_offset(chip, &n))
		return snprintf(path, len, "/dev/gpiochip%u", n) < (int)len
			       ? 0
			       : -EINVAL;
	return snprintf(path, len, "/dev/%s", chip) < (int)len ? 0 : -EINVAL;
}

int ssc_drdy_open(struct ssc_drdy **dp, const char *spec, bool falling,
		  const char *consumer, struct sscope_diag *diag)
{
	char chip[64], line[64], path[96];
	struct ssc_drdy *d;
	struct gpiod_line_settings *ls = NULL;
	struct gpiod_line_config *lc = NULL;
	struct gpiod_request_config *rc_cfg = NULL;
	unsigned off;
	int rc;

	*dp = NULL;
	rc = split_spec(spec, chip, sizeof(chip), line, sizeof(line), diag);
	if (rc)
		return rc;
	if (chip_path(chip, path, sizeof(path)))
		return ssc_acq_diag(diag, -EINVAL, "--drdy: bad chip '%s'",
				    chip);
	d = calloc(1, sizeof(*d));
	if (!d)
		return -ENOMEM;
	d->chip = gpiod_chip_open(path);
	if (!d->chip) {
		rc = -errno;
		ssc_acq_diag(diag, rc, "%s: %s%s", path, sscope_strerror(errno),
			     errno == EACCES ? " (add yourself to the gpio group, see the README)"
					     : "");
		goto fail;
	}
	if (!parse_offset(line, &off)) {
		int o = gpiod_chip_get_line_offset_from_name(d->chip, line);

		if (o < 0) {
			rc = ssc_acq_diag(diag, -ENODEV,
					  "%s: no line named '%s'", path, line);
			goto fail;
		}
		off = (unsigned)o;
	}
	d->offset = off;
	ls = gpiod_line_settings_new();
	lc = gpiod_line_config_new();
	rc_cfg = gpiod_request_config_new();
	d->buf = gpiod_edge_event_buffer_new(MAX_EVENTS);
	if (!ls || !lc || !rc_cfg || !d->buf) {
		rc = -ENOMEM;
		goto fail;
	}
	gpiod_line_settings_set_direction(ls, GPIOD_LINE_DIRECTION_INPUT);
	gpiod_line_settings_set_edge_detection(ls, falling ? GPIOD_LINE_EDGE_FALLING
							   : GPIOD_LINE_EDGE_RISING);
	gpiod_line_settings_set_event_clock(ls, GPIOD_LINE_CLOCK_MONOTONIC);
	if (gpiod_line_config_add_line_settings(lc, &off, 1, ls)) {
		rc = -errno;
		goto fail_msg;
	}
	gpiod_request_config_set_consumer(rc_cfg, consumer);
	d->req = gpiod_chip_request_lines(d->chip, rc_cfg, lc);
	if (!d->req) {
		rc = -errno;
		goto fail_msg;
	}
	snprintf(d->name, sizeof(d->name), "%s line %u (libgpiod v2)", path,
		 off);
	gpiod_line_settings_free(ls);
	gpiod_line_config_free(lc);
	gpiod_request_config_free(rc_cfg);
	*dp = d;
	return 0;
fail_msg:
	ssc_acq_diag(diag, rc, "%s line %u: cannot request edge events: %s%s",
		     path, off, sscope_strerror(-rc),
		     rc == -EBUSY ? " (the line is used by another program or driver)"
				  : "");
fail:
	gpiod_line_settings_free(ls);
	gpiod_line_config_free(lc);
	gpiod_request_config_free(rc_cfg);
	ssc_drdy_close(d);
	return rc;
}

int ssc_drdy_fd(const struct ssc_drdy *d)
{
	return gpiod_line_request_get_fd(d->req);
}

int ssc_drdy_read(struct ssc_drdy *d, struct ssc_drdy_events *ev)
{
	int n = gpiod_line_request_read_edge_events(d->req, d->buf, MAX_EVENTS);

	memset(ev, 0, sizeof(*ev));
	if (n < 0)
		return -errno;
	for (int i = 0; i < n; i++) {
		struct gpiod_edge_event *e =
			gpiod_edge_event_buffer_get_event(d->buf, (unsigned long)i);
		unsigned long seq = gpiod_edge_event_get_line_seqno(e);

		if (d->have_seq && seq > d->last_seq + 1)
			ev->lost += seq - d->last_seq - 1;
		d->last_seq = seq;
		d->have_seq = true;
		ev->t_ns = (int64_t)gpiod_edge_event_get_timestamp_ns(e);
	}
	ev->n = (unsigned)n;
	return 0;
}

const char *ssc_drdy_name(const struct ssc_drdy *d)
{
	return d->name;
}

void ssc_drdy_close(struct ssc_drdy *d)
{
	if (!d)
		return;
	if (d->req)
		gpiod_line_request_release(d->req);
	if (d->buf)
		gpiod_edge_event_buffer_free(d->buf);
	if (d->chip)
		gpiod_chip_close(d->chip);
	free(d);
}

#else /* libgpiod 1.6 */

struct ssc_drdy {
	struct gpiod_chip *chip;
	struct gpiod_line *line;
	char name[128];
};

int ssc_drdy_open(struct ssc_drdy **dp, const char *spec, bool falling,
		  const char *consumer, struct sscope_diag *diag)
{
	char chip[64], line[64];
	struct ssc_drdy *d;
	unsigned off;
	int rc;

	*dp = NULL;
	rc = split_spec(spec, chip, sizeof(chip), line, sizeof(line), diag);
	if (rc)
		return rc;
	d = calloc(1, sizeof(*d));
	if (!d)
		return -ENOMEM;
	/* name ("gpiochip0"), number, path or label */
	d->chip = gpiod_chip_open_lookup(chip);
	if (!d->chip) {
		rc = -errno;
		ssc_acq_diag(diag, rc, "--drdy: GPIO chip '%s': %s%s", chip,
			     sscope_strerror(errno),
			     errno == EACCES ? " (add yourself to the gpio group, see the README)"
					     : "");
		goto fail;
	}
	if (parse_offset(line, &off)) {
		if (off >= gpiod_chip_num_lines(d->chip)) {
			rc = ssc_acq_diag(diag, -ENODEV,
					  "--drdy: %s has %u lines, no line %u",
					  gpiod_chip_name(d->chip),
					  gpiod_chip_num_lines(d->chip), off);
			goto fail;
		}
		d->line = gpiod_chip_get_line(d->chip, off);
	} else {
		d->line = gpiod_chip_find_line(d->chip, line);
		if (!d->line) {
			rc = ssc_acq_diag(diag, -ENODEV,
					  "--drdy: %s has no line named '%s'",
					  gpiod_chip_name(d->chip), line);
			goto fail;
		}
		off = gpiod_line_offset(d->line);
	}
	if (!d->line) {
		rc = -errno;
		ssc_acq_diag(diag, rc, "--drdy: %s line %u: %s",
			     gpiod_chip_name(d->chip), off, sscope_strerror(errno));
		goto fail;
	}
	rc = falling ? gpiod_line_request_falling_edge_events(d->line, consumer)
		     : gpiod_line_request_rising_edge_events(d->line, consumer);
	if (rc) {
		rc = -errno;
		ssc_acq_diag(diag, rc,
			     "--drdy: %s line %u: cannot request edge events: %s%s",
			     gpiod_chip_name(d->chip), off, sscope_strerror(errno),
			     errno == EBUSY ? " (the line is used by another program or driver)"
					    : "");
		d->line = NULL;
		goto fail;
	}
	snprintf(d->name, sizeof(d->name), "%s line %u (libgpiod v1)",
		 gpiod_chip_name(d->chip), off);
	*dp = d;
	return 0;
fail:
	ssc_drdy_close(d);
	return rc;
}

int ssc_drdy_fd(const struct ssc_drdy *d)
{
	return gpiod_line_event_get_fd(d->line);
}

int ssc_drdy_read(struct ssc_drdy *d, struct ssc_drdy_events *ev)
{
	struct gpiod_line_event e[16];
	int n = gpiod_line_event_read_multiple(d->line, e, 16);

	memset(ev, 0, sizeof(*ev));
	if (n < 0)
		return -errno;
	if (n > 0)
		ev->t_ns = (int64_t)e[n - 1].ts.tv_sec * 1000000000 +
			   e[n - 1].ts.tv_nsec;
	ev->n = (unsigned)n;
	/* the v1 kernel queue holds 16 events per line */
	ev->full = n >= 16;
	return 0;
}

const char *ssc_drdy_name(const struct ssc_drdy *d)
{
	return d->name;
}

void ssc_drdy_close(struct ssc_drdy *d)
{
	if (!d)
		return;
	if (d->line)
		gpiod_line_release(d->line);
	if (d->chip)
		gpiod_chip_close(d->chip);
	free(d);
}

#endif
