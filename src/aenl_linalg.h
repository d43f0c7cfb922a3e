/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_linalg.h
 * @brief Private small-matrix kernels of the core: row-major matrices with an explicit leading
 *        dimension (stride) so that fixed-capacity arrays (`P[AENL_SKF_MAX_X][AENL_SKF_MAX_X]`) are
 *        used in their active top-left block. No allocation, no temporaries on the stack beyond
 *        a few scalars; outputs must not alias inputs unless a function says so.
 */
#ifndef AENL_LINALG_H
#define AENL_LINALG_H

#include "aenl/aenl_types.h"

/*
 * Where the strided kernels (aenl_la_gemm, aenl_la_solve_tri) are compiled. 1: static inline,
 * here, so that a speed-optimising build specialises every call for its constant strides and
 * accumulate mode (the host SKF step spends most of its time in them); 0: one out-of-line copy
 * shared by every view, the smallest code (a -Os build: the budgeted Cortex-M4F text). Either way
 * the same loop below, so the same sums in the same order. -DAENL_LA_INLINE=0/1 overrides.
 */
#ifndef AENL_LA_INLINE
#ifdef __OPTIMIZE_SIZE__
#define AENL_LA_INLINE 0
#else
#define AENL_LA_INLINE 1
#endif
#endif

/**
 * C (n x m) = A B (acc 0), C + A B (acc > 0) or C - A B (acc < 0), with A(i, r) = a[i ai + r ar]
 * and B(r, j) = b[r br + j bj] (a transposed or strided view costs nothing); each entry is summed
 * in ascending r, from C(i, j) or from zero. C must not alias A or B.
 */
static inline void aenl_la_gemm_loop(aenl_real_t *c, size_t ldc, const aenl_real_t *a, size_t ai,
                                     size_t ar, const aenl_real_t *b, size_t br, size_t bj,
                                     uint32_t n, uint32_t k, uint32_t m, int acc)
{
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < m; ++j)
        {
            aenl_real_t s = acc ? c[i * ldc + j] : AENL_R(0.0);
            if (acc < 0) /* the test outside the loop: it runs per product otherwise */
            {
                for (size_t r = 0; r < k; ++r)
                {
                    s -= a[i * ai + r * ar] * b[r * br + j * bj];
                }
            }
            else
            {
                for (size_t r = 0; r < k; ++r)
                {
                    s += a[i * ai + r * ar] * b[r * br + j * bj];
                }
            }
            c[i * ldc + j] = s;
        }
    }
}

#if AENL_LA_INLINE
/* With B's rows contiguous (bj == 1), four entries of a row of C at a time, which the compiler
 * keeps in vector registers: each is still its own sum in ascending r (s - p is s + (-a) b
 * exactly), so the results are those of the loop; the columns left over go through the loop. */
static inline void aenl_la_gemm(aenl_real_t *c, size_t ldc, const aenl_real_t *a, size_t ai,
                                size_t ar, const aenl_real_t *b, size_t br, size_t bj, uint32_t n,
                                uint32_t k, uint32_t m, int acc)
{
    const size_t m4 = (bj == 1u) ? m & ~3u : 0u;
    const aenl_real_t sg = (acc < 0) ? AENL_R(-1.0) : AENL_R(1.0);
    for (size_t i = 0; i < n; ++i)
    {
        aenl_real_t *ci = c + i * ldc;
        for (size_t j = 0; j < m4; j += 4u)
        {
            aenl_real_t s0 = acc ? ci[j] : AENL_R(0.0), s1 = acc ? ci[j + 1u] : AENL_R(0.0),
                        s2 = acc ? ci[j + 2u] : AENL_R(0.0), s3 = acc ? ci[j + 3u] : AENL_R(0.0);
            for (size_t r = 0; r < k; ++r)
            {
                const aenl_real_t air = sg * a[i * ai + r * ar];
                const aenl_real_t *brow = b + r * br + j;
                s0 += air * brow[0];
                s1 += air * brow[1];
                s2 += air * brow[2];
                s3 += air * brow[3];
            }
            ci[j] = s0;
            ci[j + 1u] = s1;
            ci[j + 2u] = s2;
            ci[j + 3u] = s3;
        }
    }
    aenl_la_gemm_loop(c + m4, ldc, a, ai, ar, b + m4 * bj, br, bj, n, k, (uint32_t)(m - m4), acc);
}
#else
void aenl_la_gemm(aenl_real_t *c, size_t ldc, const aenl_real_t *a, size_t ai, size_t ar,
                  const aenl_real_t *b, size_t br, size_t bj, uint32_t n, uint32_t k, uint32_t m,
                  int acc);
