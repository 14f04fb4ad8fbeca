/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Error-model calibration of accelerometer and gyro triads.
 *
 * Multi-position calibration without external equipment after D. Tedaldi,
 * A. Pretto and E. Menegatti, "A robust and easy to implement method for IMU
 * calibration without external equipments", ICRA 2014: static intervals
 * from the variance magnitude of the accelerometer (sec. IV-A), the
 * accelerometer model a' = T K (a - b) with T upper triangular fitted by
 * Levenberg-Marquardt on sum(|g| - |a'|)^2 (sec. III-B, IV-B), the gyro
 * model w' = T K (w - b) with a full unit-diagonal T fitted by matching the
 * gravity direction of pose k with the one of pose k-1 carried by the
 * integrated calibrated rotation (sec. IV-C).  GSL's gsl_multifit_nlinear
 * (trust region, Levenberg-Marquardt step) minimises, covariances are
 * s^2 (J^T J)^-1 with s^2 the residual variance.
 *
 * Known-reference fits (six-position test, rate table, centrifuge, tilt
 * table; IEEE Std 528 terms: scale factor as the slope of the least-squares
 * straight line, non-linearity as the largest deviation from it relative to
 * full-scale output) use gsl_multifit_linear (SVD).
 *
 * The sensor-class table is described at sscope_calib_grades() below.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_eigen.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_statistics_double.h>
#include <gsl/gsl_vector.h>

#include "sscope-calib.h"
#include "sscope-quantity.h"
#include "sscope-stats.h"


/* ------------------------------------------------------------------ */
/* Static intervals                                                    */
/* ------------------------------------------------------------------ */

int sscope_calib_variance_magnitude(const double *x, const double *y,
				    const double *z, size_t stride, size_t n,
				    size_t window, double *out)
{
	const double *ch[3] = { x, y, z };
	/* one channel given three times (a one-axis detector) is summed
	 * once: the same numbers */
	int nc = x == y && y == z ? 1 : 3;
	size_t h, w;

	if (!x || !y || !z || !out || stride == 0 || window < 3)
		return -EINVAL;
	h = window / 2;
	w = 2 * h + 1;
	if (n < w)
		return -EDOM;
	for (size_t i = 0; i < n; i++)
		out[i] = INFINITY;
	/* Sliding sums of (x - shift), re-anchored every w steps so that the
	 * rounding of the add/remove updates never accumulates. */
	double s1[3] = { 0 }, s2[3] = { 0 }, shift[3] = { 0 };
	size_t anchor = 0; /* the next lo that is a multiple of w */

	for (size_t i = h; i + h < n; i++) {
		size_t lo = i - h;

		if (lo == anchor) {
			anchor += w;
			for (int c = 0; c < nc; c++) {
				shift[c] = ch[c][lo * stride];
				s1[c] = s2[c] = 0;
				for (size_t j = lo; j < lo + w; j++) {
					double d = ch[c][j * stride] - shift[c];

					s1[c] += d;
					s2[c] += d * d;
				}
			}
		} else {
			for (int c = 0; c < nc; c++) {
				double dout = ch[c][(lo - 1) * stride] - shift[c];
				double din = ch[c][(i + h) * stride] - shift[c];

				s1[c] += din - dout;
				s2[c] += din * din - dout * dout;
			}
		}
		double v2 = 0, v[3];

		for (int c = 0; c < nc; c++) {
			v[c] = (s2[c] - s1[c] * s1[c] / (double)w) / (double)(w - 1);
			if (v[c] < 0)
				v[c] = 0;
		}
		for (int c = nc; c < 3; c++)
			v[c] = v[0];
		for (int c = 0; c < 3; c++)
			v2 += v[c] * v[c];
		out[i] = sqrt(v2);
	}
	return 0;
}

int sscope_calib_static_intervals(const double *vs, size_t n, double threshold,
				  size_t min_len,
				  struct sscope_calib_interval *iv, size_t max,
				  size_t *n_iv)
{
	size_t count = 0, i = 0;

	if (!vs || !n_iv || (max && !iv) || !(threshold > 0))
		return -EINVAL;
	if (min_len < 1)
		min_len = 1;
	while (i < n) {
		size_t s;

		while (i < n && !(vs[i] < threshold))
			i++;
		s = i;
		while (i < n && vs[i] < threshold)
			i++;
		if (i > s && i - s >= min_len) {
			if (count < max) {
				iv[count].start = s;
				iv[count].end = i;
			}
			count++;
		}
	}
	*n_iv = count;
	return 0;
}

int sscope_calib_interval_mean(const double *x, size_t stride,
			       const struct sscope_calib_interval *iv,
			       double *mean, double *sd)
{
	struct sscope_stats st;
	int rc;

	if (!x || !iv || iv->end <= iv->start || stride == 0)
		return -EINVAL;
	rc = sscope_stats_compute(x + iv->start * stride, stride,
				  iv->end - iv->start, &st);
	if (rc)
		return rc;
	if (mean)
		*mean = st.mean;
	if (sd)
		*sd = st.n > 1 ? st.sd : (double)NAN;
	return 0;
}

/* ------------------------------------------------------------------ */
/* Triads                                                              */
/* ------------------------------------------------------------------ */

void sscope_calib_triad_identity(struct sscope_calib_triad *c)
{
	memset(c, 0, sizeof(*c));
	for (int i = 0; i < 3; i++) {
		c->scale[i] = 1;
		c->mis[i][i] = 1;
		c->bias_sd[i] = c->scale_sd[i] = NAN;
		for (int j = 0; j < 3; j++) {
			c->mis_sd[i][j] = i == j ? 0 : (double)NAN;
			c->gsens_sd[i][j] = NAN;
		}
	}
	c->residual_rms = NAN;
	c->cond = NAN;
}

/* C = T K */
static void triad_matrix(const struct sscope_calib_triad *c, double C[3][3])
{
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			C[i][j] = c->mis[i][j] * c->scale[j];
}

void sscope_calib_apply(const struct sscope_calib_triad *c, double *x,
			double *y, double *z, size_t stride, size_t n,
			const double *const a[3], size_t astride)
{
	double C[3][3];
	double *ch[3] = { x, y, z };

	triad_matrix(c, C);
	for (size_t k = 0; k < n; k++) {
		double u[3], v[3];

		for (int i = 0; i < 3; i++) {
			u[i] = ch[i][k * stride] - c->bias[i];
			if (a && c->has_gsens)
				for (int j = 0; j < 3; j++)
					u[i] -= c->gsens[i][j] *
						a[j][k * astride];
		}
		for (int i = 0; i < 3; i++)
			v[i] = C[i][0] * u[0] + C[i][1] * u[1] + C[i][2] * u[2];
		for (int i = 0; i < 3; i++)
			ch[i][k * stride] = v[i];
	}
}

/* Condition number of J (columns scaled to unit norm), by SVD. */
static double cond_scaled(const gsl_matrix *J)
{
	size_t m = J->size1, p = J->size2;
	gsl_matrix *A, *V;
	gsl_vector *S, *work;
	double c = INFINITY;

	if (m < p)
		return INFINITY;
	A = gsl_matrix_alloc(m, p);
	V = gsl_matrix_alloc(p, p);
	S = gsl_vector_alloc(p);
	work = gsl_vector_alloc(p);
	if (!A || !V || !S || !work)
		goto out;
	gsl_matrix_memcpy(A, J);
	for (size_t j = 0; j < p; j++) {
		gsl_vector_view col = gsl_matrix_column(A, j);
		double nrm = gsl_blas_dnrm2(&col.vector);

		if (!(nrm > 0))
			goto out; /* a parameter without influence */
		gsl_vector_scale(&col.vector, 1 / nrm);
	}
	gsl_linalg_SV_decomp(A, V, S, work);
	if (gsl_vector_get(S, p - 1) > 0)
		c = gsl_vector_get(S, 0) / gsl_vector_get(S, p - 1);
out:
	gsl_matrix_free(A);
	gsl_matrix_free(V);
	gsl_vector_free(S);
	gsl_vector_free(work);
	return c;
}

#define COND_MAX 1e8

/*
 * Excitation rule: the smallest eigenvalue of the normalised second-moment
 * matrix sum(v v^T) / sum(|v|^2) of the stimulus directions (gravity in the
 * poses, rotation rates in the motions) must be at least EXCITE_MIN, i.e.
 * every direction carries at least 1 % of the stimulus energy (an ideal
 * design has 1/3 on each axis).  Below it the parameters of the weak axis
 * are fitted to noise.
 */
#define EXCITE_MIN 0.01

static double min_eig_ratio(const double M[3][3])
{
	double A[9], tr = M[0][0] + M[1][1] + M[2][2], lo;
	gsl_matrix_view mv = gsl_matrix_view_array(A, 3, 3);
	gsl_vector *ev = gsl_vector_alloc(3);
	gsl_eigen_symm_workspace *w = gsl_eigen_symm_alloc(3);

	if (!ev || !w || !(tr > 0)) {
		gsl_vector_free(ev);
		gsl_eigen_symm_free(w);
		return 0;
	}
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			A[3 * i + j] = M[i][j];
	gsl_eigen_symm(&mv.matrix, ev, w);
	lo = gsl_vector_min(ev) / tr;
	gsl_vector_free(ev);
	gsl_eigen_symm_free(w);
	return lo;
}

/* ------------------------------------------------------------------ */
/* Accelerometer multi-position fit                                    */
/* ------------------------------------------------------------------ */

/*
 * Parameters (dimensionless): p[0..2] = alpha_yz, alpha_zy, alpha_zx of
 * T = [1 -a_yz a_zy; 0 1 -a_zx; 0 0 1]; p[3..5] = K / s0; p[6..8] =
 * b * s0 / g.  Residuals are (g - |a'|) / g.
 */
struct accel_ctx {
	const double (*m)[3];
	size_t n;
	double g, s0;
};

static void accel_params(const double *p, const struct accel_ctx *a,
			 struct sscope_calib_triad *c)
{
	c->mis[0][0] = 1;
	c->mis[0][1] = -p[0];
	c->mis[0][2] = p[1];
	c->mis[1][0] = 0;
	c->mis[1][1] = 1;
	c->mis[1][2] = -p[2];
	c->mis[2][0] = c->mis[2][1] = 0;
	c->mis[2][2] = 1;
	for (int i = 0; i < 3; i++) {
		c->scale[i] = p[3 + i] * a->s0;
		c->bias[i] = p[6 + i] * a->g / a->s0;
	}
}

static int accel_f(const gsl_vector *x, void *params, gsl_vector *f)
{
	const struct accel_ctx *a = params;
	struct sscope_calib_triad c;
	double C[3][3];

	accel_params(x->data, a, &c);
	triad_matrix(&c, C);
	for (size_t k = 0; k < a->n; k++) {
		double u[3], v2 = 0;

		for (int i = 0; i < 3; i++)
			u[i] = a->m[k][i] - c.bias[i];
		for (int i = 0; i < 3; i++) {
			double v = C[i][0] * u[0] + C[i][1] * u[1] + C[i][2] * u[2];

			v2 += v * v;
		}
		gsl_vector_set(f, k, (a->g - sqrt(v2)) / a->g);
	}
	return GSL_SUCCESS;
}

/* Levenberg-Marquardt driver shared by the accelerometer and gyro fits;
 * returns the solution, covariance (unscaled by s^2), residuals. */
struct lm_out {
	double x[12];
	double cov[12][12];
	double rss;
	double cond;
	size_t iter;
};

/*
 * Central-difference Jacobian with absolute steps 1e-6 max(|x_j|, 1):
 * GSL's own steps are relative to |x_j|, so a parameter near 0 (a
 * misalignment of 1e-3) gets a step of 1e-11 and a Jacobian column that
 * is mostly rounding noise, which stops the iteration wherever the noise
 * wins (1e-9 apart for the same data in other raw units).  The parameters
 * here are dimensionless and of order 1e-3..1.
 */
struct fd_wrap {
	int (*f)(const gsl_vector *x, void *params, gsl_vector *f);
	void *params;
	gsl_vector *xp, *fp, *fm;
};

static int fd_f(const gsl_vector *x, void *params, gsl_vector *f)
{
	const struct fd_wrap *fw = params;

	return fw->f(x, fw->params, f);
}

static int fd_df(const gsl_vector *x, void *params, gsl_matrix *J)
{
	const struct fd_wrap *fw = params;

	gsl_vector_memcpy(fw->xp, x);
	for (size_t j = 0; j < x->size; j++) {
		double xj = gsl_vector_get(x, j);
		double h = 1e-6 * fmax(fabs(xj), 1);

		gsl_vector_set(fw->xp, j, xj + h);
		fw->f(fw->xp, fw->params, fw->fp);
		gsl_vector_set(fw->xp, j, xj - h);
		fw->f(fw->xp, fw->params, fw->fm);
		gsl_vector_set(fw->xp, j, xj);
		for (size_t i = 0; i < J->size1; i++)
			gsl_matrix_set(J, i, j,
				       (gsl_vector_get(fw->fp, i) -
					gsl_vector_get(fw->fm, i)) / (2 * h));
	}
	return GSL_SUCCESS;
}

static int lm_solve(gsl_multifit_nlinear_fdf *fdf_in, const double *x0,
		    struct lm_out *o)
{
	size_t p = fdf_in->p, n = fdf_in->n;
	struct fd_wrap fw = { fdf_in->f, fdf_in->params, NULL, NULL, NULL };
	gsl_multifit_nlinear_fdf fdf_fd = *fdf_in, *fdf = &fdf_fd;
	gsl_multifit_nlinear_parameters fp =
		gsl_multifit_nlinear_default_parameters();
	gsl_multifit_nlinear_workspace *w;
	gsl_matrix *cov;
	gsl_vector_const_view xv = gsl_vector_const_view_array(x0, p);
	int info, status, rc = 0;

	fp.trs = gsl_multifit_nlinear_trs_lm;
	fp.scale = gsl_multifit_nlinear_scale_more;
	fdf->f = fd_f;
	fdf->df = fd_df;
	fdf->params = &fw;
	fw.xp = gsl_vector_alloc(p);
	fw.fp = gsl_vector_alloc(n);
	fw.fm = gsl_vector_alloc(n);
	w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &fp, n, p);
	cov = gsl_matrix_alloc(p, p);
	if (!w || !cov || !fw.xp || !fw.fp || !fw.fm) {
		rc = -ENOMEM;
		goto out;
	}
	gsl_multifit_nlinear_init(&xv.vector, fdf, w);
	status = gsl_multifit_nlinear_driver(500, 1e-12, 1e-12, 0, NULL, NULL,
					     &info, w);
	o->iter = gsl_multifit_nlinear_niter(w);
	if (status != GSL_SUCCESS && status != GSL_ENOPROG) {
		rc = -EDOM;
		goto out;
	}
	{
		gsl_matrix *J = gsl_multifit_nlinear_jac(w);
		gsl_vector *f = gsl_multifit_nlinear_residual(w);
		gsl_vector *xs = gsl_multifit_nlinear_position(w);

		o->cond = cond_scaled(J);
		if (!(o->cond < COND_MAX)) {
			rc = -ERANGE; /* degenerate: reported as -EDOM */
			goto out;
		}
		gsl_blas_ddot(f, f, &o->rss);
		gsl_multifit_nlinear_covar(J, 0.0, cov);
		for (size_t i = 0; i < p; i++) {
			o->x[i] = gsl_vector_get(xs, i);
			for (size_t j = 0; j < p; j++)
				o->cov[i][j] = gsl_matrix_get(cov, i, j);
		}
		for (size_t i = 0; i < p; i++)
			if (!isfinite(o->x[i]))
				rc = -EDOM;
	}
out:
	if (w)
		gsl_multifit_nlinear_free(w);
	gsl_matrix_free(cov);
	gsl_vector_free(fw.xp);
	gsl_vector_free(fw.fp);
	gsl_vector_free(fw.fm);
	return rc;
}

