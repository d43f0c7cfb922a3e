/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_em.c
 * @brief EM identification of a threshold-switching linear state-space model (see aenl_em.h).
 *
 * E-step: Kalman filter (standard form, symmetrised; double) and Rauch-Tung-Striebel smoother
 * with the lag-one covariance Cov(x_{k+1}, x_k | y) = P_{k+1|n} J_k' (Shumway & Stoffer 1982,
 * de Jong 1989), accumulating per mode the sufficient statistics of the transitions
 * S11 = sum E[x_{k+1} x_{k+1}'], S10 = sum E[x_{k+1} x_k'], S00 = sum E[x_k x_k'], s1, s0, count.
 * M-step with W = [A b], z = (x_k, 1): W = H G^-1 with G = E[z z'], H = E[x_{k+1} z'] (dposv),
 * Q = (S11 - W H' - H W' + W G W') / count, which is exact for any (possibly frozen) W;
 * C = Syx Sxx^-1, R = (Syy - C Syx' - Syx C' + C Sxx C') / n_obs; x0 = x_{0|n} (P0 fixed).
 */
#define _POSIX_C_SOURCE 200809L

#include "aenl_tools/aenl_em.h"

#include <lapacke.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LOG_2PI 1.8378770664093453

/* ---- small dense helpers (row-major, contiguous) --------------------------------------------- */

static void mm(double *c, const double *a, const double *b, size_t n, size_t k, size_t m)
{
    for (size_t i = 0; i < n; ++i)
    {
        double *ci = c + i * m;
        for (size_t j = 0; j < m; ++j)
        {
            ci[j] = 0.0;
        }
        for (size_t r = 0; r < k; ++r)
        {
            const double air = a[i * k + r];
            const double *br = b + r * m;
            for (size_t j = 0; j < m; ++j)
            {
                ci[j] += air * br[j];
            }
        }
    }
}

/* C (n x m) = A (n x k) B' with B (m x k) */
static void mmt(double *c, const double *a, const double *b, size_t n, size_t k, size_t m)
{
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < m; ++j)
        {
            double s = 0.0;
            for (size_t r = 0; r < k; ++r)
            {
                s += a[i * k + r] * b[j * k + r];
            }
            c[i * m + j] = s;
        }
    }
}

static void symm(double *a, size_t n)
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

/* In-place lower Cholesky; 0 on success. */
static int chol(double *a, size_t n)
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
        const double l = sqrt(d);
        a[j * n + j] = l;
        for (size_t i = j + 1; i < n; ++i)
        {
            double s = a[i * n + j];
            for (size_t r = 0; r < j; ++r)
            {
                s -= a[i * n + r] * a[j * n + r];
            }
            a[i * n + j] = s / l;
        }
    }
    return 0;
}

/* Solve (L L') X = B, B n x m in place. */
static void chol_solve(const double *l, size_t n, double *b, size_t m)
{
    for (size_t c = 0; c < m; ++c)
    {
        for (size_t i = 0; i < n; ++i)
        {
            double s = b[i * m + c];
            for (size_t r = 0; r < i; ++r)
            {
                s -= l[i * n + r] * b[r * m + c];
            }
            b[i * m + c] = s / l[i * n + i];
        }
        for (size_t ii = n; ii > 0; --ii)
        {
            const size_t i = ii - 1;
            double s = b[i * m + c];
            for (size_t r = i + 1; r < n; ++r)
            {
                s -= l[r * n + i] * b[r * m + c];
            }
            b[i * m + c] = s / l[i * n + i];
        }
    }
}

/* Factor a copy of a symmetric matrix, adding a growing diagonal jitter if needed. */
static int chol_jitter(double *l, const double *a, size_t n)
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
        if (chol(l, n) == 0)
        {
            return 0;
        }
        jit = (attempt == 0) ? 1e-14 * (tr / (double)n + 1e-300) : jit * 100.0;
    }
    return -1;
}

/* ---- model ------------------------------------------------------------------------------------
 */

void aenl_em_opts_default(aenl_em_opts_t *o)
{
    memset(o, 0, sizeof(*o));
    o->max_iter = 50;
    o->freeze = AENL_EM_FREEZE_C;
    o->refine_iter = 5;
    o->dt = 1.0;
}

