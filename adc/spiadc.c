/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Generic SPI converter frames (see sscope-spiadc.h): a frame template,
 * bit fields holding each channel's code, the code format, and the
 * straight-line conversion code -> volts -> physical unit.  Coding
 * conventions as in IEEE Std 1241 (straight binary, offset binary, two's
 * complement); LSB = span / 2^N.
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sscope-spiadc.h"
#include "sscope-quantity.h"
#include "sscope-unit.h"

static int hexval(char c)
{
	if (c >= '0' && c <= '9')
		return c - '0';
	if (c >= 'a' && c <= 'f')
		return c - 'a' + 10;
	if (c >= 'A' && c <= 'F')
		return c - 'A' + 10;
	return -1;
}

static int parse_tx(const char *v, size_t n, struct sscope_spiadc_frame *f,
		    struct sscope_diag *diag)
{
	size_t cur = 0;

	f->n_bytes = 0;
	f->n_xfers = 0;
	for (size_t i = 0; i <= n; i++) {
		if (i == n || v[i] == '/') {
			if (cur == 0)
				return ssc_diag(diag, -EINVAL,
						"tx: empty transfer in '%.*s'",
						(int)n, v);
			if (f->n_xfers == SSCOPE_SPIADC_MAX_XFERS)
				return ssc_diag(diag, -EINVAL,
						"tx: more than %d transfers",
						SSCOPE_SPIADC_MAX_XFERS);
			f->xfer_len[f->n_xfers++] = cur;
			cur = 0;
			continue;
		}
		if (i + 1 >= n || hexval(v[i]) < 0 || hexval(v[i + 1]) < 0)
			return ssc_diag(diag, -EINVAL,
					"tx: '%.*s' is not hexadecimal bytes "
					"(two digits each, '/' between transfers)",
					(int)n, v);
		if (f->n_bytes == SSCOPE_SPIADC_MAX_BYTES)
			return ssc_diag(diag, -EINVAL, "tx: more than %d bytes",
					SSCOPE_SPIADC_MAX_BYTES);
		f->tx[f->n_bytes++] =
			(uint8_t)(hexval(v[i]) << 4 | hexval(v[i + 1]));
		cur++;
		i++;
	}
	return 0;
}

static int parse_uint(const char *v, size_t n, unsigned long lo,
		      unsigned long hi, unsigned long *out)
{
	char buf[32], *end;
	unsigned long x;

	if (n == 0 || n >= sizeof(buf) || v[0] == '-' || v[0] == '+')
		return -EINVAL;
	memcpy(buf, v, n);
	buf[n] = '\0';
	errno = 0;
	x = strtoul(buf, &end, 10);
	if (*end || errno || x < lo || x > hi)
		return -EINVAL;
	*out = x;
	return 0;
}

static int parse_num(const char *v, size_t n, double *out)
{
	double x;

	if (n == 0 || ssc_parse_double(v, v + n, &x) != n || !isfinite(x))
		return -EINVAL;
	*out = x;
	return 0;
}

/* "NAME@BIT[+BITS]" */
static int parse_channel(const char *v, size_t n,
			 struct sscope_spiadc_channel *c, struct sscope_diag *diag)
{
	const char *at = memchr(v, '@', n), *plus;
	unsigned long x;

	if (!at || at == v || (size_t)(at - v) >= sizeof(c->name))
		return ssc_diag(diag, -EINVAL,
				"ch: '%.*s' is not NAME@BIT[+BITS]", (int)n, v);
	memcpy(c->name, v, (size_t)(at - v));
	c->name[at - v] = '\0';
	plus = memchr(at, '+', (size_t)(v + n - at));
	if (parse_uint(at + 1, (size_t)((plus ? plus : v + n) - at - 1), 0,
		       SSCOPE_SPIADC_MAX_BYTES * 8 - 1, &x))
		return ssc_diag(diag, -EINVAL, "ch: bad bit position in '%.*s'",
				(int)n, v);
	c->bit = (unsigned)x;
	if (plus) {
		if (parse_uint(plus + 1, (size_t)(v + n - plus - 1), 1, 32, &x))
			return ssc_diag(diag, -EINVAL,
					"ch: bad width in '%.*s' (1..32 bits)",
					(int)n, v);
		c->bits = (unsigned)x;
	}
	return 0;
}

static bool key_is(const char *k, size_t kn, const char *name)
{
	return strlen(name) == kn && !memcmp(k, name, kn);
}

/* scaling in force where a ch= item appears */
struct scaling {
	unsigned long bits;
	enum sscope_spiadc_coding coding;
	double lo, hi, zero, sens;
	struct sscope_unit sens_unit;
	bool have_zero;
	char unit[32];
};

