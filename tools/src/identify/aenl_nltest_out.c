/* SPDX-License-Identifier: MIT */
/**
 * @file aenl_nltest_out.c
 * @brief The record-alone test's result as JSON and as a table.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <cjson/cJSON.h>

#include "aenl_tools/aenl_nltest.h"
#include "aenl_tools/aenl_json.h"

const char *aenl_nlt_class_name(aenl_class_t cls, int undetermined)
{
    return undetermined ? "undetermined" : aenl_class_name(cls);
}

static cJSON *num_array(const double *v, size_t n)
{
    cJSON *a = cJSON_CreateArray();
    for (size_t i = 0; a != NULL && i < n; ++i)
    {
        cJSON *x = aenl_json_num(v[i]);
        if (x == NULL)
        {
            cJSON_Delete(a);
            return NULL;
        }
        cJSON_AddItemToArray(a, x);
    }
    return a;
}

static int add_points(cJSON *o, const aenl_nlt_channel_t *c, int undetermined)
{
    /* the points of a named law only: an undetermined class has none to stand by */
    const size_t np = c->nonlinear && !undetermined ? c->n_points : 0u;
    int bad = aenl_json_add(o, "switch_points", num_array(c->points, np));
    bad |= aenl_json_add(o, "switch_point_lo", num_array(c->point_lo, np));
    bad |= aenl_json_add(o, "switch_point_hi", num_array(c->point_hi, np));
    return bad;
}

static cJSON *json_channel(const aenl_nlt_channel_t *c, const char *name, size_t n_controls,
                           double dt)
{
    cJSON *o = cJSON_CreateObject();
    if (o == NULL)
    {
        return NULL;
    }
    cJSON *w = cJSON_CreateObject();
    int bad = aenl_json_add(o, "name", cJSON_CreateString(name));
    bad |= aenl_json_add(
        o, "class",
        cJSON_CreateString(aenl_nlt_class_name(c->nonlinear ? c->cls : AENL_CLASS_LINEAR,
                                               c->nonlinear && c->undetermined)));
    bad |= aenl_json_add(o, "statistic", aenl_json_num(c->stat));
    bad |= aenl_json_add(o, "dof", aenl_json_num(c->dof));
    bad |= aenl_json_add(o, "p_value", aenl_json_num(c->p));
    bad |= aenl_json_add(o, "nonlinear", cJSON_CreateBool(c->nonlinear));
    for (size_t l = 0; w != NULL && l < AENL_NLT_N_LAWS; ++l)
    {
        bad |= aenl_json_add(w, aenl_nlt_law_name((aenl_nlt_law_t)l),
                             aenl_json_num(c->nonlinear ? c->law_p[l] : (double)NAN));
    }
    bad |= aenl_json_add(o, "law_p_values", w);
    bad |=
        aenl_json_add(o, "confidence", aenl_json_num(c->nonlinear ? c->confidence : (double)NAN));
    const int poly = c->nonlinear && !c->undetermined && c->cls == AENL_CLASS_POLYNOMIAL;
    bad |= aenl_json_add(o, "samples_per_period", aenl_json_num(c->samples_per_period));
    bad |= aenl_json_add(o, "period_samples", aenl_json_num(c->samples_per_period));
    bad |= aenl_json_add(o, "period_s", aenl_json_num(c->samples_per_period * dt));
    bad |= aenl_json_add(o, "hardening",
                         poly && c->hardening != 0 ? cJSON_CreateBool(c->hardening > 0)
                                                   : cJSON_CreateNull());
    bad |= add_points(o, c, c->undetermined);
    if (n_controls > 0)
    {
        bad |= aenl_json_add(o, "control_exceed", cJSON_CreateNumber((double)c->control_exceed));
        bad |= aenl_json_add(o, "control_p", aenl_json_num(c->control_p));
    }
    if (bad)
    {
        cJSON_Delete(o);
        return NULL;
    }
    return o;
}

/* The note on a channel sampled too coarsely for the laws' shape into buf (the table prints
 * it, the JSON lists it); 0 when the channel needs none. */
