/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Internal helpers shared by the library's modules (not installed).
 * Every .c file of the library includes this header first, so config.h
 * precedes everything else.  It lives in src/core/, the bottom layer: it
 * includes only sscope-core.h and ssc.h.
 */
#ifndef SSCOPE_INTERNAL_H
#define SSCOPE_INTERNAL_H

#include "config.h"

#include <errno.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sscope-core.h"
#include "ssc.h"

/* Each file includes the public headers of what it uses (sscope-AREA.h),
 * never the umbrella sensorscope.h, so that its includes show its layer. */
struct sscope_clip;
struct sscope_reader;
struct sscope_reader_chunk;
struct sscope_reader_opts;

#if defined(__GNUC__)
#define SSC_PRINTF(f, a) __attribute__((format(printf, f, a)))
#define SSC_UNUSED __attribute__((unused))
#else
#define SSC_PRINTF(f, a)
#define SSC_UNUSED
#endif

/* OpenMP directives that vanish without OpenMP (no unknown-pragma
 * warnings): SSC_OMP(omp parallel for schedule(static, 1)) */
#ifdef _OPENMP
#define SSC_OMP(...) _Pragma(#__VA_ARGS__)
#else
#define SSC_OMP(...)
#endif

/* Fill diag->msg (if diag is not NULL); returns err for tail calls. */
int ssc_diag(struct sscope_diag *diag, int err, const char *fmt, ...)
	SSC_PRINTF(3, 4);

/* A stretch whose GSL failures are expected and handled from their
 * return codes (src/core/gslerr.c): no GSL error handler runs inside it.
 * With the recorder of sscope-gsl.h installed it only marks the calling
 * thread (no process-wide change, so threads do not race); otherwise it
 * switches GSL's handler off and back, as the library always did. */
struct ssc_gsl_quiet {
	void (*old)(const char *reason, const char *file, int line, int code);
	bool swapped;
};
void ssc_gsl_quiet_begin(struct ssc_gsl_quiet *q);
void ssc_gsl_quiet_end(struct ssc_gsl_quiet *q);

/* Overflow-checked size_t arithmetic: return false on overflow. */
static inline bool ssc_mul(size_t a, size_t b, size_t *out)
{
	return !__builtin_mul_overflow(a, b, out);
}

static inline bool ssc_add(size_t a, size_t b, size_t *out)
{
	return !__builtin_add_overflow(a, b, out);
}

/* A duration times a rate (or any real) as a count of samples, v already
 * rounded the caller's way (round, ceil, floor): 0 for NaN and negative
 * v, SSC_COUNT_MAX for v at or beyond it (2^62: more samples than any
 * record holds), where converting the double to size_t would be
 * undefined (a --run-length of 1e20 s crashed). */
#define SSC_COUNT_MAX ((size_t)1 << 62)
static inline size_t ssc_count(double v)
{
	if (!(v > 0))
		return 0;
	return v >= (double)SSC_COUNT_MAX ? SSC_COUNT_MAX : (size_t)v;
}

/* malloc of a * b bytes with overflow check; NULL on failure. */
void *ssc_alloc_array(size_t count, size_t size);

/* Map the whole pages of [p, p + bytes) writable now, in one call (a
 * region about to be written: one kernel entry instead of a page fault
 * per page); the data are not touched.  A hint: does nothing where the
 * kernel cannot. */
void ssc_prefault(void *p, size_t bytes);
/* The same for a region about to be read (a mapped file's pages: one
 * kernel entry instead of a fault per 64 KiB). */
void ssc_prefault_read(const void *p, size_t bytes);
/* Ask for 2 MiB pages on the whole 2 MiB blocks of [p, p + bytes): on
 * virtual machines where each 4 KiB page's first touch is costly (11 us
 * a page on the 2-core development machine: 0.36 GB/s), a large array
 * faulted in 2 MiB at a time costs a fraction of it.  A hint: does
 * nothing where the kernel cannot. */
void ssc_hint_huge(void *p, size_t bytes);
/* As ssc_alloc_array(), on whole 4 KiB pages, and a block of 1 MiB or
 * more on whole 2 MiB pages, hinted as above (freed with free()): on the
 * development machine a 2 MiB fault costs 0.8-2.5 ms, a 4 KiB one 9.3 us
 * (256 of them for 1 MiB: 2.4 ms); --taus all on 30,000 samples 1,486
 * faults and 29.4 ms from 1.5 MiB on, 859 and 27.3 ms from 1 MiB on. */
