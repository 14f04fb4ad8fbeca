/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * INI files (sensor, ADC and scene specifications) and the sensor
 * specification.  Syntax: "[section]" headers, "key = value" or
 * "key: value" lines, '#' or ';' comments (whole lines, or after a blank
 * inside a value), keys case-insensitive.  Values may carry units inline
 * ("noise_density = 0.15 deg/sqrt(h)"); they are converted to SI with the
 * unit parser, and a unit of the wrong dimension is an error naming the
 * file, line and key.  Sensor noise terms follow IEEE Std 952-1997 Annex C
 * (Q, N, B, K, R).
 */
#include "internal.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "sscope-quantity.h"
#include "sscope-sensor.h"
#include "sscope-unit.h"

struct ini_kv {
	char *key;
	char *value;
	size_t line;
};

struct ini_section {
	char *name;
	size_t line;
	struct ini_kv *kv;
	size_t n, cap;
};

struct ssc_ini {
	char *name; /* file name for messages */
	struct ini_section *sec;
	size_t n, cap;
};

static char *trim_dup(const char *a, const char *b)
{
	char *s;

	while (a < b && isspace((unsigned char)*a))
		a++;
	while (b > a && isspace((unsigned char)b[-1]))
		b--;
	s = malloc((size_t)(b - a) + 1);
	if (s) {
		memcpy(s, a, (size_t)(b - a));
		s[b - a] = '\0';
	}
	return s;
}

void ssc_ini_free(struct ssc_ini *ini)
{
	if (!ini)
		return;
	for (size_t i = 0; i < ini->n; i++) {
		for (size_t k = 0; k < ini->sec[i].n; k++) {
			free(ini->sec[i].kv[k].key);
			free(ini->sec[i].kv[k].value);
		}
		free(ini->sec[i].kv);
		free(ini->sec[i].name);
	}
	free(ini->sec);
	free(ini->name);
	free(ini);
}

static struct ini_section *add_section(struct ssc_ini *ini, char *name,
				       size_t line)
{
	if (ini->n == ini->cap) {
		size_t nc = ini->cap ? 2 * ini->cap : 8;
		struct ini_section *ns = realloc(ini->sec, nc * sizeof(*ns));

		if (!ns)
			return NULL;
		ini->sec = ns;
		ini->cap = nc;
	}
	memset(&ini->sec[ini->n], 0, sizeof(ini->sec[0]));
	ini->sec[ini->n].name = name;
	ini->sec[ini->n].line = line;
	return &ini->sec[ini->n++];
}

static int add_kv(struct ini_section *s, char *key, char *value, size_t line)
{
	if (s->n == s->cap) {
		size_t nc = s->cap ? 2 * s->cap : 8;
		struct ini_kv *nk = realloc(s->kv, nc * sizeof(*nk));

		if (!nk)
			return -ENOMEM;
		s->kv = nk;
		s->cap = nc;
	}
	s->kv[s->n++] = (struct ini_kv){ key, value, line };
	return 0;
}

