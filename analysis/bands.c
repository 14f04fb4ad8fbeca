/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Bands of a spectrum: bands between given edges, the IEC 61260-1
 * fractional-octave bands a spectrum resolves (at least one bin wide).
 */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sscope-psd.h"

int sscope_psd_band_edges(double lo_hz, double hi_hz, double nyquist_hz,
			  struct sscope_psd_band *band)
{
	if (!band || !(lo_hz >= 0) || !(hi_hz > lo_hz) || !isfinite(hi_hz) ||
	    !(nyquist_hz > 0))
		return -EINVAL;
	if (lo_hz >= nyquist_hz)
		return -EDOM;
	band->lo_hz = lo_hz;
	band->hi_hz = hi_hz > nyquist_hz ? nyquist_hz : hi_hz;
	band->center_hz = sqrt(lo_hz * band->hi_hz);
	band->nominal_hz = NAN;
	band->rms = NAN;
	return 0;
}

int sscope_psd_spectrum_octave_bands(const struct sscope_psd_spectrum *s,
				     unsigned fraction, struct sscope_psd_band *bands,
				     size_t max, size_t *n_found)
{
	struct sscope_psd_band *all;
	size_t na, k = 0;
	int rc;

	if (!s || !n_found || !(s->bin_hz > 0) || !(s->fs_hz > 0))
		return -EINVAL;
	*n_found = 0;
	rc = sscope_psd_octave_bands(fraction, s->bin_hz / 2, s->fs_hz / 2, NULL, 0,
				     &na);
	if (rc)
		return rc;
	all = ssc_alloc_array(na ? na : 1, sizeof(*all));
	if (!all)
		return -ENOMEM;
	sscope_psd_octave_bands(fraction, s->bin_hz / 2, s->fs_hz / 2, all, na, &na);
	for (size_t i = 0; i < na; i++) {
		if (all[i].hi_hz - all[i].lo_hz < s->bin_hz)
			continue;
		if (bands && k < max)
			bands[k] = all[i];
		k++;
	}
	free(all);
	*n_found = k;
	return bands && k > max ? -ERANGE : 0;
}
