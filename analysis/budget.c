/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Drift budget of a strapdown navigator, one horizontal channel (textbook eqs
 * 95-101; D. H. Titterton and J. L. Weston, "Strapdown Inertial Navigation
 * Technology", 2nd ed., 2004, ch. 12 "Inertial navigation system error
 * analysis": the single-channel error model with Schuler feedback).
 *
 * Error dynamics: dv/dt = b_a + w_a - g phi, dphi/dt = v / R + b_g + w_g,
 * dx/dt = v.  Open loop drops the v / R feedback (valid for t << 1/omega_s,
 * omega_s = sqrt(g/R)); the Schuler-bounded forms solve the full
 * second-order system.  Random walks: the variances are integrals of the
 * squared impulse responses of the channel (Wiener process through a linear
 * system): for white gyro noise of density N, var(att) = N^2 int cos^2,
 * var(vel) = (gN/w)^2 int sin^2, var(pos) = (gN/w^2)^2 int (1 - cos)^2;
 * for white accelerometer noise var(vel) = N^2 int cos^2,
 * var(pos) = (N/w)^2 int sin^2, var(att) = (N/(R w))^2 int sin^2; in the
 * limit w t -> 0 they become N^2 t, g^2 N^2 t^3/3, g^2 N^2 t^5/20, and
 * N^2 t^3/3.  Short arguments use series to avoid cancellation.
 *
 * The Monte-Carlo check draws each step's joint increment of (walk,
 * integral, double integral) from its exact covariance (Cholesky of
 * N^2 h [1 1/2 1/6; 1/2 1/3 1/8; 1/6 1/8 1/20] in the scaled variables
 * (walk, integral / h, double integral / h^2)), so the simulated variances
 * equal the closed forms at every step -- including the asked times, which
 * split the uniform grid -- and the only deviation is sampling error.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "sscope-budget.h"
#include "sscope-calib.h"
#include "sscope-quantity.h"
#include "sscope-unit.h"

static const char *const source_names[SSCOPE_BUDGET_N_SOURCES] = {
	"gyro_bias", "accel_bias", "arw", "vrw", "scale_factor"
};

const char *sscope_budget_source_name(enum sscope_budget_source s)
{
	if ((unsigned)s >= SSCOPE_BUDGET_N_SOURCES)
		return NULL;
	return source_names[s];
}

bool sscope_budget_source_random(enum sscope_budget_source s)
{
	return s == SSCOPE_BUDGET_ARW || s == SSCOPE_BUDGET_VRW;
}

static double grav(const struct sscope_budget_params *p)
{
	return p->gravity_m_s2 > 0 ? p->gravity_m_s2 : SSCOPE_UNIT_GRAVITY_STD;
}

static double radius(const struct sscope_budget_params *p)
{
	return p->radius_m > 0 ? p->radius_m : SSCOPE_BUDGET_EARTH_RADIUS_M;
}

double sscope_budget_schuler_rad_s(const struct sscope_budget_params *p)
{
	return sqrt(grav(p) / radius(p));
}

bool sscope_budget_is_schuler(const struct sscope_budget_params *p,
			      double t_s)
{
	double sw = p->switch_time_s > 0 ? p->switch_time_s : 300;

	if (p->model == SSCOPE_BUDGET_SCHULER)
		return true;
	if (p->model == SSCOPE_BUDGET_OPEN_LOOP)
		return false;
	return t_s > sw;
}

/* int_0^x sin^2 u du */
static double f_sin2(double x)
{
	if (x < 0.05)
		return x * x * x / 3 - pow(x, 5) / 15 + 2 * pow(x, 7) / 315;
	return x / 2 - sin(2 * x) / 4;
}

/* int_0^x cos^2 u du */
static double f_cos2(double x)
{
	return x / 2 + sin(2 * x) / 4;
}

/* int_0^x (1 - cos u)^2 du */
static double f_omc2(double x)
{
	if (x < 0.05)
		return pow(x, 5) / 20 - pow(x, 7) / 168 + pow(x, 9) / 2880;
	return 1.5 * x - 2 * sin(x) + sin(2 * x) / 4;
}

/* x - sin x */
static double x_minus_sin(double x)
{
	if (x < 0.05)
		return x * x * x / 6 - pow(x, 5) / 120 + pow(x, 7) / 5040;
	return x - sin(x);
}

