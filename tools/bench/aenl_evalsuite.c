/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_evalsuite.c
 * @brief The identification evaluation suite (aenl_evalsuite.h): strata, law and velocity
 *        design from the describing function and the linear flutter analysis, simulation,
 *        materiality checks, measurement noise and INI output.
 */
#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aenl_evalsuite.h"
#include "aenl_tools/aenl_rng.h"
#include "aenl_tools/aenl_sort.h"

#define PI       3.14159265358979323846
#define DEG      (PI / 180.0)
#define DF_N     256 /* samples of one cycle for the describing function */
#define N_SET    10  /* stiffnesses checked by the decay/turbulence velocity design */
#define N_SCAN   48  /* velocity grid of the designs */
#define N_BISECT 40

/* ---- strata --------------------------------------------------------------------------------- */

typedef struct slot
{
    aenl_eval_variant_t variant;
    aenl_sim_type_t model;
    int dof;
    aenl_eval_regime_t regime;
} slot_t;

#define A2 AENL_SIM_AIRFOIL2DOF
#define S3 AENL_SIM_SECTION3DOF
#define PT AENL_SIM_DOF_PITCH
#define PL AENL_SIM_DOF_PLUNGE
#define FL AENL_SIM_DOF_FLAP
#define DC AENL_EVAL_DECAY
#define LC AENL_EVAL_LCO
#define TB AENL_EVAL_TURBULENCE

/* Per variant, the physically possible (model, DOF, regime) combinations (see the header). */
static const slot_t k_linear[8] = {{AENL_EVAL_LINEAR, A2, -1, DC}, {AENL_EVAL_LINEAR, S3, -1, TB},
                                   {AENL_EVAL_LINEAR, S3, -1, DC}, {AENL_EVAL_LINEAR, A2, -1, TB},
                                   {AENL_EVAL_LINEAR, A2, -1, DC}, {AENL_EVAL_LINEAR, S3, -1, TB},
                                   {AENL_EVAL_LINEAR, S3, -1, DC}, {AENL_EVAL_LINEAR, A2, -1, TB}};
static const slot_t k_hard[12] = {
    {AENL_EVAL_HARDENING, A2, PT, LC}, {AENL_EVAL_HARDENING, S3, FL, DC},
    {AENL_EVAL_HARDENING, A2, PL, TB}, {AENL_EVAL_HARDENING, S3, PT, LC},
    {AENL_EVAL_HARDENING, A2, PT, DC}, {AENL_EVAL_HARDENING, S3, PL, TB},
    {AENL_EVAL_HARDENING, S3, PT, DC}, {AENL_EVAL_HARDENING, A2, PT, TB},
    {AENL_EVAL_HARDENING, S3, PL, DC}, {AENL_EVAL_HARDENING, S3, FL, TB},
    {AENL_EVAL_HARDENING, A2, PL, DC}, {AENL_EVAL_HARDENING, S3, PT, TB}};
static const slot_t k_soft[14] = {
    {AENL_EVAL_SOFTENING, A2, PL, LC}, {AENL_EVAL_SOFTENING, S3, PT, DC},
    {AENL_EVAL_SOFTENING, A2, PT, TB}, {AENL_EVAL_SOFTENING, S3, PT, LC},
    {AENL_EVAL_SOFTENING, S3, FL, DC}, {AENL_EVAL_SOFTENING, A2, PL, TB},
    {AENL_EVAL_SOFTENING, A2, PT, LC}, {AENL_EVAL_SOFTENING, S3, PL, DC},
    {AENL_EVAL_SOFTENING, S3, FL, TB}, {AENL_EVAL_SOFTENING, S3, PL, LC},
    {AENL_EVAL_SOFTENING, A2, PT, DC}, {AENL_EVAL_SOFTENING, S3, PT, TB},
    {AENL_EVAL_SOFTENING, A2, PL, DC}, {AENL_EVAL_SOFTENING, S3, PL, TB}};
static const slot_t k_free[13] = {
    {AENL_EVAL_FREEPLAY, S3, FL, LC}, {AENL_EVAL_FREEPLAY, A2, PT, DC},
    {AENL_EVAL_FREEPLAY, S3, PL, TB}, {AENL_EVAL_FREEPLAY, A2, PT, LC},
    {AENL_EVAL_FREEPLAY, S3, FL, DC}, {AENL_EVAL_FREEPLAY, A2, PT, TB},
    {AENL_EVAL_FREEPLAY, S3, PT, LC}, {AENL_EVAL_FREEPLAY, A2, PL, DC},
    {AENL_EVAL_FREEPLAY, S3, FL, TB}, {AENL_EVAL_FREEPLAY, S3, PT, DC},
    {AENL_EVAL_FREEPLAY, A2, PL, TB}, {AENL_EVAL_FREEPLAY, S3, PL, DC},
    {AENL_EVAL_FREEPLAY, S3, PT, TB}};
static const slot_t k_hyst[13] = {
    {AENL_EVAL_HYSTERESIS, A2, PT, LC}, {AENL_EVAL_HYSTERESIS, S3, PT, TB},
    {AENL_EVAL_HYSTERESIS, A2, PL, DC}, {AENL_EVAL_HYSTERESIS, S3, FL, LC},
    {AENL_EVAL_HYSTERESIS, A2, PT, TB}, {AENL_EVAL_HYSTERESIS, S3, PL, DC},
    {AENL_EVAL_HYSTERESIS, S3, PT, LC}, {AENL_EVAL_HYSTERESIS, S3, FL, TB},
    {AENL_EVAL_HYSTERESIS, A2, PT, DC}, {AENL_EVAL_HYSTERESIS, A2, PL, TB},
    {AENL_EVAL_HYSTERESIS, S3, FL, DC}, {AENL_EVAL_HYSTERESIS, S3, PL, TB},
    {AENL_EVAL_HYSTERESIS, S3, PT, DC}};

/* Slot k of the interleaved order: round robin over the variants' lists. */
static slot_t slot_at(size_t k)
{
    const slot_t *lists[AENL_EVAL_N_VARIANTS] = {k_linear, k_hard, k_soft, k_free, k_hyst};
    const size_t len[AENL_EVAL_N_VARIANTS] = {8, 12, 14, 13, 13};
    size_t round = 0, seen = 0;
    k %= AENL_EVAL_N_SLOTS;
    for (;;)
    {
        for (size_t v = 0; v < AENL_EVAL_N_VARIANTS; ++v)
        {
            if (round < len[v])
            {
                if (seen == k)
                {
                    return lists[v][round];
                }
                ++seen;
            }
        }
        ++round;
    }
}

void aenl_eval_stratum_of(size_t index, aenl_eval_stratum_t *s)
{
    static const double k_snr[AENL_EVAL_N_SNR] = {0.0, 10.0, 3.0, 2.0};
    const size_t k = index % AENL_EVAL_N_SLOTS;
    const slot_t sl = slot_at(k);
    s->variant = sl.variant;
    s->model = sl.model;
    s->dof = sl.dof;
    s->regime = sl.regime;
    s->snr_level = (unsigned)((index / AENL_EVAL_N_SLOTS + k) % AENL_EVAL_N_SNR);
    s->snr = k_snr[s->snr_level];
}

const char *aenl_eval_variant_name(aenl_eval_variant_t v)
{
    switch (v)
    {
        case AENL_EVAL_LINEAR:
            return "linear";
        case AENL_EVAL_HARDENING:
            return "hardening";
        case AENL_EVAL_SOFTENING:
            return "softening";
        case AENL_EVAL_FREEPLAY:
            return "freeplay";
        case AENL_EVAL_HYSTERESIS:
            return "hysteresis";
        default:
            return "unknown";
    }
}

const char *aenl_eval_regime_name(aenl_eval_regime_t r)
{
    switch (r)
    {
        case AENL_EVAL_DECAY:
            return "decay";
        case AENL_EVAL_LCO:
            return "lco";
        case AENL_EVAL_TURBULENCE:
            return "turbulence";
        default:
            return "unknown";
    }
}

