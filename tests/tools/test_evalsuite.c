/* SPDX-License-Identifier: MIT */
/**
 * @file test_evalsuite.c
 * @brief The identification evaluation suite's generator (aenl_evalsuite.h), checked from the
 *        outside: the strata promised are all there (and nothing else), the truth's switching
 *        points are where the law changes slope (brute force), the truth's channel and class
 *        follow the stratum, a case is a pure function of (seed, index), its noise and INI
 *        reproduce it through the simulator, and the materiality rules hold on a sample of
 *        generated cases (recomputed here from the noise-free run).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "unity.h"

#include "aenl_evalsuite.h"
#include "aenl_tools/aenl_sim.h"

#define SEED 1u

void setUp(void)
{
}

void tearDown(void)
{
}

/* ---- independent expectations ---------------------------------------------------------------- */

/* The combinations the header promises (its table), written out again here. */
static int promised(aenl_eval_variant_t v, aenl_sim_type_t model, int dof, aenl_eval_regime_t rg)
{
    if (v == AENL_EVAL_LINEAR)
    {
        return dof == -1 && rg != AENL_EVAL_LCO;
    }
    if (dof < 0 || dof > 2 || (dof == AENL_SIM_DOF_FLAP && model != AENL_SIM_SECTION3DOF))
    {
        return 0;
    }
    if (rg != AENL_EVAL_LCO)
    {
        return 1;
    }
    switch (v)
    {
        case AENL_EVAL_HARDENING:
            return dof == AENL_SIM_DOF_PITCH;
        case AENL_EVAL_SOFTENING:
            return dof == AENL_SIM_DOF_PITCH || dof == AENL_SIM_DOF_PLUNGE;
        case AENL_EVAL_FREEPLAY:
        case AENL_EVAL_HYSTERESIS:
            return dof == AENL_SIM_DOF_PITCH || dof == AENL_SIM_DOF_FLAP;
        case AENL_EVAL_LINEAR:
        default:
            return 0;
    }
}

static const char *expected_channel(aenl_sim_type_t model, int dof)
{
    if (dof < 0)
    {
        return "";
    }
    if (model == AENL_SIM_AIRFOIL2DOF)
    {
        return dof == AENL_SIM_DOF_PITCH ? "alpha" : "xi";
    }
    return dof == AENL_SIM_DOF_PLUNGE ? "h" : (dof == AENL_SIM_DOF_PITCH ? "alpha" : "beta");
}

static aenl_class_t expected_class(aenl_eval_variant_t v)
{
    switch (v)
    {
        case AENL_EVAL_HARDENING:
        case AENL_EVAL_SOFTENING:
            return AENL_CLASS_POLYNOMIAL;
        case AENL_EVAL_FREEPLAY:
            return AENL_CLASS_FREEPLAY;
        case AENL_EVAL_HYSTERESIS:
            return AENL_CLASS_HYSTERESIS;
        case AENL_EVAL_LINEAR:
        default:
            return AENL_CLASS_LINEAR;
    }
}

/* First index (in the first 240) whose stratum matches; -1 none. */
static long find_index(aenl_eval_variant_t v, aenl_sim_type_t model, int dof, aenl_eval_regime_t rg)
{
    for (size_t i = 0; i < 240; ++i)
    {
        aenl_eval_stratum_t s;
        aenl_eval_stratum_of(i, &s);
        if (s.variant == v && s.model == model && s.dof == dof && s.regime == rg)
        {
            return (long)i;
        }
    }
    return -1;
}

/* ---- strata -----------------------------------------------------------------------------------
 */

