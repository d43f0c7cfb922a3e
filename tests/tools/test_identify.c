/* SPDX-License-Identifier: MIT */
/**
 * @file test_identify.c
 * @brief `identify` on whole records. Sustained oscillations: the kurtosis it reports is 1.5 for
 *        a sinusoid and 3 for a Gaussian process (analytic values); a lightly damped linear
 *        structure under Gaussian forcing, sustained at 10 periods, is not taken for a limit
 *        cycle and stays linear; a limit cycle the core classifier calls linear in every channel
 *        is not linear. Direction-dependent forces: turbulence driving a nonlinear spring is not
 *        hysteresis, a hysteresis loop under turbulence still is.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_evalsuite.h"
#include "aenl_tools/aenl_identify.h"
#include "aenl_tools/aenl_rng.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

#define PI       3.14159265358979323846
#define PERIOD   20.0
#define N_LINEAR 200000u

static const char *const k_names[2] = {"a", "b"};

static void run(const double *const *cols, const char *const *names, size_t n_ch, size_t n,
                aenl_identify_result_t *r)
{
    aenl_identify_source_t src;
    aenl_identify_arrays_t ctx;
    aenl_identify_arrays_source(&src, &ctx, cols, names, n_ch, n);
    aenl_identify_opts_t o;
    aenl_identify_opts_default(&o);
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_identify_run(&src, &o, r, &err), err.msg);
}

/* Two sinusoids (a linear filter keeps a sinusoid's shape): kurtosis 3/2 exactly. */
static void test_identify_kurtosis_of_a_sinusoid(void)
{
    const size_t n = 20000u;
    double *a = malloc(n * sizeof(double)), *b = malloc(n * sizeof(double));
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    for (size_t i = 0; i < n; ++i)
    {
        a[i] = sin(2.0 * PI * (double)i / PERIOD);
        b[i] = 0.3 * cos(2.0 * PI * (double)i / PERIOD + 0.4);
    }
    const double *cols[2] = {a, b};
    aenl_identify_result_t r;
    run(cols, k_names, 2u, n, &r);
    for (size_t k = 0; k < 2u; ++k)
    {
        TEST_ASSERT_DOUBLE_WITHIN(0.01, 1.5, r.ch[k].kurtosis);
        TEST_ASSERT_GREATER_THAN_DOUBLE(0.99, r.ch[k].sustained);
    }
    TEST_ASSERT_TRUE(r.limit_cycle >= 0);
    aenl_identify_free(&r);
    free(a);
    free(b);
}

/* A lightly damped linear oscillator driven by Gaussian white noise (damping ratio 0.008: its
 * autocorrelation at 10 periods is exp(-2 pi 10 0.008) = 0.60, so it passes for sustained) and a
 * second channel mixing it with its own noise. Gaussian in, Gaussian out: kurtosis 3 (the
 * amplitude decorrelates over about 1 / (zeta omega) = 400 samples, so 200 000 samples give
 * about 500 independent values and a standard error near 0.2). Not a limit cycle; linear. */
