/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope acquire: record a live sensor (an ADIS1646x/1647x IMU or a
 * converter frame on spidev, paced by a data-ready GPIO line or polled)
 * or the simulator into a capture file, with a live view and an end
 * summary: samples, effective rate, data-ready interval jitter, drops,
 * checksum errors.  The work is done by src/acq/.
 */
#include "cli.h"

#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "acq/acq.h"
#include "plan.h"

enum {
	OPT_SPI = 300,
	OPT_DRDY,
	OPT_DEVICE,
	OPT_SOURCE,
	OPT_COUNT,
	OPT_DURATION,
	OPT_RATE,
	OPT_EDGE,
	OPT_SPEED,
	OPT_TIMEOUT,
	OPT_CAPFMT,
	OPT_LIVE,
	OPT_REALTIME,
	OPT_RTPRIO,
	OPT_RING,
	OPT_OVERWRITE,
	OPT_UNTIL,
};

static const struct ssc_option options[] = {
	{ "spi", required_argument, OPT_SPI, "/dev/spidevB.C",
	  "SPI device the sensor or converter is on" },
	{ "device", required_argument, OPT_DEVICE, "NAME",
	  "adis16470, adis16465-1/2/3, adis16467-1/2/3, adis16475-1/2/3, adis16477-1/2/3, or spiadc:FRAME (see below)" },
	{ "drdy", required_argument, OPT_DRDY, "CHIP:LINE",
	  "data-ready GPIO line, e.g. gpiochip0:25 (needs libgpiod); without it the device is polled" },
	{ "edge", required_argument, OPT_EDGE, "rising|falling",
	  "data-ready edge (ADIS default: from MSC_CTRL's DR polarity; frames: rising)" },
	{ "source", required_argument, OPT_SOURCE, "sim[:OPTS]",
	  "the simulator instead of hardware (see below)" },
	{ "count", required_argument, OPT_COUNT, "N",
	  "stop after N samples" },
	{ "duration", required_argument, OPT_DURATION, "S",
	  "stop after S seconds of data (units allowed: 10min)" },
	{ "until", required_argument, OPT_UNTIL, "[CH:]T:W",
	  "stop once the noise fit of channel CH (default the first) shows term T present with a relative half-width W (B:25%); needs --duration as the cap" },
	{ "rate", required_argument, OPT_RATE, "HZ",
	  "ADIS: set DEC_RATE for this output rate; spiadc: poll rate (or nominal rate with --drdy); sim: its rate" },
	{ "speed", required_argument, OPT_SPEED, "HZ",
	  "cap the SPI clock (ADIS: 1 MHz default, bursts at most 1 MHz)" },
	{ "timeout", required_argument, OPT_TIMEOUT, "S",
	  "give up when no data arrives for S seconds (default 1)" },
	{ "capture-format", required_argument, OPT_CAPFMT, "csv|f32|f64",
	  "capture file format: CSV (default) or sensorscope binary" },
	{ "live", no_argument, OPT_LIVE, NULL,
	  "show a running view on stderr (rate, last values, drops, ADEV at a few tau)" },
	{ "realtime", no_argument, OPT_REALTIME, NULL,
	  "SCHED_FIFO reader thread and mlockall (warns when not permitted)" },
	{ "rt-priority", required_argument, OPT_RTPRIO, "1..99",
	  "SCHED_FIFO priority with --realtime (default 50)" },
	{ "ring", required_argument, OPT_RING, "N",
	  "samples buffered between reader and writer (default 16384)" },
	{ "overwrite", no_argument, OPT_OVERWRITE, NULL,
	  "replace an existing FILE when the recording ends (without it an existing FILE is refused)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "acquire",
	.usage = "acquire (--spi /dev/spidevB.C --device NAME [--drdy CHIP:LINE] | --source sim[:OPTS]) -o FILE [OPTIONS]",
	.summary =
		"Record a live sensor into a capture file: on each data-ready edge read a\n"
		"frame over spidev, check and decode it, time-stamp it with the edge's\n"
		"kernel time stamp and stream it to FILE (CSV or sensorscope binary) that\n"
		"every other command reads.  A reader thread (optionally SCHED_FIFO) hands\n"
		"samples to a writer thread through a lock-free ring.  Samples lost on the\n"
		"way -- a jump of the device's sample counter, lost data-ready edges, ring\n"
		"overruns, frames failing their checksum -- are counted, reported and\n"
		"marked in the capture (a '# gap: ...' comment before the next row of a CSV,\n"
		"and always the time stamps); nothing is interpolated.  Ctrl-C (SIGINT),\n"
		"SIGTERM or SIGHUP stops cleanly: everything read is written and the file is valid.\n"
		"While recording, the capture is FILE.partial, which every command reads\n"
		"(up to its last complete row); a clean stop renames it to FILE.  Rows\n"
		"reach it within 0.2 s and the disk within about 1 s, so SIGKILL, the\n"
		"out-of-memory killer or a power cut leaves all but the last second or\n"
		"two in FILE.partial.\n"
		"A full disk (or quota, or file size limit) stops the run: the file is cut\n"
		"at its last complete row, given its end line if that fits, and kept as FILE.\n"
		"An existing FILE is refused unless --overwrite (then replaced at the end);\n"
		"an existing FILE.partial is always refused.  The unpaced simulator waits for\n"
		"the writer, so it never drops a sample; hardware overruns are counted.\n"
		"The summary (text, or --format json) gives samples, effective rate,\n"
		"jitter of the data-ready intervals, drops and checksum errors.",
	.options = options,
	.output_opts = true,
	.notes =
		"Capture: columns time [s] (from the first data-ready time stamp), the\n"
		"channels in their units, temp [degC].  ADIS: gx gy gz [deg/s],\n"
		"ax ay az [m/s^2]; PROD_ID must match --device or the run is refused.\n"
		"-o - writes the capture to stdout (the summary then goes to stderr);\n"
		"FIFOs and devices are written directly.\n"
		"\n"
		"--until refits the channel at 60 s of data, then every 5 % more (allan's\n"
		"fit, progress on stderr); the file holds every sample read.\n"
		"\n"
		"Exit status: 0 when stopped by --count, --duration, --until or a signal; 1 for a\n"
		"device error, a timeout, a full disk or another write error (the samples\n"
		"before it are kept and the message says where), or an existing FILE;\n"
		"2 for usage errors.\n"
		"\n"
		"Simulator: --source sim[:rate=HZ,channels=1..6,seed=N,arw=Q,bi=Q,rrw=Q,\n"
		"vrw=Q,temp=C,speed=X|max]; defaults 1 kHz, 6 channels like an ADIS16470,\n"
		"seed 1, white noise of ARW 0.34 deg/sqrt(h) and VRW 0.037 m/s/sqrt(h)\n"
		"(gyros: bias instability bi and rate random walk rrw, default 0), real-time\n"
		"pacing (speed=10 paces ten times faster, max unpaced).\n"
		"\n"
		"Converter frame: --device spiadc:tx=HEX[/HEX..],bits=N,range=LO:HI,\n"
		"[coding=unsigned|twos|offset,zero=V,sens=Q,unit=U,]ch=NAME@BIT[+BITS],...\n"
		"[,mode=0..3,speed=HZ]; scaling items apply to the ch= items after them.\n"
		"\n"
		"Without --drdy the device is polled: an ADIS at twice its output rate\n"
		"(repeated DATA_CNTR values discarded), a converter at --rate.\n"
		"\n"
		"Examples:\n"
		"  sensorscope acquire --spi /dev/spidev0.0 --drdy gpiochip0:25 \\\n"
		"      --device adis16470 --rate 200 --duration 1h -o imu.csv\n"
		"  sensorscope acquire --source sim --count 10000 --live -o sim.csv\n"
		"  sensorscope acquire --spi /dev/spidev0.1 --rate 1000 --duration 60 \\\n"
		"      --device spiadc:tx=060000,bits=12,range=0:3.3,zero=1.65,sens=6mV/\\(deg/s\\),unit=deg/s,ch=rate@12 \\\n"
		"      -o gyro.csv",
};

struct acq_opts {
	const char *spi, *drdy, *device, *source;
	int edge;
	uint64_t count;
	double duration_s, rate_hz, speed_hz, timeout_s;
	enum sscope_capture_format fmt;
	bool live, realtime, overwrite;
	int rt_priority;
	size_t ring;
	const char *until_ch;
	char until_name[32];
	int until_term;
	double until_w;
	struct ssc_until *until;
};

static int handle(int key, const char *arg, void *ctx)
{
	struct acq_opts *o = ctx;
	size_t n;

	switch (key) {
	case OPT_SPI:
		o->spi = arg;
		return 0;
	case OPT_DRDY: {
		const char *c = strrchr(arg, ':');

		if (!c || c == arg || !c[1])
			return ssc_usage_error("acquire",
					       "--drdy: '%s' is not CHIP:LINE (e.g. gpiochip0:25)",
					       arg);
		o->drdy = arg;
		return 0;
	}
	case OPT_DEVICE:
		o->device = arg;
		return 0;
	case OPT_SOURCE:
		if (strcmp(arg, "sim") && strncmp(arg, "sim:", 4))
			return ssc_usage_error("acquire",
					       "--source: '%s' is not sim[:OPTIONS] (hardware: --spi and --device)",
					       arg);
		o->source = arg;
		return 0;
	case OPT_EDGE:
		if (!strcmp(arg, "rising"))
			o->edge = 1;
		else if (!strcmp(arg, "falling"))
			o->edge = -1;
		else
			return ssc_usage_error("acquire",
					       "--edge: '%s' is not rising or falling",
					       arg);
		return 0;
	case OPT_COUNT:
		if (ssc_arg_size("acquire", "count", arg, &n))
			return SSC_EXIT_USAGE;
		if (n == 0)
			return ssc_usage_error("acquire", "--count: must be positive");
		o->count = n;
		return 0;
	case OPT_DURATION:
		return ssc_arg_positive("acquire", "duration", arg, "s", &o->duration_s);
	case OPT_UNTIL: {
		const char *c = strchr(arg, ':'), *t = arg, *q;
		char *end;

		if (c && strchr(c + 1, ':')) { /* CH:T:W */
			snprintf(o->until_name, sizeof(o->until_name), "%.*s",
				 (int)(c - arg), arg);
			o->until_ch = o->until_name;
			t = c + 1;
		}
		q = t[0] ? strchr("QNBKR", t[0]) : NULL;
		o->until_w = q && t[1] == ':' ? strtod(t + 2, &end) : (double)NAN;
		if (q && t[1] == ':' && end != t + 2 && *end == '%' && !end[1])
			o->until_w /= 100;
		else if (!q || t[1] != ':' || end == t + 2 || *end)
			o->until_w = NAN;
		if (!(o->until_w > 0) || !isfinite(o->until_w))
			return ssc_usage_error("acquire", "--until: '%s' is not [CHANNEL:]TERM:WIDTH (TERM one of Q N B K R, WIDTH 25%% or 0.25)",
					       arg);
		o->until_term = (int)(q - "QNBKR");
		return 0;
	}
	case OPT_RATE:
		return ssc_arg_positive("acquire", "rate", arg, "Hz", &o->rate_hz);
	case OPT_SPEED:
		if (ssc_arg_quantity("acquire", "speed", arg, "Hz", &o->speed_hz))
			return SSC_EXIT_USAGE;
		if (!(o->speed_hz >= 1000 && o->speed_hz <= 100e6))
			return ssc_usage_error("acquire",
					       "--speed: '%s' is not 1 kHz to 100 MHz",
					       arg);
		return 0;
	case OPT_TIMEOUT:
		if (ssc_arg_quantity("acquire", "timeout", arg, "s",
				     &o->timeout_s))
			return SSC_EXIT_USAGE;
		if (!(o->timeout_s > 0 && o->timeout_s < 1e6))
			return ssc_usage_error("acquire", "--timeout: must be positive");
		return 0;
	case OPT_CAPFMT:
		if (!strcmp(arg, "csv"))
			o->fmt = SSCOPE_CAPTURE_CSV;
		else if (!strcmp(arg, "f32"))
			o->fmt = SSCOPE_CAPTURE_BIN32;
		else if (!strcmp(arg, "f64"))
			o->fmt = SSCOPE_CAPTURE_BIN64;
		else
			return ssc_usage_error("acquire",
					       "--capture-format: '%s' is not csv, f32 or f64",
					       arg);
		return 0;
	case OPT_LIVE:
		o->live = true;
		return 0;
	case OPT_REALTIME:
		o->realtime = true;
		return 0;
	case OPT_OVERWRITE:
		o->overwrite = true;
		return 0;
	case OPT_RTPRIO:
		if (ssc_arg_size("acquire", "rt-priority", arg, &n))
			return SSC_EXIT_USAGE;
		if (n < 1 || n > 99)
			return ssc_usage_error("acquire", "--rt-priority: not 1..99");
		o->rt_priority = (int)n;
		o->realtime = true;
		return 0;
	case OPT_RING:
		if (ssc_arg_size("acquire", "ring", arg, &n))
			return SSC_EXIT_USAGE;
		if (n < 16 || n > (1u << 24))
			return ssc_usage_error("acquire", "--ring: not 16..16777216");
		o->ring = n;
		return 0;
	default:
		return ssc_usage_error("acquire", "unexpected option");
	}
}

/* ------------------------------------------------------------ live view */

struct live_ctx {
	bool tty;
	int lines;        /* lines drawn last time (to redraw over them) */
	uint64_t last_samples;
	double last_elapsed;
	double rate;
};

static void live_view(const struct ssc_acq_live *l, void *ctx)
{
	struct live_ctx *lc = ctx;
	const struct ssc_source_info *info = l->info;
	char a[32], b[32], c[32];
	double rate = lc->rate;
	int lines = 0;

	if (l->elapsed_s > lc->last_elapsed)
		rate = lc->rate = (double)(l->samples - lc->last_samples) /
				  (l->elapsed_s - lc->last_elapsed);
	lc->last_samples = l->samples;
	lc->last_elapsed = l->elapsed_s;
	if (lc->tty && lc->lines)
		fprintf(stderr, "\033[%dF\033[J", lc->lines);
	fprintf(stderr, "acquire: %s s, %llu samples, %s Hz, missing %llu, checksum errors %llu",
		ssc_fmt(a, sizeof(a), l->elapsed_s, 6),
		(unsigned long long)l->samples, ssc_fmt(b, sizeof(b), rate, 6),
		(unsigned long long)l->missing,
		(unsigned long long)l->checksum_errors);
	if (info->has_temp)
		fprintf(stderr, ", %s degC", ssc_fmt(c, sizeof(c), l->temp_degc, 4));
	fputc('\n', stderr);
	lines++;
	fprintf(stderr, "  %-18s %12s %12s", "channel", "last", "mean");
	for (size_t k = 0; k < SSC_LIVE_TAUS; k++) {
		char h[40];

		snprintf(h, sizeof(h), "ADEV %s s",
			 ssc_fmt(a, sizeof(a), l->tau_s[k], 3));
		fprintf(stderr, " %14s", h);
	}
	fputc('\n', stderr);
	lines++;
	for (size_t ch = 0; ch < info->n_channels; ch++) {
		struct sscope_unit u;
		char label[64];

		if (sscope_unit_parse(info->unit[ch], &u, NULL))
			sscope_unit_parse("", &u, NULL);
		snprintf(label, sizeof(label), "%s [%s]", info->name[ch],
			 info->unit[ch]);
		fprintf(stderr, "  %-18s %12s %12s", label,
			ssc_fmt(a, sizeof(a), sscope_unit_from_si(&u, l->last[ch]), 6),
			ssc_fmt(b, sizeof(b), sscope_unit_from_si(&u, l->mean[ch]), 6));
		for (size_t k = 0; k < SSC_LIVE_TAUS; k++)
			fprintf(stderr, " %14s",
				ssc_fmt(a, sizeof(a), l->adev[ch][k] / u.scale, 4));
		fputc('\n', stderr);
		lines++;
	}
	if (!lc->tty)
		fputc('\n', stderr);
	fflush(stderr);
	lc->lines = lines;
}

/* ------------------------------------------------------------ summary */

static const char *stop_name(const struct ssc_acq_result *r)
{
	switch (r->stop) {
	case SSC_STOP_COUNT:
		return "count";
	case SSC_STOP_DURATION:
		return "duration";
	case SSC_STOP_SIGNAL:
		return "signal";
	case SSC_STOP_TIMEOUT:
		return "timeout";
	case SSC_STOP_FULL:
		return ssc_acq_full_words(r->error);
	case SSC_STOP_UNTIL:
		return "until";
	default:
		return "error";
	}
}

struct drops {
	uint64_t counter, events, ring, total;
};

static struct drops count_drops(const struct ssc_source_info *info,
				const struct ssc_acq_result *r)
{
	struct drops d = { 0, 0, 0, 0 };

	d.ring = r->drops_ring;
	if (info->has_counter)
		d.counter = r->src.counter_missing;
	else
		d.events = r->src.events_lost + r->events_gap;
	d.total = d.counter + d.events + d.ring;
	return d;
}

static const char *format_name(enum sscope_capture_format f)
{
	return f == SSCOPE_CAPTURE_CSV ? "csv" : f == SSCOPE_CAPTURE_BIN32 ? "f32" : "f64";
}

static void text_summary(FILE *f, const struct acq_opts *o, const char *path,
			 const struct ssc_source_info *info,
			 const struct ssc_acq_result *r)
{
	struct drops d = count_drops(info, r);
	char a[32], b[32], c[32], e[32];

	if (path && r->committed)
		fprintf(f, "capture:         %s (%s)\n", r->file, format_name(o->fmt));
	else if (path)
		fprintf(f, "capture:         none (no sample recorded)\n");
	else
		fprintf(f, "capture:         none (live view only)\n");
	fprintf(f, "source:          %s\n", info->desc);
	fprintf(f, "stopped by:      %s%s\n", stop_name(r),
		r->stop == SSC_STOP_SIGNAL && r->signal
			? (r->signal == SIGINT ? " (SIGINT)" :
			   r->signal == SIGHUP ? " (SIGHUP)" : " (SIGTERM)")
			: r->stop == SSC_STOP_FULL
			? ": the capture ends at its last complete row"
			: "");
	if (o->until) {
		double w, fs;
		unsigned nf;
		bool ok;

		ssc_until_state(o->until, &w, &fs, &nf, &ok);
		fprintf(f, "until:           %c to %.1f %% %s (%.1f %% after %.6g s, fits: %u)\n",
			"QNBKR"[o->until_term], 100 * o->until_w,
			ok ? "reached" : "not reached", 100 * w, fs, nf);
	}
	fprintf(f, "samples:         %llu\n", (unsigned long long)r->samples);
	if (r->unsaved)
		fprintf(f, "not saved:       %llu samples read after the write failed\n",
			(unsigned long long)r->unsaved);
	fprintf(f, "duration:        %s s\n", ssc_fmt(a, sizeof(a), r->duration_s, 8));
	fprintf(f, "effective rate:  %s Hz", ssc_fmt(a, sizeof(a), r->effective_rate_hz, 8));
	if (info->rate_hz > 0)
		fprintf(f, " (nominal %s Hz)", ssc_fmt(b, sizeof(b), info->rate_hz, 8));
	fputc('\n', f);
	if (r->iv.n)
		fprintf(f, "data-ready:      interval %s s mean, jitter %s s rms, min %s s, max %s s (%llu regular intervals%s)\n",
			ssc_fmt(a, sizeof(a), r->iv.mean_s, 6),
			ssc_fmt(b, sizeof(b), ssc_intervals_sd(&r->iv), 3),
			ssc_fmt(c, sizeof(c), r->iv.min_s, 6),
			ssc_fmt(e, sizeof(e), r->iv.max_s, 6),
			(unsigned long long)r->iv.n,
			info->nominal_time ? "; simulated time stamps" : "");
	if (r->src.late_n)
		fprintf(f, "pacing:          late by %s s rms, %s s at most\n",
			ssc_fmt(a, sizeof(a), ssc_source_late_rms(&r->src), 3),
			ssc_fmt(b, sizeof(b), r->src.late_max_s, 3));
	fprintf(f, "drops:           %llu (", (unsigned long long)d.total);
	if (info->has_counter)
		fprintf(f, "device counter %llu, ", (unsigned long long)d.counter);
	else
		fprintf(f, "missed data-ready edges %llu, ", (unsigned long long)d.events);
	fprintf(f, "ring overruns %llu)\n", (unsigned long long)d.ring);
	fprintf(f, "checksum errors: %llu\n", (unsigned long long)r->src.checksum_errors);
	fprintf(f, "missing rows:    %llu in %llu gap%s (marked in the capture)\n",
		(unsigned long long)r->missing, (unsigned long long)r->gaps,
		r->gaps == 1 ? "" : "s");
	if (info->has_counter)
		fprintf(f, "repeats:         %llu; data-ready edges not served: %llu\n",
			(unsigned long long)r->src.duplicates,
			(unsigned long long)r->src.events_lost);
	if (r->src.time_estimated)
		fprintf(f, "late edges:      %llu samples were newer than their data-ready edge; their time is the edge's plus whole periods of DATA_CNTR\n",
			(unsigned long long)r->src.time_estimated);
	if (r->src.status_samples) {
		char t[160];

		sscope_adis_diag_text(r->src.status_or, t, sizeof(t));
		fprintf(f, "device status:   DIAG_STAT flags in %llu samples: %s\n",
			(unsigned long long)r->src.status_samples, t);
	}
	fprintf(f, "CPU:             writer %s s, reader %s s in %s s\n",
		ssc_fmt(a, sizeof(a), r->writer_cpu_s, 3),
		ssc_fmt(b, sizeof(b), r->reader_cpu_s, 3),
		ssc_fmt(c, sizeof(c), r->wall_s, 4));
}

static json_t *json_summary(const struct acq_opts *o, const char *path,
			    const struct ssc_source_info *info,
			    const struct ssc_acq_result *r, const char *error)
{
	struct drops d = count_drops(info, r);
	json_t *j = json_object(), *iv = json_object(), *dr = json_object(),
	       *ch = json_array();

	json_object_set_new(j, "command", json_string("acquire"));
	json_object_set_new(j, "file", path ? json_string(r->committed ? r->file : path)
					    : json_null());
	json_object_set_new(j, "format", json_string(format_name(o->fmt)));
	json_object_set_new(j, "committed", json_boolean(r->committed));
	json_object_set_new(j, "source", json_string(info->desc));
	for (size_t k = 0; k < info->n_channels; k++) {
		json_t *c = json_object();

		json_object_set_new(c, "name", json_string(info->name[k]));
		json_object_set_new(c, "unit", json_string(info->unit[k]));
		json_array_append_new(ch, c);
	}
	json_object_set_new(j, "channels", ch);
	json_object_set_new(j, "stop", json_string(stop_name(r)));
	if (o->until) {
		json_t *u = json_object();
		double w, fs;
		unsigned nf;
		bool ok;

		ssc_until_state(o->until, &w, &fs, &nf, &ok);
		json_object_set_new(u, "term", json_stringn(&"QNBKR"[o->until_term], 1));
		json_object_set_new(u, "target", ssc_jreal(o->until_w));
		json_object_set_new(u, "reached", json_boolean(ok));
		json_object_set_new(u, "rel_half_width", ssc_jreal(w));
		json_object_set_new(u, "fitted_s", ssc_jreal(fs));
		json_object_set_new(u, "fits", json_integer(nf));
		json_object_set_new(j, "until", u);
	}
	json_object_set_new(j, "samples", json_integer((json_int_t)r->samples));
	json_object_set_new(j, "unsaved", json_integer((json_int_t)r->unsaved));
	json_object_set_new(j, "end_line", json_boolean(r->committed &&
							 o->fmt == SSCOPE_CAPTURE_CSV &&
							 !r->trailer_lost));
	json_object_set_new(j, "duration_s", ssc_jreal(r->duration_s));
	json_object_set_new(j, "effective_rate_hz", ssc_jreal(r->effective_rate_hz));
	json_object_set_new(j, "nominal_rate_hz",
			    info->rate_hz > 0 ? json_real(info->rate_hz) : json_null());
	json_object_set_new(iv, "n", json_integer((json_int_t)r->iv.n));
	json_object_set_new(iv, "mean_s", ssc_jreal(r->iv.n ? r->iv.mean_s : (double)NAN));
	json_object_set_new(iv, "jitter_s", ssc_jreal(ssc_intervals_sd(&r->iv)));
	json_object_set_new(iv, "min_s", ssc_jreal(r->iv.n ? r->iv.min_s : (double)NAN));
	json_object_set_new(iv, "max_s", ssc_jreal(r->iv.n ? r->iv.max_s : (double)NAN));
	json_object_set_new(iv, "simulated", json_boolean(info->nominal_time));
	json_object_set_new(j, "interval", iv);
	json_object_set_new(dr, "total", json_integer((json_int_t)d.total));
	json_object_set_new(dr, "counter", json_integer((json_int_t)d.counter));
	json_object_set_new(dr, "events", json_integer((json_int_t)d.events));
	json_object_set_new(dr, "ring", json_integer((json_int_t)d.ring));
	json_object_set_new(j, "drops", dr);
	json_object_set_new(j, "checksum_errors",
			    json_integer((json_int_t)r->src.checksum_errors));
	json_object_set_new(j, "missing", json_integer((json_int_t)r->missing));
	json_object_set_new(j, "gaps", json_integer((json_int_t)r->gaps));
	json_object_set_new(j, "repeats", json_integer((json_int_t)r->src.duplicates));
	json_object_set_new(j, "edges_not_served",
			    json_integer((json_int_t)r->src.events_lost));
	json_object_set_new(j, "times_estimated",
			    json_integer((json_int_t)r->src.time_estimated));
	json_object_set_new(j, "status_samples",
			    json_integer((json_int_t)r->src.status_samples));
	json_object_set_new(j, "status_flags", json_integer(r->src.status_or));
	json_object_set_new(j, "pacing_late_max_s",
			    r->src.late_n ? json_real(r->src.late_max_s) : json_null());
	json_object_set_new(j, "writer_cpu_s", ssc_jreal(r->writer_cpu_s));
	json_object_set_new(j, "reader_cpu_s", ssc_jreal(r->reader_cpu_s));
	json_object_set_new(j, "wall_s", ssc_jreal(r->wall_s));
	json_object_set_new(j, "realtime",
			    json_boolean(o->realtime && !r->rt_errno));
	json_object_set_new(j, "memory_locked",
			    json_boolean(o->realtime && !r->mlock_errno));
	json_object_set_new(j, "error", error ? json_string(error) : json_null());
	return j;
}

/* ------------------------------------------------------------ main */

static int open_source(const struct ssc_common *co, const struct acq_opts *o,
		       struct ssc_source **src)
{
	struct sscope_diag d = { "" };
	int rc;

	if (o->source) {
		const char *opts = o->source[3] == ':' ? o->source + 4 : "";
		char buf[512];

		if (o->rate_hz > 0) {
			snprintf(buf, sizeof(buf), "rate=%.17g%s%s", o->rate_hz,
				 *opts ? "," : "", opts);
			opts = buf;
		}
		rc = ssc_source_sim_open(src, opts, &d);
	} else {
		struct ssc_spi_opts so = {
			.spi = o->spi, .device = o->device, .drdy = o->drdy,
			.drdy_edge = o->edge, .rate_hz = o->rate_hz,
			.speed_hz = (uint32_t)o->speed_hz,
		};

		rc = ssc_source_spi_open(src, &so, &d);
	}
	if (rc == -EINVAL) {
		ssc_err(co->cmd, "%s (see 'sensorscope acquire --help')", d.msg);
		return SSC_EXIT_USAGE;
	}
	if (rc)
		return ssc_fail(co->cmd, rc, &d, o->source ? "sim" : o->spi);
	return SSC_EXIT_OK;
}

int ssc_cmd_acquire(int argc, char **argv)
{
	struct ssc_common co;
	struct acq_opts o = { .timeout_s = 1, .ring = 16384, .rt_priority = 50,
			      .fmt = SSCOPE_CAPTURE_CSV };
	struct ssc_source *src = NULL;
	struct ssc_acq_config cfg;
	struct ssc_acq_result res;
	struct sscope_diag d = { "" };
	struct live_ctx lc = { .rate = (double)NAN };
	char c0[300], c1[64], c2[64];
	const char *comments[4];
	size_t nc = 0;
	int first, rc;
	FILE *sf;

	rc = ssc_parse(&spec, argc, argv, &co, handle, &o, &first);
	if (rc < 0)
		return SSC_EXIT_OK;
	if (rc)
		return rc;
	if (first < argc)
		return ssc_usage_error(co.cmd, "unexpected operand '%s'", argv[first]);
	if (co.format == SSC_FMT_CSV)
		return ssc_usage_error(co.cmd, "--format: the summary is text or json (the capture format is --capture-format)");
	if (o.source && (o.spi || o.device || o.drdy))
		return ssc_usage_error(co.cmd, "--source sim and --spi/--device/--drdy exclude each other");
	if (!o.source && (!o.spi || !o.device))
		return ssc_usage_error(co.cmd, "give --spi and --device (hardware) or --source sim");
	if (o.drdy && !ssc_drdy_available()) {
		ssc_err(co.cmd, "--drdy: data-ready lines need libgpiod, and this sensorscope was built without it (install libgpiod-dev and rebuild, or leave out --drdy to poll)");
		return SSC_EXIT_USAGE;
	}
	if (!co.output && !o.live)
		return ssc_usage_error(co.cmd, "give -o FILE for the capture (or --live to watch without recording)");

	if (o.until_w > 0 && !(o.duration_s > 0))
		return ssc_usage_error(co.cmd, "--until needs --duration, the longest the recording may run");
	rc = open_source(&co, &o, &src);
	if (rc)
		return rc;
	if (o.until_w > 0) {
		size_t ch = 0;

		while (o.until_ch && ch < src->info.n_channels &&
		       strcmp(src->info.name[ch], o.until_ch))
			ch++;
		if (ch == src->info.n_channels || !(src->info.rate_hz > 0) ||
		    ssc_until_new(co.cmd, ch, src->info.name[ch], o.until_term,
				  o.until_w, src->info.rate_hz, co.quiet, &o.until)) {
			rc = ch == src->info.n_channels ? SSC_EXIT_USAGE : SSC_EXIT_FAIL;
			ssc_err(co.cmd, "--until: %s", rc == SSC_EXIT_USAGE ?
				"no such channel" : "the source has no nominal rate (or out of memory)");
			ssc_source_close(src);
			return rc;
		}
	}

	snprintf(c0, sizeof(c0), "sensorscope acquire: %s", src->info.desc);
	comments[nc++] = c0;
	{
		time_t now = time(NULL);
		struct tm tm;

		if (gmtime_r(&now, &tm)) {
			strftime(c1, sizeof(c1), "started: %Y-%m-%dT%H:%M:%SZ", &tm);
			comments[nc++] = c1;
		}
	}
	if (src->info.rate_hz > 0) {
		char a[32];

		snprintf(c2, sizeof(c2), "nominal rate: %s Hz",
			 ssc_fmt(a, sizeof(a), src->info.rate_hz, 10));
		comments[nc++] = c2;
	}
	comments[nc] = NULL;

	memset(&cfg, 0, sizeof(cfg));
	cfg.src = src;
	cfg.path = co.output;
	cfg.format = o.fmt;
	cfg.count = o.count;
	cfg.duration_s = o.duration_s;
	cfg.timeout_s = o.timeout_s;
	cfg.ring_capacity = o.ring;
	cfg.rt_priority = o.realtime ? o.rt_priority : 0;
	cfg.lock_memory = o.realtime;
	cfg.handle_signals = true;
	cfg.overwrite = o.overwrite;
	cfg.comments = comments;
	cfg.until = o.until ? ssc_until_check : NULL;
	cfg.until_ctx = o.until;
	if (o.live) {
		lc.tty = isatty(STDERR_FILENO);
		cfg.live = live_view;
		cfg.live_ctx = &lc;
		cfg.live_period_s = lc.tty ? 0.25 : 1.0;
	}
	rc = ssc_acq_run(&cfg, &res, &d);

	if (o.realtime && res.rt_errno)
		ssc_warn(&co, "SCHED_FIFO priority %d not permitted (%s): the reader ran at normal priority (man sensorscope, acquire: rtprio limit or CAP_SYS_NICE)",
			 cfg.rt_priority, sscope_strerror(res.rt_errno));
	if (o.realtime && res.mlock_errno)
		ssc_warn(&co, "mlockall failed (%s): memory not locked (man sensorscope, acquire: memlock limit)",
			 sscope_strerror(res.mlock_errno));
	if (res.drops_ring)
		ssc_warn(&co, "the writer fell behind: %llu samples lost in ring overruns (larger --ring, faster disk, --capture-format f32)",
			 (unsigned long long)res.drops_ring);

	/* the summary goes to stdout unless the capture does */
	sf = co.output && !strcmp(co.output, "-") ? stderr : stdout;
	if (co.format == SSC_FMT_JSON) {
		json_t *j = json_summary(&o, co.output, &src->info, &res,
					 rc ? d.msg : NULL);

		if (j) {
			json_dumpf(j, sf, JSON_REAL_PRECISION(15) | JSON_COMPACT);
			fputc('\n', sf);
			json_decref(j);
		}
	} else if (res.samples || !rc) {
		text_summary(sf, &o, co.output, &src->info, &res);
	}
	if (sf == stdout) /* a failed summary is said like every output */
		ssc_stdout_finish(co.cmd);
	else
		fflush(sf);
	ssc_source_close(src);
	ssc_until_free(o.until);

	if (rc) {
		if (res.stop == SSC_STOP_FULL && res.committed)
			ssc_err(co.cmd, "stopped: %s: %s; the %llu samples recorded before it are in %s%s",
				ssc_acq_full_words(res.error), d.msg,
				(unsigned long long)res.samples, res.file,
				res.trailer_lost ? " (no room for its end line)" : "");
		else if (res.rename_err && res.committed && !res.error)
			ssc_err(co.cmd, "%s", d.msg);
		else if (res.committed)
			ssc_err(co.cmd, "%s (the %llu samples before it are in %s)",
				d.msg[0] ? d.msg : sscope_strerror(rc),
				(unsigned long long)res.samples, res.file);
		else
			ssc_err(co.cmd, "%s", d.msg[0] ? d.msg : sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	if (res.samples == 0) {
		ssc_err(co.cmd, "no sample was recorded%s", co.output ? "; no file written" : "");
		return SSC_EXIT_FAIL;
	}
	return SSC_EXIT_OK;
}
