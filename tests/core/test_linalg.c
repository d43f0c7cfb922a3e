/* SPDX-License-Identifier: MIT */
/**
 * @file test_linalg.c
 * @brief The private small-matrix kernels (the .c included: no public API reaches them) against
 *        brute-force double references: products, Cholesky (and its non-PD status), triangular
 *        solves, symmetrisation, stride handling. Builds as f32 and f64.
 */
#include <string.h>

#include "aenl_test.h"

#include "aenl_linalg.c" /* NOLINT(bugprone-suspicious-include): white-box test */

#define LD 7 /* a stride larger than the active sizes, as in the filter */

void setUp(void)
{
}

void tearDown(void)
{
}

static uint64_t g_lcg = 12345u;

static double uni(void)
{
    g_lcg = g_lcg * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(g_lcg >> 11) * (1.0 / 9007199254740992.0) - 0.5;
}

static void fill(aenl_real_t *a, double *ad, int n, int m)
{
    for (int i = 0; i < n; ++i)
    {
        for (int j = 0; j < m; ++j)
        {
            const double v = uni();
            a[i * LD + j] = (aenl_real_t)v;
            ad[i * LD + j] = (double)a[i * LD + j];
        }
    }
}

static void test_linalg_products_match_brute_force(void)
{
    aenl_real_t a[LD * LD], b[LD * LD], c[LD * LD];
    double ad[LD * LD], bd[LD * LD];
    const int n = 5, k = 4, m = 3;
    fill(a, ad, LD, LD);
    fill(b, bd, LD, LD);
    for (int i = 0; i < LD * LD; ++i)
    {
        c[i] = AENL_R(99.0); /* guard values outside the active block */
    }
    aenl_la_mul(c, LD, a, LD, b, LD, (uint16_t)n, (uint16_t)k, (uint16_t)m);
    for (int i = 0; i < n; ++i)
    {
        for (int j = 0; j < m; ++j)
        {
            double s = 0.0;
            for (int r = 0; r < k; ++r)
            {
                s += ad[i * LD + r] * bd[r * LD + j];
            }
            TEST_ASSERT_REAL_WITHIN(10.0 * AENL_TEST_REL_TOL, s, c[i * LD + j]);
        }
        TEST_ASSERT_REAL_WITHIN(0.0, 99.0, c[i * LD + m]);
    }
    TEST_ASSERT_REAL_WITHIN(0.0, 99.0, c[(size_t)n * LD]);
    aenl_la_mul_nt(c, LD, a, LD, b, LD, (uint16_t)n, (uint16_t)k, (uint16_t)m);
    for (int i = 0; i < n; ++i)
    {
        for (int j = 0; j < m; ++j)
        {
            double s = 0.0;
            for (int r = 0; r < k; ++r)
            {
                s += ad[i * LD + r] * bd[j * LD + r];
            }
            TEST_ASSERT_REAL_WITHIN(10.0 * AENL_TEST_REL_TOL, s, c[i * LD + j]);
        }
    }
    aenl_la_mul_tn(c, LD, a, LD, b, LD, (uint16_t)n, (uint16_t)k, (uint16_t)m);
    for (int i = 0; i < n; ++i)
    {
        for (int j = 0; j < m; ++j)
        {
            double s = 0.0;
            for (int r = 0; r < k; ++r)
            {
                s += ad[r * LD + i] * bd[r * LD + j];
            }
            TEST_ASSERT_REAL_WITHIN(10.0 * AENL_TEST_REL_TOL, s, c[i * LD + j]);
        }
    }
    aenl_real_t x[LD], y[LD];
    for (int i = 0; i < LD; ++i)
    {
        x[i] = (aenl_real_t)uni();
    }
    aenl_la_mv(y, a, LD, x, (uint16_t)n, (uint16_t)k);
    for (int i = 0; i < n; ++i)
    {
        double s = 0.0;
        for (int r = 0; r < k; ++r)
        {
            s += ad[i * LD + r] * (double)x[r];
        }
        TEST_ASSERT_REAL_WITHIN(10.0 * AENL_TEST_REL_TOL, s, y[i]);
    }
}

