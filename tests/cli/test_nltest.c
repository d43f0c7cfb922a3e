/* SPDX-License-Identifier: MIT */
/**
 * @file test_nltest.c
 * @brief The record-alone test (aenl_nltest) and `aenl identify --method test`.
 *
 * References: the chi-square tail against closed forms (k = 2: exp(-x/2); k = 1:
 * erfc(sqrt(x/2))) and published critical values; the long-run variance of the laws'
 * comparison against its double sum written out; the test's level against its own definition
 * (linear records from the project's simulator, another model than the test fits: a rejection
 * count at level 0.01 that a binomial bound allows); its power and switching points against the
 * simulated law's known gap.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cjson/cJSON.h>

#include "aenl_cli_test.h"
#include "aenl_nlt_internal.h"
#include "aenl_test_rand.h"
#include "aenl_test_sanitized.h"
#include "aenl_tools/aenl_csv.h"
#include "aenl_tools/aenl_nltest.h"
#include "aenl_tools/aenl_sim.h"
#include "aenl_tools/aenl_stats.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

#define DEG 0.017453292519943295

/* ---- chi-square tail --------------------------------------------------------------------------
 */

static void test_chi2_sf_closed_forms(void)
{
    const double xs[] = {1e-6, 0.1, 1.0, 3.0, 10.0, 50.0, 200.0, 700.0};
    for (size_t i = 0; i < sizeof(xs) / sizeof(xs[0]); ++i)
    {
        const double x = xs[i];
        const double two = exp(-0.5 * x);
        const double one = erfc(sqrt(0.5 * x));
        TEST_ASSERT_DOUBLE_WITHIN(1e-13 * two + 1e-300, two, aenl_chi2_sf(x, 2.0));
        TEST_ASSERT_DOUBLE_WITHIN(1e-12 * one + 1e-300, one, aenl_chi2_sf(x, 1.0));
    }
    TEST_ASSERT_EQUAL_DOUBLE(1.0, aenl_chi2_sf(0.0, 3.0));
    TEST_ASSERT_EQUAL_DOUBLE(0.0, aenl_chi2_sf(INFINITY, 3.0));
    TEST_ASSERT_TRUE(isnan(aenl_chi2_sf(1.0, 0.0)));
}

/* Upper critical values from the standard tables (Abramowitz & Stegun, table 26.8), printed to
 * six figures: the tail at the printed value is the level within 1e-4 of itself. */
static void test_chi2_sf_critical_values(void)
{
    const struct
    {
        double k, x, alpha;
    } tab[] = {{1, 3.84146, 0.05},  {1, 6.63490, 0.01},   {5, 11.0705, 0.05},
               {10, 23.2093, 0.01}, {24, 51.1786, 0.001}, {30, 43.7730, 0.05},
               {30, 50.8922, 0.01}, {100, 135.807, 0.01}};
    for (size_t i = 0; i < sizeof(tab) / sizeof(tab[0]); ++i)
    {
        TEST_ASSERT_DOUBLE_WITHIN(1e-4 * tab[i].alpha, tab[i].alpha,
                                  aenl_chi2_sf(tab[i].x, tab[i].k));
    }
}

/* The long-run variance of the laws' comparison against its definition written out as a double
 * sum: sum over s, t of w(|s - t|) (x_s - mean)(x_t - mean), Bartlett weights
 * w(h) = 1 - h / (L + 1) up to L = floor(4 (n / 100)^(2/9)), on an autocorrelated series. */
static void test_nlt_long_run_variance_brute_force(void)
{
    enum
    {
        N = 700
    };
    static double x[N];
    uint64_t seed = 7u;
    double prev = 0.0;
    for (size_t t = 0; t < N; ++t)
    {
        prev = 0.6 * prev + test_gauss(&seed) + 0.3;
        x[t] = prev;
    }
    double mean = 0.0;
    for (size_t t = 0; t < N; ++t)
    {
        mean += x[t] / (double)N;
    }
    const double lag = floor(4.0 * pow((double)N / 100.0, 2.0 / 9.0));
    double ref = 0.0;
    for (size_t s = 0; s < N; ++s)
    {
        for (size_t t = 0; t < N; ++t)
        {
            const double h = fabs((double)s - (double)t);
            if (h <= lag)
            {
                ref += (1.0 - h / (lag + 1.0)) * (x[s] - mean) * (x[t] - mean);
            }
        }
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-9 * ref, ref, nlt_long_run_variance(x, N));
    TEST_ASSERT_EQUAL_DOUBLE(0.0, nlt_long_run_variance(x, 0));
}

/* ---- records -----------------------------------------------------------------------------------
 */

/* The 2-DOF airfoil at U* = 4 (below its flutter speed), run as set by how (gusts, noise,
 * initial state), with the pitch law pitch (linear when NULL). y: n x 2 row-major (alpha, xi). */
static double *airfoil_run(const aenl_sim_law_t *pitch,
                           void (*how)(aenl_sim_model_t *, aenl_sim_run_t *, uint64_t),
                           uint64_t seed, size_t *n_out)
{
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    aenl_sim_run_default(&run, AENL_SIM_AIRFOIL2DOF);
    aenl_sim_set_velocity(&m, 4.0);
    if (pitch != NULL)
    {
        m.law[AENL_SIM_DOF_PITCH] = *pitch;
    }
    run.dt = 0.5;
    how(&m, &run, seed);
    aenl_sim_result_t r;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &run, &r, &err), err.msg);
    double *y = malloc(r.n_samples * 2u * sizeof(double));
    TEST_ASSERT_NOT_NULL(y);
    for (size_t k = 0; k < r.n_samples; ++k)
    {
        y[2u * k] = r.y[k];
        y[2u * k + 1u] = r.y[r.n_samples + k];
    }
    *n_out = r.n_samples;
    aenl_sim_result_free(&r);
    return y;
}

/* First-order gusts, noise at SNR 5. */
static void gusts(aenl_sim_model_t *m, aenl_sim_run_t *run, uint64_t seed)
{
    (void)m;
    run->duration = 4000.0;
    run->turbulence = 1;
    run->turb_intensity = 0.004;
    run->turb_length = 4.0;
    run->turb_seed = seed;
    run->snr = 5.0;
    run->noise_seed = seed + 1000u;
}

