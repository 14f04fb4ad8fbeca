/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * The process around a command: OpenMP's wait policy set before its
 * runtime starts.
 */
#include "workbench.h"

#include <limits.h>
#include <stdlib.h>
#include <unistd.h>

/*
 * OpenMP's worker threads busy-wait between parallel regions by default
 * (libgomp spins some 300,000 rounds before sleeping), taking a core from
 * the thread that reads the next block and from everything else on the
 * machine: a streamed psd spent half its CPU spinning.  sensorscope's
 * parallel regions are few and long, so passive waiting costs nothing.
 *
 * libgomp reads OMP_WAIT_POLICY once, in its constructor, before main.
 * The command's .preinit_array function runs before every library's
 * constructor (glibc's _dl_init calls the executable's pre-initialisers
 * first), but setenv() there is lost: libc's own initialisation, which
 * follows, points environ back at the environment block the kernel gave.
 * So the policy is written into that block, in place of one entry that no
 * library's constructor reads (the shell's "_", else another that is not
 * OpenMP's, the loader's, libc's or a sanitizer's), and that entry is put
 * back at the start of main (ssc_omp_wait_passive): the command, and what
 * it runs, see the user's environment unchanged.  Where no entry can be
 * borrowed (an empty environment) the command runs itself again with the
 * policy set, as it did before (about a millisecond and a second start).
 * A policy the user set is kept.  The man page's ENVIRONMENT section and
 * tests/cli-basics.sh (OMP_DISPLAY_ENV) check the outcome.
 */
static char **early_env;
static char *early_saved;
static size_t early_slot;

static bool has_prefix(const char *s, const char *p)
{
	while (*p && *s == *p) {
		s++;
		p++;
	}
	return !*p;
}

/* may this entry be hidden from the libraries' constructors? */
static bool borrowable(const char *e)
{
	static const char *const keep[] = { "OMP_", "GOMP_", "ACC_", "LD_",
					    "GLIBC_", "MALLOC_", "ASAN_",
					    "UBSAN_", "LSAN_", "TSAN_", "GCONV_",
					    "LOCPATH=", "TZ=", "LANG=", "LC_" };

	for (size_t i = 0; i < sizeof(keep) / sizeof(keep[0]); i++)
		if (has_prefix(e, keep[i]))
			return false;
	return true;
}

static void omp_policy_early(int argc, char **argv, char **envp)
{
	static char passive[] = "OMP_WAIT_POLICY=passive";
	size_t pick = SIZE_MAX;

	(void)argc;
	(void)argv;
	if (!envp)
		return;
	/* no libc here: it is not initialised yet */
	for (size_t i = 0; envp[i]; i++) {
		if (has_prefix(envp[i], "OMP_WAIT_POLICY="))
			return; /* the user's */
		if (has_prefix(envp[i], "_="))
			pick = i;
		else if (pick == SIZE_MAX || !has_prefix(envp[pick], "_="))
			if (borrowable(envp[i]))
				pick = i;
	}
	if (pick == SIZE_MAX)
		return;
	early_env = envp;
	early_slot = pick;
	early_saved = envp[pick];
	envp[pick] = passive;
}

__attribute__((section(".preinit_array"), used))
static void (*const ssc_preinit_omp)(int, char **, char **) = omp_policy_early;

void ssc_omp_wait_passive(char **argv, bool may_exec)
{
	char exe[PATH_MAX];
	ssize_t n;

	if (early_env) {
		/* the policy reached libgomp: give the entry back */
		early_env[early_slot] = early_saved;
		early_env = NULL;
		return;
	}
	if (!may_exec || getenv("OMP_WAIT_POLICY"))
		return;
	n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
	if (n <= 0 || setenv("OMP_WAIT_POLICY", "passive", 1))
		return;
	exe[n] = '\0';
	execv(exe, argv);
	unsetenv("OMP_WAIT_POLICY"); /* not run again: carry on spinning */
}
