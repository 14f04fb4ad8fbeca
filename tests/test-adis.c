/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * ADIS1646x/1647x decoder: a hand-built burst with its checksum computed
 * by hand, scaling of every model against its data-sheet LSB, sign
 * extension at the extremes, checksum and dead-bus refusals, counter gaps
 * across the wrap, register command bytes, DEC_RATE arithmetic.
 */
#include "internal.h"
#include "sensorscope.h"

#include <math.h>
#include <string.h>

#include "check-main.h"

#define DEG (M_PI / 180.0)

/* DIAG 0x0000, gyro 100 -200 32767, accel -32768 800 -1, temp 250,
 * DATA_CNTR 0x1234; checksum = byte sum of the 18 bytes */
static const uint8_t burst_ok[20] = {
	0x00, 0x00, 0x00, 0x64, 0xff, 0x38, 0x7f, 0xff, 0x80, 0x00,
	0x03, 0x20, 0xff, 0xff, 0x00, 0xfa, 0x12, 0x34, 0x06, 0xfa,
};

START_TEST(checksum_by_hand)
{
	/* 0x00+0x00+0x00+0x64+0xff+0x38+0x7f+0xff+0x80+0x00+0x03+0x20+0xff+
	 * 0xff+0x00+0xfa+0x12+0x34 = 1786 = 0x06fa */
	ck_assert_uint_eq(sscope_adis_checksum(burst_ok), 0x06fa);
}
END_TEST

START_TEST(decode_adis16470)
{
	const struct sscope_adis_model *m = sscope_adis_find("adis16470");
	struct sscope_adis_sample s;

	ck_assert_ptr_nonnull(m);
	ck_assert_uint_eq(m->prod_id, 16470);
	ck_assert_int_eq(sscope_adis_decode(m, burst_ok, &s), 0);
	ck_assert_uint_eq(s.diag_stat, 0);
	ck_assert_int_eq(s.raw[0], 100);
	ck_assert_int_eq(s.raw[1], -200);
	ck_assert_int_eq(s.raw[2], 32767);
	ck_assert_int_eq(s.raw[3], -32768);
	ck_assert_int_eq(s.raw[4], 800);
	ck_assert_int_eq(s.raw[5], -1);
	ck_assert_int_eq(s.raw[6], 250);
	ck_assert_uint_eq(s.data_cntr, 0x1234);
	/* 0.1 deg/s per LSB, 1.25 mg per LSB, 0.1 degC per LSB */
	ck_assert_rel(s.gyro_rad_s[0], 10.0 * DEG, 1e-15);
	ck_assert_rel(s.gyro_rad_s[1], -20.0 * DEG, 1e-15);
	ck_assert_rel(s.gyro_rad_s[2], 3276.7 * DEG, 1e-15);
	ck_assert_rel(s.accel_m_s2[0], -32768 * 1.25e-3 * 9.80665, 1e-15);
	ck_assert_rel(s.accel_m_s2[1], 9.80665, 1e-15);
	ck_assert_rel(s.accel_m_s2[2], -1.25e-3 * 9.80665, 1e-15);
	ck_assert_rel(s.temp_degc, 25.0, 1e-15);
}
END_TEST

