/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Captures in memory: loading a whole capture through the chunked reader
 * (rows counted first on mapped files so the arrays are allocated once),
 * and constructing captures for generators and writers.
 */
#include "internal.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "io-formats.h"
#include "sscope-capture.h"
#include "sscope-quantity.h"
#include "sscope-reader.h"
#include "sscope-timing.h"
#include "sscope-unit.h"

static int copy_column(struct sscope_capture_column *dst, const struct sscope_capture_column *src)
{
	*dst = *src;
	dst->name = ssc_strdup(src->name);
	dst->unit_label = ssc_strdup(src->unit_label ? src->unit_label : "");
	return (dst->name && dst->unit_label) ? 0 : -ENOMEM;
}

static void free_column(struct sscope_capture_column *c)
{
	free((char *)c->name);
	free((char *)c->unit_label);
	c->name = NULL;
	c->unit_label = NULL;
}

static bool in_mapping(const struct sscope_capture *cap, const void *p)
{
	const char *m = cap->mapping;

	return m && (const char *)p >= m && (const char *)p < m + cap->mapping_len;
}

bool sscope_capture_mapped(const struct sscope_capture *cap, const double *x)
{
	return cap && x && in_mapping(cap, x);
}

int sscope_capture_check_values(const struct sscope_capture *cap,
				bool allow_nan, struct sscope_diag *diag)
{
	if (!cap || !cap->values_unchecked)
		return 0;
	for (size_t k = 0; k < cap->n_channels; k++) {
		const struct sscope_capture_channel *c = &cap->channels[k];

		for (size_t i = 0; i < cap->n; i++)
			if ((isnan(c->data[i]) && !allow_nan) || isinf(c->data[i]))
				return ssc_raw_value_error(diag, cap->source, i + 1,
							   c->col.index + 1,
							   c->col.name,
							   c->data[i], false);
	}
	return 0;
}

void sscope_capture_free(struct sscope_capture *cap)
{
	if (!cap)
		return;
	if (cap->is_view) {
		free(cap->channels);
		free(cap);
		return;
	}
	for (size_t k = 0; cap->channels && k < cap->n_channels; k++) {
		free_column(&cap->channels[k].col);
		if (!in_mapping(cap, cap->channels[k].data))
			free(cap->channels[k].data);
	}
	if (cap->mapping)
		munmap(cap->mapping, cap->mapping_len);
	free(cap->channels);
	free(cap->time_s);
	free(cap->temp_degc);
	free_column(&cap->time_col);
	free_column(&cap->temp_col);
	free(cap->source);
	free(cap->gaps);
	ssc_source_free(cap->source_info);
	free(cap);
}

/* rows up to which a capture's arrays are mapped before the parse */
#define PREFAULT_ROWS ((size_t)1 << 20)

/* one array to `bytes`, its large blocks on 2 MiB pages */
static int grow_array(double **a, size_t bytes)
{
	void *p = realloc(*a, bytes);

	if (!p)
		return -ENOMEM;
	*a = p;
	ssc_hint_huge(p, bytes);
	return 0;
}

/* (Re)allocate every array of the capture to hold `rows` rows. */
static int grow(struct sscope_capture *cap, size_t rows)
{
	size_t bytes;

	if (!ssc_mul(rows ? rows : 1, sizeof(double), &bytes))
		return -ENOMEM;
	for (size_t k = 0; k < cap->n_channels; k++)
		if (grow_array(&cap->channels[k].data, bytes))
			return -ENOMEM;
	if (cap->time_col.name && grow_array(&cap->time_s, bytes))
		return -ENOMEM;
	if (cap->temp_col.name && grow_array(&cap->temp_degc, bytes))
		return -ENOMEM;
	return 0;
}

/*
 * After the rows are read: every channel is checked for NaN (counted) and
 * for values infinite in SI units (an error, reported for the first such
 * channel and row), the time column is analysed (the two passes of
 * sscope_timing_split_*) and the reader closed (the file unmapped).  These
 * are tasks taken in turn by the calling thread and, on a long capture, a
 * second one, so that a thread the system holds back leaves its share to
 * the other; the results are those of doing it all in order.
 */
enum { TASK_SUMS, TASK_MEDIAN, TASK_CLOSE, TASK_CHANNEL };

struct finish {
	struct sscope_capture *cap;
	size_t n;
	bool timed;
	struct sscope_timing_split sp;
	double *scratch;
	atomic_size_t next;  /* the next task */
	size_t *inf_row;     /* per channel: the first infinite row, or SIZE_MAX */
	struct sscope_reader *r;
};

