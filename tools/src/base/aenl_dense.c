/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_dense.c
 * @brief Host dense linear algebra (see aenl_dense.h): one implementation of each kernel, with
 *        the arithmetic order every caller's results depend on.
 */
#include "aenl_tools/aenl_dense.h"

#include <lapacke.h>
#include <math.h>
#include <string.h>

/* ---- products ---------------------------------------------------------------------------------
 * The products keep a 2 x 4 block of the result in registers (8 independent accumulators),
 * which is what makes the 8-state E-step fast without -O3 or intrinsics. Each accumulator still
 * sums over the inner index in ascending order from 0.0, so every entry is rounded as the plain
 * triple loop rounds it. The symmetric variants compute only the blocks on or below the diagonal
 * and copy the lower triangle into the upper one.
 */

void aenl_dense_mirror_lower(double *s, size_t n)
{
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = i + 1; j < n; ++j)
        {
            s[i * n + j] = s[j * n + i];
        }
    }
}

void aenl_dense_symmetrise(double *a, size_t n)
{
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < i; ++j)
        {
            const double v = 0.5 * (a[i * n + j] + a[j * n + i]);
            a[i * n + j] = v;
            a[j * n + i] = v;
        }
    }
}

/* C (n x m) = A (n x k) B (k x m); sym: n == m and only the lower triangle is computed. */
static void mul_nn(double *restrict c, const double *restrict a, const double *restrict b, size_t n,
                   size_t k, size_t m, int sym)
{
    size_t i = 0;
    for (; i + 2 <= n; i += 2)
    {
        const double *a0 = a + i * k, *a1 = a0 + k;
        const size_t jend = sym ? (i + 2 < m ? i + 2 : m) : m;
        size_t j = 0;
        for (; j + 4 <= jend || (j < jend && j + 4 <= m); j += 4)
        {
            double c00 = 0.0, c01 = 0.0, c02 = 0.0, c03 = 0.0;
            double c10 = 0.0, c11 = 0.0, c12 = 0.0, c13 = 0.0;
            for (size_t r = 0; r < k; ++r)
            {
                const double *br = b + r * m + j;
                const double x0 = a0[r], x1 = a1[r];
                c00 += x0 * br[0];
                c01 += x0 * br[1];
                c02 += x0 * br[2];
                c03 += x0 * br[3];
                c10 += x1 * br[0];
                c11 += x1 * br[1];
                c12 += x1 * br[2];
                c13 += x1 * br[3];
            }
            double *c0 = c + i * m + j, *c1 = c0 + m;
            c0[0] = c00;
            c0[1] = c01;
            c0[2] = c02;
            c0[3] = c03;
            c1[0] = c10;
            c1[1] = c11;
            c1[2] = c12;
            c1[3] = c13;
        }
        for (; j < jend; ++j)
        {
            double s0 = 0.0, s1 = 0.0;
            for (size_t r = 0; r < k; ++r)
            {
                s0 += a0[r] * b[r * m + j];
                s1 += a1[r] * b[r * m + j];
            }
            c[i * m + j] = s0;
            c[(i + 1) * m + j] = s1;
        }
    }
    for (; i < n; ++i)
    {
        const size_t jend = sym ? i + 1 : m;
        for (size_t j = 0; j < jend; ++j)
        {
            double s = 0.0;
            for (size_t r = 0; r < k; ++r)
            {
                s += a[i * k + r] * b[r * m + j];
            }
            c[i * m + j] = s;
        }
    }
    if (sym)
    {
        aenl_dense_mirror_lower(c, n);
    }
}

/* C (n x m) = A' B with A (k x n), B (k x m); sym: n == m, lower triangle computed and mirrored.
 * Both operands are read along contiguous rows. */
static void mul_tn(double *restrict c, const double *restrict a, const double *restrict b, size_t n,
                   size_t k, size_t m, int sym)
{
    size_t i = 0;
    for (; i + 2 <= n; i += 2)
    {
        const size_t jend = sym ? (i + 2 < m ? i + 2 : m) : m;
        size_t j = 0;
        for (; j + 4 <= jend || (j < jend && j + 4 <= m); j += 4)
        {
            double c00 = 0.0, c01 = 0.0, c02 = 0.0, c03 = 0.0;
            double c10 = 0.0, c11 = 0.0, c12 = 0.0, c13 = 0.0;
            for (size_t r = 0; r < k; ++r)
            {
                const double *br = b + r * m + j;
                const double x0 = a[r * n + i], x1 = a[r * n + i + 1];
                c00 += x0 * br[0];
                c01 += x0 * br[1];
                c02 += x0 * br[2];
                c03 += x0 * br[3];
                c10 += x1 * br[0];
                c11 += x1 * br[1];
                c12 += x1 * br[2];
                c13 += x1 * br[3];
            }
            double *c0 = c + i * m + j, *c1 = c0 + m;
            c0[0] = c00;
            c0[1] = c01;
            c0[2] = c02;
            c0[3] = c03;
            c1[0] = c10;
            c1[1] = c11;
            c1[2] = c12;
            c1[3] = c13;
        }
        for (; j < jend; ++j)
        {
            double s0 = 0.0, s1 = 0.0;
            for (size_t r = 0; r < k; ++r)
            {
                s0 += a[r * n + i] * b[r * m + j];
                s1 += a[r * n + i + 1] * b[r * m + j];
            }
            c[i * m + j] = s0;
            c[(i + 1) * m + j] = s1;
        }
    }
    for (; i < n; ++i)
    {
        const size_t jend = sym ? i + 1 : m;
        for (size_t j = 0; j < jend; ++j)
        {
            double s = 0.0;
            for (size_t r = 0; r < k; ++r)
            {
                s += a[r * n + i] * b[r * m + j];
            }
            c[i * m + j] = s;
        }
    }
    if (sym)
    {
        aenl_dense_mirror_lower(c, n);
    }
}

