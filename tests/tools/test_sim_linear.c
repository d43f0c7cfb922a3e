/* SPDX-License-Identifier: MIT */
/**
 * @file test_sim_linear.c
 * @brief Linear aeroelastic checks against reference values: flutter of the classic 2-DOF case
 *        (U* 6.2851, Lee, Jiang & Wong 1999) and its flutter speed against ω̄, the 3-DOF section
 *        (23.897 m/s), and the event-located time integration of a linear case against an exact
 *        matrix exponential.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "unity.h"

#include "aenl_tools/aenl_sim.h"

#define DEG (3.14159265358979323846 / 180.0)

void setUp(void)
{
}

void tearDown(void)
{
}

static void test_flutter_classic_case(void)
{
    aenl_sim_model_t m;
    aenl_sim_flutter_t f;
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_flutter(&m, NULL, 0.0, 0.0, &f, &err));
    TEST_ASSERT_EQUAL_INT(1, f.found);
    TEST_ASSERT_DOUBLE_WITHIN(1e-4, 6.2851, f.speed);   /* literature */
    TEST_ASSERT_DOUBLE_WITHIN(1e-6, 6.285092, f.speed); /* 8-state reference, 7 digits */
    TEST_ASSERT_DOUBLE_WITHIN(1e-5, 0.52823, f.frequency);
}

static void test_flutter_omega_bar_table(void)
{
    static const double wb[6] = {0.2, 0.4, 0.6, 0.8, 1.0, 1.2};
    static const double us[6] = {6.2851, 5.2338, 4.4010, 4.1145, 4.3356, 4.9371};
    aenl_sim_model_t m;
    aenl_sim_flutter_t f;
    aenl_err_t err;
    int i;
    aenl_err_clear(&err);
    for (i = 0; i < 6; ++i)
    {
        aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
        m.airfoil.omega_bar = wb[i];
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_flutter(&m, NULL, 0.0, 0.0, &f, &err));
        TEST_ASSERT_EQUAL_INT(1, f.found);
        TEST_ASSERT_DOUBLE_WITHIN(1e-4, us[i], f.speed);
    }
}

static void test_flutter_section3dof(void)
{
    aenl_sim_model_t m;
    aenl_sim_flutter_t f;
    aenl_sim_mode_t modes[8];
    aenl_err_t err;
    size_t n = 0;
    const double zero_flap[3] = {1.0, 1.0, 0.0};
    aenl_err_clear(&err);
    aenl_sim_model_default(&m, AENL_SIM_SECTION3DOF);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_flutter(&m, NULL, 0.0, 0.0, &f, &err));
    TEST_ASSERT_EQUAL_INT(1, f.found);
    TEST_ASSERT_DOUBLE_WITHIN(1e-3, 23.897, f.speed);
    TEST_ASSERT_DOUBLE_WITHIN(1e-3, 6.088, f.frequency);
    TEST_ASSERT_DOUBLE_WITHIN(0.01, 6.09, f.frequency);
    /* Zero flap stiffness: the lower bound of flap-freeplay LCOs. */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_flutter(&m, zero_flap, 0.0, 0.0, &f, &err));
    TEST_ASSERT_DOUBLE_WITHIN(5e-3, 6.71, f.speed);
    /* Nearly wind-off: 4.40, 9.14, 19.37 Hz. */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_modes(&m, 1e-3, NULL, modes, 8, &n, &err));
    TEST_ASSERT_EQUAL_size_t(3, n);
    TEST_ASSERT_DOUBLE_WITHIN(5e-3, 4.40, modes[0].frequency);
    TEST_ASSERT_DOUBLE_WITHIN(5e-3, 9.14, modes[1].frequency);
    TEST_ASSERT_DOUBLE_WITHIN(5e-3, 19.37, modes[2].frequency);
}

static void test_flutter_freeplay_inner_slope(void)
{
    aenl_sim_model_t m;
    double outer[3], inner[3];
    aenl_sim_model_default(&m, AENL_SIM_SECTION3DOF);
    TEST_ASSERT_EQUAL_INT(0, aenl_sim_slopes(&m, outer, inner));
    m.law[AENL_SIM_DOF_FLAP].kind = AENL_SIM_LAW_FREEPLAY;
    m.law[AENL_SIM_DOF_FLAP].delta = 1.0 * DEG;
    TEST_ASSERT_EQUAL_INT(1, aenl_sim_slopes(&m, outer, inner));
    TEST_ASSERT_EQUAL_DOUBLE(1.0, outer[AENL_SIM_DOF_FLAP]);
    TEST_ASSERT_EQUAL_DOUBLE(0.0, inner[AENL_SIM_DOF_FLAP]);
}