static int finish_channel(struct sscope_spiadc_channel *c,
			  const struct scaling *sc, struct sscope_diag *diag)
{
	const char *unit = sc->unit[0] ? sc->unit : "V";

	if (!c->bits)
		c->bits = (unsigned)sc->bits;
	if (!c->bits)
		return ssc_diag(diag, -EINVAL,
				"channel %s: no width (give bits= before it, or ch=NAME@BIT+BITS)",
				c->name);
	if (isnan(sc->lo))
		return ssc_diag(diag, -EINVAL,
				"channel %s: no input span (give range=LO:HI before it)",
				c->name);
	if (sc->have_zero && !(sc->sens > 0))
		return ssc_diag(diag, -EINVAL, "channel %s: zero= needs sens=",
				c->name);
	if (sc->sens > 0) {
		char buf[48];
		struct sscope_unit want;

		if (!sc->unit[0])
			return ssc_diag(diag, -EINVAL,
					"channel %s: sens= needs unit= (the unit of the sensed quantity, e.g. deg/s)",
					c->name);
		snprintf(buf, sizeof(buf), "V/(%s)", unit);
		if (sscope_unit_parse(buf, &want, NULL))
			return ssc_diag(diag, -EINVAL, "unit: '%s' is not a unit",
					unit);
		if (!sscope_unit_compatible(&want, &sc->sens_unit))
			return ssc_diag(diag, -EINVAL,
					"channel %s: the sensitivity is not in volts per %s",
					c->name, unit);
	} else {
		struct sscope_unit u, volt;

		sscope_unit_parse("V", &volt, NULL);
		if (sscope_unit_parse(unit, &u, NULL) ||
		    !sscope_unit_compatible(&u, &volt))
			return ssc_diag(diag, -EINVAL,
					"channel %s: unit '%s' is not a voltage (give sens= to convert volts)",
					c->name, unit);
	}
	c->coding = sc->coding;
	c->volts_per_lsb = (sc->hi - sc->lo) / ldexp(1.0, (int)c->bits);
	c->volts_zero = sc->coding == SSCOPE_SPIADC_UNSIGNED
				? sc->lo
				: 0.5 * (sc->lo + sc->hi);
	c->zero_v = sc->sens > 0 ? sc->zero : 0;
	c->sens = sc->sens > 0 ? sc->sens : 0;
	snprintf(c->unit, sizeof(c->unit), "%s", unit);
	return 0;
}

static int copy_item(char *buf, size_t size, const char *v, size_t vn)
{
	if (vn >= size)
		return -EINVAL;
	memcpy(buf, v, vn);
	buf[vn] = '\0';
	return 0;
}

int sscope_spiadc_parse(const char *spec, struct sscope_spiadc_frame *f,
			struct sscope_diag *diag)
{
	struct scaling sc = { .coding = SSCOPE_SPIADC_UNSIGNED,
			      .lo = NAN, .hi = NAN };
	unsigned long x;
	bool have_tx = false;
	const char *p = spec;
	int rc;