int sscope_calib_accel_fit(const double (*means)[3], size_t n_poses,
			   double gravity_m_s2, struct sscope_calib_triad *c,
			   struct sscope_diag *diag)
{
	struct accel_ctx a = { means, n_poses, gravity_m_s2, 1 };
	gsl_multifit_nlinear_fdf fdf;
	struct lm_out o;
	double x0[9] = { 0, 0, 0, 1, 1, 1, 0, 0, 0 }, norm = 0, s2;
	double ctr[3], dsc[3], (*um)[3];
	int rc;

	if (!means || !c || !(gravity_m_s2 > 0) || !isfinite(gravity_m_s2))
		return ssc_diag(diag, -EINVAL, "calibration: bad parameter");
	if (n_poses < 10)
		return ssc_diag(diag, -EDOM,
				"%zu static poses: the 9-parameter accelerometer model needs at least 10",
				n_poses);
	for (size_t k = 0; k < n_poses; k++)
		for (int i = 0; i < 3; i++)
			if (!isfinite(means[k][i]))
				return ssc_diag(diag, -EINVAL,
						"pose %zu: non-finite mean", k + 1);
	/*
	 * Centre and scale each axis by the mean and sd of the pose means:
	 * a = ctr + D u turns T K (a - b) into T (K D) (u - D^-1 (b - ctr)),
	 * the same model, so the fit in u is the same whatever affine units
	 * the raw columns have (counts with a large offset included), and the
	 * excitation test sees the spread of the poses, not their offset.
	 */
	for (int i = 0; i < 3; i++) {
		struct ssc_ksum sm = { 0, 0 }, sv = { 0, 0 };

		for (size_t k = 0; k < n_poses; k++)
			ssc_ksum_add(&sm, means[k][i]);
		ctr[i] = ssc_ksum_value(&sm) / (double)n_poses;
		for (size_t k = 0; k < n_poses; k++)
			ssc_ksum_add(&sv, (means[k][i] - ctr[i]) * (means[k][i] - ctr[i]));
		dsc[i] = sqrt(ssc_ksum_value(&sv) / (double)n_poses);
		if (!(dsc[i] > 0))
			return ssc_diag(diag, -EDOM,
					"the %zu poses do not determine the 9 parameters: axis %c reads the same in every pose: turn the sensor about all three axes",
					n_poses, "xyz"[i]);
	}
	um = ssc_alloc_array(n_poses, sizeof(*um));
	if (!um)
		return -ENOMEM;
	for (size_t k = 0; k < n_poses; k++) {
		for (int i = 0; i < 3; i++)
			um[k][i] = (means[k][i] - ctr[i]) / dsc[i];
		norm += sqrt(um[k][0] * um[k][0] + um[k][1] * um[k][1] +
			     um[k][2] * um[k][2]);
	}
	norm /= (double)n_poses;
	a.m = (const double(*)[3])um;
	{
		double M[3][3] = { { 0 } }, e;

		for (size_t k = 0; k < n_poses; k++)
			for (int i = 0; i < 3; i++)
				for (int j = 0; j < 3; j++)
					M[i][j] += um[k][i] * um[k][j];
		e = min_eig_ratio(M);
		if (e < EXCITE_MIN) {
			free(um);
			return ssc_diag(diag, -EDOM,
					"the %zu poses do not determine the 9 parameters: gravity never points along one direction (%.2g %% of the spread, need 1 %%): turn the sensor about all three axes",
					n_poses, 100 * e);
		}
	}
	a.s0 = gravity_m_s2 / norm;
	fdf.f = accel_f;
	fdf.df = NULL;
	fdf.fvv = NULL;
	fdf.n = n_poses;
	fdf.p = 9;
	fdf.params = &a;
	rc = lm_solve(&fdf, x0, &o);
	free(um);
	if (rc == -ENOMEM)
		return rc;
	if (rc == -ERANGE)
		return ssc_diag(diag, -EDOM,
				"the %zu poses do not determine the 9 parameters (condition number %.3g): turn the sensor about all three axes",
				n_poses, o.cond);
	if (rc)
		return ssc_diag(diag, -EDOM,
				"the accelerometer fit did not converge");
	sscope_calib_triad_identity(c);
	accel_params(o.x, &a, c);
	s2 = n_poses > 9 ? o.rss / (double)(n_poses - 9) : (double)NAN;
	{
		double sd[9];

		for (int i = 0; i < 9; i++)
			sd[i] = sqrt(s2 * o.cov[i][i]);
		c->mis_sd[0][1] = sd[0];
		c->mis_sd[0][2] = sd[1];
		c->mis_sd[1][2] = sd[2];
		c->mis_sd[1][0] = c->mis_sd[2][0] = c->mis_sd[2][1] = 0;
		/* back from u: K = K_u / d, b = ctr + d b_u */
		for (int i = 0; i < 3; i++) {
			c->scale[i] /= dsc[i];
			c->bias[i] = ctr[i] + dsc[i] * c->bias[i];
			c->scale_sd[i] = sd[3 + i] * a.s0 / dsc[i];
			c->bias_sd[i] = sd[6 + i] * gravity_m_s2 / a.s0 * dsc[i];
		}
	}
	c->n_params = 9;
	c->poses = n_poses;
	c->residual_rms = sqrt(o.rss / (double)n_poses) * gravity_m_s2;
	c->iterations = (unsigned)o.iter;
	c->cond = o.cond;
	return 0;
}

