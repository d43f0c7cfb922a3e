/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_curves.h
 * @brief Host-only: conditional mean/variance curves of a whole recorded channel, computed with the
 *        core estimator (the same code that runs onboard), with the grid and bandwidth chosen
 *        from the data when not given.
 *
 * Defaults: the grid spans the 0.1 % to 99.9 % quantiles of the finite samples (so a few outliers
 * do not stretch it) with 64 nodes; the bandwidth is chosen by exact leave-one-out
 * cross-validation over the requested lags (aenl_bw_select), with the rule of thumb as fallback.
 */
#ifndef AENL_TOOLS_CURVES_H
#define AENL_TOOLS_CURVES_H

#include <stddef.h>

#include "aenl/aenl_moments.h"
#include "aenl_tools/aenl_io.h"

typedef struct aenl_curves_opts
{
    uint16_t lags[AENL_MOMENTS_MAX_LAGS]; /**< lags in samples */
    uint16_t n_lags;
    int grid_given;      /**< 0: grid from the data's quantiles */
    double x_min, x_max; /**< grid ends when grid_given */
    uint16_t n_grid;     /**< nodes (default 64) */
    double bandwidth;    /**< > 0: use it; <= 0: cross-validation */
    double forgetting;   /**< (0, 1]; default 1 */
    int split;           /**< accumulate rising/falling separately (needed for RISING/FALLING) */
    double prefilter;    /**< 0 off (default); > 0 low-pass cutoff as a fraction of the sample
                              rate (< 0.5); < 0 automatic: 8 / period, at most 0.4 */
    int lags_auto;       /**< 1: lags chosen from the period, geometric 1 .. max(5, period/8) */
    size_t cv_max;       /**< samples the cross-validation reads (default 200 000; 0: all): a
                              longer record's bandwidth is cross-validated on its first cv_max
                              samples and scaled by (cv_max / n)^(1/5), the rate at which the
                              kernel regression's optimal bandwidth shrinks with the record */
} aenl_curves_opts_t;

/** Defaults: lags 1, 10, 30; 64 nodes; CV bandwidth (on at most 200 000 samples); no forgetting;
 *  split on. */
void aenl_curves_opts_default(aenl_curves_opts_t *o);

/** Curves for every lag and direction. Arrays are [lag][node]; NaN where a node has no weight. */
typedef struct aenl_curves
{
    uint16_t n_lags, n_grid, n_dir; /**< n_dir 3 (all, rising, falling) with the split, else 1 */
    uint16_t lags[AENL_MOMENTS_MAX_LAGS];
    double *x;                       /**< n_grid node positions */
    double *mean, *var, *n_eff, *se; /**< [dir][lag][node], dir as aenl_dir_t */
    double bandwidth;
    int bw_method;     /**< AENL_BW_CV or AENL_BW_RULE (aenl_bandwidth.h), or -1 given */
    size_t cv_samples; /**< samples the bandwidth was chosen on (0 when given); fewer than
                            n_samples: scaled to the record by (cv_samples / n_samples)^(1/5) */
    size_t n_samples, n_missing;
    double period;    /**< estimated dominant period in samples (0 when not needed) */
    double prefilter; /**< cutoff applied, fraction of the sample rate (0: none) */
    /** Lag expansion per [dir][node] (aenl_moments_taylor, order min(4, n_lags - 1)); NULL when
     *  fewer than 3 lags; NaN where a node has no estimate. */
    double *position, *velocity, *accel, *se_position, *se_velocity, *se_accel;
    uint16_t taylor_order;
} aenl_curves_t;

/** Index of (dir, lag, node) in the arrays. */
static inline size_t aenl_curves_at(const aenl_curves_t *c, int dir, size_t lag, size_t node)
{
    return ((size_t)dir * c->n_lags + lag) * c->n_grid + node;
}

/**
 * @brief Compute the curves of x[0..n-1] (NaN = missing sample).
 * @return AENL_OK; AENL_E_ARG with a message for: no finite sample, a constant signal, a grid of
 *         < 3 nodes or inverted, a bandwidth that is negative or not finite, a lag of 0 or above
 *         the compile-time maximum, too many lags, too few samples for the largest lag;
 *         AENL_E_DIM when the configuration exceeds the estimator's capacity.
 */
aenl_status_t aenl_curves_compute(const double *x, size_t n, const aenl_curves_opts_t *opts,
                                  aenl_curves_t *out, aenl_err_t *err);

/** Free and zero. Safe on a zeroed struct. */
void aenl_curves_free(aenl_curves_t *c);

/** Index of (dir, node) in the expansion arrays. */
static inline size_t aenl_curves_node_at(const aenl_curves_t *c, int dir, size_t node)
{
    return (size_t)dir * c->n_grid + node;
}

/**
 * @brief Dominant period of x in samples, from crossings of the mean with hysteresis (a crossing
 *        counts only once the signal has moved half a standard deviation past the mean), so noise
 *        chattering around the mean does not inflate the count.
 * @return AENL_OK; AENL_E_ARG with a message when fewer than two full oscillations are found.
 */
aenl_status_t aenl_curves_period(const double *x, size_t n, double *period, aenl_err_t *err);

/**
 * @brief Write the lag expansion as CSV: '#' lines, then
 *        `dir,x,position,velocity,accel,se_position,se_velocity,se_accel` with dir 0 all pairs,
 *        1 rising, 2 falling; velocity per sample, accel per sample squared; nan where empty.
 * @return AENL_OK; AENL_E_ARG when the curves have no expansion (fewer than 3 lags); AENL_E_IO.
 */
aenl_status_t aenl_curves_write_expansion_csv(const aenl_curves_t *c, const char *source,
                                              const char *channel, const char *path,
                                              aenl_err_t *err);

/** Parse "1,10,30" into opts->lags. AENL_E_ARG with a message on a bad list. */
aenl_status_t aenl_curves_parse_lags(const char *s, aenl_curves_opts_t *opts, aenl_err_t *err);

/**
 * @brief Write the curves of one direction as CSV: comment lines (`# key=value`: source, channel,
 *        bandwidth and its method, grid) then `lag,x,mean,var,n_eff,se`; empty nodes as nan.
 *        `path` NULL or "-" writes to stdout.
 */
aenl_status_t aenl_curves_write_csv(const aenl_curves_t *c, int dir, const char *source,
                                    const char *channel, const char *path, aenl_err_t *err);

#endif /* AENL_TOOLS_CURVES_H */
