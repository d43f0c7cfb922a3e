/* SPDX-License-Identifier: MIT */
/**
 * @file test_classifier.c
 * @brief aenl_classifier on records of a randomly forced single-DOF oscillator written here (not
 *        the project's simulators): the restoring law is known exactly, so the class and the
 *        switching points have an independent truth.
 */
#include <math.h>
#include <string.h>

#include "aenl/aenl_classifier.h"
#include "aenl_test.h"

void setUp(void)
{
}
void tearDown(void)
{
}

enum
{
    LAW_LINEAR,
    LAW_FREEPLAY,
    LAW_CUBIC,
    LAW_HYSTERESIS
};

/* Restoring law R(x), stiffness 1 outside the gap. Hysteresis: the simulator's loop
 * (docs/simulate.md) with alpha_f = 0, delta = 2g and the preload M0 = g that closes the loop
 * (dissipative): the gap sits at [0, 2g] while the DOF rises and at [-2g, 0] while it falls. */
static double law(int kind, double x, double v, double g)
{
    switch (kind)
    {
        case LAW_FREEPLAY:
            return x < -g ? x + g : (x > g ? x - g : 0.0);
        case LAW_CUBIC:
            return x + 0.6 * x * x * x;
        case LAW_HYSTERESIS:
            if (v >= 0.0)
            {
                return x < 0.0 ? x + g : (x > 2.0 * g ? x - g : g);
            }
            return x > 0.0 ? x - g : (x < -2.0 * g ? x + g : -g);
        default:
            return x;
    }
}

#define N_REC 120000u
static aenl_moments_t g_m;
static aenl_classifier_t g_c;
static double g_x[N_REC];

/*
 * x'' + 2 zeta w x' + w^2 R(x) = forcing, white noise held over each sample, integrated with 8
 * semi-implicit Euler substeps per sample; period about 40 samples; measurement noise of noise
 * times the response's standard deviation (SNR 1 / noise).
 */
static void make_record(int kind, double g, double force, double noise, uint64_t seed)
{
    const double w = 2.0 * 3.14159265358979 / 40.0, zeta = 0.04, sub = 8.0;
    double x = 0.0, v = 0.0, sum2 = 0.0;
    g_lcg = seed;
    for (size_t n = 0; n < N_REC; ++n)
    {
        const double f = force * lcg_normal();
        for (int s = 0; s < (int)sub; ++s)
        {
            v += (-2.0 * zeta * w * v - w * w * law(kind, x, v, g) + f) / sub;
            x += v / sub;
        }
        g_x[n] = x;
        sum2 += x * x;
    }
    const double sd = sqrt(sum2 / N_REC);
    for (size_t n = 0; n < N_REC; ++n)
    {
        g_x[n] += noise * sd * lcg_normal();
    }
}

/* Moments over +-3 sd, one node per bandwidth, lags 1 2 3 5 symmetric, split; then classify. */
static const aenl_classifier_result_t *classify(void)
{
    double sum2 = 0.0;
    for (size_t n = 0; n < N_REC; ++n)
    {
        sum2 += g_x[n] * g_x[n];
    }
    const double sd = sqrt(sum2 / N_REC);
    aenl_moments_cfg_t mc;
    memset(&mc, 0, sizeof(mc));
    mc.x_min = (aenl_real_t)(-3.0 * sd);
    mc.x_max = (aenl_real_t)(3.0 * sd);
    mc.n_grid = 32; /* the Cortex-M4F capacity: 3 lags x 2 (symmetric) x 32 x 2 directions */
    mc.bandwidth = (mc.x_max - mc.x_min) / AENL_R(31.0);
    mc.n_lags = 3;
    mc.lags[0] = 2; /* not 1: the direction split reads X_{c-1} */
    mc.lags[1] = 3;
    mc.lags[2] = 4;
    mc.forgetting = AENL_R(1.0);
    mc.direction_split = 1;
    mc.symmetric = 1;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &mc));
    aenl_classifier_cfg_t cc;
    aenl_classifier_cfg_default(&cc);
    cc.taylor_order = 3;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_classifier_init(&g_c, &cc));
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_INSUFFICIENT, aenl_classifier_result(&g_c)->cls);
    for (size_t n = 0; n < N_REC; ++n)
    {
        aenl_moments_push(&g_m, (aenl_real_t)g_x[n]);
        if (n == 200u) /* far too early: no node has enough pairs */
        {
            TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_classifier_update(&g_c, &g_m));
            TEST_ASSERT_EQUAL_INT(AENL_CLASS_INSUFFICIENT, aenl_classifier_result(&g_c)->cls);
        }
    }
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_classifier_update(&g_c, &g_m));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_classifier_update(&g_c, &g_m));
    const aenl_classifier_result_t *r = aenl_classifier_result(&g_c);
    TEST_ASSERT_EQUAL_UINT32(3u, r->n_updates);
    TEST_ASSERT_EQUAL_UINT32(2u, r->n_stable); /* the same data twice: the same decision */
    return r;
}

