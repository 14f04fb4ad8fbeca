/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The inputs of a command: a capture loaded with the shared options (-c,
 * -r, -u, --raw, --calibration, ...), its values and time stamps judged,
 * inputs named twice refused.  Errors are printed; exit codes returned.
 */
#include "workbench.h"
#include "calibfile.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static void read_progress(void *ctx, uint64_t done, uint64_t total)
{
	struct ssc_read_progress *p = ctx;

	ssc_progress(p->co, p->label, (double)done, (double)total);
}

void ssc_read_progress_on(const struct ssc_common *co, const char *label,
			  struct ssc_read_progress *p, struct sscope_reader_opts *o)
{
	p->co = co;
	p->label = label;
	if (ssc_progress_on(co)) {
		o->progress = read_progress;
		o->progress_ctx = p;
	}
}

void ssc_read_opts(const struct ssc_common *co, struct sscope_reader_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->raw = co->raw;
	o->raw_scale = co->scale;
	o->raw_offset = co->offset;
	o->default_unit = co->units;
	o->columns = co->columns;
	o->time_column = co->time_column;
	o->temp_column = co->temp_column;
	o->rate_hz = co->rate_hz;
	o->nan_as_gap = co->allow_nan;
	o->topic = co->topic;
}

int ssc_load(const struct ssc_common *co, const char *path,
	     struct sscope_capture **cap)
{
	struct sscope_capture_open_opts o = { 0 };
	struct sscope_reader_opts ro;
	struct sscope_capture_notes nt;
	struct sscope_calib_file_triad *t = NULL;
	struct sscope_diag d = { "" };
	struct ssc_read_progress pc;
	int rc;

	ssc_read_opts(co, &ro);
	/* the reader reads only the columns -c names, in place (with a
	 * calibration, sscope_capture_open() reads every channel) */
	ro.in_place = true;
	/* (with --allow-nan the reader counts the gaps) */
	ro.in_place_unchecked = co->values_in_run && !co->allow_nan;
	ssc_read_progress_on(co, path, &pc, &ro);
	o.read = &ro;
	if (co->calibration) {
		rc = ssc_calfile_read(co->cmd, co->calibration, &t, &o.n_calib);
		if (rc)
			return rc;
		o.calib = t;
	}
	rc = sscope_capture_open(cap, path, &o, &nt, &d);
	ssc_progress_end(co);
	if (nt.unterminated)
		ssc_warn_unterminated(co, path, nt.rows_read);
	for (size_t i = 0; t && i < o.n_calib && i < 8 * sizeof(unsigned); i++)
		if (nt.calib_gsens_skipped & (1u << i))
			ssc_warn(co, "%s: no accelerometer channels %s,%s,%s: g-sensitivity not corrected",
				 path, t[i].accel_channels[0], t[i].accel_channels[1],
				 t[i].accel_channels[2]);
	if (rc && nt.stage == SSCOPE_CAPTURE_STAGE_CALIBRATE) {
		if (rc == -ENOMEM)
			ssc_err(co->cmd, "out of memory");
		else
			ssc_err(co->cmd, "--calibration: %s: %s: %s", co->calibration,
				path, d.msg[0] ? d.msg : sscope_strerror(rc));
		rc = SSC_EXIT_FAIL;
	} else if (rc) {
		rc = ssc_fail(co->cmd, rc, &d, path);
	}
	free(t);
	if (rc)
		return rc;
	/* -u names the unit of data columns whose header names none: say so
	 * when no channel took it */
	if (nt.unit_unused)
		ssc_warn(co, "%s: -u %s changes nothing: the file names the unit of every channel (%s: %s%s); -u only fills in a missing unit",
			 path, co->units, (*cap)->channels[0].col.name,
			 (*cap)->channels[0].col.unit_label,
			 (*cap)->n_channels > 1 ? ", ..." : "");
	if (nt.rate_implausible)
		ssc_warn(co, "%s: %s", path, nt.rate_hint.msg);
	if (nt.rate_disagrees)
		ssc_warn(co, "%s: --rate %g Hz but the time column implies %.6g Hz: using --rate %g Hz",
			 path, co->rate_hz, nt.time_column_rate_hz, co->rate_hz);
	return SSC_EXIT_OK;
}

int ssc_check_values(const struct ssc_common *co,
		     const struct sscope_capture *cap)
{
	struct sscope_diag d = { "" };
	int rc = sscope_capture_check_values(cap, co->allow_nan, &d);

	return rc ? ssc_fail(co->cmd, rc, &d, cap->source) : SSC_EXIT_OK;
}

