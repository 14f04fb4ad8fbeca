/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope calib accel|gyro: error-model calibration of a triad
 * (textbook eqs 93-94) by the multi-position method of Tedaldi, Pretto and
 * Menegatti (ICRA 2014), the six-position test, rate-table / centrifuge
 * runs against a reference column, and static tilt poses for the
 * g-dependent gyro bias; writes a calibration file for --calibration.
 */
#include "cli.h"
#include "results.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "plot.h"

#define MAX_IV 4096

enum mode { M_MULTIPOS = 0, M_SIXPOS, M_RATE_TABLE, M_TILT };
static const char *const mode_names[] = { "multipos", "sixpos", "rate-table",
					  "tilt" };

enum {
	O_MODE = 300,
	O_GRAVITY,
	O_WINDOW,
	O_MIN_STATIC,
	O_INIT_STATIC,
	O_THRESHOLD,
	O_ACCEL,
	O_GYRO,
	O_REFERENCE,
	O_TABLE_AXIS,
	O_SETTLE,
	O_CUBIC,
	O_GSENS,
	O_SAVE,
	O_SCHEDULE,
	O_TRIAD,
};

static const struct ssc_option calib_opts[] = {
	{ "triad", required_argument, O_TRIAD, "accel|gyro",
	  "the triad to calibrate (on the command line: the word after 'calib'; in a scene: this key)" },
	{ "mode", required_argument, O_MODE, "multipos|sixpos|rate-table|tilt",
	  "method (default multipos; tilt is gyro only)" },
	{ "gravity", required_argument, O_GRAVITY, "G",
	  "local gravity (default 9.80665 m/s^2; units allowed, e.g. 9.8094 m/s^2)" },
	{ "window", required_argument, O_WINDOW, "S",
	  "static detector: variance window (default 1 s)" },
	{ "min-static", required_argument, O_MIN_STATIC, "S",
	  "static detector: shortest static interval (default 2 s)" },
	{ "init-static", required_argument, O_INIT_STATIC, "S",
	  "static detector: reference noise from the first S seconds (default: 10th percentile rule)" },
	{ "threshold", required_argument, O_THRESHOLD, "K|auto",
	  "static detector: threshold = K x reference (default auto: best K in 2..10)" },
	{ "accel", required_argument, O_ACCEL, "X,Y,Z",
	  "accelerometer channels (default: the first three in m/s^2 or g)" },
	{ "gyro", required_argument, O_GYRO, "X,Y,Z",
	  "gyro channels (default: the first three angular-rate channels)" },
	{ "reference", required_argument, O_REFERENCE, "NAME[,NAME,NAME]",
	  "rate-table mode: commanded rate (or specific force) column(s)" },
	{ "schedule", required_argument, O_SCHEDULE, "FILE",
	  "rate-table mode without a reference column: lines 'START END RATE' (e.g. 10 15 50deg/s)" },
	{ "table-axis", required_argument, O_TABLE_AXIS, "x|y|z|auto[,...]",
	  "rate-table mode, one reference column: sensor axis on the table, per file (default auto)" },
	{ "settle", required_argument, O_SETTLE, "S",
	  "rate-table mode: samples dropped after each step (default 1 s)" },
	{ "cubic", no_argument, O_CUBIC, NULL,
	  "rate-table mode: fit quadratic and cubic scale-factor terms too" },
	{ "g-sensitivity", no_argument, O_GSENS, NULL,
	  "calib gyro multipos: estimate the g-dependent bias matrix too" },
	{ "save-calibration", required_argument, O_SAVE, "PATH",
	  "write the calibration file (JSON) for --calibration" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "calib",
	.usage = "calib accel|gyro [OPTIONS] FILE...",
	.summary =
		"Error-model calibration of an accelerometer or gyro triad: bias, scale\n"
		"factors and misalignment with 1-sigma uncertainties.  multipos (default):\n"
		"multi-position calibration without external equipment (Tedaldi, Pretto,\n"
		"Menegatti, ICRA 2014): hold the sensor still in 10 or more orientations\n"
		"(rotating between them for 'calib gyro'); static intervals are found\n"
		"automatically and the accelerometer is fitted to |g|, the gyro to the\n"
		"rotation of gravity between poses.  sixpos: +-g on each axis (12\n"
		"parameters).  rate-table: steps of a commanded rate (or centrifuge\n"
		"specific force) in a reference column: scale factor, its non-linearity\n"
		"(best-fit straight line, % of full scale), cross-axis terms, bias.\n"
		"tilt: static poses, gyro bias against gravity (g-dependent bias).\n"
		"The sensor is classed against typical technology ranges.",
	.options = calib_opts,
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope calib accel samples/imu-multipose.csv\n"
		 "  sensorscope calib gyro --save-calibration imu-cal.json samples/imu-multipose.csv\n"
		 "  sensorscope info --calibration imu-cal.json samples/imu-multipose.csv\n"
		 "  sensorscope calib accel --mode sixpos samples/accel-6pos.csv\n"
		 "  sensorscope calib gyro --mode rate-table --reference rate_cmd --cubic samples/gyro-ratetable.csv\n"
		 "Model: corrected = T K (reading - bias - G a'); bias in input units,\n"
		 "scale in output SI units per input unit, T with a unit diagonal.",
};

struct opts {
	bool gyro;
	enum mode mode;
	double gravity;
	struct sscope_calib_detect det;
	const char *accel, *gyro_names, *reference, *table_axis, *save;
	const char *schedule;
	double settle_s;
	bool cubic, gsens, settle_set;
	bool triad_set;
};

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;

	switch (key) {
	case O_TRIAD:
		if (strcmp(arg, "accel") && strcmp(arg, "gyro"))
			return ssc_usage_error("calib", "--triad: '%s' is not accel or gyro",
					       arg);
		o->gyro = !strcmp(arg, "gyro");
		o->triad_set = true;
		return 0;
	case O_MODE:
		for (int m = 0; m < 4; m++)
			if (!strcmp(arg, mode_names[m])) {
				o->mode = (enum mode)m;
				return 0;
			}
		return ssc_usage_error("calib", "--mode: '%s' is not multipos, sixpos, rate-table or tilt",
				       arg);
	case O_GRAVITY:
		return ssc_arg_gravity("calib", arg, &o->gravity);
	case O_WINDOW:
	case O_MIN_STATIC:
	case O_INIT_STATIC:
	case O_SETTLE: {
		double v;
		const char *nm = key == O_WINDOW ? "window" :
				 key == O_MIN_STATIC ? "min-static" :
				 key == O_INIT_STATIC ? "init-static" : "settle";

		if (ssc_arg_quantity("calib", nm, arg, "s", &v))
			return SSC_EXIT_USAGE;
		if (!(v > 0) && !(key == O_SETTLE && v == 0))
			return ssc_usage_error("calib", "--%s: must be positive", nm);
		if (key == O_WINDOW)
			o->det.window_s = v;
		else if (key == O_MIN_STATIC)
			o->det.min_static_s = v;
		else if (key == O_INIT_STATIC)
			o->det.init_static_s = v;
		else
			o->settle_s = v;
		o->settle_set |= key == O_SETTLE;
		return 0;
	}
	case O_THRESHOLD:
		if (!strcmp(arg, "auto")) {
			o->det.k = 0;
			return 0;
		}
		if (ssc_arg_double("calib", "threshold", arg, &o->det.k))
			return SSC_EXIT_USAGE;
		if (!(o->det.k > 1))
			return ssc_usage_error("calib", "--threshold: K must exceed 1");
		return 0;
	case O_ACCEL:
		o->accel = arg;
		return 0;
	case O_GYRO:
		o->gyro_names = arg;
		return 0;
	case O_REFERENCE:
		o->reference = arg;
		return 0;
	case O_TABLE_AXIS:
		o->table_axis = arg;
		return 0;
	case O_CUBIC:
		o->cubic = true;
		return 0;
	case O_GSENS:
		o->gsens = true;
		return 0;
	case O_SAVE:
		o->save = arg;
		return 0;
	case O_SCHEDULE:
		o->schedule = arg;
		return 0;
	default:
		return ssc_usage_error("calib", "unexpected option");
	}
}