	memset(f, 0, sizeof(*f));
	f->speed_hz = 1000000;
	if (!spec || !*spec)
		return ssc_diag(diag, -EINVAL,
				"empty frame description (need tx=, bits=, range=, ch=)");
	while (*p) {
		const char *e = strchr(p, ','), *eq, *v;
		size_t n, kn, vn;
		char buf[64];

		if (!e)
			e = p + strlen(p);
		n = (size_t)(e - p);
		eq = memchr(p, '=', n);
		if (!eq)
			return ssc_diag(diag, -EINVAL,
					"'%.*s' is not key=value", (int)n, p);
		kn = (size_t)(eq - p);
		v = eq + 1;
		vn = (size_t)(e - v);
		if (key_is(p, kn, "tx")) {
			rc = parse_tx(v, vn, f, diag);
			if (rc)
				return rc;
			have_tx = true;
		} else if (key_is(p, kn, "ch")) {
			struct sscope_spiadc_channel *c;

			if (f->n_channels == SSCOPE_SPIADC_MAX_CHANNELS)
				return ssc_diag(diag, -EINVAL,
						"more than %d channels",
						SSCOPE_SPIADC_MAX_CHANNELS);
			c = &f->ch[f->n_channels];
			rc = parse_channel(v, vn, c, diag);
			if (!rc)
				rc = finish_channel(c, &sc, diag);
			if (rc)
				return rc;
			for (size_t j = 0; j < f->n_channels; j++)
				if (!strcmp(f->ch[j].name, c->name))
					return ssc_diag(diag, -EINVAL,
							"channel %s named twice",
							c->name);
			f->n_channels++;
		} else if (key_is(p, kn, "bits")) {
			if (parse_uint(v, vn, 1, 32, &sc.bits))
				return ssc_diag(diag, -EINVAL,
						"bits: '%.*s' is not 1..32",
						(int)vn, v);
		} else if (key_is(p, kn, "coding")) {
			if (vn == 8 && !memcmp(v, "unsigned", 8))
				sc.coding = SSCOPE_SPIADC_UNSIGNED;
			else if (vn == 4 && !memcmp(v, "twos", 4))
				sc.coding = SSCOPE_SPIADC_TWOS;
			else if (vn == 6 && !memcmp(v, "offset", 6))
				sc.coding = SSCOPE_SPIADC_OFFSET;
			else
				return ssc_diag(diag, -EINVAL,
						"coding: '%.*s' is not unsigned, twos or offset",
						(int)vn, v);
		} else if (key_is(p, kn, "range")) {
			const char *c = memchr(v, ':', vn);

			if (!c || parse_num(v, (size_t)(c - v), &sc.lo) ||
			    parse_num(c + 1, (size_t)(v + vn - c - 1), &sc.hi) ||
			    !(sc.hi > sc.lo))
				return ssc_diag(diag, -EINVAL,
						"range: '%.*s' is not LO:HI volts with LO < HI",
						(int)vn, v);
		} else if (key_is(p, kn, "zero")) {
			if (parse_num(v, vn, &sc.zero))
				return ssc_diag(diag, -EINVAL,
						"zero: '%.*s' is not a voltage",
						(int)vn, v);
			sc.have_zero = true;
		} else if (key_is(p, kn, "sens")) {
			if (vn == 4 && !memcmp(v, "none", 4)) {
				sc.sens = 0;
				sc.have_zero = false;
				sc.unit[0] = '\0';
			} else if (copy_item(buf, sizeof(buf), v, vn) ||
				   sscope_quantity_parse(buf, &sc.sens,
							 &sc.sens_unit, NULL) ||
				   !(sc.sens > 0) ||
				   sc.sens_unit.dim2[SSCOPE_UNIT_DIM_VOLTAGE] != 2) {
				return ssc_diag(diag, -EINVAL,
						"sens: '%.*s' is not a positive sensitivity in volts per unit, such as 6mV/(deg/s)",
						(int)vn, v);
			}
		} else if (key_is(p, kn, "unit")) {
			if (vn == 0 || copy_item(sc.unit, sizeof(sc.unit), v, vn))
				return ssc_diag(diag, -EINVAL, "unit: bad length");
		} else if (key_is(p, kn, "mode")) {
			if (parse_uint(v, vn, 0, 3, &x))
				return ssc_diag(diag, -EINVAL,
						"mode: '%.*s' is not 0..3",
						(int)vn, v);
			f->mode = (unsigned)x;
		} else if (key_is(p, kn, "speed")) {
			double hz;

			if (copy_item(buf, sizeof(buf), v, vn) ||
			    sscope_quantity_parse(buf, &hz, NULL, NULL) ||
			    !(hz >= 1000) || hz > 100e6)
				return ssc_diag(diag, -EINVAL,
						"speed: '%.*s' is not a clock of 1 kHz to 100 MHz",
						(int)vn, v);
			f->speed_hz = (uint32_t)lround(hz);
		} else {
			return ssc_diag(diag, -EINVAL,
					"unknown item '%.*s' (tx, ch, bits, coding, range, zero, sens, unit, mode, speed)",
					(int)kn, p);
		}
		p = *e ? e + 1 : e;
	}
	if (!have_tx)
		return ssc_diag(diag, -EINVAL, "no tx= bytes to send");
	if (f->n_channels == 0)
		return ssc_diag(diag, -EINVAL, "no ch=NAME@BIT channel");
	for (size_t k = 0; k < f->n_channels; k++) {
		const struct sscope_spiadc_channel *c = &f->ch[k];

		if ((size_t)c->bit + c->bits > f->n_bytes * 8)
			return ssc_diag(diag, -EINVAL,
					"channel %s: bits %u..%u lie outside the %zu-byte frame",
					c->name, c->bit, c->bit + c->bits - 1,
					f->n_bytes);
	}
	return 0;
}

uint32_t sscope_spiadc_field(const uint8_t *rx, unsigned bit, unsigned bits)
{
	uint32_t v = 0;

	for (unsigned i = 0; i < bits; i++) {
		unsigned b = bit + i;

		v = v << 1 | ((rx[b / 8] >> (7 - b % 8)) & 1u);
	}
	return v;
}

void sscope_spiadc_decode(const struct sscope_spiadc_frame *f,
			  const uint8_t *rx, double *values, int64_t *codes)
{
	for (size_t k = 0; k < f->n_channels; k++) {
		const struct sscope_spiadc_channel *c = &f->ch[k];
		uint32_t u = sscope_spiadc_field(rx, c->bit, c->bits);
		int64_t half = (int64_t)1 << (c->bits - 1), code;
		double v;

		switch (c->coding) {
		case SSCOPE_SPIADC_TWOS:
			code = (int64_t)u >= half ? (int64_t)u - 2 * half
						  : (int64_t)u;
			break;
		case SSCOPE_SPIADC_OFFSET:
			code = (int64_t)u - half;
			break;
		default:
			code = (int64_t)u;
			break;
		}
		v = c->volts_zero + (double)code * c->volts_per_lsb;
		if (c->sens > 0)
			v = (v - c->zero_v) / c->sens;
		values[k] = v;
		if (codes)
			codes[k] = code;
	}
}
