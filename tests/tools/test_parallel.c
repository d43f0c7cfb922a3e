/* SPDX-License-Identifier: MIT */
/**
 * @file test_parallel.c
 * @brief aenl_parallel_for: every index exactly once at any thread count, a loop inside a task
 *        on that task's thread, the thread-count setting; aenl_parallel_try's first failure; and
 * the diagnosis, whose simulations it and the record-alone test run at once, giving the same answer
 * on one thread and on several.
 */
#define _POSIX_C_SOURCE 200809L

#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "aenl_diagnose_cases.h"
#include "aenl_tools/aenl_diagnose.h"
#include "aenl_tools/aenl_nltest.h"
#include "aenl_tools/aenl_parallel.h"
#include "unity.h"

#define N_MAX 1000u

void setUp(void)
{
}

void tearDown(void)
{
    aenl_set_jobs(0);
}

typedef struct
{
    unsigned count[N_MAX];
    pthread_t who[N_MAX];
    int nap; /* each task sleeps this many microseconds */
} tally_t;

static void tally(void *ctx, size_t i)
{
    tally_t *t = (tally_t *)ctx;
    t->count[i]++;
    t->who[i] = pthread_self();
    if (t->nap > 0)
    {
        const struct timespec ts = {0, 1000L * t->nap};
        (void)nanosleep(&ts, NULL);
    }
}

static size_t distinct_threads(const tally_t *t, size_t n)
{
    size_t d = 0;
    for (size_t i = 0; i < n; ++i)
    {
        size_t k = 0;
        while (k < i && !pthread_equal(t->who[k], t->who[i]))
        {
            ++k;
        }
        d += k == i ? 1u : 0u;
    }
    return d;
}

static void test_every_index_once(void)
{
    static const size_t ns[] = {0u, 1u, 7u, N_MAX};
    static const unsigned jobs[] = {1u, 2u, 8u};
    static tally_t t;
    for (size_t a = 0; a < sizeof(jobs) / sizeof(jobs[0]); ++a)
    {
        aenl_set_jobs(jobs[a]);
        for (size_t b = 0; b < sizeof(ns) / sizeof(ns[0]); ++b)
        {
            memset(&t, 0, sizeof(t));
            aenl_parallel_for(ns[b], tally, &t);
            for (size_t i = 0; i < N_MAX; ++i)
            {
                TEST_ASSERT_EQUAL_UINT(i < ns[b] ? 1u : 0u, t.count[i]);
            }
        }
    }
    /* one thread: all on the caller's, in order */
    aenl_set_jobs(1);
    memset(&t, 0, sizeof(t));
    aenl_parallel_for(50, tally, &t);
    TEST_ASSERT_EQUAL_size_t(1, distinct_threads(&t, 50));
    TEST_ASSERT_TRUE(pthread_equal(t.who[0], pthread_self()));
}

/* With four threads and tasks that take a while, the work is shared (a task of 2 ms leaves the
 * other threads ample time to start). */
static void test_work_is_shared(void)
{
    static tally_t t;
    memset(&t, 0, sizeof(t));
    t.nap = 2000;
    aenl_set_jobs(4);
    aenl_parallel_for(100, tally, &t);
    const size_t d = distinct_threads(&t, 100);
    TEST_ASSERT_TRUE(d >= 2u && d <= 4u);
}

typedef struct
{
    pthread_t outer[8];
    tally_t inner[8];
} nest_t;

static void nested(void *ctx, size_t i)
{
    nest_t *n = (nest_t *)ctx;
    n->outer[i] = pthread_self();
    n->inner[i].nap = 100;
    aenl_parallel_for(20, tally, &n->inner[i]);
}

