/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Converter tests of IEEE Std 1241-2010 ("Terminology and Test Methods for
 * Analog-to-Digital Converters"): three- and four-parameter sine fits
 * (4.1.4 / Annex B; linear least squares and Levenberg-Marquardt from GSL),
 * SINAD and ENOB (9.3, 9.4), THD and SFDR from a windowed FFT (FFTW,
 * 4-term Blackman-Harris), and the code-density (histogram) test with a
 * sine input (6.4.3: transition levels T_k = C - A cos(pi CH_{k-1} / S))
 * with the record length it needs (6.4.4: a mid-scale code's count is
 * binomial with mean 2 S / (pi n), so DNL has sd sqrt(pi n / (2 S)) LSB).
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <fftw3.h>
#include <gsl/gsl_blas.h>
#include <gsl/gsl_multifit.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_vector.h>

#include "sscope-adc.h"


static void finish_fit(struct sscope_adc_sine_fit *f)
{
	f->amplitude = hypot(f->a, f->b);
	/* a cos + b sin = amp cos(wt + phase), phase = atan2(-b, a) */
	f->phase_rad = atan2(-f->b, f->a);
}

static double resid_rms(const double *x, size_t n, double fs,
			const struct sscope_adc_sine_fit *f)
{
	struct ssc_ksum s = { 0, 0 };
	double w = 2 * PI * f->freq_hz;

	for (size_t i = 0; i < n; i++) {
		double t = (double)i / fs;
		double e = x[i] - (f->a * cos(w * t) + f->b * sin(w * t) + f->offset);

		ssc_ksum_add(&s, e * e);
	}
	return sqrt(ssc_ksum_value(&s) / (double)n);
}

int sscope_adc_sine_fit3(const double *x, size_t n, double fs, double f0,
			 struct sscope_adc_sine_fit *fit)
{
	gsl_matrix *X;
	gsl_vector *y, *c;
	gsl_matrix *cov;
	gsl_multifit_linear_workspace *ws;
	double chisq, w = 2 * PI * f0;
	int rc = 0;

	if (!x || !fit || !(fs > 0) || !(f0 > 0) || !(f0 < fs / 2))
		return -EINVAL;
	if (n < 4)
		return -EDOM;
	X = gsl_matrix_alloc(n, 3);
	y = gsl_vector_alloc(n);
	c = gsl_vector_alloc(3);
	cov = gsl_matrix_alloc(3, 3);
	ws = gsl_multifit_linear_alloc(n, 3);
	if (!X || !y || !c || !cov || !ws) {
		rc = -ENOMEM;
		goto out;
	}
	for (size_t i = 0; i < n; i++) {
		double t = (double)i / fs;

		gsl_matrix_set(X, i, 0, cos(w * t));
		gsl_matrix_set(X, i, 1, sin(w * t));
		gsl_matrix_set(X, i, 2, 1);
		gsl_vector_set(y, i, x[i]);
	}
	if (gsl_multifit_linear(X, y, c, cov, &chisq, ws)) {
		rc = -EDOM;
		goto out;
	}
	memset(fit, 0, sizeof(*fit));
	fit->freq_hz = f0;
	fit->a = gsl_vector_get(c, 0);
	fit->b = gsl_vector_get(c, 1);
	fit->offset = gsl_vector_get(c, 2);
	finish_fit(fit);
	fit->rms_residual = resid_rms(x, n, fs, fit);
out:
	gsl_matrix_free(X);
	gsl_vector_free(y);
	gsl_vector_free(c);
	gsl_matrix_free(cov);
	if (ws)
		gsl_multifit_linear_free(ws);
	return rc;
}

/* frequency of the largest spectral peak (Hann window, parabolic
 * interpolation of log magnitudes) */
static int peak_freq(const double *x, size_t n, double fs, double *f)
{
	size_t nb = n / 2 + 1, kmax = 1;
	double *in = fftw_malloc(n * sizeof(double));
	fftw_complex *out = fftw_malloc(nb * sizeof(fftw_complex));
	fftw_plan p;
	double mean = 0, best = -1;

	if (!in || !out) {
		fftw_free(in);
		fftw_free(out);
		return -ENOMEM;
	}
	for (size_t i = 0; i < n; i++)
		mean += x[i];
	mean /= (double)n;
	p = fftw_plan_dft_r2c_1d((int)n, in, out, FFTW_ESTIMATE);
	for (size_t i = 0; i < n; i++)
		in[i] = (x[i] - mean) * (0.5 - 0.5 * cos(2 * PI * (double)i / (double)n));
	fftw_execute(p);
	for (size_t k = 1; k + 1 < nb; k++) {
		double m = out[k][0] * out[k][0] + out[k][1] * out[k][1];

		if (m > best) {
			best = m;
			kmax = k;
		}
	}
	{
		double a = log(hypot(out[kmax - 1][0], out[kmax - 1][1]) + 1e-300);
		double b = log(hypot(out[kmax][0], out[kmax][1]) + 1e-300);
		double c = log(hypot(out[kmax + 1][0], out[kmax + 1][1]) + 1e-300);
		double d = a - 2 * b + c, delta = d < 0 ? 0.5 * (a - c) / d : 0;

		*f = ((double)kmax + delta) * fs / (double)n;
	}
	fftw_destroy_plan(p);
	fftw_free(in);
	fftw_free(out);
	return 0;
}

struct fit4_data {
	const double *x;
	size_t n;
	double fs;
};

static int f4_f(const gsl_vector *p, void *ctx, gsl_vector *fv)
{
	const struct fit4_data *d = ctx;
	double a = gsl_vector_get(p, 0), b = gsl_vector_get(p, 1);
	double c = gsl_vector_get(p, 2), w = gsl_vector_get(p, 3);

	for (size_t i = 0; i < d->n; i++) {
		double t = (double)i / d->fs;

		gsl_vector_set(fv, i, a * cos(w * t) + b * sin(w * t) + c - d->x[i]);
	}
	return GSL_SUCCESS;
}

static int f4_df(const gsl_vector *p, void *ctx, gsl_matrix *J)
{
	const struct fit4_data *d = ctx;
	double a = gsl_vector_get(p, 0), b = gsl_vector_get(p, 1);
	double w = gsl_vector_get(p, 3);

	for (size_t i = 0; i < d->n; i++) {
		double t = (double)i / d->fs, cw = cos(w * t), sw = sin(w * t);

		gsl_matrix_set(J, i, 0, cw);
		gsl_matrix_set(J, i, 1, sw);
		gsl_matrix_set(J, i, 2, 1);
		gsl_matrix_set(J, i, 3, t * (-a * sw + b * cw));
	}
	return GSL_SUCCESS;
}

int sscope_adc_sine_fit4(const double *x, size_t n, double fs, double f0,
			 struct sscope_adc_sine_fit *fit)
{
	struct sscope_adc_sine_fit f3;
	struct fit4_data d = { x, n, fs };
	gsl_multifit_nlinear_parameters par = gsl_multifit_nlinear_default_parameters();
	gsl_multifit_nlinear_workspace *w = NULL;
	gsl_multifit_nlinear_fdf fdf;
	gsl_vector *p0 = NULL;
	int rc, info = 0;

	if (!x || !fit || !(fs > 0))
		return -EINVAL;
	if (n < 8)
		return -EDOM;
	if (!(f0 > 0)) {
		rc = peak_freq(x, n, fs, &f0);
		if (rc)
			return rc;
	}
	rc = sscope_adc_sine_fit3(x, n, fs, f0, &f3);
	if (rc)
		return rc;
	fdf.f = f4_f;
	fdf.df = f4_df;
	fdf.fvv = NULL;
	fdf.n = n;
	fdf.p = 4;
	fdf.params = &d;
	par.trs = gsl_multifit_nlinear_trs_lm;
	w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &par, n, 4);
	p0 = gsl_vector_alloc(4);
	if (!w || !p0) {
		rc = -ENOMEM;
		goto out;
	}
	gsl_vector_set(p0, 0, f3.a);
	gsl_vector_set(p0, 1, f3.b);
	gsl_vector_set(p0, 2, f3.offset);
	gsl_vector_set(p0, 3, 2 * PI * f0);
	gsl_multifit_nlinear_init(p0, &fdf, w);
	if (gsl_multifit_nlinear_driver(100, 1e-12, 1e-12, 1e-12, NULL, NULL,
					&info, w) != GSL_SUCCESS &&
	    gsl_multifit_nlinear_niter(w) >= 100) {
		rc = -ERANGE;
		goto out;
	}
	{
		gsl_vector *p = gsl_multifit_nlinear_position(w);

		memset(fit, 0, sizeof(*fit));
		fit->a = gsl_vector_get(p, 0);
		fit->b = gsl_vector_get(p, 1);
		fit->offset = gsl_vector_get(p, 2);
		fit->freq_hz = gsl_vector_get(p, 3) / (2 * PI);
		fit->iterations = (int)gsl_multifit_nlinear_niter(w);
		finish_fit(fit);
		fit->rms_residual = resid_rms(x, n, fs, fit);
		if (!(fit->rms_residual <= f3.rms_residual * (1 + 1e-9))) {
			/* never worse than the three-parameter start */
			*fit = f3;
		}
	}
	rc = 0;
out:
	gsl_vector_free(p0);
	if (w)
		gsl_multifit_nlinear_free(w);
	return rc;
}

