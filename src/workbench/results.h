/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Typed results of the stages that other stages read (budget, heading,
 * walk and navsim read allan's noise terms; budget calib's remaining
 * uncertainty, navsim calib's error model): plain structs around the
 * library's result structs, so a later stage takes numbers and quantities
 * directly, never from re-parsed JSON or unit strings.
 */
#ifndef SSCOPE_RESULTS_H
#define SSCOPE_RESULTS_H

#include "stage.h"
#include "calibfile.h"

/* ------------------------------------------------------------ allan */

/* Units of one channel's results (as text for presentation). */
struct ssc_allan_units {
	enum sscope_quantity rq; /* quantity of the rate the deviations are
				    of (angle input: its derivative) */
	char rate[64];           /* the rate unit as text ("deg/s") */
	char rate_si[64];        /* its SI form ("rad/s") */
	char dev[96];            /* unit of the deviation values in JSON */
	double dev_scale;        /* SI per JSON dev unit */
	char show[96];           /* unit of deviations in text/CSV/plot */
	double show_scale;       /* SI per shown unit */
	char term[5][96];        /* conventional unit of each term */
	char term_si[5][96];     /* SI unit of each term */
};

struct ssc_allan_chan {
	const struct sscope_capture_column *col;
	struct ssc_allan_units u;
	struct sscope_allan_result *res; /* deviations and the noise fit */
	struct sscope_adequacy *adq;     /* what the record supports (NULL
					    with --no-fit) */
	size_t n, nan;
};

struct ssc_allan_file {
	const char *path;
	const struct sscope_capture *cap;
	struct ssc_allan_chan *ch;
	size_t n_ch;
};

struct ssc_allan_res {
	struct ssc_allan_file *fr;
	size_t n_files;
	double ci_level; /* level of the channels' intervals (0: none) */
	/* what every channel was computed with (sscope_allan_analyze()'s
	 * grid and options; no release callback, no plan) */
	enum sscope_allan_tau_grid grid;
	struct sscope_allan_opts ao;
	struct sscope_noise_fit_opts fo;
};

/*
 * The result an allan stage computed for the samples data[0..n) at
 * rate_hz (a channel of one of its captures, the very array) with this
 * grid and these options (release and plan ignored), or NULL: a later
 * stage that needs exactly that takes it instead of computing it again.
 */
const struct sscope_allan_result *
ssc_allan_res_find(const struct ssc_allan_res *R, const double *data, size_t n,
		   double rate_hz, enum sscope_allan_tau_grid grid,
		   const struct sscope_allan_opts *ao,
		   const struct sscope_noise_fit_opts *fo);

/* The name of the noise type of slope alpha ("WFM", ...; "?" outside
 * -4..2), as the allan JSON writes it (allan-json.c). */
const char *ssc_allan_noise_name(int alpha);

/* The "points" array of an allan channel's JSON as text, the very bytes
 * jansson writes of it; @p dev_scale SI per JSON deviation unit; a long
 * grid is split over two threads when @p two_threads.  Returns false on a
 * write error. */
bool ssc_allan_points_text(FILE *f, const struct sscope_allan_point *pts,
			   size_t n, double dev_scale,
			   enum sscope_allan_dev dev, bool two_threads);

/* The adequacy object of an allan channel's JSON: the verdict, each
 * test's outcome, the findings and the DAVAR map with its deviations in
 * @p rate_unit (allan-json.c).  A new reference. */
json_t *ssc_adequacy_json(const struct sscope_adequacy *q, const char *rate_unit);

/* How an allan result was computed, as its JSON says it (the command
 * fills it from its options). */
struct ssc_allan_json_opts {
	enum sscope_allan_input input;
	enum sscope_allan_dev dev;
	double ci;          /* level of the deviations' intervals; < 0: none */
	bool no_fit;        /* deviations only: no terms, fit, read-offs */
	double model_error; /* the fit's relative model error (<= 0: none) */
	bool two_threads;   /* a long grid's points text on two threads */
};

/*
 * The JSON of an allan result: one file's object ({"command", "file",
 * "channels"}), or {"command", "files"} for several.  With @p slot, each
 * channel's "points" is a placeholder numbered from *slot on (see
 * ssc_emit_json_slots) that ssc_allan_json_points() writes; without, the
 * points are in the tree.  A new reference.
 */
json_t *ssc_allan_json(const struct ssc_allan_json_opts *o,
		       const struct ssc_allan_res *R, size_t *slot);

/* The "points" text of slot @p slot of ssc_allan_json() (the channels of
 * the files in order).  Returns false on a write error or no such slot. */
bool ssc_allan_json_points(FILE *f, const struct ssc_allan_json_opts *o,
			   const struct ssc_allan_res *R, size_t slot);

/* Words and values the text output shares with the JSON. */

/* A fit whose chi-squared p-value is below this is rejected: the
 * five-term model does not describe the data (1 % level). */
#define SSC_ALLAN_FIT_REJECT_P 0.01
bool ssc_allan_fit_rejected(const struct sscope_noise_fit *ft);
/* why a term is not reported present, in words (NULL when present) */
const char *ssc_allan_absent_reason(const struct sscope_noise_coef *cf);
/* why the read-off of term t is not given */
const char *ssc_allan_readoff_absent(const struct sscope_noise_fit *ft, int t);
/* the presence test, in words, with its level, into buf */
const char *ssc_allan_select_words(const struct sscope_noise_fit *ft, char *buf,
				   size_t len);
/* value (SI) in unit; NaN stays NaN, an unconvertible value is NaN */
double ssc_allan_in_unit(double si, const char *si_unit, const char *unit);
/* why the noise fit of a channel failed */
const char *ssc_allan_fit_msg(const struct ssc_allan_chan *c);
/* the first adequacy finding of severity doubt or invalid on term t */
const struct sscope_adequacy_finding *
ssc_allan_term_doubt(const struct ssc_allan_chan *c, int t);

/* What the analysis doubts in a channel's fit: the text, JSON and report
 * show the same messages. */
struct ssc_allan_warn {
	const char *code; /* JSON warning code ("fit_rejected") */
	char msg[480];
};

/* At most @p max warnings of channel @p c into w; returns their number. */
size_t ssc_allan_chan_warnings(const struct ssc_allan_json_opts *o,
			       const struct ssc_allan_chan *c,
			       struct ssc_allan_warn *w, size_t max);

/*
 * The quantity of the rate whose deviations a saved allan channel (one
 * object of its "channels") holds: its "quantity", differentiated for an
 * "input" of "angle" (sscope_allan_rate_quantity()); in a result of the
 * contract's shape, without "quantity", the quantity whose N has the
 * dimension of the channel's N "si_unit" (parsed, never compared as
 * text).  The one rule by which a result read back (budget --result,
 * heading/walk/navsim --from-allan) is a gyro or an accelerometer;
 * SSCOPE_QUANTITY_UNKNOWN for anything else.
 */
enum sscope_quantity ssc_allan_json_rate_quantity(const json_t *ch);

/* ------------------------------------------------------------ calib */

/* struct ssc_calib_res, the calib stage's result: calibfile.h */

#endif
