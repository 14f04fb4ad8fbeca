/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Power spectral density by Welch's method (P. D. Welch, "The use of fast
 * Fourier transform for the estimation of power spectra", IEEE Trans. Audio
 * Electroacoust. 15(2), 1967) with the conventions of scipy.signal.welch /
 * periodogram (scipy 1.10: DFT-even windows, per-segment detrending,
 * one-sided doubling, "density" 1/(fs sum w^2) and "spectrum" 1/(sum w)^2
 * scaling, mean over segments), so that the numbers equal scipy's.
 *
 * Windows are scipy's cosine sums (F. J. Harris, "On the use of windows for
 * harmonic analysis with the discrete Fourier transform", Proc. IEEE 66(1),
 * 1978, for the figures: coherent gain, ENBW, scalloping loss).  Their
 * transforms are evaluated in closed form as sums of Dirichlet kernels,
 * which gives an exact sub-bin interpolation of a sine's frequency and
 * amplitude from the ratio of the two largest bins.
 *
 * Octave bands: IEC 61260-1:2014, base-10 (G = 10^(3/10)).
 *
 * Significant peaks: each bin of a Welch estimate over its expectation is
 * chi-square with the equivalent degrees of freedom of Percival & Walden
 * (1993, eq. 292b, the overlap correction); a peak is listed when its ratio
 * to the local floor (median of the neighbours) passes an F test at a
 * Bonferroni level over the bins searched (see sscope-psd.h).
 *
 * Streaming: samples are staged in a buffer that holds one batch of
 * segments (nperseg + (B - 1) step samples); a full batch is transformed on
 * OpenMP threads (FFTW r2c, plan made once, executed with the new-array
 * interface on per-thread arrays), the periodograms are added in segment
 * order with compensated sums, and the overlap is kept for the next batch.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <fftw3.h>
#if defined(__SSE2__) && defined(__x86_64__)
#include <emmintrin.h>
#endif
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "sscope-psd.h"


/* ------------------------------------------------------------ windows */

struct wdef {
	const char *name;
	size_t nterms;
	double a[5];
};

static const struct wdef wdefs[SSCOPE_PSD_WINDOW_COUNT_] = {
	[SSCOPE_PSD_WINDOW_HANN] = { "hann", 2, { 0.5, 0.5 } },
	[SSCOPE_PSD_WINDOW_HAMMING] = { "hamming", 2, { 0.54, 0.46 } },
	[SSCOPE_PSD_WINDOW_BLACKMAN] = { "blackman", 3, { 0.42, 0.50, 0.08 } },
	[SSCOPE_PSD_WINDOW_BLACKMANHARRIS] = { "blackmanharris", 4,
					   { 0.35875, 0.48829, 0.14128,
					     0.01168 } },
	[SSCOPE_PSD_WINDOW_FLATTOP] = { "flattop", 5,
				    { 0.21557895, 0.41663158, 0.277263158,
				      0.083578947, 0.006947368 } },
	[SSCOPE_PSD_WINDOW_BOXCAR] = { "boxcar", 1, { 1 } },
};

static const struct wdef boxcar1 = { "boxcar", 1, { 1 } };

/* scipy returns ones for a window of one sample */
static const struct wdef *wdef_of(enum sscope_psd_window w, size_t n)
{
	if ((unsigned)w >= SSCOPE_PSD_WINDOW_COUNT_)
		return NULL;
	return n == 1 ? &boxcar1 : &wdefs[w];
}

const char *sscope_psd_window_name(enum sscope_psd_window w)
{
	return (unsigned)w < SSCOPE_PSD_WINDOW_COUNT_ ? wdefs[w].name : NULL;
}

int sscope_psd_window_from_name(const char *name, enum sscope_psd_window *w)
{
	if (!name || !w)
		return -EINVAL;
	for (unsigned i = 0; i < SSCOPE_PSD_WINDOW_COUNT_; i++)
		if (!ssc_strcasecmp(name, wdefs[i].name)) {
			*w = (enum sscope_psd_window)i;
			return 0;
		}
	if (!ssc_strcasecmp(name, "hanning")) {
		*w = SSCOPE_PSD_WINDOW_HANN;
		return 0;
	}
	if (!ssc_strcasecmp(name, "rect") ||
	    !ssc_strcasecmp(name, "rectangular") ||
	    !ssc_strcasecmp(name, "boxcar")) {
		*w = SSCOPE_PSD_WINDOW_BOXCAR;
		return 0;
	}
	return -EINVAL;
}

int sscope_psd_window_fill(enum sscope_psd_window w, size_t n, double *out)
{
	const struct wdef *d = wdef_of(w, n);

	if (!d || n == 0 || !out)
		return -EINVAL;
	for (size_t i = 0; i < n; i++) {
		double v = 0;

		/* cos(k (2 pi i / n - pi)) = (-1)^k cos(2 pi (k i mod n) / n),
		 * the argument reduced exactly in integers */
		for (size_t k = 0; k < d->nterms; k++) {
			size_t m = (size_t)(((unsigned long long)k * i) % n);
			double c = cos(2 * PI * (double)m / (double)n);

			v += (k & 1 ? -d->a[k] : d->a[k]) * c;
		}
		out[i] = v;
	}
	return 0;
}

/* Dirichlet kernel sum_{j<m} exp(-2 pi i x j) = exp(-i pi x (m-1))
 * sin(pi x m) / sin(pi x), added times c to (re, im). */
static void dirichlet_add(double x, size_t m, double c, double *re, double *im)
{
	double s = sin(PI * x), mag, ph = -PI * x * (double)(m - 1);

	if (fabs(s) < 1e-300)
		mag = (double)m;
	else
		mag = sin(PI * x * (double)m) / s;
	*re += c * mag * cos(ph);
	*im += c * mag * sin(ph);
}

double sscope_psd_window_response(enum sscope_psd_window w, size_t n, size_t nfft,
				  double bins)
{
	const struct wdef *d = wdef_of(w, n);
	double re = 0, im = 0, nu;

	if (!d || n == 0 || nfft == 0 || !isfinite(bins))
		return (double)NAN;
	nu = bins / (double)nfft;
	/* w[j] = sum_k c_k cos(2 pi k j / n), c_k = (-1)^k a_k, and
	 * cos = (e^{+} + e^{-}) / 2 */
	for (size_t k = 0; k < d->nterms; k++) {
		double c = (k & 1 ? -d->a[k] : d->a[k]) / 2;
		double kn = (double)k / (double)n;

		dirichlet_add(nu - kn, n, c, &re, &im);
		dirichlet_add(nu + kn, n, c, &re, &im);
	}
	return hypot(re, im);
}

#if defined(__GNUC__)
#define SSC_PSD_VEC 1
typedef double ssc_pv2 __attribute__((vector_size(16)));
#endif

/* Pairwise sum (as numpy's): error O(log n) ulps, vectorisable. */
static double psum(const double *x, size_t n)
{
	if (n <= 128) {
		double s;
		size_t i = 0;
#ifdef SSC_PSD_VEC
		/* the eight lanes in registers, as four pairs (an array of
		 * eight, or 32-byte vectors without AVX, went through memory
		 * on every add) */
		ssc_pv2 a = { 0 }, b = { 0 }, c = { 0 }, d = { 0 };

		for (; i + 8 <= n; i += 8) {
			ssc_pv2 u, v, w, z;

			memcpy(&u, x + i, sizeof(u));
			memcpy(&v, x + i + 2, sizeof(v));
			memcpy(&w, x + i + 4, sizeof(w));
			memcpy(&z, x + i + 6, sizeof(z));
			a += u;
			b += v;
			c += w;
			d += z;
		}
		s = ((a[0] + a[1]) + (b[0] + b[1])) +
		    ((c[0] + c[1]) + (d[0] + d[1]));
#else
		double a[8] = { 0 };

		for (; i + 8 <= n; i += 8)
			for (size_t j = 0; j < 8; j++)
				a[j] += x[i + j];
		s = ((a[0] + a[1]) + (a[2] + a[3])) +
		    ((a[4] + a[5]) + (a[6] + a[7]));
#endif
		for (; i < n; i++)
			s += x[i];
		return s;
	} else {
		size_t h = (n / 2) & ~(size_t)7;

		return psum(x, h) + psum(x + h, n - h);
	}
}