START_TEST(scale_factors_of_every_model)
{
	/* LSB per deg/s and per g from the data sheets / Linux driver */
	static const struct {
		const char *name;
		double gyro_lsb_per_dps, accel_lsb_per_g, range_dps;
	} t[] = {
		{ "adis16470", 10, 800, 2000 },    { "ADIS16465-1", 160, 4000, 125 },
		{ "adis16465-2", 40, 4000, 500 },  { "adis16465-3", 10, 4000, 2000 },
		{ "adis16467-1", 160, 800, 125 },  { "adis16467-2", 40, 800, 500 },
		{ "adis16467-3", 10, 800, 2000 },  { "adis16475-1", 160, 4000, 125 },
		{ "adis16475-2", 40, 4000, 500 },  { "adis16475-3", 10, 4000, 2000 },
		{ "adis16477-1", 160, 800, 125 },  { "adis16477-2", 40, 800, 500 },
		{ "adis16477-3", 10, 800, 2000 },
	};
	size_t n = 0;

	for (size_t i = 0; i < sizeof(t) / sizeof(t[0]); i++) {
		const struct sscope_adis_model *m = sscope_adis_find(t[i].name);

		ck_assert_ptr_nonnull(m);
		ck_assert_rel(m->gyro_lsb_rad_s * t[i].gyro_lsb_per_dps, DEG,
			      1e-15);
		ck_assert_rel(m->accel_lsb_m_s2 * t[i].accel_lsb_per_g, 9.80665,
			      1e-15);
		ck_assert_rel(m->gyro_range_rad_s, t[i].range_dps * DEG, 1e-15);
		/* the 16-bit output covers the range */
		ck_assert(32767 * m->gyro_lsb_rad_s >= m->gyro_range_rad_s);
	}
	while (sscope_adis_model_at(n))
		n++;
	ck_assert_uint_eq(n, sizeof(t) / sizeof(t[0]));
	ck_assert_ptr_null(sscope_adis_find("adis16465"));
	ck_assert_ptr_null(sscope_adis_find(NULL));
}
END_TEST

START_TEST(refusals)
{
	const struct sscope_adis_model *m = sscope_adis_find("adis16470");
	struct sscope_adis_sample s;
	uint8_t b[20];

	/* every single-bit error in the data or the checksum is caught */
	for (int i = 0; i < 20; i++)
		for (int bit = 0; bit < 8; bit++) {
			memcpy(b, burst_ok, 20);
			b[i] ^= (uint8_t)(1u << bit);
			ck_assert_int_eq(sscope_adis_decode(m, b, &s), -EBADMSG);
		}
	/* MISO stuck low passes a plain byte sum: refused anyway */
	memset(b, 0, 20);
	ck_assert_uint_eq(sscope_adis_checksum(b), 0);
	ck_assert_int_eq(sscope_adis_decode(m, b, &s), -EBADMSG);
	/* stuck high */
	memset(b, 0xff, 20);
	ck_assert_int_eq(sscope_adis_decode(m, b, &s), -EBADMSG);
	/* the raw values are still reported */
	ck_assert_int_eq(s.raw[0], -1);
}
END_TEST

START_TEST(encode_round_trip)
{
	const struct sscope_adis_model *m = sscope_adis_find("adis16465-2");
	const int16_t raw[7] = { -32768, 32767, 0, 1, -1, 4000, -400 };
	struct sscope_adis_sample s;
	uint8_t b[20];

	sscope_adis_encode(0x0020, raw, 65535, b);
	ck_assert_int_eq(sscope_adis_decode(m, b, &s), 0);
	ck_assert_uint_eq(s.diag_stat, 0x0020);
	ck_assert_uint_eq(s.data_cntr, 65535);
	for (int k = 0; k < 7; k++)
		ck_assert_int_eq(s.raw[k], raw[k]);
	ck_assert_rel(s.gyro_rad_s[0], -32768 / 40.0 * DEG, 1e-15);
	ck_assert_rel(s.accel_m_s2[2], 9.80665, 1e-15);
	ck_assert_rel(s.temp_degc, -40.0, 1e-15);
	/* and the hand-built burst encodes to itself */
	{
		const int16_t r2[7] = { 100, -200, 32767, -32768, 800, -1, 250 };

		sscope_adis_encode(0, r2, 0x1234, b);
		ck_assert_mem_eq(b, burst_ok, 20);
	}
}
END_TEST

