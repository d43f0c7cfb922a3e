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
#include "aenl_tools/aenl_dense.h"
#include "aenl_tools/aenl_rng.h"

#include <lapacke.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LOG_2PI 1.8378770664093453

/* ---- model ------------------------------------------------------------------------------------
 */

void aenl_em_opts_default(aenl_em_opts_t *o)
{
    memset(o, 0, sizeof(*o));
    o->max_iter = 50;
    o->freeze = AENL_EM_FREEZE_C;
    o->refine_iter = 5;
    o->dt = 1.0;
    o->steady_tol = AENL_EM_STEADY_TOL;
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
    m->B = calloc(1, sizeof(double)); /* no input yet: aenl_em_model_set_inputs */
    m->Q = calloc(n_modes * n_x * n_x, sizeof(double));
    m->C = calloc(n_z * n_x, sizeof(double));
    m->R = calloc(n_z * n_z, sizeof(double));
    m->x0 = calloc(n_x, sizeof(double));
    m->P0 = calloc(n_x * n_x, sizeof(double));
    if (!m->A || !m->b || !m->B || !m->Q || !m->C || !m->R || !m->x0 || !m->P0)
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
    free(m->B);
    free(m->Q);
    free(m->C);
    free(m->R);
    free(m->x0);
    free(m->P0);
    memset(m, 0, sizeof(*m));
}

