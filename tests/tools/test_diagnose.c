/* SPDX-License-Identifier: MIT */
/**
 * @file test_diagnose.c
 * @brief aenl_diagnose: the signature pieces (Welch peak, noise estimate, distance properties,
 *        rejected records) and representative hidden-effect cases: measured data from a
 *        truth model with the effect (parameters and seeds drawn from a seed the diagnosis never
 *        sees, SNR 3), a baseline lacking it. Goals checked: effect and DOF named, parameters
 *        within 15 %, gap reduced at least 5-fold; null case: none, gap within 2x the noise
 *        floor. The full matrix is `aenl bench diagnose` (too slow for CI under the sanitizers).
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_tools/aenl_diagnose.h"
#include "aenl_diagnose_cases.h"
#include "aenl_evalsuite.h"
#include "aenl_tools/aenl_rng.h"
#include "aenl_diagnose_internal.h"
#include "aenl_test_sanitized.h"
#include "unity.h"

#define PI 3.14159265358979323846

/* The truth seed of the representative cases: never given to the diagnosis. */
#define TRUTH_SEED 101u

/* The sanitizer build runs the whole diagnosis once for each model (the 2-DOF airfoil's hidden
 * pitch freeplay through the command in test_cli_diagnose, the 3-DOF section's hidden hysteresis
 * here), and every unit test: each of those diagnoses fits every candidate effect, so the code
 * they walk is the same in the other end-to-end runs, whose accuracy the plain build checks
 * (minutes each under the sanitizers). */
#define PLAIN_BUILD_ONLY() AENL_PLAIN_BUILD_ONLY("another end-to-end run: left to the plain build")

void setUp(void)
{
}

void tearDown(void)
{
}

/* Mean over `trials` sets of n_run runs of M independent N(0,1) elements of the pair statistic
 * g^2 = sum of the M squared differences: rel_var's estimate of 2 / M (the relative variance of
 * chi-square with M degrees of freedom), the reference. */
static double mean_rel_var(size_t m, size_t n_run, unsigned trials, aenl_rng_t *g)
{
    double x[6][200];
    double acc = 0.0;
    for (unsigned t = 0; t < trials; ++t)
    {
        for (size_t i = 0; i < n_run; ++i)
        {
            for (size_t k = 0; k < m; ++k)
            {
                x[i][k] = aenl_rng_gauss(g);
            }
        }
        double s2 = 0.0, s4 = 0.0;
        size_t n_pair = 0;
        for (size_t i = 0; i < n_run; ++i)
        {
            for (size_t j = i + 1u; j < n_run; ++j)
            {
                double q = 0.0;
                for (size_t k = 0; k < m; ++k)
                {
                    q += (x[i][k] - x[j][k]) * (x[i][k] - x[j][k]);
                }
                s2 += q;
                s4 += q * q;
                n_pair++;
            }
        }
        acc += aenl_diagnose_rel_var(s2, s4, n_pair, n_run);
    }
    return acc / (double)trials;
}

/* The relative variance of the replicate pairs' squared gaps, which sets the scores' chi-square
 * units, against chi-square's 2 / M: the pairs of 4 and of 6 runs share runs (correlation 1/4),
 * and uncorrected their spread would be 20 % (4 runs) and 14 % (6 runs) short. */
static void test_rel_var_is_chi_square(void)
{
    aenl_rng_t g;
    aenl_rng_seed(&g, 11u);
    const double r4 = mean_rel_var(200u, 4u, 4000u, &g) / (2.0 / 200.0);
    const double r6 = mean_rel_var(200u, 6u, 2000u, &g) / (2.0 / 200.0);
    const double r4_small = mean_rel_var(20u, 4u, 4000u, &g) / (2.0 / 20.0);
    printf("rel_var / (2/M): M 200, 4 runs %.3f; 6 runs %.3f; M 20, 4 runs %.3f\n", r4, r6,
           r4_small);
    TEST_ASSERT_DOUBLE_WITHIN(0.06, 1.0, r4);
    TEST_ASSERT_DOUBLE_WITHIN(0.06, 1.0, r6);
    TEST_ASSERT_DOUBLE_WITHIN(0.15, 1.0, r4_small);
    /* nothing to measure: one pair, or every run alike */
    TEST_ASSERT_TRUE(isnan(aenl_diagnose_rel_var(1.0, 1.0, 1u, 2u)));
    TEST_ASSERT_TRUE(isnan(aenl_diagnose_rel_var(0.0, 0.0, 6u, 4u)));
}

static void test_welch_peak_at_sinusoid(void)
{
    const size_t n = 8192, seg = 1024;
    double *x = malloc(n * sizeof(double));
    double *p = malloc((seg / 2u + 1u) * sizeof(double));
    TEST_ASSERT_NOT_NULL(x);
    TEST_ASSERT_NOT_NULL(p);
    for (size_t i = 0; i < n; ++i)
    {
        x[i] = 3.0 + sin(2.0 * PI * 0.05 * (double)i);
    }
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_welch(x, n, seg, p, &err));
    size_t best = 1;
    double total = 0.0;
    for (size_t k = 1; k <= seg / 2u; ++k)
    {
        best = p[k] > p[best] ? k : best;
        total += p[k] / (double)seg;
    }
    TEST_ASSERT_TRUE(best == 51u || best == 52u); /* 0.05 * 1024 = 51.2 */
    TEST_ASSERT_DOUBLE_WITHIN(0.05, 0.5, total);  /* Parseval: the variance of the sine */
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_diagnose_welch(x, n, 1000, p, &err)); /* not 2^k */
    free(x);
    free(p);
}

/* The periodogram peak against a brute-force maximisation of the same windowed power over a
 * fine frequency grid, on a sinusoid in noise at SNR 3 (std ratio). */
