/* SPDX-License-Identifier: MIT */
/**
 * @file test_rfs.c
 * @brief The restoring-force regression (aenl_rfs.h): its cross-validated gain against a brute
 *        force refit of explicit design matrices, and its verdicts on two coupled oscillators
 *        (written here) that are linear, carry a freeplay gap, or a hardening cubic in one of them.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_tools/aenl_rfs.h"
#include "unity.h"

#include "aenl_test_rand.h"

void setUp(void)
{
}

void tearDown(void)
{
}

#define N_ROWS 60000u
#define DT     0.05

static uint64_t g_rng;

typedef enum
{
    LAW_LINEAR,
    LAW_GAP,      /* freeplay: no stiffness inside [-GAP, GAP] on oscillator 0 */
    LAW_CUBIC,    /* hardening cubic on oscillator 1 */
    LAW_SOFT,     /* softening with a quintic recovery on oscillator 0 (a polynomial law,
                     Σ p_k x^k): stiffness 1 at rest, 0.1 at |x| = 0.45, rising beyond */
    LAW_SATURATE, /* stiffness 1 inside [-GAP, GAP], 0.2 outside, on oscillator 0 */
    LAW_FRICTION, /* LAW_GAP plus dry friction FRICTION sign(v) on oscillator 0 */
    LAW_HYST,     /* the simulator's loop (alpha_f 0, delta 2 GAP, M0 HYST_M0) on oscillator 0:
                     no stiffness in [0, 2 GAP] rising, in [-2 GAP, 0] falling, offset +-M0 */
    LAW_ANTI,     /* LAW_GAP with its contacts reached early in the direction of motion (the
                     gap shifted by -ANTI rising, +ANTI falling), as a freeplay looks through
                     a position sensor that lags: a loop that anticipates the motion */
    LAW_BOTH      /* LAW_GAP on oscillator 0 and LAW_CUBIC on oscillator 1 */
} law_t;

#define GAP      0.4
#define FRICTION 0.15
#define HYST_M0  0.1
#define ANTI     0.1

static double clip(double x, double a, double b)
{
    return x < a ? a : (x > b ? b : x);
}

/* Two oscillators coupled by a spring, white-noise forcing on both, symplectic Euler. */
static double *simulate(law_t law, uint64_t seed)
{
    double *x = malloc((size_t)2 * N_ROWS * sizeof(double));
    TEST_ASSERT_NOT_NULL(x);
    g_rng = seed;
    double p0 = 0.0, p1 = 0.0, v0 = 0.0, v1 = 0.0;
    for (size_t n = 0; n < N_ROWS + 2000u; ++n)
    {
        double f0 = p0, f1 = 2.0 * p1;
        if (law == LAW_GAP || law == LAW_FRICTION || law == LAW_BOTH)
        {
            f0 = p0 - clip(p0, -GAP, GAP);
        }
        if (law == LAW_FRICTION)
        {
            f0 += v0 > 0.0 ? FRICTION : -FRICTION;
        }
        if (law == LAW_HYST)
        {
            f0 = v0 > 0.0 ? p0 - clip(p0, 0.0, 2.0 * GAP) + HYST_M0
                          : p0 - clip(p0, -2.0 * GAP, 0.0) - HYST_M0;
        }
        if (law == LAW_ANTI)
        {
            f0 = v0 > 0.0 ? p0 - clip(p0, -GAP - ANTI, GAP - ANTI)
                          : p0 - clip(p0, -GAP + ANTI, GAP + ANTI);
        }
        if (law == LAW_CUBIC || law == LAW_BOTH)
        {
            f1 += 3.0 * p1 * p1 * p1;
        }
        if (law == LAW_SATURATE)
        {
            f0 = 0.2 * p0 + 0.8 * clip(p0, -GAP, GAP);
        }
        if (law == LAW_SOFT)
        {
            const double q = p0 * p0;
            f0 = p0 * (1.0 - 3.0 * q + 4.5 * q * q);
        }
        const double a0 = -f0 - 0.3 * (p0 - p1) - 0.06 * v0 + 0.25 * test_gauss(&g_rng) / sqrt(DT);
        const double a1 = -f1 - 0.3 * (p1 - p0) - 0.08 * v1 + 0.25 * test_gauss(&g_rng) / sqrt(DT);
        v0 += DT * a0;
        v1 += DT * a1;
        p0 += DT * v0;
        p1 += DT * v1;
        if (n >= 2000u) /* past the start-up */
        {
            x[n - 2000u] = p0;
            x[N_ROWS + n - 2000u] = p1;
        }
    }
    return x;
}