const char *aenl_eval_dof_name(int dof)
{
    switch (dof)
    {
        case AENL_SIM_DOF_PITCH:
            return "pitch";
        case AENL_SIM_DOF_PLUNGE:
            return "plunge";
        case AENL_SIM_DOF_FLAP:
            return "flap";
        default:
            return "-";
    }
}

/* Output column of a DOF: airfoil2dof (alpha, xi), section3dof (h, alpha, beta). */
static long dof_column(aenl_sim_type_t type, int dof)
{
    if (type == AENL_SIM_AIRFOIL2DOF)
    {
        return dof == AENL_SIM_DOF_PITCH ? 0 : 1;
    }
    return dof == AENL_SIM_DOF_PLUNGE ? 0 : (dof == AENL_SIM_DOF_PITCH ? 1 : 2);
}

static const char *column_name(aenl_sim_type_t type, long col)
{
    static const char *const k2[2] = {"alpha", "xi"};
    static const char *const k3[3] = {"h", "alpha", "beta"};
    if (col < 0 || col > (type == AENL_SIM_AIRFOIL2DOF ? 1 : 2))
    {
        return "";
    }
    return type == AENL_SIM_AIRFOIL2DOF ? k2[col] : k3[col];
}

/* ---- random draws --------------------------------------------------------------------------- */

static uint64_t mix64(uint64_t z)
{
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double uni(aenl_rng_t *r, double lo, double hi)
{
    return lo + (hi - lo) * aenl_rng_uniform(r);
}

static double logu(aenl_rng_t *r, double lo, double hi)
{
    return lo * pow(hi / lo, aenl_rng_uniform(r));
}

static int chance(aenl_rng_t *r, double p)
{
    return aenl_rng_uniform(r) < p;
}

/* ---- laws at unit amplitude, describing function ------------------------------------------- */

/* The law scaled from unit amplitude to amplitude a: lengths times a, polynomial c_k / a^(k-1). */
static aenl_sim_law_t law_scaled(const aenl_sim_law_t *unit, double a)
{
    aenl_sim_law_t l = *unit;
    if (l.kind == AENL_SIM_LAW_FREEPLAY || l.kind == AENL_SIM_LAW_HYSTERESIS)
    {
        l.delta *= a;
        l.x_f *= a;
        l.preload *= a;
    }
    else if (l.kind == AENL_SIM_LAW_POLYNOMIAL)
    {
        double p = 1.0;
        for (size_t k = 1; k < l.n_coeffs; ++k)
        {
            p *= a;
            l.coeffs[k] /= p;
        }
    }
    return l;
}

/* Restoring force at phase k of x = c + a sin θ (hysteresis branch from the sign of cos θ). */
static double cycle_force(const aenl_sim_law_t *law, double c, double a, int k)
{
    const double th = 2.0 * PI * ((double)k + 0.5) / DF_N;
    return aenl_sim_law_eval(law, c + a * sin(th), cos(th) >= 0.0 ? 1 : -1);
}

static double cycle_mean(const aenl_sim_law_t *law, double c, double a)
{
    double s = 0.0;
    for (int k = 0; k < DF_N; ++k)
    {
        s += cycle_force(law, c, a, k);
    }
    return s / DF_N;
}

/* Centre of an oscillation of amplitude a: the mean restoring force over the cycle is zero
 * (bisection; the mean force rises with the centre for every law here). */
static double df_center(const aenl_sim_law_t *law, double a)
{
    double lo = -3.0 - 3.0 * a, hi = 3.0 + 3.0 * a;
    if (law->kind == AENL_SIM_LAW_LINEAR)
    {
        return 0.0;
    }
    for (int it = 0; it < 60; ++it)
    {
        const double mid = 0.5 * (lo + hi);
        if (cycle_mean(law, mid, a) > 0.0)
        {
            hi = mid;
        }
        else
        {
            lo = mid;
        }
    }
    return 0.5 * (lo + hi);
}

/* First-harmonic in-phase stiffness N(a) about the centre c. */
static double df_stiffness(const aenl_sim_law_t *law, double c, double a)
{
    double s = 0.0;
    for (int k = 0; k < DF_N; ++k)
    {
        const double th = 2.0 * PI * ((double)k + 0.5) / DF_N;
        s += cycle_force(law, c, a, k) * sin(th);
    }
    return 2.0 * s / (DF_N * a);
}

static double df_at(const aenl_sim_law_t *law, double a)
{
    return df_stiffness(law, df_center(law, a), a);
}

/* ---- linear stability ----------------------------------------------------------------------- */

typedef struct stab
{
    double growth; /* largest real part of the non-neutral eigenvalues */
    double zeta;   /* least damping of the oscillatory modes */
    double omega;  /* Im λ of that least-damped mode, rad per model time unit */
} stab_t;

static aenl_status_t stab_eval(const aenl_sim_model_t *m, int dof, double n_slope, double v,
                               stab_t *out, aenl_err_t *err)
{
    double A[AENL_SIM_MAX_X * AENL_SIM_MAX_X], wr[AENL_SIM_MAX_X], wi[AENL_SIM_MAX_X];
    double vl[1], vr[1], slope[AENL_SIM_N_DOF] = {1.0, 1.0, 1.0};
    size_t n = 0;
    aenl_status_t st;
    if (dof >= 0)
    {
        slope[dof] = n_slope;
    }
    if ((st = aenl_sim_state_matrix(m, v, slope, A, &n, err)) != AENL_OK)
    {
        return st;
    }
    if (LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'N', (lapack_int)n, A, (lapack_int)n, wr, wi, vl, 1,
                      vr, 1) != 0)
    {
        aenl_err_set(err, "eigenvalues failed at velocity %g", v);
        return AENL_E_NUMERIC;
    }
    out->growth = -HUGE_VAL;
    out->zeta = HUGE_VAL;
    out->omega = 0.0;
    for (size_t i = 0; i < n; ++i)
    {
        const double mag = hypot(wr[i], wi[i]);
        if (mag < 1e-9)
        {
            continue; /* neutral: zero total stiffness */
        }
        out->growth = fmax(out->growth, wr[i]);
        if (wi[i] > 0.0 && -wr[i] / mag < out->zeta)
        {
            out->zeta = -wr[i] / mag;
            out->omega = wi[i];
        }
    }
    return AENL_OK;
}

/* Index of a DOF in q (state order q, q̇, aero states): airfoil2dof q = (ξ, α), section3dof
 * q = (h, α, β). */
static size_t q_index(aenl_sim_type_t type, int dof)
{
    if (type == AENL_SIM_AIRFOIL2DOF)
    {
        return dof == AENL_SIM_DOF_PITCH ? 1u : 0u;
    }
    return dof == AENL_SIM_DOF_PLUNGE ? 0u : (dof == AENL_SIM_DOF_PITCH ? 1u : 2u);
}

/* The oscillatory mode in which DOF `of` has the largest share of the displacement eigenvector
 * (|φ_of|² / Σ_q |φ_q|²), at velocity v with the nonlinear DOF at slope n: the mode a kick in
 * that DOF, or its own response, is dominated by. */
