/* SPDX-License-Identifier: MIT */
/**
 * @file test_sim_lco.c
 * @brief Limit cycles with structural nonlinearities against reference values from an
 *        independent implementation of the same equations (tools/examples/validate_*.ini state
 *        one case each): pitch freeplay, cubic pitch spring, hysteresis with sticking, 3-DOF flap
 *        freeplay; the hysteresis that is a centred freeplay; tolerance convergence;
 *        two nonlinear DOFs at once; naive RK4 converging to the event-located solution (no
 *        missed crossings).
 *
 * Amplitude: half peak-to-peak after the transient; frequency: from upward crossings of the
 * mid-level (linear interpolation between samples), ω/ω_α = 2π f U* for airfoil2dof.
 */
#include <math.h>
#include <stdio.h>

#include "unity.h"

#include "aenl_tools/aenl_sim.h"

#define DEG    (3.14159265358979323846 / 180.0)
#define TWO_PI (2.0 * 3.14159265358979323846)

void setUp(void)
{
}

void tearDown(void)
{
}

typedef struct lco
{
    double amp, mean, freq;
} lco_t;

static lco_t measure(const aenl_sim_result_t *r, size_t ch, double t_from)
{
    const size_t n = r->n_samples;
    const double *y = r->y + ch * n;
    double mx = -HUGE_VAL, mn = HUGE_VAL, first = -1.0, last = -1.0;
    size_t k, nc = 0;
    lco_t o;
    for (k = 0; k < n; ++k)
    {
        if (r->t[k] >= t_from)
        {
            mx = fmax(mx, y[k]);
            mn = fmin(mn, y[k]);
        }
    }
    o.amp = 0.5 * (mx - mn);
    o.mean = 0.5 * (mx + mn);
    for (k = 1; k < n; ++k)
    {
        if (r->t[k - 1] >= t_from && y[k - 1] < o.mean && y[k] >= o.mean)
        {
            const double tc =
                r->t[k - 1] + (o.mean - y[k - 1]) / (y[k] - y[k - 1]) * (r->t[k] - r->t[k - 1]);
            if (first < 0.0)
            {
                first = tc;
            }
            last = tc;
            ++nc;
        }
    }
    o.freq = nc > 1 ? (double)(nc - 1) / (last - first) : 0.0;
    return o;
}

static void report(const char *what, double got, double want)
{
    char msg[160];
    (void)snprintf(msg, sizeof(msg), "%s: %.5g (reference %.5g, %+.2f %%)", what, got, want,
                   100.0 * (got - want) / want);
    TEST_MESSAGE(msg);
}

static void check_within_1pc(const char *what, double got, double want)
{
    report(what, got, want);
    TEST_ASSERT_DOUBLE_WITHIN(0.01 * fabs(want), want, got);
}

static void airfoil(aenl_sim_model_t *m, aenl_sim_run_t *r, double ustar, double alpha0_deg,
                    double duration)
{
    aenl_sim_model_default(m, AENL_SIM_AIRFOIL2DOF);
    m->airfoil.ustar = ustar;
    m->x0[AENL_SIM_DOF_PITCH] = alpha0_deg * DEG;
    aenl_sim_run_default(r, AENL_SIM_AIRFOIL2DOF);
    r->duration = duration;
    r->dt = 0.1;
}

static void pitch_freeplay(aenl_sim_model_t *m)
{
    m->law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_FREEPLAY;
    m->law[AENL_SIM_DOF_PITCH].delta = 0.5 * DEG;
    m->law[AENL_SIM_DOF_PITCH].x_f = 0.25 * DEG;
}

static lco_t run_lco(const aenl_sim_model_t *m, const aenl_sim_run_t *r, size_t ch, double t_from,
                     aenl_sim_info_t *info)
{
    aenl_sim_result_t res;
    aenl_err_t err;
    lco_t o;
    aenl_err_clear(&err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(m, r, &res, &err), err.msg);
    o = measure(&res, ch, t_from);
    if (info != NULL)
    {
        *info = res.info;
    }
    aenl_sim_result_free(&res);
    return o;
}

