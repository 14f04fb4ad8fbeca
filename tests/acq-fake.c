/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * End-to-end tests of the real `sensorscope acquire` against emulated
 * kernel devices (umockdev >= 0.16 custom ioctl handlers):
 *
 *  - /dev/gpiochip0: a GPIO character device serving the uAPI v1 ioctls
 *    libgpiod 1.6 uses (chip info, line info, line event request) and the
 *    v2 ones of libgpiod 2 (line info, line request).  The event fd handed
 *    to the client is a pipe the child inherits at the fixed descriptor
 *    EV_FD; edge events (struct gpioevent_data, or gpio_v2_line_event) are
 *    written to it.  Like the v1 kernel, at most 16 events queue per line
 *    and newer ones are dropped.
 *  - /dev/spidev0.0: spidev's mode / word size / clock ioctls and
 *    SPI_IOC_MESSAGE(n) with an ADIS16470 behind it: pipelined 16-bit
 *    register access (PROD_ID, DEC_RATE, MSC_CTRL, DATA_CNTR), burst reads
 *    (0x6800 then DIAG_STAT, gyro, accel, TEMP_OUT, DATA_CNTR, checksum).
 *    The model is strict: a wrong SPI mode, word size or bit order, a clock
 *    above 2 MHz (1 MHz for bursts) or a missing 16 us stall garbles the
 *    answer and is counted, so the tests also check how sensorscope drives
 *    the bus.
 *
 * Pacing: lock-step (the next data-ready edge is emitted when the previous
 * burst has been served) for exact assertions; free-running (a thread
 * emits samples and edges on the monotonic clock, whatever the reader
 * does) for consistency assertions; silent (no edge) for the timeout.
 * Edge time stamps are the ideal k * period (as if the kernel stamped
 * each edge without latency), so that time stamps can be checked
 * against the sample counter.  Stock
 * gpioinfo and gpiomon are run against the fake to check the fake itself.
 *
 * The values of a sample are a function of its DATA_CNTR (gx is an
 * invertible function of it), so every row of a capture can be traced back
 * to the sample it came from.  Output: TAP.  Environment: SSCOPE (the
 * binary), SSCOPE_RUN (a prefix such as valgrind).
 */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/gpio.h>
#include <linux/spi/spidev.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <jansson.h>
#include <umockdev.h>

#include "sensorscope.h"

#define EV_FD 100        /* the child's event descriptor */
#define N_LINES 32
#define DR_LINE 25
#define PI 3.14159265358979323846
#define GYRO_LSB (0.1 * PI / 180)      /* ADIS16470: 0.1 deg/s */
#define ACCEL_LSB (1.25e-3 * 9.80665)  /* 1.25 mg */
#define TEMP_LSB 0.1
#define GX_MUL 1237u
#define GX_ADD 101u

/* ------------------------------------------------------------ TAP */

static int tap_n;

static void tap(bool cond, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
static void tap(bool cond, const char *fmt, ...)
{
	va_list ap;

	printf("%s %d - ", cond ? "ok" : "not ok", ++tap_n);
	va_start(ap, fmt);
	vprintf(fmt, ap);
	va_end(ap);
	putchar('\n');
	fflush(stdout);
}

static void skip(const char *what, const char *why)
{
	printf("ok %d - %s # SKIP %s\n", ++tap_n, what, why);
	fflush(stdout);
}

static void note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void note(const char *fmt, ...)
{
	va_list ap;

	fputs("# ", stdout);
	va_start(ap, fmt);
	vprintf(fmt, ap);
	va_end(ap);
	putchar('\n');
	fflush(stdout);
}

static void show_file(const char *path)
{
	FILE *f = fopen(path, "r");
	char line[512];
	int n = 0;

	if (!f)
		return;
	while (fgets(line, sizeof(line), f) && n++ < 20)
		printf("#   %s%s", line, strchr(line, '\n') ? "" : "\n");
	fclose(f);
}

/* ------------------------------------------------------------ the model */

/* sizes, scaled down under valgrind (SSCOPE_RUN set) */
static unsigned NS = 500, NG = 300, NC = 200, NF = 1000, NP = 300;
static uint16_t C0;

static const char *num(unsigned v)
{
	static char buf[8][16];
	static int i;

	i = (i + 1) % 8;
	snprintf(buf[i], sizeof(buf[i]), "%u", v);
	return buf[i];
}

enum pacing { P_LOCKSTEP, P_FREE, P_SILENT };

static struct model {
	pthread_mutex_t mu;
	/* scenario */
	enum pacing pacing;
	int64_t period_ns;
	uint16_t prod_id, dec_rate, msc_ctrl, cntr0;
	long gap_at;          /* sample index after a gap, -1 none */
	unsigned gap_len;
	long bad_crc_at;      /* sample whose burst is corrupted, -1 none */
	bool bad_crc_done;
	unsigned slow_bursts; /* the first bursts answered 12 ms late */
	/* state */
	uint64_t k;           /* samples produced */
	uint16_t cntr;
	int64_t ts_ns;
	uint16_t pending;     /* pipelined register answer */
	uint8_t mode, bits, lsb_first;
	uint32_t speed;
	/* what the client did */
	unsigned bursts, regs, garbled, fast, no_stall, cs_tail;
	/* GPIO */
	int ev_w, ev_r;       /* pipe ends kept by the harness */
	int evfmt;            /* 1: v1 events, 2: v2 events */
	bool requested;
	unsigned req_line;
	uint32_t req_edges;   /* bit 0 rising, bit 1 falling */
	char consumer[40];
	unsigned queue_drops;
	uint32_t seqno;
	/* free-running pacer */
	pthread_t thr;
	bool thr_on;
	atomic_bool thr_stop;
} M = { .mu = PTHREAD_MUTEX_INITIALIZER };

static int16_t s16(uint32_t v)
{
	v &= 0xffff;
	return v < 0x8000 ? (int16_t)v : (int16_t)((int32_t)v - 65536);
}

static void raw_of(uint16_t c, int16_t raw[7])
{
	raw[0] = s16(c * GX_MUL + GX_ADD);
	raw[1] = s16(c * 4099u + 7u);
	raw[2] = s16(0u - (c * GX_MUL + GX_ADD));
	raw[3] = s16(c * 3u + 64536u);
	raw[4] = s16(c * 11u);
	raw[5] = 800; /* 1 g */
	raw[6] = (int16_t)(250 + c % 50);
}

static uint16_t gx_inverse; /* GX_MUL^-1 mod 2^16 */

static uint16_t counter_of_gx(double gx_si)
{
	long raw = lround(gx_si / GYRO_LSB);

	return (uint16_t)((uint32_t)(raw - (long)GX_ADD) * gx_inverse);
}

static void put16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)(v >> 8);
	p[1] = (uint8_t)v;
}

/* the burst answer for the current sample (own encoder: an independent
 * oracle of the decoder under test) */
static void burst_of(uint8_t out[20], bool corrupt)
{
	int16_t raw[7];
	unsigned sum = 0;

	raw_of(M.cntr, raw);
	put16(out, 0);
	for (int i = 0; i < 7; i++)
		put16(out + 2 + 2 * i, (uint16_t)raw[i]);
	put16(out + 16, M.cntr);
	for (int i = 0; i < 18; i++)
		sum += out[i];
	put16(out + 18, (uint16_t)(sum + (corrupt ? 1 : 0)));
}