static aenl_status_t dof_mode(const aenl_sim_model_t *m, int dof, int of, double n_slope, double v,
                              double *omega, aenl_err_t *err)
{
    double A[AENL_SIM_MAX_X * AENL_SIM_MAX_X], vr[AENL_SIM_MAX_X * AENL_SIM_MAX_X];
    double wr[AENL_SIM_MAX_X], wi[AENL_SIM_MAX_X], vl[1], slope[AENL_SIM_N_DOF] = {1.0, 1.0, 1.0};
    double best = -1.0;
    size_t n = 0;
    aenl_status_t st;
    const size_t nq = m->type == AENL_SIM_AIRFOIL2DOF ? 2u : 3u, k = q_index(m->type, of);
    if (dof >= 0)
    {
        slope[dof] = n_slope;
    }
    if ((st = aenl_sim_state_matrix(m, v, slope, A, &n, err)) != AENL_OK)
    {
        return st;
    }
    if (LAPACKE_dgeev(LAPACK_ROW_MAJOR, 'N', 'V', (lapack_int)n, A, (lapack_int)n, wr, wi, vl, 1,
                      vr, (lapack_int)n) != 0)
    {
        aenl_err_set(err, "eigenvectors failed at velocity %g", v);
        return AENL_E_NUMERIC;
    }
    *omega = 0.0;
    for (size_t j = 0; j + 1 < n; ++j)
    {
        if (!(wi[j] > 0.0))
        {
            continue;
        }
        double tot = 0.0, mine = 0.0;
        for (size_t r = 0; r < nq; ++r)
        {
            const double e = vr[r * n + j] * vr[r * n + j] + vr[r * n + j + 1] * vr[r * n + j + 1];
            tot += e;
            mine += r == k ? e : 0.0;
        }
        if (tot > 0.0 && mine / tot > best)
        {
            best = mine / tot;
            *omega = wi[j];
        }
    }
    return AENL_OK;
}

/* ---- the design of one attempt -------------------------------------------------------------- */

typedef struct design
{
    aenl_rng_t rng;
    aenl_eval_case_t *c;
    int dof;
    aenl_sim_law_t unit;     /* the law at unit amplitude */
    double center;           /* centre of the unit-amplitude oscillation */
    double v_lo, v_hi;       /* velocities a test could fly */
    double omega;            /* dominant angular frequency, per model time unit */
    double decay_factor;     /* decay: designed amplitude ratio over one release */
    int kick_dof;            /* the DOF kicked (decay), displaced (LCO) or watched (turbulence) */
    double kick_gain;        /* decay: kick scale from the pilot ring-down */
    char why[96];            /* rejection reason */
    aenl_eval_options_t opt; /* simulator variant */
} design_t;

/* One run of the design's simulator (the event integrator, or naive RK4). */
static aenl_status_t simulate(const design_t *d, const aenl_sim_model_t *m, const aenl_sim_run_t *r,
                              aenl_sim_result_t *res, aenl_err_t *err)
{
    if (d->opt.rk4)
    {
        return aenl_sim_simulate_rk4(m, r, r->dt / AENL_EVAL_RK4_STEPS, res, err);
    }
    return aenl_sim_simulate(m, r, res, err);
}

static void draw_model(design_t *d)
{
    aenl_sim_model_t *m = &d->c->model;
    aenl_sim_model_default(m, d->c->stratum.model);
    if (m->type == AENL_SIM_AIRFOIL2DOF)
    {
        m->airfoil.mu = uni(&d->rng, 70.0, 130.0);
        m->airfoil.omega_bar = uni(&d->rng, 0.15, 0.3);
        m->airfoil.zeta_alpha = uni(&d->rng, 0.0, 0.005);
        m->airfoil.zeta_xi = uni(&d->rng, 0.0, 0.005);
        d->v_lo = 0.3;
        d->v_hi = 20.0;
    }
    else
    {
        d->v_lo = 1.5;
        d->v_hi = 60.0;
    }
}

/* Amplitude range of the DOF (its own unit). */
static void dof_range(aenl_sim_type_t type, int dof, double *lo, double *hi)
{
    if (dof == AENL_SIM_DOF_PLUNGE)
    {
        *lo = type == AENL_SIM_AIRFOIL2DOF ? 0.02 : 0.002;
        *hi = type == AENL_SIM_AIRFOIL2DOF ? 0.2 : 0.02;
    }
    else if (dof == AENL_SIM_DOF_PITCH && type == AENL_SIM_SECTION3DOF)
    {
        *lo = 0.5 * DEG;
        *hi = 4.0 * DEG;
    }
    else
    {
        *lo = 1.0 * DEG;
        *hi = 6.0 * DEG;
    }
}

static void draw_polynomial(design_t *d, int softening)
{
    aenl_sim_law_t *l = &d->unit;
    const aenl_eval_regime_t rg = d->c->stratum.regime;
    double s;
    memset(l, 0, sizeof(*l));
    l->kind = AENL_SIM_LAW_POLYNOMIAL;
    l->coeffs[0] = 1.0;
    if (!softening)
    {
        s = rg == AENL_EVAL_LCO
                ? uni(&d->rng, 0.6, 1.5)
                : (rg == AENL_EVAL_DECAY ? uni(&d->rng, 2.5, 6.0) : uni(&d->rng, 1.0, 5.0));
        l->n_coeffs = 3;
        l->coeffs[2] = s;
        return;
    }
    const double cq = uni(&d->rng, 0.5, 0.55);
    if (rg == AENL_EVAL_LCO)
    {
        s = d->dof == AENL_SIM_DOF_PLUNGE ? uni(&d->rng, 0.6, 0.95) : uni(&d->rng, 1.4, 3.0);
    }
    else
    {
        s = rg == AENL_EVAL_DECAY ? uni(&d->rng, 1.8, 2.5) : uni(&d->rng, 0.4, 1.0);
    }
    l->n_coeffs = 5;
    l->coeffs[2] = -s;
    l->coeffs[4] = cq * s * s;
}

static void draw_freeplay(design_t *d)
{
    aenl_sim_law_t *l = &d->unit;
    const aenl_eval_regime_t rg = d->c->stratum.regime;
    const double r = rg == AENL_EVAL_LCO ? uni(&d->rng, 0.15, 0.5)
                                         : (rg == AENL_EVAL_DECAY ? uni(&d->rng, 0.1, 0.35)
                                                                  : uni(&d->rng, 0.3, 0.8));
    double centre = 0.0;
    memset(l, 0, sizeof(*l));
    l->kind = AENL_SIM_LAW_FREEPLAY;
    l->delta = 2.0 * r;
    if (chance(&d->rng, 0.5))
    {
        centre = chance(&d->rng, 0.5) ? r : uni(&d->rng, -l->delta, l->delta);
    }
    l->x_f = centre - r;
    if (chance(&d->rng, 1.0 / 3.0))
    {
        l->preload = (chance(&d->rng, 0.5) ? 1.0 : -1.0) * uni(&d->rng, 0.05, 0.3) * l->delta;
    }
    const int need_inner = d->c->stratum.model == AENL_SIM_SECTION3DOF &&
                           d->dof == AENL_SIM_DOF_PITCH && rg != AENL_EVAL_LCO;
    if (need_inner || chance(&d->rng, 1.0 / 3.0))
    {
        l->inner_stiffness = uni(&d->rng, 0.1, 0.4);
    }
}

static void draw_hysteresis(design_t *d)
{
    aenl_sim_law_t *l = &d->unit;
    const aenl_eval_regime_t rg = d->c->stratum.regime;
    const double rho = rg == AENL_EVAL_LCO ? uni(&d->rng, 0.2, 0.6)
                                           : (rg == AENL_EVAL_DECAY ? uni(&d->rng, 0.1, 0.35)
                                                                    : uni(&d->rng, 0.3, 0.8));
    const double q = chance(&d->rng, 0.5) ? 0.0 : uni(&d->rng, 0.25, 0.5);
    memset(l, 0, sizeof(*l));
    l->kind = AENL_SIM_LAW_HYSTERESIS;
    l->delta = rho / (1.0 + q);
    l->x_f = q * l->delta;
    /* LCO: the outer loop injects energy (M0 < α_f + δ/2); decay: a dissipative loop. */
    if (rg == AENL_EVAL_DECAY)
    {
        l->preload = l->x_f + uni(&d->rng, 0.5, 0.75) * l->delta;
    }
    else
    {
        l->preload = uni(&d->rng, 0.0, l->x_f + (rg == AENL_EVAL_LCO ? 0.25 : 0.5) * l->delta);
    }
}

