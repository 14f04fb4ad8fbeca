/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope inclino calibrate | apply: inclinometer look-up table of
 * per-axis offset, scale and misalignment against temperature
 * (analysis/inclino.c, ADI AN-1057) from static captures at known tilts,
 * validated in degrees; and roll/pitch from raw accelerations with the
 * table, each sample flagged still or moving.
 */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "plot.h"
#include "stage.h"

#define R2D (180 / PI)
#define MAX_VAL 16
#define MAX_POSES 100000

enum {
	O_ACCEL = 300,
	O_ROLL,
	O_PITCH,
	O_GRAVITY,
	O_POSETOL,
	O_NODEGAP,
	O_VALIDATE,
	O_CUBIC,
	O_TILTS,
	O_LUT,
	O_GYRO,
	O_NOGYRO,
	O_STILLTOL,
	O_RATETOL,
	O_AXES,
};

/* ------------------------------------------------------------------ */
/* shared                                                              */
/* ------------------------------------------------------------------ */

static int pick_accel(const char *cmd, const struct sscope_capture *cap,
		      const char *names, const char *path, long idx[3])
{
	if (names) {
		char buf[256], *save = NULL, *tok;
		int k = 0;

		snprintf(buf, sizeof(buf), "%s", names);
		for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
			if (k == 3)
				break;
			idx[k] = sscope_capture_find(cap, tok);
			if (idx[k] < 0) {
				ssc_err(cmd, "%s: no column '%s'", path, tok);
				return SSC_EXIT_FAIL;
			}
			k++;
		}
		if (k != 3) {
			ssc_err(cmd, "--accel: give three channel names");
			return SSC_EXIT_USAGE;
		}
		return 0;
	}
	for (size_t i = 0, k = 0; i < cap->n_channels && k < 3; i++)
		if (cap->channels[i].col.quantity == SSCOPE_QUANTITY_ACCELERATION)
			idx[k++] = (long)i;
	{
		int k = 0;

		for (size_t i = 0; i < cap->n_channels; i++)
			k += cap->channels[i].col.quantity == SSCOPE_QUANTITY_ACCELERATION;
		if (k < 3) {
			ssc_err(cmd, "%s: %d acceleration column%s, 3 needed (give units, or --accel X,Y,Z)",
				path, k, k == 1 ? "" : "s");
			return SSC_EXIT_FAIL;
		}
	}
	return 0;
}

/* ------------------------------------------------------------------ */
/* calibrate (a stage)                                                 */
/* ------------------------------------------------------------------ */