/* ------------------------------------------------------------------ */

/* item i (0-based) of a comma list into buf; false when absent */
static bool list_item(const char *list, int i, char *buf, size_t len)
{
	const char *p = list;

	for (int k = 0; k < i; k++) {
		p = strchr(p, ',');
		if (!p)
			return false;
		p++;
	}
	size_t n = strcspn(p, ",");

	if (n == 0 || n >= len)
		return false;
	memcpy(buf, p, n);
	buf[n] = 0;
	return true;
}

static size_t list_count(const char *list)
{
	size_t n = 1;

	for (; *list; list++)
		n += *list == ',';
	return n;
}

static bool in_list(const char *list, const char *name)
{
	char b[128];

	if (!list)
		return false;
	for (int i = 0; list_item(list, i, b, sizeof(b)); i++)
		if (!strcmp(b, name))
			return true;
	return false;
}

/* three channels by name, or the first three of quantity q */
static int pick3(const struct ssc_common *co, const struct sscope_capture *cap,
		 const char *names, enum sscope_quantity q, const char *excl,
		 const char *opt, long idx[3])
{
	if (names) {
		char b[128];

		if (list_count(names) != 3)
			return ssc_usage_error(co->cmd, "--%s: give three channel names",
					       opt);
		for (int i = 0; i < 3; i++) {
			list_item(names, i, b, sizeof(b));
			idx[i] = sscope_capture_find(cap, b);
			if (idx[i] < 0) {
				ssc_err(co->cmd, "%s: --%s: no channel '%s'",
					cap->source, opt, b);
				return SSC_EXIT_FAIL;
			}
		}
		return SSC_EXIT_OK;
	}
	int k = 0;

	for (size_t c = 0; c < cap->n_channels && k < 3; c++)
		if (cap->channels[c].col.quantity == q &&
		    !in_list(excl, cap->channels[c].col.name))
			idx[k++] = (long)c;
	if (k < 3) {
		ssc_err(co->cmd, "%s: fewer than three %s channels (name them with --%s X,Y,Z)",
			cap->source, sscope_quantity_name(q), opt);
		return SSC_EXIT_FAIL;
	}
	return SSC_EXIT_OK;
}

/* the unit of the raw channel ("" for raw values without a unit) */
static void held_unit(const struct sscope_capture_column *col, char *out, size_t len)
{
	snprintf(out, len, "%s", col->unit_label);
}

/* ------------------------------------------------------------------ */
/* Results                                                             */
/* ------------------------------------------------------------------ */

static void triad_text(FILE *f, const struct ssc_calib_triad_out *o)
{
	const struct sscope_calib_triad *c = &o->t.c;
	double s = ssc_calfile_unit_scale(o->t.input_unit);
	const char *iu = o->t.input_unit[0] ? o->t.input_unit : "counts";
	char a[32], b[32];
	size_t ng;
	const struct sscope_calib_class *gr = sscope_calib_grades(&ng);

	fprintf(f, "  %s triad %s,%s,%s  (%s -> %s)\n", o->t.kind,
		o->t.channels[0], o->t.channels[1], o->t.channels[2], iu,
		o->t.output_unit);
	fprintf(f, "    poses %zu, parameters %u, residual rms %s %s",
		c->poses, c->n_params, ssc_fmt(a, sizeof(a), c->residual_rms, 4),
		strcmp(o->residual_unit, "1") ? o->residual_unit :
						"(unit-vector difference)");
	if (c->iterations)
		fprintf(f, ", %u LM iterations", c->iterations);
	fprintf(f, ", condition %s\n", ssc_fmt(a, sizeof(a), c->cond, 3));
	if (o->n_motion)
		fprintf(f, "    over its %zu motions the calibrated gyro carries gravity to within %s deg rms (max %s deg) of the next pose; %s deg rms with the bias removed only\n",
			o->n_motion, ssc_fmt(a, sizeof(a), o->motion_rms * 180 / PI, 3),
			ssc_fmt(b, sizeof(b), o->motion_max * 180 / PI, 3),
			ssc_fmt((char[32]){ 0 }, 32, o->motion_rms_bias_only * 180 / PI, 3));
	fprintf(f, "    %-6s %16s %16s   %s\n", "axis", "bias", "scale",
		"misalignment row (T)");
	for (int i = 0; i < 3; i++) {
		fprintf(f, "    %-6s %9s±%-6s ", o->t.channels[i],
			ssc_fmt(a, sizeof(a), c->bias[i] / s, 5),
			ssc_fmt(b, sizeof(b), c->bias_sd[i] / s, 2));
		if (isfinite(c->scale_sd[i]))
			fprintf(f, "%9s±%-6s ", ssc_fmt(a, sizeof(a), c->scale[i] * s, 6),
				ssc_fmt(b, sizeof(b), c->scale_sd[i] * s, 2));
		else
			fprintf(f, "%9s (fixed) ", ssc_fmt(a, sizeof(a), c->scale[i] * s, 6));
		for (int j = 0; j < 3; j++)
			fprintf(f, " %10s", ssc_fmt(a, sizeof(a), c->mis[i][j], 4));
		fputc('\n', f);
	}
	fprintf(f, "    (bias in %s, scale in %s per %s, uncertainties 1 sigma)\n",
		iu, o->t.output_unit, iu);
	if (c->has_gsens) {
		fprintf(f, "    g-sensitivity G (%s per m/s^2):\n", iu);
		for (int i = 0; i < 3; i++)
			fprintf(f, "      %12s %12s %12s\n",
				ssc_fmt(a, sizeof(a), c->gsens[i][0] / s, 4),
				ssc_fmt(b, sizeof(b), c->gsens[i][1] / s, 4),
				ssc_fmt((char[32]){ 0 }, 32, c->gsens[i][2] / s, 4));
	}
	if (o->error_model) {
		const char *bu = sscope_term_unit(o->q, SSCOPE_TERM_B);
		const char *si = sscope_quantity_si_unit(o->q);

		double bmax = 0;

		for (int i = 0; i < 3; i++)
			bmax = fmax(bmax, fabs(c->bias[i]));
		if (o->q == SSCOPE_QUANTITY_ACCELERATION && bmax >= 1e-3 * SSCOPE_UNIT_GRAVITY_STD)
			bu = "mg";
		fprintf(f, "    error model (textbook eqs 93-94), per axis: ");
		for (int i = 0; i < 3; i++) {
			double v = c->bias[i];

			sscope_unit_convert_text(c->bias[i], si, bu, &v);
			fprintf(f, "%sbias %s %s", i ? "; " : "",
				ssc_fmt(a, sizeof(a), v, 4), bu);
			if (isfinite(c->scale_sd[i]))
				fprintf(f, ", scale-factor error %s ppm",
					ssc_fmt(b, sizeof(b), (o->A[i][i] - 1) * 1e6, 4));
		}
		fputc('\n', f);
	}
	if (isfinite(o->noise_density)) {
		double v = o->noise_density;
		const char *nu = sscope_term_unit(o->q, SSCOPE_TERM_N);

		sscope_unit_convert_text(o->noise_density,
					 sscope_term_si_unit(o->q, SSCOPE_TERM_N), nu, &v);
		fprintf(f, "    noise density (static intervals): %s %s\n",
			ssc_fmt(a, sizeof(a), v, 3), nu);
	}
	if (o->grade >= 0 && o->grade_dist > 0)
		fprintf(f, "    grade: closest to %s (%.2g decades outside its typical ranges)\n",
			gr[o->grade].name, o->grade_dist);
	else if (o->grade >= 0)
		fprintf(f, "    grade: %s (within its typical ranges)\n", gr[o->grade].name);
}

/* ------------------------------------------------------------------ */
/* Modes                                                               */
/* ------------------------------------------------------------------ */

