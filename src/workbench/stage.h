/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Commands as stages.  An analysis command is written once as a stage:
 * options (the command's long options, also the keys of its scene
 * section), a check of them, a run() that computes a typed result (a
 * struct of the stage, made of the library's result structs, declared in
 * results.h so that later stages read it directly), and renderers that
 * present that result in the form asked for -- the contract's JSON object,
 * the text for people, CSV for machines, the summary rows of a report, the
 * figure, the files its options name (--kalibr, --save-calibration).
 *
 * ssc_stage_exec() is the one sequence parse -> check -> inputs -> run ->
 * present.  `sensorscope CMD ...` (ssc_stage_main) and the scene runner
 * (`run`, `report`) both call it: a scene hands it the options of its
 * section as a command line, the captures it has loaded once, and the
 * results of earlier stages, so a stage cannot behave differently in a
 * scene than as a command.
 */
#ifndef SSCOPE_STAGE_H
#define SSCOPE_STAGE_H

#include "workbench.h"

struct ssc_stage_ops;

/* A stage's typed result (owned by whoever ran it; ssc_result_free). */
struct ssc_result {
	const struct ssc_stage_ops *ops; /* the stage that made it */
	void *data;                      /* its result struct (results.h) */
};

/* What a stage's run() receives. */
struct ssc_stage_env {
	const struct ssc_common *co;      /* shared options */
	struct sscope_capture *const *caps; /* inputs shaped by -c (may be
					       0 of them; NULL when the
					       stage streams them) */
	const char *const *paths;         /* their names */
	/* the units' names a manifest gives (stages with folders), else
	 * NULL; an entry NULL: none given */
	const char *const *labels;
	size_t n_caps;
	const struct sscope_sensor_spec *sensor; /* scene's [sensor] or NULL */
	const char *sensor_path;          /* its file, or NULL */
	const char *const *adc_paths;     /* scene's [adc] spec files */
	size_t n_adc;
	/* scene's inline [adc] specification (section "adc"), or NULL */
	const struct ssc_ini *adc_ini;
	/* results of earlier stages this one uses (scene), or none */
	const struct ssc_result *upstream;
	size_t n_upstream;
	/* results of every stage a scene ran before this one, used or not:
	 * a stage takes from them only the very computation it would
	 * repeat (the same samples and options), so that its result is the
	 * same with or without them */
	const struct ssc_result *earlier;
	size_t n_earlier;
	/* a stage that streams its inputs (streams(), caps NULL): input i
	 * read as the command reads it (a manifest's channels and
	 * temperature column); errors printed, an exit code returned; the
	 * caller frees *cap with sscope_capture_free() */
	int (*load)(const struct ssc_stage_env *env, size_t i,
		    struct sscope_capture **cap);
	const void *load_ctx;
	/* a manifest's channels and temperature column of each input
	 * (entries NULL: none given), or NULL without a manifest */
	const char *const *unit_columns, *const *unit_temps;
};

/* Inputs a stage needs (for scene planning). */
enum {
	SSC_NEED_DATA = 1u << 0,   /* data channels */
	SSC_NEED_TEMP = 1u << 1,   /* a temperature column */
	SSC_NEED_SENSOR = 1u << 2, /* a sensor specification */
	SSC_NEED_ADC = 1u << 3,    /* ADC specifications */
	/* with SSC_NEED_DATA: a scene without captures may give a sensor
	 * specification instead */
	SSC_NEED_DATA_OR_SENSOR = 1u << 4,
};