aenl_status_t aenl_em_model_alloc(aenl_em_model_t *m, size_t n_x, size_t n_z, size_t n_modes,
                                  aenl_err_t *err)
{
    memset(m, 0, sizeof(*m));
    if (n_x == 0 || n_z == 0 || n_modes == 0 || n_x > AENL_EM_MAX_X || n_modes > AENL_EM_MAX_MODES)
    {
        aenl_err_set(err, "model sizes out of range (states %zu, outputs %zu, modes %zu)", n_x, n_z,
                     n_modes);
        return AENL_E_ARG;
    }
    m->n_x = n_x;
    m->n_z = n_z;
    m->n_modes = n_modes;
    m->dt = 1.0;
    m->A = calloc(n_modes * n_x * n_x, sizeof(double));
    m->b = calloc(n_modes * n_x, sizeof(double));
    m->Q = calloc(n_modes * n_x * n_x, sizeof(double));
    m->C = calloc(n_z * n_x, sizeof(double));
    m->R = calloc(n_z * n_z, sizeof(double));
    m->x0 = calloc(n_x, sizeof(double));
    m->P0 = calloc(n_x * n_x, sizeof(double));
    if (!m->A || !m->b || !m->Q || !m->C || !m->R || !m->x0 || !m->P0)
    {
        aenl_em_model_free(m);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    return AENL_OK;
}

void aenl_em_model_free(aenl_em_model_t *m)
{
    if (m == NULL)
    {
        return;
    }
    free(m->A);
    free(m->b);
    free(m->Q);
    free(m->C);
    free(m->R);
    free(m->x0);
    free(m->P0);
    memset(m, 0, sizeof(*m));
}

aenl_status_t aenl_em_model_copy(aenl_em_model_t *dst, const aenl_em_model_t *src, aenl_err_t *err)
{
    const aenl_status_t st = aenl_em_model_alloc(dst, src->n_x, src->n_z, src->n_modes, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const size_t nx = src->n_x, nz = src->n_z, nm = src->n_modes;
    dst->switch_channel = src->switch_channel;
    memcpy(dst->thresholds, src->thresholds, sizeof(dst->thresholds));
    dst->dt = src->dt;
    memcpy(dst->A, src->A, nm * nx * nx * sizeof(double));
    memcpy(dst->b, src->b, nm * nx * sizeof(double));
    memcpy(dst->Q, src->Q, nm * nx * nx * sizeof(double));
    memcpy(dst->C, src->C, nz * nx * sizeof(double));
    memcpy(dst->R, src->R, nz * nz * sizeof(double));
    memcpy(dst->x0, src->x0, nx * sizeof(double));
    memcpy(dst->P0, src->P0, nx * nx * sizeof(double));
    return AENL_OK;
}

static void model_assign(aenl_em_model_t *dst, const aenl_em_model_t *src)
{
    const size_t nx = src->n_x, nz = src->n_z, nm = src->n_modes;
    memcpy(dst->thresholds, src->thresholds, sizeof(dst->thresholds));
    memcpy(dst->A, src->A, nm * nx * nx * sizeof(double));
    memcpy(dst->b, src->b, nm * nx * sizeof(double));
    memcpy(dst->Q, src->Q, nm * nx * nx * sizeof(double));
    memcpy(dst->C, src->C, nz * nx * sizeof(double));
    memcpy(dst->R, src->R, nz * nz * sizeof(double));
    memcpy(dst->x0, src->x0, nx * sizeof(double));
    memcpy(dst->P0, src->P0, nx * nx * sizeof(double));
}

static size_t mode_of(const double *thr, size_t n_modes, double u)
{
    size_t s = 0;
    for (size_t i = 0; i + 1 < n_modes; ++i)
    {
        if (u >= thr[i])
        {
            s = i + 1;
        }
    }
    return s;
}

/* ---- workspace --------------------------------------------------------------------------------
 */

typedef struct
{
    size_t n, nx, nz, nm;
    const double *y;
    unsigned char *obs;        /* y_k fully observed */
    unsigned char *mode;       /* mode[k]: transition k-1 -> k (mode[0] unused) */
    double *xp, *Pp, *xf, *Pf; /* xf/Pf become the smoothed moments in the backward pass */
    double *tmp;               /* scratch: 6 nx*nx + 4 nx + 2 nz*nz + 2 nx*nz */
    /* statistics */
    double *S11, *S10, *S00, *s1, *s0, cnt[AENL_EM_MAX_MODES];
    double *Syx, *Sxx, *Syy, ny;
} ws_t;

static void ws_free(ws_t *w)
{
    free(w->obs);
    free(w->mode);
    free(w->xp);
    free(w->Pp);
    free(w->xf);
    free(w->Pf);
    free(w->tmp);
    free(w->S11);
    free(w->S10);
    free(w->S00);
    free(w->s1);
    free(w->s0);
    free(w->Syx);
    free(w->Sxx);
    free(w->Syy);
    memset(w, 0, sizeof(*w));
}

static aenl_status_t ws_alloc(ws_t *w, const double *y, size_t n, size_t nx, size_t nz, size_t nm,
                              aenl_err_t *err)
{
    memset(w, 0, sizeof(*w));
    w->n = n;
    w->nx = nx;
    w->nz = nz;
    w->nm = nm;
    w->y = y;
    w->obs = calloc(n, 1);
    w->mode = calloc(n, 1);
    w->xp = malloc(n * nx * sizeof(double));
    w->Pp = malloc(n * nx * nx * sizeof(double));
    w->xf = malloc(n * nx * sizeof(double));
    w->Pf = malloc(n * nx * nx * sizeof(double));
    w->tmp = malloc((6 * nx * nx + 4 * nx + 2 * nz * nz + 2 * nx * nz + 16) * sizeof(double));
    w->S11 = calloc(nm * nx * nx, sizeof(double));
    w->S10 = calloc(nm * nx * nx, sizeof(double));
    w->S00 = calloc(nm * nx * nx, sizeof(double));
    w->s1 = calloc(nm * nx, sizeof(double));
    w->s0 = calloc(nm * nx, sizeof(double));
    w->Syx = calloc(nz * nx, sizeof(double));
    w->Sxx = calloc(nx * nx, sizeof(double));
    w->Syy = calloc(nz * nz, sizeof(double));
    if (!w->obs || !w->mode || !w->xp || !w->Pp || !w->xf || !w->Pf || !w->tmp || !w->S11 ||
        !w->S10 || !w->S00 || !w->s1 || !w->s0 || !w->Syx || !w->Sxx || !w->Syy)
    {
        ws_free(w);
        aenl_err_set(err, "out of memory (%zu samples, %zu states)", n, nx);
        return AENL_E_DIM;
    }
    for (size_t k = 0; k < n; ++k)
    {
        int ok = 1;
        for (size_t r = 0; r < nz; ++r)
        {
            ok &= isfinite(y[k * nz + r]) ? 1 : 0;
        }
        w->obs[k] = (unsigned char)ok;
    }
    return AENL_OK;
}

static void set_modes(ws_t *w, const double *thr, const double *u, size_t stride)
{
    w->mode[0] = 0;
    for (size_t k = 1; k < w->n; ++k)
    {
        const double v = u[(k - 1) * stride];
        w->mode[k] = (unsigned char)(isfinite(v) ? mode_of(thr, w->nm, v) : w->mode[k - 1]);
    }
}

/* ---- E-step -----------------------------------------------------------------------------------
 */

/* Forward Kalman filter: fills xp, Pp, xf, Pf; returns the log-likelihood in *ll. */
static aenl_status_t kf_forward(ws_t *w, const aenl_em_model_t *m, double *ll)
{
    const size_t nx = w->nx, nz = w->nz, nn = nx * nx;
    double *T = w->tmp, *PCt = T + nn, *S = PCt + nx * nz, *e = S + nz * nz, *u = e + nz;
    double total = 0.0;
    for (size_t k = 0; k < w->n; ++k)
    {
        double *xp = w->xp + k * nx, *Pp = w->Pp + k * nn;
        double *xf = w->xf + k * nx, *Pf = w->Pf + k * nn;
        if (k == 0)
        {
            memcpy(xp, m->x0, nx * sizeof(double));
            memcpy(Pp, m->P0, nn * sizeof(double));
        }
        else
        {
            const size_t s = w->mode[k];
            const double *A = m->A + s * nn, *b = m->b + s * nx, *Q = m->Q + s * nn;
            const double *xo = w->xf + (k - 1) * nx, *Po = w->Pf + (k - 1) * nn;
            for (size_t i = 0; i < nx; ++i)
            {
                double acc = b[i];
                for (size_t j = 0; j < nx; ++j)
                {
                    acc += A[i * nx + j] * xo[j];
                }
                xp[i] = acc;
            }
            mm(T, A, Po, nx, nx, nx);
            mmt(Pp, T, A, nx, nx, nx);
            for (size_t i = 0; i < nn; ++i)
            {
                Pp[i] += Q[i];
            }
            symm(Pp, nx);
        }
        if (!w->obs[k])
        {
            memcpy(xf, xp, nx * sizeof(double));
            memcpy(Pf, Pp, nn * sizeof(double));
            continue;
        }
        const double *yk = w->y + k * nz;
        mmt(PCt, Pp, m->C, nx, nx, nz); /* P C' (nx x nz) */
        for (size_t r = 0; r < nz; ++r)
        {
            double acc = yk[r];
            for (size_t j = 0; j < nx; ++j)
            {
                acc -= m->C[r * nx + j] * xp[j];
            }
            e[r] = acc;
            for (size_t c = 0; c < nz; ++c)
            {
                double sc = m->R[r * nz + c];
                for (size_t j = 0; j < nx; ++j)
                {
                    sc += m->C[r * nx + j] * PCt[j * nz + c];
                }
                S[r * nz + c] = sc;
            }
        }
        symm(S, nz);
        if (chol(S, nz) != 0)
        {
            return AENL_E_NOT_PD;
        }
        memcpy(u, e, nz * sizeof(double));
        double logdet = 0.0, q = 0.0;
        for (size_t i = 0; i < nz; ++i) /* forward solve for the quadratic form */
        {
            double acc = u[i];
            for (size_t r = 0; r < i; ++r)
            {
                acc -= S[i * nz + r] * u[r];
            }
            u[i] = acc / S[i * nz + i];
            q += u[i] * u[i];
            logdet += 2.0 * log(S[i * nz + i]);
        }
        total += -0.5 * (q + logdet + (double)nz * LOG_2PI);
        memcpy(u, e, nz * sizeof(double));
        chol_solve(S, nz, u, 1); /* S^-1 e */
        for (size_t i = 0; i < nx; ++i)
        {
            double acc = xp[i];
            for (size_t r = 0; r < nz; ++r)
            {
                acc += PCt[i * nz + r] * u[r];
            }
            xf[i] = acc;
        }
        /* K' = S^-1 C P  (nz x nx) in T; Pf = Pp - P C' K' */
        for (size_t r = 0; r < nz; ++r)
        {
            for (size_t j = 0; j < nx; ++j)
            {
                T[r * nx + j] = PCt[j * nz + r];
            }
        }
        chol_solve(S, nz, T, nx);
        for (size_t i = 0; i < nx; ++i)
        {
            for (size_t j = 0; j < nx; ++j)
            {
                double acc = Pp[i * nx + j];
                for (size_t r = 0; r < nz; ++r)
                {
                    acc -= PCt[i * nz + r] * T[r * nx + j];
                }
                Pf[i * nx + j] = acc;
            }
        }
        symm(Pf, nx);
    }
    if (!isfinite(total))
    {
        return AENL_E_NUMERIC;
    }
    *ll = total;
    return AENL_OK;
}

static void add_outer(double *S, const double *a, const double *b, size_t n)
{
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < n; ++j)
        {
            S[i * n + j] += a[i] * b[j];
        }
    }
}

