/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sort.c
 * @brief See aenl_sort.h.
 */
#include <math.h>
#include <stdlib.h>

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

void aenl_median_mad(double *v, size_t n, double *median, double *sd)
{
    qsort(v, n, sizeof(double), aenl_cmp_double);
    const double med = aenl_quantile_sorted(v, n, 0.5);
    for (size_t k = 0; k < n; ++k)
    {
        v[k] = fabs(v[k] - med);
    }
    qsort(v, n, sizeof(double), aenl_cmp_double);
    *median = med;
    *sd = 1.482602218505602 * aenl_quantile_sorted(v, n, 0.5); /* 1 / Phi^-1(3/4) */
}
