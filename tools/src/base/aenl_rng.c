/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_rng.c
 * @brief xoshiro256** + splitmix64 seeding, uniform and polar-method Gaussian (see aenl_rng.h).
 */
#include "aenl_tools/aenl_rng.h"

#include <math.h>

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += UINT64_C(0x9e3779b97f4a7c15));
    z = (z ^ (z >> 30)) * UINT64_C(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94d049bb133111eb);
    return z ^ (z >> 31);
}

void aenl_rng_seed(aenl_rng_t *rng, uint64_t seed)
{
    uint64_t x = seed;
    int i;
    for (i = 0; i < 4; ++i)
    {
        rng->s[i] = splitmix64(&x);
    }
    rng->spare = 0.0;
    rng->has_spare = 0;
}

uint64_t aenl_rng_next(aenl_rng_t *rng)
{
    uint64_t *s = rng->s;
    const uint64_t result = rotl(s[1] * 5U, 7) * 9U;
    const uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double aenl_rng_uniform(aenl_rng_t *rng)
{
    /* 2^-53 is exact; the 53-bit integer converts exactly. */
    return (double)(aenl_rng_next(rng) >> 11) * 0x1.0p-53;
}

double aenl_rng_log(double x)
{
    /* log x = e ln2 + 2 atanh(s), s = (m-1)/(m+1), m in [sqrt(1/2), sqrt(2)): |s| <= 0.1716,
     * s^2 <= 0.0295, so 13 odd terms of the atanh series reach s^27 ~ 1e-21 relative. */
    static const double ln2_hi = 6.93147180369123816490e-01; /* fdlibm split of ln 2 */
    static const double ln2_lo = 1.90821492927058770002e-10;
    double m, s, s2, poly;
    int e, k;
    if (!(x > 0.0))
    {
        return NAN;
    }
    if (isinf(x))
    {
        return x;
    }
    m = frexp(x, &e); /* x = m 2^e, m in [0.5, 1), exact */
    if (m < 0.70710678118654752440)
    {
        m *= 2.0;
        e -= 1;
    }
    s = (m - 1.0) / (m + 1.0);
    s2 = s * s;
    poly = 1.0 / 27.0;
    for (k = 12; k >= 0; --k)
    {
        poly = poly * s2 + 1.0 / (double)(2 * k + 1);
    }
    return (double)e * ln2_hi + ((double)e * ln2_lo + 2.0 * s * poly);
}

double aenl_rng_gauss(aenl_rng_t *rng)
{
    double u, v, s, f;
    if (rng->has_spare)
    {
        rng->has_spare = 0;
        return rng->spare;
    }
    do
    {
        u = 2.0 * aenl_rng_uniform(rng) - 1.0;
        v = 2.0 * aenl_rng_uniform(rng) - 1.0;
        s = u * u + v * v;
    } while (s >= 1.0 || !(s > 0.0));
    f = sqrt(-2.0 * aenl_rng_log(s) / s);
    rng->spare = v * f;
    rng->has_spare = 1;
    return u * f;
}
