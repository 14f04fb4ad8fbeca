/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope walk: the random-walk fan of a stationary record (see
 * analysis/sscope-walk.h): runs integrated after bias removal against the
 * +-2 sigma envelope of the channel's noise terms (from `allan` on the
 * same record unless given), the fraction of runs inside against time and
 * the angle random walk the spread implies, beside allan's.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "navcommon.h"
#include "plot.h"
#include "results.h"
#include "stage.h"

#define D2R (PI / 180)
#define N_TABLE 10

enum {
	O_RUN = 300,
	O_BIASW,
	O_SIGMA,
	O_CI,
	O_SENSOR,
	O_ALLAN,
	O_ARW,
	O_BI,
	O_RRW,
	O_PATHS,
	O_CONTRAST,
};

static const struct ssc_option walk_opts[] = {
	{ "run-length", required_argument, O_RUN, "T",
	  "integration length of each run (default: 60 s, shorter when fewer than 20 runs fit)" },
	{ "bias-window", required_argument, O_BIASW, "T",
	  "remove the mean of the T seconds before each run (default: the run length; 0: the record's mean)" },
	{ "sigma", required_argument, O_SIGMA, "K", "envelope half-width in sigmas (default 2)" },
	{ "ci", required_argument, O_CI, "LEVEL",
	  "confidence level of the implied N and of allan's fit (default 0.683)" },
	{ "sensor", required_argument, O_SENSOR, "SPEC.ini", "noise terms from a sensor spec instead of allan" },
	{ "from-allan", required_argument, O_ALLAN, "RESULT.json",
	  "noise terms from an 'allan' result (matched by channel name)" },
	{ "arw", required_argument, O_ARW, "V", "angle (velocity) random walk for the envelope" },
	{ "bias-instability", required_argument, O_BI, "V", "bias instability for the envelope" },
	{ "rrw", required_argument, O_RRW, "V", "rate random walk for the envelope" },
	{ "paths", required_argument, O_PATHS, "N", "runs drawn in the figure (default 100)" },
	{ "contrast", required_argument, O_CONTRAST, "C",
	  "refuse a record whose 1 s variance spans more than C times, i.e. that moves (default 9; 0: no check)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "walk",
	.usage = "walk [OPTIONS] FILE",
	.summary =
		"The random-walk fan of a stationary gyro or accelerometer: the record is\n"
		"cut into runs, each integrated (to angle or velocity) after its bias is\n"
		"removed (the mean of the stretch before it, or the record's mean), and\n"
		"drawn against the +-2 sigma envelope its noise terms predict\n"
		"(angle random walk 2 N sqrt(t), plus the bias-instability and rate-random-\n"
		"walk parts and the error of the removed bias).  Reports the fraction of\n"
		"runs inside the envelope against time and the N the spread implies,\n"
		"beside the N of 'allan' on the same record, with their intervals.",
	.options = walk_opts,
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope walk samples/gyro-static.csv\n"
		 "  sensorscope walk --run-length 2min --bias-window 30s --plot fan.png -c gz samples/gyro-static.csv\n"
		 "Expected inside +-2 sigma: 95.45 %, with a binomial sd of sqrt(0.0434 / runs).",
};

struct opts {
	double run_s, bias_s, k, ci, contrast;
	const char *sensor, *allan;
	const char *arw, *bi, *rrw; /* with units: converted per channel */
	bool set_terms;
	size_t paths;
};

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;

	switch (key) {
	case O_RUN:
		return ssc_arg_positive("walk", "run-length", arg, "s", &o->run_s);
	case O_BIASW:
		if (ssc_arg_quantity("walk", "bias-window", arg, "s", &o->bias_s))
			return SSC_EXIT_USAGE;
		return o->bias_s >= 0 ? 0 : ssc_usage_error("walk", "--bias-window: must not be negative");
	case O_SIGMA:
		if (ssc_arg_double("walk", "sigma", arg, &o->k))
			return SSC_EXIT_USAGE;
		return o->k > 0 ? 0 : ssc_usage_error("walk", "--sigma: must be positive");
	case O_CI:
		if (ssc_arg_double("walk", "ci", arg, &o->ci))
			return SSC_EXIT_USAGE;
		return o->ci > 0 && o->ci < 1 ? 0 :
						ssc_usage_error("walk", "--ci: a level between 0 and 1");
	case O_SENSOR:
		o->sensor = arg;
		return 0;
	case O_ALLAN:
		o->allan = arg;
		return 0;
	case O_ARW:
		o->set_terms = true;
		o->arw = arg;
		return 0;
	case O_BI:
		o->set_terms = true;
		o->bi = arg;
		return 0;
	case O_RRW:
		o->set_terms = true;
		o->rrw = arg;
		return 0;
	case O_PATHS:
		return ssc_arg_size("walk", "paths", arg, &o->paths) ? SSC_EXIT_USAGE : 0;
	case O_CONTRAST:
		if (ssc_arg_double("walk", "contrast", arg, &o->contrast))
			return SSC_EXIT_USAGE;
		return o->contrast == 0 || o->contrast > 1 ? 0 :
			ssc_usage_error("walk", "--contrast: 0 (no check) or more than 1");
	default:
		return ssc_usage_error("walk", "unexpected option");
	}
}

