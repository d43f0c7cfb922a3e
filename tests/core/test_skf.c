/* SPDX-License-Identifier: MIT */
/**
 * @file test_skf.c
 * @brief aenl_skf: a one-mode filter equals a plain Kalman filter written here in double (standard
 *        form, Gauss-Jordan inverse) and converges to the steady-state Riccati solution found by
 *        iterating the Riccati equation here; mean NIS over 10^4 steps of data simulated from the
 *        filter's own 3-mode model is within 5 % of the measurement dimension; missing (NaN)
 *        components, infinite inputs and non-PD / overflow paths keep the previous estimate;
 *        thresholds with a direction-dependent band; IMM; argument checks. Builds as f32 and f64.
 */
#include <string.h>

#include "aenl_test.h"

#include "aenl/aenl_skf.h"

#define NX 4
#define NZ 2

/* Agreement with the double reference filter: rounding of the build's precision, amplified by
 * a few hundred recursive steps. */
#if AENL_USE_DOUBLE
#define KF_TOL 1e-9
#else
#define KF_TOL 2e-3
#endif

static aenl_skf_t g_f;
static aenl_skf_model_t g_m;

void setUp(void)
{
    memset(&g_f, 0xA5, sizeof(g_f));
    memset(&g_m, 0, sizeof(g_m));
}

void tearDown(void)
{
}

/* ---- the test model: two coupled damped oscillators, 4 states, 2 outputs ----------------------
 */

static const double k_A[NX][NX] = {{0.95, -0.28, 0.02, 0.0},
                                   {0.28, 0.95, 0.0, 0.01},
                                   {0.01, 0.0, 0.90, -0.40},
                                   {0.0, 0.02, 0.40, 0.90}};
static const double k_Q[NX][NX] = {
    {4e-4, 1e-4, 0.0, 0.0}, {1e-4, 9e-4, 0.0, 0.0}, {0.0, 0.0, 4e-4, 0.0}, {0.0, 0.0, 0.0, 1e-3}};
static const double k_C[NZ][NX] = {{1.0, 0.0, 0.0, 0.0}, {0.0, 0.0, 1.0, 0.5}};
static const double k_R[NZ][NZ] = {{2.5e-3, 5e-4}, {5e-4, 4e-3}};

/* Mode s: A + d_s e0' with b_s = -d_s t_s, continuous at the thresholds t0 = -0.1, t1 = 0.1. */
static const double k_d[3][NX] = {{-0.15, 0.1, 0.0, 0.02}, {0, 0, 0, 0}, {0.12, -0.2, 0.03, 0.0}};
static const double k_thr[2] = {-0.1, 0.1};

static void model_fill(aenl_skf_model_t *m, int n_modes)
{
    memset(m, 0, sizeof(*m));
    m->n_x = NX;
    m->n_z = NZ;
    m->n_modes = (uint16_t)n_modes;
    m->switch_state = 0u;
    m->dir_state = AENL_SKF_DIR_DIFF;
    for (int s = 0; s < n_modes; ++s)
    {
        const int ds = (n_modes == 1) ? 1 : s; /* one mode: the middle (plain) model */
        for (int i = 0; i < NX; ++i)
        {
            for (int j = 0; j < NX; ++j)
            {
                m->A[s][i][j] = (aenl_real_t)(k_A[i][j] + (j == 0 ? k_d[ds][i] : 0.0));
                m->Q[s][i][j] = (aenl_real_t)k_Q[i][j];
            }
            const double t = (ds == 0) ? k_thr[0] : k_thr[1];
            m->b[s][i] = (aenl_real_t)(-k_d[ds][i] * t);
        }
    }
    if (n_modes == 3)
    {
        m->thr_rising[0] = m->thr_falling[0] = (aenl_real_t)k_thr[0];
        m->thr_rising[1] = m->thr_falling[1] = (aenl_real_t)k_thr[1];
    }
    for (int r = 0; r < NZ; ++r)
    {
        for (int j = 0; j < NX; ++j)
        {
            m->C[r][j] = (aenl_real_t)k_C[r][j];
        }
        for (int c = 0; c < NZ; ++c)
        {
            m->R[r][c] = (aenl_real_t)k_R[r][c];
        }
    }
    for (int i = 0; i < NX; ++i)
    {
        m->P0[i][i] = AENL_R(1.0);
    }
}

/* ---- double references ------------------------------------------------------------------------
 */

