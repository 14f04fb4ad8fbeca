/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Data-ready GPIO lines (drdy.c) and the spidev transport (spidev.c),
 * used by the SPI sources.
 */
#ifndef SSCOPE_ACQ_DRDY_H
#define SSCOPE_ACQ_DRDY_H

#include "acq.h"

struct ssc_drdy;

/* Events read at one wake-up. */
struct ssc_drdy_events {
	unsigned n;        /* edges read */
	uint64_t lost;     /* edges the kernel reports lost (v2 seqno) */
	int64_t t_ns;      /* time stamp of the last edge */
	bool full;         /* the kernel queue was full: newer edges may
			      have been dropped (uAPI v1 drops the newest) */
};

/*
 * Request edge events on CHIP:LINE (chip name, number or path; line
 * offset or name).  0; -ENOTSUP without libgpiod; -EINVAL bad spec;
 * -ENODEV no such line; -errno from the kernel (EACCES, EBUSY).
 */
int ssc_drdy_open(struct ssc_drdy **d, const char *spec, bool falling,
		  const char *consumer, struct sscope_diag *diag);
/* Descriptor that becomes readable when edges are queued. */
int ssc_drdy_fd(const struct ssc_drdy *d);
/* Read the queued edges (call when the descriptor is readable). */
int ssc_drdy_read(struct ssc_drdy *d, struct ssc_drdy_events *ev);
/* "gpiochip0 line 25 (libgpiod v1)" */
const char *ssc_drdy_name(const struct ssc_drdy *d);
void ssc_drdy_close(struct ssc_drdy *d);

/* One segment of a SPI message. */
struct ssc_spi_seg {
	const uint8_t *tx;   /* NULL: zeros */
	uint8_t *rx;         /* NULL: ignored */
	uint32_t len;
	bool cs_change;      /* release chip select after this segment */
	uint16_t delay_us;   /* wait after it (before the next) */
	uint32_t speed_hz;   /* 0: the device's speed */
};

struct ssc_spi {
	int fd;
	uint32_t speed_hz;
	char path[128];
};

/* Open and set mode, 8 bits per word and the clock.  0 or -errno. */
int ssc_spi_open(struct ssc_spi *spi, const char *path, unsigned mode,
		 uint32_t speed_hz, struct sscope_diag *diag);
/* One message of n segments (chip select held between segments unless
 * cs_change).  0 or -errno. */
int ssc_spi_message(struct ssc_spi *spi, const struct ssc_spi_seg *seg,
		    size_t n);
void ssc_spi_close(struct ssc_spi *spi);

#endif