int ssc_ini_parse(struct ssc_ini **out, const char *text, size_t len,
		  const char *name, struct sscope_diag *diag)
{
	struct ssc_ini *ini = calloc(1, sizeof(*ini));
	struct ini_section *cur = NULL;
	const char *p = text, *end = text + len;
	size_t line = 0;
	int rc = 0;

	*out = NULL;
	if (!ini)
		return -ENOMEM;
	ini->name = ssc_strdup(name ? name : "(spec)");
	if (!ini->name) {
		free(ini);
		return -ENOMEM;
	}
	/* the byte-order mark Windows editors write at the start */
	if (end - p >= 3 && !memcmp(p, "\xef\xbb\xbf", 3))
		p += 3;
	while (p < end) {
		const char *e = memchr(p, '\n', (size_t)(end - p)), *q, *eq;
		char *key, *value;

		if (!e)
			e = end;
		line++;
		q = p;
		while (q < e && isspace((unsigned char)*q))
			q++;
		if (q >= e || *q == '#' || *q == ';') {
			p = e + 1;
			continue;
		}
		if (*q == '[') {
			const char *c = memchr(q, ']', (size_t)(e - q));
			char *sname;

			if (!c) {
				rc = ssc_diag(diag, -EBADMSG,
					      "%s: line %zu: section header without ']'",
					      ini->name, line);
				goto fail;
			}
			sname = trim_dup(q + 1, c);
			if (!sname) {
				rc = -ENOMEM;
				goto fail;
			}
			for (size_t i = 0; i < ini->n; i++)
				if (!strcasecmp(ini->sec[i].name, sname)) {
					rc = ssc_diag(diag, -EBADMSG,
						      "%s: line %zu: section [%s] repeats line %zu",
						      ini->name, line, sname,
						      ini->sec[i].line);
					free(sname);
					goto fail;
				}
			cur = add_section(ini, sname, line);
			if (!cur) {
				free(sname);
				rc = -ENOMEM;
				goto fail;
			}
			p = e + 1;
			continue;
		}
		eq = q;
		while (eq < e && *eq != '=' && *eq != ':')
			eq++;
		if (eq >= e) {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: line %zu: expected 'key = value'",
				      ini->name, line);
			goto fail;
		}
		if (!cur) {
			rc = ssc_diag(diag, -EBADMSG,
				      "%s: line %zu: key outside any [section]",
				      ini->name, line);
			goto fail;
		}
		{
			/* a comment inside a value starts with " #" or " ;" */
			const char *ve = eq + 1;

			while (ve < e) {
				if ((*ve == '#' || *ve == ';') &&
				    isspace((unsigned char)ve[-1]))
					break;
				ve++;
			}
			key = trim_dup(q, eq);
			value = trim_dup(eq + 1, ve);
		}
		if (!key || !value) {
			free(key);
			free(value);
			rc = -ENOMEM;
			goto fail;
		}
		if (!*key) {
			free(key);
			free(value);
			rc = ssc_diag(diag, -EBADMSG, "%s: line %zu: empty key",
				      ini->name, line);
			goto fail;
		}
		for (size_t k = 0; k < cur->n; k++)
			if (!strcasecmp(cur->kv[k].key, key)) {
				rc = ssc_diag(diag, -EBADMSG,
					      "%s: line %zu: key '%s' repeats line %zu",
					      ini->name, line, key, cur->kv[k].line);
				free(key);
				free(value);
				goto fail;
			}
		rc = add_kv(cur, key, value, line);
		if (rc) {
			free(key);
			free(value);
			goto fail;
		}
		p = e + 1;
	}
	*out = ini;
	return 0;
fail:
	ssc_ini_free(ini);
	return rc;
}

/* a file ssc_ini_load() opened ('-' is standard input: left open) */
static void close_in(FILE *f)
{
	if (f != stdin)
		fclose(f);
}

int ssc_ini_load(struct ssc_ini **out, const char *path,
		 struct sscope_diag *diag)
{
	FILE *f;
	char *buf = NULL;
	size_t len = 0, cap = 0;
	int rc;

	if (!out || !path)
		return ssc_diag(diag, -EINVAL, "no file named");
	*out = NULL;
	/* '-': standard input, as for captures */
	f = strcmp(path, "-") ? fopen(path, "rb") : stdin;
	if (!f)
		return ssc_diag(diag, -errno, "%s: %s", path,
				sscope_strerror(-errno));
	for (;;) {
		size_t got;

		if (len + 4096 > cap) {
			size_t nc = cap ? 2 * cap : 8192;
			char *nb;

			if (nc > (16u << 20)) {
				free(buf);
				close_in(f);
				return ssc_diag(diag, -EBADMSG,
						"%s: too large for a specification",
						path);
			}
			nb = realloc(buf, nc);
			if (!nb) {
				free(buf);
				close_in(f);
				return -ENOMEM;
			}
			buf = nb;
			cap = nc;
		}
		errno = 0;
		got = fread(buf + len, 1, cap - len, f);
		len += got;
		if (got == 0)
			break;
	}
	if (ferror(f)) {
		/* the system's reason (a directory opens, then fails to read) */
		int err = errno ? -errno : -EIO;

		free(buf);
		close_in(f);
		return ssc_diag(diag, err, "%s: %s", path, sscope_strerror(err));
	}
	close_in(f);
	if (memchr(buf, '\0', len)) {
		free(buf);
		return ssc_diag(diag, -EBADMSG, "%s: binary data, not an INI file",
				path);
	}
	rc = ssc_ini_parse(out, buf, len, path, diag);
	free(buf);
	return rc;
}

const char *ssc_ini_name(const struct ssc_ini *ini)
{
	return ini->name;
}

size_t ssc_ini_n_sections(const struct ssc_ini *ini)
{
	return ini->n;
}

