/* SPDX-License-Identifier: MIT */
/**
 * @file test_filter.c
 * @brief aenl_filter against the analytic Butterworth magnitude (bilinear, pre-warped) and a
 *        time-domain gain measurement, plus priming, missing samples and argument checks.
 *        Builds as f32 and f64.
 */
#include <string.h>

#include "aenl_test.h"

#include "aenl/aenl_filter.h"

static aenl_filter_t g_f;

void setUp(void)
{
    memset(&g_f, 0xA5, sizeof(g_f));
}

void tearDown(void)
{
}

static const double k_pi = 3.14159265358979323846;

static aenl_filter_cfg_t cfg_of(double cutoff, uint16_t order)
{
    aenl_filter_cfg_t c;
    memset(&c, 0, sizeof(c));
    c.cutoff = (aenl_real_t)cutoff;
    c.order = order;
    return c;
}

/* |H(e^{jw})|^2 of the designed cascade, evaluated in double from its coefficients. */
static double cascade_gain2(const aenl_filter_t *f, double w)
{
    double g2 = 1.0;
    for (uint16_t s = 0; s < f->n_sections; ++s)
    {
        const double b0 = (double)f->b0[s], a1 = (double)f->a1[s], a2 = (double)f->a2[s];
        /* numerator b0 (1 + z^-1)^2, denominator 1 + a1 z^-1 + a2 z^-2, z = e^{jw} */
        const double nr = b0 * (1.0 + 2.0 * cos(w) + cos(2.0 * w));
        const double ni = -b0 * (2.0 * sin(w) + sin(2.0 * w));
        const double dr = 1.0 + a1 * cos(w) + a2 * cos(2.0 * w);
        const double di = -(a1 * sin(w) + a2 * sin(2.0 * w));
        g2 *= (nr * nr + ni * ni) / (dr * dr + di * di);
    }
    return g2;
}

static void test_filter_magnitude_is_butterworth(void)
{
    static const double cutoffs[] = {0.02, 0.1, 0.3, 0.45};
    static const uint16_t orders[] = {2, 4, 6, 8};
    for (size_t i = 0; i < sizeof(cutoffs) / sizeof(cutoffs[0]); ++i)
    {
        for (size_t j = 0; j < sizeof(orders) / sizeof(orders[0]); ++j)
        {
            const aenl_filter_cfg_t c = cfg_of(cutoffs[i], orders[j]);
            TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_filter_init(&g_f, &c));
            for (int q = 1; q < 40; ++q)
            {
                const double w = k_pi * q / 40.0;
                const double r = tan(w / 2.0) / tan(k_pi * (double)c.cutoff);
                const double want = 1.0 / (1.0 + pow(r, 2.0 * orders[j]));
                const double got = cascade_gain2(&g_f, w);
                /* f32 coefficients carry ~1e-7 relative error, amplified near the poles. */
                TEST_ASSERT_DOUBLE_WITHIN(AENL_USE_DOUBLE ? 1e-10 : 2e-4 + 1e-3 * want, want, got);
            }
        }
    }
}

/* Steady-state amplitude of a pushed sinusoid: a measurement independent of the design formulas. */
static double measured_gain(double cutoff, uint16_t order, double freq)
{
    const aenl_filter_cfg_t c = cfg_of(cutoff, order);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_filter_init(&g_f, &c));
    const int n = (int)(200.0 / freq) + 2000;
    double peak = 0.0;
    for (int i = 0; i < n; ++i)
    {
        aenl_real_t y;
        TEST_ASSERT_EQUAL_INT(AENL_OK,
                              aenl_filter_push(&g_f, (aenl_real_t)sin(2.0 * k_pi * freq * i), &y));
        if (i > n / 2 && fabs((double)y) > peak)
        {
            peak = fabs((double)y);
        }
    }
    return peak;
}

static void test_filter_time_domain_gain(void)
{
    /* -3 dB at the cutoff for every order; flat well below; Butterworth roll-off above. */
    TEST_ASSERT_DOUBLE_WITHIN(2e-3, sqrt(0.5), measured_gain(0.05, 4, 0.05));
    TEST_ASSERT_DOUBLE_WITHIN(2e-3, sqrt(0.5), measured_gain(0.05, 2, 0.05));
    TEST_ASSERT_DOUBLE_WITHIN(2e-3, 1.0, measured_gain(0.05, 4, 0.01));
    const double r = tan(k_pi * 0.15) / tan(k_pi * 0.05);
    TEST_ASSERT_DOUBLE_WITHIN(2e-3, 1.0 / sqrt(1.0 + pow(r, 8.0)), measured_gain(0.05, 4, 0.15));
}

