/*
 * unity.c - clean-room test harness for the aenl test suite.
 *
 * Written by the aenl authors; no code or text from the ThrowTheSwitch
 * Unity project.  Implements the subset of the Unity API declared in
 * unity.h.  See README.md.
 */
#include "unity.h"

#include <math.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>

/* ---- configuration ----------------------------------------------------- */

#ifndef UNITY_OUTPUT_CHAR
#define UNITY_OUTPUT_CHAR(c) ((void)putchar(c))
#endif
#ifndef UNITY_OUTPUT_FLUSH
#define UNITY_OUTPUT_FLUSH() ((void)fflush(stdout))
#endif
/* EQUAL_FLOAT / EQUAL_DOUBLE accept |actual - expected| <= |expected| * precision. */
#ifndef UNITY_FLOAT_PRECISION
#define UNITY_FLOAT_PRECISION (0.00001f)
#endif
#ifndef UNITY_DOUBLE_PRECISION
#define UNITY_DOUBLE_PRECISION (1e-12)
#endif

/* Significant digits used when printing values in failure messages. */
#define UNITYCR_FLOAT_DIGITS  7
#define UNITYCR_DOUBLE_DIGITS 15

/* ---- run state --------------------------------------------------------- */

static struct
{
    const char *file;
    const char *name; /* current test, NULL outside RUN_TEST */
    UnityTestFunction func;
    int line; /* line of the RUN_TEST */
    unsigned long tests;
    unsigned long failures;
    unsigned long ignores;
    int in_test;
    int failed;
    int ignored;
    jmp_buf frame;
} ucr;

/* ---- output ------------------------------------------------------------ */

static void out_char(char c)
{
    UNITY_OUTPUT_CHAR(c);
}

static void out_str(const char *s)
{
    if (s == NULL)
    {
        return;
    }
    while (*s != '\0')
    {
        out_char(*s);
        s++;
    }
}

static void out_u64(uint64_t v)
{
    char buf[24];
    size_t n = 0;
    do
    {
        buf[n++] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0u);
    while (n > 0u)
    {
        n--;
        out_char(buf[n]);
    }
}

static void out_s64(int64_t v)
{
    if (v < 0)
    {
        out_char('-');
        /* Magnitude computed in unsigned arithmetic: safe for INT64_MIN. */
        out_u64((uint64_t)0 - (uint64_t)v);
    }
    else
    {
        out_u64((uint64_t)v);
    }
}

static void out_hex(uint64_t v, int digits)
{
    static const char hexdig[] = "0123456789ABCDEF";
    int shift;
    out_str("0x");
    for (shift = (digits - 1) * 4; shift >= 0; shift -= 4)
    {
        out_char(hexdig[(v >> shift) & 0xFu]);
    }
}

static void out_uint_fmt(uint64_t v, UnityCR_Fmt fmt)
{
    switch (fmt)
    {
        case UNITYCR_DEC:
            out_u64(v);
            break;
        case UNITYCR_HEX8:
            out_hex(v, 2);
            break;
        case UNITYCR_HEX16:
            out_hex(v, 4);
            break;
        case UNITYCR_HEX32:
            out_hex(v, 8);
            break;
        case UNITYCR_HEX64:
            out_hex(v, 16);
            break;
    }
}

static void out_real(double v, int digits)
{
    char buf[64];
    if (isnan(v))
    {
        out_str("NaN");
    }
    else if (isinf(v))
    {
        out_str(v < 0.0 ? "-Infinity" : "Infinity");
    }
    else
    {
        (void)snprintf(buf, sizeof buf, "%.*g", digits, v);
        out_str(buf);
    }
}

/* Prints a string in single quotes (at most max characters), escaping
 * control and non-ASCII bytes; a NULL pointer prints as NULL. */
