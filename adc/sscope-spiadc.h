/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-spiadc.h
 * @brief Generic SPI converter frames: what to send, where each channel's
 *        code sits in the answer, and how codes become volts and, through
 *        an analog sensor's sensitivity, physical units.
 *
 * Enough to digitise an analog gyro through an ordinary SPI ADC (MCP3208,
 * ADS8688, AD7689, ...).  Pure: bytes in, SI values out.
 *
 * A frame is one SPI message of up to SSCOPE_SPIADC_MAX_BYTES bytes split
 * into up to SSCOPE_SPIADC_MAX_XFERS transfers (chip select is released
 * between transfers).  Channel codes are bit fields of the received bytes
 * taken most significant bit first; bit 0 is the MSB of the first byte.
 *
 * Text form (sscope_spiadc_parse), comma-separated key=value items:
 * - `tx=HEX[/HEX...]`  bytes sent, '/' releases chip select (required);
 * - `ch=NAME@BIT[+BITS]` a channel whose code's MSB is received bit BIT
 *   (one item per channel; the capture keeps their order);
 * - scaling items, which apply to the ch= items that FOLLOW them:
 *   `bits=N` code width (1..32) of channels that give none;
 *   `coding=unsigned|twos|offset` straight binary (default), two's
 *   complement or offset binary;
 *   `range=LO:HI` input span in volts: code c of an unsigned channel is
 *   LO + c * LSB, a bipolar code (twos, offset) is (LO + HI) / 2 + c * LSB,
 *   with LSB = (HI - LO) / 2^bits;
 *   `sens=Q`, `zero=V`, `unit=U` an analog sensor's sensitivity (e.g.
 *   `6mV/(deg/s)`), its output at zero input (volts, default 0) and the
 *   unit written to the capture: physical value = (volts - zero) / sens;
 *   `sens=none` returns to plain volts;
 * - `mode=0..3`, `speed=HZ`  SPI mode (default 0) and clock (default
 *   1 MHz).
 * Example (MCP3208: channel 1 carries a temperature voltage, channel 0 a
 * 6 mV/(deg/s) gyro centred at 1.65 V, 3.3 V reference):
 * `tx=060000/064000,bits=12,range=0:3.3,ch=vtemp@36,`
 * `zero=1.65,sens=6mV/(deg/s),unit=deg/s,ch=rate@12`.
 */
#ifndef SSCOPE_SPIADC_H
#define SSCOPE_SPIADC_H

#include "sscope-core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSCOPE_SPIADC_MAX_BYTES 64
#define SSCOPE_SPIADC_MAX_XFERS 16
#define SSCOPE_SPIADC_MAX_CHANNELS 16

/** Code formats. */
enum sscope_spiadc_coding {
	SSCOPE_SPIADC_UNSIGNED = 0, /**< straight binary */
	SSCOPE_SPIADC_TWOS,         /**< two's complement */
	SSCOPE_SPIADC_OFFSET,       /**< offset binary (bipolar) */
};

/** One channel of a frame. */
struct sscope_spiadc_channel {
	char name[32];
	char unit[32];        /**< unit written to captures */
	unsigned bit;         /**< received bit holding the code's MSB */
	unsigned bits;        /**< code width, 1..32 */
	enum sscope_spiadc_coding coding;
	double volts_per_lsb; /**< LSB in volts */
	double volts_zero;    /**< volts at code 0 (unsigned) or mid-code */
	double zero_v;        /**< sensor output at zero input, V */
	double sens;          /**< V per SI unit; 0: the value is in volts */
};

/** A frame description. */
struct sscope_spiadc_frame {
	size_t n_bytes;                               /**< total length */
	uint8_t tx[SSCOPE_SPIADC_MAX_BYTES];          /**< bytes sent */
	size_t n_xfers;
	size_t xfer_len[SSCOPE_SPIADC_MAX_XFERS];     /**< bytes per transfer */
	size_t n_channels;
	struct sscope_spiadc_channel ch[SSCOPE_SPIADC_MAX_CHANNELS];
	unsigned mode;                                /**< SPI mode 0..3 */
	uint32_t speed_hz;                            /**< SPI clock */
};

/**
 * Parse the text form (see the file comment).
 * @param spec   the text (without the "spiadc:" prefix).
 * @param f      receives the frame.
 * @param diag   names the item at fault.
 * @return 0; -EINVAL for a malformed or missing item, a channel outside the
 *         frame, a unit that does not fit the sensitivity.
 */
int sscope_spiadc_parse(const char *spec, struct sscope_spiadc_frame *f,
			struct sscope_diag *diag);

/**
 * Extract @p bits bits starting at received bit @p bit (MSB first).
 * @return the code as an unsigned number.
 */
uint32_t sscope_spiadc_field(const uint8_t *rx, unsigned bit, unsigned bits);

/**
 * Decode a received frame.
 * @param f       the frame.
 * @param rx      f->n_bytes received bytes.
 * @param values  receives f->n_channels values in SI (volts when the
 *                channel has no sensitivity).
 * @param codes   optional: receives the signed codes.
 */
void sscope_spiadc_decode(const struct sscope_spiadc_frame *f,
			  const uint8_t *rx, double *values, int64_t *codes);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_SPIADC_H */