static void test_identify_narrowband_gaussian_is_not_a_limit_cycle(void)
{
    double *a = malloc(N_LINEAR * sizeof(double)), *b = malloc(N_LINEAR * sizeof(double));
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    const double zeta = 0.008, w = 2.0 * PI / PERIOD;
    const double rho = exp(-zeta * w), c1 = 2.0 * rho * cos(w * sqrt(1.0 - zeta * zeta));
    const double c2 = -rho * rho;
    aenl_rng_t rng;
    aenl_rng_seed(&rng, 20261121u);
    double x1 = 0.0, x2 = 0.0;
    for (size_t i = 0; i < N_LINEAR; ++i)
    {
        const double x = c1 * x1 + c2 * x2 + aenl_rng_gauss(&rng);
        x2 = x1;
        x1 = x;
        a[i] = x;
        b[i] = 0.5 * x + 2.0 * aenl_rng_gauss(&rng);
    }
    const double *cols[2] = {a, b};
    aenl_identify_result_t r;
    run(cols, k_names, 2u, N_LINEAR, &r);
    char msg[96];
    (void)snprintf(msg, sizeof(msg), "sustained %.3f, kurtosis %.3f", r.ch[0].sustained,
                   r.ch[0].kurtosis);
    TEST_MESSAGE(msg);
    TEST_ASSERT_GREATER_OR_EQUAL_DOUBLE(0.5, r.ch[0].sustained);
    TEST_ASSERT_DOUBLE_WITHIN(0.5, 3.0, r.ch[0].kurtosis);
    TEST_ASSERT_EQUAL_INT(-1, (int)r.limit_cycle);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, r.verdict_class);
    /* no channel named: the verdict is as sure as the least sure of the linear channels */
    TEST_ASSERT_EQUAL_INT(-1, (int)r.verdict);
    TEST_ASSERT_EQUAL_DOUBLE(fmin((double)r.ch[0].res.confidence, (double)r.ch[1].res.confidence),
                             r.verdict_confidence);
    aenl_identify_free(&r);
    free(a);
    free(b);
}

/* Make eval-suite case `index` (checked to be of `regime` and class `truth`) and identify it. */
static void identify_case(size_t index, aenl_eval_regime_t regime, aenl_class_t truth,
                          aenl_eval_case_t *c, aenl_identify_result_t *r)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_eval_case_make(1, index, c, &err));
    TEST_ASSERT_EQUAL_INT(regime, c->stratum.regime);
    TEST_ASSERT_EQUAL_INT(truth, c->cls);
    run((const double *const *)c->cols, (const char *const *)c->names, c->n_channels, c->n_samples,
        r);
}

/* Eval-suite case 1: 2-DOF section with a hardening pitch spring (+747 x^3) in a limit cycle of
 * 1.7 deg, SNR 10. The cubic changes the stiffness little over the cycle, and the core
 * classifier calls both channels linear; a structure in a limit cycle is not linear. */
static void test_identify_limit_cycle_is_not_linear(void)
{
    aenl_eval_case_t c;
    aenl_identify_result_t r;
    identify_case(1, AENL_EVAL_LCO, AENL_CLASS_POLYNOMIAL, &c, &r);
    TEST_ASSERT_TRUE(r.limit_cycle >= 0);
    TEST_ASSERT_LESS_THAN_DOUBLE(7.0 / 3.0, r.ch[r.limit_cycle].kurtosis);
    for (size_t k = 0; k < r.n_channels; ++k)
    {
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_CLASS_LINEAR, r.ch[k].onboard.cls, r.ch[k].name);
    }
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, r.verdict_class);
    TEST_ASSERT_TRUE(r.verdict >= 0);
    /* named by its polynomial weight among the channels called linear: as sure of the channel
     * as its share of those weights */
    double sum = 0.0;
    for (size_t k = 0; k < r.n_channels; ++k)
    {
        sum += (long)k == r.verdict || r.ch[k].res.cls == AENL_CLASS_LINEAR
                   ? (double)r.ch[k].res.prob[AENL_CLASS_POLYNOMIAL]
                   : 0.0;
    }
    const double share = (double)r.ch[r.verdict].res.prob[AENL_CLASS_POLYNOMIAL] / sum;
    char msg[64];
    (void)snprintf(msg, sizeof(msg), "channel share %.4f", share);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE(share > 0.0 && share <= 1.0);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, share, r.verdict_share);
    /* one orbit does not weigh the laws: each nonlinear class as likely */
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, share / 3.0, r.verdict_confidence);
    aenl_identify_free(&r);
    aenl_eval_case_free(&c);
}

/* Eval-suite case 16: 3-DOF section with a hardening pitch spring in a limit cycle, noise-free.
 * The core classifier finds a nonlinear law in more than one channel and names one by its
 * evidence; over one orbit its weights between the nonlinear laws are not evidence of the law,
 * so the verdict's confidence is a third (each nonlinear class as likely) times the channel's
 * share of the evidence, computed here from the channels' own evidence. */