START_TEST(counter_gaps)
{
	ck_assert_int_eq(sscope_adis_counter_gap(5, 6), 0);
	ck_assert_int_eq(sscope_adis_counter_gap(5, 9), 3);
	ck_assert_int_eq(sscope_adis_counter_gap(65535, 0), 0);
	ck_assert_int_eq(sscope_adis_counter_gap(65534, 1), 2);
	ck_assert_int_eq(sscope_adis_counter_gap(7, 7), -1);
	ck_assert_int_eq(sscope_adis_counter_gap(0, 65535), 65534);
	ck_assert_int_eq(sscope_adis_counter_gap(1, 0), 65534);
}
END_TEST

START_TEST(register_commands)
{
	uint8_t tx[4];

	sscope_adis_read_cmd(SSCOPE_ADIS_REG_PROD_ID, tx);
	ck_assert_uint_eq(tx[0], 0x72);
	ck_assert_uint_eq(tx[1], 0x00);
	/* DEC_RATE (0x64) = 0x0109: low byte to 0x64, high byte to 0x65 */
	sscope_adis_write_cmd(SSCOPE_ADIS_REG_DEC_RATE, 0x0109, tx);
	ck_assert_uint_eq(tx[0], 0xe4);
	ck_assert_uint_eq(tx[1], 0x09);
	ck_assert_uint_eq(tx[2], 0xe5);
	ck_assert_uint_eq(tx[3], 0x01);
	ck_assert_uint_eq(SSCOPE_ADIS_BURST_CMD >> 8, SSCOPE_ADIS_REG_GLOB_CMD);
}
END_TEST

START_TEST(dec_rate)
{
	const struct sscope_adis_model *m = sscope_adis_find("adis16470");
	uint16_t d;

	ck_assert_int_eq(sscope_adis_dec_rate(m, 2000, &d), 0);
	ck_assert_uint_eq(d, 0);
	ck_assert_int_eq(sscope_adis_dec_rate(m, 200, &d), 0);
	ck_assert_uint_eq(d, 9);
	ck_assert_int_eq(sscope_adis_dec_rate(m, 1, &d), 0);
	ck_assert_uint_eq(d, 1999);
	ck_assert_rel(sscope_adis_rate_hz(m, 9), 200.0, 1e-15);
	/* 2000/300 is not an integer: nearest is 7 (DEC_RATE 6) */
	ck_assert_int_eq(sscope_adis_dec_rate(m, 300, &d), -EDOM);
	ck_assert_uint_eq(d, 6);
	ck_assert_int_eq(sscope_adis_dec_rate(m, 4000, &d), -EDOM);
	ck_assert_int_eq(sscope_adis_dec_rate(m, 0.5, &d), -EDOM);
	ck_assert_int_eq(sscope_adis_dec_rate(m, -1, &d), -EDOM);
	ck_assert_int_eq(sscope_adis_dec_rate(m, NAN, &d), -EDOM);
}
END_TEST

START_TEST(diag_text)
{
	char buf[128], tiny[8];

	ck_assert_int_eq(sscope_adis_diag_text(0, buf, sizeof(buf)), 0);
	ck_assert_str_eq(buf, "");
	ck_assert_int_eq(sscope_adis_diag_text(SSCOPE_ADIS_DIAG_SENSOR |
						       SSCOPE_ADIS_DIAG_CLOCK |
						       0x8000,
					       buf, sizeof(buf)),
			 0);
	ck_assert_str_eq(buf, "sensor failure, clock error, bit 15");
	ck_assert_int_eq(sscope_adis_diag_text(SSCOPE_ADIS_DIAG_SPI, tiny,
					       sizeof(tiny)),
			 -ERANGE);
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("adis");
	TCase *t = tcase_create("core");

	tcase_add_test(t, checksum_by_hand);
	tcase_add_test(t, decode_adis16470);
	tcase_add_test(t, scale_factors_of_every_model);
	tcase_add_test(t, refusals);
	tcase_add_test(t, encode_round_trip);
	tcase_add_test(t, counter_gaps);
	tcase_add_test(t, register_commands);
	tcase_add_test(t, dec_rate);
	tcase_add_test(t, diag_text);
	suite_add_tcase(s, t);
	return s;
}
