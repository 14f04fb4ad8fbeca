/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Vibration: bearing defect frequencies against the published multiples
 * of the CWRU bearing data centre's SKF 6205 drive-end bearing, ISO zone
 * boundaries, velocity from acceleration (closed form of a sine), kurtosis
 * (sine 1.5 exactly, Gaussian 3 within 4 sd), the envelope of an AM signal
 * (closed form), and synthetic machines diagnosed: unbalance,
 * misalignment, an outer-race and an inner-race defect, a healthy machine
 * with no finding.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "check-main.h"

#define PI 3.14159265358979323846

/* SKF 6205-2RS JEM (CWRU drive end): 9 balls, d = 0.3126 in,
 * D = 1.537 in, contact angle 0 */
static const struct sscope_vib_bearing skf6205 = { 9, 0.3126 * 0.0254,
					       1.537 * 0.0254, 0 };

START_TEST(bearing_frequencies)
{
	struct sscope_vib_bearing_freqs f;
	struct sscope_vib_bearing b = skf6205;
	const double fr = 1797.0 / 60;

	/* CWRU's published defect frequencies, multiples of the shaft
	 * frequency: inner 5.4152, outer 3.5848, cage 0.39828, rolling
	 * element 4.7135 (= 2 BSF: a ball defect strikes both races) */
	ck_assert_int_eq(sscope_vib_bearing_frequencies(&b, fr, &f), 0);
	ck_assert_rel(f.bpfi_hz / fr, 5.4152, 1e-4);
	ck_assert_rel(f.bpfo_hz / fr, 3.5848, 1e-4);
	ck_assert_rel(f.ftf_hz / fr, 0.39828, 2e-4);
	ck_assert_rel(2 * f.bsf_hz / fr, 4.7135, 2e-4);
	/* kinematic identities, any angle: BPFO + BPFI = n fr,
	 * FTF = BPFO / n */
	b.contact_angle_rad = 15 * PI / 180;
	ck_assert_int_eq(sscope_vib_bearing_frequencies(&b, fr, &f), 0);
	ck_assert_rel(f.bpfo_hz + f.bpfi_hz, 9 * fr, 1e-14);
	ck_assert_rel(f.ftf_hz, f.bpfo_hz / 9, 1e-14);
	/* errors */
	b = skf6205;
	b.ball_diameter_m = b.pitch_diameter_m;
	ck_assert_int_eq(sscope_vib_bearing_frequencies(&b, fr, &f), -EINVAL);
	b = skf6205;
	b.n_elements = 0;
	ck_assert_int_eq(sscope_vib_bearing_frequencies(&b, fr, &f), -EINVAL);
	b = skf6205;
	b.contact_angle_rad = PI / 2;
	ck_assert_int_eq(sscope_vib_bearing_frequencies(&b, fr, &f), -EINVAL);
	ck_assert_int_eq(sscope_vib_bearing_frequencies(&skf6205, 0, &f), -EINVAL);
}
END_TEST

START_TEST(iso_zones)
{
	double lim[3];
	char z;

	ck_assert(strstr(sscope_vib_iso_edition(), "10816-1:1995") != NULL);
	ck_assert_int_eq(sscope_vib_iso_limits(SSCOPE_VIB_ISO_II, lim), 0);
	ck_assert_rel(lim[0], 1.12e-3, 1e-15);
	ck_assert_rel(lim[1], 2.8e-3, 1e-15);
	ck_assert_rel(lim[2], 7.1e-3, 1e-15);
	ck_assert_int_eq(sscope_vib_iso_zone(SSCOPE_VIB_ISO_II, 2.79e-3, &z), 0);
	ck_assert_int_eq(z, 'B');
	ck_assert_int_eq(sscope_vib_iso_zone(SSCOPE_VIB_ISO_II, 2.8e-3, &z), 0);
	ck_assert_int_eq(z, 'C'); /* a boundary belongs to the zone above */
	ck_assert_int_eq(sscope_vib_iso_zone(SSCOPE_VIB_ISO_I, 0.7e-3, &z), 0);
	ck_assert_int_eq(z, 'A');
	ck_assert_int_eq(sscope_vib_iso_zone(SSCOPE_VIB_ISO_IV, 18e-3, &z), 0);
	ck_assert_int_eq(z, 'D');
	ck_assert_int_eq(sscope_vib_iso_zone(SSCOPE_VIB_ISO_III, 0, &z), 0);
	ck_assert_int_eq(z, 'A');
	ck_assert_int_eq(sscope_vib_iso_zone(SSCOPE_VIB_ISO_NONE, 1e-3, &z), -EINVAL);
	ck_assert_int_eq(sscope_vib_iso_zone(SSCOPE_VIB_ISO_I, NAN, &z), -EINVAL);
	ck_assert_int_eq(sscope_vib_iso_limits((enum sscope_vib_iso_class)9, lim), -EINVAL);
}
END_TEST

