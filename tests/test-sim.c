/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Sensor simulator: determinism and streaming, independent streams, each
 * noise term's Allan variance against its closed form within the EDF's
 * statistical bound, the flicker model's plateau (2 ln2/pi) B^2 (exact
 * theory and simulation), bias, scale factor, temperature profiles,
 * polynomial, hysteresis, gradient, tones, quantization, clipping and
 * every refused parameter.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check-main.h"

#define PI 3.14159265358979323846

static bool under_valgrind(void)
{
	const char *f = getenv("CK_FORK");

	return f && !strcmp(f, "no");
}

static struct sscope_sim *mk(const struct sscope_sensor_spec *sp,
			     const struct sscope_sim_opts *o)
{
	struct sscope_sim *s = NULL;
	struct sscope_diag d = { "" };

	ck_assert_msg(sscope_sim_new(&s, sp, o, &d) == 0, "%s", d.msg);
	return s;
}

START_TEST(determinism)
{
	struct sscope_sensor_spec sp = { 0 };
	struct sscope_sim_opts o = { 0 };
	struct sscope_sim *a, *b;
	double x[1000], y[1000];

	sp.n = 1e-3;
	sp.b = 2e-4;
	sp.k = 1e-5;
	sp.q = 1e-6;
	o.rate_hz = 100;
	o.seed = 7;
	a = mk(&sp, &o);
	b = mk(&sp, &o);
	sscope_sim_generate(a, NULL, x, NULL, 1000);
	/* any split of the record gives the same samples */
	sscope_sim_generate(b, NULL, y, NULL, 1);
	sscope_sim_generate(b, NULL, y + 1, NULL, 612);
	sscope_sim_generate(b, NULL, y + 613, NULL, 387);
	ck_assert(memcmp(x, y, sizeof(x)) == 0);
	ck_assert_uint_eq(sscope_sim_position(b), 1000);
	sscope_sim_reset(b);
	ck_assert_uint_eq(sscope_sim_position(b), 0);
	sscope_sim_generate(b, NULL, y, NULL, 1000);
	ck_assert(memcmp(x, y, sizeof(x)) == 0);
	sscope_sim_free(b);
	/* another seed differs */
	o.seed = 8;
	b = mk(&sp, &o);
	sscope_sim_generate(b, NULL, y, NULL, 1000);
	ck_assert(memcmp(x, y, sizeof(x)) != 0);
	sscope_sim_free(b);
	/* switching a term off leaves the others' realisations alone */
	o.seed = 7;
	sp.b = 0;
	b = mk(&sp, &o);
	sscope_sim_generate(b, NULL, y, NULL, 1000);
	{
		struct sscope_sensor_spec only = { 0 };
		struct sscope_sim *c;
		double z[1000];

		only.b = 2e-4;
		c = mk(&only, &o);
		sscope_sim_generate(c, NULL, z, NULL, 1000);
		for (int i = 0; i < 1000; i++)
			ck_assert_rel(y[i] + z[i], x[i], 1e-12);
		sscope_sim_free(c);
	}
	sscope_sim_free(a);
	sscope_sim_free(b);
}
END_TEST

START_TEST(streams)
{
	/* streams of one seed are uncorrelated: |r| < 4 / sqrt(n) */
	const size_t n = 20000;
	struct sscope_sensor_spec sp = { 0 };
	struct sscope_sim_opts o = { 0 };
	struct sscope_sim *s[3];
	double *y[3];
	double *const out[3] = { y[0] = malloc(n * 8), y[1] = malloc(n * 8),
				 y[2] = malloc(n * 8) };
	double *ref = malloc(n * 8);

	sp.n = 1;
	o.rate_hz = 1;
	o.seed = 123;
	for (int k = 0; k < 3; k++) {
		o.stream = (uint64_t)k;
		s[k] = mk(&sp, &o);
	}
	ck_assert_int_eq(sscope_sim_generate_multi(s, 3, NULL, out, NULL, n), 0);
	for (int a = 0; a < 3; a++)
		for (int b = a + 1; b < 3; b++) {
			double sab = 0, saa = 0, sbb = 0;

			for (size_t i = 0; i < n; i++) {
				sab += y[a][i] * y[b][i];
				saa += y[a][i] * y[a][i];
				sbb += y[b][i] * y[b][i];
			}
			ck_assert(fabs(sab / sqrt(saa * sbb)) < 4 / sqrt((double)n));
		}
	/* generate_multi gives what generate gives */
	o.stream = 2;
	sscope_sim_free(s[0]);
	s[0] = mk(&sp, &o);
	sscope_sim_generate(s[0], NULL, ref, NULL, n);
	ck_assert(memcmp(ref, y[2], n * 8) == 0);
	for (int k = 0; k < 3; k++) {
		sscope_sim_free(s[k]);
		free(y[k]);
	}
	free(ref);
}
END_TEST

