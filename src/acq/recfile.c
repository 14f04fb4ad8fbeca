/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The recording file of a live acquisition: the samples are the user's
 * only copy, so the file is never deleted and always readable.
 *
 *   - Rows go to NAME.partial, created with O_EXCL beside NAME; a clean
 *     stop renames it to NAME.  Every reader takes a NAME.partial file up
 *     to its last complete row (src/reader.c), so what a kill, an OOM kill
 *     or a power cut leaves behind is a capture like any other.
 *   - Rows are formatted into memory (sscope_writer on an fopencookie(3)
 *     stream) and handed to the file with write(2) at least every
 *     SSC_REC_FLUSH_S; the engine's control thread calls fdatasync(2)
 *     once a second, so after a power cut the file holds what was read up
 *     to about two seconds before.
 *   - When a write fails (a full disk, a quota, RLIMIT_FSIZE) the file is
 *     cut back to the last complete row (ftruncate), kept, and given its
 *     end line if that still fits.
 *   - NAME is never replaced unless asked (overwrite): without it an
 *     existing NAME is refused before anything starts, and the final
 *     rename refuses to replace a NAME that appeared during the run
 *     (renameat2 RENAME_NOREPLACE, or link + unlink): the recording then
 *     stays under NAME.partial.  An existing NAME.partial (an interrupted
 *     recording) is always refused.
 *   - "-", /dev/stdout, /dev/stderr, /dev/fd/N, FIFOs and devices are
 *     written directly and never renamed, truncated or synced.
 */
#include "acq.h"
#include "atomic.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

struct ssc_recfile {
	char *target;     /* the final name (links resolved) */
	char *partial;    /* target + ".partial"; NULL: written directly */
	char *shown;      /* the name in messages */
	int fd;
	bool own_fd;
	bool regular;     /* a file we created: cut and synced */
	bool overwrite;
	bool csv;
	FILE *cf;         /* the writer's stream into buf */
	struct sscope_writer *w;
	char *buf;        /* formatted, not yet written */
	size_t len, cap;
	bool oom;
	bool dirty;       /* something formatted since the last flush */
	bool keep_partial; /* the file may end in a cut row: not renamed */
	uint64_t rows_buf;   /* rows in buf */
	uint64_t rows_file;  /* rows in the file */
	uint64_t off;        /* bytes in the file (whole lines or rows) */
	uint64_t data_off;   /* binary: where the rows start */
	size_t row_bytes;    /* binary: bytes per row */
	int err;             /* first write error (-errno), 0 none */
	atomic_int sync_err; /* first fdatasync error (-errno), 0 none */
	uint64_t fail_after; /* tests: the disk is full after so many bytes */
};

static ssize_t mem_write(void *cookie, const char *p, size_t n)
{
	struct ssc_recfile *rf = cookie;

	if (rf->len + n > rf->cap) {
		size_t cap = rf->cap ? rf->cap : 1 << 18;
		char *b;

		while (cap < rf->len + n)
			cap *= 2;
		b = realloc(rf->buf, cap);
		if (!b) {
			rf->oom = true;
			return 0;
		}
		rf->buf = b;
		rf->cap = cap;
	}
	memcpy(rf->buf + rf->len, p, n);
	rf->len += n;
	return (ssize_t)n;
}

/* fsync the folder holding path (its entries survive a power cut) */
static void sync_dir(const char *path)
{
	const char *sl = strrchr(path, '/');
	char dir[PATH_MAX];
	int fd;

	if (!sl)
		snprintf(dir, sizeof(dir), ".");
	else if (sl == path)
		snprintf(dir, sizeof(dir), "/");
	else
		snprintf(dir, sizeof(dir), "%.*s", (int)(sl - path), path);
	fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
	if (fd >= 0) {
		fsync(fd);
		close(fd);
	}
}

static void rf_free(struct ssc_recfile *rf)
{
	if (rf->w)
		sscope_writer_abort(rf->w);
	if (rf->cf)
		fclose(rf->cf);
	if (rf->own_fd && rf->fd >= 0)
		close(rf->fd);
	free(rf->target);
	free(rf->partial);
	free(rf->shown);
	free(rf->buf);
	free(rf);
}