/* ---- exact solution of the linear case: x(t_k) = expm(A dt)^k x0 -------------------------- */

#define NA 10 /* 8 states + 2 states generating the start-up forcing */

static void matmul(const double *a, const double *b, double *c)
{
    int i, j, k;
    for (i = 0; i < NA; ++i)
    {
        for (j = 0; j < NA; ++j)
        {
            double acc = 0.0;
            for (k = 0; k < NA; ++k)
            {
                acc += a[i * NA + k] * b[k * NA + j];
            }
            c[i * NA + j] = acc;
        }
    }
}

/* Scaling and squaring with a degree-24 Taylor polynomial (‖A/2^s‖_1 < 0.5). */
static void expm(const double *A, double *E)
{
    double B[NA * NA], T[NA * NA], P[NA * NA], nrm = 0.0;
    int i, j, s = 0, k;
    for (j = 0; j < NA; ++j)
    {
        double col = 0.0;
        for (i = 0; i < NA; ++i)
        {
            col += fabs(A[i * NA + j]);
        }
        nrm = fmax(nrm, col);
    }
    while (nrm > 0.5)
    {
        nrm *= 0.5;
        ++s;
    }
    for (i = 0; i < NA * NA; ++i)
    {
        B[i] = ldexp(A[i], -s);
    }
    /* Horner: E = I + B(I + B/2(I + B/3(...))) */
    memset(E, 0, sizeof(double) * NA * NA);
    for (i = 0; i < NA; ++i)
    {
        E[i * NA + i] = 1.0;
    }
    for (k = 24; k >= 1; --k)
    {
        matmul(B, E, T);
        for (i = 0; i < NA * NA; ++i)
        {
            E[i] = T[i] / (double)k;
        }
        for (i = 0; i < NA; ++i)
        {
            E[i * NA + i] += 1.0;
        }
    }
    for (k = 0; k < s; ++k)
    {
        matmul(E, E, P);
        memcpy(E, P, sizeof(P));
    }
}

