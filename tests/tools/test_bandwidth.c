/* SPDX-License-Identifier: MIT */
/**
 * @file test_bandwidth.c
 * @brief Host tools: leave-one-out CV bandwidth for the triangular-kernel lag regression.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "unity.h"

#include "aenl_test_rand.h"

#include "aenl_tools/aenl_bandwidth.h"
#include "aenl_tools/aenl_curves.h"

static aenl_err_t g_err;
static uint64_t g_lcg;

void setUp(void)
{
    aenl_err_clear(&g_err);
    g_lcg = 0x853c49e6748fea9bULL;
}

void tearDown(void)
{
}

/* ---- deterministic data -------------------------------------------------------------------- */

/* AR(2) x_t = 1.6 x_{t-1} − 0.8 x_{t-2} + e_t, plus measurement noise of std `noise`. */
static double *make_ar2(size_t n, double noise)
{
    double *x = (double *)malloc(n * sizeof *x);
    double a = 0.0;
    double b = 0.0;
    size_t i;
    TEST_ASSERT_NOT_NULL(x);
    for (i = 0; i < n + 200; ++i)
    {
        double c = 1.6 * a - 0.8 * b + test_gauss(&g_lcg);
        b = a;
        a = c;
        if (i >= 200)
        {
            x[i - 200] = c + noise * test_gauss(&g_lcg);
        }
    }
    return x;
}

/* Nonlinear AR(1) with a known lag-1 regression m(u) = 2 sin(u): x_t = 2 sin(x_{t-1}) + e_t. */
static double *make_sine_ar(size_t n, double noise_std)
{
    double *x = (double *)malloc(n * sizeof *x);
    double a = 0.3;
    size_t i;
    TEST_ASSERT_NOT_NULL(x);
    for (i = 0; i < n + 100; ++i)
    {
        a = 2.0 * sin(a) + noise_std * test_gauss(&g_lcg);
        if (i >= 100)
        {
            x[i - 100] = a;
        }
    }
    return x;
}

static double data_range(const double *x, size_t n)
{
    double lo = (double)INFINITY;
    double hi = -(double)INFINITY;
    size_t i;
    for (i = 0; i < n; ++i)
    {
        if (isfinite(x[i]))
        {
            lo = (x[i] < lo) ? x[i] : lo;
            hi = (x[i] > hi) ? x[i] : hi;
        }
    }
    return hi - lo;
}

static void assert_rel(double want, double got, double rel, const char *what)
{
    char msg[256];
    double err = fabs(got - want) / fabs(want);
    (void)snprintf(msg, sizeof msg, "%s: want %.17g got %.17g (rel %.3g)", what, want, got, err);
    TEST_ASSERT_TRUE_MESSAGE(err <= rel, msg);
}

static void compare_fast_brute(const double *x, size_t n, const uint16_t *lags, size_t n_lags,
                               double h)
{
    aenl_bw_score_t fast;
    aenl_bw_score_t brute;
    char what[96];
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_bw_loo_score(x, n, lags, n_lags, h, &fast, &g_err),
                                  g_err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_loo_score_brute(x, n, lags, n_lags, h, &brute, &g_err));
    (void)snprintf(what, sizeof what, "h=%g lag0=%u n_lags=%lu", h, (unsigned)lags[0],
                   (unsigned long)n_lags);
    TEST_ASSERT_TRUE_MESSAGE(isfinite(fast.score), what);
    assert_rel(brute.score, fast.score, 1e-12, what);
    TEST_ASSERT_EQUAL_size_t(brute.n_pairs, fast.n_pairs);
    TEST_ASSERT_EQUAL_size_t(brute.n_used, fast.n_used);
    TEST_ASSERT_EQUAL_size_t(brute.n_excluded, fast.n_excluded);
    assert_rel(brute.mean_neighbours, fast.mean_neighbours, 1e-12, what);
}

/* ---- fast score == definition -------------------------------------------------------------- */

static void test_bw_loo_fast_matches_brute_force(void)
{
    const size_t n = 2000;
    const uint16_t lags[] = {1, 10, 30};
    const double fractions[] = {1.0 / 500.0, 1.0 / 100.0, 1.0 / 30.0, 1.0 / 8.0, 1.0 / 2.0};
    double *x = make_ar2(n, 0.5);
    double range = data_range(x, n);
    size_t f;
    size_t l;
    for (f = 0; f < sizeof fractions / sizeof fractions[0]; ++f)
    {
        for (l = 0; l < 3; ++l)
        {
            compare_fast_brute(x, n, &lags[l], 1, range * fractions[f]);
        }
        compare_fast_brute(x, n, lags, 3, range * fractions[f]);
    }
    free(x);
}

