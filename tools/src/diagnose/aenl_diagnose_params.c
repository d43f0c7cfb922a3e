/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_diagnose_params.c
 * @brief The parameters of each structural effect as a vector: count, names, get and set in a
 *        law, and relative errors against a known law.
 */
#include <math.h>

#include "aenl_diagnose_internal.h"

/* Pointer to parameter k of `effect` in law l (the order of aenl_diagnose_law_n_params). */
static double *param_ptr(aenl_sim_law_t *l, aenl_diagnose_effect_t effect, size_t k)
{
    switch (effect)
    {
        case AENL_DIAGNOSE_POLYNOMIAL:
            return k == 0u ? &l->coeffs[2] : &l->coeffs[4];
        case AENL_DIAGNOSE_PRELOAD:
            return &l->preload;
        case AENL_DIAGNOSE_FREEPLAY:
        case AENL_DIAGNOSE_HYSTERESIS:
        case AENL_DIAGNOSE_NONE:
        default:
            return k == 0u ? &l->delta : (k == 1u ? &l->x_f : &l->preload);
    }
}

size_t aenl_diagnose_n_params(aenl_diagnose_effect_t effect)
{
    switch (effect)
    {
        case AENL_DIAGNOSE_FREEPLAY:
            return 2;
        case AENL_DIAGNOSE_HYSTERESIS:
            return 3;
        case AENL_DIAGNOSE_POLYNOMIAL:
        case AENL_DIAGNOSE_PRELOAD:
            return 1;
        case AENL_DIAGNOSE_NONE:
        default:
            return 0;
    }
}

size_t aenl_diagnose_law_n_params(aenl_diagnose_effect_t effect, const aenl_sim_law_t *law)
{
    if (effect == AENL_DIAGNOSE_POLYNOMIAL && law->kind == AENL_SIM_LAW_POLYNOMIAL &&
        law->n_coeffs >= 5u)
    {
        return 2;
    }
    return aenl_diagnose_n_params(effect);
}

double aenl_diagnose_param_get(const aenl_sim_law_t *law, aenl_diagnose_effect_t effect, size_t k)
{
    aenl_sim_law_t l = *law;
    return *param_ptr(&l, effect, k);
}

void aenl_diagnose_param_set(aenl_sim_law_t *law, aenl_diagnose_effect_t effect, size_t k, double v)
{
    if (effect == AENL_DIAGNOSE_POLYNOMIAL && k > 0u && law->n_coeffs < 5u)
    {
        for (size_t i = law->n_coeffs; i < 5u; ++i)
        {
            law->coeffs[i] = 0.0;
        }
        law->n_coeffs = 5;
    }
    *param_ptr(law, effect, k) = v;
}

const char *aenl_diagnose_param_name(aenl_diagnose_effect_t effect, size_t k)
{
    static const char *const gap[] = {"delta", "alpha_f", "M0"};
    switch (effect)
    {
        case AENL_DIAGNOSE_POLYNOMIAL:
            return k == 0u ? "c3" : "c5";
        case AENL_DIAGNOSE_PRELOAD:
            return "M0";
        case AENL_DIAGNOSE_FREEPLAY:
        case AENL_DIAGNOSE_HYSTERESIS:
        case AENL_DIAGNOSE_NONE:
        default:
            return gap[k < 3u ? k : 2u];
    }
}

size_t aenl_diagnose_param_errors(aenl_diagnose_effect_t effect, const aenl_sim_law_t *truth,
                                  const aenl_sim_law_t *fit, double rel[AENL_DIAGNOSE_MAX_PAR])
{
    const size_t np = aenl_diagnose_n_params(effect);
    for (size_t k = 0; k < np; ++k)
    {
        const double t = aenl_diagnose_param_get(truth, effect, k);
        const double f = effect == AENL_DIAGNOSE_POLYNOMIAL && fit->n_coeffs < 3u
                             ? 0.0
                             : aenl_diagnose_param_get(fit, effect, k);
        rel[k] = fabs(f - t) / fmax(fabs(t), 1e-300);
    }
    return np;
}
