/*
 * selftest.c - checks the clean-room Unity harness: every test here must
 * pass.  Build once with and once without -DUNITY_INCLUDE_DOUBLE; without
 * it the double test is reported as ignored.  Exit status: failures, or
 * 100 if the harness itself misbehaved (setUp/tearDown/TEST_PASS).
 */
#include "unity.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static int set_up_calls;
static int tear_down_calls;
static int after_pass_reached;

void setUp(void)
{
    set_up_calls++;
}

void tearDown(void)
{
    tear_down_calls++;
}

static void test_boolean_and_pointers(void)
{
    int x = 5;
    const int *p = &x;
    const int *null_p = NULL;

    TEST_ASSERT(x == 5);
    TEST_ASSERT_MESSAGE(x > 0, "x positive");
    TEST_ASSERT_TRUE(x);
    TEST_ASSERT_TRUE_MESSAGE(p != NULL, "pointer set");
    TEST_ASSERT_FALSE(x == 4);
    TEST_ASSERT_FALSE_MESSAGE(0, "zero is false");
    TEST_ASSERT_UNLESS(x < 0);
    TEST_ASSERT_UNLESS_MESSAGE(x < 0, "unless");
    TEST_ASSERT_NULL(null_p);
    TEST_ASSERT_NULL_MESSAGE(null_p, "null");
    TEST_ASSERT_NOT_NULL(p);
    TEST_ASSERT_NOT_NULL_MESSAGE(p, "not null");
    TEST_ASSERT_NOT_EQUAL(3, x);
    TEST_ASSERT_NOT_EQUAL_MESSAGE(3, x, "not equal");
    TEST_MESSAGE("informational line from test_boolean_and_pointers");
}

static void test_signed_integers(void)
{
    int i = -7;
    long l = 123456789L;
    int8_t i8 = -128;
    int16_t i16 = -32768;
    int32_t i32 = INT32_MIN;
    int64_t i64 = INT64_MIN;

    TEST_ASSERT_EQUAL(-7, i);
    TEST_ASSERT_EQUAL_MESSAGE(-7, i, "generic");
    TEST_ASSERT_EQUAL_INT(-7, i);
    TEST_ASSERT_EQUAL_INT(123456789, l);
    TEST_ASSERT_EQUAL_INT_MESSAGE(-7, i, "int");
    TEST_ASSERT_EQUAL_INT8(-128, i8);
    TEST_ASSERT_EQUAL_INT8(0x80, i8); /* truncated to 8 bits, as in Unity */
    TEST_ASSERT_EQUAL_INT8_MESSAGE(-128, i8, "int8");
    TEST_ASSERT_EQUAL_INT16(-32768, i16);
    TEST_ASSERT_EQUAL_INT16_MESSAGE(-32768, i16, "int16");
    TEST_ASSERT_EQUAL_INT32(INT32_MIN, i32);
    TEST_ASSERT_EQUAL_INT32_MESSAGE(INT32_MIN, i32, "int32");
    TEST_ASSERT_EQUAL_INT64(INT64_MIN, i64);
    TEST_ASSERT_EQUAL_INT64_MESSAGE(INT64_MIN, i64, "int64");

    TEST_ASSERT_NOT_EQUAL_INT(1, i);
    TEST_ASSERT_NOT_EQUAL_INT8_MESSAGE(1, i8, "ne8");
    TEST_ASSERT_NOT_EQUAL_INT32(0, i32);
    TEST_ASSERT_NOT_EQUAL_INT64(0, i64);

    /* (threshold, actual) */
    TEST_ASSERT_GREATER_THAN(-8, i);
    TEST_ASSERT_GREATER_THAN_MESSAGE(-8, i, "gt");
    TEST_ASSERT_GREATER_THAN_INT(-8, i);
    TEST_ASSERT_GREATER_THAN_INT32(INT32_MIN, 0);
    TEST_ASSERT_GREATER_THAN_INT64(INT64_MIN, i64 + 1);
    TEST_ASSERT_LESS_THAN(0, i);
    TEST_ASSERT_LESS_THAN_INT(-6, i);
    TEST_ASSERT_LESS_THAN_INT32_MESSAGE(0, i32, "lt32");
    TEST_ASSERT_GREATER_OR_EQUAL(-7, i);
    TEST_ASSERT_GREATER_OR_EQUAL_INT(-7, i);
    TEST_ASSERT_GREATER_OR_EQUAL_INT32(INT32_MIN, i32);
    TEST_ASSERT_LESS_OR_EQUAL(-7, i);
    TEST_ASSERT_LESS_OR_EQUAL_INT(-7, i);
    TEST_ASSERT_LESS_OR_EQUAL_INT32_MESSAGE(-1, i32, "le32");

    TEST_ASSERT_INT_WITHIN(2, -7, -5);
    TEST_ASSERT_INT_WITHIN_MESSAGE(0, -7, i, "within");
    TEST_ASSERT_INT_WITHIN(UINT64_MAX, INT64_MIN, INT64_MAX);
    TEST_ASSERT_INT8_WITHIN(1, 127, 126);
    TEST_ASSERT_INT16_WITHIN(10, -100, -91);
    TEST_ASSERT_INT32_WITHIN(5, 0, -5);
    TEST_ASSERT_INT64_WITHIN(1, INT64_MAX, INT64_MAX - 1);
}

