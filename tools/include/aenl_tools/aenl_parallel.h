/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_parallel.h
 * @brief Host helper: independent tasks on several threads. The simulations of a diagnosis (its
 *        search grid, its refinements, its noise floors, its summary fit) do not depend on each
 *        other; they run at once, and each writes only what belongs to it, so that the answer is
 *        the same whatever the number of threads.
 */
#ifndef AENL_TOOLS_PARALLEL_H
#define AENL_TOOLS_PARALLEL_H

#include <stddef.h>

#include "aenl/aenl_types.h"
#include "aenl_tools/aenl_io.h"

/** The largest number of threads a parallel loop runs on. */
#define AENL_MAX_JOBS 64u

/** A task: the work of index i, given the caller's context. */
typedef void (*aenl_task_fn)(void *ctx, size_t i);

/**
 * @brief Sets the number of threads of the host library's parallel loops (1: everything on the
 *        calling thread; 0: the default, the processors online; at most AENL_MAX_JOBS). A
 *        process-wide setting, like a BLAS's thread count: set it before the work starts, not
 *        while a parallel loop runs.
 */
void aenl_set_jobs(unsigned n);

/** The number of threads a parallel loop uses now (>= 1). */
unsigned aenl_jobs(void);

/**
 * @brief Runs fn(ctx, i) for every i < n, each exactly once, on up to aenl_jobs() threads (the
 *        caller's among them), and returns when all are done. Tasks are taken in ascending
 *        order. fn must write only what belongs to its i (results are reduced by the caller
 *        afterwards, in index order), so that the outcome does not depend on the threads. A loop
 *        inside a task of a loop that runs on several threads stays on that task's thread; a
 *        thread that cannot be started leaves its share to the others.
 */
void aenl_parallel_for(size_t n, aenl_task_fn fn, void *ctx);

/** A task that can fail: the work of index i; its status, with the cause in err. */
typedef aenl_status_t (*aenl_task_try_fn)(void *ctx, size_t i, aenl_err_t *err);

/**
 * @brief As aenl_parallel_for, for tasks that can fail, each with its own error: the status is
 *        that of the first task in index order that failed (its cause into err), as a loop that
 *        stopped there would give; AENL_OK when none did. Every task before that one runs; a
 *        task after it may be skipped (its result is not to be read). AENL_E_DIM when the
 *        bookkeeping cannot be allocated (then no task runs).
 */
aenl_status_t aenl_parallel_try(size_t n, aenl_task_try_fn fn, void *ctx, aenl_err_t *err);

#endif /* AENL_TOOLS_PARALLEL_H */
