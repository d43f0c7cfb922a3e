/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_rng.h
 * @brief Host-only portable seeded random numbers: xoshiro256** integers, uniform doubles and
 *        standard Gaussian deviates that are bit-identical on every IEEE-754 machine.
 *
 * Memory: the caller owns an aenl_rng_t (40 bytes); no allocation. Threading: none; one
 * generator per thread.
 *
 * Why these choices:
 *  - Integers: xoshiro256** (Blackman & Vigna 2018) seeded by expanding the 64-bit seed with
 *    splitmix64, exactly as the authors recommend. Only 64-bit integer arithmetic: identical
 *    everywhere by construction.
 *  - Uniform: the top 53 bits times 2^-53 (exact).
 *  - Gaussian: Marsaglia's polar method. Box-Muller needs cos/sin and the polar method needs log,
 *    and neither is correctly rounded in every libm, so the last bit could differ between
 *    machines. We therefore do not call libm's log: aenl_rng_log() evaluates log with frexp
 *    (exact), +, -, *, / and a fixed atanh series, and the final scaling uses sqrt, which IEEE-754
 *    requires to be correctly rounded. The result is bit-reproducible wherever doubles are IEEE
 *    binary64 evaluated without excess precision (SSE2, AArch64, ...; not x87) and without
 *    contraction into FMA (the project builds with -std=c99, where GCC defaults to
 *    -ffp-contract=off). A ziggurat would also avoid log in its main path but still needs
 *    log/exp for the tail and large precomputed tables; the polar method is short and exact
 *    in its acceptance test.
 */
#ifndef AENL_TOOLS_RNG_H
#define AENL_TOOLS_RNG_H

#include <stdint.h>

/** Generator state. Fields are private. */
typedef struct aenl_rng
{
    uint64_t s[4]; /**< xoshiro256** state */
    double spare;  /**< second polar deviate, valid when has_spare */
    int has_spare;
} aenl_rng_t;

/** @brief Seed the generator (any 64-bit value, 0 included). Cannot fail. */
void aenl_rng_seed(aenl_rng_t *rng, uint64_t seed);

/** @brief Next 64-bit output of xoshiro256**. */
uint64_t aenl_rng_next(aenl_rng_t *rng);

/** @brief Uniform double in [0, 1) with 53 random bits. */
double aenl_rng_uniform(aenl_rng_t *rng);

/** @brief Standard normal deviate (mean 0, variance 1), portable to the last bit. */
double aenl_rng_gauss(aenl_rng_t *rng);

/**
 * @brief Natural logarithm from +, -, *, /, frexp only (see the file comment). Accurate to about
 *        1 ulp for finite x > 0; returns NaN for x <= 0 or NaN, +inf for +inf.
 */
double aenl_rng_log(double x);

#endif /* AENL_TOOLS_RNG_H */