START_TEST(velocity_of_a_sine)
{
	/* a = A sin(2 pi f t): v_rms = A / (2 pi f sqrt 2); tones outside
	 * 10-1000 Hz do not count.  The Hann window spreads a tone over
	 * +-2 bins of 1.2 Hz, where 1/f^2 changes by a few per cent: the
	 * second-order error is below 0.1 % at 100 Hz */
	const size_t n = 50000;
	const double fs = 5000, A = 2.385;
	double *x = malloc(n * sizeof(double)), ms;
	struct sscope_psd_spectrum s;
	struct sscope_psd_opts o;

	for (size_t i = 0; i < n; i++) {
		double t = (double)i / fs;

		x[i] = A * sin(2 * PI * 100.3 * t) + 3 * sin(2 * PI * 4 * t) +
		       3 * sin(2 * PI * 1700 * t);
	}
	sscope_psd_opts_init(&o);
	o.nperseg = 4096;
	ck_assert_int_eq(sscope_psd_welch(x, 1, n, fs, &o, &s), 0);
	ck_assert_int_eq(sscope_vib_velocity_ms(&s, 10, 1000, &ms), 0);
	ck_assert_rel(sqrt(ms), A / (2 * PI * 100.3) / sqrt(2.0), 2e-3);
	ck_assert_int_eq(sscope_vib_velocity_ms(&s, 0, 1000, &ms), -EINVAL);
	ck_assert_int_eq(sscope_vib_velocity_ms(&s, 100, 10, &ms), -EINVAL);
	sscope_psd_spectrum_clear(&s);
	free(x);
}
END_TEST

START_TEST(kurtosis)
{
	const size_t n = 100000;
	double *x = malloc(n * sizeof(double)), k;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	/* a sine over whole periods: 3/8 / (1/2)^2 = 1.5 exactly */
	for (size_t i = 0; i < 1000; i++)
		x[i] = 2.385 * sin(2 * PI * 7 * (double)i / 1000) + 4;
	ck_assert_int_eq(sscope_vib_kurtosis(x, 1, 1000, &k), 0);
	ck_assert_rel(k, 1.5, 1e-12);
	/* Gaussian: 3, sd sqrt(24 / n) */
	gsl_rng_set(r, 21);
	for (size_t i = 0; i < n; i++)
		x[i] = gsl_ran_gaussian_ziggurat(r, 2.385);
	ck_assert_int_eq(sscope_vib_kurtosis(x, 1, n, &k), 0);
	ck_assert_msg(fabs(k - 3) < 4 * sqrt(24.0 / (double)n), "kurtosis %g", k);
	/* errors */
	ck_assert_int_eq(sscope_vib_kurtosis(x, 1, 3, &k), -EDOM);
	for (size_t i = 0; i < 10; i++)
		x[i] = 1.25;
	ck_assert_int_eq(sscope_vib_kurtosis(x, 1, 10, &k), -EDOM);
	x[3] = NAN;
	ck_assert_int_eq(sscope_vib_kurtosis(x, 1, 10, &k), -EDOM);
	ck_assert_int_eq(sscope_vib_kurtosis(x, 0, 10, &k), -EINVAL);
	free(x);
	gsl_rng_free(r);
}
END_TEST

