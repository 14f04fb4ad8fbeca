/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Inclinometer tilt and temperature look-up-table calibration after
 * Analog Devices AN-1057 (C. Fisher, "Using an accelerometer for
 * inclination sensing", 2010): 1-axis asin, 2-axis atan2, 3-axis roll and
 * pitch; per-axis offset, scale and cross-axis coupling at each
 * temperature node by linear least squares on static poses of known tilt;
 * interpolation by GSL gsl_interp (linear / cubic spline), clamped outside
 * the calibrated range (as the Linux sca3300 driver and PX4 clamp
 * temperature compensation).
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_interp.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit.h>
#include <gsl/gsl_vector.h>

#include "sscope-inclino.h"

#define NPAR 12 /* 3 offsets, 3 scales, 6 couplings */

int sscope_inclino_tilt(enum sscope_inclino_axes axes, const double a[3],
			double g, double *roll, double *pitch, double *sens)
{
	double s = NAN;

	if (!a || !roll || !pitch)
		return -EINVAL;
	switch (axes) {
	case SSCOPE_INCLINO_1AXIS: {
		double r = -a[0] / g;

		if (!(g > 0))
			return -EINVAL;
		r = r > 1 ? 1 : r < -1 ? -1 : r;
		*roll = NAN;
		*pitch = asin(r);
		s = g * cos(*pitch);
		break;
	}
	case SSCOPE_INCLINO_2AXIS:
		*roll = NAN;
		*pitch = atan2(-a[0], a[2]);
		s = hypot(a[0], a[2]);
		break;
	case SSCOPE_INCLINO_3AXIS:
		*pitch = atan2(-a[0], hypot(a[1], a[2]));
		*roll = atan2(a[1], a[2]);
		s = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
		break;
	default:
		return -EINVAL;
	}
	if (sens)
		*sens = s;
	return 0;
}

static void truth(const struct sscope_inclino_pose *p, double g, double t[3])
{
	t[0] = -g * sin(p->pitch_rad);
	t[1] = g * sin(p->roll_rad) * cos(p->pitch_rad);
	t[2] = g * cos(p->roll_rad) * cos(p->pitch_rad);
}

int sscope_inclino_poses(const double *ax, const double *ay, const double *az,
			 const double *temp, const double *roll,
			 const double *pitch, size_t n, double tol,
			 struct sscope_inclino_pose *poses, size_t cap,
			 size_t *n_poses)
{
	size_t np = 0, i = 0;

	if (!ax || !ay || !az || !temp || !roll || !pitch || !n_poses ||
	    (cap && !poses))
		return -EINVAL;
	/* pose means feed fits of squared magnitudes */
	if (ssc_magnitude_check(ax, 1, n, 250, "", NULL) ||
	    ssc_magnitude_check(ay, 1, n, 250, "", NULL) ||
	    ssc_magnitude_check(az, 1, n, 250, "", NULL) ||
	    ssc_magnitude_check(temp, 1, n, 250, "", NULL))
		return -ERANGE;
	if (!(tol > 0))
		tol = 1;
	while (i < n) {
		size_t k = i, cnt = 0;
		double s[4] = { 0 };

		if (!isfinite(roll[i]) || !isfinite(pitch[i]) || !isfinite(temp[i])) {
			i++;
			continue;
		}
		while (k < n && roll[k] == roll[i] && pitch[k] == pitch[i] &&
		       (!isfinite(temp[k]) || fabs(temp[k] - temp[i]) <= tol)) {
			if (isfinite(ax[k]) && isfinite(ay[k]) && isfinite(az[k]) &&
			    isfinite(temp[k])) {
				s[0] += ax[k];
				s[1] += ay[k];
				s[2] += az[k];
				s[3] += temp[k];
				cnt++;
			}
			k++;
		}
		if (cnt > 0) {
			if (np < cap) {
				struct sscope_inclino_pose *p = &poses[np];

				for (int j = 0; j < 3; j++)
					p->a[j] = s[j] / (double)cnt;
				p->temp_degc = s[3] / (double)cnt;
				p->roll_rad = roll[i];
				p->pitch_rad = pitch[i];
				p->n = cnt;
			}
			np++;
		}
		i = k;
	}
	*n_poses = np;
	return np ? 0 : -EDOM;
}

int sscope_inclino_fit(const struct sscope_inclino_pose *poses, size_t n,
		       double g, struct sscope_inclino_params *p,
		       struct sscope_diag *diag)
{
	gsl_matrix *X, *cov;
	gsl_vector *y, *c;
	gsl_multifit_linear_workspace *w;
	struct ssc_gsl_quiet quiet;
	bool bad;
	int rc = 0;
	double ss = 0;

	if (!poses || !p || !(g > 0))
		return ssc_diag(diag, -EINVAL, "bad arguments");
	if (n < 5)
		return ssc_diag(diag, -EDOM, "%zu poses: at least 5 are needed", n);
	memset(p, 0, sizeof(*p));
	X = gsl_matrix_alloc(n, 4);
	cov = gsl_matrix_alloc(4, 4);
	y = gsl_vector_alloc(n);
	c = gsl_vector_alloc(4);
	w = gsl_multifit_linear_alloc(n, 4);
	if (!X || !cov || !y || !c || !w) {
		rc = ssc_diag(diag, -ENOMEM, "out of memory");
		goto out;
	}
	for (int ax = 0; ax < 3 && !rc; ax++) {
		double chisq;
		int o1 = (ax + 1) % 3, o2 = (ax + 2) % 3;

		for (size_t i = 0; i < n; i++) {
			double t[3];

			truth(&poses[i], g, t);
			/* scaled by g: columns of order 1 */
			gsl_matrix_set(X, i, 0, 1);
			gsl_matrix_set(X, i, 1, t[ax] / g);
			gsl_matrix_set(X, i, 2, t[o1] / g);
			gsl_matrix_set(X, i, 3, t[o2] / g);
			gsl_vector_set(y, i, poses[i].a[ax] / g);
		}
		/* poses that leave an axis unexcited are a result (-EDOM),
		 * not a fault */
		ssc_gsl_quiet_begin(&quiet);
		bad = gsl_multifit_linear(X, y, c, cov, &chisq, w) ||
		      !(gsl_multifit_linear_rcond(w) > 1e-8);
		ssc_gsl_quiet_end(&quiet);
		if (bad) {
			rc = ssc_diag(diag, -EDOM,
				      "the poses do not excite every axis (axis %c cannot be separated)",
				      "xyz"[ax]);
			break;
		}
		{
			/* gsl_multifit_linear's cov is already
			 * chisq / (n - p) * (X^T X)^-1 */
			double sc = 1;

			p->offset[ax] = g * gsl_vector_get(c, 0);
			p->scale[ax] = gsl_vector_get(c, 1);
			p->mis[ax][o1] = gsl_vector_get(c, 2);
			p->mis[ax][o2] = gsl_vector_get(c, 3);
			p->offset_sd[ax] = g * sqrt(gsl_matrix_get(cov, 0, 0) * sc);
			p->scale_sd[ax] = sqrt(gsl_matrix_get(cov, 1, 1) * sc);
			p->mis_sd[ax][o1] = sqrt(gsl_matrix_get(cov, 2, 2) * sc);
			p->mis_sd[ax][o2] = sqrt(gsl_matrix_get(cov, 3, 3) * sc);
			ss += chisq * g * g;
		}
	}
	p->residual_rms = sqrt(ss / (3.0 * (double)n));
	p->poses = n;
out:
	gsl_matrix_free(X);
	gsl_matrix_free(cov);
	gsl_vector_free(y);
	gsl_vector_free(c);
	if (w)
		gsl_multifit_linear_free(w);
	return rc;
}

static int cmp_pose_temp(const void *a, const void *b)
{
	double x = ((const struct sscope_inclino_pose *)a)->temp_degc;
	double y = ((const struct sscope_inclino_pose *)b)->temp_degc;

	return (x > y) - (x < y);
}

int sscope_inclino_build(const struct sscope_inclino_pose *poses, size_t n,
			 double g, double gap, struct sscope_inclino_lut *lut,
			 struct sscope_diag *diag)
{
	struct sscope_inclino_pose *s;
	size_t i = 0;
	int rc = 0;

	if (!poses || !lut || n == 0 || !(g > 0))
		return ssc_diag(diag, -EINVAL, "no poses");
	if (!(gap > 0))
		gap = 3;
	s = ssc_alloc_array(n, sizeof(*s));
	if (!s)
		return ssc_diag(diag, -ENOMEM, "out of memory");
	memcpy(s, poses, n * sizeof(*s));
	qsort(s, n, sizeof(*s), cmp_pose_temp);
	memset(lut, 0, sizeof(*lut));
	lut->gravity_m_s2 = g;
	while (i < n && !rc) {
		size_t k = i + 1;
		double st = s[i].temp_degc * (double)s[i].n, cnt = (double)s[i].n;

		while (k < n && s[k].temp_degc - s[k - 1].temp_degc <= gap) {
			st += s[k].temp_degc * (double)s[k].n;
			cnt += (double)s[k].n;
			k++;
		}
		if (lut->n == SSCOPE_INCLINO_MAX_NODES) {
			rc = ssc_diag(diag, -EDOM, "more than %d temperature nodes",
				      SSCOPE_INCLINO_MAX_NODES);
			break;
		}
		lut->temp_degc[lut->n] = st / cnt;
		rc = sscope_inclino_fit(s + i, k - i, g, &lut->p[lut->n], diag);
		if (rc) {
			char m[200];

			if (diag) {
				snprintf(m, sizeof(m), "%.150s", diag->msg);
				snprintf(diag->msg, sizeof(diag->msg),
					 "node at %.1f degC: %s", st / cnt, m);
			}
			break;
		}
		lut->n++;
		i = k;
	}
	free(s);
	return rc;
}

int sscope_inclino_check(const struct sscope_inclino_lut *lut,
			 struct sscope_diag *diag)
{
	if (!lut || lut->n == 0)
		return ssc_diag(diag, -EDOM, "the table has no node");
	if (lut->n > SSCOPE_INCLINO_MAX_NODES)
		return ssc_diag(diag, -EDOM, "more than %d nodes", SSCOPE_INCLINO_MAX_NODES);
	if (!(lut->gravity_m_s2 > 0) || !isfinite(lut->gravity_m_s2))
		return ssc_diag(diag, -EDOM, "gravity not positive");
	for (size_t i = 0; i < lut->n; i++) {
		const struct sscope_inclino_params *p = &lut->p[i];

		if (!isfinite(lut->temp_degc[i]))
			return ssc_diag(diag, -EDOM, "node %zu: temperature not finite", i + 1);
		if (i && !(lut->temp_degc[i] > lut->temp_degc[i - 1]))
			return ssc_diag(diag, -EDOM,
					"temperatures not strictly increasing (node %zu: %g degC after %g degC)",
					i + 1, lut->temp_degc[i], lut->temp_degc[i - 1]);
		for (int a = 0; a < 3; a++) {
			if (!isfinite(p->offset[a]) || !(p->scale[a] > 0) ||
			    !isfinite(p->scale[a]))
				return ssc_diag(diag, -EDOM, "node %zu: bad offset or scale of axis %c",
						i + 1, "xyz"[a]);
			for (int b = 0; b < 3; b++)
				if (!isfinite(p->mis[a][b]))
					return ssc_diag(diag, -EDOM, "node %zu: bad misalignment", i + 1);
		}
	}
	return 0;
}

struct sscope_inclino_plan {
	struct sscope_inclino_lut lut;
	gsl_interp *it[NPAR];
	gsl_interp_accel *acc;
	double y[NPAR][SSCOPE_INCLINO_MAX_NODES];
};

static const int mis_i[6][2] = { { 0, 1 }, { 0, 2 }, { 1, 0 },
				 { 1, 2 }, { 2, 0 }, { 2, 1 } };

void sscope_inclino_plan_free(struct sscope_inclino_plan *pl)
{
	if (!pl)
		return;
	for (int k = 0; k < NPAR; k++)
		if (pl->it[k])
			gsl_interp_free(pl->it[k]);
	if (pl->acc)
		gsl_interp_accel_free(pl->acc);
	free(pl);
}

int sscope_inclino_plan_new(struct sscope_inclino_plan **plan,
			    const struct sscope_inclino_lut *lut, bool cubic,
			    struct sscope_diag *diag)
{
	struct sscope_inclino_plan *pl;
	int rc;

	if (!plan)
		return ssc_diag(diag, -EINVAL, "NULL plan");
	*plan = NULL;
	rc = sscope_inclino_check(lut, diag);
	if (rc)
		return rc;
	pl = calloc(1, sizeof(*pl));
	if (!pl)
		return ssc_diag(diag, -ENOMEM, "out of memory");
	pl->lut = *lut;
	for (size_t i = 0; i < lut->n; i++) {
		for (int a = 0; a < 3; a++) {
			pl->y[a][i] = lut->p[i].offset[a];
			pl->y[3 + a][i] = lut->p[i].scale[a];
		}
		for (int k = 0; k < 6; k++)
			pl->y[6 + k][i] = lut->p[i].mis[mis_i[k][0]][mis_i[k][1]];
	}
	if (lut->n >= 2) {
		const gsl_interp_type *T = cubic && lut->n >= 3 ? gsl_interp_cspline :
								  gsl_interp_linear;

		pl->acc = gsl_interp_accel_alloc();
		if (!pl->acc)
			goto oom;
		for (int k = 0; k < NPAR; k++) {
			pl->it[k] = gsl_interp_alloc(T, lut->n);
			if (!pl->it[k])
				goto oom;
			gsl_interp_init(pl->it[k], pl->lut.temp_degc, pl->y[k], lut->n);
		}
	}
	*plan = pl;
	return 0;
oom:
	sscope_inclino_plan_free(pl);
	return ssc_diag(diag, -ENOMEM, "out of memory");
}

void sscope_inclino_params_at(struct sscope_inclino_plan *pl, double T,
			      struct sscope_inclino_params *p, bool *clamped)
{
	const struct sscope_inclino_lut *l = &pl->lut;
	double v[NPAR];
	bool cl = false;

	if (!(T >= l->temp_degc[0])) {
		T = l->temp_degc[0];
		cl = true;
	} else if (T > l->temp_degc[l->n - 1]) {
		T = l->temp_degc[l->n - 1];
		cl = true;
	}
	for (int k = 0; k < NPAR; k++)
		v[k] = l->n >= 2 ? gsl_interp_eval(pl->it[k], l->temp_degc, pl->y[k], T, pl->acc)
				 : pl->y[k][0];
	memset(p, 0, sizeof(*p));
	for (int a = 0; a < 3; a++) {
		p->offset[a] = v[a];
		p->scale[a] = v[3 + a];
	}
	for (int k = 0; k < 6; k++)
		p->mis[mis_i[k][0]][mis_i[k][1]] = v[6 + k];
	if (clamped)
		*clamped = cl;
}

static int solve(const struct sscope_inclino_params *p, const double raw[3],
		 double out[3])
{
	double A[3][3], r[3], det;

	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			A[i][j] = i == j ? p->scale[i] : p->mis[i][j];
		r[i] = raw[i] - p->offset[i];
	}
	det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
	      A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
	      A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
	if (!(fabs(det) > 1e-12))
		return -EDOM;
	/* Cramer's rule */
	for (int c = 0; c < 3; c++) {
		double M[3][3];

		memcpy(M, A, sizeof(M));
		for (int i = 0; i < 3; i++)
			M[i][c] = r[i];
		out[c] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
			  M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
			  M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) / det;
	}
	return 0;
}

