/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_bandwidth.h
 * @brief Host-only: bandwidth of the triangular-kernel lag regression by exact leave-one-out
 *        cross-validation, with a normal-reference rule of thumb as fallback.
 *
 * The regression is the paper's formula (10) (its section 3.1): for a lag L the pairs are
 * (u_i, y_i) = (x_{i-L}, x_i), and m_L(u) = Σ_j y_j φ_h(u − u_j) / Σ_j φ_h(u − u_j) with the
 * triangular kernel φ_h(d) = (1 − |d|/h)/h for |d| < h, 0 otherwise. A pair with a non-finite
 * member (NaN gap, Inf) is skipped; time alignment is kept.
 *
 * Leave-one-out score of one lag:
 *     CV_L(h) = (1/N_used) Σ_i (y_i − m_{L,−i}(u_i))²,
 * where m_{L,−i} is the estimate without pair i. A pair with no other pair strictly within h of
 * u_i has no estimate (zero denominator): it is *excluded* and counted. The score of h over a set
 * of lags is the **mean** of the per-lag scores (so it stays on the scale of Var(x) whatever the
 * number of lags).
 *
 * Memory: the functions allocate (pairs sorted by u plus compensated prefix sums: about 64 bytes
 * per pair and lag) and free everything before returning, on every path. No global state; the
 * functions are re-entrant. Only the caller prints err.
 */
#ifndef AENL_TOOLS_BANDWIDTH_H
#define AENL_TOOLS_BANDWIDTH_H

#include <stddef.h>
#include <stdint.h>

#include "aenl_tools/aenl_io.h"

/** How the reported bandwidth was chosen (aenl_bw_result_t.method). */
enum aenl_bw_method
{
    AENL_BW_CV = 1,  /**< minimiser of the leave-one-out score */
    AENL_BW_RULE = 2 /**< normal-reference rule of thumb (fallback, or forced) */
};

/** Why the rule of thumb was used (aenl_bw_result_t.fallback). */
enum aenl_bw_fallback
{
    AENL_BW_FB_NONE = 0,         /**< CV was used */
    AENL_BW_FB_FORCED = 1,       /**< opts->force_rule */
    AENL_BW_FB_FEW_PAIRS = 2,    /**< a lag has fewer than opts->min_pairs usable pairs */
    AENL_BW_FB_INADMISSIBLE = 3, /**< no candidate h had few enough excluded pairs */
    AENL_BW_FB_NO_MINIMUM = 4    /**< the CV curve is flat or monotone over [h_lo, h_hi] */
};

/** Search options. Fill with aenl_bw_opts_default() and change what you need. */
typedef struct aenl_bw_opts
{
    double h_lo;              /**< smallest candidate (input units); 0 = automatic:
                                   max(4 × median spacing of the sorted samples, range/1000) */
    double h_hi;              /**< largest candidate; 0 = automatic: range/4 */
    size_t n_grid;            /**< log-spaced grid points in [h_lo, h_hi], >= 3 (default 20) */
    size_t max_refine;        /**< golden-section steps after the grid (default 30) */
    double refine_rel_tol;    /**< stop refining when the bracket is within (1 + tol) (1e-3) */
    size_t min_pairs;         /**< fewer usable pairs in any lag → rule of thumb (default 50) */
    double max_excluded_frac; /**< an h whose excluded fraction exceeds this is inadmissible
                                   (default 0.05) */
    int force_rule;           /**< 1: skip CV, return the rule of thumb (default 0) */
} aenl_bw_opts_t;

/** Outcome of aenl_bw_select(). */
typedef struct aenl_bw_result
{
    double h;            /**< the chosen bandwidth, always set on success (input units) */
    double score;        /**< mean-over-lags LOO score at h; NaN when not computable there */
    int method;          /**< AENL_BW_CV or AENL_BW_RULE */
    int fallback;        /**< enum aenl_bw_fallback: why the rule was used (0 with CV) */
    size_t n_pairs;      /**< finite pairs, summed over the lags */
    size_t n_candidates; /**< LOO score evaluations made */
    double h_rule;       /**< the rule-of-thumb value (computed in every case, for reference) */
} aenl_bw_result_t;

