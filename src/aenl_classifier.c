/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_classifier.c
 * @brief Incremental nonlinearity classifier (see aenl_classifier.h for the method).
 *
 * Coordinates: every fit runs on scaled points, u = (p - centre) / half-range in [-1, 1] and
 * a / rms(a), so the normal equations are well scaled in float32 whatever the signal's units.
 * Normal equations: a hinge (u - b)+ only touches the points above b, so with the points sorted
 * by u and suffix sums
 *     S_m = sum_{u > b} W u^m (m = 0..2),  V_m = sum_{u > b} W v u^m,  T_m = sum_{u > b} W a u^m
 * (m = 0..1) every entry of a kinked law's normal equations costs O(1) per candidate b (plus a
 * binary search for the first point above it):
 *     sum W (u - b)+ = S1 - b S0,  sum W u (u - b)+ = S2 - b S1,
 *     sum W (u - b)+^2 = S2 - 2b S1 + b^2 S0,  sum W (u - b1)+ (u - b2)+ over u > b2 (b1 < b2)
 *     = S2 - (b1 + b2) S1 + b1 b2 S0,  sum W v (u - b)+ = V1 - b V0,  sum W a (u - b)+ = T1 - b T0.
 * The two directions share every coefficient of a law (the restoring force does not depend on the
 * direction for linear, polynomial and freeplay laws; a damping-like term c v carries what the
 * direction changes for them), so their normal equations are summed; hysteresis adds what only it
 * can explain: the kinks shift with the direction, and the rising points get their own offset.
 */
#include "aenl/aenl_classifier.h"

#include <string.h>

#include "aenl_linalg.h"

/** Largest basis: 1, u, v, rising offset, hinge 1, hinge 2. */
#define NB_MAX 6

/**
 * Degrees of freedom of a location searched over the candidates (a kink, a shift): more than one
 * parameter, since the search picks the best of many fits. Three, as in adaptive regression
 * splines (a knot costs 2-3 parameters).
 */
#define KINK_DF 3u

/** Kink searches: candidates and shifts of the coarse pass at most (bounded work per update). */
#define SEARCH_MAX       48u
#define SEARCH_MAX_SHIFT 16u

/** Huber threshold of the robust loss, in noise standard deviations. */
#define HUBER_C AENL_R(2.0)

typedef aenl_cls_sums_t cls_sums_t;
typedef aenl_cls_table_t cls_table_t;

/** One set of points sorted by u. */
typedef struct cls_set
{
    const aenl_cls_point_t *pt;
    uint32_t n;
} cls_set_t;

/** What every fit of one evidence reads: its sets (the second: falling points), their suffix
 *  tables and the candidate kink positions. */
typedef struct cls_data
{
    const cls_set_t *s;
    const cls_table_t *t;
    uint32_t n_sets;
    const aenl_real_t *cand; /**< ascending */
    uint32_t n_cand;
} cls_data_t;

/** A law fitted to one or two sets (the second: falling points). */
typedef struct cls_spec
{
    uint8_t cubic;     /**< 1: cubic in u; else linear with n_k hinges */
    uint8_t use_v;     /**< velocity regressor */
    uint8_t dir_term;  /**< an own offset for set 0 (rising) */
    uint8_t n_k;       /**< hinges, 0..2 */
    aenl_real_t b[2];  /**< kinks, ascending */
    aenl_real_t shift; /**< set 0 kinks at b + shift/2, set 1 at b - shift/2 */
} cls_spec_t;

/** Result of a kink search. */
typedef struct cls_kinks
{
    aenl_real_t rss;
    aenl_real_t b[2];
    aenl_real_t curv[2]; /**< curvature of the RSS profile at each kink (0: unknown) */
    aenl_real_t shift;
    int ok;
} cls_kinks_t;

static const char *const k_class_names[AENL_CLASS_COUNT] = {"insufficient", "linear", "polynomial",
                                                            "freeplay", "hysteresis"};

const char *aenl_class_name(aenl_class_t cls)
{
    return ((unsigned)cls < AENL_CLASS_COUNT) ? k_class_names[cls] : "unknown";
}

void aenl_classifier_cfg_default(aenl_classifier_cfg_t *cfg)
{
    if (cfg == NULL)
    {
        return;
    }
    memset(cfg, 0, sizeof(*cfg));
    cfg->taylor_order = 2u;
    cfg->trim = AENL_R(0.03);
    cfg->min_n_eff = AENL_R(20.0);
    cfg->min_nodes = 8u;
}

aenl_status_t aenl_classifier_init(aenl_classifier_t *c, const aenl_classifier_cfg_t *cfg)
{
    /* the range tests reject NaN (every comparison false) and Inf */
    if (c == NULL || cfg == NULL || cfg->taylor_order < 2u ||
        cfg->taylor_order > AENL_MOMENTS_TAYLOR_MAX_ORDER ||
        !(cfg->trim >= AENL_R(0.0) && cfg->trim < AENL_R(0.25)) ||
        !(cfg->min_n_eff >= AENL_R(1.0) && cfg->min_n_eff <= AENL_REAL_MAX) ||
        cfg->min_nodes < 8u || cfg->min_nodes > AENL_CLASSIFIER_MAX_NODES ||
        cfg->use_noise_acf > 1u)
    {
        return AENL_E_ARG;
    }
    memset(c, 0, sizeof(*c));
    c->cfg = *cfg;
    c->res.cls = AENL_CLASS_INSUFFICIENT;
    return AENL_OK;
}

/* ---- point sets -------------------------------------------------------------------------- */

/** Insertion sort by u (at most AENL_CLASSIFIER_MAX_NODES points, nearly sorted already). */
static void sort_points(aenl_cls_point_t *pt, uint32_t n)
{
    for (uint32_t i = 1; i < n; ++i)
    {
        const aenl_cls_point_t key = pt[i];
        uint32_t j = i;
        while (j > 0u && pt[j - 1u].p > key.p)
        {
            pt[j] = pt[j - 1u];
            --j;
        }
        pt[j] = key;
    }
}

/** Index of the first point with u > b. */
static uint32_t first_above(const cls_set_t *s, aenl_real_t b)
{
    uint32_t lo = 0u, hi = s->n;
    while (lo < hi)
    {
        const uint32_t mid = (uint32_t)((lo + hi) / 2u);
        if (s->pt[mid].p > b)
        {
            hi = mid;
        }
        else
        {
            lo = (uint32_t)(mid + 1u);
        }
    }
    return lo;
}

/** Suffix-sum table of a set, built once per set in O(n). */
static void build_table(const cls_set_t *s, cls_table_t *t)
{
    memset(&t->row[s->n], 0, sizeof(t->row[0]));
    t->wvv = t->wva = t->waa = AENL_R(0.0);
    for (int k = (int)s->n - 1; k >= 0; --k)
    {
        const aenl_cls_point_t *q = &s->pt[k];
        const cls_sums_t *nx = &t->row[k + 1];
        cls_sums_t *r = &t->row[k];
        const aenl_real_t w = q->w, wu = w * q->p;
        r->s0 = nx->s0 + w;
        r->s1 = nx->s1 + wu;
        r->s2 = nx->s2 + wu * q->p;
        r->v0 = nx->v0 + w * q->v;
        r->v1 = nx->v1 + wu * q->v;
        r->t0 = nx->t0 + w * q->a;
        r->t1 = nx->t1 + wu * q->a;
        t->wvv += w * q->v * q->v;
        t->wva += w * q->v * q->a;
        t->waa += w * q->a * q->a;
    }
}

