/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Unit tests of analysis/calib.c on simulated data made here with seeded
 * GSL generators: gravity rotated into random poses (uniform random
 * rotations), the error model applied, white noise added.  Recovery is
 * judged against the uncertainties the fit reports: over R seeded runs
 * and P parameters, a Gaussian estimate lies within 2 sd with probability
 * 0.954; the tests require 90 %, which is more than 3 binomial sd below.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "check-main.h"

#define G0 SSCOPE_CALIB_GRAVITY_STD
#define PI 3.14159265358979323846
#define D2R (PI / 180)

/* valgrind runs (SSCOPE_RUN or CK_FORK=no set) use fewer seeded runs */
static int n_runs(int full)
{
	const char *v = getenv("SSCOPE_RUN"), *f = getenv("CK_FORK");

	if ((v && *v) || (f && !strcmp(f, "no")))
		return full / 2 > 4 ? full / 2 : 4;
	return full;
}

/* rotation matrix from a unit quaternion */
static void q2r(const double q[4], double R[3][3])
{
	double w = q[0], x = q[1], y = q[2], z = q[3];

	R[0][0] = 1 - 2 * (y * y + z * z);
	R[0][1] = 2 * (x * y - w * z);
	R[0][2] = 2 * (x * z + w * y);
	R[1][0] = 2 * (x * y + w * z);
	R[1][1] = 1 - 2 * (x * x + z * z);
	R[1][2] = 2 * (y * z - w * x);
	R[2][0] = 2 * (x * z - w * y);
	R[2][1] = 2 * (y * z + w * x);
	R[2][2] = 1 - 2 * (x * x + y * y);
}

static void random_quat(gsl_rng *r, double q[4])
{
	double n = 0;

	for (int i = 0; i < 4; i++) {
		q[i] = gsl_ran_gaussian_ziggurat(r, 1);
		n += q[i] * q[i];
	}
	for (int i = 0; i < 4; i++)
		q[i] /= sqrt(n);
}

static void inv3(const double A[3][3], double B[3][3])
{
	double d = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
		   A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
		   A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);

	B[0][0] = (A[1][1] * A[2][2] - A[1][2] * A[2][1]) / d;
	B[0][1] = (A[0][2] * A[2][1] - A[0][1] * A[2][2]) / d;
	B[0][2] = (A[0][1] * A[1][2] - A[0][2] * A[1][1]) / d;
	B[1][0] = (A[1][2] * A[2][0] - A[1][0] * A[2][2]) / d;
	B[1][1] = (A[0][0] * A[2][2] - A[0][2] * A[2][0]) / d;
	B[1][2] = (A[0][2] * A[1][0] - A[0][0] * A[1][2]) / d;
	B[2][0] = (A[1][0] * A[2][1] - A[1][1] * A[2][0]) / d;
	B[2][1] = (A[0][1] * A[2][0] - A[0][0] * A[2][1]) / d;
	B[2][2] = (A[0][0] * A[1][1] - A[0][1] * A[1][0]) / d;
}

/* the true accelerometer correction of the simulations */
static void true_accel(struct sscope_calib_triad *c)
{
	sscope_calib_triad_identity(c);
	c->bias[0] = 0.0213;
	c->bias[1] = -0.0371;
	c->bias[2] = 0.0452;
	c->scale[0] = 1.0123;
	c->scale[1] = 0.9871;
	c->scale[2] = 1.0047;
	c->mis[0][1] = -0.0042;  /* -alpha_yz */
	c->mis[0][2] = 0.0027;   /* alpha_zy */
	c->mis[1][2] = -0.0061;  /* -alpha_zx */
}

/* reading = (T K)^-1 f + b */
static void measure(const struct sscope_calib_triad *c, const double f[3],
		    double y[3])
{
	double C[3][3], Ci[3][3];

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			C[i][j] = c->mis[i][j] * c->scale[j];
	inv3(C, Ci);
	for (int i = 0; i < 3; i++)
		y[i] = Ci[i][0] * f[0] + Ci[i][1] * f[1] + Ci[i][2] * f[2] +
		       c->bias[i];
}

static int within(double est, double truth, double sd, double k)
{
	return fabs(est - truth) <= k * sd;
}

START_TEST(test_variance_magnitude)
{
	enum { N = 500, W = 21 };
	double x[3 * N], vs[N];
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	gsl_rng_set(r, 11);
	for (int i = 0; i < 3 * N; i++)
		x[i] = 1000.5 + 0.37 * gsl_ran_gaussian_ziggurat(r, 1);
	ck_assert_int_eq(sscope_calib_variance_magnitude(x, x + 1, x + 2, 3, N,
							 W, vs), 0);
	ck_assert(isinf(vs[0]) && isinf(vs[W / 2 - 1]) && isinf(vs[N - 1]));
	/* cross-check with a direct two-pass variance at every sample */
	for (int i = W / 2; i + W / 2 < N; i++) {
		double v2 = 0;

		for (int c = 0; c < 3; c++) {
			struct sscope_stats st;

			sscope_stats_compute(x + 3 * (i - W / 2) + c, 3, W, &st);
			v2 += st.sd * st.sd * st.sd * st.sd;
		}
		ck_assert_rel(vs[i], sqrt(v2), 1e-9);
	}
	/* affine raw units (x' = 1e3 x + 33000): the magnitude scales by
	 * 1e6, so the static detector's thresholds (multiples of a
	 * percentile of it) pick the same samples */
	{
		double x2[3 * N], vs2[N];

		for (int i = 0; i < 3 * N; i++)
			x2[i] = 1e3 * x[i] + 33000;
		sscope_calib_variance_magnitude(x2, x2 + 1, x2 + 2, 3, N, W, vs2);
		for (int i = W / 2; i + W / 2 < N; i++)
			ck_assert_rel(vs2[i], 1e6 * vs[i], 1e-9);
	}
	/* a constant gives zero */
	for (int i = 0; i < 3 * N; i++)
		x[i] = 2.385;
	sscope_calib_variance_magnitude(x, x + 1, x + 2, 3, N, W, vs);
	ck_assert(vs[N / 2] == 0);
	ck_assert_int_eq(sscope_calib_variance_magnitude(x, x, x, 3, N, 2, vs),
			 -EINVAL);
	ck_assert_int_eq(sscope_calib_variance_magnitude(x, x, x, 0, N, W, vs),
			 -EINVAL);
	ck_assert_int_eq(sscope_calib_variance_magnitude(x, x, x, 3, 10, W, vs),
			 -EDOM);
	gsl_rng_free(r);
}
END_TEST

