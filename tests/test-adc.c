/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Converter model: quantization noise against its closed forms (SQNR
 * 6.02 N + 1.76 dB, AVAR q^2/(12 fs tau), 3 Q^2 / tau^2), the dither bias
 * bound of Widrow & Kollar checked by simulation, IEEE 1241 ENOB of an
 * ideal quantizer, code-density recovery of injected INL/DNL, spec errors,
 * and the REFERENCE.md word-length table (+-100 deg/s, 100 Hz).
 * Tolerances are from the estimators' statistics with fixed seeds.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "check-main.h"
#include "sscope-adc.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180)

/* smaller records under valgrind (CK_FORK=no) */
static size_t scaled(size_t n)
{
	const char *f = getenv("CK_FORK");

	return f && !strcmp(f, "no") ? n / 4 : n;
}

static struct sscope_adc_spec ideal(int bits, double lo, double hi)
{
	struct sscope_adc_spec s;

	memset(&s, 0, sizeof(s));
	s.bits = bits;
	s.lo = lo;
	s.hi = hi;
	s.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	s.ref_temp_degc = 25;
	return s;
}

/* SQNR of an ideal quantizer on a full-scale sine: 6.02 N + 1.76 dB.
 * The error e is (very nearly) uniform on +-q/2 and independent of the
 * phase; mean(e^2) has relative sd sqrt(1/80 - 1/144) * 12 / sqrt(n) =
 * 0.894 / sqrt(n); 4 sd in dB. */
START_TEST(test_sqnr)
{
	static const int bits[] = { 10, 12, 16 };
	size_t n = scaled(1 << 16);
	double *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));

	ck_assert(x && y);
	for (size_t b = 0; b < 3; b++) {
		struct sscope_adc_spec s = ideal(bits[b], -1, 1);
		struct sscope_adc *a;
		double q = 2 / ldexp(1, bits[b]), A = 1 - q, e2 = 0, sqnr, theory;
		double f = (3 - sqrt(5.0)) / 2; /* badly approximable: phases spread */
		double tol = 4 * 10 / log(10) * 0.894 / sqrt((double)n);
		size_t clipped = 0;

		ck_assert_int_eq(sscope_adc_new(&a, &s, 1, 0, 1, NULL), 0);
		ck_assert_rel(sscope_adc_lsb(a), q, 1e-15);
		for (size_t i = 0; i < n; i++)
			x[i] = A * sin(2 * PI * f * (double)i + 0.3);
		ck_assert_int_eq(sscope_adc_digitize(a, x, 1, n, 100, NULL, y, NULL,
						     &clipped), 0);
		ck_assert_uint_eq(clipped, 0);
		for (size_t i = 0; i < n; i++)
			e2 += (y[i] - x[i]) * (y[i] - x[i]);
		e2 /= (double)n;
		sqnr = 10 * log10(A * A / 2 / e2);
		/* the formula is for amplitude FS/2 = 1: scale to A */
		theory = 6.02 * bits[b] + 1.76 + 20 * log10(A);
		ck_assert_msg(fabs(sqnr - theory) <= tol + 0.005,
			      "%d bits: SQNR %.4f dB, theory %.4f dB, tol %.4f",
			      bits[b], sqnr, theory, tol);
		sscope_adc_free(a);
	}
	free(x);
	free(y);
}
END_TEST

/* the deviation of the error record e at m = 1, 10, 100 against AVAR
 * model(tau); 4 sd of the AVAR estimate, sd from the EDF */
static void check_avar(const double *e, size_t n, double fs, int alpha,
		       double (*model)(double tau, double q, double fs), double q)
{
	struct sscope_allan *plan;
	struct sscope_allan_opts o = { 0 };
	struct sscope_allan_point pts[3];
	size_t m[] = { 1, 10, 100 }, np;

	o.alpha_fixed = true;
	o.alpha = alpha;
	o.threads = 1;
	ck_assert_int_eq(sscope_allan_new(&plan, n, &o), 0);
	ck_assert_int_eq(sscope_allan_compute(plan, e, 1, n, fs, m, 3, pts, &np,
					      NULL), 0);
	ck_assert_uint_eq(np, 3);
	for (size_t i = 0; i < np; i++) {
		double av = pts[i].dev * pts[i].dev, th = model(pts[i].tau_s, q, fs);
		double tol = 4 * sqrt(2 / pts[i].edf);

		ck_assert_msg(fabs(av / th - 1) <= tol,
			      "tau %g: AVAR %.6g, theory %.6g (ratio %.4f, tol %.4f)",
			      pts[i].tau_s, av, th, av / th, tol);
	}
	sscope_allan_free(plan);
}

static double avar_round(double tau, double q, double fs)
{
	return q * q / (12 * fs * tau);
}

static double avar_integrate(double tau, double q, double fs)
{
	double Q = q / (fs * sqrt(12.0));

	return 3 * Q * Q / (tau * tau);
}

static void noise_record(double *x, size_t n, double sd, unsigned long seed)
{
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	gsl_rng_set(r, seed);
	for (size_t i = 0; i < n; i++)
		x[i] = 0.37 * sd + gsl_ran_gaussian_ziggurat(r, sd);
	gsl_rng_free(r);
}