static void test_lco_pitch_freeplay_table(void)
{
    static const double us[4] = {4.5, 5.0, 5.5, 6.0};
    static const double amp[4] = {0.97, 1.067, 1.621, 4.172};
    static const double om[4] = {0.340, 0.435, 0.475, 0.510};
    int i;
    for (i = 0; i < 4; ++i)
    {
        aenl_sim_model_t m;
        aenl_sim_run_t r;
        aenl_sim_info_t info;
        char what[64];
        lco_t o;
        airfoil(&m, &r, us[i], 1.0, 3000.0);
        pitch_freeplay(&m);
        o = run_lco(&m, &r, 0, 2000.0, &info);
        (void)snprintf(what, sizeof(what), "freeplay U*=%.1f amplitude [deg]", us[i]);
        check_within_1pc(what, o.amp / DEG, amp[i]);
        (void)snprintf(what, sizeof(what), "freeplay U*=%.1f omega/omega_alpha", us[i]);
        check_within_1pc(what, TWO_PI * o.freq * us[i], om[i]);
        if (i > 0)
        {
            /* Centred on the gap centre 0.5 deg. */
            TEST_ASSERT_DOUBLE_WITHIN(1e-3, 0.5, o.mean / DEG);
        }
        else
        {
            TEST_ASSERT_DOUBLE_WITHIN(0.01, 0.40, o.mean / DEG);
        }
        TEST_ASSERT_TRUE(info.n_events > 50);
    }
}

static void test_lco_cubic_table(void)
{
    static const double us[3] = {6.5, 7.0, 8.0};
    static const double amp[3] = {9.45, 17.77, 29.05};
    static const double om[3] = {0.542, 0.572, 0.627};
    int i;
    for (i = 0; i < 3; ++i)
    {
        aenl_sim_model_t m;
        aenl_sim_run_t r;
        char what[64];
        lco_t o;
        airfoil(&m, &r, us[i], 1.0, 4000.0);
        m.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_POLYNOMIAL;
        m.law[AENL_SIM_DOF_PITCH].n_coeffs = 3;
        m.law[AENL_SIM_DOF_PITCH].coeffs[0] = 1.0;
        m.law[AENL_SIM_DOF_PITCH].coeffs[1] = 0.0;
        m.law[AENL_SIM_DOF_PITCH].coeffs[2] = 3.0;
        o = run_lco(&m, &r, 0, 3000.0, NULL);
        (void)snprintf(what, sizeof(what), "cubic U*=%.1f amplitude [deg]", us[i]);
        check_within_1pc(what, o.amp / DEG, amp[i]);
        (void)snprintf(what, sizeof(what), "cubic U*=%.1f omega/omega_alpha", us[i]);
        check_within_1pc(what, TWO_PI * o.freq * us[i], om[i]);
    }
}

static void hysteresis(aenl_sim_model_t *m, double preload_deg)
{
    m->law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_HYSTERESIS;
    m->law[AENL_SIM_DOF_PITCH].delta = 0.5 * DEG;
    m->law[AENL_SIM_DOF_PITCH].x_f = 0.25 * DEG;
    m->law[AENL_SIM_DOF_PITCH].preload = preload_deg * DEG;
}

static void test_lco_hysteresis_table(void)
{
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_sim_info_t info;
    lco_t o;
    airfoil(&m, &r, 5.0, 2.0, 3000.0);
    hysteresis(&m, 0.25);
    o = run_lco(&m, &r, 0, 2000.0, &info);
    check_within_1pc("hysteresis M0=0.25 U*=5 amplitude [deg]", o.amp / DEG, 2.32);
    check_within_1pc("hysteresis M0=0.25 U*=5 omega/omega_alpha", TWO_PI * o.freq * 5.0, 0.744);
    airfoil(&m, &r, 4.0, 2.0, 3000.0);
    hysteresis(&m, 0.1);
    o = run_lco(&m, &r, 0, 2000.0, &info);
    check_within_1pc("hysteresis M0=0.1 U*=4 amplitude [deg]", o.amp / DEG, 4.01);
}

static void test_hysteresis_dissipative_loop_sticks(void)
{
    /* M0 = 0.5 deg (closed dissipative loop), U* = 5: decays and sticks, without chatter. */
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_sim_result_t res;
    aenl_err_t err;
    const size_t n_tail = 100;
    size_t k, n;
    aenl_err_clear(&err);
    airfoil(&m, &r, 5.0, 2.0, 1500.0);
    hysteresis(&m, 0.5);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &r, &res, &err), err.msg);
    n = res.n_samples;
    TEST_ASSERT_TRUE(res.info.n_stuck >= 1);
    TEST_ASSERT_TRUE(res.info.n_events < 100); /* a naive sign(α') switch chatters here */
    for (k = n - n_tail; k < n; ++k)
    {
        /* α frozen at the end: held exactly by the sliding mode. */
        TEST_ASSERT_EQUAL_DOUBLE(res.y[n - 1], res.y[k]);
    }
    /* It stuck inside the loop: |α| below the outer branches' reach of 0.75 deg. */
    TEST_ASSERT_TRUE(fabs(res.y[n - 1]) < 0.75 * DEG);
    aenl_sim_result_free(&res);
}

