/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Capture readers: delimited text (comma, tab, semicolon or whitespace, '#'
 * comments, units in the header as "name [unit]" or "name (unit)", EuRoC's
 * "#timestamp [ns],w_RS_S_x [rad s^-1],..."), the sensorscope binary capture
 * (a two-line text header, then little-endian float32/float64 rows), raw
 * binary (--raw TYPE:CHANNELS[:le|be]) and MATLAB 5 MAT-files (io-mat.c).
 * Other formats are recognised by their leading bytes (io-formats.h): gzip
 * is undone as a stream (then recognised again), containers (ROS bags,
 * MCAP, rosbag2, npy) are decoded into a table served like the columns of
 * a file.
 *
 * Regular files are memory-mapped; pipes are read in 4 MiB blocks into a
 * buffer that slides over the input, so memory does not grow with the
 * record.  Only the selected columns are converted: other cells are skipped
 * by scanning for the delimiter.
 */
#include "internal.h"

#include <fcntl.h>
#include <float.h>
#include <pthread.h>
#include <stdatomic.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#ifdef __SSE2__
#include <emmintrin.h>
#include <immintrin.h>
#endif

#include "io-formats.h"
#include "numparse.h"
#include "io-mat.h"
#include "sscope-capture.h"
#include "sscope-quantity.h"
#include "sscope-reader.h"
#include "sscope-unit.h"

#define BLOCK (4u << 20)
#define BIN_MAGIC "#sensorscope-binary"

enum kind { K_TEXT, K_BIN, K_RAW, K_MAT, K_TABLE };
enum rawtype { R_I16, R_U16, R_I24, R_I32, R_U32, R_F32, R_F64 };

struct colx {
	struct sscope_capture_column c;
	char *name;
	char *unit_label;
	int unit_rc;      /* result of parsing the unit (0 ok) */
	int dest;         /* data channel number, or -1 */
	bool is_time;
	bool is_temp;
	bool used;        /* converted at all */
	bool hidden;      /* not in the default selection (text, metadata) */
	/* text in the first data line (text files): its line and cell */
	size_t text_line;
	char text_cell[24];
	bool dec_comma;   /* that cell is a number with a decimal comma */
};

struct sscope_reader {
	char *path;
	const char *disp; /* path for messages */
	enum kind kind;
	/* source */
	int fd;
	bool mapped;
	bool partial;     /* NAME.partial: a recording still being written or
			     interrupted (acquire): an unfinished last row
			     is left out */
	size_t map_len;   /* bytes mapped */
	const char *base; /* mapped file or buffer */
	size_t len;       /* bytes valid in base */
	size_t pos;       /* parse position */
	bool eof;
	char *buf;
	size_t cap;
	uint64_t size;    /* file size, 0 for pipes */
	uint64_t consumed; /* bytes before base[0] (pipes) */
	uint64_t last_progress;
	size_t line;      /* 1-based number of the line at pos */
	/* layout */
	char delim;       /* ',', '\t', ';' or ' ' (whitespace runs) */
	size_t ncols;
	struct colx *cols;
	size_t nsel;
	size_t *sel;      /* column index of each selected channel */
	long time_col, temp_col;
	/* binary */
	enum rawtype rtype;
	size_t rsize;     /* bytes per value */
	bool big_endian;
	double rscale, roffset;
	/* time origin */
	bool have_t0;
	int64_t t0_mant;
	int t0_exp;
	double t0_double;
	double header_rate_hz;
	char header_rate_note[SSCOPE_CAPTURE_RATE_NOTE_MAX]; /* a rate comment rejected */
	/* a mapped text file split for parallel reading */
	struct part *parts;
	size_t np, nthr; /* parts, threads */
	size_t split_pos;
	const struct sscope_reader_opts *opts;
	struct sscope_reader_opts opts_copy;
	/* MATLAB 5 MAT-file (io-mat.c) */
	struct ssc_mat *mat;
	size_t mat_row;
	unsigned char *matz; /* expanded MATLAB v7 file (io-matz.c) */
	/* gzip stream (io-gzip.c), decoded containers (io-formats.h) */
	struct ssc_gz *gz;
	struct ssc_table *tab;
	size_t tab_row;
	int64_t tab_t0;
	struct sscope_capture_source *src;
	/* a mapped binary file: pages before `dropped` were given back */
	size_t dropped, pagesz;
	size_t last_used; /* last column converted (SIZE_MAX: none) */
	/* a row of text right under the header that is not all units: its
	 * line and the first cell that is not a unit (text files) */
	size_t units_row_line;
	char units_row_bad[24];
};

/* files up to this size are mapped with all their pages at once */
#define MAP_POPULATE_MAX ((off_t)8 << 20)

/* ------------------------------------------------------------ source */

/* NAME.partial: the name acquire records under until a clean stop */
static bool is_partial_name(const char *path)
{
	size_t n = strlen(path), k = strlen(".partial");

	return n > k && !strcmp(path + n - k, ".partial");
}

static int src_open(struct sscope_reader *r, struct sscope_diag *diag)
{
	struct stat st;

	if (!strcmp(r->path, "-")) {
		r->fd = STDIN_FILENO;
	} else {
		r->fd = open(r->path, O_RDONLY | O_CLOEXEC);
		if (r->fd < 0)
			return ssc_diag(diag, -errno, "%s: %s", r->disp,
					sscope_strerror(-errno));
	}
	if (fstat(r->fd, &st) < 0)
		return ssc_diag(diag, -errno, "%s: %s", r->disp,
				sscope_strerror(-errno));
	if (S_ISDIR(st.st_mode))
		return ssc_diag(diag, -EISDIR, "%s: is a directory", r->disp);
	if (S_ISREG(st.st_mode) && st.st_size > 0) {
		/* a small file's pages mapped at once (one call, not a fault
		 * per 64 KiB); a large one's by read-ahead as the parse goes */
		void *m = mmap(NULL, (size_t)st.st_size, PROT_READ,
			       MAP_PRIVATE | (st.st_size <= MAP_POPULATE_MAX ? MAP_POPULATE : 0),
			       r->fd, 0);

		if (m != MAP_FAILED) {
			long pg = sysconf(_SC_PAGESIZE);

			madvise(m, (size_t)st.st_size, MADV_SEQUENTIAL);
			r->pagesz = pg > 0 ? (size_t)pg : 4096;
			r->mapped = true;
			r->partial = is_partial_name(r->path);
			r->map_len = (size_t)st.st_size;
			r->base = m;
			r->len = (size_t)st.st_size;
			r->size = (uint64_t)st.st_size;
			r->eof = true;
			return 0;
		}
	}
	if (S_ISREG(st.st_mode))
		r->size = (uint64_t)st.st_size;
	r->cap = BLOCK;
	r->buf = malloc(r->cap);
	if (!r->buf)
		return -ENOMEM;
	r->base = r->buf;
	return 0;
}

/* Make at least `want` bytes available from pos (or reach EOF). */
static int src_fill(struct sscope_reader *r, size_t want,
		    struct sscope_diag *diag)
{
	if (r->mapped || r->eof)
		return 0;
	if (r->pos > 0) {
		memmove(r->buf, r->buf + r->pos, r->len - r->pos);
		r->consumed += r->pos;
		r->len -= r->pos;
		r->pos = 0;
	}
	while (!r->eof && r->len < want) {
		ssize_t got;

		if (r->len == r->cap) {
			size_t ncap = r->cap * 2;
			char *nb;

			/* gzip held whole (a container inside): at most half
			 * the memory (deflate's 1032:1 bounds the work) */
			if (r->gz && ncap > ssc_expand_cap())
				return ssc_diag(diag, -ENOMEM,
						"%s: gzip data expand to more than the %.0f MiB a decompressed file may take here (half the memory this process may use): decompress it with gunzip and name the file",
						r->disp, (double)ssc_expand_cap() / 1048576.0);
			nb = realloc(r->buf, ncap);
			if (!nb)
				return r->gz ? ssc_diag(diag, -ENOMEM,
							"%s: out of memory expanding the gzip data (%.0f MiB so far): decompress it with gunzip and name the file",
							r->disp, (double)r->len / 1048576.0) :
					       -ENOMEM;
			r->buf = nb;
			r->base = nb;
			r->cap = ncap;
		}
		if (r->gz) {
			got = ssc_gz_read(r->gz, r->buf + r->len,
					  r->cap - r->len, r->disp, diag);
			if (got < 0)
				return (int)got;
		} else {
			got = read(r->fd, r->buf + r->len, r->cap - r->len);
		}
		if (got < 0) {
			if (errno == EINTR)
				continue;
			return ssc_diag(diag, -EIO, "%s: read error: %s",
					r->disp, sscope_strerror(-errno));
		}
		if (got == 0)
			r->eof = true;
		r->len += (size_t)got;
	}
	return 0;
}

static void progress(struct sscope_reader *r)
{
	uint64_t done;

	if (!r->opts->progress)
		return;
	done = r->consumed + r->pos;
	if (done - r->last_progress >= (16u << 20) || (r->eof && r->pos == r->len)) {
		r->last_progress = done;
		r->opts->progress(r->opts->progress_ctx, done, r->size);
	}
}

/* ------------------------------------------------------------ header */

static bool blank(char c)
{
	return c == ' ' || c == '\t' || c == '\r';
}

/* Find the end of the line starting at p; returns pointer to '\n' or end. */
static const char *line_end(const char *p, const char *end)
{
	const char *q = memchr(p, '\n', (size_t)(end - p));

	return q ? q : end;
}

static bool skip_line(const char *p, const char *e);

static char *dup_range(const char *a, const char *b)
{
	char *s;

	while (a < b && blank(*a))
		a++;
	while (b > a && blank(b[-1]))
		b--;
	if (b - a >= 2 && *a == '"' && b[-1] == '"') {
		a++;
		b--;
	}
	s = malloc((size_t)(b - a) + 1);
	if (s) {
		memcpy(s, a, (size_t)(b - a));
		s[b - a] = '\0';
	}
	return s;
}

/* Split one line into fields (used for headers and format detection). */
static size_t split_fields(const char *p, const char *e, char delim,
			   const char **fs, const char **fe, size_t max)
{
	size_t n = 0;

	if (e > p && e[-1] == '\r')
		e--;
	if (delim == ' ') {
		while (p < e) {
			while (p < e && blank(*p))
				p++;
			if (p >= e)
				break;
			/* a unit in brackets belongs to the name before it */
			if ((*p == '[' || *p == '(') && n > 0) {
				char close = *p == '[' ? ']' : ')';
				int depth = 0;

				while (p < e) {
					if (*p == '[' || *p == '(')
						depth++;
					if (*p == ']' || *p == ')')
						depth--;
					p++;
					if (depth == 0 && p[-1] == close)
						break;
				}
				fe[n - 1] = p;
				continue;
			}
			if (n < max)
				fs[n] = p;
			while (p < e && !blank(*p))
				p++;
			if (n < max)
				fe[n] = p;
			n++;
		}
		return n;
	}
	for (;;) {
		const char *q = p;

		while (q < e && *q != delim)
			q++;
		if (n < max) {
			fs[n] = p;
			fe[n] = q;
		}
		n++;
		if (q >= e)
			break;
		p = q + 1;
	}
	return n;
}

static bool field_is_number(const char *a, const char *b)
{
	double v;
	size_t n;

	while (a < b && blank(*a))
		a++;
	while (b > a && blank(b[-1]))
		b--;
	if (a == b)
		return true; /* empty cell: a gap, not a name */
	n = ssc_parse_double(a, b, &v);
	return n == (size_t)(b - a);
}

static char detect_delim(const char *p, const char *e)
{
	static const char cands[] = { ',', '\t', ';' };
	size_t best = 0;
	char d = ' ';

	for (size_t i = 0; i < sizeof(cands); i++) {
		size_t c = 0;

		for (const char *q = p; q < e; q++)
			c += *q == cands[i];
		if (c > best) {
			best = c;
			d = cands[i];
		}
	}
	return d;
}

/* Split "name [unit]" / "name (unit)" into its parts. */
static int split_name_unit(const char *cell, char **name, char **unit)
{
	size_t n = strlen(cell);
	const char *open = NULL;

	while (n && blank(cell[n - 1]))
		n--;
	if (n && (cell[n - 1] == ']' || cell[n - 1] == ')')) {
		char close = cell[n - 1], op = close == ']' ? '[' : '(';
		int depth = 0;

		for (size_t i = n; i-- > 0;) {
			if (cell[i] == close)
				depth++;
			else if (cell[i] == op && --depth == 0) {
				open = cell + i;
				break;
			}
		}
	}
	if (open && open > cell) {
		*name = dup_range(cell, open);
		*unit = dup_range(open + 1, cell + n - 1);
	} else {
		*name = dup_range(cell, cell + n);
		*unit = dup_range(cell, cell); /* "" */
	}
	return (*name && *unit) ? 0 : -ENOMEM;
}

static bool name_is(const char *name, const char *const *list)
{
	for (; *list; list++) {
		size_t n = strlen(*list);

		if (!ssc_strcasecmp(name, *list))
			return true;
		if (!strncasecmp(name, *list, n) && name[n] == '_')
			return true;
	}
	return false;
}

static const char *const time_names[] = { "t", "time", "timestamp", NULL };
static const char *const temp_names[] = { "temp", "temperature", NULL };

/* Parse unit labels and fill quantities; the unit errors are kept and
 * reported only for columns that are used. */
