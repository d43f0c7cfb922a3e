/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_linalg.c
 * @brief Private small-matrix kernels (see aenl_linalg.h). Plain loops: the sizes are at most
 *        AENL_SKF_MAX_X, where blocking or vectorised libraries gain nothing on a Cortex-M.
 */
#include "aenl_linalg.h"

#if !AENL_LA_INLINE
void aenl_la_gemm(aenl_real_t *c, size_t ldc, const aenl_real_t *a, size_t ai, size_t ar,
                  const aenl_real_t *b, size_t br, size_t bj, uint32_t n, uint32_t k, uint32_t m,
                  int acc)
{
    aenl_la_gemm_loop(c, ldc, a, ai, ar, b, br, bj, n, k, m, acc);
}
#endif

void aenl_la_symmetrise(aenl_real_t *a, uint32_t lda, uint32_t n)
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

aenl_status_t aenl_la_chol(aenl_real_t *a, uint32_t lda, uint32_t n)
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

#if !AENL_LA_INLINE
void aenl_la_solve_tri(const aenl_real_t *t, size_t ti, size_t tj, uint32_t n, aenl_real_t *b,
                       size_t ldb, uint32_t m, int upper)
{
    aenl_la_solve_tri_loop(t, ti, tj, n, b, ldb, m, upper);
}
#endif

void aenl_la_chol_solve(const aenl_real_t *l, uint32_t ldl, uint32_t n, aenl_real_t *b,
                        uint32_t ldb, uint32_t m)
{
    aenl_la_solve_lower(l, ldl, n, b, ldb, m);
    aenl_la_solve_lower_t(l, ldl, n, b, ldb, m);
}

int aenl_la_all_finite(const aenl_real_t *a, uint32_t lda, uint32_t n, uint32_t m)
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

int aenl_la_is_symmetric(const aenl_real_t *a, uint32_t lda, uint32_t n, aenl_real_t rel_tol)
{
    for (uint32_t i = 0; i < n; ++i)
    {
        for (uint32_t j = 0; j < i; ++j)
        {
            const aenl_real_t u = a[(size_t)i * lda + j];
            const aenl_real_t v = a[(size_t)j * lda + i];
            if (aenl_fabs(u - v) > rel_tol * (aenl_fabs(u) + aenl_fabs(v)))
            {
                return 0;
            }
        }
    }
    return 1;
}
