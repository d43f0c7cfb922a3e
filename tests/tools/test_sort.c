/* SPDX-License-Identifier: MIT */
/**
 * @file test_sort.c
 * @brief aenl_sort_doubles against the C library's qsort (the reference) on random, repeated,
 *        ordered, reversed, constant and organ-pipe inputs of lengths around the short-run
 *        threshold and up to a record's length; aenl_select_doubles and aenl_quantile_select
 *        against the sorted order on the same inputs; aenl_median_mad on a known set.
 */
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
    RUN_TEST(test_median_mad);
    return UNITY_END();
}
