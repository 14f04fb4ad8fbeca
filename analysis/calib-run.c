/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Calibration runs, from a capture's samples to what `calib` reports:
 * static poses at a fixed detector threshold and the six-position test
 * with the threshold chosen by the fit's residual (as Tedaldi et al. 2014
 * choose it for the multi-position fit), the g-dependent gyro bias from
 * static tilts, the steps of a rate table or centrifuge (segments of
 * constant reference, Lawrence, "Modern Inertial Technology", ch. 4 test
 * procedures), the noise density pooled over the static poses, the error
 * model A = (T K)^-1 of textbook eqs 93-94 and the class of the sensor, and
 * how a correction does over the poses and motions it was fitted to.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sscope-calib.h"
#include "sscope-quantity.h"
#include "sscope-unit.h"

/* varsigma into work and the detector's reference into det */
static int detect_reference(const double *x, const double *y, const double *z,
			    size_t stride, size_t n, double rate_hz,
			    struct sscope_calib_detect *det, double *work,
			    double *work2, struct sscope_diag *diag)
{
	double win_s;
	size_t window;
	int rc;

	if (!x || !y || !z || !det || !work || !work2 || !(rate_hz > 0) ||
	    stride == 0)
		return ssc_diag(diag, -EINVAL, "calibration: bad parameter");
	win_s = det->window_s > 0 ? det->window_s : 1.0;
	window = ssc_count(round(win_s * rate_hz));
	if (window < 3)
		window = 3;
	rc = sscope_calib_variance_magnitude(x, y, z, stride, n, window, work);
	if (rc)
		return ssc_diag(diag, rc,
				"%zu samples: shorter than the %g s variance window",
				n, win_s);
	return sscope_calib_static_reference(x, y, z, stride, n, rate_hz,
					     det->init_static_s, work, work2,
					     &det->reference, diag);
}

int sscope_calib_detect_static(const double *x, const double *y,
			       const double *z, size_t stride, size_t n,
			       double rate_hz, struct sscope_calib_detect *det,
			       struct sscope_calib_interval *iv, size_t max_iv,
			       double *work, double *work2,
			       struct sscope_diag *diag)
{
	double min_s;
	int rc;

	if (!det || !(det->k > 1) || !iv || max_iv == 0)
		return ssc_diag(diag, -EINVAL, "static detection: bad parameter");
	rc = detect_reference(x, y, z, stride, n, rate_hz, det,
					   work, work2, diag);
	if (rc)
		return rc;
	min_s = det->min_static_s > 0 ? det->min_static_s : 2.0;
	det->threshold = det->k * det->reference;
	sscope_calib_static_intervals(work, n, det->threshold,
				      ssc_count(round(min_s * rate_hz)), iv, max_iv,
				      &det->n_intervals);
	if (det->n_intervals > max_iv)
		det->n_intervals = max_iv;
	return 0;
}

/* mean readings of the static intervals */
static void pose_means(const double *const ch[3], size_t stride,
		       const struct sscope_calib_interval *iv, size_t n_iv,
		       double (*m)[3])
{
	for (size_t k = 0; k < n_iv; k++)
		for (int i = 0; i < 3; i++)
			sscope_calib_interval_mean(ch[i], stride, &iv[k], &m[k][i],
						   NULL);
}

int sscope_calib_accel_sixpos_run(const double *x, const double *y,
				  const double *z, size_t stride, size_t n,
				  double rate_hz, double gravity_m_s2,
				  struct sscope_calib_detect *det,
				  struct sscope_calib_interval *iv, size_t max_iv,
				  struct sscope_calib_linear *lf,
				  struct sscope_calib_triad *c, double *work,
				  double *work2, struct sscope_diag *diag)
{
	const double *ch[3] = { x, y, z };
	double (*m)[3], best = INFINITY, bk = 0, k0;
	struct sscope_calib_triad tc;
	struct sscope_calib_linear tl;
	struct sscope_diag d = { "" }, bd = { "" };
	int rc = -EDOM;

	if (!det || !lf || !c || !iv || max_iv == 0)
		return ssc_diag(diag, -EINVAL, "six-position calibration: bad parameter");
	k0 = det->k;
	m = ssc_alloc_array(max_iv, sizeof(*m));
	if (!m)
		return -ENOMEM;
	rc = detect_reference(x, y, z, stride, n, rate_hz, det,
					   work, work2, &bd);
	for (int kk = 2; !rc && kk <= 10; kk++) {
		double k = k0 > 0 ? k0 : (double)kk;
		size_t cnt;

		sscope_calib_static_intervals(work, n, k * det->reference,
					      ssc_count(round((det->min_static_s > 0 ?
							       det->min_static_s : 2) *
							      rate_hz)),
					      iv, max_iv, &cnt);
		if (cnt > max_iv)
			cnt = max_iv;
		pose_means(ch, stride, iv, cnt, m);
		if (sscope_calib_accel_sixpos((const double(*)[3])m, cnt,
					      gravity_m_s2, &tl, &tc, &d) == 0) {
			if (tc.residual_rms < best) {
				best = tc.residual_rms;
				bk = k;
				*c = tc;
				*lf = tl;
			}
		} else {
			bd = d;
		}
		if (k0 > 0)
			break;
	}
	free(m);
	if (!isfinite(best)) {
		if (diag)
			*diag = bd.msg[0] ? bd :
				(struct sscope_diag){ "no static intervals (capture shorter than the window, or zero noise)" };
		return rc ? rc : -EDOM;
	}
	det->k = bk;
	return sscope_calib_detect_static(x, y, z, stride, n, rate_hz, det, iv,
					  max_iv, work, work2, diag);
}