static void check_channel(struct finish *f, size_t k)
{
	const double *d = f->cap->channels[k].data;
	size_t nan = 0, i;

	for (i = 0; i < f->n; i++) {
		nan += isnan(d[i]);
		if (isinf(d[i]))
			break;
	}
	f->inf_row[k] = i < f->n ? i : SIZE_MAX;
	f->cap->channels[k].n_nan = nan;
}

static void *finish_run(void *arg)
{
	struct finish *f = arg;

	for (;;) {
		size_t k = atomic_fetch_add(&f->next, 1);

		if (k == TASK_SUMS && f->timed)
			sscope_timing_split_sums(&f->sp, f->cap->time_s, f->n);
		else if (k == TASK_MEDIAN && f->timed)
			sscope_timing_split_median(&f->sp, f->cap->time_s, f->n,
						   f->scratch);
		else if (k == TASK_CLOSE)
			sscope_reader_close(f->r);
		else if (k >= TASK_CHANNEL + f->cap->n_channels)
			return NULL;
		else if (k >= TASK_CHANNEL)
			check_channel(f, k - TASK_CHANNEL);
	}
}

/* rows from which the tasks take a second thread */
#define FINISH_THREAD_ROWS ((size_t)1 << 16)

static int finish_load(struct sscope_capture *cap, size_t n, unsigned threads,
		       struct sscope_reader *r, const char *path,
		       struct sscope_diag *diag)
{
	struct finish f = { .cap = cap, .n = n, .r = r };
	bool started = false;
	pthread_t tid;
	int rc = 0;

	f.timed = cap->time_s && n >= 2;
	f.inf_row = calloc(cap->n_channels ? cap->n_channels : 1,
			   sizeof(*f.inf_row));
	if (f.timed) {
		f.scratch = ssc_alloc_array(n - 1, sizeof(double));
		cap->gaps = calloc(SSCOPE_CAPTURE_GAPS, sizeof(*cap->gaps));
	}
	if (!f.inf_row || (f.timed && (!f.scratch || !cap->gaps))) {
		sscope_reader_close(r);
		rc = -ENOMEM;
		goto out;
	}
	atomic_init(&f.next, 0);
	if (threads > 1 && n >= FINISH_THREAD_ROWS)
		started = pthread_create(&tid, NULL, finish_run, &f) == 0;
	finish_run(&f);
	if (started)
		pthread_join(tid, NULL);
	for (size_t k = 0; k < cap->n_channels; k++) {
		if (f.inf_row[k] != SIZE_MAX) {
			/* finite in the file, infinite in SI (1e308 g) */
			rc = ssc_diag(diag, -ERANGE,
				      "%s: channel %s, row %zu: the value in %s exceeds the double range in SI units",
				      strcmp(path, "-") ? path : "(stdin)",
				      cap->channels[k].col.name, f.inf_row[k] + 1,
				      cap->channels[k].col.unit_label);
			goto out;
		}
		cap->n_nan += cap->channels[k].n_nan;
	}
	if (f.timed) {
		rc = sscope_timing_split_join(&f.sp, cap->time_s, n,
					      SSCOPE_TIMING_GAP_FACTOR,
					      &cap->timing, cap->gaps,
					      SSCOPE_CAPTURE_GAPS, &cap->n_gaps);
		if (rc == 0)
			cap->has_timing = true;
		else if (rc == -EDOM)
			rc = 0;
	}
out:
	free(f.scratch);
	free(f.inf_row);
	return rc;
}

/* a rate comment the reader could not read, kept for the messages */
static void note_rate(struct sscope_capture *cap,
		      const struct sscope_reader *r)
{
	const char *note = sscope_reader_header_rate_note(r);

	snprintf(cap->rate_note, sizeof(cap->rate_note), "%s", note ? note : "");
}

int sscope_capture_load(struct sscope_capture **out, const char *path,
			const struct sscope_reader_opts *opts,
			struct sscope_diag *diag)
{
	struct sscope_reader *r = NULL;
	struct sscope_capture *cap;
	struct sscope_reader_chunk ch = { 0 };
	double **ptrs = NULL;
	size_t cap_rows, n = 0;
	double header_hz = 0;
	unsigned threads;
	int rc;

