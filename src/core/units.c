/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Units: a small recursive-descent parser for unit expressions ("deg/s",
 * "rad s^-1", "deg/h/sqrt(h)", "mV/(deg/s)", "°C") into a scale, an offset
 * and a vector of doubled base-dimension exponents.  Atoms are listed
 * explicitly (no generic SI prefixes) because the field's spellings clash
 * with a prefix grammar: "mg" is milli-g, not milligram; "min" is minute.
 * Conversion factors are exact by definition (BIPM SI Brochure, 9th ed.;
 * standard gravity 9.80665 m/s^2, CGPM 1901).
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sscope-quantity.h"
#include "sscope-term.h"
#include "sscope-unit.h"


enum { L = SSCOPE_UNIT_DIM_LENGTH, T = SSCOPE_UNIT_DIM_TIME, A = SSCOPE_UNIT_DIM_ANGLE,
       K = SSCOPE_UNIT_DIM_TEMP, V = SSCOPE_UNIT_DIM_VOLTAGE, C = SSCOPE_UNIT_DIM_COUNTS };

struct atom {
	const char *name;
	double scale;
	double offset; /* only for a lone absolute temperature */
	int8_t dim2[SSCOPE_UNIT_DIM_COUNT];
};

#define D(l, t, a, k, v, c) { 2 * (l), 2 * (t), 2 * (a), 2 * (k), 2 * (v), 2 * (c) }
#define GN SSCOPE_UNIT_GRAVITY_STD

