/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_identify_model.c
 * @brief The model-based verdict of `aenl identify --model`: a diagnosis against the baseline
 *        model (aenl_diagnose.h) read in the classes of identify (aenl_identify.h).
 */
#include <math.h>
#include <string.h>

#include "aenl_tools/aenl_identify.h"

/* The class of identify an effect of diagnose stands for; hardening from the cubic's sign. */
static aenl_class_t class_of(aenl_diagnose_effect_t e)
{
    switch (e)
    {
        case AENL_DIAGNOSE_FREEPLAY:
            return AENL_CLASS_FREEPLAY;
        case AENL_DIAGNOSE_HYSTERESIS:
            return AENL_CLASS_HYSTERESIS;
        case AENL_DIAGNOSE_POLYNOMIAL:
            return AENL_CLASS_POLYNOMIAL;
        case AENL_DIAGNOSE_PRELOAD: /* a constant moment: the stiffness keeps its slope */
        case AENL_DIAGNOSE_NONE:
        default:
            return AENL_CLASS_LINEAR;
    }
}

/* Weight exp(-score / 2) relative to the least score s0 (so the best is 1, nothing overflows). */
static double weight(double score, double s0)
{
    return isfinite(score) ? exp(-0.5 * (score - s0)) : 0.0;
}

/* Standard error of parameter k of the named effect (NaN: none given). */
static double sd_of(const aenl_diagnose_result_t *d, size_t k)
{
    return k < d->n_param_sd && isfinite(d->param_sd[k]) ? d->param_sd[k] : (double)NAN;
}

/*
 * Switching points of the fitted law (aenl_sim_law_switch_points) with their standard errors: a
 * point at ±α_f gets sd(α_f), one at ±(α_f + δ) gets sd(α_f) + sd(δ), the most its error can be
 * whatever their correlation (a tie, |α_f| = |α_f + δ|, takes the larger).
 */
static void law_points(const aenl_diagnose_result_t *d, const aenl_sim_law_t *law,
                       aenl_classifier_result_t *res)
{
    const double sd_delta = sd_of(d, 0), sd_start = sd_of(d, 1);
    const double a = fabs(law->x_f), b = fabs(law->x_f + law->delta);
    double p[4];
    const size_t n = aenl_sim_law_switch_points(law, p);
    res->n_switch = 0;
    for (size_t i = 0; i < n && i < AENL_CLASSIFIER_MAX_SWITCH; ++i)
    {
        const int outer = law->kind == AENL_SIM_LAW_FREEPLAY
                              ? i == 1u
                              : fabs(fabs(p[i]) - b) <= fabs(fabs(p[i]) - a);
        res->switch_points[i] = (aenl_real_t)p[i];
        res->switch_std[i] = (aenl_real_t)(outer ? sd_start + sd_delta : sd_start);
        res->n_switch++;
    }
}

/* Index of the channel of res named like model channel q, or -1. */
static long channel_named(const aenl_identify_result_t *res, const aenl_diagnose_result_t *d,
                          size_t q)
{
    long k_named = -1;
    for (size_t k = 0; q < d->n_channels && k < res->n_channels; ++k)
    {
        k_named = strcmp(res->ch[k].name, d->names[q]) == 0 ? (long)k : k_named;
    }
    return k_named;
}