/* The hysteresis with alpha_f = -delta / 2 and M0 = 0 is the freeplay centred on zero: both
 * branches are zero across the gap and the outer ones coincide (M0 = α_f + δ/2), so no jump at a
 * reversal and nothing to stick. The diagnosis's hysteresis candidate therefore holds its
 * centred freeplay, and comparing the two as nested laws needs the nesting to hold in the
 * simulations too, not only in the law (the sticking rule acts on the branch switch at every
 * reversal): the two pitch histories from 2 deg over 1500 tau agree within the integrator's
 * tolerance. */
static void test_hysteresis_holds_the_centred_freeplay(void)
{
    aenl_sim_model_t fp, hy;
    aenl_sim_run_t r;
    aenl_sim_result_t a, b;
    aenl_err_t err;
    aenl_err_clear(&err);
    airfoil(&fp, &r, 5.0, 2.0, 1500.0);
    fp.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_FREEPLAY;
    fp.law[AENL_SIM_DOF_PITCH].delta = 1.0 * DEG;
    fp.law[AENL_SIM_DOF_PITCH].x_f = -0.5 * DEG;
    hy = fp;
    hy.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_HYSTERESIS;
    for (int k = -30; k <= 30; ++k)
    {
        const double x = 0.05 * DEG * (double)k;
        TEST_ASSERT_DOUBLE_WITHIN(1e-15, aenl_sim_law_eval(&fp.law[AENL_SIM_DOF_PITCH], x, 1),
                                  aenl_sim_law_eval(&hy.law[AENL_SIM_DOF_PITCH], x, 1));
        TEST_ASSERT_DOUBLE_WITHIN(1e-15, aenl_sim_law_eval(&fp.law[AENL_SIM_DOF_PITCH], x, 1),
                                  aenl_sim_law_eval(&hy.law[AENL_SIM_DOF_PITCH], x, -1));
    }
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&fp, &r, &a, &err), err.msg);
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&hy, &r, &b, &err), err.msg);
    TEST_ASSERT_EQUAL_size_t(a.n_samples, b.n_samples);
    double amp = 0.0, diff = 0.0;
    for (size_t k = 0; k < a.n_samples; ++k)
    {
        amp = fmax(amp, fabs(a.y[k]));
        diff = fmax(diff, fabs(a.y[k] - b.y[k]));
    }
    char msg[120];
    (void)snprintf(msg, sizeof(msg), "pitch: largest |difference| %.3g deg, amplitude %.3g deg",
                   diff / DEG, amp / DEG);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE(amp > 1.0 * DEG); /* it moved across the gap */
    TEST_ASSERT_TRUE_MESSAGE(diff < 1e-4 * amp, msg);
    aenl_sim_result_free(&a);
    aenl_sim_result_free(&b);
}

static void test_kick_frees_a_stuck_hysteresis_dof(void)
{
    /* The dissipative loop above, rapped every 1500 τ: each release rings down and sticks again,
     * and each kick frees the held DOF (it takes the direction of its new rate). */
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_sim_result_t res;
    aenl_err_t err;
    const size_t every = 15000, n_tail = 100;
    aenl_err_clear(&err);
    airfoil(&m, &r, 5.0, 2.0, 4500.0);
    hysteresis(&m, 0.5);
    r.kicks = 1;
    r.kick_dof = AENL_SIM_DOF_PITCH;
    r.kick_every = 1500.0;
    r.kick_rate = r.kick_rate_max = 0.007; /* rad/τ: about a 2 deg swing */
    r.kick_sign = AENL_SIM_KICK_ALTERNATE;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &r, &res, &err), err.msg);
    TEST_ASSERT_TRUE(res.info.n_stuck >= 3);
    TEST_ASSERT_TRUE(res.info.n_events < 300);
    for (size_t kick = every; kick < res.n_samples - 1; kick += every)
    {
        for (size_t k = kick - n_tail; k <= kick; ++k)
        {
            TEST_ASSERT_EQUAL_DOUBLE(res.y[kick], res.y[k]); /* held until the kick */
        }
        /* moving again right after it, by about the kick's 0.007 rad/τ x 0.1 τ per step */
        const double step = res.y[kick + 1] - res.y[kick];
        TEST_ASSERT_DOUBLE_WITHIN(0.2 * 0.0007, (kick / every) % 2 == 1 ? -0.0007 : 0.0007, step);
        TEST_ASSERT_TRUE(fabs(res.y[kick + 100] - res.y[kick]) > 0.3 * DEG);
    }
    aenl_sim_result_free(&res);
}