/* SPD matrix M = G G' + n I, its factor, and solves. */
static void test_linalg_cholesky_and_solves(void)
{
    const int n = 6;
    aenl_real_t g[LD * LD], m[LD * LD], l[LD * LD], bsol[LD * LD];
    double gd[LD * LD], md[LD * LD];
    fill(g, gd, LD, LD);
    for (int i = 0; i < n; ++i)
    {
        for (int j = 0; j < n; ++j)
        {
            double s = (i == j) ? (double)n : 0.0;
            for (int r = 0; r < n; ++r)
            {
                s += gd[i * LD + r] * gd[j * LD + r];
            }
            md[i * LD + j] = s;
            m[i * LD + j] = (aenl_real_t)s;
        }
    }
    memcpy(l, m, sizeof(l));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_la_chol(l, LD, (uint16_t)n));
    for (int i = 0; i < n; ++i)
    {
        for (int j = 0; j < n; ++j)
        {
            double s = 0.0;
            for (int r = 0; r < n; ++r)
            {
                s += (double)l[i * LD + r] * (double)l[j * LD + r];
            }
            TEST_ASSERT_REAL_WITHIN(20.0 * AENL_TEST_REL_TOL * (double)n, md[i * LD + j], s);
            if (j > i)
            {
                TEST_ASSERT_REAL_WITHIN(0.0, 0.0, l[i * LD + j]);
            }
        }
    }
    /* Solve M X = B for 3 right-hand sides; check M X = B in double. */
    double bd[LD * LD];
    fill(bsol, bd, LD, LD);
    aenl_la_chol_solve(l, LD, (uint16_t)n, bsol, LD, 3u);
    for (int i = 0; i < n; ++i)
    {
        for (int c = 0; c < 3; ++c)
        {
            double s = 0.0;
            for (int r = 0; r < n; ++r)
            {
                s += md[i * LD + r] * (double)bsol[r * LD + c];
            }
            TEST_ASSERT_REAL_WITHIN(100.0 * AENL_TEST_REL_TOL, bd[i * LD + c], s);
        }
    }
}

static void test_linalg_cholesky_reports_not_pd(void)
{
    aenl_real_t a[LD * LD];
    memset(a, 0, sizeof(a));
    /* [[1, 2], [2, 1]] is indefinite */
    a[0] = AENL_R(1.0);
    a[1] = AENL_R(2.0);
    a[LD] = AENL_R(2.0);
    a[LD + 1] = AENL_R(1.0);
    TEST_ASSERT_EQUAL_INT(AENL_E_NOT_PD, aenl_la_chol(a, LD, 2u));
    a[0] = AENL_R(0.0);
    TEST_ASSERT_EQUAL_INT(AENL_E_NOT_PD, aenl_la_chol(a, LD, 1u));
    a[0] = (aenl_real_t)NAN;
    TEST_ASSERT_EQUAL_INT(AENL_E_NOT_PD, aenl_la_chol(a, LD, 1u));
    a[0] = (aenl_real_t)INFINITY;
    TEST_ASSERT_EQUAL_INT(AENL_E_NOT_PD, aenl_la_chol(a, LD, 1u));
    /* semidefinite: second pivot exactly zero */
    a[0] = AENL_R(1.0);
    a[1] = AENL_R(1.0);
    a[LD] = AENL_R(1.0);
    a[LD + 1] = AENL_R(1.0);
    TEST_ASSERT_EQUAL_INT(AENL_E_NOT_PD, aenl_la_chol(a, LD, 2u));
}

static void test_linalg_symmetrise_and_checks(void)
{
    aenl_real_t a[LD * LD];
    double ad[LD * LD];
    fill(a, ad, LD, LD);
    TEST_ASSERT_EQUAL_INT(0, aenl_la_is_symmetric(a, LD, 4u, AENL_R(0.0)));
    aenl_la_symmetrise(a, LD, 4u);
    TEST_ASSERT_EQUAL_INT(1, aenl_la_is_symmetric(a, LD, 4u, AENL_R(0.0)));
    TEST_ASSERT_REAL_WITHIN(AENL_TEST_REL_TOL, 0.5 * (ad[LD] + ad[1]), a[1]);
    TEST_ASSERT_REAL_WITHIN(0.0, ad[LD + 4], a[LD + 4]); /* outside the block: untouched */
    TEST_ASSERT_EQUAL_INT(1, aenl_la_all_finite(a, LD, 4u, 4u));
    a[3 * LD + 2] = (aenl_real_t)NAN;
    TEST_ASSERT_EQUAL_INT(0, aenl_la_all_finite(a, LD, 4u, 4u));
    TEST_ASSERT_EQUAL_INT(1, aenl_la_all_finite(a, LD, 3u, 4u));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_linalg_products_match_brute_force);
    RUN_TEST(test_linalg_cholesky_and_solves);
    RUN_TEST(test_linalg_cholesky_reports_not_pd);
    RUN_TEST(test_linalg_symmetrise_and_checks);
    return UNITY_END();
}