static void test_nested_loop_stays_on_its_thread(void)
{
    static nest_t n;
    memset(&n, 0, sizeof(n));
    aenl_set_jobs(4);
    aenl_parallel_for(8, nested, &n);
    for (size_t i = 0; i < 8; ++i)
    {
        for (size_t k = 0; k < 20; ++k)
        {
            TEST_ASSERT_EQUAL_UINT(1, n.inner[i].count[k]);
            TEST_ASSERT_TRUE(pthread_equal(n.outer[i], n.inner[i].who[k]));
        }
    }
}

/* Tasks 2 and 5 of 10 fail, each with its own cause; task i records that it ran. */
typedef struct
{
    int ran[10];
} fails_t;

static aenl_status_t failing(void *ctx, size_t i, aenl_err_t *err)
{
    fails_t *f = (fails_t *)ctx;
    f->ran[i] = 1;
    if (i == 2u || i == 5u)
    {
        aenl_err_set(err, "task %zu failed", i);
        return i == 2u ? AENL_E_NUMERIC : AENL_E_DIM;
    }
    return AENL_OK;
}

static aenl_status_t fine(void *ctx, size_t i, aenl_err_t *err)
{
    (void)err;
    ((fails_t *)ctx)->ran[i] = 1;
    return AENL_OK;
}

/* The first failure in index order is the outcome, with its cause, on any thread count; every
 * task before it ran. */
static void test_try_reports_first_failure(void)
{
    static const unsigned jobs[] = {1u, 4u};
    for (size_t a = 0; a < 2u; ++a)
    {
        aenl_set_jobs(jobs[a]);
        fails_t f;
        memset(&f, 0, sizeof(f));
        aenl_err_t err;
        aenl_err_clear(&err);
        TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_parallel_try(10, failing, &f, &err));
        TEST_ASSERT_EQUAL_STRING("task 2 failed", err.msg);
        TEST_ASSERT_EQUAL_INT(1, f.ran[0]);
        TEST_ASSERT_EQUAL_INT(1, f.ran[1]);
        TEST_ASSERT_EQUAL_INT(1, f.ran[2]);
        memset(&f, 0, sizeof(f));
        aenl_err_clear(&err);
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_parallel_try(10, fine, &f, &err));
        TEST_ASSERT_EQUAL_STRING("", err.msg);
        for (size_t i = 0; i < 10u; ++i)
        {
            TEST_ASSERT_EQUAL_INT(1, f.ran[i]);
        }
    }
}

static void test_jobs_setting(void)
{
    const long online = sysconf(_SC_NPROCESSORS_ONLN);
    aenl_set_jobs(0);
    TEST_ASSERT_EQUAL_UINT(online < 1 ? 1u : (online > 64 ? 64u : (unsigned)online), aenl_jobs());
    aenl_set_jobs(3);
    TEST_ASSERT_EQUAL_UINT(3, aenl_jobs());
    aenl_set_jobs(1000);
    TEST_ASSERT_EQUAL_UINT(AENL_MAX_JOBS, aenl_jobs());
}

/* A short diagnosis of a hidden freeplay with every stage that runs simulations at once (grid,
 * refinement, restarts, floors, the summary fit) on jobs threads. */
static void diagnose_with(unsigned jobs, aenl_diagnose_result_t *r)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_diagnose_case_t c;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_make(0, 101u, 0, &c, &err));
    c.truth_run.duration = 2000.0 * c.truth_run.dt;
    aenl_table_t t;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_case_measure(&c, &t, &err), err.msg);
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    o.n_replicates = 2;
    o.n_refine = 2;
    o.max_evals = 8;
    o.summary_records = 32;
    aenl_set_jobs(jobs);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &c.base, &c.base_run, &o, r, &err),
                                  err.msg);
    aenl_table_free(&t);
}

