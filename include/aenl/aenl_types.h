/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_types.h
 * @brief Scalar type, literal macro, math wrappers and the status codes of the aenl core.
 *
 * One source builds twice: `float` for the MCU (AENL_USE_DOUBLE = 0) and `double` on the host.
 * Core code never calls sqrt/exp/log/fabs directly and never writes a bare floating literal:
 * it uses aenl_sqrt() etc. and AENL_R(), so no double arithmetic leaks into the float build.
 */
#ifndef AENL_TYPES_H
#define AENL_TYPES_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "aenl/aenl_config.h"

#if AENL_USE_DOUBLE
typedef double aenl_real_t;
#define AENL_R(x)     (x)
#define AENL_REAL_EPS 2.220446049250313e-16
#define AENL_REAL_MAX 1.7976931348623157e308
#else
typedef float aenl_real_t;
#define AENL_R(x)     (x##f)
#define AENL_REAL_EPS 1.1920929e-7f
#define AENL_REAL_MAX 3.40282347e38f
#endif

/** Square root in the build's precision. */
static inline aenl_real_t aenl_sqrt(aenl_real_t x)
{
#if AENL_USE_DOUBLE
    return sqrt(x);
#else
    return sqrtf(x);
#endif
}

/** Exponential in the build's precision. */
static inline aenl_real_t aenl_exp(aenl_real_t x)
{
#if AENL_USE_DOUBLE
    return exp(x);
#else
    return expf(x);
#endif
}

/** Natural logarithm in the build's precision. */
static inline aenl_real_t aenl_log(aenl_real_t x)
{
#if AENL_USE_DOUBLE
    return log(x);
#else
    return logf(x);
#endif
}

/** Absolute value in the build's precision. */
static inline aenl_real_t aenl_fabs(aenl_real_t x)
{
#if AENL_USE_DOUBLE
    return fabs(x);
#else
    return fabsf(x);
#endif
}

/** Round towards minus infinity, in the build's precision. */
static inline aenl_real_t aenl_floor(aenl_real_t x)
{
#if AENL_USE_DOUBLE
    return floor(x);
#else
    return floorf(x);
#endif
}

/** Round towards plus infinity, in the build's precision. */
static inline aenl_real_t aenl_ceil(aenl_real_t x)
{
#if AENL_USE_DOUBLE
    return ceil(x);
#else
    return ceilf(x);
#endif
}

/** Cosine in the build's precision. */
static inline aenl_real_t aenl_cos(aenl_real_t x)
{
#if AENL_USE_DOUBLE
    return cos(x);
#else
    return cosf(x);
#endif
}

/** Tangent in the build's precision. */
static inline aenl_real_t aenl_tan(aenl_real_t x)
{
#if AENL_USE_DOUBLE
    return tan(x);
#else
    return tanf(x);
#endif
}

/** 1 when x is neither NaN nor infinite. */
static inline int aenl_is_finite(aenl_real_t x)
{
    return isfinite(x) ? 1 : 0;
}

/**
 * Status of every core call: zero is success, negatives are errors. Test `!= AENL_OK`.
 * New codes may be added; callers should not rely on the list being closed.
 */
typedef enum
{
    AENL_OK = 0,         /**< success */
    AENL_E_ARG = -1,     /**< NULL or out-of-range argument; nothing was changed */
    AENL_E_DIM = -2,     /**< a size above a compile-time maximum; nothing was changed */
    AENL_E_EMPTY = -3,   /**< not enough data for this query yet */
    AENL_E_NOT_PD = -4,  /**< covariance not positive definite; previous estimate kept */
    AENL_E_NUMERIC = -5, /**< NaN/Inf received or produced */
    AENL_E_IO = -6       /**< file or stream failure (host tools only; the core never returns it) */
} aenl_status_t;

/**
 * @brief Constant name of a status code, e.g. "AENL_E_ARG".
 * @return a static string; "AENL_E_UNKNOWN" for a value outside the enum.
 * @note O(1), no allocation, no stdio.
 */
const char *aenl_status_str(aenl_status_t status);

#endif /* AENL_TYPES_H */