START_TEST(envelope_closed_form)
{
	/* (1 + m cos(2 pi fm t)) cos(2 pi fc t) over whole periods: the
	 * envelope of the band around fc is 1 + m cos(2 pi fm t) */
	const size_t n = 4000;
	const double fs = 4000, fc = 1000, fm = 37, m = 0.5;
	double *x = malloc(n * sizeof(double)), *e = malloc(n * sizeof(double));
	double sk;
	struct sscope_vib_envelope *env;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	for (size_t i = 0; i < n; i++) {
		double t = (double)i / fs;

		x[i] = (1 + m * cos(2 * PI * fm * t)) * cos(2 * PI * fc * t) +
		       0.7 * sin(2 * PI * 113 * t); /* outside the band */
	}
	ck_assert_int_eq(sscope_vib_envelope_new(&env, n), 0);
	ck_assert_int_eq(sscope_vib_envelope_band(env, fs, 900, 1100, e, &sk), -EINVAL);
	ck_assert_int_eq(sscope_vib_envelope_set(env, x, 1), 0);
	ck_assert_int_eq(sscope_vib_envelope_band(env, fs, 900, 1100, e, &sk), 0);
	for (size_t i = 0; i < n; i++)
		ck_assert_msg(fabs(e[i] - (1 + m * cos(2 * PI * fm * (double)i / fs))) < 1e-12,
			      "envelope[%zu] = %.15g", i, e[i]);
	/* a steady tone: spectral kurtosis -1 */
	ck_assert_int_eq(sscope_vib_envelope_band(env, fs, 100, 130, NULL, &sk), 0);
	ck_assert_rel(sk, -1, 1e-12);
	/* no energy there; bad bands */
	ck_assert_int_eq(sscope_vib_envelope_band(env, fs, 1500, 1600, NULL, &sk), -EDOM);
	ck_assert_int_eq(sscope_vib_envelope_band(env, fs, 1500, 2500, NULL, &sk), -EINVAL);
	ck_assert_int_eq(sscope_vib_envelope_band(env, fs, 600, 500, NULL, &sk), -EINVAL);
	/* Gaussian noise: spectral kurtosis 0 (sd about sqrt(4 / (n B/fs)) for
	 * the n B / fs independent samples of the band) */
	gsl_rng_set(r, 22);
	for (size_t i = 0; i < n; i++)
		x[i] = gsl_ran_gaussian_ziggurat(r, 1);
	ck_assert_int_eq(sscope_vib_envelope_set(env, x, 1), 0);
	ck_assert_int_eq(sscope_vib_envelope_band(env, fs, 500, 1500, NULL, &sk), 0);
	ck_assert_msg(fabs(sk) < 4 * sqrt(4.0 / (n * 1000.0 / fs)), "sk %g", sk);
	x[7] = NAN;
	ck_assert_int_eq(sscope_vib_envelope_set(env, x, 1), -EDOM);
	sscope_vib_envelope_free(env);
	ck_assert_int_eq(sscope_vib_envelope_new(&env, 3), -EINVAL);
	free(x);
	free(e);
	gsl_rng_free(r);
}
END_TEST

/* ------------------------------------------------------------ machines */

struct machine {
	double fs, T, fr;
	double a1, a2, a3; /* orders, m/s^2 */
	double noise;      /* white, m/s^2 rms */
	double imp;        /* impulse amplitude (0: none), m/s^2 */
	double f_imp;      /* impulse rate */
	double mod;        /* amplitude modulation of impulses by 1x */
	unsigned long seed;
};

/* Impulses at f_imp with 1 % random jitter of each interval (slip), each
 * ringing a 3 kHz resonance with 0.6 ms decay, plus orders and noise. */
