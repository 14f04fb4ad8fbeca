/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Simulated captures with stops for the zero-velocity-aided navigation
 * (tests/test-zupt.c, tests/bench-zupt.c, tests/gen-samples.c): a route
 * of stops and legs as a navsim trajectory table (sscope-navsim.h,
 * TABLE motion), the readings of navsim's sensor model along it
 * (sscope_navsim_readings()), and the true poses at the records.
 *
 * A leg of duration M speeds up to V over ramp_s (v = V sin^2(pi t /
 * (2 ramp_s)), the acceleration rising from zero), cruises, turns by D
 * (yaw = y0 + D (u - sin(2 pi u) / (2 pi)) over the cruise, u from 0 to 1)
 * with a weave of +-5 deg at 0.25 Hz, and slows down the same way: never at
 * constant velocity for long (an IMU-only detector cannot tell that from
 * rest).  Walking adds a 2 Hz vertical bob of 3 cm and a 3 deg roll sway
 * at 1 Hz while moving.
 */
#ifndef SSCOPE_ZUPT_SIM_H
#define SSCOPE_ZUPT_SIM_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sensorscope.h"

struct zsim {
	struct sscope_navsim *ns;
	double *table_t, (*ned)[3], (*eu)[3];
	size_t n_table;
	double *imu;     /* n x 6: rad/s, m/s^2 */
	size_t n;
	double bias[6];  /* the run's true biases */
	double fs;
};

struct zsim_route {
	double stop_s, leg_s, ramp_s, speed_m_s, turn_rad;
	size_t legs;
	bool walk;
	double lat_rad, heading_rad;
};

/* the sensor of the bench, the tests' walks and the walk sample: gyro N
 * 0.2 deg/sqrt(h), accelerometer N 0.05 m/s/sqrt(h), turn-on biases
 * with 1 sigma 0.2 deg/s and 5 mg */
static inline void zsim_imu(struct sscope_navsim_imu *imu)
{
	const double d2r = 3.14159265358979323846 / 180;

	memset(imu, 0, sizeof(*imu));
	imu->gyro.n = 0.2 * d2r / 60;
	imu->gyro.bias = 0.2 * d2r;
	imu->accel.n = 0.05 / 60;
	imu->accel.bias = 0.005 * 9.80665;
}

static inline void zsim_free(struct zsim *z)
{
	sscope_navsim_free(z->ns);
	free(z->table_t);
	free(z->ned);
	free(z->eu);
	free(z->imu);
	memset(z, 0, sizeof(*z));
}

/* speed, yaw, bob and sway of the route at time t */
static inline void zsim_motion(const struct zsim_route *r, double t, double *v,
			double *yaw, double *bob, double *sway)
{
	const double pi = 3.14159265358979323846;
	double cyc = r->stop_s + r->leg_s, u = t - r->stop_s, tl, tr = r->ramp_s;
	double cr = r->leg_s - 2 * tr;
	size_t leg = u > 0 ? (size_t)floor(u / cyc) : 0, done;

	*v = *bob = *sway = 0;
	*yaw = r->heading_rad;
	if (u <= 0)
		return;
	done = leg < r->legs ? leg : r->legs;
	tl = u - (double)leg * cyc;
	if (leg < r->legs && tl >= r->leg_s)
		done = leg + 1; /* the stop after a leg: its turn is done */
	*yaw += r->turn_rad * (double)done;
	if (leg >= r->legs || tl >= r->leg_s)
		return;
	if (tl < tr)
		*v = r->speed_m_s * pow(sin(pi * tl / (2 * tr)), 2);
	else if (tl > r->leg_s - tr)
		*v = r->speed_m_s * pow(sin(pi * (r->leg_s - tl) / (2 * tr)), 2);
	else
		*v = r->speed_m_s;
	if (tl > tr && tl < r->leg_s - tr) {
		double x = (tl - tr) / cr;

		*yaw += r->turn_rad * (x - sin(2 * pi * x) / (2 * pi)) +
			5 * pi / 180 * sin(2 * pi * 0.25 * (tl - tr));
	} else if (tl >= r->leg_s - tr) {
		*yaw += r->turn_rad;
	}
	if (r->walk) {
		double env = *v / r->speed_m_s;

		*bob = 0.03 * env * sin(2 * pi * 2 * tl);
		*sway = 3 * pi / 180 * env * sin(2 * pi * tl);
	}
}

