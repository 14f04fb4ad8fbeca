/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope navsim: strapdown or gimballed navigation error simulation (see
 * analysis/sscope-navsim.h).  Sensor errors from a spec, an `allan`
 * result, a `calib` result and options; a reference trajectory (at rest,
 * a straight line, a turn or a CSV of true motion); Monte-Carlo runs;
 * percentiles of position, velocity and attitude error against time
 * beside the drift budget's analytic curves.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "navcommon.h"
#include "plot.h"
#include "results.h"
#include "stage.h"

#define D2R (PI / 180)
#define UG (SSCOPE_UNIT_GRAVITY_STD * 1e-6) /* a micro-g in m/s^2 */

enum {
	O_SENSOR = 300,
	O_ALLAN,
	O_CALIB,
	O_GBIAS,
	O_ABIAS,
	O_ARW,
	O_VRW,
	O_LAT,
	O_LON,
	O_HEIGHT,
	O_HEADING,
	O_TRAJ,
	O_TRAJ_FILE,
	O_DURATION,
	O_RATE,
	O_RUNS,
	O_SEED,
	O_STEP,
	O_VERTICAL,
	O_THREADS,
	O_PLOT,
	O_GADC,
	O_AADC,
	O_MECH,
	O_MECH_PLOT,
};