static int64_t now_ns(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

static void write_event_locked(int64_t ts, bool rising)
{
	int queued = 0;
	size_t sz;
	ssize_t w;

	M.seqno++;
	if (!M.requested || !(M.req_edges & (rising ? 1u : 2u)))
		return;
	sz = M.evfmt == 2 ? sizeof(struct gpio_v2_line_event)
			  : sizeof(struct gpioevent_data);
	if (ioctl(M.ev_r, FIONREAD, &queued) == 0 && (size_t)queued >= 16 * sz) {
		M.queue_drops++; /* the kernel's 16-event queue is full */
		return;
	}
	if (M.evfmt == 2) {
		struct gpio_v2_line_event e;

		memset(&e, 0, sizeof(e));
		e.timestamp_ns = (uint64_t)ts;
		e.id = rising ? GPIO_V2_LINE_EVENT_RISING_EDGE
			      : GPIO_V2_LINE_EVENT_FALLING_EDGE;
		e.offset = M.req_line;
		e.seqno = M.seqno;
		e.line_seqno = M.seqno;
		w = write(M.ev_w, &e, sizeof(e));
	} else {
		struct gpioevent_data e;

		memset(&e, 0, sizeof(e));
		e.timestamp = (uint64_t)ts;
		e.id = rising ? GPIOEVENT_EVENT_RISING_EDGE
			      : GPIOEVENT_EVENT_FALLING_EDGE;
		w = write(M.ev_w, &e, sizeof(e));
	}
	if (w < 0)
		M.queue_drops++;
}

/* a new sample and its data-ready pulse (DR active high when MSC_CTRL
 * bit 0 is set: the rising edge marks new data) */
static void emit_locked(void)
{
	unsigned adv = 1;
	bool active_high = M.msc_ctrl & 1;

	if (M.k == 0) {
		M.cntr = M.cntr0;
		M.ts_ns = 1000000000; /* 1 s */
	} else {
		if ((long)M.k == M.gap_at)
			adv += M.gap_len; /* samples (and edges) lost */
		M.cntr = (uint16_t)(M.cntr + adv);
		M.ts_ns += (int64_t)adv * M.period_ns;
		M.seqno += adv - 1;
	}
	M.k++;
	write_event_locked(M.ts_ns, active_high);
	write_event_locked(M.ts_ns + M.period_ns / 2, !active_high);
}

static void *pacer(void *arg)
{
	struct timespec ts;
	int64_t next = now_ns();

	(void)arg;
	while (!atomic_load(&M.thr_stop)) {
		next += M.period_ns;
		ts.tv_sec = (time_t)(next / 1000000000);
		ts.tv_nsec = (long)(next % 1000000000);
		clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL);
		pthread_mutex_lock(&M.mu);
		emit_locked();
		pthread_mutex_unlock(&M.mu);
	}
	return NULL;
}

static uint16_t reg_read(uint8_t reg)
{
	switch (reg & 0x7e) {
	case 0x72:
		return M.prod_id;
	case 0x64:
		return M.dec_rate;
	case 0x60:
		return M.msc_ctrl;
	case 0x22:
		return M.cntr;
	default:
		return 0;
	}
}

static void reg_write(uint8_t reg, uint8_t byte)
{
	switch (reg) {
	case 0x64:
		M.dec_rate = (uint16_t)((M.dec_rate & 0xff00) | byte);
		break;
	case 0x65:
		M.dec_rate = (uint16_t)((M.dec_rate & 0x00ff) | byte << 8);
		break;
	case 0x60:
		M.msc_ctrl = (uint16_t)((M.msc_ctrl & 0xff00) | byte);
		break;
	case 0x61:
		M.msc_ctrl = (uint16_t)((M.msc_ctrl & 0x00ff) | byte << 8);
		break;
	default:
		return;
	}
	/* output rate 2000 / (DEC_RATE + 1) Hz */
	M.period_ns = 500000 * ((int64_t)M.dec_rate + 1);
}

/* One chip-select frame: tx in, rx out.  Returns true for a burst. */
static bool adis_frame(const uint8_t *tx, size_t len, uint8_t *rx,
		       uint32_t max_speed)
{
	bool burst = len >= 22 && tx[0] == 0x68 && tx[1] == 0x00;
	bool garble = M.mode != SPI_MODE_3 || M.bits != 8 || M.lsb_first;

	memset(rx, 0, len);
	if (burst) {
		bool corrupt = false;

		M.bursts++;
		put16(rx, M.pending);
		M.pending = 0;
		if (M.bad_crc_at >= 0 && M.k == (uint64_t)M.bad_crc_at + 1 &&
		    !M.bad_crc_done) {
			corrupt = true;
			M.bad_crc_done = true;
		}
		burst_of(rx + 2, corrupt);
		if (max_speed > 1000000) {
			M.fast++;
			garble = true;
		}
	} else {
		for (size_t i = 0; i + 1 < len; i += 2) {
			put16(rx + i, M.pending);
			if (tx[i] & 0x80) {
				reg_write(tx[i] & 0x7f, tx[i + 1]);
				M.pending = 0;
			} else {
				M.pending = reg_read(tx[i]);
			}
			M.regs++;
		}
		if (max_speed > 2000000) {
			M.fast++;
			garble = true;
		}
	}
	if (garble) { /* sampled on the wrong edge: shifted by a bit */
		M.garbled++;
		for (size_t i = len; i-- > 0;)
			rx[i] = (uint8_t)(rx[i] >> 1 | (i ? rx[i - 1] << 7 : 0x80));
	}
	return burst;
}

#define MAX_XFERS 16