static void test_strata_cover_every_promised_combination_at_every_snr(void)
{
    /* [variant][model][dof + 1][regime][snr level] */
    static unsigned count[5][2][4][3][4];
    memset(count, 0, sizeof(count));
    for (size_t i = 0; i < 240; ++i)
    {
        aenl_eval_stratum_t s;
        aenl_eval_stratum_of(i, &s);
        TEST_ASSERT_TRUE_MESSAGE(promised(s.variant, s.model, s.dof, s.regime),
                                 "a stratum outside the promised table");
        TEST_ASSERT_TRUE(s.snr_level < 4u);
        static const double k_snr[4] = {0.0, 10.0, 3.0, 2.0};
        TEST_ASSERT_EQUAL_DOUBLE(k_snr[s.snr_level], s.snr);
        ++count[s.variant][s.model][s.dof + 1][s.regime][s.snr_level];
    }
    unsigned combos = 0;
    for (int v = 0; v < 5; ++v)
    {
        for (int m = 0; m < 2; ++m)
        {
            for (int dof = -1; dof < 3; ++dof)
            {
                for (int rg = 0; rg < 3; ++rg)
                {
                    if (!promised((aenl_eval_variant_t)v, (aenl_sim_type_t)m, dof,
                                  (aenl_eval_regime_t)rg))
                    {
                        continue;
                    }
                    ++combos;
                    for (int l = 0; l < 4; ++l)
                    {
                        char msg[96];
                        (void)snprintf(msg, sizeof(msg),
                                       "variant %d model %d dof %d regime %d snr %d", v, m, dof, rg,
                                       l);
                        /* linear combinations twice per SNR, the others once */
                        TEST_ASSERT_EQUAL_UINT_MESSAGE(v == 0 ? 2u : 1u,
                                                       count[v][m][dof + 1][rg][l], msg);
                    }
                }
            }
        }
    }
    TEST_ASSERT_EQUAL_UINT(56u, combos);
}

static void test_strata_prefix_is_balanced(void)
{
    /* The first 20 cases already hold every variant and every regime. */
    unsigned var[5] = {0}, reg[3] = {0};
    for (size_t i = 0; i < 20; ++i)
    {
        aenl_eval_stratum_t s;
        aenl_eval_stratum_of(i, &s);
        ++var[s.variant];
        ++reg[s.regime];
    }
    for (int v = 0; v < 5; ++v)
    {
        TEST_ASSERT_GREATER_OR_EQUAL_UINT(3u, var[v]);
    }
    for (int r = 0; r < 3; ++r)
    {
        TEST_ASSERT_GREATER_OR_EQUAL_UINT(3u, reg[r]);
    }
}

/* ---- truth against the law ------------------------------------------------------------------- */

/* Places where the law (either branch) changes slope, by brute force over [lo, hi]: cell slopes
 * on a fine grid, a change of more than 5 % between neighbours marks a kink; marks closer than
 * 4 cells (a cell straddling the kink) are one kink at their midpoint. */
static size_t find_kinks(const aenl_sim_law_t *law, double lo, double hi, double *out, size_t cap)
{
    enum
    {
        N_CELLS = 200000,
        MAX_MARKS = 64
    };
    const double h = (hi - lo) / (double)N_CELLS;
    double mark[MAX_MARKS];
    size_t m = 0;
    for (int dir = -1; dir <= 1; dir += 2)
    {
        double prev = 0.0;
        for (size_t k = 0; k < N_CELLS; ++k)
        {
            const double x = lo + h * (double)k;
            const double s =
                (aenl_sim_law_eval(law, x + h, dir) - aenl_sim_law_eval(law, x, dir)) / h;
            if (k > 0 && fabs(s - prev) > 0.05 * (1.0 + fabs(s)) && m < MAX_MARKS)
            {
                mark[m++] = x;
            }
            prev = s;
        }
    }
    for (size_t i = 1; i < m; ++i) /* insertion sort */
    {
        for (size_t j = i; j > 0 && mark[j - 1] > mark[j]; --j)
        {
            const double t = mark[j];
            mark[j] = mark[j - 1];
            mark[j - 1] = t;
        }
    }
    size_t k = 0;
    for (size_t i = 0; i < m;)
    {
        size_t j = i;
        while (j + 1 < m && mark[j + 1] - mark[j] < 4.0 * h)
        {
            ++j;
        }
        if (k < cap)
        {
            out[k++] = 0.5 * (mark[i] + mark[j]);
        }
        i = j + 1;
    }
    return k;
}

static double slope_at(const aenl_sim_law_t *law, double x, double dx, int dir)
{
    return (aenl_sim_law_eval(law, x + dx, dir) - aenl_sim_law_eval(law, x, dir)) / dx;
}

