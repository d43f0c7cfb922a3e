/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_skf.c
 * @brief Switching Kalman filter; model and conventions in aenl_skf.h.
 *
 * All-or-nothing: the estimate is double-buffered (x[cur], P[cur]). A step writes the new
 * estimate into the other half and flips `cur` only when everything succeeded, so a rejected step
 * (non-PD innovation covariance, non-finite result) leaves the previous estimate in place.
 *
 * Update (Joseph form, valid for any gain, keeps P symmetric PSD in float32):
 *     e = z - C x_p,  S = C P_p C' + R = L L',  K' = S^-1 C P_p,
 *     x = x_p + K e,  P = (I - K C) P_p (I - K C)' + K R K',  NIS = |L^-1 e|^2,
 *     log N(e; 0, S) = -(NIS + 2 sum log L_ii + n log 2 pi) / 2.
 * IMM: Blom & Bar-Shalom (1988), mixing - mode-matched filtering - probability update.
 */
#include <string.h>

#include "aenl/aenl_skf.h"

#include "aenl_linalg.h"

#define LDX         ((uint32_t)AENL_SKF_MAX_X)
#define LDZ         ((uint32_t)AENL_SKF_MAX_Z)
#define LOG_2PI     AENL_R(1.8378770664093453)
#define SYM_REL_TOL (AENL_R(64.0) * AENL_REAL_EPS)

static inline uint32_t sat_inc(uint32_t v)
{
    return v == UINT32_MAX ? v : v + 1u;
}

uint16_t aenl_skf_mode_of(const aenl_skf_model_t *model, aenl_real_t value, int rising)
{
    if (model == NULL)
    {
        return 0u;
    }
    const aenl_real_t *thr = rising ? model->thr_rising : model->thr_falling;
    uint32_t s = 0u;
    for (uint32_t i = 0; i + 1u < model->n_modes; ++i)
    {
        if (value >= thr[i])
        {
            s = (uint32_t)(i + 1u);
        }
    }
    return (uint16_t)s;
}

/* ---- model validation ------------------------------------------------------------------------ */

/* Flags of matrix_ok: the matrix must be symmetric, and its diagonal >= 0. */
#define CHK_SYM 1u
#define CHK_PSD 2u

/* 1 when the n x m block is finite and passes the checks of flags. */
static int matrix_ok(const aenl_real_t *a, uint32_t lda, uint32_t n, uint32_t m, unsigned flags)
{
    if (!aenl_la_all_finite(a, lda, n, m) ||
        ((flags & CHK_SYM) && !aenl_la_is_symmetric(a, lda, n, SYM_REL_TOL)))
    {
        return 0;
    }
    for (uint32_t i = 0; (flags & CHK_PSD) && i < n; ++i)
    {
        if (a[(size_t)i * lda + i] < AENL_R(0.0))
        {
            return 0;
        }
    }
    return 1;
}

static aenl_status_t check_thresholds(const aenl_skf_model_t *m)
{
    for (uint32_t i = 0; i + 1u < m->n_modes; ++i)
    {
        if (!aenl_is_finite(m->thr_rising[i]) || !aenl_is_finite(m->thr_falling[i]))
        {
            return AENL_E_ARG;
        }
        if (i > 0u && (!(m->thr_rising[i] > m->thr_rising[i - 1u]) ||
                       !(m->thr_falling[i] > m->thr_falling[i - 1u])))
        {
            return AENL_E_ARG;
        }
    }
    return AENL_OK;
}

static aenl_status_t check_imm(const aenl_skf_model_t *m)
{
    if (m->imm > 1u)
    {
        return AENL_E_ARG;
    }
    if (m->imm == 0u)
    {
        return AENL_OK;
    }
    for (uint32_t i = 0; i < m->n_modes; ++i)
    {
        aenl_real_t s = AENL_R(0.0);
        for (uint32_t j = 0; j < m->n_modes; ++j)
        {
            const aenl_real_t p = m->trans[i][j];
            if (!aenl_is_finite(p) || p < AENL_R(0.0) || p > AENL_R(1.0))
            {
                return AENL_E_ARG;
            }
            s += p;
        }
        if (aenl_fabs(s - AENL_R(1.0)) > AENL_R(1e-4))
        {
            return AENL_E_ARG;
        }
    }
    return AENL_OK;
}

