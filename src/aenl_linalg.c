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

void aenl_la_solve_tri(const aenl_real_t *t, size_t ti, size_t tj, uint32_t n, aenl_real_t *b,
                       size_t ldb, uint32_t m, int upper)
{
    aenl_la_solve_tri_loop(t, ti, tj, n, b, ldb, m, upper);
}

void aenl_la_symmetrise(aenl_real_t *a, uint32_t lda, uint32_t n)
{
    aenl_la_symmetrise_loop(a, lda, n);
}

aenl_status_t aenl_la_chol(aenl_real_t *a, uint32_t lda, uint32_t n)
{
    return aenl_la_chol_loop(a, lda, n);
}

void aenl_la_chol_solve(const aenl_real_t *l, uint32_t ldl, uint32_t n, aenl_real_t *b,
                        uint32_t ldb, uint32_t m)
{
    aenl_la_chol_solve_loop(l, ldl, n, b, ldb, m);
}

int aenl_la_all_finite(const aenl_real_t *a, uint32_t lda, uint32_t n, uint32_t m)
{
    return aenl_la_all_finite_loop(a, lda, n, m);
}
#endif

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
