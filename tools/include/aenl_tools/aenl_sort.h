/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sort.h
 * @brief Host helpers on sorted samples: an in-place sort of doubles, the qsort comparator of
 *        doubles and the interpolated quantile, shared by the bandwidth, curves, diagnose,
 *        identify and evaluation-suite modules.
 */
#ifndef AENL_TOOLS_SORT_H
#define AENL_TOOLS_SORT_H

#include <stddef.h>

/** qsort comparator of doubles, ascending (no NaN expected). */
int aenl_cmp_double(const void *a, const void *b);

/**
 * @brief Sorts v[0..n-1] ascending in place (no NaN expected): the values qsort with
 *        aenl_cmp_double puts in order, equal ones (-0 and +0 among them) in any order; several
 *        times faster (no comparison through a function pointer; introsort: quicksort on the
 *        median of three, insertion sort for short runs, heapsort when the partitions degrade,
 *        so O(n log n) at worst).
 */
void aenl_sort_doubles(double *v, size_t n);

/**
 * @brief Reorders v[0..n-1] (no NaN expected) so that v[k] is the value a sort puts there, none
 *        before it larger and none after it smaller (nothing when k >= n). O(n) on average,
 *        O(n log n) at worst.
 */
void aenl_select_doubles(double *v, size_t n, size_t k);

/**
 * @brief aenl_quantile_sorted's value (the same order statistics, the same interpolation) for
 *        unsorted v[0..n-1] (n >= 1), which it reorders: O(n) instead of a sort's O(n log n).
 */
double aenl_quantile_select(double *v, size_t n, double p);

/**
 * @brief The quantiles p[0..np-1] (each in [0, 1]) of the finite values of x[0..n-1], of which
 *        there are n_fin >= 1, into q: the values aenl_quantile_select gives on a copy holding
 *        them, bit for bit, without the copy and mostly in one pass (x is not changed). A
 *        sample of x brackets each quantile's two order statistics, one pass counts the values
 *        below each bracket and keeps those inside it, and they are selected among the kept;
 *        where a bracket misses (an unlucky sample, a short record) the quantile is selected
 *        on a copy. 0; -1 when memory lacks, or for more than 4 quantiles or n_fin 0.
 */
int aenl_quantiles_finite(const double *x, size_t n, size_t n_fin, const double *p, size_t np,
                          double *q);

/**
 * @brief Quantile p in [0, 1] of sorted s[0..n-1] (n >= 1) by linear interpolation between the
 *        order statistics at position (n - 1) p.
 */
double aenl_quantile_sorted(const double *s, size_t n, double p);

/**
 * @brief Median of v[0..n-1] (n >= 1) into *median and 1.4826 times its median absolute
 *        deviation into *sd: the standard deviation of a normal spread, unmoved by a few
 *        outliers. v is reordered (it holds the absolute deviations, in no order, on return).
 */
void aenl_median_mad(double *v, size_t n, double *median, double *sd);

#endif /* AENL_TOOLS_SORT_H */
