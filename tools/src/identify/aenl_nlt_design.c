/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_nlt_design.c
 * @brief The record-alone test's regressions: columns that are the innovations' sensitivities
 *        to a force, their cross-products, least-squares fits, the robust score and the
 *        residualised columns of stage 2.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_nlt_internal.h"
#include "aenl_tools/aenl_dense.h"

/* ---- regressions on the innovations' sensitivities ------------------------------------------- */

/* One step of the sensitivities of the series s0.. (nc columns): Dn = F D + the inputs of
 * sample t, then D and Dn swap. */
static void design_step(const design_t *d, size_t s0, size_t nc, const double *F, size_t t,
                        size_t nx, double **D, double **Dn)
{
    double *out = *Dn;
    aenl_dense_mul(out, F, *D, nx, nx, nc);
    size_t c = 0;
    for (size_t s = s0; s < d->n_series; ++s)
    {
        const double gt = d->g[s][t];
        if (d->full[s])
        {
            for (size_t i = 0; i < nx; ++i)
            {
                out[i * nc + c + i] += gt;
            }
            c += nx;
        }
        else
        {
            for (size_t i = 0; i < nx; ++i)
            {
                out[i * nc + c] += gt * d->dir[i];
            }
            c += 1;
        }
    }
    *Dn = *D;
    *D = out;
}

/* What a pass over the sensitivities hands each sample the filter used: R (nz x ncols, the
 * whitened innovations' sensitivities to the design's columns) and the whitened innovations e. */
typedef void (*design_visit_fn)(void *ctx, const double *R, const double *e);

/* The number of series that the columns 0..nk-1 are, all of them full; 0 when they are not whole
 * full series (the known sensitivities then cannot stand for them). */
static size_t series_of_columns(const design_t *d, size_t nx, size_t nk)
{
    size_t s = 0;
    size_t c = 0;
    for (; c < nk && s < d->n_series && d->full[s]; ++s)
    {
        c += nx;
    }
    return c == nk ? s : 0u;
}

/* One pass over the record: D_{t+1} = F_t D_t + the columns' inputs of sample t, from D_0 = 0,
 * and R = WC_t D_t handed to visit at every sample the filter used. The first n_known columns'
 * R comes from d->R_known when it is given (the same values: every entry of a product is
 * summed in the same order whatever the other columns), and only the others are walked. */