/* Sorted by nothing; the parser takes the longest atom that matches. */
static const struct atom atoms[] = {
	/* length */
	{ "m", 1, 0, D(1, 0, 0, 0, 0, 0) },
	{ "mm", 1e-3, 0, D(1, 0, 0, 0, 0, 0) },
	{ "cm", 1e-2, 0, D(1, 0, 0, 0, 0, 0) },
	{ "km", 1e3, 0, D(1, 0, 0, 0, 0, 0) },
	{ "um", 1e-6, 0, D(1, 0, 0, 0, 0, 0) },
	{ "\xc2\xb5m", 1e-6, 0, D(1, 0, 0, 0, 0, 0) },
	{ "nm", 1e-9, 0, D(1, 0, 0, 0, 0, 0) },
	{ "ft", 0.3048, 0, D(1, 0, 0, 0, 0, 0) },
	/* time */
	{ "s", 1, 0, D(0, 1, 0, 0, 0, 0) },
	{ "sec", 1, 0, D(0, 1, 0, 0, 0, 0) },
	{ "ms", 1e-3, 0, D(0, 1, 0, 0, 0, 0) },
	{ "us", 1e-6, 0, D(0, 1, 0, 0, 0, 0) },
	{ "\xc2\xb5s", 1e-6, 0, D(0, 1, 0, 0, 0, 0) },
	{ "\xce\xbcs", 1e-6, 0, D(0, 1, 0, 0, 0, 0) },
	{ "ns", 1e-9, 0, D(0, 1, 0, 0, 0, 0) },
	{ "min", 60, 0, D(0, 1, 0, 0, 0, 0) },
	{ "h", 3600, 0, D(0, 1, 0, 0, 0, 0) },
	{ "hr", 3600, 0, D(0, 1, 0, 0, 0, 0) },
	{ "hour", 3600, 0, D(0, 1, 0, 0, 0, 0) },
	{ "day", 86400, 0, D(0, 1, 0, 0, 0, 0) },
	{ "days", 86400, 0, D(0, 1, 0, 0, 0, 0) },
	{ "d", 86400, 0, D(0, 1, 0, 0, 0, 0) },
	/* frequency */
	{ "Hz", 1, 0, D(0, -1, 0, 0, 0, 0) },
	{ "mHz", 1e-3, 0, D(0, -1, 0, 0, 0, 0) },
	{ "kHz", 1e3, 0, D(0, -1, 0, 0, 0, 0) },
	{ "MHz", 1e6, 0, D(0, -1, 0, 0, 0, 0) },
	/* angle */
	{ "rad", 1, 0, D(0, 0, 1, 0, 0, 0) },
	{ "mrad", 1e-3, 0, D(0, 0, 1, 0, 0, 0) },
	{ "urad", 1e-6, 0, D(0, 0, 1, 0, 0, 0) },
	{ "\xc2\xb5rad", 1e-6, 0, D(0, 0, 1, 0, 0, 0) },
	{ "deg", PI / 180, 0, D(0, 0, 1, 0, 0, 0) },
	{ "degree", PI / 180, 0, D(0, 0, 1, 0, 0, 0) },
	{ "degrees", PI / 180, 0, D(0, 0, 1, 0, 0, 0) },
	{ "\xc2\xb0", PI / 180, 0, D(0, 0, 1, 0, 0, 0) },
	{ "mdeg", PI / 180e3, 0, D(0, 0, 1, 0, 0, 0) },
	{ "arcmin", PI / 10800, 0, D(0, 0, 1, 0, 0, 0) },
	{ "arcsec", PI / 648000, 0, D(0, 0, 1, 0, 0, 0) },
	{ "\xe2\x80\xb2", PI / 10800, 0, D(0, 0, 1, 0, 0, 0) },
	{ "\xe2\x80\xb3", PI / 648000, 0, D(0, 0, 1, 0, 0, 0) },
	{ "rev", 2 * PI, 0, D(0, 0, 1, 0, 0, 0) },
	/* angular rate shorthands */
	{ "dps", PI / 180, 0, D(0, -1, 1, 0, 0, 0) },
	{ "mdps", PI / 180e3, 0, D(0, -1, 1, 0, 0, 0) },
	{ "rpm", 2 * PI / 60, 0, D(0, -1, 1, 0, 0, 0) },
	/* acceleration */
	{ "g", GN, 0, D(1, -2, 0, 0, 0, 0) },
	{ "mg", GN * 1e-3, 0, D(1, -2, 0, 0, 0, 0) },
	{ "ug", GN * 1e-6, 0, D(1, -2, 0, 0, 0, 0) },
	{ "\xc2\xb5g", GN * 1e-6, 0, D(1, -2, 0, 0, 0, 0) },
	{ "\xce\xbcg", GN * 1e-6, 0, D(1, -2, 0, 0, 0, 0) },
	{ "ng", GN * 1e-9, 0, D(1, -2, 0, 0, 0, 0) },
	{ "Gal", 1e-2, 0, D(1, -2, 0, 0, 0, 0) },
	{ "mGal", 1e-5, 0, D(1, -2, 0, 0, 0, 0) },
	/* voltage */
	{ "V", 1, 0, D(0, 0, 0, 0, 1, 0) },
	{ "kV", 1e3, 0, D(0, 0, 0, 0, 1, 0) },
	{ "mV", 1e-3, 0, D(0, 0, 0, 0, 1, 0) },
	{ "uV", 1e-6, 0, D(0, 0, 0, 0, 1, 0) },
	{ "\xc2\xb5V", 1e-6, 0, D(0, 0, 0, 0, 1, 0) },
	{ "\xce\xbcV", 1e-6, 0, D(0, 0, 0, 0, 1, 0) },
	{ "nV", 1e-9, 0, D(0, 0, 0, 0, 1, 0) },
	/* temperature (absolute when alone, a difference in compounds) */
	{ "degC", 1, 0, D(0, 0, 0, 1, 0, 0) },
	{ "\xc2\xb0" "C", 1, 0, D(0, 0, 0, 1, 0, 0) },
	{ "C", 1, 0, D(0, 0, 0, 1, 0, 0) },
	{ "celsius", 1, 0, D(0, 0, 0, 1, 0, 0) },
	{ "mdegC", 1e-3, 0, D(0, 0, 0, 1, 0, 0) },
	{ "K", 1, -273.15, D(0, 0, 0, 1, 0, 0) },
	{ "degF", 5.0 / 9.0, -160.0 / 9.0, D(0, 0, 0, 1, 0, 0) },
	{ "\xc2\xb0" "F", 5.0 / 9.0, -160.0 / 9.0, D(0, 0, 0, 1, 0, 0) },
	/* converter codes */
	{ "counts", 1, 0, D(0, 0, 0, 0, 0, 1) },
	{ "count", 1, 0, D(0, 0, 0, 0, 0, 1) },
	{ "cnt", 1, 0, D(0, 0, 0, 0, 0, 1) },
	{ "LSB", 1, 0, D(0, 0, 0, 0, 0, 1) },
	{ "lsb", 1, 0, D(0, 0, 0, 0, 0, 1) },
	{ "code", 1, 0, D(0, 0, 0, 0, 0, 1) },
	{ "codes", 1, 0, D(0, 0, 0, 0, 0, 1) },
	/* ratios */
	{ "ppm", 1e-6, 0, D(0, 0, 0, 0, 0, 0) },
	{ "ppb", 1e-9, 0, D(0, 0, 0, 0, 0, 0) },
	{ "%", 1e-2, 0, D(0, 0, 0, 0, 0, 0) },
};