static void config(const double *x, aenl_rfs_cfg_t *c, uint16_t nodes)
{
    memset(c, 0, sizeof(*c));
    c->n_ch = 2;
    c->n_nodes = nodes;
    c->n_total = N_ROWS;
    c->n_lags = 2;
    c->lags[0] = 2;
    c->lags[1] = 3;
    for (size_t j = 0; j < 2; ++j)
    {
        double m = 0.0, m2 = 0.0, lo = HUGE_VAL, hi = -HUGE_VAL;
        for (size_t n = 0; n < N_ROWS; ++n)
        {
            const double v = x[j * N_ROWS + n];
            m += v;
            m2 += v * v;
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
        m /= N_ROWS;
        c->center[j] = m;
        c->scale[j] = sqrt(m2 / N_ROWS - m * m);
        c->lo[j] = lo;
        c->hi[j] = hi;
    }
}

static void run(const double *x, const aenl_rfs_cfg_t *c, aenl_rfs_fit_t fit[2])
{
    aenl_rfs_t *r = NULL;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_rfs_create(&r, c, &err), err.msg);
    for (size_t n = 0; n < N_ROWS; ++n)
    {
        const double row[2] = {x[n], x[N_ROWS + n]};
        aenl_rfs_push(r, row);
    }
    for (size_t ch = 0; ch < 2; ++ch)
    {
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_rfs_analyse(r, ch, &fit[ch], &err), err.msg);
    }
    aenl_rfs_free(r);
}

/* Simulate `law`, configure (`nodes` tents) and analyse both channels; returns the record. */
static double *fit_record(law_t law, uint64_t seed, uint16_t nodes, aenl_rfs_cfg_t *c,
                          aenl_rfs_fit_t fit[2])
{
    double *x = simulate(law, seed);
    config(x, c, nodes);
    run(x, c, fit);
    return x;
}

/* ---- brute force: explicit design matrices, blocked refits -------------------------------- */

#define MAX_COLS 24

/* Solve the normal equations (Gauss-Jordan with partial pivoting) of X'X b = X'y. */
static void normal_solve(double (*xtx)[MAX_COLS], const double *xty, size_t m, double *b)
{
    double a[MAX_COLS][MAX_COLS + 1];
    for (size_t i = 0; i < m; ++i)
    {
        memcpy(a[i], xtx[i], m * sizeof(double));
        a[i][m] = xty[i];
    }
    for (size_t c = 0; c < m; ++c)
    {
        size_t piv = c;
        for (size_t i = c + 1u; i < m; ++i)
        {
            piv = fabs(a[i][c]) > fabs(a[piv][c]) ? i : piv;
        }
        for (size_t k = 0; k <= m; ++k)
        {
            const double t = a[c][k];
            a[c][k] = a[piv][k];
            a[piv][k] = t;
        }
        for (size_t i = 0; i < m; ++i)
        {
            if (i != c)
            {
                const double f = a[i][c] / a[c][c];
                for (size_t k = c; k <= m; ++k)
                {
                    a[i][k] -= f * a[c][k];
                }
            }
        }
    }
    for (size_t i = 0; i < m; ++i)
    {
        b[i] = a[i][m] / a[i][i];
    }
}

/* Another channel's law among the regressors: its values tau at that channel's tent nodes
 * (rising motion first), NULL for none. */
typedef struct
{
    size_t ch;
    const double *tau;
} given_t;

/* Cell k (clamped to the grid, the law extrapolated linearly beyond it) and the weight w1 of
 * node k + 1 of channel ch's standardised position u. */
