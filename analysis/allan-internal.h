/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Internal interface between the files of the Allan module (allan.c: the
 * deviation engine, allan-edf.c: degrees of freedom and noise
 * identification, noisefit.c: the IEEE 952 fit).  Not installed.
 */
#ifndef SSCOPE_ALLAN_INTERNAL_H
#define SSCOPE_ALLAN_INTERNAL_H

#include "internal.h"

#include "sscope-allan.h"

/* Decimated-phase points the noise identification looks at, at most. */
#define SSC_NOISE_ID_MAX 65536
/* Averages the lag-1 method needs (Riley & Greenhall 2004). */
#define SSC_NOISE_ID_MIN 30
/* Analysis points from which a lag-1 type stands on its own for the
 * interval: the r1 of a white series (sd 1 / sqrt(n)) reaches the rounding
 * boundary to flicker phase, r1 = -0.2 (rho = -0.25), at 3 sd only from
 * n = (3 / 0.2)^2 on; with fewer, a type of more degrees of freedom than
 * the shorter tau's is not trusted for the interval (allan.c compute()). */
#define SSC_NOISE_ID_SURE 225

/* Averages the B1 fallback needs before it carries the last
 * identification instead (Stable32's behaviour on its reference sets;
 * TOTDEV uses the Allan variance's identification, this minimum too). */
#define SSC_B1_MIN_AVERAGES 8

/* What the B1 / R(n) fallback for fewer than SSC_NOISE_ID_MIN points
 * needs (NIST SP 1065 section 5.6). */
struct ssc_nid_few {
	double n_points;     /* analysis points of the deviation (the N of
				Barnes' B1 function, as Stable32) */
	size_t m;            /* averaging factor */
	size_t min_averages; /* fewer valid averages: -EDOM (carry) */
	double rn;           /* MVAR / AVAR at m for modified deviations
				(tells white from flicker phase), else NaN */
};

/*
 * Noise identification on an already decimated series z[0..n) (phase
 * points z_k = x(k m)), with optional validity flags (NULL: all valid):
 * the lag-1 autocorrelation with at least SSC_NOISE_ID_MIN analysis
 * points, else the B1 ratio when few is given.  Work space: 2 n doubles
 * and n bytes, given by the caller.  -EDOM: not identified (too few
 * points, constant data).
 */
int ssc_noise_id_series(const double *z, const unsigned char *valid,
			size_t n, bool rate_like, int dmax,
			const struct ssc_nid_few *few, int *alpha,
			double *alpha_est, double *work, unsigned char *vwork);

/* quantile of chi-squared (safeguarded Newton; never calls the GSL
 * error handler) */
double ssc_chi2_quantile(double p, double nu);

/* chi-squared bounds of a deviation with edf degrees of freedom */
void ssc_allan_ci(double dev, double edf, double level, double *lo,
		  double *hi);

/* what the bounds of one confidence level share at every tau: the two
 * tail probabilities and their normal scores (computed once a grid) */
struct ssc_ci_start;
struct ssc_ci_level {
	double pl, ph; /* lower and upper tail probability */
	double zl, zh; /* their normal scores */
	bool ok;       /* both inside (0, 1) */
	struct ssc_ci_start *start; /* ssc_allan_ci_starts(), or NULL */
};
void ssc_allan_ci_level(struct ssc_ci_level *cl, double level);
/* Grids of at least this many taus take the quantiles from a table. */
#define SSC_CI_STARTS_MIN 2048
/* For a grid of many taus: the level's two quantiles tabulated against
 * the degrees of freedom (Chebyshev series of ln q in ln nu, 0.5 <= nu <
 * 1000), instead of one or two incomplete-gamma evaluations each (the
 * same quantiles to 3e-14 at usual levels, tested to 1e-13).  -ENOMEM:
 * none (the full computation is used).  Freed by
 * ssc_allan_ci_level_free(). */
int ssc_allan_ci_starts(struct ssc_ci_level *cl);
void ssc_allan_ci_level_free(struct ssc_ci_level *cl);
/* ssc_allan_ci() with the level's shared part */
void ssc_allan_ci_at(const struct ssc_ci_level *lv, double dev, double edf,
		     double *lo, double *hi);