static void test_linear_time_response_matches_expm(void)
{
    const double ustar = 4.0, dt = 0.5, duration = 300.0;
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_sim_result_t res;
    aenl_err_t err;
    double A8[64 * 4], A[NA * NA], E[NA * NA], x[NA], y[NA], max_err = 0.0;
    size_t n8 = 0, k;
    int i, j;
    aenl_err_clear(&err);
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    m.airfoil.ustar = ustar;
    m.x0[AENL_SIM_DOF_PITCH] = 1.0 * DEG;
    aenl_sim_run_default(&run, AENL_SIM_AIRFOIL2DOF);
    run.duration = duration;
    run.dt = dt;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &run, &res, &err));
    TEST_ASSERT_EQUAL_size_t(601, res.n_samples);

    /* 8x8 part from the library (validated by the flutter speed above); the start-up forcing is
     * rebuilt here independently: [ξ'', α''] += Minv [f, g] φ(τ) with
     * φ = p1 + p2, p_i' = −ε_i p_i, p_i(0) = ψ_i ε_i. State: ξ, α, ξ', α', w1..w4, p1, p2. */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_state_matrix(&m, ustar, NULL, A8, &n8, &err));
    TEST_ASSERT_EQUAL_size_t(8, n8);
    memset(A, 0, sizeof(A));
    for (i = 0; i < 8; ++i)
    {
        for (j = 0; j < 8; ++j)
        {
            A[i * NA + j] = A8[i * 8 + j];
        }
    }
    {
        const double mu = 100.0, ah = -0.5, xa = 0.25, ra2 = 0.25;
        const double c0 = 1.0 + 1.0 / mu, c1 = xa - ah / mu;
        /* cppcheck-suppress duplicateExpression ; xa and ra2 happen to be equal */
        const double d0 = xa / ra2 - ah / (mu * ra2),
                     d1 = 1.0 + (1.0 + 8.0 * ah * ah) / (8.0 * mu * ra2);
        const double f = (2.0 / mu) * (0.0 + (0.5 - ah) * 1.0 * DEG);
        const double g = -(1.0 + 2.0 * ah) / (2.0 * ra2) * f;
        const double det = c0 * d1 - c1 * d0;
        const double xi_f = (d1 * f - c1 * g) / det, al_f = (-d0 * f + c0 * g) / det;
        A[2 * NA + 8] = A[2 * NA + 9] = xi_f;
        A[3 * NA + 8] = A[3 * NA + 9] = al_f;
        A[8 * NA + 8] = -0.0455;
        A[9 * NA + 9] = -0.3;
    }
    for (i = 0; i < NA * NA; ++i)
    {
        A[i] *= dt;
    }
    expm(A, E);
    memset(x, 0, sizeof(x));
    x[1] = 1.0 * DEG;
    x[8] = 0.165 * 0.0455;
    x[9] = 0.335 * 0.3;
    for (k = 0; k < res.n_samples; ++k)
    {
        max_err = fmax(max_err, fabs(res.y[k] - x[1]));                 /* alpha */
        max_err = fmax(max_err, fabs(res.y[res.n_samples + k] - x[0])); /* xi */
        for (i = 0; i < NA; ++i)
        {
            double acc = 0.0;
            for (j = 0; j < NA; ++j)
            {
                acc += E[i * NA + j] * x[j];
            }
            y[i] = acc;
        }
        memcpy(x, y, sizeof(x));
    }
    aenl_sim_result_free(&res);
    TEST_ASSERT_TRUE(max_err > 0.0);
    TEST_ASSERT_DOUBLE_WITHIN(1e-8, 0.0, max_err);  /* the requirement */
    TEST_ASSERT_DOUBLE_WITHIN(1e-10, 0.0, max_err); /* what we actually reach */
    {
        char msg[96];
        (void)snprintf(msg, sizeof(msg), "U*=4, alpha(0)=1 deg: max |event - expm| = %.3g",
                       max_err);
        TEST_MESSAGE(msg);
    }
}

static void test_linear_rk4_converges_to_expm_solution(void)
{
    /* Naive RK4 at h = 0.05 agrees with the event-located solution on a linear case. */
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_sim_result_t a, b;
    aenl_err_t err;
    double d = 0.0;
    size_t k;
    aenl_err_clear(&err);
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    m.airfoil.ustar = 4.0;
    m.x0[AENL_SIM_DOF_PITCH] = 1.0 * DEG;
    aenl_sim_run_default(&run, AENL_SIM_AIRFOIL2DOF);
    run.duration = 300.0;
    run.dt = 0.5;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &run, &a, &err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate_rk4(&m, &run, 0.05, &b, &err));
    for (k = 0; k < a.n_samples * a.n_channels; ++k)
    {
        d = fmax(d, fabs(a.y[k] - b.y[k]));
    }
    aenl_sim_result_free(&a);
    aenl_sim_result_free(&b);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 0.0, d);
}

/* Sample autocorrelation of w[0..n) at lag l (w has mean 0 by construction; the sample mean is
 * taken out all the same). */
static double autocorr(const double *w, size_t n, size_t l)
{
    double mean = 0.0, c0 = 0.0, cl = 0.0;
    for (size_t k = 0; k < n; ++k)
    {
        mean += w[k];
    }
    mean /= (double)n;
    for (size_t k = 0; k < n; ++k)
    {
        c0 += (w[k] - mean) * (w[k] - mean);
        if (k + l < n)
        {
            cl += (w[k] - mean) * (w[k + l] - mean);
        }
    }
    return (cl / (double)(n - l)) / (c0 / (double)n);
}