int sscope_psd_window_figures(enum sscope_psd_window w, size_t n,
			      struct sscope_psd_window_figures *f)
{
	double *win;
	struct ssc_ksum s = { 0, 0 }, q = { 0, 0 };

	if (!wdef_of(w, n) || n == 0 || !f)
		return -EINVAL;
	win = ssc_alloc_array(n, sizeof(double));
	if (!win)
		return -ENOMEM;
	sscope_psd_window_fill(w, n, win);
	for (size_t i = 0; i < n; i++) {
		ssc_ksum_add(&s, win[i]);
		ssc_ksum_add(&q, win[i] * win[i]);
	}
	free(win);
	f->sum = ssc_ksum_value(&s);
	f->sum_sq = ssc_ksum_value(&q);
	f->coherent_gain = f->sum / (double)n;
	f->enbw_bins = (double)n * f->sum_sq / (f->sum * f->sum);
	f->scalloping_db = 20 * log10(sscope_psd_window_response(w, n, n, 0.5) /
				      sscope_psd_window_response(w, n, n, 0));
	return 0;
}

/* ------------------------------------------------------------ workspace */

struct sscope_psd {
	struct sscope_psd_opts o;
	size_t m, l, step, nfft, nbins; /* nperseg, noverlap */
	double *win;
	double sum_w, sum_w2;
	fftw_plan plan;
	int nth;
	double **tin;
	fftw_complex **tout;
	/* staging of one batch of segments */
	size_t batch;      /* segments per batch */
	double *stage;
	size_t stage_cap, have;
	uint64_t consumed; /* stream index of stage[0] */
	uint64_t n_samples;
	double *pg;        /* batch x nbins periodograms */
	unsigned char *bad;
	/* extreme magnitudes: a segment beyond 2^+-300 is transformed scaled
	 * by 2^-e (seg_exp, 0 otherwise); acc, comp and sg hold sums scaled
	 * by 2^(-2 acc_exp) */
	int *seg_exp;
	int acc_exp;
	/* accumulation */
	double *acc, *comp;
	size_t nseg, nskip;
	/* spectrogram: columns of summed periodograms */
	size_t sg_max, sg_n, sg_per;
	double *sg;
	size_t *sg_used, *sg_slots;
	double *sg_start; /* sum of segment starts of all slots */
};

void sscope_psd_opts_init(struct sscope_psd_opts *o)
{
	memset(o, 0, sizeof(*o));
}

size_t sscope_psd_noverlap(double fraction, size_t nperseg)
{
	size_t l = fraction > 0 ? (size_t)floor(fraction * (double)nperseg) : 0;

	if (nperseg && l >= nperseg)
		l = nperseg - 1;
	return l ? l : SSCOPE_PSD_NO_OVERLAP;
}

/* nperseg of options whose zero asks for the default */
static size_t opts_nperseg(const struct sscope_psd_opts *o)
{
	return o->nperseg ? o->nperseg : 256;
}

void sscope_psd_free(struct sscope_psd *p)
{
	if (!p)
		return;
	if (p->plan)
		fftw_destroy_plan(p->plan);
	for (int t = 0; p->tin && t < p->nth; t++)
		fftw_free(p->tin[t]);
	for (int t = 0; p->tout && t < p->nth; t++)
		fftw_free(p->tout[t]);
	free(p->tin);
	free(p->tout);
	free(p->win);
	free(p->stage);
	free(p->pg);
	free(p->bad);
	free(p->seg_exp);
	free(p->acc);
	free(p->comp);
	free(p->sg);
	free(p->sg_used);
	free(p->sg_slots);
	free(p->sg_start);
	free(p);
}

void sscope_psd_reset(struct sscope_psd *p)
{
	if (!p)
		return;
	p->have = 0;
	p->consumed = 0;
	p->n_samples = 0;
	p->nseg = 0;
	p->nskip = 0;
	memset(p->acc, 0, p->nbins * sizeof(double));
	memset(p->comp, 0, p->nbins * sizeof(double));
	p->acc_exp = 0;
	p->sg_n = 0;
	p->sg_per = 1;
}

/* Periodogram batch size: about 2^20 doubles of FFT input per batch, so
 * that a parallel region (and its barrier, costly on a loaded machine)
 * holds enough work; memory is about 12 MB per workspace then. */
static size_t batch_size(size_t nfft, int nth)
{
	size_t b = ((size_t)1 << 20) / nfft;

	if (b > 4096)
		b = 4096;
	if (b < (size_t)nth)
		b = (size_t)nth;
	return b ? b : 1;
}

int sscope_psd_new(struct sscope_psd **out, const struct sscope_psd_opts *opts)
{
	struct sscope_psd_opts def = { 0 };
	struct sscope_psd *p;
	size_t sz;

	if (!out)
		return -EINVAL;
	*out = NULL;
	if (!opts)
		opts = &def;
	if ((unsigned)opts->window >= SSCOPE_PSD_WINDOW_COUNT_ ||
	    (unsigned)opts->detrend > SSCOPE_PSD_DETREND_NONE ||
	    (unsigned)opts->scaling > SSCOPE_PSD_SCALING_SPECTRUM ||
	    opts_nperseg(opts) > INT32_MAX)
		return -EINVAL;
	p = calloc(1, sizeof(*p));
	if (!p)
		return -ENOMEM;
	p->o = *opts;
	p->o.nperseg = p->m = opts_nperseg(opts);
	p->l = opts->noverlap == SSCOPE_PSD_HALF_OVERLAP ? p->m / 2 :
	       opts->noverlap == SSCOPE_PSD_NO_OVERLAP	 ? 0 :
							   opts->noverlap;
	p->nfft = opts->nfft ? opts->nfft : p->m;
	/* more than 64 times zero padding only interpolates, at the cost of
	 * memory and time without bound */
	if (p->l >= p->m || p->nfft < p->m || p->nfft > INT32_MAX ||
	    p->nfft > (size_t)SSCOPE_PSD_MAX_PAD * p->m) {
		free(p);
		return -EINVAL;
	}
	p->step = p->m - p->l;
	p->nbins = p->nfft / 2 + 1;
#ifdef _OPENMP
	p->nth = opts->threads ? (int)opts->threads : omp_get_max_threads();
	if (p->nth < 1)
		p->nth = 1;
#else
	p->nth = 1;
#endif
	p->batch = batch_size(p->nfft, p->nth);
	if (!ssc_mul(p->batch - 1, p->step, &sz) ||
	    !ssc_add(sz, p->m, &p->stage_cap))
		goto nomem;
	p->win = ssc_alloc_array(p->m, sizeof(double));
	p->tin = calloc((size_t)p->nth, sizeof(*p->tin));
	p->tout = calloc((size_t)p->nth, sizeof(*p->tout));
	p->stage = ssc_alloc_huge(p->stage_cap, sizeof(double));
	p->bad = calloc(p->batch, 1);
	p->seg_exp = calloc(p->batch, sizeof(int));
	p->acc = calloc(p->nbins, sizeof(double));
	p->comp = calloc(p->nbins, sizeof(double));
	if (!ssc_mul(p->batch, p->nbins, &sz))
		goto nomem;
	p->pg = ssc_alloc_huge(sz, sizeof(double));
	if (!p->win || !p->tin || !p->tout || !p->stage || !p->bad ||
	    !p->seg_exp ||
	    !p->acc || !p->comp || !p->pg)
		goto nomem;
	for (int t = 0; t < p->nth; t++) {
		p->tin[t] = fftw_alloc_real(p->nfft);
		p->tout[t] = fftw_alloc_complex(p->nbins);
		if (!p->tin[t] || !p->tout[t])
			goto nomem;
	}
	sscope_psd_window_fill(opts->window, p->m, p->win);
	p->sum_w = psum(p->win, p->m);
	{
		struct ssc_ksum q = { 0, 0 };

		for (size_t i = 0; i < p->m; i++)
			ssc_ksum_add(&q, p->win[i] * p->win[i]);
		p->sum_w2 = ssc_ksum_value(&q);
	}
	p->plan = fftw_plan_dft_r2c_1d((int)p->nfft, p->tin[0], p->tout[0],
				       opts->measure ? FFTW_MEASURE :
						       FFTW_ESTIMATE);
	if (!p->plan)
		goto nomem;
	for (int t = 0; t < p->nth; t++)
		memset(p->tin[t], 0, p->nfft * sizeof(double));
	if (opts->spectrogram_cols) {
		p->sg_max = opts->spectrogram_cols < 2 ? 2 :
							 opts->spectrogram_cols;
		if (!ssc_mul(p->sg_max, p->nbins, &sz))
			goto nomem;
		p->sg = ssc_alloc_array(sz, sizeof(double));
		p->sg_used = calloc(p->sg_max, sizeof(size_t));
		p->sg_slots = calloc(p->sg_max, sizeof(size_t));
		p->sg_start = calloc(p->sg_max, sizeof(double));
		if (!p->sg || !p->sg_used || !p->sg_slots || !p->sg_start)
			goto nomem;
	}
	sscope_psd_reset(p);
	*out = p;
	return 0;
nomem:
	sscope_psd_free(p);
	return -ENOMEM;
}

