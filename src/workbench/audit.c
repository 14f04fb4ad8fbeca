/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope audit: other tools' IMU noise files checked for the known
 * convention errors (issue 33, item 5).
 *
 * Formats, from their own documentation (named in sensorscope(1)):
 * - Kalibr imu.yaml (ethz-asl/kalibr wiki "IMU Noise Model", "YAML
 *   formats"): gyroscope/accelerometer_noise_density, continuous-time
 *   white-noise densities (rad/s/sqrt(Hz), m/s^2/sqrt(Hz)); *_random_walk,
 *   continuous bias random walks (rad/s^2/sqrt(Hz), m/s^3/sqrt(Hz));
 *   update_rate (Hz), with which Kalibr discretises: sigma_d = sigma /
 *   sqrt(dt) for the noise, sigma_bd = sigma_b sqrt(dt) for the bias.
 * - OpenVINS kalibr_imu_chain.yaml: the same keys under imu0.
 * - allan_variance_ros (ori-drs): an imu.yaml of the Kalibr keys (comment
 *   lines "#Accelerometer", "#Gyroscope"), and a printed summary whose
 *   "Bias Instability" lines are the minimum of the Allan deviation.
 * - imu_utils (gaowenliang): Gyr/Acc blocks, avg-axis gyr_n/gyr_w,
 *   acc_n/acc_w; its README calls *_w the "bias instability", and it
 *   writes the minimum of its fitted Allan deviation there, the value the
 *   readers of the file (VINS) take as the bias random walk.
 *
 * The checks (numbers of IEEE Std 952-1997 Annex C): the Allan minimum of
 * a bias-instability floor is 0.6643 B; the white-noise and rate-random-
 * walk lines N/sqrt(tau) and K sqrt(tau/3) cross at tau_c = sqrt(3) N/K,
 * tens to thousands of seconds for real sensors; a per-sample standard
 * deviation at rate f is N sqrt(f), a discrete bias step K / sqrt(f).
 * A finding is "error" when the file itself proves it (a value, another
 * number of the file, a tool's documented output) and "likely" when the
 * evidence is circumstantial (a magnitude, a ratio).
 */
#include "workbench.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "audit.h"

#define MAX_BYTES (1u << 20)
#define MIN_TO_B 0.6642824703 /* sqrt(2 ln 2 / pi): Allan minimum / B */
#define TAU_C_LO 10.0         /* s: N and K lines crossing earlier: not K */
#define TAU_C_HI 1e5          /* s: later: a per-sample value, likely */
#define REL_TOL 0.005         /* two numbers of the file "equal" */
#define KEYLEN 176            /* "path.key" */

enum fmt { F_KALIBR, F_OPENVINS, F_AVR, F_AVR_TEXT, F_IMU_UTILS };
static const char *const fmt_name[] = {
	"kalibr", "openvins", "allan_variance_ros", "allan_variance_ros_text",
	"imu_utils"
};
static const char *const fmt_what[] = {
	"Kalibr imu.yaml", "OpenVINS kalibr_imu_chain.yaml",
	"allan_variance_ros imu.yaml", "allan_variance_ros printed summary",
	"imu_utils parameter YAML"
};

struct line {
	int no;
	int indent;
	bool comment;   /* a whole-line comment: text in note */
	char key[64];
	char path[96];  /* enclosing blocks, "Gyr.avg-axis" */
	char section[16]; /* the printed summary's ACCELEROMETER/GYROSCOPE */
	char value[160];
	char note[320]; /* the comment */
};

struct finding {
	char key[KEYLEN];
	int line;           /* 0: none (a missing key) */
	bool likely;
	const char *problem;
	char msg[768];
	double corrected;   /* NaN: none */
	char unit[32];
	double as_b;        /* an imu_utils *_w read as B (NaN: -) */
};

struct slot {
	const struct line *l;
	int sensor;  /* 0 gyro, 1 accelerometer */
	int term;    /* 0 N (density), 1 K (random walk) */
	double v;
	bool ok;     /* a positive finite number */
};

struct audit {
	const char *path;
	struct line *ln;
	size_t n, cap;
	struct finding *f;
	size_t nf, fcap;
	enum fmt fmt;
	bool sensorscope;
	double rate;          /* Hz, NaN unknown */
	const char *rate_from;
	struct slot s[8];
	size_t ns;
};

static const char *const unit_si[2][2] = {
	{ "rad/s/sqrt(Hz)", "rad/s^2/sqrt(Hz)" },
	{ "m/s^2/sqrt(Hz)", "m/s^3/sqrt(Hz)" },
};
/* plausible densities, SI: from below the best navigation-grade parts to
 * above any MEMS part after the usual x10 inflation */
static const double n_lo[2] = { 1e-6, 1e-6 };
static const double n_hi[2] = { M_PI / 180, 0.0980665 };
static const char *const n_hi_text[2] = { "1 deg/s/sqrt(Hz)", "10 mg/sqrt(Hz)" };

static void trim(char *s)
{
	size_t n = strlen(s);

	while (n && (s[n - 1] == ' ' || s[n - 1] == '\t' || s[n - 1] == '\r'))
		s[--n] = 0;
	n = strspn(s, " \t");
	memmove(s, s + n, strlen(s + n) + 1);
}

static void copy(char *dst, size_t len, const char *src, size_t n)
{
	if (n >= len)
		n = len - 1;
	memcpy(dst, src, n);
	dst[n] = 0;
	trim(dst);
}

static struct finding *add(struct audit *a, const char *key, int line,
			   bool likely, const char *problem, double corrected,
			   const char *unit)
{
	struct finding *f;

	if (a->nf == a->fcap) {
		size_t c = a->fcap ? 2 * a->fcap : 16;
		void *p = realloc(a->f, c * sizeof(*a->f));

		if (!p)
			return NULL;
		a->f = p;
		a->fcap = c;
	}
	f = &a->f[a->nf++];
	memset(f, 0, sizeof(*f));
	snprintf(f->key, sizeof(f->key), "%s", key);
	f->line = line;
	f->likely = likely;
	f->problem = problem;
	f->corrected = corrected;
	snprintf(f->unit, sizeof(f->unit), "%s", unit);
	f->as_b = (double)NAN;
	return f;
}

/* ------------------------------------------------------------ reading */

static int parse(struct audit *a, char *text)
{
	struct { int indent; char key[64]; } stack[8];
	int depth = 0, no = 0;
	char section[16] = "";

	/* the byte-order mark Windows editors write at the start */
	if (!strncmp(text, "\xef\xbb\xbf", 3))
		text += 3;
	for (char *s = text, *next; s; s = next) {
		struct line *l;
		char *colon, *hash;
		bool quote = false;

		next = strchr(s, '\n');
		if (next)
			*next++ = 0;
		no++;
		if (a->n == a->cap) {
			size_t c = a->cap ? 2 * a->cap : 64;
			void *p = realloc(a->ln, c * sizeof(*a->ln));

			if (!p)
				return -ENOMEM;
			a->ln = p;
			a->cap = c;
		}
		l = &a->ln[a->n];
		memset(l, 0, sizeof(*l));
		l->no = no;
		l->indent = (int)strspn(s, " \t");
		s += l->indent;
		s[strcspn(s, "\r")] = 0;
		if (!*s || *s == '%' || !strncmp(s, "---", 3) || *s == '-')
			continue;
		if (*s == '#') {
			l->comment = true;
			copy(l->note, sizeof(l->note), s + 1, strlen(s + 1));
			a->n++;
			continue;
		}
		colon = strchr(s, ':');
		if (!colon)
			continue;
		for (hash = colon + 1; *hash; hash++) {
			if (*hash == '"' || *hash == '\'')
				quote = !quote;
			if (*hash == '#' && !quote)
				break;
		}
		copy(l->key, sizeof(l->key), s, (size_t)(colon - s));
		copy(l->value, sizeof(l->value), colon + 1, (size_t)(hash - colon - 1));
		if (*hash)
			copy(l->note, sizeof(l->note), hash + 1, strlen(hash + 1));
		if (!strcmp(l->key, "ACCELEROMETER") || !strcmp(l->key, "GYROSCOPE"))
			snprintf(section, sizeof(section), "%s",
				 l->key[0] == 'A' ? "ACCELEROMETER" : "GYROSCOPE");
		snprintf(l->section, sizeof(l->section), "%s", section);
		while (depth && stack[depth - 1].indent >= l->indent)
			depth--;
		for (int i = 0; i < depth; i++)
			snprintf(l->path + strlen(l->path), sizeof(l->path) - strlen(l->path),
				 "%s%s", i ? "." : "", stack[i].key);
		if (!l->value[0] && depth < 8) {
			stack[depth].indent = l->indent;
			snprintf(stack[depth].key, sizeof(stack[depth].key), "%s", l->key);
			depth++;
		}
		a->n++;
	}
	return 0;
}

static const struct line *find(const struct audit *a, const char *key,
			       const char *path)
{
	for (size_t i = 0; i < a->n; i++)
		if (!a->ln[i].comment && !strcmp(a->ln[i].key, key) &&
		    (!path || !strcmp(a->ln[i].path, path)))
			return &a->ln[i];
	return NULL;
}

static bool comment_has(const struct audit *a, const char *what)
{
	for (size_t i = 0; i < a->n; i++)
		if (strstr(a->ln[i].note, what))
			return true;
	return false;
}

static const char *const kalibr_key[2][2] = {
	{ "gyroscope_noise_density", "gyroscope_random_walk" },
	{ "accelerometer_noise_density", "accelerometer_random_walk" },
};
static const char *const utils_key[2][2] = {
	{ "gyr_n", "gyr_w" }, { "acc_n", "acc_w" },
};

/* which format, and the path of its values ("" or "imu0") */
static int detect(struct audit *a, char *path, size_t len)
{
	for (size_t i = 0; i < a->n; i++) {
		const struct line *l = &a->ln[i];

		if (l->comment)
			continue;
		if (l->section[0] && strlen(l->key) > 2 && l->key[1] == ' ' &&
		    strstr(l->key, "Bias Instability")) {
			a->fmt = F_AVR_TEXT;
			return 0;
		}
		for (int s = 0; s < 2; s++)
			for (int t = 0; t < 2; t++) {
				if (!strcmp(l->key, utils_key[s][t]) &&
				    !strcmp(l->path, s ? "Acc.avg-axis" : "Gyr.avg-axis")) {
					a->fmt = F_IMU_UTILS;
					return 0;
				}
				if (strcmp(l->key, kalibr_key[s][t]))
					continue;
				if (!l->path[0]) {
					a->fmt = comment_has(a, "Make sure this is correct") ?
						 F_AVR : F_KALIBR;
					for (size_t j = 0; j < a->n && a->fmt == F_KALIBR; j++)
						if (a->ln[j].comment &&
						    (!strcmp(a->ln[j].note, "Accelerometer") ||
						     !strcmp(a->ln[j].note, "Gyroscope")))
							a->fmt = F_AVR;
					path[0] = 0;
					return 0;
				}
				if (!strncmp(l->path, "imu", 3) && !strchr(l->path, '.')) {
					a->fmt = F_OPENVINS;
					snprintf(path, len, "%s", l->path);
					return 0;
				}
			}
	}
	return -1;
}

/* ------------------------------------------------------------- checks */

static const char *fmtv(char *buf, size_t len, double v)
{
	return ssc_fmt(buf, len, v, 4);
}

static const char *keyname(const struct audit *a, const struct line *l,
			   char *buf, size_t len)
{
	snprintf(buf, len, "%s%s%s", a->fmt == F_OPENVINS || a->fmt == F_IMU_UTILS ?
		 l->path : "", l->path[0] && (a->fmt == F_OPENVINS || a->fmt == F_IMU_UTILS) ?
		 "." : "", l->key);
	return buf;
}

/* read a number; false (and a finding) when it is none a filter can use */
static bool number(struct audit *a, const struct line *l, const char *unit,
		   double *v)
{
	char k[KEYLEN], *end;
	struct finding *f;

	*v = strtod(l->value, &end);
	keyname(a, l, k, sizeof(k));
	if (end == l->value) {
		f = add(a, k, l->no, false, "not_a_number", (double)NAN, unit);
		if (f)
			snprintf(f->msg, sizeof(f->msg), "'%s' is not a number", l->value);
		return false;
	}
	if (!isfinite(*v) || *v <= 0) {
		bool rate = !strcmp(unit, "Hz");

		f = add(a, k, l->no, false, *v == 0 ? "zero" : "invalid_value", (double)NAN, unit);
		if (f && rate)
			snprintf(f->msg, sizeof(f->msg), "%s: a sample rate is a positive frequency; give the IMU's rate in Hz",
				 isnan(*v) ? "not a number" : *v < 0 ? "a negative rate" :
				 *v == 0 ? "0 Hz" : "infinite");
		else if (f)
			snprintf(f->msg, sizeof(f->msg), "%s: %s",
				 *v == 0 ? "0 is never a valid noise value (a filter reading it trusts the sensor completely: a singular covariance)" :
				 isnan(*v) ? "not a number" : *v < 0 ? "a negative value (a standard deviation or density is positive)" : "infinite",
				 "no corrected value can be derived from the file: measure it (sensorscope allan --export TARGET)");
		return false;
	}
	return true;
}

/* numbers a file gives beside a value: in the comment on its line, and in
 * commented-out assignments of the same key ("#  key: 0.005") */
static size_t beside(const struct audit *a, const struct line *l, double *x,
		     size_t max)
{
	size_t n = 0;

	for (size_t i = 0; i < a->n && n < max; i++) {
		const struct line *c = &a->ln[i];
		const char *s;
		size_t kl = strlen(l->key);

		if (c == l) {
			s = c->note;
		} else if (c->comment && !strncmp(c->note, l->key, kl) &&
			   c->note[kl] == ':') {
			char *end;
			double v = strtod(c->note + kl + 1, &end);

			if (end != c->note + kl + 1 && v > 0 && isfinite(v))
				x[n++] = v;
			continue;
		} else {
			continue;
		}
		for (const char *p = s; *p && n < max; p++) {
			char *end;
			double v;

			if (!((*p >= '0' && *p <= '9') || (*p == '.' && p[1] >= '0' && p[1] <= '9')))
				continue;
			/* not a digit of a name (imu0), an exponent or a
			 * power of a unit (m/s^2) */
			if (p > s && (isalnum((unsigned char)p[-1]) || p[-1] == '_' ||
				      p[-1] == '.' || p[-1] == '-' || p[-1] == '^'))
				continue;
			v = strtod(p, &end);
			if (end > p && v > 0 && isfinite(v))
				x[n++] = v;
			p = end - 1;
		}
	}
	return n;
}

static bool same(double a, double b)
{
	return fabs(a - b) <= REL_TOL * fabs(a);
}

/* a value equal to another number of the file times or over sqrt(rate) */
static bool check_equal(struct audit *a, const struct slot *sl)
{
	double x[16], r = sqrt(a->rate), c = (double)NAN;
	size_t n;
	char k[KEYLEN], v1[32], v2[32], rt[32];
	const char *how = NULL, *problem = NULL;
	struct finding *f;

	if (!isfinite(a->rate) || fabs(r - 1) < 0.05)
		return false;
	n = beside(a, sl->l, x, 16);
	for (size_t i = 0; i < n && !how; i++) {
		if (sl->term == 0 && same(sl->v, x[i] * r)) {
			how = "times";
			problem = "discrete_density";
			c = x[i];
		} else if (sl->term == 1 && same(sl->v, x[i] / r)) {
			how = "over";
			problem = "discrete_random_walk";
			c = x[i];
		} else if (sl->term == 1 && same(sl->v, x[i] * r)) {
			how = "times";
			problem = "discrete_random_walk";
			c = x[i];
		}
	}
	if (!how)
		return false;
	keyname(a, sl->l, k, sizeof(k));
	f = add(a, k, sl->l->no, false, problem, c, unit_si[sl->sensor][sl->term]);
	if (f)
		snprintf(f->msg, sizeof(f->msg),
			 "%s is %s %s sqrt(update_rate %s Hz), the number the file gives beside it: a discrete per-sample value at that rate (%s) in a continuous-time field",
			 fmtv(v1, sizeof(v1), sl->v), fmtv(v2, sizeof(v2), c), how,
			 ssc_fmt(rt, sizeof(rt), a->rate, 6),
			 sl->term ? "a bias step per sample" : "a per-sample standard deviation, sigma sqrt(f), not a density");
	return true;
}

static void check_magnitude(struct audit *a, const struct slot *sl)
{
	char k[KEYLEN], v1[32], v2[32], lo[32];
	double r = sqrt(a->rate);
	struct finding *f;
	int s = sl->sensor;

	if (sl->term)
		return;
	keyname(a, sl->l, k, sizeof(k));
	if (sl->v > n_hi[s]) {
		bool disc = isfinite(r) && sl->v / r <= n_hi[s] && sl->v / r >= n_lo[s];

		f = add(a, k, sl->l->no, disc, disc ? "discrete_density" : "implausible_magnitude",
			disc ? sl->v / r : (double)NAN, unit_si[s][0]);
		if (f && disc)
			snprintf(f->msg, sizeof(f->msg),
				 "%s %s is above %s, more than any %s noise density, while %s / sqrt(update_rate %s Hz) = %s is a plausible one: likely a per-sample standard deviation (sigma sqrt(f)) labelled as a density",
				 fmtv(v1, sizeof(v1), sl->v), unit_si[s][0], n_hi_text[s],
				 s ? "MEMS accelerometer's" : "MEMS gyro's",
				 v1, ssc_fmt(lo, sizeof(lo), a->rate, 6),
				 fmtv(v2, sizeof(v2), sl->v / r));
		else if (f)
			snprintf(f->msg, sizeof(f->msg),
				 "%s %s is above %s, more than any %s noise density (even inflated x10 for a filter); a unit or convention error%s",
				 fmtv(v1, sizeof(v1), sl->v), unit_si[s][0], n_hi_text[s],
				 s ? "MEMS accelerometer's" : "MEMS gyro's",
				 isfinite(r) ? "; no corrected value follows from the file" :
				 "; with the IMU's rate (update_rate or --rate) the per-sample case could be checked");
	} else if (sl->v < n_lo[s]) {
		f = add(a, k, sl->l->no, false, "implausible_magnitude", (double)NAN, unit_si[s][0]);
		if (f)
			snprintf(f->msg, sizeof(f->msg),
				 "%s %s is below 1e-6 %s, less than any MEMS part and about the best navigation-grade %s: a unit or convention error (degrees per hour, a discrete value?); no corrected value follows from the file",
				 fmtv(v1, sizeof(v1), sl->v), unit_si[s][0], unit_si[s][0],
				 s ? "accelerometers" : "fibre-optic gyros");
	}
}

/* the density and the random walk of one sensor against each other */
static void check_pair(struct audit *a, const struct slot *n, const struct slot *w,
		       bool declared)
{
	double tc = sqrt(3) * n->v / w->v, r = sqrt(a->rate);
	char k[KEYLEN], v1[32], v2[32], t[32], rt[32];
	struct finding *f;
	int s = n->sensor;

	keyname(a, w->l, k, sizeof(k));
	if (a->fmt == F_IMU_UTILS && !declared) {
		f = add(a, k, w->l->no, true, "bias_instability_in_random_walk", (double)NAN,
			unit_si[s][1]);
		if (!f)
			return;
		f->as_b = w->v / MIN_TO_B;
		snprintf(f->msg, sizeof(f->msg),
			 "the file does not say what %s holds, and imu_utils (gaowenliang/imu_utils, whose README calls it the bias instability) writes there the minimum of its fitted Allan deviation in %s, where its readers (VINS-Mono/Fusion) expect the bias random walk; "
			 "the N and K lines would cross at tau = sqrt(3) %s / %s = %s s%s. "
			 "As IEEE 952's bias instability it is B = %s / 0.6643 = %s %s; the rate random walk is not in the file: measure it (sensorscope allan --export imu_utils)",
			 w->l->key, s ? "m/s^2" : "rad/s", n->l->key, w->l->key,
			 ssc_fmt(t, sizeof(t), tc, 3),
			 tc < TAU_C_LO ? ", where a real sensor's Allan deviation still falls (a random walk that large is implausible)" : "",
			 fmtv(v1, sizeof(v1), w->v), fmtv(v2, sizeof(v2), w->v / MIN_TO_B),
			 s ? "m/s^2" : "rad/s");
		return;
	}
	/* the file states what the field holds (sensorscope's exports say
	 * "K" and "continuous time" beside it) or that the value is only a
	 * bound, which may be large: the ratio proves nothing */
	if (declared || strstr(w->l->note, "UPPER BOUND"))
		return;
	if (tc < TAU_C_LO) {
		f = add(a, k, w->l->no, true, "bias_instability_in_random_walk", (double)NAN,
			unit_si[s][1]);
		if (f)
			snprintf(f->msg, sizeof(f->msg),
				 "%s %s is so large beside the noise density %s that the N and K lines of the Allan deviation cross at tau = sqrt(3) N / K = %s s, where a real sensor's curve still falls: likely a bias instability (an Allan minimum or B, in %s) written in the random-walk field; the random walk is not in the file: measure it",
				 fmtv(v1, sizeof(v1), w->v), unit_si[s][1],
				 fmtv(v2, sizeof(v2), n->v), ssc_fmt(t, sizeof(t), tc, 3),
				 s ? "m/s^2" : "rad/s");
		return;
	}
	if (tc > TAU_C_HI && isfinite(r) && tc / r <= TAU_C_HI && tc / r >= TAU_C_LO) {
		keyname(a, n->l, k, sizeof(k));
		f = add(a, k, n->l->no, true, "discrete_density", n->v / r, unit_si[s][0]);
		if (f)
			snprintf(f->msg, sizeof(f->msg),
				 "the noise density %s is implausibly large beside the random walk %s: their Allan lines cross at tau = %s s (%s h), a factor sqrt(update_rate %s Hz) beyond the usual; likely a per-sample standard deviation (sigma sqrt(f)) labelled as a density, corrected %s / sqrt(%s); "
				 "or the random walk is a discrete bias step K / sqrt(f), whose continuous value would be %s %s",
				 fmtv(v1, sizeof(v1), n->v), fmtv(v2, sizeof(v2), w->v),
				 ssc_fmt(t, sizeof(t), tc, 3), ssc_fmt(t + 16, 16, tc / 3600, 3),
				 ssc_fmt(rt, sizeof(rt), a->rate, 6), v1, rt,
				 fmtv(v2, sizeof(v2), w->v * r), unit_si[s][1]);
	}
}

static void check_rate(struct audit *a, const char *path, double opt_rate)
{
	const struct line *l;
	struct finding *f;
	char k[KEYLEN];

	a->rate = (double)NAN;
	a->rate_from = NULL;
	if (a->fmt == F_IMU_UTILS) {
		if (opt_rate > 0) {
			a->rate = opt_rate;
			a->rate_from = "--rate";
		}
		return;
	}
	l = find(a, "update_rate", path);
	if (l) {
		double v;

		if (number(a, l, "Hz", &v)) {
			a->rate = v;
			a->rate_from = "file";
		}
		if (opt_rate > 0 && isfinite(a->rate) &&
		    fabs(a->rate - opt_rate) > 0.01 * opt_rate) {
			char r1[32], r2[32];

			keyname(a, l, k, sizeof(k));
			f = add(a, k, l->no, false, "rate_mismatch", opt_rate, "Hz");
			if (f)
				snprintf(f->msg, sizeof(f->msg),
					 "%s Hz is not the IMU's rate %s Hz (--rate): Kalibr discretises the densities with update_rate, so every per-sample noise it derives is off by sqrt(%s / %s)",
					 ssc_fmt(r1, sizeof(r1), a->rate, 6),
					 ssc_fmt(r2, sizeof(r2), opt_rate, 6), r2, r1);
		}
		if (opt_rate > 0 && !(a->rate == opt_rate)) {
			a->rate = opt_rate;
			a->rate_from = "--rate";
		}
		return;
	}
	snprintf(k, sizeof(k), "%s%supdate_rate", path, path[0] ? "." : "");
	f = add(a, k, 0, false, "missing_rate", opt_rate > 0 ? opt_rate : (double)NAN, "Hz");
	if (f)
		snprintf(f->msg, sizeof(f->msg),
			 "missing: Kalibr discretises the densities with it (sigma_d = sigma / sqrt(dt)) and needs it; the corrected value is the IMU's message rate%s",
			 opt_rate > 0 ? " (--rate)" : ", which the file does not give");
	if (opt_rate > 0) {
		a->rate = opt_rate;
		a->rate_from = "--rate";
	}
}

/* allan_variance_ros' printed summary: "X Bias Instability: v unit ..." is
 * the minimum of the Allan deviation (its analysis takes the curve's
 * minimum), not B */
static void check_avr_text(struct audit *a)
{
	for (size_t i = 0; i < a->n; i++) {
		const struct line *l = &a->ln[i];
		char unit[32] = "", *end, v1[32], v2[32];
		struct finding *f;
		double v;

		if (l->comment || !l->section[0] || strlen(l->key) < 3 || l->key[1] != ' ')
			continue;
		v = strtod(l->value, &end);
		sscanf(end, "%31s", unit);
		if (end == l->value)
			continue;
		if (!(v > 0) || !isfinite(v)) {
			f = add(a, l->key, l->no, false, v == 0 ? "zero" : "invalid_value", (double)NAN, unit);
			if (f)
				snprintf(f->msg, sizeof(f->msg), "%s (%s): no valid noise value is 0, negative or not finite%s",
					 l->value, l->section, v == 0 ? " (at 5 decimals, a value below 0.000005 prints as 0: the summary is too coarse for this sensor; read the imu.yaml)" : "");
			continue;
		}
		if (!strstr(l->key, "Bias Instability"))
			continue;
		f = add(a, l->key, l->no, false, "allan_minimum_as_b", v / MIN_TO_B, unit);
		if (f)
			snprintf(f->msg, sizeof(f->msg),
				 "%s %s (%s) is the minimum of the Allan deviation, which allan_variance_ros prints as the bias instability; IEEE 952's B is the minimum / 0.6643 = %s %s",
				 fmtv(v1, sizeof(v1), v), unit, l->section,
				 fmtv(v2, sizeof(v2), v / MIN_TO_B), unit);
	}
}

static int audit(struct audit *a, double opt_rate)
{
	char path[96];
	bool declared[2] = { false, false };

	if (detect(a, path, sizeof(path)))
		return -1;
	a->sensorscope = comment_has(a, "from sensorscope");
	if (a->fmt == F_AVR_TEXT) {
		check_avr_text(a);
		a->rate = (double)NAN;
		return 0;
	}
	check_rate(a, path, opt_rate);
	for (int s = 0; s < 2; s++) {
		const char *p = a->fmt == F_IMU_UTILS ? (s ? "Acc.avg-axis" : "Gyr.avg-axis") : path;

		/* a comment stating that the random-walk field is K
		 * (sensorscope's exports, or an edited file) */
		for (size_t i = 0; i < a->n; i++)
			if (strstr(a->ln[i].note, s ? "acc_w = K" : "gyr_w = K") ||
			    strstr(a->ln[i].note, s ? "accelerometer K per axis" :
				   "gyro K per axis"))
				declared[s] = true;
		for (int t = 0; t < 2; t++) {
			const struct line *l = find(a, a->fmt == F_IMU_UTILS ?
						    utils_key[s][t] : kalibr_key[s][t], p);
			struct slot *sl = &a->s[a->ns];

			if (!l) {
				/* a sensor the file describes needs both its
				 * terms: the other without this one is a
				 * finding (a file of one sensor, as a gyro's
				 * own export, is complete) */
				const char *key = a->fmt == F_IMU_UTILS ? utils_key[s][t] :
									 kalibr_key[s][t];
				const char *other = a->fmt == F_IMU_UTILS ? utils_key[s][!t] :
									   kalibr_key[s][!t];
				char k[KEYLEN];
				struct finding *f;

				if (!find(a, other, p))
					continue;
				snprintf(k, sizeof(k), "%s%s%s", p, p[0] ? "." : "", key);
				f = add(a, k, 0, false, "missing_key", (double)NAN, unit_si[s][t]);
				if (f)
					snprintf(f->msg, sizeof(f->msg),
						 "missing: a filter reading the file needs the %s %s; measure it (sensorscope allan --export TARGET)",
						 s ? "accelerometer's" : "gyro's",
						 t ? "random walk" : "noise density");
				continue;
			}
			sl->l = l;
			sl->sensor = s;
			sl->term = t;
			sl->ok = number(a, l, unit_si[s][t], &sl->v);
			a->ns++;
		}
	}
	for (size_t i = 0; i < a->ns; i++) {
		const struct slot *sl = &a->s[i], *w = NULL;
		size_t before = a->nf;

		if (!sl->ok || sl->term)
			continue;
		for (size_t j = 0; j < a->ns; j++)
			if (a->s[j].sensor == sl->sensor && a->s[j].term == 1)
				w = &a->s[j];
		if (!check_equal(a, sl))
			check_magnitude(a, sl);
		if (w && w->ok && !check_equal(a, w) && a->nf == before)
			check_pair(a, sl, w, declared[sl->sensor]);
	}
	return 0;
}

/* ------------------------------------------------------------ output */

static json_t *to_json(const struct audit *a)
{
	json_t *root = json_object(), *vals = json_array(), *fs = json_array();

	json_object_set_new(root, "command", json_string("audit"));
	json_object_set_new(root, "file", json_string(a->path));
	json_object_set_new(root, "format", json_string(fmt_name[a->fmt]));
	json_object_set_new(root, "written_by", a->sensorscope ?
			    json_string("sensorscope") : json_null());
	json_object_set_new(root, "update_rate_hz", ssc_jreal(a->rate));
	json_object_set_new(root, "rate_from", a->rate_from ?
			    json_string(a->rate_from) : json_null());
	for (size_t i = 0; i < a->ns; i++) {
		const struct slot *s = &a->s[i];
		json_t *o = json_object();

		json_object_set_new(o, "key", json_string(s->l->key));
		json_object_set_new(o, "line", json_integer(s->l->no));
		json_object_set_new(o, "sensor", json_string(s->sensor ? "accelerometer" : "gyro"));
		json_object_set_new(o, "term", json_string(s->term ? "K" : "N"));
		json_object_set_new(o, "value", s->ok ? ssc_jreal(s->v) : json_null());
		json_object_set_new(o, "unit", json_string(unit_si[s->sensor][s->term]));
		json_array_append_new(vals, o);
	}
	json_object_set_new(root, "values", vals);
	for (size_t i = 0; i < a->nf; i++) {
		const struct finding *f = &a->f[i];
		json_t *o = json_object();

		json_object_set_new(o, "key", json_string(f->key));
		json_object_set_new(o, "line", f->line ? json_integer(f->line) : json_null());
		json_object_set_new(o, "severity", json_string(f->likely ? "likely" : "error"));
		json_object_set_new(o, "problem", json_string(f->problem));
		json_object_set_new(o, "message", json_string(f->msg));
		json_object_set_new(o, "corrected", ssc_jreal(f->corrected));
		json_object_set_new(o, "unit", json_string(f->unit));
		if (isfinite(f->as_b))
			json_object_set_new(o, "as_bias_instability", ssc_jreal(f->as_b));
		json_array_append_new(fs, o);
	}
	json_object_set_new(root, "findings", fs);
	json_object_set_new(root, "clean", json_boolean(a->nf == 0));
	return root;
}

static void to_text(FILE *out, const struct audit *a)
{
	char c[32], r[32];

	for (size_t i = 0; i < a->nf; i++) {
		const struct finding *f = &a->f[i];

		if (f->line)
			fprintf(out, "%s:%d: %s: %s%s; corrected: ", a->path, f->line,
				f->key, f->likely ? "likely: " : "", f->msg);
		else
			fprintf(out, "%s: %s: %s; corrected: ", a->path, f->key, f->msg);
		if (isfinite(f->corrected))
			fprintf(out, "%s %s\n", ssc_fmt(c, sizeof(c), f->corrected, 6), f->unit);
		else
			fprintf(out, "none (the file does not give it)\n");
	}
	fprintf(out, "%s: %s%s", a->path, fmt_what[a->fmt],
		a->sensorscope ? " written by sensorscope" : "");
	if (isfinite(a->rate))
		fprintf(out, ", rate %s Hz (%s)", ssc_fmt(r, sizeof(r), a->rate, 6),
			!strcmp(a->rate_from, "file") ? "update_rate" : a->rate_from);
	else if (a->fmt == F_IMU_UTILS)
		fprintf(out, ", no rate (the format has none; --rate HZ enables the per-sample checks)");
	if (a->nf)
		fprintf(out, ": %zu finding%s\n", a->nf, a->nf > 1 ? "s" : "");
	else
		fprintf(out, ": no findings\n");
}

static char *slurp(const char *cmd, const char *path)
{
	FILE *f = strcmp(path, "-") ? fopen(path, "rb") : stdin;
	char *buf;
	size_t n;

	if (!f) {
		ssc_err(cmd, "%s: %s", path, sscope_strerror(errno));
		return NULL;
	}
	buf = malloc(MAX_BYTES + 1);
	if (!buf) {
		ssc_err(cmd, "out of memory");
		if (f != stdin)
			fclose(f);
		return NULL;
	}
	n = fread(buf, 1, MAX_BYTES + 1, f);
	if (ferror(f) || n > MAX_BYTES || memchr(buf, 0, n)) {
		ssc_err(cmd, "%s: %s", path, ferror(f) ? sscope_strerror(errno) :
			n > MAX_BYTES ? "larger than 1 MiB: not a noise parameter file" :
			"binary data: not a noise parameter file");
		free(buf);
		buf = NULL;
	} else {
		buf[n] = 0;
	}
	if (f != stdin)
		fclose(f);
	return buf;
}

int ssc_audit_run(const struct ssc_common *co, const char *path,
		  double rate_hz, bool strict)
{
	struct audit a;
	struct ssc_out out;
	char *text = slurp(co->cmd, path);
	int rc;

	if (!text)
		return SSC_EXIT_FAIL;
	memset(&a, 0, sizeof(a));
	a.path = path;
	rc = parse(&a, text);
	if (!rc)
		rc = audit(&a, rate_hz);
	if (rc == -ENOMEM) {
		ssc_err(co->cmd, "out of memory");
		rc = SSC_EXIT_FAIL;
	} else if (rc) {
		ssc_err(co->cmd, "%s: %s: expected a Kalibr or allan_variance_ros imu.yaml (gyroscope_noise_density, ...), an OpenVINS kalibr_imu_chain.yaml (imu0:), an imu_utils parameter YAML (Gyr: avg-axis: gyr_n) or allan_variance_ros' printed summary",
			path, comment_has(&a, "from sensorscope") ?
			"a sensorscope export for another consumer, not a format audit reads" :
			"not a noise file audit reads");
		rc = SSC_EXIT_FAIL;
	} else if (co->format == SSC_FMT_JSON) {
		rc = ssc_emit_json(co, to_json(&a));
	} else {
		rc = ssc_out_open(co, &out);
		if (!rc) {
			to_text(out.f, &a);
			rc = ssc_out_close(co, &out, !ferror(out.f));
		}
	}
	if (!rc && strict && a.nf)
		rc = SSC_EXIT_FAIL;
	free(a.ln);
	free(a.f);
	free(text);
	return rc;
}