static aenl_status_t check_model(const aenl_skf_model_t *m)
{
    if (m->n_x == 0u || m->n_z == 0u || m->n_modes == 0u)
    {
        return AENL_E_ARG;
    }
    if (m->n_x > AENL_SKF_MAX_X || m->n_z > AENL_SKF_MAX_Z || m->n_modes > AENL_SKF_MAX_MODES)
    {
        return AENL_E_DIM;
    }
    if (m->switch_state >= m->n_x || (m->dir_state >= m->n_x && m->dir_state != AENL_SKF_DIR_DIFF))
    {
        return AENL_E_ARG;
    }
    if (check_thresholds(m) != AENL_OK || check_imm(m) != AENL_OK)
    {
        return AENL_E_ARG;
    }
    const uint32_t nx = m->n_x;
    for (uint32_t s = 0; s < m->n_modes; ++s)
    {
        if (!matrix_ok(&m->A[s][0][0], LDX, nx, nx, 0u) || !matrix_ok(m->b[s], LDX, 1u, nx, 0u) ||
            !matrix_ok(&m->Q[s][0][0], LDX, nx, nx, CHK_SYM | CHK_PSD))
        {
            return AENL_E_ARG;
        }
    }
    if (!matrix_ok(&m->C[0][0], LDX, m->n_z, nx, 0u) ||
        !matrix_ok(&m->R[0][0], LDZ, m->n_z, m->n_z, CHK_SYM) ||
        !matrix_ok(m->x0, LDX, 1u, nx, 0u) ||
        !matrix_ok(&m->P0[0][0], LDX, nx, nx, CHK_SYM | CHK_PSD))
    {
        return AENL_E_ARG;
    }
    aenl_real_t r[AENL_SKF_MAX_Z][AENL_SKF_MAX_Z]; /* <= 128 B */
    memcpy(r, m->R, sizeof(r));
    if (aenl_la_chol(&r[0][0], LDZ, m->n_z) != AENL_OK)
    {
        return AENL_E_ARG;
    }
    return AENL_OK;
}

/* ---- init / reset -----------------------------------------------------------------------------
 */

aenl_status_t aenl_skf_init(aenl_skf_t *f, const aenl_skf_model_t *model)
{
    if (f == NULL || model == NULL)
    {
        return AENL_E_ARG;
    }
    const aenl_status_t st = check_model(model);
    if (st != AENL_OK)
    {
        return st;
    }
    memset(f, 0, sizeof(*f));
    f->model = model;
    f->n_x = model->n_x;
    f->n_z = model->n_z;
    f->n_modes = model->n_modes;
    aenl_skf_reset(f);
    return AENL_OK;
}

void aenl_skf_reset(aenl_skf_t *f)
{
    if (f == NULL || f->model == NULL)
    {
        return;
    }
    const aenl_skf_model_t *m = f->model;
    f->cur = 0u;
    f->dir = 1;
    f->x_prev_s = m->x0[m->switch_state];
    const uint32_t n_est = m->imm ? f->n_modes : 1u;
    for (uint32_t s = 0; s < n_est; ++s)
    {
        memcpy(f->x[0][s], m->x0, sizeof(f->x[0][s]));
        memcpy(f->P[0][s], m->P0, sizeof(f->P[0][s]));
    }
    memset(f->mode_prob, 0, sizeof(f->mode_prob));
    if (m->imm)
    {
        for (uint32_t s = 0; s < f->n_modes; ++s)
        {
            f->mode_prob[s] = AENL_R(1.0) / (aenl_real_t)f->n_modes;
        }
        f->mode = 0u;
    }
    else
    {
        f->mode = aenl_skf_mode_of(m, m->x0[m->switch_state], 1);
        f->mode_prob[f->mode] = AENL_R(1.0);
    }
    f->n_steps = 0u;
    f->n_missing = 0u;
    f->n_not_pd = 0u;
    f->n_numeric = 0u;
    f->nis_sum = AENL_R(0.0);
    f->n_nis = 0u;
}

/* ---- one mode-matched Kalman step -------------------------------------------------------------
 */

/* P_p = T A' + Q into pp, T = A P (rows LDX apart): T A' is symmetric, so its upper triangle,
 * mirrored, with Q's symmetric part. */