int sscope_calib_gyro_gsens_run(const double *const g[3],
				const double *const a[3], size_t stride,
				size_t n, double rate_hz,
				struct sscope_calib_detect *det,
				struct sscope_calib_interval *iv, size_t max_iv,
				struct sscope_calib_triad *c, double *work,
				double *work2, struct sscope_diag *diag)
{
	struct sscope_calib_linear lf;
	double (*gm)[3], (*am)[3];
	size_t np;
	int rc;

	if (!g || !a || !det || !c)
		return ssc_diag(diag, -EINVAL, "g-sensitivity: bad parameter");
	if (!(det->k > 0))
		det->k = 4;
	rc = sscope_calib_detect_static(a[0], a[1], a[2], stride, n, rate_hz,
					det, iv, max_iv, work, work2, diag);
	if (rc)
		return rc;
	np = det->n_intervals;
	gm = ssc_alloc_array(np ? np : 1, sizeof(*gm));
	am = ssc_alloc_array(np ? np : 1, sizeof(*am));
	if (!gm || !am) {
		free(gm);
		free(am);
		return -ENOMEM;
	}
	pose_means(g, stride, iv, np, gm);
	pose_means(a, stride, iv, np, am);
	rc = sscope_calib_linear_fit((const double(*)[3])gm,
				     (const double(*)[3])am, np, false, &lf,
				     diag);
	free(gm);
	free(am);
	if (!rc && !(lf.axis_excited[0] && lf.axis_excited[1] &&
		     lf.axis_excited[2]))
		rc = ssc_diag(diag, -EDOM,
			      "%zu poses do not tilt gravity onto all three axes",
			      np);
	if (rc)
		return rc;
	sscope_calib_triad_identity(c);
	c->has_gsens = true;
	for (int i = 0; i < 3; i++) {
		c->bias[i] = lf.bias[i];
		c->bias_sd[i] = lf.bias_sd[i];
		c->scale_sd[i] = NAN;
		for (int j = 0; j < 3; j++) {
			c->gsens[i][j] = lf.A[i][j];
			c->gsens_sd[i][j] = lf.A_sd[i][j];
		}
	}
	c->n_params = 12;
	c->poses = np;
	c->residual_rms = sqrt((lf.residual_rms[0] * lf.residual_rms[0] +
				lf.residual_rms[1] * lf.residual_rms[1] +
				lf.residual_rms[2] * lf.residual_rms[2]) / 3);
	c->cond = lf.cond;
	return 0;
}

int sscope_calib_noise_density(const double *const ch[3], size_t stride,
			       const struct sscope_calib_interval *iv,
			       size_t n_iv, const double scale[3],
			       double rate_hz, double *nd)
{
	double sum = 0;

	if (!ch || !iv || !scale || !nd || !(rate_hz > 0))
		return -EINVAL;
	*nd = NAN;
	for (int i = 0; i < 3; i++) {
		struct ssc_ksum ss = { 0, 0 };
		double dof = 0, sd;

		for (size_t k = 0; k < n_iv; k++) {
			double m, s;

			if (sscope_calib_interval_mean(ch[i], stride, &iv[k], &m,
						       &s) == 0 && isfinite(s)) {
				double d = (double)(iv[k].end - iv[k].start - 1);

				ssc_ksum_add(&ss, s * s * d);
				dof += d;
			}
		}
		if (!(dof > 0))
			return -EDOM;
		sd = sqrt(ssc_ksum_value(&ss) / dof) * fabs(scale[i]);
		sum += sd * sd;
	}
	*nd = sqrt(sum / 3 / rate_hz);
	return 0;
}