static void init(void *opts)
{
	struct opts *o = opts;

	memset(o, 0, sizeof(*o));
	o->k = 2;
	o->ci = 0.683;
	o->bias_s = -1; /* the run length */
	o->paths = 100;
	o->contrast = 9;
}

/* ------------------------------------------------------------ per channel */

struct chan {
	const struct sscope_capture_column *col;
	double fs;
	size_t n;
	struct sscope_walk_result *w;
	struct ssc_nav_terms terms;  /* used for the envelope */
	const char *terms_from;
	struct ssc_nav_terms allan;  /* allan's fit on the record (have false:
				        not computed) */
	struct sscope_walk_implied im[N_TABLE];
	size_t idx[N_TABLE], n_idx;
	double run_s;
	/* allan on the record: the signed squares of the terms and their
	 * covariance (the envelope and the implied N take them) */
	bool have_sq;
	double sq[5], sq_cov[25];
	char fit_why[160]; /* why allan's fit on the record failed ("" none) */
};

static const char *angle_unit(enum sscope_quantity q)
{
	return q == SSCOPE_QUANTITY_ANGULAR_RATE ? "deg" : "m/s";
}

static double angle_scale(enum sscope_quantity q)
{
	return q == SSCOPE_QUANTITY_ANGULAR_RATE ? 1 / D2R : 1;
}

/* option values in the SI units of the channel's terms */
static int option_terms(const char *cmd, const struct opts *o, enum sscope_quantity q,
			struct ssc_nav_terms *t)
{
	static const enum sscope_term which[3] = { SSCOPE_TERM_N, SSCOPE_TERM_B,
						   SSCOPE_TERM_K };
	static const char *const name[3] = { "arw", "bias-instability", "rrw" };
	const char *v[3] = { o->arw, o->bi, o->rrw };

	memset(t, 0, sizeof(*t));
	t->quantity = q;
	t->n_lo = t->n_hi = (double)NAN;
	for (int i = 0; i < 3; i++) {
		if (!v[i])
			continue;
		if (ssc_arg_quantity(cmd, name[i], v[i], sscope_term_si_unit(q, which[i]),
				     &t->coef[which[i]]))
			return SSC_EXIT_USAGE;
		if (!(t->coef[which[i]] > 0))
			return ssc_usage_error(cmd, "--%s: must be positive", name[i]);
	}
	return 0;
}

/* allan on the record: the resolved terms (shown beside the fan) and for
 * the envelope the fit's estimates of N, B and K, resolved or not (an
 * unresolved rate random walk still makes the runs wander), with Q and
 * the deterministic ramp R only when resolved.  The very computation an
 * earlier allan stage of the scene made on these samples is taken from
 * it; the channels of a capture share the fit's plan. */
