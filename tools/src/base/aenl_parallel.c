/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_parallel.c
 * @brief See aenl_parallel.h. POSIX threads: a shared counter hands out the indices.
 */
#define _POSIX_C_SOURCE 200809L

#include "aenl_tools/aenl_parallel.h"

#include <pthread.h>
#include <stdlib.h>
#include <unistd.h>

static unsigned g_jobs; /* 0: the processors online */

/* Marks the threads that run tasks, so that a loop inside a task stays on its thread instead of
 * starting threads of its own (the outer loop already keeps every processor busy). */
static pthread_key_t g_in_task;
static pthread_once_t g_once = PTHREAD_ONCE_INIT;
static int g_key_ok;

static void make_key(void)
{
    g_key_ok = pthread_key_create(&g_in_task, NULL) == 0;
}

void aenl_set_jobs(unsigned n)
{
    g_jobs = n > AENL_MAX_JOBS ? AENL_MAX_JOBS : n;
}

unsigned aenl_jobs(void)
{
    if (g_jobs > 0u)
    {
        return g_jobs;
    }
    const long c = sysconf(_SC_NPROCESSORS_ONLN);
    return c < 1 ? 1u : (c > (long)AENL_MAX_JOBS ? AENL_MAX_JOBS : (unsigned)c);
}

typedef struct
{
    pthread_mutex_t mu;
    size_t next, n;
    aenl_task_fn fn;
    void *ctx;
} pool_t;

static void *worker(void *arg)
{
    pool_t *p = (pool_t *)arg;
    static const int mark = 1;
    if (g_key_ok)
    {
        (void)pthread_setspecific(g_in_task, &mark);
    }
    for (;;)
    {
        (void)pthread_mutex_lock(&p->mu);
        const size_t i = p->next;
        p->next += i < p->n ? 1u : 0u;
        (void)pthread_mutex_unlock(&p->mu);
        if (i >= p->n)
        {
            break;
        }
        p->fn(p->ctx, i);
    }
    if (g_key_ok)
    {
        (void)pthread_setspecific(g_in_task, NULL);
    }
    return NULL;
}

void aenl_parallel_for(size_t n, aenl_task_fn fn, void *ctx)
{
    (void)pthread_once(&g_once, make_key);
    unsigned jobs = aenl_jobs();
    jobs = (size_t)jobs > n ? (unsigned)n : jobs;
    const int nested = g_key_ok && pthread_getspecific(g_in_task) != NULL;
    pool_t p;
    if (jobs <= 1u || nested || pthread_mutex_init(&p.mu, NULL) != 0)
    {
        for (size_t i = 0; i < n; ++i)
        {
            fn(ctx, i);
        }
        return;
    }
    p.next = 0;
    p.n = n;
    p.fn = fn;
    p.ctx = ctx;
    pthread_t th[AENL_MAX_JOBS];
    unsigned started = 0;
    for (unsigned k = 1; k < jobs; ++k)
    {
        started += pthread_create(&th[started], NULL, worker, &p) == 0 ? 1u : 0u;
    }
    (void)worker(&p);
    for (unsigned k = 0; k < started; ++k)
    {
        (void)pthread_join(th[k], NULL);
    }
    (void)pthread_mutex_destroy(&p.mu);
}

typedef struct
{
    aenl_task_try_fn fn;
    void *ctx;
    aenl_status_t *st;
    aenl_err_t *err;
    pthread_mutex_t mu;
    size_t first_fail; /* the least index that failed so far (n: none) */
} try_t;

/* A task after one that failed is skipped: its result would not be read. The least failing
 * index always runs (only an earlier failure could skip it), so the outcome does not depend on
 * the threads. */
static void try_task(void *ctx, size_t i)
{
    try_t *t = (try_t *)ctx;
    (void)pthread_mutex_lock(&t->mu);
    const int skip = i > t->first_fail;
    (void)pthread_mutex_unlock(&t->mu);
    aenl_err_clear(&t->err[i]);
    t->st[i] = AENL_OK;
    if (skip)
    {
        return;
    }
    t->st[i] = t->fn(t->ctx, i, &t->err[i]);
    if (t->st[i] != AENL_OK)
    {
        (void)pthread_mutex_lock(&t->mu);
        t->first_fail = i < t->first_fail ? i : t->first_fail;
        (void)pthread_mutex_unlock(&t->mu);
    }
}

aenl_status_t aenl_parallel_try(size_t n, aenl_task_try_fn fn, void *ctx, aenl_err_t *err)
{
    const size_t n1 = n > 0u ? n : 1u;
    try_t t;
    t.fn = fn;
    t.ctx = ctx;
    t.st = (aenl_status_t *)calloc(n1, sizeof(aenl_status_t));
    t.err = (aenl_err_t *)calloc(n1, sizeof(aenl_err_t));
    t.first_fail = n;
    aenl_status_t out = AENL_OK;
    if (t.st == NULL || t.err == NULL || pthread_mutex_init(&t.mu, NULL) != 0)
    {
        free(t.st);
        free(t.err);
        aenl_err_set(err, "out of memory (tasks)");
        return AENL_E_DIM;
    }
    aenl_parallel_for(n, try_task, &t);
    for (size_t i = 0; i < n && out == AENL_OK; ++i)
    {
        if (t.st[i] != AENL_OK)
        {
            aenl_err_set(err, "%s", t.err[i].msg);
            out = t.st[i];
        }
    }
    (void)pthread_mutex_destroy(&t.mu);
    free(t.st);
    free(t.err);
    return out;
}
