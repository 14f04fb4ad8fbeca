/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Helpers shared by the navigation commands (heading, walk, navsim):
 * noise terms from a sensor spec, an `allan` result or options, the error
 * model of a `calib` result, vectors of quantities on the command line.
 */
#ifndef SSCOPE_NAVCOMMON_H
#define SSCOPE_NAVCOMMON_H

#include "workbench.h"

/* The IEEE 952 terms of one channel (SI, enum sscope_term order). */
struct ssc_nav_terms {
	char name[64];                 /* channel, or "" */
	enum sscope_quantity quantity; /* ANGULAR_RATE or ACCELERATION */
	double coef[5];                /* Q N B K R; 0 when not fitted */
	double n_lo, n_hi;             /* N's interval (NaN: none) */
	double lo[5], hi[5];           /* each term's interval, SI (NaN: none;
					  an absent term's hi is its bound) */
	bool present[5];               /* the presence test kept the term */
	double ci_level;               /* of that interval */
	bool have;                     /* any term is set */
};

/* Terms of every channel of an `allan` JSON result (single file or
 * "files"); *out is malloc'ed (caller frees).  Prints errors naming
 * @p what; returns an exit code. */
int ssc_nav_terms_from_allan(const char *cmd, const json_t *root,
			     const char *what, struct ssc_nav_terms **out,
			     size_t *n);

/* The same from the allan stage's typed result (a scene's upstream). */
struct ssc_allan_res;
int ssc_nav_terms_from_allan_res(const char *cmd,
				 const struct ssc_allan_res *a,
				 const char *what, struct ssc_nav_terms **out,
				 size_t *n);

/* A library failure about @p path: "path: detail" (or the error's text);
 * returns the exit code (ssc_fail's). */
int ssc_nav_fail(const char *cmd, int rc, const struct sscope_diag *d,
		 const char *path);

/* Read a JSON file; prints errors; returns an exit code. */
int ssc_nav_load_json(const char *cmd, const char *opt, const char *path,
		      json_t **root);

/* The channel of @p terms named @p name, else the first of quantity @p q
 * with the largest N ("the worst axis"), or NULL. */
const struct ssc_nav_terms *ssc_nav_terms_pick(const struct ssc_nav_terms *t,
					       size_t n, const char *name,
					       enum sscope_quantity q);

/* Terms of a sensor spec. */
void ssc_nav_terms_from_spec(const struct sscope_sensor_spec *s,
			     struct ssc_nav_terms *t);

/* The error model of a `calib` triad (kind "gyro" or "accel") of the calib
 * stage's typed result (or a saved one, ssc_calib_res_from_json()): fixed
 * bias (SI) and error matrix M = A - I.  Returns 0 when found, 1 when the
 * result has no such triad or no error model (bias in counts). */
struct ssc_calib_res;
int ssc_nav_calib_errors_res(const struct ssc_calib_res *c, const char *kind,
			     double bias[3], double M[3][3]);

/* "V" or "V,V,V" with units, each converted to @p si; one value is used
 * for every axis.  Prints usage errors; returns an exit code. */
int ssc_nav_arg_vec3(const char *cmd, const char *opt, const char *arg,
		     const char *si, double out[3]);

/* A term's SI value in its conventional unit (deg/sqrt(h), ug, ...);
 * *unit receives that unit (the SI one when there is none). */
double ssc_nav_term_value(double si, enum sscope_quantity q, enum sscope_term t,
			  const char **unit);

/* Text of the terms in conventional units ("N 0.15 deg/sqrt(h), B ...") */
void ssc_nav_terms_text(const struct ssc_nav_terms *t, char *buf, size_t len);

/* JSON {"Q": C, "N": C, ...} (C as allan's) of a set of terms. */
json_t *ssc_nav_terms_json(const struct ssc_nav_terms *t);

/* A trajectory file: time plus tangent-plane position (north, east,
 * down) and attitude (roll, pitch, yaw); down, roll and pitch may be
 * absent (zero). */
struct ssc_nav_table {
	struct sscope_capture *cap;
	double *ned, *eu; /* n x 3 */
};

/* Read a trajectory; errors are printed, an exit code returned.  On
 * failure *t holds what was allocated: free it with ssc_nav_table_free. */
int ssc_nav_table_load(const char *cmd, const char *path, struct ssc_nav_table *t);
void ssc_nav_table_free(struct ssc_nav_table *t);

/* navsim --plot-mechanisations: the same sensor and runs (@p seed) under
 * the other mechanisation than that of @p ns, whose statistics are
 * @p st; a figure of both (horizontal position error, median and 95 %;
 * heading error rms) at @p path.  @p ns keeps its mechanisation.
 * Errors are printed; returns an exit code. */
int ssc_navsim_mech_plot(const char *cmd, struct sscope_navsim *ns,
			 const struct sscope_navsim_imu *imu, size_t runs,
			 uint64_t seed, const struct sscope_navsim_stat *st,
			 enum sscope_navsim_mech mech, const char *traj,
			 const char *path);

#endif