static int allan_terms(const struct ssc_stage_env *env, const double *x,
		       size_t n, double fs, enum sscope_quantity q, double ci,
		       struct sscope_noise_plan *plan, struct ssc_nav_terms *t,
		       struct ssc_nav_terms *est, struct chan *ch)
{
	const char *cmd = env->co->cmd;
	const struct sscope_allan_result *done = NULL;
	struct sscope_allan_result *res = NULL;
	struct sscope_allan_opts ao = { 0 };
	struct sscope_noise_fit_opts fo = { 0 };
	struct sscope_diag d = { "" };
	int rc;

	memset(t, 0, sizeof(*t));
	t->quantity = q;
	t->n_lo = t->n_hi = (double)NAN;
	*est = *t;
	ao.ci_level = ci;
	fo.ci_level = ci;
	for (size_t i = 0; i < env->n_earlier && !done; i++)
		if (env->earlier[i].ops == &ssc_allan_stage && env->earlier[i].data)
			done = ssc_allan_res_find(env->earlier[i].data, x, n, fs,
						  SSCOPE_ALLAN_TAUS_DENSE, &ao, &fo);
	if (!done) {
		fo.plan = plan;
		rc = sscope_allan_analyze(x, 1, n, fs, SSCOPE_ALLAN_TAUS_DENSE, &ao, &fo,
					  &res, &d);
		if (rc)
			return ssc_fail(cmd, rc, &d, "allan");
		done = res;
	}
	if (!done->have_fit)
		snprintf(ch->fit_why, sizeof(ch->fit_why), "%.*s",
			 (int)sizeof(ch->fit_why) - 1,
			 done->fit_diag.msg[0] ? done->fit_diag.msg : "failed");
	/* terms from a fit the chi-squared test rejects: said */
	if (done->have_fit && ssc_allan_fit_rejected(&done->fit))
		ssc_warn(env->co, "channel '%s': allan's noise fit on this record is rejected (bootstrap p below %g): the envelope's terms are indicative only (give --arw and the others, or a sensor spec)",
			 ch->col->name, SSC_ALLAN_FIT_REJECT_P);
	if (done->have_fit) {
		for (int i = 0; i < 5; i++) {
			const struct sscope_noise_coef *c = &done->fit.coef[i];

			if (c->fitted && c->value > 0) {
				t->coef[i] = c->value;
				t->have = true;
			}
			/* N, B, K as estimated; Q and the deterministic
			 * ramp R only when present */
			if ((i == SSCOPE_TERM_N || i == SSCOPE_TERM_B ||
			     i == SSCOPE_TERM_K) ? c->estimate > 0 :
						   c->fitted && c->value > 0) {
				est->coef[i] = i == SSCOPE_TERM_N || i == SSCOPE_TERM_B ||
							       i == SSCOPE_TERM_K ?
						       c->estimate :
						       c->value;
				est->have = true;
			}
		}
		/* the signed squares (an estimate^2 floored at 0 is biased
		 * up: the envelope too wide, the implied N too low) and their
		 * covariance, for the same terms */
		ch->have_sq = est->have;
		for (int i = 0; i < 5; i++) {
			bool use = est->coef[i] > 0 || i == SSCOPE_TERM_N ||
				   i == SSCOPE_TERM_B || i == SSCOPE_TERM_K;

			ch->sq[i] = use ? done->fit.coef[i].square : 0;
			for (int j = 0; j < 5; j++)
				ch->sq_cov[i * 5 + j] = use ? done->fit.sq_cov[i][j] : 0;
		}
		t->n_lo = est->n_lo = done->fit.coef[SSCOPE_TERM_N].lo;
		t->n_hi = est->n_hi = done->fit.coef[SSCOPE_TERM_N].hi;
		t->ci_level = est->ci_level = done->fit.ci_level;
	}
	sscope_allan_result_free(res);
	return 0;
}

static int analyse(const struct ssc_stage_env *env, const struct opts *o,
		   const char *path, const struct sscope_capture *cap, size_t k,
		   const struct ssc_nav_terms *given, size_t n_given,
		   struct sscope_noise_plan *plan, struct chan *c)
{
	const char *cmd = env->co->cmd;
	const struct sscope_capture_channel *ch = &cap->channels[k];
	enum sscope_quantity q = ch->col.quantity;
	struct sscope_walk_opts wo = { 0 };
	struct sscope_diag d = { "" };
	double dur;
	int rc;

