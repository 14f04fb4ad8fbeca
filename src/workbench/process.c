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
 * libgomp reads OMP_WAIT_POLICY once, when it is loaded (before main), so
 * the command runs itself again with the policy set (about a millisecond);
 * a policy the user set is kept, and `info`, which starts no OpenMP
 * thread, is not run twice.
 */
void ssc_omp_wait_passive(char **argv)
{
	char exe[PATH_MAX];
	ssize_t n;

	if (getenv("OMP_WAIT_POLICY"))
		return;
	n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
	if (n <= 0 || setenv("OMP_WAIT_POLICY", "passive", 1))
		return;
	exe[n] = '\0';
	execv(exe, argv);
	unsetenv("OMP_WAIT_POLICY"); /* not run again: carry on spinning */
}
