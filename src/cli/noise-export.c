/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Noise parameters for the estimators that read them, from the IEEE 952
 * fit of `allan`:
 * - Kalibr imu.yaml (Kalibr wiki "IMU Noise Model" and "YAML formats"):
 *   gyroscope/accelerometer_noise_density = N in rad/s/sqrt(Hz),
 *   m/s^2/sqrt(Hz) (continuous time), *_random_walk = K in
 *   rad/s^2/sqrt(Hz), m/s^3/sqrt(Hz), the largest axis of each sensor.
 * - OpenVINS kalibr_imu_chain.yaml: the same four values under imu0 with
 *   T_i_b (identity), rostopic, time_offset, update_rate, model.
 * - imu_utils (gaowenliang/imu_utils) parameter YAML: Gyr/Acc blocks with
 *   unit, avg-axis, x-axis, y-axis, z-axis and gyr_n/gyr_w, acc_n/acc_w.
 *   The original imu_utils writes the bias instability as *_w, which the
 *   estimators that read the file (VINS-Mono/Fusion) use as the bias
 *   random walk; sensorscope writes the random walk K there, as the
 *   corrected fork of imu_utils does, and gives B in a comment.
 * Every value is multiplied by the inflation factor (--inflate, default
 * 1): Kalibr and OpenVINS advise inflating Allan-variance values for
 * effects the white-noise-plus-random-walk model leaves out (vibration,
 * temperature, mounting); each file states the factor and the measured
 * values.
 *
 * The gate (ssc_export_write): each value a file needs is the largest over
 * the axes of its sensor of the term's estimate where the fit establishes
 * the term, else of its upper bound (marked "upper bound" in a comment
 * beside it, with a warning); a value is never 0 (no positive value and no
 * bound: the file is not written).  A value that an adequacy finding of
 * severity doubt or invalid concerns (the record moves, the fit is
 * rejected, a warm-up, step or temperature drift biases it) refuses the
 * file with the finding as the reason, unless --force, which writes it
 * with the finding in a comment beside the value.
 */
#include "cli.h"

#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "noise-export.h"

/* one value of a file: a sensor's term over its axes */
struct ssc_export_value {
	bool have;       /* a positive value to write */
	double v;        /* SI, before inflation */
	bool bound;      /* the largest axis gives only an upper bound */
	bool doubt;      /* an adequacy finding concerns it */
	char axes[512];  /* "gx 1.2e-4, gy 1.3e-4 (upper bound)" */
	char why[480];   /* the first doubt, or the bound's reason */
};

struct ssc_export_values {
	struct ssc_export_value g[5], a[5]; /* gyro, accelerometer, by term */
	bool gyro, accel;                   /* channels of the sensor */
};

/* a channel's value of term t: estimate (established) or upper bound;
 * false when neither is a positive number */
static bool chan_value(const struct ssc_noise_chan *c, int t, double *v,
		       bool *bound)
{
	const struct sscope_noise_coef *cf;

	if (!c->fit)
		return false;
	cf = &c->fit->coef[t];
	if (sscope_adequacy_term_established(cf)) {
		*v = cf->value;
		*bound = false;
	} else {
		*v = cf->hi;
		*bound = true;
	}
	return *v > 0 && isfinite(*v);
}

/* the finding of channel c that puts term t in doubt, or NULL */
static const struct sscope_adequacy_finding *
chan_doubt(const struct ssc_noise_chan *c, int t)
{
	if (!c->adq)
		return NULL;
	for (size_t i = 0; i < c->adq->n_findings; i++) {
		const struct sscope_adequacy_finding *f = &c->adq->findings[i];

		if (f->severity >= SSCOPE_ADEQUACY_DOUBT && ((f->terms >> t) & 1))
			return f;
	}
	return NULL;
}