/* Detrend and window one segment into in[0..m); returns false when it
 * holds a non-finite sample (the sum of a segment holding a NaN or an
 * infinity is not finite).  Every loop here vectorises. */
static bool prepare(const struct sscope_psd *p, const double *seg, double *in)
{
	size_t m = p->m;
	double sum = psum(seg, m), mean = 0, slope = 0;
	double c = (double)(m - 1) / 2;

	if (!isfinite(sum))
		return false;
	if (m <= (p->o.detrend == SSCOPE_PSD_DETREND_LINEAR ? 2u :
		  p->o.detrend == SSCOPE_PSD_DETREND_CONSTANT ? 1u : 0u)) {
		/* the fit passes through every sample: exact zeros, not the
		 * rounding of a fit (scipy: 1e-35 for a line through two) */
		memset(in, 0, m * sizeof(double));
		return true;
	}
	if (p->o.detrend != SSCOPE_PSD_DETREND_NONE) {
		size_t k = 1;
		bool same;

		/* stops at the first sample that differs: almost always the
		 * second, so no extra pass over the segment */
		while (k < m && seg[k] == seg[0])
			k++;
		same = k >= m;
		/* a constant segment detrends to exact zeros */
		mean = same ? seg[0] : sum / (double)m;
		if (p->o.detrend == SSCOPE_PSD_DETREND_LINEAR && !same) {
			double s = 0, d = (double)m;

			for (size_t i = 0; i < m; i++)
				s += ((double)i - c) * (seg[i] - mean);
			slope = s / (d * (d * d - 1) / 12);
		}
	}
	if (slope != 0)
		for (size_t i = 0; i < m; i++)
			in[i] = (seg[i] - mean - slope * ((double)i - c)) *
				p->win[i];
	else
		for (size_t i = 0; i < m; i++)
			in[i] = (seg[i] - mean) * p->win[i];
	return true;
}

static void sg_add(struct sscope_psd *p, const double *pg, bool used,
		   uint64_t start)
{
	double *col;
	size_t c;

	if (!p->sg_max)
		return;
	if (p->sg_n == 0 || p->sg_slots[p->sg_n - 1] >= p->sg_per) {
		if (p->sg_n == p->sg_max) {
			/* merge neighbouring columns in pairs */
			size_t nn = 0;

			for (size_t i = 0; i < p->sg_n; i += 2, nn++) {
				double *dst = p->sg + nn * p->nbins;
				const double *a = p->sg + i * p->nbins;

				if (dst != a)
					memcpy(dst, a, p->nbins * sizeof(double));
				p->sg_used[nn] = p->sg_used[i];
				p->sg_slots[nn] = p->sg_slots[i];
				p->sg_start[nn] = p->sg_start[i];
				if (i + 1 < p->sg_n) {
					const double *b = a + p->nbins;

					for (size_t k = 0; k < p->nbins; k++)
						dst[k] += b[k];
					p->sg_used[nn] += p->sg_used[i + 1];
					p->sg_slots[nn] += p->sg_slots[i + 1];
					p->sg_start[nn] += p->sg_start[i + 1];
				}
			}
			p->sg_n = nn;
			p->sg_per *= 2;
		}
		if (p->sg_n == 0 || p->sg_slots[p->sg_n - 1] >= p->sg_per) {
			c = p->sg_n++;
			memset(p->sg + c * p->nbins, 0,
			       p->nbins * sizeof(double));
			p->sg_used[c] = 0;
			p->sg_slots[c] = 0;
			p->sg_start[c] = 0;
		}
	}
	c = p->sg_n - 1;
	col = p->sg + c * p->nbins;
	p->sg_slots[c]++;
	p->sg_start[c] += (double)start;
	if (used) {
		p->sg_used[c]++;
		for (size_t k = 0; k < p->nbins; k++)
			col[k] += pg[k];
	}
}

/* A segment of finite samples whose largest magnitude lies outside
 * 2^+-300: copied into in[] scaled by 2^-e (exact), *e set; false for
 * ordinary (or non-finite) segments. */
static bool rescaled(const struct sscope_psd *p, const double *seg,
		     double *in, int *e)
{
	double amax = 0, sc;

	for (size_t i = 0; i < p->m; i++) {
		double a = fabs(seg[i]);

		if (!isfinite(a))
			return false;
		amax = amax > a ? amax : a;
	}
	sc = ssc_safe_scale(amax);
	if (sc == 1)
		return false;
	frexp(amax, e);
	for (size_t i = 0; i < p->m; i++)
		in[i] = seg[i] * sc;
	return true;
}

/* Bring the batch's periodograms and the sums to one exponent, the
 * largest: smaller ones are negligible beside it.  Nothing to do for
 * ordinary data. */
static void common_exponent(struct sscope_psd *p, size_t count)
{
	bool any = p->acc_exp != 0, first = true;
	int emax = p->acc_exp;

	for (size_t j = 0; j < count; j++) {
		if (p->bad[j])
			continue;
		any |= p->seg_exp[j] != 0;
		/* before the first sums the exponent is free (tiny data) */
		if ((first && p->nseg == 0) || p->seg_exp[j] > emax)
			emax = p->seg_exp[j];
		first = false;
	}
	if (!any)
		return;
	if (emax > p->acc_exp || (p->nseg == 0 && emax != p->acc_exp)) {
		int d = 2 * (p->acc_exp - emax);

		for (size_t k = 0; k < p->nbins; k++) {
			p->acc[k] = ldexp(p->acc[k], d);
			p->comp[k] = ldexp(p->comp[k], d);
		}
		for (size_t k = 0; p->sg && k < p->sg_n * p->nbins; k++)
			p->sg[k] = ldexp(p->sg[k], d);
		p->acc_exp = emax;
	}
	for (size_t j = 0; j < count; j++) {
		double *pg = p->pg + j * p->nbins;
		int d = 2 * (p->seg_exp[j] - p->acc_exp);

		if (p->bad[j] || d == 0)
			continue;
		for (size_t k = 0; k < p->nbins; k++)
			pg[k] = ldexp(pg[k], d);
	}
}

/*
 * pg[k] = |out[k]|^2 for k < n; returns what the running maximum
 * pmax = pmax > pg[k] ? pmax : pg[k] from pmax = 0 gives.  Four lanes of
 * maxima instead of one chain of them (the chain was the loop's cost);
 * without NaN the maximum does not depend on the order, with one (an
 * overflowed transform) the chain is run as written.
 */