aenl_status_t aenl_em_model_set_inputs(aenl_em_model_t *m, size_t n_u, aenl_err_t *err)
{
    if (n_u > AENL_EM_MAX_U)
    {
        aenl_err_set(err, "at most %d inputs (got %zu)", AENL_EM_MAX_U, n_u);
        return AENL_E_ARG;
    }
    double *B = calloc(n_u > 0 ? m->n_modes * m->n_x * n_u : 1u, sizeof(double));
    if (B == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    free(m->B);
    m->B = B;
    m->n_u = n_u;
    return AENL_OK;
}

aenl_status_t aenl_em_model_copy(aenl_em_model_t *dst, const aenl_em_model_t *src, aenl_err_t *err)
{
    aenl_status_t st = aenl_em_model_alloc(dst, src->n_x, src->n_z, src->n_modes, err);
    if (st != AENL_OK)
    {
        return st;
    }
    if (src->n_u > 0)
    {
        st = aenl_em_model_set_inputs(dst, src->n_u, err);
        if (st != AENL_OK)
        {
            aenl_em_model_free(dst);
            return st;
        }
    }
    memcpy(dst->B, src->B, src->n_modes * src->n_x * src->n_u * sizeof(double));
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
    memcpy(dst->B, src->B, nm * nx * src->n_u * sizeof(double));
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

/* ||a - b|| / ||a|| in the Frobenius norm (0 when both are zero); branch-free, four partial
 * sums. */
static double rel_change(const double *a, const double *b, size_t n)
{
    double d0 = 0.0, d1 = 0.0, s0 = 0.0, s1 = 0.0;
    size_t i = 0;
    for (; i + 2 <= n; i += 2)
    {
        const double e0 = a[i] - b[i], e1 = a[i + 1] - b[i + 1];
        d0 += e0 * e0;
        d1 += e1 * e1;
        s0 += a[i] * a[i];
        s1 += a[i + 1] * a[i + 1];
    }
    for (; i < n; ++i)
    {
        const double e = a[i] - b[i];
        d0 += e * e;
        s0 += a[i] * a[i];
    }
    const double d = d0 + d1, s = s0 + s1;
    return (s > 0.0) ? sqrt(d / s) : (d > 0.0 ? HUGE_VAL : 0.0);
}

/* Geometric-convergence test of a covariance recursion (see the E-step comment): with the last
 * two relative changes d (now) and d_prev, the contraction estimate rho = d/d_prev bounds the
 * remaining drift by d rho/(1 - rho); converged when that is below tol. */
static int converged(double d, double d_prev, double tol)
{
    if (!(tol > 0.0))
    {
        return 0;
    }
    if (d <= 0.0)
    {
        return 1;
    }
    if (!(d < 1e-6) || !isfinite(d_prev) || !(d < d_prev))
    {
        return 0;
    }
    const double rho = d / d_prev;
    return d * rho <= tol * (1.0 - rho);
}

/* ---- workspace --------------------------------------------------------------------------------
 */

/* The covariance-side quantities of the E-step do not depend on the data, only on the mode
 * sequence and the missing-sample pattern. They live in "slots": slot[k] indexes the filtered
 * covariance Pf_k, the gain K_k = Pp_k C' S_k^-1 (nx x nz), the Cholesky factor of the
 * innovation covariance S_k and its log-determinant, and for the transition (k-1 -> k) the
 * smoother gain J_{k-1} = Pf_{k-1} A' Pp_k^-1 and Pfg_{k-1} = Pf_{k-1} - J_{k-1} Pp_k J_{k-1}'
 * (so that the RTS covariance is Ps_{k-1} = Pfg_{k-1} + J_{k-1} Ps_k J_{k-1}', no Pp needed).
 * Once the recursion has converged inside a run of constant mode, consecutive steps share one
 * slot (steady state) until the mode changes or a sample is missing. */
typedef struct
{
    size_t n, nx, nz, nm;
    const double *y;
    unsigned char *obs;  /* y_k fully observed */
    unsigned char *mode; /* mode[k]: transition k-1 -> k (mode[0] unused) */
    double *xp, *xf;     /* predicted and filtered means; xf becomes x_{k|n} in the backward pass */
    size_t *slot;        /* covariance slot of step k */
    double *JP;          /* per slot, what the backward pass needs: J' (nn), Pfg (packed lower) */
    size_t slot_len;     /* nn + nx (nx + 1) / 2 */
    double *At, *Ct;     /* A_s' per mode and C', refreshed by each forward pass */
    int c_select; /* C is a 0/1 selection (the default C = [I 0]): state sel[r] is output r */
    size_t sel[AENL_EM_MAX_X];
    double *Pf, *K, *Ls, *logdet; /* of the last two slots (index slot & 1): nn, nx*nz, nz*nz, 1 */
    size_t n_slots;               /* slots used by the last forward pass */
    double steady_tol;            /* steady-state tolerance (0: full recursion at every step) */
    double *tmp; /* scratch: [0,5nn) predict, [6nn,9nn) update, 10nn means, 11nn 1/diag */
    /* statistics */
    double *S11, *S10, *S00, *s1, *s0, cnt[AENL_EM_MAX_MODES];
    double *Syx, *Sxx, *Syy, ny;
    const double *u; /* known inputs, n x nu (NULL: none) */
    size_t nu;
    double *S0u, *S1u, *Suu, *su; /* per mode: sum x_k u_k', x_{k+1} u_k', u_k u_k', u_k */
    double *bE, *be;              /* (n_modes+1)^2 * 2 buckets of nn and nx (see add_state_stats) */
    const unsigned char *jump;    /* jump[k]: transition k-1 -> k is a jump (NULL: none) */
    const double *Pjump;          /* its added prediction covariance */
} ws_t;

/* Whether the transition k-1 -> k carries a jump. */
static int is_jump(const ws_t *w, size_t k)
{
    return w->jump != NULL && k > 0 && k < w->n && w->jump[k] != 0;
}

static void ws_free(ws_t *w)
{
    free(w->obs);
    free(w->mode);
    free(w->xp);
    free(w->xf);
    free(w->slot);
    free(w->Pf);
    free(w->JP);
    free(w->At);
    free(w->Ct);
    free(w->K);
    free(w->Ls);
    free(w->logdet);
    free(w->tmp);
    free(w->S11);
    free(w->S10);
    free(w->S00);
    free(w->s1);
    free(w->s0);
    free(w->Syx);
    free(w->Sxx);
    free(w->Syy);
    free(w->bE);
    free(w->be);
    free(w->S0u);
    free(w->S1u);
    free(w->Suu);
    free(w->su);
    memset(w, 0, sizeof(*w));
}

static aenl_status_t ws_alloc(ws_t *w, const double *y, size_t n, size_t nx, size_t nz, size_t nm,
                              aenl_err_t *err)
{
    memset(w, 0, sizeof(*w));
    const size_t nn = nx * nx;
    w->n = n;
    w->nx = nx;
    w->nz = nz;
    w->nm = nm;
    w->y = y;
    w->steady_tol = AENL_EM_STEADY_TOL;
    w->obs = calloc(n, 1);
    w->mode = calloc(n, 1);
    w->xp = malloc(n * nx * sizeof(double));
    w->xf = malloc(n * nx * sizeof(double));
    w->slot = malloc(n * sizeof(size_t));
    w->Pf = malloc(2 * nn * sizeof(double));
    w->slot_len = nn + nx * (nx + 1) / 2;
    w->JP = malloc(n * w->slot_len * sizeof(double));
    w->At = malloc(nm * nn * sizeof(double));
    w->Ct = malloc(nx * nz * sizeof(double));
    w->K = malloc(2 * nx * nz * sizeof(double));
    w->Ls = malloc(2 * nz * nz * sizeof(double));
    w->logdet = malloc(2 * sizeof(double));
    w->tmp = malloc((12 * nn + 4 * nx + 4 * nz * nz + 4 * nx * nz + 16) * sizeof(double));
    w->S11 = calloc(nm * nn, sizeof(double));
    w->S10 = calloc(nm * nn, sizeof(double));
    w->S00 = calloc(nm * nn, sizeof(double));
    w->s1 = calloc(nm * nx, sizeof(double));
    w->s0 = calloc(nm * nx, sizeof(double));
    w->Syx = calloc(nz * nx, sizeof(double));
    w->Sxx = calloc(nn, sizeof(double));
    w->Syy = calloc(nz * nz, sizeof(double));
    w->bE = calloc((nm + 1) * (nm + 1) * 2 * nn, sizeof(double));
    w->be = calloc((nm + 1) * (nm + 1) * 2 * nx, sizeof(double));
    if (!w->bE || !w->be || !w->obs || !w->mode || !w->xp || !w->xf || !w->slot || !w->Pf ||
        !w->JP || !w->At || !w->Ct || !w->K || !w->Ls || !w->logdet || !w->tmp || !w->S11 ||
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

/* Known inputs u (n x nu) for the workspace's E- and M-steps. */
static aenl_status_t ws_set_inputs(ws_t *w, const double *u, size_t nu, aenl_err_t *err)
{
    if (nu == 0 || u == NULL)
    {
        return AENL_OK;
    }
    const size_t nm = w->nm, nx = w->nx;
    w->S0u = calloc(nm * nx * nu, sizeof(double));
    w->S1u = calloc(nm * nx * nu, sizeof(double));
    w->Suu = calloc(nm * nu * nu, sizeof(double));
    w->su = calloc(nm * nu, sizeof(double));
    if (!w->S0u || !w->S1u || !w->Suu || !w->su)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    w->u = u;
    w->nu = nu;
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
 * Exactness of the steady-state reuse: inside a run of constant mode with every sample observed,
 * the filter covariance follows the Riccati map of that mode and converges geometrically. With
 * d_k = ||Pf_k - Pf_{k-1}|| / ||Pf_k|| (Frobenius) and rho = d_k/d_{k-1}, the distance from Pf_k to
 * the fixed point is at most about d_k rho/(1 - rho); when that is below steady_tol (default 1e-10,
 * relative) the run's remaining steps reuse slot k (Pf, gain, smoother gain) instead of
 * recomputing it, and the backward covariance recursion Ps does the same (same test, run read
 * backwards). The result equals the full recursion to about steady_tol relative (the equivalence
 * is checked by a test with steady_tol = 0). */

/* Measurement update of slot q from the predicted covariance Pp: gain, chol(S), log det S, Pf.
 * Pp is the scratch w->tmp + 3 nn where kf_forward leaves it; it is taken from w, not passed: a
 * const pointer into w->tmp passed next to w made clang-analyzer lose track of w->tmp and report
 * a leak that cannot happen. */
static aenl_status_t cov_update(ws_t *w, const aenl_em_model_t *m, size_t q)
{
    const size_t nx = w->nx, nz = w->nz, nn = nx * nx;
    const double *Pp = w->tmp + 3 * nn;
    double *PCt = w->tmp + 6 * nn, *S = PCt + nx * nz, *Kt = S + nz * nz;
    const size_t r2 = q & 1u;
    double *K = w->K + r2 * nx * nz, *L = w->Ls + r2 * nz * nz, *Pf = w->Pf + r2 * nn;
    if (w->c_select)
    {
        /* C picks states: P C' and C P C' are columns and entries of P */
        for (size_t i = 0; i < nx; ++i)
        {
            for (size_t r = 0; r < nz; ++r)
            {
                PCt[i * nz + r] = Pp[i * nx + w->sel[r]];
            }
        }
        for (size_t r = 0; r < nz; ++r)
        {
            for (size_t c = 0; c < nz; ++c)
            {
                S[r * nz + c] = PCt[w->sel[r] * nz + c];
            }
        }
    }
    else
    {
        aenl_dense_mul(PCt, Pp, w->Ct, nx, nx, nz); /* P C' (nx x nz) */
        aenl_dense_mul_sym(S, m->C, PCt, nz, nx);   /* C P C' */
    }
    for (size_t i = 0; i < nz * nz; ++i)
    {
        S[i] += m->R[i];
    }
    aenl_dense_symmetrise(S, nz);
    memcpy(L, S, nz * nz * sizeof(double));
    if (aenl_dense_chol(L, nz, NULL) != 0)
    {
        return AENL_E_NOT_PD;
    }
    double ld = 0.0;
    for (size_t i = 0; i < nz; ++i)
    {
        ld += 2.0 * log(L[i * nz + i]);
    }
    w->logdet[r2] = ld;
    /* K' = S^-1 C P (nz x nx) */
    for (size_t r = 0; r < nz; ++r)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            Kt[r * nx + j] = PCt[j * nz + r];
        }
    }
    for (size_t i = 0; i < nz; ++i)
    {
        w->tmp[11 * nn + i] = 1.0 / L[i * nz + i];
    }
    aenl_dense_chol_solve(L, w->tmp + 11 * nn, nz, Kt, nx);
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t r = 0; r < nz; ++r)
        {
            K[i * nz + r] = Kt[r * nx + i];
        }
    }
    /* Pf = Pp - P C' K' */
    aenl_dense_mul_sym(Pf, PCt, Kt, nx, nz);
    for (size_t i = 0; i < nn; ++i)
    {
        Pf[i] = Pp[i] - Pf[i];
    }
    return AENL_OK;
}

/* Prediction from slot p through mode s into Pp; the smoother quantities of the transition
 * (J', Pfg) go to slot q. */
static aenl_status_t cov_predict(ws_t *w, const aenl_em_model_t *m, size_t s, size_t p, size_t q,
                                 double *Pp, const double *Pextra)
{
    const size_t nx = w->nx, nn = nx * nx;
    const double *A = m->A + s * nn, *Q = m->Q + s * nn, *Pfp = w->Pf + (p & 1u) * nn;
    double *T = w->tmp, *L = T + nn;
    double *Jt = w->JP + q * w->slot_len, *Pfg = Jt + nn, *G = L + nn;
    aenl_dense_mul(T, A, Pfp, nx, nx, nx);             /* T = A Pf_{k-1} */
    aenl_dense_mul_sym(Pp, T, w->At + s * nn, nx, nx); /* A Pf A' */
    for (size_t i = 0; i < nn; ++i)
    {
        Pp[i] += Q[i] + (Pextra != NULL ? Pextra[i] : 0.0);
    }
    /* J' = Pp^-1 T */
    memcpy(L, Pp, nn * sizeof(double));
    double *inv = w->tmp + 11 * nn;
    if (aenl_dense_chol(L, nx, inv) != 0 && aenl_dense_chol_jitter(L, Pp, nx, inv) != 0)
    {
        return AENL_E_NOT_PD;
    }
    double *X = w->tmp + 4 * nn; /* solved in cache, then stored once */
    memcpy(X, T, nn * sizeof(double));
    aenl_dense_chol_solve(L, inv, nx, X, nx);
    memcpy(Jt, X, nn * sizeof(double));
    /* Pfg = Pf - J Pp J' = Pf - J T (J Pp = Pf A' = T'), packed lower triangle */
    aenl_dense_mul_tn_sym(G, X, T, nx, nx);
    for (size_t i = 0, idx = 0; i < nx; ++i)
    {
        for (size_t j = 0; j <= i; ++j)
        {
            Pfg[idx++] = Pfp[i * nx + j] - G[i * nx + j];
        }
    }
    return AENL_OK;
}

/* The model's transposes for the forward pass: A_s' into w->At and C' into w->Ct, and whether
 * C is a 0/1 selection (w->c_select, w->sel). */
static void kf_prepare(ws_t *w, const aenl_em_model_t *m)
{
    const size_t nx = w->nx, nz = w->nz, nn = nx * nx;
    for (size_t s = 0; s < w->nm; ++s)
    {
        for (size_t i = 0; i < nx; ++i)
        {
            for (size_t j = 0; j < nx; ++j)
            {
                w->At[s * nn + j * nx + i] = m->A[s * nn + i * nx + j];
            }
        }
    }
    w->c_select = 1;
    for (size_t r = 0; r < nz; ++r)
    {
        size_t ones = 0, zeros = 0;
        for (size_t j = 0; j < nx; ++j)
        {
            const double c = m->C[r * nx + j];
            w->Ct[j * nz + r] = c;
            if (fabs(c - 1.0) <= 0.0) /* exactly 1: a structural 0/1 pattern */
            {
                ++ones;
                w->sel[r] = j;
            }
            else if (fabs(c) <= 0.0)
            {
                ++zeros;
            }
        }
        w->c_select &= (ones == 1 && zeros + 1 == nx) ? 1 : 0;
    }
}

/* The forward pass's steady-state tracking: slots used so far, whether the covariance has
 * converged in the current run of constant mode, and the last relative change of Pf. */
typedef struct
{
    size_t nslot;
    int steady;
    double d_prev;
} kf_steady_t;

/* Whether the filtered covariance of slot q (step k, mode s) has reached the steady state of
 * its run; d_prev carries the last relative change from step to step. */
static int kf_is_steady(const ws_t *w, size_t k, size_t s, size_t q, double *d_prev)
{
    const size_t nx = w->nx, nn = nx * nx;
    if (!(k > 0 && s == w->mode[k - 1] && w->obs[k] && w->obs[k - 1] && w->steady_tol > 0.0 &&
          !is_jump(w, k)))
    {
        *d_prev = HUGE_VAL;
        return 0;
    }
    const double *Pa = w->Pf + (q & 1u) * nn, *Pb = w->Pf + (w->slot[k - 1] & 1u) * nn;
    /* the diagonal first: far from convergence the full test is not worth it */
    double dd = 0.0, sd = 0.0;
    for (size_t i = 0; i < nn; i += nx + 1)
    {
        dd += (Pa[i] - Pb[i]) * (Pa[i] - Pb[i]);
        sd += Pa[i] * Pa[i];
    }
    if (dd > 1e-12 * sd)
    {
        *d_prev = HUGE_VAL;
        return 0;
    }
    const double d = rel_change(Pa, Pb, nn);
    const int steady = converged(d, *d_prev, w->steady_tol);
    *d_prev = d;
    return steady;
}

/* A new covariance slot for step k (mode s): prediction from the previous step's slot (P0 at
 * the start), measurement update when y_k is observed, then the steady-state test. */
static aenl_status_t kf_new_slot(ws_t *w, const aenl_em_model_t *m, size_t k, size_t s,
                                 kf_steady_t *ks)
{
    const size_t nn = w->nx * w->nx;
    double *Pp = w->tmp + 3 * nn; /* see cov_update */
    const size_t q = ks->nslot++;
    w->slot[k] = q;
    if (k == 0)
    {
        memcpy(Pp, m->P0, nn * sizeof(double));
    }
    else
    {
        const aenl_status_t st =
            cov_predict(w, m, s, w->slot[k - 1], q, Pp, is_jump(w, k) ? w->Pjump : NULL);
        if (st != AENL_OK)
        {
            return st;
        }
    }
    if (w->obs[k])
    {
        const aenl_status_t st = cov_update(w, m, q);
        if (st != AENL_OK)
        {
            return st;
        }
    }
    else
    {
        memcpy(w->Pf + (q & 1u) * nn, Pp, nn * sizeof(double));
    }
    ks->steady = kf_is_steady(w, k, s, q, &ks->d_prev);
    return AENL_OK;
}

/* The predicted mean of step k > 0 (mode s): xp = A xf_{k-1} + B u_{k-1} + b. */
static void kf_predict_mean(const ws_t *w, const aenl_em_model_t *m, size_t k, size_t s, double *xp)
{
    const size_t nx = w->nx, nn = nx * nx;
    const double *A = m->A + s * nn, *b = m->b + s * nx, *xo = w->xf + (k - 1) * nx;
    const size_t nu = w->nu;
    const double *B = m->B + s * nx * nu, *uo = nu > 0 ? w->u + (k - 1) * nu : NULL;
    for (size_t i = 0; i < nx; ++i)
    {
        double acc = b[i];
        const double *Ai = A + i * nx;
        for (size_t j = 0; j < nx; ++j)
        {
            acc += Ai[j] * xo[j];
        }
        for (size_t p = 0; p < nu; ++p)
        {
            acc += B[i * nu + p] * uo[p];
        }
        xp[i] = acc;
    }
}

/* The filtered mean of the observed step k, xf = xp + K (y_k - C xp), from its slot's gain;
 * returns the step's log-likelihood term (the innovation's quadratic form by a forward solve
 * with chol(S)). */
static double kf_update_mean(ws_t *w, const aenl_em_model_t *m, size_t k, const double *xp,
                             double *xf)
{
    const size_t nx = w->nx, nz = w->nz, nn = nx * nx;
    double *e = w->tmp + 10 * nn, *u = e + nz;
    const size_t q = w->slot[k] & 1u;
    const double *yk = w->y + k * nz, *K = w->K + q * nx * nz, *L = w->Ls + q * nz * nz;
    for (size_t r = 0; r < nz; ++r)
    {
        double acc = yk[r];
        for (size_t j = 0; j < nx; ++j)
        {
            acc -= m->C[r * nx + j] * xp[j];
        }
        e[r] = acc;
    }
    memcpy(u, e, nz * sizeof(double));
    aenl_dense_lower_solve(L, u, nz);
    double qf = 0.0;
    for (size_t i = 0; i < nz; ++i)
    {
        qf += u[i] * u[i];
    }
    for (size_t i = 0; i < nx; ++i)
    {
        double acc = xp[i];
        for (size_t r = 0; r < nz; ++r)
        {
            acc += K[i * nz + r] * e[r];
        }
        xf[i] = acc;
    }
    return -0.5 * (qf + w->logdet[q] + (double)nz * LOG_2PI);
}

/* Forward Kalman filter: fills xp, xf and the covariance slots; log-likelihood in *ll. */
static aenl_status_t kf_forward(ws_t *w, const aenl_em_model_t *m, double *ll)
{
    const size_t nx = w->nx, n = w->n;
    double total = 0.0;
    kf_steady_t ks = {0, 0, HUGE_VAL};
    kf_prepare(w, m);
    for (size_t k = 0; k < n; ++k)
    {
        double *xp = w->xp + k * nx, *xf = w->xf + k * nx;
        const size_t s = w->mode[k];
        if (k > 0 && ks.steady && s == w->mode[k - 1] && w->obs[k] && !is_jump(w, k))
        {
            w->slot[k] = w->slot[k - 1]; /* steady state: reuse everything */
        }
        else
        {
            const aenl_status_t st = kf_new_slot(w, m, k, s, &ks);
            if (st != AENL_OK)
            {
                return st;
            }
        }
        if (k == 0)
        {
            memcpy(xp, m->x0, nx * sizeof(double));
        }
        else
        {
            kf_predict_mean(w, m, k, s, xp);
        }
        if (!w->obs[k])
        {
            memcpy(xf, xp, nx * sizeof(double));
            continue;
        }
        total += kf_update_mean(w, m, k, xp, xf);
    }
    w->n_slots = ks.nslot;
    if (!isfinite(total))
    {
        return AENL_E_NUMERIC;
    }
    *ll = total;
    return AENL_OK;
}

/* S += a b' (lower triangle only when sym) */
static void add_outer(double *S, const double *a, const double *b, size_t n, int sym)
{
    for (size_t i = 0; i < n; ++i)
    {
        const double ai = a[i];
        const size_t jend = sym ? i + 1 : n;
        double *Si = S + i * n;
        for (size_t j = 0; j < jend; ++j)
        {
            Si[j] += ai * b[j];
        }
    }
}

/* E_k = Ps_k + x_{k|n} x_{k|n}' enters S11 (as the arrival of transition k-1 -> k, mode[k]),
 * S00 (as the start of k -> k+1, mode[k+1]) and Sxx (when y_k is observed). It is added once,
 * to the bucket of its (arrival mode, start mode, observed) triple; the buckets are spread into
 * the statistics after the pass. Lower triangles only. */
static size_t bucket_of(const ws_t *w, size_t k)
{
    const size_t nm = w->nm;
    /* a jump's transition enters no transition statistic: its ends count as "none" (nm) */
    const size_t a = (k >= 1 && !is_jump(w, k)) ? w->mode[k] : nm;
    const size_t b = (k + 1 < w->n && !is_jump(w, k + 1)) ? w->mode[k + 1] : nm;
    return (a * (nm + 1) + b) * 2 + (w->obs[k] ? 1u : 0u);
}

static void add_state_stats(ws_t *w, size_t k, const double *xs, const double *Ps)
{
    const size_t nx = w->nx, nz = w->nz, bk = bucket_of(w, k);
    double *E = w->bE + bk * nx * nx, *e = w->be + bk * nx;
    for (size_t i = 0; i < nx; ++i)
    {
        const double xi = xs[i];
        double *Ei = E + i * nx;
        const double *Pi = Ps + i * nx;
        for (size_t j = 0; j <= i; ++j)
        {
            Ei[j] += Pi[j] + xi * xs[j];
        }
        e[i] += xi;
    }
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
    w->ny += 1.0;
}

static void spread_buckets(ws_t *w)
{
    const size_t nx = w->nx, nn = nx * nx, nm = w->nm;
    for (size_t a = 0; a <= nm; ++a)
    {
        for (size_t b = 0; b <= nm; ++b)
        {
            for (size_t o = 0; o < 2; ++o)
            {
                const size_t bk = (a * (nm + 1) + b) * 2 + o;
                const double *E = w->bE + bk * nn, *e = w->be + bk * nx;
                for (size_t i = 0; i < nn; ++i)
                {
                    if (a < nm)
                    {
                        w->S11[a * nn + i] += E[i];
                    }
                    if (b < nm)
                    {
                        w->S00[b * nn + i] += E[i];
                    }
                    if (o)
                    {
                        w->Sxx[i] += E[i];
                    }
                }
                for (size_t i = 0; i < nx; ++i)
                {
                    if (a < nm)
                    {
                        w->s1[a * nx + i] += e[i];
                    }
                    if (b < nm)
                    {
                        w->s0[b * nx + i] += e[i];
                    }
                }
            }
        }
    }
    for (size_t s = 0; s < nm; ++s)
    {
        aenl_dense_mirror_lower(w->S11 + s * nn, nx);
        aenl_dense_mirror_lower(w->S00 + s * nn, nx);
    }
    aenl_dense_mirror_lower(w->Sxx, nx);
}

/* RTS smoother: xf becomes x_{k|n}; accumulates the sufficient statistics. The covariance
 * recursion Ps_k = Pfg_k + J_k Ps_{k+1} J_k' and the lag-one covariance Pc_k = Ps_{k+1} J_k'
 * (Cov(x_{k+1}, x_k | y)) are data-independent too: when two consecutive transitions share a
 * slot and Ps has converged (same test as the forward pass), they are reused. */
static aenl_status_t rts_backward(ws_t *w)
{
    const size_t nx = w->nx, nn = nx * nx, nm = w->nm, nz = w->nz, n = w->n;
    const size_t nb = (nm + 1) * (nm + 1) * 2;
    memset(w->S11, 0, nm * nn * sizeof(double));
    memset(w->S10, 0, nm * nn * sizeof(double));
    memset(w->S00, 0, nm * nn * sizeof(double));
    memset(w->s1, 0, nm * nx * sizeof(double));
    memset(w->s0, 0, nm * nx * sizeof(double));
    memset(w->cnt, 0, sizeof(w->cnt));
    memset(w->Syx, 0, nz * nx * sizeof(double));
    memset(w->Sxx, 0, nn * sizeof(double));
    memset(w->Syy, 0, nz * nz * sizeof(double));
    memset(w->bE, 0, nb * nn * sizeof(double));
    memset(w->be, 0, nb * nx * sizeof(double));
    w->ny = 0.0;
    const size_t nu = w->nu;
    if (nu > 0)
    {
        memset(w->S0u, 0, nm * nx * nu * sizeof(double));
        memset(w->S1u, 0, nm * nx * nu * sizeof(double));
        memset(w->Suu, 0, nm * nu * nu * sizeof(double));
        memset(w->su, 0, nm * nu * sizeof(double));
    }
    double *Ps1 = w->tmp, *Ps = Ps1 + nn, *Pc = Ps + nn, *dx = w->tmp + 10 * nn;
    memcpy(Ps1, w->Pf + (w->slot[n - 1] & 1u) * nn, nn * sizeof(double));
    add_state_stats(w, n - 1, w->xf + (n - 1) * nx, Ps1);
    int steady = 0;
    double d_prev = HUGE_VAL;
    for (size_t kk = n - 1; kk > 0; --kk)
    {
        const size_t k = kk - 1; /* smooth k from k+1 */
        const size_t s = w->mode[k + 1], q = w->slot[k + 1];
        const double *Jt = w->JP + q * w->slot_len;
        const int same = (k + 2 < n) && w->slot[k + 2] == q && w->mode[k + 2] == s;
        const double *Psk = Ps1; /* Ps_k: Ps_{k+1} in the steady state */
        if (!(steady && same))
        {
            steady = 0;
            Psk = Ps;
            aenl_dense_mul(Pc, Ps1, Jt, nx, nx, nx);   /* Pc = Ps_{k+1} J' */
            aenl_dense_mul_tn_sym(Ps, Jt, Pc, nx, nx); /* J Ps_{k+1} J' */
            const double *Pfg = Jt + nn;
            for (size_t i = 0, idx = 0; i < nx; ++i)
            {
                for (size_t j = 0; j < i; ++j)
                {
                    Ps[i * nx + j] += Pfg[idx];
                    Ps[j * nx + i] += Pfg[idx++];
                }
                Ps[i * nx + i] += Pfg[idx++];
            }
            if (same)
            {
                const double d = rel_change(Ps, Ps1, nn);
                steady = converged(d, d_prev, w->steady_tol);
                d_prev = d;
            }
            else
            {
                d_prev = HUGE_VAL;
            }
        }
        /* means: x_{k|n} = x_{k|k} + J (x_{k+1|n} - x_{k+1|k}) */
        double *xf = w->xf + k * nx;
        const double *xs1 = w->xf + (k + 1) * nx, *xp1 = w->xp + (k + 1) * nx;
        for (size_t i = 0; i < nx; ++i)
        {
            dx[i] = xs1[i] - xp1[i];
        }
        for (size_t r = 0; r < nx; ++r)
        {
            const double dr = dx[r];
            const double *Jr = Jt + r * nx;
            for (size_t i = 0; i < nx; ++i)
            {
                xf[i] += Jr[i] * dr;
            }
        }
        const int trans = !is_jump(w, k + 1); /* a jump's transition is left out */
        double *S10 = w->S10 + s * nn;
        for (size_t i = 0; trans && i < nx; ++i)
        {
            const double xi = xs1[i];
            double *Si = S10 + i * nx;
            const double *Pi = Pc + i * nx;
            for (size_t j = 0; j < nx; ++j)
            {
                Si[j] += Pi[j] + xi * xf[j];
            }
        }
        w->cnt[s] += trans ? 1.0 : 0.0;
        if (nu > 0 && trans) /* the inputs are known: only the means pair with them */
        {
            const double *uk = w->u + k * nu;
            double *S0u = w->S0u + s * nx * nu, *S1u = w->S1u + s * nx * nu;
            for (size_t i = 0; i < nx; ++i)
            {
                for (size_t p = 0; p < nu; ++p)
                {
                    S0u[i * nu + p] += xf[i] * uk[p];
                    S1u[i * nu + p] += xs1[i] * uk[p];
                }
            }
            for (size_t p = 0; p < nu; ++p)
            {
                for (size_t p2 = 0; p2 < nu; ++p2)
                {
                    w->Suu[s * nu * nu + p * nu + p2] += uk[p] * uk[p2];
                }
                w->su[s * nu + p] += uk[p];
            }
        }
        add_state_stats(w, k, xf, Psk);
        if (Psk == Ps)
        {
            double *t = Ps1; /* Ps becomes Ps_{k+1} of the next step */
            Ps1 = Ps;
            Ps = t;
        }
    }
    spread_buckets(w);
    return AENL_OK;
}

static aenl_status_t e_step(ws_t *w, const aenl_em_model_t *m, double *ll, int smooth)
{
    aenl_status_t st = kf_forward(w, m, ll);
    if (st == AENL_OK && smooth)
    {
        st = rts_backward(w);
    }
    return st;
}

/* ---- M-step -----------------------------------------------------------------------------------
 */

/* The M-step's buffers for one mode's transition, over the regressors of x_{k+1}: (x_k, u_k, 1),
 * the constant last (index nc), na in all. */
typedef struct
{
    size_t nc, na;
    double *G, *H;  /* normal equations: G = E[z z'] (na x na), H = E[x_{k+1} z'] (nx x na) */
    double *Gc, *X; /* solve copies: G, and the solution (na x nx) */
    double *W, *T;  /* W = [A B b] and W G (nx x na) */
} mstep_buf_t;

/* The normal equations of mode s's transition into b->G and b->H (G[nc][nc] = c, the count). */
static void mode_normal_equations(const ws_t *w, size_t s, double c, mstep_buf_t *bf)
{
    const size_t nx = w->nx, nn = nx * nx, nu = w->nu, nc = bf->nc, na = bf->na;
    double *G = bf->G, *H = bf->H;
    const double *S00 = w->S00 + s * nn, *S10 = w->S10 + s * nn;
    const double *s0 = w->s0 + s * nx, *s1 = w->s1 + s * nx;
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            G[i * na + j] = S00[i * nx + j];
            H[i * na + j] = S10[i * nx + j];
        }
        G[i * na + nc] = s0[i];
        G[nc * na + i] = s0[i];
        H[i * na + nc] = s1[i];
    }
    for (size_t p = 0; p < nu; ++p)
    {
        const double *S0u = w->S0u + s * nx * nu, *S1u = w->S1u + s * nx * nu;
        for (size_t i = 0; i < nx; ++i)
        {
            G[i * na + nx + p] = S0u[i * nu + p];
            G[(nx + p) * na + i] = S0u[i * nu + p];
            H[i * na + nx + p] = S1u[i * nu + p];
        }
        for (size_t q = 0; q < nu; ++q)
        {
            G[(nx + p) * na + nx + q] = w->Suu[s * nu * nu + p * nu + q];
        }
        G[(nx + p) * na + nc] = w->su[s * nu + p];
        G[nc * na + nx + p] = w->su[s * nu + p];
    }
    G[nc * na + nc] = c;
}