const char *ssc_ini_section(const struct ssc_ini *ini, size_t i,
			    size_t *line)
{
	if (i >= ini->n)
		return NULL;
	if (line)
		*line = ini->sec[i].line;
	return ini->sec[i].name;
}

static const struct ini_section *find_section(const struct ssc_ini *ini,
					      const char *section)
{
	for (size_t i = 0; i < ini->n; i++)
		if (!strcasecmp(ini->sec[i].name, section))
			return &ini->sec[i];
	return NULL;
}

bool ssc_ini_has_section(const struct ssc_ini *ini, const char *section)
{
	return find_section(ini, section) != NULL;
}

size_t ssc_ini_n_keys(const struct ssc_ini *ini, const char *section)
{
	const struct ini_section *s = find_section(ini, section);

	return s ? s->n : 0;
}

const char *ssc_ini_key(const struct ssc_ini *ini, const char *section,
			size_t k, const char **value, size_t *line)
{
	const struct ini_section *s = find_section(ini, section);

	if (!s || k >= s->n)
		return NULL;
	if (value)
		*value = s->kv[k].value;
	if (line)
		*line = s->kv[k].line;
	return s->kv[k].key;
}

const char *ssc_ini_get(const struct ssc_ini *ini, const char *section,
			const char *key, size_t *line)
{
	const struct ini_section *s = find_section(ini, section);

	if (!s)
		return NULL;
	for (size_t k = 0; k < s->n; k++)
		if (!strcasecmp(s->kv[k].key, key)) {
			if (line)
				*line = s->kv[k].line;
			return s->kv[k].value;
		}
	return NULL;
}

int ssc_ini_check_keys(const struct ssc_ini *ini, const char *section,
		       const char *const *allowed, struct sscope_diag *diag)
{
	const struct ini_section *s = find_section(ini, section);

	if (!s)
		return 0;
	for (size_t k = 0; k < s->n; k++) {
		const char *const *a = allowed;

		while (*a && strcasecmp(*a, s->kv[k].key))
			a++;
		if (!*a)
			return ssc_diag(diag, -EINVAL,
					"%s: line %zu: unknown key '%s' in [%s]",
					ini->name, s->kv[k].line, s->kv[k].key,
					s->name);
	}
	return 0;
}

int ssc_ini_quantity(const struct ssc_ini *ini, const char *section,
		     const char *key, const char *si_unit, double *out,
		     struct sscope_diag *diag)
{
	struct sscope_unit u, want;
	struct sscope_diag d = { "" };
	size_t line = 0;
	const char *v = ssc_ini_get(ini, section, key, &line);
	double x;
	int rc;

	if (!v)
		return -ENOENT;
	rc = sscope_unit_parse(si_unit, &want, NULL);
	if (rc)
		return ssc_diag(diag, -EINVAL, "bad SI unit '%s'", si_unit);
	rc = sscope_quantity_parse(v, &x, &u, &d);
	if (rc)
		return ssc_diag(diag, -EINVAL, "%s: line %zu: %s: %s", ini->name,
				line, key, d.msg);
	if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS &&
	    u.scale == 1 && !sscope_unit_compatible(&u, &want)) {
		/* a bare number is taken in the SI unit */
		x = sscope_unit_to_si(&want, x);
	} else if (!sscope_unit_compatible(&u, &want)) {
		char si[64];

		sscope_unit_si_string(&want, si, sizeof(si));
		return ssc_diag(diag, -EINVAL,
				"%s: line %zu: %s = %s: wrong unit (expected something in %s)",
				ini->name, line, key, v, si);
	}
	*out = x;
	return 0;
}

int ssc_ini_integer(const struct ssc_ini *ini, const char *section,
		    const char *key, long lo, long hi, long *out,
		    struct sscope_diag *diag)
{
	size_t line = 0;
	const char *v = ssc_ini_get(ini, section, key, &line);
	char *end;
	long x;

	if (!v)
		return -ENOENT;
	errno = 0;
	x = strtol(v, &end, 10);
	while (*end == ' ' || *end == '\t')
		end++;
	if (end == v || *end || errno)
		return ssc_diag(diag, -EINVAL,
				"%s: line %zu: %s = %s: not an integer", ini->name,
				line, key, v);
	if (x < lo || x > hi)
		return ssc_diag(diag, -EINVAL,
				"%s: line %zu: %s = %ld: outside %ld..%ld",
				ini->name, line, key, x, lo, hi);
	*out = x;
	return 0;
}