static void out_quoted(const char *s, size_t max)
{
    static const char hexdig[] = "0123456789ABCDEF";
    size_t i;
    if (s == NULL)
    {
        out_str("NULL");
        return;
    }
    out_char('\'');
    for (i = 0; i < max && s[i] != '\0'; i++)
    {
        unsigned char c = (unsigned char)s[i];
        if (c == '\n')
        {
            out_str("\\n");
        }
        else if (c == '\r')
        {
            out_str("\\r");
        }
        else if (c == '\t')
        {
            out_str("\\t");
        }
        else if (c < 0x20u || c > 0x7Eu)
        {
            out_str("\\x");
            out_char(hexdig[c >> 4]);
            out_char(hexdig[c & 0xFu]);
        }
        else
        {
            out_char((char)c);
        }
    }
    out_char('\'');
}

/* "file:line:test_name:" */
static void out_prefix(int line)
{
    out_str(ucr.file);
    out_char(':');
    out_s64((int64_t)line);
    out_char(':');
    out_str(ucr.name);
    out_char(':');
}

/* ---- test control ------------------------------------------------------ */

/* Starts a failure line ("...:FAIL") and returns 1, or returns 0 when the
 * current test has already failed or been ignored: then nothing is printed
 * (only the first problem of a test is reported). */
static int fail_start(int line)
{
    if (ucr.in_test && (ucr.failed || ucr.ignored))
    {
        return 0;
    }
    out_prefix(line);
    out_str("FAIL");
    return 1;
}

/* Ends a failure: appends the user message, then leaves the test.
 * had_detail tells whether fail_start was followed by ": details". */
static void fail_finish(int printed, int had_detail, const char *message)
{
    if (printed)
    {
        if (message != NULL && message[0] != '\0')
        {
            out_str(had_detail ? ". " : ": ");
            out_str(message);
        }
        out_char('\n');
    }
    if (ucr.in_test)
    {
        ucr.failed = 1;
        longjmp(ucr.frame, 1);
    }
    /* Assertion outside RUN_TEST: count it, nothing to abort. */
    ucr.failures++;
}

/* Shorthand for a failure whose whole detail is one fixed text. */
static void fail_text(const char *what, const char *message, int line)
{
    int printed = fail_start(line);
    if (printed)
    {
        out_str(": ");
        out_str(what);
    }
    fail_finish(printed, 1, message);
}

void UnityCR_Begin(const char *file)
{
    ucr.file = file;
    ucr.name = NULL;
    ucr.func = NULL;
    ucr.line = 0;
    ucr.tests = 0;
    ucr.failures = 0;
    ucr.ignores = 0;
    ucr.in_test = 0;
    ucr.failed = 0;
    ucr.ignored = 0;
}

int UnityCR_End(void)
{
    out_str("\n-----------------------\n");
    out_u64((uint64_t)ucr.tests);
    out_str(" Tests ");
    out_u64((uint64_t)ucr.failures);
    out_str(" Failures ");
    out_u64((uint64_t)ucr.ignores);
    out_str(" Ignored \n");
    out_str(ucr.failures == 0u ? "OK\n" : "FAIL\n");
    UNITY_OUTPUT_FLUSH();
    return (int)ucr.failures;
}

void UnityCR_Run(UnityTestFunction func, const char *name, int line)
{
    /* Only static storage is used across setjmp/longjmp. */
    ucr.func = func;
    ucr.name = name;
    ucr.line = line;
    ucr.failed = 0;
    ucr.ignored = 0;
    ucr.in_test = 1;
    ucr.tests++;
    if (setjmp(ucr.frame) == 0)
    {
        setUp();
        ucr.func();
    }
    /* tearDown runs whatever happened above, and may itself abort. */
    if (setjmp(ucr.frame) == 0)
    {
        tearDown();
    }
    ucr.in_test = 0;
    if (ucr.failed)
    {
        ucr.failures++;
    }
    else if (ucr.ignored)
    {
        ucr.ignores++;
    }
    else
    {
        out_prefix(ucr.line);
        out_str("PASS\n");
    }
    ucr.name = NULL;
    UNITY_OUTPUT_FLUSH();
}

void UnityCR_Fail(const char *message, int line)
{
    fail_finish(fail_start(line), 0, message);
}