/* OADEV of a simulated term against sscope_sim_avar: 4 sd of the EDF */
static void term_check(struct sscope_sensor_spec sp, double fs, size_t n,
		       int alpha, uint64_t seed, double tau_max)
{
	struct sscope_sim_opts o = { 0 };
	struct sscope_sim *s;
	double *y = malloc(n * sizeof(double));
	struct sscope_allan_opts ao = { 0 };
	struct sscope_allan *p;
	size_t m[64], nm, np;
	struct sscope_allan_point pt[64];

	o.rate_hz = fs;
	o.seed = seed;
	s = mk(&sp, &o);
	sscope_sim_generate(s, NULL, y, NULL, n);
	ao.alpha_fixed = true;
	ao.alpha = alpha;
	sscope_allan_grid(SSCOPE_ALLAN_TAUS_OCTAVE, (size_t)(tau_max * fs), m, 64, &nm);
	ck_assert_int_eq(sscope_allan_new(&p, n, &ao), 0);
	ck_assert_int_eq(sscope_allan_compute(p, y, 1, n, fs, m, nm, pt, &np, NULL), 0);
	for (size_t i = 0; i < np; i++) {
		double want = sscope_sim_avar(s, pt[i].tau_s);
		double v = pt[i].dev * pt[i].dev;

		ck_assert_msg(fabs(v / want - 1) <= 4 * sqrt(2 / pt[i].edf),
			      "Q%g N%g B%g K%g R%g tau %g: %g vs %g (edf %g)",
			      sp.q, sp.n, sp.b, sp.k, sp.r, pt[i].tau_s, v, want,
			      pt[i].edf);
	}
	sscope_allan_free(p);
	sscope_sim_free(s);
	free(y);
}

START_TEST(terms)
{
	const size_t n = under_valgrind() ? 20000 : 400000;
	struct sscope_sensor_spec sp;

	memset(&sp, 0, sizeof(sp));
	sp.q = 2.385e-4;
	term_check(sp, 100, n, 2, 31, (double)n / 100 / 8);
	memset(&sp, 0, sizeof(sp));
	sp.n = 2.385e-3;
	term_check(sp, 100, n, 0, 32, (double)n / 100 / 8);
	memset(&sp, 0, sizeof(sp));
	sp.k = 2.385e-5;
	term_check(sp, 100, n, -2, 33, (double)n / 100 / 8);
	memset(&sp, 0, sizeof(sp));
	sp.b = 2.385e-4;
	term_check(sp, 100, n, -1, 34, (double)n / 100 / 8);
	/* the rate ramp is deterministic: exact */
	{
		struct sscope_sim_opts o = { 0 };
		struct sscope_sim *s;
		double y[4000];
		size_t m[3] = { 1, 10, 100 }, np;
		struct sscope_allan_point pt[3];
		struct sscope_allan *p;

		memset(&sp, 0, sizeof(sp));
		sp.r = 2.385e-3;
		o.rate_hz = 10;
		s = mk(&sp, &o);
		sscope_sim_generate(s, NULL, y, NULL, 4000);
		ck_assert_int_eq(sscope_allan_new(&p, 4000, NULL), 0);
		ck_assert_int_eq(sscope_allan_compute(p, y, 1, 4000, 10, m, 3, pt, &np, NULL), 0);
		for (int i = 0; i < 3; i++) {
			ck_assert_rel(pt[i].dev, sp.r * pt[i].tau_s / sqrt(2), 1e-9);
			ck_assert_rel(sscope_sim_avar(s, pt[i].tau_s),
				      pow(sp.r * pt[i].tau_s, 2) / 2, 1e-12);
		}
		sscope_allan_free(p);
		sscope_sim_free(s);
	}
}
END_TEST