static void test_peak_freq_matches_brute_force(void)
{
    const size_t n = 6000;
    const double f0 = 0.0123456;
    double *x = malloc(n * sizeof(double));
    TEST_ASSERT_NOT_NULL(x);
    aenl_rng_t g;
    aenl_rng_seed(&g, 7u);
    const double noise = 1.0 / (sqrt(2.0) * 3.0);
    double mean = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        x[i] = 0.4 + cos(2.0 * PI * f0 * (double)i + 0.3) + noise * aenl_rng_gauss(&g);
        mean += x[i] / (double)n;
    }
    aenl_err_t err;
    aenl_err_clear(&err);
    double f = 0.0;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_peak_freq(x, n, &f, &err));
    double f_best = 0.0, p_best = -1.0;
    for (long k = -20000; k <= 20000; ++k)
    {
        const double ft = f0 + 1e-8 * (double)k;
        double re = 0.0, im = 0.0;
        for (size_t i = 0; i < n; ++i)
        {
            const double w = 0.5 - 0.5 * cos(2.0 * PI * ((double)i + 0.5) / (double)n);
            re += w * (x[i] - mean) * cos(2.0 * PI * ft * (double)i);
            im -= w * (x[i] - mean) * sin(2.0 * PI * ft * (double)i);
        }
        if (re * re + im * im > p_best)
        {
            p_best = re * re + im * im;
            f_best = ft;
        }
    }
    /* Within 1 % of a padded bin (1/32768) of the brute-force peak. And near the truth: the
     * Cramer-Rao sd of a sinusoid's frequency here is sqrt(12 sigma^2 / (A^2 N^3)) / (2 pi) =
     * 2.8e-7 (the Hann window widens it); 1.5e-6 is a seven-hundredth of a 1024-point bin. */
    TEST_ASSERT_DOUBLE_WITHIN(3e-7, f_best, f);
    TEST_ASSERT_DOUBLE_WITHIN(1.5e-6, f0, f);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_diagnose_peak_freq(x, 8, &f, &err));
    free(x);
}

static void test_chan_setup_noise_and_period(void)
{
    const size_t n = 20000;
    double *x = malloc(n * sizeof(double));
    TEST_ASSERT_NOT_NULL(x);
    aenl_rng_t g;
    aenl_rng_seed(&g, 5);
    for (size_t i = 0; i < n; ++i)
    {
        x[i] = sin(2.0 * PI * (double)i / 100.0) + 0.2 * aenl_rng_gauss(&g);
    }
    aenl_diagnose_chan_t c;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_chan_setup(x, n, &c, &err));
    TEST_ASSERT_DOUBLE_WITHIN(0.02, 0.2, c.noise_sd);
    TEST_ASSERT_DOUBLE_WITHIN(5.0, 100.0, c.period);
    TEST_ASSERT_TRUE(c.lags[0] < c.lags[1] && c.lags[1] < c.lags[2]);
    TEST_ASSERT_TRUE(c.n_bands >= 5u);
    /* A signature against itself: zero gap; against a louder copy: a positive amplitude gap. */
    aenl_diagnose_sig_t a, b;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_signature(x, n, &c, &a, NULL, &err));
    TEST_ASSERT_TRUE(a.valid);
    double fam[AENL_DIAGNOSE_N_FAMILY];
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0, aenl_diagnose_distance(&c, &a, &a, fam));
    for (size_t i = 0; i < n; ++i)
    {
        x[i] *= 1.5;
    }
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_signature(x, n, &c, &b, NULL, &err));
    TEST_ASSERT_TRUE(aenl_diagnose_distance(&c, &a, &b, fam) > 0.1);
    TEST_ASSERT_TRUE(fam[AENL_DIAGNOSE_AMPLITUDE] > 0.2);
    /* A diverged record: invalid signature, capped distance. */
    x[n / 2u] = (double)NAN;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_signature(x, n, &c, &b, NULL, &err));
    TEST_ASSERT_FALSE(b.valid);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 10.0, aenl_diagnose_distance(&c, &a, &b, fam));
    /* A simulated record at rest (a model without noise that never moves): invalid, not an
     * error (its curves cannot be formed; the LCO bench's noise-free cases 122 and 213 meet
     * such records). */
    for (size_t i = 0; i < n; ++i)
    {
        x[i] = 0.0;
    }
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_signature(x, n, &c, &b, NULL, &err));
    TEST_ASSERT_FALSE(b.valid);
    free(x);
}

static void test_chan_setup_rejects(void)
{
    double x[1000];
    aenl_diagnose_chan_t c;
    aenl_err_t err;
    for (size_t i = 0; i < 1000u; ++i)
    {
        x[i] = 2.0;
    }
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_diagnose_chan_setup(x, 1000, &c, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "constant"));
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_diagnose_chan_setup(x, 100, &c, &err));
    x[10] = (double)NAN;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_diagnose_chan_setup(x, 1000, &c, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "missing"));
}

static void test_run_rejects_wrong_step_and_channels(void)
{
    aenl_diagnose_case_t c;
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_make(0, TRUTH_SEED, 0, &c, &err));
    aenl_table_t t;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_measure(&c, &t, &err));
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    aenl_diagnose_result_t r;
    aenl_sim_run_t run = c.base_run;
    run.dt = 0.25;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_diagnose_run(&t, &c.base, &run, &o, &r, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "dt"));
    aenl_sim_model_t m3;
    aenl_sim_model_default(&m3, AENL_SIM_SECTION3DOF);
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_diagnose_run(&t, &m3, &c.base_run, &o, &r, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "no column 'h'"));
    o.n_replicates = 1;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_diagnose_run(&t, &c.base, &c.base_run, &o, &r, &err));
    aenl_table_free(&t);
}

/* The named law against its rival on the summaries (aenl_diagnose_result_t.rival), sought only
 * where the gap accepts the best law: another effect or DOF the gap's scores could not tell
 * from the best (within one penalty), and the named one the least chi2 + penalty x
 * parameters of the two unless the rival's fit was rejected. */
