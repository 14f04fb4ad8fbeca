/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Fuzz harness of INL profiles (the inl_profile key of an [adc] spec: one
 * INL value per transition, 2^bits of them, '#' comments).  The first
 * input byte picks the word length (1..12 bits), the rest is the profile;
 * a profile that reads is set on a converter that then digitizes a ramp.
 */
#include "fuzz.h"

#include <stdio.h>
#include <string.h>

#include "cli.h"
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
	struct sscope_adc_spec spec;
	struct ssc_inl_profile prof;
	struct sscope_diag d = { "" };
	char path[64], text[256];
	int bits, fd;

	if (size < 1)
		return 0;
	bits = 1 + data[0] % 12;
	fd = fuzz_file(data + 1, size - 1, path, sizeof(path));
	if (fd < 0)
		return 0;
	snprintf(text, sizeof(text),
		 "[adc]\nbits = %d\nrange = -2.5:2.5 V\nrate = 100 Hz\ninl_profile = %s\n",
		 bits, path);
	if (ssc_ini_parse(&ini, text, strlen(text), "fuzz.ini", &d) == 0) {
		if (ssc_adc_spec_from_ini(ini, "adc", &spec, &d) == 0 &&
		    ssc_adc_profile_load("adc", "fuzz.ini", &spec, &prof) == 0) {
			struct sscope_adc *adc;

			if (ssc_adc_new(&adc, &spec, &prof, 0.006, 2.5, 1, &d) == 0) {
				double x[64], out[64];
				int64_t codes[64];
				size_t clipped;

				for (int i = 0; i < 64; i++)
					x[i] = -450 + 14.3 * i;
				sscope_adc_digitize(adc, x, 1, 64, 100, NULL, out,
						    codes, &clipped);
				sscope_adc_free(adc);
			}
			ssc_adc_profile_free(&prof);
		}
		ssc_ini_free(ini);
	}
	fuzz_file_close(fd);
	return 0;
}
