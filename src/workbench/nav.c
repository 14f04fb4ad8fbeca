/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The `nav` stage (see nav.h): options, channels and noise terms, the
 * zero-velocity-aided navigation of analysis/zupt.c, and its JSON, text,
 * CSV (navsim's trajectory columns first, so that the output is a navsim
 * --trajectory file) and figure (plan view with 1-sigma circles, biases
 * against time with 1-sigma bands).
 */
#include "workbench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "datasheet.h"
#include "nav.h"
#include "navcommon.h"
#include "plot.h"
#include "stage.h"

#define D2R (PI / 180)
#define DEG_H (D2R / 3600)      /* 1 deg/h in rad/s */
#define MG (9.80665e-3)         /* 1 mg in m/s^2 */

static const char *const axis_name[3] = { "x", "y", "z" };

void ssc_nav_init(void *opts)
{
	struct ssc_nav_opts *o = opts;

	memset(o, 0, sizeof(*o));
	sscope_zupt_opts_init(&o->zo);
}

int ssc_nav_handle(int key, const char *arg, void *opts)
{
	struct ssc_nav_opts *o = opts;
	double v;

	switch (key) {
	case SSC_NAV_O_LAT:
		if (ssc_arg_quantity("nav", "latitude", arg, "deg", &v))
			return SSC_EXIT_USAGE;
		if (!(fabs(v) < 89 * D2R))
			return ssc_usage_error("nav", "--latitude: '%s' is out of range (within +-89 degrees)", arg);
		o->zo.start.lat_rad = v;
		return 0;
	case SSC_NAV_O_LON:
		return ssc_arg_quantity("nav", "longitude", arg, "deg", &o->zo.start.lon_rad) ?
			       SSC_EXIT_USAGE : 0;
	case SSC_NAV_O_HEIGHT:
		return ssc_arg_quantity("nav", "height", arg, "m", &o->zo.start.height_m) ?
			       SSC_EXIT_USAGE : 0;
	case SSC_NAV_O_HEADING:
		o->zo.heading_given = true;
		return ssc_arg_quantity("nav", "heading", arg, "deg", &o->zo.heading_rad) ?
			       SSC_EXIT_USAGE : 0;
	case SSC_NAV_O_ALLAN:
		o->allan = arg;
		return 0;
	case SSC_NAV_O_SPEC:
		o->spec = arg;
		return 0;
	case SSC_NAV_O_NO_ZUPT:
		o->zo.no_zupt = true;
		return 0;
	case SSC_NAV_O_WINDOW:
		return ssc_arg_positive("nav", "window", arg, "s", &o->zo.window_s);
	case SSC_NAV_O_STEP:
		return ssc_arg_positive("nav", "output-step", arg, "s", &o->zo.output_step_s);
	default:
		return ssc_usage_error("nav", "unexpected option");
	}
}

int ssc_nav_check(struct ssc_common *co, void *opts)
{
	const struct ssc_nav_opts *o = opts;

	if (o->allan && o->spec)
		return ssc_usage_error(co->cmd, "--from-allan and --spec: give one source of noise terms");
	return 0;
}

/* three channels of quantity q, in the capture's order */
static int pick(const char *cmd, const char *path, const struct sscope_capture *cap,
		enum sscope_quantity q, long idx[3])
{
	size_t k = 0;

	for (size_t c = 0; c < cap->n_channels && k < 3; c++)
		if (cap->channels[c].col.quantity == q)
			idx[k++] = (long)c;
	if (k == 3)
		return 0;
	ssc_err(cmd, "%s: %zu %s channel%s: three are needed (give units, e.g. '%s' or -u, and pick them with -c)",
		path, k, q == SSCOPE_QUANTITY_ANGULAR_RATE ? "angular-rate" : "acceleration",
		k == 1 ? "" : "s", q == SSCOPE_QUANTITY_ANGULAR_RATE ? "gx [deg/s]" : "ax [m/s^2]");
	return SSC_EXIT_FAIL;
}