static void check_rival(const aenl_diagnose_result_t *r, double penalty)
{
    if (r->rival >= r->n_cand)
    {
        TEST_ASSERT_FALSE(r->by_summaries);
        return;
    }
    TEST_ASSERT_TRUE(r->gap_accepts);
    const aenl_diagnose_cand_t *c = &r->cand[r->chosen], *v = &r->cand[r->rival];
    double least = HUGE_VAL;
    for (size_t i = 0; i < r->n_cand; ++i)
    {
        least = fmin(least, r->cand[i].score);
    }
    printf("  rival %s %s: score %.4g (named %.4g, least %.4g); summary chi2 %.4g for %zu%s vs "
           "the named's %.4g%s\n",
           aenl_diagnose_effect_name(v->effect), aenl_diagnose_dof_name(v->dof), v->score, c->score,
           least, r->rival_chi2, r->rival_chi2_dof, r->rival_rejected ? " rejected" : "", r->chi2,
           r->by_summaries ? ", named by the summaries" : "");
    TEST_ASSERT_TRUE(v->effect != c->effect || v->dof != c->dof);
    TEST_ASSERT_TRUE(c->score - least < penalty && v->score - least < penalty);
    TEST_ASSERT_TRUE(r->by_summaries == (c->score > least));
    if (r->by_summaries || (!r->rival_rejected && isfinite(r->rival_chi2)))
    {
        TEST_ASSERT_FALSE(r->summary_rejected);
        TEST_ASSERT_TRUE(r->rival_rejected ||
                         r->chi2 + penalty * c->n_params <= r->rival_chi2 + penalty * v->n_params);
    }
}

/* Diagnose the named case and check the goals (docs/diagnose.md); the JSON and the INI round
 * trip too.
 * other_sim: the truth is measured with a simulator the diagnosis does not share (naive RK4, no
 * event location; Dryden gusts where the baseline assumes first-order ones). */
static void check_case(const char *name, int other_sim)
{
    aenl_diagnose_case_t c;
    memset(&c, 0, sizeof(c));
    aenl_err_t err;
    aenl_err_clear(&err);
    size_t k = 0;
    for (; k < aenl_diagnose_n_cases(); ++k)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_make(k, TRUTH_SEED, 0, &c, &err));
        if (strcmp(c.name, name) == 0)
        {
            break;
        }
    }
    TEST_ASSERT_TRUE_MESSAGE(k < aenl_diagnose_n_cases(), name);
    if (other_sim)
    {
        c.truth_rk4_steps = (unsigned)AENL_EVAL_RK4_STEPS; /* as bench identify --rk4 */
        c.truth_run.turb_spectrum = AENL_SIM_GUST_DRYDEN;
        TEST_ASSERT_EQUAL_INT(AENL_SIM_GUST_FIRST_ORDER, c.base_run.turb_spectrum);
    }
    aenl_table_t t;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_case_measure(&c, &t, &err), err.msg);
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    aenl_diagnose_result_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        AENL_OK, aenl_diagnose_run(&t, &c.base, &c.base_run, &o, &r, &err), err.msg);
    aenl_table_free(&t);
    const size_t nc = r.n_channels;
    printf("%s: named %s %s, gap %.3g -> %.3g, floor %.3g, %u simulations, %.1f s\n", name,
           aenl_diagnose_effect_name(r.effect), aenl_diagnose_dof_name(r.dof), r.gap_before[nc],
           r.gap_after[nc], r.floor_before[nc], r.n_sims, r.seconds);
    TEST_ASSERT_EQUAL_STRING_MESSAGE(aenl_diagnose_effect_name(c.effect),
                                     aenl_diagnose_effect_name(r.effect), name);
    if (c.effect == AENL_DIAGNOSE_NONE)
    {
        TEST_ASSERT_TRUE_MESSAGE(r.gap_before[nc] <= 2.0 * r.floor_before[nc], name);
        TEST_ASSERT_EQUAL_size_t(0, r.n_dis);
        /* and the summaries' test of the baseline, run only then, accepts it */
        TEST_ASSERT_EQUAL_UINT(o.summary_records, r.base_test.n_rep);
        printf("  summary test of the baseline: distance^2 %.3g for %zu, p %.3g\n", r.base_test.d2,
               r.base_test.d, r.base_test.p);
        TEST_ASSERT_TRUE_MESSAGE(r.base_test.p > AENL_DIAGNOSE_SUMTEST_LEVEL, name);
    }
    else
    {
        TEST_ASSERT_EQUAL_STRING_MESSAGE(aenl_diagnose_dof_name(c.dof),
                                         aenl_diagnose_dof_name(r.dof), name);
        double rel[AENL_DIAGNOSE_MAX_PAR];
        const size_t np =
            aenl_diagnose_param_errors(c.effect, &c.truth.law[c.dof], &r.updated.law[c.dof], rel);
        TEST_ASSERT_TRUE(np >= 1u);
        /* The summary fit's standard errors cover the errors (at 5 sd: a check that they are
         * not too small, not a coverage test). */
        TEST_ASSERT_EQUAL_size_t(np, r.n_param_sd);
        TEST_ASSERT_TRUE(r.chi2_dof > 0u && r.chi2 <= r.chi2_start);
        for (size_t i = 0; i < np; ++i)
        {
            const double sd_rel =
                r.param_sd[i] / fabs(aenl_diagnose_param_get(&c.truth.law[c.dof], c.effect, i));
            printf("  parameter %zu: relative error %.2f %%, standard error %.2f %%\n", i,
                   100.0 * rel[i], 100.0 * sd_rel);
            TEST_ASSERT_TRUE_MESSAGE(rel[i] <= 0.15, name);
            TEST_ASSERT_TRUE_MESSAGE(sd_rel > 0.0 && rel[i] <= 5.0 * sd_rel, name);
        }
        TEST_ASSERT_TRUE_MESSAGE(r.gap_before[nc] >= 5.0 * r.gap_after[nc], name);
        check_rival(&r, o.penalty);
        TEST_ASSERT_TRUE(r.n_dis >= 1u);
        TEST_ASSERT_TRUE(r.dis[0].significance > o.report_ratio);
    }
    /* JSON: exactly the documented keys. */
    char *js = aenl_diagnose_json(&r, NULL);
    TEST_ASSERT_NOT_NULL(js);
    cJSON *root = cJSON_Parse(js);
    TEST_ASSERT_NOT_NULL(root);
    TEST_ASSERT_TRUE(cJSON_IsArray(cJSON_GetObjectItemCaseSensitive(root, "disagreement")));
    const cJSON *me = cJSON_GetObjectItemCaseSensitive(root, "missing_effect");
    TEST_ASSERT_EQUAL_STRING(aenl_diagnose_effect_name(c.effect),
                             cJSON_GetObjectItemCaseSensitive(me, "type")->valuestring);
    TEST_ASSERT_TRUE(cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(me, "params")));
    TEST_ASSERT_TRUE(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(root, "gap_before")));
    TEST_ASSERT_TRUE(cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(root, "gap_after")));
    TEST_ASSERT_TRUE(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(root, "updated_model")));
    TEST_ASSERT_EQUAL_STRING("aenl-diagnose/1",
                             cJSON_GetObjectItemCaseSensitive(root, "schema")->valuestring);
    TEST_ASSERT_EQUAL_INT(7, cJSON_GetArraySize(root));
    cJSON_Delete(root);
    free(js);
    /* The updated INI loads and holds the named law. */
    char path[512];
    (void)snprintf(path, sizeof(path), "%s/%s.ini", AENL_TEST_TMP_DIR, name);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_write_ini(&r, "test", path, &err));
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_load_ini(path, &m, &run, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(r.updated.law[c.dof].kind, m.law[c.dof].kind);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, r.updated.law[c.dof].delta, m.law[c.dof].delta);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, r.run.dt, run.dt);
    TEST_ASSERT_TRUE(run.snr > 1.0 && run.snr < 10.0); /* the record's SNR 3, estimated */
    aenl_diagnose_result_free(&r);
}