static const struct ssc_option navsim_opts[] = {
	{ "sensor", required_argument, O_SENSOR, "SPEC.ini",
	  "sensor spec (a gyro and an accelerometer file may both be given): noise terms, range; bias and scale_factor_error as 1-sigma constants drawn per run" },
	{ "from-allan", required_argument, O_ALLAN, "RESULT.json",
	  "noise terms from a JSON result of 'allan': those it resolved, of the worst gyro and accelerometer channel" },
	{ "from-calib", required_argument, O_CALIB, "RESULT.json",
	  "fixed biases, scale factors and misalignments from a JSON result of 'calib' (the uncompensated sensor)" },
	{ "gyro-adc", required_argument, O_GADC, "FILE.ini",
	  "digitize every gyro axis through this converter ([adc] spec; a range in volts uses the gyro spec's sensitivity)" },
	{ "accel-adc", required_argument, O_AADC, "FILE.ini",
	  "digitize every accelerometer axis through this converter" },
	{ "gyro-bias", required_argument, O_GBIAS, "V[,V,V]",
	  "fixed gyro bias, one value for every axis or x,y,z (e.g. 10 deg/h)" },
	{ "accel-bias", required_argument, O_ABIAS, "V[,V,V]",
	  "fixed accelerometer bias (e.g. 1 mg)" },
	{ "arw", required_argument, O_ARW, "V", "angle random walk of every gyro axis (e.g. 0.15 deg/sqrt(h))" },
	{ "vrw", required_argument, O_VRW, "V", "velocity random walk of every accelerometer axis (e.g. 0.05 m/s/sqrt(h))" },
	{ "latitude", required_argument, O_LAT, "DEG", "start latitude (default 45; any, within +-89.9 for a turn or a file)" },
	{ "longitude", required_argument, O_LON, "DEG", "start longitude (default 0)" },
	{ "height", required_argument, O_HEIGHT, "H", "start height above the WGS 84 ellipsoid (default 0 m)" },
	{ "heading", required_argument, O_HEADING, "DEG", "initial heading (default 0, north)" },
	{ "trajectory", required_argument, O_TRAJ, "KIND",
	  "reference motion: static (default), straight:SPEED, turn:RATE[:SPEED] or FILE.csv" },
	{ "trajectory-file", required_argument, O_TRAJ_FILE, "FILE.csv",
	  "the same as --trajectory FILE.csv (in a scene: relative to the scene file)" },
	{ "duration", required_argument, O_DURATION, "T", "simulated span (default 10 min; a file: its span)" },
	{ "rate", required_argument, O_RATE, "HZ", "IMU sample rate (default 100 Hz)" },
	{ "runs", required_argument, O_RUNS, "M", "Monte-Carlo runs (default 100)" },
	{ "seed", required_argument, O_SEED, "N", "random seed (default 1)" },
	{ "output-step", required_argument, O_STEP, "T", "time between error records (default: about 600 records)" },
	{ "vertical", required_argument, O_VERTICAL, "aided|free",
	  "vertical channel aided by a perfect altimeter (default) or free-inertial (diverges in about 10 min)" },
	{ "mechanisation", required_argument, O_MECH, "strapdown|gimballed",
	  "sensors on the body (default) or on a platform torqued to the local level (body rates never reach its gyros)" },
	{ "plot-mechanisations", required_argument, O_MECH_PLOT, "PATH.svg|PATH.png",
	  "also simulate the other mechanisation with the same sensor and runs, and draw both" },
	{ "threads", required_argument, O_THREADS, "N", "threads (default: all)" },
	{ "plot", required_argument, O_PLOT, "PATH.svg|PATH.png",
	  "draw the error percentiles and the budget's curves (PNG needs OpenCV)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "navsim",
	.usage = "navsim [--sensor S.ini | --from-allan RESULT.json] [OPTIONS]",
	.summary =
		"Navigation error simulator: a reference trajectory on the WGS 84 Earth\n"
		"(at any latitude), the increments a perfect IMU gives along it, the same IMU\n"
		"with sensor errors (noise terms, biases, scale factors, misalignments, range),\n"
		"and the error of a wander-azimuth strapdown or gimballed mechanisation (coning\n"
		"and sculling corrections, Earth rate, transport rate, Coriolis, normal\n"
		"gravity) over Monte-Carlo runs: percentiles of position, velocity and\n"
		"attitude error against time, beside the drift budget's Schuler-bounded\n"
		"single-channel curves.",
	.options = navsim_opts,
	.output_opts = true,
	.notes = "Examples:\n"
		 "  sensorscope navsim --gyro-bias 0,10deg/h,0 --runs 1 --duration 2min\n"
		 "  sensorscope navsim --sensor samples/gyro-mems-250.ini --runs 100 --plot navsim.png\n"
		 "  sensorscope navsim --from-allan allan.json --trajectory turn:10deg/s:10m/s\n"
		 "A trajectory file is CSV with 'time [s]', 'north [m]', 'east [m]', 'yaw [deg|rad]'\n"
		 "and optionally 'down', 'roll', 'pitch': positions in the tangent plane of the\n"
		 "start point, attitude relative to the local level.  --format csv writes\n"
		 "time, north, east, down (m) and roll, pitch, yaw (rad) errors: the single run\n"
		 "with --runs 1, the median over runs otherwise.",
};

struct opts {
	const char *sensor[2];
	int n_sensor;
	const char *allan, *calib;
	const char *adc[2]; /* gyro, accelerometer converter specs */
	double gbias[3], abias[3];
	bool set_gbias, set_abias;
	double arw, vrw;
	bool set_arw, set_vrw;
	double lat, lon, height, heading;
	enum sscope_navsim_motion motion;
	double speed, turn_rate;
	const char *traj_file;
	const char *traj_text;
	double duration;
	bool set_duration;
	double rate;
	size_t runs;
	uint64_t seed;
	double step;
	bool free_vertical;
	unsigned threads;
	const char *plot, *mech_plot;
	enum sscope_navsim_mech mech;
};

static int parse_traj(struct opts *o, const char *arg)
{
	o->traj_text = arg;
	o->traj_file = NULL;
	if (!strcmp(arg, "static")) {
		o->motion = SSCOPE_NAVSIM_STATIC;
		return 0;
	}
	if (!strncmp(arg, "straight:", 9)) {
		o->motion = SSCOPE_NAVSIM_STRAIGHT;
		if (ssc_arg_quantity("navsim", "trajectory", arg + 9, "m/s", &o->speed))
			return SSC_EXIT_USAGE;
		if (!(o->speed > 0))
			return ssc_usage_error("navsim", "--trajectory: the speed of a straight line must be positive");
		if (o->speed > 1e4)
			return ssc_usage_error("navsim", "--trajectory: a speed of %g m/s (at most 10 km/s)",
					       o->speed);
		return 0;
	}
	if (!strncmp(arg, "turn:", 5)) {
		char *s = strdup(arg + 5), *colon;
		int rc = 0;

		if (!s)
			return SSC_EXIT_FAIL;
		colon = strchr(s, ':');
		if (colon)
			*colon = '\0';
		o->motion = SSCOPE_NAVSIM_TURN;
		o->speed = 0;
		rc = ssc_arg_quantity("navsim", "trajectory", s, "rad/s", &o->turn_rate);
		if (!rc && colon)
			rc = ssc_arg_quantity("navsim", "trajectory", colon + 1, "m/s", &o->speed);
		if (!rc && (o->turn_rate == 0 || !(o->speed >= 0)))
			rc = ssc_usage_error("navsim", "--trajectory: a turn needs a non-zero rate and a speed >= 0");
		/* a gyro's range ends near 5000 deg/s; 100 rev/s is beyond any */
		if (!rc && fabs(o->turn_rate) > 200 * M_PI)
			rc = ssc_usage_error("navsim", "--trajectory: a turn rate of '%s' is beyond any gyro's range (at most 36000 deg/s)",
					     s);
		if (!rc && o->speed > 1e4)
			rc = ssc_usage_error("navsim", "--trajectory: a speed of %g m/s (at most 10 km/s)",
					     o->speed);
		free(s);
		return rc;
	}
	o->motion = SSCOPE_NAVSIM_TABLE;
	o->traj_file = arg;
	return 0;
}

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;
	const char *cmd = "navsim";
	double v;

	switch (key) {
	case O_SENSOR:
		if (o->n_sensor == 2)
			return ssc_usage_error(cmd, "--sensor: at most two (a gyro and an accelerometer)");
		o->sensor[o->n_sensor++] = arg;
		return 0;
	case O_ALLAN:
		o->allan = arg;
		return 0;
	case O_CALIB:
		o->calib = arg;
		return 0;
	case O_GADC:
	case O_AADC:
		o->adc[key == O_AADC] = arg;
		return 0;
	case O_GBIAS:
		o->set_gbias = true;
		return ssc_nav_arg_vec3(cmd, "gyro-bias", arg, "rad/s", o->gbias);
	case O_ABIAS:
		o->set_abias = true;
		return ssc_nav_arg_vec3(cmd, "accel-bias", arg, "m/s^2", o->abias);
	case O_ARW:
		o->set_arw = true;
		if (ssc_arg_quantity(cmd, "arw", arg, "rad/sqrt(s)", &o->arw))
			return SSC_EXIT_USAGE;
		return o->arw >= 0 ? 0 : ssc_usage_error(cmd, "--arw: must not be negative");
	case O_VRW:
		o->set_vrw = true;
		if (ssc_arg_quantity(cmd, "vrw", arg, "m/s/sqrt(s)", &o->vrw))
			return SSC_EXIT_USAGE;
		return o->vrw >= 0 ? 0 : ssc_usage_error(cmd, "--vrw: must not be negative");
	case O_LAT:
		if (ssc_arg_quantity(cmd, "latitude", arg, "deg", &v))
			return SSC_EXIT_USAGE;
		if (!(fabs(v) <= 90 * D2R))
			return ssc_usage_error(cmd, "--latitude: '%s' is out of range (within +-90 degrees)", arg);
		o->lat = v;
		return 0;
	case O_LON:
		if (ssc_arg_quantity(cmd, "longitude", arg, "deg", &v))
			return SSC_EXIT_USAGE;
		if (!(fabs(v) <= 360 * D2R))
			return ssc_usage_error(cmd, "--longitude: '%s' is out of range", arg);
		o->lon = v;
		return 0;
	case O_HEIGHT:
		if (ssc_arg_quantity(cmd, "height", arg, "m", &o->height))
			return SSC_EXIT_USAGE;
		if (!(o->height > -1e4 && o->height < 1e6))
			return ssc_usage_error(cmd, "--height: must be within -10 km and 1000 km");
		return 0;
	case O_HEADING:
		return ssc_arg_quantity(cmd, "heading", arg, "deg", &o->heading) ?
			       SSC_EXIT_USAGE : 0;
	case O_TRAJ:
		return parse_traj(o, arg);
	case O_TRAJ_FILE:
		o->motion = SSCOPE_NAVSIM_TABLE;
		o->traj_file = o->traj_text = arg;
		return 0;
	case O_DURATION:
		if (ssc_arg_quantity(cmd, "duration", arg, "s", &o->duration))
			return SSC_EXIT_USAGE;
		if (!(o->duration > 0) || o->duration > 30 * 86400)
			return ssc_usage_error(cmd, "--duration: must be positive and at most 30 days");
		o->set_duration = true;
		return 0;
	case O_RATE:
		if (ssc_arg_quantity(cmd, "rate", arg, "Hz", &o->rate))
			return SSC_EXIT_USAGE;
		if (!(o->rate > 0) || o->rate > 1e5)
			return ssc_usage_error(cmd, "--rate: must be positive and at most 100 kHz");
		return 0;
	case O_RUNS:
		if (ssc_arg_size(cmd, "runs", arg, &o->runs))
			return SSC_EXIT_USAGE;
		if (o->runs < 1 || o->runs > 100000)
			return ssc_usage_error(cmd, "--runs: between 1 and 100000");
		return 0;
	case O_SEED: {
		size_t s;

		if (ssc_arg_size(cmd, "seed", arg, &s))
			return SSC_EXIT_USAGE;
		o->seed = s;
		return 0;
	}
	case O_STEP:
		if (ssc_arg_quantity(cmd, "output-step", arg, "s", &o->step))
			return SSC_EXIT_USAGE;
		return o->step > 0 ? 0 : ssc_usage_error(cmd, "--output-step: must be positive");
	case O_VERTICAL:
		if (!strcmp(arg, "aided"))
			o->free_vertical = false;
		else if (!strcmp(arg, "free"))
			o->free_vertical = true;
		else
			return ssc_usage_error(cmd, "--vertical: '%s' is not aided or free", arg);
		return 0;
	case O_THREADS: {
		size_t t;

		if (ssc_arg_size(cmd, "threads", arg, &t))
			return SSC_EXIT_USAGE;
		if (t < 1 || t > 256)
			return ssc_usage_error(cmd, "--threads: between 1 and 256");
		o->threads = (unsigned)t;
		return 0;
	}
	case O_PLOT:
	case O_MECH_PLOT:
		*(key == O_PLOT ? &o->plot : &o->mech_plot) = arg;
		return 0;
	case O_MECH:
		for (o->mech = 0; sscope_navsim_mech_name(o->mech); o->mech++)
			if (!strcmp(arg, sscope_navsim_mech_name(o->mech)))
				return 0;
		return ssc_usage_error(cmd, "--mechanisation: '%s' is not strapdown or gimballed", arg);
	default:
		return ssc_usage_error(cmd, "unexpected option");
	}
}

