/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Sensor noise simulator: the IEEE Std 952-1997 (Annex C) rate-noise model
 * Q, N, B, K, R plus bias, scale factor, temperature dependence (bias
 * polynomial, heating/cooling hysteresis, thermal-gradient term) and
 * vibration tones, as a stream (see sscope-sim.h for the model).
 *
 * Bias instability as flicker rate noise: a sum of first-order
 * Gauss-Markov processes with correlation times in geometric progression,
 * each with the same variance, approximates a 1/f spectrum between the
 * extreme corner frequencies (the classic construction, e.g. N. J. Kasdin,
 * "Discrete simulation of colored noise and stochastic processes and
 * 1/f^alpha power law noise generation", Proc. IEEE 83(5), 1995, sec. IV):
 * with correlation times T_j = T_0 r^j the one-sided PSD
 * sum_j 4 s^2 T_j / (1 + (2 pi f T_j)^2) tends to s^2 / (f ln r), so
 * s^2 = B^2 ln(r) / pi gives S(f) = B^2 / (pi f), i.e. the Allan plateau
 * (2 ln 2 / pi) B^2 of IEEE 952.  Unlike Kasdin-Walter's power-law filter
 * it needs O(1) state per process, so the stream can run forever.  The
 * Allan variance of the discrete AR(1) processes is exact in closed form
 * (sscope_sim_avar), which is what the tests compare the simulation with.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "sscope-sim.h"
#include "sscope-sensor.h"

/* spacing of the Gauss-Markov correlation times: 10^(2/3) */
#define GM_RATIO 4.6415888336127788
#define GM_MAX 48

enum { G_Q = 0, G_N, G_B, G_K, G_T, G_COUNT };

struct sscope_sim {
	struct sscope_sensor_spec spec;
	struct sscope_sim_opts o;
	double dt, poly[SSCOPE_SIM_MAX_POLY];
	gsl_rng *rng[G_COUNT];
	/* flicker */
	size_t n_gm;
	double gm_phi[GM_MAX], gm_in[GM_MAX], gm_s; /* in: sqrt(1-phi^2) s */
	double gm_lam[GM_MAX];                      /* dt / T */
	double gm[GM_MAX];
	/* state */
	uint64_t k, clipped;
	double e_prev; /* last white-angle value (Q) */
	double rw;     /* rate random walk (K) */
	int hyst;      /* -1 cooling, 0 unknown, +1 heating */
	double t_prev; /* previous given temperature */
	bool have_prev;
};

static uint64_t splitmix64(uint64_t *x)
{
	uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);

	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
	return z ^ (z >> 31);
}

/* 32-bit seed of generator (seed, stream, term); MT19937 in GSL uses the
 * low 32 bits of its seed */
static unsigned long term_seed(uint64_t seed, uint64_t stream, unsigned term)
{
	uint64_t st = seed;
	uint64_t a = splitmix64(&st);

	st = a ^ (stream * 0xd1b54a32d192ed03ULL);
	a = splitmix64(&st);
	st = a ^ ((uint64_t)(term + 1) * 0x8cb92ba72f3d8dd7ULL);
	a = splitmix64(&st);
	return (unsigned long)((a >> 32) ^ (a & 0xffffffffULL));
}

static double gauss(gsl_rng *r)
{
	return gsl_ran_gaussian_ziggurat(r, 1.0);
}

void sscope_sim_reset(struct sscope_sim *s)
{
	for (unsigned g = 0; g < G_COUNT; g++)
		gsl_rng_set(s->rng[g], term_seed(s->o.seed, s->o.stream, g));
	s->k = 0;
	s->clipped = 0;
	s->rw = 0;
	s->hyst = 0;
	s->have_prev = false;
	s->t_prev = 0;
	/* stationary start of every Gauss-Markov process */
	for (size_t j = 0; j < s->n_gm; j++)
		s->gm[j] = s->gm_s * gauss(s->rng[G_B]);
	s->e_prev = s->spec.q * gauss(s->rng[G_Q]);
}