/* A release from 3 deg of pitch, no gusts, no measurement noise. */
static void noise_free_release(aenl_sim_model_t *m, aenl_sim_run_t *run, uint64_t seed)
{
    (void)seed;
    m->x0[AENL_SIM_DOF_PITCH] = 3.0 * DEG;
    run->duration = 3000.0;
    run->snr = 0.0;
}

/* The airfoil under gusts with noise (airfoil_run, gusts). */
static double *airfoil_record(const aenl_sim_law_t *pitch, uint64_t seed, size_t *n_out)
{
    return airfoil_run(pitch, gusts, seed, n_out);
}

/* A pitch freeplay of 1 deg starting at -0.3 deg (no preload, no stiffness inside). */
static aenl_sim_law_t pitch_freeplay(void)
{
    aenl_sim_law_t law;
    memset(&law, 0, sizeof(law));
    law.kind = AENL_SIM_LAW_FREEPLAY;
    law.delta = 1.0 * DEG;
    law.x_f = -0.3 * DEG;
    return law;
}

/* A cubic pitch spring R = a + c3 a^3 (a in rad). */
static aenl_sim_law_t pitch_cubic(double c3)
{
    aenl_sim_law_t law;
    memset(&law, 0, sizeof(law));
    law.kind = AENL_SIM_LAW_POLYNOMIAL;
    law.n_coeffs = 3;
    law.coeffs[0] = 1.0;
    law.coeffs[2] = c3;
    return law;
}

/* The test of the two-channel record y (n samples, freed here) with the default options. */
static void test_record(double *y, size_t n, aenl_nlt_result_t *r)
{
    aenl_nlt_opts_t o;
    aenl_nlt_opts_default(&o);
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_nlt_run(y, n, 2, &o, r, &err), err.msg);
    free(y);
}

/* Linear records: at level 0.01 the number of nonlinear verdicts among 20 is binomial(20, 0.01)
 * when the test holds its level; P(X >= 3) = 0.001, so three or more fail. */
#define NULL_RECORDS      20u
#define NULL_MAX_REJECTED 2u
/* Linear controls count their own nonlinear verdicts: at level 0.01 the controls of a linear
 * gust record are linear (at most one of six, a binomial bound); at level 0.5, where each of the
 * two channels rejects a linear record half the time, some are called nonlinear and some not. */
static void test_nlt_controls_count_their_verdicts(void)
{
    /* fourteen runs of the test; the controls' code runs under the sanitizers in
     * test_parallel and in the --controls runs of the command line here */
    AENL_PLAIN_BUILD_ONLY("fourteen runs of the test: left to the plain build");
    size_t n = 0;
    double *y = airfoil_record(NULL, 7100u, &n);
    aenl_nlt_opts_t o;
    aenl_nlt_opts_default(&o);
    o.n_controls = 6;
    aenl_nlt_result_t r;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_nlt_run(y, n, 2, &o, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_size_t(6, r.n_controls);
    TEST_ASSERT_LESS_OR_EQUAL_size_t(1, r.n_controls_nonlinear);
    o.level = 0.5;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_nlt_run(y, n, 2, &o, &r, &err), err.msg);
    printf("linear controls called nonlinear at level 0.5: %zu of %zu\n", r.n_controls_nonlinear,
           r.n_controls);
    TEST_ASSERT_TRUE(r.n_controls_nonlinear >= 1u && r.n_controls_nonlinear < r.n_controls);
    free(y);
}

static void test_nlt_linear_records_hold_the_level(void)
{
    /* linear records run through the test under the sanitizers in test_cli_bench_null */
    AENL_PLAIN_BUILD_ONLY("twenty runs of the test: left to the plain build");
    size_t rejected = 0;
    size_t impulses = 0;
    size_t samples = 0;
    for (uint64_t s = 1; s <= NULL_RECORDS; ++s)
    {
        size_t n = 0;
        double *y = airfoil_record(NULL, 7000u + s, &n);
        aenl_nlt_result_t r;
        test_record(y, n, &r);
        TEST_ASSERT_EQUAL_size_t(2, r.n_channels);
        /* BIC's choice among 4 and 6 states per channel and 12 */
        TEST_ASSERT_TRUE(r.n_states == 8u || r.n_states == 12u);
        rejected += r.verdict >= 0;
        impulses += r.n_impulses;
        samples += n;
        for (size_t j = 0; j < 2; ++j)
        {
            TEST_ASSERT_TRUE(r.ch[j].p >= 0.0 && r.ch[j].p <= 1.0);
            TEST_ASSERT_EQUAL_DOUBLE(4.0 * (double)r.n_states, r.ch[j].dof); /* 4 shapes */
        }
    }
    printf("linear records called nonlinear: %zu of %u; impulses %zu in %zu samples\n", rejected,
           NULL_RECORDS, impulses, samples);
    TEST_ASSERT_LESS_OR_EQUAL_size_t(NULL_MAX_REJECTED, rejected);
    /* Gaussian gusts: about samples x 1e-4 innovations beyond the impulse quantile (16 here)
     * with exact innovations; a fitted model's are a little heavier-tailed. Three times that
     * count says impulses stay rare where there are none. */
    TEST_ASSERT_LESS_THAN_size_t(3u * samples / 10000u + 1u, impulses);
}

/* A pitch freeplay of 1 deg starting at -0.3 deg under the same gusts: named, in alpha, its two
 * switching points within 10 % of the gap's width, each inside its interval's neighbourhood. */