static void test_bw_loo_fast_matches_brute_with_ties_and_gaps(void)
{
    const size_t n = 2000;
    const uint16_t lags[] = {1, 10, 30};
    double *x = make_ar2(n, 0.2);
    size_t i;
    for (i = 0; i < n; ++i)
    {
        x[i] = 100.0 + floor(x[i] * 4.0) / 4.0; /* coarse quantisation: many ties, offset */
    }
    for (i = 300; i < 340; ++i)
    {
        x[i] = (double)NAN; /* a gap */
    }
    x[1000] = (double)INFINITY;              /* treated as missing */
    compare_fast_brute(x, n, lags, 3, 0.25); /* exactly the quantisation step */
    compare_fast_brute(x, n, lags, 3, 0.6);
    compare_fast_brute(x, n, lags, 3, 3.0);
    free(x);
}

static void test_bw_loo_counts_skipped_pairs_and_exclusions(void)
{
    /* x = 0, 1, NaN, 3, 4, 10: lag-1 pairs (0,1) (3,4) (4,10), lag 2: (1,3) (3,10)... */
    const double x[] = {0.0, 1.0, (double)NAN, 3.0, 4.0, 10.0};
    const uint16_t lag1[] = {1};
    aenl_bw_score_t sc;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_loo_score(x, 6, lag1, 1, 1.5, &sc, &g_err));
    TEST_ASSERT_EQUAL_size_t(3, sc.n_pairs);
    /* u = 0, 3, 4: within 1.5 only 3 and 4 see each other; u = 0 has no neighbour. */
    TEST_ASSERT_EQUAL_size_t(1, sc.n_excluded);
    TEST_ASSERT_EQUAL_size_t(2, sc.n_used);
    /* m_{-(3,4)}(3) = 10, m_{-(4,10)}(4) = 4: CV = ((4-10)² + (10-4)²)/2 = 36 */
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 36.0, sc.score);
}

/* ---- the search ---------------------------------------------------------------------------- */

static void test_bw_select_finds_interior_minimum_for_sine_regression(void)
{
    const size_t n = 5000;
    const uint16_t lag1[] = {1};
    double *x = make_sine_ar(n, 0.3);
    double range = data_range(x, n);
    aenl_bw_result_t r;
    aenl_bw_score_t half;
    aenl_bw_score_t twice;
    char msg[160];
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_bw_select(x, n, lag1, 1, NULL, &r, &g_err),
                                  g_err.msg);
    (void)snprintf(msg, sizeof msg, "h=%g range=%g score=%g rule=%g cand=%lu fb=%s", r.h, range,
                   r.score, r.h_rule, (unsigned long)r.n_candidates,
                   aenl_bw_fallback_str(r.fallback));
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_BW_CV, r.method, msg);
    TEST_ASSERT_EQUAL_STRING("cv", aenl_bw_method_str(r.method));
    TEST_ASSERT_EQUAL_size_t(n - 1, r.n_pairs);
    TEST_ASSERT_TRUE_MESSAGE(r.h > range / 200.0 && r.h < range / 4.0, msg);
    /* With noise 0.3 the LOO error cannot beat the noise variance 0.09, and a good h gets close. */
    TEST_ASSERT_TRUE_MESSAGE(r.score > 0.09 * 0.9 && r.score < 0.09 * 1.2, msg);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_loo_score(x, n, lag1, 1, r.h / 2.0, &half, &g_err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_loo_score(x, n, lag1, 1, r.h * 2.0, &twice, &g_err));
    TEST_ASSERT_TRUE_MESSAGE(r.score < half.score, msg);
    TEST_ASSERT_TRUE_MESSAGE(r.score < twice.score, msg);
    TEST_ASSERT_TRUE(r.n_candidates > 20);
    free(x);
}

