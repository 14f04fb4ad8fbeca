/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope model accel|fog: sensor physics calculators (textbook section
 * 5.1): the second-order proof-mass accelerometer and the Sagnac phase of
 * an interferometric fibre-optic gyro.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "plot.h"

#define NSTEP 21

enum {
	O_MASS = 300,
	O_STIFF,
	O_DAMP,
	O_FN,
	O_ZETA,
	O_STEP,
	O_DURATION,
	O_RADIUS,
	O_TURNS,
	O_WAVELENGTH,
	O_RATE,
	O_PLOT,
};

static const struct ssc_option model_opts[] = {
	{ "mass", required_argument, O_MASS, "KG", "accel: proof mass, kg" },
	{ "stiffness", required_argument, O_STIFF, "N/M",
	  "accel: spring constant, N/m" },
	{ "damping", required_argument, O_DAMP, "N*S/M",
	  "accel: damping coefficient, N s/m" },
	{ "fn", required_argument, O_FN, "HZ",
	  "accel: natural frequency instead of mass and stiffness (e.g. 2.4 kHz)" },
	{ "zeta", required_argument, O_ZETA, "Z",
	  "accel: damping ratio (with --fn)" },
	{ "step", required_argument, O_STEP, "A",
	  "accel: step input (default 1 g; units allowed)" },
	{ "duration", required_argument, O_DURATION, "T",
	  "accel: span of the step table and plot (default 1.5 x settling time)" },
	{ "radius", required_argument, O_RADIUS, "R",
	  "fog: coil radius (e.g. 5 cm)" },
	{ "turns", required_argument, O_TURNS, "N", "fog: number of turns" },
	{ "wavelength", required_argument, O_WAVELENGTH, "L",
	  "fog: vacuum wavelength (e.g. 1550 nm)" },
	{ "rate", required_argument, O_RATE, "V[,V...]",
	  "fog: rates for the phase table (default 1 deg/s, 15 deg/h)" },
	{ "plot", required_argument, O_PLOT, "PATH.svg|PATH.png",
	  "accel: step response; fog: phase against rate (PNG needs OpenCV)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "model",
	.usage = "model accel|fog [OPTIONS]",
	.summary =
		"Sensor physics calculators.  accel: second-order proof-mass\n"
		"accelerometer (m x'' + c x' + k x = m a): natural frequency, damping\n"
		"ratio, -3 dB bandwidth, resonance peak, displacement per g and the step\n"
		"response (analytic, checked against a Runge-Kutta integration).\n"
		"fog: Sagnac phase dphi = 8 pi^2 N R^2 Omega / (lambda c) of a coil of N\n"
		"turns of radius R at wavelength lambda, the scale factor and the largest\n"
		"rate inside the +-90 deg open-loop phase range.  (The textbook prints its\n"
		"eq. 92 without R^2 and lambda; this is the dimensionally correct form.)",
	.options = model_opts,
	.output_opts = true,
	.notes = "Examples:\n"
		 "  sensorscope model accel --mass 1e-9 --stiffness 0.2 --damping 1e-5\n"
		 "  sensorscope model accel --fn 2.4kHz --zeta 0.7 --plot step.png\n"
		 "  sensorscope model fog --radius 5cm --turns 1000 --wavelength 1550nm --rate 10deg/s",
};

struct opts {
	bool fog;
	double mass, stiff, damp, fn, zeta, step, duration;
	double radius, turns, wavelength;
	double rates[32];
	size_t n_rates;
	const char *plot;
	const char *accel_opt, *fog_opt; /* an option of each model given */
};

static int pos_number(const char *opt, const char *arg, double *out)
{
	if (ssc_arg_double("model", opt, arg, out))
		return SSC_EXIT_USAGE;
	if (!(*out > 0))
		return ssc_usage_error("model", "--%s: must be positive", opt);
	return 0;
}

static int pos_quantity(const char *opt, const char *arg, const char *si,
			double *out)
{
	if (ssc_arg_quantity("model", opt, arg, si, out))
		return SSC_EXIT_USAGE;
	if (!(*out > 0))
		return ssc_usage_error("model", "--%s: must be positive", opt);
	return 0;
}

/* a positive quantity within what the model's devices have: bare
 * numbers are SI, so a wavelength of '1550' is 1550 m */
static int quantity_in(const char *opt, const char *arg, const char *si,
		       double lo, double hi, const char *range, double *out)
{
	if (pos_quantity(opt, arg, si, out))
		return SSC_EXIT_USAGE;
	if (*out < lo || *out > hi)
		return ssc_usage_error("model", "--%s: '%s' is outside %s", opt, arg, range);
	return 0;
}

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;

	/* the options of the other model would be ignored: remember one */
	if (key >= O_MASS && key <= O_DURATION)
		o->accel_opt = model_opts[key - O_MASS].name;
	else if (key >= O_RADIUS && key <= O_RATE)
		o->fog_opt = model_opts[key - O_MASS].name;
	switch (key) {
	case O_MASS:
		return pos_number("mass", arg, &o->mass);
	case O_STIFF:
		return pos_number("stiffness", arg, &o->stiff);
	case O_DAMP:
		return pos_number("damping", arg, &o->damp);
	case O_FN:
		return quantity_in("fn", arg, "Hz", 1e-3, 1e7, "1 mHz .. 10 MHz", &o->fn);
	case O_ZETA:
		if (pos_number("zeta", arg, &o->zeta))
			return SSC_EXIT_USAGE;
		return o->zeta >= 1e-6 && o->zeta <= 1e3 ? 0 :
		       ssc_usage_error("model", "--zeta: '%s' is outside 1e-6 .. 1000", arg);
	case O_STEP:
		return ssc_arg_quantity("model", "step", arg, "m/s^2", &o->step);
	case O_DURATION:
		return quantity_in("duration", arg, "s", 0, 1e6, "0 .. 1e6 s", &o->duration);
	case O_RADIUS:
		return quantity_in("radius", arg, "m", 1e-4, 10, "0.1 mm .. 10 m", &o->radius);
	case O_TURNS:
		if (pos_number("turns", arg, &o->turns))
			return SSC_EXIT_USAGE;
		return o->turns <= 1e8 ? 0 :
		       ssc_usage_error("model", "--turns: '%s' is more than 1e8", arg);
	case O_WAVELENGTH:
		return quantity_in("wavelength", arg, "m", 1e-7, 2e-5,
				   "100 nm .. 20 um (bare numbers are metres: write 1550 nm)",
				   &o->wavelength);
	case O_RATE: {
		char *s = strdup(arg), *save = NULL, *tok;
		int rc = 0;

		o->n_rates = 0;
		for (tok = strtok_r(s, ",", &save); tok && !rc;
		     tok = strtok_r(NULL, ",", &save)) {
			if (o->n_rates == 32) {
				rc = ssc_usage_error("model", "--rate: at most 32 rates");
				break;
			}
			rc = ssc_arg_quantity("model", "rate", tok, "rad/s",
					      &o->rates[o->n_rates++]);
		}
		free(s);
		return rc;
	}
	case O_PLOT:
		o->plot = arg;
		return 0;
	default:
		return ssc_usage_error("model", "unexpected option");
	}
}