static void test_nlt_freeplay_named_with_its_gap(void)
{
    /* every run fits every law: the freeplay's code runs under the sanitizers in the command's
     * runs below */
    AENL_PLAIN_BUILD_ONLY("another run of the test: left to the plain build");
    const aenl_sim_law_t law = pitch_freeplay();
    size_t n = 0;
    double *y = airfoil_record(&law, 4242u, &n);
    aenl_nlt_opts_t o;
    aenl_nlt_opts_default(&o);
    aenl_nlt_result_t r;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_nlt_run(y, n, 2, &o, &r, &err), err.msg);
    /* the same record as separate channel arrays gives the same run, bit for bit */
    double *split = (double *)malloc(2u * n * sizeof(double));
    TEST_ASSERT_NOT_NULL(split);
    for (size_t k = 0; k < n; ++k)
    {
        split[k] = y[2u * k];
        split[n + k] = y[2u * k + 1u];
    }
    const double *cols[2] = {split, split + n};
    aenl_nlt_result_t rc;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_nlt_run_columns(cols, n, 2, &o, &rc, &err),
                                  err.msg);
    free(split);
    free(y);
    TEST_ASSERT_EQUAL_INT(r.verdict_class, rc.verdict_class);
    TEST_ASSERT_EQUAL_DOUBLE(r.ch[0].stat, rc.ch[0].stat);
    TEST_ASSERT_EQUAL_DOUBLE(r.ch[1].stat, rc.ch[1].stat);
    TEST_ASSERT_EQUAL_DOUBLE(r.ch[0].points[0], rc.ch[0].points[0]);
    TEST_ASSERT_EQUAL_INT(0, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_FREEPLAY, r.verdict_class);
    TEST_ASSERT_FALSE(r.undetermined);
    /* named: both other laws lose their comparison with freeplay at 5 % each, and the best
     * model heads the candidates */
    TEST_ASSERT_TRUE(r.class_confidence >= 0.9);
    /* the verdict's confidence is the union bound of its law's and its channel's */
    TEST_ASSERT_EQUAL_DOUBLE(fmax(r.class_confidence + r.channel_confidence - 1.0, 0.0),
                             r.confidence);
    TEST_ASSERT_TRUE(r.ch[0].law_p[AENL_NLT_POLYNOMIAL] < 0.05);
    TEST_ASSERT_TRUE(r.ch[0].law_p[AENL_NLT_HYSTERESIS] < 0.05);
    TEST_ASSERT_EQUAL_DOUBLE(1.0, r.ch[0].law_p[AENL_NLT_FREEPLAY]);
    TEST_ASSERT_TRUE(r.n_candidates >= 1);
    TEST_ASSERT_EQUAL_size_t(0, r.candidates[0].channel);
    TEST_ASSERT_EQUAL_INT(AENL_NLT_FREEPLAY, r.candidates[0].law);
    TEST_ASSERT_TRUE(r.ch[0].p < 1e-6);
    TEST_ASSERT_EQUAL_size_t(2, r.ch[0].n_points);
    const double lo = law.x_f;
    const double hi = law.x_f + law.delta;
    printf("freeplay: %.5f %.5f rad (truth %.5f %.5f)\n", r.ch[0].points[0], r.ch[0].points[1], lo,
           hi);
    TEST_ASSERT_DOUBLE_WITHIN(0.1 * law.delta, lo, r.ch[0].points[0]);
    TEST_ASSERT_DOUBLE_WITHIN(0.1 * law.delta, hi, r.ch[0].points[1]);
    for (size_t k = 0; k < 2; ++k)
    {
        TEST_ASSERT_TRUE(r.ch[0].point_lo[k] <= r.ch[0].points[k]);
        TEST_ASSERT_TRUE(r.ch[0].point_hi[k] >= r.ch[0].points[k]);
    }
    /* the fitted freeplay force is the truth's shape: softer inside the gap than outside
     * (a force that raises the frequency grows with position, so its slope in the gap is the
     * smaller), with its kinks at the reported points */
    const aenl_nlt_channel_t *c = &r.ch[0];
    const double p0 = c->points[0];
    const double p1 = c->points[1];
    const double d = 0.1 * (p1 - p0);
    const double in = (aenl_nlt_law_force(c, AENL_NLT_FREEPLAY, p1 - d, 0) -
                       aenl_nlt_law_force(c, AENL_NLT_FREEPLAY, p0 + d, 0)) /
                      (p1 - p0 - 2.0 * d);
    const double right = (aenl_nlt_law_force(c, AENL_NLT_FREEPLAY, p1 + 2.0 * d, 0) -
                          aenl_nlt_law_force(c, AENL_NLT_FREEPLAY, p1 + d, 0)) /
                         d;
    const double left = (aenl_nlt_law_force(c, AENL_NLT_FREEPLAY, p0 - d, 0) -
                         aenl_nlt_law_force(c, AENL_NLT_FREEPLAY, p0 - 2.0 * d, 0)) /
                        d;
    TEST_ASSERT_TRUE(in < right);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9 * fabs(right) + 1e-12, right, left);
}

/* Pitch-rate kicks every 150 time units (rate 0.002-0.003), noise at SNR 10. */
static void kicks(aenl_sim_model_t *m, aenl_sim_run_t *run, uint64_t seed)
{
    (void)m;
    run->duration = 3000.0;
    run->kicks = 1;
    run->kick_dof = AENL_SIM_DOF_PITCH;
    run->kick_every = 150.0;
    run->kick_rate = 0.002;
    run->kick_rate_max = 0.003;
    run->kick_seed = seed;
    run->snr = 10.0;
    run->noise_seed = seed + 1u;
}

/* The test of y (n samples, 2 channels) with the record declared driven by impulses; frees y. */
static void test_impulsive_record(double *y, size_t n, aenl_nlt_result_t *r)
{
    aenl_nlt_opts_t o;
    aenl_nlt_opts_default(&o);
    o.impulsive = 1;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_nlt_run(y, n, 2, &o, r, &err), err.msg);
    free(y);
}

/* Kicks (the pitch rate jumps every 150 time units) are impulses: the filter restarts there.
 * Declared impulsive, the record is linear: the model fitted again with its kicks as state jumps
 * finds each of the 19 after the start once, and its noise no longer holds them. */
static void test_nlt_kicks_are_impulses(void)
{
    size_t n = 0;
    double *y = airfoil_run(NULL, kicks, 11u, &n);
    aenl_nlt_result_t r;
    test_record(y, n, &r);
    printf("kicked record: %zu impulses (20 kicks)\n", r.n_impulses);
    TEST_ASSERT_TRUE(r.n_impulses >= 5u);
    TEST_ASSERT_FALSE(r.jumps);
    y = airfoil_run(NULL, kicks, 11u, &n);
    test_impulsive_record(y, n, &r);
    printf("declared impulsive: %zu impulses, verdict %s, chi-square %.1f and %.1f on %.0f\n",
           r.n_impulses, aenl_nlt_class_name(r.verdict_class, r.undetermined), r.ch[0].stat,
           r.ch[1].stat, r.ch[0].dof);
    TEST_ASSERT_TRUE(r.jumps);
    TEST_ASSERT_TRUE(r.n_impulses >= 17u && r.n_impulses <= 21u);
    TEST_ASSERT_EQUAL_INT(-1, r.verdict);
}

