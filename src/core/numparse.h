/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Inline helpers of the number parser (numparse.c) shared with the
 * delimited-text reader: eight digits at once (SWAR), and the conversion
 * of a cell whose extent is already known, without a loop or a branch per
 * digit.
 *
 * Eight digits at once after Lemire, "Fast number parsing without
 * fallback" (Software: Practice and Experience, 2023): test that 8 bytes
 * are all ASCII digits, then combine them in three multiplications.
 * A known cell: the 16 bytes that end with it are validated as two words,
 * the decimal point is squeezed out by shifts, and the
 * value is one exact integer divided by one exact power of ten (Clinger,
 * "How to read floating point numbers accurately", PLDI 1990: correctly
 * rounded, so equal to strtod).
 */
#ifndef SSCOPE_NUMPARSE_H
#define SSCOPE_NUMPARSE_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

static inline uint64_t ssc_load8(const char *p)
{
	uint64_t v;

	memcpy(&v, p, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
	v = __builtin_bswap64(v);
#endif
	return v;
}

static inline bool ssc_all8_digits(uint64_t v)
{
	return ((v & 0xF0F0F0F0F0F0F0F0u) |
		(((v + 0x0606060606060606u) & 0xF0F0F0F0F0F0F0F0u) >> 4)) ==
	       0x3333333333333333u;
}

/* The value of eight ASCII digits, the first in the lowest byte. */
static inline uint64_t ssc_parse8(uint64_t v)
{
	const uint64_t mask = 0x000000FF000000FFu;
	const uint64_t mul1 = 100 + (UINT64_C(1000000) << 32);
	const uint64_t mul2 = 1 + (UINT64_C(10000) << 32);

	v -= 0x3030303030303030u;
	v = (v * 10) + (v >> 8);
	return (((v & mask) * mul1) + (((v >> 16) & mask) * mul2)) >> 32;
}

/* Where the digits (or the point) of the cell of len bytes ending at e
 * start in the 16 bytes before e: after the sign; 16 when the cell cannot
 * be a plain decimal of at most 15 bytes. */
static inline unsigned ssc_cell_start(const char *e, size_t len, bool *neg)
{
	if (len - 1 >= 15)
		return 16;
	*neg = e[-(ptrdiff_t)len] == '-';
	return 16 - (unsigned)len + (*neg | (e[-(ptrdiff_t)len] == '+'));
}

/* The cell's value from its exact decimal +-m * 10^-f (m below 2^53,
 * f <= 14): one correctly rounded division (Clinger).  v may be NULL when
 * only the exact decimal is wanted (no division then). */
static inline bool ssc_cell_value(uint64_t m, unsigned f, bool neg, double *v,
				  int64_t *mant, int *frac)
{
	static const double p10[] = { 1e0, 1e1, 1e2,  1e3,  1e4,
				      1e5, 1e6, 1e7,  1e8,  1e9,
				      1e10, 1e11, 1e12, 1e13, 1e14 };

	if (v) {
		double x = (double)(int64_t)m / p10[f];
		uint64_t bits;

		memcpy(&bits, &x, 8);
		bits |= (uint64_t)neg << 63;
		memcpy(v, &bits, 8);
	}
	*mant = neg ? -(int64_t)m : (int64_t)m;
	*frac = (int)f;
	return true;
}

#if defined(__SIZEOF_INT128__) && defined(__BYTE_ORDER__) && \
	__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
#define SSC_HAVE_PARSE_CELL 1

__extension__ typedef unsigned __int128 ssc_u128;

/* 0x80 in every byte of w that is not an ASCII digit (no carries between
 * bytes: a byte's low seven bits plus 0x76 stay below 0x100) */
static inline uint64_t ssc_nondigits8(uint64_t w)
{
	uint64_t x = w ^ 0x3030303030303030u;

	return (((x & 0x7F7F7F7F7F7F7F7Fu) + 0x7676767676767676u) | x) &
	       0x8080808080808080u;
}

/*
 * The cell of len bytes ending at e, 1 <= len <= 15, with the 16 bytes
 * before e readable: when it is a plain decimal, [+-]DIGITS[.DIGITS] or
 * [+-].DIGITS, set *v to its value (bit-identical to strtod), *mant and
 * *frac to the exact decimal *mant * 10^-*frac, and return true.  Anything
 * else (exponents, NaN, blanks, garbage, longer cells) returns false: the
 * caller then parses the cell with ssc_parse_double.
 *
 * The 16 bytes before e are one little-endian number w (byte i is
 * e[i - 16]), the cell in its top len bytes.
 */
static inline bool ssc_parse_cell(const char *e, size_t len, double *v,
				  int64_t *mant, int *frac)
{
	const ssc_u128 zeros = (ssc_u128)0x3030303030303030u << 64 |
			       0x3030303030303030u;
	ssc_u128 w, nd, low;
	uint64_t m;
	unsigned j, q, f;
	bool neg = false, dot;

	/* the digits (and the point) start at byte j */
	j = ssc_cell_start(e, len, &neg);
	if (j == 16)
		return false;
	memcpy(&w, e - 16, 16);
	nd = ((ssc_u128)ssc_nondigits8((uint64_t)(w >> 64)) << 64 |
	      ssc_nondigits8((uint64_t)w)) >> (8 * j);
	dot = nd != 0;
	f = 0;
	if (dot) { /* one non-digit, the point, then at least one digit */
		uint64_t lo = (uint64_t)nd;

		q = j + ((lo ? (unsigned)__builtin_ctzll(lo) :
			  64 + (unsigned)__builtin_ctzll((uint64_t)(nd >> 64))) >> 3);
		if ((nd & (nd - 1)) || e[(int)q - 16] != '.' || j == 15)
			return false;
		/* squeeze the point out: the bytes below it move up one */
		low = ((ssc_u128)1 << (8 * q)) - 1;
		w = ((w & low) << 8) | (w & ~(low << 8 | 0xFF));
		f = 15 - q;
		j++;
	}
	/* '0' below the digits (sign, point, bytes before the cell) */
	low = ((ssc_u128)1 << (8 * j)) - 1;
	w = (w & ~low) | (zeros & low);
	/* at most 15 digits: below 2^53, exact as a double */
	m = ssc_parse8((uint64_t)w) * 100000000u + ssc_parse8((uint64_t)(w >> 64));
	return ssc_cell_value(m, f, neg, v, mant, frac);
}
#endif

#if defined(__x86_64__) && defined(__GNUC__)
#define SSC_HAVE_PARSE_CELL_SSSE3 1
#include <tmmintrin.h>

/*
 * ssc_parse_cell with SSSE3 (the caller checks the processor has it): the
 * non-digits found by one comparison, the point squeezed out and the
 * digits right-aligned by one byte shuffle, eight digits combined in three
 * multiply-adds (Mula, "SIMD-ized faster parse of integers", 2014).
 */
__attribute__((target("ssse3"))) static inline bool
ssc_parse_cell_ssse3(const char *e, size_t len, double *v, int64_t *mant,
		     int *frac)
{
	const __m128i iota = _mm_setr_epi8(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10,
					   11, 12, 13, 14, 15);
	__m128i x, t, idx;
	unsigned j, nd, f;
	int q;
	uint64_t m;
	bool neg = false;

	/* the digits (and the point) start at byte j */
	j = ssc_cell_start(e, len, &neg);
	if (j == 16)
		return false;
	x = _mm_loadu_si128((const __m128i *)(const void *)(e - 16));
	t = _mm_sub_epi8(x, _mm_set1_epi8('0'));
	nd = (~(unsigned)_mm_movemask_epi8(_mm_cmpeq_epi8(
		      _mm_min_epu8(t, _mm_set1_epi8(9)), t)) &
	      0xFFFFu) >> j;
	q = -1;
	f = 0;
	if (nd) { /* one non-digit, the point, then at least one digit */
		q = (int)(j + (unsigned)__builtin_ctz(nd));
		if ((nd & (nd - 1)) || e[q - 16] != '.' || j == 15)
			return false;
		f = 15 - (unsigned)q;
		j++;
	}
	/* byte i takes byte i - 1 up to the point, byte i after it, and 0
	 * below the digits */
	idx = _mm_add_epi8(iota, _mm_cmpgt_epi8(_mm_set1_epi8((char)(q + 1)), iota));
	idx = _mm_or_si128(idx, _mm_cmpgt_epi8(_mm_set1_epi8((char)j), iota));
	t = _mm_shuffle_epi8(t, idx);
	t = _mm_maddubs_epi16(t, _mm_setr_epi8(10, 1, 10, 1, 10, 1, 10, 1, 10,
					       1, 10, 1, 10, 1, 10, 1));
	t = _mm_madd_epi16(t, _mm_setr_epi16(100, 1, 100, 1, 100, 1, 100, 1));
	t = _mm_packs_epi32(t, t);
	t = _mm_madd_epi16(t, _mm_setr_epi16(10000, 1, 10000, 1, 10000, 1,
					     10000, 1));
	/* at most 15 digits: below 2^53, exact as a double */
	m = (uint64_t)(uint32_t)_mm_cvtsi128_si32(t) * 100000000u +
	    (uint32_t)_mm_cvtsi128_si32(_mm_srli_si128(t, 4));
	return ssc_cell_value(m, f, neg, v, mant, frac);
}
#endif

#endif
