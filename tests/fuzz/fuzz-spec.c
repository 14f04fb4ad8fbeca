/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Fuzz harness of the sensor and ADC specification files: the INI parser,
 * the [sensor] and [adc] readers (quantities with units, ranges, enums),
 * and what a report derives from a spec that parsed: the converter (for
 * word lengths that keep its tables small) and the ADC-selection analysis.
 */
#include "fuzz.h"

#include <string.h>

#include "internal.h"
#include "sensorscope.h"
#include "sscope-adc.h"

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	fuzz_quiet();
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct ssc_ini *ini;
	struct sscope_sensor_spec s;
	struct sscope_adc_spec a;
	struct sscope_diag d = { "" };
	bool have_s, have_a;

	if (memchr(data, '\0', size)) /* refused by ssc_ini_load */
		return 0;
	if (ssc_ini_parse(&ini, (const char *)data, size, "fuzz.ini", &d))
		return 0;
	have_s = ssc_sensor_spec_from_ini(ini, "sensor", &s, &d) == 0;
	have_a = ssc_adc_spec_from_ini(ini, "adc", &a, &d) == 0;
	if (have_a && a.bits <= 16) {
		struct sscope_adc *adc;
		double x[8] = { 0, 1e-3, -2.5, 7, 1e3, -1e9, 0.3, 1e-300 };

		if (sscope_adc_new(&adc, &a, a.analog ? 0.006 : 1, a.analog ? 2.5 : 0,
				   1, &d) == 0) {
			double out[8];
			int64_t codes[8];
			size_t clipped;

			sscope_adc_digitize(adc, x, 1, 8,
					    a.rate_hz > 0 ? a.rate_hz : 100, NULL,
					    out, codes, &clipped);
			sscope_adc_free(adc);
		}
	}
	if (have_s && have_a) {
		struct sscope_adc_analysis res;

		sscope_adc_analyze(&s, &a, 0, &res, &d);
	}
	ssc_ini_free(ini);
	return 0;
}
