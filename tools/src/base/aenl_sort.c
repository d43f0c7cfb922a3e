/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sort.c
 * @brief See aenl_sort.h.
 */
#include "aenl_tools/aenl_sort.h"

int aenl_cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a;
    const double y = *(const double *)b;
    return (x > y) - (x < y);
}

double aenl_quantile_sorted(const double *s, size_t n, double p)
{
    const double pos = p * (double)(n - 1u);
    const size_t i = (size_t)pos;
    if (i + 1u >= n)
    {
        return s[n - 1u];
    }
    const double f = pos - (double)i;
    return s[i] + f * (s[i + 1u] - s[i]);
}