/* 1 - cos x */
static double one_minus_cos(double x)
{
	double s = sin(x / 2);

	return 2 * s * s;
}

static void gyro_bias_pt(double b, double t, bool sch, double g, double R,
			 double w, struct sscope_budget_point *o)
{
	if (!sch) {
		o->attitude_rad = b * t;
		o->velocity_m_s = g * b * t * t / 2;
		o->position_m = g * b * t * t * t / 6;
	} else {
		double x = w * t;

		o->attitude_rad = b / w * fabs(sin(x));
		o->velocity_m_s = R * b * one_minus_cos(x);
		o->position_m = R * b / w * x_minus_sin(x);
	}
}

static void accel_bias_pt(double b, double t, bool sch, double g, double w,
			  struct sscope_budget_point *o)
{
	if (!sch) {
		o->attitude_rad = 0;
		o->velocity_m_s = b * t;
		o->position_m = b * t * t / 2;
	} else {
		double x = w * t;

		o->attitude_rad = b / g * one_minus_cos(x);
		o->velocity_m_s = b / w * fabs(sin(x));
		o->position_m = b / (w * w) * one_minus_cos(x);
	}
}

int sscope_budget_source_eval(const struct sscope_budget_params *p,
			      enum sscope_budget_source s, double t_s,
			      struct sscope_budget_point *o)
{
	double g, R, w, t = t_s;
	bool sch;
	const double in[8] = { p ? p->gyro_bias_rad_s : 0,
			       p ? p->accel_bias_m_s2 : 0,
			       p ? p->arw_rad_sqrt_s : 0,
			       p ? p->vrw_m_s_sqrt_s : 0,
			       p ? p->gyro_sf : 0,
			       p ? p->accel_sf : 0,
			       p ? p->turn_rate_rad_s : 0,
			       p ? p->accel_profile_m_s2 : 0 };

	if (!p || !o || !(t_s >= 0) || !isfinite(t_s) ||
	    (unsigned)s >= SSCOPE_BUDGET_N_SOURCES)
		return -EINVAL;
	for (int i = 0; i < 8; i++)
		if (!isfinite(in[i]))
			return -EINVAL;
	if (p->gravity_m_s2 < 0 || p->radius_m < 0 || p->switch_time_s < 0)
		return -EINVAL;
	g = grav(p);
	R = radius(p);
	w = sqrt(g / R);
	sch = sscope_budget_is_schuler(p, t);
	memset(o, 0, sizeof(*o));
	switch (s) {
	case SSCOPE_BUDGET_GYRO_BIAS:
		gyro_bias_pt(fabs(p->gyro_bias_rad_s), t, sch, g, R, w, o);
		break;
	case SSCOPE_BUDGET_ACCEL_BIAS:
		accel_bias_pt(fabs(p->accel_bias_m_s2), t, sch, g, w, o);
		break;
	case SSCOPE_BUDGET_ARW: {
		double N = fabs(p->arw_rad_sqrt_s);

		if (!sch) {
			o->attitude_rad = N * sqrt(t);
			o->velocity_m_s = g * N * sqrt(t * t * t / 3);
			o->position_m = g * N * sqrt(pow(t, 5) / 20);
		} else {
			double x = w * t;

			o->attitude_rad = N * sqrt(f_cos2(x) / w);
			o->velocity_m_s = g * N * sqrt(f_sin2(x) / (w * w * w));
			o->position_m = g * N * sqrt(f_omc2(x) / pow(w, 5));
		}
		break;
	}
	case SSCOPE_BUDGET_VRW: {
		double N = fabs(p->vrw_m_s_sqrt_s);

		if (!sch) {
			o->attitude_rad = 0;
			o->velocity_m_s = N * sqrt(t);
			o->position_m = N * sqrt(t * t * t / 3);
		} else {
			double x = w * t;

			o->velocity_m_s = N * sqrt(f_cos2(x) / w);
			o->position_m = N * sqrt(f_sin2(x) / (w * w * w));
			o->attitude_rad = N / R * sqrt(f_sin2(x) / (w * w * w));
		}
		break;
	}
	case SSCOPE_BUDGET_SCALE_FACTOR: {
		struct sscope_budget_point a, b;

		gyro_bias_pt(fabs(p->gyro_sf * p->turn_rate_rad_s), t, sch, g, R,
			     w, &a);
		accel_bias_pt(fabs(p->accel_sf * p->accel_profile_m_s2), t, sch,
			      g, w, &b);
		o->attitude_rad = a.attitude_rad + b.attitude_rad;
		o->velocity_m_s = a.velocity_m_s + b.velocity_m_s;
		o->position_m = a.position_m + b.position_m;
		break;
	}
	default:
		return -EINVAL;
	}
	return 0;
}