static double power(const fftw_complex *out, double *pg, size_t n)
{
	double pmax = 0;
	size_t k = 0;

#if defined(__SSE2__) && defined(__x86_64__)
	__m128d m0 = _mm_setzero_pd(), m1 = m0, un = m0;

	for (; k + 4 <= n; k += 4) {
		__m128d a = _mm_loadu_pd(out[k]), b = _mm_loadu_pd(out[k + 1]);
		__m128d c = _mm_loadu_pd(out[k + 2]), d = _mm_loadu_pd(out[k + 3]);
		__m128d p01, p23;

		a = _mm_mul_pd(a, a);
		b = _mm_mul_pd(b, b);
		c = _mm_mul_pd(c, c);
		d = _mm_mul_pd(d, d);
		/* re^2 + im^2 of each bin */
		p01 = _mm_add_pd(_mm_unpacklo_pd(a, b), _mm_unpackhi_pd(a, b));
		p23 = _mm_add_pd(_mm_unpacklo_pd(c, d), _mm_unpackhi_pd(c, d));
		_mm_storeu_pd(pg + k, p01);
		_mm_storeu_pd(pg + k + 2, p23);
		m0 = _mm_max_pd(m0, p01);
		m1 = _mm_max_pd(m1, p23);
		un = _mm_or_pd(un, _mm_cmpunord_pd(p01, p23));
	}
	if (_mm_movemask_pd(un)) {
		for (size_t i = 0; i < k; i++)
			pmax = pmax > pg[i] ? pmax : pg[i];
	} else {
		double l[4];

		_mm_storeu_pd(l, m0);
		_mm_storeu_pd(l + 2, m1);
		for (int i = 0; i < 4; i++)
			pmax = pmax > l[i] ? pmax : l[i];
	}
#endif
	for (; k < n; k++) {
		pg[k] = out[k][0] * out[k][0] + out[k][1] * out[k][1];
		pmax = pmax > pg[k] ? pmax : pg[k];
	}
	return pmax;
}

/* acc[k] + comp[k] += x[k], k < n, Neumaier's step; two bins at a time
 * where SSE2 is (the same operations on each bin) */
static void neumaier_add(double *acc, double *comp, const double *x, size_t n)
{
	size_t k = 0;

#if defined(__SSE2__) && defined(__x86_64__)
	const __m128d sign = _mm_set1_pd(-0.0);

	for (; k + 2 <= n; k += 2) {
		__m128d s = _mm_loadu_pd(acc + k), v = _mm_loadu_pd(x + k);
		__m128d t = _mm_add_pd(s, v);
		__m128d big = _mm_cmpge_pd(_mm_andnot_pd(sign, s),
					   _mm_andnot_pd(sign, v));
		__m128d e1 = _mm_add_pd(_mm_sub_pd(s, t), v);
		__m128d e2 = _mm_add_pd(_mm_sub_pd(v, t), s);
		__m128d e = _mm_or_pd(_mm_and_pd(big, e1), _mm_andnot_pd(big, e2));

		_mm_storeu_pd(comp + k, _mm_add_pd(_mm_loadu_pd(comp + k), e));
		_mm_storeu_pd(acc + k, t);
	}
#endif
	for (; k < n; k++) {
		double s = acc[k], v = x[k], t = s + v;

		comp[k] += fabs(s) >= fabs(v) ? (s - t) + v : (v - t) + s;
		acc[k] = t;
	}
}

/* Transform `count` segments starting at base[0], base[step], ...: the
 * stage, or the caller's buffer itself when it holds whole batches.
 * Dynamic scheduling: on a loaded machine a thread that loses its core
 * takes fewer segments instead of holding the others at the barrier. */
static int process(struct sscope_psd *p, const double *base, size_t count)
{
	long cnt = (long)count;

#ifdef _OPENMP
#pragma omp parallel for num_threads(p->nth) schedule(dynamic, 4) \
	if (cnt > 1 && (size_t)cnt * p->nfft >= ((size_t)1 << 16))
#endif
	for (long j = 0; j < cnt; j++) {
#ifdef _OPENMP
		int t = omp_get_thread_num();
#else
		int t = 0;
#endif
		double *in = p->tin[t], *pg = p->pg + (size_t)j * p->nbins;
		fftw_complex *out = p->tout[t];

		const double *seg = base + (size_t)j * p->step;
		double pmax = 0;

		p->seg_exp[j] = 0;
		p->bad[j] = !prepare(p, seg, in);
		if (!p->bad[j]) {
			fftw_execute_dft_r2c(p->plan, in, out);
			pmax = power(out, pg, p->nbins);
		}
		/* squares beyond the double range (or a sum of samples that
		 * overflowed): the segment again, scaled */
		if ((p->bad[j] || !(pmax >= 0x1p-800 && pmax <= 0x1p800)) &&
		    rescaled(p, seg, in, &p->seg_exp[j])) {
			p->bad[j] = !prepare(p, in, in);
			if (p->bad[j])
				continue;
			fftw_execute_dft_r2c(p->plan, in, out);
			for (size_t k = 0; k < p->nbins; k++)
				pg[k] = out[k][0] * out[k][0] + out[k][1] * out[k][1];
		}
	}
	for (size_t j = 0; j < count; j++) {
		if (p->bad[j] && !p->o.skip_nonfinite)
			return -EDOM;
	}
	common_exponent(p, count);
	/* Neumaier sums of the bins, segments in order within each bin (the
	 * same result on any number of threads); each thread takes a block
	 * of bins and walks the segments row by row through it.  Blocks of
	 * at most 1024 bins, as many per thread: 2049 bins in blocks of 1024
	 * left one of two threads a single bin. */
	{
		size_t nth = p->nth > 0 ? (size_t)p->nth : 1;
		size_t want = (p->nbins + 1023) / 1024, bs;
		long nblk;

		want = (want + nth - 1) / nth * nth;
		bs = ((p->nbins + want - 1) / want + 7) & ~(size_t)7;
		nblk = (long)((p->nbins + bs - 1) / bs);

#ifdef _OPENMP
#pragma omp parallel for num_threads(p->nth) schedule(dynamic, 1) \
	if (cnt > 1 && (size_t)cnt * p->nbins >= ((size_t)1 << 18))
#endif
		for (long b = 0; b < nblk; b++) {
			size_t k0 = (size_t)b * bs;
			size_t k1 = k0 + bs < p->nbins ? k0 + bs : p->nbins;

			for (size_t j = 0; j < count; j++) {
				const double *pg = p->pg + j * p->nbins;

				if (p->bad[j])
					continue;
				neumaier_add(p->acc + k0, p->comp + k0, pg + k0,
					     k1 - k0);
			}
		}
	}
	for (size_t j = 0; j < count; j++) {
		const double *pg = p->pg + j * p->nbins;
		uint64_t start = p->consumed + j * p->step;

		if (p->bad[j])
			p->nskip++;
		else
			p->nseg++;
		sg_add(p, pg, !p->bad[j], start);
	}
	if (base != p->stage) {
		p->consumed += count * p->step;
	} else if (count) {
		/* keep the samples from the next segment's start on */
		size_t adv = count * p->step;

		memmove(p->stage, p->stage + adv,
			(p->have - adv) * sizeof(double));
		p->have -= adv;
		p->consumed += adv;
	}
	return 0;
}

size_t sscope_psd_segments_end(const struct sscope_psd *p, size_t n)
{
	if (!p || n < p->m)
		return 0;
	return (n - p->m) / p->step * p->step + p->m;
}