static inline void covariance_predicted(aenl_real_t *pp, const aenl_real_t *t, const aenl_real_t *a,
                                        const aenl_real_t *q, uint32_t nx)
{
    for (uint32_t i = 0; i < nx; ++i)
    {
        for (uint32_t j = i; j < nx; ++j)
        {
            aenl_real_t acc = AENL_R(0.0);
            for (uint32_t k = 0; k < nx; ++k)
            {
                acc += t[(size_t)i * LDX + k] * a[(size_t)j * LDX + k];
            }
            acc += AENL_R(0.5) * (q[(size_t)i * LDX + j] + q[(size_t)j * LDX + i]);
            pp[(size_t)i * LDX + j] = acc;
            pp[(size_t)j * LDX + i] = acc;
        }
    }
}

/* x_p = A x + b, P_p = A P A' + Q into work.xp / work.Pp. */
static inline void predict(aenl_skf_t *f, uint32_t s, const aenl_real_t *x, const aenl_real_t *P,
                           uint32_t nx)
{
    const aenl_skf_model_t *m = f->model;
    aenl_skf_work_t *w = &f->work;
    aenl_la_mv(w->xp, &m->A[s][0][0], LDX, x, nx, nx);
    for (uint32_t i = 0; i < nx; ++i)
    {
        w->xp[i] += m->b[s][i];
    }
#if AENL_LA_INLINE
    if (nx == LDX)
    {
        /* A and P on the stack, where the compiler knows that nothing else writes them and
         * keeps their rows in registers across the unrolled loops (the same sums in the same
         * order); their frame is 512 B in float32 at the default capacity */
        aenl_real_t a[LDX][LDX], p[LDX][LDX];
        memcpy(a, m->A[s], sizeof(a));
        memcpy(p, P, sizeof(p));
        aenl_la_mul(&w->T[0][0], LDX, &a[0][0], LDX, &p[0][0], LDX, LDX, LDX, LDX);
        covariance_predicted(&w->Pp[0][0], &w->T[0][0], &a[0][0], &m->Q[s][0][0], LDX);
        return;
    }
#endif
    aenl_la_mul(&w->T[0][0], LDX, &m->A[s][0][0], LDX, P, LDX, nx, nx, nx);
    covariance_predicted(&w->Pp[0][0], &w->T[0][0], &m->A[s][0][0], &m->Q[s][0][0], nx);
}

/*
 * Update work.xp / work.Pp with the used components (work.idx[0..n_used)) of z into x_out,
 * P_out (which must not alias the work buffers, each other or the model: restrict lets the
 * compiler keep the work rows in registers while it writes P_out). Returns NOT_PD / NUMERIC
 * without touching anything outside the work area and the outputs.
 */