static void spi_message(UMockdevIoctlClient *c, UMockdevIoctlData *arg,
			unsigned n)
{
	UMockdevIoctlData *d, *tx[MAX_XFERS] = { NULL }, *rx[MAX_XFERS] = { NULL };
	struct spi_ioc_transfer *x;
	uint8_t fb[4096], fr[4096];
	size_t flen = 0, first = 0, total = 0;
	uint32_t fspeed = 0;
	bool burst_served = false, slow;
	GError *err = NULL;

	if (n == 0 || n > MAX_XFERS) {
		umockdev_ioctl_client_complete(c, -1, EINVAL);
		return;
	}
	d = umockdev_ioctl_data_resolve(arg, 0, n * sizeof(*x), &err);
	if (!d) {
		umockdev_ioctl_client_complete(c, -1, EFAULT);
		return;
	}
	x = (struct spi_ioc_transfer *)d->data;
	for (unsigned i = 0; i < n; i++) {
		size_t base = i * sizeof(*x);

		if (x[i].len > sizeof(fb)) {
			umockdev_ioctl_client_complete(c, -1, EMSGSIZE);
			goto out;
		}
		if (x[i].tx_buf)
			tx[i] = umockdev_ioctl_data_resolve(
				d, base + offsetof(struct spi_ioc_transfer, tx_buf),
				x[i].len, &err);
		if (x[i].rx_buf)
			rx[i] = umockdev_ioctl_data_resolve(
				d, base + offsetof(struct spi_ioc_transfer, rx_buf),
				x[i].len, &err);
	}
	pthread_mutex_lock(&M.mu);
	for (unsigned i = 0; i < n; i++) {
		uint32_t sp = x[i].speed_hz ? x[i].speed_hz : M.speed;
		bool end = i + 1 == n || x[i].cs_change;

		if (flen + x[i].len > sizeof(fb))
			break;
		if (tx[i])
			memcpy(fb + flen, tx[i]->data, x[i].len);
		else
			memset(fb + flen, 0, x[i].len);
		flen += x[i].len;
		total += x[i].len;
		if (sp > fspeed)
			fspeed = sp;
		if (x[i].cs_change && i + 1 < n && x[i].delay_usecs < 16)
			M.no_stall++;
		if (x[i].cs_change && i + 1 == n)
			M.cs_tail++;
		if (!end)
			continue;
		if (adis_frame(fb, flen, fr, fspeed))
			burst_served = true;
		/* hand the answer back, transfer by transfer */
		for (size_t j = first, off = 0; j <= i; j++) {
			if (rx[j])
				memcpy(rx[j]->data, fr + off, x[j].len);
			off += x[j].len;
		}
		first = i + 1;
		flen = 0;
		fspeed = 0;
	}
	if (burst_served && M.pacing == P_LOCKSTEP)
		emit_locked(); /* the next data-ready edge */
	slow = burst_served && M.slow_bursts && M.slow_bursts--;
	pthread_mutex_unlock(&M.mu);
	if (slow) {
		/* a reader that cannot keep up: more than 16 periods pass,
		 * the event queue fills and drops the newest edges */
		struct timespec ts = { 0, 12000000 };

		nanosleep(&ts, NULL);
	}
	umockdev_ioctl_client_complete(c, (glong)total, 0);
out:
	for (unsigned i = 0; i < n; i++) {
		if (tx[i])
			g_object_unref(tx[i]);
		if (rx[i])
			g_object_unref(rx[i]);
	}
	g_object_unref(d);
}

static gboolean on_spi(UMockdevIoctlBase *h, UMockdevIoctlClient *c,
		       gpointer ud)
{
	gulong req = umockdev_ioctl_client_get_request(c);
	UMockdevIoctlData *arg = umockdev_ioctl_client_get_arg(c), *d;
	unsigned size = _IOC_SIZE(req), nr = _IOC_NR(req);
	bool wr = _IOC_DIR(req) == _IOC_WRITE;
	GError *err = NULL;

	(void)h;
	(void)ud;
	if (_IOC_TYPE(req) != SPI_IOC_MAGIC) {
		umockdev_ioctl_client_complete(c, -1, ENOTTY);
		return TRUE;
	}
	if (nr == 0 && wr) {
		spi_message(c, arg, size / (unsigned)sizeof(struct spi_ioc_transfer));
		return TRUE;
	}
	d = umockdev_ioctl_data_resolve(arg, 0, size, &err);
	if (!d) {
		umockdev_ioctl_client_complete(c, -1, EFAULT);
		return TRUE;
	}
	pthread_mutex_lock(&M.mu);
	switch (nr) {
	case 1: /* MODE (u8) */
		if (wr)
			M.mode = d->data[0];
		else
			d->data[0] = M.mode;
		break;
	case 2: /* LSB_FIRST */
		if (wr)
			M.lsb_first = d->data[0];
		else
			d->data[0] = M.lsb_first;
		break;
	case 3: /* BITS_PER_WORD */
		if (wr)
			M.bits = d->data[0] ? d->data[0] : 8;
		else
			d->data[0] = M.bits;
		break;
	case 4: /* MAX_SPEED_HZ (u32) */
		if (wr)
			memcpy(&M.speed, d->data, 4);
		else
			memcpy(d->data, &M.speed, 4);
		break;
	case 5: { /* MODE32 */
		uint32_t m;

		if (wr) {
			memcpy(&m, d->data, 4);
			M.mode = (uint8_t)m;
		} else {
			m = M.mode;
			memcpy(d->data, &m, 4);
		}
		break;
	}
	default:
		pthread_mutex_unlock(&M.mu);
		g_object_unref(d);
		umockdev_ioctl_client_complete(c, -1, ENOTTY);
		return TRUE;
	}
	pthread_mutex_unlock(&M.mu);
	umockdev_ioctl_client_complete(c, 0, 0);
	g_object_unref(d);
	return TRUE;
}

static void line_name(unsigned off, char *buf, size_t len)
{
	snprintf(buf, len, "GPIO%u", off);
}

static void grant_events(uint32_t lineoffset, uint32_t edges,
			 const char *consumer, int fmt)
{
	M.requested = true;
	M.req_line = lineoffset;
	M.req_edges = edges;
	M.evfmt = fmt;
	snprintf(M.consumer, sizeof(M.consumer), "%.31s", consumer);
	if (M.pacing == P_LOCKSTEP && lineoffset == DR_LINE)
		emit_locked(); /* the first sample */
}

