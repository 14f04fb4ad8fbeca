/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * allan's export files: the requests of --export TARGET[:FILE] (and the
 * aliases --kalibr, --imu-utils, --openvins), the channels of the result
 * handed to the library's sscope_export(), which gates and formats each
 * file, written atomically here with its warnings and refusals said.
 */
#include "workbench.h"

#include <stdlib.h>
#include <string.h>

#include "noise-export.h"
#include "results.h"

/* "kalibr, imu_utils, ..." (static) */
static const char *target_names(void)
{
	static char names[256];
	size_t used = 0;

	if (!names[0])
		for (size_t i = 0; sscope_export_target(i); i++)
			used += (size_t)snprintf(names + used, sizeof(names) - used,
						 "%s%s", i ? ", " : "",
						 sscope_export_target(i));
	return names;
}

int ssc_export_parse(const char *opt, const char *arg,
		     struct ssc_export_req *req, size_t *n)
{
	const char *colon = strchr(arg, ':'), *target = opt;
	char name[64];
	size_t len = colon ? (size_t)(colon - arg) : strlen(arg);

	if (*n >= SSC_EXPORT_MAX)
		return ssc_usage_error("allan", "--%s: at most %d export files", opt,
				       SSC_EXPORT_MAX);
	if (!strcmp(opt, "export")) {
		snprintf(name, sizeof(name), "%.*s", (int)(len < 63 ? len : 63), arg);
		if (len >= 63 || !sscope_export_default_file(name))
			return ssc_usage_error("allan", "--export: '%.*s' is not %s",
					       (int)len, arg, target_names());
		target = name;
		arg = colon ? colon + 1 : sscope_export_default_file(name);
		if (!*arg)
			return ssc_usage_error("allan", "--export: %s: the file name after ':' is empty",
					       name);
	}
	for (size_t i = 0; i < *n; i++)
		if (!strcmp(req[i].path, arg))
			return ssc_usage_error("allan", "--%s: %s is written twice (give each export its own FILE)",
					       opt, arg);
	/* the library's name of the target, and the option that asked */
	req[*n].target = sscope_export_name(target);
	/* the three with options of their own are named by them */
	if (!strcmp(req[*n].target, "kalibr") ||
	    !strcmp(req[*n].target, "openvins"))
		snprintf(req[*n].option, sizeof(req[*n].option), "--%s", req[*n].target);
	else if (!strcmp(req[*n].target, "imu_utils"))
		snprintf(req[*n].option, sizeof(req[*n].option), "--imu-utils");
	else
		snprintf(req[*n].option, sizeof(req[*n].option), "--export %s", req[*n].target);
	req[(*n)++].path = arg;
	return 0;
}

/* one file: made by the library, then written atomically */
static int write_one(const struct ssc_common *co, const struct ssc_export_req *r,
		     const struct sscope_export_chan *ch, size_t nch,
		     const struct sscope_export_opts *o)
{
	struct sscope_export_file x;
	struct sscope_diag d = { "" };
	struct ssc_out at;
	int rc = sscope_export(r->target, ch, nch, o, &x, &d);

	if (rc) {
		ssc_err(co->cmd, "%s: %s%s", r->option,
			d.msg[0] ? d.msg : sscope_strerror(rc),
			x.forcible ? " (--force writes it with each doubtful value marked)" : "");
		return SSC_EXIT_FAIL;
	}
	for (char *l = x.warnings, *nl; l && *l; l = nl + 1) {
		nl = strchr(l, '\n');
		*nl = 0;
		ssc_warn(co, "%s: %s", r->option, l);
	}
	rc = ssc_file_open(co->cmd, r->path, &at);
	if (!rc) {
		fwrite(x.text, 1, x.len, at.f);
		rc = ssc_file_close(&at, true);
	}
	sscope_export_file_free(&x);
	return rc;
}

int ssc_export_allan(const struct ssc_common *co, const struct ssc_allan_res *R,
		     const struct ssc_export_req *req, size_t n, double inflate,
		     bool force)
{
	const struct ssc_allan_file *fr = R->fr;
	const struct sscope_capture_source *si = fr[0].cap->source_info;
	struct sscope_export_opts o = { 0 };
	struct sscope_export_chan *ch;
	size_t nch = 0, k = 0;
	int rc = SSC_EXIT_OK;

	if (!n)
		return SSC_EXIT_OK;
	for (size_t i = 0; i < R->n_files; i++)
		nch += fr[i].n_ch;
	ch = calloc(nch ? nch : 1, sizeof(*ch));
	if (!ch) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	o.rate_hz = fr[0].cap->rate_hz;
	for (size_t i = 0; i < R->n_files; i++)
		for (size_t j = 0; j < fr[i].n_ch; j++) {
			const struct ssc_allan_chan *c = &fr[i].ch[j];

			ch[k++] = (struct sscope_export_chan){
				c->col->name, c->u.rq,
				c->res->have_fit ? &c->res->fit : NULL, c->adq
			};
			if ((double)c->n / o.rate_hz > o.duration_s)
				o.duration_s = (double)c->n / o.rate_hz;
		}
	o.inflate = inflate;
	o.source = R->n_files > 1 ? "several files" : fr[0].path;
	for (size_t i = 0; si && i < si->n_topics; i++)
		if (si->topics[i].selected && !o.topic &&
		    !strstr(si->topics[i].type, "Temperature"))
			o.topic = si->topics[i].name;
	o.force = force;
	for (size_t i = 0; i < n && !rc; i++)
		rc = write_one(co, &req[i], ch, nch, &o);
	free(ch);
	return rc;
}