static void test_diagnosis_same_on_any_thread_count(void)
{
    aenl_diagnose_result_t a, b;
    diagnose_with(1, &a);
    diagnose_with(3, &b);
    TEST_ASSERT_EQUAL_INT(a.effect, b.effect);
    TEST_ASSERT_EQUAL_UINT(a.n_sims, b.n_sims);
    TEST_ASSERT_EQUAL_size_t(a.n_cand, b.n_cand);
    TEST_ASSERT_EQUAL_MEMORY(a.gap_before, b.gap_before, sizeof(a.gap_before));
    TEST_ASSERT_EQUAL_MEMORY(a.gap_after, b.gap_after, sizeof(a.gap_after));
    for (size_t i = 0; i < a.n_cand; ++i)
    {
        TEST_ASSERT_EQUAL_INT(a.cand[i].effect, b.cand[i].effect);
        TEST_ASSERT_EQUAL_INT(a.cand[i].dof, b.cand[i].dof);
        TEST_ASSERT_EQUAL_MEMORY(&a.cand[i].gap, &b.cand[i].gap, sizeof(double));
        TEST_ASSERT_EQUAL_MEMORY(&a.cand[i].floor, &b.cand[i].floor, sizeof(double));
        TEST_ASSERT_EQUAL_UINT(a.cand[i].n_evals, b.cand[i].n_evals);
    }
    TEST_ASSERT_EQUAL_MEMORY(a.updated.law, b.updated.law, sizeof(a.updated.law));
    TEST_ASSERT_EQUAL_size_t(a.n_param_sd, b.n_param_sd);
    TEST_ASSERT_EQUAL_MEMORY(a.param_sd, b.param_sd, sizeof(a.param_sd));
    TEST_ASSERT_EQUAL_MEMORY(&a.chi2, &b.chi2, sizeof(double));
    aenl_diagnose_result_free(&a);
    aenl_diagnose_result_free(&b);
}

/* The record-alone test of a 2-DOF airfoil under gusts with a hardening pitch spring, its two
 * channels and two linear controls run at once, on jobs threads. */
static void nltest_with(unsigned jobs, aenl_nlt_result_t *r)
{
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    aenl_sim_run_default(&run, AENL_SIM_AIRFOIL2DOF);
    aenl_sim_set_velocity(&m, 4.0);
    m.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_POLYNOMIAL;
    m.law[AENL_SIM_DOF_PITCH].n_coeffs = 3;
    m.law[AENL_SIM_DOF_PITCH].coeffs[0] = 1.0;
    m.law[AENL_SIM_DOF_PITCH].coeffs[2] = 400.0;
    run.dt = 0.5;
    run.duration = 2999.0 * run.dt;
    run.turbulence = 1;
    run.turb_intensity = 0.05;
    run.turb_length = 4.0;
    run.turb_seed = 5;
    run.snr = 10.0;
    run.noise_seed = 6;
    aenl_sim_result_t sr;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &run, &sr, &err), err.msg);
    const double *cols[2] = {sr.y, sr.y + sr.n_samples};
    aenl_nlt_opts_t o;
    aenl_nlt_opts_default(&o);
    o.n_controls = 2;
    aenl_set_jobs(jobs);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_nlt_run_columns(cols, sr.n_samples, 2, &o, r, &err),
                                  err.msg);
    aenl_sim_result_free(&sr);
}

static void test_nltest_same_on_any_thread_count(void)
{
    static aenl_nlt_result_t a, b;
    nltest_with(1, &a);
    nltest_with(3, &b);
    printf("nltest: p %g %g, impulses %zu\n", a.ch[0].p, a.ch[1].p, a.n_impulses);
    TEST_ASSERT_TRUE(a.ch[0].nonlinear);
    TEST_ASSERT_EQUAL_size_t(2, a.n_controls);
    TEST_ASSERT_EQUAL_MEMORY(&a, &b, sizeof(a));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_index_once);
    RUN_TEST(test_work_is_shared);
    RUN_TEST(test_nested_loop_stays_on_its_thread);
    RUN_TEST(test_try_reports_first_failure);
    RUN_TEST(test_jobs_setting);
    RUN_TEST(test_diagnosis_same_on_any_thread_count);
    RUN_TEST(test_nltest_same_on_any_thread_count);
    return UNITY_END();
}
