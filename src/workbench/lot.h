/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The `lot` stage's computation and presentation: many captures of one
 * model (one unit each), every gyro and accelerometer channel's noise
 * terms N, B, K with their intervals (the allan stage's fit), and per
 * channel and term the spread between units (sscope_lot_spread(): the
 * population mean, the between-unit sd separated from each unit's own
 * uncertainty, the outlier units); the same for each unit's bias, its
 * drift over the record and its temperature sensitivity.
 */
#ifndef SSCOPE_WB_LOT_H
#define SSCOPE_WB_LOT_H

#include "workbench.h"

#include "stage.h"

#include "datasheet.h"

/* level of the interval a unit's verdict against a limit is guard-banded
 * by (the datasheet command's default): a unit exactly at its limit is
 * called within spec in about (1 - 0.99) / 2 = 0.5 % of the cases */
#define SSC_LOT_SPEC_LEVEL 0.99

/* the terms of a unit's channel: the noise terms of the allan stage's
 * fit, then the bias over the record, its drift and its temperature
 * sensitivity (sscope_lot_bias(): batch means) */
enum {
	SSC_LOT_N, SSC_LOT_B, SSC_LOT_K, SSC_LOT_BIAS, SSC_LOT_DRIFT,
	SSC_LOT_TEMPCO, SSC_LOT_NT
};
/* batches of sscope_lot_bias() */
#define SSC_LOT_BIAS_BLOCKS 20
/* a drift's or temperature sensitivity's interval is flagged when its
 * conservative standard error (B, K at the fit's upper bounds where it
 * does not show them) exceeds the reported one by more than this: a
 * 68.3 % interval whose true se is 1.5 times its own covers 49.5 %, less
 * than half the time (1.2 times: 59.5 %, within the sampling spread of
 * an se from 17 degrees of freedom) */
#define SSC_LOT_SE_UPPER_RATIO 1.5

/* one unit's channel: each term in SI (NaN when not present), its 68.3 %
 * interval and standard error */
struct ssc_lot_cell {
	double v[SSC_LOT_NT], lo[SSC_LOT_NT], hi[SSC_LOT_NT], se[SSC_LOT_NT];
	bool present[SSC_LOT_NT];
	bool constant;       /* every sample equal: a stuck sensor? */
	/* against a limit (has_spec): the fit's interval at
	 * SSC_LOT_SPEC_LEVEL [glo, ghi], or ghi alone as an upper bound
	 * (gbound: the term not shown), and the verdict */
	bool has_spec[SSC_LOT_NT], gbound[SSC_LOT_NT];
	double glo[SSC_LOT_NT], ghi[SSC_LOT_NT];
	enum sscope_datasheet_verdict verdict[SSC_LOT_NT];
	struct sscope_lot_bias bias; /* SI */
	/* the noise model of the drift's and sensitivity's intervals: N,
	 * B, K shown by the fit of the record less its temperature effect
	 * (0: not shown) */
	double model[3];
	/* the upper bounds of B and K: the upper end of the interval where
	 * the fit shows the term, its bound where not (INFINITY: none
	 * finite), [0] unused: the conservative standard errors
	 * (sscope_lot_bias()'s se_upper) */
	double model_hi[3];
	/* the Allan deviation (OADEV, dense taus) for the figure */
	double *tau_s, *adev;
	size_t n_adev;
	/* the bias figure's record: compensated sums of the samples about
	 * their mean at every fig_block-th sample (fig_k + 1 of them, the
	 * last at the record's end); the record itself is not kept */
	double fig_mean, *fig_cs;
	size_t fig_block, fig_k;
};

/* one channel's term over the lot */
struct ssc_lot_term {
	size_t n_resolved;   /* units whose fit shows the term */
	bool done;           /* spread estimated (>= 3 units) */
	struct sscope_lot_spread sp; /* SI */
	bool *outlier;       /* per unit (false where not resolved) */
	double *z;           /* per unit (NaN where not resolved) */
	double limit;        /* upper limit, SI; NaN without */
	size_t count[3];     /* units per enum sscope_datasheet_verdict */
	bool cpk_done;       /* cpk computed (>= 3 units show the term) */
	bool mean_lo_cut;    /* a noise amplitude's interval cut at 0 */
	struct sscope_lot_cpk cpk; /* SI, over the units that show it */
};

struct ssc_lot_result {
	size_t n_units, n_chan;
	const char *const *paths;
	const char *const *labels;        /* the units' names (a manifest's),
					     or NULL: the files' base names */
	double *rate_hz;                  /* per unit, Hz */
	size_t *n_samples;                /* per unit */
	bool temp;                        /* the units have temperatures */
	char **chan;                      /* channel names (the first unit's) */
	enum sscope_quantity *q;
	struct ssc_lot_cell *cell;        /* n_units x n_chan */
	struct ssc_lot_term *term;        /* n_chan x SSC_LOT_NT */
	double level;
	double smooth_s;                  /* the figure's moving mean, s
					     (0: 1/100 of the record) */
	struct ssc_datasheet *spec;       /* the limits (NULL without) */
	const char *spec_path;            /* their file */
	struct ssc_lot_merged *merged;    /* what a merged lot points into, or
					     NULL (freed with the result) */
	char note[512];                   /* --plan-jobs, --job: what was
					     written (no units), or "" */
};

/* the results a merged lot points into (lot-jobs.c) */
struct ssc_lot_merged {
	json_t *plan, **units;
	const char **paths, **labels;
	size_t n;
};

/* Analyse each unit of env (its captures, or each read in turn by
 * env->load and freed when analysed: memory of one record at a time) and
 * the lot, against the limits in the datasheet INI @p spec_path when not
 * NULL: prints errors, returns an exit code and *out (which points into
 * env's paths and labels and into spec_path). */
int ssc_lot_run(const struct ssc_stage_env *env, double level,
		const char *spec_path, double smooth_s,
		struct ssc_lot_result **out);
/* The lot in parts (ssc_lot_run, and runs split over machines:
 * lot-jobs.c): a result for n units; its channels (those of angular rate
 * and acceleration among names, the limits of spec_path checked against
 * them), set from the first unit's capture by ssc_lot_unit() when not set
 * before; each unit's analysis into its row; the spread and verdicts.
 * Each prints its errors and returns an exit code. */
struct ssc_lot_result *ssc_lot_new(const char *cmd, size_t n,
				   const char *const *paths,
				   const char *const *labels, double level,
				   const char *spec_path, double smooth_s,
				   int *rc);
int ssc_lot_set_channels(const char *cmd, struct ssc_lot_result *r, bool temp,
			 const char *const *names,
			 const enum sscope_quantity *q, size_t n);
int ssc_lot_unit(const char *cmd, struct ssc_lot_result *r, size_t u,
		 const struct sscope_capture *cap, struct sscope_noise_plan *plan);
int ssc_lot_finish(const char *cmd, struct ssc_lot_result *r);

/* Runs split over machines (lot-jobs.c): --plan-jobs ENGINE:DIR writes
 * DIR/plan.json and the engine's file (slurm: DIR/lot.sbatch, parallel:
 * DIR/jobs.txt) for env's units; --job DIR:I analyses unit I into
 * DIR/unit-I.json; --merge DIR makes the lot of those results (*out as
 * ssc_lot_run's).  Each prints its errors and returns an exit code. */
int ssc_lot_plan_jobs(const struct ssc_stage_env *env, const char *engine,
		      const char *dir, double level, const char *spec,
		      double smooth_s, char *note, size_t len);
int ssc_lot_job(const struct ssc_common *co, const char *arg, char *note,
		size_t len);
int ssc_lot_merge(const struct ssc_common *co, const char *dir,
		  struct ssc_lot_result **out);
void ssc_lot_merged_free(struct ssc_lot_merged *m);

/* For the presenters of lot-report.c: an SI value in the term's unit as
 * the text shows it (*unit set), the term's JSON key, a unit's name, why a
 * unit's interval is doubtful (NULL: it is not). */
double ssc_lot_value(const struct ssc_lot_result *r, size_t c, int t, double si,
		     const char **unit);
const char *ssc_lot_term_key(int t);
/* the same in words (text and pages) */
const char *ssc_lot_term_label(int t);
/* the words for a term's JSON key (the key itself when not a term's) */
const char *ssc_lot_key_label(const char *key);
/* "mean [lo, hi]" and "between-unit sd [lo, hi]" of a term, as the text */
void ssc_lot_spread_text(const struct ssc_lot_result *r, size_t c, int t,
			 char *mean, size_t ml, char *sd, size_t sl);
const char *ssc_lot_unit_name(const struct ssc_lot_result *r, size_t u);
const char *ssc_lot_doubt(const struct ssc_lot_cell *cl, int t);
/* the conservative standard error of a unit's drift or sensitivity (B,
 * K at the fit's bounds where not shown), SI; NaN for the other terms */
double ssc_lot_se_upper(const struct ssc_lot_cell *cl, int t);
/* --format csv: one row per unit, channel and term (lot-report.c) */
void ssc_lot_csv(FILE *f, const void *opts, const void *result);
/* --report DIR (a new folder): index.html (the lot's table, both figures,
 * one row per unit linking to its page units/unit-N.html), lot.json,
 * lot.csv, the figures' SVG files; prints errors, returns an exit code */
int ssc_lot_report(const struct ssc_common *co, const struct ssc_lot_result *r,
		   const char *dir);

/* the stage's presenters (opts unused; result a struct ssc_lot_result) */
json_t *ssc_lot_json(const void *opts, const void *result);
void ssc_lot_text(FILE *f, const void *opts, const void *result);
void ssc_lot_summary(json_t *rows, const void *opts, const void *result);
void ssc_lot_free(void *result);
/* --plot PATH: the units' biases against time at PATH, their Allan
 * deviations at PATH with "-adev" before the extension */
int ssc_lot_plot(const struct ssc_common *co, const void *opts,
		 const void *result, const char *path);

#endif