/* ---- one weighted least-squares fit ------------------------------------------------------ */

static uint32_t spec_nb(const cls_spec_t *sp)
{
    return sp->cubic ? (uint32_t)(4u + sp->use_v)
                     : (uint32_t)(2u + sp->use_v + sp->dir_term + sp->n_k);
}

/** Kinks of set d: b + shift/2 on set 0 (rising), b - shift/2 on set 1 (falling). */
static void set_kinks(const cls_spec_t *sp, uint32_t d, aenl_real_t *bb)
{
    aenl_real_t off = AENL_R(0.5) * sp->shift;
    off = (d == 0u) ? off : -off;
    bb[0] = sp->b[0] + off;
    bb[1] = sp->b[1] + off;
}

/** Basis functions of the law at one point of set d, in coefficient order; returns their count. */
static uint32_t basis(const cls_spec_t *sp, uint32_t d, const aenl_cls_point_t *q,
                      const aenl_real_t *bb, aenl_real_t *phi)
{
    uint32_t k = 0u;
    phi[k++] = AENL_R(1.0);
    phi[k++] = q->p;
    if (sp->cubic)
    {
        phi[k++] = q->p * q->p;
        phi[k++] = q->p * q->p * q->p;
    }
    if (sp->use_v)
    {
        phi[k++] = q->v;
    }
    if (!sp->cubic)
    {
        if (sp->dir_term)
        {
            phi[k++] = (d == 0u) ? AENL_R(1.0) : AENL_R(0.0);
        }
        for (uint32_t j = 0; j < sp->n_k; ++j)
        {
            phi[k++] = (q->p > bb[j]) ? q->p - bb[j] : AENL_R(0.0);
        }
    }
    return k;
}

/**
 * Add row col of a kinked law's normal equations (lower triangle): e holds its products with
 * 1, u, v, itself and a; the rising offset's product equals the one with 1. Columns iv
 * (velocity) and idr (rising offset) lie left of col, or are 0 when absent.
 */
static void add_column(aenl_real_t g[NB_MAX][NB_MAX], aenl_real_t *r, uint32_t col,
                       const aenl_real_t *e, uint32_t iv, uint32_t idr)
{
    g[col][0] += e[0];
    g[col][1] += e[1];
    if (iv != 0u)
    {
        g[col][iv] += e[2];
    }
    if (idr != 0u)
    {
        g[col][idr] += e[0];
    }
    g[col][col] += e[3];
    r[col] += e[4];
}

/**
 * Add the normal equations of set d (lower triangle of g, right-hand side r, sum of w a^2).
 * Kinked laws read the suffix table: O(n_k log n); cubic laws sum over the points: O(n).
 */
static void accumulate(const cls_set_t *s, const cls_table_t *t, const cls_spec_t *sp, uint32_t d,
                       aenl_real_t g[NB_MAX][NB_MAX], aenl_real_t *r, aenl_real_t *waa)
{
    aenl_real_t bb[2];
    set_kinks(sp, d, bb);
    *waa += t->waa;
    if (sp->cubic)
    {
        for (uint32_t i = 0; i < s->n; ++i)
        {
            const aenl_cls_point_t *q = &s->pt[i];
            aenl_real_t phi[NB_MAX];
            const uint32_t nb = basis(sp, d, q, bb, phi);
            for (uint32_t a = 0; a < nb; ++a)
            {
                for (uint32_t b = a; b < nb; ++b)
                {
                    g[b][a] += q->w * phi[a] * phi[b];
                }
                r[a] += q->w * phi[a] * q->a;
            }
        }
        return;
    }
    const cls_sums_t *tot = &t->row[0];
    /* columns of the velocity and of the rising offset (0: not in this law or set) */
    const uint32_t iv = sp->use_v ? 2u : 0u, idr = 2u + sp->use_v;
    const uint32_t h0 = 2u + sp->use_v + sp->dir_term;
    const uint32_t own = (sp->dir_term && d == 0u) ? idr : 0u;
    g[0][0] += tot->s0;
    g[1][0] += tot->s1;
    g[1][1] += tot->s2;
    r[0] += tot->t0;
    r[1] += tot->t1;
    if (sp->use_v)
    {
        const aenl_real_t e[5] = {tot->v0, tot->v1, AENL_R(0.0), t->wvv, t->wva};
        add_column(g, r, iv, e, 0u, 0u);
    }
    if (own != 0u)
    {
        const aenl_real_t e[5] = {tot->s0, tot->s1, tot->v0, tot->s0, tot->t0};
        add_column(g, r, own, e, iv, 0u);
    }
    for (uint32_t j = 0; j < sp->n_k; ++j)
    {
        const cls_sums_t *q = &t->row[first_above(s, bb[j])];
        const aenl_real_t bj = bb[j];
        const uint32_t hj = h0 + j;
        const aenl_real_t e[5] = {q->s1 - bj * q->s0, /* sum w (u - b)+ */
                                  q->s2 - bj * q->s1, q->v1 - bj * q->v0,
                                  q->s2 - AENL_R(2.0) * bj * q->s1 + bj * bj * q->s0,
                                  q->t1 - bj * q->t0};
        add_column(g, r, hj, e, iv, own);
        for (uint32_t i = 0; i < j; ++i) /* bb[i] < bb[j]: the product lives above bb[j] */
        {
            g[hj][h0 + i] += q->s2 - (bb[i] + bj) * q->s1 + bb[i] * bj * q->s0;
        }
    }
}

/**
 * Weighted least squares of a law over n_sets sets (shared coefficients). Returns the residual
 * sum of squares (floored at a tiny fraction of sum w a^2), or -1 when the normal equations are
 * singular. coef (NB_MAX) and res (standardised residuals sqrt(w) (a - fit), set after set) may
 * be NULL.
 */
static aenl_real_t fit(const cls_data_t *dt, const cls_spec_t *sp, aenl_real_t *coef,
                       aenl_real_t *res)
{
    const cls_set_t *s = dt->s;
    const uint32_t n_sets = dt->n_sets;
    aenl_real_t g[NB_MAX][NB_MAX], r[NB_MAX], c[NB_MAX], waa = AENL_R(0.0);
    memset(g, 0, sizeof(g));
    memset(r, 0, sizeof(r));
    const uint32_t nb = spec_nb(sp);
    for (uint32_t d = 0; d < n_sets; ++d)
    {
        accumulate(&s[d], &dt->t[d], sp, d, g, r, &waa);
    }
    memcpy(c, r, sizeof(c)); /* g holds the lower triangle, all that the factorisation reads */
    if (aenl_la_chol(&g[0][0], NB_MAX, (uint16_t)nb) != AENL_OK)
    {
        return AENL_R(-1.0);
    }
    aenl_la_chol_solve(&g[0][0], NB_MAX, (uint16_t)nb, c, 1u, 1u);
    aenl_real_t explained = AENL_R(0.0);
    for (uint32_t a = 0; a < nb; ++a)
    {
        explained += c[a] * r[a];
    }
    const aenl_real_t floor_rss = waa * AENL_R(1e-9);
    aenl_real_t rss = waa - explained;
    rss = (aenl_is_finite(rss) && rss > floor_rss) ? rss : floor_rss;
    if (coef != NULL)
    {
        memcpy(coef, c, sizeof(c));
    }
    if (res != NULL)
    {
        uint32_t k = 0u;
        for (uint32_t d = 0; d < n_sets; ++d)
        {
            aenl_real_t bb[2];
            set_kinks(sp, d, bb);
            for (uint32_t i = 0; i < s[d].n; ++i)
            {
                aenl_real_t phi[NB_MAX], f = AENL_R(0.0);
                const aenl_cls_point_t *q = &s[d].pt[i];
                const uint32_t m = basis(sp, d, q, bb, phi);
                for (uint32_t a = 0; a < m; ++a)
                {
                    f += c[a] * phi[a];
                }
                res[k++] = aenl_sqrt(q->w) * (q->a - f);
            }
        }
    }
    return rss;
}