/* rate rounding adds white rate noise: AVAR q^2 / (12 fs tau) */
START_TEST(test_avar_round)
{
	size_t n = scaled(200000);
	double fs = 100, *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));
	struct sscope_adc_spec s = ideal(12, -1, 1);
	struct sscope_adc *a;
	double q = 2.0 / 4096;

	ck_assert(x && y);
	noise_record(x, n, 2 * q, 11);
	ck_assert_int_eq(sscope_adc_new(&a, &s, 1, 0, 1, NULL), 0);
	ck_assert_int_eq(sscope_adc_digitize(a, x, 1, n, fs, NULL, y, NULL, NULL), 0);
	for (size_t i = 0; i < n; i++)
		y[i] -= x[i];
	check_avar(y, n, fs, 0, avar_round, q);
	sscope_adc_free(a);
	free(x);
	free(y);
}
END_TEST

/* integrating counter with the residual carried: 3 Q^2 / tau^2 with
 * Q = q / (fs sqrt 12) (white angle noise) */
START_TEST(test_avar_integrate)
{
	size_t n = scaled(200000);
	double fs = 100, *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));
	struct sscope_adc_spec s = ideal(12, -1, 1);
	struct sscope_adc *a;
	double q = 2.0 / 4096, sum_in = 0, sum_out = 0;

	ck_assert(x && y);
	s.mode = SSCOPE_ADC_INTEGRATE;
	noise_record(x, n, 3 * q, 12);
	ck_assert_int_eq(sscope_adc_new(&a, &s, 1, 0, 1, NULL), 0);
	ck_assert_int_eq(sscope_adc_digitize(a, x, 1, n, fs, NULL, y, NULL, NULL), 0);
	for (size_t i = 0; i < n; i++) {
		sum_in += x[i];
		sum_out += y[i];
		y[i] -= x[i];
	}
	/* the integral is kept to within half a count */
	ck_assert_msg(fabs(sum_out - sum_in) / fs <= 0.5 * q / fs * (1 + 1e-9),
		      "integral error %g", fabs(sum_out - sum_in) / fs);
	check_avar(y, n, fs, 2, avar_integrate, q);
	sscope_adc_free(a);
	free(x);
	free(y);
}
END_TEST

/* The mean error of a quantizer under Gaussian noise is bounded by
 * (q/pi) exp(-2 pi^2 sigma^2/q^2), and at mu = q/4 (sin = 1) the first
 * Fourier term attains it: simulated within 4 standard errors. */
START_TEST(test_dither_bound)
{
	static const double ratios[] = { 0.2, 0.27, 0.35, 0.5 };
	size_t n = scaled(400000);
	double *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));
	struct sscope_adc_spec s = ideal(8, -1, 1);
	struct sscope_adc *a;
	double q = 2.0 / 256;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	ck_assert(x && y && r);
	ck_assert_int_eq(sscope_adc_new(&a, &s, 1, 0, 1, NULL), 0);
	for (size_t k = 0; k < 4; k++) {
		double sig = ratios[k] * q, mu = q / 4, mean = 0, var = 0, bias, se;
		double bound = sscope_adc_dither_bound(q, sig);
		double second = q / (2 * PI) * exp(-8 * PI * PI * sig * sig / (q * q));

		gsl_rng_set(r, 100 + k);
		for (size_t i = 0; i < n; i++)
			x[i] = mu + gsl_ran_gaussian_ziggurat(r, sig);
		ck_assert_int_eq(sscope_adc_digitize(a, x, 1, n, 100, NULL, y, NULL,
						     NULL), 0);
		for (size_t i = 0; i < n; i++)
			mean += y[i] - x[i];
		mean /= (double)n;
		for (size_t i = 0; i < n; i++)
			var += (y[i] - x[i] - mean) * (y[i] - x[i] - mean);
		se = sqrt(var / (double)(n - 1) / (double)n);
		bias = fabs(mean);
		ck_assert_msg(bias <= bound + 4 * se,
			      "sigma/q %.2f: bias %.4g q > bound %.4g q + 4 se",
			      ratios[k], bias / q, bound / q);
		/* tight: the first term is the bound; the second harmonic
		 * vanishes at mu = q/4 (sin pi = 0), the third is below
		 * bound * exp(-16 pi^2 sigma^2/q^2) / 3 */
		ck_assert_msg(bias >= bound * (1 - exp(-16 * PI * PI * ratios[k] * ratios[k]) / 3) -
					      4 * se,
			      "sigma/q %.2f: bias %.4g q well below the bound %.4g q",
			      ratios[k], bias / q, bound / q);
		(void)second;
		/* an arbitrary mean (the textbook's 0.37 deg/h at q = 10.99 deg/h):
		 * the first harmonic sscope_adc_bias_error() is the mean error
		 * within the second harmonic's amplitude (q/2pi) exp(-8 pi^2
		 * sigma^2/q^2) and 4 standard errors */
		mu = 0.37 / 10.986328125 * q;
		gsl_rng_set(r, 200 + k);
		for (size_t i = 0; i < n; i++)
			x[i] = mu + gsl_ran_gaussian_ziggurat(r, sig);
		ck_assert_int_eq(sscope_adc_digitize(a, x, 1, n, 100, NULL, y, NULL,
						     NULL), 0);
		mean = 0;
		for (size_t i = 0; i < n; i++)
			mean += y[i] - x[i];
		mean /= (double)n;
		ck_assert_msg(fabs(mean - sscope_adc_bias_error(q, sig, mu)) <= second + 4 * se,
			      "sigma/q %.2f: mean error %.4g q, first harmonic %.4g q",
			      ratios[k], mean / q, sscope_adc_bias_error(q, sig, mu) / q);
	}
	sscope_adc_free(a);
	gsl_rng_free(r);
	free(x);
	free(y);
}
END_TEST

