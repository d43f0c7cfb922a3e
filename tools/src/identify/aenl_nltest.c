/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_nltest.c
 * @brief Identification from the record alone as a score test on Kalman innovations, then the
 *        law by a test between the laws' per-sample fits (aenl_nltest.h has the method).
 *
 * Layout: the linear fit (aenl_em, one mode), one Kalman filter pass that keeps what the
 * regressions need (whitened innovations, the whitened output matrix and the transition of the
 * innovations' sensitivity at every step, shared once the filter reaches its steady state),
 * then regressions whose columns are the sensitivities of the innovations to a force along B:
 * D_{t+1} = A (I - K_t C) D_t + B g_t, row block -S_t^{-1/2} C D_t. A series is either "full"
 * (B free: one column per state) or "directed" (B fixed to a direction: one column).
 */
#include "aenl_tools/aenl_nltest.h"

#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_tools/aenl_dense.h"
#include "aenl_tools/aenl_em.h"
#include "aenl_tools/aenl_parallel.h"
#include "aenl_tools/aenl_rng.h"
#include "aenl_tools/aenl_sort.h"
#include "aenl_tools/aenl_stats.h"
#include "aenl_nlt_internal.h"

#define NLT_N_QUANT     25 /* coarse switching-point grid: points evenly over the motion */
#define NLT_N_FINE      9  /* fine grid points per switching point */
#define NLT_HOLD        2u /* values of an input per step: at its start and its end */
#define NLT_STAGE1_LAWS 4  /* u^2, u^3, d, d u */
#define NLT_N_ORDERS    3  /* candidate model orders: 4 and 6 states a channel, and 12 */
#define NLT_JUMP_ROUNDS 3  /* refits of the linear model with its impulses as state jumps */

/* every input's two values fit among the EM fit's inputs */
typedef char nlt_inputs_fit[(NLT_HOLD * AENL_NLT_MAX_INPUT <= AENL_EM_MAX_U) ? 1 : -1];

/* ---- stage 2: the laws along a fixed direction ----------------------------------------------- */

/* Gain of one column x = sum_i c_i s_i (nc entries of idx/coef). */
static double gain1(const resid_t *r, const size_t *idx, const double *c, size_t n)
{
    double num = 0.0;
    double den = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        num += c[i] * r->rt[idx[i]];
        for (size_t j = 0; j < n; ++j)
        {
            den += c[i] * c[j] * r->Gt[idx[i] * r->ns + idx[j]];
        }
    }
    return den > 0.0 ? num * num / den : 0.0;
}

/* Gain of two columns: x1 as in gain1, x2 the single series j2. */
static double gain2(const resid_t *r, const size_t *idx, const double *c, size_t n, size_t j2)
{
    double r1 = 0.0;
    double g11 = 0.0;
    double g12 = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        r1 += c[i] * r->rt[idx[i]];
        g12 += c[i] * r->Gt[idx[i] * r->ns + j2];
        for (size_t j = 0; j < n; ++j)
        {
            g11 += c[i] * c[j] * r->Gt[idx[i] * r->ns + idx[j]];
        }
    }
    const double r2 = r->rt[j2];
    const double g22 = r->Gt[j2 * r->ns + j2];
    const double det = g11 * g22 - g12 * g12;
    if (!(det > 1e-14 * g11 * g22) || g11 <= 0.0)
    {
        return fmax(g11 > 0.0 ? r1 * r1 / g11 : 0.0, g22 > 0.0 ? r2 * r2 / g22 : 0.0);
    }
    return (g22 * r1 * r1 - 2.0 * g12 * r1 * r2 + g11 * r2 * r2) / det;
}

/* Series of stage 2 for one channel: fixed shapes, then rising and falling hinges at knots. */
enum
{
    S2_U3 = 0,
    S2_U5 = 1,
    S2_D = 2,
    S2_FIXED = 3
};

typedef struct
{
    size_t nk;
    const double *knots; /* ascending */
    double *buf;         /* (S2_FIXED + 2 nk) x n */
    const double **g;
    int *full;
} s2_series_t;

static int s2_build(s2_series_t *s, const double *u, const double *dsg, size_t n,
                    const double *const *nuis, size_t n_nuis, const double *knots, size_t nk)
{
    const size_t ns = n_nuis + S2_FIXED + 2u * nk;
    s->nk = nk;
    s->knots = knots;
    s->buf = (double *)malloc((S2_FIXED + 2u * nk) * n * sizeof(double));
    s->g = (const double **)malloc(ns * sizeof(double *));
    s->full = (int *)malloc(ns * sizeof(int));
    if (s->buf == NULL || s->g == NULL || s->full == NULL)
    {
        return -1;
    }
    for (size_t i = 0; i < n_nuis; ++i)
    {
        s->g[i] = nuis[i];
        s->full[i] = 1;
    }
    for (size_t i = n_nuis; i < ns; ++i)
    {
        s->g[i] = s->buf + (i - n_nuis) * n;
        s->full[i] = 0;
    }
    double *u3 = s->buf + S2_U3 * n;
    double *u5 = s->buf + S2_U5 * n;
    double *dd = s->buf + S2_D * n;
    for (size_t t = 0; t < n; ++t)
    {
        const double v = u[t];
        u3[t] = v * v * v;
        u5[t] = u3[t] * v * v;
        dd[t] = dsg[t];
    }
    for (size_t k = 0; k < nk; ++k)
    {
        double *up = s->buf + (S2_FIXED + k) * n;
        double *dn = s->buf + (S2_FIXED + nk + k) * n;
        for (size_t t = 0; t < n; ++t)
        {
            const double h = fmax(u[t] - knots[k], 0.0);
            up[t] = dsg[t] > 0.0 ? h : 0.0;
            dn[t] = dsg[t] < 0.0 ? h : 0.0;
        }
    }
    return 0;
}

static void s2_free(s2_series_t *s)
{
    free(s->buf);
    free((void *)s->g);
    free(s->full);
    memset(s, 0, sizeof(*s));
}

static size_t knot_index(const double *knots, size_t nk, double v)
{
    size_t best = 0;
    for (size_t k = 1; k < nk; ++k)
    {
        if (fabs(knots[k] - v) < fabs(knots[best] - v))
        {
            best = k;
        }
    }
    return best;
}

/* Freeplay gap [k1, k2] (knot indices): h(k1) - h(k2), h = rising + falling hinge. */
static double freeplay_gain(const resid_t *r, size_t nk, size_t k1, size_t k2)
{
    const size_t idx[4] = {S2_FIXED + k1, S2_FIXED + nk + k1, S2_FIXED + k2, S2_FIXED + nk + k2};
    const double c[4] = {1.0, 1.0, -1.0, -1.0};
    return gain1(r, idx, c, 4);
}

/* Hysteresis with rising gap [a1, a2] and falling gap [-a2, -a1] (knot indices; the knot set is
 * symmetric, so -a is knot nk-1-a), with the direction-dependent preload. */
static double hysteresis_gain(const resid_t *r, size_t nk, size_t a1, size_t a2)
{
    const size_t m1 = nk - 1u - a1;
    const size_t m2 = nk - 1u - a2;
    const size_t idx[4] = {S2_FIXED + a1, S2_FIXED + a2, S2_FIXED + nk + m2, S2_FIXED + nk + m1};
    const double c[4] = {1.0, -1.0, 1.0, -1.0};
    return gain2(r, idx, c, 4, S2_D);
}

/* Profile of a two-point law over a knot grid: best pair and, per point, the 95 % range. */
typedef struct
{
    double best;
    size_t k1, k2;
    double lo1, hi1, lo2, hi2; /* knot values */
} profile_t;

typedef double (*pair_gain_fn)(const resid_t *r, size_t nk, size_t a, size_t b);

static void profile_pairs(const resid_t *r, const double *knots, size_t nk, const size_t *c1,
                          size_t n1, const size_t *c2, size_t n2, pair_gain_fn fn, double s2,
                          profile_t *p)
{
    double *tab = (double *)malloc(n1 * n2 * sizeof(double));
    p->best = -1.0;
    p->k1 = c1[0];
    p->k2 = c2[0];
    p->lo1 = p->hi1 = knots[p->k1];
    p->lo2 = p->hi2 = knots[p->k2];
    if (tab == NULL)
    {
        return; /* no pair evaluated: best stays -1, the law's gain 0 */
    }
    for (size_t i = 0; i < n1; ++i)
    {
        for (size_t j = 0; j < n2; ++j)
        {
            double v = -1.0;
            if (knots[c1[i]] < knots[c2[j]])
            {
                v = fn(r, nk, c1[i], c2[j]);
            }
            tab[i * n2 + j] = v;
            if (v > p->best)
            {
                p->best = v;
                p->k1 = c1[i];
                p->k2 = c2[j];
            }
        }
    }
    const double cut = p->best - NLT_CHI2_1_95 * s2;
    p->lo1 = p->hi1 = knots[p->k1];
    p->lo2 = p->hi2 = knots[p->k2];
    for (size_t i = 0; i < n1; ++i)
    {
        for (size_t j = 0; j < n2; ++j)
        {
            if (tab[i * n2 + j] >= cut)
            {
                p->lo1 = fmin(p->lo1, knots[c1[i]]);
                p->hi1 = fmax(p->hi1, knots[c1[i]]);
                p->lo2 = fmin(p->lo2, knots[c2[j]]);
                p->hi2 = fmax(p->hi2, knots[c2[j]]);
            }
        }
    }
    free(tab);
}

/* The symmetric knot set: the coarse quantiles of u and their negatives, sorted, duplicates
 * (closer than 1e-9 of the range) merged; knots[i] = -knots[nk-1-i]. */
static size_t symmetric_knots(const double *q, size_t nq, double *knots)
{
    size_t n = 0;
    double span = 0.0;
    for (size_t i = 0; i < nq; ++i)
    {
        span = fmax(span, fabs(q[i]));
    }
    for (size_t i = 0; i < nq; ++i)
    {
        knots[n++] = fabs(q[i]);
    }
    aenl_sort_doubles(knots, n);
    size_t m = 0;
    for (size_t i = 0; i < n; ++i)
    {
        if (knots[i] <= 1e-9 * span)
        {
            continue; /* zero is added once below */
        }
        if (m == 0 || knots[i] - knots[m - 1] > 1e-9 * span)
        {
            knots[m++] = knots[i];
        }
    }
    /* mirror: negatives (descending magnitude), zero, positives */
    double tmp[4 * NLT_N_QUANT + 8];
    size_t k = 0;
    for (size_t i = m; i-- > 0;)
    {
        tmp[k++] = -knots[i];
    }
    tmp[k++] = 0.0;
    for (size_t i = 0; i < m; ++i)
    {
        tmp[k++] = knots[i];
    }
    memcpy(knots, tmp, k * sizeof(double));
    return k;
}

/* ---- the whole run --------------------------------------------------------------------------- */

/* The freeplay law's series: the motion's part beyond a, up to b (a <= b). */
static double gap_ramp(double u, double a, double b)
{
    return fmax(u - a, 0.0) - fmax(u - b, 0.0);
}

/* The hysteresis law's series: the ramp on the branch of the motion's direction dir (the
 * falling branch mirrors the rising one), 0 at rest. */
static double loop_branch(double u, double a1, double a2, double dir)
{
    return dir > 0.0 ? gap_ramp(u, a1, a2) : dir < 0.0 ? gap_ramp(u, -a2, -a1) : 0.0;
}

void aenl_nlt_opts_default(aenl_nlt_opts_t *opts)
{
    memset(opts, 0, sizeof(*opts));
    opts->level = 0.01;
    opts->min_confidence = 0.9;
    opts->n_states = 0;
    opts->em_iter = 200;
    opts->control_seed = 1u;
}

double aenl_nlt_law_force(const aenl_nlt_channel_t *c, aenl_nlt_law_t law, double u, int dir)
{
    if (c == NULL || !c->laws_fitted || (unsigned)law >= AENL_NLT_N_LAWS || !(c->law_scale > 0.0))
    {
        return (double)NAN;
    }
    const double v = u / c->law_scale;
    const double *k = c->law_coef[law];
    const double *p = c->law_pts[law];
    double f = 0.0;
    switch (law)
    {
        case AENL_NLT_POLYNOMIAL:
            f = k[0] * v * v * v + k[1] * v * v * v * v * v;
            break;
        case AENL_NLT_FREEPLAY:
            f = k[0] * gap_ramp(v, p[0], p[1]);
            break;
        case AENL_NLT_HYSTERESIS:
        case AENL_NLT_N_LAWS:
        default:
            f = dir != 0 ? k[0] * loop_branch(v, p[0], p[1], (double)dir) + (dir > 0 ? k[1] : -k[1])
                         : 0.0;
            break;
    }
    return c->law_sign < 0 ? -f : f;
}