/* A, B and b of mode s together: W' = G^-1 H'. */
static aenl_status_t solve_transition(const ws_t *w, aenl_em_model_t *m, size_t s, mstep_buf_t *bf)
{
    const size_t nx = w->nx, nn = nx * nx, nu = w->nu, nc = bf->nc, na = bf->na;
    double *A = m->A + s * nn, *b = m->b + s * nx, *B = m->B + s * nx * nu, *X = bf->X;
    memcpy(bf->Gc, bf->G, na * na * sizeof(double));
    for (size_t i = 0; i < na; ++i) /* X = H' */
    {
        for (size_t j = 0; j < nx; ++j)
        {
            X[i * nx + j] = bf->H[j * na + i];
        }
    }
    if (aenl_dense_posv(bf->Gc, X, na, nx) != 0)
    {
        return AENL_E_NOT_PD;
    }
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            A[i * nx + j] = X[j * nx + i];
        }
        for (size_t p = 0; p < nu; ++p)
        {
            B[i * nu + p] = X[(nx + p) * nx + i];
        }
        b[i] = X[nc * nx + i];
    }
    return AENL_OK;
}

/* A of mode s with b frozen: S00 A' = (S10 - b s0')'. */
static aenl_status_t solve_A_given_b(const ws_t *w, aenl_em_model_t *m, size_t s, mstep_buf_t *bf)
{
    const size_t nx = w->nx, nn = nx * nx;
    const double *S00 = w->S00 + s * nn, *S10 = w->S10 + s * nn, *s0 = w->s0 + s * nx;
    double *A = m->A + s * nn, *Gc = bf->Gc, *X = bf->X;
    const double *b = m->b + s * nx;
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            Gc[i * nx + j] = S00[i * nx + j];
            X[i * nx + j] = S10[j * nx + i] - b[j] * s0[i];
        }
    }
    if (aenl_dense_posv(Gc, X, nx, nx) != 0)
    {
        return AENL_E_NOT_PD;
    }
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            A[i * nx + j] = X[j * nx + i];
        }
    }
    return AENL_OK;
}