START_TEST(test_intervals)
{
	double vs[20];
	struct sscope_calib_interval iv[4];
	size_t n;

	for (int i = 0; i < 20; i++)
		vs[i] = (i >= 2 && i < 7) || (i >= 9 && i < 11) || i >= 15 ? 0.5 : 3;
	ck_assert_int_eq(sscope_calib_static_intervals(vs, 20, 1, 3, iv, 4, &n), 0);
	ck_assert_uint_eq(n, 2);
	ck_assert_uint_eq(iv[0].start, 2);
	ck_assert_uint_eq(iv[0].end, 7);
	ck_assert_uint_eq(iv[1].start, 15);
	ck_assert_uint_eq(iv[1].end, 20);
	ck_assert_int_eq(sscope_calib_static_intervals(vs, 20, 0, 3, iv, 4, &n),
			 -EINVAL);
	/* constant-reference segments with settling */
	{
		double rr[12] = { 0, 0, 0, 0, 5, 5, 5, 5, 5, -5, -5, -5 };

		ck_assert_int_eq(sscope_calib_constant_segments(rr, 1, 12, 1e-9, 1,
								2, iv, 4, &n), 0);
		ck_assert_uint_eq(n, 3);
		ck_assert_uint_eq(iv[1].start, 5);
		ck_assert_uint_eq(iv[1].end, 9);
		ck_assert_uint_eq(iv[2].start, 10);
		ck_assert_int_eq(sscope_calib_constant_segments(rr, 1, 12, -1, 1, 2,
								iv, 4, &n),
				 -EINVAL);
		/* NaN (a gap, or outside a schedule) ends a segment */
		rr[6] = NAN;
		rr[0] = NAN;
		ck_assert_int_eq(sscope_calib_constant_segments(rr, 1, 12, 1e-9, 0,
								2, iv, 4, &n), 0);
		ck_assert_uint_eq(n, 4);
		ck_assert_uint_eq(iv[0].start, 1);
		ck_assert_uint_eq(iv[0].end, 4);
		ck_assert_uint_eq(iv[1].start, 4);
		ck_assert_uint_eq(iv[1].end, 6);
		ck_assert_uint_eq(iv[2].start, 7);
		ck_assert_uint_eq(iv[2].end, 9);
	}
	{
		struct sscope_calib_interval e = { 3, 3 };
		double m;

		ck_assert_int_eq(sscope_calib_interval_mean(vs, 1, &e, &m, NULL),
				 -EINVAL);
	}
}
END_TEST

/* pose means of a random multi-position test */
static void sim_poses(gsl_rng *r, const struct sscope_calib_triad *c,
		      size_t n, double sd, double (*m)[3])
{
	for (size_t k = 0; k < n; k++) {
		double q[4], R[3][3], f[3];

		random_quat(r, q);
		q2r(q, R);
		for (int i = 0; i < 3; i++)
			f[i] = R[2][i] * G0; /* R^T (0, 0, g) */
		measure(c, f, m[k]);
		for (int i = 0; i < 3; i++)
			m[k][i] += sd * gsl_ran_gaussian_ziggurat(r, 1);
	}
}

START_TEST(test_accel_fit_coverage)
{
	enum { POSES = 30 };
	struct sscope_calib_triad tru, est;
	double m[POSES][3];
	int runs = n_runs(40), inside = 0, total = 0;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	true_accel(&tru);
	for (int run = 0; run < runs; run++) {
		gsl_rng_set(r, 100 + (unsigned long)run);
		sim_poses(r, &tru, POSES, 2e-3, m);
		ck_assert_int_eq(sscope_calib_accel_fit((const double(*)[3])m, POSES,
							G0, &est, NULL), 0);
		ck_assert_uint_eq(est.poses, POSES);
		ck_assert_uint_eq(est.n_params, 9);
		for (int i = 0; i < 3; i++) {
			inside += within(est.bias[i], tru.bias[i], est.bias_sd[i], 2);
			inside += within(est.scale[i], tru.scale[i], est.scale_sd[i], 2);
			/* sd are positive and small */
			ck_assert(est.bias_sd[i] > 0 && est.bias_sd[i] < 5e-3);
			ck_assert(est.scale_sd[i] > 0 && est.scale_sd[i] < 1e-3);
			total += 2;
		}
		inside += within(est.mis[0][1], tru.mis[0][1], est.mis_sd[0][1], 2);
		inside += within(est.mis[0][2], tru.mis[0][2], est.mis_sd[0][2], 2);
		inside += within(est.mis[1][2], tru.mis[1][2], est.mis_sd[1][2], 2);
		total += 3;
		/* residual rms near the noise: |g| error of one pose has sd 2e-3 */
		ck_assert(est.residual_rms > 1e-3 && est.residual_rms < 3e-3);
	}
	ck_assert_msg(inside >= 0.9 * total, "%d of %d within 2 sd", inside,
		      total);
	gsl_rng_free(r);
}
END_TEST

START_TEST(test_accel_fit_errors)
{
	struct sscope_calib_triad tru, est;
	double m[30][3];
	struct sscope_diag d = { "" };
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	true_accel(&tru);
	gsl_rng_set(r, 7);
	sim_poses(r, &tru, 30, 1e-3, m);
	/* too few poses */
	ck_assert_int_eq(sscope_calib_accel_fit((const double(*)[3])m, 9, G0,
						&est, &d), -EDOM);
	ck_assert(strstr(d.msg, "at least 10") != NULL);
	ck_assert_int_eq(sscope_calib_accel_fit((const double(*)[3])m, 30, -1,
						&est, NULL), -EINVAL);
	/* degenerate: gravity always in the x-y plane (z never excited) */
	for (int k = 0; k < 30; k++) {
		double a = 2 * PI * k / 30, f[3] = { G0 * cos(a), G0 * sin(a), 0 };

		measure(&tru, f, m[k]);
	}
	d.msg[0] = 0;
	ck_assert_int_eq(sscope_calib_accel_fit((const double(*)[3])m, 30, G0,
						&est, &d), -EDOM);
	ck_assert_msg(strstr(d.msg, "do not determine") != NULL, "%s", d.msg);
	m[3][1] = NAN;
	ck_assert_int_eq(sscope_calib_accel_fit((const double(*)[3])m, 30, G0,
						&est, NULL), -EINVAL);
	/* raw counts: an offset of 33000 and 414 counts per m/s^2 give the
	 * same calibration as the SI means (bias' = 414 b + 33000, scale' =
	 * scale / 414), to 1e-9 */
	{
		struct sscope_calib_triad e1, e2;

		sim_poses(r, &tru, 30, 1e-3, m);
		ck_assert_int_eq(sscope_calib_accel_fit((const double(*)[3])m, 30, G0,
							&e1, NULL), 0);
		for (int k = 0; k < 30; k++)
			for (int i = 0; i < 3; i++)
				m[k][i] = 414 * m[k][i] + 33000;
		ck_assert_int_eq(sscope_calib_accel_fit((const double(*)[3])m, 30, G0,
							&e2, NULL), 0);
		for (int i = 0; i < 3; i++) {
			ck_assert_rel((e2.bias[i] - 33000) / 414, e1.bias[i], 1e-9);
			ck_assert_rel(e2.scale[i] * 414, e1.scale[i], 1e-9);
			ck_assert_rel(e2.scale_sd[i] * 414, e1.scale_sd[i], 1e-7);
			for (int j = 0; j < 3; j++)
				ck_assert(fabs(e2.mis[i][j] - e1.mis[i][j]) < 1e-9);
		}
		ck_assert_rel(e2.residual_rms, e1.residual_rms, 1e-9);
	}
	gsl_rng_free(r);
}
END_TEST

/*
 * A multi-position time series: static poses of t_static s joined by
 * rotations of t_move s about a fixed body axis with a raised-cosine rate
 * profile.  Optionally the gyro (with its own error model) is simulated.
 */
struct series {
	size_t n;
	double fs;
	double *a;   /* n x 3 accelerometer readings */
	double *f;   /* n x 3 true specific force */
	double *w;   /* n x 3 gyro readings */
	size_t poses;
};