/* A pitch freeplay under the same kicks, declared impulsive: the jumps do not take the law's
 * place, and pitch is nonlinear. */
static void test_nlt_kicked_freeplay_is_found_with_its_jumps(void)
{
    const aenl_sim_law_t law = pitch_freeplay();
    size_t n = 0;
    double *y = airfoil_run(&law, kicks, 12u, &n);
    aenl_nlt_result_t r;
    test_impulsive_record(y, n, &r);
    printf("kicked pitch freeplay, declared impulsive: %zu impulses, %s in %d, chi-square %.1f\n",
           r.n_impulses, aenl_nlt_class_name(r.verdict_class, r.undetermined), (int)r.verdict,
           r.verdict >= 0 ? r.ch[r.verdict].stat : 0.0);
    TEST_ASSERT_TRUE(r.jumps);
    TEST_ASSERT_EQUAL_INT(0, r.verdict);
}

/* A hardening cubic in pitch (R = a + 3e5 a^3, a in rad) under the same gusts: polynomial in
 * alpha, and hardening: the frequency rises with amplitude. */
static void test_nlt_hardening_cubic(void)
{
    AENL_PLAIN_BUILD_ONLY("another run of the test: left to the plain build");
    const aenl_sim_law_t law = pitch_cubic(3e5);
    size_t n = 0;
    double *y = airfoil_record(&law, 5151u, &n);
    aenl_nlt_result_t r;
    test_record(y, n, &r);
    TEST_ASSERT_EQUAL_INT(0, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, r.verdict_class);
    TEST_ASSERT_EQUAL_INT(1, r.ch[0].hardening);
    /* the fitted force, oriented as documented, has the truth's hardening shape: it grows
     * faster than in proportion on both sides (an odd cubic: f(2a) - 2 f(a) has the sign of
     * a) */
    TEST_ASSERT_TRUE(r.ch[0].laws_fitted);
    const double a = 0.01;
    const double up = aenl_nlt_law_force(&r.ch[0], AENL_NLT_POLYNOMIAL, 2.0 * a, 0) -
                      2.0 * aenl_nlt_law_force(&r.ch[0], AENL_NLT_POLYNOMIAL, a, 0);
    const double down = aenl_nlt_law_force(&r.ch[0], AENL_NLT_POLYNOMIAL, -2.0 * a, 0) -
                        2.0 * aenl_nlt_law_force(&r.ch[0], AENL_NLT_POLYNOMIAL, -a, 0);
    TEST_ASSERT_TRUE(up > 0.0);
    TEST_ASSERT_TRUE(down < 0.0);
    TEST_ASSERT_TRUE(isnan(aenl_nlt_law_force(&r.ch[1], AENL_NLT_POLYNOMIAL, a, 0)) ||
                     r.ch[1].laws_fitted);
}

/* A record without measurement noise is dithered (the fitted noise is nil), and the test then
 * works as on a measured record: the linear decay stays linear, the same decay with a hardening
 * pitch cubic is a polynomial in alpha. A record with noise is not dithered. The dither's seed
 * is fixed, so each run is deterministic; its statistics are printed to show the margins (the
 * level's limit, on 48 degrees of freedom at 0.005, is about 80). */
static void test_nlt_noise_free_records_dithered(void)
{
    const aenl_sim_law_t law = pitch_cubic(100.0);
    /* under the sanitizers the dithering's code runs once; every record in the plain build */
    const int n_records = AENL_TEST_IS_SANITIZED ? 1 : 2;
    for (int k = 0; k < n_records; ++k)
    {
        size_t n = 0;
        double *y = airfoil_run(k == 0 ? NULL : &law, noise_free_release, 0u, &n);
        aenl_nlt_result_t r;
        test_record(y, n, &r);
        printf("noise-free decay, %s: %zu channels dithered, verdict %s (chi-square %.1f, %.1f on "
               "%.0f)\n",
               k == 0 ? "linear" : "cubic", r.n_dithered,
               aenl_nlt_class_name(r.verdict_class, r.undetermined), r.ch[0].stat, r.ch[1].stat,
               r.ch[0].dof);
        TEST_ASSERT_EQUAL_size_t(2, r.n_dithered);
        TEST_ASSERT_TRUE(r.ch[0].dithered && r.ch[1].dithered);
        TEST_ASSERT_EQUAL_INT(k == 0 ? -1 : 0, r.verdict);
        TEST_ASSERT_EQUAL_INT(k == 0 ? AENL_CLASS_LINEAR : AENL_CLASS_POLYNOMIAL, r.verdict_class);
    }
    if (AENL_TEST_IS_SANITIZED)
    {
        return;
    }
    size_t n = 0;
    double *y = airfoil_record(NULL, 7001u, &n);
    aenl_nlt_result_t r;
    test_record(y, n, &r);
    TEST_ASSERT_EQUAL_size_t(0, r.n_dithered);
    TEST_ASSERT_FALSE(r.ch[0].dithered || r.ch[1].dithered);
}

/* A narrow-band motion at 5.5 samples per period (an AR(2) process with poles at radius rho and
 * angle w, its lag-one autocorrelation 2 rho cos(w) / (1 + rho^2) by Yule-Walker) seen in two
 * channels with noise at SNR 10: each channel's samples per period matches 2 pi / arccos of that
 * autocorrelation, and the table notes that the motion is sampled coarsely. */