/* In-place Gauss-Jordan inverse with partial pivoting (n <= NX). */
static void inv_gj(double *a, int n)
{
    double aug[NX][2 * NX];
    for (int i = 0; i < n; ++i)
    {
        for (int j = 0; j < n; ++j)
        {
            aug[i][j] = a[i * n + j];
            aug[i][n + j] = (i == j) ? 1.0 : 0.0;
        }
    }
    for (int c = 0; c < n; ++c)
    {
        int p = c;
        for (int r = c + 1; r < n; ++r)
        {
            if (fabs(aug[r][c]) > fabs(aug[p][c]))
            {
                p = r;
            }
        }
        for (int j = 0; j < 2 * n; ++j)
        {
            const double t = aug[c][j];
            aug[c][j] = aug[p][j];
            aug[p][j] = t;
        }
        const double piv = aug[c][c];
        for (int j = 0; j < 2 * n; ++j)
        {
            aug[c][j] /= piv;
        }
        for (int r = 0; r < n; ++r)
        {
            if (r != c)
            {
                const double f = aug[r][c];
                for (int j = 0; j < 2 * n; ++j)
                {
                    aug[r][j] -= f * aug[c][j];
                }
            }
        }
    }
    for (int i = 0; i < n; ++i)
    {
        for (int j = 0; j < n; ++j)
        {
            a[i * n + j] = aug[i][n + j];
        }
    }
}

/* One standard-form KF step of the plain model (A, Q, C, R), in double. */
static void ref_kf_step(double x[NX], double P[NX][NX], const double z[NZ])
{
    double xp[NX], Pp[NX][NX], T[NX][NX];
    for (int i = 0; i < NX; ++i)
    {
        xp[i] = 0.0;
        for (int j = 0; j < NX; ++j)
        {
            xp[i] += k_A[i][j] * x[j];
            T[i][j] = 0.0;
            for (int r = 0; r < NX; ++r)
            {
                T[i][j] += k_A[i][r] * P[r][j];
            }
        }
    }
    for (int i = 0; i < NX; ++i)
    {
        for (int j = 0; j < NX; ++j)
        {
            Pp[i][j] = k_Q[i][j];
            for (int r = 0; r < NX; ++r)
            {
                Pp[i][j] += T[i][r] * k_A[j][r];
            }
        }
    }
    double PCt[NX][NZ], S[NZ * NZ], K[NX][NZ], e[NZ];
    for (int i = 0; i < NX; ++i)
    {
        for (int r = 0; r < NZ; ++r)
        {
            PCt[i][r] = 0.0;
            for (int j = 0; j < NX; ++j)
            {
                PCt[i][r] += Pp[i][j] * k_C[r][j];
            }
        }
    }
    for (int r = 0; r < NZ; ++r)
    {
        e[r] = z[r];
        for (int j = 0; j < NX; ++j)
        {
            e[r] -= k_C[r][j] * xp[j];
        }
        for (int c = 0; c < NZ; ++c)
        {
            S[r * NZ + c] = k_R[r][c];
            for (int j = 0; j < NX; ++j)
            {
                S[r * NZ + c] += k_C[r][j] * PCt[j][c];
            }
        }
    }
    inv_gj(S, NZ);
    for (int i = 0; i < NX; ++i)
    {
        for (int c = 0; c < NZ; ++c)
        {
            K[i][c] = 0.0;
            for (int r = 0; r < NZ; ++r)
            {
                K[i][c] += PCt[i][r] * S[r * NZ + c];
            }
        }
        x[i] = xp[i];
        for (int c = 0; c < NZ; ++c)
        {
            x[i] += K[i][c] * e[c];
        }
    }
    for (int i = 0; i < NX; ++i)
    {
        for (int j = 0; j < NX; ++j)
        {
            P[i][j] = Pp[i][j];
            for (int c = 0; c < NZ; ++c)
            {
                P[i][j] -= K[i][c] * PCt[j][c];
            }
        }
    }
    for (int i = 0; i < NX; ++i) /* the standard form drifts from symmetry: symmetrise */
    {
        for (int j = 0; j < i; ++j)
        {
            P[i][j] = P[j][i] = 0.5 * (P[i][j] + P[j][i]);
        }
    }
}

static double max_abs_p(double P[NX][NX])
{
    double m = 0.0;
    for (int i = 0; i < NX; ++i)
    {
        for (int j = 0; j < NX; ++j)
        {
            m = fabs(P[i][j]) > m ? fabs(P[i][j]) : m;
        }
    }
    return m;
}

/* ---- tests ------------------------------------------------------------------------------------
 */