static void test_unsigned_integers(void)
{
    unsigned int u = 4000000000u;
    uint8_t u8 = 255;
    uint16_t u16 = 65535;
    uint32_t u32 = UINT32_MAX;
    uint64_t u64 = UINT64_MAX;
    size_t sz = sizeof(uint64_t);

    TEST_ASSERT_EQUAL_UINT(4000000000u, u);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(4000000000u, u, "uint");
    TEST_ASSERT_EQUAL_UINT8(255, u8);
    TEST_ASSERT_EQUAL_UINT8(-1, u8); /* truncated to 8 bits */
    TEST_ASSERT_EQUAL_UINT16(65535, u16);
    TEST_ASSERT_EQUAL_UINT32(UINT32_MAX, u32);
    TEST_ASSERT_EQUAL_UINT64(UINT64_MAX, u64);
    TEST_ASSERT_EQUAL_UINT64_MESSAGE(UINT64_MAX, u64, "u64");
    TEST_ASSERT_EQUAL_HEX8(0xFF, u8);
    TEST_ASSERT_EQUAL_HEX8_MESSAGE(0xFF, u8, "hex8");
    TEST_ASSERT_EQUAL_HEX16(0xFFFF, u16);
    TEST_ASSERT_EQUAL_HEX32(0xFFFFFFFFu, u32);
    TEST_ASSERT_EQUAL_HEX(0xFFFFFFFFu, u32);
    TEST_ASSERT_EQUAL_HEX64(UINT64_MAX, u64);
    TEST_ASSERT_EQUAL_size_t(8, sz);
    TEST_ASSERT_EQUAL_size_t_MESSAGE(8u, sz, "size_t");

    TEST_ASSERT_NOT_EQUAL_UINT(0u, u);
    TEST_ASSERT_NOT_EQUAL_UINT32(0u, u32);
    TEST_ASSERT_NOT_EQUAL_HEX8(0x00, u8);
    TEST_ASSERT_NOT_EQUAL_size_t(0u, sz);
    TEST_ASSERT_NOT_EQUAL_size_t_MESSAGE(0u, sz, "ne size_t");

    TEST_ASSERT_GREATER_THAN_UINT(3999999999u, u);
    TEST_ASSERT_GREATER_THAN_UINT32(0u, u32);
    TEST_ASSERT_GREATER_THAN_UINT64(0u, u64);
    TEST_ASSERT_GREATER_THAN_size_t(7u, sz);
    TEST_ASSERT_LESS_THAN_UINT(4000000001u, u);
    TEST_ASSERT_LESS_THAN_UINT16(65535u, u8);
    TEST_ASSERT_LESS_THAN_UINT64(UINT64_MAX, 0u);
}

static void test_unsigned_order(void)
{
    uint32_t u32 = 10u;
    size_t sz = 16u;

    TEST_ASSERT_LESS_THAN_UINT32(11u, u32);
    TEST_ASSERT_LESS_THAN_size_t(17u, sz);
    TEST_ASSERT_LESS_THAN_size_t_MESSAGE(17u, sz, "lt size_t");
    TEST_ASSERT_GREATER_OR_EQUAL_UINT(10u, u32);
    TEST_ASSERT_GREATER_OR_EQUAL_UINT32(10u, u32);
    TEST_ASSERT_GREATER_OR_EQUAL_size_t(16u, sz);
    TEST_ASSERT_LESS_OR_EQUAL_UINT(10u, u32);
    TEST_ASSERT_LESS_OR_EQUAL_UINT32(10u, u32);
    TEST_ASSERT_LESS_OR_EQUAL_size_t(16u, sz);
    TEST_ASSERT_LESS_OR_EQUAL_size_t_MESSAGE(16u, sz, "le size_t");
    TEST_ASSERT_GREATER_THAN_HEX8(0x0F, 0x10);
    TEST_ASSERT_LESS_OR_EQUAL_HEX32(0x10u, 0x10u);

    TEST_ASSERT_UINT_WITHIN(3u, 10u, 13u);
    TEST_ASSERT_UINT_WITHIN(3u, 13u, 10u);
    TEST_ASSERT_UINT_WITHIN_MESSAGE(0u, 10u, u32, "uwithin");
    TEST_ASSERT_UINT8_WITHIN(5, 250, 255);
    TEST_ASSERT_UINT16_WITHIN(1, 0, 1);
    TEST_ASSERT_UINT32_WITHIN(1u, UINT32_MAX, UINT32_MAX - 1u);
    TEST_ASSERT_UINT64_WITHIN(0u, UINT64_MAX, UINT64_MAX);
}

