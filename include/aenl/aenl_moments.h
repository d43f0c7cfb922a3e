/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_moments.h
 * @brief Streaming triangular-kernel conditional mean and variance on a fixed grid, several lags.
 *
 * For every configured lag L (the paper's j = -L) and grid node x_k the estimator keeps the
 * Nadaraya-Watson estimates of
 *
 *     m_L(x) = E(X_n | X_{n-L} = x)   and   v_L(x) = Var(X_n | X_{n-L} = x)
 *
 * with the triangular kernel phi_h(u) = (1 - |u|/h)/h for |u| < h, 0 otherwise (the paper's
 * formulas (10)-(11)): m = sum X_n phi(x - X_{n-L}) / sum phi(x - X_{n-L}), and v the same weighted
 * mean of (X_n - m)^2. All lags are conditioned on the same samples (lockstep): the pairs are
 * (X_c, X_{c+L}) for c = 0 .. N-1-L_max (from 1 with the direction split), L_max the largest lag,
 * so lag curves differ only by the lag, never by which part of the record they saw. Each (lag,
 * node[, direction]) cell holds the weighted mean and the weighted second central moment M2
 * updated in Welford form, so there is no sum(x^2) - sum(x)^2 cancellation; the lags share one
 * weight sum (and sum of squared weights) per (node[, direction]). With
 * AENL_MOMENTS_COMPENSATED (default in float32) every sum also carries a compensation term, so a
 * float32 estimator stays accurate past 10^9 samples.
 *
 * Options: an exponential forgetting factor lambda (weight of a sample of age a is lambda^a), for
 * non-stationary conditions; and a direction split, which accumulates separately for a rising
 * (X_{n-L} > X_{n-L-1}) and a falling (otherwise) conditioning value: hysteresis shifts the kinks
 * between the two.
 *
 * Memory: the caller owns the aenl_moments_t (declare it static on an MCU); the library never
 * allocates. sizeof(aenl_moments_t) is fixed by the capacities in aenl_config.h.
 * Threading: none; every function is re-entrant over its own state.
 */
#ifndef AENL_MOMENTS_H
#define AENL_MOMENTS_H

#include "aenl/aenl_types.h"

/**
 * Smallest forgetting factor, 2^-20: a sample's weight then grows by at most 2^20 per push, which
 * one renormalisation of the cells absorbs (a smaller lambda overflowed the weights to Inf). Any
 * useful lambda is far above it (0.9 already forgets within ~50 samples).
 */
#define AENL_MOMENTS_MIN_FORGETTING AENL_R(9.5367431640625e-7)

/** Which conditioning-value direction a query reads. */
typedef enum
{
    AENL_DIR_ALL = 0,    /**< every pair (rising and falling merged) */
    AENL_DIR_RISING = 1, /**< X_{n-L} > X_{n-L-1}; needs direction_split */
    AENL_DIR_FALLING = 2 /**< X_{n-L} <= X_{n-L-1}; needs direction_split */
} aenl_dir_t;

/** Configuration, copied by aenl_moments_init(). */
typedef struct aenl_moments_cfg
{
    aenl_real_t x_min;     /**< first grid node, input units, finite */
    aenl_real_t x_max;     /**< last grid node, input units, finite, > x_min */
    uint16_t n_grid;       /**< nodes, 3 .. AENL_MOMENTS_MAX_GRID, evenly spaced, ends included */
    aenl_real_t bandwidth; /**< kernel half-width h > 0, input units */
    uint16_t n_lags;       /**< 1 .. AENL_MOMENTS_MAX_LAGS */
    uint16_t lags[AENL_MOMENTS_MAX_LAGS]; /**< distinct, each 1 .. AENL_MOMENTS_MAX_LAG samples */
    aenl_real_t forgetting;  /**< lambda in [AENL_MOMENTS_MIN_FORGETTING, 1]; 1 = plain averages */
    uint8_t direction_split; /**< 0 or 1 */
    uint8_t symmetric;       /**< 0 or 1: also pair each conditioning value X_c with X_{c-L}
                                  (lag -L, lag index n_lags + i for lags[i]), so the lag expansion
                                  is centred on the conditioning sample; needs L_max more history */
} aenl_moments_cfg_t;

/** One estimate at one (lag, node, direction). */
typedef struct aenl_moments_point
{
    aenl_real_t x;      /**< node position, input units */
    aenl_real_t mean;   /**< conditional mean, input units */
    aenl_real_t var;    /**< conditional variance (>= 0), input units squared */
    aenl_real_t weight; /**< kernel weight sum (forgetting applied), 1/input units; saturates at
                             AENL_REAL_MAX */
    aenl_real_t n_eff;  /**< effective sample size (sum w)^2 / sum w^2 */
    aenl_real_t se;     /**< standard error of the mean, sqrt(var / n_eff) */
} aenl_moments_point_t;

/** Estimator state. Caller-owned; every field is read-only for the caller. */
typedef struct aenl_moments
{
    aenl_moments_cfg_t cfg; /**< the configuration as given */
    aenl_real_t dx;         /**< grid spacing */
    aenl_real_t inv_dx;     /**< 1 / dx */
    aenl_real_t inv_h;      /**< 1 / bandwidth */
    aenl_real_t inv_lambda; /**< 1 / forgetting */
    aenl_real_t scale;      /**< weight of the newest sample relative to the cells, in [1, 2^20) */
    uint16_t n_dir;         /**< 2 with the direction split, else 1 */
    uint16_t max_lag;       /**< largest configured lag */
    uint16_t head;          /**< ring index of the newest sample */
    uint16_t n_hist;        /**< samples (incl. missing) in the ring, saturating at its length */
    uint32_t n_samples;     /**< finite samples accepted (saturating) */
    uint32_t n_missing;     /**< NaN/Inf samples received (saturating) */
    uint32_t n_renorm;      /**< forgetting-scale renormalisations (saturating) */
    aenl_real_t hist[2 * AENL_MOMENTS_MAX_LAG + 2]; /**< sample history ring */
    uint8_t valid[2 * AENL_MOMENTS_MAX_LAG + 2];    /**< 0 marks a missing sample */
    /** Running sums, active part only: first the weight sum W and the sum of squared weights W2
     *  of every (direction, node), which the lags share, then the weighted mean (relative to the
     *  node when compensated) and the weighted second central moment M2 of every cell, a
     *  (direction, node)'s cells of the lag series side by side. */
    aenl_real_t sum[AENL_MOMENTS_MAX_SUMS];
#if AENL_MOMENTS_COMPENSATED
    int16_t sum_lo[AENL_MOMENTS_MAX_SUMS]; /**< compensation of each sum (aenl_config.h) */
#endif
} aenl_moments_t;

/**
 * @brief Validate the configuration and set up an empty estimator.
 * @param[out] m    state; its previous content (even garbage) is irrelevant
 * @param[in]  cfg  configuration; copied
 * @return AENL_OK; AENL_E_ARG for NULL, a non-finite or inverted grid, n_grid < 3, bandwidth <= 0,
 *         n_lags = 0, a zero or repeated lag, forgetting outside [AENL_MOMENTS_MIN_FORGETTING, 1],
 *         direction_split or symmetric not 0/1;
 *         AENL_E_DIM for n_grid, n_lags or a lag above its compile-time maximum, or
 *         n_lags * (1 + symmetric) * n_grid * (1 + direction_split) > AENL_MOMENTS_MAX_CELLS,
 *         or its running sums > AENL_MOMENTS_MAX_SUMS (aenl_config.h).
 *         On error *m is not written.
 * @note O(cells), no allocation.
 */
aenl_status_t aenl_moments_init(aenl_moments_t *m, const aenl_moments_cfg_t *cfg);

/**
 * @brief Forget every sample and statistic; keep the configuration. NULL is ignored.
 * @note O(cells).
 */
void aenl_moments_reset(aenl_moments_t *m);

/**
 * @brief Add one sample X_n. The conditioning sample is c = n - L_max; for each lag L the pair
 *        (X_c, X_{c+L}) updates the nodes within h of X_c (with the split: the cells of the
 *        direction of X_c against X_{c-1}). The first pairs form once L_max + 1 samples are in.
 * @param[in,out] m       an initialised estimator
 * @param[in]     sample  X_n in input units
 * @return AENL_OK; AENL_E_ARG for NULL (nothing changed); AENL_E_NUMERIC for a NaN/Inf sample,
 *         which is a *missing* sample: the statistics stay byte-identical, the history records the
 *         gap (no pair is formed across it, time alignment is kept) and n_missing counts it.
 *         The lags share their weight sums, so a conditioning sample X_c forms pairs at every
 *         lag or at none (at none when one of its responses is missing).
 * @note O(n_lags * min(n_grid, 2h/dx + 1)) per sample, no loop over the grid (the node range is
 *       found once per sample for all lags). With forgetting < 1,
 *       one push in every ~(14 / -ln(lambda)) also rescales all active cells (O(cells)).
 *       No allocation, stack < 96 B.
 */
aenl_status_t aenl_moments_push(aenl_moments_t *m, aenl_real_t sample);

/**
 * @brief Read the estimate at one lag, node and direction.
 * @param[in]  m          an initialised estimator
 * @param[in]  lag_index  index into cfg.lags, < n_lags; with cfg.symmetric, n_lags + i reads the
 *                        backward series of lags[i] (aenl_moments_lag gives the signed lag)
 * @param[in]  node       grid node, < n_grid
 * @param[in]  dir        AENL_DIR_ALL, or RISING/FALLING when the split is on
 * @param[out] out        the estimate
 * @return AENL_OK; AENL_E_ARG for NULL, an index out of range, or a direction the configuration
 *         lacks; AENL_E_EMPTY when no pair has weight at that node yet (out then holds x only, the
 *         rest zero); AENL_E_NUMERIC when the cell's statistics overflowed (out as for
 *         AENL_E_EMPTY). Overflow needs samples far beyond any physical range: the squared spread
 *         of the samples times the weight sum must exceed AENL_REAL_MAX (float32: about 1e10 in
 *         magnitude over 2^32 samples); it never happens silently as an Inf or NaN result.
 * @note O(1), no allocation.
 */
aenl_status_t aenl_moments_query(const aenl_moments_t *m, uint16_t lag_index, uint16_t node,
                                 aenl_dir_t dir, aenl_moments_point_t *out);

/** Highest power of the lag in aenl_moments_taylor(). */
#define AENL_MOMENTS_TAYLOR_MAX_ORDER 4

/**
 * Local expansion of the conditional mean in the lag at one node (aenl_moments_taylor): for a
 * response s observed with independent noise, X = s + e, and lags L in samples,
 *     m_L(x) = E(X_{n+L} | X_n = x) = p(x) + v(x) L + a(x) L^2 / 2 + ...
 * where p(x) = E(s_n | X_n = x) is the noise-free position given the observed one (the intercept
 * at L = 0, which the noisy X_n itself is not: the errors-in-variables correction), v(x) the
 * conditional velocity and a(x) the conditional acceleration, both per sample. For all pairs of a
 * stationary record v(x) = 0; per direction (the split) v and a trace the phase portrait, and
 * a(p) is the restoring-force curve of the DOF. Standard errors are nominal: they treat the lags'
 * estimates as independent, which they are not (the same samples condition every lag).
 */
typedef struct aenl_moments_taylor
{
    aenl_real_t x;           /**< node, input units */
    aenl_real_t position;    /**< p(x), input units */
    aenl_real_t velocity;    /**< v(x), input units per sample */
    aenl_real_t accel;       /**< a(x), input units per sample squared */
    aenl_real_t se_position; /**< nominal standard errors of the three */
    aenl_real_t se_velocity;
    aenl_real_t se_accel;
    aenl_real_t chi2; /**< reduced chi-square of the fit (residual sum of squares in units of the
                           lags' se, per degree of freedom); 0 without residual degrees of freedom
                           or weights. The lags' errors are strongly correlated (the same pairs,
                           dominated by the spread of the velocity, which the fit absorbs), so
                           se * sqrt(chi2), pooled over nodes, is the realistic error scale. */
} aenl_moments_taylor_t;

/**
 * @brief Fit m_L = c0 + c1 L + ... + c_order L^order over every configured lag at one node and
 *        direction (weighted by 1 / se_L^2, or unweighted when a lag's se is 0), and report
 *        position c0, velocity c1 and acceleration 2 c2.
 * @param[in] order  2 .. AENL_MOMENTS_TAYLOR_MAX_ORDER, and at most aenl_moments_n_series - 1
 *                   (every series is used, backward ones with their negative lag; the lags must
 *                   span the curvature: small against the period, e.g. 1 .. T/8)
 * @return AENL_OK; AENL_E_ARG for NULL, an index or direction as in aenl_moments_query, or an
 *         order outside its range; AENL_E_EMPTY when a lag has no weight at the node;
 *         AENL_E_NUMERIC when the weighted normal equations are singular.
 * @note O(n_lags * order^2 + order^3); no allocation, stack < 400 B in float32.
 */
aenl_status_t aenl_moments_taylor(const aenl_moments_t *m, uint16_t node, aenl_dir_t dir,
                                  uint16_t order, aenl_moments_taylor_t *out);

/**
 * @brief aenl_moments_taylor with one more regressor: m_L = polynomial(L) + g * nuisance[L], with
 *        nuisance[i] given per configured lag i (the same value for the backward series of a
 *        symmetric estimator). For a record low-pass filtered before the estimator, the
 *        measurement noise left in the pass band is correlated over a few samples, so
 *        E(e_{n+L} | X_n = x) = rho(L) E(e_n | X_n = x) adds a term that is not polynomial in L;
 *        with nuisance = rho (the filter's normalised noise autocorrelation) it is fitted and
 *        removed instead of bending the expansion. NULL: exactly aenl_moments_taylor.
 * @return as aenl_moments_taylor; the order is then at most aenl_moments_n_series - 2.
 */
aenl_status_t aenl_moments_taylor_ex(const aenl_moments_t *m, uint16_t node, aenl_dir_t dir,
                                     uint16_t order, const aenl_real_t *nuisance,
                                     aenl_moments_taylor_t *out);

/** Lag series: n_lags, doubled when symmetric (indices n_lags .. 2 n_lags - 1 are -lags[i]). */
static inline uint16_t aenl_moments_n_series(const aenl_moments_t *m)
{
    return (uint16_t)(m->cfg.n_lags * (m->cfg.symmetric ? 2u : 1u));
}

/** Signed lag of a series index (negative for the backward series of a symmetric estimator). */
static inline int32_t aenl_moments_lag(const aenl_moments_t *m, uint16_t lag_index)
{
    return (lag_index < m->cfg.n_lags) ? (int32_t)m->cfg.lags[lag_index]
                                       : -(int32_t)m->cfg.lags[lag_index - m->cfg.n_lags];
}

/** Position of a grid node (no range check beyond returning x_max past the end). */
static inline aenl_real_t aenl_moments_node_x(const aenl_moments_t *m, uint16_t node)
{
    return (node + 1u >= m->cfg.n_grid) ? m->cfg.x_max : m->cfg.x_min + (aenl_real_t)node * m->dx;
}

#endif /* AENL_MOMENTS_H */