static void col_units(struct sscope_reader *r)
{
	for (size_t i = 0; i < r->ncols; i++) {
		struct colx *c = &r->cols[i];
		const char *u = c->unit_label;

		c->c.name = c->name;
		c->c.index = i;
		if (!*u && r->opts->default_unit &&
		    c->c.role == SSCOPE_CAPTURE_ROLE_DATA) {
			free(c->unit_label);
			c->unit_label = ssc_strdup(r->opts->default_unit);
			u = c->unit_label ? c->unit_label : "";
		}
		c->c.unit_label = u;
		c->unit_rc = sscope_unit_parse(
			*u ? u : (c->c.role == SSCOPE_CAPTURE_ROLE_TIME ? "s" :
				  c->c.role == SSCOPE_CAPTURE_ROLE_TEMP ? "degC" : ""),
			&c->c.unit, NULL);
		c->c.quantity = c->unit_rc || (!*u && c->c.role == SSCOPE_CAPTURE_ROLE_DATA) ?
					SSCOPE_QUANTITY_UNKNOWN :
					sscope_unit_quantity(&c->c.unit);
	}
}

static const char *col_name(const void *ctx, size_t i)
{
	return ((const struct sscope_reader *)ctx)->cols[i].name;
}

static size_t col_number(const void *ctx, size_t i)
{
	(void)ctx;
	return i + 1;
}

/* The 1-based numbers of the columns whose name equals column i's (case
 * aside), "2, 3 and 4" into buf; returns how many there are. */
static size_t same_name(const struct sscope_reader *r, size_t i, char *buf,
			size_t len)
{
	size_t n = 0, used = 0, last = 0;

	buf[0] = '\0';
	for (size_t k = 0; k < r->ncols; k++) {
		if (ssc_strcasecmp(r->cols[k].name, r->cols[i].name))
			continue;
		if (n && used + 24 < len)
			used += (size_t)snprintf(buf + used, len - used, "%s%zu",
						 n > 1 ? ", " : "", last);
		last = k + 1;
		n++;
	}
	if (used + 24 < len)
		snprintf(buf + used, len - used, "%s%zu", n > 1 ? " and " : "",
			 last);
	return n;
}

struct named {
	const char *name;
	size_t col;
};

static int cmp_name(const void *a, const void *b)
{
	return ssc_strcasecmp(((const struct named *)a)->name,
			      ((const struct named *)b)->name);
}

static int column_list(struct sscope_reader *r, char *buf, size_t len)
{
	size_t used = 0;

	buf[0] = '\0';
	for (size_t i = 0; i < r->ncols && used + 4 < len; i++) {
		int w = snprintf(buf + used, len - used, "%s%s", i ? ", " : "",
				 r->cols[i].name);

		if (w < 0)
			break;
		used += (size_t)w;
	}
	return 0;
}

static int assign_roles(struct sscope_reader *r, struct sscope_diag *diag)
{
	const struct sscope_reader_opts *o = r->opts;
	char names[200];

	r->time_col = -1;
	r->temp_col = -1;
	if (o->time_column && *o->time_column) {
		r->time_col = ssc_column_find(o->time_column, r->ncols, col_name, col_number, r);
		if (r->time_col < 0) {
			column_list(r, names, sizeof(names));
			return ssc_diag(diag, -EINVAL,
					"%s: no time column '%s' (columns: %s)",
					r->disp, o->time_column, names);
		}
	} else if (r->kind == K_TABLE) {
		for (size_t i = 0; i < r->ncols; i++)
			if (r->tab->cols[i].role == SSCOPE_CAPTURE_ROLE_TIME)
				r->time_col = (long)i;
	} else if (r->kind == K_TEXT || r->kind == K_BIN || r->kind == K_MAT) {
		for (size_t i = 0; i < r->ncols; i++)
			if (name_is(r->cols[i].name, time_names)) {
				r->time_col = (long)i;
				break;
			}
	}
	if (o->no_time)
		r->time_col = -1;
	if (o->temp_column && *o->temp_column) {
		r->temp_col = ssc_column_find(o->temp_column, r->ncols, col_name, col_number, r);
		if (r->temp_col < 0) {
			column_list(r, names, sizeof(names));
			return ssc_diag(diag, -EINVAL,
					"%s: no temperature column '%s' (columns: %s)",
					r->disp, o->temp_column, names);
		}
	} else if (r->kind == K_TABLE) {
		for (size_t i = 0; i < r->ncols; i++)
			if (r->tab->cols[i].role == SSCOPE_CAPTURE_ROLE_TEMP)
				r->temp_col = (long)i;
	} else if (r->kind != K_RAW) {
		for (size_t i = 0; i < r->ncols; i++)
			if ((long)i != r->time_col &&
			    name_is(r->cols[i].name, temp_names)) {
				r->temp_col = (long)i;
				break;
			}
	}
	for (size_t i = 0; i < r->ncols; i++) {
		r->cols[i].c.role = (long)i == r->time_col ? SSCOPE_CAPTURE_ROLE_TIME :
				    (long)i == r->temp_col ? SSCOPE_CAPTURE_ROLE_TEMP :
							     SSCOPE_CAPTURE_ROLE_DATA;
		r->cols[i].dest = -1;
	}
	col_units(r);
	return 0;
}

static int check_unit(struct sscope_reader *r, struct colx *c,
		      struct sscope_diag *diag)
{
	if (c->unit_rc) {
		struct sscope_diag d = { "" };

		sscope_unit_parse(c->c.unit_label, &c->c.unit, &d);
		return ssc_diag(diag, -EINVAL, "%s: column %zu (%s): %s",
				r->disp, c->c.index + 1, c->name, d.msg);
	}
	return 0;
}

static int select_columns(struct sscope_reader *r, struct sscope_diag *diag)
{
	const char *spec = r->opts->columns;
	char names[200];
	int rc;

	r->sel = ssc_alloc_array(r->ncols + 1, sizeof(*r->sel));
	if (!r->sel)
		return -ENOMEM;
	r->nsel = 0;
	if (spec && *spec) {
		const char *p = spec;
		char tok[256];
		bool too_long;

		while (ssc_list_next(&p, tok, sizeof(tok), &too_long)) {
			long idx = too_long ? -1 :
				   ssc_column_find(tok, r->ncols, col_name,
						   col_number, r);

			if (idx < 0) {
				column_list(r, names, sizeof(names));
				return ssc_diag(diag, -EINVAL,
						"%s: no column '%s' (columns: %s)",
						r->disp, tok, names);
			}
			if (strcmp(tok, r->cols[idx].name) == 0 ||
			    ssc_strcasecmp(tok, r->cols[idx].name) == 0) {
				/* a name, not an index: it must be unique */
				if (same_name(r, (size_t)idx, names,
					      sizeof(names)) > 1)
					return ssc_diag(diag, -EINVAL,
							"%s: '%s' names columns %s: select one by its number",
							r->disp, tok, names);
			}
			if (r->cols[idx].dest >= 0)
				continue; /* named twice */
			if (r->nsel >= r->ncols)
				break;
			r->cols[idx].dest = (int)r->nsel;
			r->sel[r->nsel++] = (size_t)idx;
		}
	} else {
		for (size_t i = 0; i < r->ncols; i++) {
			if (r->cols[i].c.role != SSCOPE_CAPTURE_ROLE_DATA ||
			    r->cols[i].hidden)
				continue;
			r->cols[i].dest = (int)r->nsel;
			r->sel[r->nsel++] = i;
		}
	}
	r->last_used = SIZE_MAX;
	for (size_t i = 0; i < r->ncols; i++) {
		struct colx *c = &r->cols[i];

		c->is_time = (long)i == r->time_col;
		c->is_temp = (long)i == r->temp_col;
		c->used = c->dest >= 0 || c->is_time || c->is_temp;
		if (c->used)
			r->last_used = i;
	}
	/* two columns in use under one name: results could not tell them
	 * apart (t,gx,gx,gx); the used names sorted, neighbours compared */
	{
		struct named *un = ssc_alloc_array(r->ncols + 1, sizeof(*un));
		size_t nu = 0;

		if (!un)
			return -ENOMEM;
		for (size_t i = 0; i < r->ncols; i++)
			if (r->cols[i].used)
				un[nu++] = (struct named){ r->cols[i].name, i };
		qsort(un, nu, sizeof(*un), cmp_name);
		for (size_t i = 1; i < nu; i++)
			if (!ssc_strcasecmp(un[i - 1].name, un[i].name)) {
				size_t k = un[i].col;
				size_t n = same_name(r, k, names, sizeof(names));

				rc = ssc_diag(diag, -EINVAL,
					      "%s: columns %s are %s named '%s': rename them in the header, or select one by its number (-c)",
					      r->disp, names, n > 2 ? "all" : "both",
					      r->cols[k].name);
				free(un);
				return rc;
			}
		free(un);
	}
	for (size_t k = 0; k < r->nsel; k++) {
		rc = check_unit(r, &r->cols[r->sel[k]], diag);
		if (rc)
			return rc;
	}
	if (r->time_col >= 0) {
		struct colx *c = &r->cols[r->time_col];

		rc = check_unit(r, c, diag);
		if (rc)
			return rc;
		if (sscope_unit_quantity(&c->c.unit) != SSCOPE_QUANTITY_TIME)
			return ssc_diag(diag, -EINVAL,
					"%s: time column '%s' has unit '%s', not a time",
					r->disp, c->name, c->c.unit_label);
	}
	if (r->temp_col >= 0) {
		struct colx *c = &r->cols[r->temp_col];

		rc = check_unit(r, c, diag);
		if (rc)
			return rc;
		if (sscope_unit_quantity(&c->c.unit) != SSCOPE_QUANTITY_TEMPERATURE)
			return ssc_diag(diag, -EINVAL,
					"%s: temperature column '%s' has unit '%s', not a temperature",
					r->disp, c->name, c->c.unit_label);
	}
	return 0;
}

static int add_columns(struct sscope_reader *r, const char **fs,
		       const char **fe, size_t n, bool names_given)
{
	r->cols = calloc(n ? n : 1, sizeof(*r->cols));
	if (!r->cols)
		return -ENOMEM;
	r->ncols = n;
	for (size_t i = 0; i < n; i++) {
		int rc;

		if (names_given) {
			char *cell = dup_range(fs[i], fe[i]);

			if (!cell)
				return -ENOMEM;
			if (i == 0 && cell[0] == '#') {
				memmove(cell, cell + 1, strlen(cell));
				while (blank(cell[0]))
					memmove(cell, cell + 1, strlen(cell));
			}
			rc = split_name_unit(cell, &r->cols[i].name,
					     &r->cols[i].unit_label);
			free(cell);
			if (rc)
				return rc;
			if (!r->cols[i].name[0]) {
				char tmp[24];

				free(r->cols[i].name);
				snprintf(tmp, sizeof(tmp), "col%zu", i + 1);
				r->cols[i].name = ssc_strdup(tmp);
				if (!r->cols[i].name)
					return -ENOMEM;
			}
		} else {
			char tmp[24];

			snprintf(tmp, sizeof(tmp), "col%zu", i + 1);
			r->cols[i].name = ssc_strdup(tmp);
			r->cols[i].unit_label = ssc_strdup("");
			if (!r->cols[i].name || !r->cols[i].unit_label)
				return -ENOMEM;
		}
	}
	return 0;
}

#define MAXF 4096

/* "# rate: 100 Hz" and similar metadata comments */
static void header_rate(struct sscope_reader *r, const char *p, const char *e)
{
	static const char *const keys[] = { "sample_rate", "sample rate",
					    "sampling rate", "rate_hz", "rate",
					    "fs", NULL };
	char buf[96];
	size_t n;
	double v;
	struct sscope_unit u, hz;

	while (p < e && blank(*p))
		p++;
	if (e > p && e[-1] == '\r')
		e--;
	for (const char *const *k = keys; *k; k++) {
		size_t kl = strlen(*k);
		const char *q = p + kl;

		if ((size_t)(e - p) <= kl || strncasecmp(p, *k, kl))
			continue;
		while (q < e && blank(*q))
			q++;
		if (q >= e || (*q != ':' && *q != '='))
			continue;
		q++;
		n = (size_t)(e - q);
		if (n >= sizeof(buf))
			return;
		memcpy(buf, q, n);
		buf[n] = '\0';
		sscope_unit_parse("Hz", &hz, NULL);
		if (!sscope_quantity_parse(buf, &v, &u, NULL)) {
			if (sscope_unit_quantity(&u) == SSCOPE_QUANTITY_DIMENSIONLESS &&
			    u.scale == 1)
				u = hz;
			if (sscope_unit_compatible(&u, &hz) && v > 0 && isfinite(v)) {
				r->header_rate_hz = v;
				return;
			}
		}
		/* told where a rate is needed and none was found (the
		 * comment quoted in printable ASCII: it reaches terminals) */
		n = (size_t)(e - p) < 40 ? (size_t)(e - p) : 40;
		memcpy(buf, p, n);
		for (size_t i = 0; i < n; i++)
			if ((unsigned char)buf[i] < 0x20 || (unsigned char)buf[i] >= 0x7f)
				buf[i] = '?';
		snprintf(r->header_rate_note, sizeof(r->header_rate_note),
			 "line %zu: '# %.*s%s' is not a sample rate (a positive frequency, as in '# rate: 100 Hz')",
			 r->line, (int)n, buf, e - p > 40 ? "..." : "");
		return;
	}
}

static bool skip_line(const char *p, const char *e);
static int text_columns(struct sscope_reader *r);

