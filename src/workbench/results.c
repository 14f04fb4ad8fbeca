/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Typed results shared between stages (results.h): the allan result a
 * later stage takes instead of computing it again, and the one rule by
 * which a saved allan channel is a gyro or an accelerometer.
 */
#include "workbench.h"
#include "results.h"

#include <string.h>

const struct sscope_allan_result *
ssc_allan_res_find(const struct ssc_allan_res *R, const double *data, size_t n,
		   double rate_hz, enum sscope_allan_tau_grid grid,
		   const struct sscope_allan_opts *ao,
		   const struct sscope_noise_fit_opts *fo)
{
	const struct sscope_allan_opts *a = &R->ao;
	const struct sscope_noise_fit_opts *f = &R->fo;

	if (R->grid != grid || a->dev != ao->dev || a->input != ao->input ||
	    a->ci_level != ao->ci_level || a->alpha_fixed != ao->alpha_fixed ||
	    (a->alpha_fixed && a->alpha != ao->alpha) ||
	    a->stride_div != ao->stride_div || a->threads != ao->threads ||
	    f->ci_level != fo->ci_level || f->allowed != fo->allowed ||
	    f->forced != fo->forced || f->model_error != fo->model_error ||
	    f->detect_sigma != fo->detect_sigma ||
	    f->tau_min_s != fo->tau_min_s || f->tau_max_s != fo->tau_max_s ||
	    f->skip != fo->skip)
		return NULL;
	for (size_t i = 0; i < R->n_files; i++) {
		const struct ssc_allan_file *fr = &R->fr[i];

		if (!fr->cap || fr->cap->n != n || fr->cap->rate_hz != rate_hz)
			continue;
		for (size_t k = 0; k < fr->n_ch && k < fr->cap->n_channels; k++)
			if (fr->cap->channels[k].data == data && fr->ch[k].res)
				return fr->ch[k].res;
	}
	return NULL;
}

/* the quantity (gyro or accelerometer) whose noise term N has the SI
 * unit si_unit, by the unit's dimension */
static enum sscope_quantity n_quantity(const char *si_unit)
{
	static const enum sscope_quantity qs[2] = { SSCOPE_QUANTITY_ANGULAR_RATE,
						    SSCOPE_QUANTITY_ACCELERATION };
	struct sscope_unit u, w;

	if (!si_unit || sscope_unit_parse(si_unit, &u, NULL))
		return SSCOPE_QUANTITY_UNKNOWN;
	for (int i = 0; i < 2; i++)
		if (!sscope_unit_parse(sscope_term_si_unit(qs[i], SSCOPE_TERM_N),
				       &w, NULL) &&
		    sscope_unit_compatible(&u, &w))
			return qs[i];
	return SSCOPE_QUANTITY_UNKNOWN;
}

enum sscope_quantity ssc_allan_json_rate_quantity(const json_t *ch)
{
	const char *q = json_string_value(json_object_get(ch, "quantity"));
	const char *in = json_string_value(json_object_get(ch, "input"));
	enum sscope_allan_input input = in && !strcmp(in, "angle") ?
						SSCOPE_ALLAN_ANGLE : SSCOPE_ALLAN_RATE;

	for (int k = 0; q && k < SSCOPE_QUANTITY_COUNT_; k++)
		if (!strcmp(q, sscope_quantity_name((enum sscope_quantity)k)))
			return sscope_allan_rate_quantity((enum sscope_quantity)k,
							  input);
	/* the contract's shape, without "quantity": the dimension of N */
	return n_quantity(json_string_value(json_object_get(
		json_object_get(json_object_get(ch, "noise"), "N"), "si_unit")));
}