/* ---- kink search ------------------------------------------------------------------------- */

/** RSS of sp with kink j moved to b, or -1 when the kinks are then out of order or the fit fails.
 */
static aenl_real_t fit_kink(const cls_data_t *dt, cls_spec_t *sp, uint32_t j, aenl_real_t b)
{
    sp->b[j] = b;
    return (sp->n_k == 2u && !(sp->b[0] < sp->b[1])) ? AENL_R(-1.0) : fit(dt, sp, NULL, NULL);
}

/**
 * Refine kink j of the best fit by a parabola through the RSS at the candidate and its two
 * neighbours; keep the vertex when it fits better, and the profile's curvature for the standard
 * error.
 */
static void refine_kink(const cls_data_t *dt, const cls_spec_t *best, uint32_t ci, uint32_t j,
                        cls_kinks_t *k)
{
    const aenl_real_t *cand = dt->cand;
    k->curv[j] = AENL_R(0.0);
    if (ci == 0u || ci + 1u >= dt->n_cand)
    {
        return;
    }
    cls_spec_t sp = *best;
    const aenl_real_t x0 = cand[ci - 1u], x1 = cand[ci], x2 = cand[ci + 1u];
    aenl_real_t rr[2];
    const aenl_real_t xs[2] = {x0, x2};
    for (uint32_t e = 0; e < 2u; ++e)
    {
        rr[e] = fit_kink(dt, &sp, j, xs[e]);
        if (rr[e] < AENL_R(0.0))
        {
            return;
        }
    }
    const aenl_real_t r1 = k->rss;
    const aenl_real_t d01 = (r1 - rr[0]) / (x1 - x0), d12 = (rr[1] - r1) / (x2 - x1);
    const aenl_real_t c2 = (d12 - d01) / (x2 - x0);
    if (!(c2 > AENL_R(0.0)) || !aenl_is_finite(c2))
    {
        return;
    }
    k->curv[j] = AENL_R(2.0) * c2;
    /* vertex of rr0 + d01 (x - x0) + c2 (x - x0)(x - x1) */
    aenl_real_t v = AENL_R(0.5) * (x0 + x1) - d01 / (AENL_R(2.0) * c2);
    v = (v < x0) ? x0 : ((v > x2) ? x2 : v);
    const aenl_real_t rv = fit_kink(dt, &sp, j, v);
    if (rv >= AENL_R(0.0) && rv <= k->rss)
    {
        k->rss = rv;
        k->b[j] = v;
    }
}

/**
 * Best kinks (base->n_k, 1 or 2) at the candidate positions cand[] (ascending), and, with
 * n_shift > 0, the best shift of the kinks between the directions among 0, 1, .., n_shift steps
 * of the mean candidate spacing. Cost: O(n_cand^n_k (n_shift + 1)) fits of O(n_sets log n) each.
 */
/** A box of the search: shifts js_lo..js_hi, first kinks i_lo..i_hi, second kinks j_lo..j_hi
 *  (n_k 2; j >= i + 2), each in steps of `step` (shifts of `shift_step`). */
typedef struct cls_box
{
    uint32_t js_lo, js_hi, shift_step, i_lo, i_hi, j_lo, j_hi, step;
} cls_box_t;

/** Fit every candidate of the box; keep the best in k (and its candidate indices). */
static void scan_box(const cls_data_t *dt, const cls_spec_t *base, aenl_real_t du,
                     const cls_box_t *bx, cls_kinks_t *k, uint32_t *bi, uint32_t *bj)
{
    const aenl_real_t *cand = dt->cand;
    const uint32_t n_cand = dt->n_cand;
    cls_spec_t sp = *base;
    for (uint32_t js = bx->js_lo; js <= bx->js_hi; js = (uint32_t)(js + bx->shift_step))
    {
        sp.shift = (aenl_real_t)js * du;
        for (uint32_t i = bx->i_lo; i <= bx->i_hi && i + 2u < n_cand; i = (uint32_t)(i + bx->step))
        {
            sp.b[0] = cand[i];
            const uint32_t j_lo = (sp.n_k == 2u) ? bx->j_lo : i;
            const uint32_t j_hi = (sp.n_k == 2u) ? bx->j_hi : i;
            for (uint32_t j = j_lo; j <= j_hi; j = (uint32_t)(j + (sp.n_k == 2u ? bx->step : 1u)))
            {
                if (sp.n_k == 2u && (j < i + 2u || j + 2u >= n_cand))
                {
                    continue;
                }
                sp.b[1] = cand[j];
                const aenl_real_t rss = fit(dt, &sp, NULL, NULL);
                if (rss >= AENL_R(0.0) && rss < k->rss)
                {
                    k->rss = rss;
                    k->b[0] = sp.b[0];
                    k->b[1] = sp.b[1];
                    k->shift = sp.shift;
                    *bi = (uint32_t)i;
                    *bj = (uint32_t)j;
                    k->ok = 1;
                }
            }
        }
    }
}