/* N, B, K of both triads: an allan result (file or the scene's stage), a
 * datasheet, a scene's [sensor]; what is missing keeps the default */
static int noise_terms(const struct ssc_stage_env *env, const void *up,
		       struct ssc_nav_result *s)
{
	const char *cmd = env->co->cmd;
	struct sscope_zupt_opts *zo = &s->o.zo;
	double t[2][3] = { { NAN, NAN, NAN }, { NAN, NAN, NAN } };
	int rc = 0;

	s->noise_from = "defaults";
	if (s->o.allan || up) {
		json_t *root = NULL;
		struct ssc_nav_terms *tt = NULL;
		size_t n = 0;

		if (s->o.allan) {
			rc = ssc_nav_load_json(cmd, "from-allan", s->o.allan, &root);
			if (!rc)
				rc = ssc_nav_terms_from_allan(cmd, root, s->o.allan, &tt, &n);
			json_decref(root);
		} else {
			rc = ssc_nav_terms_from_allan_res(cmd, up, "the allan stage", &tt, &n);
		}
		if (rc)
			return rc;
		for (int q = 0; q < 2; q++) {
			const struct ssc_nav_terms *p = ssc_nav_terms_pick(
				tt, n, NULL, q ? SSCOPE_QUANTITY_ACCELERATION : SSCOPE_QUANTITY_ANGULAR_RATE);

			if (p) {
				t[q][0] = p->coef[SSCOPE_TERM_N];
				t[q][1] = p->coef[SSCOPE_TERM_B];
				t[q][2] = p->coef[SSCOPE_TERM_K];
			}
		}
		free(tt);
		s->noise_from = "allan";
	} else if (s->o.spec) {
		struct ssc_datasheet ds;

		rc = ssc_datasheet_load(cmd, s->o.spec, &ds);
		if (rc)
			return rc;
		for (size_t k = 0; k < ds.n_sec; k++) {
			int from[3];

			ssc_datasheet_terms(&ds.sec[k],
					    t[ds.sec[k].quantity == SSCOPE_QUANTITY_ACCELERATION], from);
		}
		s->noise_from = "datasheet";
	} else if (env->sensor) {
		int q = env->sensor->quantity == SSCOPE_QUANTITY_ACCELERATION;

		t[q][0] = env->sensor->n;
		t[q][1] = env->sensor->b;
		t[q][2] = env->sensor->k;
		s->noise_from = "sensor spec";
	}
	/* a term the source does not give (or gives as 0: not resolved)
	 * keeps its default; N must be positive for the detector */
	s->noise_note[0] = 0;
	for (int q = 0; q < 2; q++) {
		double *dst[3] = { q ? &zo->accel_n : &zo->gyro_n, q ? &zo->accel_b : &zo->gyro_b,
				   q ? &zo->accel_k : &zo->gyro_k };

		for (int i = 0; i < 3; i++) {
			if (isfinite(t[q][i]) && (t[q][i] > 0 || i > 0))
				*dst[i] = t[q][i];
			else if (strcmp(s->noise_from, "defaults") && i == 0) {
				size_t l = strlen(s->noise_note);

				snprintf(s->noise_note + l, sizeof(s->noise_note) - l, "%s%s N: the default",
					 l ? "; " : "", q ? "accelerometer" : "gyro");
			}
		}
	}
	return 0;
}