static aenl_status_t design_walk(const design_t *d, const kf_t *k, design_visit_fn visit, void *ctx,
                                 aenl_err_t *err)
{
    const size_t nx = k->nx;
    const size_t nz = k->nz;
    const size_t nc = d->ncols;
    const size_t s0 = d->R_known != NULL ? series_of_columns(d, nx, d->n_known) : 0u;
    const size_t nk = s0 > 0 ? d->n_known : 0u;
    const size_t nw = nc - nk; /* columns walked */
    double *D = (double *)calloc(nx * nw + 1u, sizeof(double));
    double *Dn = (double *)calloc(nx * nw + 1u, sizeof(double));
    double *R = (double *)calloc(nz * nc, sizeof(double));
    double *Rw = nk > 0 ? (double *)calloc(nz * nw + 1u, sizeof(double)) : R; /* walked part */
    if (D == NULL || Dn == NULL || R == NULL || Rw == NULL)
    {
        free(D);
        free(Dn);
        free(R);
        free(Rw != R ? Rw : NULL);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    for (size_t t = 0; t < k->n; ++t)
    {
        const double *F = k->F + k->slot[t] * nx * nx;
        if (k->used[t])
        {
            aenl_dense_mul(Rw, k->WC + k->slot[t] * nz * nx, D, nz, nx, nw);
            for (size_t j = 0; nk > 0 && j < nz; ++j)
            {
                memcpy(R + j * nc, d->R_known + (t * nz + j) * nk, nk * sizeof(double));
                memcpy(R + j * nc + nk, Rw + j * nw, nw * sizeof(double));
            }
            if (d->R_save != NULL)
            {
                memcpy(d->R_save + t * nz * nc, R, nz * nc * sizeof(double));
            }
            visit(ctx, R, k->eps + t * nz);
        }
        design_step(d, s0, nw, F, t, nx, &D, &Dn);
    }
    free(D);
    free(Dn);
    free(R);
    free(Rw != R ? Rw : NULL);
    return AENL_OK;
}

/* G (nc x nc) += X' X over the m rows of X (m x nc, row-major); the upper triangle and the
 * diagonal 4 x 4 tiles are right (the caller mirrors the upper triangle), except the 4 x 4 tiles
 * wholly inside the first `known` columns, which are skipped. Sixteen sums in registers per 4 x 4
 * tile make it several times faster than adding each row's outer product to G, which streams the
 * whole of G through the cache for every row; a tile's four columns are adjacent in a row, so
 * the sums of a row go two or four at a time in vector registers, each still summed in row
 * order. */
static void syrk_rows(double *restrict G, size_t nc, const double *restrict X, size_t m,
                      size_t known)
{
    for (size_t i0 = 0; i0 < nc; i0 += 4u)
    {
        /* tiles inside the first `known` columns' block are left out (copied in later) */
        for (size_t j0 = i0; j0 < nc; j0 += 4u)
        {
            if (j0 + 4u <= known)
            {
                continue;
            }
            if (j0 + 4u <= nc) /* then i0 + 4 <= nc too */
            {
                double s[4][4] = {{0.0}};
                for (size_t q = 0; q < m; ++q)
                {
                    const double *x = X + q * nc + i0;
                    const double *y = X + q * nc + j0;
                    for (size_t a = 0; a < 4u; ++a)
                    {
                        for (size_t b = 0; b < 4u; ++b)
                        {
                            s[a][b] += x[a] * y[b];
                        }
                    }
                }
                for (size_t a = 0; a < 4u; ++a)
                {
                    for (size_t b = 0; b < 4u; ++b)
                    {
                        G[(i0 + a) * nc + j0 + b] += s[a][b];
                    }
                }
                continue;
            }
            for (size_t i = i0; i < i0 + 4u && i < nc; ++i)
            {
                for (size_t j = j0; j < j0 + 4u && j < nc; ++j)
                {
                    double acc = 0.0;
                    for (size_t q = 0; q < m; ++q)
                    {
                        acc += X[q * nc + i] * X[q * nc + j];
                    }
                    G[i * nc + j] += acc;
                }
            }
        }
    }
}

/* The cross-products' accumulator: each sample's rows wait in X for a block's G update. */
typedef struct
{
    design_t *d;
    double *X;    /* m_blk rows of ncols */
    size_t m_blk; /* rows a block holds */
    size_t rows;  /* rows waiting */
    size_t nz;
} accum_t;

static void accumulate_rows(void *ctx, const double *R, const double *e)
{
    accum_t *a = (accum_t *)ctx;
    const size_t nc = a->d->ncols;
    /* e(beta) = e - R beta: G += R'R and r += R'e, so that beta = G^-1 r is the force */
    for (size_t j = 0; j < a->nz; ++j)
    {
        const double *rj = R + j * nc;
        for (size_t i = 0; i < nc; ++i)
        {
            a->d->r[i] += rj[i] * e[j];
        }
        memcpy(a->X + a->rows * nc, rj, nc * sizeof(double));
        a->rows++;
    }
    if (a->rows == a->m_blk)
    {
        syrk_rows(a->d->G, nc, a->X, a->rows, a->d->G_known != NULL ? a->d->n_known : 0u);
        a->rows = 0;
    }
}

aenl_status_t nlt_design_accumulate(design_t *d, const kf_t *k, aenl_err_t *err)
{
    const size_t nx = k->nx;
    const size_t nz = k->nz;
    size_t nc = 0;
    for (size_t s = 0; s < d->n_series; ++s)
    {
        nc += d->full[s] ? nx : 1u;
    }
    d->ncols = nc;
    if (nc == 0 || nx == 0 || nz == 0)
    {
        aenl_err_set(err, "aenl_nltest: an empty design");
        return AENL_E_ARG;
    }
    accum_t a = {d, NULL, NLT_ROW_BLOCK * nz, 0, nz};
    a.X = (double *)calloc(nc * a.m_blk, sizeof(double));
    d->G = (double *)calloc(nc * nc, sizeof(double));
    d->r = (double *)calloc(nc, sizeof(double));
    aenl_status_t st = AENL_E_DIM;
    if (a.X == NULL || d->G == NULL || d->r == NULL)
    {
        aenl_err_set(err, "out of memory");
    }
    else
    {
        st = design_walk(d, k, accumulate_rows, &a, err);
    }
    if (st == AENL_OK && a.rows > 0)
    {
        syrk_rows(d->G, nc, a.X, a.rows, d->G_known != NULL ? d->n_known : 0u);
    }
    free(a.X);
    for (size_t i = 0; st == AENL_OK && d->G_known != NULL && i < d->n_known; ++i)
    {
        for (size_t j = i; j < d->n_known; ++j)
        {
            d->G[i * nc + j] = d->G_known[i * d->n_known + j];
        }
    }
    for (size_t i = 0; st == AENL_OK && i < nc; ++i)
    {
        for (size_t j = 0; j < i; ++j)
        {
            d->G[i * nc + j] = d->G[j * nc + i];
        }
    }
    return st;
}

void nlt_design_free(design_t *d)
{
    free(d->G);
    free(d->r);
    d->G = NULL;
    d->r = NULL;
}

/* The normal equations of columns idx[0..m-1] scaled to unit diagonal (sc: the scales; a zero
 * column gets scale 0 and a unit diagonal), with a small ridge that keeps near-collinear sets
 * solvable: A (m x m) and, when r_out is not NULL, the scaled right-hand side. */
static void scaled_normal(const design_t *d, const size_t *idx, size_t m, double *A, double *sc,
                          double *r_out)
{
    for (size_t i = 0; i < m; ++i)
    {
        const double gii = d->G[idx[i] * d->ncols + idx[i]];
        sc[i] = gii > 0.0 ? 1.0 / sqrt(gii) : 0.0;
    }
    for (size_t i = 0; i < m; ++i)
    {
        for (size_t j = 0; j < m; ++j)
        {
            A[i * m + j] = d->G[idx[i] * d->ncols + idx[j]] * sc[i] * sc[j];
        }
        A[i * m + i] += NLT_RIDGE + (sc[i] > 0.0 ? 0.0 : 1.0);
        if (r_out != NULL)
        {
            r_out[i] = d->r[idx[i]] * sc[i];
        }
    }
}

/* The least-squares fit on columns idx[0..m-1] of the design: returns r' G^-1 r (the reduction of
 * the residual sum of squares), NaN when singular, and, when beta is not NULL, the coefficients. */
double nlt_fit_subset(const design_t *d, const size_t *idx, size_t m, double *beta)
{
    double *A = (double *)malloc(m * m * sizeof(double));
    double *b = (double *)malloc(m * sizeof(double));
    double *sc = (double *)malloc(m * sizeof(double));
    double *x = (double *)malloc(m * sizeof(double));
    double red = NAN;
    if (A != NULL && b != NULL && sc != NULL && x != NULL)
    {
        scaled_normal(d, idx, m, A, sc, b);
        memcpy(x, b, m * sizeof(double));
        if (aenl_dense_posv(A, x, m, 1) == 0)
        {
            red = 0.0;
            for (size_t i = 0; i < m; ++i)
            {
                red += b[i] * x[i];
                if (beta != NULL)
                {
                    beta[i] = x[i] * sc[i];
                }
            }
        }
    }
    free(x);
    free(A);
    free(b);
    free(sc);
    return red;
}

/* The Bartlett lag of the long-run variance of the score contributions: Newey and West's rule
 * floor(4 (n / 100)^(2/9)). */
static size_t hac_lag(size_t n)
{
    return (size_t)floor(4.0 * pow((double)n / 100.0, 2.0 / 9.0));
}

/* The robust score's accumulator (nlt_design_robust). */
typedef struct
{
    size_t nz, nc, nn, nl, hac;
    const double *Pi;
    double *q, *st, *z, *ring; /* nc, nl, nl, (hac + 1) nl */
    double *score, *meat;
    size_t ti; /* samples seen */
} robust_t;

static void robust_rows(void *ctx, const double *R, const double *e)
{
    robust_t *a = (robust_t *)ctx;
    const size_t nc = a->nc;
    const size_t nn = a->nn;
    const size_t nl = a->nl;
    /* the row's columns weighted by the innovations first, q = R' e, then partialled:
     * st = q[nn..] - Pi' q[..nn], the same as partialling each channel's row and weighting
     * after, at 1 / nz of the cost */
    for (size_t c = 0; c < nc; ++c)
    {
        double v = 0.0;
        for (size_t j = 0; j < a->nz; ++j)
        {
            v += R[j * nc + c] * e[j];
        }
        a->q[c] = v;
    }
    for (size_t l = 0; l < nl; ++l)
    {
        double x = a->q[nn + l];
        for (size_t i = 0; i < nn; ++i)
        {
            x -= a->Pi[i * nl + l] * a->q[i];
        }
        a->st[l] = x;
    }
    /* the lags' Bartlett-weighted sum first, z = sum_h w_h s_{t-h}: then
     * sum_h w_h (s_t s_{t-h}' + s_{t-h} s_t') = s_t z' + z s_t', one outer product instead of
     * one per lag */
    memset(a->z, 0, nl * sizeof(double));
    for (size_t h = 1; h <= a->hac && h <= a->ti; ++h)
    {
        const double w = 1.0 - (double)h / (double)(a->hac + 1);
        const double *sp = a->ring + ((a->ti - h) % (a->hac + 1)) * nl;
        for (size_t l = 0; l < nl; ++l)
        {
            a->z[l] += w * sp[l];
        }
    }
    for (size_t l = 0; l < nl; ++l)
    {
        a->score[l] += a->st[l];
        for (size_t m = l; m < nl; ++m)
        {
            a->meat[l * nl + m] += a->st[l] * a->st[m] + a->st[l] * a->z[m] + a->z[l] * a->st[m];
        }
    }
    if (a->hac > 0)
    {
        memcpy(a->ring + (a->ti % (a->hac + 1)) * nl, a->st, nl * sizeof(double));
    }
    a->ti++;
}

/* The heteroskedasticity-robust score of the columns nn.. of a design given its first nn
 * (Wooldridge's robust LM): the test columns are partialled on the nuisance ones with Pi
 * (nn x nl, the least-squares coefficients of G), and the per-sample score contributions
 * s_t = sum over channels of (partialled row) x (whitened innovation) give
 * score = sum s_t and meat = their long-run variance (sum s_t s_t' plus the Bartlett-weighted
 * autocovariances up to hac_lag). score' meat^-1 score is chi-square with nl degrees of freedom
 * when the innovations are uncorrelated with the past, whatever their distribution and however
 * their spread changes over the record (an impulse, a decay's fading amplitude); the lags keep
 * it so when an approximate linear model leaves the innovations a little serially correlated. */
aenl_status_t nlt_design_robust(const design_t *d, const kf_t *k, size_t nn, const double *Pi,
                                double *score, double *meat, aenl_err_t *err)
{
    const size_t nc = d->ncols;
    const size_t nl = nc - nn;
    const size_t hac = hac_lag(k->n);
    robust_t a = {k->nz, nc, nn, nl, hac, Pi, NULL, NULL, NULL, NULL, score, meat, 0};
    a.q = (double *)calloc(nc, sizeof(double));
    a.st = (double *)malloc(nl * sizeof(double));
    a.z = (double *)calloc(nl, sizeof(double));
    a.ring = (double *)calloc((hac + 1) * nl, sizeof(double));
    memset(score, 0, nl * sizeof(double));
    memset(meat, 0, nl * nl * sizeof(double));
    aenl_status_t st = AENL_E_DIM;
    if (a.q == NULL || a.st == NULL || a.z == NULL || a.ring == NULL)
    {
        aenl_err_set(err, "out of memory");
    }
    else
    {
        st = design_walk(d, k, robust_rows, &a, err);
    }
    for (size_t l = 0; st == AENL_OK && l < nl; ++l)
    {
        for (size_t m = 0; m < l; ++m)
        {
            meat[l * nl + m] = meat[m * nl + l];
        }
    }
    free(a.q);
    free(a.st);
    free(a.z);
    free(a.ring);
    return st;
}

/* Pi (nn x nl): the coefficients of the columns nn.. of the design regressed on its first nn,
 * from the scaled normal equations. */
aenl_status_t nlt_partial_coefficients(const design_t *d, size_t nn, double *Pi, aenl_err_t *err)
{
    const size_t nc = d->ncols;
    const size_t nl = nc - nn;
    double *A = (double *)malloc(nn * nn * sizeof(double));
    double *sc = (double *)malloc(nn * sizeof(double));
    size_t *idx = (size_t *)calloc(nn, sizeof(size_t));
    aenl_status_t st = AENL_OK;
    if (A == NULL || sc == NULL || idx == NULL)
    {
        st = AENL_E_DIM;
        aenl_err_set(err, "out of memory");
    }
    else
    {
        for (size_t i = 0; i < nn; ++i)
        {
            idx[i] = i;
        }
        scaled_normal(d, idx, nn, A, sc, NULL);
        for (size_t i = 0; i < nn; ++i)
        {
            for (size_t l = 0; l < nl; ++l)
            {
                Pi[i * nl + l] = d->G[i * nc + nn + l] * sc[i];
            }
        }
        if (aenl_dense_posv(A, Pi, nn, nl) != 0)
        {
            st = AENL_E_NUMERIC;
            aenl_err_set(err, "the nuisance regression is singular");
        }
        for (size_t i = 0; i < nn && st == AENL_OK; ++i)
        {
            for (size_t l = 0; l < nl; ++l)
            {
                Pi[i * nl + l] *= sc[i];
            }
        }
    }
    free(A);
    free(sc);
    free(idx);
    return st;
}

/* x' A^-1 x for a symmetric positive semi-definite A (n x n), scaled to unit diagonal with a
 * small ridge; NaN when it cannot be solved. */
double nlt_quad_inverse(const double *A, const double *x, size_t n)
{
    double *M = (double *)malloc(n * n * sizeof(double));
    double *v = (double *)malloc(n * sizeof(double));
    double *w = (double *)malloc(n * sizeof(double));
    double q = NAN;
    if (M != NULL && v != NULL && w != NULL)
    {
        for (size_t i = 0; i < n; ++i)
        {
            const double di = A[i * n + i];
            w[i] = di > 0.0 ? 1.0 / sqrt(di) : 0.0;
        }
        for (size_t i = 0; i < n; ++i)
        {
            for (size_t j = 0; j < n; ++j)
            {
                M[i * n + j] = A[i * n + j] * w[i] * w[j];
            }
            M[i * n + i] += NLT_RIDGE + (w[i] > 0.0 ? 0.0 : 1.0);
            v[i] = x[i] * w[i];
        }
        double *b = (double *)malloc(n * sizeof(double));
        if (b != NULL)
        {
            memcpy(b, v, n * sizeof(double));
            if (aenl_dense_posv(M, b, n, 1) == 0)
            {
                q = 0.0;
                for (size_t i = 0; i < n; ++i)
                {
                    q += v[i] * b[i];
                }
            }
            free(b);
        }
    }
    free(M);
    free(v);
    free(w);
    return q;
}

aenl_status_t nlt_residualise(const design_t *d, size_t nn, resid_t *out, aenl_err_t *err)
{
    const size_t nc = d->ncols;
    const size_t ns = nc - nn;
    double *L = (double *)malloc(nn * nn * sizeof(double));
    double *W = (double *)malloc(nn * ns * sizeof(double));
    double *w = (double *)malloc(nn * sizeof(double));
    out->ns = ns;
    out->Gt = (double *)malloc(ns * ns * sizeof(double));
    out->rt = (double *)malloc(ns * sizeof(double));
    if (L == NULL || W == NULL || w == NULL || out->Gt == NULL || out->rt == NULL)
    {
        free(L);
        free(W);
        free(w);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    /* factor of the scaled nuisance block with a ridge, as in nlt_fit_subset */
    double sc[NLT_NUIS_MAX * NLT_MAX_X];
    size_t nidx[NLT_NUIS_MAX * NLT_MAX_X];
    for (size_t i = 0; i < nn; ++i)
    {
        nidx[i] = i;
    }
    scaled_normal(d, nidx, nn, L, sc, NULL);
    aenl_status_t st = AENL_OK;
    if (aenl_dense_potrf(L, nn) != 0)
    {
        aenl_err_set(err, "nuisance regression singular");
        st = AENL_E_NUMERIC;
    }
    else
    {
        for (size_t s = 0; s < ns; ++s) /* W[:, s] = L^-1 (scaled G_NS[:, s]) */
        {
            for (size_t i = 0; i < nn; ++i)
            {
                w[i] = d->G[i * nc + nn + s] * sc[i];
            }
            aenl_dense_lower_solve(L, w, nn);
            for (size_t i = 0; i < nn; ++i)
            {
                W[i * ns + s] = w[i];
            }
        }
        for (size_t i = 0; i < nn; ++i)
        {
            w[i] = d->r[i] * sc[i];
        }
        aenl_dense_lower_solve(L, w, nn);
        for (size_t a = 0; a < ns; ++a)
        {
            double ra = d->r[nn + a];
            for (size_t i = 0; i < nn; ++i)
            {
                ra -= W[i * ns + a] * w[i];
            }
            out->rt[a] = ra;
            for (size_t b = a; b < ns; ++b)
            {
                double g = d->G[(nn + a) * nc + nn + b];
                for (size_t i = 0; i < nn; ++i)
                {
                    g -= W[i * ns + a] * W[i * ns + b];
                }
                out->Gt[a * ns + b] = g;
                out->Gt[b * ns + a] = g;
            }
        }
    }
    free(L);
    free(W);
    free(w);
    return st;
}

void nlt_resid_free(resid_t *r)
{
    free(r->Gt);
    free(r->rt);
    r->Gt = NULL;
    r->rt = NULL;
}

/* The per-sample losses of n_fit fits of the design's columns: b holds n_fit coefficient vectors
 * of d->ncols each (row-major), and loss (used samples x n_fit) receives, for every sample the
 * filter used, sum over channels of (e - R b_f)^2, the squared whitened innovation that fit
 * leaves. One sensitivity recursion per fit (the fit's force folded into one vector per series)
 * instead of one per column: the fits are known, only their per-sample residuals are wanted. */
aenl_status_t nlt_design_losses(const design_t *d, const kf_t *k, const double *b, size_t n_fit,
                                double *loss, aenl_err_t *err)
{
    const size_t nx = k->nx;
    const size_t nz = k->nz;
    const size_t nc = d->ncols;
    double *W = (double *)calloc(d->n_series * nx * n_fit, sizeof(double));
    double *D = (double *)calloc(nx * n_fit, sizeof(double));
    double *Dn = (double *)calloc(nx * n_fit, sizeof(double));
    double *R = (double *)calloc(nz * n_fit, sizeof(double));
    if (W == NULL || D == NULL || Dn == NULL || R == NULL)
    {
        free(W);
        free(D);
        free(Dn);
        free(R);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    /* W[s] (nx x n_fit): series s's force on the states under each fit */
    size_t c = 0;
    for (size_t s = 0; s < d->n_series; ++s)
    {
        double *ws = W + s * nx * n_fit;
        for (size_t f = 0; f < n_fit; ++f)
        {
            const double *bf = b + f * nc;
            for (size_t i = 0; i < nx; ++i)
            {
                ws[i * n_fit + f] = d->full[s] ? bf[c + i] : bf[c] * d->dir[i];
            }
        }
        c += d->full[s] ? nx : 1u;
    }
    size_t ti = 0;
    for (size_t t = 0; t < k->n; ++t)
    {
        const double *F = k->F + k->slot[t] * nx * nx;
        if (k->used[t])
        {
            const double *WC = k->WC + k->slot[t] * nz * nx;
            const double *e = k->eps + t * nz;
            aenl_dense_mul(R, WC, D, nz, nx, n_fit);
            for (size_t f = 0; f < n_fit; ++f)
            {
                double v = 0.0;
                for (size_t a = 0; a < nz; ++a)
                {
                    const double r = e[a] - R[a * n_fit + f];
                    v += r * r;
                }
                loss[ti * n_fit + f] = v;
            }
            ti++;
        }
        aenl_dense_mul(Dn, F, D, nx, nx, n_fit);
        for (size_t s = 0; s < d->n_series; ++s)
        {
            const double gt = d->g[s][t];
            const double *ws = W + s * nx * n_fit;
            for (size_t i = 0; i < nx * n_fit; ++i)
            {
                Dn[i] += gt * ws[i];
            }
        }
        double *tmp = D;
        D = Dn;
        Dn = tmp;
    }
    free(W);
    free(D);
    free(Dn);
    free(R);
    return AENL_OK;
}

/* The long-run variance of x (n values): its centred sum of squares plus the Bartlett-weighted
 * autocovariances up to the lag of the robust score (the same kernel and lag). */
double nlt_long_run_variance(const double *x, size_t n)
{
    if (n == 0)
    {
        return 0.0;
    }
    double mean = 0.0;
    for (size_t t = 0; t < n; ++t)
    {
        mean += x[t];
    }
    mean /= (double)n;
    const size_t hac = hac_lag(n);
    double v = 0.0;
    for (size_t t = 0; t < n; ++t)
    {
        v += (x[t] - mean) * (x[t] - mean);
    }
    for (size_t h = 1; h <= hac && h < n; ++h)
    {
        const double w = 1.0 - (double)h / (double)(hac + 1);
        double acc = 0.0;
        for (size_t t = h; t < n; ++t)
        {
            acc += (x[t] - mean) * (x[t - h] - mean);
        }
        v += 2.0 * w * acc;
    }
    return fmax(v, 0.0);
}
