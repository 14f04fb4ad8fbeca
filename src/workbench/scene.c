/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Scene runner (see scene.h).  The stage graph is a fixed table: each stage
 * names the inputs it needs (data channels, temperature, a sensor or ADC
 * specification) and the stages whose results it may consume.  A scene's
 * sections say which stages are wanted; the runner adds what they consume,
 * refuses impossible requests (a stage whose inputs are missing) with the
 * reason, orders the stages topologically (a cycle is reported), reads each
 * capture once with the union of the columns in use, and runs each stage
 * once.  SSCOPE_TRACE=1 in the environment prints every read and every
 * stage run on stderr, so tests can prove what was skipped.
 */
#include "scene.h"

#include <ctype.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "hashjob.h"
#include "html.h"
#include "plot.h"
#include "report.h"
#include "ssc.h"

/* The stage graph (src/cli/stages.c), given to ssc_scene_load() or
 * ssc_scene_infer(); the CLI is single-threaded and runs one scene. */
static const struct ssc_stage_def *stages;

#define N_STAGES S_COUNT_

struct ssc_scene;
static int check_stages(const char *cmd, struct ssc_scene *sc);

struct ssc_scene {
	struct ssc_hashjob *hashes; /* provenance, while running */
	char *path;             /* scene file, or NULL when inferred */
	char *dir;              /* its directory */
	char *title;
	struct ssc_ini *ini;
	char **files;
	size_t n_files;
	/* [input] */
	char *columns, *units, *temp_column, *time_column, *raw, *calibration;
	char *topic;
	double rate_hz, scale, offset;
	bool allow_nan;
	/* [sensor], [adc] */
	bool have_sensor;
	struct sscope_sensor_spec sensor;
	char *sensor_path;
	char *adc_paths[8];
	size_t n_adc;
	struct ssc_ini *adc_ini; /* inline [adc] specification */
	/* stages */
	unsigned want;          /* bit per stage: requested */
	unsigned run;           /* bit per stage: will run */
	unsigned uses[N_STAGES]; /* results each consumes */
	char *why[N_STAGES];    /* why it runs / is skipped */
	/* each stage's options as a command line: args[s][0] the command,
	 * then "--key=value"; where[s][i] the scene line of args[s][i] */
	char **args[N_STAGES];
	char **where[N_STAGES];
	int n_args[N_STAGES];
	char *stage_columns[N_STAGES];
	bool no_plot[N_STAGES];
	size_t order[N_STAGES], n_order;
	/* [report] */
	unsigned formats;
	char *out_dir;
	bool quiet;
	/* wall time of the reads and of each stage, s */
	double t_read_s, t_stage_s[S_COUNT_];
	/* the captures each stage runs on (bit f: file f), all by default */
	uint64_t file_mask[S_COUNT_];
	/* files named by stage options (made relative to the scene file),
	 * and for each the option when it writes the file ("--kalibr"), NULL
	 * when it reads it: checked against the inputs before a run */
	char *io_path[64];
	const char *io_out[64];
	size_t n_io;
};

/* ------------------------------------------------------------ helpers */

static char *xstrdup(const char *s)
{
	char *d = s ? strdup(s) : NULL;

	if (s && !d) {
		fprintf(stderr, "sensorscope: out of memory\n");
		exit(SSC_EXIT_FAIL);
	}
	return d;
}

static char *join_path(const char *dir, const char *name)
{
	char *p;
	size_t n;

	if (name[0] == '/' || !dir || !*dir || !strcmp(dir, "."))
		return xstrdup(name);
	n = strlen(dir) + strlen(name) + 2;
	p = malloc(n);
	if (!p)
		exit(SSC_EXIT_FAIL);
	snprintf(p, n, "%s/%s", dir, name);
	return p;
}

static char *dir_of(const char *path)
{
	const char *sl = strrchr(path, '/');
	char *d;

	if (!sl)
		return xstrdup(".");
	d = xstrdup(path);
	d[sl - path ? sl - path : 1] = '\0';
	return d;
}

static bool truthy(const char *v, bool *out)
{
	if (!strcasecmp(v, "yes") || !strcasecmp(v, "true") || !strcmp(v, "1") ||
	    !strcasecmp(v, "on")) {
		*out = true;
		return true;
	}
	if (!strcasecmp(v, "no") || !strcasecmp(v, "false") || !strcmp(v, "0") ||
	    !strcasecmp(v, "off")) {
		*out = false;
		return true;
	}
	return false;
}

static long stage_index(const char *name)
{
	for (size_t i = 0; i < N_STAGES; i++)
		if (stages[i].name && !strcasecmp(stages[i].name, name))
			return (long)i;
	return -1;
}

