/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Shared CLI machinery: option parsing with getopt_long over the shared
 * options plus a command's own, --help generation, progress, JSON and
 * number formatting (messages are msg.c, the loading of inputs load.c,
 * output sinks output.c).
 */
#include "workbench.h"

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "plot.h"
#ifdef HAVE_OPENCV
#include "cvload.h"
#endif

enum {
	OPT_FORMAT = 1000,
	OPT_PLOT,
	OPT_PROGRESS,
	OPT_NO_PROGRESS,
	OPT_RAW,
	OPT_SCALE,
	OPT_OFFSET,
	OPT_ALLOW_NAN,
	OPT_TIME_COLUMN,
	OPT_TEMP_COLUMN,
	OPT_HELP,
	OPT_CALIBRATION,
	OPT_TOPIC,
};

static const struct ssc_option analysis_opts[] = {
	{ "column", required_argument, 'c', "NAME|INDEX[,...]",
	  "channels to analyse (default: every data column that is not time or temperature; INDEX is 1-based)" },
	{ "rate", required_argument, 'r', "HZ",
	  "sample rate in Hz (or with a unit: 1 kHz); otherwise from the time column" },
	{ "units", required_argument, 'u', "UNIT",
	  "unit of data columns whose header names none (e.g. deg/s, g, V)" },
	{ "raw", required_argument, OPT_RAW, "TYPE:CH[:le|be]",
	  "raw binary input: TYPE i16 u16 i24 i32 u32 f32 f64, CH channels" },
	{ "scale", required_argument, OPT_SCALE, "K",
	  "raw input: physical = (raw + offset) * K" },
	{ "offset", required_argument, OPT_OFFSET, "C",
	  "raw input: offset added before scaling" },
	{ "allow-nan", no_argument, OPT_ALLOW_NAN, NULL,
	  "read NaN and empty cells as gaps instead of refusing them" },
	{ "time-column", required_argument, OPT_TIME_COLUMN, "NAME",
	  "the time column (default: a column named t, time or timestamp)" },
	{ "temp-column", required_argument, OPT_TEMP_COLUMN, "NAME",
	  "the temperature column (default: temp or temperature)" },
	{ "topic", required_argument, OPT_TOPIC, "NAME[,TEMP]",
	  "ROS bag, rosbag2 or MCAP input: the topic to read (default: the only IMU topic), and a sensor_msgs/Temperature topic for the temperature column" },
	{ "calibration", required_argument, OPT_CALIBRATION, "FILE",
	  "apply a calibration file of 'sensorscope calib' to the channels it names" },
	{ "plot", required_argument, OPT_PLOT, "PATH.svg|PATH.png",
	  "draw the command's figure (SVG; PNG needs OpenCV)" },
	{ NULL, 0, 0, NULL, NULL },
};

static const struct ssc_option output_opts[] = {
	{ "format", required_argument, OPT_FORMAT, "text|json|csv",
	  "output format (default text)" },
	{ "output", required_argument, 'o', "PATH",
	  "write the result there (default stdout): a file atomically, a FIFO or device written through, never an input" },
	{ "quiet", no_argument, 'q', NULL, "no warnings, no progress" },
	{ "progress", no_argument, OPT_PROGRESS, NULL,
	  "show progress on stderr" },
	{ "no-progress", no_argument, OPT_NO_PROGRESS, NULL,
	  "never show progress (default: only when stderr is a terminal)" },
	{ "help", no_argument, OPT_HELP, NULL, "show this help" },
	{ NULL, 0, 0, NULL, NULL },
};

int ssc_arg_double(const char *cmd, const char *opt, const char *arg,
		   double *out)
{
	double v;
	size_t n = ssc_parse_double(arg, arg + strlen(arg), &v);

	if (!*arg || n != strlen(arg) || !isfinite(v))
		return ssc_usage_error(cmd, "--%s: '%s' is not a number", opt,
				       arg);
	*out = v;
	return 0;
}

int ssc_arg_size(const char *cmd, const char *opt, const char *arg,
		 size_t *out)
{
	char *end;
	unsigned long long v;

	errno = 0;
	if (*arg == '-' || !*arg)
		goto bad;
	v = strtoull(arg, &end, 10);
	if (*end || errno || v > SIZE_MAX)
		goto bad;
	*out = (size_t)v;
	return 0;
bad:
	return ssc_usage_error(cmd, "--%s: '%s' is not a non-negative integer",
			       opt, arg);
}

int ssc_arg_positive(const char *cmd, const char *opt, const char *arg,
		     const char *si, double *out)
{
	if (si ? ssc_arg_quantity(cmd, opt, arg, si, out) :
		 ssc_arg_double(cmd, opt, arg, out))
		return SSC_EXIT_USAGE;
	return *out > 0 ? 0 : ssc_usage_error(cmd, "--%s: must be positive", opt);
}

