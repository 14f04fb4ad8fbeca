/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Version, error strings and small helpers shared by the library.
 */
#include "internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <pthread.h>
#include <unistd.h>

const char *sscope_version(void)
{
	return PACKAGE_VERSION;
}

enum { OS_TEXTS = 192 };
static char os_texts[OS_TEXTS][96];
static pthread_once_t os_texts_once = PTHREAD_ONCE_INIT;

static void os_texts_make(void)
{
	for (int e = 0; e < OS_TEXTS; e++) {
		char *t = os_texts[e];

		snprintf(t, sizeof(os_texts[e]), "%s", strerror(e));
		if (t[0] >= 'A' && t[0] <= 'Z' && t[1] >= 'a' && t[1] <= 'z')
			t[0] = (char)(t[0] - 'A' + 'a');
	}
}

const char *sscope_strerror(int err)
{
	if (err < 0)
		err = -err;
	switch (err) {
	case 0:
		return "success";
	case EINVAL:
		return "invalid parameter";
	case EDOM:
		return "data do not fit the request";
	case ERANGE:
		return "value out of range";
	case ENOMEM:
		return "out of memory";
	case ENOTSUP:
		return "feature not built in";
	case EIO:
		return "input/output error";
	case ETIMEDOUT:
		return "timed out";
	case ENODEV:
		return "no such device";
	case EBADMSG:
		return "malformed file or frame";
	case ENOENT:
		return "no such file or directory";
	case EACCES:
		return "permission denied";
	case EISDIR:
		return "is a directory";
	case ENOSPC:
		return "no space left on device";
	default:
		break;
	}
	/* the OS's text (Read-only file system, ...), its first letter in
	 * lower case as in every other message (not an acronym's: "EOF"),
	 * from a table made once: static strings, as promised */
	pthread_once(&os_texts_once, os_texts_make);
	return err < OS_TEXTS ? os_texts[err] : "unknown error";
}

int ssc_diag(struct sscope_diag *diag, int err, const char *fmt, ...)
{
	va_list ap;

	if (diag) {
		va_start(ap, fmt);
		vsnprintf(diag->msg, sizeof(diag->msg), fmt, ap);
		va_end(ap);
	}
	return err;
}

void *ssc_alloc_array(size_t count, size_t size)
{
	size_t bytes;

	if (!ssc_mul(count, size, &bytes))
		return NULL;
	return malloc(bytes ? bytes : 1);
}

/* the whole pages inside [p, p + bytes): their start in *lo, their
 * number returned; *ps the page size */
static size_t inner_pages(const void *p, size_t bytes, uintptr_t *lo,
			  uintptr_t *ps)
{
	long pg = sysconf(_SC_PAGESIZE);
	uintptr_t hi;

	*ps = pg > 0 ? (uintptr_t)pg : 4096;
	*lo = ((uintptr_t)p + *ps - 1) / *ps * *ps;
	hi = ((uintptr_t)p + bytes) / *ps * *ps;
	return hi > *lo ? (size_t)((hi - *lo) / *ps) : 0;
}

#if defined(MADV_POPULATE_WRITE) || defined(MADV_POPULATE_READ)
/* madvise(advice) on the whole pages of [p, p + bytes): a hint, so an
 * EINVAL on older kernels is harmless */
static void advise_pages(const void *p, size_t bytes, int advice)
{
	uintptr_t a, ps;
	size_t pages = inner_pages(p, bytes, &a, &ps);

	if (pages)
		(void)madvise((void *)a, pages * ps, advice);
}
#endif

void ssc_prefault(void *p, size_t bytes)
{
#ifdef MADV_POPULATE_WRITE
	advise_pages(p, bytes, MADV_POPULATE_WRITE);
#else
	(void)p;
	(void)bytes;
#endif
}

void ssc_prefault_read(const void *p, size_t bytes)
{
#ifdef MADV_POPULATE_READ
	advise_pages(p, bytes, MADV_POPULATE_READ);
#else
	(void)p;
	(void)bytes;
#endif
}

void ssc_hint_huge(void *p, size_t bytes)
{
#ifdef MADV_HUGEPAGE
	const uintptr_t H = (uintptr_t)1 << 21;
	uintptr_t a = ((uintptr_t)p + H - 1) & ~(H - 1);
	uintptr_t e = ((uintptr_t)p + bytes) & ~(H - 1);

	if (e > a) /* EINVAL without THP is harmless */
		(void)madvise((void *)a, e - a, MADV_HUGEPAGE);
#else
	(void)p;
	(void)bytes;
#endif
}

