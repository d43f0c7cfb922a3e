/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_nlt_filter.c
 * @brief The record-alone test's Kalman filter pass: whitened innovations, the whitened output
 *        matrix and the transition of the innovations' sensitivity at every step (shared once
 *        the filter is steady), and the restarts at impulses.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_nlt_internal.h"
#include "aenl_tools/aenl_dense.h"
#include "aenl_tools/aenl_stats.h"

/* ---- the filter pass ------------------------------------------------------------------------- */

void nlt_kf_free(kf_t *k)
{
    free(k->eps);
    free(k->used);
    free(k->u);
    free(k->xs);
    free(k->slot);
    free(k->F);
    free(k->WC);
    memset(k, 0, sizeof(*k));
}

/* The run's results freed, its set-up (length, sizes, inputs) kept for another run. */
void nlt_kf_clear_run(kf_t *k)
{
    const size_t n = k->n;
    const size_t nz = k->nz;
    const size_t nx = k->nx;
    const double *in = k->in;
    const size_t n_in = k->n_in;
    nlt_kf_free(k);
    k->n = n;
    k->nz = nz;
    k->nx = nx;
    k->in = in;
    k->n_in = n_in;
}

static int kf_new_slot(kf_t *k)
{
    if (k->n_slots == k->cap_slots)
    {
        const size_t cap = k->cap_slots == 0 ? 64 : 2 * k->cap_slots;
        double *f = (double *)realloc(k->F, cap * k->nx * k->nx * sizeof(double));
        if (f == NULL)
        {
            return -1;
        }
        k->F = f;
        double *w = (double *)realloc(k->WC, cap * k->nz * k->nx * sizeof(double));
        if (w == NULL)
        {
            return -1;
        }
        k->WC = w;
        k->cap_slots = cap;
    }
    k->n_slots++;
    return 0;
}

static int rel_close(const double *a, const double *b, size_t n, double tol)
{
    double num = 0.0;
    double den = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        num = fmax(num, fabs(a[i] - b[i]));
        den = fmax(den, fabs(b[i]));
    }
    return num <= tol * den;
}

/* out = A P A' + Q (the covariance one step ahead); out must not be P. */
static void predict_cov(const aenl_em_model_t *m, const double *P, double *out, size_t nx)
{
    double T[NLT_MAX_X * NLT_MAX_X] = {0};
    aenl_dense_mul(T, m->A, P, nx, nx, nx);
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            double s = m->Q[i * nx + j];
            for (size_t l = 0; l < nx; ++l)
            {
                s += T[i * nx + l] * m->A[j * nx + l];
            }
            out[i * nx + j] = s;
        }
    }
}

/* One covariance step at a used row: gain pieces into a new slot, P advanced. */
typedef struct
{
    double K[NLT_MAX_X * AENL_NLT_MAX_CH];
    double L[AENL_NLT_MAX_CH * AENL_NLT_MAX_CH];
} kf_gain_t;