static gboolean on_gpio(UMockdevIoctlBase *h, UMockdevIoctlClient *c,
			gpointer ud)
{
	gulong req = umockdev_ioctl_client_get_request(c);
	UMockdevIoctlData *arg = umockdev_ioctl_client_get_arg(c), *d;
	GError *err = NULL;
	int rc = 0, e = 0;

	(void)h;
	(void)ud;
	if (req != GPIO_GET_CHIPINFO_IOCTL && req != GPIO_GET_LINEINFO_IOCTL &&
	    req != GPIO_GET_LINEEVENT_IOCTL &&
	    req != GPIO_V2_GET_LINEINFO_IOCTL && req != GPIO_V2_GET_LINE_IOCTL) {
		umockdev_ioctl_client_complete(c, -1, ENOTTY);
		return TRUE;
	}
	d = umockdev_ioctl_data_resolve(arg, 0, _IOC_SIZE(req), &err);
	if (!d) {
		umockdev_ioctl_client_complete(c, -1, EFAULT);
		return TRUE;
	}
	pthread_mutex_lock(&M.mu);
	if (req == GPIO_GET_CHIPINFO_IOCTL) {
		struct gpiochip_info *ci = (void *)d->data;

		memset(ci, 0, sizeof(*ci));
		snprintf(ci->name, sizeof(ci->name), "gpiochip0");
		snprintf(ci->label, sizeof(ci->label), "sensorscope-fake");
		ci->lines = N_LINES;
	} else if (req == GPIO_GET_LINEINFO_IOCTL) {
		struct gpioline_info *li = (void *)d->data;
		unsigned off = li->line_offset;

		if (off >= N_LINES) {
			rc = -1;
			e = EINVAL;
		} else {
			memset(li, 0, sizeof(*li));
			li->line_offset = off;
			line_name(off, li->name, sizeof(li->name));
			if (M.requested && off == M.req_line) {
				li->flags = GPIOLINE_FLAG_KERNEL;
				snprintf(li->consumer, sizeof(li->consumer), "%.31s",
					 M.consumer);
			}
		}
	} else if (req == GPIO_V2_GET_LINEINFO_IOCTL) {
		struct gpio_v2_line_info *li = (void *)d->data;
		unsigned off = li->offset;

		if (off >= N_LINES) {
			rc = -1;
			e = EINVAL;
		} else {
			memset(li, 0, sizeof(*li));
			li->offset = off;
			line_name(off, li->name, sizeof(li->name));
			li->flags = GPIO_V2_LINE_FLAG_INPUT;
			if (M.requested && off == M.req_line) {
				li->flags |= GPIO_V2_LINE_FLAG_USED;
				snprintf(li->consumer, sizeof(li->consumer), "%.31s",
					 M.consumer);
			}
		}
	} else if (req == GPIO_GET_LINEEVENT_IOCTL) {
		struct gpioevent_request *r = (void *)d->data;

		if (r->lineoffset >= N_LINES || !(r->eventflags & 3)) {
			rc = -1;
			e = EINVAL;
		} else if (M.requested) {
			rc = -1;
			e = EBUSY;
		} else {
			r->fd = EV_FD;
			grant_events(r->lineoffset, r->eventflags & 3,
				     r->consumer_label, 1);
		}
	} else {
		struct gpio_v2_line_request *r = (void *)d->data;
		uint64_t f = r->config.flags;
		uint32_t edges = (f & GPIO_V2_LINE_FLAG_EDGE_RISING ? 1u : 0u) |
				 (f & GPIO_V2_LINE_FLAG_EDGE_FALLING ? 2u : 0u);

		if (r->num_lines != 1 || r->offsets[0] >= N_LINES || !edges) {
			rc = -1;
			e = EINVAL;
		} else if (M.requested) {
			rc = -1;
			e = EBUSY;
		} else {
			r->fd = EV_FD;
			grant_events(r->offsets[0], edges, r->consumer, 2);
		}
	}
	pthread_mutex_unlock(&M.mu);
	umockdev_ioctl_client_complete(c, rc, e);
	g_object_unref(d);
	return TRUE;
}

/* ------------------------------------------------------------ scenarios */

struct scenario {
	enum pacing pacing;
	int64_t period_ns;
	uint16_t prod_id, cntr0, msc_ctrl, dec_rate;
	long gap_at;
	unsigned gap_len;
	long bad_crc_at;
	unsigned slow_bursts;
};

static const struct scenario base = {
	.pacing = P_LOCKSTEP, .period_ns = 500000, .prod_id = 16470,
	.cntr0 = 0 /* C0 */, .msc_ctrl = 0x00c1, .dec_rate = 0, .gap_at = -1,
	.bad_crc_at = -1,
};

static void start(const struct scenario *s)
{
	int p[2];

	pthread_mutex_lock(&M.mu);
	if (M.ev_w > 0) {
		close(M.ev_w);
		close(M.ev_r);
	}
	if (pipe2(p, O_CLOEXEC)) {
		perror("pipe2");
		exit(99);
	}
	M.ev_r = p[0];
	M.ev_w = p[1];
	fcntl(M.ev_w, F_SETFL, O_NONBLOCK);
	M.pacing = s->pacing;
	M.period_ns = s->period_ns;
	M.prod_id = s->prod_id;
	M.cntr0 = s->cntr0 ? s->cntr0 : C0;
	M.msc_ctrl = s->msc_ctrl;
	M.dec_rate = s->dec_rate;
	M.gap_at = s->gap_at;
	M.gap_len = s->gap_len;
	M.bad_crc_at = s->bad_crc_at;
	M.bad_crc_done = false;
	M.slow_bursts = s->slow_bursts;
	M.k = 0;
	M.cntr = M.cntr0;
	M.ts_ns = 0;
	M.pending = 0;
	M.mode = 0;
	M.bits = 8;
	M.lsb_first = 0;
	M.speed = 500000;
	M.bursts = M.regs = M.garbled = M.fast = M.no_stall = M.cs_tail = 0;
	M.requested = false;
	M.req_edges = 0;
	M.consumer[0] = '\0';
	M.queue_drops = 0;
	M.seqno = 0;
	pthread_mutex_unlock(&M.mu);
	if (s->pacing == P_FREE) {
		atomic_store(&M.thr_stop, false);
		M.thr_on = pthread_create(&M.thr, NULL, pacer, NULL) == 0;
	}
}

static void stop(void)
{
	if (M.thr_on) {
		atomic_store(&M.thr_stop, true);
		pthread_join(M.thr, NULL);
		M.thr_on = false;
	}
}

static char tmpdir[256];

static const char *tpath(const char *name)
{
	static char buf[4][512];
	static int i;

	i = (i + 1) % 4;
	snprintf(buf[i], sizeof(buf[i]), "%s/%s", tmpdir, name);
	return buf[i];
}

/*
 * Run a program with the preload library, the event pipe at EV_FD,
 * stdout and stderr into files.  prefix: prepend $SSCOPE_RUN.  Sends sig
 * once the device has served sig_after bursts (0: never).  Returns the
 * exit status, 128 + signal when killed, -1 on timeout.
 */