static int coarse_note(const aenl_nlt_channel_t *c, const char *name, char *buf, size_t n)
{
    if (!(c->samples_per_period < AENL_NLT_MIN_SAMPLES_PER_PERIOD))
    {
        return 0;
    }
    (void)snprintf(buf, n,
                   "%s moves with %.1f samples per period (fewer than %g): the direction of "
                   "motion lags it by %.0f degrees and a cycle is seen at few positions, so the "
                   "law's shape and switching points are resolved coarsely; sample faster where "
                   "you can",
                   name, c->samples_per_period, AENL_NLT_MIN_SAMPLES_PER_PERIOD,
                   180.0 / c->samples_per_period);
    return 1;
}

/* The notes: the caller's first, then every line the table prints as a note. */
static cJSON *json_notes(const aenl_nlt_result_t *r, const char *const *names,
                         const char *lead_note)
{
    cJSON *a = cJSON_CreateArray();
    int bad = a == NULL;
    if (!bad && lead_note != NULL)
    {
        cJSON *x = cJSON_CreateString(lead_note);
        bad |= x == NULL;
        if (x != NULL)
        {
            cJSON_AddItemToArray(a, x);
        }
    }
    for (size_t j = 0; j < r->n_channels && !bad; ++j)
    {
        char line[1024]; /* the same words in both outputs, a very long name cut alike */
        if (coarse_note(&r->ch[j], names[j], line, sizeof(line)))
        {
            cJSON *x = cJSON_CreateString(line);
            bad |= x == NULL;
            if (x != NULL)
            {
                cJSON_AddItemToArray(a, x);
            }
        }
    }
    if (bad)
    {
        cJSON_Delete(a);
        return NULL;
    }
    return a;
}

static cJSON *json_verdict(const aenl_nlt_result_t *r, const char *const *names)
{
    cJSON *v = cJSON_CreateObject();
    if (v == NULL)
    {
        return NULL;
    }
    const aenl_nlt_channel_t *c = r->verdict >= 0 ? &r->ch[r->verdict] : NULL;
    int bad = aenl_json_add(
        v, "class", cJSON_CreateString(aenl_nlt_class_name(r->verdict_class, r->undetermined)));
    bad |= aenl_json_add(v, "channel",
                         c != NULL ? cJSON_CreateString(names[r->verdict]) : cJSON_CreateNull());
    if (c != NULL)
    {
        bad |= add_points(v, c, r->undetermined);
    }
    else
    {
        bad |= aenl_json_add(v, "switch_points", cJSON_CreateArray());
        bad |= aenl_json_add(v, "switch_point_lo", cJSON_CreateArray());
        bad |= aenl_json_add(v, "switch_point_hi", cJSON_CreateArray());
    }
    bad |= aenl_json_add(v, "confidence", aenl_json_num(r->confidence));
    bad |= aenl_json_add(v, "class_confidence", aenl_json_num(r->class_confidence));
    bad |= aenl_json_add(v, "channel_confidence",
                         c != NULL ? aenl_json_num(r->channel_confidence) : cJSON_CreateNull());
    cJSON *cand = cJSON_CreateArray();
    for (size_t i = 0; c != NULL && cand != NULL && i < r->n_candidates; ++i)
    {
        const aenl_nlt_candidate_t *cd = &r->candidates[i];
        cJSON *e = cJSON_CreateObject();
        if (e == NULL ||
            aenl_json_add(e, "class", cJSON_CreateString(aenl_nlt_law_name(cd->law))) != 0 ||
            aenl_json_add(e, "channel", cJSON_CreateString(names[cd->channel])) != 0 ||
            aenl_json_add(e, "p_value", aenl_json_num(cd->p)) != 0)
        {
            cJSON_Delete(e);
            bad = 1;
            break;
        }
        cJSON_AddItemToArray(cand, e);
    }
    bad |= aenl_json_add(v, "candidates", cand);
    if (bad)
    {
        cJSON_Delete(v);
        return NULL;
    }
    return v;
}

/* A JSON array of names[p], p < n, those with sel[p] set (all when sel is NULL); NULL when it
 * cannot be made. */
static cJSON *name_array(const char *const *names, size_t n, const int *sel)
{
    cJSON *a = cJSON_CreateArray();
    for (size_t p = 0; a != NULL && p < n; ++p)
    {
        if (sel != NULL && !sel[p])
        {
            continue;
        }
        cJSON *nm = cJSON_CreateString(names[p]);
        if (nm == NULL)
        {
            cJSON_Delete(a);
            return NULL;
        }
        cJSON_AddItemToArray(a, nm);
    }
    return a;
}

