/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Zero-velocity-aided strapdown navigation (see sscope-zupt.h): a 15-state
 * error-state Kalman filter (Groves 2013, sec. 14.2 and 15.3.1; Foxlin
 * 2005) around the two-sample NED mechanisation of analysis/strapdown.c,
 * levelling and gyrocompassing on the first still interval, and the
 * sliding-window stop detector of Skog et al. (2010) with a chi-squared
 * threshold.
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_cdf.h>

#include "sscope-nav.h"
#include "sscope-strapdown.h"
#include "sscope-zupt.h"

#define NS SSCOPE_ZUPT_N_STATES
#define D2R (PI / 180)

/* state indices */
enum { IP = 0, IV = 3, IA = 6, IG = 9, IB = 12 };

void sscope_zupt_opts_init(struct sscope_zupt_opts *o)
{
	memset(o, 0, sizeof(*o));
	o->start.lat_rad = 45 * D2R;
	o->gyro_n = 0.3 * D2R / 60;          /* 0.3 deg/sqrt(h) */
	o->gyro_b = 10 * D2R / 3600;         /* 10 deg/h */
	o->accel_n = 0.1 / 60;               /* 0.1 m/s/sqrt(h) */
	o->accel_b = 1e-4 * 9.80665;         /* 0.1 mg */
	o->gyro_bias_sd_rad_s = 0.5 * D2R;
	o->accel_bias_sd_m_s2 = 0.02 * 9.80665;
	o->bias_time_s = 100;
	o->window_s = 0.5;
	o->false_alarm = 1e-3;
	o->min_level_s = 1;
	o->zupt_sd_m_s = 0.01;
	o->gyrocompass_max_rad = 5 * D2R;
	o->propagate_s = 0.05;
}

const char *sscope_zupt_heading_name(enum sscope_zupt_heading h)
{
	static const char *const n[] = { "given", "gyrocompass", "assumed" };

	return (unsigned)h < 3 ? n[h] : NULL;
}

void sscope_zupt_result_free(struct sscope_zupt_result *r)
{
	if (!r)
		return;
	free(r->rec);
	free(r->stops);
	free(r);
}

/* ------------------------------------------------------------ filter */

struct kf {
	double P[NS][NS];
	double x[NS];
	/* the non-zero entries of F T: rows, columns, values */
	int n_e;
	unsigned char ei[64], ej[64];
	double ev[64];
	double q[NS];  /* process noise density of each state (diagonal) */
	double s_h;    /* horizontal accelerometer-bias variance, NED sum */
	/* F T summed over the updates of one propagation interval (the
	 * same entries as ev while moving) */
	double acc[64];
	unsigned char ai[64], aj[64];
	int n_ae;
	size_t n_acc;
	double t_acc;
};

static void add_e(struct kf *k, int i, int j, double v)
{
	k->ei[k->n_e] = (unsigned char)i;
	k->ej[k->n_e] = (unsigned char)j;
	k->ev[k->n_e] = v;
	k->n_e++;
}

/* P = (I + E) P (I + E)^T + Q T, E sparse (n_e entries ev at ei, ej) */
static void kf_propagate(struct kf *k, const unsigned char *ei,
			 const unsigned char *ej, const double *ev, int n_e,
			 double T)
{
	double M[NS][NS];

	memcpy(M, k->P, sizeof(M));
	for (int e = 0; e < n_e; e++) {
		const double v = ev[e];
		const double *src = k->P[ej[e]];
		double *dst = M[ei[e]];

		for (int c = 0; c < NS; c++)
			dst[c] += v * src[c];
	}
	memcpy(k->P, M, sizeof(M));
	for (int e = 0; e < n_e; e++) {
		const double v = ev[e];
		const int i = ei[e], j = ej[e];

		for (int r = 0; r < NS; r++)
			k->P[r][i] += v * M[r][j];
	}
	for (int i = 0; i < NS; i++)
		k->P[i][i] += k->q[i] * T;
	/* keep P symmetric against rounding */
	for (int i = 0; i < NS; i++)
		for (int j = 0; j < i; j++) {
			double m = 0.5 * (k->P[i][j] + k->P[j][i]);

			k->P[i][j] = m;
			k->P[j][i] = m;
		}
}

