/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Strapdown navigation error simulator (see sscope-navsim.h): the
 * reference trajectory computed through ECEF (Groves 2013, ch. 2 and 5:
 * the Coriolis theorem in the form f = C_e^n (r'' + 2 Omega x r') - g),
 * perfect increments by three-point Gauss-Legendre quadrature, sensor
 * errors from the library's noise simulator (analysis/sim.c), the
 * mechanisation of analysis/strapdown.c, and Monte-Carlo statistics over
 * runs computed in parallel (one run per OpenMP task; a run depends only
 * on the seed and its index).
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_spline.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "sscope-adc.h"
#include "sscope-nav.h"
#include "sscope-navsim.h"
#include "sscope-sim.h"
#include "sscope-strapdown.h"
#include "sscope-budget.h"
#include "sscope-sensor.h"

/* samples simulated per block of a run */
#define BLOCK 1024

static const char *const comp_names[SSCOPE_NAVSIM_N_COMP] = {
	"north", "east", "down", "v_north", "v_east", "v_down",
	"roll", "pitch", "yaw"
};

const char *sscope_navsim_comp_name(enum sscope_navsim_comp c)
{
	return (unsigned)c < SSCOPE_NAVSIM_N_COMP ? comp_names[c] : NULL;
}

const char *sscope_navsim_mech_name(enum sscope_navsim_mech m)
{
	return m == SSCOPE_NAVSIM_STRAPDOWN ? "strapdown" :
	       m == SSCOPE_NAVSIM_GIMBALLED ? "gimballed" : NULL;
}

struct sscope_navsim {
	double fs, dt;
	size_t n_samp, n_nav, out_every, n_out;
	double *incr;        /* n_samp x 6 (dtheta, dv), or one row */
	size_t incr_stride;  /* 6, or 0 when every sample is the same */
	double *aid;         /* (n_nav + 1) x 2 (height, v_down), or one row */
	size_t aid_stride;
	bool free_vertical;
	enum sscope_navsim_mech mech;
	unsigned threads;
	void (*progress)(void *ctx, size_t done, size_t total);
	void *progress_ctx;
	struct sscope_navsim_pose *truth; /* n_out */
};

/* ------------------------------------------------------------ trajectory */

struct traj {
	const struct sscope_navsim_opts *o;
	struct sscope_nav_ltp ltp;
	double Cbt0[3][3];   /* STATIC, STRAIGHT: C_b^t at the start */
	double rho;          /* STRAIGHT: radius of the great circle */
	double t0;           /* TABLE: time of the first row */
	gsl_spline *sp[6];   /* TABLE: n, e, d, roll, pitch, unwrapped yaw */
};

/* tangent-plane position and its derivatives, Euler angles and rates */
static void motion_at(const struct traj *tr, double t, double x[3],
		      double xd[3], double xdd[3], double e[3], double ed[3])
{
	const struct sscope_navsim_opts *o = tr->o;

	memset(x, 0, 3 * sizeof(double));
	memset(xd, 0, 3 * sizeof(double));
	memset(xdd, 0, 3 * sizeof(double));
	memset(ed, 0, 3 * sizeof(double));
	e[0] = o->roll_rad;
	e[1] = o->pitch_rad;
	e[2] = o->yaw_rad;
	switch (o->motion) {
	case SSCOPE_NAVSIM_STRAIGHT: {
		double v = o->speed_m_s, th = v * t / tr->rho;
		double cy = cos(o->yaw_rad), sy = sin(o->yaw_rad);
		double xh = tr->rho * sin(th), vh = v * cos(th);
		double ah = -v * v / tr->rho * sin(th);

		x[0] = xh * cy;
		x[1] = xh * sy;
		/* rho (1 - cos th) without cancellation */
		x[2] = 2 * tr->rho * sin(th / 2) * sin(th / 2);
		xd[0] = vh * cy;
		xd[1] = vh * sy;
		xd[2] = v * sin(th);
		xdd[0] = ah * cy;
		xdd[1] = ah * sy;
		xdd[2] = v * v / tr->rho * cos(th);
		break;
	}
	case SSCOPE_NAVSIM_TURN: {
		double r = o->turn_rate_rad_s, v = o->speed_m_s;
		double y = o->yaw_rad + r * t, y0 = o->yaw_rad;

		e[2] = y;
		ed[2] = r;
		if (v > 0) {
			x[0] = v / r * (sin(y) - sin(y0));
			x[1] = -v / r * (cos(y) - cos(y0));
			xd[0] = v * cos(y);
			xd[1] = v * sin(y);
			xdd[0] = -v * r * sin(y);
			xdd[1] = v * r * cos(y);
		}
		break;
	}
	case SSCOPE_NAVSIM_TABLE: {
		double tt = tr->t0 + t;

		for (int i = 0; i < 3; i++) {
			x[i] = gsl_spline_eval(tr->sp[i], tt, NULL);
			xd[i] = gsl_spline_eval_deriv(tr->sp[i], tt, NULL);
			xdd[i] = gsl_spline_eval_deriv2(tr->sp[i], tt, NULL);
			e[i] = gsl_spline_eval(tr->sp[3 + i], tt, NULL);
			ed[i] = gsl_spline_eval_deriv(tr->sp[3 + i], tt, NULL);
		}
		break;
	}
	default:
		break;
	}
}

/* the true state and what a perfect IMU senses at time t */
struct tp {
	double lat, lon, h, v[3], e[3];
	double w_b[3]; /* omega_ib^b, rad/s */
	double f_b[3]; /* specific force, body, m/s^2 */
};

static void mv(const double M[3][3], const double x[3], double y[3])
{
	for (int i = 0; i < 3; i++)
		y[i] = M[i][0] * x[0] + M[i][1] * x[1] + M[i][2] * x[2];
}

static void mtv(const double M[3][3], const double x[3], double y[3])
{
	for (int i = 0; i < 3; i++)
		y[i] = M[0][i] * x[0] + M[1][i] * x[1] + M[2][i] * x[2];
}

static void cross3(const double a[3], const double b[3], double c[3])
{
	c[0] = a[1] * b[2] - a[2] * b[1];
	c[1] = a[2] * b[0] - a[0] * b[2];
	c[2] = a[0] * b[1] - a[1] * b[0];
}

static double det3(const double a[3], const double b[3], const double c[3])
{
	return a[0] * (b[1] * c[2] - b[2] * c[1]) -
	       b[0] * (a[1] * c[2] - a[2] * c[1]) +
	       c[0] * (a[1] * b[2] - a[2] * b[1]);
}

/*
 * At rest and on the great circle the attitude is fixed to the route: the
 * body turns with the circle about its axis k = d0 x h0 (the right-hand
 * horizontal of the start heading) at v / rho, so C_b^e and
 * omega_ib^b = C_t^b k v / rho + C_e^b omega_ie come from the Earth-fixed
 * tangent frame without latitude or longitude rates: valid over a pole.
 */
static void truth_ecef(const struct traj *tr, double t, const double rd[3],
		       const double rdd[3], const double Cen[3][3], struct tp *p)
{
	const struct sscope_navsim_opts *o = tr->o;
	double th = 0, thd = 0, k[3] = { -sin(o->yaw_rad), cos(o->yaw_rad), 0 };
	double R[3][3], Cbt[3][3], Cbn[3][3], Cbe[3][3], q[4], rv[3];
	double fe[3], fn[3], we[3] = { 0, 0, SSCOPE_NAV_WGS84_OMEGA }, wn[3];

	if (o->motion == SSCOPE_NAVSIM_STRAIGHT) {
		thd = o->speed_m_s / tr->rho;
		th = thd * t;
	}
	for (int i = 0; i < 3; i++)
		rv[i] = k[i] * th;
	sscope_nav_quat_from_rotvec(rv, q);
	sscope_nav_dcm_from_quat(q, R);
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			Cbt[i][j] = R[i][0] * tr->Cbt0[0][j] + R[i][1] * tr->Cbt0[1][j] +
				    R[i][2] * tr->Cbt0[2][j];
	/* C_b^e = C_t^e C_b^t (ltp.C is C_e^t), C_b^n = C_e^n C_b^e */
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			Cbe[i][j] = tr->ltp.C[0][i] * Cbt[0][j] + tr->ltp.C[1][i] * Cbt[1][j] +
				    tr->ltp.C[2][i] * Cbt[2][j];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			Cbn[i][j] = Cen[i][0] * Cbe[0][j] + Cen[i][1] * Cbe[1][j] +
				    Cen[i][2] * Cbe[2][j];
	sscope_nav_euler_from_dcm(Cbn, &p->e[0], &p->e[1], &p->e[2]);
	fe[0] = rdd[0] - 2 * SSCOPE_NAV_WGS84_OMEGA * rd[1];
	fe[1] = rdd[1] + 2 * SSCOPE_NAV_WGS84_OMEGA * rd[0];
	fe[2] = rdd[2];
	mv(Cen, fe, fn);
	fn[2] -= sscope_nav_gravity(p->lat, p->h);
	mtv(Cbn, fn, p->f_b);
	mv(Cen, we, wn);
	mtv(Cbn, wn, p->w_b);
	mtv(Cbt, k, rv);
	for (int i = 0; i < 3; i++)
		p->w_b[i] += rv[i] * thd;
}

static void truth_at(const struct traj *tr, double t, struct tp *p)
{
	const struct sscope_nav_wgs84 *w = sscope_nav_wgs84();
	double x[3], xd[3], xdd[3], ed[3], r[3], rd[3], rdd[3], Cen[3][3];
	double Cbn[3][3], fe[3], fn[3], win[3], wb[3];
	struct sscope_nav_geodetic g;

	motion_at(tr, t, x, xd, xdd, p->e, ed);
	sscope_nav_ltp_to_ecef(&tr->ltp, x, r);
	mtv(tr->ltp.C, xd, rd);
	mtv(tr->ltp.C, xdd, rdd);
	sscope_nav_ecef_to_geodetic(r, &g);
	p->lat = g.lat_rad;
	p->lon = g.lon_rad;
	p->h = g.height_m;
	sscope_nav_dcm_ecef_to_ned(g.lat_rad, g.lon_rad, Cen);
	mv(Cen, rd, p->v);
	if (tr->o->motion == SSCOPE_NAVSIM_STATIC ||
	    tr->o->motion == SSCOPE_NAVSIM_STRAIGHT) {
		truth_ecef(tr, t, rd, rdd, Cen, p);
		return;
	}
	/* f = C_e^n (r'' + 2 Omega x r') - g^n */
	fe[0] = rdd[0] - 2 * SSCOPE_NAV_WGS84_OMEGA * rd[1];
	fe[1] = rdd[1] + 2 * SSCOPE_NAV_WGS84_OMEGA * rd[0];
	fe[2] = rdd[2];
	mv(Cen, fe, fn);
	fn[2] -= sscope_nav_gravity(g.lat_rad, g.height_m);
	/* latitude, longitude and height rates from the Jacobian of the
	 * geodetic-to-ECEF map, J (lat', lon', h') = r' (Cramer's rule) */
	{
		double s = sin(g.lat_rad), c = cos(g.lat_rad);
		double sl = sin(g.lon_rad), cl = cos(g.lon_rad);
		double q = 1 - w->e2 * s * s, N = w->a / sqrt(q);
		double dN = N * w->e2 * s * c / q, h = g.height_m;
		double jp[3] = { (dN * c - (N + h) * s) * cl,
				 (dN * c - (N + h) * s) * sl,
				 dN * (1 - w->e2) * s + (N * (1 - w->e2) + h) * c };
		double jl[3] = { -(N + h) * c * sl, (N + h) * c * cl, 0 };
		double jh[3] = { c * cl, c * sl, s };
		double D = det3(jp, jl, jh);
		double latd = det3(rd, jl, jh) / D, lond = det3(jp, rd, jh) / D;
		double wie_e[3] = { 0, 0, SSCOPE_NAV_WGS84_OMEGA }, wie[3];

		/* omega_in = omega_ie + omega_en; omega_en from the rates */
		mv(Cen, wie_e, wie);
		win[0] = wie[0] + lond * c;
		win[1] = wie[1] - latd;
		win[2] = wie[2] - lond * s;
	}
	sscope_nav_dcm_from_euler(p->e[0], p->e[1], p->e[2], Cbn);
	mtv(Cbn, win, wb);
	mtv(Cbn, fn, p->f_b);
	{
		/* omega_nb^b from the Euler rates (Z-Y-X) */
		double sr = sin(p->e[0]), cr = cos(p->e[0]);
		double sp = sin(p->e[1]), cp = cos(p->e[1]);

		p->w_b[0] = wb[0] + ed[0] - ed[2] * sp;
		p->w_b[1] = wb[1] + ed[1] * cr + ed[2] * sr * cp;
		p->w_b[2] = wb[2] - ed[1] * sr + ed[2] * cr * cp;
	}
}

static void free_traj(struct traj *tr)
{
	for (int i = 0; i < 6; i++)
		if (tr->sp[i])
			gsl_spline_free(tr->sp[i]);
}

static int table_init(struct traj *tr, const struct sscope_navsim_opts *o,
		      struct sscope_diag *diag)
{
	size_t n = o->n_table;
	double *y = NULL;
	int rc = 0;

	if (!o->table_t_s || !o->table_ned_m || !o->table_euler_rad)
		return ssc_diag(diag, -EINVAL, "table without data");
	if (n < 3)
		return ssc_diag(diag, -EINVAL,
				"a trajectory table needs at least 3 rows (has %zu)",
				n);
	for (size_t i = 0; i < n; i++) {
		if (!isfinite(o->table_t_s[i]))
			return ssc_diag(diag, -EINVAL, "table row %zu: time is not finite",
					i + 1);
		if (i && !(o->table_t_s[i] > o->table_t_s[i - 1]))
			return ssc_diag(diag, -EINVAL,
					"table row %zu: time does not increase",
					i + 1);
		for (int k = 0; k < 3; k++)
			if (!isfinite(o->table_ned_m[i][k]) ||
			    !isfinite(o->table_euler_rad[i][k]))
				return ssc_diag(diag, -EINVAL,
						"table row %zu: a non-finite value",
						i + 1);
		if (fabs(o->table_euler_rad[i][1]) >= 89 * PI / 180)
			return ssc_diag(diag, -EINVAL,
					"table row %zu: pitch of 89 degrees or more (Euler angles are singular at 90)",
					i + 1);
	}
	y = ssc_alloc_array(n, sizeof(double));
	if (!y)
		return -ENOMEM;
	tr->t0 = o->table_t_s[0];
	for (int k = 0; k < 6 && !rc; k++) {
		for (size_t i = 0; i < n; i++) {
			double v = k < 3 ? o->table_ned_m[i][k] :
					   o->table_euler_rad[i][k - 3];

			/* unwrap angles: steps of at most pi between rows */
			if (k >= 3 && i > 0)
				v = y[i - 1] + remainder(v - y[i - 1], 2 * PI);
			y[i] = v;
		}
		tr->sp[k] = gsl_spline_alloc(gsl_interp_cspline, n);
		if (!tr->sp[k] || gsl_spline_init(tr->sp[k], o->table_t_s, y, n))
			rc = -ENOMEM;
	}
	free(y);
	return rc;
}

static unsigned n_threads(unsigned req)
{
#ifdef _OPENMP
	int t = req ? (int)req : omp_get_max_threads();

	return t < 1 ? 1 : (unsigned)t;
#else
	(void)req;
	return 1;
#endif
}

void sscope_navsim_free(struct sscope_navsim *ns)
{
	if (!ns)
		return;
	free(ns->incr);
	free(ns->aid);
	free(ns->truth);
	free(ns);
}

int sscope_navsim_set_mechanisation(struct sscope_navsim *ns,
				    enum sscope_navsim_mech m)
{
	if (!ns || !sscope_navsim_mech_name(m))
		return -EINVAL;
	ns->mech = m;
	return 0;
}

size_t sscope_navsim_n_out(const struct sscope_navsim *ns)
{
	return ns->n_out;
}

double sscope_navsim_time(const struct sscope_navsim *ns, size_t k)
{
	return (double)(k * ns->out_every * 2) * ns->dt;
}

size_t sscope_navsim_n_samples(const struct sscope_navsim *ns)
{
	return ns->n_samp;
}

int sscope_navsim_truth(const struct sscope_navsim *ns, size_t k,
			struct sscope_navsim_pose *p)
{
	if (!ns || !p || k >= ns->n_out)
		return -EINVAL;
	*p = ns->truth[k];
	return 0;
}

static void to_pose(const struct tp *t, struct sscope_navsim_pose *p)
{
	p->pos.lat_rad = t->lat;
	p->pos.lon_rad = t->lon;
	p->pos.height_m = t->h;
	memcpy(p->v_ned_m_s, t->v, sizeof(t->v));
	for (int i = 0; i < 3; i++)
		p->euler_rad[i] = remainder(t->e[i], 2 * PI);
}

int sscope_navsim_new(struct sscope_navsim **nsp,
		      const struct sscope_navsim_opts *o,
		      struct sscope_diag *diag)
{
	struct traj tr = { 0 };
	struct sscope_navsim *ns;
	double dur;
	size_t n2, nrow;
	bool still;
	int rc;
	unsigned T;

	if (!nsp)
		return -EINVAL;
	*nsp = NULL;
	if (!o)
		return ssc_diag(diag, -EINVAL, "no options");
	if (!(o->rate_hz > 0) || !isfinite(o->rate_hz))
		return ssc_diag(diag, -EINVAL, "the rate must be positive");
	if (o->motion != SSCOPE_NAVSIM_TABLE &&
	    (!(o->duration_s > 0) || !isfinite(o->duration_s)))
		return ssc_diag(diag, -EINVAL, "the duration must be positive");
	if (!isfinite(o->start.lat_rad) || !isfinite(o->start.lon_rad) ||
	    !isfinite(o->start.height_m) || !(fabs(o->start.lat_rad) <= PI / 2))
		return ssc_diag(diag, -EINVAL, "the start latitude must be within +-90 degrees");
	if ((o->motion == SSCOPE_NAVSIM_TURN || o->motion == SSCOPE_NAVSIM_TABLE) &&
	    fabs(o->start.lat_rad) >= 89.9 * PI / 180)
		return ssc_diag(diag, -EINVAL,
				"a turn or a table gives the attitude relative to north: the start latitude must be within +-89.9 degrees");
	if ((unsigned)o->mechanisation > SSCOPE_NAVSIM_GIMBALLED)
		return ssc_diag(diag, -EINVAL, "unknown mechanisation");
	if (!isfinite(o->roll_rad) || !isfinite(o->pitch_rad) ||
	    !isfinite(o->yaw_rad) || fabs(o->pitch_rad) >= 89 * PI / 180)
		return ssc_diag(diag, -EINVAL,
				"bad start attitude (|pitch| must be below 89 degrees)");
	if (!(o->output_step_s >= 0) || !isfinite(o->output_step_s))
		return ssc_diag(diag, -EINVAL, "bad output step");
	if ((unsigned)o->motion > SSCOPE_NAVSIM_TABLE)
		return ssc_diag(diag, -EINVAL, "unknown motion");
	if (o->motion == SSCOPE_NAVSIM_STRAIGHT &&
	    (!(o->speed_m_s > 0) || !isfinite(o->speed_m_s)))
		return ssc_diag(diag, -EINVAL, "a straight line needs a positive speed");
	if (o->motion == SSCOPE_NAVSIM_TURN &&
	    (!(o->speed_m_s >= 0) || !isfinite(o->speed_m_s) ||
	     o->turn_rate_rad_s == 0 || !isfinite(o->turn_rate_rad_s)))
		return ssc_diag(diag, -EINVAL,
				"a turn needs a non-zero turn rate and a speed >= 0");
	tr.o = o;
	sscope_nav_dcm_from_euler(o->roll_rad, o->pitch_rad, o->yaw_rad, tr.Cbt0);
	rc = sscope_nav_ltp_init(&tr.ltp, &o->start);
	if (rc)
		return ssc_diag(diag, rc, "bad start point");
	{
		double rn, re;

		sscope_nav_radii(o->start.lat_rad, &rn, &re);
		tr.rho = sqrt(rn * re) + o->start.height_m;
	}
	dur = o->duration_s;
	if (o->motion == SSCOPE_NAVSIM_TABLE) {
		double span;

		rc = table_init(&tr, o, diag);
		if (rc) {
			free_traj(&tr);
			return rc;
		}
		span = o->table_t_s[o->n_table - 1] - o->table_t_s[0];
		if (!(dur > 0) || dur > span)
			dur = span;
	}
	if (!(dur * o->rate_hz < 4e15)) {
		free_traj(&tr);
		return ssc_diag(diag, -ERANGE, "too many samples");
	}
	n2 = ssc_count(floor(dur * o->rate_hz / 2 + 1e-9));
	if (n2 < 1) {
		free_traj(&tr);
		return ssc_diag(diag, -EDOM,
				"%g s at %g Hz is shorter than two samples",
				dur, o->rate_hz);
	}
	ns = calloc(1, sizeof(*ns));
	if (!ns) {
		free_traj(&tr);
		return -ENOMEM;
	}
	ns->fs = o->rate_hz;
	ns->dt = 1 / o->rate_hz;
	ns->n_nav = n2;
	ns->n_samp = 2 * n2;
	ns->free_vertical = o->free_vertical;
	ns->mech = o->mechanisation;
	ns->threads = o->threads;
	ns->progress = o->progress;
	ns->progress_ctx = o->progress_ctx;
	if (o->output_step_s > 0)
		ns->out_every = ssc_count(fmax(1, round(o->output_step_s / (2 * ns->dt))));
	else
		ns->out_every = ssc_count(fmax(1, round((double)n2 / 600)));
	if (ns->out_every > n2)
		ns->out_every = n2;
	ns->n_out = n2 / ns->out_every + 1;
	still = o->motion == SSCOPE_NAVSIM_STATIC;
	ns->incr_stride = still ? 0 : 6;
	ns->aid_stride = still ? 0 : 2;
	nrow = still ? 1 : ns->n_samp;
	ns->incr = ssc_alloc_array(nrow, 6 * sizeof(double));
	ns->aid = ssc_alloc_array(still ? 1 : n2 + 1, 2 * sizeof(double));
	ns->truth = ssc_alloc_array(ns->n_out, sizeof(*ns->truth));
	if (!ns->incr || !ns->aid || !ns->truth) {
		free_traj(&tr);
		sscope_navsim_free(ns);
		return -ENOMEM;
	}
	T = n_threads(o->threads);
	{
		/* Gauss-Legendre nodes and weights on [-1, 1] */
		const double gx[3] = { -sqrt(0.6), 0, sqrt(0.6) };
		const double gw[3] = { 5.0 / 9, 8.0 / 9, 5.0 / 9 };
		const double dt = ns->dt;
		double *incr = ns->incr;

SSC_OMP(omp parallel for num_threads(T) schedule(static))
		for (size_t i = 0; i < nrow; i++) {
			double a[6] = { 0 };

			for (int q = 0; q < 3; q++) {
				struct tp p;

				truth_at(&tr, ((double)i + 0.5 * (1 + gx[q])) * dt, &p);
				for (int k = 0; k < 3; k++) {
					a[k] += 0.5 * dt * gw[q] * p.w_b[k];
					a[3 + k] += 0.5 * dt * gw[q] * p.f_b[k];
				}
			}
			memcpy(incr + 6 * i, a, sizeof(a));
		}
	}
	{
		size_t na = still ? 1 : n2 + 1;
		double *aid = ns->aid;
		const double Tn = 2 * ns->dt;

SSC_OMP(omp parallel for num_threads(T) schedule(static))
		for (size_t j = 0; j < na; j++) {
			struct tp p;

			truth_at(&tr, (double)j * Tn, &p);
			aid[2 * j] = p.h;
			aid[2 * j + 1] = p.v[2];
		}
	}
	for (size_t k = 0; k < ns->n_out; k++) {
		struct tp p;

		truth_at(&tr, sscope_navsim_time(ns, k), &p);
		to_pose(&p, &ns->truth[k]);
	}
	free_traj(&tr);
	*nsp = ns;
	return 0;
}

/* ------------------------------------------------------------ runs */

static bool spec_ok(const struct sscope_sensor_spec *s)
{
	double v[] = { s->q, s->n, s->b, s->k, s->r, s->bias,
		       s->scale_factor_error };

	for (size_t i = 0; i < sizeof(v) / sizeof(v[0]); i++)
		if (!(v[i] >= 0) || !isfinite(v[i]))
			return false;
	return !(s->has & SSCOPE_SENSOR_HAS_RANGE) || s->range > 0;
}

static bool has_noise(const struct sscope_sensor_spec *s)
{
	return s->q > 0 || s->n > 0 || s->b > 0 || s->k > 0 || s->r > 0 ||
	       (s->has & SSCOPE_SENSOR_HAS_RANGE);
}

/* errors of a state against record k */
static void record(const struct sscope_navsim *ns, size_t k,
		   const struct sscope_strapdown_wander *w, double *e)
{
	const struct sscope_navsim_pose *t = &ns->truth[k];
	const double polar = 89.9 * PI / 180;
	struct sscope_strapdown_state s;
	struct sscope_nav_geodetic g;
	double Cen[3][3], r_est[3], r_true[3], d[3], eu[3];

	sscope_strapdown_wander_to_ned(w, &s);
	/* position: the ECEF difference in the true local level (north and
	 * east), the height difference (down) */
	g.lat_rad = s.lat_rad;
	g.lon_rad = s.lon_rad;
	g.height_m = s.height_m;
	sscope_nav_dcm_ecef_to_ned(t->pos.lat_rad, t->pos.lon_rad, Cen);
	sscope_nav_geodetic_to_ecef(&g, r_est);
	sscope_nav_geodetic_to_ecef(&t->pos, r_true);
	for (int i = 0; i < 3; i++)
		d[i] = r_est[i] - r_true[i];
	mv(Cen, d, e);
	{
		/* the horizontal part as long as the arc between the two
		 * points (the chord's projection falls short of it by
		 * d^3 / (6 R^2) and more for errors of hundreds of km) */
		double c[3], hz = hypot(e[0], e[1]), rt = 0, ang;

		cross3(r_est, r_true, c);
		ang = atan2(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
			    r_est[0] * r_true[0] + r_est[1] * r_true[1] +
			    r_est[2] * r_true[2]);
		for (int i = 0; i < 3; i++)
			rt += r_true[i] * r_true[i];
		if (hz > 0) {
			e[0] *= ang * sqrt(rt) / hz;
			e[1] *= ang * sqrt(rt) / hz;
		}
	}
	e[SSCOPE_NAVSIM_DOWN] = -(s.height_m - t->pos.height_m);
	if (fabs(t->pos.lat_rad) >= polar || fabs(s.lat_rad) >= polar) {
		/* north is undefined at one of them: velocity and attitude
		 * in the true local level */
		double Cwe[3][3], Cbw[3][3], Cbn[3][3], ve[3];

		sscope_strapdown_wander_position(w, NULL, NULL, NULL, Cwe);
		mv(Cwe, w->v_w_m_s, ve);
		mv(Cen, ve, d);
		for (int i = 0; i < 3; i++)
			e[SSCOPE_NAVSIM_VN + i] = d[i] - t->v_ned_m_s[i];
		sscope_nav_dcm_from_quat(w->q_bw, Cbw);
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++) {
				double x = 0;

				for (int l = 0; l < 3; l++)
					x += (Cen[i][0] * Cwe[0][l] + Cen[i][1] * Cwe[1][l] +
					      Cen[i][2] * Cwe[2][l]) * Cbw[l][j];
				Cbn[i][j] = x;
			}
		sscope_nav_euler_from_dcm(Cbn, &eu[0], &eu[1], &eu[2]);
	} else {
		for (int i = 0; i < 3; i++)
			e[SSCOPE_NAVSIM_VN + i] = s.v_ned_m_s[i] - t->v_ned_m_s[i];
		sscope_strapdown_euler(&s, &eu[0], &eu[1], &eu[2]);
	}
	for (int i = 0; i < 3; i++)
		e[SSCOPE_NAVSIM_ROLL + i] = remainder(eu[i] - t->euler_rad[i],
						      2 * PI);
}

struct run_ctx {
	struct sscope_sim *sim[7];
	struct sscope_adc *adc[6];
	double *in[6], *out[6];
	bool noisy[2], buffered[2];
	size_t adc_clipped; /* samples clipped by the converters */
};

static void run_ctx_free(struct run_ctx *c)
{
	for (int i = 0; i < 7; i++)
		sscope_sim_free(c->sim[i]);
	for (int i = 0; i < 6; i++) {
		sscope_adc_free(c->adc[i]);
		free(c->in[i]);
		free(c->out[i]);
	}
}

/* seed of the converter of axis ax in run @p run: splitmix64 of both */
static uint64_t adc_seed(uint64_t seed, uint64_t run, int ax)
{
	uint64_t z = seed ^ ((run * 8 + (uint64_t)ax + 1) * 0x9E3779B97F4A7C15u);

	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
	return z ^ (z >> 31);
}

/* The sensors of a run: noise simulators and converters per axis, the
 * error matrices I + M + diag(s) (Mx) and biases b + b_r (bx) of both
 * triads with this run's random constants. */
static int run_setup(const struct sscope_navsim *ns,
		     const struct sscope_navsim_imu *imu, uint64_t seed,
		     uint64_t run, bool gimb, struct run_ctx *c,
		     double Mx[2][3][3], double bx[2][3],
		     struct sscope_diag *diag)
{
	double z[12] = { 0 };
	int rc = 0;

	if (!spec_ok(&imu->gyro) || !spec_ok(&imu->accel))
		return ssc_diag(diag, -EINVAL,
				"noise terms, biases and scale-factor errors must be finite and non-negative");
	for (int i = 0; i < 3; i++) {
		if (!isfinite(imu->gyro_bias_rad_s[i]) ||
		    !isfinite(imu->accel_bias_m_s2[i]))
			return ssc_diag(diag, -EINVAL, "biases must be finite");
		for (int k = 0; k < 3; k++)
			if (!isfinite(imu->gyro_m[i][k]) || !isfinite(imu->accel_m[i][k]))
				return ssc_diag(diag, -EINVAL,
						"error matrices must be finite");
	}
	if (gimb && (imu->gyro_adc || imu->accel_adc))
		return ssc_diag(diag, -EINVAL,
				"converters are not modelled on a gimballed platform");
	c->noisy[0] = has_noise(&imu->gyro);
	c->noisy[1] = has_noise(&imu->accel);
	for (int tri = 0; tri < 2; tri++) {
		const struct sscope_sensor_spec *sp = tri ? &imu->accel : &imu->gyro;
		const struct sscope_adc_spec *as = tri ? imu->accel_adc : imu->gyro_adc;

		c->buffered[tri] = c->noisy[tri] || as;
		if (!c->buffered[tri])
			continue;
		for (int a = 0; a < 3; a++) {
			struct sscope_sensor_spec s = *sp;
			struct sscope_sim_opts so = { 0 };
			int ax = 3 * tri + a;

			s.bias = 0;
			s.scale_factor_error = 0;
			s.bias_tempco = 0;
			if (gimb) /* the platform's sensors: errors only */
				s.has &= ~(unsigned)SSCOPE_SENSOR_HAS_RANGE;
			so.rate_hz = ns->fs;
			so.seed = seed;
			so.stream = run * 8 + (uint64_t)ax;
			if (c->noisy[tri])
				rc = sscope_sim_new(&c->sim[ax], &s, &so, diag);
			if (!rc && as)
				rc = sscope_adc_new(&c->adc[ax], as,
						    as->analog ? sp->sensitivity : 1,
						    as->analog ? sp->zero_output_v : 0,
						    adc_seed(seed, run, ax), diag);
			c->in[ax] = malloc(BLOCK * sizeof(double));
			c->out[ax] = malloc(BLOCK * sizeof(double));
			if (!rc && (!c->in[ax] || !c->out[ax]))
				rc = -ENOMEM;
			if (rc)
				return rc;
		}
	}
	/* random constants of this run: unit normal deviates from the
	 * simulator's white-noise stream (N = 1 at 1 Hz) */
	if (imu->gyro.bias > 0 || imu->gyro.scale_factor_error > 0 ||
	    imu->accel.bias > 0 || imu->accel.scale_factor_error > 0) {
		struct sscope_sensor_spec u = { .n = 1 };
		struct sscope_sim_opts so = { .rate_hz = 1, .seed = seed,
					      .stream = run * 8 + 6 };

		rc = sscope_sim_new(&c->sim[6], &u, &so, diag);
		if (rc)
			return rc;
		sscope_sim_generate(c->sim[6], NULL, z, NULL, 12);
	}
	for (int tri = 0; tri < 2; tri++) {
		const struct sscope_sensor_spec *sp = tri ? &imu->accel : &imu->gyro;
		const double (*M)[3] = tri ? imu->accel_m : imu->gyro_m;
		const double *b = tri ? imu->accel_bias_m_s2 : imu->gyro_bias_rad_s;

		for (int i = 0; i < 3; i++) {
			for (int k = 0; k < 3; k++)
				Mx[tri][i][k] = (i == k) + M[i][k];
			Mx[tri][i][i] += sp->scale_factor_error * z[6 * tri + i];
			bx[tri][i] = b[i] + sp->bias * z[6 * tri + 3 + i];
		}
	}
	return 0;
}

/* The readings of samples s0 .. s0 + nb - 1 as increments (rad, m/s):
 * meas[i][0..2] gyro, [3..5] accelerometer. */
static void run_block(const struct sscope_navsim *ns, struct run_ctx *c,
		      bool gimb, const double Mx[2][3][3],
		      const double bx[2][3], size_t s0, size_t nb,
		      double meas[][6])
{
	const double dt = ns->dt;

	for (size_t i = 0; i < nb; i++) {
		const double *u = ns->incr + (s0 + i) * ns->incr_stride;

		for (int tri = 0; tri < 2; tri++) {
			double y[3];

			if (gimb) /* the platform: errors only */
				memset(y, 0, sizeof(y));
			else
				mv(Mx[tri], u + 3 * tri, y);
			for (int a = 0; a < 3; a++) {
				if (c->buffered[tri])
					c->in[3 * tri + a][i] = y[a] / dt;
				else
					meas[i][3 * tri + a] = y[a] + bx[tri][a] * dt;
			}
		}
	}
	for (int ax = 0; ax < 6; ax++) {
		const double b = bx[ax / 3][ax % 3];

		if (!c->buffered[ax / 3])
			continue;
		if (c->sim[ax])
			sscope_sim_generate(c->sim[ax], c->in[ax], c->out[ax], NULL, nb);
		else
			memcpy(c->out[ax], c->in[ax], nb * sizeof(double));
		if (c->adc[ax]) {
			for (size_t i = 0; i < nb; i++)
				c->out[ax][i] += b;
			sscope_adc_digitize(c->adc[ax], c->out[ax], 1, nb, ns->fs,
					    NULL, c->out[ax], NULL, &c->adc_clipped);
		}
		for (size_t i = 0; i < nb; i++)
			meas[i][ax] = (c->out[ax][i] + (c->adc[ax] ? 0 : b)) * dt;
	}
}

int sscope_navsim_run(const struct sscope_navsim *ns,
		      const struct sscope_navsim_imu *imu, uint64_t seed,
		      uint64_t run, double *err, uint64_t *clipped,
		      struct sscope_diag *diag)
{
	struct run_ctx c = { 0 };
	struct sscope_strapdown_wander st;
	struct sscope_strapdown_platform pe;
	bool gimb = ns && ns->mech == SSCOPE_NAVSIM_GIMBALLED;
	double Mx[2][3][3], bx[2][3];
	const double dt = ns ? ns->dt : 0;
	size_t j = 0;
	int rc = 0;

	if (!ns || !imu || !err)
		return ssc_diag(diag, -EINVAL, "bad parameter");
	rc = run_setup(ns, imu, seed, run, gimb, &c, Mx, bx, diag);
	if (rc)
		goto out;
	for (int tri = 0; tri < 2; tri++)
		for (int i = 0; i < 3; i++)
			for (int k = 0; k < 3; k++)
				(tri ? pe.accel_m : pe.gyro_m)[i][k] = Mx[tri][i][k] - (i == k);
	{
		const struct sscope_navsim_pose *t0 = &ns->truth[0];

		rc = sscope_strapdown_wander_init(&st, t0->pos.lat_rad, t0->pos.lon_rad,
					   t0->pos.height_m, t0->v_ned_m_s,
					   t0->euler_rad[0], t0->euler_rad[1],
					   t0->euler_rad[2]);
		if (rc) {
			rc = ssc_diag(diag, rc, "bad start state");
			goto out;
		}
	}
	record(ns, 0, &st, err);
	for (size_t s0 = 0; s0 < ns->n_samp; s0 += BLOCK) {
		size_t nb = ns->n_samp - s0 < BLOCK ? ns->n_samp - s0 : BLOCK;
		double meas[BLOCK][6];

		run_block(ns, &c, gimb, (const double (*)[3][3])Mx,
			  (const double (*)[3])bx, s0, nb, meas);
		for (size_t i = 0; i + 1 < nb; i += 2) {
			if (gimb) {
				const double *u = ns->incr + (s0 + i) * ns->incr_stride;
				const double *u2 = ns->incr + (s0 + i + 1) * ns->incr_stride;

				for (int a = 0; a < 3; a++) {
					pe.dtheta_rad[a] = meas[i][a] + meas[i + 1][a];
					pe.dv_m_s[a] = meas[i][3 + a] + meas[i + 1][3 + a];
				}
				sscope_strapdown_wander_step2(&st, u, u2, u + 3, u2 + 3, dt, &pe);
			} else {
				sscope_strapdown_wander_step2(&st, meas[i], meas[i + 1], meas[i] + 3,
						    meas[i + 1] + 3, dt, NULL);
			}
			j++;
			if (!ns->free_vertical) {
				const double *a = ns->aid + j * ns->aid_stride;

				st.height_m = a[0];
				st.v_w_m_s[2] = a[1];
			}
			if (j % ns->out_every == 0 && j / ns->out_every < ns->n_out)
				record(ns, j / ns->out_every, &st,
				       err + (j / ns->out_every) * SSCOPE_NAVSIM_N_COMP);
		}
	}
	if (clipped) {
		*clipped = 0;
		for (int ax = 0; ax < 6; ax++)
			if (c.sim[ax])
				*clipped += sscope_sim_clipped(c.sim[ax]);
		*clipped += c.adc_clipped;
	}
out:
	run_ctx_free(&c);
	return rc;
}

int sscope_navsim_readings(const struct sscope_navsim *ns,
			   const struct sscope_navsim_imu *imu, uint64_t seed,
			   uint64_t run, double *out, double bias[6],
			   struct sscope_diag *diag)
{
	struct run_ctx c = { 0 };
	double Mx[2][3][3], bx[2][3];
	int rc;

	if (!ns || !imu || !out)
		return ssc_diag(diag, -EINVAL, "bad parameter");
	rc = run_setup(ns, imu, seed, run, false, &c, Mx, bx, diag);
	if (rc)
		goto out;
	for (size_t s0 = 0; s0 < ns->n_samp; s0 += BLOCK) {
		size_t nb = ns->n_samp - s0 < BLOCK ? ns->n_samp - s0 : BLOCK;
		double meas[BLOCK][6];

		run_block(ns, &c, false, (const double (*)[3][3])Mx,
			  (const double (*)[3])bx, s0, nb, meas);
		for (size_t i = 0; i < nb; i++)
			for (int a = 0; a < 6; a++)
				out[6 * (s0 + i) + (size_t)a] = meas[i][a] * ns->fs;
	}
	if (bias)
		for (int a = 0; a < 6; a++)
			bias[a] = bx[a / 3][a % 3];
out:
	run_ctx_free(&c);
	return rc;
}

/* percentile of sorted x (numpy's linear interpolation) */
/* Monte-Carlo standard error of rms = sqrt(mean x^2) over n runs: the sd
 * of x^2 over sqrt(n), through d rms = d ms / (2 rms); NaN for one run or
 * a zero rms */
static double rms_se(const double *x, size_t n, double rms)
{
	double ms = rms * rms, v = 0;

	if (n < 2 || !(rms > 0))
		return (double)NAN;
	for (size_t r = 0; r < n; r++)
		v += (x[r] * x[r] - ms) * (x[r] * x[r] - ms);
	return sqrt(v / (double)(n - 1) / (double)n) / (2 * rms);
}

static double pct(const double *x, size_t n, double p)
{
	double pos = p * (double)(n - 1);
	size_t lo = (size_t)floor(pos);

	if (lo + 1 >= n)
		return x[n - 1];
	return x[lo] + (pos - (double)lo) * (x[lo + 1] - x[lo]);
}

int sscope_navsim_monte_carlo(const struct sscope_navsim *ns,
			      const struct sscope_navsim_imu *imu, size_t runs,
			      uint64_t seed, struct sscope_navsim_stat *out,
			      double *err_all, uint64_t *clipped,
			      struct sscope_diag *diag)
{
	const size_t NC = SSCOPE_NAVSIM_N_COMP;
	size_t per, total, done = 0;
	double *all;
	uint64_t clip = 0;
	int rc = 0;
	unsigned T;

	if (!ns || !imu || !out || runs == 0)
		return ssc_diag(diag, -EINVAL, "bad parameter (runs must be >= 1)");
	if (!ssc_mul(ns->n_out, NC, &per) || !ssc_mul(per, runs, &total) ||
	    !ssc_mul(total, sizeof(double), &(size_t){ 0 }))
		return ssc_diag(diag, -ERANGE, "%zu runs x %zu records is too large",
				runs, ns->n_out);
	all = err_all ? err_all : ssc_alloc_array(total, sizeof(double));
	if (!all)
		return -ENOMEM;
	T = n_threads(ns->threads);
	if ((size_t)T > runs)
		T = (unsigned)runs;
SSC_OMP(omp parallel for num_threads(T) schedule(dynamic, 1) reduction(+ : clip))
	for (size_t r = 0; r < runs; r++) {
		struct sscope_diag d = { "" };
		uint64_t cl = 0;
		int e = rc ? 0 : sscope_navsim_run(ns, imu, seed, r, all + r * per,
						   &cl, &d);

		clip += cl;
SSC_OMP(omp critical(ssc_navsim_rc))
		{
			if (e && !rc) {
				rc = e;
				if (diag)
					*diag = d;
			}
			done++;
			if (ns->progress)
				ns->progress(ns->progress_ctx, done, runs);
		}
	}
	if (rc)
		goto done;
SSC_OMP(omp parallel num_threads(T))
	{
		double *x = malloc((runs + 1) * sizeof(double));

SSC_OMP(omp for schedule(static))
		for (size_t k = 0; k < ns->n_out; k++) {
			struct sscope_navsim_stat *s = &out[k];

			s->t_s = sscope_navsim_time(ns, k);
			if (!x)
				continue;
			for (size_t c = 0; c < NC; c++) {
				struct ssc_ksum m = { 0, 0 };
				double mean, ss = 0, sq = 0;

				for (size_t r = 0; r < runs; r++) {
					x[r] = all[r * per + k * NC + c];
					ssc_ksum_add(&m, x[r]);
				}
				mean = ssc_ksum_value(&m) / (double)runs;
				for (size_t r = 0; r < runs; r++) {
					ss += (x[r] - mean) * (x[r] - mean);
					sq += x[r] * x[r];
				}
				s->mean[c] = mean;
				s->sd[c] = runs > 1 ? sqrt(ss / (double)(runs - 1)) : (double)NAN;
				s->rms[c] = sqrt(sq / (double)runs);
				s->rms_se[c] = rms_se(x, runs, s->rms[c]);
				qsort(x, runs, sizeof(double), ssc_cmp_double);
				s->p05[c] = pct(x, runs, 0.05);
				s->p50[c] = pct(x, runs, 0.50);
				s->p95[c] = pct(x, runs, 0.95);
			}
			{
				double sq = 0;

				for (size_t r = 0; r < runs; r++) {
					const double *e = all + r * per + k * NC;

					x[r] = hypot(e[SSCOPE_NAVSIM_NORTH],
						     e[SSCOPE_NAVSIM_EAST]);
					sq += x[r] * x[r];
				}
				s->horiz_rms = sqrt(sq / (double)runs);
				s->horiz_rms_se = rms_se(x, runs, s->horiz_rms);
				qsort(x, runs, sizeof(double), ssc_cmp_double);
				s->horiz_p50 = pct(x, runs, 0.50);
				s->horiz_p95 = pct(x, runs, 0.95);
			}
		}
		if (!x) {
SSC_OMP(omp critical(ssc_navsim_rc))
			rc = -ENOMEM;
		}
		free(x);
	}
	if (clipped)
		*clipped = clip;
done:
	if (!err_all)
		free(all);
	return rc;
}

void sscope_navsim_budget(const struct sscope_navsim *ns,
			  const struct sscope_navsim_imu *imu,
			  struct sscope_budget_params *p)
{
	const struct sscope_navsim_pose *t0 = &ns->truth[0];
	double rn, re, gb = 0, ab = 0;

	memset(p, 0, sizeof(*p));
	/* bias instability counts as a 1-sigma bias, as in `budget` */
	for (int i = 0; i < 2; i++) {
		gb = fmax(gb, hypot(hypot(imu->gyro_bias_rad_s[i], imu->gyro.bias),
				    imu->gyro.b));
		ab = fmax(ab, hypot(hypot(imu->accel_bias_m_s2[i], imu->accel.bias),
				    imu->accel.b));
	}
	p->gyro_bias_rad_s = gb;
	p->accel_bias_m_s2 = ab;
	p->arw_rad_sqrt_s = imu->gyro.n;
	p->vrw_m_s_sqrt_s = imu->accel.n;
	/* a converter adds its noise and quantization to the white noise
	 * (as `adc report` computes them), and its offset error and the
	 * bound of the bias a quantizer loses when the noise does not dither
	 * it (Widrow-Kollar, 0 when it does) to the bias */
	for (int tri = 0; tri < 2; tri++) {
		const struct sscope_adc_spec *as = tri ? imu->accel_adc : imu->gyro_adc;
		struct sscope_sensor_spec ss = tri ? imu->accel : imu->gyro;
		struct sscope_adc_spec ac;
		struct sscope_adc_analysis an;
		double off;

		if (!as)
			continue;
		/* what the run uses, whether or not a spec file said it */
		ac = *as;
		if (ac.noise > 0)
			ac.has |= SSCOPE_ADC_HAS_NOISE;
		if (ss.n > 0)
			ss.has |= SSCOPE_SENSOR_HAS_N;
		if (ss.sensitivity > 0)
			ss.has |= SSCOPE_SENSOR_HAS_SENSITIVITY | SSCOPE_SENSOR_HAS_ZERO;
		if (sscope_adc_analyze(&ss, &ac, ns->fs, &an, NULL))
			continue;
		off = hypot(ac.offset / (ac.analog ? ss.sensitivity : 1), an.bias_bound);
		if (tri) {
			p->vrw_m_s_sqrt_s = an.n_total;
			p->accel_bias_m_s2 = hypot(ab, off);
		} else {
			p->arw_rad_sqrt_s = an.n_total;
			p->gyro_bias_rad_s = hypot(gb, off);
		}
	}
	sscope_nav_radii(t0->pos.lat_rad, &rn, &re);
	p->gravity_m_s2 = sscope_nav_gravity(t0->pos.lat_rad, t0->pos.height_m);
	p->radius_m = sqrt(rn * re) + t0->pos.height_m;
	p->model = SSCOPE_BUDGET_SCHULER;
}
