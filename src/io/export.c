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
 * The gate (sscope_export): each value a file needs is the largest over
 * the axes of its sensor of the term's estimate where the fit establishes
 * the term, else of its upper bound (marked "upper bound" in a comment
 * beside it, with a warning); a value is never 0 (no positive value and no
 * bound: the file is not written).  A value that an adequacy finding of
 * severity doubt or invalid concerns (the record moves, the fit is
 * rejected, a warm-up, step or temperature drift biases it) refuses the
 * file with the finding as the reason, unless --force, which writes it
 * with the finding in a comment beside the value.
 *
 * The texts name the command's options (--inflate, --force): the Python
 * module's keywords of the same names say so in their documentation.
 */
#include "internal.h"

#include <math.h>
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sscope-export.h"

/* the data of one file */
struct xp {
	const struct sscope_export_chan *ch;
	size_t n;
	double rate_hz;
	double inflate;      /* multiplies every exported value */
	const char *source;  /* for the header comment */
	const char *topic;   /* ROS topic of the data, or NULL */
	const char *name;    /* sensor name (imu_utils), or NULL */
	double duration_s;   /* the longest channel's record length */
	bool force;          /* write values the adequacy check doubts */
};

struct xvalues;
struct xhdr;

/* comment styles of the leading block */
enum {
	SSC_EXPORT_HASH,    /* # (YAML, Python) */
	SSC_EXPORT_PERCENT, /* % (MATLAB) */
	SSC_EXPORT_XML,     /* <!-- --> (SDF) */
	SSC_EXPORT_JSON,    /* a "sensorscope_note" array of strings */
};

/* the sensors a target needs */
enum {
	SSC_EXPORT_GYRO = 1u << 0,
	SSC_EXPORT_ACCEL = 1u << 1,
	SSC_EXPORT_ANY = 1u << 2,
};

/* An export target: a new file format is one entry of the table. */
struct xtarget {
	const char *name;    /* "kalibr" */
	const char *defname; /* the file written by default */
	int style;           /* comment style (SSC_EXPORT_HASH, ...) */
	const char *what;    /* "Kalibr IMU noise model" (header comment) */
	const char *preamble; /* lines before the header, or NULL */
	unsigned need;       /* SSC_EXPORT_GYRO / _ACCEL: sensors it needs
				(both bits: both; SSC_EXPORT_ANY: either) */
	unsigned terms;      /* terms it writes (bits of enum sscope_term) */
	/* the body after the common header; v holds the gated values */
	void (*body)(FILE *f, const struct xp *e, const struct xvalues *v);
	/* its convention, as lines of the leading comment (note()) */
	void (*notes)(struct xhdr *h, const struct xp *e,
		      const struct xvalues *v);
};

/* one value of a file: a sensor's term over its axes */
struct xvalue {
	bool have;       /* a positive value to write */
	double v;        /* SI, before inflation */
	bool bound;      /* the largest axis gives only an upper bound */
	bool doubt;      /* an adequacy finding concerns it */
	char axes[512];  /* "gx 1.2e-4, gy 1.3e-4 (upper bound)" */
	char why[480];   /* the first doubt, or the bound's reason */
};

struct xvalues {
	struct xvalue g[5], a[5]; /* gyro, accelerometer, by term */
	bool gyro, accel;                   /* channels of the sensor */
};

/* a channel's value of term t: estimate (established) or upper bound;
 * false when neither is a positive number */