/*
 * The order statistics k[0..nk) (0-based ranks among the finite values,
 * nf of them) of vs in one pass: a sorted sample of the finite values
 * brackets each wanted rank by two values; the pass counts the values
 * below each bracket and gathers those inside it, and the statistic is
 * selected among the gathered ones.  It is the exact value whenever the
 * counts show the rank inside its bracket; returns -EAGAIN (nothing
 * set) when a bracket missed or overflowed, for the caller to select
 * from all values.  A day's record at 100 Hz: one pass instead of a copy
 * and two quickselects.
 */
#define BAND_SAMPLE 4096
#define BAND_HALF 48
static int band_select(const double *vs, size_t n, size_t nf, const size_t *k,
		       int nk, double *out)
{
	double samp[BAND_SAMPLE], lo[2], hi[2], *buf[2] = { NULL, NULL };
	size_t ns = 0, below[2] = { 0, 0 }, in[2] = { 0, 0 }, cap = nf / 16 + 1;
	int rc = 0;

	for (size_t s = 0; s < BAND_SAMPLE; s++) {
		size_t i = (size_t)((double)s * (double)n / BAND_SAMPLE);

		while (i < n && !isfinite(vs[i]))
			i++;
		if (i < n)
			samp[ns++] = vs[i];
	}
	if (ns < BAND_SAMPLE / 2)
		return -EAGAIN;
	qsort(samp, ns, sizeof(double), ssc_cmp_double);
	for (int j = 0; j < nk; j++) {
		double r = (double)k[j] / (double)nf * (double)ns;
		long a = (long)r - BAND_HALF, b = (long)r + BAND_HALF;

		lo[j] = a <= 0 ? -(double)INFINITY : samp[a];
		hi[j] = b >= (long)ns - 1 ? (double)INFINITY : samp[b];
		buf[j] = ssc_alloc_array(cap, sizeof(double));
		if (!buf[j])
			rc = -ENOMEM;
	}
	for (size_t i = 0; i < n && !rc; i++) {
		double v = vs[i];

		if (!isfinite(v))
			continue;
		for (int j = 0; j < nk; j++) {
			if (v < lo[j]) {
				below[j]++;
			} else if (v <= hi[j]) {
				if (in[j] == cap) {
					rc = -EAGAIN;
					break;
				}
				buf[j][in[j]++] = v;
			}
		}
	}
	for (int j = 0; j < nk && !rc; j++)
		if (!(k[j] >= below[j] && k[j] - below[j] < in[j]))
			rc = -EAGAIN;
	for (int j = 0; j < nk && !rc; j++)
		out[j] = gsl_stats_select(buf[j], 1, in[j], k[j] - below[j]);
	free(buf[0]);
	free(buf[1]);
	return rc;
}