struct parser {
	const char *s; /* whole text, for messages */
	const char *p;
	struct sscope_diag *diag;
	int n_factors;        /* atoms and numbers multiplied in */
	const struct atom *last_atom;
	bool lone_power_one;  /* the only atom has exponent 1 */
	int depth;            /* parentheses and roots open */
};

struct val {
	double scale;
	int dim2[SSCOPE_UNIT_DIM_COUNT];
};

static int parse_expr(struct parser *ps, struct val *out);

static void skip_blanks(struct parser *ps)
{
	while (*ps->p == ' ' || *ps->p == '\t')
		ps->p++;
}

static bool starts(const char *p, const char *lit)
{
	return strncmp(p, lit, strlen(lit)) == 0;
}

static bool is_atom_byte(unsigned char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '%' ||
	       c == '_' || c >= 0x80;
}

/* UTF-8 sequences that are operators, not parts of an atom */
static const char *const U_SQRT = "\xe2\x88\x9a"; /* √ */
static const char *const U_DOT = "\xc2\xb7";      /* · */
static const char *const U_MINUS = "\xe2\x81\xbb"; /* superscript minus */

static int superscript_digit(const char *p, int *len)
{
	unsigned char a = (unsigned char)p[0], b, c;

	if (a != 0xc2 && a != 0xe2)
		return -1;
	b = (unsigned char)p[1]; /* p[1] exists: p[0] is not the NUL */
	if (a == 0xc2 && (b == 0xb2 || b == 0xb3 || b == 0xb9)) {
		*len = 2;
		return b == 0xb2 ? 2 : b == 0xb3 ? 3 : 1;
	}
	if (a != 0xe2 || b != 0x81)
		return -1;
	c = (unsigned char)p[2];
	if (c == 0xb0 || (c >= 0xb4 && c <= 0xb9)) {
		*len = 3;
		return c == 0xb0 ? 0 : c - 0xb0;
	}
	return -1;
}

static bool is_operator_utf8(const char *p)
{
	int len;

	return starts(p, U_SQRT) || starts(p, U_DOT) || starts(p, U_MINUS) ||
	       superscript_digit(p, &len) >= 0;
}

static int err_at(struct parser *ps, const char *what)
{
	return ssc_diag(ps->diag, -EINVAL, "%s at '%s' in unit '%s'", what,
			*ps->p ? ps->p : "(end)", ps->s);
}

/* Read an exponent after '^' as a doubled integer. */
static int parse_exponent(struct parser *ps, int *e2)
{
	char *end;
	double e;
	bool paren = false;

	skip_blanks(ps);
	if (*ps->p == '(') {
		paren = true;
		ps->p++;
	}
	e = strtod(ps->p, &end);
	if (end == ps->p)
		return err_at(ps, "expected an exponent");
	ps->p = end;
	if (*ps->p == '/' && ps->p[1] >= '0' && ps->p[1] <= '9') { /* n/d */
		double d = strtod(ps->p + 1, &end);

		if (end == ps->p + 1 || d == 0)
			return err_at(ps, "bad rational exponent");
		ps->p = end;
		e /= d;
	}
	if (paren) {
		if (*ps->p != ')')
			return err_at(ps, "expected ')'");
		ps->p++;
	}
	if (fabs(2 * e - nearbyint(2 * e)) > 1e-12 || fabs(e) > 12)
		return err_at(ps, "exponent must be a multiple of 1/2");
	*e2 = (int)nearbyint(2 * e);
	return 0;
}

static void val_pow(struct val *v, int e2)
{
	int i;

	v->scale = pow(v->scale, e2 / 2.0);
	for (i = 0; i < SSCOPE_UNIT_DIM_COUNT; i++)
		v->dim2[i] = v->dim2[i] * e2 / 2;
}