void sscope_sim_free(struct sscope_sim *s)
{
	if (!s)
		return;
	for (unsigned g = 0; g < G_COUNT; g++)
		if (s->rng[g])
			gsl_rng_free(s->rng[g]);
	free(s);
}

int sscope_sim_new(struct sscope_sim **simp,
		   const struct sscope_sensor_spec *spec,
		   const struct sscope_sim_opts *o, struct sscope_diag *diag)
{
	struct sscope_sim *s;
	double tmin, tmax;

	if (!simp)
		return -EINVAL;
	*simp = NULL;
	if (!spec || !o)
		return ssc_diag(diag, -EINVAL, "no spec or options");
	if (!(o->rate_hz > 0) || !isfinite(o->rate_hz))
		return ssc_diag(diag, -EINVAL, "rate must be positive");
	if (!(spec->q >= 0) || !(spec->n >= 0) || !(spec->b >= 0) ||
	    !(spec->k >= 0) || !(spec->r >= 0) || !isfinite(spec->q + spec->n +
							     spec->b + spec->k +
							     spec->r))
		return ssc_diag(diag, -EINVAL,
				"noise terms must be finite and non-negative");
	if (!isfinite(spec->bias) || !isfinite(spec->scale_factor_error) ||
	    !isfinite(spec->bias_tempco))
		return ssc_diag(diag, -EINVAL, "bias, scale factor and tempco must be finite");
	if (o->n_tones > SSCOPE_SIM_MAX_TONES)
		return ssc_diag(diag, -EINVAL, "at most %d tones",
				SSCOPE_SIM_MAX_TONES);
	for (size_t i = 0; i < o->n_tones; i++)
		if (!(o->tones[i].freq_hz >= 0) ||
		    !(o->tones[i].freq_hz < o->rate_hz / 2) ||
		    !isfinite(o->tones[i].amplitude) ||
		    !isfinite(o->tones[i].phase_rad))
			return ssc_diag(diag, -EINVAL,
					"tone %zu: frequency must be in [0, rate/2) and amplitude, phase finite",
					i + 1);
	if ((unsigned)o->temp_profile > SSCOPE_SIM_TEMP_GIVEN ||
	    (unsigned)o->temp_wave > SSCOPE_SIM_TRIANGLE ||
	    !isfinite(o->temp_degc) || !isfinite(o->temp2_degc) ||
	    !isfinite(o->temp_rate_degc_s) || !isfinite(o->ref_temp_degc) ||
	    !(o->temp_noise_degc >= 0) || !isfinite(o->temp_noise_degc))
		return ssc_diag(diag, -EINVAL, "bad temperature profile");
	if (o->temp_profile == SSCOPE_SIM_TEMP_CYCLE &&
	    (!(o->temp_period_s > 0) || !isfinite(o->temp_period_s)))
		return ssc_diag(diag, -EINVAL,
				"a temperature cycle needs a positive period");
	if (o->temp_profile == SSCOPE_SIM_TEMP_RAMP && o->temp_rate_degc_s != 0 &&
	    (o->temp2_degc - o->temp_degc) * o->temp_rate_degc_s < 0)
		return ssc_diag(diag, -EINVAL,
				"the ramp runs away from its end temperature");
	for (int i = 0; i < SSCOPE_SIM_MAX_POLY; i++)
		if (!isfinite(o->bias_poly[i]))
			return ssc_diag(diag, -EINVAL, "bias polynomial must be finite");
	if (!isfinite(o->hysteresis) || !(o->hysteresis_deadband_degc_s >= 0) ||
	    !isfinite(o->hysteresis_deadband_degc_s) || !isfinite(o->gradient))
		return ssc_diag(diag, -EINVAL, "bad hysteresis or gradient");
	if (!(o->quant_step >= 0) || !isfinite(o->quant_step))
		return ssc_diag(diag, -EINVAL,
				"quantization step must be non-negative");
	tmin = o->flicker_tau_min_s > 0 ? o->flicker_tau_min_s : 1 / o->rate_hz;
	tmax = o->flicker_tau_max_s > 0 ? o->flicker_tau_max_s : 1e6;
	if (o->flicker_tau_min_s < 0 || o->flicker_tau_max_s < 0 ||
	    !isfinite(tmin) || !isfinite(tmax) || !(tmax >= tmin) ||
	    log(tmax / tmin) / log(GM_RATIO) > GM_MAX - 2)
		return ssc_diag(diag, -EINVAL,
				"flicker band must satisfy 0 < min <= max <= min * 10^%d",
				2 * (GM_MAX - 2) / 3);
	s = calloc(1, sizeof(*s));
	if (!s)
		return -ENOMEM;
	s->spec = *spec;
	s->o = *o;
	s->dt = 1 / o->rate_hz;
	memcpy(s->poly, o->bias_poly, sizeof(s->poly));
	s->poly[0] += spec->bias_tempco;
	for (unsigned g = 0; g < G_COUNT; g++) {
		s->rng[g] = gsl_rng_alloc(gsl_rng_mt19937);
		if (!s->rng[g]) {
			sscope_sim_free(s);
			return -ENOMEM;
		}
	}
	if (spec->b > 0) {
		size_t J = (size_t)ceil(log(tmax / tmin) / log(GM_RATIO) - 1e-9) + 1;

		s->n_gm = J;
		s->gm_s = spec->b * sqrt(log(GM_RATIO) / PI);
		for (size_t j = 0; j < J; j++) {
			double T = tmin * pow(GM_RATIO, (double)j);
			double phi = exp(-s->dt / T);

			s->gm_phi[j] = phi;
			s->gm_lam[j] = s->dt / T;
			s->gm_in[j] = s->gm_s * sqrt(-expm1(-2 * s->dt / T));
		}
	}
	sscope_sim_reset(s);
	*simp = s;
	return 0;
}