/* propagate over the updates accumulated while moving */
static void kf_flush(struct kf *k, double q_att)
{
	if (!k->n_acc)
		return;
	for (int i = 0; i < 3; i++)
		k->q[IA + i] = q_att;
	kf_propagate(k, k->ai, k->aj, k->acc, k->n_ae, k->t_acc);
	k->n_acc = 0;
	k->t_acc = 0;
}

/*
 * After levelling, a horizontal accelerometer bias b_h lengthens the
 * measured gravity by |b_h|^2 / 2g, which the linear model takes for a
 * vertical bias until turns separate them.  When the horizontal bias
 * variance s (north plus east) falls from s0 to s1, the part of that
 * term that the vertical bias estimate holds is released: its second
 * moment 2 ((s0 - s1) / 2g)^2 (chi-squared with two degrees of freedom)
 * is added to the variance of the bias along the vertical.
 */
static void release_gravity_term(struct kf *k, const double C[3][3], double g)
{
	double cd[3], s = 0, v = 0;

	for (int i = 0; i < 3; i++)
		cd[i] = C[2][i];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) {
			s += (i == j) * k->P[IB + i][IB + j];
			v += cd[i] * k->P[IB + i][IB + j] * cd[j];
		}
	s -= v;
	if (s < k->s_h) {
		double d = (k->s_h - s) / (2 * g), add = 2 * d * d;

		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				k->P[IB + i][IB + j] += add * cd[i] * cd[j];
	}
	k->s_h = s;
}

/* scalar measurement z = s x_j + noise (variance r) */
static void kf_update(struct kf *k, int j, double s, double z, double r)
{
	double Pj[NS], S = k->P[j][j] + r, y = z - s * k->x[j];

	if (!(S > 0))
		return;
	for (int i = 0; i < NS; i++)
		Pj[i] = k->P[i][j];
	for (int i = 0; i < NS; i++) {
		k->x[i] += s * Pj[i] / S * y;
		for (int c = 0; c <= i; c++) {
			double v = k->P[i][c] - Pj[i] * Pj[c] / S;

			k->P[i][c] = v;
			k->P[c][i] = v;
		}
	}
}

static void mv(const double C[3][3], const double x[3], double y[3])
{
	for (int i = 0; i < 3; i++)
		y[i] = C[i][0] * x[0] + C[i][1] * x[1] + C[i][2] * x[2];
}

static void mtv(const double C[3][3], const double x[3], double y[3])
{
	for (int i = 0; i < 3; i++)
		y[i] = C[0][i] * x[0] + C[1][i] * x[1] + C[2][i] * x[2];
}

/* ------------------------------------------------------------ detector */

/* running sums of the window (offsets removed) */
struct win {
	size_t W;
	double off[6], s1[6], s2[6];
};

static double sample(const double *const g[3], const double *const a[3],
		     size_t stride, size_t k, int ax)
{
	return ax < 3 ? g[ax][k * stride] : a[ax - 3][k * stride];
}

static void win_add(struct win *w, const double *const g[3],
		    const double *const a[3], size_t stride, size_t k,
		    double sign)
{
	for (int ax = 0; ax < 6; ax++) {
		double x = sample(g, a, stride, k, ax) - w->off[ax];

		w->s1[ax] += sign * x;
		w->s2[ax] += sign * x * x;
	}
}

/* the variance part: sum over samples of squared deviations / variance */
static double win_var(const struct win *w, double vg, double va)
{
	double t = 0;

	for (int ax = 0; ax < 6; ax++) {
		double d = w->s2[ax] - w->s1[ax] * w->s1[ax] / (double)w->W;

		t += fmax(d, 0) / (ax < 3 ? vg : va);
	}
	return t;
}

static void win_mean(const struct win *w, double m[6])
{
	for (int ax = 0; ax < 6; ax++)
		m[ax] = w->off[ax] + w->s1[ax] / (double)w->W;
}

/* ------------------------------------------------------------ run */

static bool opts_ok(const struct sscope_zupt_opts *o)
{
	const double pos[] = { o->rate_hz, o->gyro_n, o->accel_n,
			       o->bias_time_s, o->window_s, o->zupt_sd_m_s,
			       o->false_alarm };
	const double nonneg[] = { o->gyro_b, o->gyro_k, o->accel_b, o->accel_k,
				  o->gyro_bias_sd_rad_s, o->accel_bias_sd_m_s2,
				  o->min_level_s, o->output_step_s,
				  o->heading_sd_rad, o->gyrocompass_max_rad,
				  o->propagate_s };

	for (size_t i = 0; i < sizeof(pos) / sizeof(pos[0]); i++)
		if (!(pos[i] > 0) || !isfinite(pos[i]))
			return false;
	for (size_t i = 0; i < sizeof(nonneg) / sizeof(nonneg[0]); i++)
		if (!(nonneg[i] >= 0) || !isfinite(nonneg[i]))
			return false;
	return o->false_alarm < 1 && isfinite(o->heading_rad);
}