static size_t grid_cell(const aenl_rfs_cfg_t *c, size_t ch, double u, double *w1)
{
    const double lo = (c->lo[ch] - c->center[ch]) / c->scale[ch];
    const double hi = (c->hi[ch] - c->center[ch]) / c->scale[ch];
    const double cell = (hi - lo) / (double)(c->n_nodes - 1u);
    double k = floor((u - lo) / cell);
    k = k < 0.0 ? 0.0 : (k > (double)(c->n_nodes - 2u) ? (double)(c->n_nodes - 2u) : k);
    *w1 = (u - lo) / cell - k;
    return (size_t)k;
}

/* One regression row of channel ch at centre n: the linear regressors, the given law's column
 * (when gv->tau), the law's column(s) for a two-kink gap [ga, gb] (standardised) through the
 * tents, and y. Returns the column count. */
static size_t design_row(const double *x, const aenl_rfs_cfg_t *c, size_t ch, size_t n,
                         const given_t *gv, int with_law, double ga, double gb, double *row,
                         double *y)
{
    size_t m = 0;
    row[m++] = 1.0;
    for (size_t j = 0; j < 2; ++j)
    {
        const double *s = &x[j * N_ROWS];
        const double z0 = (s[n] - c->center[j]) / c->scale[j];
        const double zp = (s[n + 1u] - c->center[j]) / c->scale[j];
        const double zm = (s[n - 1u] - c->center[j]) / c->scale[j];
        row[m++] = z0;
        row[m++] = 0.5 * (zp - zm);
        if (j == ch)
        {
            *y = zp - 2.0 * z0 + zm;
        }
        else
        {
            row[m++] = zp - 2.0 * z0 + zm;
        }
        for (size_t l = 0; l < c->n_lags; ++l)
        {
            row[m++] = (s[n - c->lags[l]] - c->center[j]) / c->scale[j];
        }
    }
    if (gv->tau != NULL)
    {
        /* the other channel's law at its position, on the tents of its direction of motion */
        const double *s = &x[gv->ch * N_ROWS];
        double w1;
        const size_t k = grid_cell(c, gv->ch, (s[n] - c->center[gv->ch]) / c->scale[gv->ch], &w1);
        const size_t off = s[n + 1u] - s[n - 1u] > 0.0 ? 0u : c->n_nodes;
        row[m++] = (1.0 - w1) * gv->tau[off + k] + w1 * gv->tau[off + k + 1u];
    }
    if (with_law)
    {
        /* the gap law's node values, interpolated by the tents (linear within a cell) */
        const double u = (x[ch * N_ROWS + n] - c->center[ch]) / c->scale[ch];
        const double lo = (c->lo[ch] - c->center[ch]) / c->scale[ch];
        const double hi = (c->hi[ch] - c->center[ch]) / c->scale[ch];
        const double cell = (hi - lo) / (double)(c->n_nodes - 1u);
        double w1;
        const double k = (double)grid_cell(c, ch, u, &w1);
        const double x0 = lo + k * cell, x1 = x0 + cell;
        const double c0 = x0 < ga ? ga : (x0 > gb ? gb : x0);
        const double c1 = x1 < ga ? ga : (x1 > gb ? gb : x1);
        row[m++] = (1.0 - w1) * c0 + w1 * c1;
    }
    return m;
}

/* Cross-validated gain of the gap law over the linear one (both with the given law's column,
 * if any), by explicit refits. */