/* Bare numbers read in an SI unit nobody in the field writes (a random
 * walk in rad/sqrt(s), a bias in rad/s): said once the options are read
 * (-q may come later), with the value in the field's unit. */
#define BARE_MAX 8
static const struct {
	const char *si, *shown;
} field_units[] = {
	{ "rad/sqrt(s)", "deg/sqrt(h)" },
	{ "rad/s/sqrt(Hz)", "deg/sqrt(h)" },
	{ "rad/s", "deg/h" },
	{ "rad/s^2/sqrt(Hz)", "deg/h/sqrt(h)" },
	{ "rad/s^2", "deg/h/h" },
	{ "m/s/sqrt(s)", "m/s/sqrt(h)" },
	{ "m/s^2/sqrt(Hz)", "m/s/sqrt(h)" },
	{ "m/s^3/sqrt(Hz)", "ug/sqrt(h)" },
	{ "rad", "deg" },
};

static struct {
	char opt[32], arg[48];
	size_t unit; /* in field_units */
	double v;
} bare_given[BARE_MAX];
static size_t n_bare;

static void note_bare(const char *opt, const char *arg, const char *si,
		      double v)
{
	size_t i = 0, nu = sizeof(field_units) / sizeof(field_units[0]);

	while (i < nu && strcmp(si, field_units[i].si))
		i++;
	if (i == nu || n_bare >= BARE_MAX)
		return;
	snprintf(bare_given[n_bare].opt, sizeof(bare_given[n_bare].opt), "%s", opt);
	snprintf(bare_given[n_bare].arg, sizeof(bare_given[n_bare].arg), "%s", arg);
	bare_given[n_bare].unit = i;
	bare_given[n_bare++].v = v;
}

/* a scene checks its stages' options once before running them: said
 * then only once, when they run */
static bool bare_silent;

void ssc_bare_numbers_silent(bool on)
{
	bare_silent = on;
}

void ssc_say_bare_numbers(const struct ssc_common *co)
{
	if (bare_silent) {
		n_bare = 0;
		return;
	}
	for (size_t k = 0; k < n_bare; k++) {
		const char *opt = bare_given[k].opt, *arg = bare_given[k].arg;
		const char *si = field_units[bare_given[k].unit].si;
		const char *shown = field_units[bare_given[k].unit].shown;
		struct sscope_unit u;
		double v;

		if (sscope_unit_parse(shown, &u, NULL))
			continue;
		v = sscope_unit_from_si(&u, bare_given[k].v);
		if (isfinite(v))
			ssc_warn(co, "--%s %s has no unit: read as %s %s, that is %.4g %s (write the unit, as in '%s %s')",
				 opt, arg, arg, si, v, shown, arg, shown);
		else
			ssc_warn(co, "--%s %s has no unit: read as %s %s (write the unit, as in '%s %s')",
				 opt, arg, arg, si, arg, shown);
	}
	n_bare = 0;
}

json_t *ssc_json_read(const char *cmd, const char *opt, const char *path,
		      const char *what)
{
	char where[96] = "";
	json_error_t je;
	json_t *root;
	FILE *f;

	if (opt)
		snprintf(where, sizeof(where), "--%s: ", opt);
	/* '-': standard input, as for captures */
	f = strcmp(path, "-") ? fopen(path, "rb") : stdin;
	if (!f) {
		ssc_err(cmd, "%s%s: %s", where, path, sscope_strerror(-errno));
		return NULL;
	}
	root = json_loadf(f, 0, &je);
	if (!root && ferror(f)) /* a directory opens, then fails to read */
		ssc_err(cmd, "%s%s: %s", where, path, sscope_strerror(-EISDIR));
	else if (!root)
		ssc_err(cmd, "%s%s: not %s (JSON error at line %d: %s)", where,
			path, what, je.line, je.text);
	if (f != stdin)
		fclose(f);
	return root;
}

int ssc_arg_gravity(const char *cmd, const char *arg, double *out)
{
	if (ssc_arg_positive(cmd, "gravity", arg, "m/s^2", out))
		return SSC_EXIT_USAGE;
	if (*out < 1 || *out > 30)
		return ssc_usage_error(cmd, "--gravity: %g m/s^2 is not a local gravity (1 to 30 m/s^2; 9.78 to 9.83 on Earth)",
				       *out);
	return 0;
}

int ssc_arg_quantity(const char *cmd, const char *opt, const char *arg,
		     const char *si, double *out)
{
	struct sscope_unit u, target;
	struct sscope_diag d = { "" };
	double v;

	if (sscope_quantity_parse(arg, &v, &u, &d))
		return ssc_usage_error(cmd, "--%s: %s", opt, d.msg);
	sscope_unit_parse(si, &target, NULL);
	if (sscope_unit_quantity(&u) != SSCOPE_QUANTITY_DIMENSIONLESS &&
	    !sscope_unit_compatible(&u, &target))
		return ssc_usage_error(cmd, "--%s: '%s' is not in units of %s",
				       opt, arg, si);
	if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS &&
	    u.scale == 1) {
		v = sscope_unit_to_si(&target, v); /* bare number: SI */
		if (v != 0)
			note_bare(opt, arg, si, v);
	}
	*out = v;
	return 0;
}

