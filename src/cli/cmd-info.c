/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope info: the first look at a capture: channels, units and what
 * they measure, sample rate and where it came from, time-stamp gaps and
 * jitter, per-channel statistics in the channel's own unit, temperature
 * range; --plot draws every channel against time (the long series are
 * reduced for the figure from the envelopes the statistics' pass finds:
 * each channel is read once).
 */
#include "cli.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "plot.h"
#include "stage.h"


static const struct ssc_command_spec spec = {
	.name = "info",
	.usage = "info [OPTIONS] FILE...",
	.summary =
		"Describe captures: channels, units and quantities, sample rate (and\n"
		"whether it came from --rate or the time column), duration, time-stamp\n"
		"gaps and jitter, per-channel mean, standard deviation, minimum and\n"
		"maximum in the channel's unit, and the temperature range.  A rate,\n"
		"acceleration, voltage or count channel with samples piled up on its\n"
		"smallest or largest value (at least 8, over 4 times the next value\n"
		"inward) is reported as clipped: a warning, JSON \"clipped\".",
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope info samples/gyro-static.csv\n"
		 "  sensorscope info --raw i16:6:le --scale 0.01 -u deg/s -r 100 imu.bin\n"
		 "  sensorscope info --format json - < capture.csv\n"
		 "  sensorscope info --topic /imu/data recording.bag\n"
		 "ROS bags, rosbag2 (.db3 or the bag folder) and MCAP files list their\n"
		 "topics; the header stamps are the time column, and the container's\n"
		 "receive times are compared with them (latency, and rate or gaps when\n"
		 "they disagree).",
};

struct file_info {
	const char *path;
	struct sscope_capture *cap;
	struct sscope_stats *st;
	struct sscope_clip *clip; /* samples piled at a channel's extremes */
	/* for the figure: the envelopes of the channels drawn (FIG_CHANNELS
	 * at most) and of the temperature, SSC_PLOT_LINE_BINS each, and
	 * where the time column is finite; NULL: none */
	struct sscope_clip_envelope *env, *temp_env;
	bool *t_fin;
	struct sscope_stats temp;
	bool have_temp;
	/* receive times of a ROS container */
	bool have_rx;
	struct sscope_timing rx;
	double lat_median_s, lat_min_s, lat_max_s;
	bool rx_disagree;
};

/* the channels the figure draws */
#define FIG_CHANNELS 6

/* the figure of the first capture */
struct fig_job {
	const struct sscope_capture *cap;
	const char *path;
	const struct file_info *fi; /* its envelopes, or NULL */
	struct ssc_fig *fig;
	int rc;
};

struct info_res {
	size_t n;
	struct file_info *fi;
};

/* receive times against header stamps: latency, and rate and gaps */
static void receive_times(const struct sscope_capture *cap,
			  struct file_info *fi, double *scratch)
{
	const double *rx = cap->source_info ? cap->source_info->receive_s : NULL;

	if (!rx || !cap->time_s || cap->n < 2)
		return;
	fi->have_rx = sscope_timing_analyze(rx, cap->n, SSCOPE_TIMING_GAP_FACTOR, &fi->rx, NULL, 0,
					    NULL, scratch) == 0;
	if (!fi->have_rx)
		return;
	/* the first n - 1 samples, as the stamps' intervals */
	if (sscope_timing_latency(rx, cap->time_s, cap->n - 1, &fi->lat_median_s,
				  &fi->lat_min_s, &fi->lat_max_s, scratch)) {
		fi->have_rx = false;
		return;
	}
	fi->rx_disagree = cap->has_timing &&
			  !sscope_timing_agree(&fi->rx, &cap->timing, 1e-3);
}

static double to_unit(const struct sscope_capture_column *c, double si)
{
	return sscope_unit_from_si(&c->unit, si);
}

/* sd and spreads are differences: no offset */
static double to_unit_diff(const struct sscope_capture_column *c, double si)
{
	return si / c->unit.scale;
}

/* What a sensor or its converter outputs, where a range ends: clipping is
 * looked for there, not in a trajectory's angles and positions (whose
 * noise-free plateaus would read as a pile-up). */