static void axis_angle(const double Ra[3][3], const double Rb[3][3],
		       double ax[3], double *ang)
{
	/* D = Ra^T Rb, the body-frame rotation from pose a to pose b */
	double D[3][3], tr, s;

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			D[i][j] = Ra[0][i] * Rb[0][j] + Ra[1][i] * Rb[1][j] +
				  Ra[2][i] * Rb[2][j];
	tr = D[0][0] + D[1][1] + D[2][2];
	*ang = acos(fmax(-1, fmin(1, (tr - 1) / 2)));
	ax[0] = D[2][1] - D[1][2];
	ax[1] = D[0][2] - D[2][0];
	ax[2] = D[1][0] - D[0][1];
	s = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
	for (int i = 0; i < 3; i++)
		ax[i] /= s;
}

/* R(t) = Ra exp([ax * phi]x) */
static void rot_about(const double Ra[3][3], const double ax[3], double phi,
		      double R[3][3])
{
	double c = cos(phi), s = sin(phi), E[3][3];
	const double *u = ax;

	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			E[i][j] = (i == j ? c : 0) + (1 - c) * u[i] * u[j];
	E[0][1] -= s * u[2];
	E[0][2] += s * u[1];
	E[1][0] += s * u[2];
	E[1][2] -= s * u[0];
	E[2][0] -= s * u[1];
	E[2][1] += s * u[0];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			R[i][j] = Ra[i][0] * E[0][j] + Ra[i][1] * E[1][j] +
				  Ra[i][2] * E[2][j];
}

static void make_series(gsl_rng *r, size_t poses, double fs, double t_static,
			double t_move, const struct sscope_calib_triad *ca,
			double sda, const struct sscope_calib_triad *cg,
			double sdg, int single_axis, struct series *s)
{
	size_t ns = (size_t)(t_static * fs), nm = (size_t)(t_move * fs), k = 0;
	double (*Rp)[3][3] = malloc(poses * sizeof(*Rp));

	s->fs = fs;
	s->poses = poses;
	s->n = poses * ns + (poses - 1) * nm;
	s->a = malloc(3 * s->n * sizeof(double));
	s->f = malloc(3 * s->n * sizeof(double));
	s->w = malloc(3 * s->n * sizeof(double));
	for (size_t p = 0; p < poses; p++) {
		if (single_axis) {
			/* rotations about body x only: gravity sweeps y-z */
			double phi = 2 * PI * (double)p / (double)poses + 0.3;
			double Rx[3][3] = { { 1, 0, 0 },
					    { 0, cos(phi), -sin(phi) },
					    { 0, sin(phi), cos(phi) } };

			memcpy(Rp[p], Rx, sizeof(Rx));
		} else {
			double q[4];

			random_quat(r, q);
			q2r(q, Rp[p]);
		}
	}
	for (size_t p = 0; p < poses; p++) {
		for (size_t i = 0; i < ns; i++, k++) {
			double wt[3] = { 0, 0, 0 };

			for (int c = 0; c < 3; c++)
				s->f[3 * k + c] = Rp[p][2][c] * G0;
			measure(ca, s->f + 3 * k, s->a + 3 * k);
			measure(cg, wt, s->w + 3 * k);
		}
		if (p + 1 == poses)
			break;
		{
			double ax[3], ang, R[3][3];

			axis_angle(Rp[p], Rp[p + 1], ax, &ang);
			for (size_t i = 0; i < nm; i++, k++) {
				double t = ((double)i + 1) / fs, T = t_move;
				double phi = ang * (t / T - sin(2 * PI * t / T) /
								 (2 * PI));
				double rate = ang / T * (1 - cos(2 * PI * t / T));
				double wt[3] = { ax[0] * rate, ax[1] * rate,
						 ax[2] * rate };

				rot_about(Rp[p], ax, phi, R);
				for (int c = 0; c < 3; c++)
					s->f[3 * k + c] = R[2][c] * G0;
				measure(ca, s->f + 3 * k, s->a + 3 * k);
				measure(cg, wt, s->w + 3 * k);
			}
		}
	}
	for (size_t i = 0; i < 3 * s->n; i++) {
		s->a[i] += sda * gsl_ran_gaussian_ziggurat(r, 1);
		s->w[i] += sdg * gsl_ran_gaussian_ziggurat(r, 1);
	}
	free(Rp);
}

static void free_series(struct series *s)
{
	free(s->a);
	free(s->f);
	free(s->w);
}

START_TEST(test_accel_multipos_series)
{
	struct sscope_calib_triad tru, est, gid;
	struct series s;
	struct sscope_calib_detect det = { 0 };
	struct sscope_calib_interval iv[64];
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double *w1, *w2;
	int ok = 0;

	true_accel(&tru);
	sscope_calib_triad_identity(&gid);
	gsl_rng_set(r, 2024);
	make_series(r, 24, 100, 4, 2, &tru, 0.02, &gid, 0.001, 0, &s);
	w1 = malloc(s.n * sizeof(double));
	w2 = malloc(s.n * sizeof(double));
	ck_assert_int_eq(sscope_calib_accel_multipos(s.a, s.a + 1, s.a + 2, 3, s.n,
						     100, G0, &det, iv, 64, &est,
						     w1, w2, NULL), 0);
	/* every pose found, one interval each, and the reported rule */
	ck_assert_uint_eq(det.n_intervals, 24);
	ck_assert(det.k >= 2 && det.k <= 10);
	ck_assert(det.threshold == det.k * det.reference);
	/* white noise sd 0.02 per axis, window 101: varsigma = sqrt(3) sd^2 */
	ck_assert_rel(det.reference, sqrt(3) * 4e-4, 0.3);
	for (int i = 0; i < 3; i++) {
		ok += within(est.bias[i], tru.bias[i], est.bias_sd[i], 3);
		ok += within(est.scale[i], tru.scale[i], est.scale_sd[i], 3);
	}
	ok += within(est.mis[0][1], tru.mis[0][1], est.mis_sd[0][1], 3);
	ok += within(est.mis[0][2], tru.mis[0][2], est.mis_sd[0][2], 3);
	ok += within(est.mis[1][2], tru.mis[1][2], est.mis_sd[1][2], 3);
	ck_assert_int_ge(ok, 8);
	/* a fixed k and Tedaldi's initial static period */
	det.k = 4;
	det.init_static_s = 3;
	ck_assert_int_eq(sscope_calib_accel_multipos(s.a, s.a + 1, s.a + 2, 3, s.n,
						     100, G0, &det, iv, 64, &est,
						     w1, w2, NULL), 0);
	ck_assert(det.k == 4);
	ck_assert_uint_eq(det.n_intervals, 24);
	ck_assert_int_eq(sscope_calib_accel_multipos(s.a, s.a + 1, s.a + 2, 3, s.n,
						     0, G0, &det, iv, 64, &est,
						     w1, w2, NULL), -EINVAL);
	free(w1);
	free(w2);
	free_series(&s);
	gsl_rng_free(r);
}
END_TEST

static void true_gyro(struct sscope_calib_triad *c)
{
	sscope_calib_triad_identity(c);
	c->bias[0] = 0.31 * D2R;
	c->bias[1] = -0.17 * D2R;
	c->bias[2] = 0.52 * D2R;
	c->scale[0] = 1.0213;
	c->scale[1] = 0.9764;
	c->scale[2] = 1.0081;
	c->mis[0][1] = 0.0081;
	c->mis[0][2] = -0.0043;
	c->mis[1][0] = 0.0057;
	c->mis[1][2] = 0.0112;
	c->mis[2][0] = -0.0069;
	c->mis[2][1] = 0.0036;
}

/* gyro fit on a simulated series with the true accelerometer force */
static int gyro_run(unsigned long seed, double wscale, double guess,
		    int single_axis, struct sscope_calib_triad *tru,
		    struct sscope_calib_triad *est, struct sscope_diag *d)
{
	struct sscope_calib_triad ca;
	struct series s;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	struct sscope_calib_interval iv[40];
	size_t ns = 300, nm = 150, h = 50;
	int rc;

