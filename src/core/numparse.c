/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Correctly rounded decimal-to-double conversion, fast for the numbers
 * capture files hold.
 *
 * Path 1 (Clinger, "How to read floating point numbers accurately", PLDI
 * 1990): a decimal with at most 2^53 as significand and |exponent| <= 22 is
 * one exact double times or divided by one exact power of ten, so a single
 * IEEE operation rounds it correctly.
 * Path 2: significands up to 19 digits and |exponent| <= 27: the significand
 * and the power of ten are exact double-doubles, their product or quotient
 * is formed in double-double arithmetic (Dekker, "A floating-point
 * technique for extending the available precision", Numer. Math. 1971),
 * good to about 2^-100 relative; rounding it to double is correct unless it
 * lies that close to a half-way point between doubles, which is detected and
 * sent to path 3.  (Only IEEE double operations: exact under valgrind too,
 * unlike x87 long double.)
 * Path 3: everything else (more digits, huge exponents, ties) goes to the C
 * library's strtod, which is correctly rounded in glibc.
 * Why hand-written: no C library in Debian offers locale-independent,
 * correctly rounded parsing of a non-terminated buffer at this speed
 * (fast_float and double-conversion are C++).
 */
#include "internal.h"
#include "numparse.h"

#include <locale.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double pow10_exact[] = {
	1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
	1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
};

/* ---- double-double arithmetic (error-free transformations) */

struct dd {
	double hi, lo;
};

static inline struct dd two_sum(double a, double b)
{
	double s = a + b, bb = s - a;

	return (struct dd){ s, (a - (s - bb)) + (b - bb) };
}

static inline struct dd quick_two_sum(double a, double b)
{
	double s = a + b;

	return (struct dd){ s, b - (s - a) };
}

static inline void split(double a, double *hi, double *lo)
{
	double c = 134217729.0 * a; /* 2^27 + 1 */

	*hi = c - (c - a);
	*lo = a - *hi;
}

static inline struct dd two_prod(double a, double b)
{
	double p = a * b, ah, al, bh, bl;

	split(a, &ah, &al);
	split(b, &bh, &bl);
	return (struct dd){ p, ((ah * bh - p) + ah * bl + al * bh) + al * bl };
}

static inline struct dd dd_mul(struct dd a, struct dd b)
{
	struct dd p = two_prod(a.hi, b.hi);

	p.lo += a.hi * b.lo + a.lo * b.hi;
	return quick_two_sum(p.hi, p.lo);
}

static inline struct dd dd_sub(struct dd a, struct dd b)
{
	struct dd s = two_sum(a.hi, -b.hi);

	s.lo += a.lo - b.lo;
	return quick_two_sum(s.hi, s.lo);
}

static inline struct dd dd_div(struct dd a, struct dd b)
{
	double q1 = a.hi / b.hi, q2, q3;
	struct dd r = dd_sub(a, dd_mul((struct dd){ q1, 0 }, b)), s;

	q2 = r.hi / b.hi;
	r = dd_sub(r, dd_mul((struct dd){ q2, 0 }, b));
	q3 = r.hi / b.hi;
	s = quick_two_sum(q1, q2);
	s.lo += q3;
	return quick_two_sum(s.hi, s.lo);
}

/* An integer below 2^64 as an exact double-double. */
static inline struct dd dd_u64(uint64_t m)
{
	double hi = (double)m;
	uint64_t h = hi >= 18446744073709551616.0 ? UINT64_MAX : (uint64_t)hi;

	return (struct dd){ hi, (double)(int64_t)(m - h) };
}

/* 10^k, 0 <= k <= 27, exactly: one double up to 10^22 (5^22 < 2^53),
 * else 5^k < 2^63 as a double-double times 2^k. */
static inline struct dd dd_pow10(int k)
{
	uint64_t f = 1;
	struct dd d;

	if (k <= 22)
		return (struct dd){ pow10_exact[k], 0 };
	for (int i = 0; i < k; i++)
		f *= 5;
	d = dd_u64(f);
	d.hi = ldexp(d.hi, k);
	d.lo = ldexp(d.lo, k);
	return d;
}

/* Round a positive normal double-double within rel_err of the exact
 * value to double; false when it lies too near a half-way point to
 * decide. */
static inline bool dd_round(struct dd x, double rel_err, double *out)
{
	double up, gap, half;
	uint64_t bits;

	if (x.lo == 0) {
		*out = x.hi;
		return true;
	}
	/* the neighbour of hi on lo's side (nextafter without the call: hi
	 * is positive and normal, its neighbours one unit of its bits away) */
	memcpy(&bits, &x.hi, 8);
	bits = x.lo > 0 ? bits + 1 : bits - 1;
	memcpy(&up, &bits, 8);
	gap = fabs(up - x.hi);
	half = gap / 2;
	if (fabs(half - fabs(x.lo)) <= rel_err * fabs(x.hi))
		return false;
	*out = fabs(x.lo) < half ? x.hi : up;
	return true;
}

