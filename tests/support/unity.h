/*
 * unity.h - clean-room test harness for the aenl test suite.
 *
 * Written by the aenl authors.  It contains no code or text from the
 * ThrowTheSwitch Unity project; it only offers a subset of the same public
 * macro names with the same calling conventions, so test files written
 * against it also build against the real Unity (v2.6+).  See README.md.
 *
 * Everything whose name starts with UnityCR_ / UNITYCR_ is private to the
 * harness; tests must only use the documented TEST_ and RUN_TEST macros.
 */
#ifndef UNITY_FRAMEWORK_H
#define UNITY_FRAMEWORK_H

#include <stddef.h>
#include <stdint.h>

/* ---- configuration (same names as Unity) ------------------------------ */

#ifndef UNITY_FLOAT_TYPE
#define UNITY_FLOAT_TYPE float
#endif
#ifndef UNITY_DOUBLE_TYPE
#define UNITY_DOUBLE_TYPE double
#endif

typedef UNITY_FLOAT_TYPE UNITY_FLOAT;
typedef UNITY_DOUBLE_TYPE UNITY_DOUBLE;
typedef void (*UnityTestFunction)(void);

/* Provided by every test file. */
void setUp(void);
void tearDown(void);

/* ---- private interface ------------------------------------------------ */

typedef enum
{
    UNITYCR_EQ,
    UNITYCR_NE,
    UNITYCR_GT,
    UNITYCR_GE,
    UNITYCR_LT,
    UNITYCR_LE
} UnityCR_Op;

typedef enum
{
    UNITYCR_DEC,
    UNITYCR_HEX8,
    UNITYCR_HEX16,
    UNITYCR_HEX32,
    UNITYCR_HEX64
} UnityCR_Fmt;

typedef enum
{
    UNITYCR_INF,
    UNITYCR_NEG_INF,
    UNITYCR_NAN,
    UNITYCR_DETERMINATE
} UnityCR_Trait;

void UnityCR_Begin(const char *file);
int UnityCR_End(void);
void UnityCR_Run(UnityTestFunction func, const char *name, int line);

void UnityCR_Fail(const char *message, int line);
void UnityCR_Ignore(const char *message, int line);
void UnityCR_Pass(void);
void UnityCR_Message(const char *message, int line);
void UnityCR_Check(int ok, const char *what, const char *message, int line);

void UnityCR_CmpInt(int64_t ref, int64_t actual, UnityCR_Op op, const char *message, int line);
void UnityCR_CmpUint(uint64_t ref, uint64_t actual, UnityCR_Op op, UnityCR_Fmt fmt,
                     const char *message, int line);
void UnityCR_IntWithin(uint64_t delta, int64_t expected, int64_t actual, const char *message,
                       int line);
void UnityCR_UintWithin(uint64_t delta, uint64_t expected, uint64_t actual, const char *message,
                        int line);

void UnityCR_String(const char *expected, const char *actual, const char *message, int line);
void UnityCR_StringLen(const char *expected, const char *actual, uint32_t len, const char *message,
                       int line);
void UnityCR_Memory(const void *expected, const void *actual, uint32_t len, const char *message,
                    int line);
void UnityCR_IntArray(const void *expected, const void *actual, uint32_t count, const char *message,
                      int line);
void UnityCR_Uint8Array(const void *expected, const void *actual, uint32_t count,
                        const char *message, int line);

void UnityCR_FloatWithin(UNITY_FLOAT delta, UNITY_FLOAT expected, UNITY_FLOAT actual,
                         int want_within, const char *message, int line);
void UnityCR_FloatEqual(UNITY_FLOAT expected, UNITY_FLOAT actual, int want_equal,
                        const char *message, int line);
void UnityCR_FloatArray(UNITY_FLOAT delta, const UNITY_FLOAT *expected, const UNITY_FLOAT *actual,
                        uint32_t count, const char *message, int line);
void UnityCR_FloatOrder(UNITY_FLOAT threshold, UNITY_FLOAT actual, UnityCR_Op op,
                        const char *message, int line);
void UnityCR_FloatTrait(UNITY_FLOAT actual, UnityCR_Trait trait, int want, const char *message,
                        int line);

void UnityCR_DoubleWithin(UNITY_DOUBLE delta, UNITY_DOUBLE expected, UNITY_DOUBLE actual,
                          int want_within, const char *message, int line);
void UnityCR_DoubleEqual(UNITY_DOUBLE expected, UNITY_DOUBLE actual, int want_equal,
                         const char *message, int line);
void UnityCR_DoubleArray(UNITY_DOUBLE delta, const UNITY_DOUBLE *expected,
                         const UNITY_DOUBLE *actual, uint32_t count, const char *message, int line);
void UnityCR_DoubleOrder(UNITY_DOUBLE threshold, UNITY_DOUBLE actual, UnityCR_Op op,
                         const char *message, int line);
void UnityCR_DoubleTrait(UNITY_DOUBLE actual, UnityCR_Trait trait, int want, const char *message,
                         int line);

/* ---- running tests ---------------------------------------------------- */

#define UNITY_BEGIN()  UnityCR_Begin(__FILE__)
#define UNITY_END()    UnityCR_End()
#define RUN_TEST(func) UnityCR_Run((func), #func, __LINE__)

/* ---- fail, pass, ignore, message -------------------------------------- */

#define TEST_FAIL()                  UnityCR_Fail(NULL, __LINE__)
#define TEST_FAIL_MESSAGE(message)   UnityCR_Fail((message), __LINE__)
#define TEST_IGNORE()                UnityCR_Ignore(NULL, __LINE__)
#define TEST_IGNORE_MESSAGE(message) UnityCR_Ignore((message), __LINE__)
#define TEST_PASS()                  UnityCR_Pass()
#define TEST_PASS_MESSAGE(message)   (UnityCR_Message((message), __LINE__), UnityCR_Pass())
#define TEST_MESSAGE(message)        UnityCR_Message((message), __LINE__)

/* ---- boolean and pointer ---------------------------------------------- */

#define UNITYCR_BOOL(cond, what, message)                                                          \
    UnityCR_Check(((cond) ? 1 : 0), (what), (message), __LINE__)

#define TEST_ASSERT(condition) UNITYCR_BOOL((condition), "Expression Evaluated To FALSE", NULL)
#define TEST_ASSERT_MESSAGE(condition, message)                                                    \
    UNITYCR_BOOL((condition), "Expression Evaluated To FALSE", (message))