	sscope_calib_triad_identity(&ca);
	true_gyro(tru);
	/* readings in other units: reading = wscale * rad/s */
	for (int i = 0; i < 3; i++) {
		tru->scale[i] /= wscale;
		tru->bias[i] *= wscale;
	}
	gsl_rng_set(r, seed);
	make_series(r, 16, 100, 3, 1.5, &ca, 0.01, tru,
		    0.05 * D2R * wscale, single_axis, &s);
	/* the static intervals as a detector with a 1 s window finds them */
	for (size_t p = 0; p < s.poses; p++) {
		iv[p].start = p * (ns + nm) + (p ? h : 0);
		iv[p].end = p * (ns + nm) + ns - h;
	}
	{
		const double *g[3] = { s.w, s.w + 1, s.w + 2 };
		const double *a[3] = { s.f, s.f + 1, s.f + 2 };

		rc = sscope_calib_gyro_fit(g, a, 3, s.n, 100, guess, iv, s.poses,
					   false, est, d);
	}
	free_series(&s);
	gsl_rng_free(r);
	return rc;
}

START_TEST(test_gyro_fit_coverage)
{
	struct sscope_calib_triad tru, est;
	int runs = n_runs(16), inside = 0, total = 0;

	for (int run = 0; run < runs; run++) {
		ck_assert_int_eq(gyro_run(500 + (unsigned long)run, 1, 1, 0, &tru,
					  &est, NULL), 0);
		ck_assert_uint_eq(est.poses, 16);
		for (int i = 0; i < 3; i++) {
			inside += within(est.scale[i], tru.scale[i], est.scale_sd[i], 2);
			inside += within(est.bias[i], tru.bias[i], est.bias_sd[i], 2);
			total += 2;
			for (int j = 0; j < 3; j++)
				if (i != j) {
					inside += within(est.mis[i][j], tru.mis[i][j],
							 est.mis_sd[i][j], 2);
					total++;
				}
		}
	}
	ck_assert_msg(inside >= 0.9 * total, "%d of %d within 2 sd", inside,
		      total);
}
END_TEST

START_TEST(test_gyro_fit_counts)
{
	struct sscope_calib_triad tru, est;

	/* a gyro in counts of 1/1000 rad/s, no starting scale: grid scan */
	ck_assert_int_eq(gyro_run(77, 1000, 0, 0, &tru, &est, NULL), 0);
	for (int i = 0; i < 3; i++)
		ck_assert_msg(within(est.scale[i], tru.scale[i], est.scale_sd[i], 4),
			      "axis %d: %g vs %g (sd %g)", i, est.scale[i],
			      tru.scale[i], est.scale_sd[i]);
}
END_TEST

START_TEST(test_gyro_fit_errors)
{
	struct sscope_calib_triad tru, est;
	struct sscope_diag d = { "" };
	struct sscope_calib_interval iv[3] = { { 0, 10 }, { 20, 30 }, { 40, 50 } };
	double z[60] = { 0 };
	const double *g[3] = { z, z, z };

	/* rotations about one body axis only */
	ck_assert_int_eq(gyro_run(9, 1, 1, 1, &tru, &est, &d), -EDOM);
	ck_assert_msg(strstr(d.msg, "do not determine") != NULL, "%s", d.msg);
	ck_assert_int_eq(sscope_calib_gyro_fit(g, g, 1, 60, 100, 1, iv, 3, false,
					       &est, &d), -EDOM);
	ck_assert(strstr(d.msg, "at least 6") != NULL);
	iv[1].start = 5;
	ck_assert_int_eq(sscope_calib_gyro_fit(g, g, 1, 60, 100, 1, iv, 3, false,
					       &est, NULL), -EINVAL);
	ck_assert_int_eq(sscope_calib_gyro_fit(g, g, 1, 60, -1, 1, iv, 3, false,
					       &est, NULL), -EINVAL);
}
END_TEST

/* Motion errors: single-axis rotations of 2 pi / 16 about body x with a
 * gyro whose x scale is 1.02 (reading = rate / 1.02): the bias-only
 * correction turns each motion by 1/1.02 of the true angle, so gravity
 * (perpendicular to x) is off by (2 pi / 16)(1 - 1/1.02); the true
 * correction leaves only the integration error.  On a fitted triad the
 * angles agree with the fit's own residual. */
START_TEST(test_gyro_motion_errors)
{
	struct sscope_calib_triad ca, cg, bias_only, tru, est;
	struct sscope_calib_interval iv[16];
	struct series s;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double ang[15], want = 2 * PI / 16 * (1 - 1 / 1.02), sum = 0;
	size_t ns = 300, nm = 150, h = 50;

	sscope_calib_triad_identity(&ca);
	sscope_calib_triad_identity(&cg);
	cg.scale[0] = 1.02;
	cg.bias[0] = 0.01;
	bias_only = ca;
	bias_only.bias[0] = 0.01;
	gsl_rng_set(r, 5);
	make_series(r, 16, 100, 3, 1.5, &ca, 0, &cg, 0, 1, &s);
	for (size_t p = 0; p < 16; p++) {
		iv[p].start = p * (ns + nm) + (p ? h : 0);
		iv[p].end = p * (ns + nm) + ns - h;
	}
	{
		const double *g[3] = { s.w, s.w + 1, s.w + 2 };
		const double *a[3] = { s.f, s.f + 1, s.f + 2 };

		ck_assert_int_eq(sscope_calib_gyro_motion_errors(g, a, 3, s.n, 100, iv, 16,
								 &bias_only, ang), 0);
		for (int k = 0; k < 15; k++)
			ck_assert_msg(fabs(ang[k] - want) < 1e-4 * want,
				      "motion %d: %.9g rad, want %.9g", k, ang[k], want);
		ck_assert_int_eq(sscope_calib_gyro_motion_errors(g, a, 3, s.n, 100, iv, 16,
								 &cg, ang), 0);
		for (int k = 0; k < 15; k++)
			ck_assert_msg(ang[k] < 1e-6, "motion %d: %g rad", k, ang[k]);
		ck_assert_int_eq(sscope_calib_gyro_motion_errors(g, a, 3, s.n, 100, iv, 1,
								 &cg, ang), -EINVAL);
		ck_assert_int_eq(sscope_calib_gyro_motion_errors(g, a, 3, s.n, 0, iv, 16,
								 &cg, ang), -EINVAL);
		iv[3].start = iv[2].start;
		ck_assert_int_eq(sscope_calib_gyro_motion_errors(g, a, 3, s.n, 100, iv, 16,
								 &cg, ang), -EINVAL);
	}
	free_series(&s);
	/* a fitted triad: rms of the chords equals the fit's residual */
	ck_assert_int_eq(gyro_run(41, 1, 1, 0, &tru, &est, NULL), 0);
	{
		struct sscope_calib_triad ca2;
		struct sscope_calib_interval iv2[16];

		sscope_calib_triad_identity(&ca2);
		gsl_rng_set(r, 41);
		make_series(r, 16, 100, 3, 1.5, &ca2, 0.01, &tru, 0.05 * D2R, 0, &s);
		for (size_t p = 0; p < 16; p++) {
			iv2[p].start = p * (ns + nm) + (p ? h : 0);
			iv2[p].end = p * (ns + nm) + ns - h;
		}
		{
			const double *g[3] = { s.w, s.w + 1, s.w + 2 };
			const double *a[3] = { s.f, s.f + 1, s.f + 2 };

			ck_assert_int_eq(sscope_calib_gyro_motion_errors(g, a, 3, s.n, 100,
									 iv2, 16, &est,
									 ang), 0);
		}
		for (int k = 0; k < 15; k++)
			sum += 4 * sin(ang[k] / 2) * sin(ang[k] / 2);
		ck_assert_msg(fabs(sqrt(sum / 45) - est.residual_rms) < 1e-9 * est.residual_rms,
			      "%.12g vs %.12g", sqrt(sum / 45), est.residual_rms);
		free_series(&s);
	}
	gsl_rng_free(r);
}
END_TEST

