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
	double lo[5], hi[5];      /* a pilot's intervals of the terms, SI
				     (lo 0: not bounded below) */
	double ci_level;          /* their level (0: not a pilot) */
};

/* One wish: term (enum sscope_term) to relative half-width target. */
struct ssc_plan_wish {
	int term;
	double target;
};

/* What the plan command (or a scene's [plan]) asks: the sensor file
 * (NULL: the pilot capture, else the scene's [sensor]), a datasheet's
 * section, the wishes, the lengths to show, the planner's options. */
struct ssc_plan_req {
	const char *sensor, *section;
	struct ssc_plan_wish wish[5];
	size_t n_wish;
	double lengths_s[SSC_PLAN_MAX_LENGTHS];
	size_t n_len;
	struct sscope_plan_opts po;
};

/* points of the figure's curves: probability against record length */
#define SSC_PLAN_CURVE 25

/* The plan: the model, and per wish the length needed and the
 * prediction at each length (and along the figure's lengths when drawn). */
struct ssc_plan_res {
	struct ssc_plan_req req;
	struct ssc_plan_model m;
	double rate_hz;
	double needed_s[5];
	/* from a pilot: the needed length with the planned term at the upper
	 * and the lower end of the pilot's interval (INFINITY: never) */
	double range_s[5][2];
	struct sscope_plan_point pt[5][SSC_PLAN_MAX_LENGTHS];
	size_t n_curve;            /* 0: no figure asked for */
	struct sscope_plan_point curve[5][SSC_PLAN_CURVE];
};

/* The model from req->sensor (a [sensor] spec or a datasheet INI; its
 * section "gyro" or "accel", NULL: gyro when given), else the pilot
 * capture's channel (the first of those -c selects, fitted as `allan`
 * does with dense taus), else the scene's sensor; then the plan at
 * co->rate_hz (else the pilot's rate), with the figure's curves when
 * co->plot.  Prints errors; returns an exit code. */
int ssc_plan_run(const struct ssc_common *co, const struct ssc_plan_req *req,
		 const struct sscope_capture *pilot, const char *pilot_path,
		 const struct sscope_sensor_spec *sensor, const char *sensor_path,
		 struct ssc_plan_res **out);

/* the stage's presenters (opts unused; result a struct ssc_plan_res) */
json_t *ssc_plan_json(const void *opts, const void *result);
void ssc_plan_text(FILE *f, const void *opts, const void *result);
void ssc_plan_summary(json_t *rows, const void *opts, const void *result);
int ssc_plan_plot(const struct ssc_common *co, const void *opts,
		  const void *result, const char *path);
void ssc_plan_free(void *result);

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