/* ------------------------------------------------------------ sensor */

static const char *const sensor_keys[] = {
	"name", "range", "noise_density", "bias_instability",
	"rate_random_walk", "quantization", "rate_ramp", "bias",
	"scale_factor_error", "bias_tempco", "temp_min", "temp_max",
	"sensitivity", "zero_output", "bandwidth", "filter_order", NULL
};

const char *const *sscope_sensor_spec_keys(void)
{
	return sensor_keys;
}

/* SI unit of each field, for a rate unit U ("rad/s" or "m/s^2") */
static void unit_for(char *buf, size_t len, const char *U, const char *suffix)
{
	snprintf(buf, len, "%s%s", U, suffix);
}

static int detect_quantity(const struct ssc_ini *ini, const char *sec,
			   enum sscope_quantity *q, struct sscope_diag *diag)
{
	static const char *const probe[] = { "range", "noise_density",
					     "bias_instability", "bias",
					     "rate_random_walk", NULL };
	static const struct {
		enum sscope_quantity q;
		const char *U;
	} kinds[] = { { SSCOPE_QUANTITY_ANGULAR_RATE, "rad/s" },
		      { SSCOPE_QUANTITY_ACCELERATION, "m/s^2" } };
	static const char *const suffix[] = { "", "/sqrt(Hz)", "", "",
					      "/s/sqrt(Hz)" };

	for (size_t i = 0; probe[i]; i++) {
		const char *v = ssc_ini_get(ini, sec, probe[i], NULL);
		struct sscope_unit u;
		double x;

		if (!v || sscope_quantity_parse(v, &x, &u, NULL))
			continue;
		for (size_t k = 0; k < 2; k++) {
			char want[48];
			struct sscope_unit w;

			unit_for(want, sizeof(want), kinds[k].U, suffix[i]);
			sscope_unit_parse(want, &w, NULL);
			if (sscope_unit_compatible(&u, &w)) {
				*q = kinds[k].q;
				return 0;
			}
		}
	}
	return ssc_diag(diag, -EINVAL,
			"%s: [%s]: cannot tell a gyro from an accelerometer: give 'range' or 'noise_density' with a unit (e.g. 250 deg/s, 0.15 deg/sqrt(h))",
			ssc_ini_name(ini), sec);
}

int ssc_sensor_spec_from_ini(const struct ssc_ini *ini,
			     const char *section,
			     struct sscope_sensor_spec *s,
			     struct sscope_diag *diag)
{
	static const struct {
		const char *key;
		const char *suffix; /* appended to the rate unit U */
		size_t off;
		unsigned flag;
	} fields[] = {
		{ "range", "", offsetof(struct sscope_sensor_spec, range),
		  SSCOPE_SENSOR_HAS_RANGE },
		{ "quantization", "*s",
		  offsetof(struct sscope_sensor_spec, q), SSCOPE_SENSOR_HAS_Q },
		{ "noise_density", "/sqrt(Hz)",
		  offsetof(struct sscope_sensor_spec, n), SSCOPE_SENSOR_HAS_N },
		{ "bias_instability", "",
		  offsetof(struct sscope_sensor_spec, b), SSCOPE_SENSOR_HAS_B },
		{ "rate_random_walk", "/s/sqrt(Hz)",
		  offsetof(struct sscope_sensor_spec, k), SSCOPE_SENSOR_HAS_K },
		{ "rate_ramp", "/s", offsetof(struct sscope_sensor_spec, r),
		  SSCOPE_SENSOR_HAS_R },
		{ "bias", "", offsetof(struct sscope_sensor_spec, bias),
		  SSCOPE_SENSOR_HAS_BIAS },
		{ "bias_tempco", "/degC",
		  offsetof(struct sscope_sensor_spec, bias_tempco),
		  SSCOPE_SENSOR_HAS_TEMPCO },
		{ "sensitivity", "", offsetof(struct sscope_sensor_spec, sensitivity),
		  SSCOPE_SENSOR_HAS_SENSITIVITY },
	};
	const char *U;
	const char *v;
	int rc;
	long order;