void UnityCR_Ignore(const char *message, int line)
{
    if (!ucr.in_test)
    {
        return;
    }
    if (!ucr.failed && !ucr.ignored)
    {
        out_prefix(line);
        out_str("IGNORE");
        if (message != NULL && message[0] != '\0')
        {
            out_str(": ");
            out_str(message);
        }
        out_char('\n');
        ucr.ignored = 1;
    }
    longjmp(ucr.frame, 1);
}

void UnityCR_Pass(void)
{
    if (ucr.in_test)
    {
        longjmp(ucr.frame, 1);
    }
}

void UnityCR_Message(const char *message, int line)
{
    out_prefix(line);
    out_str("INFO");
    if (message != NULL && message[0] != '\0')
    {
        out_str(": ");
        out_str(message);
    }
    out_char('\n');
}

void UnityCR_Check(int ok, const char *what, const char *message, int line)
{
    if (!ok)
    {
        fail_text(what, message, line);
    }
}

/* ---- integers ---------------------------------------------------------- */

static const char *op_words(UnityCR_Op op)
{
    switch (op)
    {
        case UNITYCR_EQ:
            return " to be equal to ";
        case UNITYCR_NE:
            return " to be not equal to ";
        case UNITYCR_GT:
            return " to be greater than ";
        case UNITYCR_GE:
            return " to be greater or equal to ";
        case UNITYCR_LT:
            return " to be less than ";
        case UNITYCR_LE:
            return " to be less or equal to ";
    }
    return " ? ";
}

/* cmp: -1, 0 or 1 for actual below, equal to or above the reference. */
static int op_holds(int cmp, UnityCR_Op op)
{
    switch (op)
    {
        case UNITYCR_EQ:
            return cmp == 0;
        case UNITYCR_NE:
            return cmp != 0;
        case UNITYCR_GT:
            return cmp > 0;
        case UNITYCR_GE:
            return cmp >= 0;
        case UNITYCR_LT:
            return cmp < 0;
        case UNITYCR_LE:
            return cmp <= 0;
    }
    return 0;
}

void UnityCR_CmpInt(int64_t ref, int64_t actual, UnityCR_Op op, const char *message, int line)
{
    int cmp = (actual < ref) ? -1 : ((actual > ref) ? 1 : 0);
    if (!op_holds(cmp, op))
    {
        int printed = fail_start(line);
        if (printed)
        {
            out_str(": Expected ");
            if (op == UNITYCR_EQ)
            {
                out_s64(ref);
                out_str(" Was ");
                out_s64(actual);
            }
            else
            {
                out_s64(actual);
                out_str(op_words(op));
                out_s64(ref);
            }
        }
        fail_finish(printed, 1, message);
    }
}

void UnityCR_CmpUint(uint64_t ref, uint64_t actual, UnityCR_Op op, UnityCR_Fmt fmt,
                     const char *message, int line)
{
    int cmp = (actual < ref) ? -1 : ((actual > ref) ? 1 : 0);
    if (!op_holds(cmp, op))
    {
        int printed = fail_start(line);
        if (printed)
        {
            out_str(": Expected ");
            if (op == UNITYCR_EQ)
            {
                out_uint_fmt(ref, fmt);
                out_str(" Was ");
                out_uint_fmt(actual, fmt);
            }
            else
            {
                out_uint_fmt(actual, fmt);
                out_str(op_words(op));
                out_uint_fmt(ref, fmt);
            }
        }
        fail_finish(printed, 1, message);
    }
}

void UnityCR_IntWithin(uint64_t delta, int64_t expected, int64_t actual, const char *message,
                       int line)
{
    /* Distance in unsigned arithmetic: exact even across the full range. */
    uint64_t diff = (actual > expected) ? (uint64_t)actual - (uint64_t)expected
                                        : (uint64_t)expected - (uint64_t)actual;
    if (diff > delta)
    {
        int printed = fail_start(line);
        if (printed)
        {
            out_str(": Values Not Within Delta ");
            out_u64(delta);
            out_str(" Expected ");
            out_s64(expected);
            out_str(" Was ");
            out_s64(actual);
        }
        fail_finish(printed, 1, message);
    }
}