static void draw_law(design_t *d)
{
    switch (d->c->stratum.variant)
    {
        case AENL_EVAL_HARDENING:
            draw_polynomial(d, 0);
            break;
        case AENL_EVAL_SOFTENING:
            draw_polynomial(d, 1);
            break;
        case AENL_EVAL_FREEPLAY:
            draw_freeplay(d);
            break;
        case AENL_EVAL_HYSTERESIS:
            draw_hysteresis(d);
            break;
        case AENL_EVAL_LINEAR:
        default:
            memset(&d->unit, 0, sizeof(d->unit));
            d->unit.kind = AENL_SIM_LAW_LINEAR;
            break;
    }
    d->center = df_center(&d->unit, 1.0);
}

static double grid_v(const design_t *d, int k)
{
    return d->v_lo * pow(d->v_hi / d->v_lo, (double)k / (N_SCAN - 1));
}

/* Lowest velocity of the range where the system at stiffness n is unstable (0: none). */
static aenl_status_t instability_speed(const design_t *d, double n, double *v_out, double *omega,
                                       aenl_err_t *err)
{
    double v_prev = d->v_lo;
    stab_t s;
    aenl_status_t st;
    *v_out = 0.0;
    if ((st = stab_eval(&d->c->model, d->dof, n, v_prev, &s, err)) != AENL_OK)
    {
        return st;
    }
    if (s.growth > 0.0)
    {
        return AENL_OK; /* unstable from the bottom of the range: no usable crossing */
    }
    for (int k = 1; k < N_SCAN; ++k)
    {
        const double v = grid_v(d, k);
        if ((st = stab_eval(&d->c->model, d->dof, n, v, &s, err)) != AENL_OK)
        {
            return st;
        }
        if (s.growth > 0.0)
        {
            double lo = v_prev, hi = v;
            for (int it = 0; it < N_BISECT; ++it)
            {
                const double mid = 0.5 * (lo + hi);
                if ((st = stab_eval(&d->c->model, d->dof, n, mid, &s, err)) != AENL_OK)
                {
                    return st;
                }
                if (s.growth > 0.0)
                {
                    hi = mid;
                }
                else
                {
                    lo = mid;
                }
            }
            if ((st = stab_eval(&d->c->model, d->dof, n, hi, &s, err)) != AENL_OK)
            {
                return st;
            }
            *v_out = 0.5 * (lo + hi);
            *omega = s.omega > 0.0 ? s.omega : 0.0;
            return AENL_OK;
        }
        v_prev = v;
    }
    return AENL_OK;
}

/* LCO: the velocity where the system linearised at N(A) is neutral, if the cycle is stable
 * there (larger amplitude damped, smaller amplitude growing). */
static aenl_status_t design_lco(design_t *d, aenl_err_t *err)
{
    const double n_star = df_at(&d->unit, 1.0);
    const double n_big = df_at(&d->unit, 1.15), n_small = df_at(&d->unit, 1.0 / 1.15);
    double v = 0.0, om = 0.0;
    stab_t sb, ss;
    aenl_status_t st;
    if ((st = instability_speed(d, n_star, &v, &om, err)) != AENL_OK)
    {
        return st;
    }
    if (!(v > 0.0))
    {
        (void)snprintf(d->why, sizeof(d->why), "no flutter speed at N = %.3f", n_star);
        return AENL_E_NUMERIC;
    }
    if ((st = stab_eval(&d->c->model, d->dof, n_big, v, &sb, err)) != AENL_OK ||
        (st = stab_eval(&d->c->model, d->dof, n_small, v, &ss, err)) != AENL_OK)
    {
        return st;
    }
    if (!(sb.growth < 0.0) || !(ss.growth > 0.0))
    {
        (void)snprintf(d->why, sizeof(d->why), "unstable cycle (N %.3f at %.4g)", n_star, v);
        return AENL_E_NUMERIC;
    }
    aenl_sim_set_velocity(&d->c->model, v);
    d->omega = om;
    return AENL_OK;
}

/* Largest growth rate over the stiffnesses nset at velocity v. */
static aenl_status_t growth_over(const design_t *d, const double *nset, size_t nn, double v,
                                 double *g, aenl_err_t *err)
{
    *g = -HUGE_VAL;
    for (size_t i = 0; i < nn; ++i)
    {
        stab_t s;
        const aenl_status_t st = stab_eval(&d->c->model, d->dof, nset[i], v, &s, err);
        if (st != AENL_OK)
        {
            return st;
        }
        *g = fmax(*g, s.growth);
    }
    return AENL_OK;
}

/* Lowest velocity of the range where the system is unstable at one of the stiffnesses nset
 * (v_hi when none is). */
static aenl_status_t critical_speed(const design_t *d, const double *nset, size_t nn, double *vc,
                                    aenl_err_t *err)
{
    double g = 0.0, lo = d->v_lo;
    *vc = d->v_hi;
    for (int k = 0; k < N_SCAN; ++k)
    {
        const double v = grid_v(d, k);
        aenl_status_t st = growth_over(d, nset, nn, v, &g, err);
        if (st != AENL_OK)
        {
            return st;
        }
        if (g > 0.0)
        {
            double hi = v;
            for (int it = 0; it < N_BISECT && k > 0; ++it)
            {
                const double mid = 0.5 * (lo + hi);
                if ((st = growth_over(d, nset, nn, mid, &g, err)) != AENL_OK)
                {
                    return st;
                }
                if (g > 0.0)
                {
                    hi = mid;
                }
                else
                {
                    lo = mid;
                }
            }
            *vc = k > 0 ? lo : 0.0;
            return AENL_OK;
        }
        lo = v;
    }
    return AENL_OK;
}

/* Stiffnesses met by an oscillation whose amplitude ranges over (0, a_max]. */
static size_t stiffness_set(const design_t *d, double a_max, double nset[N_SET + 1])
{
    static const double k_frac[N_SET] = {0.02, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.75, 0.9, 1.0};
    if (d->dof < 0)
    {
        nset[0] = 1.0;
        return 1;
    }
    for (size_t i = 0; i < N_SET; ++i)
    {
        nset[i] = df_at(&d->unit, k_frac[i] * a_max);
    }
    /* slope 1: the small-amplitude limit of a polynomial, the large-amplitude one of a gap */
    nset[N_SET] = 1.0;
    return N_SET + 1;
}

/* Decay and turbulence: a test point at a fraction of the lowest instability speed over the
 * stiffnesses the law meets (amplitudes up to 1.25 A for releases, 2 A for turbulence), and the
 * dominant mode of the watched DOF there. LCO: design_lco. */
static aenl_status_t design_velocity(design_t *d, aenl_err_t *err)
{
    aenl_eval_case_t *c = d->c;
    double nset[N_SET + 1], vc = 0.0;
    aenl_status_t st;
    if (c->stratum.regime == AENL_EVAL_LCO)
    {
        return design_lco(d, err);
    }
    const int decay = c->stratum.regime == AENL_EVAL_DECAY;
    if (decay)
    {
        d->decay_factor = uni(&d->rng, 3.0, 10.0);
    }
    if ((st = critical_speed(d, nset, stiffness_set(d, decay ? 1.25 : 2.0, nset), &vc, err)) !=
        AENL_OK)
    {
        return st;
    }
    const double v = vc * (decay ? uni(&d->rng, 0.5, 0.95) : uni(&d->rng, 0.5, 0.9));
    if (v < d->v_lo)
    {
        (void)snprintf(d->why, sizeof(d->why), "critical speed %.3g too low", vc);
        return AENL_E_NUMERIC;
    }
    aenl_sim_set_velocity(&c->model, v);
    return dof_mode(&c->model, d->dof, d->kick_dof, df_at(&d->unit, 1.0), v, &d->omega, err);
}

/* ---- run settings, amplitude, truth --------------------------------------------------------- */