static void init(void *opts)
{
	struct opts *o = opts;

	memset(o, 0, sizeof(*o));
	o->lat = 45 * D2R;
	o->duration = 600;
	o->rate = 100;
	o->runs = 100;
	o->seed = 1;
	o->traj_text = "static";
}

static int check(struct ssc_common *co, void *opts)
{
	struct opts *o = opts;

	if ((o->motion == SSCOPE_NAVSIM_TURN || o->motion == SSCOPE_NAVSIM_TABLE) &&
	    fabs(o->lat) >= 89.9 * D2R)
		return ssc_usage_error(co->cmd, "--latitude: beyond +-89.9 degrees a turn or a file, given relative to north, is undefined");
	if (o->mech_plot && ssc_plot_check(co->cmd, o->mech_plot))
		return SSC_EXIT_USAGE;
	if (o->plot) {
		int rc = ssc_plot_check(co->cmd, o->plot);

		if (rc)
			return rc;
		co->plot = o->plot;
	}
	return SSC_EXIT_OK;
}

/* ------------------------------------------------------------ inputs */

struct imu_in {
	struct sscope_navsim_imu imu;
	struct ssc_nav_terms gyro, accel; /* noise terms used */
	struct sscope_adc_spec adc[2];    /* converters (gyro, accel) */
	char from[6][160];                /* where each part came from */
	size_t n_from;
};

static void add_from(struct imu_in *in, const char *fmt, const char *what)
{
	if (in->n_from < sizeof(in->from) / sizeof(in->from[0]))
		snprintf(in->from[in->n_from++], sizeof(in->from[0]), fmt, what);
}

static int apply_spec(const char *cmd, struct imu_in *in,
		      const struct sscope_sensor_spec *s, const char *path)
{
	struct sscope_sensor_spec *d;

	if (s->quantity == SSCOPE_QUANTITY_ANGULAR_RATE)
		d = &in->imu.gyro;
	else if (s->quantity == SSCOPE_QUANTITY_ACCELERATION)
		d = &in->imu.accel;
	else {
		ssc_err(cmd, "%s: neither a gyro nor an accelerometer (give range or noise_density with a unit)",
			path);
		return SSC_EXIT_FAIL;
	}
	*d = *s;
	add_from(in, "spec %s", path);
	return SSC_EXIT_OK;
}

/* the worst gyro and accelerometer channel of an allan result's terms */
static void apply_terms(struct imu_in *in, const struct ssc_nav_terms *t,
			size_t n, const char *what)
{
	for (int k = 0; k < 2; k++) {
		const struct ssc_nav_terms *p = ssc_nav_terms_pick(
			t, n, NULL, k ? SSCOPE_QUANTITY_ACCELERATION : SSCOPE_QUANTITY_ANGULAR_RATE);
		struct sscope_sensor_spec *d = k ? &in->imu.accel : &in->imu.gyro;

		if (!p)
			continue;
		d->q = p->coef[SSCOPE_TERM_Q];
		d->n = p->coef[SSCOPE_TERM_N];
		d->b = p->coef[SSCOPE_TERM_B];
		d->k = p->coef[SSCOPE_TERM_K];
		d->r = p->coef[SSCOPE_TERM_R];
	}
	add_from(in, "noise terms of %s", what);
}

static int apply_allan(const char *cmd, struct imu_in *in, const json_t *root,
		       const char *what)
{
	struct ssc_nav_terms *t;
	size_t n;
	int rc = ssc_nav_terms_from_allan(cmd, root, what, &t, &n);

	if (rc)
		return rc;
	apply_terms(in, t, n, "an allan result");
	free(t);
	return SSC_EXIT_OK;
}

static int apply_calib_res(const char *cmd, struct imu_in *in,
			   const struct ssc_calib_res *c, const char *what)
{
	int found = 0;

	if (ssc_nav_calib_errors_res(c, "gyro", in->imu.gyro_bias_rad_s, in->imu.gyro_m) == 0)
		found++;
	if (ssc_nav_calib_errors_res(c, "accel", in->imu.accel_bias_m_s2, in->imu.accel_m) == 0)
		found++;
	if (!found) {
		ssc_err(cmd, "%s: no triad with an error model in physical units", what);
		return SSC_EXIT_FAIL;
	}
	add_from(in, "biases, scale factors and misalignments of %s",
		 "a calib result");
	return SSC_EXIT_OK;
}