/* Can dims be raised to e2/2 without leaving half-integers behind? */
static bool pow_ok(const struct val *v, int e2)
{
	int i;

	for (i = 0; i < SSCOPE_UNIT_DIM_COUNT; i++)
		if ((v->dim2[i] * e2) % 2)
			return false;
	return true;
}

/* Optimal string alignment distance (Levenshtein with transpositions)
 * of two short strings; long ones count as far. */
static size_t edit_distance(const char *a, size_t na, const char *b, size_t nb,
			    bool fold)
{
	size_t d[33][33];

	if (na > 32 || nb > 32)
		return SIZE_MAX;
	for (size_t i = 0; i <= na; i++)
		d[i][0] = i;
	for (size_t j = 0; j <= nb; j++)
		d[0][j] = j;
	for (size_t i = 1; i <= na; i++)
		for (size_t j = 1; j <= nb; j++) {
			char x = a[i - 1], y = b[j - 1];
			size_t c;

			if (fold) {
				x = (char)(x >= 'A' && x <= 'Z' ? x + 32 : x);
				y = (char)(y >= 'A' && y <= 'Z' ? y + 32 : y);
			}
			c = d[i - 1][j - 1] + (x != y);

			if (d[i - 1][j] + 1 < c)
				c = d[i - 1][j] + 1;
			if (d[i][j - 1] + 1 < c)
				c = d[i][j - 1] + 1;
			if (i > 1 && j > 1 && a[i - 1] == b[j - 2] &&
			    a[i - 2] == b[j - 1] && d[i - 2][j - 2] + 1 < c)
				c = d[i - 2][j - 2] + 1;
			d[i][j] = c;
		}
	return d[na][nb];
}

/* the spellings users type most, as whole expressions */
static const char *const common_units[] = {
	"rad/s", "deg/s", "dps", "deg/h", "rpm", "rad", "deg", "m/s^2", "g",
	"mg", "ug", "V", "mV", "uV", "degC", "K", "counts", "s", "ms", "us",
	"ns", "Hz", "deg/sqrt(h)", "deg/h/sqrt(h)", "m/s/sqrt(h)",
	"ug/sqrt(Hz)", "mg/sqrt(Hz)", "rad/s/sqrt(Hz)", "m/s", "ppm", NULL
};

/* " (nearest known: a, b, c)" for an unknown atom, or "" when nothing is
 * close: the whole text against the common expressions, the atom against
 * the listed atoms; at most 3, within max(1, length / 3) edits. */
static void suggest(const char *text, const char *atom, size_t alen,
		    char *buf, size_t len)
{
	const char *best[3] = { NULL, NULL, NULL };
	size_t bd[3] = { SIZE_MAX, SIZE_MAX, SIZE_MAX };
	size_t tl = strlen(text), used = 0;
	const char *cand;

	buf[0] = '\0';
	for (size_t pass = 0; pass < 2; pass++) {
		size_t n = pass == 0 ? sizeof(common_units) / sizeof(common_units[0]) - 1 :
				       sizeof(atoms) / sizeof(atoms[0]);
		const char *s = pass == 0 ? text : atom;
		size_t sl = pass == 0 ? tl : alen;
		size_t lim = sl / 3 > 1 ? sl / 3 : 1;

		for (size_t i = 0; i < n; i++) {
			size_t d, k;
			bool dup = false;

			cand = pass == 0 ? common_units[i] : atoms[i].name;
			if ((unsigned char)cand[0] >= 0x80)
				continue; /* ASCII spellings are suggested */
			/* case-blind edits first, exact case breaks ties */
			d = edit_distance(s, sl, cand, strlen(cand), true);
			if (d > lim)
				continue;
			d = 2 * d + (edit_distance(s, sl, cand, strlen(cand), false) > d);
			for (k = 0; k < 3; k++)
				dup |= best[k] && !strcmp(best[k], cand);
			if (dup)
				continue;
			for (k = 0; k < 3 && d >= bd[k]; k++)
				;
			if (k == 3)
				continue;
			for (size_t m = 2; m > k; m--) {
				best[m] = best[m - 1];
				bd[m] = bd[m - 1];
			}
			best[k] = cand;
			bd[k] = d;
		}
	}
	for (size_t k = 0; k < 3 && best[k]; k++) {
		int w = snprintf(buf + used, len - used, "%s%s",
				 k ? ", " : " (nearest known: ", best[k]);

		if (w < 0 || (size_t)w >= len - used) {
			buf[0] = '\0';
			return;
		}
		used += (size_t)w;
	}
	if (used && used + 2 < len)
		snprintf(buf + used, len - used, ")");
}