static void test_nlt_samples_per_period(void)
{
    const size_t n = 6000;
    const double w = 2.0 * acos(-1.0) / 5.5;
    const double rho = 0.99;
    const double ref = 2.0 * acos(-1.0) / acos(2.0 * rho * cos(w) / (1.0 + rho * rho));
    double *y = (double *)malloc(2u * n * sizeof(double));
    TEST_ASSERT_NOT_NULL(y);
    uint64_t g = 77u;
    double x1 = 0.0;
    double x2 = 0.0;
    const double sd =
        sqrt((1.0 + rho * rho) / ((1.0 - rho * rho) * ((1.0 + rho * rho) * (1.0 + rho * rho) -
                                                       4.0 * rho * rho * cos(w) * cos(w))));
    for (size_t t = 0; t < n + 500u; ++t)
    {
        const double x = 2.0 * rho * cos(w) * x1 - rho * rho * x2 + test_gauss(&g);
        if (t >= 500u)
        {
            y[2u * (t - 500u)] = x + 0.1 * sd * test_gauss(&g);
            y[2u * (t - 500u) + 1u] = x1 + 0.1 * sd * test_gauss(&g);
        }
        x2 = x1;
        x1 = x;
    }
    aenl_nlt_result_t r;
    test_record(y, n, &r);
    printf("samples per period: %.3f, %.3f (AR(2): %.3f)\n", r.ch[0].samples_per_period,
           r.ch[1].samples_per_period, ref);
    TEST_ASSERT_DOUBLE_WITHIN(0.03 * ref, ref, r.ch[0].samples_per_period);
    TEST_ASSERT_DOUBLE_WITHIN(0.03 * ref, ref, r.ch[1].samples_per_period);
    char buf[4096] = {0};
    FILE *f = tmpfile();
    TEST_ASSERT_NOT_NULL(f);
    const char *names[2] = {"a", "b"};
    aenl_nlt_print_table(f, &r, names, NULL, "rec.csv");
    rewind(f);
    const size_t got = fread(buf, 1, sizeof(buf) - 1u, f);
    (void)fclose(f);
    buf[got] = '\0';
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(buf, "note: a moves with 5."), buf);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(buf, "note: b moves with 5."), buf);
}

static void test_nlt_bad_input(void)
{
    double y[400];
    aenl_nlt_opts_t o;
    aenl_nlt_opts_default(&o);
    aenl_nlt_result_t r;
    aenl_err_t err;
    for (size_t i = 0; i < 400; ++i)
    {
        y[i] = sin(0.3 * (double)i);
    }
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_nlt_run(y, 400, 1, &o, &r, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "too few"), err.msg);
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_nlt_run(NULL, 400, 1, &o, &r, &err));
    o.level = 1.5;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_nlt_run(y, 400, 1, &o, &r, &err));
    aenl_nlt_opts_default(&o);
    double *c = calloc(20000u, sizeof(double));
    TEST_ASSERT_NOT_NULL(c);
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_nlt_run(c, 20000u, 1, &o, &r, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "constant"), err.msg);
    c[7] = 1.0;
    c[100] = NAN;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_nlt_run(c, 20000u, 1, &o, &r, &err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err.msg, "sample 101 of channel 1 is missing"), err.msg);
    free(c);
}

/* ---- the command -------------------------------------------------------------------------- */

/* A freeplay record as CSV in the test folder; its path. */
static char g_freeplay_csv[600];

/* The freeplay record's CSV path (written by freeplay_csv). */
static const char *freeplay_csv_path(void)
{
    return g_freeplay_csv;
}

static const char *freeplay_csv(void)
{
    char *path = g_freeplay_csv;
    const aenl_sim_law_t law = pitch_freeplay();
    size_t n = 0;
    double *y = airfoil_record(&law, 4242u, &n);
    (void)snprintf(path, sizeof(g_freeplay_csv), "%s/nlt_freeplay.csv", AENL_TEST_TMP_DIR);
    FILE *f = fopen(path, "w");
    TEST_ASSERT_NOT_NULL(f);
    (void)fprintf(f, "t,alpha,xi\n");
    for (size_t k = 0; k < n; ++k)
    {
        (void)fprintf(f, "%.17g,%.17g,%.17g\n", 0.5 * (double)k, y[2u * k], y[2u * k + 1u]);
    }
    TEST_ASSERT_EQUAL_INT(0, fclose(f));
    free(y);
    return path;
}

/* The test's figures of the freeplay record (out: the table's run with --plot nlt_figs/sub):
 * the record of every channel, the laws of each channel that rejects, listed after the table;
 * a folder that cannot be made leaves nothing behind. */
static void check_test_figures(const char *out)
{
    const char *const want[] = {"nlt_figs/sub/nlt_freeplay_alpha_timeseries.png",
                                "nlt_figs/sub/nlt_freeplay_xi_timeseries.png",
                                "nlt_figs/sub/nlt_freeplay_alpha_law.png"};
    char path[700];
    for (size_t i = 0; i < 3; ++i)
    {
        struct stat sb;
        (void)snprintf(path, sizeof(path), "%s/%s", AENL_TEST_TMP_DIR, want[i]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, stat(path, &sb), path);
        TEST_ASSERT_TRUE_MESSAGE(sb.st_size > 1000, path);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(out, want[i]), out);
    }
    /* xi's laws are drawn when, and only when, its row in the table rejects linearity */
    const char *row = strstr(out, "\nxi ");
    TEST_ASSERT_NOT_NULL_MESSAGE(row, out);
    const char *eol = strchr(row + 1, '\n');
    const char *lin = strstr(row, " linear");
    const int xi_linear = lin != NULL && (eol == NULL || lin < eol);
    struct stat sb;
    (void)snprintf(path, sizeof(path), "%s/nlt_figs/sub/nlt_freeplay_xi_law.png",
                   AENL_TEST_TMP_DIR);
    TEST_ASSERT_EQUAL_INT_MESSAGE(xi_linear ? -1 : 0, stat(path, &sb), out);
    /* the folder is made before the test runs: one that cannot be made fails at once */
    const char *csv = freeplay_csv_path();
    const char *bad[] = {"identify", csv, "--plot", "/proc/nope/figs", NULL};
    cli_result_t r;
    cli_run(&r, bad);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, "/proc/nope"), r.err);
}