static void test_gust_series_has_the_textbook_autocorrelation(void)
{
    /* The gust sequences the integrators are driven with: unit variance, and the autocorrelation
     * of the continuous filters, exp(-t/T) (first order) and (1 - t/(2T)) exp(-t/T) (Dryden
     * vertical gust), at t = T/2, T, 2T, 3T. 4e5 samples at dt = T/20 hold about 1e4 correlation
     * times: the sample variance is good to about 1.5 %, each correlation to about 0.015. */
    enum
    {
        N = 400000
    };
    static double w[N];
    const double T = 1.3, dt = T / 20.0;
    aenl_sim_run_t run;
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_run_default(&run, AENL_SIM_AIRFOIL2DOF);
    run.dt = dt;
    run.turb_seed = 20261121u;
    for (int spec = 0; spec < 2; ++spec)
    {
        run.turb_spectrum = spec ? AENL_SIM_GUST_DRYDEN : AENL_SIM_GUST_FIRST_ORDER;
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_gust_series(&run, T, N, w, &err), err.msg);
        double m2 = 0.0;
        for (size_t k = 0; k < N; ++k)
        {
            m2 += w[k] * w[k];
        }
        TEST_ASSERT_DOUBLE_WITHIN(0.05, 1.0, m2 / N);
        const size_t lags[4] = {10, 20, 40, 60};
        for (int i = 0; i < 4; ++i)
        {
            const double t = (double)lags[i] * dt / T;
            const double want = spec ? (1.0 - 0.5 * t) * exp(-t) : exp(-t);
            char msg[96];
            (void)snprintf(msg, sizeof(msg), "%s, lag %.1f T", spec ? "Dryden" : "first order", t);
            TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(0.04, want, autocorr(w, N, lags[i]), msg);
        }
    }
    /* The filter starts stationary: the first value over many seeds has unit variance too. */
    for (int spec = 0; spec < 2; ++spec)
    {
        double m2 = 0.0;
        run.turb_spectrum = spec ? AENL_SIM_GUST_DRYDEN : AENL_SIM_GUST_FIRST_ORDER;
        for (uint64_t seed = 1; seed <= 4000; ++seed)
        {
            run.turb_seed = seed;
            TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_gust_series(&run, T, 1, w, &err));
            m2 += w[0] * w[0];
        }
        TEST_ASSERT_DOUBLE_WITHIN(0.1, 1.0, m2 / 4000.0);
    }
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_gust_series(&run, 0.0, 10, w, &err));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_gust_series(&run, T, 0, w, &err));
}

static void test_dryden_turbulence_event_matches_rk4(void)
{
    /* Both integrators drive the linear airfoil through the two-lag Dryden filter with the same
     * held inputs: their responses agree, and differ from the first-order spectrum's. */
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_sim_result_t a, b, c;
    aenl_err_t err;
    double d = 0.0, dfo = 0.0, scale = 0.0;
    aenl_err_clear(&err);
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    m.airfoil.ustar = 4.0;
    aenl_sim_run_default(&run, AENL_SIM_AIRFOIL2DOF);
    run.duration = 300.0;
    run.dt = 0.5;
    run.turbulence = 1;
    run.turb_intensity = 0.01;
    run.turb_seed = 99u;
    run.turb_spectrum = AENL_SIM_GUST_DRYDEN;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &run, &a, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate_rk4(&m, &run, 0.01, &b, &err));
    run.turb_spectrum = AENL_SIM_GUST_FIRST_ORDER;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &run, &c, &err));
    for (size_t k = 0; k < a.n_samples * a.n_channels; ++k)
    {
        d = fmax(d, fabs(a.y[k] - b.y[k]));
        dfo = fmax(dfo, fabs(a.y[k] - c.y[k]));
        scale = fmax(scale, fabs(a.y[k]));
    }
    aenl_sim_result_free(&a);
    aenl_sim_result_free(&b);
    aenl_sim_result_free(&c);
    char msg[128];
    (void)snprintf(msg, sizeof(msg), "max |event - rk4| %.3g, |dryden - first order| %.3g, of %.3g",
                   d, dfo, scale);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE(scale > 0.0);
    TEST_ASSERT_TRUE(d < 1e-6 * scale);
    TEST_ASSERT_TRUE(dfo > 0.1 * scale);
}

/* Above the flutter speed the linear airfoil's pitch grows without end. With a runaway bound
 * both integrators stop between the two samples of the unbounded run that straddle the bound;
 * a bound that is never reached changes nothing; a negative bound is a usage error. */
