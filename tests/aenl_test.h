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

#endif /* AENL_TEST_H */