static aenl_status_t pilot_rms(design_t *d, double *rms, aenl_err_t *err)
{
    aenl_sim_model_t m = d->c->model;
    aenl_sim_run_t r = d->c->run;
    aenl_sim_result_t res;
    const long col = dof_column(m.type, d->dof);
    const size_t n = d->c->n_samples < 8000 ? d->c->n_samples : 8000;
    aenl_status_t st;
    double s = 0.0, s2 = 0.0;
    m.law[d->dof].kind = AENL_SIM_LAW_LINEAR;
    r.duration = (double)(n - 1) * r.dt;
    r.snr = 0.0;
    if ((st = simulate(d, &m, &r, &res, err)) != AENL_OK)
    {
        return st;
    }
    const double *y = res.y + (size_t)col * res.n_samples;
    for (size_t k = 0; k < res.n_samples; ++k)
    {
        s += y[k];
        s2 += y[k] * y[k];
    }
    const double mean = s / (double)res.n_samples;
    *rms = sqrt(fmax(s2 / (double)res.n_samples - mean * mean, 0.0));
    aenl_sim_result_free(&res);
    return AENL_OK;
}

static double flutter_ratio(const design_t *d)
{
    design_t tmp = *d;
    double v = 0.0, om = 0.0;
    aenl_err_t e;
    tmp.dof = -1;
    tmp.v_hi = 4.0 * d->v_hi;
    if (instability_speed(&tmp, 1.0, &v, &om, &e) != AENL_OK || !(v > 0.0))
    {
        return 0.0;
    }
    return aenl_sim_velocity(&d->c->model) / v;
}

static void fill_truth(design_t *d)
{
    aenl_eval_case_t *c = d->c;
    const aenl_sim_law_t *l = &c->model.law[d->dof < 0 ? 0 : d->dof];
    c->n_switch = 0;
    c->gap = 0.0;
    c->hardening = 0;
    c->channel = "";
    c->channel_index = -1;
    c->cls = AENL_CLASS_LINEAR;
    if (d->dof < 0)
    {
        return;
    }
    c->channel_index = dof_column(c->model.type, d->dof);
    c->channel = column_name(c->model.type, c->channel_index);
    switch (c->stratum.variant)
    {
        case AENL_EVAL_HARDENING:
        case AENL_EVAL_SOFTENING:
            c->cls = AENL_CLASS_POLYNOMIAL;
            c->hardening = c->stratum.variant == AENL_EVAL_HARDENING ? 1 : -1;
            break;
        case AENL_EVAL_FREEPLAY:
        case AENL_EVAL_HYSTERESIS:
            c->cls = c->stratum.variant == AENL_EVAL_FREEPLAY ? AENL_CLASS_FREEPLAY
                                                              : AENL_CLASS_HYSTERESIS;
            c->gap = l->delta;
            c->n_switch = aenl_sim_law_switch_points(l, c->switch_points);
            break;
        case AENL_EVAL_LINEAR:
        default:
            break;
    }
}

static const char *unit_name(const aenl_eval_case_t *c)
{
    if (c->stratum.dof == AENL_SIM_DOF_PLUNGE)
    {
        return c->model.type == AENL_SIM_AIRFOIL2DOF ? "" : " m";
    }
    return " deg";
}

static double unit_scale(const aenl_eval_case_t *c)
{
    return c->stratum.dof == AENL_SIM_DOF_PLUNGE ? 1.0 : 1.0 / DEG;
}

static void law_text(const aenl_eval_case_t *c, char *buf, size_t cap)
{
    const aenl_sim_law_t *l = &c->model.law[c->stratum.dof < 0 ? 0 : c->stratum.dof];
    const double u = unit_scale(c);
    const char *un = unit_name(c);
    if (c->stratum.dof < 0)
    {
        (void)snprintf(buf, cap, "linear");
    }
    else if (l->kind == AENL_SIM_LAW_POLYNOMIAL)
    {
        (void)snprintf(buf, cap, "%s %s R = x %+.4g x^3%s", aenl_eval_dof_name(c->stratum.dof),
                       c->hardening > 0 ? "hardening" : "softening", l->coeffs[2],
                       l->n_coeffs > 4 ? " + q x^5" : "");
    }
    else
    {
        (void)snprintf(buf, cap, "%s %s gap [%.4g, %.4g]%s M0 %.3g%s Mf %.3g",
                       aenl_eval_dof_name(c->stratum.dof),
                       aenl_eval_variant_name(c->stratum.variant), l->x_f * u,
                       (l->x_f + l->delta) * u, un, l->preload * u, un, l->inner_stiffness);
    }
}

static void describe(design_t *d)
{
    aenl_eval_case_t *c = d->c;
    char law[160];
    law_text(c, law, sizeof(law));
    const int two = c->model.type == AENL_SIM_AIRFOIL2DOF;
    (void)snprintf(
        c->description, sizeof(c->description),
        "%s %s=%.4g (%.3f of flutter); %s; %s A %.4g%s; %zu samples, %.1f/period, SNR "
        "%s",
        two ? "airfoil2dof" : "section3dof", two ? "U*" : "U", aenl_sim_velocity(&c->model),
        c->velocity_ratio, law, aenl_eval_regime_name(c->stratum.regime),
        c->amplitude * (c->stratum.dof < 0 ? 1.0 / DEG : unit_scale(c)),
        c->stratum.dof < 0 ? " deg" : unit_name(c), c->n_samples, c->samples_per_period,
        c->stratum.snr > 0.0 ? (c->stratum.snr > 5.0 ? "10" : (c->stratum.snr > 2.5 ? "3" : "2"))
                             : "inf");
}

/* Sampling, velocity, amplitude, initial state and excitation of one attempt. */
static aenl_status_t design_attempt(design_t *d, aenl_err_t *err)
{
    aenl_eval_case_t *c = d->c;
    aenl_status_t st;
    double lo, hi;
    draw_model(d);
    c->n_samples = (size_t)(20000.0 + floor(aenl_rng_uniform(&d->rng) * 40001.0));
    c->samples_per_period = logu(&d->rng, 12.0, 60.0);
    draw_law(d);
    d->kick_dof =
        d->dof >= 0 ? d->dof : (chance(&d->rng, 0.7) ? AENL_SIM_DOF_PITCH : AENL_SIM_DOF_PLUNGE);
    if ((st = design_velocity(d, err)) != AENL_OK)
    {
        return st;
    }
    if (!(d->omega > 0.0))
    {
        (void)snprintf(d->why, sizeof(d->why), "no oscillatory mode");
        return AENL_E_NUMERIC;
    }
    aenl_sim_run_default(&c->run, c->model.type);
    /* The default 1e-10 costs 2-3x the time for no visible difference; with turbulence the
     * integrator restarts at every held gust value, so it gets 1e-7. */
    c->run.rtol = c->stratum.regime == AENL_EVAL_TURBULENCE ? 1e-7 : 1e-8;
    c->run.dt = 2.0 * PI / d->omega / c->samples_per_period;
    c->run.duration = (double)(c->n_samples - 1) * c->run.dt;
    c->run.snr = c->stratum.snr;
    c->run.noise_seed = aenl_rng_next(&d->rng) >> 16;
    const int ic_dof = d->kick_dof;
    dof_range(c->model.type, ic_dof, &lo, &hi);
    if (c->stratum.regime == AENL_EVAL_TURBULENCE)
    {
        c->run.turbulence = 1;
        c->run.turb_spectrum = d->opt.spectrum;
        c->run.turb_intensity = logu(&d->rng, 0.002, 0.02);
        c->run.turb_seed = aenl_rng_next(&d->rng) >> 16;
        c->amplitude = logu(&d->rng, lo, hi);
        if (d->dof >= 0)
        {
            double rms = 0.0;
            if ((st = pilot_rms(d, &rms, err)) != AENL_OK)
            {
                return st;
            }
            c->amplitude = sqrt(2.0) * rms;
        }
    }
    else if (c->stratum.regime == AENL_EVAL_DECAY)
    {
        /* Releases (run_releases; their length comes from a pilot ring-down). */
        c->amplitude = logu(&d->rng, lo, hi);
        c->model.x0[ic_dof] = d->center * c->amplitude;
        if (c->model.type == AENL_SIM_AIRFOIL2DOF)
        {
            c->model.airfoil.ic_forcing = 0; /* a release in established flow, not a start-up */
        }
    }
    else
    {
        c->amplitude = logu(&d->rng, lo, hi);
        c->model.x0[ic_dof] = (d->center + 1.0) * c->amplitude;
    }
    if (d->dof >= 0)
    {
        c->model.law[d->dof] = law_scaled(&d->unit, c->amplitude);
    }
    c->velocity_ratio = flutter_ratio(d);
    if ((st = aenl_sim_validate(&c->model, &c->run, err)) != AENL_OK)
    {
        return st;
    }
    fill_truth(d);
    describe(d);
    return AENL_OK;
}

