/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Generic SPI converter frames: parsing of the text form (and every
 * refusal), bit-field extraction across byte boundaries, the three code
 * formats at their end points, and the analog-gyro conversion
 * (volts - zero) / sensitivity against hand arithmetic.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <string.h>

#include "check-main.h"

#define DEG (M_PI / 180.0)

static const char *mcp3208 =
	"tx=060000/064000,bits=12,range=0:3.3,ch=vtemp@36,"
	"zero=1.65,sens=6mV/(deg/s),unit=deg/s,ch=rate@12";

START_TEST(parse_mcp3208)
{
	struct sscope_spiadc_frame f;
	struct sscope_diag d = { "" };

	ck_assert_int_eq(sscope_spiadc_parse(mcp3208, &f, &d), 0);
	ck_assert_uint_eq(f.n_bytes, 6);
	ck_assert_uint_eq(f.n_xfers, 2);
	ck_assert_uint_eq(f.xfer_len[0], 3);
	ck_assert_uint_eq(f.xfer_len[1], 3);
	ck_assert_uint_eq(f.tx[0], 0x06);
	ck_assert_uint_eq(f.tx[4], 0x40);
	ck_assert_uint_eq(f.n_channels, 2);
	ck_assert_str_eq(f.ch[0].name, "vtemp");
	ck_assert_str_eq(f.ch[0].unit, "V");
	ck_assert(f.ch[0].sens == 0);
	ck_assert_str_eq(f.ch[1].name, "rate");
	ck_assert_str_eq(f.ch[1].unit, "deg/s");
	ck_assert_uint_eq(f.ch[1].bit, 12);
	ck_assert_uint_eq(f.ch[1].bits, 12);
	/* 6 mV per deg/s = 0.006 V / (pi/180 rad/s) */
	ck_assert_rel(f.ch[1].sens, 0.006 / DEG, 1e-15);
	ck_assert_uint_eq(f.mode, 0);
	ck_assert_uint_eq(f.speed_hz, 1000000);
}
END_TEST

START_TEST(decode_mcp3208)
{
	struct sscope_spiadc_frame f;
	double v[2];
	int64_t c[2];
	/* rate code 2148 (0x864) in bits 12..23; vtemp code 0xfff in 36..47 */
	const uint8_t rx[6] = { 0xff, 0xf8, 0x64, 0x00, 0x0f, 0xff };

	ck_assert_int_eq(sscope_spiadc_parse(mcp3208, &f, NULL), 0);
	sscope_spiadc_decode(&f, rx, v, c);
	ck_assert_int_eq(c[0], 4095);
	ck_assert_int_eq(c[1], 2148);
	ck_assert_rel(v[0], 4095 * 3.3 / 4096, 1e-15);
	/* (2148 * 3.3 / 4096 - 1.65) V / 6 mV/(deg/s) in rad/s */
	ck_assert_rel(v[1], (2148 * 3.3 / 4096 - 1.65) / 0.006 * DEG, 1e-12);
}
END_TEST

START_TEST(fields)
{
	const uint8_t rx[5] = { 0x81, 0x23, 0x45, 0x67, 0x89 };

	ck_assert_uint_eq(sscope_spiadc_field(rx, 0, 1), 1);
	ck_assert_uint_eq(sscope_spiadc_field(rx, 1, 7), 1);
	ck_assert_uint_eq(sscope_spiadc_field(rx, 0, 16), 0x8123);
	ck_assert_uint_eq(sscope_spiadc_field(rx, 4, 12), 0x123);
	ck_assert_uint_eq(sscope_spiadc_field(rx, 0, 32), 0x81234567u);
	ck_assert_uint_eq(sscope_spiadc_field(rx, 8, 32), 0x23456789u);
	ck_assert_uint_eq(sscope_spiadc_field(rx, 39, 1), 1);
}
END_TEST

START_TEST(codings)
{
	struct sscope_spiadc_frame f;
	double v[3];
	int64_t c[3];
	/* three 16-bit words: twos, offset, unsigned on a -10..10 V span */
	uint8_t rx[6];
	const double lsb = 20.0 / 65536;

	ck_assert_int_eq(sscope_spiadc_parse("tx=000000000000,range=-10:10,"
					     "bits=16,coding=twos,ch=a@0,"
					     "coding=offset,ch=b@16,"
					     "coding=unsigned,ch=c@32",
					     &f, NULL),
			 0);
	memcpy(rx, "\x80\x00\x00\x00\x00\x00", 6);
	sscope_spiadc_decode(&f, rx, v, c);
	ck_assert_int_eq(c[0], -32768);
	ck_assert_rel(v[0], -10.0, 1e-15);
	ck_assert_int_eq(c[1], -32768);
	ck_assert_rel(v[1], -10.0, 1e-15);
	ck_assert_int_eq(c[2], 0);
	ck_assert_rel(v[2], -10.0, 1e-15);
	memcpy(rx, "\x7f\xff\x80\x00\xff\xff", 6);
	sscope_spiadc_decode(&f, rx, v, c);
	ck_assert_int_eq(c[0], 32767);
	ck_assert_rel(v[0], 10.0 - lsb, 1e-15);
	ck_assert_int_eq(c[1], 0);
	ck_assert(v[1] == 0.0);
	ck_assert_int_eq(c[2], 65535);
	ck_assert_rel(v[2], 10.0 - lsb, 1e-15);
	/* a 32-bit two's complement code */
	ck_assert_int_eq(sscope_spiadc_parse("tx=00000000,bits=32,coding=twos,"
					     "range=-1:1,ch=x@0",
					     &f, NULL),
			 0);
	memcpy(rx, "\xff\xff\xff\xff", 4);
	sscope_spiadc_decode(&f, rx, v, c);
	ck_assert_int_eq(c[0], -1);
	ck_assert_rel(v[0], -2.0 / 4294967296.0, 1e-15);
}
END_TEST

