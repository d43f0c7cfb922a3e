/* SPDX-License-Identifier: MIT */
/**
 * @file fuzz_moments.c
 * @brief libFuzzer target: aenl_moments init / push / reset / query with arbitrary configurations
 *        and sample streams. Built twice (AENL_USE_DOUBLE 0 and 1) by tools/scripts/run_fuzz.sh.
 *
 * Input layout (every read past the end gives zeros):
 *   byte 0        flags: bit 0 raw configuration (reals taken bit for bit), else structured;
 *                 bit 1 direction split, bit 2 forgetting < 1 (structured only)
 *   ...           the configuration (see read_cfg)
 *   then ops      one op byte each, high 3 bits select: 0-2 a sample inside (or near) the grid,
 *                 3 a raw real (any bit pattern), 4 NaN, 5 +-Inf, 6 reset, 7 a query
 *
 * Properties checked (abort() on violation, which libFuzzer reports as a crash):
 *  - init returns AENL_OK, AENL_E_ARG or AENL_E_DIM; on error the state is not written;
 *  - a NaN/Inf push returns AENL_E_NUMERIC and leaves every statistic byte-identical;
 *  - a query returns AENL_OK, AENL_E_EMPTY or (bad index / direction) AENL_E_ARG and nothing else;
 *    AENL_E_ARG leaves *out untouched; AENL_E_EMPTY gives x only, the rest zero;
 *  - AENL_OK gives finite mean, var, weight, n_eff and se, var >= 0, n_eff > 0, a mean inside the
 *    range of the finite samples fed since the last reset and var <= (range/2)^2 (Popoviciu),
 *    both with a small rounding allowance; AENL_E_NUMERIC ("produced") is accepted only when a
 *    finite sample beyond the documented magnitude limit was pushed;
 *  - after reset every query is AENL_E_EMPTY.
 */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FUZZ_NAME "fuzz_moments"
#include "fuzz_common.h"

#include "aenl/aenl_moments.h"

static void read_cfg(input_t *in, uint8_t flags, aenl_moments_cfg_t *cfg)
{
    memset(cfg, 0, sizeof(*cfg));
    if (flags & 1u)
    {
        cfg->x_min = take_raw_real(in);
        cfg->x_max = take_raw_real(in);
        cfg->n_grid = take_u16(in);
        cfg->bandwidth = take_raw_real(in);
        cfg->n_lags = take_u16(in);
        for (size_t i = 0; i < AENL_MOMENTS_MAX_LAGS; ++i)
        {
            cfg->lags[i] = take_u16(in);
        }
        cfg->forgetting = take_raw_real(in);
        cfg->direction_split = take_u8(in);
        return;
    }
    const aenl_real_t span = (aenl_real_t)(take_u8(in) + 1) / AENL_R(16.0);
    cfg->x_min = (aenl_real_t)(int8_t)take_u8(in) / AENL_R(8.0);
    cfg->x_max = cfg->x_min + span;
    cfg->n_grid = (uint16_t)(take_u16(in) % (AENL_MOMENTS_MAX_GRID + 4u));
    cfg->bandwidth = span * (aenl_real_t)(take_u8(in) + 1) / AENL_R(64.0);
    cfg->n_lags = (uint16_t)(take_u8(in) % (AENL_MOMENTS_MAX_LAGS + 2u));
    for (size_t i = 0; i < cfg->n_lags && i < AENL_MOMENTS_MAX_LAGS; ++i)
    {
        cfg->lags[i] = (uint16_t)(take_u16(in) % (AENL_MOMENTS_MAX_LAG + 3u));
    }
    cfg->forgetting =
        (flags & 4u) ? AENL_R(1.0) - (aenl_real_t)(take_u8(in) + 1) / AENL_R(512.0) : AENL_R(1.0);
    cfg->direction_split = (flags & 2u) ? 1u : 0u;
}