static void test_lco_section3dof_flap_freeplay_table(void)
{
    static const double U[3] = {10.0, 15.0, 20.0};
    static const double beta[3] = {2.88, 3.68, 3.88};
    static const double alpha[3] = {0.52, 0.38, 0.51};
    static const double hz[3] = {4.89, 11.1, 11.4};
    int i;
    for (i = 0; i < 3; ++i)
    {
        aenl_sim_model_t m;
        aenl_sim_run_t r;
        aenl_sim_result_t res;
        aenl_err_t err;
        char what[64];
        lco_t ob, oa;
        aenl_err_clear(&err);
        aenl_sim_model_default(&m, AENL_SIM_SECTION3DOF);
        m.section.velocity = U[i];
        m.x0[AENL_SIM_DOF_PITCH] = 1.0 * DEG;
        m.law[AENL_SIM_DOF_FLAP].kind = AENL_SIM_LAW_FREEPLAY;
        m.law[AENL_SIM_DOF_FLAP].delta = 2.0 * 2.12 * DEG; /* Conner's half gap 2.12 deg */
        m.law[AENL_SIM_DOF_FLAP].x_f = -2.12 * DEG;
        aenl_sim_run_default(&r, AENL_SIM_SECTION3DOF);
        r.duration = 20.0;
        r.dt = 1e-3;
        TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &r, &res, &err), err.msg);
        ob = measure(&res, 2, 10.0);
        oa = measure(&res, 1, 10.0);
        aenl_sim_result_free(&res);
        (void)snprintf(what, sizeof(what), "3-DOF U=%.0f beta amplitude [deg]", U[i]);
        check_within_1pc(what, ob.amp / DEG, beta[i]);
        /* The alpha column has two decimals: 0.375 prints as 0.38 (1.3 %), so the tolerance
         * is 1 % or half a unit of the last printed digit, whichever is larger. */
        (void)snprintf(what, sizeof(what), "3-DOF U=%.0f alpha amplitude [deg]", U[i]);
        report(what, oa.amp / DEG, alpha[i]);
        TEST_ASSERT_DOUBLE_WITHIN(fmax(0.01 * alpha[i], 0.005 + 1e-9), alpha[i], oa.amp / DEG);
        (void)snprintf(what, sizeof(what), "3-DOF U=%.0f frequency [Hz]", U[i]);
        check_within_1pc(what, ob.freq, hz[i]);
    }
}

static void test_freeplay_tolerance_convergence(void)
{
    /* Pitch freeplay U* = 5.5: halving rtol and atol moves the result by < 1e-6 relative. */
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_sim_result_t a, b;
    aenl_err_t err;
    double dmax = 0.0, ymax = 0.0;
    lco_t oa, ob;
    size_t k;
    char msg[128];
    aenl_err_clear(&err);
    airfoil(&m, &r, 5.5, 1.0, 1500.0);
    pitch_freeplay(&m);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &a, &err));
    r.rtol *= 0.5;
    r.atol *= 0.5;
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &b, &err));
    for (k = 0; k < a.n_samples; ++k)
    {
        dmax = fmax(dmax, fabs(a.y[k] - b.y[k]));
        ymax = fmax(ymax, fabs(b.y[k]));
    }
    oa = measure(&a, 0, 1000.0);
    ob = measure(&b, 0, 1000.0);
    aenl_sim_result_free(&a);
    aenl_sim_result_free(&b);
    (void)snprintf(msg, sizeof(msg),
                   "rtol 1e-10 vs 5e-11: max |d alpha|/max|alpha| = %.2g, amplitude %.2g, "
                   "frequency %.2g (relative)",
                   dmax / ymax, fabs(oa.amp - ob.amp) / ob.amp, fabs(oa.freq - ob.freq) / ob.freq);
    TEST_MESSAGE(msg);
    TEST_ASSERT_TRUE(dmax / ymax < 1e-6);
    TEST_ASSERT_TRUE(fabs(oa.amp - ob.amp) / ob.amp < 1e-6);
    TEST_ASSERT_TRUE(fabs(oa.freq - ob.freq) / ob.freq < 1e-6);
}