int ssc_calib_vs_deciles(const double *vs, size_t n, double *work,
			 size_t min_finite, double *p10, double *p90)
{
	size_t nf = 0, k[2];
	double q[2];

	for (size_t i = 0; i < n; i++)
		nf += isfinite(vs[i]) != 0;
	if (nf == 0 || nf < min_finite)
		return -EDOM;
	k[0] = (nf - 1) / 10;
	k[1] = (nf - 1) * 9 / 10;
	if (nf >= 64 * BAND_SAMPLE &&
	    band_select(vs, n, nf, k, p90 ? 2 : 1, q) == 0) {
		*p10 = q[0];
		if (p90)
			*p90 = q[1];
		return 0;
	}
	nf = 0;
	for (size_t i = 0; i < n; i++)
		if (isfinite(vs[i]))
			work[nf++] = vs[i];
	/* order statistics by selection (GSL's quickselect, O(n); a full
	 * sort of a day's record took seconds), the values a sort gives */
	*p10 = gsl_stats_select(work, 1, nf, k[0]);
	if (p90)
		*p90 = gsl_stats_select(work, 1, nf, k[1]);
	return 0;
}

int sscope_calib_static_reference(const double *x, const double *y,
				  const double *z, size_t stride, size_t n,
				  double rate_hz, double init_static_s,
				  const double *vs, double *work,
				  double *reference, struct sscope_diag *diag)
{
	if (!x || !y || !z || !vs || !work || !reference || stride == 0 ||
	    !(rate_hz > 0))
		return ssc_diag(diag, -EINVAL, "static detector: bad parameter");
	if (init_static_s > 0) {
		size_t m = ssc_count(round(init_static_s * rate_hz));
		double v2 = 0;

		if (m < 3 || m > n)
			return ssc_diag(diag, -EDOM,
					"initial static period of %g s does not fit the capture",
					init_static_s);
		for (int ch = 0; ch < 3; ch++) {
			const double *p = ch == 0 ? x : ch == 1 ? y : z;
			struct sscope_stats st;

			sscope_stats_compute(p, stride, m, &st);
			v2 += st.sd * st.sd * st.sd * st.sd;
		}
		*reference = sqrt(v2);
	} else if (ssc_calib_vs_deciles(vs, n, work, 1, reference, NULL)) {
		return ssc_diag(diag, -EDOM, "no detector window with a finite variance: the record is too short, or its samples too large to square (beyond about 1e154)");
	}
	if (!(*reference > 0))
		return ssc_diag(diag, -EDOM,
				"the detector's channels do not vary at all (zero noise): cannot set a static threshold");
	return 0;
}

int sscope_calib_accel_multipos(const double *x, const double *y,
				const double *z, size_t stride, size_t n,
				double rate_hz, double gravity_m_s2,
				struct sscope_calib_detect *det,
				struct sscope_calib_interval *iv, size_t max_iv,
				struct sscope_calib_triad *c, double *work,
				double *work2, struct sscope_diag *diag)
{
	double win_s, min_s, (*means)[3] = NULL;
	size_t window, min_len;
	double best = INFINITY, best_k = 0;
	int rc, last_rc = -EDOM;
	struct sscope_diag last = { "" };
	struct sscope_calib_triad trial;

	if (!x || !y || !z || !det || !iv || !c || !work || !work2 ||
	    !(rate_hz > 0) || stride == 0 || max_iv == 0)
		return ssc_diag(diag, -EINVAL, "calibration: bad parameter");
	/* least squares on squared magnitudes: samples in a sane range */
	if ((rc = ssc_magnitude_check(x, stride, n, 250, "calibration", diag)) ||
	    (rc = ssc_magnitude_check(y, stride, n, 250, "calibration", diag)) ||
	    (rc = ssc_magnitude_check(z, stride, n, 250, "calibration", diag)))
		return rc;
	win_s = det->window_s > 0 ? det->window_s : 1.0;
	min_s = det->min_static_s > 0 ? det->min_static_s : 2.0;
	window = ssc_count(round(win_s * rate_hz));
	if (window < 3)
		window = 3;
	min_len = ssc_count(round(min_s * rate_hz));
	rc = sscope_calib_variance_magnitude(x, y, z, stride, n, window, work);
	if (rc)
		return ssc_diag(diag, rc == -EDOM ? -EDOM : rc,
				"%zu samples: shorter than the %g s variance window",
				n, win_s);
	rc = sscope_calib_static_reference(x, y, z, stride, n, rate_hz,
					   det->init_static_s, work, work2,
					   &det->reference, diag);
	if (rc)
		return rc;
	means = ssc_alloc_array(max_iv, sizeof(*means));
	if (!means)
		return -ENOMEM;
	for (int kk = 2; kk <= 10; kk++) {
		double k = det->k > 0 ? det->k : (double)kk;
		size_t cnt;

		sscope_calib_static_intervals(work, n, k * det->reference,
					      min_len, iv, max_iv, &cnt);
		if (cnt > max_iv)
			cnt = max_iv;
		for (size_t q = 0; q < cnt; q++) {
			sscope_calib_interval_mean(x, stride, &iv[q], &means[q][0], NULL);
			sscope_calib_interval_mean(y, stride, &iv[q], &means[q][1], NULL);
			sscope_calib_interval_mean(z, stride, &iv[q], &means[q][2], NULL);
		}
		rc = sscope_calib_accel_fit((const double(*)[3])means, cnt,
					    gravity_m_s2, &trial, &last);
		if (rc == -ENOMEM) {
			free(means);
			return rc;
		}
		if (rc == 0 && trial.residual_rms < best) {
			best = trial.residual_rms;
			best_k = k;
			*c = trial;
		}
		last_rc = rc;
		det->n_intervals = cnt; /* (the last trial's, on failure) */
		if (det->k > 0)
			break;
	}
	free(means);
	if (!isfinite(best)) {
		if (diag)
			*diag = last;
		return last_rc;
	}
	det->k = best_k;
	det->threshold = best_k * det->reference;
	sscope_calib_static_intervals(work, n, det->threshold, min_len, iv,
				      max_iv, &det->n_intervals);
	if (det->n_intervals > max_iv)
		det->n_intervals = max_iv;
	return 0;
}

/* ------------------------------------------------------------------ */
/* Gyro multi-position fit                                             */
/* ------------------------------------------------------------------ */

struct gyro_ctx {
	const double *const *g;
	size_t stride, n;
	double dt, s0;
	const struct sscope_calib_interval *iv;
	size_t n_iv;
	double (*u)[3];   /* calibrated gravity direction per pose */
	double bias[3];
	double G[3][3];
	bool with_g;
	const double *const *a;
};

/* T = I + off-diagonal p[0..5] (row-major), K = diag(p[6..8]) * s0 */
static void gyro_params(const double *p, double s0, double C[3][3])
{
	double T[3][3] = { { 1, p[0], p[1] }, { p[2], 1, p[3] },
			   { p[4], p[5], 1 } };

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			C[i][j] = T[i][j] * p[6 + j] * s0;
}

static void gyro_rate(const struct gyro_ctx *gc, double C[3][3], size_t k,
		      double w[3])
{
	double u[3];

	for (int i = 0; i < 3; i++) {
		u[i] = gc->g[i][k * gc->stride] - gc->bias[i];
		if (gc->with_g)
			for (int j = 0; j < 3; j++)
				u[i] -= gc->G[i][j] * gc->a[j][k * gc->stride];
	}
	for (int i = 0; i < 3; i++)
		w[i] = C[i][0] * u[0] + C[i][1] * u[1] + C[i][2] * u[2];
}

/* quaternion product r = p * q, (w, x, y, z) */
static void qmul(const double p[4], const double q[4], double r[4])
{
	double t[4];

	t[0] = p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3];
	t[1] = p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2];
	t[2] = p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1];
	t[3] = p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0];
	memcpy(r, t, sizeof(t));
}