static void test_bw_select_ar2_three_lags(void)
{
    const size_t n = 3000;
    const uint16_t lags[] = {1, 10, 30};
    double *x = make_ar2(n, 0.3);
    aenl_bw_result_t r;
    aenl_bw_score_t half;
    aenl_bw_score_t twice;
    char msg[160];
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_bw_select(x, n, lags, 3, NULL, &r, &g_err),
                                  g_err.msg);
    (void)snprintf(msg, sizeof msg, "h=%g score=%g rule=%g cand=%lu fb=%s", r.h, r.score, r.h_rule,
                   (unsigned long)r.n_candidates, aenl_bw_fallback_str(r.fallback));
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_BW_CV, r.method, msg);
    TEST_ASSERT_EQUAL_size_t((n - 1) + (n - 10) + (n - 30), r.n_pairs);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_loo_score(x, n, lags, 3, r.h / 2.0, &half, &g_err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_loo_score(x, n, lags, 3, r.h * 2.0, &twice, &g_err));
    TEST_ASSERT_TRUE_MESSAGE(r.score <= half.score && r.score <= twice.score, msg);
    free(x);
}

static void test_bw_select_white_noise_has_no_minimum(void)
{
    /* m(u) is constant: the LOO error keeps falling as h grows, so the rule is used. */
    const size_t n = 4000;
    const uint16_t lag1[] = {1};
    double *x = (double *)malloc(n * sizeof *x);
    aenl_bw_result_t r;
    size_t i;
    TEST_ASSERT_NOT_NULL(x);
    for (i = 0; i < n; ++i)
    {
        x[i] = test_gauss(&g_lcg);
    }
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_select(x, n, lag1, 1, NULL, &r, &g_err));
    TEST_ASSERT_EQUAL_INT(AENL_BW_RULE, r.method);
    TEST_ASSERT_EQUAL_INT(AENL_BW_FB_NO_MINIMUM, r.fallback);
    TEST_ASSERT_EQUAL_DOUBLE(r.h_rule, r.h);
    TEST_ASSERT_TRUE(isfinite(r.score));
    free(x);
}

static void test_bw_select_few_samples_uses_rule(void)
{
    const uint16_t lag1[] = {1};
    double x[30];
    double h_rule;
    aenl_bw_result_t r;
    size_t i;
    for (i = 0; i < 30; ++i)
    {
        x[i] = sin(0.7 * (double)i);
    }
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_select(x, 30, lag1, 1, NULL, &r, &g_err));
    TEST_ASSERT_EQUAL_INT(AENL_BW_RULE, r.method);
    TEST_ASSERT_EQUAL_INT(AENL_BW_FB_FEW_PAIRS, r.fallback);
    TEST_ASSERT_EQUAL_STRING("rule", aenl_bw_method_str(r.method));
    TEST_ASSERT_EQUAL_size_t(29, r.n_pairs);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_rule(x, 30, &h_rule, &g_err));
    TEST_ASSERT_EQUAL_DOUBLE(h_rule, r.h);
}

static void test_bw_select_force_rule(void)
{
    const size_t n = 2000;
    const uint16_t lag1[] = {1};
    double *x = make_ar2(n, 0.3);
    aenl_bw_opts_t o;
    aenl_bw_result_t r;
    aenl_bw_opts_default(&o);
    o.force_rule = 1;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_select(x, n, lag1, 1, &o, &r, &g_err));
    TEST_ASSERT_EQUAL_INT(AENL_BW_RULE, r.method);
    TEST_ASSERT_EQUAL_INT(AENL_BW_FB_FORCED, r.fallback);
    TEST_ASSERT_EQUAL_size_t(1, r.n_candidates);
    free(x);
}

/* ---- rule of thumb, by hand ---------------------------------------------------------------- */

static int cmp_d(const void *a, const void *b)
{
    double p = *(const double *)a;
    double q = *(const double *)b;
    return (p < q) ? -1 : (p > q) ? 1 : 0;
}

