/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The workbench (src/workbench/): what every command and every scene
 * shares -- option parsing, loading of inputs, output sinks (atomic files,
 * stdout), messages and exit codes.  It may include the library
 * (sensorscope.h), src/acq/ and src/figure/; never src/cli/.
 */
#ifndef SSCOPE_WORKBENCH_H
#define SSCOPE_WORKBENCH_H

#include "config.h"

#include <errno.h>
#include <getopt.h>
#include <stdbool.h>
#include <stdio.h>

#include <jansson.h>

#include "sensorscope.h"
#include "ssc.h"

/* Exit codes (documented in --help, the README and the man page). */
enum {
	SSC_EXIT_OK = 0,    /* success */
	SSC_EXIT_FAIL = 1,  /* runtime or data error */
	SSC_EXIT_USAGE = 2, /* usage error, or feature not built */
};

enum ssc_format { SSC_FMT_TEXT = 0, SSC_FMT_JSON, SSC_FMT_CSV };

/* Options shared by every analysis command (CONTRACT.md). */
struct ssc_common {
	const char *cmd;       /* command name for messages */
	const char *columns;   /* -c */
	double rate_hz;        /* -r, 0 when not given */
	const char *units;     /* -u */
	enum ssc_format format;
	const char *output;    /* -o, NULL for stdout */
	const char *plot;      /* --plot PATH.png */
	int progress;          /* -1 auto (terminal), 0 off, 1 on */
	bool quiet;
	const char *raw;       /* --raw TYPE:CH[:le|be] */
	double scale;          /* --scale */
	double offset;         /* --offset */
	bool allow_nan;        /* --allow-nan */
	const char *time_column;
	const char *temp_column;
	const char *calibration; /* --calibration FILE, applied by ssc_load */
	const char *topic;     /* --topic NAME[,TEMPERATURE] of a ROS bag/MCAP */
	/* set by the stage runner: the stage's analysis rejects NaN and
	 * infinite samples itself, so ssc_load need not check a file used
	 * in place (ssc_check_values reports as the reader would) */
	bool values_in_run;
};

/* A command-specific option: getopt_long entry plus help text. */
struct ssc_option {
	const char *name;  /* long name */
	int has_arg;       /* no_argument / required_argument */
	int key;           /* value passed to the handler (>= 256 or a short
			      option character) */
	const char *arg;   /* argument name for help, e.g. "HZ" */
	const char *help;  /* one line */
};

/* Description of a command for parsing and --help. */
struct ssc_command_spec {
	const char *name;     /* "allan" */
	const char *usage;    /* "allan [OPTIONS] FILE..." */
	const char *summary;  /* one paragraph */
	const struct ssc_option *options; /* NULL-name terminated, or NULL */
	bool analysis;        /* accepts the shared analysis options */
	bool output_opts;     /* accepts --format/-o (non-analysis commands) */
	bool output_dir;      /* -o names a folder replaced as a whole */
	bool no_csv;          /* --format is text or json only */
	bool no_plot;         /* draws no figure (--plot refused) */
	const char *notes;    /* extra help text after the options, or NULL */
};

/*
 * Parse argv for a command.  Shared options go into *co; others are passed
 * to handler(key, optarg, ctx), which returns 0 or SSC_EXIT_USAGE (after
 * printing a message with ssc_usage_error).  On return *first is the index
 * of the first operand.
 * Returns SSC_EXIT_OK, SSC_EXIT_USAGE, or -1 when --help was printed
 * (the caller exits 0).
 */
int ssc_parse(const struct ssc_command_spec *spec, int argc, char **argv,
	      struct ssc_common *co,
	      int (*handler)(int key, const char *arg, void *ctx), void *ctx,
	      int *first);

/* ssc_parse() for options that come from elsewhere than the command line
 * (a scene): where[i] names the origin of argv[i] ("scene.ini: line 12")
 * in usage errors of the handler (NULL entries: none). */
int ssc_parse_where(const struct ssc_command_spec *spec, int argc, char **argv,
		    const char *const *where, struct ssc_common *co,
		    int (*handler)(int key, const char *arg, void *ctx),
		    void *ctx, int *first);

/* Read an interval table: lines "START END V1 ... Vn" (nval values, at
 * most 6; comma or blanks; '#' comments).  Times in s unless a unit says
 * otherwise; values in SI unit `si` unless a unit says otherwise, bare
 * values in `bare` (NULL: si).  *out receives n_rows x (2 + nval) doubles
 * (SI; caller frees).  Errors name --opt, the file and the line.
 * Returns an exit code. */