static double brute_cv_gain(const double *x, const aenl_rfs_cfg_t *c, size_t ch, const given_t *gv,
                            double ga, double gb)
{
    static double xtx[2][AENL_RFS_BLOCKS][MAX_COLS][MAX_COLS];
    static double xty[2][AENL_RFS_BLOCKS][MAX_COLS];
    static double yy[AENL_RFS_BLOCKS];
    memset(xtx, 0, sizeof(xtx));
    memset(xty, 0, sizeof(xty));
    memset(yy, 0, sizeof(yy));
    size_t m[2] = {0, 0};
    const size_t first = c->lags[c->n_lags - 1u]; /* the first row aenl_rfs forms */
    for (size_t n = first; n + 1u < N_ROWS; ++n)
    {
        const size_t b = (size_t)(((double)n * AENL_RFS_BLOCKS) / (double)N_ROWS);
        double row[MAX_COLS], y = 0.0;
        for (int w = 0; w < 2; ++w)
        {
            m[w] = design_row(x, c, ch, n, gv, w, ga, gb, row, &y);
            for (size_t i = 0; i < m[w]; ++i)
            {
                for (size_t k = 0; k < m[w]; ++k)
                {
                    xtx[w][b][i][k] += row[i] * row[k];
                }
                xty[w][b][i] += row[i] * y;
            }
        }
        yy[b] += y * y;
    }
    double gain = 0.0, base = 0.0;
    for (size_t f = 0; f < AENL_RFS_BLOCKS; ++f)
    {
        double rss[2];
        for (int w = 0; w < 2; ++w)
        {
            double a[MAX_COLS][MAX_COLS], v[MAX_COLS], beta[MAX_COLS];
            for (size_t i = 0; i < m[w]; ++i)
            {
                v[i] = 0.0;
                for (size_t k = 0; k < m[w]; ++k)
                {
                    a[i][k] = 0.0;
                }
            }
            for (size_t b = 0; b < AENL_RFS_BLOCKS; ++b)
            {
                for (size_t i = 0; b != f && i < m[w]; ++i)
                {
                    for (size_t k = 0; k < m[w]; ++k)
                    {
                        a[i][k] += xtx[w][b][i][k];
                    }
                    v[i] += xty[w][b][i];
                }
            }
            normal_solve(a, v, m[w], beta);
            double r = yy[f];
            for (size_t i = 0; i < m[w]; ++i)
            {
                double s = 0.0;
                for (size_t k = 0; k < m[w]; ++k)
                {
                    s += xtx[w][f][i][k] * beta[k];
                }
                r += beta[i] * (s - 2.0 * xty[w][f][i]);
            }
            rss[w] = r;
        }
        base += rss[0];
        gain += rss[0] - rss[1];
    }
    return gain / base;
}

/* ---- tests ----------------------------------------------------------------------------------- */

/* Row n of channel ch for the free law: the linear regressors but the constant and the
 * channel's own position (the tents span both), then every tent, rising motion first. */
static size_t free_row(const double *x, const aenl_rfs_cfg_t *c, size_t ch, size_t n, double *row,
                       double *y)
{
    double lin[MAX_COLS];
    const given_t none = {0, NULL};
    const size_t m = design_row(x, c, ch, n, &none, 0, 0.0, 0.0, lin, y);
    const size_t own = ch == 0 ? 1u : 1u + 3u + c->n_lags; /* channel 0 has its d2 column */
    size_t q = 0;
    for (size_t i = 1; i < m; ++i)
    {
        if (i != own)
        {
            row[q++] = lin[i];
        }
    }
    const size_t K = c->n_nodes;
    const double *s = &x[ch * N_ROWS];
    const double u = (s[n] - c->center[ch]) / c->scale[ch];
    const double lo = (c->lo[ch] - c->center[ch]) / c->scale[ch];
    const double hi = (c->hi[ch] - c->center[ch]) / c->scale[ch];
    const double cell = (hi - lo) / (double)(K - 1u);
    double k = floor((u - lo) / cell);
    k = k < 0.0 ? 0.0 : (k > (double)(K - 2u) ? (double)(K - 2u) : k);
    const double w1 = (u - lo) / cell - k;
    const size_t col = q + (s[n + 1u] > s[n - 1u] ? 0u : K) + (size_t)k;
    memset(&row[q], 0, 2u * K * sizeof(double));
    row[col] = 1.0 - w1;
    row[col + 1u] = w1;
    return q + 2u * K;
}

/* The free-law model's residuals (aenl_rfs_model, aenl_rfs_residual) against an explicit
 * least-squares fit of the same columns, row by row. */