START_TEST(test_gsens)
{
	/* static tilt poses: omega = b + G a + noise */
	enum { P = 24 };
	const double G[3][3] = { { 2.1e-4, -0.7e-4, 0.3e-4 },
				 { 0.5e-4, -1.4e-4, 0.9e-4 },
				 { -0.2e-4, 0.6e-4, 3.3e-4 } };
	const double b[3] = { 1.3e-3, -2.2e-3, 0.7e-3 };
	double y[P][3], a[P][3];
	struct sscope_calib_linear lf;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	int ok = 0;

	gsl_rng_set(r, 31);
	for (int k = 0; k < P; k++) {
		double q[4], R[3][3];

		random_quat(r, q);
		q2r(q, R);
		for (int i = 0; i < 3; i++)
			a[k][i] = R[2][i] * G0;
		for (int i = 0; i < 3; i++)
			y[k][i] = b[i] + G[i][0] * a[k][0] + G[i][1] * a[k][1] +
				  G[i][2] * a[k][2] +
				  2e-5 * gsl_ran_gaussian_ziggurat(r, 1);
	}
	ck_assert_int_eq(sscope_calib_linear_fit((const double(*)[3])y,
						 (const double(*)[3])a, P,
						 false, &lf, NULL), 0);
	for (int i = 0; i < 3; i++) {
		ok += within(lf.bias[i], b[i], lf.bias_sd[i], 3);
		for (int j = 0; j < 3; j++)
			ok += within(lf.A[i][j], G[i][j], lf.A_sd[i][j], 3);
	}
	ck_assert_int_ge(ok, 11);
	gsl_rng_free(r);
}
END_TEST

/* a single-axis rate table: steps of commanded rate on x */
START_TEST(test_rate_table_cubic)
{
	const double s = 1.0137, b = 0.0021, c3 = -2.3e-4, m_yx = 0.0048,
		     m_zx = -0.0031, sd = 2e-4;
	double y[25][3], rr[25][3];
	struct sscope_calib_linear lf;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	int n = 0;

	gsl_rng_set(r, 41);
	for (int k = -12; k <= 12; k++, n++) {
		double w = k * 25 * D2R; /* up to 300 deg/s = 5.24 rad/s */

		rr[n][0] = w;
		rr[n][1] = rr[n][2] = 0;
		y[n][0] = b + s * w + c3 * w * w * w +
			  sd * gsl_ran_gaussian_ziggurat(r, 1);
		y[n][1] = -0.001 + m_yx * w + sd * gsl_ran_gaussian_ziggurat(r, 1);
		y[n][2] = 0.0005 + m_zx * w + sd * gsl_ran_gaussian_ziggurat(r, 1);
	}
	ck_assert_int_eq(sscope_calib_linear_fit((const double(*)[3])y,
						 (const double(*)[3])rr, 25,
						 true, &lf, NULL), 0);
	ck_assert(lf.axis_excited[0] && !lf.axis_excited[1] &&
		  !lf.axis_excited[2]);
	ck_assert(within(lf.A[0][0], s, lf.A_sd[0][0], 4));
	ck_assert(within(lf.c3[0], c3, lf.c3_sd[0], 4));
	ck_assert(within(lf.c2[0], 0, lf.c2_sd[0], 4));
	ck_assert(within(lf.bias[0], b, lf.bias_sd[0], 4));
	ck_assert(within(lf.A[1][0], m_yx, lf.A_sd[1][0], 4));
	ck_assert(within(lf.A[2][0], m_zx, lf.A_sd[2][0], 4));
	ck_assert(isnan(lf.A_sd[0][1]) && lf.A[0][1] == 0);
	/*
	 * Best-fit-straight-line non-linearity of c3 w^3 over [-W, W] at
	 * the 25 levels: the largest deviation of the cubic from its own
	 * least-squares line, divided by s W.  Computed here independently.
	 */
	{
		double W = 12 * 25 * D2R, sxx = 0, sxy = 0, slope, dev = 0;

		for (int k = -12; k <= 12; k++) {
			double w = k * 25 * D2R;

			sxx += w * w;
			sxy += w * c3 * w * w * w;
		}
		slope = sxy / sxx;
		for (int k = -12; k <= 12; k++) {
			double w = k * 25 * D2R;

			dev = fmax(dev, fabs(c3 * w * w * w - slope * w));
		}
		/* noise adds about 2 sd to the largest deviation */
		ck_assert_msg(fabs(lf.nonlinearity[0] - dev / (s * W)) <
				      4 * sd / (s * W),
			      "nonlinearity %g, expected %g", lf.nonlinearity[0],
			      dev / (s * W));
		ck_assert(fabs(lf.sf_bfsl[0] - (s + slope)) < 4 * lf.A_sd[0][0]);
	}
	/* errors */
	for (int k = 0; k < 25; k++)
		rr[k][0] = 1.5;
	ck_assert_int_eq(sscope_calib_linear_fit((const double(*)[3])y,
						 (const double(*)[3])rr, 25,
						 false, &lf, NULL), -EDOM);
	ck_assert_int_eq(sscope_calib_linear_fit((const double(*)[3])y,
						 (const double(*)[3])rr, 0,
						 false, &lf, NULL), -EDOM);
	gsl_rng_free(r);
}
END_TEST

START_TEST(test_sixpos_and_apply)
{
	struct sscope_calib_triad tru, est;
	struct sscope_calib_linear lf;
	double m[12][3];
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	struct sscope_diag d = { "" };
	int ok = 0;

	true_accel(&tru);
	/* a full (lower-triangular part too) misalignment for the 12-param
	 * model */
	tru.mis[1][0] = 0.0033;
	tru.mis[2][0] = -0.0018;
	tru.mis[2][1] = 0.0025;
	gsl_rng_set(r, 51);
	for (int k = 0; k < 12; k++) {
		double f[3] = { 0, 0, 0 };

		f[(k % 6) / 2] = (k % 2) ? -G0 : G0;
		measure(&tru, f, m[k]);
		for (int i = 0; i < 3; i++)
			m[k][i] += 1e-3 * gsl_ran_gaussian_ziggurat(r, 1);
	}
	ck_assert_int_eq(sscope_calib_accel_sixpos((const double(*)[3])m, 12, G0,
						   &lf, &est, NULL), 0);
	for (int i = 0; i < 3; i++) {
		ok += within(est.bias[i], tru.bias[i], est.bias_sd[i], 3);
		ok += within(est.scale[i], tru.scale[i], est.scale_sd[i], 3);
		for (int j = 0; j < 3; j++)
			if (i != j)
				ok += within(est.mis[i][j], tru.mis[i][j],
					     est.mis_sd[i][j], 3);
	}
	ck_assert_int_ge(ok, 11);
	/* applying the estimate to a reading returns the force */
	{
		double f[3] = { 3.1, -5.2, 7.4 }, y[3], x[1], yy[1], z[1];

		measure(&tru, f, y);
		x[0] = y[0];
		yy[0] = y[1];
		z[0] = y[2];
		sscope_calib_apply(&tru, x, yy, z, 1, 1, NULL, 1);
		ck_assert_rel(x[0], f[0], 1e-12);
		ck_assert_rel(yy[0], f[1], 1e-12);
		ck_assert_rel(z[0], f[2], 1e-12);
	}
	/* a missing orientation */
	ck_assert_int_eq(sscope_calib_accel_sixpos((const double(*)[3])m, 5, G0,
						   &lf, &est, &d), -EDOM);
	ck_assert_msg(strstr(d.msg, "-z") != NULL, "%s", d.msg);
	gsl_rng_free(r);
}
END_TEST