aenl_status_t aenl_identify_apply_model(aenl_identify_result_t *res,
                                        const aenl_diagnose_result_t *d, aenl_err_t *err)
{
    const aenl_sim_type_t type = d->updated.type;
    const long named = d->effect != AENL_DIAGNOSE_NONE
                           ? channel_named(res, d, aenl_diagnose_dof_channel(type, d->dof))
                           : -1;
    if (d->effect != AENL_DIAGNOSE_NONE && named < 0)
    {
        aenl_err_set(err,
                     "the channel of the DOF the diagnosis names (%s) is not among the channels "
                     "identified",
                     aenl_diagnose_dof_name(d->dof));
        return AENL_E_ARG;
    }
    aenl_identify_model_t *m = &res->model;
    memset(m, 0, sizeof(*m));
    m->applied = 1;
    m->explained = d->explained;
    m->effect = d->effect;
    m->dof = d->dof;
    m->data_verdict = res->verdict;
    m->data_class = res->verdict_class;
    m->data_confidence = res->verdict_confidence;
    m->gap_before = d->gap_before[d->n_channels];
    m->gap_after = d->gap_after[d->n_channels];
    if (!d->explained || d->effect == AENL_DIAGNOSE_NONE)
    {
        /* No disagreement it can explain, or none beyond twice the noise floor: the test has no
         * evidence either way (a small law under turbulence stays within the floor), and the
         * record's own analysis, an independent test, stands. */
        return AENL_OK;
    }
    /* Weights of the baseline and of every calibrated candidate from their penalised gaps. */
    const double g0 = d->gap_before[d->n_channels] / d->common_floor, s_base = g0 * g0;
    double s0 = s_base;
    for (size_t i = 0; i < d->n_cand; ++i)
    {
        s0 = isfinite(d->cand[i].score) && d->cand[i].score < s0 ? d->cand[i].score : s0;
    }
    const aenl_class_t cls = class_of(d->effect);
    double w_all = weight(s_base, s0), w_lin = w_all, w_dof[3] = {0.0, 0.0, 0.0}, w_named = 0.0;
    for (size_t i = 0; i < d->n_cand; ++i)
    {
        const aenl_diagnose_cand_t *cd = &d->cand[i];
        const double w = weight(cd->score, s0);
        const aenl_class_t c = class_of(cd->effect);
        w_all += w;
        w_lin += c == AENL_CLASS_LINEAR ? w : 0.0;
        w_dof[cd->dof] += c != AENL_CLASS_LINEAR ? w : 0.0;
        w_named += c == cls && cd->dof == d->dof ? w : 0.0;
    }
    /* Every channel of the model: the named one takes the fitted law, the others are linear
     * with the weight of every way of their DOF not carrying a law. */
    for (size_t dof = 0; dof < d->n_channels && dof < 3u; ++dof)
    {
        const long k = channel_named(res, d, aenl_diagnose_dof_channel(type, (aenl_sim_dof_t)dof));
        if (k < 0)
        {
            continue;
        }
        aenl_identify_channel_t *c = &res->ch[k];
        memset(&c->res, 0, sizeof(c->res));
        c->explained_by = -1;
        if (k != named || cls == AENL_CLASS_LINEAR)
        {
            c->res.cls = AENL_CLASS_LINEAR;
            c->res.confidence = (aenl_real_t)(1.0 - w_dof[dof] / w_all);
            c->res.prob[AENL_CLASS_LINEAR] = c->res.confidence;
            continue;
        }
        const aenl_sim_law_t *law = &d->updated.law[d->dof];
        c->res.cls = cls;
        c->res.confidence = (aenl_real_t)(w_named / w_dof[dof]);
        c->res.prob[cls] = c->res.confidence;
        const double c3 = law->n_coeffs >= 3u ? law->coeffs[2] : 0.0;
        c->res.hardening = 0;
        if (cls == AENL_CLASS_POLYNOMIAL && c3 > 0.0)
        {
            c->res.hardening = 1;
        }
        else if (cls == AENL_CLASS_POLYNOMIAL && c3 < 0.0)
        {
            c->res.hardening = -1;
        }
        law_points(d, law, &c->res);
    }
    if (cls == AENL_CLASS_LINEAR)
    {
        res->verdict = -1;
        res->verdict_class = AENL_CLASS_LINEAR;
        res->verdict_share = 0.0;
        res->verdict_confidence = w_lin / w_all;
        return AENL_OK;
    }
    res->verdict = named;
    res->verdict_class = cls;
    res->verdict_share = w_dof[d->dof] / w_all;
    res->verdict_confidence = w_named / w_all;
    return AENL_OK;
}

aenl_status_t aenl_identify_model_test(aenl_identify_result_t *res, const aenl_table_t *record,
                                       const aenl_sim_model_t *base, const aenl_sim_run_t *run,
                                       aenl_err_t *err)
{
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    aenl_diagnose_result_t d;
    aenl_status_t st = aenl_diagnose_run(record, base, run, &o, &d, err);
    if (st == AENL_OK)
    {
        st = aenl_identify_apply_model(res, &d, err);
        aenl_diagnose_result_free(&d);
    }
    return st;
}