static double *machine(const struct machine *m, size_t *n_out)
{
	size_t n = (size_t)(m->fs * m->T);
	double *x = calloc(n, sizeof(double));
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	gsl_rng_set(r, m->seed);
	for (size_t i = 0; i < n; i++) {
		double t = (double)i / m->fs, w = 2 * PI * m->fr * t;

		x[i] = m->a1 * sin(w + 0.3) + m->a2 * sin(2 * w + 1.1) +
		       m->a3 * sin(3 * w + 0.2) +
		       gsl_ran_gaussian_ziggurat(r, m->noise);
	}
	if (m->imp > 0) {
		double ti = 0.01;

		while (ti < m->T) {
			double g = m->imp * (1 + m->mod * cos(2 * PI * m->fr * ti));
			size_t i0 = (size_t)ceil(ti * m->fs);

			for (size_t i = i0; i < n && i < i0 + (size_t)(0.006 * m->fs); i++) {
				double dt = (double)i / m->fs - ti;

				x[i] += g * exp(-dt / 0.6e-3) * sin(2 * PI * 3000 * dt);
			}
			ti += (1 + 0.01 * gsl_ran_gaussian_ziggurat(r, 1)) / m->f_imp;
		}
	}
	gsl_rng_free(r);
	*n_out = n;
	return x;
}

static bool has_finding(const struct sscope_vib_result *r, const char *what)
{
	for (size_t i = 0; i < r->n_findings; i++)
		if (strstr(r->findings[i].finding, what))
			return true;
	return false;
}

static void dump(const struct sscope_vib_result *r)
{
	for (size_t i = 0; i < r->n_findings; i++)
		fprintf(stderr, "# %s: %s\n", r->findings[i].finding,
			r->findings[i].evidence);
}

START_TEST(unbalance)
{
	struct machine m = { 5000, 2, 1770.0 / 60, 4, 0.4, 0.2, 0.2, 0, 0, 0, 31 };
	struct sscope_vib_opts o;
	struct sscope_vib_result r;
	size_t n;
	double *x = machine(&m, &n), v1;

	sscope_vib_opts_init(&o);
	o.shaft_hz = m.fr;
	o.iso_class = SSCOPE_VIB_ISO_II;
	ck_assert_int_eq(sscope_vib_analyze(x, 1, n, m.fs, &o, &r, NULL), 0);
	dump(&r);
	ck_assert(has_finding(&r, "unbalance"));
	ck_assert(!has_finding(&r, "misalignment"));
	ck_assert_uint_eq(r.n_findings, 1);
	ck_assert(strstr(r.findings[0].evidence, "1x = ") != NULL);
	/* the orders: 1x at 29.5 Hz with 4 m/s^2, velocity 4 / (2 pi fr) /
	 * sqrt 2 = 15.3 mm/s; the overall velocity is dominated by it */
	ck_assert_uint_eq(r.n_orders, 3);
	ck_assert(r.orders[0].found);
	ck_assert(fabs(r.orders[0].peak.frequency_hz - m.fr) < 0.01);
	ck_assert_rel(r.orders[0].peak.amplitude, 4, 5e-3);
	v1 = 4 / (2 * PI * m.fr) / sqrt(2.0);
	ck_assert_rel(r.orders[0].velocity_rms_m_s, v1, 5e-3);
	ck_assert(r.velocity_rms_m_s > v1 && r.velocity_rms_m_s < 1.01 * v1);
	ck_assert_int_eq(r.zone, 'D'); /* 15 mm/s > 7.1 for class II */
	ck_assert_rel(r.orders[1].peak.amplitude, 0.4, 2e-2);
	ck_assert(r.kurtosis > 1.4 && r.kurtosis < 1.7);
	sscope_vib_result_clear(&r);
	/* zero fields are the defaults spelled out: ISO band 10-1000 Hz,
	 * 5 peaks, 2 % tolerance; no peaks and exact matches have names */
	{
		struct sscope_vib_opts d = o;
		struct sscope_vib_result q;

		d.iso_lo_hz = 10;
		d.iso_hi_hz = 1000;
		d.tolerance = 0.02;
		d.n_peaks = 5;
		ck_assert_int_eq(sscope_vib_analyze(x, 1, n, m.fs, &o, &r, NULL), 0);
		ck_assert_int_eq(sscope_vib_analyze(x, 1, n, m.fs, &d, &q, NULL), 0);
		ck_assert_uint_eq(r.n_peaks, 5);
		ck_assert(r.iso_lo_hz == 10 && r.iso_hi_hz == 1000);
		ck_assert(r.velocity_rms_m_s == q.velocity_rms_m_s);
		ck_assert(r.orders[0].found && q.orders[0].found);
		sscope_vib_result_clear(&q);
		d.n_peaks = SSCOPE_VIB_NO_PEAKS;
		d.tolerance = -1; /* exact: the resolution's 1.5 bins only */
		ck_assert_int_eq(sscope_vib_analyze(x, 1, n, m.fs, &d, &q, NULL), 0);
		ck_assert_uint_eq(q.n_peaks, 0);
		ck_assert(q.orders[0].found);
		sscope_vib_result_clear(&q);
		sscope_vib_result_clear(&r);
	}
	free(x);
}
END_TEST

