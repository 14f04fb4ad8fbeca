/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Small OS helpers of the acquisition code: the monotonic clock, waiting
 * for a descriptor or an absolute time while watching a stop descriptor,
 * messages.
 */
#include "acq.h"

#include <errno.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

int64_t ssc_now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static struct timespec ts_of_ns(int64_t ns)
{
	struct timespec ts;

	if (ns < 0)
		ns = 0;
	ts.tv_sec = (time_t)(ns / 1000000000);
	ts.tv_nsec = (long)(ns % 1000000000);
	return ts;
}

int ssc_wait_fd(int fd, int stop_fd, double timeout_s)
{
	int64_t deadline = timeout_s >= 0
				   ? ssc_now_ns() + (int64_t)(timeout_s * 1e9)
				   : 0;

	for (;;) {
		struct pollfd p[2] = { { .fd = fd, .events = POLLIN },
				       { .fd = stop_fd, .events = POLLIN } };
		struct timespec ts;
		int n;

		if (timeout_s >= 0)
			ts = ts_of_ns(deadline - ssc_now_ns());
		n = ppoll(p, stop_fd >= 0 ? 2 : 1, timeout_s >= 0 ? &ts : NULL,
			  NULL);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0)
			return -errno;
		if (stop_fd >= 0 && p[1].revents)
			return -ECANCELED;
		if (n == 0)
			return 0;
		if (p[0].revents & POLLIN)
			return 1;
		if (p[0].revents & (POLLERR | POLLHUP | POLLNVAL))
			return -EIO;
	}
}

int ssc_sleep_until(int64_t t_ns, int stop_fd)
{
	struct timespec ts;

	/* long waits watch the stop descriptor; the last 2 ms are slept
	 * on the absolute clock so that the wake-up time does not drift */
	while (stop_fd >= 0 && t_ns - ssc_now_ns() > 2000000) {
		struct pollfd p = { .fd = stop_fd, .events = POLLIN };

		ts = ts_of_ns(t_ns - ssc_now_ns() - 1000000);
		if (ppoll(&p, 1, &ts, NULL) > 0 && p.revents)
			return -ECANCELED;
	}
	ts = ts_of_ns(t_ns);
	while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) ==
	       EINTR)
		;
	return 0;
}

int ssc_acq_diag(struct sscope_diag *d, int err, const char *fmt, ...)
{
	va_list ap;

	if (d) {
		va_start(ap, fmt);
		vsnprintf(d->msg, sizeof(d->msg), fmt, ap);
		va_end(ap);
	}
	return err;
}

void ssc_source_close(struct ssc_source *src)
{
	if (src && src->ops && src->ops->close)
		src->ops->close(src);
	else
		free(src);
}

bool ssc_acq_storage_full(int err)
{
	return err == -ENOSPC || err == -EDQUOT || err == -EFBIG;
}

const char *ssc_acq_full_words(int err)
{
	switch (err) {
	case -EDQUOT:
		return "disk quota full";
	case -EFBIG:
		return "file size limit";
	default:
		return "disk full";
	}
}