/* Rotation R (body k-1 -> body k, R = prod exp([theta]x)) integrated with
 * the trapezoid-averaged rate over each sample interval; v' = R^T v. */
static void gyro_rotate(const struct gyro_ctx *gc, double C[3][3], size_t s,
			size_t e, const double v[3], double out[3])
{
	double q[4] = { 1, 0, 0, 0 }, w0[3], w1[3];

	gyro_rate(gc, C, s, w0);
	for (size_t k = s; k + 1 <= e && k + 1 < gc->n; k++) {
		double th[3], ang, dq[4], sn;

		gyro_rate(gc, C, k + 1, w1);
		for (int i = 0; i < 3; i++) {
			th[i] = 0.5 * (w0[i] + w1[i]) * gc->dt;
			w0[i] = w1[i];
		}
		ang = sqrt(th[0] * th[0] + th[1] * th[1] + th[2] * th[2]);
		sn = ang > 1e-8 ? sin(ang / 2) / ang : 0.5 - ang * ang / 48;
		dq[0] = cos(ang / 2);
		dq[1] = th[0] * sn;
		dq[2] = th[1] * sn;
		dq[3] = th[2] * sn;
		qmul(q, dq, q);
	}
	/* normalise, then R from q; out = R^T v */
	{
		double nq = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] +
				 q[3] * q[3]);
		double w = q[0] / nq, x = q[1] / nq, y = q[2] / nq,
		       z = q[3] / nq;
		double R[3][3] = {
			{ 1 - 2 * (y * y + z * z), 2 * (x * y - w * z),
			  2 * (x * z + w * y) },
			{ 2 * (x * y + w * z), 1 - 2 * (x * x + z * z),
			  2 * (y * z - w * x) },
			{ 2 * (x * z - w * y), 2 * (y * z + w * x),
			  1 - 2 * (x * x + y * y) }
		};

		for (int i = 0; i < 3; i++)
			out[i] = R[0][i] * v[0] + R[1][i] * v[1] + R[2][i] * v[2];
	}
}

static int gyro_f(const gsl_vector *x, void *params, gsl_vector *f)
{
	const struct gyro_ctx *gc = params;
	double C[3][3];

	gyro_params(x->data, gc->s0, C);
	for (size_t k = 1; k < gc->n_iv; k++) {
		double pred[3];
		size_t s = gc->iv[k - 1].end - 1, e = gc->iv[k].start;

		gyro_rotate(gc, C, s, e, gc->u[k - 1], pred);
		for (int i = 0; i < 3; i++)
			gsl_vector_set(f, 3 * (k - 1) + (size_t)i,
				       gc->u[k][i] - pred[i]);
	}
	return GSL_SUCCESS;
}

static double gyro_cost(struct gyro_ctx *gc, const double *p)
{
	gsl_vector *f = gsl_vector_alloc(3 * (gc->n_iv - 1));
	gsl_vector_const_view xv = gsl_vector_const_view_array(p, 9);
	double c;

	if (!f)
		return INFINITY;
	gyro_f(&xv.vector, gc, f);
	gsl_blas_ddot(f, f, &c);
	gsl_vector_free(f);
	return c;
}

int sscope_calib_gyro_fit(const double *const g[3],
			  const double *const accel_cal[3], size_t stride,
			  size_t n, double rate_hz, double scale_guess,
			  const struct sscope_calib_interval *iv, size_t n_iv,
			  bool with_gsens, struct sscope_calib_triad *c,
			  struct sscope_diag *diag)
{
	struct gyro_ctx gc = { 0 };
	gsl_multifit_nlinear_fdf fdf;
	struct lm_out o;
	double x0[9] = { 0, 0, 0, 0, 0, 0, 1, 1, 1 }, s2, w_rms = 0;
	int rc = 0;

	if (!g || !accel_cal || !c || !iv || stride == 0 || !(rate_hz > 0) ||
	    scale_guess < 0)
		return ssc_diag(diag, -EINVAL, "calibration: bad parameter");
	for (int i = 0; i < 3; i++)
		if (!g[i] || !accel_cal[i])
			return ssc_diag(diag, -EINVAL, "calibration: bad parameter");
	for (int i = 0; i < 3; i++)
		if ((rc = ssc_magnitude_check(g[i], stride, n, 250, "gyro calibration",
					      diag)) ||
		    (rc = ssc_magnitude_check(accel_cal[i], stride, n, 250,
					      "gyro calibration", diag)))
			return rc;
	for (size_t k = 0; k < n_iv; k++)
		if (iv[k].end <= iv[k].start || iv[k].end > n ||
		    (k && iv[k].start < iv[k - 1].end))
			return ssc_diag(diag, -EINVAL,
					"static intervals out of order");
	if (n_iv < 6)
		return ssc_diag(diag, -EDOM,
				"%zu static poses (%zu rotations): the 9-parameter gyro model needs at least 6 poses",
				n_iv, n_iv ? n_iv - 1 : 0);
	sscope_calib_triad_identity(c);
	gc.g = g;
	gc.a = accel_cal;
	gc.stride = stride;
	gc.n = n;
	gc.dt = 1 / rate_hz;
	gc.iv = iv;
	gc.n_iv = n_iv;
	gc.u = ssc_alloc_array(n_iv, sizeof(*gc.u));
	if (!gc.u)
		return -ENOMEM;
	/* static means: gravity direction and gyro bias (and G) */
	{
		double (*gm)[3] = ssc_alloc_array(n_iv, sizeof(*gm));
		double (*am)[3] = ssc_alloc_array(n_iv, sizeof(*am));
		struct ssc_ksum bs[3] = { { 0, 0 } };
		struct ssc_ksum vs[3] = { { 0, 0 } };
		size_t tot = 0;

		if (!gm || !am) {
			free(gm);
			free(am);
			free(gc.u);
			return -ENOMEM;
		}
		for (size_t k = 0; k < n_iv; k++) {
			double nrm = 0, len = (double)(iv[k].end - iv[k].start);

			for (int i = 0; i < 3; i++) {
				double sd;

				sscope_calib_interval_mean(accel_cal[i], stride, &iv[k],
							   &am[k][i], NULL);
				sscope_calib_interval_mean(g[i], stride, &iv[k],
							   &gm[k][i], &sd);
				nrm += am[k][i] * am[k][i];
				ssc_ksum_add(&bs[i], gm[k][i] * len);
				if (isfinite(sd))
					ssc_ksum_add(&vs[i], sd * sd * (len - 1));
			}
			tot += iv[k].end - iv[k].start;
			nrm = sqrt(nrm);
			if (!(nrm > 0)) {
				free(gm);
				free(am);
				free(gc.u);
				return ssc_diag(diag, -EDOM,
						"pose %zu: the accelerometer reads zero", k + 1);
			}
			for (int i = 0; i < 3; i++)
				gc.u[k][i] = am[k][i] / nrm;
		}
		for (int i = 0; i < 3; i++) {
			gc.bias[i] = ssc_ksum_value(&bs[i]) / (double)tot;
			c->bias_sd[i] = sqrt(ssc_ksum_value(&vs[i]) /
					     (double)(tot - n_iv)) /
					sqrt((double)tot);
		}
		if (with_gsens) {
			struct sscope_calib_linear lf;

			rc = sscope_calib_linear_fit((const double(*)[3])gm,
						     (const double(*)[3])am, n_iv,
						     false, &lf, diag);
			if (!rc && !(lf.axis_excited[0] && lf.axis_excited[1] &&
				     lf.axis_excited[2]))
				rc = ssc_diag(diag, -EDOM,
					      "the poses do not tilt gravity onto all three axes: g-sensitivity not determined");
			if (!rc) {
				gc.with_g = true;
				c->has_gsens = true;
				for (int i = 0; i < 3; i++) {
					gc.bias[i] = lf.bias[i];
					c->bias_sd[i] = lf.bias_sd[i];
					for (int j = 0; j < 3; j++) {
						gc.G[i][j] = c->gsens[i][j] = lf.A[i][j];
						c->gsens_sd[i][j] = lf.A_sd[i][j];
					}
				}
			}
		}
		free(gm);
		free(am);
		if (rc) {
			free(gc.u);
			return rc;
		}
	}
	/* excitation of the motions; their rms rate (raw units) sets the
	 * scale of the starting-value search, so that the search, and with
	 * it the fit, is the same in any affine raw units */
	{
		double M[3][3] = { { 0 } }, e;
		size_t cnt = 0;

		for (size_t k = 1; k < n_iv; k++)
			for (size_t q = iv[k - 1].end; q < iv[k].start; q++) {
				double w[3];

				cnt++;

				for (int i = 0; i < 3; i++)
					w[i] = g[i][q * stride] - gc.bias[i];
				for (int i = 0; i < 3; i++)
					for (int j = 0; j < 3; j++)
						M[i][j] += w[i] * w[j];
			}
		w_rms = cnt ? sqrt((M[0][0] + M[1][1] + M[2][2]) / (double)cnt) : 0;
		e = min_eig_ratio(M);
		if (e < EXCITE_MIN || !(w_rms > 0)) {
			free(gc.u);
			return ssc_diag(diag, -EDOM,
					"the %zu rotations do not determine the 9 gyro parameters: one direction carries %.2g %% of the rotation (need 1 %%): rotate about all three axes",
					n_iv - 1, 100 * e);
		}
	}
	/* starting scale */
	if (scale_guess > 0) {
		gc.s0 = scale_guess;
	} else {
		double bestc = INFINITY, bests = 1;

		/* 1 rad/s per rms raw unit, times 1e-6 .. 1e6 */
		for (int e = -60; e <= 60; e++) {
			double p[9] = { 0, 0, 0, 0, 0, 0, 1, 1, 1 }, cst;

			gc.s0 = pow(10, e / 10.0) / w_rms;
			cst = gyro_cost(&gc, p);
			if (cst < bestc) {
				bestc = cst;
				bests = gc.s0;
			}
		}
		gc.s0 = bests;
	}
	fdf.f = gyro_f;
	fdf.df = NULL;
	fdf.fvv = NULL;
	fdf.n = 3 * (n_iv - 1);
	fdf.p = 9;
	fdf.params = &gc;
	rc = lm_solve(&fdf, x0, &o);
	if (rc == -ENOMEM)
		goto out;
	if (rc == -ERANGE) {
		rc = ssc_diag(diag, -EDOM,
			      "the %zu rotations do not determine the 9 gyro parameters (condition number %.3g): rotate about all three axes",
			      n_iv - 1, o.cond);
		goto out;
	}
	if (rc) {
		rc = ssc_diag(diag, -EDOM, "the gyro fit did not converge");
		goto out;
	}
	/* residual dof: two per rotation (unit vectors), minus 9 */
	s2 = 2 * (n_iv - 1) > 9 ? o.rss / (double)(2 * (n_iv - 1) - 9) :
				  (double)NAN;
	{
		const int ij[6][2] = { { 0, 1 }, { 0, 2 }, { 1, 0 },
				       { 1, 2 }, { 2, 0 }, { 2, 1 } };

		for (int q = 0; q < 6; q++) {
			c->mis[ij[q][0]][ij[q][1]] = o.x[q];
			c->mis_sd[ij[q][0]][ij[q][1]] = sqrt(s2 * o.cov[q][q]);
		}
		for (int i = 0; i < 3; i++) {
			c->mis[i][i] = 1;
			c->mis_sd[i][i] = 0;
			c->scale[i] = o.x[6 + i] * gc.s0;
			c->scale_sd[i] = sqrt(s2 * o.cov[6 + i][6 + i]) * gc.s0;
			c->bias[i] = gc.bias[i];
		}
	}
	c->n_params = with_gsens ? 21 : 12;
	c->poses = n_iv;
	c->residual_rms = sqrt(o.rss / (double)(3 * (n_iv - 1)));
	c->iterations = (unsigned)o.iter;
	c->cond = o.cond;
	rc = 0;
out:
	free(gc.u);
	return rc;
}

