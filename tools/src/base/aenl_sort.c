/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sort.c
 * @brief See aenl_sort.h.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

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

#define QF_SAMPLE 8192u /* values of x that place the brackets */
#define QF_MAX_Q  4u

/* The quantiles p[k] of the n_fin finite values of x with need[k] set, selected on one copy of
 * them. */
static int quantiles_on_copy(const double *x, size_t n, size_t n_fin, const double *p, size_t np,
                             const int *need, double *q)
{
    double *v = (double *)malloc(n_fin * sizeof(double));
    if (v == NULL)
    {
        return -1;
    }
    for (size_t i = 0, j = 0; i < n && j < n_fin; ++i)
    {
        if (isfinite(x[i]))
        {
            v[j++] = x[i];
        }
    }
    for (size_t k = 0; k < np; ++k)
    {
        q[k] = need[k] ? aenl_quantile_select(v, n_fin, p[k]) : q[k];
    }
    free(v);
    return 0;
}

/* One quantile's bracket: the order statistics rank and rank + 1 of the finite values are sought
 * among the values in [a, b]; below counts those under a. */
typedef struct
{
    size_t rank;
    double f; /* the interpolation's weight of rank + 1 */
    double a, b;
    size_t below, n_in, cap;
    double *in;
    int full; /* 1: more values fell inside than cap: the bracket is given up */
} qf_bracket_t;

/* The bracket of quantile p from the sorted sample s[0..m-1]: the sample ranks around the one
 * that stands for rank, widened by four standard deviations of a sample count and a few ranks,
 * and room for the values the bracket is expected to hold, twice over. */
static void qf_place(qf_bracket_t *k, const double *s, size_t m, size_t n_fin, double p)
{
    const double pos = p * (double)(n_fin - 1u);
    k->rank = (size_t)pos;
    k->f = pos - (double)k->rank;
    const double share = (double)k->rank / (double)n_fin;
    const double sd = sqrt((double)m * fmax(share * (1.0 - share), 1.0 / (double)m));
    const double j = share * (double)m;
    const double lo = j - 4.0 * sd - 4.0;
    const double hi = j + 4.0 * sd + 5.0;
    k->a = lo < 0.0 ? -HUGE_VAL : s[(size_t)lo];
    k->b = hi >= (double)(m - 1u) ? HUGE_VAL : s[(size_t)hi];
    k->cap = (size_t)(2.0 * (hi - lo + 1.0) * (double)n_fin / (double)m) + 64u;
}

int aenl_quantiles_finite(const double *x, size_t n, size_t n_fin, const double *p, size_t np,
                          double *q)
{
    if (np > QF_MAX_Q || n_fin == 0)
    {
        return -1;
    }
    int need[QF_MAX_Q] = {1, 1, 1, 1}; /* the quantiles left to the copy */
    if (n_fin < (size_t)8u * QF_SAMPLE)
    {
        return quantiles_on_copy(x, n, n_fin, p, np, need, q);
    }
    /* the sample: finite values at an even stride */
    double *s = (double *)malloc(QF_SAMPLE * sizeof(double));
    if (s == NULL)
    {
        return -1;
    }
    size_t m = 0;
    const size_t stride = n / QF_SAMPLE;
    for (size_t i = 0; i < QF_SAMPLE; ++i)
    {
        const double v = x[i * stride];
        if (isfinite(v))
        {
            s[m++] = v;
        }
    }
    aenl_sort_doubles(s, m);
    qf_bracket_t br[QF_MAX_Q];
    memset(br, 0, sizeof(br));
    int ok = m >= QF_SAMPLE / 2u;
    for (size_t k = 0; k < np && ok; ++k)
    {
        qf_place(&br[k], s, m, n_fin, p[k]);
        br[k].in = (double *)malloc(br[k].cap * sizeof(double));
        ok = br[k].in != NULL;
    }
    free(s);
    /* one pass: each bracket counts the values below it and keeps those inside it */
    for (size_t i = 0; i < n && ok; ++i)
    {
        const double v = x[i];
        if (!isfinite(v))
        {
            continue;
        }
        for (size_t k = 0; k < np; ++k)
        {
            qf_bracket_t *b = &br[k];
            if (v < b->a)
            {
                ++b->below;
            }
            else if (v <= b->b && !b->full)
            {
                if (b->n_in == b->cap)
                {
                    b->full = 1;
                }
                else
                {
                    b->in[b->n_in++] = v;
                }
            }
        }
    }
    int missed = 0;
    for (size_t k = 0; k < np; ++k)
    {
        qf_bracket_t *b = &br[k];
        const size_t r = b->rank - (b->rank >= b->below ? b->below : 0u);
        const size_t last = b->rank + 1u < n_fin ? b->rank + 1u : b->rank;
        /* both order statistics inside the bracket, or the quantile on the copy below */
        need[k] = !ok || b->full || b->rank < b->below || last >= b->below + b->n_in;
        missed |= need[k];
        if (need[k])
        {
            continue;
        }
        aenl_select_doubles(b->in, b->n_in, r);
        if (b->rank + 1u >= n_fin)
        {
            q[k] = b->in[r];
            continue;
        }
        double next = b->in[r + 1u];
        for (size_t j = r + 2u; j < b->n_in; ++j)
        {
            next = b->in[j] < next ? b->in[j] : next;
        }
        q[k] = b->in[r] + b->f * (next - b->in[r]);
    }
    for (size_t k = 0; k < np; ++k)
    {
        free(br[k].in);
    }
    return missed ? quantiles_on_copy(x, n, n_fin, p, np, need, q) : 0;
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