static aenl_status_t kf_cov_step(kf_t *k, const aenl_em_model_t *m, double *P, kf_gain_t *g,
                                 size_t slot, aenl_err_t *err)
{
    const size_t nx = k->nx;
    const size_t nz = k->nz;
    double PCt[NLT_MAX_X * AENL_NLT_MAX_CH];
    double IKC[NLT_MAX_X * NLT_MAX_X];
    double T1[NLT_MAX_X * NLT_MAX_X];
    double T2[NLT_MAX_X * NLT_MAX_X];
    /* S = C P C' + R, PCt = P C' */
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nz; ++j)
        {
            double s = 0.0;
            for (size_t l = 0; l < nx; ++l)
            {
                s += P[i * nx + l] * m->C[j * nx + l];
            }
            PCt[i * nz + j] = s;
        }
    }
    for (size_t i = 0; i < nz; ++i)
    {
        for (size_t j = 0; j < nz; ++j)
        {
            double s = m->R[i * nz + j];
            for (size_t l = 0; l < nx; ++l)
            {
                s += m->C[i * nx + l] * PCt[l * nz + j];
            }
            g->L[i * nz + j] = s;
        }
    }
    for (size_t i = 0; i < nz; ++i)
    {
        for (size_t j = i + 1; j < nz; ++j)
        {
            g->L[i * nz + j] = 0.0; /* lower factor only */
        }
    }
    if (aenl_dense_potrf(g->L, nz) != 0)
    {
        aenl_err_set(err, "innovation covariance not positive definite");
        return AENL_E_NUMERIC;
    }
    /* K' = S^-1 (P C')': solve with the factor, column by column of K' */
    for (size_t i = 0; i < nx; ++i)
    {
        double v[AENL_NLT_MAX_CH];
        for (size_t j = 0; j < nz; ++j)
        {
            v[j] = PCt[i * nz + j];
        }
        aenl_dense_lower_solve(g->L, v, nz);
        for (size_t jj = nz; jj-- > 0;)
        {
            double s = v[jj];
            for (size_t l = jj + 1; l < nz; ++l)
            {
                s -= g->L[l * nz + jj] * v[l];
            }
            v[jj] = s / g->L[jj * nz + jj];
        }
        for (size_t j = 0; j < nz; ++j)
        {
            g->K[i * nz + j] = v[j];
        }
    }
    /* IKC = I - K C; Pf = IKC P IKC' + K R K' (Joseph form) */
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            double s = (i == j) ? 1.0 : 0.0;
            for (size_t l = 0; l < nz; ++l)
            {
                s -= g->K[i * nz + l] * m->C[l * nx + j];
            }
            IKC[i * nx + j] = s;
        }
    }
    aenl_dense_mul(T1, IKC, P, nx, nx, nx);
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j < nx; ++j)
        {
            double s = 0.0;
            for (size_t l = 0; l < nx; ++l)
            {
                s += T1[i * nx + l] * IKC[j * nx + l];
            }
            double kr = 0.0;
            for (size_t a = 0; a < nz; ++a)
            {
                for (size_t b = 0; b < nz; ++b)
                {
                    kr += g->K[i * nz + a] * m->R[a * nz + b] * g->K[j * nz + b];
                }
            }
            T2[i * nx + j] = s + kr;
        }
    }
    /* the slot: F = A IKC, WC = L^-1 C */
    aenl_dense_mul(k->F + slot * nx * nx, m->A, IKC, nx, nx, nx);
    for (size_t j = 0; j < nx; ++j)
    {
        double v[AENL_NLT_MAX_CH];
        for (size_t i = 0; i < nz; ++i)
        {
            v[i] = m->C[i * nx + j];
        }
        aenl_dense_lower_solve(g->L, v, nz);
        for (size_t i = 0; i < nz; ++i)
        {
            k->WC[slot * nz * nx + i * nx + j] = v[i];
        }
    }
    /* P_next = A Pf A' + Q */
    predict_cov(m, T2, T1, nx);
    memcpy(T2, T1, nx * nx * sizeof(double));
    memcpy(P, T2, nx * nx * sizeof(double)); /* symmetric by construction; keep it so */
    aenl_dense_symmetrise(P, nx);
    return AENL_OK;
}