static const struct ssc_option cal_opts[] = {
	{ "accel", required_argument, O_ACCEL, "X,Y,Z",
	  "accelerometer channels (default: the first three acceleration columns)" },
	{ "roll-ref", required_argument, O_ROLL, "NAME", "reference roll column (default roll_ref)" },
	{ "pitch-ref", required_argument, O_PITCH, "NAME", "reference pitch column (default pitch_ref)" },
	{ "gravity", required_argument, O_GRAVITY, "G", "local gravity (default 9.80665 m/s^2)" },
	{ "pose-tol", required_argument, O_POSETOL, "DEGC",
	  "temperature tolerance within a pose (default 1 degC)" },
	{ "node-gap", required_argument, O_NODEGAP, "DEGC",
	  "pose temperatures further apart start a new LUT node (default 3 degC)" },
	{ "validate", required_argument, O_VALIDATE, "FILE",
	  "validation capture (same columns) at other temperatures/angles; repeatable" },
	{ "cubic", no_argument, O_CUBIC, NULL, "cubic-spline interpolation (3+ nodes; default linear)" },
	{ "tilt-table", required_argument, O_TILTS, "FILE",
	  "tilts by time, used instead of the calibration captures' reference columns: lines 'START END ROLL PITCH' (s from the capture's start, degrees)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec cal_spec = {
	.name = "inclino calibrate",
	.usage = "inclino calibrate [OPTIONS] FILE... -o LUT.json",
	.summary =
		"Inclinometer look-up table from static captures at known tilts (columns\n"
		"roll_ref [deg], pitch_ref [deg], constant within a pose) at several\n"
		"temperatures: per-axis offset, scale and misalignment at each temperature\n"
		"node (least squares, AN-1057 model), linear interpolation (cubic optional)\n"
		"and clamping outside the range; validation errors in degrees against the\n"
		"0.1 degree class, with the dominant residual term.  With -o *.json the\n"
		"output is JSON: the LUT that 'inclino apply --lut' reads.",
	.options = cal_opts,
	.analysis = true,
	.notes = "Convention: a level, still sensor reads (0, 0, +1 g); pitch = atan2(-ax, sqrt(ay^2+az^2)),\n"
		 "roll = atan2(ay, az).  Examples:\n"
		 "  sensorscope inclino calibrate samples/inclino-cal.csv -o lut.json\n"
		 "  sensorscope inclino calibrate --validate samples/inclino-val.csv samples/inclino-cal.csv\n"
		 "  sensorscope inclino apply --lut lut.json -o tilt.csv samples/inclino-val.csv",
};

struct cal_opts_s {
	const char *accel, *roll, *pitch, *tilts;
	double gravity, pose_tol, node_gap;
	const char *validate[MAX_VAL];
	int n_val;
	bool cubic;
};

static int cal_handler(int key, const char *arg, void *ctx)
{
	struct cal_opts_s *o = ctx;

	switch (key) {
	case O_ACCEL:
		o->accel = arg;
		return 0;
	case O_ROLL:
		o->roll = arg;
		return 0;
	case O_PITCH:
		o->pitch = arg;
		return 0;
	case O_GRAVITY:
		return ssc_arg_gravity("inclino calibrate", arg, &o->gravity);
	case O_POSETOL:
		if (ssc_arg_double("inclino calibrate", "pose-tol", arg, &o->pose_tol) || !(o->pose_tol > 0))
			return ssc_usage_error("inclino calibrate", "--pose-tol: a positive number of degC");
		return 0;
	case O_NODEGAP:
		if (ssc_arg_double("inclino calibrate", "node-gap", arg, &o->node_gap) || !(o->node_gap > 0))
			return ssc_usage_error("inclino calibrate", "--node-gap: a positive number of degC");
		return 0;
	case O_VALIDATE:
		if (o->n_val == MAX_VAL)
			return ssc_usage_error("inclino calibrate", "--validate: at most %d files", MAX_VAL);
		o->validate[o->n_val++] = arg;
		return 0;
	case O_TILTS:
		o->tilts = arg;
		return 0;
	case O_CUBIC:
		o->cubic = true;
		return 0;
	}
	return SSC_EXIT_USAGE;
}

static void cal_init(void *opts)
{
	struct cal_opts_s *o = opts;

	memset(o, 0, sizeof(*o));
	o->roll = "roll_ref";
	o->pitch = "pitch_ref";
	o->gravity = SSCOPE_CALIB_GRAVITY_STD;
}

/* A tilt table (--tilt-table: "START END ROLL PITCH", s from the
 * capture's first time stamp, bare angles in degrees) turned into
 * reference columns (rad), NaN outside every interval. */
static int tilt_table(const struct ssc_common *co, const char *path,
		      const struct sscope_capture *cap, double *roll,
		      double *pitch)
{
	double *v, *out[2] = { roll, pitch };
	size_t rows;
	int rc = ssc_read_intervals(co, "tilt-table", path, "ROLL PITCH", 2,
				    "rad", "deg", &v, &rows);

	if (rc)
		return rc;
	sscope_timing_intervals_sample(cap->time_s, cap->rate_hz, cap->n, v, rows, 2, out);
	free(v);
	return 0;
}

/* Poses of a capture appended to *poses: its tilts from the tilt table
 * when @p table (a calibration capture and --tilt-table), else from its
 * reference columns. */
static int cap_poses(const struct ssc_common *co, const struct cal_opts_s *o,
		     const struct sscope_capture *cap, const char *path,
		     bool table, struct sscope_inclino_pose *poses, size_t *np)
{
	long a[3], ir, ip;
	size_t got = 0;
	int rc;

	if (!cap->temp_degc) {
		ssc_err(co->cmd, "%s: no temperature column (give --temp-column NAME)", path);
		return SSC_EXIT_FAIL;
	}
	ir = sscope_capture_find(cap, o->roll);
	ip = sscope_capture_find(cap, o->pitch);
	table = table && o->tilts;
	if ((ir < 0 || ip < 0) && !table) {
		ssc_err(co->cmd, "%s: no tilt reference column '%s' (give --roll-ref/--pitch-ref NAME%s)",
			path, ir < 0 ? o->roll : o->pitch,
			o->tilts ? "" : " or --tilt-table FILE");
		return SSC_EXIT_FAIL;
	}
	if (table && ir >= 0 && ip >= 0)
		ssc_warn(co, "%s: --tilt-table gives the tilts: the reference columns '%s' and '%s' are not used",
			 path, o->roll, o->pitch);
	rc = pick_accel(co->cmd, cap, o->accel, path, a);
	if (rc)
		return rc;
	if (table) {
		double *ref = malloc(2 * (cap->n ? cap->n : 1) * sizeof(double));

		if (!(cap->time_s || cap->rate_hz > 0)) {
			free(ref);
			ssc_err(co->cmd, "%s: --tilt-table needs time stamps or a sample rate", path);
			return SSC_EXIT_FAIL;
		}
		if (!ref) {
			ssc_err(co->cmd, "out of memory");
			return SSC_EXIT_FAIL;
		}
		rc = tilt_table(co, o->tilts, cap, ref, ref + cap->n);
		if (!rc)
			rc = sscope_inclino_poses(cap->channels[a[0]].data,
						  cap->channels[a[1]].data,
						  cap->channels[a[2]].data, cap->temp_degc,
						  ref, ref + cap->n, cap->n, o->pose_tol,
						  poses + *np, MAX_POSES - *np, &got) ?
				     -1 : 0;
		free(ref);
		if (rc > 0)
			return rc;
	} else {
		rc = sscope_inclino_poses(cap->channels[a[0]].data, cap->channels[a[1]].data,
					  cap->channels[a[2]].data, cap->temp_degc,
					  cap->channels[ir].data, cap->channels[ip].data, cap->n,
					  o->pose_tol, poses + *np, MAX_POSES - *np, &got);
	}
	if (rc) {
		ssc_err(co->cmd, "%s: no static pose with finite data", path);
		return SSC_EXIT_FAIL;
	}
	if (got > MAX_POSES - *np) {
		ssc_err(co->cmd, "%s: more than %d poses", path, MAX_POSES);
		return SSC_EXIT_FAIL;
	}
	*np += got;
	return 0;
}

struct incl_res {
	const char *const *paths;
	size_t n_files;
	struct sscope_inclino_lut *lut;
	struct sscope_inclino_validation v;
	size_t nv;
	bool have_v;
	/* the validation poses and each one's (roll, pitch) error,
	 * calibrated and uncompensated, deg (n_err of them; 0: none) */
	struct sscope_inclino_pose *vposes;
	double (*err)[2], (*raw)[2];
	size_t n_err;
};

/* The validation: each pose's roll and pitch error, calibrated and
 * uncompensated, against the 0.1 degree class (poses in file order, their
 * temperature range in the title). */
static void val_plot(struct ssc_ax *ax, const struct sscope_inclino_pose *vp,
		     const double (*e)[2], const double (*u)[2], size_t n)
{
	double *t = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));
	static const char *const lab[2][2] = {
		{ "roll, uncompensated", "pitch, uncompensated" },
		{ "roll, calibrated", "pitch, calibrated" }
	};
	struct ssc_style cls = { .color = 0xd62728, .width = 1.5,
				 .dash = SSC_DASHED };
	double tlo = INFINITY, thi = -INFINITY;
	char buf[160];

	if (!t || !y) {
		free(t);
		free(y);
		return;
	}
	for (int cal = 0; cal < 2; cal++)
		for (int c = 0; c < 2; c++) {
			struct ssc_style st = {
				.color = cal ? ssc_plot_color((size_t)c) : 0xa0a0a0,
				.width = -1,
				.marker = c ? SSC_MK_SQUARE : SSC_MK_CIRCLE,
				.marker_size = cal ? 7 : 5
			};

			for (size_t i = 0; i < n; i++) {
				t[i] = (double)i + 1;
				y[i] = cal ? e[i][c] : u[i][c];
				tlo = fmin(tlo, vp[i].temp_degc);
				thi = fmax(thi, vp[i].temp_degc);
			}
			ssc_ax_line(ax, t, y, n, &st, lab[cal][c]);
		}
	ssc_ax_hline(ax, 0.1, &cls, "0.1\xc2\xb0 class");
	ssc_ax_hline(ax, -0.1, &cls, NULL);
	ssc_ax_xlim(ax, 0, (double)n + 1);
	ssc_ax_xlabel(ax, "validation pose");
	ssc_ax_ylabel(ax, "tilt error (\xc2\xb0)");
	snprintf(buf, sizeof(buf),
		 "validation: tilt error of %zu poses at %.3g to %.3g \xc2\xb0" "C",
		 n, tlo, thi);
	ssc_ax_title(ax, buf);
	ssc_ax_grid(ax, true);
	free(t);
	free(y);
}