/* root sum of squares, scaled by the largest term (neither 1e200^2 nor
 * 1e-200^2 leaves the double range) */
static double rss(const double *v, int n)
{
	double m = 0, s = 0;

	for (int i = 0; i < n; i++)
		m = fmax(m, fabs(v[i]));
	if (!(m > 0) || !isfinite(m))
		return m;
	for (int i = 0; i < n; i++)
		s += (v[i] / m) * (v[i] / m);
	return m * sqrt(s);
}

int sscope_budget_total(const struct sscope_budget_params *p, double t_s,
			struct sscope_budget_point *out)
{
	double a[SSCOPE_BUDGET_N_SOURCES], v[SSCOPE_BUDGET_N_SOURCES],
		x[SSCOPE_BUDGET_N_SOURCES];

	if (!out)
		return -EINVAL;
	for (int s = 0; s < SSCOPE_BUDGET_N_SOURCES; s++) {
		struct sscope_budget_point pt;
		int rc = sscope_budget_source_eval(p, (enum sscope_budget_source)s,
						   t_s, &pt);

		if (rc)
			return rc;
		a[s] = pt.attitude_rad;
		v[s] = pt.velocity_m_s;
		x[s] = pt.position_m;
	}
	out->attitude_rad = rss(a, SSCOPE_BUDGET_N_SOURCES);
	out->velocity_m_s = rss(v, SSCOPE_BUDGET_N_SOURCES);
	out->position_m = rss(x, SSCOPE_BUDGET_N_SOURCES);
	if (!isfinite(out->attitude_rad) || !isfinite(out->velocity_m_s) ||
	    !isfinite(out->position_m))
		return -ERANGE;
	return 0;
}

static int value_at(const struct sscope_budget_params *p, int source,
		    enum sscope_budget_quantity what, double t, double *v)
{
	struct sscope_budget_point pt;
	int rc = source < 0 ? sscope_budget_total(p, t, &pt) :
			      sscope_budget_source_eval(p,
							(enum sscope_budget_source)source,
							t, &pt);

	if (rc)
		return rc;
	*v = what == SSCOPE_BUDGET_POSITION ? pt.position_m :
	     what == SSCOPE_BUDGET_VELOCITY ? pt.velocity_m_s :
					      pt.attitude_rad;
	return 0;
}

int sscope_budget_time_to(const struct sscope_budget_params *p, int source,
			  enum sscope_budget_quantity what, double target,
			  double t_max_s, double *t_s)
{
	double lo = 0, hi, v;
	int rc;

	if (!p || !t_s || !(target > 0) || !(t_max_s > 0) ||
	    source >= SSCOPE_BUDGET_N_SOURCES || (unsigned)what > 2)
		return -EINVAL;
	hi = fmin(1e-3, t_max_s);
	for (;;) {
		rc = value_at(p, source, what, hi, &v);
		if (rc)
			return rc;
		if (v >= target)
			break;
		if (hi >= t_max_s)
			return -EDOM;
		lo = hi;
		hi = fmin(hi * 1.02, t_max_s);
	}
	while (hi - lo > 1e-9 * hi) {
		double mid = 0.5 * (lo + hi);

		rc = value_at(p, source, what, mid, &v);
		if (rc)
			return rc;
		if (v >= target)
			hi = mid;
		else
			lo = mid;
	}
	*t_s = hi;
	return 0;
}