static void design_init(design_t *d, aenl_eval_case_t *c, uint64_t suite_seed, size_t index,
                        unsigned attempt)
{
    memset(d, 0, sizeof(*d));
    memset(c, 0, sizeof(*c));
    c->suite_seed = suite_seed;
    c->index = index;
    c->attempt = attempt;
    aenl_eval_stratum_of(index, &c->stratum);
    d->c = c;
    d->dof = c->stratum.dof;
    aenl_rng_seed(&d->rng, mix64(mix64(mix64(suite_seed) ^ (uint64_t)index) ^ attempt));
}

aenl_status_t aenl_eval_case_design(uint64_t suite_seed, size_t index, unsigned attempt,
                                    aenl_eval_case_t *out, aenl_err_t *err)
{
    design_t d;
    aenl_status_t st;
    if (out == NULL)
    {
        aenl_err_set(err, "NULL case");
        return AENL_E_ARG;
    }
    design_init(&d, out, suite_seed, index, attempt);
    st = design_attempt(&d, err);
    if (st == AENL_E_NUMERIC && d.why[0] != '\0')
    {
        aenl_err_set(err, "%s", d.why);
    }
    return st;
}

/* ---- materiality ---------------------------------------------------------------------------- */

static double rms_about_zero(const double *y, size_t n)
{
    double s = 0.0;
    for (size_t k = 0; k < n; ++k)
    {
        s += y[k] * y[k];
    }
    return n > 0 ? sqrt(s / (double)n) : 0.0;
}

static double rms_about_mean(const double *y, size_t n)
{
    double s = 0.0, s2 = 0.0;
    for (size_t k = 0; k < n; ++k)
    {
        s += y[k];
    }
    const double m = n > 0 ? s / (double)n : 0.0;
    for (size_t k = 0; k < n; ++k)
    {
        s2 += (y[k] - m) * (y[k] - m);
    }
    return n > 0 ? sqrt(s2 / (double)n) : 0.0;
}

/* Largest |R(x)/x − 1| over 0 < |x| <= xa (secant-stiffness change of a polynomial law). */
static double secant_change(const aenl_sim_law_t *l, double xa)
{
    double best = 0.0;
    for (int k = 1; k <= 200; ++k)
    {
        const double x = xa * (double)k / 200.0;
        best = fmax(best, fabs(aenl_sim_law_eval(l, x, 1) / x - 1.0));
        best = fmax(best, fabs(aenl_sim_law_eval(l, -x, 1) / -x - 1.0));
    }
    return best;
}

static aenl_status_t quantiles(const double *y, size_t n, double *q01, double *q99)
{
    if (n == 0)
    {
        return AENL_E_ARG;
    }
    double *s = malloc(n * sizeof(double));
    if (s == NULL)
    {
        return AENL_E_IO;
    }
    memcpy(s, y, n * sizeof(double));
    aenl_sort_doubles(s, n);
    *q01 = s[(size_t)(0.01 * (double)(n - 1))];
    *q99 = s[(size_t)(0.99 * (double)(n - 1))];
    free(s);
    return AENL_OK;
}

/* Median over the releases of rms(last fifth) / rms(first fifth) (windows at least a period,
 * at most half the release). */
static double release_decay(const aenl_eval_case_t *c, const double *x)
{
    double r[64];
    size_t m = 0;
    for (size_t i = 0; i < c->n_releases && m < 64; ++i)
    {
        const size_t a = i * c->release_samples;
        const size_t b = i + 1 < c->n_releases ? a + c->release_samples : c->n_samples;
        const size_t p = (size_t)c->samples_per_period;
        const size_t f = (b - a) / 5 > p ? (b - a) / 5 : ((b - a) / 2 < p ? (b - a) / 2 : p);
        if (f >= 4 && b - a >= c->release_samples / 2)
        {
            r[m++] = rms_about_mean(x + b - f, f) / fmax(rms_about_mean(x + a, f), 1e-300);
        }
    }
    if (m == 0)
    {
        return 1.0;
    }
    aenl_sort_doubles(r, m);
    return r[m / 2];
}

/* The checks of the header; 0 accepted, else 1 with d->why set. */
static int check_material(design_t *d, aenl_status_t *st)
{
    aenl_eval_case_t *c = d->c;
    aenl_eval_metrics_t *mt = &c->metrics;
    const size_t n = c->n_samples;
    const long col =
        c->channel_index >= 0 ? c->channel_index : dof_column(c->model.type, AENL_SIM_DOF_PITCH);
    const double *x = c->clean + (size_t)col * n;
    const double scale = c->amplitude > 0.0 ? c->amplitude : rms_about_zero(x, n);
    *st = AENL_OK;
    for (size_t k = 0; k < n * c->n_channels; ++k)
    {
        if (!isfinite(c->clean[k]))
        {
            (void)snprintf(d->why, sizeof(d->why), "non-finite sample");
            return 1;
        }
    }
    double xmax = 0.0;
    for (size_t k = 0; k < n; ++k)
    {
        xmax = fmax(xmax, fabs(x[k]));
    }
    mt->x_rms = rms_about_zero(x, n);
    const double r_all = rms_about_mean(x, n), r_end = rms_about_mean(x + n - n / 10, n / 10);
    if (xmax > 20.0 * scale + 1e-300 || r_end > 3.0 * r_all)
    {
        (void)snprintf(d->why, sizeof(d->why), "diverges");
        return 1;
    }
    switch (c->stratum.regime)
    {
        case AENL_EVAL_DECAY:
            mt->trend_ratio = release_decay(c, x);
            if (!(mt->trend_ratio < 0.8))
            {
                (void)snprintf(d->why, sizeof(d->why), "no decay (%.2f)", mt->trend_ratio);
                return 1;
            }
            break;
        case AENL_EVAL_LCO:
            mt->trend_ratio =
                rms_about_mean(x + n - n / 4, n / 4) / rms_about_mean(x + n / 4, n / 4);
            if (!(mt->trend_ratio > 0.8 && mt->trend_ratio < 1.25) ||
                !(sqrt(2.0) * rms_about_mean(x + n - n / 4, n / 4) > 0.2 * scale))
            {
                (void)snprintf(d->why, sizeof(d->why), "no LCO (%.2f)", mt->trend_ratio);
                return 1;
            }
            break;
        case AENL_EVAL_TURBULENCE:
        default:
            mt->trend_ratio = rms_about_mean(x + n / 2, n - n / 2) / rms_about_mean(x, n / 2);
            if (!(mt->trend_ratio > 0.5 && mt->trend_ratio < 2.0))
            {
                (void)snprintf(d->why, sizeof(d->why), "not stationary (%.2f)", mt->trend_ratio);
                return 1;
            }
            break;
    }
    if (c->cls == AENL_CLASS_POLYNOMIAL)
    {
        mt->kappa = secant_change(&c->model.law[d->dof], sqrt(2.0) * mt->x_rms);
        if (!(mt->kappa >= 0.4))
        {
            (void)snprintf(d->why, sizeof(d->why), "polynomial immaterial (%.2f)", mt->kappa);
            return 1;
        }
    }
    if (c->n_switch > 0)
    {
        const double lo = c->switch_points[0] - 0.25 * c->gap;
        const double hi = c->switch_points[c->n_switch - 1] + 0.25 * c->gap;
        size_t nb = 0, na = 0;
        double q01 = 0.0, q99 = 0.0;
        for (size_t k = 0; k < n; ++k)
        {
            nb += x[k] < lo;
            na += x[k] > hi;
        }
        mt->frac_below = (double)nb / (double)n;
        mt->frac_above = (double)na / (double)n;
        if ((*st = quantiles(x, n, &q01, &q99)) != AENL_OK)
        {
            return 1;
        }
        mt->gap_ratio = q99 > q01 ? c->gap / (q99 - q01) : 1.0;
        if (!(mt->frac_below >= 0.05 && mt->frac_above >= 0.05))
        {
            (void)snprintf(d->why, sizeof(d->why), "gap not covered (%.3f below, %.3f above)",
                           mt->frac_below, mt->frac_above);
            return 1;
        }
        if (!(mt->gap_ratio >= 0.06))
        {
            (void)snprintf(d->why, sizeof(d->why), "gap negligible (%.3f of the range)",
                           mt->gap_ratio);
            return 1;
        }
    }
    return 0;
}

