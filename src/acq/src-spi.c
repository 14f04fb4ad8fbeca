/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * SPI sources: an ADIS1646x/1647x IMU (burst reads, DATA_CNTR, DIAG_STAT,
 * PROD_ID check; adc/sscope-adis.h) or a generic converter frame
 * (adc/sscope-spiadc.h), paced by a data-ready GPIO line (drdy.c) or, as
 * the documented fallback without one, by polling on the monotonic clock.
 *
 * ADIS protocol (data sheet): SPI mode 3, register access at most 2 MHz
 * with a 16 us stall between 16-bit words, burst reads at most 1 MHz.
 * Polling an ADIS: reads at twice its output rate, frames whose DATA_CNTR
 * did not advance are discarded as repeats, so the capture holds each
 * sample once with the time of the read (accurate to the poll period).
 * Polling a converter: the poll tick is the sample clock; late ticks are
 * counted as lost samples.
 *
 * Stale edges: the time stamp of the last queued edge belongs to the
 * sample read next -- unless newer edges never reached the queue (the v1
 * kernel queue holds 16 events and drops newer ones) or an edge came
 * between reading the events and the burst.  The device counter shows
 * it: when DATA_CNTR advanced by more steps than the edge time stamps
 * account for (round(dt / T)), the sample is that many periods newer than
 * the edge, and its time stamp is the edge's plus those whole periods of
 * the device clock.  Such corrections are counted (time_estimated).  The
 * chain starts from the first ANCHOR_N samples, held back until their
 * common offset to the device clock is known (see anchor()); while no
 * held edge is known fresh (one new edge since the last read and the next
 * counter value: a reader keeping up), the oldest is let go and the
 * capture starts later.
 */
#include "acq.h"
#include "drdy.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BAD_RUN_LIMIT 50 /* consecutive refused frames: give up */
#define ANCHOR_N 8       /* samples held to anchor the time stamps */
#define ANCHOR_SLIDES 1000 /* samples skipped at most waiting for a fresh edge */

struct spisrc {
	struct ssc_spi spi;
	struct ssc_drdy *drdy;
	const struct sscope_adis_model *model; /* NULL: converter frame */
	struct sscope_spiadc_frame frame;
	uint32_t burst_speed_hz;
	/* pacing without a data-ready line */
	double poll_hz;
	int64_t next_tick;
	bool started;
	uint64_t ticks_lost;        /* lost before the coming sample */
	/* counter bookkeeping (ADIS) */
	bool have_cnt;
	uint16_t last_cnt;
	int64_t last_t;
	int64_t last_progress;
	uint64_t rejected;          /* refused since the last good frame */
	unsigned bad_run;
	bool last_full;             /* the last event read found a full queue */
	unsigned anchor_tries;
	unsigned anchor_slides;
	/* the first samples, held until their time stamps are anchored */
	bool anchored;
	size_t n_hold, pos_out;
	struct held {
		struct ssc_acq_sample s;
		uint64_t u;             /* counter steps since the first */
		uint64_t lost;          /* counted in counter_missing */
		bool fresh;             /* its edge is its own, not a stale one */
	} hold[ANCHOR_N];
};

/* ---------------------------------------------------------------- pacing */

