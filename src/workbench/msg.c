/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Messages: "sensorscope: CMD: message" on one line of standard error,
 * with the bytes a terminal would act on escaped and long quoted excerpts
 * cut; warnings, usage errors and the exit code of a library error.
 */
#include "workbench.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------ messages */

/* A message line is at most this long; a quoted excerpt longer than
 * EXCERPT_MAX bytes keeps its first EXCERPT_KEEP. */
#define MSG_MAX 1024
#define EXCERPT_MAX 64
#define EXCERPT_KEEP 48

static char last_error[MSG_MAX];

/* Where options come from when not from the command line ("scene.ini:
 * line 12"), and the command a stage runs inside; the CLI is
 * single-threaded. */
static const char *option_context;
static const char *outer_cmd;

const char *ssc_last_error(void)
{
	return last_error;
}

void ssc_set_context(const char *ctx)
{
	option_context = ctx;
}

void ssc_set_outer(const char *outer)
{
	outer_cmd = outer;
}

/* Length of the UTF-8 sequence at s and its code point, 0 when it is not
 * one (overlong, surrogate, beyond U+10FFFF, cut short). */
static size_t utf8_seq(const unsigned char *s, unsigned long *cp)
{
	size_t n = s[0] >= 0xf0 ? 4 : s[0] >= 0xe0 ? 3 : s[0] >= 0xc2 ? 2 : 0;
	unsigned long v;

	if (!n || s[0] > 0xf4)
		return 0;
	v = s[0] & (0x7fu >> n);
	for (size_t i = 1; i < n; i++) {
		if ((s[i] & 0xc0) != 0x80)
			return 0;
		v = v << 6 | (s[i] & 0x3fu);
	}
	if ((n == 3 && v < 0x800) || (n == 4 && (v < 0x10000 || v > 0x10ffff)) ||
	    (v >= 0xd800 && v <= 0xdfff))
		return 0;
	*cp = v;
	return n;
}

struct line {
	char *p;
	size_t n, cap; /* cap: room for the text, "..." and the NUL kept */
	bool full;
};

static void put(struct line *l, const char *s, size_t n)
{
	if (l->full)
		return;
	if (l->n + n > l->cap) {
		memcpy(l->p + l->n, "...", 4);
		l->n += 3;
		l->full = true;
		return;
	}
	memcpy(l->p + l->n, s, n);
	l->n += n;
	l->p[l->n] = '\0';
}

/* Append in[0..n) with every byte a terminal would act on as \xNN:
 * C0 controls, DEL, C1 controls, bidirectional embeddings/overrides/
 * isolates, and bytes that are not UTF-8. */
static void put_escaped(struct line *l, const char *in, size_t n)
{
	const unsigned char *s = (const unsigned char *)in;

	for (size_t i = 0; i < n;) {
		unsigned long cp = 0;
		size_t k = s[i] < 0x80 ? 1 : utf8_seq(s + i, &cp);
		bool bad = s[i] < 0x20 || s[i] == 0x7f || k == 0 || i + k > n ||
			   (cp >= 0x80 && cp <= 0x9f) ||
			   (cp >= 0x202a && cp <= 0x202e) ||
			   (cp >= 0x2066 && cp <= 0x2069);

		if (bad) {
			size_t m = k && i + k <= n ? k : 1;

			for (size_t j = 0; j < m; j++) {
				char x[5];

				snprintf(x, sizeof(x), "\\x%02x", s[i + j]);
				put(l, x, 4);
			}
			i += m;
		} else {
			put(l, in + i, k);
			i += k;
		}
	}
}

/* Clean a message: escape (put_escaped) and cut quoted excerpts ('...' or
 * "...", opened after a non-alphanumeric character, closed before one)
 * longer than EXCERPT_MAX bytes. */
static void clean(struct line *l, const char *in)
{
	size_t len = strlen(in), i = 0;

	while (i < len) {
		size_t run = i, j = len;
		char q;

		/* quotes are ASCII: never inside a multibyte character */
		while (run < len && in[run] != '\'' && in[run] != '"')
			run++;
		put_escaped(l, in + i, run - i);
		if (run >= len)
			break;
		i = run;
		q = in[i];
		if (i == 0 || !isalnum((unsigned char)in[i - 1]))
			for (j = i + 1; j < len; j++)
				if (in[j] == q && !isalnum((unsigned char)in[j + 1]))
					break;
		if (j < len && j - i - 1 > EXCERPT_MAX) {
			size_t keep = EXCERPT_KEEP;
			char note[48];

			/* cut on a character boundary */
			while (keep > 0 &&
			       ((unsigned char)in[i + 1 + keep] & 0xc0) == 0x80)
				keep--;
			put(l, &q, 1);
			put_escaped(l, in + i + 1, keep);
			snprintf(note, sizeof(note), "...%c (%zu bytes)", q,
				 j - i - 1);
			put(l, note, strlen(note));
			i = j + 1;
			continue;
		}
		put(l, &q, 1);
		i++;
	}
}

