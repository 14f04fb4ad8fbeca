/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The `nav` stage: strapdown navigation of a recorded 6-axis capture with
 * zero-velocity and zero-angular-rate updates at every stop
 * (analysis/sscope-zupt.h computes): its options, the capture's gyro and
 * accelerometer channels, the noise terms (an allan result, a datasheet
 * or the defaults), and the presenters (JSON, text, CSV, figure).
 */
#ifndef SSCOPE_WB_NAV_H
#define SSCOPE_WB_NAV_H

#include "workbench.h"

enum {
	SSC_NAV_O_LAT = 300,
	SSC_NAV_O_LON,
	SSC_NAV_O_HEIGHT,
	SSC_NAV_O_HEADING,
	SSC_NAV_O_ALLAN,
	SSC_NAV_O_SPEC,
	SSC_NAV_O_NO_ZUPT,
	SSC_NAV_O_WINDOW,
	SSC_NAV_O_STEP,
};

struct ssc_nav_opts {
	struct sscope_zupt_opts zo;
	const char *allan, *spec;
};

struct ssc_nav_result {
	const char *path;
	struct ssc_nav_opts o;
	const struct sscope_capture *cap;
	long gyro[3], accel[3];     /* channel indices */
	const char *noise_from;     /* "allan", "datasheet", "sensor spec",
				       "defaults" (with what was missing) */
	char noise_note[160];
	struct sscope_zupt_result *r;
};

struct ssc_stage_env;
void ssc_nav_init(void *opts);
int ssc_nav_handle(int key, const char *arg, void *opts);
int ssc_nav_check(struct ssc_common *co, void *opts);
/* the stage's run(); @p allan_up: the result of a scene's allan stage
 * (struct ssc_allan_res), or NULL */
int ssc_nav_run(const struct ssc_stage_env *env, const void *allan_up, void *opts,
		void **result);
json_t *ssc_nav_json(const void *opts, const void *result);
void ssc_nav_text(FILE *f, const void *opts, const void *result);
void ssc_nav_csv(FILE *f, const void *opts, const void *result);
void ssc_nav_summary(json_t *rows, const void *opts, const void *result);
int ssc_nav_plot(const struct ssc_common *co, const void *opts,
		 const void *result, const char *path);
void ssc_nav_free(void *result);

#endif