/* Wait for the next data-ready edge or poll tick; *t its time stamp. */
static int wait_ready(struct ssc_source *src, struct spisrc *p, int64_t *t,
		      struct sscope_diag *diag)
{
	if (p->drdy) {
		struct ssc_drdy_events ev;
		int r;

		r = ssc_wait_fd(ssc_drdy_fd(p->drdy), src->stop_fd,
				src->timeout_s);

		if (r == 0)
			return ssc_acq_diag(diag, -ETIMEDOUT,
					    "%s: no data-ready edge within %g s "
					    "(check the DR wire, the line, the edge and that the device runs)",
					    ssc_drdy_name(p->drdy), src->timeout_s);
		if (r < 0)
			return r == -ECANCELED
				       ? r
				       : ssc_acq_diag(diag, r, "%s: %s",
						      ssc_drdy_name(p->drdy),
						      sscope_strerror(-r));
		r = ssc_drdy_read(p->drdy, &ev);
		if (r < 0)
			return ssc_acq_diag(diag, r, "%s: reading events: %s",
					    ssc_drdy_name(p->drdy),
					    sscope_strerror(-r));
		if (ev.n == 0)
			return -EAGAIN;
		if (!p->started) {
			p->started = true;
			/* a full queue at the start holds edges from the
			 * set-up and may have dropped the newest: the last
			 * time stamp would be stale, start from the next */
			if (ev.full)
				return -EAGAIN;
		}
		p->last_full = ev.full;
		/* edges queued before the last one were never served */
		p->ticks_lost = ev.lost + ev.n - 1;
		src->counts.events_lost += p->ticks_lost;
		*t = ev.t_ns;
		return 0;
	} else {
		int64_t period = llround(1e9 / p->poll_hz), now, late;

		if (!p->started) {
			p->next_tick = ssc_now_ns();
			p->started = true;
		}
		if (ssc_sleep_until(p->next_tick, src->stop_fd))
			return -ECANCELED;
		now = ssc_now_ns();
		late = now - p->next_tick;
		if (late > src->counts.late_max_s * 1e9)
			src->counts.late_max_s = 1e-9 * (double)late;
		src->counts.late_sum2_s2 += 1e-18 * (double)late * (double)late;
		src->counts.late_n++;
		/* ticks that passed while we were late are lost samples */
		p->ticks_lost = late > period ? (uint64_t)(late / period) : 0;
		src->counts.events_lost += p->ticks_lost;
		p->next_tick += period * (int64_t)(p->ticks_lost + 1);
		*t = now;
		return 0;
	}
}

/* ---------------------------------------------------------------- ADIS */

static int adis_read_reg(struct spisrc *p, uint8_t reg, uint16_t *val)
{
	uint8_t tx[2], rx[2] = { 0, 0 };
	const struct ssc_spi_seg seg[2] = {
		{ .tx = tx, .len = 2, .cs_change = true, .delay_us = 16 },
		{ .rx = rx, .len = 2, .delay_us = 16 },
	};
	int rc;

	sscope_adis_read_cmd(reg, tx);
	rc = ssc_spi_message(&p->spi, seg, 2);
	*val = (uint16_t)((unsigned)rx[0] << 8 | rx[1]);
	return rc;
}

static int adis_write_reg(struct spisrc *p, uint8_t reg, uint16_t val)
{
	uint8_t tx[4];
	const struct ssc_spi_seg seg[2] = {
		{ .tx = tx, .len = 2, .cs_change = true, .delay_us = 16 },
		{ .tx = tx + 2, .len = 2, .delay_us = 16 },
	};

	sscope_adis_write_cmd(reg, val, tx);
	return ssc_spi_message(&p->spi, seg, 2);
}

static int adis_read(struct ssc_source *src, struct ssc_acq_sample *s,
		     struct sscope_diag *diag)
{
	struct spisrc *p = src->priv;
	/* writable buffers only: ioctl emulators may copy them back */
	uint8_t cmd[2] = { SSCOPE_ADIS_BURST_CMD >> 8,
			   SSCOPE_ADIS_BURST_CMD & 0xff };
	uint8_t rx[SSCOPE_ADIS_BURST_BYTES] = { 0 };
	const struct ssc_spi_seg seg[2] = {
		{ .tx = cmd, .len = 2, .speed_hz = p->burst_speed_hz },
		{ .rx = rx, .len = SSCOPE_ADIS_BURST_BYTES,
		  .speed_hz = p->burst_speed_hz },
	};
	struct sscope_adis_sample a;
	int64_t t;
	long gap;
	uint64_t refused;
	int rc = wait_ready(src, p, &t, diag);

