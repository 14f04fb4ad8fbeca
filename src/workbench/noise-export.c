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
 * values.  A term the fit did not resolve is exported as its upper limit.
 */
#include "workbench.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "noise-export.h"

/* value of term t of channel c: the estimate or the upper limit */
static bool coef(const struct ssc_noise_chan *c, int t, double *v, bool *limit)
{
	const struct sscope_noise_coef *cf;

	if (!c->fit)
		return false;
	cf = &c->fit->coef[t];
	*v = cf->fitted ? cf->value : cf->hi;
	*limit = !cf->fitted;
	return isfinite(*v);
}

/* largest value of term t over the channels of quantity q */
static bool pick(const struct ssc_noise_export *e, enum sscope_quantity q,
		 int t, double *v, char *note, size_t nl)
{
	bool any = false;
	size_t used = 0;

	*v = 0;
	note[0] = '\0';
	for (size_t k = 0; k < e->n; k++) {
		const struct ssc_noise_chan *c = &e->ch[k];
		double x;
		bool lim;
		int w;

		if (c->q != q || !coef(c, t, &x, &lim))
			continue;
		any = true;
		if (x > *v)
			*v = x;
		w = snprintf(note + used, nl - used, "%s%s %.4g%s",
			     used ? ", " : "", c->name, x,
			     lim ? " (upper limit)" : "");
		if (w > 0 && (size_t)w < nl - used)
			used += (size_t)w;
	}
	return any;
}

static void header(FILE *f, const struct ssc_noise_export *e,
		   const char *what)
{
	fprintf(f, "# %s from sensorscope %s allan (IEEE 952 fit on OADEV)\n",
		what, PACKAGE_VERSION);
	fprintf(f, "# data: %s; the largest axis of each sensor is used\n",
		e->source);
	if (e->inflate != 1)
		fprintf(f, "# every noise value below is the measured one times %.6g (--inflate)\n",
			e->inflate);
}

int ssc_export_kalibr(const char *cmd, const char *path,
		      const struct ssc_noise_export *e)
{
	struct ssc_out at;
	double n, k;
	char note[512];
	bool gyro = false, acc = false;
	int rc = ssc_file_open(cmd, path, &at);

	if (rc)
		return rc;
	header(at.f, e, "Kalibr IMU noise model");
	fprintf(at.f, "rostopic: %s%s\n", e->topic ? e->topic : "/imu0",
		e->topic ? "" : " # edit to your topic");
	fprintf(at.f, "update_rate: %.10g # Hz\n", e->rate_hz);
	if (pick(e, SSCOPE_QUANTITY_ANGULAR_RATE, SSCOPE_TERM_N, &n, note, sizeof(note))) {
		fprintf(at.f, "# gyro N per axis (rad/s/sqrt(Hz)): %s\n", note);
		pick(e, SSCOPE_QUANTITY_ANGULAR_RATE, SSCOPE_TERM_K, &k, note, sizeof(note));
		fprintf(at.f, "# gyro K per axis (rad/s^2/sqrt(Hz)): %s\n", note);
		fprintf(at.f, "gyroscope_noise_density: %.6e # rad/s/sqrt(Hz) (continuous time)\n",
			n * e->inflate);
		fprintf(at.f, "gyroscope_random_walk: %.6e # rad/s^2/sqrt(Hz)\n",
			k * e->inflate);
		gyro = true;
	}
	if (pick(e, SSCOPE_QUANTITY_ACCELERATION, SSCOPE_TERM_N, &n, note, sizeof(note))) {
		fprintf(at.f, "# accelerometer N per axis (m/s^2/sqrt(Hz)): %s\n", note);
		pick(e, SSCOPE_QUANTITY_ACCELERATION, SSCOPE_TERM_K, &k, note, sizeof(note));
		fprintf(at.f, "# accelerometer K per axis (m/s^3/sqrt(Hz)): %s\n", note);
		fprintf(at.f, "accelerometer_noise_density: %.6e # m/s^2/sqrt(Hz) (continuous time)\n",
			n * e->inflate);
		fprintf(at.f, "accelerometer_random_walk: %.6e # m/s^3/sqrt(Hz)\n",
			k * e->inflate);
		acc = true;
	}
	if (!gyro && !acc) {
		ssc_file_close(&at, false);
		ssc_err(cmd, "--kalibr: no fitted gyro (rad/s, deg/s, ...) or accelerometer (m/s^2, g, ...) channel");
		return SSC_EXIT_FAIL;
	}
	if (!gyro || !acc)
		fprintf(at.f, "# no %s channel was analysed: its keys are missing\n",
			gyro ? "accelerometer" : "gyro");
	return ssc_file_close(&at, true);
}

