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

/* Short runs: insertion sort. */
static void insertion(double *v, size_t n)
{
    for (size_t i = 1; i < n; ++i)
    {
        const double x = v[i];
        size_t j = i;
        while (j > 0u && v[j - 1u] > x)
        {
            v[j] = v[j - 1u];
            --j;
        }
        v[j] = x;
    }
}

static void sift_down(double *v, size_t root, size_t n)
{
    for (;;)
    {
        size_t child = 2u * root + 1u;
        if (child >= n)
        {
            return;
        }
        if (child + 1u < n && v[child + 1u] > v[child])
        {
            ++child;
        }
        if (!(v[child] > v[root]))
        {
            return;
        }
        const double t = v[root];
        v[root] = v[child];
        v[child] = t;
        root = child;
    }
}

/* The fallback that bounds the worst case. */
static void heapsort_doubles(double *v, size_t n)
{
    for (size_t i = n / 2u; i-- > 0u;)
    {
        sift_down(v, i, n);
    }
    for (size_t end = n; end-- > 1u;)
    {
        const double t = v[0];
        v[0] = v[end];
        v[end] = t;
        sift_down(v, 0, end);
    }
}

#define SORT_SHORT 16u

static void introsort(double *v, size_t n, unsigned depth)
{
    while (n > SORT_SHORT)
    {
        if (depth == 0u)
        {
            heapsort_doubles(v, n);
            return;
        }
        --depth;
        /* median of three to v[0], then Hoare partition around it */
        const size_t mid = n / 2u;
        double a = v[0], b = v[mid], c = v[n - 1u];
        const double pivot = a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));
        size_t i = 0, j = n - 1u;
        for (;;)
        {
            while (v[i] < pivot)
            {
                ++i;
            }
            while (v[j] > pivot)
            {
                --j;
            }
            if (i >= j)
            {
                break;
            }
            const double t = v[i];
            v[i] = v[j];
            v[j] = t;
            ++i;
            --j;
        }
        /* v[0..j] <= pivot <= v[j+1..n-1]; recurse on the smaller side, loop on the larger */
        const size_t left = j + 1u;
        if (left < n - left)
        {
            introsort(v, left, depth);
            v += left;
            n -= left;
        }
        else
        {
            introsort(v + left, n - left, depth);
            n = left;
        }
    }
    insertion(v, n);
}

void aenl_sort_doubles(double *v, size_t n)
{
    unsigned depth = 0;
    for (size_t k = n; k > 1u; k >>= 1u)
    {
        depth += 2u;
    }
    if (n > 1u)
    {
        introsort(v, n, depth);
    }
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
    aenl_sort_doubles(v, n);
    const double med = aenl_quantile_sorted(v, n, 0.5);
    for (size_t k = 0; k < n; ++k)
    {
        v[k] = fabs(v[k] - med);
    }
    aenl_sort_doubles(v, n);
    *median = med;
    *sd = 1.482602218505602 * aenl_quantile_sorted(v, n, 0.5); /* 1 / Phi^-1(3/4) */
}