	*out = NULL;
	rc = sscope_reader_open(&r, path, opts, diag);
	if (rc)
		return rc;
	cap = calloc(1, sizeof(*cap));
	if (!cap) {
		sscope_reader_close(r);
		return -ENOMEM;
	}
	cap->source = ssc_strdup(path);
	cap->n_channels = sscope_reader_n_channels(r);
	cap->channels = calloc(cap->n_channels ? cap->n_channels : 1,
			       sizeof(*cap->channels));
	ptrs = calloc(cap->n_channels ? cap->n_channels : 1, sizeof(*ptrs));
	if (!cap->source || !cap->channels || !ptrs) {
		rc = -ENOMEM;
		goto fail;
	}
	for (size_t k = 0; k < cap->n_channels; k++) {
		rc = copy_column(&cap->channels[k].col,
				 sscope_reader_channel(r, k));
		if (rc)
			goto fail;
	}
	if (sscope_reader_time_column(r)) {
		rc = copy_column(&cap->time_col, sscope_reader_time_column(r));
		if (rc)
			goto fail;
	}
	if (sscope_reader_temp_column(r)) {
		rc = copy_column(&cap->temp_col, sscope_reader_temp_column(r));
		if (rc)
			goto fail;
	}
	if (opts && opts->in_place && cap->n_channels == 1 &&
	    ssc_reader_take_inplace(r, opts->nan_as_gap, opts->in_place_unchecked,
				    &cap->channels[0].data, &n, &cap->n_nan,
				    &cap->mapping, &cap->mapping_len)) {
		if (n == 0) {
			rc = ssc_diag(diag, -EDOM, "%s: no data rows", path);
			goto fail;
		}
		cap->n = n;
		cap->values_unchecked = opts->in_place_unchecked;
		cap->channels[0].n_nan = cap->n_nan;
		header_hz = sscope_reader_header_rate(r);
		note_rate(cap, r);
		goto rate;
	}
	/* A mapped file (or any source of known size) is read in one pass,
	 * on several threads for text, into arrays sized from a bound on the
	 * row count, then trimmed; a pipe grows its arrays. */
	{
#ifdef _OPENMP
		/* OpenMP's default team (OMP_NUM_THREADS) */
		long ncpu = omp_get_max_threads();
#else
		long ncpu = sysconf(_SC_NPROCESSORS_ONLN);
#endif

		threads = opts && opts->threads ? opts->threads :
			  ncpu > 0 ? (unsigned)ncpu : 1;
	}
	cap_rows = ssc_reader_max_rows(r, threads);
	if (cap_rows) {
		rc = grow(cap, cap_rows);
		if (rc)
			goto fail;
		/* the rows are known (at most the lines): a small record's
		 * arrays mapped in one call each, not faulted in a page at a
		 * time (a quarter of `info` on a 1 MB CSV); a large one's
		 * pages come as the parse fills them (all at once, the peak
		 * memory of a 530 MB CSV grew from 0.83 to 1.31 GB) */
		for (size_t k = 0; k < cap->n_channels; k++) {
			ptrs[k] = cap->channels[k].data;
			if (cap_rows <= PREFAULT_ROWS)
				ssc_prefault(ptrs[k], cap_rows * sizeof(double));
		}
		if (cap->time_s && cap_rows <= PREFAULT_ROWS)
			ssc_prefault(cap->time_s, cap_rows * sizeof(double));
		if (cap->temp_degc && cap_rows <= PREFAULT_ROWS)
			ssc_prefault(cap->temp_degc, cap_rows * sizeof(double));
		ch = (struct sscope_reader_chunk){ cap_rows, 0, ptrs, cap->time_s,
					    cap->temp_degc };
		rc = ssc_reader_read_all(r, &ch, diag);
		if (rc)
			goto fail;
		n = ch.rows;
	} else {
		/* 64 Ki rows, or fewer for many channels (a 4 MiB start; 2555
		 * raw channels on a pipe asked for 1.3 GB up front); the
		 * arrays double as the rows come */
		cap_rows = ((size_t)4 << 20) / (sizeof(double) *
						 (cap->n_channels + 2));
		cap_rows = cap_rows < 256 ? 256 :
			   cap_rows > ((size_t)1 << 16) ? (size_t)1 << 16 : cap_rows;
		for (;;) {
			rc = grow(cap, cap_rows);
			if (rc)
				goto fail;
			for (size_t k = 0; k < cap->n_channels; k++)
				ptrs[k] = cap->channels[k].data + n;
			ch = (struct sscope_reader_chunk){
				cap_rows - n, 0, ptrs,
				cap->time_s ? cap->time_s + n : NULL,
				cap->temp_degc ? cap->temp_degc + n : NULL
			};
			rc = sscope_reader_read(r, &ch, diag);
			if (rc)
				goto fail;
			n += ch.rows;
			if (ch.rows == 0 || n < cap_rows)
				break;
			if (!ssc_mul(cap_rows, 2, &cap_rows)) {
				rc = -ENOMEM;
				goto fail;
			}
		}
	}
	if (n == 0) {
		rc = ssc_diag(diag, -EDOM, "%s: no data rows",
			      strcmp(path, "-") ? path : "(stdin)");
		goto fail;
	}
	rc = grow(cap, n); /* trim */
	if (rc)
		goto fail;
	cap->n = n;
	cap->unterminated = sscope_reader_unterminated(r);
	if (sscope_reader_source(r)) {
		cap->source_info = ssc_reader_take_source(r, n);
		if (!cap->source_info) {
			rc = -ENOMEM;
			goto fail;
		}
	}
	header_hz = sscope_reader_header_rate(r);
	note_rate(cap, r);
	rc = finish_load(cap, n, threads, r, path, diag);
	r = NULL; /* closed */
	if (rc)
		goto fail;
rate:
	if (opts && opts->rate_hz > 0) {
		cap->rate_hz = opts->rate_hz;
		cap->rate_source = SSCOPE_CAPTURE_RATE_GIVEN;
	} else if (cap->has_timing) {
		cap->rate_hz = cap->timing.rate_hz;
		cap->rate_source = SSCOPE_CAPTURE_RATE_TIME_COLUMN;
	}
	if (cap->rate_source == SSCOPE_CAPTURE_RATE_NONE && header_hz > 0) {
		cap->rate_hz = header_hz;
		cap->rate_source = SSCOPE_CAPTURE_RATE_HEADER;
	}
	if (cap->rate_hz > 0)
		cap->rate_note[0] = '\0';
	free(ptrs);
	sscope_reader_close(r);
	*out = cap;
	return 0;
fail:
	free(ptrs);
	sscope_reader_close(r);
	sscope_capture_free(cap);
	return rc;
}

