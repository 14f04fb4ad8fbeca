/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The "sim:" source: a simulated 6-axis IMU paced by the monotonic clock
 * (or unpaced), so that the whole acquisition path -- reader thread,
 * ring, writer, live view, summary -- runs anywhere without hardware.
 * Time stamps are the nominal k / rate; the pacing lateness is counted
 * separately.  Rates above 1 kHz (times the speed) are paced in batches of
 * 1 ms, like a device with a FIFO.  Unpaced (speed=max), it waits for the
 * writer when the ring is full (can_wait): a file gets every sample.  Values come from the library's sensor
 * simulator (analysis/sscope-sim.h, the model behind `sensorscope
 * simulate`): one stream per channel of the seed, white noise of density N
 * (so the Allan deviation of the capture is N / sqrt(tau), IEEE Std 952
 * Annex C) around a constant true input, and for the gyros optionally
 * bias instability B (bi) and rate random walk K (rrw).
 */
#include "acq.h"
#include "ssc.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


#define BLOCK 256
#define G0 SSCOPE_UNIT_GRAVITY_STD

struct sim {
	struct sscope_sim *sim[6];
	double input_block[6][BLOCK]; /* the true input, constant */
	double rate_hz;
	double speed;          /* 0: unpaced */
	int64_t period_ns;     /* of the pacing */
	size_t n_ch;
	double temp_degc;
	double block[6][BLOCK];
	double temp[BLOCK];
	size_t pos;            /* next unread index in the block */
	uint64_t k;            /* samples produced */
	int64_t start_ns;
};

/* n samples per channel into s->block, and their temperatures */
static void sim_generate(struct sim *s, size_t n)
{
	for (size_t c = 0; c < s->n_ch; c++)
		sscope_sim_generate(s->sim[c], s->input_block[c], s->block[c],
				    c == 0 ? s->temp : NULL, n);
}

static int sim_next(struct ssc_source *src, struct ssc_acq_sample *smp,
		    struct sscope_diag *diag)
{
	struct sim *s = src->priv;

	(void)diag;
	if (s->pos == BLOCK) {
		sim_generate(s, BLOCK);
		s->pos = 0;
	}
	if (s->k == 0)
		s->start_ns = ssc_now_ns();
	if (s->speed > 0) {
		int64_t due = s->start_ns +
			      llround((double)s->k * 1e9 / (s->rate_hz * s->speed));
		int64_t now = ssc_now_ns();
		double late;

		/* periods under a millisecond are paced in 1 ms batches: a
		 * wake-up per sample would cost more than the sample */
		if (due - now > (s->period_ns < 1000000 ? 1000000 - s->period_ns
							 : 0)) {
			if (ssc_sleep_until(due, src->stop_fd))
				return -ECANCELED;
			now = ssc_now_ns();
		}
		late = now > due ? 1e-9 * (double)(now - due) : 0;
		if (late > src->counts.late_max_s)
			src->counts.late_max_s = late;
		src->counts.late_sum2_s2 += late * late;
		src->counts.late_n++;
	}
	smp->t_ns = llround((double)s->k * 1e9 / s->rate_hz);
	for (size_t c = 0; c < s->n_ch; c++)
		smp->v[c] = s->block[c][s->pos];
	smp->temp_degc = s->temp[s->pos];
	s->pos++;
	s->k++;
	src->counts.frames++;
	return 0;
}

static void sim_close(struct ssc_source *src)
{
	struct sim *s = src->priv;

	if (s)
		for (size_t c = 0; c < 6; c++)
			sscope_sim_free(s->sim[c]);
	free(s);
	free(src);
}

static const struct ssc_source_ops sim_ops = { sim_next, NULL, sim_close };

static int opt_quantity(const char *key, const char *v, const char *si,
			double *out, struct sscope_diag *diag)
{
	struct sscope_unit u, want;
	double x;

	sscope_unit_parse(si, &want, NULL);
	if (sscope_quantity_parse(v, &x, &u, NULL) || !isfinite(x) || x < 0)
		return ssc_acq_diag(diag, -EINVAL,
				    "sim: %s: '%s' is not a non-negative quantity",
				    key, v);
	if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS)
		x = sscope_unit_to_si(&want, x); /* bare number: SI */
	else if (!sscope_unit_compatible(&u, &want))
		return ssc_acq_diag(diag, -EINVAL,
				    "sim: %s: '%s' is not in units of %s", key,
				    v, si);
	*out = x;
	return 0;
}

int ssc_source_sim_open(struct ssc_source **out, const char *opts,
			struct sscope_diag *diag)
{
	static const char *const names[6] = { "gx", "gy", "gz",
					      "ax", "ay", "az" };
	struct ssc_source *src;
	struct sim *s;
	double arw = 0.34 * (M_PI / 180) / 60; /* 0.34 deg/sqrt(h) */
	double vrw = 0.037 / 60;               /* 0.037 m/s/sqrt(h) */
	double bi = 0, rrw = 0;                /* gyro B, K: none */
	unsigned long seed = 1;
	char *copy = NULL, *save = NULL;
	int rc = 0;