const char *aenl_nlt_law_name(aenl_nlt_law_t law)
{
    switch (law)
    {
        case AENL_NLT_POLYNOMIAL:
            return "polynomial";
        case AENL_NLT_FREEPLAY:
            return "freeplay";
        case AENL_NLT_HYSTERESIS:
            return "hysteresis";
        case AENL_NLT_N_LAWS:
        default:
            return "?";
    }
}

typedef struct
{
    const aenl_nlt_opts_t *opts;
    const kf_t *kf;
    const aenl_em_model_t *m;
    size_t n, nz, nx;
    double scale[AENL_NLT_MAX_CH];
    double *one, *lin, *dsg, *work;      /* n each; work: 4 n for stage 1 */
    const double *in_col[AENL_EM_MAX_U]; /* the scaled inputs, one series each */
    size_t n_in;
    double lnrows;
    /* the laws' per-sample losses, channel j's at loss + j n AENL_NLT_N_LAWS (rows x laws), and
     * their criteria (summed loss + penalty), for the comparison across channels */
    double *loss;
    double crit[AENL_NLT_MAX_CH][AENL_NLT_N_LAWS];
    int compared[AENL_NLT_MAX_CH]; /* 1: channel j's laws were fitted */
    double *G_nn; /* the nuisance's cross-products, the same in every design (n_nuis nx square) */
    double *R_nn; /* the nuisance's whitened sensitivities (design_t.R_known), NULL: walked again */
} run_t;

/* The direction of motion of u: +1 rising, -1 falling, 0 at rest. */
static void direction(const double *u, size_t nz, size_t j, size_t n, double *d)
{
    d[0] = 0.0;
    for (size_t t = 1; t < n; ++t)
    {
        const double du = u[t * nz + j] - u[(t - 1u) * nz + j];
        d[t] = (du > 0.0) - (du < 0.0);
    }
}

/* Stage 1's law series of the channel in rn->lin, in rn->work: law l (u^2, u^3, d, d u with d
 * the direction of motion) at rn->work + l n. */
static void stage1_series(const run_t *rn)
{
    const size_t n = rn->n;
    double *u2 = rn->work;
    double *u3 = rn->work + n;
    double *dd = rn->work + 2u * n;
    double *du = rn->work + 3u * n;
    for (size_t t = 0; t < n; ++t)
    {
        const double v = rn->lin[t];
        u2[t] = v * v;
        u3[t] = v * v * v;
        dd[t] = rn->dsg[t];
        du[t] = rn->dsg[t] * v;
    }
}

/* What stage 1's regression yields. */
typedef struct
{
    double red_n, red_f; /* reductions of the squared innovations: nuisance only, and with laws */
    double q;            /* the robust score statistic of the laws */
    size_t n_nuis;       /* nuisance series (the laws' series follow) */
    size_t ncols;
    double beta[(NLT_NUIS_MAX + NLT_STAGE1_LAWS) * NLT_MAX_X]; /* coefficients of the full fit */
} s1_fit_t;

/* The robust score statistic of the columns nn.. of d given the nuisance columns 0..nn-1 into
 * *q (NaN when it fails). */
static aenl_status_t robust_score(const design_t *d, const kf_t *kf, size_t nn, double *q,
                                  aenl_err_t *err)
{
    const size_t nl = d->ncols - nn;
    double *Pi = (double *)malloc(nn * nl * sizeof(double));
    double *score = (double *)malloc(nl * sizeof(double));
    double *meat = (double *)malloc(nl * nl * sizeof(double));
    aenl_status_t st = AENL_OK;
    if (Pi == NULL || score == NULL || meat == NULL)
    {
        aenl_err_set(err, "out of memory");
        st = AENL_E_DIM;
    }
    if (st == AENL_OK)
    {
        st = nlt_partial_coefficients(d, nn, Pi, err);
    }
    if (st == AENL_OK)
    {
        st = nlt_design_robust(d, kf, nn, Pi, score, meat, err);
    }
    *q = st == AENL_OK ? nlt_quad_inverse(meat, score, nl) : (double)NAN;
    free(Pi);
    free(score);
    free(meat);
    return st;
}

/* The nuisance series of every regression, full: an offset and a perturbation of A along every
 * filtered state (the first-order change of the fitted linear model, so that its estimation error
 * is not taken for a law), and of B along every input. Returns their count. */
static size_t nuisance_series(const run_t *rn, const double **nuis)
{
    nuis[0] = rn->one;
    for (size_t i = 0; i < rn->nx; ++i)
    {
        nuis[1u + i] = rn->kf->xs + i * rn->n;
    }
    for (size_t p = 0; p < rn->n_in; ++p)
    {
        nuis[1u + rn->nx + p] = rn->in_col[p];
    }
    return 1u + rn->nx + rn->n_in;
}

/* Stage 1's regression: the law series of stage1_series, full, after the nuisance. */
static aenl_status_t stage1_regress(const run_t *rn, s1_fit_t *f, aenl_err_t *err)
{
    const size_t n = rn->n;
    const size_t nx = rn->nx;
    const double *g[NLT_NUIS_MAX + NLT_STAGE1_LAWS];
    int full[NLT_NUIS_MAX + NLT_STAGE1_LAWS];
    size_t ns = nuisance_series(rn, g);
    f->n_nuis = ns;
    for (size_t l = 0; l < NLT_STAGE1_LAWS; ++l)
    {
        g[ns++] = rn->work + l * n;
    }
    for (size_t i = 0; i < ns; ++i)
    {
        full[i] = 1;
    }
    design_t d = {ns, g, full, NULL, 0, NULL, NULL, rn->G_nn, f->n_nuis * nx, rn->R_nn, NULL};
    aenl_status_t st = nlt_design_accumulate(&d, rn->kf, err);
    if (st != AENL_OK)
    {
        nlt_design_free(&d);
        return st;
    }
    size_t idx[(NLT_NUIS_MAX + NLT_STAGE1_LAWS) * NLT_MAX_X];
    for (size_t i = 0; i < d.ncols; ++i)
    {
        idx[i] = i;
    }
    f->red_n = nlt_fit_subset(&d, idx, f->n_nuis * nx, NULL);
    f->red_f = nlt_fit_subset(&d, idx, d.ncols, f->beta);
    f->ncols = d.ncols;
    st = robust_score(&d, rn->kf, f->n_nuis * nx, &f->q, err);
    nlt_design_free(&d);
    return st;
}

/* The law coefficients of stage 1 (nx x 4) into M, each column weighted by its regressor's
 * spread so that the direction does not depend on the laws' units. */
static void weighted_law_coefficients(const run_t *rn, const s1_fit_t *f, double *M)
{
    const size_t n = rn->n;
    const size_t nx = rn->nx;
    for (size_t l = 0; l < NLT_STAGE1_LAWS; ++l)
    {
        const double *gl = rn->work + l * n;
        double mean = 0.0;
        double var = 0.0;
        for (size_t t = 0; t < n; ++t)
        {
            mean += gl[t];
        }
        mean /= (double)n;
        for (size_t t = 0; t < n; ++t)
        {
            var += (gl[t] - mean) * (gl[t] - mean);
        }
        const double sd = sqrt(var / (double)n);
        for (size_t i = 0; i < nx; ++i)
        {
            M[i * NLT_STAGE1_LAWS + l] = f->beta[(f->n_nuis + l) * nx + i] * sd;
        }
    }
}

/* The leading left singular vector of M (nx x 4) into v, by power iteration on M M'. */
static void leading_direction(const double *M, size_t nx, double *v)
{
    for (size_t i = 0; i < nx; ++i)
    {
        v[i] = 1.0 / sqrt((double)nx);
    }
    for (int it = 0; it < 200; ++it)
    {
        double w[NLT_STAGE1_LAWS] = {0};
        double v2[NLT_MAX_X] = {0};
        for (size_t l = 0; l < NLT_STAGE1_LAWS; ++l)
        {
            for (size_t i = 0; i < nx; ++i)
            {
                w[l] += M[i * NLT_STAGE1_LAWS + l] * v[i];
            }
        }
        double nrm = 0.0;
        for (size_t i = 0; i < nx; ++i)
        {
            for (size_t l = 0; l < NLT_STAGE1_LAWS; ++l)
            {
                v2[i] += M[i * NLT_STAGE1_LAWS + l] * w[l];
            }
            nrm += v2[i] * v2[i];
        }
        nrm = sqrt(nrm);
        if (!(nrm > 0.0))
        {
            break;
        }
        double change = 0.0;
        for (size_t i = 0; i < nx; ++i)
        {
            change = fmax(change, fabs(v2[i] / nrm - v[i]));
            v[i] = v2[i] / nrm;
        }
        if (change < 1e-12)
        {
            break;
        }
    }
}

/* Stage 1 for channel j: the generic score test; dir receives the force direction. */
static aenl_status_t stage1(run_t *rn, size_t j, aenl_nlt_channel_t *c, double *dir, double *s2,
                            aenl_err_t *err)
{
    const size_t nx = rn->nx;
    stage1_series(rn);
    s1_fit_t f;
    aenl_status_t st = stage1_regress(rn, &f, err);
    if (st != AENL_OK)
    {
        return st;
    }
    if (!isfinite(f.red_n) || !isfinite(f.red_f) || !isfinite(f.q))
    {
        aenl_err_set(err, "channel %lu: the test regression is singular", (unsigned long)j);
        return AENL_E_NUMERIC;
    }
    const double dof_res = (double)rn->kf->rows - (double)f.ncols;
    *s2 = fmax((rn->kf->ee - f.red_f) / dof_res, 1e-300);
    c->dof = (double)(NLT_STAGE1_LAWS * nx);
    c->stat = fmax(f.q, 0.0);
    /* The laws are compared with the classical (homoskedastic) gains; where the robust score
     * says the innovations' spread makes those gains overstate the evidence, they are scaled
     * down by that ratio (a quasi-likelihood dispersion, as in QAIC). */
    const double classic = fmax(f.red_f - f.red_n, 0.0) / *s2;
    const double disp = c->stat > 0.0 ? classic / c->stat : 1.0;
    *s2 *= fmax(disp, 1.0);
    c->p = aenl_chi2_sf(c->stat, c->dof);
    /* direction: the leading left singular vector of the weighted law coefficients */
    double M[NLT_MAX_X * NLT_STAGE1_LAWS];
    weighted_law_coefficients(rn, &f, M);
    double v[NLT_MAX_X];
    leading_direction(M, nx, v);
    memcpy(dir, v, nx * sizeof(double));
    return AENL_OK;
}

/* Sign of the change of the most sensitive oscillatory frequency of A + eps dir c_j' with eps. */
static int frequency_sensitivity(const aenl_em_model_t *m, const double *dir, size_t j)
{
    const size_t nx = m->n_x;
    double best = 0.0;
    double fr[2][NLT_MAX_X];
    double fi[2][NLT_MAX_X];
    const double h = 1e-4;
    for (int s = 0; s < 2; ++s)
    {
        double A[NLT_MAX_X * NLT_MAX_X];
        const double eps = s == 0 ? -h : h;
        for (size_t a = 0; a < nx; ++a)
        {
            for (size_t b = 0; b < nx; ++b)
            {
                A[a * nx + b] = m->A[a * nx + b] + eps * dir[a] * m->C[j * nx + b];
            }
        }
        if (LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', (lapack_int)nx, A, (lapack_int)nx, fr[s],
                          fi[s], NULL, 1, NULL, 1) != 0)
        {
            return 0;
        }
    }
    int sign = 0;
    for (size_t a = 0; a < nx; ++a)
    {
        if (fi[0][a] <= 0.0)
        {
            continue;
        }
        /* the same eigenvalue after the perturbation: the nearest with Im > 0 */
        size_t b = 0;
        double dist = INFINITY;
        for (size_t c = 0; c < nx; ++c)
        {
            const double dd = hypot(fr[1][c] - fr[0][a], fi[1][c] - fi[0][a]);
            if (fi[1][c] > 0.0 && dd < dist)
            {
                dist = dd;
                b = c;
            }
        }
        const double w0 = atan2(fi[0][a], fr[0][a]);
        const double w1 = atan2(fi[1][b], fr[1][b]);
        if (fabs(w1 - w0) > best)
        {
            best = fabs(w1 - w0);
            sign = (w1 > w0) - (w1 < w0);
        }
    }
    return sign;
}

/* Stage 2's coarse grid: q, NLT_N_QUANT points evenly over the motion, and their symmetric
 * knot set knots (*nk knots). */
