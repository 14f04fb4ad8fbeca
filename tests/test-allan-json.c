/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The allan result's JSON codec (src/workbench/allan-json.c, read back by
 * navcommon.c): a result of a gyro and an accelerometer file, encoded by
 * ssc_allan_json() and written as the command writes it (15 significant
 * digits), is read back by ssc_nav_terms_from_allan() with the values,
 * intervals and presence of every term it was given, the same terms
 * ssc_nav_terms_from_allan_res() takes from the typed result, and the
 * points it was given; the points text of each slot is the very text
 * jansson writes of the tree's points (one thread or two).
 */
#include "config.h"

#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "workbench.h"
#include "results.h"
#include "navcommon.h"
#include "check-main.h"

/* the JSON text has 15 significant digits; a value read back and turned
 * to SI (one unit conversion) is within a few units of the 15th */
#define REL 1e-13

#define NPTS 6

static struct sscope_capture cap[2];
static struct sscope_capture_column col[2];
static struct sscope_allan_result res[2];
static struct sscope_allan_point pts[2][NPTS];
static struct ssc_allan_chan ch[2];
static struct ssc_allan_file fr[2];
static struct ssc_allan_res R;

static void close_to(double got, double want, const char *what)
{
	if (isnan(want)) {
		ck_assert_msg(isnan(got), "%s: %.17g, want none", what, got);
		return;
	}
	ck_assert_msg(fabs(got - want) <= REL * fmax(fabs(got), fabs(want)),
		      "%s: %.17g, want %.17g", what, got, want);
}

static void set_units(struct ssc_allan_units *u, enum sscope_quantity q,
		      const char *unit)
{
	struct sscope_unit su;

	memset(u, 0, sizeof(*u));
	u->rq = q;
	ck_assert_int_eq(sscope_unit_parse(unit, &su, NULL), 0);
	snprintf(u->rate, sizeof(u->rate), "%s", unit);
	ck_assert_int_eq(sscope_unit_si_string(&su, u->rate_si, sizeof(u->rate_si)), 0);
	snprintf(u->dev, sizeof(u->dev), "%s", unit);
	snprintf(u->show, sizeof(u->show), "%s", unit);
	u->dev_scale = u->show_scale = su.scale;
	for (int t = 0; t < 5; t++) {
		const char *c = sscope_term_unit(q, (enum sscope_term)t);
		const char *s = sscope_term_si_unit(q, (enum sscope_term)t);

		ck_assert_ptr_nonnull(c);
		ck_assert_ptr_nonnull(s);
		snprintf(u->term[t], sizeof(u->term[t]), "%s", c);
		snprintf(u->term_si[t], sizeof(u->term_si[t]), "%s", s);
	}
}

static void set_coef(struct sscope_noise_coef *cf, enum sscope_noise_why why,
		     double value, double lo, double hi)
{
	memset(cf, 0, sizeof(*cf));
	cf->why = why;
	cf->present = cf->fitted = why == SSCOPE_NOISE_PRESENT;
	cf->value = value;
	cf->lo = lo;
	cf->hi = hi;
	cf->z = why == SSCOPE_NOISE_NOT_ALLOWED ? (double)NAN : cf->present ? 9.5 : 1.25;
	cf->estimate = isfinite(value) ? value : 0.5 * (isfinite(hi) ? hi : 0);
}

/*
 * Channel k: N present and resolved, K present with an interval reaching
 * zero, B absent below a finite bound, R absent without one, Q not
 * allowed; s scales the values (a gyro's and an accelerometer's).
 */
static void make_chan(int k, const char *name, const char *unit,
		      enum sscope_quantity q, double rate_hz, double s)
{
	struct sscope_allan_result *r = &res[k];
	struct sscope_noise_fit *ft = &r->fit;