/* b of mode s with A frozen: b = (s1 - A s0) / c. */
static void solve_b_given_A(const ws_t *w, aenl_em_model_t *m, size_t s, double c)
{
    const size_t nx = w->nx, nn = nx * nx;
    const double *A = m->A + s * nn, *s0 = w->s0 + s * nx, *s1 = w->s1 + s * nx;
    double *b = m->b + s * nx;
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

/* Q of mode s = (S11 - W H' - H W' + W G W') / c with W = [A B b], exact for any (possibly
 * frozen) W; its diagonal clipped at 0. */
static void solve_Q(const ws_t *w, aenl_em_model_t *m, size_t s, double c, mstep_buf_t *bf)
{
    const size_t nx = w->nx, nn = nx * nx, nu = w->nu, nc = bf->nc, na = bf->na;
    const double *A = m->A + s * nn, *b = m->b + s * nx, *B = m->B + s * nx * nu;
    const double *S11 = w->S11 + s * nn, *H = bf->H;
    double *Q = m->Q + s * nn, *W = bf->W, *T = bf->T;
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            W[i * na + j] = A[i * nx + j];
        }
        for (size_t p = 0; p < nu; ++p)
        {
            W[i * na + nx + p] = B[i * nu + p];
        }
        W[i * na + nc] = b[i];
    }
    aenl_dense_mul(T, W, bf->G, nx, na, na); /* W G */
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
    aenl_dense_symmetrise(Q, nx);
    for (size_t i = 0; i < nx; ++i)
    {
        if (Q[i * nx + i] < 0.0)
        {
            Q[i * nx + i] = 0.0;
        }
    }
}

/* The transitions of every mode with enough transitions (the others keep their parameters). */
static aenl_status_t m_step_modes(const ws_t *w, aenl_em_model_t *m, unsigned freeze,
                                  mstep_buf_t *bf)
{
    const int fa = (freeze & AENL_EM_FREEZE_A) != 0, fb = (freeze & AENL_EM_FREEZE_B) != 0;
    for (size_t s = 0; s < w->nm; ++s)
    {
        const double c = w->cnt[s];
        if (c < (double)(w->nx + 2))
        {
            continue; /* too few transitions: keep this mode's parameters */
        }
        mode_normal_equations(w, s, c, bf);
        aenl_status_t st = AENL_OK;
        if (!fa && !fb)
        {
            st = solve_transition(w, m, s, bf);
        }
        else if (fa && !fb)
        {
            solve_b_given_A(w, m, s, c);
        }
        else if (!fa && fb)
        {
            st = solve_A_given_b(w, m, s, bf);
        }
        if (st != AENL_OK)
        {
            return st;
        }
        if (!(freeze & AENL_EM_FREEZE_Q))
        {
            solve_Q(w, m, s, c, bf);
        }
    }
    return AENL_OK;
}

/* C = Syx Sxx^-1, solved as Sxx C' = Syx'. */
static aenl_status_t solve_C(const ws_t *w, aenl_em_model_t *m)
{
    const size_t nx = w->nx, nz = w->nz, nn = nx * nx;
    double *Sc = malloc(nn * sizeof(double)), *Ct = malloc(nx * nz * sizeof(double));
    if (!Sc || !Ct)
    {
        free(Sc);
        free(Ct);
        return AENL_E_DIM;
    }
    memcpy(Sc, w->Sxx, nn * sizeof(double));
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t r = 0; r < nz; ++r)
        {
            Ct[i * nz + r] = w->Syx[r * nx + i];
        }
    }
    const int info = aenl_dense_posv(Sc, Ct, nx, nz);
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
    return info != 0 ? AENL_E_NOT_PD : AENL_OK;
}

/* R = (Syy - C Syx' - Syx C' + C Sxx C') / n_obs. */
static void solve_R(const ws_t *w, aenl_em_model_t *m)
{
    const size_t nx = w->nx, nz = w->nz;
    for (size_t r = 0; r < nz; ++r)
    {
        for (size_t c2 = 0; c2 < nz; ++c2)
        {
            double v = w->Syy[r * nz + c2];
            for (size_t i = 0; i < nx; ++i)
            {
                v -=
                    m->C[r * nx + i] * w->Syx[c2 * nx + i] + w->Syx[r * nx + i] * m->C[c2 * nx + i];
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
    aenl_dense_symmetrise(m->R, nz);
}

static aenl_status_t m_step(ws_t *w, aenl_em_model_t *m, unsigned freeze)
{
    const size_t nx = w->nx, nc = nx + w->nu, na = nc + 1;
    mstep_buf_t bf;
    bf.nc = nc;
    bf.na = na;
    bf.G = malloc(na * na * sizeof(double));
    bf.H = malloc(nx * na * sizeof(double));
    bf.Gc = malloc(na * na * sizeof(double));
    bf.X = malloc(na * nx * sizeof(double));
    bf.W = malloc(nx * na * sizeof(double));
    bf.T = malloc(nx * na * sizeof(double));
    aenl_status_t st = AENL_E_DIM;
    if (bf.G && bf.H && bf.Gc && bf.X && bf.W && bf.T)
    {
        st = m_step_modes(w, m, freeze, &bf);
    }
    if (st == AENL_OK && w->ny > 0.0 && !(freeze & AENL_EM_FREEZE_C))
    {
        st = solve_C(w, m);
    }
    if (st == AENL_OK && w->ny > 0.0 && !(freeze & AENL_EM_FREEZE_R))
    {
        solve_R(w, m);
    }
    if (st == AENL_OK && !(freeze & AENL_EM_FREEZE_X0))
    {
        memcpy(m->x0, w->xf, nx * sizeof(double)); /* x_{0|n} */
    }
    free(bf.G);
    free(bf.H);
    free(bf.Gc);
    free(bf.X);
    free(bf.W);
    free(bf.T);
    return st;
}

/* ---- least-squares initialisation -------------------------------------------------------------
 */

static double y_at(const double *y, size_t nz, long k, size_t r)
{
    return y[(size_t)(k < 0 ? 0 : k) * nz + r];
}

/* One mode's regression of an initialisation, from its normal equations G X = H (G: na x na over
 * (nx regressors, 1), H: na x nout): at least 2 na transitions, a tiny ridge against collinear
 * regressors, then the solve in place of G (Cholesky when G is a Gram matrix, LU when it pairs
 * instruments with regressors). X receives the coefficients (na x nout). */
/* Regressors of the delay-embedding start at most: outputs, inputs' lags, the constant. */
#define LS_MAX_A (AENL_EM_MAX_X + AENL_EM_MAX_X * AENL_EM_MAX_U + 1)

static aenl_status_t mode_regression(double *G, const double *H, size_t na, size_t nout, double cnt,
                                     size_t s, int symmetric, double *X, aenl_err_t *err)
{
    const size_t nx = na - 1u; /* regressors before the constant */
    if (cnt < (double)(2 * na))
    {
        aenl_err_set(err,
                     "mode %zu (threshold interval %zu) has %.0f usable transitions; at least "
                     "%zu are needed for %zu states (move the thresholds or use fewer states)",
                     s, s, cnt, 2 * na, nx);
        return AENL_E_ARG;
    }
    double tr = 0.0;
    for (size_t i = 0; i < nx; ++i)
    {
        tr += G[i * na + i];
    }
    for (size_t i = 0; i < nx; ++i)
    {
        G[i * na + i] += 1e-10 * tr / (double)nx;
    }
    memcpy(X, H, na * nout * sizeof(double));
    int info;
    if (symmetric)
    {
        info = aenl_dense_posv(G, X, na, nout);
    }
    else
    {
        lapack_int piv[LS_MAX_A];
        info = LAPACKE_dgesv(LAPACK_ROW_MAJOR, (lapack_int)na, (lapack_int)nout, G, (lapack_int)na,
                             piv, X, (lapack_int)nout);
    }
    if (info != 0)
    {
        aenl_err_set(err, "mode %zu: the initial regression is singular", s);
        return AENL_E_NOT_PD;
    }
    return AENL_OK;
}

/* The delay-embedding start's record, dimensions and buffers. */
typedef struct
{
    const double *y; /* n x nz */
    size_t n, nz;
    const ws_t *w;
    size_t p, nu, nl;  /* embedding depth, inputs, the inputs' lags 0 .. p-1 (p nu) */
    size_t nx, nc, na; /* states, regressors before the constant, all regressors */
    int use_iv;
    double *G, *H;  /* normal equations of a mode: na x na, na x nz */
    double *z;      /* regressors of one transition (na) */
    double *res;    /* residual covariance of a mode (nz x nz) */
    double *pooled; /* per output: the residual sum of squares over every mode */
    double *X;      /* coefficients of a mode (na x nz) */
} ls_t;

/* Transition k -> k+1 into the normal equations, regressors z = (embedded outputs, the inputs'
 * lags, 1) and their instruments. 1 when it entered, 0 when a sample it needs is missing. */
static int ls_add_transition(const ls_t *ls, size_t k)
{
    const double *y = ls->y;
    const size_t nz = ls->nz, nx = ls->nx, nu = ls->nu, nl = ls->nl, nc = ls->nc, na = ls->na;
    double *z = ls->z;
    double zeta[LS_MAX_A];
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
        return 0;
    }
    for (size_t i = 0; i < nl; ++i) /* u_{k-j}, j = i / nu */
    {
        z[nx + i] = y_at(ls->w->u, nu, (long)k - (long)(i / nu), i % nu);
    }
    z[nc] = 1.0;
    /* instruments: the same embedding p samples earlier (independent of the noise in the
     * regressors and in y_{k+1}); plain least squares when use_iv is 0 */
    for (size_t i = 0; i < nx && ok; ++i)
    {
        zeta[i] = ls->use_iv ? y_at(y, nz, (long)k - (long)ls->p - (long)(i / nz), i % nz) : z[i];
        ok = isfinite(zeta[i]);
    }
    if (!ok)
    {
        return 0;
    }
    for (size_t i = 0; i < nl; ++i) /* the inputs are their own instruments */
    {
        zeta[nx + i] = z[nx + i];
    }
    zeta[nc] = 1.0;
    add_outer(ls->G, zeta, z, na, 0);
    for (size_t i = 0; i < na; ++i)
    {
        for (size_t r = 0; r < nz; ++r)
        {
            ls->H[i * nz + r] += zeta[i] * y[(k + 1) * nz + r];
        }
    }
    return 1;
}

/* The residual covariance of mode s's regression (A, b of m and the input coefficients of
 * ls->X), computed directly rather than as (Syy - X' H - H' X + X' G X)/cnt: into m->Q's
 * output block, and added to ls->pooled. */
static void ls_mode_noise(const ls_t *ls, aenl_em_model_t *m, size_t s, double cnt)
{
    const double *y = ls->y;
    const size_t nz = ls->nz, nx = ls->nx, nu = ls->nu, nl = ls->nl, nn = nx * nx;
    const double *A = m->A + s * nn, *b = m->b + s * nx, *X = ls->X;
    double *Q = m->Q + s * nn, *z = ls->z, *res = ls->res;
    memset(res, 0, nz * nz * sizeof(double));
    for (size_t k = 1; k + 1 < ls->n; ++k)
    {
        if (ls->w->mode[k + 1] != s)
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
            for (size_t i = 0; i < nl; ++i)
            {
                acc -= X[(nx + i) * nz + r] * y_at(ls->w->u, nu, (long)k - (long)(i / nu), i % nu);
            }
            e[r] = acc;
            ok = isfinite(acc);
        }
        if (!ok)
        {
            continue;
        }
        add_outer(res, e, e, nz, 0);
    }
    for (size_t r = 0; r < nz; ++r)
    {
        for (size_t c = 0; c < nz; ++c)
        {
            Q[r * nx + c] = res[r * nz + c] / cnt;
        }
        ls->pooled[r] += res[r * nz + r];
    }
}

/* Mode s's A and B in the observer canonical form (exact for any observable linear system,
 * noise in every block): row (j, r) holds the coefficients of lag j, and a shifted identity. */
static void ls_observer_form(const ls_t *ls, aenl_em_model_t *m, size_t s)
{
    const size_t nz = ls->nz, nx = ls->nx, nu = ls->nu;
    double *A = m->A + s * nx * nx, *B = m->B + s * nx * nu;
    const double *X = ls->X;
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
        for (size_t q = 0; q < nu; ++q) /* input lag j enters block j */
        {
            B[i * nu + q] = X[(nx + j * nu + q) * nz + r];
        }
    }
}