uint64_t sscope_sim_position(const struct sscope_sim *s)
{
	return s->k;
}

uint64_t sscope_sim_clipped(const struct sscope_sim *s)
{
	return s->clipped;
}

/* temperature of the profile at t and its rate of change */
static void profile(const struct sscope_sim *s, double t, double *T,
		    double *dTdt)
{
	const struct sscope_sim_opts *o = &s->o;

	switch (o->temp_profile) {
	case SSCOPE_SIM_TEMP_RAMP: {
		double v = o->temp_degc + o->temp_rate_degc_s * t;
		bool up = o->temp_rate_degc_s >= 0;

		if ((up && v >= o->temp2_degc) || (!up && v <= o->temp2_degc)) {
			*T = o->temp2_degc;
			*dTdt = 0;
		} else {
			*T = v;
			*dTdt = o->temp_rate_degc_s;
		}
		break;
	}
	case SSCOPE_SIM_TEMP_CYCLE: {
		double a = o->temp_degc, b = o->temp2_degc, P = o->temp_period_s;
		double ph = fmod(t / P, 1.0);

		if (o->temp_wave == SSCOPE_SIM_SINE) {
			*T = a + (b - a) * 0.5 * (1 - cos(2 * PI * ph));
			*dTdt = (b - a) * PI / P * sin(2 * PI * ph);
		} else if (ph < 0.5) {
			*T = a + (b - a) * 2 * ph;
			*dTdt = 2 * (b - a) / P;
		} else {
			*T = b - (b - a) * 2 * (ph - 0.5);
			*dTdt = -2 * (b - a) / P;
		}
		break;
	}
	default:
		*T = o->temp_degc;
		*dTdt = 0;
		break;
	}
}