static void test_runaway_bound_stops_where_the_unbounded_run_crosses_it(void)
{
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_sim_result_t a, b;
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    m.airfoil.ustar = 1.2 * 6.285092;
    m.x0[AENL_SIM_DOF_PITCH] = 1.0 * DEG;
    aenl_sim_run_default(&run, AENL_SIM_AIRFOIL2DOF);
    run.duration = 400.0;
    run.dt = 0.5;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &run, &a, &err));
    size_t cross = 0; /* first sample beyond 10 degrees */
    while (cross < a.n_samples && fabs(a.y[cross]) <= 10.0 * DEG)
    {
        cross++;
    }
    TEST_ASSERT_TRUE(cross > 10u && cross < a.n_samples);
    run.bound[0] = 10.0 * DEG;
    for (int rk4 = 0; rk4 < 2; ++rk4)
    {
        aenl_err_clear(&err);
        const aenl_status_t st = rk4 ? aenl_sim_simulate_rk4(&m, &run, 0.05, &b, &err)
                                     : aenl_sim_simulate(&m, &run, &b, &err);
        TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, st);
        TEST_ASSERT_NULL(b.y);
        TEST_ASSERT_NOT_NULL(strstr(err.msg, "channel alpha ran away"));
        const char *at = strstr(err.msg, "t = ");
        TEST_ASSERT_NOT_NULL(at);
        const double t_stop = strtod(at + 4, NULL);
        TEST_ASSERT_TRUE(t_stop > a.t[cross - 1u] && t_stop <= a.t[cross] + 1e-9);
    }
    /* Never reached: the same samples bit for bit. */
    run.bound[0] = 2.0 * fabs(a.y[a.n_samples - 1u]) + 1.0;
    run.bound[1] = 1e9;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &run, &b, &err));
    TEST_ASSERT_EQUAL_size_t(a.n_samples, b.n_samples);
    TEST_ASSERT_EQUAL_MEMORY(a.y, b.y, a.n_samples * a.n_channels * sizeof(double));
    aenl_sim_result_free(&b);
    aenl_sim_result_free(&a);
    run.bound[1] = -1.0;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate(&m, &run, &b, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "runaway bound"));
}

