/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * json-same A.json[#/POINTER] B.json[#/POINTER] [REL]: exit 0 when the two
 * JSON values are the same -- objects with the same keys, arrays of the
 * same length, equal strings, booleans and nulls, and numbers equal within
 * the relative tolerance REL (default 0: bit-equal; in an array of numbers,
 * relative to its largest magnitude, so that a curve passing near zero is
 * held to its own scale) -- else print the
 * first difference (its path and both values) and exit 1; 2 for a
 * missing or malformed file.  POINTER selects a member (RFC 6901), e.g.
 * "#/files/1".  Used by the equivalence tests of scenes and commands.
 */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double rel_tol;

static json_t *load(const char *arg, json_t **root)
{
	char path[4096];
	const char *hash = strchr(arg, '#');
	size_t n = hash ? (size_t)(hash - arg) : strlen(arg);
	json_error_t err;
	json_t *v;

	if (n >= sizeof(path))
		return NULL;
	memcpy(path, arg, n);
	path[n] = '\0';
	*root = json_load_file(path, JSON_DECODE_ANY, &err);
	if (!*root) {
		fprintf(stderr, "json-same: %s: %s (line %d)\n", path, err.text,
			err.line);
		return NULL;
	}
	v = *root;
	if (hash && hash[1] == '/') {
		const char *p = hash + 2;

		while (v && *p) {
			const char *e = strchr(p, '/');
			size_t l = e ? (size_t)(e - p) : strlen(p);
			char key[256];

			if (l >= sizeof(key))
				return NULL;
			memcpy(key, p, l);
			key[l] = '\0';
			if (json_is_array(v))
				v = json_array_get(v, strtoul(key, NULL, 10));
			else
				v = json_object_get(v, key);
			p += l + (e ? 1 : 0);
		}
		if (!v)
			fprintf(stderr, "json-same: %s: no member %s\n", path, hash);
	}
	return v;
}

static int differ(const char *path, json_t *a, json_t *b)
{
	char *sa = json_dumps(a, JSON_ENCODE_ANY | JSON_COMPACT | JSON_REAL_PRECISION(17));
	char *sb = json_dumps(b, JSON_ENCODE_ANY | JSON_COMPACT | JSON_REAL_PRECISION(17));

	fprintf(stderr, "json-same: %s: %.200s <> %.200s\n", *path ? path : "/",
		sa ? sa : "?", sb ? sb : "?");
	free(sa);
	free(sb);
	return 1;
}

/* The largest magnitude in two arrays when both hold only numbers, else 0. */
static double array_scale(json_t *a, json_t *b)
{
	double m = 0;

	for (size_t i = 0; i < json_array_size(a); i++) {
		json_t *x = json_array_get(a, i), *y = json_array_get(b, i);

		if (!json_is_number(x) || !json_is_number(y))
			return 0;
		m = fmax(m, fmax(fabs(json_number_value(x)),
				 fabs(json_number_value(y))));
	}
	return m;
}

static int same(const char *path, json_t *a, json_t *b);

static int same_scaled(const char *path, json_t *a, json_t *b, double scale)
{
	char sub[1024];

	if (json_is_number(a) && json_is_number(b)) {
		double x = json_number_value(a), y = json_number_value(b);

		if (x == y ||
		    fabs(x - y) <= rel_tol * fmax(scale, fmax(fabs(x), fabs(y))))
			return 0;
		return differ(path, a, b);
	}
	if (json_typeof(a) != json_typeof(b))
		return differ(path, a, b);
	if (json_is_object(a)) {
		const char *k;
		json_t *v;

		if (json_object_size(a) != json_object_size(b))
			return differ(path, a, b);
		json_object_foreach(a, k, v) {
			json_t *w = json_object_get(b, k);

			snprintf(sub, sizeof(sub), "%s/%s", path, k);
			if (!w)
				return differ(sub, v, json_null());
			if (same(sub, v, w))
				return 1;
		}
		return 0;
	}
	if (json_is_array(a)) {
		if (json_array_size(a) != json_array_size(b))
			return differ(path, a, b);
		double m = array_scale(a, b);

		for (size_t i = 0; i < json_array_size(a); i++) {
			snprintf(sub, sizeof(sub), "%s/%zu", path, i);
			if (same_scaled(sub, json_array_get(a, i),
					json_array_get(b, i), m))
				return 1;
		}
		return 0;
	}
	return json_equal(a, b) ? 0 : differ(path, a, b);
}

static int same(const char *path, json_t *a, json_t *b)
{
	return same_scaled(path, a, b, 0);
}

int main(int argc, char **argv)
{
	json_t *ra = NULL, *rb = NULL, *a, *b;
	int rc;

	if (argc < 3 || argc > 4) {
		fprintf(stderr, "usage: json-same A.json[#/POINTER] B.json[#/POINTER] [REL]\n");
		return 2;
	}
	rel_tol = argc == 4 ? strtod(argv[3], NULL) : 0;
	a = load(argv[1], &ra);
	b = a ? load(argv[2], &rb) : NULL;
	rc = a && b ? same("", a, b) : 2;
	json_decref(ra);
	json_decref(rb);
	return rc;
}