/** Detail of one score evaluation (aenl_bw_loo_score, aenl_bw_loo_score_brute). */
typedef struct aenl_bw_score
{
    double score;           /**< mean over lags of CV_L(h); NaN if some lag has no usable pair */
    size_t n_pairs;         /**< finite pairs, summed over lags */
    size_t n_used;          /**< pairs with a leave-one-out estimate, summed over lags */
    size_t n_excluded;      /**< pairs without one (no other pair within h), summed over lags */
    double mean_neighbours; /**< k: mean number of other pairs within h per pair */
} aenl_bw_score_t;

/** Default options (see aenl_bw_opts_t). */
void aenl_bw_opts_default(aenl_bw_opts_t *opts);

/**
 * @brief Choose the bandwidth for the lag regressions of x.
 *
 * Log-spaced grid of opts->n_grid candidates in [h_lo, h_hi], then golden-section refinement
 * (in log h) around the best admissible grid point. Falls back to aenl_bw_rule() when a lag has
 * fewer than min_pairs usable pairs, when no candidate is admissible, or when the best grid point
 * is at an end of the admissible range or the curve is flat (no interior minimum).
 *
 * @param[in]  x       n samples; NaN/Inf = missing (pairs through them are skipped)
 * @param[in]  lags    n_lags lags, each >= 1
 * @param[in]  opts    NULL for defaults
 * @param[out] out     result (zeroed on error)
 * @param[out] err     message on error (may be NULL)
 * @return AENL_OK; AENL_E_ARG for NULL pointers, n_lags == 0, a zero lag, bad options, fewer than
 *         two finite samples ("no finite samples") or a constant signal ("constant signal");
 *         AENL_E_IO when out of memory.
 * @note Cost: O(n_lags · N log N) once (sorting), then O(n_lags · N) per candidate h; memory
 *       about 64 bytes per pair and lag.
 */
aenl_status_t aenl_bw_select(const double *x, size_t n, const uint16_t *lags, size_t n_lags,
                             const aenl_bw_opts_t *opts, aenl_bw_result_t *out, aenl_err_t *err);

/**
 * @brief Exact leave-one-out score at one bandwidth (sorted pairs + compensated prefix sums).
 * @param[in]  h   bandwidth > 0, finite
 * @return AENL_OK (out->score may be NaN when a lag has no usable pair); AENL_E_ARG bad arguments;
 *         AENL_E_IO out of memory.
 * @note O(n_lags · N log N) (sorting), then O(n_lags · N) for the score itself.
 */
aenl_status_t aenl_bw_loo_score(const double *x, size_t n, const uint16_t *lags, size_t n_lags,
                                double h, aenl_bw_score_t *out, aenl_err_t *err);

/**
 * @brief The same score by the definition, O(n_lags · N²): the reference for tests.
 * @return as aenl_bw_loo_score().
 */
aenl_status_t aenl_bw_loo_score_brute(const double *x, size_t n, const uint16_t *lags,
                                      size_t n_lags, double h, aenl_bw_score_t *out,
                                      aenl_err_t *err);

/**
 * @brief Normal-reference rule of thumb for the triangular kernel:
 *        h = 2.578 · σ · N^(−1/5), σ = min(sd, IQR/1.349) of the finite samples
 *        (sd with divisor N−1; IQR from linearly interpolated quantiles, position (N−1)p;
 *        σ = sd when the IQR is 0), N = number of finite samples. Derivation in aenl_bandwidth.c.
 * @return AENL_OK; AENL_E_ARG for NULL, fewer than two finite samples or a constant signal;
 *         AENL_E_IO out of memory.
 */
aenl_status_t aenl_bw_rule(const double *x, size_t n, double *h, aenl_err_t *err);

/** The constant of aenl_bw_rule(): 1.06 · (48√π)^(1/5) ≈ 2.5779. */
double aenl_bw_rule_constant(void);

/** "cv", "rule" or "unknown". */
const char *aenl_bw_method_str(int method);

/** Short text for enum aenl_bw_fallback, e.g. "too few pairs". */
const char *aenl_bw_fallback_str(int fallback);

#endif /* AENL_TOOLS_BANDWIDTH_H */