struct run {
	struct ssc_calib_res pub; /* the triads (first: results.h) */
	const struct ssc_common *co; /* during run() only */
	struct opts o;          /* the options, with the detector's outputs */
	const char *const *paths;
	size_t n_files;
	struct sscope_capture *cap;
	long ai[3], gi[3];
	struct sscope_calib_interval *iv;
	size_t n_iv;
	double *vs;             /* variance magnitude, for the plot */
	/* pose norms before/after (plot) */
	double *pose_before, *pose_after;
	size_t n_pose;
	/* gyro: error of each motion with the bias removed only / calibrated,
	 * rad (plot) */
	double *mot_before, *mot_after;
	size_t n_mot;
	/* rate table */
	struct sscope_calib_linear lf;
	double (*ry)[3], (*rr)[3];
	size_t n_pts;
	bool have_lf;
};

static void fill_triad(struct ssc_calib_triad_out *t, const char *kind,
		       const struct sscope_capture *cap, const long idx[3],
		       enum sscope_quantity q, const struct sscope_calib_triad *c)
{
	memset(t, 0, sizeof(*t));
	snprintf(t->t.kind, sizeof(t->t.kind), "%s", kind);
	for (int i = 0; i < 3; i++)
		snprintf(t->t.channels[i], sizeof(t->t.channels[i]), "%s",
			 cap->channels[idx[i]].col.name);
	held_unit(&cap->channels[idx[0]].col, t->t.input_unit,
		  sizeof(t->t.input_unit));
	snprintf(t->t.output_unit, sizeof(t->t.output_unit), "%s",
		 sscope_quantity_si_unit(q));
	t->t.c = *c;
	t->q = q;
	t->noise_density = NAN;
}

/* the three channels idx of the capture */
static const double *const *chans(const struct run *r, const long idx[3],
				  const double *ch[3])
{
	for (int i = 0; i < 3; i++)
		ch[i] = r->cap->channels[idx[i]].data;
	return ch;
}

/* the output's noise density from the static poses */
static void noise_density(const struct run *r, const long idx[3],
			  struct ssc_calib_triad_out *o)
{
	const double *ch[3];

	sscope_calib_noise_density(chans(r, idx, ch), 1, r->iv, r->n_iv,
				   o->t.c.scale, r->cap->rate_hz,
				   &o->noise_density);
}