int sscope_psd_feed(struct sscope_psd *p, const double *x, size_t stride,
		    size_t n)
{
	const double *x0 = x;

	if (!p || (!x && n) || stride == 0)
		return -EINVAL;
	for (;;) {
		size_t take;
		double *d;

		/* whole batches straight from a contiguous buffer, without
		 * a copy */
		while (p->have == 0 && stride == 1 && n >= p->stage_cap) {
			size_t adv = p->batch * p->step;
			int rc = process(p, x, p->batch);

			if (rc)
				return rc;
			x += adv;
			n -= adv;
			p->n_samples += adv;
		}
		if (!n)
			break;
		take = p->stage_cap - p->have;
		d = p->stage + p->have;
		if (take > n)
			take = n;
		if (stride == 1) {
			memcpy(d, x, take * sizeof(double));
		} else {
			for (size_t i = 0; i < take; i++)
				d[i] = x[i * stride];
		}
		p->have += take;
		p->n_samples += take;
		x += take * stride;
		n -= take;
		if (p->have == p->stage_cap) {
			int rc = process(p, p->stage, p->batch);

			if (rc)
				return rc;
			/* the samples kept for the next segments came from
			 * this buffer: read them there, so that a record fed
			 * in large pieces is staged only across each piece's
			 * end, not copied whole */
			if (stride == 1 && p->have <= (size_t)(x - x0) &&
			    n + p->have >= p->stage_cap) {
				x -= p->have;
				n += p->have;
				p->n_samples -= p->have;
				p->have = 0;
			}
		}
	}
	return 0;
}

/* Process the whole segments waiting in the stage. */
static int flush(struct sscope_psd *p)
{
	if (p->have < p->m)
		return 0;
	return process(p, p->stage, (p->have - p->m) / p->step + 1);
}

static double one_sided(const struct sscope_psd *p, size_t k)
{
	if (k == 0)
		return 1;
	if (p->nfft % 2 == 0 && k == p->nbins - 1)
		return 1;
	return 2;
}

void sscope_psd_spectrum_clear(struct sscope_psd_spectrum *s)
{
	if (!s)
		return;
	free(s->freq_hz);
	free(s->value);
	s->freq_hz = NULL;
	s->value = NULL;
	s->n_bins = 0;
}

void sscope_psd_spectrogram_clear(struct sscope_psd_spectrogram *s)
{
	if (!s)
		return;
	free(s->time_s);
	free(s->freq_hz);
	free(s->value);
	s->time_s = NULL;
	s->freq_hz = NULL;
	s->value = NULL;
	s->n_times = 0;
	s->n_bins = 0;
}

static double psd_scale(const struct sscope_psd *p, double fs)
{
	return p->o.scaling == SSCOPE_PSD_SCALING_DENSITY ?
		       1.0 / (fs * p->sum_w2) :
		       1.0 / (p->sum_w * p->sum_w);
}

static int fill_freq(double *f, size_t nbins, size_t nfft, double fs)
{
	/* numpy.fft.rfftfreq: k * (1 / (n * d)) with d = 1 / fs; at rates
	 * whose reciprocal leaves the normal range, fs / n directly */
	double val = 1.0 / ((double)nfft * (1.0 / fs));

	if (!isnormal(1.0 / fs))
		val = fs / (double)nfft;
	if (!isnormal(val))
		return -ERANGE;
	for (size_t k = 0; k < nbins; k++)
		f[k] = (double)k * val;
	return 0;
}

/*
 * The spectrum's values from the sums: sum * one-sided factor / segments
 * (in the sums' scale 2^(-2 acc_exp)) over fs sum w^2 or (sum w)^2.  For
 * ordinary data and rates, scipy's order of operations; otherwise
 * exponents kept apart (fs as mantissa and exponent) and put together
 * once, so that only a result outside the double range fails: -ERANGE
 * when a value overflows or the largest underflows (closer than 2^52 to
 * the smallest normal double).
 */
static int values(const struct sscope_psd *p, double fs, const double *sum,
		  double n_avg, double *out)
{
	double scale = psd_scale(p, fs), vmax = 0, smax = 0, fm;
	int fe;

	bool plain = p->acc_exp == 0 && isnormal(scale) &&
		     isnormal(fs * p->sum_w2) && isnormal(1.0 / fs);

	fm = frexp(fs, &fe);
	for (size_t k = 0; k < p->nbins; k++) {
		double a = sum[k];

		if (plain)
			out[k] = a * scale * one_sided(p, k) / n_avg;
		else if (p->o.scaling == SSCOPE_PSD_SCALING_DENSITY)
			out[k] = ldexp(a * one_sided(p, k) / n_avg / p->sum_w2 / fm,
				       2 * p->acc_exp - fe);
		else
			out[k] = ldexp(a * one_sided(p, k) / n_avg /
					       (p->sum_w * p->sum_w),
				       2 * p->acc_exp);
		if (!isfinite(out[k]))
			return -ERANGE;
		vmax = out[k] > vmax ? out[k] : vmax;
		smax = a > smax ? a : smax;
	}
	if (smax > 0 && vmax < 0x1p-970)
		return -ERANGE;
	return 0;
}

/* A record shorter than one segment: the record is the segment. */
static int short_result(struct sscope_psd *p, double fs,
			struct sscope_psd_spectrum *s)
{
	struct sscope_psd_opts o = p->o;
	struct sscope_psd *q;
	int rc;

	o.nperseg = p->have;
	o.noverlap = SSCOPE_PSD_HALF_OVERLAP;
	/* the zero padding asked for, within its bound for this length */
	o.nfft = p->o.nfft < p->have ? 0 :
		 p->o.nfft / SSCOPE_PSD_MAX_PAD >= p->have ?
		 (size_t)SSCOPE_PSD_MAX_PAD * p->have : p->o.nfft;
	o.shorten = false;
	o.spectrogram_cols = p->sg_max ? 2 : 0;
	o.threads = 1;
	rc = sscope_psd_new(&q, &o);
	if (rc)
		return rc;
	rc = sscope_psd_feed(q, p->stage, 1, p->have);
	if (!rc)
		rc = sscope_psd_result(q, fs, s);
	sscope_psd_free(q);
	return rc;
}

int sscope_psd_result(struct sscope_psd *p, double fs,
		      struct sscope_psd_spectrum *s)
{
	struct ssc_ksum tot = { 0, 0 };
	int rc;

	if (!p || !s || !(fs > 0) || !isfinite(fs))
		return -EINVAL;
	memset(s, 0, sizeof(*s));
	rc = flush(p);
	if (rc)
		return rc;
	if (p->nseg == 0) {
		if (p->nskip == 0 && p->have > 0 && p->o.shorten)
			return short_result(p, fs, s);
		return -EDOM;
	}
	s->freq_hz = ssc_alloc_array(p->nbins, sizeof(double));
	s->value = ssc_alloc_array(p->nbins, sizeof(double));
	if (!s->freq_hz || !s->value) {
		sscope_psd_spectrum_clear(s);
		return -ENOMEM;
	}
	s->n_bins = p->nbins;
	for (size_t k = 0; k < p->nbins; k++)
		s->value[k] = p->acc[k] + p->comp[k];
	rc = fill_freq(s->freq_hz, p->nbins, p->nfft, fs);
	if (!rc)
		rc = values(p, fs, s->value, (double)p->nseg, s->value);
	if (rc) {
		sscope_psd_spectrum_clear(s);
		return rc;
	}
	s->fs_hz = fs;
	s->scaling = p->o.scaling;
	s->window = p->o.window;
	s->detrend = p->o.detrend;
	s->nperseg = p->m;
	s->noverlap = p->l;
	s->nfft = p->nfft;
	s->n_segments = p->nseg;
	s->n_skipped = p->nskip;
	s->n_samples = p->n_samples;
	s->enbw_hz = fs * p->sum_w2 / (p->sum_w * p->sum_w);
	if (!isfinite(s->enbw_hz))
		s->enbw_hz = fs * (p->sum_w2 / (p->sum_w * p->sum_w));
	s->bin_hz = fs / (double)p->nfft;
	if (p->acc_exp == 0 && isnormal(psd_scale(p, fs)) &&
	    isnormal(fs * p->sum_w2)) {
		for (size_t k = 0; k < p->nbins; k++)
			ssc_ksum_add(&tot, s->value[k]);
		s->rms = sqrt(ssc_ksum_value(&tot) * s->bin_hz *
			      (s->scaling == SSCOPE_PSD_SCALING_SPECTRUM ?
				       1 / s->enbw_hz : 1));
	} else {
		/* sum of value * bin width (/ ENBW for "spectrum") is the
		 * same for both scalings and free of fs: from the sums */
		for (size_t k = 0; k < p->nbins; k++)
			ssc_ksum_add(&tot, (p->acc[k] + p->comp[k]) *
						   one_sided(p, k));
		s->rms = ldexp(sqrt(ssc_ksum_value(&tot) / (double)p->nseg /
				    (p->sum_w2 * (double)p->nfft)),
			       p->acc_exp);
	}
	return 0;
}