static void add_obs_stats(ws_t *w, size_t k, const double *xs, const double *Ps)
{
    const size_t nx = w->nx, nz = w->nz;
    if (!w->obs[k])
    {
        return;
    }
    const double *yk = w->y + k * nz;
    for (size_t r = 0; r < nz; ++r)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            w->Syx[r * nx + j] += yk[r] * xs[j];
        }
        for (size_t c = 0; c < nz; ++c)
        {
            w->Syy[r * nz + c] += yk[r] * yk[c];
        }
    }
    for (size_t i = 0; i < nx * nx; ++i)
    {
        w->Sxx[i] += Ps[i];
    }
    add_outer(w->Sxx, xs, xs, nx);
    w->ny += 1.0;
}

/* RTS smoother in place over xf/Pf, accumulating the sufficient statistics. */
static aenl_status_t rts_backward(ws_t *w, const aenl_em_model_t *m)
{
    const size_t nx = w->nx, nn = nx * nx, nm = w->nm, nz = w->nz;
    memset(w->S11, 0, nm * nn * sizeof(double));
    memset(w->S10, 0, nm * nn * sizeof(double));
    memset(w->S00, 0, nm * nn * sizeof(double));
    memset(w->s1, 0, nm * nx * sizeof(double));
    memset(w->s0, 0, nm * nx * sizeof(double));
    memset(w->cnt, 0, sizeof(w->cnt));
    memset(w->Syx, 0, nz * nx * sizeof(double));
    memset(w->Sxx, 0, nn * sizeof(double));
    memset(w->Syy, 0, nz * nz * sizeof(double));
    w->ny = 0.0;
    double *L = w->tmp, *M = L + nn, *J = M + nn, *D = J + nn, *T = D + nn, *Pc = T + nn;
    double *dx = Pc + nn;
    const size_t n = w->n;
    add_obs_stats(w, n - 1, w->xf + (n - 1) * nx, w->Pf + (n - 1) * nn);
    for (size_t kk = n - 1; kk > 0; --kk)
    {
        const size_t k = kk - 1; /* smooth k from k+1 */
        const size_t s = w->mode[k + 1];
        const double *A = m->A + s * nn;
        double *xf = w->xf + k * nx, *Pf = w->Pf + k * nn;
        const double *xs1 = w->xf + (k + 1) * nx, *Ps1 = w->Pf + (k + 1) * nn;
        const double *xp1 = w->xp + (k + 1) * nx, *Pp1 = w->Pp + (k + 1) * nn;
        /* J = Pf A' Pp1^-1  <=>  Pp1 J' = A Pf */
        if (chol_jitter(L, Pp1, nx) != 0)
        {
            return AENL_E_NOT_PD;
        }
        mm(M, A, Pf, nx, nx, nx);
        chol_solve(L, nx, M, nx); /* M = J' */
        for (size_t i = 0; i < nx; ++i)
        {
            for (size_t j = 0; j < nx; ++j)
            {
                J[i * nx + j] = M[j * nx + i];
            }
        }
        for (size_t i = 0; i < nx; ++i)
        {
            dx[i] = xs1[i] - xp1[i];
        }
        for (size_t i = 0; i < nn; ++i)
        {
            D[i] = Ps1[i] - Pp1[i];
        }
        for (size_t i = 0; i < nx; ++i)
        {
            double acc = 0.0;
            for (size_t j = 0; j < nx; ++j)
            {
                acc += J[i * nx + j] * dx[j];
            }
            xf[i] += acc;
        }
        mm(T, J, D, nx, nx, nx);
        mmt(D, T, J, nx, nx, nx);
        for (size_t i = 0; i < nn; ++i)
        {
            Pf[i] += D[i];
        }
        symm(Pf, nx);
        /* lag-one covariance Cov(x_{k+1}, x_k) = Ps1 J' */
        mmt(Pc, Ps1, J, nx, nx, nx);
        double *S11 = w->S11 + s * nn, *S10 = w->S10 + s * nn, *S00 = w->S00 + s * nn;
        for (size_t i = 0; i < nn; ++i)
        {
            S11[i] += Ps1[i];
            S10[i] += Pc[i];
            S00[i] += Pf[i];
        }
        add_outer(S11, xs1, xs1, nx);
        add_outer(S10, xs1, xf, nx);
        add_outer(S00, xf, xf, nx);
        for (size_t i = 0; i < nx; ++i)
        {
            w->s1[s * nx + i] += xs1[i];
            w->s0[s * nx + i] += xf[i];
        }
        w->cnt[s] += 1.0;
        add_obs_stats(w, k, xf, Pf);
    }
    return AENL_OK;
}

static aenl_status_t e_step(ws_t *w, const aenl_em_model_t *m, double *ll, int smooth)
{
    aenl_status_t st = kf_forward(w, m, ll);
    if (st == AENL_OK && smooth)
    {
        st = rts_backward(w, m);
    }
    return st;
}

/* ---- M-step -----------------------------------------------------------------------------------
 */

/* Solve G X = B (G n x n SPD, B n x m, row-major) with LAPACKE dposv; G, B overwritten. */
static int posv(double *G, double *B, size_t n, size_t m)
{
    return LAPACKE_dposv(LAPACK_ROW_MAJOR, 'L', (lapack_int)n, (lapack_int)m, G, (lapack_int)n, B,
                         (lapack_int)m);
}