#endif

/* The products below are views of aenl_la_gemm (inline: no code of their own). */

/** C (n x m) = A (n x k) * B (k x m). */
static inline void aenl_la_mul(aenl_real_t *c, uint32_t ldc, const aenl_real_t *a, uint32_t lda,
                               const aenl_real_t *b, uint32_t ldb, uint32_t n, uint32_t k,
                               uint32_t m)
{
    aenl_la_gemm(c, ldc, a, lda, 1u, b, ldb, 1u, n, k, m, 0);
}

/** C (n x m) = A (n x k) * B' with B (m x k). */
static inline void aenl_la_mul_nt(aenl_real_t *c, uint32_t ldc, const aenl_real_t *a, uint32_t lda,
                                  const aenl_real_t *b, uint32_t ldb, uint32_t n, uint32_t k,
                                  uint32_t m)
{
    aenl_la_gemm(c, ldc, a, lda, 1u, b, 1u, ldb, n, k, m, 0);
}

/** C (n x m) = A' * B with A (k x n), B (k x m). */
static inline void aenl_la_mul_tn(aenl_real_t *c, uint32_t ldc, const aenl_real_t *a, uint32_t lda,
                                  const aenl_real_t *b, uint32_t ldb, uint32_t n, uint32_t k,
                                  uint32_t m)
{
    aenl_la_gemm(c, ldc, a, 1u, lda, b, ldb, 1u, n, k, m, 0);
}

/** y (n) = A (n x m) x (m). y must not alias x. */
static inline void aenl_la_mv(aenl_real_t *y, const aenl_real_t *a, uint32_t lda,
                              const aenl_real_t *x, uint32_t n, uint32_t m)
{
    aenl_la_gemm(y, 1u, a, lda, 1u, x, 1u, 0u, n, m, 1u, 0);
}

/** A = (A + A') / 2 in place (n x n). */
static inline void aenl_la_symmetrise_loop(aenl_real_t *a, uint32_t lda, uint32_t n)
{
    for (uint32_t i = 0; i < n; ++i)
    {
        for (uint32_t j = 0; j < i; ++j)
        {
            const aenl_real_t v = AENL_R(0.5) * (a[(size_t)i * lda + j] + a[(size_t)j * lda + i]);
            a[(size_t)i * lda + j] = v;
            a[(size_t)j * lda + i] = v;
        }
    }
}

/**
 * @brief In-place lower Cholesky A = L L' (upper triangle set to zero).
 * @return AENL_OK; AENL_E_NOT_PD when a pivot is <= 0 or not finite (A is then partly
 *         overwritten: factor a copy when the original must survive).
 */
static inline aenl_status_t aenl_la_chol_loop(aenl_real_t *a, uint32_t lda, uint32_t n)
{
    for (uint32_t j = 0; j < n; ++j)
    {
        aenl_real_t d = a[(size_t)j * lda + j];
        for (uint32_t r = 0; r < j; ++r)
        {
            d -= a[(size_t)j * lda + r] * a[(size_t)j * lda + r];
        }
        if (!(d > AENL_R(0.0)) || !aenl_is_finite(d))
        {
            return AENL_E_NOT_PD;
        }
        const aenl_real_t ljj = aenl_sqrt(d);
        a[(size_t)j * lda + j] = ljj;
        const aenl_real_t inv = AENL_R(1.0) / ljj;
        for (uint32_t i = (uint32_t)(j + 1u); i < n; ++i)
        {
            aenl_real_t s = a[(size_t)i * lda + j];
            for (uint32_t r = 0; r < j; ++r)
            {
                s -= a[(size_t)i * lda + r] * a[(size_t)j * lda + r];
            }
            a[(size_t)i * lda + j] = s * inv;
        }
        for (uint32_t i = 0; i < j; ++i)
        {
            a[(size_t)i * lda + j] = AENL_R(0.0);
        }
    }
    return AENL_OK;
}

#if AENL_LA_INLINE
static inline void aenl_la_symmetrise(aenl_real_t *a, uint32_t lda, uint32_t n)
{
    aenl_la_symmetrise_loop(a, lda, n);
}

static inline aenl_status_t aenl_la_chol(aenl_real_t *a, uint32_t lda, uint32_t n)
{
    return aenl_la_chol_loop(a, lda, n);
}
#else
void aenl_la_symmetrise(aenl_real_t *a, uint32_t lda, uint32_t n);
aenl_status_t aenl_la_chol(aenl_real_t *a, uint32_t lda, uint32_t n);
#endif