int sscope_inclino_correct(struct sscope_inclino_plan *pl, double T,
			   const double raw[3], double out[3], bool *clamped)
{
	struct sscope_inclino_params p;

	sscope_inclino_params_at(pl, T, &p, clamped);
	return solve(&p, raw, out);
}

static double wrap_deg(double d)
{
	while (d > 180)
		d -= 360;
	while (d < -180)
		d += 360;
	return d;
}

/* Roll and pitch errors of one pose, calibrated (e) and raw (eu), deg;
 * false for a pose that is not used (beyond 85 degrees of pitch). */
static bool pose_error(struct sscope_inclino_plan *pl,
		       const struct sscope_inclino_pose *pose, double e[2],
		       double eu[2], bool *clamped)
{
	double c[3], r, p, ru, pu, g = pl->lut.gravity_m_s2;

	if (fabs(pose->pitch_rad) > 85 * PI / 180)
		return false;
	if (sscope_inclino_correct(pl, pose->temp_degc, pose->a, c, clamped))
		return false;
	sscope_inclino_tilt(SSCOPE_INCLINO_3AXIS, c, g, &r, &p, NULL);
	sscope_inclino_tilt(SSCOPE_INCLINO_3AXIS, pose->a, g, &ru, &pu, NULL);
	e[0] = wrap_deg((r - pose->roll_rad) * 180 / PI);
	e[1] = wrap_deg((p - pose->pitch_rad) * 180 / PI);
	eu[0] = wrap_deg((ru - pose->roll_rad) * 180 / PI);
	eu[1] = wrap_deg((pu - pose->pitch_rad) * 180 / PI);
	return true;
}

