/* SPDX-License-Identifier: MIT */
/**
 * @file test_diagnose_initial.c
 * @brief The baseline's initial state fitted to a free decay's record: when it is fitted, that
 *        the fit is unbiased with standard errors equal to the spread of the estimates over
 *        noise draws (Monte Carlo, the reference), and that it is exact on a noise-free record
 *        of a nonlinear baseline started far from the truth.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_diagnose_internal.h"
#include "aenl_tools/aenl_rng.h"
#include "unity.h"

void setUp(void)
{
}

void tearDown(void)
{
}

/* The 2-DOF airfoil below its flutter speed (6.285), no turbulence, and its run of n samples. */
static void decay_model(aenl_sim_model_t *m, aenl_sim_run_t *run, size_t n)
{
    aenl_sim_model_default(m, AENL_SIM_AIRFOIL2DOF);
    aenl_sim_set_velocity(m, 4.0);
    m->airfoil.zeta_alpha = 0.01;
    m->airfoil.zeta_xi = 0.01;
    aenl_sim_run_default(run, AENL_SIM_AIRFOIL2DOF);
    run->dt = 0.5;
    run->duration = (double)(n - 1u) * run->dt;
}

/* The clean response of m under run into y (channel-major, n a channel). */
static void clean_response(const aenl_sim_model_t *m, const aenl_sim_run_t *run, size_t n,
                           double *y)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_result_t r;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(m, run, &r, &err), err.msg);
    TEST_ASSERT_TRUE(r.n_samples >= n);
    for (size_t c = 0; c < r.n_channels; ++c)
    {
        memcpy(y + c * n, r.y + c * r.n_samples, n * sizeof(double));
    }
    aenl_sim_result_free(&r);
}

static double std_of(const double *y, size_t n)
{
    double m = 0.0, v = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        m += y[i];
    }
    m /= (double)n;
    for (size_t i = 0; i < n; ++i)
    {
        v += (y[i] - m) * (y[i] - m);
    }
    return sqrt(v / (double)n);
}

/* Fit the zero-state baseline base to record y (2 channels, n samples); the fitted model and
 * its standard errors into *out and *info. */
static void fit(const aenl_sim_model_t *base, const aenl_sim_run_t *run, const double *y, size_t n,
                aenl_sim_model_t *out, aenl_diagnose_initial_t *info)
{
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_diagnose_chan_t chan[2];
    for (size_t c = 0; c < 2u; ++c)
    {
        TEST_ASSERT_EQUAL_INT_MESSAGE(
            AENL_OK, aenl_diagnose_chan_setup(y + c * n, n, &chan[c], &err), err.msg);
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        AENL_OK, aenl_diagnose_initial_fit(base, run, y, n, chan, out, info, &err), err.msg);
    TEST_ASSERT_TRUE(info->estimated);
}

/* Which baselines get the fit: only runs without turbulence, and only when asked or when the
 * state given is zero (such a baseline would not move). */
static void test_initial_wanted(void)
{
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    decay_model(&m, &run, 100u);
    TEST_ASSERT_TRUE(aenl_diagnose_initial_wanted(&m, &run));
    m.x0[AENL_SIM_DOF_PITCH] = 0.01;
    TEST_ASSERT_FALSE(aenl_diagnose_initial_wanted(&m, &run));
    m.initial = AENL_SIM_INITIAL_ESTIMATE;
    TEST_ASSERT_TRUE(aenl_diagnose_initial_wanted(&m, &run));
    run.turbulence = 1;
    TEST_ASSERT_FALSE(aenl_diagnose_initial_wanted(&m, &run));
    run.turbulence = 0;
    m.x0[AENL_SIM_DOF_PITCH] = 0.0;
    m.initial = AENL_SIM_INITIAL_GIVEN;
    TEST_ASSERT_FALSE(aenl_diagnose_initial_wanted(&m, &run));
}

/* A release from a known state (pitch, plunge and both rates nonzero), white noise of the
 * fractions f_alpha and f_xi of each channel's std, 40 noise draws: the estimates' mean is
 * within 3 of its standard errors of the truth, and the reported standard error matches the
 * estimates' spread over the draws within the spread's own sampling error (40 draws: about
 * 11 %; allowed 0.65 to 1.5). */
