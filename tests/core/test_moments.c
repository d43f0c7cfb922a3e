/* SPDX-License-Identifier: MIT */
/**
 * @file test_moments.c
 * @brief aenl_moments against a brute-force evaluation of the paper's formula (10) and its variance
 *        analogue, plus argument, missing-sample and long-stream checks. Builds as f32 and f64.
 */
#include <string.h>

#include "aenl_test.h"

#include "aenl/aenl_moments.h"

static aenl_moments_t g_m;

void setUp(void)
{
    memset(&g_m, 0xA5, sizeof(g_m));
}

void tearDown(void)
{
}

/* ---- deterministic test signal ------------------------------------------------------------- */

/* A damped two-frequency oscillation driven by noise: an AR(2) process plus measurement noise. */
static void make_signal(aenl_real_t *x, size_t n, uint64_t seed, double offset)
{
    g_lcg = seed;
    double y1 = 0.0, y2 = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        const double y = 1.6 * y1 - 0.8 * y2 + 0.3 * lcg_normal();
        y2 = y1;
        y1 = y;
        x[i] = (aenl_real_t)(offset + y + 0.1 * lcg_normal());
    }
}

/* ---- brute force: formula (10), its variance analogue, optional direction and forgetting ---- */

typedef struct
{
    double mean, var, w, n_eff;
    int empty;
} ref_point_t;

/* Weight of the pair (x[c], x[c + lag]) for the reference: 0 when it is not in the estimate.
 * The estimator conditions every lag on the same samples c = 0 (1 with the split) .. n-1-max_lag,
 * and forms them at push c + max_lag, whose age sets the forgetting weight. */
/* With the symmetric option the conditioning samples also need max_lag samples before them. */
static int g_sym;

static double pair_weight(const aenl_real_t *x, size_t n, size_t c, unsigned max_lag, double node,
                          double h, int dir, int split, double lambda)
{
    if (c + max_lag >= n || (split && c == 0) || (g_sym && c < max_lag))
    {
        return 0.0;
    }
    const double u = (double)x[c];
    if (split)
    {
        const int rising = u > (double)x[c - 1u];
        if ((dir == 1 && !rising) || (dir == 2 && rising))
        {
            return 0.0;
        }
    }
    const double d = u > node ? u - node : node - u;
    if (!(d < h))
    {
        return 0.0;
    }
    double w = (1.0 - d / h) / h;
    if (lambda < 1.0)
    {
        w *= pow(lambda, (double)(n - 1u - (c + max_lag)));
    }
    return w;
}

/* Formula (10) and its variance analogue by direct summation over the pairs, two-pass. */
static ref_point_t brute(const aenl_real_t *x, size_t n, long lag, unsigned max_lag, double node,
                         double h, int dir /* 0 all, 1 rising, 2 falling */, int split,
                         double lambda)
{
    ref_point_t r = {0.0, 0.0, 0.0, 0.0, 1};
    double sw = 0.0, swy = 0.0, sw2 = 0.0;
    for (size_t c = 0; c < n; ++c)
    {
        const double w = pair_weight(x, n, c, max_lag, node, h, dir, split, lambda);
        if (w > 0.0)
        {
            sw += w;
            swy += w * (double)x[(long)c + lag];
            sw2 += w * w;
        }
    }
    if (sw > 0.0)
    {
        r.empty = 0;
        r.w = sw;
        r.mean = swy / sw;
        double s = 0.0;
        for (size_t c = 0; c < n; ++c)
        {
            const double w = pair_weight(x, n, c, max_lag, node, h, dir, split, lambda);
            const double e = (w > 0.0) ? (double)x[(long)c + lag] - r.mean : 0.0;
            s += w * e * e;
        }
        r.var = s / sw;
        r.n_eff = sw * sw / sw2;
    }
    return r;
}

static aenl_moments_cfg_t std_cfg(aenl_real_t x_min, aenl_real_t x_max, uint16_t n_grid)
{
    aenl_moments_cfg_t c;
    memset(&c, 0, sizeof(c));
    c.x_min = x_min;
    c.x_max = x_max;
    c.n_grid = n_grid;
    c.bandwidth = AENL_R(3.0) * (x_max - x_min) / (aenl_real_t)(n_grid - 1u);
    c.n_lags = 3;
    c.lags[0] = 1;
    c.lags[1] = 10;
    c.lags[2] = 30;
    c.forgetting = AENL_R(1.0);
    c.direction_split = 1;
    return c;
}

/* Compare every (lag, node, dir) with the brute force. Tolerances are relative to the signal's
 * scale for the mean (which may cross zero) and to the value for the variance. */
