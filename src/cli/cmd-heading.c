/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope heading: heading from a vertical gyro with the bias
 * estimated on the first stop and re-estimated at every later stop (see
 * analysis/sscope-heading.h); the predicted error envelope from the
 * gyro's noise terms; with a true heading column, the error with and
 * without re-estimation.
 */
#include "cli.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "navcommon.h"
#include "plot.h"
#include "stage.h"

#define D2R (PI / 180)

enum {
	O_AXIS = 300,
	O_AXIS_UP,
	O_DETECT,
	O_WINDOW,
	O_MIN_STOP,
	O_THRESHOLD,
	O_INIT,
	O_CONTRAST,
	O_LAT,
	O_MODEL,
	O_INITIAL,
	O_REF,
	O_SENSOR,
	O_ALLAN,
	O_ARW,
	O_BI,
	O_RRW,
};

static const struct ssc_option heading_opts[] = {
	{ "axis", required_argument, O_AXIS, "NAME",
	  "the vertical-axis rate channel (default: the only rate channel, or the one whose name ends in z)" },
	{ "axis-up", no_argument, O_AXIS_UP, NULL,
	  "the axis points up (heading is minus its integral; default: down, as NED)" },
	{ "detect", required_argument, O_DETECT, "A,B,C",
	  "three channels for the stop detector (default: the accelerometers, else the gyros, else the axis)" },
	{ "window", required_argument, O_WINDOW, "T", "detector window (default 1 s)" },
	{ "min-stop", required_argument, O_MIN_STOP, "T", "shortest stop (default 2 s)" },
	{ "threshold", required_argument, O_THRESHOLD, "K",
	  "still below K times the noise reference (default 3)" },
	{ "init-still", required_argument, O_INIT, "T",
	  "noise reference from the first T seconds (default: 10th percentile of the variance)" },
	{ "contrast", required_argument, O_CONTRAST, "C",
	  "motion must reach C times the reference somewhere (default K^2)" },
	{ "latitude", required_argument, O_LAT, "DEG",
	  "remove the vertical Earth rate from the stop biases" },
	{ "bias-model", required_argument, O_MODEL, "hold|interpolate",
	  "bias between stops: the last stop's (default, as in real time) or interpolated (post-processing)" },
	{ "initial-heading", required_argument, O_INITIAL, "DEG",
	  "heading at the first stop (default: the reference's, else 0)" },
	{ "reference", required_argument, O_REF, "COLUMN",
	  "true heading column: report the error with and without re-estimation" },
	{ "sensor", required_argument, O_SENSOR, "SPEC.ini", "noise terms of the gyro for the envelope" },
	{ "from-allan", required_argument, O_ALLAN, "RESULT.json",
	  "noise terms from an 'allan' result (the axis' channel, else the worst gyro)" },
	{ "arw", required_argument, O_ARW, "V", "angle random walk for the envelope (e.g. 0.3 deg/sqrt(h))" },
	{ "bias-instability", required_argument, O_BI, "V", "bias instability for the envelope (e.g. 5 deg/h)" },
	{ "rrw", required_argument, O_RRW, "V", "rate random walk for the envelope (e.g. 10 deg/h/sqrt(h))" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "heading",
	.usage = "heading [OPTIONS] FILE",
	.summary =
		"Heading from the gyro about the vertical: the bias is estimated on the\n"
		"first stationary interval and re-estimated at every stop (found by the\n"
		"static detector of 'calib'), the heading is held while still; the same\n"
		"record integrated with the first bias alone shows what the stops buy.\n"
		"The predicted 1- and 2-sigma heading-error envelope comes from the\n"
		"gyro's noise terms (N, B, K: options, a sensor spec or an 'allan'\n"
		"result; otherwise N from the scatter within the stops).",
	.options = heading_opts,
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope heading --reference heading_ref samples/drive-stops.csv\n"
		 "  sensorscope heading --latitude 48 --from-allan allan.json --plot heading.png drive.csv\n"
		 "--format csv writes time, heading, heading with the first bias only, their\n"
		 "predicted 1-sigma errors (deg) and the still flag, plus the reference and\n"
		 "the errors with --reference.  Headings are in [0, 360) degrees.",
};

struct opts {
	const char *axis, *detect, *ref, *sensor, *allan;
	bool axis_up;
	struct sscope_heading_opts ho;
	double arw, bi, rrw;
	bool set_terms, set_initial;
};

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;
	double v;

	switch (key) {
	case O_AXIS:
		o->axis = arg;
		return 0;
	case O_AXIS_UP:
		o->axis_up = true;
		return 0;
	case O_DETECT:
		o->detect = arg;
		return 0;
	case O_WINDOW:
		return ssc_arg_positive("heading", "window", arg, "s", &o->ho.window_s);
	case O_MIN_STOP:
		return ssc_arg_positive("heading", "min-stop", arg, "s", &o->ho.min_static_s);
	case O_THRESHOLD:
		if (ssc_arg_double("heading", "threshold", arg, &o->ho.k))
			return SSC_EXIT_USAGE;
		return o->ho.k > 1 ? 0 : ssc_usage_error("heading", "--threshold: must exceed 1");
	case O_INIT:
		return ssc_arg_positive("heading", "init-still", arg, "s", &o->ho.init_static_s);
	case O_CONTRAST:
		if (ssc_arg_double("heading", "contrast", arg, &o->ho.min_contrast))
			return SSC_EXIT_USAGE;
		return o->ho.min_contrast > 1 ? 0 :
						ssc_usage_error("heading", "--contrast: must exceed 1");
	case O_LAT:
		if (ssc_arg_quantity("heading", "latitude", arg, "deg", &v))
			return SSC_EXIT_USAGE;
		if (!(fabs(v) <= PI / 2))
			return ssc_usage_error("heading", "--latitude: '%s' is out of range (-90 to 90 degrees)",
					       arg);
		o->ho.latitude_rad = v;
		return 0;
	case O_MODEL:
		if (!strcmp(arg, "hold"))
			o->ho.bias_model = SSCOPE_HEADING_HOLD;
		else if (!strcmp(arg, "interpolate"))
			o->ho.bias_model = SSCOPE_HEADING_INTERPOLATE;
		else
			return ssc_usage_error("heading", "--bias-model: '%s' is not hold or interpolate",
					       arg);
		return 0;
	case O_INITIAL:
		o->set_initial = true;
		return ssc_arg_quantity("heading", "initial-heading", arg, "deg",
					&o->ho.initial_heading_rad) ?
			       SSC_EXIT_USAGE : 0;
	case O_REF:
		o->ref = arg;
		return 0;
	case O_SENSOR:
		o->sensor = arg;
		return 0;
	case O_ALLAN:
		o->allan = arg;
		return 0;
	case O_ARW:
		o->set_terms = true;
		return ssc_arg_positive("heading", "arw", arg, "rad/sqrt(s)", &o->arw);
	case O_BI:
		o->set_terms = true;
		return ssc_arg_positive("heading", "bias-instability", arg, "rad/s", &o->bi);
	case O_RRW:
		o->set_terms = true;
		return ssc_arg_positive("heading", "rrw", arg, "rad/s^2/sqrt(Hz)", &o->rrw);
	default:
		return ssc_usage_error("heading", "unexpected option");
	}
}

