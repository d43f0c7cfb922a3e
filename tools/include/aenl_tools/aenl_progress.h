/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_progress.h
 * @brief Host-only: how a long host function reports how far it has got. The caller decides
 *        what to show (the command line draws a bar on a terminal and nothing otherwise); the
 *        library only counts.
 */
#ifndef AENL_TOOLS_PROGRESS_H
#define AENL_TOOLS_PROGRESS_H

#include <stddef.h>

/** A progress receiver: fn(ctx, done, total) after each of total steps (fn NULL: none). */
typedef struct aenl_progress
{
    void (*fn)(void *ctx, size_t done, size_t total);
    void *ctx;
} aenl_progress_t;

/** Report done of total steps to p (p or its fn may be NULL). */
static inline void aenl_progress_report(const aenl_progress_t *p, size_t done, size_t total)
{
    if (p != NULL && p->fn != NULL)
    {
        p->fn(p->ctx, done, total);
    }
}

#endif /* AENL_TOOLS_PROGRESS_H */
