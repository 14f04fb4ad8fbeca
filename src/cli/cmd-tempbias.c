/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensorscope tempbias: bias against temperature (analysis/tempbias.c) for
 * every data channel of one or more static captures with a temperature
 * column (several files = several power cycles): polynomial about T_ref
 * with coefficient uncertainties, hysteresis, gradient term, turn-on
 * repeatability, in-run stability after compensation and a compensation
 * table.
 */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "plot.h"
#include "stage.h"

enum {
	O_ORDER = 300,
	O_REF,
	O_BIN,
	O_SMOOTH,
	O_DEADBAND,
	O_WARMUP,
	O_NOHYST,
	O_NOGRAD,
	O_STEP,
	O_MINSPAN,
};

/* what separates the hysteresis and gradient terms (shown when they are
 * collinear) */
#define TB_SEPARATE \
	"a profile whose rate varies within heating and within cooling, e.g. a sine cycle"

static const struct ssc_option tb_opts[] = {
	{ "order", required_argument, O_ORDER, "K|auto",
	  "polynomial order 0..4 (default auto: F test at 1 %, at most one order per 5 degC of span)" },
	{ "ref-temp", required_argument, O_REF, "T",
	  "reference temperature of the polynomial (default mid-range; units allowed: 293.15K)" },
	{ "bin", required_argument, O_BIN, "DEGC", "temperature bin width (default span/100)" },
	{ "smooth", required_argument, O_SMOOTH, "S",
	  "window of the temperature smoothing and dT/dt (default 60 s)" },
	{ "deadband", required_argument, O_DEADBAND, "DEGC_PER_S",
	  "heating/cooling by a dead band of dT/dt in degC/s, 'auto' = 10 % of the 95th percentile of |dT/dt| (default: turning points of the temperature)" },
	{ "warmup", required_argument, O_WARMUP, "S",
	  "drop S seconds from the start of each file (default: detected)" },
	{ "no-hysteresis", no_argument, O_NOHYST, NULL, "no heating/cooling term" },
	{ "no-gradient", no_argument, O_NOGRAD, NULL, "no dT/dt term" },
	{ "table-step", required_argument, O_STEP, "DEGC",
	  "compensation table step (default 0.1/0.2/0.5/1/2/5/10 degC, <= 40 rows)" },
	{ "min-span", required_argument, O_MINSPAN, "DEGC",
	  "refuse a smaller temperature span (default 1 degC)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_command_spec spec = {
	.name = "tempbias",
	.usage = "tempbias [OPTIONS] FILE...",
	.summary =
		"Bias against temperature of every data channel of static captures with a\n"
		"temperature column (one file per power cycle, or one long file):\n"
		"b(T) = sum c_k (T - T_ref)^k by weighted least squares on temperature bins\n"
		"(centred and scaled variable), order by F test and capped by the span,\n"
		"coefficient uncertainties, heating/cooling hysteresis (IEEE 528), a\n"
		"dT/dt gradient term, turn-on to turn-on repeatability over the files,\n"
		"in-run stability after compensation (minimum Allan deviation of the\n"
		"residuals), and a compensation table.",
	.options = tb_opts,
	.analysis = true,
	.notes = "Examples:\n"
		 "  sensorscope tempbias samples/accel-thermal.csv\n"
		 "  sensorscope tempbias --order 3 --ref-temp 20 -c az --plot tb.png samples/accel-thermal.csv\n"
		 "Turn-on repeatability: 1 sigma (n-1) and max - min of the settled biases of the\n"
		 "files at T_ref after removing the common temperature curve, warm-up dropped.\n"
		 "Exit 1 when a file has no temperature column or the span is too small.",
};

struct opts {
	struct sscope_tempbias_opts t;
};

static int handler(int key, const char *arg, void *ctx)
{
	struct opts *o = ctx;
	double v;

	switch (key) {
	case O_ORDER:
		if (!strcmp(arg, "auto")) {
			o->t.order_auto = true;
			o->t.order = -1;
			return 0;
		}
		if (ssc_arg_double("tempbias", "order", arg, &v))
			return SSC_EXIT_USAGE;
		if (v != floor(v) || v < 0 || v > SSCOPE_TEMPBIAS_MAX_ORDER)
			return ssc_usage_error("tempbias", "--order: '%s' is not auto or 0..%d",
					       arg, SSCOPE_TEMPBIAS_MAX_ORDER);
		o->t.order_auto = false;
		o->t.order = (int)v;
		return 0;
	case O_REF:
		o->t.ref_temp_set = true;
		if (ssc_arg_quantity("tempbias", "ref-temp", arg, "degC",
				     &o->t.ref_temp_degc))
			return SSC_EXIT_USAGE;
		return o->t.ref_temp_degc >= -273.15 ? 0 :
		       ssc_usage_error("tempbias", "--ref-temp: '%s' is below absolute zero", arg);
	case O_BIN:
		return ssc_arg_positive("tempbias", "bin", arg, NULL, &o->t.bin_degc);
	case O_SMOOTH:
		return ssc_arg_positive("tempbias", "smooth", arg, "s", &o->t.smooth_s);
	case O_DEADBAND:
		o->t.rate_deadband = true;
		if (!strcmp(arg, "auto")) {
			o->t.deadband_degc_s = 0;
			return 0;
		}
		return ssc_arg_positive("tempbias", "deadband", arg, NULL, &o->t.deadband_degc_s);
	case O_WARMUP:
		o->t.warmup_set = true;
		if (ssc_arg_quantity("tempbias", "warmup", arg, "s", &o->t.warmup_s))
			return SSC_EXIT_USAGE;
		if (!(o->t.warmup_s >= 0))
			return ssc_usage_error("tempbias", "--warmup: must not be negative");
		return 0;
	case O_NOHYST:
		o->t.no_hysteresis = true;
		return 0;
	case O_NOGRAD:
		o->t.no_gradient = true;
		return 0;
	case O_STEP:
		return ssc_arg_positive("tempbias", "table-step", arg, NULL, &o->t.table_step_degc);
	case O_MINSPAN:
		return ssc_arg_positive("tempbias", "min-span", arg, NULL, &o->t.min_span_degc);
	}
	return SSC_EXIT_USAGE;
}

static void init(void *opts)
{
	struct opts *o = opts;

	memset(o, 0, sizeof(*o));
	o->t.order_auto = true;
	o->t.order = -1;
}

/* Display unit of a channel: deg/h for rates, mg for accelerations, the
 * file's unit otherwise. */
struct dunit {
	char label[32];
	struct sscope_unit u;
};

static void display_unit(const struct sscope_capture_column *col, struct dunit *d)
{
	const char *l = NULL;

	if (col->quantity == SSCOPE_QUANTITY_ANGULAR_RATE)
		l = "deg/h";
	else if (col->quantity == SSCOPE_QUANTITY_ACCELERATION)
		l = "mg";
	if (l && !sscope_unit_parse(l, &d->u, NULL)) {
		snprintf(d->label, sizeof(d->label), "%s", l);
		return;
	}
	d->u = col->unit;
	snprintf(d->label, sizeof(d->label), "%s", col->unit_label);
}

/* a difference / coefficient from SI to the display unit */
static double du(const struct dunit *d, double si)
{
	return si / d->u.scale;
}

struct chan {
	const char *name;
	struct dunit d;
	struct sscope_tempbias_result *res;
};

static json_t *chan_json(const struct chan *ch, size_t n_runs)
{
	const struct sscope_tempbias_result *r = ch->res;
	json_t *o = json_object(), *fit = json_object(), *c = json_array(),
	       *csd = json_array(), *tab = json_array(), *runs = json_array();
	char k[48];

	json_object_set_new(o, "channel", json_string(ch->name));
	json_object_set_new(o, "unit", json_string(ch->d.label));
	json_object_set_new(fit, "ref_temp_degc", json_real(r->ref_temp_degc));
	json_object_set_new(fit, "order", json_integer(r->order));
	json_object_set_new(fit, "order_requested",
			    r->order_requested < 0 ? json_string("auto") :
						     json_integer(r->order_requested));
	json_object_set_new(fit, "order_cap", json_integer(r->order_cap));
	for (int i = 0; i <= r->order; i++) {
		json_array_append_new(c, ssc_jreal(du(&ch->d, r->coef[i])));
		json_array_append_new(csd, ssc_jreal(du(&ch->d, r->coef_sd[i])));
	}
	json_object_set_new(fit, "coefficients", c);
	json_object_set_new(fit, "coefficient_sd", csd);
	json_object_set_new(fit, "coefficient_sd_method", json_string(
		"sandwich of the time-ordered block scores under white noise, a random walk and flicker (bias instability) of the bias, their levels by REML (Kalman filter per file)"));
	snprintf(k, sizeof(k), "%s/degC^k", ch->d.label);
	json_object_set_new(fit, "coefficient_unit", json_string(k));
	json_object_set_new(fit, "residual_rms", ssc_jreal(du(&ch->d, r->residual_rms)));
	json_object_set_new(fit, "dof", ssc_jreal(r->dof));
	json_object_set_new(fit, "temp_min_degc", json_real(r->temp_min_degc));
	json_object_set_new(fit, "temp_max_degc", json_real(r->temp_max_degc));
	json_object_set_new(fit, "criterion", json_string(
		"F test at 1 %; order <= span / 5 degC, < distinct temperature levels, <= 4"));
	if (*r->note)
		json_object_set_new(fit, "note", json_string(r->note));
	json_object_set_new(o, "fit", fit);
	json_object_set_new(o, "sensitivity", ssc_jreal(du(&ch->d, r->sensitivity)));
	json_object_set_new(o, "sensitivity_sd", ssc_jreal(du(&ch->d, r->sensitivity_sd)));
	json_object_set_new(o, "peak_to_peak", ssc_jreal(du(&ch->d, r->peak_to_peak)));
	{
		json_t *h = json_object();

		json_object_set_new(h, "max", r->have_split ?
				    ssc_jreal(du(&ch->d, r->hysteresis_max)) : json_null());
		json_object_set_new(h, "at_degc", r->have_split ?
				    ssc_jreal(r->hysteresis_at_degc) : json_null());
		json_object_set_new(h, "term", ssc_jreal(du(&ch->d, r->hysteresis)));
		json_object_set_new(h, "term_sd", ssc_jreal(du(&ch->d, r->hysteresis_sd)));
		json_object_set_new(h, "segmentation", json_string(
			isnan(r->deadband_degc_s) ? "turning points" : "rate dead band"));
		if (isnan(r->deadband_degc_s))
			json_object_set_new(h, "turn_band_degc", json_real(r->turn_band_degc));
		else
			json_object_set_new(h, "deadband_degc_s", json_real(r->deadband_degc_s));
		if (r->hyst_grad_collinear) {
			json_t *g = json_object();

			/* the gap the profile measures: heating - cooling at
			 * its own rates (hysteresis + gradient x rate gap) */
			json_object_set_new(g, "value", ssc_jreal(du(&ch->d, r->hysteresis)));
			json_object_set_new(g, "sd", ssc_jreal(du(&ch->d, r->hysteresis_sd)));
			json_object_set_new(g, "heating_rate_degc_s", ssc_jreal(r->rate_heat_degc_s));
			json_object_set_new(g, "cooling_rate_degc_s", ssc_jreal(r->rate_cool_degc_s));
			json_object_set_new(h, "combined_gap", g);
		}
		json_object_set_new(h, "collinear_with_gradient", json_boolean(r->hyst_grad_collinear));
		json_object_set_new(h, "gradient_vif", ssc_jreal(r->hyst_grad_vif));
		if (r->hyst_grad_collinear)
			json_object_set_new(h, "separate_with", json_string(TB_SEPARATE));
		json_object_set_new(o, "hysteresis", h);
	}
	json_object_set_new(o, "gradient_sensitivity", ssc_jreal(du(&ch->d, r->gradient)));
	json_object_set_new(o, "gradient_sensitivity_sd", ssc_jreal(du(&ch->d, r->gradient_sd)));
	snprintf(k, sizeof(k), "%s/(degC/s)", ch->d.label);
	json_object_set_new(o, "gradient_unit", json_string(k));
	if (n_runs >= 2) {
		json_t *t = json_object();

		json_object_set_new(t, "sd", ssc_jreal(du(&ch->d, r->repeat_sd)));
		json_object_set_new(t, "range", ssc_jreal(du(&ch->d, r->repeat_range)));
		json_object_set_new(t, "runs", json_integer((json_int_t)n_runs));
		json_object_set_new(t, "definition", json_string(
			"1 sigma (n-1) and max-min of the settled per-file bias at T_ref after removing the common temperature curve; warm-up dropped"));
		json_object_set_new(o, "turn_on_repeatability", t);
	}
	for (size_t j = 0; j < r->n_runs; j++) {
		json_t *x = json_object();

		json_object_set_new(x, "offset", ssc_jreal(du(&ch->d, r->runs[j].offset)));
		json_object_set_new(x, "offset_sd", ssc_jreal(du(&ch->d, r->runs[j].offset_sd)));
		json_object_set_new(x, "warmup_s", json_real(r->runs[j].warmup_s));
		json_object_set_new(x, "mean_temp_degc", ssc_jreal(r->runs[j].mean_temp_degc));
		json_array_append_new(runs, x);
	}
	json_object_set_new(o, "runs", runs);
	{
		json_t *s = json_object();

		json_object_set_new(s, "adev_min", ssc_jreal(du(&ch->d, r->stability)));
		json_object_set_new(s, "tau_s", ssc_jreal(r->stability_tau_s));
		json_object_set_new(s, "method", json_string(
			"minimum overlapping Allan deviation (EDF >= 10) of the compensated 1 s block residuals of the longest file"));
		json_object_set_new(o, "stability", s);
	}
	for (size_t i = 0; i < r->n_table; i++) {
		json_t *row = json_object();

		json_object_set_new(row, "temp_degc", json_real(r->table_temp_degc[i]));
		json_object_set_new(row, "bias", ssc_jreal(du(&ch->d, r->table_bias[i])));
		json_array_append_new(tab, row);
	}
	json_object_set_new(o, "table", tab);
	return o;
}

/* why an order-0 fit gives no sensitivity */
static const char *order0_why(const struct sscope_tempbias_result *r)
{
	return r->order_requested < 0 ?
		       "not resolved (no temperature term passes the F test at 1 %: the scatter hides any dependence; a wider temperature range or a stiller record may show one)" :
		       "not estimated (order 0 requested: no temperature term)";
}

static void chan_text(FILE *f, const struct chan *ch, size_t n_runs)
{
	const struct sscope_tempbias_result *r = ch->res;
	const char *u = ch->d.label;
	char a[32], b[32];

	fprintf(f, "channel %s (%s):\n", ch->name, u);
	fprintf(f, "  fit: order %d (%s; cap %d), T_ref %s degC, range %.2f .. %.2f degC, %zu bins\n",
		r->order, r->order_requested < 0 ? "auto, F test at 1 %" : "requested",
		r->order_cap, ssc_fmt(a, sizeof(a), r->ref_temp_degc, 4),
		r->temp_min_degc, r->temp_max_degc, r->n_bins);
	if (*r->note)
		fprintf(f, "  note: %s\n", r->note);
	for (int k = 0; k <= r->order; k++)
		fprintf(f, "    c%d = %s +- %s %s%s%.0d\n", k,
			ssc_fmt(a, sizeof(a), du(&ch->d, r->coef[k]), 6),
			ssc_fmt(b, sizeof(b), du(&ch->d, r->coef_sd[k]), 2), u,
			k == 0 ? "" : k == 1 ? "/degC" : "/degC^", k > 1 ? k : 0);
	if (r->order >= 1)
		fprintf(f, "  residual RMS %s %s; sensitivity at T_ref %s +- %s %s/degC; peak-to-peak over the range %s %s\n",
			ssc_fmt(a, sizeof(a), du(&ch->d, r->residual_rms), 3), u,
			ssc_fmt(b, sizeof(b), du(&ch->d, r->sensitivity), 4),
			ssc_fmt((char[32]){ 0 }, 32, du(&ch->d, r->sensitivity_sd), 2), u,
			ssc_fmt((char[32]){ 0 }, 32, du(&ch->d, r->peak_to_peak), 4), u);
	else
		fprintf(f, "  residual RMS %s %s; sensitivity and peak-to-peak: %s\n",
			ssc_fmt(a, sizeof(a), du(&ch->d, r->residual_rms), 3), u,
			order0_why(r));
	if (r->have_hysteresis)
		fprintf(f, "  hysteresis (heating - cooling; %s %.3g %s): term %s +- %s %s",
			isnan(r->deadband_degc_s) ? "turning points, band" : "dead band",
			isnan(r->deadband_degc_s) ? r->turn_band_degc : r->deadband_degc_s,
			isnan(r->deadband_degc_s) ? "degC" : "degC/s",
			ssc_fmt(a, sizeof(a), du(&ch->d, r->hysteresis), 4),
			ssc_fmt(b, sizeof(b), du(&ch->d, r->hysteresis_sd), 2), u);
	else
		fprintf(f, "  hysteresis: not fitted");
	if (r->have_split)
		fprintf(f, "; separate fits: max gap %s %s at %.1f degC\n",
			ssc_fmt(a, sizeof(a), du(&ch->d, r->hysteresis_max), 4), u,
			r->hysteresis_at_degc);
	else
		fputc('\n', f);
	if (r->hyst_grad_collinear)
		fprintf(f, "  hysteresis and gradient (dT/dt) terms are collinear on this profile (variance inflation %.3g):\n"
			   "    the hysteresis above is their combined heating - cooling gap at heating %.3g and cooling %.3g degC/min;\n"
			   "    to separate them use %s\n",
			r->hyst_grad_vif, 60 * r->rate_heat_degc_s, 60 * r->rate_cool_degc_s, TB_SEPARATE);
	if (r->have_gradient)
		fprintf(f, "  gradient: %s +- %s %s per degC/min\n",
			ssc_fmt(a, sizeof(a), du(&ch->d, r->gradient) / 60, 4),
			ssc_fmt(b, sizeof(b), du(&ch->d, r->gradient_sd) / 60, 2), u);
	if (n_runs >= 2) {
		fprintf(f, "  turn-on repeatability over %zu files: %s %s (1 sigma), range %s %s\n",
			n_runs, ssc_fmt(a, sizeof(a), du(&ch->d, r->repeat_sd), 3), u,
			ssc_fmt(b, sizeof(b), du(&ch->d, r->repeat_range), 3), u);
		fprintf(f, "    definition: 1 sigma (n-1) and max-min of the settled per-file bias at T_ref\n"
			   "    after removing the common temperature curve; warm-up dropped\n");
	}
	for (size_t j = 0; j < r->n_runs; j++)
		if (r->runs[j].warmup_s > 0)
			fprintf(f, "  file %zu: warm-up %.0f s dropped\n", j + 1,
				r->runs[j].warmup_s);
	if (isfinite(r->stability))
		fprintf(f, "  in-run stability after compensation: %s %s at tau %s s (minimum ADEV of the residuals)\n",
			ssc_fmt(a, sizeof(a), du(&ch->d, r->stability), 3), u,
			ssc_fmt(b, sizeof(b), r->stability_tau_s, 3));
	fprintf(f, "  compensation table (subtract from the reading):\n");
	for (size_t i = 0; i < r->n_table; i++)
		fprintf(f, "    %8.2f degC  %s %s\n", r->table_temp_degc[i],
			ssc_fmt(a, sizeof(a), du(&ch->d, r->table_bias[i]), 6), u);
}

struct tb_res {
	const char *const *paths;
	size_t nf;
	struct chan *ch;
	size_t nch;
};

static int plot(const struct ssc_common *co, const void *opts,
		const void *result, const char *path)
{
	const struct tb_res *R = result;
	const struct chan *ch = R->ch;
	size_t nch = R->nch;
	const char *file = R->paths[0];
	size_t np = nch > 3 ? 3 : nch;
	struct ssc_fig *fig = ssc_fig_new(1000, 120 + 620 * (int)np, 2 * (int)np, 1);
	char buf[200];
	int rc;

	(void)opts;
	if (!fig) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	snprintf(buf, sizeof(buf), "bias against temperature: %s", file);
	ssc_fig_title(fig, buf);
	for (size_t c = 0; c < np; c++) {
		const struct sscope_tempbias_result *r = ch[c].res;
		struct ssc_ax *ax = ssc_fig_ax(fig, 2 * (int)c, 0);
		struct ssc_ax *ar = ssc_fig_ax(fig, 2 * (int)c + 1, 0);
		size_t n = r->n_bins, nf = 201;
		double *x = calloc(n + nf, sizeof(double)), *y = calloc(n + nf, sizeof(double));
		double *rr = calloc(n, sizeof(double));
		static const int states[3] = { 1, -1, 0 };
		static const char *names[3] = { "heating", "cooling", "undecided" };
		static const uint32_t colors[3] = { 0xd62728, 0x1f77b4, 0x7f7f7f };

		if (!x || !y || !rr) {
			free(x);
			free(y);
			free(rr);
			ssc_fig_free(fig);
			ssc_err(co->cmd, "out of memory");
			return SSC_EXIT_FAIL;
		}
		for (int s = 0; s < 3; s++) {
			struct ssc_style st = { .color = colors[s], .width = -1,
						.marker = SSC_MK_CIRCLE, .marker_size = 5 };
			size_t m = 0;

			for (size_t i = 0; i < n; i++)
				if (r->bins[i].state == states[s]) {
					/* bias with the run offset and the
					 * gradient term removed, on the
					 * common curve */
					double v = r->bins[i].bias - r->runs[r->bins[i].run].offset + r->coef[0];

					if (r->have_gradient)
						v -= r->gradient * r->bins[i].dtdt;
					x[m] = r->bins[i].temp_degc;
					y[m] = du(&ch[c].d, v);
					rr[m] = du(&ch[c].d, r->bins[i].resid);
					m++;
				}
			if (m) {
				ssc_ax_line(ax, x, y, m, &st, names[s]);
				ssc_ax_line(ar, x, rr, m, &st, NULL);
			}
		}
		{
			struct ssc_style fs = { .color = 0x101010, .width = 2 };
			struct ssc_style hs = { .color = 0xd62728, .width = 1.5, .dash = SSC_DASHED };
			struct ssc_style cs = { .color = 0x1f77b4, .width = 1.5, .dash = SSC_DASHED };

			for (size_t i = 0; i < nf; i++) {
				x[i] = r->temp_min_degc + (r->temp_max_degc - r->temp_min_degc) * (double)i / (double)(nf - 1);
				y[i] = du(&ch[c].d, sscope_tempbias_eval(r, x[i]));
			}
			snprintf(buf, sizeof(buf), "fit, order %d", r->order);
			ssc_ax_line(ax, x, y, nf, &fs, buf);
			if (r->have_split) {
				for (int s = 0; s < 2; s++) {
					const double *a = s ? r->cool_coef : r->heat_coef;

					for (size_t i = 0; i < nf; i++) {
						double dt = x[i] - r->ref_temp_degc, v = 0;

						for (int k = r->order; k >= 0; k--)
							v = v * dt + a[k];
						y[i] = du(&ch[c].d, v);
					}
					ssc_ax_line(ax, x, y, nf, s ? &cs : &hs,
						    s ? "cooling fit" : "heating fit");
				}
			}
		}
		snprintf(buf, sizeof(buf), "%s bias (%s)", ch[c].name, ch[c].d.label);
		ssc_ax_ylabel(ax, buf);
		ssc_ax_xlabel(ax, "temperature (°C)");
		ssc_ax_legend(ax, SSC_LEGEND_AUTO);
		ssc_ax_grid(ax, true);
		snprintf(buf, sizeof(buf), "residual (%s)", ch[c].d.label);
		ssc_ax_ylabel(ar, buf);
		ssc_ax_xlabel(ar, "temperature (°C)");
		ssc_ax_grid(ar, true);
		ssc_ax_hline(ar, 0, &(struct ssc_style){ .color = 0x101010, .width = 1 }, NULL);
		snprintf(buf, sizeof(buf), "bins of %.2g °C; residual RMS of 1 s blocks %.3g %s",
			 r->bin_degc, du(&ch[c].d, r->residual_rms), ch[c].d.label);
		ssc_ax_note(ar, buf, SSC_LEGEND_AUTO);
		free(x);
		free(y);
		free(rr);
	}
	rc = ssc_fig_save(fig, path);
	ssc_fig_free(fig);
	if (rc)
		return ssc_write_failed(co->cmd, path, rc);
	return SSC_EXIT_OK;
}

static void free_result(void *result)
{
	struct tb_res *R = result;

	for (size_t k = 0; k < R->nch; k++)
		sscope_tempbias_result_free(R->ch[k].res);
	free(R->ch);
	free(R);
}

static int run(const struct ssc_stage_env *env, void *opts, void **result)
{
	const struct ssc_common *co = env->co;
	struct opts *o = opts;
	struct sscope_capture *c0;
	struct sscope_tempbias_run runs[SSCOPE_TEMPBIAS_MAX_RUNS];
	struct tb_res *R;
	size_t nch, nf = env->n_caps;
	int rc = SSC_EXIT_OK;

	if (nf == 0)
		return ssc_usage_error(co->cmd, "give at least one file");
	if (nf > SSCOPE_TEMPBIAS_MAX_RUNS)
		return ssc_usage_error(co->cmd, "at most %d files", SSCOPE_TEMPBIAS_MAX_RUNS);
	c0 = env->caps[0];
	for (size_t j = 0; j < nf; j++) {
		const struct sscope_capture *c = env->caps[j];

		if (!c->temp_degc) {
			ssc_err(co->cmd, "%s: no temperature column (give --temp-column NAME)",
				env->paths[j]);
			return SSC_EXIT_FAIL;
		}
		if (!(c->rate_hz > 0)) {
			return ssc_err_no_rate(co->cmd, env->paths[j], c->rate_note);
		}
		if (c->n_channels != c0->n_channels) {
			ssc_err(co->cmd, "%s: %zu data channels, %s has %zu", env->paths[j],
				c->n_channels, env->paths[0], c0->n_channels);
			return SSC_EXIT_FAIL;
		}
		for (size_t k = 0; k < c->n_channels; k++)
			if (strcmp(c->channels[k].col.name, c0->channels[k].col.name)) {
				ssc_err(co->cmd, "%s: channel %zu is '%s', %s has '%s'",
					env->paths[j], k + 1, c->channels[k].col.name,
					env->paths[0], c0->channels[k].col.name);
				return SSC_EXIT_FAIL;
			}
	}
	nch = c0->n_channels;
	if (nch == 0) {
		ssc_err(co->cmd, "%s: no data channel", env->paths[0]);
		return SSC_EXIT_FAIL;
	}
	R = calloc(1, sizeof(*R));
	if (R)
		R->ch = calloc(nch, sizeof(*R->ch));
	if (!R || !R->ch) {
		free(R);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	*result = R;
	R->paths = env->paths;
	R->nf = nf;
	R->nch = nch;
	for (size_t k = 0; k < nch && !rc; k++) {
		struct sscope_diag d = { "" };
		struct chan *ch = &R->ch[k];
		int e;

		ch->name = c0->channels[k].col.name;
		display_unit(&c0->channels[k].col, &ch->d);
		for (size_t j = 0; j < nf; j++)
			runs[j] = (struct sscope_tempbias_run){
				env->caps[j]->channels[k].data, 1, env->caps[j]->temp_degc,
				env->caps[j]->n, env->caps[j]->rate_hz };
		e = sscope_tempbias_fit(runs, nf, &o->t, &ch->res, &d);
		if (e) {
			char what[160];

			snprintf(what, sizeof(what), "%s%s: channel %s", env->paths[0],
				 nf > 1 ? " ..." : "", ch->name);
			/* the library's words know no file: said with it */
			if (d.msg[0] && e != -ENOTSUP) {
				ssc_err(co->cmd, "%s: %s", what, d.msg);
				rc = SSC_EXIT_FAIL;
			} else {
				rc = ssc_fail(co->cmd, e, &d, what);
			}
		} else if (o->t.ref_temp_set && k == 0) {
			/* a reference far outside the data: the curve's
			 * coefficients are an extrapolation */
			double lo = ch->res->temp_min_degc, hi = ch->res->temp_max_degc;

			if (o->t.ref_temp_degc < lo - (hi - lo) ||
			    o->t.ref_temp_degc > hi + (hi - lo))
				ssc_warn(co, "%s: --ref-temp %g degC lies far outside the data's %.3g .. %.3g degC: the coefficients at it are an extrapolation of the curve",
					 env->paths[0], o->t.ref_temp_degc, lo, hi);
		}
	}
	return rc;
}

static json_t *json(const void *opts, const void *result)
{
	const struct tb_res *R = result;
	json_t *root = json_object(), *jch = json_array(), *files = json_array();

	(void)opts;
	json_object_set_new(root, "command", json_string("tempbias"));
	json_object_set_new(root, "file", json_string(R->paths[0]));
	for (size_t j = 0; j < R->nf; j++)
		json_array_append_new(files, json_string(R->paths[j]));
	json_object_set_new(root, "files", files);
	for (size_t k = 0; k < R->nch; k++)
		json_array_append_new(jch, chan_json(&R->ch[k], R->nf));
	json_object_set_new(root, "channels", jch);
	return root;
}

static void text(FILE *f, const void *opts, const void *result)
{
	const struct tb_res *R = result;
	size_t nf = R->nf;

	(void)opts;
	fprintf(f, "tempbias: %s%s (%zu file%s = power cycle%s)\n", R->paths[0],
		nf > 1 ? " ..." : "", nf, nf > 1 ? "s" : "", nf > 1 ? "s" : "");
	for (size_t k = 0; k < R->nch; k++)
		chan_text(f, &R->ch[k], nf);
}

static void csv(FILE *f, const void *opts, const void *result)
{
	const struct tb_res *R = result;

	(void)opts;
	fprintf(f, "channel,unit,temp_degc,bias\n");
	for (size_t k = 0; k < R->nch; k++) {
		const struct sscope_tempbias_result *r = R->ch[k].res;

		for (size_t i = 0; i < r->n_table; i++)
			fprintf(f, "%s,%s,%.6g,%.10g\n", R->ch[k].name, R->ch[k].d.label,
				r->table_temp_degc[i], du(&R->ch[k].d, r->table_bias[i]));
	}
}

static void summary(json_t *rows, const void *opts, const void *result)
{
	const struct tb_res *R = result;

	(void)opts;
	for (size_t k = 0; k < R->nch; k++) {
		const struct chan *ch = &R->ch[k];
		const struct sscope_tempbias_result *r = ch->res;
		char q[64], un[48];

		snprintf(q, sizeof(q), "bias sensitivity at %.3g degC", r->ref_temp_degc);
		snprintf(un, sizeof(un), "%s/degC", ch->d.label);
		/* an interval that holds 0 does not know the sign */
		bool holds0 = r->order >= 1 &&
			      fabs(r->sensitivity) < 2 * r->sensitivity_sd;

		ssc_summary_add(rows, ch->name, q, du(&ch->d, r->sensitivity),
				du(&ch->d, r->sensitivity - 2 * r->sensitivity_sd),
				du(&ch->d, r->sensitivity + 2 * r->sensitivity_sd),
				un, r->order < 1 ? order0_why(r) : holds0 ?
				"interval: +-2 sd; it holds 0: not resolved" :
				"interval: +-2 sd");
		if (holds0)
			ssc_summary_warn_last(rows);
		ssc_summary_add(rows, ch->name, "bias peak-to-peak over the range",
				du(&ch->d, r->peak_to_peak), NAN, NAN, ch->d.label,
				r->order >= 1 ? NULL : order0_why(r));
		if (r->have_split)
			ssc_summary_add(rows, ch->name, "hysteresis (max gap)",
					du(&ch->d, fabs(r->hysteresis_max)), NAN, NAN,
					ch->d.label, NULL);
		if (R->nf >= 2)
			ssc_summary_add(rows, ch->name, "turn-on repeatability (1 sigma)",
					du(&ch->d, r->repeat_sd), NAN, NAN, ch->d.label, NULL);
	}
}

const struct ssc_stage_ops ssc_tempbias_stage = {
	.spec = &spec,
	.title = "Temperature bias",
	.needs = SSC_NEED_DATA | SSC_NEED_TEMP,
	.min_files = 1,
	.max_files = SSCOPE_TEMPBIAS_MAX_RUNS,
	.opts_size = sizeof(struct opts),
	.init = init,
	.handle = handler,
	.run = run,
	.json = json,
	.text = text,
	.csv = csv,
	.summary = summary,
	.plot = plot,
	.free_result = free_result,
};

int ssc_cmd_tempbias(int argc, char **argv)
{
	return ssc_stage_main(&ssc_tempbias_stage, argc, argv);
}
