/* SPDX-License-Identifier: MIT */
/**
 * @file test_impulse.c
 * @brief Impulse screening (aenl_impulse.h): pulses too small to see in any row are found in
 *        the window sums, pulses that bring the motion no energy are not impulses, Gaussian
 *        residuals are not screened, the delay line keeps every row;
 *        and in `identify`, a linear decay train whose kicks pass for a law when unscreened is
 *        linear in the regression once they are left out.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_evalsuite.h"
#include "aenl_tools/aenl_identify.h"
#include "aenl_tools/aenl_impulse.h"
#include "aenl_tools/aenl_rng.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

#define N_ROWS   40000u
#define N_PULSES 40u
#define SPACING  1000u

/* The pre-filtered pulse of an impulse (sums to 1). */
static const double k_pulse[5] = {0.1, 0.2, 0.4, 0.2, 0.1};

static aenl_impulse_cfg_t config(void)
{
    aenl_impulse_cfg_t c;
    c.n_ch = 1;
    c.window = 8;
    c.before = 11;
    c.after = 11;
    c.z = 3.0;
    c.span = 50;
    c.gain = 2.0;
    c.center[0] = 0.0;
    c.scale[0] = 1.0;
    return c;
}

/* The motion: a sine of 50 rows' period; with kicks, its amplitude decays over 200 rows and is
 * set back to 1 at each pulse (the energy rises a hundredfold), without, it stays at 1. */
static double motion(size_t n, int kicked)
{
    const double a = kicked ? exp(-(double)((n + SPACING - 500u) % SPACING) / 200.0) : 1.0;
    return a * sin(6.283185307179586 * (double)n / 50.0);
}

/* Residuals as measurement noise leaves them: the second difference of white noise (unit
 * variance), plus pulses of size j at 500 + SPACING i. */
static double *residuals(double j, uint64_t seed)
{
    double *e = malloc(N_ROWS * sizeof(double));
    TEST_ASSERT_NOT_NULL(e);
    aenl_rng_t rng;
    aenl_rng_seed(&rng, seed);
    double w0 = aenl_rng_gauss(&rng), w1 = aenl_rng_gauss(&rng);
    for (size_t n = 0; n < N_ROWS; ++n)
    {
        const double w2 = aenl_rng_gauss(&rng);
        e[n] = w2 - 2.0 * w1 + w0;
        w0 = w1;
        w1 = w2;
    }
    for (size_t i = 0; i < N_PULSES; ++i)
    {
        for (size_t q = 0; q < 5u; ++q)
        {
            e[500u + SPACING * i + q] += j * k_pulse[q];
        }
    }
    return e;
}

/* Both passes over e with the motion (kicked or not); left[n] says whether row n was left
 * out. Returns aenl_impulse_arm(). */
static int screen(const double *e, int kicked, aenl_impulse_t *s, unsigned char *left)
{
    for (size_t n = 0; n < N_ROWS; ++n)
    {
        aenl_impulse_scan(s, &e[n]);
    }
    const int armed = aenl_impulse_arm(s);
    size_t got = 0;
    double out;
    int lo = 0;
    for (size_t n = 0; n < N_ROWS; ++n)
    {
        const double row = motion(n, kicked);
        if (aenl_impulse_step(s, &e[n], &row, &out, &lo))
        {
            TEST_ASSERT_EQUAL_DOUBLE(motion(got, kicked), out); /* in order, none lost */
            left[got++] = (unsigned char)lo;
        }
    }
    while (aenl_impulse_drain(s, &out, &lo))
    {
        TEST_ASSERT_EQUAL_DOUBLE(motion(got, kicked), out);
        left[got++] = (unsigned char)lo;
    }
    TEST_ASSERT_EQUAL_UINT(N_ROWS, got);
    return armed;
}

/* One screening of pulses of size j (noise seed), the motion kicked or not. */
typedef struct
{
    double *e;
    unsigned char *left;
    aenl_impulse_t *s;
    int armed;
} trial_t;

static trial_t trial(double j, uint64_t seed, int kicked)
{
    trial_t t;
    t.e = residuals(j, seed);
    t.left = malloc(N_ROWS);
    TEST_ASSERT_NOT_NULL(t.left);
    t.s = NULL;
    aenl_impulse_cfg_t c = config();
    aenl_err_t err;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_impulse_create(&t.s, &c, &err));
    t.armed = screen(t.e, kicked, t.s, t.left);
    return t;
}

static void trial_free(trial_t *t)
{
    aenl_impulse_free(t->s);
    free(t->left);
    free(t->e);
}

