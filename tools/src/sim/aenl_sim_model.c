/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_sim_model.c
 * @brief Model defaults and validation, restoring laws, assembly of the generic linear form
 *        (aenl_sim_internal.h) for the 2-DOF airfoil and the 3-DOF section, and the right-hand
 *        side.
 */
#include <math.h>
#include <string.h>

#include "aenl_sim_internal.h"
#include "aenl_tools/aenl_dense.h"

void aenl_sim_model_default(aenl_sim_model_t *model, aenl_sim_type_t type)
{
    int i;
    if (model == NULL)
    {
        return;
    }
    memset(model, 0, sizeof(*model));
    model->type = type;
    /* The classic case (Lee, Jiang & Wong 1999): linear flutter at U* 6.285. */
    model->airfoil.mu = 100.0;
    model->airfoil.a_h = -0.5;
    model->airfoil.x_alpha = 0.25;
    model->airfoil.r_alpha = 0.5;
    model->airfoil.omega_bar = 0.2;
    model->airfoil.zeta_alpha = 0.0;
    model->airfoil.zeta_xi = 0.0;
    model->airfoil.ustar = 5.5;
    model->airfoil.ic_forcing = 1;
    /* Conner's parameters (Conner, Tang, Dowell & Virgin 1997): linear flutter at 23.897 m/s. */
    model->section.b = 0.127;
    model->section.a = -0.5;
    model->section.c = 0.5;
    model->section.m = 1.558;
    model->section.m_t = 3.3843;
    model->section.x_alpha = 0.434;
    model->section.x_beta = 0.01996;
    model->section.r_alpha = 0.7321;
    model->section.r_beta = 0.11397;
    model->section.omega_h = 42.5352;
    model->section.omega_alpha = 52.6506;
    model->section.omega_beta = 109.3093;
    model->section.zeta_h = 0.0133;
    model->section.zeta_alpha = 0.01626;
    model->section.zeta_beta = 0.0115;
    model->section.rho = 1.225;
    model->section.velocity = 15.0;
    for (i = 0; i < AENL_SIM_N_DOF; ++i)
    {
        model->law[i].kind = AENL_SIM_LAW_LINEAR;
        model->law[i].n_coeffs = 1;
        model->law[i].coeffs[0] = 1.0;
    }
}

void aenl_sim_run_default(aenl_sim_run_t *run, aenl_sim_type_t type)
{
    if (run == NULL)
    {
        return;
    }
    memset(run, 0, sizeof(*run));
    run->rtol = 1e-10;
    run->atol = 1e-12;
    run->turb_length = (type == AENL_SIM_AIRFOIL2DOF) ? 2.0 : 0.25;
    run->turb_seed = 1;
    run->kick_seed = 1;
    run->force_seed = 1;
    run->noise_seed = 42;
}

void sim_kick_init(sim_kick_gen_t *g, const aenl_sim_run_t *run)
{
    aenl_rng_seed(&g->rng, run->kick_seed);
    g->lo = run->kick_rate;
    g->hi = run->kick_rate_max;
    g->sign = run->kick_sign;
    g->j = 0;
}

double sim_kick_next(sim_kick_gen_t *g)
{
    /* Both draws every time, so the sizes do not depend on the sign rule. */
    const double u = aenl_rng_uniform(&g->rng), v = aenl_rng_uniform(&g->rng);
    const double r = g->lo + (g->hi - g->lo) * u;
    double s = 1.0;
    if (g->sign == AENL_SIM_KICK_RANDOM)
    {
        s = v < 0.5 ? -1.0 : 1.0;
    }
    else if (g->sign == AENL_SIM_KICK_ALTERNATE)
    {
        s = (g->j % 2u) == 0u ? 1.0 : -1.0;
    }
    ++g->j;
    return s * r;
}

size_t sim_kick_steps(const aenl_sim_run_t *run)
{
    return run->kicks ? (size_t)floor(run->kick_every / run->dt + 0.5) : 0u;
}

aenl_status_t aenl_sim_kicks(const aenl_sim_run_t *run, size_t n, double *dv, aenl_err_t *err)
{
    sim_kick_gen_t g;
    if (run == NULL || dv == NULL || !run->kicks)
    {
        aenl_err_set(err, "aenl_sim_kicks: NULL argument or a run without kicks");
        return AENL_E_ARG;
    }
    sim_kick_init(&g, run);
    for (size_t j = 0; j < n; ++j)
    {
        dv[j] = sim_kick_next(&g);
    }
    return AENL_OK;
}

double aenl_sim_velocity(const aenl_sim_model_t *model)
{
    return model->type == AENL_SIM_AIRFOIL2DOF ? model->airfoil.ustar : model->section.velocity;
}

void aenl_sim_set_velocity(aenl_sim_model_t *model, double velocity)
{
    if (model->type == AENL_SIM_AIRFOIL2DOF)
    {
        model->airfoil.ustar = velocity;
    }
    else
    {
        model->section.velocity = velocity;
    }
}

static const char *const law_section[AENL_SIM_N_DOF] = {"pitch", "plunge", "flap"};