static void test_identify_limit_cycle_does_not_weigh_the_laws(void)
{
    aenl_eval_case_t c;
    aenl_identify_result_t r;
    identify_case(16, AENL_EVAL_LCO, AENL_CLASS_POLYNOMIAL, &c, &r);
    TEST_ASSERT_TRUE(r.limit_cycle >= 0);
    TEST_ASSERT_TRUE(r.verdict >= 0);
    TEST_ASSERT_TRUE(r.verdict_class > AENL_CLASS_LINEAR);
    double sum = 0.0;
    for (size_t k = 0; k < r.n_channels; ++k)
    {
        sum +=
            r.ch[k].res.cls > AENL_CLASS_LINEAR && r.ch[k].evidence > 0.0 ? r.ch[k].evidence : 0.0;
    }
    TEST_ASSERT_TRUE(sum > 0.0);
    const double share = r.ch[r.verdict].evidence / sum;
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, share, r.verdict_share);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, share / 3.0, r.verdict_confidence);
    aenl_identify_free(&r);
    aenl_eval_case_free(&c);
}

/* The regression's class of the nonlinear channel of eval-suite case `index`. */
static aenl_class_t regression_class(size_t index, aenl_class_t truth)
{
    aenl_eval_case_t c;
    aenl_identify_result_t r;
    identify_case(index, AENL_EVAL_TURBULENCE, truth, &c, &r);
    const aenl_class_t cls = r.ch[c.channel_index].rfs.cls;
    aenl_identify_free(&r);
    aenl_eval_case_free(&c);
    return cls;
}

/* Eval-suite cases 36 and 87: 2-DOF sections in noise-free turbulence with a hardening pitch
 * (36) and a softening plunge (87) spring. The turbulence pushes the way the DOF moves, and how
 * much it does changes with the amplitude: a force that follows the motion and changes smoothly
 * with the position. With a constant rising-motion offset the regression takes it for a gap
 * moving with the direction (hysteresis); its offset may change with amplitude, so it does not.
 * Case 84 (2-DOF, pitch hysteresis, SNR 10) stays hysteresis: its switching points do move. */
static void test_identify_turbulence_on_a_nonlinear_spring_is_not_hysteresis(void)
{
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, regression_class(36, AENL_CLASS_POLYNOMIAL));
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, regression_class(87, AENL_CLASS_POLYNOMIAL));
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_HYSTERESIS, regression_class(84, AENL_CLASS_HYSTERESIS));
}

/* The sample standard deviation of x[0..n-1], two-pass. */
static double std_dev(const double *x, size_t n)
{
    double m = 0.0, v = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        m += x[i];
    }
    m /= (double)n;
    for (size_t i = 0; i < n; ++i)
    {
        v += (x[i] - m) * (x[i] - m);
    }
    return sqrt(v / (double)(n - 1u));
}

/* Eval-suite case 174: 3-DOF section, plunge freeplay, a noise-free decay. Undithered, the
 * dense lags interpolate the second difference and the regression can see no law at all.
 * Dithered up to its noise floor, 0.1 of each
 * channel's standard deviation less what the differences estimate finds (0.26-0.82 of it here:
 * the kicks' corners and the flap's fast mode read as noise), the regression
 * finds the gap in plunge and nothing in pitch or flap. Case 38 (plunge freeplay, SNR 3) is
 * noisier than the floor and is not dithered. */