static void compare_all(const aenl_moments_t *m, const aenl_real_t *x, size_t n, double lambda,
                        double scale)
{
    const double tol = AENL_TEST_REL_TOL;
    int n_checked = 0;
    g_sym = m->cfg.symmetric;
    for (uint16_t li = 0; li < aenl_moments_n_series(m); ++li)
    {
        for (int dir = 0; dir < (m->cfg.direction_split ? 3 : 1); ++dir)
        {
            for (uint16_t k = 0; k < m->cfg.n_grid; ++k)
            {
                aenl_moments_point_t p;
                const aenl_status_t st = aenl_moments_query(m, li, k, (aenl_dir_t)dir, &p);
                const ref_point_t r =
                    brute(x, n, aenl_moments_lag(m, li), m->max_lag, (double)p.x,
                          (double)m->cfg.bandwidth, dir, m->cfg.direction_split, lambda);
                if (r.empty)
                {
                    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, st);
                    continue;
                }
                TEST_ASSERT_EQUAL_INT(AENL_OK, st);
                TEST_ASSERT_DOUBLE_WITHIN(tol * (fabs(r.mean) + scale), r.mean, (double)p.mean);
                TEST_ASSERT_DOUBLE_WITHIN(tol * (r.var + 1e-3 * scale * scale) * 4.0, r.var,
                                          (double)p.var);
                TEST_ASSERT_DOUBLE_WITHIN(tol * r.n_eff * 4.0, r.n_eff, (double)p.n_eff);
                TEST_ASSERT_DOUBLE_WITHIN(sqrt(r.var / r.n_eff) * tol * 8.0 + tol * scale * 1e-3,
                                          sqrt(r.var / r.n_eff), (double)p.se);
                n_checked++;
            }
        }
    }
    /* Most nodes hold data (the brute force agrees on which ones are empty). */
    TEST_ASSERT_GREATER_THAN_INT(m->cfg.n_lags * m->cfg.n_grid / 2, n_checked);
}

#define N_SIG 4000u
static aenl_real_t g_x[N_SIG];

static void test_moments_matches_brute_force(void)
{
    make_signal(g_x, N_SIG, 12345u, 0.25);
    const aenl_moments_cfg_t c = std_cfg(AENL_R(-2.5), AENL_R(3.0), 48);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    for (size_t i = 0; i < N_SIG; ++i)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, g_x[i]));
    }
    compare_all(&g_m, g_x, N_SIG, 1.0, 1.0);
}

/* Backward series: X_{c-L} given X_c, on the same conditioning samples as the forward ones. */
static void test_moments_symmetric_matches_brute_force(void)
{
    make_signal(g_x, N_SIG, 4242u, 0.1);
    aenl_moments_cfg_t c = std_cfg(AENL_R(-2.5), AENL_R(3.0), 24);
    c.symmetric = 1;
    c.n_lags = 3;
    c.lags[0] = 2;
    c.lags[1] = 5;
    c.lags[2] = 9;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    TEST_ASSERT_EQUAL_UINT(6u, aenl_moments_n_series(&g_m));
    TEST_ASSERT_EQUAL_INT(-5, aenl_moments_lag(&g_m, 4u));
    for (size_t i = 0; i < N_SIG; ++i)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, g_x[i]));
    }
    compare_all(&g_m, g_x, N_SIG, 1.0, 1.0);
    /* series 6 does not exist */
    aenl_moments_point_t p;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_query(&g_m, 6u, 0u, AENL_DIR_ALL, &p));
    c.symmetric = 2;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
}

static void test_moments_no_split_matches_brute_force(void)
{
    make_signal(g_x, N_SIG, 777u, -0.5);
    aenl_moments_cfg_t c = std_cfg(AENL_R(-3.0), AENL_R(2.0), 31);
    c.direction_split = 0;
    c.n_lags = 2;
    c.lags[0] = 7;
    c.lags[1] = 2;
    c.bandwidth = AENL_R(0.37); /* not a multiple of the spacing */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    for (size_t i = 0; i < N_SIG; ++i)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, g_x[i]));
    }
    compare_all(&g_m, g_x, N_SIG, 1.0, 1.0);
}

static void test_moments_forgetting_matches_brute_force(void)
{
    /* lambda^-4000 = e^20 > 2^20: the cells are renormalised at least once on the way. */
    make_signal(g_x, N_SIG, 99u, 0.0);
    aenl_moments_cfg_t c = std_cfg(AENL_R(-2.0), AENL_R(2.0), 24);
    c.forgetting = AENL_R(0.995);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    for (size_t i = 0; i < N_SIG; ++i)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, g_x[i]));
    }
    TEST_ASSERT_GREATER_OR_EQUAL_UINT32(1u, g_m.n_renorm);
    compare_all(&g_m, g_x, N_SIG, (double)c.forgetting, 1.0);
}

static void test_moments_constant_input_zero_variance(void)
{
    const aenl_moments_cfg_t c = std_cfg(AENL_R(0.0), AENL_R(2.0), 16);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    for (int i = 0; i < 500; ++i)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, AENL_R(1.0)));
    }
    aenl_moments_point_t p;
    /* Constant: every pair is "falling" (ties fall), none rising. */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_query(&g_m, 0, 7, AENL_DIR_ALL, &p));
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-6), AENL_R(1.0), p.mean);
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-12), AENL_R(0.0), p.var);
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-12), AENL_R(0.0), p.se);
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_moments_query(&g_m, 0, 7, AENL_DIR_RISING, &p));
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_moments_query(&g_m, 0, 0, AENL_DIR_ALL, &p));
}

