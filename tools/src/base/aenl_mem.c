/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_mem.c
 * @brief See aenl_mem.h.
 */
#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE /* madvise, MADV_HUGEPAGE */

#include <stdlib.h>
#include <sys/mman.h>

#include "aenl_tools/aenl_mem.h"

#define HUGE_PAGE ((size_t)1 << 21u)

void *aenl_alloc_large(size_t bytes)
{
#ifdef MADV_HUGEPAGE
    void *p = NULL;
    if (bytes >= HUGE_PAGE && posix_memalign(&p, HUGE_PAGE, bytes) == 0)
    {
        (void)madvise(p, bytes, MADV_HUGEPAGE); /* a request: refused, the pages stay small */
        return p;
    }
#endif
    return malloc(bytes > 0 ? bytes : 1u);
}
