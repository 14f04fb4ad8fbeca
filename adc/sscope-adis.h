/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-adis.h
 * @brief Frame decoder of the Analog Devices ADIS1646x/1647x IMU family
 *        (ADIS16470, ADIS16465, ADIS16467, ADIS16475, ADIS16477) in their
 *        16-bit burst mode.
 *
 * Pure functions: bytes in, SI values out.  The SPI transport and the
 * data-ready line live in the acquisition code (src/acq/).
 *
 * Burst read: the host sends the command word 0x6800 and then clocks out
 * 20 bytes: ten big-endian 16-bit words DIAG_STAT, X/Y/Z_GYRO_OUT,
 * X/Y/Z_ACCL_OUT, TEMP_OUT, DATA_CNTR and a checksum equal to the sum of
 * the 18 preceding bytes.  Register access is pipelined: the answer to a
 * read command (address with bit 15 clear) comes in the next 16-bit
 * transfer; a write is two transfers (0x80 | address, low byte), then
 * (0x80 | address + 1, high byte).
 */
#ifndef SSCOPE_ADIS_H
#define SSCOPE_ADIS_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Register addresses used by the acquisition code. */
enum {
	SSCOPE_ADIS_REG_DIAG_STAT = 0x02,
	SSCOPE_ADIS_REG_DATA_CNTR = 0x22,
	SSCOPE_ADIS_REG_FILT_CTRL = 0x5c,
	SSCOPE_ADIS_REG_MSC_CTRL = 0x60,
	SSCOPE_ADIS_REG_DEC_RATE = 0x64,
	SSCOPE_ADIS_REG_GLOB_CMD = 0x68,
	SSCOPE_ADIS_REG_PROD_ID = 0x72,
};

/** Bytes answered after the burst command (the 16-bit command excluded). */
#define SSCOPE_ADIS_BURST_BYTES 20
/** The burst read command word. */
#define SSCOPE_ADIS_BURST_CMD 0x6800u

/** Bits of DIAG_STAT (non-zero means the sample is suspect). */
enum {
	SSCOPE_ADIS_DIAG_DATA_PATH = 1u << 1, /**< data path overrun */
	SSCOPE_ADIS_DIAG_FLASH = 1u << 2,     /**< flash memory update failure */
	SSCOPE_ADIS_DIAG_SPI = 1u << 3,       /**< SPI communication error */
	SSCOPE_ADIS_DIAG_STANDBY = 1u << 4,   /**< standby mode */
	SSCOPE_ADIS_DIAG_SENSOR = 1u << 5,    /**< sensor failure */
	SSCOPE_ADIS_DIAG_MEMORY = 1u << 6,    /**< memory failure */
	SSCOPE_ADIS_DIAG_CLOCK = 1u << 7,     /**< clock error */
};

/** Properties of one model (scale factors of the 16-bit outputs). */
struct sscope_adis_model {
	const char *name;       /**< "adis16470", "adis16465-2", ... */
	uint16_t prod_id;       /**< PROD_ID register (the part number) */
	double gyro_lsb_rad_s;  /**< rad/s per LSB */
	double accel_lsb_m_s2;  /**< m/s^2 per LSB */
	double temp_lsb_degc;   /**< degC per LSB (0 LSB = 0 degC) */
	double gyro_range_rad_s;   /**< +- full scale */
	double accel_range_m_s2;   /**< +- full scale */
	double clock_hz;        /**< internal sample clock before DEC_RATE */
};

/**
 * Find a model by name (case-insensitive): adis16470, adis16465-1/-2/-3,
 * adis16467-1/-2/-3, adis16475-1/-2/-3, adis16477-1/-2/-3.
 * @return the model (static), or NULL for an unknown name.
 */
const struct sscope_adis_model *sscope_adis_find(const char *name);

/**
 * Enumerate the models.
 * @param i  index from 0.
 * @return model @p i, or NULL past the end.
 */
const struct sscope_adis_model *sscope_adis_model_at(size_t i);

/** A decoded burst. */
struct sscope_adis_sample {
	uint16_t diag_stat;     /**< DIAG_STAT (0 when healthy) */
	int16_t raw[7];         /**< X/Y/Z gyro, X/Y/Z accel, temperature */
	uint16_t data_cntr;     /**< DATA_CNTR, +1 per output sample, wraps */
	uint16_t checksum;      /**< as received */
	double gyro_rad_s[3];   /**< X, Y, Z angular rate */
	double accel_m_s2[3];   /**< X, Y, Z acceleration */
	double temp_degc;       /**< internal temperature */
};

/**
 * Checksum of a burst: the sum of its first 18 bytes.
 * @param burst  SSCOPE_ADIS_BURST_BYTES bytes as received.
 */
uint16_t sscope_adis_checksum(const uint8_t *burst);

/**
 * Decode a burst.  The sample is filled even when the frame is refused, so
 * that a caller can report what was received.
 * @param model  scale factors.
 * @param burst  SSCOPE_ADIS_BURST_BYTES bytes as received (after the two
 *               bytes clocked out during the command).
 * @param s      receives the sample, SI.
 * @return 0; -EBADMSG when the checksum does not match or every byte is
 *         zero (no device driving MISO passes the checksum).
 */
int sscope_adis_decode(const struct sscope_adis_model *model,
		       const uint8_t *burst, struct sscope_adis_sample *s);

/**
 * Encode a burst (for device models in tests and simulators).
 * @param raw        7 raw words (gyro, accel, temperature).
 * @param burst      receives SSCOPE_ADIS_BURST_BYTES bytes, checksum set.
 */
void sscope_adis_encode(uint16_t diag_stat, const int16_t *raw,
			uint16_t data_cntr, uint8_t *burst);

/**
 * Samples missing between two consecutive DATA_CNTR values.
 * @return (cur - prev - 1) modulo 2^16 in 0..65534, or -1 when
 *         @p cur == @p prev (the same sample read twice).
 */
long sscope_adis_counter_gap(uint16_t prev, uint16_t cur);

/**
 * Command bytes of a register read (the value arrives in the next 16-bit
 * transfer).
 * @param reg  even register address.
 * @param tx   receives 2 bytes.
 */
void sscope_adis_read_cmd(uint8_t reg, uint8_t *tx);

/**
 * Command bytes of a 16-bit register write: two 16-bit transfers, chip
 * select released between them.
 * @param reg    even register address (the low byte's).
 * @param value  value to write.
 * @param tx     receives 4 bytes (2 per transfer).
 */
void sscope_adis_write_cmd(uint8_t reg, uint16_t value, uint8_t *tx);

/**
 * Describe the bits set in DIAG_STAT, e.g. "sensor failure, clock error".
 * @return 0, or -ERANGE when @p len is too small (truncated text).
 */
int sscope_adis_diag_text(uint16_t diag_stat, char *buf, size_t len);

/**
 * Output rate for a DEC_RATE value: clock_hz / (dec_rate + 1).
 * @return the rate in Hz.
 */
double sscope_adis_rate_hz(const struct sscope_adis_model *model,
			   uint16_t dec_rate);

/**
 * DEC_RATE giving exactly @p rate_hz.
 * @return 0; -EDOM when clock_hz / rate_hz is not an integer in
 *         1..2000 (*dec_rate then holds the nearest value).
 */
int sscope_adis_dec_rate(const struct sscope_adis_model *model,
			 double rate_hz, uint16_t *dec_rate);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_ADIS_H */