static void test_identify_a_noise_free_record_is_dithered_to_the_floor(void)
{
    aenl_eval_case_t c;
    aenl_identify_result_t r;
    identify_case(174, AENL_EVAL_DECAY, AENL_CLASS_FREEPLAY, &c, &r);
    TEST_ASSERT_EQUAL_INT(0, c.channel_index);
    TEST_ASSERT_EQUAL_size_t(3, r.n_channels);
    for (size_t k = 0; k < r.n_channels; ++k)
    {
        const double floor = 0.1 * std_dev(c.cols[k], c.n_samples);
        const double want = sqrt(floor * floor - r.ch[k].noise_std * r.ch[k].noise_std);
        TEST_ASSERT_TRUE_MESSAGE(r.ch[k].noise_std < floor, r.ch[k].name);
        TEST_ASSERT_TRUE(r.ch[k].dither_std > 0.0);
        TEST_ASSERT_DOUBLE_WITHIN(1e-6 * want, want, r.ch[k].dither_std);
    }
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_FREEPLAY, r.ch[0].rfs.cls);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, r.ch[1].rfs.cls);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, r.ch[2].rfs.cls);
    TEST_ASSERT_EQUAL_INT(0, (int)r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_FREEPLAY, r.verdict_class);
    aenl_identify_free(&r);
    aenl_eval_case_free(&c);
    identify_case(38, AENL_EVAL_DECAY, AENL_CLASS_FREEPLAY, &c, &r);
    for (size_t k = 0; k < r.n_channels; ++k)
    {
        TEST_ASSERT_EQUAL_DOUBLE(0.0, r.ch[k].dither_std);
    }
    aenl_identify_free(&r);
    aenl_eval_case_free(&c);
}

/* Eval-suite case `index`: the verdict names the nonlinear channel, and each channel in `echoes`
 * (-1 ended) is linear, its law explained by that channel's. */
static void check_echoes(size_t index, aenl_eval_regime_t regime, const long *echoes)
{
    aenl_eval_case_t c;
    aenl_identify_result_t r;
    identify_case(index, regime, AENL_CLASS_HYSTERESIS, &c, &r);
    TEST_ASSERT_EQUAL_INT((long)c.channel_index, r.verdict);
    /* the only channel left with a law: its share of the evidence is all of it */
    TEST_ASSERT_EQUAL_DOUBLE(1.0, r.verdict_share);
    TEST_ASSERT_EQUAL_DOUBLE((double)r.ch[r.verdict].res.confidence, r.verdict_confidence);
    TEST_ASSERT_EQUAL_INT(-1, r.ch[c.channel_index].explained_by);
    for (size_t i = 0; echoes[i] >= 0; ++i)
    {
        const aenl_identify_channel_t *e = &r.ch[echoes[i]];
        TEST_ASSERT_EQUAL_INT_MESSAGE((long)c.channel_index, e->explained_by, e->name);
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_CLASS_LINEAR, e->res.cls, e->name);
    }
    aenl_identify_free(&r);
    aenl_eval_case_free(&c);
}

/* A nonlinear force in one DOF reaches the equations of the others, where it can pass for a law
 * of their own. Eval-suite case 189 (3-DOF, pitch hysteresis, noise-free turbulence): plunge
 * shows a polynomial with more evidence than the pitch's loop, which would be named. Case 29
 * (3-DOF, plunge hysteresis, decay, SNR 10): pitch and flap show laws that the plunge's explains.
 * With the named channel's law among their regressors, those laws are gone; the other way
 * round, the true channel's law stays. */
static void test_identify_an_echo_of_another_channels_law_is_linear(void)
{
    const long echo189[] = {0, -1}; /* h */
    check_echoes(189, AENL_EVAL_TURBULENCE, echo189);
    const long echo29[] = {1, 2, -1}; /* alpha, beta */
    check_echoes(29, AENL_EVAL_DECAY, echo29);
}

/* ---- the model-based verdict (aenl_identify_apply_model) ---------------------------------- */

/* A 3-DOF record's result as the record alone left it: polynomial in h (confidence 0.4). */
static aenl_identify_channel_t g_ch[3];
static void data_result(aenl_identify_result_t *r)
{
    static const char *const names[3] = {"h", "alpha", "beta"};
    memset(r, 0, sizeof(*r));
    memset(g_ch, 0, sizeof(g_ch));
    for (size_t k = 0; k < 3u; ++k)
    {
        g_ch[k].name = names[k];
        g_ch[k].res.cls = k == 0u ? AENL_CLASS_POLYNOMIAL : AENL_CLASS_LINEAR;
        g_ch[k].res.confidence = 0.4f;
        g_ch[k].explained_by = -1;
    }
    r->n_channels = 3;
    r->ch = g_ch;
    r->verdict = 0;
    r->verdict_class = AENL_CLASS_POLYNOMIAL;
    r->verdict_confidence = 0.4;
    r->limit_cycle = -1;
}