/* index of --help in output_opts: commands without output options get only
 * that one */
#define OUT_HELP_ONLY 5

static void print_opts(const struct ssc_option *o)
{
	for (; o && o->name; o++) {
		char left[64];
		int n;

		if (o->key > 0 && o->key < 128)
			n = snprintf(left, sizeof(left), "-%c, --%s", o->key,
				     o->name);
		else
			n = snprintf(left, sizeof(left), "    --%s", o->name);
		if (o->arg && n > 0 && (size_t)n < sizeof(left))
			snprintf(left + n, sizeof(left) - (size_t)n, " %s",
				 o->arg);
		if (strlen(left) > 28)
			printf("  %s\n  %-28s %s\n", left, "", o->help);
		else
			printf("  %-28s %s\n", left, o->help);
	}
}

static void print_help(const struct ssc_command_spec *spec)
{
	printf("Usage: sensorscope %s\n\n%s\n", spec->usage, spec->summary);
	if (spec->options && spec->options->name) {
		printf("\nOptions:\n");
		print_opts(spec->options);
	}
	if (spec->analysis) {
		printf("\nInput options:\n");
		for (const struct ssc_option *o = analysis_opts; o->name; o++) {
			struct ssc_option one[2] = { *o, { NULL, 0, 0, NULL, NULL } };

			/* a report draws every figure itself */
			if (o->key != OPT_PLOT ||
			    !(spec->output_dir || spec->no_plot))
				print_opts(one);
		}
	}
	printf("\nOutput options:\n");
	if (spec->analysis || spec->output_opts) {
		/* --format and -o as this command takes them */
		for (const struct ssc_option *o = output_opts; o->name; o++) {
			struct ssc_option one[2] = { *o, { NULL, 0, 0, NULL, NULL } };

			if (o->key == OPT_FORMAT && spec->output_dir)
				continue;
			if (o->key == OPT_FORMAT && spec->no_csv)
				one[0].arg = "text|json";
			if (o->key == 'o' && spec->output_dir) {
				one[0].arg = "DIR";
				one[0].help = "the report folder (replaces the scene's output): built beside it and put in place when every stage succeeded; missing parent folders are created";
			}
			print_opts(one);
		}
	} else {
		print_opts(output_opts + OUT_HELP_ONLY); /* --help only */
	}
	if (spec->notes)
		printf("\n%s\n", spec->notes);
	/* once: a command that explains its own codes says it in its notes */
	if (!spec->notes || !strstr(spec->notes, "Exit status:"))
		printf("\nExit status: 0 success, 1 runtime or data error, 2 usage error or feature not built.\n");
}

static size_t count_opts(const struct ssc_option *o)
{
	size_t n = 0;

	while (o && o[n].name)
		n++;
	return n;
}

static void add_opts(struct option *lo, size_t *nl, char *so, size_t *ns,
		     const struct ssc_option *o)
{
	for (; o && o->name; o++) {
		lo[*nl].name = o->name;
		lo[*nl].has_arg = o->has_arg;
		lo[*nl].flag = NULL;
		lo[*nl].val = o->key;
		(*nl)++;
		if (o->key > 0 && o->key < 128) {
			so[(*ns)++] = (char)o->key;
			if (o->has_arg == required_argument)
				so[(*ns)++] = ':';
		}
	}
}

int ssc_parse(const struct ssc_command_spec *spec, int argc, char **argv,
	      struct ssc_common *co,
	      int (*handler)(int key, const char *arg, void *ctx), void *ctx,
	      int *first)
{
	return ssc_parse_where(spec, argc, argv, NULL, co, handler, ctx, first);
}