static int apply_calib(const char *cmd, struct imu_in *in, const json_t *root,
		       const char *what)
{
	const char *c = json_string_value(json_object_get(root, "command"));
	struct ssc_calib_res r;
	char w[4096 + 32];

	if (!c || strncmp(c, "calib", 5)) {
		ssc_err(cmd, "--from-calib: %s: not a JSON result of 'calib'", what);
		return SSC_EXIT_FAIL;
	}
	if (ssc_calib_res_from_json(root, &r)) {
		ssc_err(cmd, "--from-calib: %s: a 'calib' result whose triads cannot be read",
			what);
		return SSC_EXIT_FAIL;
	}
	snprintf(w, sizeof(w), "--from-calib: %s", what);
	return apply_calib_res(cmd, in, &r, w);
}

/* --gyro-adc (k 0) or --accel-adc (k 1): a converter for that triad */
static int load_adc(const char *cmd, struct imu_in *in, int k, const char *path)
{
	struct sscope_adc_spec *a = &in->adc[k];
	const struct sscope_sensor_spec *s = k ? &in->imu.accel : &in->imu.gyro;
	const char *opt = k ? "accel-adc" : "gyro-adc";
	struct sscope_diag d = { "" };
	int rc = sscope_adc_spec_load(path, a, &d);

	if (rc)
		return ssc_fail(cmd, rc, &d, path);
	if (a->analog && !((s->has & SSCOPE_SENSOR_HAS_SENSITIVITY) && s->sensitivity > 0))
		return ssc_usage_error(cmd, "--%s: %s has a range in volts but no %s spec gives a sensitivity",
				       opt, path, k ? "accelerometer" : "gyro");
	if (!a->analog && a->quantity != s->quantity)
		return ssc_usage_error(cmd, "--%s: %s converts %s, not %s", opt, path,
				       sscope_quantity_name(a->quantity),
				       sscope_quantity_name(s->quantity));
	if (a->oversample > 1 || a->inl_profile[0])
		return ssc_usage_error(cmd, "--%s: %s: %s is modelled by 'adc report' only",
				       opt, path, a->oversample > 1 ? "oversample" : "inl_profile");
	if (k)
		in->imu.accel_adc = a;
	else
		in->imu.gyro_adc = a;
	add_from(in, "converter %s", path);
	return SSC_EXIT_OK;
}

static int gather(const struct ssc_stage_env *env, const struct opts *o,
		  struct imu_in *in)
{
	const char *cmd = env->co->cmd;
	int rc;

	memset(in, 0, sizeof(*in));
	for (int i = 0; i < o->n_sensor; i++) {
		struct sscope_sensor_spec s;

		rc = ssc_load_sensor(cmd, o->sensor[i], &s);
		if (!rc)
			rc = apply_spec(cmd, in, &s, o->sensor[i]);
		if (rc)
			return rc;
	}
	if (env->sensor) {
		rc = apply_spec(cmd, in, env->sensor,
				env->sensor_path ? env->sensor_path : "[sensor]");
		if (rc)
			return rc;
	}
	{
		/* the scene's allan and calib stages */
		const struct ssc_result *a = ssc_stage_upstream(env, &ssc_allan_stage, NULL);
		const struct ssc_result *c = ssc_stage_upstream(env, &ssc_calib_stage, NULL);

		if (a) {
			struct ssc_nav_terms *t;
			size_t n;

			rc = ssc_nav_terms_from_allan_res(cmd, a->data,
							  "the allan stage", &t, &n);
			if (rc)
				return rc;
			apply_terms(in, t, n, "an allan result");
			free(t);
		}
		if (c && (rc = apply_calib_res(cmd, in, c->data, "the calib stage")))
			return rc;
	}
	if (o->allan) {
		json_t *root;

		rc = ssc_nav_load_json(cmd, "from-allan", o->allan, &root);
		if (!rc)
			rc = apply_allan(cmd, in, root, o->allan);
		json_decref(root);
		if (rc)
			return rc;
	}
	if (o->calib) {
		json_t *root;

		rc = ssc_nav_load_json(cmd, "from-calib", o->calib, &root);
		if (!rc)
			rc = apply_calib(cmd, in, root, o->calib);
		json_decref(root);
		if (rc)
			return rc;
	}
	if (o->set_gbias) {
		memcpy(in->imu.gyro_bias_rad_s, o->gbias, sizeof(o->gbias));
		add_from(in, "%s", "--gyro-bias");
	}
	if (o->set_abias) {
		memcpy(in->imu.accel_bias_m_s2, o->abias, sizeof(o->abias));
		add_from(in, "%s", "--accel-bias");
	}
	if (o->set_arw) {
		in->imu.gyro.n = o->arw;
		add_from(in, "%s", "--arw");
	}
	if (o->set_vrw) {
		in->imu.accel.n = o->vrw;
		add_from(in, "%s", "--vrw");
	}
	in->imu.gyro.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	in->imu.accel.quantity = SSCOPE_QUANTITY_ACCELERATION;
	for (int k = 0; k < 2; k++) {
		rc = o->adc[k] ? load_adc(cmd, in, k, o->adc[k]) : SSC_EXIT_OK;
		if (rc)
			return rc;
	}
	ssc_nav_terms_from_spec(&in->imu.gyro, &in->gyro);
	ssc_nav_terms_from_spec(&in->imu.accel, &in->accel);
	return SSC_EXIT_OK;
}

/* ------------------------------------------------------------ output */

struct result {
	struct opts o;
	struct imu_in in;
	double dur;
	struct sscope_navsim *ns;
	struct sscope_navsim_stat *st;
	size_t n;
	struct sscope_budget_params bp;
	uint64_t clipped;
};

static const char *const comp_key[SSCOPE_NAVSIM_N_COMP] = {
	"north_m", "east_m", "down_m", "v_north_m_s", "v_east_m_s", "v_down_m_s",
	"roll_rad", "pitch_rad", "yaw_rad"
};

static json_t *series(const struct result *r, int which, int c)
{
	json_t *a = json_array();

	for (size_t k = 0; k < r->n; k++) {
		const struct sscope_navsim_stat *s = &r->st[k];
		double v = which == 0 ? s->p05[c] : which == 1 ? s->p50[c] :
			   which == 2 ? s->p95[c] : which == 3 ? s->rms[c] :
			   s->rms_se[c];

		json_array_append_new(a, ssc_jreal(v));
	}
	return a;
}

static json_t *vec_json(const double v[3])
{
	json_t *a = json_array();

	for (int i = 0; i < 3; i++)
		json_array_append_new(a, ssc_jreal(v[i]));
	return a;
}