static void append(char *buf, size_t len, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

static void append(char *buf, size_t len, const char *fmt, ...)
{
	size_t used = strlen(buf);
	va_list ap;

	if (used + 1 >= len)
		return;
	va_start(ap, fmt);
	vsnprintf(buf + used, len - used, fmt, ap);
	va_end(ap);
}

static void gather(const struct ssc_noise_export *e, enum sscope_quantity q,
		   int t, struct ssc_export_value *out)
{
	memset(out, 0, sizeof(*out));
	for (size_t k = 0; k < e->n; k++) {
		const struct ssc_noise_chan *c = &e->ch[k];
		const struct sscope_adequacy_finding *f;
		double x;
		bool b;

		if (c->q != q)
			continue;
		f = chan_doubt(c, t);
		if (f && !out->doubt) {
			out->doubt = true;
			snprintf(out->why, sizeof(out->why), "%s: %s", c->name,
				 f->message);
		}
		if (!chan_value(c, t, &x, &b)) {
			append(out->axes, sizeof(out->axes), "%s%s none",
			       out->axes[0] ? ", " : "", c->name);
			continue;
		}
		append(out->axes, sizeof(out->axes), "%s%s %.4g%s",
		       out->axes[0] ? ", " : "", c->name, x,
		       b ? " (upper bound)" : "");
		if (!out->have || x > out->v) {
			out->v = x;
			out->bound = b;
		}
		out->have = true;
	}
}

/* the comment beside a value: its unit, then what is wrong with it */
static void put_value(FILE *f, const char *indent, const char *key,
		      const struct ssc_export_value *v, double inflate,
		      const char *comment)
{
	fprintf(f, "%s%s: %.6e # %s", indent, key, v->v * inflate, comment);
	if (v->bound)
		fprintf(f, " -- UPPER BOUND: the record does not establish this term, the value is the bound its fit puts on it");
	if (v->doubt)
		fprintf(f, " -- DOUBTFUL, written by --force: %s", v->why);
	fputc('\n', f);
}

static void header(FILE *f, const struct ssc_noise_export *e,
		   const char *what)
{
	fprintf(f, "# %s from sensorscope %s allan (IEEE 952 fit on OADEV)\n",
		what, PACKAGE_VERSION);
	fprintf(f, "# data: %s; the largest axis of each sensor is used\n",
		e->source);
	fprintf(f, "# continuous-time noise densities (per sqrt(Hz)), not discrete (per sample): multiply by sqrt(rate) for a per-sample sd\n");
	if (e->inflate != 1)
		fprintf(f, "# every noise value below is the measured one times %.6g (--inflate)\n",
			e->inflate);
	if (e->force)
		fprintf(f, "# written with --force: values the adequacy check doubts are marked DOUBTFUL beside them\n");
}

/* ------------------------------------------------------------ targets */

static void axes_comment(FILE *f, const char *sensor, const char *term,
			 const char *unit, const struct ssc_export_value *v)
{
	fprintf(f, "# %s %s per axis (%s): %s\n", sensor, term, unit, v->axes);
}

static void kalibr_body(FILE *f, const struct ssc_noise_export *e,
			const struct ssc_export_values *v)
{
	fprintf(f, "rostopic: %s%s\n", e->topic ? e->topic : "/imu0",
		e->topic ? "" : " # edit to your topic");
	fprintf(f, "update_rate: %.10g # Hz\n", e->rate_hz);
	if (v->gyro) {
		axes_comment(f, "gyro", "N", "rad/s/sqrt(Hz)", &v->g[SSCOPE_TERM_N]);
		axes_comment(f, "gyro", "K", "rad/s^2/sqrt(Hz)", &v->g[SSCOPE_TERM_K]);
		put_value(f, "", "gyroscope_noise_density", &v->g[SSCOPE_TERM_N],
			  e->inflate, "rad/s/sqrt(Hz) (continuous time)");
		put_value(f, "", "gyroscope_random_walk", &v->g[SSCOPE_TERM_K],
			  e->inflate, "rad/s^2/sqrt(Hz) (continuous time)");
	}
	if (v->accel) {
		axes_comment(f, "accelerometer", "N", "m/s^2/sqrt(Hz)", &v->a[SSCOPE_TERM_N]);
		axes_comment(f, "accelerometer", "K", "m/s^3/sqrt(Hz)", &v->a[SSCOPE_TERM_K]);
		put_value(f, "", "accelerometer_noise_density", &v->a[SSCOPE_TERM_N],
			  e->inflate, "m/s^2/sqrt(Hz) (continuous time)");
		put_value(f, "", "accelerometer_random_walk", &v->a[SSCOPE_TERM_K],
			  e->inflate, "m/s^3/sqrt(Hz) (continuous time)");
	}
	if (!v->gyro || !v->accel)
		fprintf(f, "# no %s channel was analysed: its keys are missing\n",
			v->gyro ? "accelerometer" : "gyro");
}

static void openvins_body(FILE *f, const struct ssc_noise_export *e,
			  const struct ssc_export_values *v)
{
	axes_comment(f, "gyro", "N", "rad/s/sqrt(Hz)", &v->g[SSCOPE_TERM_N]);
	axes_comment(f, "gyro", "K", "rad/s^2/sqrt(Hz)", &v->g[SSCOPE_TERM_K]);
	axes_comment(f, "accelerometer", "N", "m/s^2/sqrt(Hz)", &v->a[SSCOPE_TERM_N]);
	axes_comment(f, "accelerometer", "K", "m/s^3/sqrt(Hz)", &v->a[SSCOPE_TERM_K]);
	fprintf(f, "\nimu0:\n");
	fprintf(f, "  T_i_b:\n");
	for (int i = 0; i < 4; i++)
		fprintf(f, "    - [%s]\n", i == 0 ? "1.0, 0.0, 0.0, 0.0" :
					      i == 1 ? "0.0, 1.0, 0.0, 0.0" :
					      i == 2 ? "0.0, 0.0, 1.0, 0.0" :
						       "0.0, 0.0, 0.0, 1.0");
	put_value(f, "  ", "accelerometer_noise_density", &v->a[SSCOPE_TERM_N],
		  e->inflate, "[ m / s^2 / sqrt(Hz) ] ( accel \"white noise\", continuous time )");
	put_value(f, "  ", "accelerometer_random_walk", &v->a[SSCOPE_TERM_K],
		  e->inflate, "[ m / s^3 / sqrt(Hz) ] ( accel bias diffusion, continuous time )");
	put_value(f, "  ", "gyroscope_noise_density", &v->g[SSCOPE_TERM_N],
		  e->inflate, "[ rad / s / sqrt(Hz) ] ( gyro \"white noise\", continuous time )");
	put_value(f, "  ", "gyroscope_random_walk", &v->g[SSCOPE_TERM_K],
		  e->inflate, "[ rad / s^2 / sqrt(Hz) ] ( gyro bias diffusion, continuous time )");
	fprintf(f, "  rostopic: %s\n", e->topic ? e->topic : "/imu0");
	fprintf(f, "  time_offset: 0.0\n");
	fprintf(f, "  update_rate: %.10g\n", e->rate_hz);
	fprintf(f, "  model: \"kalibr\"\n");
}

/* One imu_utils block (Gyr or Acc): avg-axis and up to three axes.  The
 * average is over the axes that establish the term; axes that only bound
 * it are named and left out (all of them bounds: the largest bound,
 * marked). */
static void imu_utils_block(FILE *f, const struct ssc_noise_export *e,
			    enum sscope_quantity q, const char *block,
			    const char *unit, const char *p)
{
	static const char *const axis[] = { "x-axis", "y-axis", "z-axis" };
	const struct ssc_noise_chan *ax[3];
	struct ssc_export_value val[3][2], avg[2];
	static const int term[2] = { SSCOPE_TERM_N, SSCOPE_TERM_K };
	char ku[2][64];
	size_t na = 0;

	snprintf(ku[0], sizeof(ku[0]), "%s/sqrt(Hz) (continuous time)", unit);
	snprintf(ku[1], sizeof(ku[1]), "%s/s/sqrt(Hz) (continuous time)", unit);

	for (size_t k = 0; k < e->n && na < 3; k++)
		if (e->ch[k].q == q && e->ch[k].fit)
			ax[na++] = &e->ch[k];
	if (!na)
		return;
	fprintf(f, "# %s: %s_n = N (%s/sqrt(Hz), continuous time, numerically sigma(1 s)), %s_w = K (%s/s/sqrt(Hz), continuous time); bias instability B:",
		block, p, unit, p, unit);
	for (size_t i = 0; i < na; i++) {
		const struct sscope_noise_coef *b = &ax[i]->fit->coef[SSCOPE_TERM_B];

		if (sscope_adequacy_term_established(b))
			fprintf(f, " %s %.4g", ax[i]->name, b->value);
		else if (b->hi > 0 && isfinite(b->hi))
			fprintf(f, " %s below %.4g", ax[i]->name, b->hi);
		else
			fprintf(f, " %s not measured", ax[i]->name);
	}
	fprintf(f, " %s\n", unit);
	for (int j = 0; j < 2; j++) {
		double sum = 0, bmax = 0;
		size_t ne = 0;
		char left[256] = "";

		memset(&avg[j], 0, sizeof(avg[j]));
		for (size_t i = 0; i < na; i++) {
			struct ssc_export_value *v = &val[i][j];
			const struct sscope_adequacy_finding *fd =
				chan_doubt(ax[i], term[j]);

			memset(v, 0, sizeof(*v));
			v->have = chan_value(ax[i], term[j], &v->v, &v->bound);
			if (fd) {
				v->doubt = true;
				snprintf(v->why, sizeof(v->why), "%s: %s",
					 ax[i]->name, fd->message);
				if (!avg[j].doubt) {
					avg[j].doubt = true;
					memcpy(avg[j].why, v->why, sizeof(v->why));
				}
			}
			if (!v->have)
				continue;
			if (v->bound) {
				bmax = fmax(bmax, v->v);
				append(left, sizeof(left), "%s%s (below %.4g)",
				       left[0] ? ", " : "", ax[i]->name, v->v);
			} else {
				sum += v->v;
				ne++;
			}
		}
		if (ne) {
			avg[j].have = true;
			avg[j].v = sum / (double)ne;
			if (left[0])
				fprintf(f, "# avg-axis %s_%c: the mean of the %zu axes that establish it; left out, only bounded: %s\n",
					p, j ? 'w' : 'n', ne, left);
		} else if (bmax > 0) {
			avg[j].have = true;
			avg[j].v = bmax;
			avg[j].bound = true;
			fprintf(f, "# avg-axis %s_%c: no axis establishes it: the largest bound\n",
				p, j ? 'w' : 'n');
		}
	}
	fprintf(f, "%s:\n   unit: \" %s\"\n   avg-axis:\n", block, unit);
	for (int j = 0; j < 2; j++) {
		char key[16];

		snprintf(key, sizeof(key), "%s_%c", p, j ? 'w' : 'n');
		put_value(f, "      ", key, &avg[j], e->inflate, ku[j]);
	}
	for (size_t i = 0; i < na; i++) {
		fprintf(f, "   # %s: channel %s\n   %s:\n", axis[i], ax[i]->name,
			axis[i]);
		for (int j = 0; j < 2; j++) {
			char key[16];

			snprintf(key, sizeof(key), "%s_%c", p, j ? 'w' : 'n');
			if (val[i][j].have)
				put_value(f, "      ", key, &val[i][j], e->inflate, ku[j]);
			else
				fprintf(f, "      # %s: not measured on this axis (no value, no bound)\n",
					key);
		}
	}
}

static void imu_utils_body(FILE *f, const struct ssc_noise_export *e,
			   const struct ssc_export_values *v)
{
	fprintf(f, "# avg-axis is the mean of the axes that establish a term, as imu_utils writes it; axes that only bound it are left out and named\n");
	fprintf(f, "type: IMU\nname: %s\n", e->name ? e->name : "imu");
	if (v->gyro)
		imu_utils_block(f, e, SSCOPE_QUANTITY_ANGULAR_RATE, "Gyr", "rad/s", "gyr");
	if (v->accel)
		imu_utils_block(f, e, SSCOPE_QUANTITY_ACCELERATION, "Acc", "m/s^2", "acc");
}

#define NK ((1u << SSCOPE_TERM_N) | (1u << SSCOPE_TERM_K))

const struct ssc_export_target ssc_export_targets[] = {
	{ "kalibr", "--kalibr", "Kalibr IMU noise model", NULL, SSC_EXPORT_ANY,
	  NK, kalibr_body },
	{ "openvins", "--openvins", "OpenVINS kalibr_imu_chain.yaml",
	  "%YAML:1.0 # need to specify the file type at the top!\n",
	  SSC_EXPORT_GYRO | SSC_EXPORT_ACCEL, NK, openvins_body },
	{ "imu-utils", "--imu-utils", "imu_utils IMU parameters",
	  "%YAML:1.0\n---\n", SSC_EXPORT_ANY, NK, imu_utils_body },
	{ NULL, NULL, NULL, NULL, 0, 0, NULL },
};

const struct ssc_export_target *ssc_export_target_find(const char *name)
{
	for (const struct ssc_export_target *t = ssc_export_targets; t->name; t++)
		if (!strcmp(t->name, name))
			return t;
	return NULL;
}

/* ------------------------------------------------------------ the gate */

int ssc_export_write(const struct ssc_common *co,
		     const struct ssc_export_target *t, const char *path,
		     const struct ssc_noise_export *e)
{
	struct ssc_export_values v;
	struct ssc_out at;
	const char *cmd = co->cmd;
	int rc;

	memset(&v, 0, sizeof(v));
	for (size_t k = 0; k < e->n; k++) {
		v.gyro |= e->ch[k].q == SSCOPE_QUANTITY_ANGULAR_RATE;
		v.accel |= e->ch[k].q == SSCOPE_QUANTITY_ACCELERATION;
	}
	if ((t->need & SSC_EXPORT_GYRO) && (t->need & SSC_EXPORT_ACCEL) &&
	    (!v.gyro || !v.accel)) {
		ssc_err(cmd, "%s: the file needs both a gyro (rad/s, deg/s, ...) and an accelerometer (m/s^2, g, ...) channel",
			t->option);
		return SSC_EXIT_FAIL;
	}
	if (!v.gyro && !v.accel) {
		ssc_err(cmd, "%s: no gyro (rad/s, deg/s, ...) or accelerometer (m/s^2, g, ...) channel",
			t->option);
		return SSC_EXIT_FAIL;
	}
	for (int s = 0; s < 2; s++) {
		bool on = s ? v.accel : v.gyro;
		const char *sensor = s ? "accelerometer" : "gyro";

		for (int term = 0; term < 5 && on; term++) {
			struct ssc_export_value *x = s ? &v.a[term] : &v.g[term];

			if (!((t->terms >> term) & 1))
				continue;
			gather(e, s ? SSCOPE_QUANTITY_ACCELERATION :
				      SSCOPE_QUANTITY_ANGULAR_RATE, term, x);
			if (x->doubt && !e->force) {
				ssc_err(cmd, "%s: not written: %s (--force writes it with each doubtful value marked)",
					t->option, x->why);
				return SSC_EXIT_FAIL;
			}
			if (!x->have) {
				ssc_err(cmd, "%s: not written: no %s axis gives a value or a bound for %c (%s); a value is never written as 0",
					t->option, sensor, "QNBKR"[term],
					x->axes[0] ? x->axes : "no fit");
				return SSC_EXIT_FAIL;
			}
		}
	}
	/* bounds: written, marked, and said */
	for (int s = 0; s < 2; s++)
		for (int term = 0; term < 5; term++) {
			const struct ssc_export_value *x = s ? &v.a[term] : &v.g[term];

			if (x->have && x->bound)
				ssc_warn(co, "%s: %s %c is written as its upper bound %.4g (%s): the record does not establish it",
					 t->option, s ? "accelerometer" : "gyro",
					 "QNBKR"[term], x->v * e->inflate, x->axes);
			if (x->have && x->doubt)
				ssc_warn(co, "%s: %s %c written although doubtful (--force): %s",
					 t->option, s ? "accelerometer" : "gyro",
					 "QNBKR"[term], x->why);
		}
	rc = ssc_file_open(cmd, path, &at);
	if (rc)
		return rc;
	if (t->preamble)
		fputs(t->preamble, at.f);
	header(at.f, e, t->what);
	t->body(at.f, e, &v);
	return ssc_file_close(&at, true);
}