static int open_text(struct sscope_reader *r, struct sscope_diag *diag)
{
	const char *fs[MAXF], *fe[MAXF];
	const char *p, *end, *cm_s = NULL, *cm_e = NULL;
	size_t cm_line = 0, nf;
	int rc;

	/* the header and the first data line must lie in the first block */
	rc = src_fill(r, 1u << 20, diag);
	if (rc)
		return rc;
	p = r->base + r->pos;
	end = r->base + r->len;
	if (end - p >= 3 && !memcmp(p, "\xef\xbb\xbf", 3)) /* UTF-8 BOM */
		p += 3;
	for (;;) {
		const char *e, *q = p;
		bool numeric = true;

		if (p >= end)
			return ssc_diag(diag, -EDOM, "%s: no data rows",
					r->disp);
		e = line_end(p, end);
		r->line++;
		while (q < e && blank(*q))
			q++;
		if (q >= e) { /* blank line */
			p = e + (e < end);
			continue;
		}
		if (*q == '#') {
			header_rate(r, q + 1, e);
			cm_s = q + 1;
			cm_e = e;
			cm_line = r->line;
			p = e + (e < end);
			continue;
		}
		r->delim = detect_delim(q, e);
		nf = split_fields(q, e, r->delim, fs, fe, MAXF);
		if (nf > MAXF)
			return ssc_diag(diag, -EBADMSG,
					"%s: line %zu: more than %d columns",
					r->disp, r->line, MAXF);
		for (size_t i = 0; i < nf && numeric; i++)
			numeric = field_is_number(fs[i], fe[i]);
		if (!numeric) {
			/* a header line; data follow */
			r->pos = (size_t)(e - r->base) + (e < end);
			if (r->pos >= r->len && r->eof)
				return ssc_diag(diag, -EDOM,
						"%s: header but no data rows",
						r->disp);
			rc = add_columns(r, fs, fe, nf, true);
			return rc ? rc : text_columns(r);
		}
		/* data: a '#' comment right above it with as many fields, some
		 * of them names, is the header (EuRoC's "#timestamp [ns],...") */
		r->pos = (size_t)(p - r->base);
		r->line--;
		if (cm_s && cm_line == r->line) {
			const char *hs[MAXF], *he[MAXF];
			size_t nh = split_fields(cm_s, cm_e, r->delim, hs, he,
						 MAXF);
			bool any_name = false;

			for (size_t i = 0; i < nh && i < MAXF; i++)
				if (!field_is_number(hs[i], he[i]))
					any_name = true;
			if (nh == nf && any_name)
				return add_columns(r, hs, he, nh, true);
		}
		return add_columns(r, fs, fe, nf, false);
	}
}

/* A number written with a decimal comma: [+-]digits,digits[e[+-]digits] */
static bool decimal_comma(const char *a, const char *b)
{
	const char *p;

	while (a < b && blank(*a))
		a++;
	while (b > a && blank(b[-1]))
		b--;
	if (a < b && (*a == '+' || *a == '-'))
		a++;
	for (p = a; p < b && *p >= '0' && *p <= '9'; p++)
		;
	if (p == a || p >= b || *p != ',')
		return false;
	a = ++p;
	for (; p < b && *p >= '0' && *p <= '9'; p++)
		;
	if (p == a)
		return false;
	if (p < b && (*p == 'e' || *p == 'E')) {
		p++;
		if (p < b && (*p == '+' || *p == '-'))
			p++;
		a = p;
		for (; p < b && *p >= '0' && *p <= '9'; p++)
			;
		if (p == a)
			return false;
	}
	return p == b;
}

static void cell_copy(char *dst, size_t len, const char *a, const char *b)
{
	size_t n;

	while (a < b && blank(*a))
		a++;
	while (b > a && blank(b[-1]))
		b--;
	n = (size_t)(b - a) < len - 1 ? (size_t)(b - a) : len - 1;
	memcpy(dst, a, n);
	dst[n] = '\0';
}

/*
 * The first data line after the header.  A line of text in every cell
 * right under a header that names no units, each cell a unit (or empty),
 * is a units row ("t,gx" then "s,deg/s"): its units are taken and the
 * line skipped.  Columns whose first data cell is text (a frame id) stay
 * out of the default selection; the line and cell are kept for the
 * message when nothing numeric is left, and a decimal comma is noted.
 */
static int text_columns(struct sscope_reader *r)
{
	const char *fs[MAXF], *fe[MAXF];
	const char *p = r->base + r->pos, *end = r->base + r->len;
	size_t line = r->line;
	bool stamp = false, units_ok = true;

	for (size_t i = 0; i < r->ncols; i++)
		units_ok &= !*r->cols[i].unit_label;
	while (p < end) {
		const char *e = line_end(p, end);

		line++;
		if (!skip_line(p, e)) {
			size_t nf = split_fields(p, e, r->delim, fs, fe, MAXF);
			size_t ntext = 0, nunit = 0, nnum = 0;
			char bad[24] = "";

			for (size_t i = 0; i < nf && i < r->ncols && i < MAXF; i++) {
				struct sscope_unit u;
				char *cell;

				if (field_is_number(fs[i], fe[i])) {
					nnum += fs[i] != fe[i];
					continue;
				}
				ntext++;
				cell = dup_range(fs[i], fe[i]);
				if (!cell)
					return -ENOMEM;
				if (!sscope_unit_parse(cell, &u, NULL))
					nunit++;
				else if (!*bad)
					cell_copy(bad, sizeof(bad), fs[i], fe[i]);
				free(cell);
			}
			if (units_ok && nf == r->ncols && nnum == 0 && ntext > 0 &&
			    nunit == ntext) {
				/* a units row: take it, read from the next line */
				for (size_t i = 0; i < nf; i++) {
					free(r->cols[i].unit_label);
					r->cols[i].unit_label = dup_range(fs[i], fe[i]);
					if (!r->cols[i].unit_label)
						return -ENOMEM;
				}
				r->pos = (size_t)(e - r->base) + (e < end);
				r->line = line;
				units_ok = false;
				p = e + (e < end);
				continue;
			}
			/* text in every cell, some of it units: a units row
			 * with a cell that is not one */
			if (units_ok && nnum == 0 && nunit > 0) {
				r->units_row_line = line;
				memcpy(r->units_row_bad, bad, sizeof(bad));
			}
			for (size_t i = 0; i < nf && i < r->ncols && i < MAXF; i++)
				if (!field_is_number(fs[i], fe[i])) {
					struct colx *c = &r->cols[i];

					c->hidden = true;
					c->text_line = line;
					cell_copy(c->text_cell, sizeof(c->text_cell),
						  fs[i], fe[i]);
					c->dec_comma = r->delim != ',' &&
						       decimal_comma(fs[i], fe[i]);
				}
			break;
		}
		p = e + (e < end);
	}
	/* text in the first data line but a number in the next one is a
	 * bad cell, not a text column: read it, so that the cell is named */
	if (p < end) {
		p = line_end(p, end);
		p += p < end;
	}
	while (p < end) {
		const char *e = line_end(p, end);

		if (!skip_line(p, e)) {
			size_t nf = split_fields(p, e, r->delim, fs, fe, MAXF);

			for (size_t i = 0; i < nf && i < r->ncols && i < MAXF; i++)
				if (r->cols[i].hidden && !r->cols[i].dec_comma &&
				    fs[i] != fe[i] && field_is_number(fs[i], fe[i]))
					r->cols[i].hidden = false;
			break;
		}
		p = e + (e < end);
	}
	if (!r->ncols || !ssc_rostopic_detect(r->cols[0].name))
		return 0;
	for (size_t i = 0; i < r->ncols; i++)
		stamp |= !strcmp(r->cols[i].name, "field.header.stamp");
	for (size_t i = 0; i < r->ncols; i++) {
		struct colx *c = &r->cols[i];
		const char *name, *unit;
		bool hide;

		ssc_rostopic_column(c->name, stamp, &name, &unit, &hide);
		c->hidden |= hide;
		if (name) {
			free(c->name);
			c->name = ssc_strdup(name);
		}
		if (unit) {
			free(c->unit_label);
			c->unit_label = ssc_strdup(unit);
		}
		if (!c->name || !c->unit_label)
			return -ENOMEM;
	}
	return 0;
}

/* ------------------------------------------------------------ binary */

static const struct {
	const char *n;
	enum rawtype t;
	size_t sz;
} raw_types[] = { { "i16", R_I16, 2 }, { "u16", R_U16, 2 },
		  { "i24", R_I24, 3 }, { "i32", R_I32, 4 },
		  { "u32", R_U32, 4 }, { "f32", R_F32, 4 },
		  { "f64", R_F64, 8 } };

#define RAW_FORM "expected TYPE:CHANNELS[:le|be], TYPE one of i16 u16 i24 i32 u32 f32 f64"

/* "TYPE:CHANNELS[:le|be]": *type is an index of raw_types[]. */
static int raw_layout(const char *spec, size_t *type, size_t *channels,
		      bool *big_endian, struct sscope_diag *diag)
{
	const char *c1, *c2, *p;
	size_t ch = 0, i, tl;

	if (!spec || !*spec)
		return ssc_diag(diag, -EINVAL, "empty raw layout (" RAW_FORM ")");
	c1 = strchr(spec, ':');
	tl = c1 ? (size_t)(c1 - spec) : strlen(spec);
	for (i = 0; i < sizeof(raw_types) / sizeof(raw_types[0]); i++)
		if (strlen(raw_types[i].n) == tl && !strncmp(raw_types[i].n, spec, tl))
			break;
	if (i == sizeof(raw_types) / sizeof(raw_types[0]))
		return ssc_diag(diag, -EINVAL,
				"bad raw layout '%.40s': %s type (" RAW_FORM ")",
				spec, tl ? "unknown" : "missing");
	if (!c1)
		return ssc_diag(diag, -EINVAL,
				"bad raw layout '%.40s': no channel count (" RAW_FORM ")",
				spec);
	/* decimal digits only: no sign, no blanks, no wrap-around */
	for (p = c1 + 1; *p >= '0' && *p <= '9'; p++) {
		ch = ch * 10 + (size_t)(*p - '0');
		if (ch > MAXF)
			break;
	}
	while (*p >= '0' && *p <= '9')
		p++;
	if (p == c1 + 1 || (*p && *p != ':'))
		return ssc_diag(diag, -EINVAL,
				"bad raw layout '%.40s': the channel count is not a whole number (" RAW_FORM ")",
				spec);
	if (ch < 1 || ch > MAXF)
		return ssc_diag(diag, -EINVAL,
				"bad raw layout '%.40s': channels must be 1 to %d",
				spec, MAXF);
	c2 = p;
	*big_endian = false;
	if (*c2 == ':') {
		if (!strcmp(c2 + 1, "be"))
			*big_endian = true;
		else if (strcmp(c2 + 1, "le"))
			return ssc_diag(diag, -EINVAL,
					"bad raw layout '%.40s': byte order '%.8s' is not le or be",
					spec, c2 + 1);
	}
	*type = i;
	*channels = ch;
	return 0;
}

int sscope_reader_raw_layout_check(const char *layout, size_t *channels,
				   size_t *value_bytes, struct sscope_diag *diag)
{
	size_t t, ch;
	bool be;
	int rc = raw_layout(layout, &t, &ch, &be, diag);

	if (rc)
		return rc;
	if (channels)
		*channels = ch;
	if (value_bytes)
		*value_bytes = raw_types[t].sz;
	return 0;
}

static int parse_raw_spec(struct sscope_reader *r, const char *spec,
			  struct sscope_diag *diag)
{
	size_t t, ch;
	bool be;
	int rc = raw_layout(spec, &t, &ch, &be, diag);

	if (rc)
		return rc;
	r->rtype = raw_types[t].t;
	r->rsize = raw_types[t].sz;
	r->big_endian = be;
	r->ncols = ch;
	return 0;
}

static int open_raw(struct sscope_reader *r, struct sscope_diag *diag)
{
	size_t n;
	int rc = parse_raw_spec(r, r->opts->raw, diag);

	if (rc)
		return rc;
	n = r->ncols;
	r->cols = calloc(n, sizeof(*r->cols));
	if (!r->cols)
		return -ENOMEM;
	for (size_t i = 0; i < n; i++) {
		char tmp[24];

		snprintf(tmp, sizeof(tmp), "ch%zu", i + 1);
		r->cols[i].name = ssc_strdup(tmp);
		r->cols[i].unit_label = ssc_strdup("");
		if (!r->cols[i].name || !r->cols[i].unit_label)
			return -ENOMEM;
	}
	r->rscale = r->opts->raw_scale != 0 ? r->opts->raw_scale : 1;
	r->roffset = r->opts->raw_offset;
	if (r->size && r->size % (n * r->rsize))
		return ssc_diag(diag, -EBADMSG,
				"%s: size %llu is not a whole number of %zu-byte rows (truncated?)",
				r->disp, (unsigned long long)r->size,
				n * r->rsize);
	return 0;
}