static void test_bw_rule_matches_hand_formula(void)
{
    const size_t n = 1001;
    double *x = make_ar2(n, 0.0);
    double *s = (double *)malloc(n * sizeof *s);
    double mean = 0.0;
    double ss = 0.0;
    double sd;
    double q1;
    double q3;
    double sigma;
    double want;
    double got = 0.0;
    size_t i;
    TEST_ASSERT_NOT_NULL(s);
    /* constant: 1.06 × (δ_triangular / δ_gauss) = 1.06 × (24 × 2√π)^(1/5) */
    assert_rel(2.5779180063988147, aenl_bw_rule_constant(), 1e-15, "rule constant");
    for (i = 0; i < n; ++i)
    {
        mean += x[i];
    }
    mean /= (double)n;
    for (i = 0; i < n; ++i)
    {
        ss += (x[i] - mean) * (x[i] - mean);
    }
    sd = sqrt(ss / (double)(n - 1));
    memcpy(s, x, n * sizeof *s);
    qsort(s, n, sizeof *s, cmp_d);
    q1 = s[250]; /* (n − 1)·0.25 = 250 exactly */
    q3 = s[750];
    sigma = fmin(sd, (q3 - q1) / 1.349);
    want = 2.5779180063988147 * sigma * pow((double)n, -0.2);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_rule(x, n, &got, &g_err));
    assert_rel(want, got, 1e-12, "rule of thumb");
    /* NaNs are left out: N counts finite samples only. */
    x[10] = (double)NAN;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_rule(x, n, &got, &g_err));
    TEST_ASSERT_TRUE(isfinite(got) && got > 0.0);
    free(s);
    free(x);
}

/* ---- rejected input ------------------------------------------------------------------------ */

static void test_bw_rejects_constant_signal(void)
{
    const uint16_t lag1[] = {1};
    double x[200];
    aenl_bw_result_t r;
    size_t i;
    for (i = 0; i < 200; ++i)
    {
        x[i] = (i % 7 == 3) ? (double)NAN : 1.25;
    }
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_select(x, 200, lag1, 1, NULL, &r, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "constant signal"), g_err.msg);
    aenl_err_clear(&g_err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_rule(x, 200, &r.h, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "constant signal"), g_err.msg);
}

static void test_bw_rejects_all_nan(void)
{
    const uint16_t lag1[] = {1};
    double x[100];
    aenl_bw_result_t r;
    size_t i;
    for (i = 0; i < 100; ++i)
    {
        x[i] = (double)NAN;
    }
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_select(x, 100, lag1, 1, NULL, &r, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "no finite samples"), g_err.msg);
    TEST_ASSERT_TRUE(isnan(r.h));
}