/* Decide the names and open the descriptor. */
static int rf_create(struct ssc_recfile *rf, const char *path,
		     struct sscope_diag *diag)
{
	struct stat st;
	int fd = ssc_named_fd(path);

	if (fd >= 0) {
		rf->fd = fd;
		rf->shown = strdup(fd == STDOUT_FILENO ? "standard output"
						       : path);
		return rf->shown ? 0 : -ENOMEM;
	}
	rf->shown = strdup(path);
	if (!rf->shown)
		return -ENOMEM;
	rf->target = ssc_resolve_links(path);
	if (!rf->target) {
		int e = errno ? errno : ENOMEM;

		return ssc_acq_diag(diag, -e, "%s: %s", path, sscope_strerror(e));
	}
	if (stat(rf->target, &st) == 0) {
		if (S_ISDIR(st.st_mode))
			return ssc_acq_diag(diag, -EISDIR, "%s: is a folder",
					    path);
		if (!S_ISREG(st.st_mode)) { /* FIFO, device: written into */
			rf->fd = open(rf->target, O_WRONLY | O_CLOEXEC);
			if (rf->fd < 0)
				return ssc_acq_diag(diag, -errno, "%s: %s",
						    path, sscope_strerror(errno));
			rf->own_fd = true;
			return 0;
		}
		if (!rf->overwrite)
			return ssc_acq_diag(diag, -EEXIST,
					    "%s: exists; give another name, or --overwrite to replace it when the recording ends",
					    path);
	} else if (errno != ENOENT) {
		return ssc_acq_diag(diag, -errno, "%s: %s", path,
				    sscope_strerror(errno));
	}
	rf->partial = malloc(strlen(rf->target) + sizeof(".partial"));
	if (!rf->partial)
		return -ENOMEM;
	strcpy(rf->partial, rf->target);
	strcat(rf->partial, ".partial");
	rf->fd = open(rf->partial, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC,
		      0666);
	if (rf->fd < 0) {
		int e = errno;

		free(rf->partial);
		rf->partial = NULL;
		if (e == EEXIST)
			return ssc_acq_diag(diag, -EEXIST,
					    "%s.partial exists: an interrupted or running recording (other commands read it as it is); rename it, or record under another name",
					    rf->target);
		return ssc_acq_diag(diag, -e, "%s: %s", path, sscope_strerror(e));
	}
	rf->own_fd = true;
	rf->regular = true;
	sync_dir(rf->partial);
	return 0;
}

/* Write all of p at the end of the file, or say how much went: 0 or
 * -errno. */
static int write_all(struct ssc_recfile *rf, const char *p, size_t n,
		     size_t *done)
{
	*done = 0;
	while (*done < n) {
		size_t want = n - *done;
		ssize_t w;

		if (rf->fail_after) {
			uint64_t room = rf->fail_after > rf->off + *done
						? rf->fail_after - rf->off - *done
						: 0;

			if (room == 0)
				return -ENOSPC;
			if (want > room)
				want = (size_t)room;
		}
		/* at the file's length, whatever a cut did to the offset */
		w = rf->regular ? pwrite(rf->fd, p + *done, want,
					 (off_t)(rf->off + *done))
				: write(rf->fd, p + *done, want);
		if (w < 0 && errno == EINTR)
			continue;
		if (w < 0)
			return -errno;
		if (w == 0)
			return -EIO;
		*done += (size_t)w;
	}
	return 0;
}

/* After a failed write of done bytes of buf: the end of the last complete
 * row (or line) within them, and the rows up to it. */
static uint64_t cut_point(const struct ssc_recfile *rf, size_t done,
			  uint64_t *rows)
{
	if (!rf->csv) {
		uint64_t end = rf->off + done,
			 n = (end - rf->data_off) / rf->row_bytes;

		*rows = n;
		return rf->data_off + n * rf->row_bytes;
	}
	{
		const char *nl = done ? memrchr(rf->buf, '\n', done) : NULL;
		size_t keep = nl ? (size_t)(nl - rf->buf) + 1 : 0;
		uint64_t n = rf->rows_file;

		for (size_t i = 0; i < keep;) {
			const char *e = memchr(rf->buf + i, '\n', keep - i);

			n += rf->buf[i] != '#';
			i = (size_t)(e - rf->buf) + 1;
		}
		*rows = n;
		return rf->off + keep;
	}
}