int sscope_calib_gyro_motion_errors(const double *const g[3],
				    const double *const accel_cal[3],
				    size_t stride, size_t n, double rate_hz,
				    const struct sscope_calib_interval *iv,
				    size_t n_iv,
				    const struct sscope_calib_triad *c,
				    double *angle_rad)
{
	struct gyro_ctx gc = { 0 };
	double C[3][3];

	if (!g || !accel_cal || !c || !iv || !angle_rad || stride == 0 ||
	    !(rate_hz > 0) || n_iv < 2)
		return -EINVAL;
	for (int i = 0; i < 3; i++)
		if (!g[i] || !accel_cal[i])
			return -EINVAL;
	for (size_t k = 0; k < n_iv; k++)
		if (iv[k].end <= iv[k].start || iv[k].end > n ||
		    (k && iv[k].start < iv[k - 1].end))
			return -EINVAL;
	gc.g = g;
	gc.a = accel_cal;
	gc.stride = stride;
	gc.n = n;
	gc.dt = 1 / rate_hz;
	gc.with_g = c->has_gsens;
	for (int i = 0; i < 3; i++) {
		gc.bias[i] = c->bias[i];
		for (int j = 0; j < 3; j++)
			gc.G[i][j] = c->gsens[i][j];
	}
	triad_matrix(c, C);
	for (size_t k = 1; k < n_iv; k++) {
		double u0[3], u1[3], pred[3], d2 = 0, n0 = 0, n1 = 0;

		for (int i = 0; i < 3; i++) {
			sscope_calib_interval_mean(accel_cal[i], stride, &iv[k - 1],
						   &u0[i], NULL);
			sscope_calib_interval_mean(accel_cal[i], stride, &iv[k],
						   &u1[i], NULL);
			n0 += u0[i] * u0[i];
			n1 += u1[i] * u1[i];
		}
		if (!(n0 > 0) || !(n1 > 0))
			return -EDOM;
		for (int i = 0; i < 3; i++) {
			u0[i] /= sqrt(n0);
			u1[i] /= sqrt(n1);
		}
		gyro_rotate(&gc, C, iv[k - 1].end - 1, iv[k].start, u0, pred);
		for (int i = 0; i < 3; i++)
			d2 += (u1[i] - pred[i]) * (u1[i] - pred[i]);
		/* chord of two unit vectors -> angle between them */
		angle_rad[k - 1] = 2 * asin(fmin(1, sqrt(d2) / 2));
	}
	return 0;
}

/* ------------------------------------------------------------------ */
/* Known-reference (linear) fits                                       */
/* ------------------------------------------------------------------ */