/* Range of the finite samples fed since the last reset. */
typedef struct
{
    int any;
    aenl_real_t lo, hi;
    int beyond_limit; /* a finite sample past the magnitude the statistics can hold was fed */
} range_t;

/* Samples up to this magnitude must never overflow the statistics (see the report): the square of
 * twice the limit, times a weight sum of 2^52, stays below the largest real. */
#if AENL_USE_DOUBLE
#define SAMPLE_LIMIT AENL_R(1e120)
#else
#define SAMPLE_LIMIT AENL_R(1e10)
#endif

static void range_add(range_t *r, aenl_real_t v)
{
    if (!r->any)
    {
        r->lo = v;
        r->hi = v;
        r->any = 1;
    }
    r->lo = v < r->lo ? v : r->lo;
    r->hi = v > r->hi ? v : r->hi;
    if (aenl_fabs(v) > SAMPLE_LIMIT)
    {
        r->beyond_limit = 1;
    }
}

static void check_point(const aenl_moments_t *m, const range_t *r, uint16_t li, uint16_t k,
                        aenl_dir_t dir)
{
    aenl_moments_point_t p;
    memset(&p, 0x5A, sizeof(p));
    const aenl_status_t st = aenl_moments_query(m, li, k, dir, &p);
    const int valid_args =
        li < m->cfg.n_lags && k < m->cfg.n_grid &&
        (dir == AENL_DIR_ALL ||
         (m->cfg.direction_split && (dir == AENL_DIR_RISING || dir == AENL_DIR_FALLING)));
    if (!valid_args)
    {
        aenl_moments_point_t untouched;
        memset(&untouched, 0x5A, sizeof(untouched));
        CHECK(st == AENL_E_ARG, "query with bad arguments is not AENL_E_ARG");
        CHECK(memcmp(&p, &untouched, sizeof(p)) == 0, "rejected query wrote *out");
        return;
    }
    const aenl_real_t x = aenl_moments_node_x(m, k);
    if (st == AENL_E_EMPTY)
    {
        CHECK(memcmp(&p.x, &x, sizeof(x)) == 0, "empty query: x is not the node");
        CHECK(p.mean == AENL_R(0.0) && p.var == AENL_R(0.0) && p.weight == AENL_R(0.0) &&
                  p.n_eff == AENL_R(0.0) && p.se == AENL_R(0.0),
              "empty query: fields not zero");
        return;
    }
    if (st == AENL_E_NUMERIC && r->beyond_limit)
    {
        return;
    }
    if (st != AENL_OK)
    {
        fprintf(stderr, "lag %u node %u dir %d: status %s\n", (unsigned)li, (unsigned)k, (int)dir,
                aenl_status_str(st));
    }
    CHECK(st == AENL_OK, "query status is not OK/EMPTY/ARG");
    if (!(aenl_is_finite(p.mean) && aenl_is_finite(p.var) && aenl_is_finite(p.weight) &&
          aenl_is_finite(p.n_eff) && aenl_is_finite(p.se) && p.var >= AENL_R(0.0)))
    {
        fprintf(stderr, "lag %u node %u dir %d: mean %g var %g weight %g n_eff %g se %g\n",
                (unsigned)li, (unsigned)k, (int)dir, (double)p.mean, (double)p.var,
                (double)p.weight, (double)p.n_eff, (double)p.se);
    }
    CHECK(r->any, "a query has weight but no finite sample was fed");
    CHECK(aenl_is_finite(p.mean) && aenl_is_finite(p.var) && aenl_is_finite(p.weight) &&
              aenl_is_finite(p.n_eff) && aenl_is_finite(p.se),
          "non-finite estimate from finite samples");
    CHECK(p.var >= AENL_R(0.0), "negative variance");
    CHECK(p.n_eff > AENL_R(0.0), "n_eff not positive");
    CHECK(p.weight >= AENL_R(0.0), "negative weight");
    /* Rounding allowance: a few ulps of the magnitudes involved, per accumulated step. */
    const double lo = (double)r->lo, hi = (double)r->hi;
    const double mag = fabs(lo) > fabs(hi) ? fabs(lo) : fabs(hi);
    const double width = hi - lo;
    const double tol = 1e-3 * width + 64.0 * (double)AENL_REAL_EPS * mag;
    if (isfinite(width) && isfinite(tol))
    {
        CHECK((double)p.mean >= lo - tol && (double)p.mean <= hi + tol,
              "conditional mean outside the range of the samples");
        const double half = 0.5 * width + tol;
        CHECK((double)p.var <= half * half * 1.01 + 1e-30, "variance above (range/2)^2");
    }
}