static int open_bin(struct sscope_reader *r, struct sscope_diag *diag)
{
	const char *fs[MAXF], *fe[MAXF];
	const char *p = r->base, *end = r->base + r->len, *e1, *e2;
	char type[8] = "", endian[8] = "", l1[64];
	size_t nh, data_off;
	int rc;

	e1 = line_end(p, end);
	if (e1 >= end)
		return ssc_diag(diag, -EBADMSG, "%s: truncated binary header",
				r->disp);
	/* sscanf needs a string: the first line alone, terminated */
	if ((size_t)(e1 - p) >= sizeof(l1))
		return ssc_diag(diag, -EBADMSG, "%s: line 1: bad binary header",
				r->disp);
	memcpy(l1, p, (size_t)(e1 - p));
	l1[e1 - p] = '\0';
	if (sscanf(l1, BIN_MAGIC " 1 %7s %7s", type, endian) != 2 ||
	    (strcmp(type, "f32") && strcmp(type, "f64")) ||
	    (strcmp(endian, "le") && strcmp(endian, "be")))
		return ssc_diag(diag, -EBADMSG, "%s: line 1: bad binary header",
				r->disp);
	e2 = line_end(e1 + 1, end);
	if (e2 >= end)
		return ssc_diag(diag, -EBADMSG, "%s: truncated binary header",
				r->disp);
	nh = split_fields(e1 + 1, e2, ',', fs, fe, MAXF);
	if (nh > MAXF)
		return ssc_diag(diag, -EBADMSG, "%s: too many columns", r->disp);
	rc = add_columns(r, fs, fe, nh, true);
	if (rc)
		return rc;
	r->rtype = !strcmp(type, "f32") ? R_F32 : R_F64;
	r->rsize = r->rtype == R_F32 ? 4 : 8;
	r->big_endian = !strcmp(endian, "be");
	r->rscale = 1;
	r->roffset = 0;
	data_off = (size_t)(e2 + 1 - r->base);
	r->pos = data_off;
	r->line = 3;
	if (r->partial)
		r->len = r->size = data_off + (r->len - data_off) /
				   (nh * r->rsize) * (nh * r->rsize);
	if (r->size && (r->size - data_off) % (nh * r->rsize))
		return ssc_diag(diag, -EBADMSG,
				"%s: data are not a whole number of rows (truncated?)",
				r->disp);
	return 0;
}

/* ------------------------------------------------------------ MATLAB */

/* A MAT-file: the variables become columns (io-mat.c); a pipe is read
 * whole first. */
static int open_mat(struct sscope_reader *r, struct sscope_diag *diag)
{
	const char *fs[MAXF], *fe[MAXF];
	size_t n, zlen;
	int rc = src_fill(r, SIZE_MAX, diag);

	if (rc)
		return rc;
	rc = ssc_matz_expand((const unsigned char *)r->base, r->len, &r->matz,
			     &zlen, r->disp, diag);
	if (rc)
		return rc;
	rc = ssc_mat_open(&r->mat, r->matz ? r->matz :
				   (const unsigned char *)r->base,
			  r->matz ? zlen : r->len, r->disp, diag);
	if (rc)
		return rc;
	r->src = ssc_source_new(r->matz ? "MATLAB v7 MAT-file (compressed)" :
					  "MATLAB 5 MAT-file");
	if (!r->src)
		return -ENOMEM;
	n = ssc_mat_n_channels(r->mat);
	if (n > MAXF)
		n = MAXF;
	for (size_t i = 0; i < n; i++) {
		fs[i] = ssc_mat_channel_name(r->mat, i);
		fe[i] = fs[i] + strlen(fs[i]);
	}
	return add_columns(r, fs, fe, n, true);
}

static int read_mat(struct sscope_reader *r, struct sscope_reader_chunk *ch,
		    struct sscope_diag *diag)
{
	size_t row = 0, nrows = ssc_mat_rows(r->mat);

	for (; row < ch->capacity && r->mat_row < nrows; row++, r->mat_row++) {
		for (size_t c = 0; c < r->ncols; c++) {
			struct colx *cx = &r->cols[c];
			double v;

			if (!cx->used)
				continue;
			v = ssc_mat_value(r->mat, c, r->mat_row);
			if ((isnan(v) && (!r->opts->nan_as_gap || cx->is_time)) ||
			    isinf(v))
				return ssc_diag(diag, -EBADMSG,
						"%s: variable %s, element %zu: %s",
						r->disp, cx->name, r->mat_row + 1,
						isinf(v) ? "infinite value" :
						cx->is_time ? "NaN time stamp" :
						"NaN (use --allow-nan to read gaps)");
			if (cx->dest >= 0 && ch->data[cx->dest])
				ch->data[cx->dest][row] =
					v * cx->c.unit.scale + cx->c.unit.offset;
			if (cx->is_time) {
				if (!r->have_t0) {
					r->have_t0 = true;
					r->t0_double = v;
				}
				if (ch->time_s)
					ch->time_s[row] = (v - r->t0_double) *
							  cx->c.unit.scale;
			}
			if (cx->is_temp && ch->temp_degc)
				ch->temp_degc[row] = v * cx->c.unit.scale +
						     cx->c.unit.offset;
		}
	}
	ch->rows = row;
	return 0;
}

/* ------------------------------------------------------------ tables */

static int table_columns(struct sscope_reader *r)
{
	const char *fs[MAXF], *fe[MAXF];
	size_t n = r->tab->ncols < MAXF ? r->tab->ncols : MAXF;

	for (size_t i = 0; i < n; i++) {
		fs[i] = r->tab->cols[i].label;
		fe[i] = fs[i] + strlen(fs[i]);
	}
	return add_columns(r, fs, fe, n, true);
}

/* A container (bag, MCAP, .db3, npy) read whole, then decoded. */
static int open_table(struct sscope_reader *r, enum ssc_container kind,
		      struct sscope_diag *diag)
{
	int rc = src_fill(r, SIZE_MAX, diag);

	if (rc)
		return rc;
	rc = ssc_container_open(&r->tab, kind, (const unsigned char *)r->base,
				r->len, r->mapped, r->disp, r->opts->topic, diag);
	return rc ? rc : table_columns(r);
}

/* gzip: from here on src_fill() reads decompressed bytes */
static int open_gzip(struct sscope_reader *r, struct sscope_diag *diag)
{
	int rc;

	if (r->mapped) {
		rc = ssc_gz_open(&r->gz, (const unsigned char *)r->base, r->len,
				 -1, (void *)r->base, r->len);
		if (rc)
			return rc;
		r->mapped = false;
	} else {
		rc = ssc_gz_open(&r->gz, (const unsigned char *)r->base + r->pos,
				 r->len - r->pos, r->fd, NULL, 0);
		if (rc)
			return rc;
	}
	if (!r->buf) {
		r->cap = BLOCK;
		r->buf = malloc(r->cap);
		if (!r->buf)
			return -ENOMEM;
	}
	r->base = r->buf;
	r->len = r->pos = 0;
	r->eof = false;
	r->size = 0;
	r->consumed = 0;
	return src_fill(r, 1u << 20, diag);
}

static int read_table(struct sscope_reader *r, struct sscope_reader_chunk *ch,
		      struct sscope_diag *diag)
{
	size_t n = r->tab->nrows - r->tab_row, r0 = r->tab_row;

	if (n > ch->capacity)
		n = ch->capacity;
	for (size_t c = 0; c < r->ncols; c++) {
		const struct colx *cx = &r->cols[c];
		const struct ssc_tcol *tc = &r->tab->cols[c];
		double *dst = cx->dest >= 0 ? ch->data[cx->dest] : NULL;
		double sc = cx->c.unit.scale, of = cx->c.unit.offset;

		if (!cx->used)
			continue;
		if (cx->is_time && !r->have_t0 && r->tab->nrows) {
			r->have_t0 = true;
			r->tab_t0 = tc->type == SSC_V_I64 ? ssc_table_i64(tc, 0) : 0;
			r->t0_double = ssc_table_value(tc, 0);
		}
		for (size_t i = 0; i < n; i++) {
			double v;

			if (tc->type == SSC_V_F64 && !tc->swap) /* decoded arrays */
				memcpy(&v, tc->data + (r0 + i) * tc->stride, 8);
			else
				v = ssc_table_value(tc, r0 + i);

			if ((isnan(v) && (!r->opts->nan_as_gap || cx->is_time)) ||
			    isinf(v))
				return ssc_diag(diag, -EBADMSG,
						"%s: %s, row %zu: %s", r->disp,
						cx->name, r0 + i + 1,
						isinf(v) ? "infinite value" :
						cx->is_time ? "NaN time stamp" :
						"NaN (use --allow-nan to read gaps)");
			if (dst)
				dst[i] = v * sc + of;
			if (cx->is_temp && ch->temp_degc)
				ch->temp_degc[i] = v * sc + of;
			if (cx->is_time && ch->time_s)
				/* exact integer difference, one rounding */
				ch->time_s[i] = tc->type == SSC_V_I64 ?
					(double)(int64_t)((uint64_t)ssc_table_i64(tc, r0 + i) -
							  (uint64_t)r->tab_t0) * sc :
					(v - r->t0_double) * sc;
		}
	}
	r->tab_row += n;
	ch->rows = n;
	return 0;
}

/* name the format of what a gzip stream held */
static int gzip_source(struct sscope_reader *r)
{
	char f[160];
	const char *inner = r->kind == K_TEXT ? "text" :
			    r->kind == K_BIN ? "sensorscope binary" :
			    r->src ? r->src->format : r->tab ? r->tab->src->format :
			    "data";
	struct sscope_capture_source *s;

	snprintf(f, sizeof(f), "gzip-compressed %s", inner);
	s = ssc_source_new(f);
	if (!s)
		return -ENOMEM;
	if (r->tab) {
		free((char *)r->tab->src->format);
		r->tab->src->format = s->format;
		s->format = NULL;
		ssc_source_free(s);
	} else {
		ssc_source_free(r->src);
		r->src = s;
	}
	return 0;
}

struct sscope_capture_source *ssc_reader_take_source(struct sscope_reader *r,
						     size_t rows)
{
	if (r->tab)
		return ssc_source_copy(r->tab->src, r->tab->rx_ns,
				       r->tab->rx_ns ? rows : 0, r->tab_t0);
	return r->src ? ssc_source_copy(r->src, NULL, 0, 0) : NULL;
}

const struct sscope_capture_source *sscope_reader_source(const struct sscope_reader *r)
{
	return r->tab ? r->tab->src : r->src;
}

/* ------------------------------------------------------------ open */

/*
 * A text file that cannot be read as the user expects, in one line that
 * names the line, the cell and the columns: a decimal comma in a cell of
 * the first data line (in a column read, or in the default selection); no
 * numeric data column left because the first data line holds text (a
 * units row with a cell that is not a unit, a text column).
 */
static int text_refusal(struct sscope_reader *r, struct sscope_diag *diag)
{
	char cols[160];
	size_t used = 0, ndrop = 0, first = SIZE_MAX;
	bool defaults = !(r->opts->columns && *r->opts->columns);

	cols[0] = '\0';
	for (size_t i = 0; i < r->ncols; i++) {
		struct colx *c = &r->cols[i];
		bool read = c->used || (defaults && c->c.role == SSCOPE_CAPTURE_ROLE_DATA);

		if (!c->text_line || !read)
			continue;
		if (first == SIZE_MAX)
			first = i;
		if (c->dec_comma && !r->cols[first].dec_comma)
			first = i;
		if (c->c.role == SSCOPE_CAPTURE_ROLE_DATA && used + 40 < sizeof(cols)) {
			int w = snprintf(cols + used, sizeof(cols) - used,
					 "%s%zu (%s)", ndrop ? ", " : "", i + 1,
					 c->name);

			if (w > 0)
				used += (size_t)w;
		}
		ndrop += c->c.role == SSCOPE_CAPTURE_ROLE_DATA;
	}
	if (r->units_row_line) {
		struct sscope_unit u;
		struct sscope_diag d = { "" };

		sscope_unit_parse(r->units_row_bad, &u, &d);
		return ssc_diag(diag, -EBADMSG,
				"%s: line %zu looks like a units row, but %s: fix that cell, or write the units in the header as 'name [unit]'",
				r->disp, r->units_row_line, d.msg);
	}
	if (first == SIZE_MAX)
		return 0;
	if (r->cols[first].dec_comma) {
		struct colx *c = &r->cols[first];

		return ssc_diag(diag, -EBADMSG,
				"%s: line %zu, column %zu (%s): '%s' has a decimal comma: write decimal points (the separator is '%s', so replacing every ',' by '.' converts the file, e.g. sed 's/,/./g')",
				r->disp, c->text_line, first + 1, c->name,
				c->text_cell, r->delim == '\t' ? "tab" :
				r->delim == ' ' ? "blank" : ";");
	}
	if (r->nsel > 0)
		return 0; /* text columns (frame ids) left out; others read */
	if (ndrop <= 1)
		return ssc_diag(diag, -EDOM,
				"%s: no numeric data column: line %zu, column %zu (%s) holds text ('%s'): select numeric columns with -c, or fix the file",
				r->disp, r->cols[first].text_line, first + 1,
				r->cols[first].name, r->cols[first].text_cell);
	return ssc_diag(diag, -EDOM,
			"%s: no numeric data column: line %zu holds text in columns %s (first '%s'): select numeric columns with -c, or fix the file",
			r->disp, r->cols[first].text_line, cols,
			r->cols[first].text_cell);
}

/* A source of `mem_len` bytes at `mem` (the caller's; read in place, like
 * a mapped file) when mem is not NULL, else the file at path. */
static int reader_open(struct sscope_reader **reader, const char *path,
		       const void *mem, size_t mem_len,
		       const struct sscope_reader_opts *opts,
		       struct sscope_diag *diag)
{
	static const struct sscope_reader_opts defaults;
	struct sscope_reader *r;
	enum ssc_container kind;
	int rc;

