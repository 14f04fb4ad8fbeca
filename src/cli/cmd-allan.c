/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope allan: Allan-family deviations of each channel with
 * confidence intervals, the five IEEE 952 noise coefficients with
 * intervals and the classic read-offs; text, JSON (its encoder is
 * ssc_allan_json(), allan-json.c), CSV, a log-log plot and the noise
 * files of Kalibr, OpenVINS and imu_utils (noise-export.c).
 */
#include "cli.h"
#include "results.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "noise-export.h"
#include "plot.h"

enum {
	OPT_DEV = 2000,
	OPT_TAUS,
	OPT_INPUT,
	OPT_CI,
	OPT_KALIBR,
	OPT_NOISE_TYPE,
	OPT_TERMS,
	OPT_FIT_TAU,
	OPT_MODEL_ERROR,
	OPT_STRIDE,
	OPT_NO_FIT,
	OPT_DEV_UNIT,
	OPT_THREADS,
	OPT_OPENVINS,
	OPT_IMU_UTILS,
	OPT_INFLATE,
	OPT_FORCE,
	OPT_DAVAR,
	OPT_EXPORT,
};

static const struct ssc_option allan_opts[] = {
	{ "dev", required_argument, OPT_DEV, "NAME",
	  "oadev (default), adev, mdev, tdev, hdev, ohdev, totdev, mtotdev, htotdev, ttotdev, theo1, theobr, theoh, mtie or tierms" },
	{ "taus", required_argument, OPT_TAUS, "GRID",
	  "dense (default, about 10 per decade), octave, decade (1-2-4) or all" },
	{ "input", required_argument, OPT_INPUT, "rate|angle",
	  "the samples are a rate (default) or an angle (integrated rate)" },
	{ "ci", required_argument, OPT_CI, "LEVEL|none",
	  "confidence level of the intervals (default 0.683)" },
	{ "export", required_argument, OPT_EXPORT, "TARGET[:FILE]",
	  "write the noise parameters a consumer reads, in its own convention (repeatable): kalibr, imu_utils, openvins, vins, orbslam3, basalt, gtsam, matlab, gnss_ins_sim, gazebo; FILE defaults per target (see the manual)" },
	{ "kalibr", required_argument, OPT_KALIBR, "PATH.yaml",
	  "write Kalibr's IMU noise parameters (largest axis per sensor; = --export kalibr:PATH)" },
	{ "openvins", required_argument, OPT_OPENVINS, "PATH.yaml",
	  "write OpenVINS' kalibr_imu_chain.yaml (needs gyro and accelerometer channels)" },
	{ "imu-utils", required_argument, OPT_IMU_UTILS, "PATH.yaml",
	  "write the imu_utils parameter YAML (per axis and avg-axis; *_w is the random walk K)" },
	{ "inflate", required_argument, OPT_INFLATE, "F",
	  "multiply the exported noise values by F >= 1 (default 1; Kalibr and OpenVINS advise inflating Allan values, e.g. 2-10)" },
	{ "force", no_argument, OPT_FORCE, NULL,
	  "write an export the adequacy check refuses (the record moves, the fit is rejected, a transient, step or temperature drift biases a value), marking each doubtful value in a comment" },
	{ "davar", required_argument, OPT_DAVAR, "PATH.svg|png",
	  "draw the dynamic Allan deviation (OADEV in sliding windows over the record, against the fitted model) of each channel" },
	{ "noise-type", required_argument, OPT_NOISE_TYPE, "TYPE",
	  "noise for the EDF: auto (default: lag-1 autocorrelation per tau), wpm, fpm, wfm, ffm, rwfm" },
	{ "terms", required_argument, OPT_TERMS, "auto|LIST",
	  "terms the fit may use, e.g. N,B,K (default Q,N,B,K,R; those the presence test finds are reported with an interval)" },
	{ "fit-tau", required_argument, OPT_FIT_TAU, "MIN:MAX",
	  "fit only taus in [MIN, MAX] seconds (either may be empty)" },
	{ "model-error", required_argument, OPT_MODEL_ERROR, "F",
	  "relative error of the five-term model per point (default 0: none)" },
	{ "stride", required_argument, OPT_STRIDE, "K",
	  "with --taus all or decade only (oadev, ohdev): the strided-overlap estimator, terms every m/K samples instead of every sample; faster on long records, at a lower EDF (reported beside the full one)" },
	{ "no-fit", no_argument, OPT_NO_FIT, NULL, "deviations only" },
	{ "dev-unit", required_argument, OPT_DEV_UNIT, "UNIT",
	  "unit of deviations in text and the plot (default: deg/h for gyros, ug for accelerometers, else the channel's) and in CSV (default there: the channel's unit); a unit that fits no channel is an error" },
	{ "threads", required_argument, OPT_THREADS, "N",
	  "threads of the computation (default: all)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "allan",
	.usage = "allan [OPTIONS] FILE...",
	.summary =
		"Allan-family deviations (NIST SP 1065) of every channel with confidence\n"
		"intervals (Greenhall-Riley EDF, as Stable32), and the five IEEE 952 noise\n"
		"terms -- quantization Q, angle/velocity random walk N, bias instability B,\n"
		"rate random walk K, rate ramp R -- fitted to the overlapping Allan\n"
		"variance by weighted least squares; which terms are present is decided\n"
		"by likelihood-ratio tests of nested fits (one-sided, 0.135 %), each present\n"
		"term with its interval, each other with an upper bound and the reason; the\n"
		"classic slope read-offs are shown where the term dominates and EDF >= 10.",
	.options = allan_opts,
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope allan samples/gyro-static.csv\n"
		 "  sensorscope allan --plot allan.png --kalibr imu.yaml samples/gyro-static.csv\n"
		 "  sensorscope allan --export vins --export gazebo:imu.sdf --inflate 2 imu.bag\n"
		 "  sensorscope allan --dev mdev --taus octave --format json log.csv\n"
		 "  sensorscope allan --input angle -u deg -r 100 angle.csv\n"
		 "Taus with too few terms are dropped as Stable32 does (ADEV, OADEV, TOTDEV:\n"
		 "m <= (N-1)/2 phase points; MDEV, TDEV, MTOTDEV, TTOTDEV: m <= N/3; HDEV,\n"
		 "OHDEV, HTOTDEV: m <= (N-1)/3; Theo1, TheoBR: even m from 10 to N-1, at\n"
		 "tau = 0.75 m/rate; TheoH: OADEV to 10 % of the record, TheoBR beyond; MTIE,\n"
		 "TIE rms: m <= N-1, no interval).  The total, Theo and time-error deviations\n"
		 "refuse NaN gaps (exit 1).\n"
		 "NaN cells (with --allow-nan) are gaps: terms touching them are skipped, the\n"
		 "variance averages the complete terms (Sesia & Tavella 2008) and the EDF counts\n"
		 "only those; taus left without a complete term are omitted with a warning.",
};

struct args {
	struct sscope_allan_opts ao;
	struct sscope_noise_fit_opts fo;
	enum sscope_allan_tau_grid grid;
	struct ssc_export_req exp[SSC_EXPORT_MAX];
	size_t n_exp;
	const char *davar;
	bool force;
	double inflate;
	const char *dev_unit;
	bool no_fit;
	double ci;
};

/* what the result's JSON says of the options */
static struct ssc_allan_json_opts json_opts(const struct args *a)
{
	return (struct ssc_allan_json_opts){
		.input = a->ao.input,
		.dev = a->ao.dev,
		.ci = a->ci,
		.no_fit = a->no_fit,
		.model_error = a->fo.model_error,
		.two_threads = a->ao.threads != 1,
	};
}

static int parse_terms(const char *arg, unsigned *mask)
{
	const char *p = arg;

	*mask = 0;
	if (!strcmp(arg, "auto"))
		return 0;
	while (*p) {
		static const char names[] = "QNBKR";
		const char *c = strchr(names, *p);

		if (!c || !*c)
			return -1;
		*mask |= 1u << (c - names);
		p++;
		if (*p == ',')
			p++;
		else if (*p)
			return -1;
	}
	return *mask ? 0 : -1;
}

static int handler(int key, const char *arg, void *ctx)
{
	struct args *a = ctx;

	switch (key) {
	case OPT_DEV:
		if (sscope_allan_dev_parse(arg, &a->ao.dev))
			return ssc_usage_error("allan",
					       "--dev: '%s' is not oadev, adev, mdev, tdev, hdev, ohdev, totdev, mtotdev, htotdev, ttotdev, theo1, theobr, theoh, mtie or tierms",
					       arg);
		return 0;
	case OPT_TAUS:
		if (!strcmp(arg, "dense"))
			a->grid = SSCOPE_ALLAN_TAUS_DENSE;
		else if (!strcmp(arg, "octave"))
			a->grid = SSCOPE_ALLAN_TAUS_OCTAVE;
		else if (!strcmp(arg, "decade"))
			a->grid = SSCOPE_ALLAN_TAUS_DECADE;
		else if (!strcmp(arg, "all"))
			a->grid = SSCOPE_ALLAN_TAUS_ALL;
		else
			return ssc_usage_error("allan",
					       "--taus: '%s' is not dense, octave, decade or all",
					       arg);
		return 0;
	case OPT_INPUT:
		if (!strcmp(arg, "rate"))
			a->ao.input = SSCOPE_ALLAN_RATE;
		else if (!strcmp(arg, "angle"))
			a->ao.input = SSCOPE_ALLAN_ANGLE;
		else
			return ssc_usage_error("allan",
					       "--input: '%s' is not rate or angle",
					       arg);
		return 0;
	case OPT_CI:
		if (!strcmp(arg, "none")) {
			a->ci = -1;
			return 0;
		}
		if (ssc_arg_double("allan", "ci", arg, &a->ci))
			return SSC_EXIT_USAGE;
		if (!(a->ci > 0 && a->ci < 1))
			return ssc_usage_error("allan",
					       "--ci: %s is not a level between 0 and 1 (e.g. 0.683, 0.95) or none",
					       arg);
		return 0;
	case OPT_EXPORT:
	case OPT_KALIBR:
	case OPT_OPENVINS:
	case OPT_IMU_UTILS:
		return ssc_export_parse(key == OPT_EXPORT ? "export" :
					key == OPT_KALIBR ? "kalibr" :
					key == OPT_OPENVINS ? "openvins" : "imu-utils",
					arg, a->exp, &a->n_exp);
	case OPT_FORCE:
		a->force = true;
		return 0;
	case OPT_DAVAR:
		if (ssc_plot_format_of(arg) == SSC_PLOT_NONE)
			return ssc_usage_error("allan",
					       "--davar: '%s' does not end in .svg or .png",
					       arg);
		a->davar = arg;
		return 0;
	case OPT_INFLATE:
		if (ssc_arg_double("allan", "inflate", arg, &a->inflate))
			return SSC_EXIT_USAGE;
		if (!(a->inflate >= 1 && a->inflate <= 1000))
			return ssc_usage_error("allan",
					       "--inflate: %s is not a factor between 1 and 1000",
					       arg);
		return 0;
	case OPT_NOISE_TYPE: {
		static const char *const n[] = { "wpm", "fpm", "wfm", "ffm",
						 "rwfm" };

		if (!strcmp(arg, "auto")) {
			a->ao.alpha_fixed = false;
			return 0;
		}
		for (int i = 0; i < 5; i++)
			if (!strcmp(arg, n[i])) {
				a->ao.alpha_fixed = true;
				a->ao.alpha = 2 - i;
				return 0;
			}
		return ssc_usage_error("allan",
				       "--noise-type: '%s' is not auto, wpm, fpm, wfm, ffm or rwfm",
				       arg);
	}
	case OPT_TERMS:
		if (parse_terms(arg, &a->fo.allowed))
			return ssc_usage_error("allan",
					       "--terms: '%s' is not auto or a list of Q, N, B, K, R",
					       arg);
		return 0;
	case OPT_FIT_TAU: {
		const char *c = strchr(arg, ':');
		char lo[64];

		if (!c || (size_t)(c - arg) >= sizeof(lo))
			return ssc_usage_error("allan",
					       "--fit-tau: '%s' is not MIN:MAX", arg);
		memcpy(lo, arg, (size_t)(c - arg));
		lo[c - arg] = '\0';
		if ((lo[0] && ssc_arg_double("allan", "fit-tau", lo,
					     &a->fo.tau_min_s)) ||
		    (c[1] && ssc_arg_double("allan", "fit-tau", c + 1,
					    &a->fo.tau_max_s)))
			return SSC_EXIT_USAGE;
		if (a->fo.tau_min_s < 0 || a->fo.tau_max_s < 0 ||
		    (a->fo.tau_max_s > 0 && a->fo.tau_max_s <= a->fo.tau_min_s))
			return ssc_usage_error("allan",
					       "--fit-tau: need 0 <= MIN < MAX");
		return 0;
	}
	case OPT_MODEL_ERROR:
		if (ssc_arg_double("allan", "model-error", arg, &a->fo.model_error))
			return SSC_EXIT_USAGE;
		if (a->fo.model_error < 0 || a->fo.model_error >= 1)
			return ssc_usage_error("allan",
					       "--model-error: %s is not in [0, 1)", arg);
		if (a->fo.model_error == 0)
			a->fo.model_error = -1; /* the library's "none" */
		return 0;
	case OPT_STRIDE:
		if (ssc_arg_size("allan", "stride", arg, &a->ao.stride_div))
			return SSC_EXIT_USAGE;
		if (a->ao.stride_div == 0)
			return ssc_usage_error("allan", "--stride: must be at least 1");
		return 0;
	case OPT_NO_FIT:
		a->no_fit = true;
		a->fo.skip = true;
		return 0;
	case OPT_DEV_UNIT: {
		struct sscope_unit u;

		if (sscope_unit_parse(arg, &u, NULL))
			return ssc_usage_error("allan",
					       "--dev-unit: '%s' is not a unit", arg);
		a->dev_unit = arg;
		return 0;
	}
	case OPT_THREADS: {
		size_t t;

		if (ssc_arg_size("allan", "threads", arg, &t))
			return SSC_EXIT_USAGE;
		if (t == 0 || t > 1024)
			return ssc_usage_error("allan", "--threads: 1..1024");
		a->ao.threads = (unsigned)t;
		return 0;
	}
	default:
		return ssc_usage_error("allan", "unexpected option");
	}
}

/* ------------------------------------------------------------------ */

static double unit_scale(const char *text)
{
	struct sscope_unit u;

	if (sscope_unit_parse(text, &u, NULL))
		return NAN;
	return u.scale;
}

static void set_units(const struct args *a, const struct sscope_capture_column *col,
		      struct ssc_allan_units *u)
{
	static const char *const fmt[5] = { "%s*s", "%s/sqrt(Hz)", "%s",
					    "%s/s/sqrt(Hz)", "%s/s" };
	bool angle = a->ao.input == SSCOPE_ALLAN_ANGLE;
	const char *lab = col->unit_label;
	struct sscope_unit ru;

	memset(u, 0, sizeof(*u));
	u->rq = sscope_allan_rate_quantity(col->quantity, a->ao.input);
	if (angle) {
		snprintf(u->rate, sizeof(u->rate), "%s/s", lab[0] ? lab : "1");
	} else {
		snprintf(u->rate, sizeof(u->rate), "%s", lab[0] ? lab : "1");
	}
	if (sscope_unit_parse(u->rate, &ru, NULL) ||
	    sscope_unit_si_string(&ru, u->rate_si, sizeof(u->rate_si)))
		snprintf(u->rate_si, sizeof(u->rate_si), "%s", u->rate);
	/* TDEV is an angle: the channel's unit for angle input, rate * s
	 * otherwise */
	if (sscope_allan_dev_is_time(a->ao.dev) && angle)
		snprintf(u->dev, sizeof(u->dev), "%s", lab[0] ? lab : "1");
	else if (sscope_allan_dev_is_time(a->ao.dev)) {
		size_t l = strlen(u->rate);

		/* a rate per second times s: the angle's unit (deg/s*s is deg) */
		if (l > 2 && !strcmp(u->rate + l - 2, "/s") && !strchr(u->rate, '*'))
			snprintf(u->dev, sizeof(u->dev), "%.*s", (int)(l - 2), u->rate);
		else
			snprintf(u->dev, sizeof(u->dev), "%s*s", u->rate);
	}
	else
		snprintf(u->dev, sizeof(u->dev), "%s", u->rate);
	u->dev_scale = unit_scale(u->dev);
	/* shown unit: --dev-unit, or the conventional bias unit */
	if (a->dev_unit) {
		struct sscope_unit want, have;

		sscope_unit_parse(a->dev_unit, &want, NULL);
		sscope_unit_parse(u->dev, &have, NULL);
		if (sscope_unit_compatible(&want, &have))
			snprintf(u->show, sizeof(u->show), "%s", a->dev_unit);
	}
	if (!u->show[0]) {
		const char *b = sscope_term_unit(u->rq, SSCOPE_TERM_B);

		snprintf(u->show, sizeof(u->show), "%s",
			 b && !sscope_allan_dev_is_time(a->ao.dev) ? b : u->dev);
	}
	u->show_scale = unit_scale(u->show);
	for (int t = 0; t < 5; t++) {
		const char *c = sscope_term_unit(u->rq, (enum sscope_term)t);
		const char *s = sscope_term_si_unit(u->rq, (enum sscope_term)t);

		if (c && s) {
			snprintf(u->term[t], sizeof(u->term[t]), "%s", c);
			snprintf(u->term_si[t], sizeof(u->term_si[t]), "%s", s);
		} else {
			snprintf(u->term[t], sizeof(u->term[t]), fmt[t], u->rate);
			snprintf(u->term_si[t], sizeof(u->term_si[t]), fmt[t],
				 u->rate_si);
		}
	}
}

/* significant digits that tell the ends of [lo, hi] apart (3 at least) */
static int idigits(double v, double lo, double hi)
{
	double w = hi - lo, a = fmax(fabs(v), fabs(hi));
	int d = 3;

	if (w > 0 && a > 0 && isfinite(w) && isfinite(a))
		d = (int)ceil(log10(a / w)) + 2;
	return d < 3 ? 3 : d > 8 ? 8 : d;
}

/* what the adequacy check says beside a term: "" when nothing */
static const char *term_mark(const struct ssc_allan_chan *c, int t)
{
	if (!c->adq)
		return "";
	if (c->adq->verdict == SSCOPE_ADEQUACY_INVALID)
		return "  <- NOT VALID (see adequacy)";
	if ((c->adq->doubtful >> t) & 1)
		return "  <- doubtful (see adequacy)";
	return "";
}

/* The adequacy of a channel in text: a summary line, then one line per
 * finding. */
static void text_adequacy(FILE *f, const struct ssc_allan_chan *c)
{
	const struct sscope_adequacy *q = c->adq;
	char b1[32], b2[32];

	if (!q)
		return;
	fprintf(f, "  adequacy: %s: ", q->verdict == SSCOPE_ADEQUACY_INVALID ?
		"NOT VALID" : q->verdict == SSCOPE_ADEQUACY_DOUBT ? "DOUBTFUL" :
		q->verdict == SSCOPE_ADEQUACY_BOUND ? "valid, some terms only bounded" :
		"valid");
	if (q->still_tested && !isfinite(q->contrast))
		fprintf(f, "%s (1 s variance zero in places, not in others), ",
			q->still ? "still" : "moves");
	else if (q->still_tested)
		fprintf(f, "%s (1 s variance spans %s times, at most %s), ",
			q->still ? "still" : "moves",
			ssc_fmt(b1, sizeof(b1), q->contrast, 3),
			ssc_fmt(b2, sizeof(b2), q->max_contrast, 3));
	if (q->have_fit)
		fprintf(f, "fit %s (p %s), ", q->fit_rejected ? "rejected" : "accepted",
			ssc_fmt_p(b1, sizeof(b1), q->fit_p_value));
	fprintf(f, "%s\n", !q->stationarity_tested ? "stationarity not tested" :
		q->stationary ? "stationary" : "not stationary");
	for (size_t i = 0; i < q->n_findings; i++)
		fprintf(f, "  adequacy (%s): %s\n",
			sscope_adequacy_severity_name(q->findings[i].severity),
			q->findings[i].message);
}

/* Results of extreme samples (1e308 deg/s) can be finite in SI and
 * beyond the double range in the units shown (deg/h): an error, never
 * "inf" in a table.  Returns an exit code. */
static int check_shown(const struct ssc_common *co, const struct args *a,
		       const char *path, const struct ssc_allan_chan *c)
{
	const struct ssc_allan_units *u = &c->u;
	double dmax = 0;

	for (size_t i = 0; i < c->res->n_points; i++) {
		const struct sscope_allan_point *p = &c->res->points[i];

		if (isfinite(p->dev_hi) && p->dev_hi > dmax)
			dmax = p->dev_hi;
		if (isfinite(p->dev) && p->dev > dmax)
			dmax = p->dev;
	}
	if (!isfinite(dmax / u->dev_scale) || !isfinite(dmax / u->show_scale)) {
		ssc_err(co->cmd, "%s: %s: deviations up to %g %s exceed the double range in %s; give --dev-unit %s",
			path, c->col->name, dmax, u->rate_si,
			isfinite(dmax / u->dev_scale) ? u->show : u->dev,
			u->rate_si);
		return SSC_EXIT_FAIL;
	}
	if (a->no_fit || !c->res->have_fit)
		return SSC_EXIT_OK;
	for (int t = 0; t < 5; t++) {
		const struct sscope_noise_coef *cf = &c->res->fit.coef[t];
		double v = fmax(isfinite(cf->value) ? cf->value : 0,
				isfinite(cf->hi) ? cf->hi : 0);

		if (v > 0 && !isfinite(ssc_allan_in_unit(v, u->term_si[t], u->term[t]))) {
			ssc_err(co->cmd, "%s: %s: the %c term (up to %g %s) exceeds the double range in %s; give --no-fit",
				path, c->col->name, "QNBKR"[t], v, u->term_si[t],
				u->term[t]);
			return SSC_EXIT_FAIL;
		}
	}
	return SSC_EXIT_OK;
}

static bool inertial(enum sscope_quantity q)
{
	return q == SSCOPE_QUANTITY_ANGULAR_RATE || q == SSCOPE_QUANTITY_ACCELERATION;
}

/* The adequacy check of a channel's fit (what the record supports):
 * stillness, fit, length of each term, stationarity, the DAVAR map. */
static int check_adequacy(const struct ssc_common *co, const struct args *a,
			  const char *path, const struct sscope_capture *cap,
			  size_t k, struct ssc_allan_chan *c,
			  const struct ssc_allan_chan *moving)
{
	struct sscope_adequacy_opts qo = { 0 };
	struct sscope_diag d = { "" };
	unsigned allowed = a->fo.allowed ? a->fo.allowed : 0x1fu;
	int rc;

	qo.rate_hz = cap->rate_hz;
	qo.angle = a->ao.input == SSCOPE_ALLAN_ANGLE;
	qo.unit = c->u.rate_si;
	qo.temp_degc = cap->temp_degc;
	qo.temp_stride = 1;
	/* the terms a summary and the exporters read */
	qo.requested = allowed & ((1u << SSCOPE_TERM_N) | (1u << SSCOPE_TERM_B) |
				  (1u << SSCOPE_TERM_K));
	if (!qo.requested)
		qo.requested = allowed;
	if (moving) {
		qo.moving_channel = moving->col->name;
		qo.moving_contrast = moving->adq->contrast;
	}
	sscope_adequacy_free(c->adq);
	c->adq = NULL;
	rc = sscope_adequacy_check(cap->channels[k].data, 1, cap->n, cap->rate_hz > 0 &&
				   c->res->have_fit ? &c->res->fit : NULL,
				   &qo, &c->adq, &d);
	if (rc) {
		ssc_err(co->cmd, "%s: %s: adequacy check: %s", path, c->col->name,
			d.msg[0] ? d.msg : sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	return SSC_EXIT_OK;
}

static int analyse_file(const struct ssc_common *co, const struct args *a,
			const char *path, struct sscope_capture *cap,
			struct sscope_noise_plan *plan, bool last_file,
			struct ssc_allan_file *fr)
{
	struct sscope_noise_fit_opts fo = a->fo;
	int rc;

	fr->path = path;
	fr->cap = cap;
	rc = ssc_time_check(co, path, cap, true);
	if (rc)
		return rc;
	if (!(cap->rate_hz > 0)) {
		return ssc_err_no_rate(co->cmd, path, cap->rate_note);
	}
	if (cap->has_timing && cap->timing.n_gaps)
		ssc_warn(co, "%s: %zu time-stamp gaps (about %zu samples missing): deviations assume uniform sampling; mark missing samples as NaN rows and use --allow-nan",
			 path, cap->timing.n_gaps, cap->timing.n_missing);
	fr->n_ch = cap->n_channels;
	/* the channels share the fit's covariance sums (one length, rate
	 * and tau grid) */
	fo.plan = plan;
	fr->ch = calloc(fr->n_ch ? fr->n_ch : 1, sizeof(*fr->ch));
	if (!fr->ch) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	for (size_t k = 0; k < cap->n_channels; k++) {
		struct ssc_allan_chan *c = &fr->ch[k];
		struct sscope_diag d = { "" };
		struct sscope_allan_opts ao = a->ao;

		c->col = &cap->channels[k].col;
		c->n = cap->n;
		c->nan = cap->channels[k].n_nan;
		set_units(a, c->col, &c->u);
		/* a rate read as an angle gives deviations of its derivative */
		if (a->ao.input == SSCOPE_ALLAN_ANGLE &&
		    (c->col->quantity == SSCOPE_QUANTITY_ANGULAR_RATE ||
		     c->col->quantity == SSCOPE_QUANTITY_ACCELERATION))
			ssc_warn(co, "%s: channel %s is in %s, a rate, but --input angle: its deviations come out in %s; drop --input angle for a rate record",
				 path, c->col->name, c->col->unit_label, c->u.dev);
		ao.ci_level = a->ci;
		/* a capture used in place gives its pages back behind the
		 * phase pass */
		if (sscope_capture_mapped(cap, cap->channels[k].data))
			ao.plan_flags |= SSCOPE_ALLAN_EVICT_INPUT;
		/* samples the reader left unchecked are checked here */
		ao.reject_nan = cap->values_unchecked && !co->allow_nan;
		/* the last channel's workspace is not used again: its pages
		 * go back on every core instead of at exit on one */
		if (last_file && k + 1 == cap->n_channels)
			ao.plan_flags |= SSCOPE_ALLAN_RELEASE_WORKSPACE;
		rc = sscope_allan_analyze(cap->channels[k].data, 1, cap->n,
					  cap->rate_hz, a->grid, &ao, &fo,
					  &c->res, &d);
		if (rc && cap->values_unchecked) {
			int e = ssc_check_values(co, cap);

			if (e)
				return e;
		}
		if (rc) {
			ssc_err(co->cmd, "%s: %s: %s", path, c->col->name,
				d.msg[0] ? d.msg : sscope_strerror(rc));
			return rc == -EINVAL ? SSC_EXIT_USAGE : SSC_EXIT_FAIL;
		}
		rc = check_shown(co, a, path, c);
		if (rc)
			return rc;
		if (c->res->n_gap_omitted)
			ssc_warn(co, "%s: %s: %s", path, c->col->name,
				 c->res->gap_note.msg);
		if (a->no_fit)
			continue;
		if (!c->res->have_fit)
			ssc_warn(co, "%s: %s: %s", path, c->col->name, ssc_allan_fit_msg(c));
		rc = check_adequacy(co, a, path, cap, k, c, NULL);
		if (rc)
			return rc;
	}
	/* one sensor: when an inertial channel moves, the others' records
	 * are not still either (a gyro axis across a rate table's axis sees
	 * little of the motion), so they are checked again saying so */
	if (!a->no_fit) {
		const struct ssc_allan_chan *mv = NULL;

		for (size_t k = 0; k < fr->n_ch && !mv; k++)
			if (fr->ch[k].adq && fr->ch[k].adq->still_tested &&
			    !fr->ch[k].adq->still && inertial(fr->ch[k].u.rq))
				mv = &fr->ch[k];
		for (size_t k = 0; mv && k < fr->n_ch; k++) {
			struct ssc_allan_chan *c = &fr->ch[k];

			if (c == mv || !c->adq || !c->adq->still ||
			    !inertial(c->u.rq))
				continue;
			rc = check_adequacy(co, a, path, cap, k, c, mv);
			if (rc)
				return rc;
		}
	}
	return SSC_EXIT_OK;
}

/* ------------------------------------------------------------------ */
/* Text                                                                */
/* ------------------------------------------------------------------ */

static const char *const term_names[5] = {
	"quantization", "random walk", "bias instability", "rate random walk",
	"rate ramp"
};

static const char *term_label(enum sscope_quantity q, int t)
{
	if (t == 1)
		return q == SSCOPE_QUANTITY_ANGULAR_RATE ? "angle random walk" :
		       q == SSCOPE_QUANTITY_ACCELERATION ? "velocity random walk" :
						      "random walk";
	if (t == 0)
		return q == SSCOPE_QUANTITY_ANGULAR_RATE ? "angle quantization" :
		       q == SSCOPE_QUANTITY_ACCELERATION ? "velocity quantization" :
						      "quantization";
	return term_names[t];
}

static void text_chan(FILE *f, const struct args *a, const struct ssc_allan_file *fr,
		      const struct ssc_allan_chan *c)
{
	const struct sscope_allan_result *r = c->res;
	const struct ssc_allan_units *u = &c->u;
	double ci = a->fo.ci_level;
	char b1[32], b2[32], b3[32], b4[32], b5[32];

	fprintf(f, "%s: %s (%s, %s input), %s Hz, %zu samples (%s s)",
		strcmp(fr->path, "-") ? fr->path : "(stdin)", c->col->name,
		c->col->unit_label[0] ? c->col->unit_label : "no unit",
		a->ao.input == SSCOPE_ALLAN_ANGLE ? "angle" : "rate",
		ssc_fmt(b1, sizeof(b1), fr->cap->rate_hz, 8), c->n,
		ssc_fmt(b2, sizeof(b2), (double)c->n / fr->cap->rate_hz, 6));
	if (c->nan)
		fprintf(f, ", %zu NaN (gaps)", c->nan);
	fputc('\n', f);
	if (a->ci > 0)
		fprintf(f, "  %12s %9s %11s  %14s  %-27s %10s  %s\n", "tau (s)",
			"m", "terms", sscope_allan_dev_name(a->ao.dev), "interval",
			"edf", "noise");
	else
		fprintf(f, "  %12s %9s %11s  %14s  %10s  %s\n", "tau (s)", "m",
			"terms", sscope_allan_dev_name(a->ao.dev), "edf", "noise");
	fprintf(f, "  %12s %9s %11s  %14s\n", "", "", "", u->show);
	for (size_t i = 0; i < r->n_points; i++) {
		const struct sscope_allan_point *p = &r->points[i];
		double s = u->dev_scale / u->show_scale;

		fprintf(f, "  %12s %9zu %11zu  %14s",
			ssc_fmt(b1, sizeof(b1), p->tau_s, 6), p->m, p->terms,
			ssc_fmt(b2, sizeof(b2), p->dev / u->dev_scale * s, 5));
		if (a->ci >= 0 && !sscope_allan_dev_has_ci(a->ao.dev)) {
			fprintf(f, "  %-27s", "none (no EDF model)");
		} else if (a->ci >= 0) {
			snprintf(b5, sizeof(b5), "[%s, %s]",
				 ssc_fmt(b3, sizeof(b3), p->dev_lo / u->dev_scale * s, 4),
				 ssc_fmt(b4, sizeof(b4), p->dev_hi / u->dev_scale * s, 4));
			fprintf(f, "  %-27s", b5);
		}
		if (!sscope_allan_dev_has_ci(a->ao.dev)) {
			fprintf(f, " %10s  %s\n", "-", "-");
			continue;
		}
		fprintf(f, " %10s  %s%s\n", ssc_fmt(b1, sizeof(b1), p->edf, 4),
			ssc_allan_noise_name(p->alpha), p->alpha_identified ? "" :
			a->ao.alpha_fixed ? " (given)" : " (carried)");
	}
	if (a->ao.stride_div && r->n_points)
		fprintf(f, "  strided estimator: terms every m/%zu samples; EDF of the last point %s instead of %s (full overlap)\n",
			a->ao.stride_div,
			ssc_fmt(b1, sizeof(b1), r->points[r->n_points - 1].edf, 4),
			ssc_fmt(b2, sizeof(b2), r->points[r->n_points - 1].edf_full, 4));
	if (a->no_fit)
		return;
	if (!r->have_fit) {
		fprintf(f, "  noise terms: not fitted: %s\n", ssc_allan_fit_msg(c));
		text_adequacy(f, c);
		return;
	}
	{
		const struct sscope_noise_fit *ft = &r->fit;
		char sel[16] = "", selw[320];
		size_t k = 0;

		for (int t = 0; t < 5; t++)
			if (ft->terms & (1u << t)) {
				sel[k++] = "QNBKR"[t];
				sel[k++] = ' ';
			}
		if (k)
			sel[k - 1] = '\0';
		fprintf(f, "  IEEE 952 noise terms (fit on OADEV; %s: %s; %s%% intervals from the fit of every allowed term; chi2 %s for %s dof, bootstrap p %s):\n",
			ssc_allan_select_words(ft, selw, sizeof(selw)), k ? sel : "none",
			ssc_fmt(b1, sizeof(b1), 100 * ci, 3),
			ssc_fmt(b2, sizeof(b2), ft->chi2, 3),
			ssc_fmt(b3, sizeof(b3), ft->dof, 3),
			ssc_fmt_p(b4, sizeof(b4), ft->p_value));
		for (int t = 0; t < 5; t++) {
			const struct sscope_noise_coef *cf = &ft->coef[t];
			const char *cu = u->term[t], *su = u->term_si[t];

			int dg = idigits(cf->value, cf->lo, cf->hi);

			if (cf->fitted)
				fprintf(f, "    %c  %-22s %11s %-16s [%s, %s]   (%s %s)%s\n",
					"QNBKR"[t], term_label(u->rq, t),
					ssc_fmt(b1, sizeof(b1), ssc_allan_in_unit(cf->value, su, cu), dg + 1),
					cu,
					ssc_fmt(b2, sizeof(b2), ssc_allan_in_unit(cf->lo, su, cu), dg),
					ssc_fmt(b3, sizeof(b3), ssc_allan_in_unit(cf->hi, su, cu), dg),
					ssc_fmt(b4, sizeof(b4), cf->value, dg + 1), su,
					term_mark(c, t));
			else if (cf->why == SSCOPE_NOISE_NOT_ALLOWED)
				fprintf(f, "    %c  %-22s %11s %-16s (not fitted: %s)\n",
					"QNBKR"[t], term_label(u->rq, t), "-", cu,
					ssc_allan_absent_reason(cf));
			else if (isfinite(cf->hi) && cf->hi > 0)
				fprintf(f, "    %c  %-22s %11s %-16s (not shown present: below %s; %s)%s\n",
					"QNBKR"[t], term_label(u->rq, t), "-", cu,
					ssc_fmt(b1, sizeof(b1), ssc_allan_in_unit(cf->hi, su, cu), 3),
					ssc_allan_absent_reason(cf), term_mark(c, t));
			else
				fprintf(f, "    %c  %-22s %11s %-16s (not shown present, and this record gives it no finite bound; %s)\n",
					"QNBKR"[t], term_label(u->rq, t), "-", cu,
					ssc_allan_absent_reason(cf));
		}
		/* the classic read-offs, where the fitted model says each term
		 * dominates (or that it dominates nowhere) */
		fprintf(f, "  classic read-offs%s where the fit says the term dominates (a present term, at least 3/4 of the fitted model with the others at their upper bounds, EDF >= 10):",
			c->adq && c->adq->verdict == SSCOPE_ADEQUACY_INVALID ?
			" (NOT VALID: see adequacy)" : "");
		if (isfinite(ft->readoff.n))
			fprintf(f, " N = sigma(1 s) on the -1/2 line through tau = %s s: %s %s;",
				ssc_fmt(b3, sizeof(b3), ft->readoff.n_tau_s, 4),
				ssc_fmt(b1, sizeof(b1), ssc_allan_in_unit(ft->readoff.n, u->term_si[1], u->term[1]), 4),
				u->term[1]);
		else
			fprintf(f, " N: %s;", ssc_allan_readoff_absent(ft, 1));
		if (isfinite(ft->readoff.b))
			fprintf(f, " B = sigma/0.6643 at the bottom, tau = %s s: %s %s;",
				ssc_fmt(b3, sizeof(b3), ft->readoff.b_tau_s, 4),
				ssc_fmt(b2, sizeof(b2), ssc_allan_in_unit(ft->readoff.b, u->term_si[2], u->term[2]), 4),
				u->term[2]);
		else
			fprintf(f, " B: %s;", ssc_allan_readoff_absent(ft, 2));
		if (isfinite(ft->readoff.k))
			fprintf(f, " K = sigma(3 s) on the +1/2 line through tau = %s s: %s %s\n",
				ssc_fmt(b3, sizeof(b3), ft->readoff.k_tau_s, 4),
				ssc_fmt(b4, sizeof(b4), ssc_allan_in_unit(ft->readoff.k, u->term_si[3], u->term[3]), 4),
				u->term[3]);
		else
			fprintf(f, " K: %s\n", ssc_allan_readoff_absent(ft, 3));
	}
	{
		struct ssc_allan_warn w[7];
		struct ssc_allan_json_opts jo = json_opts(a);
		size_t nw = ssc_allan_chan_warnings(&jo, c, w, 7);

		for (size_t i = 0; i < nw; i++)
			fprintf(f, "  warning: %s\n", w[i].msg);
	}
	text_adequacy(f, c);
}

/* ------------------------------------------------------------------ */
/* CSV                                                                */
/* ------------------------------------------------------------------ */

static void csv_file(FILE *f, const struct args *a, const struct ssc_allan_file *fr)
{
	for (size_t k = 0; k < fr->n_ch; k++) {
		const struct ssc_allan_chan *c = &fr->ch[k];
		const char *un = a->dev_unit ? c->u.show : c->u.dev;
		double s = c->u.dev_scale / unit_scale(un);

		for (size_t i = 0; i < c->res->n_points; i++) {
			const struct sscope_allan_point *p = &c->res->points[i];

			if (!sscope_allan_dev_has_ci(a->ao.dev)) {
				/* MTIE, TIE rms: no interval, EDF or noise type */
				fprintf(f, "%s,%s,%s,%s,%.10g,%zu,%zu,%.10g,,,,\n",
					fr->path, c->col->name,
					sscope_allan_dev_name(a->ao.dev), un, p->tau_s,
					p->m, p->terms, p->dev / c->u.dev_scale * s);
				continue;
			}
			fprintf(f, "%s,%s,%s,%s,%.10g,%zu,%zu,%.10g,%.10g,%.10g,%.6g,%d\n",
				fr->path, c->col->name, sscope_allan_dev_name(a->ao.dev),
				un, p->tau_s, p->m, p->terms,
				p->dev / c->u.dev_scale * s,
				p->dev_lo / c->u.dev_scale * s,
				p->dev_hi / c->u.dev_scale * s, p->edf, p->alpha);
		}
	}
}

/* ------------------------------------------------------------------ */
/* Noise files for estimators                                          */
/* ------------------------------------------------------------------ */

/* the DAVAR map of every channel, one panel each (at most 12) */
static int davar_plot(const struct ssc_common *co, const struct args *a,
		      const struct ssc_allan_res *R, const char *path)
{
	const struct ssc_allan_chan *ch[12];
	size_t n = 0;
	struct ssc_fig *fig;
	int rc = 0;

	(void)a;
	for (size_t i = 0; i < R->n_files; i++)
		for (size_t k = 0; k < R->fr[i].n_ch; k++) {
			const struct ssc_allan_chan *c = &R->fr[i].ch[k];

			if (!c->adq || !c->adq->davar.n_win) {
				ssc_warn(co, "--davar: %s: %s: no map: the record is too short for windows of 64 samples",
					 R->fr[i].path, c->col->name);
				continue;
			}
			if (n == 12) {
				ssc_warn(co, "--davar: more than 12 channels; the figure shows the first 12");
				break;
			}
			ch[n++] = c;
		}
	if (!n) {
		ssc_err(co->cmd, "--davar: no channel has a map");
		return SSC_EXIT_FAIL;
	}
	fig = ssc_fig_new(1050, (int)(n * 380 + 60), (int)n, 1);
	if (!fig) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	ssc_fig_title(fig, "dynamic Allan deviation (OADEV in sliding windows)");
	for (size_t p = 0; p < n && !rc; p++) {
		char t[256];

		snprintf(t, sizeof(t), "%s: windows of %.4g s every %.4g s",
			 ch[p]->col->name, ch[p]->adq->davar.window_s,
			 ch[p]->adq->davar.step_s);
		rc = ssc_plot_davar(ssc_fig_ax(fig, (int)p, 0), ch[p]->adq, t);
	}
	if (!rc)
		rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

static int write_exports(const struct ssc_common *co, const void *opts,
			 const void *result)
{
	const struct args *a = opts;
	const struct ssc_allan_res *R = result;
	int rc;

	if (a->davar) {
		rc = davar_plot(co, a, R, a->davar);
		if (rc)
			return rc;
	}
	return ssc_export_allan(co, R, a->exp, a->n_exp, a->inflate, a->force);
}

/* ------------------------------------------------------------------ */
/* Plot                                                                */
/* ------------------------------------------------------------------ */

/* y range of a channel's points and intervals, in the shown unit */
static void chan_range(const struct ssc_allan_chan *c, double *lo, double *hi)
{
	const struct ssc_allan_units *u = &c->u;
	double s = 1 / u->show_scale;

	*lo = INFINITY;
	*hi = 0;
	for (size_t i = 0; i < c->res->n_points; i++) {
		const struct sscope_allan_point *p = &c->res->points[i];

		if (!(p->dev > 0))
			continue;
		*lo = fmin(*lo, p->dev * s);
		if (p->dev_lo > 0)
			*lo = fmin(*lo, p->dev_lo * s);
		*hi = fmax(*hi, p->dev * s);
		if (isfinite(p->dev_hi))
			*hi = fmax(*hi, p->dev_hi * s);
	}
}

/* The deviation of one channel with its intervals, the fitted model, each
 * resolved term (B's plateau drawn at its height 0.664 B and labelled so),
 * each unresolved term as an upper bound (dotted, down-pointing triangles)
 * and the coefficients in a box beside the axes. */
static int plot_chan(struct ssc_ax *ax, const struct args *a,
		     const struct ssc_allan_chan *c, double ylo, double yhi, double tlo,
		     double thi)
{
	const struct sscope_allan_result *r = c->res;
	const struct ssc_allan_units *u = &c->u;
	size_t n = r->n_points, k = 0;
	double *x = calloc(n + 1, sizeof(double)), *y = calloc(n + 1, sizeof(double));
	double *lo = calloc(n + 1, sizeof(double)), *hi = calloc(n + 1, sizeof(double));
	double s = 1 / u->show_scale, tmin = INFINITY, tmax = 0;
	char buf[512], un[96], upper[16] = "", lv[32] = "";
	struct ssc_style pst = { .color = 0x1f77b4, .width = -1,
				 .marker = SSC_MK_CIRCLE, .marker_size = 6 };
	static const uint32_t tcol[5] = { 0x9467bd, 0xd62728, 0x2ca02c,
					  0xff7f0e, 0x8c564b };

	if (!x || !y || !lo || !hi) {
		free(x);
		free(y);
		free(lo);
		free(hi);
		return -ENOMEM;
	}
	for (size_t i = 0; i < n; i++) {
		const struct sscope_allan_point *p = &r->points[i];

		if (!(p->dev > 0))
			continue;
		x[k] = p->tau_s;
		y[k] = p->dev * s;
		lo[k] = isfinite(p->dev_lo) ? p->dev_lo * s : y[k];
		hi[k] = isfinite(p->dev_hi) ? p->dev_hi * s : y[k];
		tmin = fmin(tmin, p->tau_s);
		tmax = fmax(tmax, p->tau_s);
		k++;
	}
	ssc_unit_pretty(u->show, un, sizeof(un));
	ssc_ax_log(ax, true, true);
	ssc_ax_grid(ax, true);
	ssc_ax_xlabel(ax, "averaging time \xcf\x84 (s)");
	snprintf(upper, sizeof(upper), "%s", sscope_allan_dev_label(a->ao.dev));
	if (sscope_allan_dev_has_ci(a->ao.dev))
		snprintf(buf, sizeof(buf), "%s \xcf\x83(\xcf\x84) (%s)", upper, un);
	else
		snprintf(buf, sizeof(buf), "%s(\xcf\x84) (%s)", upper, un);
	ssc_ax_ylabel(ax, buf);
	ssc_ax_title(ax, c->col->name);
	if (a->ci >= 0)
		ssc_fmt(lv, sizeof(lv), 100 * a->ci, 3);
	if (k) {
		/* the data decide the range (shared by the channels of one
		 * unit); term lines are clipped */
		if (isfinite(ylo) && yhi > ylo)
			ssc_ax_ylim(ax, ylo / 2, yhi * 2);
		ssc_ax_xlim(ax, tlo / 1.5, thi * 1.5);
		if (a->ci >= 0 && sscope_allan_dev_has_ci(a->ao.dev))
			snprintf(buf, sizeof(buf), "%s, %s %% intervals", upper, lv);
		else
			snprintf(buf, sizeof(buf), "%s", upper);
		ssc_ax_errorbar(ax, x, y, lo, hi, k, &pst, buf);
	}
	if (k >= 2 && !a->no_fit && r->have_fit) {
		const struct sscope_noise_fit *ft = &r->fit;
		enum { NG = 160 };
		double gx[NG], gy[NG], coef[5];
		char note[1024] = "", v1[32], v2[32], v3[32], cu[96];
		size_t nl = 0;
		struct ssc_style fst = { .color = 0x202020, .width = 2 };

#define NOTE(...)                                                          \
	do {                                                               \
		nl += (size_t)snprintf(note + nl, sizeof(note) - nl, __VA_ARGS__); \
		if (nl >= sizeof(note))                                    \
			nl = sizeof(note) - 1;                             \
	} while (0)
		for (int t = 0; t < 5; t++)
			coef[t] = ft->coef[t].fitted ? ft->coef[t].value : 0;
		for (int i = 0; i < NG; i++) {
			gx[i] = tmin * pow(tmax / tmin, (double)i / (NG - 1));
			gy[i] = sqrt(sscope_noise_avar(coef, gx[i])) * s;
		}
		ssc_ax_line(ax, gx, gy, NG, &fst, "fitted model");
		for (int t = 0; t < 5; t++) {
			const struct sscope_noise_coef *cf = &ft->coef[t];
			double one[5] = { 0 }, bound;
			struct ssc_style dst = { .color = tcol[t], .width = 1.8,
						 .dash = SSC_DASHED };
			int dg;

			ssc_unit_pretty(u->term[t], cu, sizeof(cu));
			if (sscope_noise_coef_resolved(cf)) {
				one[t] = cf->value;
				for (int i = 0; i < NG; i++)
					gy[i] = sqrt(sscope_noise_avar(one, gx[i])) * s;
				ssc_fmt(v1, sizeof(v1),
					ssc_allan_in_unit(cf->value, u->term_si[t], u->term[t]), 3);
				if (t == SSCOPE_TERM_B)
					snprintf(buf, sizeof(buf),
						 "B = %s %s (line at 0.664\xc2\xb7" "B)",
						 v1, cu);
				else
					snprintf(buf, sizeof(buf), "%c = %s %s",
						 "QNBKR"[t], v1, cu);
				ssc_ax_line(ax, gx, gy, NG, &dst, buf);
				dg = idigits(cf->value, cf->lo, cf->hi);
				NOTE("%s%c %s [%s, %s] %s", nl ? "\n" : "", "QNBKR"[t],
				     ssc_fmt(v1, sizeof(v1), ssc_allan_in_unit(cf->value, u->term_si[t], u->term[t]), dg),
				     ssc_fmt(v2, sizeof(v2), ssc_allan_in_unit(cf->lo, u->term_si[t], u->term[t]), dg),
				     ssc_fmt(v3, sizeof(v3), ssc_allan_in_unit(cf->hi, u->term_si[t], u->term[t]), dg),
				     cu);
				continue;
			}
			/* unresolved: the bound the data put on the term */
			bound = cf->hi;
			if (!(isfinite(bound) && bound > 0))
				continue;
			one[t] = bound;
			for (int i = 0; i < NG; i++)
				gy[i] = sqrt(sscope_noise_avar(one, gx[i])) * s;
			ssc_fmt(v1, sizeof(v1), ssc_allan_in_unit(bound, u->term_si[t], u->term[t]), 3);
			snprintf(buf, sizeof(buf), "%c < %s %s (upper bound%s)",
				 "QNBKR"[t], v1, cu,
				 t == SSCOPE_TERM_B ? "; line at 0.664\xc2\xb7" "B" : "");
			{
				struct ssc_style bst = { .color = tcol[t],
							 .width = 1.2,
							 .dash = SSC_DOTTED };
				double mx[NG / 20 + 2], my[NG / 20 + 2];
				size_t nm = 0;

				/* a power law is straight on log-log axes: a
				 * few points draw it, each with a marker */
				bst.marker = SSC_MK_TRIANGLE_DOWN;
				bst.marker_size = 9;
				for (int i = 0; i < NG; i += 20) {
					mx[nm] = gx[i];
					my[nm++] = gy[i];
				}
				mx[nm] = gx[NG - 1];
				my[nm++] = gy[NG - 1];
				ssc_ax_line(ax, mx, my, nm, &bst, buf);
			}
			NOTE("%s%c < %s %s (%s)", nl ? "\n" : "",
			     "QNBKR"[t], v1, cu, cf->present ?
			     "present, interval reaches 0" : "not shown present");
		}
		NOTE("%s\xcf\x87\xc2\xb2 %s for %s dof, bootstrap p %s", nl ? "\n" : "",
		     ssc_fmt(v1, sizeof(v1), ft->chi2, 3),
		     ssc_fmt(v2, sizeof(v2), ft->dof, 3),
		     ssc_fmt_p(v3, sizeof(v3), ft->p_value));
		if (ssc_allan_fit_rejected(ft))
			NOTE("\nFIT REJECTED (p < %g): terms indicative only",
			     SSC_ALLAN_FIT_REJECT_P);
#undef NOTE
		ssc_ax_note(ax, note, SSC_LEGEND_AUTO);
	}
	ssc_ax_legend(ax, SSC_LEGEND_AUTO);
	free(x);
	free(y);
	free(lo);
	free(hi);
	return 0;
}

/* one panel per channel of every file (at most MAX_PANELS), stacked, with
 * one scale for the channels of one unit */
#define MAX_PANELS 12

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *path)
{
	const struct args *a = opts;
	const struct ssc_allan_res *R = result;
	const struct ssc_allan_file *fr = R->fr;
	size_t nfiles = R->n_files;
	size_t n = 0, p = 0;
	const struct ssc_allan_chan *ch[MAX_PANELS];
	double ylo[MAX_PANELS], yhi[MAX_PANELS], tlo = INFINITY, thi = 0;
	struct ssc_fig *fig;
	char title[512];
	int rc = 0;

	for (size_t i = 0; i < nfiles; i++)
		n += fr[i].n_ch;
	if (n == 0)
		return SSC_EXIT_OK;
	if (n > MAX_PANELS) {
		ssc_warn(co, "--plot: %zu channels; the figure shows the first %d",
			 n, MAX_PANELS);
		n = MAX_PANELS;
	}
	for (size_t i = 0; i < nfiles; i++)
		for (size_t k = 0; k < fr[i].n_ch && p < n; k++, p++) {
			ch[p] = &fr[i].ch[k];
			chan_range(ch[p], &ylo[p], &yhi[p]);
			for (size_t j = 0; j < ch[p]->res->n_points; j++)
				if (ch[p]->res->points[j].dev > 0) {
					tlo = fmin(tlo, ch[p]->res->points[j].tau_s);
					thi = fmax(thi, ch[p]->res->points[j].tau_s);
				}
		}
	for (size_t i = 0; i < n; i++)
		for (size_t j = 0; j < n; j++)
			if (!strcmp(ch[i]->u.show, ch[j]->u.show)) {
				ylo[i] = fmin(ylo[i], ylo[j]);
				yhi[i] = fmax(yhi[i], yhi[j]);
			}
	fig = ssc_fig_new(1050, (int)(n * (n > 6 ? 360 : 420) + 60), (int)n, 1);
	if (!fig) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	if (nfiles == 1)
		snprintf(title, sizeof(title), "%s", fr->path);
	else
		snprintf(title, sizeof(title), "%s and %zu more files", fr->path,
			 nfiles - 1);
	ssc_fig_title(fig, title);
	for (p = 0; p < n && !rc; p++)
		rc = plot_chan(ssc_fig_ax(fig, (int)p, 0), a, ch[p], ylo[p],
			       yhi[p], tlo, thi);
	if (!rc)
		rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

/* ------------------------------------------------------------------ */

static void free_file(struct ssc_allan_file *fr)
{
	for (size_t k = 0; k < fr->n_ch; k++) {
		sscope_allan_result_free(fr->ch[k].res);
		sscope_adequacy_free(fr->ch[k].adq);
	}
	free(fr->ch);
}

/* The fitted N, B, K of each channel for a report's summary table; a
 * channel whose terms are not valid (the record moves, the fit is
 * rejected) gets one row that says why instead, and a doubtful term says
 * so in its note. */
static void summarize(json_t *summary, const struct args *a,
		      const struct ssc_allan_file *fr, bool many)
{
	if (a->no_fit || !summary)
		return;
	for (size_t k = 0; k < fr->n_ch; k++) {
		const struct ssc_allan_chan *c = &fr->ch[k];
		const struct sscope_noise_fit *ft = &c->res->fit;
		char note[64], what[64], who[320];
		const char *base = strrchr(fr->path, '/') ? strrchr(fr->path, '/') + 1 : fr->path;

		/* several files: "file: channel", as psd's rows */
		snprintf(who, sizeof(who), "%s%s%s", many ? base : "", many ? ": " : "",
			 c->col->name);

		if (c->adq && c->adq->verdict == SSCOPE_ADEQUACY_INVALID) {
			const struct sscope_adequacy_finding *f = &c->adq->findings[0];
			char nt[560];

			snprintf(nt, sizeof(nt), "not valid: %s", f->message);
			ssc_summary_add(summary, who, "noise terms N, B, K",
					NAN, NAN, NAN, "", nt);
			ssc_summary_warn_last(summary);
			continue;
		}
		if (!c->res->have_fit)
			continue;
		snprintf(note, sizeof(note), "fit, %.3g %% interval",
			 100 * ft->ci_level);
		for (int t = 1; t <= 3; t++) {
			const struct sscope_noise_coef *cf = &ft->coef[t];
			const struct sscope_adequacy_finding *fd = ssc_allan_term_doubt(c, t);
			char nt[640];

			if (!cf->fitted)
				continue;
			snprintf(what, sizeof(what), "%s %c",
				 term_label(c->col->quantity, t), "QNBKR"[t]);
			snprintf(nt, sizeof(nt), "%s%s%s%s%s", note,
				 ssc_allan_fit_rejected(ft) ? "; FIT REJECTED (chi-squared p < 0.01): indicative only" : "",
				 sscope_noise_coef_resolved(cf) ? "" : "; present, but the interval reaches 0",
				 fd ? "; DOUBTFUL: " : "", fd ? fd->message : "");
			ssc_summary_add(summary, who, what,
					ssc_allan_in_unit(cf->value, c->u.term_si[t], c->u.term[t]),
					ssc_allan_in_unit(cf->lo, c->u.term_si[t], c->u.term[t]),
					ssc_allan_in_unit(cf->hi, c->u.term_si[t], c->u.term[t]),
					c->u.term[t], nt);
			if (ssc_allan_fit_rejected(ft) || !sscope_noise_coef_resolved(cf) || fd)
				ssc_summary_warn_last(summary);
		}
	}
}

static void init(void *opts)
{
	struct args *a = opts;

	memset(a, 0, sizeof(*a));
	a->grid = SSCOPE_ALLAN_TAUS_DENSE;
	a->ci = 0.683;
	a->inflate = 1;
}

static int check(struct ssc_common *co, void *opts)
{
	struct args *a = opts;

	if (a->ao.stride_div && a->ao.dev != SSCOPE_ALLAN_DEV_OADEV &&
	    a->ao.dev != SSCOPE_ALLAN_DEV_OHDEV)
		return ssc_usage_error(co->cmd, "--stride applies to oadev and ohdev only");
	/* checked once every option is read (--taus may come after
	 * --stride), here for the command and a scene's [allan] alike */
	if (a->ao.stride_div && a->grid != SSCOPE_ALLAN_TAUS_ALL &&
	    a->grid != SSCOPE_ALLAN_TAUS_DECADE)
		return ssc_usage_error(co->cmd, "--stride pays only with --taus all or decade: on the octave and dense grids it saved no time up to 10^8 samples and lowers the EDF");
	if (a->n_exp && a->no_fit)
		return ssc_usage_error(co->cmd, "%s needs the fit (drop --no-fit)",
				       a->exp[0].option);
	if (a->force && !a->n_exp)
		return ssc_usage_error(co->cmd, "--force applies to an export (--export, --kalibr, --openvins, --imu-utils)");
	if (a->davar && a->no_fit)
		return ssc_usage_error(co->cmd, "--davar needs the fit (drop --no-fit)");
	a->fo.ci_level = a->ci > 0 ? a->ci : 0.683;
	return 0;
}

/* --dev-unit must fit the deviations of a channel: fitting none is a
 * usage error, each channel it does not fit a warning. */
static int check_dev_unit(const struct ssc_common *co, const struct args *a,
			  const struct ssc_stage_env *env)
{
	size_t fit = 0;
	struct ssc_allan_units u;

	for (size_t i = 0; a->dev_unit && i < env->n_caps; i++)
		for (size_t k = 0; k < env->caps[i]->n_channels; k++) {
			set_units(a, &env->caps[i]->channels[k].col, &u);
			fit += !strcmp(u.show, a->dev_unit);
		}
	for (size_t i = 0; a->dev_unit && i < env->n_caps; i++)
		for (size_t k = 0; k < env->caps[i]->n_channels; k++) {
			const struct sscope_capture_column *col = &env->caps[i]->channels[k].col;

			set_units(a, col, &u);
			if (!strcmp(u.show, a->dev_unit))
				continue;
			if (!fit)
				return ssc_usage_error(co->cmd,
						       "--dev-unit: '%s' does not fit the deviations of %s (%s)",
						       a->dev_unit, col->name, u.dev);
			ssc_warn(co, "%s: %s: --dev-unit %s does not fit its deviations (%s): shown in %s",
				 env->paths[i], col->name, a->dev_unit, u.dev, u.show);
		}
	return SSC_EXIT_OK;
}

static void free_result(void *result)
{
	struct ssc_allan_res *R = result;

	for (size_t i = 0; i < R->n_files; i++)
		free_file(&R->fr[i]);
	free(R->fr);
	free(R);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	struct ssc_allan_res *R = calloc(1, sizeof(*R));
	struct sscope_noise_plan *plan = NULL;
	int rc = SSC_EXIT_OK;

	rc = check_dev_unit(env->co, opts, env);
	if (rc) {
		free(R);
		return rc;
	}
	if (R)
		R->fr = calloc(env->n_caps ? env->n_caps : 1, sizeof(*R->fr));
	if (!R || !R->fr) {
		free(R);
		ssc_err(env->co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = R;
	R->ci_level = ((const struct args *)opts)->ci > 0 ?
		      ((const struct args *)opts)->ci : 0;
	R->grid = ((const struct args *)opts)->grid;
	R->ao = ((const struct args *)opts)->ao;
	R->ao.ci_level = ((const struct args *)opts)->ci;
	R->fo = ((const struct args *)opts)->fo;
	if (sscope_noise_plan_new(&plan))
		plan = NULL; /* each fit computes its own */
	for (size_t i = 0; i < env->n_caps && !rc; i++, R->n_files++)
		rc = analyse_file(env->co, opts, env->paths[i], env->caps[i],
				  plan, i + 1 == env->n_caps, &R->fr[i]);
	sscope_noise_plan_free(plan);
	return rc;
}

static json_t *json(const void *opts, const void *result)
{
	struct ssc_allan_json_opts jo = json_opts(opts);

	return ssc_allan_json(&jo, result, NULL);
}

/* the points of ssc_allan_json()'s slots */
struct pts_out {
	const struct ssc_allan_res *R;
	struct ssc_allan_json_opts jo;
};

static bool points_text(FILE *f, size_t slot, void *ctx)
{
	const struct pts_out *po = ctx;

	return ssc_allan_json_points(f, &po->jo, po->R, slot);
}

/* the JSON as json() dumps, the points written as text (a tree of an
 * all-tau grid's points costs more than the analysis) */
static int emit_json(const struct ssc_common *co, const void *opts,
		     const void *result)
{
	struct pts_out po = { result, json_opts(opts) };
	size_t n_slots = 0;
	json_t *root = ssc_allan_json(&po.jo, result, &n_slots);
	int rc;

	rc = ssc_emit_json_slots(co, root, n_slots, points_text, &po);
	if (rc == -EAGAIN)
		rc = ssc_emit_json(co, json(opts, result));
	return rc;
}

static void text(FILE *f, const void *opts, const void *result)
{
	const struct ssc_allan_res *R = result;

	for (size_t i = 0; i < R->n_files; i++)
		for (size_t k = 0; k < R->fr[i].n_ch; k++) {
			if (i || k)
				fputc('\n', f);
			text_chan(f, opts, &R->fr[i], &R->fr[i].ch[k]);
		}
}

static void csv(FILE *f, const void *opts, const void *result)
{
	const struct ssc_allan_res *R = result;

	fprintf(f, "file,channel,deviation,unit,tau_s,m,terms,dev,dev_lo,dev_hi,edf,alpha\n");
	for (size_t i = 0; i < R->n_files; i++)
		csv_file(f, opts, &R->fr[i]);
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct ssc_allan_res *R = result;

	for (size_t i = 0; i < R->n_files; i++)
		summarize(rows, opts, &R->fr[i], R->n_files > 1);
}

const struct ssc_stage_ops ssc_allan_stage = {
	.spec = &spec,
	.title = "Allan deviation and IEEE 952 noise terms",
	.needs = SSC_NEED_DATA,
	.min_files = 1,
	.max_files = -1,
	.opts_size = sizeof(struct args),
	.init = init,
	.handle = handler,
	.check = check,
	.checks_values = true,
	.run = run,
	.json = json,
	.emit_json = emit_json,
	.text = text,
	.csv = csv,
	.summary = summary,
	.plot = plot,
	.write = write_exports,
	.free_result = free_result,
};

int ssc_cmd_allan(int argc, char **argv)
{
	return ssc_stage_main(&ssc_allan_stage, argc, argv);
}
