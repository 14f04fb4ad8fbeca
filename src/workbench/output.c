/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The CLI's output layer: every file the command line writes goes through
 * here, so what the user owns is kept the same way everywhere.
 *
 * - Sinks (-o, --plot, --kalibr, report files) are atomic.c files: regular
 *   files are replaced atomically, links followed, FIFOs, devices and
 *   standard output written directly.  A failed write is one line with the
 *   errno's text, whatever the size of the output (ssc_write_failed).
 * - Outputs are compared with inputs before anything is written: the same
 *   device and inode (or, for a report folder, an input inside it) is a
 *   usage error (ssc_guard_check).
 * - A report folder is built in a staging folder beside it and exchanged
 *   with the old one only when complete (renameat2 RENAME_EXCHANGE).
 * - SIGINT, SIGTERM, SIGHUP and SIGPIPE remove the temporary files and
 *   staging folders in progress, then re-raise the signal.  The registry
 *   the handler reads is a fixed array of atomic pointers; the handler uses
 *   only async-signal-safe calls (unlink, open, getdents64, unlinkat,
 *   rmdir, raise).
 */
#include "workbench.h"

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include "atomic.h"

/* ------------------------------------------------------------ registry */

#define N_TMP_FILES 64
#define N_TMP_DIRS 8

static _Atomic(char *) tmp_files[N_TMP_FILES];
static _Atomic(char *) tmp_dirs[N_TMP_DIRS];

/* Track a copy of @p path; returns the slot, or -1 (then it is simply not
 * removed on a signal). */
static int track(_Atomic(char *) *slots, int n, const char *path)
{
	char *p = path ? strdup(path) : NULL;

	if (!p)
		return -1;
	for (int i = 0; i < n; i++) {
		char *none = NULL;

		if (atomic_compare_exchange_strong(&slots[i], &none, p))
			return i;
	}
	free(p);
	return -1;
}

static void untrack(_Atomic(char *) *slots, int slot)
{
	if (slot >= 0)
		free(atomic_exchange(&slots[slot], NULL));
}

/* Remove the regular files of a flat folder (all of them, or those @p keep
 * refuses) and the folder.  Async-signal-safe when @p keep is NULL.
 * Returns 0 when the folder is gone. */
static int remove_flat_dir(const char *dir,
			   bool (*keep)(const char *name, void *ctx), void *ctx)
{
	int fd = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	bool again = fd >= 0;

	while (again) {
		/* dirent64 records are 8-byte aligned */
		_Alignas(8) char buf[4096];
		ssize_t n;

		again = false;
		lseek(fd, 0, SEEK_SET);
		while ((n = getdents64(fd, buf, sizeof(buf))) > 0)
			for (ssize_t off = 0; off < n;) {
				struct dirent64 *d = (struct dirent64 *)(void *)(buf + off);

				off += d->d_reclen;
				if (d->d_type != DT_REG && d->d_type != DT_UNKNOWN)
					continue;
				if (keep && keep(d->d_name, ctx))
					continue;
				if (unlinkat(fd, d->d_name, 0) == 0)
					again = true;
			}
	}
	if (fd >= 0)
		close(fd);
	return rmdir(dir);
}

static void cleanup_all(void)
{
	for (int i = 0; i < N_TMP_FILES; i++) {
		char *p = atomic_load(&tmp_files[i]);

		if (p)
			unlink(p);
	}
	for (int i = 0; i < N_TMP_DIRS; i++) {
		char *p = atomic_load(&tmp_dirs[i]);

		/* a thread still writing a figure may add a file between
		 * the last pass and the rmdir: pass again */
		for (int k = 0; p && k < 100; k++)
			if (remove_flat_dir(p, NULL, NULL) == 0 ||
			    errno != ENOTEMPTY)
				break;
	}
}

static const int cleanup_signals[] = { SIGINT, SIGTERM, SIGHUP, SIGPIPE };

static void on_signal(int sig)
{
	int e = errno;
	sigset_t set;

	ssc_set_interrupted();
	cleanup_all();
	signal(sig, SIG_DFL);
	/* blocked in the handler (sa_mask): unblocked, it ends the process
	 * at once with the signal's default action */
	sigemptyset(&set);
	sigaddset(&set, sig);
	sigprocmask(SIG_UNBLOCK, &set, NULL);
	raise(sig);
	errno = e;
}