void *ssc_alloc_huge(size_t count, size_t size);
/* the whole pages inside [p, p + bytes) back to the system (their
 * contents become zeros), split over `threads` threads: the system's
 * work per page runs on every core */
void ssc_release_pages(void *p, size_t bytes, unsigned threads);

/* Golden-section search for a minimum of f on [a, b]: at most `iters`
 * steps while the bracket is wider than tol (f at x1 first, then x2; each
 * step one value).  On equal values the left part is kept when
 * left_on_tie, else the right.  *g: the final bracket, its inner points
 * and their values (a maximum: pass -f, left_on_tie keeps the left part
 * on equal maxima). */
struct ssc_golden {
	double a, b, x1, x2, f1, f2;
};
void ssc_golden_min(double (*f)(double x, void *ctx), void *ctx, double a,
		    double b, int iters, double tol, bool left_on_tie,
		    struct ssc_golden *g);

/* fn(ctx, i, slot) for every i in [0, n) on up to `threads` threads, the
 * caller among them (slot 0; helpers 1..threads-1, for per-thread
 * scratch), items claimed one at a time; returns when all are done,
 * without waiting for a helper that never got to run (pool.c).  An
 * item's result must not depend on the thread that runs it. */
void ssc_par_for(size_t n, unsigned threads,
		 void (*fn)(void *ctx, size_t i, unsigned slot), void *ctx);

/* 10th and 90th percentiles (lower order statistics) of the finite values
 * of a sliding variance (sscope_calib_variance_magnitude()), through
 * @p work (n doubles); p90 may be NULL.  Returns 0, or -EDOM when fewer
 * than max(1, min_finite) values are finite.  In analysis/calib.c. */
int ssc_calib_vs_deciles(const double *vs, size_t n, double *work,
			 size_t min_finite, double *p10, double *p90);

/* The stillness test (in analysis/walk.c): the 90th over the 10th
 * percentile of a record's variance over sliding windows of max(11,
 * rate_hz) samples (calib's detector).  A still record stays near 1 (walk
 * and the adequacy check accept up to 9); motion spans far more.  Returns
 * 0, -EDOM (record shorter than a window, fewer than 10 finite values),
 * -ENOMEM. */
int ssc_still_contrast(const double *x, size_t stride, size_t n, double fs,
		       double *ratio);

/* Symmetric positive definite Toeplitz matrix T (first column r[0..P-1])
 * by the Levinson-Durbin recursion (in analysis/adequacy.c): phi receives
 * the forward predictors of orders 1 .. P-1 (row k, of k entries, from
 * phi[(k - 1) k / 2]: P (P - 1) / 2 doubles) and v[k] the prediction
 * error variance of order k, which is the square of the k-th diagonal
 * entry of T's Cholesky factor L.  O(P^2).  Returns false when T is not
 * positive definite (a variance not positive, or not finite). */
bool ssc_levinson(const double *r, size_t P, double *phi, double *v);
/* out = L^-1 x (the innovations of x, each over its sd) with L the
 * Cholesky factor of ssc_levinson()'s matrix; out may be x.  O(P^2). */
void ssc_levinson_whiten(const double *phi, const double *v, size_t P,
			 const double *x, double *out);

/* strdup that accepts NULL (returns NULL) */
char *ssc_strdup(const char *s);

/*
 * Neumaier (improved Kahan-Babuska) compensated summation.  The running
 * error term keeps the sum exact to about one ulp of the result whatever
 * the order and magnitudes of the terms.
 */
struct ssc_ksum {
	double s;
	double c;
};

static inline void ssc_ksum_add(struct ssc_ksum *k, double x)
{
	double t = k->s + x;

	if ((k->s < 0 ? -k->s : k->s) >= (x < 0 ? -x : x))
		k->c += (k->s - t) + x;
	else
		k->c += (x - t) + k->s;
	k->s = t;
}

static inline double ssc_ksum_value(const struct ssc_ksum *k)
{
	return k->s + k->c;
}

/* Clip detection (analysis/clip.c) fed in pieces: the two largest
 * distinct values at each side and their counts, as sscope_clip_detect()
 * keeps them; the pieces may be cut anywhere, the result is the same. */