static inline aenl_status_t update(aenl_skf_t *f, const aenl_real_t *z, uint32_t nu,
                                   aenl_real_t *restrict x_out, aenl_real_t *restrict P_out,
                                   aenl_real_t *nis, aenl_real_t *ll, uint32_t nx)
{
    const aenl_skf_model_t *m = f->model;
    aenl_skf_work_t *w = &f->work;
    *nis = AENL_R(0.0);
    *ll = AENL_R(0.0);
    if (nu == 0u)
    {
        memcpy(x_out, w->xp, sizeof(w->xp));
        memcpy(P_out, w->Pp, sizeof(w->Pp));
        return AENL_OK;
    }
    for (uint32_t r = 0; r < nu; ++r)
    {
        memcpy(w->Cu[r], m->C[w->idx[r]], sizeof(w->Cu[r]));
    }
    aenl_la_mv(w->e, &w->Cu[0][0], LDX, w->xp, nu, nx);
    for (uint32_t r = 0; r < nu; ++r)
    {
        w->e[r] = z[w->idx[r]] - w->e[r];
    }
    aenl_la_mul(&w->CP[0][0], LDX, &w->Cu[0][0], LDX, &w->Pp[0][0], LDX, nu, nx, nx);
    aenl_la_mul_nt(&w->S[0][0], LDZ, &w->CP[0][0], LDX, &w->Cu[0][0], LDX, nu, nx, nu);
    aenl_real_t ru[AENL_SKF_MAX_Z][AENL_SKF_MAX_Z]; /* R of the used components */
    for (uint32_t r = 0; r < nu; ++r)
    {
        for (uint32_t c = 0; c < nu; ++c)
        {
            ru[r][c] = m->R[w->idx[r]][w->idx[c]];
            w->S[r][c] += ru[r][c];
        }
    }
    aenl_la_symmetrise(&w->S[0][0], LDZ, nu);
    if (aenl_la_chol(&w->S[0][0], LDZ, nu) != AENL_OK)
    {
        return AENL_E_NOT_PD;
    }
    /* NIS and log-likelihood from the whitened innovation u = L^-1 e; then e <- S^-1 e. */
    aenl_real_t u[AENL_SKF_MAX_Z];
    memcpy(u, w->e, sizeof(u));
    aenl_la_solve_lower(&w->S[0][0], LDZ, nu, u, 1u, 1u);
    aenl_real_t q = AENL_R(0.0), logdet = AENL_R(0.0);
    for (uint32_t r = 0; r < nu; ++r)
    {
        q += u[r] * u[r];
        logdet += aenl_log(w->S[r][r]);
    }
    aenl_la_solve_lower_t(&w->S[0][0], LDZ, nu, u, 1u, 1u);
    /* K' = S^-1 C P_p (in CP); x = x_p + P_p C' S^-1 e = x_p + (C P_p)' u. */
    memcpy(x_out, w->xp, sizeof(w->xp));
    aenl_la_gemm(x_out, 1u, &w->CP[0][0], 1u, LDX, u, 1u, 0u, nx, nu, 1u, 1);
    /* C P_p into the first rows of T (T is free), then K' = S^-1 C P_p in CP. */
    memcpy(w->T, w->CP, nu * sizeof(w->T[0]));
    aenl_la_chol_solve(&w->S[0][0], LDZ, nu, &w->CP[0][0], LDX, nx);
    /* Joseph form (I - K C) P_p (I - K C)' + K R K', with I - K C applied as a rank-nu
     * correction instead of an nx x nx product: first P_out = (I - K C) P_p = P_p - K (C P_p). */
    memcpy(P_out, w->Pp, sizeof(w->Pp));
    aenl_la_gemm(P_out, LDX, &w->CP[0][0], 1u, LDX, &w->T[0][0], LDX, 1u, nx, nu, nx, -1);
    /* V = P_out C' (nx x nu) into T's first columns: P_out (I - K C)' = P_out - V K'. */
    aenl_la_mul_nt(&w->T[0][0], LDX, P_out, LDX, &w->Cu[0][0], LDX, nx, nx, nu);
    /* R_u K' into Cu (C rows no longer needed) */
    aenl_la_mul(&w->Cu[0][0], LDX, &ru[0][0], LDZ, &w->CP[0][0], LDX, nu, nu, nx);
    /* P_out - V K' + K (R_u K'), a row at a time: each entry still adds its nu terms in ascending
     * r, but the innermost loop runs along rows (vectorised on the host, K and V read once per
     * row on the Cortex-M4F). */
    for (uint32_t i = 0; i < nx; ++i)
    {
        aenl_real_t *pi = &P_out[(size_t)i * LDX];
        for (uint32_t r = 0; r < nu; ++r)
        {
            const aenl_real_t kir = w->CP[r][i], vir = w->T[i][r];
            for (uint32_t j = 0; j < nx; ++j)
            {
                pi[j] += kir * w->Cu[r][j] - vir * w->CP[r][j];
            }
        }
    }
    aenl_la_symmetrise(P_out, LDX, nx);
    *nis = q;
    *ll = AENL_R(-0.5) * (q + AENL_R(2.0) * logdet + (aenl_real_t)nu * LOG_2PI);
    return AENL_OK;
}

static aenl_status_t check_result(const aenl_real_t *x, const aenl_real_t *P, uint32_t nx)
{
    if (!aenl_la_all_finite(x, LDX, 1u, nx) || !aenl_la_all_finite(P, LDX, nx, nx))
    {
        return AENL_E_NUMERIC;
    }
    return AENL_OK;
}

/* ---- threshold switching ----------------------------------------------------------------------
 */

static int16_t next_direction(const aenl_skf_t *f, const aenl_real_t *x)
{
    const aenl_skf_model_t *m = f->model;
    const aenl_real_t v =
        (m->dir_state == AENL_SKF_DIR_DIFF) ? x[m->switch_state] - f->x_prev_s : x[m->dir_state];
    if (v > AENL_R(0.0))
    {
        return 1;
    }
    if (v < AENL_R(0.0))
    {
        return -1;
    }
    return f->dir;
}

