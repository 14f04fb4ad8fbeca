/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * GSL's errors recorded instead of abort() (src/core/gslerr.c,
 * sscope-gsl.h).  The oracle is GSL itself: log(x) of a negative x is its
 * domain error (GSL_EDOM), exp(1000) its overflow (GSL_EOVRFLW), and with
 * GSL's default handler either aborts the process (checked in a forked
 * child).  Then: the first error of a thread is kept, taken once, and
 * cleared; a thread's record is its own; an error on a thread that keeps
 * none (an OpenMP worker, a plain thread) reaches the process-wide record
 * and is not lost; the library's quiet stretches record nothing and leave
 * the handler as they found it.
 *
 * make check-valgrind runs every case in one process (CK_FORK=no): the
 * cases without the recorder come first, and the recorder, once
 * installed, stays.
 */
#include "config.h"

#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_sf_exp.h>
#include <gsl/gsl_sf_log.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "check-main.h"
#include "internal.h"
#include "sensorscope.h"

/* the status a forked child ends with after calling f */
static int child_status(void (*f)(void))
{
	pid_t pid = fork();
	int st = 0;

	ck_assert_int_ge(pid, 0);
	if (pid == 0) {
		/* an expected abort() leaves no core file behind */
		struct rlimit no_core = { 0, 0 };

		setrlimit(RLIMIT_CORE, &no_core);
		/* nor GSL's two lines on stderr */
		if (!freopen("/dev/null", "w", stderr))
			_exit(3);
		f();
		_exit(0);
	}
	ck_assert_int_eq(waitpid(pid, &st, 0), pid);
	return st;
}

static volatile double sink;

static void domain_error(void)
{
	sink = gsl_sf_log(-2.385);
}

static void no_record_then_domain_error(void)
{
	gsl_set_error_handler(NULL); /* GSL's default, whatever came before */
	domain_error();
}

/* the error inside a quiet stretch: the child lives */
static void quiet_domain_error(void)
{
	struct ssc_gsl_quiet q;

	gsl_set_error_handler(NULL);
	ssc_gsl_quiet_begin(&q);
	domain_error();
	ssc_gsl_quiet_end(&q);
}

static void take_expect(int code, const char *reason)
{
	char buf[256];
	int got;

	ck_assert(sscope_gsl_error_pending());
	ck_assert_int_eq(sscope_gsl_error_take(&got, buf, sizeof(buf)), 1);
	ck_assert_int_eq(got, code);
	ck_assert_msg(strstr(buf, reason) != NULL, "'%s' lacks '%s'", buf,
		      reason);
	/* GSL's own file and line: "FILE:LINE: REASON" */
	ck_assert_msg(strstr(buf, ".c:") != NULL, "'%s' has no file:line", buf);
}

static void drain(void)
{
	while (sscope_gsl_error_take(NULL, NULL, 0))
		;
	ck_assert(!sscope_gsl_error_pending());
}

/* Without the recorder: GSL's default aborts, which is the reason for it;
 * a quiet stretch switches the handler off and back (the child of the
 * stretch survives; after it, the default aborts again). */
START_TEST(default_aborts)
{
	int st = child_status(no_record_then_domain_error);

	ck_assert_msg(WIFSIGNALED(st) && WTERMSIG(st) == SIGABRT,
		      "status %#x: a domain error did not abort", st);
	st = child_status(quiet_domain_error);
	ck_assert_msg(WIFEXITED(st) && WEXITSTATUS(st) == 0,
		      "status %#x: a quiet stretch did not keep quiet", st);
}
END_TEST

static void quiet_then_domain_error(void)
{
	quiet_domain_error();
	domain_error();
}

START_TEST(quiet_restores_handler)
{
	int st = child_status(quiet_then_domain_error);

	ck_assert_msg(WIFSIGNALED(st) && WTERMSIG(st) == SIGABRT,
		      "status %#x: the handler stayed off after the stretch",
		      st);
}
END_TEST

