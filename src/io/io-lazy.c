/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * Libraries that only some inputs need (the ROS containers' codecs and
 * SQLite for rosbag2's .db3 files), opened with dlopen() when the first
 * such input is read instead of at every start: linked, they cost each
 * command, `--help` included, their loading and relocation (libsqlite3
 * alone more than /bin/true's whole run).  The library is opened by its
 * run-time name (the SONAME of Debian's runtime package, which the -dev
 * package the build needs depends on) and its functions are found with
 * dlsym() into the caller's table, once per process.
 */
#include "internal.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "io-formats.h"

static pthread_mutex_t lazy_lock = PTHREAD_MUTEX_INITIALIZER;

int ssc_lazylib_load(struct ssc_lazylib *l, struct sscope_diag *diag,
		     const char *what)
{
	int st = __atomic_load_n(&l->state, __ATOMIC_ACQUIRE);

	if (st == 0) {
		pthread_mutex_lock(&lazy_lock);
		st = l->state;
		if (st == 0) {
			void *h = dlopen(l->soname, RTLD_NOW | RTLD_LOCAL);

			st = 1;
			if (!h) {
				const char *e = dlerror();

				snprintf(l->why, sizeof(l->why), "%s",
					 e ? e : l->soname);
				st = -ENOSYS;
			}
			for (size_t i = 0; h && l->names[i]; i++) {
				void *f = dlsym(h, l->names[i]);

				if (!f) {
					snprintf(l->why, sizeof(l->why),
						 "%s has no %s", l->soname,
						 l->names[i]);
					st = -ENOSYS;
					break;
				}
				memcpy(&l->fn[i], &f, sizeof(f));
			}
			__atomic_store_n(&l->state, st, __ATOMIC_RELEASE);
		}
		pthread_mutex_unlock(&lazy_lock);
	}
	if (st > 0)
		return 0;
	return ssc_diag(diag, -ENOSYS,
			"%s: cannot load %s (%s): install it (Debian: apt-get install %s)",
			what, l->soname, l->why, l->package);
}