static int cal_plot(const struct ssc_common *co, const void *opts,
		    const void *result, const char *path)
{
	const struct incl_res *R = result;
	const struct sscope_inclino_lut *lut = R->lut;
	size_t nv = R->n_err;
	struct ssc_fig *fig = ssc_fig_new(1000, nv ? 1150 : 800, nv ? 3 : 2, 1);
	struct ssc_ax *a0, *a1;
	double t[SSCOPE_INCLINO_MAX_NODES], y[SSCOPE_INCLINO_MAX_NODES];
	double lo[SSCOPE_INCLINO_MAX_NODES], hi[SSCOPE_INCLINO_MAX_NODES];
	int rc;

	(void)opts;
	if (!fig) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	ssc_fig_title(fig, "inclinometer look-up table (±2 sd)");
	a0 = ssc_fig_ax(fig, 0, 0);
	a1 = ssc_fig_ax(fig, 1, 0);
	for (int a = 0; a < 3; a++) {
		struct ssc_style st = { .color = ssc_plot_color((size_t)a), .marker = SSC_MK_CIRCLE };
		char lab[32];

		snprintf(lab, sizeof(lab), "%c axis", "xyz"[a]);
		for (size_t i = 0; i < lut->n; i++) {
			double k = 1e3 / lut->gravity_m_s2;

			t[i] = lut->temp_degc[i];
			y[i] = lut->p[i].offset[a] * k;
			lo[i] = y[i] - 2 * lut->p[i].offset_sd[a] * k;
			hi[i] = y[i] + 2 * lut->p[i].offset_sd[a] * k;
		}
		ssc_ax_errorbar(a0, t, y, lo, hi, lut->n, &st, lab);
		for (size_t i = 0; i < lut->n; i++) {
			y[i] = (lut->p[i].scale[a] - 1) * 100;
			lo[i] = y[i] - 2 * lut->p[i].scale_sd[a] * 100;
			hi[i] = y[i] + 2 * lut->p[i].scale_sd[a] * 100;
		}
		ssc_ax_errorbar(a1, t, y, lo, hi, lut->n, &st, lab);
	}
	ssc_ax_ylabel(a0, "offset (mg)");
	ssc_ax_ylabel(a1, "scale error (%)");
	ssc_ax_xlabel(a0, "temperature (°C)");
	ssc_ax_xlabel(a1, "temperature (°C)");
	ssc_ax_legend(a0, SSC_LEGEND_AUTO);
	ssc_ax_legend(a1, SSC_LEGEND_AUTO);
	ssc_ax_grid(a0, true);
	ssc_ax_grid(a1, true);
	ssc_ax_title(a0, "offset of each axis at the calibration nodes");
	ssc_ax_title(a1, "scale error of each axis at the calibration nodes");
	if (nv)
		val_plot(ssc_fig_ax(fig, 2, 0), R->vposes,
			 (const double(*)[2])R->err, (const double(*)[2])R->raw, nv);
	rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

static void cal_free(void *result)
{
	struct incl_res *R = result;

	free(R->lut);
	free(R->vposes);
	free(R->err);
	free(R->raw);
	free(R);
}

static int cal_run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const struct ssc_common *co = env->co;
	struct cal_opts_s *o = opts;
	struct sscope_inclino_pose *poses = calloc(MAX_POSES, sizeof(*poses));
	struct incl_res *R = calloc(1, sizeof(*R));
	struct sscope_inclino_plan *plan = NULL;
	struct sscope_diag d = { "" };
	size_t np = 0;
	int rc = 0;

	if (R)
		R->lut = malloc(sizeof(*R->lut));
	if (!poses || !R || !R->lut) {
		free(poses);
		if (R)
			cal_free(R);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = R;
	R->paths = env->paths;
	R->n_files = env->n_caps;
	for (size_t j = 0; j < env->n_caps && !rc; j++)
		rc = cap_poses(co, o, env->caps[j], env->paths[j], true, poses,
			       &np);
	if (rc)
		goto done;
	rc = sscope_inclino_build(poses, np, o->gravity, o->node_gap, R->lut, &d);
	if (rc) {
		rc = ssc_fail(co->cmd, rc, &d, env->paths[0]);
		goto done;
	}
	rc = sscope_inclino_plan_new(&plan, R->lut, o->cubic, &d);
	if (rc) {
		rc = ssc_fail(co->cmd, rc, &d, env->paths[0]);
		goto done;
	}
	if (o->n_val) {
		np = 0;
		for (int j = 0; j < o->n_val && !rc; j++) {
			struct sscope_capture *cap = NULL;

			rc = ssc_load(co, o->validate[j], &cap);
			if (!rc)
				rc = cap_poses(co, o, cap, o->validate[j], false,
					       poses, &np);
			sscope_capture_free(cap);
		}
		if (rc)
			goto done;
		if (sscope_inclino_validate(plan, poses, np, &R->v)) {
			ssc_err(co->cmd, "%s: no validation pose within +-85 degrees of pitch",
				o->validate[0]);
			rc = SSC_EXIT_FAIL;
			goto done;
		}
		R->have_v = true;
		R->nv = R->v.poses;
		if (R->v.clamped)
			ssc_warn(co, "%zu validation poses outside the calibrated range %.1f .. %.1f degC (clamped)",
				 R->v.clamped, R->lut->temp_degc[0],
				 R->lut->temp_degc[R->lut->n - 1]);
	}
	if (R->have_v) {
		/* each validation pose's error, for the figure */
		R->err = malloc(np * sizeof(*R->err));
		R->raw = malloc(np * sizeof(*R->raw));
		if (R->err && R->raw &&
		    !sscope_inclino_pose_errors(plan, poses, np, R->err, R->raw)) {
			R->vposes = poses;
			poses = NULL;
			R->n_err = np;
		}
	}
done:
	sscope_inclino_plan_free(plan);
	free(poses);
	return rc;
}

static json_t *cal_json(const void *opts, const void *result)
{
	const struct cal_opts_s *o = opts;
	const struct incl_res *R = result;
	const struct sscope_inclino_validation *v = &R->v;
	json_t *root = json_object(), *f = json_array();

	json_object_set_new(root, "command", json_string("inclino calibrate"));
	json_object_set_new(root, "file", json_string(R->paths[0]));
	for (size_t j = 0; j < R->n_files; j++)
		json_array_append_new(f, json_string(R->paths[j]));
	json_object_set_new(root, "files", f);
	json_object_set_new(root, "lut", ssc_inclino_lut_json(R->lut, o->cubic));
	if (R->have_v) {
		json_t *jv = json_object();

		json_object_set_new(jv, "poses", json_integer((json_int_t)R->nv));
		json_object_set_new(jv, "max_deg", json_real(v->max_deg));
		json_object_set_new(jv, "rms_deg", json_real(v->rms_deg));
		json_object_set_new(jv, "uncompensated_max_deg", json_real(v->max_uncomp_deg));
		json_object_set_new(jv, "uncompensated_rms_deg", json_real(v->rms_uncomp_deg));
		json_object_set_new(jv, "class_deg", json_real(0.1));
		json_object_set_new(jv, "within_class", json_boolean(v->max_deg <= 0.1));
		json_object_set_new(jv, "offset_deg", ssc_jreal(v->offset_deg));
		json_object_set_new(jv, "scale_deg", ssc_jreal(v->scale_deg));
		json_object_set_new(jv, "misalignment_deg", ssc_jreal(v->mis_deg));
		json_object_set_new(jv, "dominant", v->dominant ? json_string(v->dominant) : json_null());
		json_object_set_new(jv, "clamped", json_integer((json_int_t)v->clamped));
		json_object_set_new(root, "validation", jv);
	}
	return root;
}

static void cal_text(FILE *f, const void *opts, const void *result)
{
	const struct cal_opts_s *o = opts;
	const struct incl_res *R = result;
	const struct sscope_inclino_lut *lut = R->lut;
	const struct sscope_inclino_validation *v = &R->v;

	fprintf(f, "inclino calibrate: %s%s: %zu temperature node%s, %s interpolation, clamped outside %.1f .. %.1f degC\n",
		R->paths[0], R->n_files > 1 ? " ..." : "", lut->n, lut->n == 1 ? "" : "s",
		o->cubic && lut->n >= 3 ? "cubic-spline" : "linear", lut->temp_degc[0],
		lut->temp_degc[lut->n - 1]);
	fprintf(f, "  %8s %4s %5s %10s %8s %10s %8s %9s %9s\n", "T degC", "axis", "poses",
		"offset mg", "sd", "scale %", "sd", "mis mrad", "(j, k)");
	for (size_t i = 0; i < lut->n; i++) {
		const struct sscope_inclino_params *p = &lut->p[i];
		double k = 1e3 / lut->gravity_m_s2;

		for (int a = 0; a < 3; a++) {
			int j = (a + 1) % 3, l = (a + 2) % 3;

			fprintf(f, "  %8.2f %4c %5zu %10.4f %8.4f %10.4f %8.4f %9.3f %9.3f\n",
				lut->temp_degc[i], "xyz"[a], p->poses, p->offset[a] * k,
				p->offset_sd[a] * k, (p->scale[a] - 1) * 100, p->scale_sd[a] * 100,
				p->mis[a][j] * 1e3, p->mis[a][l] * 1e3);
		}
	}
	if (R->have_v) {
		fprintf(f, "  validation (%zu poses): max %.4f deg, rms %.4f deg calibrated (0.1 deg class: %s); uncompensated max %.3f deg, rms %.3f deg\n",
			R->nv, v->max_deg, v->rms_deg, v->max_deg <= 0.1 ? "within" : "OUTSIDE",
			v->max_uncomp_deg, v->rms_uncomp_deg);
		if (v->dominant)
			fprintf(f, "  residual terms (as tilt error, AN-1057 equivalents): offset %.3g deg, scale %.3g deg, misalignment %.3g deg: %s dominates\n",
				v->offset_deg, v->scale_deg, v->mis_deg, v->dominant);
	}
}

static void cal_csv(FILE *f, const void *opts, const void *result)
{
	const struct incl_res *R = result;
	const struct sscope_inclino_lut *lut = R->lut;

	(void)opts;
	fprintf(f, "temp_degc,axis,offset_mg,offset_sd_mg,scale,scale_sd,mis_j_mrad,mis_k_mrad,residual_rms_mg,poses\n");
	for (size_t i = 0; i < lut->n; i++) {
		const struct sscope_inclino_params *p = &lut->p[i];
		double k = 1e3 / lut->gravity_m_s2;

		for (int a = 0; a < 3; a++) {
			int j = (a + 1) % 3, l = (a + 2) % 3;

			fprintf(f, "%.4f,%c,%.8g,%.4g,%.10g,%.4g,%.6g,%.6g,%.4g,%zu\n",
				lut->temp_degc[i], "xyz"[a], p->offset[a] * k, p->offset_sd[a] * k,
				p->scale[a], p->scale_sd[a], p->mis[a][j] * 1e3, p->mis[a][l] * 1e3,
				p->residual_rms * k, p->poses);
		}
	}
}

static void cal_summary(json_t *rows, const void *opts, const void *result)
{
	const struct incl_res *R = result;

	(void)opts;
	if (R->lut && R->lut->n) {
		/* the table itself: its nodes and its worst fit */
		const struct sscope_inclino_lut *lut = R->lut;
		double worst = 0, k = 1e3 / lut->gravity_m_s2;
		char note[96];

		for (size_t i = 0; i < lut->n; i++)
			worst = fmax(worst, lut->p[i].residual_rms * k);
		snprintf(note, sizeof(note), "%zu temperature node%s, %.4g to %.4g degC",
			 lut->n, lut->n == 1 ? "" : "s", lut->temp_degc[0],
			 lut->temp_degc[lut->n - 1]);
		ssc_summary_add(rows, NULL, "calibration fit residual (worst node, rms)",
				worst, NAN, NAN, "mg", note);
	}
	if (!R->have_v)
		return;
	ssc_summary_add(rows, NULL, "tilt error after calibration (max)", R->v.max_deg,
			NAN, NAN, "deg", "validation poses");
	ssc_summary_add(rows, NULL, "tilt error uncompensated (max)", R->v.max_uncomp_deg,
			NAN, NAN, "deg", "validation poses");
}

const struct ssc_stage_ops ssc_inclino_stage = {
	.spec = &cal_spec,
	.title = "Inclinometer calibration",
	.needs = SSC_NEED_DATA | SSC_NEED_TEMP,
	.min_files = 1,
	.max_files = -1,
	.opts_size = sizeof(struct cal_opts_s),
	.init = cal_init,
	.handle = cal_handler,
	.run = cal_run,
	.json = cal_json,
	.text = cal_text,
	.csv = cal_csv,
	.summary = cal_summary,
	.plot = cal_plot,
	.free_result = cal_free,
};

/* ------------------------------------------------------------------ */
/* apply                                                               */
/* ------------------------------------------------------------------ */

static const struct ssc_option app_opts[] = {
	{ "lut", required_argument, O_LUT, "LUT.json", "table written by 'inclino calibrate' (required)" },
	{ "accel", required_argument, O_ACCEL, "X,Y,Z",
	  "accelerometer channels (default: the first three acceleration columns)" },
	{ "gyro", required_argument, O_GYRO, "X,Y,Z",
	  "gyro channels for the still test (default: the first three angular-rate columns, if any)" },
	{ "no-gyro", no_argument, O_NOGYRO, NULL, "ignore gyro columns" },
	{ "still-tol", required_argument, O_STILLTOL, "A",
	  "still when ||a| - g| <= A (default 20 mg)" },
	{ "rate-tol", required_argument, O_RATETOL, "W",
	  "and, with gyro data, |w| <= W (default 0.5 deg/s)" },
	{ "cubic", no_argument, O_CUBIC, NULL, "cubic-spline interpolation (3+ nodes)" },
	{ "axes", required_argument, O_AXES, "1|2|3",
	  "tilt formula: 3 roll and pitch (default); 2 pitch = atan2(-ax, az); 1 pitch = asin(-ax/g), with the sensitivity column" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec app_spec = {
	.name = "inclino apply",
	.usage = "inclino apply --lut LUT.json [OPTIONS] FILE",
	.summary =
		"Roll and pitch (degrees) of every sample from raw accelerations corrected\n"
		"with the look-up table at the sample's temperature (clamped outside the\n"
		"table's range, with a warning), and a still flag: 1 when ||a| - g| is\n"
		"within --still-tol and, with gyro data, |w| within --rate-tol.  Angles\n"
		"during motion are written but flagged (still = 0), never silently valid.\n"
		"Output: CSV with time (when present), temp, roll_deg, pitch_deg, still.",
	.options = app_opts,
	.analysis = true,
	.notes = "Example:\n  sensorscope inclino apply --lut lut.json -o tilt.csv samples/inclino-val.csv",
};

struct app_opts_s {
	const char *lut, *accel, *gyro;
	bool no_gyro, cubic, rate_tol_set;
	double still_tol, rate_tol;
	int axes;
};

static int app_handler(int key, const char *arg, void *ctx)
{
	struct app_opts_s *o = ctx;

	switch (key) {
	case O_LUT:
		o->lut = arg;
		return 0;
	case O_ACCEL:
		o->accel = arg;
		return 0;
	case O_GYRO:
		o->gyro = arg;
		return 0;
	case O_NOGYRO:
		o->no_gyro = true;
		return 0;
	case O_CUBIC:
		o->cubic = true;
		return 0;
	case O_AXES:
		if (strcmp(arg, "1") && strcmp(arg, "2") && strcmp(arg, "3"))
			return ssc_usage_error("inclino apply", "--axes: '%s' is not 1, 2 or 3", arg);
		o->axes = arg[0] - '0';
		return 0;
	case O_STILLTOL:
		return ssc_arg_positive("inclino apply", "still-tol", arg, "m/s^2", &o->still_tol);
	case O_RATETOL:
		if (ssc_arg_quantity("inclino apply", "rate-tol", arg, "rad/s", &o->rate_tol))
			return SSC_EXIT_USAGE;
		if (!(o->rate_tol > 0))
			return ssc_usage_error("inclino apply", "--rate-tol: must be positive");
		o->rate_tol_set = true;
		return 0;
	}
	return SSC_EXIT_USAGE;
}

static int apply_main(int argc, char **argv)
{
	struct ssc_common co;
	struct app_opts_s o = { 0 };
	struct sscope_inclino_lut *lut = malloc(sizeof(*lut));
	struct sscope_inclino_plan *plan = NULL;
	struct sscope_capture *cap = NULL;
	struct sscope_diag d = { "" };
	struct ssc_out out = { 0 };
	long a[3], gi[3] = { -1, -1, -1 };
	struct sscope_inclino_apply_stats st = { 0, 0, 0 };
	int first, rc;
	double g;

	if (!lut)
		return SSC_EXIT_FAIL;
	o.still_tol = 20e-3 * SSCOPE_CALIB_GRAVITY_STD;
	o.axes = 3;
	o.rate_tol = 0.5 * PI / 180;
	rc = ssc_parse(&app_spec, argc, argv, &co, app_handler, &o, &first);
	if (rc) {
		free(lut);
		return rc < 0 ? SSC_EXIT_OK : rc;
	}
	co.cmd = "inclino apply";
	if (!o.lut) {
		free(lut);
		return ssc_usage_error(co.cmd, "--lut LUT.json is required");
	}
	if (argc - first != 1) {
		free(lut);
		return ssc_usage_error(co.cmd, "give one input file");
	}
	/* options that would be ignored */
	if (co.format == SSC_FMT_JSON || co.plot || (o.no_gyro && (o.gyro || o.rate_tol_set))) {
		free(lut);
		return ssc_usage_error(co.cmd, "%s",
				       co.format == SSC_FMT_JSON ? "--format json: apply writes a capture (CSV)" :
				       co.plot ? "--plot: no figure here (apply writes a capture)" :
						 "--no-gyro: and --gyro or --rate-tol?");
	}
	rc = ssc_inclino_lut_read(co.cmd, o.lut, lut);
	if (rc)
		goto done;
	g = lut->gravity_m_s2;
	if (sscope_inclino_plan_new(&plan, lut, o.cubic, &d)) {
		rc = ssc_fail(co.cmd, -EDOM, &d, o.lut);
		goto done;
	}
	rc = ssc_load(&co, argv[first], &cap);
	if (rc)
		goto done;
	if (!cap->temp_degc) {
		ssc_err(co.cmd, "%s: no temperature column (give --temp-column NAME)", argv[first]);
		rc = SSC_EXIT_FAIL;
		goto done;
	}
	rc = pick_accel(co.cmd, cap, o.accel, argv[first], a);
	if (rc)
		goto done;
	if (o.gyro && !o.no_gyro) {
		{
			char buf[256], *save = NULL, *tok;
			int k = 0;

			snprintf(buf, sizeof(buf), "%s", o.gyro);
			for (tok = strtok_r(buf, ",", &save); tok && k < 3; tok = strtok_r(NULL, ",", &save)) {
				gi[k] = sscope_capture_find(cap, tok);
				if (gi[k] < 0) {
					ssc_err(co.cmd, "%s: no column '%s'", argv[first], tok);
					rc = SSC_EXIT_FAIL;
					goto done;
				}
				k++;
			}
			if (k != 3) {
				rc = ssc_usage_error(co.cmd, "--gyro: give three channel names");
				goto done;
			}
		}
	} else if (!o.no_gyro) {
		size_t k = 0;

		for (size_t i = 0; i < cap->n_channels && k < 3; i++)
			if (cap->channels[i].col.quantity == SSCOPE_QUANTITY_ANGULAR_RATE)
				gi[k++] = (long)i;
		if (k < 3)
			gi[0] = -1;
	}
	co.format = SSC_FMT_CSV;
	rc = ssc_out_open(&co, &out);
	if (rc)
		goto done;
	fprintf(out.f, "# sensorscope inclino apply: %s with %s (%s interpolation); still: ||a| - g| <= %.4g m/s^2%s\n",
		argv[first], o.lut, o.cubic && lut->n >= 3 ? "cubic" : "linear", o.still_tol,
		gi[0] >= 0 ? " and |w| <= rate-tol" : " (no gyro data)");
	if (o.axes != 3)
		fprintf(out.f, "# %d-axis: %s; sens = d(reading)/d(pitch) in mg per degree (17.45 cos(pitch) for 1 axis); the LUT correction uses all three axes\n",
			o.axes, o.axes == 1 ? "pitch = asin(-ax/g)" : "pitch = atan2(-ax, az), x-z plane, full circle");
	fprintf(out.f, "%stemp [degC],%s,still\n", cap->time_s ? "time [s]," : "",
		o.axes == 3 ? "roll_deg,pitch_deg" : "pitch_deg,sens [mg/deg]");
	{
		const double *ac[3], *w[3];
		double *r = malloc(cap->n * sizeof(double)),
		       *p = malloc(cap->n * sizeof(double)),
		       *sens = malloc(cap->n * sizeof(double));
		bool *still = malloc(cap->n * sizeof(bool));

		for (int k = 0; k < 3; k++) {
			ac[k] = cap->channels[a[k]].data;
			w[k] = gi[0] >= 0 ? cap->channels[gi[k]].data : NULL;
		}
		if (!r || !p || !sens || !still ||
		    sscope_inclino_apply(plan, (enum sscope_inclino_axes)o.axes, g, ac,
					 cap->temp_degc, gi[0] >= 0 ? w : NULL, cap->n,
					 o.still_tol, o.rate_tol, r, p, sens, still,
					 &st)) {
			free(r);
			free(p);
			free(sens);
			free(still);
			ssc_out_close(&co, &out, false);
			ssc_err(co.cmd, "out of memory");
			rc = SSC_EXIT_FAIL;
			goto done;
		}
		for (size_t i = 0; i < cap->n; i++) {
			double T = cap->temp_degc[i];

			if (cap->time_s)
				fprintf(out.f, "%.9g,", cap->time_s[i]);
			if (o.axes == 3)
				fprintf(out.f, "%.6g,%.6f,%.6f,%d\n", T, r[i] * R2D,
					p[i] * R2D, still[i] ? 1 : 0);
			else
				fprintf(out.f, "%.6g,%.6f,%.4f,%d\n", T, p[i] * R2D,
					sens[i] / R2D / (1e-3 * g), still[i] ? 1 : 0);
		}
		free(r);
		free(p);
		free(sens);
		free(still);
	}
	rc = ssc_out_close(&co, &out, !ferror(out.f));
	if (rc)
		goto done;
	if (st.n_clamped)
		ssc_warn(&co, "%zu samples outside the table's range %.1f .. %.1f degC: parameters clamped",
			 st.n_clamped, lut->temp_degc[0], lut->temp_degc[lut->n - 1]);
	if (!co.quiet)
		fprintf(stderr, "sensorscope: inclino apply: %zu samples, %zu still, %zu flagged moving, %zu without a value\n",
			cap->n, st.n_still, cap->n - st.n_still - st.n_bad, st.n_bad);
done:
	sscope_capture_free(cap);
	sscope_inclino_plan_free(plan);
	free(lut);
	return rc;
}

int ssc_cmd_inclino(int argc, char **argv)
{
	if (argc >= 2 && !strcmp(argv[1], "calibrate")) {
		char *args[256];
		int n = 0;
		bool fmt = false, json_out = false;

		if (argc + 2 > 256)
			return ssc_usage_error("inclino", "too many arguments");
		for (int i = 2; i < argc; i++) {
			if (!strcmp(argv[i], "--format") || !strncmp(argv[i], "--format=", 9))
				fmt = true;
			if ((!strcmp(argv[i], "-o") || !strcmp(argv[i], "--output")) && i + 1 < argc) {
				size_t l = strlen(argv[i + 1]);

				json_out = l > 5 && !strcmp(argv[i + 1] + l - 5, ".json");
			}
		}
		args[n++] = argv[0];
		if (json_out && !fmt) {
			/* -o LUT.json: the LUT */
			args[n++] = "--format";
			args[n++] = "json";
		}
		for (int i = 2; i < argc; i++)
			args[n++] = argv[i];
		return ssc_stage_main(&ssc_inclino_stage, n, args);
	}
	if (argc >= 2 && !strcmp(argv[1], "apply"))
		return apply_main(argc - 1, argv + 1);
	if (argc >= 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
		printf("Usage: sensorscope inclino calibrate [OPTIONS] FILE... -o LUT.json\n"
		       "       sensorscope inclino apply --lut LUT.json [OPTIONS] FILE\n"
		       "Inclinometer look-up-table calibration against temperature, and tilt\n"
		       "with a still flag.  'sensorscope inclino calibrate --help' and\n"
		       "'sensorscope inclino apply --help' list the options.\n\n"
		       "Exit status: 0 success, 1 runtime or data error, 2 usage error or feature not built.\n");
		return SSC_EXIT_OK;
	}
	return ssc_usage_error("inclino", "give 'calibrate' or 'apply' first");
}