void UnityCR_UintWithin(uint64_t delta, uint64_t expected, uint64_t actual, const char *message,
                        int line)
{
    uint64_t diff = (actual > expected) ? actual - expected : expected - actual;
    if (diff > delta)
    {
        int printed = fail_start(line);
        if (printed)
        {
            out_str(": Values Not Within Delta ");
            out_u64(delta);
            out_str(" Expected ");
            out_u64(expected);
            out_str(" Was ");
            out_u64(actual);
        }
        fail_finish(printed, 1, message);
    }
}

/* ---- strings, memory, arrays ------------------------------------------- */

static void fail_strings(const char *expected, const char *actual, size_t max, const char *message,
                         int line)
{
    int printed = fail_start(line);
    if (printed)
    {
        out_str(": Expected ");
        out_quoted(expected, max);
        out_str(" Was ");
        out_quoted(actual, max);
    }
    fail_finish(printed, 1, message);
}

void UnityCR_String(const char *expected, const char *actual, const char *message, int line)
{
    int same;
    if (expected == NULL || actual == NULL)
    {
        same = (expected == actual);
    }
    else
    {
        same = (strcmp(expected, actual) == 0);
    }
    if (!same)
    {
        fail_strings(expected, actual, SIZE_MAX, message, line);
    }
}

void UnityCR_StringLen(const char *expected, const char *actual, uint32_t len, const char *message,
                       int line)
{
    int same = 1;
    if (expected == NULL || actual == NULL)
    {
        same = (expected == actual);
    }
    else
    {
        uint32_t i;
        for (i = 0; i < len; i++)
        {
            if (expected[i] != actual[i])
            {
                same = 0;
                break;
            }
            if (expected[i] == '\0')
            {
                break;
            }
        }
    }
    if (!same)
    {
        fail_strings(expected, actual, (size_t)len, message, line);
    }
}

/* Common checks for array-like assertions.  Returns 1 when the elements
 * still need comparing, 0 when the assertion has passed already; fails
 * (and leaves the test) for an empty range or a single NULL pointer. */
static int range_check(const void *expected, const void *actual, uint32_t count,
                       const char *message, int line)
{
    if (count == 0u)
    {
        fail_text("You asked to compare nothing (length 0)", message, line);
        return 0;
    }
    if (expected == actual)
    {
        return 0;
    }
    if (expected == NULL)
    {
        fail_text("Expected pointer is NULL", message, line);
        return 0;
    }
    if (actual == NULL)
    {
        fail_text("Actual pointer is NULL", message, line);
        return 0;
    }
    return 1;
}

static void out_element(uint32_t index)
{
    out_str(": Element ");
    out_u64((uint64_t)index);
}

void UnityCR_Memory(const void *expected, const void *actual, uint32_t len, const char *message,
                    int line)
{
    const unsigned char *e = (const unsigned char *)expected;
    const unsigned char *a = (const unsigned char *)actual;
    uint32_t i;
    if (!range_check(expected, actual, len, message, line))
    {
        return;
    }
    for (i = 0; i < len; i++)
    {
        if (e[i] != a[i])
        {
            int printed = fail_start(line);
            if (printed)
            {
                out_str(": Memory Mismatch. Byte ");
                out_u64((uint64_t)i);
                out_str(" Expected ");
                out_hex((uint64_t)e[i], 2);
                out_str(" Was ");
                out_hex((uint64_t)a[i], 2);
            }
            fail_finish(printed, 1, message);
            return;
        }
    }
}

void UnityCR_IntArray(const void *expected, const void *actual, uint32_t count, const char *message,
                      int line)
{
    const int *e = (const int *)expected;
    const int *a = (const int *)actual;
    uint32_t i;
    if (!range_check(expected, actual, count, message, line))
    {
        return;
    }
    for (i = 0; i < count; i++)
    {
        if (e[i] != a[i])
        {
            int printed = fail_start(line);
            if (printed)
            {
                out_element(i);
                out_str(" Expected ");
                out_s64((int64_t)e[i]);
                out_str(" Was ");
                out_s64((int64_t)a[i]);
            }
            fail_finish(printed, 1, message);
            return;
        }
    }
}