static void fill_rec(const struct sscope_strapdown_state *s,
		     const struct kf *k, const struct sscope_nav_ltp *ltp,
		     const double bg[3], const double ba[3], double t,
		     bool still, struct sscope_zupt_rec *r)
{
	struct sscope_nav_geodetic g = { s->lat_rad, s->lon_rad, s->height_m };
	double re[3];

	r->t_s = t;
	r->lat_rad = s->lat_rad;
	r->lon_rad = s->lon_rad;
	r->height_m = s->height_m;
	sscope_nav_geodetic_to_ecef(&g, re);
	sscope_nav_ltp_from_ecef(ltp, re, r->ned_m);
	memcpy(r->v_ned_m_s, s->v_ned_m_s, sizeof(r->v_ned_m_s));
	sscope_strapdown_euler(s, &r->euler_rad[0], &r->euler_rad[1],
			       &r->euler_rad[2]);
	for (int i = 0; i < 3; i++) {
		r->gyro_bias_rad_s[i] = bg[i];
		r->accel_bias_m_s2[i] = ba[i];
		r->sd_ned_m[i] = sqrt(k->P[IP + i][IP + i]);
		r->sd_v_m_s[i] = sqrt(k->P[IV + i][IV + i]);
		r->sd_euler_rad[i] = sqrt(k->P[IA + i][IA + i]);
		r->sd_gyro_bias_rad_s[i] = sqrt(k->P[IG + i][IG + i]);
		r->sd_accel_bias_m_s2[i] = sqrt(k->P[IB + i][IB + i]);
	}
	r->still = still;
}

/* feed the estimated errors back into the state and biases */
static void inject(struct kf *k, struct sscope_strapdown_state *s,
		   double bg[3], double ba[3])
{
	double rn, re, qc[4], q[4], neg[3];

	sscope_nav_radii(s->lat_rad, &rn, &re);
	s->lat_rad -= k->x[IP] / (rn + s->height_m);
	s->lon_rad -= k->x[IP + 1] / ((re + s->height_m) * cos(s->lat_rad));
	s->height_m += k->x[IP + 2];
	for (int i = 0; i < 3; i++) {
		s->v_ned_m_s[i] -= k->x[IV + i];
		neg[i] = -k->x[IA + i];
		bg[i] -= k->x[IG + i];
		ba[i] -= k->x[IB + i];
	}
	sscope_nav_quat_from_rotvec(neg, qc);
	sscope_nav_quat_mul(qc, s->q_bn, q);
	sscope_nav_quat_normalize(q);
	memcpy(s->q_bn, q, sizeof(q));
	memset(k->x, 0, sizeof(k->x));
}

int sscope_zupt_run(const double *const gyro[3], const double *const accel[3],
		    size_t stride, size_t n, const struct sscope_zupt_opts *o,
		    struct sscope_zupt_result **resp, struct sscope_diag *diag)
{
	struct sscope_zupt_result *res;
	struct sscope_strapdown_state st;
	struct sscope_nav_ltp ltp;
	struct win w = { 0 };
	struct kf *k = NULL;
	double fs, dt, T, vg, va, thr_var, thr_mean, g0, w_ie[3], bg[3] = { 0 },
	       ba[3] = { 0 }, mean[6], roll, pitch, yaw, C[3][3];
	size_t W, n_lev, n_upd, out_every, max_stops, level_windows, m_prop;
	bool in_stop = false;
	int rc;