aenl_status_t aenl_nlt_print_json(FILE *out, const aenl_nlt_result_t *r, const char *const *names,
                                  const char *const *input_names, const char *path, double dt,
                                  const char *lead_note)
{
    cJSON *root = cJSON_CreateObject();
    cJSON *model = cJSON_CreateObject();
    cJSON *chs = cJSON_CreateArray();
    int bad = root == NULL || model == NULL || chs == NULL;
    if (!bad)
    {
        bad |= aenl_json_add(root, "schema", cJSON_CreateString("aenl-identify-test/5"));
        bad |= aenl_json_add(root, "aenl_version", cJSON_CreateString(AENL_VERSION));
        bad |= aenl_json_add(root, "file", cJSON_CreateString(path));
        bad |= aenl_json_add(root, "method", cJSON_CreateString("test"));
        bad |= aenl_json_add(root, "level", aenl_json_num(r->level));
        bad |= aenl_json_add(root, "dt", aenl_json_num(dt));
        bad |= aenl_json_add(model, "states", cJSON_CreateNumber((double)r->n_states));
        bad |= aenl_json_add(model, "samples", cJSON_CreateNumber((double)r->n_samples));
        bad |= aenl_json_add(model, "loglik", aenl_json_num(r->loglik));
        bad |= aenl_json_add(model, "impulses", cJSON_CreateNumber((double)r->n_impulses));
        if (r->jumps)
        {
            bad |= aenl_json_add(model, "jumps", cJSON_CreateBool(1));
        }
        if (r->n_inputs > 0 && input_names != NULL)
        {
            bad |= aenl_json_add(model, "inputs", name_array(input_names, r->n_inputs, NULL));
        }
        if (r->n_dithered > 0)
        {
            int sel[AENL_NLT_MAX_CH] = {0};
            for (size_t j = 0; j < r->n_channels; ++j)
            {
                sel[j] = r->ch[j].dithered;
            }
            bad |= aenl_json_add(model, "dithered", name_array(names, r->n_channels, sel));
        }
        bad |= aenl_json_add(root, "model", model);
        model = NULL;
        if (r->n_controls > 0)
        {
            bad |= aenl_json_add(root, "controls", cJSON_CreateNumber((double)r->n_controls));
            bad |= aenl_json_add(root, "controls_nonlinear",
                                 cJSON_CreateNumber((double)r->n_controls_nonlinear));
        }
        bad |= aenl_json_add(root, "verdict", json_verdict(r, names));
        for (size_t j = 0; j < r->n_channels && !bad; ++j)
        {
            cJSON *c = json_channel(&r->ch[j], names[j], r->n_controls, dt);
            bad |= c == NULL;
            if (c != NULL)
            {
                cJSON_AddItemToArray(chs, c);
            }
        }
        bad |= aenl_json_add(root, "channels", chs);
        chs = NULL;
        bad |= aenl_json_add(root, "notes", json_notes(r, names, lead_note));
    }
    char *text = bad ? NULL : cJSON_Print(root);
    cJSON_Delete(root);
    cJSON_Delete(model);
    cJSON_Delete(chs);
    if (text == NULL)
    {
        return AENL_E_DIM;
    }
    (void)fprintf(out, "%s\n", text);
    cJSON_free(text);
    return AENL_OK;
}

static void print_points(FILE *out, const aenl_nlt_channel_t *c)
{
    for (size_t k = 0; k < c->n_points; ++k)
    {
        (void)fprintf(out, "%s%.6g [%.6g, %.6g]", k ? ", " : "", c->points[k], c->point_lo[k],
                      c->point_hi[k]);
    }
}