/* IEEE 1241: the ENOB of an ideal quantizer equals its word length within
 * 0.1; the four-parameter fit finds the frequency. */
START_TEST(test_enob_ideal)
{
	static const int bits[] = { 8, 12 };
	size_t n = scaled(16384);
	double fs = 1000, f0 = 1000 * 0.0371234;
	double *x = malloc(n * sizeof(double)), *y = malloc(n * sizeof(double));

	ck_assert(x && y);
	for (size_t b = 0; b < 2; b++) {
		struct sscope_adc_spec s = ideal(bits[b], -1, 1);
		struct sscope_adc *a;
		struct sscope_adc_dynamic d;
		double q = 2 / ldexp(1, bits[b]);

		ck_assert_int_eq(sscope_adc_new(&a, &s, 1, 0, 1, NULL), 0);
		for (size_t i = 0; i < n; i++)
			x[i] = (1 - q) * cos(2 * PI * f0 * (double)i / fs + 0.7) + 0.1 * q;
		ck_assert_int_eq(sscope_adc_digitize(a, x, 1, n, fs, NULL, y, NULL,
						     NULL), 0);
		ck_assert_int_eq(sscope_adc_dynamic_test(y, n, fs, 2, &d), 0);
		ck_assert_msg(fabs(d.enob - bits[b]) <= 0.1, "%d bits: ENOB %.4f",
			      bits[b], d.enob);
		ck_assert_rel(d.fit.freq_hz, f0, 1e-6);
		ck_assert_rel(d.fit.amplitude, 1 - q, q / 10);
		ck_assert_msg(fabs(d.sinad_db - (6.02 * bits[b] + 1.76 + 20 * log10(1 - q))) < 0.6,
			      "SINAD %.3f", d.sinad_db);
		sscope_adc_free(a);
	}
	free(x);
	free(y);
}
END_TEST

/* THD of a sine with a known 3rd harmonic (-60 dBc) */
START_TEST(test_thd)
{
	size_t n = 8192;
	double fs = 1000, f0 = 1000 * 0.0512345, *x = malloc(n * sizeof(double));
	struct sscope_adc_dynamic d;

	ck_assert(x);
	for (size_t i = 0; i < n; i++) {
		double t = (double)i / fs;

		x[i] = sin(2 * PI * f0 * t) + 1e-3 * sin(2 * PI * 3 * f0 * t + 0.4);
	}
	ck_assert_int_eq(sscope_adc_dynamic_test(x, n, fs, 0, &d), 0);
	ck_assert_msg(fabs(d.thd_db + 60) < 0.05, "THD %.4f dB", d.thd_db);
	ck_assert_msg(fabs(d.sfdr_db - 60) < 0.5, "SFDR %.4f dB", d.sfdr_db);
	free(x);
}
END_TEST

/* Code density: an injected INL profile (and its DNL) is recovered.
 * The sine's phases are the golden-ratio Kronecker sequence, whose
 * discrepancy is O(log S / S): cumulative counts are then within a few
 * tens of their expectation (not sqrt(S) as with random phases), i.e.
 * within 0.05 LSB at >= 600 counts per code. */