int ssc_recfile_flush(struct ssc_recfile *rf)
{
	size_t done;
	int rc;

	if (rf->err)
		return rf->err;
	if (fflush(rf->cf) != 0 || rf->oom)
		return rf->err = -ENOMEM;
	rc = write_all(rf, rf->buf, rf->len, &done);
	if (rc) {
		uint64_t rows, cut = rf->off + done;

		if (rf->regular) {
			cut = cut_point(rf, done, &rows);
			/* a cut that fails leaves part of a row: the
			 * file keeps the name every reader takes up to
			 * its last complete row */
			if (cut < rf->off + done &&
			    ftruncate(rf->fd, (off_t)cut) != 0) {
				cut = rf->off + done;
				rf->keep_partial = true;
			}
			rf->rows_file = rows;
		}
		rf->off = cut;
		rf->len = 0;
		rf->rows_buf = 0;
		return rf->err = rc;
	}
	rf->off += rf->len;
	rf->rows_file += rf->rows_buf;
	rf->len = 0;
	rf->rows_buf = 0;
	rf->dirty = false;
	rc = atomic_load(&rf->sync_err);
	if (rc)
		rf->err = rc;
	return rc;
}

int ssc_recfile_open(struct ssc_recfile **out, const struct ssc_rec_opts *o,
		     struct sscope_diag *diag)
{
	static const cookie_io_functions_t io = { .write = mem_write };
	struct ssc_recfile *rf;
	int rc;

	*out = NULL;
	rf = calloc(1, sizeof(*rf));
	if (!rf)
		return -ENOMEM;
	rf->fd = -1;
	rf->overwrite = o->overwrite;
	rf->csv = o->format == SSCOPE_CAPTURE_CSV;
	rf->fail_after = o->fail_after_bytes;
	atomic_init(&rf->sync_err, 0);
	rc = rf_create(rf, o->path, diag);
	if (rc)
		goto fail;
	rf->cf = fopencookie(rf, "w", io);
	if (!rf->cf) {
		rc = -ENOMEM;
		goto fail;
	}
	setvbuf(rf->cf, NULL, _IOFBF, 1 << 16);
	rc = sscope_writer_fopen(&rf->w, rf->cf, o->format, o->cols, o->n_cols,
				 0, diag);
	if (rc)
		goto fail;
	/* the header alone: the rows start after it */
	if (fflush(rf->cf) != 0 || rf->oom) {
		rc = -ENOMEM;
		goto fail;
	}
	rf->data_off = rf->len;
	rf->row_bytes = o->n_cols *
			(o->format == SSCOPE_CAPTURE_BIN32 ? 4 : 8);
	for (size_t i = 0; o->comments && o->comments[i] && !rc; i++)
		rc = sscope_writer_comment(rf->w, o->comments[i]);
	if (!rc)
		rc = ssc_recfile_flush(rf);
	if (rc) {
		ssc_acq_diag(diag, rc, "%s: %s", rf->shown, sscope_strerror(-rc));
		goto fail;
	}
	*out = rf;
	return 0;
fail:
	if (rf->partial)
		unlink(rf->partial); /* nothing recorded yet */
	rf_free(rf);
	return rc;
}

int ssc_recfile_append(struct ssc_recfile *rf, const double *rows, size_t n)
{
	int rc;

	if (rf->err)
		return rf->err;
	rc = sscope_writer_append(rf->w, rows, n);
	if (rc || rf->oom)
		return rf->err = rf->oom ? -ENOMEM : rc;
	rf->rows_buf += n;
	rf->dirty = true;
	return 0;
}

int ssc_recfile_comment(struct ssc_recfile *rf, const char *text)
{
	int rc;

	if (rf->err)
		return rf->err;
	rc = sscope_writer_comment(rf->w, text);
	if (rc || rf->oom)
		return rf->err = rf->oom ? -ENOMEM : rc;
	rf->dirty = true;
	return 0;
}