static void check_points(const aenl_classifier_result_t *r, const double *truth, int n, double tol)
{
    TEST_ASSERT_EQUAL_INT(n, r->n_switch);
    for (int i = 0; i < n; ++i)
    {
        TEST_ASSERT_DOUBLE_WITHIN(tol, truth[i], (double)r->switch_points[i]);
        TEST_ASSERT_TRUE(r->switch_std[i] > AENL_R(0.0));
        if (i > 0)
        {
            TEST_ASSERT_TRUE(r->switch_points[i] > r->switch_points[i - 1]);
        }
    }
}

static void test_classifier_linear(void)
{
    make_record(LAW_LINEAR, 0.0, 0.02, 0.1, 11u);
    const aenl_classifier_result_t *r = classify();
    TEST_ASSERT_EQUAL_STRING("linear", aenl_class_name(r->cls));
    TEST_ASSERT_EQUAL_INT(0, r->n_switch);
    TEST_ASSERT_TRUE(r->confidence > AENL_R(0.5));
}

static void test_classifier_freeplay(void)
{
    make_record(LAW_FREEPLAY, 0.4, 0.02, 0.1, 12u);
    const aenl_classifier_result_t *r = classify();
    TEST_ASSERT_EQUAL_STRING("freeplay", aenl_class_name(r->cls));
    const double truth[2] = {-0.4, 0.4};
    check_points(r, truth, 2, 0.08); /* 10 % of the gap */
    TEST_ASSERT_TRUE(r->confidence > AENL_R(0.9));
}

static void test_classifier_cubic(void)
{
    make_record(LAW_CUBIC, 0.0, 0.02, 0.1, 13u);
    const aenl_classifier_result_t *r = classify();
    TEST_ASSERT_EQUAL_STRING("polynomial", aenl_class_name(r->cls));
    TEST_ASSERT_EQUAL_INT(1, r->hardening);
    TEST_ASSERT_EQUAL_INT(0, r->n_switch);
}

static void test_classifier_hysteresis(void)
{
    /* SNR 50: the direction split reads X_c > X_{c-1} of the unfiltered record here (the identify
     * pipeline low-passes first), and the noise on a difference must stay below the motion. */
    make_record(LAW_HYSTERESIS, 0.5, 0.04, 0.02, 14u);
    const aenl_classifier_result_t *r = classify();
    TEST_ASSERT_EQUAL_STRING("hysteresis", aenl_class_name(r->cls));
    /* The outer kinks (the gap ends of the two branches, -1 and 1) are resolved; the inner ones
     * (both at 0) are smoothed over the lag window and may come out as two points. */
    TEST_ASSERT_TRUE(r->n_switch >= 3u && r->n_switch <= 4u);
    TEST_ASSERT_DOUBLE_WITHIN(0.2, -1.0, (double)r->switch_points[0]);
    TEST_ASSERT_DOUBLE_WITHIN(0.2, 1.0, (double)r->switch_points[r->n_switch - 1u]);
}

static void test_classifier_rejects_bad_arguments(void)
{
    aenl_classifier_cfg_t cc;
    aenl_classifier_cfg_default(&cc);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_classifier_init(NULL, &cc));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_classifier_init(&g_c, NULL));
    cc.taylor_order = 1;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_classifier_init(&g_c, &cc));
    aenl_classifier_cfg_default(&cc);
    cc.trim = AENL_R(0.3);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_classifier_init(&g_c, &cc));
    aenl_classifier_cfg_default(&cc);
    cc.min_nodes = 3;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_classifier_init(&g_c, &cc));
    /* a previous decision survives a rejected update */
    aenl_classifier_cfg_default(&cc);
    cc.taylor_order = 4;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_classifier_init(&g_c, &cc));
    aenl_moments_cfg_t mc;
    memset(&mc, 0, sizeof(mc));
    mc.x_min = AENL_R(-1.0);
    mc.x_max = AENL_R(1.0);
    mc.n_grid = 16;
    mc.bandwidth = AENL_R(0.2);
    mc.n_lags = 2;
    mc.lags[0] = 1;
    mc.lags[1] = 2;
    mc.forgetting = AENL_R(1.0);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_moments_init(&g_m, &mc));
    aenl_classifier_result_t before = *aenl_classifier_result(&g_c);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_classifier_update(&g_c, &g_m)); /* 2 lags, order 4 */
    TEST_ASSERT_EQUAL_MEMORY(&before, aenl_classifier_result(&g_c), sizeof(before));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_classifier_update(NULL, &g_m));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_classifier_update(&g_c, NULL));
    TEST_ASSERT_EQUAL_STRING("unknown", aenl_class_name((aenl_class_t)9));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_classifier_linear);
    RUN_TEST(test_classifier_freeplay);
    RUN_TEST(test_classifier_cubic);
    RUN_TEST(test_classifier_hysteresis);
    RUN_TEST(test_classifier_rejects_bad_arguments);
    return UNITY_END();
}
