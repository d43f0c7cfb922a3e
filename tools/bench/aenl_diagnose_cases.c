/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose_cases.c
 * @brief Hidden-effect cases for the diagnosis tests and `aenl bench diagnose`: a truth model
 *        with one structural effect (parameters and seeds drawn from a seed the diagnosis never
 *        sees, measurement noise at SNR 3) and a baseline of the same test lacking it.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "aenl_diagnose_cases.h"
#include "aenl_tools/aenl_rng.h"

static const double k_rad = 0.017453292519943295769;

typedef struct
{
    const char *name;
    aenl_sim_type_t type;
    aenl_diagnose_effect_t effect;
    aenl_sim_dof_t dof;
    double velocity;
    double turbulence; /* intensity (0: none) */
} case_spec_t;

static const case_spec_t k_cases[] = {
    {"a2_freeplay_pitch", AENL_SIM_AIRFOIL2DOF, AENL_DIAGNOSE_FREEPLAY, AENL_SIM_DOF_PITCH, 5.5,
     0.0005},
    {"a2_hysteresis_pitch", AENL_SIM_AIRFOIL2DOF, AENL_DIAGNOSE_HYSTERESIS, AENL_SIM_DOF_PITCH, 5.0,
     0.0005},
    {"a2_polynomial_pitch", AENL_SIM_AIRFOIL2DOF, AENL_DIAGNOSE_POLYNOMIAL, AENL_SIM_DOF_PITCH, 6.5,
     0.0005},
    {"a2_preload_pitch", AENL_SIM_AIRFOIL2DOF, AENL_DIAGNOSE_PRELOAD, AENL_SIM_DOF_PITCH, 4.5,
     0.002},
    {"a2_none", AENL_SIM_AIRFOIL2DOF, AENL_DIAGNOSE_NONE, AENL_SIM_DOF_PITCH, 5.5, 0.001},
    {"s3_freeplay_flap", AENL_SIM_SECTION3DOF, AENL_DIAGNOSE_FREEPLAY, AENL_SIM_DOF_FLAP, 15.0,
     0.002},
    {"s3_freeplay_pitch", AENL_SIM_SECTION3DOF, AENL_DIAGNOSE_FREEPLAY, AENL_SIM_DOF_PITCH, 15.0,
     0.002},
    {"s3_hysteresis_flap", AENL_SIM_SECTION3DOF, AENL_DIAGNOSE_HYSTERESIS, AENL_SIM_DOF_FLAP, 15.0,
     0.002},
    {"s3_polynomial_pitch", AENL_SIM_SECTION3DOF, AENL_DIAGNOSE_POLYNOMIAL, AENL_SIM_DOF_PITCH,
     25.0, 0.002},
    {"s3_preload_flap", AENL_SIM_SECTION3DOF, AENL_DIAGNOSE_PRELOAD, AENL_SIM_DOF_FLAP, 12.0,
     0.005},
    {"s3_none", AENL_SIM_SECTION3DOF, AENL_DIAGNOSE_NONE, AENL_SIM_DOF_PITCH, 12.0, 0.005},
};

size_t aenl_diagnose_n_cases(void)
{
    return sizeof(k_cases) / sizeof(k_cases[0]);
}

static double uni(aenl_rng_t *g, double lo, double hi)
{
    return lo + (hi - lo) * aenl_rng_uniform(g);
}

/* The truth's law (angles in rad) and its initial displacement, drawn from g. */
static void draw_truth(const case_spec_t *cs, aenl_rng_t *g, aenl_sim_model_t *m)
{
    aenl_sim_law_t *law = &m->law[cs->dof];
    const aenl_sim_dof_t d = cs->dof;
    const int a2 = cs->type == AENL_SIM_AIRFOIL2DOF;
    switch (cs->effect)
    {
        case AENL_DIAGNOSE_FREEPLAY:
            law->kind = AENL_SIM_LAW_FREEPLAY;
            if (a2)
            {
                law->delta = uni(g, 0.3, 0.8) * k_rad;
                law->x_f = uni(g, 0.1, 0.4) * k_rad;
                m->x0[d] = law->x_f + 2.5 * law->delta;
            }
            else if (d == AENL_SIM_DOF_FLAP)
            {
                const double half = uni(g, 1.0, 2.5) * k_rad; /* Conner's half gap */
                law->delta = 2.0 * half;
                law->x_f = -half * uni(g, 0.8, 1.2);
                m->x0[AENL_SIM_DOF_PITCH] = 1.0 * k_rad;
            }
            else
            {
                law->delta = uni(g, 0.6, 1.5) * k_rad;
                law->x_f = -law->delta * uni(g, 0.3, 0.7);
                m->x0[AENL_SIM_DOF_PITCH] = 2.0 * k_rad;
            }
            break;
        case AENL_DIAGNOSE_HYSTERESIS:
            law->kind = AENL_SIM_LAW_HYSTERESIS;
            if (a2)
            {
                law->delta = uni(g, 0.3, 0.7) * k_rad;
                law->x_f = law->delta * uni(g, 0.4, 0.6);
                law->preload = law->delta * uni(g, 0.4, 0.6);
                m->x0[d] = 4.0 * law->delta;
            }
            else
            {
                law->delta = uni(g, 1.5, 3.0) * k_rad;
                law->x_f = law->delta * uni(g, 0.4, 0.6);
                law->preload = law->delta * uni(g, 0.2, 0.3);
                m->x0[AENL_SIM_DOF_PITCH] = 1.0 * k_rad;
                m->x0[d] = 2.0 * law->delta;
            }
            break;
        case AENL_DIAGNOSE_POLYNOMIAL:
            law->kind = AENL_SIM_LAW_POLYNOMIAL;
            law->n_coeffs = 3;
            law->coeffs[0] = 1.0;
            law->coeffs[1] = 0.0;
            law->coeffs[2] = a2 ? uni(g, 2.0, 6.0) : uni(g, 5.0, 15.0);
            m->x0[AENL_SIM_DOF_PITCH] = 1.0 * k_rad;
            break;
        case AENL_DIAGNOSE_PRELOAD:
        {
            const double sign = aenl_rng_uniform(g) < 0.5 ? -1.0 : 1.0;
            law->kind = AENL_SIM_LAW_FREEPLAY;
            law->delta = 1e-9;
            law->inner_stiffness = 1.0;
            law->preload = sign * (a2 ? uni(g, 0.3, 1.0) : uni(g, 1.0, 3.0)) * k_rad;
            break;
        }
        case AENL_DIAGNOSE_NONE:
        default:
            m->x0[AENL_SIM_DOF_PITCH] = 1.0 * k_rad;
            break;
    }
}