static void check_truth(const aenl_eval_case_t *c)
{
    char msg[400];
    const aenl_eval_stratum_t *s = &c->stratum;
    (void)snprintf(msg, sizeof(msg), "case %zu: %s", c->index, c->description);
    TEST_ASSERT_EQUAL_INT_MESSAGE(expected_class(s->variant), c->cls, msg);
    TEST_ASSERT_EQUAL_STRING_MESSAGE(expected_channel(s->model, s->dof), c->channel, msg);
    if (s->dof < 0)
    {
        TEST_ASSERT_EQUAL_INT_MESSAGE(-1, (int)c->channel_index, msg);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, (unsigned)c->n_switch, msg);
        for (int q = 0; q < 3; ++q)
        {
            TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_SIM_LAW_LINEAR, c->model.law[q].kind, msg);
        }
        return;
    }
    /* every other DOF linear */
    for (int q = 0; q < 3; ++q)
    {
        if (q != s->dof)
        {
            TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_SIM_LAW_LINEAR, c->model.law[q].kind, msg);
        }
    }
    const aenl_sim_law_t *law = &c->model.law[s->dof];
    double kinks[8];
    if (c->cls == AENL_CLASS_POLYNOMIAL)
    {
        TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, (unsigned)c->n_switch, msg);
        TEST_ASSERT_EQUAL_DOUBLE_MESSAGE(0.0, c->gap, msg);
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_SIM_LAW_POLYNOMIAL, law->kind, msg);
        /* hardening: positive cubic; softening: negative cubic (stabilised by a quintic) */
        TEST_ASSERT_TRUE_MESSAGE(c->hardening * law->coeffs[2] > 0.0, msg);
        TEST_ASSERT_EQUAL_DOUBLE_MESSAGE(1.0, law->coeffs[0], msg);
        /* smooth: no kink anywhere over ±3 amplitudes (slope changes only gradually) */
        const double a = 3.0 * c->amplitude;
        const size_t nk = find_kinks(law, -a, a, kinks, 8);
        TEST_ASSERT_EQUAL_UINT_MESSAGE(0u, (unsigned)nk, msg);
        return;
    }
    TEST_ASSERT_TRUE_MESSAGE(c->n_switch >= 2 && c->n_switch <= AENL_EVAL_MAX_SWITCH, msg);
    TEST_ASSERT_TRUE_MESSAGE(c->gap > 0.0, msg);
    TEST_ASSERT_EQUAL_DOUBLE_MESSAGE(law->delta, c->gap, msg);
    for (size_t i = 1; i < c->n_switch; ++i)
    {
        TEST_ASSERT_TRUE_MESSAGE(c->switch_points[i] > c->switch_points[i - 1], msg);
    }
    /* at each truth point the slope differs on either side (on at least one branch) */
    const double eps = 1e-3 * c->gap;
    for (size_t i = 0; i < c->n_switch; ++i)
    {
        const double p = c->switch_points[i];
        double jump = 0.0;
        for (int dir = -1; dir <= 1; dir += 2)
        {
            const double left = slope_at(law, p - 3.0 * eps, eps, dir);
            const double right = slope_at(law, p + 2.0 * eps, eps, dir);
            jump = fmax(jump, fabs(right - left));
        }
        TEST_ASSERT_TRUE_MESSAGE(jump > 0.5 * fabs(1.0 - law->inner_stiffness), msg);
    }
    /* and the law has no other kink: brute force over the points' span plus 2 gaps each side */
    const size_t nk = find_kinks(law, c->switch_points[0] - 2.0 * c->gap,
                                 c->switch_points[c->n_switch - 1] + 2.0 * c->gap, kinks, 8);
    TEST_ASSERT_EQUAL_UINT_MESSAGE((unsigned)c->n_switch, (unsigned)nk, msg);
    for (size_t i = 0; i < nk; ++i)
    {
        TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(2e-4 * c->gap, c->switch_points[i], kinks[i], msg);
    }
    if (c->cls == AENL_CLASS_FREEPLAY)
    {
        TEST_ASSERT_EQUAL_UINT_MESSAGE(2u, (unsigned)c->n_switch, msg);
        TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(1e-12 * c->gap, c->gap,
                                          c->switch_points[1] - c->switch_points[0], msg);
    }
}