static void test_skf_init_ignores_garbage_and_starts_at_x0(void)
{
    model_fill(&g_m, 3);
    g_m.x0[0] = AENL_R(0.3);
    g_m.x0[3] = AENL_R(-0.2);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    aenl_real_t x[NX], P[NX * NX], prob[3];
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x, P));
    TEST_ASSERT_REAL_WITHIN(0.0, 0.3, x[0]);
    TEST_ASSERT_REAL_WITHIN(0.0, 0.0, x[1]);
    TEST_ASSERT_REAL_WITHIN(0.0, -0.2, x[3]);
    TEST_ASSERT_REAL_WITHIN(0.0, 1.0, P[0]);
    TEST_ASSERT_REAL_WITHIN(0.0, 0.0, P[1]);
    TEST_ASSERT_EQUAL_UINT32(0u, g_f.n_steps);
    TEST_ASSERT_EQUAL_UINT32(0u, g_f.n_not_pd);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_mode_prob(&g_f, prob));
    TEST_ASSERT_REAL_WITHIN(0.0, 1.0, prob[2]); /* 0.3 >= 0.1: top mode */
    aenl_real_t nis;
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_skf_mean_nis(&g_f, &nis));
}

static void expect_reject(aenl_status_t want)
{
    static aenl_skf_t before;
    memset(&g_f, 0xA5, sizeof(g_f));
    memcpy(&before, &g_f, sizeof(g_f));
    TEST_ASSERT_EQUAL_INT(want, aenl_skf_init(&g_f, &g_m));
    TEST_ASSERT_EQUAL_MEMORY(&before, &g_f, sizeof(g_f)); /* not written on error */
}

static void test_skf_init_rejects_bad_models(void)
{
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_skf_init(NULL, &g_m));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_skf_init(&g_f, NULL));
    model_fill(&g_m, 3);
    g_m.n_x = 0;
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.n_x = AENL_SKF_MAX_X + 1;
    expect_reject(AENL_E_DIM);
    model_fill(&g_m, 3);
    g_m.n_z = AENL_SKF_MAX_Z + 1;
    expect_reject(AENL_E_DIM);
    model_fill(&g_m, 3);
    g_m.n_modes = AENL_SKF_MAX_MODES + 1;
    expect_reject(AENL_E_DIM);
    model_fill(&g_m, 3);
    g_m.n_z = 0;
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.switch_state = NX;
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.dir_state = NX;
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.thr_rising[1] = g_m.thr_rising[0]; /* not ascending */
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.thr_falling[0] = (aenl_real_t)NAN;
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.A[2][1][3] = (aenl_real_t)INFINITY;
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.Q[1][0][1] = AENL_R(0.5); /* not symmetric */
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.Q[0][2][2] = AENL_R(-1e-3);
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.R[0][1] = g_m.R[1][0] = AENL_R(1.0); /* symmetric, indefinite */
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.P0[3][3] = AENL_R(-1.0);
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.imm = 2u;
    expect_reject(AENL_E_ARG);
    model_fill(&g_m, 3);
    g_m.imm = 1u; /* transition rows all zero: not probabilities */
    expect_reject(AENL_E_ARG);
}

static void test_skf_step_rejects_null(void)
{
    model_fill(&g_m, 1);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    const aenl_real_t z[NZ] = {AENL_R(0.0), AENL_R(0.0)};
    aenl_skf_out_t out;
    aenl_real_t x[NX];
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_skf_step(NULL, z, &out));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_skf_step(&g_f, NULL, &out));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_skf_estimate(NULL, x, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_skf_estimate(&g_f, NULL, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_skf_mode_prob(&g_f, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_E_ARG, aenl_skf_mean_nis(&g_f, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, NULL)); /* out is optional */
    aenl_skf_reset(NULL);                                         /* ignored */
}

/* One mode: the same numbers as a textbook Kalman filter, and the steady-state Riccati solution. */
static void test_skf_one_mode_equals_plain_kf_and_riccati(void)
{
    model_fill(&g_m, 1);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    double xr[NX] = {0, 0, 0, 0}, Pr[NX][NX];
    memset(Pr, 0, sizeof(Pr));
    for (int i = 0; i < NX; ++i)
    {
        Pr[i][i] = 1.0;
    }
    g_lcg = 7u;
    aenl_real_t x[NX], P[NX * NX];
    for (int k = 0; k < 600; ++k)
    {
        const double zd[NZ] = {0.3 * lcg_normal(), 0.3 * lcg_normal()};
        const aenl_real_t z[NZ] = {(aenl_real_t)zd[0], (aenl_real_t)zd[1]};
        aenl_skf_out_t out;
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, &out));
        TEST_ASSERT_EQUAL_UINT16(NZ, out.n_used);
        TEST_ASSERT_EQUAL_UINT16(0u, out.mode);
        ref_kf_step(xr, Pr, zd);
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x, P));
        const double pscale = max_abs_p(Pr);
        for (int i = 0; i < NX; ++i)
        {
            TEST_ASSERT_REAL_WITHIN(KF_TOL, xr[i], x[i]);
            for (int j = 0; j < NX; ++j)
            {
                TEST_ASSERT_REAL_WITHIN(KF_TOL * pscale, Pr[i][j], P[i * NX + j]);
            }
        }
    }
    /* Steady state: iterate the Riccati equation for the predicted covariance to a fixed point,
     * then take its filtered form; compare with the filter's P after 600 steps. */
    double Pp[NX][NX];
    memset(Pp, 0, sizeof(Pp));
    for (int it = 0; it < 3000; ++it)
    {
        double Pf[NX][NX];
        memcpy(Pf, Pp, sizeof(Pf));
        const double z0[NZ] = {0.0, 0.0};
        double x0[NX] = {0, 0, 0, 0};
        /* ref_kf_step predicts then updates: feed it P_{k-1|k-1}, read P_{k|k} */
        ref_kf_step(x0, Pf, z0);
        memcpy(Pp, Pf, sizeof(Pp));
    }
    const double pscale = max_abs_p(Pp);
    for (int i = 0; i < NX; ++i)
    {
        for (int j = 0; j < NX; ++j)
        {
            TEST_ASSERT_REAL_WITHIN(KF_TOL * pscale, Pp[i][j], P[i * NX + j]);
        }
    }
}