START_TEST(options)
{
	struct sscope_spiadc_frame f;

	ck_assert_int_eq(sscope_spiadc_parse("tx=0000,ch=x@4+12,range=0:5,"
					     "mode=3,speed=2MHz",
					     &f, NULL),
			 -EINVAL); /* range after the channel: no span yet */
	ck_assert_int_eq(sscope_spiadc_parse("mode=3,speed=2MHz,tx=0000,"
					     "range=0:5,ch=x@4+12",
					     &f, NULL),
			 0);
	ck_assert_uint_eq(f.mode, 3);
	ck_assert_uint_eq(f.speed_hz, 2000000);
	ck_assert_uint_eq(f.ch[0].bits, 12);
	ck_assert_str_eq(f.ch[0].unit, "V");
	/* a voltage unit is allowed without sens */
	ck_assert_int_eq(sscope_spiadc_parse("tx=0000,range=0:5,unit=mV,"
					     "ch=x@4+12",
					     &f, NULL),
			 0);
	ck_assert_str_eq(f.ch[0].unit, "mV");
	/* sens=none returns to volts */
	ck_assert_int_eq(sscope_spiadc_parse("tx=00000000,bits=12,range=0:5,"
					     "sens=2mV/(m/s^2),unit=m/s^2,"
					     "ch=a@4,sens=none,ch=b@20",
					     &f, NULL),
			 0);
	ck_assert(f.ch[0].sens > 0);
	ck_assert(f.ch[1].sens == 0);
	ck_assert_str_eq(f.ch[1].unit, "V");
}
END_TEST

START_TEST(refusals)
{
	static const char *const bad[] = {
		"",
		"ch=x@0",                               /* no tx */
		"tx=00,range=0:1,bits=8",               /* no channel */
		"tx=0g,range=0:1,bits=8,ch=x@0",        /* not hex */
		"tx=000,range=0:1,bits=8,ch=x@0",       /* odd digits */
		"tx=00//00,range=0:1,bits=8,ch=x@0",    /* empty transfer */
		"tx=00,range=0:1,ch=x@0",               /* no width */
		"tx=00,bits=8,ch=x@0",                  /* no span */
		"tx=00,range=1:0,bits=8,ch=x@0",        /* LO > HI */
		"tx=00,range=0:1,bits=8,ch=x@1",        /* outside the frame */
		"tx=00,range=0:1,bits=33,ch=x@0",       /* too wide */
		"tx=0000,range=0:1,bits=8,ch=x@0,ch=x@8", /* named twice */
		"tx=00,range=0:1,bits=8,zero=1,ch=x@0", /* zero without sens */
		"tx=00,range=0:1,bits=8,sens=6mV/(deg/s),ch=x@0", /* no unit */
		"tx=00,range=0:1,bits=8,sens=6mV/(deg/s),unit=g,ch=x@0",
		"tx=00,range=0:1,bits=8,sens=6mA,unit=deg/s,ch=x@0",
		"tx=00,range=0:1,bits=8,unit=deg/s,ch=x@0", /* not volts */
		"tx=00,range=0:1,bits=8,coding=gray,ch=x@0",
		"tx=00,range=0:1,bits=8,mode=4,ch=x@0",
		"tx=00,range=0:1,bits=8,speed=10Hz,ch=x@0",
		"tx=00,range=0:1,bits=8,ch=@0",
		"tx=00,range=0:1,bits=8,ch=x",
		"tx=00,range=0:1,bits=8,ch=x@-1",
		"tx=00,range=0:1,bits=8,frob=1,ch=x@0",
		"tx=00,range=0:1,bits=8,ch=x@0,novalue",
		"tx=00/00/00/00/00/00/00/00/00/00/00/00/00/00/00/00/00,"
		"range=0:1,bits=8,ch=x@0",
	};
	struct sscope_spiadc_frame f;

	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		struct sscope_diag d = { "" };

		ck_assert_msg(sscope_spiadc_parse(bad[i], &f, &d) == -EINVAL,
			      "accepted '%s'", bad[i]);
		ck_assert_msg(d.msg[0], "no message for '%s'", bad[i]);
	}
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("spiadc");
	TCase *t = tcase_create("core");

	tcase_add_test(t, parse_mcp3208);
	tcase_add_test(t, decode_mcp3208);
	tcase_add_test(t, fields);
	tcase_add_test(t, codings);
	tcase_add_test(t, options);
	tcase_add_test(t, refusals);
	suite_add_tcase(s, t);
	return s;
}