/* nothing recorded: 0, an empty line, code 0 */
START_TEST(take_empty)
{
	char buf[16] = "x";
	int code = 7;

	ck_assert_int_eq(sscope_gsl_error_take(&code, buf, sizeof(buf)), 0);
	ck_assert_int_eq(code, 0);
	ck_assert_str_eq(buf, "");
	ck_assert(!sscope_gsl_error_pending());
}
END_TEST

START_TEST(record_take)
{
	char buf[8];
	int code;
	double v;

	sscope_gsl_errors_record();
	drain();
	v = gsl_sf_log(-2.385);
	ck_assert(isnan(v));
	take_expect(GSL_EDOM, "domain error");
	ck_assert(!sscope_gsl_error_pending());
	ck_assert_int_eq(sscope_gsl_error_take(&code, NULL, 0), 0);

	/* the first error is kept, later ones until the take are not */
	sink = gsl_sf_exp(1000.0);
	sink = gsl_sf_log(-2.385);
	take_expect(GSL_EOVRFLW, "overflow");
	ck_assert(!sscope_gsl_error_pending());

	/* a short buffer: truncated, terminated */
	sink = gsl_sf_log(-2.385);
	ck_assert_int_eq(sscope_gsl_error_take(&code, buf, sizeof(buf)), 1);
	ck_assert_int_eq(code, GSL_EDOM);
	ck_assert_uint_eq(strlen(buf), sizeof(buf) - 1);
	/* no buffer at all, the record is still taken */
	sink = gsl_sf_log(-2.385);
	ck_assert_int_eq(sscope_gsl_error_take(NULL, NULL, 0), 1);
	ck_assert(!sscope_gsl_error_pending());
}
END_TEST

/* A failure the library handles from the return code (a Cholesky factor
 * of a matrix that is not positive definite) records nothing; the
 * recorder is in place again after the stretch. */
START_TEST(quiet_records_nothing)
{
	double a[4] = { 1.0, 2.385, 2.385, 1.0 };
	gsl_matrix_view m = gsl_matrix_view_array(a, 2, 2);
	struct ssc_gsl_quiet q, q2;
	int rc;

	sscope_gsl_errors_record();
	drain();
	ssc_gsl_quiet_begin(&q);
	ssc_gsl_quiet_begin(&q2); /* stretches nest */
	ssc_gsl_quiet_end(&q2);
	rc = gsl_linalg_cholesky_decomp1(&m.matrix);
	ssc_gsl_quiet_end(&q);
	ck_assert_int_eq(rc, GSL_EDOM);
	ck_assert(!sscope_gsl_error_pending());
	sink = gsl_sf_log(-2.385);
	take_expect(GSL_EDOM, "domain error");
}
END_TEST

struct job {
	bool keep;      /* asks for its own record before the error */
	int taken, code;
};

static void *thread_error(void *arg)
{
	struct job *j = arg;

	if (j->keep)
		ck_assert(!sscope_gsl_error_pending());
	sink = gsl_sf_exp(1000.0);
	if (j->keep)
		j->taken = sscope_gsl_error_take(&j->code, NULL, 0);
	return NULL;
}

static void run_thread(struct job *j)
{
	pthread_t t;

	ck_assert_int_eq(pthread_create(&t, NULL, thread_error, j), 0);
	ck_assert_int_eq(pthread_join(t, NULL), 0);
}

/* A thread that keeps its own record: its error is its own, another
 * thread's record stays as it was. */
START_TEST(per_thread)
{
	struct job j = { .keep = true };

	sscope_gsl_errors_record();
	drain();
	sink = gsl_sf_log(-2.385); /* this thread's */
	run_thread(&j);
	ck_assert_int_eq(j.taken, 1);
	ck_assert_int_eq(j.code, GSL_EOVRFLW);
	take_expect(GSL_EDOM, "domain error");
	ck_assert(!sscope_gsl_error_pending());
}
END_TEST

/* A thread that keeps none (a worker): its error reaches the
 * process-wide record, which the caller sees after its own. */
