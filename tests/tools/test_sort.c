/* SPDX-License-Identifier: MIT */
/**
 * @file test_sort.c
 * @brief aenl_sort_doubles against the C library's qsort (the reference) on random, repeated,
 *        ordered, reversed, constant and organ-pipe inputs of lengths around the short-run
 *        threshold and up to a record's length; aenl_select_doubles and aenl_quantile_select
 *        against the sorted order on the same inputs; aenl_quantiles_finite against the sorted
 *        finite values; aenl_median_mad on a known set.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_tools/aenl_rng.h"
#include "aenl_tools/aenl_sort.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

enum
{
    P_UNIFORM,
    P_FEW_VALUES,
    P_ASCENDING,
    P_DESCENDING,
    P_CONSTANT,
    P_ORGAN_PIPE,
    P_GAUSS,
    P_COUNT
};

static void fill(double *v, size_t n, int pattern, aenl_rng_t *g)
{
    for (size_t i = 0; i < n; ++i)
    {
        switch (pattern)
        {
            case P_UNIFORM:
                v[i] = aenl_rng_uniform(g) - 0.5;
                break;
            case P_FEW_VALUES:
                v[i] = (double)(int)(10.0 * aenl_rng_uniform(g));
                break;
            case P_ASCENDING:
                v[i] = (double)i;
                break;
            case P_DESCENDING:
                v[i] = -(double)i;
                break;
            case P_CONSTANT:
                v[i] = 3.25;
                break;
            case P_ORGAN_PIPE:
                v[i] = (double)(i < n / 2u ? i : n - i);
                break;
            default:
                v[i] = aenl_rng_gauss(g);
                break;
        }
    }
}

/* Every pattern at lengths around the short-run threshold and up to a record's: a holds the
 * input, b the same sorted by qsort (the reference), and check looks at them. */
static void for_each_input(uint64_t seed, void (*check)(double *a, const double *b, size_t n))
{
    static const size_t ns[] = {0, 1, 2, 3, 15, 16, 17, 33, 100, 1000, 20000};
    aenl_rng_t g;
    aenl_rng_seed(&g, seed);
    double *a = malloc(20000u * sizeof(double));
    double *b = malloc(20000u * sizeof(double));
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    for (size_t k = 0; k < sizeof(ns) / sizeof(ns[0]); ++k)
    {
        for (int p = 0; p < P_COUNT; ++p)
        {
            fill(a, ns[k], p, &g);
            memcpy(b, a, ns[k] * sizeof(double));
            qsort(b, ns[k], sizeof(double), aenl_cmp_double);
            check(a, b, ns[k]);
        }
    }
    free(a);
    free(b);
}

static void check_sort(double *a, const double *b, size_t n)
{
    aenl_sort_doubles(a, n);
    TEST_ASSERT_TRUE_MESSAGE(n == 0u || memcmp(a, b, n * sizeof(double)) == 0,
                             "differs from qsort");
}

static void test_sort_matches_qsort(void)
{
    for_each_input(11u, check_sort);
}

/* Selection puts at place k what qsort puts there, nothing larger before it and nothing smaller
 * after it, and the quantile from it is the sorted quantile's, bit for bit. */
static void check_select(double *a, const double *b, size_t n)
{
    static const double ps[] = {0.0, 0.001, 0.25, 0.5, 0.7, 0.999, 1.0};
    if (n == 0u)
    {
        return;
    }
    const size_t ks[] = {0, n / 3u, n / 2u, n - 1u};
    for (size_t q = 0; q < 4; ++q)
    {
        const size_t k = ks[q];
        aenl_select_doubles(a, n, k);
        TEST_ASSERT_EQUAL_DOUBLE(b[k], a[k]);
        for (size_t j = 0; j < n; ++j)
        {
            TEST_ASSERT_TRUE_MESSAGE(j < k ? a[j] <= a[k] : a[j] >= a[k] || j == k,
                                     "not partitioned about place k");
        }
    }
    for (size_t q = 0; q < sizeof(ps) / sizeof(ps[0]); ++q)
    {
        const double want = aenl_quantile_sorted(b, n, ps[q]);
        const double got = aenl_quantile_select(a, n, ps[q]);
        uint64_t bw, bg; /* bit for bit */
        memcpy(&bw, &want, sizeof(bw));
        memcpy(&bg, &got, sizeof(bg));
        TEST_ASSERT_TRUE_MESSAGE(bw == bg, "quantile differs from the sorted one");
    }
}

static void test_select_matches_sorted(void)
{
    for_each_input(12u, check_select);
}

/* aenl_quantiles_finite against the sorted finite values (qsort, aenl_quantile_sorted), bit for
 * bit, on every pattern at lengths from 1 to 300 007, with missing (NaN) and infinite
 * values sprinkled in or not; and on a record whose values at the sample's stride are all one
 * value, so that the sample places every bracket wrong and the copy decides. x is not changed. */