int ssc_parse_where(const struct ssc_command_spec *spec, int argc, char **argv,
		    const char *const *where, struct ssc_common *co,
		    int (*handler)(int key, const char *arg, void *ctx),
		    void *ctx, int *first)
{
	size_t n = count_opts(spec->options) + count_opts(analysis_opts) +
		   count_opts(output_opts) + 1;
	struct option *lo = calloc(n, sizeof(*lo));
	char *so = calloc(3 * n + 2, 1);
	/* every path the command line names, compared before anything is
	 * written */
	struct ssc_guard_item *paths = calloc((size_t)argc + 1, sizeof(*paths));
	size_t nl = 0, ns = 0, np = 0;
	bool to_stdout = !spec->output_dir, raw_scaled = false;
	int c, rc = SSC_EXIT_OK;

	memset(co, 0, sizeof(*co));
	co->cmd = spec->name;
	co->progress = -1;
	co->scale = 1;
	if (!lo || !so || !paths) {
		free(lo);
		free(so);
		free(paths);
		ssc_err(spec->name, "out of memory");
		return SSC_EXIT_FAIL;
	}
	add_opts(lo, &nl, so, &ns, spec->options);
	if (spec->analysis)
		add_opts(lo, &nl, so, &ns, analysis_opts);
	if (spec->analysis || spec->output_opts)
		add_opts(lo, &nl, so, &ns, output_opts);
	else
		add_opts(lo, &nl, so, &ns, output_opts + OUT_HELP_ONLY);
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, so, lo, NULL)) != -1) {
		if (optarg && c != '?' && c != ':' && np < (size_t)argc) {
			const char *what = NULL;

			for (size_t i = 0; i < nl && !what; i++)
				if (lo[i].val == c)
					what = ssc_output_option(lo[i].name);
			paths[np].what = what;
			paths[np].path = optarg;
			paths[np].role = !what ? SSC_GUARD_IN :
					 c == 'o' && spec->output_dir ? SSC_GUARD_DIR :
									SSC_GUARD_OUT;
			if (c == 'o')
				to_stdout = !spec->output_dir && !strcmp(optarg, "-");
			np++;
		}
		switch (c) {
		case OPT_HELP:
			print_help(spec);
			rc = -1;
			goto out;
		case '?':
			if (optopt && optopt < 128 && optopt > 0)
				rc = ssc_usage_error(spec->name,
						     "unknown option or missing argument: -%c",
						     optopt);
			else
				rc = ssc_usage_error(spec->name,
						     "unknown option or missing argument: %s",
						     argv[optind - 1]);
			goto out;
		case 'c':
			if (!spec->analysis)
				goto own;
			co->columns = optarg;
			break;
		case 'r':
			if (!spec->analysis)
				goto own;
			/* in Hz, or with a unit (10Hz, 1 kHz), as a scene's rate */
			rc = ssc_arg_quantity(co->cmd, "rate", optarg, "Hz", &co->rate_hz);
			/* a bare number is Hz; '10 %' is not a rate */
			if (!rc) {
				struct sscope_unit ru;
				double rv;

				if (!sscope_quantity_parse(optarg, &rv, &ru, NULL) &&
				    sscope_unit_quantity(&ru) == SSCOPE_QUANTITY_DIMENSIONLESS &&
				    ru.scale != 1)
					rc = ssc_usage_error(co->cmd, "--rate: '%s' is not in units of Hz",
							     optarg);
			}
			if (!rc && !(co->rate_hz > 0 && isfinite(co->rate_hz)))
				rc = ssc_usage_error(co->cmd,
						     "--rate: must be positive");
			if (rc)
				goto out;
			break;
		case 'u':
			if (!spec->analysis)
				goto own;
			co->units = optarg;
			{
				struct sscope_unit u;
				struct sscope_diag d = { "" };

				if (sscope_unit_parse(optarg, &u, &d)) {
					rc = ssc_usage_error(co->cmd, "-u: %s", d.msg);
					goto out;
				}
			}
			break;
		case 'o':
			if (!spec->analysis && !spec->output_opts)
				goto own;
			co->output = optarg;
			break;
		case 'q':
			if (!spec->analysis && !spec->output_opts)
				goto own;
			co->quiet = true;
			co->progress = 0;
			break;
		case OPT_FORMAT:
			if (!strcmp(optarg, "text"))
				co->format = SSC_FMT_TEXT;
			else if (!strcmp(optarg, "json"))
				co->format = SSC_FMT_JSON;
			else if (!strcmp(optarg, "csv"))
				co->format = SSC_FMT_CSV;
			else {
				rc = ssc_usage_error(co->cmd,
						     "--format: '%s' is not text, json or csv",
						     optarg);
				goto out;
			}
			break;
		case OPT_PLOT:
			co->plot = optarg;
			break;
		case OPT_PROGRESS:
			co->progress = 1;
			break;
		case OPT_NO_PROGRESS:
			co->progress = 0;
			break;
		case OPT_RAW: {
			struct sscope_diag d = { "" };

			if (sscope_reader_raw_layout_check(optarg, NULL, NULL, &d)) {
				rc = ssc_usage_error(co->cmd, "--raw: %s", d.msg);
				goto out;
			}
			co->raw = optarg;
			break;
		}
		case OPT_SCALE:
			raw_scaled = true;
			rc = ssc_arg_double(co->cmd, "scale", optarg, &co->scale);
			if (!rc && co->scale == 0)
				rc = ssc_usage_error(co->cmd, "--scale: must not be 0");
			if (rc)
				goto out;
			break;
		case OPT_OFFSET:
			raw_scaled = true;
			rc = ssc_arg_double(co->cmd, "offset", optarg, &co->offset);
			if (rc)
				goto out;
			break;
		case OPT_ALLOW_NAN:
			co->allow_nan = true;
			break;
		case OPT_TIME_COLUMN:
			co->time_column = optarg;
			break;
		case OPT_TEMP_COLUMN:
			co->temp_column = optarg;
			break;
		case OPT_CALIBRATION:
			co->calibration = optarg;
			break;
		case OPT_TOPIC:
			co->topic = optarg;
			break;
		default:
		own:
			if (!handler) {
				rc = ssc_usage_error(spec->name, "unexpected option");
				goto out;
			}
			/* a scene writes one "--key=value" per key: its line
			 * is where argv[optind - 1] came from */
			if (where && optind >= 1 && where[optind - 1])
				ssc_set_context(where[optind - 1]);
			rc = handler(c, optarg, ctx);
			if (where)
				ssc_set_context(NULL);
			if (rc)
				goto out;
			break;
		}
	}
	if (co->plot) {
		rc = ssc_plot_check(co->cmd, co->plot);
		if (rc)
			goto out;
	}
	if (raw_scaled && !co->raw) {
		rc = ssc_usage_error(co->cmd, "--scale and --offset apply to --raw input only");
		goto out;
	}
	for (int i = optind; i < argc && np < (size_t)argc; i++)
		paths[np++] = (struct ssc_guard_item){ NULL, argv[i], SSC_GUARD_IN };
	rc = ssc_guard_check(co->cmd, paths, np, to_stdout);
	if (rc)
		goto out;
	/* a file to write in a folder that does not exist: said before any
	 * work, so that no other output is left written (a scene's report
	 * folder, made later, is checked by the scene) */
	for (size_t i = 0; i < np && !where && !rc; i++) {
		const char *sl = paths[i].role == SSC_GUARD_OUT &&
				 strcmp(paths[i].path, "-") ? strrchr(paths[i].path, '/') : NULL;
		char dir[4096];
		struct stat st;

		if (!sl || sl == paths[i].path)
			continue;
		snprintf(dir, sizeof(dir), "%.*s", (int)(sl - paths[i].path), paths[i].path);
		if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
			ssc_err(co->cmd, "%s %s: no folder %s to write it in", paths[i].what,
				paths[i].path, dir);
			rc = SSC_EXIT_FAIL;
		}
	}
	if (rc)
		goto out;
	ssc_say_bare_numbers(co);
	*first = optind;