int ssc_nav_run(const struct ssc_stage_env *env, const void *allan_up, void *opts,
		void **result)
{
	const char *cmd = env->co->cmd, *path = env->paths[0];
	const struct sscope_capture *cap = env->caps[0];
	struct ssc_nav_result *s = calloc(1, sizeof(*s));
	struct sscope_diag d = { "" };
	const double *g[3], *a[3];
	int rc;

	if (!s) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = s;
	s->path = path;
	s->o = *(struct ssc_nav_opts *)opts;
	s->cap = cap;
	rc = ssc_time_check(env->co, path, cap, true);
	if (rc)
		return rc;
	if (!(cap->rate_hz > 0)) {
		return ssc_err_no_rate(cmd, path, cap->rate_note);
	}
	rc = pick(cmd, path, cap, SSCOPE_QUANTITY_ANGULAR_RATE, s->gyro);
	if (!rc)
		rc = pick(cmd, path, cap, SSCOPE_QUANTITY_ACCELERATION, s->accel);
	if (!rc)
		rc = noise_terms(env, allan_up, s);
	if (rc)
		return rc;
	if (s->noise_note[0])
		ssc_warn(env->co, "%s: %s", s->o.allan ? s->o.allan : s->o.spec ? s->o.spec : path,
			 s->noise_note);
	for (int i = 0; i < 3; i++) {
		g[i] = cap->channels[s->gyro[i]].data;
		a[i] = cap->channels[s->accel[i]].data;
	}
	s->o.zo.rate_hz = cap->rate_hz;
	rc = sscope_zupt_run(g, a, 1, cap->n, &s->o.zo, &s->r, &d);
	if (rc)
		return ssc_nav_fail(cmd, rc, &d, path);
	if (s->r->heading_from == SSCOPE_ZUPT_HEADING_ASSUMED) {
		char b[32];

		ssc_warn(env->co, "%s: heading is unobservable (gyrocompassing: 1 sigma %s deg with this gyro's noise and bias): the track starts at heading %g deg (give --heading)",
			 path, s->r->gyrocompass_sd_rad > PI ? "> 180" :
			 ssc_fmt(b, sizeof(b), s->r->gyrocompass_sd_rad / D2R, 3),
			 s->o.zo.heading_rad / D2R);
	}
	return SSC_EXIT_OK;
}

void ssc_nav_free(void *result)
{
	struct ssc_nav_result *s = result;

	if (!s)
		return;
	sscope_zupt_result_free(s->r);
	free(s);
}

/* ------------------------------------------------------------ JSON */

static json_t *vec3(const double *v, double scale)
{
	json_t *a = json_array();

	for (int i = 0; i < 3; i++)
		json_array_append_new(a, ssc_jreal(v[i] / scale));
	return a;
}

static json_t *names(const struct sscope_capture *cap, const long *idx)
{
	json_t *a = json_array();

	for (int i = 0; i < 3; i++)
		json_array_append_new(a, json_string(cap->channels[idx[i]].col.name));
	return a;
}

/* a record field as a column of the trajectory */
#define REC_OFF(f) offsetof(struct sscope_zupt_rec, f)
struct col {
	const char *key, *csv;
	size_t off;
	double scale;
};