static void test_cli_identify_method_test_json_and_table(void)
{
    const char *csv = freeplay_csv();
    const char *json_args[] = {"identify", csv, "--method", "test", "--json", NULL};
    /* the table's run also draws the figures when gnuplot is there (one run of the test) */
    const int with_plot = system("command -v gnuplot >/dev/null 2>&1") == 0; /* NOLINT */
    const char *table_args[] = {
        "identify", csv, "--method", "test", with_plot ? "--plot" : NULL, "nlt_figs/sub", NULL};
    cli_result_t r;
    cli_run(&r, json_args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    cJSON *root = cJSON_Parse(r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, r.out);
    TEST_ASSERT_EQUAL_STRING("test", cJSON_GetObjectItem(root, "method")->valuestring);
    TEST_ASSERT_TRUE(cJSON_IsString(cJSON_GetObjectItem(root, "aenl_version")));
    const cJSON *v = cJSON_GetObjectItem(root, "verdict");
    TEST_ASSERT_EQUAL_STRING("freeplay", cJSON_GetObjectItem(v, "class")->valuestring);
    TEST_ASSERT_EQUAL_STRING("alpha", cJSON_GetObjectItem(v, "channel")->valuestring);
    TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(cJSON_GetObjectItem(v, "switch_points")));
    TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(cJSON_GetObjectItem(v, "switch_point_lo")));
    TEST_ASSERT_TRUE(cJSON_GetArraySize(cJSON_GetObjectItem(v, "candidates")) >= 1);
    const cJSON *chs = cJSON_GetObjectItem(root, "channels");
    TEST_ASSERT_EQUAL_INT(2, cJSON_GetArraySize(chs));
    const cJSON *c0 = cJSON_GetArrayItem(chs, 0);
    TEST_ASSERT_TRUE(cJSON_GetObjectItem(c0, "p_value")->valuedouble < 1e-6);
    TEST_ASSERT_TRUE(cJSON_IsTrue(cJSON_GetObjectItem(c0, "nonlinear")));
    cJSON_Delete(root);
    cli_run(&r, table_args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "verdict: freeplay in alpha"), r.out);
    if (with_plot)
    {
        check_test_figures(r.out);
    }
}

static void test_cli_identify_method_test_bad_usage(void)
{
    const char *csv = cli_file("nlt_small.csv", "t,a\n0,1\n1,2\n2,1\n3,0\n");
    const char *with_plot[] = {"identify", csv, "--method", "test", "--bandwidth", "0.1", NULL};
    const char *bad_method[] = {"identify", csv, "--method", "magic", NULL};
    const char *bad_level[] = {"identify", csv, "--method", "test", "--level", "2", NULL};
    const char *too_short[] = {"identify", csv, "--method", "test", NULL};
    const char *level_alone[] = {"identify", csv, "--method", "moments", "--level", "0.05", NULL};
    const char *impulsive[] = {"identify", csv, "--method", "moments", "--impulsive", NULL};
    const char *const *cases[] = {with_plot, bad_method,  bad_level,
                                  too_short, level_alone, impulsive};
    const char *const words[] = {"belong to the moments", "not a method",
                                 "not a test level",      "too few",
                                 "belongs to the test",   "--impulsive belongs to"};
    for (size_t i = 0; i < 6; ++i)
    {
        cli_expect_refused(cases[i], words[i]);
    }
}

/* The suite through the test: one short case runs, the table has the undetermined column and
 * the cost per value is printed; a wrong method or a combination it does not take is refused. */
static void test_cli_bench_identify_method_test(void)
{
    const char *run_args[] = {"bench", "identify", "--method", "test",      "--cases",
                              "1",     "--rows",   "2000",     "--verbose", NULL};
    const char *bad_method[] = {"bench", "identify", "--method", "magic", NULL};
    const char *with_model[] = {"bench", "identify", "--method", "test", "--model", NULL};
    const char *impulsive[] = {"bench",  "identify", "--method",    "test",      "--cases", "1",
                               "--rows", "2000",     "--impulsive", "--verbose", NULL};
    const char *impulsive_alone[] = {"bench", "identify", "--impulsive", NULL};
    cli_result_t r;
    cli_run(&r, run_args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "identify --method test (aenl_nlt_run)"), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "undet"), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "s per million values"), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "identification: "), r.out);
    TEST_ASSERT_NULL_MESSAGE(strstr(r.out, "failures\n  case"), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, " imp "), r.out);
    TEST_ASSERT_NULL_MESSAGE(strstr(r.out, " jumps"), r.out);
    cli_expect_refused(bad_method, "--method");
    cli_expect_refused(with_model, "does not combine");
    cli_expect_refused(impulsive_alone, "--impulsive needs --method test");
    /* the first case is a decay (a kick train): declared driven by impulses, it is tested on the
     * jump model (undeclared above, not), and said so */
    cli_run(&r, impulsive);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "declared driven by impulses"), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, " jumps"), r.out);
}

/* The level bench: two records run and the table is printed; a bad option is refused. */
static void test_cli_bench_null(void)
{
    const char *run_args[] = {"bench", "null", "--records", "2", "--verbose", NULL};
    const char *bad_level[] = {"bench", "null", "--level", "0.7", NULL};
    cli_result_t r;
    cli_run(&r, run_args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "free decay"), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "/2 ("), r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.out, "0 records failed"), r.out);
    cli_run(&r, bad_level);
    TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, r.err);
    TEST_ASSERT_EQUAL_size_t(0, r.n_out);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, "--level"), r.err);
}

/* ---- a measured force as a known input -------------------------------------------------------
 * The 3-DOF section shaken in pitch by a multisine (the project's example of a ground test),
 * the force written as a column: with the force given, the linear section is linear and the
 * flap freeplay (half gap 1 deg) is found in beta. Which law is named changes with the noise
 * draw (freeplay, a hysteresis loop whose inner pair is the gap, or undetermined between them):
 * a named gap law must put the gap's edges within 15 % of its width, an undetermined verdict must
 * hold freeplay among its candidates. */

#define MULTISINE_HEAD                                                                             \
    "[model]\ntype = section3dof\nvelocity = 12\n\n"                                               \
    "[excitation]\ntype = multisine\ndof = pitch\nrms_deg = 0.5\nf_min = 1\nf_max = 20\n"          \
    "period = 4\nseed = 3\n\n[run]\nduration = 8\ndt = 0.002\n\n[noise]\nsnr = 10\nseed = 7\n"