static int run(bool prefix, const char *const *args, const char *out,
	       const char *err, unsigned sig_after, int sig)
{
	const char *pre = prefix ? getenv("SSCOPE_RUN") : NULL;
	char *preword = pre ? strdup(pre) : NULL, *save = NULL;
	const char *argv[64];
	size_t n = 0;
	int64_t t0 = now_ns();
	bool signalled = false;
	int status;
	pid_t pid;

	if (preword)
		for (char *w = strtok_r(preword, " ", &save); w && n < 40;
		     w = strtok_r(NULL, " ", &save))
			argv[n++] = w;
	for (size_t i = 0; args[i] && n < 63; i++)
		argv[n++] = args[i];
	argv[n] = NULL;
	pid = fork();
	if (pid == 0) {
		const char *old = getenv("LD_PRELOAD");
		char pl[1024];
		int fo = open(out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
		int fe = open(err, O_WRONLY | O_CREAT | O_TRUNC, 0644);
		int fi = open("/dev/null", O_RDONLY);

		if (fo < 0 || fe < 0 || fi < 0 || dup2(M.ev_r, EV_FD) < 0)
			_exit(126);
		dup2(fi, 0);
		dup2(fo, 1);
		dup2(fe, 2);
		snprintf(pl, sizeof(pl), "libumockdev-preload.so.0%s%s",
			 old && *old ? ":" : "", old && *old ? old : "");
		setenv("LD_PRELOAD", pl, 1);
		/* an ASan build tolerates the preload library */
		setenv("ASAN_OPTIONS", "verify_asan_link_order=0", 0);
		execvp(argv[0], (char *const *)argv);
		_exit(127);
	}
	free(preword);
	if (pid < 0)
		return -1;
	for (;;) {
		pid_t r = waitpid(pid, &status, WNOHANG);
		double el = 1e-9 * (double)(now_ns() - t0);

		if (r == pid)
			break;
		if (sig_after && !signalled) {
			unsigned b;

			pthread_mutex_lock(&M.mu);
			b = M.bursts;
			pthread_mutex_unlock(&M.mu);
			if (b >= sig_after) {
				kill(pid, sig);
				signalled = true;
			}
		}
		if (el > 120) {
			kill(pid, SIGKILL);
			waitpid(pid, &status, 0);
			return -1;
		}
		usleep(5000);
	}
	if (WIFEXITED(status))
		return WEXITSTATUS(status);
	return 128 + WTERMSIG(status);
}

static const char *sscope;

/* run sensorscope acquire ARGS with the prefix; "out", "err" files */
static int acquire(const char *const *extra, unsigned sig_after, int sig)
{
	const char *args[48] = { sscope, "acquire" };
	size_t n = 2;

	for (size_t i = 0; extra[i] && n < 47; i++)
		args[n++] = extra[i];
	args[n] = NULL;
	return run(true, args, tpath("out"), tpath("err"), sig_after, sig);
}

static json_t *summary(void)
{
	json_error_t e;
	json_t *j = json_load_file(tpath("out"), 0, &e);

	if (!j) {
		note("summary is not JSON: %s", e.text);
		show_file(tpath("out"));
		show_file(tpath("err"));
	}
	return j;
}

static long long jint(json_t *j, const char *path)
{
	char buf[128], *save = NULL;
	json_t *v = j;

	snprintf(buf, sizeof(buf), "%s", path);
	for (char *k = strtok_r(buf, ".", &save); k && v;
	     k = strtok_r(NULL, ".", &save))
		v = json_object_get(v, k);
	if (json_is_integer(v))
		return (long long)json_integer_value(v);
	return -999999;
}

static double jreal(json_t *j, const char *path)
{
	char buf[128], *save = NULL;
	json_t *v = j;

	snprintf(buf, sizeof(buf), "%s", path);
	for (char *k = strtok_r(buf, ".", &save); k && v;
	     k = strtok_r(NULL, ".", &save))
		v = json_object_get(v, k);
	return json_is_number(v) ? json_number_value(v) : (double)NAN;
}

static const char *jstr(json_t *j, const char *key)
{
	json_t *v = json_object_get(j, key);

	return json_is_string(v) ? json_string_value(v) : "";
}

static bool file_has(const char *path, const char *text)
{
	FILE *f = fopen(path, "r");
	char line[1024];
	bool found = false;

	if (!f)
		return false;
	while (!found && fgets(line, sizeof(line), f))
		found = strstr(line, text) != NULL;
	fclose(f);
	return found;
}

static long lines_of(const char *path)
{
	FILE *f = fopen(path, "r");
	long n = 0;
	int ch;

	if (!f)
		return -1;
	while ((ch = fgetc(f)) != EOF)
		n += ch == '\n';
	fclose(f);
	return n;
}

static bool exists(const char *path)
{
	struct stat st;

	return stat(path, &st) == 0;
}

/* no temporary file left beside the capture */
static bool no_leftovers(void)
{
	char cmd[600];

	snprintf(cmd, sizeof(cmd), "ls %s | grep -q '\\.tmp\\.\\|\\.partial$'",
		 tmpdir);
	return system(cmd) != 0;
}

/* every row: values are those of the sample with counter c_i; returns the
 * number of rows that disagree */
static size_t check_rows(const struct sscope_capture *cap, uint16_t *cnt)
{
	size_t bad = 0;

	for (size_t i = 0; i < cap->n; i++) {
		uint16_t c = counter_of_gx(cap->channels[0].data[i]);
		int16_t raw[7];
		double want[6];

		raw_of(c, raw);
		for (int k = 0; k < 3; k++) {
			want[k] = raw[k] * GYRO_LSB;
			want[3 + k] = raw[3 + k] * ACCEL_LSB;
		}
		for (int k = 0; k < 6; k++) {
			double got = cap->channels[k].data[i];

			if (fabs(got - want[k]) > 1e-13 * fmax(1, fabs(want[k])))
				bad++;
		}
		if (!cap->temp_degc ||
		    fabs(cap->temp_degc[i] - raw[6] * TEMP_LSB) > 1e-12)
			bad++;
		if (cnt)
			cnt[i] = c;
	}
	return bad;
}

static struct sscope_capture *load(const char *path)
{
	struct sscope_capture *cap = NULL;
	struct sscope_diag d = { "" };

	if (sscope_capture_load(&cap, path, NULL, &d)) {
		note("cannot load %s: %s", path, d.msg);
		return NULL;
	}
	return cap;
}

static void fidelity(const char *what)
{
	tap(M.garbled == 0 && M.fast == 0,
	    "%s: the bus was driven in mode 3, 8 bits, MSB first, within the clock limits (garbled %u, too fast %u)",
	    what, M.garbled, M.fast);
	tap(M.no_stall == 0 && M.cs_tail == 0,
	    "%s: 16 us stall between register words, chip select released after each message (%u, %u)",
	    what, M.no_stall, M.cs_tail);
}

static void lockstep_exact(const char *fmt_opt, const char *file)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:25",
			    "--device", "adis16470", "--count", num(NS),
			    "--format", "json", "--capture-format", fmt_opt,
			    "-o", tpath(file), NULL };
	const double T = 0.0005;
	struct sscope_capture *cap;
	json_t *j;
	int rc;

	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 0, "lock-step %s: exit 0 (got %d)", fmt_opt, rc);
	if (rc)
		show_file(tpath("err"));
	j = summary();
	tap(j && jint(j, "samples") == NS && !strcmp(jstr(j, "stop"), "count"),
	    "lock-step %s: %u samples, stopped by count", fmt_opt, NS);
	tap(j && jint(j, "drops.total") == 0 && jint(j, "missing") == 0 &&
		    jint(j, "checksum_errors") == 0 && jint(j, "gaps") == 0,
	    "lock-step %s: no drop, no gap, no checksum error", fmt_opt);
	tap(j && jint(j, "interval.n") == NS - 1 &&
		    fabs(jreal(j, "interval.mean_s") - T) < 1e-15 &&
		    jreal(j, "interval.jitter_s") == 0 &&
		    fabs(jreal(j, "effective_rate_hz") - 2000) < 1e-9 &&
		    jreal(j, "nominal_rate_hz") == 2000,
	    "lock-step %s: %u intervals of exactly 500 us, jitter 0, 2000 Hz effective and nominal",
	    fmt_opt, NS - 1);
	json_decref(j);
	tap(M.bursts == NS && M.requested && M.req_line == DR_LINE &&
		    M.req_edges == 1 && !strcmp(M.consumer, "sensorscope"),
	    "lock-step %s: all bursts served, line 25 requested for rising edges by 'sensorscope' (%u bursts, edges %u, '%s')",
	    fmt_opt, M.bursts, M.req_edges, M.consumer);
	fidelity("lock-step");
	cap = load(tpath(file));
	tap(cap && cap->n == NS && cap->n_channels == 6 && cap->time_s &&
		    cap->temp_degc,
	    "lock-step %s: the capture loads with %u rows, 6 channels, time and temperature",
	    fmt_opt, NS);
	if (cap && cap->n == NS) {
		uint16_t cnt[500];
		size_t bad = check_rows(cap, cnt), seq = 0, tbad = 0;

		for (size_t i = 0; i < NS; i++) {
			seq += cnt[i] != (uint16_t)(C0 + i);
			tbad += fabs(cap->time_s[i] - (double)i * T) > 1e-12;
		}
		tap(bad == 0, "lock-step %s: every value equals the sample's raw word times its LSB (%zu differ)",
		    fmt_opt, bad);
		tap(seq == 0, "lock-step %s: rows are samples %u..65535,0,.. (DATA_CNTR wraps)",
		    fmt_opt, C0);
		tap(tbad == 0, "lock-step %s: time = k * 500 us from the data-ready time stamps",
		    fmt_opt);
		tap(!strcmp(cap->channels[0].col.name, "gx") &&
			    !strcmp(cap->channels[0].col.unit_label, "deg/s") &&
			    !strcmp(cap->channels[5].col.unit_label, "m/s^2"),
		    "lock-step %s: gx [deg/s] ... az [m/s^2]", fmt_opt);
	}
	sscope_capture_free(cap);
}

