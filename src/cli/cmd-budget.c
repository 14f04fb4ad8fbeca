/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope budget: attitude, velocity and position error against time
 * from each sensor error source (textbook eqs 95-101), which source dominates
 * when, the time to reach a given error, and a Monte-Carlo check of the
 * random-walk terms (fraction of seeded realisations inside +-2 sigma).
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "plot.h"
#include "navcommon.h"
#include "results.h"

#define MAX_TIMES 256
#define MAX_ERR 16

enum {
	O_SENSOR = 300,
	O_GBIAS,
	O_ABIAS,
	O_ARW,
	O_VRW,
	O_GSF,
	O_ASF,
	O_TURN,
	O_APROF,
	O_TIME,
	O_MODEL,
	O_SCHULER,
	O_SWITCH,
	O_ERROR,
	O_MC,
	O_SEED,
	O_GRAVITY,
	O_PLOT,
	O_RESULT,
};

static const struct ssc_option budget_opts[] = {
	{ "sensor", required_argument, O_SENSOR, "SPEC.ini",
	  "sensor spec ([sensor] section; a gyro and an accelerometer file may both be given)" },
	{ "result", required_argument, O_RESULT, "FILE.json",
	  "take sources from a JSON result of 'allan' (N, B) or 'calib' (remaining uncertainty)" },
	{ "gyro-bias", required_argument, O_GBIAS, "V",
	  "gyro bias, e.g. 10 deg/h" },
	{ "accel-bias", required_argument, O_ABIAS, "V",
	  "accelerometer bias, e.g. 1 mg" },
	{ "arw", required_argument, O_ARW, "V",
	  "angle random walk, e.g. 0.15 deg/sqrt(h)" },
	{ "vrw", required_argument, O_VRW, "V",
	  "velocity random walk, e.g. 0.03 m/s/sqrt(h)" },
	{ "gyro-sf", required_argument, O_GSF, "V",
	  "gyro scale-factor error (ppm, or with a unit: 0.1 %)" },
	{ "accel-sf", required_argument, O_ASF, "V",
	  "accelerometer scale-factor error (ppm)" },
	{ "turn-rate", required_argument, O_TURN, "V",
	  "motion profile for the scale factor: sustained turn rate, e.g. 10 deg/s" },
	{ "accel-profile", required_argument, O_APROF, "V",
	  "motion profile for the scale factor: sustained acceleration, e.g. 0.1 g" },
	{ "time", required_argument, O_TIME, "T[,T...]",
	  "times up to a year (default 10,30,60,120,300,600,1800,3600 s; units allowed: 2 min)" },
	{ "model", required_argument, O_MODEL, "auto|open-loop|schuler",
	  "formulas (default auto: open loop up to the switch time, Schuler-bounded after)" },
	{ "schuler", no_argument, O_SCHULER, NULL, "same as --model schuler" },
	{ "switch-time", required_argument, O_SWITCH, "T",
	  "auto model: switch time (default 300 s)" },
	{ "error", required_argument, O_ERROR, "E[,E...]",
	  "report the time to reach each error: a length (100 m), a velocity (1 m/s) or an angle (1 deg)" },
	{ "monte-carlo", required_argument, O_MC, "N",
	  "realisations of the random-walk check (default 1000; 0 off)" },
	{ "seed", required_argument, O_SEED, "N", "Monte-Carlo seed (default 1)" },
	{ "gravity", required_argument, O_GRAVITY, "G", "gravity (default 9.80665 m/s^2)" },
	{ "plot", required_argument, O_PLOT, "PATH.svg|PATH.png",
	  "draw error against time (log-log) and Monte-Carlo walks (PNG needs OpenCV)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "budget",
	.usage = "budget (--sensor SPEC.ini | --gyro-bias V --accel-bias V --arw V --vrw V) [OPTIONS]",
	.summary =
		"Drift budget of one horizontal navigation channel: attitude, velocity\n"
		"and position error against time from each source -- gyro bias (open\n"
		"loop g b t^3/6), accelerometer bias (b t^2/2), angle and velocity random\n"
		"walks (1 sigma; 95 % of runs stay inside +-2 sigma), scale factor under\n"
		"a motion profile -- with the Schuler-bounded forms past the switch time,\n"
		"the dominant source at each time, the time to reach a given error, and\n"
		"a Monte-Carlo check of the random walks.",
	.options = budget_opts,
	.output_opts = true,
	.notes = "Examples:\n"
		 "  sensorscope budget --gyro-bias 10deg/h --time 120\n"
		 "  sensorscope budget --gyro-bias 1deg/h --accel-bias 100ug --arw 0.1deg/sqrt(h) \\\n"
		 "      --vrw 0.05m/s/sqrt(h) --error 100m --plot budget.png\n"
		 "Total = root sum of squares of the sources (biases as 1-sigma values).",
};

struct opts {
	struct sscope_budget_params p;
	const char *sensor[2];
	int n_sensor;
	const char *result[4];
	int n_result;
	bool set[4]; /* gyro bias, accel bias, arw, vrw given directly */
	double times[MAX_TIMES];
	size_t n_times;
	double err[MAX_ERR];
	enum sscope_budget_quantity err_q[MAX_ERR];
	size_t n_err;
	size_t mc;
	unsigned long seed;
	const char *plot;
	bool seed_set, gsf_set, asf_set; /* given on the command line */
};

static int parse_ratio(const char *opt, const char *arg, double *out)
{
	struct sscope_unit u;
	struct sscope_diag d = { "" };
	double v;

	if (sscope_quantity_parse(arg, &v, &u, &d))
		return ssc_usage_error("budget", "--%s: %s", opt, d.msg);
	if (sscope_unit_quantity(&u) != SSCOPE_QUANTITY_DIMENSIONLESS)
		return ssc_usage_error("budget", "--%s: '%s' is not a ratio", opt, arg);
	if (u.scale == 1)
		v *= 1e-6; /* bare number: ppm */
	*out = v;
	return 0;
}

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;
	struct sscope_budget_params *p = &o->p;

	switch (key) {
	case O_SENSOR:
		if (o->n_sensor == 2)
			return ssc_usage_error("budget", "--sensor: at most two (a gyro and an accelerometer)");
		o->sensor[o->n_sensor++] = arg;
		return 0;
	case O_RESULT:
		if (o->n_result == 4)
			return ssc_usage_error("budget", "--result: at most four files");
		o->result[o->n_result++] = arg;
		return 0;
	case O_GBIAS:
		o->set[0] = true;
		return ssc_arg_quantity("budget", "gyro-bias", arg, "rad/s",
					&p->gyro_bias_rad_s);
	case O_ABIAS:
		o->set[1] = true;
		return ssc_arg_quantity("budget", "accel-bias", arg, "m/s^2",
					&p->accel_bias_m_s2);
	case O_ARW:
		o->set[2] = true;
		if (ssc_arg_quantity("budget", "arw", arg, "rad/sqrt(s)",
				     &p->arw_rad_sqrt_s))
			return SSC_EXIT_USAGE;
		return p->arw_rad_sqrt_s >= 0 ? 0 :
		       ssc_usage_error("budget", "--arw: a random walk is not negative");
	case O_VRW:
		o->set[3] = true;
		if (ssc_arg_quantity("budget", "vrw", arg, "m/s/sqrt(s)",
				     &p->vrw_m_s_sqrt_s))
			return SSC_EXIT_USAGE;
		return p->vrw_m_s_sqrt_s >= 0 ? 0 :
		       ssc_usage_error("budget", "--vrw: a random walk is not negative");
	case O_GSF:
		o->gsf_set = true;
		return parse_ratio("gyro-sf", arg, &p->gyro_sf);
	case O_ASF:
		o->asf_set = true;
		return parse_ratio("accel-sf", arg, &p->accel_sf);
	case O_TURN:
		return ssc_arg_quantity("budget", "turn-rate", arg, "rad/s",
					&p->turn_rate_rad_s);
	case O_APROF:
		return ssc_arg_quantity("budget", "accel-profile", arg, "m/s^2",
					&p->accel_profile_m_s2);
	case O_TIME: {
		char *s = strdup(arg), *save = NULL, *tok;
		int rc = 0;

		o->n_times = 0;
		for (tok = strtok_r(s, ",", &save); tok && !rc;
		     tok = strtok_r(NULL, ",", &save)) {
			if (o->n_times == MAX_TIMES) {
				rc = ssc_usage_error("budget", "--time: at most %d times",
						     MAX_TIMES);
				break;
			}
			rc = ssc_arg_quantity("budget", "time", tok, "s",
					      &o->times[o->n_times]);
			if (!rc && !(o->times[o->n_times] > 0))
				rc = ssc_usage_error("budget", "--time: '%s' must be positive",
						     tok);
			/* beyond a year a drift budget of constant sources
			 * describes no navigation */
			else if (!rc && o->times[o->n_times] > 3.2e7)
				rc = ssc_usage_error("budget", "--time: '%s' is beyond a year (3.2e7 s)",
						     tok);
			o->n_times++;
		}
		free(s);
		return rc;
	}
	case O_MODEL:
		if (!strcmp(arg, "auto"))
			p->model = SSCOPE_BUDGET_AUTO;
		else if (!strcmp(arg, "open-loop") || !strcmp(arg, "open"))
			p->model = SSCOPE_BUDGET_OPEN_LOOP;
		else if (!strcmp(arg, "schuler"))
			p->model = SSCOPE_BUDGET_SCHULER;
		else
			return ssc_usage_error("budget", "--model: '%s' is not auto, open-loop or schuler",
					       arg);
		return 0;
	case O_SCHULER:
		p->model = SSCOPE_BUDGET_SCHULER;
		return 0;
	case O_SWITCH:
		return ssc_arg_positive("budget", "switch-time", arg, "s", &p->switch_time_s);
	case O_ERROR: {
		char *s = strdup(arg), *save = NULL, *tok;
		int rc = 0;

		o->n_err = 0;
		for (tok = strtok_r(s, ",", &save); tok && !rc;
		     tok = strtok_r(NULL, ",", &save)) {
			struct sscope_unit u;
			struct sscope_diag d = { "" };
			double v;
			enum sscope_quantity q;

			if (o->n_err == MAX_ERR) {
				rc = ssc_usage_error("budget", "--error: at most %d values",
						     MAX_ERR);
				break;
			}
			if (sscope_quantity_parse(tok, &v, &u, &d)) {
				rc = ssc_usage_error("budget", "--error: %s", d.msg);
				break;
			}
			q = sscope_unit_quantity(&u);
			if (q == SSCOPE_QUANTITY_LENGTH)
				o->err_q[o->n_err] = SSCOPE_BUDGET_POSITION;
			else if (q == SSCOPE_QUANTITY_VELOCITY)
				o->err_q[o->n_err] = SSCOPE_BUDGET_VELOCITY;
			else if (q == SSCOPE_QUANTITY_ANGLE)
				o->err_q[o->n_err] = SSCOPE_BUDGET_ATTITUDE;
			else {
				rc = ssc_usage_error("budget", "--error: '%s' is not a length, velocity or angle",
						     tok);
				break;
			}
			if (!(v > 0)) {
				rc = ssc_usage_error("budget", "--error: '%s' must be positive",
						     tok);
				break;
			}
			o->err[o->n_err++] = v;
		}
		free(s);
		return rc;
	}
	case O_MC:
		if (ssc_arg_size("budget", "monte-carlo", arg, &o->mc))
			return SSC_EXIT_USAGE;
		if (o->mc > 1000000)
			return ssc_usage_error("budget", "--monte-carlo: at most 1000000");
		return 0;
	case O_SEED: {
		size_t v;

		if (ssc_arg_size("budget", "seed", arg, &v))
			return SSC_EXIT_USAGE;
		o->seed = (unsigned long)v;
		o->seed_set = true;
		return 0;
	}
	case O_GRAVITY:
		return ssc_arg_gravity("budget", arg, &p->gravity_m_s2);
	case O_PLOT:
		o->plot = arg;
		return 0;
	default:
		return ssc_usage_error("budget", "unexpected option");
	}
}