	c->col = &ch->col;
	c->fs = cap->rate_hz;
	c->n = cap->n;
	dur = (double)cap->n / c->fs;
	/* allan's terms: from a result when there is one, else computed */
	if (n_given) {
		const struct ssc_nav_terms *p = ssc_nav_terms_pick(given, n_given, ch->col.name, q);

		if (!p) {
			ssc_err(cmd, "%s: no noise terms for channel '%s' in %s", path, ch->col.name,
				o->allan ? o->allan : "the allan stage");
			return SSC_EXIT_FAIL;
		}
		if (strcmp(p->name, ch->col.name))
			ssc_warn(env->co, "%s: channel '%s': %s has no channel of that name: the terms of its '%s' are used (the largest N of its channels of this quantity)",
				 path, ch->col.name,
				 o->allan ? o->allan : "the allan stage", p->name);
		c->allan = *p;
		/* the same words for a file and the scene's stage */
		c->terms_from = "allan result";
		c->terms = c->allan;
	} else {
		rc = allan_terms(env, ch->data, cap->n, c->fs, q, o->ci, plan,
				 &c->allan, &c->terms, c);
		if (rc)
			return rc;
		c->terms_from = "allan on this record: N, B, K estimated (signed squares, with their covariance), present or not";
	}
	if (o->set_terms) {
		rc = option_terms(cmd, o, q, &c->terms);
		if (rc)
			return rc;
		if (k == 0)
			ssc_say_bare_numbers(env->co);
		c->terms_from = "options";
		c->have_sq = false;
	} else if (!n_given && (o->sensor || env->sensor)) {
		struct sscope_sensor_spec sp;

		if (o->sensor) {
			rc = ssc_load_sensor(cmd, o->sensor, &sp);
			if (rc)
				return rc;
		} else {
			sp = *env->sensor;
		}
		if (sp.quantity == q) {
			ssc_nav_terms_from_spec(&sp, &c->terms);
			c->terms_from = "sensor spec";
			c->have_sq = false;
		}
	}
	if (!(c->terms.coef[0] > 0 || c->terms.coef[1] > 0 || c->terms.coef[2] > 0 ||
	      c->terms.coef[3] > 0 || c->terms.coef[4] > 0)) {
		ssc_err(cmd, "%s: channel '%s': no noise terms for the envelope (allan's fit: %s; give --arw)",
			path, ch->col.name, c->fit_why[0] ? c->fit_why :
				"no term above zero");
		return SSC_EXIT_FAIL;
	}
	c->run_s = o->run_s;
	if (!(c->run_s > 0)) {
		/* 60 s, or the longest whole second that leaves 20 runs
		 * (with their bias windows) */
		c->run_s = o->bias_s < 0 ? fmin(60, floor(dur / 40)) :
					   fmin(60, floor(dur / 20 - o->bias_s));
		if (c->run_s < 1) {
			if (o->bias_s >= 0)
				ssc_err(cmd, "%s: %g s is too short for 20 runs of 1 s after a %g s bias window each (give a shorter --bias-window, or --run-length)",
					path, dur, o->bias_s);
			else
				ssc_err(cmd, "%s: %g s is too short for 20 runs of 1 s (give --run-length)",
					path, dur);
			return SSC_EXIT_FAIL;
		}
	}
	wo.rate_hz = c->fs;
	wo.run_s = c->run_s;
	wo.bias_s = o->bias_s < 0 ? c->run_s : o->bias_s;
	wo.k_sigma = o->k;
	wo.max_contrast = o->contrast > 0 ? o->contrast : -1;
	/* the figure draws the first o->paths runs */
	wo.keep_paths = o->paths ? o->paths : 1;
	memcpy(wo.coef, c->terms.coef, sizeof(wo.coef));
	if (c->have_sq) {
		wo.have_sq = true;
		memcpy(wo.sq, c->sq, sizeof(wo.sq));
		memcpy(wo.sq_cov, c->sq_cov, sizeof(wo.sq_cov));
	}
	rc = sscope_walk_compute(ch->data, 1, cap->n, &wo, &c->w, &d);
	if (rc)
		return ssc_nav_fail(cmd, rc, &d, path);
	/* N_TABLE points evenly over the run */
	for (size_t j = 1; j <= N_TABLE; j++) {
		size_t i = (size_t)lround((double)j * (double)(c->w->n_points - 1) / N_TABLE);

		if (i == 0 || (c->n_idx && c->idx[c->n_idx - 1] == i))
			continue;
		c->idx[c->n_idx] = i;
		sscope_walk_implied_n(c->w, i, o->ci, &c->im[c->n_idx]);
		c->n_idx++;
	}
	return 0;
}