static int parse_atom(struct parser *ps, struct val *out)
{
	const char *start = ps->p, *q = ps->p;
	const struct atom *best = NULL;
	size_t best_len = 0, i;

	while (*q && is_atom_byte((unsigned char)*q) && !is_operator_utf8(q))
		q++;
	/* longest listed atom that is a prefix of the run and ends it, or is
	 * followed directly by exponent digits ("s2") */
	for (i = 0; i < sizeof(atoms) / sizeof(atoms[0]); i++) {
		size_t n = strlen(atoms[i].name);

		if (n > (size_t)(q - start) || strncmp(start, atoms[i].name, n))
			continue;
		if (start + n != q)
			continue;
		if (n > best_len) {
			best = &atoms[i];
			best_len = n;
		}
	}
	if (!best) {
		int len = (int)(q - start);
		char near[96];

		if (len == 0)
			return err_at(ps, "expected a unit");
		suggest(ps->s, start, (size_t)len, near, sizeof(near));
		if (start == ps->s && (size_t)len == strlen(ps->s))
			return ssc_diag(ps->diag, -EINVAL, "unknown unit '%s'%s",
					ps->s, near);
		return ssc_diag(ps->diag, -EINVAL, "unknown unit '%.*s' in '%s'%s",
				len, start, ps->s, near);
	}
	ps->p = start + best_len;
	out->scale = best->scale;
	for (i = 0; i < SSCOPE_UNIT_DIM_COUNT; i++)
		out->dim2[i] = best->dim2[i];
	ps->n_factors++;
	ps->last_atom = best;
	return 0;
}

static int primary(struct parser *ps, struct val *out);

/* Nesting is bounded: "((((...": an error, never a stack overflow. */
static int parse_primary(struct parser *ps, struct val *out)
{
	int rc;

	if (ps->depth >= 32)
		return err_at(ps, "parentheses nested deeper than 32");
	ps->depth++;
	rc = primary(ps, out);
	ps->depth--;
	return rc;
}

static int primary(struct parser *ps, struct val *out)
{
	int rc;

	skip_blanks(ps);
	if (*ps->p == '(') {
		ps->p++;
		rc = parse_expr(ps, out);
		if (rc)
			return rc;
		skip_blanks(ps);
		if (*ps->p != ')')
			return err_at(ps, "expected ')'");
		ps->p++;
		return 0;
	}
	if (starts(ps->p, "sqrt(") || starts(ps->p, U_SQRT)) {
		bool word = *ps->p == 's';

		ps->p += word ? 5 : strlen(U_SQRT);
		if (word) {
			rc = parse_expr(ps, out);
			if (rc)
				return rc;
			skip_blanks(ps);
			if (*ps->p != ')')
				return err_at(ps, "expected ')'");
			ps->p++;
		} else {
			rc = parse_primary(ps, out);
			if (rc)
				return rc;
		}
		ps->n_factors++; /* a root is never a lone temperature */
		out->scale = sqrt(out->scale);
		for (int i = 0; i < SSCOPE_UNIT_DIM_COUNT; i++) {
			if (out->dim2[i] % 2)
				return err_at(ps, "square root of a square root");
			out->dim2[i] /= 2;
		}
		return 0;
	}
	if ((*ps->p >= '0' && *ps->p <= '9') || *ps->p == '.') {
		char *end;
		double x = strtod(ps->p, &end);

		if (!(x > 0) || !isfinite(x))
			return err_at(ps, "bad numeric factor");
		ps->p = end;
		out->scale = x;
		memset(out->dim2, 0, sizeof(out->dim2));
		if (x != 1)
			ps->n_factors++;
		return 0;
	}
	return parse_atom(ps, out);
}

