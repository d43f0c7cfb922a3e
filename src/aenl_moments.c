/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_moments.c
 * @brief Streaming triangular-kernel conditional moments (the paper's formulas 10-11;
 *        docs/moments.md).
 *
 * Cell update (weighted Welford, West 1979), for a pair (u, y) with kernel weight w at a node:
 *     W' = W + w,  d = y - mean,  mean' = mean + d w / W',  M2' = M2 + w d (y - mean'),
 *     W2' = W2 + w^2.
 * Every lag is conditioned on the same samples (lockstep), so W and W2 are the same for all lags
 * of a (direction, node) and are kept once there, and w / W' is divided out once for them; each
 * (lag series, direction, node) cell keeps its mean and M2, the cells of a (direction, node)
 * side by side, so a push walks its sums in order. Forgetting: rather than multiplying every cell
 * by lambda at every sample (O(grid)), the newest sample's weight is multiplied by scale =
 * lambda^-n; ratios (mean, M2/W, W^2/W2) are unchanged. When the scale reaches 2^20 all active sums
 * are multiplied by 2^-20 (exact in binary floating point) and the scale divided by 2^20, so
 * nothing overflows and no rounding is added. The cells accumulate the kernel weight without its
 * constant factor 1/h (1 - |d|/h, at most 1 times the scale): the factor cancels in the mean, the
 * variance and n_eff, and leaving it out keeps W and W2 bounded by the sample count whatever the
 * bandwidth (with 1/h inside, a bandwidth of 1e-20 in float32 overflowed W2 = sum w^2 at the first
 * pair). Query applies it to `weight`.
 *
 * Compensation (AENL_MOMENTS_COMPENSATED): each sum s is a Kahan sum whose compensation c, the
 * rounding error of its last addition (|c| <= ulp(s)/2 <= |s| eps/2), is stored as the integer
 * lo = round(c / (|s| eps 2^-15)), |lo| <= 2^14: the sum then has about 40 significant bits in
 * float32 (6 bytes instead of 8 for a float compensation). Rounding c costs at most
 * |s| eps 2^-16 (float32: |s| 2^-39) per addition. That is far below the increments of W, W2
 * and M2, which grow with the count: after N additions an increment is about |s| / N, so the
 * rounding is 2^-39 N of it (5e-5 at N = 10^9 additions to one sum), and these roundings, spread
 * over many units of c and of either sign, add up like a random walk (about 1e-8 of the sum; all
 * of one sign they would reach 2e-3). A weighted mean does not grow: its increments shrink like
 * its spread / N, and would fall to |mean| 2^-39 when the signal sits on a large offset
 * (1000 +- 0.1: 1e-11 of the mean after 10^7 pairs, 2e-12 after 5 10^7). So the compensated
 * build keeps each cell's mean relative to its node x_k, whose distance from the conditional
 * mean is bounded by the grid rather than by the offset.
 */
#include <string.h>

#include "aenl/aenl_moments.h"

#include "aenl_linalg.h"

#define RING_LEN     ((uint16_t)(2 * AENL_MOMENTS_MAX_LAG + 2))
#define SCALE_LIMIT  AENL_R(1048576.0)                 /* 2^20 */
#define SCALE_SHRINK AENL_R(9.5367431640625e-7)        /* 2^-20 */
#define LO_UNIT      (AENL_REAL_EPS / AENL_R(32768.0)) /* compensation unit relative to |s| */
#define LO_MAX       AENL_R(32767.0)
/* 1.5 2^mantissa bits: its ulp is 1, so adding it to a value of magnitude below 2^(bits-1) leaves
 * no fraction bit, and subtracting it again gives the value rounded to an integer */
#if AENL_USE_DOUBLE
#define ROUND_MAGIC AENL_R(6755399441055744.0)
#else
#define ROUND_MAGIC AENL_R(12582912.0)
#endif

/* Value of sum i (file comment: compensation). */
static aenl_real_t sum_get(const aenl_moments_t *m, uint32_t i)
{
#if AENL_MOMENTS_COMPENSATED
    return m->sum[i] - (aenl_real_t)m->sum_lo[i] * (aenl_fabs(m->sum[i]) * LO_UNIT);
#else
    return m->sum[i];
#endif
}

/* sum i += v. A compensation that does not fit (a sum cancelled to nearly nothing, or one so
 * small that its unit underflows) is dropped: that addition is then a plain one. */
static void sum_add(aenl_moments_t *m, uint32_t i, aenl_real_t v)
{
#if AENL_MOMENTS_COMPENSATED
    const aenl_real_t s = m->sum[i];
    const aenl_real_t y = v - (aenl_real_t)m->sum_lo[i] * (aenl_fabs(s) * LO_UNIT);
    const aenl_real_t t = s + y;
    const aenl_real_t k = ((t - s) - y) / (aenl_fabs(t) * LO_UNIT);
    int32_t lo = 0;
    if (k >= -LO_MAX && k <= LO_MAX)
    {
        /* to nearest, without a branch on the sign of k: that sign is random, a branch on it is
         * mispredicted half the time, and on the host that makes the compensated push several
         * times slower (an evaluation wider than the build's precision, or -ffast-math folding
         * the two additions, rounds toward zero instead, within one unit) */
        lo = (int32_t)((k + ROUND_MAGIC) - ROUND_MAGIC);
    }
    m->sum_lo[i] = (int16_t)lo;
    m->sum[i] = t;
#else
    m->sum[i] += v;
#endif
}

/* Where the sums of a cell are: its weight sum W at *iw and W2 at *iw + W2_OFF, kept once per
 * (direction, node) and shared by every lag series, all of them ahead of the cells; its mean
 * (relative to the node when compensated) at *im and M2 at *im + 1, the cells of the lag series
 * of a (direction, node) next to each other. */
#define W2_OFF 1u

static void cell_index(const aenl_moments_t *m, uint32_t series, uint32_t dir, uint32_t node,
                       uint32_t *iw, uint32_t *im)
{
    const uint32_t cell = (dir * m->cfg.n_grid + node) * aenl_moments_n_series(m) + series;
    *iw = 2u * (dir * m->cfg.n_grid + node);
    *im = 2u * ((uint32_t)m->n_dir * m->cfg.n_grid + cell);
}

/* Sums in use (see cell_index). */
static uint32_t active_sums(const aenl_moments_t *m)
{
    const uint32_t n_groups = (uint32_t)m->n_dir * m->cfg.n_grid;
    return 2u * (1u + aenl_moments_n_series(m)) * n_groups;
}

/* Validate cfg; on success *dx is the grid spacing. */
static aenl_status_t check_cfg(const aenl_moments_cfg_t *cfg, aenl_real_t *dx)
{
    const aenl_real_t ends[3] = {cfg->x_min, cfg->x_max, cfg->x_max - cfg->x_min};
    if (!aenl_la_all_finite(ends, 0u, 1u, 3u) || !(cfg->x_max > cfg->x_min))
    {
        return AENL_E_ARG;
    }
    if (cfg->n_grid < 3u)
    {
        return AENL_E_ARG;
    }
    if (cfg->n_grid > AENL_MOMENTS_MAX_GRID)
    {
        return AENL_E_DIM;
    }
    if (!(cfg->bandwidth > AENL_R(0.0) && cfg->bandwidth <= AENL_REAL_MAX)) /* NaN, Inf fail */
    {
        return AENL_E_ARG;
    }
    if (cfg->n_lags == 0u)
    {
        return AENL_E_ARG;
    }
    if (cfg->n_lags > AENL_MOMENTS_MAX_LAGS)
    {
        return AENL_E_DIM;
    }
    for (uint32_t i = 0; i < cfg->n_lags; ++i)
    {
        if (cfg->lags[i] == 0u)
        {
            return AENL_E_ARG;
        }
        if (cfg->lags[i] > AENL_MOMENTS_MAX_LAG)
        {
            return AENL_E_DIM;
        }
        for (uint32_t j = 0; j < i; ++j)
        {
            if (cfg->lags[j] == cfg->lags[i])
            {
                return AENL_E_ARG;
            }
        }
    }
    if (!(cfg->forgetting >= AENL_MOMENTS_MIN_FORGETTING && cfg->forgetting <= AENL_R(1.0)))
    {
        return AENL_E_ARG;
    }
    if (cfg->direction_split > 1u || cfg->symmetric > 1u)
    {
        return AENL_E_ARG;
    }
    const uint32_t groups = (uint32_t)cfg->n_grid * (cfg->direction_split ? 2u : 1u);
    const uint32_t series = (uint32_t)cfg->n_lags * (cfg->symmetric ? 2u : 1u);
    const uint32_t sums = 2u * (series + 1u) * groups;
    if (series * groups > AENL_MOMENTS_MAX_CELLS || sums > (uint32_t)AENL_MOMENTS_MAX_SUMS)
    {
        return AENL_E_DIM;
    }
    /* The spacing and the bandwidth must be representable relative to the grid. */
    *dx = (cfg->x_max - cfg->x_min) / (aenl_real_t)(cfg->n_grid - 1u);
    if (!(*dx > AENL_R(0.0)) || !aenl_is_finite(AENL_R(1.0) / *dx) ||
        !aenl_is_finite(AENL_R(1.0) / cfg->bandwidth))
    {
        return AENL_E_ARG;
    }
    return AENL_OK;
}

aenl_status_t aenl_moments_init(aenl_moments_t *m, const aenl_moments_cfg_t *cfg)
{
    if (m == NULL || cfg == NULL)
    {
        return AENL_E_ARG;
    }
    aenl_real_t dx;
    const aenl_status_t st = check_cfg(cfg, &dx);
    if (st != AENL_OK)
    {
        return st;
    }
    memset(m, 0, sizeof(*m));
    m->cfg = *cfg;
    for (uint32_t i = 0; i < AENL_MOMENTS_MAX_LAGS; ++i)
    {
        if (i >= cfg->n_lags)
        {
            m->cfg.lags[i] = 0u; /* unused entries: defined, never read */
        }
        else if (cfg->lags[i] > m->max_lag)
        {
            m->max_lag = cfg->lags[i];
        }
    }
    m->dx = dx;
    m->inv_dx = AENL_R(1.0) / m->dx;
    m->inv_h = AENL_R(1.0) / cfg->bandwidth;
    m->inv_lambda = AENL_R(1.0) / cfg->forgetting;
    m->n_dir = cfg->direction_split ? 2u : 1u;
    aenl_moments_reset(m);
    return AENL_OK;
}

void aenl_moments_reset(aenl_moments_t *m)
{
    if (m == NULL)
    {
        return;
    }
    memset(m->sum, 0, sizeof(m->sum[0]) * active_sums(m));
#if AENL_MOMENTS_COMPENSATED
    memset(m->sum_lo, 0, sizeof(m->sum_lo[0]) * active_sums(m));
#endif
    memset(m->hist, 0, sizeof(m->hist));
    memset(m->valid, 0, sizeof(m->valid));
    m->head = 0u;
    m->n_hist = 0u;
    m->n_samples = 0u;
    m->n_missing = 0u;
    m->n_renorm = 0u;
    m->scale = AENL_R(1.0);
}

/* Ring index back samples before head (back < RING_LEN). */
static uint32_t ring_back(uint32_t head, uint32_t back)
{
    return (head >= back) ? head - back : head + RING_LEN - back;
}

/* Ring index of the response of lag series ls to the conditioning sample X_c, c = n - L_max. */
static uint32_t response(const aenl_moments_t *m, uint32_t ls)
{
    return ring_back(m->head, (uint32_t)((int32_t)m->max_lag - aenl_moments_lag(m, (uint16_t)ls)));
}

static void ring_store(aenl_moments_t *m, aenl_real_t v, uint8_t ok)
{
    m->head = (uint16_t)((m->head + 1u < RING_LEN) ? m->head + 1u : 0u);
    m->hist[m->head] = v;
    m->valid[m->head] = ok;
    if (m->n_hist < RING_LEN)
    {
        m->n_hist++;
    }
}

/* First node index >= v (ceil) and last node index <= v (floor), for v in grid units, clamped to
 * [-1, n_grid] before any conversion so that a far-off value cannot overflow the integer. Written
 * without ceil/floor: those are library calls on many targets, and this is the hot path. */
static int32_t node_ceil(aenl_real_t v, uint32_t n_grid)
{
    if (!(v > AENL_R(-1.0)))
    {
        return 0;
    }
    if (v > (aenl_real_t)n_grid)
    {
        return (int32_t)n_grid;
    }
    const int32_t k = (int32_t)v; /* truncation: v > -1, so 0 <= k <= the ceiling of v */
    return ((aenl_real_t)k < v) ? k + 1 : k;
}

static int32_t node_floor(aenl_real_t v, uint32_t n_grid)
{
    if (!(v >= AENL_R(0.0)))
    {
        return -1;
    }
    if (v >= (aenl_real_t)(n_grid - 1u))
    {
        return (int32_t)n_grid - 1;
    }
    return (int32_t)v; /* v >= 0: truncation is floor */
}

/* Scale every weight-carrying sum (W, M2 by 2^-20, W2 by 2^-40; not the means) and the scale. */
static void renormalise(aenl_moments_t *m)
{
    const uint32_t n = active_sums(m);
    const uint32_t n_w = 2u * m->n_dir * m->cfg.n_grid; /* (W, W2) of each group, then cells */
    for (uint32_t i = 0; i < n; i += 2u)
    {
        if (i < n_w)
        {
            m->sum[i] *= SCALE_SHRINK;
            m->sum[i + 1u] *= SCALE_SHRINK * SCALE_SHRINK;
        }
        else
        {
            m->sum[i + 1u] *= SCALE_SHRINK; /* M2 after the mean */
        }
    }
    m->scale *= SCALE_SHRINK;
    if (m->n_renorm < UINT32_MAX)
    {
        m->n_renorm++;
    }
}

aenl_status_t aenl_moments_push(aenl_moments_t *m, aenl_real_t sample)
{
    if (m == NULL)
    {
        return AENL_E_ARG;
    }
    if (!aenl_is_finite(sample))
    {
        ring_store(m, AENL_R(0.0), 0u);
        if (m->n_missing < UINT32_MAX)
        {
            m->n_missing++;
        }
        return AENL_E_NUMERIC;
    }
    ring_store(m, sample, 1u);
    if (m->n_samples < UINT32_MAX)
    {
        m->n_samples++;
    }
    if (m->cfg.forgetting < AENL_R(1.0))
    {
        m->scale *= m->inv_lambda;
        if (m->scale >= SCALE_LIMIT)
        {
            renormalise(m);
        }
    }
    /* Lockstep pairing: every lag is conditioned on the same sample c = n - max_lag, with the
     * responses X_{c+L}. All lags thus see one set of conditioning samples, so differences
     * between lags (aenl_moments_taylor) carry no bias from where the record starts or ends. */
    const uint32_t max_lag = m->max_lag;
    /* history before X_c: L_max for the backward series, one sample for the direction */
    const uint32_t n_before = m->cfg.symmetric ? max_lag : (m->n_dir == 2u ? 1u : 0u);
    if (m->n_hist <= max_lag + n_before)
    {
        return AENL_OK;
    }
    const uint32_t pc = ring_back(m->head, max_lag);
    if (!m->valid[pc])
    {
        return AENL_OK;
    }
    const aenl_real_t u = m->hist[pc];
    uint32_t dir = 0u;
    if (m->n_dir == 2u)
    {
        const uint32_t q = ring_back(pc, 1u);
        if (!m->valid[q])
        {
            return AENL_OK; /* the direction of u is unknown: no pair is formed */
        }
        dir = (u > m->hist[q]) ? 0u : 1u; /* 0 rising, 1 falling (ties fall) */
    }
    const uint32_t n_series = aenl_moments_n_series(m);
    /* The lags share W and W2: X_c pairs at every lag or, one response missing, at none. The
     * responses are read once here, not once a node: the ring's index arithmetic would
     * otherwise be a quarter of the update's work. */
    aenl_real_t y_of[2u * AENL_MOMENTS_MAX_LAGS];
    uint8_t all_valid = 1u;
    for (uint32_t ls = 0; ls < n_series; ++ls)
    {
        const uint32_t i = response(m, ls);
        all_valid &= m->valid[i];
        y_of[ls] = m->hist[i];
    }
    if (!all_valid)
    {
        return AENL_OK;
    }
    /* The nodes within h of u, found once for all lags. */
    const aenl_real_t t = (u - m->cfg.x_min) * m->inv_dx; /* u in grid units */
    const aenl_real_t h_units = m->cfg.bandwidth * m->inv_dx;
    const int32_t k0 = node_ceil(t - h_units, m->cfg.n_grid);
    const int32_t k1 = node_floor(t + h_units, m->cfg.n_grid);
    /* read once: the stores into the sums below would otherwise make the compiler reload them */
    const aenl_real_t scale = m->scale;
    const aenl_real_t inv_h = m->inv_h;
    for (int32_t k = k0; k <= k1; ++k)
    {
        const aenl_real_t xk = aenl_moments_node_x(m, (uint16_t)k);
        /* 1/h is left out of the stored weight and applied at query time (file comment). The
         * weight itself is tested, not the distance: a distance just below h can round the
         * weight to 0, which would make w / W' 0/0 at an empty node. */
        const aenl_real_t w = scale * (AENL_R(1.0) - aenl_fabs(xk - u) * inv_h);
        if (!(w > AENL_R(0.0)))
        {
            continue;
        }
        /* the lag series share the node's weight sum, and their cells follow one another */
        uint32_t iw, im;
        cell_index(m, 0u, dir, (uint32_t)k, &iw, &im);
        const aenl_real_t r = w / (sum_get(m, iw) + w); /* w / W' */
#if AENL_MOMENTS_COMPENSATED
        for (uint32_t ls = 0; ls < n_series; ++ls, im += 2u) /* ls >= n_lags: X_{c-L} */
        {
            const aenl_real_t dy = (y_of[ls] - xk) - sum_get(m, im); /* mean relative to x_k */
            const aenl_real_t step = dy * r;
            sum_add(m, im, step);
            sum_add(m, im + 1u, w * dy * (dy - step));
        }
#else
        /* the same updates as above through a pointer into one cell run, which the compiler
         * keeps in registers (the sums are then the only memory the loop writes) */
        aenl_real_t *cell = &m->sum[im];
        for (uint32_t ls = 0; ls < n_series; ++ls, cell += 2) /* ls >= n_lags: X_{c-L} */
        {
            const aenl_real_t dy = y_of[ls] - cell[0];
            const aenl_real_t step = dy * r;
            cell[0] += step;
            cell[1] += w * dy * (dy - step);
        }
#endif
        sum_add(m, iw, w); /* once for all lag series */
        sum_add(m, iw + W2_OFF, w * w);
    }
    return AENL_OK;
}

/* W, mean, M2, W2 of one cell. */
static void cell_read(const aenl_moments_t *m, uint32_t series, uint32_t dir, uint32_t node,
                      aenl_real_t *v)
{
    uint32_t iw, im;
    cell_index(m, series, dir, node, &iw, &im);
    v[0] = sum_get(m, iw);
    v[1] = sum_get(m, im);
    v[2] = sum_get(m, im + 1u);
    v[3] = sum_get(m, iw + W2_OFF);
}

aenl_status_t aenl_moments_query(const aenl_moments_t *m, uint16_t lag_index, uint16_t node,
                                 aenl_dir_t dir, aenl_moments_point_t *out)
{
    if (m == NULL || out == NULL || lag_index >= aenl_moments_n_series(m) || node >= m->cfg.n_grid)
    {
        return AENL_E_ARG;
    }
    if (dir != AENL_DIR_ALL && dir != AENL_DIR_RISING && dir != AENL_DIR_FALLING)
    {
        return AENL_E_ARG;
    }
    if (dir != AENL_DIR_ALL && m->n_dir != 2u)
    {
        return AENL_E_ARG;
    }
    aenl_real_t a[4]; /* W, mean, M2, W2 */
    cell_read(m, lag_index, (dir == AENL_DIR_FALLING) ? 1u : 0u, node, a);
    aenl_real_t w = a[0], mean = a[1], m2 = a[2], w2 = a[3];
    if (dir == AENL_DIR_ALL && m->n_dir == 2u)
    {
        /* Merge rising and falling (Chan et al.'s pairwise combination). */
        aenl_real_t b[4];
        cell_read(m, lag_index, 1u, node, b);
        const aenl_real_t wa = a[0];
        const aenl_real_t wb = b[0];
        w = wa + wb;
        if (w > AENL_R(0.0))
        {
            const aenl_real_t d = b[1] - a[1];
            mean = a[1] + d * (wb / w);
            m2 = a[2] + b[2] + d * d * (wa / w) * wb;
        }
        else
        {
            mean = AENL_R(0.0);
            m2 = AENL_R(0.0);
        }
        w2 = a[3] + b[3];
    }
    const aenl_real_t x = aenl_moments_node_x(m, node);
#if AENL_MOMENTS_COMPENSATED
    mean += x; /* kept relative to the node */
#endif
    memset(out, 0, sizeof(*out));
    out->x = x;
    if (!(w > AENL_R(0.0)) || !(w2 > AENL_R(0.0)))
    {
        return AENL_E_EMPTY;
    }
    const aenl_real_t var = (m2 > AENL_R(0.0)) ? m2 / w : AENL_R(0.0);
    const aenl_real_t n_eff = (w / w2) * w;
    const aenl_real_t se = aenl_sqrt(var / n_eff);
    /* m2 itself is checked: a NaN m2 (Inf - Inf in the compensated sums) would read as var 0. */
    const aenl_real_t all[5] = {mean, m2, var, n_eff, se};
    if (!aenl_la_all_finite(all, 0u, 1u, 5u))
    {
        return AENL_E_NUMERIC; /* the statistics overflowed: never a silent Inf/NaN */
    }
    /* Kernel weight sum sum phi_h = sum (1 - |d|/h) / h, saturating (a bandwidth near the
     * smallest real could push it past the largest one; mean and variance do not need it). */
    const aenl_real_t weight = (w / m->scale) * m->inv_h;
    out->mean = mean;
    out->var = var;
    out->weight = aenl_is_finite(weight) ? weight : AENL_REAL_MAX;
    out->n_eff = n_eff;
    out->se = se;
    return AENL_OK;
}

aenl_status_t aenl_moments_taylor(const aenl_moments_t *m, uint16_t node, aenl_dir_t dir,
                                  uint16_t order, aenl_moments_taylor_t *out)
{
    return aenl_moments_taylor_ex(m, node, dir, order, NULL, out);
}

aenl_status_t aenl_moments_taylor_ex(const aenl_moments_t *m, uint16_t node, aenl_dir_t dir,
                                     uint16_t order, const aenl_real_t *nuisance,
                                     aenl_moments_taylor_t *out)
{
    enum
    {
        NT = AENL_MOMENTS_TAYLOR_MAX_ORDER + 2 /* polynomial + the nuisance column */
    };
    if (m == NULL || out == NULL || order < 2u || order > AENL_MOMENTS_TAYLOR_MAX_ORDER ||
        order + 1u + (nuisance != NULL ? 1u : 0u) > aenl_moments_n_series(m) ||
        node >= m->cfg.n_grid)
    {
        return AENL_E_ARG;
    }
    const uint32_t nt = order + 1u + (nuisance != NULL ? 1u : 0u);
    const uint32_t np = order + 1u; /* polynomial columns */
    const uint32_t n = aenl_moments_n_series(m);
    /* Weighted least squares on rows [sqrt(w) t^k | sqrt(w) y], lags scaled to t = L / L_max in
     * [-1, 1], by a QR factorisation built one row at a time with Givens rotations: no normal
     * equations (whose squared condition number costs float32 every digit at order 4) and a
     * stack that does not grow with the number of lags. r holds [R | Q'b]. */
    aenl_real_t r[NT][NT + 1], col2[NT], rss = AENL_R(0.0);
    memset(r, 0, sizeof(r));
    memset(col2, 0, sizeof(col2));
    const aenl_real_t inv_lmax = AENL_R(1.0) / (aenl_real_t)m->max_lag;
    int weighted = 1;
    for (uint32_t pass = 0; pass < 2u; ++pass) /* pass 0: are all se > 0? pass 1: rows */
    {
        for (uint32_t li = 0; li < n; ++li)
        {
            aenl_moments_point_t p;
            const aenl_status_t st = aenl_moments_query(m, (uint16_t)li, node, dir, &p);
            if (st != AENL_OK)
            {
                return st;
            }
            if (pass == 0u)
            {
                weighted = weighted && (p.se > AENL_R(0.0));
                continue;
            }
            const aenl_real_t sw = weighted ? AENL_R(1.0) / p.se : AENL_R(1.0);
            const aenl_real_t t = (aenl_real_t)aenl_moments_lag(m, (uint16_t)li) * inv_lmax;
            aenl_real_t row[NT + 1];
            aenl_real_t pw = sw;
            for (uint32_t k = 0; k < np; ++k)
            {
                row[k] = pw;
                pw *= t;
            }
            if (nuisance != NULL)
            {
                row[np] = sw * nuisance[li % m->cfg.n_lags]; /* the same for L and -L */
            }
            row[nt] = p.mean * sw;
            for (uint32_t j = 0; j < nt; ++j)
            {
                col2[j] += row[j] * row[j];
            }
            for (uint32_t j = 0; j < nt; ++j) /* rotate the row into R */
            {
                const aenl_real_t x = r[j][j], y = row[j];
                if (!(aenl_fabs(y) > AENL_R(0.0)))
                {
                    continue;
                }
                const aenl_real_t hyp = aenl_sqrt(x * x + y * y);
                const aenl_real_t cs = x / hyp, sn = y / hyp;
                for (uint32_t k = j; k <= nt; ++k)
                {
                    const aenl_real_t rk = r[j][k], wk = row[k];
                    r[j][k] = cs * rk + sn * wk;
                    row[k] = cs * wk - sn * rk;
                }
            }
            rss += row[nt] * row[nt]; /* what the columns cannot reach: the residual */
        }
    }
    /* A pivot that lost all but rounding of its column's norm: the columns are dependent
     * (e.g. too few distinct lags for the order and the nuisance column). */
    const aenl_real_t rank_tol = AENL_USE_DOUBLE ? AENL_R(1e-9) : AENL_R(1e-4);
    for (uint32_t j = 0; j < nt; ++j)
    {
        if (!(aenl_fabs(r[j][j]) > rank_tol * aenl_sqrt(col2[j])) || !aenl_is_finite(r[j][j]))
        {
            return AENL_E_NUMERIC;
        }
    }
    /* Back substitution R c = Q'b, and R^-1 (upper triangular) for the coefficient variances:
     * Cov(c) = (R'R)^-1 = R^-1 R^-T, so var(c_k) = sum_j (R^-1)_kj^2;
     * R^-1 column by column: R x = e_k (the terms below the diagonal come out as zeros). */
    aenl_real_t c[NT], rinv[NT][NT];
    memset(rinv, 0, sizeof(rinv));
    for (uint32_t i = 0; i < nt; ++i)
    {
        c[i] = r[i][nt];
        rinv[i][i] = AENL_R(1.0);
    }
    aenl_la_solve_tri(&r[0][0], NT + 1u, 1u, nt, c, 1u, 1u, 1);
    aenl_la_solve_tri(&r[0][0], NT + 1u, 1u, nt, &rinv[0][0], NT, nt, 1);
    aenl_real_t var[3] = {AENL_R(0.0), AENL_R(0.0), AENL_R(0.0)};
    for (uint32_t k = 0; k < 3u; ++k)
    {
        for (uint32_t j = k; j < nt; ++j)
        {
            var[k] += rinv[k][j] * rinv[k][j];
        }
    }
    const aenl_real_t s1 = inv_lmax, s2 = inv_lmax * inv_lmax;
    memset(out, 0, sizeof(*out));
    out->x = aenl_moments_node_x(m, node);
    if (!aenl_la_all_finite(c, 0u, 1u, 3u)) /* position, velocity, acceleration */
    {
        return AENL_E_NUMERIC;
    }
    out->position = c[0];
    out->velocity = c[1] * s1;
    out->accel = AENL_R(2.0) * c[2] * s2;
    /* Nominal errors need weights in units of 1/se^2; an unweighted fit has none. */
    out->se_position = weighted ? aenl_sqrt(var[0]) : AENL_R(0.0);
    out->se_velocity = weighted ? aenl_sqrt(var[1]) * s1 : AENL_R(0.0);
    out->se_accel = weighted ? AENL_R(2.0) * aenl_sqrt(var[2]) * s2 : AENL_R(0.0);
    out->chi2 = (weighted && n > nt) ? rss / (aenl_real_t)(n - nt) : AENL_R(0.0);
    return AENL_OK;
}