START_TEST(test_grades)
{
	size_t n;
	const struct sscope_calib_class *g = sscope_calib_grades(&n);
	int i;

	ck_assert(n >= 6);
	/* a MEMS gyro: 0.3 deg/s bias, 0.5 % scale, 0.3 deg/sqrt(h) */
	i = sscope_calib_grade(SSCOPE_QUANTITY_ANGULAR_RATE, 0.3 * D2R, 5e-3,
			       0.3 * D2R / 60, NAN, NULL);
	ck_assert_int_ge(i, 0);
	ck_assert_msg(strstr(g[i].name, "silicon") != NULL, "%s", g[i].name);
	/* a navigation RLG: 0.003 deg/h, 5 ppm, 0.002 deg/sqrt(h) */
	i = sscope_calib_grade(SSCOPE_QUANTITY_ANGULAR_RATE, 0.003 * D2R / 3600, 5e-6,
			       0.002 * D2R / 60, NAN, NULL);
	ck_assert_msg(strstr(g[i].name, "ring laser") != NULL, "%s", g[i].name);
	/* a 5 mg accelerometer is tactical */
	i = sscope_calib_grade(SSCOPE_QUANTITY_ACCELERATION, 5e-3 * G0, NAN, NAN, NAN,
			       NULL);
	ck_assert_msg(strstr(g[i].name, "tactical") != NULL, "%s", g[i].name);
	ck_assert_int_eq(sscope_calib_grade(SSCOPE_QUANTITY_ANGULAR_RATE, NAN, NAN,
					    NAN, NAN, NULL), -EDOM);
	ck_assert_int_eq(sscope_calib_grade(SSCOPE_QUANTITY_VOLTAGE, 1, 1, 1, 1, NULL),
			 -EINVAL);
}
END_TEST

/* ---- calibration runs (analysis/calib-run.c) ---- */

/* A capture of poses: static for ns samples (gravity along f[k]), then nm
 * samples of motion (readings swinging by 3 m/s^2, far above the noise). */
static size_t pose_capture(gsl_rng *r, const struct sscope_calib_triad *c,
			   const double (*f)[3], size_t poses, size_t ns,
			   size_t nm, double sd, double *x[3])
{
	size_t n = poses * ns + (poses - 1) * nm, k = 0;

	for (int i = 0; i < 3; i++)
		x[i] = malloc(n * sizeof(double));
	for (size_t p = 0; p < poses; p++) {
		for (size_t i = 0; i < ns + (p + 1 < poses ? nm : 0); i++, k++) {
			double y[3];

			measure(c, f[p], y);
			for (int a = 0; a < 3; a++)
				x[a][k] = y[a] + sd * gsl_ran_gaussian_ziggurat(r, 1) +
					  (i >= ns ? 3 * sin(0.37 * (double)i + a) : 0);
		}
	}
	return n;
}

/* The six-position test on a capture: the six poses found, the threshold
 * chosen among 2..10, the parameters within 3 of their sd (11 of 12). */
START_TEST(test_sixpos_run)
{
	const double f[6][3] = { { G0, 0, 0 }, { -G0, 0, 0 }, { 0, G0, 0 },
				 { 0, -G0, 0 }, { 0, 0, G0 }, { 0, 0, -G0 } };
	struct sscope_calib_triad tru, est;
	struct sscope_calib_linear lf;
	struct sscope_calib_detect det = { 0 };
	struct sscope_calib_interval iv[32];
	struct sscope_diag d = { "" };
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double *x[3], *w1, *w2, nd;
	size_t n;
	int ok = 0;

	true_accel(&tru);
	gsl_rng_set(r, 61);
	n = pose_capture(r, &tru, f, 6, 500, 200, 0.02, x);
	w1 = malloc(n * sizeof(double));
	w2 = malloc(n * sizeof(double));
	ck_assert_int_eq(sscope_calib_accel_sixpos_run(x[0], x[1], x[2], 1, n, 100,
						       G0, &det, iv, 32, &lf, &est,
						       w1, w2, &d), 0);
	ck_assert_uint_eq(det.n_intervals, 6);
	ck_assert(det.k >= 2 && det.k <= 10);
	ck_assert_rel(det.threshold, det.k * det.reference, 1e-15);
	for (int i = 0; i < 3; i++) {
		ok += within(est.bias[i], tru.bias[i], est.bias_sd[i], 3);
		ok += within(est.scale[i], tru.scale[i], est.scale_sd[i], 3);
		for (int j = 0; j < 3; j++)
			if (i < j)
				ok += within(est.mis[i][j], tru.mis[i][j],
					     est.mis_sd[i][j], 3);
	}
	ck_assert_int_ge(ok, 8);
	/* the pooled noise density: sd 0.02 through the scales, per sqrt(Hz)
	 * (relative sd of a pooled sd over ~2000 dof: 1.6 %; 5 % is > 3 sd) */
	{
		const double *ch[3] = { x[0], x[1], x[2] };
		double want = 0;

		for (int i = 0; i < 3; i++)
			want += 0.02 * est.scale[i] * 0.02 * est.scale[i];
		want = sqrt(want / 3 / 100);
		ck_assert_int_eq(sscope_calib_noise_density(ch, 1, iv, 6, est.scale,
							    100, &nd), 0);
		ck_assert_rel(nd, want, 0.05);
		ck_assert_int_eq(sscope_calib_noise_density(ch, 1, iv, 0, est.scale,
							    100, &nd), -EDOM);
		ck_assert(isnan(nd));
	}
	/* at a threshold below the noise nothing is static */
	det.k = 1.01;
	det.min_static_s = 4.9;
	ck_assert_int_eq(sscope_calib_accel_sixpos_run(x[0], x[1], x[2], 1, n, 100,
						       G0, &det, iv, 32, &lf, &est,
						       w1, w2, &d), -EDOM);
	ck_assert(d.msg[0] != '\0');
	for (int i = 0; i < 3; i++)
		free(x[i]);
	free(w1);
	free(w2);
	gsl_rng_free(r);
}
END_TEST