static void test_strings_memory_arrays(void)
{
    const char *hello = "hello";
    char buf[8];
    const int ints_a[4] = {1, -2, 3, 2147483647};
    const int ints_b[4] = {1, -2, 3, 2147483647};
    const uint8_t bytes_a[3] = {0x00, 0x7F, 0xFF};
    uint8_t bytes_b[3] = {0x00, 0x7F, 0xFF};

    (void)strcpy(buf, "hello");
    TEST_ASSERT_EQUAL_STRING("hello", buf);
    TEST_ASSERT_EQUAL_STRING_MESSAGE(hello, buf, "strings");
    TEST_ASSERT_EQUAL_STRING(NULL, NULL);
    TEST_ASSERT_EQUAL_STRING_LEN("help", hello, 3);
    TEST_ASSERT_EQUAL_STRING_LEN("hello", hello, 99); /* stops at the terminator */
    TEST_ASSERT_EQUAL_STRING_LEN_MESSAGE("hex", hello, 1, "len");
    TEST_ASSERT_EQUAL_MEMORY("hello", buf, 6);
    TEST_ASSERT_EQUAL_MEMORY_MESSAGE(bytes_a, bytes_b, sizeof bytes_a, "memory");
    TEST_ASSERT_EQUAL_INT_ARRAY(ints_a, ints_b, 4);
    TEST_ASSERT_EQUAL_INT_ARRAY_MESSAGE(ints_a, ints_b, 4u, "ints");
    TEST_ASSERT_EQUAL_UINT8_ARRAY(bytes_a, bytes_b, 3);
    TEST_ASSERT_EQUAL_UINT8_ARRAY_MESSAGE(bytes_a, bytes_b, sizeof bytes_b, "bytes");
}

/* Real type that is float in some builds and double in others. */
#ifdef SELFTEST_REAL_IS_DOUBLE
typedef double real_t;
#else
typedef float real_t;
#endif