int sscope_inclino_pose_errors(struct sscope_inclino_plan *pl,
			       const struct sscope_inclino_pose *poses,
			       size_t n, double (*err_deg)[2],
			       double (*raw_deg)[2])
{
	size_t m = 0;

	if (!pl || !poses || !err_deg)
		return -EINVAL;
	for (size_t i = 0; i < n; i++) {
		double e[2], eu[2];
		bool cl;

		if (!pose_error(pl, &poses[i], e, eu, &cl)) {
			e[0] = e[1] = eu[0] = eu[1] = NAN;
		} else {
			m++;
		}
		err_deg[i][0] = e[0];
		err_deg[i][1] = e[1];
		if (raw_deg) {
			raw_deg[i][0] = eu[0];
			raw_deg[i][1] = eu[1];
		}
	}
	return m ? 0 : -EDOM;
}

int sscope_inclino_validate(struct sscope_inclino_plan *pl,
			    const struct sscope_inclino_pose *poses, size_t n,
			    struct sscope_inclino_validation *v)
{
	double s2 = 0, s2u = 0, g;
	size_t m = 0;

	if (!pl || !poses || !v)
		return -EINVAL;
	memset(v, 0, sizeof(*v));
	g = pl->lut.gravity_m_s2;
	for (size_t i = 0; i < n; i++) {
		double e[2], eu[2];
		bool cl;

		if (!pose_error(pl, &poses[i], e, eu, &cl))
			continue;
		v->clamped += cl;
		for (int k = 0; k < 2; k++) {
			v->max_deg = fmax(v->max_deg, fabs(e[k]));
			v->max_uncomp_deg = fmax(v->max_uncomp_deg, fabs(eu[k]));
			s2 += e[k] * e[k];
			s2u += eu[k] * eu[k];
		}
		m++;
	}
	v->poses = m;
	if (!m)
		return -EDOM;
	v->rms_deg = sqrt(s2 / (2.0 * (double)m));
	v->rms_uncomp_deg = sqrt(s2u / (2.0 * (double)m));
	/* residual model error: direct fit of the validation poses (one
	 * cluster per 3 degC) against the LUT's parameters there */
	v->offset_deg = v->scale_deg = v->mis_deg = NAN;
	{
		struct sscope_inclino_lut *vl = malloc(sizeof(*vl));

		if (vl && !sscope_inclino_build(poses, n, g, 3, vl, NULL)) {
			v->offset_deg = v->scale_deg = v->mis_deg = 0;
			for (size_t k = 0; k < vl->n; k++) {
				struct sscope_inclino_params q;

				sscope_inclino_params_at(pl, vl->temp_degc[k], &q, NULL);
				for (int a = 0; a < 3; a++) {
					v->offset_deg = fmax(v->offset_deg,
							     fabs(vl->p[k].offset[a] - q.offset[a]) / g * 180 / PI);
					v->scale_deg = fmax(v->scale_deg,
							    fabs(vl->p[k].scale[a] - q.scale[a]) / 0.0035 * 0.1);
					for (int b = 0; b < 3; b++)
						if (a != b)
							v->mis_deg = fmax(v->mis_deg,
									  fabs(vl->p[k].mis[a][b] - q.mis[a][b]) * 180 / PI);
				}
			}
			v->dominant = v->offset_deg >= v->scale_deg && v->offset_deg >= v->mis_deg ?
					      "offset" :
				      v->scale_deg >= v->mis_deg ? "scale" : "misalignment";
		}
		free(vl);
	}
	return 0;
}

