/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * A lot split over machines (lot.h): --plan-jobs ENGINE DIR writes
 * DIR/plan.json (every unit's file with its SHA-256, how to read it, the
 * options that change a unit's analysis) and the engine's file (a Slurm
 * job-array script, or a GNU parallel command file); each task runs
 * `sensorscope lot --job DIR:I`, which analyses unit I as `lot` does and
 * writes DIR/unit-I.json (every number with 17 digits: read back
 * exactly); --merge DIR reads them all and makes the lot, equal to the
 * run of `lot` on one machine.  A result of another plan, or of an input
 * that changed since the plan, is refused.
 */
#include "workbench.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "html.h"
#include "lot.h"

#define PLAN_KIND "sensorscope lot plan"
#define UNIT_KIND "sensorscope lot unit"

/* ------------------------------------------------- numbers, exactly */

/* a double as JSON: 17 digits at dump time; NaN null, +-inf strings */
static json_t *num(double v)
{
	if (isfinite(v))
		return json_real(v);
	return isnan(v) ? json_null() : json_string(v > 0 ? "inf" : "-inf");
}

static double get_num(const json_t *j)
{
	const char *s = json_string_value(j);

	if (json_is_number(j))
		return json_number_value(j);
	if (s && !strcmp(s, "inf"))
		return INFINITY;
	if (s && !strcmp(s, "-inf"))
		return -INFINITY;
	return NAN;
}

static json_t *nums(const double *v, size_t n)
{
	json_t *a = json_array();

	for (size_t i = 0; i < n; i++)
		json_array_append_new(a, num(v[i]));
	return a;
}

/* the array key of o into v[0..n): false unless it has n entries */
static bool get_nums(const json_t *o, const char *key, double *v, size_t n)
{
	const json_t *a = json_object_get(o, key);

	if (!json_is_array(a) || json_array_size(a) != n)
		return false;
	for (size_t i = 0; i < n; i++)
		v[i] = get_num(json_array_get(a, i));
	return true;
}

static const char *get_str(const json_t *o, const char *key)
{
	return json_string_value(json_object_get(o, key));
}

static int write_json(const char *cmd, const char *path, json_t *j)
{
	struct ssc_out at;
	int rc;

	if (!j)
		return ssc_fail(cmd, -ENOMEM, NULL, NULL);
	rc = ssc_file_open(cmd, path, &at);
	if (!rc) {
		bool ok = json_dumpf(j, at.f, JSON_INDENT(1) | JSON_REAL_PRECISION(17)) == 0;

		fputc('\n', at.f);
		rc = ssc_file_close(&at, ok);
	}
	json_decref(j);
	return rc;
}

static json_t *read_json(const char *cmd, const char *path, const char *kind,
			 int *rc)
{
	json_t *j = ssc_json_read(cmd, NULL, path, "a file of 'sensorscope lot'");

	*rc = 0;
	if (!j) {
		*rc = SSC_EXIT_FAIL;
		return NULL;
	}
	if (!get_str(j, "kind") || strcmp(get_str(j, "kind"), kind)) {
		ssc_err(cmd, "%s: not a %s file", path, kind);
		json_decref(j);
		*rc = SSC_EXIT_FAIL;
		return NULL;
	}
	return j;
}

/* --------------------------------------------------------- the plan */

static json_t *opt_str(const char *s)
{
	return s ? json_string(s) : json_null();
}

int ssc_lot_plan_jobs(const struct ssc_stage_env *env, const char *engine,
		      const char *dir, double level, const char *spec,
		      double smooth_s, char *note, size_t len)
{
	const struct ssc_common *co = env->co;
	const char *cmd = co->cmd;
	json_t *plan = json_object(), *units = json_array(), *rd = json_object();
	char id[65], hex[65], self[PATH_MAX], seed[128], *path = NULL;
	struct stat st;
	ssize_t sl;
	int rc = 0;
	FILE *f;

	if (stat(dir, &st) == 0) {
		ssc_err(cmd, "--plan-jobs: %s exists: give a new folder (nothing in it is overwritten)",
			dir);
		json_decref(plan);
		json_decref(units);
		json_decref(rd);
		return SSC_EXIT_FAIL;
	}
	if (mkdir(dir, 0777)) {
		ssc_err(cmd, "--plan-jobs: %s: %s", dir, sscope_strerror(errno));
		json_decref(plan);
		json_decref(units);
		json_decref(rd);
		return SSC_EXIT_FAIL;
	}
	sl = readlink("/proc/self/exe", self, sizeof(self) - 1);
	self[sl > 0 ? sl : 0] = 0;
	if (sl <= 0)
		snprintf(self, sizeof(self), "sensorscope");
	for (size_t i = 0; i < env->n_caps && !rc; i++) {
		json_t *u = json_object();
		char *abs = realpath(env->paths[i], NULL);

		if (!abs || ssc_sha256_file(abs, hex)) {
			ssc_err(cmd, "%s: %s", env->paths[i], sscope_strerror(errno ? errno : EIO));
			free(abs);
			json_decref(u);
			rc = SSC_EXIT_FAIL;
			break;
		}
		json_object_set_new(u, "path", json_string(env->paths[i]));
		json_object_set_new(u, "file", json_string(abs));
		json_object_set_new(u, "sha256", json_string(hex));
		json_object_set_new(u, "label", opt_str(env->labels ? env->labels[i] : NULL));
		json_object_set_new(u, "columns",
				    opt_str(env->unit_columns ? env->unit_columns[i] : NULL));
		json_object_set_new(u, "temperature",
				    opt_str(env->unit_temps ? env->unit_temps[i] : NULL));
		json_array_append_new(units, u);
		free(abs);
	}
	/* how every unit is read: the command's reading options */
	json_object_set_new(rd, "columns", opt_str(co->columns));
	json_object_set_new(rd, "rate_hz", num(co->rate_hz));
	json_object_set_new(rd, "units", opt_str(co->units));
	json_object_set_new(rd, "raw", opt_str(co->raw));
	json_object_set_new(rd, "scale", num(co->scale));
	json_object_set_new(rd, "offset", num(co->offset));
	json_object_set_new(rd, "allow_nan", json_boolean(co->allow_nan));
	json_object_set_new(rd, "time_column", opt_str(co->time_column));
	json_object_set_new(rd, "temp_column", opt_str(co->temp_column));
	json_object_set_new(rd, "calibration", opt_str(co->calibration));
	json_object_set_new(rd, "topic", opt_str(co->topic));
	/* the plan's identity: its time, process and first input */
	snprintf(seed, sizeof(seed), "%ld.%ld %d %s", (long)time(NULL),
		 (long)clock(), (int)getpid(), env->n_caps ? env->paths[0] : "");
	{
		char *sp = ssc_path_join(dir, ".id");

		if (!sp || ssc_file_put(sp, seed, strlen(seed)) || ssc_sha256_file(sp, id))
			snprintf(id, sizeof(id), "%s", seed);
		if (sp)
			unlink(sp);
		free(sp);
	}
	json_object_set_new(plan, "kind", json_string(PLAN_KIND));
	json_object_set_new(plan, "version", json_string(PACKAGE_VERSION));
	json_object_set_new(plan, "id", json_string(id));
	json_object_set_new(plan, "level", num(level));
	json_object_set_new(plan, "smooth_s", num(smooth_s));
	json_object_set_new(plan, "spec", opt_str(spec));
	if (spec && !rc) {
		char *abs = realpath(spec, NULL);

		if (!abs || ssc_sha256_file(abs, hex)) {
			ssc_err(cmd, "--spec: %s: %s", spec, sscope_strerror(errno ? errno : EIO));
			rc = SSC_EXIT_FAIL;
		} else {
			json_object_set_new(plan, "spec_file", json_string(abs));
			json_object_set_new(plan, "spec_sha256", json_string(hex));
		}
		free(abs);
	}
	json_object_set_new(plan, "read", rd);
	json_object_set_new(plan, "units", units);
	if (rc) {
		json_decref(plan);
		return rc;
	}
	path = ssc_path_join(dir, "plan.json");
	rc = path ? write_json(cmd, path, plan) : ssc_fail(cmd, -ENOMEM, NULL, NULL);
	free(path);
	if (rc)
		return rc;
	/* the engine's file */
	{
		char *adir = realpath(dir, NULL);
		bool slurm = !strcmp(engine, "slurm");

		path = ssc_path_join(dir, slurm ? "lot.sbatch" : "jobs.txt");
		if (!adir || !path) {
			free(adir);
			free(path);
			return ssc_fail(cmd, -ENOMEM, NULL, NULL);
		}
		f = fopen(path, "w");
		if (!f) {
			ssc_err(cmd, "--plan-jobs: %s: %s", path, sscope_strerror(errno));
			free(adir);
			free(path);
			return SSC_EXIT_FAIL;
		}
		if (slurm)
			fprintf(f, "#!/bin/sh\n"
				"# sensorscope lot: one unit per task of a Slurm job array.\n"
				"# Submit:  sbatch %s\n"
				"# Then:    sensorscope lot --merge %s\n"
				"#SBATCH --job-name=sensorscope-lot\n"
				"#SBATCH --array=0-%zu\n"
				"#SBATCH --cpus-per-task=2\n"
				"#SBATCH --output=%s/unit-%%a.log\n"
				"exec '%s' lot --job '%s':\"$SLURM_ARRAY_TASK_ID\"\n",
				path, adir, env->n_caps - 1, adir, self, adir);
		else
			for (size_t i = 0; i < env->n_caps; i++)
				fprintf(f, "'%s' lot --job '%s:%zu'\n", self, adir, i);
		if (fclose(f)) {
			ssc_err(cmd, "--plan-jobs: %s: %s", path, sscope_strerror(errno));
			rc = SSC_EXIT_FAIL;
		}
		if (!rc && slurm)
			chmod(path, 0755);
		if (!rc)
			snprintf(note, len, "%zu units planned in %s: run %s %s, then sensorscope lot --merge %s",
				 env->n_caps, dir, slurm ? "sbatch" : "parallel <",
				 path, dir);
		free(adir);
		free(path);
	}
	return rc;
}

/* ----------------------------------------------------- a unit's task */

static const char *const bias_keys[] = {
	"level", "bias", "bias_se", "bias_lo", "bias_hi", "drift_u_s", "drift_se",
	"drift_lo", "drift_hi", "tempco_u_degc", "tempco_se", "tempco_lo",
	"tempco_hi", "temp_mean_degc", "temp_span_degc", "temp_time_corr",
	"resid_lag1", "drift_se_resid", "drift_se_model", "tempco_se_resid",
	"tempco_se_model", "drift_se_upper", "drift_upper_lo", "drift_upper_hi",
	"tempco_se_upper", "tempco_upper_lo", "tempco_upper_hi"
};

static double *bias_field(struct sscope_lot_bias *b, size_t k)
{
	double *f[] = {
		&b->level, &b->bias, &b->bias_se, &b->bias_lo, &b->bias_hi,
		&b->drift_u_s, &b->drift_se, &b->drift_lo, &b->drift_hi,
		&b->tempco_u_degc, &b->tempco_se, &b->tempco_lo, &b->tempco_hi,
		&b->temp_mean_degc, &b->temp_span_degc, &b->temp_time_corr,
		&b->resid_lag1, &b->drift_se_resid, &b->drift_se_model,
		&b->tempco_se_resid, &b->tempco_se_model, &b->drift_se_upper,
		&b->drift_upper_lo, &b->drift_upper_hi, &b->tempco_se_upper,
		&b->tempco_upper_lo, &b->tempco_upper_hi
	};

	return f[k];
}

static json_t *cell_json(const struct ssc_lot_result *r, size_t c,
			 const struct ssc_lot_cell *cl)
{
	json_t *o = json_object(), *pr = json_array(), *gb = json_array();
	json_t *b = json_object();
	struct sscope_lot_bias bias = cl->bias;

	json_object_set_new(o, "name", json_string(r->chan[c]));
	json_object_set_new(o, "quantity", json_integer(r->q[c]));
	json_object_set_new(o, "v", nums(cl->v, SSC_LOT_NT));
	json_object_set_new(o, "lo", nums(cl->lo, SSC_LOT_NT));
	json_object_set_new(o, "hi", nums(cl->hi, SSC_LOT_NT));
	json_object_set_new(o, "se", nums(cl->se, SSC_LOT_NT));
	for (size_t t = 0; t < SSC_LOT_NT; t++)
		json_array_append_new(pr, json_boolean(cl->present[t]));
	json_object_set_new(o, "present", pr);
	json_object_set_new(o, "constant", json_boolean(cl->constant));
	for (size_t t = 0; t < SSC_LOT_NT; t++)
		json_array_append_new(gb, json_boolean(cl->gbound[t]));
	json_object_set_new(o, "guard_bound", gb);
	json_object_set_new(o, "guard_lo", nums(cl->glo, SSC_LOT_NT));
	json_object_set_new(o, "guard_hi", nums(cl->ghi, SSC_LOT_NT));
	json_object_set_new(o, "noise_model", nums(cl->model, 3));
	json_object_set_new(b, "blocks", json_integer((json_int_t)bias.blocks));
	json_object_set_new(b, "block_n", json_integer((json_int_t)bias.block_n));
	json_object_set_new(b, "have_temp", json_boolean(bias.have_temp));
	json_object_set_new(b, "resid_correlated", json_boolean(bias.resid_correlated));
	json_object_set_new(b, "drift_se_from_model", json_boolean(bias.drift_se_from_model));
	json_object_set_new(b, "tempco_se_from_model", json_boolean(bias.tempco_se_from_model));
	for (size_t k = 0; k < sizeof(bias_keys) / sizeof(*bias_keys); k++)
		json_object_set_new(b, bias_keys[k], num(*bias_field(&bias, k)));
	json_object_set_new(o, "bias", b);
	json_object_set_new(o, "tau_s", nums(cl->tau_s, cl->n_adev));
	json_object_set_new(o, "adev", nums(cl->adev, cl->n_adev));
	json_object_set_new(o, "fig_mean", num(cl->fig_mean));
	json_object_set_new(o, "fig_block", json_integer((json_int_t)cl->fig_block));
	json_object_set_new(o, "fig_cs", nums(cl->fig_cs, cl->fig_k + 1));
	return o;
}

/* "DIR:I" */
static int job_of(const char *cmd, const char *arg, char **dir, size_t *i)
{
	const char *colon = strrchr(arg, ':');
	char *end;
	unsigned long long v;

	if (!colon || colon == arg || !colon[1])
		return ssc_usage_error(cmd, "--job: '%s' is not PLAN_FOLDER:INDEX", arg);
	errno = 0;
	v = strtoull(colon + 1, &end, 10);
	if (errno || *end || colon[1] == '-')
		return ssc_usage_error(cmd, "--job: '%s' is not a task index (0, 1, ...)",
				       colon + 1);
	*dir = strndup(arg, (size_t)(colon - arg));
	*i = (size_t)v;
	return *dir ? 0 : ssc_fail(cmd, -ENOMEM, NULL, NULL);
}

/* the plan's reading options into co (strings point into plan) */
static void plan_read(const json_t *plan, struct ssc_common *co)
{
	const json_t *rd = json_object_get(plan, "read");

	co->columns = get_str(rd, "columns");
	co->rate_hz = isfinite(get_num(json_object_get(rd, "rate_hz"))) ?
		      get_num(json_object_get(rd, "rate_hz")) : 0;
	co->units = get_str(rd, "units");
	co->raw = get_str(rd, "raw");
	co->scale = get_num(json_object_get(rd, "scale"));
	co->offset = get_num(json_object_get(rd, "offset"));
	co->allow_nan = json_is_true(json_object_get(rd, "allow_nan"));
	co->time_column = get_str(rd, "time_column");
	co->temp_column = get_str(rd, "temp_column");
	co->calibration = get_str(rd, "calibration");
	co->topic = get_str(rd, "topic");
}

int ssc_lot_job(const struct ssc_common *co0, const char *arg, char *note,
		size_t len)
{
	const char *cmd = co0->cmd;
	struct ssc_common co = *co0;
	struct ssc_lot_result *r = NULL;
	struct sscope_capture *cap = NULL;
	json_t *plan = NULL, *u, *out, *chans;
	char *dir = NULL, *path = NULL, hex[65], name[32];
	const char *file, *label;
	size_t i = 0;
	int rc = job_of(cmd, arg, &dir, &i);

	if (rc)
		return rc;
	path = ssc_path_join(dir, "plan.json");
	plan = path ? read_json(cmd, path, PLAN_KIND, &rc) : NULL;
	if (!plan) {
		rc = rc ? rc : ssc_fail(cmd, -ENOMEM, NULL, NULL);
		goto out;
	}
	u = json_array_get(json_object_get(plan, "units"), i);
	if (!u) {
		ssc_err(cmd, "--job: %s plans %zu units: no task %zu", path,
			json_array_size(json_object_get(plan, "units")), i);
		rc = SSC_EXIT_FAIL;
		goto out;
	}
	file = get_str(u, "file");
	label = get_str(u, "label");
	if (!file || ssc_sha256_file(file, hex)) {
		ssc_err(cmd, "--job: unit %zu: %s: %s", i, file ? file : "(no file)",
			sscope_strerror(errno ? errno : EIO));
		rc = SSC_EXIT_FAIL;
		goto out;
	}
	if (strcmp(hex, get_str(u, "sha256") ? get_str(u, "sha256") : "")) {
		ssc_err(cmd, "--job: unit %zu: %s changed since the plan (its SHA-256 differs): plan again",
			i, file);
		rc = SSC_EXIT_FAIL;
		goto out;
	}
	plan_read(plan, &co);
	if (get_str(u, "columns"))
		co.columns = get_str(u, "columns");
	if (get_str(u, "temperature"))
		co.temp_column = get_str(u, "temperature");
	rc = ssc_load(&co, file, &cap);
	if (rc)
		goto out;
	r = ssc_lot_new(cmd, 1, &file, label ? &label : NULL,
			get_num(json_object_get(plan, "level")),
			get_str(plan, "spec_file"), 0, &rc);
	if (!r)
		goto out;
	rc = ssc_lot_unit(cmd, r, 0, cap, NULL);
	if (rc)
		goto out;
	out = json_object();
	json_object_set_new(out, "kind", json_string(UNIT_KIND));
	json_object_set_new(out, "version", json_string(PACKAGE_VERSION));
	json_object_set_new(out, "plan", json_string(get_str(plan, "id")));
	json_object_set_new(out, "index", json_integer((json_int_t)i));
	json_object_set_new(out, "file", json_string(file));
	json_object_set_new(out, "sha256", json_string(hex));
	json_object_set_new(out, "rate_hz", num(r->rate_hz[0]));
	json_object_set_new(out, "samples", json_integer((json_int_t)r->n_samples[0]));
	json_object_set_new(out, "temperature", json_boolean(r->temp));
	chans = json_array();
	for (size_t c = 0; c < r->n_chan; c++)
		json_array_append_new(chans, cell_json(r, c, &r->cell[c]));
	json_object_set_new(out, "channels", chans);
	free(path);
	snprintf(name, sizeof(name), "unit-%zu.json", i);
	path = ssc_path_join(dir, name);
	rc = path ? write_json(cmd, path, out) : ssc_fail(cmd, -ENOMEM, NULL, NULL);
	if (!rc)
		snprintf(note, len, "unit %zu (%s) analysed: %s", i, file, path);
out:
	ssc_lot_free(r);
	sscope_capture_free(cap);
	json_decref(plan);
	free(path);
	free(dir);
	return rc;
}

/* ------------------------------------------------------------ merge */

static int cell_from(const char *cmd, const char *path, const json_t *o,
		     struct ssc_lot_cell *cl)
{
	const json_t *b = json_object_get(o, "bias"), *pr = json_object_get(o, "present");
	const json_t *gb = json_object_get(o, "guard_bound");
	const json_t *cs = json_object_get(o, "fig_cs");
	size_t na = json_array_size(json_object_get(o, "tau_s"));
	size_t nk = json_array_size(cs);
	bool ok = json_is_object(b) && json_array_size(pr) == SSC_LOT_NT &&
		  json_array_size(gb) == SSC_LOT_NT && nk >= 2 &&
		  get_nums(o, "v", cl->v, SSC_LOT_NT) &&
		  get_nums(o, "lo", cl->lo, SSC_LOT_NT) &&
		  get_nums(o, "hi", cl->hi, SSC_LOT_NT) &&
		  get_nums(o, "se", cl->se, SSC_LOT_NT) &&
		  get_nums(o, "guard_lo", cl->glo, SSC_LOT_NT) &&
		  get_nums(o, "guard_hi", cl->ghi, SSC_LOT_NT) &&
		  get_nums(o, "noise_model", cl->model, 3);

	if (ok) {
		cl->tau_s = malloc((na + 1) * sizeof(double));
		cl->adev = malloc((na + 1) * sizeof(double));
		cl->fig_cs = malloc(nk * sizeof(double));
		if (!cl->tau_s || !cl->adev || !cl->fig_cs)
			return ssc_fail(cmd, -ENOMEM, NULL, NULL);
		ok = get_nums(o, "tau_s", cl->tau_s, na) &&
		     get_nums(o, "adev", cl->adev, na) &&
		     get_nums(o, "fig_cs", cl->fig_cs, nk);
		cl->n_adev = na;
		cl->fig_k = nk - 1;
	}
	for (size_t t = 0; ok && t < SSC_LOT_NT; t++)
		cl->present[t] = json_is_true(json_array_get(pr, t));
	cl->constant = json_is_true(json_object_get(o, "constant"));
	for (size_t t = 0; ok && t < SSC_LOT_NT; t++)
		cl->gbound[t] = json_is_true(json_array_get(gb, t));
	if (ok) {
		cl->bias.blocks = (size_t)json_integer_value(json_object_get(b, "blocks"));
		cl->bias.block_n = (size_t)json_integer_value(json_object_get(b, "block_n"));
		cl->bias.have_temp = json_is_true(json_object_get(b, "have_temp"));
		cl->bias.resid_correlated = json_is_true(json_object_get(b, "resid_correlated"));
		cl->bias.drift_se_from_model = json_is_true(json_object_get(b, "drift_se_from_model"));
		cl->bias.tempco_se_from_model = json_is_true(json_object_get(b, "tempco_se_from_model"));
		for (size_t k = 0; k < sizeof(bias_keys) / sizeof(*bias_keys); k++)
			*bias_field(&cl->bias, k) = get_num(json_object_get(b, bias_keys[k]));
		cl->fig_mean = get_num(json_object_get(o, "fig_mean"));
		cl->fig_block = (size_t)json_integer_value(json_object_get(o, "fig_block"));
		ok = cl->fig_block > 0;
	}
	if (!ok) {
		ssc_err(cmd, "%s: channel %s: a field is missing or malformed", path,
			get_str(o, "name") ? get_str(o, "name") : "?");
		return SSC_EXIT_FAIL;
	}
	return 0;
}

int ssc_lot_merge(const struct ssc_common *co, const char *dir,
		  struct ssc_lot_result **out)
{
	struct ssc_lot_merged *m = calloc(1, sizeof(*m));
	const char *cmd = co->cmd;
	char *path = ssc_path_join(dir, "plan.json"), name[32], hex[65];
	json_t *plan, *units, **res = NULL;
	struct ssc_lot_result *r = NULL;
	size_t n;
	int rc;

	*out = NULL;
	if (!m) {
		free(path);
		return ssc_fail(cmd, -ENOMEM, NULL, NULL);
	}
	plan = path ? read_json(cmd, path, PLAN_KIND, &rc) : NULL;
	free(path);
	if (!plan) {
		free(m);
		return rc ? rc : ssc_fail(cmd, -ENOMEM, NULL, NULL);
	}
	m->plan = plan;
	units = json_object_get(plan, "units");
	n = json_array_size(units);
	if (n < 3) {
		ssc_err(cmd, "--merge: %s: the plan has %zu units; a lot needs at least 3", dir, n);
		rc = SSC_EXIT_FAIL;
		goto fail;
	}
	m->paths = calloc(n, sizeof(*m->paths));
	m->labels = calloc(n, sizeof(*m->labels));
	res = calloc(n, sizeof(*res));
	if (!m->paths || !m->labels || !res) {
		free(res);
		rc = ssc_fail(cmd, -ENOMEM, NULL, NULL);
		goto fail;
	}
	m->units = res;
	m->n = n;
	for (size_t i = 0; i < n; i++) {
		const json_t *u = json_array_get(units, i);

		m->paths[i] = get_str(u, "path");
		m->labels[i] = get_str(u, "label");
		snprintf(name, sizeof(name), "unit-%zu.json", i);
		path = ssc_path_join(dir, name);
		if (!path) {
			rc = ssc_fail(cmd, -ENOMEM, NULL, NULL);
			goto fail;
		}
		if (access(path, F_OK)) {
			ssc_err(cmd, "--merge: %s is missing: task %zu (%s) has not run, or failed (see its log)",
				path, i, m->paths[i]);
			free(path);
			rc = SSC_EXIT_FAIL;
		goto fail;
		}
		res[i] = read_json(cmd, path, UNIT_KIND, &rc);
		if (!res[i]) {
			free(path);
			goto fail;
		}
		if (!get_str(res[i], "plan") || strcmp(get_str(res[i], "plan"), get_str(plan, "id")) ||
		    json_integer_value(json_object_get(res[i], "index")) != (json_int_t)i) {
			ssc_err(cmd, "--merge: %s is the result of another plan (or task): results of different plans cannot be merged; run task %zu again",
				path, i);
			free(path);
			rc = SSC_EXIT_FAIL;
		goto fail;
		}
		if (strcmp(get_str(res[i], "sha256") ? get_str(res[i], "sha256") : "",
			   get_str(u, "sha256") ? get_str(u, "sha256") : "") ||
		    (get_str(u, "file") && !access(get_str(u, "file"), F_OK) &&
		     (ssc_sha256_file(get_str(u, "file"), hex) ||
		      strcmp(hex, get_str(u, "sha256"))))) {
			ssc_err(cmd, "--merge: %s: its input %s is not the file of the plan (SHA-256 differs): stale, plan again",
				path, get_str(u, "file"));
			free(path);
			rc = SSC_EXIT_FAIL;
		goto fail;
		}
		free(path);
	}
	if (get_str(plan, "spec_file") &&
	    (ssc_sha256_file(get_str(plan, "spec_file"), hex) ||
	     strcmp(hex, get_str(plan, "spec_sha256") ? get_str(plan, "spec_sha256") : ""))) {
		ssc_err(cmd, "--merge: the limits file %s changed or went since the plan: plan again",
			get_str(plan, "spec_file"));
		rc = SSC_EXIT_FAIL;
		goto fail;
	}
	r = ssc_lot_new(cmd, n, m->paths, m->labels, get_num(json_object_get(plan, "level")),
			get_str(plan, "spec") && !access(get_str(plan, "spec"), R_OK) ?
				get_str(plan, "spec") : get_str(plan, "spec_file"),
			isfinite(get_num(json_object_get(plan, "smooth_s"))) ?
				get_num(json_object_get(plan, "smooth_s")) : 0, &rc);
	if (!r)
		goto fail;
	/* the first unit's channels, as the lot on one machine takes them */
	{
		const json_t *ch = json_object_get(res[0], "channels");
		size_t nc = json_array_size(ch);
		const char **names = calloc(nc + 1, sizeof(*names));
		enum sscope_quantity *q = calloc(nc + 1, sizeof(*q));

		if (!names || !q)
			rc = ssc_fail(cmd, -ENOMEM, NULL, NULL);
		for (size_t c = 0; !rc && c < nc; c++) {
			names[c] = get_str(json_array_get(ch, c), "name");
			q[c] = (enum sscope_quantity)json_integer_value(
				json_object_get(json_array_get(ch, c), "quantity"));
			if (!names[c])
				names[c] = "?";
		}
		if (!rc)
			rc = ssc_lot_set_channels(cmd, r,
						  json_is_true(json_object_get(res[0], "temperature")),
						  names, q, nc);
		free(names);
		free(q);
	}
	for (size_t u = 0; u < n && !rc; u++) {
		const json_t *ch = json_object_get(res[u], "channels");

		if (json_is_true(json_object_get(res[u], "temperature")) != r->temp) {
			ssc_err(cmd, "%s: %s temperature column, but %s %s: the units of a lot must have the same columns",
				m->paths[u], r->temp ? "no" : "a", m->paths[0],
				r->temp ? "has one" : "has none");
			rc = SSC_EXIT_FAIL;
			break;
		}
		r->rate_hz[u] = get_num(json_object_get(res[u], "rate_hz"));
		r->n_samples[u] = (size_t)json_integer_value(json_object_get(res[u], "samples"));
		for (size_t c = 0; c < r->n_chan && !rc; c++) {
			const json_t *o = NULL;

			for (size_t k = 0; k < json_array_size(ch); k++) {
				const json_t *x = json_array_get(ch, k);

				if (get_str(x, "name") && !strcmp(get_str(x, "name"), r->chan[c]) &&
				    json_integer_value(json_object_get(x, "quantity")) == (json_int_t)r->q[c])
					o = x;
			}
			if (!o) {
				ssc_err(cmd, "%s: no channel '%s' of the same quantity as in %s: the units of a lot must have the same channels",
					m->paths[u], r->chan[c], m->paths[0]);
				rc = SSC_EXIT_FAIL;
				break;
			}
			rc = cell_from(cmd, m->paths[u], o, &r->cell[u * r->n_chan + c]);
		}
	}
	if (!rc)
		rc = ssc_lot_finish(cmd, r);
	if (rc)
		goto fail;
	r->merged = m;
	*out = r;
	return 0;
fail:
	ssc_lot_free(r);
	ssc_lot_merged_free(m);
	free(m);
	return rc;
}