struct ssc_stage_ops {
	const struct ssc_command_spec *spec;
	const char *title;        /* section title in reports */
	unsigned needs;           /* SSC_NEED_* */
	int min_files, max_files; /* operands (max -1: any) */
	size_t opts_size;
	void (*init)(void *opts);
	int (*handle)(int key, const char *arg, void *opts);
	/* after all options: cross-checks (usage errors) and what follows
	 * from the options (a stage's own --plot sets co->plot); called for
	 * the command and in scenes alike */
	int (*check)(struct ssc_common *co, void *opts);
	/* optional: true when the command should read its input itself
	 * (streaming, memory independent of the record); run() then gets
	 * paths without captures */
	bool (*streams)(const void *opts);
	/* true when run() rejects NaN (without --allow-nan) and infinite
	 * samples in its first pass over them and calls ssc_check_values()
	 * when it fails: a command then reads a file used in place without
	 * the reader's pass over the samples */
	bool checks_values;
	/* a folder operand (not a rosbag2 folder, which holds
	 * metadata.yaml) stands for its files, sorted by name: every regular
	 * file not hidden and not a scene, document or figure (.ini, .md,
	 * .json, .yaml, .yml, .svg, .png, .html); a manifest (a CSV file
	 * whose header names the columns unit and file, optionally channels
	 * and temperature) for its units, each file relative to the
	 * manifest, read with its channels (-c) and temperature column */
	bool folders;
	/* optional (with folders): an operand the options name (a
	 * manifest), read after the command line's, or NULL */
	const char *(*manifest)(const void *opts);
	/* compute: *result receives the stage's result struct, which may
	 * point into env's captures and paths (they live as long as it) */
	int (*run)(const struct ssc_stage_env *env, void *opts, void **result);
	/* present the result (each called only when its form is asked for) */
	json_t *(*json)(const void *opts, const void *result);
	/* optional: write the --format json output of the command itself,
	 * the very text ssc_emit_json() makes of json() (large results
	 * without a tree); returns an exit code */
	int (*emit_json)(const struct ssc_common *co, const void *opts,
			 const void *result);
	void (*text)(FILE *f, const void *opts, const void *result);
	void (*csv)(FILE *f, const void *opts, const void *result); /* or NULL */
	/* rows {"channel","quantity","value","lo","hi","unit","note"} */
	void (*summary)(json_t *rows, const void *opts, const void *result);
	/* the figure (NULL: none); returns an exit code */
	int (*plot)(const struct ssc_common *co, const void *opts,
		    const void *result, const char *path);
	/* files the options ask for besides the output (NULL: none) */
	int (*write)(const struct ssc_common *co, const void *opts,
		     const void *result);
	void (*free_result)(void *result);
	void (*fini)(void *opts);
};

/* Forms a scene asks for. */
enum {
	SSC_WANT_TEXT = 1u << 0,
	SSC_WANT_JSON = 1u << 1,
	SSC_WANT_SUMMARY = 1u << 2,
};

/* One invocation of a stage. */
struct ssc_stage_call {
	/* options as a command line: argv[0] the command, then options (a
	 * scene writes one "--key=value" per key of its section) and, for
	 * the command, the input files */
	int argc;
	char **argv;
	const char *const *where; /* where argv[i] came from ("scene.ini:
				     line 12"), or NULL */
	const char *name;    /* scene: the stage's name in messages */
	const char *context; /* scene: its file, for usage errors of
				check() and run() */
	/* a scene: its shared options ([input]), loaded inputs, specs and
	 * earlier results; base == NULL: the command line */
	const struct ssc_common *base;
	struct sscope_capture *const *caps;
	const char *const *paths;
	size_t n_caps;
	const struct sscope_sensor_spec *sensor;
	const char *sensor_path;
	const char *const *adc_paths;
	size_t n_adc;
	const struct ssc_ini *adc_ini;
	const struct ssc_result *upstream;
	size_t n_upstream;
	const struct ssc_result *earlier; /* see ssc_stage_env */
	size_t n_earlier;
	bool check_only;       /* parse and check the options, nothing else */
	unsigned want;         /* scene: SSC_WANT_* */
	const char *plot_path; /* scene: draw the figure there, or NULL */
	/* out (scene): owned by the caller, ssc_stage_call_clear() */
	struct ssc_result result;
	json_t *json;
	char *text;
	json_t *summary;
	/* the inputs the result may point into (views of the scene's
	 * captures), freed with it */
	struct sscope_capture **views;
	size_t n_views;
};

/*
 * Parse the options, check them, shape (or load) the inputs, run the stage
 * and present its result: for the command line in its --format to -o (or
 * stdout), for a scene into call->json/text/summary as asked, with the
 * typed result in call->result.  Prints errors.  Returns the exit code.
 */
int ssc_stage_exec(const struct ssc_stage_ops *ops, struct ssc_stage_call *call);

/* Free what ssc_stage_exec() left in a call. */
void ssc_stage_call_clear(struct ssc_stage_call *call);

/* `sensorscope CMD [OPTIONS] FILE...`: ssc_stage_exec() of argv. */
int ssc_stage_main(const struct ssc_stage_ops *ops, int argc, char **argv);

/* Free a result (and set it empty). */
void ssc_result_free(struct ssc_result *r);

/* The first result of stage @p ops among @p env's upstream results, and
 * the number of them in *n (a stage run once per capture leaves one per
 * capture); NULL when none. */
const struct ssc_result *ssc_stage_upstream(const struct ssc_stage_env *env,
					    const struct ssc_stage_ops *ops,
					    size_t *n);

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
extern const struct ssc_stage_ops ssc_datasheet_stage;
extern const struct ssc_stage_ops ssc_lot_stage;
extern const struct ssc_stage_ops ssc_nav_stage;
extern const struct ssc_stage_ops ssc_plan_stage;

#endif