int sscope_psd_spectrogram(struct sscope_psd *p, double fs,
			   struct sscope_psd_spectrogram *s)
{
	size_t sz;
	int rc;

	if (!p || !s || !(fs > 0) || !isfinite(fs) || !p->sg_max)
		return -EINVAL;
	memset(s, 0, sizeof(*s));
	rc = flush(p);
	if (rc)
		return rc;
	if (p->sg_n == 0)
		return -EDOM;
	if (!ssc_mul(p->sg_n, p->nbins, &sz))
		return -ENOMEM;
	s->time_s = ssc_alloc_array(p->sg_n, sizeof(double));
	s->freq_hz = ssc_alloc_array(p->nbins, sizeof(double));
	s->value = ssc_alloc_array(sz, sizeof(double));
	if (!s->time_s || !s->freq_hz || !s->value) {
		sscope_psd_spectrogram_clear(s);
		return -ENOMEM;
	}
	s->n_times = p->sg_n;
	s->n_bins = p->nbins;
	s->segments_per_column = p->sg_per;
	rc = fill_freq(s->freq_hz, p->nbins, p->nfft, fs);
	for (size_t c = 0; !rc && c < p->sg_n; c++) {
		const double *col = p->sg + c * p->nbins;
		double *v = s->value + c * p->nbins;

		s->time_s[c] = (p->sg_start[c] / (double)p->sg_slots[c] +
				(double)p->m / 2) / fs;
		if (p->sg_used[c])
			rc = values(p, fs, col, (double)p->sg_used[c], v);
		else
			for (size_t k = 0; k < p->nbins; k++)
				v[k] = (double)NAN;
	}
	if (rc)
		sscope_psd_spectrogram_clear(s);
	return rc;
}

int sscope_psd_welch(const double *x, size_t stride, size_t n, double fs,
		     const struct sscope_psd_opts *opts,
		     struct sscope_psd_spectrum *out)
{
	struct sscope_psd_opts o;
	struct sscope_psd *p;
	int rc;

	if (!out || (!x && n) || stride == 0 || !(fs > 0))
		return -EINVAL;
	memset(out, 0, sizeof(*out));
	if (opts)
		o = *opts;
	else
		sscope_psd_opts_init(&o);
	if (n == 0)
		return -EDOM;
	o.nperseg = opts_nperseg(&o);
	if (o.nperseg > n) {
		o.nperseg = n;
		if (o.noverlap != SSCOPE_PSD_HALF_OVERLAP &&
		    o.noverlap != SSCOPE_PSD_NO_OVERLAP && o.noverlap >= n)
			return -EINVAL;
	}
	rc = sscope_psd_new(&p, &o);
	if (rc)
		return rc;
	rc = sscope_psd_feed(p, x, stride, n);
	if (!rc)
		rc = sscope_psd_result(p, fs, out);
	sscope_psd_free(p);
	return rc;
}

int sscope_psd_periodogram(const double *x, size_t stride, size_t n,
			   double fs, enum sscope_psd_window window, size_t nfft,
			   enum sscope_psd_detrend detrend,
			   enum sscope_psd_scaling scaling,
			   struct sscope_psd_spectrum *out)
{
	struct sscope_psd_opts o;

	sscope_psd_opts_init(&o);
	o.window = window;
	o.nperseg = n;
	o.noverlap = SSCOPE_PSD_NO_OVERLAP;
	o.nfft = nfft;
	o.detrend = detrend;
	o.scaling = scaling;
	o.threads = 1;
	if (n == 0) {
		if (out)
			memset(out, 0, sizeof(*out));
		return out ? -EDOM : -EINVAL;
	}
	return sscope_psd_welch(x, stride, n, fs, &o, out);
}

/* ------------------------------------------------------------ peaks */

/* Least-squares fit of the window's power response, centred at
 * k + delta bins, to the values of bins k-2 .. k+2 (DC excluded):
 * the scale c is linear (solved in closed form), the residual returned. */
static double fit_resid(const struct sscope_psd_spectrum *s, size_t k,
			double delta, double w0, double *c)
{
	size_t j0 = k >= 3 ? k - 2 : 1, j1 = k + 2 < s->n_bins ? k + 2 :
							      s->n_bins - 1;
	double m[5], svm = 0, smm = 0, r = 0, cc;

	for (size_t j = j0; j <= j1; j++) {
		double a = sscope_psd_window_response(s->window, s->nperseg,
						      s->nfft,
						      (double)j - (double)k - delta) /
			   w0;

		m[j - j0] = a * a;
		svm += s->value[j] * m[j - j0];
		smm += m[j - j0] * m[j - j0];
	}
	cc = smm > 0 ? svm / smm : 0;
	for (size_t j = j0; j <= j1; j++) {
		double e = s->value[j] - cc * m[j - j0];

		r += e * e;
	}
	*c = cc;
	return r;
}

/* fit_resid() at offset d, for the golden-section search */
struct resid_ctx {
	const struct sscope_psd_spectrum *s;
	size_t k;
	double w0;
};

static double resid_at(double d, void *ctx)
{
	const struct resid_ctx *r = ctx;
	double c;

	return fit_resid(r->s, r->k, d, r->w0, &c);
}

int sscope_psd_spectrum_peak_at(const struct sscope_psd_spectrum *s, size_t k,
				struct sscope_psd_peak *pk)
{
	const double span = 1.5;
	double w0, best = 0, rbest = (double)INFINITY, c, a, b, pspec;

	if (!s || !pk || !s->value || k == 0 || k + 1 >= s->n_bins)
		return -EINVAL;
	w0 = sscope_psd_window_response(s->window, s->nperseg, s->nfft, 0);
	/* a coarse scan (the flat-top window's response is not monotonic
	 * near its centre), then golden-section refinement */
	for (int i = 0; i <= 120; i++) {
		double d = -span + 2 * span * i / 120.0;
		double r = fit_resid(s, k, d, w0, &c);

		if (r < rbest) {
			rbest = r;
			best = d;
		}
	}
	a = best - 2 * span / 120.0;
	b = best + 2 * span / 120.0;
	{
		struct resid_ctx rc = { s, k, w0 };
		struct ssc_golden gs;

		ssc_golden_min(resid_at, &rc, a, b, 80, 1e-13, false, &gs);
		best = (gs.a + gs.b) / 2;
	}
	fit_resid(s, k, best, w0, &c);
	/* c is the value the spectrum would show with the tone centred on a
	 * bin: A^2 / 2 in "spectrum" scaling */
	pspec = s->scaling == SSCOPE_PSD_SCALING_DENSITY ? c * s->enbw_hz : c;
	pk->bin = k;
	pk->offset_bins = best;
	pk->frequency_hz = ((double)k + best) * s->bin_hz;
	pk->value = s->value[k];
	pk->amplitude = sqrt(2 * (pspec > 0 ? pspec : 0));
	pk->rms = pk->amplitude / sqrt(2.0);
	return 0;
}

static bool local_max(const double *v, size_t k)
{
	return v[k] > v[k - 1] && v[k] >= v[k + 1] && v[k] > 0;
}