	*reader = NULL;
	if (!path)
		return ssc_diag(diag, -EINVAL, "no input file");
	r = calloc(1, sizeof(*r));
	if (!r)
		return -ENOMEM;
	r->fd = -1;
	r->opts_copy = opts ? *opts : defaults;
	r->opts = &r->opts_copy;
	r->path = ssc_strdup(path);
	if (!r->path) {
		free(r);
		return -ENOMEM;
	}
	r->disp = strcmp(path, "-") ? r->path : "(stdin)";
	if (r->opts->rate_hz < 0 || isnan(r->opts->rate_hz)) {
		rc = ssc_diag(diag, -EINVAL, "bad sample rate");
		goto fail;
	}
	if (r->opts->default_unit && *r->opts->default_unit) {
		struct sscope_unit u;
		struct sscope_diag d = { "" };

		rc = sscope_unit_parse(r->opts->default_unit, &u, &d);
		if (rc) {
			ssc_diag(diag, rc, "%s", d.msg);
			goto fail;
		}
	}
	if (!mem && !(r->opts->raw && *r->opts->raw) &&
	    ssc_rosbag2_is_dir(path)) {
		r->kind = K_TABLE;
		rc = ssc_rosbag2_open(&r->tab, path, r->opts->topic, diag);
		if (!rc)
			rc = table_columns(r);
		goto opened;
	}
	if (mem) {
		r->base = mem;
		r->len = mem_len;
		r->size = mem_len;
		r->eof = true;
	} else {
		rc = src_open(r, diag);
		if (rc)
			goto fail;
	}
	if (r->opts->raw && *r->opts->raw) {
		r->kind = K_RAW;
		rc = open_raw(r, diag);
	} else {
		rc = src_fill(r, 1u << 20, diag);
		if (rc)
			goto fail;
		if (r->len == 0) {
			rc = ssc_diag(diag, -EDOM, "%s: empty file", r->disp);
			goto fail;
		}
		kind = ssc_container_detect(r->base, r->len);
		if (kind == SSC_C_GZIP) {
			r->partial = false;
			rc = open_gzip(r, diag);
			if (!rc && r->len == 0)
				rc = ssc_diag(diag, -EDOM, "%s: empty file (gzip)",
					      r->disp);
			if (rc)
				goto fail;
			kind = ssc_container_detect(r->base, r->len);
		}
		if (kind == SSC_C_MAT) {
			r->kind = K_MAT;
			rc = open_mat(r, diag);
		} else if (kind != SSC_C_NONE && kind != SSC_C_GZIP) {
			r->kind = K_TABLE;
			rc = open_table(r, kind, diag);
		} else if (r->len >= strlen(BIN_MAGIC) &&
		    !memcmp(r->base, BIN_MAGIC, strlen(BIN_MAGIC))) {
			r->kind = K_BIN;
			rc = open_bin(r, diag);
		} else {
			if (memchr(r->base, '\0', r->len < 4096 ? r->len : 4096)) {
				rc = ssc_diag(diag, -EBADMSG,
					      "%s: binary data (use --raw TYPE:CHANNELS for raw files)",
					      r->disp);
				goto fail;
			}
			r->kind = K_TEXT;
			if (r->partial) {
				const char *nl = memrchr(r->base, '\n', r->len);

				r->len = nl ? (size_t)(nl + 1 - r->base) : 0;
				r->size = r->len;
			}
			rc = open_text(r, diag);
		}
		if (!rc && r->gz)
			rc = gzip_source(r);
	}
opened:
	if (rc)
		goto fail;
	if (r->opts->topic && *r->opts->topic &&
	    !(r->tab && r->tab->src->n_topics)) {
		rc = ssc_diag(diag, -EINVAL,
			      "%s: --topic applies to ROS bags, rosbag2 and MCAP files",
			      r->disp);
		goto fail;
	}
	rc = assign_roles(r, diag);
	if (!rc)
		rc = select_columns(r, diag);
	if (rc)
		goto fail;
	if (r->kind == K_TEXT) {
		rc = text_refusal(r, diag);
		if (rc)
			goto fail;
	}
	if (r->nsel == 0 && r->kind != K_RAW) {
		rc = ssc_diag(diag, -EDOM,
			      "%s: no data column (only time/temperature)",
			      r->disp);
		goto fail;
	}
	*reader = r;
	return 0;
fail:
	sscope_reader_close(r);
	return rc;
}

int sscope_reader_open(struct sscope_reader **reader, const char *path,
		       const struct sscope_reader_opts *opts,
		       struct sscope_diag *diag)
{
	return reader_open(reader, path, NULL, 0, opts, diag);
}

int ssc_reader_open_mem(struct sscope_reader **reader, const void *buf,
			size_t len, const char *name,
			const struct sscope_reader_opts *opts,
			struct sscope_diag *diag)
{
	if (!buf)
		return ssc_diag(diag, -EINVAL, "no input buffer");
	return reader_open(reader, name ? name : "(memory)", buf, len, opts,
			   diag);
}

bool sscope_reader_unterminated(const struct sscope_reader *r)
{
	const char *p, *e;

	if (!r || r->kind != K_TEXT || !r->eof || r->pos < r->len || !r->len)
		return false;
	e = r->base + r->len;
	if (e[-1] == '\n')
		return false;
	/* the last line is still in the buffer: a pipe's buffer slides by
	 * whole lines */
	p = memrchr(r->base, '\n', r->len);
	p = p ? p + 1 : r->base;
	return !skip_line(p, e);
}

size_t sscope_reader_n_channels(const struct sscope_reader *r)
{
	return r->nsel;
}

const struct sscope_capture_column *sscope_reader_channel(const struct sscope_reader *r,
							  size_t k)
{
	return k < r->nsel ? &r->cols[r->sel[k]].c : NULL;
}

const struct sscope_capture_column *
sscope_reader_time_column(const struct sscope_reader *r)
{
	return r->time_col >= 0 ? &r->cols[r->time_col].c : NULL;
}

const struct sscope_capture_column *
sscope_reader_temp_column(const struct sscope_reader *r)
{
	return r->temp_col >= 0 ? &r->cols[r->temp_col].c : NULL;
}

size_t sscope_reader_n_columns(const struct sscope_reader *r)
{
	return r->ncols;
}

const struct sscope_capture_column *sscope_reader_column(const struct sscope_reader *r,
							 size_t k)
{
	return k < r->ncols ? &r->cols[k].c : NULL;
}

double sscope_reader_header_rate(const struct sscope_reader *r)
{
	return r->header_rate_hz;
}

const char *sscope_reader_header_rate_note(const struct sscope_reader *r)
{
	return r->header_rate_hz > 0 || !r->header_rate_note[0] ?
		       NULL : r->header_rate_note;
}

uint64_t sscope_reader_size(const struct sscope_reader *r)
{
	return r->size;
}

void sscope_reader_close(struct sscope_reader *r)
{
	if (!r)
		return;
	if (r->mapped)
		munmap((void *)r->base, r->map_len);
	if (r->fd >= 0 && r->fd != STDIN_FILENO)
		close(r->fd);
	free(r->buf);
	for (size_t i = 0; r->cols && i < r->ncols; i++) {
		free(r->cols[i].name);
		free(r->cols[i].unit_label);
	}
	free(r->cols);
	free(r->sel);
	free(r->parts);
	free(r->path);
	ssc_mat_free(r->mat);
	free(r->matz);
	ssc_gz_close(r->gz);
	ssc_table_free(r->tab);
	ssc_source_free(r->src);
	free(r);
}

/* ------------------------------------------------------------ rows */

/* Exact decimal of a time stamp: value = mant * 10^exp, when the digits
 * fit an int64 (19 digits: nanosecond epoch stamps do). */
static bool parse_exact(const char *p, const char *e, int64_t *mant, int *exp)
{
	bool neg = false, any = false;
	int64_t m = 0;
	int x = 0;

	if (p < e && (*p == '-' || *p == '+')) {
		neg = *p == '-';
		p++;
	}
	for (; p < e && *p >= '0' && *p <= '9'; p++, any = true) {
		if (__builtin_mul_overflow(m, 10, &m) ||
		    __builtin_add_overflow(m, *p - '0', &m))
			return false;
	}
	if (p < e && *p == '.') {
		for (p++; p < e && *p >= '0' && *p <= '9'; p++, any = true) {
			if (__builtin_mul_overflow(m, 10, &m) ||
			    __builtin_add_overflow(m, *p - '0', &m))
				return false;
			x--;
		}
	}
	if (!any || p != e)
		return false;
	*mant = neg ? -m : m;
	*exp = x;
	return true;
}

/* Set the time origin from a time cell (the first row's). */
static void set_t0(struct sscope_reader *r, const char *a, const char *b,
		   double v)
{
	r->have_t0 = true;
	r->t0_double = v;
	if (!parse_exact(a, b, &r->t0_mant, &r->t0_exp))
		r->t0_exp = 1000; /* marks "not exact" */
}

/* Time since the first row from the exact decimal m * 10^x when both
 * stamps have the same number of decimals (one rounding): true with *dt
 * set, else false. */
static inline __attribute__((always_inline)) bool
time_exact(const struct sscope_reader *r, int64_t m, int x, double *dt)
{
	static const double p10[] = { 1, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7,
				      1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14,
				      1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
				      1e21, 1e22 };
	int64_t d;
	double dd;

	if (r->t0_exp == 1000 || x != r->t0_exp ||
	    __builtin_sub_overflow(m, r->t0_mant, &d))
		return false;
	dd = (double)d;
	if (x < 0 && x >= -22)
		*dt = dd / p10[-x];
	else
		*dt = x == 0 ? dd : dd * pow(10, x);
	return true;
}

/* The same, else from the doubles. */
static inline __attribute__((always_inline)) double
time_since(const struct sscope_reader *r, bool exact, int64_t m, int x,
	   double v)
{
	double dt;

	return exact && time_exact(r, m, x, &dt) ? dt : v - r->t0_double;
}

/* The same from the text of the time cell. */
static double time_value(const struct sscope_reader *r, const char *a,
			 const char *b, double v)
{
	int64_t m = 0;
	int x = 0;
	bool exact = parse_exact(a, b, &m, &x);

	return time_since(r, exact, m, x, v);
}

static int bad_cell(const struct sscope_reader *r, size_t line, size_t col,
		    const char *a, const char *b, const char *why,
		    struct sscope_diag *diag)
{
	int len = (int)(b - a);

	if (len > 40)
		len = 40;
	return ssc_diag(diag, -EBADMSG, "%s: line %zu, column %zu (%s): %s '%.*s'",
			r->disp, line, col + 1, r->cols[col].name, why, len, a);
}

/* Slow path for a cell the fast path did not take: blanks, empty cells,
 * NaN, infinities, garbage.  Returns 0 with *v set, or an error. */
static int cell_value(const struct sscope_reader *r, size_t line, size_t col,
		      const char **pa, const char **pb, double *v,
		      struct sscope_diag *diag)
{
	const struct colx *c = &r->cols[col];
	const char *a = *pa, *b = *pb;
	size_t used;

	while (a < b && blank(*a))
		a++;
	while (b > a && blank(b[-1]))
		b--;
	*pa = a;
	*pb = b;
	if (a == b) {
		if (!r->opts->nan_as_gap || c->is_time)
			return bad_cell(r, line, col, a, b,
					"empty cell (use --allow-nan to read gaps)",
					diag);
		*v = NAN;
		return 0;
	}
	used = ssc_parse_double(a, b, v);
	if (used != (size_t)(b - a))
		return bad_cell(r, line, col, a, b, "not a number", diag);
	if (isnan(*v) && (!r->opts->nan_as_gap || c->is_time))
		return bad_cell(r, line, col, a, b,
				c->is_time ? "NaN time stamp" :
					     "NaN (use --allow-nan to read gaps)",
				diag);
	if (isinf(*v))
		return bad_cell(r, line, col, a, b, "infinite value", diag);
	return 0;
}

static inline void put_cell(const struct sscope_reader *r,
			    const struct colx *c, struct sscope_reader_chunk *ch,
			    size_t row, const char *a, const char *b, double v)
{
	if (c->dest >= 0 && ch->data[c->dest])
		ch->data[c->dest][row] = v * c->c.unit.scale + c->c.unit.offset;
	if (c->is_time && ch->time_s)
		ch->time_s[row] = time_value(r, a, b, v) * c->c.unit.scale;
	if (c->is_temp && ch->temp_degc)
		ch->temp_degc[row] = v * c->c.unit.scale + c->c.unit.offset;
}

static int ragged(const struct sscope_reader *r, size_t line, size_t cols,
		  struct sscope_diag *diag)
{
	return ssc_diag(diag, -EBADMSG,
			"%s: line %zu: %zu columns where the header has %zu",
			r->disp, line, cols, r->ncols);
}

/* One data line [p, e) (no newline).  Reentrant: reads r, writes ch. */
static int parse_line(const struct sscope_reader *r, const char *p,
		      const char *e, size_t line, struct sscope_reader_chunk *ch,
		      size_t row, struct sscope_diag *diag)
{
	size_t col = 0;
	int rc;

	if (e > p && e[-1] == '\r')
		e--;
	if (r->delim == ' ') {
		for (;;) {
			const char *a, *b;
			double v;

			while (p < e && blank(*p))
				p++;
			if (p >= e)
				break;
			a = p;
			while (p < e && !blank(*p))
				p++;
			b = p;
			if (col < r->ncols && r->cols[col].used) {
				rc = cell_value(r, line, col, &a, &b, &v, diag);
				if (rc)
					return rc;
				put_cell(r, &r->cols[col], ch, row, a, b, v);
			}
			col++;
		}
		return col == r->ncols ? 0 : ragged(r, line, col, diag);
	}
	for (;;) {
		const char d = r->delim;
		const char *a = p, *b;

		if (col >= r->ncols) {
			/* count the extra fields for the message */
			while (p < e)
				col += *p++ == d;
			return ragged(r, line, col + 1, diag);
		}
		if (r->cols[col].used) {
			double v;
			size_t n = ssc_parse_double(p, e, &v);

			b = p + n;
			if (!(n && (b == e || *b == d) && isfinite(v))) {
				/* slow path: find the cell's end, then judge */
				b = memchr(p, d, (size_t)(e - p));
				if (!b)
					b = e;
				p = b;
				rc = cell_value(r, line, col, &a, &b, &v, diag);
				if (rc)
					return rc;
			} else {
				p = b;
			}
			put_cell(r, &r->cols[col], ch, row, a, b, v);
		} else {
			const char *q = memchr(p, d, (size_t)(e - p));

			p = q ? q : e;
		}
		col++;
		if (p >= e)
			break;
		p++; /* the delimiter */
	}
	return col == r->ncols ? 0 : ragged(r, line, col, diag);
}

