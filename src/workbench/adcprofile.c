/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The inl_profile key of an [adc] specification: a text file of the INL of
 * every transition, LSB (one number per line, '#' comments, exactly 2^bits
 * values, index k = transition k as sscope_adc_set_inl() documents).  The
 * library stores the path only (adc/ does no I/O); the commands that build
 * converters read it here, and set the spec's INL bound to max |INL| so
 * that the report shows the profile's size.
 */
#include "workbench.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static char *resolve(const char *spec_path, const char *rel)
{
	const char *slash = spec_path ? strrchr(spec_path, '/') : NULL;
	size_t dl = slash && rel[0] != '/' ? (size_t)(slash - spec_path) + 1 : 0;
	char *p = malloc(dl + strlen(rel) + 1);

	if (!p)
		return NULL;
	memcpy(p, spec_path ? spec_path : "", dl);
	strcpy(p + dl, rel);
	return p;
}

int ssc_adc_profile_load(const char *cmd, const char *spec_path,
			 struct sscope_adc_spec *spec, struct ssc_inl_profile *prof)
{
	char *path, line[512];
	size_t nc, n = 0, lineno = 0, *at = NULL;
	double *inl = NULL, mx = 0;
	FILE *f;
	int rc = SSC_EXIT_FAIL;

	memset(prof, 0, sizeof(*prof));
	if (!spec->inl_profile[0])
		return SSC_EXIT_OK;
	if (spec->bits > SSCOPE_ADC_TABLE_BITS) { /* refused by the parser too */
		ssc_err(cmd, "%s: inl_profile: a profile needs bits <= %d", spec_path,
			SSCOPE_ADC_TABLE_BITS);
		return SSC_EXIT_FAIL;
	}
	nc = (size_t)1 << spec->bits;
	path = resolve(spec_path, spec->inl_profile);
	inl = malloc(nc * sizeof(double));
	at = malloc(nc * sizeof(size_t));
	if (!path || !inl || !at) {
		ssc_err(cmd, "out of memory");
		goto out;
	}
	f = fopen(path, "r");
	if (!f) {
		ssc_err(cmd, "%s: inl_profile: %s: %s", spec_path, path, sscope_strerror(errno));
		goto out;
	}
	while (fgets(line, sizeof(line), f)) {
		char *p = line, *e, *hash = strchr(line, '#');
		size_t len = strlen(line);
		double v;
		size_t k;

		lineno++;
		if (len == sizeof(line) - 1 && line[len - 1] != '\n' && !hash) {
			ssc_err(cmd, "%s: line %zu: line too long (one INL value per line)",
				path, lineno);
			fclose(f);
			goto out;
		}
		if (hash)
			*hash = '\0';
		while (isspace((unsigned char)*p))
			p++;
		e = p + strlen(p);
		while (e > p && isspace((unsigned char)e[-1]))
			*--e = '\0';
		if (!*p)
			continue;
		k = ssc_parse_double(p, e, &v);
		if (k != (size_t)(e - p) || !isfinite(v)) {
			ssc_err(cmd, "%s: line %zu: '%s' is not a number (INL of one transition, LSB)",
				path, lineno, p);
			fclose(f);
			goto out;
		}
		if (n == nc) {
			ssc_err(cmd, "%s: line %zu: more than %zu values (2^%d, one per transition of the converter)",
				path, lineno, nc, spec->bits);
			fclose(f);
			goto out;
		}
		at[n] = lineno;
		inl[n++] = v;
	}
	fclose(f);
	if (n != nc) {
		ssc_err(cmd, "%s: %zu values, need %zu (2^%d, one per transition of the converter)",
			path, n, nc, spec->bits);
		goto out;
	}
	/* transition k sits at k - 1/2 + inl[k] LSB (k >= 1; inl[0] unused) */
	for (size_t k = 1; k < nc; k++) {
		if (k > 1 && !(inl[k] + 1 > inl[k - 1])) {
			ssc_err(cmd, "%s: line %zu: transition %zu at or below transition %zu (INL %g after %g: the transitions must increase)",
				path, at[k], k, k - 1, inl[k], inl[k - 1]);
			goto out;
		}
		mx = fmax(mx, fabs(inl[k]));
	}
	spec->inl_lsb = mx;
	spec->has |= SSCOPE_ADC_HAS_INL;
	prof->inl = inl;
	prof->n = nc;
	inl = NULL;
	rc = SSC_EXIT_OK;
out:
	free(path);
	free(inl);
	free(at);
	return rc;
}

int ssc_adc_new(struct sscope_adc **adc, const struct sscope_adc_spec *spec,
		const struct ssc_inl_profile *prof, double sensitivity,
		double zero_v, uint64_t seed, struct sscope_diag *diag)
{
	int rc = sscope_adc_new(adc, spec, sensitivity, zero_v, seed, diag);

	if (rc || !prof || !prof->inl)
		return rc;
	rc = sscope_adc_set_inl(*adc, prof->inl, prof->n);
	if (rc) {
		sscope_adc_free(*adc);
		*adc = NULL;
		if (diag)
			snprintf(diag->msg, sizeof(diag->msg), "inl_profile: %s",
				 sscope_strerror(rc));
	}
	return rc;
}

void ssc_adc_profile_free(struct ssc_inl_profile *prof)
{
	if (!prof)
		return;
	free(prof->inl);
	prof->inl = NULL;
	prof->n = 0;
}
