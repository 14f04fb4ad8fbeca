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

/* acquire --until: the recording's channel refitted as it grows (at 60 s
 * of data, then every 5 % more), until the term is present with a relative
 * half-width at most the target; progress on stderr unless quiet. */
struct ssc_until;
struct ssc_acq_sample;
int ssc_until_new(const char *cmd, size_t channel, const char *chan_name,
		  int term, double target, double rate_hz, bool quiet,
		  struct ssc_until **u);
/* the engine's until callback (ctx: the struct ssc_until) */
bool ssc_until_check(const struct ssc_acq_sample *s, size_t n,
		     double elapsed_s, void *ctx);
/* the last fit: relative half-width (INFINITY when not present), data
 * length fitted (s), number of fits, whether it was reached */
void ssc_until_state(const struct ssc_until *u, double *width,
		     double *fitted_s, unsigned *fits, bool *reached);
void ssc_until_free(struct ssc_until *u);

#endif /* SSCOPE_WB_PLAN_H */