	col[k].name = name;
	col[k].unit_label = unit;
	col[k].quantity = q;
	cap[k].rate_hz = rate_hz;
	cap[k].n = 36000;
	for (int i = 0; i < NPTS; i++) {
		struct sscope_allan_point *p = &pts[k][i];
		size_t m = (size_t)1 << (2 * i);

		p->m = m;
		p->tau_s = (double)m / rate_hz;
		p->terms = cap[k].n - 2 * m + 1 - (i == 3 ? 7 : 0);
		p->skipped = i == 3 ? 7 : 0;
		p->stride = 1;
		p->dev = s * 3.1e-3 / sqrt(p->tau_s) * (1 + 0.01 * i);
		p->edf = 35000.0 / (double)(m + 1);
		p->edf_full = p->edf;
		p->alpha = i < 4 ? 0 : -1;
		p->alpha_identified = i < 4;
		/* a point without an interval */
		p->dev_lo = i == 2 ? (double)NAN : p->dev * (1 - 1 / sqrt(p->edf));
		p->dev_hi = i == 2 ? (double)NAN : p->dev * (1 + 1.2 / sqrt(p->edf));
	}
	r->points = r->oadev = pts[k];
	r->n_points = r->n_oadev = NPTS;
	r->n_phase = cap[k].n + 1;
	r->have_fit = true;
	ft->ci_level = 0.683;
	ft->n_points = NPTS;
	ft->chi2 = 4.25;
	ft->dof = 3;
	ft->p_value = 0.236;
	ft->select_z = 3;
	ft->terms = ft->present = (1u << SSCOPE_TERM_N) | (1u << SSCOPE_TERM_K);
	ft->readoff.n = s * 3.05e-3;
	ft->readoff.n_tau_s = 1;
	ft->readoff.b = ft->readoff.k = (double)NAN;
	ft->readoff.b_tau_s = ft->readoff.k_tau_s = (double)NAN;
	set_coef(&ft->coef[SSCOPE_TERM_Q], SSCOPE_NOISE_NOT_ALLOWED, (double)NAN, (double)NAN, (double)NAN);
	set_coef(&ft->coef[SSCOPE_TERM_N], SSCOPE_NOISE_PRESENT, s * 3.1e-3,
		 s * 3.02e-3, s * 3.19e-3);
	set_coef(&ft->coef[SSCOPE_TERM_B], SSCOPE_NOISE_NOT_NEEDED, (double)NAN, 0,
		 s * 2.7e-5);
	set_coef(&ft->coef[SSCOPE_TERM_K], SSCOPE_NOISE_PRESENT, s * 4.4e-6, 0,
		 s * 9.1e-6);
	set_coef(&ft->coef[SSCOPE_TERM_R], SSCOPE_NOISE_NOT_SEPARABLE, (double)NAN, 0,
		 (double)INFINITY);
	ch[k].col = &col[k];
	ch[k].res = r;
	ch[k].n = cap[k].n;
	set_units(&ch[k].u, q, unit);
	fr[k].path = k ? "accel.csv" : "gyro.csv";
	fr[k].cap = &cap[k];
	fr[k].ch = &ch[k];
	fr[k].n_ch = 1;
}

static void make_result(void)
{
	memset(&R, 0, sizeof(R));
	make_chan(0, "gx", "deg/s", SSCOPE_QUANTITY_ANGULAR_RATE, 200, M_PI / 180);
	make_chan(1, "az", "m/s^2", SSCOPE_QUANTITY_ACCELERATION, 100, 0.02);
	R.fr = fr;
	R.n_files = 2;
	R.ci_level = 0.683;
	R.grid = SSCOPE_ALLAN_TAUS_OCTAVE;
}

static const struct ssc_allan_json_opts opts = {
	.input = SSCOPE_ALLAN_RATE,
	.dev = SSCOPE_ALLAN_DEV_OADEV,
	.ci = 0.683,
	.no_fit = false,
	.model_error = 0,
	.two_threads = false,
};

/* the result as the command writes it, read back */
static json_t *encode_decode(const struct ssc_allan_json_opts *o)
{
	json_t *root = ssc_allan_json(o, &R, NULL), *back;
	char *text = json_dumps(root, JSON_REAL_PRECISION(15) | JSON_COMPACT);
	json_error_t err;

	ck_assert_ptr_nonnull(text);
	back = json_loads(text, 0, &err);
	ck_assert_msg(back != NULL, "%s", err.text);
	free(text);
	json_decref(root);
	return back;
}