static void check_calibrated(double f_alpha, double f_xi)
{
    const size_t n = 3000u;
    const unsigned draws = 40u;
    aenl_sim_model_t truth, base;
    aenl_sim_run_t run;
    decay_model(&truth, &run, n);
    base = truth;
    truth.x0[AENL_SIM_DOF_PITCH] = 0.03;
    truth.x0[AENL_SIM_DOF_PLUNGE] = -0.01;
    truth.v0[AENL_SIM_DOF_PITCH] = 0.004;
    truth.v0[AENL_SIM_DOF_PLUNGE] = 0.002;
    double *clean = malloc(2u * n * sizeof(double));
    double *y = malloc(2u * n * sizeof(double));
    TEST_ASSERT_NOT_NULL(clean);
    TEST_ASSERT_NOT_NULL(y);
    clean_response(&truth, &run, n, clean);
    const double sd_noise[2] = {f_alpha * std_of(clean, n), f_xi * std_of(clean + n, n)};
    const double want[4] = {truth.x0[AENL_SIM_DOF_PITCH], truth.x0[AENL_SIM_DOF_PLUNGE],
                            truth.v0[AENL_SIM_DOF_PITCH], truth.v0[AENL_SIM_DOF_PLUNGE]};
    double s1[4] = {0}, s2[4] = {0}, sd_sum[4] = {0};
    aenl_rng_t g;
    aenl_rng_seed(&g, 2026u);
    for (unsigned k = 0; k < draws; ++k)
    {
        for (size_t i = 0; i < 2u * n; ++i)
        {
            y[i] = clean[i] + sd_noise[i / n] * aenl_rng_gauss(&g);
        }
        aenl_sim_model_t out;
        aenl_diagnose_initial_t info;
        fit(&base, &run, y, n, &out, &info);
        const double got[4] = {out.x0[AENL_SIM_DOF_PITCH], out.x0[AENL_SIM_DOF_PLUNGE],
                               out.v0[AENL_SIM_DOF_PITCH], out.v0[AENL_SIM_DOF_PLUNGE]};
        const double sd[4] = {info.x0_sd[AENL_SIM_DOF_PITCH], info.x0_sd[AENL_SIM_DOF_PLUNGE],
                              info.v0_sd[AENL_SIM_DOF_PITCH], info.v0_sd[AENL_SIM_DOF_PLUNGE]};
        for (size_t j = 0; j < 4u; ++j)
        {
            s1[j] += got[j] - want[j];
            s2[j] += (got[j] - want[j]) * (got[j] - want[j]);
            sd_sum[j] += sd[j];
        }
    }
    for (size_t j = 0; j < 4u; ++j)
    {
        const double mean = s1[j] / draws;
        const double spread = sqrt((s2[j] - draws * mean * mean) / (draws - 1u));
        const double reported = sd_sum[j] / draws;
        char msg[160];
        (void)snprintf(msg, sizeof(msg),
                       "noise %g/%g, parameter %zu: bias %g, spread %g, reported sd %g", f_alpha,
                       f_xi, j, mean, spread, reported);
        TEST_ASSERT_TRUE_MESSAGE(fabs(mean) < 3.0 * spread / sqrt((double)draws), msg);
        TEST_ASSERT_TRUE_MESSAGE(reported > 0.65 * spread && reported < 1.5 * spread, msg);
    }
    free(clean);
    free(y);
}

/* Equal noise on both channels, and noise 25 times larger on one than on the other (one
 * pooled residual variance would put the quiet channel's errors 4 times too high and the loud
 * one's too low). */
static void test_fit_unbiased_and_sd_calibrated(void)
{
    check_calibrated(0.1, 0.1);
    check_calibrated(0.01, 0.25);
}

/* The true model with a pitch freeplay as the baseline, a noise-free record, and the fit started
 * from a state far from the truth (estimate = true, pitch 0.005 instead of 0.03, the rates of
 * the wrong sign): the state is recovered to 1e-6 of its scale. */
static void test_fit_exact_on_nonlinear_baseline(void)
{
    const size_t n = 2000u;
    aenl_sim_model_t truth, base, out;
    aenl_sim_run_t run;
    decay_model(&truth, &run, n);
    truth.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_FREEPLAY;
    truth.law[AENL_SIM_DOF_PITCH].delta = 0.01;
    truth.law[AENL_SIM_DOF_PITCH].x_f = -0.004;
    base = truth;
    truth.x0[AENL_SIM_DOF_PITCH] = 0.03;
    truth.v0[AENL_SIM_DOF_PITCH] = 0.002;
    truth.v0[AENL_SIM_DOF_PLUNGE] = -0.001;
    base.initial = AENL_SIM_INITIAL_ESTIMATE;
    base.x0[AENL_SIM_DOF_PITCH] = 0.005;
    base.v0[AENL_SIM_DOF_PITCH] = -0.002;
    base.v0[AENL_SIM_DOF_PLUNGE] = 0.001;
    double *y = malloc(2u * n * sizeof(double));
    TEST_ASSERT_NOT_NULL(y);
    clean_response(&truth, &run, n, y);
    aenl_diagnose_initial_t info;
    fit(&base, &run, y, n, &out, &info);
    TEST_ASSERT_DOUBLE_WITHIN(3e-8, 0.03, out.x0[AENL_SIM_DOF_PITCH]);
    TEST_ASSERT_DOUBLE_WITHIN(3e-8, 0.0, out.x0[AENL_SIM_DOF_PLUNGE]);
    TEST_ASSERT_DOUBLE_WITHIN(3e-8, 0.002, out.v0[AENL_SIM_DOF_PITCH]);
    TEST_ASSERT_DOUBLE_WITHIN(3e-8, -0.001, out.v0[AENL_SIM_DOF_PLUNGE]);
    TEST_ASSERT_TRUE(info.rms < 1e-6);
    /* everything but the state is the baseline's */
    TEST_ASSERT_EQUAL_INT(AENL_SIM_LAW_FREEPLAY, out.law[AENL_SIM_DOF_PITCH].kind);
    TEST_ASSERT_EQUAL_DOUBLE(base.airfoil.ustar, out.airfoil.ustar);
    free(y);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_initial_wanted);
    RUN_TEST(test_fit_unbiased_and_sd_calibrated);
    RUN_TEST(test_fit_exact_on_nonlinear_baseline);
    return UNITY_END();
}