START_TEST(test_histogram)
{
	const int bits = 8;
	size_t nc = 256, S = scaled(1 << 18);
	double *inl = malloc(nc * sizeof(double)), *x = malloc(S * sizeof(double));
	double *y = malloc(S * sizeof(double)), *dnl_r = malloc(nc * sizeof(double));
	double *inl_r = malloc(nc * sizeof(double)), dmax, imax;
	int64_t *codes = malloc(S * sizeof(int64_t));
	struct sscope_adc_spec s = ideal(bits, -1, 1);
	struct sscope_adc *a;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double phi = (sqrt(5.0) - 1) / 2, tol = S < (1u << 18) ? 0.1 : 0.05;
	double w_true[256];

	ck_assert(inl && x && y && dnl_r && inl_r && codes && r);
	gsl_rng_set(r, 5);
	/* transitions with random widths 1 + U(-0.4, 0.4) LSB plus a bow */
	inl[0] = 0;
	{
		double c = 0;

		for (size_t k = 1; k < nc; k++) {
			inl[k] = c + 0.8 * sin(PI * (double)k / (double)nc);
			c += 0.8 * (gsl_rng_uniform(r) - 0.5);
		}
	}
	ck_assert_int_eq(sscope_adc_new(&a, &s, 1, 0, 1, NULL), 0);
	ck_assert_int_eq(sscope_adc_set_inl(a, inl, nc), 0);
	for (size_t i = 0; i < S; i++) {
		double ph = fmod((double)i * phi, 1.0);

		x[i] = 1.03 * sin(2 * PI * ph) - 1.0 / 256;
	}
	ck_assert_int_eq(sscope_adc_digitize(a, x, 1, S, 1000, NULL, y, codes, NULL), 0);
	ck_assert_int_eq(sscope_adc_histogram_test(codes, S, nc, dnl_r, inl_r, &dmax,
						   &imax), 0);
	/* compare after removing a least-squares line over the same codes
	 * (gain and offset are not INL) */
	{
		double sx = 0, sy = 0, sxx = 0, sxy = 0, m = 0, sl, ic, mw = 0;
		size_t nw = 0;

		for (size_t k = 0; k < nc; k++) {
			if (!isfinite(inl_r[k]))
				continue;
			sx += (double)k;
			sy += inl[k];
			sxx += (double)k * (double)k;
			sxy += (double)k * inl[k];
			m++;
		}
		ck_assert(m > 200);
		sl = (m * sxy - sx * sy) / (m * sxx - sx * sx);
		ic = (sy - sl * sx) / m;
		for (size_t k = 0; k < nc; k++) {
			if (!isfinite(inl_r[k]))
				continue;
			ck_assert_msg(fabs(inl_r[k] - (inl[k] - ic - sl * (double)k) / (1 + sl)) <= tol,
				      "INL[%zu] %.4f vs %.4f", k, inl_r[k],
				      inl[k] - ic - sl * (double)k);
		}
		for (size_t k = 2; k + 1 < nc; k++) {
			w_true[k] = 1 + inl[k + 1] - inl[k];
			mw += w_true[k];
			nw++;
		}
		mw = 1 + sl;
		for (size_t k = 0; k < nc; k++) {
			if (!isfinite(dnl_r[k]))
				continue;
			ck_assert_msg(fabs(dnl_r[k] - (w_true[k] / mw - 1)) <= 2 * tol,
				      "DNL[%zu] %.4f vs %.4f", k, dnl_r[k],
				      w_true[k] / mw - 1);
		}
		ck_assert(nw > 0);
	}
	ck_assert(dmax > 0.3 && imax > 0.3);
	sscope_adc_free(a);
	gsl_rng_free(r);
	free(inl);
	free(x);
	free(y);
	free(dnl_r);
	free(inl_r);
	free(codes);
}
END_TEST

static int spec_err(const char *text, char *msg)
{
	struct ssc_ini *ini = NULL;
	struct sscope_adc_spec s;
	struct sscope_diag d = { "" };
	int rc = ssc_ini_parse(&ini, text, strlen(text), "A.ini", NULL);

	ck_assert_int_eq(rc, 0);
	rc = ssc_adc_spec_from_ini(ini, "adc", &s, &d);
	strcpy(msg, d.msg);
	ssc_ini_free(ini);
	return rc;
}

/*
 * Record length of the histogram test: with random phases a mid-scale
 * code's count is binomial with mean 2 S / (pi n), so its DNL has sd
 * sqrt(pi n / (2 S)); the spread of the measured DNL over the 64 central
 * codes (where the sine density is flat within 3 %) must match it within
 * 4 sd of a sample sd from 64 values (1 / sqrt(126)).  Then the verdict
 * and the formula for the samples needed, and the error codes.
 */
START_TEST(test_histogram_record_length)
{
	const size_t nc = 256, S = 40000;
	int64_t *codes = malloc(S * sizeof(int64_t));
	double *dnl = malloc(nc * sizeof(double)), *inl = malloc(nc * sizeof(double));
	double s2 = 0, want, got;
	struct sscope_adc_hist_quality q;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	ck_assert(codes && dnl && inl && r);
	gsl_rng_set(r, 2385);
	for (size_t i = 0; i < S; i++) {
		double v = 1.02 * sin(2 * PI * gsl_rng_uniform(r));
		double k = floor((v + 1) / 2 * (double)nc);

		codes[i] = k < 0 ? 0 : k > (double)(nc - 1) ? (int64_t)(nc - 1) : (int64_t)k;
	}
	ck_assert_int_eq(sscope_adc_histogram_test(codes, S, nc, dnl, inl, NULL, NULL), 0);
	for (size_t k = nc / 2 - 32; k < nc / 2 + 32; k++)
		s2 += dnl[k] * dnl[k];
	got = sqrt(s2 / 64);
	ck_assert_int_eq(sscope_adc_histogram_quality(codes, S, 0.1, &q), 0);
	ck_assert_uint_eq(q.codes_spanned, nc);
	want = sqrt(PI * (double)nc / (2.0 * (double)S));
	ck_assert(fabs(q.dnl_sd_lsb / want - 1) < 1e-12);
	ck_assert_msg(fabs(got / want - 1) < 4 / sqrt(126.0),
		      "DNL sd %g, predicted %g", got, want);
	/* 156 samples per code: not resolved to 0.1 LSB; the samples needed
	 * are pi n / (2 0.01) */
	ck_assert(!q.resolved);
	ck_assert(q.samples_needed == ceil(PI * (double)nc / 0.02));
	ck_assert_int_eq(sscope_adc_histogram_quality(codes, S, 0.2, &q), 0);
	ck_assert(q.resolved);
	ck_assert_int_eq(sscope_adc_histogram_quality(codes, S, 0, &q), -EINVAL);
	ck_assert_int_eq(sscope_adc_histogram_quality(NULL, S, 0.1, &q), -EINVAL);
	ck_assert_int_eq(sscope_adc_histogram_quality(codes, 0, 0.1, &q), -EINVAL);
	free(codes);
	free(dnl);
	free(inl);
	gsl_rng_free(r);
}
END_TEST