static void test_float(void)
{
    real_t r = (real_t)0.1;
    float f = 20000.0f;
    float zero = 0.0f;
    float pinf = (float)INFINITY;
    float ninf = -(float)INFINITY;
    float nan_v = (float)NAN;
    const float fa[3] = {1.0f, -2.5f, 1000.0f};
    const float fb[3] = {1.0f, -2.5f, 1000.004f};
    const float fc[3] = {1.05f, -2.45f, 1000.0f};

    TEST_ASSERT_FLOAT_WITHIN(0.001f, 0.1f, r);
    TEST_ASSERT_FLOAT_WITHIN(0.5, 1.0, 1.5);     /* delta is inclusive */
    TEST_ASSERT_FLOAT_WITHIN(-0.5f, 1.0f, 0.5f); /* negative delta: absolute value */
    TEST_ASSERT_FLOAT_WITHIN_MESSAGE(0.0f, r, r, "r");
    TEST_ASSERT_FLOAT_NOT_WITHIN(0.1f, 1.0f, 2.0f);
    TEST_ASSERT_FLOAT_NOT_WITHIN_MESSAGE(0.1f, 1.0f, nan_v, "nan never within a number");
    TEST_ASSERT_EQUAL_FLOAT(20000.0f, f);
    TEST_ASSERT_EQUAL_FLOAT(20000.0f, 20000.19f); /* 1e-5 relative */
    TEST_ASSERT_EQUAL_FLOAT_MESSAGE(0.1, r, "real");
    TEST_ASSERT_EQUAL_FLOAT(0.0f, zero);
    TEST_ASSERT_NOT_EQUAL_FLOAT(20000.0f, 20000.5f);
    TEST_ASSERT_NOT_EQUAL_FLOAT_MESSAGE(0.0f, 1e-30f, "zero needs exact match");

    TEST_ASSERT_EQUAL_FLOAT(pinf, pinf);
    TEST_ASSERT_EQUAL_FLOAT(ninf, ninf);
    TEST_ASSERT_NOT_EQUAL_FLOAT(pinf, ninf);
    TEST_ASSERT_NOT_EQUAL_FLOAT(pinf, 1.0f);
    TEST_ASSERT_EQUAL_FLOAT(nan_v, nan_v); /* documented choice: NaN "equals" NaN */
    TEST_ASSERT_NOT_EQUAL_FLOAT(nan_v, 0.0f);
    TEST_ASSERT_NOT_EQUAL_FLOAT(1.0f, nan_v);
    TEST_ASSERT_FLOAT_WITHIN(1e30f, 0.0f, 1.0f);
    TEST_ASSERT_FLOAT_NOT_WITHIN(1.0f, 0.0f, pinf);

    TEST_ASSERT_EQUAL_FLOAT_ARRAY(fa, fb, 3); /* 1000.004 within 1000 * 1e-5 */
    TEST_ASSERT_EQUAL_FLOAT_ARRAY_MESSAGE(fa, fa, 3u, "same pointer");
    TEST_ASSERT_FLOAT_ARRAY_WITHIN(0.05f, fa, fc, 3);
    TEST_ASSERT_FLOAT_ARRAY_WITHIN_MESSAGE(0.1, fa, fc, 3, "array within");

    TEST_ASSERT_LESS_THAN_FLOAT(1.0f, 0.5f);
    TEST_ASSERT_LESS_THAN_FLOAT_MESSAGE(1.0, r, "lt");
    TEST_ASSERT_GREATER_THAN_FLOAT(0.0f, r);
    TEST_ASSERT_GREATER_THAN_FLOAT_MESSAGE(-1.0f, 0.0f, "gt");
    TEST_ASSERT_LESS_OR_EQUAL_FLOAT(1.0f, 1.0f);
    TEST_ASSERT_GREATER_OR_EQUAL_FLOAT(1.0f, 1.0f);
    TEST_ASSERT_GREATER_OR_EQUAL_FLOAT_MESSAGE(1.0f, 2.0f, "ge");
    TEST_ASSERT_LESS_OR_EQUAL_FLOAT_MESSAGE(1.0f, ninf, "le");

    TEST_ASSERT_FLOAT_IS_INF(pinf);
    TEST_ASSERT_FLOAT_IS_INF_MESSAGE(1.0f / zero, "1/0");
    TEST_ASSERT_FLOAT_IS_NEG_INF(ninf);
    TEST_ASSERT_FLOAT_IS_NEG_INF_MESSAGE(-1.0f / zero, "-1/0");
    TEST_ASSERT_FLOAT_IS_NOT_INF(ninf);
    TEST_ASSERT_FLOAT_IS_NOT_INF_MESSAGE(r, "finite");
    TEST_ASSERT_FLOAT_IS_NOT_NEG_INF(pinf);
    TEST_ASSERT_FLOAT_IS_NAN(nan_v);
    TEST_ASSERT_FLOAT_IS_NAN_MESSAGE(zero / zero, "0/0");
    TEST_ASSERT_FLOAT_IS_NOT_NAN(r);
    TEST_ASSERT_FLOAT_IS_NOT_NAN_MESSAGE(pinf, "inf is not nan");
    TEST_ASSERT_FLOAT_IS_DETERMINATE(r);
    TEST_ASSERT_FLOAT_IS_DETERMINATE_MESSAGE(f, "finite");
    TEST_ASSERT_FLOAT_IS_NOT_DETERMINATE(nan_v);
    TEST_ASSERT_FLOAT_IS_NOT_DETERMINATE_MESSAGE(ninf, "-inf");
}