static void test_moments_init_on_garbage_memory(void)
{
    /* setUp filled g_m with 0xA5; a fresh init must behave exactly like one on zeroed memory. */
    static aenl_moments_t zeroed;
    memset(&zeroed, 0, sizeof(zeroed));
    const aenl_moments_cfg_t c = std_cfg(AENL_R(-1.0), AENL_R(1.0), 21);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&zeroed, &c));
    make_signal(g_x, 300, 5u, 0.0);
    for (size_t i = 0; i < 300; ++i)
    {
        aenl_moments_push(&g_m, g_x[i]);
        aenl_moments_push(&zeroed, g_x[i]);
    }
    TEST_ASSERT_EQUAL_MEMORY(&zeroed, &g_m, sizeof(g_m));
}

static void test_moments_init_rejects_bad_config(void)
{
    static aenl_moments_t before;
    const aenl_moments_cfg_t good = std_cfg(AENL_R(-1.0), AENL_R(1.0), 21);
    aenl_moments_cfg_t c;
    memcpy(&before, &g_m, sizeof(g_m));

    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(NULL, &good));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, NULL));
    c = good;
    c.x_max = c.x_min;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.x_min = (aenl_real_t)NAN;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.x_max = (aenl_real_t)INFINITY;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.n_grid = 2;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.n_grid = AENL_MOMENTS_MAX_GRID + 1;
    TEST_ASSERT_EQUAL_INT(AENL_E_DIM, aenl_moments_init(&g_m, &c));
    c = good;
    c.bandwidth = AENL_R(0.0);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.bandwidth = AENL_R(-0.1);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.bandwidth = (aenl_real_t)NAN;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.n_lags = 0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.n_lags = AENL_MOMENTS_MAX_LAGS + 1;
    TEST_ASSERT_EQUAL_INT(AENL_E_DIM, aenl_moments_init(&g_m, &c));
    c = good;
    c.lags[1] = 0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.lags[2] = c.lags[0];
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.lags[2] = AENL_MOMENTS_MAX_LAG + 1;
    TEST_ASSERT_EQUAL_INT(AENL_E_DIM, aenl_moments_init(&g_m, &c));
    c = good;
    c.forgetting = AENL_R(0.0);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.forgetting = AENL_R(1.5);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good; /* fuzz_moments: 1/lambda overflowed the weight scale to Inf */
    c.forgetting = AENL_MOMENTS_MIN_FORGETTING * AENL_R(0.5);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    c = good;
    c.direction_split = 2;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_init(&g_m, &c));
    /* Too many cells for the compile-time pool, each dimension within its own limit. */
    c = good;
    c.n_grid = AENL_MOMENTS_MAX_GRID;
    c.n_lags = AENL_MOMENTS_MAX_LAGS;
    for (uint16_t i = 0; i < c.n_lags; ++i)
    {
        c.lags[i] = (uint16_t)(i + 1u);
    }
    if ((uint32_t)c.n_grid * c.n_lags * 2u > AENL_MOMENTS_MAX_CELLS)
    {
        TEST_ASSERT_EQUAL_INT(AENL_E_DIM, aenl_moments_init(&g_m, &c));
    }
    /* None of the rejected calls wrote anything. */
    TEST_ASSERT_EQUAL_MEMORY(&before, &g_m, sizeof(g_m));
}

static void test_moments_missing_sample_keeps_statistics(void)
{
    static aenl_moments_t snap;
    const aenl_moments_cfg_t c = std_cfg(AENL_R(-3.0), AENL_R(3.0), 32);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    make_signal(g_x, 500, 3u, 0.0);
    for (size_t i = 0; i < 500; ++i)
    {
        aenl_moments_push(&g_m, g_x[i]);
    }
    memcpy(&snap, &g_m, sizeof(g_m));
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_moments_push(&g_m, (aenl_real_t)NAN));
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_moments_push(&g_m, (aenl_real_t)INFINITY));
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_moments_push(&g_m, -(aenl_real_t)INFINITY));
    /* Statistics byte-identical; the counters say what happened. */
    TEST_ASSERT_EQUAL_MEMORY(snap.sum, g_m.sum, sizeof(g_m.sum));
#if AENL_MOMENTS_COMPENSATED
    TEST_ASSERT_EQUAL_MEMORY(snap.sum_lo, g_m.sum_lo, sizeof(g_m.sum_lo));
#endif
    TEST_ASSERT_EQUAL_UINT32(snap.n_samples, g_m.n_samples);
    TEST_ASSERT_EQUAL_UINT32(3u, g_m.n_missing);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_push(NULL, AENL_R(1.0)));
}