/* A sensor a million times more precise than the prior (P0 = 1, R ~ 1e-6 of it): the update
 * cancels almost all of P. The product form of the Joseph update, symmetrised, keeps P positive
 * semi-definite to rounding in float32; the same update expanded as P - M'K' - K (M - S K'), or
 * symmetrised before its last stage, reads minors two orders of magnitude below that bound. Every
 * filtered covariance must stay symmetric with non-negative diagonal and 2 x 2 principal minors
 * (to rounding), every step succeed. */
static void test_skf_precise_sensor_keeps_covariance_psd(void)
{
    model_fill(&g_m, 1);
    for (int r = 0; r < NZ; ++r)
    {
        for (int c = 0; c < NZ; ++c)
        {
            g_m.R[r][c] = (aenl_real_t)(1e-6 * k_R[r][c]);
        }
    }
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    g_lcg = 11u;
    aenl_real_t x[NX], P[NX * NX];
    for (int k = 0; k < 2000; ++k)
    {
        const aenl_real_t z[NZ] = {(aenl_real_t)(0.3 * lcg_normal()),
                                   (aenl_real_t)(0.3 * lcg_normal())};
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, NULL));
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x, P));
        double pmax = 0.0;
        for (int i = 0; i < NX * NX; ++i)
        {
            pmax = fabs((double)P[i]) > pmax ? fabs((double)P[i]) : pmax;
        }
        const double tol = 1e3 * (double)AENL_REAL_EPS * pmax;
        for (int i = 0; i < NX; ++i)
        {
            TEST_ASSERT_TRUE((double)P[i * NX + i] >= -tol);
            for (int j = 0; j < NX; ++j)
            {
                TEST_ASSERT_EQUAL_FLOAT(P[i * NX + j], P[j * NX + i]);
                const double minor = (double)P[i * NX + i] * (double)P[j * NX + j] -
                                     (double)P[i * NX + j] * (double)P[j * NX + i];
                TEST_ASSERT_TRUE(minor >= -10.0 * tol * tol);
            }
        }
    }
}

/* Simulate the 3-mode model itself (mode from the true state) and run the filter on it. */
static double run_nis(int n_steps, int with_missing, double *mode_agree)
{
    model_fill(&g_m, 3);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    double L[NX][NX], Lr[NZ][NZ]; /* Cholesky factors of Q and R, by hand */
    memset(L, 0, sizeof(L));
    memset(Lr, 0, sizeof(Lr));
    for (int j = 0; j < NX; ++j)
    {
        double d = k_Q[j][j];
        for (int r = 0; r < j; ++r)
        {
            d -= L[j][r] * L[j][r];
        }
        L[j][j] = sqrt(d);
        for (int i = j + 1; i < NX; ++i)
        {
            double s = k_Q[i][j];
            for (int r = 0; r < j; ++r)
            {
                s -= L[i][r] * L[j][r];
            }
            L[i][j] = s / L[j][j];
        }
    }
    Lr[0][0] = sqrt(k_R[0][0]);
    Lr[1][0] = k_R[1][0] / Lr[0][0];
    Lr[1][1] = sqrt(k_R[1][1] - Lr[1][0] * Lr[1][0]);
    g_lcg = 2024u;
    double xt[NX] = {0.2, 0.0, 0.1, 0.0};
    double nis_sum = 0.0;
    long n_nis = 0, agree = 0;
    for (int k = 0; k < n_steps; ++k)
    {
        const int s = xt[0] < k_thr[0] ? 0 : (xt[0] < k_thr[1] ? 1 : 2);
        double xn[NX], v[NX];
        for (int i = 0; i < NX; ++i)
        {
            v[i] = lcg_normal();
        }
        for (int i = 0; i < NX; ++i)
        {
            xn[i] = (double)g_m.b[s][i];
            for (int j = 0; j < NX; ++j)
            {
                xn[i] += (double)g_m.A[s][i][j] * xt[j] + L[i][j] * v[j];
            }
        }
        memcpy(xt, xn, sizeof(xt));
        const double w0 = lcg_normal(), w1 = lcg_normal();
        aenl_real_t z[NZ];
        z[0] = (aenl_real_t)(xt[0] + Lr[0][0] * w0);
        z[1] = (aenl_real_t)(xt[2] + 0.5 * xt[3] + Lr[1][0] * w0 + Lr[1][1] * w1);
        if (with_missing && k % 5 == 3)
        {
            z[k % 2] = (aenl_real_t)NAN;
        }
        aenl_skf_out_t out;
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, &out));
        agree += (out.mode == (uint16_t)s);
        nis_sum += (double)out.nis;
        n_nis += out.n_used;
    }
    *mode_agree = (double)agree / (double)n_steps;
    return nis_sum / (double)n_nis; /* per used component */
}