static void test_truth_switching_points_are_the_kinks_of_the_law(void)
{
    /* The design of every slot's first attempt (no simulation), turbulence excepted (its design
     * runs a pilot simulation; the generated cases below cover it). */
    unsigned checked = 0, gap_laws = 0;
    for (size_t i = 0; i < AENL_EVAL_N_SLOTS; ++i)
    {
        aenl_eval_stratum_t s;
        aenl_eval_case_t c;
        aenl_err_t err;
        aenl_eval_stratum_of(i, &s);
        if (s.regime == AENL_EVAL_TURBULENCE)
        {
            continue;
        }
        aenl_err_clear(&err);
        const aenl_status_t st = aenl_eval_case_design(SEED, i, 0, &c, &err);
        if (st == AENL_E_NUMERIC)
        {
            continue; /* rejected at the design step: redrawn by aenl_eval_case_make */
        }
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, st, err.msg);
        TEST_ASSERT_NULL(c.y);
        check_truth(&c);
        gap_laws += c.n_switch > 0;
        ++checked;
        aenl_eval_case_free(&c);
    }
    TEST_ASSERT_GREATER_OR_EQUAL_UINT(30u, checked);
    TEST_ASSERT_GREATER_OR_EQUAL_UINT(12u, gap_laws);
}

static void test_hysteresis_truth_has_three_or_four_points(void)
{
    /* α_f = 0: three distinct kinks (−δ, 0, δ); α_f > 0: four, at least δ/2 apart. */
    unsigned three = 0, four = 0;
    for (size_t i = 0; i < 240; ++i)
    {
        aenl_eval_stratum_t s;
        aenl_eval_case_t c;
        aenl_err_t err;
        aenl_eval_stratum_of(i, &s);
        if (s.variant != AENL_EVAL_HYSTERESIS || s.regime == AENL_EVAL_TURBULENCE)
        {
            continue;
        }
        aenl_err_clear(&err);
        if (aenl_eval_case_design(SEED, i, 0, &c, &err) != AENL_OK)
        {
            continue;
        }
        const aenl_sim_law_t *l = &c.model.law[s.dof];
        if (c.n_switch == 3)
        {
            ++three;
            TEST_ASSERT_EQUAL_DOUBLE(0.0, l->x_f);
            TEST_ASSERT_DOUBLE_WITHIN(1e-12 * c.gap, -c.gap, c.switch_points[0]);
            TEST_ASSERT_DOUBLE_WITHIN(1e-12 * c.gap, 0.0, c.switch_points[1]);
            TEST_ASSERT_DOUBLE_WITHIN(1e-12 * c.gap, c.gap, c.switch_points[2]);
        }
        else
        {
            ++four;
            TEST_ASSERT_EQUAL_UINT(4u, (unsigned)c.n_switch);
            for (int k = 1; k < 4; ++k)
            {
                TEST_ASSERT_TRUE(c.switch_points[k] - c.switch_points[k - 1] >=
                                 0.5 * c.gap * 0.999);
            }
        }
        aenl_eval_case_free(&c);
    }
    TEST_ASSERT_GREATER_THAN_UINT(0u, three);
    TEST_ASSERT_GREATER_THAN_UINT(0u, four);
}

/* ---- generated cases ---------------------------------------------------------------------------
 */

static double rms_about_mean(const double *y, size_t n)
{
    double s = 0.0, s2 = 0.0;
    for (size_t k = 0; k < n; ++k)
    {
        s += y[k];
    }
    const double m = s / (double)n;
    for (size_t k = 0; k < n; ++k)
    {
        s2 += (y[k] - m) * (y[k] - m);
    }
    return sqrt(s2 / (double)n);
}

/* Polynomial value from the coefficients (not through the simulator). */
static double poly(const aenl_sim_law_t *l, double x)
{
    double acc = 0.0, p = 1.0;
    for (size_t k = 0; k < l->n_coeffs; ++k)
    {
        p *= x;
        acc += l->coeffs[k] * p;
    }
    return acc;
}

