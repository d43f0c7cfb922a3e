/* SPDX-License-Identifier: MIT */
/**
 * @file test_dense.c
 * @brief The host dense kernels (aenl_dense) against independent references on random
 *        matrices: the products bit for bit against the plain triple loop (the order their
 *        callers' results depend on), the Cholesky factors by L L' = A, the solves by the
 *        residual A x - b, the inverse by A A^-1 = I, and the failures on matrices that are not
 *        positive definite or are singular.
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "aenl_test_rand.h"
#include "aenl_tools/aenl_dense.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

#define MAXN 16

/* Sizes around the kernels' blocks (pairs of rows, 4 and 8 columns) and their remainders. */
static const size_t SIZES[] = {1, 2, 3, 4, 5, 7, 8, 9, 12, 13, 16};
#define N_SIZES (sizeof(SIZES) / sizeof(SIZES[0]))

static void fill_gauss(double *v, size_t n, uint64_t *s)
{
    for (size_t i = 0; i < n; ++i)
    {
        v[i] = test_gauss(s);
    }
}

/* A random symmetric positive definite n x n: X X' + n I with X n x (n + 2) Gaussian. */
static void random_spd(double *a, size_t n, uint64_t *s)
{
    double x[MAXN * (MAXN + 2)];
    const size_t k = n + 2u;
    fill_gauss(x, n * k, s);
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < n; ++j)
        {
            double acc = (i == j) ? (double)n : 0.0;
            for (size_t r = 0; r < k; ++r)
            {
                acc += x[i * k + r] * x[j * k + r];
            }
            a[i * n + j] = acc;
        }
    }
}

/* Exact equality, bit for bit (the warnings forbid == on doubles). */
static int same_bits(double a, double b)
{
    uint64_t ua, ub;
    memcpy(&ua, &a, sizeof(ua));
    memcpy(&ub, &b, sizeof(ub));
    return ua == ub;
}

/* The largest |entry| of a (n entries), at least 1e-300. */
static double max_abs(const double *a, size_t n)
{
    double m = 1e-300;
    for (size_t i = 0; i < n; ++i)
    {
        m = fmax(m, fabs(a[i]));
    }
    return m;
}

/* max |(L L')_ij - A_ij| / max |A| for the lower triangle of l (upper entries ignored). */
static double reconstruction_error(const double *l, const double *a, size_t n)
{
    double err = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < n; ++j)
        {
            double acc = 0.0;
            for (size_t r = 0; r <= (i < j ? i : j); ++r)
            {
                acc += l[i * n + r] * l[j * n + r];
            }
            err = fmax(err, fabs(acc - a[i * n + j]));
        }
    }
    return err / max_abs(a, n * n);
}

/* max |A X - B| / (max |A| max |X| n) over the m right-hand sides (columns of the n x m X). */
static double residual(const double *a, const double *x, const double *b, size_t n, size_t m)
{
    double err = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < m; ++j)
        {
            double acc = 0.0;
            for (size_t r = 0; r < n; ++r)
            {
                acc += a[i * n + r] * x[r * m + j];
            }
            err = fmax(err, fabs(acc - b[i * m + j]));
        }
    }
    return err / (max_abs(a, n * n) * max_abs(x, n * m) * (double)n);
}

/* The reference product ref (n x m), ref_ij = sum over r = 0..k-1, in that order, of
 * a[i ai + r ar] b[r br + j bj]: the plain triple loop, with the strides naming A or A' and
 * B or B'. */
static void ref_product(double *ref, const double *a, size_t ai, size_t ar, const double *b,
                        size_t br, size_t bj, size_t n, size_t k, size_t m)
{
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < m; ++j)
        {
            double acc = 0.0;
            for (size_t r = 0; r < k; ++r)
            {
                acc += a[i * ai + r * ar] * b[r * br + j * bj];
            }
            ref[i * m + j] = acc;
        }
    }
}