START_TEST(misalignment)
{
	struct machine m = { 5000, 2, 1770.0 / 60, 1.5, 3, 1, 0.2, 0, 0, 0, 32 };
	struct sscope_vib_opts o;
	struct sscope_vib_result r;
	size_t n;
	double *x = machine(&m, &n);

	sscope_vib_opts_init(&o);
	o.shaft_hz = m.fr;
	ck_assert_int_eq(sscope_vib_analyze(x, 1, n, m.fs, &o, &r, NULL), 0);
	dump(&r);
	ck_assert(has_finding(&r, "misalignment"));
	ck_assert(!has_finding(&r, "unbalance"));
	ck_assert_int_eq(r.zone, 0); /* no class given */
	sscope_vib_result_clear(&r);
	free(x);
}
END_TEST

START_TEST(outer_race)
{
	/* 1797 rpm, SKF 6205: BPFO = 107.4 Hz, impulses ringing 3 kHz with a
	 * peak only 3 times the noise rms: the overall kurtosis is barely
	 * above a Gaussian's, the envelope shows the defect */
	struct machine m = { 12000, 2, 1797.0 / 60, 0.05, 0.02, 0, 0.5, 1.5, 0, 0, 33 };
	struct sscope_vib_opts o;
	struct sscope_vib_result r;
	struct sscope_vib_bearing_freqs f;
	size_t n, nb = 0;
	double *x;

	sscope_vib_bearing_frequencies(&skf6205, m.fr, &f);
	m.f_imp = f.bpfo_hz;
	x = machine(&m, &n);
	sscope_vib_opts_init(&o);
	o.shaft_hz = m.fr;
	o.have_bearing = true;
	o.bearing = skf6205;
	ck_assert_int_eq(sscope_vib_analyze(x, 1, n, m.fs, &o, &r, NULL), 0);
	dump(&r);
	ck_assert(has_finding(&r, "outer-race"));
	ck_assert(!has_finding(&r, "inner-race"));
	ck_assert(!has_finding(&r, "rolling-element"));
	ck_assert(!has_finding(&r, "cage"));
	/* the band found contains the resonance; impulsive */
	ck_assert(r.env_lo_hz < 3000 && r.env_hi_hz > 3000);
	ck_assert(r.env_sk > 0.2); /* Gaussian noise: 0 */
	ck_assert(r.kurtosis > 3.1);
	/* the strongest envelope line is BPFO */
	ck_assert_uint_ge(r.n_env_peaks, 2);
	ck_assert_str_eq(r.env_peaks[0].match, "BPFO");
	for (size_t i = 0; i < r.n_env_peaks; i++)
		nb += strstr(r.env_peaks[i].match, "BPFO") != NULL;
	ck_assert_uint_ge(nb, 3);
	sscope_vib_result_clear(&r);
	free(x);
}
END_TEST

START_TEST(inner_race)
{
	/* impulses at BPFI, their strength modulated by the shaft (load
	 * zone): sidebands at BPFI +- 1x */
	struct machine m = { 12000, 2, 1797.0 / 60, 0.05, 0.02, 0, 0.5, 1.5, 0, 0.8, 34 };
	struct sscope_vib_opts o;
	struct sscope_vib_result r;
	struct sscope_vib_bearing_freqs f;
	size_t n;
	double *x;

	sscope_vib_bearing_frequencies(&skf6205, m.fr, &f);
	m.f_imp = f.bpfi_hz;
	x = machine(&m, &n);
	sscope_vib_opts_init(&o);
	o.shaft_hz = m.fr;
	o.have_bearing = true;
	o.bearing = skf6205;
	ck_assert_int_eq(sscope_vib_analyze(x, 1, n, m.fs, &o, &r, NULL), 0);
	dump(&r);
	ck_assert(has_finding(&r, "inner-race"));
	ck_assert(!has_finding(&r, "outer-race"));
	ck_assert(!has_finding(&r, "cage"));
	sscope_vib_result_clear(&r);
	free(x);
}
END_TEST