START_TEST(flicker_plateau)
{
	/* exact theory of the Gauss-Markov sum against (2 ln2/pi) B^2: the
	 * documented ripple (0.7 % from 100 tau_min to tau_max / 100; for the
	 * default band from the sample period 0.5 % there, 2 % from 20
	 * tau_min to tau_max / 30 and 7 % from tau_min), for three bands */
	const double B = 2.385e-5, plateau = 2 * log(2) / PI * B * B;
	const double bands[3][3] = { { 100, 0, 0 }, { 1, 0, 1e4 }, { 10, 0.5, 1e5 } };

	for (int i = 0; i < 3; i++) {
		struct sscope_sensor_spec sp = { 0 };
		struct sscope_sim_opts o = { 0 };
		struct sscope_sim *s;
		double tmin, tmax;

		sp.b = B;
		o.rate_hz = bands[i][0];
		o.flicker_tau_min_s = bands[i][1];
		o.flicker_tau_max_s = bands[i][2];
		tmin = bands[i][1] > 0 ? bands[i][1] : 1 / bands[i][0];
		tmax = bands[i][2] > 0 ? bands[i][2] : 1e6;
		s = mk(&sp, &o);
		for (double t = tmin; t <= tmax / 30; t *= 1.1) {
			double r;

			if (t * o.rate_hz < 1)
				continue;
			r = sscope_sim_avar(s, t) / plateau;
			if (bands[i][1] == 0) /* band from the sample period */
				ck_assert_msg(fabs(r - 1) <= 0.07, "tau %g: %g", t, r);
			if (t >= 20 * tmin && bands[i][1] == 0)
				ck_assert_msg(fabs(r - 1) <= 0.02, "tau %g: %g", t, r);
			if (t >= 100 * tmin && t <= tmax / 100)
				ck_assert_msg(fabs(r - 1) <= (bands[i][1] == 0 &&
							      bands[i][2] == 0 ?
								      0.005 :
								      0.007),
					      "tau %g: %g", t, r);
		}
		sscope_sim_free(s);
	}
}
END_TEST

START_TEST(bias_scale_tones_quantization)
{
	struct sscope_sensor_spec sp = { 0 };
	struct sscope_sim_opts o = { 0 };
	struct sscope_sim *s;
	const size_t n = 2000;
	double in[2000], y[2000];

	sp.bias = 0.125;
	sp.scale_factor_error = 2.385e-3;
	o.rate_hz = 200;
	for (size_t i = 0; i < n; i++)
		in[i] = sin(0.01 * (double)i) * 3.3;
	s = mk(&sp, &o);
	sscope_sim_generate(s, in, y, NULL, n);
	for (size_t i = 0; i < n; i++)
		ck_assert_rel(y[i], (1 + 2.385e-3) * in[i] + 0.125, 1e-14);
	sscope_sim_free(s);
	/* a tone: its amplitude and phase back by projection over whole
	 * cycles (25 Hz at 200 Hz: 8 samples per cycle) */
	memset(&sp, 0, sizeof(sp));
	o.n_tones = 2;
	o.tones[0] = (struct sscope_sim_tone){ 25, 0.7, 0.3 };
	o.tones[1] = (struct sscope_sim_tone){ 50, 0.2, 0 };
	s = mk(&sp, &o);
	sscope_sim_generate(s, NULL, y, NULL, n);
	{
		double c = 0, sn = 0;

		for (size_t i = 0; i < n; i++) {
			double w = 2 * PI * 25 * (double)i / 200;

			c += y[i] * cos(w);
			sn += y[i] * sin(w);
		}
		c *= 2.0 / n;
		sn *= 2.0 / n;
		ck_assert_rel(hypot(c, sn), 0.7, 1e-12);
		ck_assert_rel(atan2(c, sn), 0.3, 1e-12);
	}
	sscope_sim_free(s);
	/* quantization to multiples of a step, and clipping to the range */
	memset(&sp, 0, sizeof(sp));
	sp.n = 1;
	sp.range = 2;
	sp.has = SSCOPE_SENSOR_HAS_RANGE;
	o.n_tones = 0;
	o.quant_step = 0.25;
	s = mk(&sp, &o);
	sscope_sim_generate(s, NULL, y, NULL, n);
	for (size_t i = 0; i < n; i++) {
		ck_assert(y[i] == 0.25 * round(y[i] / 0.25));
		ck_assert(fabs(y[i]) <= 2);
	}
	/* per-sample sd sqrt(200): P(|y| > 2) is about 0.89 */
	ck_assert_uint_gt(sscope_sim_clipped(s), n / 2);
	sscope_sim_free(s);
	o.no_clip = true;
	s = mk(&sp, &o);
	sscope_sim_generate(s, NULL, y, NULL, n);
	ck_assert_uint_eq(sscope_sim_clipped(s), 0);
	sscope_sim_free(s);
}
END_TEST

