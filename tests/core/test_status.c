/* SPDX-License-Identifier: MIT */
/**
 * @file test_status.c
 * @brief Status names and the scalar-type wrappers. Builds as f32 and f64.
 */
#include <string.h>

#include "aenl_test.h"

void setUp(void)
{
}

void tearDown(void)
{
}

static void test_status_names_are_distinct(void)
{
    const aenl_status_t all[] = {AENL_OK,       AENL_E_ARG,     AENL_E_DIM, AENL_E_EMPTY,
                                 AENL_E_NOT_PD, AENL_E_NUMERIC, AENL_E_IO};
    const size_t n = sizeof(all) / sizeof(all[0]);
    for (size_t i = 0; i < n; ++i)
    {
        const char *s = aenl_status_str(all[i]);
        TEST_ASSERT_NOT_NULL(s);
        TEST_ASSERT_EQUAL_INT(0, strncmp(s, "AENL_", 5));
        for (size_t j = 0; j < i; ++j)
        {
            TEST_ASSERT_NOT_EQUAL(0, strcmp(s, aenl_status_str(all[j])));
        }
    }
    TEST_ASSERT_EQUAL_STRING("AENL_OK", aenl_status_str(AENL_OK));
    TEST_ASSERT_EQUAL_STRING("AENL_E_NOT_PD", aenl_status_str(AENL_E_NOT_PD));
    TEST_ASSERT_EQUAL_STRING("AENL_E_UNKNOWN", aenl_status_str((aenl_status_t)-99));
}

static void test_status_errors_are_negative(void)
{
    TEST_ASSERT_EQUAL_INT(0, AENL_OK);
    TEST_ASSERT_LESS_THAN_INT(0, AENL_E_ARG);
    TEST_ASSERT_LESS_THAN_INT(0, AENL_E_NUMERIC);
    TEST_ASSERT_LESS_THAN_INT(0, AENL_E_IO);
}

static void test_status_real_wrappers(void)
{
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-6), AENL_R(1.5), aenl_sqrt(AENL_R(2.25)));
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-6), AENL_R(2.718281828), aenl_exp(AENL_R(1.0)));
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-6), AENL_R(0.0), aenl_log(AENL_R(1.0)));
    TEST_ASSERT_REAL_WITHIN(AENL_R(0.0), AENL_R(3.0), aenl_fabs(AENL_R(-3.0)));
    TEST_ASSERT_REAL_WITHIN(AENL_R(0.0), AENL_R(-2.0), aenl_floor(AENL_R(-1.5)));
    TEST_ASSERT_REAL_WITHIN(AENL_R(0.0), AENL_R(-1.0), aenl_ceil(AENL_R(-1.5)));
    TEST_ASSERT_EQUAL_INT(1, aenl_is_finite(AENL_R(1.0)));
    TEST_ASSERT_EQUAL_INT(0, aenl_is_finite((aenl_real_t)NAN));
    TEST_ASSERT_EQUAL_INT(0, aenl_is_finite((aenl_real_t)INFINITY));
    TEST_ASSERT_EQUAL_size_t(AENL_USE_DOUBLE ? sizeof(double) : sizeof(float), sizeof(aenl_real_t));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_status_names_are_distinct);
    RUN_TEST(test_status_errors_are_negative);
    RUN_TEST(test_status_real_wrappers);
    return UNITY_END();
}
