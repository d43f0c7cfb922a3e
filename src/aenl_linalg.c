/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_linalg.c
 * @brief Private small-matrix kernels (see aenl_linalg.h). Plain loops: the sizes are at most
 *        AENL_SKF_MAX_X, where blocking or vectorised libraries gain nothing on a Cortex-M.
 */
#include "aenl_linalg.h"

void aenl_la_mul(aenl_real_t *c, uint16_t ldc, const aenl_real_t *a, uint16_t lda,
                 const aenl_real_t *b, uint16_t ldb, uint16_t n, uint16_t k, uint16_t m)
{
    for (uint16_t i = 0; i < n; ++i)
    {
        for (uint16_t j = 0; j < m; ++j)
        {
            aenl_real_t s = AENL_R(0.0);
            for (uint16_t r = 0; r < k; ++r)
            {
                s += a[(size_t)i * lda + r] * b[(size_t)r * ldb + j];
            }
            c[(size_t)i * ldc + j] = s;
        }
    }
}

void aenl_la_mul_nt(aenl_real_t *c, uint16_t ldc, const aenl_real_t *a, uint16_t lda,
                    const aenl_real_t *b, uint16_t ldb, uint16_t n, uint16_t k, uint16_t m)
{
    for (uint16_t i = 0; i < n; ++i)
    {
        for (uint16_t j = 0; j < m; ++j)
        {
            aenl_real_t s = AENL_R(0.0);
            for (uint16_t r = 0; r < k; ++r)
            {
                s += a[(size_t)i * lda + r] * b[(size_t)j * ldb + r];
            }
            c[(size_t)i * ldc + j] = s;
        }
    }
}

void aenl_la_mul_tn(aenl_real_t *c, uint16_t ldc, const aenl_real_t *a, uint16_t lda,
                    const aenl_real_t *b, uint16_t ldb, uint16_t n, uint16_t k, uint16_t m)
{
    for (uint16_t i = 0; i < n; ++i)
    {
        for (uint16_t j = 0; j < m; ++j)
        {
            aenl_real_t s = AENL_R(0.0);
            for (uint16_t r = 0; r < k; ++r)
            {
                s += a[(size_t)r * lda + i] * b[(size_t)r * ldb + j];
            }
            c[(size_t)i * ldc + j] = s;
        }
    }
}

void aenl_la_mv(aenl_real_t *y, const aenl_real_t *a, uint16_t lda, const aenl_real_t *x,
                uint16_t n, uint16_t m)
{
    for (uint16_t i = 0; i < n; ++i)
    {
        aenl_real_t s = AENL_R(0.0);
        for (uint16_t j = 0; j < m; ++j)
        {
            s += a[(size_t)i * lda + j] * x[j];
        }
        y[i] = s;
    }
}

void aenl_la_symmetrise(aenl_real_t *a, uint16_t lda, uint16_t n)
{
    for (uint16_t i = 0; i < n; ++i)
    {
        for (uint16_t j = 0; j < i; ++j)
        {
            const aenl_real_t v = AENL_R(0.5) * (a[(size_t)i * lda + j] + a[(size_t)j * lda + i]);
            a[(size_t)i * lda + j] = v;
            a[(size_t)j * lda + i] = v;
        }
    }
}

aenl_status_t aenl_la_chol(aenl_real_t *a, uint16_t lda, uint16_t n)
{
    for (uint16_t j = 0; j < n; ++j)
    {
        aenl_real_t d = a[(size_t)j * lda + j];
        for (uint16_t r = 0; r < j; ++r)
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
        for (uint16_t i = (uint16_t)(j + 1u); i < n; ++i)
        {
            aenl_real_t s = a[(size_t)i * lda + j];
            for (uint16_t r = 0; r < j; ++r)
            {
                s -= a[(size_t)i * lda + r] * a[(size_t)j * lda + r];
            }
            a[(size_t)i * lda + j] = s * inv;
        }
        for (uint16_t i = 0; i < j; ++i)
        {
            a[(size_t)i * lda + j] = AENL_R(0.0);
        }
    }
    return AENL_OK;
}

void aenl_la_solve_lower(const aenl_real_t *l, uint16_t ldl, uint16_t n, aenl_real_t *b,
                         uint16_t ldb, uint16_t m)
{
    for (uint16_t c = 0; c < m; ++c)
    {
        for (uint16_t i = 0; i < n; ++i)
        {
            aenl_real_t s = b[(size_t)i * ldb + c];
            for (uint16_t r = 0; r < i; ++r)
            {
                s -= l[(size_t)i * ldl + r] * b[(size_t)r * ldb + c];
            }
            b[(size_t)i * ldb + c] = s / l[(size_t)i * ldl + i];
        }
    }
}

void aenl_la_solve_lower_t(const aenl_real_t *l, uint16_t ldl, uint16_t n, aenl_real_t *b,
                           uint16_t ldb, uint16_t m)
{
    for (uint16_t c = 0; c < m; ++c)
    {
        for (uint16_t ii = n; ii > 0u; --ii)
        {
            const uint16_t i = (uint16_t)(ii - 1u);
            aenl_real_t s = b[(size_t)i * ldb + c];
            for (uint16_t r = (uint16_t)(i + 1u); r < n; ++r)
            {
                s -= l[(size_t)r * ldl + i] * b[(size_t)r * ldb + c];
            }
            b[(size_t)i * ldb + c] = s / l[(size_t)i * ldl + i];
        }
    }
}

void aenl_la_chol_solve(const aenl_real_t *l, uint16_t ldl, uint16_t n, aenl_real_t *b,
                        uint16_t ldb, uint16_t m)
{
    aenl_la_solve_lower(l, ldl, n, b, ldb, m);
    aenl_la_solve_lower_t(l, ldl, n, b, ldb, m);
}

int aenl_la_all_finite(const aenl_real_t *a, uint16_t lda, uint16_t n, uint16_t m)
{
    for (uint16_t i = 0; i < n; ++i)
    {
        for (uint16_t j = 0; j < m; ++j)
        {
            if (!aenl_is_finite(a[(size_t)i * lda + j]))
            {
                return 0;
            }
        }
    }
    return 1;
}

int aenl_la_is_symmetric(const aenl_real_t *a, uint16_t lda, uint16_t n, aenl_real_t rel_tol)
{
    for (uint16_t i = 0; i < n; ++i)
    {
        for (uint16_t j = 0; j < i; ++j)
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