static double max_diff(const aenl_sim_result_t *a, const aenl_sim_result_t *b)
{
    double d = 0.0;
    size_t k;
    for (k = 0; k < a->n_samples * a->n_channels; ++k)
    {
        d = fmax(d, fabs(a->y[k] - b->y[k]));
    }
    return d;
}

static void test_freeplay_rk4_converges_to_event_solution(void)
{
    /* No missed crossings: the naive RK4 (branch from the state at each stage) converges to the
     * event-located solution as h shrinks (the reference: 1.2e-6 relative at h = 0.02). */
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_sim_result_t ev, rk1, rk2;
    aenl_err_t err;
    double d1, d2;
    aenl_err_clear(&err);
    airfoil(&m, &r, 5.5, 1.0, 300.0);
    pitch_freeplay(&m);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate(&m, &r, &ev, &err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate_rk4(&m, &r, 0.02, &rk1, &err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate_rk4(&m, &r, 0.005, &rk2, &err));
    d1 = max_diff(&ev, &rk1) / (1.621 * DEG);
    d2 = max_diff(&ev, &rk2) / (1.621 * DEG);
    aenl_sim_result_free(&ev);
    aenl_sim_result_free(&rk1);
    aenl_sim_result_free(&rk2);
    TEST_ASSERT_TRUE(d1 < 1e-4);
    TEST_ASSERT_TRUE(d2 < d1 / 4.0);
}

static void test_two_freeplays_flap_and_pitch(void)
{
    /* Freeplay in flap and in pitch at once (3-DOF): runs without chatter, both DOFs switch, and
     * naive RK4 converges to it. */
    aenl_sim_model_t m;
    aenl_sim_run_t r;
    aenl_sim_result_t ev, rk1, rk2;
    aenl_err_t err;
    double d1, d2;
    aenl_err_clear(&err);
    aenl_sim_model_default(&m, AENL_SIM_SECTION3DOF);
    m.section.velocity = 15.0;
    m.x0[AENL_SIM_DOF_PITCH] = 1.0 * DEG;
    m.law[AENL_SIM_DOF_FLAP].kind = AENL_SIM_LAW_FREEPLAY;
    m.law[AENL_SIM_DOF_FLAP].delta = 2.0 * DEG;
    m.law[AENL_SIM_DOF_FLAP].x_f = -1.0 * DEG;
    m.law[AENL_SIM_DOF_PITCH].kind = AENL_SIM_LAW_FREEPLAY;
    m.law[AENL_SIM_DOF_PITCH].delta = 0.2 * DEG;
    m.law[AENL_SIM_DOF_PITCH].x_f = -0.1 * DEG;
    aenl_sim_run_default(&r, AENL_SIM_SECTION3DOF);
    r.duration = 1.0;
    r.dt = 1e-3;
    TEST_ASSERT_EQUAL_INT_MESSAGE(AENL_OK, aenl_sim_simulate(&m, &r, &ev, &err), err.msg);
    TEST_ASSERT_TRUE(ev.info.n_events > 20);
    TEST_ASSERT_TRUE(ev.info.n_events < 2000);
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate_rk4(&m, &r, 4e-5, &rk1, &err));
    TEST_ASSERT_EQUAL_INT(AENL_OK, aenl_sim_simulate_rk4(&m, &r, 1e-5, &rk2, &err));
    d1 = max_diff(&ev, &rk1);
    d2 = max_diff(&ev, &rk2);
    aenl_sim_result_free(&ev);
    aenl_sim_result_free(&rk1);
    aenl_sim_result_free(&rk2);
    TEST_ASSERT_TRUE(d1 < 1e-4 * DEG * 10.0);
    TEST_ASSERT_TRUE(d2 < d1 / 2.0);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_lco_pitch_freeplay_table);
    RUN_TEST(test_lco_cubic_table);
    RUN_TEST(test_lco_hysteresis_table);
    RUN_TEST(test_hysteresis_dissipative_loop_sticks);
    RUN_TEST(test_hysteresis_holds_the_centred_freeplay);
    RUN_TEST(test_kick_frees_a_stuck_hysteresis_dof);
    RUN_TEST(test_lco_section3dof_flap_freeplay_table);
    RUN_TEST(test_freeplay_tolerance_convergence);
    RUN_TEST(test_freeplay_rk4_converges_to_event_solution);
    RUN_TEST(test_two_freeplays_flap_and_pitch);
    return UNITY_END();
}