START_TEST(test_spec_errors)
{
	char msg[320];

	ck_assert_int_eq(spec_err("[adc]\nrange = -2.5:2.5 V\n", msg), -EINVAL);
	ck_assert_msg(strstr(msg, "A.ini") && strstr(msg, "bits: missing"), "%s", msg);
	ck_assert_int_eq(spec_err("[adc]\nbits = 16\nrange = -100 deg/s\n", msg), -EINVAL);
	ck_assert_msg(strstr(msg, "range") && strstr(msg, "positive"), "%s", msg);
	ck_assert_int_eq(spec_err("[adc]\nbits = 16\nrange = 5:-5 V\n", msg), -EINVAL);
	ck_assert_msg(strstr(msg, "range") && strstr(msg, "below"), "%s", msg);
	ck_assert_int_eq(spec_err("[adc]\nbits = 16\nrange = -5:5 furlong\n", msg), -EINVAL);
	ck_assert_msg(strstr(msg, "range") && strstr(msg, "furlong"), "%s", msg);
	ck_assert_int_eq(spec_err("[adc]\nbits = 16\nrange = 0:5 V\nnoise = 3 deg/s\n", msg),
			 -EINVAL);
	ck_assert_msg(strstr(msg, "noise"), "%s", msg);
	ck_assert_int_eq(spec_err("[adc]\nbits = 40\nrange = 0:5 V\n", msg), -EINVAL);
	ck_assert_msg(strstr(msg, "bits"), "%s", msg);
	ck_assert_int_eq(spec_err("[adc]\nbits = 16\nrange = 0:5 V\noversample = 0\n", msg),
			 -EINVAL);
	ck_assert_msg(strstr(msg, "oversample"), "%s", msg);
	ck_assert_int_eq(spec_err("[adc]\nbits = 16\nrange = 0:5 V\nwhatever = 1\n", msg),
			 -EINVAL);
	ck_assert_msg(strstr(msg, "whatever"), "%s", msg);
	/* inl_profile: stored as written; refused above the table bits and
	 * next to the bounds it defines */
	ck_assert_int_eq(spec_err("[adc]\nbits = 24\nrange = 0:5 V\ninl_profile = p.txt\n", msg),
			 -EINVAL);
	ck_assert_msg(strstr(msg, "A.ini: line 4: inl_profile") && strstr(msg, "bits <= 20"),
		      "%s", msg);
	ck_assert_int_eq(spec_err("[adc]\nbits = 8\nrange = 0:5 V\ndnl = 0.5\ninl_profile = p.txt\n",
				  msg), -EINVAL);
	ck_assert_msg(strstr(msg, "not both"), "%s", msg);
	ck_assert_int_eq(spec_err("[adc]\nbits = 8\nrange = 0:5 V\ninl_profile = dir/p.txt\n", msg),
			 0);
	{
		struct ssc_ini *ini = NULL;
		struct sscope_adc_spec s;
		const char *t = "[adc]\nbits = 8\nrange = 0:5 V\ninl_profile = dir/p.txt\n";

		ck_assert_int_eq(ssc_ini_parse(&ini, t, strlen(t), "A.ini", NULL), 0);
		ck_assert_int_eq(ssc_adc_spec_from_ini(ini, "adc", &s, NULL), 0);
		ck_assert_str_eq(s.inl_profile, "dir/p.txt");
		ck_assert(!(s.has & SSCOPE_ADC_HAS_INL)); /* the CLI sets it from the file */
		ssc_ini_free(ini);
	}
	/* a good one */
	{
		struct ssc_ini *ini = NULL;
		struct sscope_adc_spec s;
		const char *t = "[adc]\nname = x\nbits = 16\nrange = 0:3.3 V\nrate = 1 kHz\n"
				"noise = 30 uV\ninl = 2 LSB\ndnl = 0.5\n"
				"offset_drift = 2 uV/degC\ngain_drift = 20 ppm/degC\n"
				"reference = ratiometric\nmode = integrate\noversample = 4\n";

		ck_assert_int_eq(ssc_ini_parse(&ini, t, strlen(t), "A.ini", NULL), 0);
		ck_assert_int_eq(ssc_adc_spec_from_ini(ini, "adc", &s, NULL), 0);
		ck_assert(s.analog);
		ck_assert_rel(s.hi, 3.3, 1e-15);
		ck_assert_rel(s.rate_hz, 1000, 1e-15);
		ck_assert_rel(s.noise, 30e-6, 1e-12);
		ck_assert_rel(s.offset_drift, 2e-6, 1e-12);
		ck_assert_rel(s.gain_drift, 20e-6, 1e-12);
		ck_assert_rel(s.inl_lsb, 2, 0);
		ck_assert_int_eq(s.reference, SSCOPE_ADC_RATIOMETRIC);
		ck_assert_int_eq(s.mode, SSCOPE_ADC_INTEGRATE);
		ck_assert_uint_eq(s.oversample, 4);
		ssc_ini_free(ini);
	}
}
END_TEST