static void at_exit(void)
{
	if (ssc_interrupted())
		for (;;)
			pause(); /* the handler's signal ends the process */
	cleanup_all();
}

void ssc_signals_init(void)
{
	struct sigaction sa;

	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	for (size_t i = 0; i < sizeof(cleanup_signals) / sizeof(int); i++)
		sigaddset(&sa.sa_mask, cleanup_signals[i]);
	sa.sa_flags = SA_RESTART;
	for (size_t i = 0; i < sizeof(cleanup_signals) / sizeof(int); i++) {
		struct sigaction old;

		/* a signal the caller ignores stays ignored (nohup, ...) */
		if (sigaction(cleanup_signals[i], NULL, &old) == 0 &&
		    old.sa_handler == SIG_IGN)
			continue;
		sigaction(cleanup_signals[i], &sa, NULL);
	}
	atexit(at_exit);
}

/* Hold the cleanup signals in this thread while a temporary name is
 * created and tracked (or renamed and forgotten). */
static void hold_signals(sigset_t *old)
{
	sigset_t set;

	sigemptyset(&set);
	for (size_t i = 0; i < sizeof(cleanup_signals) / sizeof(int); i++)
		sigaddset(&set, cleanup_signals[i]);
	sigprocmask(SIG_BLOCK, &set, old);
}

static void release_signals(const sigset_t *old)
{
	sigprocmask(SIG_SETMASK, old, NULL);
}

/* ------------------------------------------------------------ sinks */

/* The report folder being staged (one at a time): messages name its files
 * where they will be, not where they are being built. */
static const struct ssc_outdir *staging;

/* @p path as messages show it (malloc'ed). */
static char *shown_name(const char *path)
{
	size_t n = staging && staging->dir ? strlen(staging->dir) : 0;
	char *s;

	if (!path || !strcmp(path, "-"))
		return strdup("standard output");
	if (!n || strncmp(path, staging->dir, n) || path[n] != '/')
		return strdup(path);
	s = malloc(strlen(staging->shown) + strlen(path + n) + 1);
	if (s) {
		strcpy(s, staging->shown);
		strcat(s, path + n);
	}
	return s;
}

/* The one message of a failed output: "CMD: PATH: <errno text>". */
static int say_failed(const char *cmd, const char *shown, int rc)
{
	if (rc == -ENOTSUP) {
		ssc_err(cmd, "%s: %s", shown, sscope_strerror(rc));
		return SSC_EXIT_USAGE;
	}
	ssc_err(cmd, "%s: %s", shown, sscope_strerror(rc < 0 ? -rc : EIO));
	return SSC_EXIT_FAIL;
}

int ssc_write_failed(const char *cmd, const char *path, int rc)
{
	char *shown = shown_name(path);
	int e = say_failed(cmd, shown ? shown : path, rc);

	free(shown);
	return e;
}

struct sink {
	struct ssc_atomic a;
	const char *cmd;
	char *shown; /* the name in messages */
	int slot;
};

static bool is_stdout(const char *path)
{
	return !path || !strcmp(path, "-");
}

/* "2.5 TB", "840 MB" */
static void fmt_bytes(char *buf, size_t len, double b)
{
	static const char *const unit[] = { "bytes", "kB", "MB", "GB", "TB", "PB" };
	size_t u = 0;

	while (b >= 1000 && u + 1 < sizeof(unit) / sizeof(unit[0])) {
		b /= 1000;
		u++;
	}
	snprintf(buf, len, "%.*f %s", u && b < 10 ? 1 : 0, b, unit[u]);
}

int ssc_out_room(const char *cmd, const struct ssc_out *out, double written,
		 double total, const char *hint, double *projected)
{
	const struct sink *s = out->priv;
	struct statvfs vf;
	struct stat st;
	double pos, need, avail;
	char a[32], b[32];

	*projected = 0;
	/* (the sink's FILE writes through to its descriptor) */
	if (!out->f || !s || s->a.fd < 0 || !(written > 0) || fflush(out->f) ||
	    fstat(s->a.fd, &st) || !S_ISREG(st.st_mode))
		return SSC_EXIT_OK;
	pos = (double)st.st_size;
	*projected = pos * total / written;
	need = *projected - pos;
	if (fstatvfs(s->a.fd, &vf))
		return SSC_EXIT_OK;
	avail = (double)vf.f_bavail * (double)vf.f_frsize;
	if (need <= avail)
		return SSC_EXIT_OK;
	fmt_bytes(a, sizeof(a), *projected);
	fmt_bytes(b, sizeof(b), avail);
	ssc_err(cmd, "%s: about %s to write, %s free on its file system: %s",
		s->shown, a, b, hint);
	return SSC_EXIT_FAIL;
}

