/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * spidev transport (Linux Documentation/spi/spidev): mode, word size and
 * clock are set once with SPI_IOC_WR_*; each frame is one SPI_IOC_MESSAGE
 * of a few transfers, with the clock given in every transfer and chip
 * select released only where a segment asks for it.
 */
#include "acq.h"
#include "drdy.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/spi/spidev.h>
#include <stdio.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#define MAX_SEGS 16

int ssc_spi_open(struct ssc_spi *spi, const char *path, unsigned mode,
		 uint32_t speed_hz, struct sscope_diag *diag)
{
	uint8_t m = (uint8_t)mode, bits = 8, got_mode = 0xff;
	uint32_t speed = speed_hz;
	const char *what;

	memset(spi, 0, sizeof(*spi));
	spi->fd = -1;
	spi->fd = open(path, O_RDWR | O_CLOEXEC);
	if (spi->fd < 0) {
		int e = errno;

		return ssc_acq_diag(diag, -e, "%s: %s%s", path, sscope_strerror(e),
				    e == EACCES ? " (give your user access to spidev: see the README's wiring section)"
				    : e == ENOENT ? " (is SPI enabled, e.g. dtparam=spi=on on a Raspberry Pi?)"
						  : "");
	}
	snprintf(spi->path, sizeof(spi->path), "%s", path);
	spi->speed_hz = speed_hz;
	what = "set SPI mode";
	if (ioctl(spi->fd, SPI_IOC_WR_MODE, &m) < 0)
		goto fail;
	what = "read SPI mode";
	if (ioctl(spi->fd, SPI_IOC_RD_MODE, &got_mode) < 0)
		goto fail;
	if ((got_mode & 3) != (m & 3)) {
		int rc = ssc_acq_diag(diag, -EIO,
				      "%s: the controller kept SPI mode %u instead of %u",
				      path, got_mode & 3u, mode);

		ssc_spi_close(spi);
		return rc;
	}
	what = "set 8 bits per word";
	if (ioctl(spi->fd, SPI_IOC_WR_BITS_PER_WORD, &bits) < 0)
		goto fail;
	what = "set the SPI clock";
	if (ioctl(spi->fd, SPI_IOC_WR_MAX_SPEED_HZ, &speed) < 0)
		goto fail;
	return 0;
fail: {
	int e = errno, rc = ssc_acq_diag(diag, -e, "%s: cannot %s: %s", path,
					  what, sscope_strerror(e));

	ssc_spi_close(spi);
	return rc;
}
}

int ssc_spi_message(struct ssc_spi *spi, const struct ssc_spi_seg *seg,
		    size_t n)
{
	struct spi_ioc_transfer x[MAX_SEGS];
	int rc;

	if (n == 0 || n > MAX_SEGS)
		return -EINVAL;
	memset(x, 0, n * sizeof(x[0]));
	for (size_t i = 0; i < n; i++) {
		x[i].tx_buf = (uint64_t)(uintptr_t)seg[i].tx;
		x[i].rx_buf = (uint64_t)(uintptr_t)seg[i].rx;
		x[i].len = seg[i].len;
		x[i].speed_hz = seg[i].speed_hz ? seg[i].speed_hz : spi->speed_hz;
		x[i].delay_usecs = seg[i].delay_us;
		x[i].bits_per_word = 8;
		x[i].cs_change = seg[i].cs_change;
	}
	do
		rc = ioctl(spi->fd,
			   _IOC(_IOC_WRITE, SPI_IOC_MAGIC, 0, SPI_MSGSIZE(n)), x);
	while (rc < 0 && errno == EINTR);
	return rc < 0 ? -errno : 0;
}

void ssc_spi_close(struct ssc_spi *spi)
{
	if (spi->fd >= 0)
		close(spi->fd);
	spi->fd = -1;
}