void UnityCR_Uint8Array(const void *expected, const void *actual, uint32_t count,
                        const char *message, int line)
{
    const uint8_t *e = (const uint8_t *)expected;
    const uint8_t *a = (const uint8_t *)actual;
    uint32_t i;
    if (!range_check(expected, actual, count, message, line))
    {
        return;
    }
    for (i = 0; i < count; i++)
    {
        if (e[i] != a[i])
        {
            int printed = fail_start(line);
            if (printed)
            {
                out_element(i);
                out_str(" Expected ");
                out_u64((uint64_t)e[i]);
                out_str(" Was ");
                out_u64((uint64_t)a[i]);
            }
            fail_finish(printed, 1, message);
            return;
        }
    }
}

/* ---- floating point ----------------------------------------------------- */
/*
 * "within" rule, shared by float and double (see README.md):
 *   both NaN                         -> within
 *   both infinite with the same sign -> within
 *   otherwise within iff |actual - expected| <= |delta|, so any NaN or
 *   infinite difference, and a NaN delta, are never within.
 * Equality is "within |expected| * precision".
 */

static const char *trait_name(UnityCR_Trait trait)
{
    switch (trait)
    {
        case UNITYCR_INF:
            return "Infinity";
        case UNITYCR_NEG_INF:
            return "Negative Infinity";
        case UNITYCR_NAN:
            return "NaN";
        case UNITYCR_DETERMINATE:
            return "Determinate";
    }
    return "?";
}

static void fail_reals(const char *lead, double expected, double actual, int digits,
                       const char *message, int line)
{
    int printed = fail_start(line);
    if (printed)
    {
        out_str(lead);
        out_real(expected, digits);
        out_str(" Was ");
        out_real(actual, digits);
    }
    fail_finish(printed, 1, message);
}

static void fail_real_order(double threshold, double actual, UnityCR_Op op, int digits,
                            const char *message, int line)
{
    int printed = fail_start(line);
    if (printed)
    {
        out_str(": Expected ");
        out_real(actual, digits);
        out_str(op_words(op));
        out_real(threshold, digits);
    }
    fail_finish(printed, 1, message);
}

static void fail_real_trait(double actual, UnityCR_Trait trait, int want, int digits,
                            const char *message, int line)
{
    int printed = fail_start(line);
    if (printed)
    {
        out_str(": Expected ");
        out_str(want ? "" : "Not ");
        out_str(trait_name(trait));
        out_str(" Was ");
        out_real(actual, digits);
    }
    fail_finish(printed, 1, message);
}

/* -- float -- */

static UNITY_FLOAT float_abs(UNITY_FLOAT v)
{
    return (v < (UNITY_FLOAT)0) ? -v : v;
}

static int float_within(UNITY_FLOAT delta, UNITY_FLOAT expected, UNITY_FLOAT actual)
{
    UNITY_FLOAT diff;
    if (isnan(expected) && isnan(actual))
    {
        return 1;
    }
    if (isinf(expected) && isinf(actual))
    {
        return (expected < (UNITY_FLOAT)0) == (actual < (UNITY_FLOAT)0);
    }
    diff = float_abs(actual - expected);
    if (isnan(diff) || isinf(diff))
    {
        return 0;
    }
    return diff <= float_abs(delta);
}

static UNITY_FLOAT float_tolerance(UNITY_FLOAT expected)
{
    return float_abs(expected * (UNITY_FLOAT)(UNITY_FLOAT_PRECISION));
}

void UnityCR_FloatWithin(UNITY_FLOAT delta, UNITY_FLOAT expected, UNITY_FLOAT actual,
                         int want_within, const char *message, int line)
{
    if (float_within(delta, expected, actual) != (want_within != 0))
    {
        int printed = fail_start(line);
        if (printed)
        {
            out_str(want_within ? ": Values Not Within Delta " : ": Values Within Delta ");
            out_real((double)delta, UNITYCR_FLOAT_DIGITS);
            out_str(" Expected ");
            out_real((double)expected, UNITYCR_FLOAT_DIGITS);
            out_str(" Was ");
            out_real((double)actual, UNITYCR_FLOAT_DIGITS);
        }
        fail_finish(printed, 1, message);
    }
}