START_TEST(worker_thread)
{
	struct job j = { .keep = false };

	sscope_gsl_errors_record();
	drain();
	run_thread(&j);
	take_expect(GSL_EOVRFLW, "overflow");
	ck_assert(!sscope_gsl_error_pending());

	sink = gsl_sf_log(-2.385);
	run_thread(&j);
	take_expect(GSL_EDOM, "domain error");     /* own first */
	take_expect(GSL_EOVRFLW, "overflow");      /* then the worker's */
	ck_assert(!sscope_gsl_error_pending());
}
END_TEST

/* OpenMP's workers: only the threads other than the caller (thread 0)
 * fail, the caller reads the error after the team. */
START_TEST(openmp_workers)
{
#ifdef _OPENMP
	int team = 0;

	sscope_gsl_errors_record();
	drain();
#pragma omp parallel num_threads(4)
	{
#pragma omp single
		team = omp_get_num_threads();
		if (omp_get_thread_num() != 0)
			sink = gsl_sf_exp(1000.0);
	}
	if (team < 2) {
		ck_assert(!sscope_gsl_error_pending());
		return;
	}
	take_expect(GSL_EOVRFLW, "overflow");
	ck_assert(!sscope_gsl_error_pending());
#endif
}
END_TEST

/* Many threads fail while another takes: every take returns a whole
 * record (a known code and reason), none is returned twice, and a record
 * made after the last take is still there at the end. */
#define N_FAIL 4
#define FAILS 2000

static atomic_int failing;

static void *fail_many(void *arg)
{
	(void)arg;
	for (int i = 0; i < FAILS; i++)
		sink = (i & 1) ? gsl_sf_exp(1000.0) : gsl_sf_log(-2.385);
	atomic_fetch_sub(&failing, 1);
	return NULL;
}

START_TEST(slot_race)
{
	pthread_t t[N_FAIL];
	char buf[256];
	int code, taken = 0;

	sscope_gsl_errors_record();
	drain();
	atomic_store(&failing, N_FAIL);
	for (int i = 0; i < N_FAIL; i++)
		ck_assert_int_eq(pthread_create(&t[i], NULL, fail_many, NULL),
				 0);
	while (atomic_load(&failing) > 0) {
		if (sscope_gsl_error_take(&code, buf, sizeof(buf))) {
			taken++;
			ck_assert(code == GSL_EDOM || code == GSL_EOVRFLW);
			/* GSL reports a failing gsl_sf_f() twice: the
			 * reason inside gsl_sf_f_e(), then its call */
			ck_assert_msg(code == GSL_EDOM ?
				      strstr(buf, "domain error") ||
				      strstr(buf, "gsl_sf_log_e") :
				      strstr(buf, "overflow") ||
				      strstr(buf, "gsl_sf_exp_e"), "%s", buf);
		}
	}
	for (int i = 0; i < N_FAIL; i++)
		ck_assert_int_eq(pthread_join(t[i], NULL), 0);
	/* the slot holds at most one record: one take drains it, and
	 * 8000 errors made at least one record */
	taken += sscope_gsl_error_take(NULL, NULL, 0);
	ck_assert_int_ge(taken, 1);
	ck_assert(!sscope_gsl_error_pending());
	run_thread(&(struct job){ .keep = false });
	take_expect(GSL_EOVRFLW, "overflow");
}
END_TEST

static Suite *make_suite(void)
{
	Suite *s = suite_create("gslerr");
	TCase *tc = tcase_create("default");

	/* first: the cases without the recorder (CK_FORK=no keeps it) */
	tcase_add_test(tc, default_aborts);
	tcase_add_test(tc, quiet_restores_handler);
	tcase_add_test(tc, take_empty);
	suite_add_tcase(s, tc);
	tc = tcase_create("record");
	tcase_add_test(tc, record_take);
	tcase_add_test(tc, quiet_records_nothing);
	tcase_add_test(tc, per_thread);
	tcase_add_test(tc, worker_thread);
	tcase_add_test(tc, openmp_workers);
	tcase_add_test(tc, slot_race);
	suite_add_tcase(s, tc);
	return s;
}