struct sscope_capture *sscope_capture_new(size_t n_channels, size_t n,
					  bool with_time, bool with_temp)
{
	struct sscope_capture *cap = calloc(1, sizeof(*cap));

	if (!cap)
		return NULL;
	cap->n = n;
	cap->n_channels = n_channels;
	cap->channels = calloc(n_channels ? n_channels : 1,
			       sizeof(*cap->channels));
	if (!cap->channels)
		goto fail;
	for (size_t k = 0; k < n_channels; k++) {
		cap->channels[k].data = ssc_alloc_array(n, sizeof(double));
		if (!cap->channels[k].data)
			goto fail;
		memset(cap->channels[k].data, 0, n * sizeof(double));
		if (sscope_capture_set_channel(cap, k, "", ""))
			goto fail;
	}
	if (with_time) {
		cap->time_s = ssc_alloc_array(n, sizeof(double));
		cap->time_col.name = ssc_strdup("time");
		cap->time_col.unit_label = ssc_strdup("s");
		if (!cap->time_s || !cap->time_col.name ||
		    !cap->time_col.unit_label)
			goto fail;
		memset(cap->time_s, 0, n * sizeof(double));
		sscope_unit_parse("s", &cap->time_col.unit, NULL);
		cap->time_col.quantity = SSCOPE_QUANTITY_TIME;
		cap->time_col.role = SSCOPE_CAPTURE_ROLE_TIME;
	}
	if (with_temp) {
		cap->temp_degc = ssc_alloc_array(n, sizeof(double));
		cap->temp_col.name = ssc_strdup("temp");
		cap->temp_col.unit_label = ssc_strdup("degC");
		if (!cap->temp_degc || !cap->temp_col.name ||
		    !cap->temp_col.unit_label)
			goto fail;
		memset(cap->temp_degc, 0, n * sizeof(double));
		sscope_unit_parse("degC", &cap->temp_col.unit, NULL);
		cap->temp_col.quantity = SSCOPE_QUANTITY_TEMPERATURE;
		cap->temp_col.role = SSCOPE_CAPTURE_ROLE_TEMP;
	}
	return cap;
fail:
	sscope_capture_free(cap);
	return NULL;
}

int sscope_capture_set_channel(struct sscope_capture *cap, size_t k,
			       const char *name, const char *unit)
{
	struct sscope_capture_column c = { 0 };
	int rc;

	if (!cap || k >= cap->n_channels || !name || !unit)
		return -EINVAL;
	rc = sscope_unit_parse(unit, &c.unit, NULL);
	if (rc)
		return rc;
	c.name = name;
	c.unit_label = unit;
	c.quantity = *unit ? sscope_unit_quantity(&c.unit) : SSCOPE_QUANTITY_UNKNOWN;
	c.role = SSCOPE_CAPTURE_ROLE_DATA;
	c.index = k;
	free_column(&cap->channels[k].col);
	return copy_column(&cap->channels[k].col, &c);
}