static struct sscope_sensor_spec seed_gyro(double arw_deg_sqrt_h)
{
	struct sscope_sensor_spec g;

	memset(&g, 0, sizeof(g));
	g.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	g.has = SSCOPE_SENSOR_HAS_RANGE | SSCOPE_SENSOR_HAS_N | SSCOPE_SENSOR_HAS_B;
	g.range = 100 * DEG;
	g.n = arw_deg_sqrt_h * DEG / 60;
	g.b = 1 * DEG / 3600;
	return g;
}

/* REFERENCE.md word-length table, +-100 deg/s at 100 Hz, and the textbook's
 * verdicts: 16 bits pass for ARW 0.1, fail for 0.005 deg/sqrt(h) */
START_TEST(test_seed_case)
{
	static const struct {
		int bits;
		double lsb_deg_h, arw;
	} tab[] = { { 12, 175.8, 0.0846 }, { 14, 43.9, 0.0211 }, { 16, 10.99, 0.00529 },
		    { 18, 2.75, 0.00132 }, { 20, 0.69, 0.00033 } };
	struct sscope_sensor_spec mems = seed_gyro(0.1), quiet = seed_gyro(0.005);
	struct sscope_adc_analysis r;

	for (size_t i = 0; i < 5; i++) {
		struct sscope_adc_spec s = ideal(tab[i].bits, -100 * DEG, 100 * DEG);
		double lsb, arw;

		ck_assert_int_eq(sscope_adc_analyze(&mems, &s, 100, &r, NULL), 0);
		lsb = r.lsb / DEG * 3600;
		arw = r.n_quant / DEG * 60;
		/* the table's rounding: 4 significant digits, 3 for small ones */
		ck_assert_msg(fabs(lsb - tab[i].lsb_deg_h) <= 0.006 * tab[i].lsb_deg_h,
			      "%d bits: LSB %.4f", tab[i].bits, lsb);
		ck_assert_msg(fabs(arw - tab[i].arw) <= 0.006 * tab[i].arw,
			      "%d bits: ARW_q %.6f", tab[i].bits, arw);
	}
	{
		struct sscope_adc_spec s = ideal(16, -100 * DEG, 100 * DEG);

		ck_assert_int_eq(sscope_adc_analyze(&mems, &s, 100, &r, NULL), 0);
		ck_assert_int_eq(r.verdict, SSCOPE_ADC_PASS);
		ck_assert(r.dithered);
		ck_assert_rel(r.adev_q_100s / DEG * 3600, 0.0317, 0.01);
		ck_assert_int_le(r.min_bits, 16);
		ck_assert_int_eq(sscope_adc_analyze(&quiet, &s, 100, &r, NULL), 0);
		ck_assert_int_eq(r.verdict, SSCOPE_ADC_FAIL);
		ck_assert(!r.dithered);
		ck_assert_rel(r.sigma_over_q, 0.273, 0.01);
		ck_assert_int_eq(r.term[SSCOPE_ADC_T_BIAS].verdict, SSCOPE_ADC_FAIL);
		ck_assert_int_gt(r.min_bits, 16);
		/* at min_bits both word-length terms pass */
		s.bits = r.min_bits;
		ck_assert_int_eq(sscope_adc_analyze(&quiet, &s, 100, &r, NULL), 0);
		ck_assert_int_eq(r.verdict, SSCOPE_ADC_PASS);
		s.bits--;
		ck_assert_int_eq(sscope_adc_analyze(&quiet, &s, 100, &r, NULL), 0);
		ck_assert_int_ne(r.verdict, SSCOPE_ADC_PASS);
	}
	/* oversampling M: conversions at M fs, averaged: sigma/q grows by
	 * sqrt(M) (white sensor noise to M fs/2), q/sqrt(12 M fs) */
	{
		struct sscope_adc_spec s = ideal(16, -100 * DEG, 100 * DEG);
		double q = 200 * DEG / 65536;

		s.oversample = 16;
		ck_assert_int_eq(sscope_adc_analyze(&quiet, &s, 100, &r, NULL), 0);
		ck_assert_rel(r.n_quant, q / sqrt(12 * 1600.0), 1e-12);
		ck_assert_rel(r.sigma_over_q, quiet.n * sqrt(1600.0) / q, 1e-12);
		ck_assert_rel(r.rate_hz, 100, 0);
		ck_assert(r.dithered);
		ck_assert_int_eq(r.verdict, SSCOPE_ADC_PASS);
	}
	/* temperature terms of REFERENCE.md: 2 uV/degC on 6 mV/(deg/s) =
	 * 1.2 deg/h per degC; 20 ppm/degC over 60 degC = 0.12 % */
	{
		struct sscope_adc_spec s = ideal(16, 0, 5);
		struct sscope_sensor_spec g = mems;

		s.analog = true;
		s.quantity = SSCOPE_QUANTITY_VOLTAGE;
		s.offset_drift = 2e-6;
		s.gain_drift = 20e-6;
		g.has |= SSCOPE_SENSOR_HAS_SENSITIVITY | SSCOPE_SENSOR_HAS_ZERO | SSCOPE_SENSOR_HAS_TEMPS;
		g.sensitivity = 6e-3 / DEG;
		g.zero_output_v = 2.5;
		g.temp_min_degc = -10;
		g.temp_max_degc = 50;
		ck_assert_int_eq(sscope_adc_analyze(&g, &s, 100, &r, NULL), 0);
		ck_assert_rel(r.offset_drift_bias / DEG * 3600, 1.2 * 60, 1e-9);
		ck_assert_rel(r.scale_drift, 1.2e-3, 1e-9);
		s.reference = SSCOPE_ADC_RATIOMETRIC;
		ck_assert_int_eq(sscope_adc_analyze(&g, &s, 100, &r, NULL), 0);
		ck_assert(r.scale_drift == 0);
		/* +-2.5 V / 6 mV/(deg/s) = +-416.7 deg/s: 4.17x headroom */
		ck_assert_rel(r.headroom, 2.5 / 6e-3 / 100, 1e-12);
	}
}
END_TEST