void aenl_nlt_print_table(FILE *out, const aenl_nlt_result_t *r, const char *const *names,
                          const char *const *input_names, const char *path)
{
    if (r->n_inputs > 0 && input_names != NULL)
    {
        (void)fprintf(out, "known input%s:", r->n_inputs == 1 ? "" : "s");
        for (size_t p = 0; p < r->n_inputs; ++p)
        {
            (void)fprintf(out, " %s", input_names[p]);
        }
        (void)fprintf(out, r->n_inputs == 1
                               ? " (it drives the linear model and is not tested)\n"
                               : " (they drive the linear model and are not tested)\n");
    }
    if (r->n_dithered > 0)
    {
        (void)fprintf(out, "fitted measurement noise nil in");
        for (size_t j = 0; j < r->n_channels; ++j)
        {
            if (r->ch[j].dithered)
            {
                (void)fprintf(out, " %s", names[j]);
            }
        }
        (void)fprintf(out, ": white noise of %g of the standard deviation added (dither)\n",
                      AENL_NLT_DITHER);
    }
    (void)fprintf(out,
                  "%s: %lu samples, %lu channel%s; linear state-space model with %lu states "
                  "(%lu impulse%s%s)\n"
                  "test of a structural law against the linear model at level %.3g (each "
                  "channel at %.3g)\n\n",
                  path, (unsigned long)r->n_samples, (unsigned long)r->n_channels,
                  r->n_channels == 1 ? "" : "s", (unsigned long)r->n_states,
                  (unsigned long)r->n_impulses, r->n_impulses == 1 ? "" : "s",
                  r->jumps ? ", taken as state jumps" : "", r->level,
                  r->level / (double)r->n_channels);
    (void)fprintf(out, "%-12s %12s %5s %10s  %-12s %s%s\n", "channel", "chi-square", "dof",
                  "p-value", "class", "p vs best law poly/freeplay/hyst",
                  r->n_controls > 0 ? "  controls >= (p)" : "");
    for (size_t j = 0; j < r->n_channels; ++j)
    {
        const aenl_nlt_channel_t *c = &r->ch[j];
        (void)fprintf(out, "%-12s %12.1f %5.0f %10.3g  %-12s", names[j], c->stat, c->dof, c->p,
                      aenl_nlt_class_name(c->nonlinear ? c->cls : AENL_CLASS_LINEAR,
                                          c->nonlinear && c->undetermined));
        if (c->nonlinear)
        {
            (void)fprintf(out, " %.3f/%.3f/%.3f", c->law_p[0], c->law_p[1], c->law_p[2]);
        }
        if (r->n_controls > 0)
        {
            (void)fprintf(out, "%s  %lu/%lu (%.3g)", c->nonlinear ? "" : "                  ",
                          (unsigned long)c->control_exceed, (unsigned long)r->n_controls,
                          c->control_p);
        }
        (void)fprintf(out, "\n");
    }
    if (r->n_controls > 0)
    {
        (void)fprintf(out,
                      "linear controls (the fitted linear model, driven as the record was) called "
                      "nonlinear: %lu of %lu\n",
                      (unsigned long)r->n_controls_nonlinear, (unsigned long)r->n_controls);
    }
    (void)fprintf(out, "\nverdict: %s", aenl_nlt_class_name(r->verdict_class, r->undetermined));
    if (r->verdict >= 0)
    {
        const aenl_nlt_channel_t *c = &r->ch[r->verdict];
        (void)fprintf(out, " in %s (confidence %.3f: the law %.3f, the channel %.3f)",
                      names[r->verdict], r->confidence, r->class_confidence, r->channel_confidence);
        if (r->verdict_class == AENL_CLASS_POLYNOMIAL && c->hardening != 0)
        {
            (void)fprintf(out, ", %s", c->hardening > 0 ? "hardening" : "softening");
        }
        if (c->n_points > 0 && !r->undetermined)
        {
            (void)fprintf(out, "\nswitching points [95 %% profile interval, not calibrated]: ");
            print_points(out, c);
        }
        if (r->n_candidates > 1)
        {
            (void)fprintf(out, "\n%s; candidates (p against the best):",
                          r->undetermined ? "the record cannot tell the laws apart"
                                          : "the record cannot tell these channels apart");
            for (size_t i = 0; i < r->n_candidates; ++i)
            {
                const aenl_nlt_candidate_t *cd = &r->candidates[i];
                (void)fprintf(out, " %s in %s %.3g", aenl_nlt_law_name(cd->law), names[cd->channel],
                              cd->p);
            }
        }
    }
    else
    {
        (void)fprintf(out, " (no channel rejects the linear model; confidence %.3f)",
                      r->confidence);
    }
    (void)fprintf(out, "\n");
    for (size_t j = 0; j < r->n_channels; ++j)
    {
        char line[1024]; /* the same words in both outputs, a very long name cut alike */
        if (coarse_note(&r->ch[j], names[j], line, sizeof(line)))
        {
            (void)fprintf(out, "note: %s\n", line);
        }
    }
}