static aenl_status_t m_step(ws_t *w, aenl_em_model_t *m, unsigned freeze)
{
    const size_t nx = w->nx, nz = w->nz, nn = nx * nx, na = nx + 1;
    double *G = malloc(na * na * sizeof(double)), *H = malloc(nx * na * sizeof(double));
    double *Gc = malloc(na * na * sizeof(double)), *X = malloc(na * nx * sizeof(double));
    double *W = malloc(nx * na * sizeof(double)), *T = malloc(nx * na * sizeof(double));
    aenl_status_t st = AENL_OK;
    if (!G || !H || !Gc || !X || !W || !T)
    {
        st = AENL_E_DIM;
        goto done;
    }
    for (size_t s = 0; s < w->nm; ++s)
    {
        const double c = w->cnt[s];
        if (c < (double)(nx + 2))
        {
            continue; /* too few transitions: keep this mode's parameters */
        }
        const double *S00 = w->S00 + s * nn, *S10 = w->S10 + s * nn, *S11 = w->S11 + s * nn;
        const double *s0 = w->s0 + s * nx, *s1 = w->s1 + s * nx;
        for (size_t i = 0; i < nx; ++i)
        {
            for (size_t j = 0; j < nx; ++j)
            {
                G[i * na + j] = S00[i * nx + j];
                H[i * na + j] = S10[i * nx + j];
            }
            G[i * na + nx] = s0[i];
            G[nx * na + i] = s0[i];
            H[i * na + nx] = s1[i];
        }
        G[nx * na + nx] = c;
        double *A = m->A + s * nn, *b = m->b + s * nx, *Q = m->Q + s * nn;
        const int fa = (freeze & AENL_EM_FREEZE_A) != 0, fb = (freeze & AENL_EM_FREEZE_B) != 0;
        if (!fa && !fb)
        {
            memcpy(Gc, G, na * na * sizeof(double));
            for (size_t i = 0; i < na; ++i) /* X = H' */
            {
                for (size_t j = 0; j < nx; ++j)
                {
                    X[i * nx + j] = H[j * na + i];
                }
            }
            if (posv(Gc, X, na, nx) != 0)
            {
                st = AENL_E_NOT_PD;
                goto done;
            }
            for (size_t i = 0; i < nx; ++i)
            {
                for (size_t j = 0; j < nx; ++j)
                {
                    A[i * nx + j] = X[j * nx + i];
                }
                b[i] = X[nx * nx + i];
            }
        }
        else if (fa && !fb)
        {
            for (size_t i = 0; i < nx; ++i)
            {
                double acc = s1[i];
                for (size_t j = 0; j < nx; ++j)
                {
                    acc -= A[i * nx + j] * s0[j];
                }
                b[i] = acc / c;
            }
        }
        else if (!fa && fb)
        {
            /* S00 A' = (S10 - b s0')' */
            for (size_t i = 0; i < nx; ++i)
            {
                for (size_t j = 0; j < nx; ++j)
                {
                    Gc[i * nx + j] = S00[i * nx + j];
                    X[i * nx + j] = S10[j * nx + i] - b[j] * s0[i];
                }
            }
            if (posv(Gc, X, nx, nx) != 0)
            {
                st = AENL_E_NOT_PD;
                goto done;
            }
            for (size_t i = 0; i < nx; ++i)
            {
                for (size_t j = 0; j < nx; ++j)
                {
                    A[i * nx + j] = X[j * nx + i];
                }
            }
        }
        if (!(freeze & AENL_EM_FREEZE_Q))
        {
            /* Q = (S11 - W H' - H W' + W G W') / c with W = [A b] */
            for (size_t i = 0; i < nx; ++i)
            {
                for (size_t j = 0; j < nx; ++j)
                {
                    W[i * na + j] = A[i * nx + j];
                }
                W[i * na + nx] = b[i];
            }
            mm(T, W, G, nx, na, na); /* W G */
            for (size_t i = 0; i < nx; ++i)
            {
                for (size_t j = 0; j < nx; ++j)
                {
                    double wh = 0.0, hw = 0.0, wgw = 0.0;
                    for (size_t r = 0; r < na; ++r)
                    {
                        wh += W[i * na + r] * H[j * na + r];
                        hw += H[i * na + r] * W[j * na + r];
                        wgw += T[i * na + r] * W[j * na + r];
                    }
                    Q[i * nx + j] = (S11[i * nx + j] - wh - hw + wgw) / c;
                }
            }
            symm(Q, nx);
            for (size_t i = 0; i < nx; ++i)
            {
                if (Q[i * nx + i] < 0.0)
                {
                    Q[i * nx + i] = 0.0;
                }
            }
        }
    }
    if (w->ny > 0.0)
    {
        if (!(freeze & AENL_EM_FREEZE_C))
        {
            /* C = Syx Sxx^-1  <=>  Sxx C' = Syx' */
            double *Sc = malloc(nn * sizeof(double)), *Ct = malloc(nx * nz * sizeof(double));
            if (!Sc || !Ct)
            {
                free(Sc);
                free(Ct);
                st = AENL_E_DIM;
                goto done;
            }
            memcpy(Sc, w->Sxx, nn * sizeof(double));
            for (size_t i = 0; i < nx; ++i)
            {
                for (size_t r = 0; r < nz; ++r)
                {
                    Ct[i * nz + r] = w->Syx[r * nx + i];
                }
            }
            const int info = posv(Sc, Ct, nx, nz);
            if (info == 0)
            {
                for (size_t r = 0; r < nz; ++r)
                {
                    for (size_t i = 0; i < nx; ++i)
                    {
                        m->C[r * nx + i] = Ct[i * nz + r];
                    }
                }
            }
            free(Sc);
            free(Ct);
            if (info != 0)
            {
                st = AENL_E_NOT_PD;
                goto done;
            }
        }
        if (!(freeze & AENL_EM_FREEZE_R))
        {
            for (size_t r = 0; r < nz; ++r)
            {
                for (size_t c2 = 0; c2 < nz; ++c2)
                {
                    double v = w->Syy[r * nz + c2];
                    for (size_t i = 0; i < nx; ++i)
                    {
                        v -= m->C[r * nx + i] * w->Syx[c2 * nx + i] +
                             w->Syx[r * nx + i] * m->C[c2 * nx + i];
                        double cs = 0.0;
                        for (size_t j = 0; j < nx; ++j)
                        {
                            cs += w->Sxx[i * nx + j] * m->C[c2 * nx + j];
                        }
                        v += m->C[r * nx + i] * cs;
                    }
                    m->R[r * nz + c2] = v / w->ny;
                }
            }
            symm(m->R, nz);
        }
    }
    if (!(freeze & AENL_EM_FREEZE_X0))
    {
        memcpy(m->x0, w->xf, nx * sizeof(double)); /* x_{0|n} */
    }
done:
    free(G);
    free(H);
    free(Gc);
    free(X);
    free(W);
    free(T);
    return st;
}

/* ---- least-squares initialisation -------------------------------------------------------------
 */

static double y_at(const double *y, size_t nz, long k, size_t r)
{
    return y[(size_t)(k < 0 ? 0 : k) * nz + r];
}