aenl_status_t aenl_diagnose_case_make(size_t index, uint64_t seed, int long_record,
                                      aenl_diagnose_case_t *c, aenl_err_t *err)
{
    memset(c, 0, sizeof(*c));
    if (index >= aenl_diagnose_n_cases())
    {
        aenl_err_set(err, "case %zu: only %zu cases", index, aenl_diagnose_n_cases());
        return AENL_E_ARG;
    }
    const case_spec_t *cs = &k_cases[index];
    (void)snprintf(c->name, sizeof(c->name), "%s", cs->name);
    c->effect = cs->effect;
    c->dof = cs->dof;
    aenl_rng_t g;
    aenl_rng_seed(&g, seed * 1000003u + index);
    aenl_sim_model_default(&c->truth, cs->type);
    aenl_sim_set_velocity(&c->truth, cs->velocity);
    draw_truth(cs, &g, &c->truth);
    aenl_sim_run_t *tr = &c->truth_run;
    aenl_sim_run_default(tr, cs->type);
    if (cs->type == AENL_SIM_AIRFOIL2DOF)
    {
        tr->dt = 0.5;
        tr->duration = long_record ? 5999.5 : 2999.5;
    }
    else
    {
        tr->dt = long_record ? 0.001 : 0.002;
        tr->duration = long_record ? 60.0 : 12.0;
    }
    tr->turbulence = cs->turbulence > 0.0;
    tr->turb_intensity = cs->turbulence;
    tr->turb_seed = 1000u + (aenl_rng_next(&g) >> 40u); /* hidden from the diagnosis */
    tr->snr = 3.0;
    tr->noise_seed = 5000u + (aenl_rng_next(&g) >> 40u);
    /* The baseline: the same test with that DOF linear, and its own seeds. */
    c->base = c->truth;
    memset(&c->base.law[cs->dof], 0, sizeof(c->base.law[cs->dof]));
    c->base.law[cs->dof].kind = AENL_SIM_LAW_LINEAR;
    c->base_run = *tr;
    c->base_run.turb_seed = 1;
    c->base_run.snr = 0.0;
    c->base_run.noise_seed = 42;
    return AENL_OK;
}

aenl_status_t aenl_diagnose_case_measure(const aenl_diagnose_case_t *c, aenl_table_t *out,
                                         aenl_err_t *err)
{
    memset(out, 0, sizeof(*out));
    aenl_sim_result_t r;
    aenl_status_t st =
        c->truth_rk4_steps > 0u
            ? aenl_sim_simulate_rk4(&c->truth, &c->truth_run,
                                    c->truth_run.dt / (double)c->truth_rk4_steps, &r, err)
            : aenl_sim_simulate(&c->truth, &c->truth_run, &r, err);
    if (st != AENL_OK)
    {
        return st;
    }
    const char *names[1 + AENL_SIM_MAX_Q];
    for (size_t k = 0; k <= r.n_channels; ++k)
    {
        names[k] = r.names[k];
    }
    st = aenl_table_alloc(out, r.n_samples, r.n_channels + 1u, names, err);
    if (st == AENL_OK)
    {
        memcpy(out->data, r.t, r.n_samples * sizeof(double));
        memcpy(out->data + r.n_samples, r.y, r.n_channels * r.n_samples * sizeof(double));
    }
    aenl_sim_result_free(&r);
    return st;
}

aenl_status_t aenl_diagnose_case_bound(const aenl_diagnose_case_t *c, unsigned n_rep,
                                       unsigned n_jac, double rel_sd[AENL_DIAGNOSE_MAX_PAR],
                                       size_t *n_par, aenl_err_t *err)
{
    const aenl_status_t st = aenl_diagnose_bound(&c->truth, &c->truth_run, c->effect, c->dof, NULL,
                                                 n_rep, n_jac, rel_sd, n_par, err);
    for (size_t k = 0; k < *n_par && st == AENL_OK; ++k)
    {
        rel_sd[k] /=
            fmax(fabs(aenl_diagnose_param_get(&c->truth.law[c->dof], c->effect, k)), 1e-300);
    }
    return st;
}