/* The g-dependent gyro bias from static tilts of a capture. */
START_TEST(test_gsens_run)
{
	enum { P = 14 };
	const double G[3][3] = { { 2.1e-4, -0.7e-4, 0.3e-4 },
				 { 0.5e-4, -1.4e-4, 0.9e-4 },
				 { -0.2e-4, 0.6e-4, 3.3e-4 } };
	const double b[3] = { 1.3e-3, -2.2e-3, 0.7e-3 };
	double f[P][3], *a[3], *g[3], *w1, *w2;
	struct sscope_calib_triad ida, c;
	struct sscope_calib_detect det = { 0 };
	struct sscope_calib_interval iv[32];
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	size_t n;
	int ok = 0;

	gsl_rng_set(r, 62);
	for (int k = 0; k < P; k++) {
		double q[4], R[3][3];

		random_quat(r, q);
		q2r(q, R);
		for (int i = 0; i < 3; i++)
			f[k][i] = R[2][i] * G0;
	}
	sscope_calib_triad_identity(&ida);
	n = pose_capture(r, &ida, (const double(*)[3])f, P, 400, 150, 0.01, a);
	for (int i = 0; i < 3; i++)
		g[i] = malloc(n * sizeof(double));
	for (size_t k = 0; k < n; k++)
		for (int i = 0; i < 3; i++)
			g[i][k] = b[i] + G[i][0] * a[0][k] + G[i][1] * a[1][k] +
				  G[i][2] * a[2][k] + 1e-3 * gsl_ran_gaussian_ziggurat(r, 1);
	w1 = malloc(n * sizeof(double));
	w2 = malloc(n * sizeof(double));
	ck_assert_int_eq(sscope_calib_gyro_gsens_run((const double *const *)g,
						     (const double *const *)a, 1, n,
						     100, &det, iv, 32, &c, w1, w2,
						     NULL), 0);
	ck_assert(det.k == 4); /* the default threshold */
	ck_assert_uint_eq(det.n_intervals, P);
	ck_assert(c.has_gsens && c.n_params == 12 && c.poses == P);
	for (int i = 0; i < 3; i++) {
		ok += within(c.bias[i], b[i], c.bias_sd[i], 3);
		for (int j = 0; j < 3; j++)
			ok += within(c.gsens[i][j], G[i][j], c.gsens_sd[i][j], 3);
		ck_assert(c.scale[i] == 1 && isnan(c.scale_sd[i]));
	}
	ck_assert_int_ge(ok, 11);
	for (int i = 0; i < 3; i++) {
		free(a[i]);
		free(g[i]);
	}
	free(w1);
	free(w2);
	gsl_rng_free(r);
}
END_TEST

/* The error model is the inverse of T K; the class from its figures. */
START_TEST(test_error_model_and_grade)
{
	struct sscope_calib_triad c;
	double A[3][3], dist, dist2;
	int g1, g2;

	true_accel(&c);
	ck_assert_int_eq(sscope_calib_error_model(&c, A), 0);
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) {
			double p = 0;

			for (int k = 0; k < 3; k++)
				p += A[i][k] * c.mis[k][j] * c.scale[j];
			ck_assert_msg(fabs(p - (i == j)) < 1e-14, "(A T K)[%d][%d] = %g", i, j, p);
		}
	/* the class from the largest |bias|, |A_ii - 1| and noise */
	{
		double sf = 0, bias = 0;

		for (int i = 0; i < 3; i++) {
			sf = fmax(sf, fabs(A[i][i] - 1));
			bias = fmax(bias, fabs(c.bias[i]));
		}
		g1 = sscope_calib_triad_grade(SSCOPE_QUANTITY_ACCELERATION, &c,
					      (const double(*)[3])A, 3e-3, &dist);
		g2 = sscope_calib_grade(SSCOPE_QUANTITY_ACCELERATION, bias, sf, 3e-3, NAN,
					&dist2);
		ck_assert_int_eq(g1, g2);
		ck_assert(dist == dist2);
	}
	/* raw readings: the bias through T K, no scale error */
	{
		double tkb = 0;

		for (int i = 0; i < 3; i++) {
			double v = 0;

			for (int j = 0; j < 3; j++)
				v += c.mis[i][j] * c.scale[j] * c.bias[j];
			tkb = fmax(tkb, fabs(v));
		}
		g1 = sscope_calib_triad_grade(SSCOPE_QUANTITY_ACCELERATION, &c, NULL, NAN, &dist);
		g2 = sscope_calib_grade(SSCOPE_QUANTITY_ACCELERATION, tkb, NAN, NAN, NAN, &dist2);
		ck_assert_int_eq(g1, g2);
		ck_assert(dist == dist2);
	}
	c.scale[1] = 0;
	ck_assert_int_eq(sscope_calib_error_model(&c, A), -EDOM);
}
END_TEST

/* Pose norms: the true correction puts every pose on |g|. */
START_TEST(test_pose_errors)
{
	const double f[3][3] = { { G0, 0, 0 }, { 0, 0, -G0 },
				 { 0.6 * G0, 0.8 * G0, 0 } };
	struct sscope_calib_triad tru, id;
	struct sscope_calib_interval iv[3];
	double *x[3], before[3], after[3];
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	true_accel(&tru);
	sscope_calib_triad_identity(&id);
	gsl_rng_set(r, 63);
	pose_capture(r, &tru, f, 3, 100, 20, 0, x);
	for (size_t p = 0; p < 3; p++) {
		iv[p].start = p * 120;
		iv[p].end = p * 120 + 100;
	}
	ck_assert_int_eq(sscope_calib_pose_errors((const double *const *)x, 1, iv, 3,
						  &tru, G0, true, before, after), 0);
	for (int p = 0; p < 3; p++) {
		double y[3], nb;

		measure(&tru, f[p], y);
		nb = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
		ck_assert_msg(fabs(after[p]) < 1e-12, "pose %d: %g", p, after[p]);
		ck_assert_rel(before[p] + G0, nb, 1e-14);
	}
	ck_assert_int_eq(sscope_calib_pose_errors((const double *const *)x, 1, iv, 3,
						  &id, G0, false, before, after), 0);
	ck_assert(before[0] == 0);
	for (int i = 0; i < 3; i++)
		free(x[i]);
	gsl_rng_free(r);
}
END_TEST

/* The motion summary is the rms and maximum of
 * sscope_calib_gyro_motion_errors() for the triad and for its bias alone
 * at the nominal scale. */
START_TEST(test_motion_summary)
{
	struct sscope_calib_triad ca, cg, bias_only;
	struct sscope_calib_interval iv[16];
	struct sscope_calib_motion ms;
	struct series s;
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
	double after[15], before[15], ang[15], want = 2 * PI / 16 * (1 - 1 / 1.02);
	size_t ns = 300, nm = 150, h = 50;

	sscope_calib_triad_identity(&ca);
	sscope_calib_triad_identity(&cg);
	cg.scale[0] = 1.02;
	cg.bias[0] = 0.01;
	bias_only = ca;
	bias_only.bias[0] = 0.01;
	gsl_rng_set(r, 5);
	make_series(r, 16, 100, 3, 1.5, &ca, 0, &cg, 0, 1, &s);
	for (size_t p = 0; p < 16; p++) {
		iv[p].start = p * (ns + nm) + (p ? h : 0);
		iv[p].end = p * (ns + nm) + ns - h;
	}
	{
		const double *g[3] = { s.w, s.w + 1, s.w + 2 };
		const double *a[3] = { s.f, s.f + 1, s.f + 2 };

		ck_assert_int_eq(sscope_calib_motion_summary(g, a, 3, s.n, 100, iv, 16,
							     &cg, true, after, before,
							     &ms), 0);
		ck_assert_uint_eq(ms.motions, 15);
		ck_assert(ms.rms_rad < 1e-6 && ms.max_rad < 1e-6);
		/* nominal scale 1: the bias-only error of the true triad */
		ck_assert_rel(ms.rms_bias_only_rad, want, 1e-4);
		ck_assert_int_eq(sscope_calib_gyro_motion_errors(g, a, 3, s.n, 100, iv,
								 16, &bias_only, ang), 0);
		for (int k = 0; k < 15; k++)
			ck_assert(before[k] == ang[k]);
		ck_assert_int_eq(sscope_calib_motion_summary(g, a, 3, s.n, 100, iv, 1,
							     &cg, true, after, before,
							     &ms), -EINVAL);
	}
	free_series(&s);
	gsl_rng_free(r);
}
END_TEST