static int save_fig(struct ssc_fig *fig, const char *path)
{
	int rc = ssc_fig_save(fig, path);

	ssc_fig_free(fig);
	if (rc)
		return ssc_write_failed("model", path, rc);
	return SSC_EXIT_OK;
}

static int do_accel(struct ssc_common *co, struct opts *o)
{
	struct sscope_model_accel m;
	struct sscope_model_rk4_check chk;
	int rc;
	double T, dt, t[NSTEP], xa[NSTEP], *xr, maxdev = 0;
	size_t nr;
	char a[32], b[32];

	if (o->fn > 0 || o->zeta > 0) {
		if (!(o->fn > 0 && o->zeta > 0) || o->mass > 0 || o->stiff > 0 ||
		    o->damp > 0)
			return ssc_usage_error(co->cmd, "give --fn with --zeta, or --mass, --stiffness and --damping");
		rc = sscope_model_accel_fn(o->fn, o->zeta, &m);
	} else {
		if (!(o->mass > 0 && o->stiff > 0 && o->damp > 0))
			return ssc_usage_error(co->cmd, "give --mass, --stiffness and --damping (or --fn and --zeta)");
		rc = sscope_model_accel_mkc(o->mass, o->stiff, o->damp, &m);
	}
	if (rc)
		return ssc_fail(co->cmd, rc, NULL, "model accel");
	if (!(m.fn_hz >= 1e-3 && m.fn_hz <= 1e7))
		return ssc_usage_error(co->cmd, "--mass, --stiffness: a natural frequency of %g Hz, outside 1 mHz .. 10 MHz",
				       m.fn_hz);
	T = o->duration > 0 ? o->duration : 1.5 * m.settling_time_s;
	for (int i = 0; i < NSTEP; i++)
		t[i] = T * i / (NSTEP - 1);
	sscope_model_accel_step(&m, o->step, t, NSTEP, xa);
	/* the RK4 cross-check on a grid 400 steps per natural period */
	rc = sscope_model_accel_rk4_check(&m, o->step, T, 20000000, &xr, &chk);
	if (rc)
		return ssc_fail(co->cmd, rc, NULL, "model accel");
	dt = chk.dt_s;
	nr = chk.n;
	maxdev = chk.max_dev_m;
	if (o->plot) {
		enum { NP = 600 };
		double tp[NP], xp[NP], xq[NP];
		struct ssc_fig *fig = ssc_fig_new(1000, 650, 1, 1);
		struct ssc_ax *ax = ssc_fig_ax(fig, 0, 0);
		struct ssc_style sa = { .color = 0x1f77b4, .width = 2.5 };
		struct ssc_style sr = { .color = 0xd62728, .width = 1.2,
					.dash = SSC_DASHED };
		struct ssc_style ss = { .color = 0x7f7f7f, .width = 1,
					.dash = SSC_DOTTED };
		double xs = o->step / (m.omega_n_rad_s * m.omega_n_rad_s) * 1e6;
		char buf[256];

		for (int i = 0; i < NP; i++) {
			size_t k;

			tp[i] = T * i / (NP - 1);
			k = (size_t)lround(tp[i] / dt);
			if (k >= nr)
				k = nr - 1;
			xq[i] = xr[k] * 1e6;
			tp[i] = (double)k * dt;
		}
		sscope_model_accel_step(&m, o->step, tp, NP, xp);
		for (int i = 0; i < NP; i++) {
			xp[i] *= 1e6;
			tp[i] *= 1e3;
		}
		ssc_fig_title(fig, "second-order accelerometer: step response");
		ssc_ax_line(ax, tp, xp, NP, &sa, "analytic");
		ssc_ax_line(ax, tp, xq, NP, &sr, "Runge-Kutta");
		ssc_ax_hline(ax, xs, &ss, "static deflection a/ω_{n}^{2}");
		ssc_ax_xlabel(ax, "time (ms)");
		ssc_ax_ylabel(ax, "proof-mass deflection (µm)");
		snprintf(buf, sizeof(buf), "f_{n} = %.4g Hz, ζ = %.3g\nbandwidth %.4g Hz\novershoot %.3g %%, settling (2 %%) %.3g ms",
			 m.fn_hz, m.zeta, m.bandwidth_hz, m.overshoot * 100,
			 m.settling_time_s * 1e3);
		ssc_ax_note(ax, buf, SSC_LEGEND_LR);
		ssc_ax_legend(ax, SSC_LEGEND_UR);
		rc = save_fig(fig, o->plot);
		if (rc) {
			free(xr);
			return rc;
		}
	}
	if (co->format == SSC_FMT_JSON) {
		json_t *r = json_object(), *st = json_object(), *jt = json_array(),
		       *jx = json_array(), *jr = json_array(), *jtr = json_array();

		json_object_set_new(r, "command", json_string("model accel"));
		json_object_set_new(r, "mass_kg", ssc_jreal(m.mass_kg));
		json_object_set_new(r, "stiffness_n_m", ssc_jreal(m.stiffness_n_m));
		json_object_set_new(r, "damping_n_s_m", ssc_jreal(m.damping_n_s_m));
		json_object_set_new(r, "natural_frequency_hz", json_real(m.fn_hz));
		json_object_set_new(r, "omega_n_rad_s", json_real(m.omega_n_rad_s));
		json_object_set_new(r, "damping_ratio", json_real(m.zeta));
		json_object_set_new(r, "q_factor", json_real(m.q_factor));
		json_object_set_new(r, "damped_frequency_hz", ssc_jreal(m.fd_hz));
		json_object_set_new(r, "bandwidth_hz", json_real(m.bandwidth_hz));
		json_object_set_new(r, "resonance_peak", json_real(m.peak_gain));
		json_object_set_new(r, "displacement_per_g_m", json_real(m.displacement_per_g_m));
		json_object_set_new(st, "a_m_s2", json_real(o->step));
		json_object_set_new(st, "overshoot", json_real(m.overshoot));
		json_object_set_new(st, "rise_time_s", ssc_jreal(m.rise_time_s));
		json_object_set_new(st, "settling_time_s", json_real(m.settling_time_s));
		for (int i = 0; i < NSTEP; i++) {
			size_t k = (size_t)lround(t[i] / dt);

			if (k >= nr)
				k = nr - 1;
			json_array_append_new(jt, json_real(t[i]));
			json_array_append_new(jx, json_real(xa[i]));
			json_array_append_new(jtr, json_real((double)k * dt));
			json_array_append_new(jr, json_real(xr[k]));
		}
		json_object_set_new(st, "t_s", jt);
		json_object_set_new(st, "x_m", jx);
		json_object_set_new(st, "t_rk4_s", jtr);
		json_object_set_new(st, "x_rk4_m", jr);
		json_object_set_new(st, "rk4_step_s", json_real(dt));
		json_object_set_new(st, "max_rk4_deviation_m", json_real(maxdev));
		json_object_set_new(r, "step", st);
		free(xr);
		return ssc_emit_json(co, r);
	}
	{
		struct ssc_out out;

		rc = ssc_out_open(co, &out);
		if (rc) {
			free(xr);
			return rc;
		}
		if (co->format == SSC_FMT_CSV) {
			fprintf(out.f, "t_s,x_m\n");
			for (int i = 0; i < NSTEP; i++)
				fprintf(out.f, "%.10g,%.10g\n", t[i], xa[i]);
		} else {
			FILE *f = out.f;

			fprintf(f, "second-order accelerometer (m x'' + c x' + k x = m a)\n");
			if (isfinite(m.mass_kg))
				fprintf(f, "  mass %s kg, stiffness %s N/m, damping %s N s/m\n",
					ssc_fmt(a, sizeof(a), m.mass_kg, 5),
					ssc_fmt(b, sizeof(b), m.stiffness_n_m, 5),
					ssc_fmt((char[32]){ 0 }, 32, m.damping_n_s_m, 5));
			fprintf(f, "  natural frequency   %s Hz (%s rad/s)\n",
				ssc_fmt(a, sizeof(a), m.fn_hz, 6),
				ssc_fmt(b, sizeof(b), m.omega_n_rad_s, 6));
			fprintf(f, "  damping ratio       %s (Q %s)\n",
				ssc_fmt(a, sizeof(a), m.zeta, 5),
				ssc_fmt(b, sizeof(b), m.q_factor, 5));
			if (isfinite(m.fd_hz))
				fprintf(f, "  damped frequency    %s Hz\n",
					ssc_fmt(a, sizeof(a), m.fd_hz, 6));
			fprintf(f, "  bandwidth (-3 dB)   %s Hz, resonance peak x%s\n",
				ssc_fmt(a, sizeof(a), m.bandwidth_hz, 6),
				ssc_fmt(b, sizeof(b), m.peak_gain, 4));
			fprintf(f, "  displacement per g  %s m\n",
				ssc_fmt(a, sizeof(a), m.displacement_per_g_m, 5));
			fprintf(f, "  step of %s m/s^2: overshoot %s %%, rise (10-90 %%) %s s, settling (2 %%) %s s\n",
				ssc_fmt(a, sizeof(a), o->step, 5),
				ssc_fmt(b, sizeof(b), m.overshoot * 100, 4),
				ssc_fmt((char[32]){ 0 }, 32, m.rise_time_s, 4),
				ssc_fmt((char[32]){ 0 }, 32, m.settling_time_s, 4));
			fprintf(f, "  %12s %14s\n", "t (s)", "x (m)");
			for (int i = 0; i < NSTEP; i++)
				fprintf(f, "  %12s %14s\n", ssc_fmt(a, sizeof(a), t[i], 5),
					ssc_fmt(b, sizeof(b), xa[i], 6));
			fprintf(f, "  analytic vs Runge-Kutta (step %s s): largest difference %s m\n",
				ssc_fmt(a, sizeof(a), dt, 3), ssc_fmt(b, sizeof(b), maxdev, 3));
		}
		free(xr);
		return ssc_out_close(co, &out, !ferror(out.f));
	}
}