static void test_rfs_free_law_residuals_match_brute_force(void)
{
    aenl_rfs_cfg_t c;
    double *x = simulate(LAW_GAP, 17);
    config(x, &c, 8);
    const size_t ch = 0, first = c.lags[c.n_lags - 1u];
    static double xtx[MAX_COLS][MAX_COLS];
    double xty[MAX_COLS] = {0.0}, beta[MAX_COLS], row[MAX_COLS], y = 0.0;
    memset(xtx, 0, sizeof(xtx));
    size_t m = 0;
    for (size_t n = first; n + 1u < N_ROWS; ++n)
    {
        m = free_row(x, &c, ch, n, row, &y);
        for (size_t i = 0; i < m; ++i)
        {
            for (size_t k = 0; k < m; ++k)
            {
                xtx[i][k] += row[i] * row[k];
            }
            xty[i] += row[i] * y;
        }
    }
    TEST_ASSERT_LESS_OR_EQUAL_UINT(MAX_COLS, m);
    normal_solve(xtx, xty, m, beta);
    aenl_rfs_t *r = NULL;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_rfs_create(&r, &c, &err));
    for (size_t n = 0; n < N_ROWS; ++n)
    {
        const double in[2] = {x[n], x[N_ROWS + n]};
        aenl_rfs_push(r, in);
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_rfs_model(r, &err), err.msg);
    double worst = 0.0, ss = 0.0;
    size_t formed = 0;
    for (size_t n = 0; n < N_ROWS; ++n)
    {
        const double in[2] = {x[n], x[N_ROWS + n]};
        double e[2];
        aenl_rfs_residual(r, in, e);
        if (!isfinite(e[ch]))
        {
            TEST_ASSERT_TRUE(n < first + 2u); /* only while the window fills */
            continue;
        }
        (void)free_row(x, &c, ch, n - 1u, row, &y);
        double ref = y;
        for (size_t i = 0; i < m; ++i)
        {
            ref -= beta[i] * row[i];
        }
        worst = fmax(worst, fabs(e[ch] - ref));
        ss += ref * ref;
        formed++;
    }
    TEST_ASSERT_EQUAL_UINT(N_ROWS - first - 1u, formed); /* centres first .. N - 2 */
    /* to 1e-5 of the residual: the model's ridge (1e-9 of the tent mass) on a near-collinear
     * design */
    TEST_ASSERT_LESS_THAN_DOUBLE(1e-5 * sqrt(ss / (double)formed), worst);
    aenl_rfs_free(r);
    free(x);
}

static void test_rfs_cv_gain_matches_brute_force(void)
{
    aenl_rfs_cfg_t c;
    aenl_rfs_fit_t fit[2];
    double *x = fit_record(LAW_GAP, 11u, 12, &c, fit);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_FREEPLAY, fit[0].cls);
    TEST_ASSERT_EQUAL_INT(AENL_RFS_GAP, fit[0].law);
    TEST_ASSERT_EQUAL_size_t(2, fit[0].n_points);
    const double ga = (fit[0].points[0] - c.center[0]) / c.scale[0];
    const double gb = (fit[0].points[1] - c.center[0]) / c.scale[0];
    const given_t none = {0, NULL};
    const double ref = brute_cv_gain(x, &c, 0, &none, ga, gb);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6 * fabs(ref) + 1e-12, ref, fit[0].gain[AENL_RFS_GAP]);
    free(x);
}

/* A gap in oscillator 0 and a cubic in oscillator 1: channel 0's analysis with channel 1's law
 * among its regressors. Its gap law's cross-validated gain, refitted by brute force with that
 * law's column in the design (the cubic's values at channel 1's tents, interpolated at channel
 * 1's position on the tents of its direction), and the same in the other direction; the gap
 * stays, as it is no function of the other oscillator. */