static void test_products_match_triple_loop(void)
{
    uint64_t s = 1u;
    double a[MAXN * MAXN], b[MAXN * MAXN], c[MAXN * MAXN], ref[MAXN * MAXN];
    for (size_t in = 0; in < N_SIZES; ++in)
    {
        for (size_t ik = 0; ik < N_SIZES; ++ik)
        {
            for (size_t im = 0; im < N_SIZES; ++im)
            {
                const size_t n = SIZES[in], k = SIZES[ik], m = SIZES[im];
                fill_gauss(a, n * k, &s);
                fill_gauss(b, k * m, &s);
                aenl_dense_mul(c, a, b, n, k, m);
                ref_product(ref, a, k, 1u, b, m, 1u, n, k, m);
                TEST_ASSERT_EQUAL_MEMORY(ref, c, n * m * sizeof(double));
                /* A' B with A stored k x n */
                fill_gauss(a, k * n, &s);
                aenl_dense_mul_tn(c, a, b, n, k, m);
                ref_product(ref, a, 1u, n, b, m, 1u, n, k, m);
                TEST_ASSERT_EQUAL_MEMORY(ref, c, n * m * sizeof(double));
            }
        }
    }
}

/* The symmetric variants on X X' and X' X, whose triple loops are symmetric bit for bit. */
static void test_symmetric_products(void)
{
    uint64_t s = 2u;
    double x[MAXN * MAXN], xt[MAXN * MAXN], c[MAXN * MAXN], ref[MAXN * MAXN];
    for (size_t in = 0; in < N_SIZES; ++in)
    {
        for (size_t ik = 0; ik < N_SIZES; ++ik)
        {
            const size_t n = SIZES[in], k = SIZES[ik];
            fill_gauss(x, n * k, &s);
            for (size_t i = 0; i < n; ++i)
            {
                for (size_t r = 0; r < k; ++r)
                {
                    xt[r * n + i] = x[i * k + r];
                }
            }
            ref_product(ref, x, k, 1u, x, 1u, k, n, k, n); /* X X' */
            memset(c, 0, sizeof(c));
            aenl_dense_mul_sym(c, x, xt, n, k); /* X X' */
            TEST_ASSERT_EQUAL_MEMORY(ref, c, n * n * sizeof(double));
            memset(c, 0, sizeof(c));
            aenl_dense_mul_tn_sym(c, xt, xt, n, k); /* (X')' X' = X X' */
            TEST_ASSERT_EQUAL_MEMORY(ref, c, n * n * sizeof(double));
        }
    }
}

static void test_mirror_and_symmetrise(void)
{
    const double a[9] = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0};
    const double mirrored[9] = {1.0, 4.0, 7.0, 4.0, 5.0, 8.0, 7.0, 8.0, 9.0};
    const double mean[9] = {1.0, 3.0, 5.0, 3.0, 5.0, 7.0, 5.0, 7.0, 9.0};
    double b[9];
    memcpy(b, a, sizeof(b));
    aenl_dense_mirror_lower(b, 3);
    TEST_ASSERT_EQUAL_MEMORY(mirrored, b, sizeof(b));
    memcpy(b, a, sizeof(b));
    aenl_dense_symmetrise(b, 3);
    TEST_ASSERT_EQUAL_MEMORY(mean, b, sizeof(b));
}

static void test_chol_reconstructs_and_solves(void)
{
    uint64_t s = 3u;
    double a[MAXN * MAXN], l[MAXN * MAXN], inv[MAXN], x[MAXN * MAXN], rhs[MAXN * MAXN];
    for (size_t in = 0; in < N_SIZES; ++in)
    {
        const size_t n = SIZES[in];
        random_spd(a, n, &s);
        memcpy(l, a, n * n * sizeof(double));
        for (size_t i = 0; i < n; ++i)
        {
            for (size_t j = i + 1u; j < n; ++j)
            {
                l[i * n + j] = 12345.0; /* the upper triangle is left as it was */
            }
        }
        TEST_ASSERT_EQUAL_INT(0, aenl_dense_chol(l, n, inv));
        TEST_ASSERT_TRUE(reconstruction_error(l, a, n) < 1e-14);
        for (size_t i = 0; i < n; ++i)
        {
            TEST_ASSERT_TRUE(same_bits(inv[i], 1.0 / l[i * n + i]));
            for (size_t j = i + 1u; j < n; ++j)
            {
                TEST_ASSERT_TRUE(same_bits(l[i * n + j], 12345.0));
            }
        }
        for (size_t im = 0; im < N_SIZES; ++im) /* 8-, 4- and 1-column paths of the solve */
        {
            const size_t m = SIZES[im];
            fill_gauss(rhs, n * m, &s);
            memcpy(x, rhs, n * m * sizeof(double));
            aenl_dense_chol_solve(l, inv, n, x, m);
            TEST_ASSERT_TRUE(residual(a, x, rhs, n, m) < 1e-14);
        }
    }
}