/* Least squares of one output axis on the columns selected. */
static int lin_axis(const double (*y)[3], const double (*r)[3], size_t n,
		    int out_axis, const bool exc[3], bool nonlin,
		    double coef[6], double sd[6], double *rms, double *maxres,
		    double *cond)
{
	size_t p = 1, col;
	int idx[6];
	gsl_matrix *X, *cov;
	gsl_vector *yv, *c;
	gsl_multifit_linear_workspace *w;
	double chisq;
	int rc = 0;

	idx[0] = -1; /* intercept */
	for (int j = 0; j < 3; j++)
		if (exc[j])
			idx[p++] = j;
	if (nonlin && exc[out_axis]) {
		idx[p++] = 10; /* r_own^2 */
		idx[p++] = 11; /* r_own^3 */
	}
	if (n <= p)
		return -EDOM;
	X = gsl_matrix_alloc(n, p);
	cov = gsl_matrix_alloc(p, p);
	yv = gsl_vector_alloc(n);
	c = gsl_vector_alloc(p);
	w = gsl_multifit_linear_alloc(n, p);
	if (!X || !cov || !yv || !c || !w) {
		rc = -ENOMEM;
		goto out;
	}
	for (size_t k = 0; k < n; k++) {
		double ro = r[k][out_axis];

		gsl_vector_set(yv, k, y[k][out_axis]);
		for (col = 0; col < p; col++) {
			double v = idx[col] < 0 ? 1 :
				   idx[col] == 10 ? ro * ro :
				   idx[col] == 11 ? ro * ro * ro :
						    r[k][idx[col]];

			gsl_matrix_set(X, k, col, v);
		}
	}
	/* scale columns to unit max for conditioning */
	{
		double sc[6];

		for (col = 0; col < p; col++) {
			double m = 0;

			for (size_t k = 0; k < n; k++)
				m = fmax(m, fabs(gsl_matrix_get(X, k, col)));
			sc[col] = m > 0 ? m : 1;
			for (size_t k = 0; k < n; k++)
				gsl_matrix_set(X, k, col,
					       gsl_matrix_get(X, k, col) / sc[col]);
		}
		gsl_multifit_linear(X, yv, c, cov, &chisq, w);
		*cond = 1 / gsl_multifit_linear_rcond(w);
		if (!(*cond < 1e12)) {
			rc = -EDOM;
			goto out;
		}
		for (int q = 0; q < 6; q++)
			coef[q] = sd[q] = 0;
		/* map back: coef order [b, A_x, A_y, A_z, c2, c3] */
		for (col = 0; col < p; col++) {
			int slot = idx[col] < 0 ? 0 : idx[col] == 10 ? 4 :
				   idx[col] == 11 ? 5 : 1 + idx[col];

			coef[slot] = gsl_vector_get(c, col) / sc[col];
			sd[slot] = sqrt(gsl_matrix_get(cov, col, col)) / sc[col];
		}
		*rms = sqrt(chisq / (double)n);
		*maxres = 0;
		for (size_t k = 0; k < n; k++) {
			double pred = 0;

			for (col = 0; col < p; col++)
				pred += gsl_matrix_get(X, k, col) *
					gsl_vector_get(c, col);
			*maxres = fmax(*maxres, fabs(y[k][out_axis] - pred));
		}
	}
out:
	gsl_matrix_free(X);
	gsl_matrix_free(cov);
	gsl_vector_free(yv);
	gsl_vector_free(c);
	gsl_multifit_linear_free(w);
	return rc;
}

int sscope_calib_linear_fit(const double (*y)[3], const double (*r)[3],
			    size_t n, bool nonlinear,
			    struct sscope_calib_linear *out,
			    struct sscope_diag *diag)
{
	double rmax = 0;
	bool any = false;

	if (!y || !r || !out)
		return ssc_diag(diag, -EINVAL, "calibration: bad parameter");
	memset(out, 0, sizeof(*out));
	for (size_t k = 0; k < n; k++)
		for (int i = 0; i < 3; i++) {
			if (!isfinite(y[k][i]) || !isfinite(r[k][i]))
				return ssc_diag(diag, -EINVAL,
						"point %zu: non-finite value", k + 1);
			rmax = fmax(rmax, fabs(r[k][i]));
		}
	for (int j = 0; j < 3; j++) {
		double lo = INFINITY, hi = -INFINITY;

		for (size_t k = 0; k < n; k++) {
			lo = fmin(lo, r[k][j]);
			hi = fmax(hi, r[k][j]);
		}
		out->axis_excited[j] = n > 0 && hi - lo > 1e-9 * rmax;
		out->full_scale[j] = n > 0 ? fmax(fabs(lo), fabs(hi)) : 0;
		any |= out->axis_excited[j];
	}
	if (!any)
		return ssc_diag(diag, -EDOM,
				"the reference never changes: nothing to fit");
	out->nonlinear = nonlinear;
	out->points = n;
	for (int i = 0; i < 3; i++) {
		double coef[6], sd[6], rms, maxres, cond;
		int rc = lin_axis(y, r, n, i, out->axis_excited, false, coef, sd,
				  &rms, &maxres, &cond);

		if (rc == -ENOMEM)
			return rc;
		if (rc)
			return ssc_diag(diag, -EDOM,
					"%zu reference points do not determine the linear model (too few, or the inputs move together)",
					n);
		out->cond = fmax(out->cond, cond);
		out->bias[i] = coef[0];
		out->bias_sd[i] = sd[0];
		for (int j = 0; j < 3; j++) {
			out->A[i][j] = coef[1 + j];
			out->A_sd[i][j] = out->axis_excited[j] ? sd[1 + j] :
								 (double)NAN;
		}
		out->sf_bfsl[i] = coef[1 + i];
		out->residual_rms[i] = rms;
		out->nonlinearity[i] =
			out->axis_excited[i] && out->full_scale[i] > 0 &&
					fabs(coef[1 + i]) > 0 ?
				maxres / (fabs(coef[1 + i]) * out->full_scale[i]) :
				(double)NAN;
		out->c2[i] = out->c3[i] = 0;
		out->c2_sd[i] = out->c3_sd[i] = NAN;
		if (nonlinear && out->axis_excited[i]) {
			rc = lin_axis(y, r, n, i, out->axis_excited, true, coef,
				      sd, &rms, &maxres, &cond);
			if (rc == -ENOMEM)
				return rc;
			if (rc)
				return ssc_diag(diag, -EDOM,
						"%zu reference points do not determine the cubic model of axis %d (need more rate levels)",
						n, i + 1);
			out->bias[i] = coef[0];
			out->bias_sd[i] = sd[0];
			for (int j = 0; j < 3; j++)
				if (out->axis_excited[j]) {
					out->A[i][j] = coef[1 + j];
					out->A_sd[i][j] = sd[1 + j];
				}
			out->cond = fmax(out->cond, cond);
			out->c2[i] = coef[4];
			out->c2_sd[i] = sd[4];
			out->c3[i] = coef[5];
			out->c3_sd[i] = sd[5];
		}
	}
	return 0;
}

int sscope_calib_linear_to_triad(const struct sscope_calib_linear *lf,
				 struct sscope_calib_triad *c)
{
	gsl_matrix *A, *inv;
	gsl_permutation *perm;
	int sg, rc = 0;
	double C[3][3];

	if (!lf || !c)
		return -EINVAL;
	if (!(lf->axis_excited[0] && lf->axis_excited[1] && lf->axis_excited[2]))
		return -EDOM;
	A = gsl_matrix_alloc(3, 3);
	inv = gsl_matrix_alloc(3, 3);
	perm = gsl_permutation_alloc(3);
	if (!A || !inv || !perm) {
		rc = -ENOMEM;
		goto out;
	}
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			gsl_matrix_set(A, i, j, lf->A[i][j]);
	gsl_linalg_LU_decomp(A, perm, &sg);
	if (!(fabs(gsl_linalg_LU_det(A, sg)) > 0)) {
		rc = -EDOM;
		goto out;
	}
	gsl_linalg_LU_invert(A, perm, inv);
	sscope_calib_triad_identity(c);
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			C[i][j] = gsl_matrix_get(inv, i, j);
	for (int j = 0; j < 3; j++) {
		c->scale[j] = C[j][j];
		c->bias[j] = lf->bias[j];
		c->bias_sd[j] = lf->bias_sd[j];
	}
	/* first order: dC = -C dA C, entries of A independent */
	for (int k = 0; k < 3; k++)
		for (int l = 0; l < 3; l++) {
			double v = 0;

			for (int i = 0; i < 3; i++)
				for (int j = 0; j < 3; j++)
					v += C[k][i] * C[k][i] * C[j][l] * C[j][l] *
					     lf->A_sd[i][j] * lf->A_sd[i][j];
			if (k == l)
				c->scale_sd[k] = sqrt(v);
			else
				c->mis_sd[k][l] = sqrt(v) / fabs(C[l][l]);
			c->mis[k][l] = k == l ? 1 : C[k][l] / C[l][l];
		}
	c->n_params = lf->nonlinear ? 18 : 12;
	c->poses = lf->points;
	c->residual_rms = sqrt((lf->residual_rms[0] * lf->residual_rms[0] +
				lf->residual_rms[1] * lf->residual_rms[1] +
				lf->residual_rms[2] * lf->residual_rms[2]) / 3);
	c->iterations = 0;
	c->cond = lf->cond;
out:
	gsl_matrix_free(A);
	gsl_matrix_free(inv);
	gsl_permutation_free(perm);
	return rc;
}