/* Predict estimate e of the next half from (x, P) in mode s and update it with z: NOT_PD from the
 * update, NUMERIC for a non-finite result. */
static aenl_status_t mode_step(aenl_skf_t *f, uint32_t s, uint32_t e, const aenl_real_t *x,
                               const aenl_real_t *P, const aenl_real_t *z, uint32_t nu,
                               aenl_real_t *nis, aenl_real_t *ll)
{
    const uint32_t nxt = 1u - f->cur;
#if AENL_LA_INLINE
    /* A speed-optimising build: with as many states as the capacity, the same steps with loops of
     * constant length, which the compiler unrolls and vectorises (the same sums in the same
     * order, so the same results): 17 % fewer instructions on the host. */
    if (f->n_x == LDX)
    {
        predict(f, s, x, P, LDX);
        const aenl_status_t st = update(f, z, nu, f->x[nxt][e], &f->P[nxt][e][0][0], nis, ll, LDX);
        return (st == AENL_OK) ? check_result(f->x[nxt][e], &f->P[nxt][e][0][0], LDX) : st;
    }
#endif
    predict(f, s, x, P, f->n_x);
    const aenl_status_t st = update(f, z, nu, f->x[nxt][e], &f->P[nxt][e][0][0], nis, ll, f->n_x);
    return (st == AENL_OK) ? check_result(f->x[nxt][e], &f->P[nxt][e][0][0], f->n_x) : st;
}

static aenl_status_t step_threshold(aenl_skf_t *f, const aenl_real_t *z, uint32_t nu,
                                    aenl_skf_out_t *out)
{
    const uint32_t cur = f->cur;
    const aenl_real_t *x = f->x[cur][0];
    const int16_t dir = next_direction(f, x);
    const uint32_t s = aenl_skf_mode_of(f->model, x[f->model->switch_state], dir > 0);
    aenl_real_t nis, ll;
    aenl_status_t st = mode_step(f, s, 0u, x, &f->P[cur][0][0][0], z, nu, &nis, &ll);
    /* A finite estimate can still come with an innovation whose square overflows. */
    const aenl_real_t fit[2] = {nis, ll};
    if (st == AENL_OK && !aenl_la_all_finite(fit, 0u, 1u, 2u))
    {
        st = AENL_E_NUMERIC;
    }
    if (st != AENL_OK)
    {
        return st;
    }
    f->x_prev_s = x[f->model->switch_state];
    f->dir = dir;
    f->mode = (uint16_t)s;
    memset(f->mode_prob, 0, sizeof(f->mode_prob));
    f->mode_prob[s] = AENL_R(1.0);
    f->cur = (uint16_t)(1u - cur);
    out->mode = (uint16_t)s;
    out->mode_threshold = (uint16_t)s;
    out->nis = nis;
    out->log_lik = ll;
    return AENL_OK;
}

/* ---- IMM --------------------------------------------------------------------------------------
 */

/* Moment-matched mixture of the estimates of half h with weights w[j]: x_out = sum w_j x_j and,
 * when P_out (rows ldp apart) is not NULL, P_out = sum w_j (P_j + (x_j - x_out)(x_j - x_out)')
 * over the modes with w_j > 0 (0 times an overflowing spread would be NaN). */
static void mixture(const aenl_skf_t *f, uint32_t h, const aenl_real_t *w, aenl_real_t *x_out,
                    aenl_real_t *P_out, size_t ldp)
{
    const uint32_t nx = f->n_x, nm = f->n_modes;
    for (uint32_t r = 0; r < nx; ++r)
    {
        aenl_real_t s = AENL_R(0.0);
        for (uint32_t j = 0; j < nm; ++j)
        {
            s += w[j] * f->x[h][j][r];
        }
        x_out[r] = s;
    }
    for (uint32_t r = 0; P_out != NULL && r < nx; ++r)
    {
        for (uint32_t c = 0; c < nx; ++c)
        {
            aenl_real_t s = AENL_R(0.0);
            for (uint32_t j = 0; j < nm; ++j)
            {
                const aenl_real_t *xj = f->x[h][j];
                if (w[j] > AENL_R(0.0))
                {
                    s += w[j] * (f->P[h][j][r][c] + (xj[r] - x_out[r]) * (xj[c] - x_out[c]));
                }
            }
            P_out[r * ldp + c] = s;
        }
    }
}