static void test_hidden_freeplay_airfoil2dof(void)
{
    PLAIN_BUILD_ONLY();
    check_case("a2_freeplay_pitch", 0);
}

/* The same hidden freeplay, measured by another integrator under another gust spectrum. */
static void test_hidden_freeplay_other_simulator(void)
{
    PLAIN_BUILD_ONLY();
    check_case("a2_freeplay_pitch", 1);
}

static void test_hidden_polynomial_airfoil2dof(void)
{
    PLAIN_BUILD_ONLY();
    check_case("a2_polynomial_pitch", 0);
}

static void test_hidden_preload_airfoil2dof(void)
{
    PLAIN_BUILD_ONLY();
    check_case("a2_preload_pitch", 0);
}

static void test_hidden_hysteresis_section3dof(void)
{
    check_case("s3_hysteresis_flap", 0);
}

static void test_null_section3dof(void)
{
    PLAIN_BUILD_ONLY();
    check_case("s3_none", 0);
}

/* The information floor tells a determined parameter from a ridge: the 2-DOF hysteresis loop
 * in a limit cycle much larger than the loop fixes delta, while alpha_f and M0 moving together
 * leave amplitude and waveform almost unchanged (docs/diagnose.md, "Hidden-effect results"); the
 * freeplay gap and offset are both fixed. */
/* A softening spring that stiffens again, R = x - s x^3 + q x^5: the evaluation suite's case 152
 * (seed 1; 2-DOF pitch limit cycle at 1.03 of the flutter speed, SNR 3), its first 12 000 rows,
 * against the suite's own model with the pitch law made linear. A cubic alone cannot follow such
 * a law without running away; the quintic candidate is named, with both coefficients near the
 * truth's, and it closes the gap much further than the best cubic. */
static void test_hidden_softening_quintic(void)
{
    PLAIN_BUILD_ONLY();
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_eval_case_t c;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_eval_case_make(1u, 152u, &c, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_EVAL_SOFTENING, c.stratum.variant);
    TEST_ASSERT_EQUAL_INT(AENL_EVAL_LCO, c.stratum.regime);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_DOF_PITCH, c.stratum.dof);
    const aenl_sim_law_t *truth = &c.model.law[AENL_SIM_DOF_PITCH];
    TEST_ASSERT_EQUAL_INT(AENL_SIM_LAW_POLYNOMIAL, truth->kind);
    TEST_ASSERT_TRUE(truth->n_coeffs >= 5u && truth->coeffs[2] < 0.0 && truth->coeffs[4] > 0.0);
    const size_t n = 12000u;
    TEST_ASSERT_TRUE(c.n_samples >= n);
    const char *names[] = {"t", c.names[0], c.names[1]};
    aenl_table_t t;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_table_alloc(&t, n, 3u, names, &err));
    for (size_t i = 0; i < n; ++i)
    {
        t.data[i] = (double)i * c.run.dt;
        t.data[n + i] = c.cols[0][i];
        t.data[2u * n + i] = c.cols[1][i];
    }
    aenl_sim_model_t base = c.model;
    memset(&base.law[AENL_SIM_DOF_PITCH], 0, sizeof(base.law[AENL_SIM_DOF_PITCH]));
    base.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_LINEAR;
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    aenl_diagnose_result_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &base, &c.run, &o, &r, &err),
                                  err.msg);
    aenl_table_free(&t);
    const aenl_sim_law_t *fit = &r.updated.law[AENL_SIM_DOF_PITCH];
    double cubic_gap = HUGE_VAL;
    for (size_t i = 0; i < r.n_cand; ++i)
    {
        if (r.cand[i].effect == AENL_DIAGNOSE_POLYNOMIAL && r.cand[i].n_params == 1u &&
            r.cand[i].dof == AENL_SIM_DOF_PITCH)
        {
            cubic_gap = r.cand[i].gap;
        }
    }
    const size_t nc = r.n_channels;
    printf("softening (x^5) pitch LCO: named %s %s, c3 %.5g (truth %.5g), c5 %.5g (truth %.5g), "
           "gap %.3g -> %.3g, best cubic %.3g, %.1f s\n",
           aenl_diagnose_effect_name(r.effect), aenl_diagnose_dof_name(r.dof), fit->coeffs[2],
           truth->coeffs[2], fit->coeffs[4], truth->coeffs[4], r.gap_before[nc], r.gap_after[nc],
           cubic_gap, r.seconds);
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_POLYNOMIAL, r.effect);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_DOF_PITCH, r.dof);
    TEST_ASSERT_EQUAL_size_t(2, aenl_diagnose_law_n_params(r.effect, fit));
    TEST_ASSERT_DOUBLE_WITHIN(0.1 * fabs(truth->coeffs[2]), truth->coeffs[2], fit->coeffs[2]);
    TEST_ASSERT_DOUBLE_WITHIN(0.1 * truth->coeffs[4], truth->coeffs[4], fit->coeffs[4]);
    TEST_ASSERT_TRUE(r.gap_after[nc] < 0.2 * cubic_gap);
    aenl_diagnose_result_free(&r);
    aenl_eval_case_free(&c);
}