/* EDF of TOTDEV (NIST SP 1065 table 7; OADEV's for phase noises) */
double ssc_totdev_edf(int alpha, size_t m, size_t n_phase);

/* Benchmarks and tests: force the contiguous per-tau engine (no tiling,
 * no fusion) for OADEV and OHDEV, to compare the two. */
void ssc_allan_force_contiguous(struct sscope_allan *plan, bool on);

/* Tests: leave the 64-byte (AVX-512) kernels unused on a CPU that has
 * them, to show that both give the same sums (process-wide). */
void ssc_allan_force_narrow(bool on);

/* Tests: the OADEV sums by their definition only (no transforms for a
 * grid of many factors), to compare the kernels bit for bit
 * (process-wide). */
void ssc_allan_force_definition(bool on);

/* Difference order and whether a deviation is a "modified" one */
int ssc_dev_order(enum sscope_allan_dev dev);

/* allan-family.c: the total, Theo and time-error deviations on phase
 * points x[0..np) (see that file for definitions and costs); NAN outside
 * a deviation's limits (or -ENOMEM for the total ones) */
/* TheoBR averages at most this many bias ratios (SP 1065 eq. 35) */
#define SSC_THEOBR_RATIOS 32
/* phase points TheoBR's bias ratio needs: floor(0.1 np / 3) - 3 >= 0 */
#define SSC_THEOBR_MIN_NP 90
struct ssc_xf_ws;
double ssc_theo1_var(const double *x, size_t np, size_t m, double tau0,
		     unsigned threads, struct ssc_xf_ws *ws);
double ssc_theobr_ratio(const double *x, size_t np, double tau0,
			unsigned threads, struct ssc_xf_ws *ws);
/* the largest Theo1 factor of that ratio (0: too short) */
size_t ssc_theobr_mmax(size_t np);
double ssc_mtot_var(const double *x, size_t np, size_t m, double tau0,
		    unsigned threads);
double ssc_htot_var(const double *x, size_t np, size_t m, double tau0,
		    unsigned threads);
size_t ssc_mtie_work(size_t m);
double ssc_mtie(const double *x, size_t np, size_t m, size_t *work);
double ssc_tierms(const double *x, size_t np, size_t m);
double ssc_mtot_edf(int alpha, size_t m, size_t np);
double ssc_htot_edf(int alpha, size_t m, size_t np);
double ssc_theo1_edf(int alpha, size_t m, size_t np);
double ssc_htot_bias(int alpha);

/* allan-xform.c: sums by Fourier transforms.  A workspace holds the phase
 * less its line and its autocorrelation (NULL: no memory, or np beyond
 * 2^22), for Theo1 and OADEV; used by one call at a time.
 * ssc_theo_fast_pays() says where the transforms beat
 * the definition; ssc_theo1_sum_fast() returns the sum of eq. 33 (NAN: m
 * outside [128, np), odd) and a bound of its rounding error in *err. */
#define SSC_THEO_FAST_TOL 1e-8 /* largest accepted bound, of the sum */
struct ssc_xf_ws *ssc_xf_ws_new(const double *x, size_t np);
void ssc_xf_ws_free(struct ssc_xf_ws *w);
bool ssc_theo_fast_pays(size_t np, size_t m);
double ssc_theo1_sum_fast(struct ssc_xf_ws *w, size_t m, unsigned threads,
			  double *err);
/* the overlapping Allan variance's sums at every m in [1, D] (2D < np)
 * by transforms, into V[m] with rounding bounds err[m] (V and err have
 * D + 1 entries); ssc_oadev_fast_pays(): whether that beats summing the
 * n factors m[] by the definition */
#define SSC_OADEV_FAST_TOL 1e-10 /* largest accepted bound, of the sum */
bool ssc_oadev_fast_pays(size_t np, const size_t *m, size_t n);
int ssc_oadev_sums_fast(struct ssc_xf_ws *w, size_t D, unsigned threads,
			double *V, double *err);

/* sscope_noise_avar_cov() for n_coef coefficient sets at once (the sums
 * over pairs of points computed once): cov receives n_coef blocks of
 * n * n values. */
int ssc_noise_avar_cov_many(const double (*coef)[5], size_t n_coef,
			    double rate_hz, const size_t *m,
			    const size_t *terms, size_t n, double *cov);

#endif
