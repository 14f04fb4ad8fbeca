/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Machinery vibration analysis.
 *
 * - Severity: velocity RMS in the ISO 10816-1 band (10-1000 Hz) by
 *   frequency-domain integration of the acceleration PSD (each bin's
 *   density divided by (2 pi f)^2, integrated exactly over the bin), and
 *   the zone of ISO 10816-1:1995 Annex B (Table B.1; shipped below as
 *   data).
 * - Shaft orders 1x..3x from the Welch spectrum with the exact sub-bin
 *   interpolation of psd.c; unbalance = dominant 1x, misalignment =
 *   strong 2x (the classical rules of machinery diagnostics, e.g. ISO
 *   13373-3:2015 annex tables; J. S. Mitchell, "Introduction to Machinery
 *   Analysis and Monitoring", 1993).
 * - Bearings: defect frequencies BPFO, BPFI, BSF, FTF from the kinematics
 *   (T. A. Harris, "Rolling Bearing Analysis"); envelope analysis (R. B.
 *   Randall and J. Antoni, "Rolling element bearing diagnostics -- a
 *   tutorial", MSSP 25(2), 2011): band-pass and Hilbert transform in one
 *   inverse FFT (FFTW), the band chosen by the largest spectral kurtosis
 *   of the complex envelope over a dyadic and half-shifted band tree (a
 *   coarse form of J. Antoni's fast kurtogram, MSSP 21(1), 2007), and the
 *   envelope's Welch spectrum searched for the defect harmonics within a
 *   slip tolerance.  A line counts when it exceeds its local median floor
 *   by a Gamma quantile for the number of averaged segments (false-alarm
 *   probability 1e-3 per bin).
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <fftw3.h>
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_sort.h>
#include <gsl/gsl_statistics_double.h>

#include "sscope-vib.h"
#include "sscope-psd.h"


/* ------------------------------------------------------------ bearings */

int sscope_vib_bearing_frequencies(const struct sscope_vib_bearing *b, double fr,
				   struct sscope_vib_bearing_freqs *f)
{
	double r;

	if (!b || !f || b->n_elements == 0 || !(b->ball_diameter_m > 0) ||
	    !(b->pitch_diameter_m > b->ball_diameter_m) ||
	    !(b->contact_angle_rad >= 0) || !(b->contact_angle_rad < PI / 2) ||
	    !(fr > 0) || !isfinite(fr) || !isfinite(b->pitch_diameter_m))
		return -EINVAL;
	r = b->ball_diameter_m / b->pitch_diameter_m * cos(b->contact_angle_rad);
	f->bpfo_hz = b->n_elements / 2.0 * fr * (1 - r);
	f->bpfi_hz = b->n_elements / 2.0 * fr * (1 + r);
	f->bsf_hz = b->pitch_diameter_m / (2 * b->ball_diameter_m) * fr *
		    (1 - r * r);
	f->ftf_hz = fr / 2 * (1 - r);
	return 0;
}

/* ------------------------------------------------------------ ISO zones */

/*
 * ISO 10816-1:1995, Annex B (informative), Table B.1: typical zone
 * boundaries, velocity RMS in mm/s over 10-1000 Hz, for the machine
 * classes of Annex B.  These are the values as commonly reproduced from
 * that edition; public copies differ in places, and ISO 20816-1:2016
 * replaces it: users should check the boundaries against their own copy
 * of the standard that applies to their machine.
 */
static const double iso_table_mm_s[4][3] = {
	{ 0.71, 1.8, 4.5 },  /* class I */
	{ 1.12, 2.8, 7.1 },  /* class II */
	{ 1.8, 4.5, 11.2 },  /* class III */
	{ 2.8, 7.1, 18.0 },  /* class IV */
};

const char *sscope_vib_iso_edition(void)
{
	return "ISO 10816-1:1995 Annex B, Table B.1 (typical zone boundaries; "
	       "check against your copy)";
}

int sscope_vib_iso_limits(enum sscope_vib_iso_class c, double lim[3])
{
	if (c < SSCOPE_VIB_ISO_I || c > SSCOPE_VIB_ISO_IV || !lim)
		return -EINVAL;
	for (int i = 0; i < 3; i++)
		lim[i] = iso_table_mm_s[c - SSCOPE_VIB_ISO_I][i] / 1000;
	return 0;
}

int sscope_vib_iso_zone(enum sscope_vib_iso_class c, double v, char *zone)
{
	double lim[3];

	if (!zone || !(v >= 0) || sscope_vib_iso_limits(c, lim))
		return -EINVAL;
	*zone = v < lim[0] ? 'A' : v < lim[1] ? 'B' : v < lim[2] ? 'C' : 'D';
	return 0;
}

/* ------------------------------------------------------------ velocity */

int sscope_vib_velocity_ms(const struct sscope_psd_spectrum *s, double lo, double hi,
			   double *ms)
{
	struct ssc_ksum acc = { 0, 0 };
	double nyq, df, conv;

	if (!s || !ms || !s->value || !(lo > 0) || !(hi >= lo))
		return -EINVAL;
	nyq = s->fs_hz / 2;
	df = s->bin_hz;
	conv = s->scaling == SSCOPE_PSD_SCALING_SPECTRUM ? 1 / s->enbw_hz : 1;
	for (size_t k = 0; k < s->n_bins; k++) {
		double a = s->freq_hz[k] - df / 2, b = s->freq_hz[k] + df / 2;
		double oa, ob, dens;

		a = a < 0 ? 0 : a;
		b = b > nyq ? nyq : b;
		oa = a > lo ? a : lo;
		ob = b < hi ? b : hi;
		if (!(ob > oa) || !(b > a))
			continue;
		/* the bin's power spread evenly over [a, b] */
		dens = s->value[k] * conv * df / (b - a);
		ssc_ksum_add(&acc, dens / (4 * PI * PI) * (1 / oa - 1 / ob));
	}
	*ms = ssc_ksum_value(&acc);
	return 0;
}

/* ------------------------------------------------------------ kurtosis */

int sscope_vib_kurtosis(const double *x, size_t stride, size_t n, double *kurt)
{
	struct ssc_ksum s = { 0, 0 }, s2 = { 0, 0 }, s4 = { 0, 0 };
	double mean, m2, m4, amax = 0, sc = 1;
	int e;

	if (!x || !kurt || stride == 0)
		return -EINVAL;
	if (n < 4)
		return -EDOM;
	for (size_t i = 0; i < n; i++) {
		if (!isfinite(x[i * stride]))
			return -EDOM;
		amax = fmax(amax, fabs(x[i * stride]));
	}
	/* 4th powers leave the double range beyond 2^+-250: a power of two
	 * (exact; the ratio does not change) brings the samples near 1 */
	if (amax > 0 && (amax > 0x1p120 || amax < 0x1p-120)) {
		frexp(amax, &e);
		sc = ldexp(1.0, -e);
	}
	for (size_t i = 0; i < n; i++)
		ssc_ksum_add(&s, x[i * stride] * sc);
	mean = ssc_ksum_value(&s) / (double)n;
	for (size_t i = 0; i < n; i++) {
		double d = x[i * stride] * sc - mean, d2 = d * d;

		ssc_ksum_add(&s2, d2);
		ssc_ksum_add(&s4, d2 * d2);
	}
	m2 = ssc_ksum_value(&s2) / (double)n;
	m4 = ssc_ksum_value(&s4) / (double)n;
	if (!(m2 > 0))
		return -EDOM;
	*kurt = m4 / (m2 * m2);
	return 0;
}

/* ------------------------------------------------------------ envelope */

struct sscope_vib_envelope {
	size_t n;
	double *xin;
	fftw_complex *X; /* n/2 + 1 */
	fftw_complex *z; /* n, in place */
	fftw_plan fwd, inv;
	double energy; /* sum of |X|^2 over the positive frequencies */
	bool set;
};

void sscope_vib_envelope_free(struct sscope_vib_envelope *e)
{
	if (!e)
		return;
	if (e->fwd)
		fftw_destroy_plan(e->fwd);
	if (e->inv)
		fftw_destroy_plan(e->inv);
	fftw_free(e->xin);
	fftw_free(e->X);
	fftw_free(e->z);
	free(e);
}

int sscope_vib_envelope_new(struct sscope_vib_envelope **out, size_t n)
{
	struct sscope_vib_envelope *e;

	if (!out)
		return -EINVAL;
	*out = NULL;
	if (n < 4 || n > INT32_MAX)
		return -EINVAL;
	e = calloc(1, sizeof(*e));
	if (!e)
		return -ENOMEM;
	e->n = n;
	e->xin = fftw_alloc_real(n);
	e->X = fftw_alloc_complex(n / 2 + 1);
	e->z = fftw_alloc_complex(n);
	if (!e->xin || !e->X || !e->z)
		goto nomem;
	e->fwd = fftw_plan_dft_r2c_1d((int)n, e->xin, e->X, FFTW_ESTIMATE);
	e->inv = fftw_plan_dft_1d((int)n, e->z, e->z, FFTW_BACKWARD,
				  FFTW_ESTIMATE);
	if (!e->fwd || !e->inv)
		goto nomem;
	*out = e;
	return 0;
nomem:
	sscope_vib_envelope_free(e);
	return -ENOMEM;
}

int sscope_vib_envelope_set(struct sscope_vib_envelope *e, const double *x,
			    size_t stride)
{
	if (!e || !x || stride == 0)
		return -EINVAL;
	for (size_t i = 0; i < e->n; i++) {
		if (!isfinite(x[i * stride]))
			return -EDOM;
		e->xin[i] = x[i * stride];
	}
	fftw_execute(e->fwd);
	e->energy = 0;
	for (size_t k = 0; k <= e->n / 2; k++)
		e->energy += e->X[k][0] * e->X[k][0] + e->X[k][1] * e->X[k][1];
	e->set = true;
	return 0;
}

int sscope_vib_envelope_band(struct sscope_vib_envelope *e, double fs, double lo,
			     double hi, double *env, double *sk)
{
	size_t n, half, k0, k1;
	struct ssc_ksum s2 = { 0, 0 }, s4 = { 0, 0 };
	double m2, m4;

	if (!e || !e->set || !(fs > 0) || !(lo >= 0) || !(hi > lo) ||
	    hi > fs / 2 * (1 + 1e-12))
		return -EINVAL;
	n = e->n;
	half = n / 2;
	k0 = (size_t)ceil(lo * (double)n / fs);
	k1 = (size_t)floor(hi * (double)n / fs);
	if (k1 > half)
		k1 = half;
	if (k1 < k0)
		return -EINVAL;
	memset(e->z, 0, n * sizeof(fftw_complex));
	for (size_t k = k0; k <= k1; k++) {
		/* the analytic signal: positive frequencies doubled, DC and
		 * Nyquist kept once */
		double g = (k == 0 || (n % 2 == 0 && k == half)) ? 1 : 2;

		e->z[k][0] = g * e->X[k][0];
		e->z[k][1] = g * e->X[k][1];
	}
	fftw_execute(e->inv);
	for (size_t i = 0; i < n; i++) {
		double re = e->z[i][0] / (double)n, im = e->z[i][1] / (double)n;
		double p = re * re + im * im;

		if (env)
			env[i] = sqrt(p);
		ssc_ksum_add(&s2, p);
		ssc_ksum_add(&s4, p * p);
	}
	m2 = ssc_ksum_value(&s2) / (double)n;
	m4 = ssc_ksum_value(&s4) / (double)n;
	/* below the rounding of the transform: no energy in the band */
	if (!(m2 * (double)n > 1e-20 * 4 * e->energy / (double)n))
		return -EDOM;
	if (sk)
		*sk = m4 / (m2 * m2) - 2;
	return 0;
}

/* ------------------------------------------------------------ analysis */

void sscope_vib_opts_init(struct sscope_vib_opts *o)
{
	memset(o, 0, sizeof(*o));
}

size_t sscope_vib_default_nperseg(size_t n)
{
	size_t m = 256;

	if (n <= 256)
		return n;
	while (m * 2 <= 65536 && m * 2 * 9 / 2 <= n)
		m *= 2; /* 2m with half overlap: (n - m) / m >= 8 segments */
	return m;
}

void sscope_vib_result_clear(struct sscope_vib_result *r)
{
	if (!r)
		return;
	sscope_psd_spectrum_clear(&r->accel);
	sscope_psd_spectrum_clear(&r->envelope);
}

static void add_finding(struct sscope_vib_result *r, const char *finding,
			const char *evidence)
{
	struct sscope_vib_finding *f;

	if (r->n_findings >= SSCOPE_VIB_FINDINGS)
		return;
	f = &r->findings[r->n_findings++];
	snprintf(f->finding, sizeof(f->finding), "%s", finding);
	snprintf(f->evidence, sizeof(f->evidence), "%s", evidence);
}

/* median of a spectrum around bin k (excluding the peak) */
static double local_floor(const struct sscope_psd_spectrum *s, size_t k)
{
	double buf[64];
	size_t n = 0, lo = k > 26 ? k - 26 : 1;

	for (size_t j = lo; j < s->n_bins && j <= k + 26 && n < 64; j++)
		if (j + 3 <= k || j >= k + 3)
			buf[n++] = s->value[j];
	if (n == 0)
		return (double)NAN;
	gsl_sort(buf, 1, n);
	return gsl_stats_median_from_sorted_data(buf, 1, n);
}

/* A line's threshold over the local median: a Welch average of K
 * segments holds at each bin of noise a mean of K_eff exponential
 * variates (Hann, 50 % overlap: K_eff = K / (1 + 2 * 0.167^2), Welch
 * 1967); the threshold is its 1 - 1e-3 quantile over its median. */
static double line_threshold(size_t n_segments)
{
	double keff = (double)n_segments / (1 + 2 * 0.167 * 0.167);

	if (keff < 1)
		keff = 1;
	return gsl_cdf_gamma_Qinv(1e-3, keff, 1 / keff) /
	       gsl_cdf_gamma_Pinv(0.5, keff, 1 / keff);
}

static void orders_findings(struct sscope_vib_result *r, double gate)
{
	const struct sscope_vib_order *o1 = &r->orders[0], *o2 = &r->orders[1];
	double v = r->velocity_rms_m_s, v1, v2;
	char ev[400];

	if (r->n_orders < 2 || !(v > 0))
		return;
	v1 = o1->found ? o1->velocity_rms_m_s : 0;
	v2 = o2->found ? o2->velocity_rms_m_s : 0;
	if (v < gate)
		return; /* zones A and B: acceptable, nothing to act on */
	if (o1->found && v1 * v1 >= 0.5 * v * v && v2 < 0.5 * v1) {
		int w = snprintf(ev, sizeof(ev),
				 "1x = %.3g mm/s rms at %.2f Hz carries %.0f %% "
				 "of the velocity power (overall %.3g mm/s, "
				 "%g-%g Hz); ",
				 v1 * 1e3, o1->peak.frequency_hz,
				 100 * v1 * v1 / (v * v), v * 1e3,
				 r->iso_lo_hz, r->iso_hi_hz);

		if (w > 0 && (size_t)w < sizeof(ev)) {
			if (o2->found)
				snprintf(ev + w, sizeof(ev) - (size_t)w,
					 "2x = %.3g mm/s (%.0f %% of 1x)",
					 v2 * 1e3, 100 * v2 / v1);
			else
				snprintf(ev + w, sizeof(ev) - (size_t)w,
					 "no 2x line above the noise");
		}
		add_finding(r, "unbalance", ev);
	}
	if (o2->found && v2 >= 0.5 * v1 && v2 * v2 >= 0.2 * v * v) {
		snprintf(ev, sizeof(ev),
			 "2x = %.3g mm/s rms at %.2f Hz is %.0f %% of 1x "
			 "(%.3g mm/s) and carries %.0f %% of the velocity power "
			 "(overall %.3g mm/s); check the axial 1x too",
			 v2 * 1e3, o2->peak.frequency_hz,
			 v1 > 0 ? 100 * v2 / v1 : (double)INFINITY, v1 * 1e3,
			 100 * v2 * v2 / (v * v), v * 1e3);
		add_finding(r, "misalignment", ev);
	}
}

struct defect {
	const char *name;   /* label base */
	const char *finding;
	double f;
};

static double match_tol(const struct sscope_vib_opts *o, double f,
			double bin)
{
	double t = o->tolerance * f;

	return t > 1.5 * bin ? t : 1.5 * bin;
}

/* The defect (index < nd) or shaft harmonic (index nd) closest to f
 * within its tolerance, relative to that tolerance; false when none. */
static bool best_match(double f, const struct defect *d, size_t nd, double fr,
		       const struct sscope_vib_opts *o, double bin, size_t *idx,
		       unsigned *harm)
{
	double best = (double)INFINITY;

	for (size_t i = 0; i <= nd; i++) {
		double base = i < nd ? d[i].f : fr;

		for (unsigned h = 1; h <= 10; h++) {
			double e = h * base, q = fabs(f - e) / match_tol(o, e, bin);

			if (q > 1 || q >= best)
				continue;
			best = q;
			*idx = i;
			*harm = h;
		}
	}
	return best <= 1;
}

/* Label an envelope peak with the closest defect or shaft harmonic. */
static void label_peak(struct sscope_vib_env_peak *ep,
		       const struct defect *d, size_t nd, double fr,
		       const struct sscope_vib_opts *o, double bin)
{
	size_t i;
	unsigned h;

	ep->match[0] = '\0';
	ep->expected_hz = (double)NAN;
	if (!best_match(ep->peak.frequency_hz, d, nd, fr, o, bin, &i, &h))
		return;
	ep->expected_hz = h * (i < nd ? d[i].f : fr);
	if (i == nd)
		snprintf(ep->match, sizeof(ep->match), "%ux", h);
	else if (h == 1)
		snprintf(ep->match, sizeof(ep->match), "%s", d[i].name);
	else
		snprintf(ep->match, sizeof(ep->match), "%ux%s", h, d[i].name);
}

static int bearing_analysis(const double *x, size_t stride, size_t n,
			    double fs, const struct sscope_vib_opts *o,
			    struct sscope_vib_result *r,
			    struct sscope_diag *diag)
{
	const struct sscope_vib_bearing_freqs *bf = &r->bearing;
	const double fr = o->shaft_hz, nyq = fs / 2;
	struct defect d[4] = {
		{ "BPFO", "outer-race defect", bf->bpfo_hz },
		{ "BPFI", "inner-race defect", bf->bpfi_hz },
		{ "BSF", "rolling-element defect", bf->bsf_hz },
		{ "FTF", "cage defect", bf->ftf_hz },
	};
	struct sscope_vib_envelope *e = NULL;
	struct sscope_psd_opts po;
	double *env = NULL, fhigh = 0, lo = o->env_lo_hz, hi = o->env_hi_hz;
	double thr, res, fmin_env, fmax_env;
	int rc;

	for (int i = 0; i < 4; i++)
		fhigh = fmax(fhigh, d[i].f * (i == 2 ? 2 : 1));
	rc = sscope_vib_envelope_new(&e, n);
	if (rc)
		return rc == -EINVAL ?
			       ssc_diag(diag, -EDOM,
					"record too short for envelope analysis (%zu samples)",
					n) :
			       rc;
	rc = sscope_vib_envelope_set(e, x, stride);
	if (rc)
		goto out;
	if (!(lo > 0 || hi > 0)) {
		/* the band of largest spectral kurtosis among dyadic bands
		 * and bands shifted by half their width, wide enough (3x the
		 * highest defect frequency) and above it (2x) */
		double best = -(double)INFINITY;

		for (int level = 1; level <= 6; level++) {
			double w = nyq / (double)(1 << level);

			if (w < 3 * fhigh)
				break;
			for (int half = 0; half < 2; half++)
				for (double a = half * w / 2; a + w <= nyq * (1 + 1e-12);
				     a += w) {
					double sk;

					if (a < 2 * fhigh)
						continue;
					if (sscope_vib_envelope_band(e, fs, a,
								     fmin(a + w, nyq),
								     NULL, &sk))
						continue;
					if (sk > best) {
						best = sk;
						lo = a;
						hi = fmin(a + w, nyq);
					}
				}
		}
		if (!(best > -(double)INFINITY)) {
			lo = 2 * fhigh;
			hi = 0.95 * nyq;
			if (hi - lo < 3 * fhigh) {
				rc = ssc_diag(diag, -EDOM,
					      "sample rate %g Hz too low for envelope analysis of defect frequencies up to %.1f Hz",
					      fs, fhigh);
				goto out;
			}
		}
	}
	if (!(hi > lo) || hi > nyq * (1 + 1e-12) || lo < 0) {
		rc = ssc_diag(diag, -EINVAL,
			      "envelope band %g-%g Hz is not inside 0-%g Hz",
			      lo, hi, nyq);
		goto out;
	}
	env = ssc_alloc_array(n, sizeof(double));
	if (!env) {
		rc = -ENOMEM;
		goto out;
	}
	rc = sscope_vib_envelope_band(e, fs, lo, hi, env, &r->env_sk);
	if (rc) {
		rc = ssc_diag(diag, -EDOM, "no signal in the envelope band %g-%g Hz",
			      lo, hi);
		goto out;
	}
	r->env_lo_hz = lo;
	r->env_hi_hz = hi;
	/* envelope spectrum: resolution a quarter of the lowest frequency
	 * of interest (cage or shaft) */
	res = fmin(bf->ftf_hz, fr) / 4;
	sscope_psd_opts_init(&po);
	po.scaling = SSCOPE_PSD_SCALING_SPECTRUM;
	po.nperseg = 256;
	while (po.nperseg < n && fs / (double)po.nperseg > res &&
	       po.nperseg < ((size_t)1 << 24))
		po.nperseg *= 2;
	po.shorten = true;
	po.threads = o->psd.threads;
	rc = sscope_psd_welch(env, 1, n, fs, &po, &r->envelope);
	if (rc)
		goto out;
	/* noise threshold at a false-alarm probability of 1e-3 per bin */
	thr = line_threshold(r->envelope.n_segments);
	r->env_threshold = thr;
	/* strongest envelope lines, labelled */
	fmin_env = fmax(2 * r->envelope.bin_hz, 0.5 * fmin(fr, bf->ftf_hz));
	fmax_env = fmin(hi - lo, 5.5 * fhigh);
	{
		struct sscope_psd_peak pk[SSCOPE_VIB_ENV_PEAKS];
		size_t np;

		sscope_psd_spectrum_peaks(&r->envelope, SSCOPE_VIB_ENV_PEAKS,
					  fmin_env, fmax_env, pk, &np);
		for (size_t i = 0; i < np; i++) {
			struct sscope_vib_env_peak *ep = &r->env_peaks[i];

			ep->peak = pk[i];
			ep->snr = pk[i].value / local_floor(&r->envelope, pk[i].bin);
			label_peak(ep, d, 4, fr, o, r->envelope.bin_hz);
		}
		r->n_env_peaks = np;
	}
	/* findings: the fundamental of a defect frequency (1x or 2x for the
	 * ball spin) and at least one more harmonic above threshold, each
	 * line closer to that harmonic than to any other defect or shaft
	 * harmonic (BPFO + BPFI = n fr makes harmonics of the two meet) */
	for (int i = 0; i < 4; i++) {
		char ev[400], *p = ev;
		size_t left = sizeof(ev), mi;
		unsigned count = 0, mh;
		bool fund = false;

		for (unsigned h = 1; h <= 5; h++) {
			struct sscope_psd_peak pk;
			double fe = h * d[i].f, snr;
			int w;

			if (fe > fmax_env)
				break;
			if (sscope_psd_spectrum_peak_near(&r->envelope, fe,
							  match_tol(o, fe, r->envelope.bin_hz),
							  &pk))
				continue;
			snr = pk.value / local_floor(&r->envelope, pk.bin);
			if (!(snr >= thr) ||
			    !best_match(pk.frequency_hz, d, 4, fr, o,
					r->envelope.bin_hz, &mi, &mh) ||
			    mi != (size_t)i || mh != h)
				continue;
			count++;
			fund = fund || h == 1 || (i == 2 && h == 2);
			if (h == 1)
				w = snprintf(p, left, "%s%.2f Hz (%s %.2f Hz, %.0fx floor)",
					     count > 1 ? ", " : "", pk.frequency_hz,
					     d[i].name, fe, snr);
			else
				w = snprintf(p, left, "%s%.2f Hz (%ux%s, %.0fx floor)",
					     count > 1 ? ", " : "", pk.frequency_hz,
					     h, d[i].name, snr);
			if (w > 0 && (size_t)w < left) {
				p += w;
				left -= (size_t)w;
			}
		}
		if (count < 2 || !fund)
			continue;
		if (i == 1 && left > 1) {
			/* inner race: sidebands at +-1x (load modulation) */
			struct sscope_psd_peak a, b;
			double tol = match_tol(o, fr, r->envelope.bin_hz);
			bool sa = !sscope_psd_spectrum_peak_near(&r->envelope, d[1].f - fr, tol, &a) &&
				  a.value / local_floor(&r->envelope, a.bin) >= thr;
			bool sb = !sscope_psd_spectrum_peak_near(&r->envelope, d[1].f + fr, tol, &b) &&
				  b.value / local_floor(&r->envelope, b.bin) >= thr;
			int w = snprintf(p, left, "; sidebands at BPFI -+1x: %s",
					 sa && sb ? "both" : sa || sb ? "one" : "none");

			if (w > 0 && (size_t)w < left) {
				p += w;
				left -= (size_t)w;
			}
		}
		snprintf(p, left,
			 "; envelope of %.0f-%.0f Hz (spectral kurtosis %.2f), "
			 "threshold %.1fx floor, kurtosis %.2f",
			 lo, hi, r->env_sk, thr, r->kurtosis);
		add_finding(r, d[i].finding, ev);
	}
	rc = 0;
out:
	free(env);
	sscope_vib_envelope_free(e);
	return rc;
}

int sscope_vib_analyze(const double *x, size_t stride, size_t n,
		       double fs, const struct sscope_vib_opts *o,
		       struct sscope_vib_result *r,
		       struct sscope_diag *diag)
{
	struct sscope_vib_opts def;
	struct sscope_psd_opts po;
	double lim[3], ms, hi;
	int rc;

	if (o) { /* zeros ask for the defaults */
		def = *o;
		if (def.iso_lo_hz == 0 && def.iso_hi_hz == 0) {
			def.iso_lo_hz = 10;
			def.iso_hi_hz = 1000;
		}
		if (def.tolerance == 0)
			def.tolerance = 0.02;
		else if (def.tolerance < 0)
			def.tolerance = 0;
		if (def.n_peaks == 0)
			def.n_peaks = 5;
		else if (def.n_peaks == SSCOPE_VIB_NO_PEAKS)
			def.n_peaks = 0;
		o = &def;
	}
	if (!x || !o || !r || stride == 0 || !(fs > 0) || !isfinite(fs) ||
	    !(o->tolerance >= 0) || !(o->iso_lo_hz > 0) ||
	    !(o->iso_hi_hz > o->iso_lo_hz) || o->shaft_hz < 0 ||
	    (o->iso_class != SSCOPE_VIB_ISO_NONE && sscope_vib_iso_limits(o->iso_class, lim)))
		return ssc_diag(diag, -EINVAL, "bad vibration options");
	memset(r, 0, sizeof(*r));
	/* the velocity band must start below the Nyquist frequency */
	if (!(fs / 2 > o->iso_lo_hz))
		return ssc_diag(diag, -EDOM,
				"a rate of %g Hz shows nothing of the velocity band (%g to %g Hz): its Nyquist frequency is %g Hz; vibration needs a rate above %g Hz (%g Hz for the whole band)",
				fs, o->iso_lo_hz, o->iso_hi_hz, fs / 2, 2 * o->iso_lo_hz,
				2 * o->iso_hi_hz);
	if (n < 16)
		return ssc_diag(diag, -EDOM,
				"%zu samples: too short for vibration analysis",
				n);
	/* the envelope's kurtosis takes 4th powers of the analytic signal */
	rc = ssc_magnitude_check(x, stride, n, 120, "vibration", diag);
	if (rc)
		return rc;
	rc = sscope_vib_kurtosis(x, stride, n, &r->kurtosis);
	if (rc)
		return ssc_diag(diag, rc, "%s",
				"the record is constant or holds a non-finite sample");
	po = o->psd;
	if (!po.nperseg)
		po.nperseg = sscope_vib_default_nperseg(n);
	po.shorten = true;
	rc = sscope_psd_welch(x, stride, n, fs, &po, &r->accel);
	if (rc)
		return ssc_diag(diag, rc, "spectrum: %s", sscope_strerror(rc));
	r->accel_rms_m_s2 = r->accel.rms;
	hi = fmin(o->iso_hi_hz, fs / 2);
	r->iso_lo_hz = o->iso_lo_hz;
	r->iso_hi_hz = hi;
	r->velocity_rms_m_s = (double)NAN;
	if (hi > o->iso_lo_hz && !sscope_vib_velocity_ms(&r->accel, o->iso_lo_hz, hi, &ms))
		r->velocity_rms_m_s = sqrt(ms);
	if (o->iso_class != SSCOPE_VIB_ISO_NONE && isfinite(r->velocity_rms_m_s))
		sscope_vib_iso_zone(o->iso_class, r->velocity_rms_m_s, &r->zone);
	{
		size_t np = o->n_peaks < 16 ? o->n_peaks : 16;

		sscope_psd_spectrum_peaks(&r->accel, np, 0, fs / 2, r->peaks,
					  &r->n_peaks);
	}
	if (o->shaft_hz > 0) {
		double thr = line_threshold(r->accel.n_segments);

		for (unsigned k = 1; k <= SSCOPE_VIB_ORDERS; k++) {
			struct sscope_vib_order *od = &r->orders[k - 1];
			double f = k * o->shaft_hz;

			od->order = k;
			od->expected_hz = f;
			od->velocity_rms_m_s = (double)NAN;
			if (f >= fs / 2)
				break;
			r->n_orders = k;
			/* a line: a local maximum within the tolerance that
			 * stands above the noise */
			od->found = !sscope_psd_spectrum_peak_near(
					    &r->accel, f,
					    match_tol(o, f, r->accel.bin_hz),
					    &od->peak) &&
				    od->peak.value >=
					    thr * local_floor(&r->accel,
							      od->peak.bin);
			if (od->found)
				od->velocity_rms_m_s = od->peak.amplitude /
						       (2 * PI * od->peak.frequency_hz) /
						       sqrt(2.0);
		}
		sscope_vib_iso_limits(o->iso_class != SSCOPE_VIB_ISO_NONE ?
					  o->iso_class : SSCOPE_VIB_ISO_I,
				      lim);
		orders_findings(r, lim[1]);
	}
	if (o->have_bearing) {
		if (!(o->shaft_hz > 0)) {
			sscope_vib_result_clear(r);
			return ssc_diag(diag, -EINVAL,
					"bearing analysis needs the shaft speed");
		}
		rc = sscope_vib_bearing_frequencies(&o->bearing, o->shaft_hz,
						    &r->bearing);
		if (rc) {
			sscope_vib_result_clear(r);
			return ssc_diag(diag, rc, "bad bearing geometry");
		}
		r->have_bearing = true;
		rc = bearing_analysis(x, stride, n, fs, o, r, diag);
		if (rc) {
			sscope_vib_result_clear(r);
			return rc;
		}
	}
	return 0;
}