	if (rc)
		return rc;
	if (!p->last_progress)
		p->last_progress = t;
	rc = ssc_spi_message(&p->spi, seg, 2);
	if (rc)
		return ssc_acq_diag(diag, rc, "%s: burst read: %s", p->spi.path,
				    sscope_strerror(-rc));
	src->counts.frames++;
	if (sscope_adis_decode(p->model, rx, &a)) {
		src->counts.checksum_errors++;
		p->rejected++;
		if (++p->bad_run >= BAD_RUN_LIMIT)
			return ssc_acq_diag(diag, -EIO,
					    "%s: the last %d bursts all failed their checksum "
					    "(check SPI mode 3, a clock of at most 1 MHz and the wiring)",
					    p->spi.path, BAD_RUN_LIMIT);
		return -EAGAIN;
	}
	p->bad_run = 0;
	if (!p->have_cnt && p->drdy && p->last_full &&
	    ++p->anchor_tries < 100)
		return -EAGAIN; /* a full queue's last edge may be old */
	if (!p->have_cnt) {
		s->missing = 0;
		p->rejected = 0;
	} else {
		gap = ssc_gap_from_counter(p->last_cnt, a.data_cntr,
					   1e-9 * (double)(t - p->last_t),
					   1.0 / src->info.rate_hz);
		if (gap < 0) {
			/* the same sample again: a poll faster than the
			 * output rate, or a spurious edge */
			src->counts.duplicates++;
			if (1e-9 * (double)(t - p->last_progress) >
			    src->timeout_s)
				return ssc_acq_diag(diag, -ETIMEDOUT,
						    "%s: DATA_CNTR has not advanced for %g s "
						    "(is the device in standby or the clock stopped?)",
						    p->spi.path, src->timeout_s);
			return -EAGAIN;
		}
		if (p->drdy && p->anchored && src->info.rate_hz > 0) {
			double T = 1.0 / src->info.rate_hz;
			double by_time = nearbyint(1e-9 * (double)(t - p->last_t) / T);

			if ((double)gap + 1 > by_time) {
				t += llround(((double)gap + 1 - by_time) * T * 1e9);
				src->counts.time_estimated++;
			}
		}
		refused = p->rejected < (uint64_t)gap ? p->rejected
						     : (uint64_t)gap;
		src->counts.counter_missing += (uint64_t)gap - refused;
		s->missing = gap > UINT32_MAX ? UINT32_MAX : (uint32_t)gap;
		s->cause = (uint16_t)(((uint64_t)gap > refused ? SSC_GAP_COUNTER : 0) |
				      (refused ? SSC_GAP_REJECTED : 0));
		p->rejected = 0;
	}
	p->have_cnt = true;
	p->last_cnt = a.data_cntr;
	p->last_t = t;
	p->last_progress = t;
	s->t_ns = t;
	s->status = a.diag_stat;
	if (a.diag_stat) {
		src->counts.status_samples++;
		src->counts.status_or |= a.diag_stat;
	}
	for (int k = 0; k < 3; k++) {
		s->v[k] = a.gyro_rad_s[k];
		s->v[3 + k] = a.accel_m_s2[k];
	}
	s->temp_degc = a.temp_degc;
	return 0;
}

/*
 * Anchor the time stamps of the held first samples.  A sample is never
 * older than the edge read before its burst, so each observation gives a
 * lower bound t_edge - u T on the offset of the device clock (u: counter
 * steps since the first sample); the largest bound is exact as soon as
 * one of the held observations was fresh.  Samples whose edge time lies
 * more than half a period below offset + u T get that time instead.
 */
static void anchor(struct ssc_source *src, struct spisrc *p)
{
	double T = 1e9 / src->info.rate_hz, off = -INFINITY;

	for (size_t j = 0; j < p->n_hold; j++) {
		double o = (double)p->hold[j].s.t_ns - (double)p->hold[j].u * T;

		if (o > off)
			off = o;
	}
	for (size_t j = 0; j < p->n_hold; j++) {
		double est = off + (double)p->hold[j].u * T;

		if ((double)p->hold[j].s.t_ns < est - 0.5 * T) {
			p->hold[j].s.t_ns = llround(est);
			src->counts.time_estimated++;
		}
	}
	p->anchored = true;
	if (p->n_hold)
		p->last_t = p->hold[p->n_hold - 1].s.t_ns;
}

/* whether one of the held edges is known fresh: its time stamp is then
 * the sample's own, which anchors the rest */
static bool any_fresh(const struct spisrc *p)
{
	for (size_t j = 0; j < p->n_hold; j++)
		if (p->hold[j].fresh)
			return true;
	return false;
}

static int adis_next(struct ssc_source *src, struct ssc_acq_sample *s,
		     struct sscope_diag *diag)
{
	struct spisrc *p = src->priv;
	struct held *h;
	uint64_t lost0;
	int rc;