/* Mode s of the delay-embedding start: the regression of y_{k+1} on the embedding, its residual
 * covariance, then the observer canonical form. *cnt receives its transitions. */
static aenl_status_t ls_mode(const ls_t *ls, aenl_em_model_t *m, size_t s, double *cnt,
                             aenl_err_t *err)
{
    const size_t nz = ls->nz, nx = ls->nx, na = ls->na, nn = nx * nx;
    memset(ls->G, 0, na * na * sizeof(double));
    memset(ls->H, 0, na * nz * sizeof(double));
    *cnt = 0.0;
    for (size_t k = 1; k + 1 < ls->n; ++k)
    {
        if (ls->w->mode[k + 1] == s && ls_add_transition(ls, k))
        {
            *cnt += 1.0;
        }
    }
    const aenl_status_t st = mode_regression(ls->G, ls->H, na, nz, *cnt, s, 0, ls->X, err);
    if (st != AENL_OK)
    {
        return st;
    }
    double *A = m->A + s * nn, *b = m->b + s * nx;
    memset(A, 0, nn * sizeof(double));
    memset(b, 0, nx * sizeof(double));
    memset(m->Q + s * nn, 0, nn * sizeof(double));
    for (size_t r = 0; r < nz; ++r)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            A[r * nx + j] = ls->X[j * nz + r];
        }
        b[r] = ls->X[ls->nc * nz + r];
    }
    ls_mode_noise(ls, m, s, *cnt);
    ls_observer_form(ls, m, s);
    return AENL_OK;
}

/* The noise of the delay-embedding start from the pooled residuals: a small R and a large Q (EM
 * then leaves the noise to R), Q's lag blocks too. */
static void ls_noise(const ls_t *ls, aenl_em_model_t *m, double pooled_n)
{
    const size_t nz = ls->nz, nx = ls->nx, nn = nx * nx;
    double *pooled = ls->pooled;
    for (size_t r = 0; r < nz; ++r)
    {
        pooled[r] /= pooled_n;
    }
    memset(m->R, 0, nz * nz * sizeof(double));
    for (size_t r = 0; r < nz; ++r)
    {
        m->R[r * nz + r] = 0.05 * pooled[r];
    }
    for (size_t s = 0; s < m->n_modes; ++s)
    {
        for (size_t i = nz; i < nx; ++i)
        {
            m->Q[s * nn + i * nx + i] = pooled[i % nz];
        }
    }
}

/* x0 from the first samples, P0 from the channel variances (state i is output i % nz). */
static void ls_initial_state(const double *y, size_t n, size_t nz, aenl_em_model_t *m)
{
    const size_t nx = m->n_x;
    memset(m->P0, 0, nx * nx * sizeof(double));
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
}

static aenl_status_t ls_init(const double *y, size_t n, size_t nz, const ws_t *w,
                             aenl_em_model_t *m, int use_iv, aenl_err_t *err)
{
    ls_t ls;
    ls.y = y;
    ls.n = n;
    ls.nz = nz;
    ls.w = w;
    ls.p = (m->n_x + nz - 1) / nz; /* embedding depth */
    ls.nu = w->nu;
    ls.nl = ls.p * ls.nu;
    ls.nx = m->n_x;
    ls.nc = ls.nx + ls.nl;
    ls.na = ls.nc + 1;
    ls.use_iv = use_iv;
    const size_t na = ls.na, nx = ls.nx;
    ls.G = calloc(na * na, sizeof(double));
    ls.H = calloc(na * nz, sizeof(double));
    ls.z = calloc(na, sizeof(double));
    ls.res = calloc(nz * nz, sizeof(double));
    ls.pooled = calloc(nz, sizeof(double));
    ls.X = malloc(na * nz * sizeof(double));
    aenl_status_t st = AENL_OK;
    if (!ls.G || !ls.H || !ls.z || !ls.res || !ls.pooled || !ls.X)
    {
        aenl_err_set(err, "out of memory");
        st = AENL_E_DIM;
    }
    if (st == AENL_OK)
    {
        /* C = [I 0]; shift rows of every A */
        memset(m->C, 0, nz * nx * sizeof(double));
        for (size_t r = 0; r < nz; ++r)
        {
            m->C[r * nx + r] = 1.0;
        }
    }
    double pooled_n = 0.0;
    for (size_t s = 0; s < m->n_modes && st == AENL_OK; ++s)
    {
        double cnt = 0.0;
        st = ls_mode(&ls, m, s, &cnt, err);
        pooled_n += cnt;
    }
    if (st == AENL_OK)
    {
        ls_noise(&ls, m, pooled_n);
        ls_initial_state(y, n, nz, m);
    }
    free(ls.G);
    free(ls.H);
    free(ls.z);
    free(ls.res);
    free(ls.pooled);
    free(ls.X);
    return st;
}

/* ---- subspace initialisation ------------------------------------------------------------------
 * Covariance-driven stochastic subspace identification (Peeters & De Roeck 1999; Van Overschee
 * & De Moor 1996, the state as the projection of the future onto the past):
 *  1. sample output covariances Lambda_k = E[(y_{j+k} - ybar)(y_j - ybar)'], k = 0 .. 2i-1;
 *  2. with the past p_k = (y_{k-i}, ..., y_{k-1}) and the future f_k = (y_k, ..., y_{k+i-1})
 *     (mean removed), E[f p'] = O Ctrl (blocks Lambda_{i+r-c}); its SVD gives the
 *     observability matrix O = U_n S_n^1/2 and Ctrl = S_n^1/2 V_n'. White measurement noise
 *     enters only Lambda_0, so these are not biased by it;
 *  3. the state estimate from the past, x_k = Ctrl E[p p']^-1 p_k (the Kalman filter state of
 *     a filter started i samples earlier), in the basis where C = [I 0] (C = the first block
 *     row of O, completed by an orthonormal basis of its null space), shifted by ybar so that
 *     C x is the output;
 *  4. per mode, as in ls_init, the regression of x_{k+1} on (x_k, 1): A_s, b_s, and Q_s from its
 *     residuals (plus a small ridge); R half the covariance of y_k - C x_k.
 * For one mode this is consistent as i grows; with several modes the pooled projection only
 * approximates the state, and EM does the rest. No positive-realness condition is needed. */

/* Output covariances (mean removed, pairs with both samples observed): lam[k] for k < n_lag. */
static void output_covariances(const double *y, size_t n, size_t nz, const unsigned char *obs,
                               size_t n_lag, double *ybar, double *lam)
{
    double cnt = 0.0;
    memset(ybar, 0, nz * sizeof(double));
    for (size_t k = 0; k < n; ++k)
    {
        if (obs[k])
        {
            for (size_t r = 0; r < nz; ++r)
            {
                ybar[r] += y[k * nz + r];
            }
            cnt += 1.0;
        }
    }
    for (size_t r = 0; r < nz; ++r)
    {
        ybar[r] /= (cnt > 0.0 ? cnt : 1.0);
    }
    for (size_t lag = 0; lag < n_lag; ++lag)
    {
        double *L = lam + lag * nz * nz, c = 0.0;
        memset(L, 0, nz * nz * sizeof(double));
        for (size_t k = 0; k + lag < n; ++k)
        {
            if (!obs[k] || !obs[k + lag])
            {
                continue;
            }
            const double *a = y + (k + lag) * nz, *b = y + k * nz;
            for (size_t r = 0; r < nz; ++r)
            {
                for (size_t q = 0; q < nz; ++q)
                {
                    L[r * nz + q] += (a[r] - ybar[r]) * (b[q] - ybar[q]);
                }
            }
            c += 1.0;
        }
        for (size_t i = 0; i < nz * nz; ++i)
        {
            L[i] /= (c > 0.0 ? c : 1.0);
        }
    }
}

/* Steps 2-3 above: the state map Mt (nx x rows*nz, C = [I 0] basis), x_k = Mt p_k. 0: success. */
static int ssi_state_map(const double *lam, size_t nz, size_t nx, size_t rows, double *Mt)
{
    const size_t L = rows * nz, nn = nx * nx;
    int ok = 0;
    double *H = malloc(L * L * sizeof(double)), *U = malloc(L * L * sizeof(double));
    double *Vt = malloc(L * L * sizeof(double)), *sv = malloc(L * sizeof(double));
    double *sup = malloc(L * sizeof(double)), *Ct = malloc(L * nx * sizeof(double));
    double *T = malloc(nn * sizeof(double)), *Vc = malloc(nn * sizeof(double));
    double *C = malloc(nz * nx * sizeof(double));
    if (!H || !U || !Vt || !sv || !sup || !Ct || !T || !Vc || !C)
    {
        goto done;
    }
    /* E[f p'], block (r, c) = Lambda_{rows + r - c} */
    for (size_t r = 0; r < rows; ++r)
    {
        for (size_t c = 0; c < rows; ++c)
        {
            const double *B = lam + (rows + r - c) * nz * nz;
            for (size_t a = 0; a < nz; ++a)
            {
                for (size_t b = 0; b < nz; ++b)
                {
                    H[(r * nz + a) * L + c * nz + b] = B[a * nz + b];
                }
            }
        }
    }
    if (LAPACKE_dgesvd(LAPACK_ROW_MAJOR, 'S', 'S', (lapack_int)L, (lapack_int)L, H, (lapack_int)L,
                       sv, U, (lapack_int)L, Vt, (lapack_int)L, sup) != 0 ||
        !(sv[nx - 1] > 1e-12 * sv[0]))
    {
        goto done;
    }
    for (size_t c = 0; c < nx; ++c)
    {
        for (size_t a = 0; a < nz; ++a)
        {
            C[a * nx + c] = U[a * L + c] * sqrt(sv[c]); /* first block row of O */
        }
        for (size_t j = 0; j < L; ++j)
        {
            Ct[j * nx + c] = sqrt(sv[c]) * Vt[c * L + j]; /* Ctrl' */
        }
    }
    /* E[p p'], block (a, b) = Lambda_{a-b} (a >= b) or Lambda_{b-a}' ; then Ctrl' <- E[p p']^-1
     * Ctrl' (H is reused) */
    for (size_t a = 0; a < rows; ++a)
    {
        for (size_t b = 0; b < rows; ++b)
        {
            const double *B = lam + (a >= b ? a - b : b - a) * nz * nz;
            for (size_t r = 0; r < nz; ++r)
            {
                for (size_t q = 0; q < nz; ++q)
                {
                    H[(a * nz + r) * L + b * nz + q] = (a >= b) ? B[r * nz + q] : B[q * nz + r];
                }
            }
        }
    }
    if (aenl_dense_posv(H, Ct, L, nx) != 0)
    {
        goto done;
    }
    /* T = [C; null(C)'] from the full SVD of C: rows nz.. of Vc span the null space */
    memcpy(T, C, nz * nx * sizeof(double));
    if (LAPACKE_dgesvd(LAPACK_ROW_MAJOR, 'N', 'A', (lapack_int)nz, (lapack_int)nx, T,
                       (lapack_int)nx, sv, NULL, 1, Vc, (lapack_int)nx, sup) != 0 ||
        !(sv[nz - 1] > 1e-8 * sv[0]))
    {
        goto done;
    }
    memcpy(T, C, nz * nx * sizeof(double));
    memcpy(T + nz * nx, Vc + nz * nx, (nx - nz) * nx * sizeof(double));
    /* Mt = T Ctrl E[p p']^-1 = T (Ct)' */
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < L; ++j)
        {
            double acc = 0.0;
            for (size_t r = 0; r < nx; ++r)
            {
                acc += T[i * nx + r] * Ct[j * nx + r];
            }
            Mt[i * L + j] = acc;
        }
    }
    ok = 1;