static const struct col cols[] = {
	{ "time_s", "time [s]", REC_OFF(t_s), 1 },
	{ "north_m", "north [m]", REC_OFF(ned_m[0]), 1 },
	{ "east_m", "east [m]", REC_OFF(ned_m[1]), 1 },
	{ "down_m", "down [m]", REC_OFF(ned_m[2]), 1 },
	{ "roll_rad", "roll [rad]", REC_OFF(euler_rad[0]), 1 },
	{ "pitch_rad", "pitch [rad]", REC_OFF(euler_rad[1]), 1 },
	{ "yaw_rad", "yaw [rad]", REC_OFF(euler_rad[2]), 1 },
	{ "v_north_m_s", "v_north [m/s]", REC_OFF(v_ned_m_s[0]), 1 },
	{ "v_east_m_s", "v_east [m/s]", REC_OFF(v_ned_m_s[1]), 1 },
	{ "v_down_m_s", "v_down [m/s]", REC_OFF(v_ned_m_s[2]), 1 },
	{ "latitude_deg", "latitude [deg]", REC_OFF(lat_rad), D2R },
	{ "longitude_deg", "longitude [deg]", REC_OFF(lon_rad), D2R },
	{ "height_m", "height [m]", REC_OFF(height_m), 1 },
	{ "sd_north_m", "sd_north [m]", REC_OFF(sd_ned_m[0]), 1 },
	{ "sd_east_m", "sd_east [m]", REC_OFF(sd_ned_m[1]), 1 },
	{ "sd_down_m", "sd_down [m]", REC_OFF(sd_ned_m[2]), 1 },
	{ "sd_v_north_m_s", "sd_v_north [m/s]", REC_OFF(sd_v_m_s[0]), 1 },
	{ "sd_v_east_m_s", "sd_v_east [m/s]", REC_OFF(sd_v_m_s[1]), 1 },
	{ "sd_v_down_m_s", "sd_v_down [m/s]", REC_OFF(sd_v_m_s[2]), 1 },
	{ "sd_roll_rad", "sd_roll [rad]", REC_OFF(sd_euler_rad[0]), 1 },
	{ "sd_pitch_rad", "sd_pitch [rad]", REC_OFF(sd_euler_rad[1]), 1 },
	{ "sd_yaw_rad", "sd_yaw [rad]", REC_OFF(sd_euler_rad[2]), 1 },
	{ "gyro_bias_x_rad_s", "gyro_bias_x [rad/s]", REC_OFF(gyro_bias_rad_s[0]), 1 },
	{ "gyro_bias_y_rad_s", "gyro_bias_y [rad/s]", REC_OFF(gyro_bias_rad_s[1]), 1 },
	{ "gyro_bias_z_rad_s", "gyro_bias_z [rad/s]", REC_OFF(gyro_bias_rad_s[2]), 1 },
	{ "sd_gyro_bias_x_rad_s", "sd_gyro_bias_x [rad/s]", REC_OFF(sd_gyro_bias_rad_s[0]), 1 },
	{ "sd_gyro_bias_y_rad_s", "sd_gyro_bias_y [rad/s]", REC_OFF(sd_gyro_bias_rad_s[1]), 1 },
	{ "sd_gyro_bias_z_rad_s", "sd_gyro_bias_z [rad/s]", REC_OFF(sd_gyro_bias_rad_s[2]), 1 },
	{ "accel_bias_x_m_s2", "accel_bias_x [m/s^2]", REC_OFF(accel_bias_m_s2[0]), 1 },
	{ "accel_bias_y_m_s2", "accel_bias_y [m/s^2]", REC_OFF(accel_bias_m_s2[1]), 1 },
	{ "accel_bias_z_m_s2", "accel_bias_z [m/s^2]", REC_OFF(accel_bias_m_s2[2]), 1 },
	{ "sd_accel_bias_x_m_s2", "sd_accel_bias_x [m/s^2]", REC_OFF(sd_accel_bias_m_s2[0]), 1 },
	{ "sd_accel_bias_y_m_s2", "sd_accel_bias_y [m/s^2]", REC_OFF(sd_accel_bias_m_s2[1]), 1 },
	{ "sd_accel_bias_z_m_s2", "sd_accel_bias_z [m/s^2]", REC_OFF(sd_accel_bias_m_s2[2]), 1 },
};

#define N_COLS (sizeof(cols) / sizeof(cols[0]))

static double colv(const struct sscope_zupt_rec *r, const struct col *c)
{
	return *(const double *)((const char *)r + c->off) / c->scale;
}

/* distance along the track and the horizontal 1-sigma at the end */
static void track_stats(const struct sscope_zupt_result *r, double *dist, double *sd_end)
{
	const struct sscope_zupt_rec *e = &r->rec[r->n_rec - 1];

	*dist = 0;
	for (size_t k = 1; k < r->n_rec; k++)
		*dist += hypot(r->rec[k].ned_m[0] - r->rec[k - 1].ned_m[0],
			       r->rec[k].ned_m[1] - r->rec[k - 1].ned_m[1]);
	*sd_end = hypot(e->sd_ned_m[0], e->sd_ned_m[1]);
}