	if (p->anchored && p->pos_out < p->n_hold) {
		*s = p->hold[p->pos_out++].s;
		return 0;
	}
	lost0 = src->counts.counter_missing;
	rc = adis_read(src, s, diag);
	if (rc || !p->drdy || p->anchored)
		return rc;
	h = &p->hold[p->n_hold];
	h->s = *s;
	h->u = p->n_hold ? p->hold[p->n_hold - 1].u + s->missing + 1 : 0;
	h->lost = src->counts.counter_missing - lost0;
	/* one new edge since the last read and the counter value after the
	 * last held sample's: the reader keeps up, so the edge is this
	 * sample's own (had the burst come after a newer edge, that edge
	 * would be queued at the next read; a first sample has no such
	 * check, its burst may have come late) */
	h->fresh = p->n_hold > 0 && !p->last_full && p->ticks_lost == 0 &&
		   s->missing == 0;
	if (++p->n_hold < ANCHOR_N)
		return -EAGAIN;
	if (!any_fresh(p) && p->anchor_slides++ < ANCHOR_SLIDES) {
		/* every held edge may be stale: the capture starts one
		 * sample later, so the oldest is not a row and the gap
		 * before the new first one is not a loss */
		memmove(&p->hold[0], &p->hold[1], (ANCHOR_N - 1) * sizeof(p->hold[0]));
		p->n_hold--;
		src->counts.counter_missing -= p->hold[0].lost;
		p->hold[0].lost = 0;
		p->hold[0].s.missing = 0;
		p->hold[0].s.cause = 0;
		return -EAGAIN;
	}
	anchor(src, p);
	*s = p->hold[0].s;
	p->pos_out = 1;
	return 0;
}

static int adis_flush(struct ssc_source *src, struct ssc_acq_sample *s)
{
	struct spisrc *p = src->priv;

	if (!p->anchored && p->n_hold)
		anchor(src, p);
	if (p->pos_out < p->n_hold) {
		*s = p->hold[p->pos_out++].s;
		return 0;
	}
	return -ENODATA;
}

static const char *adis_known(uint16_t id)
{
	for (size_t i = 0; sscope_adis_model_at(i); i++)
		if (sscope_adis_model_at(i)->prod_id == id)
			return sscope_adis_model_at(i)->name;
	return NULL;
}