/* The header's materiality rules, recomputed from the noise-free run. */
static void check_material(const aenl_eval_case_t *c)
{
    char msg[400];
    const size_t n = c->n_samples;
    (void)snprintf(msg, sizeof(msg), "case %zu: %s", c->index, c->description);
    TEST_ASSERT_TRUE_MESSAGE(n >= 20000 && n <= 60001, msg);
    TEST_ASSERT_TRUE_MESSAGE(c->samples_per_period >= 12.0 && c->samples_per_period <= 60.0, msg);
    TEST_ASSERT_EQUAL_UINT_MESSAGE(c->model.type == AENL_SIM_AIRFOIL2DOF ? 2u : 3u,
                                   (unsigned)c->n_channels, msg);
    for (size_t k = 0; k < n * c->n_channels; ++k)
    {
        TEST_ASSERT_TRUE_MESSAGE(isfinite(c->clean[k]) && isfinite(c->y[k]), msg);
    }
    for (size_t ch = 0; ch < c->n_channels; ++ch)
    {
        const double *clean = c->clean + ch * n;
        const double sd = rms_about_mean(clean, n);
        TEST_ASSERT_TRUE_MESSAGE(sd > 0.0, msg);
        TEST_ASSERT_TRUE_MESSAGE(c->cols[ch] == c->y + ch * n, msg);
        if (c->stratum.snr > 0.0)
        {
            double e2 = 0.0;
            for (size_t k = 0; k < n; ++k)
            {
                e2 += (c->y[ch * n + k] - clean[k]) * (c->y[ch * n + k] - clean[k]);
            }
            /* noise std / signal std = 1 / SNR, to the sampling error of n Gaussian values */
            TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.03, 1.0, sqrt(e2 / (double)n) * c->stratum.snr / sd,
                                              msg);
        }
        else
        {
            TEST_ASSERT_EQUAL_MEMORY_MESSAGE(clean, c->y + ch * n, n * sizeof(double), msg);
        }
    }
    if (c->channel_index < 0)
    {
        return;
    }
    const double *x = c->clean + (size_t)c->channel_index * n;
    if (c->cls == AENL_CLASS_POLYNOMIAL)
    {
        double s2 = 0.0, kappa = 0.0;
        for (size_t k = 0; k < n; ++k)
        {
            s2 += x[k] * x[k];
        }
        const double xa = sqrt(2.0 * s2 / (double)n);
        const aenl_sim_law_t *l = &c->model.law[c->stratum.dof];
        for (int k = 1; k <= 1000; ++k)
        {
            const double u = xa * (double)k / 1000.0;
            kappa = fmax(kappa, fmax(fabs(poly(l, u) / u - 1.0), fabs(poly(l, -u) / -u - 1.0)));
        }
        TEST_ASSERT_TRUE_MESSAGE(kappa >= 0.4, msg);
        return;
    }
    size_t below = 0, above = 0;
    const double lo = c->switch_points[0] - 0.25 * c->gap;
    const double hi = c->switch_points[c->n_switch - 1] + 0.25 * c->gap;
    for (size_t k = 0; k < n; ++k)
    {
        below += x[k] < lo;
        above += x[k] > hi;
    }
    TEST_ASSERT_TRUE_MESSAGE((double)below >= 0.05 * (double)n, msg);
    TEST_ASSERT_TRUE_MESSAGE((double)above >= 0.05 * (double)n, msg);
}

static void make(long index, aenl_eval_case_t *c)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_TRUE(index >= 0);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_eval_case_make(SEED, (size_t)index, c, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_UINT(index, c->index);
}

