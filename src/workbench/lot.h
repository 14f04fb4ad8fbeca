/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The `lot` stage's computation and presentation: many captures of one
 * model (one unit each), every gyro and accelerometer channel's noise
 * terms N, B, K with their intervals (the allan stage's fit), and per
 * channel and term the spread between units (sscope_lot_spread(): the
 * population mean, the between-unit sd separated from each unit's own
 * uncertainty, the outlier units).
 */
#ifndef SSCOPE_WB_LOT_H
#define SSCOPE_WB_LOT_H

#include "workbench.h"

#include "datasheet.h"

/* level of the interval a unit's verdict against a limit is guard-banded
 * by (the datasheet command's default): a unit exactly at its limit is
 * called within spec in about (1 - 0.99) / 2 = 0.5 % of the cases */
#define SSC_LOT_SPEC_LEVEL 0.99

/* one unit's channel: N, B, K in SI (NaN when not present) */
struct ssc_lot_cell {
	double v[3], lo[3], hi[3];
	bool present[3];
	/* against a limit (has_spec): the fit's interval at
	 * SSC_LOT_SPEC_LEVEL [glo, ghi], or ghi alone as an upper bound
	 * (gbound: the term not shown), and the verdict */
	bool has_spec[3], gbound[3];
	double glo[3], ghi[3];
	enum sscope_datasheet_verdict verdict[3];
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
	struct sscope_lot_cpk cpk; /* SI, over the units that show it */
};

struct ssc_lot_result {
	size_t n_units, n_chan;
	const char *const *paths;
	const char **chan;                /* channel names (the first unit's) */
	enum sscope_quantity *q;
	struct ssc_lot_cell *cell;        /* n_units x n_chan */
	struct ssc_lot_term *term;        /* n_chan x 3 */
	double level;
	struct ssc_datasheet *spec;       /* the limits (NULL without) */
};

/* Analyse each capture and the lot, against the limits in the datasheet
 * INI @p spec_path when not NULL: prints errors, returns an exit code and
 * *out (which points into paths and spec_path). */
int ssc_lot_run(const char *cmd, struct sscope_capture *const *caps,
		const char *const *paths, size_t n, double level,
		const char *spec_path, struct ssc_lot_result **out);
/* the stage's presenters (opts unused; result a struct ssc_lot_result) */
json_t *ssc_lot_json(const void *opts, const void *result);
void ssc_lot_text(FILE *f, const void *opts, const void *result);
void ssc_lot_summary(json_t *rows, const void *opts, const void *result);
void ssc_lot_free(void *result);

#endif