bool ssc_recfile_dirty(const struct ssc_recfile *rf)
{
	return rf->dirty;
}

uint64_t ssc_recfile_buffered(const struct ssc_recfile *rf)
{
	return rf->rows_buf;
}

uint64_t ssc_recfile_rows(const struct ssc_recfile *rf)
{
	return rf->rows_file;
}

const char *ssc_recfile_name(const struct ssc_recfile *rf)
{
	return rf->shown;
}

void ssc_recfile_sync(struct ssc_recfile *rf)
{
	if (rf->regular && fdatasync(rf->fd) != 0) {
		int expected = 0;

		atomic_compare_exchange_strong(&rf->sync_err, &expected,
					       -errno);
	}
}

/* Rename partial to target without replacing anything: 0, -EEXIST, or
 * -errno. */
static int rename_noreplace(const char *from, const char *to)
{
	if (renameat2(AT_FDCWD, from, AT_FDCWD, to, RENAME_NOREPLACE) == 0)
		return 0;
	if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
		return -errno;
	/* a file system without RENAME_NOREPLACE: a hard link fails on an
	 * existing name */
	if (link(from, to) == 0) {
		unlink(from);
		return 0;
	}
	if (errno == EEXIST)
		return -EEXIST;
	/* nor hard links (FAT): the last look, then rename */
	if (access(to, F_OK) == 0)
		return -EEXIST;
	return rename(from, to) == 0 ? 0 : -errno;
}

int ssc_recfile_close(struct ssc_recfile *rf, const char *trailer,
		      struct ssc_rec_end *end)
{
	int rc = rf->err;

	memset(end, 0, sizeof(*end));
	if (!rc && trailer)
		rc = ssc_recfile_comment(rf, trailer);
	if (!rc)
		rc = ssc_recfile_flush(rf);
	if (rc && trailer && rf->csv && rf->regular && !rf->keep_partial) {
		/* after a failed write: a short end line if it fits in
		 * what is left, else none (the file ends at its last row) */
		char line[128];
		size_t n, done;
		int wrc;

		n = (size_t)snprintf(line, sizeof(line),
				     "# end: %llu samples; stopped: %s\n",
				     (unsigned long long)rf->rows_file,
				     ssc_acq_storage_full(rc)
					     ? ssc_acq_full_words(rc)
					     : "write error");
		wrc = write_all(rf, line, n, &done);
		if (wrc && done && ftruncate(rf->fd, (off_t)rf->off) != 0)
			rf->keep_partial = true; /* a cut line: .partial */
		end->trailer_lost = wrc != 0;
		if (!wrc)
			rf->off += n;
	} else if (rc && trailer && rf->csv) {
		end->trailer_lost = true;
	}
	end->rows = rf->rows_file;
	if (rf->regular) {
		if (fdatasync(rf->fd) != 0 && !rc)
			rc = -errno;
		if (!rc)
			rc = atomic_load(&rf->sync_err);
	}
	if (rf->own_fd && close(rf->fd) != 0 && !rc)
		rc = -errno;
	rf->fd = -1;
	if (!rf->regular) {
		snprintf(end->where, sizeof(end->where), "%s", rf->shown);
	} else if (rf->rows_file == 0) {
		unlink(rf->partial); /* a header alone: nothing was recorded */
		end->removed = true;
	} else {
		int rr = rf->keep_partial ? -EIO
			 : rf->overwrite ? (rename(rf->partial, rf->target)
						    ? -errno : 0)
					 : rename_noreplace(rf->partial,
							    rf->target);

		if (rr) {
			end->rename_err = rr;
			snprintf(end->where, sizeof(end->where), "%s",
				 rf->partial);
		} else {
			/* the name the user gave (a link still leads here) */
			snprintf(end->where, sizeof(end->where), "%s",
				 rf->shown);
			sync_dir(rf->target);
		}
		end->kept = true;
	}
	return rc;
}

void ssc_recfile_free(struct ssc_recfile *rf)
{
	if (rf)
		rf_free(rf);
}