struct ssc_top2 {
	double v, next;
	size_t n, n_next;
};
struct ssc_clip_acc {
	struct ssc_top2 hi, lo; /* lo holds the negated samples */
};
void ssc_clip_init(struct ssc_clip_acc *a);
void ssc_clip_feed(struct ssc_clip_acc *a, const double *x, size_t stride,
		   size_t n);
/* 0, or -EDOM when no sample fed was finite (c untouched) */
int ssc_clip_finish(const struct ssc_clip_acc *a, size_t min_count,
		    double ratio, struct sscope_clip *c);
/* min_count >= 2, ratio > 1 and finite */
bool ssc_clip_args_ok(size_t min_count, double ratio);

/* Upper bound of the rows a reader will still produce (lines left in a
 * mapped text file, exact for binary files), 0 when unknown (a pipe).  A
 * mapped text file is split into up to `threads` parts, counted in
 * parallel, for ssc_reader_read_all(). */
size_t ssc_reader_max_rows(struct sscope_reader *r, unsigned threads);

/* Read every remaining row into ch (capacity >= ssc_reader_max_rows()),
 * one thread per part of a split text file; other sources sequentially. */
int ssc_reader_read_all(struct sscope_reader *r, struct sscope_reader_chunk *ch,
			struct sscope_diag *diag);

/* Open a capture held in memory (buf is read in place and must outlive
 * the reader; name is used in messages): the same formats and errors as
 * sscope_reader_open().  For the fuzz harnesses, where ASan sees a read
 * past the end of an exact-size buffer that a mapped file would hide. */
int ssc_reader_open_mem(struct sscope_reader **reader, const void *buf,
			size_t len, const char *name,
			const struct sscope_reader_opts *opts,
			struct sscope_diag *diag);

/*
 * A raw file of one float64 channel in the host's byte order, without
 * scaling or unit conversion, is used in place: on success *x points at its
 * *n samples inside a private mapping (*map, *map_len bytes) that the caller
 * now owns and must munmap(); it is read-only.  *n_nan counts NaN samples
 * (gaps, only when allow_nan).  Returns false, changing nothing, for any
 * other source or when a value is not finite and not an allowed gap (the
 * reader then reports it as usual).  With unchecked the samples are not
 * looked at (*n_nan is 0): the caller checks them.
 */
bool ssc_reader_take_inplace(struct sscope_reader *r, bool allow_nan,
			     bool unchecked, double **x, size_t *n,
			     size_t *n_nan, void **map, size_t *map_len);

/* The reader's error for a sample v (NaN or infinite) of a raw file: row
 * and column 1-based; a time column's NaN is never a gap. */
int ssc_raw_value_error(struct sscope_diag *diag, const char *disp,
			size_t row, size_t col, const char *name, double v,
			bool is_time);

/* Scale for sums of squares over samples whose largest magnitude is
 * amax: 1 when amax lies in [2^-300, 2^300] (or is 0), else the power of
 * two that brings amax into [0.5, 1) -- exact, so results scaled back are
 * those of a wider exponent range (analysis/stats.c). */
double ssc_safe_scale(double amax);

/* Analyses that square (or raise to the 4th power) sums of samples
 * without scaling them: -ERANGE, with a message naming `what`, when the
 * largest finite magnitude of x lies outside [2^-lim, 2^lim] (0 passes);
 * one pass over the samples. */
int ssc_magnitude_check(const double *x, size_t stride, size_t n, int lim,
			const char *what, struct sscope_diag *diag);

/* Case-insensitive ASCII comparison of two strings. */
int ssc_strcasecmp(const char *a, const char *b);

/* Column lists (-c, "columns =", the reader's selection), one rule for
 * all: items separated by commas, the blanks around an item not part of
 * it, empty items skipped.  The next item of *p (advanced) into buf (len
 * bytes, cut with *too_long set when longer); false at the end. */
bool ssc_list_next(const char **p, char *buf, size_t len, bool *too_long);

/* The item of a column list among n columns: a whole number is a file
 * column number (1-based), anything else a name, matched exactly first
 * and then case aside.  name(ctx, i) and number(ctx, i) describe column
 * i.  Returns i, or -1 when none matches. */
long ssc_column_find(const char *item, size_t n,
		     const char *(*name)(const void *ctx, size_t i),
		     size_t (*number)(const void *ctx, size_t i),
		     const void *ctx);

#endif /* SSCOPE_INTERNAL_H */