static const char *multisine_csv(const char *stem, int freeplay)
{
    static char csv[2][600];
    char *out = csv[freeplay ? 1 : 0];
    char ini_name[64];
    (void)snprintf(ini_name, sizeof(ini_name), "%s.ini", stem);
    (void)snprintf(out, 600, "%s.csv", stem);
    const char *ini =
        cli_file(ini_name, freeplay ? MULTISINE_HEAD
                               "\n[flap]\nlaw = freeplay\ndelta_deg = 2\nalpha_f_deg = -1\n"
                                    : MULTISINE_HEAD);
    const char *sim[] = {"simulate", ini, "-o", out, NULL};
    cli_result_t r;
    cli_run(&r, sim);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    return out;
}

/* --write-control: the flap-freeplay multisine's linear control is a record of the same
 * length with the time and force columns as recorded and the channels simulated from the
 * fitted linear model; identified with the force given it is linear. A folder that does not
 * exist is refused before the run, and the moments method does not take the option. */
static void test_cli_identify_writes_a_linear_control(void)
{
    const char *fp = multisine_csv("ms_freeplay", 1);
    const char *args[] = {"identify",        fp,           "--input", "f_pitch",
                          "--write-control", "ms_ctl.csv", NULL};
    cli_result_t r;
    cli_run(&r, args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    char rec_path[700];
    char ctl_path[700];
    (void)snprintf(rec_path, sizeof(rec_path), "%s/%s", AENL_TEST_TMP_DIR, fp);
    (void)snprintf(ctl_path, sizeof(ctl_path), "%s/ms_ctl.csv", AENL_TEST_TMP_DIR);
    aenl_table_t rec;
    aenl_table_t ctl;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(rec_path, &rec, &err), err.msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(ctl_path, &ctl, &err), err.msg);
    TEST_ASSERT_EQUAL_size_t(rec.n_rows, ctl.n_rows);
    TEST_ASSERT_EQUAL_size_t(rec.n_cols, ctl.n_cols);
    const char *const same[] = {"t", "f_pitch"};
    for (size_t k = 0; k < 2; ++k)
    {
        const long a = aenl_table_find(&rec, same[k]);
        const long b = aenl_table_find(&ctl, same[k]);
        TEST_ASSERT_TRUE_MESSAGE(a >= 0 && b >= 0, same[k]);
        TEST_ASSERT_EQUAL_MEMORY(rec.data + (size_t)a * rec.n_rows,
                                 ctl.data + (size_t)b * ctl.n_rows, rec.n_rows * sizeof(double));
    }
    const long ba = aenl_table_find(&rec, "beta");
    const long bb = aenl_table_find(&ctl, "beta");
    TEST_ASSERT_TRUE(ba >= 0 && bb >= 0);
    double diff = 0.0;
    double var = 0.0;
    double var_c = 0.0;
    for (size_t i = 0; i < rec.n_rows; ++i)
    {
        const double x = rec.data[(size_t)ba * rec.n_rows + i];
        const double y = ctl.data[(size_t)bb * ctl.n_rows + i];
        diff += (x - y) * (x - y);
        var += x * x;
        var_c += y * y;
    }
    /* simulated, not copied; of the record's size (its linear model's) */
    TEST_ASSERT_TRUE(diff > 0.01 * var);
    TEST_ASSERT_TRUE(var_c > 0.1 * var && var_c < 10.0 * var);
    aenl_table_free(&rec);
    aenl_table_free(&ctl);
    const char *again[] = {"identify", "ms_ctl.csv", "--input", "f_pitch", "--json", NULL};
    cli_run(&r, again);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    cJSON *root = cJSON_Parse(r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, r.out);
    printf("the flap freeplay's linear control, the force given: %s\n",
           cJSON_GetObjectItem(cJSON_GetObjectItem(root, "verdict"), "class")->valuestring);
    TEST_ASSERT_EQUAL_STRING(
        "linear", cJSON_GetObjectItem(cJSON_GetObjectItem(root, "verdict"), "class")->valuestring);
    cJSON_Delete(root);
    const char *no_dir[] = {"identify",          fp,  "--input", "f_pitch", "--write-control",
                            "no_such_dir/c.csv", NULL};
    cli_expect_refused(no_dir, "cannot create");
    const char *moments[] = {"identify",        fp,      "--method", "moments",
                             "--write-control", "c.csv", NULL};
    cli_expect_refused(moments, "--write-control");
    /* not standard output, which holds the result; not the record itself, which stays as it is */
    const char *to_stdout[] = {"identify", fp, "--input", "f_pitch", "--write-control", "-", NULL};
    cli_expect_refused(to_stdout, "not '-'");
    const char *onto_itself[] = {"identify", fp, "--input", "f_pitch", "--write-control", fp, NULL};
    cli_expect_refused(onto_itself, "the record itself");
    aenl_table_t rec2;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_table_read(rec_path, &rec2, &err), err.msg);
    const long b2 = aenl_table_find(&rec2, "beta");
    TEST_ASSERT_TRUE(b2 >= 0);
    double var2 = 0.0;
    for (size_t i = 0; i < rec2.n_rows; ++i)
    {
        const double x = rec2.data[(size_t)b2 * rec2.n_rows + i];
        var2 += x * x;
    }
    TEST_ASSERT_EQUAL_DOUBLE(var, var2);
    aenl_table_free(&rec2);
}

