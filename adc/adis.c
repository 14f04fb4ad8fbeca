/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * ADIS1646x/1647x burst decoder (see sscope-adis.h).
 *
 * Reference: Analog Devices ADIS16470 data sheet (burst read function,
 * register map: PROD_ID 0x72, DEC_RATE 0x64, MSC_CTRL 0x60, DATA_CNTR
 * 0x22); the scale factors of the 16-bit outputs are those of the Linux
 * IIO driver drivers/iio/imu/adis16475.c (gyro LSB per deg/s: 10 for the
 * +-2000 deg/s parts, 40 for +-500, 160 for +-125; accel LSB per g: 800
 * for ADIS16470/16467/16477, 4000 for ADIS16465/16475; temperature
 * 0.1 degC per LSB; internal clock 2000 Hz), the checksum rule is the
 * driver's adis16475_validate_crc().
 */
#include "internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sscope-adis.h"
#include "sscope-unit.h"

#define DEG (M_PI / 180.0)
#define G0 SSCOPE_UNIT_GRAVITY_STD /* the data sheets' g */

#define MODEL(n, id, g_lsb, a_lsb, g_range, a_range)                        \
	{ n, id, DEG / (g_lsb), G0 / (a_lsb), 0.1, (g_range) * DEG,         \
	  (a_range) * G0, 2000.0 }

static const struct sscope_adis_model models[] = {
	MODEL("adis16470", 16470, 10, 800, 2000, 40),
	MODEL("adis16465-1", 16465, 160, 4000, 125, 8),
	MODEL("adis16465-2", 16465, 40, 4000, 500, 8),
	MODEL("adis16465-3", 16465, 10, 4000, 2000, 8),
	MODEL("adis16467-1", 16467, 160, 800, 125, 40),
	MODEL("adis16467-2", 16467, 40, 800, 500, 40),
	MODEL("adis16467-3", 16467, 10, 800, 2000, 40),
	MODEL("adis16475-1", 16475, 160, 4000, 125, 8),
	MODEL("adis16475-2", 16475, 40, 4000, 500, 8),
	MODEL("adis16475-3", 16475, 10, 4000, 2000, 8),
	MODEL("adis16477-1", 16477, 160, 800, 125, 40),
	MODEL("adis16477-2", 16477, 40, 800, 500, 40),
	MODEL("adis16477-3", 16477, 10, 800, 2000, 40),
};

#define N_MODELS (sizeof(models) / sizeof(models[0]))

const struct sscope_adis_model *sscope_adis_find(const char *name)
{
	if (!name)
		return NULL;
	for (size_t i = 0; i < N_MODELS; i++)
		if (!ssc_strcasecmp(name, models[i].name))
			return &models[i];
	return NULL;
}

const struct sscope_adis_model *sscope_adis_model_at(size_t i)
{
	return i < N_MODELS ? &models[i] : NULL;
}

static uint16_t be16(const uint8_t *p)
{
	return (uint16_t)((unsigned)p[0] << 8 | p[1]);
}

static int16_t s16(uint16_t u)
{
	/* two's complement without implementation-defined conversion */
	return u < 0x8000u ? (int16_t)u : (int16_t)(-(int)(0x10000u - u));
}

uint16_t sscope_adis_checksum(const uint8_t *burst)
{
	unsigned sum = 0;

	for (int i = 0; i < 18; i++)
		sum += burst[i];
	return (uint16_t)sum;
}

int sscope_adis_decode(const struct sscope_adis_model *m,
		       const uint8_t *burst, struct sscope_adis_sample *s)
{
	bool all_zero = true;

	for (int i = 0; i < SSCOPE_ADIS_BURST_BYTES; i++)
		if (burst[i])
			all_zero = false;
	s->diag_stat = be16(burst);
	for (int k = 0; k < 7; k++)
		s->raw[k] = s16(be16(burst + 2 + 2 * k));
	s->data_cntr = be16(burst + 16);
	s->checksum = be16(burst + 18);
	for (int k = 0; k < 3; k++) {
		s->gyro_rad_s[k] = s->raw[k] * m->gyro_lsb_rad_s;
		s->accel_m_s2[k] = s->raw[3 + k] * m->accel_lsb_m_s2;
	}
	s->temp_degc = s->raw[6] * m->temp_lsb_degc;
	if (all_zero || sscope_adis_checksum(burst) != s->checksum)
		return -EBADMSG;
	return 0;
}

static void put_be16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)(v >> 8);
	p[1] = (uint8_t)v;
}

void sscope_adis_encode(uint16_t diag_stat, const int16_t *raw,
			uint16_t data_cntr, uint8_t *burst)
{
	put_be16(burst, diag_stat);
	for (int k = 0; k < 7; k++)
		put_be16(burst + 2 + 2 * k, (uint16_t)raw[k]);
	put_be16(burst + 16, data_cntr);
	put_be16(burst + 18, sscope_adis_checksum(burst));
}

long sscope_adis_counter_gap(uint16_t prev, uint16_t cur)
{
	if (cur == prev)
		return -1;
	return (long)(uint16_t)(cur - prev - 1u);
}

void sscope_adis_read_cmd(uint8_t reg, uint8_t *tx)
{
	tx[0] = reg & 0x7f;
	tx[1] = 0;
}

void sscope_adis_write_cmd(uint8_t reg, uint16_t value, uint8_t *tx)
{
	tx[0] = (uint8_t)(0x80 | (reg & 0x7f));
	tx[1] = (uint8_t)value;
	tx[2] = (uint8_t)(0x80 | ((reg + 1) & 0x7f));
	tx[3] = (uint8_t)(value >> 8);
}

int sscope_adis_diag_text(uint16_t d, char *buf, size_t len)
{
	static const char *const names[16] = {
		[1] = "data path overrun", [2] = "flash update failure",
		[3] = "SPI communication error", [4] = "standby mode",
		[5] = "sensor failure", [6] = "memory failure",
		[7] = "clock error",
	};
	size_t used = 0;
	int rc = 0;

	if (len)
		buf[0] = '\0';
	for (int b = 0; b < 16; b++) {
		char item[40];
		int n;

		if (!(d & (1u << b)))
			continue;
		if (names[b])
			snprintf(item, sizeof(item), "%s", names[b]);
		else
			snprintf(item, sizeof(item), "bit %d", b);
		n = snprintf(buf + used, len > used ? len - used : 0, "%s%s",
			     used ? ", " : "", item);
		if (n < 0 || used + (size_t)n >= len) {
			rc = -ERANGE;
			break;
		}
		used += (size_t)n;
	}
	return rc;
}

double sscope_adis_rate_hz(const struct sscope_adis_model *m,
			   uint16_t dec_rate)
{
	return m->clock_hz / (dec_rate + 1.0);
}

int sscope_adis_dec_rate(const struct sscope_adis_model *m, double rate_hz,
			 uint16_t *dec_rate)
{
	double q;
	long n;

	if (!(rate_hz > 0) || !isfinite(rate_hz)) {
		*dec_rate = 0;
		return -EDOM;
	}
	q = m->clock_hz / rate_hz;
	n = lround(q);
	if (n < 1)
		n = 1;
	if (n > 2000)
		n = 2000;
	*dec_rate = (uint16_t)(n - 1);
	if (fabs(q - (double)n) > 1e-9 * q || q < 1 || q > 2000)
		return -EDOM;
	return 0;
}