int sscope_calib_error_model(const struct sscope_calib_triad *c,
			     double A[3][3])
{
	double C[3][3], d;

	if (!c || !A)
		return -EINVAL;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			C[i][j] = c->mis[i][j] * c->scale[j];
	d = C[0][0] * (C[1][1] * C[2][2] - C[1][2] * C[2][1]) -
	    C[0][1] * (C[1][0] * C[2][2] - C[1][2] * C[2][0]) +
	    C[0][2] * (C[1][0] * C[2][1] - C[1][1] * C[2][0]);
	if (!(fabs(d) > 0) || !isfinite(d))
		return -EDOM;
	A[0][0] = (C[1][1] * C[2][2] - C[1][2] * C[2][1]) / d;
	A[0][1] = (C[0][2] * C[2][1] - C[0][1] * C[2][2]) / d;
	A[0][2] = (C[0][1] * C[1][2] - C[0][2] * C[1][1]) / d;
	A[1][0] = (C[1][2] * C[2][0] - C[1][0] * C[2][2]) / d;
	A[1][1] = (C[0][0] * C[2][2] - C[0][2] * C[2][0]) / d;
	A[1][2] = (C[0][2] * C[1][0] - C[0][0] * C[1][2]) / d;
	A[2][0] = (C[1][0] * C[2][1] - C[1][1] * C[2][0]) / d;
	A[2][1] = (C[0][1] * C[2][0] - C[0][0] * C[2][1]) / d;
	A[2][2] = (C[0][0] * C[1][1] - C[0][1] * C[1][0]) / d;
	return 0;
}

int sscope_calib_triad_grade(enum sscope_quantity q,
			     const struct sscope_calib_triad *c,
			     const double (*A)[3], double noise_density,
			     double *distance)
{
	double sf = 0, gs = NAN, bias = 0;

	if (!c)
		return -EINVAL;
	if (A) {
		for (int i = 0; i < 3; i++) {
			sf = fmax(sf, fabs(A[i][i] - 1));
			bias = fmax(bias, fabs(c->bias[i]));
		}
		if (c->has_gsens) {
			gs = 0;
			for (int i = 0; i < 3; i++)
				for (int j = 0; j < 3; j++)
					gs = fmax(gs, fabs(c->gsens[i][j]));
		}
	} else {
		/* raw input: the bias in output units, T K b; no scale error */
		for (int i = 0; i < 3; i++) {
			double v = 0;

			for (int j = 0; j < 3; j++)
				v += c->mis[i][j] * c->scale[j] * c->bias[j];
			bias = fmax(bias, fabs(v));
		}
		sf = NAN;
	}
	return sscope_calib_grade(q, bias, sf, noise_density, gs, distance);
}

int sscope_calib_pose_errors(const double *const ch[3], size_t stride,
			     const struct sscope_calib_interval *iv,
			     size_t n_iv, const struct sscope_calib_triad *c,
			     double gravity_m_s2, bool raw_is_si,
			     double *before, double *after)
{
	if (!ch || !iv || !c || !before || !after || !(gravity_m_s2 > 0))
		return -EINVAL;
	for (size_t k = 0; k < n_iv; k++) {
		double m[3], u[3], nb = 0;

		for (int i = 0; i < 3; i++) {
			sscope_calib_interval_mean(ch[i], stride, &iv[k], &m[i], NULL);
			u[i] = m[i];
			nb += m[i] * m[i];
		}
		sscope_calib_apply(c, &u[0], &u[1], &u[2], 1, 1, NULL, 1);
		before[k] = raw_is_si ? sqrt(nb) - gravity_m_s2 : 0;
		after[k] = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]) -
			   gravity_m_s2;
	}
	return 0;
}

int sscope_calib_motion_summary(const double *const g[3],
				const double *const accel_cal[3],
				size_t stride, size_t n, double rate_hz,
				const struct sscope_calib_interval *iv,
				size_t n_iv, const struct sscope_calib_triad *c,
				bool rate_in_si, double *after, double *before,
				struct sscope_calib_motion *sum)
{
	struct sscope_calib_triad nominal;
	double s0, s2 = 0, b2 = 0, mx = 0;
	size_t m;
	int rc;