static void search(const cls_data_t *dt, const cls_spec_t *base, uint32_t n_shift, cls_kinks_t *k)
{
    const aenl_real_t *cand = dt->cand;
    const uint32_t n_cand = dt->n_cand;
    memset(k, 0, sizeof(*k));
    k->rss = AENL_REAL_MAX;
    if (n_cand < 6u)
    {
        return;
    }
    const aenl_real_t du = (cand[n_cand - 1u] - cand[0]) / (aenl_real_t)(n_cand - 1u);
    /* bounded work: a coarse pass over at most SEARCH_MAX candidates and SEARCH_MAX_SHIFT
     * shifts, then full resolution around the best */
    const uint32_t stride = (uint32_t)((n_cand + SEARCH_MAX - 1u) / SEARCH_MAX);
    uint32_t shift_stride = (uint32_t)((n_shift + SEARCH_MAX_SHIFT - 1u) / SEARCH_MAX_SHIFT);
    shift_stride = (shift_stride > 0u) ? shift_stride : 1u;
    uint32_t bi = 0u, bj = 0u;
    const cls_box_t coarse = {
        0u,    n_shift, shift_stride, 1u, (uint32_t)(n_cand - 1u), 0u, (uint32_t)(n_cand - 1u),
        stride};
    scan_box(dt, base, du, &coarse, k, &bi, &bj);
    if (!k->ok)
    {
        return;
    }
    if (stride > 1u || shift_stride > 1u)
    {
        const uint32_t js0 = (uint32_t)(k->shift / du + AENL_R(0.5));
        const uint32_t js_hi = (uint32_t)(js0 + shift_stride);
        const cls_box_t fine = {(js0 > shift_stride) ? (uint32_t)(js0 - shift_stride) : 0u,
                                (js_hi < n_shift) ? js_hi : n_shift,
                                1u,
                                (bi > stride + 1u) ? (uint32_t)(bi - stride) : 1u,
                                (uint32_t)(bi + stride),
                                (bj > stride) ? (uint32_t)(bj - stride) : 0u,
                                (uint32_t)(bj + stride),
                                1u};
        scan_box(dt, base, du, &fine, k, &bi, &bj);
    }
    cls_spec_t best = *base;
    best.b[0] = k->b[0];
    best.b[1] = k->b[1];
    best.shift = k->shift;
    refine_kink(dt, &best, bi, 0u, k);
    if (base->n_k == 2u)
    {
        best.b[0] = k->b[0];
        refine_kink(dt, &best, bj, 1u, k);
    }
}

/* ---- evidence ---------------------------------------------------------------------------- */

/** Median of the squares of res[0..n) (reorders res). Quickselect, O(n) expected. */
static aenl_real_t median_sq(aenl_real_t *res, uint32_t n)
{
    for (uint32_t i = 0; i < n; ++i)
    {
        res[i] *= res[i];
    }
    uint32_t lo = 0u, hi = (uint32_t)(n - 1u);
    const uint32_t k = (uint32_t)(n / 2u);
    while (lo < hi)
    {
        const aenl_real_t pivot = res[(lo + hi) / 2u];
        uint32_t i = lo, j = hi;
        while (i <= j)
        {
            while (res[i] < pivot)
            {
                ++i;
            }
            while (res[j] > pivot)
            {
                --j;
            }
            if (i <= j)
            {
                const aenl_real_t t = res[i];
                res[i] = res[j];
                res[j] = t;
                ++i;
                if (j == 0u)
                {
                    break;
                }
                --j;
            }
        }
        if (k <= j)
        {
            hi = j;
        }
        else if (k >= i)
        {
            lo = i;
        }
        else
        {
            break;
        }
    }
    return res[k];
}

/**
 * Scale of the standardised residuals: one nominal standard error of the lag expansion, or more
 * when the best-fitting model's residuals say the nominal errors are optimistic (median of a
 * chi-square with one degree of freedom: 0.4549). Never less: estimates at neighbouring nodes share
 * trajectories, so their residuals are smooth and their scatter understates the error. The weights
 * were divided by wmax, so one nominal standard error is 1 / sqrt(wmax).
 */
static aenl_real_t noise_scale(aenl_real_t *res, uint32_t n, aenl_real_t wmax)
{
    /* the weights were divided by wmax: one nominal standard error is 1 / sqrt(wmax) */
    const aenl_real_t nominal = AENL_R(1.0) / aenl_sqrt(wmax);
    const aenl_real_t s = aenl_sqrt(median_sq(res, n) / AENL_R(0.4549));
    return (s > nominal) ? s : nominal;
}

/** Huber loss of standardised residuals at 1/inv_sigma: z^2 inside +-HUBER_C, linear beyond. */
static aenl_real_t huber_sum(const aenl_real_t *res, uint32_t n, aenl_real_t inv_sigma)
{
    aenl_real_t sum = AENL_R(0.0);
    for (uint32_t i = 0; i < n; ++i)
    {
        const aenl_real_t z = aenl_fabs(res[i] * inv_sigma);
        sum += (z <= HUBER_C) ? z * z : AENL_R(2.0) * HUBER_C * z - HUBER_C * HUBER_C;
    }
    return sum;
}

/**
 * Robust information criterion of a law: frac * sum huber(res / sigma) + k ln(n_ind). The loss
 * is the chi-square of the fit for residuals within HUBER_C sigma (a few misfitting nodes cannot
 * decide), counted per independent point.
 */
static aenl_real_t criterion(const cls_data_t *dt, const cls_spec_t *sp, aenl_real_t sigma,
                             aenl_real_t frac, aenl_real_t n_ind, uint32_t k, aenl_real_t *scratch)
{
    const cls_set_t *s = dt->s;
    const uint32_t n_sets = dt->n_sets;
    if (fit(dt, sp, NULL, scratch) < AENL_R(0.0))
    {
        return AENL_REAL_MAX;
    }
    uint32_t n = 0u;
    for (uint32_t d = 0; d < n_sets; ++d)
    {
        n = (uint32_t)(n + s[d].n);
    }
    return frac * huber_sum(scratch, n, AENL_R(1.0) / sigma) + (aenl_real_t)k * aenl_log(n_ind);
}

/**
 * Standard error of a kink from the curvature of the RSS profile: RSS(b) - RSS* = sigma^2 / frac
 * at one standard error (frac: independent share of the points). fallback when unknown.
 */
static aenl_real_t kink_se(aenl_real_t curv, aenl_real_t sigma, aenl_real_t frac,
                           aenl_real_t fallback)
{
    if (!(curv > AENL_R(0.0)))
    {
        return fallback;
    }
    const aenl_real_t se = aenl_sqrt(AENL_R(2.0) * sigma * sigma / (frac * curv));
    return (aenl_is_finite(se) && se < AENL_R(4.0) * fallback) ? se : fallback;
}

/** The scaled frame of the points and how many of them are independent. */
typedef struct cls_frame
{
    aenl_real_t centre, half; /**< p = centre + u half */
    aenl_real_t ascale;       /**< acceleration scale: a and v are divided by it */
    aenl_real_t frac;         /**< independent share of the nodes */
    aenl_real_t n_ind;        /**< independent points of all pairs */
    aenl_real_t wmax;         /**< divisor of the all-pairs weights */
    uint32_t n;               /**< points of all pairs */
    uint32_t nc;              /**< candidate kink positions */
} cls_frame_t;

/**
 * Gather the usable nodes of one direction into pt[], scaled in the frame fr:
 * p -> (p - centre) / half, a and v times inv_ascale, weight 1 / se_a^2 (scaled).
 */
static uint32_t gather(aenl_classifier_t *c, const aenl_moments_t *m, aenl_dir_t dir,
                       const cls_frame_t *fr, aenl_real_t inv_ascale, aenl_cls_point_t *pt)
{
    const aenl_real_t centre = fr->centre, inv_half = AENL_R(1.0) / fr->half;
    uint32_t n = 0u;
    for (uint32_t k = 0; k < m->cfg.n_grid; ++k)
    {
        if (!c->interior[k])
        {
            continue;
        }
        aenl_moments_point_t q;
        if (aenl_moments_query(m, 0u, (uint16_t)k, dir, &q) != AENL_OK ||
            q.n_eff < c->cfg.min_n_eff)
        {
            continue;
        }
        aenl_moments_taylor_t tx;
        if (aenl_moments_taylor_ex(m, (uint16_t)k, dir, c->cfg.taylor_order,
                                   c->cfg.use_noise_acf ? c->cfg.noise_acf : NULL,
                                   &tx) != AENL_OK ||
            !(tx.se_accel > AENL_R(0.0)) || !aenl_is_finite(tx.se_accel))
        {
            continue;
        }
        aenl_cls_point_t *o = &pt[n++];
        o->p = (tx.position - centre) * inv_half;
        o->a = tx.accel * inv_ascale;
        o->v = tx.velocity * inv_ascale;
        const aenl_real_t se = tx.se_accel * inv_ascale;
        o->w = AENL_R(1.0) / (se * se);
    }
    return n;
}