int sscope_psd_spectrum_peaks(const struct sscope_psd_spectrum *s, size_t max,
			      double fmin, double fmax, struct sscope_psd_peak *peaks,
			      size_t *n_found)
{
	size_t *top, nt = 0;

	if (!s || !n_found || (max && !peaks))
		return -EINVAL;
	*n_found = 0;
	if (max == 0 || s->n_bins < 3)
		return 0;
	top = ssc_alloc_array(max, sizeof(size_t));
	if (!top)
		return -ENOMEM;
	for (size_t k = 1; k + 1 < s->n_bins; k++) {
		size_t i;

		if (s->freq_hz[k] < fmin || s->freq_hz[k] > fmax ||
		    !local_max(s->value, k))
			continue;
		if (nt == max && s->value[k] <= s->value[top[nt - 1]])
			continue;
		/* insertion into the sorted list of the strongest */
		i = nt < max ? nt++ : nt - 1;
		while (i > 0 && s->value[top[i - 1]] < s->value[k]) {
			top[i] = top[i - 1];
			i--;
		}
		top[i] = k;
	}
	for (size_t i = 0; i < nt; i++)
		sscope_psd_spectrum_peak_at(s, top[i], &peaks[i]);
	*n_found = nt;
	free(top);
	return 0;
}

int sscope_psd_spectrum_peak_near(const struct sscope_psd_spectrum *s, double f,
				  double tol, struct sscope_psd_peak *pk)
{
	size_t best = 0;

	if (!s || !pk || !s->value || !(tol >= 0) || !isfinite(f))
		return -EINVAL;
	for (size_t k = 1; k + 1 < s->n_bins; k++) {
		if (fabs(s->freq_hz[k] - f) > tol || !local_max(s->value, k))
			continue;
		if (!best || s->value[k] > s->value[best])
			best = k;
	}
	if (!best)
		return -ENOENT;
	return sscope_psd_spectrum_peak_at(s, best, pk);
}

/* ------------------------------------------------------------ bands */

int sscope_psd_spectrum_band_ms(const struct sscope_psd_spectrum *s, double lo,
				double hi, double *ms)
{
	struct ssc_ksum acc = { 0, 0 };
	double nyq, df, conv;

	if (!s || !ms || !s->value || !(hi >= lo) || isnan(lo))
		return -EINVAL;
	nyq = s->fs_hz / 2;
	df = s->bin_hz;
	conv = s->scaling == SSCOPE_PSD_SCALING_SPECTRUM ? 1 / s->enbw_hz : 1;
	for (size_t k = 0; k < s->n_bins; k++) {
		double a = s->freq_hz[k] - df / 2, b = s->freq_hz[k] + df / 2;
		double oa, ob;

		a = a < 0 ? 0 : a;
		b = b > nyq ? nyq : b;
		oa = a > lo ? a : lo;
		ob = b < hi ? b : hi;
		if (!(ob > oa) || !(b > a))
			continue;
		ssc_ksum_add(&acc, s->value[k] * conv * df * (ob - oa) / (b - a));
	}
	*ms = ssc_ksum_value(&acc);
	return 0;
}

int sscope_psd_octave_bands(unsigned b, double fmin, double fmax,
			    struct sscope_psd_band *bands, size_t max, size_t *n_found)
{
	static const double r10[10] = { 1, 1.25, 1.6, 2, 2.5,
					3.15, 4, 5, 6.3, 8 };
	const double g = pow(10, 0.3), lg = 0.3 * log(10.0);
	long x0, x1;
	size_t n = 0;
	int rc = 0;

	if (!n_found || b < 1 || b > 24 || !(fmin > 0) || !(fmax >= fmin) ||
	    !isfinite(fmax))
		return -EINVAL;
	*n_found = 0;
	x0 = (long)floor((double)b * log(fmin / 1000) / lg) - 2;
	x1 = (long)ceil((double)b * log(fmax / 1000) / lg) + 2;
	for (long x = x0; x <= x1; x++) {
		double e = b % 2 ? (double)x / b : (2.0 * (double)x + 1) / (2.0 * b);
		double fm = 1000 * pow(g, e), h = pow(g, 1.0 / (2.0 * b));
		struct sscope_psd_band bd;

		bd.center_hz = fm;
		bd.lo_hz = fm / h;
		bd.hi_hz = fm * h;
		bd.rms = (double)NAN;
		if (bd.lo_hz < fmin * (1 - 1e-12) || bd.hi_hz > fmax * (1 + 1e-12))
			continue;
		if (b == 1 || b == 3) {
			long xt = b == 1 ? 3 * x : x;
			long q = xt >= 0 ? xt / 10 : -((-xt + 9) / 10);
			long r = xt - 10 * q;

			bd.nominal_hz = r10[r] * pow(10, (double)(q + 3));
		} else {
			double p10 = pow(10, floor(log10(fm)) - 2);

			bd.nominal_hz = round(fm / p10) * p10;
		}
		if (bands) {
			if (n < max)
				bands[n] = bd;
			else
				rc = -ERANGE;
		}
		n++;
	}
	*n_found = bands && n > max ? max : n;
	return rc;
}

/* ------------------------------------------------------------ significant peaks */

/*
 * Statistics of a Welch estimate (Welch 1967; D. B. Percival and A. T.
 * Walden, "Spectral Analysis for Physical Applications", 1993, sec. 6.17):
 * in a bin away from DC and Nyquist, the estimate over its expectation is
 * chi-square with nu degrees of freedom over nu, where for K segments of N
 * samples shifted by D,
 *   nu = 2K / (1 + 2 sum_{j=1}^{K-1} (1 - j/K) rho(jD)^2),
 *   rho(m) = sum_n w[n] w[n + m] / sum_n w[n]^2
 * (the overlap correction: rho = 1/6 for Hann at half overlap).
 */
double sscope_psd_spectrum_edf(const struct sscope_psd_spectrum *s)
{
	double *w, sw2 = 0, den = 1;
	size_t N, D, K;

	if (!s || s->n_segments == 0 || s->nperseg == 0)
		return NAN;
	N = s->nperseg;
	K = s->n_segments;
	D = N - s->noverlap;
	if (K == 1 || D >= N)
		return 2.0 * (double)K;
	w = ssc_alloc_array(N, sizeof(double));
	if (!w || sscope_psd_window_fill(s->window, N, w)) {
		free(w);
		return NAN;
	}
	for (size_t n = 0; n < N; n++)
		sw2 += w[n] * w[n];
	for (size_t j = 1; j < K && j * D < N; j++) {
		double c = 0;

		for (size_t n = 0; n + j * D < N; n++)
			c += w[n] * w[n + j * D];
		c /= sw2;
		den += 2 * (1 - (double)j / (double)K) * c * c;
	}
	free(w);
	return 2.0 * (double)K / den;
}

/* The x with F(x) = target for a decreasing tail function F on (0, inf),
 * by bisection on log x (GSL's own inverses give up on far tails). */
static double tail_inverse(double (*F)(double, double, double), double a,
			   double b, double target)
{
	double lo = -30, hi = 30;

	for (int i = 0; i < 200 && hi - lo > 1e-13; i++) {
		double mid = (lo + hi) / 2;

		if (F(exp(mid), a, b) > target)
			lo = mid;
		else
			hi = mid;
	}
	return exp((lo + hi) / 2);
}

/* Q of F(nu1, nu2): GSL's incomplete beta function, which returns NaN
 * near x = 1 for degrees of freedom of millions (the Welch estimate of
 * 1e9 samples: nu1 1.5e7, nu2 5.5e8); from 1e5 degrees of freedom up
 * (and wherever GSL has no value) Paulson's normal approximation of
 * the cube root of F (Johnson, Kotz and Balakrishnan, Continuous
 * Univariate Distributions 2, 27.5), within 1.4e-4 of the exact tail
 * probability down to 1e-8 at nu1 1e5, nu2 1e6 */