static void test_generated_cases_are_material(void)
{
    const long idx[5] = {
        find_index(AENL_EVAL_FREEPLAY, AENL_SIM_SECTION3DOF, AENL_SIM_DOF_FLAP, AENL_EVAL_LCO),
        find_index(AENL_EVAL_HYSTERESIS, AENL_SIM_AIRFOIL2DOF, AENL_SIM_DOF_PLUNGE,
                   AENL_EVAL_DECAY),
        find_index(AENL_EVAL_HARDENING, AENL_SIM_SECTION3DOF, AENL_SIM_DOF_PLUNGE,
                   AENL_EVAL_TURBULENCE),
        find_index(AENL_EVAL_SOFTENING, AENL_SIM_AIRFOIL2DOF, AENL_SIM_DOF_PLUNGE, AENL_EVAL_LCO),
        find_index(AENL_EVAL_LINEAR, AENL_SIM_SECTION3DOF, -1, AENL_EVAL_DECAY)};
    for (int i = 0; i < 5; ++i)
    {
        aenl_eval_case_t c;
        make(idx[i], &c);
        check_truth(&c);
        check_material(&c);
        if (c.stratum.regime == AENL_EVAL_DECAY)
        {
            /* a sequence of releases covering the record, the first at the start: the run's
             * kick train, one kick per release */
            TEST_ASSERT_GREATER_OR_EQUAL_UINT(2u, (unsigned)c.n_releases);
            TEST_ASSERT_EQUAL_INT(1, c.run.kicks);
            TEST_ASSERT_EQUAL_DOUBLE((double)c.release_samples * c.run.dt, c.run.kick_every);
            TEST_ASSERT_TRUE((c.n_releases - 1u) * c.release_samples < c.n_samples - 1u);
            TEST_ASSERT_TRUE(c.n_releases * c.release_samples >= c.n_samples - 1u);
            TEST_ASSERT_TRUE(c.run.kick_rate > 0.0 && c.run.kick_rate_max > c.run.kick_rate);
        }
        else
        {
            TEST_ASSERT_EQUAL_UINT(0u, (unsigned)c.n_releases);
            TEST_ASSERT_EQUAL_INT(0, c.run.kicks);
        }
        aenl_eval_case_free(&c);
    }
}

static void test_case_is_a_function_of_seed_and_index(void)
{
    const long i =
        find_index(AENL_EVAL_HARDENING, AENL_SIM_SECTION3DOF, AENL_SIM_DOF_PITCH, AENL_EVAL_LCO);
    aenl_eval_case_t a, b, other;
    make(i, &a);
    make(i, &b);
    TEST_ASSERT_EQUAL_UINT(a.n_samples, b.n_samples);
    TEST_ASSERT_EQUAL_UINT(a.attempt, b.attempt);
    TEST_ASSERT_EQUAL_MEMORY(a.y, b.y, a.n_samples * a.n_channels * sizeof(double));
    TEST_ASSERT_EQUAL_MEMORY(a.clean, b.clean, a.n_samples * a.n_channels * sizeof(double));
    TEST_ASSERT_EQUAL_MEMORY(a.switch_points, b.switch_points, sizeof(a.switch_points));
    TEST_ASSERT_EQUAL_STRING(a.description, b.description);
    TEST_ASSERT_EQUAL_MEMORY(&a.model.law[AENL_SIM_DOF_PITCH], &b.model.law[AENL_SIM_DOF_PITCH],
                             sizeof(aenl_sim_law_t));
    /* another suite seed draws another case in the same stratum */
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_eval_case_make(SEED + 1u, (size_t)i, &other, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_INT(a.stratum.variant, other.stratum.variant);
    TEST_ASSERT_EQUAL_INT(a.stratum.regime, other.stratum.regime);
    TEST_ASSERT_TRUE(a.n_samples != other.n_samples ||
                     memcmp(a.y, other.y, a.n_samples * sizeof(double)) != 0);
    aenl_eval_case_free(&a);
    aenl_eval_case_free(&b);
    aenl_eval_case_free(&other);
    /* freeing twice is safe */
    aenl_eval_case_free(&a);
}

/* Case i's INI through the loader and the simulator gives its noisy record. */
static void reproduce_case(long i)
{
    aenl_eval_case_t c;
    make(i, &c);
    char path[512];
    aenl_err_t err;
    aenl_err_clear(&err);
    (void)snprintf(path, sizeof(path), "%s/case.ini", AENL_TEST_TMP_DIR);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_eval_case_write_ini(&c, path, &err), err.msg);
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_load_ini(path, &m, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_DOUBLE(aenl_sim_velocity(&c.model), aenl_sim_velocity(&m));
    TEST_ASSERT_EQUAL_DOUBLE(c.model.law[AENL_SIM_DOF_PITCH].delta,
                             m.law[AENL_SIM_DOF_PITCH].delta);
    TEST_ASSERT_EQUAL_DOUBLE(c.model.law[AENL_SIM_DOF_PITCH].x_f, m.law[AENL_SIM_DOF_PITCH].x_f);
    TEST_ASSERT_EQUAL_DOUBLE(c.run.dt, r.dt);
    TEST_ASSERT_EQUAL_DOUBLE(c.run.snr, r.snr);
    TEST_ASSERT_EQUAL_INT(c.run.kicks, r.kicks);
    aenl_sim_result_t res;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &r, &res, &err), err.msg);
    TEST_ASSERT_EQUAL_UINT(c.n_samples, res.n_samples);
    TEST_ASSERT_EQUAL_MEMORY(c.y, res.y, c.n_samples * c.n_channels * sizeof(double));
    aenl_sim_result_free(&res);
    aenl_eval_case_free(&c);
}