/* The Monte-Carlo check of the report, shipped: a dithered sensor (sigma
 * = 1.03 q) through 10 bits over +-100 deg/s at 100 Hz gains white noise
 * q^2/12, so its fitted N grows by sqrt(1 + q^2 / (12 fs N^2)) = 1.0387
 * while B is unchanged and the mean shifts by nothing but the error's
 * mean (sd q / sqrt(12 n)).  The two records share the sensor's noise, so
 * the ratio scatters only through the quantizer's share: about
 * (r^2 - 1) / r^2 / sqrt(2 EDF) ~ 0.3 % per run; 1 % covers 4 sd of the
 * mean over 3 runs.  Student-t intervals must hold the mean, the run-0
 * ADEV curves follow the fits. */
START_TEST(test_monte_carlo)
{
	struct sscope_adc_spec s = ideal(10, -100 * DEG, 100 * DEG);
	struct sscope_sensor_spec ss;
	struct sscope_adc_mc_opts mo = { .runs = 3, .duration_s = 600, .seed = 7,
					  .ci_level = 0.6827, .rate_hz = 100 };
	struct sscope_adc_mc mc;
	struct sscope_diag d = { "" };
	double q = 200 * DEG / 1024, N = 1.03 * q / 10; /* sigma = N sqrt(fs) */
	double want = sqrt(1 + q * q / (12 * 100 * N * N));

	memset(&ss, 0, sizeof(ss));
	ss.quantity = SSCOPE_QUANTITY_ANGULAR_RATE;
	ss.has = SSCOPE_SENSOR_HAS_RANGE | SSCOPE_SENSOR_HAS_N;
	ss.range = 100 * DEG;
	ss.n = N;
	s.rate_hz = 100;
	ck_assert_int_eq(sscope_adc_monte_carlo(&ss, &s, NULL, 0, 1, 0, &mo, &mc, &d), 0);
	ck_assert_uint_eq(mc.runs, 3);
	ck_assert_uint_eq(mc.ratio[0].runs, 3);
	ck_assert_msg(fabs(mc.ratio[0].mean / want - 1) < 0.01,
		      "N ratio %.5f, closed form %.5f", mc.ratio[0].mean, want);
	ck_assert(mc.ratio[0].lo < mc.ratio[0].mean && mc.ratio[0].mean < mc.ratio[0].hi);
	ck_assert(fabs(mc.bias_shift.mean) < 4 * q / sqrt(12 * 60000.0));
	ck_assert_uint_eq(mc.clipped, 0);
	ck_assert_rel(mc.duration_s, 600, 1e-15);
	ck_assert_uint_ge(mc.n_points, 10);
	/* at tau = 1 s the ADEV through the converter is up by about the N ratio */
	for (size_t i = 0; i < mc.n_points; i++)
		if (fabs(mc.tau_s[i] - 1) < 1e-9)
			ck_assert_msg(fabs(mc.dev_out[i] / mc.dev_in[i] / want - 1) < 0.02,
				      "ADEV ratio at 1 s %.4f", mc.dev_out[i] / mc.dev_in[i]);
	/* every run's curves are kept; the band over the runs: the median of
	 * three values is the middle one, the 10 and 90 % points interpolate
	 * towards the ends */
	ck_assert_uint_eq(mc.n_runs, 3);
	{
		size_t np = mc.n_points, i = np / 2;
		double qb[3], v[3], t;

		for (int r = 0; r < 3; r++)
			v[r] = mc.dev_out[r * np + i] / mc.dev_in[r * np + i];
		for (int a = 0; a < 2; a++) /* sort three */
			for (int b = 0; b < 2 - a; b++)
				if (v[b] > v[b + 1]) {
					t = v[b];
					v[b] = v[b + 1];
					v[b + 1] = t;
				}
		ck_assert_int_eq(sscope_adc_mc_band(&mc, SSCOPE_ADC_MC_RATIO, i, qb), 0);
		ck_assert(qb[1] == v[1]);
		ck_assert_rel(qb[0], v[0] + 0.2 * (v[1] - v[0]), 1e-12);
		ck_assert_rel(qb[2], v[1] + 0.8 * (v[2] - v[1]), 1e-12);
		ck_assert_int_eq(sscope_adc_mc_band(&mc, SSCOPE_ADC_MC_ALONE, np, qb), -EINVAL);
	}
	sscope_adc_mc_clear(&mc);
	sscope_adc_mc_clear(&mc); /* twice is harmless */
	/* errors */
	mo.duration_s = 5; /* 500 samples */
	ck_assert_int_eq(sscope_adc_monte_carlo(&ss, &s, NULL, 0, 1, 0, &mo, &mc, &d), -EDOM);
	ck_assert_ptr_nonnull(strstr(d.msg, "need 1000"));
	mo.duration_s = 600;
	mo.runs = 0;
	ck_assert_int_eq(sscope_adc_monte_carlo(&ss, &s, NULL, 0, 1, 0, &mo, &mc, &d), -EINVAL);
}
END_TEST

