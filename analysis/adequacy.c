/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The adequacy check of a noise fit (see sscope-adequacy.h): what a record
 * can and cannot support.
 *
 * - Stillness: walk's test (ssc_still_contrast(), the static detector of
 *   Tedaldi, Pretto and Menegatti, ICRA 2014, as a contrast of deciles).
 * - Fit: the chi-squared test of sscope_noise_fit() (IEEE Std 952-1997
 *   Annex C model).
 * - Length: where each requested term, at the bound its fit puts on it,
 *   would dominate the fitted model.
 * - Stationarity: the differences of block means are the terms of the
 *   Allan variance at tau = one block (IEEE 952, NIST SP 1065); for a
 *   noise with stationary increments their covariance follows from the
 *   structure function of the integrated rate (sscope-heading.h:
 *   Cov(sum a X, sum b X) = -sum a_i b_j D(|t_i - t_j|) for combinations
 *   with sum a = sum b = 0).  With Q and N from the fit and B and K by
 *   maximum likelihood (Gaussian; the covariance is Toeplitz, factored by
 *   the Levinson-Durbin recursion), a
 *   deterministic component (step, exponential transient, temperature
 *   dependence) is tested by the likelihood ratio; the largest statistic
 *   over the candidates (steps at every half block, transient time
 *   constants on an octave grid) is calibrated by drawing the whitened
 *   null.
 * - DAVAR: OADEV in sliding windows (Galleani and Tavella, "The dynamic
 *   Allan variance", IEEE Trans. UFFC 56(3), 2009), through the library's
 *   deviation engine.
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "sscope-adequacy.h"
#include "sscope-allan.h"
#include "sscope-heading.h"
#include "sscope-noise.h"

#define ALL_TERMS 0x1fu
#define MAX_BLOCKS 256
#define MIN_BLOCK_SAMPLES 8
/* the Allan variance of a detected component must reach this share of
 * the model's for the deviation to change by 10 % */
#define AFFECT_SHARE 0.21
#define MAX_FINDINGS 16

bool sscope_adequacy_term_established(const struct sscope_noise_coef *c)
{
	/* the one place that decides presence: the fit's "resolved" today */
	return c && sscope_noise_coef_resolved(c);
}

const char *sscope_adequacy_cause_name(enum sscope_adequacy_cause c)
{
	static const char *const n[] = { "moves", "no_fit", "fit_rejected",
					 "short", "warm_up", "step",
					 "temperature", "ramp", "unchecked" };

	return (unsigned)c < sizeof(n) / sizeof(n[0]) ? n[c] : "?";
}

const char *sscope_adequacy_severity_name(enum sscope_adequacy_severity s)
{
	static const char *const n[] = { "note", "bound", "doubt", "invalid" };

	return (unsigned)s < sizeof(n) / sizeof(n[0]) ? n[s] : "?";
}

void sscope_adequacy_free(struct sscope_adequacy *r)
{
	if (!r)
		return;
	free(r->findings);
	free(r->davar.t_s);
	free(r->davar.tau_s);
	free(r->davar.dev);
	free(r->davar.edf);
	free(r->davar.model);
	free(r);
}

/* ------------------------------------------------------------ findings */

static struct sscope_adequacy_finding *
add_finding(struct sscope_adequacy *r, enum sscope_adequacy_cause cause,
	    enum sscope_adequacy_severity sev, unsigned terms)
{
	struct sscope_adequacy_finding *f;

	if (r->n_findings >= MAX_FINDINGS)
		return NULL;
	f = &r->findings[r->n_findings++];
	memset(f, 0, sizeof(*f));
	f->cause = cause;
	f->severity = sev;
	f->terms = terms;
	f->t_start_s = f->t_end_s = NAN;
	f->tau_min_s = f->tau_max_s = NAN;
	f->statistic = f->p_value = f->action_s = NAN;
	return f;
}

static void say(struct sscope_adequacy_finding *f, const char *fmt, ...)
	SSC_PRINTF(2, 3);

static void say(struct sscope_adequacy_finding *f, const char *fmt, ...)
{
	va_list ap;

	if (!f)
		return;
	va_start(ap, fmt);
	vsnprintf(f->message, sizeof(f->message), fmt, ap);
	va_end(ap);
}

/* "N, B and K" */
static const char *term_list(unsigned terms, char *buf, size_t len)
{
	size_t k = 0, n = 0, used = 0;

	for (int t = 0; t < 5; t++)
		n += (terms >> t) & 1;
	buf[0] = '\0';
	for (int t = 0; t < 5; t++) {
		int w;

		if (!((terms >> t) & 1))
			continue;
		w = snprintf(buf + used, len - used, "%s%c",
			     k == 0 ? "" : k + 1 == n ? " and " : ", ",
			     "QNBKR"[t]);
		if (w > 0 && (size_t)w < len - used)
			used += (size_t)w;
		k++;
	}
	return buf;
}

/* ------------------------------------------------------------ model */

/* the fitted model (unconstrained estimates; R included) at tau */
static double model_avar(const double est[5], double tau)
{
	return sscope_noise_avar(est, tau);
}

/* terms whose share of the model is the largest somewhere in [lo, hi] */
static unsigned dominant_terms(const double est[5], double lo, double hi)
{
	unsigned m = 0;

	if (!(hi >= lo) || !(lo > 0))
		return 0;
	for (int i = 0; i <= 24; i++) {
		double tau = lo * pow(hi / lo, i / 24.0), best = 0;
		int bt = -1;

		for (int t = 0; t < 5; t++) {
			double one[5] = { 0 }, v;

			one[t] = est[t];
			v = sscope_noise_avar(one, tau);
			if (v > best) {
				best = v;
				bt = t;
			}
		}
		if (bt >= 0)
			m |= 1u << bt;
	}
	return m;
}

/* ------------------------------------------------------------ length */

static void check_length(struct sscope_adequacy *r,
			 const struct sscope_noise_fit *fit,
			 const double est[5], double fs, double T)
{
	static const char *const names[5] = {
		"quantization Q", "random walk N", "bias instability B",
		"rate random walk K", "rate ramp R"
	};
	double tau_lo = 1 / fs, tau_hi = T / 2;

	for (int t = 0; t < 5; t++) {
		const struct sscope_noise_coef *c = &fit->coef[t];
		struct sscope_adequacy_finding *f;
		double rest[5], one[5] = { 0 }, a = NAN, b = NAN;

		if (!((r->requested >> t) & 1))
			continue;
		if (sscope_adequacy_term_established(c)) {
			r->established |= 1u << t;
			continue;
		}
		f = add_finding(r, SSCOPE_ADEQUACY_SHORT, SSCOPE_ADEQUACY_BOUND, 1u << t);
		if (!f)
			return;
		if (!(c->hi > 0) || !isfinite(c->hi)) {
			say(f, "%s not measured: the fit %s; the record gives no value for it",
			    names[t], isnan(c->hi) ? "was not allowed to use it" :
			    "puts no positive bound on it");
			continue;
		}
		memcpy(rest, est, sizeof(rest));
		rest[t] = 0;
		one[t] = c->hi;
		/* where the term at its bound would dominate the rest */
		for (int i = 0; i <= 160; i++) {
			double tau = tau_lo / 100 * pow(1e4 * T / (tau_lo / 100),
							i / 160.0);

			if (sscope_noise_avar(one, tau) >= sscope_noise_avar(rest, tau)) {
				if (!isfinite(a))
					a = tau;
				b = tau;
			}
		}
		f->tau_min_s = a;
		f->tau_max_s = b;
		if (!isfinite(a)) {
			say(f, "%s not established: even at its bound the other terms hide it at every tau; the record bounds it only",
			    names[t]);
		} else if (a > tau_hi) {
			f->action_s = 10 * a;
			say(f, "%s not established: at its bound it would dominate only from tau = %.3g s, beyond this %.3g s record's longest tau (%.3g s); record at least %.3g s (ten times that tau) to measure it",
			    names[t], a, T, tau_hi, f->action_s);
		} else if (b < tau_lo) {
			f->action_s = 1 / b;
			say(f, "%s not established: at its bound it would dominate only below tau = %.3g s, shorter than the sample interval; sample faster than %.3g Hz to measure it",
			    names[t], b, 1 / b);
		} else {
			f->action_s = 10 * T;
			say(f, "%s not established: the %.3g s record only bounds it, although at that bound it would dominate at tau = %.3g to %.3g s; a longer record narrows the bound (ten times longer: %.3g s)",
			    names[t], T, fmax(a, tau_lo), fmin(b, tau_hi),
			    f->action_s);
		}
	}
}

/* ------------------------------------------------------------ blocks */

/*
 * The differences d_k = ybar_{k+1} - ybar_k of M block means, k < P = M - 1,
 * have under the noise terms the Toeplitz covariance sum_t theta_t C_t
 * (theta_t the squared coefficient, C_t its unit covariance).  Q and N are
 * taken from the fit (the short taus fix them, and a slow anomaly does not
 * touch them); B and K are estimated by maximum likelihood under each
 * hypothesis, so that an anomaly the fit has absorbed into B or K (its
 * Allan variance looks like theirs) is not explained away by them.
 */
struct ml {
	size_t M, P;
	double Tb;
	double *ybar, *tbar;  /* M block means (record mean removed), temps */
	double *d;            /* P differences */
	double *col[4];       /* unit covariances (first columns): Q N B K */
	double th[4];         /* current squares */
	double sc[2];         /* scales of the B and K squares */
	double *r;            /* covariance of the differences at th: the
				 Toeplitz matrix's first column (P) */
	double *phi, *v;      /* its Levinson-Durbin factor */
	double *w;            /* work, P */
	double *X[6];         /* design columns (P), whitened copies in Xw */
	double *Xw[6], *dw, *q[6];
	size_t p;
};

static double dot(const double *a, const double *b, size_t n)
{
	double s = 0;

	for (size_t i = 0; i < n; i++)
		s += a[i] * b[i];
	return s;
}

/* Cov(d_0, d_h) under the terms coef (R excluded) */
static double dcov(const double coef[5], double Tb, size_t h)
{
	double t[6], c[6], v, v0;

	t[0] = 0;
	t[1] = Tb;
	t[2] = 2 * Tb;
	c[0] = 1 / Tb;
	c[1] = -2 / Tb;
	c[2] = 1 / Tb;
	v0 = sscope_heading_drift_var_points(coef, t, c, 3);
	if (h == 0)
		return v0;
	for (int i = 0; i < 3; i++) {
		t[3 + i] = (double)(h + (size_t)i) * Tb;
		c[3 + i] = c[i];
	}
	v = sscope_heading_drift_var_points(coef, t, c, 6);
	return (v - 2 * v0) / 2;
}

/*
 * The Levinson-Durbin recursion (J. Durbin, "The fitting of time-series
 * models", Rev. Int. Stat. Inst. 28, 1960; G. H. Golub, C. F. Van Loan,
 * Matrix Computations, 4th ed., algorithm 4.7.1): the forward predictors
 * of orders 1 .. P-1 and their error variances.  Written here because
 * neither GSL nor the CBLAS it ships has a Toeplitz factorisation; the
 * Gaussian likelihood of the block differences needs one per trial value
 * of the B and K squares (a few thousand per channel), and a dense
 * Cholesky factor costs P^3 / 3 where this costs 2 P^2.  For a positive
 * definite matrix it is as accurate as Cholesky's (G. Cybenko, SIAM J.
 * Sci. Stat. Comput. 1(3), 1980); tests/test-adequacy.c checks it
 * against GSL's Cholesky factor on these covariances.
 */
bool ssc_levinson(const double *r, size_t P, double *phi, double *v)
{
	if (P == 0 || !(r[0] > 0) || !isfinite(r[0]))
		return false;
	v[0] = r[0];
	for (size_t k = 1; k < P; k++) {
		const double *prev = phi + (k - 1) * (k - 2) / 2; /* k - 1 */
		double *cur = phi + (k - 1) * k / 2;              /* k */
		double acc = r[k], kappa;

		if (k == 1)
			prev = NULL;
		for (size_t j = 1; j < k; j++)
			acc -= prev[j - 1] * r[k - j];
		kappa = acc / v[k - 1];
		for (size_t j = 1; j < k; j++)
			cur[j - 1] = prev[j - 1] - kappa * prev[k - j - 1];
		cur[k - 1] = kappa;
		v[k] = v[k - 1] * (1 - kappa) * (1 + kappa);
		if (!(v[k] > 0) || !isfinite(v[k]))
			return false;
	}
	return true;
}

void ssc_levinson_whiten(const double *phi, const double *v, size_t P,
			 const double *x, double *out)
{
	/* from the last: out[k] needs x[0 .. k], untouched below k */
	for (size_t k = P; k-- > 0;) {
		const double *a = phi + (k > 0 ? (k - 1) * k / 2 : 0);
		double e = x[k];

		for (size_t j = 1; j <= k; j++)
			e -= a[j - 1] * x[k - j];
		out[k] = e / sqrt(v[k]);
	}
}

/* factor of the covariance at th; false when not positive definite */
static bool ml_factor(struct ml *m)
{
	for (size_t h = 0; h < m->P; h++) {
		double c = 0;

		for (int t = 0; t < 4; t++)
			c += m->th[t] * m->col[t][h];
		m->r[h] = c;
	}
	return ssc_levinson(m->r, m->P, m->phi, m->v);
}

static void ml_whiten(const struct ml *m, const double *in, double *out)
{
	ssc_levinson_whiten(m->phi, m->v, m->P, in, out);
}

/* orthonormalise the whitened design (modified Gram-Schmidt, twice) into
 * q; returns the rank; r[j] the norm of column j after the earlier ones */
static size_t ml_ortho(struct ml *m, double *r)
{
	size_t rank = 0;

	for (size_t j = 0; j < m->p; j++) {
		double *v = m->q[rank], n0, n;

		memcpy(v, m->Xw[j], m->P * sizeof(double));
		n0 = sqrt(dot(v, v, m->P));
		for (int pass = 0; pass < 2; pass++)
			for (size_t k = 0; k < rank; k++) {
				double c = dot(m->q[k], v, m->P);

				for (size_t i = 0; i < m->P; i++)
					v[i] -= c * m->q[k][i];
			}
		n = sqrt(dot(v, v, m->P));
		r[j] = n;
		if (!(n > 1e-9 * n0) || !(n0 > 0))
			continue;
		for (size_t i = 0; i < m->P; i++)
			v[i] /= n;
		rank++;
	}
	return rank;
}

/* Gaussian log-likelihood of d (up to a constant) at th with the design's
 * coefficients at their GLS values: -(log det S + rss) / 2 */
static double ml_loglik(struct ml *m)
{
	double logdet = 0, rss, r[6];
	size_t rank;

	if (!ml_factor(m))
		return -INFINITY;
	for (size_t i = 0; i < m->P; i++)
		logdet += log(m->v[i]);
	ml_whiten(m, m->d, m->dw);
	for (size_t j = 0; j < m->p; j++)
		ml_whiten(m, m->X[j], m->Xw[j]);
	rank = ml_ortho(m, r);
	rss = dot(m->dw, m->dw, m->P);
	for (size_t k = 0; k < rank; k++) {
		double c = dot(m->q[k], m->dw, m->P);

		rss -= c * c;
	}
	return -(logdet + fmax(rss, 0)) / 2;
}

/* the B and K squares as th = sc * exp(u) (u below -30: zero) */
static double ml_at(struct ml *m, double ub, double uk)
{
	m->th[2] = ub < -30 ? 0 : m->sc[0] * exp(ub);
	m->th[3] = uk < -30 ? 0 : m->sc[1] * exp(uk);
	return ml_loglik(m);
}

/* maximise over the B and K squares: a grid, then a pattern search;
 * leaves th at the maximum and returns the log-likelihood there */
static double ml_fit(struct ml *m)
{
	static const double grid[] = { -40, -14, -10, -7, -5, -3.5, -2, -1, 0, 1, 2, 3.5, 5 };
	const size_t ng = sizeof(grid) / sizeof(grid[0]);
	double bu = 0, bk = 0, best = -INFINITY, step = 1;

	for (size_t i = 0; i < ng; i++)
		for (size_t j = 0; j < ng; j++) {
			double l = ml_at(m, grid[i], grid[j]);

			if (l > best) {
				best = l;
				bu = grid[i];
				bk = grid[j];
			}
		}
	while (step > 0.02) {
		static const double dir[4][2] = { { 1, 0 }, { -1, 0 }, { 0, 1 }, { 0, -1 } };
		bool moved = false;

		for (int k = 0; k < 4; k++) {
			double u = bu + step * dir[k][0], v = bk + step * dir[k][1], l;

			/* zero stays zero unless a step brings it back */
			if (bu < -30 && dir[k][0] > 0)
				u = -14;
			if (bk < -30 && dir[k][1] > 0)
				v = -14;
			l = ml_at(m, u, v);
			if (l > best + 1e-12) {
				best = l;
				bu = u;
				bk = v;
				moved = true;
			}
		}
		if (!moved)
			step /= 2;
	}
	ml_at(m, bu, bk);
	return best;
}

static int ml_init(struct ml *m, const double *x, size_t stride, size_t n,
		   const double *temp, size_t tstride, size_t M, double fs,
		   const double est[5])
{
	size_t L = n / M, P = M - 1;
	double mean, v0;
	struct ssc_ksum ks = { 0, 0 };

	memset(m, 0, sizeof(*m));
	m->M = M;
	m->P = P;
	m->Tb = (double)L / fs;
	m->ybar = calloc(M, sizeof(double));
	m->d = calloc(P, sizeof(double));
	m->w = calloc(P, sizeof(double));
	m->dw = calloc(P, sizeof(double));
	m->r = calloc(P, sizeof(double));
	m->v = calloc(P, sizeof(double));
	m->phi = ssc_alloc_array(P * (P - 1) / 2 + 1, sizeof(double));
	if (temp)
		m->tbar = calloc(M, sizeof(double));
	if (!m->ybar || !m->d || !m->w || !m->dw || !m->r || !m->v || !m->phi ||
	    (temp && !m->tbar))
		return -ENOMEM;
	for (int t = 0; t < 4; t++)
		if (!(m->col[t] = calloc(P, sizeof(double))))
			return -ENOMEM;
	for (int j = 0; j < 6; j++)
		if (!(m->X[j] = calloc(P, sizeof(double))) ||
		    !(m->Xw[j] = calloc(P, sizeof(double))) ||
		    !(m->q[j] = calloc(P, sizeof(double))))
			return -ENOMEM;
	for (size_t i = 0; i < M * L; i++)
		ssc_ksum_add(&ks, x[i * stride]);
	mean = ssc_ksum_value(&ks) / (double)(M * L);
	for (size_t k = 0; k < M; k++) {
		struct ssc_ksum b = { 0, 0 }, bt = { 0, 0 };

		for (size_t i = k * L; i < (k + 1) * L; i++) {
			ssc_ksum_add(&b, x[i * stride] - mean);
			if (temp)
				ssc_ksum_add(&bt, temp[i * tstride]);
		}
		m->ybar[k] = ssc_ksum_value(&b) / (double)L;
		if (temp)
			m->tbar[k] = ssc_ksum_value(&bt) / (double)L;
	}
	for (size_t k = 0; k < P; k++)
		m->d[k] = m->ybar[k + 1] - m->ybar[k];
	for (int t = 0; t < 4; t++) {
		double unit[5] = { 0 };

		unit[t] = 1;
		for (size_t h = 0; h < P; h++)
			m->col[t][h] = dcov(unit, m->Tb, h);
	}
	m->th[0] = est[SSCOPE_TERM_Q] * est[SSCOPE_TERM_Q];
	m->th[1] = est[SSCOPE_TERM_N] * est[SSCOPE_TERM_N];
	/* scales: the square that alone would give the differences'
	 * variance */
	v0 = dot(m->d, m->d, P) / (double)P;
	if (!(v0 > 0))
		return -EDOM;
	m->sc[0] = v0 / m->col[2][0];
	m->sc[1] = v0 / m->col[3][0];
	return 0;
}

static void ml_free(struct ml *m)
{
	free(m->ybar);
	free(m->tbar);
	free(m->d);
	free(m->w);
	free(m->dw);
	for (int t = 0; t < 4; t++)
		free(m->col[t]);
	for (int j = 0; j < 6; j++) {
		free(m->X[j]);
		free(m->Xw[j]);
		free(m->q[j]);
	}
	free(m->r);
	free(m->v);
	free(m->phi);
}

/* level-space vector (M) into design column j as differences */
static void ml_set_col(struct ml *m, size_t j, const double *lev)
{
	for (size_t k = 0; k < m->P; k++)
		m->X[j][k] = lev[k + 1] - lev[k];
}

/* GLS coefficients of the design at the current th (after ml_loglik):
 * solves the triangular system of the Gram-Schmidt */
static void ml_beta(struct ml *m, double *beta)
{
	double R[6][6] = { { 0 } }, a[6];
	size_t p = m->p;

	/* classical Gram-Schmidt coefficients of Xw on q (full rank
	 * assumed: the callers' designs are) */
	for (size_t j = 0; j < p; j++)
		for (size_t k = 0; k <= j; k++)
			R[k][j] = dot(m->q[k], m->Xw[j], m->P);
	for (size_t k = 0; k < p; k++)
		a[k] = dot(m->q[k], m->dw, m->P);
	for (size_t j = p; j-- > 0;) {
		double s = a[j];

		for (size_t k = j + 1; k < p; k++)
			s -= R[j][k] * beta[k];
		beta[j] = R[j][j] != 0 ? s / R[j][j] : 0;
	}
}

/* The best candidate column (level vectors from make(k)) by its GLS t
 * statistic at the current th, given the nuisance design (p columns), and
 * the null distribution of the largest squared statistic over all the
 * candidates: under the null the whitened differences are independent
 * standard normal, so NULL_DRAWS draws of them (a fixed generator seed)
 * give the maximum's distribution exactly for these candidates -- far
 * less conservative than Bonferroni, the candidates being correlated
 * (neighbouring steps, neighbouring time constants).  null_max receives
 * the NULL_DRAWS maxima, sorted. */
#define NULL_DRAWS 2000

typedef void (*cand_fn)(const struct ml *m, size_t k, double *lev, void *ctx);

static size_t best_candidate(struct ml *m, size_t n_cand, cand_fn make,
			     void *ctx, double *lev, double *null_max)
{
	double r[6], best = -1, *V, *z, *Vt = NULL, *acc = NULL;
	size_t rank, kb = 0, p = m->p, nv = 0;
	gsl_rng *rng;

	for (size_t i = 0; i < NULL_DRAWS; i++)
		null_max[i] = INFINITY; /* no usable candidate: p = 1 */
	if (!ml_factor(m))
		return 0;
	V = ssc_alloc_array(n_cand * m->P, sizeof(double));
	z = calloc(m->P, sizeof(double));
	rng = gsl_rng_alloc(gsl_rng_mt19937);
	if (!V || !z || !rng) {
		free(V);
		free(z);
		if (rng)
			gsl_rng_free(rng);
		return 0;
	}
	ml_whiten(m, m->d, m->dw);
	for (size_t j = 0; j < p; j++)
		ml_whiten(m, m->X[j], m->Xw[j]);
	rank = ml_ortho(m, r);
	for (size_t k = 0; k < n_cand; k++) {
		double *v = V + nv * m->P, n0, n, a;

		make(m, k, lev, ctx);
		for (size_t i = 0; i < m->P; i++)
			v[i] = lev[i + 1] - lev[i];
		ml_whiten(m, v, v);
		n0 = sqrt(dot(v, v, m->P));
		for (int pass = 0; pass < 2; pass++)
			for (size_t q = 0; q < rank; q++) {
				double c = dot(m->q[q], v, m->P);

				for (size_t i = 0; i < m->P; i++)
					v[i] -= c * m->q[q][i];
			}
		n = sqrt(dot(v, v, m->P));
		if (!(n > 1e-9 * n0))
			continue;
		for (size_t i = 0; i < m->P; i++)
			v[i] /= n;
		nv++;
		a = fabs(dot(v, m->dw, m->P));
		if (a > best) {
			best = a;
			kb = k;
		}
	}
	gsl_rng_set(rng, 30u + (unsigned long)n_cand);
	/* the candidates' statistics of a draw, V z, a column of V at a
	 * time: the same sums in the same order as a dot product per
	 * candidate, but independent lanes (vector units) */
	Vt = ssc_alloc_array(m->P * nv + 1, sizeof(double));
	acc = ssc_alloc_array(nv + 1, sizeof(double));
	if (!Vt || !acc)
		nv = 0; /* no null distribution: p = 1 */
	for (size_t k = 0; k < nv; k++)
		for (size_t i = 0; i < m->P; i++)
			Vt[i * nv + k] = V[k * m->P + i];
	for (size_t d = 0; d < NULL_DRAWS && nv; d++) {
		double mx = 0;

		for (size_t i = 0; i < m->P; i++)
			z[i] = gsl_ran_gaussian_ziggurat(rng, 1);
		for (size_t k = 0; k < nv; k++)
			acc[k] = 0;
		for (size_t i = 0; i < m->P; i++) {
			const double *vi = Vt + i * nv, zi = z[i];

			for (size_t k = 0; k < nv; k++)
				acc[k] += vi[k] * zi;
		}
		for (size_t k = 0; k < nv; k++)
			mx = fmax(mx, acc[k] * acc[k]);
		null_max[d] = mx;
	}
	qsort(null_max, NULL_DRAWS, sizeof(double), ssc_cmp_double);
	free(V);
	free(Vt);
	free(acc);
	free(z);
	gsl_rng_free(rng);
	return kb;
}

/* P(max >= stat) from the sorted null draws (at least 1 / (draws + 1)) */
static double null_p(const double *null_max, double stat)
{
	size_t lo = 0, hi = NULL_DRAWS;

	while (lo < hi) {
		size_t mid = (lo + hi) / 2;

		if (null_max[mid] < stat)
			lo = mid + 1;
		else
			hi = mid;
	}
	return (double)(NULL_DRAWS - lo + 1) / (NULL_DRAWS + 1);
}

/* Allan variance of the block sequence a (M) at j blocks (overlapping) */
static double block_avar(const double *a, size_t M, size_t j)
{
	double s = 0;
	size_t nt;

	if (2 * j >= M)
		return NAN;
	nt = M - 2 * j + 1;
	for (size_t i = 0; i < nt; i++) {
		double m1 = 0, m2 = 0;

		for (size_t k = 0; k < j; k++) {
			m1 += a[i + k];
			m2 += a[i + j + k];
		}
		s += (m2 - m1) * (m2 - m1) / ((double)j * (double)j);
	}
	return s / (2 * (double)nt);
}

/* tau range where the component a (level space, M) raises the model's
 * Allan variance by AFFECT_SHARE; false when nowhere */
static bool affected_taus(const double *a, size_t M, double Tb,
			  const double est[5], double *lo, double *hi)
{
	*lo = *hi = NAN;
	for (size_t j = 1; 4 * j <= M; j *= 2) {
		double va = block_avar(a, M, j), vm = model_avar(est, (double)j * Tb);

		if (va >= AFFECT_SHARE * vm && vm > 0) {
			if (!isfinite(*lo))
				*lo = (double)j * Tb;
			*hi = (double)j * Tb;
		}
	}
	return isfinite(*lo);
}

/* candidates: a step inside block k / 2 + 1 at the fraction (k % 4) / 4
 * of it (so a step between two blocks' boundaries loses no power); a
 * transient exp(-t / tau_w) */
#define STEP_FRACTIONS 2

static void make_step(const struct ml *m, size_t k, double *lev, void *ctx)
{
	size_t b = k / STEP_FRACTIONS + 1;
	double f = (double)(k % STEP_FRACTIONS) / STEP_FRACTIONS;

	(void)ctx;
	for (size_t i = 0; i < m->M; i++)
		lev[i] = i > b ? 1 : i == b ? 1 - f : 0;
}

static void make_warmup(const struct ml *m, size_t k, double *lev, void *ctx)
{
	double tw = ((const double *)ctx)[k];

	for (size_t i = 0; i < m->M; i++)
		lev[i] = tw / m->Tb * (exp(-(double)i * m->Tb / tw) -
				       exp(-(double)(i + 1) * m->Tb / tw));
}

/* the noise model under the current th for the effect comparison */
static void ml_model(const struct ml *m, const double est[5], double rramp,
		     double out[5])
{
	out[SSCOPE_TERM_Q] = est[SSCOPE_TERM_Q];
	out[SSCOPE_TERM_N] = est[SSCOPE_TERM_N];
	out[SSCOPE_TERM_B] = sqrt(m->th[2]);
	out[SSCOPE_TERM_K] = sqrt(m->th[3]);
	out[SSCOPE_TERM_R] = fabs(rramp);
}

/* A family of candidates (steps, transients) and its test: the best
 * candidate beside the first p0 design columns (the nuisance), its
 * likelihood ratio with B and K refitted, and the p-value of the largest
 * statistic over the family. */
struct family {
	cand_fn make;
	void *ctx;
	size_t n;
	size_t k;      /* the best candidate */
	double lr, p, beta;
	bool first;    /* a step after the first block, taken as a transient */
};

static void family_test(struct ml *m, size_t p0, struct family *f,
			double *null_max, double *lev)
{
	double l0, l1, beta[6];

	f->p = 1;
	f->lr = 0;
	f->beta = 0;
	f->k = 0;
	f->first = false;
	if (!f->n)
		return;
	m->p = p0;
	l0 = ml_fit(m);
	f->k = best_candidate(m, f->n, f->make, f->ctx, lev, null_max);
	f->make(m, f->k, lev, f->ctx);
	ml_set_col(m, p0, lev);
	m->p = p0 + 1;
	l1 = ml_fit(m);
	ml_beta(m, beta);
	f->beta = beta[p0];
	f->lr = 2 * (l1 - l0);
	f->p = null_p(null_max, f->lr);
}

static void report_step(struct sscope_adequacy *r, struct ml *m,
			const struct family *s, const double est[5], double T,
			const char *U, double *lev)
{
	struct sscope_adequacy_finding *f;
	double lo, hi, model[5], beta[6];
	double at = ((double)(s->k / STEP_FRACTIONS + 1) +
		     (double)(s->k % STEP_FRACTIONS) / STEP_FRACTIONS) * m->Tb;
	size_t M = m->M;
	char tl[32];
	bool aff;

	/* the noise terms of the fit that holds the step */
	ml_beta(m, beta);
	ml_model(m, est, beta[0] / m->Tb, model);
	make_step(m, s->k, lev, NULL);
	for (size_t k = 0; k < M; k++)
		lev[k] *= s->beta;
	aff = affected_taus(lev, M, m->Tb, model, &lo, &hi);
	f = add_finding(r, SSCOPE_ADEQUACY_STEP, aff ? SSCOPE_ADEQUACY_DOUBT : SSCOPE_ADEQUACY_NOTE,
			aff ? dominant_terms(model, lo, T / 2) : 0);
	if (!f)
		return;
	f->statistic = s->lr;
	f->p_value = s->p;
	f->t_start_s = at - m->Tb;
	f->t_end_s = at + m->Tb;
	f->tau_min_s = lo;
	f->tau_max_s = hi;
	f->action_s = at;
	if (aff)
		say(f, "bias step of %.3g %s near t = %.4g s (between %.4g and %.4g s; p = %.2g): it raises the deviation by more than 10 %% at tau = %.3g to %.3g s (%s); analyse the parts before and after it separately",
		    s->beta, U, at, at - m->Tb, at + m->Tb, s->p, lo, hi,
		    term_list(f->terms, tl, sizeof(tl)));
	else
		say(f, "a small bias step of %.3g %s near t = %.4g s (p = %.2g) that changes the deviation by less than 10 %% at every tau",
		    s->beta, U, at, s->p);
}

static void report_warmup(struct sscope_adequacy *r, struct ml *m,
			  const struct family *w, const double *tau_w,
			  const double est[5], double T, const char *U,
			  double *lev)
{
	struct sscope_adequacy_finding *f;
	double lo, hi, A, cut, floor = INFINITY, tw = tau_w[w->k], model[5];
	size_t M = m->M;
	char tl[32];
	bool aff;

	ml_model(m, est, 0, model);
	if (w->first) {
		/* the first block alone stands out: a transient shorter than
		 * a block */
		for (size_t k = 0; k < M; k++)
			lev[k] = k == 0 ? -w->beta : 0;
		cut = m->Tb;
		A = -w->beta;
	} else {
		make_warmup(m, w->k, lev, (void *)tau_w);
		for (size_t k = 0; k < M; k++)
			lev[k] *= w->beta;
		A = w->beta;
		/* until the transient is a tenth of the deviation's floor */
		for (int i = 0; i <= 40; i++) {
			double tau = m->Tb / 8 * pow(4 * T / m->Tb, i / 40.0);

			floor = fmin(floor, sqrt(model_avar(model, tau)));
		}
		cut = tw * log(fabs(A) / (0.1 * floor));
		if (!(cut > m->Tb))
			cut = m->Tb;
	}
	aff = affected_taus(lev, M, m->Tb, model, &lo, &hi);
	f = add_finding(r, SSCOPE_ADEQUACY_WARMUP, aff ? SSCOPE_ADEQUACY_DOUBT : SSCOPE_ADEQUACY_NOTE,
			aff ? dominant_terms(model, lo, T / 2) : 0);
	if (!f)
		return;
	f->statistic = w->lr;
	f->p_value = w->p;
	f->t_start_s = 0;
	f->t_end_s = fmin(cut, T);
	f->tau_min_s = lo;
	f->tau_max_s = hi;
	f->action_s = cut;
	if (!aff)
		say(f, "a small transient at the start (p = %.2g) that changes the deviation by less than 10 %% at every tau; cutting the first %.3g s removes it",
		    w->p, cut);
	else if (cut < T / 2)
		say(f, "warm-up transient over the first %.3g s (%.3g %s at the start; p = %.2g): it raises the deviation by more than 10 %% at tau = %.3g to %.3g s (%s); cut the first %.3g s and analyse again",
		    cut, A, U, w->p, lo, hi, term_list(f->terms, tl, sizeof(tl)),
		    cut);
	else
		say(f, "warm-up transient lasting most of the %.3g s record (time constant %.3g s, p = %.2g): it raises the deviation by more than 10 %% at tau = %.3g to %.3g s (%s); record after the sensor has settled (about %.3g s)",
		    T, tw, w->p, lo, hi, term_list(f->terms, tl, sizeof(tl)), cut);
}

static void stationarity(struct sscope_adequacy *r, const double *x,
			 size_t stride, size_t n, const double *temp,
			 size_t tstride, const double est[5],
			 const struct sscope_adequacy_opts *o, size_t M)
{
	struct ml m;
	double fs = o->rate_hz, T = (double)n / fs;
	double alpha = o->alpha > 0 ? o->alpha : 0.02;
	double a3 = alpha / 3, *lev = NULL, *lev2 = NULL, l0, model[5], beta[6];
	double tau_w[32], ones_l0 = 0, *null_s = NULL, *null_w = NULL;
	size_t n_tau = 0, base_p;
	bool temp_found = false;
	const char *U = o->unit ? o->unit : "(SI)";
	char tl[32];
	int rc;

	rc = ml_init(&m, x, stride, n, temp, tstride, M, fs, est);
	lev = calloc(M, sizeof(double));
	lev2 = calloc(M, sizeof(double));
	null_s = calloc(NULL_DRAWS, sizeof(double));
	null_w = calloc(NULL_DRAWS, sizeof(double));
	if (rc || !lev || !lev2 || !null_s || !null_w) {
		say(add_finding(r, SSCOPE_ADEQUACY_UNCHECKED, SSCOPE_ADEQUACY_NOTE, 0),
		    "stationarity not tested: %s", rc == -EDOM ?
		    "the block means are all equal" : "out of memory");
		goto out;
	}
	r->stationarity_tested = true;
	r->stationary = true;

	/* the rate ramp: a constant difference, against none (a note) */
	m.p = 0;
	ones_l0 = ml_fit(&m);
	for (size_t k = 0; k < m.P; k++)
		m.X[0][k] = 1;
	m.p = 1;
	l0 = ml_fit(&m);
	{
		double lr = 2 * (l0 - ones_l0), p = gsl_cdf_chisq_Q(fmax(lr, 0), 1);

		if (p < a3) {
			struct sscope_adequacy_finding *f =
				add_finding(r, SSCOPE_ADEQUACY_RAMP, SSCOPE_ADEQUACY_NOTE,
					    1u << SSCOPE_TERM_R);

			ml_beta(&m, beta);
			if (f) {
				f->statistic = lr;
				f->p_value = p;
				f->t_start_s = 0;
				f->t_end_s = T;
				say(f, "the rate drifts linearly over the record (%.3g %s per hour; likelihood ratio %.3g, p = %.2g): IEEE 952's rate ramp R models it; if it follows the temperature, use tempbias first",
				    beta[0] / m.Tb * 3600, U, lr, p);
			}
		}
	}

	/* temperature: linear and quadratic in the block temperature, no
	 * ramp beside it (a temperature ramp and a rate ramp are the same
	 * thing, and the temperature is the likelier cause) */
	if (m.tbar) {
		double tmin = m.tbar[0], tmax = m.tbar[0], tm = 0, ts = 0;

		for (size_t k = 0; k < M; k++) {
			tmin = fmin(tmin, m.tbar[k]);
			tmax = fmax(tmax, m.tbar[k]);
			tm += m.tbar[k] / (double)M;
		}
		for (size_t k = 0; k < M; k++)
			ts += (m.tbar[k] - tm) * (m.tbar[k] - tm);
		ts = sqrt(ts / (double)M);
		if (ts > 0 && isfinite(ts)) {
			double l1, lr, p, span = 0, lo, hi;
			bool aff;

			for (size_t k = 0; k < M; k++) {
				lev[k] = (m.tbar[k] - tm) / ts;
				lev2[k] = lev[k] * lev[k];
			}
			ml_set_col(&m, 0, lev);
			ml_set_col(&m, 1, lev2);
			m.p = 2;
			l1 = ml_fit(&m);
			lr = 2 * (l1 - ones_l0);
			p = gsl_cdf_chisq_Q(fmax(lr, 0), 2);
			if (p < a3) {
				struct sscope_adequacy_finding *f;

				ml_beta(&m, beta);
				for (size_t k = 0; k < M; k++)
					lev[k] = beta[0] * lev[k] + beta[1] * lev2[k];
				for (size_t k = 0; k < M; k++)
					for (size_t j = 0; j < M; j++)
						span = fmax(span, fabs(lev[k] - lev[j]));
				ml_model(&m, est, 0, model);
				aff = affected_taus(lev, M, m.Tb, model, &lo, &hi);
				temp_found = true;
				f = add_finding(r, SSCOPE_ADEQUACY_TEMPERATURE,
						aff ? SSCOPE_ADEQUACY_DOUBT : SSCOPE_ADEQUACY_NOTE,
						aff ? dominant_terms(model, lo, T / 2) : 0);
				if (f) {
					f->statistic = lr;
					f->p_value = p;
					f->t_start_s = 0;
					f->t_end_s = T;
					f->tau_min_s = lo;
					f->tau_max_s = hi;
					if (aff)
						say(f, "the bias follows the temperature column (%.3g to %.3g degC, a drift of %.3g %s; likelihood ratio %.3g, p = %.2g): it raises the deviation by more than 10 %% at tau = %.3g to %.3g s (%s); use tempbias first and analyse the compensated record",
						    tmin, tmax, span, U, lr, p, lo, hi,
						    term_list(f->terms, tl, sizeof(tl)));
					else
						say(f, "the bias follows the temperature column (%.3g to %.3g degC; likelihood ratio %.3g, p = %.2g), but by too little (%.3g %s) to change the deviation by 10 %% at any tau",
						    tmin, tmax, lr, p, span, U);
				}
			}
		}
	}

	/* the nuisance of the step and warm-up tests: the ramp, and the
	 * temperature terms when the temperature was found */
	for (size_t k = 0; k < m.P; k++)
		m.X[0][k] = 1;
	m.p = 1;
	if (temp_found) {
		double tm = 0, ts = 0;

		for (size_t k = 0; k < M; k++)
			tm += m.tbar[k] / (double)M;
		for (size_t k = 0; k < M; k++)
			ts += (m.tbar[k] - tm) * (m.tbar[k] - tm);
		ts = sqrt(ts / (double)M);
		for (size_t k = 0; k < M; k++) {
			lev[k] = (m.tbar[k] - tm) / ts;
			lev2[k] = lev[k] * lev[k];
		}
		ml_set_col(&m, 1, lev);
		ml_set_col(&m, 2, lev2);
		m.p = 3;
	}
	base_p = m.p;
	for (double tw = m.Tb / 2; tw <= T / 4 * 1.0001 && n_tau < 32; tw *= 2)
		tau_w[n_tau++] = tw;
	{
		struct family s = { .make = make_step,
				    .n = (M - 1) * STEP_FRACTIONS - (STEP_FRACTIONS - 1) };
		struct family w = { .make = make_warmup, .ctx = tau_w, .n = n_tau };
		bool ss, sw;

		/* each against the ramp (and temperature); when both stand
		 * out, the stronger one is kept and the other tested again
		 * beside it (the tail of a transient is no step) */
		family_test(&m, base_p, &s, null_s, lev);
		family_test(&m, base_p, &w, null_w, lev);
		ss = s.p < a3;
		sw = w.p < a3;
		if (ss && sw) {
			struct family *keep = w.lr >= s.lr ? &w : &s;
			struct family *other = keep == &w ? &s : &w;

			keep->make(&m, keep->k, lev, keep->ctx);
			ml_set_col(&m, base_p, lev);
			family_test(&m, base_p + 1, other, keep == &w ? null_s : null_w,
				    lev);
			if (keep == &w)
				ss = s.p < a3;
			else
				sw = w.p < a3;
		}
		/* a step after the first block is a transient inside it */
		if (ss && s.k < STEP_FRACTIONS && !sw) {
			w.p = s.p;
			w.lr = s.lr;
			w.first = true;
			w.beta = s.beta;
			sw = true;
			ss = false;
		} else if (ss && s.k < STEP_FRACTIONS) {
			ss = false; /* the transient found already says it */
		}
		if (ss)
			report_step(r, &m, &s, est, T, U, lev);
		if (sw)
			report_warmup(r, &m, &w, tau_w, est, T, U, lev);
	}
	for (size_t i = 0; i < r->n_findings; i++) {
		enum sscope_adequacy_cause c = r->findings[i].cause;

		if ((c == SSCOPE_ADEQUACY_WARMUP || c == SSCOPE_ADEQUACY_STEP ||
		     c == SSCOPE_ADEQUACY_TEMPERATURE) &&
		    r->findings[i].severity >= SSCOPE_ADEQUACY_DOUBT)
			r->stationary = false;
	}
out:
	free(lev);
	free(lev2);
	free(null_s);
	free(null_w);
	ml_free(&m);
}

/* ------------------------------------------------------------ DAVAR */

static int davar(struct sscope_adequacy *r, const double *x, size_t stride,
		 size_t n, const double est[5], bool have_fit,
		 const struct sscope_adequacy_opts *o)
{
	struct sscope_adequacy_davar *d = &r->davar;
	double fs = o->rate_hz, T = (double)n / fs;
	double W = o->davar_window_s > 0 ? o->davar_window_s : T / 8;
	double S = o->davar_step_s > 0 ? o->davar_step_s : W / 4;
	size_t nw = ssc_count(round(W * fs)), ns = ssc_count(round(S * fs));
	size_t m[64], nm = 0, nwin;
	struct sscope_allan *plan = NULL;
	struct sscope_allan_opts ao = { 0 };
	struct sscope_allan_point *pts;
	int rc;

	if (nw < 64 || nw > n || ns < 1)
		return 0; /* no map: too short */
	for (size_t mm = 1; mm <= (nw - 1) / 4 && nm < 64; mm *= 2)
		m[nm++] = mm;
	nwin = (n - nw) / ns + 1;
	d->window_s = (double)nw / fs;
	d->step_s = (double)ns / fs;
	d->t_s = calloc(nwin, sizeof(double));
	d->tau_s = calloc(nm, sizeof(double));
	d->dev = ssc_alloc_array(nwin * nm, sizeof(double));
	d->edf = ssc_alloc_array(nwin * nm, sizeof(double));
	d->model = calloc(nm, sizeof(double));
	pts = calloc(nm, sizeof(*pts));
	if (!d->t_s || !d->tau_s || !d->dev || !d->edf || !d->model || !pts) {
		free(pts);
		return -ENOMEM;
	}
	ao.ci_level = -1;
	ao.threads = 1;
	rc = sscope_allan_new(&plan, nw, &ao);
	if (rc) {
		free(pts);
		return rc;
	}
	for (size_t j = 0; j < nm; j++) {
		d->tau_s[j] = (double)m[j] / fs;
		d->model[j] = have_fit ? sqrt(model_avar(est, d->tau_s[j])) : (double)NAN;
	}
	for (size_t w = 0; w < nwin; w++) {
		size_t np = 0;

		d->t_s[w] = ((double)(w * ns) + (double)nw / 2) / fs;
		for (size_t j = 0; j < nm; j++) {
			d->dev[w * nm + j] = NAN;
			d->edf[w * nm + j] = NAN;
		}
		if (sscope_allan_compute(plan, x + w * ns * stride, stride, nw, fs,
					 m, nm, pts, &np, NULL))
			continue;
		for (size_t i = 0; i < np; i++)
			for (size_t j = 0; j < nm; j++)
				if (pts[i].m == m[j]) {
					d->dev[w * nm + j] = pts[i].dev;
					d->edf[w * nm + j] = pts[i].edf;
				}
	}
	d->n_win = nwin;
	d->n_tau = nm;
	sscope_allan_free(plan);
	free(pts);
	return 0;
}

/* ------------------------------------------------------------ check */

/* where the record moves: the blocks whose variance exceeds the bound
 * times the 10th percentile of the blocks' */
static void motion_range(const double *x, size_t stride, size_t n, double fs,
			 double bound, double *t0, double *t1)
{
	size_t M = n / ssc_count(fmax(11, round(fs))), L;
	double *v, *s, p10;

	*t0 = *t1 = NAN;
	if (M < 10)
		return;
	if (M > 4096)
		M = 4096;
	L = n / M;
	v = calloc(M, sizeof(double));
	s = calloc(M, sizeof(double));
	if (!v || !s)
		goto out;
	for (size_t k = 0; k < M; k++) {
		double m = 0, q = 0;

		for (size_t i = k * L; i < (k + 1) * L; i++)
			m += x[i * stride];
		m /= (double)L;
		for (size_t i = k * L; i < (k + 1) * L; i++)
			q += (x[i * stride] - m) * (x[i * stride] - m);
		v[k] = s[k] = q / (double)(L - 1);
	}
	{
		/* sort a copy for the percentile */
		for (size_t i = 1; i < M; i++) {
			double t = s[i];
			size_t j = i;

			while (j > 0 && s[j - 1] > t) {
				s[j] = s[j - 1];
				j--;
			}
			s[j] = t;
		}
		p10 = s[(M - 1) / 10];
	}
	for (size_t k = 0; k < M; k++)
		if (v[k] > bound * p10) {
			if (!isfinite(*t0))
				*t0 = (double)(k * L) / fs;
			*t1 = (double)((k + 1) * L) / fs;
		}
out:
	free(v);
	free(s);
}

static int cmp_sev(const void *a, const void *b)
{
	const struct sscope_adequacy_finding *x = a, *y = b;

	if (x->severity != y->severity)
		return x->severity > y->severity ? -1 : 1;
	return x->cause < y->cause ? -1 : x->cause > y->cause;
}

int sscope_adequacy_check(const double *x, size_t stride, size_t n,
			  const struct sscope_noise_fit *fit,
			  const struct sscope_adequacy_opts *o,
			  struct sscope_adequacy **resp,
			  struct sscope_diag *diag)
{
	struct sscope_adequacy *r;
	double *rate = NULL, fs, T, est[5] = { 0 };
	const double *y = x, *temp;
	size_t ys = stride, ny = n, ts, n_nan = 0, temp_bad = 0;
	int rc = 0;

	if (!resp)
		return -EINVAL;
	*resp = NULL;
	if (!x || !o || stride == 0 || !(o->rate_hz > 0) || !isfinite(o->rate_hz) ||
	    o->alpha < 0 || o->alpha >= 1 || o->fit_p_level < 0 ||
	    o->fit_p_level >= 1 || o->davar_window_s < 0 || o->davar_step_s < 0 ||
	    (o->requested & ~ALL_TERMS))
		return ssc_diag(diag, -EINVAL, "bad parameter");
	if (n < 2)
		return ssc_diag(diag, -EDOM, "fewer than 2 samples");
	fs = o->rate_hz;
	temp = o->temp_degc;
	ts = o->temp_stride ? o->temp_stride : 1;
	for (size_t i = 0; i < n; i++) {
		double v = x[i * stride];

		if (isnan(v))
			n_nan++;
		else if (!isfinite(v))
			return ssc_diag(diag, -EINVAL, "sample %zu is infinite", i + 1);
	}
	if (temp)
		for (size_t i = 0; i < n; i++)
			if (!isfinite(temp[i * ts])) {
				/* a gap in the temperature: not used, said */
				temp = NULL;
				temp_bad = i + 1;
				break;
			}
	if (o->angle) {
		rate = ssc_alloc_array(n - 1, sizeof(double));
		if (!rate)
			return -ENOMEM;
		for (size_t i = 0; i + 1 < n; i++)
			rate[i] = (x[(i + 1) * stride] - x[i * stride]) * fs;
		y = rate;
		ys = 1;
		ny = n - 1;
		if (temp)
			temp += ts;
	}
	T = (double)ny / fs;
	r = calloc(1, sizeof(*r));
	if (!r) {
		free(rate);
		return -ENOMEM;
	}
	r->findings = calloc(MAX_FINDINGS, sizeof(*r->findings));
	if (!r->findings) {
		free(rate);
		free(r);
		return -ENOMEM;
	}
	r->duration_s = T;
	r->requested = o->requested ? o->requested :
		       (1u << SSCOPE_TERM_N) | (1u << SSCOPE_TERM_B) |
		       (1u << SSCOPE_TERM_K);
	r->contrast = NAN;
	r->fit_p_value = NAN;
	r->max_contrast = o->max_contrast > 0 ? o->max_contrast : 9;
	r->still = true;
	r->have_fit = fit != NULL;
	if (fit)
		for (int t = 0; t < 5; t++)
			est[t] = isfinite(fit->coef[t].estimate) ?
				 fit->coef[t].estimate : 0;

	/* still? */
	if (o->max_contrast >= 0 && n_nan == 0) {
		double ratio;
		int e = ssc_still_contrast(y, ys, ny, fs, &ratio);

		if (e == -ENOMEM) {
			rc = e;
			goto fail;
		}
		if (!e) {
			r->still_tested = true;
			r->contrast = ratio;
			r->still = ratio <= r->max_contrast;
		} else {
			say(add_finding(r, SSCOPE_ADEQUACY_UNCHECKED, SSCOPE_ADEQUACY_NOTE, 0),
			    "stillness not tested: the record is shorter than two 1 s windows");
		}
	} else if (o->max_contrast >= 0) {
		say(add_finding(r, SSCOPE_ADEQUACY_UNCHECKED, SSCOPE_ADEQUACY_NOTE, 0),
		    "stillness and stationarity not tested: the record has %zu gaps (NaN samples)",
		    n_nan);
	}
	if (r->still && o->moving_channel) {
		struct sscope_adequacy_finding *f =
			add_finding(r, SSCOPE_ADEQUACY_MOVES, SSCOPE_ADEQUACY_INVALID, ALL_TERMS);

		r->still = false;
		if (f) {
			f->statistic = o->moving_contrast;
			if (isfinite(o->moving_contrast))
				say(f, "the sensor moves: its channel %s does (its variance over 1 s windows spans %.3g times, a still record at most %g), although this one shows little of it; noise terms need the sensor at rest",
				    o->moving_channel, o->moving_contrast, r->max_contrast);
			else
				say(f, "the sensor may move: its channel %s may (its variance over 1 s windows is zero in some windows and not in others: a held value then motion, or a quantisation coarse beside the noise), although this one shows little of it; noise terms need the sensor at rest",
				    o->moving_channel);
		}
	} else if (!r->still) {
		struct sscope_adequacy_finding *f =
			add_finding(r, SSCOPE_ADEQUACY_MOVES, SSCOPE_ADEQUACY_INVALID, ALL_TERMS);
		double t0, t1;

		motion_range(y, ys, ny, fs, r->max_contrast, &t0, &t1);
		if (f && !isfinite(r->contrast)) {
			f->statistic = r->contrast;
			f->t_start_s = t0;
			f->t_end_s = t1;
			say(f, "the record may move (its variance over 1 s windows is zero in some windows and not in others: a held value then motion, or a quantisation coarse beside the noise): noise terms need the sensor at rest; record it still, or with a finer quantisation");
		} else if (f) {
			f->statistic = r->contrast;
			f->t_start_s = t0;
			f->t_end_s = t1;
			if (isfinite(t0))
				say(f, "the record moves (its variance over 1 s windows spans %.3g times, a still record at most %g; motion from t = %.4g to %.4g s): noise terms need the sensor at rest; record it still, or cut the still part out",
				    r->contrast, r->max_contrast, t0, t1);
			else
				say(f, "the record moves (its variance over 1 s windows spans %.3g times, a still record at most %g): noise terms need the sensor at rest; record it still",
				    r->contrast, r->max_contrast);
		}
	}
	/* the fit */
	if (!fit) {
		say(add_finding(r, SSCOPE_ADEQUACY_NO_FIT, SSCOPE_ADEQUACY_INVALID, ALL_TERMS),
		    "no noise fit: the record gives no noise terms");
	} else {
		double pl = o->fit_p_level > 0 ? o->fit_p_level : 0.01;

		r->fit_p_value = fit->p_value;
		r->fit_rejected = sscope_noise_fit_rejected(fit, pl);
		if (!isfinite(fit->p_value))
			say(add_finding(r, SSCOPE_ADEQUACY_UNCHECKED, SSCOPE_ADEQUACY_NOTE, 0),
			    "the fit's goodness of fit was not computed (chi-squared %.3g for %.3g dof): whether the model describes the record is not tested",
			    fit->chi2, fit->dof);
		if (r->fit_rejected) {
			struct sscope_adequacy_finding *f =
				add_finding(r, SSCOPE_ADEQUACY_FIT_REJECTED,
					    SSCOPE_ADEQUACY_INVALID, ALL_TERMS);

			if (f) {
				f->statistic = fit->chi2;
				f->p_value = fit->p_value;
				say(f, "the five-term noise model does not describe the record (chi-squared %.3g for %.3g dof, p %s %.2g, below %g): its terms are not valid; a trend, a transient or motion the model lacks (see the other findings; the dynamic Allan deviation (DAVAR) of the record shows where in time)",
				    fit->chi2, fit->dof,
				    sscope_noise_p_is_bound(fit->p_value) ? "<" : "=",
				    sscope_noise_p_is_bound(fit->p_value) ? 0.001 : fit->p_value,
				    pl);
			}
		}
		/* a moving record's terms are not valid at all: no bounds */
		if (r->still)
			check_length(r, fit, est, fs, T);
	}
	/* stationarity */
	if (fit && r->still && n_nan == 0) {
		size_t M = o->blocks ? o->blocks : 64;

		if (M > MAX_BLOCKS)
			M = MAX_BLOCKS;
		while (M >= 8 && ny / M < MIN_BLOCK_SAMPLES)
			M /= 2;
		if (temp_bad)
			say(add_finding(r, SSCOPE_ADEQUACY_UNCHECKED, SSCOPE_ADEQUACY_NOTE, 0),
			    "drift with temperature not tested: temperature sample %zu is not a number (a gap or an infinite value)",
			    temp_bad);
		if (M >= 8)
			stationarity(r, y, ys, ny, temp, ts, est, o, M);
		else
			say(add_finding(r, SSCOPE_ADEQUACY_UNCHECKED, SSCOPE_ADEQUACY_NOTE, 0),
			    "stationarity not tested: %zu samples are too few for 8 blocks of %d",
			    ny, MIN_BLOCK_SAMPLES);
	}
	if (!o->no_davar) {
		rc = davar(r, y, ys, ny, est, fit != NULL, o);
		if (rc)
			goto fail;
	}
	qsort(r->findings, r->n_findings, sizeof(*r->findings), cmp_sev);
	r->verdict = SSCOPE_ADEQUACY_NOTE;
	for (size_t i = 0; i < r->n_findings; i++) {
		const struct sscope_adequacy_finding *f = &r->findings[i];

		if (f->severity > r->verdict)
			r->verdict = f->severity;
		if (f->severity >= SSCOPE_ADEQUACY_DOUBT)
			r->doubtful |= f->terms;
	}
	free(rate);
	*resp = r;
	return 0;
fail:
	free(rate);
	sscope_adequacy_free(r);
	return rc;
}