static void scenario_gap(void)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:25",
			    "--device", "adis16470", "--count", num(NG),
			    "--format", "json", "-o", tpath("gap.csv"), NULL };
	const long at = (long)NG / 3;
	struct sscope_capture *cap;
	json_t *j;
	int rc;

	s.gap_at = at;
	s.gap_len = 7;
	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 0, "counter gap: exit 0 (got %d)", rc);
	j = summary();
	tap(j && jint(j, "samples") == NG && jint(j, "drops.counter") == 7 &&
		    jint(j, "drops.total") == 7 && jint(j, "missing") == 7 &&
		    jint(j, "gaps") == 1,
	    "counter gap: exactly 7 drops reported, in 1 gap (drops %lld, missing %lld)",
	    j ? jint(j, "drops.total") : -1, j ? jint(j, "missing") : -1);
	tap(j && jint(j, "interval.n") == NG - 2,
	    "counter gap: the interval across the gap is left out of the jitter");
	json_decref(j);
	tap(file_has(tpath("gap.csv"),
		     "# gap: 7 samples missing before the next row (device counter)"),
	    "counter gap: marked in the capture");
	cap = load(tpath("gap.csv"));
	if (cap && cap->n == NG) {
		uint16_t cnt[300];
		size_t bad = check_rows(cap, cnt);
		struct sscope_timing tm;
		double scratch[299];

		tap(bad == 0 && cnt[at - 1] == (uint16_t)(C0 + at - 1) &&
			    cnt[at] == (uint16_t)(C0 + at + 7),
		    "counter gap: rows %ld and %ld are samples %u and %u, nothing interpolated",
		    at - 1, at, (uint16_t)(C0 + at - 1), (uint16_t)(C0 + at + 7));
		tap(fabs(cap->time_s[at] - (double)(at + 7) * 0.0005) < 1e-12,
		    "counter gap: the time column jumps by 8 periods");
		tap(sscope_timing_analyze(cap->time_s, cap->n, 1.5, &tm, NULL,
					  0, NULL, scratch) == 0 &&
			    tm.n_gaps == 1 && tm.n_missing == 7,
		    "counter gap: info finds the same gap of 7 in the time stamps");
	} else {
		tap(false, "counter gap: capture of %u rows", NG);
	}
	sscope_capture_free(cap);
}

static void scenario_checksum(void)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:25",
			    "--device", "adis16470", "--count", num(NC),
			    "--format", "json", "-o", tpath("crc.csv"), NULL };
	const long at = (long)NC / 4;
	struct sscope_capture *cap;
	json_t *j;
	int rc;

	s.bad_crc_at = at;
	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 0, "bad checksum: exit 0 (got %d)", rc);
	j = summary();
	tap(j && jint(j, "checksum_errors") == 1 && jint(j, "samples") == NC &&
		    jint(j, "drops.total") == 0,
	    "bad checksum: counted once, %u good samples, no device drop", NC);
	tap(j && jint(j, "missing") == 1 && jint(j, "gaps") == 1,
	    "bad checksum: the refused sample is one missing row");
	json_decref(j);
	tap(M.bursts == NC + 1, "bad checksum: %u bursts read (got %u)", NC + 1,
	    M.bursts);
	tap(file_has(tpath("crc.csv"),
		     "# gap: 1 sample missing before the next row (frames refused)"),
	    "bad checksum: marked in the capture");
	cap = load(tpath("crc.csv"));
	if (cap && cap->n == NC) {
		uint16_t cnt[200];
		size_t bad = check_rows(cap, cnt);

		tap(bad == 0 && cnt[at - 1] == (uint16_t)(C0 + at - 1) &&
			    cnt[at] == (uint16_t)(C0 + at + 1),
		    "bad checksum: skipped, not written (rows %ld, %ld are samples %u, %u)",
		    at - 1, at, (uint16_t)(C0 + at - 1), (uint16_t)(C0 + at + 1));
	} else {
		tap(false, "bad checksum: capture of %u rows", NC);
	}
	sscope_capture_free(cap);
}

static void scenario_timeout(void)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:25",
			    "--device", "adis16470", "--count", "10",
			    "--timeout", "0.3", "-o", tpath("to.csv"), NULL };
	int rc;

	s.pacing = P_SILENT;
	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 1, "data-ready timeout: exit 1 (got %d)", rc);
	tap(lines_of(tpath("err")) == 1 &&
		    file_has(tpath("err"),
			     "sensorscope: acquire: gpiochip0 line 25 (libgpiod v") &&
		    file_has(tpath("err"), "no data-ready edge within 0.3 s"),
	    "data-ready timeout: one clear line naming the line and the time");
	if (lines_of(tpath("err")) != 1)
		show_file(tpath("err"));
	tap(!exists(tpath("to.csv")) && no_leftovers(),
	    "data-ready timeout: no file, no temporary left");
}

static void scenario_prod_id(uint16_t id, const char *what,
			     const char *expect)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:25",
			    "--device", "adis16470", "--count", "10",
			    "-o", tpath("id.csv"), NULL };
	int rc;

	s.prod_id = id;
	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 1, "%s: exit 1 (got %d)", what, rc);
	tap(lines_of(tpath("err")) == 1 && file_has(tpath("err"), expect),
	    "%s: refused with '%s'", what, expect);
	if (!file_has(tpath("err"), expect))
		show_file(tpath("err"));
	tap(!exists(tpath("id.csv")) && M.bursts == 0 && !M.requested,
	    "%s: nothing read, no line requested, no file", what);
}

/* Consistency of a free-running capture: rows trace back to counters,
 * reported drops equal the counter discontinuities. */
