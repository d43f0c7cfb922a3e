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

/* The weights exp(-score / 2) of a diagnosis' baseline and candidates: all of them, those that
 * leave the structure linear, those with a law per DOF, and those of the named class on the
 * named DOF. */
typedef struct
{
    double all, lin, dof[3], named;
} weights_t;

static void model_weights(const aenl_diagnose_result_t *d, weights_t *w)
{
    const double g0 = d->gap_before[d->n_channels] / d->common_floor, s_base = d->m_eff * g0 * g0;
    double s0 = s_base;
    for (size_t i = 0; i < d->n_cand; ++i)
    {
        s0 = isfinite(d->cand[i].score) && d->cand[i].score < s0 ? d->cand[i].score : s0;
    }
    const aenl_class_t cls = class_of(d->effect);
    memset(w, 0, sizeof(*w));
    w->all = weight(s_base, s0);
    w->lin = w->all;
    for (size_t i = 0; i < d->n_cand; ++i)
    {
        const aenl_diagnose_cand_t *cd = &d->cand[i];
        const double wi = weight(cd->score, s0);
        const aenl_class_t c = class_of(cd->effect);
        w->all += wi;
        w->lin += c == AENL_CLASS_LINEAR ? wi : 0.0;
        w->dof[cd->dof] += c != AENL_CLASS_LINEAR ? wi : 0.0;
        w->named += c == cls && cd->dof == d->dof ? wi : 0.0;
    }
}

/* Channel c takes the law the diagnosis d fitted to its named DOF, class cls (not linear). */
static void set_law(aenl_identify_channel_t *c, const aenl_diagnose_result_t *d, aenl_class_t cls,
                    double confidence)
{
    const aenl_sim_law_t *law = &d->updated.law[d->dof];
    memset(&c->res, 0, sizeof(c->res));
    c->explained_by = -1;
    c->res.cls = cls;
    c->res.confidence = (aenl_real_t)confidence;
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
    m->effect2 = AENL_DIAGNOSE_NONE;
    m->gap_after2 = (double)NAN;
    m->n_diagnoses = 1;
    m->base_test = -1;
    if (d->explained && d->effect == AENL_DIAGNOSE_NONE)
    {
        m->base_test = aenl_diagnose_baseline_agrees(d);
        m->base_sum = d->base_test;
    }
    if (!d->explained || (d->effect == AENL_DIAGNOSE_NONE && m->base_test != 1))
    {
        /* No disagreement it can explain; or none beyond twice the noise floor by the gap, but
         * the precise summaries reject the baseline (a small law under turbulence stays within
         * the floor) or could not be tested: the test has no evidence either way, and the
         * record's own analysis, an independent test, stands. A baseline that both accept is
         * the record's model: linear. */
        return AENL_OK;
    }
    /* Weights of the baseline and of every calibrated candidate from their penalised gaps. */
    weights_t w;
    model_weights(d, &w);
    const aenl_class_t cls = class_of(d->effect);
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
        if (k != named || cls == AENL_CLASS_LINEAR)
        {
            memset(&c->res, 0, sizeof(c->res));
            c->explained_by = -1;
            c->res.cls = AENL_CLASS_LINEAR;
            c->res.confidence = (aenl_real_t)(1.0 - w.dof[dof] / w.all);
            c->res.prob[AENL_CLASS_LINEAR] = c->res.confidence;
            continue;
        }
        set_law(c, d, cls, w.named / w.dof[dof]);
    }
    if (cls == AENL_CLASS_LINEAR)
    {
        res->verdict = -1;
        res->verdict_class = AENL_CLASS_LINEAR;
        res->verdict_share = 0.0;
        res->verdict_confidence = w.lin / w.all;
        return AENL_OK;
    }
    res->verdict = named;
    res->verdict_class = cls;
    res->verdict_share = w.dof[d->dof] / w.all;
    res->verdict_confidence = w.named / w.all;
    return AENL_OK;
}

/* 1 when diagnosis d names an effect it explains, with a law of identify's classes. */
static int names_law(const aenl_diagnose_result_t *d)
{
    return d->explained && class_of(d->effect) != AENL_CLASS_LINEAR;
}

/* The second effect (aenl_identify_model_test): d2's named DOF's channel takes its law; the
 * first effect's channel and the verdict stay. */
static void apply_second(aenl_identify_result_t *res, const aenl_diagnose_result_t *d2)
{
    const long k = channel_named(res, d2, aenl_diagnose_dof_channel(d2->updated.type, d2->dof));
    if (k < 0 || k == res->verdict)
    {
        return;
    }
    weights_t w;
    model_weights(d2, &w);
    set_law(&res->ch[k], d2, class_of(d2->effect), w.named / w.dof[d2->dof]);
    res->model.effect2 = d2->effect;
    res->model.dof2 = d2->dof;
}