static void test_kick_train_matches_expm_with_jumps(void)
{
    /* A linear airfoil (no start-up terms, so time-invariant) rapped in pitch every 20 τ with
     * seeded random kicks: between kicks x(t_k+1) = expm(A dt) x(t_k), and at each kick the
     * pitch rate jumps by the sequence aenl_sim_kicks gives. */
    const double ustar = 4.0, dt = 0.5, every = 20.0;
    aenl_sim_model_t m;
    aenl_sim_run_t run;
    aenl_sim_result_t res, r4;
    aenl_err_t err;
    double A8[64 * 4], A[NA * NA], E[NA * NA], x[NA], y[NA], dv[64], max_err = 0.0, peak = 0.0;
    size_t n8 = 0;
    aenl_err_clear(&err);
    aenl_sim_model_default(&m, AENL_SIM_AIRFOIL2DOF);
    m.airfoil.ustar = ustar;
    m.airfoil.ic_forcing = 0;
    aenl_sim_run_default(&run, AENL_SIM_AIRFOIL2DOF);
    run.duration = 300.0;
    run.dt = dt;
    run.kicks = 1;
    run.kick_dof = AENL_SIM_DOF_PITCH;
    run.kick_every = every;
    run.kick_rate = 0.01;
    run.kick_rate_max = 0.02;
    run.kick_seed = 5;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &run, &res, &err), err.msg);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_kicks(&run, 64, dv, &err));
    /* the sequence: sizes in [rate, rate_max], both signs */
    int n_neg = 0;
    for (size_t j = 0; j < 64; ++j)
    {
        TEST_ASSERT_TRUE(fabs(dv[j]) >= 0.01 && fabs(dv[j]) <= 0.02);
        n_neg += dv[j] < 0.0;
    }
    TEST_ASSERT_TRUE(n_neg > 16 && n_neg < 48);

    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_state_matrix(&m, ustar, NULL, A8, &n8, &err));
    TEST_ASSERT_EQUAL_size_t(8, n8);
    memset(A, 0, sizeof(A));
    for (int i = 0; i < 8; ++i)
    {
        for (int j = 0; j < 8; ++j)
        {
            A[i * NA + j] = A8[i * 8 + j] * dt;
        }
    }
    expm(A, E);
    memset(x, 0, sizeof(x));
    size_t next = 0;
    for (size_t k = 0; k < res.n_samples; ++k)
    {
        max_err = fmax(max_err, fabs(res.y[k] - x[1]));                 /* alpha */
        max_err = fmax(max_err, fabs(res.y[res.n_samples + k] - x[0])); /* xi */
        peak = fmax(peak, fabs(x[1]));
        if (k % 40u == 0u && k + 1 < res.n_samples)
        {
            x[3] += dv[next++]; /* state: xi, alpha, xi', alpha', ... */
        }
        for (int i = 0; i < NA; ++i)
        {
            double acc = 0.0;
            for (int j = 0; j < NA; ++j)
            {
                acc += E[i * NA + j] * x[j];
            }
            y[i] = acc;
        }
        memcpy(x, y, sizeof(x));
    }
    TEST_ASSERT_EQUAL_size_t(15, next); /* t = 0, 20, ..., 280 */
    TEST_ASSERT_TRUE(peak > 0.01);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9 * peak, 0.0, max_err); /* rtol 1e-10 over 600 steps */
    /* RK4 applies the same kicks at the same samples. */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate_rk4(&m, &run, 0.05, &r4, &err));
    double d4 = 0.0;
    for (size_t i = 0; i < 2 * res.n_samples; ++i)
    {
        d4 = fmax(d4, fabs(r4.y[i] - res.y[i]));
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-5 * peak, 0.0, d4);
    char msg[128];
    (void)snprintf(msg, sizeof(msg), "kicks: max |event - expm| = %.3g, |rk4 - event| = %.3g",
                   max_err, d4);
    TEST_MESSAGE(msg);
    aenl_sim_result_free(&r4);
    aenl_sim_result_free(&res);

    /* Sign rules: the same sizes; alternate +,-,+..., positive all +. */
    double alt[64], pos[64];
    run.kick_sign = AENL_SIM_KICK_ALTERNATE;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_kicks(&run, 64, alt, &err));
    run.kick_sign = AENL_SIM_KICK_POSITIVE;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_kicks(&run, 64, pos, &err));
    for (size_t j = 0; j < 64; ++j)
    {
        TEST_ASSERT_EQUAL_DOUBLE(fabs(dv[j]), pos[j]);
        TEST_ASSERT_EQUAL_DOUBLE(j % 2 == 0 ? pos[j] : -pos[j], alt[j]);
    }
    /* Validation: not a whole number of steps, with turbulence, no flap on the airfoil. */
    run.kick_every = 20.25;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate(&m, &run, &res, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "whole number"));
    run.kick_every = 20.0;
    run.turbulence = 1;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate_rk4(&m, &run, 0.05, &res, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "turbulence"));
    run.turbulence = 0;
    run.kick_dof = AENL_SIM_DOF_FLAP;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate(&m, &run, &res, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "dof"));
    run.kick_dof = AENL_SIM_DOF_PITCH;
    run.kick_rate_max = 0.005;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_simulate(&m, &run, &res, &err));
    TEST_ASSERT_NOT_NULL(strstr(err.msg, "rate_max"));
    run.kicks = 0;
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_sim_kicks(&run, 4, dv, &err));
}

/* A force far below the first natural frequency, at a speed where the air's stiffness is
 * negligible, is resisted by the DOF's own spring alone: the DOF follows f (the force is κ f),
 * to within the dynamic amplification (f/f_n)² and the air's share. */