done:
    free(H);
    free(U);
    free(Vt);
    free(sv);
    free(sup);
    free(Ct);
    free(T);
    free(Vc);
    free(C);
    return ok ? 0 : -1;
}

/* The subspace start's record and states: x_k (xs, n x nx) for k >= rows. */
typedef struct
{
    const double *y; /* n x nz */
    size_t n, nz, nx, rows;
    const ws_t *w;
    double *xs;
} ssi_t;

/* Step 3 above: the states x_k = ybar (first nz) + Mt p_k for k >= rows (a missing past sample
 * counts as the mean). */
static void ssi_states(const ssi_t *si, const double *Mt, const double *ybar)
{
    const size_t nz = si->nz, nx = si->nx, rows = si->rows, L = rows * nz;
    for (size_t k = rows; k < si->n; ++k)
    {
        for (size_t i = 0; i < nx; ++i)
        {
            double acc = (i < nz) ? ybar[i] : 0.0;
            const double *Mi = Mt + i * L;
            for (size_t q = 0; q < L; ++q) /* sample k - rows + q / nz, output q % nz */
            {
                const size_t j = k - rows + q / nz, r = q % nz;
                if (si->w->obs[j])
                {
                    acc += Mi[q] * (si->y[j * nz + r] - ybar[r]);
                }
            }
            si->xs[k * nx + i] = acc;
        }
    }
}

/* Step 4 above for mode s: A_s, b_s by the regression of x_{k+1} on (x_k, 1) (Gm, Hm, X:
 * scratch of na x na, na x nx, na x nx); *cnt receives its transitions. */
static aenl_status_t ssi_mode_regression(const ssi_t *si, aenl_em_model_t *m, size_t s, double *Gm,
                                         double *Hm, double *X, double *cnt, aenl_err_t *err)
{
    const size_t nx = si->nx, na = nx + 1, nn = nx * nx;
    const double *xs = si->xs;
    memset(Gm, 0, na * na * sizeof(double));
    memset(Hm, 0, na * nx * sizeof(double));
    double c = 0.0, z[AENL_EM_MAX_X + 1];
    for (size_t k = si->rows; k + 1 < si->n; ++k)
    {
        if (si->w->mode[k + 1] != s)
        {
            continue;
        }
        memcpy(z, xs + k * nx, nx * sizeof(double));
        z[nx] = 1.0;
        add_outer(Gm, z, z, na, 0);
        for (size_t i = 0; i < na; ++i)
        {
            for (size_t j = 0; j < nx; ++j)
            {
                Hm[i * nx + j] += z[i] * xs[(k + 1) * nx + j];
            }
        }
        c += 1.0;
    }
    *cnt = c;
    const aenl_status_t st = mode_regression(Gm, Hm, na, nx, c, s, 1, X, err);
    if (st != AENL_OK)
    {
        return st;
    }
    double *As = m->A + s * nn, *bs = m->b + s * nx;
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            As[i * nx + j] = X[j * nx + i];
        }
        bs[i] = X[nx * nx + i];
    }
    return AENL_OK;
}

/* Q_s from the residuals of mode s's regression (res: nx x nx scratch), with a small ridge so
 * that the filter starts positive definite. */
static void ssi_mode_noise(const ssi_t *si, aenl_em_model_t *m, size_t s, double cnt, double *res)
{
    const size_t nx = si->nx, nn = nx * nx;
    const double *As = m->A + s * nn, *bs = m->b + s * nx, *xs = si->xs;
    double *Qs = m->Q + s * nn;
    memset(res, 0, nn * sizeof(double));
    for (size_t k = si->rows; k + 1 < si->n; ++k)
    {
        if (si->w->mode[k + 1] != s)
        {
            continue;
        }
        double e[AENL_EM_MAX_X];
        for (size_t i = 0; i < nx; ++i)
        {
            double acc = xs[(k + 1) * nx + i] - bs[i];
            for (size_t j = 0; j < nx; ++j)
            {
                acc -= As[i * nx + j] * xs[k * nx + j];
            }
            e[i] = acc;
        }
        add_outer(res, e, e, nx, 0);
    }
    double trq = 0.0;
    for (size_t i = 0; i < nn; ++i)
    {
        Qs[i] = res[i] / cnt;
    }
    aenl_dense_symmetrise(Qs, nx);
    for (size_t i = 0; i < nx; ++i)
    {
        trq += Qs[i * nx + i];
    }
    for (size_t i = 0; i < nx; ++i)
    {
        Qs[i * nx + i] += 1e-3 * trq / (double)nx;
    }
}

/* R: half the covariance of y_k - C x_k (res: nx x nx scratch); x0, P0 from the states. */
static void ssi_output_noise_and_start(const ssi_t *si, aenl_em_model_t *m, double *res)
{
    const size_t nz = si->nz, nx = si->nx, nn = nx * nx, rows = si->rows, n = si->n;
    const double *y = si->y, *xs = si->xs;
    memset(res, 0, nn * sizeof(double));
    double ne = 0.0;
    for (size_t k = rows; k < n; ++k)
    {
        if (!si->w->obs[k])
        {
            continue;
        }
        double e[AENL_EM_MAX_X];
        for (size_t r = 0; r < nz; ++r)
        {
            e[r] = y[k * nz + r] - xs[k * nx + r];
        }
        add_outer(res, e, e, nz, 0);
        ne += 1.0;
    }
    for (size_t i = 0; i < nz * nz; ++i)
    {
        m->R[i] = 0.5 * res[i] / (ne > 0.0 ? ne : 1.0);
    }
    aenl_dense_symmetrise(m->R, nz);
    memset(m->P0, 0, nn * sizeof(double));
    for (size_t i = 0; i < nx; ++i)
    {
        double mean = 0.0, m2 = 0.0;
        for (size_t k = rows; k < n; ++k)
        {
            const double d = xs[k * nx + i] - mean;
            mean += d / (double)(k - rows + 1);
            m2 += d * (xs[k * nx + i] - mean);
        }
        m->x0[i] = (i < nz && si->w->obs[0]) ? y[i] : mean;
        m->P0[i * nx + i] = (m2 > 0.0) ? m2 / (double)(n - rows) : 1.0;
    }
}

/* The model m (C = [I 0]) from the subspace states (steps 1-4 above), rows block rows. */
static aenl_status_t ssi_init(const double *y, size_t n, size_t nz, const ws_t *w,
                              aenl_em_model_t *m, size_t rows, aenl_err_t *err)
{
    const size_t nx = m->n_x, na = nx + 1, nn = nx * nx, L = rows * nz;
    const size_t n_lag = 2 * rows;
    if (nz == 0 || L <= nx || 4 * n_lag > n)
    {
        aenl_err_set(err, "subspace start: %zu block rows do not fit %zu states and %zu samples",
                     rows, nx, n);
        return AENL_E_ARG;
    }
    double *lam = malloc(n_lag * nz * nz * sizeof(double)), ybar[AENL_EM_MAX_X];
    double *Mt = malloc(nx * L * sizeof(double));
    const ssi_t si = {y, n, nz, nx, rows, w, malloc(n * nx * sizeof(double))};
    double *Gm = malloc(na * na * sizeof(double)), *Hm = malloc(na * nx * sizeof(double));
    double *res = malloc(nn * sizeof(double)), *X = malloc(na * nx * sizeof(double));
    aenl_status_t st = AENL_OK;
    if (!lam || !Mt || !si.xs || !Gm || !Hm || !res || !X)
    {
        aenl_err_set(err, "out of memory");
        st = AENL_E_DIM;
    }
    if (st == AENL_OK)
    {
        output_covariances(y, n, nz, w->obs, n_lag, ybar, lam);
        if (ssi_state_map(lam, nz, nx, rows, Mt) != 0)
        {
            aenl_err_set(err, "subspace start: rank-deficient covariances with %zu block rows",
                         rows);
            st = AENL_E_NOT_PD;
        }
    }
    if (st == AENL_OK)
    {
        ssi_states(&si, Mt, ybar);
        memset(m->C, 0, nz * nx * sizeof(double));
        for (size_t r = 0; r < nz; ++r)
        {
            m->C[r * nx + r] = 1.0;
        }
    }
    for (size_t s = 0; s < m->n_modes && st == AENL_OK; ++s)
    {
        double cnt = 0.0;
        st = ssi_mode_regression(&si, m, s, Gm, Hm, X, &cnt, err);
        if (st == AENL_OK)
        {
            ssi_mode_noise(&si, m, s, cnt, res);
        }
    }
    if (st == AENL_OK)
    {
        ssi_output_noise_and_start(&si, m, res);
    }
    free(lam);
    free(Mt);
    free(si.xs);
    free(Gm);
    free(Hm);
    free(res);
    free(X);
    return st;
}

/* The starting model (opts.init): the delay-embedding regression, or the subspace start with
 * opts.ssi_rows block rows (default 4 (n_x / n_z + 2), at most an eighth of the record). */
