/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The command-line driver of a stage (see stage.h) and helpers shared by
 * stages.
 */
#include "stage.h"

#include <stdlib.h>
#include <string.h>

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

void ssc_stage_out_free(struct ssc_stage_out *out)
{
	json_decref(out->json);
	json_decref(out->summary);
	free(out->text);
	free(out->csv);
	memset(out, 0, sizeof(*out));
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

int ssc_stage_present(const struct ssc_common *co, struct ssc_stage_out *out)
{
	struct ssc_out o;
	const char *s;
	int rc;

	if (!out->json || !out->text) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	if (co->format == SSC_FMT_JSON) {
		json_incref(out->json);
		return ssc_emit_json(co, out->json);
	}
	s = co->format == SSC_FMT_CSV ? out->csv : out->text;
	if (!s)
		return ssc_usage_error(co->cmd, "--format %s is not available here",
				       co->format == SSC_FMT_CSV ? "csv" : "text");
	rc = ssc_out_open(co, &o);
	if (rc)
		return rc;
	fputs(s, o.f);
	return ssc_out_close(co, &o, !ferror(o.f));
}

int ssc_stage_main(const struct ssc_stage_ops *ops, int argc, char **argv)
{
	struct ssc_common co;
	struct ssc_stage_out out = { 0 };
	struct ssc_stage_env env = { 0 };
	struct sscope_capture **caps = NULL;
	void *opts = calloc(1, ops->opts_size ? ops->opts_size : 1);
	int first, rc, n = 0;

	if (!opts) {
		ssc_err(ops->spec->name, "out of memory");
		return SSC_EXIT_FAIL;
	}
	if (ops->init)
		ops->init(opts);
	rc = ssc_parse(ops->spec, argc, argv, &co, ops->handle, opts, &first);
	if (rc) {
		rc = rc < 0 ? SSC_EXIT_OK : rc;
		goto done;
	}
	n = argc - first;
	if (n < ops->min_files) {
		rc = ssc_usage_error(co.cmd, n ? "too few input files" :
						 "no input file");
		goto done;
	}
	if (ops->max_files >= 0 && n > ops->max_files) {
		rc = ssc_usage_error(co.cmd, "at most %d input file%s",
				     ops->max_files, ops->max_files == 1 ? "" : "s");
		goto done;
	}
	rc = ssc_check_inputs(co.cmd, (const char *const *)argv + first,
			      (size_t)n);
	if (rc)
		goto done;
	if (ops->check) {
		rc = ops->check(&co, opts);
		if (rc)
			goto done;
	}
	caps = calloc((size_t)(n ? n : 1), sizeof(*caps));
	if (!caps) {
		rc = SSC_EXIT_FAIL;
		goto done;
	}
	for (int i = 0; i < n; i++) {
		rc = ssc_load(&co, argv[first + i], &caps[i]);
		if (rc)
			goto done;
	}
	env.co = &co;
	env.caps = caps;
	env.paths = (const char *const *)argv + first;
	env.n_caps = (size_t)n;
	env.plot_path = co.plot;
	out.summary = json_array();
	rc = ops->run(&env, opts, &out);
	if (rc)
		goto done;
	rc = ssc_stage_present(&co, &out);
done:
	for (int i = 0; caps && i < n; i++)
		sscope_capture_free(caps[i]);
	free(caps);
	ssc_stage_out_free(&out);
	if (ops->fini)
		ops->fini(opts);
	free(opts);
	return rc;
}