/** The largest of wmax and the weights of pt[0..n). */
static aenl_real_t max_weight(const aenl_cls_point_t *pt, uint32_t n, aenl_real_t wmax)
{
    for (uint32_t k = 0; k < n; ++k)
    {
        wmax = (pt[k].w > wmax) ? pt[k].w : wmax;
    }
    return wmax;
}

static void divide_weights(aenl_cls_point_t *pt, uint32_t n, aenl_real_t wmax)
{
    for (uint32_t k = 0; k < n; ++k)
    {
        pt[k].w /= wmax;
    }
}

/** Normalise the weights to a maximum of 1 (keeps every sum far from overflow in float32); returns
 * the divisor. */
static aenl_real_t normalise_weights(aenl_cls_point_t *pt, uint32_t n)
{
    const aenl_real_t wmax = max_weight(pt, n, AENL_R(0.0));
    divide_weights(pt, n, wmax);
    return wmax;
}

/** Candidate kink positions: the sorted u of the points (duplicates dropped). */
static uint32_t candidates(const aenl_cls_point_t *pt, uint32_t n, aenl_real_t *cand)
{
    uint32_t nc = 0u;
    for (uint32_t k = 0; k < n; ++k)
    {
        if (nc == 0u || pt[k].p > cand[nc - 1u])
        {
            cand[nc++] = pt[k].p;
        }
    }
    return nc;
}

/** Merge the switching points q[0..m) (value in p, standard error in w; sorted here) into
 *  distinct ones (closer than 2 combined se merge); m <= AENL_CLASSIFIER_MAX_SWITCH. */
static uint8_t merge_points(aenl_cls_point_t *q, uint32_t m, aenl_real_t *out, aenl_real_t *out_se)
{
    sort_points(q, m); /* by value */
    uint8_t k = 0u;
    for (uint32_t i = 0; i < m; ++i)
    {
        if (k > 0u)
        {
            const aenl_real_t tol =
                AENL_R(2.0) * aenl_sqrt(q[i].w * q[i].w + out_se[k - 1u] * out_se[k - 1u]);
            if (q[i].p - out[k - 1u] <= tol)
            {
                /* inverse-variance mean of the two estimates of one switching point */
                const aenl_real_t w1 = AENL_R(1.0) / (out_se[k - 1u] * out_se[k - 1u]);
                const aenl_real_t w2 = AENL_R(1.0) / (q[i].w * q[i].w);
                out[k - 1u] = (w1 * out[k - 1u] + w2 * q[i].p) / (w1 + w2);
                out_se[k - 1u] = aenl_sqrt(AENL_R(1.0) / (w1 + w2));
                continue;
            }
        }
        out[k] = q[i].p;
        out_se[k] = q[i].w;
        ++k;
    }
    return k;
}

/** Root mean square of a (the acceleration scale). */
static aenl_real_t accel_rms(const aenl_cls_point_t *pt, uint32_t n)
{
    aenl_real_t s = AENL_R(0.0);
    for (uint32_t k = 0; k < n; ++k)
    {
        s += pt[k].a * pt[k].a;
    }
    return aenl_sqrt(s / (aenl_real_t)n);
}

/** Divide a and v by the acceleration scale, multiply w by its square. */
static void rescale(aenl_cls_point_t *pt, uint32_t n, aenl_real_t inv_ascale)
{
    for (uint32_t k = 0; k < n; ++k)
    {
        pt[k].a *= inv_ascale;
        pt[k].v *= inv_ascale;
        pt[k].w /= inv_ascale * inv_ascale;
    }
}

/** Posterior weights exp(-B/2) of n criterion values, normalised. */
static void posterior(const aenl_real_t *b, uint32_t n, aenl_real_t *p)
{
    aenl_real_t bmin = b[0], sum = AENL_R(0.0);
    for (uint32_t i = 1; i < n; ++i)
    {
        bmin = (b[i] < bmin) ? b[i] : bmin;
    }
    for (uint32_t i = 0; i < n; ++i)
    {
        p[i] = aenl_exp(AENL_R(-0.5) * (b[i] - bmin));
        sum += p[i];
    }
    for (uint32_t i = 0; i < n; ++i)
    {
        p[i] /= sum;
    }
}

/**
 * Interior nodes: inside the central (1 - 2 trim) of the lag-0 conditioning weight, and where the
 * signal dominates the conditioning value: the noise-free position p(x) rises with x at a rate of
 * at least one half (the reliability ratio of errors in variables; towards the edges of a bounded
 * oscillation p(x) flattens, the measured extremes being mostly noise). The longest run of such
 * nodes is kept.
 */
static uint32_t mark_interior(aenl_classifier_t *c, const aenl_moments_t *m, aenl_real_t *x_lo,
                              aenl_real_t *x_hi)
{
    const uint32_t ng = m->cfg.n_grid;
    aenl_real_t total = AENL_R(0.0);
    for (uint32_t k = 0; k < ng; ++k)
    {
        aenl_moments_point_t q;
        const aenl_real_t w = (aenl_moments_query(m, 0u, (uint16_t)k, AENL_DIR_ALL, &q) == AENL_OK)
                                  ? q.weight
                                  : AENL_R(0.0);
        c->cand[k] = w; /* borrowed as scratch until the kink search */
        total += w;
        aenl_moments_taylor_t tx;
        c->pt[0][k].p = AENL_R(0.0); /* scratch: the position, valid flag in w */
        c->pt[0][k].w = AENL_R(0.0);
        if (w > AENL_R(0.0) &&
            aenl_moments_taylor_ex(m, (uint16_t)k, AENL_DIR_ALL, c->cfg.taylor_order,
                                   c->cfg.use_noise_acf ? c->cfg.noise_acf : NULL, &tx) == AENL_OK)
        {
            c->pt[0][k].p = tx.position;
            c->pt[0][k].w = AENL_R(1.0);
        }
    }
    aenl_real_t cum = AENL_R(0.0);
    for (uint32_t k = 0; k < ng; ++k)
    {
        const aenl_real_t w = c->cand[k];
        const aenl_real_t mid = cum + AENL_R(0.5) * w;
        cum += w;
        int in = (w > AENL_R(0.0)) && mid >= c->cfg.trim * total &&
                 mid <= (AENL_R(1.0) - c->cfg.trim) * total;
        if (in)
        {
            const uint32_t kl = (k > 0u) ? k - 1u : k;
            const uint32_t kr = (k + 1u < ng) ? k + 1u : k;
            in = kr > kl && c->pt[0][kl].w > AENL_R(0.0) && c->pt[0][kr].w > AENL_R(0.0) &&
                 (c->pt[0][kr].p - c->pt[0][kl].p) >= AENL_R(0.5) * (aenl_real_t)(kr - kl) * m->dx;
        }
        c->interior[k] = (uint8_t)in;
    }
    /* keep the longest run */
    uint32_t best_start = 0u, best_len = 0u, run = 0u;
    for (uint32_t k = 0; k < ng; ++k) /* the longest run, the first of equal ones */
    {
        run = c->interior[k] ? run + 1u : 0u;
        if (run > best_len)
        {
            best_len = run;
            best_start = k + 1u - run;
        }
    }
    for (uint32_t k = 0; k < ng; ++k)
    {
        c->interior[k] = (uint8_t)(k >= best_start && k < best_start + best_len);
    }
    *x_lo = aenl_moments_node_x(m, (uint16_t)best_start);
    *x_hi = aenl_moments_node_x(m, (uint16_t)(best_start + (best_len > 0u ? best_len - 1u : 0u)));
    return best_len;
}