static void test_skf_mean_nis_matches_measurement_dimension(void)
{
    double agree = 0.0;
    const double nis_per_component = run_nis(10000, 0, &agree);
    TEST_ASSERT_REAL_WITHIN(0.05, 1.0, nis_per_component); /* mean NIS within 5 % of n_z */
    aenl_real_t mean_nis;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_mean_nis(&g_f, &mean_nis));
    TEST_ASSERT_REAL_WITHIN(0.05 * NZ, (double)NZ, mean_nis);
    TEST_ASSERT_TRUE(agree > 0.9); /* the mode from the estimate is mostly the true mode */
    /* the three modes were all visited */
    TEST_ASSERT_EQUAL_UINT32(10000u, g_f.n_steps);
    /* with partly missing measurements, still consistent per used component */
    const double nis_missing = run_nis(10000, 1, &agree);
    TEST_ASSERT_REAL_WITHIN(0.05, 1.0, nis_missing);
}

static void test_skf_nan_measurement_predicts_only(void)
{
    model_fill(&g_m, 1);
    g_m.b[0][1] = AENL_R(0.25);
    g_m.x0[0] = AENL_R(1.0);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    const aenl_real_t z[NZ] = {(aenl_real_t)NAN, (aenl_real_t)NAN};
    aenl_skf_out_t out;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, &out));
    TEST_ASSERT_EQUAL_UINT16(0u, out.n_used);
    TEST_ASSERT_REAL_WITHIN(0.0, 0.0, out.nis);
    TEST_ASSERT_EQUAL_UINT32(1u, g_f.n_missing);
    aenl_real_t x[NX], P[NX * NX];
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x, P));
    for (int i = 0; i < NX; ++i)
    {
        /* x = A x0 + b, P = A A' + Q (P0 = I) */
        TEST_ASSERT_REAL_WITHIN(AENL_TEST_REL_TOL, k_A[i][0] + (i == 1 ? 0.25 : 0.0), x[i]);
        for (int j = 0; j < NX; ++j)
        {
            double s = k_Q[i][j];
            for (int r = 0; r < NX; ++r)
            {
                s += k_A[i][r] * k_A[j][r];
            }
            TEST_ASSERT_REAL_WITHIN(10.0 * AENL_TEST_REL_TOL, s, P[i * NX + j]);
        }
    }
    aenl_real_t nis;
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_skf_mean_nis(&g_f, &nis));
}

/* A NaN in one component: same as a filter whose model has only the other output. */
static void test_skf_partial_nan_uses_the_other_component(void)
{
    static aenl_skf_model_t m1;
    static aenl_skf_t f1;
    model_fill(&g_m, 1);
    model_fill(&m1, 1);
    m1.n_z = 1;
    memcpy(m1.C[0], g_m.C[1], sizeof(m1.C[0]));
    m1.R[0][0] = g_m.R[1][1];
    m1.R[0][1] = m1.R[1][0] = AENL_R(0.0);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&f1, &m1));
    g_lcg = 99u;
    for (int k = 0; k < 50; ++k)
    {
        const aenl_real_t v = (aenl_real_t)(0.2 * lcg_normal());
        const aenl_real_t z2[NZ] = {(aenl_real_t)NAN, v};
        const aenl_real_t z1[1] = {v};
        aenl_skf_out_t o2, o1;
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z2, &o2));
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&f1, z1, &o1));
        TEST_ASSERT_EQUAL_UINT16(1u, o2.n_used);
        TEST_ASSERT_REAL_WITHIN(AENL_TEST_REL_TOL * 10.0, o1.nis, o2.nis);
        TEST_ASSERT_REAL_WITHIN(AENL_TEST_REL_TOL * 10.0 * (1.0 + fabs((double)o1.log_lik)),
                                o1.log_lik, o2.log_lik);
    }
    aenl_real_t x2[NX], x1[NX];
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x2, NULL));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&f1, x1, NULL));
    for (int i = 0; i < NX; ++i)
    {
        TEST_ASSERT_REAL_WITHIN(AENL_TEST_REL_TOL * 10.0, x1[i], x2[i]);
    }
}