/* Set while a cleanup signal is handled (output.c's handler): the other
 * threads go on meanwhile, and one that meets a file just removed must
 * neither say so nor end the process before the signal does. */
static atomic_int dying;

void ssc_set_interrupted(void)
{
	atomic_store(&dying, 1);
}

bool ssc_interrupted(void)
{
	return atomic_load(&dying) != 0;
}

/* Inside a scene file the options are keys: [input]'s (-c columns, -u
 * units, --rate, --time-column time_column, --temp-column temp_column,
 * --raw, --scale, --offset, --allow-nan allow_nan, --calibration,
 * --topic) said with their section, "--sensor" the [sensor] section, any
 * other option its analysis' key of the same name ("--run-length 2min"
 * reads "run-length = 2min"). */
static const char *input_key(const char *opt)
{
	static const char *const map[][2] = {
		{ "c", "columns" }, { "columns", "columns" }, { "column", "columns" },
		{ "u", "units" }, { "units", "units" }, { "r", "rate" },
		{ "rate", "rate" }, { "time-column", "time_column" },
		{ "temp-column", "temp_column" }, { "raw", "raw" },
		{ "scale", "scale" }, { "offset", "offset" },
		{ "allow-nan", "allow_nan" }, { "calibration", "calibration" },
		{ "topic", "topic" },
	};

	for (size_t i = 0; i < sizeof(map) / sizeof(*map); i++)
		if (!strcmp(opt, map[i][0]))
			return map[i][1];
	return NULL;
}