static void test_slow_forcing_gives_the_static_deflection(void)
{
    static const aenl_sim_dof_t dofs[2] = {AENL_SIM_DOF_PITCH, AENL_SIM_DOF_PLUNGE};
    static const size_t channel[2] = {1, 0}; /* section3dof channels: h, alpha, beta */
    for (size_t d = 0; d < 2; ++d)
    {
        aenl_sim_model_t m;
        aenl_sim_run_t r;
        aenl_sim_result_t res;
        aenl_err_t err;
        aenl_err_clear(&err);
        aenl_sim_model_default(&m, AENL_SIM_SECTION3DOF);
        aenl_sim_set_velocity(&m, 1.0);
        aenl_sim_run_default(&r, AENL_SIM_SECTION3DOF);
        r.duration = 40.0;
        r.dt = 0.01;
        r.force = AENL_SIM_FORCE_SWEEP;
        r.force_dof = dofs[d];
        r.force_amp = d == 0 ? 0.5 * DEG : 1e-3;
        r.force_f0 = 0.02;
        r.force_f1 = 0.05;
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &r, &res, &err), err.msg);
        TEST_ASSERT_NOT_NULL(res.u);
        TEST_ASSERT_EQUAL_STRING(d == 0 ? "f_pitch" : "f_plunge", res.u_name);
        const size_t n = res.n_samples;
        double worst = 0.0;
        double peak = 0.0;
        for (size_t k = 0; k < n; ++k)
        {
            /* the analytic sweep: amplitude, start and end frequency */
            const double t = res.t[k];
            const double phi =
                2.0 * 3.14159265358979323846 *
                (r.force_f0 * t + (r.force_f1 - r.force_f0) * t * t / (2.0 * r.duration));
            TEST_ASSERT_DOUBLE_WITHIN(1e-12 * r.force_amp, r.force_amp * sin(phi), res.u[k]);
            peak = fmax(peak, fabs(res.u[k]));
            if (t >= 10.0) /* the start-up transient has rung down */
            {
                worst = fmax(worst, fabs(res.y[channel[d] * n + k] - res.u[k]));
            }
        }
        TEST_ASSERT_DOUBLE_WITHIN(1e-6 * r.force_amp, r.force_amp, peak);
        TEST_ASSERT_TRUE_MESSAGE(worst < 2e-3 * r.force_amp, "DOF does not follow the slow force");
        aenl_sim_result_free(&res);
    }
}

/* A multisine over whole periods: its DFT is a/2 · n on each grid line of the band and 0 on every
 * other bin (orthogonality of the sampled sines), and its mean square is rms². */
static void test_multisine_has_its_lines_and_rms(void)
{
    aenl_sim_run_t r;
    aenl_err_t err;
    aenl_err_clear(&err);
    aenl_sim_run_default(&r, AENL_SIM_AIRFOIL2DOF);
    r.duration = 256.0;
    r.dt = 1.0;
    r.force = AENL_SIM_FORCE_MULTISINE;
    r.force_dof = AENL_SIM_DOF_PITCH;
    r.force_amp = 0.02;
    r.force_f0 = 10.0 / 256.0;
    r.force_f1 = 29.0 / 256.0;
    r.force_seed = 5;
    const size_t n = 256;
    double f[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_force_series(&r, n, f, &err), err.msg);
    double ms = 0.0;
    for (size_t k = 0; k < n; ++k)
    {
        ms += f[k] * f[k] / (double)n;
    }
    TEST_ASSERT_DOUBLE_WITHIN(1e-12, r.force_amp, sqrt(ms));
    const double a = r.force_amp * sqrt(2.0 / 20.0); /* 20 lines: 10 .. 29 */
    for (size_t j = 1; j < n / 2; ++j)
    {
        double re = 0.0;
        double im = 0.0;
        for (size_t k = 0; k < n; ++k)
        {
            const double w = 2.0 * 3.14159265358979323846 * (double)(j * k % n) / (double)n;
            re += f[k] * cos(w);
            im -= f[k] * sin(w);
        }
        const double mag = sqrt(re * re + im * im);
        const double want = (j >= 10 && j <= 29) ? 0.5 * a * (double)n : 0.0;
        TEST_ASSERT_DOUBLE_WITHIN(1e-9 * a * (double)n, want, mag);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_flutter_classic_case);
    RUN_TEST(test_flutter_omega_bar_table);
    RUN_TEST(test_flutter_section3dof);
    RUN_TEST(test_flutter_freeplay_inner_slope);
    RUN_TEST(test_linear_time_response_matches_expm);
    RUN_TEST(test_linear_rk4_converges_to_expm_solution);
    RUN_TEST(test_gust_series_has_the_textbook_autocorrelation);
    RUN_TEST(test_dryden_turbulence_event_matches_rk4);
    RUN_TEST(test_runaway_bound_stops_where_the_unbounded_run_crosses_it);
    RUN_TEST(test_kick_train_matches_expm_with_jumps);
    RUN_TEST(test_slow_forcing_gives_the_static_deflection);
    RUN_TEST(test_multisine_has_its_lines_and_rms);
    return UNITY_END();
}