static void test_double(void)
{
    double d = 0.1;
    double big = 1e6;
    double zero = 0.0;
    double pinf = (double)INFINITY;
    double nan_v = (double)NAN;
    const double da[2] = {1.0, 1e10};
    const double db[2] = {1.0, 1e10 + 0.001}; /* 1e-13 relative */
    const double dc[2] = {1.001, 1e10};

#ifndef UNITY_INCLUDE_DOUBLE
    TEST_IGNORE_MESSAGE("double assertions disabled (no UNITY_INCLUDE_DOUBLE)");
#endif
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.1, d);
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.5, 1.0, 1.5, "inclusive");
    TEST_ASSERT_DOUBLE_NOT_WITHIN(1e-9, 0.1, 0.2);
    TEST_ASSERT_DOUBLE_NOT_WITHIN_MESSAGE(1.0, 0.0, nan_v, "nan");
    TEST_ASSERT_EQUAL_DOUBLE(0.1, d);
    TEST_ASSERT_EQUAL_DOUBLE(1e6, big + 1e-7); /* within 1e6 * 1e-12 */
    TEST_ASSERT_EQUAL_DOUBLE_MESSAGE(0.0, zero, "zero");
    TEST_ASSERT_EQUAL_DOUBLE(pinf, pinf);
    TEST_ASSERT_EQUAL_DOUBLE(nan_v, nan_v);
    TEST_ASSERT_NOT_EQUAL_DOUBLE(1e6, big + 1e-5);
    TEST_ASSERT_NOT_EQUAL_DOUBLE_MESSAGE(pinf, -pinf, "signs");
    TEST_ASSERT_EQUAL_DOUBLE_ARRAY(da, db, 2);
    TEST_ASSERT_EQUAL_DOUBLE_ARRAY_MESSAGE(da, db, 2u, "array");
    TEST_ASSERT_DOUBLE_ARRAY_WITHIN(0.01, da, dc, 2);
    TEST_ASSERT_DOUBLE_ARRAY_WITHIN_MESSAGE(0.01, da, dc, 2, "array within");
    TEST_ASSERT_LESS_THAN_DOUBLE(1.0, d);
    TEST_ASSERT_LESS_THAN_DOUBLE_MESSAGE(1.0, d, "lt");
    TEST_ASSERT_GREATER_THAN_DOUBLE(0.0, d);
    TEST_ASSERT_GREATER_THAN_DOUBLE_MESSAGE(0.0, d, "gt");
    TEST_ASSERT_LESS_OR_EQUAL_DOUBLE(0.1, d);
    TEST_ASSERT_LESS_OR_EQUAL_DOUBLE_MESSAGE(0.1, d, "le");
    TEST_ASSERT_GREATER_OR_EQUAL_DOUBLE(0.1, d);
    TEST_ASSERT_GREATER_OR_EQUAL_DOUBLE_MESSAGE(0.1, d, "ge");
    TEST_ASSERT_DOUBLE_IS_INF(pinf);
    TEST_ASSERT_DOUBLE_IS_INF_MESSAGE(1.0 / zero, "1/0");
    TEST_ASSERT_DOUBLE_IS_NEG_INF(-pinf);
    TEST_ASSERT_DOUBLE_IS_NEG_INF_MESSAGE(-1.0 / zero, "-1/0");
    TEST_ASSERT_DOUBLE_IS_NOT_INF(d);
    TEST_ASSERT_DOUBLE_IS_NOT_INF_MESSAGE(-pinf, "-inf");
    TEST_ASSERT_DOUBLE_IS_NOT_NEG_INF(pinf);
    TEST_ASSERT_DOUBLE_IS_NOT_NEG_INF_MESSAGE(d, "d");
    TEST_ASSERT_DOUBLE_IS_NAN(nan_v);
    TEST_ASSERT_DOUBLE_IS_NAN_MESSAGE(zero / zero, "0/0");
    TEST_ASSERT_DOUBLE_IS_NOT_NAN(d);
    TEST_ASSERT_DOUBLE_IS_NOT_NAN_MESSAGE(pinf, "inf");
    TEST_ASSERT_DOUBLE_IS_DETERMINATE(d);
    TEST_ASSERT_DOUBLE_IS_DETERMINATE_MESSAGE(big, "big");
    TEST_ASSERT_DOUBLE_IS_NOT_DETERMINATE(nan_v);
    TEST_ASSERT_DOUBLE_IS_NOT_DETERMINATE_MESSAGE(pinf, "inf");
}

static void test_pass_ends_test(void)
{
    TEST_PASS();
    after_pass_reached = 1; /* must not run */
}

static void test_pass_message(void)
{
    TEST_PASS_MESSAGE("passing early with a message");
    after_pass_reached = 1; /* must not run */
}

int main(void)
{
    int failures;

    UNITY_BEGIN();
    RUN_TEST(test_boolean_and_pointers);
    RUN_TEST(test_signed_integers);
    RUN_TEST(test_unsigned_integers);
    RUN_TEST(test_unsigned_order);
    RUN_TEST(test_strings_memory_arrays);
    RUN_TEST(test_float);
    RUN_TEST(test_double);
    RUN_TEST(test_pass_ends_test);
    RUN_TEST(test_pass_message);
    failures = UNITY_END();

    if (set_up_calls != 9 || tear_down_calls != 9 || after_pass_reached != 0)
    {
        printf("HARNESS SELF-CHECK FAILED: setUp %d, tearDown %d, after TEST_PASS %d\n",
               set_up_calls, tear_down_calls, after_pass_reached);
        return 100;
    }
    return failures;
}