/* bytes of a 64-bit word equal to the byte in every lane of pat: the high
 * bit of each such byte (exact, no false positives) */
static inline uint64_t eq_bytes(uint64_t w, uint64_t pat)
{
	const uint64_t lo7 = 0x7f7f7f7f7f7f7f7full;
	uint64_t x = w ^ pat;

	return ~(((x & lo7) + lo7) | x | lo7);
}

#define BYTES(c) (0x0101010101010101ull * (unsigned char)(c))
#define ALWAYS_INLINE inline __attribute__((always_inline))

/*
 * Fast path of the data lines: the positions of the delimiters and
 * newlines are found 64 bytes at a time as a bit mask (the structural
 * index of simdjson: Langdale and Lemire, "Parsing gigabytes of JSON per
 * second", VLDB Journal 2019), so every cell's extent is known before it
 * is converted and the conversions of successive cells overlap in the
 * processor instead of waiting for each other.  Cells of columns nobody
 * asked for cost one bit each.
 */
struct sepscan {
	const char *blk; /* 64 bytes scanned */
	uint64_t m;      /* bit i: blk[i] is a separator not yet consumed */
	uint64_t nl;     /* bit i: blk[i] is a newline */
};

#ifdef __SSE2__
/* sep_mask() with AVX2: 32 bytes a comparison */
__attribute__((target("avx2"))) static inline uint64_t
sep_mask_avx2(const char *p, char d, uint64_t *nl)
{
	const __m256i vd = _mm256_set1_epi8(d), vn = _mm256_set1_epi8('\n');
	__m256i x0 = _mm256_loadu_si256((const __m256i *)(const void *)p);
	__m256i x1 = _mm256_loadu_si256((const __m256i *)(const void *)(p + 32));
	__m256i n0 = _mm256_cmpeq_epi8(x0, vn), n1 = _mm256_cmpeq_epi8(x1, vn);
	uint64_t m0 = (uint32_t)_mm256_movemask_epi8(
		_mm256_or_si256(_mm256_cmpeq_epi8(x0, vd), n0));
	uint64_t m1 = (uint32_t)_mm256_movemask_epi8(
		_mm256_or_si256(_mm256_cmpeq_epi8(x1, vd), n1));

	*nl = (uint32_t)_mm256_movemask_epi8(n0) |
	      (uint64_t)(uint32_t)_mm256_movemask_epi8(n1) << 32;
	return m0 | m1 << 32;
}
#endif

/* bit i set when p[i] is d or a newline, 0 <= i < 64; *nl the newlines;
 * avx2: the processor has it (the caller is compiled for it) */
