/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_mem.h
 * @brief Host helper: memory for a large array (a whole record, a copy of a channel).
 */
#ifndef AENL_TOOLS_MEM_H
#define AENL_TOOLS_MEM_H

#include <stddef.h>

/**
 * @brief bytes of memory, released with free() and resizable with realloc() like malloc's. From
 *        2 MiB up, aligned to 2 MiB and marked for huge pages where the system gives them on
 *        request (Linux's madvise mode): the first touch of a large array is otherwise a page
 *        fault every 4 KiB, most of the system time of reading a 10^6-row record. realloc
 *        keeps the contents, not the alignment.
 *        NULL when memory lacks.
 */
void *aenl_alloc_large(size_t bytes);

#endif /* AENL_TOOLS_MEM_H */