static void consistency(const char *what, const char *file, json_t *j,
			double period, bool check_time)
{
	struct sscope_capture *cap = load(file);
	uint16_t *cnt;
	size_t bad, back = 0, tbad = 0;
	uint64_t disc = 0;

	if (!cap || !j) {
		tap(false, "%s: capture and summary", what);
		sscope_capture_free(cap);
		return;
	}
	cnt = calloc(cap->n, sizeof(*cnt));
	bad = check_rows(cap, cnt);
	for (size_t i = 1; i < cap->n; i++) {
		uint16_t d = (uint16_t)(cnt[i] - cnt[i - 1]);
		double dt = cap->time_s[i] - cap->time_s[0];
		double dc = (double)(uint16_t)(cnt[i] - cnt[0]) * period;

		if (d == 0 || d > 30000)
			back++;
		else
			disc += d - 1u;
		/* the burst after an edge may already hold the next sample */
		if (check_time && fabs(dt - dc) > 1.5 * period) {
			if (tbad < 5)
				note("row %zu: t %.6f, counter %u (from %u): %.6f", i, dt, cnt[i], cnt[0], dc);
			tbad++;
		}
	}
	tap((long long)cap->n == jint(j, "samples"),
	    "%s: rows = reported samples (%zu)", what, cap->n);
	tap(bad == 0 && back == 0,
	    "%s: every row is a sample of the device, counters strictly increase (%zu bad, %zu back)",
	    what, bad, back);
	tap((long long)disc == jint(j, "drops.counter") &&
		    (long long)disc == jint(j, "missing") &&
		    jint(j, "drops.ring") == 0,
	    "%s: reported drops = counter discontinuities (%llu vs %lld)",
	    what, (unsigned long long)disc, jint(j, "drops.counter"));
	if (check_time)
		tap(tbad == 0, "%s: time stamps agree with the counters within a period (%zu off)",
		    what, tbad);
	note("%s: %zu rows, %llu dropped, %lld repeats, %u edges lost in the 16-event queue",
	     what, cap->n, (unsigned long long)disc, jint(j, "repeats"),
	     M.queue_drops);
	free(cnt);
	sscope_capture_free(cap);
}

static void scenario_free(void)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:25",
			    "--device", "adis16470", "--count", num(NF),
			    "--format", "json", "-o", tpath("free.csv"), NULL };
	json_t *j;
	int rc;

	s.pacing = P_FREE;
	if (NF < 1000) { /* under valgrind: 200 Hz */
		s.period_ns = 5000000;
		s.dec_rate = 9;
	}
	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 0, "free-running: exit 0 (got %d)", rc);
	if (rc)
		show_file(tpath("err"));
	j = summary();
	consistency("free-running", tpath("free.csv"), j,
		    1e-9 * (double)s.period_ns, true);
	json_decref(j);
	fidelity("free-running");
}

/* A reader too slow at the start: every one of the first 30 bursts finds
 * the edge queue full, so each edge read is stale by several periods; the
 * time stamps must still follow the device counter from the first row. */
static void scenario_slow_start(void)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:25",
			    "--device", "adis16470", "--count", "300",
			    "--format", "json", "-o", tpath("slow.csv"), NULL };
	json_t *j;
	int rc;

	s.pacing = P_FREE;
	s.slow_bursts = 30;
	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 0, "slow start: exit 0 (got %d)", rc);
	if (rc)
		show_file(tpath("err"));
	j = summary();
	tap(M.queue_drops > 0, "slow start: the edge queue overflowed (%u edges lost)",
	    M.queue_drops);
	consistency("slow start", tpath("slow.csv"), j,
		    1e-9 * (double)s.period_ns, true);
	json_decref(j);
}

static void scenario_poll(void)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--device", "adis16470",
			    "--count", num(NP), "--format", "json",
			    "-o", tpath("poll.csv"), NULL };
	json_t *j;
	int rc;

	s.pacing = P_FREE;
	s.dec_rate = 3; /* 500 Hz; polled at 1 kHz */
	s.period_ns = 2000000;
	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 0, "polling (no data-ready line): exit 0 (got %d)", rc);
	if (rc)
		show_file(tpath("err"));
	j = summary();
	tap(j && strstr(jstr(j, "source"), "polled at 1000 Hz") &&
		    jreal(j, "nominal_rate_hz") == 500,
	    "polling: 500 Hz device (DEC_RATE 3) polled at 1 kHz");
	/* polled time stamps are read times: no exact relation to check */
	consistency("polling", tpath("poll.csv"), j, 0.002, false);
	json_decref(j);
	tap(!M.requested, "polling: no GPIO line requested");
	fidelity("polling");
}

static void scenario_rate_and_polarity(void)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:GPIO25",
			    "--device", "adis16470", "--rate", "200",
			    "--count", "50", "--format", "json",
			    "-o", tpath("rate.csv"), NULL };
	json_t *j;
	int rc;

	s.msc_ctrl = 0x00c0; /* DR active low: data ready on falling edges */
	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 0, "--rate 200, DR active low, line by name: exit 0 (got %d)", rc);
	if (rc)
		show_file(tpath("err"));
	j = summary();
	tap(M.dec_rate == 9 && M.req_edges == 2,
	    "--rate 200 wrote DEC_RATE 9; MSC_CTRL bit 0 clear made it wait for falling edges (DEC_RATE %u, edges %u)",
	    M.dec_rate, M.req_edges);
	tap(j && jint(j, "samples") == 50 && jreal(j, "nominal_rate_hz") == 200 &&
		    fabs(jreal(j, "interval.mean_s") - 0.005) < 1e-15,
	    "--rate 200: 50 samples 5 ms apart");
	json_decref(j);
	fidelity("--rate");
}

static void scenario_signal(void)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:25",
			    "--device", "adis16470", "--format", "json",
			    "-o", tpath("sig.csv"), NULL };
	struct sscope_capture *cap;
	json_t *j;
	int rc;

	start(&s);
	rc = acquire(a, NS, SIGTERM); /* once NS samples were read */
	stop();
	tap(rc == 0, "SIGTERM: clean exit 0 (got %d)", rc);
	if (rc)
		show_file(tpath("err"));
	j = summary();
	cap = load(tpath("sig.csv"));
	tap(j && !strcmp(jstr(j, "stop"), "signal") && cap &&
		    (long long)cap->n == jint(j, "samples") && cap->n > 0,
	    "SIGTERM: every sample read is in a valid file (%lld)",
	    j ? jint(j, "samples") : -1);
	if (cap && cap->n) {
		uint16_t *cnt = calloc(cap->n, sizeof(*cnt));
		size_t bad = check_rows(cap, cnt), seq = 0;

		for (size_t i = 0; i < cap->n; i++)
			seq += cnt[i] != (uint16_t)(C0 + i);
		tap(bad == 0 && seq == 0 && M.bursts == cap->n,
		    "SIGTERM: rows are samples 0..n-1 and every burst read was written (%u bursts)",
		    M.bursts);
		free(cnt);
	}
	tap(no_leftovers(), "SIGTERM: no temporary file left");
	json_decref(j);
	sscope_capture_free(cap);
}

static void scenario_not_built(void)
{
	struct scenario s = base;
	const char *a[] = { "--spi", "/dev/spidev0.0", "--drdy", "gpiochip0:25",
			    "--device", "adis16470", "--count", "10",
			    "-o", tpath("nb.csv"), NULL };
	int rc;

	start(&s);
	rc = acquire(a, 0, 0);
	stop();
	tap(rc == 2 && lines_of(tpath("err")) == 1 &&
		    file_has(tpath("err"), "built without") &&
		    file_has(tpath("err"), "libgpiod"),
	    "built without libgpiod: --drdy is refused with exit 2 and says why (got %d)",
	    rc);
	tap(M.regs == 0 && !exists(tpath("nb.csv")),
	    "built without libgpiod: no device touched, no file");
}