json_t *ssc_nav_json(const void *opts, const void *result)
{
	const struct ssc_nav_result *s = result;
	const struct sscope_zupt_result *r = s->r;
	const struct sscope_zupt_opts *zo = &s->o.zo;
	json_t *root = json_object(), *o, *st = json_array(), *tr = json_object();
	double dist, sd_end;

	(void)opts;
	json_object_set_new(root, "command", json_string("nav"));
	json_object_set_new(root, "file", json_string(s->path));
	json_object_set_new(root, "rate_hz", ssc_jreal(s->cap->rate_hz));
	json_object_set_new(root, "samples", json_integer((json_int_t)s->cap->n));
	o = json_object();
	json_object_set_new(o, "gyro", names(s->cap, s->gyro));
	json_object_set_new(o, "accel", names(s->cap, s->accel));
	json_object_set_new(root, "channels", o);
	o = json_object();
	json_object_set_new(o, "source", json_string(s->noise_from));
	json_object_set_new(o, "gyro_n_rad_s_sqrt_hz", ssc_jreal(zo->gyro_n));
	json_object_set_new(o, "gyro_b_rad_s", ssc_jreal(zo->gyro_b));
	json_object_set_new(o, "gyro_k_rad_s2_sqrt_hz", ssc_jreal(zo->gyro_k));
	json_object_set_new(o, "accel_n_m_s2_sqrt_hz", ssc_jreal(zo->accel_n));
	json_object_set_new(o, "accel_b_m_s2", ssc_jreal(zo->accel_b));
	json_object_set_new(o, "accel_k_m_s3_sqrt_hz", ssc_jreal(zo->accel_k));
	json_object_set_new(o, "gyro_bias_prior_rad_s", ssc_jreal(zo->gyro_bias_sd_rad_s));
	json_object_set_new(o, "accel_bias_prior_m_s2", ssc_jreal(zo->accel_bias_sd_m_s2));
	json_object_set_new(root, "noise", o);
	o = json_object();
	json_object_set_new(o, "latitude_deg", ssc_jreal(zo->start.lat_rad / D2R));
	json_object_set_new(o, "longitude_deg", ssc_jreal(zo->start.lon_rad / D2R));
	json_object_set_new(o, "height_m", ssc_jreal(zo->start.height_m));
	json_object_set_new(o, "level_s", ssc_jreal(r->level_s));
	json_object_set_new(o, "roll_deg", ssc_jreal(r->roll0_rad / D2R));
	json_object_set_new(o, "pitch_deg", ssc_jreal(r->pitch0_rad / D2R));
	json_object_set_new(o, "heading_deg", ssc_jreal(r->heading0_rad / D2R));
	/* an assumed heading is not known: no 0 for its uncertainty */
	json_object_set_new(o, "heading_sd_deg",
			    r->heading_from == SSCOPE_ZUPT_HEADING_ASSUMED ?
				    json_null() :
				    ssc_jreal(r->heading0_sd_rad / D2R));
	json_object_set_new(o, "heading_from", json_string(sscope_zupt_heading_name(r->heading_from)));
	json_object_set_new(o, "gyrocompass_sd_deg", ssc_jreal(r->gyrocompass_sd_rad / D2R));
	json_object_set_new(root, "start", o);
	o = json_object();
	json_object_set_new(o, "window_s", ssc_jreal((double)r->window / s->cap->rate_hz));
	json_object_set_new(o, "false_alarm", ssc_jreal(zo->false_alarm));
	json_object_set_new(o, "threshold_variance", ssc_jreal(r->threshold));
	json_object_set_new(o, "threshold_mean", ssc_jreal(r->threshold_mean));
	json_object_set_new(o, "still_fraction",
			    ssc_jreal(r->n_updates ? (double)r->n_still / (double)r->n_updates : 0));
	json_object_set_new(root, "detector", o);
	json_object_set_new(root, "zupt", json_boolean(!zo->no_zupt));
	for (size_t k = 0; k < r->n_stops; k++) {
		const struct sscope_zupt_stop *p = &r->stops[k];

		o = json_object();
		json_object_set_new(o, "start_s", ssc_jreal(p->t_start_s));
		json_object_set_new(o, "end_s", ssc_jreal(p->t_end_s));
		json_object_set_new(o, "gyro_bias_rad_s", vec3(p->gyro_bias_rad_s, 1));
		json_object_set_new(o, "gyro_bias_sd_rad_s", vec3(p->sd_gyro_bias_rad_s, 1));
		json_object_set_new(o, "accel_bias_m_s2", vec3(p->accel_bias_m_s2, 1));
		json_object_set_new(o, "accel_bias_sd_m_s2", vec3(p->sd_accel_bias_m_s2, 1));
		json_array_append_new(st, o);
	}
	json_object_set_new(root, "stops", st);
	track_stats(r, &dist, &sd_end);
	o = json_object();
	{
		const struct sscope_zupt_rec *e = &r->rec[r->n_rec - 1];

		json_object_set_new(o, "time_s", ssc_jreal(e->t_s));
		json_object_set_new(o, "north_m", ssc_jreal(e->ned_m[0]));
		json_object_set_new(o, "east_m", ssc_jreal(e->ned_m[1]));
		json_object_set_new(o, "down_m", ssc_jreal(e->ned_m[2]));
		json_object_set_new(o, "horizontal_sd_m", ssc_jreal(sd_end));
		json_object_set_new(o, "distance_m", ssc_jreal(dist));
	}
	json_object_set_new(root, "end", o);
	for (size_t c = 0; c < N_COLS; c++) {
		json_t *a = json_array();

		for (size_t k = 0; k < r->n_rec; k++)
			json_array_append_new(a, ssc_jreal(colv(&r->rec[k], &cols[c])));
		json_object_set_new(tr, cols[c].key, a);
	}
	{
		json_t *a = json_array();

		for (size_t k = 0; k < r->n_rec; k++)
			json_array_append_new(a, json_boolean(r->rec[k].still));
		json_object_set_new(tr, "still", a);
	}
	json_object_set_new(root, "trajectory", tr);
	return root;
}