static void test_bw_rejects_bad_arguments(void)
{
    const uint16_t lag1[] = {1};
    const uint16_t lag0[] = {0};
    double x[100];
    aenl_bw_result_t r;
    aenl_bw_score_t sc;
    aenl_bw_opts_t o;
    size_t i;
    for (i = 0; i < 100; ++i)
    {
        x[i] = (double)(i % 10);
    }
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_select(NULL, 100, lag1, 1, NULL, &r, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_select(x, 100, NULL, 1, NULL, &r, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_select(x, 100, lag1, 0, NULL, &r, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_select(x, 100, lag1, 1, NULL, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_select(x, 100, lag0, 1, NULL, &r, &g_err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(g_err.msg, "lag 1 is 0"), g_err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_loo_score(x, 100, lag1, 1, 0.0, &sc, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_loo_score(x, 100, lag1, 1, (double)NAN, &sc, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_loo_score_brute(x, 100, lag1, 1, -1.0, &sc, NULL));
    aenl_bw_opts_default(&o);
    o.n_grid = 2;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_select(x, 100, lag1, 1, &o, &r, NULL));
    aenl_bw_opts_default(&o);
    o.h_lo = 2.0;
    o.h_hi = 1.0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_bw_select(x, 100, lag1, 1, &o, &r, NULL));
    TEST_ASSERT_EQUAL_STRING("unknown", aenl_bw_method_str(0));
}

static void test_bw_nan_gaps_are_skipped(void)
{
    const size_t n = 3000;
    const uint16_t lags[] = {1, 10};
    double *x = make_sine_ar(n, 0.3);
    aenl_bw_result_t r;
    size_t i;
    size_t want_pairs = 0;
    for (i = 500; i < 800; ++i)
    {
        x[i] = (double)NAN;
    }
    for (i = 1000; i < n; i += 37)
    {
        x[i] = (double)NAN;
    }
    for (i = 1; i < n; ++i)
    {
        want_pairs += (!isnan(x[i]) && !isnan(x[i - 1])) ? 1U : 0U;
    }
    for (i = 10; i < n; ++i)
    {
        want_pairs += (!isnan(x[i]) && !isnan(x[i - 10])) ? 1U : 0U;
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_bw_select(x, n, lags, 2, NULL, &r, &g_err),
                                  g_err.msg);
    TEST_ASSERT_EQUAL_size_t(want_pairs, r.n_pairs);
    TEST_ASSERT_TRUE(isfinite(r.h) && r.h > 0.0);
    TEST_ASSERT_TRUE(isfinite(r.score));
    free(x);
}

/* ---- cost ---------------------------------------------------------------------------------- */

/* A long record's bandwidth chosen on its first samples and carried to the whole record by the
 * n^(-1/5) rate, against the cross-validation of the whole record (the reference): within the
 * spread of a cross-validated bandwidth, while the block's own bandwidth, unscaled, is not (it
 * is (n / m)^(1/5) = 2 times too wide here). */
static void test_curves_bandwidth_from_a_block(void)
{
    const size_t n = 320000;
    double *x = make_sine_ar(n, 0.5);
    aenl_curves_opts_t o;
    aenl_curves_opts_default(&o);
    o.n_lags = 1;
    o.lags[0] = 1;
    o.cv_max = 0; /* the whole record */
    aenl_curves_t full;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_curves_compute(x, n, &o, &full, &g_err), g_err.msg);
    o.cv_max = 10000;
    aenl_curves_t blk;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_curves_compute(x, n, &o, &blk, &g_err), g_err.msg);
    aenl_bw_result_t own;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_bw_select(x, 10000, o.lags, 1, NULL, &own, &g_err));
    char msg[200];
    (void)snprintf(msg, sizeof msg, "whole %g, block scaled %g, block unscaled %g", full.bandwidth,
                   blk.bandwidth, own.h);
    TEST_MESSAGE(msg);
    TEST_ASSERT_EQUAL_INT(AENL_BW_CV, full.bw_method);
    TEST_ASSERT_EQUAL_INT(AENL_BW_CV, blk.bw_method);
    TEST_ASSERT_EQUAL_size_t(n, full.cv_samples);
    TEST_ASSERT_EQUAL_size_t(10000, blk.cv_samples);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12 * own.h, own.h * pow(10000.0 / (double)n, 0.2), blk.bandwidth);
    const double ratio = blk.bandwidth / full.bandwidth;
    TEST_ASSERT_TRUE_MESSAGE(ratio > 0.75 && ratio < 1.33, msg);
    TEST_ASSERT_TRUE_MESSAGE(own.h / full.bandwidth > 1.33, msg);
    aenl_curves_free(&full);
    aenl_curves_free(&blk);
    free(x);
}

static void test_bw_select_timing_1e5_samples_3_lags(void)
{
    const size_t n = 100000;
    const uint16_t lags[] = {1, 10, 30};
    double *x = make_ar2(n, 0.3);
    aenl_bw_result_t r;
    char msg[200];
    clock_t t0 = clock();
    double secs;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_bw_select(x, n, lags, 3, NULL, &r, &g_err),
                                  g_err.msg);
    secs = (double)(clock() - t0) / (double)CLOCKS_PER_SEC;
    (void)snprintf(msg, sizeof msg, "N=1e5, 3 lags: %.2f s, %lu candidates, h=%g (%s), rule %g",
                   secs, (unsigned long)r.n_candidates, r.h, aenl_bw_method_str(r.method),
                   r.h_rule);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE_MESSAGE(secs < 60.0, msg);
    free(x);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_bw_loo_fast_matches_brute_force);
    RUN_TEST(test_bw_loo_fast_matches_brute_with_ties_and_gaps);
    RUN_TEST(test_bw_loo_counts_skipped_pairs_and_exclusions);
    RUN_TEST(test_bw_select_finds_interior_minimum_for_sine_regression);
    RUN_TEST(test_bw_select_ar2_three_lags);
    RUN_TEST(test_bw_select_white_noise_has_no_minimum);
    RUN_TEST(test_bw_select_few_samples_uses_rule);
    RUN_TEST(test_bw_select_force_rule);
    RUN_TEST(test_bw_rule_matches_hand_formula);
    RUN_TEST(test_bw_rejects_constant_signal);
    RUN_TEST(test_bw_rejects_all_nan);
    RUN_TEST(test_bw_rejects_bad_arguments);
    RUN_TEST(test_bw_nan_gaps_are_skipped);
    RUN_TEST(test_bw_select_timing_1e5_samples_3_lags);
    RUN_TEST(test_curves_bandwidth_from_a_block);
    return UNITY_END();
}