static const char *model_name(const struct sscope_budget_params *p, double t)
{
	return sscope_budget_is_schuler(p, t) ? "schuler" : "open_loop";
}

static const char *qty_name(enum sscope_budget_quantity q)
{
	return q == SSCOPE_BUDGET_POSITION ? "position" :
	       q == SSCOPE_BUDGET_VELOCITY ? "velocity" : "attitude";
}

static const char *qty_unit(enum sscope_budget_quantity q)
{
	return q == SSCOPE_BUDGET_POSITION ? "m" :
	       q == SSCOPE_BUDGET_VELOCITY ? "m/s" : "rad";
}

struct mc_res {
	bool done;
	struct sscope_budget_mc_opts o;
	struct sscope_budget_mc_point *pt;
	size_t n;
	double *paths;
	size_t n_paths;
};

static int run_mc(const struct opts *o, bool gyro, double t_end, bool paths,
		  struct mc_res *m)
{
	size_t nt = 0;

	memset(&m->o, 0, sizeof(m->o));
	m->o.gyro = gyro;
	m->o.strength = gyro ? fabs(o->p.arw_rad_sqrt_s) : fabs(o->p.vrw_m_s_sqrt_s);
	m->o.gravity_m_s2 = o->p.gravity_m_s2;
	m->o.t_end_s = t_end;
	m->o.steps = 1000;
	m->o.realisations = o->mc;
	m->o.seed = o->seed + (gyro ? 0 : 1);
	m->pt = calloc(o->n_times, sizeof(*m->pt));
	m->n_paths = paths ? 40 : 0;
	m->paths = m->n_paths ? calloc(m->n_paths * (m->o.steps + 1), sizeof(double)) :
				NULL;
	if (!m->pt || (m->n_paths && !m->paths))
		return -ENOMEM;
	if (m->n_paths > o->mc)
		m->n_paths = o->mc;
	{
		double *ts = malloc(o->n_times * sizeof(double));
		int rc;

		if (!ts)
			return -ENOMEM;
		for (size_t j = 0; j < o->n_times; j++)
			ts[nt++] = o->times[j];
		rc = sscope_budget_mc(&m->o, ts, nt, m->pt, m->paths, m->n_paths);
		free(ts);
		if (rc)
			return rc;
	}
	m->n = nt;
	m->done = true;
	return 0;
}