/* Exactly the simulator's measurement noise (aenl_sim_integrate.c): per channel, in order, one
 * generator seeded with noise_seed, std(clean)/snr with the population standard deviation. */
static void add_noise(aenl_eval_case_t *c)
{
    aenl_rng_t rng;
    const size_t n = c->n_samples;
    memcpy(c->y, c->clean, n * c->n_channels * sizeof(double));
    if (!(c->run.snr > 0.0))
    {
        return;
    }
    aenl_rng_seed(&rng, c->run.noise_seed);
    for (size_t ch = 0; ch < c->n_channels; ++ch)
    {
        double *y = c->y + ch * n, mean = 0.0, var = 0.0;
        for (size_t k = 0; k < n; ++k)
        {
            mean += y[k];
        }
        mean /= (double)n;
        for (size_t k = 0; k < n; ++k)
        {
            var += (y[k] - mean) * (y[k] - mean);
        }
        const double sd = sqrt(var / (double)n) / c->run.snr;
        for (size_t k = 0; k < n; ++k)
        {
            y[k] += sd * aenl_rng_gauss(&rng);
        }
    }
}

/* One noise-free run of `model` over m output steps into clean[] at sample offset `at` (the
 * run's first sample, its initial state, is skipped when skip_first). */
static aenl_status_t run_piece(design_t *d, const aenl_sim_model_t *model, size_t m, size_t at,
                               int skip_first, aenl_err_t *e2)
{
    aenl_eval_case_t *c = d->c;
    aenl_sim_run_t r = c->run;
    aenl_sim_result_t res;
    aenl_status_t st;
    r.snr = 0.0;
    r.duration = (double)m * r.dt;
    if ((st = simulate(d, model, &r, &res, e2)) != AENL_OK)
    {
        return st;
    }
    const size_t first = skip_first ? 1 : 0;
    const size_t take = res.n_samples - first;
    c->n_channels = res.n_channels;
    for (size_t ch = 0; ch < res.n_channels && at + first + take <= c->n_samples; ++ch)
    {
        memcpy(c->clean + ch * c->n_samples + at + first, res.y + ch * res.n_samples + first,
               take * sizeof(double));
    }
    aenl_sim_result_free(&res);
    return AENL_OK;
}

/* Velocity per unit angular frequency that gives the DOF the potential energy of its law at a
 * displacement a from the centre: sqrt(2 |∫ (R(x) − R(centre)) dx|) (unit stiffness; a for a
 * linear law). Hysteresis: the rising branch. */
static double kick_speed(const design_t *d, double a)
{
    if (d->dof < 0)
    {
        return a;
    }
    const aenl_sim_law_t *l = &d->c->model.law[d->dof];
    const double x0 = d->center * d->c->amplitude, r0 = aenl_sim_law_eval(l, x0, 1);
    double e = 0.0;
    for (int k = 0; k < 200; ++k)
    {
        const double x = x0 + a * ((double)k + 0.5) / 200.0;
        e += (aenl_sim_law_eval(l, x, 1) - r0) * a / 200.0;
    }
    return sqrt(2.0 * fabs(e));
}

/* The response's centre and the amplitude at which a release has rung down: A / decay_factor,
 * and for a gap law at least 2.5x the switching points' largest distance from the centre. */
static void release_end(const design_t *d, double *centre, double *a_end)
{
    const aenl_eval_case_t *c = d->c;
    *centre = 0.0;
    *a_end = c->amplitude / d->decay_factor;
    if (c->n_switch > 0)
    {
        *centre = d->center * c->amplitude;
        const double span = fmax(fabs(c->switch_points[0] - *centre),
                                 fabs(c->switch_points[c->n_switch - 1] - *centre));
        *a_end = fmax(*a_end, 2.5 * span);
    }
}

/* One pilot ring-down: a kick of kick_gain x kick_speed(A) from the initial state, at most 150
 * periods. Returns the largest excursion from the centre over the first two periods and the
 * first whole period whose excursion stays below release_end() (in samples; the run's length
 * when none). */
static aenl_status_t pilot_ring(design_t *d, double omega, double *peak, size_t *len,
                                aenl_err_t *e2)
{
    aenl_eval_case_t *c = d->c;
    aenl_sim_model_t m = c->model;
    aenl_sim_run_t r = c->run;
    aenl_sim_result_t res;
    aenl_status_t st;
    const size_t w = (size_t)lround(c->samples_per_period);
    size_t steps = (size_t)lround(150.0 * c->samples_per_period);
    double centre, a_end;
    steps = steps < c->n_samples - 1 ? steps : c->n_samples - 1;
    m.v0[d->kick_dof] = d->kick_gain * kick_speed(d, c->amplitude) * omega;
    r.snr = 0.0;
    r.duration = (double)steps * r.dt;
    if ((st = simulate(d, &m, &r, &res, e2)) != AENL_OK)
    {
        return st;
    }
    release_end(d, &centre, &a_end);
    const double *y = res.y + (size_t)dof_column(m.type, d->kick_dof) * res.n_samples;
    *peak = 0.0;
    for (size_t k = 0; k < 2 * w && k < res.n_samples; ++k)
    {
        *peak = fmax(*peak, fabs(y[k] - centre));
    }
    *len = steps;
    for (size_t j = 0; (j + 1) * w <= res.n_samples; ++j)
    {
        double env = 0.0;
        for (size_t k = j * w; k < (j + 1) * w; ++k)
        {
            env = fmax(env, fabs(y[k] - centre));
        }
        if (env < a_end)
        {
            *len = j * w;
            break;
        }
    }
    aenl_sim_result_free(&res);
    return AENL_OK;
}

/* Kick size and release length from pilot ring-downs: the kick is scaled (1..4x) so that the
 * first excursion reaches A (energy also flows into the other DOFs and the aerodynamics), and a
 * release lasts until the excursion falls below release_end(), at least 3 periods. */
static aenl_status_t pilot_release(design_t *d, const double omega, aenl_err_t *e2)
{
    aenl_eval_case_t *c = d->c;
    const size_t w = (size_t)lround(c->samples_per_period);
    double peak = 0.0;
    size_t len = 0;
    aenl_status_t st;
    d->kick_gain = 1.0;
    if ((st = pilot_ring(d, omega, &peak, &len, e2)) != AENL_OK)
    {
        return st;
    }
    if (peak > 0.0 && peak < 0.9 * c->amplitude)
    {
        d->kick_gain = fmin(c->amplitude / peak, 4.0);
        if ((st = pilot_ring(d, omega, &peak, &len, e2)) != AENL_OK)
        {
            return st;
        }
    }
    c->release_samples = len > 3 * w ? len : 3 * w;
    if (c->release_samples >= c->n_samples)
    {
        c->release_samples = c->n_samples - 1;
    }
    return AENL_OK;
}