static void init(void *opts)
{
	struct opts *o = opts;

	memset(o, 0, sizeof(*o));
	o->ho.latitude_rad = (double)NAN;
}

/* ------------------------------------------------------------ channels */

static long find(const struct sscope_capture *cap, const char *name)
{
	return sscope_capture_find(cap, name);
}

static bool ends_z(const char *n)
{
	size_t l = strlen(n);

	return l && tolower((unsigned char)n[l - 1]) == 'z';
}

static int pick_axis(const char *cmd, const struct sscope_capture *cap,
		     const char *want, const char *path, long *axis)
{
	long only = -1, z = -1;
	size_t n_rate = 0;

	if (want) {
		*axis = find(cap, want);
		if (*axis < 0) {
			ssc_err(cmd, "%s: no channel '%s' (--axis)", path, want);
			return SSC_EXIT_FAIL;
		}
		if (cap->channels[*axis].col.quantity != SSCOPE_QUANTITY_ANGULAR_RATE) {
			ssc_err(cmd, "%s: channel '%s' is not an angular rate (give its unit, e.g. 'gz [deg/s]' or -u deg/s)",
				path, want);
			return SSC_EXIT_FAIL;
		}
		return 0;
	}
	for (size_t k = 0; k < cap->n_channels; k++) {
		if (cap->channels[k].col.quantity != SSCOPE_QUANTITY_ANGULAR_RATE)
			continue;
		n_rate++;
		only = (long)k;
		if (z < 0 && ends_z(cap->channels[k].col.name))
			z = (long)k;
	}
	*axis = n_rate == 1 ? only : z;
	if (*axis < 0) {
		ssc_err(cmd, "%s: no vertical-axis channel: %s", path,
			n_rate ? "several angular-rate channels and none named ...z; name it with --axis" :
				 "no angular-rate channel (give units, e.g. 'gz [deg/s]' or -u deg/s)");
		return SSC_EXIT_FAIL;
	}
	return 0;
}