aenl_status_t aenl_identify_model_test(aenl_identify_result_t *res, const aenl_table_t *record,
                                       const aenl_sim_model_t *base, const aenl_sim_run_t *run,
                                       const char *time_column, const aenl_progress_t *progress,
                                       aenl_err_t *err)
{
    aenl_diagnose_opts_t o;
    aenl_diagnose_opts_default(&o);
    o.time_column = time_column;
    o.progress = progress;
    /* d[0]: against the baseline; d[1]: against the baseline with d[0]'s law, for a second
     * effect on a DOF d[0] left linear; then backfitting, each law refitted with the other in
     * place: d[2] the first DOF's (the baseline with d[1]'s law), d[3] the second's (the baseline
     * with the first DOF's final law); d[4], d[5] a second pass when d[3] changed the second
     * law's class, for then d[2] was fitted against a law no longer in the model. Without the
     * backfitting, a first law fitted while the second effect is missing absorbs part of it
     * (its edges move, or a loop takes the place of a gap), and the second is then fitted
     * against that distorted first law. */
    aenl_diagnose_result_t d[AENL_IDENTIFY_MAX_DIAGNOSES];
    memset(d, 0, sizeof(d));
    aenl_status_t st = aenl_diagnose_run(record, base, run, &o, &d[0], err);
    unsigned n_run = st == AENL_OK ? 1u : 0u;
    if (st == AENL_OK && names_law(&d[0]))
    {
        st = aenl_diagnose_run(record, &d[0].updated, run, &o, &d[1], err);
        n_run += st == AENL_OK ? 1u : 0u;
    }
    const int second = n_run == 2u && names_law(&d[1]) && d[1].dof != d[0].dof;
    const aenl_diagnose_result_t *first = &d[0], *other = second ? &d[1] : NULL;
    int explains = 0; /* first's law alone leaves nothing to name (the last refit agrees) */
    for (size_t k = 2; st == AENL_OK && other != NULL && k + 1u < AENL_IDENTIFY_MAX_DIAGNOSES;
         k += 2u)
    {
        const aenl_diagnose_result_t *const was = other;
        aenl_sim_model_t m = *base;
        m.law[other->dof] = other->updated.law[other->dof];
        st = aenl_diagnose_run(record, &m, run, &o, &d[k], err);
        if (st != AENL_OK)
        {
            break;
        }
        n_run++;
        first = names_law(&d[k]) && d[k].dof == d[0].dof ? &d[k] : first;
        m = *base;
        m.law[first->dof] = first->updated.law[first->dof];
        st = aenl_diagnose_run(record, &m, run, &o, &d[k + 1u], err);
        n_run += st == AENL_OK ? 1u : 0u;
        /* The second effect stands only if the first's final law still leaves it to name.
         * If that law leaves nothing at all (the baseline with it agrees within the noise, by
         * the gap and the summaries), it alone explains the record, which the first effect as
         * found alone did not (the second was named on top of it): it is the verdict. Else the
         * first is as it was found alone. A plunge hysteresis under turbulence the model does
         * not share can be found alone as a cubic in plunge, then a cubic in pitch on top;
         * refitted with that, the plunge law becomes the hysteresis, and the baseline with the
         * hysteresis alone agrees. */
        const aenl_diagnose_result_t *const dk = &d[k + 1u];
        other = st == AENL_OK && names_law(dk) && dk->dof == d[1].dof ? dk : NULL;
        explains = st == AENL_OK && other == NULL && first != &d[0] && dk->explained &&
                   dk->effect == AENL_DIAGNOSE_NONE && aenl_diagnose_baseline_agrees(dk) == 1;
        first = other != NULL || explains ? first : &d[0];
        if (other == NULL || other->effect == was->effect)
        {
            break; /* the classes stand: the pass changed parameters only */
        }
    }
    if (st == AENL_OK)
    {
        st = aenl_identify_apply_model(res, first, err);
    }
    if (st == AENL_OK)
    {
        res->model.n_diagnoses = n_run;
        /* the gaps against the baseline, before and with the first effect alone */
        res->model.gap_before = d[0].gap_before[d[0].n_channels];
        res->model.gap_after = explains ? d[n_run - 1u].gap_before[d[n_run - 1u].n_channels]
                                        : d[0].gap_after[d[0].n_channels];
        if (other != NULL)
        {
            apply_second(res, other);
            res->model.gap_after2 = other->gap_after[other->n_channels];
        }
    }
    for (size_t i = 0; i < AENL_IDENTIFY_MAX_DIAGNOSES; ++i)
    {
        aenl_diagnose_result_free(&d[i]);
    }
    return st;
}
