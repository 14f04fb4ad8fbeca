/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Scenes: an INI file naming inputs, sensor/ADC specifications and the
 * outputs wanted.  The runner resolves which stages those outputs need
 * (and the stages they consume), reads each capture once with only the
 * columns in use, runs each needed stage once, and writes text, JSON, PNG
 * figures and a self-contained HTML report.
 */
#ifndef SSCOPE_SCENE_H
#define SSCOPE_SCENE_H

#include "stage.h"

/* A stage of the scene graph. */
struct ssc_stage_def {
	const char *name;                 /* scene section, e.g. "allan" */
	const struct ssc_stage_ops *ops;  /* the command it runs */
	unsigned deps;                    /* bit i: consumes stage i's result */
	const char *command;              /* its command line's words (NULL:
					     the command's name) */
	const char *definitions;          /* definitions used, for reports */
};

/* The stages of the scene graph, in the order of the table handed to
 * ssc_scene_load() and ssc_scene_infer() (src/cli/stages.c). */
enum {
	S_INFO = 0, S_ALLAN, S_PSD, S_VIBRATION, S_TEMPBIAS, S_INCLINO, S_ADC,
	S_CALIB, S_BUDGET, S_HEADING, S_WALK, S_NAVSIM, S_DATASHEET, S_LOT, S_NAV, S_PLAN, S_COUNT_
};

/* Output formats of [report] formats = ... */
enum {
	SSC_OUT_TEXT = 1u << 0,
	SSC_OUT_JSON = 1u << 1,
	SSC_OUT_HTML = 1u << 2,
	SSC_OUT_PNG = 1u << 3,
	SSC_OUT_SVG = 1u << 4,
};

struct ssc_scene;

/* Parse a scene file; prints errors ("sensorscope: CMD: FILE: line N: ...").
 * @p graph: the stage graph, S_COUNT_ entries indexed by S_*.  Returns an
 * exit code. */
int ssc_scene_load(const char *cmd, const char *path,
		   const struct ssc_stage_def *graph, struct ssc_scene **sc);

/* A scene inferred from captures (sensorscope report): prints what it
 * chose and why unless quiet.  Returns an exit code. */
int ssc_scene_infer(const struct ssc_common *co, char **files, size_t n,
		    const char *out_dir, const struct ssc_stage_def *graph,
		    struct ssc_scene **sc);

/* Print the plan (stages to run and why, stages skipped and why, columns
 * read, outputs). */
/* Write the outputs into DIR instead of the scene's [report] output. */
void ssc_scene_set_output(struct ssc_scene *sc, const char *dir);

void ssc_scene_plan(const struct ssc_scene *sc, FILE *f);

/* Run the scene.  Returns an exit code. */
int ssc_scene_run(struct ssc_scene *sc, const struct ssc_common *co);

void ssc_scene_free(struct ssc_scene *sc);

#endif