void aenl_dense_mul(double *restrict c, const double *restrict a, const double *restrict b,
                    size_t n, size_t k, size_t m)
{
    mul_nn(c, a, b, n, k, m, 0);
}

void aenl_dense_mul_sym(double *restrict c, const double *restrict a, const double *restrict b,
                        size_t n, size_t k)
{
    mul_nn(c, a, b, n, k, n, 1);
}

void aenl_dense_mul_tn(double *restrict c, const double *restrict a, const double *restrict b,
                       size_t n, size_t k, size_t m)
{
    mul_tn(c, a, b, n, k, m, 0);
}

void aenl_dense_mul_tn_sym(double *restrict c, const double *restrict a, const double *restrict b,
                           size_t n, size_t k)
{
    mul_tn(c, a, b, n, k, n, 1);
}

/* ---- Cholesky factor with reciprocal pivots ------------------------------------------------- */

int aenl_dense_chol(double *a, size_t n, double *inv)
{
    for (size_t j = 0; j < n; ++j)
    {
        double d = a[j * n + j];
        for (size_t r = 0; r < j; ++r)
        {
            d -= a[j * n + r] * a[j * n + r];
        }
        if (!(d > 0.0) || !isfinite(d))
        {
            return -1;
        }
        const double l = sqrt(d), il = 1.0 / l;
        a[j * n + j] = l;
        if (inv != NULL)
        {
            inv[j] = il;
        }
        for (size_t i = j + 1; i < n; ++i)
        {
            double s = a[i * n + j];
            for (size_t r = 0; r < j; ++r)
            {
                s -= a[i * n + r] * a[j * n + r];
            }
            a[i * n + j] = s * il;
        }
    }
    return 0;
}

int aenl_dense_chol_jitter(double *l, const double *a, size_t n, double *inv)
{
    double tr = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        tr += fabs(a[i * n + i]);
    }
    double jit = 0.0;
    for (int attempt = 0; attempt < 8; ++attempt)
    {
        memcpy(l, a, n * n * sizeof(double));
        for (size_t i = 0; i < n; ++i)
        {
            l[i * n + i] += jit;
        }
        if (aenl_dense_chol(l, n, inv) == 0)
        {
            return 0;
        }
        jit = (attempt == 0) ? 1e-14 * (tr / (double)n + 1e-300) : jit * 100.0;
    }
    return -1;
}

/* Eight (then four, then one) columns of B at a time stay in registers through the forward and
 * backward substitutions: the substitutions are latency-bound chains, and independent columns
 * fill them. */