out:
	n_bare = 0;
	free(lo);
	free(so);
	free(paths);
	return rc;
}

bool ssc_progress_on(const struct ssc_common *co)
{
	if (co->quiet || co->progress == 0)
		return false;
	if (co->progress == 1)
		return true;
	return isatty(STDERR_FILENO);
}

void ssc_progress(const struct ssc_common *co, const char *label, double done,
		  double total)
{
	if (!ssc_progress_on(co))
		return;
	if (total > 0)
		fprintf(stderr, "\r%s: %3.0f%% (%.1f of %.1f MB)   ", label,
			100 * done / total, done / 1e6, total / 1e6);
	else
		fprintf(stderr, "\r%s: %.1f MB   ", label, done / 1e6);
	fflush(stderr);
}

void ssc_progress_end(const struct ssc_common *co)
{
	if (ssc_progress_on(co)) {
		fprintf(stderr, "\r%60s\r", "");
		fflush(stderr);
	}
}

json_t *ssc_jreal(double v)
{
	return isfinite(v) ? json_real(v) : json_null();
}

int ssc_emit_json(const struct ssc_common *co, json_t *root)
{
	struct ssc_out out;
	int rc;
	bool ok;

	if (!root) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	rc = ssc_out_open(co, &out);
	if (rc) {
		json_decref(root);
		return rc;
	}
	ok = json_dumpf(root, out.f, JSON_REAL_PRECISION(15) | JSON_COMPACT) == 0;
	if (ok)
		fputc('\n', out.f);
	json_decref(root);
	return ssc_out_close(co, &out, ok);
}

/* jansson's fix-ups of a "%.15g" text of n characters in buf */
static size_t jansson_fixup(char *buf, size_t n)
{
	char *e = memchr(buf, 'e', n);

	if (!e) {
		if (!memchr(buf, '.', n)) {
			memcpy(buf + n, ".0", 3);
			n += 2;
		}
		return n;
	}
	{
		char *d = e + 1, *s = e + 1;

		if (*s == '+')
			s++;
		else if (*s == '-')
			*d++ = *s++;
		while (*s == '0' && s[1])
			s++;
		while (*s)
			*d++ = *s++;
		*d = '\0';
		return (size_t)(d - buf);
	}
}

#if LDBL_MANT_DIG == 64
/*
 * The 15 significant digits of |v| as "%.15g" rounds them, from one
 * product or quotient in 64-bit long double (10^k is exact for |k| <= 27,
 * so the scaled value carries one rounding, below 1e-4 in units of the
 * last digit): taken only when it is farther than 1e-3 units from a
 * rounding tie, else (and out of range) false and snprintf decides.
 */