static ALWAYS_INLINE uint64_t sep_mask(const char *p, char d, uint64_t *nl,
				       bool avx2)
{
	uint64_t m = 0, n = 0;
#ifdef __SSE2__
	const __m128i vd = _mm_set1_epi8(d), vn = _mm_set1_epi8('\n');

	if (avx2)
		return sep_mask_avx2(p, d, nl);

	for (unsigned k = 0; k < 4; k++) {
		__m128i x = _mm_loadu_si128((const __m128i *)(const void *)(p + 16 * k));
		__m128i isn = _mm_cmpeq_epi8(x, vn);

		m |= (uint64_t)(unsigned)_mm_movemask_epi8(
			     _mm_or_si128(_mm_cmpeq_epi8(x, vd), isn))
		     << (16 * k);
		n |= (uint64_t)(unsigned)_mm_movemask_epi8(isn) << (16 * k);
	}
#else
	const uint64_t pd = BYTES(d), pn = BYTES('\n');

	(void)avx2;

	for (unsigned k = 0; k < 8; k++) {
		uint64_t w, hd, hn;

		memcpy(&w, p + 8 * k, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
		w = __builtin_bswap64(w);
#endif
		hd = eq_bytes(w, pd) >> 7;
		hn = eq_bytes(w, pn) >> 7;
		/* gather the lowest bit of each byte into one byte */
		m |= (((hd | hn) * 0x0102040810204080ull) >> 56) << (8 * k);
		n |= ((hn * 0x0102040810204080ull) >> 56) << (8 * k);
	}
#endif
	*nl = n;
	return m;
}

/* The next separator, or NULL when the next 64 bytes are not all before
 * end (the scan is then spent). */
static ALWAYS_INLINE const char *next_sep(struct sepscan *sc,
					  const char *end, char d, bool hw)
{
	const char *b;

	while (!sc->m) {
		sc->blk += 64;
		if (end - sc->blk < 64)
			return NULL;
		sc->m = sep_mask(sc->blk, d, &sc->nl, hw);
	}
	b = sc->blk + __builtin_ctzll(sc->m);
	sc->m &= sc->m - 1;
	return b;
}

/* The value of the plain decimal cell [a, e), with the 16 bytes before e
 * readable, and its exact decimal (numparse.h); false for other cells. */
static ALWAYS_INLINE bool plain_cell(const char *a, const char *e, bool simd,
				     double *v, int64_t *m, int *f)
{
#ifdef SSC_HAVE_PARSE_CELL_SSSE3
	if (simd)
		return ssc_parse_cell_ssse3(e, (size_t)(e - a), v, m, f);
#endif
	(void)simd;
#ifdef SSC_HAVE_PARSE_CELL
	return ssc_parse_cell(e, (size_t)(e - a), v, m, f);
#else
	(void)a, (void)e, (void)v, (void)m, (void)f;
	return false;
#endif
}

/* Convert the cell [a, e) of a column in use when it is a plain finite
 * number; false sends the line to the careful path. */
static ALWAYS_INLINE bool fast_cell(const struct sscope_reader *r,
				   const struct colx *c,
				   struct sscope_reader_chunk *ch, size_t row,
				   const char *a, const char *e, bool simd)
{
	double v;
	int64_t m;
	int f;
	size_t n;

	if (e - r->base >= 16 && c->is_time && c->dest < 0 && !c->is_temp &&
	    plain_cell(a, e, simd, NULL, &m, &f)) {
		/* a time column read for its time alone: its value is needed
		 * only when the stamps' decimals differ */
		double dt;

		if (!time_exact(r, m, -f, &dt)) {
			if (!m) /* (the sign of a zero) */
				goto value;
			ssc_cell_value((uint64_t)(m < 0 ? -m : m), (unsigned)f,
				       m < 0, &v, &m, &f);
			dt = v - r->t0_double;
		}
		if (ch->time_s)
			ch->time_s[row] = dt * c->c.unit.scale;
		return true;
	}
value:
	if (e - r->base >= 16 && plain_cell(a, e, simd, &v, &m, &f)) {
		if (c->dest >= 0 && ch->data[c->dest])
			ch->data[c->dest][row] =
				v * c->c.unit.scale + c->c.unit.offset;
		if (c->is_time && ch->time_s)
			ch->time_s[row] = time_since(r, true, m, -f, v) *
					  c->c.unit.scale;
		if (c->is_temp && ch->temp_degc)
			ch->temp_degc[row] =
				v * c->c.unit.scale + c->c.unit.offset;
		return true;
	}
	n = ssc_parse_double(a, e, &v);
	if (!n || n != (size_t)(e - a) || !isfinite(v))
		return false;
	put_cell(r, c, ch, row, a, e, v);
	return true;
}

/* One line at p whose cells are all plain numbers, the line ending with
 * '\n' (CR LF too): returns the start of the next line, or NULL to let the
 * careful path (messages, blanks, NaN, comments) handle the line -- it
 * rewrites the whole row. */
/* bits set in x (without the popcnt instruction, which SSSE3 processors
 * may lack, and without a library call) */
static ALWAYS_INLINE size_t bits64(uint64_t x, bool hw)
{
	if (hw)
		return (size_t)__builtin_popcountll(x);
	x -= (x >> 1) & 0x5555555555555555ull;
	x = (x & 0x3333333333333333ull) + ((x >> 2) & 0x3333333333333333ull);
	x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0full;
	return (size_t)((x * 0x0101010101010101ull) >> 56);
}

/* Past the last column in use: the rest of the line is k separators, k - 1
 * delimiters then the newline, counted from the masks without visiting
 * them; the start of the next line, or NULL as next_sep. */
static ALWAYS_INLINE const char *skip_rest(struct sepscan *sc,
					   const char *end, char d, size_t k,
					   bool hw)
{
	for (;;) {
		uint64_t nl = sc->nl & sc->m;

		if (nl) {
			uint64_t upto = (nl & -nl) - 1; /* bits below the newline */

			if (bits64(sc->m & upto, hw) != k - 1)
				return NULL; /* ragged: the careful path says so */
			sc->m &= ~(upto | (upto + 1));
			return sc->blk + __builtin_ctzll(nl) + 1;
		}
		/* only delimiters left in this block */
		if (bits64(sc->m, hw) > k - 1)
			return NULL;
		k -= bits64(sc->m, hw);
		sc->m = 0;
		sc->blk += 64;
		if (end - sc->blk < 64)
			return NULL;
		sc->m = sep_mask(sc->blk, d, &sc->nl, hw);
	}
}

static ALWAYS_INLINE const char *
scan_line(const struct sscope_reader *r, struct sepscan *sc, const char *p,
	  const char *end, struct sscope_reader_chunk *ch, size_t row, bool simd,
	  bool hw, size_t n_used)
{
	const char d = r->delim;
	const size_t last = r->ncols - 1;

	for (size_t col = 0; col < n_used; col++) {
		const char *b = next_sep(sc, end, d, hw), *e;

		if (!b || *b != (col < last ? d : '\n'))
			return NULL;
		if (r->cols[col].used) {
			e = b;
			if (col == last && e > p && e[-1] == '\r')
				e--;
			if (!fast_cell(r, &r->cols[col], ch, row, p, e, simd))
				return NULL;
		}
		p = b + 1;
	}
	return n_used > last ? p :
	       skip_rest(sc, end, d, last + 1 - n_used, hw);
}

static bool skip_line(const char *p, const char *e)
{
	while (p < e && blank(*p))
		p++;
	return p >= e || *p == '#';
}

/* Parse rows from [p, end) into ch starting at row `row` until max_rows are
 * filled or the text ends.  A final line without newline is parsed only
 * when `eof`.  *line counts lines; *stop receives where parsing stopped. */
static ALWAYS_INLINE int
parse_rows_with(const struct sscope_reader *r, const char *p, const char *end,
		bool eof, size_t *line, struct sscope_reader_chunk *ch, size_t row,
		size_t max_rows, size_t *rows_out, const char **stop,
		struct sscope_diag *diag, bool simd, bool hw)
{
	size_t n = 0, ln = *line, n_used = 0;
	struct sepscan sc = { 0 };
	bool synced = false;
	int rc = 0;

	/* the columns up to the last one in use are visited cell by cell */
	for (size_t c = 0; c < r->ncols; c++)
		if (r->cols[c].used)
			n_used = c + 1;
	while (n < max_rows && p < end) {
		const char *e, *next;

		if (r->delim != ' ') {
			if (!synced && end - p >= 64) {
				sc.blk = p;
				sc.m = sep_mask(p, r->delim, &sc.nl, hw);
				synced = true;
			}
			if (synced &&
			    (next = scan_line(r, &sc, p, end, ch, row + n,
					       simd, hw, n_used))) {
				ln++;
				n++;
				p = next;
				continue;
			}
			synced = false;
		}
		e = memchr(p, '\n', (size_t)(end - p));
		if (!e) {
			if (!eof)
				break;
			e = end;
			next = end;
		} else {
			next = e + 1;
		}
		ln++;
		if (!skip_line(p, e)) {
			rc = parse_line(r, p, e, ln, ch, row + n, diag);
			if (rc)
				break;
			n++;
		}
		p = next;
	}
	*line = ln;
	*rows_out = n;
	*stop = p;
	return rc;
}

static int parse_rows_plain(const struct sscope_reader *r, const char *p,
			    const char *end, bool eof, size_t *line,
			    struct sscope_reader_chunk *ch, size_t row,
			    size_t max_rows, size_t *rows_out,
			    const char **stop, struct sscope_diag *diag)
{
	return parse_rows_with(r, p, end, eof, line, ch, row, max_rows,
			       rows_out, stop, diag, false, false);
}

#ifdef SSC_HAVE_PARSE_CELL_SSSE3
__attribute__((target("ssse3"))) static int
parse_rows_ssse3(const struct sscope_reader *r, const char *p,
		 const char *end, bool eof, size_t *line,
		 struct sscope_reader_chunk *ch, size_t row, size_t max_rows,
		 size_t *rows_out, const char **stop, struct sscope_diag *diag)
{
	return parse_rows_with(r, p, end, eof, line, ch, row, max_rows,
			       rows_out, stop, diag, true, false);
}

/* the same with AVX2 and the population count instruction */
__attribute__((target("avx2,popcnt"))) static int
parse_rows_avx2(const struct sscope_reader *r, const char *p,
		const char *end, bool eof, size_t *line,
		struct sscope_reader_chunk *ch, size_t row, size_t max_rows,
		size_t *rows_out, const char **stop, struct sscope_diag *diag)
{
	return parse_rows_with(r, p, end, eof, line, ch, row, max_rows,
			       rows_out, stop, diag, true, true);
}
#endif

/* The same, with the processor's byte shuffles when it has them. */
static int parse_rows(const struct sscope_reader *r, const char *p,
		      const char *end, bool eof, size_t *line,
		      struct sscope_reader_chunk *ch, size_t row, size_t max_rows,
		      size_t *rows_out, const char **stop,
		      struct sscope_diag *diag)
{
#ifdef SSC_HAVE_PARSE_CELL_SSSE3
	if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt"))
		return parse_rows_avx2(r, p, end, eof, line, ch, row,
				       max_rows, rows_out, stop, diag);
	if (__builtin_cpu_supports("ssse3"))
		return parse_rows_ssse3(r, p, end, eof, line, ch, row,
					max_rows, rows_out, stop, diag);
#endif
	return parse_rows_plain(r, p, end, eof, line, ch, row, max_rows,
				rows_out, stop, diag);
}

/* The time origin is the first data row's time cell; find it before
 * parsing so that parsing can be split between threads. */
static int init_t0(struct sscope_reader *r, struct sscope_diag *diag)
{
	const char *p = r->base + r->pos, *end = r->base + r->len;
	size_t ln = r->line;

	if (r->time_col < 0 || r->have_t0)
		return 0;
	while (p < end) {
		const char *e = memchr(p, '\n', (size_t)(end - p)), *a, *b;
		size_t col = 0;
		double v;
		int rc;

		if (!e)
			e = end;
		ln++;
		if (skip_line(p, e)) {
			p = e + (e < end);
			continue;
		}
		if (e > p && e[-1] == '\r')
			e--;
		/* walk to the time cell */
		a = p;
		for (;;) {
			if (r->delim == ' ')
				while (a < e && blank(*a))
					a++;
			b = a;
			if (r->delim == ' ')
				while (b < e && !blank(*b))
					b++;
			else
				while (b < e && *b != r->delim)
					b++;
			if ((long)col == r->time_col || b >= e)
				break;
			a = b + 1;
			col++;
		}
		if ((long)col != r->time_col)
			return 0; /* ragged: reported by the parser */
		rc = cell_value(r, ln, col, &a, &b, &v, diag);
		if (rc)
			return rc;
		set_t0(r, a, b, v);
		return 0;
	}
	return 0;
}

static int read_text(struct sscope_reader *r, struct sscope_reader_chunk *ch,
		     struct sscope_diag *diag)
{
	size_t row = 0;
	int rc;

	rc = init_t0(r, diag);
	if (rc)
		return rc;
	while (row < ch->capacity) {
		const char *p = r->base + r->pos, *stop;
		size_t got;

		rc = parse_rows(r, p, r->base + r->len, r->eof, &r->line, ch,
				row, ch->capacity - row, &got, &stop, diag);
		r->pos = (size_t)(stop - r->base);
		row += got;
		if (rc)
			return rc;
		if (r->pos >= r->len && r->eof)
			break;
		if (row < ch->capacity) {
			/* an incomplete last line: read more of the pipe */
			rc = src_fill(r, r->len - r->pos + BLOCK, diag);
			if (rc)
				return rc;
			if (!r->have_t0) {
				rc = init_t0(r, diag);
				if (rc)
					return rc;
			}
		}
	}
	ch->rows = row;
	progress(r);
	return 0;
}

/* ---- whole mapped file on several threads */

struct part {
	const struct sscope_reader *r;
	const char *from, *to;
	size_t line0;        /* lines before `from` */
	size_t row0;         /* first row it writes */
	size_t nl;           /* newlines in it */
	size_t cap;          /* rows it may write */
	struct sscope_reader_chunk *ch;
	size_t rows;
	size_t line_err;
	bool counted;        /* nl known before parsing */
	const char *pop_from, *pop_to; /* counting: pages to map as well */
	int rc;
	struct sscope_diag diag;
};

static void *part_run(void *arg)
{
	struct part *pt = arg;
	const char *stop;
	size_t line = pt->line0;

	pt->rc = parse_rows(pt->r, pt->from, pt->to, true, &line, pt->ch,
			    pt->row0, pt->cap, &pt->rows, &stop, &pt->diag);
	if (!pt->counted && !pt->rc)
		/* its newlines: the lines parsed, less an unterminated last */
		pt->nl = line - pt->line0 -
			 (pt->to > pt->from && pt->to[-1] != '\n');
	return NULL;
}

static size_t count_nl(const char *p, const char *end)
{
	size_t n = 0;
#ifdef __SSE2__
	/* byte counters (each compare adds 0 or 1, at most 255 times), then
	 * summed by the sum of absolute differences */
	const __m128i nl = _mm_set1_epi8('\n'), zero = _mm_setzero_si128();

	while (end - p >= 16) {
		__m128i acc = zero, sums;
		size_t k = 0;

		for (; k < 255 && end - p >= 16; k++, p += 16)
			acc = _mm_sub_epi8(acc, _mm_cmpeq_epi8(_mm_loadu_si128(
						(const __m128i *)(const void *)p),
						nl));
		sums = _mm_sad_epu8(acc, zero);
		n += (size_t)_mm_cvtsi128_si32(sums) +
		     (size_t)_mm_cvtsi128_si32(_mm_srli_si128(sums, 8));
	}
#endif
	while ((p = memchr(p, '\n', (size_t)(end - p)))) {
		n++;
		p++;
	}
	return n;
}

#ifdef __SSE2__
/* count_nl() with AVX2 */
__attribute__((target("avx2"))) static size_t count_nl_avx2(const char *p,
							    const char *end)
{
	const __m256i nl = _mm256_set1_epi8('\n'), zero = _mm256_setzero_si256();
	size_t n = 0;

	while (end - p >= 32) {
		__m256i acc = zero, sums;
		size_t k = 0;

		for (; k < 255 && end - p >= 32; k++, p += 32)
			acc = _mm256_sub_epi8(acc, _mm256_cmpeq_epi8(
					_mm256_loadu_si256((const __m256i *)(const void *)p),
					nl));
		sums = _mm256_sad_epu8(acc, zero);
		n += (size_t)_mm256_extract_epi64(sums, 0) +
		     (size_t)_mm256_extract_epi64(sums, 1) +
		     (size_t)_mm256_extract_epi64(sums, 2) +
		     (size_t)_mm256_extract_epi64(sums, 3);
	}
	return n + count_nl(p, end);
}
#endif

static void *count_run(void *arg)
{
	struct part *pt = arg;

	/* the pages counted, mapped in one call (a fault per 64 KiB costs
	 * about as much as the counting on a virtual machine), unless the
	 * whole file was mapped so */
	if (pt->r->map_len > (size_t)MAP_POPULATE_MAX)
		ssc_prefault_read(pt->from, (size_t)(pt->to - pt->from));
#ifdef __SSE2__
	if (__builtin_cpu_supports("avx2"))
		pt->nl = count_nl_avx2(pt->from, pt->to);
	else
#endif
		pt->nl = count_nl(pt->from, pt->to);
#ifdef MADV_POPULATE_READ
	if (pt->pop_to > pt->pop_from) {
		/* from the page holding pop_from (the mapping starts on one) */
		size_t a = (size_t)(pt->pop_from - pt->r->base) &
			   ~(pt->r->pagesz - 1);

		madvise((void *)(uintptr_t)(pt->r->base + a),
			(size_t)(pt->pop_to - pt->r->base) - a,
			MADV_POPULATE_READ);
	}
#endif
	return NULL;
}

enum { MAXP = 8, PIECES = 4 };

struct pool {
	struct part *parts;
	size_t n;
	atomic_size_t next; /* the next part not yet taken */
	void *(*fn)(void *);
};

static void *pool_run(void *arg)
{
	struct pool *p = arg;

	for (;;) {
		size_t k = atomic_fetch_add(&p->next, 1);

		if (k >= p->n)
			return NULL;
		p->fn(&p->parts[k]);
	}
}

/* Run fn on every part on up to `threads` threads, the calling one among
 * them, each taking the next part not yet taken (the calling thread alone
 * when no other starts). */
static void run_parts(struct part *parts, size_t np, size_t threads,
		      void *(*fn)(void *))
{
	pthread_t tid[MAXP];
	struct pool p = { .parts = parts, .n = np, .fn = fn };
	size_t started = 0;

	atomic_init(&p.next, 0);
	if (threads > np)
		threads = np;
	for (size_t k = 1; k < threads && k < MAXP; k++) {
		if (pthread_create(&tid[started], NULL, pool_run, &p))
			break;
		started++;
	}
	pool_run(&p);
	for (size_t k = 0; k < started; k++)
		pthread_join(tid[k], NULL);
}

/*
 * Newlines of the parts, for the row each part starts at.  The last part
 * need not be counted: its rows go after all others, into arrays sized by
 * a bound on its rows, and its parse counts its lines.  The bound costs
 * address space only (pages never written are never backed), taken when
 * it is at most twice the input's size; otherwise every part is counted.
 * The counting is spread over all the threads, in pieces; they also map
 * the last part's pages (which counting would otherwise leave to its parse
 * alone, the other parts' threads waiting for it).
 */
static void count_parts(struct sscope_reader *r, size_t np, size_t nthr)
{
	struct part *last = &r->parts[np - 1], job[PIECES * MAXP];
	size_t arrays = r->nsel + (r->time_col >= 0) + (r->temp_col >= 0), bound, nc;

	bound = (size_t)(last->to - last->from) / r->ncols + 1;
	nc = np > 1 && arrays && bound <= 2 * r->len / (arrays * sizeof(double)) ?
		     np - 1 : np;
	/* PIECES pieces a part, taken in turn by the threads (one held back
	 * by the system leaves its share to the others) */
	for (size_t k = 0; k < nc; k++) {
		const char *a = r->parts[k].from, *b = r->parts[k].to;

		for (size_t i = 0; i < PIECES; i++)
			job[PIECES * k + i] = (struct part){
				.r = r, .from = a + (b - a) * i / PIECES,
				.to = a + (b - a) * (i + 1) / PIECES
			};
	}
	for (size_t k = 0; nc < np && k < PIECES * nc; k++) {
		size_t len = (size_t)(last->to - last->from);

		job[k].pop_from = last->from + len * k / (PIECES * nc);
		job[k].pop_to = last->from + len * (k + 1) / (PIECES * nc);
	}
	run_parts(job, PIECES * nc, nthr, count_run);
	for (size_t k = 0; k < np; k++) {
		r->parts[k].counted = k < nc;
		r->parts[k].nl = 0;
		for (size_t i = 0; k < nc && i < PIECES; i++)
			r->parts[k].nl += job[PIECES * k + i].nl;
	}
}

size_t ssc_reader_max_rows(struct sscope_reader *r, unsigned threads)
{
	const char *base, *end;
	size_t np, total = 0;

	if (r->kind == K_MAT)
		return ssc_mat_rows(r->mat) - r->mat_row;
	if (r->kind == K_TABLE)
		return r->tab->nrows - r->tab_row;
	if (r->kind != K_TEXT) {
		if (!r->size || !r->mapped)
			return 0;
		return (r->len - r->pos) / (r->ncols * r->rsize);
	}
	if (!r->mapped)
		return 0;
	r->nthr = threads < 1 ? 1 : threads > MAXP ? MAXP : threads;
	if (r->len - r->pos < (8u << 20))
		r->nthr = 1;
	/* on several threads, parts of at least 4 MiB, up to four per
	 * thread: one held back by another process leaves its parts to
	 * the others */
	np = r->nthr;
	if (np > 1 && ((r->len - r->pos) >> 22) > np)
		np = ((r->len - r->pos) >> 22) < 4 * np ? (r->len - r->pos) >> 22 : 4 * np;
	if (np > MAXP)
		np = MAXP;
	free(r->parts);
	r->parts = calloc(np, sizeof(*r->parts));
	if (!r->parts)
		return 0;
	r->np = np;
	r->split_pos = r->pos;
	base = r->base + r->pos;
	end = r->base + r->len;
	/* cut at line boundaries; the first touch of the mapped pages (page
	 * faults) happens while counting, on every thread */
	for (size_t k = 0; k < np; k++) {
		const char *from = k ? r->parts[k - 1].to : base, *to;

		if (k == np - 1) {
			to = end;
		} else {
			to = base + (size_t)(end - base) * (k + 1) / np;
			to = memchr(to, '\n', (size_t)(end - to));
			to = to ? to + 1 : end;
		}
		if (to < from)
			to = from;
		r->parts[k] = (struct part){ .r = r, .from = from, .to = to,
					     .diag = { "" } };
	}
	count_parts(r, np, r->nthr);
	for (size_t k = 0; k < np; k++) {
		struct part *pt = &r->parts[k];

		/* every part but the last ends with a newline; the last, when
		 * not counted, holds at most one row per ncols bytes (a row
		 * is at least its delimiters and newline) */
		pt->cap = pt->counted ? pt->nl + (k == np - 1) :
					(size_t)(pt->to - pt->from) / r->ncols + 1;
		pt->line0 = k ? r->parts[k - 1].line0 + r->parts[k - 1].nl : r->line;
		pt->row0 = total;
		total += pt->cap;
	}
	return total;
}

int ssc_reader_read_all(struct sscope_reader *r, struct sscope_reader_chunk *ch,
			struct sscope_diag *diag)
{
	struct part *parts = r->parts;
	size_t np = r->np, row = 0;
	int rc;

	if (r->kind != K_TEXT || !parts || np < 2 || r->split_pos != r->pos ||
	    parts[np - 1].row0 + parts[np - 1].cap > ch->capacity)
		return sscope_reader_read(r, ch, diag);
	rc = init_t0(r, diag);
	if (rc)
		return rc;
	for (size_t k = 0; k < np; k++)
		parts[k].ch = ch;
	run_parts(parts, np, r->nthr, part_run);
	for (size_t k = 0; k < np; k++) {
		if (parts[k].rc) {
			if (diag)
				*diag = parts[k].diag;
			return parts[k].rc;
		}
	}
	/* close up: a part with comment or blank lines wrote fewer rows than
	 * its bound */
	for (size_t k = 0; k < np; k++) {
		if (parts[k].row0 != row) {
			for (size_t c = 0; c < r->nsel; c++)
				if (ch->data[c])
					memmove(ch->data[c] + row,
						ch->data[c] + parts[k].row0,
						parts[k].rows * sizeof(double));
			if (ch->time_s)
				memmove(ch->time_s + row, ch->time_s + parts[k].row0,
					parts[k].rows * sizeof(double));
			if (ch->temp_degc)
				memmove(ch->temp_degc + row,
					ch->temp_degc + parts[k].row0,
					parts[k].rows * sizeof(double));
		}
		row += parts[k].rows;
	}
	r->pos = r->len;
	r->line = parts[np - 1].line0 + parts[np - 1].nl;
	ch->rows = row;
	if (r->opts->progress)
		r->opts->progress(r->opts->progress_ctx, r->size, r->size);
	return 0;
}

static double raw_value(const struct sscope_reader *r, const unsigned char *b)
{
	unsigned char t[8];
	size_t n = r->rsize;
	bool swap = r->big_endian;

	for (size_t i = 0; i < n; i++)
		t[i] = b[swap ? n - 1 - i : i];
	switch (r->rtype) {
	case R_I16: {
		int16_t v;

		memcpy(&v, t, 2);
		return v;
	}
	case R_U16: {
		uint16_t v;

		memcpy(&v, t, 2);
		return v;
	}
	case R_I24: {
		int32_t v = (int32_t)((uint32_t)t[0] | (uint32_t)t[1] << 8 |
				      (uint32_t)t[2] << 16);

		if (v & 0x800000)
			v -= 0x1000000;
		return v;
	}
	case R_I32: {
		int32_t v;

		memcpy(&v, t, 4);
		return v;
	}
	case R_U32: {
		uint32_t v;

		memcpy(&v, t, 4);
		return v;
	}
	case R_F32: {
		float v;

		memcpy(&v, t, 4);
		return v;
	}
	case R_F64:
	default: {
		double v;

		memcpy(&v, t, 8);
		return v;
	}
	}
}

/*
 * Fast path of binary rows in the host's byte order: the block of `rows`
 * whole rows at b is converted column by column (loops the compiler
 * vectorises), with the same arithmetic as the row-by-row path.  Returns
 * false, having written nothing that matters, when a value is not finite:
 * the careful path then redoes the block (gaps, messages).
 */
static bool convert_block(struct sscope_reader *r, const unsigned char *b,
			  size_t rows, struct sscope_reader_chunk *ch, size_t row)
{
	const size_t rowb = r->ncols * r->rsize;
	const double off = r->roffset, sc = r->rscale;

	for (size_t c = 0; c < r->ncols; c++) {
		const struct colx *cx = &r->cols[c];
		const unsigned char *p = b + c * r->rsize;
		double *out[3] = { NULL, NULL, NULL };
		double mul[3], add[3];
		int bad = 0;

		if (!cx->used)
			continue;
		if (cx->dest >= 0 && ch->data[cx->dest]) {
			out[0] = ch->data[cx->dest] + row;
			mul[0] = cx->c.unit.scale;
			add[0] = cx->c.unit.offset;
		}
		if (cx->is_time) {
			if (!r->have_t0) {
				double v0 = (raw_value(r, p) + off) * sc;

				if (!isfinite(v0))
					return false;
				r->have_t0 = true;
				r->t0_double = v0;
				r->t0_exp = 1000;
			}
			if (ch->time_s)
				out[1] = ch->time_s + row;
		}
		if (cx->is_temp && ch->temp_degc) {
			out[2] = ch->temp_degc + row;
			mul[2] = cx->c.unit.scale;
			add[2] = cx->c.unit.offset;
		}
		for (int k = 0; k < 3; k++) {
			double *o = out[k];
			const double t0 = r->t0_double, us = cx->c.unit.scale;

			if (!o)
				continue;
#define CONV(T)                                                                \
	for (size_t i = 0; i < rows; i++) {                                    \
		T t;                                                           \
		double v;                                                      \
                                                                               \
		memcpy(&t, p + i * rowb, sizeof(t));                           \
		v = ((double)t + off) * sc;                                    \
		bad |= !(fabs(v) <= DBL_MAX);                                  \
		o[i] = k == 1 ? (v - t0) * us : v * mul[k] + add[k];           \
	}
			switch (r->rtype) {
			case R_F64:
				CONV(double);
				break;
			case R_F32:
				CONV(float);
				break;
			case R_I16:
				CONV(int16_t);
				break;
			case R_U16:
				CONV(uint16_t);
				break;
			case R_I32:
				CONV(int32_t);
				break;
			case R_U32:
				CONV(uint32_t);
				break;
			default:
				return false;
			}
#undef CONV
			if (bad)
				return false;
		}
	}
	return true;
}

/* Give back the pages of a mapped file that the reader has passed: a
 * streamed record then holds only its chunk in memory (the pages stay in
 * the page cache). */
static void drop_behind(struct sscope_reader *r)
{
	size_t to;

	if (!r->mapped || !r->pagesz)
		return;
	to = r->pos / r->pagesz * r->pagesz;
	if (to >= r->dropped + (4u << 20)) {
		madvise((char *)r->base + r->dropped, to - r->dropped,
			MADV_DONTNEED);
		r->dropped = to;
	}
}

static bool host_order(const struct sscope_reader *r)
{
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
	return !r->big_endian;
#elif defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
	return r->big_endian;
#else
	(void)r;
	return false;
#endif
}

/* whether x[0..n) holds only finite values, on vectors where available */
static bool all_finite(const double *x, size_t n)
{
	double z = 0;
	size_t i = 0;

#if defined(__GNUC__)
	typedef double v4 __attribute__((vector_size(32)));
	v4 a = { 0 }, b = { 0 };

	for (; i + 8 <= n; i += 8) {
		v4 u, w;

		memcpy(&u, x + i, sizeof(u));
		memcpy(&w, x + i + 4, sizeof(w));
		a += u * 0.0;
		b += w * 0.0;
	}
	a += b;
	z = (a[0] + a[1]) + (a[2] + a[3]);
#endif
	for (; i < n; i++)
		z += x[i] * 0.0;
	return z == 0;
}

/* all_finite over blocks on the OpenMP threads: the pass reads the whole
 * record and ran on one core while the other waited.  Each thread maps
 * the pages of its blocks first (page tables in one call per block
 * instead of a fault per 64 KiB; x is page-aligned, blocks are whole
 * pages). */
static bool all_finite_par(const double *x, size_t n)
{
	const size_t blk = (size_t)1 << 18;
	long nb = (long)((n + blk - 1) / blk);
	bool ok = true;

	(void)nb;
SSC_OMP(omp parallel for schedule(dynamic, 1) reduction(&& : ok) if (nb > 1))
	for (long b = 0; b < nb; b++) {
		size_t a = (size_t)b * blk, len = n - a < blk ? n - a : blk;

#ifdef MADV_POPULATE_READ
		madvise((void *)(uintptr_t)(x + a), len * sizeof(double),
			MADV_POPULATE_READ);
#endif
		if (ok)
			ok = all_finite(x + a, len);
	}
	return ok;
}

bool ssc_reader_take_inplace(struct sscope_reader *r, bool allow_nan,
			     bool unchecked, double **x, size_t *n,
			     size_t *n_nan, void **map, size_t *map_len)
{
	const struct colx *c = r->ncols == 1 ? &r->cols[0] : NULL;
	const double *v = (const double *)r->base;
	size_t len, nn = 0, ninf = 0;
	void *base = (void *)r->base;

	if (r->kind != K_RAW || !r->mapped || r->rtype != R_F64 ||
	    !host_order(r) || !c || r->nsel != 1 || c->dest != 0 ||
	    c->is_time || c->is_temp || r->rscale != 1 || r->roffset != 0 ||
	    c->c.unit.scale != 1 || c->c.unit.offset != 0 || r->pos != 0 ||
	    r->len % sizeof(double) || ((uintptr_t)base & 63))
		return false;
	len = r->len / sizeof(double);
	/* NaN (a gap, if allowed) and infinities, counted in one pass when
	 * a quick one finds any (0 * x is 0 for every finite x) */
	if (!unchecked && !all_finite_par(v, len))
		for (size_t i = 0; i < len; i++) {
			nn += v[i] != v[i];
			ninf += fabs(v[i]) > DBL_MAX;
		}
	if (ninf || (nn && !allow_nan))
		return false; /* the row-by-row path reports it */
	madvise(base, r->len, MADV_NORMAL);
	*x = (double *)base;
	*n = len;
	*n_nan = nn;
	*map = base;
	*map_len = r->len;
	r->mapped = false; /* the caller unmaps it */
	r->base = NULL;
	r->pos = r->len = 0;
	return true;
}

int ssc_raw_value_error(struct sscope_diag *diag, const char *disp,
			size_t row, size_t col, const char *name, double v,
			bool is_time)
{
	if (isnan(v))
		return ssc_diag(diag, -EBADMSG, "%s: row %zu, column %zu (%s): NaN%s",
				disp, row, col, name,
				is_time ? " time stamp" :
				" (use --allow-nan to read gaps)");
	return ssc_diag(diag, -EBADMSG,
			"%s: row %zu, column %zu (%s): infinite value", disp,
			row, col, name);
}

static int read_binary(struct sscope_reader *r, struct sscope_reader_chunk *ch,
		       struct sscope_diag *diag)
{
	size_t rowb = r->ncols * r->rsize, row = 0, slow = 0;
	const bool fast = host_order(r) && r->rtype != R_I24;
	int rc;

	while (row < ch->capacity) {
		const unsigned char *b;

		if (slow)
			slow--;
		else if (fast && r->len - r->pos >= rowb) {
			size_t rows = (r->len - r->pos) / rowb;

			if (rows > ch->capacity - row)
				rows = ch->capacity - row;
			/* blocks of at most 1 MiB: a failed block is redone */
			if (rows > (1u << 20) / rowb + 1)
				rows = (1u << 20) / rowb + 1;
			if (convert_block(r, (const unsigned char *)r->base + r->pos,
					  rows, ch, row)) {
				r->pos += rows * rowb;
				r->line += rows;
				row += rows;
				drop_behind(r);
				continue;
			}
			slow = rows; /* this block row by row */
		}

		if (r->len - r->pos < rowb) {
			if (!r->eof) {
				rc = src_fill(r, rowb * 4096, diag);
				if (rc)
					return rc;
				continue;
			}
			if (r->len != r->pos)
				return ssc_diag(diag, -EBADMSG,
						"%s: truncated: %zu bytes after the last whole row",
						r->disp, r->len - r->pos);
			break;
		}
		b = (const unsigned char *)r->base + r->pos;
		for (size_t c = 0; c < r->ncols; c++) {
			struct colx *cx = &r->cols[c];
			double v;

			if (!cx->used)
				continue;
			v = (raw_value(r, b + c * r->rsize) + r->roffset) * r->rscale;
			if ((isnan(v) && (!r->opts->nan_as_gap || cx->is_time)) ||
			    isinf(v))
				return ssc_raw_value_error(diag, r->disp,
							   r->line + 1, c + 1,
							   cx->name, v,
							   cx->is_time);
			if (cx->dest >= 0 && ch->data[cx->dest])
				ch->data[cx->dest][row] =
					v * cx->c.unit.scale + cx->c.unit.offset;
			if (cx->is_time) {
				if (!r->have_t0) {
					r->have_t0 = true;
					r->t0_double = v;
					r->t0_exp = 1000;
				}
				if (ch->time_s)
					ch->time_s[row] = (v - r->t0_double) *
							  cx->c.unit.scale;
			}
			if (cx->is_temp && ch->temp_degc)
				ch->temp_degc[row] = v * cx->c.unit.scale +
						     cx->c.unit.offset;
		}
		r->pos += rowb;
		r->line++;
		row++;
	}
	ch->rows = row;
	progress(r);
	return 0;
}

int sscope_reader_read(struct sscope_reader *r, struct sscope_reader_chunk *ch,
		       struct sscope_diag *diag)
{
	if (!r || !ch || (r->nsel && !ch->data))
		return ssc_diag(diag, -EINVAL, "bad chunk");
	ch->rows = 0;
	if (r->kind == K_TEXT)
		return read_text(r, ch, diag);
	if (r->kind == K_MAT)
		return read_mat(r, ch, diag);
	if (r->kind == K_TABLE)
		return read_table(r, ch, diag);
	return read_binary(r, ch, diag);
}