static void test_moments_no_pair_across_a_gap(void)
{
    aenl_moments_cfg_t c = std_cfg(AENL_R(-1.0), AENL_R(1.0), 11);
    c.direction_split = 0;
    c.n_lags = 2;
    c.lags[0] = 1;
    c.lags[1] = 2;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    /* a, gap, b: lag 1 sees (a,gap) and (gap,b): no pair; lag 2 sees (a, b), but the lags share
     * their weight sums, so a conditioning sample pairs at every lag or at none, and a's lag-1
     * response is missing: no pair at either lag. */
    aenl_moments_push(&g_m, AENL_R(0.0));
    aenl_moments_push(&g_m, (aenl_real_t)NAN);
    aenl_moments_push(&g_m, AENL_R(0.5));
    aenl_moments_point_t p;
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_moments_query(&g_m, 0, 5, AENL_DIR_ALL, &p));
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_moments_query(&g_m, 1, 5, AENL_DIR_ALL, &p));
    /* Then 0, 0.25, 0.5: the conditioning samples 0.5 (weight 1/6 at node 5, x = 0, h = 0.6) and
     * 0 (weight 1) pair at both lags. */
    aenl_moments_push(&g_m, AENL_R(0.0));
    aenl_moments_push(&g_m, AENL_R(0.25));
    aenl_moments_push(&g_m, AENL_R(0.5));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_query(&g_m, 0, 5, AENL_DIR_ALL, &p));
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-5), (aenl_real_t)(0.25 / (7.0 / 6.0)), p.mean);
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-5), (aenl_real_t)(49.0 / 37.0), p.n_eff);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_query(&g_m, 1, 5, AENL_DIR_ALL, &p));
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-5), (aenl_real_t)((0.25 / 6.0 + 0.5) / (7.0 / 6.0)), p.mean);
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-5), (aenl_real_t)(49.0 / 37.0), p.n_eff);
}

static void test_moments_query_rejects_bad_arguments(void)
{
    aenl_moments_cfg_t c = std_cfg(AENL_R(-1.0), AENL_R(1.0), 11);
    c.direction_split = 0;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    aenl_moments_point_t p[2];
    memset(p, 0x5A, sizeof(p));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_query(NULL, 0, 0, AENL_DIR_ALL, &p[0]));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_query(&g_m, 0, 0, AENL_DIR_ALL, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_query(&g_m, 3, 0, AENL_DIR_ALL, &p[0]));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_query(&g_m, 0, 11, AENL_DIR_ALL, &p[0]));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_query(&g_m, 0, 0, AENL_DIR_RISING, &p[0]));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_query(&g_m, 0, 0, (aenl_dir_t)7, &p[0]));
    /* Rejected queries wrote nothing; an accepted one writes exactly one point (guard intact). */
    uint8_t guard[sizeof(p[1])];
    memset(guard, 0x5A, sizeof(guard));
    TEST_ASSERT_EQUAL_MEMORY(guard, &p[0], sizeof(guard));
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_moments_query(&g_m, 0, 4, AENL_DIR_ALL, &p[0]));
    TEST_ASSERT_EQUAL_MEMORY(guard, &p[1], sizeof(guard));
}

static void test_moments_reset_keeps_config(void)
{
    const aenl_moments_cfg_t c = std_cfg(AENL_R(-3.0), AENL_R(3.0), 32);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    make_signal(g_x, 200, 8u, 0.0);
    for (size_t i = 0; i < 200; ++i)
    {
        aenl_moments_push(&g_m, g_x[i]);
    }
    aenl_moments_reset(&g_m);
    aenl_moments_reset(NULL);
    static aenl_moments_t fresh;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&fresh, &c));
    TEST_ASSERT_EQUAL_MEMORY(&fresh, &g_m, sizeof(g_m));
}

static void test_moments_far_outlier_is_harmless(void)
{
    aenl_moments_cfg_t c = std_cfg(AENL_R(-1.0), AENL_R(1.0), 11);
    c.n_lags = 1; /* lag 1 only: the first pair forms at the third sample */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, AENL_R(1e30)));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, AENL_R(-1e30)));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, AENL_R(0.0)));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, AENL_R(0.0)));
    aenl_moments_point_t p;
    /* Pairs (-1e30 -> 0) and (0 after -1e30 -> 0): only the second lands on the grid, rising. */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_query(&g_m, 0, 5, AENL_DIR_RISING, &p));
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-6), AENL_R(0.0), p.mean);
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-6), AENL_R(1.0), p.n_eff);
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_moments_query(&g_m, 0, 5, AENL_DIR_FALLING, &p));
}

/* Independent weighted polynomial fit in double (Gauss-Jordan on the normal equations). */
/* Weighted least squares by Gauss-Jordan on the normal equations in double: the polynomial
 * 1, t, .., t^(nt-1) in t, plus the column extra[] when it is not NULL (coefficient c[nt]). */
static void wls_double_ex(const double *t, const double *extra, const double *y, const double *w,
                          int n, int nt, double *c)
{
    double a[6][7];
    memset(a, 0, sizeof(a));
    const int np = nt + (extra != NULL ? 1 : 0);
    for (int i = 0; i < n; ++i)
    {
        double pw[6] = {1.0, 0, 0, 0, 0, 0};
        for (int k = 1; k < nt; ++k)
        {
            pw[k] = pw[k - 1] * t[i];
        }
        if (extra != NULL)
        {
            pw[nt] = extra[i];
        }
        for (int r = 0; r < np; ++r)
        {
            for (int q = 0; q < np; ++q)
            {
                a[r][q] += w[i] * pw[r] * pw[q];
            }
            a[r][np] += w[i] * pw[r] * y[i];
        }
    }
    for (int col = 0; col < np; ++col)
    {
        for (int r = 0; r < np; ++r)
        {
            if (r != col)
            {
                const double f = a[r][col] / a[col][col];
                for (int q = col; q <= np; ++q)
                {
                    a[r][q] -= f * a[col][q];
                }
            }
        }
    }
    for (int r = 0; r < np; ++r)
    {
        c[r] = a[r][np] / a[r][r];
    }
}

