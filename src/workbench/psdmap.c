/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The psd command's input straight from a mapping of a raw float64 file
 * (see ssc_psd_fed_from_mapping() in workbench.h).
 */
#include "workbench.h"

#include <fcntl.h>
#include <math.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

/* samples per piece of a mapped record (32 MiB): the estimate copies
 * up to a batch of segments (4 MiB for nperseg 4096) across each end */
#define MAP_PIECE ((size_t)1 << 22)

/*
 * A raw record of one float64 channel in the host's byte order, without
 * scaling or unit conversion, in a regular file, is fed to the estimate
 * straight from a mapping of the file: whole batches of segments without
 * a copy, no reader thread taking a core from the transforms, the pages
 * given back behind.  The same segments in the same order: the same
 * numbers.  The result is computed here (the rate is given).  A
 * non-finite sample (a segment the estimate refuses, or one after the
 * last segment) or any failure resets the estimate and returns false: the
 * streamed path then reads the record and reports as before.
 */
bool ssc_psd_fed_from_mapping(const struct ssc_common *co, const char *path,
			      size_t nch_sel, struct sscope_reader *rd,
			      struct sscope_psd *p, struct sscope_psd_spectrum *s,
			      uint64_t *rows)
{
	const struct sscope_capture_column *col;
	const char *l = co->raw;
	size_t nch = 0, vbytes = 0, n, pos = 0, dropped = 0, seg_end;
	long pg = sysconf(_SC_PAGESIZE);
	size_t ps = pg > 0 ? (size_t)pg : 4096;
	const double *x;
	struct stat st;
	void *map;
	bool ok = true;
	int fd;

	if (!l || strncmp(l, "f64:", 4) || strstr(l, ":be") || co->allow_nan ||
	    (co->scale != 0 && co->scale != 1) || co->offset != 0 ||
	    ssc_progress_on(co) || !(co->rate_hz > 0) || nch_sel != 1 ||
	    sscope_reader_n_columns(rd) != 1 || sscope_reader_time_column(rd) ||
	    sscope_reader_temp_column(rd) ||
	    sscope_reader_raw_layout_check(l, &nch, &vbytes, NULL) || nch != 1 ||
	    vbytes != sizeof(double) || !strcmp(path, "-"))
		return false;
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
	if (!strstr(l, ":be"))
		return false;
#endif
	col = sscope_reader_channel(rd, 0);
	if (!col || col->unit.scale != 1 || col->unit.offset != 0)
		return false;
	fd = open(path, O_RDONLY | O_CLOEXEC);
	if (fd < 0)
		return false;
	if (fstat(fd, &st) || !S_ISREG(st.st_mode) || st.st_size <= 0 ||
	    st.st_size % sizeof(double)) {
		close(fd);
		return false;
	}
	map = mmap(NULL, (size_t)st.st_size, PROT_READ, MAP_PRIVATE, fd, 0);
	close(fd);
	if (map == MAP_FAILED)
		return false;
	x = map;
	n = (size_t)st.st_size / sizeof(double);
	while (ok && pos < n) {
		size_t len = n - pos < MAP_PIECE ? n - pos : MAP_PIECE;
		size_t a = pos * sizeof(double) / ps * ps;

#ifdef MADV_POPULATE_READ
		madvise((char *)map + a, (pos + len) * sizeof(double) - a,
			MADV_POPULATE_READ);
#endif
		ok = sscope_psd_feed(p, x + pos, 1, len) == 0;
		pos += len;
		/* every sample fed is transformed or copied into the stage */
		a = pos * sizeof(double) / ps * ps;
		if (a > dropped) {
			madvise((char *)map + dropped, a - dropped, MADV_DONTNEED);
			dropped = a;
		}
	}
	/* the samples after the last whole segment, which the estimate
	 * never looks at but the reader refuses when not finite */
	seg_end = sscope_psd_segments_end(p, n);
	for (size_t k = seg_end; ok && k < n; k++)
		ok = isfinite(x[k]);
	munmap(map, (size_t)st.st_size);
	/* the segments still staged are transformed by the result: a
	 * refusal there is a non-finite sample (or an error the streamed
	 * path reports in its words) */
	if (ok)
		ok = sscope_psd_result(p, co->rate_hz, s) == 0;
	if (!ok) {
		sscope_psd_reset(p);
		return false;
	}
	*rows = n;
	return true;
}