static int do_fog(struct ssc_common *co, struct opts *o)
{
	struct sscope_model_fog f;
	int rc;
	char a[32], b[32];

	if (!(o->radius > 0 && o->turns > 0 && o->wavelength > 0))
		return ssc_usage_error(co->cmd, "give --radius, --turns and --wavelength");
	rc = sscope_model_fog_coil(o->radius, o->turns, o->wavelength, &f);
	if (rc)
		return ssc_fail(co->cmd, rc, NULL, "model fog");
	if (o->n_rates == 0) {
		o->rates[0] = PI / 180;
		o->rates[1] = 15 * PI / 180 / 3600;
		o->n_rates = 2;
	}
	if (o->plot) {
		enum { NP = 401 };
		double x[NP], y[NP];
		struct ssc_fig *fig = ssc_fig_new(1000, 650, 1, 1);
		struct ssc_ax *ax = ssc_fig_ax(fig, 0, 0);
		struct ssc_style sl = { .color = 0x1f77b4, .width = 2.5 };
		struct ssc_style so = { .color = 0xd62728, .width = 1.5 };
		struct ssc_style sh = { .color = 0x7f7f7f, .width = 1, .dash = SSC_DASHED };
		double wmax = 1.5 * f.max_rate_rad_s;
		char buf[200];

		for (int i = 0; i < NP; i++) {
			double w = -wmax + 2 * wmax * i / (NP - 1);

			x[i] = w * 180 / PI;
			y[i] = sscope_model_fog_phase(&f, w) * 180 / PI;
		}
		ssc_fig_title(fig, "fibre-optic gyro: Sagnac phase");
		ssc_ax_line(ax, x, y, NP, &sl, "Δφ = 8π^{2}NR^{2}Ω/(λc)");
		for (int i = 0; i < NP; i++)
			y[i] = sin(y[i] * PI / 180) * 90;
		ssc_ax_line(ax, x, y, NP, &so, "open-loop output sin(Δφ), scaled to ±90");
		ssc_ax_hline(ax, 90, &sh, "±90° range");
		ssc_ax_hline(ax, -90, &sh, NULL);
		ssc_ax_xlabel(ax, "rate (°/s)");
		ssc_ax_ylabel(ax, "phase (°)");
		snprintf(buf, sizeof(buf), "R = %.4g m, N = %.6g, λ = %.5g nm\nL = %.4g m, scale factor %.4g s\nmax rate ±%.4g °/s",
			 f.radius_m, f.turns, f.wavelength_m * 1e9, f.fibre_length_m,
			 f.scale_factor_s, f.max_rate_rad_s * 180 / PI);
		ssc_ax_note(ax, buf, SSC_LEGEND_LR);
		ssc_ax_legend(ax, SSC_LEGEND_UL);
		rc = save_fig(fig, o->plot);
		if (rc)
			return rc;
	}
	if (co->format == SSC_FMT_JSON) {
		json_t *r = json_object(), *arr = json_array();

		json_object_set_new(r, "command", json_string("model fog"));
		json_object_set_new(r, "radius_m", json_real(f.radius_m));
		json_object_set_new(r, "turns", json_real(f.turns));
		json_object_set_new(r, "wavelength_m", json_real(f.wavelength_m));
		json_object_set_new(r, "fibre_length_m", json_real(f.fibre_length_m));
		json_object_set_new(r, "scale_factor_s", json_real(f.scale_factor_s));
		json_object_set_new(r, "max_rate_rad_s", json_real(f.max_rate_rad_s));
		json_object_set_new(r, "max_rate_deg_s", json_real(f.max_rate_rad_s * 180 / PI));
		for (size_t i = 0; i < o->n_rates; i++) {
			json_t *q = json_object();
			double ph = sscope_model_fog_phase(&f, o->rates[i]);

			json_object_set_new(q, "rate_rad_s", json_real(o->rates[i]));
			json_object_set_new(q, "phase_rad", json_real(ph));
			json_object_set_new(q, "phase_deg", json_real(ph * 180 / PI));
			json_object_set_new(q, "in_range", json_boolean(fabs(ph) <= PI / 2));
			json_array_append_new(arr, q);
		}
		json_object_set_new(r, "rates", arr);
		json_object_set_new(r, "formula", json_string("dphi = 8 pi^2 N R^2 Omega / (lambda c)"));
		return ssc_emit_json(co, r);
	}
	{
		struct ssc_out out;

		rc = ssc_out_open(co, &out);
		if (rc)
			return rc;
		if (co->format == SSC_FMT_CSV) {
			fprintf(out.f, "rate_rad_s,phase_rad\n");
			for (size_t i = 0; i < o->n_rates; i++)
				fprintf(out.f, "%.10g,%.10g\n", o->rates[i],
					sscope_model_fog_phase(&f, o->rates[i]));
		} else {
			FILE *fo = out.f;

			fprintf(fo, "fibre-optic gyro coil: R = %s m, N = %s turns, lambda = %s nm\n",
				ssc_fmt(a, sizeof(a), f.radius_m, 5),
				ssc_fmt(b, sizeof(b), f.turns, 6),
				ssc_fmt((char[32]){ 0 }, 32, f.wavelength_m * 1e9, 6));
			fprintf(fo, "  Sagnac phase dphi = 8 pi^2 N R^2 Omega / (lambda c)  (the textbook's eq. 92 omits R^2 and lambda)\n");
			fprintf(fo, "  fibre length     %s m\n", ssc_fmt(a, sizeof(a), f.fibre_length_m, 6));
			fprintf(fo, "  scale factor     %s rad per rad/s (%s deg per deg/s)\n",
				ssc_fmt(a, sizeof(a), f.scale_factor_s, 6),
				ssc_fmt(b, sizeof(b), f.scale_factor_s, 6));
			fprintf(fo, "  max rate (+-90 deg open loop)  %s deg/s\n",
				ssc_fmt(a, sizeof(a), f.max_rate_rad_s * 180 / PI, 6));
			for (size_t i = 0; i < o->n_rates; i++) {
				double ph = sscope_model_fog_phase(&f, o->rates[i]);

				fprintf(fo, "  rate %s deg/s: phase %s rad (%s deg)%s\n",
					ssc_fmt(a, sizeof(a), o->rates[i] * 180 / PI, 6),
					ssc_fmt(b, sizeof(b), ph, 6),
					ssc_fmt((char[32]){ 0 }, 32, ph * 180 / PI, 6),
					fabs(ph) > PI / 2 ? "  (outside the +-90 deg range)" : "");
			}
		}
		return ssc_out_close(co, &out, !ferror(out.f));
	}
}