/* Cholesky factor of a symmetric positive definite n x n (n <= 3). */
int sscope_budget_dominant(const struct sscope_budget_params *p, double t_s,
			   double *position_m)
{
	int best = -1;
	double bv = 0;

	for (int s = 0; s < SSCOPE_BUDGET_N_SOURCES; s++) {
		struct sscope_budget_point pt;

		if (sscope_budget_source_eval(p, (enum sscope_budget_source)s,
					      t_s, &pt))
			return -1;
		if (pt.position_m > bv) {
			bv = pt.position_m;
			best = s;
		}
	}
	if (position_m)
		*position_m = bv;
	return best;
}

int sscope_budget_crossovers(const struct sscope_budget_params *p,
			     double t0_s, double t1_s,
			     struct sscope_budget_crossover *out, size_t max,
			     size_t *n_out)
{
	size_t n = 0;
	double prev_t = t0_s;
	int prev;

	if (!p || !n_out || (max && !out) || !(t0_s > 0) || !(t1_s >= t0_s))
		return -EINVAL;
	prev = sscope_budget_dominant(p, t0_s, NULL);
	for (double t = t0_s * 1.01; t <= t1_s * 1.0001 && n < max; t *= 1.01) {
		int d = sscope_budget_dominant(p, t, NULL);

		if (d != prev && prev >= 0 && d >= 0) {
			double lo = prev_t, hi = t;

			for (int it = 0; it < 60; it++) {
				double mid = 0.5 * (lo + hi);

				if (sscope_budget_dominant(p, mid, NULL) == prev)
					lo = mid;
				else
					hi = mid;
			}
			out[n].t_s = hi;
			out[n].from = (enum sscope_budget_source)prev;
			out[n].to = (enum sscope_budget_source)d;
			n++;
		}
		prev = d;
		prev_t = t;
	}
	*n_out = n;
	return 0;
}

/* the larger of *dst and |v| into *dst; true when v raised it */
static bool raise_to(double *dst, double v)
{
	if (isfinite(v) && fabs(v) > fabs(*dst)) {
		*dst = fabs(v);
		return true;
	}
	return false;
}

unsigned sscope_budget_take_noise(struct sscope_budget_params *p,
				  enum sscope_quantity q, double n_si,
				  double b_si, unsigned keep, bool *used)
{
	bool gyro = q == SSCOPE_QUANTITY_ANGULAR_RATE;
	int bias = gyro ? SSCOPE_BUDGET_GYRO_BIAS : SSCOPE_BUDGET_ACCEL_BIAS;
	int walk = gyro ? SSCOPE_BUDGET_ARW : SSCOPE_BUDGET_VRW;
	unsigned raised = 0;

	if (used)
		*used = false;
	if (!p || (!gyro && q != SSCOPE_QUANTITY_ACCELERATION))
		return 0;
	if (!(keep & (1u << walk))) {
		if (raise_to(gyro ? &p->arw_rad_sqrt_s : &p->vrw_m_s_sqrt_s, n_si))
			raised |= 1u << walk;
		if (used)
			*used = true;
	}
	if (!(keep & (1u << bias)) && isfinite(b_si)) {
		if (raise_to(gyro ? &p->gyro_bias_rad_s : &p->accel_bias_m_s2, b_si))
			raised |= 1u << bias;
		if (used)
			*used = true;
	}
	return raised;
}

unsigned sscope_budget_take_calib(struct sscope_budget_params *p,
				  enum sscope_quantity q,
				  const struct sscope_calib_triad *c,
				  double noise_density, unsigned keep)
{
	bool gyro = q == SSCOPE_QUANTITY_ANGULAR_RATE;
	int bias = gyro ? SSCOPE_BUDGET_GYRO_BIAS : SSCOPE_BUDGET_ACCEL_BIAS;
	int walk = gyro ? SSCOPE_BUDGET_ARW : SSCOPE_BUDGET_VRW;
	unsigned raised = 0;

	if (!p || !c || (!gyro && q != SSCOPE_QUANTITY_ACCELERATION))
		return 0;
	for (int k = 0; k < 3; k++) {
		/* bias sd in input units -> output SI through the scale */
		if (!(keep & (1u << bias)) && isfinite(c->bias_sd[k]) &&
		    raise_to(gyro ? &p->gyro_bias_rad_s : &p->accel_bias_m_s2,
			     c->bias_sd[k] * c->scale[k]))
			raised |= 1u << bias;
		if (isfinite(c->scale_sd[k]) && c->scale[k] != 0)
			raise_to(gyro ? &p->gyro_sf : &p->accel_sf,
				 c->scale_sd[k] / c->scale[k]);
	}
	if (!(keep & (1u << walk)) &&
	    raise_to(gyro ? &p->arw_rad_sqrt_s : &p->vrw_m_s_sqrt_s,
		     noise_density))
		raised |= 1u << walk;
	return raised;
}

