/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The one driver of a stage (see stage.h), for the command line and for
 * scenes, and helpers shared by stages.
 */
#include "stage.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

int ssc_membuf_open(struct ssc_membuf *m)
{
	m->buf = NULL;
	m->len = 0;
	m->f = open_memstream(&m->buf, &m->len);
	return m->f ? 0 : -ENOMEM;
}

char *ssc_membuf_take(struct ssc_membuf *m)
{
	bool bad = !m->f || ferror(m->f);
	char *b;

	if (m->f && fclose(m->f) != 0)
		bad = true;
	m->f = NULL;
	b = m->buf;
	m->buf = NULL;
	if (bad) {
		free(b);
		return NULL;
	}
	return b;
}

void ssc_summary_add(json_t *summary, const char *channel,
		     const char *quantity, double value, double lo, double hi,
		     const char *unit, const char *note)
{
	json_t *o;

	if (!summary)
		return;
	o = json_object();
	json_object_set_new(o, "channel", json_string(channel ? channel : ""));
	json_object_set_new(o, "quantity", json_string(quantity));
	json_object_set_new(o, "value", ssc_jreal(value));
	json_object_set_new(o, "lo", ssc_jreal(lo));
	json_object_set_new(o, "hi", ssc_jreal(hi));
	json_object_set_new(o, "unit", json_string(unit ? unit : ""));
	json_object_set_new(o, "note", json_string(note ? note : ""));
	json_array_append_new(summary, o);
}

void ssc_summary_warn_last(json_t *summary)
{
	json_t *last = json_array_get(summary, json_array_size(summary) - 1);

	if (last)
		json_object_set_new(last, "status", json_string("warning"));
}

void ssc_result_free(struct ssc_result *r)
{
	if (r->data && r->ops && r->ops->free_result)
		r->ops->free_result(r->data);
	r->data = NULL;
	r->ops = NULL;
}

void ssc_stage_call_clear(struct ssc_stage_call *call)
{
	ssc_result_free(&call->result);
	json_decref(call->json);
	json_decref(call->summary);
	free(call->text);
	call->json = NULL;
	call->summary = NULL;
	call->text = NULL;
	for (size_t i = 0; i < call->n_views; i++)
		sscope_capture_free(call->views[i]);
	free(call->views);
	call->views = NULL;
	call->n_views = 0;
}

const struct ssc_result *ssc_stage_upstream(const struct ssc_stage_env *env,
					    const struct ssc_stage_ops *ops,
					    size_t *n)
{
	const struct ssc_result *first = NULL;
	size_t k = 0;

	for (size_t i = 0; i < env->n_upstream; i++)
		if (env->upstream[i].ops == ops && env->upstream[i].data) {
			if (!first)
				first = &env->upstream[i];
			k++;
		}
	if (n)
		*n = k;
	return first;
}

/* SSCOPE_TRACE=1: the time of each part of a stage on stderr, wall and
 * CPU (every thread of the process) */
struct trace_t {
	double wall, cpu; /* wall < 0: not tracing */
};

static struct trace_t trace_clock(void)
{
	const char *t = getenv("SSCOPE_TRACE");
	struct trace_t r = { -1, 0 };
	struct timespec ts;

	if (!t || !*t || !strcmp(t, "0"))
		return r;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	r.wall = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	r.cpu = (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
	return r;
}

/* "trace: STAGE PART S s (CPU C s)" since *t0, and *t0 set to now */
static void trace_part(const struct ssc_stage_ops *ops, const char *part,
		       struct trace_t *t0)
{
	struct trace_t t;