/* The filter over y (n x nz, standardised), keeping what the regressions need. */
aenl_status_t nlt_kf_run(kf_t *k, const aenl_em_model_t *m, const double *y,
                         const unsigned char *reset, const double *P_reset, aenl_err_t *err)
{
    const size_t nx = k->nx;
    const size_t nz = k->nz;
    const size_t n = k->n;
    double x[NLT_MAX_X];
    double xf[NLT_MAX_X];
    double P[NLT_MAX_X * NLT_MAX_X];
    double Pprev[NLT_MAX_X * NLT_MAX_X];
    kf_gain_t g;
    int steady = 0;
    size_t cur = 0;
    size_t miss_slot = (size_t)-1;
    if (n == 0 || nz == 0 || nx == 0 || nx > NLT_MAX_X)
    {
        aenl_err_set(err, "aenl_nltest: an empty record or model");
        return AENL_E_ARG;
    }
    k->eps = (double *)calloc(n * nz, sizeof(double));
    k->u = (double *)calloc(n * nz, sizeof(double));
    k->used = (unsigned char *)calloc(n, 1);
    k->slot = (size_t *)calloc(n, sizeof(size_t));
    k->xs = (double *)calloc(n * nx, sizeof(double));
    if (k->eps == NULL || k->u == NULL || k->used == NULL || k->slot == NULL || k->xs == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    memcpy(x, m->x0, nx * sizeof(double));
    memcpy(P, m->P0, nx * nx * sizeof(double));
    for (size_t t = 0; t < n; ++t)
    {
        const double *yt = y + t * nz;
        int ok = 1;
        for (size_t j = 0; j < nz; ++j)
        {
            ok &= isfinite(yt[j]) ? 1 : 0;
        }
        if (!ok)
        {
            /* No update: the innovations' sensitivity moves with A alone. */
            if (miss_slot == (size_t)-1)
            {
                if (kf_new_slot(k) != 0)
                {
                    aenl_err_set(err, "out of memory");
                    return AENL_E_DIM;
                }
                miss_slot = k->n_slots - 1;
                memcpy(k->F + miss_slot * nx * nx, m->A, nx * nx * sizeof(double));
                memset(k->WC + miss_slot * nz * nx, 0, nz * nx * sizeof(double));
            }
            k->slot[t] = miss_slot;
            memcpy(xf, x, nx * sizeof(double));
            double T2[NLT_MAX_X * NLT_MAX_X] = {0};
            predict_cov(m, P, T2, nx);
            memcpy(P, T2, nx * nx * sizeof(double));
            steady = 0;
        }
        else
        {
            if (reset != NULL && reset[t])
            {
                /* An impulse the model's Gaussian noise does not explain: the state may have
                 * moved anywhere in its usual range, and the filter starts afresh from there. */
                for (size_t i = 0; i < nx * nx; ++i)
                {
                    P[i] += P_reset[i];
                }
                steady = 0;
            }
            if (!steady)
            {
                memcpy(Pprev, P, nx * nx * sizeof(double));
                if (kf_new_slot(k) != 0)
                {
                    aenl_err_set(err, "out of memory");
                    return AENL_E_DIM;
                }
                cur = k->n_slots - 1;
                const aenl_status_t st = kf_cov_step(k, m, P, &g, cur, err);
                if (st != AENL_OK)
                {
                    return st;
                }
                steady = rel_close(P, Pprev, nx * nx, NLT_STEADY_TOL);
            }
            k->slot[t] = cur;
            k->used[t] = 1;
            double e[AENL_NLT_MAX_CH];
            for (size_t j = 0; j < nz; ++j)
            {
                double s = yt[j];
                for (size_t l = 0; l < nx; ++l)
                {
                    s -= m->C[j * nx + l] * x[l];
                }
                e[j] = s;
            }
            for (size_t i = 0; i < nx; ++i)
            {
                double s = x[i];
                for (size_t j = 0; j < nz; ++j)
                {
                    s += g.K[i * nz + j] * e[j];
                }
                xf[i] = s;
            }
            aenl_dense_lower_solve(g.L, e, nz);
            for (size_t j = 0; j < nz; ++j)
            {
                k->eps[t * nz + j] = e[j];
                k->ee += e[j] * e[j];
            }
            k->rows += nz;
        }
        for (size_t j = 0; j < nz; ++j)
        {
            double s = 0.0;
            for (size_t l = 0; l < nx; ++l)
            {
                s += m->C[j * nx + l] * xf[l];
            }
            k->u[t * nz + j] = s;
        }
        for (size_t i = 0; i < nx; ++i)
        {
            k->xs[i * n + t] = xf[i];
        }
        for (size_t i = 0; i < nx; ++i)
        {
            double s = m->b[i];
            for (size_t l = 0; l < nx; ++l)
            {
                s += m->A[i * nx + l] * xf[l];
            }
            for (size_t p = 0; p < k->n_in; ++p)
            {
                s += m->B[i * k->n_in + p] * k->in[t * k->n_in + p];
            }
            x[i] = s;
        }
    }
    return AENL_OK;
}

/* The chi-square quantile with k degrees of freedom whose upper tail is alpha (bisection). */
static double chi2_quantile_upper(double alpha, double k)
{
    double lo = 0.0;
    double hi = k + 10.0 * sqrt(2.0 * k) + 100.0;
    for (int it = 0; it < 200; ++it)
    {
        const double mid = 0.5 * (lo + hi);
        if (aenl_chi2_sf(mid, k) > alpha)
        {
            lo = mid;
        }
        else
        {
            hi = mid;
        }
    }
    return 0.5 * (lo + hi);
}

/* Whether sample t of run k is a peak of the jump statistic q beyond thr, not flagged yet. */
static int new_peak(const kf_t *k, const double *q, const unsigned char *flag, double thr, size_t t)
{
    const size_t n = k->n;
    const int peak = (t == 0 || q[t] >= q[t - 1u]) && (t + 1u == n || q[t] > q[t + 1u]);
    return k->used[t] && peak && q[t] > thr && !flag[t];
}

/* A peak of the jump statistic: its value and sample. */
typedef struct
{
    double q;
    size_t t;
} peak_t;

/* Larger statistic first; equal ones in sample order, so the order is the same on every run. */
static int peak_cmp(const void *pa, const void *pb)
{
    const peak_t *a = (const peak_t *)pa;
    const peak_t *b = (const peak_t *)pb;
    if (a->q > b->q || a->q < b->q)
    {
        return a->q > b->q ? -1 : 1;
    }
    return (a->t > b->t) - (a->t < b->t);
}

/* Impulses: instants at which the state jumped (a tap, a kick, a gust front), found by the
 * generalised likelihood ratio of a jump (Willsky and Jones). A jump nu into sample tau leaves
 * the filter's predicted state wrong by Phi(t, tau) nu at every later t (Phi(tau, tau) = I,
 * Phi(t + 1, tau) = A (I - K_t C) Phi(t, tau)), so the whitened innovations move by
 * W_t C Phi(t, tau) nu. Its least-squares estimate over the rest of the record has the statistic
 * q_tau = r' G^-1 r, with r = sum_t Phi' (W_t C)' eps_t and G = sum_t Phi' (W_t C)' (W_t C) Phi,
 * both by a backward recursion; without a jump q_tau is chi-square with nx degrees of freedom. An
 * instant whose q lies beyond the quantile at NLT_IMPULSE_LEVEL and is a local maximum of q is an
 * impulse. The evidence of a jump that the measurement noise hides in any one sample (a rate jump
 * seen through displacements) accumulates over the samples the filter needs to absorb it, which a
 * test of single innovations misses; and a filter that believes its state goes on mispredicting
 * after a jump in a way that follows the motion, which the law test would read as a law.
 * Instants are added to flag (n entries; those set stay set); *n_imp receives the number set. */
aenl_status_t nlt_impulses(const kf_t *k, int windows, unsigned char *flag, size_t *n_imp,
                           aenl_err_t *err)
{
    const size_t n = k->n;
    const size_t nz = k->nz;
    const size_t nx = k->nx;
    const double thr = chi2_quantile_upper(NLT_IMPULSE_LEVEL, (double)nx);
    double *q = (double *)malloc(n * sizeof(double));
    if (q == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    double r[NLT_MAX_X] = {0};
    double G[NLT_MAX_X * NLT_MAX_X] = {0};
    double L[NLT_MAX_X * NLT_MAX_X] = {0}; /* Cholesky factor of G (lower) */
    int L_ok = 0;
    int steady = 0; /* G, like the filter's covariance, depends on the slots only: once it has
                       converged inside a run of one slot, it and its factor stay */
    for (size_t tt = n; tt-- > 0;)
    {
        const double *F = k->F + k->slot[tt] * nx * nx;
        const double *W = k->WC + k->slot[tt] * nz * nx;
        const double *e = k->eps + tt * nz;
        double r2[NLT_MAX_X] = {0};
        for (size_t i = 0; i < nx; ++i) /* r <- W' e + F' r */
        {
            double v = 0.0;
            for (size_t j = 0; j < nz; ++j)
            {
                v += W[j * nx + i] * e[j];
            }
            for (size_t l = 0; l < nx; ++l)
            {
                v += F[l * nx + i] * r[l];
            }
            r2[i] = v;
        }
        memcpy(r, r2, nx * sizeof(double));
        const int same = tt + 1u < n && k->slot[tt] == k->slot[tt + 1u];
        steady = steady && same;
        if (!steady)
        {
            double T[NLT_MAX_X * NLT_MAX_X] = {0};
            double G2[NLT_MAX_X * NLT_MAX_X] = {0};
            aenl_dense_mul(T, G, F, nx, nx, nx); /* G <- W' W + F' G F */
            for (size_t i = 0; i < nx; ++i)
            {
                for (size_t j = 0; j <= i; ++j)
                {
                    double v = 0.0;
                    for (size_t l = 0; l < nz; ++l)
                    {
                        v += W[l * nx + i] * W[l * nx + j];
                    }
                    for (size_t l = 0; l < nx; ++l)
                    {
                        v += F[l * nx + i] * T[l * nx + j];
                    }
                    G2[i * nx + j] = v;
                    G2[j * nx + i] = v;
                }
            }
            steady = same && rel_close(G2, G, nx * nx, NLT_STEADY_TOL);
            memcpy(G, G2, nx * nx * sizeof(double));
            memcpy(L, G, nx * nx * sizeof(double));
            L_ok = aenl_dense_potrf(L, nx) == 0;
        }
        /* q = r' G^-1 r by the factor (0 when G is not positive definite) */
        double x[NLT_MAX_X];
        memcpy(x, r, nx * sizeof(double));
        double v = 0.0;
        if (L_ok)
        {
            aenl_dense_lower_solve(L, x, nx);
            for (size_t i = 0; i < nx; ++i)
            {
                v += x[i] * x[i];
            }
        }
        q[tt] = v;
    }
    /* A jump at tau and one a few samples away differ only in how the first samples after them
     * see the state, which takes h = ceil(nx / nz) samples to observe in full, and in noise the
     * statistic places a jump less sharply still: its instant is known to within the samples
     * whose statistic stays within chi-square_1(0.95) = 3.84 of the peak's (a profile-likelihood
     * interval). So the peaks are taken largest first, none inside the window of one taken
     * already (this run's or an earlier run's), and the filter is widened over the window: the
     * interval, and at least the h samples either side of the peak. */
    const size_t h = (windows && nz > 0) ? (nx + nz - 1u) / nz : 0u;
    size_t n_peaks = 0;
    for (size_t t = 0; t < n; ++t)
    {
        n_peaks += new_peak(k, q, flag, thr, t) ? 1u : 0u;
    }
    peak_t *pk = n_peaks > 0 ? (peak_t *)malloc(n_peaks * sizeof(peak_t)) : NULL;
    if (n_peaks > 0 && pk == NULL)
    {
        free(q);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    size_t n_found = 0;
    for (size_t t = 0; t < n && n_found < n_peaks; ++t)
    {
        if (new_peak(k, q, flag, thr, t))
        {
            pk[n_found].q = q[t];
            pk[n_found++].t = t;
        }
    }
    n_peaks = n_found;
    if (n_peaks > 1)
    {
        qsort(pk, n_peaks, sizeof(peak_t), peak_cmp);
    }
    for (size_t i = 0; i < n_peaks; ++i)
    {
        const size_t t = pk[i].t;
        if (flag[t])
        {
            continue; /* within h samples of a larger peak */
        }
        size_t lo = t > h ? t - h : 0u;
        size_t hi = t + h < n ? t + h : n - 1u;
        while (h > 0 && lo > 0 && q[lo - 1u] >= q[t] - NLT_CHI2_1_95 && t - lo < NLT_JUMP_SPAN * h)
        {
            --lo;
        }
        while (h > 0 && hi + 1u < n && q[hi + 1u] >= q[t] - NLT_CHI2_1_95 &&
               hi - t < NLT_JUMP_SPAN * h)
        {
            ++hi;
        }
        for (size_t s = lo; s <= hi; ++s)
        {
            flag[s] = flag[s] ? flag[s] : NLT_IMPULSE_NEAR;
        }
        flag[t] = NLT_IMPULSE_AT;
    }
    size_t cnt = 0;
    for (size_t t = 0; t < n; ++t)
    {
        cnt += flag[t] == NLT_IMPULSE_AT ? 1u : 0u;
    }
    free(pk);
    free(q);
    *n_imp = cnt;
    return AENL_OK;
}

/* The covariance of the filtered states of run k over the record into P (nx x nx): the state's
 * usual range, by which the filter's covariance is widened at an impulse (the state may have
 * moved anywhere in it). */
void nlt_state_range(const kf_t *k, double *P)
{
    const size_t n = k->n;
    const size_t nx = k->nx;
    double mean[NLT_MAX_X] = {0};
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t t = 0; t < n; ++t)
        {
            mean[i] += k->xs[i * n + t];
        }
        mean[i] /= (double)n;
    }
    for (size_t i = 0; i < nx; ++i)
    {
        for (size_t j = 0; j <= i; ++j)
        {
            double c = 0.0;
            for (size_t t = 0; t < n; ++t)
            {
                c += (k->xs[i * n + t] - mean[i]) * (k->xs[j * n + t] - mean[j]);
            }
            P[i * nx + j] = c / (double)n;
            P[j * nx + i] = c / (double)n;
        }
    }
}