static void check_all(const aenl_moments_t *m, const range_t *r)
{
    const int n_dir = m->cfg.direction_split ? 3 : 1;
    for (uint16_t li = 0; li < m->cfg.n_lags; ++li)
    {
        for (uint16_t k = 0; k < m->cfg.n_grid; ++k)
        {
            for (int d = 0; d < n_dir; ++d)
            {
                check_point(m, r, li, k, (aenl_dir_t)d);
            }
        }
    }
}

static aenl_moments_t g_m;
static aenl_moments_t g_before;

/* The sums in use: two per (direction, node) and two per (lag series, direction, node). */
static size_t active_sums(const aenl_moments_t *m)
{
    return 2u * (1u + aenl_moments_n_series(m)) * m->cfg.n_grid *
           (m->cfg.direction_split ? 2u : 1u);
}

/* AENL_FUZZ_TRACE=1 in the environment prints the configuration and every push (for replaying
 * a crash input: ./fuzz_moments_f64 crash-file). */
static int trace_on(void)
{
    static int on = -1;
    if (on < 0)
    {
        on = getenv("AENL_FUZZ_TRACE") != NULL ? 1 : 0;
    }
    return on;
}

static void trace_push(aenl_real_t v, aenl_status_t st)
{
    if (trace_on())
    {
        fprintf(stderr, "push %.17g -> %s\n", (double)v, aenl_status_str(st));
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    input_t in = {data, size};
    aenl_moments_cfg_t cfg;
    const uint8_t flags = take_u8(&in);
    read_cfg(&in, flags, &cfg);
    if (trace_on())
    {
        fprintf(stderr, "cfg x %.17g..%.17g n_grid %u h %.17g n_lags %u (", (double)cfg.x_min,
                (double)cfg.x_max, (unsigned)cfg.n_grid, (double)cfg.bandwidth,
                (unsigned)cfg.n_lags);
        for (size_t i = 0; i < cfg.n_lags && i < AENL_MOMENTS_MAX_LAGS; ++i)
        {
            fprintf(stderr, " %u", (unsigned)cfg.lags[i]);
        }
        fprintf(stderr, " ) lambda %.17g split %u\n", (double)cfg.forgetting,
                (unsigned)cfg.direction_split);
    }

    /* init on garbage: an error must leave the state unwritten. */
    memset(&g_m, 0xA5, sizeof(g_m));
    aenl_status_t st = aenl_moments_init(&g_m, &cfg);
    if (st != AENL_OK)
    {
        CHECK(st == AENL_E_ARG || st == AENL_E_DIM, "init status is not OK/ARG/DIM");
        memset(&g_before, 0xA5, sizeof(g_before));
        CHECK(memcmp(&g_m, &g_before, sizeof(g_m)) == 0, "failed init wrote the state");
        return 0;
    }
    CHECK(g_m.n_samples == 0u && g_m.n_missing == 0u, "init left counters");

    range_t r = {0, AENL_R(0.0), AENL_R(0.0), 0};
    const aenl_real_t span = g_m.cfg.x_max - g_m.cfg.x_min;
    const aenl_real_t mid = g_m.cfg.x_min + AENL_R(0.5) * span;
    aenl_real_t last = mid;
    while (in.n > 0u)
    {
        const uint8_t op = take_u8(&in);
        switch (op >> 5)
        {
            case 0:
            case 1:
            case 2:
            {
                /* Inside or near the grid: mid + [-1, 1) * span; low bits repeat it. A grid
                 * that spans most of the float32 range puts that beyond it (-inf): rejected. */
                const aenl_real_t v =
                    mid + (aenl_real_t)(int16_t)take_u16(&in) / AENL_R(32768.0) * span;
                const unsigned reps = 1u + (op & 7u);
                for (unsigned i = 0; i < reps; ++i)
                {
                    st = aenl_moments_push(&g_m, v);
                    trace_push(v, st);
                    CHECK(!aenl_is_finite(v) || st == AENL_OK, "finite push not OK");
                    CHECK(aenl_is_finite(v) || st == AENL_E_NUMERIC,
                          "overflowed push not E_NUMERIC");
                }
                if (aenl_is_finite(v))
                {
                    range_add(&r, v);
                    last = v;
                }
                break;
            }
            case 3:
            {
                const aenl_real_t v = (op & 1u) ? take_raw_real(&in) : last;
                st = aenl_moments_push(&g_m, v);
                trace_push(v, st);
                if (aenl_is_finite(v))
                {
                    CHECK(st == AENL_OK, "finite raw push not OK");
                    range_add(&r, v);
                    last = v;
                }
                else
                {
                    CHECK(st == AENL_E_NUMERIC, "non-finite raw push not E_NUMERIC");
                }
                break;
            }
            case 4:
            case 5:
            {
                const aenl_real_t v = (op >> 5) == 4u ? (aenl_real_t)NAN
                                      : (op & 1u)     ? (aenl_real_t)INFINITY
                                                      : -(aenl_real_t)INFINITY;
                const size_t ns = active_sums(&g_m);
                const uint32_t n_samples = g_m.n_samples;
                const uint32_t n_missing = g_m.n_missing;
                memcpy(g_before.sum, g_m.sum, ns * sizeof(g_m.sum[0]));
#if AENL_MOMENTS_COMPENSATED
                memcpy(g_before.sum_lo, g_m.sum_lo, ns * sizeof(g_m.sum_lo[0]));
#endif
                st = aenl_moments_push(&g_m, v);
                trace_push(v, st);
                CHECK(st == AENL_E_NUMERIC, "NaN/Inf push not E_NUMERIC");
                int same = memcmp(g_before.sum, g_m.sum, ns * sizeof(g_m.sum[0])) == 0;
#if AENL_MOMENTS_COMPENSATED
                same = same && memcmp(g_before.sum_lo, g_m.sum_lo, ns * sizeof(g_m.sum_lo[0])) == 0;
#endif
                CHECK(same, "NaN/Inf push changed statistics");
                CHECK(g_m.n_samples == n_samples, "NaN/Inf push counted as a sample");
                CHECK(g_m.n_missing == n_missing + (n_missing < UINT32_MAX ? 1u : 0u),
                      "NaN/Inf push not counted as missing");
                break;
            }
            case 6:
                aenl_moments_reset(&g_m);
                if (trace_on())
                {
                    fprintf(stderr, "reset\n");
                }
                r.any = 0;
                r.beyond_limit = 0;
                CHECK(g_m.n_samples == 0u && g_m.n_missing == 0u, "reset left counters");
                if (op & 1u)
                {
                    check_all(&g_m, &r); /* every query is EMPTY now */
                }
                break;
            default:
            {
                const uint16_t li = (uint16_t)(take_u8(&in) % (g_m.cfg.n_lags + 1u));
                const uint16_t k = (uint16_t)(take_u16(&in) % (g_m.cfg.n_grid + 1u));
                check_point(&g_m, &r, li, k, (aenl_dir_t)(op & 3u));
                break;
            }
        }
    }
    check_all(&g_m, &r);
    return 0;
}