#define TEST_ASSERT_TRUE(condition) UNITYCR_BOOL((condition), "Expected TRUE Was FALSE", NULL)
#define TEST_ASSERT_TRUE_MESSAGE(condition, message)                                               \
    UNITYCR_BOOL((condition), "Expected TRUE Was FALSE", (message))
#define TEST_ASSERT_UNLESS(condition)                                                              \
    UNITYCR_BOOL(!(condition), "Expression Evaluated To TRUE", NULL)
#define TEST_ASSERT_UNLESS_MESSAGE(condition, message)                                             \
    UNITYCR_BOOL(!(condition), "Expression Evaluated To TRUE", (message))
#define TEST_ASSERT_FALSE(condition) UNITYCR_BOOL(!(condition), "Expected FALSE Was TRUE", NULL)
#define TEST_ASSERT_FALSE_MESSAGE(condition, message)                                              \
    UNITYCR_BOOL(!(condition), "Expected FALSE Was TRUE", (message))
#define TEST_ASSERT_NULL(pointer) UNITYCR_BOOL(((pointer) == NULL), "Expected NULL", NULL)
#define TEST_ASSERT_NULL_MESSAGE(pointer, message)                                                 \
    UNITYCR_BOOL(((pointer) == NULL), "Expected NULL", (message))
#define TEST_ASSERT_NOT_NULL(pointer) UNITYCR_BOOL(((pointer) != NULL), "Expected Non-NULL", NULL)
#define TEST_ASSERT_NOT_NULL_MESSAGE(pointer, message)                                             \
    UNITYCR_BOOL(((pointer) != NULL), "Expected Non-NULL", (message))

/* Generic not-equal: a plain != on the arguments, as in Unity. */
#define TEST_ASSERT_NOT_EQUAL(expected, actual)                                                    \
    UNITYCR_BOOL(((expected) != (actual)), "Expected Not-Equal", NULL)
#define TEST_ASSERT_NOT_EQUAL_MESSAGE(expected, actual, message)                                   \
    UNITYCR_BOOL(((expected) != (actual)), "Expected Not-Equal", (message))

/* ---- integers ---------------------------------------------------------- */
/* Each value is first cast to the named width (so wider arguments are
 * truncated, as in Unity), then widened to 64 bits for the comparison. */

#define UNITYCR_I(r, a, op, m) UnityCR_CmpInt((int64_t)(r), (int64_t)(a), (op), (m), __LINE__)
#define UNITYCR_I8(r, a, op, m)                                                                    \
    UnityCR_CmpInt((int64_t)(int8_t)(r), (int64_t)(int8_t)(a), (op), (m), __LINE__)
#define UNITYCR_I16(r, a, op, m)                                                                   \
    UnityCR_CmpInt((int64_t)(int16_t)(r), (int64_t)(int16_t)(a), (op), (m), __LINE__)
#define UNITYCR_I32(r, a, op, m)                                                                   \
    UnityCR_CmpInt((int64_t)(int32_t)(r), (int64_t)(int32_t)(a), (op), (m), __LINE__)
#define UNITYCR_U(r, a, op, m)                                                                     \
    UnityCR_CmpUint((uint64_t)(r), (uint64_t)(a), (op), UNITYCR_DEC, (m), __LINE__)
#define UNITYCR_U8(r, a, op, m)                                                                    \
    UnityCR_CmpUint((uint64_t)(uint8_t)(r), (uint64_t)(uint8_t)(a), (op), UNITYCR_DEC, (m),        \
                    __LINE__)
#define UNITYCR_U16(r, a, op, m)                                                                   \
    UnityCR_CmpUint((uint64_t)(uint16_t)(r), (uint64_t)(uint16_t)(a), (op), UNITYCR_DEC, (m),      \
                    __LINE__)
#define UNITYCR_U32(r, a, op, m)                                                                   \
    UnityCR_CmpUint((uint64_t)(uint32_t)(r), (uint64_t)(uint32_t)(a), (op), UNITYCR_DEC, (m),      \
                    __LINE__)
#define UNITYCR_H8(r, a, op, m)                                                                    \
    UnityCR_CmpUint((uint64_t)(uint8_t)(r), (uint64_t)(uint8_t)(a), (op), UNITYCR_HEX8, (m),       \
                    __LINE__)
#define UNITYCR_H16(r, a, op, m)                                                                   \
    UnityCR_CmpUint((uint64_t)(uint16_t)(r), (uint64_t)(uint16_t)(a), (op), UNITYCR_HEX16, (m),    \
                    __LINE__)
#define UNITYCR_H32(r, a, op, m)                                                                   \
    UnityCR_CmpUint((uint64_t)(uint32_t)(r), (uint64_t)(uint32_t)(a), (op), UNITYCR_HEX32, (m),    \
                    __LINE__)
#define UNITYCR_H64(r, a, op, m)                                                                   \
    UnityCR_CmpUint((uint64_t)(r), (uint64_t)(a), (op), UNITYCR_HEX64, (m), __LINE__)