int ssc_export_openvins(const char *cmd, const char *path,
			const struct ssc_noise_export *e)
{
	struct ssc_out at;
	double gn, gk, an, ak;
	char gnote[512], anote[512], tmp[512];
	int rc;

	if (!pick(e, SSCOPE_QUANTITY_ANGULAR_RATE, SSCOPE_TERM_N, &gn, gnote, sizeof(gnote)) ||
	    !pick(e, SSCOPE_QUANTITY_ACCELERATION, SSCOPE_TERM_N, &an, anote, sizeof(anote))) {
		ssc_err(cmd, "--openvins: kalibr_imu_chain.yaml needs both a gyro (rad/s, deg/s, ...) and an accelerometer (m/s^2, g, ...) channel with a fit");
		return SSC_EXIT_FAIL;
	}
	pick(e, SSCOPE_QUANTITY_ANGULAR_RATE, SSCOPE_TERM_K, &gk, tmp, sizeof(tmp));
	pick(e, SSCOPE_QUANTITY_ACCELERATION, SSCOPE_TERM_K, &ak, tmp, sizeof(tmp));
	rc = ssc_file_open(cmd, path, &at);
	if (rc)
		return rc;
	fprintf(at.f, "%%YAML:1.0 # need to specify the file type at the top!\n");
	header(at.f, e, "OpenVINS kalibr_imu_chain.yaml");
	fprintf(at.f, "# gyro N per axis (rad/s/sqrt(Hz)): %s\n", gnote);
	fprintf(at.f, "# accelerometer N per axis (m/s^2/sqrt(Hz)): %s\n", anote);
	fprintf(at.f, "\nimu0:\n");
	fprintf(at.f, "  T_i_b:\n");
	for (int i = 0; i < 4; i++)
		fprintf(at.f, "    - [%s]\n", i == 0 ? "1.0, 0.0, 0.0, 0.0" :
					      i == 1 ? "0.0, 1.0, 0.0, 0.0" :
					      i == 2 ? "0.0, 0.0, 1.0, 0.0" :
						       "0.0, 0.0, 0.0, 1.0");
	fprintf(at.f, "  accelerometer_noise_density: %.6e  # [ m / s^2 / sqrt(Hz) ]   ( accel \"white noise\" )\n",
		an * e->inflate);
	fprintf(at.f, "  accelerometer_random_walk: %.6e    # [ m / s^3 / sqrt(Hz) ].  ( accel bias diffusion )\n",
		ak * e->inflate);
	fprintf(at.f, "  gyroscope_noise_density: %.6e      # [ rad / s / sqrt(Hz) ]   ( gyro \"white noise\" )\n",
		gn * e->inflate);
	fprintf(at.f, "  gyroscope_random_walk: %.6e        # [ rad / s^2 / sqrt(Hz) ] ( gyro bias diffusion )\n",
		gk * e->inflate);
	fprintf(at.f, "  rostopic: %s\n", e->topic ? e->topic : "/imu0");
	fprintf(at.f, "  time_offset: 0.0\n");
	fprintf(at.f, "  update_rate: %.10g\n", e->rate_hz);
	fprintf(at.f, "  model: \"kalibr\"\n");
	return ssc_file_close(&at, true);
}

/* one imu_utils block (Gyr or Acc): avg-axis and up to three axes */
static bool imu_utils_block(FILE *f, const struct ssc_noise_export *e,
			    enum sscope_quantity q, const char *block,
			    const char *unit, const char *p)
{
	const struct ssc_noise_chan *ax[3];
	static const char *const axis[] = { "x-axis", "y-axis", "z-axis" };
	double n[3], w[3], b[3], sn = 0, sw = 0;
	size_t na = 0;
	bool lim;

	for (size_t k = 0; k < e->n && na < 3; k++) {
		const struct ssc_noise_chan *c = &e->ch[k];

		if (c->q != q || !coef(c, SSCOPE_TERM_N, &n[na], &lim))
			continue;
		if (!coef(c, SSCOPE_TERM_K, &w[na], &lim))
			w[na] = 0;
		if (!coef(c, SSCOPE_TERM_B, &b[na], &lim))
			b[na] = NAN;
		ax[na] = c;
		sn += n[na];
		sw += w[na];
		na++;
	}
	if (!na)
		return false;
	fprintf(f, "# %s: %s_n = N (%s/sqrt(Hz), numerically sigma(1 s)), %s_w = K (%s/s/sqrt(Hz)); bias instability B:",
		block, p, unit, p, unit);
	for (size_t i = 0; i < na; i++)
		fprintf(f, " %s %.4g", ax[i]->name, b[i]);
	fprintf(f, " %s\n", unit);
	fprintf(f, "%s:\n   unit: \" %s\"\n   avg-axis:\n", block, unit);
	fprintf(f, "      %s_n: %.16e\n      %s_w: %.16e\n", p,
		sn / (double)na * e->inflate, p, sw / (double)na * e->inflate);
	for (size_t i = 0; i < na; i++)
		fprintf(f, "   # %s: channel %s\n   %s:\n      %s_n: %.16e\n      %s_w: %.16e\n",
			axis[i], ax[i]->name, axis[i], p, n[i] * e->inflate, p,
			w[i] * e->inflate);
	return true;
}

int ssc_export_imu_utils(const char *cmd, const char *path,
			 const struct ssc_noise_export *e)
{
	struct ssc_out at;
	bool g, a;
	int rc = ssc_file_open(cmd, path, &at);

	if (rc)
		return rc;
	fprintf(at.f, "%%YAML:1.0\n---\n");
	header(at.f, e, "imu_utils IMU parameters");
	fprintf(at.f, "# avg-axis is the mean of the axes, as imu_utils writes it\n");
	fprintf(at.f, "type: IMU\nname: %s\n", e->name ? e->name : "imu");
	g = imu_utils_block(at.f, e, SSCOPE_QUANTITY_ANGULAR_RATE, "Gyr", "rad/s", "gyr");
	a = imu_utils_block(at.f, e, SSCOPE_QUANTITY_ACCELERATION, "Acc", "m/s^2", "acc");
	if (!g && !a) {
		ssc_file_close(&at, false);
		ssc_err(cmd, "--imu-utils: no fitted gyro (rad/s, deg/s, ...) or accelerometer (m/s^2, g, ...) channel");
		return SSC_EXIT_FAIL;
	}
	return ssc_file_close(&at, true);
}