static void set_why(struct ssc_scene *sc, size_t i, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

static void set_why(struct ssc_scene *sc, size_t i, const char *fmt, ...)
{
	va_list ap;
	char buf[256];

	va_start(ap, fmt);
	vsnprintf(buf, sizeof(buf), fmt, ap);
	va_end(ap);
	free(sc->why[i]);
	sc->why[i] = xstrdup(buf);
}

void ssc_scene_free(struct ssc_scene *sc)
{
	if (!sc)
		return;
	for (size_t i = 0; i < sc->n_files; i++)
		free(sc->files[i]);
	free(sc->files);
	for (size_t i = 0; i < N_STAGES; i++) {
		for (int k = 0; k < sc->n_args[i]; k++) {
			free(sc->args[i][k]);
			free(sc->where[i][k]);
		}
		free(sc->args[i]);
		free(sc->where[i]);
		free(sc->why[i]);
		free(sc->stage_columns[i]);
	}
	for (size_t i = 0; i < sc->n_adc; i++)
		free(sc->adc_paths[i]);
	for (size_t i = 0; i < sc->n_io; i++)
		free(sc->io_path[i]);
	ssc_ini_free(sc->adc_ini);
	ssc_ini_free(sc->ini);
	free(sc->columns);
	free(sc->units);
	free(sc->temp_column);
	free(sc->time_column);
	free(sc->topic);
	free(sc->raw);
	free(sc->calibration);
	free(sc->sensor_path);
	free(sc->out_dir);
	free(sc->title);
	free(sc->path);
	free(sc->dir);
	free(sc);
}

/* Append an option of stage s to its command line: "--name=value", or
 * "--name" for a flag (value NULL); name NULL appends value as it is. */
static void add_arg(struct ssc_scene *sc, size_t s, const char *name,
		    const char *value, const char *where)
{
	char **a = realloc(sc->args[s], (size_t)(sc->n_args[s] + 2) * sizeof(*a));
	char **w = a ? realloc(sc->where[s], (size_t)(sc->n_args[s] + 2) * sizeof(*w)) :
		       NULL;
	char *arg;

	if (a)
		sc->args[s] = a;
	if (!a || !w) {
		fprintf(stderr, "sensorscope: out of memory\n");
		exit(SSC_EXIT_FAIL);
	}
	sc->where[s] = w;
	if (!name) {
		arg = xstrdup(value);
	} else {
		size_t n = strlen(name) + (value ? strlen(value) : 0) + 4;

		arg = malloc(n);
		if (!arg)
			exit(SSC_EXIT_FAIL);
		snprintf(arg, n, "--%s%s%s", name, value ? "=" : "",
			 value ? value : "");
	}
	a[sc->n_args[s]] = arg;
	w[sc->n_args[s]] = xstrdup(where);
	sc->n_args[s]++;
	a[sc->n_args[s]] = NULL;
	w[sc->n_args[s]] = NULL;
}

static struct ssc_scene *scene_new(void)
{
	struct ssc_scene *sc = calloc(1, sizeof(*sc));

	if (!sc)
		exit(SSC_EXIT_FAIL);
	sc->scale = 1;
	sc->formats = SSC_OUT_TEXT | SSC_OUT_JSON | SSC_OUT_HTML | SSC_OUT_PNG |
		      SSC_OUT_SVG;
	for (size_t i = 0; i < N_STAGES; i++)
		add_arg(sc, i, NULL, stages[i].name, NULL);
	return sc;
}

/* Split a comma list into trimmed items (modifies s). */
/* Split a comma list into at most max items; *more (may be NULL) tells
 * whether items were left over (an error for lists of inputs). */
static size_t split_list_n(char *s, char **items, size_t max, bool *more)
{
	size_t n = 0;
	char *save = NULL;

	if (more)
		*more = false;
	for (char *t = strtok_r(s, ",", &save); t;
	     t = strtok_r(NULL, ",", &save)) {
		char *e;

		while (isspace((unsigned char)*t))
			t++;
		e = t + strlen(t);
		while (e > t && isspace((unsigned char)e[-1]))
			*--e = '\0';
		if (!*t)
			continue;
		if (n == max) {
			if (more)
				*more = true;
			break;
		}
		items[n++] = t;
	}
	return n;
}

static size_t split_list(char *s, char **items, size_t max)
{
	return split_list_n(s, items, max, NULL);
}

/* ------------------------------------------------------------ parsing */

static int scene_error(const char *cmd, const struct ssc_scene *sc, size_t line,
		       const char *fmt, ...) __attribute__((format(printf, 4, 5)));

static int scene_error(const char *cmd, const struct ssc_scene *sc, size_t line,
		       const char *fmt, ...)
{
	va_list ap;
	char buf[512];

	va_start(ap, fmt);
	vsnprintf(buf, sizeof(buf), fmt, ap);
	va_end(ap);
	if (line)
		ssc_err(cmd, "%s: line %zu: %s", sc->path, line, buf);
	else
		ssc_err(cmd, "%s: %s", sc->path, buf);
	return SSC_EXIT_USAGE;
}

static int parse_input(const char *cmd, struct ssc_scene *sc)
{
	static const char *const keys[] = { "files", "columns", "rate", "units",
					    "temp_column", "time_column", "raw",
					    "scale", "offset", "allow_nan",
					    "calibration", "topic", NULL };
	struct sscope_diag d = { "" };
	size_t line = 0;
	const char *v;
	int rc;

	if (ssc_ini_check_keys(sc->ini, "input", keys, &d)) {
		ssc_err(cmd, "%s", d.msg);
		return SSC_EXIT_USAGE;
	}
	v = ssc_ini_get(sc->ini, "input", "files", &line);
	if ((!v || !*v) &&
	    !ssc_ini_get(sc->ini, "input", "rate", NULL))
		return scene_error(cmd, sc, 0, "[input] needs 'files = ...' (or only 'rate = HZ', the rate a [plan] from the [sensor] plans at)");
	if (v && *v) {
		char *copy = xstrdup(v), *items[64];
		bool more;
		size_t n = split_list_n(copy, items, 64, &more);

		if (more) {
			free(copy);
			return scene_error(cmd, sc, line, "files: more than 64 captures");
		}
		sc->files = calloc(n ? n : 1, sizeof(char *));
		for (size_t i = 0; i < n; i++) {
			struct stat st;

			sc->files[i] = join_path(sc->dir, items[i]);
			sc->n_files++;
			if (stat(sc->files[i], &st) != 0) {
				rc = scene_error(cmd, sc, line, "files: %s: %s",
						 sc->files[i], sscope_strerror(errno));
				free(copy);
				return rc == SSC_EXIT_USAGE ? SSC_EXIT_FAIL : rc;
			}
		}
		free(copy);
		if (!n)
			return scene_error(cmd, sc, line, "files: empty list");
		rc = ssc_check_inputs(cmd, (const char *const *)sc->files,
				      sc->n_files);
		if (rc)
			return rc;
	}
	sc->columns = xstrdup(ssc_ini_get(sc->ini, "input", "columns", NULL));
	sc->units = xstrdup(ssc_ini_get(sc->ini, "input", "units", NULL));
	sc->temp_column = xstrdup(ssc_ini_get(sc->ini, "input", "temp_column", NULL));
	sc->time_column = xstrdup(ssc_ini_get(sc->ini, "input", "time_column", NULL));
	sc->topic = xstrdup(ssc_ini_get(sc->ini, "input", "topic", NULL));
	v = ssc_ini_get(sc->ini, "input", "raw", &line);
	if (v && sscope_reader_raw_layout_check(v, NULL, NULL, &d))
		return scene_error(cmd, sc, line, "raw: %s", d.msg);
	sc->raw = xstrdup(v);
	v = ssc_ini_get(sc->ini, "input", "calibration", NULL);
	if (v)
		sc->calibration = join_path(sc->dir, v);
	rc = ssc_ini_quantity(sc->ini, "input", "rate", "Hz", &sc->rate_hz, &d);
	if (rc && rc != -ENOENT) {
		ssc_err(cmd, "%s", d.msg);
		return SSC_EXIT_USAGE;
	}
	if (!rc && !(sc->rate_hz > 0))
		return scene_error(cmd, sc, 0, "[input] rate must be positive");
	rc = ssc_ini_quantity(sc->ini, "input", "scale", "1", &sc->scale, &d);
	if (rc && rc != -ENOENT) {
		ssc_err(cmd, "%s", d.msg);
		return SSC_EXIT_USAGE;
	}
	rc = ssc_ini_quantity(sc->ini, "input", "offset", "1", &sc->offset, &d);
	if (rc && rc != -ENOENT) {
		ssc_err(cmd, "%s", d.msg);
		return SSC_EXIT_USAGE;
	}
	if (!sc->raw && (ssc_ini_get(sc->ini, "input", "scale", &line) ||
			 ssc_ini_get(sc->ini, "input", "offset", &line)))
		return scene_error(cmd, sc, line,
				   "scale and offset apply to raw input only (raw = TYPE:CH)");
	v = ssc_ini_get(sc->ini, "input", "allow_nan", &line);
	if (v && !truthy(v, &sc->allow_nan))
		return scene_error(cmd, sc, line, "allow_nan: expected yes or no");
	if (sc->units) {
		struct sscope_unit u;

		if (sscope_unit_parse(sc->units, &u, &d)) {
			ssc_err(cmd, "%s: [input] units: %s", sc->path, d.msg);
			return SSC_EXIT_USAGE;
		}
	}
	return SSC_EXIT_OK;
}

static int parse_sensor(const char *cmd, struct ssc_scene *sc)
{
	struct sscope_diag d = { "" };
	size_t line = 0;
	const char *spec = ssc_ini_get(sc->ini, "sensor", "spec", &line);
	int rc;

	if (spec) {
		if (ssc_ini_n_keys(sc->ini, "sensor") > 1)
			return scene_error(cmd, sc, line,
					   "[sensor] takes either 'spec = FILE' or inline keys, not both");
		sc->sensor_path = join_path(sc->dir, spec);
		rc = sscope_sensor_spec_load(sc->sensor_path, &sc->sensor, &d);
	} else {
		rc = ssc_sensor_spec_from_ini(sc->ini, "sensor", &sc->sensor, &d);
	}
	if (rc) {
		ssc_err(cmd, "%s", d.msg);
		return rc == -EINVAL ? SSC_EXIT_USAGE : SSC_EXIT_FAIL;
	}
	sc->have_sensor = true;
	return SSC_EXIT_OK;
}

/* The long option of stage s named `name` (any case), or NULL. */
static const struct ssc_option *find_option(size_t s, const char *name)
{
	const struct ssc_option *o = stages[s].ops->spec->options;

	while (o && o->name && strcasecmp(o->name, name))
		o++;
	return o && o->name ? o : NULL;
}

/* Is key a long option of the stage's command (or a scene stage key)? */
static bool stage_key(size_t s, const char *key)
{
	return !strcasecmp(key, "plot") || !strcasecmp(key, "uses") ||
	       !strcasecmp(key, "column") || !strcasecmp(key, "columns") ||
	       find_option(s, key);
}

/* [adc]: 'spec = FILE[, FILE...]' or an inline specification, plus the
 * options of 'adc report'.  The inline keys are parsed as an [adc]
 * section kept at the scene's line numbers, so errors name the line. */
static int parse_adc(const char *cmd, struct ssc_scene *sc)
{
	size_t line = 0, sec_line = 0, n_inline = 0, len = 0, cur = 1;
	const char *spec = ssc_ini_get(sc->ini, "adc", "spec", &line);
	char *text;

	for (size_t k = 0; k < ssc_ini_n_sections(sc->ini); k++) {
		size_t l;
		const char *name = ssc_ini_section(sc->ini, k, &l);

		if (!strcasecmp(name, "adc"))
			sec_line = l;
	}
	for (size_t k = 0; k < ssc_ini_n_keys(sc->ini, "adc"); k++) {
		const char *v, *key = ssc_ini_key(sc->ini, "adc", k, &v, &line);

		if (strcasecmp(key, "spec") && !stage_key(S_ADC, key)) {
			n_inline++;
			len += strlen(key) + strlen(v) + 8 + line;
		}
	}
	if (spec && n_inline)
		return scene_error(cmd, sc, 0,
				   "[adc] takes either 'spec = FILE[, FILE...]' or inline keys, not both");
	if (n_inline) {
		struct sscope_diag d = { "" };
		struct sscope_adc_spec tmp;
		int e;

		text = calloc(1, len + sec_line + 16);
		for (; cur < sec_line; cur++)
			strcat(text, "\n");
		strcat(text, "[adc]\n");
		cur++;
		for (size_t k = 0; k < ssc_ini_n_keys(sc->ini, "adc"); k++) {
			const char *v, *key = ssc_ini_key(sc->ini, "adc", k, &v, &line);

			if (!strcasecmp(key, "spec") || stage_key(S_ADC, key))
				continue;
			for (; cur < line; cur++)
				strcat(text, "\n");
			sprintf(text + strlen(text), "%s = %s\n", key, v);
			cur++;
		}
		e = ssc_ini_parse(&sc->adc_ini, text, strlen(text), sc->path, &d);
		free(text);
		if (!e)
			e = ssc_adc_spec_from_ini(sc->adc_ini, "adc", &tmp, &d);
		if (e) {
			ssc_err(cmd, "%s", d.msg[0] ? d.msg : sscope_strerror(e));
			return SSC_EXIT_USAGE;
		}
		return SSC_EXIT_OK;
	}
	if (!spec)
		return SSC_EXIT_OK;
	{
		char *copy = xstrdup(spec), *items[8];
		bool more;
		size_t n = split_list_n(copy, items, 8, &more);

		if (more) {
			free(copy);
			return scene_error(cmd, sc, line, "spec: more than 8 converters");
		}

		for (size_t i = 0; i < n; i++) {
			sc->adc_paths[i] = join_path(sc->dir, items[i]);
			if (access(sc->adc_paths[i], R_OK) != 0) {
				int rc = scene_error(cmd, sc, line, "spec: %s: %s",
						     sc->adc_paths[i], sscope_strerror(errno));

				sc->n_adc = i + 1;
				free(copy);
				return rc;
			}
		}
		sc->n_adc = n;
		free(copy);
	}
	return SSC_EXIT_OK;
}

static int parse_report(const char *cmd, struct ssc_scene *sc)
{
	static const char *const keys[] = { "formats", "output", "title", NULL };
	struct sscope_diag d = { "" };
	size_t line = 0;
	const char *v;

	if (ssc_ini_check_keys(sc->ini, "report", keys, &d)) {
		ssc_err(cmd, "%s", d.msg);
		return SSC_EXIT_USAGE;
	}
	v = ssc_ini_get(sc->ini, "report", "formats", &line);
	if (v) {
		char *copy = xstrdup(v), *items[8];
		size_t n = split_list(copy, items, 8);

		sc->formats = 0;
		for (size_t i = 0; i < n; i++) {
			if (!strcasecmp(items[i], "text"))
				sc->formats |= SSC_OUT_TEXT;
			else if (!strcasecmp(items[i], "json"))
				sc->formats |= SSC_OUT_JSON;
			else if (!strcasecmp(items[i], "html"))
				sc->formats |= SSC_OUT_HTML;
			else if (!strcasecmp(items[i], "png"))
				sc->formats |= SSC_OUT_PNG;
			else if (!strcasecmp(items[i], "svg"))
				sc->formats |= SSC_OUT_SVG;
			else {
				int rc = scene_error(cmd, sc, line,
						     "formats: '%s' is not text, json, html, png or svg",
						     items[i]);

				free(copy);
				return rc;
			}
		}
		free(copy);
		if (!sc->formats)
			return scene_error(cmd, sc, line,
					   "formats: empty: give one or more of text, json, html, png and svg (or leave the key out for all)");
	}
	v = ssc_ini_get(sc->ini, "report", "output", NULL);
	if (v)
		sc->out_dir = join_path(sc->dir, v);
	v = ssc_ini_get(sc->ini, "report", "title", NULL);
	if (v)
		sc->title = xstrdup(v);
	return SSC_EXIT_OK;
}

/* A stage section: its keys are the command's long options. */
static int parse_stage(const char *cmd, struct ssc_scene *sc, size_t s)
{
	const struct ssc_stage_ops *ops = stages[s].ops;
	const char *sec = stages[s].name;

	for (size_t k = 0; k < ssc_ini_n_keys(sc->ini, sec); k++) {
		const char *value;
		size_t line;
		const char *key = ssc_ini_key(sc->ini, sec, k, &value, &line);
		const struct ssc_option *o;
		char ctx[320];
		int rc;

		if (!strcasecmp(key, "column") || !strcasecmp(key, "columns")) {
			/* within [input]'s columns, which are all that is read */
			if (sc->columns) {
				char *copy = xstrdup(value), *items[64], *in = xstrdup(sc->columns),
				     *have[64];
				size_t n = split_list(copy, items, 64), m = split_list(in, have, 64);
				const char *out = NULL;

				for (size_t i = 0; i < n && !out; i++) {
					bool found = false;

					for (size_t j = 0; j < m && !found; j++)
						found = !strcmp(items[i], have[j]);
					if (!found)
						out = items[i];
				}
				if (out) {
					int e = scene_error(cmd, sc, line,
							    "columns: '%s' is not among [input]'s columns (%s), which are all the scene reads",
							    out, sc->columns);

					free(copy);
					free(in);
					return e;
				}
				free(copy);
				free(in);
			}
			free(sc->stage_columns[s]);
			sc->stage_columns[s] = xstrdup(value);
			if (ops->spec->analysis) {
				char at[320];

				snprintf(at, sizeof(at), "%s: line %zu", sc->path, line);
				add_arg(sc, s, "column", value, at);
			}
			continue;
		}
		if (s == S_ADC && (!strcasecmp(key, "spec") || !stage_key(s, key)))
			continue; /* the converter's specification */
		if (!strcasecmp(key, "plot")) {
			bool on;

			if (!truthy(value, &on))
				return scene_error(cmd, sc, line,
						   "plot: expected yes or no");
			sc->no_plot[s] = !on;
			continue;
		}
		if (!strcasecmp(key, "uses")) {
			char *copy = xstrdup(value), *items[16];
			size_t n = split_list(copy, items, 16);

			for (size_t i = 0; i < n; i++) {
				long u = stage_index(items[i]);

				if (u < 0 || !(stages[s].deps & (1u << u))) {
					rc = scene_error(cmd, sc, line,
							 "impossible request: [%s] cannot use the results of '%s'",
							 sec, items[i]);
					free(copy);
					return rc;
				}
				sc->uses[s] |= 1u << u;
			}
			free(copy);
			continue;
		}
		o = find_option(s, key);
		if (!o)
			return scene_error(cmd, sc, line,
					   "unknown key '%s' in [%s] (keys are the long options of 'sensorscope %s')",
					   key, sec, ops->spec->name);
		snprintf(ctx, sizeof(ctx), "%s: line %zu", sc->path, line);
		if (o->has_arg == no_argument) {
			bool on;

			if (!truthy(value, &on))
				return scene_error(cmd, sc, line,
						   "%s: expected yes or no", key);
			if (on)
				add_arg(sc, s, o->name, NULL, ctx);
		} else if (o->arg && (strstr(o->arg, "FILE") || strstr(o->arg, "PATH"))) {
			/* a file named in a scene is relative to the scene */
			char *path = join_path(sc->dir, value);

			add_arg(sc, s, o->name, path, ctx);
			if (sc->n_io < 64) {
				sc->io_out[sc->n_io] = ssc_output_option(o->name);
				sc->io_path[sc->n_io++] = path;
			} else {
				free(path);
			}
		} else {
			add_arg(sc, s, o->name, value, ctx);
		}
	}
	return SSC_EXIT_OK;
}

/* Which stages run, and why; impossible requests are errors. */
static int resolve(const char *cmd, struct ssc_scene *sc)
{
	unsigned visiting = 0, done = 0;

	if (!sc->want)
		return scene_error(cmd, sc, 0,
				   "nothing to do: no output section (e.g. [allan], [psd], [budget])");
	sc->run = sc->want | (sc->n_files ? 1u << S_INFO : 0);
	for (size_t s = 0; s < N_STAGES; s++)
		if (!sc->file_mask[s])
			sc->file_mask[s] = sc->n_files >= 64 ? ~(uint64_t)0 :
				((uint64_t)1 << sc->n_files) - 1;
	for (size_t s = 0; s < N_STAGES; s++) {
		if (!(sc->want & (1u << s)))
			continue;
		if ((stages[s].ops->needs & SSC_NEED_DATA) && !sc->n_files &&
		    !((stages[s].ops->needs & SSC_NEED_DATA_OR_SENSOR) &&
		      sc->have_sensor))
			return scene_error(cmd, sc, 0,
					   "impossible request: [%s] needs captures: give [input] files = ...",
					   stages[s].name);
		if ((s == S_BUDGET || s == S_NAVSIM) && !sc->uses[s] &&
		    !sc->have_sensor) {
			/* noise terms from the scene's own analyses */
			sc->uses[s] = sc->want & stages[s].deps;
			if (!sc->uses[s] && sc->n_files)
				sc->uses[s] = 1u << S_ALLAN; /* measure them */
			/* else its own keys (gyro-bias = ...) must name the
			 * sources: the stage's check says so */
		}
		sc->run |= sc->uses[s];
		if ((stages[s].ops->needs & SSC_NEED_SENSOR) && !sc->have_sensor)
			return scene_error(cmd, sc, 0,
					   "impossible request: [%s] needs a [sensor] specification",
					   stages[s].name);
		if ((stages[s].ops->needs & SSC_NEED_ADC) && !sc->n_adc &&
		    !sc->adc_ini)
			return scene_error(cmd, sc, 0,
					   "impossible request: [%s] needs an [adc] specification",
					   stages[s].name);
	}
	/* depth-first topological order over "uses"; a back edge is a cycle */
	sc->n_order = 0;
	for (size_t root = 0; root < N_STAGES; root++) {
		size_t stack[N_STAGES], depth = 0, next[N_STAGES] = { 0 };

		if (!(sc->run & (1u << root)) || (done & (1u << root)))
			continue;
		stack[depth++] = root;
		visiting |= 1u << root;
		while (depth) {
			size_t s = stack[depth - 1];

			while (next[s] < N_STAGES && !(sc->uses[s] & (1u << next[s])))
				next[s]++;
			if (next[s] < N_STAGES) {
				size_t u = next[s]++;

				if (visiting & (1u << u))
					return scene_error(cmd, sc, 0,
							   "cyclic request: [%s] and [%s] use each other's results",
							   stages[s].name, stages[u].name);
				if (!(done & (1u << u))) {
					visiting |= 1u << u;
					stack[depth++] = u;
				}
				continue;
			}
			visiting &= ~(1u << s);
			done |= 1u << s;
			sc->order[sc->n_order++] = s;
			depth--;
		}
	}
	for (size_t s = 0; s < N_STAGES; s++) {
		if ((sc->want & (1u << s)) && sc->why[s])
			continue; /* inferred, with its reason */
		if (sc->want & (1u << s))
			set_why(sc, s, "requested by [%s]", stages[s].name);
		else if (s == S_INFO)
			set_why(sc, s, sc->n_files ? "always: describes the inputs" :
						     "no captures to describe");
		else if (sc->run & (1u << s)) {
			for (size_t t = 0; t < N_STAGES; t++)
				if (sc->uses[t] & (1u << s))
					set_why(sc, s, "its results are used by [%s]",
						stages[t].name);
		} else if (sc->path) {
			set_why(sc, s, "not requested (no [%s] section)",
				stages[s].name);
		} else {
			/* no scene file: nothing asked, the data did not call
			 * for it */
			set_why(sc, s, "not inferred from these data");
		}
	}
	return SSC_EXIT_OK;
}

int ssc_scene_load(const char *cmd, const char *path,
		   const struct ssc_stage_def *graph, struct ssc_scene **out)
{
	struct ssc_scene *sc;
	struct sscope_diag d = { "" };
	int rc;

	stages = graph;
	sc = scene_new();
	*out = NULL;
	sc->path = xstrdup(path);
	sc->dir = dir_of(path);
	rc = ssc_ini_load(&sc->ini, path, &d);
	if (rc) {
		ssc_err(cmd, "%s", d.msg[0] ? d.msg : sscope_strerror(rc));
		ssc_scene_free(sc);
		return rc == -EBADMSG ? SSC_EXIT_USAGE : SSC_EXIT_FAIL;
	}
	for (size_t i = 0; i < ssc_ini_n_sections(sc->ini); i++) {
		size_t line;
		const char *name = ssc_ini_section(sc->ini, i, &line);
		long s;

		if (!strcasecmp(name, "input") || !strcasecmp(name, "sensor") ||
		    !strcasecmp(name, "report"))
			continue;
		s = stage_index(name);
		if (s < 0 || s == S_INFO) {
			char list[256] = "";

			for (size_t k = 1; k < N_STAGES; k++)
				snprintf(list + strlen(list), sizeof(list) - strlen(list),
					 ", %s", stages[k].name);
			rc = scene_error(cmd, sc, line,
					 "unknown section [%s] (sections: input, sensor, adc, report, and one per output: %s)",
					 name, list + 2);
			goto fail;
		}
		sc->want |= 1u << s;
	}
	rc = 0;
	if (ssc_ini_has_section(sc->ini, "input"))
		rc = parse_input(cmd, sc);
	if (!rc && ssc_ini_has_section(sc->ini, "sensor"))
		rc = parse_sensor(cmd, sc);
	if (!rc && ssc_ini_has_section(sc->ini, "adc"))
		rc = parse_adc(cmd, sc);
	if (!rc && ssc_ini_has_section(sc->ini, "report"))
		rc = parse_report(cmd, sc);
	for (size_t s = 0; !rc && s < N_STAGES; s++)
		if (sc->want & (1u << s))
			rc = parse_stage(cmd, sc, s);
	if (!rc)
		rc = resolve(cmd, sc);
	if (!rc)
		rc = check_stages(cmd, sc);
	if (rc)
		goto fail;
	if (!sc->out_dir)
		sc->out_dir = join_path(sc->dir, "sensorscope-report");
	*out = sc;
	return SSC_EXIT_OK;
fail:
	ssc_scene_free(sc);
	return rc;
}

/* ------------------------------------------------------------ inference */

/* A column of commanded rate (a rate table's set point): its name says
 * so ("rate_cmd", "cmd_rate", "commanded", "setpoint", "table_rate",
 * "w_ref"). */
static bool commanded_column(const char *nm)
{
	size_t l = strlen(nm);

	return strcasestr(nm, "cmd") || strcasestr(nm, "command") ||
	       strcasestr(nm, "setpoint") || strcasestr(nm, "table") ||
	       (l >= 3 && !strcasecmp(nm + l - 3, "ref"));
}

/* Set a stage option by its long name, as a scene key would. */
static void set_option(struct ssc_scene *sc, size_t s, const char *name,
		       const char *value)
{
	add_arg(sc, s, name, value, NULL);
}

int ssc_scene_infer(const struct ssc_common *co, char **files, size_t n,
		    const char *out_dir, const struct ssc_stage_def *graph,
		    struct ssc_scene **out)
{
	struct ssc_scene *sc;

	stages = graph;
	sc = scene_new();

	sc->files = calloc(n ? n : 1, sizeof(char *));
	for (size_t i = 0; i < n; i++)
		sc->files[sc->n_files++] = xstrdup(files[i]);
	sc->columns = xstrdup(co->columns);
	sc->units = xstrdup(co->units);
	sc->temp_column = xstrdup(co->temp_column);
	sc->time_column = xstrdup(co->time_column);
	sc->topic = xstrdup(co->topic);
	sc->raw = xstrdup(co->raw);
	sc->calibration = xstrdup(co->calibration);
	sc->rate_hz = co->rate_hz;
	sc->scale = co->scale;
	sc->offset = co->offset;
	sc->allow_nan = co->allow_nan;
	sc->out_dir = xstrdup(out_dir);
	sc->quiet = co->quiet;
	sc->dir = xstrdup(".");
	/* the data decide what runs: look at each file's columns and rate
	 * (header and first rows only; the run reads each file once) */
	for (size_t i = 0; i < n; i++) {
		struct sscope_reader_opts ro;
		struct sscope_reader *r = NULL;
		struct sscope_diag d = { "" };
		double rate = co->rate_hz;
		bool acc = false, gyro = false, other = false, tilt = false;
		bool temp;
		uint64_t bit;
		int e;
		char heading_ref[64] = "", cmd_ref[64] = "", data_cols[512] = "";

		ssc_read_opts(co, &ro);
		e = sscope_reader_open(&r, files[i], &ro, &d);
		if (e) {
			ssc_fail(co->cmd, e, &d, files[i]);
			ssc_scene_free(sc);
			return SSC_EXIT_FAIL;
		}
		if (!(rate > 0))
			rate = sscope_reader_header_rate(r);
		if (!(rate > 0) && sscope_reader_time_column(r)) {
			double t[512], *cols[64] = { 0 };
			struct sscope_reader_chunk ch = { 512, 0, cols, t, NULL };

			if (sscope_reader_n_channels(r) <= 64 &&
			    !sscope_reader_read(r, &ch, NULL) && ch.rows >= 2 &&
			    t[ch.rows - 1] > 0)
				rate = (double)(ch.rows - 1) / t[ch.rows - 1];
		}
		for (size_t k = 0; k < sscope_reader_n_channels(r); k++) {
			enum sscope_quantity q = sscope_reader_channel(r, k)->quantity;
			const char *nm = sscope_reader_channel(r, k)->name;

			if (!strcmp(nm, "roll_ref") || !strcmp(nm, "pitch_ref"))
				tilt = true;
			/* a true heading beside a gyro: a drive to check */
			if (q == SSCOPE_QUANTITY_ANGLE && strcasestr(nm, "heading") &&
			    strlen(nm) < sizeof(heading_ref)) {
				strcpy(heading_ref, nm);
				continue; /* a reference, not a sensor's channel */
			}

			/* a commanded rate is the reference of a rate-table
			 * run, not a gyro */
			if (q == SSCOPE_QUANTITY_ANGULAR_RATE && !cmd_ref[0] &&
			    commanded_column(nm) && strlen(nm) < sizeof(cmd_ref)) {
				strcpy(cmd_ref, nm);
				continue;
			}
			if (strlen(data_cols) + strlen(nm) + 2 < sizeof(data_cols))
				snprintf(data_cols + strlen(data_cols),
					 sizeof(data_cols) - strlen(data_cols), "%s%s",
					 data_cols[0] ? "," : "", nm);
			if (q == SSCOPE_QUANTITY_ACCELERATION)
				acc = true;
			else if (q == SSCOPE_QUANTITY_ANGULAR_RATE)
				gyro = true;
			else
				other = true;
		}
		temp = sscope_reader_temp_column(r) != NULL;
		sscope_reader_close(r);
		bit = i < 64 ? (uint64_t)1 << i : 0;
		if (tilt && acc && temp) {
			/* a tilt table: calibrate the inclinometer, nothing else */
			if (!(sc->want & (1u << S_INCLINO)))
				set_why(sc, S_INCLINO,
					"inferred: accelerations with reference tilts (roll_ref, pitch_ref) and temperature: a calibration run");
			sc->want |= 1u << S_INCLINO;
			sc->file_mask[S_INCLINO] |= bit;
			continue;
		}
		if (gyro && cmd_ref[0]) {
			/* a rate-table run: the gyro's scale factors against
			 * the commanded rate; allan still runs on the gyro
			 * channels, and its adequacy check says why the record
			 * gives no noise terms (it moves) */
			if (!(sc->want & (1u << S_CALIB))) {
				set_why(sc, S_CALIB,
					"inferred: a gyro with a commanded-rate column (%s): a rate-table calibration run",
					cmd_ref);
				set_option(sc, S_CALIB, "triad", "gyro");
				set_option(sc, S_CALIB, "mode", "rate-table");
				set_option(sc, S_CALIB, "reference", cmd_ref);
			}
			sc->want |= 1u << S_CALIB;
			sc->file_mask[S_CALIB] |= i < 64 ? (uint64_t)1 << i : 0;
			if (!co->columns && !sc->stage_columns[S_ALLAN] && data_cols[0]) {
				sc->stage_columns[S_ALLAN] = xstrdup(data_cols);
				add_arg(sc, S_ALLAN, "column", data_cols, NULL);
			}
		} else if (gyro && heading_ref[0]) {
			if (!(sc->want & (1u << S_HEADING))) {
				set_why(sc, S_HEADING,
					"inferred: a gyro with a true heading column (%s): heading with the bias re-estimated at stops",
					heading_ref);
				set_option(sc, S_HEADING, "reference", heading_ref);
			}
			sc->want |= 1u << S_HEADING;
			sc->file_mask[S_HEADING] |= bit;
			/* the true heading is the reference, not a channel
			 * for the noise, the spectrum or the temperature (one
			 * file: its columns; others may hold other columns) */
			for (int st = 0; st < 3 && !co->columns && data_cols[0] &&
					 n == 1; st++) {
				int sg = st == 0 ? S_ALLAN : st == 1 ? S_PSD : S_TEMPBIAS;

				if (!sc->stage_columns[sg]) {
					sc->stage_columns[sg] = xstrdup(data_cols);
					add_arg(sc, sg, "column", data_cols, NULL);
				}
			}
		} else if (gyro && !temp) {
			/* a stationary gyro gets the random-walk fan (the
			 * stage refuses a record that moves) */
			if (!(sc->want & (1u << S_WALK)))
				set_why(sc, S_WALK,
					"inferred: a gyro record without temperature: the random-walk fan");
			sc->want |= 1u << S_WALK;
			sc->file_mask[S_WALK] |= bit;
		}
		if (temp && (acc || gyro)) {
			if (!(sc->want & (1u << S_TEMPBIAS)))
				set_why(sc, S_TEMPBIAS,
					"inferred: inertial channels with a temperature column");
			sc->want |= 1u << S_TEMPBIAS;
			sc->file_mask[S_TEMPBIAS] |= bit;
		}
		if (gyro || (acc && rate < 500)) {
			if (!(sc->want & (1u << S_ALLAN)))
				set_why(sc, S_ALLAN,
					"inferred: %s record: noise terms from the Allan deviation",
					gyro ? "a rate-gyro" : "an inertial-rate accelerometer");
			sc->want |= 1u << S_ALLAN;
			sc->file_mask[S_ALLAN] |= bit;
		}
		if (acc && rate >= 500) {
			if (!(sc->want & (1u << S_VIBRATION)))
				set_why(sc, S_VIBRATION,
					"inferred: acceleration sampled at %.4g Hz (>= 500 Hz) is a vibration record",
					rate);
			sc->want |= 1u << S_VIBRATION;
			sc->file_mask[S_VIBRATION] |= bit;
		}
		if (acc || gyro || other)
			sc->file_mask[S_PSD] |= bit;
		if ((acc || gyro || other) && !(sc->want & (1u << S_PSD))) {
			sc->want |= 1u << S_PSD;
			set_why(sc, S_PSD, "inferred: the spectrum of every data channel");
			if (rate > 0) {
				/* segments of about 1 s above 500 Hz (1 Hz
				 * bins for machinery orders), 10 s below */
				double want = rate >= 500 ? rate : 10 * rate;
				char v[32];

				snprintf(v, sizeof(v), "%.0f",
					 fmax(256, pow(2, round(log2(want)))));
				set_option(sc, S_PSD, "nperseg", v);
			}
		}
	}
	if (resolve(co->cmd, sc) || check_stages(co->cmd, sc)) {
		ssc_scene_free(sc);
		return SSC_EXIT_FAIL;
	}
	*out = sc;
	return SSC_EXIT_OK;
}

void ssc_scene_set_output(struct ssc_scene *sc, const char *dir)
{
	free(sc->out_dir);
	sc->out_dir = xstrdup(dir);
}

/* ------------------------------------------------------------ plan */

static void stage_columns(const struct ssc_scene *sc, size_t s, char *buf,
			  size_t len)
{
	const char *c = sc->stage_columns[s] ? sc->stage_columns[s] : sc->columns;

	snprintf(buf, len, "%s", c ? c : "all data columns");
}

/* Union of the columns stages use, or NULL for every data column. */
static char *columns_to_read(const struct ssc_scene *sc)
{
	size_t len = 0;
	char *u;

	for (size_t s = 0; s < N_STAGES; s++) {
		if (!(sc->run & (1u << s)) || !(stages[s].ops->needs & SSC_NEED_DATA))
			continue;
		/* info describes what the others read, or [input]'s columns
		 * when it names them */
		if (s == S_INFO && sc->run != (1u << S_INFO) && !sc->columns)
			continue;
		if (!sc->stage_columns[s] && !sc->columns)
			return NULL;
		len += strlen(sc->stage_columns[s] ? sc->stage_columns[s] :
						     sc->columns) + 2;
	}
	if (!len)
		return sc->columns ? xstrdup(sc->columns) : NULL;
	u = calloc(1, len + 1);
	for (size_t s = 0; s < N_STAGES; s++) {
		char *copy, *items[64];
		size_t n;

		if (!(sc->run & (1u << s)) || !(stages[s].ops->needs & SSC_NEED_DATA))
			continue;
		if (s == S_INFO && sc->run != (1u << S_INFO) && !sc->columns)
			continue;
		copy = xstrdup(sc->stage_columns[s] ? sc->stage_columns[s] :
						      sc->columns);
		n = split_list(copy, items, 64);
		for (size_t i = 0; i < n; i++) {
			/* add unless present */
			char *p = u;
			size_t l = strlen(items[i]);
			bool found = false;

			while (*p) {
				char *e = strchr(p, ',');
				size_t pl = e ? (size_t)(e - p) : strlen(p);

				if (pl == l && !strncmp(p, items[i], l))
					found = true;
				p += pl + (e != NULL);
			}
			if (!found) {
				if (*u)
					strcat(u, ",");
				strcat(u, items[i]);
			}
		}
		free(copy);
	}
	return u;
}

/* An argument as the shell reads it. */
static void put_arg(FILE *f, const char *a)
{
	bool plain = *a != '\0';

	for (const char *p = a; *p; p++)
		if (!isalnum((unsigned char)*p) && !strchr("_./:=,+-@%^", *p))
			plain = false;
	if (plain) {
		fprintf(f, " %s", a);
		return;
	}
	fputs(" '", f);
	for (const char *p = a; *p; p++)
		if (*p == '\'')
			fputs("'\\''", f);
		else
			fputc(*p, f);
	fputc('\'', f);
}

/* "--name=value" (or "--name" without a value) as one argument */
static void put_opt(FILE *f, const char *name, const char *value)
{
	char buf[1200];

	snprintf(buf, sizeof(buf), "--%s%s%s", name, value ? "=" : "",
		 value ? value : "");
	put_arg(f, buf);
}

/* The option of stage s that reads the saved result of stage u. */
static const char *result_option(size_t s, size_t u)
{
	if (s == S_BUDGET)
		return "result";
	return u == S_CALIB ? "from-calib" : "from-allan";
}

/* Does stage s read the scene's [sensor] (as its --sensor would)? */
static bool takes_sensor(const struct ssc_scene *sc, size_t s)
{
	if (!sc->have_sensor)
		return false;
	if (s == S_HEADING) /* a gyro's spec only */
		return sc->sensor.quantity == SSCOPE_QUANTITY_ANGULAR_RATE;
	return s == S_ADC || s == S_BUDGET || s == S_WALK || s == S_NAVSIM;
}

/* The command line that computes what stage s computes in this scene (one
 * per capture for a stage run per capture): the same options, the same
 * inputs, the earlier results it uses as --result files. */
static void print_commands(const struct ssc_scene *sc, size_t s, FILE *f)
{
	const struct ssc_stage_ops *ops = stages[s].ops;
	bool data = ops->needs & SSC_NEED_DATA;
	size_t idx[64], n = 0, runs;
	char buf[64];

	for (size_t j = 0; data && j < sc->n_files && j < 64; j++)
		if ((sc->file_mask[s] >> j) & 1)
			idx[n++] = j;
	runs = ops->max_files == 1 && n > 1 ? n : 1;
	for (size_t r = 0; r < runs; r++) {
		fprintf(f, "     command: sensorscope %s",
			stages[s].command ? stages[s].command : ops->spec->name);
		if (ops->spec->analysis) {
			if (sc->columns && !sc->stage_columns[s])
				put_opt(f, "column", sc->columns);
			if (sc->rate_hz > 0) {
				snprintf(buf, sizeof(buf), "%.17g", sc->rate_hz);
				put_opt(f, "rate", buf);
			}
			if (sc->units)
				put_opt(f, "units", sc->units);
			if (sc->raw)
				put_opt(f, "raw", sc->raw);
			if (sc->raw && sc->scale != 1) {
				snprintf(buf, sizeof(buf), "%.17g", sc->scale);
				put_opt(f, "scale", buf);
			}
			if (sc->raw && sc->offset != 0) {
				snprintf(buf, sizeof(buf), "%.17g", sc->offset);
				put_opt(f, "offset", buf);
			}
			if (sc->allow_nan)
				put_opt(f, "allow-nan", NULL);
			if (sc->time_column)
				put_opt(f, "time-column", sc->time_column);
			if (sc->temp_column)
				put_opt(f, "temp-column", sc->temp_column);
			if (sc->topic)
				put_opt(f, "topic", sc->topic);
			if (sc->calibration)
				put_opt(f, "calibration", sc->calibration);
		}
		/* navsim applies its own --sensor files first */
		if (takes_sensor(sc, s) && s != S_NAVSIM)
			put_opt(f, "sensor", sc->sensor_path ? sc->sensor_path :
				"(the scene's [sensor])");
		for (size_t a = 0; s == S_ADC && a < sc->n_adc; a++)
			put_opt(f, "adc", sc->adc_paths[a]);
		if (s == S_ADC && sc->adc_ini)
			put_opt(f, "adc", "(the scene's [adc])");
		for (size_t u = 0; u < N_STAGES; u++)
			if (sc->uses[s] & (1u << u)) {
				char p[1100];

				snprintf(p, sizeof(p), "%s/%s.json", sc->out_dir,
					 stages[u].name);
				put_opt(f, result_option(s, u), p);
			}
		for (int k = 1; k < sc->n_args[s]; k++)
			put_arg(f, sc->args[s][k]);
		if (takes_sensor(sc, s) && s == S_NAVSIM)
			put_opt(f, "sensor", sc->sensor_path ? sc->sensor_path :
				"(the scene's [sensor])");
		for (size_t j = 0; j < n; j++)
			if (runs == 1 || j == r)
				put_arg(f, sc->files[idx[j]]);
		fputc('\n', f);
	}
}

void ssc_scene_plan(const struct ssc_scene *sc, FILE *f)
{
	char *cols = columns_to_read(sc), buf[256];
	size_t k = 1;

	fprintf(f, "scene: %s\n", sc->path ? sc->path : "(inferred from the data)");
	fprintf(f, "inputs (each read once, columns: %s):\n",
		cols ? cols : "every data column");
	for (size_t i = 0; i < sc->n_files; i++)
		fprintf(f, "  %s\n", sc->files[i]);
	if (sc->have_sensor)
		fprintf(f, "sensor: %s%s%s\n", sc->sensor.name,
			sc->sensor_path ? " from " : "",
			sc->sensor_path ? sc->sensor_path : "");
	fprintf(f, "stages to run, in order:\n");
	for (size_t i = 0; i < sc->n_order; i++) {
		size_t s = sc->order[i];

		char uses[128] = "";

		if (stages[s].ops->needs & SSC_NEED_DATA)
			stage_columns(sc, s, buf, sizeof(buf));
		else
			snprintf(buf, sizeof(buf), "none (no capture data)");
		for (size_t u = 0; u < N_STAGES; u++)
			if (sc->uses[s] & (1u << u)) {
				size_t l = strlen(uses);

				snprintf(uses + l, sizeof(uses) - l, "%s%s",
					 l ? ", " : "; uses the results of ",
					 stages[u].name);
			}
		fprintf(f, "  %zu. %-10s %s%s; channels: %s", k++,
			stages[s].name, sc->why[s], uses, buf);
		if ((stages[s].ops->needs & SSC_NEED_DATA) && sc->n_files > 1) {
			size_t nf = 0;

			for (size_t j = 0; j < sc->n_files && j < 64; j++)
				nf += (sc->file_mask[s] >> j) & 1;
			if (nf < sc->n_files) {
				fprintf(f, "; files:");
				for (size_t j = 0; j < sc->n_files && j < 64; j++)
					if ((sc->file_mask[s] >> j) & 1)
						fprintf(f, " %s", sc->files[j]);
			}
			if (stages[s].ops->max_files == 1 && nf > 1)
				fprintf(f, "; once per file");
		}
		fputc('\n', f);
		print_commands(sc, s, f);
	}
	fprintf(f, "stages skipped:%s\n", sc->run == (1u << N_STAGES) - 1 ?
		" none" : "");
	for (size_t s = 0; s < N_STAGES; s++)
		if (!(sc->run & (1u << s)))
			fprintf(f, "  %-10s %s\n", stages[s].name, sc->why[s]);
	fprintf(f, "outputs in %s:", sc->out_dir);
	if (sc->formats & SSC_OUT_HTML)
		fprintf(f, " report.html");
	if (sc->formats & SSC_OUT_JSON)
		fprintf(f, " report.json");
	if (sc->formats & SSC_OUT_TEXT)
		fprintf(f, " report.txt");
	/* each analysis' own files, by name: its JSON and its figure (one
	 * per file, NAME-1 ..., for one run per file) */
	for (size_t i = 0; i < sc->n_order; i++) {
		size_t s = sc->order[i], nf = 0;
		bool per_file;

		for (size_t j = 0; j < sc->n_files && j < 64; j++)
			nf += (sc->file_mask[s] >> j) & 1;
		per_file = (stages[s].ops->needs & SSC_NEED_DATA) &&
			   stages[s].ops->max_files == 1 && nf > 1;
		if (sc->formats & SSC_OUT_JSON)
			fprintf(f, " %s.json", stages[s].name);
		for (int e = 0; e < 2; e++) {
			const char *ext = e ? ".svg" : ".png";

			/* PNG only where a PNG can be drawn, as the run does */
			if (!(sc->formats & (e ? SSC_OUT_SVG : SSC_OUT_PNG)) ||
			    (!e && !ssc_plot_available()) ||
			    sc->no_plot[s] || !stages[s].ops->plot)
				continue;
			if (per_file && nf > 3)
				fprintf(f, " %s-1%s .. %s-%zu%s", stages[s].name, ext,
					stages[s].name, nf, ext);
			else if (per_file)
				for (size_t r = 1; r <= nf; r++)
					fprintf(f, " %s-%zu%s", stages[s].name, r, ext);
			else
				fprintf(f, " %s%s", stages[s].name, ext);
		}
	}
	fputc('\n', f);
	free(cols);
}

/* ------------------------------------------------------------ running */

static bool tracing(void)
{
	const char *t = getenv("SSCOPE_TRACE");

	return t && *t && strcmp(t, "0");
}

static int write_text(const char *path, const char *text)
{
	struct ssc_common co = { .cmd = "run", .output = path };
	struct ssc_out o;
	int rc = ssc_out_open(&co, &o);

	if (rc)
		return rc;
	fputs(text, o.f);
	return ssc_out_close(&co, &o, !ferror(o.f));
}

static int write_json(const char *path, json_t *j)
{
	struct ssc_common co = { .cmd = "run", .output = path };

	json_incref(j);
	return ssc_emit_json(&co, j);
}

/* What the scene keeps of a stage: one call per run (one per capture for
 * a one-capture stage on several captures) and the outputs made of them. */
struct stage_out {
	struct ssc_stage_call *calls;
	size_t n_calls;
	json_t *json;    /* the stage's result, or {"command", "files"} */
	char *text;
	json_t *summary;
	struct ssc_result *results; /* the typed results, for later stages */
};

static void stage_out_free(struct stage_out *o)
{
	for (size_t i = 0; i < o->n_calls; i++) {
		ssc_stage_call_clear(&o->calls[i]);
		free((void *)o->calls[i].paths);
	}
	free(o->calls);
	free(o->results);
	json_decref(o->json);
	json_decref(o->summary);
	free(o->text);
	memset(o, 0, sizeof(*o));
}

/* Outputs against inputs before anything is written: the report folder
 * holds no input, no stage option writes over one (output.c). */
static int guard_paths(const struct ssc_scene *sc, const char *cmd)
{
	size_t n = 0, max = sc->n_files + sc->n_io + sc->n_adc + 3;
	struct ssc_guard_item *it = calloc(max, sizeof(*it));
	int rc;

	if (!it) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	for (size_t i = 0; i < sc->n_files; i++)
		it[n++] = (struct ssc_guard_item){ NULL, sc->files[i], SSC_GUARD_IN };
	for (size_t i = 0; i < sc->n_adc; i++)
		it[n++] = (struct ssc_guard_item){ NULL, sc->adc_paths[i], SSC_GUARD_IN };
	for (size_t i = 0; i < sc->n_io; i++)
		it[n++] = (struct ssc_guard_item){ sc->io_out[i], sc->io_path[i],
						   sc->io_out[i] ? SSC_GUARD_OUT :
								      SSC_GUARD_IN };
	if (sc->path)
		it[n++] = (struct ssc_guard_item){ NULL, sc->path, SSC_GUARD_IN };
	if (sc->sensor_path)
		it[n++] = (struct ssc_guard_item){ NULL, sc->sensor_path, SSC_GUARD_IN };
	it[n++] = (struct ssc_guard_item){ "report folder", sc->out_dir, SSC_GUARD_DIR };
	rc = ssc_guard_check(cmd, it, n, false);
	free(it);
	return rc;
}

/* Remove a figure's files in the formats not kept. */
static void unlink_fig(const char *base, unsigned keep)
{
	char p[1100];

	if (!(keep & SSC_OUT_SVG)) {
		snprintf(p, sizeof(p), "%s.svg", base);
		unlink(p);
	}
	if (!(keep & SSC_OUT_PNG)) {
		snprintf(p, sizeof(p), "%s.png", base);
		unlink(p);
	}
}

/* The figures of one stage as the report names them. */
struct fig_names {
	char svg[64][1100];
	const char *svgp[65], *link[65];
};

/* The stages that ran, for the report: results, texts and figures (their
 * SVG files, and the names to link them by when the files stay). */
static size_t report_stages(const struct ssc_scene *sc,
			    const struct stage_out *outs,
			    char *(*figs)[64], struct fig_names *fn,
			    struct ssc_report_stage *st)
{
	size_t n = 0;

	for (size_t i = 0; i < sc->n_order; i++) {
		size_t s = sc->order[i], r;

		for (r = 0; r < 64 && figs[s][r]; r++) {
			const char *slash = strrchr(figs[s][r], '/');

			snprintf(fn[s].svg[r], sizeof(fn[s].svg[r]), "%s.svg",
				 figs[s][r]);
			fn[s].svgp[r] = fn[s].svg[r];
			slash = strrchr(fn[s].svg[r], '/');
			fn[s].link[r] = sc->formats & SSC_OUT_SVG ?
					(slash ? slash + 1 : fn[s].svg[r]) :
					NULL;
		}
		fn[s].svgp[r] = NULL;
		st[n] = (struct ssc_report_stage){
			.name = stages[s].name,
			.title = stages[s].ops->title,
			.why = sc->why[s],
			.definitions = stages[s].definitions,
			.result = outs[s].json,
			.text = outs[s].text,
			.figs = fn[s].svgp,
			.links = fn[s].link,
		};
		n++;
	}
	return n;
}

static void html_report(struct ssc_scene *sc, struct ssc_html *h,
			json_t *summary, const struct stage_out *outs,
			char *(*figs)[64], const char *cols)
{
	char buf[512], now[64];
	time_t t = time(NULL);
	static const char *const prov_head[] = { "input", "bytes", "SHA-256" };
	struct ssc_report_stage rs[N_STAGES];
	struct fig_names *fn = calloc(N_STAGES, sizeof(*fn));
	size_t n = fn ? report_stages(sc, outs, figs, fn, rs) : 0;

	strftime(now, sizeof(now), "%Y-%m-%d %H:%M:%S UTC", gmtime(&t));
	snprintf(buf, sizeof(buf), "%s", sc->title ? sc->title :
		 sc->n_files ? sc->files[0] : "sensorscope report");
	ssc_html_h1(h, buf);
	ssc_html_note(h, "sensorscope %s, %s. Intervals are the stated confidence level of each analysis.",
		      PACKAGE_VERSION, now);
	ssc_report_body(h, summary, rs, n);
	ssc_html_h2(h, "provenance", "Provenance");
	ssc_html_table_begin(h, NULL, prov_head, 3);
	for (size_t i = 0; i < sc->n_files; i++) {
		char hex[65] = "", bytes[32] = "";
		struct stat st;
		const char *cells[3];

		if (ssc_hashjob_get(sc->hashes, sc->files, i, hex))
			snprintf(hex, sizeof(hex), "(unreadable)");
		if (!stat(sc->files[i], &st))
			snprintf(bytes, sizeof(bytes), "%lld", (long long)st.st_size);
		cells[0] = sc->files[i];
		cells[1] = bytes;
		cells[2] = hex;
		ssc_html_table_row(h, cells, 3);
	}
	if (sc->path) {
		char hex[65] = "";
		const char *cells[3] = { sc->path, "", hex };

		ssc_sha256_file(sc->path, hex);
		ssc_html_table_row(h, cells, 3);
	}
	ssc_html_table_end(h);
	ssc_html_p(h, "Tool: sensorscope %s. Scene: %s. Columns read: %s.",
		   PACKAGE_VERSION, sc->path ? sc->path : "inferred from the data",
		   cols ? cols : "every data column");
	{
		char line[1024];
		size_t used = (size_t)snprintf(line, sizeof(line),
					       "Wall time: reading %.3g s",
					       sc->t_read_s);

		for (size_t i = 0; i < sc->n_order && used < sizeof(line); i++)
			used += (size_t)snprintf(line + used, sizeof(line) - used,
						 "; %s %.3g s",
						 stages[sc->order[i]].name,
						 sc->t_stage_s[sc->order[i]]);
		ssc_html_p(h, "%s.", line);
	}
	for (size_t i = 0; i < sc->n_order; i++) {
		size_t s = sc->order[i];
		const char *sec = stages[s].name;
		char line[1024] = "";
		size_t used = 0;

		if (!sc->ini || !ssc_ini_has_section(sc->ini, sec))
			continue;
		for (size_t k = 0; k < ssc_ini_n_keys(sc->ini, sec); k++) {
			const char *v, *key = ssc_ini_key(sc->ini, sec, k, &v, NULL);
			int w = snprintf(line + used, sizeof(line) - used, "%s%s = %s",
					 used ? "; " : "", key, v);

			if (w > 0 && (size_t)w < sizeof(line) - used)
				used += (size_t)w;
		}
		ssc_html_p(h, "Options of [%s]: %s", sec, used ? line : "(defaults)");
	}
	free(fn);
}

/* The shared options of the scene ([input], or the report's command
 * line), as a stage sees them. */
static void scene_common(const struct ssc_scene *sc, const char *cmd,
			 const struct ssc_common *cli, struct ssc_common *co)
{
	memset(co, 0, sizeof(*co));
	co->cmd = cmd;
	co->quiet = cli ? cli->quiet : sc->quiet;
	co->progress = cli ? cli->progress : 0;
	co->columns = sc->columns;
	co->units = sc->units;
	co->rate_hz = sc->rate_hz;
	co->raw = sc->raw;
	co->scale = sc->scale;
	co->offset = sc->offset;
	co->allow_nan = sc->allow_nan;
	co->time_column = sc->time_column;
	co->temp_column = sc->temp_column;
	co->topic = sc->topic;
	co->calibration = sc->calibration;
	/* a scene's stages give their results as the JSON objects of their
	 * commands (the files, the report, the terminal summary): checked
	 * as `CMD --format json` is */
	co->format = SSC_FMT_JSON;
}

/* A call of stage s with the scene's inputs and specifications. */
static void stage_call(const struct ssc_scene *sc, size_t s,
		       const struct ssc_common *base, struct ssc_stage_call *c)
{
	memset(c, 0, sizeof(*c));
	c->name = stages[s].name;
	c->argc = sc->n_args[s];
	c->argv = sc->args[s];
	c->where = (const char *const *)sc->where[s];
	c->context = sc->path;
	c->base = base;
	c->sensor = sc->have_sensor ? &sc->sensor : NULL;
	c->sensor_path = sc->sensor_path;
	c->adc_paths = (const char *const *)sc->adc_paths;
	c->n_adc = sc->n_adc;
	c->adc_ini = sc->adc_ini;
}

/* Check every stage's options as its command would (at load time, so a
 * bad value stops the scene before anything runs). */
static int check_stages(const char *cmd, struct ssc_scene *sc)
{
	struct ssc_common base;

	scene_common(sc, cmd, NULL, &base);
	for (size_t s = 0; s < N_STAGES; s++) {
		struct ssc_stage_call c;
		int rc;

		if (!(sc->run & (1u << s)))
			continue;
		stage_call(sc, s, &base, &c);
		c.check_only = true;
		rc = ssc_stage_exec(stages[s].ops, &c);
		if (rc)
			return rc;
	}
	return SSC_EXIT_OK;
}

/* Run stage s once on the captures idx[0..n) (run > 0: the run-th of a
 * stage run per capture, drawn into STAGE-run.svg/png).  *fig_out gets the
 * figure's path without its extension when one was drawn. */
static int run_stage(struct ssc_scene *sc, size_t s,
		     const struct ssc_common *base, struct sscope_capture **caps,
		     const size_t *idx, size_t n, int run,
		     const struct stage_out *outs, struct ssc_stage_call *c,
		     char **fig_out)
{
	struct sscope_capture **v = calloc(n ? n : 1, sizeof(*v));
	const char **paths = calloc(n ? n : 1, sizeof(*paths));
	struct ssc_result *up = NULL, *earlier = NULL;
	size_t n_up = 0, n_earlier = 0;
	char base_name[1024], fig[1100];
	bool svg = sc->formats & (SSC_OUT_SVG | SSC_OUT_HTML);
	bool png = (sc->formats & SSC_OUT_PNG) && ssc_plot_available();
	int rc;

	if (!v || !paths)
		exit(SSC_EXIT_FAIL);
	for (size_t f = 0; f < n; f++) {
		v[f] = caps[idx[f]];
		paths[f] = sc->files[idx[f]];
	}
	for (size_t u = 0; u < N_STAGES; u++)
		if (sc->uses[s] & (1u << u))
			n_up += outs[u].n_calls;
	up = calloc(n_up ? n_up : 1, sizeof(*up));
	if (!up)
		exit(SSC_EXIT_FAIL);
	n_up = 0;
	for (size_t u = 0; u < N_STAGES; u++)
		if (sc->uses[s] & (1u << u))
			for (size_t r = 0; r < outs[u].n_calls; r++)
				up[n_up++] = outs[u].calls[r].result;
	/* every result so far (outs[s] itself: earlier runs of a stage run
	 * per capture) */
	for (size_t u = 0; u < N_STAGES; u++)
		n_earlier += outs[u].n_calls;
	earlier = calloc(n_earlier ? n_earlier : 1, sizeof(*earlier));
	if (!earlier)
		exit(SSC_EXIT_FAIL);
	n_earlier = 0;
	for (size_t u = 0; u < N_STAGES; u++)
		for (size_t r = 0; r < outs[u].n_calls; r++)
			earlier[n_earlier++] = outs[u].calls[r].result;
	if (run)
		snprintf(base_name, sizeof(base_name), "%s/%s-%d", sc->out_dir,
			 stages[s].name, run);
	else
		snprintf(base_name, sizeof(base_name), "%s/%s", sc->out_dir,
			 stages[s].name);
	/* one drawing, in the formats asked for (the HTML inlines the SVG) */
	snprintf(fig, sizeof(fig), "%s%s", base_name,
		 svg && png ? SSC_PLOT_SVG_AND_PNG : svg ? ".svg" : ".png");
	stage_call(sc, s, base, c);
	c->caps = v;
	c->paths = paths;
	c->n_caps = n;
	c->upstream = up;
	c->n_upstream = n_up;
	c->earlier = earlier;
	c->n_earlier = n_earlier;
	/* JSON for the files, the HTML report and the summary printed on
	 * the terminal (its warnings) */
	c->want = SSC_WANT_SUMMARY |
		  (sc->formats & (SSC_OUT_JSON | SSC_OUT_HTML) || !sc->quiet ?
		   SSC_WANT_JSON : 0) |
		  (sc->formats & (SSC_OUT_TEXT | SSC_OUT_HTML) ? SSC_WANT_TEXT : 0);
	/* a stage that draws nothing is given no figure to draw */
	c->plot_path = (svg || png) && !sc->no_plot[s] && stages[s].ops->plot ?
		       fig : NULL;
	rc = ssc_stage_exec(stages[s].ops, c);
	snprintf(fig, sizeof(fig), "%s%s", base_name, svg ? ".svg" : ".png");
	if (!rc && c->plot_path && access(fig, R_OK) == 0)
		*fig_out = xstrdup(base_name);
	c->plot_path = NULL;
	c->upstream = NULL;
	c->n_upstream = 0;
	c->earlier = NULL;
	c->n_earlier = 0;
	c->caps = NULL;
	free(up);
	free(earlier);
	free(v);
	/* c->paths stays: the result may point to it (stage_out_free) */
	return rc;
}

/* A stage's outputs from its calls: one call gives its own; a stage run
 * per capture gives {"command", "files": [result...]}, the texts one after
 * the other and summary rows that name their file. */
static void assemble(struct stage_out *o, bool fan, const char *name,
		     char *const *files, const size_t *idx)
{
	struct ssc_membuf m;

	o->summary = json_array();
	o->results = calloc(o->n_calls ? o->n_calls : 1, sizeof(*o->results));
	if (!o->summary || !o->results)
		exit(SSC_EXIT_FAIL);
	for (size_t i = 0; i < o->n_calls; i++)
		o->results[i] = o->calls[i].result;
	if (!fan) {
		struct ssc_stage_call *c = &o->calls[0];

		o->json = c->json;
		o->text = c->text;
		c->json = NULL;
		c->text = NULL;
		json_array_extend(o->summary, c->summary);
		return;
	}
	if (o->calls[0].json) {
		json_t *arr = json_array();

		o->json = json_object();
		json_object_set_new(o->json, "command", json_string(name));
		for (size_t i = 0; i < o->n_calls; i++)
			json_array_append(arr, o->calls[i].json);
		json_object_set_new(o->json, "files", arr);
	}
	if (o->calls[0].text && !ssc_membuf_open(&m)) {
		for (size_t i = 0; i < o->n_calls; i++)
			fprintf(m.f, "%s%s", i ? "\n" : "", o->calls[i].text);
		o->text = ssc_membuf_take(&m);
	}
	for (size_t i = 0; i < o->n_calls; i++) {
		const char *path = files[idx[i]];
		const char *b = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;

		for (size_t r = 0; r < json_array_size(o->calls[i].summary); r++) {
			json_t *row = json_array_get(o->calls[i].summary, r);
			const char *ch = json_string_value(json_object_get(row, "channel"));
			char buf[512];

			snprintf(buf, sizeof(buf), "%s%s%s", b, ch && *ch ? ": " : "",
				 ch ? ch : "");
			json_object_set_new(row, "channel", json_string(buf));
			json_array_append(o->summary, row);
		}
	}
}

static double wall_s(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *open_drawing(void *arg)
{
	(void)arg;
	(void)ssc_plot_available();
	return NULL;
}

int ssc_scene_run(struct ssc_scene *sc, const struct ssc_common *co_cli)
{
	pthread_t cv_tid;
	bool cv_started = false;
	struct ssc_common co, base;
	struct sscope_capture **caps = NULL;
	struct stage_out outs[N_STAGES];
	char *figs[N_STAGES][64] = { { 0 } };
	json_t *results = json_object(), *summary = json_array(), *all;
	char *cols = columns_to_read(sc);
	struct ssc_membuf txt;
	struct ssc_outdir od;
	const char *stage_names[N_STAGES + 1] = { NULL };
	char *final_dir = sc->out_dir;
	int rc = SSC_EXIT_OK, e;

	memset(outs, 0, sizeof(outs));
	scene_common(sc, co_cli->cmd, co_cli, &base);
	co = base;
	co.columns = cols;
	/* the report is built in a staging folder beside out_dir and put in
	 * its place only when every stage succeeded */
	for (size_t s = 0; s < N_STAGES; s++)
		stage_names[s] = stages[s].name;
	rc = guard_paths(sc, co.cmd);
	if (!rc)
		rc = ssc_outdir_begin(co.cmd, "report folder", sc->out_dir,
				      stage_names, &od);
	if (rc) {
		free(cols);
		json_decref(results);
		json_decref(summary);
		return rc;
	}
	sc->out_dir = od.dir;
	caps = calloc(sc->n_files ? sc->n_files : 1, sizeof(*caps));
	/* the report's provenance hashes, beside the reading */
	if (sc->formats & SSC_OUT_HTML)
		sc->hashes = ssc_hashjob_start(sc->files, sc->n_files);
	/* the drawing module opened beside the reading, not in the first
	 * stage that draws */
	if ((sc->formats & SSC_OUT_PNG) &&
	    !pthread_create(&cv_tid, NULL, open_drawing, NULL))
		cv_started = true;
	sc->t_read_s = wall_s();
	for (size_t i = 0; i < sc->n_files && !rc; i++) {
		if (tracing())
			fprintf(stderr, "trace: read %s columns %s\n", sc->files[i],
				cols ? cols : "(all data columns)");
		rc = ssc_load(&co, sc->files[i], &caps[i]);
	}
	sc->t_read_s = wall_s() - sc->t_read_s;
	if (cv_started)
		pthread_join(cv_tid, NULL);
	if (tracing())
		fprintf(stderr, "trace: time read %.3f s\n", sc->t_read_s);
	if (rc)
		goto done;
	for (size_t i = 0; i < sc->n_order && !rc; i++) {
		size_t s = sc->order[i];
		size_t idx[64], n_in = 0, runs;
		bool fan;

		for (size_t f = 0; f < sc->n_files && f < 64; f++)
			if (sc->file_mask[s] & ((uint64_t)1 << f))
				idx[n_in++] = f;
		if (!(stages[s].ops->needs & SSC_NEED_DATA))
			n_in = 0;
		/* a one-capture stage runs once per capture */
		fan = stages[s].ops->max_files == 1 && n_in > 1;
		runs = fan ? n_in : 1;
		if (tracing())
			fprintf(stderr, "trace: stage %s\n", stages[s].name);
		outs[s].calls = calloc(runs, sizeof(*outs[s].calls));
		if (!outs[s].calls)
			exit(SSC_EXIT_FAIL);
		sc->t_stage_s[s] = wall_s();
		for (size_t r = 0; r < runs && !rc; r++) {
			rc = run_stage(sc, s, &base, caps, fan ? idx + r : idx,
				       fan ? 1 : n_in, fan ? (int)r + 1 : 0, outs,
				       &outs[s].calls[r], &figs[s][r]);
			outs[s].n_calls++;
		}
		sc->t_stage_s[s] = wall_s() - sc->t_stage_s[s];
		if (tracing())
			fprintf(stderr, "trace: time %s %.3f s\n", stages[s].name,
				sc->t_stage_s[s]);
		if (rc == SSC_EXIT_FAIL && !sc->path && s != S_INFO) {
			/* an inferred analysis the data do not support: the
			 * report goes on without it and says so */
			ssc_warn(&co, "%s: not in the report (%s)",
				 stages[s].name, "the reason is above");
			set_why(sc, s, "inferred, but refused by the data: %s",
				ssc_last_error());
			stage_out_free(&outs[s]);
			for (size_t r = 0; r < 64 && figs[s][r]; r++) {
				unlink_fig(figs[s][r], 0);
				free(figs[s][r]);
				figs[s][r] = NULL;
			}
			rc = SSC_EXIT_OK;
			continue;
		}
		if (rc)
			break;
		assemble(&outs[s], fan, stages[s].name, sc->files, idx);
		if (outs[s].json)
			json_object_set(results, stages[s].name, outs[s].json);
		for (size_t r = 0; r < json_array_size(outs[s].summary); r++) {
			json_t *row = json_array_get(outs[s].summary, r);

			json_object_set_new(row, "stage", json_string(stages[s].name));
			json_array_append(summary, row);
		}
		if (sc->formats & SSC_OUT_JSON) {
			char p[1024];

			snprintf(p, sizeof(p), "%s/%s.json", sc->out_dir,
				 stages[s].name);
			if (write_json(p, outs[s].json))
				rc = SSC_EXIT_FAIL;
		}
	}
	if (rc)
		goto done;
	all = json_object();
	json_object_set_new(all, "command", json_string("run"));
	json_object_set_new(all, "scene", sc->path ? json_string(sc->path) : json_null());
	json_object_set(all, "summary", summary);
	json_object_set(all, "results", results);
	{
		json_t *tm = json_object();

		json_object_set_new(tm, "read", json_real(sc->t_read_s));
		for (size_t i = 0; i < sc->n_order; i++)
			json_object_set_new(tm, stages[sc->order[i]].name,
					    json_real(sc->t_stage_s[sc->order[i]]));
		json_object_set_new(all, "wall_time_s", tm);
	}
	if (sc->formats & SSC_OUT_JSON) {
		char p[1024];

		snprintf(p, sizeof(p), "%s/report.json", sc->out_dir);
		if (write_json(p, all))
			rc = SSC_EXIT_FAIL;
	}
	json_decref(all);
	if (!rc && (sc->formats & SSC_OUT_TEXT) && !ssc_membuf_open(&txt)) {
		char p[1024], *t;

		for (size_t i = 0; i < sc->n_order; i++) {
			size_t s = sc->order[i];

			fprintf(txt.f, "== %s (%s)\n%s\n", stages[s].ops->title,
				stages[s].name, outs[s].text ? outs[s].text : "");
		}
		t = ssc_membuf_take(&txt);
		snprintf(p, sizeof(p), "%s/report.txt", sc->out_dir);
		if (!t || write_text(p, t))
			rc = SSC_EXIT_FAIL;
		free(t);
	}
	if (!rc && (sc->formats & SSC_OUT_HTML)) {
		struct ssc_html *h = ssc_html_new(sc->title ? sc->title :
						  "sensorscope report");
		char p[1024];

		html_report(sc, h, summary, outs, figs, cols);
		snprintf(p, sizeof(p), "%s/report.html", sc->out_dir);
		e = ssc_html_write(h, p);
		ssc_html_free(h);
		if (e)
			rc = ssc_write_failed(co.cmd, p, e);
	}
	for (size_t s = 0; s < N_STAGES; s++)
		for (size_t r = 0; r < 64 && figs[s][r]; r++)
			unlink_fig(figs[s][r], sc->formats);
	if (!rc && !sc->quiet) {
		/* the results for the person at the terminal */
		struct ssc_report_stage st[N_STAGES];
		struct fig_names *fn = calloc(N_STAGES, sizeof(*fn));
		size_t n = fn ? report_stages(sc, outs, figs, fn, st) : 0;

		ssc_report_terminal(stdout, summary, st, n);
		free(fn);
	}
done:
	ssc_hashjob_free(sc->hashes);
	sc->hashes = NULL;
	sc->out_dir = final_dir;
	if (!rc)
		rc = ssc_outdir_commit(co.cmd, &od);
	else
		ssc_outdir_abort(&od);
	if (!rc && (sc->formats & SSC_OUT_HTML) && !sc->quiet && !co.quiet)
		fprintf(stderr, "sensorscope: %s: wrote %s/report.html\n", co.cmd,
			sc->out_dir);
	/* later stages' results point into earlier ones' inputs: results
	 * first, captures last */
	for (size_t s = 0; s < N_STAGES; s++) {
		stage_out_free(&outs[s]);
		for (size_t r = 0; r < 64; r++)
			free(figs[s][r]);
	}
	for (size_t i = 0; caps && i < sc->n_files; i++)
		sscope_capture_free(caps[i]);
	free(caps);
	json_decref(results);
	json_decref(summary);
	free(cols);
	return rc;
}