static void test_filter_first_sample_primes_steady_state(void)
{
    const aenl_filter_cfg_t c = cfg_of(0.05, 8);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_filter_init(&g_f, &c));
    for (int i = 0; i < 50; ++i)
    {
        aenl_real_t y;
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_filter_push(&g_f, AENL_R(1000.0), &y));
        TEST_ASSERT_REAL_WITHIN(AENL_R(1e3) * (aenl_real_t)AENL_TEST_REL_TOL, AENL_R(1000.0), y);
    }
}

static void test_filter_missing_sample_holds_state(void)
{
    static aenl_filter_t snap;
    const aenl_filter_cfg_t c = cfg_of(0.1, 4);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_filter_init(&g_f, &c));
    aenl_real_t y;
    for (int i = 0; i < 20; ++i)
    {
        aenl_filter_push(&g_f, (aenl_real_t)(0.1 * i), &y);
    }
    memcpy(&snap, &g_f, sizeof(g_f));
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_filter_push(&g_f, (aenl_real_t)NAN, &y));
    TEST_ASSERT_FLOAT_IS_NAN((float)y);
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_filter_push(&g_f, (aenl_real_t)INFINITY, &y));
    TEST_ASSERT_EQUAL_MEMORY(snap.z1, g_f.z1, sizeof(g_f.z1));
    TEST_ASSERT_EQUAL_MEMORY(snap.z2, g_f.z2, sizeof(g_f.z2));
    TEST_ASSERT_EQUAL_UINT32(2u, g_f.n_missing);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_push(NULL, AENL_R(1.0), &y));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_push(&g_f, AENL_R(1.0), NULL));
}

static void test_filter_init_rejects_bad_config(void)
{
    static aenl_filter_t before;
    memcpy(&before, &g_f, sizeof(g_f));
    aenl_filter_cfg_t c = cfg_of(0.1, 4);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_init(NULL, &c));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_init(&g_f, NULL));
    c = cfg_of(0.0, 4);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_init(&g_f, &c));
    c = cfg_of(0.5, 4);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_init(&g_f, &c));
    c = cfg_of(-0.1, 4);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_init(&g_f, &c));
    c = cfg_of((double)NAN, 4);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_init(&g_f, &c));
    c = cfg_of(0.1, 3);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_init(&g_f, &c));
    c = cfg_of(0.1, 0);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_filter_init(&g_f, &c));
    c = cfg_of(0.1, (uint16_t)(2u * AENL_FILTER_MAX_SECTIONS + 2u));
    TEST_ASSERT_EQUAL_INT(AENL_E_DIM, aenl_filter_init(&g_f, &c));
    TEST_ASSERT_EQUAL_MEMORY(&before, &g_f, sizeof(g_f));
}

static void test_filter_init_on_garbage_and_reset(void)
{
    static aenl_filter_t zeroed;
    memset(&zeroed, 0, sizeof(zeroed));
    const aenl_filter_cfg_t c = cfg_of(0.07, 6);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_filter_init(&g_f, &c));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_filter_init(&zeroed, &c));
    aenl_real_t y1, y2;
    for (int i = 0; i < 100; ++i)
    {
        const aenl_real_t x = (aenl_real_t)((i % 7) - 3);
        aenl_filter_push(&g_f, x, &y1);
        aenl_filter_push(&zeroed, x, &y2);
        TEST_ASSERT_EQUAL_MEMORY(&y2, &y1, sizeof(y1));
    }
    aenl_filter_reset(&g_f);
    aenl_filter_reset(NULL);
    TEST_ASSERT_EQUAL_INT(0, g_f.primed);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_filter_push(&g_f, AENL_R(2.0), &y1));
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-5), AENL_R(2.0), y1);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_filter_magnitude_is_butterworth);
    RUN_TEST(test_filter_time_domain_gain);
    RUN_TEST(test_filter_first_sample_primes_steady_state);
    RUN_TEST(test_filter_missing_sample_holds_state);
    RUN_TEST(test_filter_init_rejects_bad_config);
    RUN_TEST(test_filter_init_on_garbage_and_reset);
    return UNITY_END();
}