void UnityCR_FloatEqual(UNITY_FLOAT expected, UNITY_FLOAT actual, int want_equal,
                        const char *message, int line)
{
    if (float_within(float_tolerance(expected), expected, actual) != (want_equal != 0))
    {
        fail_reals(want_equal ? ": Expected " : ": Expected Not-Equal to ", (double)expected,
                   (double)actual, UNITYCR_FLOAT_DIGITS, message, line);
    }
}

void UnityCR_FloatArray(UNITY_FLOAT delta, const UNITY_FLOAT *expected, const UNITY_FLOAT *actual,
                        uint32_t count, const char *message, int line)
{
    uint32_t i;
    if (!range_check(expected, actual, count, message, line))
    {
        return;
    }
    for (i = 0; i < count; i++)
    {
        UNITY_FLOAT tol = float_abs(delta) + float_tolerance(expected[i]);
        if (!float_within(tol, expected[i], actual[i]))
        {
            int printed = fail_start(line);
            if (printed)
            {
                out_element(i);
                out_str(" Expected ");
                out_real((double)expected[i], UNITYCR_FLOAT_DIGITS);
                out_str(" Was ");
                out_real((double)actual[i], UNITYCR_FLOAT_DIGITS);
            }
            fail_finish(printed, 1, message);
            return;
        }
    }
}

void UnityCR_FloatOrder(UNITY_FLOAT threshold, UNITY_FLOAT actual, UnityCR_Op op,
                        const char *message, int line)
{
    int ok;
    int equal = float_within(float_tolerance(threshold), threshold, actual);
    switch (op)
    {
        case UNITYCR_GT:
            ok = actual > threshold;
            break;
        case UNITYCR_LT:
            ok = actual < threshold;
            break;
        case UNITYCR_GE:
            ok = (actual > threshold) || equal;
            break;
        case UNITYCR_LE:
            ok = (actual < threshold) || equal;
            break;
        case UNITYCR_EQ:
            ok = equal;
            break;
        case UNITYCR_NE:
            ok = !equal;
            break;
        default:
            ok = 0;
            break;
    }
    if (!ok)
    {
        fail_real_order((double)threshold, (double)actual, op, UNITYCR_FLOAT_DIGITS, message, line);
    }
}

void UnityCR_FloatTrait(UNITY_FLOAT actual, UnityCR_Trait trait, int want, const char *message,
                        int line)
{
    int has;
    switch (trait)
    {
        case UNITYCR_INF:
            has = isinf(actual) && actual > (UNITY_FLOAT)0;
            break;
        case UNITYCR_NEG_INF:
            has = isinf(actual) && actual < (UNITY_FLOAT)0;
            break;
        case UNITYCR_NAN:
            has = isnan(actual) ? 1 : 0;
            break;
        case UNITYCR_DETERMINATE:
            has = isfinite(actual) ? 1 : 0;
            break;
        default:
            has = 0;
            break;
    }
    if (has != (want != 0))
    {
        fail_real_trait((double)actual, trait, want, UNITYCR_FLOAT_DIGITS, message, line);
    }
}

/* -- double (always built; unity.h decides whether the macros use it) -- */

static UNITY_DOUBLE double_abs(UNITY_DOUBLE v)
{
    return (v < (UNITY_DOUBLE)0) ? -v : v;
}

static int double_within(UNITY_DOUBLE delta, UNITY_DOUBLE expected, UNITY_DOUBLE actual)
{
    UNITY_DOUBLE diff;
    if (isnan(expected) && isnan(actual))
    {
        return 1;
    }
    if (isinf(expected) && isinf(actual))
    {
        return (expected < (UNITY_DOUBLE)0) == (actual < (UNITY_DOUBLE)0);
    }
    diff = double_abs(actual - expected);
    if (isnan(diff) || isinf(diff))
    {
        return 0;
    }
    return diff <= double_abs(delta);
}