static void test_skf_infinite_input_and_overflow_keep_estimate(void)
{
    static aenl_skf_t before;
    model_fill(&g_m, 1);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    const aenl_real_t z[NZ] = {AENL_R(0.1), (aenl_real_t)INFINITY};
    memcpy(&before, &g_f, sizeof(g_f));
    aenl_skf_out_t out;
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_skf_step(&g_f, z, &out));
    TEST_ASSERT_EQUAL_UINT32(1u, g_f.n_numeric);
    g_f.n_numeric = 0u;
    TEST_ASSERT_EQUAL_MEMORY(&before, &g_f, sizeof(g_f));

    /* A covariance that overflows: S is not positive definite (infinite), estimate kept. */
    const aenl_real_t big = aenl_sqrt(AENL_REAL_MAX) * AENL_R(4.0);
    model_fill(&g_m, 1);
    g_m.A[0][0][0] = big;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    aenl_real_t x_before[NX], P_before[NX * NX], x[NX], P[NX * NX];
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x_before, P_before));
    const aenl_real_t zf[NZ] = {AENL_R(0.1), AENL_R(0.2)};
    TEST_ASSERT_EQUAL_INT(AENL_E_NOT_PD, aenl_skf_step(&g_f, zf, &out));
    TEST_ASSERT_EQUAL_UINT32(1u, g_f.n_not_pd);
    TEST_ASSERT_EQUAL_UINT32(0u, g_f.n_steps);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x, P));
    TEST_ASSERT_EQUAL_MEMORY(x_before, x, sizeof(x));
    TEST_ASSERT_EQUAL_MEMORY(P_before, P, sizeof(P));
    /* Predict-only into an overflow: non-finite result, E_NUMERIC, kept. */
    const aenl_real_t zn[NZ] = {(aenl_real_t)NAN, (aenl_real_t)NAN};
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_skf_step(&g_f, zn, &out));
    TEST_ASSERT_EQUAL_UINT32(1u, g_f.n_numeric);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x, P));
    TEST_ASSERT_EQUAL_MEMORY(P_before, P, sizeof(P));
}

/* Found by fuzz_skf: a finite estimate whose innovation square overflows gave AENL_OK with
 * NIS = inf and log_lik = -inf, which then poisoned nis_sum and aenl_skf_mean_nis for good. */
static void test_skf_overflowing_nis_is_rejected(void)
{
    aenl_real_t x_before[NX], P_before[NX * NX], x[NX], P[NX * NX];
    model_fill(&g_m, 1);
    memset(g_m.A, 0, sizeof(g_m.A));
    memset(g_m.Q, 0, sizeof(g_m.Q));
    for (int i = 0; i < NX; ++i)
    {
        g_m.A[0][i][i] = AENL_R(1.0);
    }
    g_m.x0[0] = AENL_REAL_MAX / AENL_R(4.0); /* e = z - x = -REAL_MAX/2: finite, e^2 is not */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x_before, P_before));
    const aenl_real_t z[NZ] = {-AENL_REAL_MAX / AENL_R(4.0), (aenl_real_t)NAN};
    aenl_skf_out_t out;
    TEST_ASSERT_EQUAL_INT(AENL_E_NUMERIC, aenl_skf_step(&g_f, z, &out));
    TEST_ASSERT_EQUAL_UINT32(1u, g_f.n_numeric);
    TEST_ASSERT_EQUAL_UINT32(0u, g_f.n_steps);
    TEST_ASSERT_EQUAL_UINT32(0u, g_f.n_nis);
    TEST_ASSERT_EQUAL_INT(AENL_E_EMPTY, aenl_skf_mean_nis(&g_f, x));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x, P));
    TEST_ASSERT_EQUAL_MEMORY(x_before, x, sizeof(x));
    TEST_ASSERT_EQUAL_MEMORY(P_before, P, sizeof(P));
}

/* Found by fuzz_skf: IMM with a mode of probability 0 whose estimate is far away (finite, but
 * its squared spread overflows) gave a NaN covariance from aenl_skf_estimate (0 * inf). */