int sscope_calib_accel_sixpos(const double (*means)[3], size_t n_poses,
			      double gravity_m_s2,
			      struct sscope_calib_linear *lf,
			      struct sscope_calib_triad *c,
			      struct sscope_diag *diag)
{
	double (*r)[3];
	unsigned seen = 0;
	int rc;

	if (!means || !lf || !c || !(gravity_m_s2 > 0))
		return ssc_diag(diag, -EINVAL, "calibration: bad parameter");
	r = ssc_alloc_array(n_poses ? n_poses : 1, sizeof(*r));
	if (!r)
		return -ENOMEM;
	for (size_t k = 0; k < n_poses; k++) {
		int ax = 0;

		for (int i = 1; i < 3; i++)
			if (fabs(means[k][i]) > fabs(means[k][ax]))
				ax = i;
		r[k][0] = r[k][1] = r[k][2] = 0;
		r[k][ax] = means[k][ax] >= 0 ? gravity_m_s2 : -gravity_m_s2;
		seen |= 1u << (2 * ax + (means[k][ax] < 0));
	}
	if (seen != 0x3f) {
		static const char *nm[6] = { "+x", "-x", "+y", "-y", "+z", "-z" };
		char miss[40] = "";

		for (int q = 0; q < 6; q++)
			if (!(seen & (1u << q))) {
				strcat(miss, miss[0] ? " " : "");
				strcat(miss, nm[q]);
			}
		free(r);
		return ssc_diag(diag, -EDOM,
				"six-position test: %zu poses, no pose with %s up",
				n_poses, miss);
	}
	rc = sscope_calib_linear_fit(means, (const double(*)[3])r, n_poses,
				     false, lf, diag);
	free(r);
	if (rc)
		return rc;
	rc = sscope_calib_linear_to_triad(lf, c);
	if (rc)
		return ssc_diag(diag, rc, "six-position test: singular sensitivity matrix");
	return 0;
}

int sscope_calib_constant_segments(const double *r, size_t stride, size_t n,
				   double tol, size_t settle, size_t min_len,
				   struct sscope_calib_interval *iv,
				   size_t max, size_t *n_iv)
{
	size_t i = 0, count = 0;

	if (!r || stride == 0 || !n_iv || (max && !iv) || !(tol >= 0))
		return -EINVAL;
	if (min_len < 1)
		min_len = 1;
	while (i < n) {
		size_t s = i;
		double r0 = r[i * stride];

		/* at least one sample per run, so a NaN (never equal) ends it */
		i++;
		while (i < n && fabs(r[i * stride] - r0) <= tol)
			i++;
		if (!isfinite(r0))
			continue;
		if (i - s > settle && i - s - settle >= min_len) {
			if (count < max) {
				iv[count].start = s + settle;
				iv[count].end = i;
			}
			count++;
		}
	}
	*n_iv = count;
	return 0;
}

/* ------------------------------------------------------------------ */
/* Sensor classes                                                      */
/* ------------------------------------------------------------------ */

#define DPH (PI / 180 / 3600)            /* deg/h in rad/s */
#define DPSH (PI / 180 / 60)             /* deg/sqrt(h) in rad/sqrt(s) */
#define UG (SSCOPE_CALIB_GRAVITY_STD * 1e-6)   /* ug in m/s^2 */
#define DPHG (DPH / SSCOPE_CALIB_GRAVITY_STD)  /* deg/h/g in rad/s per m/s^2 */

/*
 * Typical performance by technology, orders of magnitude only.  Gyros after
 * the performance summaries in D. H. Titterton and J. L. Weston, "Strapdown
 * Inertial Navigation Technology", 2nd ed., IEE/AIAA 2004, ch. 4 (ring
 * laser, fibre optic, vibratory gyroscopes); accelerometer grades after
 * P. D. Groves, "Principles of GNSS, Inertial, and Multisensor Integrated
 * Navigation Systems", 2nd ed., Artech House 2013, sec. 4.4 (bias by IMU
 * grade).  The ranges were recalled, not copied from the books: they are
 * labelled "typical" in every output and are no specification.
 */
static const struct sscope_calib_class grades[] = {
	{ "ring laser gyro (RLG)", SSCOPE_QUANTITY_ANGULAR_RATE,
	  0.001 * DPH, 10 * DPH, 1e-6, 100e-6, 0.0005 * DPSH, 0.01 * DPSH,
	  0, 0.01 * DPHG },
	{ "fibre optic gyro (FOG)", SSCOPE_QUANTITY_ANGULAR_RATE,
	  0.01 * DPH, 50 * DPH, 10e-6, 1000e-6, 0.001 * DPSH, 0.5 * DPSH,
	  0, 1 * DPHG },
	{ "ceramic vibrating-structure gyro", SSCOPE_QUANTITY_ANGULAR_RATE,
	  360 * DPH, 3600 * DPH, 5000e-6, 50000e-6, 0.5 * DPSH, 5 * DPSH,
	  36 * DPHG, 360 * DPHG },
	{ "silicon vibrating-structure gyro (MEMS)", SSCOPE_QUANTITY_ANGULAR_RATE,
	  1 * DPH, 1800 * DPH, 100e-6, 20000e-6, 0.01 * DPSH, 1 * DPSH,
	  3.6 * DPHG, 360 * DPHG },
	{ "navigation-grade accelerometer", SSCOPE_QUANTITY_ACCELERATION,
	  10 * UG, 100 * UG, 10e-6, 200e-6, 5 * UG, 30 * UG, 0, 0 },
	{ "intermediate-grade accelerometer", SSCOPE_QUANTITY_ACCELERATION,
	  100 * UG, 1000 * UG, 100e-6, 1000e-6, 20 * UG, 100 * UG, 0, 0 },
	{ "tactical-grade accelerometer", SSCOPE_QUANTITY_ACCELERATION,
	  1000 * UG, 10000 * UG, 300e-6, 3000e-6, 50 * UG, 300 * UG, 0, 0 },
	{ "consumer/automotive accelerometer", SSCOPE_QUANTITY_ACCELERATION,
	  10000 * UG, 100000 * UG, 1000e-6, 30000e-6, 100 * UG, 1000 * UG, 0,
	  0 },
};

const struct sscope_calib_class *sscope_calib_grades(size_t *n)
{
	if (n)
		*n = sizeof(grades) / sizeof(grades[0]);
	return grades;
}

static double decades_out(double v, double lo, double hi)
{
	if (!(isfinite(v) && v > 0))
		return 0;
	if (lo > 0 && v < lo)
		return log10(lo / v);
	if (hi > 0 && v > hi)
		return log10(v / hi);
	return 0;
}

int sscope_calib_grade(enum sscope_quantity q, double bias, double sf,
		       double noise, double gsens, double *distance)
{
	size_t n, best_i = 0;
	const struct sscope_calib_class *g = sscope_calib_grades(&n);
	double best = INFINITY;
	int used = 0;

	if (q != SSCOPE_QUANTITY_ANGULAR_RATE && q != SSCOPE_QUANTITY_ACCELERATION)
		return -EINVAL;
	used = (isfinite(bias) && bias > 0) + (isfinite(sf) && sf > 0) +
	       (isfinite(noise) && noise > 0) + (isfinite(gsens) && gsens > 0);
	if (!used)
		return -EDOM;
	for (size_t i = 0; i < n; i++) {
		double d;

		if (g[i].quantity != q)
			continue;
		d = decades_out(bias, g[i].bias_lo, g[i].bias_hi) +
		    decades_out(sf, g[i].sf_lo, g[i].sf_hi) +
		    decades_out(noise, g[i].noise_lo, g[i].noise_hi);
		if (g[i].gsens_hi > 0)
			d += decades_out(gsens, g[i].gsens_lo, g[i].gsens_hi);
		if (d < best) {
			best = d;
			best_i = i;
		}
	}
	if (distance)
		*distance = best;
	return (int)best_i;
}
