/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_rfs.c
 * @brief Multi-channel restoring-force regression with blocked cross-validation (aenl_rfs.h).
 *
 * Notation: z the linear regressors of the target channel (every regressor but its own second
 * difference), y its second difference, B the 2K tents (rising motion first). Per block the
 * accumulator holds G = sum w w' over all regressors w (the y of every channel is among them),
 * Z'B and the tridiagonal B'B of every target, and B_i'B_j of every pair of channels (a law of
 * one among the regressors of the other: an extra column u = B_i tau). With A = Z'Z, the
 * Frisch-Waugh projection M = B'B - B'Z A^-1 Z'B, r = B'y - B'Z A^-1 Z'y turns a law with tent map
 * T (2K x q) into the q x q problem (T'MT) g = T'r, its in-sample gain g'T'r over the linear fit.
 */
#include "aenl_tools/aenl_rfs.h"
#include "aenl_tools/aenl_dense.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define RFS_B AENL_RFS_BLOCKS
/** Kinks are searched where at least this fraction of the samples lies on each side. */
#define RFS_TAIL 0.02
/** Refinement step of a switching point, in grid cells. */
#define RFS_FINE 0.25
/** Paired t by which a more specific law must beat the simpler one (one-sided 0.5 %, 15 df). */
#define RFS_T_PAIR 3.0
/** Columns of a law at most (the polynomial's four and a direction offset that changes with
 *  amplitude: two). */
#define RFS_MAX_Q 6

struct aenl_rfs
{
    aenl_rfs_cfg_t cfg;
    size_t p;        /* regressors incl. every channel's second difference and the constant */
    size_t per_ch;   /* 3 + n_lags */
    size_t k2;       /* 2 * n_nodes */
    size_t hist_len; /* longest lag + 2 */
    size_t max_lag;
    double *hist;  /* [hist_len][n_ch], standardised, NaN missing */
    double *w;     /* one regressor row [p] */
    size_t pushed; /* rows pushed */
    size_t rows[RFS_B];
    double *G;    /* [B][p][p], upper triangle */
    double *ZB;   /* [B][n_ch][p][k2] */
    double *BBd;  /* [B][n_ch][k2] */
    double *BBo;  /* [B][n_ch][k2]: (k, k+1) inside one direction */
    double *BX;   /* [B][pair][k2][k2]: B_i' B_j of channels i < j (pair_block), NULL for one */
    double *coef; /* [n_ch][p + k2]: every channel's free-law model (aenl_rfs_model), or NULL */
};

/* ---- accumulation ------------------------------------------------------------------------ */

aenl_status_t aenl_rfs_create(aenl_rfs_t **out, const aenl_rfs_cfg_t *cfg, aenl_err_t *err)
{
    if (out == NULL || cfg == NULL || cfg->n_ch == 0 || cfg->n_ch > AENL_RFS_MAX_CH ||
        cfg->n_nodes < 8 || cfg->n_nodes > AENL_RFS_MAX_NODES || cfg->n_lags > AENL_RFS_MAX_LAGS ||
        cfg->n_total == 0)
    {
        aenl_err_set(err, "restoring-force regression: bad configuration");
        return AENL_E_ARG;
    }
    size_t max_lag = 1;
    for (size_t j = 0; j < cfg->n_ch; ++j)
    {
        if (!(cfg->scale[j] > 0.0) || !isfinite(cfg->center[j]) || !isfinite(cfg->scale[j]) ||
            !(cfg->hi[j] > cfg->lo[j]) || !isfinite(cfg->lo[j]) || !isfinite(cfg->hi[j]))
        {
            aenl_err_set(err, "restoring-force regression: bad range or scale of channel %zu", j);
            return AENL_E_ARG;
        }
    }
    for (size_t l = 0; l < cfg->n_lags; ++l)
    {
        if (cfg->lags[l] < 2)
        {
            aenl_err_set(err, "restoring-force regression: lag %u below 2", cfg->lags[l]);
            return AENL_E_ARG;
        }
        max_lag = cfg->lags[l] > max_lag ? cfg->lags[l] : max_lag;
    }
    aenl_rfs_t *r = calloc(1, sizeof(*r));
    if (r == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    r->cfg = *cfg;
    r->per_ch = 3u + cfg->n_lags;
    r->p = 1u + cfg->n_ch * r->per_ch;
    r->k2 = 2u * (size_t)cfg->n_nodes;
    r->max_lag = max_lag;
    r->hist_len = max_lag + 2u;
    r->hist = malloc(r->hist_len * cfg->n_ch * sizeof(double));
    r->w = malloc(r->p * sizeof(double));
    r->G = calloc(RFS_B * r->p * r->p, sizeof(double));
    r->ZB = calloc(RFS_B * cfg->n_ch * r->p * r->k2, sizeof(double));
    r->BBd = calloc(RFS_B * cfg->n_ch * r->k2, sizeof(double));
    r->BBo = calloc(RFS_B * cfg->n_ch * r->k2, sizeof(double));
    const size_t pairs = cfg->n_ch * (cfg->n_ch - 1u) / 2u;
    r->BX = pairs > 0 ? calloc(RFS_B * pairs * r->k2 * r->k2, sizeof(double)) : NULL;
    if (r->hist == NULL || r->w == NULL || r->G == NULL || r->ZB == NULL || r->BBd == NULL ||
        r->BBo == NULL || (pairs > 0 && r->BX == NULL))
    {
        aenl_rfs_free(r);
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    *out = r;
    return AENL_OK;
}

void aenl_rfs_free(aenl_rfs_t *r)
{
    if (r != NULL)
    {
        free(r->hist);
        free(r->w);
        free(r->G);
        free(r->ZB);
        free(r->BBd);
        free(r->BBo);
        free(r->BX);
        free(r->coef);
        free(r);
    }
}

/* B_i'B_j of channels i < j in block b (k2 x k2, rows channel i's tents). */
static double *pair_block(const aenl_rfs_t *r, size_t b, size_t i, size_t j)
{
    const size_t nc = r->cfg.n_ch, pair = i * nc - i * (i + 1u) / 2u + (j - i - 1u);
    return &r->BX[(b * (nc * (nc - 1u) / 2u) + pair) * r->k2 * r->k2];
}

/* Sample `back` rows before the newest of channel j (standardised). */
static double hist_at(const aenl_rfs_t *r, size_t back, size_t j)
{
    const size_t slot = (r->pushed - 1u - back) % r->hist_len;
    return r->hist[slot * r->cfg.n_ch + j];
}

/* Position of x (standardised) on channel j's tent grid: cell k and weight of node k+1. */
static void tent(const aenl_rfs_t *r, size_t j, double x, size_t *k, double *w1)
{
    const double lo = (r->cfg.lo[j] - r->cfg.center[j]) / r->cfg.scale[j];
    const double hi = (r->cfg.hi[j] - r->cfg.center[j]) / r->cfg.scale[j];
    const size_t K = r->cfg.n_nodes;
    const double s = (x - lo) / (hi - lo) * (double)(K - 1u);
    double c = floor(s);
    c = c < 0.0 ? 0.0 : (c > (double)(K - 2u) ? (double)(K - 2u) : c);
    *k = (size_t)c;
    *w1 = s - c; /* outside [0, 1] beyond the grid ends: linear extrapolation */
}

/* The tent column (rising motion first) of channel i's regressors wi (position, first
 * difference, ...) and the weight of the column after it. */
static size_t tent_col(const aenl_rfs_t *r, size_t i, const double *wi, double *w1)
{
    size_t k;
    tent(r, i, wi[0], &k, w1);
    return (wi[1] > 0.0 ? 0u : (size_t)r->cfg.n_nodes) + k;
}

/* Take one row into the history and form the regressor row w centred one row back: 1 when
 * every regressor is finite, 0 while the history fills or when a gap lies inside the window. */
static int form_row(aenl_rfs_t *r, const double *row)
{
    const size_t nc = r->cfg.n_ch;
    double *slot = &r->hist[(r->pushed % r->hist_len) * nc];
    for (size_t j = 0; j < nc; ++j)
    {
        slot[j] = isfinite(row[j]) ? (row[j] - r->cfg.center[j]) / r->cfg.scale[j] : (double)NAN;
    }
    r->pushed++;
    if (r->pushed < r->hist_len)
    {
        return 0;
    }
    /* the regression row is centred on n = newest - 1 */
    double *w = r->w;
    w[0] = 1.0;
    for (size_t j = 0; j < nc; ++j)
    {
        const double xp = hist_at(r, 0, j), x0 = hist_at(r, 1, j), xm = hist_at(r, 2, j);
        double *wj = &w[1u + j * r->per_ch];
        wj[0] = x0;
        wj[1] = 0.5 * (xp - xm);
        wj[2] = xp - 2.0 * x0 + xm;
        for (size_t l = 0; l < r->cfg.n_lags; ++l)
        {
            wj[3u + l] = hist_at(r, 1u + r->cfg.lags[l], j);
        }
    }
    for (size_t a = 0; a < r->p; ++a)
    {
        if (!isfinite(w[a]))
        {
            return 0; /* a gap inside the window */
        }
    }
    return 1;
}

void aenl_rfs_push(aenl_rfs_t *r, const double *row)
{
    if (r == NULL || row == NULL || !form_row(r, row))
    {
        return;
    }
    const double *w = r->w;
    const size_t nc = r->cfg.n_ch;
    const size_t n = r->pushed - 2u; /* index of the centre row */
    size_t b = (size_t)(((double)n * RFS_B) / (double)r->cfg.n_total);
    b = b >= RFS_B ? RFS_B - 1u : b;
    r->rows[b]++;
    const size_t p = r->p;
    double *G = &r->G[b * p * p];
    for (size_t a = 0; a < p; ++a)
    {
        const double wa = w[a];
        double *ga = &G[a * p];
        for (size_t c = a; c < p; ++c)
        {
            ga[c] += wa * w[c];
        }
    }
    /* each channel's tent cell (its direction's block) and the weights of its two nodes */
    size_t cols[AENL_RFS_MAX_CH];
    double ws[AENL_RFS_MAX_CH][2];
    for (size_t i = 0; i < nc; ++i)
    {
        double w1;
        cols[i] = tent_col(r, i, &w[1u + i * r->per_ch], &w1);
        ws[i][0] = 1.0 - w1;
        ws[i][1] = w1;
    }
    const size_t k2 = r->k2;
    for (size_t i = 0; i < nc; ++i)
    {
        const size_t col = cols[i];
        const double w0 = ws[i][0], w1 = ws[i][1];
        double *zb = &r->ZB[(b * nc + i) * p * k2];
        for (size_t a = 0; a < p; ++a)
        {
            zb[a * k2 + col] += w[a] * w0;
            zb[a * k2 + col + 1u] += w[a] * w1;
        }
        double *bd = &r->BBd[(b * nc + i) * k2];
        double *bo = &r->BBo[(b * nc + i) * k2];
        bd[col] += w0 * w0;
        bd[col + 1u] += w1 * w1;
        bo[col] += w0 * w1;
    }
    /* the tents of every pair of channels, for a law of one among the regressors of another */
    for (size_t i = 0; i + 1u < nc; ++i)
    {
        for (size_t j = i + 1u; j < nc; ++j)
        {
            double *bx = pair_block(r, b, i, j);
            for (size_t u = 0; u < 2u; ++u)
            {
                for (size_t v = 0; v < 2u; ++v)
                {
                    bx[(cols[i] + u) * k2 + cols[j] + v] += ws[i][u] * ws[j][v];
                }
            }
        }
    }
}

/* ---- small dense linear algebra ------------------------------------------------------------ */

/** Regressors at most (the constant, then per channel: position, first and second difference,
 *  lags). */
#define RFS_MAX_P (2u + AENL_RFS_MAX_CH * (3u + AENL_RFS_MAX_LAGS))
/** No channel's law among the regressors; the regressor index that stands for the given law. */
#define RFS_NONE  ((size_t)-1)
#define RFS_GIVEN ((size_t)-1)

/* Cholesky factor (LAPACK, row-major, lower) of the m x m symmetric a in place; 0, or -1 when it
 * is not positive definite or a pivot falls to `rel` of its diagonal or below (collinear). */
static int spd_factor(double *a, size_t m, double rel)
{
    double diag[RFS_MAX_P];
    for (size_t j = 0; j < m; ++j)
    {
        diag[j] = a[j * m + j];
    }
    if (aenl_dense_potrf(a, m) != 0)
    {
        return -1;
    }
    for (size_t j = 0; j < m; ++j)
    {
        if (!(a[j * m + j] * a[j * m + j] > rel * diag[j]))
        {
            return -1;
        }
    }
    return 0;
}

/* Solve the q x q (q <= RFS_MAX_Q) system Q g = h; 0, or -1 when its columns are collinear. */
static int solve_small(const double *Q, const double *h, size_t q, double *g)
{
    double L[RFS_MAX_Q * RFS_MAX_Q];
    memcpy(L, Q, q * q * sizeof(double));
    if (spd_factor(L, q, 1e-10) != 0)
    {
        return -1;
    }
    memcpy(g, h, q * sizeof(double));
    aenl_dense_potrs(L, q, g, 1);
    return 0;
}

/* ---- sums over blocks and the projection ------------------------------------------------- */

typedef struct
{
    size_t m; /* linear regressors of the target */
    double *A, *c, yy, *ZB, *By, *BBd, *BBo;
} rfs_gram_t;

typedef struct
{
    double *L, *W; /* Cholesky of A; W = A^-1 [Z'B | Z'y], m x (k2 + 1) */
    double *M, *r; /* k2 x k2, k2 */
    double rss_lin;
} rfs_proj_t;

typedef struct
{
    const aenl_rfs_t *rfs;
    size_t ch, m, k2, K;
    size_t idx[RFS_MAX_P];           /* z -> regressor index (RFS_GIVEN: the given law) */
    size_t given;                    /* channel whose law is a regressor, or RFS_NONE */
    const double *tau;               /* that law's values at its tents (k2) */
    size_t iy;                       /* y's regressor index */
    double node[AENL_RFS_MAX_NODES]; /* standardised node positions */
    double lo_q, hi_q;               /* where kinks may lie (standardised) */
    double x_abs;                    /* largest |node|: the polynomial law's scale */
    double cell;
    rfs_gram_t all, one, tr;
    rfs_proj_t pj;          /* all data */
    rfs_proj_t fold[RFS_B]; /* each block left out: cross-validation, then the jackknife */
    double *tmp;            /* k2 x RFS_MAX_Q */
} rfs_work_t;

static int gram_alloc(rfs_gram_t *g, size_t m, size_t k2)
{
    g->m = m;
    g->A = calloc(m * m, sizeof(double));
    g->c = calloc(m, sizeof(double));
    g->ZB = calloc(m * k2, sizeof(double));
    g->By = calloc(k2, sizeof(double));
    g->BBd = calloc(k2, sizeof(double));
    g->BBo = calloc(k2, sizeof(double));
    return (g->A && g->c && g->ZB && g->By && g->BBd && g->BBo) ? 0 : -1;
}

static void gram_free(rfs_gram_t *g)
{
    free(g->A);
    free(g->c);
    free(g->ZB);
    free(g->By);
    free(g->BBd);
    free(g->BBo);
}

/* The given law's column u = B_g tau in block b: its products with every regressor (ug[p]),
 * with itself (*uu) and with the target's tents (uB[k2]). */
static void given_sums(const rfs_work_t *wk, size_t b, double *ug, double *uu, double *uB)
{
    const aenl_rfs_t *r = wk->rfs;
    const size_t k2 = wk->k2, p = r->p, nc = r->cfg.n_ch, K = wk->K, g = wk->given;
    const double *tau = wk->tau;
    const double *zg = &r->ZB[(b * nc + g) * p * k2];
    for (size_t a = 0; a < p; ++a)
    {
        double v = 0.0;
        for (size_t k = 0; k < k2; ++k)
        {
            v += zg[a * k2 + k] * tau[k];
        }
        ug[a] = v;
    }
    const double *bd = &r->BBd[(b * nc + g) * k2], *bo = &r->BBo[(b * nc + g) * k2];
    double v = 0.0;
    for (size_t k = 0; k < k2; ++k)
    {
        v += bd[k] * tau[k] * tau[k];
        if (k % K + 1u < K)
        {
            v += 2.0 * bo[k] * tau[k] * tau[k + 1u];
        }
    }
    *uu = v;
    const size_t ch = wk->ch, lo = g < ch ? g : ch, hi = g < ch ? ch : g;
    const double *bx = pair_block(r, b, lo, hi);
    for (size_t k = 0; k < k2; ++k)
    {
        double t = 0.0;
        for (size_t l = 0; l < k2; ++l)
        {
            /* rows of bx are the lower channel's tents */
            t += tau[l] * (g < ch ? bx[l * k2 + k] : bx[k * k2 + l]);
        }
        uB[k] = t;
    }
}

/* Sum every block (only < 0) or block `only` into g. */
static void gram_sum(const rfs_work_t *wk, int only, rfs_gram_t *g)
{
    const aenl_rfs_t *r = wk->rfs;
    const size_t m = wk->m, k2 = wk->k2, p = r->p, nc = r->cfg.n_ch;
    memset(g->A, 0, m * m * sizeof(double));
    memset(g->c, 0, m * sizeof(double));
    memset(g->ZB, 0, m * k2 * sizeof(double));
    memset(g->By, 0, k2 * sizeof(double));
    memset(g->BBd, 0, k2 * sizeof(double));
    memset(g->BBo, 0, k2 * sizeof(double));
    g->yy = 0.0;
    double ug[RFS_MAX_P], uu = 0.0, uB[2 * AENL_RFS_MAX_NODES];
    for (int b = 0; b < RFS_B; ++b)
    {
        if (only >= 0 && b != only)
        {
            continue;
        }
        const double *G = &r->G[(size_t)b * p * p];
        const double *zb = &r->ZB[((size_t)b * nc + wk->ch) * p * k2];
        if (wk->given != RFS_NONE)
        {
            given_sums(wk, (size_t)b, ug, &uu, uB);
        }
        for (size_t a = 0; a < m; ++a)
        {
            const size_t ia = wk->idx[a];
            for (size_t c = 0; c < m; ++c)
            {
                const size_t ic = wk->idx[c];
                double v;
                if (ia == RFS_GIVEN || ic == RFS_GIVEN)
                {
                    v = ia == ic ? uu : ug[ia == RFS_GIVEN ? ic : ia];
                }
                else
                {
                    v = ia <= ic ? G[ia * p + ic] : G[ic * p + ia];
                }
                g->A[a * m + c] += v;
            }
            if (ia == RFS_GIVEN)
            {
                g->c[a] += ug[wk->iy];
                for (size_t k = 0; k < k2; ++k)
                {
                    g->ZB[a * k2 + k] += uB[k];
                }
                continue;
            }
            g->c[a] += ia <= wk->iy ? G[ia * p + wk->iy] : G[wk->iy * p + ia];
            for (size_t k = 0; k < k2; ++k)
            {
                g->ZB[a * k2 + k] += zb[ia * k2 + k];
            }
        }
        g->yy += G[wk->iy * p + wk->iy];
        for (size_t k = 0; k < k2; ++k)
        {
            g->By[k] += zb[wk->iy * k2 + k];
            g->BBd[k] += r->BBd[((size_t)b * nc + wk->ch) * k2 + k];
            g->BBo[k] += r->BBo[((size_t)b * nc + wk->ch) * k2 + k];
        }
    }
}

/* tr = all - one (the training set of a fold), element by element. */
static void gram_diff(const rfs_work_t *wk, const rfs_gram_t *all, const rfs_gram_t *one,
                      rfs_gram_t *tr)
{
    const size_t m = wk->m, k2 = wk->k2;
    for (size_t i = 0; i < m * m; ++i)
    {
        tr->A[i] = all->A[i] - one->A[i];
    }
    for (size_t i = 0; i < m * k2; ++i)
    {
        tr->ZB[i] = all->ZB[i] - one->ZB[i];
    }
    for (size_t i = 0; i < m; ++i)
    {
        tr->c[i] = all->c[i] - one->c[i];
    }
    for (size_t k = 0; k < k2; ++k)
    {
        tr->By[k] = all->By[k] - one->By[k];
        tr->BBd[k] = all->BBd[k] - one->BBd[k];
        tr->BBo[k] = all->BBo[k] - one->BBo[k];
    }
    tr->yy = all->yy - one->yy;
}

/* out = B'B t for the tridiagonal-by-direction B'B of g. */
static void bb_mul(const rfs_work_t *wk, const rfs_gram_t *g, const double *t, double *out)
{
    const size_t K = wk->K;
    for (size_t k = 0; k < wk->k2; ++k)
    {
        const size_t in_dir = k % K;
        double s = g->BBd[k] * t[k];
        if (in_dir + 1u < K)
        {
            s += g->BBo[k] * t[k + 1u];
        }
        if (in_dir > 0)
        {
            s += g->BBo[k - 1u] * t[k - 1u];
        }
        out[k] = s;
    }
}

/* Project g: p->W, p->M, p->r, p->rss_lin. -1 when A is not positive definite. */
static int project(rfs_work_t *wk, const rfs_gram_t *g, rfs_proj_t *pj)
{
    const size_t m = wk->m, k2 = wk->k2, st = k2 + 1u;
    memcpy(pj->L, g->A, m * m * sizeof(double));
    double tr = 0.0;
    for (size_t a = 0; a < m; ++a)
    {
        tr += g->A[a * m + a];
    }
    for (size_t a = 0; a < m; ++a)
    {
        pj->L[a * m + a] += 1e-12 * tr / (double)m; /* rounding guard, not a prior */
    }
    if (spd_factor(pj->L, m, 0.0) != 0)
    {
        return -1;
    }
    for (size_t a = 0; a < m; ++a)
    {
        memcpy(&pj->W[a * st], &g->ZB[a * k2], k2 * sizeof(double));
        pj->W[a * st + k2] = g->c[a];
    }
    aenl_dense_potrs(pj->L, m, pj->W, st);
    double rss = g->yy;
    for (size_t a = 0; a < m; ++a)
    {
        rss -= g->c[a] * pj->W[a * st + k2];
    }
    pj->rss_lin = rss;
    for (size_t k = 0; k < k2; ++k)
    {
        double rk = g->By[k];
        for (size_t a = 0; a < m; ++a)
        {
            rk -= g->ZB[a * k2 + k] * pj->W[a * st + k2];
        }
        pj->r[k] = rk;
        for (size_t l = k; l < k2; ++l)
        {
            double s = 0.0;
            for (size_t a = 0; a < m; ++a)
            {
                s -= g->ZB[a * k2 + k] * pj->W[a * st + l];
            }
            pj->M[k * k2 + l] = s;
            pj->M[l * k2 + k] = s;
        }
    }
    const size_t K = wk->K;
    for (size_t k = 0; k < k2; ++k)
    {
        pj->M[k * k2 + k] += g->BBd[k];
        if (k % K + 1u < K)
        {
            pj->M[k * k2 + k + 1u] += g->BBo[k];
            pj->M[(k + 1u) * k2 + k] += g->BBo[k];
        }
    }
    return 0;
}

/* ---- laws ---------------------------------------------------------------------------------- */

typedef struct
{
    double a, b, s; /* kinks (standardised): kink a; gap [a, b]; hysteresis gap [a, b] +- s/2 */
    aenl_rfs_law_t law;
    int offset; /* plus a rising-motion offset a + b x^2 (hysteresis has a of its own) */
} rfs_law_t;

static double clip(double x, double a, double b)
{
    return x < a ? a : (x > b ? b : x);
}

/* Tent map T (k2 x q, column-major: T[c * k2 + k]); returns q (0 for the linear law). */
static size_t law_map(const rfs_work_t *wk, const rfs_law_t *lw, double *T)
{
    const size_t K = wk->K, k2 = wk->k2;
    double *t1 = T, *t2 = &T[k2];
    for (size_t k = 0; k < k2; ++k)
    {
        const double x = wk->node[k % K];
        const int rising = k < K;
        switch (lw->law)
        {
            case AENL_RFS_POLY:
            {
                const double u = x / wk->x_abs, u2 = u * u; /* scaled: conditioning */
                t1[k] = u2;
                t2[k] = u2 * u;
                T[2u * k2 + k] = u2 * u2;
                T[3u * k2 + k] = u2 * u2 * u;
                break;
            }
            case AENL_RFS_KINK:
                t1[k] = x > lw->a ? x - lw->a : 0.0;
                break;
            case AENL_RFS_GAP:
                t1[k] = clip(x, lw->a, lw->b);
                break;
            case AENL_RFS_HYSTERESIS:
            {
                const double sh = rising ? 0.5 * lw->s : -0.5 * lw->s;
                t1[k] = clip(x, lw->a + sh, lw->b + sh);
                t2[k] = rising ? 1.0 : 0.0;
                break;
            }
            case AENL_RFS_LINEAR:
                break;
        }
    }
    size_t q = 0;
    switch (lw->law)
    {
        case AENL_RFS_POLY:
            q = 4u;
            break;
        case AENL_RFS_HYSTERESIS:
            q = 2u;
            break;
        case AENL_RFS_KINK:
        case AENL_RFS_GAP:
            q = 1u;
            break;
        case AENL_RFS_LINEAR:
            break;
    }
    if (lw->offset && q > 0)
    {
        /* a rising-motion offset a + b x^2; the hysteresis law has its a as a column already */
        const size_t own = lw->law == AENL_RFS_HYSTERESIS ? 1u : 0u;
        for (size_t k = 0; k < k2; ++k)
        {
            const double u = wk->node[k % K] / wk->x_abs;
            if (!own)
            {
                T[q * k2 + k] = k < K ? 1.0 : 0.0;
            }
            T[(q + 1u - own) * k2 + k] = k < K ? u * u : 0.0;
        }
        q += 2u - own;
    }
    return q;
}

/* In-sample gain of the law with tent map T (q columns) on projection pj (g: its coefficients);
 * -1 if degenerate. */
static double map_gain(rfs_work_t *wk, const rfs_proj_t *pj, const double *T, size_t q, double *g)
{
    const size_t k2 = wk->k2;
    double Q[RFS_MAX_Q * RFS_MAX_Q], h[RFS_MAX_Q] = {0.0};
    if (q == 0)
    {
        return 0.0;
    }
    for (size_t c = 0; c < q; ++c)
    {
        double *mt = &wk->tmp[c * k2];
        for (size_t k = 0; k < k2; ++k)
        {
            double s = 0.0;
            const double *mk = &pj->M[k * k2];
            for (size_t l = 0; l < k2; ++l)
            {
                s += mk[l] * T[c * k2 + l];
            }
            mt[k] = s;
            h[c] += T[c * k2 + k] * pj->r[k];
        }
    }
    for (size_t c = 0; c < q; ++c)
    {
        for (size_t d = 0; d < q; ++d)
        {
            double s = 0.0;
            for (size_t k = 0; k < k2; ++k)
            {
                s += T[c * k2 + k] * wk->tmp[d * k2 + k];
            }
            Q[c * q + d] = s;
        }
    }
    if (solve_small(Q, h, q, g) != 0)
    {
        return -1.0;
    }
    double gain = 0.0;
    for (size_t c = 0; c < q; ++c)
    {
        gain += g[c] * h[c];
    }
    return gain;
}

/* In-sample gain of law lw on projection pj (g: its coefficients); -1 if degenerate. */
static double law_gain(rfs_work_t *wk, const rfs_proj_t *pj, const rfs_law_t *lw, double *g)
{
    double T[RFS_MAX_Q * 2 * AENL_RFS_MAX_NODES];
    return map_gain(wk, pj, T, law_map(wk, lw, T), g);
}

static int kink_ok(const rfs_work_t *wk, double x)
{
    return x >= wk->lo_q && x <= wk->hi_q;
}

static int law_ok(const rfs_work_t *wk, const rfs_law_t *lw)
{
    switch (lw->law)
    {
        case AENL_RFS_KINK:
            return kink_ok(wk, lw->a);
        case AENL_RFS_GAP:
            return lw->b - lw->a >= 0.999 * wk->cell && kink_ok(wk, lw->a) && kink_ok(wk, lw->b);
        case AENL_RFS_HYSTERESIS:
            /* the loop lags the motion (s > 0): rising motion meets the band later (the
             * simulator's loop: rising band [x_f, x_f + delta], falling [-x_f - delta, -x_f],
             * s = 2 x_f + delta) */
            return lw->b - lw->a >= 0.999 * wk->cell && lw->s >= 0.999 * wk->cell &&
                   kink_ok(wk, lw->a - 0.5 * lw->s) && kink_ok(wk, lw->b + 0.5 * lw->s);
        case AENL_RFS_LINEAR:
        case AENL_RFS_POLY:
            return 1;
    }
    return 1;
}

/* Best law of a family on pj: a box scan of half-width `span` cells and step `step` cells
 * around *lw (or the whole interior when span <= 0); *lw is updated; returns its gain. */
static double law_search(rfs_work_t *wk, const rfs_proj_t *pj, rfs_law_t *lw, double span,
                         double step)
{
    double g[RFS_MAX_Q];
    if (lw->law == AENL_RFS_POLY)
    {
        return law_gain(wk, pj, lw, g);
    }
    const double h = wk->cell;
    double a0, a1, b0 = 0.0, b1 = 0.0, s0 = 0.0, s1 = 0.0;
    if (span > 0.0)
    {
        a0 = lw->a - span * h;
        a1 = lw->a + span * h;
        b0 = lw->b - span * h;
        b1 = lw->b + span * h;
        s0 = lw->s - span * h;
        s1 = lw->s + span * h;
    }
    else
    {
        a0 = b0 = wk->lo_q;
        a1 = b1 = wk->hi_q;
        s0 = 0.0;
        s1 = wk->hi_q - wk->lo_q;
    }
    if (lw->law != AENL_RFS_HYSTERESIS)
    {
        s0 = s1 = lw->s;
    }
    if (lw->law == AENL_RFS_KINK)
    {
        b0 = b1 = lw->b;
    }
    rfs_law_t best = *lw, c = *lw;
    double best_gain = -1.0;
    const double d = step * h;
    const long na = (long)floor((a1 - a0) / d + 1e-9), nb = (long)floor((b1 - b0) / d + 1e-9);
    const long ns = (long)floor((s1 - s0) / d + 1e-9);
    for (long ia = 0; ia <= na; ++ia)
    {
        c.a = a0 + (double)ia * d;
        for (long ib = 0; ib <= nb; ++ib)
        {
            c.b = b0 + (double)ib * d;
            for (long is = 0; is <= ns; ++is)
            {
                c.s = s0 + (double)is * d;
                if (!law_ok(wk, &c))
                {
                    continue;
                }
                const double gn = law_gain(wk, pj, &c, g);
                if (gn > best_gain)
                {
                    best_gain = gn;
                    best = c;
                }
            }
        }
    }
    *lw = best;
    return best_gain;
}

/* Full search of one family on all data: coarse, then two refinements. */
static double law_fit_all(rfs_work_t *wk, rfs_law_t *lw)
{
    const double coarse = lw->law == AENL_RFS_HYSTERESIS ? 2.0 : 1.0;
    const double gn = law_search(wk, &wk->pj, lw, 0.0, coarse);
    if (lw->law == AENL_RFS_POLY || gn < 0.0)
    {
        return gn;
    }
    if (coarse > 1.0)
    {
        (void)law_search(wk, &wk->pj, lw, coarse, 1.0);
    }
    return law_search(wk, &wk->pj, lw, 1.0, RFS_FINE);
}

/* Residual sum of squares on block set `te` of the law lw fitted on the projection pj. */
static double test_rss(rfs_work_t *wk, const rfs_proj_t *pj, const rfs_law_t *lw,
                       const rfs_gram_t *te, int *ok)
{
    const size_t m = wk->m, k2 = wk->k2, st = k2 + 1u;
    double T[RFS_MAX_Q * 2 * AENL_RFS_MAX_NODES] = {0.0};
    double g[RFS_MAX_Q] = {0.0};
    *ok = 1;
    const size_t q = law_map(wk, lw, T);
    if (map_gain(wk, pj, T, q, g) < 0.0)
    {
        *ok = 0;
        return 0.0;
    }
    /* beta = W_y - W_B T g */
    double beta[RFS_MAX_P];
    double tg[2 * AENL_RFS_MAX_NODES] = {0.0};
    for (size_t k = 0; k < k2; ++k)
    {
        tg[k] = 0.0;
        for (size_t c = 0; c < q; ++c)
        {
            tg[k] += T[c * k2 + k] * g[c];
        }
    }
    for (size_t a = 0; a < m; ++a)
    {
        double s = pj->W[a * st + k2];
        for (size_t k = 0; k < k2; ++k)
        {
            s -= pj->W[a * st + k] * tg[k];
        }
        beta[a] = s;
    }
    /* rss = yy - 2 theta' X'y + theta' X'X theta on the test blocks, X = [Z, B T] */
    double rss = te->yy;
    double btg[2 * AENL_RFS_MAX_NODES] = {0.0};
    bb_mul(wk, te, tg, btg);
    for (size_t k = 0; k < k2; ++k)
    {
        rss += -2.0 * tg[k] * te->By[k] + tg[k] * btg[k];
    }
    for (size_t a = 0; a < m; ++a)
    {
        double az = 0.0, zbt = 0.0;
        for (size_t c = 0; c < m; ++c)
        {
            az += te->A[a * m + c] * beta[c];
        }
        for (size_t k = 0; k < k2; ++k)
        {
            zbt += te->ZB[a * k2 + k] * tg[k];
        }
        rss += beta[a] * (az - 2.0 * te->c[a] + 2.0 * zbt);
    }
    return rss;
}

/* mean / (sd / sqrt(n)) of d[0..n-1]; +-1e6 for a constant non-zero series. */
static double batch_t(const double *d, size_t n)
{
    double mean = 0.0, m2 = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        mean += d[i];
    }
    mean /= (double)n;
    for (size_t i = 0; i < n; ++i)
    {
        m2 += (d[i] - mean) * (d[i] - mean);
    }
    const double sd = sqrt(m2 / (double)(n - 1u));
    if (!(sd > 1e-300))
    {
        return mean > 0.0 ? 1e6 : (mean < 0.0 ? -1e6 : 0.0);
    }
    return mean / (sd / sqrt((double)n));
}

/* The class of a law; the gap law of a spring stiffer inside its band (saturating) is a
 * softening polynomial, not freeplay. */
static aenl_class_t law_class_of(aenl_rfs_law_t law, int saturating)
{
    switch (law)
    {
        case AENL_RFS_POLY:
            return AENL_CLASS_POLYNOMIAL;
        case AENL_RFS_GAP:
            return saturating ? AENL_CLASS_POLYNOMIAL : AENL_CLASS_FREEPLAY;
        case AENL_RFS_KINK:
            return AENL_CLASS_FREEPLAY;
        case AENL_RFS_HYSTERESIS:
            return AENL_CLASS_HYSTERESIS;
        case AENL_RFS_LINEAR:
            return AENL_CLASS_LINEAR;
    }
    return AENL_CLASS_LINEAR;
}

/* Switching points of a law, standardised, ascending; returns their count. */
static size_t law_points(const rfs_law_t *lw, double *pt)
{
    switch (lw->law)
    {
        case AENL_RFS_KINK:
            pt[0] = lw->a;
            return 1;
        case AENL_RFS_GAP:
            pt[0] = lw->a;
            pt[1] = lw->b;
            return 2;
        case AENL_RFS_HYSTERESIS:
        {
            const double h = 0.5 * lw->s;
            pt[0] = lw->a - h;
            pt[1] = lw->a + h;
            pt[2] = lw->b - h;
            pt[3] = lw->b + h;
            for (size_t i = 1; i < 4; ++i) /* insertion sort of four */
            {
                for (size_t j = i; j > 0 && pt[j] < pt[j - 1u]; --j)
                {
                    const double t = pt[j];
                    pt[j] = pt[j - 1u];
                    pt[j - 1u] = t;
                }
            }
            return 4;
        }
        case AENL_RFS_LINEAR:
        case AENL_RFS_POLY:
            return 0;
    }
    return 0;
}

/* ---- analysis ------------------------------------------------------------------------------ */

static int proj_alloc(rfs_proj_t *pj, size_t m, size_t k2)
{
    pj->L = malloc(m * m * sizeof(double));
    pj->W = malloc(m * (k2 + 1u) * sizeof(double));
    pj->M = malloc(k2 * k2 * sizeof(double));
    pj->r = malloc(k2 * sizeof(double));
    return (pj->L && pj->W && pj->M && pj->r) ? 0 : -1;
}

static void proj_free(rfs_proj_t *pj)
{
    free(pj->L);
    free(pj->W);
    free(pj->M);
    free(pj->r);
}

static int work_alloc(rfs_work_t *wk)
{
    const size_t m = wk->m, k2 = wk->k2;
    int bad = proj_alloc(&wk->pj, m, k2);
    for (int f = 0; f < RFS_B; ++f)
    {
        bad |= proj_alloc(&wk->fold[f], m, k2);
    }
    wk->tmp = malloc(RFS_MAX_Q * k2 * sizeof(double));
    bad |= gram_alloc(&wk->all, m, k2) | gram_alloc(&wk->one, m, k2) | gram_alloc(&wk->tr, m, k2);
    return (bad == 0 && wk->tmp != NULL) ? 0 : -1;
}

static void work_free(rfs_work_t *wk)
{
    proj_free(&wk->pj);
    for (int f = 0; f < RFS_B; ++f)
    {
        proj_free(&wk->fold[f]);
    }
    free(wk->tmp);
    gram_free(&wk->all);
    gram_free(&wk->one);
    gram_free(&wk->tr);
}

/* The target channel ch: its regressors (and channel given's law tau, unless RFS_NONE), tent
 * nodes and scales (no allocation). */
static void work_setup(rfs_work_t *wk, const aenl_rfs_t *r, size_t ch, size_t given,
                       const double *tau)
{
    memset(wk, 0, sizeof(*wk));
    wk->rfs = r;
    wk->ch = ch;
    wk->given = given;
    wk->tau = tau;
    wk->K = r->cfg.n_nodes;
    wk->k2 = r->k2;
    wk->iy = 1u + ch * r->per_ch + 2u;
    for (size_t a = 0; a < r->p; ++a)
    {
        if (a != wk->iy)
        {
            wk->idx[wk->m++] = a;
        }
    }
    if (given != RFS_NONE)
    {
        wk->idx[wk->m++] = RFS_GIVEN;
    }
    const double lo = (r->cfg.lo[ch] - r->cfg.center[ch]) / r->cfg.scale[ch];
    const double hi = (r->cfg.hi[ch] - r->cfg.center[ch]) / r->cfg.scale[ch];
    wk->cell = (hi - lo) / (double)(wk->K - 1u);
    wk->x_abs = fmax(fabs(lo), fabs(hi));
    for (size_t k = 0; k < wk->K; ++k)
    {
        wk->node[k] = lo + wk->cell * (double)k;
    }
}

/* Where kinks may lie: between the RFS_TAIL and 1 - RFS_TAIL quantiles of the tent mass. */
static void interior(rfs_work_t *wk)
{
    const rfs_gram_t *g = &wk->all;
    const size_t K = wk->K;
    double mass[AENL_RFS_MAX_NODES], tot = 0.0;
    for (size_t k = 0; k < K; ++k)
    {
        mass[k] = 0.0;
        for (size_t d = 0; d < 2u; ++d)
        {
            const size_t i = d * K + k;
            mass[k] += g->BBd[i] + (k + 1u < K ? g->BBo[i] : 0.0) + (k > 0 ? g->BBo[i - 1u] : 0.0);
        }
        mass[k] = mass[k] > 0.0 ? mass[k] : 0.0;
        tot += mass[k];
    }
    double cum = 0.0;
    wk->lo_q = wk->node[0];
    wk->hi_q = wk->node[K - 1u];
    int have_lo = 0;
    for (size_t k = 0; k < K; ++k)
    {
        cum += mass[k];
        if (!have_lo && cum >= RFS_TAIL * tot)
        {
            wk->lo_q = wk->node[k];
            have_lo = 1;
        }
        if (cum <= (1.0 - RFS_TAIL) * tot)
        {
            wk->hi_q = wk->node[k + 1u < K ? k + 1u : k];
        }
    }
}

/* Paired batch-means t of fold gains a over fold gains b. */
static double pair_t(const double *a, const double *b)
{
    double diff[RFS_B];
    for (int f = 0; f < RFS_B; ++f)
    {
        diff[f] = a[f] - b[f];
    }
    return batch_t(diff, RFS_B);
}

/*
 * The law, from the fold gains d: linear unless a law the same in both directions reaches
 * AENL_RFS_T_CRIT. Among those, the smooth polynomial stands unless the best kinked law beats it by
 * a paired t of RFS_T_PAIR (a kinked law with free switching points can mimic a polynomial over a
 * bounded range, so kinks must earn their place); hysteresis replaces it only when the
 * direction-dependent law beats it by RFS_T_PAIR as well, both as they are and with the same
 * rising-motion offset, which may change with amplitude (a + b x^2), added to each (d_off): what
 * marks hysteresis is switching points that move with the direction, so that is all the second
 * comparison leaves to tell them apart. An offset alone is a force that follows the
 * motion, which dry friction, the kicks of a decay train, or damping the linear terms miss give
 * as well; damping that grows with the speed (|v| v, largest mid-stroke) and forcing whose
 * correlation with the direction of motion changes with amplitude (turbulence driving a
 * nonlinear spring) give one that changes smoothly with the position.
 */
static int choose_law(double d[AENL_RFS_N_LAWS][RFS_B], double d_off[AENL_RFS_N_LAWS][RFS_B],
                      const int *usable, const double *t, const double *D)
{
    double top = 0.0;
    for (int l = AENL_RFS_POLY; l <= AENL_RFS_GAP; ++l)
    {
        top = usable[l] && t[l] > top ? t[l] : top;
    }
    if (top < AENL_RFS_T_CRIT)
    {
        return AENL_RFS_LINEAR;
    }
    int kinked = -1;
    for (int l = AENL_RFS_KINK; l <= AENL_RFS_GAP; ++l)
    {
        if (usable[l] && (kinked < 0 || D[l] > D[kinked]))
        {
            kinked = l;
        }
    }
    int law;
    if (kinked < 0)
    {
        law = AENL_RFS_POLY;
    }
    else if (!usable[AENL_RFS_POLY] || t[AENL_RFS_POLY] < AENL_RFS_T_CRIT)
    {
        law = kinked;
    }
    else
    {
        law = pair_t(d[kinked], d[AENL_RFS_POLY]) >= RFS_T_PAIR ? kinked : AENL_RFS_POLY;
    }
    if (usable[AENL_RFS_HYSTERESIS] && pair_t(d[AENL_RFS_HYSTERESIS], d[law]) >= RFS_T_PAIR &&
        pair_t(d_off[AENL_RFS_HYSTERESIS], d_off[law]) >= RFS_T_PAIR)
    {
        law = AENL_RFS_HYSTERESIS;
    }
    return law;
}

/* Every law fitted to all data, and the fold gains of each over the linear law. */
typedef struct
{
    rfs_law_t law[AENL_RFS_N_LAWS];
    int usable[AENL_RFS_N_LAWS];
    double d[AENL_RFS_N_LAWS][RFS_B];     /* fold gains */
    double d_off[AENL_RFS_N_LAWS][RFS_B]; /* the same with a rising-motion offset */
    double rss_lin_cv;                    /* the linear law's test RSS over every fold */
} rfs_cv_t;

/* Each block has at least twice as many rows as the regression has unknowns; the rows used go
 * into out either way. */
static int enough_rows(const aenl_rfs_t *r, const rfs_work_t *wk, aenl_rfs_fit_t *out)
{
    size_t n_used = 0, min_rows = (size_t)-1;
    for (size_t b = 0; b < RFS_B; ++b)
    {
        n_used += r->rows[b];
        min_rows = r->rows[b] < min_rows ? r->rows[b] : min_rows;
    }
    out->n_used = n_used;
    return min_rows >= 2u * (wk->m + wk->k2);
}

/* The scratch, the sums over all blocks, their projection and the interior; on failure the
 * scratch is freed and err says why. */
static aenl_status_t work_prepare(rfs_work_t *wk, size_t ch, aenl_err_t *err)
{
    if (work_alloc(wk) != 0)
    {
        aenl_err_set(err, "out of memory");
        work_free(wk);
        return AENL_E_IO;
    }
    gram_sum(wk, -1, &wk->all);
    if (project(wk, &wk->all, &wk->pj) != 0)
    {
        aenl_err_set(err,
                     "restoring-force regression: the linear regressors of channel %zu are "
                     "degenerate",
                     ch);
        work_free(wk);
        return AENL_E_NUMERIC;
    }
    interior(wk);
    return AENL_OK;
}

/* Every law fitted on all data; a law whose fit fails is not usable. */
static void fit_laws(rfs_work_t *wk, rfs_cv_t *cv)
{
    for (int l = 0; l < AENL_RFS_N_LAWS; ++l)
    {
        cv->law[l].law = (aenl_rfs_law_t)l;
        cv->law[l].a = cv->law[l].b = cv->law[l].s = 0.0;
        cv->law[l].offset = 0;
        cv->usable[l] = law_fit_all(wk, &cv->law[l]) >= 0.0;
    }
}

/* The fold gains of fold f: the laws fitted without block f, scored on it. A law whose test
 * fails on any fold is not usable. */
static void fold_gains(rfs_work_t *wk, int f, double base, rfs_cv_t *cv)
{
    int ok = 1;
    for (int l = 0; l < AENL_RFS_N_LAWS; ++l)
    {
        cv->d[l][f] = 0.0;
        if (l > 0 && cv->usable[l])
        {
            const double v = test_rss(wk, &wk->fold[f], &cv->law[l], &wk->one, &ok);
            cv->d[l][f] = ok ? base - v : 0.0;
            cv->usable[l] = cv->usable[l] && ok;
        }
        /* every law with a rising-motion offset that may change with amplitude; the
         * offset's own fold gains, not the better of the law's with and without it on the
         * fold scored (that would pick the competitor on the test data) */
        cv->d_off[l][f] = cv->d[l][f];
        if (l >= AENL_RFS_POLY && cv->usable[l])
        {
            rfs_law_t lw_off = cv->law[l];
            lw_off.offset = 1;
            const double v = test_rss(wk, &wk->fold[f], &lw_off, &wk->one, &ok);
            cv->d_off[l][f] = ok ? base - v : cv->d[l][f];
        }
    }
}

/* Cross-validation: each block out in turn (its projection is kept for the jackknife). Nonzero
 * when the regressors of a fold are degenerate. */
static int cross_validate(rfs_work_t *wk, rfs_cv_t *cv)
{
    cv->rss_lin_cv = 0.0;
    for (int f = 0; f < RFS_B; ++f)
    {
        gram_sum(wk, f, &wk->one);
        gram_diff(wk, &wk->all, &wk->one, &wk->tr);
        if (project(wk, &wk->tr, &wk->fold[f]) != 0)
        {
            return -1;
        }
        int ok = 1;
        const double base = test_rss(wk, &wk->fold[f], &cv->law[0], &wk->one, &ok);
        cv->rss_lin_cv += base;
        fold_gains(wk, f, base, cv);
    }
    return 0;
}

/* The t and relative gain of every law, the chosen law and the evidence, into out; returns the
 * chosen law. */
static int score_laws(rfs_cv_t *cv, aenl_rfs_fit_t *out)
{
    double D[AENL_RFS_N_LAWS];
    for (int l = 0; l < AENL_RFS_N_LAWS; ++l)
    {
        D[l] = 0.0;
        for (int f = 0; f < RFS_B; ++f)
        {
            D[l] += cv->d[l][f];
        }
        out->t[l] = (l > 0 && cv->usable[l]) ? batch_t(cv->d[l], RFS_B) : 0.0;
        out->gain[l] = cv->rss_lin_cv > 0.0 ? D[l] / cv->rss_lin_cv : 0.0;
    }
    const int best = choose_law(cv->d, cv->d_off, cv->usable, out->t, D);
    /* the evidence is that of the laws the same in both directions: a direction-dependent
     * offset alone also fits excitation that follows the motion (the kicks of a decay train) */
    out->evidence = 0.0;
    for (int l = AENL_RFS_POLY; l <= AENL_RFS_GAP; ++l)
    {
        out->evidence = out->t[l] > out->evidence ? out->t[l] : out->evidence;
    }
    out->law = (aenl_rfs_law_t)best;
    return best;
}

/* The law's values at the tents, fitted on all data: a regressor for another channel. */
static void law_tents(rfs_work_t *wk, const rfs_law_t *lw, aenl_rfs_fit_t *out)
{
    double T[RFS_MAX_Q * 2 * AENL_RFS_MAX_NODES] = {0.0}, gb[RFS_MAX_Q] = {0.0};
    const size_t q = law_map(wk, lw, T);
    if (map_gain(wk, &wk->pj, T, q, gb) >= 0.0)
    {
        for (size_t k = 0; k < wk->k2; ++k)
        {
            for (size_t c = 0; c < q; ++c)
            {
                out->tents[k] += T[c * wk->k2 + k] * gb[c];
            }
        }
    }
}

/* Class weights: paired t of each law against the chosen one, normalised over the classes. */
static void class_weights(const rfs_cv_t *cv, int best, int saturating, aenl_rfs_fit_t *out)
{
    double wsum = 0.0;
    for (int l = 0; l < AENL_RFS_N_LAWS; ++l)
    {
        double tp;
        if (l == best)
        {
            tp = 0.0;
        }
        else if (!cv->usable[l] && l != AENL_RFS_LINEAR)
        {
            continue;
        }
        else
        {
            tp = pair_t(cv->d[best], cv->d[l]);
            if (best == AENL_RFS_LINEAR)
            {
                tp = AENL_RFS_T_CRIT - out->t[l]; /* how far the law is from being accepted */
            }
        }
        tp = tp > 0.0 ? tp : 0.0;
        const double wgt = exp(-0.5 * (tp > 30.0 ? 900.0 : tp * tp));
        const aenl_class_t c = law_class_of((aenl_rfs_law_t)l, saturating);
        out->prob[c] = wgt > out->prob[c] ? wgt : out->prob[c];
    }
    for (int c = 0; c < AENL_CLASS_COUNT; ++c)
    {
        wsum += out->prob[c];
    }
    for (int c = 0; c < AENL_CLASS_COUNT; ++c)
    {
        out->prob[c] = wsum > 0.0 ? out->prob[c] / wsum : 0.0;
    }
    out->confidence = out->prob[out->cls];
}

/* The switching points of the chosen law lw and their block-jackknife errors, in channel ch's
 * units. */
static void switching_points(rfs_work_t *wk, const aenl_rfs_t *r, size_t ch, const rfs_law_t *lw,
                             aenl_rfs_fit_t *out)
{
    double pt[4];
    out->n_points = out->cls == AENL_CLASS_POLYNOMIAL ? 0u : law_points(lw, pt);
    if (out->n_points == 0)
    {
        return;
    }
    double acc[4] = {0.0, 0.0, 0.0, 0.0}, acc2[4] = {0.0, 0.0, 0.0, 0.0};
    for (int f = 0; f < RFS_B; ++f)
    {
        rfs_law_t lf = *lw;
        (void)law_search(wk, &wk->fold[f], &lf, 2.0, RFS_FINE * 2.0);
        (void)law_search(wk, &wk->fold[f], &lf, 0.5, RFS_FINE * 0.5);
        double pf[4] = {0.0, 0.0, 0.0, 0.0}; /* as many as pt: the search keeps the law */
        (void)law_points(&lf, pf);
        for (size_t i = 0; i < out->n_points; ++i)
        {
            acc[i] += pf[i];
            acc2[i] += pf[i] * pf[i];
        }
    }
    for (size_t i = 0; i < out->n_points; ++i)
    {
        const double mean = acc[i] / RFS_B;
        const double var = acc2[i] / RFS_B - mean * mean;
        out->points[i] = r->cfg.center[ch] + r->cfg.scale[ch] * pt[i];
        /* the jackknife variance, plus that of the search grid's quantisation (a uniform
         * error over one step), which a jackknife on a grid cannot see */
        const double q = RFS_FINE * 0.5 * wk->cell;
        out->point_std[i] =
            r->cfg.scale[ch] * sqrt((double)(RFS_B - 1) * (var > 0.0 ? var : 0.0) + q * q / 12.0);
    }
}

static aenl_status_t analyse(const aenl_rfs_t *r, size_t ch, size_t given, const double *tau,
                             aenl_rfs_fit_t *out, aenl_err_t *err)
{
    memset(out, 0, sizeof(*out));
    out->cls = AENL_CLASS_INSUFFICIENT;
    rfs_work_t wk;
    work_setup(&wk, r, ch, given, tau);
    if (!enough_rows(r, &wk, out))
    {
        return AENL_OK; /* insufficient */
    }
    aenl_status_t st = work_prepare(&wk, ch, err);
    if (st != AENL_OK)
    {
        return st;
    }
    rfs_cv_t cv;
    fit_laws(&wk, &cv);
    double g_poly[RFS_MAX_Q] = {0.0};
    (void)law_gain(&wk, &wk.pj, &cv.law[AENL_RFS_POLY], g_poly);
    if (cross_validate(&wk, &cv) != 0)
    {
        aenl_err_set(err,
                     "restoring-force regression: degenerate regressors in a fold of "
                     "channel %zu",
                     ch);
        work_free(&wk);
        return AENL_E_NUMERIC;
    }
    const int best = score_laws(&cv, out);
    if (best != AENL_RFS_LINEAR)
    {
        law_tents(&wk, &cv.law[best], out);
    }
    /* A symmetric two-stiffness law is freeplay only when the band is the softer part: d2 = -f,
     * so a positive clip coefficient takes stiffness away inside. Stiffer inside than outside is
     * a saturating spring: polynomial, softening. */
    double g_gap[RFS_MAX_Q] = {0.0};
    const int saturating = cv.usable[AENL_RFS_GAP] &&
                           law_gain(&wk, &wk.pj, &cv.law[AENL_RFS_GAP], g_gap) >= 0.0 &&
                           g_gap[0] < 0.0;
    out->cls = law_class_of(out->law, saturating);
    class_weights(&cv, best, saturating, out);
    if (out->law == AENL_RFS_POLY)
    {
        /* d2 = -f: a negative cubic term stiffens as the motion leaves the centre (a quintic
         * term may turn it round further out; docs/identify.md names the law by its cubic
         * term) */
        out->hardening = g_poly[1] < 0.0 ? 1 : -1;
    }
    else if (out->cls == AENL_CLASS_POLYNOMIAL)
    {
        out->hardening = -1; /* the saturating gap law */
    }
    switching_points(&wk, r, ch, &cv.law[best], out);
    work_free(&wk);
    return AENL_OK;
}

aenl_status_t aenl_rfs_analyse(const aenl_rfs_t *r, size_t ch, aenl_rfs_fit_t *out, aenl_err_t *err)
{
    if (r == NULL || out == NULL || ch >= r->cfg.n_ch)
    {
        aenl_err_set(err, "restoring-force regression: bad channel");
        return AENL_E_ARG;
    }
    return analyse(r, ch, RFS_NONE, NULL, out, err);
}

aenl_status_t aenl_rfs_analyse_given(const aenl_rfs_t *r, size_t ch, size_t given,
                                     const aenl_rfs_fit_t *given_fit, aenl_rfs_fit_t *out,
                                     aenl_err_t *err)
{
    if (r == NULL || out == NULL || given_fit == NULL || ch >= r->cfg.n_ch ||
        given >= r->cfg.n_ch || given == ch)
    {
        aenl_err_set(err, "restoring-force regression: bad channel");
        return AENL_E_ARG;
    }
    if (given_fit->law == AENL_RFS_LINEAR || given_fit->cls <= AENL_CLASS_LINEAR)
    {
        return analyse(r, ch, RFS_NONE, NULL, out, err); /* nothing to add */
    }
    return analyse(r, ch, given, given_fit->tents, out, err);
}

/* ---- the free-law model: equation residuals ------------------------------------------------ */

/* Channel ch's free law: every tent coefficient free on top of the linear terms, fitted on all
 * blocks, into coef[p + k2] (the regressor weights, the own second difference's 0, then the
 * tents). The tents span constant and linear functions of the position already in the linear
 * terms, and a tent the motion never reached has no data, so a ridge of 1e-9 of the mean tent
 * mass picks the smallest such coefficients; it does not change the fitted values. */
static int model_channel(const aenl_rfs_t *r, size_t ch, double *coef)
{
    rfs_work_t wk;
    work_setup(&wk, r, ch, RFS_NONE, NULL);
    const size_t m = wk.m, k2 = wk.k2, st = k2 + 1u;
    if (m == 0 || k2 == 0)
    {
        return -1; /* cannot happen for a created accumulator */
    }
    int bad = proj_alloc(&wk.pj, m, k2) | gram_alloc(&wk.all, m, k2);
    double *gam = malloc(k2 * sizeof(double));
    if (bad != 0 || gam == NULL)
    {
        bad = -2;
    }
    else
    {
        gram_sum(&wk, -1, &wk.all);
        bad = project(&wk, &wk.all, &wk.pj);
    }
    if (bad == 0)
    {
        double mass = 0.0;
        for (size_t k = 0; k < k2; ++k)
        {
            mass += wk.all.BBd[k];
        }
        for (size_t k = 0; k < k2; ++k)
        {
            wk.pj.M[k * k2 + k] += 1e-9 * mass / (double)k2 + 1e-300;
        }
        memcpy(gam, wk.pj.r, k2 * sizeof(double));
        bad = spd_factor(wk.pj.M, k2, 0.0);
    }
    if (bad == 0)
    {
        aenl_dense_potrs(wk.pj.M, k2, gam, 1);
        memset(coef, 0, (r->p + k2) * sizeof(double));
        for (size_t a = 0; a < m; ++a)
        {
            double b = wk.pj.W[a * st + k2];
            for (size_t k = 0; k < k2; ++k)
            {
                b -= wk.pj.W[a * st + k] * gam[k];
            }
            coef[wk.idx[a]] = b;
        }
        memcpy(&coef[r->p], gam, k2 * sizeof(double));
    }
    free(gam);
    proj_free(&wk.pj);
    gram_free(&wk.all);
    return bad;
}

aenl_status_t aenl_rfs_model(aenl_rfs_t *r, aenl_err_t *err)
{
    if (r == NULL)
    {
        aenl_err_set(err, "restoring-force regression: no accumulator");
        return AENL_E_ARG;
    }
    const size_t len = r->p + r->k2;
    double *coef = malloc(r->cfg.n_ch * len * sizeof(double));
    if (coef == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_IO;
    }
    for (size_t ch = 0; ch < r->cfg.n_ch; ++ch)
    {
        const int bad = model_channel(r, ch, &coef[ch * len]);
        if (bad != 0)
        {
            free(coef);
            if (bad == -2)
            {
                aenl_err_set(err, "out of memory");
                return AENL_E_IO;
            }
            aenl_err_set(err,
                         "restoring-force regression: the regressors of channel %zu are "
                         "degenerate",
                         ch);
            return AENL_E_NUMERIC;
        }
    }
    free(r->coef);
    r->coef = coef;
    aenl_rfs_rewind(r);
    return AENL_OK;
}

void aenl_rfs_rewind(aenl_rfs_t *r)
{
    if (r != NULL)
    {
        r->pushed = 0;
    }
}

void aenl_rfs_residual(aenl_rfs_t *r, const double *row, double *e)
{
    if (r == NULL || row == NULL || e == NULL)
    {
        return;
    }
    const size_t nc = r->cfg.n_ch;
    const int whole = form_row(r, row) && r->coef != NULL;
    const size_t len = r->p + r->k2;
    for (size_t i = 0; i < nc; ++i)
    {
        e[i] = (double)NAN;
        if (!whole)
        {
            continue;
        }
        const double *c = &r->coef[i * len];
        const double *wi = &r->w[1u + i * r->per_ch];
        double v = wi[2];
        for (size_t a = 0; a < r->p; ++a)
        {
            v -= c[a] * r->w[a];
        }
        double w1;
        const size_t col = tent_col(r, i, wi, &w1);
        e[i] = v - (1.0 - w1) * c[r->p + col] - w1 * c[r->p + col + 1u];
    }
}