/** Laws of the direction split, indices into cls_dir_t.bd. */
enum
{
    D_LIN = 0,
    D_POLY,
    D_FP1,
    D_FP2,
    D_HYST,
    D_N
};

/** The laws one fit compares; the kinked ones take their kinks from the searches. */
typedef struct cls_laws
{
    cls_spec_t lin, poly, one, two, hy; /**< one and two: hinges; hy: hysteresis */
} cls_laws_t;

/** Evidence from all pairs. */
typedef struct cls_all
{
    cls_kinks_t k1, k2;
    aenl_real_t b[AENL_CLS_N_MODELS];  /**< criterion of each law */
    aenl_real_t pm[AENL_CLS_N_MODELS]; /**< posterior weights */
    aenl_real_t se_k1, se_k2[2];       /**< standard errors of the kinks */
} cls_all_t;

/** Evidence from the direction split (the rest is valid only when ok). */
typedef struct cls_dir
{
    int ok;
    aenl_real_t nd_ind; /**< independent points of both directions */
    aenl_real_t bd[D_N];
    cls_kinks_t t1, t2, hy;
    aenl_real_t se_t1, se_t2[2], se_hy[2];
} cls_dir_t;

/** Publish r, counting the updates in a row that gave its class. */
static void publish(aenl_classifier_t *c, aenl_classifier_result_t *r)
{
    r->n_stable = (c->res.cls == r->cls) ? c->res.n_stable + 1u : 1u;
    c->res = *r;
}

/** The laws, with (use_v) or without the velocity regressor. */
static void laws_init(cls_laws_t *l, uint8_t use_v)
{
    /* cubic, use_v, dir_term, n_k; the kinks and the shift come from the searches */
    static const cls_laws_t k_laws = {{0u, 0u, 0u, 0u, {AENL_R(0.0), AENL_R(0.0)}, AENL_R(0.0)},
                                      {1u, 0u, 0u, 0u, {AENL_R(0.0), AENL_R(0.0)}, AENL_R(0.0)},
                                      {0u, 0u, 0u, 1u, {AENL_R(0.0), AENL_R(0.0)}, AENL_R(0.0)},
                                      {0u, 0u, 0u, 2u, {AENL_R(0.0), AENL_R(0.0)}, AENL_R(0.0)},
                                      {0u, 0u, 1u, 2u, {AENL_R(0.0), AENL_R(0.0)}, AENL_R(0.0)}};
    *l = k_laws;
    l->lin.use_v = l->poly.use_v = l->one.use_v = l->two.use_v = l->hy.use_v = use_v;
}

/**
 * The law whose residuals give the noise scale: the best-fitting of the polynomial (rss_poly,
 * negative when its fit failed) and the nk kinked laws, or the linear law when none fits.
 */
static const cls_spec_t *noise_reference(const cls_laws_t *l, aenl_real_t rss_poly,
                                         const cls_spec_t *const *ksp, const cls_kinks_t *const *kk,
                                         uint32_t nk)
{
    const cls_spec_t *ref = &l->poly;
    aenl_real_t ref_rss = (rss_poly >= AENL_R(0.0)) ? rss_poly : AENL_REAL_MAX;
    for (uint32_t i = 0; i < nk; ++i)
    {
        if (kk[i]->ok && kk[i]->rss < ref_rss)
        {
            ref = ksp[i];
            ref_rss = kk[i]->rss;
        }
    }
    return (ref_rss >= AENL_REAL_MAX) ? &l->lin : ref;
}

/**
 * The all-pairs points in c->pt[0], scaled, sorted and weighted, and their frame. Zero when too
 * few are usable for any fit (r->n_nodes says how many there are).
 */
static int prepare_points(aenl_classifier_t *c, const aenl_moments_t *m, cls_frame_t *fr,
                          aenl_classifier_result_t *r)
{
    aenl_real_t x_lo = AENL_R(0.0), x_hi = AENL_R(0.0);
    const uint32_t n_in = mark_interior(c, m, &x_lo, &x_hi);
    /* independent share of the nodes: kernels one bandwidth apart barely overlap */
    fr->frac = (m->dx < m->cfg.bandwidth) ? m->dx / m->cfg.bandwidth : AENL_R(1.0);
    fr->n = 0u;
    fr->centre = AENL_R(0.0);
    fr->half = AENL_R(1.0);
    if (n_in >= c->cfg.min_nodes && x_hi > x_lo)
    {
        fr->centre = AENL_R(0.5) * (x_lo + x_hi);
        fr->half = AENL_R(0.5) * (x_hi - x_lo);
        fr->n = gather(c, m, AENL_DIR_ALL, fr, AENL_R(1.0), c->pt[0]);
    }
    fr->n_ind = (aenl_real_t)fr->n * fr->frac;
    fr->ascale = (fr->n > 0u) ? accel_rms(c->pt[0], fr->n) : AENL_R(0.0);
    r->n_nodes = (uint16_t)fr->n;
    if (fr->n < c->cfg.min_nodes || fr->n_ind < AENL_R(8.0) || !(fr->ascale > AENL_R(0.0)))
    {
        return 0;
    }
    rescale(c->pt[0], fr->n, AENL_R(1.0) / fr->ascale);
    sort_points(c->pt[0], fr->n);
    fr->wmax = normalise_weights(c->pt[0], fr->n);
    return 1;
}

/**
 * Criteria of the first n_laws laws (lin, poly, one, two, hy) on n_sets sets; AENL_REAL_MAX for
 * a law whose fit failed or whose kink search found nothing (ok[i] zero). Parameters: the law's
 * coefficients (the kinks at KINK_DF each), plus the rising offset of a direction split.
 */
static void score_laws(aenl_classifier_t *c, const cls_data_t *dt, const cls_laws_t *l,
                       const int *ok, uint32_t n_laws, aenl_real_t sigma, aenl_real_t frac,
                       aenl_real_t n_ind, aenl_real_t *b)
{
    static const uint8_t k_params[5] = {2u, 4u, 3u + KINK_DF, 4u + 2u * KINK_DF, 5u + 3u * KINK_DF};
    const cls_spec_t *const sp[5] = {&l->lin, &l->poly, &l->one, &l->two, &l->hy};
    for (uint32_t i = 0; i < n_laws; ++i)
    {
        b[i] = ok[i] ? criterion(dt, sp[i], sigma, frac, n_ind,
                                 (uint32_t)(k_params[i] + dt->n_sets - 1u), c->resid)
                     : AENL_REAL_MAX;
    }
}