long sscope_capture_find(const struct sscope_capture *cap, const char *name)
{
	for (size_t k = 0; k < cap->n_channels; k++)
		if (!strcmp(cap->channels[k].col.name, name))
			return (long)k;
	return -1;
}

static const char *chan_name(const void *ctx, size_t k)
{
	return ((const struct sscope_capture *)ctx)->channels[k].col.name;
}

static size_t chan_number(const void *ctx, size_t k)
{
	return ((const struct sscope_capture *)ctx)->channels[k].col.index + 1;
}

/* The channels a column list names, in its order: idx[0..*n). */
static int resolve(const struct sscope_capture *cap, const char *columns,
		   size_t *idx, size_t *n, struct sscope_diag *diag)
{
	const char *p = columns;
	char item[256];
	bool too_long;

	*n = 0;
	if (!columns || !*columns) {
		for (size_t k = 0; k < cap->n_channels; k++)
			idx[(*n)++] = k;
		return 0;
	}
	while (ssc_list_next(&p, item, sizeof(item), &too_long)) {
		long k = too_long ? -1 :
			 ssc_column_find(item, cap->n_channels, chan_name,
					 chan_number, cap);
		bool dup = false;

		if (k < 0) {
			char names[200] = "";
			size_t used = 0;

			for (size_t j = 0; j < cap->n_channels && used + 4 < sizeof(names); j++) {
				int w = snprintf(names + used, sizeof(names) - used,
						 "%s%s", j ? ", " : "",
						 cap->channels[j].col.name);

				if (w < 0)
					break;
				used += (size_t)w;
			}
			return ssc_diag(diag, -EINVAL,
					"%s: no column '%s' (columns: %s)",
					cap->source && strcmp(cap->source, "-") ?
						cap->source : "(stdin)",
					item, names);
		}
		for (size_t j = 0; j < *n; j++)
			dup |= idx[j] == (size_t)k;
		if (!dup)
			idx[(*n)++] = (size_t)k;
	}
	return 0;
}

int sscope_capture_view(const struct sscope_capture *cap, const char *columns,
			struct sscope_capture **view, struct sscope_diag *diag)
{
	struct sscope_capture *v;
	size_t *idx, n;
	int rc;

	if (!cap || !view)
		return -EINVAL;
	*view = NULL;
	idx = ssc_alloc_array(cap->n_channels + 1, sizeof(*idx));
	v = malloc(sizeof(*v));
	if (!idx || !v) {
		free(idx);
		free(v);
		return -ENOMEM;
	}
	rc = resolve(cap, columns, idx, &n, diag);
	if (rc) {
		free(idx);
		free(v);
		return rc;
	}
	*v = *cap;
	v->is_view = true;
	v->n_channels = n;
	v->channels = ssc_alloc_array(n + 1, sizeof(*v->channels));
	if (!v->channels) {
		free(idx);
		free(v);
		return -ENOMEM;
	}
	v->n_nan = 0;
	for (size_t k = 0; k < n; k++) {
		v->channels[k] = cap->channels[idx[k]];
		v->n_nan += v->channels[k].n_nan;
	}
	free(idx);
	*view = v;
	return 0;
}

int sscope_capture_select(struct sscope_capture *cap, const char *columns,
			  struct sscope_diag *diag)
{
	struct sscope_capture_channel *ch;
	size_t *idx, n;
	bool *kept;
	int rc;

	if (!cap || cap->is_view)
		return -EINVAL;
	if (!columns || !*columns)
		return 0;
	idx = ssc_alloc_array(cap->n_channels + 1, sizeof(*idx));
	kept = calloc(cap->n_channels + 1, sizeof(*kept));
	ch = ssc_alloc_array(cap->n_channels + 1, sizeof(*ch));
	rc = idx && kept && ch ? resolve(cap, columns, idx, &n, diag) : -ENOMEM;
	if (rc) {
		free(idx);
		free(kept);
		free(ch);
		return rc;
	}
	cap->n_nan = 0;
	for (size_t k = 0; k < n; k++) {
		ch[k] = cap->channels[idx[k]];
		kept[idx[k]] = true;
		cap->n_nan += ch[k].n_nan;
	}
	for (size_t j = 0; j < cap->n_channels; j++)
		if (!kept[j]) {
			free_column(&cap->channels[j].col);
			if (!in_mapping(cap, cap->channels[j].data))
				free(cap->channels[j].data);
		}
	free(cap->channels);
	cap->channels = ch;
	cap->n_channels = n;
	free(idx);
	free(kept);
	return 0;
}