START_TEST(temperature)
{
	struct sscope_sensor_spec sp = { 0 };
	struct sscope_sim_opts o = { 0 };
	struct sscope_sim *s;
	const size_t n = 4000;
	double y[4000], T[4000];

	/* ramp 20 -> 30 degC at 0.01 degC/s (10 Hz): 1000 s, then held;
	 * bias = tempco (T - 25) + c2 (T - 25)^2 + gradient dT/dt */
	sp.bias_tempco = 0.01;
	o.rate_hz = 10;
	o.temp_profile = SSCOPE_SIM_TEMP_RAMP;
	o.temp_degc = 20;
	o.temp2_degc = 30;
	o.temp_rate_degc_s = 0.01;
	o.ref_temp_degc = 25;
	o.bias_poly[1] = 1e-3;
	o.gradient = 2;
	s = mk(&sp, &o);
	sscope_sim_generate(s, NULL, y, T, n);
	for (size_t i = 0; i < n; i++) {
		double t = (double)i / 10, want_T = t < 1000 ? 20 + 0.01 * t : 30;
		double d = want_T - 25, rate = t < 1000 ? 0.01 : 0;

		ck_assert_msg(fabs(T[i] - want_T) < 1e-9, "T %g vs %g", T[i], want_T);
		ck_assert_msg(fabs(y[i] - (0.01 * d + 1e-3 * d * d + 2 * rate)) < 1e-12,
			      "t %g: %g", t, y[i]);
	}
	sscope_sim_free(s);
	/* triangle cycle 0..40 degC, period 200 s: hysteresis +-h/2 with the
	 * sign of dT/dt (0 before the first change: it starts heating) */
	memset(&o, 0, sizeof(o));
	memset(&sp, 0, sizeof(sp));
	o.rate_hz = 10;
	o.temp_profile = SSCOPE_SIM_TEMP_CYCLE;
	o.temp_wave = SSCOPE_SIM_TRIANGLE;
	o.temp_degc = 0;
	o.temp2_degc = 40;
	o.temp_period_s = 200;
	o.hysteresis = 0.5;
	o.temp_noise_degc = 0.1;
	s = mk(&sp, &o);
	sscope_sim_generate(s, NULL, y, T, n);
	{
		double lo = INFINITY, hi = -INFINITY, m = 0, v = 0;

		for (size_t i = 0; i < n; i++) {
			double ph = fmod((double)i / 10 / 200, 1), Tt;

			Tt = ph < 0.5 ? 80 * ph : 40 - 80 * (ph - 0.5);
			lo = fmin(lo, T[i]);
			hi = fmax(hi, T[i]);
			m += T[i] - Tt;
			v += (T[i] - Tt) * (T[i] - Tt);
			ck_assert(y[i] == (ph < 0.5 ? 0.25 : -0.25));
		}
		m /= n;
		v = v / n - m * m;
		/* reading noise 0.1 degC: sd within 4 sd of its estimate */
		ck_assert(fabs(sqrt(v) / 0.1 - 1) < 4 / sqrt(2.0 * n));
		ck_assert(lo < 0.5 && hi > 39.5);
	}
	sscope_sim_free(s);
	/* sine cycle from the low temperature; given temperatures */
	o.temp_wave = SSCOPE_SIM_SINE;
	o.temp_noise_degc = 0;
	o.hysteresis = 0;
	o.gradient = 1;
	s = mk(&sp, &o);
	sscope_sim_generate(s, NULL, y, T, n);
	ck_assert(fabs(T[0]) < 1e-12 && fabs(T[1000] - 40) < 1e-9);
	ck_assert(fabs(y[500] - 40 * PI / 200) < 1e-9); /* max dT/dt at P/4 */
	sscope_sim_free(s);
	o.temp_profile = SSCOPE_SIM_TEMP_GIVEN;
	o.gradient = 0;
	o.bias_poly[0] = 0.02;
	o.ref_temp_degc = 10;
	s = mk(&sp, &o);
	for (size_t i = 0; i < 100; i++)
		T[i] = 10 + 0.5 * (double)i;
	sscope_sim_generate(s, NULL, y, T, 100);
	for (size_t i = 0; i < 100; i++)
		ck_assert_rel(y[i], 0.02 * 0.5 * (double)i, 1e-12);
	ck_assert_int_eq(sscope_sim_generate(s, NULL, y, NULL, 10), -EINVAL);
	T[3] = NAN;
	ck_assert_int_eq(sscope_sim_generate(s, NULL, y, T, 10), -EINVAL);
	sscope_sim_free(s);
}
END_TEST