static int parse_term(struct parser *ps, struct val *out)
{
	int rc, e2 = 2, len;
	bool atom_end;

	rc = parse_primary(ps, out);
	if (rc)
		return rc;
	/* "s2" (exponent written right after an atom's letters) */
	atom_end = ps->p > ps->s && is_atom_byte((unsigned char)ps->p[-1]);
	if (*ps->p == '^' || starts(ps->p, "**")) {
		ps->p += *ps->p == '^' ? 1 : 2;
		rc = parse_exponent(ps, &e2);
		if (rc)
			return rc;
	} else if (atom_end && *ps->p >= '1' && *ps->p <= '9' &&
		   !(ps->p[1] >= '0' && ps->p[1] <= '9')) {
		e2 = 2 * (*ps->p - '0');
		ps->p++;
	} else if (starts(ps->p, U_MINUS) || superscript_digit(ps->p, &len) >= 0) {
		int sign = 1, d;

		if (starts(ps->p, U_MINUS)) {
			sign = -1;
			ps->p += strlen(U_MINUS);
		}
		d = superscript_digit(ps->p, &len);
		if (d < 0)
			return err_at(ps, "expected a superscript digit");
		ps->p += len;
		e2 = 2 * sign * d;
	}
	if (e2 != 2) {
		if (!pow_ok(out, e2))
			return err_at(ps, "exponent leaves a fractional power");
		val_pow(out, e2);
		ps->lone_power_one = false;
	}
	return 0;
}

static int parse_expr(struct parser *ps, struct val *out)
{
	int rc, i;

	rc = parse_term(ps, out);
	if (rc)
		return rc;
	for (;;) {
		struct val rhs;
		bool divide = false;
		const char *save;

		save = ps->p;
		skip_blanks(ps);
		if (*ps->p == '/') {
			divide = true;
			ps->p++;
		} else if (*ps->p == '*' && ps->p[1] != '*') {
			ps->p++;
		} else if (starts(ps->p, U_DOT)) {
			ps->p += strlen(U_DOT);
		} else if (ps->p != save && *ps->p && *ps->p != ')') {
			/* implicit product: "rad s^-1" */
		} else {
			ps->p = save;
			return 0;
		}
		rc = parse_term(ps, &rhs);
		if (rc)
			return rc;
		if (divide) {
			out->scale /= rhs.scale;
			for (i = 0; i < SSCOPE_UNIT_DIM_COUNT; i++)
				out->dim2[i] -= rhs.dim2[i];
		} else {
			out->scale *= rhs.scale;
			for (i = 0; i < SSCOPE_UNIT_DIM_COUNT; i++)
				out->dim2[i] += rhs.dim2[i];
		}
	}
}

int sscope_unit_parse(const char *text, struct sscope_unit *unit,
		      struct sscope_diag *diag)
{
	struct parser ps = { .s = text, .p = text, .diag = diag,
			     .lone_power_one = true };
	struct val v = { 1, { 0 } };
	int rc, i;

	if (!text || !unit)
		return ssc_diag(diag, -EINVAL, "no unit given");
	skip_blanks(&ps);
	if (*ps.p == '\0') {
		memset(unit, 0, sizeof(*unit));
		unit->scale = 1;
		return 0;
	}
	rc = parse_expr(&ps, &v);
	if (rc)
		return rc;
	skip_blanks(&ps);
	if (*ps.p != '\0')
		return err_at(&ps, "unexpected text");
	for (i = 0; i < SSCOPE_UNIT_DIM_COUNT; i++) {
		if (v.dim2[i] > 127 || v.dim2[i] < -128)
			return err_at(&ps, "exponent too large");
	}
	if (!(v.scale > 0) || !isfinite(v.scale))
		return ssc_diag(diag, -EINVAL, "unit '%s' has no finite scale",
				text);
	unit->scale = v.scale;
	unit->offset = 0;
	for (i = 0; i < SSCOPE_UNIT_DIM_COUNT; i++)
		unit->dim2[i] = (int8_t)v.dim2[i];
	/* an absolute temperature only when the unit is one temperature atom */
	if (ps.n_factors == 1 && ps.lone_power_one && ps.last_atom &&
	    ps.last_atom->dim2[K] == 2)
		unit->offset = ps.last_atom->offset;
	return 0;
}

bool sscope_unit_compatible(const struct sscope_unit *a,
			    const struct sscope_unit *b)
{
	return memcmp(a->dim2, b->dim2, sizeof(a->dim2)) == 0;
}

double sscope_unit_to_si(const struct sscope_unit *unit, double value)
{
	return value * unit->scale + unit->offset;
}