/* sum of |X|^2 over bins k0 +- half (clamped to 1 .. nb-1) */
static double tone_power(const double *pw, size_t nb, long k0, long half)
{
	double s = 0;

	for (long k = k0 - half; k <= k0 + half; k++)
		if (k >= 1 && (size_t)k < nb)
			s += pw[k];
	return s;
}

static long alias_bin(double f, double fs, size_t n)
{
	double r = fmod(f, fs);

	if (r > fs / 2)
		r = fs - r;
	return lround(r * (double)n / fs);
}

int sscope_adc_dynamic_test(const double *x, size_t n, double fs, double fsr,
			    struct sscope_adc_dynamic *res)
{
	const long half = 4;
	size_t nb = n / 2 + 1;
	double *in = NULL, *pw = NULL, sw2 = 0, p1, harm = 0, spur = 0, peak1 = 0;
	fftw_complex *out = NULL;
	fftw_plan p;
	long k1;
	int rc;

	if (!x || !res || !(fs > 0))
		return -EINVAL;
	memset(res, 0, sizeof(*res));
	/* fits and powers: samples in a sane range */
	rc = ssc_magnitude_check(x, 1, n, 250, "adc test", NULL);
	if (rc)
		return rc;
	rc = sscope_adc_sine_fit4(x, n, fs, 0, &res->fit);
	if (rc)
		return rc;
	res->sinad_db = 20 * log10(res->fit.amplitude / sqrt(2.0) /
				   res->fit.rms_residual);
	res->enob = fsr > 0 ? log2(fsr / (res->fit.rms_residual * sqrt(12.0))) :
			      (res->sinad_db - 1.76) / 6.02;
	in = fftw_malloc(n * sizeof(double));
	out = fftw_malloc(nb * sizeof(fftw_complex));
	pw = malloc(nb * sizeof(double));
	if (!in || !out || !pw) {
		rc = -ENOMEM;
		goto done;
	}
	p = fftw_plan_dft_r2c_1d((int)n, in, out, FFTW_ESTIMATE);
	for (size_t i = 0; i < n; i++) {
		double u = 2 * PI * (double)i / (double)n;
		double wv = 0.35875 - 0.48829 * cos(u) + 0.14128 * cos(2 * u) -
			    0.01168 * cos(3 * u);

		in[i] = (x[i] - res->fit.offset) * wv;
		sw2 += wv * wv;
	}
	fftw_execute(p);
	fftw_destroy_plan(p);
	for (size_t k = 0; k < nb; k++)
		pw[k] = out[k][0] * out[k][0] + out[k][1] * out[k][1];
	k1 = alias_bin(res->fit.freq_hz, fs, n);
	p1 = tone_power(pw, nb, k1, half);
	for (long k = k1 - half; k <= k1 + half; k++)
		if (k >= 1 && (size_t)k < nb && pw[k] > peak1)
			peak1 = pw[k];
	for (int h = 2; h <= 10; h++) {
		long kh = alias_bin(h * res->fit.freq_hz, fs, n);

		if (kh <= half || labs(kh - k1) <= 2 * half)
			continue;
		harm += tone_power(pw, nb, kh, half);
	}
	for (size_t k = (size_t)half + 1; k < nb; k++) {
		if (labs((long)k - k1) <= half)
			continue;
		if (pw[k] > spur)
			spur = pw[k];
	}
	res->thd_db = harm > 0 ? 10 * log10(harm / p1) : -(double)INFINITY;
	res->sfdr_db = spur > 0 ? 10 * log10(peak1 / spur) : (double)INFINITY;
	{
		/* mean square of the harmonics, in the unit of x squared */
		double hms = harm * 2 / ((double)n * sw2);
		double noise = res->fit.rms_residual * res->fit.rms_residual - hms;
		double sig = res->fit.amplitude * res->fit.amplitude / 2;

		res->snr_db = noise > 0 ? 10 * log10(sig / noise) : (double)INFINITY;
	}
	rc = 0;
done:
	fftw_free(in);
	fftw_free(out);
	free(pw);
	return rc;
}

