/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_filter.c
 * @brief Butterworth low-pass as biquads (bilinear transform with pre-warping).
 *
 * Section k of an order-N design has the analog prototype 1 / (s^2 + s/Q_k + 1) with
 * Q_k = 1 / (2 cos(pi (2k + 1) / (2N))). With K = tan(pi fc) the bilinear transform gives
 *     b0 = K^2 / D, b1 = 2 b0, b2 = b0, a1 = 2 (K^2 - 1) / D, a2 = (1 - K/Q + K^2) / D,
 *     D = 1 + K/Q + K^2,
 * unit gain at DC in every section. Transposed direct form II per section:
 *     y = b0 x + z1,  z1' = b1 x - a1 y + z2,  z2' = b2 x - a2 y.
 * Priming with a constant input x0 (y = x0): z1 = (1 - b0) x0, z2 = (b2 - a2) x0.
 */
#include <string.h>

#include "aenl/aenl_filter.h"

#define PI AENL_R(3.14159265358979323846)

aenl_status_t aenl_filter_init(aenl_filter_t *f, const aenl_filter_cfg_t *cfg)
{
    if (f == NULL || cfg == NULL || !(cfg->cutoff > AENL_R(0.0) && cfg->cutoff < AENL_R(0.5)) ||
        cfg->order == 0u || (cfg->order % 2u) != 0u) /* (a NaN cutoff fails the range) */
    {
        return AENL_E_ARG;
    }
    if (cfg->order > 2u * AENL_FILTER_MAX_SECTIONS)
    {
        return AENL_E_DIM;
    }
    const aenl_real_t k = aenl_tan(PI * cfg->cutoff);
    if (!aenl_is_finite(k) || !(k > AENL_R(0.0)))
    {
        return AENL_E_ARG;
    }
    memset(f, 0, sizeof(*f));
    f->cfg = *cfg;
    f->n_sections = (uint16_t)(cfg->order / 2u);
    const aenl_real_t k2 = k * k;
    for (uint32_t s = 0; s < f->n_sections; ++s)
    {
        const aenl_real_t angle =
            PI * (aenl_real_t)(2u * s + 1u) / (aenl_real_t)(2u * (uint32_t)cfg->order);
        const aenl_real_t inv_q = AENL_R(2.0) * aenl_cos(angle); /* 1 / Q_k */
        const aenl_real_t d = AENL_R(1.0) + k * inv_q + k2;
        f->b0[s] = k2 / d;
        f->a1[s] = AENL_R(2.0) * (k2 - AENL_R(1.0)) / d;
        f->a2[s] = (AENL_R(1.0) - k * inv_q + k2) / d;
    }
    return AENL_OK;
}

void aenl_filter_reset(aenl_filter_t *f)
{
    if (f == NULL)
    {
        return;
    }
    memset(f->z1, 0, sizeof(f->z1));
    memset(f->z2, 0, sizeof(f->z2));
    f->primed = 0u;
    f->n_missing = 0u;
}

aenl_status_t aenl_filter_push(aenl_filter_t *f, aenl_real_t in, aenl_real_t *out)
{
    if (f == NULL || out == NULL)
    {
        return AENL_E_ARG;
    }
    if (!aenl_is_finite(in))
    {
        if (f->n_missing < UINT32_MAX)
        {
            f->n_missing++;
        }
        *out = in;
        return AENL_E_NUMERIC;
    }
    if (!f->primed)
    {
        for (uint32_t s = 0; s < f->n_sections; ++s)
        {
            f->z1[s] = (AENL_R(1.0) - f->b0[s]) * in;
            f->z2[s] = (f->b0[s] - f->a2[s]) * in;
        }
        f->primed = 1u;
    }
    aenl_real_t x = in;
    for (uint32_t s = 0; s < f->n_sections; ++s)
    {
        const aenl_real_t b0 = f->b0[s];
        const aenl_real_t y = b0 * x + f->z1[s];
        f->z1[s] = AENL_R(2.0) * b0 * x - f->a1[s] * y + f->z2[s];
        f->z2[s] = b0 * x - f->a2[s] * y;
        x = y;
    }
    *out = x;
    return AENL_OK;
}