static aenl_status_t ls_init(const double *y, size_t n, size_t nz, const ws_t *w,
                             aenl_em_model_t *m, int use_iv, aenl_err_t *err)
{
    const size_t nx = m->n_x, na = nx + 1, nm = m->n_modes, nn = nx * nx;
    const size_t p = (nx + nz - 1) / nz; /* embedding depth */
    double zeta[AENL_EM_MAX_X + 1];
    double *G = calloc(na * na, sizeof(double)), *H = calloc(na * nz, sizeof(double));
    double *z = calloc(na, sizeof(double)), *res = calloc(nz * nz, sizeof(double));
    double *pooled = calloc(nz, sizeof(double));
    aenl_status_t st = AENL_OK;
    if (!G || !H || !z || !res || !pooled)
    {
        aenl_err_set(err, "out of memory");
        st = AENL_E_DIM;
        goto done;
    }
    /* C = [I 0]; shift rows of every A */
    memset(m->C, 0, nz * nx * sizeof(double));
    for (size_t r = 0; r < nz; ++r)
    {
        m->C[r * nx + r] = 1.0;
    }
    double pooled_n = 0.0;
    for (size_t s = 0; s < nm; ++s)
    {
        memset(G, 0, na * na * sizeof(double));
        memset(H, 0, na * nz * sizeof(double));
        double cnt = 0.0;
        for (size_t k = 1; k + 1 < n; ++k)
        {
            if (w->mode[k + 1] != s)
            {
                continue;
            }
            int ok = 1;
            for (size_t i = 0; i < nx && ok; ++i)
            {
                z[i] = y_at(y, nz, (long)k - (long)(i / nz), i % nz);
                ok = isfinite(z[i]);
            }
            for (size_t r = 0; r < nz && ok; ++r)
            {
                ok = isfinite(y[(k + 1) * nz + r]);
            }
            if (!ok)
            {
                continue;
            }
            z[nx] = 1.0;
            /* instruments: the same embedding p samples earlier (independent of the noise in
             * the regressors and in y_{k+1}); plain least squares when use_iv is 0 */
            for (size_t i = 0; i < nx && ok; ++i)
            {
                zeta[i] = use_iv ? y_at(y, nz, (long)k - (long)p - (long)(i / nz), i % nz) : z[i];
                ok = isfinite(zeta[i]);
            }
            if (!ok)
            {
                continue;
            }
            zeta[nx] = 1.0;
            add_outer(G, zeta, z, na);
            for (size_t i = 0; i < na; ++i)
            {
                for (size_t r = 0; r < nz; ++r)
                {
                    H[i * nz + r] += zeta[i] * y[(k + 1) * nz + r];
                }
            }
            cnt += 1.0;
        }
        if (cnt < (double)(2 * na))
        {
            aenl_err_set(err,
                         "mode %zu (threshold interval %zu) has %.0f usable transitions; at least "
                         "%zu are needed for %zu states (move the thresholds or use fewer states)",
                         s, s, cnt, 2 * na, nx);
            st = AENL_E_ARG;
            goto done;
        }
        double tr = 0.0;
        for (size_t i = 0; i < nx; ++i)
        {
            tr += G[i * na + i];
        }
        double *Gc = malloc(na * na * sizeof(double)), *X = malloc(na * nz * sizeof(double));
        if (!Gc || !X)
        {
            free(Gc);
            free(X);
            st = AENL_E_DIM;
            goto done;
        }
        memcpy(Gc, G, na * na * sizeof(double));
        memcpy(X, H, na * nz * sizeof(double));
        for (size_t i = 0; i < nx; ++i)
        {
            Gc[i * na + i] += 1e-10 * tr / (double)nx; /* tiny ridge: collinear lags */
        }
        lapack_int *piv = malloc(na * sizeof(lapack_int));
        const int info = (piv == NULL)
                             ? -1
                             : LAPACKE_dgesv(LAPACK_ROW_MAJOR, (lapack_int)na, (lapack_int)nz, Gc,
                                             (lapack_int)na, piv, X, (lapack_int)nz);
        free(piv);
        if (info != 0)
        {
            free(Gc);
            free(X);
            aenl_err_set(err, "mode %zu: the least-squares initialisation is singular", s);
            st = AENL_E_NOT_PD;
            goto done;
        }
        double *A = m->A + s * nn, *b = m->b + s * nx, *Q = m->Q + s * nn;
        memset(A, 0, nn * sizeof(double));
        memset(b, 0, nx * sizeof(double));
        memset(Q, 0, nn * sizeof(double));
        for (size_t r = 0; r < nz; ++r)
        {
            for (size_t j = 0; j < nx; ++j)
            {
                A[r * nx + j] = X[j * nz + r];
            }
            b[r] = X[nx * nz + r];
        }
        /* residual covariance: (Syy - X' H - H' X + X' G X)/cnt computed directly */
        memset(res, 0, nz * nz * sizeof(double));
        for (size_t k = 1; k + 1 < n; ++k)
        {
            if (w->mode[k + 1] != s)
            {
                continue;
            }
            int ok = 1;
            for (size_t i = 0; i < nx && ok; ++i)
            {
                z[i] = y_at(y, nz, (long)k - (long)(i / nz), i % nz);
                ok = isfinite(z[i]);
            }
            double e[AENL_EM_MAX_X];
            for (size_t r = 0; r < nz && ok; ++r)
            {
                double acc = y[(k + 1) * nz + r] - b[r];
                for (size_t j = 0; j < nx; ++j)
                {
                    acc -= A[r * nx + j] * z[j];
                }
                e[r] = acc;
                ok = isfinite(acc);
            }
            if (!ok)
            {
                continue;
            }
            add_outer(res, e, e, nz);
        }
        for (size_t r = 0; r < nz; ++r)
        {
            for (size_t c = 0; c < nz; ++c)
            {
                Q[r * nx + c] = res[r * nz + c] / cnt;
            }
            pooled[r] += res[r * nz + r];
        }
        pooled_n += cnt;
        /* to the observer canonical form (exact for any observable linear system, noise in
         * every block): row (j, r) holds the coefficients of lag j, and a shifted identity */
        for (size_t i = 0; i < nx; ++i)
        {
            const size_t j = i / nz, r = i % nz;
            for (size_t c = 0; c < nx; ++c)
            {
                A[i * nx + c] = 0.0;
            }
            for (size_t c = 0; c < nz; ++c)
            {
                A[i * nx + c] = (j * nz + c < nx) ? X[(j * nz + c) * nz + r] : 0.0;
            }
            if (i + nz < nx)
            {
                A[i * nx + i + nz] = 1.0;
            }
        }
        free(Gc);
        free(X);
    }
    for (size_t r = 0; r < nz; ++r)
    {
        pooled[r] /= pooled_n;
    }
    memset(m->R, 0, nz * nz * sizeof(double));
    for (size_t r = 0; r < nz; ++r)
    {
        m->R[r * nz + r] = 0.05 * pooled[r]; /* small R, large Q: EM then leaves the noise to R */
    }
    for (size_t s = 0; s < nm; ++s)
    {
        for (size_t i = nz; i < nx; ++i)
        {
            m->Q[s * nn + i * nx + i] = pooled[i % nz];
        }
    }
    /* x0 from the first samples; P0 from the channel variances */
    memset(m->P0, 0, nn * sizeof(double));
    for (size_t i = 0; i < nx; ++i)
    {
        double mean = 0.0, m2 = 0.0, c = 0.0;
        for (size_t k = 0; k < n; ++k)
        {
            const double v = y[k * nz + i % nz];
            if (isfinite(v))
            {
                c += 1.0;
                const double d = v - mean;
                mean += d / c;
                m2 += d * (v - mean);
            }
        }
        const double v0 = y[i % nz];
        m->x0[i] = isfinite(v0) ? v0 : mean;
        m->P0[i * nx + i] = (c > 1.0) ? m2 / (c - 1.0) : 1.0;
        if (!(m->P0[i * nx + i] > 0.0))
        {
            m->P0[i * nx + i] = 1.0;
        }
    }
done:
    free(G);
    free(H);
    free(z);
    free(res);
    free(pooled);
    return st;
}

/* Modes from the smoothed switching output of model m (one E-step). */
static aenl_status_t modes_from_smoother(ws_t *w, const aenl_em_model_t *m, double *u)
{
    double ll;
    const aenl_status_t st = e_step(w, m, &ll, 1);
    if (st != AENL_OK)
    {
        return st;
    }
    const size_t nx = w->nx, ch = m->switch_channel;
    for (size_t k = 0; k < w->n; ++k)
    {
        double acc = 0.0;
        for (size_t j = 0; j < nx; ++j)
        {
            acc += m->C[ch * nx + j] * w->xf[k * nx + j];
        }
        u[k] = acc;
    }
    set_modes(w, m->thresholds, u, 1);
    return AENL_OK;
}

/* Run up to n_iter EM iterations; loglik (may be NULL) receives one value per iteration. */
static aenl_status_t em_run(ws_t *w, aenl_em_model_t *m, const aenl_em_opts_t *o, size_t n_iter,
                            double *loglik, size_t *done_iter, double *ll_final)
{
    size_t it = 0;
    double prev = -INFINITY;
    aenl_status_t st = AENL_OK;
    for (; it < n_iter; ++it)
    {
        double ll;
        st = e_step(w, m, &ll, 1);
        if (st != AENL_OK)
        {
            break;
        }
        if (loglik != NULL)
        {
            loglik[it] = ll;
        }
        const int converged = o->tol > 0.0 && it > 0 && (ll - prev) < o->tol * fabs(ll);
        prev = ll;
        if (converged)
        {
            ++it;
            break;
        }
        st = m_step(w, m, o->freeze);
        if (st != AENL_OK)
        {
            break;
        }
    }
    *done_iter = it;
    if (st == AENL_OK && ll_final != NULL)
    {
        st = e_step(w, m, ll_final, 0);
    }
    return st;
}