static void test_chol_failures_and_jitter(void)
{
    double inv[2], l[4];
    double indefinite[4] = {1.0, 0.0, 0.0, -1.0};
    TEST_ASSERT_EQUAL_INT(-1, aenl_dense_chol(indefinite, 2, inv));
    double nan_pivot[4] = {(double)NAN, 0.0, 0.0, 1.0};
    TEST_ASSERT_EQUAL_INT(-1, aenl_dense_chol(nan_pivot, 2, NULL));
    /* singular semi-definite: the plain factor fails, a jitter of about 1e-14 succeeds */
    const double singular[4] = {1.0, 1.0, 1.0, 1.0};
    memcpy(l, singular, sizeof(l));
    TEST_ASSERT_EQUAL_INT(-1, aenl_dense_chol(l, 2, NULL));
    TEST_ASSERT_EQUAL_INT(0, aenl_dense_chol_jitter(l, singular, 2, inv));
    TEST_ASSERT_TRUE(reconstruction_error(l, singular, 2) < 1e-12);
    TEST_ASSERT_TRUE(same_bits(inv[1], 1.0 / l[3]));
    /* indefinite: the largest jitter, 1e-2 of the diagonal, is not enough */
    const double indef[4] = {1.0, 0.0, 0.0, -1.0};
    TEST_ASSERT_EQUAL_INT(-1, aenl_dense_chol_jitter(l, indef, 2, inv));
    /* a positive definite matrix is factored without jitter: the plain factor bit for bit */
    uint64_t s = 4u;
    double a[MAXN * MAXN], l1[MAXN * MAXN], l2[MAXN * MAXN];
    random_spd(a, 7, &s);
    memcpy(l1, a, sizeof(double) * 49u);
    TEST_ASSERT_EQUAL_INT(0, aenl_dense_chol(l1, 7, NULL));
    TEST_ASSERT_EQUAL_INT(0, aenl_dense_chol_jitter(l2, a, 7, NULL));
    TEST_ASSERT_EQUAL_MEMORY(l1, l2, sizeof(double) * 49u);
}

static void test_lower_solve(void)
{
    uint64_t s = 5u;
    double l[MAXN * MAXN], x[MAXN], b[MAXN];
    for (size_t in = 0; in < N_SIZES; ++in)
    {
        const size_t n = SIZES[in];
        fill_gauss(l, n * n, &s);
        for (size_t i = 0; i < n; ++i)
        {
            l[i * n + i] = 2.0 + fabs(l[i * n + i]); /* well away from singular */
        }
        fill_gauss(b, n, &s);
        memcpy(x, b, n * sizeof(double));
        aenl_dense_lower_solve(l, x, n);
        /* residual of the lower triangle only: the upper one is not read */
        double err = 0.0, scale = 1e-300;
        for (size_t i = 0; i < n; ++i)
        {
            double acc = 0.0;
            for (size_t r = 0; r <= i; ++r)
            {
                acc += l[i * n + r] * x[r];
                scale = fmax(scale, fabs(l[i * n + r] * x[r]));
            }
            err = fmax(err, fabs(acc - b[i]));
        }
        TEST_ASSERT_TRUE(err < 1e-14 * scale * (double)n);
    }
}