static void test_cli_identify_with_a_known_input(void)
{
    const char *lin = multisine_csv("ms_linear", 0);
    const char *fp = multisine_csv("ms_freeplay", 1);
    const char *lin_args[] = {"identify", lin,       "--method", "test",
                              "--input",  "f_pitch", "--json",   NULL};
    const char *fp_args[] = {"identify", fp,           "--method", "test", "--input=f_pitch",
                             "--json",   "--controls", "2",        NULL};
    cli_result_t r;
    cli_run(&r, lin_args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    cJSON *root = cJSON_Parse(r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, r.out);
    const cJSON *model = cJSON_GetObjectItem(root, "model");
    const cJSON *inputs = cJSON_GetObjectItem(model, "inputs");
    TEST_ASSERT_EQUAL_INT(1, cJSON_GetArraySize(inputs));
    TEST_ASSERT_EQUAL_STRING("f_pitch", cJSON_GetArrayItem(inputs, 0)->valuestring);
    TEST_ASSERT_EQUAL_INT(3, cJSON_GetArraySize(cJSON_GetObjectItem(root, "channels")));
    TEST_ASSERT_EQUAL_STRING(
        "linear", cJSON_GetObjectItem(cJSON_GetObjectItem(root, "verdict"), "class")->valuestring);
    cJSON_Delete(root);
    cli_run(&r, fp_args);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, r.status, r.err);
    root = cJSON_Parse(r.out);
    TEST_ASSERT_NOT_NULL_MESSAGE(root, r.out);
    const cJSON *v = cJSON_GetObjectItem(root, "verdict");
    const char *cls = cJSON_GetObjectItem(v, "class")->valuestring;
    TEST_ASSERT_EQUAL_STRING("beta", cJSON_GetObjectItem(v, "channel")->valuestring);
    /* linear controls (the fitted linear model driven by the same force): none reaches beta */
    TEST_ASSERT_EQUAL_INT(2, cJSON_GetObjectItem(root, "controls")->valueint);
    TEST_ASSERT_TRUE(cJSON_GetObjectItem(root, "controls_nonlinear")->valueint <= 2);
    const cJSON *beta = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "channels"), 2);
    TEST_ASSERT_EQUAL_INT(0, cJSON_GetObjectItem(beta, "control_exceed")->valueint);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 1.0 / 3.0,
                              cJSON_GetObjectItem(beta, "control_p")->valuedouble);
    if (strcmp(cls, "undetermined") == 0) /* then freeplay is among the candidates */
    {
        const cJSON *cands = cJSON_GetObjectItem(v, "candidates");
        int has_freeplay = 0;
        for (int i = 0; i < cJSON_GetArraySize(cands); ++i)
        {
            const cJSON *c = cJSON_GetObjectItem(cJSON_GetArrayItem(cands, i), "class");
            has_freeplay |= strcmp(c->valuestring, "freeplay") == 0;
        }
        printf("flap freeplay with the force given: undetermined, freeplay a candidate: %d\n",
               has_freeplay);
        TEST_ASSERT_TRUE(has_freeplay);
    }
    else
    {
        /* a named gap law: a freeplay's two points or a hysteresis loop's inner pair (its
         * points are -a2, -a1, a1, a2) are the gap's edges */
        TEST_ASSERT_TRUE_MESSAGE(strcmp(cls, "freeplay") == 0 || strcmp(cls, "hysteresis") == 0,
                                 cls);
        const cJSON *sp = cJSON_GetObjectItem(v, "switch_points");
        const int np = cJSON_GetArraySize(sp);
        TEST_ASSERT_TRUE(np == 2 || np == 4);
        const double lo = cJSON_GetArrayItem(sp, np == 2 ? 0 : 1)->valuedouble;
        const double hi = cJSON_GetArrayItem(sp, np == 2 ? 1 : 2)->valuedouble;
        printf("flap freeplay with the force given: %s, gap %.5f %.5f rad (truth +-0.01745)\n", cls,
               lo, hi);
        TEST_ASSERT_DOUBLE_WITHIN(0.15 * 2.0 * DEG, -DEG, lo);
        TEST_ASSERT_DOUBLE_WITHIN(0.15 * 2.0 * DEG, DEG, hi);
    }
    cJSON_Delete(root);
    /* usage: an unknown or time column, twice the same, the channel as input, the moments method */
    const char *unknown[] = {"identify", lin, "--method", "test", "--input", "force", NULL};
    const char *timecol[] = {"identify", lin, "--method", "test", "--input", "t", NULL};
    const char *twice[] = {"identify", lin, "--method", "test", "--input", "f_pitch,f_pitch", NULL};
    const char *as_channel[] = {"identify", lin,         "--method", "test", "--input",
                                "f_pitch",  "--channel", "f_pitch",  NULL};
    const char *moments[] = {"identify", lin, "--method", "moments", "--input", "f_pitch", NULL};
    const char *controls[] = {"identify", lin, "--bandwidth", "0.1", "--controls", "3", NULL};
    const char *bad_controls[] = {"identify", lin, "--method", "test", "--controls", "0", NULL};
    const char *empty[] = {"identify", lin, "--method", "test", "--input=", NULL};
    const char *trailing[] = {"identify", lin, "--method", "test", "--input", "f_pitch,", NULL};
    const char *const *cases[] = {unknown,  timecol,      twice, as_channel, moments,
                                  controls, bad_controls, empty, trailing};
    const char *const words[] = {"no such column",
                                 "time column",
                                 "named twice",
                                 "also an --input",
                                 "belongs to the test",
                                 "belongs to the test",
                                 "--controls",
                                 "not a list of column names",
                                 "not a list of column names"};
    for (size_t i = 0; i < 9; ++i)
    {
        cli_run(&r, cases[i]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(2, r.status, r.err);
        TEST_ASSERT_EQUAL_size_t(0, r.n_out);
        TEST_ASSERT_EQUAL_INT(1, r.err_lines);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(r.err, words[i]), r.err);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_chi2_sf_closed_forms);
    RUN_TEST(test_chi2_sf_critical_values);
    RUN_TEST(test_nlt_long_run_variance_brute_force);
    RUN_TEST(test_nlt_bad_input);
    RUN_TEST(test_nlt_kicks_are_impulses);
    RUN_TEST(test_nlt_kicked_freeplay_is_found_with_its_jumps);
    RUN_TEST(test_nlt_hardening_cubic);
    RUN_TEST(test_nlt_noise_free_records_dithered);
    RUN_TEST(test_nlt_samples_per_period);
    RUN_TEST(test_nlt_freeplay_named_with_its_gap);
    RUN_TEST(test_cli_identify_method_test_json_and_table);
    RUN_TEST(test_cli_identify_method_test_bad_usage);
    RUN_TEST(test_cli_identify_with_a_known_input);
    RUN_TEST(test_cli_identify_writes_a_linear_control);
    RUN_TEST(test_cli_bench_identify_method_test);
    RUN_TEST(test_cli_bench_null);
    RUN_TEST(test_nlt_controls_count_their_verdicts);
    RUN_TEST(test_nlt_linear_records_hold_the_level);
    return UNITY_END();
}
