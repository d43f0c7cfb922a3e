/*
 * selftest_fail.c - checks the clean-room Unity harness on failures.
 *
 * Five tests: three fail, one is ignored, one passes, so the program must
 * print "5 Tests 3 Failures 1 Ignored", then "FAIL", and exit with 3.
 * It also checks that a failing assertion or TEST_IGNORE skips the rest of
 * the test, that tearDown still runs, and that a second failure inside
 * tearDown is not reported again.  Exit status 100 means one of these
 * harness checks went wrong.
 */
#include "unity.h"

#include <stdio.h>

static int set_up_calls;
static int tear_down_calls;
static int reached_after_abort;
static int fail_in_tear_down;
static int tear_down_fail_attempts;
static int reached_after_tear_down_fail;

void setUp(void)
{
    set_up_calls++;
}

void tearDown(void)
{
    tear_down_calls++;
    if (fail_in_tear_down)
    {
        fail_in_tear_down = 0;
        tear_down_fail_attempts++;
        TEST_FAIL_MESSAGE("second failure in tearDown: must not be printed");
        reached_after_tear_down_fail = 1; /* must not run */
    }
}

/* Failure 1: integer mismatch with a user message. */
static void test_int_failure_stops_test(void)
{
    int actual = 2;
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, actual, "one is not two");
    reached_after_abort = 1; /* must not run */
}

/* Failure 2: with UNITY_INCLUDE_DOUBLE a real mismatch (1e-9 relative is
 * above the 1e-12 precision); without it any double assertion fails with
 * "Unity Double Precision Disabled". */
static void test_double_failure(void)
{
#ifdef UNITY_INCLUDE_DOUBLE
    TEST_ASSERT_EQUAL_DOUBLE(1.0, 1.0 + 1e-9);
#else
    TEST_ASSERT_EQUAL_DOUBLE(1.0, 1.0);
#endif
    reached_after_abort = 1; /* must not run */
}

/* Failure 3: float outside delta; tearDown then fails too, which must be
 * neither printed nor counted a second time. */
static void test_float_failure_then_tear_down_failure(void)
{
    fail_in_tear_down = 1;
    TEST_ASSERT_FLOAT_WITHIN(0.1f, 1.0f, 1.5f);
    reached_after_abort = 1; /* must not run */
}

static void test_ignored(void)
{
    TEST_IGNORE_MESSAGE("not ready yet");
    reached_after_abort = 1; /* must not run */
}

static void test_passes(void)
{
    TEST_ASSERT_TRUE(1);
}

int main(void)
{
    int failures;

    UNITY_BEGIN();
    RUN_TEST(test_int_failure_stops_test);
    RUN_TEST(test_double_failure);
    RUN_TEST(test_float_failure_then_tear_down_failure);
    RUN_TEST(test_ignored);
    RUN_TEST(test_passes);
    failures = UNITY_END();

    if (set_up_calls != 5 || tear_down_calls != 5 || reached_after_abort != 0 ||
        tear_down_fail_attempts != 1 || reached_after_tear_down_fail != 0)
    {
        printf("HARNESS SELF-CHECK FAILED: setUp %d, tearDown %d, after abort %d, "
               "tearDown failures %d, after tearDown failure %d\n",
               set_up_calls, tear_down_calls, reached_after_abort, tear_down_fail_attempts,
               reached_after_tear_down_fail);
        return 100;
    }
    return failures;
}