static int adis_setup(struct ssc_source *src, struct spisrc *p,
		      const struct ssc_spi_opts *o, struct sscope_diag *diag)
{
	uint32_t reg_speed = o->speed_hz ? o->speed_hz : 1000000;
	uint16_t id, dec, msc;
	int rc;

	if (reg_speed > 2000000)
		reg_speed = 2000000;
	p->burst_speed_hz = reg_speed > 1000000 ? 1000000 : reg_speed;
	rc = ssc_spi_open(&p->spi, o->spi, 3, reg_speed, diag);
	if (rc)
		return rc;
	rc = adis_read_reg(p, SSCOPE_ADIS_REG_PROD_ID, &id);
	if (rc)
		return ssc_acq_diag(diag, rc, "%s: reading PROD_ID: %s", o->spi,
				    sscope_strerror(-rc));
	if (id != p->model->prod_id) {
		const char *other = adis_known(id);

		if (id == 0x0000 || id == 0xffff)
			return ssc_acq_diag(diag, -ENODEV,
					    "%s: no answer from the device (PROD_ID reads 0x%04x): "
					    "check power, wiring and chip select",
					    o->spi, id);
		if (other) {
			char base[16];
			const char *dash = strchr(other, '-');

			snprintf(base, sizeof(base), "%.*s",
				 (int)(dash ? dash - other : (long)strlen(other)),
				 other);
			return ssc_acq_diag(diag, -ENODEV,
					    "%s: PROD_ID is %u: this is an ADIS%u, not an %s; "
					    "refusing to decode it with the wrong scale factors "
					    "(give --device %s%s)",
					    o->spi, id, id, p->model->name, base,
					    dash ? "-1, -2 or -3 as fitted" : "");
		}
		return ssc_acq_diag(diag, -ENODEV,
				    "%s: PROD_ID is %u (0x%04x), not %u: not an %s; refusing",
				    o->spi, id, id, p->model->prod_id,
				    p->model->name);
	}
	if (o->rate_hz > 0) {
		rc = sscope_adis_dec_rate(p->model, o->rate_hz, &dec);
		if (rc)
			return ssc_acq_diag(diag, -EINVAL,
					    "--rate: an %s outputs %g Hz / (DEC_RATE + 1); %g Hz is not one "
					    "of those rates (nearest: %g Hz)",
					    p->model->name, p->model->clock_hz,
					    o->rate_hz,
					    sscope_adis_rate_hz(p->model, dec));
		rc = adis_write_reg(p, SSCOPE_ADIS_REG_DEC_RATE, dec);
		if (rc)
			return ssc_acq_diag(diag, rc, "%s: writing DEC_RATE: %s",
					    o->spi, sscope_strerror(-rc));
	}
	rc = adis_read_reg(p, SSCOPE_ADIS_REG_DEC_RATE, &dec);
	if (!rc)
		rc = adis_read_reg(p, SSCOPE_ADIS_REG_MSC_CTRL, &msc);
	if (rc)
		return ssc_acq_diag(diag, rc, "%s: reading registers: %s",
				    o->spi, sscope_strerror(-rc));
	if (dec > 1999)
		return ssc_acq_diag(diag, -EIO, "%s: DEC_RATE reads %u (> 1999)",
				    o->spi, dec);
	if (o->rate_hz > 0 &&
	    fabs(sscope_adis_rate_hz(p->model, dec) - o->rate_hz) >
		    1e-9 * o->rate_hz)
		return ssc_acq_diag(diag, -EIO,
				    "%s: DEC_RATE reads %u after writing it: the write did not take",
				    o->spi, dec);
	src->info.rate_hz = sscope_adis_rate_hz(p->model, dec);
	if (o->drdy) {
		/* MSC_CTRL bit 0: DR polarity, 1 = active high (rising) */
		bool falling = o->drdy_edge ? o->drdy_edge < 0 : !(msc & 1);

		rc = ssc_drdy_open(&p->drdy, o->drdy, falling, "sensorscope",
				   diag);
		if (rc)
			return rc;
	} else {
		p->poll_hz = 2 * src->info.rate_hz;
	}
	for (int k = 0; k < 6; k++) {
		static const char *const n[6] = { "gx", "gy", "gz",
						  "ax", "ay", "az" };

		snprintf(src->info.name[k], sizeof(src->info.name[k]), "%s",
			 n[k]);
		snprintf(src->info.unit[k], sizeof(src->info.unit[k]), "%s",
			 k < 3 ? "deg/s" : "m/s^2");
	}
	src->info.n_channels = 6;
	src->info.has_temp = true;
	src->info.has_counter = true;
	if (p->drdy)
		snprintf(src->info.desc, sizeof(src->info.desc),
			 "%s on %s, data ready %s, %g Hz (DEC_RATE %u)",
			 p->model->name, o->spi, ssc_drdy_name(p->drdy),
			 src->info.rate_hz, dec);
	else
		snprintf(src->info.desc, sizeof(src->info.desc),
			 "%s on %s, polled at %g Hz (no data-ready line), %g Hz (DEC_RATE %u)",
			 p->model->name, o->spi, p->poll_hz, src->info.rate_hz,
			 dec);
	return 0;
}

/* ---------------------------------------------------------------- frames */

static int frame_next(struct ssc_source *src, struct ssc_acq_sample *s,
		      struct sscope_diag *diag)
{
	struct spisrc *p = src->priv;
	const struct sscope_spiadc_frame *f = &p->frame;
	struct ssc_spi_seg seg[SSCOPE_SPIADC_MAX_XFERS];
	uint8_t rx[SSCOPE_SPIADC_MAX_BYTES] = { 0 };
	size_t off = 0;
	int64_t t;
	int rc = wait_ready(src, p, &t, diag);

	if (rc)
		return rc;
	memset(seg, 0, sizeof(seg));
	for (size_t i = 0; i < f->n_xfers; i++) {
		seg[i].tx = f->tx + off;
		seg[i].rx = rx + off;
		seg[i].len = (uint32_t)f->xfer_len[i];
		seg[i].cs_change = i + 1 < f->n_xfers;
		off += f->xfer_len[i];
	}
	rc = ssc_spi_message(&p->spi, seg, f->n_xfers);
	if (rc)
		return ssc_acq_diag(diag, rc, "%s: frame: %s", p->spi.path,
				    sscope_strerror(-rc));
	src->counts.frames++;
	sscope_spiadc_decode(f, rx, s->v, NULL);
	s->t_ns = t;
	if (p->ticks_lost) {
		s->missing = p->ticks_lost > UINT32_MAX ? UINT32_MAX
							: (uint32_t)p->ticks_lost;
		s->cause = SSC_GAP_EVENTS;
	}
	return 0;
}