/* the decoded terms t of channel k equal what the encoder was given */
static void check_terms(const struct ssc_nav_terms *t, int k)
{
	const struct sscope_noise_fit *ft = &res[k].fit;
	char what[64];

	ck_assert_str_eq(t->name, col[k].name);
	ck_assert_int_eq(t->quantity, col[k].quantity);
	close_to(t->ci_level, 0.683, "ci_level");
	ck_assert(t->have);
	for (int i = 0; i < 5; i++) {
		const struct sscope_noise_coef *cf = &ft->coef[i];

		snprintf(what, sizeof(what), "%s %c", col[k].name, "QNBKR"[i]);
		ck_assert_msg(t->present[i] == cf->present, "%s: presence", what);
		if (cf->present)
			close_to(t->coef[i], cf->value, what);
		else
			ck_assert_msg(t->coef[i] == 0, "%s: %g for an absent term",
				      what, t->coef[i]);
		close_to(t->lo[i], isfinite(cf->lo) ? cf->lo : (double)NAN, what);
		close_to(t->hi[i], isfinite(cf->hi) ? cf->hi : (double)NAN, what);
	}
	close_to(t->n_lo, ft->coef[SSCOPE_TERM_N].lo, "N lo");
	close_to(t->n_hi, ft->coef[SSCOPE_TERM_N].hi, "N hi");
	/* the bounds themselves, so that a decoder dropping them fails */
	ck_assert(t->lo[SSCOPE_TERM_B] == 0 && t->hi[SSCOPE_TERM_B] > 0);
	ck_assert(isnan(t->hi[SSCOPE_TERM_R]) && isnan(t->hi[SSCOPE_TERM_Q]));
}

/* the "points" of channel k read back equal the points it was given */
static void check_points(const json_t *jp, int k)
{
	const struct ssc_allan_units *u = &ch[k].u;

	ck_assert_int_eq(json_array_size(jp), NPTS);
	for (size_t i = 0; i < NPTS; i++) {
		const struct sscope_allan_point *p = &pts[k][i];
		const json_t *q = json_array_get(jp, i);
		const json_t *lo = json_object_get(q, "dev_lo");
		const json_t *hi = json_object_get(q, "dev_hi");
		const json_t *sk = json_object_get(q, "skipped");

		close_to(json_number_value(json_object_get(q, "tau_s")), p->tau_s, "tau_s");
		ck_assert_int_eq(json_integer_value(json_object_get(q, "m")), p->m);
		ck_assert_int_eq(json_integer_value(json_object_get(q, "terms")), p->terms);
		close_to(json_number_value(json_object_get(q, "dev")) * u->dev_scale,
			 p->dev, "dev");
		close_to(json_is_null(lo) ? (double)NAN : json_number_value(lo) * u->dev_scale,
			 p->dev_lo, "dev_lo");
		close_to(json_is_null(hi) ? (double)NAN : json_number_value(hi) * u->dev_scale,
			 p->dev_hi, "dev_hi");
		close_to(json_number_value(json_object_get(q, "edf")), p->edf, "edf");
		ck_assert_int_eq(json_integer_value(json_object_get(q, "alpha")), p->alpha);
		ck_assert_str_eq(json_string_value(json_object_get(q, "noise")),
				 ssc_allan_noise_name(p->alpha));
		if (p->skipped)
			ck_assert_int_eq(json_integer_value(sk), p->skipped);
		else
			ck_assert_ptr_null(sk);
		ck_assert_ptr_null(json_object_get(q, "stride"));
	}
}

static const json_t *chan_json(const json_t *root, int k)
{
	const json_t *f = json_array_get(json_object_get(root, "files"), (size_t)k);

	ck_assert_str_eq(json_string_value(json_object_get(f, "file")), fr[k].path);
	return json_array_get(json_object_get(f, "channels"), 0);
}

START_TEST(terms_and_points_round_trip)
{
	struct ssc_nav_terms *t = NULL, *typed = NULL;
	size_t n = 0, nt = 0;
	json_t *back;

	make_result();
	back = encode_decode(&opts);
	ck_assert_str_eq(json_string_value(json_object_get(back, "command")), "allan");
	ck_assert_int_eq(ssc_nav_terms_from_allan("test", back, "result", &t, &n),
			 SSC_EXIT_OK);
	ck_assert_int_eq(n, 2);
	ck_assert_int_eq(ssc_nav_terms_from_allan_res("test", &R, "result", &typed, &nt),
			 SSC_EXIT_OK);
	ck_assert_int_eq(nt, 2);
	for (int k = 0; k < 2; k++) {
		/* what the encoder was given, and what a scene passes */
		check_terms(&t[k], k);
		check_terms(&typed[k], k);
		check_points(json_object_get(chan_json(back, k), "points"), k);
	}
	free(t);
	free(typed);
	json_decref(back);
}
END_TEST