static bool sensor_output(enum sscope_quantity q)
{
	return q == SSCOPE_QUANTITY_ANGULAR_RATE || q == SSCOPE_QUANTITY_ACCELERATION ||
	       q == SSCOPE_QUANTITY_VOLTAGE || q == SSCOPE_QUANTITY_COUNTS ||
	       q == SSCOPE_QUANTITY_UNKNOWN || q == SSCOPE_QUANTITY_DIMENSIONLESS;
}

/* The statistics of each channel, the samples piled at the extremes of
 * those a sensor outputs and (fi->env) the envelopes the figure draws, in
 * one pass over it: one channel at a time on each of two threads, and
 * where the time column is finite as one more job; messages are left to
 * the caller, in order. */
struct chan_job {
	const struct sscope_capture *cap;
	struct file_info *fi;
	int *rc;
	atomic_size_t next;
};

static void *chan_work(void *arg)
{
	struct chan_job *j = arg;
	const struct sscope_capture *cap = j->cap;
	struct file_info *fi = j->fi;
	size_t k;

	while ((k = atomic_fetch_add(&j->next, 1)) <= cap->n_channels) {
		const double *x;
		bool env = fi->env && k < FIG_CHANNELS;

		if (k == cap->n_channels) {
			if (fi->env && cap->time_s)
				fi->t_fin = ssc_line_x_finite(cap->time_s, cap->n);
			continue;
		}
		x = cap->channels[k].data;
		/* all in one pass over the channel */
		j->rc[k] = sscope_clip_detect_stats_envelope(
			x, 1, cap->n, SSCOPE_CLIP_MIN_COUNT, SSCOPE_CLIP_RATIO,
			&fi->st[k],
			sensor_output(cap->channels[k].col.quantity) ?
				&fi->clip[k] : NULL,
			env ? SSC_PLOT_LINE_BINS : 0,
			env ? fi->env + k * SSC_PLOT_LINE_BINS : NULL);
	}
	return NULL;
}

/* below this many samples in all, one thread */
#define CHAN_THREAD_MIN ((size_t)1 << 20)

static void chan_compute(const struct sscope_capture *cap, struct file_info *fi,
			 int *rc)
{
	struct chan_job j = { .cap = cap, .fi = fi, .rc = rc };
	pthread_t tid;
	bool two = cap->n_channels >= 2 &&
		   cap->n * cap->n_channels >= CHAN_THREAD_MIN;

	atomic_init(&j.next, 0);
	two = two && !pthread_create(&tid, NULL, chan_work, &j);
	chan_work(&j);
	if (two)
		pthread_join(tid, NULL);
}