static void wls_double(const double *t, const double *y, const double *w, int n, int nt, double *c)
{
    wls_double_ex(t, NULL, y, w, n, nt, c);
}

static void test_moments_taylor_matches_weighted_fit(void)
{
    make_signal(g_x, N_SIG, 4242u, 0.1);
    aenl_moments_cfg_t c = std_cfg(AENL_R(-2.0), AENL_R(2.0), 21);
    static const uint16_t lags[6] = {1, 2, 3, 5, 8, 13};
    c.n_lags = 6;
    memcpy(c.lags, lags, sizeof(lags));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    for (size_t i = 0; i < N_SIG; ++i)
    {
        aenl_moments_push(&g_m, g_x[i]);
    }
    int n_checked = 0;
    for (uint16_t order = 2; order <= 4; ++order)
    {
        for (int dir = 0; dir < 3; ++dir)
        {
            for (uint16_t k = 4; k < 17; ++k)
            {
                double t[6], y[6], w[6], cf[5];
                for (uint16_t li = 0; li < 6; ++li)
                {
                    aenl_moments_point_t p;
                    TEST_ASSERT_EQUAL_INT(AENL_OK,
                                          aenl_moments_query(&g_m, li, k, (aenl_dir_t)dir, &p));
                    t[li] = (double)lags[li];
                    y[li] = (double)p.mean;
                    w[li] = 1.0 / ((double)p.se * (double)p.se);
                }
                wls_double(t, y, w, 6, order + 1, cf);
                aenl_moments_taylor_t tp;
                TEST_ASSERT_EQUAL_INT(AENL_OK,
                                      aenl_moments_taylor(&g_m, k, (aenl_dir_t)dir, order, &tp));
                /* float32 normal equations lose digits with the order: tolerances grow with it. */
                const double tol = AENL_USE_DOUBLE ? 1e-8 : 2e-3 * (double)(order * order);
                TEST_ASSERT_DOUBLE_WITHIN(tol * (fabs(cf[0]) + 1.0), cf[0], (double)tp.position);
                TEST_ASSERT_DOUBLE_WITHIN(tol * (fabs(cf[1]) + 0.1), cf[1], (double)tp.velocity);
                TEST_ASSERT_DOUBLE_WITHIN(tol * (fabs(2.0 * cf[2]) + 0.01), 2.0 * cf[2],
                                          (double)tp.accel);
                TEST_ASSERT_TRUE(tp.se_accel > AENL_R(0.0));
                n_checked++;
            }
        }
    }
    TEST_ASSERT_EQUAL_INT(3 * 3 * 13, n_checked);
}

/* A clean sinusoid of amplitude 1 and period 197.3 samples (incommensurate with the sampling, so
 * 40 cycles cover every phase): per direction the expansion is the phase portrait,
 * v = +-w sqrt(1 - p^2) and a = -w^2 p, with w = 2 pi / 197.3 (analytic). */
/* Symmetric lags (negative backward series) with the nuisance column: the same weighted fit. */
static void test_moments_taylor_ex_symmetric_matches_weighted_fit(void)
{
    make_signal(g_x, N_SIG, 99u, 0.0);
    aenl_moments_cfg_t c = std_cfg(AENL_R(-2.0), AENL_R(2.0), 21);
    static const uint16_t lags[3] = {1, 3, 7};
    static const aenl_real_t rho[3] = {AENL_R(0.6), AENL_R(0.2), AENL_R(-0.05)};
    c.n_lags = 3;
    memcpy(c.lags, lags, sizeof(lags));
    c.symmetric = 1;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    for (size_t i = 0; i < N_SIG; ++i)
    {
        aenl_moments_push(&g_m, g_x[i]);
    }
    int n_checked = 0;
    for (uint16_t order = 2; order <= 3; ++order)
    {
        for (int dir = 0; dir < 3; ++dir)
        {
            for (uint16_t k = 5; k < 16; ++k)
            {
                double t[6], y[6], w[6], e[6], cf[6];
                for (uint16_t li = 0; li < 6; ++li)
                {
                    aenl_moments_point_t p;
                    TEST_ASSERT_EQUAL_INT(AENL_OK,
                                          aenl_moments_query(&g_m, li, k, (aenl_dir_t)dir, &p));
                    t[li] = (double)aenl_moments_lag(&g_m, li);
                    e[li] = (double)rho[li % 3u];
                    y[li] = (double)p.mean;
                    w[li] = 1.0 / ((double)p.se * (double)p.se);
                }
                wls_double_ex(t, e, y, w, 6, order + 1, cf);
                aenl_moments_taylor_t tp;
                TEST_ASSERT_EQUAL_INT(
                    AENL_OK, aenl_moments_taylor_ex(&g_m, k, (aenl_dir_t)dir, order, rho, &tp));
                const double tol = AENL_USE_DOUBLE ? 1e-8 : 2e-3 * (double)(order * order);
                TEST_ASSERT_DOUBLE_WITHIN(tol * (fabs(cf[0]) + 1.0), cf[0], (double)tp.position);
                TEST_ASSERT_DOUBLE_WITHIN(tol * (fabs(cf[1]) + 0.1), cf[1], (double)tp.velocity);
                TEST_ASSERT_DOUBLE_WITHIN(tol * (fabs(2.0 * cf[2]) + 0.01), 2.0 * cf[2],
                                          (double)tp.accel);
                n_checked++;
            }
        }
    }
    TEST_ASSERT_EQUAL_INT(2 * 3 * 11, n_checked);
    /* Order 4: the even columns 1, L^2, L^4 and the nuisance take 4 values on 3 distinct |L|, a
     * singular fit that must be reported, not returned as garbage. Order 5 is out of range. */
    aenl_moments_taylor_t tp;
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC,
                          aenl_moments_taylor_ex(&g_m, 8u, AENL_DIR_ALL, 4u, rho, &tp));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_taylor_ex(&g_m, 8u, AENL_DIR_ALL, 5u, rho, &tp));
}

