/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_clock.c
 * @brief See aenl_clock.h.
 */
#define _POSIX_C_SOURCE 200809L

#include <time.h>

#include "aenl_tools/aenl_clock.h"

double aenl_now_s(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