/* ------------------------------------------------------------ text, CSV */

void ssc_nav_text(FILE *f, const void *opts, const void *result)
{
	const struct ssc_nav_result *s = result;
	const struct sscope_zupt_result *r = s->r;
	const struct sscope_zupt_opts *zo = &s->o.zo;
	const struct sscope_zupt_rec *e = &r->rec[r->n_rec - 1];
	double dist, sd_end;

	(void)opts;
	track_stats(r, &dist, &sd_end);
	fprintf(f, "%s: %zu samples at %g Hz (%.1f s); gyro %s,%s,%s; accelerometer %s,%s,%s\n", s->path,
		s->cap->n, s->cap->rate_hz, (double)s->cap->n / s->cap->rate_hz,
		s->cap->channels[s->gyro[0]].col.name, s->cap->channels[s->gyro[1]].col.name,
		s->cap->channels[s->gyro[2]].col.name, s->cap->channels[s->accel[0]].col.name,
		s->cap->channels[s->accel[1]].col.name, s->cap->channels[s->accel[2]].col.name);
	fprintf(f, "noise (%s): gyro N %.3g deg/sqrt(h), B %.3g deg/h; accelerometer N %.3g m/s/sqrt(h), B %.3g mg\n",
		s->noise_from, zo->gyro_n / D2R * 60, zo->gyro_b / DEG_H, zo->accel_n * 60,
		zo->accel_b / MG);
	fprintf(f, "start: levelled on %.2f s: roll %.3f deg, pitch %.3f deg; heading %.2f deg (",
		r->level_s, r->roll0_rad / D2R, r->pitch0_rad / D2R, r->heading0_rad / D2R);
	if (r->heading_from == SSCOPE_ZUPT_HEADING_ASSUMED)
		fprintf(f, "assumed: unobservable, its error not in the 1 sigma below)\n");
	else if (r->heading0_sd_rad > 0)
		fprintf(f, "%s, 1 sigma %.3g deg)\n", sscope_zupt_heading_name(r->heading_from),
			r->heading0_sd_rad / D2R);
	else
		fprintf(f, "%s, taken as exact)\n", sscope_zupt_heading_name(r->heading_from));
	fprintf(f, "stops: %zu (still %.1f %% of the time; window %.2f s)%s\n", r->n_stops,
		r->n_updates ? 100.0 * (double)r->n_still / (double)r->n_updates : 0,
		(double)r->window / s->cap->rate_hz,
		zo->no_zupt ? "; no updates applied (--no-zupt)" : "");
	fprintf(f, "  %9s %9s  %-32s %-32s\n", "start s", "end s", "gyro bias x,y,z +-1sd (deg/h)",
		"accel bias x,y,z +-1sd (mg)");
	for (size_t k = 0; k < r->n_stops; k++) {
		const struct sscope_zupt_stop *p = &r->stops[k];
		char gb[96] = "", ab[96] = "";

		for (int i = 0; i < 3; i++) {
			size_t lg = strlen(gb), la = strlen(ab);

			snprintf(gb + lg, sizeof(gb) - lg, "%s%.3g+-%.2g", i ? " " : "",
				 p->gyro_bias_rad_s[i] / DEG_H, p->sd_gyro_bias_rad_s[i] / DEG_H);
			snprintf(ab + la, sizeof(ab) - la, "%s%.3g+-%.2g", i ? " " : "",
				 p->accel_bias_m_s2[i] / MG, p->sd_accel_bias_m_s2[i] / MG);
		}
		fprintf(f, "  %9.2f %9.2f  %-32s %-32s\n", p->t_start_s, p->t_end_s, gb, ab);
	}
	fprintf(f, "end at %.1f s: north %.2f m, east %.2f m, down %.2f m; horizontal 1 sigma %.3g m; %.1f m travelled\n",
		e->t_s, e->ned_m[0], e->ned_m[1], e->ned_m[2], sd_end, dist);
}