static void test_moments_taylor_sinusoid_phase_portrait(void)
{
    const double w = 2.0 * 3.14159265358979323846 / 197.3;
    aenl_moments_cfg_t c = std_cfg(AENL_R(-1.1), AENL_R(1.1), 23); /* fits the MCU capacity */
    static const uint16_t lags[8] = {1, 2, 4, 6, 9, 13, 18, 25};
    c.n_lags = 8;
    memcpy(c.lags, lags, sizeof(lags));
    c.bandwidth = AENL_R(0.15);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    for (int i = 0; i < 8000; ++i)
    {
        aenl_moments_push(&g_m, (aenl_real_t)sin(w * i + 0.3));
    }
    int n_checked = 0;
    for (uint16_t k = 0; k < 23; ++k)
    {
        aenl_moments_taylor_t up, down, all;
        if (fabs((double)aenl_moments_node_x(&g_m, k)) > 0.7)
        {
            continue;
        }
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_taylor(&g_m, k, AENL_DIR_RISING, 4, &up));
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_taylor(&g_m, k, AENL_DIR_FALLING, 4, &down));
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_taylor(&g_m, k, AENL_DIR_ALL, 4, &all));
        const double p = (double)up.position;
        TEST_ASSERT_DOUBLE_WITHIN(0.01, (double)up.x, p);
        /* The kernel averages the concave sqrt over +-h: 0.8 % low at |x| = 0.7 (measured). */
        TEST_ASSERT_DOUBLE_WITHIN(0.01 * w, w * sqrt(1.0 - p * p), (double)up.velocity);
        TEST_ASSERT_DOUBLE_WITHIN(0.01 * w, -w * sqrt(1.0 - p * p), (double)down.velocity);
        TEST_ASSERT_DOUBLE_WITHIN(0.01 * w * w, -w * w * p, (double)up.accel);
        TEST_ASSERT_DOUBLE_WITHIN(0.01 * w * w, -w * w * (double)down.position, (double)down.accel);
        /* All pairs: zero for a stationary record, up to the unequal record ends of the lags. */
        TEST_ASSERT_DOUBLE_WITHIN(0.02 * w, 0.0, (double)all.velocity);
        n_checked++;
    }
    TEST_ASSERT_GREATER_THAN_INT(10, n_checked);
}

static void test_moments_taylor_rejects_bad_arguments(void)
{
    const aenl_moments_cfg_t c = std_cfg(AENL_R(-1.0), AENL_R(1.0), 11); /* 3 lags */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    aenl_moments_taylor_t t;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_taylor(NULL, 0, AENL_DIR_ALL, 2, &t));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_taylor(&g_m, 0, AENL_DIR_ALL, 2, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_taylor(&g_m, 11, AENL_DIR_ALL, 2, &t));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_taylor(&g_m, 5, AENL_DIR_ALL, 1, &t));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_moments_taylor(&g_m, 5, AENL_DIR_ALL, 3, &t));
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_moments_taylor(&g_m, 5, AENL_DIR_ALL, 2, &t));
}

#if !AENL_USE_DOUBLE
/* float32 over 10^8 samples of a signal with mean 10^3: the estimator stays within 1e-3 relative
 * of a double accumulation of the same pairs (checked at a spread of nodes, all lags, both
 * directions). The reference sums y - 1000 (an exact shift), so it loses nothing to cancellation.
 */
#if defined(AENL_TEST_EMULATED) || defined(AENL_TEST_SANITIZED)
#define LONG_N                                                                                     \
    1000000u /* emulated or sanitized, a hundredth: the plain host build runs the whole length */
#else
#define LONG_N 100000000u
#endif
#define LONG_CHECKED 9u

