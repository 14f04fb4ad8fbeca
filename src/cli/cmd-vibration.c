/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope vibration: machinery vibration of accelerometer channels:
 * acceleration spectrum and peaks, velocity RMS in the ISO 10816 band and
 * its zone, shaft orders (--rpm) with unbalance / misalignment findings,
 * bearing defect frequencies and envelope analysis (--bearing) with
 * defect findings, kurtosis; --plot draws the spectrum with fault-frequency
 * markers and the envelope spectrum.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "plot.h"
#include "stage.h"


enum {
	OPT_RPM = 256,
	OPT_BEARING,
	OPT_ISO,
	OPT_TOL,
	OPT_ENV_BAND,
	OPT_WINDOW,
	OPT_NPERSEG,
	OPT_OVERLAP,
	OPT_PEAKS,
	OPT_ISO_BAND,
};

static const struct ssc_option vib_opts[] = {
	{ "rpm", required_argument, OPT_RPM, "R",
	  "shaft speed, rev/min: shaft orders, unbalance and misalignment" },
	{ "bearing", required_argument, OPT_BEARING, "N,d,D[,ANGLE]",
	  "rolling bearing: N elements, ball and pitch diameters (same unit), contact angle in degrees (default 0); needs --rpm" },
	{ "iso-class", required_argument, OPT_ISO, "I|II|III|IV",
	  "ISO 10816-1 machine class for the severity zone" },
	{ "tolerance", required_argument, OPT_TOL, "F",
	  "relative tolerance (slip) of order and defect matches (default 0.02)" },
	{ "envelope-band", required_argument, OPT_ENV_BAND, "LO:HI",
	  "band (Hz) demodulated for the envelope (default: largest spectral kurtosis)" },
	{ "iso-band", required_argument, OPT_ISO_BAND, "LO:HI",
	  "velocity band in Hz (default 10:1000; 2:1000 for slow machines)" },
	{ "window", required_argument, OPT_WINDOW, "NAME",
	  "window of the acceleration spectrum (default hann)" },
	{ "nperseg", required_argument, OPT_NPERSEG, "N",
	  "segment length of the spectrum (default: a power of two giving ~8 segments)" },
	{ "overlap", required_argument, OPT_OVERLAP, "F",
	  "segment overlap, fraction (default 0.5)" },
	{ "peaks", required_argument, OPT_PEAKS, "K",
	  "report the K strongest spectrum peaks (default 5, at most 16)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "vibration",
	.usage = "vibration [OPTIONS] FILE",
	.summary =
		"Machinery vibration of accelerometer channels.  Velocity RMS over\n"
		"10-1000 Hz by frequency-domain integration of the acceleration PSD and\n"
		"its ISO 10816-1 zone (--iso-class; the table of ISO 10816-1:1995 Annex B\n"
		"is shipped with the program: check it against your copy).  With --rpm:\n"
		"the 1x, 2x, 3x shaft orders and findings for unbalance (dominant 1x) and\n"
		"misalignment (strong 2x).  With --bearing: the defect frequencies BPFO,\n"
		"BPFI, BSF, FTF, the envelope spectrum (band-pass and Hilbert transform by\n"
		"FFT, band of largest spectral kurtosis) and defect findings when the\n"
		"fundamental and another harmonic of a defect frequency stand above the\n"
		"noise within the tolerance.  Kurtosis (3 for Gaussian noise) flags\n"
		"impulsive signals.  Each finding quotes its evidence.",
	.options = vib_opts,
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope vibration --rpm 1770 --iso-class II samples/vibration.csv\n"
		 "  sensorscope vibration --rpm 1797 --bearing 9,7.94,39.04 samples/bearing-outer.csv\n"
		 "  sensorscope vibration -r 12000 -u m/s^2 --rpm 1797 --bearing 9,7.94,39.04 record.mat\n"
		 "\n"
		 "Unbalance and misalignment are reported when the velocity reaches zone C\n"
		 "of the class (class I without --iso-class); bearing defects whatever the\n"
		 "level.  Channels must be accelerations (a unit such as m/s^2, g or mg;\n"
		 "-u for unlabelled columns).",
};

struct args {
	struct sscope_vib_opts vo;
	double overlap;
	double rpm;
	bool bearing, tol_set;
	const char *env_band;
};

static int parse_pair(const char *cmd, const char *opt, const char *arg,
		      double *lo, double *hi)
{
	const char *c = strchr(arg, ':');

	if (!c || ssc_parse_double(arg, c, lo) != (size_t)(c - arg) ||
	    ssc_parse_double(c + 1, c + strlen(c), hi) != strlen(c + 1) ||
	    !(*lo >= 0) || !(*hi > *lo) || !isfinite(*hi))
		return ssc_usage_error(cmd, "--%s: '%s' is not LO:HI in Hz", opt, arg);
	return 0;
}

static int handle(int key, const char *arg, void *ctx)
{
	struct args *a = ctx;
	size_t v;

	switch (key) {
	case OPT_RPM:
		return ssc_arg_positive("vibration", "rpm", arg, NULL, &a->rpm);
	case OPT_BEARING: {
		double f[4] = { 0, 0, 0, 0 };
		int n = 0;
		const char *p = arg;

		while (n < 4) {
			const char *e = strchr(p, ',');
			size_t l = e ? (size_t)(e - p) : strlen(p);

			if (ssc_parse_double(p, p + l, &f[n]) != l || l == 0)
				goto bad_bearing;
			n++;
			if (!e)
				break;
			p = e + 1;
		}
		if (n < 3 || strchr(p, ',') || f[0] < 1 || f[0] != floor(f[0]) ||
		    f[0] > 1000 || !(f[1] > 0) || !(f[2] > f[1]) ||
		    !(f[3] >= 0 && f[3] < 90))
			goto bad_bearing;
		a->bearing = true;
		a->vo.bearing.n_elements = (unsigned)f[0];
		a->vo.bearing.ball_diameter_m = f[1];
		a->vo.bearing.pitch_diameter_m = f[2];
		a->vo.bearing.contact_angle_rad = f[3] * PI / 180;
		return 0;
bad_bearing:
		return ssc_usage_error("vibration",
				       "--bearing: '%s' is not N,d,D[,angle]: N elements, ball diameter d < pitch diameter D, angle in [0, 90) degrees",
				       arg);
	}
	case OPT_ISO:
		if (!strcmp(arg, "I") || !strcmp(arg, "1"))
			a->vo.iso_class = SSCOPE_VIB_ISO_I;
		else if (!strcmp(arg, "II") || !strcmp(arg, "2"))
			a->vo.iso_class = SSCOPE_VIB_ISO_II;
		else if (!strcmp(arg, "III") || !strcmp(arg, "3"))
			a->vo.iso_class = SSCOPE_VIB_ISO_III;
		else if (!strcmp(arg, "IV") || !strcmp(arg, "4"))
			a->vo.iso_class = SSCOPE_VIB_ISO_IV;
		else
			return ssc_usage_error("vibration", "--iso-class: '%s' is not I, II, III or IV", arg);
		return 0;
	case OPT_TOL:
		if (ssc_arg_double("vibration", "tolerance", arg, &a->vo.tolerance))
			return SSC_EXIT_USAGE;
		if (!(a->vo.tolerance >= 0 && a->vo.tolerance < 0.2))
			return ssc_usage_error("vibration", "--tolerance: must be in [0, 0.2)");
		if (a->vo.tolerance == 0)
			a->vo.tolerance = -1; /* exact */
		a->tol_set = true;
		return 0;
	case OPT_ENV_BAND:
		return parse_pair("vibration", "envelope-band", arg,
				  &a->vo.env_lo_hz, &a->vo.env_hi_hz);
	case OPT_ISO_BAND:
		if (parse_pair("vibration", "iso-band", arg, &a->vo.iso_lo_hz,
			       &a->vo.iso_hi_hz))
			return SSC_EXIT_USAGE;
		if (!(a->vo.iso_lo_hz > 0))
			return ssc_usage_error("vibration", "--iso-band: the lower edge must be positive");
		return 0;
	case OPT_WINDOW:
		if (sscope_psd_window_from_name(arg, &a->vo.psd.window))
			return ssc_usage_error("vibration", "--window: unknown window '%s'", arg);
		return 0;
	case OPT_NPERSEG:
		if (ssc_arg_size("vibration", "nperseg", arg, &v))
			return SSC_EXIT_USAGE;
		if (v < 16 || v > ((size_t)1 << 26))
			return ssc_usage_error("vibration", "--nperseg: must be 16 to 2^26");
		a->vo.psd.nperseg = v;
		return 0;
	case OPT_OVERLAP:
		if (ssc_arg_double("vibration", "overlap", arg, &a->overlap))
			return SSC_EXIT_USAGE;
		if (!(a->overlap >= 0 && a->overlap < 1))
			return ssc_usage_error("vibration", "--overlap: must be in [0, 1)");
		return 0;
	case OPT_PEAKS:
		if (ssc_arg_size("vibration", "peaks", arg, &a->vo.n_peaks))
			return SSC_EXIT_USAGE;
		if (a->vo.n_peaks > 16)
			return ssc_usage_error("vibration", "--peaks: at most 16");
		if (a->vo.n_peaks == 0)
			a->vo.n_peaks = SSCOPE_VIB_NO_PEAKS;
		return 0;
	default:
		return ssc_usage_error("vibration", "unexpected option");
	}
}

struct chres {
	const struct sscope_capture_column *col;
	struct sscope_vib_result r;
	bool done;
};

static const char *class_name(enum sscope_vib_iso_class c)
{
	static const char *const n[] = { NULL, "I", "II", "III", "IV" };

	return c >= SSCOPE_VIB_ISO_I && c <= SSCOPE_VIB_ISO_IV ? n[c] : NULL;
}

static double usc(const struct sscope_capture_column *c)
{
	return c->unit.scale != 0 ? c->unit.scale : 1;
}

/* ------------------------------------------------------------ output */

static json_t *jarr(const double *v, size_t n, double div)
{
	json_t *a = json_array();

	for (size_t i = 0; i < n; i++)
		json_array_append_new(a, ssc_jreal(v[i] / div));
	return a;
}

static json_t *json_channel(const struct sscope_capture *cap,
			    const struct args *a, const struct chres *c,
			    json_t *alldiag)
{
	const struct sscope_vib_result *r = &c->r;
	const struct sscope_capture_column *col = c->col;
	double sc = usc(col);
	json_t *o = json_object(), *pk = json_array(), *sev = json_object();
	json_t *ord = json_array(), *ep = json_array(), *dg = json_array();
	char pu[96];

	snprintf(pu, sizeof(pu), "(%s)^2/Hz", col->unit_label);
	json_object_set_new(o, "name", json_string(col->name));
	json_object_set_new(o, "unit", json_string(col->unit_label));
	json_object_set_new(o, "rate_hz", json_real(cap->rate_hz));
	json_object_set_new(o, "samples", json_integer((json_int_t)cap->n));
	json_object_set_new(o, "scaling", json_string("density"));
	json_object_set_new(o, "psd_unit", json_string(pu));
	json_object_set_new(o, "nperseg", json_integer((json_int_t)r->accel.nperseg));
	json_object_set_new(o, "frequency_hz", jarr(r->accel.freq_hz, r->accel.n_bins, 1));
	json_object_set_new(o, "psd", jarr(r->accel.value, r->accel.n_bins, sc * sc));
	json_object_set_new(o, "rms", ssc_jreal(r->accel_rms_m_s2 / sc));
	for (size_t i = 0; i < r->n_peaks; i++) {
		json_t *e = json_object();

		json_object_set_new(e, "frequency_hz", ssc_jreal(r->peaks[i].frequency_hz));
		json_object_set_new(e, "value", ssc_jreal(r->peaks[i].value / (sc * sc)));
		json_object_set_new(e, "amplitude", ssc_jreal(r->peaks[i].amplitude / sc));
		json_array_append_new(pk, e);
	}
	json_object_set_new(o, "peaks", pk);
	json_object_set_new(sev, "velocity_rms_mm_s", ssc_jreal(r->velocity_rms_m_s * 1e3));
	if (r->zone) {
		char z[2] = { r->zone, 0 };

		json_object_set_new(sev, "zone", json_string(z));
	} else {
		json_object_set_new(sev, "zone", json_null());
	}
	json_object_set_new(sev, "class", class_name(a->vo.iso_class) ?
				  json_string(class_name(a->vo.iso_class)) : json_null());
	{
		json_t *b = json_array(), *zs = json_object();

		json_array_append_new(b, json_real(r->iso_lo_hz));
		json_array_append_new(b, json_real(r->iso_hi_hz));
		json_object_set_new(sev, "band_hz", b);
		for (int k = SSCOPE_VIB_ISO_I; k <= SSCOPE_VIB_ISO_IV; k++) {
			char z[2] = { 0, 0 };

			if (isfinite(r->velocity_rms_m_s) &&
			    !sscope_vib_iso_zone((enum sscope_vib_iso_class)k, r->velocity_rms_m_s, &z[0]))
				json_object_set_new(zs, class_name((enum sscope_vib_iso_class)k), json_string(z));
		}
		json_object_set_new(sev, "zones", zs);
	}
	json_object_set_new(o, "severity", sev);
	json_object_set_new(o, "kurtosis", ssc_jreal(r->kurtosis));
	if (a->rpm > 0) {
		json_object_set_new(o, "shaft_hz", json_real(a->rpm / 60));
		for (size_t i = 0; i < r->n_orders; i++) {
			const struct sscope_vib_order *od = &r->orders[i];
			json_t *e = json_object();

			json_object_set_new(e, "order", json_integer(od->order));
			json_object_set_new(e, "expected_hz", json_real(od->expected_hz));
			json_object_set_new(e, "found", json_boolean(od->found));
			json_object_set_new(e, "frequency_hz", od->found ? ssc_jreal(od->peak.frequency_hz) : json_null());
			json_object_set_new(e, "amplitude", od->found ? ssc_jreal(od->peak.amplitude / sc) : json_null());
			json_object_set_new(e, "velocity_rms_mm_s", od->found ? ssc_jreal(od->velocity_rms_m_s * 1e3) : json_null());
			json_array_append_new(ord, e);
		}
	}
	json_object_set_new(o, "orders", ord);
	if (r->have_bearing) {
		json_t *b = json_object(), *env = json_object(), *band = json_array();

		json_object_set_new(b, "bpfo_hz", json_real(r->bearing.bpfo_hz));
		json_object_set_new(b, "bpfi_hz", json_real(r->bearing.bpfi_hz));
		json_object_set_new(b, "bsf_hz", json_real(r->bearing.bsf_hz));
		json_object_set_new(b, "ftf_hz", json_real(r->bearing.ftf_hz));
		json_object_set_new(o, "bearing", b);
		json_array_append_new(band, json_real(r->env_lo_hz));
		json_array_append_new(band, json_real(r->env_hi_hz));
		json_object_set_new(env, "band_hz", band);
		json_object_set_new(env, "spectral_kurtosis", ssc_jreal(r->env_sk));
		json_object_set_new(env, "threshold", ssc_jreal(r->env_threshold));
		json_object_set_new(env, "frequency_hz", jarr(r->envelope.freq_hz, r->envelope.n_bins, 1));
		json_object_set_new(env, "spectrum", jarr(r->envelope.value, r->envelope.n_bins, sc * sc));
		json_object_set_new(o, "envelope", env);
		for (size_t i = 0; i < r->n_env_peaks; i++) {
			const struct sscope_vib_env_peak *p = &r->env_peaks[i];
			json_t *e = json_object();

			json_object_set_new(e, "frequency_hz", ssc_jreal(p->peak.frequency_hz));
			json_object_set_new(e, "value", ssc_jreal(p->peak.value / (sc * sc)));
			json_object_set_new(e, "amplitude", ssc_jreal(p->peak.amplitude / sc));
			json_object_set_new(e, "snr", ssc_jreal(p->snr));
			json_object_set_new(e, "match", p->match[0] ? json_string(p->match) : json_null());
			json_object_set_new(e, "expected_hz", ssc_jreal(p->expected_hz));
			json_array_append_new(ep, e);
		}
	}
	json_object_set_new(o, "envelope_peaks", ep);
	for (size_t i = 0; i < r->n_findings; i++) {
		json_t *e = json_object(), *e2 = json_object();

		json_object_set_new(e, "finding", json_string(r->findings[i].finding));
		json_object_set_new(e, "evidence", json_string(r->findings[i].evidence));
		json_array_append_new(dg, e);
		json_object_set_new(e2, "channel", json_string(col->name));
		json_object_set_new(e2, "finding", json_string(r->findings[i].finding));
		json_object_set_new(e2, "evidence", json_string(r->findings[i].evidence));
		json_array_append_new(alldiag, e2);
	}
	json_object_set_new(o, "diagnosis", dg);
	return o;
}

static void text_channel(FILE *f, const struct args *a, const struct chres *c)
{
	const struct sscope_vib_result *r = &c->r;
	const struct sscope_capture_column *col = c->col;
	const char *u = col->unit_label;
	double sc = usc(col);
	char b1[32], b2[32], b3[32];

	fprintf(f, "\n  %s (%s): rms %s %s, kurtosis %s%s\n", col->name, u,
		ssc_fmt(b1, sizeof(b1), r->accel_rms_m_s2 / sc, 5), u,
		ssc_fmt(b2, sizeof(b2), r->kurtosis, 4),
		r->kurtosis > 4 ? " (impulsive)" : "");
	fprintf(f, "    velocity %g-%g Hz: %s mm/s rms", r->iso_lo_hz, r->iso_hi_hz,
		ssc_fmt(b1, sizeof(b1), r->velocity_rms_m_s * 1e3, 4));
	if (r->zone) {
		fprintf(f, ", zone %c (class %s)\n", r->zone, class_name(a->vo.iso_class));
	} else {
		fprintf(f, ", zones by class:");
		for (int k = SSCOPE_VIB_ISO_I; k <= SSCOPE_VIB_ISO_IV; k++) {
			char z = 0;

			if (isfinite(r->velocity_rms_m_s))
				sscope_vib_iso_zone((enum sscope_vib_iso_class)k, r->velocity_rms_m_s, &z);
			fprintf(f, " %s %c", class_name((enum sscope_vib_iso_class)k), z ? z : '-');
		}
		fprintf(f, " (--iso-class picks one)\n");
	}
	if (r->n_peaks) {
		fprintf(f, "    peaks:");
		for (size_t i = 0; i < r->n_peaks; i++)
			fprintf(f, "%s %s Hz (%s %s)", i ? "," : "",
				ssc_fmt(b1, sizeof(b1), r->peaks[i].frequency_hz, 5),
				ssc_fmt(b2, sizeof(b2), r->peaks[i].amplitude / sc, 3), u);
		fputc('\n', f);
	}
	if (a->rpm > 0) {
		fprintf(f, "    orders (%g rpm = %s Hz):\n", a->rpm,
			ssc_fmt(b1, sizeof(b1), a->rpm / 60, 5));
		for (size_t i = 0; i < r->n_orders; i++) {
			const struct sscope_vib_order *od = &r->orders[i];

			if (od->found)
				fprintf(f, "      %ux  %10s Hz  %10s %s  %8s mm/s rms\n", od->order,
					ssc_fmt(b1, sizeof(b1), od->peak.frequency_hz, 5),
					ssc_fmt(b2, sizeof(b2), od->peak.amplitude / sc, 4), u,
					ssc_fmt(b3, sizeof(b3), od->velocity_rms_m_s * 1e3, 4));
			else
				fprintf(f, "      %ux  %10s Hz  no line above the noise within the tolerance\n", od->order,
					ssc_fmt(b1, sizeof(b1), od->expected_hz, 5));
		}
	}
	if (r->have_bearing) {
		fprintf(f, "    bearing: BPFO %.2f Hz, BPFI %.2f Hz, BSF %.2f Hz, FTF %.2f Hz\n",
			r->bearing.bpfo_hz, r->bearing.bpfi_hz, r->bearing.bsf_hz,
			r->bearing.ftf_hz);
		fprintf(f, "    envelope of %.0f-%.0f Hz (spectral kurtosis %.2f), lines above %.1fx the local floor:\n",
			r->env_lo_hz, r->env_hi_hz, r->env_sk, r->env_threshold);
		for (size_t i = 0; i < r->n_env_peaks; i++) {
			const struct sscope_vib_env_peak *p = &r->env_peaks[i];

			if (p->snr < r->env_threshold)
				continue;
			fprintf(f, "      %9s Hz  %9s %s  %5.0fx  %s\n",
				ssc_fmt(b1, sizeof(b1), p->peak.frequency_hz, 5),
				ssc_fmt(b2, sizeof(b2), p->peak.amplitude / sc, 3), u,
				p->snr, p->match[0] ? p->match : "-");
		}
	}
	if (r->n_findings == 0) {
		fprintf(f, "    diagnosis: no fault finding\n");
	} else {
		fprintf(f, "    diagnosis:\n");
		for (size_t i = 0; i < r->n_findings; i++)
			fprintf(f, "      %s: %s\n", r->findings[i].finding,
				r->findings[i].evidence);
	}
}

/* ------------------------------------------------------------ plot */

/* a dashed fault-frequency line; the label goes into the legend */
static void marker(struct ssc_ax *ax, double x, uint32_t color,
		   const char *label)
{
	struct ssc_style st = { .color = color, .width = 1.2, .dash = SSC_DASHED };

	ssc_ax_vline(ax, x, &st, label);
}

struct vib_res {
	const char *path;
	const struct sscope_capture *cap;
	struct args a;     /* the options as run (overlap resolved) */
	struct chres *cr;
	size_t n;
};

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *path)
{
	const struct vib_res *R = result;
	const struct sscope_capture *cap = R->cap;
	const struct args *a = &R->a;
	const struct chres *cr = R->cr;
	size_t nch = R->n;
	size_t np = nch < 3 ? nch : 3;
	bool env = cr[0].r.have_bearing;
	int rows = (int)(np * (env ? 2 : 1)), row = 0, rc;
	struct ssc_fig *fig = ssc_fig_new(1100, 120 + 380 * rows, rows, 1);
	char buf[256];

	if (!fig)
		return SSC_EXIT_FAIL;
	(void)opts;
	if (!nch) {
		ssc_fig_free(fig);
		return SSC_EXIT_OK;
	}
	snprintf(buf, sizeof(buf), "%s: vibration", R->path);
	ssc_fig_title(fig, buf);
	for (size_t k = 0; k < np; k++) {
		const struct sscope_vib_result *r = &cr[k].r;
		const struct sscope_capture_column *col = cr[k].col;
		double sc = usc(col), fhi = cap->rate_hz / 2, ymax = 0;
		double *amp = malloc(r->accel.n_bins * sizeof(double));
		struct ssc_ax *ax = ssc_fig_ax(fig, row++, 0);
		struct ssc_style st = { .color = ssc_plot_color(0), .width = 1.2 };

		if (!amp)
			break;
		if (a->rpm > 0 && !r->have_bearing && fhi > 1000 &&
		    fhi > 12 * a->rpm / 60)
			fhi = fmax(1000, 12 * a->rpm / 60);
		double amp_floor = 0;

		/* amplitude spectrum: the sine amplitude of each line */
		for (size_t i = 0; i < r->accel.n_bins; i++) {
			amp[i] = sqrt(2 * r->accel.value[i] * r->accel.enbw_hz) / sc;
			ymax = fmax(ymax, amp[i]);
		}
		{
			double *c = malloc(r->accel.n_bins * sizeof(double));

			if (c) {
				memcpy(c, r->accel.value, r->accel.n_bins * sizeof(double));
				qsort(c, r->accel.n_bins, sizeof(double), ssc_cmp_double);
				amp_floor = c[r->accel.n_bins / 2];
				free(c);
			}
		}
		/* log frequency: the shaft orders sit at the low end */
		ssc_ax_log(ax, true, true);
		ssc_ax_line(ax, r->accel.freq_hz, amp, r->accel.n_bins, &st, NULL);
		if (r->accel.n_bins > 1)
			ssc_ax_xlim(ax, r->accel.freq_hz[1], fhi);
		if (a->rpm > 0)
			for (size_t i = 0; i < r->n_orders; i++) {
				snprintf(buf, sizeof(buf),
					 "shaft orders 1\xc3\x97, 2\xc3\x97, 3\xc3\x97 of %.4g Hz",
					 a->rpm / 60);
				marker(ax, r->orders[i].expected_hz, 0xd62728,
				       i ? NULL : buf);
			}
		for (size_t i = 0; i < r->n_peaks && i < 5; i++) {
			struct ssc_style mk = { .color = 0x1f77b4, .width = -1,
						.marker = SSC_MK_CIRCLE };
			double px = r->peaks[i].frequency_hz, py = r->peaks[i].amplitude / sc;

			/* label lines, not the largest noise bins */
			if (px > fhi || r->peaks[i].value < 10 * amp_floor)
				continue;
			ssc_ax_line(ax, &px, &py, 1, &mk, NULL);
			snprintf(buf, sizeof(buf), " %.4g Hz", px);
			ssc_ax_text(ax, px, py * 1.5, buf, -1, 0x1f77b4);
		}
		{
			double ymin = ymax;

			for (size_t i = 1; i < r->accel.n_bins; i++)
				if (amp[i] > 0 && amp[i] < ymin)
					ymin = amp[i];
			ssc_ax_ylim(ax, ymin * 0.2, ymax * 6);
		}
		ssc_ax_legend(ax, SSC_LEGEND_LR);
		snprintf(buf, sizeof(buf), "%s: amplitude spectrum (%s)", col->name, col->unit_label);
		ssc_ax_title(ax, buf);
		snprintf(buf, sizeof(buf), "amplitude (%s)", col->unit_label);
		ssc_ax_ylabel(ax, buf);
		ssc_ax_xlabel(ax, "frequency (Hz)");
		snprintf(buf, sizeof(buf), "velocity %.3g mm/s rms (%g-%g Hz)%s%s\nkurtosis %.2f",
			 r->velocity_rms_m_s * 1e3, r->iso_lo_hz, r->iso_hi_hz,
			 r->zone ? ", zone " : "", r->zone ? (char[2]){ r->zone, 0 } : "",
			 r->kurtosis);
		ssc_ax_note(ax, buf, SSC_LEGEND_UR);
		free(amp);
		if (env && r->have_bearing && r->envelope.n_bins > 2) {
			static const uint32_t col4[4] = { 0xd62728, 0x9467bd, 0x2ca02c, 0x8c564b };
			const char *nm[4] = { "BPFO", "BPFI", "BSF", "FTF" };
			double fd[4] = { r->bearing.bpfo_hz, r->bearing.bpfi_hz,
					 r->bearing.bsf_hz, r->bearing.ftf_hz };
			double emax = 0, xmax = fmin(5.5 * fmax(fd[1], 2 * fd[2]),
						     r->env_hi_hz - r->env_lo_hz);
			double *ea = malloc(r->envelope.n_bins * sizeof(double));
			struct ssc_style es = { .color = 0x333333, .width = 1.2 };

			ax = ssc_fig_ax(fig, row++, 0);
			if (!ea)
				break;
			for (size_t i = 0; i < r->envelope.n_bins; i++) {
				ea[i] = sqrt(2 * r->envelope.value[i]) / sc;
				if (r->envelope.freq_hz[i] > 2 && r->envelope.freq_hz[i] <= xmax)
					emax = fmax(emax, ea[i]);
			}
			ssc_ax_line(ax, r->envelope.freq_hz, ea, r->envelope.n_bins, &es, NULL);
			ssc_ax_xlim(ax, 0, xmax);
			ssc_ax_ylim(ax, 0, emax * 1.6 > 0 ? emax * 1.6 : 1);
			ssc_ax_legend(ax, SSC_LEGEND_UR);
			for (int d = 0; d < 4; d++)
				for (unsigned h = 1; h <= 5; h++) {
					double fx = h * fd[d] * (d == 2 ? 2 : 1);

					if (fx > xmax)
						break;
					snprintf(buf, sizeof(buf), "%s %.1f Hz and harmonics",
						 d == 2 ? "2xBSF" : nm[d], fx);
					marker(ax, fx, col4[d], h == 1 ? buf : NULL);
				}
			for (size_t i = 0; i < r->n_env_peaks; i++) {
				const struct sscope_vib_env_peak *p = &r->env_peaks[i];
				double px = p->peak.frequency_hz, py = sqrt(2 * p->peak.value) / sc;

				if (p->snr < r->env_threshold || !p->match[0])
					continue;
				ssc_ax_text(ax, px, py + emax * 0.05, p->match, -1, 0x111111);
			}
			snprintf(buf, sizeof(buf), "%s: envelope spectrum of %.0f-%.0f Hz: %s%s",
				 col->name, r->env_lo_hz, r->env_hi_hz,
				 r->n_findings ? r->findings[r->n_findings - 1].finding :
						 "no bearing finding",
				 r->n_findings > 1 ? " (and more)" : "");
			ssc_ax_title(ax, buf);
			snprintf(buf, sizeof(buf), "envelope amplitude (%s)", col->unit_label);
			ssc_ax_ylabel(ax, buf);
			ssc_ax_xlabel(ax, "frequency (Hz)");
			free(ea);
		}
	}
	rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

static void init(void *opts)
{
	struct args *a = opts;

	memset(a, 0, sizeof(*a));
	sscope_vib_opts_init(&a->vo);
	a->overlap = 0.5;
}

static int check(struct ssc_common *co, void *opts)
{
	struct args *a = opts;

	if (a->bearing && !(a->rpm > 0))
		return ssc_usage_error(co->cmd, "--bearing needs --rpm (the shaft speed)");
	if (a->tol_set && !(a->rpm > 0))
		return ssc_usage_error(co->cmd, "--tolerance: matches shaft orders and bearing defects, which need --rpm");
	a->vo.shaft_hz = a->rpm / 60;
	a->vo.have_bearing = a->bearing;
	return SSC_EXIT_OK;
}

static void free_result(void *result)
{
	struct vib_res *R = result;

	for (size_t k = 0; k < R->n; k++)
		if (R->cr[k].done)
			sscope_vib_result_clear(&R->cr[k].r);
	free(R->cr);
	free(R);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	char b1[48], b2[48];
	const struct ssc_common *co = env->co;
	struct vib_res *R;
	struct args *a;
	struct sscope_capture *cap;
	const char *path;
	int rc;

	if (env->n_caps != 1) {
		ssc_err(co->cmd, "one input capture at a time");
		return SSC_EXIT_USAGE;
	}
	cap = env->caps[0];
	path = env->paths[0];
	rc = ssc_time_check(co, path, cap, true);
	if (rc)
		return rc;
	if (!(cap->rate_hz > 0)) {
		return ssc_err_no_rate(co->cmd, path, cap->rate_note);
	}
	R = calloc(1, sizeof(*R));
	if (R)
		R->cr = calloc(cap->n_channels ? cap->n_channels : 1, sizeof(*R->cr));
	if (!R || !R->cr) {
		free(R);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = R;
	R->path = path;
	R->cap = cap;
	R->a = *(struct args *)opts;
	a = &R->a;
	if (a->vo.psd.nperseg == 0 && a->overlap != 0.5)
		a->vo.psd.nperseg = sscope_vib_default_nperseg(cap->n);
	if (a->vo.psd.nperseg > cap->n && cap->n) {
		ssc_warn(co, "%s: --nperseg %zu is longer than the record (%zu samples): one segment of %zu",
			 path, a->vo.psd.nperseg, cap->n, cap->n);
		a->vo.psd.nperseg = cap->n;
	}
	ssc_warn_time_gaps(co, path, ssc_time_gaps(cap));
	if (a->rpm / 60 > cap->rate_hz / 2)
		ssc_warn(co, "%s: --rpm %g puts the shaft at %s Hz, above the Nyquist frequency %s Hz: no shaft order can be seen (check --rpm and the rate)",
			 path, a->rpm, ssc_fmt(b1, sizeof(b1), a->rpm / 60, 5),
			 ssc_fmt(b2, sizeof(b2), cap->rate_hz / 2, 5));
	if (a->vo.psd.nperseg)
		a->vo.psd.noverlap = sscope_psd_noverlap(a->overlap, a->vo.psd.nperseg);
	for (size_t k = 0; k < cap->n_channels; k++, R->n++) {
		const struct sscope_capture_column *col = &cap->channels[k].col;
		struct sscope_diag d = { "" };

		R->cr[k].col = col;
		if (col->quantity != SSCOPE_QUANTITY_ACCELERATION) {
			ssc_err(co->cmd, "%s: channel %s %s%s: not an acceleration (select accelerometer channels with -c; -u m/s^2 or g for unlabelled columns)",
				path, col->name, col->unit_label[0] ? "is in " : "has no unit",
				col->unit_label);
			return SSC_EXIT_FAIL;
		}
		rc = sscope_vib_analyze(cap->channels[k].data, 1, cap->n,
					cap->rate_hz, &a->vo, &R->cr[k].r, &d);
		if (rc) {
			ssc_err(co->cmd, "%s: channel %s: %s", path, col->name,
				d.msg[0] ? d.msg : sscope_strerror(rc));
			return rc == -EINVAL ? SSC_EXIT_USAGE : SSC_EXIT_FAIL;
		}
		R->cr[k].done = true;
	}
	if (cap->n_channels && a->vo.iso_hi_hz > cap->rate_hz / 2)
		ssc_warn(co, "%s: the velocity band ends at the Nyquist frequency %g Hz, not %g Hz",
			 path, cap->rate_hz / 2, a->vo.iso_hi_hz);
	return SSC_EXIT_OK;
}

static json_t *json(const void *opts, const void *result)
{
	const struct vib_res *R = result;
	json_t *o = json_object(), *chs = json_array(), *dg = json_array();

	(void)opts;
	json_object_set_new(o, "command", json_string("vibration"));
	json_object_set_new(o, "file", json_string(R->path));
	json_object_set_new(o, "iso_edition", json_string(sscope_vib_iso_edition()));
	for (size_t k = 0; k < R->n; k++)
		json_array_append_new(chs, json_channel(R->cap, &R->a, &R->cr[k], dg));
	json_object_set_new(o, "channels", chs);
	json_object_set_new(o, "diagnosis", dg);
	return o;
}

static void csv(FILE *f, const void *opts, const void *result)
{
	const struct vib_res *R = result;

	(void)opts;
	fprintf(f, "file,channel,unit,rate_hz,samples,rms,velocity_rms_mm_s,zone,kurtosis,findings\n");
	for (size_t k = 0; k < R->n; k++) {
		const struct sscope_vib_result *r = &R->cr[k].r;

		fprintf(f, "%s,%s,%s,%.15g,%zu,%.15g,%.15g,%c,%.15g,", R->path,
			R->cr[k].col->name, R->cr[k].col->unit_label, R->cap->rate_hz,
			R->cap->n, r->accel_rms_m_s2 / usc(R->cr[k].col),
			r->velocity_rms_m_s * 1e3, r->zone ? r->zone : '-',
			r->kurtosis);
		for (size_t i = 0; i < r->n_findings; i++)
			fprintf(f, "%s%s", i ? ";" : "", r->findings[i].finding);
		fputc('\n', f);
	}
}

static void text(FILE *f, const void *opts, const void *result)
{
	const struct vib_res *R = result;

	(void)opts;
	fprintf(f, "%s\n", strcmp(R->path, "-") ? R->path : "(stdin)");
	fprintf(f, "  rate: %g Hz, %zu samples; spectrum: %s window, nperseg %zu (%.3g Hz bins)\n",
		R->cap->rate_hz, R->cap->n, sscope_psd_window_name(R->a.vo.psd.window),
		R->n ? R->cr[0].r.accel.nperseg : 0,
		R->n ? R->cr[0].r.accel.bin_hz : 0.0);
	fprintf(f, "  severity zones: %s\n", sscope_vib_iso_edition());
	for (size_t k = 0; k < R->n; k++)
		text_channel(f, &R->a, &R->cr[k]);
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct vib_res *R = result;

	(void)opts;
	for (size_t k = 0; k < R->n; k++) {
		const struct sscope_vib_result *r = &R->cr[k].r;
		char note[64] = "";

		if (r->zone)
			snprintf(note, sizeof(note), "ISO 10816 zone %c", r->zone);
		ssc_summary_add(rows, R->cr[k].col->name, "velocity RMS",
				r->velocity_rms_m_s * 1e3, NAN, NAN, "mm/s", note);
		ssc_summary_add(rows, R->cr[k].col->name, "kurtosis",
				r->kurtosis, NAN, NAN, "", NULL);
		for (size_t i = 0; i < r->n_findings; i++)
			ssc_summary_add(rows, R->cr[k].col->name, "finding",
					NAN, NAN, NAN, "", r->findings[i].finding);
	}
}

const struct ssc_stage_ops ssc_vibration_stage = {
	.spec = &spec,
	.title = "Machinery vibration",
	.needs = SSC_NEED_DATA,
	.min_files = 1,
	.max_files = 1,
	.opts_size = sizeof(struct args),
	.init = init,
	.handle = handle,
	.check = check,
	.run = run,
	.json = json,
	.text = text,
	.csv = csv,
	.summary = summary,
	.plot = plot,
	.free_result = free_result,
};

int ssc_cmd_vibration(int argc, char **argv)
{
	return ssc_stage_main(&ssc_vibration_stage, argc, argv);
}