/* A diagnosis of that record: the baseline far off (score 100), hysteresis in the flap named
 * (score 2, weight 1), a flap freeplay at weight 1/3 and a pitch polynomial at weight 1/2. */
static aenl_diagnose_result_t g_d;
static aenl_diagnose_result_t *diagnosis(void)
{
    static const char *const names[3] = {"h", "alpha", "beta"};
    aenl_diagnose_result_t *d = &g_d;
    memset(d, 0, sizeof(*d));
    d->n_channels = 3;
    for (size_t k = 0; k < 3u; ++k)
    {
        d->names[k] = names[k];
    }
    d->updated.type = AENL_SIM_SECTION3DOF;
    d->explained = 1;
    d->common_floor = 0.5;
    d->m_eff = 1.0;
    d->gap_before[3] = 5.0; /* 1 x (5 / 0.5)^2 = 100 */
    d->gap_after[3] = 0.6;
    const aenl_diagnose_effect_t eff[3] = {AENL_DIAGNOSE_HYSTERESIS, AENL_DIAGNOSE_FREEPLAY,
                                           AENL_DIAGNOSE_POLYNOMIAL};
    const aenl_sim_dof_t dof[3] = {AENL_SIM_DOF_FLAP, AENL_SIM_DOF_FLAP, AENL_SIM_DOF_PITCH};
    const double score[3] = {2.0, 2.0 + 2.0 * log(3.0), 2.0 + 2.0 * log(2.0)};
    for (size_t i = 0; i < 3u; ++i)
    {
        d->cand[i].effect = eff[i];
        d->cand[i].dof = dof[i];
        d->cand[i].score = score[i];
    }
    d->cand[3].effect = AENL_DIAGNOSE_PRELOAD; /* scored nowhere: weight 0 */
    d->cand[3].dof = AENL_SIM_DOF_PLUNGE;
    d->cand[3].score = HUGE_VAL;
    d->n_cand = 4;
    d->chosen = 0;
    d->effect = AENL_DIAGNOSE_HYSTERESIS;
    d->dof = AENL_SIM_DOF_FLAP;
    aenl_sim_law_t *law = &d->updated.law[AENL_SIM_DOF_FLAP];
    law->kind = AENL_SIM_LAW_HYSTERESIS;
    law->delta = 0.02;
    law->x_f = 0.0;
    d->n_param_sd = 3; /* delta, alpha_f, preload */
    d->param_sd[0] = 0.001;
    d->param_sd[1] = 0.0005;
    d->param_sd[2] = 0.01;
    return d;
}

static void apply(aenl_identify_result_t *r, const aenl_diagnose_result_t *d)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_identify_apply_model(r, d, &err), err.msg);
}

/* Class, channel, switching points (the kinks of both branches of the hysteresis loop), their
 * errors and the confidences, all worked out by hand from the weights exp(-score / 2). */