static void test_rfs_law_given_another_matches_brute_force(void)
{
    aenl_rfs_cfg_t c;
    aenl_rfs_fit_t fit[2];
    double *x = simulate(LAW_BOTH, 29u);
    config(x, &c, 12);
    aenl_rfs_t *r = NULL;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_rfs_create(&r, &c, &err), err.msg);
    for (size_t n = 0; n < N_ROWS; ++n)
    {
        const double row[2] = {x[n], x[N_ROWS + n]};
        aenl_rfs_push(r, row);
    }
    for (size_t ch = 0; ch < 2; ++ch)
    {
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_rfs_analyse(r, ch, &fit[ch], &err), err.msg);
    }
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_FREEPLAY, fit[0].cls);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, fit[1].cls);
    aenl_rfs_fit_t g0, g1;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_rfs_analyse_given(r, 0, 1, &fit[1], &g0, &err));
    TEST_ASSERT_EQUAL_INT(AENL_RFS_GAP, g0.law);
    TEST_ASSERT_EQUAL_size_t(2, g0.n_points);
    const given_t gv = {1, fit[1].tents};
    const double ga = (g0.points[0] - c.center[0]) / c.scale[0];
    const double gb = (g0.points[1] - c.center[0]) / c.scale[0];
    const double ref = brute_cv_gain(x, &c, 0, &gv, ga, gb);
    TEST_ASSERT_DOUBLE_WITHIN(1e-6 * fabs(ref) + 1e-12, ref, g0.gain[AENL_RFS_GAP]);
    /* without the column the reference differs: the check can fail */
    const given_t none = {0, NULL};
    TEST_ASSERT_TRUE(fabs(brute_cv_gain(x, &c, 0, &none, ga, gb) - ref) > 1e-4 * fabs(ref));
    /* the other way round (the pair's cross-products read transposed) */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_rfs_analyse_given(r, 1, 0, &fit[0], &g1, &err));
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, g1.cls);
    /* a linear law adds nothing; bad channels are refused */
    aenl_rfs_fit_t lin = fit[0], again;
    lin.law = AENL_RFS_LINEAR;
    lin.cls = AENL_CLASS_LINEAR;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_rfs_analyse_given(r, 1, 0, &lin, &again, &err));
    TEST_ASSERT_EQUAL_DOUBLE(fit[1].evidence, again.evidence);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_rfs_analyse_given(r, 1, 1, &fit[0], &again, &err));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_rfs_analyse_given(r, 2, 0, &fit[0], &again, &err));
    aenl_rfs_free(r);
    free(x);
}

static void test_rfs_linear_oscillators_are_linear(void)
{
    for (uint64_t seed = 1; seed <= 3; ++seed)
    {
        aenl_rfs_cfg_t c;
        aenl_rfs_fit_t fit[2];
        double *x = fit_record(LAW_LINEAR, seed, 24, &c, fit);
        for (size_t ch = 0; ch < 2; ++ch)
        {
            TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, fit[ch].cls);
            TEST_ASSERT_TRUE(fit[ch].evidence < AENL_RFS_T_CRIT);
            TEST_ASSERT_EQUAL_size_t(0, fit[ch].n_points);
        }
        free(x);
    }
}

static void test_rfs_names_the_freeplay_channel_and_its_gap(void)
{
    aenl_rfs_cfg_t c;
    aenl_rfs_fit_t fit[2];
    double *x = fit_record(LAW_GAP, 5u, 24, &c, fit);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_FREEPLAY, fit[0].cls);
    TEST_ASSERT_TRUE(fit[0].evidence >= AENL_RFS_T_CRIT);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, fit[1].cls); /* coupled, driven, but linear */
    TEST_ASSERT_EQUAL_size_t(2, fit[0].n_points);
    TEST_ASSERT_DOUBLE_WITHIN(0.2 * GAP, -GAP, fit[0].points[0]);
    TEST_ASSERT_DOUBLE_WITHIN(0.2 * GAP, GAP, fit[0].points[1]);
    TEST_ASSERT_TRUE(fit[0].point_std[0] > 0.0 && fit[0].point_std[0] < 0.2 * GAP);
    free(x);
}

static void test_rfs_names_the_cubic_channel_hardening(void)
{
    aenl_rfs_cfg_t c;
    aenl_rfs_fit_t fit[2];
    double *x = fit_record(LAW_CUBIC, 7u, 24, &c, fit);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, fit[1].cls);
    TEST_ASSERT_EQUAL_INT(1, fit[1].hardening);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, fit[0].cls);
    free(x);
}

/* A spring that softens and then recovers, and one that saturates, are polynomial (softening)
 * whichever law fits them best: a two-stiffness band that is stiffer inside is not a freeplay
 * gap. */
static void test_rfs_softening_spring_is_not_freeplay(void)
{
    aenl_rfs_cfg_t c;
    aenl_rfs_fit_t fit[2];
    double *x = fit_record(LAW_SOFT, 11u, 24, &c, fit);
    TEST_ASSERT_TRUE(fit[0].evidence >= AENL_RFS_T_CRIT);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, fit[0].cls);
    TEST_ASSERT_EQUAL_INT(-1, fit[0].hardening);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, fit[1].cls);
    free(x);
    x = fit_record(LAW_SATURATE, 13u, 24, &c, fit);
    TEST_ASSERT_TRUE(fit[0].evidence >= AENL_RFS_T_CRIT);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, fit[0].cls);
    TEST_ASSERT_EQUAL_INT(-1, fit[0].hardening);
    TEST_ASSERT_EQUAL_size_t(0, fit[0].n_points);
    free(x);
}