	memset(s, 0, sizeof(*s));
	if (!ssc_ini_has_section(ini, section))
		return ssc_diag(diag, -EINVAL, "%s: no [%s] section",
				ssc_ini_name(ini), section);
	rc = ssc_ini_check_keys(ini, section, sensor_keys, diag);
	if (rc)
		return rc;
	rc = detect_quantity(ini, section, &s->quantity, diag);
	if (rc)
		return rc;
	U = s->quantity == SSCOPE_QUANTITY_ANGULAR_RATE ? "rad/s" : "m/s^2";
	v = ssc_ini_get(ini, section, "name", NULL);
	snprintf(s->name, sizeof(s->name), "%s", v ? v : section);
	for (size_t i = 0; i < sizeof(fields) / sizeof(fields[0]); i++) {
		char want[64];
		double x;

		if (!strcmp(fields[i].key, "sensitivity"))
			snprintf(want, sizeof(want), "V/(%s)", U);
		else
			unit_for(want, sizeof(want), U, fields[i].suffix);
		rc = ssc_ini_quantity(ini, section, fields[i].key, want, &x,
				      diag);
		if (rc == -ENOENT)
			continue;
		if (rc)
			return rc;
		if (!isfinite(x) ||
		    (x < 0 && strcmp(fields[i].key, "bias") &&
		     strcmp(fields[i].key, "bias_tempco")))
			return ssc_diag(diag, -EINVAL,
					"%s: [%s] %s must be a non-negative number",
					ssc_ini_name(ini), section,
					fields[i].key);
		*(double *)((char *)s + fields[i].off) = x;
		s->has |= fields[i].flag;
	}
	if ((s->has & SSCOPE_SENSOR_HAS_RANGE) && !(s->range > 0))
		return ssc_diag(diag, -EINVAL, "%s: [%s] range must be positive",
				ssc_ini_name(ini), section);
	rc = ssc_ini_quantity(ini, section, "scale_factor_error", "1",
			      &s->scale_factor_error, diag);
	if (rc == 0)
		s->has |= SSCOPE_SENSOR_HAS_SF;
	else if (rc != -ENOENT)
		return rc;
	/* a bare scale-factor error is in ppm, as datasheets give it */
	v = ssc_ini_get(ini, section, "scale_factor_error", NULL);
	if (v && rc == 0) {
		struct sscope_unit u;
		double x;

		if (!sscope_quantity_parse(v, &x, &u, NULL) &&
		    sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS &&
		    u.scale == 1)
			s->scale_factor_error = x * 1e-6;
	}
	rc = ssc_ini_quantity(ini, section, "temp_min", "degC",
			      &s->temp_min_degc, diag);
	if (rc && rc != -ENOENT)
		return rc;
	rc = ssc_ini_quantity(ini, section, "temp_max", "degC",
			      &s->temp_max_degc, diag);
	if (rc && rc != -ENOENT)
		return rc;
	if (ssc_ini_get(ini, section, "temp_min", NULL) &&
	    ssc_ini_get(ini, section, "temp_max", NULL)) {
		if (!(s->temp_max_degc > s->temp_min_degc))
			return ssc_diag(diag, -EINVAL,
					"%s: [%s] temp_max must exceed temp_min",
					ssc_ini_name(ini), section);
		s->has |= SSCOPE_SENSOR_HAS_TEMPS;
	}
	rc = ssc_ini_quantity(ini, section, "zero_output", "V",
			      &s->zero_output_v, diag);
	if (rc == 0)
		s->has |= SSCOPE_SENSOR_HAS_ZERO;
	else if (rc != -ENOENT)
		return rc;
	rc = ssc_ini_quantity(ini, section, "bandwidth", "Hz",
			      &s->bandwidth_hz, diag);
	if (rc == 0) {
		if (!(s->bandwidth_hz > 0))
			return ssc_diag(diag, -EINVAL,
					"%s: [%s] bandwidth must be positive",
					ssc_ini_name(ini), section);
		s->has |= SSCOPE_SENSOR_HAS_BANDWIDTH;
	} else if (rc != -ENOENT) {
		return rc;
	}
	rc = ssc_ini_integer(ini, section, "filter_order", 1, 8, &order, diag);
	if (rc == 0)
		s->filter_order = (int)order;
	else if (rc != -ENOENT)
		return rc;
	else
		s->filter_order = 1;
	return 0;
}

int sscope_sensor_spec_load(const char *path, struct sscope_sensor_spec *s,
			    struct sscope_diag *diag)
{
	struct ssc_ini *ini;
	int rc = ssc_ini_load(&ini, path, diag);

	if (rc)
		return rc;
	rc = ssc_sensor_spec_from_ini(ini, "sensor", s, diag);
	ssc_ini_free(ini);
	return rc;
}