static json_t *mc_json(const struct mc_res *m)
{
	json_t *o = json_object(), *pts = json_array();
	double sd, p = sscope_budget_mc_expected(m->o.realisations, &sd);

	json_object_set_new(o, "term", json_string(m->o.gyro ? "arw" : "vrw"));
	json_object_set_new(o, "walk", json_string(m->o.gyro ? "attitude_rad" :
							      "velocity_m_s"));
	json_object_set_new(o, "realisations", json_integer((json_int_t)m->o.realisations));
	json_object_set_new(o, "steps", json_integer((json_int_t)m->o.steps));
	json_object_set_new(o, "seed", json_integer((json_int_t)m->o.seed));
	json_object_set_new(o, "expected_inside", json_real(p));
	json_object_set_new(o, "binomial_sd", json_real(sd));
	for (size_t j = 0; j < m->n; j++) {
		json_t *q = json_object();

		json_object_set_new(q, "t_s", json_real(m->pt[j].t_s));
		json_object_set_new(q, "walk_sd", ssc_jreal(m->pt[j].walk_sd));
		json_object_set_new(q, "walk_sd_theory", ssc_jreal(m->pt[j].walk_sd_theory));
		json_object_set_new(q, "walk_inside_2sigma", ssc_jreal(m->pt[j].walk_inside));
		json_object_set_new(q, "position_sd", ssc_jreal(m->pt[j].pos_sd));
		json_object_set_new(q, "position_sd_theory", ssc_jreal(m->pt[j].pos_sd_theory));
		json_object_set_new(q, "position_inside_2sigma", ssc_jreal(m->pt[j].pos_inside));
		json_array_append_new(pts, q);
	}
	json_object_set_new(o, "points", pts);
	return o;
}