int sscope_inclino_apply(struct sscope_inclino_plan *plan,
			 enum sscope_inclino_axes axes, double g_m_s2,
			 const double *const a[3], const double *temp,
			 const double *const w[3], size_t n, double still_tol,
			 double rate_tol, double *roll, double *pitch,
			 double *sens, bool *still,
			 struct sscope_inclino_apply_stats *st)
{
	if (!plan || !a || !temp || !pitch || !still || !st || !(g_m_s2 > 0))
		return -EINVAL;
	memset(st, 0, sizeof(*st));
	for (size_t i = 0; i < n; i++) {
		double raw[3] = { a[0][i], a[1][i], a[2][i] }, c[3];
		double r = NAN, p = NAN, sn = NAN;
		bool cl = false, ok;

		ok = isfinite(temp[i]) && isfinite(raw[0] + raw[1] + raw[2]) &&
		     sscope_inclino_correct(plan, temp[i], raw, c, &cl) == 0;
		still[i] = false;
		if (ok) {
			sscope_inclino_tilt(axes, c, g_m_s2, &r, &p, &sn);
			still[i] = fabs(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) -
					g_m_s2) <= still_tol;
			if (still[i] && w)
				still[i] = sqrt(w[0][i] * w[0][i] + w[1][i] * w[1][i] +
						w[2][i] * w[2][i]) <= rate_tol;
		} else {
			st->n_bad++;
		}
		st->n_clamped += cl;
		st->n_still += still[i];
		if (roll)
			roll[i] = r;
		pitch[i] = p;
		if (sens)
			sens[i] = sn;
	}
	return 0;
}