static json_t *chan_json(const struct opts *o, const struct chan *c)
{
	json_t *j = json_object(), *in = json_object(), *pts = json_array(),
	       *imp = json_array();
	const struct sscope_walk_result *w = c->w;
	enum sscope_quantity q = c->col->quantity;

	json_object_set_new(j, "name", json_string(c->col->name));
	json_object_set_new(j, "unit", json_string(c->col->unit_label));
	json_object_set_new(j, "quantity", json_string(sscope_quantity_name(q)));
	json_object_set_new(j, "rate_hz", json_real(c->fs));
	json_object_set_new(j, "samples", json_integer((json_int_t)c->n));
	json_object_set_new(j, "run_s", json_real((double)(w->n_points - 1) * w->dt_s));
	json_object_set_new(j, "bias", json_string(w->global ? "record mean" : "window before each run"));
	json_object_set_new(j, "bias_window_s", json_real(w->est_s));
	json_object_set_new(j, "runs", json_integer((json_int_t)w->n_runs));
	json_object_set_new(j, "sigma_k", json_real(w->k_sigma));
	json_object_set_new(j, "noise", ssc_nav_terms_json(&c->terms));
	json_object_set_new(j, "noise_from", json_string(c->terms_from));
	json_object_set_new(in, "mean", ssc_jreal(w->inside_mean));
	json_object_set_new(in, "expected", json_real(w->inside_expected));
	json_object_set_new(in, "binomial_sd", json_real(w->inside_sd));
	for (size_t i = 0; i < c->n_idx; i++) {
		json_t *pt = json_object(), *m = json_object();
		size_t k = c->idx[i];
		const char *u;
		double s = angle_scale(q);

		json_object_set_new(pt, "t_s", json_real(c->im[i].t_s));
		json_object_set_new(pt, "inside", ssc_jreal(w->inside[k]));
		json_object_set_new(pt, "sigma", ssc_jreal(w->sigma[k] * s));
		json_object_set_new(pt, "spread", ssc_jreal(w->spread[k] * s));
		json_object_set_new(pt, "unit", json_string(angle_unit(q)));
		json_array_append_new(pts, pt);
		json_object_set_new(m, "t_s", json_real(c->im[i].t_s));
		json_object_set_new(m, "value", ssc_jreal(ssc_nav_term_value(c->im[i].n, q, SSCOPE_TERM_N, &u)));
		json_object_set_new(m, "lo", ssc_jreal(ssc_nav_term_value(c->im[i].lo, q, SSCOPE_TERM_N, &u)));
		json_object_set_new(m, "hi", ssc_jreal(ssc_nav_term_value(c->im[i].hi, q, SSCOPE_TERM_N, &u)));
		json_object_set_new(m, "unit", json_string(u));
		json_object_set_new(m, "si", ssc_jreal(c->im[i].n));
		json_array_append_new(imp, m);
	}
	json_object_set_new(in, "points", pts);
	json_object_set_new(j, "inside", in);
	json_object_set_new(j, "implied_N", imp);
	json_object_set_new(j, "ci_level", json_real(o->ci));
	if (c->allan.coef[SSCOPE_TERM_N] > 0) {
		json_t *tmp = ssc_nav_terms_json(&c->allan);

		json_object_set(j, "allan_N", json_object_get(tmp, "N"));
		json_decref(tmp);
	} else {
		json_object_set_new(j, "allan_N", json_null());
	}
	return j;
}

