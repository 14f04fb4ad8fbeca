/* SPDX-License-Identifier: GPL-3.0-or-later */
/**
 * @file sscope-gsl.h
 * @brief GSL's errors as records instead of abort(), for host programs.
 *
 * The library computes with GSL.  A GSL routine that meets a case it cannot
 * return (a special function out of range, a root that is not bracketed, a
 * singular factor the library did not expect) calls GSL's error handler,
 * whose default is abort().  The library never installs a handler by itself:
 * the handler is one process-wide setting of GSL's, and a library must not
 * change it behind its host program's back.  The host chooses:
 *
 * - its own handler (gsl_set_error_handler(), as the `sensorscope` command
 *   does: one line, exit status 1);
 * - or sscope_gsl_errors_record(): every such error is recorded instead and
 *   the calling routine goes on with what GSL returned (often NaN or an
 *   error code), so the host checks sscope_gsl_error_pending() after each
 *   library call and discards that call's results when it is true (the
 *   Python module raises sensorscope.Error).
 *
 * Where the library expects a GSL failure and handles it from the return
 * code (a Cholesky factor that fails on an ill-conditioned matrix, a
 * regression without enough rank), nothing is recorded and no handler is
 * called.
 *
 * Threads: a thread that has called one of these functions keeps its own
 * record (thread-local: the first error since its last
 * sscope_gsl_error_take()).  An error raised on any other thread, which
 * includes the library's worker threads (OpenMP teams, reader pools) during
 * a call, goes to one process-wide record (the first such error until it is
 * taken), which every thread's sscope_gsl_error_pending() sees and the
 * first sscope_gsl_error_take() returns: it is never lost, but when several
 * threads call the library at once it may be reported to another of them
 * than the one whose call raised it.
 */
#ifndef SSCOPE_GSL_H
#define SSCOPE_GSL_H

#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Install the recording GSL error handler (gsl_set_error_handler()), for
 * the whole process, in place of the one before (GSL's abort() by
 * default).  Call it once, before threads call the library, and do not
 * install another handler afterwards: the library's expected-failure
 * stretches rely on it to stay quiet without touching the process-wide
 * handler.  It also gives the calling thread its own record.
 */
void sscope_gsl_errors_record(void);

/**
 * Whether a GSL error is waiting: in the calling thread's record or in the
 * process-wide one (worker threads).  Cheap: meant for a check after every
 * library call.
 * @return true when sscope_gsl_error_take() would return 1.
 */
bool sscope_gsl_error_pending(void);

/**
 * Take (return and clear) the calling thread's recorded GSL error, or
 * when it has none the process-wide one.
 * @param gsl_errno set to GSL's error code (gsl_errno.h, e.g. GSL_EDOM),
 *                  0 when nothing was recorded; may be NULL.
 * @param buf       receives one line "FILE:LINE: REASON" (GSL's source
 *                  file and its reason), truncated to @p len bytes with
 *                  its NUL; "" when nothing was recorded; may be NULL when
 *                  @p len is 0.  Owned by the caller.
 * @param len       size of @p buf in bytes.
 * @return 1 when an error was taken, 0 when none was recorded.
 */
int sscope_gsl_error_take(int *gsl_errno, char *buf, size_t len);

#ifdef __cplusplus
}
#endif

#endif /* SSCOPE_GSL_H */