static void test_lapack_factor_and_solves(void)
{
    uint64_t s = 6u;
    double a[MAXN * MAXN], l[MAXN * MAXN], x[MAXN * MAXN], rhs[MAXN * MAXN], g[MAXN * MAXN];
    for (size_t in = 0; in < N_SIZES; ++in)
    {
        const size_t n = SIZES[in];
        random_spd(a, n, &s);
        memcpy(l, a, n * n * sizeof(double));
        for (size_t i = 0; i < n; ++i)
        {
            for (size_t j = i + 1u; j < n; ++j)
            {
                l[i * n + j] = -777.0; /* neither read nor written */
            }
        }
        TEST_ASSERT_EQUAL_INT(0, aenl_dense_potrf(l, n));
        TEST_ASSERT_TRUE(reconstruction_error(l, a, n) < 1e-14);
        for (size_t i = 0; i < n; ++i)
        {
            for (size_t j = i + 1u; j < n; ++j)
            {
                TEST_ASSERT_TRUE(same_bits(l[i * n + j], -777.0));
            }
        }
        const size_t m = SIZES[(in * 3u) % N_SIZES];
        fill_gauss(rhs, n * m, &s);
        memcpy(x, rhs, n * m * sizeof(double));
        aenl_dense_potrs(l, n, x, m);
        TEST_ASSERT_TRUE(residual(a, x, rhs, n, m) < 1e-14);
        /* dposv: the same solution from the factor it leaves in g */
        memcpy(g, a, n * n * sizeof(double));
        memcpy(x, rhs, n * m * sizeof(double));
        TEST_ASSERT_EQUAL_INT(0, aenl_dense_posv(g, x, n, m));
        TEST_ASSERT_TRUE(residual(a, x, rhs, n, m) < 1e-14);
        TEST_ASSERT_TRUE(reconstruction_error(g, a, n) < 1e-14);
    }
    double indefinite[4] = {1.0, 2.0, 2.0, 1.0};
    TEST_ASSERT_EQUAL_INT(-1, aenl_dense_potrf(indefinite, 2));
    double indefinite2[4] = {1.0, 2.0, 2.0, 1.0}, b2[2] = {1.0, 1.0};
    TEST_ASSERT_EQUAL_INT(-1, aenl_dense_posv(indefinite2, b2, 2, 1));
}

static void test_invert(void)
{
    uint64_t s = 7u;
    double a[MAXN * MAXN], w[MAXN * MAXN], inv[MAXN * MAXN];
    for (size_t in = 0; in < N_SIZES; ++in)
    {
        const size_t n = SIZES[in];
        fill_gauss(a, n * n, &s); /* general (not symmetric), pivoting needed */
        for (size_t i = 0; i < n; ++i)
        {
            a[i * n + i] *= 0.1;
        }
        memcpy(w, a, n * n * sizeof(double));
        TEST_ASSERT_EQUAL_INT(0, aenl_dense_invert(w, inv, n));
        double err = 0.0;
        for (size_t i = 0; i < n; ++i)
        {
            for (size_t j = 0; j < n; ++j)
            {
                double acc = 0.0;
                for (size_t r = 0; r < n; ++r)
                {
                    acc += a[i * n + r] * inv[r * n + j];
                }
                err = fmax(err, fabs(acc - (i == j ? 1.0 : 0.0)));
            }
        }
        TEST_ASSERT_TRUE(err < 1e-10);
    }
    /* a zero in the first pivot's place: the rows are swapped */
    double p[4] = {0.0, 2.0, 4.0, 0.0};
    const double p_inv[4] = {0.0, 0.25, 0.5, 0.0};
    TEST_ASSERT_EQUAL_INT(0, aenl_dense_invert(p, inv, 2));
    TEST_ASSERT_EQUAL_MEMORY(p_inv, inv, sizeof(p_inv));
    double singular[9] = {1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0};
    TEST_ASSERT_EQUAL_INT(-1, aenl_dense_invert(singular, inv, 3));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_products_match_triple_loop);
    RUN_TEST(test_symmetric_products);
    RUN_TEST(test_mirror_and_symmetrise);
    RUN_TEST(test_chol_reconstructs_and_solves);
    RUN_TEST(test_chol_failures_and_jitter);
    RUN_TEST(test_lower_solve);
    RUN_TEST(test_lapack_factor_and_solves);
    RUN_TEST(test_invert);
    return UNITY_END();
}
