/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * One way in: a capture read, calibrated, reduced to the channels asked
 * for and its rate judged, in that order, by one call that the command,
 * the scenes and the Python module share (sscope_capture_open()).
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sscope-calib.h"
#include "sscope-capture.h"
#include "sscope-reader.h"

int sscope_capture_open(struct sscope_capture **cap, const char *path,
			const struct sscope_capture_open_opts *opts,
			struct sscope_capture_notes *notes,
			struct sscope_diag *diag)
{
	static const struct sscope_capture_open_opts none;
	static const struct sscope_reader_opts no_read;
	const struct sscope_capture_open_opts *o = opts ? opts : &none;
	const struct sscope_reader_opts *rd = o->read ? o->read : &no_read;
	struct sscope_reader_opts ro = *rd;
	struct sscope_capture_notes nt;
	struct sscope_capture *c = NULL;
	int rc;

	memset(&nt, 0, sizeof(nt));
	if (!cap || !path || (o->n_calib && !o->calib)) {
		if (cap)
			*cap = NULL;
		return ssc_diag(diag, -EINVAL, "invalid arguments");
	}
	*cap = NULL;
	/* a calibration needs every channel of its triads (and replaces
	 * channels: no reading in place) */
	if (o->n_calib) {
		ro.columns = NULL;
		ro.in_place = false;
		ro.in_place_unchecked = false;
	}
	nt.stage = SSCOPE_CAPTURE_STAGE_READ;
	rc = sscope_capture_load(&c, path, &ro, diag);
	if (rc)
		goto out;
	nt.unterminated = c->unterminated;
	nt.rows_read = c->n;
	if (o->n_calib) {
		nt.stage = SSCOPE_CAPTURE_STAGE_CALIBRATE;
		rc = sscope_capture_apply_calib(c, o->calib, o->n_calib,
						&nt.calib_gsens_skipped, NULL, diag);
		if (rc)
			goto out;
	}
	nt.stage = SSCOPE_CAPTURE_STAGE_SELECT;
	rc = sscope_capture_select(c, rd->columns, diag);
	if (rc)
		goto out;
	nt.stage = SSCOPE_CAPTURE_STAGE_DONE;
	/* a default unit that no channel took */
	if (rd->default_unit && *rd->default_unit && c->n_channels) {
		nt.unit_unused = true;
		for (size_t k = 0; k < c->n_channels; k++)
			if (!strcmp(c->channels[k].col.unit_label, rd->default_unit))
				nt.unit_unused = false;
	}
	nt.rate_implausible = sscope_capture_check_rate(c, &nt.rate_hint) != 0;
	if (c->rate_source == SSCOPE_CAPTURE_RATE_GIVEN && c->has_timing &&
	    rd->rate_hz > 0 &&
	    fabs(c->timing.rate_hz / rd->rate_hz - 1) > 0.01) {
		nt.rate_disagrees = true;
		nt.time_column_rate_hz = c->timing.rate_hz;
	}
out:
	if (rc) {
		sscope_capture_free(c);
		c = NULL;
	}
	*cap = c;
	if (notes)
		*notes = nt;
	return rc;
}