/* The representative 2-DOF null case (a linear gust record) of aenl_diagnose_case_make. */
static void a2_none(aenl_diagnose_case_t *c)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_make(4, TRUTH_SEED, 0, c, &err));
    TEST_ASSERT_EQUAL_STRING("a2_none", c->name);
}

/* A noise-free record of the 2-DOF null case's model m (its pitch and plunge) under run, n
 * samples (run's duration set), into t; the caller frees t. */
static void a2_record(const aenl_sim_model_t *m, aenl_sim_run_t *run, size_t n, aenl_table_t *t)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    run->snr = 0.0;
    run->duration = (double)(n - 1u) * run->dt;
    aenl_sim_result_t y;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(m, run, &y, &err), err.msg);
    TEST_ASSERT_TRUE(y.n_samples >= n);
    const char *names[] = {"t", "alpha", "xi"};
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_table_alloc(t, n, 3u, names, &err));
    for (size_t i = 0; i < n; ++i)
    {
        t->data[i] = (double)i * run->dt;
        t->data[n + i] = y.y[i];
        t->data[2u * n + i] = y.y[y.n_samples + i];
    }
    aenl_sim_result_free(&y);
}

/* A noise-free free decay of the 2-DOF null case's model (no turbulence, pitch released from
 * 0.02), n samples, into t; the model and run that made it into m and run. */
static void a2_decay(aenl_sim_model_t *m, aenl_sim_run_t *run, size_t n, aenl_table_t *t)
{
    aenl_diagnose_case_t c;
    a2_none(&c);
    *run = c.base_run;
    run->turb_intensity = 0.0;
    *m = c.base;
    m->x0[AENL_SIM_DOF_PITCH] = 0.02;
    a2_record(m, run, n, t);
}

/* The simulations' measurement noise is what the record's high-frequency scale has beyond the
 * baseline's own response; the reference is the noise actually added. The 2-DOF null case's gust
 * record sampled 5 times a pitch period, where the response's own third differences are large:
 * noise-free, the diagnosis against the model that made it adds no noise and finds no gap at all;
 * with white noise of a known std added, it finds that std within 10 % while the record's raw
 * scale is over 20 % above it. */
static void test_noise_beyond_the_baseline(void)
{
    PLAIN_BUILD_ONLY();
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_diagnose_case_t c;
    a2_none(&c);
    const size_t n = 4000u;
    aenl_sim_run_t run = c.base_run;
    run.dt = 2.0 * PI / 5.0; /* the pitch frequency is 1 in the model's time unit */
    aenl_table_t t;
    a2_record(&c.base, &run, n, &t);
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    o.summary_records = 0;
    o.n_replicates = 2;
    o.n_refine = 0;
    aenl_diagnose_result_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &c.base, &run, &o, &r, &err),
                                  err.msg);
    const double raw = r.chan[0].noise_record;
    printf("noise-free, sampled 5 times a period: alpha's raw scale %.3g, noise %.3g, gap %.3g\n",
           raw, r.chan[0].noise_sd, r.gap_before[r.n_channels]);
    TEST_ASSERT_TRUE(raw > 0.0);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, r.chan[0].noise_sd);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, r.chan[1].noise_sd);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, r.gap_before[r.n_channels]);
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_NONE, r.effect);
    aenl_diagnose_result_free(&r);
    /* white noise as large as the response's own scale */
    aenl_rng_t g;
    aenl_rng_seed(&g, 99u);
    const double sigma = raw;
    for (size_t i = 0; i < n; ++i)
    {
        t.data[n + i] += sigma * aenl_rng_gauss(&g);
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &c.base, &run, &o, &r, &err),
                                  err.msg);
    printf("  with noise of std %.3g: raw scale %.3g, noise %.3g\n", sigma, r.chan[0].noise_record,
           r.chan[0].noise_sd);
    TEST_ASSERT_TRUE(r.chan[0].noise_record > 1.2 * sigma);
    TEST_ASSERT_DOUBLE_WITHIN(0.1 * sigma, sigma, r.chan[0].noise_sd);
    aenl_diagnose_result_free(&r);
    aenl_table_free(&t);
}

/* What a progress receiver heard: every report's done within its total, the total the same
 * throughout, done never going back, and the last report the whole. */
typedef struct
{
    size_t calls, last, total;
    int ok;
} heard_t;

static void hear(void *ctx, size_t done, size_t total)
{
    heard_t *h = (heard_t *)ctx;
    h->ok = h->ok && done <= total && done >= h->last && (h->calls == 0u || total == h->total);
    h->calls++;
    h->last = done;
    h->total = total;
}

/* A long free decay whose release is many of its record's stds out (here more than 20, where
 * the runaway bound once sat, and a release that far was taken for a divergence: gap at the
 * cap 10): against the model that made it, every run stays bounded and the baseline
 * reproduces the record. */