START_TEST(no_fit_has_points_and_no_terms)
{
	struct ssc_allan_json_opts o = opts;
	struct ssc_nav_terms *t = NULL;
	size_t n = 0;
	json_t *back;

	make_result();
	o.no_fit = true;
	back = encode_decode(&o);
	for (int k = 0; k < 2; k++) {
		const json_t *c = chan_json(back, k);

		ck_assert_ptr_null(json_object_get(c, "noise"));
		ck_assert_ptr_null(json_object_get(c, "fit"));
		check_points(json_object_get(c, "points"), k);
	}
	ck_assert_int_eq(ssc_nav_terms_from_allan("test", back, "result", &t, &n),
			 SSC_EXIT_FAIL);
	ck_assert_ptr_null(t);
	json_decref(back);
}
END_TEST

/* the points text of slot k, as written */
static char *slot_text(const struct ssc_allan_json_opts *o, size_t k)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);

	ck_assert_ptr_nonnull(f);
	ck_assert(ssc_allan_json_points(f, o, &R, k));
	ck_assert_int_eq(fclose(f), 0);
	return buf;
}

/* the slots' text is jansson's text of the tree's points */
static void check_slots(const struct ssc_allan_json_opts *o)
{
	json_t *tree = ssc_allan_json(o, &R, NULL), *slotted;
	size_t n_slots = 0;

	slotted = ssc_allan_json(o, &R, &n_slots);
	ck_assert_int_eq(n_slots, 2);
	for (int k = 0; k < 2; k++) {
		const json_t *pj = json_object_get(chan_json(tree, k), "points");
		char *want = json_dumps(pj, JSON_REAL_PRECISION(15) | JSON_COMPACT);
		char *got = slot_text(o, (size_t)k);

		size_t d = 0;

		ck_assert_ptr_nonnull(want);
		while (got[d] && got[d] == want[d])
			d++;
		ck_assert_msg(got[d] == want[d],
			      "slot %d differs at byte %zu: \"%.60s\" instead of \"%.60s\"",
			      k, d, got + d, want + d);
		/* the slot is a placeholder, not the points */
		ck_assert(!json_is_array(json_object_get(chan_json(slotted, k), "points")));
		free(want);
		free(got);
	}
	{
		FILE *f = fopen("/dev/null", "w");

		ck_assert_ptr_nonnull(f);
		ck_assert(!ssc_allan_json_points(f, o, &R, 2));
		fclose(f);
	}
	json_decref(tree);
	json_decref(slotted);
}

START_TEST(points_text_is_the_tree_text)
{
	make_result();
	check_slots(&opts);
}
END_TEST

/* a grid long enough to be split over two threads */
START_TEST(points_text_two_threads)
{
	struct ssc_allan_json_opts o = opts;
	size_t n = 5000;
	struct sscope_allan_point *p = calloc(n, sizeof(*p));

	ck_assert_ptr_nonnull(p);
	make_result();
	for (size_t i = 0; i < n; i++) {
		p[i] = pts[0][i % NPTS];
		p[i].m = i + 1;
		p[i].tau_s = (double)(i + 1) / cap[0].rate_hz;
		p[i].dev *= 1 + 1e-4 * (double)i;
	}
	res[0].points = p;
	res[0].n_points = n;
	o.two_threads = true;
	check_slots(&o);
	free(p);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("allan-json");
	TCase *tc = tcase_create("allan-json");

	tcase_set_timeout(tc, 60);
	tcase_add_test(tc, terms_and_points_round_trip);
	tcase_add_test(tc, no_fit_has_points_and_no_terms);
	tcase_add_test(tc, points_text_is_the_tree_text);
	tcase_add_test(tc, points_text_two_threads);
	suite_add_tcase(s, tc);
	return s;
}