int ssc_cmd_model(int argc, char **argv)
{
	struct ssc_common co;
	struct opts o = { .step = SSCOPE_UNIT_GRAVITY_STD };
	int first, rc;
	bool accel;

	if (argc >= 2 && (!strcmp(argv[1], "accel") || !strcmp(argv[1], "fog"))) {
		accel = !strcmp(argv[1], "accel");
		argc--;
		argv++;
	} else if (argc >= 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
		rc = ssc_parse(&spec, argc, argv, &co, handler, &o, &first);
		return rc < 0 ? SSC_EXIT_OK : rc;
	} else {
		return ssc_usage_error("model", "give 'accel' or 'fog' first");
	}
	rc = ssc_parse(&spec, argc, argv, &co, handler, &o, &first);
	if (rc)
		return rc < 0 ? SSC_EXIT_OK : rc;
	if (first < argc)
		return ssc_usage_error(co.cmd, "unexpected operand '%s'", argv[first]);
	if (accel ? o.fog_opt != NULL : o.accel_opt != NULL)
		return ssc_usage_error(co.cmd, "--%s: an option of 'model %s', not of 'model %s'",
				       accel ? o.fog_opt : o.accel_opt,
				       accel ? "fog" : "accel", accel ? "accel" : "fog");
	if (o.plot && (rc = ssc_plot_check(co.cmd, o.plot)))
		return rc;
	return accel ? do_accel(&co, &o) : do_fog(&co, &o);
}