/* EQUAL: (expected, actual) */
#define TEST_ASSERT_EQUAL(expected, actual) UNITYCR_I((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_MESSAGE(expected, actual, message)                                       \
    UNITYCR_I((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_INT(expected, actual) UNITYCR_I((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_INT_MESSAGE(expected, actual, message)                                   \
    UNITYCR_I((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_INT8(expected, actual) UNITYCR_I8((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_INT8_MESSAGE(expected, actual, message)                                  \
    UNITYCR_I8((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_INT16(expected, actual)                                                  \
    UNITYCR_I16((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_INT16_MESSAGE(expected, actual, message)                                 \
    UNITYCR_I16((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_INT32(expected, actual)                                                  \
    UNITYCR_I32((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_INT32_MESSAGE(expected, actual, message)                                 \
    UNITYCR_I32((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_INT64(expected, actual) UNITYCR_I((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_INT64_MESSAGE(expected, actual, message)                                 \
    UNITYCR_I((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_UINT(expected, actual) UNITYCR_U((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_UINT_MESSAGE(expected, actual, message)                                  \
    UNITYCR_U((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_UINT8(expected, actual) UNITYCR_U8((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_UINT8_MESSAGE(expected, actual, message)                                 \
    UNITYCR_U8((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_UINT16(expected, actual)                                                 \
    UNITYCR_U16((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_UINT16_MESSAGE(expected, actual, message)                                \
    UNITYCR_U16((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_UINT32(expected, actual)                                                 \
    UNITYCR_U32((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_UINT32_MESSAGE(expected, actual, message)                                \
    UNITYCR_U32((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_UINT64(expected, actual) UNITYCR_U((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_UINT64_MESSAGE(expected, actual, message)                                \
    UNITYCR_U((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_HEX(expected, actual) UNITYCR_H32((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_HEX_MESSAGE(expected, actual, message)                                   \
    UNITYCR_H32((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_HEX8(expected, actual) UNITYCR_H8((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_HEX8_MESSAGE(expected, actual, message)                                  \
    UNITYCR_H8((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_HEX16(expected, actual)                                                  \
    UNITYCR_H16((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_HEX16_MESSAGE(expected, actual, message)                                 \
    UNITYCR_H16((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_HEX32(expected, actual)                                                  \
    UNITYCR_H32((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_HEX32_MESSAGE(expected, actual, message)                                 \
    UNITYCR_H32((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_HEX64(expected, actual)                                                  \
    UNITYCR_H64((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_HEX64_MESSAGE(expected, actual, message)                                 \
    UNITYCR_H64((expected), (actual), UNITYCR_EQ, (message))
#define TEST_ASSERT_EQUAL_size_t(expected, actual) UNITYCR_U((expected), (actual), UNITYCR_EQ, NULL)
#define TEST_ASSERT_EQUAL_size_t_MESSAGE(expected, actual, message)                                \
    UNITYCR_U((expected), (actual), UNITYCR_EQ, (message))

/* NOT_EQUAL: (expected, actual) */
#define TEST_ASSERT_NOT_EQUAL_INT(expected, actual)                                                \
    UNITYCR_I((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_INT_MESSAGE(expected, actual, message)                               \
    UNITYCR_I((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_INT8(expected, actual)                                               \
    UNITYCR_I8((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_INT8_MESSAGE(expected, actual, message)                              \
    UNITYCR_I8((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_INT16(expected, actual)                                              \
    UNITYCR_I16((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_INT16_MESSAGE(expected, actual, message)                             \
    UNITYCR_I16((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_INT32(expected, actual)                                              \
    UNITYCR_I32((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_INT32_MESSAGE(expected, actual, message)                             \
    UNITYCR_I32((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_INT64(expected, actual)                                              \
    UNITYCR_I((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_INT64_MESSAGE(expected, actual, message)                             \
    UNITYCR_I((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_UINT(expected, actual)                                               \
    UNITYCR_U((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_UINT_MESSAGE(expected, actual, message)                              \
    UNITYCR_U((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_UINT8(expected, actual)                                              \
    UNITYCR_U8((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_UINT8_MESSAGE(expected, actual, message)                             \
    UNITYCR_U8((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_UINT16(expected, actual)                                             \
    UNITYCR_U16((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_UINT16_MESSAGE(expected, actual, message)                            \
    UNITYCR_U16((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_UINT32(expected, actual)                                             \
    UNITYCR_U32((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_UINT32_MESSAGE(expected, actual, message)                            \
    UNITYCR_U32((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_UINT64(expected, actual)                                             \
    UNITYCR_U((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_UINT64_MESSAGE(expected, actual, message)                            \
    UNITYCR_U((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_HEX(expected, actual)                                                \
    UNITYCR_H32((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_HEX_MESSAGE(expected, actual, message)                               \
    UNITYCR_H32((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_HEX8(expected, actual)                                               \
    UNITYCR_H8((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_HEX8_MESSAGE(expected, actual, message)                              \
    UNITYCR_H8((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_HEX16(expected, actual)                                              \
    UNITYCR_H16((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_HEX16_MESSAGE(expected, actual, message)                             \
    UNITYCR_H16((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_HEX32(expected, actual)                                              \
    UNITYCR_H32((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_HEX32_MESSAGE(expected, actual, message)                             \
    UNITYCR_H32((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_HEX64(expected, actual)                                              \
    UNITYCR_H64((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_HEX64_MESSAGE(expected, actual, message)                             \
    UNITYCR_H64((expected), (actual), UNITYCR_NE, (message))
#define TEST_ASSERT_NOT_EQUAL_size_t(expected, actual)                                             \
    UNITYCR_U((expected), (actual), UNITYCR_NE, NULL)
#define TEST_ASSERT_NOT_EQUAL_size_t_MESSAGE(expected, actual, message)                            \
    UNITYCR_U((expected), (actual), UNITYCR_NE, (message))

/* GREATER_THAN: (threshold, actual) */
#define TEST_ASSERT_GREATER_THAN(threshold, actual)                                                \
    UNITYCR_I((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_MESSAGE(threshold, actual, message)                               \
    UNITYCR_I((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_INT(threshold, actual)                                            \
    UNITYCR_I((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_INT_MESSAGE(threshold, actual, message)                           \
    UNITYCR_I((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_INT8(threshold, actual)                                           \
    UNITYCR_I8((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_INT8_MESSAGE(threshold, actual, message)                          \
    UNITYCR_I8((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_INT16(threshold, actual)                                          \
    UNITYCR_I16((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_INT16_MESSAGE(threshold, actual, message)                         \
    UNITYCR_I16((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_INT32(threshold, actual)                                          \
    UNITYCR_I32((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_INT32_MESSAGE(threshold, actual, message)                         \
    UNITYCR_I32((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_INT64(threshold, actual)                                          \
    UNITYCR_I((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_INT64_MESSAGE(threshold, actual, message)                         \
    UNITYCR_I((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_UINT(threshold, actual)                                           \
    UNITYCR_U((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_UINT_MESSAGE(threshold, actual, message)                          \
    UNITYCR_U((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_UINT8(threshold, actual)                                          \
    UNITYCR_U8((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_UINT8_MESSAGE(threshold, actual, message)                         \
    UNITYCR_U8((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_UINT16(threshold, actual)                                         \
    UNITYCR_U16((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_UINT16_MESSAGE(threshold, actual, message)                        \
    UNITYCR_U16((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_UINT32(threshold, actual)                                         \
    UNITYCR_U32((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_UINT32_MESSAGE(threshold, actual, message)                        \
    UNITYCR_U32((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_UINT64(threshold, actual)                                         \
    UNITYCR_U((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_UINT64_MESSAGE(threshold, actual, message)                        \
    UNITYCR_U((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_HEX(threshold, actual)                                            \
    UNITYCR_H32((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_HEX_MESSAGE(threshold, actual, message)                           \
    UNITYCR_H32((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_HEX8(threshold, actual)                                           \
    UNITYCR_H8((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_HEX8_MESSAGE(threshold, actual, message)                          \
    UNITYCR_H8((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_HEX16(threshold, actual)                                          \
    UNITYCR_H16((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_HEX16_MESSAGE(threshold, actual, message)                         \
    UNITYCR_H16((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_HEX32(threshold, actual)                                          \
    UNITYCR_H32((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_HEX32_MESSAGE(threshold, actual, message)                         \
    UNITYCR_H32((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_HEX64(threshold, actual)                                          \
    UNITYCR_H64((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_HEX64_MESSAGE(threshold, actual, message)                         \
    UNITYCR_H64((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_GREATER_THAN_size_t(threshold, actual)                                         \
    UNITYCR_U((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_size_t_MESSAGE(threshold, actual, message)                        \
    UNITYCR_U((threshold), (actual), UNITYCR_GT, (message))

/* LESS_THAN: (threshold, actual) */
#define TEST_ASSERT_LESS_THAN(threshold, actual) UNITYCR_I((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_MESSAGE(threshold, actual, message)                                  \
    UNITYCR_I((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_INT(threshold, actual)                                               \
    UNITYCR_I((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_INT_MESSAGE(threshold, actual, message)                              \
    UNITYCR_I((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_INT8(threshold, actual)                                              \
    UNITYCR_I8((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_INT8_MESSAGE(threshold, actual, message)                             \
    UNITYCR_I8((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_INT16(threshold, actual)                                             \
    UNITYCR_I16((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_INT16_MESSAGE(threshold, actual, message)                            \
    UNITYCR_I16((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_INT32(threshold, actual)                                             \
    UNITYCR_I32((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_INT32_MESSAGE(threshold, actual, message)                            \
    UNITYCR_I32((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_INT64(threshold, actual)                                             \
    UNITYCR_I((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_INT64_MESSAGE(threshold, actual, message)                            \
    UNITYCR_I((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_UINT(threshold, actual)                                              \
    UNITYCR_U((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_UINT_MESSAGE(threshold, actual, message)                             \
    UNITYCR_U((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_UINT8(threshold, actual)                                             \
    UNITYCR_U8((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_UINT8_MESSAGE(threshold, actual, message)                            \
    UNITYCR_U8((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_UINT16(threshold, actual)                                            \
    UNITYCR_U16((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_UINT16_MESSAGE(threshold, actual, message)                           \
    UNITYCR_U16((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_UINT32(threshold, actual)                                            \
    UNITYCR_U32((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_UINT32_MESSAGE(threshold, actual, message)                           \
    UNITYCR_U32((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_UINT64(threshold, actual)                                            \
    UNITYCR_U((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_UINT64_MESSAGE(threshold, actual, message)                           \
    UNITYCR_U((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_HEX(threshold, actual)                                               \
    UNITYCR_H32((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_HEX_MESSAGE(threshold, actual, message)                              \
    UNITYCR_H32((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_HEX8(threshold, actual)                                              \
    UNITYCR_H8((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_HEX8_MESSAGE(threshold, actual, message)                             \
    UNITYCR_H8((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_HEX16(threshold, actual)                                             \
    UNITYCR_H16((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_HEX16_MESSAGE(threshold, actual, message)                            \
    UNITYCR_H16((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_HEX32(threshold, actual)                                             \
    UNITYCR_H32((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_HEX32_MESSAGE(threshold, actual, message)                            \
    UNITYCR_H32((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_HEX64(threshold, actual)                                             \
    UNITYCR_H64((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_HEX64_MESSAGE(threshold, actual, message)                            \
    UNITYCR_H64((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_LESS_THAN_size_t(threshold, actual)                                            \
    UNITYCR_U((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_size_t_MESSAGE(threshold, actual, message)                           \
    UNITYCR_U((threshold), (actual), UNITYCR_LT, (message))

/* GREATER_OR_EQUAL: (threshold, actual) */
#define TEST_ASSERT_GREATER_OR_EQUAL(threshold, actual)                                            \
    UNITYCR_I((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_MESSAGE(threshold, actual, message)                           \
    UNITYCR_I((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_INT(threshold, actual)                                        \
    UNITYCR_I((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_INT_MESSAGE(threshold, actual, message)                       \
    UNITYCR_I((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_INT8(threshold, actual)                                       \
    UNITYCR_I8((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_INT8_MESSAGE(threshold, actual, message)                      \
    UNITYCR_I8((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_INT16(threshold, actual)                                      \
    UNITYCR_I16((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_INT16_MESSAGE(threshold, actual, message)                     \
    UNITYCR_I16((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_INT32(threshold, actual)                                      \
    UNITYCR_I32((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_INT32_MESSAGE(threshold, actual, message)                     \
    UNITYCR_I32((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_INT64(threshold, actual)                                      \
    UNITYCR_I((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_INT64_MESSAGE(threshold, actual, message)                     \
    UNITYCR_I((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT(threshold, actual)                                       \
    UNITYCR_U((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT_MESSAGE(threshold, actual, message)                      \
    UNITYCR_U((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT8(threshold, actual)                                      \
    UNITYCR_U8((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT8_MESSAGE(threshold, actual, message)                     \
    UNITYCR_U8((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT16(threshold, actual)                                     \
    UNITYCR_U16((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT16_MESSAGE(threshold, actual, message)                    \
    UNITYCR_U16((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT32(threshold, actual)                                     \
    UNITYCR_U32((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT32_MESSAGE(threshold, actual, message)                    \
    UNITYCR_U32((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT64(threshold, actual)                                     \
    UNITYCR_U((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_UINT64_MESSAGE(threshold, actual, message)                    \
    UNITYCR_U((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX(threshold, actual)                                        \
    UNITYCR_H32((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX_MESSAGE(threshold, actual, message)                       \
    UNITYCR_H32((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX8(threshold, actual)                                       \
    UNITYCR_H8((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX8_MESSAGE(threshold, actual, message)                      \
    UNITYCR_H8((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX16(threshold, actual)                                      \
    UNITYCR_H16((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX16_MESSAGE(threshold, actual, message)                     \
    UNITYCR_H16((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX32(threshold, actual)                                      \
    UNITYCR_H32((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX32_MESSAGE(threshold, actual, message)                     \
    UNITYCR_H32((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX64(threshold, actual)                                      \
    UNITYCR_H64((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_HEX64_MESSAGE(threshold, actual, message)                     \
    UNITYCR_H64((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_size_t(threshold, actual)                                     \
    UNITYCR_U((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_size_t_MESSAGE(threshold, actual, message)                    \
    UNITYCR_U((threshold), (actual), UNITYCR_GE, (message))

/* LESS_OR_EQUAL: (threshold, actual) */
#define TEST_ASSERT_LESS_OR_EQUAL(threshold, actual)                                               \
    UNITYCR_I((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_MESSAGE(threshold, actual, message)                              \
    UNITYCR_I((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_INT(threshold, actual)                                           \
    UNITYCR_I((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_INT_MESSAGE(threshold, actual, message)                          \
    UNITYCR_I((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_INT8(threshold, actual)                                          \
    UNITYCR_I8((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_INT8_MESSAGE(threshold, actual, message)                         \
    UNITYCR_I8((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_INT16(threshold, actual)                                         \
    UNITYCR_I16((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_INT16_MESSAGE(threshold, actual, message)                        \
    UNITYCR_I16((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_INT32(threshold, actual)                                         \
    UNITYCR_I32((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_INT32_MESSAGE(threshold, actual, message)                        \
    UNITYCR_I32((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_INT64(threshold, actual)                                         \
    UNITYCR_I((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_INT64_MESSAGE(threshold, actual, message)                        \
    UNITYCR_I((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_UINT(threshold, actual)                                          \
    UNITYCR_U((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_UINT_MESSAGE(threshold, actual, message)                         \
    UNITYCR_U((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_UINT8(threshold, actual)                                         \
    UNITYCR_U8((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_UINT8_MESSAGE(threshold, actual, message)                        \
    UNITYCR_U8((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_UINT16(threshold, actual)                                        \
    UNITYCR_U16((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_UINT16_MESSAGE(threshold, actual, message)                       \
    UNITYCR_U16((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_UINT32(threshold, actual)                                        \
    UNITYCR_U32((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_UINT32_MESSAGE(threshold, actual, message)                       \
    UNITYCR_U32((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_UINT64(threshold, actual)                                        \
    UNITYCR_U((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_UINT64_MESSAGE(threshold, actual, message)                       \
    UNITYCR_U((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_HEX(threshold, actual)                                           \
    UNITYCR_H32((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_HEX_MESSAGE(threshold, actual, message)                          \
    UNITYCR_H32((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_HEX8(threshold, actual)                                          \
    UNITYCR_H8((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_HEX8_MESSAGE(threshold, actual, message)                         \
    UNITYCR_H8((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_HEX16(threshold, actual)                                         \
    UNITYCR_H16((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_HEX16_MESSAGE(threshold, actual, message)                        \
    UNITYCR_H16((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_HEX32(threshold, actual)                                         \
    UNITYCR_H32((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_HEX32_MESSAGE(threshold, actual, message)                        \
    UNITYCR_H32((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_HEX64(threshold, actual)                                         \
    UNITYCR_H64((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_HEX64_MESSAGE(threshold, actual, message)                        \
    UNITYCR_H64((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_size_t(threshold, actual)                                        \
    UNITYCR_U((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_size_t_MESSAGE(threshold, actual, message)                       \
    UNITYCR_U((threshold), (actual), UNITYCR_LE, (message))

/* WITHIN: (delta, expected, actual); passes when |actual - expected| <= delta */
#define UNITYCR_IW(d, e, a, m)                                                                     \
    UnityCR_IntWithin((uint64_t)(d), (int64_t)(e), (int64_t)(a), (m), __LINE__)
#define UNITYCR_UW(d, e, a, m)                                                                     \
    UnityCR_UintWithin((uint64_t)(d), (uint64_t)(e), (uint64_t)(a), (m), __LINE__)

#define TEST_ASSERT_INT_WITHIN(delta, expected, actual)                                            \
    UNITYCR_IW((delta), (expected), (actual), NULL)
#define TEST_ASSERT_INT_WITHIN_MESSAGE(delta, expected, actual, message)                           \
    UNITYCR_IW((delta), (expected), (actual), (message))
#define TEST_ASSERT_INT8_WITHIN(delta, expected, actual)                                           \
    UNITYCR_IW((uint8_t)(delta), (int8_t)(expected), (int8_t)(actual), NULL)
#define TEST_ASSERT_INT8_WITHIN_MESSAGE(delta, expected, actual, message)                          \
    UNITYCR_IW((uint8_t)(delta), (int8_t)(expected), (int8_t)(actual), (message))
#define TEST_ASSERT_INT16_WITHIN(delta, expected, actual)                                          \
    UNITYCR_IW((uint16_t)(delta), (int16_t)(expected), (int16_t)(actual), NULL)
#define TEST_ASSERT_INT16_WITHIN_MESSAGE(delta, expected, actual, message)                         \
    UNITYCR_IW((uint16_t)(delta), (int16_t)(expected), (int16_t)(actual), (message))
#define TEST_ASSERT_INT32_WITHIN(delta, expected, actual)                                          \
    UNITYCR_IW((uint32_t)(delta), (int32_t)(expected), (int32_t)(actual), NULL)
#define TEST_ASSERT_INT32_WITHIN_MESSAGE(delta, expected, actual, message)                         \
    UNITYCR_IW((uint32_t)(delta), (int32_t)(expected), (int32_t)(actual), (message))
#define TEST_ASSERT_INT64_WITHIN(delta, expected, actual)                                          \
    UNITYCR_IW((delta), (expected), (actual), NULL)
#define TEST_ASSERT_INT64_WITHIN_MESSAGE(delta, expected, actual, message)                         \
    UNITYCR_IW((delta), (expected), (actual), (message))
#define TEST_ASSERT_UINT_WITHIN(delta, expected, actual)                                           \
    UNITYCR_UW((delta), (expected), (actual), NULL)
#define TEST_ASSERT_UINT_WITHIN_MESSAGE(delta, expected, actual, message)                          \
    UNITYCR_UW((delta), (expected), (actual), (message))
#define TEST_ASSERT_UINT8_WITHIN(delta, expected, actual)                                          \
    UNITYCR_UW((uint8_t)(delta), (uint8_t)(expected), (uint8_t)(actual), NULL)
#define TEST_ASSERT_UINT8_WITHIN_MESSAGE(delta, expected, actual, message)                         \
    UNITYCR_UW((uint8_t)(delta), (uint8_t)(expected), (uint8_t)(actual), (message))
#define TEST_ASSERT_UINT16_WITHIN(delta, expected, actual)                                         \
    UNITYCR_UW((uint16_t)(delta), (uint16_t)(expected), (uint16_t)(actual), NULL)
#define TEST_ASSERT_UINT16_WITHIN_MESSAGE(delta, expected, actual, message)                        \
    UNITYCR_UW((uint16_t)(delta), (uint16_t)(expected), (uint16_t)(actual), (message))
#define TEST_ASSERT_UINT32_WITHIN(delta, expected, actual)                                         \
    UNITYCR_UW((uint32_t)(delta), (uint32_t)(expected), (uint32_t)(actual), NULL)
#define TEST_ASSERT_UINT32_WITHIN_MESSAGE(delta, expected, actual, message)                        \
    UNITYCR_UW((uint32_t)(delta), (uint32_t)(expected), (uint32_t)(actual), (message))
#define TEST_ASSERT_UINT64_WITHIN(delta, expected, actual)                                         \
    UNITYCR_UW((delta), (expected), (actual), NULL)
#define TEST_ASSERT_UINT64_WITHIN_MESSAGE(delta, expected, actual, message)                        \
    UNITYCR_UW((delta), (expected), (actual), (message))

/* ---- strings, memory, integer arrays ----------------------------------- */

#define TEST_ASSERT_EQUAL_STRING(expected, actual)                                                 \
    UnityCR_String((const char *)(expected), (const char *)(actual), NULL, __LINE__)
#define TEST_ASSERT_EQUAL_STRING_MESSAGE(expected, actual, message)                                \
    UnityCR_String((const char *)(expected), (const char *)(actual), (message), __LINE__)
#define TEST_ASSERT_EQUAL_STRING_LEN(expected, actual, len)                                        \
    UnityCR_StringLen((const char *)(expected), (const char *)(actual), (uint32_t)(len), NULL,     \
                      __LINE__)
#define TEST_ASSERT_EQUAL_STRING_LEN_MESSAGE(expected, actual, len, message)                       \
    UnityCR_StringLen((const char *)(expected), (const char *)(actual), (uint32_t)(len),           \
                      (message), __LINE__)
#define TEST_ASSERT_EQUAL_MEMORY(expected, actual, len)                                            \
    UnityCR_Memory((const void *)(expected), (const void *)(actual), (uint32_t)(len), NULL,        \
                   __LINE__)
#define TEST_ASSERT_EQUAL_MEMORY_MESSAGE(expected, actual, len, message)                           \
    UnityCR_Memory((const void *)(expected), (const void *)(actual), (uint32_t)(len), (message),   \
                   __LINE__)
/* Elements are read as int. */
#define TEST_ASSERT_EQUAL_INT_ARRAY(expected, actual, num_elements)                                \
    UnityCR_IntArray((const void *)(expected), (const void *)(actual), (uint32_t)(num_elements),   \
                     NULL, __LINE__)
#define TEST_ASSERT_EQUAL_INT_ARRAY_MESSAGE(expected, actual, num_elements, message)               \
    UnityCR_IntArray((const void *)(expected), (const void *)(actual), (uint32_t)(num_elements),   \
                     (message), __LINE__)
/* Elements are read as uint8_t. */
#define TEST_ASSERT_EQUAL_UINT8_ARRAY(expected, actual, num_elements)                              \
    UnityCR_Uint8Array((const void *)(expected), (const void *)(actual), (uint32_t)(num_elements), \
                       NULL, __LINE__)
#define TEST_ASSERT_EQUAL_UINT8_ARRAY_MESSAGE(expected, actual, num_elements, message)             \
    UnityCR_Uint8Array((const void *)(expected), (const void *)(actual), (uint32_t)(num_elements), \
                       (message), __LINE__)

/* ---- float (UNITY_FLOAT) ----------------------------------------------- */
/* Scalars are converted to UNITY_FLOAT with explicit casts, so float or
 * double arguments are both accepted without conversion warnings.  Array
 * arguments must really be UNITY_FLOAT arrays: they are not cast. */

#define UNITYCR_F(x) ((UNITY_FLOAT)(x))
#define UNITYCR_FW(d, e, a, want, m)                                                               \
    UnityCR_FloatWithin(UNITYCR_F(d), UNITYCR_F(e), UNITYCR_F(a), (want), (m), __LINE__)
#define UNITYCR_FE(e, a, want, m)                                                                  \
    UnityCR_FloatEqual(UNITYCR_F(e), UNITYCR_F(a), (want), (m), __LINE__)
#define UNITYCR_FA(d, e, a, n, m)                                                                  \
    UnityCR_FloatArray(UNITYCR_F(d), (e), (a), (uint32_t)(n), (m), __LINE__)
#define UNITYCR_FO(t, a, op, m) UnityCR_FloatOrder(UNITYCR_F(t), UNITYCR_F(a), (op), (m), __LINE__)
#define UNITYCR_FT(a, trait, want, m)                                                              \
    UnityCR_FloatTrait(UNITYCR_F(a), (trait), (want), (m), __LINE__)

#define TEST_ASSERT_FLOAT_WITHIN(delta, expected, actual)                                          \
    UNITYCR_FW((delta), (expected), (actual), 1, NULL)
#define TEST_ASSERT_FLOAT_WITHIN_MESSAGE(delta, expected, actual, message)                         \
    UNITYCR_FW((delta), (expected), (actual), 1, (message))
#define TEST_ASSERT_FLOAT_NOT_WITHIN(delta, expected, actual)                                      \
    UNITYCR_FW((delta), (expected), (actual), 0, NULL)
#define TEST_ASSERT_FLOAT_NOT_WITHIN_MESSAGE(delta, expected, actual, message)                     \
    UNITYCR_FW((delta), (expected), (actual), 0, (message))
#define TEST_ASSERT_EQUAL_FLOAT(expected, actual) UNITYCR_FE((expected), (actual), 1, NULL)
#define TEST_ASSERT_EQUAL_FLOAT_MESSAGE(expected, actual, message)                                 \
    UNITYCR_FE((expected), (actual), 1, (message))
#define TEST_ASSERT_NOT_EQUAL_FLOAT(expected, actual) UNITYCR_FE((expected), (actual), 0, NULL)
#define TEST_ASSERT_NOT_EQUAL_FLOAT_MESSAGE(expected, actual, message)                             \
    UNITYCR_FE((expected), (actual), 0, (message))
#define TEST_ASSERT_FLOAT_ARRAY_WITHIN(delta, expected, actual, num_elements)                      \
    UNITYCR_FA((delta), (expected), (actual), (num_elements), NULL)
#define TEST_ASSERT_FLOAT_ARRAY_WITHIN_MESSAGE(delta, expected, actual, num_elements, message)     \
    UNITYCR_FA((delta), (expected), (actual), (num_elements), (message))
#define TEST_ASSERT_EQUAL_FLOAT_ARRAY(expected, actual, num_elements)                              \
    UNITYCR_FA(0, (expected), (actual), (num_elements), NULL)
#define TEST_ASSERT_EQUAL_FLOAT_ARRAY_MESSAGE(expected, actual, num_elements, message)             \
    UNITYCR_FA(0, (expected), (actual), (num_elements), (message))
#define TEST_ASSERT_LESS_THAN_FLOAT(threshold, actual)                                             \
    UNITYCR_FO((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_FLOAT_MESSAGE(threshold, actual, message)                            \
    UNITYCR_FO((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_GREATER_THAN_FLOAT(threshold, actual)                                          \
    UNITYCR_FO((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_FLOAT_MESSAGE(threshold, actual, message)                         \
    UNITYCR_FO((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_FLOAT(threshold, actual)                                         \
    UNITYCR_FO((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_FLOAT_MESSAGE(threshold, actual, message)                        \
    UNITYCR_FO((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_FLOAT(threshold, actual)                                      \
    UNITYCR_FO((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_FLOAT_MESSAGE(threshold, actual, message)                     \
    UNITYCR_FO((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_FLOAT_IS_INF(actual) UNITYCR_FT((actual), UNITYCR_INF, 1, NULL)
#define TEST_ASSERT_FLOAT_IS_INF_MESSAGE(actual, message)                                          \
    UNITYCR_FT((actual), UNITYCR_INF, 1, (message))
#define TEST_ASSERT_FLOAT_IS_NEG_INF(actual) UNITYCR_FT((actual), UNITYCR_NEG_INF, 1, NULL)
#define TEST_ASSERT_FLOAT_IS_NEG_INF_MESSAGE(actual, message)                                      \
    UNITYCR_FT((actual), UNITYCR_NEG_INF, 1, (message))
#define TEST_ASSERT_FLOAT_IS_NAN(actual) UNITYCR_FT((actual), UNITYCR_NAN, 1, NULL)
#define TEST_ASSERT_FLOAT_IS_NAN_MESSAGE(actual, message)                                          \
    UNITYCR_FT((actual), UNITYCR_NAN, 1, (message))
#define TEST_ASSERT_FLOAT_IS_DETERMINATE(actual) UNITYCR_FT((actual), UNITYCR_DETERMINATE, 1, NULL)
#define TEST_ASSERT_FLOAT_IS_DETERMINATE_MESSAGE(actual, message)                                  \
    UNITYCR_FT((actual), UNITYCR_DETERMINATE, 1, (message))
#define TEST_ASSERT_FLOAT_IS_NOT_INF(actual) UNITYCR_FT((actual), UNITYCR_INF, 0, NULL)
#define TEST_ASSERT_FLOAT_IS_NOT_INF_MESSAGE(actual, message)                                      \
    UNITYCR_FT((actual), UNITYCR_INF, 0, (message))
#define TEST_ASSERT_FLOAT_IS_NOT_NEG_INF(actual) UNITYCR_FT((actual), UNITYCR_NEG_INF, 0, NULL)
#define TEST_ASSERT_FLOAT_IS_NOT_NEG_INF_MESSAGE(actual, message)                                  \
    UNITYCR_FT((actual), UNITYCR_NEG_INF, 0, (message))
#define TEST_ASSERT_FLOAT_IS_NOT_NAN(actual) UNITYCR_FT((actual), UNITYCR_NAN, 0, NULL)
#define TEST_ASSERT_FLOAT_IS_NOT_NAN_MESSAGE(actual, message)                                      \
    UNITYCR_FT((actual), UNITYCR_NAN, 0, (message))
#define TEST_ASSERT_FLOAT_IS_NOT_DETERMINATE(actual)                                               \
    UNITYCR_FT((actual), UNITYCR_DETERMINATE, 0, NULL)
#define TEST_ASSERT_FLOAT_IS_NOT_DETERMINATE_MESSAGE(actual, message)                              \
    UNITYCR_FT((actual), UNITYCR_DETERMINATE, 0, (message))

/* ---- double (UNITY_DOUBLE), only with UNITY_INCLUDE_DOUBLE -------------- */
/* Without UNITY_INCLUDE_DOUBLE every double assertion fails with
 * "Unity Double Precision Disabled".  Its arguments are still evaluated
 * once and discarded, so they do not become unused variables. */

#if defined(UNITY_INCLUDE_DOUBLE) && !defined(UNITY_EXCLUDE_DOUBLE)
#define UNITYCR_D(x) ((UNITY_DOUBLE)(x))
#define UNITYCR_DW(d, e, a, want, m)                                                               \
    UnityCR_DoubleWithin(UNITYCR_D(d), UNITYCR_D(e), UNITYCR_D(a), (want), (m), __LINE__)
#define UNITYCR_DE(e, a, want, m)                                                                  \
    UnityCR_DoubleEqual(UNITYCR_D(e), UNITYCR_D(a), (want), (m), __LINE__)
#define UNITYCR_DA(d, e, a, n, m)                                                                  \
    UnityCR_DoubleArray(UNITYCR_D(d), (e), (a), (uint32_t)(n), (m), __LINE__)
#define UNITYCR_DO(t, a, op, m) UnityCR_DoubleOrder(UNITYCR_D(t), UNITYCR_D(a), (op), (m), __LINE__)
#define UNITYCR_DT(a, trait, want, m)                                                              \
    UnityCR_DoubleTrait(UNITYCR_D(a), (trait), (want), (m), __LINE__)
#else
#define UNITYCR_DOUBLE_OFF "Unity Double Precision Disabled"
#define UNITYCR_DW(d, e, a, want, m)                                                               \
    ((void)(d), (void)(e), (void)(a), (void)(m), UnityCR_Fail(UNITYCR_DOUBLE_OFF, __LINE__))
#define UNITYCR_DE(e, a, want, m)                                                                  \
    ((void)(e), (void)(a), (void)(m), UnityCR_Fail(UNITYCR_DOUBLE_OFF, __LINE__))
#define UNITYCR_DA(d, e, a, n, m)                                                                  \
    ((void)(d), (void)(e), (void)(a), (void)(n), (void)(m),                                        \
     UnityCR_Fail(UNITYCR_DOUBLE_OFF, __LINE__))
#define UNITYCR_DO(t, a, op, m)                                                                    \
    ((void)(t), (void)(a), (void)(m), UnityCR_Fail(UNITYCR_DOUBLE_OFF, __LINE__))
#define UNITYCR_DT(a, trait, want, m)                                                              \
    ((void)(a), (void)(m), UnityCR_Fail(UNITYCR_DOUBLE_OFF, __LINE__))
#endif

#define TEST_ASSERT_DOUBLE_WITHIN(delta, expected, actual)                                         \
    UNITYCR_DW((delta), (expected), (actual), 1, NULL)
#define TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(delta, expected, actual, message)                        \
    UNITYCR_DW((delta), (expected), (actual), 1, (message))
#define TEST_ASSERT_DOUBLE_NOT_WITHIN(delta, expected, actual)                                     \
    UNITYCR_DW((delta), (expected), (actual), 0, NULL)
#define TEST_ASSERT_DOUBLE_NOT_WITHIN_MESSAGE(delta, expected, actual, message)                    \
    UNITYCR_DW((delta), (expected), (actual), 0, (message))
#define TEST_ASSERT_EQUAL_DOUBLE(expected, actual) UNITYCR_DE((expected), (actual), 1, NULL)
#define TEST_ASSERT_EQUAL_DOUBLE_MESSAGE(expected, actual, message)                                \
    UNITYCR_DE((expected), (actual), 1, (message))
#define TEST_ASSERT_NOT_EQUAL_DOUBLE(expected, actual) UNITYCR_DE((expected), (actual), 0, NULL)
#define TEST_ASSERT_NOT_EQUAL_DOUBLE_MESSAGE(expected, actual, message)                            \
    UNITYCR_DE((expected), (actual), 0, (message))
#define TEST_ASSERT_DOUBLE_ARRAY_WITHIN(delta, expected, actual, num_elements)                     \
    UNITYCR_DA((delta), (expected), (actual), (num_elements), NULL)
#define TEST_ASSERT_DOUBLE_ARRAY_WITHIN_MESSAGE(delta, expected, actual, num_elements, message)    \
    UNITYCR_DA((delta), (expected), (actual), (num_elements), (message))
#define TEST_ASSERT_EQUAL_DOUBLE_ARRAY(expected, actual, num_elements)                             \
    UNITYCR_DA(0, (expected), (actual), (num_elements), NULL)
#define TEST_ASSERT_EQUAL_DOUBLE_ARRAY_MESSAGE(expected, actual, num_elements, message)            \
    UNITYCR_DA(0, (expected), (actual), (num_elements), (message))
#define TEST_ASSERT_LESS_THAN_DOUBLE(threshold, actual)                                            \
    UNITYCR_DO((threshold), (actual), UNITYCR_LT, NULL)
#define TEST_ASSERT_LESS_THAN_DOUBLE_MESSAGE(threshold, actual, message)                           \
    UNITYCR_DO((threshold), (actual), UNITYCR_LT, (message))
#define TEST_ASSERT_GREATER_THAN_DOUBLE(threshold, actual)                                         \
    UNITYCR_DO((threshold), (actual), UNITYCR_GT, NULL)
#define TEST_ASSERT_GREATER_THAN_DOUBLE_MESSAGE(threshold, actual, message)                        \
    UNITYCR_DO((threshold), (actual), UNITYCR_GT, (message))
#define TEST_ASSERT_LESS_OR_EQUAL_DOUBLE(threshold, actual)                                        \
    UNITYCR_DO((threshold), (actual), UNITYCR_LE, NULL)
#define TEST_ASSERT_LESS_OR_EQUAL_DOUBLE_MESSAGE(threshold, actual, message)                       \
    UNITYCR_DO((threshold), (actual), UNITYCR_LE, (message))
#define TEST_ASSERT_GREATER_OR_EQUAL_DOUBLE(threshold, actual)                                     \
    UNITYCR_DO((threshold), (actual), UNITYCR_GE, NULL)
#define TEST_ASSERT_GREATER_OR_EQUAL_DOUBLE_MESSAGE(threshold, actual, message)                    \
    UNITYCR_DO((threshold), (actual), UNITYCR_GE, (message))
#define TEST_ASSERT_DOUBLE_IS_INF(actual) UNITYCR_DT((actual), UNITYCR_INF, 1, NULL)
#define TEST_ASSERT_DOUBLE_IS_INF_MESSAGE(actual, message)                                         \
    UNITYCR_DT((actual), UNITYCR_INF, 1, (message))
#define TEST_ASSERT_DOUBLE_IS_NEG_INF(actual) UNITYCR_DT((actual), UNITYCR_NEG_INF, 1, NULL)
#define TEST_ASSERT_DOUBLE_IS_NEG_INF_MESSAGE(actual, message)                                     \
    UNITYCR_DT((actual), UNITYCR_NEG_INF, 1, (message))
#define TEST_ASSERT_DOUBLE_IS_NAN(actual) UNITYCR_DT((actual), UNITYCR_NAN, 1, NULL)
#define TEST_ASSERT_DOUBLE_IS_NAN_MESSAGE(actual, message)                                         \
    UNITYCR_DT((actual), UNITYCR_NAN, 1, (message))
#define TEST_ASSERT_DOUBLE_IS_DETERMINATE(actual) UNITYCR_DT((actual), UNITYCR_DETERMINATE, 1, NULL)
#define TEST_ASSERT_DOUBLE_IS_DETERMINATE_MESSAGE(actual, message)                                 \
    UNITYCR_DT((actual), UNITYCR_DETERMINATE, 1, (message))
#define TEST_ASSERT_DOUBLE_IS_NOT_INF(actual) UNITYCR_DT((actual), UNITYCR_INF, 0, NULL)
#define TEST_ASSERT_DOUBLE_IS_NOT_INF_MESSAGE(actual, message)                                     \
    UNITYCR_DT((actual), UNITYCR_INF, 0, (message))
#define TEST_ASSERT_DOUBLE_IS_NOT_NEG_INF(actual) UNITYCR_DT((actual), UNITYCR_NEG_INF, 0, NULL)
#define TEST_ASSERT_DOUBLE_IS_NOT_NEG_INF_MESSAGE(actual, message)                                 \
    UNITYCR_DT((actual), UNITYCR_NEG_INF, 0, (message))
#define TEST_ASSERT_DOUBLE_IS_NOT_NAN(actual) UNITYCR_DT((actual), UNITYCR_NAN, 0, NULL)
#define TEST_ASSERT_DOUBLE_IS_NOT_NAN_MESSAGE(actual, message)                                     \
    UNITYCR_DT((actual), UNITYCR_NAN, 0, (message))
#define TEST_ASSERT_DOUBLE_IS_NOT_DETERMINATE(actual)                                              \
    UNITYCR_DT((actual), UNITYCR_DETERMINATE, 0, NULL)
#define TEST_ASSERT_DOUBLE_IS_NOT_DETERMINATE_MESSAGE(actual, message)                             \
    UNITYCR_DT((actual), UNITYCR_DETERMINATE, 0, (message))

#endif /* UNITY_FRAMEWORK_H */