/* LSB of a triad's converter in the triad's SI unit */
static double adc_lsb(const struct sscope_adc_spec *a,
		      const struct sscope_sensor_spec *s)
{
	return (a->hi - a->lo) / ldexp(1, a->bits) / (a->analog ? s->sensitivity : 1);
}

static json_t *adc_json(const struct sscope_adc_spec *a,
			const struct sscope_sensor_spec *s)
{
	json_t *o;

	if (!a)
		return json_null();
	o = json_object();
	json_object_set_new(o, "name", json_string(a->name));
	json_object_set_new(o, "bits", json_integer(a->bits));
	json_object_set_new(o, "lsb_si", ssc_jreal(adc_lsb(a, s)));
	json_object_set_new(o, "analog", json_boolean(a->analog));
	json_object_set_new(o, "mode", json_string(a->mode == SSCOPE_ADC_INTEGRATE ?
							   "integrate" : "round"));
	return o;
}

static json_t *triad_json(const struct sscope_sensor_spec *s,
			  const struct ssc_nav_terms *t, const double bias[3],
			  const double M[3][3], const struct sscope_adc_spec *adc)
{
	json_t *o = json_object(), *m = json_array();

	json_object_set_new(o, "noise", ssc_nav_terms_json(t));
	json_object_set_new(o, "bias_sd", ssc_jreal(s->bias));
	json_object_set_new(o, "scale_factor_sd", ssc_jreal(s->scale_factor_error));
	json_object_set_new(o, "range", (s->has & SSCOPE_SENSOR_HAS_RANGE) ?
						ssc_jreal(s->range) : json_null());
	json_object_set_new(o, "bias", vec_json(bias));
	for (int i = 0; i < 3; i++)
		json_array_append_new(m, vec_json(M[i]));
	json_object_set_new(o, "error_matrix", m);
	json_object_set_new(o, "adc", adc_json(adc, s));
	return o;
}

static json_t *make_json(const struct opts *o, const struct imu_in *in,
			 const struct result *r, double dur)
{
	json_t *root = json_object(), *t = json_object(), *st = json_object();
	json_t *imu = json_object(), *from = json_array(), *pc = json_object();
	json_t *rms = json_object(), *h = json_object(), *times = json_array();
	json_t *b = json_object(), *bp = json_array(), *bv = json_array(),
	       *ba = json_array();
	static const char *const motion[] = { "static", "straight", "turn", "file" };

	json_object_set_new(root, "command", json_string("navsim"));
	json_object_set_new(t, "kind", json_string(motion[o->motion]));
	if (o->motion == SSCOPE_NAVSIM_STRAIGHT || o->motion == SSCOPE_NAVSIM_TURN)
		json_object_set_new(t, "speed_m_s", json_real(o->speed));
	if (o->motion == SSCOPE_NAVSIM_TURN)
		json_object_set_new(t, "turn_rate_rad_s", json_real(o->turn_rate));
	if (o->traj_file)
		json_object_set_new(t, "file", json_string(o->traj_file));
	json_object_set_new(root, "trajectory", t);
	json_object_set_new(st, "latitude_deg", json_real(o->lat / D2R));
	json_object_set_new(st, "longitude_deg", json_real(o->lon / D2R));
	json_object_set_new(st, "height_m", json_real(o->height));
	json_object_set_new(st, "heading_deg", json_real(o->heading / D2R));
	json_object_set_new(root, "start", st);
	json_object_set_new(root, "rate_hz", json_real(o->rate));
	json_object_set_new(root, "duration_s", json_real(dur));
	json_object_set_new(root, "runs", json_integer((json_int_t)o->runs));
	json_object_set_new(root, "seed", json_integer((json_int_t)o->seed));
	json_object_set_new(root, "vertical", json_string(o->free_vertical ? "free" : "aided"));
	json_object_set_new(root, "mechanisation", json_string(sscope_navsim_mech_name(o->mech)));
	json_object_set_new(imu, "gyro", triad_json(&in->imu.gyro, &in->gyro,
						     in->imu.gyro_bias_rad_s, in->imu.gyro_m,
						     in->imu.gyro_adc));
	json_object_set_new(imu, "accel", triad_json(&in->imu.accel, &in->accel,
						      in->imu.accel_bias_m_s2,
						      in->imu.accel_m, in->imu.accel_adc));
	for (size_t i = 0; i < in->n_from; i++)
		json_array_append_new(from, json_string(in->from[i]));
	json_object_set_new(imu, "sources", from);
	json_object_set_new(root, "imu", imu);
	json_object_set_new(root, "clipped_samples", json_integer((json_int_t)r->clipped));
	for (size_t k = 0; k < r->n; k++)
		json_array_append_new(times, json_real(r->st[k].t_s));
	json_object_set_new(root, "times_s", times);
	{
		static const char *const pn[3] = { "p05", "p50", "p95" };

		for (int w = 0; w < 3; w++) {
			json_t *p = json_object();

			for (int c = 0; c < SSCOPE_NAVSIM_N_COMP; c++)
				json_object_set_new(p, comp_key[c], series(r, w, c));
			json_object_set_new(pc, pn[w], p);
		}
	}
	json_object_set_new(root, "percentiles", pc);
	for (int c = 0; c < SSCOPE_NAVSIM_N_COMP; c++)
		json_object_set_new(rms, comp_key[c], series(r, 3, c));
	json_object_set_new(root, "rms", rms);
	{
		json_t *se = json_object();

		for (int c = 0; c < SSCOPE_NAVSIM_N_COMP; c++)
			json_object_set_new(se, comp_key[c], series(r, 4, c));
		json_object_set_new(root, "rms_se", se);
	}
	{
		json_t *a = json_array(), *p = json_array(), *q = json_array();
		json_t *e = json_array();

		for (size_t k = 0; k < r->n; k++) {
			json_array_append_new(a, ssc_jreal(r->st[k].horiz_p50));
			json_array_append_new(p, ssc_jreal(r->st[k].horiz_p95));
			json_array_append_new(q, ssc_jreal(r->st[k].horiz_rms));
			json_array_append_new(e, ssc_jreal(r->st[k].horiz_rms_se));
		}
		json_object_set_new(h, "p50", a);
		json_object_set_new(h, "p95", p);
		json_object_set_new(h, "rms", q);
		json_object_set_new(h, "rms_se", e);
	}
	json_object_set_new(root, "horizontal_m", h);
	for (size_t k = 0; k < r->n; k++) {
		struct sscope_budget_point pt;

		sscope_budget_total(&r->bp, r->st[k].t_s, &pt);
		json_array_append_new(bp, ssc_jreal(pt.position_m));
		json_array_append_new(bv, ssc_jreal(pt.velocity_m_s));
		json_array_append_new(ba, ssc_jreal(pt.attitude_rad));
	}
	json_object_set_new(b, "model", json_string("schuler"));
	json_object_set_new(b, "meaning",
			    json_string("one horizontal channel, root sum of squares of the sources, 1 sigma for random walks"));
	json_object_set_new(b, "gyro_bias_rad_s", ssc_jreal(r->bp.gyro_bias_rad_s));
	json_object_set_new(b, "accel_bias_m_s2", ssc_jreal(r->bp.accel_bias_m_s2));
	json_object_set_new(b, "arw_rad_sqrt_s", ssc_jreal(r->bp.arw_rad_sqrt_s));
	json_object_set_new(b, "vrw_m_s_sqrt_s", ssc_jreal(r->bp.vrw_m_s_sqrt_s));
	json_object_set_new(b, "position_m", bp);
	json_object_set_new(b, "velocity_m_s", bv);
	json_object_set_new(b, "attitude_rad", ba);
	json_object_set_new(root, "budget", b);
	return root;
}