static bool digits15(double v, char *dig, int *e10)
{
	static const long double p10[28] = {
		1e0L,  1e1L,  1e2L,  1e3L,  1e4L,  1e5L,  1e6L,  1e7L,
		1e8L,  1e9L,  1e10L, 1e11L, 1e12L, 1e13L, 1e14L, 1e15L,
		1e16L, 1e17L, 1e18L, 1e19L, 1e20L, 1e21L, 1e22L, 1e23L,
		1e24L, 1e25L, 1e26L, 1e27L
	};
	long double y, f;
	unsigned long long D;
	int e, k;

	if (!(v > 0) || !isfinite(v))
		return false;
	e = (int)floor(log10(v));
	for (int tries = 0; tries < 2; tries++) {
		k = 14 - e;
		if (k < -27 || k > 27)
			return false;
		y = k >= 0 ? (long double)v * p10[k] : (long double)v / p10[-k];
		if (y < 1e14L)
			e--;
		else if (y >= 1e15L)
			e++;
		else
			break;
	}
	if (!(y >= 1e14L && y < 1e15L))
		return false;
	f = y - floorl(y);
	if (fabsl(f - 0.5L) < 1e-3L)
		return false;
	D = (unsigned long long)floorl(y) + (f > 0.5L);
	if (D == 1000000000000000ULL) {
		D = 100000000000000ULL;
		e++;
	}
	for (int i = 14; i >= 0; i--) {
		dig[i] = (char)('0' + D % 10);
		D /= 10;
	}
	*e10 = e;
	return true;
}
#endif

size_t ssc_json_real_text(char *buf, double v)
{
#if LDBL_MANT_DIG == 64
	char dig[15], *p = buf;
	int e, nd = 15;

	if (isfinite(v) && digits15(fabs(v), dig, &e)) {
		while (nd > 1 && dig[nd - 1] == '0')
			nd--;
		if (v < 0)
			*p++ = '-';
		if (e >= -4 && e < 15) {
			/* "%.15g" fixed: the digits around the point, trailing
			 * zeros of the fraction dropped; jansson adds ".0" */
			if (e < 0) {
				*p++ = '0';
				*p++ = '.';
				for (int i = -1; i > e; i--)
					*p++ = '0';
				memcpy(p, dig, (size_t)nd);
				p += nd;
			} else {
				memcpy(p, dig, (size_t)e + 1);
				p += e + 1;
				*p++ = '.';
				if (nd > e + 1) {
					memcpy(p, dig + e + 1, (size_t)(nd - e - 1));
					p += nd - e - 1;
				} else {
					*p++ = '0';
				}
			}
		} else {
			/* exponential, the exponent as jansson leaves it */
			int a = e < 0 ? -e : e;
			char ex[8];
			int ne = 0;

			*p++ = dig[0];
			if (nd > 1) {
				*p++ = '.';
				memcpy(p, dig + 1, (size_t)nd - 1);
				p += nd - 1;
			}
			*p++ = 'e';
			if (e < 0)
				*p++ = '-';
			do {
				ex[ne++] = (char)('0' + a % 10);
				a /= 10;
			} while (a);
			while (ne)
				*p++ = ex[--ne];
		}
		*p = '\0';
		return (size_t)(p - buf);
	}
#endif
	if (!isfinite(v)) {
		memcpy(buf, "null", 5);
		return 4;
	}
	/* jansson's real: "%.15g" (JSON_REAL_PRECISION(15)), ".0" when the
	 * text has neither '.' nor 'e', the exponent without '+' and
	 * without leading zeros */
	return jansson_fixup(buf, (size_t)snprintf(buf, SSC_JSON_REAL_MAX,
						   "%.15g", v));
}

/* the text a slot's placeholder dumps as */
#define SLOT_FMT "\x1fssc-slot-%zu\x1f"
#define SLOT_DUMPED "\"\\u001Fssc-slot-%zu\\u001F\""

json_t *ssc_json_slot(size_t k)
{
	char b[48];

	snprintf(b, sizeof(b), SLOT_FMT, k);
	return json_string(b);
}