static void test_long_decay_is_not_a_runaway(void)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_table_t t;
    aenl_diagnose_case_t c;
    a2_none(&c);
    run = c.base_run;
    run.turb_intensity = 0.0;
    m = c.base;
    m.x0[AENL_SIM_DOF_PITCH] = 0.02;
    m.airfoil.zeta_alpha = 0.02;
    m.airfoil.zeta_xi = 0.02;
    a2_record(&m, &run, 12000u, &t);
    const double *alpha = aenl_table_col(&t, 1u);
    double mean = 0.0, var = 0.0;
    for (size_t i = 0; i < t.n_rows; ++i)
    {
        mean += alpha[i];
    }
    mean /= (double)t.n_rows;
    for (size_t i = 0; i < t.n_rows; ++i)
    {
        var += (alpha[i] - mean) * (alpha[i] - mean);
    }
    const double ratio = fabs(alpha[0] - mean) / sqrt(var / (double)t.n_rows);
    char msg[96];
    (void)snprintf(msg, sizeof(msg), "the release is %.3g stds out, not 20", ratio);
    TEST_ASSERT_TRUE_MESSAGE(ratio > 20.0, msg);
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    o.n_replicates = 2;
    o.n_refine = 0;
    o.summary_records = 0;
    aenl_diagnose_result_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &m, &run, &o, &r, &err), err.msg);
    TEST_ASSERT_TRUE(r.sig_base[0].valid && r.sig_base[1].valid);
    TEST_ASSERT_TRUE(r.gap_before[r.n_channels] < 0.01);
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_NONE, r.effect);
    aenl_diagnose_result_free(&r);
    aenl_table_free(&t);
}

/* A noise-free free decay of a softening spring that stiffens again (plunge, R = x - 20 x^3 +
 * 400 x^5), released 11 of its record's stds out, against the linear baseline without a
 * release: the release is fitted, and the quintic is named with both coefficients within 15 %.
 * Scaled by the record's std instead of its reach, every polynomial candidate's grid is far too
 * strong at the release (a cubic alone is named, its c3 half the truth's). */
static void test_decay_quintic_released_far_out(void)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    aenl_sim_set_velocity(&m, 4.0);
    m.airfoil.zeta_alpha = 0.01;
    m.airfoil.zeta_xi = 0.01;
    aenl_sim_run_default(&run, AENL_SIM_AIRFOIL2DOF);
    run.dt = 0.5;
    aenl_sim_model_t base = m;
    aenl_sim_law_t *law = &m.law[AENL_SIM_DOF_PLUNGE];
    law->kind = AENL_SIM_LAW_POLYNOMIAL;
    law->n_coeffs = 5u;
    law->coeffs[0] = 1.0;
    law->coeffs[2] = -20.0;
    law->coeffs[4] = 400.0;
    m.x0[AENL_SIM_DOF_PLUNGE] = 0.2;
    aenl_table_t t;
    a2_record(&m, &run, 6000u, &t);
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    aenl_diagnose_result_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &base, &run, &o, &r, &err),
                                  err.msg);
    TEST_ASSERT_TRUE(r.initial.estimated);
    TEST_ASSERT_DOUBLE_WITHIN(0.002, 0.2, r.updated.x0[AENL_SIM_DOF_PLUNGE]);
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_POLYNOMIAL, r.effect);
    TEST_ASSERT_EQUAL_INT(AENL_SIM_DOF_PLUNGE, r.dof);
    const aenl_sim_law_t *got = &r.updated.law[AENL_SIM_DOF_PLUNGE];
    TEST_ASSERT_EQUAL_size_t(5u, got->n_coeffs);
    TEST_ASSERT_DOUBLE_WITHIN(0.15 * 20.0, -20.0, got->coeffs[2]);
    TEST_ASSERT_DOUBLE_WITHIN(0.15 * 400.0, 400.0, got->coeffs[4]);
    aenl_diagnose_result_free(&r);
    aenl_table_free(&t);
}

/* A noise-free free decay against the model that made it: every run of the baseline is alike
 * (no turbulence, no noise), so its floor is 0; the summaries have nothing random to rank and
 * their test does not run; the baseline reproduces the record exactly and agrees all the same
 * (else identify --model would fall back to the record's own verdict). The progress receiver
 * hears every stage of the search, the last one the whole. */
static void test_exact_baseline_agrees(void)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_table_t t;
    a2_decay(&m, &run, 3000u, &t);
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    o.n_replicates = 2;
    o.n_refine = 0;
    heard_t heard = {0, 0, 0, 1};
    const aenl_progress_t progress = {hear, &heard};
    o.progress = &progress;
    aenl_diagnose_result_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &m, &run, &o, &r, &err), err.msg);
    /* every stage reported, the last one the whole search */
    TEST_ASSERT_TRUE(heard.ok);
    TEST_ASSERT_TRUE(heard.calls >= 3u);
    TEST_ASSERT_EQUAL_size_t(heard.total, heard.last);
    TEST_ASSERT_EQUAL_size_t(heard.calls, heard.total);
    o.progress = NULL;
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_NONE, r.effect);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, r.floor_before[r.n_channels]);
    TEST_ASSERT_EQUAL_INT(1, r.base_exact);
    TEST_ASSERT_EQUAL_UINT(0, r.base_test.n_rep);
    TEST_ASSERT_EQUAL_INT(1, aenl_diagnose_baseline_agrees(&r));
    aenl_diagnose_result_free(&r);
    /* the same record against a baseline 10 % stiffer in pitch: no longer reproduced */
    aenl_sim_model_t stiff = m;
    stiff.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_POLYNOMIAL;
    stiff.law[AENL_SIM_DOF_PITCH].n_coeffs = 1u;
    stiff.law[AENL_SIM_DOF_PITCH].coeffs[0] = 1.1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &stiff, &run, &o, &r, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_INT(0, r.base_exact);
    TEST_ASSERT_TRUE(aenl_diagnose_baseline_agrees(&r) != 1);
    aenl_diagnose_result_free(&r);
    aenl_table_free(&t);
}