static UNITY_DOUBLE double_tolerance(UNITY_DOUBLE expected)
{
    return double_abs(expected * (UNITY_DOUBLE)(UNITY_DOUBLE_PRECISION));
}

void UnityCR_DoubleWithin(UNITY_DOUBLE delta, UNITY_DOUBLE expected, UNITY_DOUBLE actual,
                          int want_within, const char *message, int line)
{
    if (double_within(delta, expected, actual) != (want_within != 0))
    {
        int printed = fail_start(line);
        if (printed)
        {
            out_str(want_within ? ": Values Not Within Delta " : ": Values Within Delta ");
            out_real((double)delta, UNITYCR_DOUBLE_DIGITS);
            out_str(" Expected ");
            out_real((double)expected, UNITYCR_DOUBLE_DIGITS);
            out_str(" Was ");
            out_real((double)actual, UNITYCR_DOUBLE_DIGITS);
        }
        fail_finish(printed, 1, message);
    }
}

void UnityCR_DoubleEqual(UNITY_DOUBLE expected, UNITY_DOUBLE actual, int want_equal,
                         const char *message, int line)
{
    if (double_within(double_tolerance(expected), expected, actual) != (want_equal != 0))
    {
        fail_reals(want_equal ? ": Expected " : ": Expected Not-Equal to ", (double)expected,
                   (double)actual, UNITYCR_DOUBLE_DIGITS, message, line);
    }
}

void UnityCR_DoubleArray(UNITY_DOUBLE delta, const UNITY_DOUBLE *expected,
                         const UNITY_DOUBLE *actual, uint32_t count, const char *message, int line)
{
    uint32_t i;
    if (!range_check(expected, actual, count, message, line))
    {
        return;
    }
    for (i = 0; i < count; i++)
    {
        UNITY_DOUBLE tol = double_abs(delta) + double_tolerance(expected[i]);
        if (!double_within(tol, expected[i], actual[i]))
        {
            int printed = fail_start(line);
            if (printed)
            {
                out_element(i);
                out_str(" Expected ");
                out_real((double)expected[i], UNITYCR_DOUBLE_DIGITS);
                out_str(" Was ");
                out_real((double)actual[i], UNITYCR_DOUBLE_DIGITS);
            }
            fail_finish(printed, 1, message);
            return;
        }
    }
}

void UnityCR_DoubleOrder(UNITY_DOUBLE threshold, UNITY_DOUBLE actual, UnityCR_Op op,
                         const char *message, int line)
{
    int ok;
    int equal = double_within(double_tolerance(threshold), threshold, actual);
    switch (op)
    {
        case UNITYCR_GT:
            ok = actual > threshold;
            break;
        case UNITYCR_LT:
            ok = actual < threshold;
            break;
        case UNITYCR_GE:
            ok = (actual > threshold) || equal;
            break;
        case UNITYCR_LE:
            ok = (actual < threshold) || equal;
            break;
        case UNITYCR_EQ:
            ok = equal;
            break;
        case UNITYCR_NE:
            ok = !equal;
            break;
        default:
            ok = 0;
            break;
    }
    if (!ok)
    {
        fail_real_order((double)threshold, (double)actual, op, UNITYCR_DOUBLE_DIGITS, message,
                        line);
    }
}

void UnityCR_DoubleTrait(UNITY_DOUBLE actual, UnityCR_Trait trait, int want, const char *message,
                         int line)
{
    int has;
    switch (trait)
    {
        case UNITYCR_INF:
            has = isinf(actual) && actual > (UNITY_DOUBLE)0;
            break;
        case UNITYCR_NEG_INF:
            has = isinf(actual) && actual < (UNITY_DOUBLE)0;
            break;
        case UNITYCR_NAN:
            has = isnan(actual) ? 1 : 0;
            break;
        case UNITYCR_DETERMINATE:
            has = isfinite(actual) ? 1 : 0;
            break;
        default:
            has = 0;
            break;
    }
    if (has != (want != 0))
    {
        fail_real_trait((double)actual, trait, want, UNITYCR_DOUBLE_DIGITS, message, line);
    }
}