static inline int lower(int c)
{
	return (c >= 'A' && c <= 'Z') ? c + ('a' - 'A') : c;
}

static size_t match_word(const char *p, const char *end, const char *w)
{
	size_t n = strlen(w), i;

	if ((size_t)(end - p) < n)
		return 0;
	for (i = 0; i < n; i++)
		if (lower((unsigned char)p[i]) != w[i])
			return 0;
	return n;
}

/* strtod on a copy, with '.' mapped to the locale's decimal point. */
static double slow_strtod(const char *p, size_t n)
{
	char buf[128], *heap = NULL, *b = buf, *q;
	const char *dp = localeconv()->decimal_point;
	double v;

	if (n + 8 > sizeof(buf)) {
		heap = malloc(n + 8);
		if (!heap)
			return NAN;
		b = heap;
	}
	q = b;
	for (size_t i = 0; i < n; i++) {
		if (p[i] == '.' && dp && dp[0] && strcmp(dp, ".")) {
			size_t l = strlen(dp);

			if (l > 7)
				l = 7;
			memcpy(q, dp, l);
			q += l;
			continue;
		}
		*q++ = p[i];
	}
	*q = '\0';
	v = strtod(b, NULL);
	free(heap);
	return v;
}

static inline bool is_digit(char c)
{
	return (unsigned char)(c - '0') < 10;
}

/* Accumulate the digits at p into *mant (may wrap: callers count digits
 * and leave long significands to strtod). */
static inline const char *digits(const char *p, const char *end,
				 uint64_t *mant)
{
	uint64_t m = *mant;

	while (end - p >= 8) {
		uint64_t v = ssc_load8(p);

		if (!ssc_all8_digits(v))
			break;
		m = m * 100000000u + ssc_parse8(v);
		p += 8;
	}
	while (p < end && is_digit(*p))
		m = m * 10 + (uint64_t)(*p++ - '0');
	*mant = m;
	return p;
}

size_t ssc_parse_double(const char *p, const char *end, double *out)
{
	const char *s = p, *d0, *sig, *f0;
	bool neg = false;
	uint64_t mant = 0;
	long exp10 = 0;
	long nd;      /* significant digits accumulated in mant */
	size_t n;

	if (p < end && (*p == '-' || *p == '+')) {
		neg = *p == '-';
		p++;
	}
	if (p < end && !is_digit(*p) && *p != '.') {
		if ((n = match_word(p, end, "nan"))) {
			*out = neg ? -NAN : NAN;
			return (size_t)(p - s) + n;
		}
		if ((n = match_word(p, end, "infinity")) ||
		    (n = match_word(p, end, "inf"))) {
			*out = neg ? -INFINITY : INFINITY;
			return (size_t)(p - s) + n;
		}
		return 0;
	}
	d0 = p;
	while (p < end && *p == '0') /* leading zeros are not significant */
		p++;
	sig = p;
	p = digits(p, end, &mant);
	nd = p - sig;
	if (p < end && *p == '.') {
		const char *f1;

		f0 = ++p;
		if (nd == 0)
			while (p < end && *p == '0')
				p++;
		f1 = p;
		p = digits(p, end, &mant);
		nd += p - f1;
		exp10 = -(long)(p - f0);
		if (p == f0 && f0 - 1 == d0) /* "." alone */
			return 0;
	} else if (p == d0) {
		return 0;
	}
	if (p < end && (*p == 'e' || *p == 'E')) {
		const char *q = p + 1;
		bool eneg = false;
		long e = 0;

		if (q < end && (*q == '-' || *q == '+')) {
			eneg = *q == '-';
			q++;
		}
		if (q < end && is_digit(*q)) {
			while (q < end && is_digit(*q)) {
				if (e < 100000)
					e = e * 10 + (*q - '0');
				q++;
			}
			exp10 += eneg ? -e : e;
			p = q;
		}
	}
	n = (size_t)(p - s);
	if (nd > 19) /* mant overflowed: exact conversion by the C library */
		goto slow;
	if (mant == 0) {
		*out = neg ? -0.0 : 0.0;
		return n;
	}
	if (mant <= (UINT64_C(1) << 53) && exp10 >= -22 && exp10 <= 22) {
		double v = (double)mant;

		v = exp10 < 0 ? v / pow10_exact[-exp10] : v * pow10_exact[exp10];
		*out = neg ? -v : v;
		return n;
	}
	if (exp10 >= -27 && exp10 <= 27) {
		struct dd m = dd_u64(mant), x;
		double d;

		x = exp10 < 0 ? dd_div(m, dd_pow10((int)-exp10)) :
				dd_mul(m, dd_pow10((int)exp10));
		if (dd_round(x, 0x1p-96, &d)) {
			*out = neg ? -d : d;
			return n;
		}
	}
slow:
	*out = slow_strtod(s, n);
	return n;
}