static void test_skf_imm_estimate_ignores_impossible_far_mode(void)
{
    memset(&g_m, 0, sizeof(g_m));
    g_m.n_x = 1u;
    g_m.n_z = 1u;
    g_m.n_modes = 2u;
    g_m.imm = 1u;
    g_m.A[0][0][0] = g_m.A[1][0][0] = AENL_R(1.0);
    g_m.b[1][0] = AENL_REAL_MAX / AENL_R(4.0); /* mode 1 jumps far away */
    g_m.C[0][0] = g_m.R[0][0] = g_m.P0[0][0] = AENL_R(1.0);
    g_m.trans[0][0] = g_m.trans[1][1] = AENL_R(1.0);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    const aenl_real_t z[1] = {AENL_R(0.0)};
    aenl_skf_out_t out;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, &out));
    TEST_ASSERT_EQUAL_UINT16(0u, out.mode);
    aenl_real_t prob[2], x[1], P[1];
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_mode_prob(&g_f, prob));
    TEST_ASSERT_FALSE(prob[1] > AENL_R(0.0)); /* exactly 0: its likelihood underflowed */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x, P));
    TEST_ASSERT_TRUE(aenl_is_finite(x[0]) && aenl_is_finite(P[0]));
    TEST_ASSERT_REAL_WITHIN(AENL_R(1e-6), AENL_R(0.5), P[0]); /* mode 0 alone: P = 1/2 */
}

static void test_skf_threshold_band_depends_on_direction(void)
{
    memset(&g_m, 0, sizeof(g_m));
    g_m.n_x = 2;
    g_m.n_z = 1;
    g_m.n_modes = 2;
    g_m.switch_state = 0;
    g_m.dir_state = 1; /* the sign of the velocity state */
    g_m.thr_rising[0] = AENL_R(0.6);
    g_m.thr_falling[0] = AENL_R(0.4);
    for (int s = 0; s < 2; ++s)
    {
        g_m.A[s][0][0] = g_m.A[s][1][1] = AENL_R(1.0);
        g_m.Q[s][0][0] = g_m.Q[s][1][1] = AENL_R(1e-4);
    }
    g_m.C[0][0] = AENL_R(1.0);
    g_m.R[0][0] = AENL_R(1.0);
    g_m.P0[0][0] = g_m.P0[1][1] = AENL_R(1e-6);
    TEST_ASSERT_EQUAL_UINT16(0u, aenl_skf_mode_of(&g_m, AENL_R(0.5), 1));
    TEST_ASSERT_EQUAL_UINT16(1u, aenl_skf_mode_of(&g_m, AENL_R(0.5), 0));
    TEST_ASSERT_EQUAL_UINT16(1u, aenl_skf_mode_of(&g_m, AENL_R(0.6), 1)); /* >= threshold */
    TEST_ASSERT_EQUAL_UINT16(0u, aenl_skf_mode_of(&g_m, AENL_R(0.39), 0));
    TEST_ASSERT_EQUAL_UINT16(0u, aenl_skf_mode_of(NULL, AENL_R(0.5), 0));
    const aenl_real_t z[1] = {AENL_R(0.5)};
    aenl_skf_out_t out;
    g_m.x0[0] = AENL_R(0.5);
    g_m.x0[1] = AENL_R(1.0); /* rising */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, &out));
    TEST_ASSERT_EQUAL_UINT16(0u, out.mode);
    g_m.x0[1] = AENL_R(-1.0); /* falling */
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, &out));
    TEST_ASSERT_EQUAL_UINT16(1u, out.mode);
    /* DIR_DIFF: direction from the change of the switching state between estimates */
    g_m.dir_state = AENL_SKF_DIR_DIFF;
    g_m.x0[0] = AENL_R(0.0);
    g_m.x0[1] = AENL_R(0.1); /* moves up by 0.1 per step */
    g_m.P0[0][0] = g_m.P0[1][1] = AENL_R(0.0);
    g_m.Q[0][0][0] = g_m.Q[1][0][0] = AENL_R(0.0);
    g_m.Q[0][1][1] = g_m.Q[1][1][1] = AENL_R(0.0);
    g_m.A[0][0][1] = g_m.A[1][0][1] = AENL_R(1.0);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    int seen_rising_switch = 0;
    for (int k = 0; k < 8; ++k)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, &out));
        /* before step k the estimate is 0.1 k; rising: mode 1 from 0.6 on */
        const double pos = 0.1 * k;
        TEST_ASSERT_EQUAL_UINT16(pos >= 0.6 - 1e-6 ? 1u : 0u, out.mode);
        seen_rising_switch |= (out.mode == 1u);
    }
    TEST_ASSERT_TRUE(seen_rising_switch);
}