void aenl_dense_chol_solve(const double *l, const double *inv, size_t n, double *b, size_t m)
{
    size_t j = 0;
    for (; j + 8 <= m; j += 8)
    {
        for (size_t pass = 0; pass < 2; ++pass)
        {
            for (size_t t = 0; t < n; ++t)
            {
                const size_t i = pass ? n - 1 - t : t;
                double *bi = b + i * m + j;
                double c0 = bi[0], c1 = bi[1], c2 = bi[2], c3 = bi[3];
                double c4 = bi[4], c5 = bi[5], c6 = bi[6], c7 = bi[7];
                const size_t r0 = pass ? i + 1 : 0, r1 = pass ? n : i;
                for (size_t r = r0; r < r1; ++r)
                {
                    const double lr = pass ? l[r * n + i] : l[i * n + r];
                    const double *br = b + r * m + j;
                    c0 -= lr * br[0];
                    c1 -= lr * br[1];
                    c2 -= lr * br[2];
                    c3 -= lr * br[3];
                    c4 -= lr * br[4];
                    c5 -= lr * br[5];
                    c6 -= lr * br[6];
                    c7 -= lr * br[7];
                }
                const double d = inv[i];
                bi[0] = c0 * d;
                bi[1] = c1 * d;
                bi[2] = c2 * d;
                bi[3] = c3 * d;
                bi[4] = c4 * d;
                bi[5] = c5 * d;
                bi[6] = c6 * d;
                bi[7] = c7 * d;
            }
        }
    }
    for (; j + 4 <= m; j += 4)
    {
        for (size_t pass = 0; pass < 2; ++pass)
        {
            for (size_t t = 0; t < n; ++t)
            {
                const size_t i = pass ? n - 1 - t : t;
                double *bi = b + i * m + j;
                double c0 = bi[0], c1 = bi[1], c2 = bi[2], c3 = bi[3];
                const size_t r0 = pass ? i + 1 : 0, r1 = pass ? n : i;
                for (size_t r = r0; r < r1; ++r)
                {
                    const double lr = pass ? l[r * n + i] : l[i * n + r];
                    const double *br = b + r * m + j;
                    c0 -= lr * br[0];
                    c1 -= lr * br[1];
                    c2 -= lr * br[2];
                    c3 -= lr * br[3];
                }
                const double d = inv[i];
                bi[0] = c0 * d;
                bi[1] = c1 * d;
                bi[2] = c2 * d;
                bi[3] = c3 * d;
            }
        }
    }
    for (; j < m; ++j)
    {
        for (size_t pass = 0; pass < 2; ++pass)
        {
            for (size_t t = 0; t < n; ++t)
            {
                const size_t i = pass ? n - 1 - t : t;
                double c = b[i * m + j];
                const size_t r0 = pass ? i + 1 : 0, r1 = pass ? n : i;
                for (size_t r = r0; r < r1; ++r)
                {
                    c -= (pass ? l[r * n + i] : l[i * n + r]) * b[r * m + j];
                }
                b[i * m + j] = c * inv[i];
            }
        }
    }
}

/* ---- triangular ------------------------------------------------------------------------------ */

void aenl_dense_lower_solve(const double *l, double *x, size_t n)
{
    for (size_t i = 0; i < n; ++i)
    {
        double s = x[i];
        for (size_t k = 0; k < i; ++k)
        {
            s -= l[i * n + k] * x[k];
        }
        x[i] = s / l[i * n + i];
    }
}

/* ---- LAPACK, lower factor -------------------------------------------------------------------- */

int aenl_dense_potrf(double *a, size_t n)
{
    return LAPACKE_dpotrf(LAPACK_ROW_MAJOR, 'L', (lapack_int)n, a, (lapack_int)n) == 0 ? 0 : -1;
}

void aenl_dense_potrs(const double *l, size_t n, double *b, size_t nrhs)
{
    (void)LAPACKE_dpotrs(LAPACK_ROW_MAJOR, 'L', (lapack_int)n, (lapack_int)nrhs, l, (lapack_int)n,
                         b, (lapack_int)nrhs);
}

int aenl_dense_posv(double *a, double *b, size_t n, size_t nrhs)
{
    return LAPACKE_dposv(LAPACK_ROW_MAJOR, 'L', (lapack_int)n, (lapack_int)nrhs, a, (lapack_int)n,
                         b, (lapack_int)nrhs) == 0
               ? 0
               : -1;
}

/* ---- inverse --------------------------------------------------------------------------------- */

/* The elimination runs over every column of a and of inv, the pivot's own and those already
 * reduced included, so that each entry is rounded as in the elimination on the augmented
 * matrix [a | I]. */
int aenl_dense_invert(double *a, double *inv, size_t n)
{
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < n; ++j)
        {
            inv[i * n + j] = (i == j) ? 1.0 : 0.0;
        }
    }
    for (size_t k = 0; k < n; ++k)
    {
        size_t p = k;
        for (size_t i = k + 1; i < n; ++i)
        {
            if (fabs(a[i * n + k]) > fabs(a[p * n + k]))
            {
                p = i;
            }
        }
        if (!(fabs(a[p * n + k]) > 0.0))
        {
            return -1;
        }
        if (p != k)
        {
            for (size_t j = 0; j < n; ++j)
            {
                const double ta = a[k * n + j], ti = inv[k * n + j];
                a[k * n + j] = a[p * n + j];
                a[p * n + j] = ta;
                inv[k * n + j] = inv[p * n + j];
                inv[p * n + j] = ti;
            }
        }
        const double piv = a[k * n + k];
        for (size_t j = 0; j < n; ++j)
        {
            a[k * n + j] /= piv;
            inv[k * n + j] /= piv;
        }
        for (size_t i = 0; i < n; ++i)
        {
            if (i != k)
            {
                const double f = a[i * n + k];
                for (size_t j = 0; j < n; ++j)
                {
                    a[i * n + j] -= f * a[k * n + j];
                    inv[i * n + j] -= f * inv[k * n + j];
                }
            }
        }
    }
    return 0;
}
