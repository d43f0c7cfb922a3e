/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_test.h
 * @brief Precision-neutral helpers for core tests: one test source builds as f32 and f64.
 */
#ifndef AENL_TEST_H
#define AENL_TEST_H

#include "unity.h"

#include "aenl/aenl_types.h"

#if AENL_USE_DOUBLE
#define TEST_ASSERT_REAL_WITHIN(delta, expected, actual)                                           \
    TEST_ASSERT_DOUBLE_WITHIN((double)(delta), (double)(expected), (double)(actual))
#define TEST_ASSERT_REAL_WITHIN_MESSAGE(delta, expected, actual, msg)                              \
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE((double)(delta), (double)(expected), (double)(actual), msg)
/** Relative tolerance for a result that should equal a double reference to rounding. */
#define AENL_TEST_REL_TOL 1e-12
#else
#define TEST_ASSERT_REAL_WITHIN(delta, expected, actual)                                           \
    TEST_ASSERT_FLOAT_WITHIN((float)(delta), (float)(expected), (float)(actual))
#define TEST_ASSERT_REAL_WITHIN_MESSAGE(delta, expected, actual, msg)                              \
    TEST_ASSERT_FLOAT_WITHIN_MESSAGE((float)(delta), (float)(expected), (float)(actual), msg)
#define AENL_TEST_REL_TOL 1e-4
#endif

/* ---- deterministic test signals ------------------------------------------------------------ */

/** State of the tests' portable generator (a 64-bit LCG); set it to seed a sequence. */
static uint64_t g_lcg;

/** Uniform in [0, 1) from the top 53 bits of the LCG. */
static inline double lcg_uniform(void)
{
    g_lcg = g_lcg * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(g_lcg >> 11) * (1.0 / 9007199254740992.0);
}

/** Sum of 12 uniforms minus 6: unit variance, approximately normal, libm-free. */
static inline double lcg_normal(void)
{
    double s = 0.0;
    for (int i = 0; i < 12; ++i)
    {
        s += lcg_uniform();
    }
    return s - 6.0;
}

#endif /* AENL_TEST_H */