int ssc_select(const struct ssc_common *co, struct sscope_capture *cap)
{
	struct sscope_diag d = { "" };
	int rc = sscope_capture_select(cap, co->columns, &d);

	return rc ? ssc_fail(co->cmd, rc, &d, cap->source) : SSC_EXIT_OK;
}

int ssc_view(const struct ssc_common *co, const struct sscope_capture *cap,
	     struct sscope_capture **view)
{
	struct sscope_diag d = { "" };
	int rc = sscope_capture_view(cap, co->columns, view, &d);

	return rc ? ssc_fail(co->cmd, rc, &d, cap->source) : SSC_EXIT_OK;
}

void ssc_warn_unterminated(const struct ssc_common *co, const char *path,
			   size_t rows)
{
	ssc_warn(co, "%s: the last line (row %zu) has no newline: was the capture cut short?",
		 strcmp(path, "-") ? path : "(stdin)", rows);
}

int ssc_check_inputs(const char *cmd, const char *const *paths, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		struct stat a;
		bool ha = !strcmp(paths[i], "-") ? fstat(STDIN_FILENO, &a) == 0 :
						     stat(paths[i], &a) == 0;

		for (size_t j = i + 1; j < n; j++) {
			struct stat b;
			bool hb;

			if (!strcmp(paths[i], "-") && !strcmp(paths[j], "-"))
				return ssc_usage_error(cmd,
						       "standard input ('-') is given twice (inputs %zu and %zu): it can be read once",
						       i + 1, j + 1);
			hb = !strcmp(paths[j], "-") ? fstat(STDIN_FILENO, &b) == 0 :
						      stat(paths[j], &b) == 0;
			if (ha && hb && a.st_dev == b.st_dev && a.st_ino == b.st_ino)
				return ssc_usage_error(cmd,
						       "inputs %zu and %zu ('%s' and '%s') are the same file: give each capture once",
						       i + 1, j + 1, paths[i], paths[j]);
		}
	}
	return SSC_EXIT_OK;
}

int ssc_time_verdict(const struct ssc_common *co, const char *path,
		     const char *column, const struct sscope_timing_order *o,
		     enum sscope_capture_rate_source rate_source, bool uniform)
{
	struct sscope_diag d = { "" };
	const char *p = strcmp(path, "-") ? path : "(stdin)";

	if (!sscope_timing_order_check(o, &d))
		return SSC_EXIT_OK;
	if (!uniform) {
		ssc_warn(co, "%s: time column '%s' %s", p, column, d.msg);
		return SSC_EXIT_OK;
	}
	if (rate_source == SSCOPE_CAPTURE_RATE_GIVEN || rate_source == SSCOPE_CAPTURE_RATE_HEADER) {
		ssc_warn(co, "%s: time column '%s' %s: the samples are taken as evenly spaced at the %s rate",
			 p, column, d.msg,
			 rate_source == SSCOPE_CAPTURE_RATE_GIVEN ? "given" : "header's");
		return SSC_EXIT_OK;
	}
	ssc_err(co->cmd, "%s: time column '%s' %s: fix the time stamps, or give --rate to take the samples as evenly spaced",
		p, column, d.msg);
	return SSC_EXIT_FAIL;
}

void ssc_time_order(const struct sscope_capture *cap,
		    struct sscope_timing_order *o)
{
	/* the capture's timing analysis fed every stamp once already */
	if (cap->has_timing) {
		*o = cap->timing.order;
		return;
	}
	memset(o, 0, sizeof(*o));
	if (cap->time_s)
		sscope_timing_order_feed(o, cap->time_s, cap->n);
}

int ssc_time_check(const struct ssc_common *co, const char *path,
		   const struct sscope_capture *cap, bool uniform)
{
	struct sscope_timing_order o;

	if (!cap->time_s)
		return SSC_EXIT_OK;
	ssc_time_order(cap, &o);
	return ssc_time_verdict(co, path, cap->time_col.name, &o,
				cap->rate_source, uniform);
}

size_t ssc_time_gaps(const struct sscope_capture *cap)
{
	return cap->has_timing &&
	       !sscope_timing_order_check(&cap->timing.order, NULL) ?
	       cap->timing.n_gaps : 0;
}

void ssc_warn_time_gaps(const struct ssc_common *co, const char *path,
			size_t gaps)
{
	if (gaps)
		ssc_warn(co, "%s: %zu gap%s in the time stamps: the spectrum assumes uniform sampling",
			 path, gaps, gaps == 1 ? "" : "s");
}