int sscope_sim_generate(struct sscope_sim *s, const double *input,
			double *out, double *temp_degc, size_t n)
{
	const struct sscope_sensor_spec *sp = &s->spec;
	const struct sscope_sim_opts *o = &s->o;
	const bool given = o->temp_profile == SSCOPE_SIM_TEMP_GIVEN;
	const double dt = s->dt, fs = o->rate_hz;
	const double sn = sp->n * sqrt(fs), sk = sp->k * sqrt(dt);
	const double range = (sp->has & SSCOPE_SENSOR_HAS_RANGE) && !o->no_clip ?
				     sp->range :
				     (double)INFINITY;
	const bool thermal = s->poly[0] != 0 || s->poly[1] != 0 ||
			     s->poly[2] != 0 || s->poly[3] != 0 ||
			     o->hysteresis != 0 || o->gradient != 0;

	if (!out || (given && !temp_degc))
		return -EINVAL;
	if (given)
		for (size_t i = 0; i < n; i++)
			if (!isfinite(temp_degc[i]))
				return -EINVAL;
	for (size_t i = 0; i < n; i++) {
		const double t = (double)s->k * dt;
		double T, dTdt, v = sp->bias;

		if (given) {
			T = temp_degc[i];
			dTdt = s->have_prev ? (T - s->t_prev) * fs : 0;
			s->t_prev = T;
			s->have_prev = true;
		} else {
			profile(s, t, &T, &dTdt);
		}
		if (thermal) {
			double d = T - o->ref_temp_degc, b = 0;

			for (int j = SSCOPE_SIM_MAX_POLY - 1; j >= 0; j--)
				b = (b + s->poly[j]) * d;
			v += b;
			if (dTdt > o->hysteresis_deadband_degc_s)
				s->hyst = 1;
			else if (dTdt < -o->hysteresis_deadband_degc_s)
				s->hyst = -1;
			v += 0.5 * o->hysteresis * s->hyst + o->gradient * dTdt;
		}
		if (input)
			v += (1 + sp->scale_factor_error) * input[i];
		if (sp->q > 0) {
			double e = sp->q * gauss(s->rng[G_Q]);

			v += (e - s->e_prev) * fs;
			s->e_prev = e;
		}
		if (sn > 0)
			v += sn * gauss(s->rng[G_N]);
		if (s->n_gm) {
			double b = 0;

			for (size_t j = 0; j < s->n_gm; j++) {
				s->gm[j] = s->gm_phi[j] * s->gm[j] +
					   s->gm_in[j] * gauss(s->rng[G_B]);
				b += s->gm[j];
			}
			v += b;
		}
		if (sk > 0) {
			s->rw += sk * gauss(s->rng[G_K]);
			v += s->rw;
		}
		if (sp->r > 0)
			v += sp->r * t;
		for (size_t j = 0; j < o->n_tones; j++)
			v += o->tones[j].amplitude *
			     sin(2 * PI * o->tones[j].freq_hz * t +
				 o->tones[j].phase_rad);
		if (o->quant_step > 0)
			v = o->quant_step * round(v / o->quant_step);
		if (v > range || v < -range) {
			v = v > 0 ? range : -range;
			s->clipped++;
		}
		out[i] = v;
		if (temp_degc && !given)
			temp_degc[i] = T + (o->temp_noise_degc > 0 ?
						    o->temp_noise_degc *
							    gauss(s->rng[G_T]) :
						    0);
		s->k++;
	}
	return 0;
}

int sscope_sim_generate_multi(struct sscope_sim *const *sims, size_t n_sims,
			      const double *const *in, double *const *out,
			      double *const *temp, size_t n)
{
	int rc = 0;

	if (!sims || !out)
		return -EINVAL;
SSC_OMP(omp parallel for schedule(dynamic, 1))
	for (size_t j = 0; j < n_sims; j++) {
		int r = sscope_sim_generate(sims[j], in ? in[j] : NULL, out[j],
					    temp ? temp[j] : NULL, n);

		if (r) {
SSC_OMP(omp critical(ssc_sim_rc))
			if (!rc)
				rc = r;
		}
	}
	return rc;
}