void ssc_nav_csv(FILE *f, const void *opts, const void *result)
{
	const struct ssc_nav_result *s = result;
	const struct sscope_zupt_result *r = s->r;

	(void)opts;
	fprintf(f, "# sensorscope nav: %s; positions in the tangent plane of the start\n", s->path);
	for (size_t c = 0; c < N_COLS; c++)
		fprintf(f, "%s,", cols[c].csv);
	fprintf(f, "still\n");
	for (size_t k = 0; k < r->n_rec; k++) {
		for (size_t c = 0; c < N_COLS; c++)
			fprintf(f, "%.10g,", colv(&r->rec[k], &cols[c]));
		fprintf(f, "%d\n", r->rec[k].still ? 1 : 0);
	}
}

void ssc_nav_summary(json_t *rows, const void *opts, const void *result)
{
	const struct ssc_nav_result *s = result;
	const struct sscope_zupt_result *r = s->r;
	double dist, sd_end;

	(void)opts;
	track_stats(r, &dist, &sd_end);
	ssc_summary_add(rows, "", "stops found", (double)r->n_stops, NAN, NAN, "", "stop detector");
	ssc_summary_add(rows, "", "distance travelled", dist, NAN, NAN, "m", "");
	ssc_summary_add(rows, "", "horizontal position 1 sigma at the end", sd_end, NAN, NAN, "m",
			s->noise_from);
	if (r->heading_from == SSCOPE_ZUPT_HEADING_ASSUMED) {
		ssc_summary_add(rows, "", "initial heading (unobservable, assumed)",
				r->heading0_rad / D2R, NAN, NAN, "deg", "");
		ssc_summary_warn_last(rows);
	}
}

/* ------------------------------------------------------------ figure */