static bool is_value_word(const char *p, bool input)
{
	static const char *const words[] = { "or", "and", "to", "for", "with",
					     "in", "is", "on", "only", "applies" };

	/* a placeholder, a number or a path */
	if ((*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '/' ||
	    (*p == '.' && (p[1] == '/' || p[1] == '.')))
		return true;
	if (!input || !((*p >= 'a' && *p <= 'z') || *p == '/'))
		return false;
	for (size_t i = 0; i < sizeof(words) / sizeof(*words); i++) {
		size_t l = strlen(words[i]);

		if (!strncmp(p, words[i], l) && (!p[l] || strchr(" ;,)'", p[l])))
			return false;
	}
	return true;
}

static void scene_words(char *buf, size_t size)
{
	char out[MSG_MAX + 8];
	size_t o = 0;
	const char *p = buf;

	while (*p && o + 96 < sizeof(out)) {
		bool start = p == buf || strchr(" (\"", p[-1]);
		char opt[48];
		const char *key, *q = p + 2;
		size_t k = 0;

		/* what the user wrote is quoted ('...'): as written */
		if (*p == '\'' && (p == buf || strchr(" (", p[-1]))) {
			const char *end = strchr(p + 1, '\'');

			end = end ? end + 1 : p + strlen(p);
			while (p < end && o + 2 < sizeof(out))
				out[o++] = *p++;
			continue;
		}
		if (start && p[0] == '-' && p[1] == '-')
			while ((*q >= 'a' && *q <= 'z') || (*q >= '0' && *q <= '9') || *q == '-')
				q++;
		/* an option ends the word (a file "--x.csv" is a file) */
		if (start && p[0] == '-' && p[1] && strchr("cur", p[1]) &&
		    (!p[2] || strchr(" ;,)", p[2]))) {
			opt[0] = p[1];
			opt[1] = '\0';
			p += 2;
		} else if (start && p[0] == '-' && p[1] == '-' && p[2] >= 'a' && p[2] <= 'z' &&
			   (!*q || strchr(" :;,)=", *q)) && (size_t)(q - p - 2) < sizeof(opt)) {
			for (p += 2; p < q; p++)
				opt[k++] = *p;
			opt[k] = '\0';
		} else {
			out[o++] = *p++;
			continue;
		}
		key = input_key(opt);
		if (!key && !strcmp(opt, "sensor")) {
			o += (size_t)snprintf(out + o, sizeof(out) - o, "[sensor]");
			if (p[0] == ' ' && is_value_word(p + 1, false))
				/* its spec file: the section's spec key */
				for (o += (size_t)snprintf(out + o, sizeof(out) - o, " spec ="),
				     out[o++] = *p++;
				     *p && !strchr(" ;,)'", *p) && o + 16 < sizeof(out);)
					out[o++] = *p++;
			continue;
		}
		o += (size_t)snprintf(out + o, sizeof(out) - o, "%s", key ? key : opt);
		/* a placeholder or value after it: KEY = VALUE */
		if (p[0] == ' ' && is_value_word(p + 1, key != NULL)) {
			o += (size_t)snprintf(out + o, sizeof(out) - o, " =");
			for (out[o++] = *p++; *p && !strchr(" ;,)'", *p) && o + 16 < sizeof(out);)
				out[o++] = *p++;
			/* a rate's unit goes with its value */
			if (!strncmp(p, " Hz", 3) && (!p[3] || strchr(" ;,)'", p[3]))) {
				memcpy(out + o, " Hz", 3);
				o += 3;
				p += 3;
			}
		}
		if (key)
			o += (size_t)snprintf(out + o, sizeof(out) - o, " in [input]");
	}
	while (*p && o + 1 < sizeof(out))
		out[o++] = *p++;
	out[o] = '\0';
	snprintf(buf, size, "%s", out);
}

/* set while a warning is only kept (a quiet scene): made, not printed */
static bool say_silent;

/* "sensorscope: [OUTER: ][CMD: ][KIND][CTX: ]message[HINT]\n" on stderr,
 * the context and message cleaned; the message is also kept for
 * ssc_last_error(). */
static void say(const char *cmd, const char *kind, const char *ctx,
		const char *hint, const char *fmt, va_list ap)
{
	char *msg = NULL, buf[MSG_MAX + 8], cbuf[MSG_MAX + 8];
	struct line l = { buf, 0, MSG_MAX, false };
	struct line c = { cbuf, 0, MSG_MAX, false };
	const char *outer = outer_cmd && cmd && strcmp(outer_cmd, cmd) ?
				    outer_cmd : NULL;

	if (ssc_interrupted())
		return; /* the files it would name are being removed */
	buf[0] = cbuf[0] = '\0';
	if (vasprintf(&msg, fmt, ap) < 0)
		msg = NULL;
	clean(&l, msg ? msg : fmt);
	free(msg);
	/* a scene file's run (not report, whose scene is inferred): its
	 * stages and inputs are set by keys */
	if (outer_cmd && !strcmp(outer_cmd, "run"))
		scene_words(buf, sizeof(buf));
	if (ctx) {
		clean(&c, ctx);
		put(&c, ": ", 2);
	}
	snprintf(last_error, sizeof(last_error), "%s", buf);
	if (say_silent)
		return;
	fprintf(stderr, "sensorscope: %s%s%s%s%s%s%s%s\n", outer ? outer : "",
		outer ? ": " : "", cmd ? cmd : "", cmd ? ": " : "",
		kind ? kind : "", cbuf, buf, hint ? hint : "");
}

void ssc_err(const char *cmd, const char *fmt, ...)
{
	va_list ap;

	va_start(ap, fmt);
	say(cmd, NULL, NULL, NULL, fmt, ap);
	va_end(ap);
}

int ssc_err_no_rate(const char *cmd, const char *path, const char *note)
{
	ssc_err(cmd, "%s: no sample rate: %s; give --rate", path,
		note && *note ? note :
				"no time column and no '# rate:' comment");
	return SSC_EXIT_FAIL;
}

/* Warnings kept while a scene's stage runs, for its report. */
enum { KEPT_MAX = 32 };
static char kept[KEPT_MAX][MSG_MAX];
static size_t n_kept;
static bool keeping;

void ssc_warn_keep(bool on)
{
	keeping = on;
	n_kept = 0;
}

size_t ssc_warn_kept(size_t i, const char **msg)
{
	if (i < n_kept)
		*msg = kept[i];
	return n_kept;
}

void ssc_warn(const struct ssc_common *co, const char *fmt, ...)
{
	char keep[MSG_MAX];
	va_list ap;

	if (co->quiet && !keeping)
		return;
	memcpy(keep, last_error, sizeof(keep)); /* a warning is no error */
	va_start(ap, fmt);
	/* quiet: not printed, but the report keeps it (cleaned alike) */
	say_silent = co->quiet;
	say(co->cmd, "warning: ", NULL, NULL, fmt, ap);
	say_silent = false;
	va_end(ap);
	if (keeping && n_kept < KEPT_MAX)
		snprintf(kept[n_kept++], MSG_MAX, "%s", last_error);
	memcpy(last_error, keep, sizeof(keep));
}

int ssc_usage_error(const char *cmd, const char *fmt, ...)
{
	char hint[96];
	va_list ap;

	snprintf(hint, sizeof(hint), " (see 'sensorscope %s --help')", cmd);
	va_start(ap, fmt);
	say(cmd, NULL, option_context, option_context ? NULL : hint, fmt, ap);
	va_end(ap);
	return SSC_EXIT_USAGE;
}

int ssc_fail(const char *cmd, int rc, const struct sscope_diag *d,
	     const char *what)
{
	if (rc == -ENOTSUP) {
		ssc_err(cmd, "%s: %s", what, d && d->msg[0] ? d->msg :
			"feature not built into this sensorscope");
		return SSC_EXIT_USAGE;
	}
	if (d && d->msg[0])
		ssc_err(cmd, "%s", d->msg);
	else
		ssc_err(cmd, "%s: %s", what, sscope_strerror(rc));
	return SSC_EXIT_FAIL;
}