static void test_ini_and_noise_reproduce_the_record(void)
{
    /* Noisy cases, a limit cycle and a train of releases (its kicks are in the INI): the INI
     * through the loader and the simulator gives the record. */
    for (int regime = 0; regime < 2; ++regime)
    {
        long i = -1;
        for (size_t k = 0; k < 240 && i < 0; ++k)
        {
            aenl_eval_stratum_t s;
            aenl_eval_stratum_of(k, &s);
            if (s.variant == AENL_EVAL_FREEPLAY &&
                s.regime == (regime == 0 ? AENL_EVAL_LCO : AENL_EVAL_DECAY) &&
                s.model == AENL_SIM_AIRFOIL2DOF && s.snr > 0.0)
            {
                i = (long)k;
            }
        }
        reproduce_case(i);
    }
}

static void test_another_simulator_keeps_the_design(void)
{
    /* --rk4 --dryden: a turbulence case from RK4 and the Dryden spectrum is drawn as the suite's
     * (same stratum, law and sampling; its gap is scaled to that simulator's own pilot runs), has
     * a record of its own and says so in its INI. */
    const long i = find_index(AENL_EVAL_FREEPLAY, AENL_SIM_AIRFOIL2DOF, AENL_SIM_DOF_PITCH,
                              AENL_EVAL_TURBULENCE);
    aenl_eval_case_t a, b;
    make(i, &a);
    const aenl_eval_options_t opt = {1, AENL_SIM_GUST_DRYDEN};
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        AENL_OK, aenl_eval_case_make_with(SEED, (size_t)i, &opt, &b, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_GUST_FIRST_ORDER, a.run.turb_spectrum);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_GUST_DRYDEN, b.run.turb_spectrum);
    TEST_ASSERT_EQUAL_INT(a.stratum.variant, b.stratum.variant);
    TEST_ASSERT_EQUAL_INT(a.model.law[AENL_SIM_DOF_PITCH].kind,
                          b.model.law[AENL_SIM_DOF_PITCH].kind);
    if (a.attempt == b.attempt)
    {
        TEST_ASSERT_EQUAL_DOUBLE(aenl_sim_velocity(&a.model), aenl_sim_velocity(&b.model));
        TEST_ASSERT_EQUAL_DOUBLE(a.run.dt, b.run.dt);
    }
    check_truth(&b);
    TEST_ASSERT_TRUE(a.n_samples != b.n_samples ||
                     memcmp(a.clean, b.clean, a.n_samples * a.n_channels * sizeof(double)) != 0);
    char path[512];
    (void)snprintf(path, sizeof(path), "%s/dryden_case.ini", AENL_TEST_TMP_DIR);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_eval_case_write_ini(&b, path, &err), err.msg);
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_load_ini(path, &m, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_GUST_DRYDEN, r.turb_spectrum);
    aenl_eval_case_free(&a);
    aenl_eval_case_free(&b);
}

static void test_rejects_null(void)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_eval_case_make(SEED, 0, NULL, &err));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_eval_case_design(SEED, 0, 0, NULL, &err));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_eval_case_write_ini(NULL, "x.ini", &err));
    aenl_eval_case_free(NULL);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_strata_cover_every_promised_combination_at_every_snr);
    RUN_TEST(test_strata_prefix_is_balanced);
    RUN_TEST(test_truth_switching_points_are_the_kinks_of_the_law);
    RUN_TEST(test_hysteresis_truth_has_three_or_four_points);
    RUN_TEST(test_generated_cases_are_material);
    RUN_TEST(test_case_is_a_function_of_seed_and_index);
    RUN_TEST(test_ini_and_noise_reproduce_the_record);
    RUN_TEST(test_another_simulator_keeps_the_design);
    RUN_TEST(test_rejects_null);
    return UNITY_END();
}
