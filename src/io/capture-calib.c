/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * A calibration (the triads of a calibration file) applied to a loaded
 * capture: the channels it names found, converted to the units the triad
 * expects, corrected in place by the error model of analysis/calib.c
 * (sscope_calib_apply()) and given the triad's output unit.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

#include "sscope-calib.h"
#include "sscope-capture.h"
#include "sscope-unit.h"

/* SI per unit of a unit label (1 for "" or an unknown unit) */
static double label_scale(const char *unit)
{
	struct sscope_unit u;

	if (!unit || !*unit || sscope_unit_parse(unit, &u, NULL))
		return 1;
	return u.scale;
}

int sscope_capture_apply_calib(struct sscope_capture *cap,
			       const struct sscope_calib_file_triad *t,
			       size_t n, unsigned *gsens_skipped,
			       size_t *applied, struct sscope_diag *diag)
{
	size_t done = 0;

	if (gsens_skipped)
		*gsens_skipped = 0;
	if (applied)
		*applied = 0;
	if (!cap || (!t && n) || cap->is_view)
		return -EINVAL;
	for (size_t i = 0; i < n; i++) {
		struct sscope_calib_triad c = t[i].c;
		double s = label_scale(t[i].input_unit);
		const double *a[3] = { NULL, NULL, NULL };
		struct sscope_unit fu;
		long idx[3];
		int found = 0;

		for (int j = 0; j < 3; j++) {
			idx[j] = sscope_capture_find(cap, t[i].channels[j]);
			found += idx[j] >= 0;
		}
		if (found == 0)
			continue;
		if (found < 3)
			return ssc_diag(diag, -EINVAL,
					"the triad %s,%s,%s needs all three channels",
					t[i].channels[0], t[i].channels[1],
					t[i].channels[2]);
		if (*t[i].input_unit &&
		    sscope_unit_parse(t[i].input_unit, &fu, NULL))
			return ssc_diag(diag, -EINVAL, "unknown unit '%s'",
					t[i].input_unit);
		for (int j = 0; j < 3; j++) {
			const struct sscope_capture_column *col = &cap->channels[idx[j]].col;

			if (col->unit_label[0] && *t[i].input_unit &&
			    !sscope_unit_compatible(&col->unit, &fu))
				return ssc_diag(diag, -EINVAL,
						"channel %s is in %s, the calibration expects %s",
						col->name, col->unit_label,
						t[i].input_unit);
		}
		/* parameters in the units the data are held in */
		if (cap->channels[idx[0]].col.unit_label[0])
			for (int j = 0; j < 3; j++) {
				c.bias[j] *= s;
				c.scale[j] /= s;
				for (int k = 0; k < 3; k++)
					c.gsens[j][k] *= s;
			}
		if (c.has_gsens) {
			for (int j = 0; j < 3; j++) {
				long q = sscope_capture_find(cap, t[i].accel_channels[j]);

				a[j] = q >= 0 ? cap->channels[q].data : NULL;
			}
			if (!a[0] || !a[1] || !a[2]) {
				if (gsens_skipped && i < 8 * sizeof(unsigned))
					*gsens_skipped |= 1u << i;
				c.has_gsens = false;
			}
		}
		sscope_calib_apply(&c, cap->channels[idx[0]].data,
				   cap->channels[idx[1]].data,
				   cap->channels[idx[2]].data, 1, cap->n,
				   c.has_gsens ? a : NULL, 1);
		for (int j = 0; j < 3; j++) {
			struct sscope_capture_channel *ch = &cap->channels[idx[j]];
			char *name = ssc_strdup(ch->col.name);
			size_t fi = ch->col.index;
			int e = name ? sscope_capture_set_channel(cap, (size_t)idx[j],
								  name,
								  t[i].output_unit) :
				       -ENOMEM;

			free(name);
			if (e)
				return e == -ENOMEM ? e :
				       ssc_diag(diag, e, "unknown unit '%s'",
						t[i].output_unit);
			ch->col.index = fi;
		}
		done++;
	}
	if (applied)
		*applied = done;
	if (!done)
		return ssc_diag(diag, -EDOM, "none of its channels is in %s",
				cap->source ? cap->source : "the capture");
	return 0;
}