static void test_impulse_finds_pulses_no_row_shows(void)
{
    /* j = 10: the largest pulse row is 4, under 1.7 standard deviations of a row (sqrt 6) and
     * far under the rows' maximum; the window sum of the noise is a difference of two first
     * differences (standard deviation 2), so the pulse stands at 5 of them. */
    trial_t t = trial(10.0, 7, 1);
    TEST_ASSERT_EQUAL_INT(1, t.armed);
    TEST_ASSERT_FLOAT_WITHIN(0.3, 2.0 * 3.0, aenl_impulse_threshold(t.s, 0));
    size_t found = 0;
    for (size_t i = 0; i < N_PULSES; ++i)
    {
        int all = 1;
        for (size_t q = 0; q < 5u; ++q)
        {
            all &= t.left[500u + SPACING * i + q];
        }
        found += (size_t)all;
    }
    TEST_ASSERT_EQUAL_UINT(N_PULSES, found);
    TEST_ASSERT_GREATER_OR_EQUAL_UINT(N_PULSES, aenl_impulse_events(t.s));
    TEST_ASSERT_EQUAL_INT(1, aenl_impulse_decaying(t.s)); /* free decays between the kicks */
    /* false alarms cost little: one window-sum row in 370 beyond 3 sigma, and few of them
     * coincide with a rise of the motion's energy */
    TEST_ASSERT_LESS_THAN_UINT(N_ROWS / 10u, aenl_impulse_left_out(t.s));
    trial_free(&t);
}

static void test_impulse_gaussian_residuals_are_not_screened(void)
{
    for (uint64_t seed = 1; seed <= 4; ++seed)
    {
        trial_t t = trial(0.0, seed, 1);
        TEST_ASSERT_EQUAL_INT(0, t.armed);
        trial_free(&t);
    }
}

/* The same pulses where the motion keeps its energy (a misfit of the model at a contact, say):
 * short runs, but no impulse. */
static void test_impulse_pulses_that_bring_no_energy_are_not_impulses(void)
{
    trial_t t = trial(10.0, 7, 0);
    TEST_ASSERT_EQUAL_INT(1, t.armed);
    TEST_ASSERT_EQUAL_UINT(0, aenl_impulse_events(t.s));
    TEST_ASSERT_EQUAL_UINT(0, aenl_impulse_left_out(t.s));
    TEST_ASSERT_EQUAL_INT(0, aenl_impulse_decaying(t.s)); /* its energy never falls */
    trial_free(&t);
}

static void test_impulse_bad_configuration(void)
{
    aenl_impulse_t *s = NULL;
    aenl_err_t err;
    aenl_impulse_cfg_t c = config();
    c.window = 0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_impulse_create(&s, &c, &err));
    c = config();
    c.before = c.window - 1u;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_impulse_create(&s, &c, &err));
    c = config();
    c.z = 0.0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_impulse_create(&s, &c, &err));
    c = config();
    c.gain = 0.5;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_impulse_create(&s, &c, &err));
    c = config();
    c.scale[0] = 0.0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_impulse_create(&s, &c, &err));
    c = config();
    c.n_ch = AENL_IMPULSE_MAX_CH + 1u;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_impulse_create(&s, &c, &err));
    TEST_ASSERT_NULL(s);
}

/* Eval-suite cases 20 (2-DOF, noise-free) and 10 (3-DOF, SNR 3): linear sections released
 * again and again by velocity kicks. Unscreened, the regression finds hysteresis in the plunge
 * of the first and a polynomial in the pitch of the second. */
static void test_identify_kicked_linear_decays_are_linear_in_the_regression(void)
{
    static const size_t k_cases[2] = {20, 10};
    for (size_t i = 0; i < 2u; ++i)
    {
        aenl_eval_case_t c;
        aenl_err_t err;
        aenl_err_clear(&err);
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_eval_case_make(1, k_cases[i], &c, &err));
        TEST_ASSERT_EQUAL_INT(AENL_EVAL_DECAY, c.stratum.regime);
        TEST_ASSERT_EQUAL_INT(AENL_CLASS_LINEAR, c.cls);
        aenl_identify_source_t src;
        aenl_identify_arrays_t ctx;
        aenl_identify_arrays_source(&src, &ctx, c.cols, c.names, c.n_channels, c.n_samples);
        aenl_identify_opts_t o;
        aenl_identify_opts_default(&o);
        aenl_identify_result_t r;
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_identify_run(&src, &o, &r, &err));
        TEST_ASSERT_GREATER_THAN_UINT(c.n_releases / 2u, r.impulses);
        for (size_t k = 0; k < r.n_channels; ++k)
        {
            TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_CLASS_LINEAR, r.ch[k].rfs.cls, r.ch[k].name);
        }
        aenl_identify_free(&r);
        aenl_eval_case_free(&c);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_impulse_finds_pulses_no_row_shows);
    RUN_TEST(test_impulse_gaussian_residuals_are_not_screened);
    RUN_TEST(test_impulse_pulses_that_bring_no_energy_are_not_impulses);
    RUN_TEST(test_impulse_bad_configuration);
    RUN_TEST(test_identify_kicked_linear_decays_are_linear_in_the_regression);
    return UNITY_END();
}