	if (!c || !after || !before || !sum || n_iv < 2)
		return -EINVAL;
	memset(sum, 0, sizeof(*sum));
	/* the bias removed only, at the nominal scale: 1 for a rate in SI
	 * units, else the fitted scales' mean magnitude */
	s0 = (fabs(c->scale[0]) + fabs(c->scale[1]) + fabs(c->scale[2])) / 3;
	sscope_calib_triad_identity(&nominal);
	for (int i = 0; i < 3; i++) {
		nominal.bias[i] = c->bias[i];
		nominal.scale[i] = rate_in_si ? 1 : copysign(s0, c->scale[i]);
		for (int j = 0; j < 3; j++)
			nominal.gsens[i][j] = c->gsens[i][j];
	}
	nominal.has_gsens = c->has_gsens;
	rc = sscope_calib_gyro_motion_errors(g, accel_cal, stride, n, rate_hz,
					     iv, n_iv, c, after);
	if (!rc)
		rc = sscope_calib_gyro_motion_errors(g, accel_cal, stride, n,
						     rate_hz, iv, n_iv, &nominal,
						     before);
	if (rc)
		return rc;
	m = n_iv - 1;
	for (size_t k = 0; k < m; k++) {
		s2 += after[k] * after[k];
		b2 += before[k] * before[k];
		mx = fmax(mx, after[k]);
	}
	sum->motions = m;
	sum->rms_rad = sqrt(s2 / (double)m);
	sum->max_rad = mx;
	sum->rms_bias_only_rad = sqrt(b2 / (double)m);
	return 0;
}

int sscope_calib_rate_table_steps(const double *const y[3],
				  const double *const ref[3], size_t n_ref,
				  size_t stride, size_t n, double rate_hz,
				  double settle_s,
				  struct sscope_calib_interval *seg, size_t max,
				  double (*ym)[3], double (*rm)[3],
				  size_t *n_steps)
{
	double *key, fs = 0;
	size_t settle, minl, ns;

	if (!y || !ref || (n_ref != 1 && n_ref != 3) || !seg || !ym || !rm ||
	    !n_steps || !(rate_hz > 0) || !(settle_s >= 0) || stride == 0)
		return -EINVAL;
	*n_steps = 0;
	key = ssc_alloc_array(n ? n : 1, sizeof(double));
	if (!key)
		return -ENOMEM;
	/* one key that changes when any reference changes: irrational
	 * weights make a change of one cancel another's only by accident */
	for (size_t i = 0; i < n; i++) {
		key[i] = ref[0][i * stride];
		if (n_ref == 3)
			key[i] += 1.6180339887 * ref[1][i * stride] +
				  2.7182818285 * ref[2][i * stride];
		if (isfinite(key[i]))
			fs = fmax(fs, fabs(key[i]));
	}
	settle = ssc_count(round(settle_s * rate_hz));
	minl = ssc_count(round(0.5 * rate_hz));
	sscope_calib_constant_segments(key, 1, n, 1e-9 * fs, settle,
				       minl < 2 ? 2 : minl, seg, max, &ns);
	free(key);
	if (ns > max)
		ns = max;
	for (size_t k = 0; k < ns; k++)
		for (int i = 0; i < 3; i++) {
			sscope_calib_interval_mean(y[i], stride, &seg[k], &ym[k][i],
						   NULL);
			rm[k][i] = 0;
			if ((size_t)i < n_ref)
				sscope_calib_interval_mean(ref[i], stride, &seg[k],
							   &rm[k][i], NULL);
		}
	*n_steps = ns;
	return ns < 2 ? -EDOM : 0;
}

int sscope_calib_table_axis(const double (*ym)[3], const double (*rm)[3],
			    size_t n)
{
	double best = -1;
	int axis = 0;

	if (!ym || !rm || n == 0)
		return 0;
	for (int i = 0; i < 3; i++) {
		double sxy = 0, sxx = 0, mx = 0, my = 0;

		for (size_t k = 0; k < n; k++) {
			mx += rm[k][0];
			my += ym[k][i];
		}
		mx /= (double)n;
		my /= (double)n;
		for (size_t k = 0; k < n; k++) {
			double dx = rm[k][0] - mx;

			sxx += dx * dx;
			sxy += dx * (ym[k][i] - my);
		}
		if (sxx > 0 && fabs(sxy / sxx) > best) {
			best = fabs(sxy / sxx);
			axis = i;
		}
	}
	return axis;
}