static aenl_status_t start_model(const double *y, size_t n, size_t nz, const ws_t *w,
                                 aenl_em_model_t *m, const aenl_em_opts_t *o, aenl_err_t *err)
{
    /* the subspace start is output-only: with inputs, the regression that takes their lags */
    if (o->init != AENL_EM_INIT_SUBSPACE || w->nu > 0)
    {
        return ls_init(y, n, nz, w, m, !o->no_iv, err);
    }
    size_t rows = (o->ssi_rows > 0) ? o->ssi_rows : 4 * (m->n_x / nz + 2);
    if (o->ssi_rows == 0 && 8 * rows > n)
    {
        rows = n / 8;
    }
    return ssi_init(y, n, nz, w, m, rows, err);
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

/* ---- EM runs: plain, and accelerated by SQUAREM -------------------------------------------------
 * Plain EM converges linearly, at the rate of the fraction of missing information; on lightly
 * excited, heavily damped modes (the plunge mode of the airfoil) that fraction is close to one
 * and thousands of iterations are needed to reach the likelihood maximum. SQUAREM (Varadhan &
 * Roland 2008, scheme S3) extrapolates two EM steps: with r = F(t0) - t0 and
 * v = F(F(t0)) - 2 F(t0) + t0, the point t' = t0 - 2 a r + a^2 v (a = -|r|/|v| <= -1) is tried;
 * it is accepted when its log-likelihood is at least that of F(t0) and its covariances are
 * valid, else a moves halfway towards -1, where t' = F(F(t0)) (a plain EM step). An accepted
 * point is followed by one EM step (stabilisation). So every logged value is the likelihood of
 * an accepted parameter set and the logged sequence never decreases, as with plain EM. */

/* Shared tail of an E-step at the current parameters: log it, test convergence. 1: stop. */
static int log_ll(double ll, double *loglik, size_t *it, double *prev, double tol)
{
    if (loglik != NULL)
    {
        loglik[*it] = ll;
    }
    const int conv = tol > 0.0 && *it > 0 && (ll - *prev) < tol * fabs(ll);
    *prev = ll;
    ++*it;
    return conv;
}

/* Run up to n_iter plain EM iterations; loglik (may be NULL) receives one value per iteration. */
static aenl_status_t em_run_plain(ws_t *w, aenl_em_model_t *m, const aenl_em_opts_t *o,
                                  size_t n_iter, double *loglik, size_t *done_iter)
{
    size_t it = 0;
    double prev = -INFINITY;
    aenl_status_t st = AENL_OK;
    while (it < n_iter)
    {
        double ll;
        st = e_step(w, m, &ll, 1);
        if (st != AENL_OK || log_ll(ll, loglik, &it, &prev, o->tol))
        {
            break;
        }
        st = m_step(w, m, o->freeze);
        if (st != AENL_OK)
        {
            break;
        }
    }
    *done_iter = it;
    return st;
}

/* The parameter arrays that EM estimates, as (pointer, length) pairs; P0 is fixed. */
static size_t param_arrays(const aenl_em_model_t *m, double **p, size_t *len)
{
    const size_t nx = m->n_x, nz = m->n_z, nm = m->n_modes;
    p[0] = m->A;
    len[0] = nm * nx * nx;
    p[1] = m->b;
    len[1] = nm * nx;
    p[2] = m->Q;
    len[2] = nm * nx * nx;
    p[3] = m->C;
    len[3] = nz * nx;
    p[4] = m->R;
    len[4] = nz * nz;
    p[5] = m->x0;
    len[5] = nx;
    p[6] = m->B;
    len[6] = nm * nx * m->n_u;
    return 7;
}

/* |r|^2 and |v|^2 of the SQUAREM step from t0, t1 = F(t0), t2 = F(t1). */
static void squarem_norms(const aenl_em_model_t *t0, const aenl_em_model_t *t1,
                          const aenl_em_model_t *t2, double *rr, double *vv)
{
    double *p0[7], *p1[7], *p2[7];
    size_t len[7];
    const size_t na = param_arrays(t0, p0, len);
    (void)param_arrays(t1, p1, len);
    (void)param_arrays(t2, p2, len);
    double sr = 0.0, sv = 0.0;
    for (size_t a = 0; a < na; ++a)
    {
        for (size_t i = 0; i < len[a]; ++i)
        {
            const double r = p1[a][i] - p0[a][i], v = p2[a][i] - 2.0 * p1[a][i] + p0[a][i];
            sr += r * r;
            sv += v * v;
        }
    }
    *rr = sr;
    *vv = sv;
}

/* out = t0 - 2 a r + a^2 v (thresholds, P0 and sizes of t0). */
static void squarem_point(aenl_em_model_t *out, const aenl_em_model_t *t0,
                          const aenl_em_model_t *t1, const aenl_em_model_t *t2, double a)
{
    double *p0[7], *p1[7], *p2[7], *po[7];
    size_t len[7];
    const size_t na = param_arrays(t0, p0, len);
    (void)param_arrays(t1, p1, len);
    (void)param_arrays(t2, p2, len);
    (void)param_arrays(out, po, len);
    model_assign(out, t0);
    for (size_t k = 0; k < na; ++k)
    {
        for (size_t i = 0; i < len[k]; ++i)
        {
            const double r = p1[k][i] - p0[k][i], v = p2[k][i] - 2.0 * p1[k][i] + p0[k][i];
            po[k][i] = p0[k][i] - 2.0 * a * r + a * a * v;
        }
    }
    aenl_dense_symmetrise(out->R, out->n_z);
    for (size_t s = 0; s < out->n_modes; ++s)
    {
        aenl_dense_symmetrise(out->Q + s * out->n_x * out->n_x, out->n_x);
    }
}

/* An extrapolated point is a model only if R is positive definite and every Q_s positive
 * semi-definite (to a relative 1e-12 of its trace). scratch: n_x^2 entries. */
static int covariances_valid(const aenl_em_model_t *m, double *scratch)
{
    const size_t nx = m->n_x, nz = m->n_z, nn = nx * nx;
    memcpy(scratch, m->R, nz * nz * sizeof(double));
    if (aenl_dense_chol(scratch, nz, NULL) != 0)
    {
        return 0;
    }
    for (size_t s = 0; s < m->n_modes; ++s)
    {
        const double *Q = m->Q + s * nn;
        double tr = 0.0;
        for (size_t i = 0; i < nx; ++i)
        {
            tr += Q[i * nx + i];
        }
        memcpy(scratch, Q, nn * sizeof(double));
        for (size_t i = 0; i < nx; ++i)
        {
            scratch[i * nx + i] += 1e-12 * tr + 1e-300;
        }
        if (aenl_dense_chol(scratch, nx, NULL) != 0)
        {
            return 0;
        }
    }
    return 1;
}

/* SQUAREM cycles (see above) up to n_iter logged E-steps; m is the start and the result. t0, t1,
 * t2: scratch models of m's sizes. A rejected extrapolation costs one forward pass (not logged). */
static aenl_status_t em_run_squarem(ws_t *w, aenl_em_model_t *m, const aenl_em_opts_t *o,
                                    size_t n_iter, double *loglik, size_t *done_iter,
                                    aenl_em_model_t *t0, aenl_em_model_t *t1, aenl_em_model_t *t2)
{
    size_t it = 0;
    double prev = -INFINITY, ll = 0.0;
    aenl_status_t st = AENL_OK;
    double *scratch = malloc(m->n_x * m->n_x * sizeof(double));
    if (scratch == NULL)
    {
        *done_iter = 0;
        return AENL_E_DIM;
    }
    model_assign(t0, m);
    while (it < n_iter)
    {
        /* t1 = F(t0) */
        model_assign(m, t0);
        st = e_step(w, t0, &ll, 1);
        if (st != AENL_OK || log_ll(ll, loglik, &it, &prev, o->tol))
        {
            break;
        }
        model_assign(t1, t0);
        if ((st = m_step(w, t1, o->freeze)) != AENL_OK)
        {
            break;
        }
        model_assign(m, t1);
        if (it >= n_iter)
        {
            break;
        }
        /* t2 = F(t1) */
        double ll1 = 0.0;
        st = e_step(w, t1, &ll1, 1);
        if (st != AENL_OK || log_ll(ll1, loglik, &it, &prev, o->tol))
        {
            break;
        }
        model_assign(t2, t1);
        if ((st = m_step(w, t2, o->freeze)) != AENL_OK)
        {
            break;
        }
        model_assign(m, t2);
        if (it >= n_iter)
        {
            break;
        }
        /* extrapolate; back off towards a = -1 (m = t2) until the likelihood is not below t1's */
        double rr, vv, llp = -INFINITY;
        squarem_norms(t0, t1, t2, &rr, &vv);
        double a = (vv > 0.0) ? -sqrt(rr / vv) : -1.0;
        for (;;)
        {
            const int plain = !(a < -1.0 - 1e-3); /* a = -1: m = t2, a plain EM step */
            if (plain)
            {
                model_assign(m, t2);
            }
            else
            {
                squarem_point(m, t0, t1, t2, a);
            }
            const aenl_status_t sf =
                (plain || covariances_valid(m, scratch)) ? kf_forward(w, m, &llp) : AENL_E_NOT_PD;
            if (sf == AENL_OK && (llp >= ll1 || plain))
            {
                break; /* in a plain EM step a loss can only be rounding */
            }
            if (plain)
            {
                st = sf;
                break;
            }
            a = 0.5 * (a - 1.0);
        }
        if (st != AENL_OK)
        {
            break;
        }
        st = rts_backward(w); /* the statistics of the accepted point */
        if (st != AENL_OK || log_ll(llp, loglik, &it, &prev, o->tol))
        {
            break;
        }
        if ((st = m_step(w, m, o->freeze)) != AENL_OK) /* stabilisation: t0 of the next cycle */
        {
            break;
        }
        model_assign(t0, m);
    }
    free(scratch);
    *done_iter = it;
    return st;
}

/* Run up to n_iter EM iterations (SQUAREM unless opts.plain); loglik (may be NULL) receives one
 * value per iteration; *ll_final that of the returned model. */
static aenl_status_t em_run(ws_t *w, aenl_em_model_t *m, const aenl_em_opts_t *o, size_t n_iter,
                            double *loglik, size_t *done_iter, double *ll_final)
{
    aenl_status_t st;
    if (o->plain_em)
    {
        st = em_run_plain(w, m, o, n_iter, loglik, done_iter);
    }
    else
    {
        /* three scratch models; a copy that fails leaves its model zeroed (safe to free) */
        aenl_em_model_t t0, t1, t2;
        aenl_err_t err;
        memset(&t0, 0, sizeof(t0));
        memset(&t1, 0, sizeof(t1));
        memset(&t2, 0, sizeof(t2));
        st = aenl_em_model_copy(&t0, m, &err);
        if (st == AENL_OK)
        {
            st = aenl_em_model_copy(&t1, m, &err);
        }
        if (st == AENL_OK)
        {
            st = aenl_em_model_copy(&t2, m, &err);
        }
        if (st == AENL_OK)
        {
            st = em_run_squarem(w, m, o, n_iter, loglik, done_iter, &t0, &t1, &t2);
        }
        else
        {
            *done_iter = 0;
        }
        aenl_em_model_free(&t0);
        aenl_em_model_free(&t1);
        aenl_em_model_free(&t2);
    }
    if (st == AENL_OK && ll_final != NULL)
    {
        st = e_step(w, m, ll_final, 0);
    }
    return st;
}

/* Jumps come with the covariance they add. */
static aenl_status_t check_jumps(const aenl_em_opts_t *o, aenl_err_t *err)
{
    if (o->jump != NULL && o->P_jump == NULL)
    {
        aenl_err_set(err, "jumps need their covariance (P_jump)");
        return AENL_E_ARG;
    }
    return AENL_OK;
}

/* What the E-step takes from the options: the steady-state tolerance and the jumps. */
static void ws_take_opts(ws_t *w, const aenl_em_opts_t *o)
{
    w->steady_tol = o->steady_tol;
    w->jump = o->jump;
    w->Pjump = o->P_jump;
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
    if (o->n_u > AENL_EM_MAX_U || (o->n_u > 0 && o->u == NULL))
    {
        aenl_err_set(err, "inputs: at most %d, with their values (got %zu)", AENL_EM_MAX_U, o->n_u);
        return AENL_E_ARG;
    }
    if (o->n_u > 0 && (o->freeze & (AENL_EM_FREEZE_A | AENL_EM_FREEZE_B)) != 0)
    {
        aenl_err_set(err, "inputs are estimated with A and b: neither may be frozen");
        return AENL_E_ARG;
    }
    if (check_jumps(o, err) != AENL_OK)
    {
        return AENL_E_ARG;
    }
    for (size_t k = 0; k < n * o->n_u; ++k)
    {
        if (!isfinite(o->u[k]))
        {
            aenl_err_set(err, "input %zu, sample %zu: not a finite number (an input has no gaps)",
                         k % o->n_u + 1u, k / o->n_u + 1u);
            return AENL_E_ARG;
        }
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
    /* the candidates are compared after the same number of plain EM iterations: SQUAREM's
     * progress in a few iterations varies from candidate to candidate */
    aenl_em_opts_t po = *o;
    po.plain_em = 1;
    o = &po;
    set_modes(w, best.thresholds, u, 1);
    st = em_run(w, &best, o, o->refine_iter, NULL, &done, &best_ll);
    for (int round = 0; round < 3 && st == AENL_OK; ++round)
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
        step *= 0.5; /* halved after each round (no continue/break skips it) */
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
    st = aenl_em_model_set_inputs(m, opts->n_u, err);
    if (st != AENL_OK)
    {
        aenl_em_model_free(m);
        return st;
    }
    m->switch_channel = opts->switch_channel;
    m->dt = opts->dt;
    memcpy(m->thresholds, opts->thresholds, opts->n_thresholds * sizeof(double));
    ws_t w;
    st = ws_alloc(&w, y, n, nx, n_z, nm, err);
    if (st == AENL_OK)
    {
        st = ws_set_inputs(&w, opts->u, opts->n_u, err);
    }
    ws_take_opts(&w, opts);
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
        st = start_model(y, n, n_z, &w, m, opts, err);
    }
    if (st == AENL_OK && !opts->modes_from_data)
    {
        st = modes_from_smoother(&w, m, u);
        if (st == AENL_OK)
        {
            st = start_model(y, n, n_z, &w, m, opts,
                             err); /* re-fit the start with the cleaner modes */
        }
    }
    if (st == AENL_OK && opts->refine && nm > 1)
    {
        if (opts->modes_from_data)
        {
            for (size_t k = 0; k < w.n; ++k) /* w.n == n: the bound refine_thresholds reads to */
            {
                u[k] = y[k * n_z + opts->switch_channel];
            }
        }
        st = refine_thresholds(&w, m, opts, u, err);
        if (st == AENL_OK)
        {
            set_modes(&w, m->thresholds, u, 1);
            st = start_model(y, n, n_z, &w, m, opts, err);
        }
    }
    if (st == AENL_OK)
    {
        for (size_t k = 1; k < n; ++k)
        {
            res->mode_count[w.mode[k]]++;
        }
        st = em_run(&w, m, opts, opts->max_iter, res->loglik, &res->n_iter, &res->loglik_final);
        res->n_cov_steps = w.n_slots;
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
    if (check_jumps(opts, err) != AENL_OK)
    {
        return AENL_E_ARG;
    }
    if (opts->n_u != m->n_u || (m->n_u > 0 && opts->u == NULL))
    {
        aenl_err_set(err, "the model has %zu inputs, the options give %zu", m->n_u, opts->n_u);
        return AENL_E_ARG;
    }
    ws_t w;
    aenl_status_t st = ws_alloc(&w, y, n, m->n_x, m->n_z, m->n_modes, err);
    if (st == AENL_OK)
    {
        st = ws_set_inputs(&w, opts->u, opts->n_u, err);
        if (st != AENL_OK)
        {
            ws_free(&w);
        }
    }
    if (st != AENL_OK)
    {
        return st;
    }
    ws_take_opts(&w, opts);
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

/* The functions below read or write models without inputs (the INI, the C header, the
 * onboard filter and the simulator have no input term). */
static int has_inputs(const aenl_em_model_t *m, const char *what, aenl_err_t *err)
{
    if (m != NULL && m->n_u > 0)
    {
        aenl_err_set(err, "%s: the model has known inputs, which %s does not take", what, what);
        return 1;
    }
    return 0;
}

aenl_status_t aenl_em_loglik(const aenl_em_model_t *m, const double *y, size_t n, const double *u,
                             double *ll, aenl_err_t *err)
{
    if (has_inputs(m, "aenl_em_loglik", err))
    {
        return AENL_E_ARG;
    }
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

/* The mode as an AR(2) process x_k = a1 x_{k-1} + a2 x_{k-2} + e_k, a1 = 2 r cos(theta),
 * a2 = -r^2, r = exp(-zeta w_n dt), theta = w_d dt: its least-squares estimate, efficient for
 * Gaussian e, has the asymptotic covariance [[1 - a2^2, -a1 (1 + a2)], [., 1 - a2^2]] / n, which
 * the delta method carries to theta and to sigma dt = -ln(r), then to f = theta / (2 pi dt)
 * and zeta = S / sqrt(S^2 + theta^2) (S = sigma dt). */
int aenl_em_mode_floor(double f, double zeta, double dt, double n, double *sf, double *sz)
{
    const double two_pi = 6.283185307179586477;
    const double th = two_pi * f * dt;
    if (!(f > 0.0) || !(zeta > 0.0) || !(zeta < 1.0) || !(dt > 0.0) || !(n >= 3.0) ||
        !(th < 0.5 * two_pi) || sf == NULL || sz == NULL)
    {
        return 0;
    }
    const double S = th * zeta / sqrt(1.0 - zeta * zeta); /* sigma dt, sigma = zeta w_n */
    const double r = exp(-S);
    const double a1 = 2.0 * r * cos(th);
    const double a2 = -r * r;
    const double m11 = (1.0 - a2 * a2) / n;
    const double m12 = -a1 * (1.0 + a2) / n;
    /* theta = acos(a1 / (2 sqrt(-a2))), S = -ln(-a2) / 2: their gradients in (a1, a2) */
    const double g1 = -1.0 / (2.0 * r * sin(th));
    const double g2 = -cos(th) / (2.0 * r * r * sin(th));
    const double h2 = 0.5 / (r * r);
    const double v_th = g1 * g1 * m11 + 2.0 * g1 * g2 * m12 + g2 * g2 * m11;
    const double v_s = h2 * h2 * m11;
    const double c_ts = g1 * h2 * m12 + g2 * h2 * m11;
    const double q = S * S + th * th;
    const double dz_ds = th * th / (q * sqrt(q));
    const double dz_dt = -S * th / (q * sqrt(q));
    const double v_z = dz_ds * dz_ds * v_s + 2.0 * dz_ds * dz_dt * c_ts + dz_dt * dz_dt * v_th;
    *sf = sqrt(v_th) / th;
    *sz = sqrt(v_z) / (S / sqrt(q));
    return 1;
}

/* A square root L (L L' = S) of the symmetric positive semidefinite n x n matrix S, from its
 * eigen-decomposition: a fitted noise covariance may be singular to rounding, where a Cholesky
 * factor fails; eigenvalues below zero by rounding count as zero. 0, or -1 on failure. */
static int psd_sqrt(const double *S, size_t n, double *L)
{
    double V[AENL_EM_MAX_X * AENL_EM_MAX_X];
    double w[AENL_EM_MAX_X];
    memcpy(V, S, n * n * sizeof(double));
    if (LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'V', 'U', (lapack_int)n, V, (lapack_int)n, w) != 0)
    {
        return -1;
    }
    for (size_t i = 0; i < n; ++i)
    {
        for (size_t j = 0; j < n; ++j)
        {
            L[i * n + j] = V[i * n + j] * sqrt(fmax(w[j], 0.0));
        }
    }
    return 0;
}

/* v += L z, z standard normal draws of g (L n x n). */
static void add_noise(const double *L, size_t n, aenl_rng_t *g, double *v)
{
    double z[AENL_EM_MAX_X];
    for (size_t j = 0; j < n; ++j)
    {
        z[j] = aenl_rng_gauss(g);
    }
    for (size_t i = 0; i < n; ++i)
    {
        double acc = 0.0;
        for (size_t j = 0; j < n; ++j)
        {
            acc += L[i * n + j] * z[j];
        }
        v[i] += acc;
    }
}

/* The noise covariances' square roots for a noisy simulation: Lq (n_modes x nx x nx), Lr, Lp. */
static aenl_status_t noise_roots(const aenl_em_model_t *m, double *Lq, double *Lr, double *Lp,
                                 aenl_err_t *err)
{
    const size_t nx = m->n_x;
    int bad = psd_sqrt(m->R, m->n_z, Lr) != 0 || psd_sqrt(m->P0, nx, Lp) != 0;
    for (size_t s = 0; s < m->n_modes && !bad; ++s)
    {
        bad = psd_sqrt(m->Q + s * nx * nx, nx, Lq + s * nx * nx) != 0;
    }
    if (bad)
    {
        aenl_err_set(err, "simulate: a noise covariance has no square root");
        return AENL_E_NUMERIC;
    }
    return AENL_OK;
}

aenl_status_t aenl_em_simulate(const aenl_em_model_t *m, const double *x_init, size_t n,
                               double *y_out, aenl_err_t *err)
{
    return aenl_em_simulate_noisy(m, x_init, n, NULL, y_out, err);
}

aenl_status_t aenl_em_simulate_noisy(const aenl_em_model_t *m, const double *x_init, size_t n,
                                     aenl_rng_t *rng, double *y_out, aenl_err_t *err)
{
    if (has_inputs(m, "aenl_em_simulate", err))
    {
        return AENL_E_ARG;
    }
    if (m == NULL || y_out == NULL)
    {
        aenl_err_set(err, "simulate: NULL argument");
        return AENL_E_ARG;
    }
    const size_t nx = m->n_x, nz = m->n_z;
    double *Lq = NULL;
    double Lr[AENL_EM_MAX_X * AENL_EM_MAX_X];
    double Lp[AENL_EM_MAX_X * AENL_EM_MAX_X];
    if (rng != NULL)
    {
        Lq = (double *)malloc(m->n_modes * nx * nx * sizeof(double));
        if (Lq == NULL)
        {
            aenl_err_set(err, "out of memory");
            return AENL_E_DIM;
        }
        const aenl_status_t st = noise_roots(m, Lq, Lr, Lp, err);
        if (st != AENL_OK)
        {
            free(Lq);
            return st;
        }
    }
    double x[AENL_EM_MAX_X], xn[AENL_EM_MAX_X];
    memcpy(x, x_init ? x_init : m->x0, nx * sizeof(double));
    if (rng != NULL && x_init == NULL)
    {
        add_noise(Lp, nx, rng, x); /* x_0 ~ N(x0, P0) */
    }
    aenl_status_t st = AENL_OK;
    for (size_t k = 0; k < n && st == AENL_OK; ++k)
    {
        double *y = y_out + k * nz;
        for (size_t r = 0; r < nz; ++r)
        {
            double acc = 0.0;
            for (size_t j = 0; j < nx; ++j)
            {
                acc += m->C[r * nx + j] * x[j];
            }
            y[r] = acc;
        }
        /* the mode follows the motion, not its measurement */
        const size_t s = mode_of(m->thresholds, m->n_modes, y[m->switch_channel]);
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
        if (rng != NULL)
        {
            add_noise(Lr, nz, rng, y);
            add_noise(Lq + s * nx * nx, nx, rng, xn);
        }
        memcpy(x, xn, nx * sizeof(double));
        if (!isfinite(x[0]))
        {
            aenl_err_set(err, "simulation diverged at sample %zu", k);
            st = AENL_E_NUMERIC;
        }
    }
    free(Lq);
    return st;
}

/* ---- export -----------------------------------------------------------------------------------
 */

aenl_status_t aenl_em_to_skf(const aenl_em_model_t *m, aenl_skf_model_t *out, aenl_err_t *err)
{
    if (has_inputs(m, "aenl_em_to_skf", err))
    {
        return AENL_E_ARG;
    }
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
    if (has_inputs(m, "aenl_em_write_ini", err))
    {
        return AENL_E_ARG;
    }
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
    /* "%.9g" of a float is at most 15 characters ("-1.17549435e-38"): cannot truncate */
    (void)snprintf(buf, sizeof(buf), "%.9g", (double)(float)v);
    fprintf(fp, "AENL_R(%s%s)", buf, strpbrk(buf, ".eE") == NULL ? ".0" : "");
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
    if (has_inputs(m, "aenl_em_write_c_header", err))
    {
        return AENL_E_ARG;
    }
    if (m == NULL || name == NULL || path == NULL)
    {
        aenl_err_set(err, "NULL argument");
        return AENL_E_ARG;
    }
    if (name[0] == '\0')
    {
        aenl_err_set(err, "the model name is empty (it must be a C identifier)");
        return AENL_E_ARG;
    }
    for (const char *p = name; *p; ++p)
    {
        const int ok = (*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || *p == '_' ||
                       (p != name && *p >= '0' && *p <= '9');
        if (!ok)
        {
            aenl_err_set(err, "'%s' is not a C identifier", name);
            return AENL_E_ARG;
        }
    }
    /* the header declares `static const aenl_skf_model_t NAME`: a keyword does not compile */
    static const char *const k_keywords[] = {
        "auto",     "break",  "case",   "char",     "const",     "continue", "default",  "do",
        "double",   "else",   "enum",   "extern",   "float",     "for",      "goto",     "if",
        "inline",   "int",    "long",   "register", "restrict",  "return",   "short",    "signed",
        "sizeof",   "static", "struct", "switch",   "typedef",   "union",    "unsigned", "void",
        "volatile", "while",  "_Bool",  "_Complex", "_Imaginary"};
    for (size_t i = 0; i < sizeof(k_keywords) / sizeof(k_keywords[0]); ++i)
    {
        if (strcmp(name, k_keywords[i]) == 0)
        {
            aenl_err_set(err, "'%s' is a C keyword, not a usable name", name);
            return AENL_E_ARG;
        }
    }
    char guard[160];
    const int glen = snprintf(guard, sizeof(guard), "AENL_MODEL_%s_H", name);
    if (glen < 0 || (size_t)glen >= sizeof(guard))
    {
        /* a truncated guard could collide with another model's header */
        aenl_err_set(err, "model name '%s' is too long (at most %zu characters)", name,
                     sizeof(guard) - sizeof("AENL_MODEL__H"));
        return AENL_E_ARG;
    }
    for (char *p = guard; *p; ++p)
    {
        if (*p >= 'a' && *p <= 'z')
        {
            *p = (char)(*p - 'a' + 'A'); /* 'A'..'Z': fits a char */
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