double sscope_unit_from_si(const struct sscope_unit *unit, double si)
{
	return (si - unit->offset) / unit->scale;
}

int sscope_unit_convert(double value, const struct sscope_unit *from,
			const struct sscope_unit *to, double *out)
{
	if (!sscope_unit_compatible(from, to))
		return -EDOM;
	*out = sscope_unit_from_si(to, sscope_unit_to_si(from, value));
	return 0;
}

int sscope_unit_convert_text(double value, const char *from, const char *to,
			     double *out)
{
	struct sscope_unit a, b;
	int rc;

	rc = sscope_unit_parse(from, &a, NULL);
	if (!rc)
		rc = sscope_unit_parse(to, &b, NULL);
	if (rc)
		return rc;
	return sscope_unit_convert(value, &a, &b, out);
}

static const struct {
	enum sscope_quantity q;
	const char *name;
	const char *si;
	int8_t dim2[SSCOPE_UNIT_DIM_COUNT];
} quantities[] = {
	{ SSCOPE_QUANTITY_DIMENSIONLESS, "dimensionless", "1", D(0, 0, 0, 0, 0, 0) },
	{ SSCOPE_QUANTITY_COUNTS, "counts", "counts", D(0, 0, 0, 0, 0, 1) },
	{ SSCOPE_QUANTITY_ANGULAR_RATE, "angular rate", "rad/s", D(0, -1, 1, 0, 0, 0) },
	{ SSCOPE_QUANTITY_ACCELERATION, "acceleration", "m/s^2", D(1, -2, 0, 0, 0, 0) },
	{ SSCOPE_QUANTITY_ANGLE, "angle", "rad", D(0, 0, 1, 0, 0, 0) },
	{ SSCOPE_QUANTITY_VELOCITY, "velocity", "m/s", D(1, -1, 0, 0, 0, 0) },
	{ SSCOPE_QUANTITY_LENGTH, "length", "m", D(1, 0, 0, 0, 0, 0) },
	{ SSCOPE_QUANTITY_TIME, "time", "s", D(0, 1, 0, 0, 0, 0) },
	{ SSCOPE_QUANTITY_FREQUENCY, "frequency", "Hz", D(0, -1, 0, 0, 0, 0) },
	{ SSCOPE_QUANTITY_TEMPERATURE, "temperature", "degC", D(0, 0, 0, 1, 0, 0) },
	{ SSCOPE_QUANTITY_VOLTAGE, "voltage", "V", D(0, 0, 0, 0, 1, 0) },
	{ SSCOPE_QUANTITY_ANGULAR_ACCEL, "angular acceleration", "rad/s^2",
	  D(0, -2, 1, 0, 0, 0) },
	{ SSCOPE_QUANTITY_JERK, "jerk", "m/s^3", D(1, -3, 0, 0, 0, 0) },
};

#define N_QTY (sizeof(quantities) / sizeof(quantities[0]))

enum sscope_quantity sscope_unit_quantity(const struct sscope_unit *unit)
{
	size_t i;

	for (i = 0; i < N_QTY; i++)
		if (!memcmp(unit->dim2, quantities[i].dim2, sizeof(unit->dim2)))
			return quantities[i].q;
	return SSCOPE_QUANTITY_UNKNOWN;
}

const char *sscope_quantity_name(enum sscope_quantity q)
{
	size_t i;

	for (i = 0; i < N_QTY; i++)
		if (quantities[i].q == q)
			return quantities[i].name;
	return "unknown";
}

const char *sscope_quantity_si_unit(enum sscope_quantity q)
{
	size_t i;

	for (i = 0; i < N_QTY; i++)
		if (quantities[i].q == q)
			return quantities[i].si;
	return "";
}

static const char *const dim_sym[SSCOPE_UNIT_DIM_COUNT] = {
	[L] = "m", [T] = "s", [A] = "rad", [K] = "degC", [V] = "V",
	[C] = "counts",
};