static void test_skf_imm_one_mode_equals_threshold_filter_and_picks_true_mode(void)
{
    static aenl_skf_model_t m_imm;
    static aenl_skf_t f_imm;
    model_fill(&g_m, 1);
    memcpy(&m_imm, &g_m, sizeof(m_imm));
    m_imm.imm = 1u;
    m_imm.trans[0][0] = AENL_R(1.0);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&f_imm, &m_imm));
    g_lcg = 5u;
    for (int k = 0; k < 100; ++k)
    {
        const aenl_real_t z[NZ] = {(aenl_real_t)(0.2 * lcg_normal()),
                                   (aenl_real_t)(0.2 * lcg_normal())};
        aenl_skf_out_t a, b;
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, &a));
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&f_imm, z, &b));
        TEST_ASSERT_REAL_WITHIN(AENL_TEST_REL_TOL * 10.0, a.nis, b.nis);
        TEST_ASSERT_REAL_WITHIN(AENL_TEST_REL_TOL * 10.0 * (1.0 + fabs((double)a.log_lik)),
                                a.log_lik, b.log_lik);
    }
    /* Two modes that differ in their offset; data from mode 1: its probability goes to 1. */
    model_fill(&m_imm, 1);
    m_imm.n_modes = 2;
    memcpy(m_imm.A[1], m_imm.A[0], sizeof(m_imm.A[1]));
    memcpy(m_imm.Q[1], m_imm.Q[0], sizeof(m_imm.Q[1]));
    m_imm.b[1][0] = AENL_R(0.2);
    m_imm.thr_rising[0] = m_imm.thr_falling[0] = AENL_R(0.0);
    m_imm.imm = 1u;
    m_imm.trans[0][0] = m_imm.trans[1][1] = AENL_R(0.99);
    m_imm.trans[0][1] = m_imm.trans[1][0] = AENL_R(0.01);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&f_imm, &m_imm));
    double xt[NX] = {0, 0, 0, 0};
    g_lcg = 11u;
    aenl_skf_out_t out;
    for (int k = 0; k < 300; ++k)
    {
        double xn[NX];
        for (int i = 0; i < NX; ++i)
        {
            xn[i] = (i == 0 ? 0.2 : 0.0) + 0.01 * lcg_normal();
            for (int j = 0; j < NX; ++j)
            {
                xn[i] += k_A[i][j] * xt[j];
            }
        }
        memcpy(xt, xn, sizeof(xt));
        const aenl_real_t z[NZ] = {(aenl_real_t)(xt[0] + 0.05 * lcg_normal()),
                                   (aenl_real_t)(xt[2] + 0.5 * xt[3] + 0.06 * lcg_normal())};
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&f_imm, z, &out));
    }
    aenl_real_t prob[2];
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_mode_prob(&f_imm, prob));
    TEST_ASSERT_EQUAL_UINT16(1u, out.mode);
    TEST_ASSERT_TRUE(prob[1] > AENL_R(0.9));
    TEST_ASSERT_REAL_WITHIN(1e-4, 1.0, (double)(prob[0] + prob[1]));
    aenl_real_t x[NX], P[NX * NX];
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&f_imm, x, P));
    TEST_ASSERT_TRUE(P[0] > AENL_R(0.0));
}

static void test_skf_reset_returns_to_x0(void)
{
    model_fill(&g_m, 3);
    g_m.x0[1] = AENL_R(0.5);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_init(&g_f, &g_m));
    const aenl_real_t z[NZ] = {AENL_R(1.0), AENL_R(-1.0)};
    for (int k = 0; k < 10; ++k)
    {
        TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_step(&g_f, z, NULL));
    }
    aenl_skf_reset(&g_f);
    aenl_real_t x[NX], P[NX * NX];
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_skf_estimate(&g_f, x, P));
    TEST_ASSERT_REAL_WITHIN(0.0, 0.5, x[1]);
    TEST_ASSERT_REAL_WITHIN(0.0, 1.0, P[5]);
    TEST_ASSERT_EQUAL_UINT32(0u, g_f.n_steps);
    TEST_ASSERT_EQUAL_UINT32(0u, g_f.n_nis);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_skf_init_ignores_garbage_and_starts_at_x0);
    RUN_TEST(test_skf_init_rejects_bad_models);
    RUN_TEST(test_skf_step_rejects_null);
    RUN_TEST(test_skf_one_mode_equals_plain_kf_and_riccati);
    RUN_TEST(test_skf_mean_nis_matches_measurement_dimension);
    RUN_TEST(test_skf_nan_measurement_predicts_only);
    RUN_TEST(test_skf_partial_nan_uses_the_other_component);
    RUN_TEST(test_skf_infinite_input_and_overflow_keep_estimate);
    RUN_TEST(test_skf_overflowing_nis_is_rejected);
    RUN_TEST(test_skf_imm_estimate_ignores_impossible_far_mode);
    RUN_TEST(test_skf_threshold_band_depends_on_direction);
    RUN_TEST(test_skf_imm_one_mode_equals_threshold_filter_and_picks_true_mode);
    RUN_TEST(test_skf_reset_returns_to_x0);
    RUN_TEST(test_skf_precise_sensor_keeps_covariance_psd);
    return UNITY_END();
}