static aenl_status_t check_opts(const aenl_em_opts_t *o, size_t n, size_t nz, aenl_err_t *err)
{
    const size_t nx = o->n_states ? o->n_states : 4 * nz;
    if (nz == 0 || nx < nz || nx > AENL_EM_MAX_X)
    {
        aenl_err_set(err, "states must be in %zu..%d (got %zu)", nz, AENL_EM_MAX_X, nx);
        return AENL_E_ARG;
    }
    if (o->switch_channel >= nz)
    {
        aenl_err_set(err, "switching channel %zu does not exist (%zu channels)", o->switch_channel,
                     nz);
        return AENL_E_ARG;
    }
    if (o->n_thresholds + 1 > AENL_EM_MAX_MODES)
    {
        aenl_err_set(err, "at most %d thresholds", AENL_EM_MAX_MODES - 1);
        return AENL_E_ARG;
    }
    for (size_t i = 0; i < o->n_thresholds; ++i)
    {
        if (!isfinite(o->thresholds[i]) || (i > 0 && !(o->thresholds[i] > o->thresholds[i - 1])))
        {
            aenl_err_set(err, "thresholds must be finite and strictly ascending");
            return AENL_E_ARG;
        }
    }
    if (!(o->dt > 0.0) || !isfinite(o->dt))
    {
        aenl_err_set(err, "the sample step must be positive (got %g)", o->dt);
        return AENL_E_ARG;
    }
    if (n < 4 * (nx + 2))
    {
        aenl_err_set(err, "%zu samples are too few for %zu states", n, nx);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

/* Coordinate search of the thresholds: short EM runs from the current model, best likelihood. */
static aenl_status_t refine_thresholds(ws_t *w, aenl_em_model_t *m, const aenl_em_opts_t *o,
                                       double *u, aenl_err_t *err)
{
    aenl_em_model_t trial, best;
    aenl_status_t st = aenl_em_model_copy(&trial, m, err);
    if (st != AENL_OK)
    {
        return st;
    }
    st = aenl_em_model_copy(&best, m, err);
    if (st != AENL_OK)
    {
        aenl_em_model_free(&trial);
        return st;
    }
    double step = o->refine_step;
    if (!(step > 0.0))
    {
        double mean = 0.0, m2 = 0.0, c = 0.0;
        for (size_t k = 0; k < w->n; ++k)
        {
            c += 1.0;
            const double d = u[k] - mean;
            mean += d / c;
            m2 += d * (u[k] - mean);
        }
        step = 0.1 * sqrt(m2 / c);
    }
    size_t done;
    double best_ll;
    set_modes(w, best.thresholds, u, 1);
    st = em_run(w, &best, o, o->refine_iter, NULL, &done, &best_ll);
    for (int round = 0; round < 3 && st == AENL_OK; ++round, step *= 0.5)
    {
        for (size_t i = 0; i + 1 < m->n_modes && st == AENL_OK; ++i)
        {
            for (int d = -1; d <= 1; d += 2)
            {
                model_assign(&trial, m);
                memcpy(trial.thresholds, best.thresholds, sizeof(trial.thresholds));
                trial.thresholds[i] += d * step;
                const int ordered =
                    (i == 0 || trial.thresholds[i] > trial.thresholds[i - 1]) &&
                    (i + 2 >= m->n_modes || trial.thresholds[i] < trial.thresholds[i + 1]);
                if (!ordered)
                {
                    continue;
                }
                set_modes(w, trial.thresholds, u, 1);
                double ll = -INFINITY;
                const aenl_status_t s2 = em_run(w, &trial, o, o->refine_iter, NULL, &done, &ll);
                if (s2 == AENL_OK && ll > best_ll)
                {
                    best_ll = ll;
                    model_assign(&best, &trial);
                }
            }
        }
    }
    if (st == AENL_OK)
    {
        memcpy(m->thresholds, best.thresholds, sizeof(m->thresholds));
    }
    aenl_em_model_free(&trial);
    aenl_em_model_free(&best);
    return st;
}

aenl_status_t aenl_em_fit(const double *y, size_t n, size_t n_z, const aenl_em_opts_t *opts,
                          aenl_em_result_t *res, aenl_err_t *err)
{
    if (res != NULL)
    {
        memset(res, 0, sizeof(*res));
    }
    if (y == NULL || opts == NULL || res == NULL)
    {
        aenl_err_set(err, "NULL argument");
        return AENL_E_ARG;
    }
    aenl_status_t st = check_opts(opts, n, n_z, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const size_t nx = opts->n_states ? opts->n_states : 4 * n_z, nm = opts->n_thresholds + 1;
    aenl_em_model_t *m = &res->model;
    st = aenl_em_model_alloc(m, nx, n_z, nm, err);
    if (st != AENL_OK)
    {
        return st;
    }
    m->switch_channel = opts->switch_channel;
    m->dt = opts->dt;
    memcpy(m->thresholds, opts->thresholds, opts->n_thresholds * sizeof(double));
    ws_t w;
    st = ws_alloc(&w, y, n, nx, n_z, nm, err);
    double *u = (st == AENL_OK) ? malloc(n * sizeof(double)) : NULL;
    res->loglik = (st == AENL_OK) ? calloc(opts->max_iter + 1, sizeof(double)) : NULL;
    if (st == AENL_OK && (u == NULL || res->loglik == NULL))
    {
        aenl_err_set(err, "out of memory");
        st = AENL_E_DIM;
    }
    if (st == AENL_OK)
    {
        for (size_t k = 0; k < n; ++k)
        {
            res->n_missing += w.obs[k] ? 0u : 1u;
        }
        set_modes(&w, m->thresholds, y + opts->switch_channel, n_z);
        st = ls_init(y, n, n_z, &w, m, !opts->no_iv, err);
    }
    if (st == AENL_OK && !opts->modes_from_data)
    {
        st = modes_from_smoother(&w, m, u);
        if (st == AENL_OK)
        {
            st = ls_init(y, n, n_z, &w, m, !opts->no_iv,
                         err); /* re-fit the start with the cleaner modes */
        }
    }
    if (st == AENL_OK && opts->refine && nm > 1)
    {
        if (opts->modes_from_data)
        {
            for (size_t k = 0; k < n; ++k)
            {
                u[k] = y[k * n_z + opts->switch_channel];
            }
        }
        st = refine_thresholds(&w, m, opts, u, err);
        if (st == AENL_OK)
        {
            set_modes(&w, m->thresholds, u, 1);
            st = ls_init(y, n, n_z, &w, m, !opts->no_iv, err);
        }
    }
    if (st == AENL_OK)
    {
        for (size_t k = 1; k < n; ++k)
        {
            res->mode_count[w.mode[k]]++;
        }
        st = em_run(&w, m, opts, opts->max_iter, res->loglik, &res->n_iter, &res->loglik_final);
        if (st != AENL_OK)
        {
            aenl_err_set(err, "EM failed (%s) after %zu iterations", aenl_status_str(st),
                         res->n_iter);
        }
    }
    free(u);
    ws_free(&w);
    if (st != AENL_OK)
    {
        aenl_em_result_free(res);
    }
    return st;
}

aenl_status_t aenl_em_iterate(aenl_em_model_t *m, const double *y, size_t n,
                              const aenl_em_opts_t *opts, double *loglik, size_t *n_iter,
                              aenl_err_t *err)
{
    if (m == NULL || y == NULL || opts == NULL || n_iter == NULL || n < 2)
    {
        aenl_err_set(err, "NULL argument or no data");
        return AENL_E_ARG;
    }
    ws_t w;
    aenl_status_t st = ws_alloc(&w, y, n, m->n_x, m->n_z, m->n_modes, err);
    if (st != AENL_OK)
    {
        return st;
    }
    set_modes(&w, m->thresholds, y + m->switch_channel, m->n_z);
    double final_ll = 0.0;
    st = em_run(&w, m, opts, opts->max_iter, loglik, n_iter, &final_ll);
    if (st == AENL_OK && loglik != NULL)
    {
        loglik[*n_iter] = final_ll;
    }
    ws_free(&w);
    if (st != AENL_OK)
    {
        aenl_err_set(err, "EM failed (%s)", aenl_status_str(st));
    }
    return st;
}

void aenl_em_result_free(aenl_em_result_t *res)
{
    if (res == NULL)
    {
        return;
    }
    aenl_em_model_free(&res->model);
    free(res->loglik);
    memset(res, 0, sizeof(*res));
}

aenl_status_t aenl_em_loglik(const aenl_em_model_t *m, const double *y, size_t n, const double *u,
                             double *ll, aenl_err_t *err)
{
    if (m == NULL || y == NULL || ll == NULL || n == 0)
    {
        aenl_err_set(err, "NULL argument or no data");
        return AENL_E_ARG;
    }
    ws_t w;
    aenl_status_t st = ws_alloc(&w, y, n, m->n_x, m->n_z, m->n_modes, err);
    if (st != AENL_OK)
    {
        return st;
    }
    if (u != NULL)
    {
        set_modes(&w, m->thresholds, u, 1);
    }
    else
    {
        set_modes(&w, m->thresholds, y + m->switch_channel, m->n_z);
    }
    st = e_step(&w, m, ll, 0);
    ws_free(&w);
    if (st != AENL_OK)
    {
        aenl_err_set(err, "log-likelihood: %s", aenl_status_str(st));
    }
    return st;
}

/* ---- modal analysis ---------------------------------------------------------------------------
 */

static int cmp_eig(const void *pa, const void *pb)
{
    const aenl_em_eig_t *a = pa, *b = pb;
    const int oa = a->im > 0.0, ob = b->im > 0.0;
    if (oa != ob)
    {
        return ob - oa; /* oscillatory first */
    }
    const double ka = oa ? a->frequency : -a->s_re, kb = ob ? b->frequency : -b->s_re;
    return (ka > kb) - (ka < kb);
}

aenl_status_t aenl_em_modal(const aenl_em_model_t *m, size_t mode, aenl_em_eig_t *eig,
                            size_t *n_eig, size_t *n_osc, aenl_err_t *err)
{
    if (m == NULL || eig == NULL || n_eig == NULL || mode >= m->n_modes || !(m->dt > 0.0))
    {
        aenl_err_set(err, "modal analysis: bad argument");
        return AENL_E_ARG;
    }
    const size_t nx = m->n_x;
    double *a = malloc(nx * nx * sizeof(double)), *wr = malloc(nx * sizeof(double));
    double *wi = malloc(nx * sizeof(double));
    if (!a || !wr || !wi)
    {
        free(a);
        free(wr);
        free(wi);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    memcpy(a, m->A + mode * nx * nx, nx * nx * sizeof(double));
    const lapack_int info = LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', (lapack_int)nx, a,
                                          (lapack_int)nx, wr, wi, NULL, 1, NULL, 1);
    size_t k = 0, osc = 0;
    if (info == 0)
    {
        for (size_t i = 0; i < nx; ++i)
        {
            if (wi[i] < 0.0)
            {
                continue; /* one entry per conjugate pair */
            }
            aenl_em_eig_t *e = &eig[k++];
            e->re = wr[i];
            e->im = wi[i];
            /* principal logarithm: ln|λ| + i arg λ */
            e->s_re = log(hypot(wr[i], wi[i])) / m->dt;
            e->s_im = atan2(wi[i], wr[i]) / m->dt;
            const double mag = hypot(e->s_re, e->s_im);
            e->frequency = fabs(e->s_im) / (2.0 * 3.14159265358979323846);
            e->damping = (mag > 0.0) ? -e->s_re / mag : 0.0;
            osc += (wi[i] > 0.0) ? 1u : 0u;
        }
        qsort(eig, k, sizeof(eig[0]), cmp_eig);
    }
    free(a);
    free(wr);
    free(wi);
    if (info != 0)
    {
        aenl_err_set(err, "dgeev failed (info %d) on mode %zu", (int)info, mode);
        return AENL_E_NUMERIC;
    }
    *n_eig = k;
    if (n_osc != NULL)
    {
        *n_osc = osc;
    }
    return AENL_OK;
}

aenl_status_t aenl_em_simulate(const aenl_em_model_t *m, const double *x_init, size_t n,
                               double *y_out, aenl_err_t *err)
{
    if (m == NULL || y_out == NULL)
    {
        aenl_err_set(err, "simulate: NULL argument");
        return AENL_E_ARG;
    }
    const size_t nx = m->n_x, nz = m->n_z;
    double x[AENL_EM_MAX_X], xn[AENL_EM_MAX_X];
    memcpy(x, x_init ? x_init : m->x0, nx * sizeof(double));
    for (size_t k = 0; k < n; ++k)
    {
        for (size_t r = 0; r < nz; ++r)
        {
            double acc = 0.0;
            for (size_t j = 0; j < nx; ++j)
            {
                acc += m->C[r * nx + j] * x[j];
            }
            y_out[k * nz + r] = acc;
        }
        const size_t s = mode_of(m->thresholds, m->n_modes, y_out[k * nz + m->switch_channel]);
        const double *A = m->A + s * nx * nx, *b = m->b + s * nx;
        for (size_t i = 0; i < nx; ++i)
        {
            double acc = b[i];
            for (size_t j = 0; j < nx; ++j)
            {
                acc += A[i * nx + j] * x[j];
            }
            xn[i] = acc;
        }
        memcpy(x, xn, nx * sizeof(double));
        if (!isfinite(x[0]))
        {
            aenl_err_set(err, "simulation diverged at sample %zu", k);
            return AENL_E_NUMERIC;
        }
    }
    return AENL_OK;
}

/* ---- export -----------------------------------------------------------------------------------
 */

aenl_status_t aenl_em_to_skf(const aenl_em_model_t *m, aenl_skf_model_t *out, aenl_err_t *err)
{
    if (m == NULL || out == NULL)
    {
        aenl_err_set(err, "NULL argument");
        return AENL_E_ARG;
    }
    if (m->n_x > AENL_SKF_MAX_X || m->n_z > AENL_SKF_MAX_Z || m->n_modes > AENL_SKF_MAX_MODES)
    {
        aenl_err_set(err,
                     "model (%zu states, %zu outputs, %zu modes) exceeds the core capacities "
                     "(%d, %d, %d)",
                     m->n_x, m->n_z, m->n_modes, AENL_SKF_MAX_X, AENL_SKF_MAX_Z,
                     AENL_SKF_MAX_MODES);
        return AENL_E_DIM;
    }
    const size_t nx = m->n_x, nz = m->n_z;
    memset(out, 0, sizeof(*out));
    out->n_x = (uint16_t)nx;
    out->n_z = (uint16_t)nz;
    out->n_modes = (uint16_t)m->n_modes;
    out->switch_state = (uint16_t)m->switch_channel; /* C = [I 0]: the channel's own state */
    out->dir_state = AENL_SKF_DIR_DIFF;
    for (size_t i = 0; i + 1 < m->n_modes; ++i)
    {
        out->thr_rising[i] = (aenl_real_t)m->thresholds[i];
        out->thr_falling[i] = (aenl_real_t)m->thresholds[i];
    }
    for (size_t s = 0; s < m->n_modes; ++s)
    {
        for (size_t i = 0; i < nx; ++i)
        {
            out->b[s][i] = (aenl_real_t)m->b[s * nx + i];
            for (size_t j = 0; j < nx; ++j)
            {
                out->A[s][i][j] = (aenl_real_t)m->A[(s * nx + i) * nx + j];
                out->Q[s][i][j] = (aenl_real_t)m->Q[(s * nx + i) * nx + j];
            }
        }
    }
    for (size_t r = 0; r < nz; ++r)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            out->C[r][j] = (aenl_real_t)m->C[r * nx + j];
        }
        for (size_t c = 0; c < nz; ++c)
        {
            out->R[r][c] = (aenl_real_t)m->R[r * nz + c];
        }
    }
    for (size_t i = 0; i < nx; ++i)
    {
        out->x0[i] = (aenl_real_t)m->x0[i];
        for (size_t j = 0; j < nx; ++j)
        {
            out->P0[i][j] = (aenl_real_t)m->P0[i * nx + j];
        }
    }
    return AENL_OK;
}

static void write_row(FILE *fp, const char *key, const double *v, size_t n)
{
    fprintf(fp, "%s =", key);
    for (size_t i = 0; i < n; ++i)
    {
        fprintf(fp, "%s %.17g", i ? "," : "", v[i]);
    }
    fputc('\n', fp);
}

aenl_status_t aenl_em_write_ini(const aenl_em_model_t *m, const char *path, aenl_err_t *err)
{
    aenl_outfile_t of;
    aenl_status_t st = aenl_outfile_open(&of, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const size_t nx = m->n_x, nz = m->n_z;
    FILE *fp = of.fp;
    fprintf(fp, "; switching linear state-space model identified by aenl fit (EM)\n");
    fprintf(fp, "; x_k = A_s x_{k-1} + b_s + v (v ~ N(0, Q_s)), y_k = C x_k + w (w ~ N(0, R));\n");
    fprintf(fp, "; s = number of thresholds <= the switching channel at k-1. Row-major.\n");
    fprintf(fp, "[model]\ntype = switching_ss\nstates = %zu\noutputs = %zu\nmodes = %zu\n", nx, nz,
            m->n_modes);
    fprintf(fp, "switch_channel = %zu\ndt = %.17g\n", m->switch_channel, m->dt);
    if (m->n_modes > 1)
    {
        write_row(fp, "thresholds", m->thresholds, m->n_modes - 1);
    }
    for (size_t s = 0; s < m->n_modes; ++s)
    {
        fprintf(fp, "\n[mode.%zu]\n", s);
        write_row(fp, "A", m->A + s * nx * nx, nx * nx);
        write_row(fp, "b", m->b + s * nx, nx);
        write_row(fp, "Q", m->Q + s * nx * nx, nx * nx);
    }
    fprintf(fp, "\n[output]\n");
    write_row(fp, "C", m->C, nz * nx);
    write_row(fp, "R", m->R, nz * nz);
    fprintf(fp, "\n[initial]\n");
    write_row(fp, "x0", m->x0, nx);
    write_row(fp, "P0", m->P0, nx * nx);
    return aenl_outfile_commit(&of, err);
}

/* A float literal that reads back to the same float (9 significant digits), symmetric-safe. */
static void c_real(FILE *fp, double v)
{
    char buf[48];
    snprintf(buf, sizeof(buf), "%.9g", (double)(float)v);
    if (strpbrk(buf, ".eE") == NULL)
    {
        strcat(buf, ".0");
    }
    fprintf(fp, "AENL_R(%s)", buf);
}

static void c_matrix(FILE *fp, const char *indent, const double *a, size_t n, size_t m,
                     size_t stride)
{
    fprintf(fp, "{");
    for (size_t i = 0; i < n; ++i)
    {
        fprintf(fp, "%s\n%s{", i ? "," : "", indent);
        for (size_t j = 0; j < m; ++j)
        {
            if (j)
            {
                fprintf(fp, ", ");
            }
            c_real(fp, a[i * stride + j]);
        }
        fprintf(fp, "}");
    }
    fprintf(fp, "}");
}

aenl_status_t aenl_em_write_c_header(const aenl_em_model_t *m, const char *name, const char *path,
                                     aenl_err_t *err)
{
    if (m == NULL || name == NULL || path == NULL)
    {
        aenl_err_set(err, "NULL argument");
        return AENL_E_ARG;
    }
    for (const char *p = name; *p; ++p)
    {
        const int ok = (*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || *p == '_' ||
                       (p != name && *p >= '0' && *p <= '9');
        if (!ok || name[0] == '\0')
        {
            aenl_err_set(err, "'%s' is not a C identifier", name);
            return AENL_E_ARG;
        }
    }
    aenl_outfile_t of;
    aenl_status_t st = aenl_outfile_open(&of, path, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const size_t nx = m->n_x, nz = m->n_z, nm = m->n_modes;
    FILE *fp = of.fp;
    char guard[160];
    snprintf(guard, sizeof(guard), "AENL_MODEL_%s_H", name);
    for (char *p = guard; *p; ++p)
    {
        *p = (*p >= 'a' && *p <= 'z') ? (char)(*p - 'a' + 'A') : *p;
    }
    fprintf(
        fp,
        "/* Generated by `aenl fit`: switching state-space model for the aenl_skf core filter.\n"
        " * %zu states, %zu outputs, %zu modes, sample step %.17g; switching on output %zu.\n"
        " * Include once, after aenl/aenl_skf.h; the object can live in flash. */\n",
        nx, nz, nm, m->dt, m->switch_channel);
    fprintf(fp, "#ifndef %s\n#define %s\n\n#include \"aenl/aenl_skf.h\"\n\n", guard, guard);
    fprintf(fp,
            "#if AENL_SKF_MAX_X < %zu || AENL_SKF_MAX_Z < %zu || AENL_SKF_MAX_MODES < %zu\n"
            "#error \"%s needs AENL_SKF_MAX_X >= %zu, AENL_SKF_MAX_Z >= %zu, "
            "AENL_SKF_MAX_MODES >= %zu\"\n#endif\n\n",
            nx, nz, nm, name, nx, nz, nm);
    fprintf(fp, "/** sample step of the identified model, in the data's time unit */\n");
    fprintf(fp, "#define %s_DT ", guard);
    c_real(fp, m->dt);
    fprintf(fp, "\n\nstatic const aenl_skf_model_t %s = {\n", name);
    fprintf(fp, "    .n_x = %zu,\n    .n_z = %zu,\n    .n_modes = %zu,\n", nx, nz, nm);
    fprintf(fp, "    .switch_state = %zu,\n    .dir_state = AENL_SKF_DIR_DIFF,\n    .imm = 0,\n",
            m->switch_channel);
    fprintf(fp, "    .thr_rising = {");
    for (size_t i = 0; i + 1 < nm; ++i)
    {
        fprintf(fp, "%s", i ? ", " : "");
        c_real(fp, m->thresholds[i]);
    }
    fprintf(fp, "%s},\n    .thr_falling = {", nm > 1 ? "" : "AENL_R(0.0)");
    for (size_t i = 0; i + 1 < nm; ++i)
    {
        fprintf(fp, "%s", i ? ", " : "");
        c_real(fp, m->thresholds[i]);
    }
    fprintf(fp, "%s},\n", nm > 1 ? "" : "AENL_R(0.0)");
    const char *names[2] = {"A", "Q"};
    const double *mats[2] = {m->A, m->Q};
    for (int w = 0; w < 2; ++w)
    {
        fprintf(fp, "    .%s = {", names[w]);
        for (size_t s = 0; s < nm; ++s)
        {
            fprintf(fp, "%s\n        /* mode %zu */ ", s ? "," : "", s);
            c_matrix(fp, "        ", mats[w] + s * nx * nx, nx, nx, nx);
        }
        fprintf(fp, "},\n");
    }
    fprintf(fp, "    .b = ");
    c_matrix(fp, "        ", m->b, nm, nx, nx);
    fprintf(fp, ",\n    .C = ");
    c_matrix(fp, "        ", m->C, nz, nx, nx);
    fprintf(fp, ",\n    .R = ");
    c_matrix(fp, "        ", m->R, nz, nz, nz);
    fprintf(fp, ",\n    .x0 = {");
    for (size_t i = 0; i < nx; ++i)
    {
        fprintf(fp, "%s", i ? ", " : "");
        c_real(fp, m->x0[i]);
    }
    fprintf(fp, "},\n    .P0 = ");
    c_matrix(fp, "        ", m->P0, nx, nx, nx);
    fprintf(fp, ",\n};\n\n#endif /* %s */\n", guard);
    return aenl_outfile_commit(&of, err);
}