static void test_moments_float32_long_stream(void)
{
    aenl_moments_cfg_t c = std_cfg(AENL_R(996.0), AENL_R(1004.0), 64);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    static double sw[3][2][LONG_CHECKED], s1[3][2][LONG_CHECKED], s2[3][2][LONG_CHECKED];
    static float hist[64];
    memset(sw, 0, sizeof(sw));
    memset(s1, 0, sizeof(s1));
    memset(s2, 0, sizeof(s2));
    uint16_t nodes[LONG_CHECKED];
    double node_x[LONG_CHECKED];
    for (unsigned k = 0; k < LONG_CHECKED; ++k)
    {
        nodes[k] = (uint16_t)(8u + 6u * k); /* 8 .. 56: the well-sampled interior */
        node_x[k] = (double)aenl_moments_node_x(&g_m, nodes[k]);
    }
    const double h = (double)c.bandwidth;
    g_lcg = 2024u;
    double y1 = 0.0, y2 = 0.0;
    for (uint32_t n = 0; n < LONG_N; ++n)
    {
        const double y = 1.6 * y1 - 0.8 * y2 + 0.3 * (lcg_uniform() + lcg_uniform() - 1.0) * 2.45;
        y2 = y1;
        y1 = y;
        const float xf = (float)(1000.0 + y);
        aenl_moments_push(&g_m, xf);
        hist[n & 63u] = xf;
        /* Lockstep pairing, as the estimator: conditioning sample c = n - 30 for every lag. */
        if (n < 31u)
        {
            continue;
        }
        const uint32_t cnd = n - 30u;
        const double u = (double)hist[cnd & 63u];
        const int d = u > (double)hist[(cnd - 1u) & 63u] ? 0 : 1;
        for (unsigned k = 0; k < LONG_CHECKED; ++k)
        {
            const double dist = fabs(u - node_x[k]);
            if (dist < h)
            {
                const double w = (1.0 - dist / h) / h;
                for (unsigned li = 0; li < 3u; ++li)
                {
                    const double r = (double)hist[(cnd + c.lags[li]) & 63u] - 1000.0;
                    sw[li][d][k] += w;
                    s1[li][d][k] += w * r;
                    s2[li][d][k] += w * r * r;
                }
            }
        }
    }
    for (unsigned li = 0; li < 3u; ++li)
    {
        for (int d = 0; d < 2; ++d)
        {
            for (unsigned k = 0; k < LONG_CHECKED; ++k)
            {
                aenl_moments_point_t p;
                TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_query(&g_m, (uint16_t)li, nodes[k],
                                                                  (aenl_dir_t)(d + 1), &p));
                const double mean_r = s1[li][d][k] / sw[li][d][k];
                const double var = s2[li][d][k] / sw[li][d][k] - mean_r * mean_r;
                TEST_ASSERT_DOUBLE_WITHIN(1e-3 * 1000.0, 1000.0 + mean_r, (double)p.mean);
                /* The demanding part: the mean's deviation from 1000 and the variance. */
                TEST_ASSERT_DOUBLE_WITHIN(1e-3 * (fabs(mean_r) + sqrt(var)), mean_r,
                                          (double)p.mean - 1000.0);
                TEST_ASSERT_DOUBLE_WITHIN(1e-3 * var, var, (double)p.var);
                TEST_ASSERT_DOUBLE_WITHIN(1e-3 * sw[li][d][k], sw[li][d][k], (double)p.weight);
            }
        }
    }
}

/* Past 2^24 contributions per sum, where a plain float32 sum stops growing (an increment below
 * half its ulp is lost): 3 nodes a bandwidth wide, so every sample adds to every cell, 6 10^7
 * samples of 1000 + AR(1) (more contributions per cell than the standard configuration gets from
 * 10^9 samples). Mean, variance, weight and n_eff stay within 1e-4 relative of a double
 * accumulation of the same pairs (the float32 mean's own rounding at 1000, 3e-5, is the floor). */
#if defined(AENL_TEST_EMULATED) || defined(AENL_TEST_SANITIZED)
#define DEEP_N                                                                                     \
    1000000u /* emulated or sanitized, a sixtieth: the plain host build runs it whole              \
              */
#else
#define DEEP_N 60000000u
#endif

