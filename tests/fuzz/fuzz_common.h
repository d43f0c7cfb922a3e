/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_common.h
 * @brief What the libFuzzer targets share: a failing check that names the target and line, and a
 *        reader that turns the fuzz input into bytes, integers and raw reals (zeros once spent).
 *        Define FUZZ_NAME ("fuzz_csv", ...) before including it.
 */
#ifndef AENL_FUZZ_COMMON_H
#define AENL_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl/aenl_types.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/** Abort (a libFuzzer crash, input saved) with "<target>: <what> (line N)" on stderr. */
#define CHECK(cond, what)                                                                          \
    do                                                                                             \
    {                                                                                              \
        if (!(cond))                                                                               \
        {                                                                                          \
            fprintf(stderr, "%s: %s (line %d)\n", FUZZ_NAME, what, __LINE__);                      \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

/** The unread rest of the fuzz input. */
typedef struct
{
    const uint8_t *p;
    size_t n;
} input_t;

/** Next byte, 0 once the input is spent. */
static inline uint8_t take_u8(input_t *in)
{
    if (in->n == 0u)
    {
        return 0u;
    }
    const uint8_t v = in->p[0];
    in->p++;
    in->n--;
    return v;
}

/** Next two bytes, little-endian. */
static inline uint16_t take_u16(input_t *in)
{
    const uint16_t lo = take_u8(in);
    const uint16_t hi = take_u8(in);
    return (uint16_t)(lo | (uint16_t)(hi << 8));
}

/** Next sizeof(aenl_real_t) bytes as a real, bit for bit (any pattern: NaN, Inf, subnormal). */
static inline aenl_real_t take_raw_real(input_t *in)
{
    uint8_t b[sizeof(aenl_real_t)];
    aenl_real_t v;
    for (size_t i = 0; i < sizeof(b); ++i)
    {
        b[i] = take_u8(in);
    }
    memcpy(&v, b, sizeof(v));
    return v;
}

#endif /* AENL_FUZZ_COMMON_H */