int ssc_file_open(const char *cmd, const char *path, struct ssc_out *out)
{
	struct sink *s = calloc(1, sizeof(*s));
	sigset_t old;
	int rc;

	out->f = NULL;
	out->priv = NULL;
	if (s)
		s->shown = shown_name(path);
	if (!s || !s->shown) {
		if (s)
			free(s);
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	s->cmd = cmd;
	hold_signals(&old);
	rc = ssc_atomic_open(&s->a, is_stdout(path) ? "-" : path);
	s->slot = rc || !s->a.tmp ? -1 : track(tmp_files, N_TMP_FILES, s->a.tmp);
	release_signals(&old);
	if (rc) {
		say_failed(cmd, s->shown, rc);
		free(s->shown);
		free(s);
		return SSC_EXIT_FAIL;
	}
	out->f = s->a.f;
	out->priv = s;
	return SSC_EXIT_OK;
}

int ssc_file_close(struct ssc_out *out, bool ok)
{
	struct sink *s = out->priv;
	sigset_t old;
	int e;

	if (!s)
		return ok ? SSC_EXIT_OK : SSC_EXIT_FAIL;
	hold_signals(&old);
	if (ok) {
		e = ssc_atomic_commit(&s->a);
		if (e)
			ssc_atomic_abort(&s->a);
	} else {
		/* the caller's failure, or a write error it saw (said here) */
		e = ssc_atomic_error(&s->a);
		ssc_atomic_abort(&s->a);
	}
	untrack(tmp_files, s->slot);
	release_signals(&old);
	if (e)
		say_failed(s->cmd, s->shown, e);
	free(s->shown);
	free(s);
	out->priv = NULL;
	out->f = NULL;
	return ok && !e ? SSC_EXIT_OK : SSC_EXIT_FAIL;
}

int ssc_out_open(const struct ssc_common *co, struct ssc_out *out)
{
	return ssc_file_open(co->cmd, co->output, out);
}

int ssc_out_close(const struct ssc_common *co, struct ssc_out *out, bool ok)
{
	(void)co;
	return ssc_file_close(out, ok);
}

char *ssc_path_join(const char *dir, const char *name)
{
	size_t n = strlen(dir) + strlen(name) + 2;
	char *p = malloc(n);

	if (p)
		snprintf(p, n, "%s/%s", dir, name);
	return p;
}

int ssc_file_put(const char *path, const void *buf, size_t len)
{
	struct ssc_atomic a;
	sigset_t old;
	int rc, slot;

	hold_signals(&old);
	rc = ssc_atomic_open(&a, path);
	slot = rc || !a.tmp ? -1 : track(tmp_files, N_TMP_FILES, a.tmp);
	release_signals(&old);
	if (rc)
		return rc;
	if (len && fwrite(buf, 1, len, a.f) != len)
		fflush(a.f);
	hold_signals(&old);
	rc = ssc_atomic_error(&a);
	if (rc)
		ssc_atomic_abort(&a);
	else if ((rc = ssc_atomic_commit(&a)) != 0)
		ssc_atomic_abort(&a);
	untrack(tmp_files, slot);
	release_signals(&old);
	return rc;
}

int ssc_stdout_finish(const char *cmd)
{
	static bool said; /* once: stdio forgets the errno after a failure */

	errno = 0;
	if (fflush(stdout) == 0 && !ferror(stdout))
		return SSC_EXIT_OK;
	if (said)
		return SSC_EXIT_FAIL;
	said = true;
	return say_failed(cmd, "standard output", errno ? -errno : -EIO);
}

/* ------------------------------------------------------------ guard */

/* What a path is: its device and inode when it exists, else its folder's
 * and its last component (for two outputs not written yet). */
struct ident {
	bool exists, parent;
	dev_t dev;
	ino_t ino;
	mode_t mode;
	const char *base;
};

static struct ident ident_of(const char *path)
{
	struct ident id = { 0 };
	struct stat st;

	if (!strcmp(path, "-") ? fstat(STDIN_FILENO, &st) == 0 :
				 stat(path, &st) == 0) {
		id.exists = true;
		id.dev = st.st_dev;
		id.ino = st.st_ino;
		id.mode = st.st_mode;
		return id;
	}
	{
		const char *sl = strrchr(path, '/');
		char *dir = sl ? strndup(path, sl == path ? 1 : (size_t)(sl - path)) :
				 strdup(".");

		if (dir && stat(dir, &st) == 0) {
			id.parent = true;
			id.dev = st.st_dev;
			id.ino = st.st_ino;
			id.base = sl ? sl + 1 : path;
		}
		free(dir);
	}
	return id;
}

static bool same(const struct ident *a, const struct ident *b)
{
	if (a->exists != b->exists || a->parent != b->parent ||
	    (!a->exists && !a->parent))
		return false;
	if (a->dev != b->dev || a->ino != b->ino)
		return false;
	return a->exists || !strcmp(a->base, b->base);
}

/* Is the existing file @p path inside the folder @p dir (at any depth)? */
static bool inside(const char *path, const struct ident *dir)
{
	char *real = realpath(path, NULL);
	bool in = false;

	while (real && !in) {
		char *sl = strrchr(real, '/');
		struct stat st;

		if (!sl || sl == real) {
			in = stat("/", &st) == 0 && st.st_dev == dir->dev &&
			     st.st_ino == dir->ino;
			break;
		}
		*sl = '\0';
		in = stat(real, &st) == 0 && st.st_dev == dir->dev &&
		     st.st_ino == dir->ino;
	}
	free(real);
	return in;
}

/* Is the output @p path (existing or not) in the report folder @p dpath
 * (ident @p dir), at any depth?  By name while the folder does not exist
 * yet. */
static bool in_folder(const char *path, const char *dpath,
		      const struct ident *dir)
{
	size_t n = strlen(dpath);
	const char *sl = strrchr(path, '/');
	char *parent;
	struct stat st;
	bool in;

	while (n > 1 && dpath[n - 1] == '/')
		n--;
	if (!strncmp(path, dpath, n) && path[n] == '/')
		return true;
	if (!dir->exists || !S_ISDIR(dir->mode))
		return false;
	parent = sl ? strndup(path, sl == path ? 1 : (size_t)(sl - path)) :
		      strdup(".");
	in = parent && stat(parent, &st) == 0 &&
	     ((st.st_dev == dir->dev && st.st_ino == dir->ino) ||
	      inside(parent, dir));
	free(parent);
	return in;
}

int ssc_guard_check(const char *cmd, const struct ssc_guard_item *items,
		    size_t n, bool stdout_out)
{
	struct ident *ids = calloc(n ? n : 1, sizeof(*ids));
	int rc = SSC_EXIT_OK;

	if (!ids) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	for (size_t i = 0; i < n; i++) {
		if (items[i].role != SSC_GUARD_IN && !*items[i].path) {
			rc = ssc_usage_error(cmd, "%s: an empty file name", items[i].what);
			goto out;
		}
		if (items[i].role != SSC_GUARD_IN && !strcmp(items[i].path, "-"))
			continue; /* standard output: below */
		ids[i] = ident_of(items[i].path);
	}
	for (size_t i = 0; i < n && !rc; i++) {
		const struct ssc_guard_item *o = &items[i];

		if (o->role == SSC_GUARD_IN || (!ids[i].exists && !ids[i].parent))
			continue;
		if (ids[i].exists && (S_ISCHR(ids[i].mode) || S_ISBLK(ids[i].mode)))
			continue; /* devices are written through, never replaced */
		for (size_t j = 0; j < n && !rc; j++) {
			const struct ssc_guard_item *x = &items[j];

			if (j == i)
				continue;
			if (x->role == SSC_GUARD_IN && ids[j].exists &&
			    S_ISREG(ids[j].mode) && same(&ids[i], &ids[j])) {
				ssc_err(cmd, "%s %s: the same file as the input %s: refusing to overwrite an input",
					o->what, o->path,
					strcmp(x->path, "-") ? x->path : "(standard input)");
				rc = SSC_EXIT_USAGE;
			} else if (x->role == SSC_GUARD_IN && ids[j].exists &&
				   S_ISREG(ids[j].mode) && o->role == SSC_GUARD_DIR &&
				   ids[i].exists && S_ISDIR(ids[i].mode) &&
				   inside(x->path, &ids[i])) {
				ssc_err(cmd, "%s %s: holds the input %s, and a report folder is replaced as a whole: choose another folder",
					o->what, o->path, x->path);
				rc = SSC_EXIT_USAGE;
			} else if (x->role != SSC_GUARD_IN && j > i &&
				   same(&ids[i], &ids[j])) {
				ssc_err(cmd, "%s %s and %s %s: the same file: give each output its own",
					o->what, o->path, x->what, x->path);
				rc = SSC_EXIT_USAGE;
			}
		}
	}
	/* a file written into a report folder would go with the old folder
	 * when the new one is put in its place */
	for (size_t i = 0; i < n && !rc; i++)
		for (size_t j = 0; j < n && !rc; j++)
			if (items[i].role == SSC_GUARD_OUT &&
			    items[j].role == SSC_GUARD_DIR &&
			    strcmp(items[i].path, "-") &&
			    in_folder(items[i].path, items[j].path, &ids[j])) {
				ssc_err(cmd, "%s %s: inside the %s %s, which is replaced as a whole: write it outside the folder",
					items[i].what, items[i].path, items[j].what,
					items[j].path);
				rc = SSC_EXIT_USAGE;
			}
	if (!rc && stdout_out) {
		struct stat st;
		struct ident so = { 0 };

		if (fstat(STDOUT_FILENO, &st) == 0 && S_ISREG(st.st_mode)) {
			so.exists = true;
			so.dev = st.st_dev;
			so.ino = st.st_ino;
			for (size_t j = 0; j < n && !rc; j++)
				if (items[j].role == SSC_GUARD_IN && ids[j].exists &&
				    S_ISREG(ids[j].mode) && same(&so, &ids[j])) {
					ssc_err(cmd, "standard output: the same file as the input %s: refusing to overwrite an input",
						strcmp(items[j].path, "-") ? items[j].path :
									     "(standard input)");
					rc = SSC_EXIT_USAGE;
				}
		}
	}
out:
	free(ids);
	return rc;
}

/* ------------------------------------------------------------ folders */

/* the file that marks a report folder sensorscope wrote */
#define SSC_REPORT_MARK ".sensorscope-report"

/* Is @p name a file a report folder holds: its mark, report.*, or STAGE.ext /
 * STAGE-N.ext for a stage of @p ctx (a NULL-terminated list)? */
static bool report_file(const char *name, void *ctx)
{
	const char *const *stages = ctx;
	static const char *const exts[] = { "json", "png", "svg", "txt", "csv",
					    "html", NULL };
	const char *dot = strrchr(name, '.');
	size_t stem;
	bool ext = false;

	if (!strcmp(name, SSC_REPORT_MARK))
		return true;
	if (!dot)
		return false;
	for (size_t i = 0; exts[i]; i++)
		ext |= !strcmp(dot + 1, exts[i]);
	if (!ext)
		return false;
	stem = (size_t)(dot - name);
	if (stem == 6 && !strncmp(name, "report", 6))
		return true;
	for (size_t i = 0; stages && stages[i]; i++) {
		size_t l = strlen(stages[i]);
		const char *p = name + l;

		if (stem < l || strncmp(name, stages[i], l))
			continue;
		if (p == dot)
			return true;
		if (*p++ != '-' || p == dot)
			continue;
		while (p < dot && *p >= '0' && *p <= '9')
			p++;
		if (p == dot)
			return true;
	}
	return false;
}

static bool not_report_file(const char *name, void *ctx)
{
	return !report_file(name, ctx);
}

static int mkdir_parents(const char *path)
{
	char *copy = strdup(path);
	int rc = 0;

	if (!copy)
		return -ENOMEM;
	for (char *p = copy + 1; *p && !rc; p++) {
		if (*p != '/')
			continue;
		*p = '\0';
		if (mkdir(copy, 0777) != 0 && errno != EEXIST)
			rc = -errno;
		*p = '/';
	}
	free(copy);
	return rc;
}

/* Is the current folder @p dir or inside it? */
static bool holds_cwd(const char *dir)
{
	struct stat st;
	struct ident id = { 0 };
	char *cwd = getcwd(NULL, 0);
	bool in;

	if (!cwd || stat(dir, &st) != 0) {
		free(cwd);
		return false;
	}
	id.exists = true;
	id.dev = st.st_dev;
	id.ino = st.st_ino;
	in = (stat(cwd, &st) == 0 && st.st_dev == id.dev && st.st_ino == id.ino) ||
	     inside(cwd, &id);
	free(cwd);
	return in;
}

/*
 * A staging folder (TARGET.tmp.XXXXXX) is locked (flock) by the run that
 * made it for as long as it lives; the lock goes with the process, however
 * it ends.  One that can be locked was left by a run that was killed where
 * no handler runs (SIGKILL, the out-of-memory killer, a power cut): its
 * report files (and their temporary files) are removed, and the folder
 * with them when nothing else is in it.  A run that finds its own new folder gone under it (removed
 * between its creation and its lock) makes another.  (A previous report
 * moved aside, TARGET.old.XXXXXX, where the file system cannot exchange
 * two names, is the user's: it is never removed here.)
 */
static bool stale_name(const char *name, const char *base, size_t nb)
{
	size_t n = strlen(name);

	return n == nb + 11 && !strncmp(name, base, nb) &&
	       !strncmp(name + nb, ".tmp.", 5);
}

/* In a stale staging folder: a report file, or the temporary file one
 * was being written to (NAME.tmp.XXXXXX), is removed; anything else is
 * kept. */
static bool stale_keep(const char *name, void *stages)
{
	size_t n = strlen(name);
	char base[NAME_MAX + 1];

	if (report_file(name, stages))
		return false;
	if (n <= 11 || n > NAME_MAX || strncmp(name + n - 11, ".tmp.", 5))
		return true;
	memcpy(base, name, n - 11);
	base[n - 11] = '\0';
	return !report_file(base, stages);
}

static void sweep_stale(const char *target, const char *const *stages)
{
	char *copy = strdup(target), *slash, *parent, *base;
	DIR *d;
	struct dirent *ent;
	size_t nb;

	if (!copy)
		return;
	slash = strrchr(copy, '/');
	if (slash) {
		*slash = '\0';
		parent = slash == copy ? "/" : copy;
		base = slash + 1;
	} else {
		parent = ".";
		base = copy;
	}
	nb = strlen(base);
	d = opendir(parent);
	while (d && (ent = readdir(d))) {
		int fd;

		if (!stale_name(ent->d_name, base, nb))
			continue;
		fd = openat(dirfd(d), ent->d_name,
			    O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
		if (fd < 0)
			continue;
		if (flock(fd, LOCK_EX | LOCK_NB) == 0) {
			size_t np = strlen(parent), ne = strlen(ent->d_name);
			char *path = malloc(np + ne + 2);

			if (path) {
				memcpy(path, parent, np);
				path[np] = '/';
				memcpy(path + np + 1, ent->d_name, ne + 1);
				remove_flat_dir(path, stale_keep,
						(void *)stages);
				free(path);
			}
		}
		close(fd); /* and its lock */
	}
	if (d)
		closedir(d);
	free(copy);
}

/* Lock the new staging folder od->dir; false when it was removed as
 * stale before the lock was taken (then make another). */
static bool lock_staging(struct ssc_outdir *od)
{
	struct stat st;

	od->lock_fd = open(od->dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW |
				    O_CLOEXEC);
	if (od->lock_fd < 0)
		return errno != ENOENT;
	if (flock(od->lock_fd, LOCK_EX) != 0 || fstat(od->lock_fd, &st) != 0 ||
	    st.st_nlink > 0)
		return true;
	close(od->lock_fd);
	od->lock_fd = -1;
	return false;
}

int ssc_outdir_begin(const char *cmd, const char *what, const char *dir,
		     const char *const *stages, struct ssc_outdir *od)
{
	struct stat st;
	mode_t mode;
	size_t n;
	int e;

	memset(od, 0, sizeof(*od));
	od->slot = -1;
	od->lock_fd = -1;
	od->stages = stages;
	if (!*dir)
		return ssc_usage_error(cmd, "%s: an empty folder name", what);
	/* the name without trailing slashes: the staging folder goes beside
	 * it, not inside */
	od->shown = strdup(dir);
	if (!od->shown) {
		ssc_err(cmd, "out of memory");
		return SSC_EXIT_FAIL;
	}
	n = strlen(od->shown);
	while (n > 1 && od->shown[n - 1] == '/')
		od->shown[--n] = '\0';
	if (stat(od->shown, &st) == 0) {
		DIR *d;
		struct dirent *ent;
		int bad = 0;

		if (!S_ISDIR(st.st_mode)) {
			ssc_err(cmd, "%s: %s", od->shown, sscope_strerror(ENOTDIR));
			ssc_outdir_abort(od);
			return SSC_EXIT_FAIL;
		}
		if (holds_cwd(od->shown)) {
			ssc_err(cmd, "%s %s: a report folder is replaced as a whole; it cannot hold the current folder: choose another folder",
				what, od->shown);
			ssc_outdir_abort(od);
			return SSC_EXIT_USAGE;
		}
		d = opendir(od->shown);
		if (!d) {
			ssc_err(cmd, "%s: %s", od->shown, sscope_strerror(errno));
			ssc_outdir_abort(od);
			return SSC_EXIT_FAIL;
		}
		{
			char first[256] = "";
			bool has_report = false;

			while (!bad && (ent = readdir(d))) {
				struct stat es;

				if (!strcmp(ent->d_name, ".") || !strcmp(ent->d_name, ".."))
					continue;
				if (fstatat(dirfd(d), ent->d_name, &es, AT_SYMLINK_NOFOLLOW) != 0 ||
				    !S_ISREG(es.st_mode) || !report_file(ent->d_name, (void *)stages)) {
					ssc_err(cmd, "%s %s: holds '%s', which is not part of a report, and a report folder is replaced as a whole: choose another folder",
						what, od->shown, ent->d_name);
					bad = 1;
				}
				if (!first[0])
					snprintf(first, sizeof(first), "%s", ent->d_name);
				has_report |= !strncmp(ent->d_name, "report.", 7) ||
					      !strcmp(ent->d_name, SSC_REPORT_MARK);
			}
			/* files named like an analysis' but no report beside
			 * them: the user's own files, not an earlier report */
			if (!bad && first[0] && !has_report) {
				ssc_err(cmd, "%s %s: holds '%s' but no report (report.html, .json or .txt): not a report folder, and a report folder is replaced as a whole: choose another folder",
					what, od->shown, first);
				bad = 1;
			}
		}
		closedir(d);
		if (bad) {
			ssc_outdir_abort(od);
			return SSC_EXIT_USAGE;
		}
		od->target = realpath(od->shown, NULL); /* links resolved */
		od->existed = true;
		mode = st.st_mode & 07777;
	} else if (errno == ENOENT) {
		mode_t um = umask(0);

		umask(um);
		mode = 0777 & ~um;
		od->target = strdup(od->shown);
		e = od->target ? mkdir_parents(od->target) : -ENOMEM;
		if (e) {
			ssc_err(cmd, "%s: %s", od->shown, sscope_strerror(-e));
			ssc_outdir_abort(od);
			return SSC_EXIT_FAIL;
		}
	} else {
		ssc_err(cmd, "%s: %s", od->shown, sscope_strerror(errno));
		ssc_outdir_abort(od);
		return SSC_EXIT_FAIL;
	}
	n = od->target ? strlen(od->target) : 0;
	od->dir = od->target ? malloc(n + 12) : NULL;
	if (!od->dir) {
		ssc_err(cmd, "%s: %s", od->shown, sscope_strerror(errno ? errno : ENOMEM));
		ssc_outdir_abort(od);
		return SSC_EXIT_FAIL;
	}
	sweep_stale(od->target, stages);
	for (bool locked = false; !locked;) {
		sigset_t old;
		char *made;

		memcpy(od->dir, od->target, n);
		memcpy(od->dir + n, ".tmp.XXXXXX", 12);
		hold_signals(&old);
		made = mkdtemp(od->dir);
		e = errno;
		if (made)
			od->slot = track(tmp_dirs, N_TMP_DIRS, od->dir);
		release_signals(&old);
		if (!made) {
			free(od->dir);
			od->dir = NULL;
			ssc_err(cmd, "%s: %s", od->shown, sscope_strerror(e));
			ssc_outdir_abort(od);
			return SSC_EXIT_FAIL;
		}
		locked = lock_staging(od);
		if (!locked) {
			untrack(tmp_dirs, od->slot);
			od->slot = -1;
		}
	}
	chmod(od->dir, mode);
	/* the mark of a report folder: the next run may replace it (a folder
	 * without it, or without a report.*, is the user's) */
	{
		char *mk = malloc(strlen(od->dir) + sizeof("/" SSC_REPORT_MARK));
		FILE *mf;

		if (mk) {
			sprintf(mk, "%s/%s", od->dir, SSC_REPORT_MARK);
			mf = fopen(mk, "w");
			if (mf) {
				fputs("A report folder written by sensorscope: the next run into it replaces the whole folder.\n", mf);
				fclose(mf);
			}
			free(mk);
		}
	}
	staging = od;
	return SSC_EXIT_OK;
}

/* The staging folder is gone or in place: stop tracking it, free. */
static void outdir_forget(struct ssc_outdir *od)
{
	untrack(tmp_dirs, od->slot);
	if (staging == od)
		staging = NULL;
	if (od->lock_fd >= 0)
		close(od->lock_fd);
	free(od->dir);
	free(od->target);
	free(od->shown);
	memset(od, 0, sizeof(*od));
	od->slot = -1;
	od->lock_fd = -1;
}

int ssc_outdir_commit(const char *cmd, struct ssc_outdir *od)
{
	sigset_t old;
	int e = 0;

	hold_signals(&old);
	if (!od->existed) {
		if (rename(od->dir, od->target) != 0)
			e = errno;
	} else if (renameat2(AT_FDCWD, od->dir, AT_FDCWD, od->target,
			     RENAME_EXCHANGE) != 0) {
		e = errno;
		if (e == EINVAL || e == ENOSYS || e == EOPNOTSUPP) {
			/* no exchange on this file system: move the old folder
			 * aside, then the new one in */
			size_t n = strlen(od->target);
			char *aside = malloc(n + 12);

			e = ENOMEM;
			if (aside) {
				memcpy(aside, od->target, n);
				memcpy(aside + n, ".old.XXXXXX", 12);
				e = mkdtemp(aside) && rmdir(aside) == 0 &&
						    rename(od->target, aside) == 0 ?
					    0 : errno;
				if (!e && rename(od->dir, od->target) != 0) {
					e = errno;
					rename(aside, od->target);
				}
				if (!e) {
					/* what remains to remove is the old one */
					untrack(tmp_dirs, od->slot);
					free(od->dir);
					od->dir = aside;
					od->slot = track(tmp_dirs, N_TMP_DIRS, aside);
					aside = NULL;
				}
				free(aside);
			}
		}
	}
	release_signals(&old);
	if (e) {
		ssc_err(cmd, "%s: %s", od->shown, sscope_strerror(e));
		ssc_outdir_abort(od);
		return SSC_EXIT_FAIL;
	}
	/* od->dir now holds the previous report, or nothing; a file someone
	 * put there meanwhile is kept */
	if (od->existed &&
	    remove_flat_dir(od->dir, not_report_file, (void *)od->stages) != 0 &&
	    errno != ENOENT)
		ssc_err(cmd, "warning: %s: the previous report is left in %s (%s)",
			od->shown, od->dir, sscope_strerror(errno));
	outdir_forget(od);
	return SSC_EXIT_OK;
}

void ssc_outdir_abort(struct ssc_outdir *od)
{
	if (od->dir)
		remove_flat_dir(od->dir, NULL, NULL);
	outdir_forget(od);
}

const char *ssc_output_option(const char *name)
{
	static const char *const writers[][2] = {
		{ "output", "-o" }, { "plot", "--plot" }, { "kalibr", "--kalibr" },
		{ "save-calibration", "--save-calibration" },
		{ "openvins", "--openvins" }, { "imu-utils", "--imu-utils" },
	};

	for (size_t i = 0; name && i < sizeof(writers) / sizeof(writers[0]); i++)
		if (!strcmp(name, writers[i][0]))
			return writers[i][1];
	return NULL;
}