static int frame_setup(struct ssc_source *src, struct spisrc *p,
		       const struct ssc_spi_opts *o, const char *spec,
		       struct sscope_diag *diag)
{
	struct sscope_diag d = { "" };
	uint32_t speed;
	int rc = sscope_spiadc_parse(spec, &p->frame, &d);

	if (rc)
		return ssc_acq_diag(diag, rc, "--device spiadc: %s", d.msg);
	if (!o->drdy && !(o->rate_hz > 0))
		return ssc_acq_diag(diag, -EINVAL,
				    "--device spiadc: give --drdy CHIP:LINE or --rate HZ (the poll rate)");
	speed = p->frame.speed_hz;
	if (o->speed_hz && o->speed_hz < speed)
		speed = o->speed_hz;
	rc = ssc_spi_open(&p->spi, o->spi, p->frame.mode, speed, diag);
	if (rc)
		return rc;
	if (o->drdy) {
		rc = ssc_drdy_open(&p->drdy, o->drdy, o->drdy_edge < 0,
				   "sensorscope", diag);
		if (rc)
			return rc;
	} else {
		p->poll_hz = o->rate_hz;
	}
	src->info.n_channels = p->frame.n_channels;
	for (size_t k = 0; k < p->frame.n_channels; k++) {
		snprintf(src->info.name[k], sizeof(src->info.name[k]), "%s",
			 p->frame.ch[k].name);
		snprintf(src->info.unit[k], sizeof(src->info.unit[k]), "%s",
			 p->frame.ch[k].unit);
	}
	src->info.rate_hz = o->rate_hz > 0 ? o->rate_hz : 0;
	if (p->drdy)
		snprintf(src->info.desc, sizeof(src->info.desc),
			 "SPI converter frame on %s (mode %u, %u Hz clock), data ready %s",
			 o->spi, p->frame.mode, speed, ssc_drdy_name(p->drdy));
	else
		snprintf(src->info.desc, sizeof(src->info.desc),
			 "SPI converter frame on %s (mode %u, %u Hz clock), polled at %g Hz",
			 o->spi, p->frame.mode, speed, p->poll_hz);
	return 0;
}

/* ---------------------------------------------------------------- open */

static void spi_close(struct ssc_source *src)
{
	struct spisrc *p = src->priv;

	if (p) {
		ssc_drdy_close(p->drdy);
		ssc_spi_close(&p->spi);
	}
	free(p);
	free(src);
}

static const struct ssc_source_ops adis_ops = { adis_next, adis_flush,
						spi_close };
static const struct ssc_source_ops frame_ops = { frame_next, NULL, spi_close };

int ssc_source_spi_open(struct ssc_source **out, const struct ssc_spi_opts *o,
			struct sscope_diag *diag)
{
	struct ssc_source *src;
	struct spisrc *p;
	int rc;

	*out = NULL;
	if (!o->spi || !o->device)
		return ssc_acq_diag(diag, -EINVAL,
				    "need --spi DEVICE and --device NAME");
	if (o->drdy && !ssc_drdy_available()) {
		struct ssc_drdy *d;

		return ssc_drdy_open(&d, o->drdy, false, "sensorscope", diag);
	}
	src = calloc(1, sizeof(*src));
	p = calloc(1, sizeof(*p));
	if (!src || !p) {
		free(src);
		free(p);
		return -ENOMEM;
	}
	p->spi.fd = -1;
	src->priv = p;
	src->stop_fd = -1;
	if (!strncmp(o->device, "spiadc:", 7)) {
		src->ops = &frame_ops;
		rc = frame_setup(src, p, o, o->device + 7, diag);
	} else {
		p->model = sscope_adis_find(o->device);
		src->ops = &adis_ops;
		if (!p->model)
			rc = ssc_acq_diag(diag, -EINVAL,
					  "--device: unknown device '%s' (adis16470, adis16465-1/2/3, "
					  "adis16467-1/2/3, adis16475-1/2/3, adis16477-1/2/3, or spiadc:FRAME)",
					  o->device);
		else
			rc = adis_setup(src, p, o, diag);
	}
	if (rc) {
		spi_close(src);
		return rc;
	}
	*out = src;
	return 0;
}