static int chol(int n, double A[3][3], double L[3][3])
{
	memset(L, 0, 9 * sizeof(double));
	for (int i = 0; i < n; i++)
		for (int j = 0; j <= i; j++) {
			double s = A[i][j];

			for (int k = 0; k < j; k++)
				s -= L[i][k] * L[j][k];
			if (i == j) {
				if (!(s > 0))
					return -EDOM;
				L[i][i] = sqrt(s);
			} else {
				L[i][j] = s / L[j][j];
			}
		}
	return 0;
}

/* A step of the simulation: length h, then the checkpoint ck (or -1) and
 * whether it ends on the uniform grid (node, for the paths). */
struct seg {
	double h;
	long ck;
	long node;
};

static int cmp_time(const void *a, const void *b)
{
	const double *x = *(const double *const *)a, *y = *(const double *const *)b;

	return (*x > *y) - (*x < *y);
}

int sscope_budget_mc(const struct sscope_budget_mc_opts *o,
		     const double *times, size_t n_times,
		     struct sscope_budget_mc_point *out, double *paths,
		     size_t n_paths)
{
	/* the joint increment of (walk, int walk / h, int int walk / h^2)
	 * over a step h has covariance N^2 h * Q0 (Q0 independent of h) */
	double Q0[3][3] = { { 1, 0.5, 1.0 / 6 },
			    { 0.5, 1.0 / 3, 0.125 },
			    { 1.0 / 6, 0.125, 0.05 } };
	double h, N, g, L[3][3];
	const double **ord = NULL;
	struct seg *sg = NULL;
	double *sw = NULL, *sp = NULL, *iw = NULL, *ip = NULL;
	size_t nseg = 0;
	int dim, rc = 0, ne = 0;
	gsl_rng *r = NULL;

	if (!o || (n_times && (!times || !out)) || o->steps == 0 ||
	    o->realisations == 0 || !(o->t_end_s > 0) || !(o->strength > 0) ||
	    !isfinite(o->strength) || !isfinite(o->t_end_s))
		return -EINVAL;
	for (size_t j = 0; j < n_times; j++)
		if (!(times[j] > 0) || times[j] > o->t_end_s * (1 + 1e-12))
			return -EINVAL;
	h = o->t_end_s / (double)o->steps;
	/* the walks are linear in N: simulated with N scaled by a power of
	 * two into [0.5, 1) when it is extreme (1e-300 squared underflows),
	 * results scaled back by 2^ne */
	N = o->strength;
	if (ssc_safe_scale(N) != 1)
		frexp(N, &ne);
	N = ldexp(N, -ne);
	g = o->gravity_m_s2 > 0 ? o->gravity_m_s2 : SSCOPE_UNIT_GRAVITY_STD;
	dim = o->gyro ? 3 : 2;
	if (chol(dim, Q0, L))
		return -EINVAL;
	ord = ssc_alloc_array(n_times ? n_times : 1, sizeof(*ord));
	sg = ssc_alloc_array(o->steps + n_times + 1, sizeof(*sg));
	sw = calloc(n_times ? n_times : 1, sizeof(double));
	sp = calloc(n_times ? n_times : 1, sizeof(double));
	iw = calloc(n_times ? n_times : 1, sizeof(double));
	ip = calloc(n_times ? n_times : 1, sizeof(double));
	r = gsl_rng_alloc(gsl_rng_mt19937);
	if (!ord || !sg || !sw || !sp || !iw || !ip || !r) {
		rc = -ENOMEM;
		goto out;
	}
	/* segments: the uniform grid split at every checkpoint */
	for (size_t j = 0; j < n_times; j++)
		ord[j] = &times[j];
	qsort(ord, n_times, sizeof(*ord), cmp_time);
	{
		size_t j = 0;
		double t = 0;

		for (size_t k = 1; k <= o->steps; k++) {
			double tk = k == o->steps ? o->t_end_s : (double)k * h;

			while (j < n_times && *ord[j] < tk - 1e-9 * h) {
				if (*ord[j] - t > 1e-9 * h) {
					sg[nseg].h = *ord[j] - t;
					sg[nseg].ck = -1;
					sg[nseg].node = -1;
					t = *ord[j];
					nseg++;
				}
				/* a checkpoint at the current time */
				if (nseg == 0) {
					sg[nseg].h = 0;
					sg[nseg].node = -1;
					nseg++;
				}
				sg[nseg - 1].ck = ord[j] - times;
				j++;
				if (j < n_times && *ord[j] - t <= 1e-9 * h) {
					/* duplicates: a zero step */
					sg[nseg].h = 0;
					sg[nseg].node = -1;
					sg[nseg].ck = -1;
					nseg++;
				}
			}
			sg[nseg].h = tk - t;
			sg[nseg].ck = -1;
			sg[nseg].node = (long)k;
			t = tk;
			nseg++;
			while (j < n_times && fabs(*ord[j] - tk) <= 1e-9 * h) {
				if (sg[nseg - 1].ck >= 0) {
					sg[nseg].h = 0;
					sg[nseg].node = -1;
					nseg++;
				}
				sg[nseg - 1].ck = ord[j] - times;
				j++;
			}
		}
	}
	gsl_rng_set(r, o->seed);
	for (size_t m = 0; m < o->realisations; m++) {
		double s[3] = { 0, 0, 0 };
		double *path = paths && m < n_paths ? paths + m * (o->steps + 1) :
						      NULL;

		if (path)
			path[0] = 0;
		for (size_t q = 0; q < nseg; q++) {
			double hh = sg[q].h;

			if (hh > 0) {
				double z[3], e[3], sc = N * sqrt(hh);

				for (int i = 0; i < dim; i++)
					z[i] = gsl_ran_gaussian_ziggurat(r, 1);
				for (int i = 0; i < dim; i++) {
					e[i] = 0;
					for (int j = 0; j <= i; j++)
						e[i] += L[i][j] * z[j];
					e[i] *= sc * (i == 0 ? 1 : i == 1 ? hh : hh * hh);
				}
				if (o->gyro) {
					s[2] += hh * s[1] + hh * hh / 2 * s[0] + e[2];
					s[1] += hh * s[0] + e[1];
					s[0] += e[0];
				} else {
					s[1] += hh * s[0] + e[1];
					s[0] += e[0];
				}
			}
			if (path && sg[q].node >= 0)
				path[sg[q].node] = ldexp(s[0], ne);
			if (sg[q].ck >= 0) {
				size_t j = (size_t)sg[q].ck;
				double t = times[j], wsd, psd, pos;

				wsd = N * sqrt(t);
				pos = o->gyro ? g * s[2] : s[1];
				psd = o->gyro ? g * N * sqrt(pow(t, 5) / 20) :
						N * sqrt(t * t * t / 3);
				sw[j] += s[0] * s[0];
				sp[j] += pos * pos;
				iw[j] += fabs(s[0]) <= 2 * wsd;
				ip[j] += fabs(pos) <= 2 * psd;
			}
		}
	}
	for (size_t j = 0; j < n_times; j++) {
		double t = times[j], M = (double)o->realisations;

		out[j].t_s = t;
		out[j].walk_sd = ldexp(sqrt(sw[j] / M), ne);
		out[j].walk_sd_theory = ldexp(N * sqrt(t), ne);
		out[j].walk_inside = iw[j] / M;
		out[j].pos_sd = ldexp(sqrt(sp[j] / M), ne);
		out[j].pos_sd_theory = ldexp(o->gyro ? g * N * sqrt(pow(t, 5) / 20) :
						       N * sqrt(t * t * t / 3),
					     ne);
		out[j].pos_inside = ip[j] / M;
	}
out:
	free(ord);
	free(sg);
	free(sw);
	free(sp);
	free(iw);
	free(ip);
	gsl_rng_free(r);
	return rc;
}

double sscope_budget_mc_expected(size_t realisations, double *sd)
{
	double p = erf(sqrt(2.0));

	if (sd)
		*sd = realisations ? sqrt(p * (1 - p) / (double)realisations) :
				     (double)NAN;
	return p;
}