/* Where no two runs differ (a noise-free free decay), the scores' degrees of freedom M are
 * measured over runs given a small nominal noise (0.1 % of each channel's std). The reference: M
 * as the replicates measure it on the same record with white noise of that size added. Measured
 * over the alike runs themselves, M would stand at 1 and every difference of the scores would
 * shrink with it. M grows slowly with the noise's size (on this
 * record about 8 at 0.1 %, 11 to 14 at 0.3 to 1 %, 22 at 3 %: more of the signatures' elements are
 * the noise's), so the reference is at the nominal size. */
static void test_dof_without_noise(void)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    const size_t n = 3000u;
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_table_t t;
    a2_decay(&m, &run, n, &t);
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    o.summary_records = 0;
    o.n_replicates = 5;
    o.n_refine = 0;
    aenl_diagnose_result_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &m, &run, &o, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, r.floor_before[r.n_channels]);
    const double m_nominal = r.m_eff * r.dispersion;
    aenl_diagnose_result_free(&r);
    aenl_rng_t g;
    aenl_rng_seed(&g, 5u);
    for (size_t k = 1; k <= 2u; ++k)
    {
        double s1 = 0.0, s2 = 0.0;
        for (size_t i = 0; i < n; ++i)
        {
            s1 += t.data[k * n + i];
            s2 += t.data[k * n + i] * t.data[k * n + i];
        }
        const double sd = sqrt(fmax(s2 / (double)n - (s1 / (double)n) * (s1 / (double)n), 0.0));
        for (size_t i = 0; i < n; ++i)
        {
            t.data[k * n + i] += 1e-3 * sd * aenl_rng_gauss(&g);
        }
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_run(&t, &m, &run, &o, &r, &err), err.msg);
    const double m_noisy = r.m_eff * r.dispersion;
    printf("M of a noise-free decay (nominal noise) %.3g; with 0.1 %% noise %.3g (floor %.3g)\n",
           m_nominal, m_noisy, r.floor_before[r.n_channels]);
    TEST_ASSERT_TRUE(r.floor_before[r.n_channels] > 0.0);
    TEST_ASSERT_TRUE(m_noisy > 2.0);
    TEST_ASSERT_TRUE(m_nominal > 0.5 * m_noisy && m_nominal < 2.0 * m_noisy);
    aenl_diagnose_result_free(&r);
    aenl_table_free(&t);
}

/* The same linear gust record made twice: once driven by the model's own turbulence (the seed
 * of its INI, as a record simulated from it), once by turbulence the model does not
 * know. The floor of runs that differ in their noise alone is well below that of runs with other
 * turbulence; the first record is read as following the model's excitation and the candidates
 * are scored in units of that floor, the second keeps the floor of other turbulence. Neither
 * names an effect. */
static void test_excitation_shared_or_not(void)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_diagnose_case_t c;
    a2_none(&c);
    const size_t n = 4000u;
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    o.summary_records = 0;
    o.n_replicates = 2;
    o.n_refine = 0;
    for (int other = 0; other <= 1; ++other)
    {
        aenl_sim_run_t run = c.base_run;
        run.turb_seed += other ? 123457u : 0u;
        aenl_table_t t;
        a2_record(&c.base, &run, n, &t);
        aenl_rng_t g;
        aenl_rng_seed(&g, 7u);
        for (size_t k = 1; k <= 2u; ++k)
        {
            double m = 0.0, v = 0.0;
            for (size_t i = 0; i < n; ++i)
            {
                m += t.data[k * n + i] / (double)n;
            }
            for (size_t i = 0; i < n; ++i)
            {
                v += (t.data[k * n + i] - m) * (t.data[k * n + i] - m) / (double)n;
            }
            for (size_t i = 0; i < n; ++i)
            {
                t.data[k * n + i] += 0.1 * sqrt(v) * aenl_rng_gauss(&g); /* SNR 10 */
            }
        }
        aenl_diagnose_result_t r;
        TEST_ASSERT_EQUAL_INT_MESSAGE(
            AENL_OK, aenl_diagnose_run(&t, &c.base, &c.base_run, &o, &r, &err), err.msg);
        aenl_table_free(&t);
        const size_t nc = r.n_channels;
        printf("%s turbulence: gap %.3g, floor %.3g, floor of the noise alone %.3g, shared %d, "
               "common floor %.3g, named %s\n",
               other ? "other" : "the model's own", r.gap_before[nc], r.floor_before[nc],
               r.floor_same, r.excitation_shared, r.common_floor,
               aenl_diagnose_effect_name(r.effect));
        TEST_ASSERT_TRUE(r.floor_same > 0.0 && r.floor_same < 0.5 * r.floor_before[nc]);
        TEST_ASSERT_EQUAL_INT(!other, r.excitation_shared);
        if (other)
        {
            TEST_ASSERT_TRUE(r.common_floor >= r.floor_before[nc]);
            TEST_ASSERT_EQUAL_DOUBLE(r.floor_before[nc], r.base_floor);
        }
        else
        {
            TEST_ASSERT_EQUAL_DOUBLE(r.floor_same, r.common_floor);
            TEST_ASSERT_TRUE(r.base_floor > 0.0 && r.base_floor <= r.floor_same);
        }
        TEST_ASSERT_TRUE(r.gap_before[nc] <= 2.0 * r.base_floor);
        TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_NONE, r.effect);
        aenl_diagnose_result_free(&r);
    }
}

static void test_bound_tells_ridge_from_determined(void)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_diagnose_case_t c;
    double sd[AENL_DIAGNOSE_MAX_PAR] = {0};
    size_t np = 0;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_make(1, TRUTH_SEED, 0, &c, &err));
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_HYSTERESIS, c.effect);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_case_bound(&c, 64, 16, sd, &np, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_size_t(3, np);
    TEST_ASSERT_TRUE(sd[0] > 0.0 && sd[0] < 0.03);
    TEST_ASSERT_TRUE(sd[1] > 10.0 * sd[0] && sd[2] > 10.0 * sd[0]);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_make(0, TRUTH_SEED, 0, &c, &err));
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_FREEPLAY, c.effect);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_case_bound(&c, 64, 16, sd, &np, &err),
                                  err.msg);
    TEST_ASSERT_EQUAL_size_t(2, np);
    TEST_ASSERT_TRUE(sd[0] > 0.0 && sd[0] < 0.03 && sd[1] > 0.0 && sd[1] < 0.03);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_diagnose_case_bound(&c, 16, 8, sd, &np, &err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_make(4, TRUTH_SEED, 0, &c, &err));
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_NONE, c.effect);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_bound(&c, 64, 16, sd, &np, &err));
    TEST_ASSERT_EQUAL_size_t(0, np);
}