static void chan_text(FILE *f, const struct chan *c)
{
	const struct sscope_walk_result *w = c->w;
	enum sscope_quantity q = c->col->quantity;
	double s = angle_scale(q);
	char a[32], b[32], e[32], buf[256];
	const char *u;

	fprintf(f, "%s: %zu runs of %s s, bias removed: %s\n", c->col->name, w->n_runs,
		ssc_fmt(a, sizeof(a), (double)(w->n_points - 1) * w->dt_s, 5),
		w->global ? "the record's mean" : "mean of the window before each run");
	ssc_nav_terms_text(&c->terms, buf, sizeof(buf));
	fprintf(f, "  envelope: +-%g sigma of %s (%s)\n", w->k_sigma, buf, c->terms_from);
	fprintf(f, "  %9s %12s %12s %9s %24s\n", "t (s)", "sigma", "spread", "inside",
		"implied N");
	for (size_t i = 0; i < c->n_idx; i++) {
		size_t k = c->idx[i];
		char d[32], g[32], h[32];

		double nv = ssc_nav_term_value(c->im[i].n, q, SSCOPE_TERM_N, &u);
		double nl = ssc_nav_term_value(c->im[i].lo, q, SSCOPE_TERM_N, &u);
		double nh = ssc_nav_term_value(c->im[i].hi, q, SSCOPE_TERM_N, &u);

		fprintf(f, "  %9s %12s %12s %9s   ",
			ssc_fmt(a, 32, c->im[i].t_s, 5), ssc_fmt(b, 32, w->sigma[k] * s, 4),
			ssc_fmt(e, 32, w->spread[k] * s, 4), ssc_fmt(d, 32, w->inside[k], 3));
		if (isfinite(nv))
			fprintf(f, "%s [%s, %s] %s\n", ssc_fmt(g, 32, nv, 4),
				ssc_fmt(h, 32, nl, 4), ssc_fmt(buf, 32, nh, 4), u);
		else if (nh > 0)
			fprintf(f, "- (below %s %s: the other terms explain the spread)\n",
				ssc_fmt(h, 32, nh, 4), u);
		else
			fprintf(f, "- (the other terms explain the spread: none left for N)\n");
	}
	fprintf(f, "  sigma, spread in %s; inside: fraction of runs within +-%g sigma, mean %s (expected %s +- %s)\n",
		angle_unit(q), w->k_sigma, ssc_fmt(a, 32, w->inside_mean, 4),
		ssc_fmt(b, 32, w->inside_expected, 4), ssc_fmt(e, 32, w->inside_sd, 2));
	if (c->allan.coef[SSCOPE_TERM_N] > 0) {
		double nv = ssc_nav_term_value(c->allan.coef[SSCOPE_TERM_N], q, SSCOPE_TERM_N, &u);
		double nl = ssc_nav_term_value(c->allan.n_lo, q, SSCOPE_TERM_N, &u);
		double nh = ssc_nav_term_value(c->allan.n_hi, q, SSCOPE_TERM_N, &u);

		fprintf(f, "  allan's N on this record: %s [%s, %s] %s (%g %% interval)\n",
			ssc_fmt(a, 32, nv, 4), ssc_fmt(b, 32, nl, 4), ssc_fmt(e, 32, nh, 4), u,
			100 * c->allan.ci_level);
	}
}