/* Decay: releases one after the other, like repeated stick raps, as the simulator's kick train
 * (one run): every release_samples samples, the first at t = 0, the rate of kick_dof jumps by a
 * kick of random sign whose size is uniform between the kicks with the energy of the law at
 * amplitudes 0.8 A and 1.25 A (kick_speed, times the pilot's kick_gain). The state carries on
 * through a kick, so each release starts where the previous one has rung down to. */
static aenl_status_t run_releases(design_t *d, aenl_err_t *e2)
{
    aenl_eval_case_t *c = d->c;
    const size_t n = c->n_samples;
    const double omega = 2.0 * PI / (c->run.dt * c->samples_per_period);
    aenl_status_t st;
    if ((st = pilot_release(d, omega, e2)) != AENL_OK)
    {
        return st;
    }
    const size_t len = c->release_samples;
    c->run.kicks = 1;
    c->run.kick_dof = (aenl_sim_dof_t)d->kick_dof;
    c->run.kick_every = (double)len * c->run.dt;
    c->run.kick_rate = d->kick_gain * kick_speed(d, 0.8 * c->amplitude) * omega;
    c->run.kick_rate_max = d->kick_gain * kick_speed(d, 1.25 * c->amplitude) * omega;
    c->run.kick_sign = AENL_SIM_KICK_RANDOM;
    c->run.kick_seed = aenl_rng_next(&d->rng) >> 16;
    c->n_releases = (n - 2) / len + 1; /* kicks at 0, len, ... before the last sample */
    return run_piece(d, &c->model, n - 1, 0, 0, e2);
}

/* Simulate one designed attempt: 0 accepted, 1 rejected (d->why), or a status through *st. */
static int run_attempt(design_t *d, aenl_status_t *st, aenl_err_t *err)
{
    aenl_eval_case_t *c = d->c;
    aenl_err_t e2;
    const size_t n_ch = c->model.type == AENL_SIM_AIRFOIL2DOF ? 2u : 3u;
    aenl_err_clear(&e2);
    c->clean = calloc(c->n_samples * n_ch, sizeof(double));
    if (c->clean == NULL)
    {
        *st = AENL_E_IO;
        aenl_err_set(err, "out of memory");
        return 1;
    }
    if (c->stratum.regime == AENL_EVAL_DECAY)
    {
        *st = run_releases(d, &e2);
    }
    else
    {
        *st = run_piece(d, &c->model, c->n_samples - 1, 0, 0, &e2);
    }
    if (*st == AENL_E_NUMERIC)
    {
        (void)snprintf(d->why, sizeof(d->why), "simulation: %.80s", e2.msg);
        *st = AENL_OK;
        return 1;
    }
    if (*st != AENL_OK)
    {
        aenl_err_set(err, "%s", e2.msg[0] != '\0' ? e2.msg : "out of memory");
        return 1;
    }
    const int rej = check_material(d, st);
    if (rej || *st != AENL_OK)
    {
        return 1;
    }
    c->y = malloc(c->n_samples * c->n_channels * sizeof(double));
    if (c->y == NULL)
    {
        *st = AENL_E_IO;
        aenl_err_set(err, "out of memory");
        return 1;
    }
    add_noise(c);
    for (size_t ch = 0; ch < c->n_channels; ++ch)
    {
        c->names[ch] = column_name(c->model.type, (long)ch);
        c->cols[ch] = c->y + ch * c->n_samples;
    }
    return 0;
}

static void append_reason(char *buf, size_t cap, const char *why)
{
    const size_t len = strlen(buf);
    if (len + 3 < cap)
    {
        (void)snprintf(buf + len, cap - len, "%s%s", len > 0 ? "; " : "", why);
    }
}

aenl_status_t aenl_eval_case_make(uint64_t suite_seed, size_t index, aenl_eval_case_t *out,
                                  aenl_err_t *err)
{
    return aenl_eval_case_make_with(suite_seed, index, NULL, out, err);
}

aenl_status_t aenl_eval_case_make_with(uint64_t suite_seed, size_t index,
                                       const aenl_eval_options_t *opt, aenl_eval_case_t *out,
                                       aenl_err_t *err)
{
    char reasons[AENL_EVAL_REASONS_CAP] = "";
    if (out == NULL)
    {
        aenl_err_set(err, "NULL case");
        return AENL_E_ARG;
    }
    for (unsigned attempt = 0; attempt < AENL_EVAL_MAX_ATTEMPT; ++attempt)
    {
        design_t d;
        aenl_status_t st;
        aenl_err_t e2;
        aenl_err_clear(&e2);
        design_init(&d, out, suite_seed, index, attempt);
        if (opt != NULL)
        {
            d.opt = *opt;
        }
        st = design_attempt(&d, &e2);
        if (st == AENL_OK)
        {
            if (run_attempt(&d, &st, err) == 0)
            {
                memcpy(out->reject_reasons, reasons, sizeof(reasons));
                return AENL_OK;
            }
            aenl_eval_case_free(out);
            if (st != AENL_OK)
            {
                return st;
            }
        }
        else if (st != AENL_E_NUMERIC || d.why[0] == '\0')
        {
            aenl_err_set(err, "case %zu: %s", index, e2.msg);
            return st;
        }
        append_reason(reasons, sizeof(reasons), d.why);
    }
    aenl_err_set(err, "case %zu: no accepted attempt in %u (%s)", index, AENL_EVAL_MAX_ATTEMPT,
                 reasons);
    return AENL_E_NUMERIC;
}

void aenl_eval_case_free(aenl_eval_case_t *c)
{
    if (c == NULL)
    {
        return;
    }
    free(c->y);
    free(c->clean);
    memset(c, 0, sizeof(*c));
}

/* ---- INI ------------------------------------------------------------------------------------ */

static const char *truth_class_name(aenl_class_t cls)
{
    switch (cls)
    {
        case AENL_CLASS_LINEAR:
            return "linear";
        case AENL_CLASS_POLYNOMIAL:
            return "polynomial";
        case AENL_CLASS_FREEPLAY:
            return "freeplay";
        case AENL_CLASS_HYSTERESIS:
            return "hysteresis";
        case AENL_CLASS_INSUFFICIENT:
        default:
            return "insufficient";
    }
}

aenl_status_t aenl_eval_case_write_ini(const aenl_eval_case_t *c, const char *path, aenl_err_t *err)
{
    aenl_outfile_t of;
    aenl_status_t st;
    if (c == NULL || path == NULL)
    {
        aenl_err_set(err, "NULL argument");
        return AENL_E_ARG;
    }
    if ((st = aenl_outfile_open(&of, path, err)) != AENL_OK)
    {
        return st;
    }
    FILE *f = of.fp;
    fprintf(f, "; aenl evaluation suite, seed %llu, case %zu (attempt %u)\n; %s\n",
            (unsigned long long)c->suite_seed, c->index, c->attempt, c->description);
    fprintf(f, "; truth: class %s, channel %s, switching points", truth_class_name(c->cls),
            c->channel[0] != '\0' ? c->channel : "-");
    for (size_t i = 0; i < c->n_switch; ++i)
    {
        fprintf(f, " %.9g", c->switch_points[i]);
    }
    fprintf(f, "%s, gap %.9g\n", c->n_switch == 0 ? " none" : "", c->gap);
    if (c->n_releases > 0)
    {
        fprintf(f, "; decay record: %zu releases of %zu samples (the [excitation] kick train)\n",
                c->n_releases, c->release_samples);
    }
    aenl_sim_write_ini(f, &c->model, &c->run);
    return aenl_outfile_commit(&of, err);
}