/* Rate-table steps: levels held 3 s with a settling transient, the table
 * driving the sensor's y axis; the steps' means, the axis found. */
START_TEST(test_rate_table_steps)
{
	enum { L = 7, HOLD = 300, N = L * HOLD };
	const double lv[L] = { -1.5, -1, -0.5, 0, 0.5, 1, 1.5 };
	double *ref = malloc(N * sizeof(double)), *y[3], ym[16][3], rm[16][3];
	const double *rf[3] = { ref, NULL, NULL };
	struct sscope_calib_interval seg[16];
	size_t ns;

	for (int i = 0; i < 3; i++)
		y[i] = malloc(N * sizeof(double));
	for (size_t k = 0; k < N; k++) {
		size_t l = k / HOLD, in = k % HOLD;

		ref[k] = lv[l];
		/* the table overshoots for 0.2 s after each change */
		y[1][k] = 0.01 + 0.997 * lv[l] + (l && in < 20 ? 0.3 : 0);
		y[0][k] = 0.002 * lv[l] - 0.004;
		y[2][k] = -0.001 * lv[l];
	}
	ck_assert_int_eq(sscope_calib_rate_table_steps((const double *const *)y, rf,
						       1, 1, N, 100, 0.5, seg, 16, ym,
						       rm, &ns), 0);
	ck_assert_uint_eq(ns, L);
	for (size_t k = 0; k < ns; k++) {
		ck_assert_uint_eq(seg[k].start, k * HOLD + 50); /* settled */
		ck_assert_rel(ym[k][1], 0.01 + 0.997 * lv[k], 1e-12);
		ck_assert(rm[k][0] == lv[k] && rm[k][1] == 0 && rm[k][2] == 0);
	}
	ck_assert_int_eq(sscope_calib_table_axis((const double(*)[3])ym,
						 (const double(*)[3])rm, ns), 1);
	/* one level only: fewer than two steps */
	ck_assert_int_eq(sscope_calib_rate_table_steps((const double *const *)y, rf,
						       1, 1, HOLD, 100, 0.5, seg, 16,
						       ym, rm, &ns), -EDOM);
	ck_assert_uint_eq(ns, 1);
	ck_assert_int_eq(sscope_calib_rate_table_steps((const double *const *)y, rf,
						       2, 1, N, 100, 0.5, seg, 16, ym,
						       rm, &ns), -EINVAL);
	for (int i = 0; i < 3; i++)
		free(y[i]);
	free(ref);
}
END_TEST

/* An interval table sampled on a time column and on a rate. */
START_TEST(test_intervals_sample)
{
	const double rows[] = { 0.5, 1.5, 10, -1, 2, 3, 20, -2 };
	double t[5] = { 100, 100.4, 100.5, 101.49, 102.9 }, a[5], b[5];
	double *out[2] = { a, b };

	ck_assert_int_eq(sscope_timing_intervals_sample(t, 0, 5, rows, 2, 2, out), 0);
	ck_assert(isnan(a[0]) && isnan(b[1]));
	ck_assert(a[2] == 10 && b[2] == -1 && a[3] == 10);
	ck_assert(a[4] == 20 && b[4] == -2);
	ck_assert_int_eq(sscope_timing_intervals_sample(NULL, 2, 5, rows, 2, 2, out), 0);
	/* t = 0, 0.5, 1, 1.5, 2 */
	ck_assert(isnan(a[0]) && a[1] == 10 && a[2] == 10 && isnan(a[3]) && a[4] == 20);
	ck_assert_int_eq(sscope_timing_intervals_sample(NULL, 0, 5, rows, 2, 2, out), -EINVAL);
	ck_assert_int_eq(sscope_timing_intervals_sample(t, 0, 5, rows, 2, 0, out), -EINVAL);
}
END_TEST

static int cmp_dbl(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return x < y ? -1 : x > y;
}

/* the deciles of a sliding variance are the order statistics a sort gives,
 * by whichever path they are found (the one-pass brackets of a long
 * record, or selection when a bracket misses: ties, sorted data) */
START_TEST(deciles_exact)
{
	const size_t n = 400000;
	double *v = malloc(n * sizeof(double)), *w = malloc(n * sizeof(double));
	double *sorted = malloc(n * sizeof(double));
	gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);

	ck_assert(v && w && sorted && r);
	gsl_rng_set(r, 2385);
	for (int kind = 0; kind < 6; kind++) {
		size_t nf = 0;
		double p10, p90;

		for (size_t i = 0; i < n; i++) {
			double x = gsl_ran_gamma(r, 2.385, 1.0);

			v[i] = kind == 1 ? round(x * 4) / 4 : /* many ties */
			       kind == 2 ? (double)i : /* sorted */
			       kind == 3 ? (double)(n - i) :
			       kind == 4 ? 2.385 : /* constant */
			       x;
			if (kind == 5 && i % 7 == 0)
				v[i] = i % 2 ? (double)NAN : (double)INFINITY;
		}
		for (size_t i = 0; i < n; i++)
			if (isfinite(v[i]))
				sorted[nf++] = v[i];
		qsort(sorted, nf, sizeof(double), cmp_dbl);
		ck_assert_int_eq(ssc_calib_vs_deciles(v, n, w, 10, &p10, &p90), 0);
		ck_assert_msg(p10 == sorted[(nf - 1) / 10], "kind %d: p10", kind);
		ck_assert_msg(p90 == sorted[(nf - 1) * 9 / 10], "kind %d: p90", kind);
		ck_assert_int_eq(ssc_calib_vs_deciles(v, n, w, 10, &p10, NULL), 0);
		ck_assert(p10 == sorted[(nf - 1) / 10]);
	}
	gsl_rng_free(r);
	free(v);
	free(w);
	free(sorted);
}
END_TEST


static Suite *make_suite(void)
{
	Suite *s = suite_create("calib");
	TCase *tc = tcase_create("core");

	tcase_set_timeout(tc, 300);
	tcase_add_test(tc, test_variance_magnitude);
	tcase_add_test(tc, test_intervals);
	tcase_add_test(tc, test_accel_fit_coverage);
	tcase_add_test(tc, test_accel_fit_errors);
	tcase_add_test(tc, test_accel_multipos_series);
	tcase_add_test(tc, test_gyro_fit_coverage);
	tcase_add_test(tc, test_gyro_fit_counts);
	tcase_add_test(tc, test_gyro_fit_errors);
	tcase_add_test(tc, test_gyro_motion_errors);
	tcase_add_test(tc, test_gsens);
	tcase_add_test(tc, test_rate_table_cubic);
	tcase_add_test(tc, test_sixpos_and_apply);
	tcase_add_test(tc, test_grades);
	tcase_add_test(tc, test_sixpos_run);
	tcase_add_test(tc, test_gsens_run);
	tcase_add_test(tc, test_error_model_and_grade);
	tcase_add_test(tc, test_pose_errors);
	tcase_add_test(tc, test_motion_summary);
	tcase_add_test(tc, test_rate_table_steps);
	tcase_add_test(tc, test_intervals_sample);
	tcase_add_test(tc, deciles_exact);
	suite_add_tcase(s, tc);
	return s;
}