START_TEST(errors)
{
	struct sscope_sensor_spec sp = { 0 };
	struct sscope_sim_opts o = { 0 }, g;
	struct sscope_sim *s;
	struct sscope_diag d = { "" };

	o.rate_hz = 100;
	ck_assert_int_eq(sscope_sim_new(NULL, &sp, &o, &d), -EINVAL);
	ck_assert_int_eq(sscope_sim_new(&s, NULL, &o, &d), -EINVAL);
	ck_assert_int_eq(sscope_sim_new(&s, &sp, NULL, &d), -EINVAL);
	g = o;
	g.rate_hz = 0;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	sp.n = -1;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &o, &d), -EINVAL);
	sp.n = 0;
	sp.bias = NAN;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &o, &d), -EINVAL);
	sp.bias = 0;
	g = o;
	g.n_tones = SSCOPE_SIM_MAX_TONES + 1;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	g = o;
	g.n_tones = 1;
	g.tones[0].freq_hz = 50;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	g = o;
	g.temp_profile = SSCOPE_SIM_TEMP_CYCLE;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	g = o;
	g.temp_profile = SSCOPE_SIM_TEMP_RAMP;
	g.temp_degc = 10;
	g.temp2_degc = 0;
	g.temp_rate_degc_s = 1;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	g = o;
	g.quant_step = -1;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	g = o;
	g.flicker_tau_min_s = 10;
	g.flicker_tau_max_s = 1;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	g.flicker_tau_min_s = 1e-3;
	g.flicker_tau_max_s = 1e40;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	g = o;
	g.temp_noise_degc = -1;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	g = o;
	g.hysteresis_deadband_degc_s = -1;
	ck_assert_int_eq(sscope_sim_new(&s, &sp, &g, &d), -EINVAL);
	ck_assert(d.msg[0] != '\0');
	s = mk(&sp, &o);
	ck_assert_int_eq(sscope_sim_generate(s, NULL, NULL, NULL, 3), -EINVAL);
	ck_assert_int_eq(sscope_sim_generate_multi(NULL, 1, NULL, NULL, NULL, 3), -EINVAL);
	sscope_sim_free(s);
	sscope_sim_free(NULL);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("sim");
	TCase *t = tcase_create("sim");

	tcase_set_timeout(t, 600);
	tcase_add_test(t, determinism);
	tcase_add_test(t, streams);
	tcase_add_test(t, terms);
	tcase_add_test(t, flicker_plateau);
	tcase_add_test(t, bias_scale_tones_quantization);
	tcase_add_test(t, temperature);
	tcase_add_test(t, errors);
	suite_add_tcase(s, t);
	return s;
}