void *ssc_alloc_huge(size_t count, size_t size)
{
	const size_t H = (size_t)1 << 21;
	size_t bytes;
	void *p;

	if (!ssc_mul(count, size, &bytes))
		return NULL;
	if (bytes > SIZE_MAX - H)
		return NULL;
	if (bytes < H / 2) /* on 4 KiB pages */
		return aligned_alloc(4096, (bytes + 4095) / 4096 * 4096 + 4096 * !bytes);
	p = aligned_alloc(H, (bytes + H - 1) / H * H);
	if (p)
		ssc_hint_huge(p, (bytes + H - 1) / H * H);
	return p;
}

void ssc_release_pages(void *p, size_t bytes, unsigned threads)
{
#ifdef MADV_DONTNEED
	uintptr_t lo, ps;
	const size_t pages = inner_pages(p, bytes, &lo, &ps);
	const unsigned T = threads ? threads : 1;

SSC_OMP(omp parallel for num_threads(T) schedule(static, 1) if (pages >= 4096))
	for (unsigned t = 0; t < T; t++) {
		size_t p0 = pages * t / T, p1 = pages * (t + 1) / T;

		if (p1 > p0)
			(void)madvise((void *)(lo + p0 * ps), (p1 - p0) * ps,
				      MADV_DONTNEED);
	}
#else
	(void)p;
	(void)bytes;
	(void)threads;
#endif
}

char *ssc_strdup(const char *s)
{
	size_t n;
	char *d;

	if (!s)
		return NULL;
	n = strlen(s) + 1;
	d = malloc(n);
	if (d)
		memcpy(d, s, n);
	return d;
}

int ssc_strcasecmp(const char *a, const char *b)
{
	for (;; a++, b++) {
		int ca = (unsigned char)*a, cb = (unsigned char)*b;

		if (ca >= 'A' && ca <= 'Z')
			ca += 'a' - 'A';
		if (cb >= 'A' && cb <= 'Z')
			cb += 'a' - 'A';
		if (ca != cb || !ca)
			return ca - cb;
	}
}

bool ssc_list_next(const char **p, char *buf, size_t len, bool *too_long)
{
	while (**p) {
		const char *s = *p, *e = strchr(s, ',');
		size_t n;

		if (!e)
			e = s + strlen(s);
		*p = *e ? e + 1 : e;
		while (s < e && (*s == ' ' || *s == '\t'))
			s++;
		while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' ||
				 e[-1] == '\n'))
			e--;
		n = (size_t)(e - s);
		if (!n)
			continue;
		*too_long = n >= len;
		if (*too_long)
			n = len - 1;
		memcpy(buf, s, n);
		buf[n] = '\0';
		return true;
	}
	return false;
}

long ssc_column_find(const char *item, size_t n,
		     const char *(*name)(const void *ctx, size_t i),
		     size_t (*number)(const void *ctx, size_t i),
		     const void *ctx)
{
	char *end;
	long num = strtol(item, &end, 10);

	if (*item && !*end) {
		for (size_t i = 0; i < n; i++)
			if ((long)number(ctx, i) == num)
				return (long)i;
		return -1;
	}
	for (size_t i = 0; i < n; i++)
		if (!strcmp(name(ctx, i), item))
			return (long)i;
	for (size_t i = 0; i < n; i++)
		if (!ssc_strcasecmp(name(ctx, i), item))
			return (long)i;
	return -1;
}

int ssc_cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;

	return (x > y) - (x < y);
}

void ssc_golden_min(double (*f)(double x, void *ctx), void *ctx, double a,
		    double b, int iters, double tol, bool left_on_tie,
		    struct ssc_golden *g)
{
	const double gr = 0.6180339887498949; /* (sqrt(5) - 1) / 2 */
	double x1 = b - gr * (b - a), x2 = a + gr * (b - a);
	double f1 = f(x1, ctx), f2 = f(x2, ctx);

	for (int it = 0; it < iters && b - a > tol; it++) {
		if (left_on_tie ? f1 <= f2 : f1 < f2) {
			b = x2;
			x2 = x1;
			f2 = f1;
			x1 = b - gr * (b - a);
			f1 = f(x1, ctx);
		} else {
			a = x1;
			x1 = x2;
			f1 = f2;
			x2 = a + gr * (b - a);
			f2 = f(x2, ctx);
		}
	}
	*g = (struct ssc_golden){ a, b, x1, x2, f1, f2 };
}
