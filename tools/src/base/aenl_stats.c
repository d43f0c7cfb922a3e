/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_stats.c
 * @brief Chi-square tail probabilities through the regularised incomplete gamma function:
 *        the power series of P(a, z) below z = a + 1, where it converges fast, and the
 *        continued fraction of Q(a, z) above, evaluated by the modified Lentz method.
 */
#define _DEFAULT_SOURCE /* lgamma_r */

#include "aenl_tools/aenl_stats.h"

#include <float.h>
#include <math.h>

#define STATS_MAX_TERMS 10000
#define STATS_EPS       1e-15
#define STATS_TINY      1e-300

/* log of z^a e^-z / Gamma(a): the common factor of both expansions. lgamma_r, because lgamma
 * writes the process-wide signgam and the tests run on several threads at once. */
static double log_prefactor(double a, double z)
{
    int sign = 0;
    return a * log(z) - z - lgamma_r(a, &sign);
}

/* P(a, z) = z^a e^-z / Gamma(a) * sum_n z^n / (a (a+1) ... (a+n)). */
static double lower_series(double a, double z)
{
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < STATS_MAX_TERMS; ++n)
    {
        term *= z / (a + (double)n);
        sum += term;
        if (fabs(term) < fabs(sum) * STATS_EPS)
        {
            break;
        }
    }
    return sum * exp(log_prefactor(a, z));
}

/* Q(a, z) = z^a e^-z / Gamma(a) * 1 / (z + 1 - a - 1 (1 - a) / (z + 3 - a - 2 (2 - a) / ...)). */
static double upper_fraction(double a, double z)
{
    double b = z + 1.0 - a;
    double c = 1.0 / STATS_TINY;
    double d = 1.0 / b;
    double h = d;
    for (int n = 1; n < STATS_MAX_TERMS; ++n)
    {
        const double an = -(double)n * ((double)n - a);
        b += 2.0;
        d = an * d + b;
        if (fabs(d) < STATS_TINY)
        {
            d = STATS_TINY;
        }
        c = b + an / c;
        if (fabs(c) < STATS_TINY)
        {
            c = STATS_TINY;
        }
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (fabs(delta - 1.0) < STATS_EPS)
        {
            break;
        }
    }
    return exp(log_prefactor(a, z)) * h;
}

double aenl_chi2_sf(double x, double k)
{
    if (isnan(x) || isnan(k) || k <= 0.0)
    {
        return NAN;
    }
    if (x <= 0.0)
    {
        return 1.0;
    }
    if (isinf(x))
    {
        return 0.0;
    }
    const double a = 0.5 * k;
    const double z = 0.5 * x;
    if (z < a + 1.0)
    {
        const double p = lower_series(a, z);
        return p >= 1.0 ? 0.0 : 1.0 - p;
    }
    return upper_fraction(a, z);
}