/* Mixed initial condition of mode j into x[nxt][j], P[nxt][j] (cbar_j in work.cbar). */
static void imm_mix(aenl_skf_t *f, uint32_t j)
{
    const aenl_skf_model_t *m = f->model;
    const uint32_t cur = f->cur, nxt = (uint32_t)(1u - cur);
    const aenl_real_t cj = f->work.cbar[j];
    aenl_real_t wi[AENL_SKF_MAX_MODES]; /* mixing weights of the modes i into j */
    for (uint32_t i = 0; i < f->n_modes; ++i)
    {
        wi[i] = (cj > AENL_R(0.0)) ? m->trans[i][j] * f->mode_prob[i] / cj
                                   : ((i == j) ? AENL_R(1.0) : AENL_R(0.0));
    }
    memset(f->x[nxt][j], 0, sizeof(f->x[nxt][j]));
    memset(f->P[nxt][j], 0, sizeof(f->P[nxt][j]));
    mixture(f, cur, wi, f->x[nxt][j], &f->P[nxt][j][0][0], LDX);
}

/* The moment-matched mixture of the estimates in half h with probabilities prob stays finite:
 * every spread (x_j - xbar)^2 + P_j of a mode with prob_j > 0 is finite (then so is every term
 * of aenl_skf_estimate's covariance, a convex combination of them). */
static int imm_mixture_finite(const aenl_skf_t *f, uint32_t h, const aenl_real_t *prob)
{
    const uint32_t nx = f->n_x, nm = f->n_modes;
    for (uint32_t r = 0; r < nx; ++r)
    {
        aenl_real_t xbar = AENL_R(0.0);
        for (uint32_t j = 0; j < nm; ++j)
        {
            xbar += prob[j] * f->x[h][j][r];
        }
        for (uint32_t j = 0; j < nm; ++j)
        {
            const aenl_real_t d = f->x[h][j][r] - xbar;
            if (prob[j] > AENL_R(0.0) && !aenl_is_finite(d * d + f->P[h][j][r][r]))
            {
                return 0;
            }
        }
    }
    return 1;
}

static aenl_status_t step_imm(aenl_skf_t *f, const aenl_real_t *z, uint32_t nu, aenl_skf_out_t *out)
{
    const aenl_skf_model_t *m = f->model;
    const uint32_t nxt = (uint32_t)(1u - f->cur), nm = f->n_modes;
    aenl_skf_work_t *w = &f->work;
    for (uint32_t j = 0; j < nm; ++j)
    {
        aenl_real_t c = AENL_R(0.0);
        for (uint32_t i = 0; i < nm; ++i)
        {
            c += m->trans[i][j] * f->mode_prob[i];
        }
        w->cbar[j] = c;
    }
    aenl_real_t nis_j[AENL_SKF_MAX_MODES] = {AENL_R(0.0)};
    for (uint32_t j = 0; j < nm; ++j)
    {
        imm_mix(f, j);
        const aenl_status_t st =
            mode_step(f, j, j, f->x[nxt][j], &f->P[nxt][j][0][0], z, nu, &nis_j[j], &w->lik[j]);
        if (st != AENL_OK)
        {
            return st;
        }
    }
    /* mode probabilities: mu_j proportional to cbar_j e^lik_j, by log-sum-exp */
    aenl_real_t lmax = -AENL_REAL_MAX;
    for (uint32_t j = 0; j < nm; ++j)
    {
        w->lik[j] = (w->cbar[j] > AENL_R(0.0)) ? w->lik[j] + aenl_log(w->cbar[j]) : -AENL_REAL_MAX;
        lmax = (w->lik[j] > lmax) ? w->lik[j] : lmax;
    }
    aenl_real_t sum = AENL_R(0.0);
    for (uint32_t j = 0; j < nm; ++j)
    {
        w->cbar[j] = (w->lik[j] > -AENL_REAL_MAX) ? aenl_exp(w->lik[j] - lmax) : AENL_R(0.0);
        sum += w->cbar[j];
    }
    const aenl_real_t norm[2] = {sum, lmax};
    if (!(sum > AENL_R(0.0)) || !aenl_la_all_finite(norm, 0u, 1u, 2u))
    {
        return AENL_E_NUMERIC;
    }
    uint32_t best = 0u;
    for (uint32_t j = 0; j < nm; ++j)
    {
        w->cbar[j] /= sum;
        best = (w->cbar[j] > w->cbar[best]) ? (uint32_t)j : best;
    }
    if (!aenl_is_finite(nis_j[best]) || !imm_mixture_finite(f, nxt, w->cbar))
    {
        return AENL_E_NUMERIC;
    }
    const aenl_real_t *x = f->x[f->cur][0];
    const int16_t dir = next_direction(f, x);
    out->mode_threshold = aenl_skf_mode_of(m, x[m->switch_state], dir > 0);
    f->x_prev_s = x[m->switch_state];
    f->dir = dir;
    memcpy(f->mode_prob, w->cbar, sizeof(f->mode_prob));
    f->mode = (uint16_t)best;
    f->cur = (uint16_t)nxt;
    out->mode = (uint16_t)best;
    out->nis = nis_j[best];
    out->log_lik = (nu > 0u) ? lmax + aenl_log(sum) : AENL_R(0.0);
    return AENL_OK;
}