int ssc_emit_json_slots(const struct ssc_common *co, json_t *root,
			size_t n_slots,
			bool (*fill)(FILE *f, size_t k, void *ctx), void *ctx)
{
	struct ssc_out out;
	char *text, **at = NULL;
	size_t len;
	int rc;
	bool ok = true;

	if (!root) {
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	text = json_dumps(root, JSON_REAL_PRECISION(15) | JSON_COMPACT);
	json_decref(root);
	at = calloc(n_slots ? n_slots : 1, sizeof(*at));
	if (!text || !at) {
		free(text);
		free(at);
		ssc_err(co->cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	len = strlen(text);
	/* each placeholder exactly once, in order (a user's string that
	 * spells one is not a slot: then the caller dumps the whole tree) */
	for (size_t k = 0; k < n_slots; k++) {
		char m[64], *p;
		size_t ml = (size_t)snprintf(m, sizeof(m), SLOT_DUMPED, k);

		p = memmem(text, len, m, ml);
		if (!p || memmem(p + 1, len - (size_t)(p + 1 - text), m, ml) ||
		    (k && p < at[k - 1])) {
			free(text);
			free(at);
			return -EAGAIN;
		}
		at[k] = p;
	}
	rc = ssc_out_open(co, &out);
	if (rc) {
		free(text);
		free(at);
		return rc;
	}
	{
		const char *from = text;

		for (size_t k = 0; k < n_slots && ok; k++) {
			char m[64];
			size_t ml = (size_t)snprintf(m, sizeof(m), SLOT_DUMPED, k);

			ok = fwrite(from, 1, (size_t)(at[k] - from), out.f) ==
				     (size_t)(at[k] - from) &&
			     fill(out.f, k, ctx);
			from = at[k] + ml;
		}
		if (ok) {
			size_t rest = len - (size_t)(from - text);

			ok = fwrite(from, 1, rest, out.f) == rest &&
			     fputc('\n', out.f) != EOF;
		}
	}
	free(text);
	free(at);
	return ssc_out_close(co, &out, ok);
}

const char *ssc_fmt_p(char *buf, size_t len, double p)
{
	char v[32];

	if (!(p >= 0))
		snprintf(buf, len, "not computed");
	else if (sscope_noise_p_is_bound(p))
		snprintf(buf, len, "< 0.001");
	else
		snprintf(buf, len, "= %s", ssc_fmt(v, sizeof(v), p, 2));
	return buf;
}

const char *ssc_fmt(char *buf, size_t len, double v, int sig)
{
	double a = fabs(v);

	if (!isfinite(v))
		snprintf(buf, len, "%s", isnan(v) ? "nan" : v > 0 ? "inf" : "-inf");
	else if (v == 0)
		snprintf(buf, len, "0");
	else if (a >= 1e-4 && a < 1e7) {
		/* fixed notation with sig significant digits, trailing zeros
		 * of the fraction dropped */
		int d = sig - 1 - (int)floor(log10(a));
		char *dot, *e;

		snprintf(buf, len, "%.*f", d > 0 ? d : 0, v);
		dot = strchr(buf, '.');
		if (dot) {
			e = buf + strlen(buf);
			while (e > dot + 1 && e[-1] == '0')
				*--e = '\0';
			if (e == dot + 1)
				*dot = '\0';
		}
	}
	else
		snprintf(buf, len, "%.*e", sig - 1, v);
	return buf;
}

bool ssc_plot_available(void)
{
#ifdef HAVE_OPENCV
	return ssc_cv_load(NULL, 0) == 0;
#else
	return false;
#endif
}

bool ssc_plot_installed(void)
{
#ifdef HAVE_OPENCV
	return ssc_cv_installed();
#else
	return false;
#endif
}

int ssc_plot_unavailable(const char *cmd)
{
#ifdef HAVE_OPENCV
	char why[512];

	if (ssc_cv_load(why, sizeof(why))) {
		ssc_err(cmd, "--plot: cannot load the drawing module: %s", why);
		return SSC_EXIT_USAGE;
	}
#endif
	ssc_err(cmd, "--plot: this sensorscope was built without OpenCV; "
		"write an SVG figure (PATH.svg) or rebuild with OpenCV "
		"(Debian: libopencv-dev) for PNG plots");
	return SSC_EXIT_USAGE;
}

int ssc_plot_check(const char *cmd, const char *path)
{
	switch (ssc_plot_format_of(path)) {
	case SSC_PLOT_SVG:
		return 0;
	case SSC_PLOT_PNG:
		return ssc_plot_available() ? 0 : ssc_plot_unavailable(cmd);
	default:
		return ssc_usage_error(cmd, "--plot: '%s' must end in .png or .svg",
				       path);
	}
}

json_t *ssc_json_coef(double si, double si_lo, double si_hi, const char *unit,
		      const char *si_unit, bool fitted)
{
	json_t *o = json_object();
	double v = si, lo = si_lo, hi = si_hi;

	if (unit && si_unit && sscope_unit_convert_text(si, si_unit, unit, &v) == 0) {
		if (sscope_unit_convert_text(si_lo, si_unit, unit, &lo))
			lo = NAN;
		if (sscope_unit_convert_text(si_hi, si_unit, unit, &hi))
			hi = NAN;
	} else {
		unit = si_unit;
	}
	json_object_set_new(o, "value", ssc_jreal(v));
	json_object_set_new(o, "unit", json_string(unit ? unit : ""));
	json_object_set_new(o, "lo", ssc_jreal(lo));
	json_object_set_new(o, "hi", ssc_jreal(hi));
	json_object_set_new(o, "si", ssc_jreal(si));
	json_object_set_new(o, "si_unit", json_string(si_unit ? si_unit : ""));
	json_object_set_new(o, "fitted", json_boolean(fitted));
	return o;
}

void ssc_unit_pretty(const char *in, char *out, size_t len)
{
	static const char *const from[] = { "deg", "sqrt(Hz)", "sqrt(h)",
					    "ug", "^2", "^3", "*", NULL };
	static const char *const to[] = { "\xc2\xb0", "\xe2\x88\x9aHz",
					  "\xe2\x88\x9ah", "\xc2\xb5g",
					  "\xc2\xb2", "\xc2\xb3", "\xc2\xb7" };
	size_t o = 0;

	while (*in && o + 8 < len) {
		int i;

		for (i = 0; from[i]; i++)
			if (!strncmp(in, from[i], strlen(from[i])))
				break;
		if (from[i]) {
			size_t l = strlen(to[i]);

			memcpy(out + o, to[i], l);
			o += l;
			in += strlen(from[i]);
		} else {
			out[o++] = *in++;
		}
	}
	out[o] = '\0';
}

void ssc_json_warn(json_t *obj, const char *code, const char *fmt, ...)
{
	json_t *arr = json_object_get(obj, "warnings"), *w;
	char msg[1024];
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	if (!json_is_array(arr)) {
		arr = json_array();
		json_object_set_new(obj, "warnings", arr);
	}
	w = json_object();
	json_object_set_new(w, "code", json_string(code));
	json_object_set_new(w, "message", json_string(msg));
	json_array_append_new(arr, w);
}

int ssc_load_sensor(const char *cmd, const char *path,
		    struct sscope_sensor_spec *spec)
{
	struct sscope_diag d = { "" };
	int rc = sscope_sensor_spec_load(path, spec, &d);

	if (rc)
		return ssc_fail(cmd, rc, &d, path);
	return SSC_EXIT_OK;
}

/* Interval tables ("START END V1 ... Vn" per line, comma or blanks, '#'
 * comments): times in s unless a unit says otherwise; values in `si`
 * unless a unit says otherwise, bare values in `bare` (NULL: si). */
int ssc_read_intervals(const struct ssc_common *co, const char *opt,
		       const char *path, const char *head, size_t nval,
		       const char *si, const char *bare, double **out,
		       size_t *n_rows)
{
	FILE *f = fopen(path, "r");
	char line[512];
	size_t n = 0, cap = 0, ln = 0, w = 2 + nval;
	double *v = NULL;
	struct sscope_unit target, bare_u;

	*out = NULL;
	*n_rows = 0;
	if (!f) {
		ssc_err(co->cmd, "--%s: %s: %s", opt, path, sscope_strerror(errno));
		return SSC_EXIT_FAIL;
	}
	if (w > 8) {
		fclose(f);
		return SSC_EXIT_FAIL;
	}
	sscope_unit_parse(si, &target, NULL);
	sscope_unit_parse(bare ? bare : si, &bare_u, NULL);
	while (fgets(line, sizeof(line), f)) {
		char *tok[8], *save = NULL, *p;
		size_t k = 0;
		double x[8];

		ln++;
		if ((p = strchr(line, '#')))
			*p = 0;
		for (p = strtok_r(line, ", \t\r\n", &save); p && k <= w;
		     p = strtok_r(NULL, ", \t\r\n", &save))
			if (k < w)
				tok[k++] = p;
			else
				k = w + 1;
		if (k == 0)
			continue;
		if (k != w)
			goto bad;
		for (size_t j = 0; j < w; j++) {
			struct sscope_unit u;

			if (sscope_quantity_parse(tok[j], &x[j], &u, NULL) ||
			    !isfinite(x[j]))
				goto bad;
			if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS &&
			    u.scale == 1) {
				if (j >= 2) /* bare value */
					x[j] = sscope_unit_to_si(&bare_u, x[j]);
				continue;
			}
			if (j < 2 ? sscope_unit_quantity(&u) != SSCOPE_QUANTITY_TIME :
				    !sscope_unit_compatible(&u, &target))
				goto bad;
		}
		if (!(x[1] > x[0]))
			goto bad;
		if (n + w > cap) {
			double *nv;

			cap = cap ? 2 * cap : 32 * w;
			nv = realloc(v, cap * sizeof(double));
			if (!nv)
				goto bad;
			v = nv;
		}
		memcpy(v + n, x, w * sizeof(double));
		n += w;
	}
	fclose(f);
	if (n == 0) {
		free(v);
		ssc_err(co->cmd, "--%s: %s: no intervals", opt, path);
		return SSC_EXIT_FAIL;
	}
	*out = v;
	*n_rows = n / w;
	return SSC_EXIT_OK;
bad:
	fclose(f);
	free(v);
	ssc_err(co->cmd, "--%s: %s:%zu: want 'START END %s' (times in s, values in %s or with a unit)",
		opt, path, ln, head, bare ? bare : si);
	return SSC_EXIT_FAIL;
}