static int analyse(const struct ssc_common *co, const char *path,
		   struct sscope_capture *cap, struct file_info *fi,
		   bool want_env)
{
	size_t nc = cap->n_channels ? cap->n_channels : 1;
	size_t nfig = cap->n_channels < FIG_CHANNELS ? cap->n_channels :
						       FIG_CHANNELS;
	int *rcs;

	fi->path = path;
	fi->cap = cap;
	fi->st = calloc(nc, sizeof(*fi->st));
	fi->clip = calloc(nc, sizeof(*fi->clip));
	rcs = calloc(nc, sizeof(*rcs));
	/* the figure's envelopes (without them it reads the channels again) */
	if (want_env && cap->n > 8 * SSC_PLOT_LINE_BINS)
		fi->env = malloc((nfig + 1) * SSC_PLOT_LINE_BINS *
				 sizeof(*fi->env));
	if (!fi->st || !fi->clip || !rcs) {
		free(rcs);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	chan_compute(cap, fi, rcs);
	for (size_t k = 0; k < cap->n_channels; k++) {
		int rc = rcs[k];

		if (rc == -EDOM)
			ssc_warn(co, "%s: channel %s holds no finite sample",
				 path, cap->channels[k].col.name);
		if (rc == -ERANGE) {
			ssc_err(co->cmd, "%s: channel %s: the standard deviation exceeds the double range",
				strcmp(path, "-") ? path : "(stdin)",
				cap->channels[k].col.name);
			free(rcs);
			return SSC_EXIT_FAIL;
		}
	}
	free(rcs);
	if (cap->time_s && cap->n >= 2) {
		double *scratch = malloc((cap->n - 1) * sizeof(double));

		if (!scratch) {
			ssc_err(co->cmd, "out of memory");
			return SSC_EXIT_FAIL;
		}
		receive_times(cap, fi, scratch);
		free(scratch);
	}
	/* a time column that is not increasing: name what is wrong with it */
	ssc_time_check(co, path, cap, false);
	if (cap->temp_degc) {
		/* the same statistics as sscope_stats_compute() */
		if (fi->env)
			fi->temp_env = fi->env + nfig * SSC_PLOT_LINE_BINS;
		fi->have_temp = sscope_clip_detect_stats_envelope(
					cap->temp_degc, 1, cap->n, 0, 0,
					&fi->temp, NULL,
					fi->temp_env ? SSC_PLOT_LINE_BINS : 0,
					fi->temp_env) == 0;
	}
	return SSC_EXIT_OK;
}

static double duration(const struct sscope_capture *cap)
{
	if (cap->rate_hz > 0)
		return (double)cap->n / cap->rate_hz;
	return NAN;
}

static const char *rate_source(const struct sscope_capture *cap)
{
	switch (cap->rate_source) {
	case SSCOPE_CAPTURE_RATE_GIVEN:
		return "given";
	case SSCOPE_CAPTURE_RATE_TIME_COLUMN:
		return "time column";
	case SSCOPE_CAPTURE_RATE_HEADER:
		return "header";
	default:
		return "unknown";
	}
}

/* The clipping warning of channel k, or false when it is not clipped. */
static bool clip_message(const struct file_info *fi, size_t k, char *msg,
			 size_t len)
{
	const struct sscope_capture_column *col = &fi->cap->channels[k].col;
	const struct sscope_clip *c = &fi->clip[k];
	size_t n = (c->low ? c->n_lo : 0) + (c->high ? c->n_hi : 0);
	char a[32], b[32], p[32];
	const char *u = col->unit_label[0] ? col->unit_label : "";

	if (!c->low && !c->high)
		return false;
	ssc_fmt(p, sizeof(p), 100.0 * (double)n / (double)fi->st[k].n, 2);
	if (c->low && c->high)
		snprintf(msg, len, "%s: clipped: %zu samples (%s %%) sit at its smallest value %s %s or its largest %s %s (%zu and %zu; the values next inward hold %zu and %zu): the sensor or its converter reached the end of its range, and analyses of this channel are unreliable",
			 col->name, n, p,
			 ssc_fmt(a, sizeof(a), to_unit(col, c->lo), 6), u,
			 ssc_fmt(b, sizeof(b), to_unit(col, c->hi), 6), u,
			 c->n_lo, c->n_hi, c->n_lo_next, c->n_hi_next);
	else
		snprintf(msg, len, "%s: clipped: %zu samples (%s %%) sit at its %s value %s %s (the value next inward holds %zu): the sensor or its converter reached the end of its range, and analyses of this channel are unreliable",
			 col->name, n, p, c->high ? "largest" : "smallest",
			 ssc_fmt(a, sizeof(a), to_unit(col, c->high ? c->hi : c->lo), 6),
			 u, c->high ? c->n_hi_next : c->n_lo_next);
	return true;
}

static void text_file(FILE *f, const struct file_info *fi)
{
	const struct sscope_capture *cap = fi->cap;
	const struct sscope_timing *tm = &cap->timing;
	const char *path = fi->path;
	char a[32], b[32], c[32], d[32];
	size_t wn = 7, wu = 4, wq = 8;

	fprintf(f, "%s\n", strcmp(path, "-") ? path : "(stdin)");
	if (cap->source_info) {
		const struct sscope_capture_source *si = cap->source_info;

		fprintf(f, "  format:      %s\n", si->format);
		for (size_t i = 0; i < si->n_topics; i++) {
			const struct sscope_capture_topic *t = &si->topics[i];

			fprintf(f, "  %-12s %s  %s  %llu message%s%s\n",
				i ? "" : "topics:", t->name, t->type,
				(unsigned long long)t->messages,
				t->messages == 1 ? "" : "s",
				t->selected ? "  (read)" :
				t->readable ? "" : "  (not an IMU type)");
		}
	}
	fprintf(f, "  rows:        %zu\n", cap->n);
	if (cap->rate_hz > 0)
		fprintf(f, "  rate:        %s Hz (%s)\n",
			ssc_fmt(a, sizeof(a), cap->rate_hz, 8), rate_source(cap));
	else if (cap->time_s)
		fprintf(f, "  rate:        unknown (time column '%s' not increasing; give --rate)\n",
			cap->time_col.name);
	else if (cap->rate_note[0])
		fprintf(f, "  rate:        unknown (%s; give --rate)\n",
			cap->rate_note);
	else
		fprintf(f, "  rate:        unknown (no time column; give --rate)\n");
	if (cap->rate_hz > 0)
		fprintf(f, "  duration:    %s s\n",
			ssc_fmt(a, sizeof(a), duration(cap), 6));
	if (cap->has_timing) {
		fprintf(f, "  time column: %s [%s], interval median %s s, min %s s, max %s s, jitter %s s rms\n",
			cap->time_col.name, cap->time_col.unit_label[0] ?
			cap->time_col.unit_label : "s",
			ssc_fmt(a, sizeof(a), tm->dt_median_s, 6),
			ssc_fmt(b, sizeof(b), tm->dt_min_s, 6),
			ssc_fmt(c, sizeof(c), tm->dt_max_s, 6),
			ssc_fmt(d, sizeof(d), tm->jitter_rms_s, 3));
		if (tm->n_gaps == 0) {
			fprintf(f, "  gaps:        none\n");
		} else {
			fprintf(f, "  gaps:        %zu (about %zu samples missing)\n",
				tm->n_gaps, tm->n_missing);
			for (size_t i = 0; i < cap->n_gaps && i < 10; i++)
				fprintf(f, "               at t = %s s (row %zu): %s s, ~%zu missing\n",
					ssc_fmt(a, sizeof(a), cap->gaps[i].t_s, 8),
					cap->gaps[i].index + 1,
					ssc_fmt(b, sizeof(b), cap->gaps[i].length_s, 6),
					cap->gaps[i].missing);
			if (tm->n_gaps > 10)
				fprintf(f, "               ... (--format json lists up to %d)\n",
					SSCOPE_CAPTURE_GAPS);
		}
	}
	if (fi->have_rx) {
		fprintf(f, "  receive times: latency after the header stamps median %s s, min %s s, max %s s\n",
			ssc_fmt(a, sizeof(a), fi->lat_median_s, 4),
			ssc_fmt(b, sizeof(b), fi->lat_min_s, 4),
			ssc_fmt(c, sizeof(c), fi->lat_max_s, 4));
		if (fi->rx_disagree)
			fprintf(f, "               they disagree with the stamps: rate %s Hz, %zu gaps, %zu backwards (stamps: %s Hz, %zu gaps, %zu backwards)\n",
				ssc_fmt(a, sizeof(a), fi->rx.rate_hz, 8),
				fi->rx.n_gaps, fi->rx.n_backwards,
				ssc_fmt(b, sizeof(b), tm->rate_hz, 8),
				tm->n_gaps, tm->n_backwards);
		else
			fprintf(f, "               rate and gaps agree with the header stamps\n");
	}
	if (cap->n_nan)
		fprintf(f, "  NaN cells:   %zu (read as gaps)\n", cap->n_nan);
	if (fi->have_temp)
		fprintf(f, "  temperature: %s .. %s degC, mean %s (column '%s')\n",
			ssc_fmt(a, sizeof(a), fi->temp.min, 5),
			ssc_fmt(b, sizeof(b), fi->temp.max, 5),
			ssc_fmt(c, sizeof(c), fi->temp.mean, 5),
			cap->temp_col.name);
	for (size_t k = 0; k < cap->n_channels; k++) {
		const struct sscope_capture_column *col = &cap->channels[k].col;
		size_t l = strlen(col->name);

		if (l > wn)
			wn = l;
		l = strlen(col->unit_label);
		if (l > wu)
			wu = l;
		l = strlen(sscope_quantity_name(col->quantity));
		if (l > wq)
			wq = l;
	}
	fprintf(f, "\n  %-*s  %-*s  %-*s  %13s  %13s  %13s  %13s\n", (int)wn,
		"channel", (int)wu, "unit", (int)wq, "quantity", "mean", "sd",
		"min", "max");
	for (size_t k = 0; k < cap->n_channels; k++) {
		const struct sscope_capture_column *col = &cap->channels[k].col;
		const struct sscope_stats *s = &fi->st[k];

		fprintf(f, "  %-*s  %-*s  %-*s  %13s  %13s  %13s  %13s\n", (int)wn,
			col->name, (int)wu, col->unit_label[0] ? col->unit_label : "-",
			(int)wq, sscope_quantity_name(col->quantity),
			ssc_fmt(a, sizeof(a), s->n ? to_unit(col, s->mean) : (double)NAN, 7),
			/* one sample has no spread: unknown, not 0 */
			s->n > 1 ? ssc_fmt(b, sizeof(b), to_unit_diff(col, s->sd), 5) : "-",
			ssc_fmt(c, sizeof(c), s->n ? to_unit(col, s->min) : (double)NAN, 7),
			ssc_fmt(d, sizeof(d), s->n ? to_unit(col, s->max) : (double)NAN, 7));
	}
	for (size_t k = 0; k < cap->n_channels; k++) {
		char msg[640];

		if (clip_message(fi, k, msg, sizeof(msg)))
			fprintf(f, "  warning: %s\n", msg);
	}
}

static json_t *json_file(const struct file_info *fi)
{
	const struct sscope_capture *cap = fi->cap;
	const struct sscope_timing *tm = &cap->timing;
	const char *path = fi->path;
	json_t *o = json_object(), *chs = json_array(), *gaps = json_array();

	json_object_set_new(o, "command", json_string("info"));
	json_object_set_new(o, "file", json_string(path));
	json_object_set_new(o, "rows", json_integer((json_int_t)cap->n));
	json_object_set_new(o, "rate_hz", cap->rate_hz > 0 ? json_real(cap->rate_hz) :
				     json_null());
	json_object_set_new(o, "rate_source", json_string(rate_source(cap)));
	if (cap->rate_note[0])
		json_object_set_new(o, "rate_note", json_string(cap->rate_note));
	for (size_t k = 0; k < cap->n_channels; k++) {
		const struct sscope_capture_column *col = &cap->channels[k].col;
		const struct sscope_stats *s = &fi->st[k];
		json_t *c = json_object();

		json_object_set_new(c, "name", json_string(col->name));
		json_object_set_new(c, "unit", json_string(col->unit_label));
		json_object_set_new(c, "quantity",
				    json_string(sscope_quantity_name(col->quantity)));
		json_object_set_new(c, "column", json_integer((json_int_t)col->index + 1));
		json_object_set_new(c, "rate_hz", cap->rate_hz > 0 ?
					  json_real(cap->rate_hz) : json_null());
		json_object_set_new(c, "samples", json_integer((json_int_t)s->n));
		json_object_set_new(c, "nan", json_integer((json_int_t)s->n_nan));
		json_object_set_new(c, "duration_s", ssc_jreal(duration(cap)));
		json_object_set_new(c, "mean", s->n ? ssc_jreal(to_unit(col, s->mean)) : json_null());
		json_object_set_new(c, "sd", s->n > 1 ? ssc_jreal(to_unit_diff(col, s->sd)) : json_null());
		json_object_set_new(c, "min", s->n ? ssc_jreal(to_unit(col, s->min)) : json_null());
		json_object_set_new(c, "max", s->n ? ssc_jreal(to_unit(col, s->max)) : json_null());
		{
			/* samples piled at each end of the range, 0: none */
			json_t *cl = json_object();

			json_object_set_new(cl, "low", json_integer(fi->clip[k].low ?
				(json_int_t)fi->clip[k].n_lo : 0));
			json_object_set_new(cl, "high", json_integer(fi->clip[k].high ?
				(json_int_t)fi->clip[k].n_hi : 0));
			json_object_set_new(c, "clipped", cl);
		}
		json_array_append_new(chs, c);
	}
	json_object_set_new(o, "channels", chs);
	for (size_t k = 0; k < cap->n_channels; k++) {
		char msg[640];

		if (clip_message(fi, k, msg, sizeof(msg)))
			ssc_json_warn(o, "clipped", "%s", msg);
	}
	for (size_t i = 0; i < cap->n_gaps; i++) {
		json_t *g = json_object();

		json_object_set_new(g, "row", json_integer((json_int_t)cap->gaps[i].index + 1));
		json_object_set_new(g, "t_s", json_real(cap->gaps[i].t_s));
		json_object_set_new(g, "length_s", json_real(cap->gaps[i].length_s));
		json_object_set_new(g, "missing", json_integer((json_int_t)cap->gaps[i].missing));
		json_array_append_new(gaps, g);
	}
	json_object_set_new(o, "gaps", gaps);
	if (cap->time_s) {
		/* what is wrong with the time column's order, or null */
		struct sscope_timing_order ord;
		struct sscope_diag d = { "" };

		ssc_time_order(cap, &ord);
		json_object_set_new(o, "time_order",
				    sscope_timing_order_check(&ord, &d) ?
				    json_string(d.msg) : json_null());
	}
	if (cap->source_info) {
		const struct sscope_capture_source *si = cap->source_info;
		json_t *tps = json_array();

		json_object_set_new(o, "format", json_string(si->format));
		for (size_t i = 0; i < si->n_topics; i++) {
			json_t *t = json_object();

			json_object_set_new(t, "name", json_string(si->topics[i].name));
			json_object_set_new(t, "type", json_string(si->topics[i].type));
			json_object_set_new(t, "messages",
					    json_integer((json_int_t)si->topics[i].messages));
			json_object_set_new(t, "readable", json_boolean(si->topics[i].readable));
			json_object_set_new(t, "selected", json_boolean(si->topics[i].selected));
			json_array_append_new(tps, t);
		}
		if (si->n_topics)
			json_object_set_new(o, "topics", tps);
		else
			json_decref(tps);
	}
	if (fi->have_rx) {
		json_t *t = json_object();

		json_object_set_new(t, "rate_hz", json_real(fi->rx.rate_hz));
		json_object_set_new(t, "gaps", json_integer((json_int_t)fi->rx.n_gaps));
		json_object_set_new(t, "backwards", json_integer((json_int_t)fi->rx.n_backwards));
		json_object_set_new(t, "latency_median_s", json_real(fi->lat_median_s));
		json_object_set_new(t, "latency_min_s", json_real(fi->lat_min_s));
		json_object_set_new(t, "latency_max_s", json_real(fi->lat_max_s));
		json_object_set_new(t, "agree", json_boolean(!fi->rx_disagree));
		json_object_set_new(o, "receive_times", t);
	}
	if (cap->has_timing) {
		json_t *t = json_object();

		json_object_set_new(t, "column", json_string(cap->time_col.name));
		json_object_set_new(t, "interval_median_s", json_real(tm->dt_median_s));
		json_object_set_new(t, "interval_min_s", json_real(tm->dt_min_s));
		json_object_set_new(t, "interval_max_s", json_real(tm->dt_max_s));
		json_object_set_new(t, "jitter_rms_s", json_real(tm->jitter_rms_s));
		json_object_set_new(t, "gaps", json_integer((json_int_t)tm->n_gaps));
		json_object_set_new(t, "missing", json_integer((json_int_t)tm->n_missing));
		json_object_set_new(t, "backwards", json_integer((json_int_t)tm->n_backwards));
		json_object_set_new(o, "timing", t);
	} else {
		json_object_set_new(o, "timing", json_null());
	}
	if (fi->have_temp) {
		json_t *t = json_object();

		json_object_set_new(t, "name", json_string(cap->temp_col.name));
		json_object_set_new(t, "unit", json_string("degC"));
		json_object_set_new(t, "min", json_real(fi->temp.min));
		json_object_set_new(t, "max", json_real(fi->temp.max));
		json_object_set_new(t, "mean", json_real(fi->temp.mean));
		json_object_set_new(o, "temperature", t);
	} else {
		json_object_set_new(o, "temperature", json_null());
	}
	return o;
}

static void csv_file(FILE *f, const struct file_info *fi)
{
	const struct sscope_capture *cap = fi->cap;
	const char *path = fi->path;

	for (size_t k = 0; k < cap->n_channels; k++) {
		const struct sscope_capture_column *col = &cap->channels[k].col;
		const struct sscope_stats *s = &fi->st[k];

		fprintf(f, "%s,%s,%s,%s,%.15g,%zu,%zu,%.15g,%.15g,%.15g,%.15g,%.15g\n",
			path, col->name, col->unit_label,
			sscope_quantity_name(col->quantity),
			cap->rate_hz > 0 ? cap->rate_hz : (double)NAN, s->n,
			s->n_nan, duration(cap), to_unit(col, s->mean),
			s->n > 1 ? to_unit_diff(col, s->sd) : (double)NAN,
			to_unit(col, s->min),
			to_unit(col, s->max));
	}
}

/* every channel (at most 6) and the temperature against time, of the
 * first file */
/* Every channel (up to six) and the temperature against time: the series
 * are added (and reduced) here, the figure is drawn by plot(). */
static void build_fig(struct fig_job *job)
{
	const struct sscope_capture *cap = job->cap;
	size_t nch = cap->n_channels < FIG_CHANNELS ? cap->n_channels :
						      FIG_CHANNELS;
	int rows = (int)nch + (cap->temp_degc ? 1 : 0);
	struct ssc_fig *fig;
	/* the time stamps as they are, else times made from the rate; the
	 * samples converted to their unit as they are drawn */
	double *tmade = cap->time_s ? NULL : malloc(cap->n * sizeof(double));
	const double *t = cap->time_s ? cap->time_s : tmade;
	const struct file_info *fi = job->fi;
	const struct sscope_clip_envelope *env = fi ? fi->env : NULL;
	bool *t_fin; /* the time column's finite stretches, looked up once */
	bool *t_own = NULL;
	char buf[256];

	if (!t || rows == 0) {
		free(tmade);
		job->rc = -ENOMEM;
		return;
	}
	for (size_t i = 0; tmade && i < cap->n; i++)
		tmade[i] = cap->rate_hz > 0 ? (double)i / cap->rate_hz : (double)i;
	t_fin = env && fi->t_fin ? fi->t_fin :
				   (t_own = ssc_line_x_finite(t, cap->n));
	fig = ssc_fig_new(1100, 80 + 250 * rows, rows, 1);
	snprintf(buf, sizeof(buf), "%s", job->path);
	ssc_fig_title(fig, buf);
	for (size_t k = 0; k < nch; k++) {
		const struct sscope_capture_column *col = &cap->channels[k].col;
		struct ssc_ax *ax = ssc_fig_ax(fig, (int)k, 0);
		struct ssc_style st = { .color = ssc_plot_color(k), .width = 1 };

		ssc_ax_line_envelope_x(ax, t, t_fin, cap->channels[k].data,
				       cap->n, col->unit.offset, col->unit.scale,
				       env ? env + k * SSC_PLOT_LINE_BINS : NULL,
				       &st, NULL);
		snprintf(buf, sizeof(buf), "%s (%s)", col->name,
			 col->unit_label[0] ? col->unit_label : "no unit");
		ssc_ax_ylabel(ax, buf);
		ssc_ax_xlabel(ax, cap->time_s || cap->rate_hz > 0 ? "time (s)" :
								    "sample");
	}
	if (cap->temp_degc) {
		struct ssc_ax *ax = ssc_fig_ax(fig, rows - 1, 0);
		struct ssc_style st = { .color = 0xd62728, .width = 1.5 };

		ssc_ax_line_envelope_x(ax, t, t_fin, cap->temp_degc, cap->n, 0,
				       1, env ? fi->temp_env : NULL, &st, NULL);
		ssc_ax_ylabel(ax, "temperature (\xc2\xb0" "C)");
		ssc_ax_xlabel(ax, cap->time_s || cap->rate_hz > 0 ? "time (s)" :
								    "sample");
	}
	free(t_own);
	free(tmade);
	job->fig = fig;
}

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *png)
{
	const struct info_res *r = result;
	struct fig_job local = { 0 }, *job = &local;
	int rc;

	(void)opts;
	local.cap = r->fi->cap;
	local.path = r->fi->path;
	local.fi = r->fi;
	build_fig(job);
	if (job->rc) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	rc = ssc_fig_save(job->fig, png);
	ssc_fig_free(job->fig);
	job->fig = NULL;
	if (rc)
		return ssc_write_failed(co->cmd, png, rc);
	return SSC_EXIT_OK;
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const struct ssc_common *co = env->co;
	struct info_res *r = calloc(1, sizeof(*r));
	int rc = SSC_EXIT_OK;

	(void)opts;
	if (r)
		r->fi = calloc(env->n_caps ? env->n_caps : 1, sizeof(*r->fi));
	if (!r || !r->fi) {
		free(r);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = r;
	/* the figure (of the first capture) is reduced from the envelopes
	 * its statistics' pass finds */
	for (size_t i = 0; i < env->n_caps && !rc; i++, r->n++)
		rc = analyse(co, env->paths[i], env->caps[i], &r->fi[i],
			     co->plot && i == 0);
	return rc;
}

static void free_result(void *result)
{
	struct info_res *r = result;

	for (size_t i = 0; i < r->n; i++) {
		free(r->fi[i].st);
		free(r->fi[i].clip);
		free(r->fi[i].env);
		free(r->fi[i].t_fin);
	}
	free(r->fi);
	free(r);
}

static void text(FILE *f, const void *opts, const void *result)
{
	const struct info_res *r = result;

	(void)opts;
	for (size_t i = 0; i < r->n; i++) {
		if (i)
			fputc('\n', f);
		text_file(f, &r->fi[i]);
	}
}

static void csv(FILE *f, const void *opts, const void *result)
{
	const struct info_res *r = result;

	(void)opts;
	fprintf(f, "file,channel,unit,quantity,rate_hz,samples,nan,duration_s,mean,sd,min,max\n");
	for (size_t i = 0; i < r->n; i++)
		csv_file(f, &r->fi[i]);
}

static json_t *json(const void *opts, const void *result)
{
	const struct info_res *r = result;
	json_t *o, *files;

	(void)opts;
	if (r->n == 1)
		return json_file(&r->fi[0]);
	o = json_object();
	files = json_array();
	json_object_set_new(o, "command", json_string("info"));
	for (size_t i = 0; i < r->n; i++)
		json_array_append_new(files, json_file(&r->fi[i]));
	json_object_set_new(o, "files", files);
	return o;
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct info_res *r = result;

	(void)opts;
	for (size_t i = 0; i < r->n; i++) {
		const struct file_info *fi = &r->fi[i];
		const struct sscope_capture *cap = fi->cap;
		/* several files: each row names its file, in the channel
		 * field as psd's rows do */
		const char *who = r->n > 1 ? (strrchr(fi->path, '/') ?
					      strrchr(fi->path, '/') + 1 : fi->path) : NULL;

		if (cap->rate_hz > 0) {
			ssc_summary_add(rows, who, "sample rate", cap->rate_hz,
					NAN, NAN, "Hz", rate_source(cap));
			ssc_summary_add(rows, who, "record length",
					duration(cap), NAN, NAN, "s", NULL);
		}
		for (size_t k = 0; k < cap->n_channels; k++) {
			const struct sscope_clip *c = &fi->clip[k];
			char ch[300];

			if (!c->low && !c->high)
				continue;
			snprintf(ch, sizeof(ch), "%s%s%s", who ? who : "", who ? ": " : "",
				 cap->channels[k].col.name);
			ssc_summary_add(rows, ch, "clipped samples",
					(double)((c->low ? c->n_lo : 0) +
						 (c->high ? c->n_hi : 0)),
					NAN, NAN, "", "at the end of the range");
			ssc_summary_warn_last(rows);
		}
		if (fi->have_temp) {
			char note[96], a[32], b[32];

			snprintf(note, sizeof(note), "from %s to %s degC",
				 ssc_fmt(a, sizeof(a), fi->temp.min, 4),
				 ssc_fmt(b, sizeof(b), fi->temp.max, 4));
			ssc_summary_add(rows, who, "temperature span",
					fi->temp.max - fi->temp.min, NAN, NAN,
					"degC", note);
		}
	}
}

const struct ssc_stage_ops ssc_info_stage = {
	.spec = &spec,
	.title = "Inputs",
	.needs = SSC_NEED_DATA,
	.min_files = 1,
	.max_files = -1,
	.run = run,
	.json = json,
	.text = text,
	.csv = csv,
	.summary = summary,
	.plot = plot,
	.free_result = free_result,
};

int ssc_cmd_info(int argc, char **argv)
{
	return ssc_stage_main(&ssc_info_stage, argc, argv);
}