/* the table (positions by fine midpoint integration of the speed along
 * the yaw), navsim's reference along it, and the readings of one run */
static inline int zsim_build(struct zsim *z, const struct zsim_route *r, double fs,
		      double out_step_s, const struct sscope_navsim_imu *imu,
		      uint64_t seed, uint64_t run)
{
	const double row_dt = r->walk ? 0.02 : 0.05;
	const int sub = 20;
	double dur = r->stop_s + (double)r->legs * (r->leg_s + r->stop_s);
	double n_e[2] = { 0, 0 };
	struct sscope_navsim_opts o = { 0 };
	size_t nt = (size_t)ceil(dur / row_dt) + 1;
	int rc;

	memset(z, 0, sizeof(*z));
	z->fs = fs;
	z->table_t = malloc(nt * sizeof(double));
	z->ned = malloc(nt * sizeof(*z->ned));
	z->eu = malloc(nt * sizeof(*z->eu));
	if (!z->table_t || !z->ned || !z->eu)
		return -ENOMEM;
	for (size_t i = 0; i < nt; i++) {
		double t1 = (double)i * row_dt, v, y, bob, sway;

		for (int s = 0; s < sub && i > 0; s++) {
			double tm = t1 - row_dt + ((double)s + 0.5) * row_dt / sub;

			zsim_motion(r, tm, &v, &y, &bob, &sway);
			n_e[0] += v * cos(y) * row_dt / sub;
			n_e[1] += v * sin(y) * row_dt / sub;
		}
		zsim_motion(r, t1, &v, &y, &bob, &sway);
		z->table_t[i] = t1;
		z->ned[i][0] = n_e[0];
		z->ned[i][1] = n_e[1];
		z->ned[i][2] = bob;
		z->eu[i][0] = sway;
		z->eu[i][1] = 0;
		z->eu[i][2] = y;
	}
	z->n_table = nt;
	o.rate_hz = fs;
	o.duration_s = dur;
	o.output_step_s = out_step_s;
	o.start.lat_rad = r->lat_rad;
	o.motion = SSCOPE_NAVSIM_TABLE;
	o.table_t_s = z->table_t;
	o.table_ned_m = (const double (*)[3])z->ned;
	o.table_euler_rad = (const double (*)[3])z->eu;
	o.n_table = nt;
	o.threads = 1;
	rc = sscope_navsim_new(&z->ns, &o, NULL);
	if (rc)
		return rc;
	z->n = sscope_navsim_n_samples(z->ns);
	z->imu = malloc(z->n * 6 * sizeof(double));
	if (!z->imu)
		return -ENOMEM;
	return sscope_navsim_readings(z->ns, imu, seed, run, z->imu, z->bias, NULL);
}

/* horizontal distance between record k of the filter and the truth */
static inline double zsim_horiz_err(const struct zsim *z, const struct sscope_zupt_rec *rec,
			     size_t k)
{
	struct sscope_navsim_pose p;
	struct sscope_nav_ltp ltp;
	struct sscope_navsim_pose p0;
	double re[3], ned[3];

	sscope_navsim_truth(z->ns, 0, &p0);
	sscope_nav_ltp_init(&ltp, &p0.pos);
	sscope_navsim_truth(z->ns, k, &p);
	sscope_nav_geodetic_to_ecef(&p.pos, re);
	sscope_nav_ltp_from_ecef(&ltp, re, ned);
	return hypot(rec[k].ned_m[0] - ned[0], rec[k].ned_m[1] - ned[1]);
}

/* filter options matching the simulated sensor */
static inline void zsim_opts(struct sscope_zupt_opts *o, const struct zsim *z,
		      const struct zsim_route *r,
		      const struct sscope_navsim_imu *imu, double out_step_s)
{
	sscope_zupt_opts_init(o);
	o->rate_hz = z->fs;
	o->start.lat_rad = r->lat_rad;
	o->heading_rad = r->heading_rad;
	o->heading_given = true;
	o->gyro_n = imu->gyro.n;
	o->gyro_b = imu->gyro.b;
	o->gyro_k = imu->gyro.k;
	o->accel_n = imu->accel.n;
	o->accel_b = imu->accel.b;
	o->accel_k = imu->accel.k;
	o->gyro_bias_sd_rad_s = imu->gyro.bias;
	o->accel_bias_sd_m_s2 = imu->accel.bias;
	o->output_step_s = out_step_s;
}

#endif