	if (!resp)
		return -EINVAL;
	*resp = NULL;
	if (!gyro || !accel || !o || stride == 0)
		return ssc_diag(diag, -EINVAL, "bad parameter");
	for (int i = 0; i < 3; i++)
		if (!gyro[i] || !accel[i])
			return ssc_diag(diag, -EINVAL, "bad parameter");
	if (!opts_ok(o))
		return ssc_diag(diag, -EINVAL,
				"rate, noise terms, window and measurement sd must be positive and finite");
	if (!isfinite(o->start.lat_rad) || !(fabs(o->start.lat_rad) < 89 * D2R) ||
	    !isfinite(o->start.lon_rad) || !isfinite(o->start.height_m))
		return ssc_diag(diag, -EINVAL,
				"the latitude must be within +-89 degrees");
	fs = o->rate_hz;
	dt = 1 / fs;
	T = 2 * dt;
	W = ssc_count(fmax(3, round(o->window_s * fs)));
	n_lev = ssc_count(ceil(o->min_level_s * fs));
	if (n_lev < W)
		n_lev = W;
	if (n < n_lev || n < 4)
		return ssc_diag(diag, -EDOM,
				"%zu samples (%g s): the initial still interval needs %g s (the longer of the %g s window and the %g s levelling)",
				n, (double)n / fs,
				fmax(fmax(3 / fs, o->window_s), o->min_level_s),
				o->window_s, o->min_level_s);
	for (size_t i = 0; i < n; i++)
		for (int ax = 0; ax < 6; ax++)
			if (!isfinite(sample(gyro, accel, stride, i, ax)))
				return ssc_diag(diag, -EDOM,
						"sample %zu is not finite", i);
	vg = o->gyro_n * o->gyro_n * fs;
	va = o->accel_n * o->accel_n * fs;
	/* ---- initial still interval: whole windows passing the variance
	 * part (white noise at rest: chi-squared with 6 (W - 1) dof) */
	thr_var = gsl_cdf_chisq_Pinv(1 - o->false_alarm, 6.0 * (double)(W - 1));
	w.W = W;
	for (int ax = 0; ax < 6; ax++)
		w.off[ax] = sample(gyro, accel, stride, 0, ax);
	level_windows = 0;
	{
		double s1[6] = { 0 };

		for (size_t b = 0; (b + 1) * W <= n; b++) {
			memset(w.s1, 0, sizeof(w.s1));
			memset(w.s2, 0, sizeof(w.s2));
			for (size_t i = b * W; i < (b + 1) * W; i++)
				win_add(&w, gyro, accel, stride, i, 1);
			if (win_var(&w, vg, va) > thr_var)
				break;
			for (int ax = 0; ax < 6; ax++)
				s1[ax] += w.s1[ax];
			level_windows++;
		}
		if (level_windows == 0 || level_windows * W < n_lev)
			return ssc_diag(diag, -EDOM,
					"not still at the start (%g s still, %g s needed to level)",
					(double)(level_windows * W) / fs,
					(double)n_lev / fs);
		for (int ax = 0; ax < 6; ax++)
			mean[ax] = w.off[ax] + s1[ax] / (double)(level_windows * W);
	}
	res = calloc(1, sizeof(*res));
	k = calloc(1, sizeof(*k));
	n_upd = n / 2;
	if (o->output_step_s > 0)
		out_every = ssc_count(fmax(1, round(o->output_step_s / T)));
	else
		out_every = ssc_count(fmax(1, round((double)n_upd / 1000)));
	max_stops = n_upd / 2 + 1; /* still and moving updates alternate at most */
	if (res) {
		res->rec = ssc_alloc_array(n_upd / out_every + 1, sizeof(*res->rec));
		res->stops = ssc_alloc_array(max_stops, sizeof(*res->stops));
	}
	if (!res || !k || !res->rec || !res->stops) {
		free(k);
		sscope_zupt_result_free(res);
		return -ENOMEM;
	}
	res->window = W;
	m_prop = ssc_count(fmax(1, round(o->propagate_s / T)));
	res->level_s = (double)(level_windows * W) / fs;
	/* ---- levelling: a still sensor reads f = g (sin p, -sin r cos p,
	 * -cos r cos p) */
	g0 = sscope_nav_gravity(o->start.lat_rad, o->start.height_m);
	roll = atan2(-mean[4], -mean[5]);
	pitch = atan2(mean[3], hypot(mean[4], mean[5]));
	sscope_nav_earth_rate(o->start.lat_rad, w_ie);
	{
		/* gyrocompass: the horizontal Earth rate in the levelled frame */
		double CL[3][3], wl[3], oc = SSCOPE_NAV_WGS84_OMEGA * cos(o->start.lat_rad);
		double tl = res->level_s;

		sscope_nav_dcm_from_euler(roll, pitch, 0, CL);
		mv(CL, mean, wl);
		res->gyrocompass_sd_rad = sqrt(o->gyro_bias_sd_rad_s * o->gyro_bias_sd_rad_s +
					       o->gyro_b * o->gyro_b +
					       o->gyro_n * o->gyro_n / tl) / oc;
		if (o->heading_given) {
			yaw = o->heading_rad;
			res->heading_from = SSCOPE_ZUPT_HEADING_GIVEN;
			res->heading0_sd_rad = o->heading_sd_rad;
		} else if (res->gyrocompass_sd_rad <= o->gyrocompass_max_rad) {
			yaw = atan2(-wl[1], wl[0]);
			res->heading_from = SSCOPE_ZUPT_HEADING_GYROCOMPASS;
			res->heading0_sd_rad = res->gyrocompass_sd_rad;
		} else {
			yaw = o->heading_rad;
			res->heading_from = SSCOPE_ZUPT_HEADING_ASSUMED;
			res->heading0_sd_rad = o->heading_sd_rad;
		}
	}
	res->roll0_rad = roll;
	res->pitch0_rad = pitch;
	res->heading0_rad = yaw;
	{
		const double v0[3] = { 0, 0, 0 };

		rc = sscope_strapdown_init(&st, o->start.lat_rad, o->start.lon_rad,
					   o->start.height_m, v0, roll, pitch, yaw);
	}
	if (!rc)
		rc = sscope_nav_ltp_init(&ltp, &o->start);
	if (rc) {
		free(k);
		sscope_zupt_result_free(res);
		return ssc_diag(diag, rc, "bad start point");
	}
	sscope_nav_dcm_from_quat(st.q_bn, C);
	{
		double eb[3];

		mtv(C, w_ie, eb);
		for (int i = 0; i < 3; i++)
			bg[i] = mean[i] - eb[i];
	}
	/* ---- initial covariance */
	{
		double sb2 = o->accel_bias_sd_m_s2 * o->accel_bias_sd_m_s2;
		double tl = res->level_s, J[2][3];
		double sn2 = va / (g0 * g0 * (double)(level_windows * W));
		double gb2 = vg / ((double)(level_windows * W));
		double oc = SSCOPE_NAV_WGS84_OMEGA * cos(o->start.lat_rad);

		(void)tl;
		for (int i = 0; i < 3; i++) {
			k->P[IV + i][IV + i] = o->zupt_sd_m_s * o->zupt_sd_m_s;
			k->P[IB + i][IB + i] = sb2;
		}
		/* tilt from levelling: psi_N = (C db)_E / g, psi_E = -(C db)_N / g */
		for (int c = 0; c < 3; c++) {
			J[0][c] = C[1][c] / g0;
			J[1][c] = -C[0][c] / g0;
		}
		for (int a = 0; a < 2; a++) {
			for (int b = 0; b < 2; b++)
				k->P[IA + a][IA + b] = sb2 * (J[a][0] * J[b][0] + J[a][1] * J[b][1] +
							      J[a][2] * J[b][2]) + (a == b ? sn2 : 0);
			for (int c = 0; c < 3; c++) {
				k->P[IA + a][IB + c] = sb2 * J[a][c];
				k->P[IB + c][IA + a] = sb2 * J[a][c];
			}
		}
		k->P[IA + 2][IA + 2] = res->heading0_sd_rad * res->heading0_sd_rad;
		/* the gyro mean starts the bias, but the filter takes the same
		 * samples again as angular-rate measurements: the prior stays
		 * the turn-on spread so that they are not counted twice */
		for (int i = 0; i < 3; i++) {
			double v = gb2 + o->gyro_b * o->gyro_b +
				   o->gyro_bias_sd_rad_s * o->gyro_bias_sd_rad_s;

			if (res->heading_from == SSCOPE_ZUPT_HEADING_ASSUMED)
				v += oc * oc; /* the horizontal Earth rate unknown */
			k->P[IG + i][IG + i] = v;
		}
		for (int i = 0; i < 3; i++) {
			k->q[IV + i] = o->accel_n * o->accel_n;
			k->q[IA + i] = o->gyro_n * o->gyro_n;
			k->q[IG + i] = o->gyro_k * o->gyro_k + o->gyro_b * o->gyro_b / o->bias_time_s;
			k->q[IB + i] = o->accel_k * o->accel_k + o->accel_b * o->accel_b / o->bias_time_s;
		}
	}
	/* the two parts tested apart (the mean part alone has the power to
	 * see a slow motion), each at half the level */
	k->s_h = 2 * o->accel_bias_sd_m_s2 * o->accel_bias_sd_m_s2;
	res->threshold = gsl_cdf_chisq_Pinv(1 - o->false_alarm / 2, 6.0 * (double)(W - 1));
	thr_mean = gsl_cdf_chisq_Pinv(1 - o->false_alarm / 2, 6);
	res->threshold_mean = thr_mean;
	fill_rec(&st, k, &ltp, bg, ba, 0, true, &res->rec[0]);
	res->n_rec = 1;
	/* ---- the pass: window sums restart from the first sample */
	memset(w.s1, 0, sizeof(w.s1));
	memset(w.s2, 0, sizeof(w.s2));
	for (int ax = 0; ax < 6; ax++)
		w.off[ax] = mean[ax];
	sscope_nav_dcm_from_quat(st.q_bn, C);
	for (size_t j = 0; j < n_upd; j++) {
		const size_t s0 = 2 * j, s1 = s0 + 1;
		double dth[2][3], dv[2][3], fb[3], fn[3], wm[3], q0[4];
		bool still = false, hold;

		/* ---- detector over the W samples ending at s1, with the state
		 * before this update */
		win_add(&w, gyro, accel, stride, s0, 1);
		if (s0 >= W)
			win_add(&w, gyro, accel, stride, s0 - W, -1);
		win_add(&w, gyro, accel, stride, s1, 1);
		if (s1 >= W)
			win_add(&w, gyro, accel, stride, s1 - W, -1);
		if (s1 + 1 >= W) {
			double m[6], eb[3], u[3], t = 0, H[3][6], HP[3][6];

			win_mean(&w, m);
			mtv(C, w_ie, eb);
			for (int i = 0; i < 3; i++)
				fb[i] = m[3 + i] - ba[i];
			mv(C, fb, u);
			u[2] += g0;
			/* u = C_est (f - b_est) + g = -g psi x e_D - C db_a: its
			 * variance from the filter's (tilt and bias correlated) */
			memset(H, 0, sizeof(H));
			H[0][1] = -g0;
			H[1][0] = g0;
			for (int i = 0; i < 3; i++)
				for (int c = 0; c < 3; c++)
					H[i][3 + c] = -C[i][c];
			for (int i = 0; i < 3; i++)
				for (int c = 0; c < 6; c++) {
					int jc = c < 3 ? IA + c : IB + c - 3;

					HP[i][c] = 0;
					for (int l = 0; l < 6; l++)
						HP[i][c] += H[i][l] * k->P[l < 3 ? IA + l : IB + l - 3][jc];
				}
			for (int i = 0; i < 3; i++) {
				double dg = m[i] - bg[i] - eb[i], hph = 0;

				for (int l = 0; l < 6; l++)
					hph += HP[i][l] * H[i][l];
				t += dg * dg / (vg / (double)W + k->P[IG + i][IG + i]);
				t += u[i] * u[i] / (va / (double)W + fmax(hph, 0));
			}
			still = t < thr_mean && win_var(&w, vg, va) < res->threshold;
		}
		/* at rest the attitude is held (the body does not turn relative
		 * to the Earth): the gyro noise then enters only through the
		 * angular-rate measurements, not twice */
		hold = still && !o->no_zupt;
		for (int i = 0; i < 3; i++) {
			double g1 = gyro[i][s0 * stride] - bg[i];
			double g2 = gyro[i][s1 * stride] - bg[i];
			double a1 = accel[i][s0 * stride] - ba[i];
			double a2 = accel[i][s1 * stride] - ba[i];

			dth[0][i] = g1 * dt;
			dth[1][i] = g2 * dt;
			dv[0][i] = a1 * dt;
			dv[1][i] = a2 * dt;
			fb[i] = 0.5 * (a1 + a2);
			wm[i] = 0.5 * (g1 + g2);
		}
		memcpy(q0, st.q_bn, sizeof(q0));
		sscope_strapdown_step2(&st, dth[0], dth[1], dv[0], dv[1], dt);
		if (hold)
			memcpy(st.q_bn, q0, sizeof(q0));
		sscope_nav_dcm_from_quat(st.q_bn, C);
		mv(C, fb, fn);
		sscope_nav_earth_rate(st.lat_rad, w_ie);
		/* F T, sparse */
		k->n_e = 0;
		for (int i = 0; i < 3; i++)
			add_e(k, IP + i, IV + i, T);
		add_e(k, IV + 2, IP + 2, 2 * g0 / SSCOPE_NAV_WGS84_A * T);
		add_e(k, IV + 0, IA + 1, fn[2] * T);
		add_e(k, IV + 0, IA + 2, -fn[1] * T);
		add_e(k, IV + 1, IA + 0, -fn[2] * T);
		add_e(k, IV + 1, IA + 2, fn[0] * T);
		add_e(k, IV + 2, IA + 0, fn[1] * T);
		add_e(k, IV + 2, IA + 1, -fn[0] * T);
		add_e(k, IV + 0, IV + 1, 2 * w_ie[2] * T);
		add_e(k, IV + 1, IV + 0, -2 * w_ie[2] * T);
		add_e(k, IV + 1, IV + 2, 2 * w_ie[0] * T);
		add_e(k, IV + 2, IV + 1, -2 * w_ie[0] * T);
		if (!hold) {
			add_e(k, IA + 0, IA + 1, w_ie[2] * T);
			add_e(k, IA + 1, IA + 0, -w_ie[2] * T);
			add_e(k, IA + 1, IA + 2, w_ie[0] * T);
			add_e(k, IA + 2, IA + 1, -w_ie[0] * T);
		}
		for (int i = 0; i < 3; i++)
			for (int c = 0; c < 3; c++) {
				add_e(k, IV + i, IB + c, -C[i][c] * T);
				if (!hold)
					add_e(k, IA + i, IG + c, -C[i][c] * T);
			}
		/* while moving, I + sum(F T) over up to m_prop updates (first
		 * order over the interval); at rest, every update */
		if (hold) {
			kf_flush(k, o->gyro_n * o->gyro_n);
			for (int i = 0; i < 3; i++)
				k->q[IA + i] = 0;
			kf_propagate(k, k->ei, k->ej, k->ev, k->n_e, T);
		} else {
			if (k->n_acc == 0) {
				memcpy(k->acc, k->ev, (size_t)k->n_e * sizeof(double));
				memcpy(k->ai, k->ei, sizeof(k->ai));
				memcpy(k->aj, k->ej, sizeof(k->aj));
				k->n_ae = k->n_e;
			} else
				for (int e = 0; e < k->n_e; e++)
					k->acc[e] += k->ev[e];
			k->n_acc++;
			k->t_acc += T;
			if (k->n_acc >= m_prop || (j + 1) % out_every == 0)
				kf_flush(k, o->gyro_n * o->gyro_n);
		}
		release_gravity_term(k, C, g0);
		if (still) {
			res->n_still++;
			if (!in_stop) {
				double t0 = (double)(s1 + 1 - W) * dt;

				/* a window overlapping the last stop continues it */
				if (res->n_stops == 0 ||
				    t0 > res->stops[res->n_stops - 1].t_end_s)
					res->stops[res->n_stops++].t_start_s = t0;
				in_stop = true;
			}
			if (!o->no_zupt) {
				double eb[3];

				mtv(C, w_ie, eb);
				for (int i = 0; i < 3; i++)
					kf_update(k, IV + i, 1, st.v_ned_m_s[i],
						  o->zupt_sd_m_s * o->zupt_sd_m_s);
				for (int i = 0; i < 3; i++)
					kf_update(k, IG + i, -1, wm[i] - eb[i], vg / 2);
				inject(k, &st, bg, ba);
			}
			{
				struct sscope_zupt_stop *sp = &res->stops[res->n_stops - 1];

				sp->t_end_s = (double)(s1 + 1) * dt;
				for (int i = 0; i < 3; i++) {
					sp->gyro_bias_rad_s[i] = bg[i];
					sp->accel_bias_m_s2[i] = ba[i];
					sp->sd_gyro_bias_rad_s[i] = sqrt(k->P[IG + i][IG + i]);
					sp->sd_accel_bias_m_s2[i] = sqrt(k->P[IB + i][IB + i]);
				}
			}
		} else {
			in_stop = false;
		}
		if ((j + 1) % out_every == 0)
			fill_rec(&st, k, &ltp, bg, ba, (double)(s1 + 1) * dt, still,
				 &res->rec[res->n_rec++]);
	}
	res->n_updates = n_upd;
	free(k);
	*resp = res;
	return 0;
}
