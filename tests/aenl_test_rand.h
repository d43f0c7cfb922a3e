/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_test_rand.h
 * @brief The host tests' random numbers: a 64-bit LCG whose state each test owns and seeds, so
 * a test's data are the same on every platform and independent of the library generator that
 * some of them test (aenl_rng).
 */
#ifndef AENL_TEST_RAND_H
#define AENL_TEST_RAND_H

#include <math.h>
#include <stdint.h>

/** Uniform in (0, 1) from the top 53 bits of the LCG at *s: never 0, so log() of it is finite. */
static inline double test_uniform(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return ((double)(*s >> 11) + 0.5) * (1.0 / 9007199254740992.0);
}

/** Uniform in [0, 1) from the top 53 bits: every multiple of 2^-53 below 1, 0 included. */
static inline double test_uniform0(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

/** Standard normal by Box and Muller (the cosine of the pair), from two uniforms in turn. */
static inline double test_gauss(uint64_t *s)
{
    const double u1 = test_uniform(s);
    const double u2 = test_uniform(s);
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586477 * u2);
}

#endif /* AENL_TEST_RAND_H */