static double fdist_q(double x, double nu1, double nu2)
{
	double q, a, b, c, z;

	if (!(x > 0))
		return x == 0 ? 1.0 : (double)NAN;
	q = nu1 < 1e5 || nu2 < 1e5 ? gsl_cdf_fdist_Q(x, nu1, nu2) : (double)NAN;
	if (!isnan(q))
		return q;
	a = 2 / (9 * nu1);
	b = 2 / (9 * nu2);
	c = cbrt(x);
	z = ((1 - b) * c - (1 - a)) / sqrt(b * c * c + a);
	return gsl_cdf_ugaussian_Q(z);
}

/* the median of chi2(nu): it lies in (nu - 2/3, nu) for every nu >= 1
 * (Chen and Rubin 1986), bisected there, where the incomplete gamma
 * function is evaluated near its mean (a bracket in logarithms reached
 * x of e^30, where GSL's large-x expansion fails and aborts for nu of a
 * million: the Welch estimate of 1e9 samples) */
static double chisq_median(double nu)
{
	double lo = nu > 1 ? nu - 1 : 0, hi = nu > 1 ? nu : 1;

	for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; i++) {
		double mid = (lo + hi) / 2;

		if (gsl_cdf_chisq_Q(mid, nu) > 0.5)
			lo = mid;
		else
			hi = mid;
	}
	return (lo + hi) / 2;
}

static int cmp_dbl(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return x < y ? -1 : x > y;
}

/* Bins of a window's main lobe each side of a tone (about twice the
 * equivalent noise bandwidth; more with zero padding). */
static size_t lobe_bins(const struct sscope_psd_spectrum *s)
{
	struct sscope_psd_window_figures f;
	double pad = (double)s->nfft / (double)s->nperseg;

	if (sscope_psd_window_figures(s->window, s->nperseg, &f))
		return 2;
	return (size_t)ceil(2 * f.enbw_bins * pad);
}

/* Largest leakage of a tone at fractional bin position t into bin k,
 * relative to its peak bin value v at bin position b (the envelope over
 * +-half a bin of frequency uncertainty). */
static double leak(const struct sscope_psd_spectrum *s, double v, double t,
		   double b, size_t k)
{
	double w0 = sscope_psd_window_response(s->window, s->nperseg, s->nfft,
					       b - t);
	double m = 0;

	if (!(w0 > 0))
		return 0;
	for (int i = -5; i <= 5; i++) {
		double r = sscope_psd_window_response(s->window, s->nperseg, s->nfft,
						      (double)k - t + i * 0.1);

		if (r > m)
			m = r;
	}
	return v * (m / w0) * (m / w0);
}

int sscope_psd_spectrum_significant_peaks(const struct sscope_psd_spectrum *s,
					  size_t max, double fmin_hz,
					  double fmax_hz, double alpha,
					  struct sscope_psd_sig_peak *peaks,
					  size_t *n_found,
					  struct sscope_psd_peak_test *test)
{
	size_t h, L, M = 0, nc = 0, *cand = NULL, na = 0;
	double nu, *nb = NULL, *floor_ = NULL, thr_p, med1, fm, nuf, nfit;
	int rc = 0;

	if (!s || !s->value || !n_found || (max && !peaks) || !(fmax_hz >= fmin_hz))
		return -EINVAL;
	if (alpha == 0)
		alpha = 0.01;
	if (!(alpha > 0 && alpha < 1))
		return -EINVAL;
	*n_found = 0;
	nu = sscope_psd_spectrum_edf(s);
	if (!(nu > 0))
		return -EINVAL;
	h = lobe_bins(s);
	L = 32 > 4 * h ? 32 : 4 * h;
	for (size_t k = 1; k + 1 < s->n_bins; k++)
		if (s->freq_hz[k] >= fmin_hz && s->freq_hz[k] <= fmax_hz)
			M++;
	/* the floor: the median of the neighbours beyond the main lobe,
	 * divided by the median of chi2(nu)/nu; its own scatter is that of
	 * chi2(nuf)/nuf with nuf = 8 n f(m)^2 m^2 (the large-sample variance
	 * of a median, n neighbours, f the density at the median m), n
	 * counted in independent bins (nperseg / nfft of them) */
	med1 = chisq_median(nu) / nu;
	fm = nu * gsl_ran_chisq_pdf(med1 * nu, nu);
	nfit = (double)(2 * (L - h)) * (double)s->nperseg / (double)s->nfft;
	nuf = 8 * nfit * fm * fm * med1 * med1;
	thr_p = M ? alpha / (double)M : alpha;
	if (test) {
		test->alpha = alpha;
		test->edf = nu;
		test->floor_edf = nuf;
		test->bins_tested = M;
		test->p_threshold = thr_p;
		test->ratio_threshold = tail_inverse(fdist_q, nu, nuf,
						     thr_p);
		test->floor_half_width = L;
		test->lobe_half_width = h;
	}
	if (max == 0 || s->n_bins < 3 || M == 0)
		return 0;
	cand = ssc_alloc_array(s->n_bins, sizeof(size_t));
	floor_ = ssc_alloc_array(s->n_bins, sizeof(double));
	nb = ssc_alloc_array(2 * L + 1, sizeof(double));
	if (!cand || !floor_ || !nb) {
		rc = -ENOMEM;
		goto out;
	}
	/* candidates: local maxima passing the test against the floor alone
	 * (leakage of other peaks can only raise what they are tested
	 * against) */
	for (size_t k = 1; k + 1 < s->n_bins; k++) {
		size_t lo, hi, n = 0;

		if (s->freq_hz[k] < fmin_hz || s->freq_hz[k] > fmax_hz ||
		    !local_max(s->value, k))
			continue;
		lo = k > L ? k - L : 1;
		hi = k + L + 1 < s->n_bins ? k + L : s->n_bins - 2;
		/* keep the window's width near the edges */
		if (hi - lo < 2 * L) {
			if (lo == 1)
				hi = lo + 2 * L < s->n_bins - 1 ? lo + 2 * L :
								  s->n_bins - 2;
			else
				lo = hi > 2 * L ? hi - 2 * L : 1;
		}
		for (size_t i = lo; i <= hi; i++)
			if (i + h < k || i > k + h)
				nb[n++] = s->value[i];
		if (n < 3)
			continue;
		qsort(nb, n, sizeof(double), cmp_dbl);
		floor_[k] = (n % 2 ? nb[n / 2] : (nb[n / 2 - 1] + nb[n / 2]) / 2) /
			    med1;
		if (!(floor_[k] > 0) ||
		    !(fdist_q(s->value[k] / floor_[k], nu, nuf) < thr_p))
			continue;
		cand[nc++] = k;
	}
	/* strongest first; each tested against its floor plus the leakage
	 * of the stronger peaks already accepted */
	for (size_t a = 1; a < nc; a++)
		for (size_t b = a; b > 0 && s->value[cand[b - 1]] < s->value[cand[b]]; b--) {
			size_t t = cand[b];

			cand[b] = cand[b - 1];
			cand[b - 1] = t;
		}
	for (size_t c = 0; c < nc && na < max; c++) {
		size_t k = cand[c];
		double ref = floor_[k], p;
		struct sscope_psd_sig_peak *pk = &peaks[na];

		for (size_t j = 0; j < na; j++)
			ref += leak(s, peaks[j].peak.value,
				    (double)peaks[j].peak.bin + peaks[j].peak.offset_bins,
				    (double)peaks[j].peak.bin, k);
		p = fdist_q(s->value[k] / ref, nu, nuf);
		if (!(p < thr_p))
			continue;
		if (sscope_psd_spectrum_peak_at(s, k, &pk->peak))
			continue;
		pk->floor = floor_[k];
		pk->ratio = s->value[k] / ref;
		pk->p_value = p;
		na++;
	}
	*n_found = na;
out:
	free(cand);
	free(floor_);
	free(nb);
	return rc;
}
