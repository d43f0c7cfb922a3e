/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_bench_cfg.h
 * @brief The moments configuration the float32 benches share (the long-stream accuracy bench and
 *        the emulated Cortex-M4F cost run), so that their figures describe the same estimator.
 */
#ifndef AENL_BENCH_CFG_H
#define AENL_BENCH_CFG_H

#include <string.h>

#include "aenl/aenl_moments.h"

/** The standard configuration over [x_min, x_max]: 64 nodes, bandwidth three node spacings,
 *  lags 1, 10 and 30, the direction split, no forgetting. */
static inline void aenl_bench_std_moments(aenl_moments_cfg_t *c, aenl_real_t x_min,
                                          aenl_real_t x_max)
{
    memset(c, 0, sizeof(*c));
    c->x_min = x_min;
    c->x_max = x_max;
    c->n_grid = 64u;
    c->bandwidth = AENL_R(3.0) * (x_max - x_min) / AENL_R(63.0);
    c->n_lags = 3u;
    c->lags[0] = 1u;
    c->lags[1] = 10u;
    c->lags[2] = 30u;
    c->forgetting = AENL_R(1.0);
    c->direction_split = 1u;
}

#endif /* AENL_BENCH_CFG_H */