/* p of the summaries' test of model `m` on the case's truth measured with turbulence and noise
 * seeds moved by k (k = 0: the case's own). */
static double summary_test_p(aenl_diagnose_case_t *c, const aenl_sim_model_t *m, uint64_t k)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    c->truth_run.turb_seed += 7u * k;
    c->truth_run.noise_seed += 13u * k;
    aenl_table_t t;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_diagnose_case_measure(c, &t, &err), err.msg);
    c->truth_run.turb_seed -= 7u * k;
    c->truth_run.noise_seed -= 13u * k;
    const size_t n = t.n_rows, n_ch = t.n_cols - 1u;
    double noise[AENL_SIM_MAX_Q];
    for (size_t q = 0; q < n_ch; ++q)
    {
        aenl_diagnose_chan_t ch;
        TEST_ASSERT_EQUAL_INT(AENL_OK,
                              aenl_diagnose_chan_setup(aenl_table_col(&t, q + 1u), n, &ch, &err));
        noise[q] = ch.noise_sd;
    }
    aenl_sim_run_t run = c->base_run;
    run.duration = (double)(n - 1u) * run.dt;
    aenl_diagnose_sumtest_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        AENL_OK, aenl_diagnose_summary_test(m, &run, noise, t.data + n, n, 64u, &r, &err), err.msg);
    TEST_ASSERT_EQUAL_size_t(8u * n_ch, r.d);
    TEST_ASSERT_TRUE(r.d2 >= 0.0 && r.p >= 1.0 / 65.0 && r.p <= 1.0);
    aenl_table_free(&t);
    return r.p;
}

/* The Monte Carlo test of the summaries (aenl_diagnose_summary_test). Size: on records of the
 * model itself (the null case's linear airfoil under other gust and noise seeds) the record's
 * rank among the 65 is uniform, so p is uniform on k / 65: of 20 records at most 4 have p at
 * or below the level 0.05 (3 / 65; binomial(20, 0.046): P(>= 5) = 0.002) and their mean p lies
 * within 3 standard deviations (0.065) of 33 / 65. Power: the hidden freeplay's record rejects
 * its linear baseline. Bad record counts are refused. */
static void test_summary_test_size_and_power(void)
{
    PLAIN_BUILD_ONLY();
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_diagnose_case_t c;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_make(4, TRUTH_SEED, 0, &c, &err));
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_NONE, c.effect);
    c.truth_run.duration /= 3.0; /* 2000 samples: the rank's law holds at any length */
    unsigned low = 0;
    double sum = 0.0;
    for (uint64_t k = 1; k <= 20u; ++k)
    {
        const double p = summary_test_p(&c, &c.base, k);
        low += p <= AENL_DIAGNOSE_SUMTEST_LEVEL;
        sum += p;
    }
    printf("summary test on 20 records of the model: mean p %.3f, %u at or below %.2f\n",
           sum / 20.0, low, AENL_DIAGNOSE_SUMTEST_LEVEL);
    TEST_ASSERT_TRUE(low <= 4u);
    TEST_ASSERT_DOUBLE_WITHIN(0.195, 33.0 / 65.0, sum / 20.0);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_diagnose_case_make(0, TRUTH_SEED, 0, &c, &err));
    TEST_ASSERT_EQUAL_INT(AENL_DIAGNOSE_FREEPLAY, c.effect);
    const double p_fp = summary_test_p(&c, &c.base, 0);
    printf("summary test of the linear baseline on a hidden freeplay: p %.3g\n", p_fp);
    TEST_ASSERT_TRUE(p_fp <= AENL_DIAGNOSE_SUMTEST_LEVEL);
    aenl_diagnose_sumtest_t r;
    const double y[4] = {0.0, 1.0, 0.0, 1.0};
    TEST_ASSERT_EQUAL_INT(
        AENL_E_ARG, aenl_diagnose_summary_test(&c.base, &c.base_run, NULL, y, 2u, 16u, &r, &err));
}

/* Part 1 or 2 (argument; none: both), so that ctest runs the two halves side by side. */
int main(int argc, char **argv)
{
    const long part = argc > 1 ? strtol(argv[1], NULL, 10) : 0;
    UNITY_BEGIN();
    if (part != 2)
    {
        RUN_TEST(test_welch_peak_at_sinusoid);
        RUN_TEST(test_rel_var_is_chi_square);
        RUN_TEST(test_peak_freq_matches_brute_force);
        RUN_TEST(test_chan_setup_noise_and_period);
        RUN_TEST(test_chan_setup_rejects);
        RUN_TEST(test_noise_beyond_the_baseline);
        RUN_TEST(test_exact_baseline_agrees);
        RUN_TEST(test_long_decay_is_not_a_runaway);
        RUN_TEST(test_dof_without_noise);
        RUN_TEST(test_excitation_shared_or_not);
        RUN_TEST(test_run_rejects_wrong_step_and_channels);
        RUN_TEST(test_hidden_freeplay_airfoil2dof);
        RUN_TEST(test_hidden_freeplay_other_simulator);
        RUN_TEST(test_hidden_polynomial_airfoil2dof);
        RUN_TEST(test_hidden_preload_airfoil2dof);
    }
    if (part != 1)
    {
        RUN_TEST(test_hidden_hysteresis_section3dof);
        RUN_TEST(test_null_section3dof);
        RUN_TEST(test_hidden_softening_quintic);
        RUN_TEST(test_bound_tells_ridge_from_determined);
        RUN_TEST(test_decay_quintic_released_far_out);
        RUN_TEST(test_summary_test_size_and_power);
    }
    return UNITY_END();
}