/* Append sym^(e2/2) to buf (e2 > 0). */
static void put_power(char *buf, size_t len, const char *sep, const char *sym,
		      int e2)
{
	size_t used = strlen(buf);

	if (used >= len)
		return;
	if (e2 == 2)
		snprintf(buf + used, len - used, "%s%s", sep, sym);
	else if (e2 % 2 == 0)
		snprintf(buf + used, len - used, "%s%s^%d", sep, sym, e2 / 2);
	else if (e2 == 1)
		snprintf(buf + used, len - used, "%ssqrt(%s)", sep, sym);
	else
		snprintf(buf + used, len - used, "%s%s^%d/2", sep, sym, e2);
}

int sscope_unit_si_string(const struct sscope_unit *unit, char *buf,
			  size_t len)
{
	static const int order[] = { L, A, V, C, K };
	int d[SSCOPE_UNIT_DIM_COUNT], i;
	bool root_hz = false, any = false;
	size_t used;

	if (!len)
		return -ERANGE;
	buf[0] = '\0';
	for (i = 0; i < SSCOPE_UNIT_DIM_COUNT; i++)
		d[i] = unit->dim2[i];
	/* noise densities: X s^(1/2) is written X/sqrt(Hz) with X s^-1 */
	if (d[T] % 2) {
		root_hz = true;
		d[T] -= 1;
	}
	for (i = 0; i < 5; i++) {
		if (d[order[i]] > 0) {
			put_power(buf, len, any ? "*" : "", dim_sym[order[i]],
				  d[order[i]]);
			any = true;
		}
	}
	if (d[T] > 0) {
		put_power(buf, len, any ? "*" : "", "s", d[T]);
		any = true;
	}
	if (!any)
		snprintf(buf, len, "1");
	if (d[T] < 0)
		put_power(buf, len, "/", "s", -d[T]);
	for (i = 0; i < 5; i++)
		if (d[order[i]] < 0)
			put_power(buf, len, "/", dim_sym[order[i]],
				  -d[order[i]]);
	if (root_hz) {
		used = strlen(buf);
		if (!strcmp(buf, "1"))
			snprintf(buf, len, "1/sqrt(Hz)");
		else if (used < len)
			snprintf(buf + used, len - used, "/sqrt(Hz)");
	}
	return strlen(buf) + 1 >= len ? -ERANGE : 0;
}

int sscope_quantity_parse(const char *text, double *si_value,
			  struct sscope_unit *unit, struct sscope_diag *diag)
{
	struct sscope_unit u;
	const char *p = text, *end;
	double x;
	size_t used;
	int rc;

	if (!text)
		return ssc_diag(diag, -EINVAL, "no value given");
	while (*p == ' ' || *p == '\t')
		p++;
	end = p + strlen(p);
	used = ssc_parse_double(p, end, &x);
	if (!used || !isfinite(x))
		return ssc_diag(diag, -EINVAL, "'%s' is not a number", text);
	rc = sscope_unit_parse(p + used, &u, diag);
	if (rc)
		return rc;
	*si_value = sscope_unit_to_si(&u, x);
	if (unit)
		*unit = u;
	return 0;
}

static const char *const term_units[2][2][SSCOPE_TERM_COUNT_] = {
	{ /* angular rate: conventional, SI */
	  { "arcsec", "deg/sqrt(h)", "deg/h", "deg/h/sqrt(h)", "deg/h/h",
	    "deg/s" },
	  { "rad", "rad/s/sqrt(Hz)", "rad/s", "rad/s^2/sqrt(Hz)", "rad/s^2",
	    "rad/s" } },
	{ /* acceleration */
	  { "m/s", "m/s/sqrt(h)", "ug", "ug/sqrt(h)", "ug/h", "g" },
	  { "m/s", "m/s^2/sqrt(Hz)", "m/s^2", "m/s^3/sqrt(Hz)", "m/s^3",
	    "m/s^2" } },
};

static const char *term_unit(enum sscope_quantity q, enum sscope_term t,
			     int si)
{
	int k;

	if (t < 0 || t >= SSCOPE_TERM_COUNT_)
		return NULL;
	if (q == SSCOPE_QUANTITY_ANGULAR_RATE)
		k = 0;
	else if (q == SSCOPE_QUANTITY_ACCELERATION)
		k = 1;
	else
		return NULL;
	return term_units[k][si][t];
}

const char *sscope_term_unit(enum sscope_quantity q, enum sscope_term t)
{
	return term_unit(q, t, 0);
}

const char *sscope_term_si_unit(enum sscope_quantity q, enum sscope_term t)
{
	return term_unit(q, t, 1);
}