static int accel_multipos(struct run *r)
{
	const struct ssc_common *co = r->co;
	struct sscope_capture *cap = r->cap;
	struct sscope_diag d = { "" };
	struct sscope_calib_triad c;
	const double *ch[3];
	double *w2 = malloc(cap->n * sizeof(double));
	const double *x = cap->channels[r->ai[0]].data,
		     *y = cap->channels[r->ai[1]].data,
		     *z = cap->channels[r->ai[2]].data;
	int rc;

	r->vs = malloc(cap->n * sizeof(double));
	if (!w2 || !r->vs) {
		free(w2);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	rc = sscope_calib_accel_multipos(x, y, z, 1, cap->n, cap->rate_hz,
					 r->o.gravity, &r->o.det, r->iv, MAX_IV,
					 &c, r->vs, w2, &d);
	free(w2);
	if (rc) {
		/* six poses are most often the six-position test */
		ssc_err(co->cmd, "%s: accelerometer calibration: %s%s", cap->source,
			d.msg[0] ? d.msg : sscope_strerror(rc),
			rc == -EDOM && r->o.det.n_intervals == 6 ?
				"; six poses of +-g on each axis are the six-position test: --mode sixpos" :
				"");
		return SSC_EXIT_FAIL;
	}
	r->n_iv = r->o.det.n_intervals;
	fill_triad(&r->pub.out[r->pub.n_out], "accel", cap, r->ai,
		   SSCOPE_QUANTITY_ACCELERATION, &c);
	r->pub.out[r->pub.n_out].residual_unit = "m/s^2";
	noise_density(r, r->ai, &r->pub.out[r->pub.n_out]);
	/* pose norms for the plot */
	r->pose_before = malloc((r->n_iv ? r->n_iv : 1) * sizeof(double));
	r->pose_after = malloc((r->n_iv ? r->n_iv : 1) * sizeof(double));
	if (r->pose_before && r->pose_after &&
	    sscope_calib_pose_errors(chans(r, r->ai, ch), 1, r->iv, r->n_iv, &c,
				     r->o.gravity,
				     cap->channels[r->ai[0]].col.quantity ==
					     SSCOPE_QUANTITY_ACCELERATION,
				     r->pose_before, r->pose_after) == 0)
		r->n_pose = r->n_iv;
	ssc_calib_triad_finish(&r->pub.out[r->pub.n_out]);
	r->pub.n_out++;
	return SSC_EXIT_OK;
}

/* How the gyro predicts each motion between poses, calibrated and with
 * its bias removed only; kept for the text, JSON and figure. */
static void motion_errors(struct run *r, double *const ac[3],
			  const struct sscope_calib_triad *c)
{
	const double *g[3], *a[3] = { ac[0], ac[1], ac[2] };
	struct ssc_calib_triad_out *o = &r->pub.out[1];
	struct sscope_calib_motion ms;
	size_t m = r->n_iv ? r->n_iv - 1 : 0;

	o->n_motion = 0;
	r->mot_before = malloc((m ? m : 1) * sizeof(double));
	r->mot_after = malloc((m ? m : 1) * sizeof(double));
	if (!r->mot_before || !r->mot_after ||
	    sscope_calib_motion_summary(chans(r, r->gi, g), a, 1, r->cap->n,
					r->cap->rate_hz, r->iv, r->n_iv, c,
					r->cap->channels[r->gi[0]].col.quantity ==
						SSCOPE_QUANTITY_ANGULAR_RATE,
					r->mot_after, r->mot_before, &ms))
		return;
	o->motion_rms = ms.rms_rad;
	o->motion_rms_bias_only = ms.rms_bias_only_rad;
	o->motion_max = ms.max_rad;
	r->n_mot = ms.motions;
	o->n_motion = ms.motions;
}

static int gyro_multipos(struct run *r)
{
	const struct ssc_common *co = r->co;
	struct sscope_capture *cap = r->cap;
	struct sscope_diag d = { "" };
	struct sscope_calib_triad c;
	double *ac[3] = { NULL, NULL, NULL };
	int rc = accel_multipos(r);

	if (rc)
		return rc;
	for (int i = 0; i < 3; i++) {
		ac[i] = malloc(cap->n * sizeof(double));
		if (!ac[i]) {
			rc = SSC_EXIT_FAIL;
			ssc_err(co->cmd, "out of memory");
			goto out;
		}
		memcpy(ac[i], cap->channels[r->ai[i]].data, cap->n * sizeof(double));
	}
	sscope_calib_apply(&r->pub.out[0].t.c, ac[0], ac[1], ac[2], 1, cap->n, NULL, 1);
	{
		const double *g[3] = { cap->channels[r->gi[0]].data,
				       cap->channels[r->gi[1]].data,
				       cap->channels[r->gi[2]].data };
		const double *a[3] = { ac[0], ac[1], ac[2] };
		bool si = cap->channels[r->gi[0]].col.quantity ==
			  SSCOPE_QUANTITY_ANGULAR_RATE;

		rc = sscope_calib_gyro_fit(g, a, 1, cap->n, cap->rate_hz,
					   si ? 1 : 0, r->iv, r->n_iv, r->o.gsens,
					   &c, &d);
	}
	if (rc) {
		ssc_err(co->cmd, "%s: gyro calibration: %s", cap->source,
			d.msg[0] ? d.msg : sscope_strerror(rc));
		rc = SSC_EXIT_FAIL;
		goto out;
	}
	fill_triad(&r->pub.out[1], "gyro", cap, r->gi, SSCOPE_QUANTITY_ANGULAR_RATE, &c);
	r->pub.out[1].residual_unit = "1";
	motion_errors(r, ac, &c);
	if (c.has_gsens)
		for (int i = 0; i < 3; i++)
			snprintf(r->pub.out[1].t.accel_channels[i], 64, "%s",
				 r->pub.out[0].t.channels[i]);
	noise_density(r, r->gi, &r->pub.out[1]);
	ssc_calib_triad_finish(&r->pub.out[1]);
	r->pub.n_out = 2;
	rc = SSC_EXIT_OK;
out:
	for (int i = 0; i < 3; i++)
		free(ac[i]);
	return rc;
}

static int accel_sixpos(struct run *r)
{
	const struct ssc_common *co = r->co;
	struct sscope_capture *cap = r->cap;
	struct sscope_calib_triad c;
	struct sscope_diag d = { "" };
	const double *ch[3];
	double *w2 = malloc(cap->n * sizeof(double));
	int rc;

	r->vs = malloc(cap->n * sizeof(double));
	if (!w2 || !r->vs) {
		free(w2);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	chans(r, r->ai, ch);
	rc = sscope_calib_accel_sixpos_run(ch[0], ch[1], ch[2], 1, cap->n,
					   cap->rate_hz, r->o.gravity, &r->o.det,
					   r->iv, MAX_IV, &r->lf, &c, r->vs, w2, &d);
	free(w2);
	if (rc) {
		/* the library's words name the six-position test */
		ssc_err(co->cmd, "%s: %s%s", cap->source,
			d.msg[0] ? "" : "six-position test: ",
			d.msg[0] ? d.msg : sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	r->n_iv = r->o.det.n_intervals;
	fill_triad(&r->pub.out[0], "accel", cap, r->ai, SSCOPE_QUANTITY_ACCELERATION,
		   &c);
	r->pub.out[0].residual_unit = r->pub.out[0].t.input_unit[0] ?
					      r->pub.out[0].t.input_unit : "counts";
	/* residual_rms of a linear fit is in held units: show input units */
	r->pub.out[0].t.c.residual_rms /= ssc_calfile_unit_scale(r->pub.out[0].t.input_unit);
	noise_density(r, r->ai, &r->pub.out[0]);
	ssc_calib_triad_finish(&r->pub.out[0]);
	r->pub.n_out = 1;
	return SSC_EXIT_OK;
}

static int gyro_tilt(struct run *r)
{
	const struct ssc_common *co = r->co;
	struct sscope_capture *cap = r->cap;
	struct sscope_calib_triad c;
	struct sscope_diag d = { "" };
	const double *g[3], *a[3];
	double *w2;
	int rc;

	if (cap->channels[r->ai[0]].col.quantity != SSCOPE_QUANTITY_ACCELERATION) {
		ssc_err(co->cmd, "%s: tilt mode needs accelerometer channels in physical units (or --calibration)",
			cap->source);
		return SSC_EXIT_FAIL;
	}
	if (cap->channels[r->gi[0]].col.quantity != SSCOPE_QUANTITY_ANGULAR_RATE) {
		ssc_err(co->cmd, "%s: tilt mode needs gyro channels in physical units (the scale is not estimated)",
			cap->source);
		return SSC_EXIT_FAIL;
	}
	w2 = malloc(cap->n * sizeof(double));
	r->vs = malloc(cap->n * sizeof(double));
	if (!w2 || !r->vs) {
		free(w2);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	rc = sscope_calib_gyro_gsens_run(chans(r, r->gi, g), chans(r, r->ai, a), 1,
					 cap->n, cap->rate_hz, &r->o.det, r->iv,
					 MAX_IV, &c, r->vs, w2, &d);
	free(w2);
	if (rc) {
		ssc_err(co->cmd, "%s: g-sensitivity: %s", cap->source,
			d.msg[0] ? d.msg : sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	r->n_iv = r->o.det.n_intervals;
	fill_triad(&r->pub.out[0], "gyro", cap, r->gi, SSCOPE_QUANTITY_ANGULAR_RATE, &c);
	r->pub.out[0].t.c.residual_rms /= ssc_calfile_unit_scale(r->pub.out[0].t.input_unit);
	r->pub.out[0].residual_unit = r->pub.out[0].t.input_unit;
	for (int i = 0; i < 3; i++)
		snprintf(r->pub.out[0].t.accel_channels[i], 64, "%s",
			 cap->channels[r->ai[i]].col.name);
	ssc_calib_triad_finish(&r->pub.out[0]);
	r->pub.n_out = 1;
	return SSC_EXIT_OK;
}

/* the table axis of file file_no from --table-axis: 0..2, -1 for auto,
 * -2 for a bad value */
static int table_axis(const struct opts *o, int file_no)
{
	char ax[16] = "auto";

	if (o->table_axis && !list_item(o->table_axis, file_no, ax, sizeof(ax)) &&
	    list_count(o->table_axis) == 1)
		list_item(o->table_axis, 0, ax, sizeof(ax));
	return !strcmp(ax, "x") ? 0 : !strcmp(ax, "y") ? 1 :
	       !strcmp(ax, "z") ? 2 : !strcmp(ax, "auto") ? -1 : -2;
}

/* one rate-table file: its steps' means appended to r->ry, r->rr */
static int rate_table_file(struct run *r, int file_no)
{
	const struct ssc_common *co = r->co;
	struct sscope_capture *cap = r->cap;
	size_t nref = r->o.reference ? list_count(r->o.reference) : 1, nseg = 0;
	const long *ci = r->o.gyro ? r->gi : r->ai;
	const double *ref[3] = { NULL, NULL, NULL }, *y[3];
	double *sched_ref = NULL, (*ny)[3], (*nr)[3];
	size_t base = r->n_pts;
	char b[128];
	int axis = -1, e;

	if (nref == 1) {
		axis = table_axis(&r->o, file_no);
		if (axis == -2)
			return ssc_usage_error(co->cmd, "--table-axis: '%s' is not x, y, z or auto",
					       r->o.table_axis);
	}
	if (r->o.schedule) {
		double *sv;
		size_t ns;

		e = ssc_read_intervals(co, "schedule", r->o.schedule, "VALUE", 1,
				       sscope_quantity_si_unit(r->o.gyro ?
								       SSCOPE_QUANTITY_ANGULAR_RATE :
								       SSCOPE_QUANTITY_ACCELERATION),
				       NULL, &sv, &ns);
		if (e)
			return e;
		nref = 1;
		sched_ref = malloc(cap->n * sizeof(double));
		if (!sched_ref) {
			free(sv);
			return SSC_EXIT_FAIL;
		}
		sscope_timing_intervals_sample(cap->time_s, cap->rate_hz, cap->n, sv, ns, 1,
					       &sched_ref);
		free(sv);
		ref[0] = sched_ref;
	} else {
		if (nref != 1 && nref != 3)
			return ssc_usage_error(co->cmd, "--reference: one or three columns");
		for (size_t j = 0; j < nref; j++) {
			long k;

			list_item(r->o.reference, (int)j, b, sizeof(b));
			k = sscope_capture_find(cap, b);
			if (k < 0) {
				ssc_err(co->cmd, "%s: --reference: no column '%s'", cap->source, b);
				return SSC_EXIT_FAIL;
			}
			ref[j] = cap->channels[k].data;
		}
	}
	ny = realloc(r->ry, (base + MAX_IV) * sizeof(*ny));
	if (ny)
		r->ry = ny;
	nr = ny ? realloc(r->rr, (base + MAX_IV) * sizeof(*nr)) : NULL;
	if (nr)
		r->rr = nr;
	e = nr ? sscope_calib_rate_table_steps(chans(r, ci, y), ref, nref, 1,
					       cap->n, cap->rate_hz,
					       r->o.settle_s >= 0 ? r->o.settle_s : 1,
					       r->iv, MAX_IV, r->ry + base,
					       r->rr + base, &nseg) :
		 -ENOMEM;
	free(sched_ref);
	if (e == -EDOM) {
		ssc_err(co->cmd, "%s: %zu steps of constant reference found (need 2 or more)",
			cap->source, nseg);
		return SSC_EXIT_FAIL;
	}
	if (e) {
		ssc_err(co->cmd, "%s: rate table: %s", cap->source, sscope_strerror(e));
		return SSC_EXIT_FAIL;
	}
	if (nref == 1) {
		/* the reference drives the table axis: given, or the sensor
		 * axis with the largest |slope| */
		if (axis < 0)
			axis = sscope_calib_table_axis((const double(*)[3])(r->ry + base),
						       (const double(*)[3])(r->rr + base),
						       nseg);
		for (size_t k = 0; k < nseg; k++) {
			double v = r->rr[base + k][0];

			r->rr[base + k][0] = 0;
			r->rr[base + k][axis] = v;
		}
	}
	r->n_pts = base + nseg;
	return SSC_EXIT_OK;
}

static int rate_table_fit(struct run *r)
{
	const struct ssc_common *co = r->co;
	struct sscope_diag d = { "" };
	struct sscope_calib_triad c;
	enum sscope_quantity q = r->o.gyro ? SSCOPE_QUANTITY_ANGULAR_RATE :
					      SSCOPE_QUANTITY_ACCELERATION;
	int rc = sscope_calib_linear_fit((const double(*)[3])r->ry,
					 (const double(*)[3])r->rr, r->n_pts,
					 r->o.cubic, &r->lf, &d);

	if (rc) {
		ssc_err(co->cmd, "rate table: %s", d.msg[0] ? d.msg : sscope_strerror(rc));
		return SSC_EXIT_FAIL;
	}
	r->have_lf = true;
	if (sscope_calib_linear_to_triad(&r->lf, &c) == 0) {
		fill_triad(&r->pub.out[0], r->o.gyro ? "gyro" : "accel", r->cap,
			   r->o.gyro ? r->gi : r->ai, q, &c);
		r->pub.out[0].t.c.residual_rms /=
			ssc_calfile_unit_scale(r->pub.out[0].t.input_unit);
		r->pub.out[0].residual_unit = r->pub.out[0].t.input_unit[0] ?
						  r->pub.out[0].t.input_unit : "counts";
		ssc_calib_triad_finish(&r->pub.out[0]);
		r->pub.n_out = 1;
	}
	return SSC_EXIT_OK;
}

/* the sensor channels have the dimension of the reference */
static bool rt_ratio(const struct run *r)
{
	const long *ci = r->o.gyro ? r->gi : r->ai;

	return r->cap->channels[ci[0]].col.quantity ==
	       (r->o.gyro ? SSCOPE_QUANTITY_ANGULAR_RATE : SSCOPE_QUANTITY_ACCELERATION);
}

static json_t *rate_table_json(const struct run *r)
{
	json_t *o = json_object(), *axes = json_array();
	const struct sscope_calib_linear *lf = &r->lf;
	const char *ch = "xyz";
	const long *ci = r->o.gyro ? r->gi : r->ai;
	double s = ssc_calfile_unit_scale(r->cap->channels[ci[0]].col.unit_label);
	/* sensitivities: ratios when the sensor's unit has the reference's
	 * dimension (held data are SI then), else input units per SI */
	double sa = rt_ratio(r) ? 1 : s;
	const char *si = sscope_quantity_si_unit(r->o.gyro ?
							 SSCOPE_QUANTITY_ANGULAR_RATE :
							 SSCOPE_QUANTITY_ACCELERATION);

	json_object_set_new(o, "points", json_integer((json_int_t)lf->points));
	json_object_set_new(o, "reference_si_unit", json_string(si));
	json_object_set_new(o, "bias_unit",
			    json_string(r->cap->channels[ci[0]].col.unit_label));
	json_object_set_new(o, "scale_factor_unit", json_string(rt_ratio(r) ? "1" :
				    "input unit per SI unit"));
	json_object_set_new(o, "cubic", json_boolean(lf->nonlinear));
	for (int i = 0; i < 3; i++) {
		json_t *a = json_object(), *cross = json_array(), *csd = json_array();

		json_object_set_new(a, "channel",
				    json_string(r->cap->channels[ci[i]].col.name));
		json_object_set_new(a, "input_axis", json_string((char[2]){ ch[i], 0 }));
		json_object_set_new(a, "excited", json_boolean(lf->axis_excited[i]));
		json_object_set_new(a, "bias", ssc_jreal(lf->bias[i] / s));
		json_object_set_new(a, "bias_sd", ssc_jreal(lf->bias_sd[i] / s));
		json_object_set_new(a, "scale_factor", lf->axis_excited[i] ?
						ssc_jreal(lf->A[i][i] / sa) : json_null());
		json_object_set_new(a, "scale_factor_sd", lf->axis_excited[i] ?
						ssc_jreal(lf->A_sd[i][i] / sa) : json_null());
		json_object_set_new(a, "scale_factor_bfsl", lf->axis_excited[i] ?
						ssc_jreal(lf->sf_bfsl[i] / sa) : json_null());
		json_object_set_new(a, "full_scale_si", lf->axis_excited[i] ? ssc_jreal(lf->full_scale[i]) : json_null());
		json_object_set_new(a, "nonlinearity_percent_fs",
				    ssc_jreal(lf->nonlinearity[i] * 100));
		json_object_set_new(a, "residual_rms", ssc_jreal(lf->residual_rms[i] / s));
		for (int j = 0; j < 3; j++) {
			json_array_append_new(cross, lf->axis_excited[j] ?
						       ssc_jreal(lf->A[i][j] / sa) : json_null());
			json_array_append_new(csd, lf->axis_excited[j] ?
						     ssc_jreal(lf->A_sd[i][j] / sa) : json_null());
		}
		json_object_set_new(a, "sensitivity_row", cross);
		json_object_set_new(a, "sensitivity_row_sd", csd);
		if (lf->nonlinear && lf->axis_excited[i]) {
			json_object_set_new(a, "c2", ssc_jreal(lf->c2[i] / sa));
			json_object_set_new(a, "c2_sd", ssc_jreal(lf->c2_sd[i] / sa));
			json_object_set_new(a, "c3", ssc_jreal(lf->c3[i] / sa));
			json_object_set_new(a, "c3_sd", ssc_jreal(lf->c3_sd[i] / sa));
		}
		json_array_append_new(axes, a);
	}
	json_object_set_new(o, "axes", axes);
	return o;
}

static void rate_table_text(FILE *f, const struct run *r)
{
	const struct sscope_calib_linear *lf = &r->lf;
	const long *ci = r->o.gyro ? r->gi : r->ai;
	const char *iu = r->cap->channels[ci[0]].col.unit_label;
	const char *si = sscope_quantity_si_unit(r->o.gyro ?
							 SSCOPE_QUANTITY_ANGULAR_RATE :
							 SSCOPE_QUANTITY_ACCELERATION);
	double s = ssc_calfile_unit_scale(iu), sa = rt_ratio(r) ? 1 : s;
	char a[32], b[32];

	if (rt_ratio(r))
		fprintf(f, "  rate table: %zu steps; scale factor and cross-axis terms as ratios, bias in %s,\n    c2, c3 per %s and %s^2; non-linearity: best-fit straight line, %% of full scale\n",
			lf->points, iu, si, si);
	else
		fprintf(f, "  rate table: %zu steps; scale factor in %s per %s, non-linearity: best-fit straight line, %% of full scale\n",
			lf->points, iu[0] ? iu : "counts", si);
	/* the full scale is the reference's (SI): deg/s for a gyro */
	const char *fsu = r->o.gyro ? "deg/s" : si;
	double fss = r->o.gyro ? 180 / PI : 1;

	{
		char fs[40];

		snprintf(fs, sizeof(fs), "FS (%s)", fsu);
		fprintf(f, "    %-8s %-8s %22s %14s %12s %12s\n", "channel", "excited",
			"scale factor", "bias", "NL (% FS)", fs);
	}
	for (int i = 0; i < 3; i++) {
		fprintf(f, "    %-8s %-8s ", r->cap->channels[ci[i]].col.name,
			lf->axis_excited[i] ? "yes" : "no");
		if (lf->axis_excited[i])
			fprintf(f, "%13s±%-8s ", ssc_fmt(a, sizeof(a), lf->A[i][i] / sa, 7),
				ssc_fmt(b, sizeof(b), lf->A_sd[i][i] / sa, 2));
		else
			fprintf(f, "%22s ", "-");
		fprintf(f, "%14s %12s %12s\n", ssc_fmt(a, sizeof(a), lf->bias[i] / s, 5),
			lf->axis_excited[i] ? ssc_fmt(b, sizeof(b), lf->nonlinearity[i] * 100, 3) : "-",
			lf->axis_excited[i] ? ssc_fmt((char[32]){ 0 }, 32,
						      lf->full_scale[i] * fss, 4) : "-");
		for (int j = 0; j < 3; j++)
			if (j != i && lf->axis_excited[j])
				fprintf(f, "      cross-axis from input %c: %s±%s\n", "xyz"[j],
					ssc_fmt(a, sizeof(a), lf->A[i][j] / sa, 4),
					ssc_fmt(b, sizeof(b), lf->A_sd[i][j] / sa, 2));
		if (lf->nonlinear && lf->axis_excited[i])
			fprintf(f, "      c2 = %s±%s, c3 = %s±%s\n",
				ssc_fmt(a, sizeof(a), lf->c2[i] / sa, 4),
				ssc_fmt(b, sizeof(b), lf->c2_sd[i] / sa, 2),
				ssc_fmt((char[32]){ 0 }, 32, lf->c3[i] / sa, 4),
				ssc_fmt((char[32]){ 0 }, 32, lf->c3_sd[i] / sa, 2));
	}
}

/* ------------------------------------------------------------------ */
/* Plot                                                                */
/* ------------------------------------------------------------------ */

/* The static intervals as thick segments at height y. */
static void plot_intervals(struct ssc_ax *ax, const struct run *r, double y)
{
	struct ssc_style sm = { .color = 0x2ca02c, .width = 4 };

	for (size_t k = 0; k < r->n_iv; k++) {
		double xs[2] = { (double)r->iv[k].start / r->cap->rate_hz,
				 (double)r->iv[k].end / r->cap->rate_hz };
		double ys[2] = { y, y };

		ssc_ax_line(ax, xs, ys, 2, &sm, k ? NULL : "static intervals");
	}
}

/* Gyro multi-position: the rate magnitude with the static poses, and how
 * far the gyro carries gravity off over each motion, with the bias
 * removed only and calibrated. */
static void plot_gyro(struct ssc_fig *fig, const struct run *r)
{
	const struct sscope_capture *cap = r->cap;
	const struct ssc_calib_triad_out *o = &r->pub.out[1];
	double *t = malloc(cap->n * sizeof(double));
	double *w = malloc(cap->n * sizeof(double));
	double *k = malloc(r->n_mot * sizeof(double));
	double *b = malloc(r->n_mot * sizeof(double));
	double *a = malloc(r->n_mot * sizeof(double));
	bool si = cap->channels[r->gi[0]].col.quantity == SSCOPE_QUANTITY_ANGULAR_RATE;
	struct ssc_ax *ax = ssc_fig_ax(fig, 0, 0);
	char buf[256];

	if (t && w) {
		double lo = INFINITY;
		struct ssc_style st = { .color = 0x1f77b4, .width = 1 };

		for (size_t i = 0; i < cap->n; i++) {
			double s = 0;

			for (int j = 0; j < 3; j++) {
				double v = cap->channels[r->gi[j]].data[i] -
					   o->t.c.bias[j];

				s += v * v;
			}
			t[i] = (double)i / cap->rate_hz;
			w[i] = sqrt(s) * (si ? 180 / PI : 1);
			if (w[i] > 0)
				lo = fmin(lo, w[i]);
		}
		ssc_ax_log(ax, false, true);
		ssc_ax_line(ax, t, w, cap->n, &st, "gyro rate magnitude, bias removed");
		if (isfinite(lo))
			plot_intervals(ax, r, lo / 2);
		ssc_ax_ylabel(ax, si ? "|\xcf\x89| (\xc2\xb0/s)" : "|\xcf\x89| (input units)");
		ssc_ax_xlabel(ax, "time (s)");
		ssc_ax_title(ax, "gyro rate between the static poses");
		snprintf(buf, sizeof(buf), "%zu static poses\n%zu motions", r->n_iv,
			 r->n_mot);
		ssc_ax_note(ax, buf, SSC_LEGEND_AUTO);
	}
	ax = ssc_fig_ax(fig, 1, 0);
	if (k && b && a) {
		struct ssc_style sb = { .color = 0x7f7f7f, .width = -1,
					.marker = SSC_MK_SQUARE };
		struct ssc_style sa = { .color = 0x1f77b4, .width = -1,
					.marker = SSC_MK_CIRCLE };

		for (size_t i = 0; i < r->n_mot; i++) {
			k[i] = (double)i + 1;
			b[i] = r->mot_before[i] * 180 / PI;
			a[i] = r->mot_after[i] * 180 / PI;
		}
		ssc_ax_log(ax, false, true);
		ssc_ax_line(ax, k, b, r->n_mot, &sb,
			    si ? "bias removed only (nominal scale)" :
				 "bias removed only (mean scale)");
		ssc_ax_line(ax, k, a, r->n_mot, &sa, "calibrated");
		ssc_ax_xlim(ax, 0.5, (double)r->n_mot + 0.5);
		ssc_ax_ylabel(ax, "gravity direction error (\xc2\xb0)");
		ssc_ax_xlabel(ax, "motion between static poses");
		ssc_ax_title(ax, "gyro-integrated rotation against the next pose");
		snprintf(buf, sizeof(buf), "rms %.3g\xc2\xb0 calibrated\n%.3g\xc2\xb0 bias removed only",
			 o->motion_rms * 180 / PI, o->motion_rms_bias_only * 180 / PI);
		ssc_ax_note(ax, buf, SSC_LEGEND_AUTO);
	}
	free(t);
	free(w);
	free(k);
	free(b);
	free(a);
}

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *path)
{
	const struct run *r = result;
	struct ssc_fig *fig;
	int rc;
	char buf[200];

	(void)opts;
	if (!r->have_lf && r->o.gyro && r->n_mot) {
		fig = ssc_fig_new(1100, 860, 2, 1);
		snprintf(buf, sizeof(buf), "calib gyro (%s): %s",
			 mode_names[r->o.mode], r->cap->source);
		ssc_fig_title(fig, buf);
		plot_gyro(fig, r);
	} else if (r->have_lf) {
		const struct sscope_calib_linear *lf = &r->lf;
		const long *ci = r->o.gyro ? r->gi : r->ai;
		int na = 0;

		for (int i = 0; i < 3; i++)
			na += lf->axis_excited[i];
		fig = ssc_fig_new(1000, 200 + 380 * na, na, 1);
		ssc_fig_title(fig, "rate table: deviation from the best-fit straight line");
		for (int i = 0, row = 0; i < 3; i++) {
			double *x, *y;
			struct ssc_ax *ax;
			struct ssc_style st = { .color = ssc_plot_color((size_t)i),
						.width = -1, .marker = SSC_MK_CIRCLE };
			size_t n = 0;

			if (!lf->axis_excited[i])
				continue;
			x = malloc(r->n_pts * sizeof(double));
			y = malloc(r->n_pts * sizeof(double));
			for (size_t k = 0; k < r->n_pts && x && y; k++) {
				double ref = r->rr[k][i];

				/* deviation from the straight line (its offset
				 * removed below), % of full-scale output */
				x[n] = ref;
				y[n++] = r->ry[k][i] - lf->sf_bfsl[i] * ref;
			}
			if (x && y && n) {
				double m = 0;

				for (size_t k = 0; k < n; k++)
					m += y[k];
				m /= (double)n;
				for (size_t k = 0; k < n; k++)
					y[k] = (y[k] - m) /
					       (fabs(lf->sf_bfsl[i]) * lf->full_scale[i]) * 100;
			}
			ax = ssc_fig_ax(fig, row++, 0);
			if (x && y) {
				double ym = 0;

				ssc_ax_line(ax, x, y, n, &st, NULL);
				for (size_t k = 0; k < n; k++)
					ym = fmax(ym, fabs(y[k]));
				ssc_ax_xlim(ax, -1.08 * lf->full_scale[i],
					    1.08 * lf->full_scale[i]);
				if (ym > 0)
					ssc_ax_ylim(ax, -1.15 * ym, 1.15 * ym);
			}
			snprintf(buf, sizeof(buf), "%s: deviation (%% FS)",
				 r->cap->channels[ci[i]].col.name);
			ssc_ax_ylabel(ax, buf);
			snprintf(buf, sizeof(buf), "reference on input %c (%s)", "xyz"[i],
				 sscope_quantity_si_unit(r->o.gyro ?
								 SSCOPE_QUANTITY_ANGULAR_RATE :
								 SSCOPE_QUANTITY_ACCELERATION));
			ssc_ax_xlabel(ax, buf);
			snprintf(buf, sizeof(buf), "non-linearity %.3g %% FS",
				 lf->nonlinearity[i] * 100);
			ssc_ax_note(ax, buf, SSC_LEGEND_AUTO);
			free(x);
			free(y);
		}
	} else {
		const struct sscope_capture *cap = r->cap;
		double *t = malloc(cap->n * sizeof(double));
		struct ssc_ax *ax;
		struct ssc_style st = { .color = 0x1f77b4, .width = 1 };
		struct ssc_style th = { .color = 0xd62728, .width = 1.5,
					.dash = SSC_DASHED };

		fig = ssc_fig_new(1100, 800, 2, 1);
		snprintf(buf, sizeof(buf), "calib %s (%s): %s",
			 r->o.gyro ? "gyro" : "accel", mode_names[r->o.mode],
			 cap->source);
		ssc_fig_title(fig, buf);
		ax = ssc_fig_ax(fig, 0, 0);
		if (t && r->vs) {
			for (size_t i = 0; i < cap->n; i++)
				t[i] = (double)i / cap->rate_hz;
			ssc_ax_log(ax, false, true);
			ssc_ax_line(ax, t, r->vs, cap->n, &st, "accelerometer variance magnitude");
			ssc_ax_hline(ax, r->o.det.threshold, &th, "threshold");
			plot_intervals(ax, r, r->o.det.threshold / 3);
			snprintf(buf, sizeof(buf), "variance magnitude ((%s)^{2})",
				 cap->channels[r->ai[0]].col.quantity ==
						 SSCOPE_QUANTITY_ACCELERATION ?
					 "m/s^{2}" : "input");
			ssc_ax_ylabel(ax, buf);
			ssc_ax_xlabel(ax, "time (s)");
			snprintf(buf, sizeof(buf), "%zu static intervals\nthreshold %.3g x reference",
				 r->n_iv, r->o.det.k);
			ssc_ax_note(ax, buf, SSC_LEGEND_UL);
		}
		free(t);
		ax = ssc_fig_ax(fig, 1, 0);
		if (r->n_pose) {
			double *k = malloc(r->n_pose * sizeof(double));
			struct ssc_style sb = { .color = 0x7f7f7f, .width = -1,
						.marker = SSC_MK_SQUARE };
			struct ssc_style sa = { .color = 0x1f77b4, .width = -1,
						.marker = SSC_MK_CIRCLE };

			for (size_t i = 0; k && i < r->n_pose; i++)
				k[i] = (double)i + 1;
			if (k) {
				if (cap->channels[r->ai[0]].col.quantity ==
				    SSCOPE_QUANTITY_ACCELERATION)
					ssc_ax_line(ax, k, r->pose_before, r->n_pose, &sb,
						    "|a| - g, raw");
				ssc_ax_line(ax, k, r->pose_after, r->n_pose, &sa,
					    "|a'| - g, calibrated");
			}
			free(k);
			ssc_ax_ylabel(ax, "norm error (m/s^{2})");
			ssc_ax_xlabel(ax, "static pose");
			ssc_ax_legend(ax, SSC_LEGEND_AUTO);
		}
	}
	rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

/* ------------------------------------------------------------------ */

static json_t *detection_json(const struct opts *o)
{
	json_t *d = json_object();

	json_object_set_new(d, "window_s",
			    json_real(o->det.window_s > 0 ? o->det.window_s : 1));
	json_object_set_new(d, "min_static_s",
			    json_real(o->det.min_static_s > 0 ? o->det.min_static_s : 2));
	json_object_set_new(d, "rule", json_string(
		o->det.init_static_s > 0 ?
			"reference = variance magnitude of the initial static period" :
			"reference = 10th percentile of the variance magnitude"));
	if (o->det.init_static_s > 0)
		json_object_set_new(d, "init_static_s", json_real(o->det.init_static_s));
	json_object_set_new(d, "reference", ssc_jreal(o->det.reference));
	json_object_set_new(d, "k", ssc_jreal(o->det.k));
	json_object_set_new(d, "threshold", ssc_jreal(o->det.threshold));
	json_object_set_new(d, "intervals",
			    json_integer((json_int_t)o->det.n_intervals));
	return d;
}

static void init(void *opts)
{
	struct opts *o = opts;

	memset(o, 0, sizeof(*o));
	o->gravity = SSCOPE_CALIB_GRAVITY_STD;
	o->settle_s = 1;
}

static int check(struct ssc_common *co, void *opts)
{
	struct opts *o = opts;

	if (!o->triad_set)
		return ssc_usage_error(co->cmd, "give 'accel' or 'gyro' first");
	if (o->mode == M_TILT && !o->gyro)
		return ssc_usage_error(co->cmd, "--mode tilt is for 'calib gyro'");
	if (o->mode == M_SIXPOS && o->gyro)
		return ssc_usage_error(co->cmd, "--mode sixpos is for 'calib accel'");
	if (o->mode == M_RATE_TABLE && !o->reference == !o->schedule)
		return ssc_usage_error(co->cmd, "--mode rate-table needs --reference or --schedule");
	/* options of another mode would be ignored */
	if (o->mode != M_RATE_TABLE) {
		const char *x = o->reference ? "reference" : o->schedule ? "schedule" :
				o->table_axis ? "table-axis" : o->settle_set ? "settle" :
				o->cubic ? "cubic" : NULL;

		if (x)
			return ssc_usage_error(co->cmd, "--%s: applies to --mode rate-table only", x);
	}
	if (o->gsens && !(o->gyro && o->mode == M_MULTIPOS))
		return ssc_usage_error(co->cmd, "--g-sensitivity: applies to 'calib gyro' --mode multipos only");
	return SSC_EXIT_OK;
}

static void free_result(void *result)
{
	struct run *r = result;

	free(r->iv);
	free(r->vs);
	free(r->pose_before);
	free(r->pose_after);
	free(r->mot_before);
	free(r->mot_after);
	free(r->ry);
	free(r->rr);
	free(r);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const struct ssc_common *co = env->co;
	struct opts *o;
	struct run *r = calloc(1, sizeof(*r));
	size_t nfiles = env->n_caps;
	int rc = SSC_EXIT_OK;

	if (r)
		r->iv = malloc(MAX_IV * sizeof(*r->iv));
	if (!r || !r->iv) {
		free(r);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = r;
	r->o = *(struct opts *)opts;
	o = &r->o;
	if (o->mode != M_RATE_TABLE && nfiles > 1)
		return ssc_usage_error(co->cmd, "--mode %s takes one input file",
				       mode_names[o->mode]);
	r->co = co;
	r->paths = env->paths;
	r->n_files = nfiles;
	for (size_t fi = 0; fi < nfiles && !rc; fi++) {
		r->cap = env->caps[fi];
		rc = ssc_time_check(co, env->paths[fi], r->cap, true);
		if (rc)
			break;
		if (!(r->cap->rate_hz > 0)) {
			rc = ssc_err_no_rate(co->cmd, env->paths[fi], r->cap->rate_note);
			break;
		}
		if (o->gyro || o->mode == M_TILT) {
			rc = pick3(co, r->cap, o->gyro_names, SSCOPE_QUANTITY_ANGULAR_RATE,
				   o->reference, "gyro", r->gi);
			if (rc)
				break;
		}
		if (!o->gyro || o->mode != M_RATE_TABLE) {
			rc = pick3(co, r->cap, o->accel, SSCOPE_QUANTITY_ACCELERATION,
				   o->reference, "accel", r->ai);
			if (rc)
				break;
		}
		switch (o->mode) {
		case M_MULTIPOS:
			rc = o->gyro ? gyro_multipos(r) : accel_multipos(r);
			break;
		case M_SIXPOS:
			rc = accel_sixpos(r);
			break;
		case M_TILT:
			rc = gyro_tilt(r);
			break;
		case M_RATE_TABLE:
			rc = rate_table_file(r, (int)fi);
			break;
		}
	}
	if (!rc && o->mode == M_RATE_TABLE)
		rc = rate_table_fit(r);
	if (!rc && o->save && r->pub.n_out == 0) {
		ssc_err(co->cmd, "--save-calibration: the runs did not excite all three axes: no full triad to save");
		rc = SSC_EXIT_FAIL;
	}
	r->co = NULL;
	return rc;
}

static const char *cmd_name(const struct run *r)
{
	return r->o.gyro ? "calib gyro" : "calib accel";
}

/* --save-calibration */
static int write_cal(const struct ssc_common *co, const void *opts,
		     const void *result)
{
	const struct run *r = result;
	struct ssc_common c2 = *co;
	struct sscope_calib_file_triad t[2];

	(void)opts;
	if (!r->o.save)
		return SSC_EXIT_OK;
	for (int i = 0; i < r->pub.n_out; i++)
		t[i] = r->pub.out[i].t;
	c2.cmd = cmd_name(r);
	return ssc_calfile_write(&c2, r->o.save, t, (size_t)r->pub.n_out);
}

static json_t *json(const void *opts, const void *result)
{
	const struct run *r = result;
	const struct opts *o = &r->o;
	json_t *root = json_object(), *tr = json_array(), *files = json_array();

	(void)opts;
	json_object_set_new(root, "command", json_string(cmd_name(r)));
	json_object_set_new(root, "mode", json_string(mode_names[o->mode]));
	for (size_t fi = 0; fi < r->n_files; fi++)
		json_array_append_new(files, json_string(r->paths[fi]));
	json_object_set_new(root, "file", json_string(r->paths[0]));
	json_object_set_new(root, "files", files);
	json_object_set_new(root, "gravity_m_s2", json_real(o->gravity));
	if (o->mode != M_RATE_TABLE)
		json_object_set_new(root, "detection", detection_json(o));
	for (int i = 0; i < r->pub.n_out; i++)
		json_array_append_new(tr, ssc_calib_triad_out_json(&r->pub.out[i]));
	json_object_set_new(root, "triads", tr);
	if (r->have_lf)
		json_object_set_new(root, "rate_table", rate_table_json(r));
	if (o->save)
		json_object_set_new(root, "calibration_file", json_string(o->save));
	return root;
}

static void csv(FILE *f, const void *opts, const void *result)
{
	const struct run *r = result;

	(void)opts;
	fprintf(f, "kind,channel,input_unit,output_unit,bias,bias_sd,scale,scale_sd,T0,T1,T2,residual_rms,poses\n");
	for (int i = 0; i < r->pub.n_out; i++) {
		const struct ssc_calib_triad_out *t = &r->pub.out[i];
		double sc = ssc_calfile_unit_scale(t->t.input_unit);

		for (int j = 0; j < 3; j++)
			fprintf(f, "%s,%s,%s,%s,%.10g,%.4g,%.10g,%.4g,%.8g,%.8g,%.8g,%.6g,%zu\n",
				t->t.kind, t->t.channels[j], t->t.input_unit,
				t->t.output_unit, t->t.c.bias[j] / sc,
				t->t.c.bias_sd[j] / sc, t->t.c.scale[j] * sc,
				t->t.c.scale_sd[j] * sc, t->t.c.mis[j][0],
				t->t.c.mis[j][1], t->t.c.mis[j][2],
				t->t.c.residual_rms, t->t.c.poses);
	}
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct run *r = result;

	(void)opts;
	if (r->have_lf) {
		/* a rate table: each turned axis' scale factor and linearity */
		const struct sscope_calib_linear *lf = &r->lf;
		const long *ci = r->o.gyro ? r->gi : r->ai;
		char un[96];
		double sa = rt_ratio(r) ? 1 :
			    ssc_calfile_unit_scale(r->cap->channels[ci[0]].col.unit_label);

		snprintf(un, sizeof(un), "%s%s%s", rt_ratio(r) ? "" :
			 r->cap->channels[ci[0]].col.unit_label, rt_ratio(r) ? "" : " per ",
			 rt_ratio(r) ? "" : sscope_quantity_si_unit(r->o.gyro ?
						SSCOPE_QUANTITY_ANGULAR_RATE :
						SSCOPE_QUANTITY_ACCELERATION));
		for (int i = 0; i < 3; i++) {
			const char *name = r->cap->channels[ci[i]].col.name;

			if (!lf->axis_excited[i])
				continue;
			ssc_summary_add(rows, name, "scale factor", lf->A[i][i] / sa,
					(lf->A[i][i] - 2 * lf->A_sd[i][i]) / sa,
					(lf->A[i][i] + 2 * lf->A_sd[i][i]) / sa, un,
					"rate table; interval: +-2 sd");
			ssc_summary_add(rows, name, "non-linearity",
					lf->nonlinearity[i] * 100, NAN, NAN, "% FS",
					"best-fit straight line");
		}
	}
	for (int i = 0; i < r->pub.n_out; i++) {
		const struct ssc_calib_triad_out *t = &r->pub.out[i];
		double sc = ssc_calfile_unit_scale(t->t.input_unit);
		char q[64];

		snprintf(q, sizeof(q), "%s bias", t->t.kind);
		for (int j = 0; j < 3; j++)
			ssc_summary_add(rows, t->t.channels[j], q,
					t->t.c.bias[j] / sc,
					(t->t.c.bias[j] - 2 * t->t.c.bias_sd[j]) / sc,
					(t->t.c.bias[j] + 2 * t->t.c.bias_sd[j]) / sc,
					t->t.input_unit, "interval: +-2 sd");
	}
}

static void text(FILE *f, const void *opts, const void *result)
{
	const struct run *r = result;
	const struct opts *o = &r->o;

	(void)opts;
	fprintf(f, "%s (%s): %s%s\n", cmd_name(r), mode_names[o->mode],
		r->paths[0], r->n_files > 1 ? " ..." : "");
	if (o->mode != M_RATE_TABLE)
		fprintf(f, "  static detector: window %g s, %s, k = %g, threshold %.4g (%s)^2, %zu intervals\n",
			o->det.window_s > 0 ? o->det.window_s : 1,
			o->det.init_static_s > 0 ? "reference from the initial static period" :
			"reference = 10th percentile of the variance magnitude",
			o->det.k, o->det.threshold,
			/* the detector runs on the accelerometers */
			sscope_quantity_si_unit(SSCOPE_QUANTITY_ACCELERATION),
			o->det.n_intervals);
	if (r->have_lf)
		rate_table_text(f, r);
	for (int i = 0; i < r->pub.n_out; i++)
		triad_text(f, &r->pub.out[i]);
	if (o->save)
		fprintf(f, "  calibration written to %s\n", o->save);
}

const struct ssc_stage_ops ssc_calib_stage = {
	.spec = &spec,
	.title = "Error-model calibration",
	.needs = SSC_NEED_DATA,
	.min_files = 1,
	.max_files = -1,
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
	.write = write_cal,
	.free_result = free_result,
};

int ssc_cmd_calib(int argc, char **argv)
{
	char *args[256];
	int n = 0;

	/* "calib accel ..." is "calib --triad accel ..." */
	if (argc >= 2 && (!strcmp(argv[1], "accel") || !strcmp(argv[1], "gyro"))) {
		if (argc + 1 > 256)
			return ssc_usage_error("calib", "too many arguments");
		args[n++] = argv[0];
		args[n++] = "--triad";
		for (int i = 1; i < argc; i++)
			args[n++] = argv[i];
		return ssc_stage_main(&ssc_calib_stage, n, args);
	}
	return ssc_stage_main(&ssc_calib_stage, argc, argv);
}