/** Criteria and posterior weights of the all-pairs laws (rss_poly < 0: the polynomial failed). */
static void all_pairs_scores(aenl_classifier_t *c, const cls_data_t *dt, const cls_laws_t *l,
                             const cls_frame_t *fr, aenl_real_t sigma, aenl_real_t rss_poly,
                             cls_all_t *ap, aenl_classifier_result_t *r)
{
    aenl_real_t *b = ap->b;
    const int ok[AENL_CLS_N_MODELS] = {1, rss_poly >= AENL_R(0.0), ap->k1.ok, ap->k2.ok};
    score_laws(c, dt, l, ok, AENL_CLS_N_MODELS, sigma, fr->frac, fr->n_ind, b);
    posterior(b, AENL_CLS_N_MODELS, ap->pm);
    for (unsigned i = 0; i < (unsigned)AENL_CLS_N_MODELS; ++i)
    {
        r->bic[i] = (b[i] < AENL_REAL_MAX) ? b[i] - b[AENL_CLS_MODEL_LINEAR] : AENL_REAL_MAX;
    }
}

/**
 * All pairs: the restoring-force curve a(p). The laws fitted to the points of c->pt[0], their
 * criteria, the hardening, the slopes of the two-kink law and the kinks' standard errors. Zero
 * when the points are degenerate.
 */
static int all_pairs(aenl_classifier_t *c, cls_frame_t *fr, cls_all_t *ap,
                     aenl_classifier_result_t *r)
{
    const uint32_t n = fr->n;
    const cls_set_t all = {c->pt[0], n};
    build_table(&all, &c->tab[0]);
    fr->nc = candidates(c->pt[0], n, c->cand);
    cls_laws_t l;
    laws_init(&l, 0u);
    const cls_data_t dt = {&all, c->tab, 1u, c->cand, fr->nc};
    search(&dt, &l.one, 0u, &ap->k1);
    search(&dt, &l.two, 0u, &ap->k2);
    l.one.b[0] = ap->k1.b[0];
    l.two.b[0] = ap->k2.b[0];
    l.two.b[1] = ap->k2.b[1];
    aenl_real_t coef[NB_MAX] = {AENL_R(0.0)};
    const aenl_real_t rss_lin = fit(&dt, &l.lin, NULL, NULL);
    const aenl_real_t rss_poly = fit(&dt, &l.poly, coef, NULL);
    const aenl_real_t c3 = coef[3];
    if (rss_lin < AENL_R(0.0))
    {
        return 0;
    }
    /* noise scale from the best-fitting law */
    const cls_spec_t *const ksp[2] = {&l.one, &l.two};
    const cls_kinks_t *const kk[2] = {&ap->k1, &ap->k2};
    const cls_spec_t *ref = noise_reference(&l, rss_poly, ksp, kk, 2u);
    (void)fit(&dt, ref, NULL, c->resid);
    const aenl_real_t sigma = noise_scale(c->resid, n, fr->wmax);
    all_pairs_scores(c, &dt, &l, fr, sigma, rss_poly, ap, r);
    r->hardening = (int8_t)((c3 < AENL_R(0.0)) ? 1 : -1);
    if (ap->k2.ok && fit(&dt, &l.two, coef, NULL) >= AENL_R(0.0))
    {
        const aenl_real_t to_phys = fr->ascale / fr->half;
        r->slope[0] = -coef[1] * to_phys;
        r->slope[1] = -(coef[1] + coef[2]) * to_phys;
        r->slope[2] = -(coef[1] + coef[2] + coef[3]) * to_phys;
    }
    const aenl_real_t fallback = AENL_R(2.0) / (aenl_real_t)n;
    ap->se_k1 = kink_se(ap->k1.curv[0], sigma, fr->frac, fallback);
    ap->se_k2[0] = kink_se(ap->k2.curv[0], sigma, fr->frac, fallback);
    ap->se_k2[1] = kink_se(ap->k2.curv[1], sigma, fr->frac, fallback);
    return 1;
}

/**
 * The rising and falling points in c->pt[1] and c->pt[2], in the all-pairs frame, sorted and
 * weighted with one divisor (*wmax). Zero when either direction has too few.
 */
static int gather_directions(aenl_classifier_t *c, const aenl_moments_t *m, const cls_frame_t *fr,
                             uint32_t *nd, aenl_real_t *wmax, cls_dir_t *dir)
{
    for (uint32_t d = 0; d < 2u; ++d)
    {
        nd[d] = gather(c, m, d ? AENL_DIR_FALLING : AENL_DIR_RISING, fr, AENL_R(1.0) / fr->ascale,
                       c->pt[1 + d]);
    }
    dir->nd_ind = (aenl_real_t)(nd[0] + nd[1]) * fr->frac;
    if (nd[0] < c->cfg.min_nodes || nd[1] < c->cfg.min_nodes || !(dir->nd_ind > AENL_R(16.0)))
    {
        return 0;
    }
    sort_points(c->pt[1], nd[0]);
    sort_points(c->pt[2], nd[1]);
    *wmax = max_weight(c->pt[2], nd[1], max_weight(c->pt[1], nd[0], AENL_R(0.0)));
    divide_weights(c->pt[1], nd[0], *wmax);
    divide_weights(c->pt[2], nd[1], *wmax);
    return 1;
}

/**
 * Criteria of the direction-split laws at noise scale sig_d, the hardening of the shared
 * polynomial and the kinks' standard errors.
 */
static void direction_scores(aenl_classifier_t *c, const cls_data_t *dt, const cls_laws_t *l,
                             const cls_frame_t *fr, aenl_real_t sig_d, cls_dir_t *dir,
                             aenl_classifier_result_t *r)
{
    const aenl_real_t frac_d = fr->frac;
    const int ok[D_N] = {1, 1, dir->t1.ok, dir->t2.ok, dir->hy.ok};
    score_laws(c, dt, l, ok, D_N, sig_d, frac_d, dir->nd_ind, dir->bd);
    aenl_real_t cp[NB_MAX];
    if (fit(dt, &l->poly, cp, NULL) >= AENL_R(0.0))
    {
        r->hardening = (int8_t)((cp[3] < AENL_R(0.0)) ? 1 : -1);
    }
    const aenl_real_t fb = AENL_R(2.0) / (aenl_real_t)fr->nc;
    dir->se_t1 = kink_se(dir->t1.curv[0], sig_d, frac_d, fb);
    for (uint32_t j = 0; j < 2u; ++j)
    {
        dir->se_t2[j] = kink_se(dir->t2.curv[j], sig_d, frac_d, fb);
        dir->se_hy[j] = kink_se(dir->hy.curv[j], sig_d, frac_d, fb);
    }
}

/**
 * Direction split: the same laws with shared coefficients, and hysteresis. dir->ok when both
 * directions have enough points and a law fits them.
 */