START_TEST(healthy)
{
	/* small orders and noise, bearing and speed given: no finding */
	for (unsigned long seed = 35; seed < 38; seed++) {
		struct machine m = { 12000, 2, 1797.0 / 60, 0.1, 0.03, 0.01, 0.3, 0, 0, 0, seed };
		struct sscope_vib_opts o;
		struct sscope_vib_result r;
		size_t n;
		double *x = machine(&m, &n);

		sscope_vib_opts_init(&o);
		o.shaft_hz = m.fr;
		o.have_bearing = true;
		o.bearing = skf6205;
		o.iso_class = SSCOPE_VIB_ISO_I;
		ck_assert_int_eq(sscope_vib_analyze(x, 1, n, m.fs, &o, &r, NULL), 0);
		dump(&r);
		ck_assert_uint_eq(r.n_findings, 0);
		ck_assert_int_eq(r.zone, 'A');
		ck_assert(fabs(r.kurtosis - 3) < 0.3);
		sscope_vib_result_clear(&r);
		free(x);
	}
}
END_TEST

START_TEST(analysis_errors)
{
	double x[64];
	struct sscope_vib_opts o;
	struct sscope_vib_result r;
	struct sscope_diag d = { "" };

	for (int i = 0; i < 64; i++)
		x[i] = sin(i * 0.7);
	sscope_vib_opts_init(&o);
	ck_assert_int_eq(sscope_vib_analyze(x, 1, 10, 100, &o, &r, &d), -EDOM);
	ck_assert(strstr(d.msg, "too short") != NULL);
	ck_assert_int_eq(sscope_vib_analyze(x, 1, 64, 0, &o, &r, NULL), -EINVAL);
	o.have_bearing = true;
	o.bearing = skf6205;
	ck_assert_int_eq(sscope_vib_analyze(x, 1, 64, 100, &o, &r, &d), -EINVAL);
	ck_assert(strstr(d.msg, "shaft speed") != NULL);
	sscope_vib_opts_init(&o);
	o.iso_class = (enum sscope_vib_iso_class)12;
	ck_assert_int_eq(sscope_vib_analyze(x, 1, 64, 100, &o, &r, NULL), -EINVAL);
	sscope_vib_opts_init(&o);
	for (int i = 0; i < 64; i++)
		x[i] = 3;
	ck_assert_int_eq(sscope_vib_analyze(x, 1, 64, 100, &o, &r, &d), -EDOM);
	ck_assert(strstr(d.msg, "constant") != NULL);
	x[5] = NAN;
	ck_assert_int_eq(sscope_vib_analyze(x, 1, 64, 100, &o, &r, &d), -EDOM);
	ck_assert_uint_eq(sscope_vib_default_nperseg(100), 100);
	ck_assert_uint_eq(sscope_vib_default_nperseg(10000), 2048);
	ck_assert_uint_eq(sscope_vib_default_nperseg(100000000), 65536);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("vibration");
	TCase *tc = tcase_create("vibration");

	tcase_set_timeout(tc, 120);
	tcase_add_test(tc, bearing_frequencies);
	tcase_add_test(tc, iso_zones);
	tcase_add_test(tc, velocity_of_a_sine);
	tcase_add_test(tc, kurtosis);
	tcase_add_test(tc, envelope_closed_form);
	tcase_add_test(tc, unbalance);
	tcase_add_test(tc, misalignment);
	tcase_add_test(tc, outer_race);
	tcase_add_test(tc, inner_race);
	tcase_add_test(tc, healthy);
	tcase_add_test(tc, analysis_errors);
	suite_add_tcase(s, tc);
	return s;
}