static int pick_detect(const char *cmd, const struct sscope_capture *cap,
		       const char *want, long axis, const char *path, long det[3])
{
	if (want) {
		char *s = strdup(want), *save = NULL, *tok;
		int k = 0, rc = 0;

		for (tok = strtok_r(s, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
			if (k == 3 || (det[k] = find(cap, tok)) < 0) {
				rc = 1;
				break;
			}
			k++;
		}
		free(s);
		if (rc || k != 3) {
			ssc_err(cmd, "%s: --detect needs three channels of the capture ('%s')", path,
				want);
			return SSC_EXIT_FAIL;
		}
		return 0;
	}
	for (int pass = 0; pass < 2; pass++) {
		enum sscope_quantity q = pass ? SSCOPE_QUANTITY_ANGULAR_RATE :
						SSCOPE_QUANTITY_ACCELERATION;
		int k = 0;

		for (size_t c = 0; c < cap->n_channels && k < 3; c++)
			if (cap->channels[c].col.quantity == q)
				det[k++] = (long)c;
		if (k == 3)
			return 0;
	}
	det[0] = det[1] = det[2] = axis;
	return 0;
}

/* ------------------------------------------------------------ run */

struct res {
	const char *path;
	struct opts o;
	struct sscope_heading_result *r;
	const struct sscope_capture *cap;
	long axis, det[3], ref;
	double fs;
	const double *refv;
	bool have_cmp;
	struct sscope_heading_cmp cmp, cmp_once;
	struct ssc_nav_terms terms;
	const char *terms_from;
};

static double compass(double rad)
{
	double d = fmod(rad / D2R, 360);

	return d < 0 ? d + 360 : d;
}

static double tm(const struct res *s, size_t i)
{
	return s->cap->time_s ? s->cap->time_s[i] : (double)i / s->fs;
}

static json_t *cmp_json(const struct sscope_heading_cmp *c)
{
	json_t *o = json_object();

	json_object_set_new(o, "rms_deg", ssc_jreal(c->rms_rad / D2R));
	json_object_set_new(o, "max_deg", ssc_jreal(c->max_abs_rad / D2R));
	json_object_set_new(o, "final_deg", ssc_jreal(c->final_rad / D2R));
	json_object_set_new(o, "inside_2sigma", ssc_jreal(c->inside_2sigma));
	return o;
}

static json_t *make_json(const char *path, const struct opts *o, const struct res *s)
{
	const struct sscope_heading_result *r = s->r;
	json_t *root = json_object(), *det = json_object(), *dc = json_array();
	json_t *stops = json_array(), *fin = json_object();
	size_t last = r->n - 1;

	json_object_set_new(root, "command", json_string("heading"));
	json_object_set_new(root, "file", json_string(path));
	json_object_set_new(root, "axis", json_string(s->cap->channels[s->axis].col.name));
	json_object_set_new(root, "axis_direction", json_string(o->axis_up ? "up" : "down"));
	json_object_set_new(root, "rate_hz", json_real(s->fs));
	json_object_set_new(root, "samples", json_integer((json_int_t)r->n));
	for (int k = 0; k < 3; k++)
		json_array_append_new(dc, json_string(s->cap->channels[s->det[k]].col.name));
	json_object_set_new(det, "channels", dc);
	json_object_set_new(det, "window_s", json_real(o->ho.window_s > 0 ? o->ho.window_s : 1));
	json_object_set_new(det, "min_stop_s",
			    json_real(o->ho.min_static_s > 0 ? o->ho.min_static_s : 2));
	json_object_set_new(det, "k", json_real(o->ho.k > 0 ? o->ho.k : 3));
	json_object_set_new(det, "rule", json_string(o->ho.init_static_s > 0 ?
						     "reference = variance magnitude of the initial still period" :
						     "reference = 10th percentile of the variance magnitude"));
	json_object_set_new(det, "reference", ssc_jreal(r->reference));
	json_object_set_new(det, "threshold", ssc_jreal(r->threshold));
	json_object_set_new(root, "detector", det);
	json_object_set_new(root, "bias_model", json_string(
		o->ho.bias_model == SSCOPE_HEADING_INTERPOLATE ? "interpolate" : "hold"));
	json_object_set_new(root, "latitude_deg", isnan(o->ho.latitude_rad) ? json_null() :
					  json_real(o->ho.latitude_rad / D2R));
	json_object_set_new(root, "earth_rate_deg_h", json_real(r->earth_rate_rad_s / D2R * 3600));
	json_object_set_new(root, "noise", ssc_nav_terms_json(&s->terms));
	json_object_set_new(root, "noise_from", json_string(s->terms_from));
	for (size_t j = 0; j < r->n_stops; j++) {
		const struct sscope_heading_stop *p = &r->stops[j];
		json_t *q = json_object();

		json_object_set_new(q, "start_s", json_real(tm(s, p->start)));
		json_object_set_new(q, "end_s", json_real(tm(s, p->end - 1) + 1 / s->fs));
		json_object_set_new(q, "bias_deg_h", json_real(p->bias_rad_s / D2R * 3600));
		json_object_set_new(q, "bias_sd_deg_h", ssc_jreal(p->bias_sd_rad_s / D2R * 3600));
		json_object_set_new(q, "sensor_bias_deg_h",
				    ssc_jreal(p->sensor_bias_rad_s / D2R * 3600));
		json_object_set_new(q, "bias_rad_s", json_real(p->bias_rad_s));
		json_array_append_new(stops, q);
	}
	json_object_set_new(root, "stops", stops);
	json_object_set_new(root, "heading_from_s", json_real(tm(s, r->first)));
	json_object_set_new(fin, "t_s", json_real(tm(s, last)));
	json_object_set_new(fin, "heading_deg", ssc_jreal(compass(r->heading_rad[last])));
	json_object_set_new(fin, "sigma_deg", ssc_jreal(r->sigma_rad[last] / D2R));
	json_object_set_new(fin, "heading_first_bias_deg",
			    ssc_jreal(compass(r->heading_once_rad[last])));
	json_object_set_new(fin, "sigma_first_bias_deg", ssc_jreal(r->sigma_once_rad[last] / D2R));
	json_object_set_new(root, "final", fin);
	if (s->have_cmp) {
		json_t *c = json_object();

		json_object_set_new(c, "column", json_string(s->cap->channels[s->ref].col.name));
		json_object_set_new(c, "reestimated", cmp_json(&s->cmp));
		json_object_set_new(c, "first_bias_only", cmp_json(&s->cmp_once));
		json_object_set_new(c, "rms_ratio", ssc_jreal(s->cmp_once.rms_rad / s->cmp.rms_rad));
		json_object_set_new(root, "reference", c);
	} else {
		json_object_set_new(root, "reference", json_null());
	}
	return root;
}

static void write_text(FILE *f, const char *path, const struct opts *o,
		       const struct res *s)
{
	const struct sscope_heading_result *r = s->r;
	size_t last = r->n - 1;
	char a[32], b[32], c[32], buf[256];

	fprintf(f, "%s: heading from %s (axis %s), %zu samples at %s Hz\n", path,
		s->cap->channels[s->axis].col.name, o->axis_up ? "up" : "down", r->n,
		ssc_fmt(a, sizeof(a), s->fs, 6));
	fprintf(f, "  stops: %zu found with %s,%s,%s (window %g s, threshold %g x reference %s)\n",
		r->n_stops, s->cap->channels[s->det[0]].col.name,
		s->cap->channels[s->det[1]].col.name, s->cap->channels[s->det[2]].col.name,
		o->ho.window_s > 0 ? o->ho.window_s : 1, o->ho.k > 0 ? o->ho.k : 3,
		ssc_fmt(a, sizeof(a), r->reference, 3));
	ssc_nav_terms_text(&s->terms, buf, sizeof(buf));
	fprintf(f, "  noise terms for the envelope: %s (%s)\n", buf, s->terms_from);
	if (!isnan(o->ho.latitude_rad))
		fprintf(f, "  vertical Earth rate along the axis: %s deg/h (latitude %g deg), removed from the sensor bias\n",
			ssc_fmt(a, sizeof(a), r->earth_rate_rad_s / D2R * 3600, 4),
			o->ho.latitude_rad / D2R);
	fprintf(f, "  bias between stops: %s\n\n",
		o->ho.bias_model == SSCOPE_HEADING_INTERPOLATE ?
			"interpolated between the stops (post-processing)" :
			"the last stop's (as in real time)");
	fprintf(f, "  %10s %10s %14s %12s %14s\n", "start (s)", "end (s)", "bias (deg/h)",
		"sd (deg/h)", "sensor (deg/h)");
	for (size_t j = 0; j < r->n_stops; j++) {
		const struct sscope_heading_stop *p = &r->stops[j];
		char d[32], e[32];

		fprintf(f, "  %10s %10s %14s %12s %14s\n", ssc_fmt(a, 32, tm(s, p->start), 6),
			ssc_fmt(b, 32, tm(s, p->end - 1) + 1 / s->fs, 6),
			ssc_fmt(c, 32, p->bias_rad_s / D2R * 3600, 5),
			ssc_fmt(d, 32, p->bias_sd_rad_s / D2R * 3600, 3),
			isnan(p->sensor_bias_rad_s) ? "-" :
						      ssc_fmt(e, 32, p->sensor_bias_rad_s / D2R * 3600, 5));
	}
	if (r->first)
		fprintf(f, "\n  no heading before the first stop (%s s): no bias estimate yet\n",
			ssc_fmt(a, sizeof(a), tm(s, r->first), 6));
	fprintf(f, "\n  final heading at %s s: %s deg (1 sigma %s deg); with the first bias only %s deg (1 sigma %s deg)\n",
		ssc_fmt(a, 32, tm(s, last), 6), ssc_fmt(b, 32, compass(r->heading_rad[last]), 6),
		ssc_fmt(c, 32, r->sigma_rad[last] / D2R, 3),
		ssc_fmt(buf, 32, compass(r->heading_once_rad[last]), 6),
		ssc_fmt(buf + 32, 32, r->sigma_once_rad[last] / D2R, 3));
	if (s->have_cmp) {
		fprintf(f, "\n  error against %s:  %14s %14s\n",
			s->cap->channels[s->ref].col.name, "re-estimated", "first bias");
		fprintf(f, "    %-28s %14s %14s\n", "rms (deg)",
			ssc_fmt(a, 32, s->cmp.rms_rad / D2R, 4),
			ssc_fmt(b, 32, s->cmp_once.rms_rad / D2R, 4));
		fprintf(f, "    %-28s %14s %14s\n", "max |error| (deg)",
			ssc_fmt(a, 32, s->cmp.max_abs_rad / D2R, 4),
			ssc_fmt(b, 32, s->cmp_once.max_abs_rad / D2R, 4));
		fprintf(f, "    %-28s %14s %14s\n", "final (deg)",
			ssc_fmt(a, 32, s->cmp.final_rad / D2R, 4),
			ssc_fmt(b, 32, s->cmp_once.final_rad / D2R, 4));
		fprintf(f, "    %-28s %14s %14s\n", "time inside +-2 sigma",
			isnan(s->cmp.inside_2sigma) ? "-" : ssc_fmt(a, 32, s->cmp.inside_2sigma, 3),
			isnan(s->cmp_once.inside_2sigma) ? "-" :
							   ssc_fmt(b, 32, s->cmp_once.inside_2sigma, 3));
		fprintf(f, "    re-estimating at the stops makes the rms error %s times smaller\n",
			ssc_fmt(a, 32, s->cmp_once.rms_rad / s->cmp.rms_rad, 3));
		if (s->cmp.inside_2sigma < 0.8)
			fprintf(f, "    the error outgrows the noise terms' envelope: the bias changes between\n"
				   "    stops by more than noise (temperature?); see the stop biases above\n");
	}
}

static void write_csv(FILE *f, const struct res *s)
{
	const struct sscope_heading_result *r = s->r;

	fprintf(f, "time [s],heading [deg],heading_first_bias [deg],sigma [deg],sigma_first_bias [deg],still%s\n",
		s->have_cmp ? ",reference [deg],error [deg],error_first_bias [deg]" : "");
	for (size_t i = r->first; i < r->n; i++) {
		fprintf(f, "%.10g,%.8g,%.8g,%.6g,%.6g,%d", tm(s, i), compass(r->heading_rad[i]),
			compass(r->heading_once_rad[i]), r->sigma_rad[i] / D2R,
			r->sigma_once_rad[i] / D2R, r->still[i]);
		if (s->have_cmp)
			fprintf(f, ",%.8g,%.6g,%.6g", compass(s->refv[i]),
				remainder(r->heading_rad[i] - s->refv[i], 2 * PI) / D2R,
				remainder(r->heading_once_rad[i] - s->refv[i], 2 * PI) / D2R);
		fputc('\n', f);
	}
}

/* unwrapped degrees of a wrapped heading series from `first` */
static void unwrap(const double *h, size_t first, size_t n, double *out)
{
	double prev = 0;

	for (size_t i = 0; i < n; i++) {
		if (i < first || !isfinite(h[i])) {
			out[i] = (double)NAN;
			continue;
		}
		out[i] = i == first ? h[i] / D2R :
				      prev + remainder(h[i] / D2R - prev, 360);
		prev = out[i];
	}
}

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *path)
{
	const struct res *s = result;
	const struct sscope_heading_result *r = s->r;
	size_t n = r->n;
	struct ssc_fig *fig = ssc_fig_new(1100, 1150, 2, 1);
	double *t = malloc(n * sizeof(double)), *y1 = malloc(n * sizeof(double));
	double *y2 = malloc(n * sizeof(double)), *y3 = malloc(n * sizeof(double));
	double *lo = malloc(n * sizeof(double)), *hi = malloc(n * sizeof(double));
	double ymin = INFINITY, ymax = -INFINITY;
	int rc = 0;

	if (!fig || !t || !y1 || !y2 || !y3 || !lo || !hi) {
		rc = -ENOMEM;
		goto out;
	}
	for (size_t i = 0; i < n; i++)
		t[i] = tm(s, i);
	ssc_fig_title(fig, "heading from the vertical gyro, bias re-estimated at every stop");
	{
		struct ssc_ax *ax = ssc_fig_ax(fig, 0, 0);
		struct ssc_style a = { .color = ssc_plot_color(0), .width = 2 };
		struct ssc_style b = { .color = ssc_plot_color(1), .width = 1.5, .dash = SSC_DASHED };
		struct ssc_style c = { .color = 0x111111, .width = 1 };

		unwrap(r->heading_rad, r->first, n, y1);
		unwrap(r->heading_once_rad, r->first, n, y2);
		if (s->have_cmp) {
			unwrap(s->refv, r->first, n, y3);
			/* the reference on the branch of the estimate */
			if (r->first < n) {
				double sh = 360 * round((y1[r->first] - y3[r->first]) / 360);

				for (size_t i = r->first; i < n; i++)
					y3[i] += sh;
			}
		}
		for (size_t i = r->first; i < n; i++) {
			ymin = fmin(ymin, fmin(y1[i], y2[i]));
			ymax = fmax(ymax, fmax(y1[i], y2[i]));
		}
		for (size_t j = 0; j < r->n_stops; j++) {
			const struct sscope_heading_stop *p = &r->stops[j];
			size_t m = p->end - p->start;
			double *bl = malloc(m * sizeof(double)), *bh = malloc(m * sizeof(double));

			if (bl && bh) {
				for (size_t i = 0; i < m; i++) {
					bl[i] = ymin;
					bh[i] = ymax;
				}
				ssc_ax_band(ax, t + p->start, bl, bh, m, 0x7f7f7f, 0.25,
					    j ? NULL : "stops");
			}
			free(bl);
			free(bh);
		}
		if (s->have_cmp)
			ssc_ax_line(ax, t, y3, n, &c, "reference");
		ssc_ax_line(ax, t, y2, n, &b, "first bias only");
		ssc_ax_line(ax, t, y1, n, &a, "re-estimated at stops");
		ssc_ax_xlabel(ax, "time (s)");
		ssc_ax_ylabel(ax, "heading (deg, unwrapped)");
		ssc_ax_legend(ax, SSC_LEGEND_AUTO);
	}
	{
		struct ssc_ax *ax = ssc_fig_ax(fig, 1, 0);
		struct ssc_style a = { .color = ssc_plot_color(0), .width = 2 };
		struct ssc_style b = { .color = ssc_plot_color(1), .width = 1.5, .dash = SSC_DASHED };

		for (size_t i = 0; i < n; i++) {
			hi[i] = 2 * r->sigma_rad[i] / D2R;
			lo[i] = -hi[i];
		}
		ssc_ax_band(ax, t, lo, hi, n, ssc_plot_color(0), 0.15, "+-2 sigma predicted");
		for (size_t i = 0; i < n; i++) {
			hi[i] = r->sigma_rad[i] / D2R;
			lo[i] = -hi[i];
		}
		ssc_ax_band(ax, t, lo, hi, n, ssc_plot_color(0), 0.2, "+-1 sigma");
		if (s->have_cmp) {
			for (size_t i = 0; i < n; i++) {
				y1[i] = i < r->first ? (double)NAN :
					remainder(r->heading_rad[i] - s->refv[i], 2 * PI) / D2R;
				y2[i] = i < r->first ? (double)NAN :
					remainder(r->heading_once_rad[i] - s->refv[i], 2 * PI) / D2R;
			}
			ssc_ax_line(ax, t, y2, n, &b, "error, first bias only");
			ssc_ax_line(ax, t, y1, n, &a, "error, re-estimated");
		}
		ssc_ax_xlabel(ax, "time (s)");
		ssc_ax_ylabel(ax, s->have_cmp ? "heading error (deg)" : "predicted error (deg)");
		ssc_ax_legend(ax, SSC_LEGEND_UL);
	}
	rc = ssc_fig_save(fig, path);
out:
	ssc_fig_free(fig);
	free(t);
	free(y1);
	free(y2);
	free(y3);
	free(lo);
	free(hi);
	(void)opts;
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

/* noise terms: options, then an allan result, a spec, the scene's allan */
static int terms(const struct ssc_stage_env *env, const struct opts *o,
		 const char *axis_name, struct res *s)
{
	const char *cmd = env->co->cmd;
	const struct ssc_result *up = ssc_stage_upstream(env, &ssc_allan_stage, NULL);

	memset(&s->terms, 0, sizeof(s->terms));
	s->terms.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	s->terms.n_lo = s->terms.n_hi = (double)NAN;
	s->terms_from = "N from the scatter within the stops";
	if (o->set_terms) {
		s->terms.coef[SSCOPE_TERM_N] = o->arw;
		s->terms.coef[SSCOPE_TERM_B] = o->bi;
		s->terms.coef[SSCOPE_TERM_K] = o->rrw;
		s->terms_from = "options";
	} else if (o->allan || up) {
		json_t *root = NULL;
		struct ssc_nav_terms *t;
		const struct ssc_nav_terms *p;
		size_t n;
		int rc;

		if (o->allan) {
			rc = ssc_nav_load_json(cmd, "from-allan", o->allan, &root);
			if (!rc)
				rc = ssc_nav_terms_from_allan(cmd, root, o->allan, &t,
							      &n);
			json_decref(root);
		} else {
			rc = ssc_nav_terms_from_allan_res(cmd, up->data,
							  "the allan stage", &t, &n);
		}
		if (rc)
			return rc;
		p = ssc_nav_terms_pick(t, n, axis_name, SSCOPE_QUANTITY_ANGULAR_RATE);
		if (!p) {
			free(t);
			ssc_err(cmd, "%s: no gyro channel", o->allan ? o->allan : "allan");
			return SSC_EXIT_FAIL;
		}
		s->terms = *p;
		free(t);
		s->terms_from = "allan";
	} else if (o->sensor) {
		struct sscope_sensor_spec sp;
		int rc = ssc_load_sensor(cmd, o->sensor, &sp);

		if (rc)
			return rc;
		if (sp.quantity != SSCOPE_QUANTITY_ANGULAR_RATE) {
			ssc_err(cmd, "%s: not a gyro specification", o->sensor);
			return SSC_EXIT_FAIL;
		}
		ssc_nav_terms_from_spec(&sp, &s->terms);
		s->terms_from = "sensor spec";
	} else if (env->sensor && env->sensor->quantity == SSCOPE_QUANTITY_ANGULAR_RATE) {
		/* a scene's [sensor], when it is a gyro */
		ssc_nav_terms_from_spec(env->sensor, &s->terms);
		s->terms_from = "sensor spec";
	}
	return SSC_EXIT_OK;
}

static void free_result(void *result)
{
	struct res *s = result;

	sscope_heading_result_free(s->r);
	free(s);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const char *cmd = env->co->cmd, *path = env->paths[0];
	const struct sscope_capture *cap = env->caps[0];
	struct res *s = calloc(1, sizeof(*s));
	struct opts *o;
	struct sscope_diag d = { "" };
	const double *det[3];
	int rc;

	if (!s) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = s;
	s->path = path;
	s->o = *(struct opts *)opts;
	o = &s->o;
	s->cap = cap;
	s->ref = -1;
	s->fs = cap->rate_hz;
	rc = ssc_time_check(env->co, path, cap, true);
	if (rc)
		return rc;
	if (!(s->fs > 0))
		return ssc_err_no_rate(cmd, path, cap->rate_note);
	rc = pick_axis(cmd, cap, o->axis, path, &s->axis);
	if (!rc)
		rc = pick_detect(cmd, cap, o->detect, s->axis, path, s->det);
	if (rc)
		return rc;
	if (o->ref) {
		s->ref = find(cap, o->ref);
		if (s->ref < 0) {
			ssc_err(cmd, "%s: no channel '%s' (--reference)", path, o->ref);
			return SSC_EXIT_FAIL;
		}
		if (cap->channels[s->ref].col.quantity != SSCOPE_QUANTITY_ANGLE) {
			ssc_err(cmd, "%s: reference '%s' is not an angle (give its unit, e.g. 'heading_ref [deg]')",
				path, o->ref);
			return SSC_EXIT_FAIL;
		}
		s->refv = cap->channels[s->ref].data;
	}
	rc = terms(env, o, cap->channels[s->axis].col.name, s);
	if (rc)
		return rc;
	memcpy(o->ho.coef, s->terms.coef, sizeof(o->ho.coef));
	o->ho.rate_hz = s->fs;
	o->ho.axis_up = o->axis_up;
	for (int k = 0; k < 3; k++)
		det[k] = cap->channels[s->det[k]].data;
	rc = sscope_heading_compute(cap->channels[s->axis].data, 1, cap->n, det, 1,
				    &o->ho, &s->r, &d);
	if (rc)
		return ssc_nav_fail(cmd, rc, &d, path);
	/* without --initial-heading, start from the reference */
	if (!o->set_initial && s->refv)
		sscope_heading_set_initial(s->r, s->refv[s->r->first]);
	if (s->r->coef_from_stops)
		memcpy(s->terms.coef, s->r->coef, sizeof(s->terms.coef));
	if (s->r->first > 0)
		ssc_warn(env->co, "%s: the record moves for %g s before the first stop: no heading there",
			 path, (double)s->r->first / s->fs);
	if (s->refv) {
		s->have_cmp = sscope_heading_compare(s->r->heading_rad, s->r->sigma_rad,
						     s->refv, 1, cap->n, s->r->first,
						     &s->cmp) == 0 &&
			      sscope_heading_compare(s->r->heading_once_rad,
						     s->r->sigma_once_rad, s->refv, 1,
						     cap->n, s->r->first,
						     &s->cmp_once) == 0;
	}
	return SSC_EXIT_OK;
}

static json_t *json(const void *opts, const void *result)
{
	const struct res *s = result;

	(void)opts;
	return make_json(s->path, &s->o, s);
}

static void text(FILE *f, const void *opts, const void *result)
{
	const struct res *s = result;

	(void)opts;
	write_text(f, s->path, &s->o, s);
}

static void csv(FILE *f, const void *opts, const void *result)
{
	(void)opts;
	write_csv(f, result);
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct res *s = result;
	const char *ax = s->cap->channels[s->axis].col.name;

	(void)opts;
	ssc_summary_add(rows, ax, "stops found", (double)s->r->n_stops, NAN, NAN,
			"", "static detector of calib");
	ssc_summary_add(rows, ax, "predicted heading error at the end, 1 sigma",
			s->r->sigma_rad[s->r->n - 1] / D2R, NAN, NAN, "deg",
			s->terms_from);
	if (s->have_cmp) {
		ssc_summary_add(rows, ax, "heading error rms, re-estimated at stops",
				s->cmp.rms_rad / D2R, NAN, NAN, "deg",
				"against the reference");
		ssc_summary_add(rows, ax, "heading error rms, first bias only",
				s->cmp_once.rms_rad / D2R, NAN, NAN, "deg",
				"against the reference");
	}
}

const struct ssc_stage_ops ssc_heading_stage = {
	.spec = &spec,
	.title = "Heading from a vertical gyro",
	.needs = SSC_NEED_DATA,
	.min_files = 1,
	.max_files = 1,
	.opts_size = sizeof(struct opts),
	.init = init,
	.handle = handler,
	.run = run,
	.json = json,
	.text = text,
	.csv = csv,
	.summary = summary,
	.plot = plot,
	.free_result = free_result,
};

int ssc_cmd_heading(int argc, char **argv)
{
	return ssc_stage_main(&ssc_heading_stage, argc, argv);
}