struct walk_res {
	const char *path;
	struct opts o;
	struct chan *ch;
	size_t n;
};

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *path)
{
	const struct walk_res *R = result;
	const struct opts *o = &R->o;
	const struct chan *ch = R->ch;
	size_t n = R->n;
	size_t rows = n < 3 ? n : 3;
	struct ssc_fig *fig = ssc_fig_new(1100, (int)(rows * 560 + 60), (int)rows, 1);
	int rc = 0;

	if (!fig)
		return SSC_EXIT_FAIL;
	ssc_fig_title(fig, "random-walk fan: runs integrated after bias removal");
	for (size_t p = 0; p < rows; p++) {
		const struct chan *c = &ch[p];
		const struct sscope_walk_result *w = c->w;
		struct ssc_ax *ax = ssc_fig_ax(fig, (int)p, 0);
		size_t np = w->n_points, shown = w->n_paths < o->paths ? w->n_paths : o->paths;
		double *t = malloc(np * sizeof(double)), *y = malloc(np * sizeof(double));
		double *lo = malloc(np * sizeof(double)), s = angle_scale(c->col->quantity);
		char lab[160], a[32];

		if (!t || !y || !lo) {
			free(t);
			free(y);
			free(lo);
			rc = -ENOMEM;
			break;
		}
		for (size_t k = 0; k < np; k++)
			t[k] = (double)k * w->dt_s;
		for (size_t r = 0; r < shown; r++) {
			struct ssc_style st = { .color = 0x9a9a9a, .width = 0.7 };

			for (size_t k = 0; k < np; k++)
				y[k] = w->paths[r * np + k] * s;
			ssc_ax_line(ax, t, y, np, &st, r ? NULL : "runs");
		}
		{
			struct ssc_style e = { .color = 0xd62728, .width = 2.2 };
			struct ssc_style a2 = { .color = 0x1f77b4, .width = 1.5, .dash = SSC_DASHED };

			for (size_t k = 0; k < np; k++) {
				y[k] = w->k_sigma * w->sigma[k] * s;
				lo[k] = -y[k];
			}
			snprintf(lab, sizeof(lab), "+-%g sigma (all terms)", w->k_sigma);
			ssc_ax_line(ax, t, y, np, &e, lab);
			ssc_ax_line(ax, t, lo, np, &e, NULL);
			for (size_t k = 0; k < np; k++) {
				y[k] = w->k_sigma * c->terms.coef[SSCOPE_TERM_N] * sqrt(t[k]) * s;
				lo[k] = -y[k];
			}
			snprintf(lab, sizeof(lab), "+-%g N sqrt(t)", w->k_sigma);
			ssc_ax_line(ax, t, y, np, &a2, lab);
			ssc_ax_line(ax, t, lo, np, &a2, NULL);
		}
		snprintf(lab, sizeof(lab), "%s: %zu of %zu runs shown; %s %% inside on average",
			 c->col->name, shown, w->n_runs, ssc_fmt(a, 32, 100 * w->inside_mean, 3));
		ssc_ax_note(ax, lab, SSC_LEGEND_LL);
		ssc_ax_xlabel(ax, "time in the run (s)");
		snprintf(lab, sizeof(lab), "integrated %s (%s)",
			 c->col->quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? "rate" : "acceleration",
			 angle_unit(c->col->quantity));
		ssc_ax_ylabel(ax, lab);
		ssc_ax_legend(ax, SSC_LEGEND_UL);
		free(t);
		free(y);
		free(lo);
	}
	(void)opts;
	if (!rc)
		rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

static void free_result(void *result)
{
	struct walk_res *R = result;

	for (size_t i = 0; i < R->n; i++)
		sscope_walk_result_free(R->ch[i].w);
	free(R->ch);
	free(R);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const char *cmd = env->co->cmd, *path = env->paths[0];
	const struct opts *o = opts;
	const struct sscope_capture *cap = env->caps[0];
	const struct ssc_result *up = ssc_stage_upstream(env, &ssc_allan_stage, NULL);
	struct walk_res *R = calloc(1, sizeof(*R));
	struct ssc_nav_terms *given = NULL;
	struct sscope_noise_plan *plan = NULL;
	size_t n_given = 0;
	int rc = 0;

	if (R)
		R->ch = calloc(cap->n_channels ? cap->n_channels : 1, sizeof(*R->ch));
	if (!R || !R->ch) {
		free(R);
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = R;
	R->path = path;
	R->o = *o;
	rc = ssc_time_check(env->co, path, cap, true);
	if (rc)
		goto done;
	if (!(cap->rate_hz > 0)) {
		rc = ssc_err_no_rate(cmd, path, cap->rate_note);
		goto done;
	}
	if (o->allan) {
		json_t *root = NULL;

		rc = ssc_nav_load_json(cmd, "from-allan", o->allan, &root);
		if (!rc)
			rc = ssc_nav_terms_from_allan(cmd, root, o->allan, &given,
						      &n_given);
		json_decref(root);
	} else if (up) {
		rc = ssc_nav_terms_from_allan_res(cmd, up->data, "the allan stage",
						  &given, &n_given);
	}
	if (rc)
		goto done;
	if (!n_given && sscope_noise_plan_new(&plan))
		plan = NULL; /* each fit computes its own */
	for (size_t k = 0; k < cap->n_channels; k++) {
		enum sscope_quantity q = cap->channels[k].col.quantity;

		if (q != SSCOPE_QUANTITY_ANGULAR_RATE && q != SSCOPE_QUANTITY_ACCELERATION)
			continue;
		rc = analyse(env, o, path, cap, k, given, n_given, plan,
			     &R->ch[R->n]);
		if (R->ch[R->n].w)
			R->n++;
		if (rc)
			goto done;
	}
	if (!R->n) {
		ssc_err(cmd, "%s: no angular-rate or acceleration channel (give units, e.g. 'gx [deg/s]' or -u deg/s)",
			path);
		rc = SSC_EXIT_FAIL;
	}
done:
	sscope_noise_plan_free(plan);
	free(given);
	return rc;
}

static json_t *json(const void *opts, const void *result)
{
	const struct walk_res *R = result;
	json_t *root = json_object(), *a = json_array();

	(void)opts;
	json_object_set_new(root, "command", json_string("walk"));
	json_object_set_new(root, "file", json_string(R->path));
	for (size_t i = 0; i < R->n; i++)
		json_array_append_new(a, chan_json(&R->o, &R->ch[i]));
	json_object_set_new(root, "channels", a);
	return root;
}

static void text(FILE *f, const void *opts, const void *result)
{
	const struct walk_res *R = result;

	(void)opts;
	for (size_t i = 0; i < R->n; i++) {
		if (i)
			fputc('\n', f);
		chan_text(f, &R->ch[i]);
	}
}

static void csv(FILE *f, const void *opts, const void *result)
{
	const struct walk_res *R = result;

	(void)opts;
	fprintf(f, "channel,t_s,sigma,spread,inside,unit\n");
	for (size_t i = 0; i < R->n; i++) {
		const struct sscope_walk_result *w = R->ch[i].w;
		double s = angle_scale(R->ch[i].col->quantity);

		for (size_t k = 1; k < w->n_points; k++)
			fprintf(f, "%s,%.10g,%.8g,%.8g,%.6g,%s\n", R->ch[i].col->name,
				(double)k * w->dt_s, w->sigma[k] * s, w->spread[k] * s,
				w->inside[k], angle_unit(R->ch[i].col->quantity));
	}
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct walk_res *R = result;

	(void)opts;
	for (size_t i = 0; i < R->n; i++) {
		const struct chan *c = &R->ch[i];
		const struct sscope_walk_implied *im = &c->im[c->n_idx - 1];
		enum sscope_quantity q = c->col->quantity;
		const char *u;
		double nv, nl, nh;

		ssc_summary_add(rows, c->col->name,
				"runs inside +-2 sigma (mean over time)",
				100 * c->w->inside_mean, NAN, NAN, "%",
				"expected 95.45 %");
		nv = ssc_nav_term_value(im->n, q, SSCOPE_TERM_N, &u);
		nl = ssc_nav_term_value(im->lo, q, SSCOPE_TERM_N, &u);
		nh = ssc_nav_term_value(im->hi, q, SSCOPE_TERM_N, &u);
		if (!isfinite(nv))
			nl = nh = NAN;	/* no estimate: no interval either */
		ssc_summary_add(rows, c->col->name, "N implied by the fan", nv, nl,
				nh, u, "spread of the runs at their end");
	}
}

const struct ssc_stage_ops ssc_walk_stage = {
	.spec = &spec,
	.title = "Random-walk fan",
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

int ssc_cmd_walk(int argc, char **argv)
{
	return ssc_stage_main(&ssc_walk_stage, argc, argv);
}