static aenl_status_t check_pos(double v, const char *name, aenl_err_t *err)
{
    if (!isfinite(v) || !(v > 0.0))
    {
        aenl_err_set(err, "%s must be a finite number > 0 (got %g)", name, v);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

static aenl_status_t check_fin(double v, const char *name, aenl_err_t *err)
{
    if (!isfinite(v))
    {
        aenl_err_set(err, "%s must be finite", name);
        return AENL_E_ARG;
    }
    return AENL_OK;
}

static aenl_status_t validate_law(const aenl_sim_law_t *law, const char *sec, aenl_err_t *err)
{
    size_t k;
    switch (law->kind)
    {
        case AENL_SIM_LAW_LINEAR:
            return AENL_OK;
        case AENL_SIM_LAW_POLYNOMIAL:
            if (law->n_coeffs < 1 || law->n_coeffs > AENL_SIM_MAX_POLY)
            {
                aenl_err_set(err, "[%s] coeffs: 1 to %d coefficients required", sec,
                             AENL_SIM_MAX_POLY);
                return AENL_E_ARG;
            }
            for (k = 0; k < law->n_coeffs; ++k)
            {
                if (!isfinite(law->coeffs[k]))
                {
                    aenl_err_set(err, "[%s] coeffs must be finite", sec);
                    return AENL_E_ARG;
                }
            }
            return AENL_OK;
        case AENL_SIM_LAW_FREEPLAY:
        case AENL_SIM_LAW_HYSTERESIS:
            if (!isfinite(law->delta) || !(law->delta > 0.0))
            {
                aenl_err_set(err, "[%s] delta must be > 0", sec);
                return AENL_E_ARG;
            }
            if (!isfinite(law->x_f) || !isfinite(law->preload) || !isfinite(law->inner_stiffness))
            {
                aenl_err_set(err, "[%s] alpha_f, preload and inner_stiffness must be finite", sec);
                return AENL_E_ARG;
            }
            return AENL_OK;
        default:
            break;
    }
    aenl_err_set(err, "[%s] unknown law", sec);
    return AENL_E_ARG;
}

static aenl_status_t check_kicks(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                 aenl_err_t *err)
{
    aenl_status_t st;
    if (run->turbulence)
    {
        aenl_err_set(err, "[excitation] kicks and turbulence cannot be combined");
        return AENL_E_ARG;
    }
    if ((int)run->kick_dof < 0 || (int)run->kick_dof >= AENL_SIM_N_DOF ||
        (run->kick_dof == AENL_SIM_DOF_FLAP && model->type != AENL_SIM_SECTION3DOF))
    {
        aenl_err_set(err, "[excitation] dof: no such DOF in this model");
        return AENL_E_ARG;
    }
    if ((st = check_pos(run->kick_every, "[excitation] every", err)) != AENL_OK)
    {
        return st;
    }
    const double steps = run->kick_every / run->dt;
    if (!(steps >= 0.5) || fabs(steps - floor(steps + 0.5)) > 1e-9 * steps)
    {
        aenl_err_set(err, "[excitation] every (%g) must be a whole number of [run] dt (%g)",
                     run->kick_every, run->dt);
        return AENL_E_ARG;
    }
    if (!isfinite(run->kick_rate) || run->kick_rate < 0.0 || !isfinite(run->kick_rate_max) ||
        run->kick_rate_max < run->kick_rate)
    {
        aenl_err_set(err, "[excitation] rate must be finite and >= 0, rate_max finite and >= rate");
        return AENL_E_ARG;
    }
    if ((int)run->kick_sign < 0 || (int)run->kick_sign > (int)AENL_SIM_KICK_POSITIVE)
    {
        aenl_err_set(err, "[excitation] sign: unknown rule");
        return AENL_E_ARG;
    }
    return AENL_OK;
}

aenl_status_t aenl_sim_validate(const aenl_sim_model_t *model, const aenl_sim_run_t *run,
                                aenl_err_t *err)
{
    aenl_status_t st;
    int i;
    if (model == NULL)
    {
        aenl_err_set(err, "no model");
        return AENL_E_ARG;
    }
    if (model->type == AENL_SIM_AIRFOIL2DOF)
    {
        const aenl_sim_airfoil_t *p = &model->airfoil;
        if ((st = check_pos(p->mu, "mu", err)) != AENL_OK ||
            (st = check_fin(p->a_h, "a_h", err)) != AENL_OK ||
            (st = check_fin(p->x_alpha, "x_alpha", err)) != AENL_OK ||
            (st = check_pos(p->r_alpha, "r_alpha", err)) != AENL_OK ||
            (st = check_pos(p->omega_bar, "omega_bar", err)) != AENL_OK ||
            (st = check_fin(p->zeta_alpha, "zeta_alpha", err)) != AENL_OK ||
            (st = check_fin(p->zeta_xi, "zeta_xi", err)) != AENL_OK ||
            (st = check_pos(p->ustar, "ustar", err)) != AENL_OK)
        {
            return st;
        }
        if (model->law[AENL_SIM_DOF_FLAP].kind != AENL_SIM_LAW_LINEAR)
        {
            aenl_err_set(err, "[flap] does not exist in an airfoil2dof model");
            return AENL_E_ARG;
        }
    }
    else if (model->type == AENL_SIM_SECTION3DOF)
    {
        const aenl_sim_section_t *p = &model->section;
        if ((st = check_pos(p->b, "b", err)) != AENL_OK ||
            (st = check_fin(p->a, "a", err)) != AENL_OK ||
            (st = check_fin(p->c, "c", err)) != AENL_OK ||
            (st = check_pos(p->m, "m", err)) != AENL_OK ||
            (st = check_pos(p->m_t, "m_t", err)) != AENL_OK ||
            (st = check_fin(p->x_alpha, "x_alpha", err)) != AENL_OK ||
            (st = check_fin(p->x_beta, "x_beta", err)) != AENL_OK ||
            (st = check_pos(p->r_alpha, "r_alpha", err)) != AENL_OK ||
            (st = check_pos(p->r_beta, "r_beta", err)) != AENL_OK ||
            (st = check_pos(p->omega_h, "omega_h", err)) != AENL_OK ||
            (st = check_pos(p->omega_alpha, "omega_alpha", err)) != AENL_OK ||
            (st = check_pos(p->omega_beta, "omega_beta", err)) != AENL_OK ||
            (st = check_fin(p->zeta_h, "zeta_h", err)) != AENL_OK ||
            (st = check_fin(p->zeta_alpha, "zeta_alpha", err)) != AENL_OK ||
            (st = check_fin(p->zeta_beta, "zeta_beta", err)) != AENL_OK ||
            (st = check_fin(p->rho, "rho", err)) != AENL_OK ||
            (st = check_pos(p->velocity, "velocity", err)) != AENL_OK)
        {
            return st;
        }
        if (!(p->c > -1.0 && p->c < 1.0) || p->rho < 0.0)
        {
            aenl_err_set(err, "c must lie in (-1, 1) and rho >= 0");
            return AENL_E_ARG;
        }
    }
    else
    {
        aenl_err_set(err, "unknown model type");
        return AENL_E_ARG;
    }
    for (i = 0; i < AENL_SIM_N_DOF; ++i)
    {
        if ((st = validate_law(&model->law[i], law_section[i], err)) != AENL_OK)
        {
            return st;
        }
        if (!isfinite(model->x0[i]) || !isfinite(model->v0[i]))
        {
            aenl_err_set(err, "[initial] values must be finite");
            return AENL_E_ARG;
        }
    }
    if (run != NULL)
    {
        if ((st = check_pos(run->duration, "[run] duration", err)) != AENL_OK ||
            (st = check_pos(run->dt, "[run] dt", err)) != AENL_OK ||
            (st = check_pos(run->rtol, "[run] rtol", err)) != AENL_OK ||
            (st = check_pos(run->atol, "[run] atol", err)) != AENL_OK)
        {
            return st;
        }
        if (run->dt > run->duration)
        {
            aenl_err_set(err, "[run] dt must not exceed duration");
            return AENL_E_ARG;
        }
        if (run->duration / run->dt > 1e9)
        {
            aenl_err_set(err, "[run] duration/dt above 1e9 samples");
            return AENL_E_ARG;
        }
        if (run->turbulence && (!isfinite(run->turb_intensity) || run->turb_intensity < 0.0 ||
                                !isfinite(run->turb_length) || !(run->turb_length > 0.0)))
        {
            aenl_err_set(err, "[excitation] intensity must be >= 0 and length_scale > 0");
            return AENL_E_ARG;
        }
        if (run->kicks && (st = check_kicks(model, run, err)) != AENL_OK)
        {
            return st;
        }
        if ((st = sim_force_check(model, run, err)) != AENL_OK)
        {
            return st;
        }
        if (!isfinite(run->snr) || run->snr < 0.0)
        {
            aenl_err_set(err, "[noise] snr must be > 0");
            return AENL_E_ARG;
        }
        for (size_t c = 0; c < AENL_SIM_MAX_Q; ++c)
        {
            if (!isfinite(run->bound[c]) || run->bound[c] < 0.0)
            {
                aenl_err_set(err, "runaway bound of channel %zu must be finite and >= 0", c);
                return AENL_E_ARG;
            }
        }
    }
    return AENL_OK;
}

/* ---- restoring laws (docs/simulate.md) ---------------------------------------------------- */

/* Hysteresis branch dir is a Lee freeplay with start lo and preload dir·M0: dir = +1 gives
 * M+ (gap [α_f, α_f+δ], value M0 inside); dir = −1 gives M−(x) = −M+(−x) (gap [−α_f−δ, −α_f],
 * value −M0 inside). */
void sim_law_bounds(const aenl_sim_law_t *law, int dir, double *lo, double *hi)
{
    if (law->kind == AENL_SIM_LAW_HYSTERESIS && dir < 0)
    {
        *lo = -law->x_f - law->delta;
        *hi = -law->x_f;
    }
    else
    {
        *lo = law->x_f;
        *hi = law->x_f + law->delta;
    }
}

size_t aenl_sim_law_switch_points(const aenl_sim_law_t *law, double p[4])
{
    if (law->kind == AENL_SIM_LAW_FREEPLAY)
    {
        p[0] = law->x_f;
        p[1] = law->x_f + law->delta;
        return 2;
    }
    if (law->kind != AENL_SIM_LAW_HYSTERESIS)
    {
        return 0;
    }
    double q[4];
    sim_law_bounds(law, -1, &q[0], &q[1]);
    sim_law_bounds(law, 1, &q[2], &q[3]);
    for (size_t i = 1; i < 4u; ++i) /* ascending by insertion (α_f may be negative) */
    {
        for (size_t j = i; j > 0u && q[j] < q[j - 1u]; --j)
        {
            const double t = q[j];
            q[j] = q[j - 1u];
            q[j - 1u] = t;
        }
    }
    size_t n = 0;
    for (size_t i = 0; i < 4u; ++i)
    {
        if (n == 0u || q[i] - p[n - 1u] > 1e-9 * fabs(law->delta))
        {
            p[n++] = q[i] + 0.0; /* -α_f = -0 prints as +0 */
        }
    }
    return n;
}

int sim_law_region(const aenl_sim_law_t *law, int dir, double x, int moving_up)
{
    double lo, hi;
    sim_law_bounds(law, dir, &lo, &hi);
    if (x < lo)
    {
        return 0;
    }
    if (x > hi)
    {
        return 2;
    }
    if (!(x > lo)) /* on lo */
    {
        return moving_up < 0 ? 0 : 1;
    }
    if (!(x < hi)) /* on hi */
    {
        return moving_up > 0 ? 2 : 1;
    }
    return 1;
}

double sim_law_branch(const aenl_sim_law_t *law, int region, int dir, double x)
{
    double lo, hi, m0, acc;
    size_t k;
    switch (law->kind)
    {
        case AENL_SIM_LAW_POLYNOMIAL:
            acc = 0.0;
            for (k = law->n_coeffs; k > 0; --k)
            {
                acc = (acc + law->coeffs[k - 1]) * x;
            }
            return acc;
        case AENL_SIM_LAW_FREEPLAY:
        case AENL_SIM_LAW_HYSTERESIS:
            sim_law_bounds(law, dir, &lo, &hi);
            m0 = (law->kind == AENL_SIM_LAW_HYSTERESIS && dir < 0) ? -law->preload : law->preload;
            if (region == 0)
            {
                return m0 + x - lo;
            }
            if (region == 1)
            {
                return m0 + law->inner_stiffness * (x - lo);
            }
            return m0 + x - lo + (hi - lo) * (law->inner_stiffness - 1.0);
        case AENL_SIM_LAW_LINEAR:
        default:
            return x;
    }
}

double aenl_sim_law_eval(const aenl_sim_law_t *law, double x, int dir)
{
    const int d = dir < 0 ? -1 : 1;
    if (law == NULL)
    {
        return NAN;
    }
    return sim_law_branch(law, sim_law_region(law, d, x, 0), d, x);
}

int aenl_sim_slopes(const aenl_sim_model_t *model, double outer[AENL_SIM_N_DOF],
                    double inner[AENL_SIM_N_DOF])
{
    int i, distinct = 0;
    for (i = 0; i < AENL_SIM_N_DOF; ++i)
    {
        const aenl_sim_law_t *law = &model->law[i];
        outer[i] = 1.0;
        if (law->kind == AENL_SIM_LAW_POLYNOMIAL)
        {
            outer[i] = law->coeffs[0];
        }
        inner[i] = outer[i];
        if (law->kind == AENL_SIM_LAW_FREEPLAY || law->kind == AENL_SIM_LAW_HYSTERESIS)
        {
            inner[i] = law->inner_stiffness;
            if (model->type == AENL_SIM_SECTION3DOF || i != AENL_SIM_DOF_FLAP)
            {
                distinct = 1;
            }
        }
    }
    return distinct;
}

/* ---- assembly ----------------------------------------------------------------------------- */

/* Minv = M^-1 for the leading n x n block of the fixed-size arrays, through the flat n x n copy
 * the dense kernel takes; Minv is left as it was when M is singular. */
static int invert_small(int n, double M[AENL_SIM_MAX_Q][AENL_SIM_MAX_Q],
                        double Minv[AENL_SIM_MAX_Q][AENL_SIM_MAX_Q])
{
    const size_t m = (size_t)n;
    double a[AENL_SIM_MAX_Q * AENL_SIM_MAX_Q], inv[AENL_SIM_MAX_Q * AENL_SIM_MAX_Q];
    for (size_t i = 0; i < m; ++i)
    {
        for (size_t j = 0; j < m; ++j)
        {
            a[i * m + j] = M[i][j];
        }
    }
    if (aenl_dense_invert(a, inv, m) != 0)
    {
        return -1;
    }
    for (size_t i = 0; i < m; ++i)
    {
        for (size_t j = 0; j < m; ++j)
        {
            Minv[i][j] = inv[i * m + j];
        }
    }
    return 0;
}

/* Eight-state form (Lee, Price & Wong 1999): the Wagner integrals become the lag states w1..w4,
 * c0..c9 the coefficients of the plunge row, d0..d9 those of the pitch row; q = (ξ, α). */
static void build_airfoil(const aenl_sim_model_t *model, double ustar, int with_gust,
                          double gust_length, sim_sys_t *s)
{
    const aenl_sim_airfoil_t *p = &model->airfoil;
    const double mu = p->mu, ah = p->a_h, xa = p->x_alpha, ra2 = p->r_alpha * p->r_alpha;
    const double wb = p->omega_bar;
    const double A = 1.0 - SIM_PSI1 - SIM_PSI2, S = SIM_PSI1 * SIM_EPS1 + SIM_PSI2 * SIM_EPS2;
    const double k = 1.0 / (mu * ra2), hm = 0.5 - ah, e2 = 1.0 + 2.0 * ah;
    const double p1e1 = SIM_PSI1 * SIM_EPS1, p2e2 = SIM_PSI2 * SIM_EPS2;
    double c[10], d[10];
    c[0] = 1.0 + 1.0 / mu;
    c[1] = xa - ah / mu;
    c[2] = 2.0 * p->zeta_xi * wb / ustar + 2.0 * A / mu;
    c[3] = (1.0 + (1.0 - 2.0 * ah) * A) / mu;
    c[4] = 2.0 * S / mu;
    c[5] = (2.0 / mu) * (A + hm * S);
    c[6] = (2.0 / mu) * p1e1 * (1.0 - SIM_EPS1 * hm);
    c[7] = (2.0 / mu) * p2e2 * (1.0 - SIM_EPS2 * hm);
    c[8] = -(2.0 / mu) * p1e1 * SIM_EPS1;
    c[9] = -(2.0 / mu) * p2e2 * SIM_EPS2;
    d[0] = xa / ra2 - ah * k;
    d[1] = 1.0 + (1.0 + 8.0 * ah * ah) * k / 8.0;
    d[2] = 2.0 * p->zeta_alpha / ustar + hm * k - e2 * hm * A * k;
    d[3] = -e2 * k * (A + hm * S);
    d[4] = -e2 * A * k;
    d[5] = -e2 * S * k;
    d[6] = -e2 * k * p1e1 * (1.0 - SIM_EPS1 * hm);
    d[7] = -e2 * k * p2e2 * (1.0 - SIM_EPS2 * hm);
    d[8] = e2 * k * p1e1 * SIM_EPS1;
    d[9] = e2 * k * p2e2 * SIM_EPS2;

    s->nq = 2;
    s->nz = with_gust ? 6 : 4;
    s->dof[0] = AENL_SIM_DOF_PLUNGE;
    s->dof[1] = AENL_SIM_DOF_PITCH;
    s->M[0][0] = c[0];
    s->M[0][1] = c[1];
    s->M[1][0] = d[0];
    s->M[1][1] = d[1];
    s->C[0][0] = c[2];
    s->C[0][1] = c[3];
    s->C[1][0] = d[4];
    s->C[1][1] = d[2];
    s->K[0][0] = c[4];
    s->K[0][1] = c[5];
    s->K[1][0] = d[5];
    s->K[1][1] = d[3];
    /* z = (w1, w2, w3, w4): w1, w2 filter α; w3, w4 filter ξ. */
    s->Ez[0][0] = -c[6];
    s->Ez[0][1] = -c[7];
    s->Ez[0][2] = -c[8];
    s->Ez[0][3] = -c[9];
    s->Ez[1][0] = -d[6];
    s->Ez[1][1] = -d[7];
    s->Ez[1][2] = -d[8];
    s->Ez[1][3] = -d[9];
    s->Zq[0][1] = 1.0;
    s->Zz[0] = -SIM_EPS1;
    s->Zq[1][1] = 1.0;
    s->Zz[1] = -SIM_EPS2;
    s->Zq[2][0] = 1.0;
    s->Zz[2] = -SIM_EPS1;
    s->Zq[3][0] = 1.0;
    s->Zz[3] = -SIM_EPS2;
    s->kappa[0] = (wb / ustar) * (wb / ustar);
    s->kappa[1] = 1.0 / (ustar * ustar);
    if (with_gust)
    {
        /* Gust angle g through the Wagner filter: Γ_g = A g + ψ1ε1 zg1 + ψ2ε2 zg2,
         * zg_i' = g − ε_i zg_i. Loads: −C_L/(πμ) = −2Γ_g/μ, 2C_M/(πμr²) = (1+2a_h)kΓ_g. */
        s->Eg[0] = -2.0 * A / mu;
        s->Eg[1] = e2 * k * A;
        s->Ez[0][4] = -2.0 * p1e1 / mu;
        s->Ez[0][5] = -2.0 * p2e2 / mu;
        s->Ez[1][4] = e2 * k * p1e1;
        s->Ez[1][5] = e2 * k * p2e2;
        s->Zg[4] = 1.0;
        s->Zz[4] = -SIM_EPS1;
        s->Zg[5] = 1.0;
        s->Zz[5] = -SIM_EPS2;
        s->gust_T = gust_length; /* L/b in τ units */
    }
    if (p->ic_forcing)
    {
        const double f0 =
            (2.0 / mu) * (model->x0[AENL_SIM_DOF_PLUNGE] + hm * model->x0[AENL_SIM_DOF_PITCH]);
        s->forcing = 1;
        s->fvec[0] = f0;
        s->fvec[1] = -e2 / (2.0 * ra2) * f0;
        s->f_amp[0] = p1e1;
        s->f_amp[1] = p2e2;
        s->f_rate[0] = SIM_EPS1;
        s->f_rate[1] = SIM_EPS2;
    }
    s->freq_scale = ustar;
    s->n_out = 2;
    s->out_q[0] = 1; /* alpha */
    s->out_q[1] = 0; /* xi */
}

/* Conner's section: q = (h, α, β), Theodorsen's (1935) T-functions, Jones/Wagner lag on the
 * 3/4-chord downwash q̂. */
static void build_section(const aenl_sim_model_t *model, double U, int with_gust,
                          double gust_length, sim_sys_t *s)
{
    const aenl_sim_section_t *p = &model->section;
    const double b = p->b, a = p->a, c = p->c, rho = p->rho;
    const double sq = sqrt(1.0 - c * c), ac = acos(c);
    const double T1 = -(2.0 + c * c) * sq / 3.0 + c * ac;
    const double T3 = -(0.125 + c * c) * ac * ac + c * sq * ac * (7.0 + 2.0 * c * c) / 4.0 -
                      (1.0 - c * c) * (5.0 * c * c + 4.0) / 8.0;
    const double T4 = -ac + c * sq;
    const double T5 = -(1.0 - c * c) - ac * ac + 2.0 * c * sq * ac;
    const double T7 = -(0.125 + c * c) * ac + c * sq * (7.0 + 2.0 * c * c) / 8.0;
    const double T8 = -(2.0 * c * c + 1.0) * sq / 3.0 + c * ac;
    const double T9 = 0.5 * (sq * sq * sq / 3.0 + a * T4);
    const double T10 = sq + ac;
    const double T11 = ac * (1.0 - 2.0 * c) + sq * (2.0 - c);
    const double T12 = sq * (2.0 + c) - ac * (2.0 * c + 1.0);
    const double T13 = 0.5 * (-T7 - (c - a) * T1);
    const double pi = 3.14159265358979323846;
    const double Sa = p->m * b * p->x_alpha, Sb = p->m * b * p->x_beta;
    const double Ia = p->m * b * b * p->r_alpha * p->r_alpha;
    const double Ib = p->m * b * b * p->r_beta * p->r_beta;
    const double rb2 = rho * b * b, A = 1.0 - SIM_PSI1 - SIM_PSI2;
    const double psie[2] = {SIM_PSI1 * SIM_EPS1, SIM_PSI2 * SIM_EPS2};
    const double eps[2] = {SIM_EPS1, SIM_EPS2};
    double D[3][3] = {{0}}, Kn[3][3] = {{0}}, cvec[3], qh_q[3], qh_qd[3];
    int i, j;

    s->nq = 3;
    s->nz = 2;
    s->dof[0] = AENL_SIM_DOF_PLUNGE;
    s->dof[1] = AENL_SIM_DOF_PITCH;
    s->dof[2] = AENL_SIM_DOF_FLAP;
    /* Ms + Mnc */
    s->M[0][0] = p->m_t + rb2 * pi;
    s->M[0][1] = Sa - rb2 * pi * a * b;
    s->M[0][2] = Sb - rb2 * T1 * b;
    s->M[1][0] = Sa - rb2 * pi * a * b;
    s->M[1][1] = Ia + rb2 * pi * b * b * (0.125 + a * a);
    s->M[1][2] = Ib + b * (c - a) * Sb - rb2 * (T7 + (c - a) * T1) * b * b;
    s->M[2][0] = Sb - rb2 * T1 * b;
    s->M[2][1] = Ib + b * (c - a) * Sb + rb2 * 2.0 * T13 * b * b;
    s->M[2][2] = Ib - rb2 * T3 * b * b / pi;
    /* Non-circulatory velocity and stiffness terms: Q_nc = −D q̇ − Kn q. */
    D[0][1] = rb2 * U * pi;
    D[0][2] = -rb2 * U * T4;
    D[1][1] = rb2 * pi * (0.5 - a) * U * b;
    D[1][2] = rb2 * (T1 - T8 - (c - a) * T4 + 0.5 * T11) * U * b;
    D[2][1] = rb2 * (-2.0 * T9 - T1 + T4 * (a - 0.5)) * U * b;
    D[2][2] = -rb2 * U * b * T4 * T11 / (2.0 * pi);
    Kn[1][2] = rb2 * (T4 + T10) * U * U;
    Kn[2][2] = rb2 * U * U * (T5 - T4 * T10) / pi;
    /* Circulatory loads (−L, M_α, M_β) = cvec Γ. */
    cvec[0] = -2.0 * pi * rho * U * U * b;
    cvec[1] = 2.0 * pi * rho * U * U * b * b * (a + 0.5);
    cvec[2] = -rho * U * U * b * b * T12;
    qh_q[0] = 0.0;
    qh_q[1] = 1.0;
    qh_q[2] = T10 / pi;
    qh_qd[0] = 1.0 / U;
    qh_qd[1] = b * (0.5 - a) / U;
    qh_qd[2] = b * T11 / (2.0 * pi * U);
    s->C[0][0] = 2.0 * p->m * p->omega_h * p->zeta_h;
    s->C[1][1] = 2.0 * Ia * p->omega_alpha * p->zeta_alpha;
    s->C[2][2] = 2.0 * Ib * p->omega_beta * p->zeta_beta;
    for (i = 0; i < 3; ++i)
    {
        for (j = 0; j < 3; ++j)
        {
            s->C[i][j] += D[i][j] - cvec[i] * A * qh_qd[j];
            s->K[i][j] = Kn[i][j] - cvec[i] * A * qh_q[j];
        }
        for (j = 0; j < 2; ++j)
        {
            s->Ez[i][j] = cvec[i] * psie[j];
        }
        s->Eg[i] = with_gust ? cvec[i] * A : 0.0;
    }
    for (j = 0; j < 2; ++j)
    {
        for (i = 0; i < 3; ++i)
        {
            s->Zq[j][i] = (U / b) * qh_q[i];
            s->Zqd[j][i] = (U / b) * qh_qd[i];
        }
        s->Zz[j] = -(U / b) * eps[j];
        s->Zg[j] = with_gust ? U / b : 0.0;
    }
    s->kappa[0] = p->m * p->omega_h * p->omega_h;
    s->kappa[1] = Ia * p->omega_alpha * p->omega_alpha;
    s->kappa[2] = Ib * p->omega_beta * p->omega_beta;
    if (with_gust)
    {
        s->gust_T = gust_length / U;
    }
    s->freq_scale = 1.0 / (2.0 * pi);
    s->n_out = 3;
    s->out_q[0] = 0;
    s->out_q[1] = 1;
    s->out_q[2] = 2;
}

int sim_gust_order(aenl_sim_gust_t spectrum)
{
    return spectrum == AENL_SIM_GUST_DRYDEN ? 2 : 1;
}

int sim_gust_states(const aenl_sim_run_t *run)
{
    return run->turbulence ? sim_gust_order(run->turb_spectrum) : 0;
}

double sim_dryden_output(double z1, double z2)
{
    return SIM_SQRT3 * z1 + (1.0 - SIM_SQRT3) * z2;
}

double sim_gust_angle(const sim_sys_t *s, const double *x)
{
    switch (s->gust)
    {
        case 1:
            return x[s->nx - 1];
        case 2:
            return sim_dryden_output(x[s->nx - 2], x[s->nx - 1]);
        default:
            return 0.0;
    }
}

aenl_status_t sim_sys_build(const aenl_sim_model_t *model, double velocity, int n_gust,
                            double gust_length, sim_sys_t *sys, aenl_err_t *err)
{
    int i;
    memset(sys, 0, sizeof(*sys));
    if (!isfinite(velocity) || !(velocity > 0.0))
    {
        aenl_err_set(err, "velocity must be > 0 (got %g)", velocity);
        return AENL_E_ARG;
    }
    sys->type = model->type;
    if (model->type == AENL_SIM_AIRFOIL2DOF)
    {
        build_airfoil(model, velocity, n_gust > 0, gust_length, sys);
    }
    else
    {
        build_section(model, velocity, n_gust > 0, gust_length, sys);
    }
    sys->gust = n_gust;
    sys->nx = 2 * sys->nq + sys->nz + sys->gust;
    for (i = 0; i < sys->nq; ++i)
    {
        sys->law[i] = model->law[sys->dof[i]];
    }
    if (invert_small(sys->nq, sys->M, sys->Minv) != 0)
    {
        aenl_err_set(err, "singular mass matrix");
        return AENL_E_NUMERIC;
    }
    return AENL_OK;
}

/* ---- right-hand side ---------------------------------------------------------------------- */

/* Loads except restoring: F = −C q̇ − K q + Ez z + Eg g + fvec φ(t). */
static void loads(const sim_sys_t *s, double t, const double *x, int with_forcing, double *F)
{
    const int nq = s->nq, nz = s->nz;
    const double *q = x, *qd = x + nq, *z = x + (ptrdiff_t)2 * nq;
    const double g = sim_gust_angle(s, x);
    double phi = 0.0;
    int i, j;
    if (with_forcing && s->forcing)
    {
        phi = s->f_amp[0] * exp(-s->f_rate[0] * t) + s->f_amp[1] * exp(-s->f_rate[1] * t);
    }
    for (i = 0; i < nq; ++i)
    {
        double acc = s->Eg[i] * g + s->fvec[i] * phi;
        for (j = 0; j < nq; ++j)
        {
            acc -= s->C[i][j] * qd[j] + s->K[i][j] * q[j];
        }
        for (j = 0; j < nz; ++j)
        {
            acc += s->Ez[i][j] * z[j];
        }
        F[i] = acc;
    }
    if (with_forcing && s->force != NULL)
    {
        F[s->force_q] += s->kappa[s->force_q] * sim_force_eval(s->force, t);
    }
}

static void lag_rhs(const sim_sys_t *s, const double *x, double u, double *dx)
{
    const int nq = s->nq, nz = s->nz;
    const double *q = x, *qd = x + nq, *z = x + (ptrdiff_t)2 * nq;
    const double g = sim_gust_angle(s, x);
    int k, j;
    for (k = 0; k < nz; ++k)
    {
        double acc = s->Zz[k] * z[k] + s->Zg[k] * g;
        for (j = 0; j < nq; ++j)
        {
            acc += s->Zq[k][j] * q[j] + s->Zqd[k][j] * qd[j];
        }
        dx[2 * nq + k] = acc;
    }
    if (s->gust == 1)
    {
        dx[s->nx - 1] = (u - g) / s->gust_T;
    }
    else if (s->gust == 2)
    {
        dx[s->nx - 2] = (u - x[s->nx - 2]) / s->gust_T;
        dx[s->nx - 1] = (x[s->nx - 2] - x[s->nx - 1]) / s->gust_T;
    }
}

void sim_rhs(const sim_sys_t *s, const sim_mode_t *mode, double t, const double *x, double u,
             double *dx, double *rreq)
{
    const int nq = s->nq;
    double F[AENL_SIM_MAX_Q], a[AENL_SIM_MAX_Q];
    int i, j, n_stuck = 0;
    loads(s, t, x, 1, F);
    for (i = 0; i < nq; ++i)
    {
        if (mode->b[i].stuck)
        {
            ++n_stuck;
            continue;
        }
        F[i] -= s->kappa[i] * sim_law_branch(&s->law[i], mode->b[i].region, mode->b[i].dir, x[i]);
    }
    if (n_stuck == 0)
    {
        for (i = 0; i < nq; ++i)
        {
            double acc = 0.0;
            for (j = 0; j < nq; ++j)
            {
                acc += s->Minv[i][j] * F[j];
            }
            a[i] = acc;
        }
    }
    else
    {
        /* Sliding mode: q̈_i = 0 for stuck i; the free rows give the other accelerations. */
        int fr[AENL_SIM_MAX_Q], nf = 0;
        for (i = 0; i < nq; ++i)
        {
            if (!mode->b[i].stuck)
            {
                fr[nf++] = i;
            }
        }
        for (i = 0; i < nq; ++i)
        {
            a[i] = 0.0;
        }
        if (nf > 0)
        {
            double Mf[AENL_SIM_MAX_Q][AENL_SIM_MAX_Q], Mfi[AENL_SIM_MAX_Q][AENL_SIM_MAX_Q];
            int r, cc;
            for (r = 0; r < nf; ++r)
            {
                for (cc = 0; cc < nf; ++cc)
                {
                    Mf[r][cc] = s->M[fr[r]][fr[cc]];
                }
            }
            /* principal submatrix of an SPD-like M; if singular all accelerations stay 0 (Mfi
             * would be uninitialised) */
            const int singular = invert_small(nf, Mf, Mfi) != 0;
            for (r = 0; r < nf && !singular; ++r)
            {
                double acc = 0.0;
                for (cc = 0; cc < nf; ++cc)
                {
                    acc += Mfi[r][cc] * F[fr[cc]];
                }
                a[fr[r]] = acc;
            }
        }
    }
    if (rreq != NULL)
    {
        for (i = 0; i < nq; ++i)
        {
            rreq[i] = 0.0;
            if (mode->b[i].stuck)
            {
                double acc = F[i];
                for (j = 0; j < nq; ++j)
                {
                    acc -= s->M[i][j] * a[j];
                }
                rreq[i] = acc / s->kappa[i];
            }
        }
    }
    for (i = 0; i < nq; ++i)
    {
        dx[i] = mode->b[i].stuck ? 0.0 : x[nq + i];
        dx[nq + i] = a[i];
    }
    lag_rhs(s, x, u, dx);
}

void sim_rhs_linear(const sim_sys_t *s, const double *slope_q, const double *x, double *dx)
{
    const int nq = s->nq;
    double F[AENL_SIM_MAX_Q];
    int i, j;
    loads(s, 0.0, x, 0, F);
    for (i = 0; i < nq; ++i)
    {
        F[i] -= s->kappa[i] * slope_q[i] * x[i];
    }
    for (i = 0; i < nq; ++i)
    {
        double acc = 0.0;
        for (j = 0; j < nq; ++j)
        {
            acc += s->Minv[i][j] * F[j];
        }
        dx[i] = x[nq + i];
        dx[nq + i] = acc;
    }
    lag_rhs(s, x, 0.0, dx);
}
