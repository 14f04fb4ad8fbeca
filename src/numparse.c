/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Correctly rounded decimal-to-double conversion, fast for the numbers
 * capture files hold.
 *
 * Path 1 (Clinger, "How to read floating point numbers accurately", PLDI
 * 1990): a decimal with at most 2^53 as significand and |exponent| <= 22 is
 * one exact double times or divided by one exact power of ten, so a single
 * IEEE operation rounds it correctly.
 * Path 2: significands up to 19 digits and |exponent| <= 27 are exact in
 * x87 extended precision (64-bit significand); one extended operation gives
 * the value within half an extended ulp, and rounding that to double is
 * correct unless it lies within one extended ulp of a double half-way point,
 * which is detected and sent to path 3.
 * Path 3: everything else (more digits, huge exponents, ties) goes to the C
 * library's strtod, which is correctly rounded in glibc.
 * Why hand-written: no C library in Debian offers locale-independent,
 * correctly rounded parsing of a non-terminated buffer at this speed
 * (fast_float and double-conversion are C++).
 */
#include "internal.h"

#include <float.h>
#include <locale.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const double pow10_exact[] = {
	1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
	1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
};

#if LDBL_MANT_DIG == 64
static const long double pow10_ld[] = {
	1e0L,  1e1L,  1e2L,  1e3L,  1e4L,  1e5L,  1e6L,  1e7L,  1e8L,  1e9L,
	1e10L, 1e11L, 1e12L, 1e13L, 1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L,
	1e20L, 1e21L, 1e22L, 1e23L, 1e24L, 1e25L, 1e26L, 1e27L,
};
#endif

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

/*
 * Eight digits at once (SWAR), after Lemire, "Fast number parsing without
 * fallback" (Software: Practice and Experience, 2023): test that 8 bytes
 * are all ASCII digits, then combine them in three multiplications.
 */
static inline uint64_t load8(const char *p)
{
	uint64_t v;

	memcpy(&v, p, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
	v = __builtin_bswap64(v);
#endif
	return v;
}

static inline bool all8_digits(uint64_t v)
{
	return ((v & 0xF0F0F0F0F0F0F0F0u) |
		(((v + 0x0606060606060606u) & 0xF0F0F0F0F0F0F0F0u) >> 4)) ==
	       0x3333333333333333u;
}

static inline uint64_t parse8(uint64_t v)
{
	const uint64_t mask = 0x000000FF000000FFu;
	const uint64_t mul1 = 100 + (UINT64_C(1000000) << 32);
	const uint64_t mul2 = 1 + (UINT64_C(10000) << 32);

	v -= 0x3030303030303030u;
	v = (v * 10) + (v >> 8);
	return (((v & mask) * mul1) + (((v >> 16) & mask) * mul2)) >> 32;
}

/* Accumulate the digits at p into *mant (may wrap: callers count digits
 * and leave long significands to strtod). */
static inline const char *digits(const char *p, const char *end,
				 uint64_t *mant)
{
	uint64_t m = *mant;

	while (end - p >= 8) {
		uint64_t v = load8(p);

		if (!all8_digits(v))
			break;
		m = m * 100000000u + parse8(v);
		p += 8;
	}
	while (p < end && is_digit(*p))
		m = m * 10 + (uint64_t)(*p++ - '0');
	*mant = m;
	return p;
}

size_t sscope_parse_double(const char *p, const char *end, double *out)
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
#if LDBL_MANT_DIG == 64
	if (exp10 >= -27 && exp10 <= 27) {
		long double v = (long double)mant, m;
		uint64_t bits, low;
		int e2;

		v = exp10 < 0 ? v / pow10_ld[-exp10] : v * pow10_ld[exp10];
		m = frexpl(v, &e2);
		bits = (uint64_t)ldexpl(m, 64);
		low = bits & 0x7ff;
		if (low < 0x3ff || low > 0x401) {
			double d = (double)v;

			*out = neg ? -d : d;
			return n;
		}
	}
#endif
slow:
	*out = slow_strtod(s, n);
	return n;
}
