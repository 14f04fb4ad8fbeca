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

/* one unit's channel: N, B, K in SI (NaN when not present) */
struct ssc_lot_cell {
	double v[3], lo[3], hi[3];
	bool present[3];
};

/* one channel's term over the lot */
struct ssc_lot_term {
	size_t n_resolved;   /* units whose fit shows the term */
	bool done;           /* spread estimated (>= 3 units) */
	struct sscope_lot_spread sp; /* SI */
	bool *outlier;       /* per unit (false where not resolved) */
	double *z;           /* per unit (NaN where not resolved) */
};

struct ssc_lot_result {
	size_t n_units, n_chan;
	const char *const *paths;
	const char **chan;                /* channel names (the first unit's) */
	enum sscope_quantity *q;
	struct ssc_lot_cell *cell;        /* n_units x n_chan */
	struct ssc_lot_term *term;        /* n_chan x 3 */
	double level;
};

/* Analyse each capture and the lot: prints errors, returns an exit code
 * and *out (which points into paths). */
int ssc_lot_run(const char *cmd, struct sscope_capture *const *caps,
		const char *const *paths, size_t n, double level,
		struct ssc_lot_result **out);
/* the stage's presenters (opts unused; result a struct ssc_lot_result) */
json_t *ssc_lot_json(const void *opts, const void *result);
void ssc_lot_text(FILE *f, const void *opts, const void *result);
void ssc_lot_summary(json_t *rows, const void *opts, const void *result);
void ssc_lot_free(void *result);

#endif
