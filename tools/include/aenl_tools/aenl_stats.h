/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_stats.h
 * @brief Host-only: distribution functions the statistical tests need.
 */
#ifndef AENL_TOOLS_STATS_H
#define AENL_TOOLS_STATS_H

/**
 * @brief Upper tail of the chi-square distribution, P(X > x) for X ~ chi2(k): the regularised
 *        upper incomplete gamma function Q(k/2, x/2). Accurate to about 1e-14 relative where
 *        the result is above 1e-300. Returns 1 for x <= 0, NaN for k <= 0 or a NaN argument.
 */
double aenl_chi2_sf(double x, double k);

#endif /* AENL_TOOLS_STATS_H */