static aenl_status_t coarse_grid(const run_t *rn, double *q, double *knots, size_t *nk,
                                 aenl_err_t *err)
{
    const size_t n = rn->n;
    double *sorted = (double *)malloc(n * sizeof(double));
    if (sorted == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    memcpy(sorted, rn->lin, n * sizeof(double));
    aenl_sort_doubles(sorted, n);
    /* Evenly over the range of motion (its 0.5 % and 99.5 % quantiles): a switching point may be
     * anywhere the motion goes, and a free decay spends most of its samples near rest. */
    const double q_lo = sorted[(size_t)(0.005 * (double)(n - 1u))];
    const double q_hi = sorted[(size_t)(0.995 * (double)(n - 1u))];
    for (size_t i = 0; i < NLT_N_QUANT; ++i)
    {
        q[i] = q_lo + (q_hi - q_lo) * (double)i / (double)(NLT_N_QUANT - 1u);
    }
    free(sorted);
    *nk = symmetric_knots(q, NLT_N_QUANT, knots);
    return AENL_OK;
}

/* Stage 2's series over the knot set knots (nk knots) along dir, residualised on the nuisance
 * into r. On failure r is freed. */
static aenl_status_t stage2_residuals(const run_t *rn, const double *dir, const double *const *nuis,
                                      size_t n_nuis, const double *knots, size_t nk, resid_t *r,
                                      aenl_err_t *err)
{
    s2_series_t ser;
    memset(&ser, 0, sizeof(ser));
    if (s2_build(&ser, rn->lin, rn->dsg, rn->n, nuis, n_nuis, knots, nk) != 0)
    {
        s2_free(&ser);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    design_t d = {n_nuis + S2_FIXED + 2u * nk,
                  ser.g,
                  ser.full,
                  dir,
                  0,
                  NULL,
                  NULL,
                  rn->G_nn,
                  n_nuis * rn->nx,
                  rn->R_nn,
                  NULL};
    aenl_status_t st = nlt_design_accumulate(&d, rn->kf, err);
    if (st == AENL_OK)
    {
        st = nlt_residualise(&d, n_nuis * rn->nx, r, err);
    }
    nlt_design_free(&d);
    s2_free(&ser);
    if (st != AENL_OK)
    {
        nlt_resid_free(r);
    }
    return st;
}

/* The polynomial law: *quintic 1 when the quintic term earns its place beside the cubic (by
 * the criterion). Returns the cubic coefficient, whose sign tells hardening from softening. */
static double polynomial_law(const run_t *rn, const resid_t *r, double s2, int *quintic)
{
    const size_t i3 = S2_U3;
    const double one = 1.0;
    const double g3 = gain1(r, &i3, &one, 1);
    const double g35 = gain2(r, &i3, &one, 1, S2_U5);
    const double bic3 = -g3 / s2 + 1.0 * rn->lnrows;
    const double bic35 = -g35 / s2 + 2.0 * rn->lnrows;
    *quintic = bic35 < bic3;
    return r->Gt[i3 * r->ns + i3] > 0.0 ? r->rt[i3] / r->Gt[i3 * r->ns + i3] : 0.0;
}

/* The fine grid around the four points centres (coarse knot indices cidx of knots, nk knots):
 * NLT_N_FINE points each, spaced a quarter of the local coarse spacing, with their mirrors;
 * sorted, duplicates merged. Returns the number of fine knots. The set stays symmetric:
 * fine[i] = -fine[nfu-1-i] holds by construction of the pairs. */
static size_t fine_grid(const double *knots, size_t nk, const double *centres, const size_t *cidx,
                        double *fine)
{
    size_t nf = 0;
    for (size_t a = 0; a < 4; ++a)
    {
        const size_t kk = cidx[a];
        const double lo = kk > 0 ? knots[kk - 1u] : knots[kk] - (knots[1] - knots[0]);
        const double hi =
            kk + 1u < nk ? knots[kk + 1u] : knots[kk] + (knots[nk - 1u] - knots[nk - 2u]);
        for (size_t f = 0; f < NLT_N_FINE; ++f)
        {
            const double v =
                centres[a] + ((double)f - 4.0) * 0.25 * (f < 4 ? centres[a] - lo : hi - centres[a]);
            fine[nf++] = v;
            fine[nf++] = -v;
        }
    }
    aenl_sort_doubles(fine, nf);
    size_t nfu = 0;
    for (size_t i = 0; i < nf; ++i)
    {
        if (nfu == 0 || fine[i] - fine[nfu - 1u] > 1e-12 * (fabs(fine[i]) + 1e-300))
        {
            fine[nfu++] = fine[i];
        }
    }
    return nfu;
}

/* The fine indices of one point: the NLT_N_FINE fine knots nearest centre. */
static void fine_window(const double *fine, size_t nfu, double centre, size_t *dst)
{
    const size_t kc = knot_index(fine, nfu, centre);
    size_t lo = kc >= NLT_N_FINE / 2 ? kc - NLT_N_FINE / 2 : 0;
    if (lo + NLT_N_FINE > nfu)
    {
        lo = nfu >= NLT_N_FINE ? nfu - NLT_N_FINE : 0;
    }
    for (size_t f = 0; f < NLT_N_FINE; ++f)
    {
        dst[f] = lo + f < nfu ? lo + f : nfu - 1u;
    }
}

/* The fine profile where it gains more than the coarse p, its 95 % ranges widened to the
 * coarse ones; *p1, *p2 receive the law's two points. */
static void refine_profile(profile_t *p, const profile_t *pfine, const double *knots,
                           const double *fine, double *p1, double *p2)
{
    if (!(pfine->best > p->best))
    {
        *p1 = knots[p->k1];
        *p2 = knots[p->k2];
        return;
    }
    profile_t q = *pfine;
    q.lo1 = fmin(q.lo1, p->lo1);
    q.hi1 = fmax(q.hi1, p->hi1);
    q.lo2 = fmin(q.lo2, p->lo2);
    q.hi2 = fmax(q.hi2, p->hi2);
    *p = q;
    *p1 = fine[pfine->k1];
    *p2 = fine[pfine->k2];
}

/* The hysteresis law's points into c, in the channel's units (scale sc): the kinks of both
 * branches, a1, a2 rising and -a2, -a1 falling, ascending, with their intervals. */
static void hysteresis_points(const profile_t *ph, double hp1, double hp2, double sc,
                              aenl_nlt_channel_t *c)
{
    double pts[4] = {hp1, hp2, -hp2, -hp1};
    double lo[4] = {ph->lo1, ph->lo2, -ph->hi2, -ph->hi1};
    double hi[4] = {ph->hi1, ph->hi2, -ph->lo2, -ph->lo1};
    for (size_t a = 0; a < 4; ++a) /* ascending by point, intervals along */
    {
        for (size_t b = a + 1u; b < 4; ++b)
        {
            if (pts[b] < pts[a])
            {
                double tp = pts[a];
                pts[a] = pts[b];
                pts[b] = tp;
                tp = lo[a];
                lo[a] = lo[b];
                lo[b] = tp;
                tp = hi[a];
                hi[a] = hi[b];
                hi[b] = tp;
            }
        }
    }
    for (size_t a = 0; a < 4; ++a)
    {
        c->points[a] = pts[a] * sc;
        c->point_lo[a] = lo[a] * sc;
        c->point_hi[a] = hi[a] * sc;
    }
    c->n_points = 4;
}

/* The two-point laws after the fine search: profiles pf (freeplay) and ph (hysteresis) with
 * their points fp and hp. */
typedef struct
{
    profile_t pf, ph;
    double fp[2], hp[2];
} two_point_t;

/* Verdict design columns after the nuisance: each law's series at its best points. */
enum
{
    V_U3 = 0,
    V_U5 = 1,
    V_FP = 2,
    V_HY = 3,
    V_D = 4,
    V_LAWCOLS = 5
};

/* The laws' series at their best points (tp) into buf (V_LAWCOLS x n), the channel's motion in
 * rn->lin, its direction in rn->dsg. */
static void verdict_series(const run_t *rn, const two_point_t *tp, double *buf)
{
    const size_t n = rn->n;
    const double f1 = tp->fp[0];
    const double f2 = tp->fp[1];
    const double a1 = tp->hp[0];
    const double a2 = tp->hp[1];
    for (size_t t = 0; t < n; ++t)
    {
        const double u = rn->lin[t];
        const double dg = rn->dsg[t];
        buf[V_U3 * n + t] = u * u * u;
        buf[V_U5 * n + t] = u * u * u * u * u;
        buf[V_FP * n + t] = gap_ramp(u, f1, f2);
        buf[V_HY * n + t] = loop_branch(u, a1, a2, dg);
        buf[V_D * n + t] = dg;
    }
}

/* Columns of each law's fit in the verdict design (nn nuisance columns first): into idx,
 * returns their number. */
static size_t law_columns(size_t law, size_t nn, int quintic, size_t *idx)
{
    size_t m = 0;
    for (; m < nn; ++m)
    {
        idx[m] = m;
    }
    switch (law)
    {
        case AENL_NLT_POLYNOMIAL:
            idx[m++] = nn + V_U3;
            if (quintic)
            {
                idx[m++] = nn + V_U5;
            }
            break;
        case AENL_NLT_FREEPLAY:
            idx[m++] = nn + V_FP;
            break;
        case AENL_NLT_HYSTERESIS:
            idx[m++] = nn + V_HY;
            idx[m++] = nn + V_D;
            break;
        default:
            break;
    }
    return m;
}

/* The one-sided p-value of Vuong's test that model b is as close to the record as model a:
 * la, lb their per-sample losses (rows values, stride apart), crit_a, crit_b their criteria
 * (residual sum of squares plus penalty); dl: rows values of scratch. */
static double vuong_p(const double *la, const double *lb, size_t stride, size_t rows, double crit_a,
                      double crit_b, double *dl)
{
    for (size_t t = 0; t < rows; ++t)
    {
        dl[t] = lb[t * stride] - la[t * stride];
    }
    const double v = nlt_long_run_variance(dl, rows);
    const double num = crit_b - crit_a;
    if (!(v > 0.0))
    {
        return num > 0.0 ? 0.0 : 1.0;
    }
    return 0.5 * erfc(num / sqrt(2.0 * v));
}

/* The law of the smallest criterion. */
static size_t best_of(const double *crit)
{
    size_t best = 0;
    for (size_t l = 1; l < AENL_NLT_N_LAWS; ++l)
    {
        best = crit[l] < crit[best] ? l : best;
    }
    return best;
}

/* Channel j's laws compared on the record (Vuong's test for non-nested models): each law is
 * fitted at its best switching points beside the nuisance, its per-sample loss is the squared
 * whitened innovation it leaves, and the difference of two laws' losses, summed over the record
 * and less their Schwarz penalty, is judged by its long-run variance (the robust score's kernel
 * and lag). The null of each comparison: the two laws are equally close to the record; the
 * variance is the record's own, so an approximate linear model or an uneven spread widens it
 * instead of making a small difference look certain. The losses and criteria are kept in rn
 * for the comparison across channels; *best receives the law of the smallest criterion and
 * c->law_p each law's p-value against it (1 for itself). */
static aenl_status_t law_comparison(run_t *rn, size_t j, const double *dir, double s2,
                                    const two_point_t *tp, int quintic, size_t *best,
                                    aenl_nlt_channel_t *c, aenl_err_t *err)
{
    const size_t n = rn->n;
    const size_t nx = rn->nx;
    const double *nuis[NLT_NUIS_MAX + V_LAWCOLS];
    const size_t n_nuis = nuisance_series(rn, nuis);
    const size_t nn = n_nuis * nx;
    const size_t nc = nn + V_LAWCOLS;
    int full[NLT_NUIS_MAX + V_LAWCOLS];
    double *buf = (double *)malloc(V_LAWCOLS * n * sizeof(double));
    double *b = (double *)calloc(AENL_NLT_N_LAWS * nc, sizeof(double));
    double *loss = rn->loss + j * n * AENL_NLT_N_LAWS;
    double *dl = (double *)malloc(n * sizeof(double));
    double *beta = (double *)malloc(nc * sizeof(double));
    size_t *idx = (size_t *)malloc(nc * sizeof(size_t));
    if (buf == NULL || b == NULL || dl == NULL || beta == NULL || idx == NULL)
    {
        free(buf);
        free(b);
        free(dl);
        free(beta);
        free(idx);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    verdict_series(rn, tp, buf);
    for (size_t i = 0; i < n_nuis; ++i)
    {
        full[i] = 1;
    }
    for (size_t i = 0; i < V_LAWCOLS; ++i)
    {
        nuis[n_nuis + i] = buf + i * n;
        full[n_nuis + i] = 0;
    }
    design_t d = {n_nuis + V_LAWCOLS, nuis, full, dir, 0, NULL, NULL, rn->G_nn, nn, rn->R_nn, NULL};
    aenl_status_t st = nlt_design_accumulate(&d, rn->kf, err);
    double red[AENL_NLT_N_LAWS + 1] = {0}; /* each fit's reduction, the nuisance alone's last */
    for (size_t l = 0; l <= AENL_NLT_N_LAWS && st == AENL_OK; ++l)
    {
        const size_t m = law_columns(l, nn, quintic, idx);
        red[l] = nlt_fit_subset(&d, idx, m, l < AENL_NLT_N_LAWS ? beta : NULL);
        if (!isfinite(red[l]))
        {
            aenl_err_set(err, "the %s regression is singular",
                         l < AENL_NLT_N_LAWS ? aenl_nlt_law_name((aenl_nlt_law_t)l) : "nuisance");
            st = AENL_E_NUMERIC;
            break;
        }
        for (size_t i = 0; i < m && l < AENL_NLT_N_LAWS; ++i)
        {
            b[l * nc + idx[i]] = beta[i];
        }
    }
    if (st == AENL_OK)
    {
        st = nlt_design_losses(&d, rn->kf, b, AENL_NLT_N_LAWS, loss, err);
    }
    if (st == AENL_OK)
    {
        const size_t rows = rn->kf->rows / rn->nz;
        const double k[AENL_NLT_N_LAWS] = {quintic ? 2.0 : 1.0, 3.0, 4.0};
        /* the criteria from the fits' reductions: the residual sum of squares of each, plus
         * the penalty; gain and BIC on the chi-square scale are the same numbers over s2 */
        double *crit = rn->crit[j];
        for (size_t l = 0; l < AENL_NLT_N_LAWS; ++l)
        {
            c->gain[l] = fmax(red[l] - red[AENL_NLT_N_LAWS], 0.0) / s2;
            c->bic[l] = -c->gain[l] + k[l] * rn->lnrows;
            crit[l] = rn->kf->ee - red[l] + s2 * k[l] * rn->lnrows;
        }
        /* each law's force, kept for aenl_nlt_law_force */
        const double pts[AENL_NLT_N_LAWS][2] = {
            {0.0, 0.0}, {tp->fp[0], tp->fp[1]}, {tp->hp[0], tp->hp[1]}};
        const size_t col[AENL_NLT_N_LAWS][2] = {{V_U3, V_U5}, {V_FP, V_FP}, {V_HY, V_D}};
        for (size_t l = 0; l < AENL_NLT_N_LAWS; ++l)
        {
            c->law_coef[l][0] = b[l * nc + nn + col[l][0]];
            c->law_coef[l][1] = col[l][1] != col[l][0] ? b[l * nc + nn + col[l][1]] : 0.0;
            c->law_pts[l][0] = pts[l][0];
            c->law_pts[l][1] = pts[l][1];
        }
        c->law_scale = rn->scale[j];
        c->law_sign = frequency_sensitivity(rn->m, dir, j);
        c->laws_fitted = 1;
        *best = best_of(crit);
        for (size_t l = 0; l < AENL_NLT_N_LAWS; ++l)
        {
            c->law_p[l] = l == *best ? 1.0
                                     : vuong_p(loss + *best, loss + l, AENL_NLT_N_LAWS, rows,
                                               crit[*best], crit[l], dl);
        }
        rn->compared[j] = 1;
    }
    nlt_design_free(&d);
    free(buf);
    free(b);
    free(dl);
    free(beta);
    free(idx);
    return st;
}

/* A law's confidence: 1 - the largest p-value of the others against it, Bonferroni-adjusted
 * over the comparisons (0 when no law beats the others). */
static double law_confidence(const aenl_nlt_channel_t *c, size_t best)
{
    double pmax = 0.0;
    for (size_t l = 0; l < AENL_NLT_N_LAWS; ++l)
    {
        if (l != best)
        {
            pmax = fmax(pmax, c->law_p[l]);
        }
    }
    return 1.0 - fmin(1.0, (double)(AENL_NLT_N_LAWS - 1u) * pmax);
}

/* The class a law names. */
static aenl_class_t law_class(aenl_nlt_law_t law)
{
    return law == AENL_NLT_POLYNOMIAL
               ? AENL_CLASS_POLYNOMIAL
               : (law == AENL_NLT_FREEPLAY ? AENL_CLASS_FREEPLAY : AENL_CLASS_HYSTERESIS);
}

/* Channel j's verdict from the laws' comparison: switching points, hardening and class into c.
 * beta3: the cubic coefficient; lbest: the law of the smallest criterion. */
static void stage2_verdict(const run_t *rn, size_t j, const two_point_t *tp, double beta3,
                           size_t lbest, aenl_nlt_channel_t *c)
{
    const double sc = rn->scale[j];
    c->n_points = 0;
    if (lbest == AENL_NLT_FREEPLAY)
    {
        c->n_points = 2;
        c->points[0] = tp->fp[0] * sc;
        c->points[1] = tp->fp[1] * sc;
        c->point_lo[0] = tp->pf.lo1 * sc;
        c->point_hi[0] = tp->pf.hi1 * sc;
        c->point_lo[1] = tp->pf.lo2 * sc;
        c->point_hi[1] = tp->pf.hi2 * sc;
    }
    else if (lbest == AENL_NLT_HYSTERESIS)
    {
        hysteresis_points(&tp->ph, tp->hp[0], tp->hp[1], sc, c);
    }
    c->hardening = 0;
    if (lbest == AENL_NLT_POLYNOMIAL)
    {
        const int bs = (beta3 > 0.0) - (beta3 < 0.0);
        c->hardening = c->law_sign * bs; /* the frequency's sensitivity along the force */
    }
    c->confidence = law_confidence(c, lbest);
    c->undetermined = c->confidence < rn->opts->min_confidence;
    c->cls = c->undetermined ? AENL_CLASS_INSUFFICIENT : law_class((aenl_nlt_law_t)lbest);
}

/* The fine search of both two-point laws around their coarse best pairs (in tp, over knots, nk
 * knots), with the four points of each law and their mirrors as knots; tp receives the result. */
static aenl_status_t fine_search(const run_t *rn, const double *dir, double s2,
                                 const double *const *nuis, size_t n_nuis, const double *knots,
                                 size_t nk, two_point_t *tp, aenl_err_t *err)
{
    double fine[8 * NLT_N_FINE + 8];
    const double centres[4] = {knots[tp->pf.k1], knots[tp->pf.k2], knots[tp->ph.k1],
                               knots[tp->ph.k2]};
    const size_t cidx[4] = {tp->pf.k1, tp->pf.k2, tp->ph.k1, tp->ph.k2};
    const size_t nfu = fine_grid(knots, nk, centres, cidx, fine);
    resid_t r = {0, NULL, NULL};
    const aenl_status_t st = stage2_residuals(rn, dir, nuis, n_nuis, fine, nfu, &r, err);
    if (st != AENL_OK)
    {
        return st;
    }
    size_t win[4][NLT_N_FINE]; /* freeplay's two points, then hysteresis' */
    for (size_t a = 0; a < 4; ++a)
    {
        fine_window(fine, nfu, centres[a], win[a]);
    }
    profile_t pf2;
    profile_t ph2;
    profile_pairs(&r, fine, nfu, win[0], NLT_N_FINE, win[1], NLT_N_FINE, freeplay_gain, s2, &pf2);
    profile_pairs(&r, fine, nfu, win[2], NLT_N_FINE, win[3], NLT_N_FINE, hysteresis_gain, s2, &ph2);
    nlt_resid_free(&r);
    refine_profile(&tp->pf, &pf2, knots, fine, &tp->fp[0], &tp->fp[1]);
    refine_profile(&tp->ph, &ph2, knots, fine, &tp->hp[0], &tp->hp[1]);
    return AENL_OK;
}

/* Stage 2 for channel j along dir. */
static aenl_status_t stage2(run_t *rn, size_t j, const double *dir, double s2,
                            aenl_nlt_channel_t *c, aenl_err_t *err)
{
    double q[NLT_N_QUANT];
    double knots[4 * NLT_N_QUANT + 8];
    size_t nk = 0;
    aenl_status_t st = coarse_grid(rn, q, knots, &nk, err);
    if (st != AENL_OK)
    {
        return st;
    }
    if (nk < 3u)
    {
        aenl_err_set(err, "channel %lu barely moves: no switching point can be placed",
                     (unsigned long)j + 1u);
        return AENL_E_ARG;
    }
    size_t qidx[NLT_N_QUANT] = {0};
    for (size_t i = 0; i < NLT_N_QUANT; ++i)
    {
        qidx[i] = knot_index(knots, nk, q[i]);
    }
    const double *nuis[NLT_NUIS_MAX];
    const size_t n_nuis = nuisance_series(rn, nuis);
    resid_t r = {0, NULL, NULL};
    st = stage2_residuals(rn, dir, nuis, n_nuis, knots, nk, &r, err);
    if (st != AENL_OK)
    {
        return st;
    }
    int quintic = 0;
    const double beta3 = polynomial_law(rn, &r, s2, &quintic);
    /* freeplay over the coarse quantile grid, hysteresis over the symmetric grid */
    size_t all[4 * NLT_N_QUANT + 8] = {0};
    for (size_t i = 0; i < nk; ++i)
    {
        all[i] = i;
    }
    two_point_t tp;
    profile_pairs(&r, knots, nk, qidx, NLT_N_QUANT, qidx, NLT_N_QUANT, freeplay_gain, s2, &tp.pf);
    profile_pairs(&r, knots, nk, all, nk, all, nk, hysteresis_gain, s2, &tp.ph);
    nlt_resid_free(&r);
    st = fine_search(rn, dir, s2, nuis, n_nuis, knots, nk, &tp, err);
    if (st != AENL_OK)
    {
        return st;
    }
    size_t lbest = 0;
    st = law_comparison(rn, j, dir, s2, &tp, quintic, &lbest, c, err);
    if (st == AENL_OK)
    {
        stage2_verdict(rn, j, &tp, beta3, lbest, c);
    }
    return st;
}

static aenl_status_t check_args(const double *y, size_t n, size_t n_ch, const aenl_nlt_opts_t *opts,
                                const aenl_nlt_result_t *res, aenl_err_t *err)
{
    if (y == NULL || opts == NULL || res == NULL)
    {
        aenl_err_set(err, "aenl_nlt_run: NULL argument");
        return AENL_E_ARG;
    }
    if (n == 0 || n_ch == 0 || n_ch > AENL_NLT_MAX_CH)
    {
        aenl_err_set(err, "the test takes 1 to %d channels (got %lu)", AENL_NLT_MAX_CH,
                     (unsigned long)n_ch);
        return AENL_E_ARG;
    }
    if (!(opts->level > 0.0 && opts->level < 1.0) ||
        !(opts->min_confidence > 0.0 && opts->min_confidence <= 1.0) ||
        opts->n_states > NLT_MAX_X || opts->em_iter == 0)
    {
        aenl_err_set(err, "aenl_nlt_run: options out of range");
        return AENL_E_ARG;
    }
    if (opts->n_input > AENL_NLT_MAX_INPUT || (opts->n_input > 0 && opts->input == NULL))
    {
        aenl_err_set(err, "the test takes at most %d inputs", AENL_NLT_MAX_INPUT);
        return AENL_E_ARG;
    }
    for (size_t p = 0; p < opts->n_input; ++p)
    {
        for (size_t t = 0; opts->input[p] != NULL && t < n; ++t)
        {
            if (!isfinite(opts->input[p][t]))
            {
                aenl_err_set(err, "sample %lu of input %lu is missing: an input has no gaps",
                             (unsigned long)t + 1u, (unsigned long)p + 1u);
                return AENL_E_ARG;
            }
        }
        if (opts->input[p] == NULL)
        {
            aenl_err_set(err, "aenl_nlt_run: input %lu is NULL", (unsigned long)p + 1u);
            return AENL_E_ARG;
        }
    }
    return AENL_OK;
}

/* Values (samples x channels) the regressions need for a model of nx states. */
static size_t values_needed(size_t nx)
{
    return 20u * (6u * nx + 4u * (nx + 2u));
}

/* The model orders to choose among: opts->n_states alone, or 4 and 6 states per channel and 12
 * (at most 12 in all), as far as the record is long enough for them; ascending. */
static size_t state_candidates(const aenl_nlt_opts_t *opts, size_t n, size_t m, size_t *cand)
{
    size_t want[NLT_N_ORDERS] = {4u * m, 6u * m, NLT_MAX_X};
    size_t nw = NLT_N_ORDERS;
    if (opts->n_states != 0)
    {
        want[0] = opts->n_states;
        nw = 1;
    }
    size_t nc = 0;
    for (size_t i = 0; i < nw; ++i)
    {
        size_t nx = want[i] > NLT_MAX_X ? NLT_MAX_X : want[i];
        nx = nx < m ? m : nx;
        if (n * m < values_needed(nx) || n < 4u * (nx + 2u) || (nc > 0 && cand[nc - 1u] >= nx))
        {
            continue;
        }
        cand[nc++] = nx;
    }
    return nc;
}

/* The linear model of nx states by EM. A likelihood whose maximum lies on the boundary (a
 * noise-free record drives R to a singular matrix) fails EM part way: the fit then stops
 * earlier, at a valid iterate. */
static aenl_status_t fit_linear(const double *ys, size_t n, size_t m, size_t nx, size_t iters,
                                const double *in, size_t n_in, aenl_em_result_t *em,
                                aenl_err_t *err)
{
    aenl_em_opts_t eo;
    aenl_em_opts_default(&eo);
    eo.u = in;
    eo.n_u = n_in;
    eo.n_states = nx;
    eo.n_thresholds = 0;
    eo.max_iter = iters;
    eo.tol = 1e-9;
    eo.dt = 1.0;
    memset(em, 0, sizeof(*em));
    aenl_status_t st = aenl_em_fit(ys, n, m, &eo, em, err);
    while (st == AENL_E_NOT_PD && eo.max_iter > 1u)
    {
        eo.max_iter /= 2u;
        aenl_em_result_free(em);
        aenl_err_clear(err);
        st = aenl_em_fit(ys, n, m, &eo, em, err);
    }
    return st;
}

/* The candidate orders' fits at once: order cand[c] into em[c], its status and cause. */
typedef struct
{
    const double *ys, *in;
    size_t n, m, n_in, iters;
    const size_t *cand;
    aenl_em_result_t *em;
    aenl_status_t *st;
    aenl_err_t *err;
} order_job_t;

static void order_task(void *ctx, size_t c)
{
    const order_job_t *o = (const order_job_t *)ctx;
    aenl_err_clear(&o->err[c]);
    o->st[c] =
        fit_linear(o->ys, o->n, o->m, o->cand[c], o->iters, o->in, o->n_in, &o->em[c], &o->err[c]);
}

/* The order by the Bayesian information criterion over the candidates: -2 log-likelihood plus
 * ln(samples) per parameter the data can tell apart. A state-space model is known only up to a
 * change of state basis, so its identifiable parameters are those of the innovations form in a
 * canonical basis: 2 nx m (the dynamics and the gain), m (m + 1) / 2 (the innovation covariance),
 * m (the offset) and nx per known input (B). An order too small for the record's dynamics
 * (aerodynamic lags, start-up transients) leaves a misfit that the test would take for a law. */
static aenl_status_t fit_linear_order(const double *ys, size_t n, size_t m, const size_t *cand,
                                      size_t n_cand, size_t iters, const double *in, size_t n_in,
                                      aenl_em_result_t *best, aenl_err_t *err)
{
    aenl_em_result_t em[NLT_N_ORDERS];
    aenl_status_t sts[NLT_N_ORDERS];
    aenl_err_t errs[NLT_N_ORDERS];
    memset(em, 0, sizeof(em));
    order_job_t job = {ys, in, n, m, n_in, iters, cand, em, sts, errs};
    aenl_parallel_for(n_cand, order_task, &job);
    double bic_best = INFINITY;
    int found = 0;
    aenl_status_t st_last = AENL_E_NUMERIC;
    memset(best, 0, sizeof(*best));
    for (size_t c = 0; c < n_cand; ++c)
    {
        st_last = sts[c];
        if (st_last != AENL_OK)
        {
            aenl_err_set(err, "%s", errs[c].msg);
            continue;
        }
        const double nx = (double)cand[c];
        const double dm = (double)m;
        const double k = 2.0 * nx * dm + 0.5 * dm * (dm + 1.0) + dm + nx * (double)n_in;
        const double bic = -2.0 * em[c].loglik_final + k * log((double)n);
        if (isfinite(bic) && bic < bic_best)
        {
            aenl_em_result_free(best);
            *best = em[c];
            bic_best = bic;
            found = 1;
        }
        else
        {
            aenl_em_result_free(&em[c]);
        }
    }
    if (found)
    {
        aenl_err_clear(err);
        return AENL_OK;
    }
    /* every fit failed, or none has a finite likelihood (then the last fit's status is OK) */
    const aenl_status_t st = st_last != AENL_OK ? st_last : AENL_E_NUMERIC;
    aenl_err_set(err, "the linear model cannot be fitted (%s)", aenl_status_str(st));
    return st;
}

/* Lower Cholesky factor of the symmetric positive semi-definite S (n x n) into L, with a ridge of
 * 1e-12 of its trace for a singular S (a noise-free direction). 0, or -1 when it fails. */
static int chol_psd(const double *S, size_t n, double *L)
{
    double tr = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        tr += S[i * n + i];
    }
    memcpy(L, S, n * n * sizeof(double));
    for (size_t i = 0; i < n; ++i)
    {
        L[i * n + i] += 1e-12 * fmax(tr, 1e-300);
        for (size_t j = i + 1u; j < n; ++j)
        {
            L[i * n + j] = 0.0;
        }
    }
    return aenl_dense_potrf(L, n);
}

/* One record of the fitted linear model m (the run's scaled units) into y (n_ch columns of n),
 * driven by the inputs in (n x n_in, row-major), with Gaussian process noise Lq z and
 * measurement noise Lr z. */
static void simulate_control(const aenl_em_model_t *m, const double *in, size_t n_in,
                             const double *Lq, const double *Lr, aenl_rng_t *g, size_t n,
                             double *const *y)
{
    const size_t nx = m->n_x;
    const size_t nz = m->n_z;
    double x[NLT_MAX_X];
    double z[NLT_MAX_X];
    memcpy(x, m->x0, nx * sizeof(double));
    for (size_t t = 0; t < n; ++t)
    {
        for (size_t r = 0; r < nz; ++r)
        {
            z[r] = aenl_rng_gauss(g);
        }
        for (size_t r = 0; r < nz; ++r)
        {
            double v = 0.0;
            for (size_t c = 0; c <= r; ++c)
            {
                v += Lr[r * nz + c] * z[c];
            }
            for (size_t i = 0; i < nx; ++i)
            {
                v += m->C[r * nx + i] * x[i];
            }
            y[r][t] = v;
        }
        double xn[NLT_MAX_X] = {0};
        for (size_t i = 0; i < nx; ++i)
        {
            z[i] = aenl_rng_gauss(g);
        }
        for (size_t i = 0; i < nx; ++i)
        {
            double v = m->b[i];
            for (size_t l = 0; l < nx; ++l)
            {
                v += m->A[i * nx + l] * x[l];
            }
            for (size_t p = 0; p < n_in; ++p)
            {
                v += m->B[i * n_in + p] * in[t * n_in + p];
            }
            for (size_t l = 0; l <= i; ++l)
            {
                v += Lq[i * nx + l] * z[l];
            }
            xn[i] = v;
        }
        memcpy(x, xn, nx * sizeof(double));
    }
}

/* Linear control b of a run whose noise seed is seed (each control its own stream). */
static void control_series(const aenl_em_model_t *m, const double *in, const double *Lq,
                           const double *Lr, uint64_t seed, size_t b, size_t n, double *const *y)
{
    aenl_rng_t g;
    aenl_rng_seed(&g, seed + (uint64_t)b * 0x9E3779B97F4A7C15ull);
    simulate_control(m, in, m->n_u, Lq, Lr, &g, n, y);
}

/* What a run hands on to its linear controls: the fitted model, the scaled inputs and the
 * channels' scales. */
typedef struct
{
    aenl_em_result_t em;
    double *in;     /* n x n_in, row-major */
    double *in_col; /* n_in series of n */
    double scale[AENL_NLT_MAX_CH];
} kept_t;

static aenl_status_t run_core(const double *const *col, size_t stride, size_t n, size_t n_ch,
                              const aenl_nlt_opts_t *opts, aenl_nlt_result_t *res, aenl_err_t *err,
                              int stats_only, kept_t *keep);

/* Linear controls at once: control b (index first + i of a batch) simulated with its own seed
 * into its own buffer and tested (stage 1 only); its statistics go to stat[b][channel], ok[b]
 * says whether its linear model could be fitted, nonlin[b] whether a channel of it rejects. */
typedef struct
{
    const aenl_em_model_t *m;
    const double *in;
    const double *Lq, *Lr;
    size_t n, n_ch;
    const aenl_nlt_opts_t *o;
    uint64_t seed;
    size_t first;
    double *stat;
    int *ok;
    int *nonlin;
} control_job_t;

static aenl_status_t control_task(void *ctx, size_t i, aenl_err_t *err)
{
    const control_job_t *c = (const control_job_t *)ctx;
    const size_t b = c->first + i;
    c->ok[b] = 0;
    double *buf = (double *)malloc(c->n * c->n_ch * sizeof(double));
    aenl_nlt_result_t *rc = (aenl_nlt_result_t *)malloc(sizeof(*rc));
    const aenl_status_t st = buf != NULL && rc != NULL ? AENL_OK : AENL_E_DIM;
    if (st != AENL_OK)
    {
        aenl_err_set(err, "out of memory");
    }
    else
    {
        double *y[AENL_NLT_MAX_CH];
        for (size_t j = 0; j < c->n_ch; ++j)
        {
            y[j] = buf + j * c->n;
        }
        control_series(c->m, c->in, c->Lq, c->Lr, c->seed, b, c->n, y);
        aenl_err_t e2;
        aenl_err_clear(&e2);
        c->ok[b] =
            run_core((const double *const *)y, 1, c->n, c->n_ch, c->o, rc, &e2, 1, NULL) == AENL_OK;
        c->nonlin[b] = 0;
        for (size_t j = 0; c->ok[b] && j < c->n_ch; ++j)
        {
            c->stat[b * AENL_NLT_MAX_CH + j] = rc->ch[j].stat;
            c->nonlin[b] |= rc->ch[j].nonlinear;
        }
    }
    free(buf);
    free(rc);
    return st;
}

/* AENL_OK when the fitted model m is stable, else an error: a model with a pole on or outside
 * the unit circle (a record that it follows only with its filter's corrections) is no linear
 * structure to simulate, and a control simulated from it grows without bound. */
static aenl_status_t check_stable(const aenl_em_model_t *m, aenl_err_t *err)
{
    aenl_em_eig_t eig[NLT_MAX_X];
    size_t n_eig = 0;
    aenl_status_t st = aenl_em_modal(m, 0, eig, &n_eig, NULL, err);
    double rho = 0.0;
    for (size_t i = 0; st == AENL_OK && i < n_eig; ++i)
    {
        const double mod = hypot(eig[i].re, eig[i].im);
        rho = mod > rho || isnan(mod) ? mod : rho; /* a NaN pole stays NaN: not stable */
    }
    if (st == AENL_OK && !(rho < 1.0))
    {
        aenl_err_set(err,
                     "the linear model fitted to the record is unstable (largest pole modulus "
                     "%.6g): no linear control can be simulated from it",
                     rho);
        st = AENL_E_NUMERIC;
    }
    return st;
}

/* What every linear control of the fitted model m needs: the factors of its noise covariances
 * (Lq, Lr) and its stability (check_stable); AENL_OK, or an error that says which is missing. */
static aenl_status_t control_noise(const aenl_em_model_t *m, size_t n_ch, double *Lq, double *Lr,
                                   aenl_err_t *err)
{
    if (chol_psd(m->Q, m->n_x, Lq) != 0 || chol_psd(m->R, n_ch, Lr) != 0)
    {
        aenl_err_set(err, "the linear model's noise covariances are not positive: no controls");
        return AENL_E_NUMERIC;
    }
    return check_stable(m, err);
}

/* The linear controls of a run (opts->n_controls records of the fitted model m, driven by the
 * run's scaled inputs), each tested like the record; a channel's control p-value is the share
 * of controls (the record counted among them) whose statistic reaches the record's: the test's
 * null distribution for this record's length, model and inputs, without the asymptotics. The
 * controls that a channel of rejects are counted too: the test's false verdicts on linear
 * records like this one. A control whose linear model cannot be fitted is left out. */
static aenl_status_t linear_controls(const aenl_em_model_t *m, const double *in,
                                     const double *const *in_col, size_t n, size_t n_ch,
                                     const aenl_nlt_opts_t *opts, aenl_nlt_result_t *res,
                                     aenl_err_t *err)
{
    double Lq[NLT_MAX_X * NLT_MAX_X];
    double Lr[AENL_NLT_MAX_CH * AENL_NLT_MAX_CH];
    const aenl_status_t st_noise = control_noise(m, n_ch, Lq, Lr, err);
    if (st_noise != AENL_OK)
    {
        return st_noise;
    }
    aenl_nlt_opts_t o = *opts;
    o.n_controls = 0;
    o.input = m->n_u > 0 ? in_col : NULL; /* the record's inputs: their first n_input series */
    control_job_t job = {m, in, Lq, Lr, n, n_ch, &o, opts->control_seed, 0, NULL, NULL, NULL};
    job.stat = (double *)malloc(opts->n_controls * AENL_NLT_MAX_CH * sizeof(double));
    job.ok = (int *)malloc(opts->n_controls * sizeof(int));
    job.nonlin = (int *)malloc(opts->n_controls * sizeof(int));
    if (job.stat == NULL || job.ok == NULL || job.nonlin == NULL)
    {
        free(job.stat);
        free(job.ok);
        free(job.nonlin);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    /* in batches of as many as run at once, so that progress is reported as they finish */
    const size_t batch = aenl_jobs();
    aenl_status_t st = AENL_OK;
    for (size_t b0 = 0; b0 < opts->n_controls && st == AENL_OK; b0 += batch)
    {
        job.first = b0;
        const size_t nb = opts->n_controls - b0 < batch ? opts->n_controls - b0 : batch;
        st = aenl_parallel_try(nb, control_task, &job, err);
        aenl_progress_report(opts->progress, b0 + nb, opts->n_controls);
    }
    for (size_t b = 0; b < opts->n_controls && st == AENL_OK; ++b)
    {
        if (!job.ok[b])
        {
            continue;
        }
        res->n_controls++;
        res->n_controls_nonlinear += job.nonlin[b] ? 1u : 0u;
        for (size_t j = 0; j < n_ch; ++j)
        {
            res->ch[j].control_exceed +=
                job.stat[b * AENL_NLT_MAX_CH + j] >= res->ch[j].stat ? 1u : 0u;
        }
    }
    free(job.stat);
    free(job.ok);
    free(job.nonlin);
    for (size_t j = 0; j < n_ch; ++j)
    {
        res->ch[j].control_p =
            (1.0 + (double)res->ch[j].control_exceed) / (1.0 + (double)res->n_controls);
    }
    return st;
}

/* The error of a record too short for every candidate order: the samples the smallest needs. */
static aenl_status_t too_few_samples(const aenl_nlt_opts_t *opts, size_t n, size_t n_ch,
                                     aenl_err_t *err)
{
    size_t nx_min = opts->n_states != 0 ? opts->n_states : 4u * n_ch;
    nx_min = nx_min > NLT_MAX_X ? NLT_MAX_X : (nx_min < n_ch ? n_ch : nx_min);
    const size_t need = values_needed(nx_min);
    const size_t need_n = (need + n_ch - 1u) / n_ch;
    aenl_err_set(err, "%lu samples are too few for the test of %lu channel%s (it needs %lu)",
                 (unsigned long)n, (unsigned long)n_ch, n_ch == 1u ? "" : "s",
                 (unsigned long)(need_n > 4u * (nx_min + 2u) ? need_n : 4u * (nx_min + 2u)));
    return AENL_E_ARG;
}

/* The sample variance of the finite values of c[t * stride], t < n (0 for fewer than two). */
static double channel_variance(const double *c, size_t stride, size_t n)
{
    double s = 0.0;
    double ss = 0.0;
    size_t cnt = 0;
    for (size_t t = 0; t < n; ++t)
    {
        const double v = c[t * stride];
        if (isfinite(v))
        {
            s += v;
            ss += v * v;
            cnt++;
        }
    }
    const double mean = cnt > 0 ? s / (double)cnt : 0.0;
    return cnt > 1 ? (ss - (double)cnt * mean * mean) / (double)(cnt - 1u) : 0.0;
}

/* The record scaled by each channel's standard deviation (scale receives them) into *ys, a new
 * n x n_ch array the caller frees. The zero stays where it is: laws are defined about the
 * channel's own zero. */
static aenl_status_t scale_channels(const double *const *col, size_t stride, size_t n, size_t n_ch,
                                    double *scale, double **ys, aenl_err_t *err)
{
    double *y = (double *)malloc(n * n_ch * sizeof(double));
    if (y == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    for (size_t t = 0; t < n * n_ch; ++t)
    {
        if (!isfinite(col[t % n_ch][(t / n_ch) * stride]))
        {
            free(y);
            aenl_err_set(err,
                         "sample %lu of channel %lu is missing: the test takes complete rows "
                         "only (cut the record or fill the gap)",
                         (unsigned long)(t / n_ch) + 1u, (unsigned long)(t % n_ch) + 1u);
            return AENL_E_ARG;
        }
    }
    for (size_t j = 0; j < n_ch; ++j)
    {
        const double var = channel_variance(col[j], stride, n);
        if (!(var > 0.0))
        {
            free(y);
            aenl_err_set(err, "channel %lu is constant", (unsigned long)j + 1u);
            return AENL_E_ARG;
        }
        scale[j] = sqrt(var);
        for (size_t t = 0; t < n; ++t)
        {
            y[t * n_ch + j] = col[j][t * stride] / scale[j];
        }
    }
    *ys = y;
    return AENL_OK;
}

/* The known inputs, scaled like the channels: row-major into in for the fit and the filter, one
 * series each into in_col (NULL when it could not be allocated) for the regressions, whose
 * pointers go to rn->in_col. */
static aenl_status_t scale_inputs(const aenl_nlt_opts_t *opts, size_t n, double *in, double *in_col,
                                  run_t *rn, aenl_err_t *err)
{
    const size_t n_in = opts->n_input;
    const size_t n_eff = NLT_HOLD * n_in;
    if (n_in > 0 && in_col == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    for (size_t p = 0; p < n_in; ++p)
    {
        double sum = 0.0;
        double ss = 0.0;
        for (size_t t = 0; t < n; ++t)
        {
            sum += opts->input[p][t];
            ss += opts->input[p][t] * opts->input[p][t];
        }
        const double mean = sum / (double)n;
        const double var = (ss - (double)n * mean * mean) / (double)(n - 1u);
        if (!(var > 0.0))
        {
            aenl_err_set(err, "input %lu is constant", (unsigned long)p + 1u);
            return AENL_E_ARG;
        }
        const double sd = sqrt(var);
        for (size_t t = 0; t < n; ++t)
        {
            const double v = opts->input[p][t] / sd;
            in[t * n_eff + p] = v;
            in_col[p * n + t] = v;
            /* and its value at the step's end: the structure feels the force change over the
             * step (a first-order hold), which a model driven by the value at its start alone
             * misses in a way that follows the motion */
            const double w = opts->input[p][t + 1u < n ? t + 1u : t] / sd;
            in[t * n_eff + n_in + p] = w;
            in_col[(n_in + p) * n + t] = w;
        }
        rn->in_col[p] = in_col + p * n;
        rn->in_col[n_in + p] = in_col + (n_in + p) * n;
    }
    return AENL_OK;
}

/* A channel's series of rn (n each; work 4 n). 0, or -1 when one could not be allocated (the
 * others are freed by free_series). */
static int alloc_series(run_t *rn)
{
    const size_t n = rn->n;
    rn->one = (double *)malloc(n * sizeof(double));
    rn->lin = (double *)malloc(n * sizeof(double));
    rn->dsg = (double *)malloc(n * sizeof(double));
    rn->work = (double *)malloc(4u * n * sizeof(double));
    return rn->one == NULL || rn->lin == NULL || rn->dsg == NULL || rn->work == NULL ? -1 : 0;
}

static void free_series(run_t *rn)
{
    free(rn->one);
    free(rn->lin);
    free(rn->dsg);
    free(rn->work);
}

/* Channel j's series for both stages: the offset, the filtered output and its direction of
 * motion. */
static void channel_series(const run_t *rn, size_t j)
{
    const size_t n = rn->n;
    const size_t n_ch = rn->nz;
    for (size_t t = 0; t < n; ++t)
    {
        rn->one[t] = 1.0;
        rn->lin[t] = rn->kf->u[t * n_ch + j];
    }
    direction(rn->kf->u, n_ch, j, n, rn->dsg);
}

/* The motion's samples per period from the lag-one autocorrelation r of the filtered output u
 * (rn->lin): 2 pi / arccos(r), exact for a sampled sinusoid (r = cos(2 pi / N)) and the mean
 * period of a narrow-band motion; large for a slow or non-oscillating motion (r near 1),
 * infinite for a constant one, 2 at r = -1. The filtered output, not the record, so that
 * measurement noise does not shorten it. */
static double samples_per_period(const run_t *rn)
{
    const size_t n = rn->n;
    double mean = 0.0;
    for (size_t t = 0; t < n; ++t)
    {
        mean += rn->lin[t];
    }
    mean /= (double)n;
    double c0 = 0.0;
    double c1 = 0.0;
    for (size_t t = 0; t < n; ++t)
    {
        const double v = rn->lin[t] - mean;
        c0 += v * v;
        c1 += t > 0 ? v * (rn->lin[t - 1u] - mean) : 0.0;
    }
    const double r = c0 > 0.0 ? c1 / c0 : 1.0;
    return r >= 1.0 ? (double)INFINITY : 2.0 * acos(-1.0) / acos(fmax(r, -1.0));
}

/* Both stages for channel j, its series set by channel_series (stage 2 only when stage 1 finds
 * it nonlinear and not stats_only); *pmin receives the smallest stage-1 p-value so far. */
static aenl_status_t test_channel(run_t *rn, size_t j, int stats_only, aenl_nlt_result_t *res,
                                  double *pmin, aenl_err_t *err)
{
    const size_t n_ch = rn->nz;
    aenl_nlt_channel_t *c = &res->ch[j];
    double dir[NLT_MAX_X];
    double s2 = 1.0;
    c->cls = AENL_CLASS_LINEAR;
    c->samples_per_period = samples_per_period(rn);
    aenl_status_t st = stage1(rn, j, c, dir, &s2, err);
    if (st != AENL_OK)
    {
        return st;
    }
    c->nonlinear = c->p < rn->opts->level / (double)n_ch;
    *pmin = fmin(*pmin, c->p);
    c->control_p = 1.0;
    if (c->nonlinear && !stats_only)
    {
        st = stage2(rn, j, dir, s2, c, err);
    }
    return st;
}

/* The cross-products of the nuisance columns (an offset, every filtered state and every input,
 * each full) into rn->G_nn: they are the same in the regressions of every channel and stage. */
static aenl_status_t nuisance_products(run_t *rn, size_t keep_max, aenl_err_t *err)
{
    double *one = (double *)malloc(rn->n * sizeof(double));
    if (one == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    for (size_t t = 0; t < rn->n; ++t)
    {
        one[t] = 1.0;
    }
    run_t r = *rn;
    r.one = one;
    const double *g[NLT_NUIS_MAX];
    int full[NLT_NUIS_MAX];
    const size_t ns = nuisance_series(&r, g);
    for (size_t i = 0; i < ns; ++i)
    {
        full[i] = 1;
    }
    design_t d = {ns, g, full, NULL, 0, NULL, NULL, NULL, 0, NULL, NULL};
    /* their sensitivities are kept for the later designs when they fit in keep_max bytes: those
     * then walk only their own columns (at 12 states, 156 of the 160 to 260 columns of a design
     * are the nuisance's); otherwise each design walks them again */
    const size_t keep = rn->n * rn->nz * ns * rn->nx;
    if (keep > 0 && keep <= keep_max / sizeof(double))
    {
        d.R_save = (double *)malloc(keep * sizeof(double));
    }
    const aenl_status_t st = nlt_design_accumulate(&d, rn->kf, err);
    if (st == AENL_OK)
    {
        rn->G_nn = d.G;
        d.G = NULL;
        rn->R_nn = d.R_save;
        d.R_save = NULL;
    }
    free(d.R_save);
    nlt_design_free(&d);
    free(one);
    return st;
}

/* The channels' tests at once: each channel's stages on a copy of the run (proto, not written
 * while they run) with its own series; a channel writes only its result, its block of the
 * losses and its slots here, which go into the run afterwards. */
typedef struct
{
    const run_t *proto;
    aenl_nlt_result_t *res;
    int stats_only;
    double pmin[AENL_NLT_MAX_CH];
    double crit[AENL_NLT_MAX_CH][AENL_NLT_N_LAWS];
    int compared[AENL_NLT_MAX_CH];
} chan_job_t;

static aenl_status_t channel_task(void *ctx, size_t j, aenl_err_t *err)
{
    chan_job_t *c = (chan_job_t *)ctx;
    run_t r = *c->proto;
    c->pmin[j] = 1.0;
    aenl_status_t st = AENL_E_DIM;
    if (alloc_series(&r) != 0)
    {
        aenl_err_set(err, "out of memory");
    }
    else
    {
        channel_series(&r, j);
        st = test_channel(&r, j, c->stats_only, c->res, &c->pmin[j], err);
        memcpy(c->crit[j], r.crit[j], sizeof(r.crit[j]));
        c->compared[j] = r.compared[j];
    }
    free_series(&r);
    return st;
}

/* Both stages of every channel (test_channel); *pmin receives the smallest stage-1 p-value. The
 * first channel that fails, in order, gives the status. */
static aenl_status_t test_channels(run_t *rn, int stats_only, aenl_nlt_result_t *res, double *pmin,
                                   aenl_err_t *err)
{
    chan_job_t *c = (chan_job_t *)calloc(1, sizeof(*c));
    if (c == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    c->proto = rn;
    c->res = res;
    c->stats_only = stats_only;
    const aenl_status_t st = aenl_parallel_try(rn->nz, channel_task, c, err);
    for (size_t j = 0; j < rn->nz && st == AENL_OK; ++j)
    {
        *pmin = fmin(*pmin, c->pmin[j]);
        memcpy(rn->crit[j], c->crit[j], sizeof(c->crit[j]));
        rn->compared[j] = c->compared[j];
    }
    free(c);
    return st;
}

/* 1 - m p, at least 0: a confidence from the largest of m p-values (Bonferroni). */
static double bonferroni_confidence(double pmax, size_t m)
{
    return m == 0 ? 1.0 : 1.0 - fmin(1.0, (double)m * pmax);
}

/* The record's verdict. Its channel is the rejecting channel of the largest stage-1 statistic
 * (every channel's has the same degrees of freedom: the largest is the smallest p-value, and
 * stays comparable where the p-values underflow to 0), its law that channel's best, named when
 * the comparison of the channel's laws is confident (class_confidence). The channel's own
 * confidence comes
 * from the same comparison across channels: every channel's best law explains the same
 * innovations, so the verdict's and another channel's compare by Vuong's test as two laws of one
 * channel do (Bonferroni over the other rejecting channels). A law of the verdict channel, or
 * another channel's best law, stays a candidate while its p-value, times the number of
 * comparisons of its kind, exceeds 1 - min_confidence. */
static aenl_status_t verdict_comparison(const run_t *rn, aenl_nlt_result_t *res, aenl_err_t *err)
{
    const size_t n = rn->n;
    long bj = -1;
    for (size_t j = 0; j < rn->nz; ++j)
    {
        if (rn->compared[j] && (bj < 0 || res->ch[j].stat > res->ch[bj].stat))
        {
            bj = (long)j;
        }
    }
    if (bj < 0)
    {
        return AENL_OK;
    }
    const aenl_nlt_channel_t *c = &res->ch[bj];
    const size_t bl = best_of(rn->crit[bj]);
    const double alpha = 1.0 - rn->opts->min_confidence;
    res->n_candidates = 0;
    for (size_t l = 0; l < AENL_NLT_N_LAWS; ++l) /* the verdict channel's laws, the best first */
    {
        const size_t ll = (bl + l) % AENL_NLT_N_LAWS;
        if (ll == bl || c->law_p[ll] * (double)(AENL_NLT_N_LAWS - 1u) > alpha)
        {
            aenl_nlt_candidate_t *cd = &res->candidates[res->n_candidates++];
            cd->channel = (size_t)bj;
            cd->law = (aenl_nlt_law_t)ll;
            cd->p = c->law_p[ll];
        }
    }
    const size_t rows = rn->kf->rows / rn->nz;
    double *dl = (double *)malloc(rows * sizeof(double));
    if (dl == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    double p[AENL_NLT_MAX_CH];
    size_t m_ch = 0;
    double pmax_ch = 0.0;
    const double *lb = rn->loss + (size_t)bj * n * AENL_NLT_N_LAWS + bl;
    for (size_t j = 0; j < rn->nz; ++j)
    {
        if (rn->compared[j] && j != (size_t)bj)
        {
            const size_t l = best_of(rn->crit[j]);
            p[j] = vuong_p(lb, rn->loss + j * n * AENL_NLT_N_LAWS + l, AENL_NLT_N_LAWS, rows,
                           rn->crit[bj][bl], rn->crit[j][l], dl);
            pmax_ch = fmax(pmax_ch, p[j]);
            m_ch++;
        }
    }
    free(dl);
    for (size_t j = 0; j < rn->nz; ++j)
    {
        if (rn->compared[j] && j != (size_t)bj && p[j] * (double)m_ch > alpha)
        {
            aenl_nlt_candidate_t *cd = &res->candidates[res->n_candidates++];
            cd->channel = j;
            cd->law = (aenl_nlt_law_t)best_of(rn->crit[j]);
            cd->p = p[j];
        }
    }
    res->verdict = bj;
    res->class_confidence = c->confidence;
    res->channel_confidence = bonferroni_confidence(pmax_ch, m_ch);
    /* the verdict names a law and a channel: right when both are (a union bound, as each
     * confidence is one) */
    res->confidence = fmax(res->class_confidence + res->channel_confidence - 1.0, 0.0);
    res->undetermined = c->undetermined;
    res->verdict_class = c->cls;
    return AENL_OK;
}

/* The model em refitted with the impulses flagged in flag as state jumps: their transitions get
 * the covariance P_imp on top of the process noise and are left out of the noise's estimate.
 * Fitted over the whole record, Gaussian process noise would hold the impulses' energy at every
 * sample; the filter would then follow the measurement noise between impulses too closely, and
 * its misprediction would grow and fade with the motion, which the test reads as a law. */
static aenl_status_t refit_with_jumps(const double *ys, const double *in, const run_t *rn,
                                      const unsigned char *flag, const double *P_imp,
                                      aenl_em_result_t *em, int *refitted, aenl_err_t *err)
{
    *refitted = 0;
    aenl_em_opts_t eo;
    aenl_em_opts_default(&eo);
    eo.u = rn->n_in > 0 ? in : NULL;
    eo.n_u = rn->n_in;
    eo.max_iter = rn->opts->em_iter;
    eo.tol = 1e-9;
    eo.jump = flag;
    eo.P_jump = P_imp;
    aenl_em_model_t trial;
    memset(&trial, 0, sizeof(trial));
    aenl_status_t st = aenl_em_model_copy(&trial, &em->model, err);
    double *ll = st == AENL_OK ? (double *)malloc((eo.max_iter + 1u) * sizeof(double)) : NULL;
    size_t it = 0;
    if (st == AENL_OK && ll == NULL)
    {
        aenl_err_set(err, "out of memory");
        st = AENL_E_DIM;
    }
    if (st == AENL_OK)
    {
        st = aenl_em_iterate(&trial, ys, rn->n, &eo, ll, &it, err);
    }
    if (st == AENL_OK)
    {
        aenl_em_model_free(&em->model);
        em->model = trial;
        em->loglik_final = ll[it];
        *refitted = 1;
    }
    else
    {
        /* a fit that fails (a noise covariance at its boundary) keeps the model it started
         * from, whose impulses are still widened in the filter; out of memory is a failure */
        aenl_em_model_free(&trial);
        if (st != AENL_E_DIM)
        {
            aenl_err_clear(err);
            st = AENL_OK;
        }
    }
    free(ll);
    return st;
}

/* The filter of ys with the model of em, restarted at the impulses: they are found in a run
 * without restarts (flag, n samples, receives them), and the filter is run again with its
 * covariance widened at each of them by the filtered states' own covariance (the state may have
 * moved anywhere in its usual range). *n_impulses receives their number. */
static aenl_status_t filter_with_impulses(const double *ys, const aenl_em_result_t *em, kf_t *kf,
                                          unsigned char *flag, size_t *n_impulses, aenl_err_t *err)
{
    size_t cnt = 0;
    aenl_status_t st = nlt_kf_run(kf, &em->model, ys, NULL, NULL, err);
    if (st == AENL_OK)
    {
        st = nlt_impulses(kf, 0, flag, &cnt, err);
    }
    if (st == AENL_OK && cnt > 0)
    {
        double P_imp[NLT_MAX_X * NLT_MAX_X] = {0};
        nlt_state_range(kf, P_imp);
        nlt_kf_clear_run(kf);
        st = nlt_kf_run(kf, &em->model, ys, flag, P_imp, err);
    }
    *n_impulses = cnt;
    return st;
}

/* The jump model: em fitted again with the impulses of flag as state jumps, the filter run with
 * its covariance widened there, and the impulses that filter still shows added to flag, until
 * none is added (at most NLT_JUMP_ROUNDS refits). A filter restarted at the impulses found so far
 * shows each remaining one once, where a filter that is not would go on mispredicting after it,
 * more so as the refitted noise is smaller. *n_impulses receives their number. */
static aenl_status_t jump_model(const double *ys, const double *in, const run_t *rn,
                                aenl_em_result_t *em, kf_t *kf, unsigned char *flag,
                                size_t *n_impulses, int *refitted, aenl_err_t *err)
{
    *refitted = 0;
    const size_t n = rn->n;
    unsigned char *prev = (unsigned char *)malloc(n);
    if (prev == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    double P_imp[NLT_MAX_X * NLT_MAX_X] = {0};
    size_t cnt = *n_impulses;
    aenl_status_t st = AENL_OK;
    for (int round = 0; st == AENL_OK && round < NLT_JUMP_ROUNDS; ++round)
    {
        nlt_state_range(kf, P_imp);
        memcpy(prev, flag, n);
        int ok = 0;
        st = refit_with_jumps(ys, in, rn, flag, P_imp, em, &ok, err);
        *refitted |= ok;
        nlt_kf_clear_run(kf);
        if (st == AENL_OK)
        {
            st = nlt_kf_run(kf, &em->model, ys, flag, P_imp, err);
        }
        if (st == AENL_OK)
        {
            st = nlt_impulses(kf, 1, flag, &cnt, err);
        }
        if (st == AENL_OK && memcmp(flag, prev, n) == 0)
        {
            break;
        }
    }
    if (st == AENL_OK && memcmp(flag, prev, n) != 0)
    {
        /* the last round added impulses: the filter restarts at every one of them */
        nlt_state_range(kf, P_imp);
        nlt_kf_clear_run(kf);
        st = nlt_kf_run(kf, &em->model, ys, flag, P_imp, err);
    }
    *n_impulses = cnt;
    free(prev);
    return st;
}

/* Dither: white Gaussian noise of AENL_NLT_DITHER (of the channel's standard deviation) added to
 * each channel of the scaled record ys whose fitted measurement noise standard deviation (of
 * em's model) is below a tenth of that, i.e. at the likelihood's boundary; dithered[j] says
 * which. Returns how many. The test's null distribution rests on innovations that are a
 * martingale difference with a regular covariance; a channel without measurement noise (a
 * simulation) puts the likelihood's maximum on its boundary (R singular), where EM stops early
 * and the innovations are the model's deterministic misfit: a law's misfit is then concentrated
 * in the large early motion of a decay, and the robust statistic, whose variance is that same
 * misfit, cannot exceed the handful of independent pieces it spans. Independent noise added to
 * a linear record leaves it a linear record. At 60 dB below the signal it is far above the
 * record's rounding; the tenth keeps a dithered record's linear controls, whose noise is the
 * dither, from being dithered again. */
static size_t dither(double *ys, size_t n, size_t m, const aenl_em_model_t *mod, int *dithered)
{
    aenl_rng_t g;
    aenl_rng_seed(&g, NLT_DITHER_SEED);
    const double floor_sd = 0.1 * AENL_NLT_DITHER;
    size_t cnt = 0;
    for (size_t j = 0; j < m; ++j)
    {
        dithered[j] = mod->R[j * m + j] < floor_sd * floor_sd;
        for (size_t t = 0; dithered[j] && t < n; ++t)
        {
            ys[t * m + j] += AENL_NLT_DITHER * aenl_rng_gauss(&g);
        }
        cnt += dithered[j] ? 1u : 0u;
    }
    return cnt;
}

/* An empty filter pass of the record for em's model. */
static void kf_setup(kf_t *kf, const run_t *rn, const aenl_em_result_t *em, const double *in)
{
    memset(kf, 0, sizeof(*kf));
    kf->n = rn->n;
    kf->nz = rn->nz;
    kf->nx = em->model.n_x;
    kf->in = in;
    kf->n_in = rn->n_in;
}

/* The linear model of the scaled record ys and its Kalman filter pass into kf (set up here even
 * when st, the status so far, is a failure: the run frees it either way). Channels whose fitted
 * noise is nil are dithered after a first fit, and the model fitted again before the filter
 * runs (dithered[j], one per channel). */
static aenl_status_t fit_and_filter(aenl_status_t st, double *ys, const double *in,
                                    const size_t *cand, size_t n_cand, const run_t *rn,
                                    aenl_em_result_t *em, kf_t *kf, unsigned char *flag,
                                    size_t *n_impulses, int *dithered, aenl_err_t *err)
{
    const size_t n = rn->n;
    const size_t n_ch = rn->nz;
    const size_t n_in = rn->n_in;
    memset(em, 0, sizeof(*em));
    if (st == AENL_OK)
    {
        st = fit_linear_order(ys, n, n_ch, cand, n_cand, rn->opts->em_iter, in, n_in, em, err);
    }
    if (st == AENL_OK && dither(ys, n, n_ch, &em->model, dithered) > 0)
    {
        aenl_em_result_free(em);
        st = fit_linear_order(ys, n, n_ch, cand, n_cand, rn->opts->em_iter, in, n_in, em, err);
        if (st != AENL_OK && err != NULL)
        {
            char why[sizeof(err->msg)];
            (void)snprintf(why, sizeof(why), "%s", err->msg);
            aenl_err_set(err, "%s, once dithered (the record's fitted noise is nil)", why);
        }
    }
    kf_setup(kf, rn, em, in);
    if (st == AENL_OK)
    {
        st = filter_with_impulses(ys, em, kf, flag, n_impulses, err);
    }
    return st;
}

/* The run's summary fields of res (its channels are filled by test_channel). */
static void result_header(aenl_nlt_result_t *res, const run_t *rn, double loglik)
{
    res->n_channels = rn->nz;
    res->n_samples = rn->n;
    res->n_states = rn->nx;
    res->n_inputs = rn->opts->n_input;
    res->level = rn->opts->level;
    res->loglik = loglik;
    res->rows = (double)rn->kf->rows;
    res->verdict = -1;
    res->verdict_class = AENL_CLASS_LINEAR;
}

/* The end of a run: a successful one with keep hands the fitted model em and the scaled inputs
 * in, in_col over to keep; otherwise they are freed. Returns st. */
static aenl_status_t hand_over(aenl_status_t st, kept_t *keep, aenl_em_result_t *em, double *in,
                               double *in_col)
{
    if (keep != NULL && st == AENL_OK)
    {
        keep->em = *em;
        keep->in = in;
        keep->in_col = in_col;
        return st;
    }
    free(in);
    free(in_col);
    aenl_em_result_free(em);
    return st;
}

/* The test of the record against the linear model em, filtered in kf: the summary, every
 * channel's statistic (and laws unless stats_only) and the verdict into res. */
static aenl_status_t test_pass(run_t *rn, const aenl_em_result_t *em, const kf_t *kf,
                               int stats_only, aenl_nlt_result_t *res, aenl_err_t *err)
{
    rn->nx = em->model.n_x;
    rn->kf = kf;
    rn->m = &em->model;
    memset(rn->crit, 0, sizeof(rn->crit));
    memset(rn->compared, 0, sizeof(rn->compared));
    rn->G_nn = NULL;
    rn->R_nn = NULL;
    const size_t n_loss = rn->nz * rn->n * AENL_NLT_N_LAWS;
    rn->loss = n_loss > 0 ? (double *)malloc(n_loss * sizeof(double)) : NULL;
    aenl_status_t st = AENL_OK;
    if (rn->loss == NULL)
    {
        aenl_err_set(err, n_loss > 0 ? "out of memory" : "aenl_nltest: an empty record");
        st = n_loss > 0 ? AENL_E_DIM : AENL_E_ARG;
    }
    result_header(res, rn, em->loglik_final);
    rn->lnrows = log(fmax((double)kf->rows, 2.0));
    double pmin = 1.0;
    if (st == AENL_OK)
    {
        /* linear controls (stats_only) run as many at once as there are jobs, each its own
         * pass: they share the memory the record's own pass may take */
        st = nuisance_products(rn, stats_only ? NLT_R_KEEP_MAX / aenl_jobs() : NLT_R_KEEP_MAX, err);
    }
    if (st == AENL_OK)
    {
        st = test_channels(rn, stats_only, res, &pmin, err);
    }
    if (st == AENL_OK)
    {
        res->confidence = bonferroni_confidence(pmin, rn->nz);
        res->class_confidence = res->confidence;
        res->channel_confidence = 1.0;
        st = verdict_comparison(rn, res, err);
    }
    free(rn->loss);
    rn->loss = NULL;
    free(rn->G_nn);
    rn->G_nn = NULL;
    free(rn->R_nn);
    rn->R_nn = NULL;
    rn->kf = NULL; /* the caller's: they need not outlive this pass */
    rn->m = NULL;
    return st;
}

/* The record as driven by impulses (opts->impulsive): the impulses found afresh on the filter of
 * the fitted model em (flag, n samples, receives them), the model fitted again with them as state
 * jumps (jump_model), and the test run again with it into res; em becomes the jump model. A
 * linear structure driven by sparse jumps is not a linear Gaussian process: a Gaussian process
 * noise fitted through the jumps holds their energy at every sample, the filter then follows
 * the measurement noise between them too closely, and its misprediction, which grows and fades
 * with the motion, reads as a law. *applied says whether it was done: without an impulse, or
 * when no refit succeeded, the caller tests the record against em as fitted. */
static aenl_status_t impulsive_pass(const double *ys, const double *in, run_t *rn,
                                    unsigned char *flag, int stats_only, aenl_em_result_t *em,
                                    aenl_nlt_result_t *res, int *applied, aenl_err_t *err)
{
    *applied = 0;
    aenl_em_result_t ej;
    memset(&ej, 0, sizeof(ej));
    aenl_status_t st = aenl_em_model_copy(&ej.model, &em->model, err);
    ej.loglik_final = em->loglik_final;
    kf_t kj;
    kf_setup(&kj, rn, &ej, in);
    aenl_nlt_result_t *rj = (aenl_nlt_result_t *)calloc(1, sizeof(*rj));
    if (rj == NULL && st == AENL_OK)
    {
        aenl_err_set(err, "out of memory");
        st = AENL_E_DIM;
    }
    size_t nj = 0;
    if (st == AENL_OK)
    {
        st = nlt_kf_run(&kj, &ej.model, ys, NULL, NULL, err);
    }
    if (st == AENL_OK)
    {
        memset(flag, 0, rn->n);
        st = nlt_impulses(&kj, 1, flag, &nj, err);
    }
    int refitted = 0;
    if (st == AENL_OK && nj > 0)
    {
        st = jump_model(ys, in, rn, &ej, &kj, flag, &nj, &refitted, err);
    }
    if (st == AENL_OK && nj > 0 && refitted)
    {
        for (size_t j = 0; j < rn->nz; ++j)
        {
            rj->ch[j].dithered = res->ch[j].dithered;
        }
        rj->n_dithered = res->n_dithered;
        rj->n_impulses = nj;
        rj->jumps = 1;
        st = test_pass(rn, &ej, &kj, stats_only, rj, err);
        if (st == AENL_OK)
        {
            *res = *rj;
            aenl_em_result_free(em);
            *em = ej;
            memset(&ej, 0, sizeof(ej));
            *applied = 1;
        }
    }
    aenl_em_result_free(&ej);
    nlt_kf_free(&kj);
    free(rj);
    return st;
}

/* The test of a record (stage 2 too unless stats_only) on channels col[j], sample t at
 * col[j][t * stride]: row-major records and separate columns both enter without a copy (the
 * run makes its own scaled one). With keep, a successful run hands its fitted model and scaled
 * inputs over instead of freeing them. */
static aenl_status_t run_core(const double *const *col, size_t stride, size_t n, size_t n_ch,
                              const aenl_nlt_opts_t *opts, aenl_nlt_result_t *res, aenl_err_t *err,
                              int stats_only, kept_t *keep)
{
    int cols_ok = col != NULL;
    for (size_t j = 0; cols_ok && j < n_ch && j < AENL_NLT_MAX_CH; ++j)
    {
        cols_ok = col[j] != NULL;
    }
    aenl_status_t st = check_args(cols_ok ? col[0] : NULL, n, n_ch, opts, res, err);
    if (st != AENL_OK)
    {
        return st;
    }
    memset(res, 0, sizeof(*res));
    size_t cand[NLT_N_ORDERS];
    const size_t n_cand = state_candidates(opts, n, n_ch, cand);
    if (n_cand == 0)
    {
        return too_few_samples(opts, n, n_ch, err);
    }
    run_t rn;
    memset(&rn, 0, sizeof(rn));
    rn.opts = opts;
    rn.n = n;
    rn.nz = n_ch;
    double *ys = NULL;
    st = scale_channels(col, stride, n, n_ch, rn.scale, &ys, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const size_t n_in = NLT_HOLD * opts->n_input;
    double *in = n_in > 0 ? (double *)malloc(n * n_in * sizeof(double)) : NULL;
    if (n_in > 0 && in == NULL)
    {
        free(ys);
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    double *in_col = n_in > 0 ? (double *)malloc(n * n_in * sizeof(double)) : NULL;
    st = scale_inputs(opts, n, in, in_col, &rn, err);
    rn.n_in = n_in;
    aenl_em_result_t em;
    kf_t kf;
    int dithered[AENL_NLT_MAX_CH] = {0};
    unsigned char *flag = (unsigned char *)calloc(n, 1);
    if (flag == NULL && st == AENL_OK)
    {
        aenl_err_set(err, "out of memory");
        st = AENL_E_DIM;
    }
    st = fit_and_filter(st, ys, in, cand, n_cand, &rn, &em, &kf, flag, &res->n_impulses, dithered,
                        err);
    for (size_t j = 0; j < n_ch; ++j)
    {
        res->ch[j].dithered = dithered[j];
        res->n_dithered += dithered[j] ? 1u : 0u;
    }
    /* declared impulsive, the record is tested against its jump model; without an impulse, or
     * not declared, against the linear model as fitted */
    int applied = 0;
    if (st == AENL_OK && opts->impulsive)
    {
        st = impulsive_pass(ys, in, &rn, flag, stats_only, &em, res, &applied, err);
    }
    if (st == AENL_OK && !applied)
    {
        st = test_pass(&rn, &em, &kf, stats_only, res, err);
    }
    free(flag);
    free(ys);
    nlt_kf_free(&kf);
    if (keep != NULL)
    {
        memcpy(keep->scale, rn.scale, sizeof(keep->scale));
    }
    return hand_over(st, keep, &em, in, in_col);
}

/* The run's first linear control into out (n x n_ch, row-major) in the channels' units. */
static aenl_status_t control_record(const kept_t *keep, size_t n, size_t n_ch,
                                    const aenl_nlt_opts_t *opts, double *out, aenl_err_t *err)
{
    const aenl_em_model_t *m = &keep->em.model;
    double Lq[NLT_MAX_X * NLT_MAX_X];
    double Lr[AENL_NLT_MAX_CH * AENL_NLT_MAX_CH];
    const aenl_status_t st = control_noise(m, n_ch, Lq, Lr, err);
    if (st != AENL_OK)
    {
        return st;
    }
    double *buf = (double *)calloc(n * n_ch, sizeof(double)); /* every value is written */
    if (buf == NULL)
    {
        aenl_err_set(err, "out of memory");
        return AENL_E_DIM;
    }
    double *y[AENL_NLT_MAX_CH];
    for (size_t j = 0; j < n_ch; ++j)
    {
        y[j] = buf + j * n;
    }
    control_series(m, keep->in, Lq, Lr, opts->control_seed, 0, n, y);
    for (size_t t = 0; t < n; ++t)
    {
        for (size_t j = 0; j < n_ch; ++j)
        {
            out[t * n_ch + j] = y[j][t] * keep->scale[j];
        }
    }
    free(buf);
    return AENL_OK;
}

/* The test of a record, then its linear controls and its control record when the options ask
 * for them. */
static aenl_status_t run_strided(const double *const *col, size_t stride, size_t n, size_t n_ch,
                                 const aenl_nlt_opts_t *opts, aenl_nlt_result_t *res,
                                 aenl_err_t *err)
{
    kept_t keep;
    memset(&keep, 0, sizeof(keep));
    const int controls = opts != NULL && opts->n_controls > 0;
    const int record = opts != NULL && opts->control_record != NULL;
    aenl_status_t st =
        run_core(col, stride, n, n_ch, opts, res, err, 0, controls || record ? &keep : NULL);
    if (st == AENL_OK && controls)
    {
        const double *in_cols[AENL_EM_MAX_U] = {NULL};
        for (size_t p = 0; p < keep.em.model.n_u; ++p)
        {
            in_cols[p] = keep.in_col + p * n;
        }
        st = linear_controls(&keep.em.model, keep.in, in_cols, n, n_ch, opts, res, err);
    }
    if (st == AENL_OK && record)
    {
        st = control_record(&keep, n, n_ch, opts, opts->control_record, err);
    }
    free(keep.in);
    free(keep.in_col);
    aenl_em_result_free(&keep.em);
    return st;
}

aenl_status_t aenl_nlt_run(const double *y, size_t n, size_t n_ch, const aenl_nlt_opts_t *opts,
                           aenl_nlt_result_t *res, aenl_err_t *err)
{
    const double *col[AENL_NLT_MAX_CH] = {NULL};
    for (size_t j = 0; y != NULL && j < n_ch && j < AENL_NLT_MAX_CH; ++j)
    {
        col[j] = y + j;
    }
    return run_strided(y != NULL ? col : NULL, n_ch, n, n_ch, opts, res, err);
}

aenl_status_t aenl_nlt_run_columns(const double *const *cols, size_t n, size_t n_ch,
                                   const aenl_nlt_opts_t *opts, aenl_nlt_result_t *res,
                                   aenl_err_t *err)
{
    return run_strided(cols, 1, n, n_ch, opts, res, err);
}