/* records to show in the text: round times up to the end, and the end */
static size_t checkpoints(const struct result *r, size_t *idx, size_t max)
{
	static const double ts[] = { 10, 30, 60, 120, 300, 600, 1200, 1800,
				     3600, 7200, 14400, 28800, 43200, 86400 };
	double end = r->st[r->n - 1].t_s;
	size_t m = 0;

	for (size_t i = 0; i < sizeof(ts) / sizeof(ts[0]) && m + 1 < max; i++) {
		size_t best = 0;

		if (ts[i] >= end * 0.999)
			break;
		for (size_t k = 0; k < r->n; k++)
			if (fabs(r->st[k].t_s - ts[i]) < fabs(r->st[best].t_s - ts[i]))
				best = k;
		if (best && (!m || idx[m - 1] != best))
			idx[m++] = best;
	}
	idx[m++] = r->n - 1;
	return m;
}

static void write_text(FILE *f, const struct opts *o, const struct imu_in *in,
		       const struct result *r, double dur)
{
	char a[32], b[32], buf[256];
	size_t idx[16], m = checkpoints(r, idx, 16);

	fprintf(f, "%s navigation error: %zu Monte-Carlo run%s (seed %llu), %s s at %s Hz, vertical channel %s\n",
		sscope_navsim_mech_name(o->mech), o->runs, o->runs == 1 ? "" : "s", (unsigned long long)o->seed,
		ssc_fmt(a, sizeof(a), dur, 6), ssc_fmt(b, sizeof(b), o->rate, 6),
		o->free_vertical ? "free" : "aided (perfect altimeter)");
	fprintf(f, "  start latitude %.5f deg, longitude %.5f deg, height %g m, heading %g deg; trajectory %s\n",
		o->lat / D2R, o->lon / D2R, o->height, o->heading / D2R, o->traj_text);
	ssc_nav_terms_text(&in->gyro, buf, sizeof(buf));
	fprintf(f, "  gyro noise:  %s", buf);
	if (in->imu.gyro.bias > 0)
		fprintf(f, "; random bias %s deg/h (1 sigma per run and axis)",
			ssc_fmt(a, sizeof(a), in->imu.gyro.bias / D2R * 3600, 4));
	if (in->imu.gyro.scale_factor_error > 0)
		fprintf(f, "; random scale factor %s ppm",
			ssc_fmt(a, sizeof(a), in->imu.gyro.scale_factor_error * 1e6, 4));
	fputc('\n', f);
	ssc_nav_terms_text(&in->accel, buf, sizeof(buf));
	fprintf(f, "  accel noise: %s", buf);
	if (in->imu.accel.bias > 0)
		fprintf(f, "; random bias %s ug (1 sigma per run and axis)",
			ssc_fmt(a, sizeof(a), in->imu.accel.bias / UG, 4));
	if (in->imu.accel.scale_factor_error > 0)
		fprintf(f, "; random scale factor %s ppm",
			ssc_fmt(a, sizeof(a), in->imu.accel.scale_factor_error * 1e6, 4));
	fputc('\n', f);
	{
		const double *g = in->imu.gyro_bias_rad_s, *c = in->imu.accel_bias_m_s2;

		if (g[0] || g[1] || g[2])
			fprintf(f, "  fixed gyro bias (x, y, z): %g, %g, %g deg/h\n",
				g[0] / D2R * 3600, g[1] / D2R * 3600, g[2] / D2R * 3600);
		if (c[0] || c[1] || c[2])
			fprintf(f, "  fixed accel bias (x, y, z): %g, %g, %g ug\n",
				c[0] / UG, c[1] / UG, c[2] / UG);
	}
	for (int k = 0; k < 2; k++) {
		const struct sscope_adc_spec *ad = k ? in->imu.accel_adc : in->imu.gyro_adc;

		if (ad)
			fprintf(f, "  %s converter %s: %d bits, LSB %s %s (%s)\n",
				k ? "accel" : "gyro", ad->name[0] ? ad->name : "(unnamed)",
				ad->bits,
				ssc_fmt(a, sizeof(a), adc_lsb(ad, k ? &in->imu.accel : &in->imu.gyro) /
						      (k ? UG : D2R / 3600), 4),
				k ? "ug" : "deg/h",
				ad->mode == SSCOPE_ADC_INTEGRATE ? "integrating" : "rounding");
	}
	for (size_t i = 0; i < in->n_from; i++)
		fprintf(f, "  from %s\n", in->from[i]);
	if (!in->n_from)
		fprintf(f, "  perfect IMU: the errors are those of the mechanisation\n");
	if (r->clipped)
		fprintf(f, "  warning: %llu samples clipped to the sensor's or converter's range\n",
			(unsigned long long)r->clipped);
	fprintf(f, "\n  %9s %11s %11s %11s %11s %11s %11s %9s %9s %9s %10s\n", "t (s)",
		"horiz p50", "horiz p95", "north rms", "east rms", "budget 1ch",
		"vel rms", "roll rms", "pitch rms", "yaw rms", "budget att");
	fprintf(f, "  %9s %11s %11s %11s %11s %11s %11s %9s %9s %9s %10s\n", "",
		"(m)", "(m)", "(m)", "(m)", "(m, 1 sd)", "(m/s)", "(deg)", "(deg)", "(deg)",
		"(deg)");
	for (size_t j = 0; j < m; j++) {
		const struct sscope_navsim_stat *s = &r->st[idx[j]];
		struct sscope_budget_point pt;
		char c[11][32];

		sscope_budget_total(&r->bp, s->t_s, &pt);
		fprintf(f, "  %9s %11s %11s %11s %11s %11s %11s %9s %9s %9s %10s\n",
			ssc_fmt(c[0], 32, s->t_s, 6), ssc_fmt(c[1], 32, s->horiz_p50, 4),
			ssc_fmt(c[2], 32, s->horiz_p95, 4),
			ssc_fmt(c[3], 32, s->rms[SSCOPE_NAVSIM_NORTH], 4),
			ssc_fmt(c[4], 32, s->rms[SSCOPE_NAVSIM_EAST], 4),
			ssc_fmt(c[5], 32, pt.position_m, 4),
			ssc_fmt(c[6], 32, hypot(s->rms[SSCOPE_NAVSIM_VN], s->rms[SSCOPE_NAVSIM_VE]), 4),
			ssc_fmt(c[7], 32, s->rms[SSCOPE_NAVSIM_ROLL] / D2R, 3),
			ssc_fmt(c[8], 32, s->rms[SSCOPE_NAVSIM_PITCH] / D2R, 3),
			ssc_fmt(c[9], 32, s->rms[SSCOPE_NAVSIM_YAW] / D2R, 3),
			ssc_fmt(c[10], 32, pt.attitude_rad / D2R, 3));
	}
	fprintf(f, "\n  rms: root mean square over runs; horiz: |(north, east)| error; budget: the drift budget's\n"
		   "  Schuler-bounded single-channel total (biases and random walks, 1 sigma)\n");
	{
		const struct sscope_navsim_stat *e = &r->st[r->n - 1];
		char t1[32], t2[32], t3[32], t4[32];

		if (isfinite(e->horiz_rms_se) && isfinite(e->rms_se[SSCOPE_NAVSIM_YAW]))
			fprintf(f, "  Monte-Carlo standard error at %s s (%zu runs): horizontal rms +-%s m (%s %%), yaw rms +-%s deg\n",
				ssc_fmt(t1, 32, e->t_s, 6), (size_t)r->o.runs,
				ssc_fmt(t2, 32, e->horiz_rms_se, 2),
				ssc_fmt(t3, 32, 100 * e->horiz_rms_se / e->horiz_rms, 2),
				ssc_fmt(t4, 32, e->rms_se[SSCOPE_NAVSIM_YAW] / D2R, 2));
	}
}