	*out = NULL;
	src = calloc(1, sizeof(*src));
	s = calloc(1, sizeof(*s));
	if (!src || !s) {
		free(src);
		free(s);
		return -ENOMEM;
	}
	src->priv = s;
	src->ops = &sim_ops;
	src->stop_fd = -1;
	s->rate_hz = 1000;
	s->speed = 1;
	s->n_ch = 6;
	s->temp_degc = 25;
	copy = strdup(opts ? opts : "");
	if (!copy) {
		rc = -ENOMEM;
		goto fail;
	}
	for (char *item = strtok_r(copy, ",", &save); item;
	     item = strtok_r(NULL, ",", &save)) {
		char *v = strchr(item, '='), *end;

		if (!v) {
			rc = ssc_acq_diag(diag, -EINVAL,
					  "sim: '%s' is not key=value", item);
			goto fail;
		}
		*v++ = '\0';
		if (!strcmp(item, "rate")) {
			rc = opt_quantity("rate", v, "Hz", &s->rate_hz, diag);
			if (!rc && !(s->rate_hz > 0 && s->rate_hz <= 1e7))
				rc = ssc_acq_diag(diag, -EINVAL,
						  "sim: rate: '%s' is not 0 to 10 MHz",
						  v);
		} else if (!strcmp(item, "channels")) {
			unsigned long n = strtoul(v, &end, 10);

			if (*end || !*v || n < 1 || n > 6)
				rc = ssc_acq_diag(diag, -EINVAL,
						  "sim: channels: '%s' is not 1..6",
						  v);
			s->n_ch = n;
		} else if (!strcmp(item, "seed")) {
			seed = strtoul(v, &end, 10);
			if (*end || !*v || *v == '-')
				rc = ssc_acq_diag(diag, -EINVAL,
						  "sim: seed: '%s' is not a non-negative integer",
						  v);
		} else if (!strcmp(item, "arw")) {
			rc = opt_quantity("arw", v, "rad/s/sqrt(Hz)", &arw,
					  diag);
		} else if (!strcmp(item, "bi")) {
			rc = opt_quantity("bi", v, "rad/s", &bi, diag);
		} else if (!strcmp(item, "rrw")) {
			rc = opt_quantity("rrw", v, "rad/s^2/sqrt(Hz)", &rrw,
					  diag);
		} else if (!strcmp(item, "vrw")) {
			rc = opt_quantity("vrw", v, "m/s^2/sqrt(Hz)", &vrw,
					  diag);
		} else if (!strcmp(item, "temp")) {
			double x;

			if (ssc_parse_double(v, v + strlen(v), &x) !=
				    strlen(v) ||
			    !*v || !isfinite(x))
				rc = ssc_acq_diag(diag, -EINVAL,
						  "sim: temp: '%s' is not a temperature in degC",
						  v);
			s->temp_degc = x;
		} else if (!strcmp(item, "speed")) {
			if (!strcmp(v, "max")) {
				s->speed = 0;
			} else if (ssc_parse_double(v, v + strlen(v),
						    &s->speed) != strlen(v) ||
				   !*v || !(s->speed > 0) ||
				   !isfinite(s->speed)) {
				rc = ssc_acq_diag(diag, -EINVAL,
						  "sim: speed: '%s' is not a positive factor or max",
						  v);
			}
		} else {
			rc = ssc_acq_diag(diag, -EINVAL,
					  "sim: unknown option '%s' (rate, channels, seed, arw, bi, rrw, vrw, temp, speed)",
					  item);
		}
		if (rc)
			goto fail;
	}
	if (s->speed > 0)
		s->period_ns = llround(1e9 / (s->rate_hz * s->speed));
	for (size_t c = 0; c < s->n_ch; c++) {
		bool gyro = c < 3;
		struct sscope_sensor_spec spec = { .filter_order = 1 };
		struct sscope_sim_opts so = { .rate_hz = s->rate_hz,
					      .seed = seed,
					      .stream = c,
					      .temp_degc = s->temp_degc,
					      .ref_temp_degc = s->temp_degc,
					      .no_clip = true };

		spec.quantity = gyro ? SSCOPE_QUANTITY_ANGULAR_RATE :
				       SSCOPE_QUANTITY_ACCELERATION;
		spec.n = gyro ? arw : vrw;
		spec.b = gyro ? bi : 0;
		spec.k = gyro ? rrw : 0;
		rc = sscope_sim_new(&s->sim[c], &spec, &so, diag);
		if (rc)
			goto fail;
		for (size_t i = 0; i < BLOCK; i++) /* level: +1 g on z */
			s->input_block[c][i] = c == 5 ? G0 : 0;
		snprintf(src->info.name[c], sizeof(src->info.name[c]), "%s",
			 names[c]);
		snprintf(src->info.unit[c], sizeof(src->info.unit[c]), "%s",
			 gyro ? "deg/s" : "m/s^2");
	}
	s->pos = BLOCK;
	src->info.n_channels = s->n_ch;
	src->info.has_temp = true;
	src->info.has_counter = false;
	src->info.nominal_time = true;
	/* unpaced, nothing is lost by waiting for the writer */
	src->info.can_wait = s->speed == 0;
	src->info.rate_hz = s->rate_hz;
	snprintf(src->info.desc, sizeof(src->info.desc),
		 "simulator: %zu channel%s at %.10g Hz, seed %lu, white noise "
		 "(ARW %.4g deg/sqrt(h), VRW %.4g m/s/sqrt(h)), %s",
		 s->n_ch, s->n_ch == 1 ? "" : "s", s->rate_hz, seed,
		 arw * 60 * 180 / M_PI, vrw * 60,
		 s->speed > 0 ? (s->speed == 1 ? "real time" : "paced faster")
			      : "unpaced");
	if (s->speed > 0 && s->speed != 1) {
		size_t l = strlen(src->info.desc);

		snprintf(src->info.desc + l, sizeof(src->info.desc) - l,
			 " (x%.6g)", s->speed);
	}
	free(copy);
	*out = src;
	return 0;
fail:
	free(copy);
	sim_close(src);
	return rc;
}
