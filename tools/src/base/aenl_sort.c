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

/* One partition of v[0..n-1] (n > SORT_SHORT) around the median of v[0], v[n/2], v[n-1]
 * (Hoare): returns the length of the left part, v[0..left-1] <= pivot <= v[left..n-1], both
 * non-empty (the median of three leaves an element at or above the pivot in front of the
 * last place, and one at or below it behind the first). */
static size_t partition(double *v, size_t n)
{
    const double a = v[0], b = v[n / 2u], c = v[n - 1u];
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
            return j + 1u;
        }
        const double t = v[i];
        v[i] = v[j];
        v[j] = t;
        ++i;
        --j;
    }
}

/* Partitions allowed before the heapsort takes over: 2 log2(n), introsort's limit. */
static unsigned depth_limit(size_t n)
{
    unsigned depth = 0;
    for (size_t k = n; k > 1u; k >>= 1u)
    {
        depth += 2u;
    }
    return depth;
}

void aenl_sort_doubles(double *v, size_t n)
{
    /* Pending parts, the larger side of each partition: the smaller side is taken next, so
     * there are never more than log2(n) of them. */
    struct
    {
        double *v;
        size_t n;
        unsigned depth;
    } stack[8u * sizeof(size_t)];
    size_t top = 0;
    unsigned depth = depth_limit(n);
    for (;;)
    {
        while (n > SORT_SHORT && depth > 0u)
        {
            --depth;
            const size_t left = partition(v, n);
            if (left < n - left)
            {
                stack[top].v = v + left;
                stack[top].n = n - left;
                stack[top].depth = depth;
                n = left;
            }
            else
            {
                stack[top].v = v;
                stack[top].n = left;
                stack[top].depth = depth;
                v += left;
                n -= left;
            }
            ++top;
        }
        if (n > SORT_SHORT)
        {
            heapsort_doubles(v, n); /* the partitions degraded */
        }
        else
        {
            insertion(v, n);
        }
        if (top == 0u)
        {
            return;
        }
        --top;
        v = stack[top].v;
        n = stack[top].n;
        depth = stack[top].depth;
    }
}

void aenl_select_doubles(double *v, size_t n, size_t k)
{
    if (k >= n)
    {
        return;
    }
    /* the part holding place k is partitioned until it is short (then sorted), as a sort would
     * do with that part alone; degraded partitions end in a heapsort, so O(n log n) at worst */
    unsigned depth = depth_limit(n);
    while (n > SORT_SHORT && depth > 0u)
    {
        --depth;
        const size_t left = partition(v, n);
        if (k < left)
        {
            n = left;
        }
        else
        {
            v += left;
            k -= left;
            n -= left;
        }
    }
    if (n > SORT_SHORT)
    {
        heapsort_doubles(v, n);
    }
    else
    {
        insertion(v, n);
    }
}

double aenl_quantile_select(double *v, size_t n, double p)
{
    const double pos = p * (double)(n - 1u);
    const size_t i = (size_t)pos;
    if (i + 1u >= n)
    {
        aenl_select_doubles(v, n, n - 1u);
        return v[n - 1u];
    }
    aenl_select_doubles(v, n, i);
    double next = v[i + 1u]; /* the next order statistic: the smallest above place i */
    for (size_t j = i + 2u; j < n; ++j)
    {
        next = v[j] < next ? v[j] : next;
    }
    const double f = pos - (double)i;
    return v[i] + f * (next - v[i]);
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
    const double med = aenl_quantile_select(v, n, 0.5);
    for (size_t k = 0; k < n; ++k)
    {
        v[k] = fabs(v[k] - med);
    }
    *median = med;
    *sd = 1.482602218505602 * aenl_quantile_select(v, n, 0.5); /* 1 / Phi^-1(3/4) */
}