int sscope_adc_codes(const double *x, size_t stride, size_t n, double lo,
		     double hi, size_t n_codes, int64_t *codes, size_t *clipped)
{
	double q = (hi - lo) / (double)n_codes;
	size_t c = 0;

	if (clipped)
		*clipped = 0;
	if (!x || !codes || stride == 0 || n_codes < 2 || !(hi > lo) ||
	    !isfinite(q) || !(q > 0))
		return -EINVAL;
	for (size_t i = 0; i < n; i++) {
		double k = floor((x[i * stride] - lo) / q + 0.5);

		if (!isfinite(x[i * stride]))
			return -EDOM;
		if (k < 0 || k > (double)(n_codes - 1)) {
			k = k < 0 ? 0 : (double)(n_codes - 1);
			c++;
		}
		codes[i] = (int64_t)k;
	}
	if (clipped)
		*clipped = c;
	return 0;
}

int sscope_adc_histogram_test(const int64_t *codes, size_t n, size_t nc,
			      double *dnl, double *inl, double *dnl_max,
			      double *inl_max)
{
	size_t *h;
	double *T, cum = 0, S = (double)n;
	double sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0, slope, icpt;
	size_t hit = 0;

	if (!codes || !dnl || !inl || nc < 3)
		return -EINVAL;
	h = calloc(nc, sizeof(*h));
	T = malloc(nc * sizeof(double));
	if (!h || !T) {
		free(h);
		free(T);
		return -ENOMEM;
	}
	for (size_t i = 0; i < n; i++) {
		if (codes[i] < 0 || (size_t)codes[i] >= nc) {
			free(h);
			free(T);
			return -EINVAL;
		}
		h[codes[i]]++;
	}
	for (size_t k = 0; k < nc; k++)
		hit += h[k] > 0;
	if (hit < 3) {
		free(h);
		free(T);
		return -EDOM;
	}
	/* transition k lies between codes k-1 and k */
	T[0] = (double)NAN;
	for (size_t k = 1; k < nc; k++) {
		cum += (double)h[k - 1];
		T[k] = cum > 0 && cum < S ? -cos(PI * cum / S) : (double)NAN;
	}
	/* the transitions of codes hit on both sides: line fit */
	for (size_t k = 2; k + 1 < nc; k++) {
		if (!isfinite(T[k - 1]) || !isfinite(T[k]) || !isfinite(T[k + 1]))
			continue;
		sx += (double)k;
		sy += T[k];
		sxx += (double)k * (double)k;
		sxy += (double)k * T[k];
		m += 1;
	}
	if (m < 2) {
		free(h);
		free(T);
		return -EDOM;
	}
	slope = (m * sxy - sx * sy) / (m * sxx - sx * sx);
	icpt = (sy - slope * sx) / m;
	if (dnl_max)
		*dnl_max = 0;
	if (inl_max)
		*inl_max = 0;
	for (size_t k = 0; k < nc; k++) {
		bool ok = k >= 2 && k + 1 < nc && isfinite(T[k - 1]) &&
			  isfinite(T[k]) && isfinite(T[k + 1]);

		inl[k] = ok ? (T[k] - (icpt + slope * (double)k)) / slope :
			      (double)NAN;
		dnl[k] = k >= 2 && k + 1 < nc && isfinite(T[k]) &&
				 isfinite(T[k + 1]) ?
			 (T[k + 1] - T[k]) / slope - 1 : (double)NAN;
		if (dnl_max && isfinite(dnl[k]) && fabs(dnl[k]) > *dnl_max)
			*dnl_max = fabs(dnl[k]);
		if (inl_max && isfinite(inl[k]) && fabs(inl[k]) > *inl_max)
			*inl_max = fabs(inl[k]);
	}
	free(h);
	free(T);
	return 0;
}

int sscope_adc_histogram_quality(const int64_t *codes, size_t n,
				 double dnl_tol_lsb,
				 struct sscope_adc_hist_quality *q)
{
	int64_t lo, hi;
	double nc;

	if (!codes || !q || n == 0 || !(dnl_tol_lsb > 0) || !isfinite(dnl_tol_lsb))
		return -EINVAL;
	lo = hi = codes[0];
	for (size_t i = 1; i < n; i++) {
		if (codes[i] < lo)
			lo = codes[i];
		if (codes[i] > hi)
			hi = codes[i];
	}
	q->codes_spanned = (size_t)(hi - lo) + 1;
	nc = (double)q->codes_spanned;
	q->samples_per_code = (double)n / nc;
	q->dnl_sd_lsb = sqrt(PI * nc / (2 * (double)n));
	q->samples_needed = ceil(PI * nc / (2 * dnl_tol_lsb * dnl_tol_lsb));
	q->resolved = q->dnl_sd_lsb <= dnl_tol_lsb;
	return 0;
}