/* Hysteresis is switching points that move with the direction of motion, lagging it. A freeplay
 * gap with dry friction also has a force that follows the motion, but its gap stays put: not
 * hysteresis (this record does not tell the gap from a polynomial, either is a fair answer). */
static void test_rfs_hysteresis_is_a_lagging_moving_gap(void)
{
    aenl_rfs_cfg_t c;
    aenl_rfs_fit_t fit[2];
    double *x = fit_record(LAW_HYST, 17u, 24, &c, fit);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_HYSTERESIS, fit[0].cls);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, fit[1].cls);
    /* the outer switching points: -2 GAP falling, +2 GAP rising */
    TEST_ASSERT_EQUAL_size_t(4, fit[0].n_points);
    TEST_ASSERT_DOUBLE_WITHIN(0.25 * GAP, -2.0 * GAP, fit[0].points[0]);
    TEST_ASSERT_DOUBLE_WITHIN(0.25 * GAP, 2.0 * GAP, fit[0].points[3]);
    free(x);
    /* a loop that anticipates the motion is a lagging sensor's view of a freeplay, not
     * hysteresis: the shift must lag the motion */
    x = fit_record(LAW_ANTI, 17u, 24, &c, fit);
    TEST_ASSERT_TRUE(fit[0].evidence >= AENL_RFS_T_CRIT);
    TEST_ASSERT_TRUE(fit[0].cls == AENL_CLASS_FREEPLAY || fit[0].cls == AENL_CLASS_POLYNOMIAL);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, fit[1].cls);
    free(x);
    x = fit_record(LAW_FRICTION, 19u, 24, &c, fit);
    TEST_ASSERT_TRUE(fit[0].evidence >= AENL_RFS_T_CRIT);
    TEST_ASSERT_TRUE(fit[0].cls == AENL_CLASS_FREEPLAY || fit[0].cls == AENL_CLASS_POLYNOMIAL);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, fit[1].cls);
    free(x);
}

static void test_rfs_bad_configuration_and_short_records(void)
{
    double *x = simulate(LAW_LINEAR, 2u);
    aenl_rfs_cfg_t c;
    config(x, &c, 24);
    aenl_rfs_t *r = NULL;
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_rfs_cfg_t bad = c;
    bad.n_nodes = 4;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_rfs_create(&r, &bad, &err));
    bad = c;
    bad.scale[1] = 0.0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_rfs_create(&r, &bad, &err));
    bad = c;
    bad.lags[0] = 1;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_rfs_create(&r, &bad, &err));
    TEST_ASSERT_NULL(r);
    /* 300 rows: too few per block -> insufficient, not an error; NaN rows leave no trace */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_rfs_create(&r, &c, &err));
    for (size_t n = 0; n < 300u; ++n)
    {
        const double row[2] = {n % 7u == 3u ? (double)NAN : x[n], x[N_ROWS + n]};
        aenl_rfs_push(r, row);
    }
    aenl_rfs_fit_t fit;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_rfs_analyse(r, 0, &fit, &err));
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_INSUFFICIENT, fit.cls);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_rfs_analyse(r, 2, &fit, &err));
    aenl_rfs_free(r);
    free(x);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_rfs_cv_gain_matches_brute_force);
    RUN_TEST(test_rfs_law_given_another_matches_brute_force);
    RUN_TEST(test_rfs_free_law_residuals_match_brute_force);
    RUN_TEST(test_rfs_linear_oscillators_are_linear);
    RUN_TEST(test_rfs_names_the_freeplay_channel_and_its_gap);
    RUN_TEST(test_rfs_names_the_cubic_channel_hardening);
    RUN_TEST(test_rfs_softening_spring_is_not_freeplay);
    RUN_TEST(test_rfs_hysteresis_is_a_lagging_moving_gap);
    RUN_TEST(test_rfs_bad_configuration_and_short_records);
    return UNITY_END();
}