/*
 * Allan variance at m samples of a stationary AR(1) process of variance v
 * and lag-1 correlation exp(-lam): v D / m^2 with
 * D = (E[(S_2 - S_1)^2]) / (2 v) = sum_L c_L exp(-lam L), S_1, S_2 the sums
 * of two adjacent blocks of m samples, c_0 = m, c_L = 2m - 3L (0 < L < m),
 * c_L = L - 2m (m <= L < 2m).  In closed form
 * D = m + a (2 m q - u (3 - p)) / q^2 (a = e^-lam, q = 1 - a, p = a^m,
 * u = 1 - p), which cancels catastrophically when lam m is small; there
 * D = sum_k (-lam)^k M_k / k! with the moments M_k = sum_L c_L L^k, exact
 * polynomials in m (below, k = 1..10; degree k + 2).  Both branches are
 * within 2e-13 of a 60-digit evaluation.
 */
static const double mk_poly[10][13] = {
	{ 0, -1.0 / 3, 0, -2.0 / 3, 0, 0, 0, 0, 0, 0, 0, 0 },
	{ 0, 0, 0, 0, -1, 0, 0, 0, 0, 0, 0, 0 },
	{ 0, 1.0 / 15, 0, 1.0 / 3, 0, -7.0 / 5, 0, 0, 0, 0, 0, 0 },
	{ 0, 0, 0, 0, 1, 0, -2, 0, 0, 0, 0, 0 },
	{ 0, -1.0 / 21, 0, -1.0 / 3, 0, 7.0 / 3, 0, -62.0 / 21, 0, 0, 0, 0 },
	{ 0, 0, 0, 0, -3.0 / 2, 0, 5, 0, -9.0 / 2, 0, 0, 0 },
	{ 0, 1.0 / 15, 0, 5.0 / 9, 0, -49.0 / 10, 0, 31.0 / 3, 0, -127.0 / 18, 0, 0 },
	{ 0, 0, 0, 0, 10.0 / 3, 0, -14, 0, 21, 0, -34.0 / 3, 0 },
	{ 0, -5.0 / 33, 0, -7.0 / 5, 0, 14, 0, -186.0 / 5, 0, 127.0 / 3, 0, -1022.0 / 55 },
	{ 0, 0, 0, 0, -21.0 / 2, 0, 50, 0, -189.0 / 2, 0, 85, 0, -31 },
};

static double ar1_avar(double v, double lam, double m)
{
	double D;

	if (lam * m >= 0.05) {
		double a = exp(-lam), q = -expm1(-lam), p = exp(-lam * m);
		double u = -expm1(-lam * m);

		D = m + a * (2 * m * q - u * (3 - p)) / (q * q);
	} else {
		double f = 1, pw = 1;

		D = 0;
		for (int k = 1; k <= 10; k++) {
			double mk = 0;

			f *= k;
			pw *= -lam;
			for (int j = k + 2; j >= 0; j--)
				mk = mk * m + mk_poly[k - 1][j];
			D += pw * mk / f;
		}
	}
	return v * D / (m * m);
}

double sscope_sim_avar(const struct sscope_sim *s, double tau_s)
{
	const struct sscope_sensor_spec *sp = &s->spec;
	double m = round(tau_s / s->dt), tau, a;

	if (m < 1)
		m = 1;
	tau = m * s->dt;
	a = 3 * sp->q * sp->q / (tau * tau) + sp->n * sp->n / tau +
	    sp->k * sp->k * tau / 3 + sp->k * sp->k * s->dt * s->dt / (6 * tau) +
	    sp->r * sp->r * tau * tau / 2;
	for (size_t j = 0; j < s->n_gm; j++)
		a += ar1_avar(s->gm_s * s->gm_s, s->gm_lam[j], m);
	return a;
}