static void check_quantiles(const double *x, size_t n)
{
    static const double ps[2][3] = {{0.0, 0.001, 0.3}, {0.5, 0.999, 1.0}};
    double *fin = malloc((n ? n : 1u) * sizeof(double));
    double *keep = malloc((n ? n : 1u) * sizeof(double));
    TEST_ASSERT_NOT_NULL(fin);
    TEST_ASSERT_NOT_NULL(keep);
    size_t n_fin = 0;
    for (size_t i = 0; i < n; ++i)
    {
        if (isfinite(x[i]))
        {
            fin[n_fin++] = x[i];
        }
    }
    memcpy(keep, x, n * sizeof(double));
    qsort(fin, n_fin, sizeof(double), aenl_cmp_double);
    for (size_t h = 0; h < 2 && n_fin > 0; ++h)
    {
        double got[3];
        TEST_ASSERT_EQUAL_INT(0, aenl_quantiles_finite(x, n, n_fin, ps[h], 3, got));
        for (size_t q = 0; q < 3; ++q)
        {
            const double want = aenl_quantile_sorted(fin, n_fin, ps[h][q]);
            TEST_ASSERT_EQUAL_MEMORY_MESSAGE(&want, &got[q], sizeof(double),
                                             "quantile differs from the sorted one");
        }
    }
    TEST_ASSERT_EQUAL_MEMORY(keep, x, n * sizeof(double));
    free(fin);
    free(keep);
}

static void test_quantiles_finite(void)
{
    static const size_t ns[] = {1, 5, 100, 65535, 65536, 200000, 300007};
    aenl_rng_t g;
    aenl_rng_seed(&g, 13u);
    double *x = malloc(300007u * sizeof(double));
    TEST_ASSERT_NOT_NULL(x);
    for (size_t k = 0; k < sizeof(ns) / sizeof(ns[0]); ++k)
    {
        const size_t n = ns[k];
        for (int p = 0; p < P_COUNT; ++p)
        {
            for (int holes = 0; holes <= 1; ++holes)
            {
                fill(x, n, p, &g);
                for (size_t i = 0; holes && i < n; ++i)
                {
                    const double u = aenl_rng_uniform(&g);
                    x[i] = u < 0.02 ? (double)NAN
                                    : (u < 0.025 ? (u < 0.0225 ? HUGE_VAL : -HUGE_VAL) : x[i]);
                }
                check_quantiles(x, n);
            }
        }
        /* every value at the sample's stride the same, or shifted up or down: the brackets
         * miss or hold one order statistic but not the next */
        const size_t stride = n / 8192u;
        for (int shift = -1; shift <= 2; ++shift)
        {
            for (size_t i = 0; i < n; ++i)
            {
                const double v = aenl_rng_gauss(&g);
                const int at = stride > 0 && i % stride == 0;
                x[i] = at ? (shift == 2 ? 0.0 : v + 3.0 * (double)shift) : v;
            }
            check_quantiles(x, n);
        }
    }
    free(x);
}

/* A bracket that ends at a quantile's first order statistic: the record's values at the
 * sample's stride are all 0 and its other values distinct, half below 0 and half above, so the
 * bracket [0, 0] holds the 0s; the quantile halfway between the last 0 and the next value needs
 * the next one, which lies outside, and is selected on a copy. */
static void test_quantiles_bracket_edge(void)
{
    const size_t n = 131072u;
    const size_t stride = n / 8192u;
    double *x = malloc(n * sizeof(double));
    TEST_ASSERT_NOT_NULL(x);
    size_t below = 0;
    size_t other = 0;
    for (size_t i = 0; i < n; ++i)
    {
        if (i % stride == 0)
        {
            x[i] = 0.0;
            continue;
        }
        const size_t mag = 1u + other / 2u; /* 1, 1, 2, 2, ...: -1, 1, -2, 2, ... */
        x[i] = (other % 2u == 0u ? -1.0 : 1.0) * (double)mag;
        below += x[i] < 0.0 ? 1u : 0u;
        ++other;
    }
    const size_t last_zero = below + n / stride - 1u;
    const double p[1] = {((double)last_zero + 0.5) / (double)(n - 1u)};
    double got = 0.0;
    TEST_ASSERT_EQUAL_INT(0, aenl_quantiles_finite(x, n, n, p, 1, &got));
    TEST_ASSERT_EQUAL_DOUBLE(0.5, got); /* halfway between the last 0 and the smallest 1 */
    check_quantiles(x, n);
    free(x);
}

/* 1, 2, 3, 4, 100: median 3, absolute deviations 2, 1, 0, 1, 97, their median 1. */
static void test_median_mad(void)
{
    double v[5] = {100.0, 3.0, 1.0, 4.0, 2.0};
    double med = 0.0, sd = 0.0;
    aenl_median_mad(v, 5, &med, &sd);
    TEST_ASSERT_EQUAL_DOUBLE(3.0, med);
    TEST_ASSERT_DOUBLE_WITHIN(1e-15, 1.482602218505602, sd);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_sort_matches_qsort);
    RUN_TEST(test_select_matches_sorted);
    RUN_TEST(test_quantiles_finite);
    RUN_TEST(test_quantiles_bracket_edge);
    RUN_TEST(test_median_mad);
    return UNITY_END();
}