static bool chan_value(const struct sscope_export_chan *c, int t, double *v,
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
chan_doubt(const struct sscope_export_chan *c, int t)
{
	if (!c->adequacy)
		return NULL;
	for (size_t i = 0; i < c->adequacy->n_findings; i++) {
		const struct sscope_adequacy_finding *f = &c->adequacy->findings[i];

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

static void gather(const struct xp *e, enum sscope_quantity q,
		   int t, struct xvalue *out)
{
	memset(out, 0, sizeof(*out));
	for (size_t k = 0; k < e->n; k++) {
		const struct sscope_export_chan *c = &e->ch[k];
		const struct sscope_adequacy_finding *f;
		double x;
		bool b;

		if (c->quantity != q)
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
		      const struct xvalue *v, double inflate,
		      const char *comment)
{
	fprintf(f, "%s%s: %.6e # %s", indent, key, v->v * inflate, comment);
	if (v->bound)
		fprintf(f, " -- UPPER BOUND: the record does not establish this term, the value is the bound its fit puts on it");
	if (v->doubt)
		fprintf(f, " -- DOUBTFUL, written by --force: %s", v->why);
	fputc('\n', f);
}

/* the leading comment block: one line at a time, in the file's style */
struct xhdr {
	FILE *f;
	int style;
	bool first;
};

static void note(struct xhdr *h, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

static void note(struct xhdr *h, const char *fmt, ...)
{
	char line[1024];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(line, sizeof(line), fmt, ap);
	va_end(ap);
	switch (h->style) {
	case SSC_EXPORT_PERCENT:
		fprintf(h->f, "%% %s\n", line);
		break;
	case SSC_EXPORT_XML:
		/* "--" may not appear inside an XML comment */
		fputs("  ", h->f);
		for (const char *c = line; *c; c++) {
			if (c[0] == '-' && c[1] == '-') {
				fputs("option ", h->f);
				c++;
				continue;
			}
			fputc(*c, h->f);
		}
		fputc('\n', h->f);
		break;
	case SSC_EXPORT_JSON:
		fprintf(h->f, "%s    \"", h->first ? "" : ",\n");
		for (const char *c = line; *c; c++) {
			if (*c == '"' || *c == '\\')
				fputc('\\', h->f);
			if ((unsigned char)*c >= 0x20)
				fputc(*c, h->f);
		}
		fputc('"', h->f);
		break;
	default:
		fprintf(h->f, "# %s\n", line);
	}
	h->first = false;
}

static const char *const term_name[5] = {
	"quantization Q", "white noise N", "bias instability B",
	"rate random walk K", "rate ramp R"
};

static void header(struct xhdr *h, const struct xp *e,
		   const struct xtarget *t,
		   const struct xvalues *v)
{
	char chans[512] = "";

	for (size_t k = 0; k < e->n; k++)
		append(chans, sizeof(chans), "%s%s (%s)", k ? ", " : "",
		       e->ch[k].name,
		       e->ch[k].quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? "gyro" :
		       e->ch[k].quantity == SSCOPE_QUANTITY_ACCELERATION ? "accelerometer" :
		       "not exported");
	note(h, "%s from sensorscope %s allan (IEEE 952 fit on OADEV)",
	     t->what, PACKAGE_VERSION);
	note(h, "data: %s at %.10g Hz; channels: %s; the largest axis of each sensor is used",
	     e->source, e->rate_hz, chans[0] ? chans : "none");
	if (e->inflate != 1)
		note(h, "every noise value below is the measured one times %.6g (--inflate), for effects the white-noise-plus-random-walk model leaves out (vibration, temperature, mounting), as Kalibr and OpenVINS advise",
		     e->inflate);
	else
		note(h, "inflation: none (--inflate 1): the values are the measured ones; Kalibr and OpenVINS advise inflating Allan values (e.g. 2-10) in a filter for vibration, temperature and mounting effects the model leaves out");
	if (e->force)
		note(h, "written with --force: values the adequacy check doubts are marked DOUBTFUL");
	for (int s = 0; s < 2; s++)
		for (int term = 0; term < 5; term++) {
			const struct xvalue *x = s ? &v->a[term] : &v->g[term];

			if (!x->have || !((t->terms >> term) & 1))
				continue;
			if (x->bound)
				note(h, "UPPER BOUND: %s %s: the record does not establish it; the values derived from it below are the bound its fit puts on it (%s)",
				     s ? "accelerometer" : "gyro", term_name[term], x->axes);
			if (x->doubt)
				note(h, "DOUBTFUL (written by --force): %s %s: %s",
				     s ? "accelerometer" : "gyro", term_name[term], x->why);
		}
	if (t->notes)
		t->notes(h, e, v);
}

static void continuous_notes(struct xhdr *h,
			     const struct xp *e,
			     const struct xvalues *v)
{
	(void)e;
	(void)v;
	note(h, "continuous-time noise densities (per sqrt(Hz)), not discrete (per sample): multiply by sqrt(rate) for a per-sample sd");
}

/* ------------------------------------------------------------ targets */

static void axes_comment(FILE *f, const char *sensor, const char *term,
			 const char *unit, const struct xvalue *v)
{
	fprintf(f, "# %s %s per axis (%s): %s\n", sensor, term, unit, v->axes);
}

static void kalibr_body(FILE *f, const struct xp *e,
			const struct xvalues *v)
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

static void openvins_body(FILE *f, const struct xp *e,
			  const struct xvalues *v)
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
static void imu_utils_block(FILE *f, const struct xp *e,
			    enum sscope_quantity q, const char *block,
			    const char *unit, const char *p)
{
	static const char *const axis[] = { "x-axis", "y-axis", "z-axis" };
	const struct sscope_export_chan *ax[3];
	struct xvalue val[3][2], avg[2];
	static const int term[2] = { SSCOPE_TERM_N, SSCOPE_TERM_K };
	char ku[2][64];
	size_t na = 0;

	snprintf(ku[0], sizeof(ku[0]), "%s/sqrt(Hz) (continuous time)", unit);
	snprintf(ku[1], sizeof(ku[1]), "%s/s/sqrt(Hz) (continuous time)", unit);

	for (size_t k = 0; k < e->n && na < 3; k++)
		if (e->ch[k].quantity == q && e->ch[k].fit)
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
			struct xvalue *v = &val[i][j];
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

static void imu_utils_body(FILE *f, const struct xp *e,
			   const struct xvalues *v)
{
	fprintf(f, "# avg-axis is the mean of the axes that establish a term, as imu_utils writes it; axes that only bound it are left out and named\n");
	fprintf(f, "type: IMU\nname: %s\n", e->name ? e->name : "imu");
	if (v->gyro)
		imu_utils_block(f, e, SSCOPE_QUANTITY_ANGULAR_RATE, "Gyr", "rad/s", "gyr");
	if (v->accel)
		imu_utils_block(f, e, SSCOPE_QUANTITY_ACCELERATION, "Acc", "m/s^2", "acc");
}

/* ------------------------------------------------- the other consumers */

static double X(const struct xvalue *v, const struct xp *e)
{
	return v->v * e->inflate;
}

/* what a comment beside the value says about it */
static const char *mark(const struct xvalue *v)
{
	if (v->bound && v->doubt)
		return " UPPER BOUND, DOUBTFUL";
	return v->bound ? " UPPER BOUND" : v->doubt ? " DOUBTFUL" : "";
}

/* the correlation time that makes a first-order Gauss-Markov bias a rate
 * random walk over the record: ten record lengths (the spectra differ by
 * (T/(2 pi tau))^2 < 3e-4 at the longest tau the fit sees) */
static double gm_tau(const struct xp *e)
{
	return fmax(10 * e->duration_s, 1000);
}

static void vins_notes(struct xhdr *h, const struct xp *e,
		       const struct xvalues *v)
{
	(void)v;
	note(h, "VINS-Mono / VINS-Fusion config keys (paste into the estimator's config file)");
	note(h, "DISCRETE time at %.10g Hz, as VINS reads them: its config calls acc_n/gyr_n the measurement noise standard deviation and acc_w/gyr_w the bias random walk noise standard deviation;", e->rate_hz);
	note(h, "integration_base.h propagates acc_n^2 as the variance of one sample and acc_w^2 * dt^2 as the bias variance added per step, so");
	note(h, "acc_n = N sqrt(rate), acc_w = K sqrt(rate) (N, K continuous: N in m/s^2/sqrt(Hz), K in m/s^3/sqrt(Hz); gyro alike in rad/s)");
}

static void vins_body(FILE *f, const struct xp *e,
		      const struct xvalues *v)
{
	double sr = sqrt(e->rate_hz);

	if (v->accel) {
		fprintf(f, "acc_n: %.6e # m/s^2 per sample (N %.4e m/s^2/sqrt(Hz) x sqrt(%.10g))%s\n",
			X(&v->a[SSCOPE_TERM_N], e) * sr, X(&v->a[SSCOPE_TERM_N], e),
			e->rate_hz, mark(&v->a[SSCOPE_TERM_N]));
		fprintf(f, "acc_w: %.6e # m/s^3 per sample (K %.4e m/s^3/sqrt(Hz) x sqrt(%.10g))%s\n",
			X(&v->a[SSCOPE_TERM_K], e) * sr, X(&v->a[SSCOPE_TERM_K], e),
			e->rate_hz, mark(&v->a[SSCOPE_TERM_K]));
	}
	if (v->gyro) {
		fprintf(f, "gyr_n: %.6e # rad/s per sample (N %.4e rad/s/sqrt(Hz) x sqrt(%.10g))%s\n",
			X(&v->g[SSCOPE_TERM_N], e) * sr, X(&v->g[SSCOPE_TERM_N], e),
			e->rate_hz, mark(&v->g[SSCOPE_TERM_N]));
		fprintf(f, "gyr_w: %.6e # rad/s^2 per sample (K %.4e rad/s^2/sqrt(Hz) x sqrt(%.10g))%s\n",
			X(&v->g[SSCOPE_TERM_K], e) * sr, X(&v->g[SSCOPE_TERM_K], e),
			e->rate_hz, mark(&v->g[SSCOPE_TERM_K]));
	}
	if (!v->gyro || !v->accel)
		fprintf(f, "# no %s channel was analysed: its keys are missing\n",
			v->gyro ? "accelerometer" : "gyro");
}

static void orbslam3_notes(struct xhdr *h, const struct xp *e,
			   const struct xvalues *v)
{
	(void)e;
	(void)v;
	note(h, "ORB-SLAM3 settings keys (paste into the camera/IMU settings file)");
	note(h, "CONTINUOUS time: IMU.NoiseGyro/NoiseAcc = N (rad/s/sqrt(Hz), m/s^2/sqrt(Hz)), IMU.GyroWalk/AccWalk = K (rad/s^2/sqrt(Hz), m/s^3/sqrt(Hz));");
	note(h, "ORB-SLAM3 discretises them itself with IMU.Frequency (Tracking.cc: noise x sqrt(f), walk / sqrt(f))");
}

static void orbslam3_body(FILE *f, const struct xp *e,
			  const struct xvalues *v)
{
	fprintf(f, "IMU.NoiseGyro: %.6e # rad/s/sqrt(Hz)%s\n", X(&v->g[SSCOPE_TERM_N], e),
		mark(&v->g[SSCOPE_TERM_N]));
	fprintf(f, "IMU.NoiseAcc: %.6e # m/s^2/sqrt(Hz)%s\n", X(&v->a[SSCOPE_TERM_N], e),
		mark(&v->a[SSCOPE_TERM_N]));
	fprintf(f, "IMU.GyroWalk: %.6e # rad/s^2/sqrt(Hz)%s\n", X(&v->g[SSCOPE_TERM_K], e),
		mark(&v->g[SSCOPE_TERM_K]));
	fprintf(f, "IMU.AccWalk: %.6e # m/s^3/sqrt(Hz)%s\n", X(&v->a[SSCOPE_TERM_K], e),
		mark(&v->a[SSCOPE_TERM_K]));
	fprintf(f, "IMU.Frequency: %.10g # Hz\n", e->rate_hz);
}

static void basalt_notes(struct xhdr *h, const struct xp *e,
			 const struct xvalues *v)
{
	(void)e;
	(void)v;
	note(h, "Basalt calib.json IMU keys: merge them into value0 of the calibration file (the camera keys are not written)");
	note(h, "CONTINUOUS time, per axis x, y, z: accel/gyro_noise_std = N (m/s^2/sqrt(Hz), rad/s/sqrt(Hz)), accel/gyro_bias_std = K (m/s^3/sqrt(Hz), rad/s^2/sqrt(Hz));");
	note(h, "Basalt discretises the noise with imu_update_rate (calibration.hpp: dicrete_time_*_noise_std = std x sqrt(rate)) and weights the bias change over dt by 1/(bias_std^2 dt)");
}

static void basalt_vec(FILE *f, const char *key, const struct xvalue *v,
		       const struct xp *e, bool last)
{
	double x = X(v, e);

	fprintf(f, "    \"%s\": [%.6e, %.6e, %.6e]%s\n", key, x, x, x, last ? "" : ",");
}

static void basalt_body(FILE *f, const struct xp *e,
			const struct xvalues *v)
{
	fprintf(f, "    \"imu_update_rate\": %.10g,\n", e->rate_hz);
	basalt_vec(f, "accel_noise_std", &v->a[SSCOPE_TERM_N], e, false);
	basalt_vec(f, "gyro_noise_std", &v->g[SSCOPE_TERM_N], e, false);
	basalt_vec(f, "accel_bias_std", &v->a[SSCOPE_TERM_K], e, false);
	basalt_vec(f, "gyro_bias_std", &v->g[SSCOPE_TERM_K], e, true);
	fprintf(f, "  }\n}\n");
}

static void gtsam_notes(struct xhdr *h, const struct xp *e,
			const struct xvalues *v)
{
	(void)e;
	(void)v;
	note(h, "GTSAM PreintegrationParams / PreintegrationCombinedParams, 3x3 matrices row-major");
	note(h, "CONTINUOUS time, as GTSAM reads them: gyroscopeCovariance = N^2 I ((rad/s)^2/Hz), accelerometerCovariance = N^2 I ((m/s^2)^2/Hz),");
	note(h, "biasOmegaCovariance = K^2 I ((rad/s^2)^2/Hz), biasAccCovariance = K^2 I ((m/s^3)^2/Hz); GTSAM divides the measurement covariances by dt and multiplies the bias ones by dt");
	note(h, "integrationCovariance is not a sensor property and is not measured: 1e-8 I is the value of GTSAM's own ImuFactorsExample");
}

static void gtsam_mat(FILE *f, const char *key, double var, const char *unit,
		      const char *m)
{
	fprintf(f, "%s: [%.6e, 0, 0, 0, %.6e, 0, 0, 0, %.6e] # %s%s\n", key, var,
		var, var, unit, m);
}

static void gtsam_body(FILE *f, const struct xp *e,
		       const struct xvalues *v)
{
	double gn = X(&v->g[SSCOPE_TERM_N], e), an = X(&v->a[SSCOPE_TERM_N], e);
	double gk = X(&v->g[SSCOPE_TERM_K], e), ak = X(&v->a[SSCOPE_TERM_K], e);

	fprintf(f, "# sigmas: gyro N %.6e rad/s/sqrt(Hz), accel N %.6e m/s^2/sqrt(Hz), gyro K %.6e rad/s^2/sqrt(Hz), accel K %.6e m/s^3/sqrt(Hz)\n",
		gn, an, gk, ak);
	gtsam_mat(f, "gyroscopeCovariance", gn * gn, "(rad/s)^2/Hz", mark(&v->g[SSCOPE_TERM_N]));
	gtsam_mat(f, "accelerometerCovariance", an * an, "(m/s^2)^2/Hz", mark(&v->a[SSCOPE_TERM_N]));
	gtsam_mat(f, "integrationCovariance", 1e-8, "m^2/s (not measured: GTSAM's example value)", "");
	gtsam_mat(f, "biasAccCovariance", ak * ak, "(m/s^3)^2/Hz", mark(&v->a[SSCOPE_TERM_K]));
	gtsam_mat(f, "biasOmegaCovariance", gk * gk, "(rad/s^2)^2/Hz", mark(&v->g[SSCOPE_TERM_K]));
	fprintf(f, "rate_hz: %.10g # the rate of the record (GTSAM takes dt from the measurements)\n",
		e->rate_hz);
}

static void matlab_notes(struct xhdr *h, const struct xp *e,
			 const struct xvalues *v)
{
	(void)e;
	(void)v;
	note(h, "MATLAB script: imuSensor with gyroparams/accelparams (Navigation or Sensor Fusion and Tracking Toolbox)");
	note(h, "CONTINUOUS time, as the gyroparams/accelparams reference states: NoiseDensity = N in (rad/s)/sqrt(Hz), (m/s^2)/sqrt(Hz);");
	note(h, "RandomWalk = K in (rad/s)*sqrt(Hz), (m/s^2)*sqrt(Hz) -- the same number as K in rad/s^2/sqrt(Hz), m/s^3/sqrt(Hz) (a rate random walk, not the angle random walk);");
	note(h, "BiasInstability = B of IEEE 952 in rad/s, m/s^2 (the Allan minimum / 0.664, as MathWorks' Allan-variance example sets it); imuSensor discretises at SampleRate");
}

static void matlab_params(FILE *f, const char *var, const char *fn,
			  const struct xvalue *t,
			  const struct xp *e, const char *u)
{
	fprintf(f, "%s = %s( ...\n", var, fn);
	fprintf(f, "    'NoiseDensity', %.6e, ... %% %s/sqrt(Hz)%s\n", X(&t[SSCOPE_TERM_N], e),
		u, mark(&t[SSCOPE_TERM_N]));
	fprintf(f, "    'BiasInstability', %.6e, ... %% %s%s\n", X(&t[SSCOPE_TERM_B], e), u,
		mark(&t[SSCOPE_TERM_B]));
	fprintf(f, "    'RandomWalk', %.6e); %% %s*sqrt(Hz)%s\n", X(&t[SSCOPE_TERM_K], e), u,
		mark(&t[SSCOPE_TERM_K]));
}

static void matlab_body(FILE *f, const struct xp *e,
			const struct xvalues *v)
{
	fprintf(f, "SampleRate = %.10g; %% Hz\n", e->rate_hz);
	if (v->gyro)
		matlab_params(f, "gyro", "gyroparams", v->g, e, "(rad/s)");
	if (v->accel)
		matlab_params(f, "accel", "accelparams", v->a, e, "(m/s^2)");
	fprintf(f, "imu = imuSensor('accel-gyro', 'SampleRate', SampleRate%s%s);\n",
		v->gyro ? ", 'Gyroscope', gyro" : "",
		v->accel ? ", 'Accelerometer', accel" : "");
}

static void gnss_notes(struct xhdr *h, const struct xp *e,
		       const struct xvalues *v)
{
	(void)v;
	note(h, "gnss-ins-sim imu_err dict (pass it as imu_model.IMU(accuracy=imu_err, ...)), per axis x, y, z");
	note(h, "gyro_arw = N in deg/sqrt(hr), accel_vrw = N in m/s/sqrt(hr) (CONTINUOUS time; gnss-ins-sim draws arw/sqrt(dt) per sample)");
	note(h, "gnss-ins-sim has no rate-random-walk key: its bias drift is a first-order Gauss-Markov process of stationary sd *_b_stability and correlation time *_b_corr (pathgen.py bias_drift);");
	note(h, "to make it the measured rate random walk K over the record, *_b_corr = %.6g s (ten record lengths) and *_b_stability = K sqrt(b_corr/2) (deg/hr, m/s^2);",
	     gm_tau(e));
	note(h, "this is NOT the bias instability B, and the process saturates beyond b_corr; the constant biases gyro_b/accel_b are not measured by one record: set them (deg/hr, m/s^2) for your part");
}

static void gnss_arr(FILE *f, const char *key, double x, const char *unit,
		     const char *m)
{
	fprintf(f, "    '%s': np.array([%.6e, %.6e, %.6e]),  # %s%s\n", key, x, x, x,
		unit, m);
}

static void gnss_body(FILE *f, const struct xp *e,
		      const struct xvalues *v)
{
	double tau = gm_tau(e), gs = sqrt(tau / 2);
	double d = 180 / M_PI;

	fprintf(f, "import numpy as np\n\n");
	if (v->gyro)
		fprintf(f, "# gyro: N %.6e rad/s/sqrt(Hz), K %.6e rad/s^2/sqrt(Hz)\n",
			X(&v->g[SSCOPE_TERM_N], e), X(&v->g[SSCOPE_TERM_K], e));
	if (v->accel)
		fprintf(f, "# accelerometer: N %.6e m/s^2/sqrt(Hz), K %.6e m/s^3/sqrt(Hz)\n",
			X(&v->a[SSCOPE_TERM_N], e), X(&v->a[SSCOPE_TERM_K], e));
	fprintf(f, "imu_err = {\n");
	if (v->gyro) {
		gnss_arr(f, "gyro_arw", X(&v->g[SSCOPE_TERM_N], e) * d * 60, "deg/sqrt(hr)",
			 mark(&v->g[SSCOPE_TERM_N]));
		gnss_arr(f, "gyro_b_stability", X(&v->g[SSCOPE_TERM_K], e) * gs * d * 3600,
			 "deg/hr (K sqrt(b_corr/2))", mark(&v->g[SSCOPE_TERM_K]));
		gnss_arr(f, "gyro_b_corr", tau, "s", "");
	}
	if (v->accel) {
		gnss_arr(f, "accel_vrw", X(&v->a[SSCOPE_TERM_N], e) * 60, "m/s/sqrt(hr)",
			 mark(&v->a[SSCOPE_TERM_N]));
		gnss_arr(f, "accel_b_stability", X(&v->a[SSCOPE_TERM_K], e) * gs,
			 "m/s^2 (K sqrt(b_corr/2))", mark(&v->a[SSCOPE_TERM_K]));
		gnss_arr(f, "accel_b_corr", tau, "s", "");
	}
	fprintf(f, "}\nimu_rate_hz = %.10g\n", e->rate_hz);
}

static void gazebo_notes(struct xhdr *h, const struct xp *e,
			 const struct xvalues *v)
{
	(void)v;
	note(h, "Gazebo (gz-sensors) IMU sensor SDF: <noise type=\"gaussian\"> per axis of <angular_velocity> and <linear_acceleration>");
	note(h, "stddev is DISCRETE, per update at %.10g Hz: N sqrt(update_rate) (gz-sensors adds a fresh Gaussian of that sd to every reading);",
	     e->rate_hz);
	note(h, "dynamic_bias_stddev is the driving density of a Gauss-Markov bias (GaussianNoiseModel.cc: sd over dt = sqrt(sigma_b^2 tau/2 (1 - exp(-2 dt/tau)))), i.e. K in rad/s^2/sqrt(Hz), m/s^3/sqrt(Hz),");
	note(h, "with dynamic_bias_correlation_time = %.6g s (ten record lengths) so that it is a rate random walk over the record;",
	     gm_tau(e));
	note(h, "bias_mean and bias_stddev (the turn-on bias) are not measured by one record and are left out (Gazebo's default applies)");
}

static void gazebo_axes(FILE *f, const char *block, const struct xvalue *t,
			const struct xp *e)
{
	static const char ax[3] = { 'x', 'y', 'z' };

	fprintf(f, "    <%s>\n", block);
	for (int i = 0; i < 3; i++) {
		fprintf(f, "      <%c>\n        <noise type=\"gaussian\">\n", ax[i]);
		fprintf(f, "          <stddev>%.6e</stddev>%s%s%s\n",
			X(&t[SSCOPE_TERM_N], e) * sqrt(e->rate_hz),
			mark(&t[SSCOPE_TERM_N])[0] ? " <!-- " : "",
			mark(&t[SSCOPE_TERM_N]), mark(&t[SSCOPE_TERM_N])[0] ? " -->" : "");
		fprintf(f, "          <dynamic_bias_stddev>%.6e</dynamic_bias_stddev>%s%s%s\n",
			X(&t[SSCOPE_TERM_K], e),
			mark(&t[SSCOPE_TERM_K])[0] ? " <!-- " : "",
			mark(&t[SSCOPE_TERM_K]), mark(&t[SSCOPE_TERM_K])[0] ? " -->" : "");
		fprintf(f, "          <dynamic_bias_correlation_time>%.6g</dynamic_bias_correlation_time>\n",
			gm_tau(e));
		fprintf(f, "        </noise>\n      </%c>\n", ax[i]);
	}
	fprintf(f, "    </%s>\n", block);
}

static void gazebo_body(FILE *f, const struct xp *e,
			const struct xvalues *v)
{
	fprintf(f, "<sensor name=\"imu_sensor\" type=\"imu\">\n");
	fprintf(f, "  <always_on>true</always_on>\n  <update_rate>%.10g</update_rate>\n  <imu>\n",
		e->rate_hz);
	if (v->gyro)
		gazebo_axes(f, "angular_velocity", v->g, e);
	if (v->accel)
		gazebo_axes(f, "linear_acceleration", v->a, e);
	fprintf(f, "  </imu>\n</sensor>\n");
}

#define NK ((1u << SSCOPE_TERM_N) | (1u << SSCOPE_TERM_K))

#define NBK (NK | (1u << SSCOPE_TERM_B))
#define BOTH (SSC_EXPORT_GYRO | SSC_EXPORT_ACCEL)

static const struct xtarget targets[] = {
	{ "kalibr", "imu.yaml", SSC_EXPORT_HASH,
	  "Kalibr IMU noise model", NULL, SSC_EXPORT_ANY, NK, kalibr_body,
	  continuous_notes },
	{ "imu_utils", "imu_param.yaml", SSC_EXPORT_HASH,
	  "imu_utils IMU parameters", "%YAML:1.0\n---\n", SSC_EXPORT_ANY, NK,
	  imu_utils_body, continuous_notes },
	{ "openvins", "kalibr_imu_chain.yaml", SSC_EXPORT_HASH,
	  "OpenVINS kalibr_imu_chain.yaml",
	  "%YAML:1.0 # need to specify the file type at the top!\n", BOTH, NK,
	  openvins_body, continuous_notes },
	{ "vins", "vins_imu.yaml", SSC_EXPORT_HASH,
	  "VINS-Mono/VINS-Fusion IMU noise", "%YAML:1.0\n", SSC_EXPORT_ANY, NK,
	  vins_body, vins_notes },
	{ "orbslam3", "orbslam3_imu.yaml", SSC_EXPORT_HASH,
	  "ORB-SLAM3 IMU noise", "%YAML:1.0\n", BOTH, NK, orbslam3_body,
	  orbslam3_notes },
	{ "basalt", "basalt_imu_calib.json", SSC_EXPORT_JSON,
	  "Basalt calib.json IMU noise", "{\n  \"value0\": {\n    \"sensorscope_note\": [\n",
	  BOTH, NK, basalt_body, basalt_notes },
	{ "gtsam", "gtsam_imu.yaml", SSC_EXPORT_HASH,
	  "GTSAM preintegration parameters", NULL, BOTH, NK, gtsam_body,
	  gtsam_notes },
	{ "matlab", "imu_params.m", SSC_EXPORT_PERCENT,
	  "MATLAB imuSensor parameters", NULL, SSC_EXPORT_ANY, NBK, matlab_body,
	  matlab_notes },
	{ "gnss_ins_sim", "gnss_ins_sim_imu.py",
	  SSC_EXPORT_HASH, "gnss-ins-sim IMU error model", NULL, SSC_EXPORT_ANY,
	  NK, gnss_body, gnss_notes },
	{ "gazebo", "imu_noise.sdf", SSC_EXPORT_XML,
	  "Gazebo IMU sensor noise", "<?xml version=\"1.0\"?>\n<!--\n",
	  SSC_EXPORT_ANY, NK, gazebo_body, gazebo_notes },
	{ NULL, NULL, 0, NULL, NULL, 0, 0, NULL, NULL },
};


/* the target of that name; '-' and '_' are the same ("imu-utils",
 * "gnss-ins-sim") */
static const struct xtarget *find(const char *name)
{
	for (const struct xtarget *t = targets; name && t->name; t++) {
		size_t i = 0;

		while (t->name[i] && (name[i] == t->name[i] ||
				      (name[i] == '-' && t->name[i] == '_')))
			i++;
		if (!t->name[i] && !name[i])
			return t;
	}
	return NULL;
}

const char *sscope_export_target(size_t i)
{
	return i < sizeof(targets) / sizeof(targets[0]) ? targets[i].name : NULL;
}

const char *sscope_export_name(const char *target)
{
	const struct xtarget *t = find(target);

	return t ? t->name : NULL;
}

const char *sscope_export_default_file(const char *target)
{
	const struct xtarget *t = find(target);

	return t ? t->defname : NULL;
}

void sscope_export_file_free(struct sscope_export_file *f)
{
	if (!f)
		return;
	free(f->text);
	free(f->warnings);
	f->text = f->warnings = NULL;
	f->len = 0;
}

/* one warning line, appended to *w (a memstream) */
static void warn_line(FILE *w, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

static void warn_line(FILE *w, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	vfprintf(w, fmt, ap);
	va_end(ap);
	fputc('\n', w);
}

/* ------------------------------------------------------------ the gate */

/* the values of every term the target writes; -EDOM with the reason */
static int gate(const struct xtarget *t, const struct xp *e,
		struct xvalues *v, struct sscope_export_file *out,
		struct sscope_diag *diag)
{
	memset(v, 0, sizeof(*v));
	for (size_t k = 0; k < e->n; k++) {
		v->gyro |= e->ch[k].quantity == SSCOPE_QUANTITY_ANGULAR_RATE;
		v->accel |= e->ch[k].quantity == SSCOPE_QUANTITY_ACCELERATION;
	}
	if ((t->need & SSC_EXPORT_GYRO) && (t->need & SSC_EXPORT_ACCEL) &&
	    (!v->gyro || !v->accel))
		return ssc_diag(diag, -EDOM, "the file needs both a gyro (rad/s, deg/s, ...) and an accelerometer (m/s^2, g, ...) channel");
	if (!v->gyro && !v->accel)
		return ssc_diag(diag, -EDOM, "no gyro (rad/s, deg/s, ...) or accelerometer (m/s^2, g, ...) channel");
	for (int s = 0; s < 2; s++) {
		bool on = s ? v->accel : v->gyro;
		const char *sensor = s ? "accelerometer" : "gyro";

		for (int term = 0; term < 5 && on; term++) {
			struct xvalue *x = s ? &v->a[term] : &v->g[term];

			if (!((t->terms >> term) & 1))
				continue;
			gather(e, s ? SSCOPE_QUANTITY_ACCELERATION :
				      SSCOPE_QUANTITY_ANGULAR_RATE, term, x);
			if (x->doubt && !e->force) {
				out->forcible = true;
				return ssc_diag(diag, -EDOM, "not written: %s", x->why);
			}
			if (!x->have)
				return ssc_diag(diag, -EDOM, "not written: no %s axis gives a value or a bound for %c (%s); a value is never written as 0",
						    sensor, "QNBKR"[term],
						    x->axes[0] ? x->axes : "no fit");
		}
	}
	return 0;
}

int sscope_export(const char *target, const struct sscope_export_chan *ch,
		  size_t n, const struct sscope_export_opts *opts,
		  struct sscope_export_file *out, struct sscope_diag *diag)
{
	const struct xtarget *t = find(target);
	struct xvalues v;
	struct xp e = { 0 };
	char *wbuf = NULL;
	size_t wlen = 0;
	FILE *f, *w;
	int rc;

	if (!out)
		return ssc_diag(diag, -EINVAL, "no output");
	memset(out, 0, sizeof(*out));
	if (!t)
		return ssc_diag(diag, -EINVAL, "'%s' is not a target (kalibr, imu_utils, openvins, vins, orbslam3, basalt, gtsam, matlab, gnss_ins_sim, gazebo)",
				    target ? target : "(none)");
	if (!opts || !(opts->rate_hz > 0) || !isfinite(opts->rate_hz))
		return ssc_diag(diag, -EINVAL, "the sample rate must be positive");
	if (!(opts->inflate >= 0) || !isfinite(opts->inflate))
		return ssc_diag(diag, -EINVAL, "the inflation factor must be positive");
	if (n && !ch)
		return ssc_diag(diag, -EINVAL, "no channels");
	e.ch = ch;
	e.n = n;
	e.rate_hz = opts->rate_hz;
	e.inflate = opts->inflate > 0 ? opts->inflate : 1;
	e.source = opts->source ? opts->source : "data";
	e.topic = opts->topic;
	e.name = opts->sensor_name;
	e.duration_s = opts->duration_s > 0 ? opts->duration_s : 0;
	e.force = opts->force;
	rc = gate(t, &e, &v, out, diag);
	if (rc)
		return rc;
	f = open_memstream(&out->text, &out->len);
	w = open_memstream(&wbuf, &wlen);
	if (!f || !w) {
		if (f)
			fclose(f);
		if (w)
			fclose(w);
		free(wbuf);
		sscope_export_file_free(out);
		return ssc_diag(diag, -ENOMEM, "out of memory");
	}
	/* bounds and forced doubts: written, marked, and said */
	for (int s = 0; s < 2; s++)
		for (int term = 0; term < 5; term++) {
			const struct xvalue *x = s ? &v.a[term] : &v.g[term];

			if (x->have && x->bound)
				warn_line(w, "%s %c is written as its upper bound %.4g %s (%s): the record does not establish it",
					  s ? "accelerometer" : "gyro", "QNBKR"[term],
					  x->v * e.inflate,
					  sscope_term_si_unit(s ? SSCOPE_QUANTITY_ACCELERATION :
								  SSCOPE_QUANTITY_ANGULAR_RATE,
							      (enum sscope_term)term),
					  x->axes);
			if (x->have && x->doubt)
				warn_line(w, "%s %c written although doubtful (--force): %s",
					  s ? "accelerometer" : "gyro", "QNBKR"[term],
					  x->why);
		}
	if (t->preamble)
		fputs(t->preamble, f);
	{
		struct xhdr h = { f, t->style, true };

		header(&h, &e, t, &v);
	}
	if (t->style == SSC_EXPORT_XML)
		fputs("-->\n", f);
	else if (t->style == SSC_EXPORT_JSON)
		fputs("\n    ],\n", f);
	t->body(f, &e, &v);
	rc = ferror(f) | ferror(w);
	rc |= fclose(f);
	rc |= fclose(w);
	if (rc || !out->text) {
		free(wbuf);
		sscope_export_file_free(out);
		return ssc_diag(diag, -ENOMEM, "out of memory");
	}
	if (wlen)
		out->warnings = wbuf;
	else
		free(wbuf);
	return 0;
}