/* ---- public step / queries --------------------------------------------------------------------
 */

aenl_status_t aenl_skf_step(aenl_skf_t *f, const aenl_real_t *z, aenl_skf_out_t *out)
{
    aenl_skf_out_t dummy;
    if (out == NULL)
    {
        out = &dummy;
    }
    memset(out, 0, sizeof(*out));
    if (f == NULL || z == NULL || f->model == NULL)
    {
        return AENL_E_ARG;
    }
    uint32_t nu = 0u;
    for (uint32_t r = 0; r < f->n_z; ++r)
    {
        if (isinf(z[r]))
        {
            f->n_numeric = sat_inc(f->n_numeric);
            return AENL_E_NUMERIC;
        }
        if (!isnan(z[r]))
        {
            f->work.idx[nu++] = (uint16_t)r;
        }
    }
    const aenl_status_t st =
        f->model->imm ? step_imm(f, z, nu, out) : step_threshold(f, z, nu, out);
    if (st != AENL_OK)
    {
        if (st == AENL_E_NOT_PD)
        {
            f->n_not_pd = sat_inc(f->n_not_pd);
        }
        else
        {
            f->n_numeric = sat_inc(f->n_numeric);
        }
        memset(out, 0, sizeof(*out));
        return st;
    }
    out->n_used = (uint16_t)nu;
    f->n_steps = sat_inc(f->n_steps);
    if (nu == 0u)
    {
        f->n_missing = sat_inc(f->n_missing);
    }
    else
    {
        f->nis_sum += out->nis;
        f->n_nis = sat_inc(f->n_nis);
    }
    return AENL_OK;
}

aenl_status_t aenl_skf_estimate(const aenl_skf_t *f, aenl_real_t *x_out, aenl_real_t *P_out)
{
    if (f == NULL || x_out == NULL || f->model == NULL)
    {
        return AENL_E_ARG;
    }
    const uint32_t nx = f->n_x, cur = f->cur;
    if (!f->model->imm)
    {
        memcpy(x_out, f->x[cur][0], (size_t)nx * sizeof(aenl_real_t));
        if (P_out != NULL)
        {
            for (uint32_t i = 0; i < nx; ++i)
            {
                memcpy(&P_out[(size_t)i * nx], f->P[cur][0][i], (size_t)nx * sizeof(aenl_real_t));
            }
        }
        return AENL_OK;
    }
    mixture(f, cur, f->mode_prob, x_out, P_out, nx);
    return AENL_OK;
}

aenl_status_t aenl_skf_mode_prob(const aenl_skf_t *f, aenl_real_t *prob)
{
    if (f == NULL || prob == NULL)
    {
        return AENL_E_ARG;
    }
    memcpy(prob, f->mode_prob, (size_t)f->n_modes * sizeof(aenl_real_t));
    return AENL_OK;
}

aenl_status_t aenl_skf_mean_nis(const aenl_skf_t *f, aenl_real_t *mean_nis)
{
    if (f == NULL || mean_nis == NULL)
    {
        return AENL_E_ARG;
    }
    if (f->n_nis == 0u)
    {
        return AENL_E_EMPTY;
    }
    *mean_nis = f->nis_sum / (aenl_real_t)f->n_nis;
    return AENL_OK;
}