/**
 * Solve T X = B in place (B n x m, rows ldb apart), T triangular with a nonzero diagonal, read as
 * T(i, j) = t[i ti + j tj] (a transposed or differently strided view costs nothing): lower
 * (forward substitution) or, with upper, upper (backward). Each entry subtracts its known terms in
 * ascending j; a row of B at a time, so that the innermost loop runs along the row.
 */
static inline void aenl_la_solve_tri_loop(const aenl_real_t *t, size_t ti, size_t tj, uint32_t n,
                                          aenl_real_t *b, size_t ldb, uint32_t m, int upper)
{
    for (size_t step = 0; step < n; ++step)
    {
        const size_t i = upper ? n - 1u - step : step;
        aenl_real_t *bi = b + i * ldb;
        for (size_t j = upper ? i + 1u : 0u; j < (upper ? n : i); ++j)
        {
            const aenl_real_t tij = t[i * ti + j * tj];
            const aenl_real_t *bj = b + j * ldb;
            for (size_t c = 0; c < m; ++c)
            {
                bi[c] -= tij * bj[c];
            }
        }
        const aenl_real_t tii = t[i * (ti + tj)];
        for (size_t c = 0; c < m; ++c)
        {
            bi[c] /= tii;
        }
    }
}

#if AENL_LA_INLINE
static inline void aenl_la_solve_tri(const aenl_real_t *t, size_t ti, size_t tj, uint32_t n,
                                     aenl_real_t *b, size_t ldb, uint32_t m, int upper)
{
    aenl_la_solve_tri_loop(t, ti, tj, n, b, ldb, m, upper);
}
#else
void aenl_la_solve_tri(const aenl_real_t *t, size_t ti, size_t tj, uint32_t n, aenl_real_t *b,
                       size_t ldb, uint32_t m, int upper);
#endif

/** Solve L X = B in place (B n x m), L lower with a nonzero diagonal. */
static inline void aenl_la_solve_lower(const aenl_real_t *l, uint32_t ldl, uint32_t n,
                                       aenl_real_t *b, uint32_t ldb, uint32_t m)
{
    aenl_la_solve_tri(l, ldl, 1u, n, b, ldb, m, 0);
}

/** Solve L' X = B in place (B n x m). */
static inline void aenl_la_solve_lower_t(const aenl_real_t *l, uint32_t ldl, uint32_t n,
                                         aenl_real_t *b, uint32_t ldb, uint32_t m)
{
    aenl_la_solve_tri(l, 1u, ldl, n, b, ldb, m, 1);
}

/** Solve (L L') X = B in place, L from aenl_la_chol. */
static inline void aenl_la_chol_solve_loop(const aenl_real_t *l, uint32_t ldl, uint32_t n,
                                           aenl_real_t *b, uint32_t ldb, uint32_t m)
{
    aenl_la_solve_lower(l, ldl, n, b, ldb, m);
    aenl_la_solve_lower_t(l, ldl, n, b, ldb, m);
}

/** 1 when every entry of the n x m block is finite. */
static inline int aenl_la_all_finite_loop(const aenl_real_t *a, uint32_t lda, uint32_t n,
                                          uint32_t m)
{
    for (uint32_t i = 0; i < n; ++i)
    {
        for (uint32_t j = 0; j < m; ++j)
        {
            if (!aenl_is_finite(a[(size_t)i * lda + j]))
            {
                return 0;
            }
        }
    }
    return 1;
}

#if AENL_LA_INLINE
static inline void aenl_la_chol_solve(const aenl_real_t *l, uint32_t ldl, uint32_t n,
                                      aenl_real_t *b, uint32_t ldb, uint32_t m)
{
    aenl_la_chol_solve_loop(l, ldl, n, b, ldb, m);
}

static inline int aenl_la_all_finite(const aenl_real_t *a, uint32_t lda, uint32_t n, uint32_t m)
{
    return aenl_la_all_finite_loop(a, lda, n, m);
}
#else
void aenl_la_chol_solve(const aenl_real_t *l, uint32_t ldl, uint32_t n, aenl_real_t *b,
                        uint32_t ldb, uint32_t m);
int aenl_la_all_finite(const aenl_real_t *a, uint32_t lda, uint32_t n, uint32_t m);
#endif

/** 1 when A (n x n) is symmetric to rel_tol * (|a_ij| + |a_ji|) (exactly, for rel_tol = 0). */
int aenl_la_is_symmetric(const aenl_real_t *a, uint32_t lda, uint32_t n, aenl_real_t rel_tol);

#endif /* AENL_LINALG_H */