static void test_identify_model_verdict_reads_the_diagnosis(void)
{
    aenl_identify_result_t r;
    data_result(&r);
    aenl_diagnose_result_t *d = diagnosis();
    apply(&r, d);
    TEST_ASSERT_EQUAL_INT(1, r.model.applied);
    TEST_ASSERT_EQUAL_INT(0, r.model.data_verdict); /* the record alone's, kept */
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, r.model.data_class);
    TEST_ASSERT_EQUAL_DOUBLE(0.4, r.model.data_confidence);
    TEST_ASSERT_EQUAL_INT(2, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_HYSTERESIS, r.verdict_class);
    /* weights 1, 1/3, 1/2 (the baseline's e^-49 is below double's resolution at this sum) */
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 6.0 / 11.0, r.verdict_confidence);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 8.0 / 11.0, r.verdict_share);
    const aenl_classifier_result_t *b = &r.ch[2].res;
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_HYSTERESIS, b->cls);
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 0.75f, (float)b->confidence);
    /* alpha_f = 0: the inner kinks of both branches meet at 0 */
    TEST_ASSERT_EQUAL_UINT8(3, b->n_switch);
    const double want[3] = {-0.02, 0.0, 0.02}, want_sd[3] = {0.0015, 0.0005, 0.0015};
    for (size_t k = 0; k < 3u; ++k)
    {
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, want[k], (double)b->switch_points[k]);
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, want_sd[k], (double)b->switch_std[k]);
    }
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, r.ch[0].res.cls); /* h: no candidate weight */
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 1.0f, (float)r.ch[0].res.confidence);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, r.ch[1].res.cls); /* alpha: 1 - (1/2) / (11/6) */
    TEST_ASSERT_FLOAT_WITHIN(1e-6f, 8.0f / 11.0f, (float)r.ch[1].res.confidence);

    /* alpha_f = 0.005: four kinks, rising [0.005, 0.025], falling [-0.025, -0.005] */
    data_result(&r);
    d->updated.law[AENL_SIM_DOF_FLAP].x_f = 0.005;
    apply(&r, d);
    TEST_ASSERT_EQUAL_UINT8(4, r.ch[2].res.n_switch);
    const double want4[4] = {-0.025, -0.005, 0.005, 0.025};
    for (size_t k = 0; k < 4u; ++k)
    {
        TEST_ASSERT_DOUBLE_WITHIN(1e-12, want4[k], (double)r.ch[2].res.switch_points[k]);
    }

    /* freeplay: the gap [alpha_f, alpha_f + delta]; no summary fit: no errors (NaN) */
    data_result(&r);
    d->effect = AENL_DIAGNOSE_FREEPLAY;
    d->cand[0].effect = AENL_DIAGNOSE_FREEPLAY;
    d->updated.law[AENL_SIM_DOF_FLAP].kind = AENL_SIM_LAW_FREEPLAY;
    d->updated.law[AENL_SIM_DOF_FLAP].x_f = -0.01;
    d->n_param_sd = 0;
    apply(&r, d);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_FREEPLAY, r.verdict_class);
    TEST_ASSERT_EQUAL_UINT8(2, r.ch[2].res.n_switch);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, -0.01, (double)r.ch[2].res.switch_points[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.01, (double)r.ch[2].res.switch_points[1]);
    TEST_ASSERT_TRUE(isnan((double)r.ch[2].res.switch_std[0]));
    /* with the summary fit's errors: sd(alpha_f) at the start, sd(alpha_f) + sd(delta) at the end
     * (|alpha_f| = |alpha_f + delta| here: the points' order decides, not their size) */
    data_result(&r);
    d->n_param_sd = 2;
    apply(&r, d);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0005, (double)r.ch[2].res.switch_std[0]);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 0.0015, (double)r.ch[2].res.switch_std[1]);
    /* the two flap freeplays now share the class: (1 + 1/3) / (11/6) */
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 8.0 / 11.0, r.verdict_confidence);

    /* a softening polynomial in pitch: no points, hardening from the cubic's sign */
    data_result(&r);
    d->effect = AENL_DIAGNOSE_POLYNOMIAL;
    d->dof = AENL_SIM_DOF_PITCH;
    aenl_sim_law_t *poly = &d->updated.law[AENL_SIM_DOF_PITCH];
    poly->kind = AENL_SIM_LAW_POLYNOMIAL;
    poly->n_coeffs = 3;
    poly->coeffs[0] = 1.0;
    poly->coeffs[2] = -3.0;
    apply(&r, d);
    TEST_ASSERT_EQUAL_INT(1, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, r.ch[1].res.cls);
    TEST_ASSERT_EQUAL_INT8(-1, r.ch[1].res.hardening);
    TEST_ASSERT_EQUAL_UINT8(0, r.ch[1].res.n_switch);

    /* a preload (a constant moment): linear, no channel; the confidence is the weight of the
     * linear laws, the baseline (score 2, as the best candidate's) and the preload (weight 0) */
    data_result(&r);
    d->effect = AENL_DIAGNOSE_PRELOAD;
    d->dof = AENL_SIM_DOF_PLUNGE;
    d->gap_before[3] = 0.5 * sqrt(2.0);
    apply(&r, d);
    TEST_ASSERT_EQUAL_INT(-1, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, r.verdict_class);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 1.0 / (1.0 + 11.0 / 6.0), r.verdict_confidence);
    for (size_t k = 0; k < 3u; ++k)
    {
        TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, r.ch[k].res.cls);
    }

    /* none (the baseline within its floor), its summaries not tested: no evidence either way,
     * the record's verdict */
    data_result(&r);
    d->effect = AENL_DIAGNOSE_NONE;
    apply(&r, d);
    TEST_ASSERT_EQUAL_INT(1, r.model.applied);
    TEST_ASSERT_EQUAL_INT(0, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, r.verdict_class);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, r.ch[0].res.cls);
    TEST_ASSERT_EQUAL_INT(-1, r.model.base_test);

    /* none, and the baseline's summaries agree too (4 of 65 records as far out: p above the
     * level): linear, with the weight of the baseline (score 2) as for the preload above */
    data_result(&r);
    d->base_test.n_rep = 64;
    d->base_test.d = 24;
    d->base_test.d2 = 40.0;
    d->base_test.p = 4.0 / 65.0;
    apply(&r, d);
    TEST_ASSERT_EQUAL_INT(1, r.model.base_test);
    TEST_ASSERT_EQUAL_INT(-1, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, r.verdict_class);
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, 6.0 / 17.0, r.verdict_confidence);
    for (size_t k = 0; k < 3u; ++k)
    {
        TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, r.ch[k].res.cls);
    }
    /* the summaries reject the baseline (3 of 65, at the level): the record's verdict stands */
    data_result(&r);
    d->base_test.p = 3.0 / 65.0;
    apply(&r, d);
    TEST_ASSERT_EQUAL_INT(0, r.model.base_test);
    TEST_ASSERT_EQUAL_INT(0, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, r.verdict_class);

    /* a disagreement no candidate explains: the record's own verdict stands */
    data_result(&r);
    d->explained = 0;
    apply(&r, d);
    TEST_ASSERT_EQUAL_INT(1, r.model.applied);
    TEST_ASSERT_EQUAL_INT(0, r.model.explained);
    TEST_ASSERT_EQUAL_INT(0, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, r.ch[0].res.cls);
}