int ssc_read_intervals(const struct ssc_common *co, const char *opt,
		       const char *path, const char *head, size_t nval,
		       const char *si, const char *bare, double **out,
		       size_t *n_rows);

/* The text of the last ssc_err() message (without the prefix). */
const char *ssc_last_error(void);
/* Print "sensorscope: CMD: message" to stderr.  Messages (and warnings,
 * usage errors) are one line: bytes a terminal would act on (control
 * characters, bidirectional overrides, bytes that are not UTF-8) are
 * written as \xNN, and a quoted excerpt longer than 64 bytes is cut, with
 * its length. */
void ssc_err(const char *cmd, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
/* "PATH: no sample rate: WHY; give --rate", WHY the rate note of the
 * capture or reader (a "# rate:" comment it could not read) when note is
 * not empty; returns SSC_EXIT_FAIL. */
int ssc_err_no_rate(const char *cmd, const char *path, const char *note);
/* Messages of commands run inside another (the stages of `run`) start
 * "sensorscope: OUTER: CMD: "; NULL ends it. */
void ssc_set_outer(const char *outer);
/* Keep the warnings said from now on (on: true; cleared), for a scene's
 * report; ssc_warn_kept() gives the i-th (and their number). */
void ssc_warn_keep(bool on);
/* Bare-number notes not said (a scene's check of its options). */
void ssc_bare_numbers_silent(bool on);
size_t ssc_warn_kept(size_t i, const char **msg);
/* Print "sensorscope: CMD: warning: message" unless quiet. */
void ssc_warn(const struct ssc_common *co, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
/* A usage error: message plus a hint to --help; returns SSC_EXIT_USAGE. */
int ssc_usage_error(const char *cmd, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));
/* Prefix usage errors with where the options came from (a scene file and
 * line), or NULL for the command line. */
void ssc_set_context(const char *ctx);
/* Map a library error to an exit code, printing "what: detail". */
int ssc_fail(const char *cmd, int rc, const struct sscope_diag *d,
	     const char *what);

/* Number parsing for option arguments: whole string, finite. */
int ssc_arg_double(const char *cmd, const char *opt, const char *arg,
		   double *out);
int ssc_arg_size(const char *cmd, const char *opt, const char *arg,
		 size_t *out);
/* Warn (unless quiet) of the bare numbers ssc_arg_quantity() read in an SI
 * unit the field does not write (rad/sqrt(s), rad/s, ...), with their
 * value in the field's unit; ssc_parse() does it once the options are
 * read, a command that reads such a value later calls it then. */
void ssc_say_bare_numbers(const struct ssc_common *co);
/* A JSON file another command wrote, for option --OPT (NULL: an operand):
 * its root, or NULL after a one-line error naming the option, the file
 * and why (missing, a folder, or not WHAT: "a calibration file"). */
json_t *ssc_json_read(const char *cmd, const char *opt, const char *path,
		      const char *what);
/* --gravity G: a local gravity in m/s^2 (1 to 30) */
int ssc_arg_gravity(const char *cmd, const char *arg, double *out);
/* A quantity with an optional unit, converted to the SI unit of @p si. */
int ssc_arg_quantity(const char *cmd, const char *opt, const char *arg,
		     const char *si, double *out);
/* A number (@p si NULL) or a quantity that must be positive. */
int ssc_arg_positive(const char *cmd, const char *opt, const char *arg,
		     const char *si, double *out);

/* Fill read options from the shared options (progress hooked up). */
void ssc_read_opts(const struct ssc_common *co, struct sscope_reader_opts *o);
/* The reader's progress shown as @p label (ssc_progress()), when the
 * command shows progress: o's callback reports into *p, which must live
 * as long as the reader. */
struct ssc_read_progress {
	const struct ssc_common *co;
	const char *label;
};
void ssc_read_progress_on(const struct ssc_common *co, const char *label,
			  struct ssc_read_progress *p, struct sscope_reader_opts *o);

/* Load a capture with the shared options (sscope_capture_open(): the
 * columns -c names, in its order, --calibration applied, the rate judged);
 * prints errors and warnings.  Returns exit. */
int ssc_load(const struct ssc_common *co, const char *path,
	     struct sscope_capture **cap);

/* After a failed analysis of a capture whose samples ssc_load left to the
 * analysis (values_in_run): the reader's error for a NaN or infinite
 * sample, printed; SSC_EXIT_OK when there is none. */
int ssc_check_values(const struct ssc_common *co,
		     const struct sscope_capture *cap);

/* Shape a capture to -c (sscope_capture_select(), in place) or make a view
 * of it (sscope_capture_view()); an unknown name is a data error (exit 1,
 * as the reader's).  Print errors, return exit codes. */
int ssc_select(const struct ssc_common *co, struct sscope_capture *cap);
int ssc_view(const struct ssc_common *co, const struct sscope_capture *cap,
	     struct sscope_capture **view);

/* Warn that a text capture's last line has no newline (cut short?). */
void ssc_warn_unterminated(const struct ssc_common *co, const char *path,
			   size_t rows);

/* Refuse an input named twice: standard input ('-') twice, or two names
 * of one file (same device and inode: a second path, a link, '-' fed
 * from that file).  Several files mean several captures (power cycles,
 * poses); one read twice would fake agreement.  Returns an exit code. */
int ssc_check_inputs(const char *cmd, const char *const *paths, size_t n);

/* Judge a time column's order (sscope_timing_order_check).  For an analysis
 * that assumes uniform sampling (@p uniform) a disordered column is an
 * error naming the problem, unless the rate came from --rate or a header
 * (then a warning); otherwise (info) a warning.  Returns an exit code. */
int ssc_time_verdict(const struct ssc_common *co, const char *path,
		     const char *column, const struct sscope_timing_order *o,
		     enum sscope_capture_rate_source rate_source, bool uniform);
/* The order of a capture's time stamps (what its timing analysis found
 * when it has one, else fed here). */
void ssc_time_order(const struct sscope_capture *cap,
		    struct sscope_timing_order *o);
/* The same for a loaded capture (nothing to judge without a time column). */
int ssc_time_check(const struct ssc_common *co, const char *path,
		   const struct sscope_capture *cap, bool uniform);
/* Gaps in a loaded capture's time stamps (0 when they are out of order:
 * said by ssc_time_check), and the warning a spectrum gives for them. */
size_t ssc_time_gaps(const struct sscope_capture *cap);
void ssc_warn_time_gaps(const struct ssc_common *co, const char *path,
			size_t gaps);

/* Is progress shown? (auto: stderr is a terminal and not quiet) */
bool ssc_progress_on(const struct ssc_common *co);
/* Progress line on stderr: "label: 42% ..." (total 0: bytes only). */
void ssc_progress(const struct ssc_common *co, const char *label,
		  double done, double total);
void ssc_progress_end(const struct ssc_common *co);

/*
 * The output layer (output.c).  Every file the CLI writes goes through it:
 * regular files are replaced atomically (a link's target, the link kept),
 * FIFOs, devices and standard output are written directly; a failed write
 * is one message "CMD: PATH: <errno text>"; temporary files and staging
 * folders are removed on SIGINT/SIGTERM/SIGHUP/SIGPIPE.
 */
struct ssc_out {
	FILE *f;
	void *priv;
};
/* Open the sink for @p path (NULL or "-": standard output).  Prints
 * errors; returns an exit code. */
int ssc_file_open(const char *cmd, const char *path, struct ssc_out *out);
/* Commit (ok) or discard.  A write error is reported here, also when the
 * caller saw it (ok false because ferror()); returns the exit code. */
int ssc_file_close(struct ssc_out *out, bool ok);
/* Room for the rest of a long output: after @p written of @p total units
 * (rows), the bytes the sink holds project its size (*projected; 0 when
 * the sink is not a regular file).  When the rest would not fit in the
 * free space of the sink's file system, print "PATH: about 2.5 TB to
 * write, 20 GB free on its file system: HINT" and return SSC_EXIT_FAIL
 * (the caller discards the sink); SSC_EXIT_OK otherwise. */
int ssc_out_room(const char *cmd, const struct ssc_out *out, double written,
		 double total, const char *hint, double *projected);
/* The same for the command's -o (or standard output). */
int ssc_out_open(const struct ssc_common *co, struct ssc_out *out);
int ssc_out_close(const struct ssc_common *co, struct ssc_out *out, bool ok);
/* Write a whole file (a figure, a page); returns 0 or -errno, prints
 * nothing. */
int ssc_file_put(const char *path, const void *buf, size_t len);
/* "dir/name" (a new string; NULL when out of memory). */
char *ssc_path_join(const char *dir, const char *name);
/* The one message for an output that could not be written: "CMD: PATH:
 * <strerror>".  Returns the exit code (2 for -ENOTSUP, else 1). */
int ssc_write_failed(const char *cmd, const char *path, int rc);
/* Flush standard output (at the end of a command, or where a command
 * flushes it itself); a failure is said once.  Returns an exit code. */
int ssc_stdout_finish(const char *cmd);
/* Install the SIGINT/SIGTERM/SIGHUP/SIGPIPE cleanup (signals the caller
 * ignores stay ignored). */
void ssc_signals_init(void);
/* True while a cleanup signal is being handled (the process is ending
 * with it): say nothing more (msg.c; the messages stay silent then).
 * ssc_set_interrupted() is the signal handler's: async-signal-safe. */
bool ssc_interrupted(void);
void ssc_set_interrupted(void);

/* Outputs compared with inputs before anything is written. */
enum { SSC_GUARD_IN, SSC_GUARD_OUT, SSC_GUARD_DIR };
struct ssc_guard_item {
	const char *what; /* how the user named it: "-o", "--plot", ... */
	const char *path;
	int role;         /* SSC_GUARD_IN, _OUT (a file), _DIR (a folder
			     replaced as a whole) */
};
/* Usage error (exit 2) when an output is an input (same device and inode;
 * for a folder: an input inside it), when two outputs are the same file,
 * or when an output's name is empty; @p stdout_out: standard output is
 * an output too. */
int ssc_guard_check(const char *cmd, const struct ssc_guard_item *items,
		    size_t n, bool stdout_out);
/* How messages name the long option @p name when it writes a file ("-o",
 * "--plot", "--kalibr", ...), or NULL when it does not write one. */
const char *ssc_output_option(const char *name);

/* A report folder built in a staging folder beside it and put into place
 * (exchanged with the old one) only when complete. */
struct ssc_outdir {
	char *dir;    /* write here: the staging folder */
	char *target; /* the folder it becomes (links resolved) */
	char *shown;  /* its name in messages */
	const char *const *stages; /* names of STAGE.ext files it may hold */
	int slot;
	int lock_fd; /* the staging folder, locked while this run owns it */
	bool existed;
};
/* Check @p dir (an existing one must hold only report files: report.*,
 * STAGE.ext, STAGE-N.ext for @p stages) and create the staging folder.
 * Staging folders of the same report left by a run that was killed
 * (SIGKILL, out of memory, power cut) are removed first: a live run holds
 * a lock on its own.  Prints errors; returns an exit code. */
int ssc_outdir_begin(const char *cmd, const char *what, const char *dir,
		     const char *const *stages, struct ssc_outdir *od);
/* Put the staging folder into place and remove the previous report. */
int ssc_outdir_commit(const char *cmd, struct ssc_outdir *od);
/* Remove the staging folder. */
void ssc_outdir_abort(struct ssc_outdir *od);

/* JSON helpers: non-finite numbers become null. */
json_t *ssc_jreal(double v);
/* Dump @p root (stolen) to the command's output; returns exit code. */
int ssc_emit_json(const struct ssc_common *co, json_t *root);

/* Longest text of ssc_json_real_text, with its NUL. */
#define SSC_JSON_REAL_MAX 32
/* The text ssc_emit_json writes for json_real(v) (null when v is not
 * finite) into buf (SSC_JSON_REAL_MAX bytes); returns its length. */
size_t ssc_json_real_text(char *buf, double v);
/* A placeholder for slot @p k of ssc_emit_json_slots (a new string). */
json_t *ssc_json_slot(size_t k);
/* ssc_emit_json, with slot k's placeholder replaced by the JSON text
 * fill(f, k, ctx) writes (returns false on a write error).  Returns
 * -EAGAIN, having written nothing, when the dump does not hold each
 * placeholder exactly once and in order (the caller then dumps a tree
 * without slots); else an exit code.  @p root is stolen. */
int ssc_emit_json_slots(const struct ssc_common *co, json_t *root,
			size_t n_slots,
			bool (*fill)(FILE *f, size_t k, void *ctx), void *ctx);

/* A unit for people: deg -> degree sign, sqrt(h) -> root, ug -> micro,
 * ^2 -> superscript (figures and reports; the JSON keeps the ASCII form). */
void ssc_unit_pretty(const char *in, char *out, size_t len);

/* Append {"code", "message"} to obj's "warnings" array (made when
 * missing): a result the analysis itself doubts (a rejected fit, an
 * unresolved term, too few samples, clipped data), which reports show as a
 * banner. */
void ssc_json_warn(json_t *obj, const char *code, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/*
 * A coefficient object of the JSON contract:
 * {"value","unit","lo","hi","si","si_unit","fitted"}; value/lo/hi are the
 * SI numbers converted to @p unit (NULL: the SI unit).  lo/hi may be NaN
 * (written as null).
 */
json_t *ssc_json_coef(double si, double si_lo, double si_hi, const char *unit,
		      const char *si_unit, bool fitted);

struct sscope_inclino_lut;
/* The "lut" object of a saved inclinometer calibration (inclinofile.c);
 * a new reference. */
json_t *ssc_inclino_lut_json(const struct sscope_inclino_lut *lut, bool cubic);
/* Read a look-up table of 'inclino calibrate' (JSON) into *lut and check
 * it; prints errors, returns exit code (inclinofile.c). */
int ssc_inclino_lut_read(const char *cmd, const char *path,
			 struct sscope_inclino_lut *lut);

/* A raw record of one float64 channel (@p nch_sel channels selected) in
 * the host's byte order, without scaling, in a regular file, fed to the
 * estimate @p p straight from a mapping of the file; the spectrum into *s
 * and the rows into *rows.  Returns false, the estimate reset, for any
 * other input or any failure: the caller then streams the record
 * (psdmap.c). */
struct sscope_psd;
struct sscope_psd_spectrum;
bool ssc_psd_fed_from_mapping(const struct ssc_common *co, const char *path,
			      size_t nch_sel, struct sscope_reader *rd,
			      struct sscope_psd *p, struct sscope_psd_spectrum *s,
			      uint64_t *rows);

/* OpenMP's passive wait policy (process.c): gives back the environment
 * entry the policy borrowed before the libraries started; where none
 * could be borrowed and may_exec, runs the command again with
 * OMP_WAIT_POLICY=passive unless the user set a policy (returns only when
 * it could not).  Call once per command, before it runs. */
void ssc_omp_wait_passive(char **argv, bool may_exec);

/* Load the [sensor] section of a spec file; prints errors, returns exit. */
int ssc_load_sensor(const char *cmd, const char *path,
		    struct sscope_sensor_spec *spec);

/* The inl_profile file of an [adc] spec (adcprofile.c): read it (relative
 * to @p spec_path's directory), check it and set spec->inl_lsb to max |INL|;
 * nothing to do without the key.  Prints errors, returns exit code. */
struct ssc_inl_profile {
	double *inl; /* 2^bits values, LSB, or NULL */
	size_t n;
};
int ssc_adc_profile_load(const char *cmd, const char *spec_path,
			 struct sscope_adc_spec *spec, struct ssc_inl_profile *prof);
/* sscope_adc_new() then sscope_adc_set_inl() of the profile (may be NULL). */
int ssc_adc_new(struct sscope_adc **adc, const struct sscope_adc_spec *spec,
		const struct ssc_inl_profile *prof, double sensitivity,
		double zero_v, uint64_t seed, struct sscope_diag *diag);
void ssc_adc_profile_free(struct ssc_inl_profile *prof);

/* Plots: PNG needs OpenCV (exit 2 with a message without it), SVG is
 * always built.  ssc_plot_check() returns 0 for a usable --plot path, else
 * the exit code after printing why. */
bool ssc_plot_available(void);
/* PNG plots installed (the module's file present, not opened): --version */
bool ssc_plot_installed(void);
int ssc_plot_unavailable(const char *cmd);
int ssc_plot_check(const char *cmd, const char *path);

/* Figures written to files (figfile.c), atomically through the output
 * layer.  ssc_fig_save_png(): 0, -ENOTSUP without OpenCV, -EINVAL for an
 * empty figure, -errno from the file system. */
struct ssc_fig;
int ssc_fig_save_png(struct ssc_fig *fig, const char *path);
/* The same as an SVG file (no OpenCV needed). */
int ssc_fig_save_svg(struct ssc_fig *fig, const char *path);
/* Write in the format of the path's extension (-EINVAL for another); a
 * path ending in SSC_PLOT_SVG_AND_PNG writes both files, BASE.svg and
 * BASE.png, from one drawing (scenes that keep both). */
int ssc_fig_save(struct ssc_fig *fig, const char *path);

/* Text formatting of a number with @p sig significant digits (no
 * exponent for ordinary magnitudes). */
const char *ssc_fmt(char *buf, size_t len, double v, int sig);
/* A fit's p-value after "p ": "= 0.023", or "< 0.001" at the bootstrap's
 * floor (sscope_noise_p_is_bound()). */
const char *ssc_fmt_p(char *buf, size_t len, double p);

#endif