struct budget_res {
	struct opts o;          /* with the sources taken from specs/results */
	const char *from[4];    /* where each of the four came from */
	struct mc_res mc[2];
	int n_mc;
	struct sscope_budget_crossover cr[32];
	size_t n_cr;
	double t_max;
};

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *path)
{
	const struct budget_res *R = result;
	const struct opts *o = &R->o;
	const struct mc_res *mc = R->mc;
	int n_mc = R->n_mc;
	double t_max = R->t_max;
	int rows = n_mc > 0 ? 2 : 1, rc;
	struct ssc_fig *fig = ssc_fig_new(1100, rows == 2 ? 1150 : 650, rows, 1);
	struct ssc_ax *ax = ssc_fig_ax(fig, 0, 0);
	enum { NG = 300 };
	double t[NG], y[NG], y2[NG], ymin = INFINITY, ymax = 0;
	double t0 = fmin(0.1, o->times[0]);
	char buf[160];

	for (int i = 0; i < NG; i++)
		t[i] = t0 * pow(t_max / t0, (double)i / (NG - 1));
	ssc_fig_title(fig, "drift budget: position error of one horizontal channel");
	ssc_ax_log(ax, true, true);
	for (int s = 0; s < SSCOPE_BUDGET_N_SOURCES; s++) {
		struct ssc_style st = { .color = ssc_plot_color((size_t)s), .width = 2 };
		bool any = false;

		for (int i = 0; i < NG; i++) {
			struct sscope_budget_point pt;

			sscope_budget_source_eval(&o->p, (enum sscope_budget_source)s,
						  t[i], &pt);
			y[i] = pt.position_m;
			y2[i] = 2 * pt.position_m;
			any |= y[i] > 0;
			if (y[i] > 0) {
				ymin = fmin(ymin, y[i]);
				ymax = fmax(ymax, y2[i]);
			}
		}
		if (!any)
			continue;
		snprintf(buf, sizeof(buf), "%s%s", sscope_budget_source_name((enum sscope_budget_source)s),
			 sscope_budget_source_random((enum sscope_budget_source)s) ? " (1σ)" : "");
		ssc_ax_line(ax, t, y, NG, &st, buf);
		if (sscope_budget_source_random((enum sscope_budget_source)s)) {
			struct ssc_style ds = st;

			ds.dash = SSC_DASHED;
			ds.width = 1.2;
			snprintf(buf, sizeof(buf), "%s ±2σ envelope",
				 sscope_budget_source_name((enum sscope_budget_source)s));
			ssc_ax_line(ax, t, y2, NG, &ds, buf);
		}
	}
	{
		struct ssc_style st = { .color = 0x111111, .width = 3 };

		for (int i = 0; i < NG; i++) {
			struct sscope_budget_point pt;

			sscope_budget_total(&o->p, t[i], &pt);
			y[i] = pt.position_m;
		}
		ssc_ax_line(ax, t, y, NG, &st, "total (RSS)");
	}
	if (o->p.model == SSCOPE_BUDGET_AUTO) {
		struct ssc_style vs = { .color = 0x7f7f7f, .width = 1, .dash = SSC_DOTTED };
		double sw = o->p.switch_time_s > 0 ? o->p.switch_time_s : 300;

		if (sw < t_max)
			ssc_ax_vline(ax, sw, &vs, "open loop | Schuler");
	}
	if (ymax > 0 && ymin < ymax)
		ssc_ax_ylim(ax, fmax(ymin, ymax * 1e-9), ymax * 2);
	ssc_ax_xlabel(ax, "time (s)");
	ssc_ax_ylabel(ax, "position error (m)");
	ssc_ax_legend(ax, SSC_LEGEND_UL);
	if (n_mc > 0) {
		const struct mc_res *m = &mc[0];
		size_t ns = m->o.steps + 1;
		double *tt = malloc(ns * sizeof(double)), *lo = malloc(ns * sizeof(double)),
		       *hi = malloc(ns * sizeof(double));
		double sc = m->o.gyro ? 180 / PI : 1;

		ax = ssc_fig_ax(fig, 1, 0);
		if (tt && lo && hi) {
			for (size_t k = 0; k < ns; k++) {
				tt[k] = m->o.t_end_s * (double)k / (double)m->o.steps;
				hi[k] = 2 * m->o.strength * sqrt(tt[k]) * sc;
				lo[k] = -hi[k];
			}
			ssc_ax_band(ax, tt, lo, hi, ns, 0x1f77b4, 0.15, "±2σ√t");
			for (size_t p = 0; p < m->n_paths; p++) {
				struct ssc_style st = { .color = 0x7f7f7f, .width = 0.8 };

				for (size_t k = 0; k < ns; k++)
					lo[k] = m->paths[p * ns + k] * sc;
				ssc_ax_line(ax, tt, lo, ns, &st, p ? NULL : "realisations");
			}
			snprintf(buf, sizeof(buf), "%s random walk: %zu of %zu runs shown\n%.1f %% of %zu inside ±2σ at t = %g s (expected 95.4 %%)",
				 m->o.gyro ? "angle" : "velocity", m->n_paths,
				 m->o.realisations, 100 * m->pt[m->n - 1].walk_inside,
				 m->o.realisations, m->pt[m->n - 1].t_s);
			ssc_ax_note(ax, buf, SSC_LEGEND_LL);
			ssc_ax_xlabel(ax, "time (s)");
			ssc_ax_ylabel(ax, m->o.gyro ? "attitude error (°)" :
						      "velocity error (m/s)");
			ssc_ax_legend(ax, SSC_LEGEND_UL);
		}
		free(tt);
		free(lo);
		free(hi);
	}
	(void)opts;
	rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

/* the sources given directly (by option) are kept */
static unsigned kept(const struct opts *o)
{
	return (o->set[0] ? 1u << SSCOPE_BUDGET_GYRO_BIAS : 0) |
	       (o->set[1] ? 1u << SSCOPE_BUDGET_ACCEL_BIAS : 0) |
	       (o->set[2] ? 1u << SSCOPE_BUDGET_ARW : 0) |
	       (o->set[3] ? 1u << SSCOPE_BUDGET_VRW : 0);
}

/* name the origin of each source a result raised */
static void mark(const char **from, unsigned raised, const char *bias,
		 const char *walk)
{
	static const int idx[4] = { SSCOPE_BUDGET_GYRO_BIAS, SSCOPE_BUDGET_ACCEL_BIAS,
				    SSCOPE_BUDGET_ARW, SSCOPE_BUDGET_VRW };

	for (int i = 0; i < 4; i++)
		if (raised & (1u << idx[i]))
			from[i] = i < 2 ? bias : walk;
}

/* One axis of an allan result: N and B of the rate it measured. */
static int take_allan_axis(struct opts *o, const char **from,
			   enum sscope_quantity rq, double n_si, double b_si)
{
	bool used;
	unsigned r = sscope_budget_take_noise(&o->p, rq, n_si, b_si, kept(o),
					      &used);

	mark(from, r, "allan B (bias instability)", "allan N");
	return used;
}

/* One triad of a calib result. */
static int take_calib_triad(struct opts *o, const char **from,
			    enum sscope_quantity q,
			    const struct sscope_calib_triad *c, double nd)
{
	unsigned r = sscope_budget_take_calib(&o->p, q, c, nd, kept(o));

	mark(from, r, "calib bias uncertainty", "calib noise density");
	return q == SSCOPE_QUANTITY_ANGULAR_RATE || q == SSCOPE_QUANTITY_ACCELERATION;
}

/* Sources from every triad of a calib result; returns how many counted. */
static int take_calib_res(struct opts *o, const char **from,
			  const struct ssc_calib_res *c)
{
	int used = 0;

	for (int t = 0; t < c->n_out; t++)
		used += take_calib_triad(o, from, c->out[t].q, &c->out[t].t.c,
					 c->out[t].noise_density);
	return used;
}

/* Sources from the typed results of a scene's allan and calib stages. */
static void take_upstream(struct opts *o, const char **from,
			  const struct ssc_stage_env *env)
{
	for (size_t i = 0; i < env->n_upstream; i++) {
		const struct ssc_result *r = &env->upstream[i];

		if (r->ops == &ssc_allan_stage) {
			const struct ssc_allan_res *a = r->data;

			for (size_t f = 0; f < a->n_files; f++)
				for (size_t k = 0; k < a->fr[f].n_ch; k++) {
					const struct ssc_allan_chan *c = &a->fr[f].ch[k];
					const struct sscope_noise_fit *ft = &c->res->fit;

					take_allan_axis(o, from, c->u.rq,
							ft->coef[SSCOPE_TERM_N].value,
							ft->coef[SSCOPE_TERM_B].value);
				}
		} else if (r->ops == &ssc_calib_stage) {
			take_calib_res(o, from, r->data);
		}
	}
}

/*
 * --result FILE: a saved JSON result of 'allan' (N and B of each axis) or
 * 'calib' (what remains after the calibration), read into the same
 * quantities the typed results give.
 */
static int load_result(struct opts *o, const char *path, const char **from)
{
	json_t *root = ssc_json_read("budget", "result", path,
				     "the JSON of 'sensorscope allan' or 'tempbias'");
	const char *cmd;
	int used = 0;

	if (!root)
		return SSC_EXIT_FAIL;
	cmd = json_string_value(json_object_get(root, "command"));
	if (cmd && !strcmp(cmd, "allan")) {
		struct ssc_nav_terms *t;
		size_t n;

		if (ssc_nav_terms_from_allan("budget", root, path, &t, &n)) {
			json_decref(root);
			return SSC_EXIT_FAIL;
		}
		for (size_t i = 0; i < n; i++)
			used += take_allan_axis(o, from, t[i].quantity,
						t[i].coef[SSCOPE_TERM_N] > 0 ?
							t[i].coef[SSCOPE_TERM_N] : (double)NAN,
						t[i].coef[SSCOPE_TERM_B] > 0 ?
							t[i].coef[SSCOPE_TERM_B] : (double)NAN);
		free(t);
	} else if (cmd && !strncmp(cmd, "calib", 5)) {
		struct ssc_calib_res c;

		if (ssc_calib_res_from_json(root, &c)) {
			json_decref(root);
			ssc_err("budget", "--result: %s: a 'calib' result whose triads cannot be read",
				path);
			return SSC_EXIT_FAIL;
		}
		used = take_calib_res(o, from, &c);
	} else {
		json_decref(root);
		ssc_err("budget", "--result: %s: neither an 'allan' nor a 'calib' JSON result",
			path);
		return SSC_EXIT_FAIL;
	}
	json_decref(root);
	if (!used) {
		ssc_err("budget", "--result: %s: no gyro or accelerometer terms in it", path);
		return SSC_EXIT_FAIL;
	}
	return SSC_EXIT_OK;
}

/* Sources from a sensor specification (unless given directly). */
static int apply_sensor(struct opts *o, const struct sscope_sensor_spec *s,
			const char *path, const char **from)
{
	if (s->quantity == SSCOPE_QUANTITY_ANGULAR_RATE) {
		if (!o->set[0] && (s->has & (SSCOPE_SENSOR_HAS_BIAS | SSCOPE_SENSOR_HAS_B))) {
			o->p.gyro_bias_rad_s = (s->has & SSCOPE_SENSOR_HAS_BIAS) ? s->bias : s->b;
			from[0] = (s->has & SSCOPE_SENSOR_HAS_BIAS) ? "bias" : "bias_instability";
		}
		if (!o->set[2] && (s->has & SSCOPE_SENSOR_HAS_N)) {
			o->p.arw_rad_sqrt_s = s->n;
			from[2] = "noise_density";
		}
		if (o->p.gyro_sf == 0 && (s->has & SSCOPE_SENSOR_HAS_SF))
			o->p.gyro_sf = s->scale_factor_error;
	} else if (s->quantity == SSCOPE_QUANTITY_ACCELERATION) {
		if (!o->set[1] && (s->has & (SSCOPE_SENSOR_HAS_BIAS | SSCOPE_SENSOR_HAS_B))) {
			o->p.accel_bias_m_s2 = (s->has & SSCOPE_SENSOR_HAS_BIAS) ? s->bias : s->b;
			from[1] = (s->has & SSCOPE_SENSOR_HAS_BIAS) ? "bias" : "bias_instability";
		}
		if (!o->set[3] && (s->has & SSCOPE_SENSOR_HAS_N)) {
			o->p.vrw_m_s_sqrt_s = s->n;
			from[3] = "noise_density";
		}
		if (o->p.accel_sf == 0 && (s->has & SSCOPE_SENSOR_HAS_SF))
			o->p.accel_sf = s->scale_factor_error;
	} else {
		ssc_err("budget", "%s: neither a gyro nor an accelerometer (give range or noise_density with a unit)",
			path);
		return SSC_EXIT_FAIL;
	}
	return SSC_EXIT_OK;
}

static void init(void *opts)
{
	struct opts *o = opts;

	memset(o, 0, sizeof(*o));
	o->mc = 1000;
	o->seed = 1;
}

static int check(struct ssc_common *co, void *opts)
{
	struct opts *o = opts;

	if (o->plot) {
		int rc = ssc_plot_check(co->cmd, o->plot);

		if (rc)
			return rc;
		co->plot = o->plot;
	}
	/* options that would be ignored */
	if (o->p.switch_time_s > 0 && o->p.model != SSCOPE_BUDGET_AUTO)
		return ssc_usage_error(co->cmd, "--switch-time: applies to --model auto only");
	if (o->seed_set && o->mc == 0)
		return ssc_usage_error(co->cmd, "--seed: no Monte-Carlo check (--monte-carlo 0)");
	return SSC_EXIT_OK;
}

static void free_result(void *result)
{
	struct budget_res *R = result;

	for (int i = 0; i < 2; i++) {
		free(R->mc[i].pt);
		free(R->mc[i].paths);
	}
	free(R);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const struct ssc_common *co = env->co;
	const double deft[] = { 10, 30, 60, 120, 300, 600, 1800, 3600 };
	struct budget_res *R = calloc(1, sizeof(*R));
	struct opts *o;
	int rc;

	if (!R) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = R;
	R->o = *(struct opts *)opts;
	o = &R->o;
	for (int i = 0; i < 4; i++)
		R->from[i] = o->set[i] ? "option" : "not given";
	for (int i = 0; i < o->n_sensor; i++) {
		struct sscope_sensor_spec s;

		rc = ssc_load_sensor(co->cmd, o->sensor[i], &s);
		if (!rc)
			rc = apply_sensor(o, &s, o->sensor[i], R->from);
		if (rc)
			return rc;
	}
	if (env->sensor) {
		rc = apply_sensor(o, env->sensor, env->sensor_path ?
				  env->sensor_path : "[sensor]", R->from);
		if (rc)
			return rc;
	}
	for (int i = 0; i < o->n_result; i++) {
		rc = load_result(o, o->result[i], R->from);
		if (rc)
			return rc;
	}
	take_upstream(o, R->from, env);
	/* a scale-factor error adds nothing without its motion profile */
	if ((o->gsf_set && o->p.turn_rate_rad_s == 0) ||
	    (o->p.turn_rate_rad_s != 0 && o->p.gyro_sf == 0))
		ssc_warn(co, "the gyro scale-factor term needs both --gyro-sf (or the sensor's scale_factor_error) and --turn-rate: it is 0");
	if ((o->asf_set && o->p.accel_profile_m_s2 == 0) ||
	    (o->p.accel_profile_m_s2 != 0 && o->p.accel_sf == 0))
		ssc_warn(co, "the accelerometer scale-factor term needs both --accel-sf (or the sensor's scale_factor_error) and --accel-profile: it is 0");
	if (o->p.gyro_bias_rad_s == 0 && o->p.accel_bias_m_s2 == 0 &&
	    o->p.arw_rad_sqrt_s == 0 && o->p.vrw_m_s_sqrt_s == 0 &&
	    (o->p.gyro_sf * o->p.turn_rate_rad_s) == 0 &&
	    (o->p.accel_sf * o->p.accel_profile_m_s2) == 0)
		return ssc_usage_error(co->cmd, "no error source: give --sensor or --gyro-bias, --accel-bias, --arw, --vrw");
	if (o->n_times == 0) {
		memcpy(o->times, deft, sizeof(deft));
		o->n_times = sizeof(deft) / sizeof(deft[0]);
	}
	qsort(o->times, o->n_times, sizeof(double), ssc_cmp_double);
	R->t_max = o->times[o->n_times - 1];
	for (size_t j = 0; j < o->n_times; j++) {
		struct sscope_budget_point pt;

		if (sscope_budget_total(&o->p, o->times[j], &pt) == -ERANGE) {
			ssc_err(co->cmd, "the drift at t = %g s exceeds the double range: check the sources' values and units",
				o->times[j]);
			return SSC_EXIT_FAIL;
		}
	}
	for (int g = 1; o->mc > 0 && g >= 0; g--) {
		if ((g ? o->p.arw_rad_sqrt_s : o->p.vrw_m_s_sqrt_s) == 0)
			continue;
		rc = run_mc(o, g, R->t_max, co->plot != NULL, &R->mc[R->n_mc]);
		if (rc) {
			ssc_err(co->cmd, "Monte Carlo: %s", sscope_strerror(rc));
			return SSC_EXIT_FAIL;
		}
		R->n_mc++;
	}
	sscope_budget_crossovers(&o->p, fmin(0.1, o->times[0]), R->t_max, R->cr,
				 32, &R->n_cr);
	return SSC_EXIT_OK;
}

static const char *source_name(int s)
{
	return sscope_budget_source_name((enum sscope_budget_source)s);
}

/* a source in words, for text (JSON and CSV keep their names) */
static const char *source_label(int s)
{
	static const char *const label[SSCOPE_BUDGET_N_SOURCES] = {
		[SSCOPE_BUDGET_GYRO_BIAS] = "gyro bias",
		[SSCOPE_BUDGET_ACCEL_BIAS] = "accel bias",
		[SSCOPE_BUDGET_ARW] = "ARW",
		[SSCOPE_BUDGET_VRW] = "VRW",
		[SSCOPE_BUDGET_SCALE_FACTOR] = "scale factor",
	};

	return s >= 0 && s < SSCOPE_BUDGET_N_SOURCES ? label[s] : "-";
}

static json_t *json(const void *opts, const void *result)
{
	const struct budget_res *R = result;
	const struct opts *o = &R->o;
	json_t *root = json_object(), *ts = json_array(), *srcs = json_array();
	json_t *tot = json_object(), *tp = json_array(), *tv = json_array(),
	       *ta = json_array(), *models = json_array(), *dom = json_array();
	json_t *in = json_object(), *jcr = json_array(), *tt = json_array();
	int rc;

	(void)opts;
	json_object_set_new(root, "command", json_string("budget"));
	for (size_t j = 0; j < o->n_times; j++) {
		struct sscope_budget_point pt;
		int d = sscope_budget_dominant(&o->p, o->times[j], NULL);

		json_array_append_new(ts, json_real(o->times[j]));
		sscope_budget_total(&o->p, o->times[j], &pt);
		json_array_append_new(tp, ssc_jreal(pt.position_m));
		json_array_append_new(tv, ssc_jreal(pt.velocity_m_s));
		json_array_append_new(ta, ssc_jreal(pt.attitude_rad));
		json_array_append_new(models, json_string(model_name(&o->p, o->times[j])));
		json_array_append_new(dom, d >= 0 ? json_string(source_name(d)) : json_null());
	}
	json_object_set_new(root, "times_s", ts);
	for (int s = 0; s < SSCOPE_BUDGET_N_SOURCES; s++) {
		json_t *so = json_object(), *p = json_array(), *v = json_array(),
		       *a = json_array();

		for (size_t j = 0; j < o->n_times; j++) {
			struct sscope_budget_point pt;

			sscope_budget_source_eval(&o->p, (enum sscope_budget_source)s,
						  o->times[j], &pt);
			json_array_append_new(p, ssc_jreal(pt.position_m));
			json_array_append_new(v, ssc_jreal(pt.velocity_m_s));
			json_array_append_new(a, ssc_jreal(pt.attitude_rad));
		}
		json_object_set_new(so, "name", json_string(source_name(s)));
		json_object_set_new(so, "random", json_boolean(sscope_budget_source_random(
						   (enum sscope_budget_source)s)));
		json_object_set_new(so, "position_m", p);
		json_object_set_new(so, "velocity_m_s", v);
		json_object_set_new(so, "attitude_rad", a);
		json_array_append_new(srcs, so);
	}
	json_object_set_new(root, "sources", srcs);
	json_object_set_new(tot, "position_m", tp);
	json_object_set_new(tot, "velocity_m_s", tv);
	json_object_set_new(tot, "attitude_rad", ta);
	json_object_set_new(tot, "combination", json_string("root sum of squares"));
	json_object_set_new(root, "total", tot);
	json_object_set_new(root, "model", models);
	json_object_set_new(root, "switch_time_s",
			    o->p.model == SSCOPE_BUDGET_AUTO ?
				    json_real(o->p.switch_time_s > 0 ? o->p.switch_time_s : 300) :
				    json_null());
	json_object_set_new(root, "schuler_period_s",
			    json_real(2 * PI / sscope_budget_schuler_rad_s(&o->p)));
	json_object_set_new(root, "dominant", dom);
	for (size_t i = 0; i < R->n_cr; i++) {
		json_t *c = json_object();

		json_object_set_new(c, "t_s", json_real(R->cr[i].t_s));
		json_object_set_new(c, "from", json_string(source_name((int)R->cr[i].from)));
		json_object_set_new(c, "to", json_string(source_name((int)R->cr[i].to)));
		json_array_append_new(jcr, c);
	}
	json_object_set_new(root, "crossovers", jcr);
	for (size_t e = 0; e < o->n_err; e++) {
		json_t *c = json_object(), *per = json_object();
		double t;

		json_object_set_new(c, "quantity", json_string(qty_name(o->err_q[e])));
		json_object_set_new(c, "value", json_real(o->err[e]));
		json_object_set_new(c, "unit", json_string(qty_unit(o->err_q[e])));
		rc = sscope_budget_time_to(&o->p, -1, o->err_q[e], o->err[e], 1e7, &t);
		json_object_set_new(c, "total_s", rc ? json_null() : json_real(t));
		for (int s = 0; s < SSCOPE_BUDGET_N_SOURCES; s++) {
			rc = sscope_budget_time_to(&o->p, s, o->err_q[e], o->err[e], 1e7, &t);
			json_object_set_new(per, source_name(s), rc ? json_null() : json_real(t));
		}
		json_object_set_new(c, "sources_s", per);
		json_array_append_new(tt, c);
	}
	json_object_set_new(root, "time_to", tt);
	json_object_set_new(in, "gyro_bias_rad_s", json_real(o->p.gyro_bias_rad_s));
	json_object_set_new(in, "gyro_bias_from", json_string(R->from[0]));
	json_object_set_new(in, "accel_bias_m_s2", json_real(o->p.accel_bias_m_s2));
	json_object_set_new(in, "accel_bias_from", json_string(R->from[1]));
	json_object_set_new(in, "arw_rad_sqrt_s", json_real(o->p.arw_rad_sqrt_s));
	json_object_set_new(in, "arw_from", json_string(R->from[2]));
	json_object_set_new(in, "vrw_from", json_string(R->from[3]));
	json_object_set_new(in, "vrw_m_s_sqrt_s", json_real(o->p.vrw_m_s_sqrt_s));
	json_object_set_new(in, "gyro_sf", json_real(o->p.gyro_sf));
	json_object_set_new(in, "accel_sf", json_real(o->p.accel_sf));
	json_object_set_new(in, "turn_rate_rad_s", json_real(o->p.turn_rate_rad_s));
	json_object_set_new(in, "accel_profile_m_s2", json_real(o->p.accel_profile_m_s2));
	json_object_set_new(root, "inputs", in);
	if (R->n_mc) {
		json_t *m = json_array();

		for (int i = 0; i < R->n_mc; i++)
			json_array_append_new(m, mc_json(&R->mc[i]));
		json_object_set_new(root, "monte_carlo", m);
	}
	return root;
}

static void csv(FILE *f, const void *opts, const void *result)
{
	const struct budget_res *R = result;
	const struct opts *o = &R->o;

	(void)opts;
	fprintf(f, "t_s,source,position_m,velocity_m_s,attitude_rad,model\n");
	for (size_t j = 0; j < o->n_times; j++) {
		for (int s = 0; s <= SSCOPE_BUDGET_N_SOURCES; s++) {
			struct sscope_budget_point pt;

			if (s < SSCOPE_BUDGET_N_SOURCES)
				sscope_budget_source_eval(&o->p, (enum sscope_budget_source)s,
							  o->times[j], &pt);
			else
				sscope_budget_total(&o->p, o->times[j], &pt);
			fprintf(f, "%.10g,%s,%.10g,%.10g,%.10g,%s\n", o->times[j],
				s < SSCOPE_BUDGET_N_SOURCES ? source_name(s) : "total",
				pt.position_m, pt.velocity_m_s, pt.attitude_rad,
				model_name(&o->p, o->times[j]));
		}
	}
}

/* where a source came from, in words (JSON keeps the spec's keys) */
static const char *from_words(const char *from)
{
	return !strcmp(from, "bias") ? "the sensor's bias" :
	       !strcmp(from, "bias_instability") ? "the sensor's bias instability" :
	       !strcmp(from, "noise_density") ? "the sensor's noise density" : from;
}

static void text(FILE *f, const void *opts, const void *result)
{
	const struct budget_res *R = result;
	const struct opts *o = &R->o;
	const char *const *bias_from = R->from;
	char a[32];
	/* a source not given (0, from no option, file or sensor): '-' in
	 * its column, not a 0 that reads as measured */
	const bool given[SSCOPE_BUDGET_N_SOURCES] = {
		[SSCOPE_BUDGET_GYRO_BIAS] = o->p.gyro_bias_rad_s != 0 || strcmp(bias_from[0], "not given"),
		[SSCOPE_BUDGET_ACCEL_BIAS] = o->p.accel_bias_m_s2 != 0 || strcmp(bias_from[1], "not given"),
		[SSCOPE_BUDGET_ARW] = o->p.arw_rad_sqrt_s != 0 || strcmp(bias_from[2], "not given"),
		[SSCOPE_BUDGET_VRW] = o->p.vrw_m_s_sqrt_s != 0 || strcmp(bias_from[3], "not given"),
		[SSCOPE_BUDGET_SCALE_FACTOR] = o->p.gyro_sf * o->p.turn_rate_rad_s != 0 ||
					       o->p.accel_sf * o->p.accel_profile_m_s2 != 0,
	};

	(void)opts;
	fprintf(f, "drift budget, one horizontal channel (g = %g m/s^2, Schuler period %.2f min)\n",
		o->p.gravity_m_s2 > 0 ? o->p.gravity_m_s2 : SSCOPE_UNIT_GRAVITY_STD,
		2 * PI / sscope_budget_schuler_rad_s(&o->p) / 60);
	{
		/* each source's value and where it came from; one not given
		 * (0 from no option, file or sensor) is said so, not as 0 */
		const double v[4] = {
			o->p.gyro_bias_rad_s * 180 / PI * 3600,
			o->p.accel_bias_m_s2 / (SSCOPE_UNIT_GRAVITY_STD * 1e-6),
			o->p.arw_rad_sqrt_s * 180 / PI * 60, o->p.vrw_m_s_sqrt_s * 60
		};
		static const char *const unit[4] = { "deg/h", "ug", "deg/sqrt(h)", "m/s/sqrt(h)" };

		fprintf(f, "  sources:");
		for (int i = 0; i < 4; i++) {
			const char *from = from_words(bias_from[i]);

			if (!given[i])
				fprintf(f, "%s %s not given", i ? "," : "", source_label(i));
			else
				fprintf(f, "%s %s %s %s%s%s%s", i ? "," : "", source_label(i),
					ssc_fmt(a, sizeof(a), v[i], 4), unit[i],
					from ? " (" : "", from ? from : "", from ? ")" : "");
		}
	}
	if (o->p.gyro_sf * o->p.turn_rate_rad_s != 0 ||
	    o->p.accel_sf * o->p.accel_profile_m_s2 != 0)
		fprintf(f, ", scale factor %s ppm at %s deg/s, %s ppm at %s m/s^2",
			ssc_fmt(a, sizeof(a), o->p.gyro_sf * 1e6, 4),
			ssc_fmt((char[32]){ 0 }, 32, o->p.turn_rate_rad_s * 180 / PI, 4),
			ssc_fmt((char[32]){ 0 }, 32, o->p.accel_sf * 1e6, 4),
			ssc_fmt((char[32]){ 0 }, 32, o->p.accel_profile_m_s2, 4));
	fputc('\n', f);
	if (o->p.model == SSCOPE_BUDGET_AUTO)
		fprintf(f, "  formulas: open loop up to %g s, Schuler-bounded after (the t^3 form is 0.7 %% high at 300 s)\n",
			o->p.switch_time_s > 0 ? o->p.switch_time_s : 300);
	else
		fprintf(f, "  formulas: %s at every time\n",
			o->p.model == SSCOPE_BUDGET_SCHULER ? "Schuler-bounded" : "open loop");
	fprintf(f, "\n  position error (m; random walks 1 sigma, +-2 sigma holds 95 %%)\n");
	fprintf(f, "  %10s %11s %11s %11s %11s %12s %11s  %-12s %s\n", "t (s)",
		"gyro bias", "accel bias", "ARW", "VRW", "scale factor",
		"total", "dominant", "model");
	for (size_t j = 0; j < o->n_times; j++) {
		struct sscope_budget_point pt;
		int d = sscope_budget_dominant(&o->p, o->times[j], NULL);

		fprintf(f, "  %10s", ssc_fmt(a, sizeof(a), o->times[j], 6));
		for (int s = 0; s < SSCOPE_BUDGET_N_SOURCES; s++) {
			sscope_budget_source_eval(&o->p, (enum sscope_budget_source)s,
						  o->times[j], &pt);
			fprintf(f, s == 4 ? " %12s" : " %11s", !given[s] ? "-" :
				ssc_fmt(a, sizeof(a), pt.position_m, 4));
		}
		sscope_budget_total(&o->p, o->times[j], &pt);
		fprintf(f, " %11s  %-12s %s\n", ssc_fmt(a, sizeof(a), pt.position_m, 4),
			source_label(d), sscope_budget_is_schuler(&o->p, o->times[j]) ?
			"Schuler" : "open loop");
	}
	fprintf(f, "\n  total velocity (m/s) and attitude (deg) error\n");
	for (size_t j = 0; j < o->n_times; j++) {
		struct sscope_budget_point pt;

		sscope_budget_total(&o->p, o->times[j], &pt);
		/* no gyro source given: the attitude error is not known, not 0 */
		fprintf(f, "  %10s %11s %11s\n", ssc_fmt(a, sizeof(a), o->times[j], 6),
			ssc_fmt((char[32]){ 0 }, 32, pt.velocity_m_s, 4),
			given[SSCOPE_BUDGET_GYRO_BIAS] || given[SSCOPE_BUDGET_ARW] ||
					given[SSCOPE_BUDGET_SCALE_FACTOR] ?
				ssc_fmt((char[32]){ 0 }, 32, pt.attitude_rad * 180 / PI, 4) : "-");
	}
	if (R->n_cr) {
		fprintf(f, "\n  dominant source changes:\n");
		for (size_t i = 0; i < R->n_cr; i++)
			fprintf(f, "    at %s s: %s -> %s\n",
				ssc_fmt(a, sizeof(a), R->cr[i].t_s, 4),
				source_label((int)R->cr[i].from), source_label((int)R->cr[i].to));
	}
	for (size_t e = 0; e < o->n_err; e++) {
		double t;

		fprintf(f, "\n  time to %s error %s %s:", qty_name(o->err_q[e]),
			ssc_fmt(a, sizeof(a), o->err[e], 4), qty_unit(o->err_q[e]));
		if (sscope_budget_time_to(&o->p, -1, o->err_q[e], o->err[e], 1e7, &t) == 0)
			fprintf(f, " total %s s", ssc_fmt(a, sizeof(a), t, 5));
		else
			fprintf(f, " total not reached within 1e7 s");
		for (int s = 0; s < SSCOPE_BUDGET_N_SOURCES; s++)
			if (sscope_budget_time_to(&o->p, s, o->err_q[e], o->err[e], 1e7, &t) == 0)
				fprintf(f, "; %s %s s", source_label(s),
					ssc_fmt(a, sizeof(a), t, 5));
		fputc('\n', f);
	}
	for (int i = 0; i < R->n_mc; i++) {
		const struct mc_res *m = &R->mc[i];
		double sd, p = sscope_budget_mc_expected(m->o.realisations, &sd);

		fprintf(f, "\n  Monte Carlo (%s, %zu seeded realisations, seed %lu): fraction inside +-2 sigma sqrt(t), expected %.4f +- %.4f (binomial sd)\n",
			m->o.gyro ? "ARW" : "VRW", m->o.realisations, m->o.seed, p,
			sd);
		for (size_t j = 0; j < m->n; j++)
			fprintf(f, "    t = %-8s %s inside %.4f (sd ratio %.4f), position inside %.4f (sd ratio %.4f)\n",
				ssc_fmt(a, sizeof(a), m->pt[j].t_s, 5),
				m->o.gyro ? "attitude" : "velocity", m->pt[j].walk_inside,
				m->pt[j].walk_sd / m->pt[j].walk_sd_theory,
				m->pt[j].pos_inside, m->pt[j].pos_sd / m->pt[j].pos_sd_theory);
	}
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct budget_res *R = result;
	const struct opts *o = &R->o;
	char a[32], q[64];

	(void)opts;
	for (size_t j = 0; j < o->n_times; j++) {
		struct sscope_budget_point pt;

		sscope_budget_total(&o->p, o->times[j], &pt);
		snprintf(q, sizeof(q), "position error after %s s",
			 ssc_fmt(a, sizeof(a), o->times[j], 5));
		ssc_summary_add(rows, NULL, q, pt.position_m, NAN, NAN, "m",
				"root sum of squares of the sources");
	}
}

const struct ssc_stage_ops ssc_budget_stage = {
	.spec = &spec,
	.title = "Drift budget",
	.needs = 0,
	.min_files = 0,
	.max_files = 0,
	.opts_size = sizeof(struct opts),
	.init = init,
	.handle = handler,
	.check = check,
	.run = run,
	.json = json,
	.text = text,
	.csv = csv,
	.summary = summary,
	.plot = plot,
	.free_result = free_result,
};

int ssc_cmd_budget(int argc, char **argv)
{
	return ssc_stage_main(&ssc_budget_stage, argc, argv);
}
