/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Commands as stages.  An analysis command is written once as a stage:
 * options (the command's long options, also the keys of its scene
 * section), and a run() that computes on loaded inputs and returns its
 * result in all three forms -- the contract's JSON object, the text for
 * people, CSV for machines -- drawing its figure when asked.  The same
 * stage serves `sensorscope CMD ...` (ssc_stage_main) and the scene runner
 * (`run`, `report`), which loads each capture once and hands the results of
 * earlier stages to later ones.
 */
#ifndef SSCOPE_STAGE_H
#define SSCOPE_STAGE_H

#include "cli.h"

/* What a stage receives. */
struct ssc_stage_env {
	const struct ssc_common *co;      /* shared options */
	struct sscope_capture **caps;     /* loaded inputs (may be 0 of them) */
	const char *const *paths;         /* their names */
	size_t n_caps;
	const struct sscope_sensor_spec *sensor; /* scene's [sensor] or NULL */
	const char *sensor_path;          /* its file, or NULL */
	const char *adc_paths[8];         /* scene's [adc] spec files */
	size_t n_adc;
	/* scene's inline [adc] specification (section "adc"), or NULL */
	const struct sscope_ini *adc_ini;
	const char *plot_path;            /* draw the figure here, or NULL */
	json_t *upstream;                 /* {"stage": result, ...} or NULL */
};

/* What a stage returns (owned by the caller after run). */
struct ssc_stage_out {
	json_t *json;    /* the contract's object */
	char *text;      /* for people */
	char *csv;       /* for machines (NULL: no CSV form) */
	json_t *summary; /* array of {"channel","quantity","value","lo","hi",
			    "unit","note"} for a report's summary table */
};

/* Inputs a stage needs (for scene planning). */
enum {
	SSC_NEED_DATA = 1u << 0,   /* data channels */
	SSC_NEED_TEMP = 1u << 1,   /* a temperature column */
	SSC_NEED_SENSOR = 1u << 2, /* a sensor specification */
	SSC_NEED_ADC = 1u << 3,    /* ADC specifications */
};

struct ssc_stage_ops {
	const struct ssc_command_spec *spec;
	const char *title;        /* section title in reports */
	unsigned needs;           /* SSC_NEED_* */
	int min_files, max_files; /* operands (max -1: any) */
	size_t opts_size;
	void (*init)(void *opts);
	int (*handle)(int key, const char *arg, void *opts);
	/* after all options: cross-checks (usage errors) */
	int (*check)(const struct ssc_common *co, void *opts);
	int (*run)(const struct ssc_stage_env *env, void *opts,
		   struct ssc_stage_out *out);
	void (*fini)(void *opts);
};

/* `sensorscope CMD [OPTIONS] FILE...` for a stage: parse, load, run,
 * present in the chosen format.  Returns the exit code. */
int ssc_stage_main(const struct ssc_stage_ops *ops, int argc, char **argv);

/* Write an output in the command's --format to its -o (or stdout). */
int ssc_stage_present(const struct ssc_common *co, struct ssc_stage_out *out);

/* Free the contents of an output. */
void ssc_stage_out_free(struct ssc_stage_out *out);

/* In-memory text building (open_memstream). */
struct ssc_membuf {
	FILE *f;
	char *buf;
	size_t len;
};
int ssc_membuf_open(struct ssc_membuf *m);
/* Close and return the text (caller frees), NULL on failure. */
char *ssc_membuf_take(struct ssc_membuf *m);

/* Append a row to a summary array. */
void ssc_summary_add(json_t *summary, const char *channel,
		     const char *quantity, double value, double lo, double hi,
		     const char *unit, const char *note);
/* Mark the last summary row as a result the analysis doubts ("status":
 * "warning"): reports flag it. */
void ssc_summary_warn_last(json_t *summary);

/* The stages (one per analysis command). */
extern const struct ssc_stage_ops ssc_info_stage;
extern const struct ssc_stage_ops ssc_psd_stage;
extern const struct ssc_stage_ops ssc_vibration_stage;
extern const struct ssc_stage_ops ssc_calib_stage;
extern const struct ssc_stage_ops ssc_budget_stage;
extern const struct ssc_stage_ops ssc_allan_stage;
extern const struct ssc_stage_ops ssc_tempbias_stage;
extern const struct ssc_stage_ops ssc_inclino_stage;
extern const struct ssc_stage_ops ssc_adc_stage;
extern const struct ssc_stage_ops ssc_heading_stage;
extern const struct ssc_stage_ops ssc_walk_stage;
extern const struct ssc_stage_ops ssc_navsim_stage;

#endif