/* The named DOF's channel must be in the result: else AENL_E_ARG and the result untouched. */
static void test_identify_model_verdict_needs_the_channel(void)
{
    aenl_identify_result_t r;
    data_result(&r);
    g_ch[2].name = "flap";
    aenl_diagnose_result_t *d = diagnosis();
    aenl_err_t err;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_identify_apply_model(&r, d, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "flap"));
    TEST_ASSERT_EQUAL_INT(0, r.model.applied);
    TEST_ASSERT_EQUAL_INT(0, r.verdict);
    TEST_ASSERT_EQUAL_INT(AENL_CLASS_POLYNOMIAL, r.ch[0].res.cls);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_identify_kurtosis_of_a_sinusoid);
    RUN_TEST(test_identify_narrowband_gaussian_is_not_a_limit_cycle);
    RUN_TEST(test_identify_limit_cycle_is_not_linear);
    RUN_TEST(test_identify_limit_cycle_does_not_weigh_the_laws);
    RUN_TEST(test_identify_turbulence_on_a_nonlinear_spring_is_not_hysteresis);
    RUN_TEST(test_identify_an_echo_of_another_channels_law_is_linear);
    RUN_TEST(test_identify_a_noise_free_record_is_dithered_to_the_floor);
    RUN_TEST(test_identify_model_verdict_reads_the_diagnosis);
    RUN_TEST(test_identify_model_verdict_needs_the_channel);
    return UNITY_END();
}