	if (t0->wall < 0)
		return;
	t = trace_clock();
	fprintf(stderr, "trace: %s %s %.3f s (CPU %.3f s)\n", ops->spec->name,
		part, t.wall - t0->wall, t.cpu - t0->cpu);
	*t0 = t;
}

/* The result's text, or NULL when out of memory. */
static char *render_text(const struct ssc_stage_ops *ops, const void *opts,
			 const void *res,
			 void (*fn)(FILE *, const void *, const void *))
{
	struct ssc_membuf m;

	(void)ops;
	if (ssc_membuf_open(&m))
		return NULL;
	fn(m.f, opts, res);
	return ssc_membuf_take(&m);
}

/* The command's output: its --format to -o or stdout. */
static int present(const struct ssc_stage_ops *ops, const struct ssc_common *co,
		   const void *opts, const void *res)
{
	struct ssc_out o;
	int rc;

	if (co->format == SSC_FMT_JSON)
		return ops->emit_json ? ops->emit_json(co, opts, res) :
					ssc_emit_json(co, ops->json(opts, res));
	rc = ssc_out_open(co, &o);
	if (rc)
		return rc;
	if (co->format == SSC_FMT_CSV)
		ops->csv(o.f, opts, res);
	else
		ops->text(o.f, opts, res);
	return ssc_out_close(co, &o, !ferror(o.f));
}

static int cmp_str(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

static bool capture_name(const char *name)
{
	static const char *const skip[] = { ".ini", ".md", ".json", ".yaml", ".yml",
					    ".svg", ".png", ".html" };
	const char *dot = strrchr(name, '.');

	if (name[0] == '.')
		return false;
	for (size_t i = 0; dot && i < sizeof(skip) / sizeof(skip[0]); i++)
		if (!strcasecmp(dot, skip[i]))
			return false;
	return true;
}

/* the operands a stage with ops->folders reads: path, and from a
 * manifest the unit's name, channels (-c) and temperature column */
struct operands {
	char **path, **label, **columns, **temp;
	size_t n, cap;
};

/* env->load of a streaming stage: what step 3 below does for one file */
struct load_ctx {
	const struct ssc_common *co;
	const struct operands *in;
};

static int load_one(const struct ssc_stage_env *env, size_t i,
		    struct sscope_capture **cap)
{
	const struct load_ctx *l = env->load_ctx;
	struct ssc_common cu = *l->co;
	int rc;

	if (l->in->n && l->in->columns[i])
		cu.columns = l->in->columns[i];
	if (l->in->n && l->in->temp[i])
		cu.temp_column = l->in->temp[i];
	rc = ssc_load(&cu, env->paths[i], cap);
	/* the stage reads samples at the capture's rate: the time column,
	 * analysed at load (gaps, jitter), is given back before the
	 * analysis (one unit's memory is its samples) */
	if (!rc && (*cap)->time_s && !(*cap)->is_view) {
		free((*cap)->time_s);
		(*cap)->time_s = NULL;
	}
	return rc;
}

static void operands_free(struct operands *o)
{
	for (size_t i = 0; i < o->n; i++) {
		free(o->path[i]);
		free(o->label[i]);
		free(o->columns[i]);
		free(o->temp[i]);
	}
	free(o->path);
	free(o->label);
	free(o->columns);
	free(o->temp);
	memset(o, 0, sizeof(*o));
}

static char *dup_or_null(const char *s)
{
	return s && *s ? strdup(s) : NULL;
}

/* append @p dir / @p name (name NULL: dir alone) with the manifest's
 * fields (may be NULL) */
static int push(struct operands *o, const char *dir, const char *name,
		const char *label, const char *columns, const char *temp)
{
	char *s;

	if (o->n == o->cap) {
		size_t c = o->cap ? 2 * o->cap : 16;
		char **v[4] = { realloc(o->path, c * sizeof(char *)), NULL, NULL, NULL };

		if (v[0])
			o->path = v[0];
		v[1] = v[0] ? realloc(o->label, c * sizeof(char *)) : NULL;
		if (v[1])
			o->label = v[1];
		v[2] = v[1] ? realloc(o->columns, c * sizeof(char *)) : NULL;
		if (v[2])
			o->columns = v[2];
		v[3] = v[2] ? realloc(o->temp, c * sizeof(char *)) : NULL;
		if (!v[3])
			return -ENOMEM;
		o->temp = v[3];
		o->cap = c;
	}
	s = malloc(strlen(dir) + (name ? strlen(name) + 1 : 0) + 1);
	if (!s)
		return -ENOMEM;
	if (name && name[0] != '/')
		sprintf(s, "%s%s%s", dir, dir[0] && dir[strlen(dir) - 1] == '/' ? "" : "/", name);
	else
		strcpy(s, name ? name : dir);
	o->path[o->n] = s;
	o->label[o->n] = dup_or_null(label);
	o->columns[o->n] = dup_or_null(columns);
	o->temp[o->n] = dup_or_null(temp);
	if ((label && *label && !o->label[o->n]) || (columns && *columns && !o->columns[o->n]) ||
	    (temp && *temp && !o->temp[o->n])) {
		o->n++;
		return -ENOMEM;
	}
	o->n++;
	return 0;
}

/* the comma-separated fields of a line (double quotes group), trimmed,
 * in place; returns the count (at most max) */
static size_t csv_fields(char *line, char **f, size_t max)
{
	size_t k = 0;
	char *p = line;

	line[strcspn(line, "\r\n")] = '\0';
	while (k < max) {
		char *w, *e;
		bool q;

		while (*p == ' ' || *p == '\t')
			p++;
		q = *p == '"';
		p += q;
		w = p;
		while (*p && (q ? *p != '"' : *p != ','))
			p++;
		e = p;
		if (q && *p == '"')
			p++;
		while (*p && *p != ',')
			p++;
		while (e > w && (e[-1] == ' ' || e[-1] == '\t'))
			e--;
		f[k++] = w;
		if (!*p) {
			*e = '\0';
			break;
		}
		*e = '\0';
		p++;
	}
	return k;
}

/* a manifest: a CSV file whose header names the columns unit and file
 * (and optionally channels, temperature); -1 not a manifest, else an
 * exit code */
static int read_manifest(const char *cmd, const char *path, struct operands *o)
{
	FILE *f = fopen(path, "r");
	char line[4096], *fl[16], dir[4096];
	int col[4] = { -1, -1, -1, -1 }; /* unit, file, channels, temperature */
	static const char *const key[4] = { "unit", "file", "channels", "temperature" };
	size_t nf, lineno = 1, n0 = o->n;
	const char *slash = strrchr(path, '/');

	if (!f)
		return -1;
	if (!fgets(line, sizeof(line), f)) {
		fclose(f);
		return -1;
	}
	nf = csv_fields(line, fl, 16);
	for (size_t i = 0; i < nf; i++)
		for (int k = 0; k < 4; k++)
			if (!strcasecmp(fl[i], key[k]))
				col[k] = (int)i;
	if (col[0] >= 0 && col[1] < 0) {
		/* a unit column without a file column: a manifest whose
		 * columns are misnamed ("path"), not a capture */
		ssc_err(cmd, "%s: a manifest names its columns unit and file (and optionally channels, temperature): no column 'file'",
			path);
		fclose(f);
		return SSC_EXIT_FAIL;
	}
	if (col[0] < 0 || col[1] < 0) {
		fclose(f);
		return -1;
	}
	snprintf(dir, sizeof(dir), "%.*s", slash ? (int)(slash - path) : 1, slash ? path : ".");
	while (fgets(line, sizeof(line), f)) {
		char *v[4] = { NULL, NULL, NULL, NULL };

		lineno++;
		if (line[strspn(line, " \t\r\n")] == '\0' || line[0] == '#')
			continue;
		nf = csv_fields(line, fl, 16);
		for (int k = 0; k < 4; k++)
			v[k] = col[k] >= 0 && (size_t)col[k] < nf ? fl[col[k]] : NULL;
		if (!v[0] || !*v[0] || !v[1] || !*v[1]) {
			ssc_err(cmd, "%s: line %zu: a unit and a file are needed", path, lineno);
			fclose(f);
			return SSC_EXIT_FAIL;
		}
		/* a unit named twice would be reported by a name that is
		 * not its own */
		for (size_t k = n0; k < o->n; k++)
			if (o->label[k] && !strcmp(o->label[k], v[0])) {
				ssc_err(cmd, "%s: line %zu: unit '%s' is named twice: each unit needs its own name",
					path, lineno, v[0]);
				fclose(f);
				return SSC_EXIT_FAIL;
			}
		/* channels separated by ';' or spaces inside the field: -c's
		 * commas */
		for (char *c = v[2]; c && *c; c++)
			if (*c == ';' || *c == ' ')
				*c = ',';
		if (push(o, dir, v[1], v[0], v[2], v[3])) {
			fclose(f);
			ssc_err(cmd, "out of memory");
			return SSC_EXIT_FAIL;
		}
	}
	fclose(f);
	if (o->n == n0) {
		ssc_err(cmd, "%s: a manifest without units", path);
		return SSC_EXIT_FAIL;
	}
	return 0;
}

/* the operands with each folder replaced by its capture files (see
 * ssc_stage_ops.folders) and each manifest by its units; prints errors,
 * returns an exit code */
static int expand_folders(const char *cmd, const char *const *in, int n,
			  struct operands *o)
{
	int rc = 0;

	for (int i = 0; i < n && !rc; i++) {
		struct stat st;
		DIR *d;
		struct dirent *e;
		size_t k0 = o->n;
		char meta[4096];

		snprintf(meta, sizeof(meta), "%s/metadata.yaml", in[i]);
		if (strcmp(in[i], "-") && stat(in[i], &st) == 0 && S_ISDIR(st.st_mode) &&
		    access(meta, F_OK) != 0) {
			d = opendir(in[i]);
			if (!d) {
				ssc_err(cmd, "%s: %s", in[i], sscope_strerror(errno));
				rc = SSC_EXIT_FAIL;
				break;
			}
			while (!rc && (e = readdir(d))) {
				struct stat fs;
				char p[4096];

				snprintf(p, sizeof(p), "%s/%s", in[i], e->d_name);
				if (capture_name(e->d_name) && stat(p, &fs) == 0 &&
				    S_ISREG(fs.st_mode))
					rc = push(o, in[i], e->d_name, NULL, NULL, NULL) ?
						     SSC_EXIT_FAIL : 0;
			}
			closedir(d);
			if (!rc && o->n == k0) {
				ssc_err(cmd, "%s: a folder without capture files", in[i]);
				rc = SSC_EXIT_FAIL;
			}
			if (!rc)
				qsort(o->path + k0, o->n - k0, sizeof(char *), cmp_str);
		} else if (strcmp(in[i], "-") && stat(in[i], &st) == 0 && S_ISREG(st.st_mode) &&
			   (rc = read_manifest(cmd, in[i], o)) >= 0) {
			/* a manifest's units */
		} else {
			rc = push(o, in[i], NULL, NULL, NULL, NULL) ? SSC_EXIT_FAIL : 0;
		}
	}
	if (rc == -ENOMEM)
		ssc_err(cmd, "out of memory");
	return rc ? SSC_EXIT_FAIL : 0;
}

/* The warnings the stage said on the terminal, as rows of its summary
 * (quantity "warning", the message as the note, flagged), so that its
 * report shows them too; its JSON stays the command's. */
static void add_kept_warnings(json_t *summary)
{
	const char *m;
	size_t n = ssc_warn_kept(0, &m);

	for (size_t i = 0; i < n && summary; i++) {
		ssc_warn_kept(i, &m);
		ssc_summary_add(summary, NULL, "warning", (double)NAN,
				(double)NAN, (double)NAN, "", m);
		ssc_summary_warn_last(summary);
	}
}

int ssc_stage_exec(const struct ssc_stage_ops *ops, struct ssc_stage_call *call)
{
	struct ssc_common co;
	struct ssc_stage_env env = { 0 };
	struct sscope_capture **caps = NULL;
	const char *const *paths = NULL;
	void *opts = calloc(1, ops->opts_size ? ops->opts_size : 1);
	void *res = NULL;
	bool scene = call->base != NULL;
	int first, rc, n = 0, loaded = 0;
	struct trace_t t0 = { -1, 0 };
	struct operands ops_in = { 0 };
	struct load_ctx lc;

	if (!opts) {
		ssc_err(ops->spec->name, "out of memory");
		return SSC_EXIT_FAIL;
	}
	if (ops->init)
		ops->init(opts);
	/* 1. options (a scene's report keeps the warnings of its run) */
	if (scene && !call->check_only)
		ssc_warn_keep(true);
	ssc_bare_numbers_silent(scene && call->check_only);
	rc = ssc_parse_where(ops->spec, call->argc, call->argv, call->where,
			     &co, ops->handle, opts, &first);
	ssc_bare_numbers_silent(false);
	if (rc) {
		rc = rc < 0 ? SSC_EXIT_OK : rc;
		goto done;
	}
	if (scene) {
		/* the scene's shared options, its section's -c */
		const char *columns = co.columns;

		co = *call->base;
		co.cmd = call->name ? call->name : ops->spec->name;
		co.plot = call->plot_path;
		if (columns)
			co.columns = columns;
		n = (int)call->n_caps;
		paths = call->paths;
	} else {
		n = call->argc - first;
		paths = (const char *const *)call->argv + first;
		if (ops->folders && !call->check_only) {
			/* and the manifest an option names, after the files */
			const char *extra = ops->manifest ? ops->manifest(opts) : NULL;

			rc = expand_folders(co.cmd, paths, n, &ops_in);
			if (!rc && extra)
				rc = expand_folders(co.cmd, &extra, 1, &ops_in);
			if (rc)
				goto done;
			paths = (const char *const *)ops_in.path;
			n = (int)ops_in.n;
		}
	}
	if (call->check_only && scene) {
		/* the scene hands the captures over when it runs */
	} else if (n < ops->min_files) {
		rc = ssc_usage_error(co.cmd, n ? "too few input files" :
						 "no input file");
		goto done;
	} else if (ops->max_files >= 0 && n > ops->max_files) {
		rc = ssc_usage_error(co.cmd, "at most %d input file%s",
				     ops->max_files, ops->max_files == 1 ? "" : "s");
		goto done;
	}
	if (!scene && !call->check_only) {
		rc = ssc_check_inputs(co.cmd, paths, (size_t)n);
		if (rc)
			goto done;
	}
	/* 2. their cross-checks and consequences */
	if (ops->check) {
		ssc_set_context(call->context);
		rc = ops->check(&co, opts);
		ssc_set_context(NULL);
		if (rc)
			goto done;
	}
	if (!scene && co.format == SSC_FMT_CSV && !ops->csv) {
		rc = ssc_usage_error(co.cmd, "--format csv is not available here");
		goto done;
	}
	if (call->check_only)
		goto done;
	/* 3. inputs: the scene's captures shaped by -c, or the files */
	caps = calloc((size_t)(n ? n : 1), sizeof(*caps));
	if (!caps) {
		ssc_err(co.cmd, "out of memory");
		rc = SSC_EXIT_FAIL;
		goto done;
	}
	if (scene) {
		for (; loaded < n && !rc; loaded++)
			rc = ssc_view(&co, call->caps[loaded], &caps[loaded]);
	} else if (!(ops->streams && ops->streams(opts))) {
		co.values_in_run = ops->checks_values;
		for (; loaded < n && !rc; loaded++) {
			/* a manifest's channels and temperature column */
			struct ssc_common cu = co;

			if (ops_in.n && ops_in.columns[loaded])
				cu.columns = ops_in.columns[loaded];
			if (ops_in.n && ops_in.temp[loaded])
				cu.temp_column = ops_in.temp[loaded];
			rc = ssc_load(&cu, paths[loaded], &caps[loaded]);
		}
	}
	if (rc)
		goto done;
	env.co = &co;
	env.caps = loaded ? caps : NULL;
	env.paths = paths;
	env.labels = ops_in.n ? (const char *const *)ops_in.label : NULL;
	env.unit_columns = ops_in.n ? (const char *const *)ops_in.columns : NULL;
	env.unit_temps = ops_in.n ? (const char *const *)ops_in.temp : NULL;
	env.n_caps = (size_t)n;
	env.sensor = call->sensor;
	env.sensor_path = call->sensor_path;
	env.adc_paths = call->adc_paths;
	env.n_adc = call->n_adc;
	env.adc_ini = call->adc_ini;
	env.upstream = call->upstream;
	env.n_upstream = call->n_upstream;
	env.earlier = call->earlier;
	env.n_earlier = call->n_earlier;
	if (!scene) {
		lc.co = &co;
		lc.in = &ops_in;
		env.load = load_one;
		env.load_ctx = &lc;
	}
	/* 4. the computation */
	t0 = trace_clock();
	ssc_set_context(call->context);
	rc = ops->run(&env, opts, &res);
	ssc_set_context(NULL);
	trace_part(ops, "computation", &t0);
	if (rc)
		goto done;
	/* 5. what was asked for: the figure, files named by options, the
	 * output in its form */
	if (co.plot && ops->plot) {
		rc = ops->plot(&co, opts, res, co.plot);
		trace_part(ops, "figure", &t0);
		if (rc)
			goto done;
	}
	if (ops->write) {
		rc = ops->write(&co, opts, res);
		if (rc)
			goto done;
	}
	if (!scene) {
		rc = present(ops, &co, opts, res);
		trace_part(ops, "output", &t0);
		goto done;
	}
	if (call->want & SSC_WANT_JSON) {
		call->json = ops->json(opts, res);
		if (!call->json)
			rc = SSC_EXIT_FAIL;
		trace_part(ops, "json", &t0);
	}
	if (!rc && (call->want & SSC_WANT_TEXT)) {
		call->text = render_text(ops, opts, res, ops->text);
		if (!call->text)
			rc = SSC_EXIT_FAIL;
		trace_part(ops, "text", &t0);
	}
	if (!rc && (call->want & SSC_WANT_SUMMARY)) {
		call->summary = json_array();
		if (ops->summary)
			ops->summary(call->summary, opts, res);
		add_kept_warnings(call->summary);
		trace_part(ops, "summary", &t0);
	}
	if (rc) {
		ssc_err(co.cmd, "out of memory");
		goto done;
	}
	call->result.ops = ops;
	call->result.data = res;
	res = NULL;
	/* the result may point into its inputs: they live with it */
	call->views = caps;
	call->n_views = (size_t)loaded;
	caps = NULL;
done:
	if (scene)
		ssc_warn_keep(false);
	if (res && ops->free_result)
		ops->free_result(res);
	for (int i = 0; caps && i < loaded; i++)
		sscope_capture_free(caps[i]);
	free(caps);
	if (ops->fini)
		ops->fini(opts);
	free(opts);
	operands_free(&ops_in);
	return rc;
}

int ssc_stage_main(const struct ssc_stage_ops *ops, int argc, char **argv)
{
	struct ssc_stage_call call = { .argc = argc, .argv = argv };

	return ssc_stage_exec(ops, &call);
}