static bool have_tool(const char *name)
{
	char cmd[256];

	snprintf(cmd, sizeof(cmd), "command -v %s >/dev/null 2>&1", name);
	return system(cmd) == 0;
}

static void scenario_gpio_tools(void)
{
	struct scenario s = base;
	const char *info[] = { "gpioinfo", "gpiochip0", NULL };
	const char *mon[] = { "gpiomon", "--num-events=6", "--rising-edge",
			      "gpiochip0", "25", NULL };
	const char *both[] = { "gpiomon", "--num-events=4", "gpiochip0", "25",
			       NULL };
	int rc;

	if (!have_tool("gpioinfo") || !have_tool("gpiomon")) {
		skip("stock gpioinfo/gpiomon against the fake",
		     "gpiod tools not installed (Debian: gpiod)");
		return;
	}
	s.pacing = P_FREE;
	s.period_ns = 10000000; /* 100 Hz */
	start(&s);
	rc = run(false, info, tpath("tout"), tpath("terr"), 0, 0);
	tap(rc == 0 && file_has(tpath("tout"), "gpiochip0 - 32 lines:") &&
		    file_has(tpath("tout"), "\"GPIO25\""),
	    "gpioinfo lists the fake chip, its 32 lines and their names (exit %d)",
	    rc);
	if (rc)
		show_file(tpath("terr"));
	rc = run(false, mon, tpath("tout"), tpath("terr"), 0, 0);
	stop();
	{
		FILE *f = fopen(tpath("tout"), "r");
		char line[256];
		int n = 0, good = 0;
		double prev = 0;

		while (f && fgets(line, sizeof(line), f)) {
			double t;

			n++;
			if (sscanf(line, "event:  RISING EDGE offset: 25 timestamp: [ %lf]", &t) == 1 &&
			    (n == 1 || fabs(t - prev - 0.01) < 0.005))
				good++;
			prev = t;
		}
		if (f)
			fclose(f);
		tap(rc == 0 && n == 6 && good == 6,
		    "gpiomon --rising-edge reads 6 rising edges of line 25, 10 ms apart (exit %d, %d lines, %d good)",
		    rc, n, good);
		tap(!strcmp(M.consumer, "gpiomon") && M.req_edges == 1,
		    "gpiomon requested rising edges as 'gpiomon'");
	}
	start(&s);
	rc = run(false, both, tpath("tout"), tpath("terr"), 0, 0);
	stop();
	tap(rc == 0 && lines_of(tpath("tout")) == 4 &&
		    file_has(tpath("tout"), "RISING EDGE") &&
		    file_has(tpath("tout"), "FALLING EDGE") && M.req_edges == 3,
	    "gpiomon on both edges sees the rising and the falling edge of each pulse");
}

/* ------------------------------------------------------------ setup */

static bool add_node(UMockdevTestbed *tb, const char *subsystem,
		     const char *name, const char *devt, const char *node,
		     GCallback handler)
{
	gchar *sys = umockdev_testbed_add_device(tb, subsystem, name, NULL,
						 "dev", devt, NULL, "DEVNAME",
						 node, NULL);
	gchar *root = umockdev_testbed_get_root_dir(tb);
	char path[512];
	UMockdevIoctlBase *h;
	GError *err = NULL;
	bool ok;

	/* the node itself: a plain file (its stat is faked as a char
	 * device from the "dev" attribute) */
	snprintf(path, sizeof(path), "%s%s", root, node);
	ok = sys && g_file_set_contents(path, "", 0, NULL);
	g_free(sys);
	g_free(root);
	if (!ok)
		return false;
	h = umockdev_ioctl_base_new();
	g_signal_connect(h, "handle-ioctl", handler, NULL);
	ok = umockdev_testbed_attach_ioctl(tb, node, h, &err);
	if (!ok) {
		note("attach_ioctl %s: %s", node, err ? err->message : "?");
		g_clear_error(&err);
	}
	g_object_unref(h);
	return ok;
}

int main(void)
{
	UMockdevTestbed *tb;
	char cmd[600], ver[256] = "";
	bool gpiod;
	FILE *p;

	sscope = getenv("SSCOPE");
	if (!sscope || access(sscope, X_OK)) {
		printf("1..0 # SKIP SSCOPE does not name the sensorscope binary\n");
		return 0;
	}
	snprintf(cmd, sizeof(cmd), "%s --version", sscope);
	p = popen(cmd, "r");
	if (!p || !fgets(ver, sizeof(ver), p)) {
		printf("Bail out! cannot run %s --version\n", sscope);
		return 1;
	}
	pclose(p);
	gpiod = strstr(ver, "acquisition: libgpiod") != NULL;
	if (getenv("SSCOPE_RUN") && *getenv("SSCOPE_RUN")) {
		NS = 100;
		NG = 100;
		NC = 60;
		NF = 200;
		NP = 100;
	}
	C0 = (uint16_t)(65536 - NS / 2); /* DATA_CNTR wraps mid-run */
	for (uint32_t i = 1; i < 65536; i += 2)
		if ((uint16_t)(i * GX_MUL) == 1) {
			gx_inverse = (uint16_t)i;
			break;
		}
	snprintf(tmpdir, sizeof(tmpdir), "%s/sscope-acq.XXXXXX",
		 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (!mkdtemp(tmpdir)) {
		printf("Bail out! mkdtemp: %s\n", strerror(errno));
		return 1;
	}
	tb = umockdev_testbed_new();
	if (!tb || !add_node(tb, "gpio", "gpiochip0", "254:0\n", "/dev/gpiochip0",
			     G_CALLBACK(on_gpio)) ||
	    !add_node(tb, "spidev", "spidev0.0", "153:0\n", "/dev/spidev0.0",
		      G_CALLBACK(on_spi))) {
		printf("1..0 # SKIP umockdev cannot emulate the devices here\n");
		return 0;
	}
	note("%s", ver);
	note("fake devices in %s", getenv("UMOCKDEV_DIR"));

	if (gpiod) {
		scenario_gpio_tools();
		lockstep_exact("csv", "ls.csv");
		lockstep_exact("f64", "ls.bin");
		scenario_gap();
		scenario_checksum();
		scenario_timeout();
		scenario_prod_id(16465, "wrong product ID",
				 "PROD_ID is 16465: this is an ADIS16465, not an adis16470; refusing");
		scenario_prod_id(0xffff, "silent device",
				 "no answer from the device (PROD_ID reads 0xffff)");
		scenario_rate_and_polarity();
		scenario_free();
		scenario_slow_start();
		scenario_signal();
	} else {
		note("sensorscope built without libgpiod: data-ready scenarios replaced by the not-built check");
		scenario_gpio_tools();
		scenario_not_built();
	}
	scenario_poll();

	printf("1..%d\n", tap_n);
	g_object_unref(tb);
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", tmpdir);
	if (system(cmd))
		return 0;
	return 0;
}