/* Ranking: pass before marginal before fail; the fewest bits among the
 * passing ones; else the larger margin, infinite for a non-finite one;
 * stable. */
/* Ideal codes of decoded values: decoding lo + k q and encoding again
 * gives k back, code k spans k -+ q/2 (mid-tread), values beyond
 * the range are clamped and counted, bad input is refused. */
START_TEST(test_codes)
{
	enum { NC = 4096 };
	const double lo = -2.385, hi = 3.117, q = (hi - lo) / NC;
	static double x[NC];
	static int64_t k[NC];
	double edge[4] = { lo - 0.49 * q, lo + 0.51 * q, hi + 10 * q, lo - 10 * q };
	int64_t ke[4];
	size_t clipped = 99;

	for (size_t i = 0; i < NC; i++)
		x[i] = lo + (double)i * q;
	ck_assert_int_eq(sscope_adc_codes(x, 1, NC, lo, hi, NC, k, &clipped), 0);
	for (size_t i = 0; i < NC; i++)
		ck_assert_int_eq(k[i], (int64_t)i);
	ck_assert_uint_eq(clipped, 0);
	/* every other sample through a stride */
	ck_assert_int_eq(sscope_adc_codes(x, 2, NC / 2, lo, hi, NC, k, NULL), 0);
	ck_assert_int_eq(k[NC / 2 - 1], NC - 2);
	ck_assert_int_eq(sscope_adc_codes(edge, 1, 4, lo, hi, NC, ke, &clipped), 0);
	ck_assert_int_eq(ke[0], 0);
	ck_assert_int_eq(ke[1], 1);
	ck_assert_int_eq(ke[2], NC - 1);
	ck_assert_int_eq(ke[3], 0);
	ck_assert_uint_eq(clipped, 2);
	ck_assert_int_eq(sscope_adc_codes(x, 1, NC, hi, lo, NC, k, NULL), -EINVAL);
	ck_assert_int_eq(sscope_adc_codes(x, 0, NC, lo, hi, NC, k, NULL), -EINVAL);
	ck_assert_int_eq(sscope_adc_codes(x, 1, NC, lo, hi, 1, k, NULL), -EINVAL);
	ck_assert_int_eq(sscope_adc_codes(NULL, 1, NC, lo, hi, NC, k, NULL), -EINVAL);
	x[7] = NAN;
	ck_assert_int_eq(sscope_adc_codes(x, 1, NC, lo, hi, NC, k, NULL), -EDOM);
}
END_TEST

START_TEST(test_rank)
{
	struct sscope_adc_analysis an[5];
	int bits[5] = { 18, 16, 12, 16, 14 };
	size_t order[5];

	memset(an, 0, sizeof(an));
	an[0].verdict = SSCOPE_ADC_PASS;
	an[0].margin = 9;
	an[1].verdict = SSCOPE_ADC_PASS;
	an[1].margin = 1.2;
	an[2].verdict = SSCOPE_ADC_FAIL;
	an[2].margin = 0.1;
	an[3].verdict = SSCOPE_ADC_MARGINAL;
	an[3].margin = 0.8;
	an[4].verdict = SSCOPE_ADC_MARGINAL;
	an[4].margin = NAN;
	sscope_adc_rank(an, bits, 5, order);
	ck_assert_uint_eq(order[0], 1); /* 16 bits pass: the cheapest */
	ck_assert_uint_eq(order[1], 0);
	ck_assert_uint_eq(order[2], 4); /* marginal, margin unknown: infinite */
	ck_assert_uint_eq(order[3], 3);
	ck_assert_uint_eq(order[4], 2);
	/* equal keys keep their order */
	bits[0] = 16;
	an[0].margin = 1.2;
	sscope_adc_rank(an, bits, 2, order);
	ck_assert_uint_eq(order[0], 0);
	ck_assert_uint_eq(order[1], 1);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("adc");
	TCase *tc = tcase_create("adc");

	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, test_sqnr);
	tcase_add_test(tc, test_avar_round);
	tcase_add_test(tc, test_avar_integrate);
	tcase_add_test(tc, test_dither_bound);
	tcase_add_test(tc, test_enob_ideal);
	tcase_add_test(tc, test_thd);
	tcase_add_test(tc, test_histogram);
	tcase_add_test(tc, test_histogram_record_length);
	tcase_add_test(tc, test_spec_errors);
	tcase_add_test(tc, test_seed_case);
	tcase_add_test(tc, test_monte_carlo);
	tcase_add_test(tc, test_rank);
	tcase_add_test(tc, test_codes);
	suite_add_tcase(s, tc);
	return s;
}