static void test_moments_float32_deep_cells(void)
{
    aenl_moments_cfg_t c = std_cfg(AENL_R(999.0), AENL_R(1001.0), 3);
    c.bandwidth = AENL_R(2.0);
    c.n_lags = 1;
    c.lags[0] = 1;
    c.direction_split = 0;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    double sw[3] = {0.0}, s1[3] = {0.0}, s2[3] = {0.0}, sw2[3] = {0.0};
    g_lcg = 77u;
    double y = 0.0;
    float prev = 0.0f;
    for (uint32_t n = 0; n < DEEP_N; ++n)
    {
        y = 0.9 * y + 0.1 * (lcg_uniform() - 0.5);
        const float xf = (float)(1000.0 + y);
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, xf));
        if (n > 0u) /* the pair (prev, xf) */
        {
            const double r = (double)xf - 1000.0;
            for (unsigned k = 0; k < 3u; ++k)
            {
                const double w = 1.0 - fabs((double)prev - (999.0 + (double)k)) / 2.0;
                sw[k] += w;
                s1[k] += w * r;
                s2[k] += w * r * r;
                sw2[k] += w * w;
            }
        }
        prev = xf;
    }
    for (unsigned k = 0; k < 3u; ++k)
    {
        aenl_moments_point_t p;
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_query(&g_m, 0, (uint16_t)k, AENL_DIR_ALL, &p));
        const double mean_r = s1[k] / sw[k];
        const double var = s2[k] / sw[k] - mean_r * mean_r;
        const double sd = sqrt(var);
        TEST_ASSERT_DOUBLE_WITHIN(1e-4 * sd + 3.1e-5, mean_r, (double)p.mean - 1000.0);
        TEST_ASSERT_DOUBLE_WITHIN(1e-4 * var, var, (double)p.var);
        TEST_ASSERT_DOUBLE_WITHIN(1e-4 * sw[k] / 2.0, sw[k] / 2.0, (double)p.weight);
        TEST_ASSERT_DOUBLE_WITHIN(1e-4 * sw[k] * sw[k] / sw2[k], sw[k] * sw[k] / sw2[k],
                                  (double)p.n_eff);
    }
}
#endif

/* Found by fuzz_moments: a bandwidth near the smallest real overflowed sum w^2 (Inf se), and the
 * smallest forgetting factor must not overflow the weight scale. Results stay finite. */
static void test_moments_extreme_config_stays_finite(void)
{
    aenl_moments_cfg_t c = std_cfg(AENL_R(-1.0), AENL_R(1.0), 5);
    c.bandwidth = AENL_R(1e-30);
    c.n_lags = 1;
    c.direction_split = 0;
    for (int pass = 0; pass < 2; ++pass)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
        for (int i = 0; i < 200; ++i)
        {
            TEST_ASSERT_EQUAL_INT(AENL_OK,
                                  aenl_moments_push(&g_m, (i % 3) ? AENL_R(0.0) : AENL_R(0.5)));
        }
        aenl_moments_point_t p;
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_query(&g_m, 0, 2, AENL_DIR_ALL, &p));
        TEST_ASSERT_TRUE(aenl_is_finite(p.mean) && aenl_is_finite(p.var) &&
                         aenl_is_finite(p.n_eff) && aenl_is_finite(p.se) &&
                         aenl_is_finite(p.weight));
        TEST_ASSERT_TRUE(p.var >= AENL_R(0.0) && p.n_eff >= AENL_R(0.999));
        c.bandwidth = AENL_R(0.5);
        c.forgetting = AENL_MOMENTS_MIN_FORGETTING;
    }
}

/* Samples far beyond any physical range overflow the second moment: the query says so with
 * AENL_E_NUMERIC (x only, the rest zero) instead of returning Inf or NaN. */
static void test_moments_overflow_is_numeric_not_nan(void)
{
    aenl_moments_cfg_t c = std_cfg(AENL_R(-1.0), AENL_R(1.0), 5);
    c.n_lags = 1;
    c.direction_split = 0;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &c));
    const aenl_real_t big = AENL_REAL_MAX / AENL_R(4.0);
    const aenl_real_t seq[] = {AENL_R(0.0), big, AENL_R(0.0), -big, AENL_R(0.0), big};
    for (size_t i = 0; i < sizeof(seq) / sizeof(seq[0]); ++i)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_push(&g_m, seq[i]));
    }
    aenl_moments_point_t p;
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_moments_query(&g_m, 0, 2, AENL_DIR_ALL, &p));
    aenl_moments_point_t zero;
    memset(&zero, 0, sizeof(zero));
    zero.x = aenl_moments_node_x(&g_m, 2);
    TEST_ASSERT_EQUAL_MEMORY(&zero, &p, sizeof(p));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_moments_matches_brute_force);
    RUN_TEST(test_moments_no_split_matches_brute_force);
    RUN_TEST(test_moments_symmetric_matches_brute_force);
    RUN_TEST(test_moments_forgetting_matches_brute_force);
    RUN_TEST(test_moments_extreme_config_stays_finite);
    RUN_TEST(test_moments_overflow_is_numeric_not_nan);
    RUN_TEST(test_moments_constant_input_zero_variance);
    RUN_TEST(test_moments_init_on_garbage_memory);
    RUN_TEST(test_moments_init_rejects_bad_config);
    RUN_TEST(test_moments_missing_sample_keeps_statistics);
    RUN_TEST(test_moments_no_pair_across_a_gap);
    RUN_TEST(test_moments_query_rejects_bad_arguments);
    RUN_TEST(test_moments_reset_keeps_config);
    RUN_TEST(test_moments_far_outlier_is_harmless);
    RUN_TEST(test_moments_taylor_matches_weighted_fit);
    RUN_TEST(test_moments_taylor_ex_symmetric_matches_weighted_fit);
    RUN_TEST(test_moments_taylor_sinusoid_phase_portrait);
    RUN_TEST(test_moments_taylor_rejects_bad_arguments);
#if !AENL_USE_DOUBLE
    RUN_TEST(test_moments_float32_long_stream);
    RUN_TEST(test_moments_float32_deep_cells);
#endif
    return UNITY_END();
}