static void write_csv(FILE *f, const struct result *r, bool single)
{
	static const int cols[6] = { SSCOPE_NAVSIM_NORTH, SSCOPE_NAVSIM_EAST,
				     SSCOPE_NAVSIM_DOWN, SSCOPE_NAVSIM_ROLL,
				     SSCOPE_NAVSIM_PITCH, SSCOPE_NAVSIM_YAW };

	fprintf(f, "# sensorscope navsim: %s\n", single ? "errors of the single run" :
		"median errors over the runs");
	fprintf(f, "time [s],north [m],east [m],down [m],roll [rad],pitch [rad],yaw [rad]\n");
	for (size_t k = 0; k < r->n; k++) {
		fprintf(f, "%.10g", r->st[k].t_s);
		for (int c = 0; c < 6; c++)
			fprintf(f, ",%.10g", r->st[k].p50[cols[c]]);
		fputc('\n', f);
	}
}

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *path)
{
	const struct result *r = result;
	const struct opts *o = &r->o;
	struct ssc_fig *fig = ssc_fig_new(1100, 1500, 3, 1);
	double *t = malloc(r->n * sizeof(double)), *lo = malloc(r->n * sizeof(double));
	double *hi = malloc(r->n * sizeof(double)), *md = malloc(r->n * sizeof(double));
	double *bl = malloc(r->n * sizeof(double)), *bh = malloc(r->n * sizeof(double));
	bool minutes = r->st[r->n - 1].t_s > 1200;
	int rc = 0;
	char title[256];

	if (!fig || !t || !lo || !hi || !md || !bl || !bh) {
		rc = -ENOMEM;
		goto out;
	}
	snprintf(title, sizeof(title), "%s navigation error: %zu run%s, trajectory %s, %s vertical channel",
		 sscope_navsim_mech_name(o->mech), o->runs, o->runs == 1 ? "" : "s", o->traj_text,
		 o->free_vertical ? "free" : "aided");
	ssc_fig_title(fig, title);
	for (size_t k = 0; k < r->n; k++)
		t[k] = r->st[k].t_s / (minutes ? 60 : 1);
	for (int p = 0; p < 3; p++) {
		struct ssc_ax *ax = ssc_fig_ax(fig, p, 0);
		static const char *const names[9] = { "north", "east", "down", "north",
						      "east", "down", "roll", "pitch",
						      "yaw" };
		double sc = p == 2 ? 1 / D2R : 1;
		int n_comp = p == 2 ? 3 : 2;

		for (int j = 0; j < n_comp; j++) {
			int c = 3 * p + j;
			struct ssc_style st = { .color = ssc_plot_color((size_t)j), .width = 2 };
			char lab[64];

			for (size_t k = 0; k < r->n; k++) {
				lo[k] = r->st[k].p05[c] * sc;
				hi[k] = r->st[k].p95[c] * sc;
				md[k] = r->st[k].p50[c] * sc;
			}
			if (o->runs > 1) {
				snprintf(lab, sizeof(lab), "%s 5-95 %%", names[c]);
				ssc_ax_band(ax, t, lo, hi, r->n, st.color, 0.2, lab);
			}
			snprintf(lab, sizeof(lab), "%s %s", names[c],
				 o->runs > 1 ? "median" : "error");
			ssc_ax_line(ax, t, md, r->n, &st, lab);
		}
		{
			struct ssc_style bs = { .color = 0x111111, .width = 1.5,
						.dash = SSC_DASHED };
			bool any = false;

			for (size_t k = 0; k < r->n; k++) {
				struct sscope_budget_point pt;
				double v;

				sscope_budget_total(&r->bp, r->st[k].t_s, &pt);
				v = (p == 0 ? pt.position_m : p == 1 ? pt.velocity_m_s :
					      pt.attitude_rad) * sc * 1.645;
				bh[k] = v;
				bl[k] = -v;
				any |= v > 0;
			}
			if (any) {
				ssc_ax_line(ax, t, bh, r->n, &bs,
					    "budget, +-1.645 sd (1 channel)");
				ssc_ax_line(ax, t, bl, r->n, &bs, NULL);
			}
		}
		ssc_ax_xlabel(ax, minutes ? "time (min)" : "time (s)");
		ssc_ax_ylabel(ax, p == 0 ? "position error (m)" :
				  p == 1 ? "velocity error (m/s)" : "attitude error (deg)");
		ssc_ax_legend(ax, SSC_LEGEND_UL);
	}
	rc = ssc_fig_save(fig, path);
out:
	ssc_fig_free(fig);
	free(t);
	free(lo);
	free(hi);
	free(md);
	free(bl);
	free(bh);
	(void)opts;
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

static void free_result(void *result)
{
	struct result *r = result;

	free(r->st);
	sscope_navsim_free(r->ns);
	free(r);
}

/* "run 12 of 100" on stderr (only when progress is on) */
static void progress(void *ctx, size_t done, size_t total)
{
	(void)ctx;
	fprintf(stderr, "\rnavsim: Monte-Carlo run %zu of %zu   ", done, total);
	fflush(stderr);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const char *cmd = env->co->cmd;
	struct result *r = calloc(1, sizeof(*r));
	struct opts *o;
	struct ssc_nav_table tb = { 0 };
	struct sscope_navsim_opts no = { 0 };
	struct sscope_diag d = { "" };
	int rc;

	if (!r) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = r;
	r->o = *(struct opts *)opts;
	o = &r->o;
	rc = gather(env, o, &r->in);
	if (rc)
		return rc;
	no.rate_hz = o->rate;
	no.duration_s = o->duration;
	no.output_step_s = o->step;
	no.start.lat_rad = o->lat;
	no.start.lon_rad = o->lon;
	no.start.height_m = o->height;
	no.yaw_rad = o->heading;
	no.motion = o->motion;
	no.speed_m_s = o->speed;
	no.turn_rate_rad_s = o->turn_rate;
	no.free_vertical = o->free_vertical;
	no.mechanisation = o->mech;
	no.threads = o->threads;
	if (ssc_progress_on(env->co))
		no.progress = progress;
	if (o->motion == SSCOPE_NAVSIM_TABLE) {
		rc = ssc_nav_table_load(cmd, o->traj_file, &tb);
		if (rc)
			goto done;
		no.table_t_s = tb.cap->time_s;
		no.table_ned_m = (const double(*)[3])tb.ned;
		no.table_euler_rad = (const double(*)[3])tb.eu;
		no.n_table = tb.cap->n;
		if (!o->set_duration)
			no.duration_s = 0;
	}
	{
		/* memory: perfect increments (48 bytes a sample) unless at
		 * rest, and every run's errors (72 bytes a record) */
		double span = o->motion == SSCOPE_NAVSIM_TABLE ?
				      tb.cap->time_s[tb.cap->n - 1] : o->duration;
		double rec = o->step > 0 ? span / o->step : 600;
		double bytes = (o->motion == SSCOPE_NAVSIM_STATIC ? 0 : 48 * span * o->rate) +
			       72.0 * (double)o->runs * (rec + 1);

		if (bytes > 2147483648.0) {
			ssc_err(cmd, "this simulation needs about %.0f MB (more than 2 GB): lower --rate, --duration or --runs, or raise --output-step",
				bytes / 1e6);
			rc = SSC_EXIT_FAIL;
			goto done;
		}
	}
	rc = sscope_navsim_new(&r->ns, &no, &d);
	if (rc) {
		rc = o->traj_file ? ssc_nav_fail(cmd, rc, &d, o->traj_file) :
				    ssc_fail(cmd, rc, &d, "navsim");
		goto done;
	}
	r->n = sscope_navsim_n_out(r->ns);
	r->dur = sscope_navsim_time(r->ns, r->n - 1);
	if (o->set_duration && r->dur < o->duration - 2 / o->rate)
		ssc_warn(env->co, "%s spans %g s: simulating that, not --duration %g s",
			 o->traj_file ? o->traj_file : "the trajectory", r->dur,
			 o->duration);
	r->st = calloc(r->n, sizeof(*r->st));
	if (!r->st) {
		ssc_err(cmd, "out of memory");
		rc = SSC_EXIT_FAIL;
		goto done;
	}
	rc = sscope_navsim_monte_carlo(r->ns, &r->in.imu, o->runs, o->seed, r->st,
				       NULL, &r->clipped, &d);
	if (no.progress)
		ssc_progress_end(env->co);
	if (rc) {
		rc = ssc_fail(cmd, rc, &d, "Monte Carlo");
		goto done;
	}
	sscope_navsim_budget(r->ns, &r->in.imu, &r->bp);
	rc = o->mech_plot ? ssc_navsim_mech_plot(cmd, r->ns, &r->in.imu, o->runs, o->seed,
						 r->st, o->mech, o->traj_text, o->mech_plot) : SSC_EXIT_OK;
done:
	ssc_nav_table_free(&tb);
	return rc;
}

static json_t *json(const void *opts, const void *result)
{
	const struct result *r = result;

	(void)opts;
	return make_json(&r->o, &r->in, r, r->dur);
}

static void text(FILE *f, const void *opts, const void *result)
{
	const struct result *r = result;

	(void)opts;
	write_text(f, &r->o, &r->in, r, r->dur);
}

static void csv(FILE *f, const void *opts, const void *result)
{
	const struct result *r = result;

	(void)opts;
	write_csv(f, r, r->o.runs == 1);
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct result *r = result;
	const struct sscope_navsim_stat *s = &r->st[r->n - 1];
	char q[96], a[32];

	(void)opts;
	ssc_fmt(a, sizeof(a), s->t_s, 5);
	snprintf(q, sizeof(q), "horizontal position error after %s s, median", a);
	ssc_summary_add(rows, NULL, q, s->horiz_p50, NAN, NAN, "m",
			"navsim Monte Carlo");
	snprintf(q, sizeof(q), "horizontal position error after %s s, 95 %%", a);
	ssc_summary_add(rows, NULL, q, s->horiz_p95, NAN, NAN, "m",
			"navsim Monte Carlo");
	snprintf(q, sizeof(q), "heading error after %s s, rms", a);
	ssc_summary_add(rows, NULL, q, s->rms[SSCOPE_NAVSIM_YAW] / D2R, NAN,
			NAN, "deg", "navsim Monte Carlo");
}

const struct ssc_stage_ops ssc_navsim_stage = {
	.spec = &spec,
	.title = "Navigation error simulation",
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

int ssc_cmd_navsim(int argc, char **argv)
{
	return ssc_stage_main(&ssc_navsim_stage, argc, argv);
}