int ssc_nav_plot(const struct ssc_common *co, const void *opts, const void *result,
		 const char *path)
{
	const struct ssc_nav_result *s = result;
	const struct sscope_zupt_result *r = s->r;
	size_t n = r->n_rec, k0 = 0;
	struct ssc_fig *fig = ssc_fig_new(1100, 1700, 3, 1);
	double *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));
	double *lo = malloc(n * sizeof(double)), *hi = malloc(n * sizeof(double));
	char title[256];
	int rc = 0;

	(void)opts;
	if (!fig || !x || !y || !lo || !hi) {
		rc = -ENOMEM;
		goto out;
	}
	snprintf(title, sizeof(title), "%s: strapdown navigation, %s, %zu stops", s->path,
		 s->o.zo.no_zupt ? "no stop updates" : "zero-velocity updates at stops", r->n_stops);
	ssc_fig_title(fig, title);
	{
		/* plan view: east right, north up; 1-sigma circles */
		struct ssc_ax *ax = ssc_fig_ax(fig, 0, 0);
		struct ssc_style tk = { .color = 0x1f77b4, .width = 2 };
		struct ssc_style cs = { .color = 0xd62728, .width = 1 };
		size_t every = n > 25 ? n / 25 : 1;
		double cx[49], cy[49];

		for (size_t k = 0; k < n; k++) {
			x[k] = r->rec[k].ned_m[1];
			y[k] = r->rec[k].ned_m[0];
		}
		ssc_ax_line(ax, x, y, n, &tk, "track");
		for (size_t k = every; k < n; k += every) {
			double rad = hypot(r->rec[k].sd_ned_m[0], r->rec[k].sd_ned_m[1]);

			for (int i = 0; i < 49; i++) {
				cx[i] = x[k] + rad * cos(2 * PI * i / 48);
				cy[i] = y[k] + rad * sin(2 * PI * i / 48);
			}
			ssc_ax_line(ax, cx, cy, 49, &cs, k == every ? "horizontal 1 sigma" : NULL);
		}
		ssc_ax_xlabel(ax, "east (m)");
		ssc_ax_ylabel(ax, "north (m)");
		ssc_ax_legend(ax, SSC_LEGEND_AUTO);
	}
	/* the biases from the end of levelling (before it: the prior) */
	while (k0 + 1 < n && r->rec[k0].t_s < r->level_s)
		k0++;
	for (int q = 0; q < 2; q++) {
		struct ssc_ax *ax = ssc_fig_ax(fig, 1 + q, 0);
		double sc = q ? MG : DEG_H;

		for (int i = 0; i < 3; i++) {
			struct ssc_style st = { .color = ssc_plot_color((size_t)i), .width = 1.6 };
			char lab[32];

			for (size_t k = k0; k < n; k++) {
				const struct sscope_zupt_rec *e = &r->rec[k];
				double b = q ? e->accel_bias_m_s2[i] : e->gyro_bias_rad_s[i];
				double sd = q ? e->sd_accel_bias_m_s2[i] : e->sd_gyro_bias_rad_s[i];

				x[k - k0] = e->t_s;
				y[k - k0] = b / sc;
				lo[k - k0] = (b - sd) / sc;
				hi[k - k0] = (b + sd) / sc;
			}
			snprintf(lab, sizeof(lab), "%s", axis_name[i]);
			ssc_ax_band(ax, x, lo, hi, n - k0, st.color, 0.2, NULL);
			ssc_ax_line(ax, x, y, n - k0, &st, lab);
		}
		ssc_ax_xlabel(ax, "time (s)");
		ssc_ax_ylabel(ax, q ? "accelerometer bias (mg), +-1 sigma" : "gyro bias (deg/h), +-1 sigma");
		ssc_ax_legend(ax, SSC_LEGEND_AUTO);
	}
	rc = ssc_fig_save(fig, path);
out:
	ssc_fig_free(fig);
	free(x);
	free(y);
	free(lo);
	free(hi);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}
