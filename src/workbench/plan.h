/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The `plan` command's model and presentation: the sensor's IEEE 952 terms
 * from a sensor spec, a datasheet or a pilot capture's fit, and the
 * planner's answers (analysis/sscope-plan.h computes) as text or JSON.
 */
#ifndef SSCOPE_WB_PLAN_H
#define SSCOPE_WB_PLAN_H

#include "workbench.h"

#define SSC_PLAN_MAX_LENGTHS 32

/* The model planned for. */
struct ssc_plan_model {
	double coef[5];           /* Q N B K R, SI (0: not in the model) */
	char why[5][160];         /* why a term is 0 ("" when given) */
	enum sscope_quantity quantity;
	char name[112];
	const char *kind;         /* "sensor spec", "datasheet", "pilot" */
	const char *path;
	double rate_hz;           /* the pilot's rate (0 for specs) */
	double pilot_s;           /* the pilot's length, s */
	unsigned unshown;         /* terms a pilot does not show present
				     (planned with their estimate) */
};

/* One wish: term (enum sscope_term) to relative half-width target. */
struct ssc_plan_wish {
	int term;
	double target;
};

/* The model from --sensor (a [sensor] spec or a datasheet INI; section
 * "gyro" or "accel" of a datasheet, NULL: gyro when given) or --pilot (the
 * first channel -c selects, fitted as `allan` does).  Prints errors;
 * returns an exit code. */
int ssc_plan_model_load(const struct ssc_common *co, const char *sensor,
			const char *pilot, const char *section,
			struct ssc_plan_model *m);

/* Plan each wish at rate_hz and print the table (text) or the JSON to the
 * command's output.  Returns an exit code. */
int ssc_plan_report(const struct ssc_common *co, const struct ssc_plan_model *m,
		    const struct ssc_plan_wish *w, size_t n_w,
		    const double *lengths_s, size_t n_len, double rate_hz,
		    const struct sscope_plan_opts *po);

#endif /* SSCOPE_WB_PLAN_H */
