/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_moments.c
 * @brief Streaming triangular-kernel conditional moments (DESIGN.md section 2.1).
 *
 * Cell update (weighted Welford, West 1979), for a pair (u, y) with kernel weight w at a node:
 *     W' = W + w,  d = y - mean,  mean' = mean + d w / W',  M2' = M2 + w d (y - mean'),  W2' = W2 +
 * w^2 Forgetting: rather than multiplying every cell by lambda at every sample (O(grid)), the
 * newest sample's weight is multiplied by scale = lambda^-n; ratios (mean, M2/W, W^2/W2) are
 * unchanged. When the scale reaches 2^20 all active cells are multiplied by 2^-20 (exact in binary
 * floating point) and the scale divided by 2^20, so nothing overflows and no rounding is added.
 * The cells accumulate the kernel weight without its constant factor 1/h (1 - |d|/h, at most 1
 * times the scale): the factor cancels in the mean, the variance and n_eff, and leaving it out
 * keeps W and W2 bounded by the sample count whatever the bandwidth (with 1/h inside, a bandwidth
 * of 1e-20 in float32 overflowed W2 = sum w^2 at the first pair). Query applies it to `weight`.
 */
#include <string.h>

#include "aenl/aenl_moments.h"

#define RING_LEN     ((uint16_t)(AENL_MOMENTS_MAX_LAG + 2))
#define SCALE_LIMIT  AENL_R(1048576.0)          /* 2^20 */
#define SCALE_SHRINK AENL_R(9.5367431640625e-7) /* 2^-20 */

/* Kahan summation: the represented value is s - c. */
static inline void kahan_add(aenl_real_t *s, aenl_real_t *c, aenl_real_t v)
{
    const aenl_real_t y = v - *c;
    const aenl_real_t t = *s + y;
    *c = (t - *s) - y;
    *s = t;
}

static inline aenl_real_t cell_w(const aenl_moments_cell_t *c)
{
#if AENL_MOMENTS_COMPENSATED
    return c->w - c->w_c;
#else
    return c->w;
#endif
}

static inline aenl_real_t cell_mean(const aenl_moments_cell_t *c)
{
#if AENL_MOMENTS_COMPENSATED
    return c->mean - c->mean_c;
#else
    return c->mean;
#endif
}

static inline aenl_real_t cell_m2(const aenl_moments_cell_t *c)
{
#if AENL_MOMENTS_COMPENSATED
    return c->m2 - c->m2_c;
#else
    return c->m2;
#endif
}

static inline aenl_real_t cell_w2(const aenl_moments_cell_t *c)
{
#if AENL_MOMENTS_COMPENSATED
    return c->w2 - c->w2_c;
#else
    return c->w2;
#endif
}

static void cell_update(aenl_moments_cell_t *c, aenl_real_t w, aenl_real_t y)
{
    const aenl_real_t w_new = cell_w(c) + w;
    const aenl_real_t d = y - cell_mean(c);
    const aenl_real_t step = d * (w / w_new);
#if AENL_MOMENTS_COMPENSATED
    kahan_add(&c->w, &c->w_c, w);
    kahan_add(&c->mean, &c->mean_c, step);
    kahan_add(&c->m2, &c->m2_c, w * d * (d - step));
    kahan_add(&c->w2, &c->w2_c, w * w);
#else
    c->w = w_new;
    c->mean += step;
    c->m2 += w * d * (d - step);
    c->w2 += w * w;
#endif
}

static void cell_scale(aenl_moments_cell_t *c, aenl_real_t f, aenl_real_t f2)
{
    c->w *= f;
    c->m2 *= f;
    c->w2 *= f2;
#if AENL_MOMENTS_COMPENSATED
    c->w_c *= f;
    c->m2_c *= f;
    c->w2_c *= f2;
#endif
}

static uint32_t active_cells(const aenl_moments_t *m)
{
    return (uint32_t)m->cfg.n_lags * m->cfg.n_grid * m->n_dir;
}

static aenl_status_t check_cfg(const aenl_moments_cfg_t *cfg)
{
    if (!aenl_is_finite(cfg->x_min) || !aenl_is_finite(cfg->x_max) || !(cfg->x_max > cfg->x_min))
    {
        return AENL_E_ARG;
    }
    if (!aenl_is_finite(cfg->x_max - cfg->x_min))
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
    if (!aenl_is_finite(cfg->bandwidth) || !(cfg->bandwidth > AENL_R(0.0)))
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
    for (uint16_t i = 0; i < cfg->n_lags; ++i)
    {
        if (cfg->lags[i] == 0u)
        {
            return AENL_E_ARG;
        }
        if (cfg->lags[i] > AENL_MOMENTS_MAX_LAG)
        {
            return AENL_E_DIM;
        }
        for (uint16_t j = 0; j < i; ++j)
        {
            if (cfg->lags[j] == cfg->lags[i])
            {
                return AENL_E_ARG;
            }
        }
    }
    if (!aenl_is_finite(cfg->forgetting) || !(cfg->forgetting >= AENL_MOMENTS_MIN_FORGETTING) ||
        cfg->forgetting > AENL_R(1.0))
    {
        return AENL_E_ARG;
    }
    if (cfg->direction_split > 1u)
    {
        return AENL_E_ARG;
    }
    const uint32_t cells = (uint32_t)cfg->n_lags * cfg->n_grid * (cfg->direction_split ? 2u : 1u);
    if (cells > AENL_MOMENTS_MAX_CELLS)
    {
        return AENL_E_DIM;
    }
    /* The spacing and the bandwidth must be representable relative to the grid. */
    const aenl_real_t dx = (cfg->x_max - cfg->x_min) / (aenl_real_t)(cfg->n_grid - 1u);
    if (!(dx > AENL_R(0.0)) || !aenl_is_finite(AENL_R(1.0) / dx) ||
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
    const aenl_status_t st = check_cfg(cfg);
    if (st != AENL_OK)
    {
        return st;
    }
    memset(m, 0, sizeof(*m));
    m->cfg = *cfg;
    for (uint16_t i = cfg->n_lags; i < AENL_MOMENTS_MAX_LAGS; ++i)
    {
        m->cfg.lags[i] = 0u; /* unused entries: defined, never read */
    }
    m->dx = (cfg->x_max - cfg->x_min) / (aenl_real_t)(cfg->n_grid - 1u);
    m->inv_dx = AENL_R(1.0) / m->dx;
    m->inv_h = AENL_R(1.0) / cfg->bandwidth;
    m->inv_lambda = AENL_R(1.0) / cfg->forgetting;
    m->n_dir = cfg->direction_split ? 2u : 1u;
    for (uint16_t i = 0; i < cfg->n_lags; ++i)
    {
        if (cfg->lags[i] > m->max_lag)
        {
            m->max_lag = cfg->lags[i];
        }
    }
    aenl_moments_reset(m);
    return AENL_OK;
}

void aenl_moments_reset(aenl_moments_t *m)
{
    if (m == NULL)
    {
        return;
    }
    memset(m->cell, 0, sizeof(m->cell[0]) * active_cells(m));
    memset(m->hist, 0, sizeof(m->hist));
    memset(m->valid, 0, sizeof(m->valid));
    m->head = 0u;
    m->n_hist = 0u;
    m->n_samples = 0u;
    m->n_missing = 0u;
    m->n_renorm = 0u;
    m->scale = AENL_R(1.0);
}

static uint16_t ring_back(uint16_t head, uint16_t back)
{
    return (uint16_t)((head + RING_LEN - back) % RING_LEN);
}

static void ring_store(aenl_moments_t *m, aenl_real_t v, uint8_t ok)
{
    m->head = (uint16_t)((m->head + 1u) % RING_LEN);
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
static int32_t node_ceil(aenl_real_t v, uint16_t n_grid)
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

static int32_t node_floor(aenl_real_t v, uint16_t n_grid)
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

/* Pair (u, y) into the nodes of one cell row. Kernel phi_h(d) = (1 - |d|/h)/h, |d| < h. */
static void accumulate(aenl_moments_t *m, aenl_moments_cell_t *row, aenl_real_t u, aenl_real_t y)
{
    const aenl_real_t t = (u - m->cfg.x_min) * m->inv_dx; /* u in grid units */
    const aenl_real_t h_units = m->cfg.bandwidth * m->inv_dx;
    const int32_t k0 = node_ceil(t - h_units, m->cfg.n_grid);
    const int32_t k1 = node_floor(t + h_units, m->cfg.n_grid);
    const aenl_real_t wscale = m->scale; /* 1/h applied at query time, see the file comment */
    for (int32_t k = k0; k <= k1; ++k)
    {
        const aenl_real_t d = aenl_fabs(aenl_moments_node_x(m, (uint16_t)k) - u);
        if (d < m->cfg.bandwidth)
        {
            cell_update(&row[k], wscale * (AENL_R(1.0) - d * m->inv_h), y);
        }
    }
}

static void renormalise(aenl_moments_t *m)
{
    const uint32_t n = active_cells(m);
    for (uint32_t i = 0; i < n; ++i)
    {
        cell_scale(&m->cell[i], SCALE_SHRINK, SCALE_SHRINK * SCALE_SHRINK);
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
    const uint16_t n_grid = m->cfg.n_grid;
    for (uint16_t li = 0; li < m->cfg.n_lags; ++li)
    {
        const uint16_t lag = m->cfg.lags[li];
        if (m->n_hist <= lag)
        {
            continue;
        }
        const uint16_t p = ring_back(m->head, lag);
        if (!m->valid[p])
        {
            continue;
        }
        const aenl_real_t u = m->hist[p];
        uint32_t dir = 0u;
        if (m->n_dir == 2u)
        {
            const uint16_t q = ring_back(p, 1u);
            if (m->n_hist <= lag + 1u || !m->valid[q])
            {
                continue; /* the direction of u is unknown: the pair is not used */
            }
            dir = (u > m->hist[q]) ? 0u : 1u; /* 0 rising, 1 falling (ties fall) */
        }
        aenl_moments_cell_t *row = &m->cell[((uint32_t)li * m->n_dir + dir) * n_grid];
        accumulate(m, row, u, sample);
    }
    return AENL_OK;
}

aenl_status_t aenl_moments_query(const aenl_moments_t *m, uint16_t lag_index, uint16_t node,
                                 aenl_dir_t dir, aenl_moments_point_t *out)
{
    if (m == NULL || out == NULL || lag_index >= m->cfg.n_lags || node >= m->cfg.n_grid)
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
    const uint16_t n_grid = m->cfg.n_grid;
    const aenl_moments_cell_t *a = &m->cell[((uint32_t)lag_index * m->n_dir) * n_grid + node];
    aenl_real_t w, mean, m2, w2;
    if (dir == AENL_DIR_ALL && m->n_dir == 2u)
    {
        /* Merge rising and falling (Chan et al.'s pairwise combination). */
        const aenl_moments_cell_t *b = a + n_grid;
        const aenl_real_t wa = cell_w(a);
        const aenl_real_t wb = cell_w(b);
        w = wa + wb;
        if (w > AENL_R(0.0))
        {
            const aenl_real_t ma = cell_mean(a);
            const aenl_real_t mb = cell_mean(b);
            const aenl_real_t d = mb - ma;
            mean = ma + d * (wb / w);
            m2 = cell_m2(a) + cell_m2(b) + d * d * (wa / w) * wb;
        }
        else
        {
            mean = AENL_R(0.0);
            m2 = AENL_R(0.0);
        }
        w2 = cell_w2(a) + cell_w2(b);
    }
    else
    {
        const aenl_moments_cell_t *c = (dir == AENL_DIR_FALLING) ? a + n_grid : a;
        w = cell_w(c);
        mean = cell_mean(c);
        m2 = cell_m2(c);
        w2 = cell_w2(c);
    }
    memset(out, 0, sizeof(*out));
    out->x = aenl_moments_node_x(m, node);
    if (!(w > AENL_R(0.0)) || !(w2 > AENL_R(0.0)))
    {
        return AENL_E_EMPTY;
    }
    const aenl_real_t var = (m2 > AENL_R(0.0)) ? m2 / w : AENL_R(0.0);
    const aenl_real_t n_eff = (w / w2) * w;
    const aenl_real_t se = aenl_sqrt(var / n_eff);
    /* m2 itself is checked: a NaN m2 (Inf - Inf in the compensated sums) would read as var 0. */
    if (!aenl_is_finite(mean) || !aenl_is_finite(m2) || !aenl_is_finite(var) ||
        !aenl_is_finite(n_eff) || !aenl_is_finite(se))
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