static void direction_split(aenl_classifier_t *c, const aenl_moments_t *m, const cls_frame_t *fr,
                            cls_dir_t *dir, aenl_classifier_result_t *r)
{
    uint32_t nd[2];
    aenl_real_t wmax;
    if (!gather_directions(c, m, fr, nd, &wmax, dir))
    {
        return;
    }
    const cls_set_t sets[2] = {{c->pt[1], nd[0]}, {c->pt[2], nd[1]}};
    build_table(&sets[0], &c->tab[0]);
    build_table(&sets[1], &c->tab[1]);
    cls_laws_t l;
    laws_init(&l, 1u);
    const cls_data_t dt = {sets, c->tab, 2u, c->cand, fr->nc};
    search(&dt, &l.one, 0u, &dir->t1);
    search(&dt, &l.two, 0u, &dir->t2);
    search(&dt, &l.hy, fr->nc / 3u, &dir->hy);
    l.one.b[0] = dir->t1.b[0];
    l.two.b[0] = dir->t2.b[0];
    l.two.b[1] = dir->t2.b[1];
    l.hy.b[0] = dir->hy.b[0];
    l.hy.b[1] = dir->hy.b[1];
    l.hy.shift = dir->hy.shift;
    const cls_spec_t *const ksp[3] = {&l.one, &l.two, &l.hy};
    const cls_kinks_t *const kk[3] = {&dir->t1, &dir->t2, &dir->hy};
    const aenl_real_t rss_poly = fit(&dt, &l.poly, NULL, NULL);
    const cls_spec_t *ref = noise_reference(&l, rss_poly, ksp, kk, 3u);
    if (fit(&dt, ref, NULL, c->resid) < AENL_R(0.0))
    {
        return;
    }
    dir->ok = 1;
    const aenl_real_t sig_d = noise_scale(c->resid, (uint32_t)(nd[0] + nd[1]), wmax);
    direction_scores(c, &dt, &l, fr, sig_d, dir, r);
}

/**
 * The class probabilities, evidence and class, from the direction split when it holds, else from
 * all pairs. Returns 1 when the two-kink freeplay law outweighs the one-kink law.
 */
static int decide(const cls_frame_t *fr, const cls_all_t *ap, const cls_dir_t *dir,
                  aenl_classifier_result_t *r)
{
    /* The laws in the same order either way (lin, poly, one kink, two kinks[, hysteresis]). */
    aenl_real_t pd[D_N];
    const aenl_real_t *b = dir->ok ? dir->bd : ap->b;
    const aenl_real_t *p = dir->ok ? pd : ap->pm;
    const unsigned n_laws = dir->ok ? (unsigned)D_N : (unsigned)AENL_CLS_N_MODELS;
    if (dir->ok)
    {
        posterior(dir->bd, D_N, pd);
        r->prob[AENL_CLASS_HYSTERESIS] = pd[D_HYST];
        r->bic_hysteresis = (dir->bd[D_HYST] < AENL_REAL_MAX && dir->bd[D_FP2] < AENL_REAL_MAX)
                                ? dir->bd[D_HYST] - dir->bd[D_FP2]
                                : AENL_R(0.0);
    }
    r->prob[AENL_CLASS_LINEAR] = p[D_LIN];
    r->prob[AENL_CLASS_POLYNOMIAL] = p[D_POLY];
    r->prob[AENL_CLASS_FREEPLAY] = p[D_FP1] + p[D_FP2];
    aenl_real_t best_nl = AENL_REAL_MAX;
    for (unsigned i = D_POLY; i < n_laws; ++i)
    {
        best_nl = (b[i] < best_nl) ? b[i] : best_nl;
    }
    r->evidence = (b[D_LIN] - best_nl) / (dir->ok ? dir->nd_ind : fr->n_ind);
    const int use_two = p[D_FP2] >= p[D_FP1];
    r->cls = AENL_CLASS_LINEAR;
    for (uint32_t i = AENL_CLASS_POLYNOMIAL; i < AENL_CLASS_COUNT; ++i)
    {
        if (r->prob[i] > r->prob[r->cls])
        {
            r->cls = (aenl_class_t)i;
        }
    }
    r->confidence = r->prob[r->cls];
    return use_two;
}

/** The switching points of the class and their standard errors, in input units. */
static void switching_points(const cls_frame_t *fr, const cls_all_t *ap, const cls_dir_t *dir,
                             int use_two, aenl_classifier_result_t *r)
{
    const aenl_real_t centre = fr->centre, half = fr->half;
    if (r->cls == AENL_CLASS_FREEPLAY)
    {
        const aenl_real_t *kb =
            dir->ok ? (use_two ? dir->t2.b : dir->t1.b) : (use_two ? ap->k2.b : ap->k1.b);
        const aenl_real_t se1[2] = {dir->ok ? dir->se_t1 : ap->se_k1, AENL_R(0.0)};
        const aenl_real_t *ks = use_two ? (dir->ok ? dir->se_t2 : ap->se_k2) : se1;
        r->n_switch = use_two ? 2u : 1u;
        for (uint32_t j = 0; j < r->n_switch; ++j)
        {
            r->switch_points[j] = centre + kb[j] * half;
            r->switch_std[j] = ks[j] * half;
        }
    }
    else if (r->cls == AENL_CLASS_HYSTERESIS)
    {
        aenl_cls_point_t q[4]; /* switching point in p, its se in w */
        memset(q, 0, sizeof(q));
        for (uint32_t j = 0; j < 2u; ++j)
        {
            q[j].p = centre + (dir->hy.b[j] + AENL_R(0.5) * dir->hy.shift) * half;
            q[2u + j].p = centre + (dir->hy.b[j] - AENL_R(0.5) * dir->hy.shift) * half;
            q[j].w = dir->se_hy[j] * half;
            q[2u + j].w = dir->se_hy[j] * half;
        }
        r->n_switch = merge_points(q, 4u, r->switch_points, r->switch_std);
    }
}

/** The class decision from posterior weights over the laws, the switching points and their se. */
aenl_status_t aenl_classifier_update(aenl_classifier_t *c, const aenl_moments_t *m)
{
    if (c == NULL || m == NULL ||
        c->cfg.taylor_order + 1u + c->cfg.use_noise_acf > aenl_moments_n_series(m))
    {
        return AENL_E_ARG;
    }
    if (m->cfg.n_grid > AENL_CLASSIFIER_MAX_NODES)
    {
        return AENL_E_DIM;
    }
    aenl_classifier_result_t r;
    memset(&r, 0, sizeof(r));
    r.cls = AENL_CLASS_INSUFFICIENT;
    r.n_updates = (c->res.n_updates < UINT32_MAX) ? c->res.n_updates + 1u : UINT32_MAX;
    cls_frame_t fr;
    cls_all_t ap;
    /* too few points, or degenerate ones: insufficient */
    if (!prepare_points(c, m, &fr, &r) || !all_pairs(c, &fr, &ap, &r))
    {
        publish(c, &r);
        return AENL_OK;
    }
    cls_dir_t dir;
    memset(&dir, 0, sizeof(dir)); /* not ok until the split fits; the rest is read only then */
    if (m->cfg.direction_split)
    {
        direction_split(c, m, &fr, &dir, &r);
    }
    const int use_two = decide(&fr, &ap, &dir, &r);
    switching_points(&fr, &ap, &dir, use_two, &r);
    publish(c, &r);
    return AENL_OK;
}
